struct Light {
    float3 position;
    int _pad1_0;
    float3 intensity;
    int _end_pad_0;
};

struct Point {
    float3 position;
    int _pad1_0;
    float3 normal;
    int _pad2_0;
    float3 albedo;
    int _end_pad_0;
};

struct Level {
    float3 origin;
    float cell;
    uint3 dims;
    uint first_cell;
    uint first_light;
    uint light_count;
    float inner2_;
    float outer2_;
    float4 ramp;
    float margin;
    uint stride;
    uint order;
    uint bank;
};

struct Params {
    uint levels;
    uint points;
    float h0_;
    uint split;
    uint k;
    uint seed;
    uint _pad0_;
    uint _pad1_;
};

struct Sample {
    float3 position;
    int _pad1_0;
    float3 weight;
    int _end_pad_0;
};

static const uint WORKGROUP = 64u;
static const float INV_PI = 0.31830987;
static const uint CELLS_ROWS = 0u;
static const uint CELLS_MORTON = 1u;
static const uint STARTS_CELLS = 0u;
static const uint STARTS_SLOTS = 1u;
static const float3 LUMINANCE = float3(0.2126, 0.7152, 0.0722);
static const uint MAX_K = 16u;

cbuffer params : register(b0) { Params params; }
ByteAddressBuffer levels : register(t1);
ByteAddressBuffer starts : register(t2);
ByteAddressBuffer lights : register(t3);
ByteAddressBuffer lights_hi : register(t6);
ByteAddressBuffer points : register(t4);
ByteAddressBuffer slots : register(t7);
static float total = (float)0;
static uint rng = (uint)0;
static float3 chosen_position[16] = (float3[16])0;
static float3 chosen_term[16] = (float3[16])0;
static float chosen_weight[16] = (float[16])0;
RWByteAddressBuffer samples : register(u5);

float blend(float4 ramp, float d)
{
    float rise = ((d * ramp.x) + ramp.y);
    float fall = (ramp.w - (d * ramp.z));
    return clamp(min(rise, fall), 0.0, 1.0);
}

Light ConstructLight(float3 arg0, float3 arg1) {
    Light ret = (Light)0;
    ret.position = arg0;
    ret.intensity = arg1;
    return ret;
}

Light light_at(uint i)
{
    uint _e3 = params.split;
    if ((i < _e3)) {
        Light _e7 = ConstructLight(asfloat(lights.Load3(i*32+0)), asfloat(lights.Load3(i*32+16)));
        const Light light_2 = _e7;
        return light_2;
    }
    uint _e11 = params.split;
    Light _e14 = ConstructLight(asfloat(lights_hi.Load3((i - _e11)*32+0)), asfloat(lights_hi.Load3((i - _e11)*32+16)));
    const Light light_3 = _e14;
    return light_3;
}

float3 contribution(Level level, Light light, float3 x, float3 n)
{
    bool local = (bool)0;
    float cosine = 0.0;

    float3 v_3 = (light.position - x);
    float d2_ = dot(v_3, v_3);
    if ((d2_ > level.inner2_)) {
        local = (d2_ <= level.outer2_);
    } else {
        local = false;
    }
    bool _e14 = local;
    if (!(_e14)) {
        return (0.0).xxx;
    }
    float d_1 = sqrt(d2_);
    float _e21 = params.h0_;
    float c_2 = max(d_1, _e21);
    if ((d_1 > 0.0)) {
        cosine = max((dot(n, v_3) / d_1), 0.0);
    }
    const float _e33 = blend(level.ramp, d_1);
    float _e38 = cosine;
    return (light.intensity * ((_e33 * (1.0 / (c_2 * c_2))) * _e38));
}

float next_uniform()
{
    uint _e2 = rng;
    rng = ((_e2 * 747796405u) + 2891336453u);
    uint _e8 = rng;
    return (float((_e8 >> 8u)) * 5.9604645e-8);
}

void visit(uint i_1, Light light_1, float3 term)
{
    uint r_2 = 0u;

    float w = dot(term, LUMINANCE);
    if (!((w > 0.0))) {
        return;
    }
    float _e9 = total;
    total = (_e9 + w);
    uint2 loop_bound = uint2(4294967295u, 4294967295u);
    bool loop_init = true;
    while(true) {
        if (all(loop_bound == uint2(0u, 0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e34 = r_2;
            r_2 = (_e34 + 1u);
        }
        loop_init = false;
        uint _e13 = r_2;
        uint _e16 = params.k;
        if ((_e13 < _e16)) {
        } else {
            break;
        }
        {
            const float _e18 = next_uniform();
            float _e20 = total;
            if (((_e18 * _e20) < w)) {
                uint _e24 = r_2;
                chosen_position[min(uint(_e24), 15u)] = light_1.position;
                uint _e28 = r_2;
                chosen_term[min(uint(_e28), 15u)] = term;
                uint _e31 = r_2;
                chosen_weight[min(uint(_e31), 15u)] = w;
            }
        }
    }
    return;
}

void visit_range(Level level_1, uint start, uint end, float3 x_1, float3 n_1)
{
    uint k = (uint)0;

    k = start;
    uint2 loop_bound_1 = uint2(4294967295u, 4294967295u);
    bool loop_init_1 = true;
    while(true) {
        if (all(loop_bound_1 == uint2(0u, 0u))) { break; }
        loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
        if (!loop_init_1) {
            uint _e14 = k;
            k = (_e14 + 1u);
        }
        loop_init_1 = false;
        uint _e6 = k;
        if ((_e6 < end)) {
        } else {
            break;
        }
        {
            uint _e9 = k;
            uint i_3 = (level_1.first_light + _e9);
            const Light _e11 = light_at(i_3);
            const float3 _e12 = contribution(level_1, _e11, x_1, n_1);
            visit(i_3, _e11, _e12);
        }
    }
    return;
}

uint cell_start(Level level_2, uint i_2)
{
    if ((level_2.bank == STARTS_SLOTS)) {
        uint _e7 = asuint(slots.Load(i_2*4));
        return _e7;
    }
    uint _e10 = asuint(starts.Load(i_2*4));
    return _e10;
}

uint spread3_(uint v)
{
    uint x_2 = (uint)0;

    x_2 = (v & 1023u);
    uint _e4 = x_2;
    uint _e5 = x_2;
    x_2 = ((_e4 | (_e5 << 16u)) & 50331903u);
    uint _e11 = x_2;
    uint _e12 = x_2;
    x_2 = ((_e11 | (_e12 << 8u)) & 50393103u);
    uint _e18 = x_2;
    uint _e19 = x_2;
    x_2 = ((_e18 | (_e19 << 4u)) & 51130563u);
    uint _e25 = x_2;
    uint _e26 = x_2;
    x_2 = ((_e25 | (_e26 << 2u)) & 153391689u);
    uint _e32 = x_2;
    return _e32;
}

uint morton3_(uint3 c)
{
    const uint _e2 = spread3_(c.x);
    const uint _e4 = spread3_(c.y);
    const uint _e9 = spread3_(c.z);
    return ((_e2 | (_e4 << 1u)) | (_e9 << 2u));
}

uint3 naga_f2u32(float3 value) {
    return uint3(clamp(value, 0.0, 4294967000.0));
}

void walk_level(Level level_3, float3 x_3, float3 n_2)
{
    bool local_1 = (bool)0;
    uint z = (uint)0;
    uint y = (uint)0;
    uint c_1 = (uint)0;

    if ((level_3.dims.x == 0u)) {
        visit_range(level_3, 0u, level_3.light_count, x_3, n_2);
        return;
    }
    float reach = (sqrt(level_3.outer2_) + level_3.margin);
    float3 lo = floor((((x_3 - (reach).xxx) - level_3.origin) / (level_3.cell).xxx));
    float3 hi = floor((((x_3 + (reach).xxx) - level_3.origin) / (level_3.cell).xxx));
    float3 top = float3((level_3.dims - (1u).xxx));
    if (!(any((hi < (0.0).xxx)))) {
        local_1 = any((lo > top));
    } else {
        local_1 = true;
    }
    bool _e44 = local_1;
    if (_e44) {
        return;
    }
    uint3 a = naga_f2u32(max(lo, (0.0).xxx));
    uint3 b = naga_f2u32(min(hi, top));
    uint s = level_3.stride;
    z = a.z;
    uint2 loop_bound_2 = uint2(4294967295u, 4294967295u);
    bool loop_init_2 = true;
    while(true) {
        if (all(loop_bound_2 == uint2(0u, 0u))) { break; }
        loop_bound_2 -= uint2(loop_bound_2.y == 0u, 1u);
        if (!loop_init_2) {
            uint _e143 = z;
            z = (_e143 + 1u);
        }
        loop_init_2 = false;
        uint _e54 = z;
        if ((_e54 <= b.z)) {
        } else {
            break;
        }
        {
            y = a.y;
            uint2 loop_bound_3 = uint2(4294967295u, 4294967295u);
            bool loop_init_3 = true;
            while(true) {
                if (all(loop_bound_3 == uint2(0u, 0u))) { break; }
                loop_bound_3 -= uint2(loop_bound_3.y == 0u, 1u);
                if (!loop_init_3) {
                    uint _e140 = y;
                    y = (_e140 + 1u);
                }
                loop_init_3 = false;
                uint _e59 = y;
                if ((_e59 <= b.y)) {
                } else {
                    break;
                }
                {
                    if ((level_3.order == CELLS_ROWS)) {
                        uint _e65 = z;
                        uint _e69 = y;
                        uint row = (((_e65 * level_3.dims.y) + _e69) * level_3.dims.x);
                        const uint _e79 = cell_start(level_3, (level_3.first_cell + (s * (row + a.x))));
                        const uint _e87 = cell_start(level_3, (level_3.first_cell + (s * ((row + b.x) + 1u))));
                        visit_range(level_3, _e79, _e87, x_3, n_2);
                    } else {
                        c_1 = a.x;
                        uint2 loop_bound_4 = uint2(4294967295u, 4294967295u);
                        bool loop_init_4 = true;
                        while(true) {
                            if (all(loop_bound_4 == uint2(0u, 0u))) { break; }
                            loop_bound_4 -= uint2(loop_bound_4.y == 0u, 1u);
                            if (!loop_init_4) {
                                uint _e137 = c_1;
                                c_1 = (_e137 + 1u);
                            }
                            loop_init_4 = false;
                            uint _e90 = c_1;
                            if ((_e90 <= b.x)) {
                            } else {
                                break;
                            }
                            {
                                uint _e94 = c_1;
                                uint _e95 = y;
                                uint _e96 = z;
                                float3 low = ((level_3.origin + (float3(uint3(_e94, _e95, _e96)) * level_3.cell)) - (level_3.margin).xxx);
                                float3 high = (low + ((level_3.cell + (2.0 * level_3.margin))).xxx);
                                float3 out_ = max(max((low - x_3), (x_3 - high)), (0.0).xxx);
                                if ((dot(out_, out_) > level_3.outer2_)) {
                                    continue;
                                }
                                uint _e121 = c_1;
                                uint _e122 = y;
                                uint _e123 = z;
                                const uint _e125 = morton3_(uint3(_e121, _e122, _e123));
                                const uint _e129 = cell_start(level_3, (level_3.first_cell + (s * _e125)));
                                const uint _e135 = cell_start(level_3, (level_3.first_cell + (s * (_e125 + 1u))));
                                visit_range(level_3, _e129, _e135, x_3, n_2);
                            }
                        }
                    }
                }
            }
        }
    }
    return;
}

Level ConstructLevel(float3 arg0, float arg1, uint3 arg2, uint arg3, uint arg4, uint arg5, float arg6, float arg7, float4 arg8, float arg9, uint arg10, uint arg11, uint arg12) {
    Level ret = (Level)0;
    ret.origin = arg0;
    ret.cell = arg1;
    ret.dims = arg2;
    ret.first_cell = arg3;
    ret.first_light = arg4;
    ret.light_count = arg5;
    ret.inner2_ = arg6;
    ret.outer2_ = arg7;
    ret.ramp = arg8;
    ret.margin = arg9;
    ret.stride = arg10;
    ret.order = arg11;
    ret.bank = arg12;
    return ret;
}

void walk(float3 x_4, float3 n_3)
{
    uint l = 0u;

    uint2 loop_bound_5 = uint2(4294967295u, 4294967295u);
    bool loop_init_5 = true;
    while(true) {
        if (all(loop_bound_5 == uint2(0u, 0u))) { break; }
        loop_bound_5 -= uint2(loop_bound_5.y == 0u, 1u);
        if (!loop_init_5) {
            uint _e14 = l;
            l = (_e14 + 1u);
        }
        loop_init_5 = false;
        uint _e4 = l;
        uint _e7 = params.levels;
        if ((_e4 < _e7)) {
        } else {
            break;
        }
        {
            uint _e10 = l;
            Level _e12 = ConstructLevel(asfloat(levels.Load3(_e10*80+0)), asfloat(levels.Load(_e10*80+12)), asuint(levels.Load3(_e10*80+16)), asuint(levels.Load(_e10*80+28)), asuint(levels.Load(_e10*80+32)), asuint(levels.Load(_e10*80+36)), asfloat(levels.Load(_e10*80+40)), asfloat(levels.Load(_e10*80+44)), asfloat(levels.Load4(_e10*80+48)), asfloat(levels.Load(_e10*80+64)), asuint(levels.Load(_e10*80+68)), asuint(levels.Load(_e10*80+72)), asuint(levels.Load(_e10*80+76)));
            walk_level(_e12, x_4, n_3);
        }
    }
    return;
}

uint point_index(uint3 id_1, uint3 groups_1)
{
    return (id_1.x + ((id_1.y * groups_1.x) * WORKGROUP));
}

uint compact3_(uint v_1)
{
    uint x_5 = (uint)0;

    x_5 = (v_1 & 153391689u);
    uint _e4 = x_5;
    uint _e5 = x_5;
    x_5 = ((_e4 | (_e5 >> 2u)) & 51130563u);
    uint _e11 = x_5;
    uint _e12 = x_5;
    x_5 = ((_e11 | (_e12 >> 4u)) & 50393103u);
    uint _e18 = x_5;
    uint _e19 = x_5;
    x_5 = ((_e18 | (_e19 >> 8u)) & 50331903u);
    uint _e25 = x_5;
    uint _e26 = x_5;
    x_5 = ((_e25 | (_e26 >> 16u)) & 1023u);
    uint _e32 = x_5;
    return _e32;
}

uint3 demorton3_(uint m)
{
    const uint _e1 = compact3_(m);
    const uint _e4 = compact3_((m >> 1u));
    const uint _e7 = compact3_((m >> 2u));
    return uint3(_e1, _e4, _e7);
}

uint pcg(uint v_2)
{
    uint state = ((v_2 * 747796405u) + 2891336453u);
    uint word = (((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u);
    return ((word >> 22u) ^ word);
}

Sample ConstructSample(float3 arg0, float3 arg1) {
    Sample ret = (Sample)0;
    ret.position = arg0;
    ret.weight = arg1;
    return ret;
}

Point ConstructPoint(float3 arg0, float3 arg1, float3 arg2) {
    Point ret = (Point)0;
    ret.position = arg0;
    ret.normal = arg1;
    ret.albedo = arg2;
    return ret;
}

[numthreads(64, 1, 1)]
void gather(uint3 id : SV_DispatchThreadID, uint3 groups : SV_GroupID)
{
    uint r = 0u;
    uint r_1 = 0u;
    float3 weight = (float3)0;

    const uint _e2 = point_index(id, groups);
    uint _e5 = params.points;
    if ((_e2 >= _e5)) {
        return;
    }
    Point p = ConstructPoint(asfloat(points.Load3(_e2*48+0)), asfloat(points.Load3(_e2*48+16)), asfloat(points.Load3(_e2*48+32)));
    uint _e13 = params.seed;
    const uint _e14 = pcg(_e2);
    const uint _e16 = pcg((_e13 ^ _e14));
    rng = _e16;
    total = 0.0;
    uint2 loop_bound_6 = uint2(4294967295u, 4294967295u);
    bool loop_init_6 = true;
    while(true) {
        if (all(loop_bound_6 == uint2(0u, 0u))) { break; }
        loop_bound_6 -= uint2(loop_bound_6.y == 0u, 1u);
        if (!loop_init_6) {
            uint _e39 = r;
            r = (_e39 + 1u);
        }
        loop_init_6 = false;
        uint _e21 = r;
        if ((_e21 < MAX_K)) {
        } else {
            break;
        }
        {
            uint _e25 = r;
            chosen_position[min(uint(_e25), 15u)] = (0.0).xxx;
            uint _e30 = r;
            chosen_term[min(uint(_e30), 15u)] = (0.0).xxx;
            uint _e35 = r;
            chosen_weight[min(uint(_e35), 15u)] = 0.0;
        }
    }
    walk(p.position, p.normal);
    uint _e47 = params.k;
    float3 scale = (p.albedo * (INV_PI / float(_e47)));
    uint2 loop_bound_7 = uint2(4294967295u, 4294967295u);
    bool loop_init_7 = true;
    while(true) {
        if (all(loop_bound_7 == uint2(0u, 0u))) { break; }
        loop_bound_7 -= uint2(loop_bound_7.y == 0u, 1u);
        if (!loop_init_7) {
            uint _e95 = r_1;
            r_1 = (_e95 + 1u);
        }
        loop_init_7 = false;
        uint _e53 = r_1;
        uint _e56 = params.k;
        if ((_e53 < _e56)) {
        } else {
            break;
        }
        {
            weight = (0.0).xxx;
            uint _e62 = r_1;
            float _e64 = chosen_weight[min(uint(_e62), 15u)];
            if ((_e64 > 0.0)) {
                uint _e68 = r_1;
                float3 _e70 = chosen_term[min(uint(_e68), 15u)];
                float _e72 = total;
                uint _e74 = r_1;
                float _e76 = chosen_weight[min(uint(_e74), 15u)];
                weight = ((_e70 * (_e72 / _e76)) * scale);
            }
            uint _e83 = params.k;
            uint _e85 = r_1;
            uint _e89 = r_1;
            float3 _e91 = chosen_position[min(uint(_e89), 15u)];
            float3 _e92 = weight;
            {
                Sample _value4 = ConstructSample(_e91, _e92);
                samples.Store3(((_e2 * _e83) + _e85)*32+0, asuint(_value4.position));
                samples.Store3(((_e2 * _e83) + _e85)*32+16, asuint(_value4.weight));
            }
        }
    }
    return;
}
