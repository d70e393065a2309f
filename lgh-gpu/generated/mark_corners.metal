// language: metal2.4
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;

struct _mslBufferSizes {
    uint size1;
    uint size2;
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
typedef metal::atomic_uint type_5[1];
typedef uint type_6[1];
constant uint WORKGROUP = 64u;

uint flat(
    metal::uint3 id_2,
    metal::uint3 groups_2
) {
    return id_2.x + ((id_2.y * groups_2.x) * WORKGROUP);
}

uint compact3_(
    uint v
) {
    uint x = {};
    x = v & 153391689u;
    uint _e4 = x;
    uint _e5 = x;
    x = (_e4 | (_e5 >> 2u)) & 51130563u;
    uint _e11 = x;
    uint _e12 = x;
    x = (_e11 | (_e12 >> 4u)) & 50393103u;
    uint _e18 = x;
    uint _e19 = x;
    x = (_e18 | (_e19 >> 8u)) & 50331903u;
    uint _e25 = x;
    uint _e26 = x;
    x = (_e25 | (_e26 >> 16u)) & 1023u;
    uint _e32 = x;
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

uint spread3_(
    uint v_1
) {
    uint x_1 = {};
    x_1 = v_1 & 1023u;
    uint _e4 = x_1;
    uint _e5 = x_1;
    x_1 = (_e4 | (_e5 << 16u)) & 50331903u;
    uint _e11 = x_1;
    uint _e12 = x_1;
    x_1 = (_e11 | (_e12 << 8u)) & 50393103u;
    uint _e18 = x_1;
    uint _e19 = x_1;
    x_1 = (_e18 | (_e19 << 4u)) & 51130563u;
    uint _e25 = x_1;
    uint _e26 = x_1;
    x_1 = (_e25 | (_e26 << 2u)) & 153391689u;
    uint _e32 = x_1;
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

struct mark_cornersInput {
};
[[max_total_threads_per_threadgroup(64)]] kernel void mark_corners(
  metal::uint3 id_1 [[thread_position_in_grid]]
, metal::uint3 groups_1 [[threadgroups_per_grid]]
, constant Step& step [[user(fake0)]]
, device type_5& marks [[user(fake0)]]
, device type_6 const& sorted_keys [[user(fake0)]]
, constant _mslBufferSizes& _buffer_sizes [[user(fake0)]]
) {
    uint k = 0u;
    uint _e2 = flat(id_1, groups_1);
    uint _e5 = step.n;
    if (_e2 >= _e5) {
        return;
    }
    uint _e9 = sorted_keys[_e2];
    metal::uint3 _e10 = demorton3_(_e9);
    uint _e13 = step.level;
    metal::uint3 c_1 = _e10 >> metal::uint3(_e13 - 1u);
    uint2 loop_bound = uint2(4294967295u);
    bool loop_init = true;
    while(true) {
        if (metal::all(loop_bound == uint2(0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e46 = k;
            k = _e46 + 1u;
        }
        loop_init = false;
        uint _e20 = k;
        if (_e20 < 8u) {
        } else {
            break;
        }
        {
            uint _e23 = k;
            uint _e26 = k;
            uint _e31 = k;
            metal::uint3 q = c_1 + metal::uint3(_e23 & 1u, (_e26 >> 1u) & 1u, _e31 >> 2u);
            uint _e39 = step.slot_offset;
            uint _e40 = morton3_(q);
            uint _e44 = metal::atomic_fetch_or_explicit(&marks[_e39 + _e40], 1u, metal::memory_order_relaxed);
        }
    }
    return;
}
