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
    uint size12;
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
typedef Level type_5[1];
typedef uint type_6[1];
typedef Light type_7[1];
typedef Point type_8[1];
struct type_10 {
    metal::float3 inner[16];
};
struct type_11 {
    float inner[16];
};
struct Sample {
    metal::float3 position;
    metal::float3 weight;
};
typedef Sample type_12[1];
constant uint WORKGROUP = 64u;
constant float INV_PI = 0.31830987;
constant uint CELLS_ROWS = 0u;
constant uint CELLS_MORTON = 1u;
constant uint STARTS_CELLS = 0u;
constant uint STARTS_SLOTS = 1u;
constant metal::float3 LUMINANCE = metal::float3(0.2126, 0.7152, 0.0722);
constant uint MAX_K = 16u;

float blend(
    metal::float4 ramp,
    float d
) {
    float rise = (d * ramp.x) + ramp.y;
    float fall = ramp.w - (d * ramp.z);
    return metal::clamp(metal::min(rise, fall), 0.0, 1.0);
}

Light light_at(
    uint i,
    constant Params& params,
    device type_7 const& lights,
    device type_7 const& lights_hi,
    constant _mslBufferSizes& _buffer_sizes
) {
    uint _e3 = params.split;
    if (i < _e3) {
        Light _e7 = lights[i];
        return _e7;
    }
    uint _e11 = params.split;
    Light _e14 = lights_hi[i - _e11];
    return _e14;
}

metal::float3 contribution(
    Level level,
    Light light,
    metal::float3 x,
    metal::float3 n,
    constant Params& params
) {
    bool local = {};
    float cosine = 0.0;
    metal::float3 v_3 = light.position - x;
    float d2_ = metal::dot(v_3, v_3);
    if (d2_ > level.inner2_) {
        local = d2_ <= level.outer2_;
    } else {
        local = false;
    }
    bool _e14 = local;
    if (!(_e14)) {
        return metal::float3(0.0);
    }
    float d_1 = metal::sqrt(d2_);
    float _e21 = params.h0_;
    float c_2 = metal::max(d_1, _e21);
    if (d_1 > 0.0) {
        cosine = metal::max(metal::dot(n, v_3) / d_1, 0.0);
    }
    float _e33 = blend(level.ramp, d_1);
    float _e38 = cosine;
    return light.intensity * ((_e33 * (1.0 / (c_2 * c_2))) * _e38);
}

float next_uniform(
    thread uint& rng
) {
    uint _e2 = rng;
    rng = (_e2 * 747796405u) + 2891336453u;
    uint _e8 = rng;
    return static_cast<float>(_e8 >> 8u) * 0.000000059604645;
}

void visit(
    uint i_1,
    Light light_1,
    metal::float3 term,
    constant Params& params,
    thread float& total,
    thread uint& rng,
    thread type_10& chosen_position,
    thread type_10& chosen_term,
    thread type_11& chosen_weight
) {
    uint r_2 = 0u;
    float w = metal::dot(term, LUMINANCE);
    if (!((w > 0.0))) {
        return;
    }
    float _e9 = total;
    total = _e9 + w;
    uint2 loop_bound = uint2(4294967295u);
    bool loop_init = true;
    while(true) {
        if (metal::all(loop_bound == uint2(0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e34 = r_2;
            r_2 = _e34 + 1u;
        }
        loop_init = false;
        uint _e13 = r_2;
        uint _e16 = params.k;
        if (_e13 < _e16) {
        } else {
            break;
        }
        {
            float _e18 = next_uniform(rng);
            float _e20 = total;
            if ((_e18 * _e20) < w) {
                uint _e24 = r_2;
                chosen_position.inner[_e24] = light_1.position;
                uint _e28 = r_2;
                chosen_term.inner[_e28] = term;
                uint _e31 = r_2;
                chosen_weight.inner[_e31] = w;
            }
        }
    }
    return;
}

void visit_range(
    Level level_1,
    uint start,
    uint end,
    metal::float3 x_1,
    metal::float3 n_1,
    constant Params& params,
    device type_7 const& lights,
    device type_7 const& lights_hi,
    thread float& total,
    thread uint& rng,
    thread type_10& chosen_position,
    thread type_10& chosen_term,
    thread type_11& chosen_weight,
    constant _mslBufferSizes& _buffer_sizes
) {
    uint k = {};
    k = start;
    uint2 loop_bound_1 = uint2(4294967295u);
    bool loop_init_1 = true;
    while(true) {
        if (metal::all(loop_bound_1 == uint2(0u))) { break; }
        loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
        if (!loop_init_1) {
            uint _e14 = k;
            k = _e14 + 1u;
        }
        loop_init_1 = false;
        uint _e6 = k;
        if (_e6 < end) {
        } else {
            break;
        }
        {
            uint _e9 = k;
            uint i_3 = level_1.first_light + _e9;
            Light _e11 = light_at(i_3, params, lights, lights_hi, _buffer_sizes);
            metal::float3 _e12 = contribution(level_1, _e11, x_1, n_1, params);
            visit(i_3, _e11, _e12, params, total, rng, chosen_position, chosen_term, chosen_weight);
        }
    }
    return;
}

uint cell_start(
    Level level_2,
    uint i_2,
    device type_6 const& starts,
    device type_6 const& slots,
    constant _mslBufferSizes& _buffer_sizes
) {
    if (level_2.bank == STARTS_SLOTS) {
        uint _e7 = slots[i_2];
        return _e7;
    }
    uint _e10 = starts[i_2];
    return _e10;
}

uint spread3_(
    uint v
) {
    uint x_2 = {};
    x_2 = v & 1023u;
    uint _e4 = x_2;
    uint _e5 = x_2;
    x_2 = (_e4 | (_e5 << 16u)) & 50331903u;
    uint _e11 = x_2;
    uint _e12 = x_2;
    x_2 = (_e11 | (_e12 << 8u)) & 50393103u;
    uint _e18 = x_2;
    uint _e19 = x_2;
    x_2 = (_e18 | (_e19 << 4u)) & 51130563u;
    uint _e25 = x_2;
    uint _e26 = x_2;
    x_2 = (_e25 | (_e26 << 2u)) & 153391689u;
    uint _e32 = x_2;
    return _e32;
}

uint morton3_(
    metal::uint3 c
) {
    uint _e2 = spread3_(c.x);
    uint _e4 = spread3_(c.y);
    uint _e9 = spread3_(c.z);
    return (_e2 | (_e4 << 1u)) | (_e9 << 2u);
}

metal::uint3 naga_f2u32(metal::float3 value) {
    return static_cast<metal::uint3>(metal::clamp(value, 0.0, 4294967000.0));
}

void walk_level(
    Level level_3,
    metal::float3 x_3,
    metal::float3 n_2,
    constant Params& params,
    device type_6 const& starts,
    device type_7 const& lights,
    device type_7 const& lights_hi,
    device type_6 const& slots,
    thread float& total,
    thread uint& rng,
    thread type_10& chosen_position,
    thread type_10& chosen_term,
    thread type_11& chosen_weight,
    constant _mslBufferSizes& _buffer_sizes
) {
    bool local_1 = {};
    uint z = {};
    uint y = {};
    uint c_1 = {};
    if (level_3.dims[0] == 0u) {
        visit_range(level_3, 0u, level_3.light_count, x_3, n_2, params, lights, lights_hi, total, rng, chosen_position, chosen_term, chosen_weight, _buffer_sizes);
        return;
    }
    float reach = metal::sqrt(level_3.outer2_) + level_3.margin;
    metal::float3 lo = metal::floor(((x_3 - metal::float3(reach)) - level_3.origin) / metal::float3(level_3.cell));
    metal::float3 hi = metal::floor(((x_3 + metal::float3(reach)) - level_3.origin) / metal::float3(level_3.cell));
    metal::float3 top = static_cast<metal::float3>(level_3.dims - metal::uint3(1u));
    if (!(metal::any(hi < metal::float3(0.0)))) {
        local_1 = metal::any(lo > top);
    } else {
        local_1 = true;
    }
    bool _e44 = local_1;
    if (_e44) {
        return;
    }
    metal::uint3 a = naga_f2u32(metal::max(lo, metal::float3(0.0)));
    metal::uint3 b = naga_f2u32(metal::min(hi, top));
    uint s = level_3.stride;
    z = a.z;
    uint2 loop_bound_2 = uint2(4294967295u);
    bool loop_init_2 = true;
    while(true) {
        if (metal::all(loop_bound_2 == uint2(0u))) { break; }
        loop_bound_2 -= uint2(loop_bound_2.y == 0u, 1u);
        if (!loop_init_2) {
            uint _e143 = z;
            z = _e143 + 1u;
        }
        loop_init_2 = false;
        uint _e54 = z;
        if (_e54 <= b.z) {
        } else {
            break;
        }
        {
            y = a.y;
            uint2 loop_bound_3 = uint2(4294967295u);
            bool loop_init_3 = true;
            while(true) {
                if (metal::all(loop_bound_3 == uint2(0u))) { break; }
                loop_bound_3 -= uint2(loop_bound_3.y == 0u, 1u);
                if (!loop_init_3) {
                    uint _e140 = y;
                    y = _e140 + 1u;
                }
                loop_init_3 = false;
                uint _e59 = y;
                if (_e59 <= b.y) {
                } else {
                    break;
                }
                {
                    if (level_3.order == CELLS_ROWS) {
                        uint _e65 = z;
                        uint _e69 = y;
                        uint row = ((_e65 * level_3.dims[1]) + _e69) * level_3.dims[0];
                        uint _e79 = cell_start(level_3, level_3.first_cell + (s * (row + a.x)), starts, slots, _buffer_sizes);
                        uint _e87 = cell_start(level_3, level_3.first_cell + (s * ((row + b.x) + 1u)), starts, slots, _buffer_sizes);
                        visit_range(level_3, _e79, _e87, x_3, n_2, params, lights, lights_hi, total, rng, chosen_position, chosen_term, chosen_weight, _buffer_sizes);
                    } else {
                        c_1 = a.x;
                        uint2 loop_bound_4 = uint2(4294967295u);
                        bool loop_init_4 = true;
                        while(true) {
                            if (metal::all(loop_bound_4 == uint2(0u))) { break; }
                            loop_bound_4 -= uint2(loop_bound_4.y == 0u, 1u);
                            if (!loop_init_4) {
                                uint _e137 = c_1;
                                c_1 = _e137 + 1u;
                            }
                            loop_init_4 = false;
                            uint _e90 = c_1;
                            if (_e90 <= b.x) {
                            } else {
                                break;
                            }
                            {
                                uint _e94 = c_1;
                                uint _e95 = y;
                                uint _e96 = z;
                                metal::float3 low = (level_3.origin + (static_cast<metal::float3>(metal::uint3(_e94, _e95, _e96)) * level_3.cell)) - metal::float3(level_3.margin);
                                metal::float3 high = low + metal::float3(level_3.cell + (2.0 * level_3.margin));
                                metal::float3 out = metal::max(metal::max(low - x_3, x_3 - high), metal::float3(0.0));
                                if (metal::dot(out, out) > level_3.outer2_) {
                                    continue;
                                }
                                uint _e121 = c_1;
                                uint _e122 = y;
                                uint _e123 = z;
                                uint _e125 = morton3_(metal::uint3(_e121, _e122, _e123));
                                uint _e129 = cell_start(level_3, level_3.first_cell + (s * _e125), starts, slots, _buffer_sizes);
                                uint _e135 = cell_start(level_3, level_3.first_cell + (s * (_e125 + 1u)), starts, slots, _buffer_sizes);
                                visit_range(level_3, _e129, _e135, x_3, n_2, params, lights, lights_hi, total, rng, chosen_position, chosen_term, chosen_weight, _buffer_sizes);
                            }
                        }
                    }
                }
            }
        }
    }
    return;
}

void walk(
    metal::float3 x_4,
    metal::float3 n_3,
    constant Params& params,
    device type_5 const& levels,
    device type_6 const& starts,
    device type_7 const& lights,
    device type_7 const& lights_hi,
    device type_6 const& slots,
    thread float& total,
    thread uint& rng,
    thread type_10& chosen_position,
    thread type_10& chosen_term,
    thread type_11& chosen_weight,
    constant _mslBufferSizes& _buffer_sizes
) {
    uint l = 0u;
    uint2 loop_bound_5 = uint2(4294967295u);
    bool loop_init_5 = true;
    while(true) {
        if (metal::all(loop_bound_5 == uint2(0u))) { break; }
        loop_bound_5 -= uint2(loop_bound_5.y == 0u, 1u);
        if (!loop_init_5) {
            uint _e14 = l;
            l = _e14 + 1u;
        }
        loop_init_5 = false;
        uint _e4 = l;
        uint _e7 = params.levels;
        if (_e4 < _e7) {
        } else {
            break;
        }
        {
            uint _e10 = l;
            Level _e12 = levels[_e10];
            walk_level(_e12, x_4, n_3, params, starts, lights, lights_hi, slots, total, rng, chosen_position, chosen_term, chosen_weight, _buffer_sizes);
        }
    }
    return;
}

uint point_index(
    metal::uint3 id_1,
    metal::uint3 groups_1
) {
    return id_1.x + ((id_1.y * groups_1.x) * WORKGROUP);
}

uint compact3_(
    uint v_1
) {
    uint x_5 = {};
    x_5 = v_1 & 153391689u;
    uint _e4 = x_5;
    uint _e5 = x_5;
    x_5 = (_e4 | (_e5 >> 2u)) & 51130563u;
    uint _e11 = x_5;
    uint _e12 = x_5;
    x_5 = (_e11 | (_e12 >> 4u)) & 50393103u;
    uint _e18 = x_5;
    uint _e19 = x_5;
    x_5 = (_e18 | (_e19 >> 8u)) & 50331903u;
    uint _e25 = x_5;
    uint _e26 = x_5;
    x_5 = (_e25 | (_e26 >> 16u)) & 1023u;
    uint _e32 = x_5;
    return _e32;
}

metal::uint3 demorton3_(
    uint m
) {
    uint _e1 = compact3_(m);
    uint _e4 = compact3_(m >> 1u);
    uint _e7 = compact3_(m >> 2u);
    return metal::uint3(_e1, _e4, _e7);
}

uint pcg(
    uint v_2
) {
    uint state = (v_2 * 747796405u) + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

struct gatherInput {
};
[[max_total_threads_per_threadgroup(64)]] kernel void gather(
  metal::uint3 id [[thread_position_in_grid]]
, metal::uint3 groups [[threadgroups_per_grid]]
, constant Params& params [[user(fake0)]]
, device type_5 const& levels [[user(fake0)]]
, device type_6 const& starts [[user(fake0)]]
, device type_7 const& lights [[user(fake0)]]
, device type_7 const& lights_hi [[user(fake0)]]
, device type_8 const& points [[user(fake0)]]
, device type_6 const& slots [[user(fake0)]]
, device type_12& samples [[user(fake0)]]
, constant _mslBufferSizes& _buffer_sizes [[user(fake0)]]
) {
    float total = {};
    uint rng = {};
    type_10 chosen_position = {};
    type_10 chosen_term = {};
    type_11 chosen_weight = {};
    uint r = 0u;
    uint r_1 = 0u;
    metal::float3 weight = {};
    uint _e2 = point_index(id, groups);
    uint _e5 = params.points;
    if (_e2 >= _e5) {
        return;
    }
    Point p = points[_e2];
    uint _e13 = params.seed;
    uint _e14 = pcg(_e2);
    uint _e16 = pcg(_e13 ^ _e14);
    rng = _e16;
    total = 0.0;
    uint2 loop_bound_6 = uint2(4294967295u);
    bool loop_init_6 = true;
    while(true) {
        if (metal::all(loop_bound_6 == uint2(0u))) { break; }
        loop_bound_6 -= uint2(loop_bound_6.y == 0u, 1u);
        if (!loop_init_6) {
            uint _e39 = r;
            r = _e39 + 1u;
        }
        loop_init_6 = false;
        uint _e21 = r;
        if (_e21 < MAX_K) {
        } else {
            break;
        }
        {
            uint _e25 = r;
            chosen_position.inner[_e25] = metal::float3(0.0);
            uint _e30 = r;
            chosen_term.inner[_e30] = metal::float3(0.0);
            uint _e35 = r;
            chosen_weight.inner[_e35] = 0.0;
        }
    }
    walk(p.position, p.normal, params, levels, starts, lights, lights_hi, slots, total, rng, chosen_position, chosen_term, chosen_weight, _buffer_sizes);
    uint _e47 = params.k;
    metal::float3 scale = p.albedo * (INV_PI / static_cast<float>(_e47));
    uint2 loop_bound_7 = uint2(4294967295u);
    bool loop_init_7 = true;
    while(true) {
        if (metal::all(loop_bound_7 == uint2(0u))) { break; }
        loop_bound_7 -= uint2(loop_bound_7.y == 0u, 1u);
        if (!loop_init_7) {
            uint _e95 = r_1;
            r_1 = _e95 + 1u;
        }
        loop_init_7 = false;
        uint _e53 = r_1;
        uint _e56 = params.k;
        if (_e53 < _e56) {
        } else {
            break;
        }
        {
            weight = metal::float3(0.0);
            uint _e62 = r_1;
            float _e64 = chosen_weight.inner[_e62];
            if (_e64 > 0.0) {
                uint _e68 = r_1;
                metal::float3 _e70 = chosen_term.inner[_e68];
                float _e72 = total;
                uint _e74 = r_1;
                float _e76 = chosen_weight.inner[_e74];
                weight = (_e70 * (_e72 / _e76)) * scale;
            }
            uint _e83 = params.k;
            uint _e85 = r_1;
            uint _e89 = r_1;
            metal::float3 _e91 = chosen_position.inner[_e89];
            metal::float3 _e92 = weight;
            samples[(_e2 * _e83) + _e85] = Sample {_e91, _e92};
        }
    }
    return;
}
