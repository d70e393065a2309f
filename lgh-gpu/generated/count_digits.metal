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

struct count_digitsInput {
};
[[max_total_threads_per_threadgroup(256)]] kernel void count_digits(
  uint lane [[thread_index_in_threadgroup]]
, metal::uint3 wg [[threadgroup_position_in_grid]]
, metal::uint3 groups [[threadgroups_per_grid]]
, constant Pass& pass [[user(fake0)]]
, device type_1 const& keys_in [[user(fake0)]]
, device type_1& histogram [[user(fake0)]]
, threadgroup type_3& tile_counts
, constant _mslBufferSizes& _buffer_sizes [[user(fake0)]]
) {
    if (lane == 0u) {
        for (int __i0 = 0; __i0 < 256; __i0++) {
            metal::atomic_store_explicit(&tile_counts.inner[__i0], 0, metal::memory_order_relaxed);
        }
    }
    metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
    bool local = {};
    uint _e3 = tile_index(wg, groups);
    uint _e6 = pass.tiles;
    if (_e3 >= _e6) {
        return;
    }
    metal::atomic_store_explicit(&tile_counts.inner[lane], 0u, metal::memory_order_relaxed);
    metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
    uint i = (_e3 * TILE) + lane;
    uint _e16 = pass.count;
    if (i < _e16) {
        uint _e21 = keys_in[i];
        uint _e22 = digit(_e21, pass);
        uint _e25 = metal::atomic_fetch_add_explicit(&tile_counts.inner[_e22], 1u, metal::memory_order_relaxed);
    }
    metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
    uint _e29 = pass.tiles;
    uint _e35 = metal::atomic_load_explicit(&tile_counts.inner[lane], metal::memory_order_relaxed);
    histogram[(lane * _e29) + _e3] = _e35;
    if (_e3 == 0u) {
        local = lane == 0u;
    } else {
        local = false;
    }
    bool _e43 = local;
    if (_e43) {
        uint _e48 = pass.tiles;
        histogram[RADIX * _e48] = 0u;
        return;
    } else {
        return;
    }
}

