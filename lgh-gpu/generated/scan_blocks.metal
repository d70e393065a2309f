// language: metal2.4
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;

struct _mslBufferSizes {
    uint size1;
};

struct Step {
    uint offset;
    uint count;
    uint sums;
    uint _pad;
};
typedef uint type_1[1];
struct type_2 {
    uint inner[256];
};
constant uint BLOCK = 256u;

uint block_index(
    metal::uint3 wg_2,
    metal::uint3 groups_2
) {
    return wg_2.x + (wg_2.y * groups_2.x);
}

struct scan_blocksInput {
};
[[max_total_threads_per_threadgroup(256)]] kernel void scan_blocks(
  uint lane [[thread_index_in_threadgroup]]
, metal::uint3 wg [[threadgroup_position_in_grid]]
, metal::uint3 groups [[threadgroups_per_grid]]
, constant Step& step [[user(fake0)]]
, device type_1& data [[user(fake0)]]
, threadgroup type_2& shared_values
, constant _mslBufferSizes& _buffer_sizes [[user(fake0)]]
) {
    if (lane == 0u) {
        shared_values = {};
    }
    metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
    uint value = 0u;
    uint d = 1u;
    uint add = {};
    bool local = {};
    uint _e3 = block_index(wg, groups);
    uint i = (_e3 * BLOCK) + lane;
    uint _e11 = step.count;
    if (i < _e11) {
        uint _e16 = step.offset;
        uint _e19 = data[_e16 + i];
        value = _e19;
    }
    uint _e22 = value;
    shared_values.inner[lane] = _e22;
    metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
    uint2 loop_bound = uint2(4294967295u);
    bool loop_init = true;
    while(true) {
        if (metal::all(loop_bound == uint2(0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e42 = d;
            d = _e42 * 2u;
        }
        loop_init = false;
        uint _e25 = d;
        if (_e25 < BLOCK) {
        } else {
            break;
        }
        {
            add = 0u;
            uint _e30 = d;
            if (lane >= _e30) {
                uint _e33 = d;
                uint _e36 = shared_values.inner[lane - _e33];
                add = _e36;
            }
            metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
            uint _e39 = shared_values.inner[lane];
            uint _e40 = add;
            shared_values.inner[lane] = _e39 + _e40;
            metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
        }
    }
    uint _e47 = step.count;
    if (i < _e47) {
        uint _e52 = step.offset;
        uint _e57 = shared_values.inner[lane];
        uint _e58 = value;
        data[_e52 + i] = _e57 - _e58;
    }
    if (lane == 255u) {
        uint _e68 = step.count;
        local = (_e3 * BLOCK) < _e68;
    } else {
        local = false;
    }
    bool _e71 = local;
    if (_e71) {
        uint _e75 = step.sums;
        uint _e80 = shared_values.inner[lane];
        data[_e75 + _e3] = _e80;
        return;
    } else {
        return;
    }
}

