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
void add_sums(uint lane_1 : SV_GroupIndex, uint3 wg_1 : SV_GroupID, uint3 groups_1 : SV_GroupID)
{
    uint i_4 = 0u;

    const uint _e3 = block_index(wg_1, groups_1);
    uint _e7 = step_.sums;
    uint add_1 = asuint(data.Load((_e7 + _e3)*4));
    uint2 loop_bound = uint2(4294967295u, 4294967295u);
    bool loop_init = true;
    while(true) {
        if (all(loop_bound == uint2(0u, 0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e36 = i_4;
            i_4 = (_e36 + 1u);
        }
        loop_init = false;
        uint _e13 = i_4;
        if ((_e13 < ITEMS)) {
        } else {
            break;
        }
        {
            uint _e18 = i_4;
            uint k = (((_e3 * BLOCK) + (_e18 * THREADS)) + lane_1);
            uint _e25 = step_.count;
            if ((k < _e25)) {
                uint _e30 = step_.offset;
                uint _e33 = asuint(data.Load((_e30 + k)*4));
                data.Store((_e30 + k)*4, asuint((_e33 + add_1)));
            }
        }
    }
    return;
}
