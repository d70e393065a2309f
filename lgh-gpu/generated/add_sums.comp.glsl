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
const uint THREADS = 256u;
const uint ITEMS = 4u;
const uint BLOCK = 1024u;

layout(std140) uniform Step_block_0Compute { Step _group_0_binding_0_cs; };

layout(std430) buffer type_1_block_1Compute { uint _group_0_binding_1_cs[]; };


uint block_index(uvec3 wg_2, uvec3 groups_2) {
    return (wg_2.x + (wg_2.y * groups_2.x));
}

void main() {
    uint lane_1 = gl_LocalInvocationIndex;
    uvec3 wg_1 = gl_WorkGroupID;
    uvec3 groups_1 = gl_NumWorkGroups;
    uint i_4 = 0u;
    uint _e3 = block_index(wg_1, groups_1);
    uint _e7 = _group_0_binding_0_cs.sums;
    uint add_1 = _group_0_binding_1_cs[(_e7 + _e3)];
    bool loop_init = true;
    while(true) {
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
            uint _e25 = _group_0_binding_0_cs.count;
            if ((k < _e25)) {
                uint _e30 = _group_0_binding_0_cs.offset;
                uint _e33 = _group_0_binding_1_cs[(_e30 + k)];
                _group_0_binding_1_cs[(_e30 + k)] = (_e33 + add_1);
            }
        }
    }
    return;
}

