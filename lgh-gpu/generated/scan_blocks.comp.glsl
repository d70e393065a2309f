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

shared uint shared_values[256];


uint block_index(uvec3 wg_2, uvec3 groups_2) {
    return (wg_2.x + (wg_2.y * groups_2.x));
}

void main() {
    if (gl_LocalInvocationID == uvec3(0u)) {
        shared_values = uint[256](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
    }
    memoryBarrierShared();
    barrier();
    uint lane = gl_LocalInvocationIndex;
    uvec3 wg = gl_WorkGroupID;
    uvec3 groups = gl_NumWorkGroups;
    uint value = 0u;
    uint d = 1u;
    uint add = 0u;
    bool local = false;
    uint _e3 = block_index(wg, groups);
    uint i = ((_e3 * BLOCK) + lane);
    uint _e11 = _group_0_binding_0_cs.count;
    if ((i < _e11)) {
        uint _e16 = _group_0_binding_0_cs.offset;
        uint _e19 = _group_0_binding_1_cs[(_e16 + i)];
        value = _e19;
    }
    uint _e22 = value;
    shared_values[lane] = _e22;
    memoryBarrierShared();
    barrier();
    bool loop_init = true;
    while(true) {
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
                uint _e36 = shared_values[(lane - _e33)];
                add = _e36;
            }
            memoryBarrierShared();
            barrier();
            uint _e39 = shared_values[lane];
            uint _e40 = add;
            shared_values[lane] = (_e39 + _e40);
            memoryBarrierShared();
            barrier();
        }
    }
    uint _e47 = _group_0_binding_0_cs.count;
    if ((i < _e47)) {
        uint _e52 = _group_0_binding_0_cs.offset;
        uint _e57 = shared_values[lane];
        uint _e58 = value;
        _group_0_binding_1_cs[(_e52 + i)] = (_e57 - _e58);
    }
    if ((lane == 255u)) {
        uint _e68 = _group_0_binding_0_cs.count;
        local = ((_e3 * BLOCK) < _e68);
    } else {
        local = false;
    }
    bool _e71 = local;
    if (_e71) {
        uint _e75 = _group_0_binding_0_cs.sums;
        uint _e80 = shared_values[lane];
        _group_0_binding_1_cs[(_e75 + _e3)] = _e80;
        return;
    } else {
        return;
    }
}

