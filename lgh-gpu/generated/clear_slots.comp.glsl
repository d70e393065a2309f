#version 430 core
#extension GL_ARB_compute_shader : require
#extension GL_ARB_shader_storage_buffer_object : require
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

struct Step {
    vec3 origin;
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
const uint WORKGROUP = 64u;

layout(std140) uniform Step_block_0Compute { Step _group_0_binding_0_cs; };

layout(std430) buffer type_5_block_1Compute { uint _group_0_binding_7_cs[]; };


uint flat_(uvec3 id_2, uvec3 groups_2) {
    return (id_2.x + ((id_2.y * groups_2.x) * WORKGROUP));
}

uint compact3_(uint v) {
    uint x = 0u;
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

uvec3 demorton3_(uint m) {
    uint _e1 = compact3_(m);
    uint _e4 = compact3_((m >> 1u));
    uint _e7 = compact3_((m >> 2u));
    return uvec3(_e1, _e4, _e7);
}

uint spread3_(uint v_1) {
    uint x_1 = 0u;
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

uint morton3_(uvec3 c) {
    uint _e2 = spread3_(c.x);
    uint _e4 = spread3_(c.y);
    uint _e9 = spread3_(c.z);
    return ((_e2 | (_e4 << 1u)) | (_e9 << 2u));
}

void main() {
    uvec3 id = gl_GlobalInvocationID;
    uvec3 groups = gl_NumWorkGroups;
    uint _e2 = flat_(id, groups);
    uint _e5 = _group_0_binding_0_cs.count;
    if ((_e2 <= _e5)) {
        uint _e10 = _group_0_binding_0_cs.slot_offset;
        atomicExchange(_group_0_binding_7_cs[(_e10 + _e2)], 0u);
        return;
    } else {
        return;
    }
}

