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

struct scan_blocksInput {
};
[[max_total_threads_per_threadgroup(256)]] kernel void scan_blocks(
  uint lane [[thread_index_in_threadgroup]]
, metal::uint3 wg [[threadgroup_position_in_grid]]
, metal::uint3 groups [[threadgroups_per_grid]]
, constant Step& step [[user(fake0)]]
, device type_1& data [[user(fake0)]]
, threadgroup type_2& values
, threadgroup type_3& totals
, constant _mslBufferSizes& _buffer_sizes [[user(fake0)]]
) {
    if (lane == 0u) {
        values = {};
        totals = {};
    }
    metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
    uint i = 0u;
    uint value = {};
    uint run = 0u;
    uint i_1 = 0u;
    uint d = 1u;
    uint add = {};
    uint i_2 = 0u;
    uint i_3 = 0u;
    bool local = {};
    uint _e3 = block_index(wg, groups);
    uint first = _e3 * BLOCK;
    uint2 loop_bound = uint2(4294967295u);
    bool loop_init = true;
    while(true) {
        if (metal::all(loop_bound == uint2(0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e34 = i;
            i = _e34 + 1u;
        }
        loop_init = false;
        uint _e8 = i;
        if (_e8 < ITEMS) {
        } else {
            break;
        }
        {
            uint _e11 = i;
            uint k = (_e11 * THREADS) + lane;
            value = 0u;
            uint _e20 = step.count;
            if ((first + k) < _e20) {
                uint _e25 = step.offset;
                uint _e29 = data[(_e25 + first) + k];
                value = _e29;
            }
            uint _e32 = value;
            values.inner[k] = _e32;
        }
    }
    metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
    uint2 loop_bound_1 = uint2(4294967295u);
    bool loop_init_1 = true;
    while(true) {
        if (metal::all(loop_bound_1 == uint2(0u))) { break; }
        loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
        if (!loop_init_1) {
            uint _e60 = i_1;
            i_1 = _e60 + 1u;
        }
        loop_init_1 = false;
        uint _e40 = i_1;
        if (_e40 < ITEMS) {
        } else {
            break;
        }
        {
            uint _e46 = i_1;
            uint value_1 = values.inner[(lane * ITEMS) + _e46];
            uint _e53 = i_1;
            uint _e56 = run;
            values.inner[(lane * ITEMS) + _e53] = _e56;
            uint _e57 = run;
            run = _e57 + value_1;
        }
    }
    uint _e64 = run;
    totals.inner[lane] = _e64;
    metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
    uint2 loop_bound_2 = uint2(4294967295u);
    bool loop_init_2 = true;
    while(true) {
        if (metal::all(loop_bound_2 == uint2(0u))) { break; }
        loop_bound_2 -= uint2(loop_bound_2.y == 0u, 1u);
        if (!loop_init_2) {
            uint _e84 = d;
            d = _e84 * 2u;
        }
        loop_init_2 = false;
        uint _e67 = d;
        if (_e67 < THREADS) {
        } else {
            break;
        }
        {
            add = 0u;
            uint _e72 = d;
            if (lane >= _e72) {
                uint _e75 = d;
                uint _e78 = totals.inner[lane - _e75];
                add = _e78;
            }
            metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
            uint _e81 = totals.inner[lane];
            uint _e82 = add;
            totals.inner[lane] = _e81 + _e82;
            metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
        }
    }
    uint _e89 = totals.inner[lane];
    uint _e90 = run;
    uint before = _e89 - _e90;
    uint2 loop_bound_3 = uint2(4294967295u);
    bool loop_init_3 = true;
    while(true) {
        if (metal::all(loop_bound_3 == uint2(0u))) { break; }
        loop_bound_3 -= uint2(loop_bound_3.y == 0u, 1u);
        if (!loop_init_3) {
            uint _e106 = i_2;
            i_2 = _e106 + 1u;
        }
        loop_init_3 = false;
        uint _e94 = i_2;
        if (_e94 < ITEMS) {
        } else {
            break;
        }
        {
            uint _e100 = i_2;
            uint _e103 = values.inner[(lane * ITEMS) + _e100];
            values.inner[(lane * ITEMS) + _e100] = _e103 + before;
        }
    }
    metal::threadgroup_barrier(metal::mem_flags::mem_threadgroup);
    uint2 loop_bound_4 = uint2(4294967295u);
    bool loop_init_4 = true;
    while(true) {
        if (metal::all(loop_bound_4 == uint2(0u))) { break; }
        loop_bound_4 -= uint2(loop_bound_4.y == 0u, 1u);
        if (!loop_init_4) {
            uint _e133 = i_3;
            i_3 = _e133 + 1u;
        }
        loop_init_4 = false;
        uint _e110 = i_3;
        if (_e110 < ITEMS) {
        } else {
            break;
        }
        {
            uint _e113 = i_3;
            uint k_1 = (_e113 * THREADS) + lane;
            uint _e120 = step.count;
            if ((first + k_1) < _e120) {
                uint _e125 = step.offset;
                uint _e131 = values.inner[k_1];
                data[(_e125 + first) + k_1] = _e131;
            }
        }
    }
    if (lane == 255u) {
        uint _e141 = step.count;
        local = first < _e141;
    } else {
        local = false;
    }
    bool _e144 = local;
    if (_e144) {
        uint _e148 = step.sums;
        uint _e153 = totals.inner[lane];
        data[_e148 + _e3] = _e153;
        return;
    } else {
        return;
    }
}

