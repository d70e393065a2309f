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
};

struct Params {
    uint levels;
    uint points;
    float h0_;
    uint split;
};

static const uint WORKGROUP = 64u;
static const float INV_PI = 0.31830987;

cbuffer params : register(b0) { Params params; }
ByteAddressBuffer levels : register(t1);
ByteAddressBuffer starts : register(t2);
ByteAddressBuffer lights : register(t3);
ByteAddressBuffer lights_hi : register(t6);
ByteAddressBuffer points : register(t4);
RWByteAddressBuffer radiance : register(u5);

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

float3 contribution(Level level, uint k, float3 x, float3 n)
{
    Light light = (Light)0;
    bool local = (bool)0;
    float cosine = 0.0;

    uint i = (level.first_light + k);
    uint _e9 = params.split;
    if ((i < _e9)) {
        Light _e13 = ConstructLight(asfloat(lights.Load3(i*32+0)), asfloat(lights.Load3(i*32+16)));
        light = _e13;
    } else {
        uint _e17 = params.split;
        Light _e20 = ConstructLight(asfloat(lights_hi.Load3((i - _e17)*32+0)), asfloat(lights_hi.Load3((i - _e17)*32+16)));
        light = _e20;
    }
    float3 _e22 = light.position;
    float3 v = (_e22 - x);
    float d2_ = dot(v, v);
    if ((d2_ > level.inner2_)) {
        local = (d2_ <= level.outer2_);
    } else {
        local = false;
    }
    bool _e32 = local;
    if (!(_e32)) {
        return (0.0).xxx;
    }
    float d_1 = sqrt(d2_);
    float _e39 = params.h0_;
    float c = max(d_1, _e39);
    if ((d_1 > 0.0)) {
        cosine = max((dot(n, v) / d_1), 0.0);
    }
    float3 _e50 = light.intensity;
    const float _e52 = blend(level.ramp, d_1);
    float _e57 = cosine;
    return (_e50 * ((_e52 * (1.0 / (c * c))) * _e57));
}

uint3 naga_f2u32(float3 value) {
    return uint3(clamp(value, 0.0, 4294967000.0));
}

float3 level_sum(Level level_1, float3 x_1, float3 n_1)
{
    float3 sum_1 = (0.0).xxx;
    uint k_1 = 0u;
    bool local_1 = (bool)0;
    uint z = (uint)0;
    uint y = (uint)0;
    uint k_2 = (uint)0;

    if ((level_1.dims.x == 0u)) {
        uint2 loop_bound = uint2(4294967295u, 4294967295u);
        bool loop_init = true;
        while(true) {
            if (all(loop_bound == uint2(0u, 0u))) { break; }
            loop_bound -= uint2(loop_bound.y == 0u, 1u);
            if (!loop_init) {
                uint _e20 = k_1;
                k_1 = (_e20 + 1u);
            }
            loop_init = false;
            uint _e12 = k_1;
            if ((_e12 < level_1.light_count)) {
            } else {
                break;
            }
            {
                float3 _e15 = sum_1;
                uint _e16 = k_1;
                const float3 _e17 = contribution(level_1, _e16, x_1, n_1);
                sum_1 = (_e15 + _e17);
            }
        }
        float3 _e22 = sum_1;
        return _e22;
    }
    float reach = sqrt(level_1.outer2_);
    float3 lo = floor((((x_1 - (reach).xxx) - level_1.origin) / (level_1.cell).xxx));
    float3 hi = floor((((x_1 + (reach).xxx) - level_1.origin) / (level_1.cell).xxx));
    float3 top = float3((level_1.dims - (1u).xxx));
    if (!(any((hi < (0.0).xxx)))) {
        local_1 = any((lo > top));
    } else {
        local_1 = true;
    }
    bool _e56 = local_1;
    if (_e56) {
        float3 _e57 = sum_1;
        return _e57;
    }
    uint3 a = naga_f2u32(max(lo, (0.0).xxx));
    uint3 b = naga_f2u32(min(hi, top));
    z = a.z;
    uint2 loop_bound_1 = uint2(4294967295u, 4294967295u);
    bool loop_init_1 = true;
    while(true) {
        if (all(loop_bound_1 == uint2(0u, 0u))) { break; }
        loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
        if (!loop_init_1) {
            uint _e111 = z;
            z = (_e111 + 1u);
        }
        loop_init_1 = false;
        uint _e66 = z;
        if ((_e66 <= b.z)) {
        } else {
            break;
        }
        {
            y = a.y;
            uint2 loop_bound_2 = uint2(4294967295u, 4294967295u);
            bool loop_init_2 = true;
            while(true) {
                if (all(loop_bound_2 == uint2(0u, 0u))) { break; }
                loop_bound_2 -= uint2(loop_bound_2.y == 0u, 1u);
                if (!loop_init_2) {
                    uint _e108 = y;
                    y = (_e108 + 1u);
                }
                loop_init_2 = false;
                uint _e71 = y;
                if ((_e71 <= b.y)) {
                } else {
                    break;
                }
                {
                    uint _e75 = z;
                    uint _e79 = y;
                    uint row = (level_1.first_cell + (((_e75 * level_1.dims.y) + _e79) * level_1.dims.x));
                    uint start = asuint(starts.Load((row + a.x)*4));
                    uint end = asuint(starts.Load(((row + b.x) + 1u)*4));
                    k_2 = start;
                    uint2 loop_bound_3 = uint2(4294967295u, 4294967295u);
                    bool loop_init_3 = true;
                    while(true) {
                        if (all(loop_bound_3 == uint2(0u, 0u))) { break; }
                        loop_bound_3 -= uint2(loop_bound_3.y == 0u, 1u);
                        if (!loop_init_3) {
                            uint _e105 = k_2;
                            k_2 = (_e105 + 1u);
                        }
                        loop_init_3 = false;
                        uint _e98 = k_2;
                        if ((_e98 < end)) {
                        } else {
                            break;
                        }
                        {
                            float3 _e100 = sum_1;
                            uint _e101 = k_2;
                            const float3 _e102 = contribution(level_1, _e101, x_1, n_1);
                            sum_1 = (_e100 + _e102);
                        }
                    }
                }
            }
        }
    }
    float3 _e113 = sum_1;
    return _e113;
}

Point ConstructPoint(float3 arg0, float3 arg1, float3 arg2) {
    Point ret = (Point)0;
    ret.position = arg0;
    ret.normal = arg1;
    ret.albedo = arg2;
    return ret;
}

Level ConstructLevel(float3 arg0, float arg1, uint3 arg2, uint arg3, uint arg4, uint arg5, float arg6, float arg7, float4 arg8) {
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
    return ret;
}

[numthreads(64, 1, 1)]
void shade(uint3 id : SV_DispatchThreadID, uint3 groups : SV_GroupID)
{
    float3 sum = (0.0).xxx;
    uint l = 0u;

    uint i_1 = (id.x + ((id.y * groups.x) * WORKGROUP));
    uint _e11 = params.points;
    if ((i_1 >= _e11)) {
        return;
    }
    Point p = ConstructPoint(asfloat(points.Load3(i_1*48+0)), asfloat(points.Load3(i_1*48+16)), asfloat(points.Load3(i_1*48+32)));
    uint2 loop_bound_4 = uint2(4294967295u, 4294967295u);
    bool loop_init_4 = true;
    while(true) {
        if (all(loop_bound_4 == uint2(0u, 0u))) { break; }
        loop_bound_4 -= uint2(loop_bound_4.y == 0u, 1u);
        if (!loop_init_4) {
            uint _e36 = l;
            l = (_e36 + 1u);
        }
        loop_init_4 = false;
        uint _e21 = l;
        uint _e24 = params.levels;
        if ((_e21 < _e24)) {
        } else {
            break;
        }
        {
            float3 _e26 = sum;
            uint _e28 = l;
            Level _e30 = ConstructLevel(asfloat(levels.Load3(_e28*64+0)), asfloat(levels.Load(_e28*64+12)), asuint(levels.Load3(_e28*64+16)), asuint(levels.Load(_e28*64+28)), asuint(levels.Load(_e28*64+32)), asuint(levels.Load(_e28*64+36)), asfloat(levels.Load(_e28*64+40)), asfloat(levels.Load(_e28*64+44)), asfloat(levels.Load4(_e28*64+48)));
            const float3 _e33 = level_sum(_e30, p.position, p.normal);
            sum = (_e26 + _e33);
        }
    }
    float3 _e40 = sum;
    radiance.Store4(i_1*16, asuint(float4(((_e40 * p.albedo) * INV_PI), 0.0)));
    return;
}
