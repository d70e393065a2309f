#!/usr/bin/env python3
"""lgh's light model against its path tracer on a uniform ball: single scattering ring by ring.

The ball: a sphere of radius 10 voxels in a 32³ grid over [-1, 1]³ (`--cells`: the radius
scales with it, so the ball's size and the optical depths through it stay), one density (τ a
voxel, times the medium's --density-scale 4) and one temperature (1,500 K); with `--edge sharp`
the temperature ends with the smoke, with `--edge wide` it reaches 30% of the radius beyond it
(the smoke's edge then has uniform emission on both sides). Seen from −Y at 64², albedo 0.7:

- lgh's model: `--backend brute --lighting-cache none --step 0.25` (every voxel light, exact
  shadows, a fine camera step), `--scatter-depth 0`, less the same at `--albedo 0`;
- the reference: `--backend pathtrace --scatter-depth 0` (`--spp`, 4,096 paths) less its
  `--albedo 0` image (a quarter of the paths), rendered once into the work folder and reused.

Prints one JSON line for each τ: the emission's ratio, single scattering's ratio over the image
(luminance, and red / green / blue), and in rings of pixels from the ball's centre each ring's
ratio and its share of the reference's single scattering (the ball's edge is 13.2 pixels out;
at 32³ the smoke's interpolated fringe reaches 14.5; the 14–16 ring holds under 1% of the
light with the sharp edge, up to 4% with the wide).
docs/cycles.md ("The lighting cache's level 0 in dense smoke") reads it.

    target/py313/bin/python tools/near_field/ball.py [--edge sharp|wide] [--cells 32] \\
        [--taus 0.5,1,2] [--tag T -- LGH FLAGS ...]   # extra flags for the model's renders

Needs numpy and OpenEXR (tools/cycles/compare.py's) and Debian's python3-openvdb (the VDB is
written by tools/cycles/write_vdb.py with /usr/bin/python3); the environment passes through to
`lgh`.
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "cycles"))
from compare import luminance, read_exr, write_volume  # noqa: E402

SIZE = 64
CAMERA = "0,-4.17,0,0,0,0,40"  # the ball's edge 13.2 pixels from the centre
RINGS = [(0, 4), (4, 8), (8, 12), (12, 14), (14, 16)]


def write_ball(work, tau, edge, cells):
    """The ball's VDB for `tau` optical depths a voxel (at --density-scale 4), on `cells`³."""
    radius = 10 * cells / 32
    prefix = os.path.join(work, f"ball{cells}_{edge}_{tau}")
    if os.path.exists(prefix + ".vdb"):
        return prefix + ".vdb"
    h = 2.0 / cells
    i = np.arange(cells) - (cells - 1) / 2
    # Indexed (z, y, x): x fastest, as write_volume writes it.
    z, y, x = np.meshgrid(i, i, i, indexing="ij")
    r = np.sqrt(x * x + y * y + z * z)
    hot = radius * (1.3 if edge == "wide" else 1.0)
    grids = {"density": (r <= radius) * (tau / (4.0 * h)), "temperature": (r <= hot) * 1.5}
    return write_volume(prefix, [cells] * 3, h, [-(cells - 1) / 2 * h] * 3, grids)


def render(lgh, vdb, out, flags, reuse=False):
    """`lgh explosion` of the ball into `out` (kept where `reuse` and it exists)."""
    if reuse and os.path.exists(out):
        return
    cmd = [lgh, "explosion", "--vdb", vdb, "--camera", CAMERA, "--width", str(SIZE),
           "--height", str(SIZE), "--density-scale", "4", "--temperature-scale", "1000",
           "--no-domain-offset", "--quiet", "--out", out] + flags
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"ball.py: {' '.join(cmd)} failed: {done.stderr.strip()[-500:]}")


def ratio(got, ref):
    """`got`'s sum over `ref`'s, rounded."""
    return round(float(got.sum() / ref.sum()), 4)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--work", default="target/ball")
    p.add_argument("--lgh", default="target/release/lgh")
    p.add_argument("--edge", choices=["sharp", "wide"], default="sharp")
    p.add_argument("--taus", default="0.5,1,2")
    p.add_argument("--tag", default="model")
    p.add_argument("--spp", type=int, default=4096)
    p.add_argument("--cells", type=int, default=32, help="voxels a side (the radius scales)")
    p.add_argument("flags", nargs="*", help="extra flags for the model's renders (after --)")
    a = p.parse_args()
    if a.cells < 8 or a.spp < 1:
        sys.exit("ball.py: --cells must be at least 8 and --spp at least 1")
    os.makedirs(a.work, exist_ok=True)
    model = ["--backend", "brute", "--lighting-cache", "none", "--step", "0.25"] + a.flags
    yy, xx = np.mgrid[0:SIZE, 0:SIZE]
    ring = np.hypot(xx - (SIZE - 1) / 2, yy - (SIZE - 1) / 2)
    for tau in a.taus.split(","):
        vdb = write_ball(a.work, float(tau), a.edge, a.cells)
        base = os.path.join(a.work, f"{a.cells}_{a.edge}_{tau}")
        # The references' files name their paths, so another --spp renders them anew.
        spp = {"pt": a.spp, "pt_e": max(a.spp // 4, 1)}
        out = {"pt": f"{base}_pt{spp['pt']}.exr", "pt_e": f"{base}_pte{spp['pt_e']}.exr",
               "model": f"{base}_{a.tag}.exr", "model_e": f"{base}_{a.tag}_e.exr"}
        render(a.lgh, vdb, out["pt"], ["--albedo", "0.7", "--scatter-depth", "0", "--backend",
                                       "pathtrace", "--spp", str(spp["pt"])], reuse=True)
        render(a.lgh, vdb, out["pt_e"], ["--albedo", "0", "--backend", "pathtrace", "--spp",
                                         str(spp["pt_e"])], reuse=True)
        render(a.lgh, vdb, out["model"], ["--albedo", "0.7", "--scatter-depth", "0"] + model)
        render(a.lgh, vdb, out["model_e"], ["--albedo", "0"] + model)
        rgb = {k: read_exr(path) for k, path in out.items()}
        ref_rgb, got_rgb = rgb["pt"] - rgb["pt_e"], rgb["model"] - rgb["model_e"]
        ref, got = luminance(ref_rgb), luminance(got_rgb)
        rings = {}
        for lo, hi in RINGS:
            inside = (ring >= lo) & (ring < hi)
            if ref[inside].sum() > 0:
                # The ring's ratio, and its share of the reference's single scattering.
                rings[f"{lo}-{hi}"] = [ratio(got[inside], ref[inside]), ratio(ref[inside], ref)]
        print(json.dumps({"edge": a.edge, "cells": a.cells, "tau": float(tau), "tag": a.tag,
                          "emission": ratio(luminance(rgb["model_e"]), luminance(rgb["pt_e"])),
                          "single": ratio(got, ref),
                          "single_rgb": [ratio(got_rgb[..., k], ref_rgb[..., k])
                                         for k in range(3)],
                          "rings": rings}))


if __name__ == "__main__":
    main()
