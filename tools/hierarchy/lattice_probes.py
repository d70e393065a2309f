#!/usr/bin/env python3
"""The hierarchy's own error at a given α on the simplest cloud there is: a uniform cubic lattice
of equal point lights, unshadowed, against brute force — `lgh.Hierarchy.probe` (eq. 3's sum with
the point fall-off `1/max(d, h0)²`, the Python package lgh-py) against the same sum over every
light, at random points inside the lattice, across its edge and outside it. docs/cycles.md ("The
hierarchy's α-2 error, taken apart") quotes it:

    target/py313/bin/python tools/hierarchy/lattice_probes.py [--n 32] [--alpha 2,4,8] [--max-level L] [--coarse-spread centre,averaged]

Prints one JSON line per region and α: the ratio of the summed light to brute force's, the mean,
minimum and maximum of the per-point ratios, and their RMS distance from 1. Needs numpy and lgh
(`.ci/run` installs both into target/py313); the random points are drawn with a fixed seed, so
the figures repeat.
"""
import argparse
import json
import random
import sys

try:
    import numpy as np
    import lgh
except ImportError as e:
    sys.exit(f"lattice_probes.py: {e.name} is missing: run it with target/py313/bin/python "
             "(`.ci/run` installs numpy and lgh there)")


def brute_force(lights, points, h0):
    """`Σ_j 1/max(d_j, h0)²` at each point over every light (unit intensities), in float64."""
    out = np.empty(len(points))
    for s in range(0, len(points), 256):
        d2 = ((points[s:s + 256, None, :] - lights[None, :, :]) ** 2).sum(axis=2)
        out[s:s + 256] = (1.0 / np.maximum(d2, h0 * h0)).sum(axis=1)
    return out


def regions(n, rng):
    """Probe points: deep inside the lattice, across its whole box and just beyond, and 3 to 10
    spacings outside one face."""
    inner = [tuple(rng.uniform(n / 4, 3 * n / 4 - 1) for _ in range(3)) for _ in range(2000)]
    across = [tuple(rng.uniform(-2, n + 1) for _ in range(3)) for _ in range(4000)]
    outside = [(rng.uniform(-10, -3), rng.uniform(0, n - 1), rng.uniform(0, n - 1)) for _ in range(1000)]
    return {"inside": inner, "across": across, "outside": outside}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                epilog="Usage as docs/cycles.md quotes it: " + __doc__.split("\n\n")[1].strip())
    p.add_argument("--n", type=int, default=32, help="lights a side of the lattice (spacing 1)")
    p.add_argument("--alpha", default="2,4", help="the α to measure, comma-separated")
    p.add_argument("--max-level", type=int, default=None,
                   help="the hierarchy's top level (default: lgh's; lower keeps only the finest "
                        "levels' transitions)")
    p.add_argument("--coarse-spread", default="centre",
                   help="how coarse lights are weighted, comma-separated: centre (eq. 3 as printed) "
                        "and/or averaged (over each light's spread, lgh-core's blend::spread)")
    a = p.parse_args()
    spreads = a.coarse_spread.split(",")
    if not all(s in ("centre", "averaged") for s in spreads):
        sys.exit(f"lattice_probes.py: --coarse-spread takes centre and/or averaged, not {a.coarse_spread!r}")
    if a.n < 4:
        sys.exit("lattice_probes.py: --n must be at least 4")
    try:
        alphas = [float(x) for x in a.alpha.split(",")]
    except ValueError:
        sys.exit(f"lattice_probes.py: --alpha wants numbers separated by commas, not {a.alpha!r}")
    if not all(0 < x < float("inf") for x in alphas):
        sys.exit(f"lattice_probes.py: every --alpha must be a finite number above 0: {a.alpha}")
    g = np.arange(a.n, dtype=np.float32)
    lights = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    ones = np.ones_like(lights)
    rng = random.Random(1)
    for name, points in regions(a.n, rng).items():
        points = np.asarray(points, dtype=np.float32)
        for alpha in alphas:
            for spread in spreads:
                # h1 = 2: the lattice's spacing is h0, the voxel size of an explosion's lights.
                try:
                    h = lgh.Hierarchy(lights, ones, alpha=alpha, h1=2.0, max_level=a.max_level)
                    h.coarse_spread = spread
                except ValueError as e:
                    sys.exit(f"lattice_probes.py: {e}")
                want = brute_force(lights.astype(np.float64), points.astype(np.float64), h.h0)
                got = h.probe(points)[:, 0].astype(np.float64)
                ratios = got / want
                print(json.dumps({
                    "region": name, "alpha": alpha, "coarse_spread": spread,
                    "max_level": a.max_level, "points": len(points),
                    "sum_ratio": round(float(got.sum() / want.sum()), 5),
                    "mean_ratio": round(float(ratios.mean()), 5),
                    "min_ratio": round(float(ratios.min()), 5), "max_ratio": round(float(ratios.max()), 5),
                    "rms": round(float(np.sqrt(((ratios - 1.0) ** 2).mean())), 5)}), flush=True)


if __name__ == "__main__":
    main()
