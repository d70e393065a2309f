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
    uint inner[1024];
};
struct type_3 {
    uint inner[256];
};
constant uint THREADS = 256u;
constant uint ITEMS = 4u;
constant uint BLOCK = 1024u;

uint block_index(
    metal::uint3 wg_2,
    metal::uint3 groups_2
) {
    return wg_2.x + (wg_2.y * groups_2.x);
}

struct add_sumsInput {
};
[[max_total_threads_per_threadgroup(256)]] kernel void add_sums(
  uint lane_1 [[thread_index_in_threadgroup]]
, metal::uint3 wg_1 [[threadgroup_position_in_grid]]
, metal::uint3 groups_1 [[threadgroups_per_grid]]
, constant Step& step [[user(fake0)]]
, device type_1& data [[user(fake0)]]
, constant _mslBufferSizes& _buffer_sizes [[user(fake0)]]
) {
    uint i_4 = 0u;
    uint _e3 = block_index(wg_1, groups_1);
    uint _e7 = step.sums;
    uint add_1 = data[_e7 + _e3];
    uint2 loop_bound = uint2(4294967295u);
    bool loop_init = true;
    while(true) {
        if (metal::all(loop_bound == uint2(0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e36 = i_4;
            i_4 = _e36 + 1u;
        }
        loop_init = false;
        uint _e13 = i_4;
        if (_e13 < ITEMS) {
        } else {
            break;
        }
        {
            uint _e18 = i_4;
            uint k = ((_e3 * BLOCK) + (_e18 * THREADS)) + lane_1;
            uint _e25 = step.count;
            if (k < _e25) {
                uint _e30 = step.offset;
                uint _e33 = data[_e30 + k];
                data[_e30 + k] = _e33 + add_1;
            }
        }
    }
    return;
}
