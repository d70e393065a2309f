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
};
struct Params {
    uint levels;
    uint points;
    float h0_;
    uint split;
};
const uint WORKGROUP = 64u;
const float INV_PI = 0.31830987;

layout(std140) uniform Params_block_0Compute { Params _group_0_binding_0_cs; };

layout(std430) readonly buffer type_5_block_1Compute { Level _group_0_binding_1_cs[]; };

layout(std430) readonly buffer type_6_block_2Compute { uint _group_0_binding_2_cs[]; };

layout(std430) readonly buffer type_7_block_3Compute { Light _group_0_binding_3_cs[]; };

layout(std430) readonly buffer type_7_block_4Compute { Light _group_0_binding_6_cs[]; };

layout(std430) readonly buffer type_8_block_5Compute { Point _group_0_binding_4_cs[]; };

layout(std430) buffer type_9_block_6Compute { vec4 _group_0_binding_5_cs[]; };


float blend(vec4 ramp, float d) {
    float rise = ((d * ramp.x) + ramp.y);
    float fall = (ramp.w - (d * ramp.z));
    return clamp(min(rise, fall), 0.0, 1.0);
}

vec3 contribution(Level level, uint k, vec3 x, vec3 n) {
    Light light = Light(vec3(0.0), vec3(0.0));
    bool local = false;
    float cosine = 0.0;
    uint i = (level.first_light + k);
    uint _e9 = _group_0_binding_0_cs.split;
    if ((i < _e9)) {
        Light _e13 = _group_0_binding_3_cs[i];
        light = _e13;
    } else {
        uint _e17 = _group_0_binding_0_cs.split;
        Light _e20 = _group_0_binding_6_cs[(i - _e17)];
        light = _e20;
    }
    vec3 _e22 = light.position;
    vec3 v = (_e22 - x);
    float d2_ = dot(v, v);
    if ((d2_ > level.inner2_)) {
        local = (d2_ <= level.outer2_);
    } else {
        local = false;
    }
    bool _e32 = local;
    if (!(_e32)) {
        return vec3(0.0);
    }
    float d_1 = sqrt(d2_);
    float _e39 = _group_0_binding_0_cs.h0_;
    float c = max(d_1, _e39);
    if ((d_1 > 0.0)) {
        cosine = max((dot(n, v) / d_1), 0.0);
    }
    vec3 _e50 = light.intensity;
    float _e52 = blend(level.ramp, d_1);
    float _e57 = cosine;
    return (_e50 * ((_e52 * (1.0 / (c * c))) * _e57));
}

vec3 level_sum(Level level_1, vec3 x_1, vec3 n_1) {
    vec3 sum_1 = vec3(0.0);
    uint k_1 = 0u;
    bool local_1 = false;
    uint z = 0u;
    uint y = 0u;
    uint k_2 = 0u;
    if ((level_1.dims.x == 0u)) {
        bool loop_init = true;
        while(true) {
            if (!loop_init) {
                uint _e20 = k_1;
                k_1 = (_e20 + 1u);
            }
            loop_init = false;
            uint _e12 = k_1;
            if ((_e12 < level_1.light_count)) {
            } else {
                break;
            }
            {
                vec3 _e15 = sum_1;
                uint _e16 = k_1;
                vec3 _e17 = contribution(level_1, _e16, x_1, n_1);
                sum_1 = (_e15 + _e17);
            }
        }
        vec3 _e22 = sum_1;
        return _e22;
    }
    float reach = sqrt(level_1.outer2_);
    vec3 lo = floor((((x_1 - vec3(reach)) - level_1.origin) / vec3(level_1.cell)));
    vec3 hi = floor((((x_1 + vec3(reach)) - level_1.origin) / vec3(level_1.cell)));
    vec3 top = vec3((level_1.dims - uvec3(1u)));
    if (!(any(lessThan(hi, vec3(0.0))))) {
        local_1 = any(greaterThan(lo, top));
    } else {
        local_1 = true;
    }
    bool _e56 = local_1;
    if (_e56) {
        vec3 _e57 = sum_1;
        return _e57;
    }
    uvec3 a = uvec3(max(lo, vec3(0.0)));
    uvec3 b = uvec3(min(hi, top));
    z = a.z;
    bool loop_init_1 = true;
    while(true) {
        if (!loop_init_1) {
            uint _e111 = z;
            z = (_e111 + 1u);
        }
        loop_init_1 = false;
        uint _e66 = z;
        if ((_e66 <= b.z)) {
        } else {
            break;
        }
        {
            y = a.y;
            bool loop_init_2 = true;
            while(true) {
                if (!loop_init_2) {
                    uint _e108 = y;
                    y = (_e108 + 1u);
                }
                loop_init_2 = false;
                uint _e71 = y;
                if ((_e71 <= b.y)) {
                } else {
                    break;
                }
                {
                    uint _e75 = z;
                    uint _e79 = y;
                    uint row = (level_1.first_cell + (((_e75 * level_1.dims.y) + _e79) * level_1.dims.x));
                    uint start = _group_0_binding_2_cs[(row + a.x)];
                    uint end = _group_0_binding_2_cs[((row + b.x) + 1u)];
                    k_2 = start;
                    bool loop_init_3 = true;
                    while(true) {
                        if (!loop_init_3) {
                            uint _e105 = k_2;
                            k_2 = (_e105 + 1u);
                        }
                        loop_init_3 = false;
                        uint _e98 = k_2;
                        if ((_e98 < end)) {
                        } else {
                            break;
                        }
                        {
                            vec3 _e100 = sum_1;
                            uint _e101 = k_2;
                            vec3 _e102 = contribution(level_1, _e101, x_1, n_1);
                            sum_1 = (_e100 + _e102);
                        }
                    }
                }
            }
        }
    }
    vec3 _e113 = sum_1;
    return _e113;
}

void main() {
    uvec3 id = gl_GlobalInvocationID;
    uvec3 groups = gl_NumWorkGroups;
    vec3 sum = vec3(0.0);
    uint l = 0u;
    uint i_1 = (id.x + ((id.y * groups.x) * WORKGROUP));
    uint _e11 = _group_0_binding_0_cs.points;
    if ((i_1 >= _e11)) {
        return;
    }
    Point p = _group_0_binding_4_cs[i_1];
    bool loop_init_4 = true;
    while(true) {
        if (!loop_init_4) {
            uint _e36 = l;
            l = (_e36 + 1u);
        }
        loop_init_4 = false;
        uint _e21 = l;
        uint _e24 = _group_0_binding_0_cs.levels;
        if ((_e21 < _e24)) {
        } else {
            break;
        }
        {
            vec3 _e26 = sum;
            uint _e28 = l;
            Level _e30 = _group_0_binding_1_cs[_e28];
            vec3 _e33 = level_sum(_e30, p.position, p.normal);
            sum = (_e26 + _e33);
        }
    }
    vec3 _e40 = sum;
    _group_0_binding_5_cs[i_1] = vec4(((_e40 * p.albedo) * INV_PI), 0.0);
    return;
}

