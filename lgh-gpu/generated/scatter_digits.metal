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
};

struct Pass {
    uint count;
    uint shift;
    uint tiles;
    uint _pad;
};
typedef uint type_1[1];
struct type_3 {
    metal::atomic_uint inner[256];
};
struct type_4 {
    uint inner[256];
};
constant uint TILE = 256u;
constant uint RADIX = 256u;

uint tile_index(
    metal::uint3 wg_2,
    metal::uint3 groups_2
) {
    return wg_2.x + (wg_2.y * groups_2.x);
}

uint digit(
    uint key,
    constant Pass& pass
) {
    uint _e3 = pass.shift;
    return (key >> _e3) & 255u;
}

struct scatter_digitsInput {
};
[[max_total_threads_per_threadgroup(256)]] kernel void scatter_digits(
  uint lane_1 [[thread_index_in_threadgroup]]
, metal::uint3 wg_1 [[threadgroup_position_in_grid]]
, metal::uint3 groups_1 [[threadgroups_per_grid]]
, constant Pass& pass [[user(fake0)]]
, device type_1 const& keys_in [[user(fake0)]]
, device type_1 const& values_in [[user(fake0)]]
, device type_1& keys_out [[user(fake0)]]
, device type_1& values_out [[user(fake0)]]
, device type_1 const& histogram [[user(fake0)]]
, threadgroup type_4& tile_digits
, constant _mslBufferSizes& _buffer_sizes [[user(fake0)]]
) {
    if (lane_1 == 0u) {
        tile_digits = {};
    }
    metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
    uint d = RADIX;
    uint rank = 0u;
    uint k = 0u;
    uint _e3 = tile_index(wg_1, groups_1);
    uint _e6 = pass.tiles;
    if (_e3 >= _e6) {
        return;
    }
    uint i = (_e3 * TILE) + lane_1;
    uint _e15 = pass.count;
    if (i < _e15) {
        uint _e19 = keys_in[i];
        uint _e20 = digit(_e19, pass);
        d = _e20;
    }
    uint _e23 = d;
    tile_digits.inner[lane_1] = _e23;
    metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
    uint _e26 = pass.count;
    if (i >= _e26) {
        return;
    }
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
        uint _e32 = k;
        if (_e32 < lane_1) {
        } else {
            break;
        }
        {
            uint _e34 = rank;
            uint _e38 = k;
            uint _e40 = tile_digits.inner[_e38];
            uint _e41 = d;
            rank = _e34 + ((_e40 == _e41) ? 1u : 0u);
        }
    }
    uint _e49 = d;
    uint _e52 = pass.tiles;
    uint _e56 = histogram[(_e49 * _e52) + _e3];
    uint _e57 = rank;
    uint at = _e56 + _e57;
    uint _e63 = keys_in[i];
    keys_out[at] = _e63;
    uint _e68 = values_in[i];
    values_out[at] = _e68;
    return;
}
