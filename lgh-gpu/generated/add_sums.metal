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
    uint _e3 = block_index(wg_1, groups_1);
    uint i = (_e3 * BLOCK) + lane_1;
    uint _e9 = step.count;
    if (i < _e9) {
        uint _e14 = step.offset;
        uint _e17 = data[_e14 + i];
        uint _e21 = step.sums;
        uint _e24 = data[_e21 + _e3];
        data[_e14 + i] = _e17 + _e24;
        return;
    } else {
        return;
    }
}
