struct Step {
    uint offset;
    uint count;
    uint sums;
    uint _pad;
};

static const uint BLOCK = 256u;

cbuffer step_ : register(b0) { Step step_; }
RWByteAddressBuffer data : register(u1);
groupshared uint shared_values[256];

uint block_index(uint3 wg_2, uint3 groups_2)
{
    return (wg_2.x + (wg_2.y * groups_2.x));
}

[numthreads(256, 1, 1)]
void scan_blocks(uint lane : SV_GroupIndex, uint3 wg : SV_GroupID, uint3 groups : SV_GroupID)
{
    if (lane == 0) {
        shared_values = (uint[256])0;
    }
    GroupMemoryBarrierWithGroupSync();
    uint value = 0u;
    uint d = 1u;
    uint add = (uint)0;
    bool local = (bool)0;

    const uint _e3 = block_index(wg, groups);
    uint i = ((_e3 * BLOCK) + lane);
    uint _e11 = step_.count;
    if ((i < _e11)) {
        uint _e16 = step_.offset;
        uint _e19 = asuint(data.Load((_e16 + i)*4));
        value = _e19;
    }
    uint _e22 = value;
    shared_values[min(uint(lane), 255u)] = _e22;
    GroupMemoryBarrierWithGroupSync();
    uint2 loop_bound = uint2(4294967295u, 4294967295u);
    bool loop_init = true;
    while(true) {
        if (all(loop_bound == uint2(0u, 0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e42 = d;
            d = (_e42 * 2u);
        }
        loop_init = false;
        uint _e25 = d;
        if ((_e25 < BLOCK)) {
        } else {
            break;
        }
        {
            add = 0u;
            uint _e30 = d;
            if ((lane >= _e30)) {
                uint _e33 = d;
                uint _e36 = shared_values[min(uint((lane - _e33)), 255u)];
                add = _e36;
            }
            GroupMemoryBarrierWithGroupSync();
            uint _e39 = shared_values[min(uint(lane), 255u)];
            uint _e40 = add;
            shared_values[min(uint(lane), 255u)] = (_e39 + _e40);
            GroupMemoryBarrierWithGroupSync();
        }
    }
    uint _e47 = step_.count;
    if ((i < _e47)) {
        uint _e52 = step_.offset;
        uint _e57 = shared_values[min(uint(lane), 255u)];
        uint _e58 = value;
        data.Store((_e52 + i)*4, asuint((_e57 - _e58)));
    }
    if ((lane == 255u)) {
        uint _e68 = step_.count;
        local = ((_e3 * BLOCK) < _e68);
    } else {
        local = false;
    }
    bool _e71 = local;
    if (_e71) {
        uint _e75 = step_.sums;
        uint _e80 = shared_values[min(uint(lane), 255u)];
        data.Store((_e75 + _e3)*4, asuint(_e80));
        return;
    } else {
        return;
    }
}

