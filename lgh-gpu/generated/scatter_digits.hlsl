struct Pass_ {
    uint count;
    uint shift;
    uint tiles;
    uint _pad;
};

static const uint TILE = 256u;
static const uint RADIX = 256u;

cbuffer pass_ : register(b0) { Pass_ pass_; }
RWByteAddressBuffer keys_in : register(u1);
RWByteAddressBuffer values_in : register(u2);
RWByteAddressBuffer keys_out : register(u3);
RWByteAddressBuffer values_out : register(u4);
RWByteAddressBuffer histogram : register(u5);
groupshared uint tile_counts[256];
groupshared uint tile_digits[256];

uint tile_index(uint3 wg_2, uint3 groups_2)
{
    return (wg_2.x + (wg_2.y * groups_2.x));
}

uint digit(uint key)
{
    uint _e3 = pass_.shift;
    return ((key >> _e3) & 255u);
}

[numthreads(256, 1, 1)]
void scatter_digits(uint lane_1 : SV_GroupIndex, uint3 wg_1 : SV_GroupID, uint3 groups_1 : SV_GroupID)
{
    if (lane_1 == 0) {
        tile_digits = (uint[256])0;
    }
    GroupMemoryBarrierWithGroupSync();
    uint d = RADIX;
    uint rank = 0u;
    uint k = 0u;

    const uint _e3 = tile_index(wg_1, groups_1);
    uint _e6 = pass_.tiles;
    if ((_e3 >= _e6)) {
        return;
    }
    uint i = ((_e3 * TILE) + lane_1);
    uint _e15 = pass_.count;
    if ((i < _e15)) {
        uint _e19 = asuint(keys_in.Load(i*4));
        const uint _e20 = digit(_e19);
        d = _e20;
    }
    uint _e23 = d;
    tile_digits[min(uint(lane_1), 255u)] = _e23;
    GroupMemoryBarrierWithGroupSync();
    uint _e26 = pass_.count;
    if ((i >= _e26)) {
        return;
    }
    uint2 loop_bound = uint2(4294967295u, 4294967295u);
    bool loop_init = true;
    while(true) {
        if (all(loop_bound == uint2(0u, 0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            uint _e46 = k;
            k = (_e46 + 1u);
        }
        loop_init = false;
        uint _e32 = k;
        if ((_e32 < lane_1)) {
        } else {
            break;
        }
        {
            uint _e34 = rank;
            uint _e38 = k;
            uint _e40 = tile_digits[min(uint(_e38), 255u)];
            uint _e41 = d;
            rank = (_e34 + ((_e40 == _e41) ? 1u : 0u));
        }
    }
    uint _e49 = d;
    uint _e52 = pass_.tiles;
    uint _e56 = asuint(histogram.Load(((_e49 * _e52) + _e3)*4));
    uint _e57 = rank;
    uint at = (_e56 + _e57);
    uint _e63 = asuint(keys_in.Load(i*4));
    keys_out.Store(at*4, asuint(_e63));
    uint _e68 = asuint(values_in.Load(i*4));
    values_out.Store(at*4, asuint(_e68));
    return;
}
