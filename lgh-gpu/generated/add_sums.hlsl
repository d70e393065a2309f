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
void add_sums(uint lane_1 : SV_GroupIndex, uint3 wg_1 : SV_GroupID, uint3 groups_1 : SV_GroupID)
{
    const uint _e3 = block_index(wg_1, groups_1);
    uint i = ((_e3 * BLOCK) + lane_1);
    uint _e9 = step_.count;
    if ((i < _e9)) {
        uint _e14 = step_.offset;
        uint _e17 = asuint(data.Load((_e14 + i)*4));
        uint _e21 = step_.sums;
        uint _e24 = asuint(data.Load((_e21 + _e3)*4));
        data.Store((_e14 + i)*4, asuint((_e17 + _e24)));
        return;
    } else {
        return;
    }
}
