struct Step {
    float3 origin;
    float h1_;
    uint n;
    uint bits;
    uint level;
    uint top;
    uint max_cell;
    uint slot_offset;
    uint light_base;
    float threshold;
    uint count;
    uint parts;
    uint _pad0_;
    uint _pad1_;
};

struct Light {
    float3 position;
    int _pad1_0;
    float3 intensity;
    int _end_pad_0;
};

struct Sorted {
    float3 frac_;
    float luminance;
    float3 intensity;
    uint cell;
};

struct Located {
    uint3 cell;
    int _pad1_0;
    float3 frac_;
    int _end_pad_0;
};

struct Sums {
    float3 intensity;
    float weight;
    float3 first;
    int _pad3_0;
    float3 second;
    int _end_pad_0;
};

static const uint WORKGROUP = 64u;
static const float3 LUMINANCE = float3(0.2126, 0.7152, 0.0722);

cbuffer step_ : register(b0) { Step step_; }
RWByteAddressBuffer positions : register(u1);
RWByteAddressBuffer intensities : register(u2);
RWByteAddressBuffer counts : register(u3);
RWByteAddressBuffer starts : register(u4);
RWByteAddressBuffer order : register(u5);
RWByteAddressBuffer sorted : register(u6);
RWByteAddressBuffer slots : register(u7);
RWByteAddressBuffer out_ : register(u8);
RWByteAddressBuffer extras : register(u9);
RWByteAddressBuffer keys : register(u10);
RWByteAddressBuffer partials : register(u11);
groupshared float4 lane_sums[64][3];
groupshared uint occupied_slot;

uint flat(uint3 id_5, uint3 groups_9)
{
    return (id_5.x + ((id_5.y * groups_9.x) * WORKGROUP));
}

uint spread3_(uint v)
{
    uint x = (uint)0;

    x = (v & 1023u);
    uint _e4 = x;
    uint _e5 = x;
    x = ((_e4 | (_e5 << 16u)) & 50331903u);
    uint _e11 = x;
    uint _e12 = x;
    x = ((_e11 | (_e12 << 8u)) & 50393103u);
    uint _e18 = x;
    uint _e19 = x;
    x = ((_e18 | (_e19 << 4u)) & 51130563u);
    uint _e25 = x;
    uint _e26 = x;
    x = ((_e25 | (_e26 << 2u)) & 153391689u);
    uint _e32 = x;
    return _e32;
}

uint compact3_(uint v_1)
{
    uint x_1 = (uint)0;

    x_1 = (v_1 & 153391689u);
    uint _e4 = x_1;
    uint _e5 = x_1;
    x_1 = ((_e4 | (_e5 >> 2u)) & 51130563u);
    uint _e11 = x_1;
    uint _e12 = x_1;
    x_1 = ((_e11 | (_e12 >> 4u)) & 50393103u);
    uint _e18 = x_1;
    uint _e19 = x_1;
    x_1 = ((_e18 | (_e19 >> 8u)) & 50331903u);
    uint _e25 = x_1;
    uint _e26 = x_1;
    x_1 = ((_e25 | (_e26 >> 16u)) & 1023u);
    uint _e32 = x_1;
    return _e32;
}

uint morton3_(uint3 c)
{
    const uint _e2 = spread3_(c.x);
    const uint _e4 = spread3_(c.y);
    const uint _e9 = spread3_(c.z);
    return ((_e2 | (_e4 << 1u)) | (_e9 << 2u));
}

uint3 demorton3_(uint m)
{
    const uint _e1 = compact3_(m);
    const uint _e4 = compact3_((m >> 1u));
    const uint _e7 = compact3_((m >> 2u));
    return uint3(_e1, _e4, _e7);
}

uint pack(uint3 c_1)
{
    return ((c_1.x | (c_1.y << 10u)) | (c_1.z << 20u));
}

uint3 unpack(uint c_2)
{
    return uint3((c_2 & 1023u), ((c_2 >> 10u) & 1023u), (c_2 >> 20u));
}

Located ConstructLocated(uint3 arg0, float3 arg1) {
    Located ret = (Located)0;
    ret.cell = arg0;
    ret.frac_ = arg1;
    return ret;
}

uint3 naga_f2u32(float3 value) {
    return uint3(clamp(value, 0.0, 4294967000.0));
}

Located locate_light(float3 p)
{
    float3 _e3 = step_.origin;
    float _e7 = step_.h1_;
    float3 t = ((p - _e3) / (_e7).xxx);
    uint _e15 = step_.max_cell;
    float3 c_4 = clamp(floor(t), (0.0).xxx, (float(_e15)).xxx);
    const Located located = ConstructLocated(naga_f2u32(c_4), clamp((t - c_4), (0.0).xxx, (1.0).xxx));
    return located;
}

uint3 corner(uint k_1)
{
    return uint3((k_1 & 1u), ((k_1 >> 1u) & 1u), (k_1 >> 2u));
}

uint cells_a_side()
{
    uint _e3 = step_.bits;
    uint _e6 = step_.level;
    return (1u << (_e3 - (_e6 - 1u)));
}

uint2 cell_range(uint3 c_3)
{
    uint _e4 = step_.level;
    uint shift = (3u * (_e4 - 1u));
    const uint _e8 = morton3_(c_3);
    uint _e12 = asuint(starts.Load((_e8 << shift)*4));
    uint _e18 = asuint(starts.Load(((_e8 + 1u) << shift)*4));
    return uint2(_e12, _e18);
}

Sums ConstructSums(float3 arg0, float arg1, float3 arg2, float3 arg3) {
    Sums ret = (Sums)0;
    ret.intensity = arg0;
    ret.weight = arg1;
    ret.first = arg2;
    ret.second = arg3;
    return ret;
}

Sorted ConstructSorted(float3 arg0, float arg1, float3 arg2, uint arg3) {
    Sorted ret = (Sorted)0;
    ret.frac_ = arg0;
    ret.luminance = arg1;
    ret.intensity = arg2;
    ret.cell = arg3;
    return ret;
}

Sums moment_sums(uint3 q, uint lane_4, uint lanes)
{
    Sums s = ConstructSums((0.0).xxx, 0.0, (0.0).xxx, (0.0).xxx);
    uint k_2 = 0u;
    bool local_2 = (bool)0;
    uint j = (uint)0;

    const uint _e12 = cells_a_side();
    uint _e15 = step_.level;
    uint sub = (_e15 - 1u);
    uint mask = ((1u << sub) - 1u);
    float scale = (1.0 / float((1u << sub)));
    uint2 loop_bound = uint2(4294967295u, 4294967295u);
    bool loop_init = true;
    while(true) {
        if (all(loop_bound == uint2(0u, 0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e104 = k_2;
            k_2 = (_e104 + 1u);
        }
        loop_init = false;
        uint _e29 = k_2;
        if ((_e29 < 8u)) {
        } else {
            break;
        }
        {
            uint _e32 = k_2;
            const uint3 _e33 = corner(_e32);
            if (!(any((q < _e33)))) {
                local_2 = any(((q - _e33) >= (_e12).xxx));
            } else {
                local_2 = true;
            }
            bool _e44 = local_2;
            if (_e44) {
                continue;
            }
            const uint2 _e46 = cell_range((q - _e33));
            float3 at = float3(_e33);
            j = (_e46.x + lane_4);
            uint2 loop_bound_1 = uint2(4294967295u, 4294967295u);
            bool loop_init_1 = true;
            while(true) {
                if (all(loop_bound_1 == uint2(0u, 0u))) { break; }
                loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
                if (!loop_init_1) {
                    uint _e101 = j;
                    j = (_e101 + lanes);
                }
                loop_init_1 = false;
                uint _e51 = j;
                if ((_e51 < _e46.y)) {
                } else {
                    break;
                }
                {
                    uint _e55 = j;
                    Sorted light = ConstructSorted(asfloat(sorted.Load3(_e55*32+0)), asfloat(sorted.Load(_e55*32+12)), asfloat(sorted.Load3(_e55*32+16)), asuint(sorted.Load(_e55*32+28)));
                    const uint3 _e59 = unpack(light.cell);
                    float3 g_2 = min(((float3((_e59 & (mask).xxx)) + light.frac_) * scale), (1.0).xxx);
                    float3 wa = ((_e33 == (1u).xxx) ? g_2 : ((1.0).xxx - g_2));
                    float w = ((wa.x * wa.y) * wa.z);
                    float v_3 = (w * light.luminance);
                    float3 off = (g_2 - at);
                    float3 _e85 = s.intensity;
                    s.intensity = (_e85 + (w * light.intensity));
                    float _e90 = s.weight;
                    s.weight = (_e90 + v_3);
                    float3 _e93 = s.first;
                    s.first = (_e93 + (v_3 * off));
                    float3 _e97 = s.second;
                    s.second = (_e97 + (v_3 * (off * off)));
                }
            }
        }
    }
    Sums _e106 = s;
    const Sums sums = _e106;
    return sums;
}

float size_sum(uint3 q_1, float3 mean, uint lane_5, uint lanes_1)
{
    float sum_2 = 0.0;
    uint k_3 = 0u;
    bool local_3 = (bool)0;
    uint j_1 = (uint)0;

    const uint _e6 = cells_a_side();
    uint _e9 = step_.level;
    uint sub_1 = (_e9 - 1u);
    uint mask_1 = ((1u << sub_1) - 1u);
    float scale_1 = (1.0 / float((1u << sub_1)));
    uint2 loop_bound_2 = uint2(4294967295u, 4294967295u);
    bool loop_init_2 = true;
    while(true) {
        if (all(loop_bound_2 == uint2(0u, 0u))) { break; }
        loop_bound_2 -= uint2(loop_bound_2.y == 0u, 1u);
        if (!loop_init_2) {
            uint _e86 = k_3;
            k_3 = (_e86 + 1u);
        }
        loop_init_2 = false;
        uint _e23 = k_3;
        if ((_e23 < 8u)) {
        } else {
            break;
        }
        {
            uint _e26 = k_3;
            const uint3 _e27 = corner(_e26);
            if (!(any((q_1 < _e27)))) {
                local_3 = any(((q_1 - _e27) >= (_e6).xxx));
            } else {
                local_3 = true;
            }
            bool _e38 = local_3;
            if (_e38) {
                continue;
            }
            const uint2 _e40 = cell_range((q_1 - _e27));
            float3 centre_1 = (float3(_e27) + mean);
            j_1 = (_e40.x + lane_5);
            uint2 loop_bound_3 = uint2(4294967295u, 4294967295u);
            bool loop_init_3 = true;
            while(true) {
                if (all(loop_bound_3 == uint2(0u, 0u))) { break; }
                loop_bound_3 -= uint2(loop_bound_3.y == 0u, 1u);
                if (!loop_init_3) {
                    uint _e83 = j_1;
                    j_1 = (_e83 + lanes_1);
                }
                loop_init_3 = false;
                uint _e46 = j_1;
                if ((_e46 < _e40.y)) {
                } else {
                    break;
                }
                {
                    uint _e50 = j_1;
                    Sorted light_1 = ConstructSorted(asfloat(sorted.Load3(_e50*32+0)), asfloat(sorted.Load(_e50*32+12)), asfloat(sorted.Load3(_e50*32+16)), asuint(sorted.Load(_e50*32+28)));
                    const uint3 _e54 = unpack(light_1.cell);
                    float3 g_3 = min(((float3((_e54 & (mask_1).xxx)) + light_1.frac_) * scale_1), (1.0).xxx);
                    float3 wa_1 = ((_e27 == (1u).xxx) ? g_3 : ((1.0).xxx - g_3));
                    float w_1 = ((wa_1.x * wa_1.y) * wa_1.z);
                    float _e76 = sum_2;
                    sum_2 = (_e76 + ((w_1 * light_1.luminance) * length((g_3 - centre_1))));
                }
            }
        }
    }
    float _e88 = sum_2;
    return _e88;
}

float3 centre(Sums s_1)
{
    if ((s_1.weight > 0.0)) {
        return (s_1.first / (s_1.weight).xxx);
    }
    return (0.0).xxx;
}

Light ConstructLight(float3 arg0, float3 arg1) {
    Light ret = (Light)0;
    ret.position = arg0;
    ret.intensity = arg1;
    return ret;
}

void write_vertex(uint3 q_2, uint v_2, Sums s_2, float3 mean_1, float size_sum_1)
{
    float3 variance = (0.0).xxx;
    float size = 0.0;
    bool local_4 = (bool)0;

    float _e7 = step_.h1_;
    uint _e11 = step_.level;
    float h = (_e7 * float((1u << (_e11 - 1u))));
    if ((s_2.weight > 0.0)) {
        variance = ((max(((s_2.second / (s_2.weight).xxx) - (mean_1 * mean_1)), (0.0).xxx) * h) * h);
        size = ((size_sum_1 / s_2.weight) * h);
    }
    float3 _e41 = step_.origin;
    float3 position = (_e41 + ((float3(q_2) + mean_1) * h));
    float luminance = dot(s_2.intensity, LUMINANCE);
    if ((luminance > 0.0)) {
        float _e55 = step_.threshold;
        local_4 = (luminance >= _e55);
    } else {
        local_4 = false;
    }
    bool reported = local_4;
    uint _e62 = step_.light_base;
    {
        Light _value2 = ConstructLight(position, (reported ? s_2.intensity : (0.0).xxx));
        out_.Store3((_e62 + v_2)*32+0, asuint(_value2.position));
        out_.Store3((_e62 + v_2)*32+16, asuint(_value2.intensity));
    }
    uint _e73 = step_.light_base;
    float3 _e76 = variance;
    float _e77 = size;
    extras.Store4((_e73 + v_2)*16, asuint(float4(_e76, _e77)));
    return;
}

bool slot_is_occupied(uint m_1, uint lane_6)
{
    if ((lane_6 == 0u)) {
        uint _e10 = step_.slot_offset;
        uint _e15 = asuint(slots.Load(((_e10 + m_1) + 1u)*4));
        uint _e19 = step_.slot_offset;
        uint _e22 = asuint(slots.Load((_e19 + m_1)*4));
        occupied_slot = ((_e15 != _e22) ? 1u : 0u);
    }
    GroupMemoryBarrierWithGroupSync();
    uint _e26 = occupied_slot;
    GroupMemoryBarrierWithGroupSync();
    return (_e26 == 1u);
}

uint naga_div(uint lhs, uint rhs) {
    return lhs / (rhs == 0u ? 1u : rhs);
}

void reduce(uint lane_7)
{
    uint stride = 32u;
    uint a_3 = (uint)0;

    uint2 loop_bound_4 = uint2(4294967295u, 4294967295u);
    bool loop_init_4 = true;
    while(true) {
        if (all(loop_bound_4 == uint2(0u, 0u))) { break; }
        loop_bound_4 -= uint2(loop_bound_4.y == 0u, 1u);
        if (!loop_init_4) {
            uint _e29 = stride;
            stride = naga_div(_e29, 2u);
        }
        loop_init_4 = false;
        uint _e3 = stride;
        if ((_e3 > 0u)) {
        } else {
            break;
        }
        {
            uint _e6 = stride;
            if ((lane_7 < _e6)) {
                a_3 = 0u;
                uint2 loop_bound_5 = uint2(4294967295u, 4294967295u);
                bool loop_init_5 = true;
                while(true) {
                    if (all(loop_bound_5 == uint2(0u, 0u))) { break; }
                    loop_bound_5 -= uint2(loop_bound_5.y == 0u, 1u);
                    if (!loop_init_5) {
                        uint _e27 = a_3;
                        a_3 = (_e27 + 1u);
                    }
                    loop_init_5 = false;
                    uint _e10 = a_3;
                    if ((_e10 < 3u)) {
                    } else {
                        break;
                    }
                    {
                        uint _e15 = a_3;
                        float4 _e17 = lane_sums[min(uint(lane_7), 63u)][min(uint(_e15), 2u)];
                        uint _e19 = stride;
                        uint _e22 = a_3;
                        float4 _e24 = lane_sums[min(uint((lane_7 + _e19)), 63u)][min(uint(_e22), 2u)];
                        lane_sums[min(uint(lane_7), 63u)][min(uint(_e15), 2u)] = (_e17 + _e24);
                    }
                }
            }
            GroupMemoryBarrierWithGroupSync();
        }
    }
    return;
}

typedef float4 ret_Constructarray3_float4_[3];
ret_Constructarray3_float4_ Constructarray3_float4_(float4 arg0, float4 arg1, float4 arg2) {
    float4 ret[3] = { arg0, arg1, arg2 };
    return ret;
}

[numthreads(64, 1, 1)]
void finish_moments(uint lane_1 : SV_GroupIndex, uint3 wg_1 : SV_GroupID, uint3 groups_6 : SV_GroupID)
{
    if (lane_1 == 0) {
        lane_sums = (float4[64][3])0;
        occupied_slot = (uint)0;
    }
    GroupMemoryBarrierWithGroupSync();
    float4 sum[3] = Constructarray3_float4_((0.0).xxxx, (0.0).xxxx, (0.0).xxxx);
    uint g = (uint)0;
    uint a_1 = (uint)0;
    uint a_2 = 0u;

    uint m_2 = (wg_1.x + (wg_1.y * groups_6.x));
    uint _e10 = step_.count;
    if ((m_2 >= _e10)) {
        return;
    }
    const bool _e12 = slot_is_occupied(m_2, lane_1);
    if (!(_e12)) {
        return;
    }
    uint _e16 = step_.parts;
    uint first = (m_2 * _e16);
    g = lane_1;
    uint2 loop_bound_6 = uint2(4294967295u, 4294967295u);
    bool loop_init_6 = true;
    while(true) {
        if (all(loop_bound_6 == uint2(0u, 0u))) { break; }
        loop_bound_6 -= uint2(loop_bound_6.y == 0u, 1u);
        if (!loop_init_6) {
            uint _e51 = g;
            g = (_e51 + WORKGROUP);
        }
        loop_init_6 = false;
        uint _e27 = g;
        uint _e30 = step_.parts;
        if ((_e27 < _e30)) {
        } else {
            break;
        }
        {
            a_1 = 0u;
            uint2 loop_bound_7 = uint2(4294967295u, 4294967295u);
            bool loop_init_7 = true;
            while(true) {
                if (all(loop_bound_7 == uint2(0u, 0u))) { break; }
                loop_bound_7 -= uint2(loop_bound_7.y == 0u, 1u);
                if (!loop_init_7) {
                    uint _e49 = a_1;
                    a_1 = (_e49 + 1u);
                }
                loop_init_7 = false;
                uint _e34 = a_1;
                if ((_e34 < 3u)) {
                } else {
                    break;
                }
                {
                    uint _e37 = a_1;
                    float4 _e39 = sum[min(uint(_e37), 2u)];
                    uint _e41 = g;
                    uint _e44 = a_1;
                    float4 _e46 = asfloat(partials.Load4(_e44*16+(first + _e41)*80));
                    sum[min(uint(_e37), 2u)] = (_e39 + _e46);
                }
            }
        }
    }
    float4 _e56[3] = sum;
    lane_sums[min(uint(lane_1), 63u)] = _e56;
    GroupMemoryBarrierWithGroupSync();
    reduce(lane_1);
    if ((lane_1 == 0u)) {
        float4 total[3] = lane_sums[0];
        uint2 loop_bound_8 = uint2(4294967295u, 4294967295u);
        bool loop_init_8 = true;
        while(true) {
            if (all(loop_bound_8 == uint2(0u, 0u))) { break; }
            loop_bound_8 -= uint2(loop_bound_8.y == 0u, 1u);
            if (!loop_init_8) {
                uint _e74 = a_2;
                a_2 = (_e74 + 1u);
            }
            loop_init_8 = false;
            uint _e64 = a_2;
            if ((_e64 < 3u)) {
            } else {
                break;
            }
            {
                uint _e69 = a_2;
                uint _e71 = a_2;
                partials.Store4(_e69*16+first*80, asuint(total[min(uint(_e71), 2u)]));
            }
        }
        Sums s_3 = ConstructSums(total[0].xyz, total[0].w, total[1].xyz, total[2].xyz);
        const float3 _e88 = centre(s_3);
        partials.Store4(48+first*80, asuint(float4(_e88, 0.0)));
        return;
    } else {
        return;
    }
}

