// A shell of 100,000 glowing embers over a ground plane, lit through lgh's C API: the hierarchy
// built once, rebuilt where the embers move (every fourth frame) and updated in place where only
// their intensities flicker (the other frames), the ground shaded with a Lambertian callback.
// Writes frame_NNN.pfm (linear RGB floats) and frame_NNN.ppm (8-bit, for a quick look).
//
//   make && ./swarm [--lights 100000] [--frames 8] [--size 256] [--out .]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "lgh.h"
#include "swarm.h"

// What the shading callback needs besides the light: the shaded point and the fall-off clamp.
struct Shading {
    float x[3];
    float h0;
};

// The ground's Lambertian response to one light, unshadowed: f · cos θ · I / max(d, h0)².
static void shade_ground(const LghLight *light, void *user, float *out) {
    const Shading *s = static_cast<const Shading *>(user);
    float d = light->distance;
    float cosine = (light->position[1] - s->x[1]) / d;  // the normal is +y
    if (!(cosine > 0.0f)) {
        out[0] = out[1] = out[2] = 0.0f;
        return;
    }
    float dd = d > s->h0 ? d : s->h0;
    float k = SWARM_BRDF * cosine * (1.0f / (dd * dd));
    for (int c = 0; c < 3; c++) out[c] = light->intensity[c] * k;
}

static void check(LghStatus status, const char *what) {
    if (status != LGH_STATUS_OK) {
        std::fprintf(stderr, "swarm: %s failed (%d): %s\n", what, (int)status, lgh_last_error());
        std::exit(1);
    }
}

static bool write_images(const std::string &stem, int size, const std::vector<float> &rgb) {
    FILE *pfm = std::fopen((stem + ".pfm").c_str(), "wb");
    FILE *ppm = std::fopen((stem + ".ppm").c_str(), "wb");
    if (!pfm || !ppm) return false;
    // PFM: rows from the first pixel row on, little-endian floats (the -1 scale).
    std::fprintf(pfm, "PF\n%d %d\n-1.0\n", size, size);
    std::fwrite(rgb.data(), sizeof(float), rgb.size(), pfm);
    std::fprintf(ppm, "P6\n%d %d\n255\n", size, size);
    for (float v : rgb) {
        float t = v / (1.0f + v);  // Reinhard, then sRGB-ish gamma
        unsigned char b = (unsigned char)(255.0f * std::pow(t, 1.0f / 2.2f) + 0.5f);
        std::fputc(b, ppm);
    }
    bool ok = std::fclose(pfm) == 0;
    return std::fclose(ppm) == 0 && ok;
}

int main(int argc, char **argv) {
    size_t count = 100000;
    int frames = 8, size = 256;
    std::string out = ".";
    for (int a = 1; a + 1 < argc; a += 2) {
        if (!std::strcmp(argv[a], "--lights")) count = std::strtoul(argv[a + 1], nullptr, 10);
        else if (!std::strcmp(argv[a], "--frames")) frames = std::atoi(argv[a + 1]);
        else if (!std::strcmp(argv[a], "--size")) size = std::atoi(argv[a + 1]);
        else if (!std::strcmp(argv[a], "--out")) out = argv[a + 1];
        else {
            std::fprintf(stderr, "swarm: unknown option %s\n", argv[a]);
            return 2;
        }
    }
    if (size < 1 || size > 8192 || frames < 1) {
        std::fprintf(stderr, "swarm: --size must be 1 to 8192 and --frames at least 1\n");
        return 2;
    }

    std::vector<float> positions(3 * count), intensities(3 * count);
    LghSettings settings;
    check(lgh_settings_default(&settings), "lgh_settings_default");
    LghHierarchy *hierarchy = nullptr;
    std::vector<float> image(3 * (size_t)size * size);
    for (int frame = 0; frame < frames; frame++) {
        int moved = frame - frame % 4;  // the embers move every fourth frame, flicker every frame
        for (size_t i = 0; i < count; i++) {
            float ignored[3];
            swarm_light(i, moved, &positions[3 * i], ignored);
            swarm_light(i, frame, ignored, &intensities[3 * i]);
        }
        auto start = std::chrono::steady_clock::now();  // the library's work from here
        const char *how;
        if (!hierarchy) {
            check(lgh_hierarchy_create(positions.data(), intensities.data(), count, &settings,
                                       &hierarchy),
                  "lgh_hierarchy_create");
            how = "built";
        } else if (frame == moved) {
            check(lgh_hierarchy_rebuild(hierarchy, positions.data(), intensities.data(), count),
                  "lgh_hierarchy_rebuild");
            how = "rebuilt";
        } else {
            check(lgh_hierarchy_update_intensities(hierarchy, intensities.data(), count),
                  "lgh_hierarchy_update_intensities");
            how = "updated";
        }
        LghBlending *blending = nullptr;
        check(lgh_blending_create(hierarchy, 2.0f, &blending), "lgh_blending_create");
        LghInfo info;
        check(lgh_hierarchy_info(hierarchy, &info), "lgh_hierarchy_info");
        auto lit = std::chrono::steady_clock::now();
        Shading s;
        s.h0 = info.h0;
        uint64_t lights = 0;
        for (int py = 0; py < size; py++) {
            for (int px = 0; px < size; px++) {
                swarm_ground_point(px, py, size, s.x);
                uint32_t n = 0;
                float *rgb = &image[3 * ((size_t)py * size + px)];
                check(lgh_sum(hierarchy, blending, s.x, shade_ground, &s, rgb, &n), "lgh_sum");
                lights += n;
            }
        }
        auto done = std::chrono::steady_clock::now();
        lgh_blending_destroy(blending);
        char stem[64];
        std::snprintf(stem, sizeof stem, "/frame_%03d", frame);
        if (!write_images(out + stem, size, image)) {
            std::fprintf(stderr, "swarm: cannot write %s%s.pfm\n", out.c_str(), stem);
            return 1;
        }
        using ms = std::chrono::duration<double, std::milli>;
        std::printf("frame %d: %zu lights %s in %.1f ms, %dx%d shaded in %.1f ms (%.1f lights a pixel)\n",
                    frame, count, how, ms(lit - start).count(), size, size, ms(done - lit).count(),
                    (double)lights / ((double)size * size));
    }
    lgh_hierarchy_destroy(hierarchy);
    return 0;
}
