/* The example's scene, shared by swarm.cpp and (transcribed) lgh-capi/tests/example.rs: a shell
 * of glowing embers around an explosion's centre, expanding and flickering, over a ground plane.
 * Only IEEE-exact operations (+, -, *, /, sqrt, floor) so that C++ and Rust agree bit for bit. */
#ifndef SWARM_H
#define SWARM_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

/* SplitMix64: the lights' fixed random numbers. */
static inline uint64_t swarm_next(uint64_t *state) {
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* A float in [0, 1) from the top 24 bits: exact. */
static inline float swarm_unit(uint64_t *state) {
    return (float)(swarm_next(state) >> 40) * (1.0f / 16777216.0f);
}

/* A triangle wave in [0, 1] of period 1. */
static inline float swarm_wave(float t) {
    float f = t - floorf(t);
    return f < 0.5f ? 2.0f * f : 2.0f - 2.0f * f;
}

/* Light i of `count` at frame `frame`: position (3 floats) and RGB intensity (3 floats). The
 * shell's radius grows from 0.5 to 2.5 over 48 frames; each ember flickers at its own rate. */
static inline void swarm_light(size_t i, int frame, float *position, float *intensity) {
    uint64_t state = 0x5EED0000ull + (uint64_t)i;
    float d[3], len2;
    do {
        for (int a = 0; a < 3; a++) d[a] = 2.0f * swarm_unit(&state) - 1.0f;
        len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    } while (len2 > 1.0f || len2 < 1e-4f);
    float len = sqrtf(len2);
    float t = (float)frame / 48.0f;
    float radius = (0.5f + 2.0f * t) * (0.85f + 0.3f * swarm_unit(&state));
    position[0] = d[0] / len * radius;
    position[1] = 1.5f + d[1] / len * radius;
    position[2] = d[2] / len * radius;
    float rate = 0.5f + 2.0f * swarm_unit(&state);
    float phase = swarm_unit(&state);
    float glow = (0.25f + 0.75f * swarm_wave(rate * t + phase)) * (1.0f - 0.7f * t);
    /* A hot core fading to red at the rim of each ember's range: W/sr. */
    float heat = swarm_unit(&state);
    intensity[0] = glow * 0.004f;
    intensity[1] = glow * 0.004f * (0.35f + 0.5f * heat);
    intensity[2] = glow * 0.004f * (0.05f + 0.3f * heat * heat);
}

/* The ground: pixel (px, py) of a `size` × `size` image sees the point (x, 0, z) of the square
 * [-4, 4]², normal +y, Lambertian with albedo 0.6 (its BRDF 0.6/π). */
static inline void swarm_ground_point(int px, int py, int size, float *x) {
    x[0] = -4.0f + 8.0f * ((float)px + 0.5f) / (float)size;
    x[1] = 0.0f;
    x[2] = -4.0f + 8.0f * ((float)py + 0.5f) / (float)size;
}

#define SWARM_BRDF (0.6f / 3.14159265358979f)

#endif
