// language: metal2.4
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;

struct _mslBufferSizes {
    uint size1;
    uint size2;
    uint size3;
    uint size4;
    uint size5;
    uint size6;
};

struct Light {
    metal::float3 position;
    metal::float3 intensity;
};
struct Point {
    metal::float3 position;
    metal::float3 normal;
    metal::float3 albedo;
};
struct Level {
    metal::packed_float3 origin;
    float cell;
    metal::packed_uint3 dims;
    uint first_cell;
    uint first_light;
    uint light_count;
    float inner2_;
    float outer2_;
    metal::float4 ramp;
};
struct Params {
    uint levels;
    uint points;
    float h0_;
    uint split;
};
typedef Level type_5[1];
typedef uint type_6[1];
typedef Light type_7[1];
typedef Point type_8[1];
typedef metal::float4 type_9[1];
constant uint WORKGROUP = 64u;
constant float INV_PI = 0.31830987;

float blend(
    metal::float4 ramp,
    float d
) {
    float rise = (d * ramp.x) + ramp.y;
    float fall = ramp.w - (d * ramp.z);
    return metal::clamp(metal::min(rise, fall), 0.0, 1.0);
}

metal::float3 contribution(
    Level level,
    uint k,
    metal::float3 x,
    metal::float3 n,
    constant Params& params,
    device type_7 const& lights,
    device type_7 const& lights_hi,
    constant _mslBufferSizes& _buffer_sizes
) {
    Light light = {};
    bool local = {};
    float cosine = 0.0;
    uint i = level.first_light + k;
    uint _e9 = params.split;
    if (i < _e9) {
        Light _e13 = lights[i];
        light = _e13;
    } else {
        uint _e17 = params.split;
        Light _e20 = lights_hi[i - _e17];
        light = _e20;
    }
    metal::float3 _e22 = light.position;
    metal::float3 v = _e22 - x;
    float d2_ = metal::dot(v, v);
    if (d2_ > level.inner2_) {
        local = d2_ <= level.outer2_;
    } else {
        local = false;
    }
    bool _e32 = local;
    if (!(_e32)) {
        return metal::float3(0.0);
    }
    float d_1 = metal::sqrt(d2_);
    float _e39 = params.h0_;
    float c = metal::max(d_1, _e39);
    if (d_1 > 0.0) {
        cosine = metal::max(metal::dot(n, v) / d_1, 0.0);
    }
    metal::float3 _e50 = light.intensity;
    float _e52 = blend(level.ramp, d_1);
    float _e57 = cosine;
    return _e50 * ((_e52 * (1.0 / (c * c))) * _e57);
}

metal::uint3 naga_f2u32(metal::float3 value) {
    return static_cast<metal::uint3>(metal::clamp(value, 0.0, 4294967000.0));
}

metal::float3 level_sum(
    Level level_1,
    metal::float3 x_1,
    metal::float3 n_1,
    constant Params& params,
    device type_6 const& starts,
    device type_7 const& lights,
    device type_7 const& lights_hi,
    constant _mslBufferSizes& _buffer_sizes
) {
    metal::float3 sum_1 = metal::float3(0.0);
    uint k_1 = 0u;
    bool local_1 = {};
    uint z = {};
    uint y = {};
    uint k_2 = {};
    if (level_1.dims[0] == 0u) {
        uint2 loop_bound = uint2(4294967295u);
        bool loop_init = true;
        while(true) {
            if (metal::all(loop_bound == uint2(0u))) { break; }
            loop_bound -= uint2(loop_bound.y == 0u, 1u);
            if (!loop_init) {
                uint _e20 = k_1;
                k_1 = _e20 + 1u;
            }
            loop_init = false;
            uint _e12 = k_1;
            if (_e12 < level_1.light_count) {
            } else {
                break;
            }
            {
                metal::float3 _e15 = sum_1;
                uint _e16 = k_1;
                metal::float3 _e17 = contribution(level_1, _e16, x_1, n_1, params, lights, lights_hi, _buffer_sizes);
                sum_1 = _e15 + _e17;
            }
        }
        metal::float3 _e22 = sum_1;
        return _e22;
    }
    float reach = metal::sqrt(level_1.outer2_);
    metal::float3 lo = metal::floor(((x_1 - metal::float3(reach)) - level_1.origin) / metal::float3(level_1.cell));
    metal::float3 hi = metal::floor(((x_1 + metal::float3(reach)) - level_1.origin) / metal::float3(level_1.cell));
    metal::float3 top = static_cast<metal::float3>(level_1.dims - metal::uint3(1u));
    if (!(metal::any(hi < metal::float3(0.0)))) {
        local_1 = metal::any(lo > top);
    } else {
        local_1 = true;
    }
    bool _e56 = local_1;
    if (_e56) {
        metal::float3 _e57 = sum_1;
        return _e57;
    }
    metal::uint3 a = naga_f2u32(metal::max(lo, metal::float3(0.0)));
    metal::uint3 b = naga_f2u32(metal::min(hi, top));
    z = a.z;
    uint2 loop_bound_1 = uint2(4294967295u);
    bool loop_init_1 = true;
    while(true) {
        if (metal::all(loop_bound_1 == uint2(0u))) { break; }
        loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
        if (!loop_init_1) {
            uint _e111 = z;
            z = _e111 + 1u;
        }
        loop_init_1 = false;
        uint _e66 = z;
        if (_e66 <= b.z) {
        } else {
            break;
        }
        {
            y = a.y;
            uint2 loop_bound_2 = uint2(4294967295u);
            bool loop_init_2 = true;
            while(true) {
                if (metal::all(loop_bound_2 == uint2(0u))) { break; }
                loop_bound_2 -= uint2(loop_bound_2.y == 0u, 1u);
                if (!loop_init_2) {
                    uint _e108 = y;
                    y = _e108 + 1u;
                }
                loop_init_2 = false;
                uint _e71 = y;
                if (_e71 <= b.y) {
                } else {
                    break;
                }
                {
                    uint _e75 = z;
                    uint _e79 = y;
                    uint row = level_1.first_cell + (((_e75 * level_1.dims[1]) + _e79) * level_1.dims[0]);
                    uint start = starts[row + a.x];
                    uint end = starts[(row + b.x) + 1u];
                    k_2 = start;
                    uint2 loop_bound_3 = uint2(4294967295u);
                    bool loop_init_3 = true;
                    while(true) {
                        if (metal::all(loop_bound_3 == uint2(0u))) { break; }
                        loop_bound_3 -= uint2(loop_bound_3.y == 0u, 1u);
                        if (!loop_init_3) {
                            uint _e105 = k_2;
                            k_2 = _e105 + 1u;
                        }
                        loop_init_3 = false;
                        uint _e98 = k_2;
                        if (_e98 < end) {
                        } else {
                            break;
                        }
                        {
                            metal::float3 _e100 = sum_1;
                            uint _e101 = k_2;
                            metal::float3 _e102 = contribution(level_1, _e101, x_1, n_1, params, lights, lights_hi, _buffer_sizes);
                            sum_1 = _e100 + _e102;
                        }
                    }
                }
            }
        }
    }
    metal::float3 _e113 = sum_1;
    return _e113;
}

struct shadeInput {
};
[[max_total_threads_per_threadgroup(64)]] kernel void shade(
  metal::uint3 id [[thread_position_in_grid]]
, metal::uint3 groups [[threadgroups_per_grid]]
, constant Params& params [[user(fake0)]]
, device type_5 const& levels [[user(fake0)]]
, device type_6 const& starts [[user(fake0)]]
, device type_7 const& lights [[user(fake0)]]
, device type_7 const& lights_hi [[user(fake0)]]
, device type_8 const& points [[user(fake0)]]
, device type_9& radiance [[user(fake0)]]
, constant _mslBufferSizes& _buffer_sizes [[user(fake0)]]
) {
    metal::float3 sum = metal::float3(0.0);
    uint l = 0u;
    uint i_1 = id.x + ((id.y * groups.x) * WORKGROUP);
    uint _e11 = params.points;
    if (i_1 >= _e11) {
        return;
    }
    Point p = points[i_1];
    uint2 loop_bound_4 = uint2(4294967295u);
    bool loop_init_4 = true;
    while(true) {
        if (metal::all(loop_bound_4 == uint2(0u))) { break; }
        loop_bound_4 -= uint2(loop_bound_4.y == 0u, 1u);
        if (!loop_init_4) {
            uint _e36 = l;
            l = _e36 + 1u;
        }
        loop_init_4 = false;
        uint _e21 = l;
        uint _e24 = params.levels;
        if (_e21 < _e24) {
        } else {
            break;
        }
        {
            metal::float3 _e26 = sum;
            uint _e28 = l;
            Level _e30 = levels[_e28];
            metal::float3 _e33 = level_sum(_e30, p.position, p.normal, params, starts, lights, lights_hi, _buffer_sizes);
            sum = _e26 + _e33;
        }
    }
    metal::float3 _e40 = sum;
    radiance[i_1] = metal::float4((_e40 * p.albedo) * INV_PI, 0.0);
    return;
}
