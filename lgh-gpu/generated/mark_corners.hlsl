struct Step {
    float3 origin;
    float h1_;
    uint n;
    uint bits;
    uint level;
    uint top;
    uint max_cell;
    uint slot_offset;
    uint light_base;
    float threshold;
    uint count;
    uint parts;
    uint list_offset;
    uint _pad0_;
};

static const uint WORKGROUP = 64u;

cbuffer step_ : register(b0) { Step step_; }
RWByteAddressBuffer marks : register(u7);
RWByteAddressBuffer sorted_keys : register(u10);

uint flat(uint3 id_2, uint3 groups_2)
{
    return (id_2.x + ((id_2.y * groups_2.x) * WORKGROUP));
}

uint compact3_(uint v)
{
    uint x = (uint)0;

    x = (v & 153391689u);
    uint _e4 = x;
    uint _e5 = x;
    x = ((_e4 | (_e5 >> 2u)) & 51130563u);
    uint _e11 = x;
    uint _e12 = x;
    x = ((_e11 | (_e12 >> 4u)) & 50393103u);
    uint _e18 = x;
    uint _e19 = x;
    x = ((_e18 | (_e19 >> 8u)) & 50331903u);
    uint _e25 = x;
    uint _e26 = x;
    x = ((_e25 | (_e26 >> 16u)) & 1023u);
    uint _e32 = x;
    return _e32;
}

uint3 demorton3_(uint m)
{
    const uint _e1 = compact3_(m);
    const uint _e4 = compact3_((m >> 1u));
    const uint _e7 = compact3_((m >> 2u));
    return uint3(_e1, _e4, _e7);
}

uint spread3_(uint v_1)
{
    uint x_1 = (uint)0;

    x_1 = (v_1 & 1023u);
    uint _e4 = x_1;
    uint _e5 = x_1;
    x_1 = ((_e4 | (_e5 << 16u)) & 50331903u);
    uint _e11 = x_1;
    uint _e12 = x_1;
    x_1 = ((_e11 | (_e12 << 8u)) & 50393103u);
    uint _e18 = x_1;
    uint _e19 = x_1;
    x_1 = ((_e18 | (_e19 << 4u)) & 51130563u);
    uint _e25 = x_1;
    uint _e26 = x_1;
    x_1 = ((_e25 | (_e26 << 2u)) & 153391689u);
    uint _e32 = x_1;
    return _e32;
}

uint morton3_(uint3 c)
{
    const uint _e2 = spread3_(c.x);
    const uint _e4 = spread3_(c.y);
    const uint _e9 = spread3_(c.z);
    return ((_e2 | (_e4 << 1u)) | (_e9 << 2u));
}

[numthreads(64, 1, 1)]
void mark_corners(uint3 id_1 : SV_DispatchThreadID, uint3 groups_1 : SV_GroupID)
{
    uint k = 0u;

    const uint _e2 = flat(id_1, groups_1);
    uint _e5 = step_.n;
    if ((_e2 >= _e5)) {
        return;
    }
    uint _e9 = asuint(sorted_keys.Load(_e2*4));
    const uint3 _e10 = demorton3_(_e9);
    uint _e13 = step_.level;
    uint3 c_1 = (_e10 >> ((_e13 - 1u)).xxx);
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
        uint _e20 = k;
        if ((_e20 < 8u)) {
        } else {
            break;
        }
        {
            uint _e23 = k;
            uint _e26 = k;
            uint _e31 = k;
            uint3 q = (c_1 + uint3((_e23 & 1u), ((_e26 >> 1u) & 1u), (_e31 >> 2u)));
            uint _e39 = step_.slot_offset;
            const uint _e40 = morton3_(q);
            uint _e44; marks.InterlockedOr((_e39 + _e40)*4, 1u, _e44);
        }
    }
    return;
}
