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
struct Light {
    vec3 position;
    vec3 intensity;
};
struct Sorted {
    vec3 frac;
    float luminance;
    vec3 intensity;
    uint cell;
};
struct Located {
    uvec3 cell;
    vec3 frac;
};
struct Sums {
    vec3 intensity;
    float weight;
    vec3 first;
    vec3 second;
};
struct Part {
    uint w;
    uint v;
    uvec3 q;
    uint g;
    bool busy;
};
const uint WORKGROUP = 64u;
const vec3 LUMINANCE = vec3(0.2126, 0.7152, 0.0722);

layout(std140) uniform Step_block_0Compute { Step _group_0_binding_0_cs; };

layout(std430) buffer type_8_block_1Compute { uint _group_0_binding_7_cs[]; };

layout(std430) buffer type_8_block_2Compute { uint _group_0_binding_12_cs[]; };


uint flat_(uvec3 id_5, uvec3 groups_9) {
    return (id_5.x + ((id_5.y * groups_9.x) * WORKGROUP));
}

uint pack(uvec3 c) {
    return ((c.x | (c.y << 10u)) | (c.z << 20u));
}

uvec3 unpack(uint c_1) {
    return uvec3((c_1 & 1023u), ((c_1 >> 10u) & 1023u), (c_1 >> 20u));
}

Located locate_light(vec3 p) {
    vec3 _e3 = _group_0_binding_0_cs.origin;
    float _e7 = _group_0_binding_0_cs.h1_;
    vec3 t = ((p - _e3) / vec3(_e7));
    uint _e15 = _group_0_binding_0_cs.max_cell;
    vec3 c_4 = clamp(floor(t), vec3(0.0), vec3(float(_e15)));
    return Located(uvec3(c_4), clamp((t - c_4), vec3(0.0), vec3(1.0)));
}

uint spread3_(uint v) {
    uint x = 0u;
    x = (v & 1023u);
    uint _e4 = x;
    uint _e5 = x;
    x = ((_e4 | (_e5 << 16u)) & 50331903u);
    uint _e11 = x;
    uint _e12 = x;
    x = ((_e11 | (_e12 << 8u)) & 50393103u);
    uint _e18 = x;
    uint _e19 = x;
    x = ((_e18 | (_e19 << 4u)) & 51130563u);
    uint _e25 = x;
    uint _e26 = x;
    x = ((_e25 | (_e26 << 2u)) & 153391689u);
    uint _e32 = x;
    return _e32;
}

uint morton3_(uvec3 c_2) {
    uint _e2 = spread3_(c_2.x);
    uint _e4 = spread3_(c_2.y);
    uint _e9 = spread3_(c_2.z);
    return ((_e2 | (_e4 << 1u)) | (_e9 << 2u));
}

uvec3 corner(uint k) {
    return uvec3((k & 1u), ((k >> 1u) & 1u), (k >> 2u));
}

uint cells_a_side() {
    uint _e3 = _group_0_binding_0_cs.bits;
    uint _e6 = _group_0_binding_0_cs.level;
    return (1u << (_e3 - (_e6 - 1u)));
}

vec3 place(Sorted light) {
    uint _e3 = _group_0_binding_0_cs.level;
    uint sub = (_e3 - 1u);
    uvec3 mask = uvec3(((1u << sub) - 1u));
    float scale = (1.0 / float((1u << sub)));
    uvec3 _e17 = unpack(light.cell);
    return min(((vec3((_e17 & mask)) + light.frac) * scale), vec3(1.0));
}

float weight(vec3 g_2, uvec3 o) {
    vec3 wa = mix((vec3(1.0) - g_2), g_2, equal(o, uvec3(1u)));
    return ((wa.x * wa.y) * wa.z);
}

vec3 centre(Sums s_1) {
    if ((s_1.weight > 0.0)) {
        return (s_1.first / vec3(s_1.weight));
    }
    return vec3(0.0);
}

uint compact3_(uint v_2) {
    uint x_1 = 0u;
    x_1 = (v_2 & 153391689u);
    uint _e4 = x_1;
    uint _e5 = x_1;
    x_1 = ((_e4 | (_e5 >> 2u)) & 51130563u);
    uint _e11 = x_1;
    uint _e12 = x_1;
    x_1 = ((_e11 | (_e12 >> 4u)) & 50393103u);
    uint _e18 = x_1;
    uint _e19 = x_1;
    x_1 = ((_e18 | (_e19 >> 8u)) & 50331903u);
    uint _e25 = x_1;
    uint _e26 = x_1;
    x_1 = ((_e25 | (_e26 >> 16u)) & 1023u);
    uint _e32 = x_1;
    return _e32;
}

uvec3 demorton3_(uint m) {
    uint _e1 = compact3_(m);
    uint _e4 = compact3_((m >> 1u));
    uint _e7 = compact3_((m >> 2u));
    return uvec3(_e1, _e4, _e7);
}

void main() {
    uvec3 id_3 = gl_GlobalInvocationID;
    uvec3 groups_3 = gl_NumWorkGroups;
    uint _e2 = flat_(id_3, groups_3);
    uint _e5 = _group_0_binding_0_cs.count;
    if ((_e2 >= _e5)) {
        return;
    }
    uint _e10 = _group_0_binding_0_cs.slot_offset;
    uint v_3 = _group_0_binding_7_cs[(_e10 + _e2)];
    uint _e17 = _group_0_binding_0_cs.slot_offset;
    uint _e22 = _group_0_binding_7_cs[((_e17 + _e2) + 1u)];
    if ((_e22 != v_3)) {
        uint _e27 = _group_0_binding_0_cs.list_offset;
        _group_0_binding_12_cs[(_e27 + v_3)] = _e2;
        return;
    } else {
        return;
    }
}

