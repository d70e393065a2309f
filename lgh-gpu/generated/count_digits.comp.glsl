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

layout(std430) buffer type_1_block_2Compute { uint _group_0_binding_5_cs[]; };

shared uint tile_counts[256];


uint tile_index(uvec3 wg_2, uvec3 groups_2) {
    return (wg_2.x + (wg_2.y * groups_2.x));
}

uint digit(uint key) {
    uint _e3 = _group_0_binding_0_cs.shift;
    return ((key >> _e3) & 255u);
}

void main() {
    if (gl_LocalInvocationID == uvec3(0u)) {
        tile_counts = uint[256](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
    }
    memoryBarrierShared();
    barrier();
    uint lane = gl_LocalInvocationIndex;
    uvec3 wg = gl_WorkGroupID;
    uvec3 groups = gl_NumWorkGroups;
    bool local = false;
    uint _e3 = tile_index(wg, groups);
    uint _e6 = _group_0_binding_0_cs.tiles;
    if ((_e3 >= _e6)) {
        return;
    }
    atomicExchange(tile_counts[lane], 0u);
    memoryBarrierShared();
    barrier();
    uint i = ((_e3 * TILE) + lane);
    uint _e16 = _group_0_binding_0_cs.count;
    if ((i < _e16)) {
        uint _e21 = _group_0_binding_1_cs[i];
        uint _e22 = digit(_e21);
        uint _e25 = atomicAdd(tile_counts[_e22], 1u);
    }
    memoryBarrierShared();
    barrier();
    uint _e29 = _group_0_binding_0_cs.tiles;
    uint _e35 = atomicOr(tile_counts[lane], 0u);
    _group_0_binding_5_cs[((lane * _e29) + _e3)] = _e35;
    if ((_e3 == 0u)) {
        local = (lane == 0u);
    } else {
        local = false;
    }
    bool _e43 = local;
    if (_e43) {
        uint _e48 = _group_0_binding_0_cs.tiles;
        _group_0_binding_5_cs[(RADIX * _e48)] = 0u;
        return;
    } else {
        return;
    }
}

