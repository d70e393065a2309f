#version 430 core
#extension GL_ARB_compute_shader : require
#extension GL_ARB_shader_storage_buffer_object : require
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

struct Light {
    vec3 position;
    vec3 intensity;
};
struct Point {
    vec3 position;
    vec3 normal;
    vec3 albedo;
};
struct Level {
    vec3 origin;
    float cell;
    uvec3 dims;
    uint first_cell;
    uint first_light;
    uint light_count;
    float inner2_;
    float outer2_;
    vec4 ramp;
    float margin;
    uint stride;
    uint order;
    uint bank;
};
struct Params {
    uint levels;
    uint points;
    float h0_;
    uint split;
    uint k;
    uint seed;
    uint _pad0_;
    uint _pad1_;
};
const uint WORKGROUP = 64u;
const float INV_PI = 0.31830987;
const uint CELLS_ROWS = 0u;
const uint CELLS_MORTON = 1u;
const uint STARTS_CELLS = 0u;
const uint STARTS_SLOTS = 1u;

layout(std140) uniform Params_block_0Compute { Params _group_0_binding_0_cs; };

layout(std430) readonly buffer type_5_block_1Compute { Level _group_0_binding_1_cs[]; };

layout(std430) readonly buffer type_6_block_2Compute { uint _group_0_binding_2_cs[]; };

layout(std430) readonly buffer type_7_block_3Compute { Light _group_0_binding_3_cs[]; };

layout(std430) readonly buffer type_7_block_4Compute { Light _group_0_binding_6_cs[]; };

layout(std430) readonly buffer type_8_block_5Compute { Point _group_0_binding_4_cs[]; };

layout(std430) readonly buffer type_6_block_6Compute { uint _group_0_binding_7_cs[]; };

vec3 sum = vec3(0.0);

layout(std430) buffer type_10_block_7Compute { vec4 _group_0_binding_5_cs[]; };


float blend(vec4 ramp, float d) {
    float rise = ((d * ramp.x) + ramp.y);
    float fall = (ramp.w - (d * ramp.z));
    return clamp(min(rise, fall), 0.0, 1.0);
}

Light light_at(uint i) {
    uint _e3 = _group_0_binding_0_cs.split;
    if ((i < _e3)) {
        Light _e7 = _group_0_binding_3_cs[i];
        return _e7;
    }
    uint _e11 = _group_0_binding_0_cs.split;
    Light _e14 = _group_0_binding_6_cs[(i - _e11)];
    return _e14;
}

vec3 contribution(Level level, Light light, vec3 x, vec3 n) {
    bool local = false;
    float cosine = 0.0;
    vec3 v_2 = (light.position - x);
    float d2_ = dot(v_2, v_2);
    if ((d2_ > level.inner2_)) {
        local = (d2_ <= level.outer2_);
    } else {
        local = false;
    }
    bool _e14 = local;
    if (!(_e14)) {
        return vec3(0.0);
    }
    float d_1 = sqrt(d2_);
    float _e21 = _group_0_binding_0_cs.h0_;
    float c_2 = max(d_1, _e21);
    if ((d_1 > 0.0)) {
        cosine = max((dot(n, v_2) / d_1), 0.0);
    }
    float _e33 = blend(level.ramp, d_1);
    float _e38 = cosine;
    return (light.intensity * ((_e33 * (1.0 / (c_2 * c_2))) * _e38));
}

void visit(uint i_1, Light light_1, vec3 term) {
    vec3 _e4 = sum;
    sum = (_e4 + term);
    return;
}

void visit_range(Level level_1, uint start, uint end, vec3 x_1, vec3 n_1) {
    uint k = 0u;
    k = start;
    bool loop_init = true;
    while(true) {
        if (!loop_init) {
            uint _e14 = k;
            k = (_e14 + 1u);
        }
        loop_init = false;
        uint _e6 = k;
        if ((_e6 < end)) {
        } else {
            break;
        }
        {
            uint _e9 = k;
            uint i_3 = (level_1.first_light + _e9);
            Light _e11 = light_at(i_3);
            vec3 _e12 = contribution(level_1, _e11, x_1, n_1);
            visit(i_3, _e11, _e12);
        }
    }
    return;
}

uint cell_start(Level level_2, uint i_2) {
    if ((level_2.bank == STARTS_SLOTS)) {
        uint _e7 = _group_0_binding_7_cs[i_2];
        return _e7;
    }
    uint _e10 = _group_0_binding_2_cs[i_2];
    return _e10;
}

uint spread3_(uint v) {
    uint x_2 = 0u;
    x_2 = (v & 1023u);
    uint _e4 = x_2;
    uint _e5 = x_2;
    x_2 = ((_e4 | (_e5 << 16u)) & 50331903u);
    uint _e11 = x_2;
    uint _e12 = x_2;
    x_2 = ((_e11 | (_e12 << 8u)) & 50393103u);
    uint _e18 = x_2;
    uint _e19 = x_2;
    x_2 = ((_e18 | (_e19 << 4u)) & 51130563u);
    uint _e25 = x_2;
    uint _e26 = x_2;
    x_2 = ((_e25 | (_e26 << 2u)) & 153391689u);
    uint _e32 = x_2;
    return _e32;
}

uint morton3_(uvec3 c) {
    uint _e2 = spread3_(c.x);
    uint _e4 = spread3_(c.y);
    uint _e9 = spread3_(c.z);
    return ((_e2 | (_e4 << 1u)) | (_e9 << 2u));
}

void walk_level(Level level_3, vec3 x_3, vec3 n_2) {
    bool local_1 = false;
    uint z = 0u;
    uint y = 0u;
    uint c_1 = 0u;
    if ((level_3.dims.x == 0u)) {
        visit_range(level_3, 0u, level_3.light_count, x_3, n_2);
        return;
    }
    float reach = (sqrt(level_3.outer2_) + level_3.margin);
    vec3 lo = floor((((x_3 - vec3(reach)) - level_3.origin) / vec3(level_3.cell)));
    vec3 hi = floor((((x_3 + vec3(reach)) - level_3.origin) / vec3(level_3.cell)));
    vec3 top = vec3((level_3.dims - uvec3(1u)));
    if (!(any(lessThan(hi, vec3(0.0))))) {
        local_1 = any(greaterThan(lo, top));
    } else {
        local_1 = true;
    }
    bool _e44 = local_1;
    if (_e44) {
        return;
    }
    uvec3 a = uvec3(max(lo, vec3(0.0)));
    uvec3 b = uvec3(min(hi, top));
    uint s = level_3.stride;
    z = a.z;
    bool loop_init_1 = true;
    while(true) {
        if (!loop_init_1) {
            uint _e143 = z;
            z = (_e143 + 1u);
        }
        loop_init_1 = false;
        uint _e54 = z;
        if ((_e54 <= b.z)) {
        } else {
            break;
        }
        {
            y = a.y;
            bool loop_init_2 = true;
            while(true) {
                if (!loop_init_2) {
                    uint _e140 = y;
                    y = (_e140 + 1u);
                }
                loop_init_2 = false;
                uint _e59 = y;
                if ((_e59 <= b.y)) {
                } else {
                    break;
                }
                {
                    if ((level_3.order == CELLS_ROWS)) {
                        uint _e65 = z;
                        uint _e69 = y;
                        uint row = (((_e65 * level_3.dims.y) + _e69) * level_3.dims.x);
                        uint _e79 = cell_start(level_3, (level_3.first_cell + (s * (row + a.x))));
                        uint _e87 = cell_start(level_3, (level_3.first_cell + (s * ((row + b.x) + 1u))));
                        visit_range(level_3, _e79, _e87, x_3, n_2);
                    } else {
                        c_1 = a.x;
                        bool loop_init_3 = true;
                        while(true) {
                            if (!loop_init_3) {
                                uint _e137 = c_1;
                                c_1 = (_e137 + 1u);
                            }
                            loop_init_3 = false;
                            uint _e90 = c_1;
                            if ((_e90 <= b.x)) {
                            } else {
                                break;
                            }
                            {
                                uint _e94 = c_1;
                                uint _e95 = y;
                                uint _e96 = z;
                                vec3 low = ((level_3.origin + (vec3(uvec3(_e94, _e95, _e96)) * level_3.cell)) - vec3(level_3.margin));
                                vec3 high = (low + vec3((level_3.cell + (2.0 * level_3.margin))));
                                vec3 out_ = max(max((low - x_3), (x_3 - high)), vec3(0.0));
                                if ((dot(out_, out_) > level_3.outer2_)) {
                                    continue;
                                }
                                uint _e121 = c_1;
                                uint _e122 = y;
                                uint _e123 = z;
                                uint _e125 = morton3_(uvec3(_e121, _e122, _e123));
                                uint _e129 = cell_start(level_3, (level_3.first_cell + (s * _e125)));
                                uint _e135 = cell_start(level_3, (level_3.first_cell + (s * (_e125 + 1u))));
                                visit_range(level_3, _e129, _e135, x_3, n_2);
                            }
                        }
                    }
                }
            }
        }
    }
    return;
}

void walk(vec3 x_4, vec3 n_3) {
    uint l = 0u;
    bool loop_init_4 = true;
    while(true) {
        if (!loop_init_4) {
            uint _e14 = l;
            l = (_e14 + 1u);
        }
        loop_init_4 = false;
        uint _e4 = l;
        uint _e7 = _group_0_binding_0_cs.levels;
        if ((_e4 < _e7)) {
        } else {
            break;
        }
        {
            uint _e10 = l;
            Level _e12 = _group_0_binding_1_cs[_e10];
            walk_level(_e12, x_4, n_3);
        }
    }
    return;
}

uint point_index(uvec3 id_1, uvec3 groups_1) {
    return (id_1.x + ((id_1.y * groups_1.x) * WORKGROUP));
}

uint compact3_(uint v_1) {
    uint x_5 = 0u;
    x_5 = (v_1 & 153391689u);
    uint _e4 = x_5;
    uint _e5 = x_5;
    x_5 = ((_e4 | (_e5 >> 2u)) & 51130563u);
    uint _e11 = x_5;
    uint _e12 = x_5;
    x_5 = ((_e11 | (_e12 >> 4u)) & 50393103u);
    uint _e18 = x_5;
    uint _e19 = x_5;
    x_5 = ((_e18 | (_e19 >> 8u)) & 50331903u);
    uint _e25 = x_5;
    uint _e26 = x_5;
    x_5 = ((_e25 | (_e26 >> 16u)) & 1023u);
    uint _e32 = x_5;
    return _e32;
}

uvec3 demorton3_(uint m) {
    uint _e1 = compact3_(m);
    uint _e4 = compact3_((m >> 1u));
    uint _e7 = compact3_((m >> 2u));
    return uvec3(_e1, _e4, _e7);
}

void main() {
    uvec3 id = gl_GlobalInvocationID;
    uvec3 groups = gl_NumWorkGroups;
    uint _e2 = point_index(id, groups);
    uint _e5 = _group_0_binding_0_cs.points;
    if ((_e2 >= _e5)) {
        return;
    }
    Point p = _group_0_binding_4_cs[_e2];
    sum = vec3(0.0);
    walk(p.position, p.normal);
    vec3 _e18 = sum;
    _group_0_binding_5_cs[_e2] = vec4(((_e18 * p.albedo) * INV_PI), 0.0);
    return;
}

