#version 430 core
#extension GL_ARB_compute_shader : require
#extension GL_ARB_shader_storage_buffer_object : require
layout(local_size_x = 256, local_size_y = 1, local_size_z = 1) in;

struct Step {
    uint offset;
    uint count;
    uint sums;
    uint _pad;
};
const uint BLOCK = 256u;

layout(std140) uniform Step_block_0Compute { Step _group_0_binding_0_cs; };

layout(std430) buffer type_1_block_1Compute { uint _group_0_binding_1_cs[]; };


uint block_index(uvec3 wg_2, uvec3 groups_2) {
    return (wg_2.x + (wg_2.y * groups_2.x));
}

void main() {
    uint lane_1 = gl_LocalInvocationIndex;
    uvec3 wg_1 = gl_WorkGroupID;
    uvec3 groups_1 = gl_NumWorkGroups;
    uint _e3 = block_index(wg_1, groups_1);
    uint i = ((_e3 * BLOCK) + lane_1);
    uint _e9 = _group_0_binding_0_cs.count;
    if ((i < _e9)) {
        uint _e14 = _group_0_binding_0_cs.offset;
        uint _e17 = _group_0_binding_1_cs[(_e14 + i)];
        uint _e21 = _group_0_binding_0_cs.sums;
        uint _e24 = _group_0_binding_1_cs[(_e21 + _e3)];
        _group_0_binding_1_cs[(_e14 + i)] = (_e17 + _e24);
        return;
    } else {
        return;
    }
}

