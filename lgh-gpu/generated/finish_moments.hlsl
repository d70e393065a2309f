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
    uint list_offset;
    uint _pad0_;
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

struct Part {
    uint w;
    uint v;
    int _pad2_0;
    int _pad2_1;
    uint3 q;
    uint g;
    bool busy;
    int _end_pad_0;
    int _end_pad_1;
    int _end_pad_2;
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
RWByteAddressBuffer vertex_slots : register(u12);
RWByteAddressBuffer partials : register(u11);
groupshared float4 lane_sums[64][3];

uint flat(uint3 id_5, uint3 groups_9)
{
    return (id_5.x + ((id_5.y * groups_9.x) * WORKGROUP));
}

uint pack(uint3 c)
{
    return ((c.x | (c.y << 10u)) | (c.z << 20u));
}

uint3 unpack(uint c_1)
{
    return uint3((c_1 & 1023u), ((c_1 >> 10u) & 1023u), (c_1 >> 20u));
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

uint morton3_(uint3 c_2)
{
    const uint _e2 = spread3_(c_2.x);
    const uint _e4 = spread3_(c_2.y);
    const uint _e9 = spread3_(c_2.z);
    return ((_e2 | (_e4 << 1u)) | (_e9 << 2u));
}

uint3 corner(uint k)
{
    return uint3((k & 1u), ((k >> 1u) & 1u), (k >> 2u));
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

uint2 corner_cell(uint3 q, uint k_1)
{
    bool local_1 = (bool)0;

    const uint3 _e2 = corner(k_1);
    if (!(any((q < _e2)))) {
        const uint _e9 = cells_a_side();
        local_1 = any(((q - _e2) >= (_e9).xxx));
    } else {
        local_1 = true;
    }
    bool _e14 = local_1;
    if (_e14) {
        return (0u).xx;
    }
    const uint2 _e18 = cell_range((q - _e2));
    return _e18;
}

float3 place(Sorted light)
{
    uint _e3 = step_.level;
    uint sub = (_e3 - 1u);
    uint3 mask = (((1u << sub) - 1u)).xxx;
    float scale = (1.0 / float((1u << sub)));
    const uint3 _e17 = unpack(light.cell);
    return min(((float3((_e17 & mask)) + light.frac_) * scale), (1.0).xxx);
}

float weight(float3 g_2, uint3 o)
{
    float3 wa = ((o == (1u).xxx) ? g_2 : ((1.0).xxx - g_2));
    return ((wa.x * wa.y) * wa.z);
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

Sums moment_sums(uint3 q_1, uint lane_4, uint lanes)
{
    Sums s = ConstructSums((0.0).xxx, 0.0, (0.0).xxx, (0.0).xxx);
    uint k_2 = 0u;
    uint j = (uint)0;

    uint2 loop_bound = uint2(4294967295u, 4294967295u);
    bool loop_init = true;
    while(true) {
        if (all(loop_bound == uint2(0u, 0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e57 = k_2;
            k_2 = (_e57 + 1u);
        }
        loop_init = false;
        uint _e14 = k_2;
        if ((_e14 < 8u)) {
        } else {
            break;
        }
        {
            uint _e17 = k_2;
            const uint2 _e18 = corner_cell(q_1, _e17);
            uint _e19 = k_2;
            const uint3 _e20 = corner(_e19);
            j = (_e18.x + lane_4);
            uint2 loop_bound_1 = uint2(4294967295u, 4294967295u);
            bool loop_init_1 = true;
            while(true) {
                if (all(loop_bound_1 == uint2(0u, 0u))) { break; }
                loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
                if (!loop_init_1) {
                    uint _e54 = j;
                    j = (_e54 + lanes);
                }
                loop_init_1 = false;
                uint _e24 = j;
                if ((_e24 < _e18.y)) {
                } else {
                    break;
                }
                {
                    uint _e28 = j;
                    Sorted light_1 = ConstructSorted(asfloat(sorted.Load3(_e28*32+0)), asfloat(sorted.Load(_e28*32+12)), asfloat(sorted.Load3(_e28*32+16)), asuint(sorted.Load(_e28*32+28)));
                    const float3 _e31 = place(light_1);
                    const float _e32 = weight(_e31, _e20);
                    float v_3 = (_e32 * light_1.luminance);
                    float3 off = (_e31 - float3(_e20));
                    float3 _e38 = s.intensity;
                    s.intensity = (_e38 + (_e32 * light_1.intensity));
                    float _e43 = s.weight;
                    s.weight = (_e43 + v_3);
                    float3 _e46 = s.first;
                    s.first = (_e46 + (v_3 * off));
                    float3 _e50 = s.second;
                    s.second = (_e50 + (v_3 * (off * off)));
                }
            }
        }
    }
    Sums _e59 = s;
    const Sums sums = _e59;
    return sums;
}

float size_sum(uint3 q_2, float3 mean, uint lane_5, uint lanes_1)
{
    float sum_2 = 0.0;
    uint k_3 = 0u;
    uint j_1 = (uint)0;

    uint2 loop_bound_2 = uint2(4294967295u, 4294967295u);
    bool loop_init_2 = true;
    while(true) {
        if (all(loop_bound_2 == uint2(0u, 0u))) { break; }
        loop_bound_2 -= uint2(loop_bound_2.y == 0u, 1u);
        if (!loop_init_2) {
            uint _e39 = k_3;
            k_3 = (_e39 + 1u);
        }
        loop_init_2 = false;
        uint _e8 = k_3;
        if ((_e8 < 8u)) {
        } else {
            break;
        }
        {
            uint _e11 = k_3;
            const uint2 _e12 = corner_cell(q_2, _e11);
            uint _e13 = k_3;
            const uint3 _e14 = corner(_e13);
            j_1 = (_e12.x + lane_5);
            uint2 loop_bound_3 = uint2(4294967295u, 4294967295u);
            bool loop_init_3 = true;
            while(true) {
                if (all(loop_bound_3 == uint2(0u, 0u))) { break; }
                loop_bound_3 -= uint2(loop_bound_3.y == 0u, 1u);
                if (!loop_init_3) {
                    uint _e36 = j_1;
                    j_1 = (_e36 + lanes_1);
                }
                loop_init_3 = false;
                uint _e18 = j_1;
                if ((_e18 < _e12.y)) {
                } else {
                    break;
                }
                {
                    uint _e22 = j_1;
                    Sorted light_2 = ConstructSorted(asfloat(sorted.Load3(_e22*32+0)), asfloat(sorted.Load(_e22*32+12)), asfloat(sorted.Load3(_e22*32+16)), asuint(sorted.Load(_e22*32+28)));
                    const float3 _e25 = place(light_2);
                    float _e26 = sum_2;
                    const float _e27 = weight(_e25, _e14);
                    sum_2 = (_e26 + ((_e27 * light_2.luminance) * length((_e25 - (float3(_e14) + mean)))));
                }
            }
        }
    }
    float _e41 = sum_2;
    return _e41;
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

void write_vertex(uint3 q_3, uint v_1, Sums s_2, float3 mean_1, float size_sum_1)
{
    float3 variance = (0.0).xxx;
    float size = 0.0;
    bool local_2 = (bool)0;

    float _e7 = step_.h1_;
    uint _e11 = step_.level;
    float h = (_e7 * float((1u << (_e11 - 1u))));
    if ((s_2.weight > 0.0)) {
        variance = ((max(((s_2.second / (s_2.weight).xxx) - (mean_1 * mean_1)), (0.0).xxx) * h) * h);
        size = ((size_sum_1 / s_2.weight) * h);
    }
    float3 _e41 = step_.origin;
    float3 position = (_e41 + ((float3(q_3) + mean_1) * h));
    float luminance = dot(s_2.intensity, LUMINANCE);
    if ((luminance > 0.0)) {
        float _e55 = step_.threshold;
        local_2 = (luminance >= _e55);
    } else {
        local_2 = false;
    }
    bool reported = local_2;
    uint _e62 = step_.light_base;
    {
        Light _value2 = ConstructLight(position, (reported ? s_2.intensity : (0.0).xxx));
        out_.Store3((_e62 + v_1)*32+0, asuint(_value2.position));
        out_.Store3((_e62 + v_1)*32+16, asuint(_value2.intensity));
    }
    uint _e73 = step_.light_base;
    float3 _e76 = variance;
    float _e77 = size;
    extras.Store4((_e73 + v_1)*16, asuint(float4(_e76, _e77)));
    return;
}

uint compact3_(uint v_2)
{
    uint x_1 = (uint)0;

    x_1 = (v_2 & 153391689u);
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

uint3 demorton3_(uint m)
{
    const uint _e1 = compact3_(m);
    const uint _e4 = compact3_((m >> 1u));
    const uint _e7 = compact3_((m >> 2u));
    return uint3(_e1, _e4, _e7);
}

uint naga_div(uint lhs, uint rhs) {
    return lhs / (rhs == 0u ? 1u : rhs);
}

uint naga_mod(uint lhs, uint rhs) {
    return lhs % (rhs == 0u ? 1u : rhs);
}

Part ConstructPart(uint arg0, uint arg1, uint3 arg2, uint arg3, bool arg4) {
    Part ret = (Part)0;
    ret.w = arg0;
    ret.v = arg1;
    ret.q = arg2;
    ret.g = arg3;
    ret.busy = arg4;
    return ret;
}

Part part(uint3 wg_4, uint3 groups_10, uint parts)
{
    uint w = (wg_4.x + (wg_4.y * groups_10.x));
    uint _e10 = step_.count;
    if ((w >= (_e10 * parts))) {
        const Part part_1 = ConstructPart(w, 0u, (0u).xxx, 0u, false);
        return part_1;
    }
    uint v_4 = naga_div(w, parts);
    uint _e23 = step_.list_offset;
    uint _e26 = asuint(vertex_slots.Load((_e23 + v_4)*4));
    const uint3 _e27 = demorton3_(_e26);
    const Part part_2 = ConstructPart(w, v_4, _e27, naga_mod(w, parts), true);
    return part_2;
}

void reduce(uint lane_6)
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
            if ((lane_6 < _e6)) {
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
                        float4 _e17 = lane_sums[min(uint(lane_6), 63u)][min(uint(_e15), 2u)];
                        uint _e19 = stride;
                        uint _e22 = a_3;
                        float4 _e24 = lane_sums[min(uint((lane_6 + _e19)), 63u)][min(uint(_e22), 2u)];
                        lane_sums[min(uint(lane_6), 63u)][min(uint(_e15), 2u)] = (_e17 + _e24);
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
    }
    GroupMemoryBarrierWithGroupSync();
    float4 sum[3] = Constructarray3_float4_((0.0).xxxx, (0.0).xxxx, (0.0).xxxx);
    uint g = (uint)0;
    uint a_1 = (uint)0;
    uint a_2 = 0u;

    const Part _e4 = part(wg_1, groups_6, 1u);
    if (!(_e4.busy)) {
        return;
    }
    uint _e10 = step_.parts;
    uint first = (_e4.v * _e10);
    g = lane_1;
    uint2 loop_bound_6 = uint2(4294967295u, 4294967295u);
    bool loop_init_6 = true;
    while(true) {
        if (all(loop_bound_6 == uint2(0u, 0u))) { break; }
        loop_bound_6 -= uint2(loop_bound_6.y == 0u, 1u);
        if (!loop_init_6) {
            uint _e45 = g;
            g = (_e45 + WORKGROUP);
        }
        loop_init_6 = false;
        uint _e21 = g;
        uint _e24 = step_.parts;
        if ((_e21 < _e24)) {
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
                    uint _e43 = a_1;
                    a_1 = (_e43 + 1u);
                }
                loop_init_7 = false;
                uint _e28 = a_1;
                if ((_e28 < 3u)) {
                } else {
                    break;
                }
                {
                    uint _e31 = a_1;
                    float4 _e33 = sum[min(uint(_e31), 2u)];
                    uint _e35 = g;
                    uint _e38 = a_1;
                    float4 _e40 = asfloat(partials.Load4(_e38*16+(first + _e35)*80));
                    sum[min(uint(_e31), 2u)] = (_e33 + _e40);
                }
            }
        }
    }
    float4 _e50[3] = sum;
    lane_sums[min(uint(lane_1), 63u)] = _e50;
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
                uint _e68 = a_2;
                a_2 = (_e68 + 1u);
            }
            loop_init_8 = false;
            uint _e58 = a_2;
            if ((_e58 < 3u)) {
            } else {
                break;
            }
            {
                uint _e63 = a_2;
                uint _e65 = a_2;
                partials.Store4(_e63*16+first*80, asuint(total[min(uint(_e65), 2u)]));
            }
        }
        Sums s_3 = ConstructSums(total[0].xyz, total[0].w, total[1].xyz, total[2].xyz);
        const float3 _e82 = centre(s_3);
        partials.Store4(48+first*80, asuint(float4(_e82, 0.0)));
        return;
    } else {
        return;
    }
}

