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
    uint _pad0_;
    uint _pad1_;
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
const uint WORKGROUP = 64u;
const vec3 LUMINANCE = vec3(0.2126, 0.7152, 0.0722);

layout(std140) uniform Step_block_0Compute { Step _group_0_binding_0_cs; };

layout(std430) buffer type_7_block_1Compute { uint _group_0_binding_4_cs[]; };

layout(std430) buffer type_8_block_2Compute { Sorted _group_0_binding_6_cs[]; };

layout(std430) buffer type_7_block_3Compute { uint _group_0_binding_7_cs[]; };

layout(std430) buffer type_14_block_4Compute { vec4 _group_0_binding_11_cs[][5]; };

shared vec4 lane_sums[64][3];

shared uint occupied_slot;


uint flat_(uvec3 id_5, uvec3 groups_9) {
    return (id_5.x + ((id_5.y * groups_9.x) * WORKGROUP));
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

uint compact3_(uint v_1) {
    uint x_1 = 0u;
    x_1 = (v_1 & 153391689u);
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

uint morton3_(uvec3 c) {
    uint _e2 = spread3_(c.x);
    uint _e4 = spread3_(c.y);
    uint _e9 = spread3_(c.z);
    return ((_e2 | (_e4 << 1u)) | (_e9 << 2u));
}

uvec3 demorton3_(uint m) {
    uint _e1 = compact3_(m);
    uint _e4 = compact3_((m >> 1u));
    uint _e7 = compact3_((m >> 2u));
    return uvec3(_e1, _e4, _e7);
}

uint pack(uvec3 c_1) {
    return ((c_1.x | (c_1.y << 10u)) | (c_1.z << 20u));
}

uvec3 unpack(uint c_2) {
    return uvec3((c_2 & 1023u), ((c_2 >> 10u) & 1023u), (c_2 >> 20u));
}

Located locate_light(vec3 p) {
    vec3 _e3 = _group_0_binding_0_cs.origin;
    float _e7 = _group_0_binding_0_cs.h1_;
    vec3 t = ((p - _e3) / vec3(_e7));
    uint _e15 = _group_0_binding_0_cs.max_cell;
    vec3 c_4 = clamp(floor(t), vec3(0.0), vec3(float(_e15)));
    return Located(uvec3(c_4), clamp((t - c_4), vec3(0.0), vec3(1.0)));
}

uvec3 corner(uint k_1) {
    return uvec3((k_1 & 1u), ((k_1 >> 1u) & 1u), (k_1 >> 2u));
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

Sums moment_sums(uvec3 q, uint lane_4, uint lanes) {
    Sums s = Sums(vec3(0.0), 0.0, vec3(0.0), vec3(0.0));
    uint k_2 = 0u;
    bool local_2 = false;
    uint j = 0u;
    uint _e12 = cells_a_side();
    uint _e15 = _group_0_binding_0_cs.level;
    uint sub = (_e15 - 1u);
    uint mask = ((1u << sub) - 1u);
    float scale = (1.0 / float((1u << sub)));
    bool loop_init = true;
    while(true) {
        if (!loop_init) {
            uint _e104 = k_2;
            k_2 = (_e104 + 1u);
        }
        loop_init = false;
        uint _e29 = k_2;
        if ((_e29 < 8u)) {
        } else {
            break;
        }
        {
            uint _e32 = k_2;
            uvec3 _e33 = corner(_e32);
            if (!(any(lessThan(q, _e33)))) {
                local_2 = any(greaterThanEqual((q - _e33), uvec3(_e12)));
            } else {
                local_2 = true;
            }
            bool _e44 = local_2;
            if (_e44) {
                continue;
            }
            uvec2 _e46 = cell_range((q - _e33));
            vec3 at = vec3(_e33);
            j = (_e46.x + lane_4);
            bool loop_init_1 = true;
            while(true) {
                if (!loop_init_1) {
                    uint _e101 = j;
                    j = (_e101 + lanes);
                }
                loop_init_1 = false;
                uint _e51 = j;
                if ((_e51 < _e46.y)) {
                } else {
                    break;
                }
                {
                    uint _e55 = j;
                    Sorted light = _group_0_binding_6_cs[_e55];
                    uvec3 _e59 = unpack(light.cell);
                    vec3 g_2 = min(((vec3((_e59 & uvec3(mask))) + light.frac) * scale), vec3(1.0));
                    vec3 wa = mix((vec3(1.0) - g_2), g_2, equal(_e33, uvec3(1u)));
                    float w = ((wa.x * wa.y) * wa.z);
                    float v_3 = (w * light.luminance);
                    vec3 off = (g_2 - at);
                    vec3 _e85 = s.intensity;
                    s.intensity = (_e85 + (w * light.intensity));
                    float _e90 = s.weight;
                    s.weight = (_e90 + v_3);
                    vec3 _e93 = s.first;
                    s.first = (_e93 + (v_3 * off));
                    vec3 _e97 = s.second;
                    s.second = (_e97 + (v_3 * (off * off)));
                }
            }
        }
    }
    Sums _e106 = s;
    return _e106;
}

float size_sum(uvec3 q_1, vec3 mean, uint lane_5, uint lanes_1) {
    float sum_2 = 0.0;
    uint k_3 = 0u;
    bool local_3 = false;
    uint j_1 = 0u;
    uint _e6 = cells_a_side();
    uint _e9 = _group_0_binding_0_cs.level;
    uint sub_1 = (_e9 - 1u);
    uint mask_1 = ((1u << sub_1) - 1u);
    float scale_1 = (1.0 / float((1u << sub_1)));
    bool loop_init_2 = true;
    while(true) {
        if (!loop_init_2) {
            uint _e86 = k_3;
            k_3 = (_e86 + 1u);
        }
        loop_init_2 = false;
        uint _e23 = k_3;
        if ((_e23 < 8u)) {
        } else {
            break;
        }
        {
            uint _e26 = k_3;
            uvec3 _e27 = corner(_e26);
            if (!(any(lessThan(q_1, _e27)))) {
                local_3 = any(greaterThanEqual((q_1 - _e27), uvec3(_e6)));
            } else {
                local_3 = true;
            }
            bool _e38 = local_3;
            if (_e38) {
                continue;
            }
            uvec2 _e40 = cell_range((q_1 - _e27));
            vec3 centre_1 = (vec3(_e27) + mean);
            j_1 = (_e40.x + lane_5);
            bool loop_init_3 = true;
            while(true) {
                if (!loop_init_3) {
                    uint _e83 = j_1;
                    j_1 = (_e83 + lanes_1);
                }
                loop_init_3 = false;
                uint _e46 = j_1;
                if ((_e46 < _e40.y)) {
                } else {
                    break;
                }
                {
                    uint _e50 = j_1;
                    Sorted light_1 = _group_0_binding_6_cs[_e50];
                    uvec3 _e54 = unpack(light_1.cell);
                    vec3 g_3 = min(((vec3((_e54 & uvec3(mask_1))) + light_1.frac) * scale_1), vec3(1.0));
                    vec3 wa_1 = mix((vec3(1.0) - g_3), g_3, equal(_e27, uvec3(1u)));
                    float w_1 = ((wa_1.x * wa_1.y) * wa_1.z);
                    float _e76 = sum_2;
                    sum_2 = (_e76 + ((w_1 * light_1.luminance) * length((g_3 - centre_1))));
                }
            }
        }
    }
    float _e88 = sum_2;
    return _e88;
}

vec3 centre(Sums s_1) {
    if ((s_1.weight > 0.0)) {
        return (s_1.first / vec3(s_1.weight));
    }
    return vec3(0.0);
}

bool slot_is_occupied(uint m_1, uint lane_6) {
    if ((lane_6 == 0u)) {
        uint _e10 = _group_0_binding_0_cs.slot_offset;
        uint _e15 = _group_0_binding_7_cs[((_e10 + m_1) + 1u)];
        uint _e19 = _group_0_binding_0_cs.slot_offset;
        uint _e22 = _group_0_binding_7_cs[(_e19 + m_1)];
        occupied_slot = ((_e15 != _e22) ? 1u : 0u);
    }
    memoryBarrierShared();
    barrier();
    uint _e26 = occupied_slot;
    memoryBarrierShared();
    barrier();
    return (_e26 == 1u);
}

void reduce(uint lane_7) {
    uint stride = 32u;
    uint a_3 = 0u;
    bool loop_init_4 = true;
    while(true) {
        if (!loop_init_4) {
            uint _e29 = stride;
            stride = (_e29 / 2u);
        }
        loop_init_4 = false;
        uint _e3 = stride;
        if ((_e3 > 0u)) {
        } else {
            break;
        }
        {
            uint _e6 = stride;
            if ((lane_7 < _e6)) {
                a_3 = 0u;
                bool loop_init_5 = true;
                while(true) {
                    if (!loop_init_5) {
                        uint _e27 = a_3;
                        a_3 = (_e27 + 1u);
                    }
                    loop_init_5 = false;
                    uint _e10 = a_3;
                    if ((_e10 < 3u)) {
                    } else {
                        break;
                    }
                    {
                        uint _e15 = a_3;
                        vec4 _e17 = lane_sums[lane_7][_e15];
                        uint _e19 = stride;
                        uint _e22 = a_3;
                        vec4 _e24 = lane_sums[(lane_7 + _e19)][_e22];
                        lane_sums[lane_7][_e15] = (_e17 + _e24);
                    }
                }
            }
            memoryBarrierShared();
            barrier();
        }
    }
    return;
}

void main() {
    if (gl_LocalInvocationID == uvec3(0u)) {
        lane_sums = vec4[64][3](vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)));
        occupied_slot = 0u;
    }
    memoryBarrierShared();
    barrier();
    uint lane = gl_LocalInvocationIndex;
    uvec3 wg = gl_WorkGroupID;
    uvec3 groups_5 = gl_NumWorkGroups;
    uint a = 0u;
    uint w_2 = (wg.x + (wg.y * groups_5.x));
    uint _e10 = _group_0_binding_0_cs.count;
    uint _e13 = _group_0_binding_0_cs.parts;
    if ((w_2 >= (_e10 * _e13))) {
        return;
    }
    uint _e18 = _group_0_binding_0_cs.parts;
    uint m_2 = (w_2 / _e18);
    uint _e22 = _group_0_binding_0_cs.parts;
    uint g_4 = (w_2 % _e22);
    bool _e24 = slot_is_occupied(m_2, lane);
    if (!(_e24)) {
        return;
    }
    uvec3 _e26 = demorton3_(m_2);
    uint _e33 = _group_0_binding_0_cs.parts;
    Sums _e35 = moment_sums(_e26, ((g_4 * WORKGROUP) + lane), (WORKGROUP * _e33));
    lane_sums[lane] = vec4[3](vec4(_e35.intensity, _e35.weight), vec4(_e35.first, 0.0), vec4(_e35.second, 0.0));
    memoryBarrierShared();
    barrier();
    reduce(lane);
    if ((lane == 0u)) {
        bool loop_init_6 = true;
        while(true) {
            if (!loop_init_6) {
                uint _e65 = a;
                a = (_e65 + 1u);
            }
            loop_init_6 = false;
            uint _e52 = a;
            if ((_e52 < 3u)) {
            } else {
                break;
            }
            {
                uint _e57 = a;
                uint _e61 = a;
                vec4 _e63 = lane_sums[0][_e61];
                _group_0_binding_11_cs[w_2][_e57] = _e63;
            }
        }
        return;
    } else {
        return;
    }
}

