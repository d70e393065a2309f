#include <stdio.h>
#include "lgh.h"

/* Each light's blended intensity over max(d, h0)²: the unshadowed light, no BRDF. */
static void shade(const LghLight *l, void *user, float *out) {
    float h0 = *(const float *)user, d = l->distance > h0 ? l->distance : h0;
    for (int c = 0; c < 3; c++) out[c] = l->intensity[c] / (d * d);
}

int main(void) {
    float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, rgb[] = {1, 1, 1, 2, 0, 0, 0, 0, 3};
    float x[] = {0.5f, 0.5f, 2.0f}, out[3];
    LghHierarchy *h; LghBlending *b; LghInfo info;
    if (lgh_hierarchy_create(pos, rgb, 3, NULL, &h) || lgh_blending_create(h, 2.0f, &b) ||
        lgh_hierarchy_info(h, &info) || lgh_sum(h, b, x, shade, &info.h0, out, NULL)) {
        fprintf(stderr, "lgh: %s\n", lgh_last_error());
        return 1;
    }
    printf("%.9g %.9g %.9g\n", out[0], out[1], out[2]);
    lgh_blending_destroy(b);
    lgh_hierarchy_destroy(h);
    return 0;
}
