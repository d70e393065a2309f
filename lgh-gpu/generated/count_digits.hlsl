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
void count_digits(uint lane : SV_GroupIndex, uint3 wg : SV_GroupID, uint3 groups : SV_GroupID)
{
    if (lane == 0) {
        tile_counts = (uint[256])0;
    }
    GroupMemoryBarrierWithGroupSync();
    bool local = (bool)0;

    const uint _e3 = tile_index(wg, groups);
    uint _e6 = pass_.tiles;
    if ((_e3 >= _e6)) {
        return;
    }
    { uint dummy = 0; InterlockedExchange(tile_counts[min(uint(lane), 255u)], 0u, dummy); }
    GroupMemoryBarrierWithGroupSync();
    uint i = ((_e3 * TILE) + lane);
    uint _e16 = pass_.count;
    if ((i < _e16)) {
        uint _e21 = asuint(keys_in.Load(i*4));
        const uint _e22 = digit(_e21);
        uint _e25; InterlockedAdd(tile_counts[min(uint(_e22), 255u)], 1u, _e25);
    }
    GroupMemoryBarrierWithGroupSync();
    uint _e29 = pass_.tiles;
    uint _e35; InterlockedOr(tile_counts[min(uint(lane), 255u)], 0, _e35);
    histogram.Store(((lane * _e29) + _e3)*4, asuint(_e35));
    if ((_e3 == 0u)) {
        local = (lane == 0u);
    } else {
        local = false;
    }
    bool _e43 = local;
    if (_e43) {
        uint _e48 = pass_.tiles;
        histogram.Store((RADIX * _e48)*4, asuint(0u));
        return;
    } else {
        return;
    }
}

