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
void clear_slots(uint3 id : SV_DispatchThreadID, uint3 groups : SV_GroupID)
{
    const uint _e2 = flat(id, groups);
    uint _e5 = step_.count;
    if ((_e2 <= _e5)) {
        uint _e10 = step_.slot_offset;
        { uint dummy = 0; marks.InterlockedExchange((_e10 + _e2)*4, 0u, dummy); }
        return;
    } else {
        return;
    }
}

