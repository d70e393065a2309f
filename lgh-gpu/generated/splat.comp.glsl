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

layout(std430) buffer type_8_block_1Compute { uint _group_0_binding_4_cs[]; };

layout(std430) buffer type_9_block_2Compute { Sorted _group_0_binding_6_cs[]; };

layout(std430) buffer type_10_block_3Compute { Light _group_0_binding_8_cs[]; };

layout(std430) buffer type_5_block_4Compute { vec4 _group_0_binding_9_cs[]; };

layout(std430) buffer type_8_block_5Compute { uint _group_0_binding_12_cs[]; };


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

uvec2 cell_range(uvec3 c_3) {
    uint _e4 = _group_0_binding_0_cs.level;
    uint shift = (3u * (_e4 - 1u));
    uint _e8 = morton3_(c_3);
    uint _e12 = _group_0_binding_4_cs[(_e8 << shift)];
    uint _e18 = _group_0_binding_4_cs[((_e8 + 1u) << shift)];
    return uvec2(_e12, _e18);
}

uvec2 corner_cell(uvec3 q, uint k_1) {
    bool local_1 = false;
    uvec3 _e2 = corner(k_1);
    if (!(any(lessThan(q, _e2)))) {
        uint _e9 = cells_a_side();
        local_1 = any(greaterThanEqual((q - _e2), uvec3(_e9)));
    } else {
        local_1 = true;
    }
    bool _e14 = local_1;
    if (_e14) {
        return uvec2(0u);
    }
    uvec2 _e18 = cell_range((q - _e2));
    return _e18;
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

Sums moment_sums(uvec3 q_1, uint lane_4, uint lanes) {
    Sums s = Sums(vec3(0.0), 0.0, vec3(0.0), vec3(0.0));
    uint k_2 = 0u;
    uint j = 0u;
    bool loop_init = true;
    while(true) {
        if (!loop_init) {
            uint _e57 = k_2;
            k_2 = (_e57 + 1u);
        }
        loop_init = false;
        uint _e14 = k_2;
        if ((_e14 < 8u)) {
        } else {
            break;
        }
        {
            uint _e17 = k_2;
            uvec2 _e18 = corner_cell(q_1, _e17);
            uint _e19 = k_2;
            uvec3 _e20 = corner(_e19);
            j = (_e18.x + lane_4);
            bool loop_init_1 = true;
            while(true) {
                if (!loop_init_1) {
                    uint _e54 = j;
                    j = (_e54 + lanes);
                }
                loop_init_1 = false;
                uint _e24 = j;
                if ((_e24 < _e18.y)) {
                } else {
                    break;
                }
                {
                    uint _e28 = j;
                    Sorted light_1 = _group_0_binding_6_cs[_e28];
                    vec3 _e31 = place(light_1);
                    float _e32 = weight(_e31, _e20);
                    float v_3 = (_e32 * light_1.luminance);
                    vec3 off = (_e31 - vec3(_e20));
                    vec3 _e38 = s.intensity;
                    s.intensity = (_e38 + (_e32 * light_1.intensity));
                    float _e43 = s.weight;
                    s.weight = (_e43 + v_3);
                    vec3 _e46 = s.first;
                    s.first = (_e46 + (v_3 * off));
                    vec3 _e50 = s.second;
                    s.second = (_e50 + (v_3 * (off * off)));
                }
            }
        }
    }
    Sums _e59 = s;
    return _e59;
}

float size_sum(uvec3 q_2, vec3 mean, uint lane_5, uint lanes_1) {
    float sum_2 = 0.0;
    uint k_3 = 0u;
    uint j_1 = 0u;
    bool loop_init_2 = true;
    while(true) {
        if (!loop_init_2) {
            uint _e39 = k_3;
            k_3 = (_e39 + 1u);
        }
        loop_init_2 = false;
        uint _e8 = k_3;
        if ((_e8 < 8u)) {
        } else {
            break;
        }
        {
            uint _e11 = k_3;
            uvec2 _e12 = corner_cell(q_2, _e11);
            uint _e13 = k_3;
            uvec3 _e14 = corner(_e13);
            j_1 = (_e12.x + lane_5);
            bool loop_init_3 = true;
            while(true) {
                if (!loop_init_3) {
                    uint _e36 = j_1;
                    j_1 = (_e36 + lanes_1);
                }
                loop_init_3 = false;
                uint _e18 = j_1;
                if ((_e18 < _e12.y)) {
                } else {
                    break;
                }
                {
                    uint _e22 = j_1;
                    Sorted light_2 = _group_0_binding_6_cs[_e22];
                    vec3 _e25 = place(light_2);
                    float _e26 = sum_2;
                    float _e27 = weight(_e25, _e14);
                    sum_2 = (_e26 + ((_e27 * light_2.luminance) * length((_e25 - (vec3(_e14) + mean)))));
                }
            }
        }
    }
    float _e41 = sum_2;
    return _e41;
}

vec3 centre(Sums s_1) {
    if ((s_1.weight > 0.0)) {
        return (s_1.first / vec3(s_1.weight));
    }
    return vec3(0.0);
}

void write_vertex(uvec3 q_3, uint v_1, Sums s_2, vec3 mean_1, float size_sum_1) {
    vec3 variance = vec3(0.0);
    float size = 0.0;
    bool local_2 = false;
    float _e7 = _group_0_binding_0_cs.h1_;
    uint _e11 = _group_0_binding_0_cs.level;
    float h = (_e7 * float((1u << (_e11 - 1u))));
    if ((s_2.weight > 0.0)) {
        variance = ((max(((s_2.second / vec3(s_2.weight)) - (mean_1 * mean_1)), vec3(0.0)) * h) * h);
        size = ((size_sum_1 / s_2.weight) * h);
    }
    vec3 _e41 = _group_0_binding_0_cs.origin;
    vec3 position = (_e41 + ((vec3(q_3) + mean_1) * h));
    float luminance = dot(s_2.intensity, LUMINANCE);
    if ((luminance > 0.0)) {
        float _e55 = _group_0_binding_0_cs.threshold;
        local_2 = (luminance >= _e55);
    } else {
        local_2 = false;
    }
    bool reported = local_2;
    uint _e62 = _group_0_binding_0_cs.light_base;
    _group_0_binding_8_cs[(_e62 + v_1)] = Light(position, (reported ? s_2.intensity : vec3(0.0)));
    uint _e73 = _group_0_binding_0_cs.light_base;
    vec3 _e76 = variance;
    float _e77 = size;
    _group_0_binding_9_cs[(_e73 + v_1)] = vec4(_e76, _e77);
    return;
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

Part part(uvec3 wg_4, uvec3 groups_10, uint parts) {
    uint w = (wg_4.x + (wg_4.y * groups_10.x));
    uint _e10 = _group_0_binding_0_cs.count;
    if ((w >= (_e10 * parts))) {
        return Part(w, 0u, uvec3(0u), 0u, false);
    }
    uint v_4 = (w / parts);
    uint _e23 = _group_0_binding_0_cs.list_offset;
    uint _e26 = _group_0_binding_12_cs[(_e23 + v_4)];
    uvec3 _e27 = demorton3_(_e26);
    return Part(w, v_4, _e27, (w % parts), true);
}

void main() {
    uvec3 id_4 = gl_GlobalInvocationID;
    uvec3 groups_4 = gl_NumWorkGroups;
    uint _e2 = flat_(id_4, groups_4);
    uint _e5 = _group_0_binding_0_cs.count;
    if ((_e2 >= _e5)) {
        return;
    }
    uint _e10 = _group_0_binding_0_cs.list_offset;
    uint _e13 = _group_0_binding_12_cs[(_e10 + _e2)];
    uvec3 _e14 = demorton3_(_e13);
    Sums _e17 = moment_sums(_e14, 0u, 1u);
    vec3 _e18 = centre(_e17);
    float _e21 = size_sum(_e14, _e18, 0u, 1u);
    write_vertex(_e14, _e2, _e17, _e18, _e21);
    return;
}

