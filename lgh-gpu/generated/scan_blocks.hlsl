struct Step {
    uint offset;
    uint count;
    uint sums;
    uint _pad;
};

static const uint THREADS = 256u;
static const uint ITEMS = 4u;
static const uint BLOCK = 1024u;

cbuffer step_ : register(b0) { Step step_; }
RWByteAddressBuffer data : register(u1);
groupshared uint values[1024];
groupshared uint totals[256];

uint block_index(uint3 wg_2, uint3 groups_2)
{
    return (wg_2.x + (wg_2.y * groups_2.x));
}

[numthreads(256, 1, 1)]
void scan_blocks(uint lane : SV_GroupIndex, uint3 wg : SV_GroupID, uint3 groups : SV_GroupID)
{
    if (lane == 0) {
        values = (uint[1024])0;
        totals = (uint[256])0;
    }
    GroupMemoryBarrierWithGroupSync();
    uint i = 0u;
    uint value = (uint)0;
    uint run = 0u;
    uint i_1 = 0u;
    uint d = 1u;
    uint add = (uint)0;
    uint i_2 = 0u;
    uint i_3 = 0u;
    bool local = (bool)0;

    const uint _e3 = block_index(wg, groups);
    uint first = (_e3 * BLOCK);
    uint2 loop_bound = uint2(4294967295u, 4294967295u);
    bool loop_init = true;
    while(true) {
        if (all(loop_bound == uint2(0u, 0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e34 = i;
            i = (_e34 + 1u);
        }
        loop_init = false;
        uint _e8 = i;
        if ((_e8 < ITEMS)) {
        } else {
            break;
        }
        {
            uint _e11 = i;
            uint k = ((_e11 * THREADS) + lane);
            value = 0u;
            uint _e20 = step_.count;
            if (((first + k) < _e20)) {
                uint _e25 = step_.offset;
                uint _e29 = asuint(data.Load(((_e25 + first) + k)*4));
                value = _e29;
            }
            uint _e32 = value;
            values[min(uint(k), 1023u)] = _e32;
        }
    }
    GroupMemoryBarrierWithGroupSync();
    uint2 loop_bound_1 = uint2(4294967295u, 4294967295u);
    bool loop_init_1 = true;
    while(true) {
        if (all(loop_bound_1 == uint2(0u, 0u))) { break; }
        loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
        if (!loop_init_1) {
            uint _e60 = i_1;
            i_1 = (_e60 + 1u);
        }
        loop_init_1 = false;
        uint _e40 = i_1;
        if ((_e40 < ITEMS)) {
        } else {
            break;
        }
        {
            uint _e46 = i_1;
            uint value_1 = values[min(uint(((lane * ITEMS) + _e46)), 1023u)];
            uint _e53 = i_1;
            uint _e56 = run;
            values[min(uint(((lane * ITEMS) + _e53)), 1023u)] = _e56;
            uint _e57 = run;
            run = (_e57 + value_1);
        }
    }
    uint _e64 = run;
    totals[min(uint(lane), 255u)] = _e64;
    GroupMemoryBarrierWithGroupSync();
    uint2 loop_bound_2 = uint2(4294967295u, 4294967295u);
    bool loop_init_2 = true;
    while(true) {
        if (all(loop_bound_2 == uint2(0u, 0u))) { break; }
        loop_bound_2 -= uint2(loop_bound_2.y == 0u, 1u);
        if (!loop_init_2) {
            uint _e84 = d;
            d = (_e84 * 2u);
        }
        loop_init_2 = false;
        uint _e67 = d;
        if ((_e67 < THREADS)) {
        } else {
            break;
        }
        {
            add = 0u;
            uint _e72 = d;
            if ((lane >= _e72)) {
                uint _e75 = d;
                uint _e78 = totals[min(uint((lane - _e75)), 255u)];
                add = _e78;
            }
            GroupMemoryBarrierWithGroupSync();
            uint _e81 = totals[min(uint(lane), 255u)];
            uint _e82 = add;
            totals[min(uint(lane), 255u)] = (_e81 + _e82);
            GroupMemoryBarrierWithGroupSync();
        }
    }
    uint _e89 = totals[min(uint(lane), 255u)];
    uint _e90 = run;
    uint before = (_e89 - _e90);
    uint2 loop_bound_3 = uint2(4294967295u, 4294967295u);
    bool loop_init_3 = true;
    while(true) {
        if (all(loop_bound_3 == uint2(0u, 0u))) { break; }
        loop_bound_3 -= uint2(loop_bound_3.y == 0u, 1u);
        if (!loop_init_3) {
            uint _e106 = i_2;
            i_2 = (_e106 + 1u);
        }
        loop_init_3 = false;
        uint _e94 = i_2;
        if ((_e94 < ITEMS)) {
        } else {
            break;
        }
        {
            uint _e100 = i_2;
            uint _e103 = values[min(uint(((lane * ITEMS) + _e100)), 1023u)];
            values[min(uint(((lane * ITEMS) + _e100)), 1023u)] = (_e103 + before);
        }
    }
    GroupMemoryBarrierWithGroupSync();
    uint2 loop_bound_4 = uint2(4294967295u, 4294967295u);
    bool loop_init_4 = true;
    while(true) {
        if (all(loop_bound_4 == uint2(0u, 0u))) { break; }
        loop_bound_4 -= uint2(loop_bound_4.y == 0u, 1u);
        if (!loop_init_4) {
            uint _e133 = i_3;
            i_3 = (_e133 + 1u);
        }
        loop_init_4 = false;
        uint _e110 = i_3;
        if ((_e110 < ITEMS)) {
        } else {
            break;
        }
        {
            uint _e113 = i_3;
            uint k_1 = ((_e113 * THREADS) + lane);
            uint _e120 = step_.count;
            if (((first + k_1) < _e120)) {
                uint _e125 = step_.offset;
                uint _e131 = values[min(uint(k_1), 1023u)];
                data.Store(((_e125 + first) + k_1)*4, asuint(_e131));
            }
        }
    }
    if ((lane == 255u)) {
        uint _e141 = step_.count;
        local = (first < _e141);
    } else {
        local = false;
    }
    bool _e144 = local;
    if (_e144) {
        uint _e148 = step_.sums;
        uint _e153 = totals[min(uint(lane), 255u)];
        data.Store((_e148 + _e3)*4, asuint(_e153));
        return;
    } else {
        return;
    }
}

