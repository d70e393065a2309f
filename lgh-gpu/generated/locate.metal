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
    uint size7;
    uint size8;
    uint size9;
    uint size10;
    uint size11;
    uint size12;
};

struct Step {
    metal::packed_float3 origin;
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
    metal::float3 position;
    metal::float3 intensity;
};
struct Sorted {
    metal::packed_float3 frac;
    float luminance;
    metal::packed_float3 intensity;
    uint cell;
};
typedef metal::float4 type_5[1];
typedef metal::atomic_uint type_7[1];
typedef uint type_8[1];
typedef Sorted type_9[1];
typedef Light type_10[1];
struct Located {
    metal::uint3 cell;
    metal::float3 frac;
};
struct Sums {
    metal::packed_float3 intensity;
    float weight;
    metal::float3 first;
    metal::float3 second;
};
struct type_13 {
    metal::float4 inner[5];
};
typedef type_13 type_14[1];
struct type_15 {
    metal::float4 inner[3];
};
struct type_16 {
    type_15 inner[64];
};
struct Part {
    uint w;
    uint v;
    char _pad2[8];
    metal::packed_uint3 q;
    uint g;
    bool busy;
    char _pad5[15];
};
constant uint WORKGROUP = 64u;
constant metal::float3 LUMINANCE = metal::float3(0.2126, 0.7152, 0.0722);

uint flat(
    metal::uint3 id_5,
    metal::uint3 groups_9
) {
    return id_5.x + ((id_5.y * groups_9.x) * WORKGROUP);
}

uint pack(
    metal::uint3 c
) {
    return (c.x | (c.y << 10u)) | (c.z << 20u);
}

metal::uint3 unpack(
    uint c_1
) {
    return metal::uint3(c_1 & 1023u, (c_1 >> 10u) & 1023u, c_1 >> 20u);
}

metal::uint3 naga_f2u32(metal::float3 value) {
    return static_cast<metal::uint3>(metal::clamp(value, 0.0, 4294967000.0));
}

Located locate_light(
    metal::float3 p,
    constant Step& step
) {
    metal::float3 _e3 = step.origin;
    float _e7 = step.h1_;
    metal::float3 t = (p - _e3) / metal::float3(_e7);
    uint _e15 = step.max_cell;
    metal::float3 c_4 = metal::clamp(metal::floor(t), metal::float3(0.0), metal::float3(static_cast<float>(_e15)));
    return Located {naga_f2u32(c_4), metal::clamp(t - c_4, metal::float3(0.0), metal::float3(1.0))};
}

uint spread3_(
    uint v
) {
    uint x = {};
    x = v & 1023u;
    uint _e4 = x;
    uint _e5 = x;
    x = (_e4 | (_e5 << 16u)) & 50331903u;
    uint _e11 = x;
    uint _e12 = x;
    x = (_e11 | (_e12 << 8u)) & 50393103u;
    uint _e18 = x;
    uint _e19 = x;
    x = (_e18 | (_e19 << 4u)) & 51130563u;
    uint _e25 = x;
    uint _e26 = x;
    x = (_e25 | (_e26 << 2u)) & 153391689u;
    uint _e32 = x;
    return _e32;
}

uint morton3_(
    metal::uint3 c_2
) {
    uint _e2 = spread3_(c_2.x);
    uint _e4 = spread3_(c_2.y);
    uint _e9 = spread3_(c_2.z);
    return (_e2 | (_e4 << 1u)) | (_e9 << 2u);
}

metal::uint3 corner(
    uint k
) {
    return metal::uint3(k & 1u, (k >> 1u) & 1u, k >> 2u);
}

uint cells_a_side(
    constant Step& step
) {
    uint _e3 = step.bits;
    uint _e6 = step.level;
    return 1u << (_e3 - (_e6 - 1u));
}

metal::uint2 cell_range(
    metal::uint3 c_3,
    constant Step& step,
    device type_8 const& starts,
    constant _mslBufferSizes& _buffer_sizes
) {
    uint _e4 = step.level;
    uint shift = 3u * (_e4 - 1u);
    uint _e8 = morton3_(c_3);
    uint _e12 = starts[_e8 << shift];
    uint _e18 = starts[(_e8 + 1u) << shift];
    return metal::uint2(_e12, _e18);
}

metal::uint2 corner_cell(
    metal::uint3 q,
    uint k_1,
    constant Step& step,
    device type_8 const& starts,
    constant _mslBufferSizes& _buffer_sizes
) {
    bool local_1 = {};
    metal::uint3 _e2 = corner(k_1);
    if (!(metal::any(q < _e2))) {
        uint _e9 = cells_a_side(step);
        local_1 = metal::any((q - _e2) >= metal::uint3(_e9));
    } else {
        local_1 = true;
    }
    bool _e14 = local_1;
    if (_e14) {
        return metal::uint2(0u);
    }
    metal::uint2 _e18 = cell_range(q - _e2, step, starts, _buffer_sizes);
    return _e18;
}

metal::float3 place(
    Sorted light,
    constant Step& step
) {
    uint _e3 = step.level;
    uint sub = _e3 - 1u;
    metal::uint3 mask = metal::uint3((1u << sub) - 1u);
    float scale = 1.0 / static_cast<float>(1u << sub);
    metal::uint3 _e17 = unpack(light.cell);
    return metal::min((static_cast<metal::float3>(_e17 & mask) + light.frac) * scale, metal::float3(1.0));
}

float weight(
    metal::float3 g_2,
    metal::uint3 o
) {
    metal::float3 wa = metal::select(metal::float3(1.0) - g_2, g_2, o == metal::uint3(1u));
    return (wa.x * wa.y) * wa.z;
}

Sums moment_sums(
    metal::uint3 q_1,
    uint lane_4,
    uint lanes,
    constant Step& step,
    device type_8 const& starts,
    device type_9 const& sorted,
    constant _mslBufferSizes& _buffer_sizes
) {
    Sums s = Sums {metal::float3(0.0), 0.0, metal::float3(0.0), metal::float3(0.0)};
    uint k_2 = 0u;
    uint j = {};
    uint2 loop_bound = uint2(4294967295u);
    bool loop_init = true;
    while(true) {
        if (metal::all(loop_bound == uint2(0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e57 = k_2;
            k_2 = _e57 + 1u;
        }
        loop_init = false;
        uint _e14 = k_2;
        if (_e14 < 8u) {
        } else {
            break;
        }
        {
            uint _e17 = k_2;
            metal::uint2 _e18 = corner_cell(q_1, _e17, step, starts, _buffer_sizes);
            uint _e19 = k_2;
            metal::uint3 _e20 = corner(_e19);
            j = _e18.x + lane_4;
            uint2 loop_bound_1 = uint2(4294967295u);
            bool loop_init_1 = true;
            while(true) {
                if (metal::all(loop_bound_1 == uint2(0u))) { break; }
                loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
                if (!loop_init_1) {
                    uint _e54 = j;
                    j = _e54 + lanes;
                }
                loop_init_1 = false;
                uint _e24 = j;
                if (_e24 < _e18.y) {
                } else {
                    break;
                }
                {
                    uint _e28 = j;
                    Sorted light_1 = sorted[_e28];
                    metal::float3 _e31 = place(light_1, step);
                    float _e32 = weight(_e31, _e20);
                    float v_3 = _e32 * light_1.luminance;
                    metal::float3 off = _e31 - static_cast<metal::float3>(_e20);
                    metal::float3 _e38 = s.intensity;
                    s.intensity = _e38 + (_e32 * light_1.intensity);
                    float _e43 = s.weight;
                    s.weight = _e43 + v_3;
                    metal::float3 _e46 = s.first;
                    s.first = _e46 + (v_3 * off);
                    metal::float3 _e50 = s.second;
                    s.second = _e50 + (v_3 * (off * off));
                }
            }
        }
    }
    Sums _e59 = s;
    return _e59;
}

float size_sum(
    metal::uint3 q_2,
    metal::float3 mean,
    uint lane_5,
    uint lanes_1,
    constant Step& step,
    device type_8 const& starts,
    device type_9 const& sorted,
    constant _mslBufferSizes& _buffer_sizes
) {
    float sum_2 = 0.0;
    uint k_3 = 0u;
    uint j_1 = {};
    uint2 loop_bound_2 = uint2(4294967295u);
    bool loop_init_2 = true;
    while(true) {
        if (metal::all(loop_bound_2 == uint2(0u))) { break; }
        loop_bound_2 -= uint2(loop_bound_2.y == 0u, 1u);
        if (!loop_init_2) {
            uint _e39 = k_3;
            k_3 = _e39 + 1u;
        }
        loop_init_2 = false;
        uint _e8 = k_3;
        if (_e8 < 8u) {
        } else {
            break;
        }
        {
            uint _e11 = k_3;
            metal::uint2 _e12 = corner_cell(q_2, _e11, step, starts, _buffer_sizes);
            uint _e13 = k_3;
            metal::uint3 _e14 = corner(_e13);
            j_1 = _e12.x + lane_5;
            uint2 loop_bound_3 = uint2(4294967295u);
            bool loop_init_3 = true;
            while(true) {
                if (metal::all(loop_bound_3 == uint2(0u))) { break; }
                loop_bound_3 -= uint2(loop_bound_3.y == 0u, 1u);
                if (!loop_init_3) {
                    uint _e36 = j_1;
                    j_1 = _e36 + lanes_1;
                }
                loop_init_3 = false;
                uint _e18 = j_1;
                if (_e18 < _e12.y) {
                } else {
                    break;
                }
                {
                    uint _e22 = j_1;
                    Sorted light_2 = sorted[_e22];
                    metal::float3 _e25 = place(light_2, step);
                    float _e26 = sum_2;
                    float _e27 = weight(_e25, _e14);
                    sum_2 = _e26 + ((_e27 * light_2.luminance) * metal::length(_e25 - (static_cast<metal::float3>(_e14) + mean)));
                }
            }
        }
    }
    float _e41 = sum_2;
    return _e41;
}

metal::float3 centre(
    Sums s_1
) {
    if (s_1.weight > 0.0) {
        return s_1.first / metal::float3(s_1.weight);
    }
    return metal::float3(0.0);
}

void write_vertex(
    metal::uint3 q_3,
    uint v_1,
    Sums s_2,
    metal::float3 mean_1,
    float size_sum_1,
    constant Step& step,
    device type_10& out,
    device type_5& extras,
    constant _mslBufferSizes& _buffer_sizes
) {
    metal::float3 variance = metal::float3(0.0);
    float size = 0.0;
    bool local_2 = {};
    float _e7 = step.h1_;
    uint _e11 = step.level;
    float h = _e7 * static_cast<float>(1u << (_e11 - 1u));
    if (s_2.weight > 0.0) {
        variance = (metal::max((s_2.second / metal::float3(s_2.weight)) - (mean_1 * mean_1), metal::float3(0.0)) * h) * h;
        size = (size_sum_1 / s_2.weight) * h;
    }
    metal::float3 _e41 = step.origin;
    metal::float3 position = _e41 + ((static_cast<metal::float3>(q_3) + mean_1) * h);
    float luminance = metal::dot(s_2.intensity, LUMINANCE);
    if (luminance > 0.0) {
        float _e55 = step.threshold;
        local_2 = luminance >= _e55;
    } else {
        local_2 = false;
    }
    bool reported = local_2;
    uint _e62 = step.light_base;
    out[_e62 + v_1] = Light {position, reported ? s_2.intensity : metal::float3(0.0)};
    uint _e73 = step.light_base;
    metal::float3 _e76 = variance;
    float _e77 = size;
    extras[_e73 + v_1] = metal::float4(_e76, _e77);
    return;
}

uint compact3_(
    uint v_2
) {
    uint x_1 = {};
    x_1 = v_2 & 153391689u;
    uint _e4 = x_1;
    uint _e5 = x_1;
    x_1 = (_e4 | (_e5 >> 2u)) & 51130563u;
    uint _e11 = x_1;
    uint _e12 = x_1;
    x_1 = (_e11 | (_e12 >> 4u)) & 50393103u;
    uint _e18 = x_1;
    uint _e19 = x_1;
    x_1 = (_e18 | (_e19 >> 8u)) & 50331903u;
    uint _e25 = x_1;
    uint _e26 = x_1;
    x_1 = (_e25 | (_e26 >> 16u)) & 1023u;
    uint _e32 = x_1;
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

uint naga_div(uint lhs, uint rhs) {
    return lhs / metal::select(rhs, 1u, rhs == 0u);
}

uint naga_mod(uint lhs, uint rhs) {
    return lhs % metal::select(rhs, 1u, rhs == 0u);
}

Part part(
    metal::uint3 wg_4,
    metal::uint3 groups_10,
    uint parts,
    constant Step& step,
    device type_8 const& vertex_slots,
    constant _mslBufferSizes& _buffer_sizes
) {
    uint w = wg_4.x + (wg_4.y * groups_10.x);
    uint _e10 = step.count;
    if (w >= (_e10 * parts)) {
        return Part {w, 0u, {}, metal::uint3(0u), 0u, false};
    }
    uint v_4 = naga_div(w, parts);
    uint _e23 = step.list_offset;
    uint _e26 = vertex_slots[_e23 + v_4];
    metal::uint3 _e27 = demorton3_(_e26);
    return Part {w, v_4, {}, _e27, naga_mod(w, parts), true};
}

void reduce(
    uint lane_6,
    threadgroup type_16& lane_sums
) {
    uint stride = 32u;
    uint a_3 = {};
    uint2 loop_bound_4 = uint2(4294967295u);
    bool loop_init_4 = true;
    while(true) {
        if (metal::all(loop_bound_4 == uint2(0u))) { break; }
        loop_bound_4 -= uint2(loop_bound_4.y == 0u, 1u);
        if (!loop_init_4) {
            uint _e29 = stride;
            stride = naga_div(_e29, 2u);
        }
        loop_init_4 = false;
        uint _e3 = stride;
        if (_e3 > 0u) {
        } else {
            break;
        }
        {
            uint _e6 = stride;
            if (lane_6 < _e6) {
                a_3 = 0u;
                uint2 loop_bound_5 = uint2(4294967295u);
                bool loop_init_5 = true;
                while(true) {
                    if (metal::all(loop_bound_5 == uint2(0u))) { break; }
                    loop_bound_5 -= uint2(loop_bound_5.y == 0u, 1u);
                    if (!loop_init_5) {
                        uint _e27 = a_3;
                        a_3 = _e27 + 1u;
                    }
                    loop_init_5 = false;
                    uint _e10 = a_3;
                    if (_e10 < 3u) {
                    } else {
                        break;
                    }
                    {
                        uint _e15 = a_3;
                        metal::float4 _e17 = lane_sums.inner[lane_6].inner[_e15];
                        uint _e19 = stride;
                        uint _e22 = a_3;
                        metal::float4 _e24 = lane_sums.inner[lane_6 + _e19].inner[_e22];
                        lane_sums.inner[lane_6].inner[_e15] = _e17 + _e24;
                    }
                }
            }
            metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
        }
    }
    return;
}

struct locateInput {
};
[[max_total_threads_per_threadgroup(64)]] kernel void locate(
  metal::uint3 id [[thread_position_in_grid]]
, metal::uint3 groups [[threadgroups_per_grid]]
, constant Step& step [[user(fake0)]]
, device type_5 const& positions [[user(fake0)]]
, device type_7& counts [[user(fake0)]]
, device type_8& order [[user(fake0)]]
, device type_8& keys [[user(fake0)]]
, constant _mslBufferSizes& _buffer_sizes [[user(fake0)]]
) {
    uint _e2 = flat(id, groups);
    uint _e5 = step.n;
    if (_e2 >= _e5) {
        return;
    }
    metal::float4 _e9 = positions[_e2];
    Located _e11 = locate_light(_e9.xyz, step);
    uint _e13 = morton3_(_e11.cell);
    uint _e17 = metal::atomic_fetch_add_explicit(&counts[_e13], 1u, metal::memory_order_relaxed);
    keys[_e2] = _e13;
    order[_e2] = _e2;
    return;
}

