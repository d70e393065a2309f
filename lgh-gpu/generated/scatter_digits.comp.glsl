#version 430 core
#extension GL_ARB_compute_shader : require
#extension GL_ARB_shader_storage_buffer_object : require
layout(local_size_x = 256, local_size_y = 1, local_size_z = 1) in;

struct Pass {
    uint count;
    uint shift;
    uint tiles;
    uint _pad;
};
const uint TILE = 256u;
const uint RADIX = 256u;

layout(std140) uniform Pass_block_0Compute { Pass _group_0_binding_0_cs; };

layout(std430) buffer type_1_block_1Compute { uint _group_0_binding_1_cs[]; };

layout(std430) buffer type_1_block_2Compute { uint _group_0_binding_2_cs[]; };

layout(std430) buffer type_1_block_3Compute { uint _group_0_binding_3_cs[]; };

layout(std430) buffer type_1_block_4Compute { uint _group_0_binding_4_cs[]; };

layout(std430) buffer type_1_block_5Compute { uint _group_0_binding_5_cs[]; };

shared uint tile_digits[256];


uint tile_index(uvec3 wg_2, uvec3 groups_2) {
    return (wg_2.x + (wg_2.y * groups_2.x));
}

uint digit(uint key) {
    uint _e3 = _group_0_binding_0_cs.shift;
    return ((key >> _e3) & 255u);
}

void main() {
    if (gl_LocalInvocationID == uvec3(0u)) {
        tile_digits = uint[256](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
    }
    memoryBarrierShared();
    barrier();
    uint lane_1 = gl_LocalInvocationIndex;
    uvec3 wg_1 = gl_WorkGroupID;
    uvec3 groups_1 = gl_NumWorkGroups;
    uint d = RADIX;
    uint rank = 0u;
    uint k = 0u;
    uint _e3 = tile_index(wg_1, groups_1);
    uint _e6 = _group_0_binding_0_cs.tiles;
    if ((_e3 >= _e6)) {
        return;
    }
    uint i = ((_e3 * TILE) + lane_1);
    uint _e15 = _group_0_binding_0_cs.count;
    if ((i < _e15)) {
        uint _e19 = _group_0_binding_1_cs[i];
        uint _e20 = digit(_e19);
        d = _e20;
    }
    uint _e23 = d;
    tile_digits[lane_1] = _e23;
    memoryBarrierShared();
    barrier();
    uint _e26 = _group_0_binding_0_cs.count;
    if ((i >= _e26)) {
        return;
    }
    bool loop_init = true;
    while(true) {
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
            uint _e40 = tile_digits[_e38];
            uint _e41 = d;
            rank = (_e34 + ((_e40 == _e41) ? 1u : 0u));
        }
    }
    uint _e49 = d;
    uint _e52 = _group_0_binding_0_cs.tiles;
    uint _e56 = _group_0_binding_5_cs[((_e49 * _e52) + _e3)];
    uint _e57 = rank;
    uint at = (_e56 + _e57);
    uint _e63 = _group_0_binding_1_cs[i];
    _group_0_binding_3_cs[at] = _e63;
    uint _e68 = _group_0_binding_2_cs[i];
    _group_0_binding_4_cs[at] = _e68;
    return;
}

