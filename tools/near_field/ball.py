#!/usr/bin/env python3
"""lgh's light model against its path tracer on a uniform ball: single scattering ring by ring.

The ball: a sphere of radius 10 voxels in a 32³ grid over [-1, 1]³ (`--cells`: the radius scales), one density (τ a
voxel, times the medium's --density-scale 4) and one temperature (1,500 K); with `--edge
sharp` the temperature ends with the smoke, with `--edge wide` it reaches 3 voxels beyond it (the
smoke's edge then has uniform emission on both sides). Seen from −Y at 64², albedo 0.7:

- lgh's model: `--backend brute --lighting-cache none --step 0.25` (every voxel light, exact
  shadows, a fine camera step), `--scatter-depth 0`, less the same at `--albedo 0`;
- the reference: `--backend pathtrace --scatter-depth 0` (4,096 paths) less its `--albedo 0`
  image (1,024 paths), rendered once into the work folder and reused.

Prints, for each τ, the emission's ratio, single scattering's ratio over the image and in rings
of pixels from the ball's centre, each with its share of the reference's single scattering (the
ball's edge is 13.2 pixels out; the smoke's interpolated fringe reaches 14.5). docs/cycles.md ("The lighting cache's level 0 in dense
smoke") reads it: inside 3–5% dark, the fringe 1.5–1.7× bright with the sharp edge.

    target/py313/bin/python tools/near_field/ball.py [--edge sharp|wide] [--taus 0.5,1,2] \
        [--tag T -- LGH FLAGS ...]      # LGH FLAGS: extra flags for the model's renders

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
from compare import luminance, read_exr  # noqa: E402

SIZE = 64
CAMERA = "0,-4.17,0,0,0,0,40"  # the ball's edge 13.2 pixels from the centre
RINGS = [(0, 4), (4, 8), (8, 12), (12, 14), (14, 16)]


def write_ball(work, tau, edge, N=32, RADIUS=10):
    """The ball's VDB for `tau` optical depths a voxel (at --density-scale 4)."""
    prefix = os.path.join(work, f"ball{N}_{edge}_{tau}")
    if os.path.exists(prefix + ".vdb"):
        return prefix + ".vdb"
    h = 2.0 / N
    i = np.arange(N) - (N - 1) / 2
    x, y, z = np.meshgrid(i, i, i, indexing="ij")
    r = np.sqrt(x * x + y * y + z * z)
    density = (r <= RADIUS) * (tau / (4.0 * h))
    hot = RADIUS + (3 * RADIUS / 10 if edge == "wide" else 0)
    temperature = (r <= hot) * 1.5
    grids = {"density": density, "temperature": temperature}
    for name, g in grids.items():
        # x fastest, as write_vdb.py reads it.
        g.transpose(2, 1, 0).astype("<f4").tofile(f"{prefix}.{name}.f32")
    meta = {"dims": [N, N, N], "voxel_size": h, "origin": [-(N - 1) / 2 * h] * 3, "up": "y",
            "grids": list(grids)}
    with open(prefix + ".json", "w") as f:
        json.dump(meta, f)
    subprocess.run(["/usr/bin/python3", os.path.join(HERE, "..", "cycles", "write_vdb.py"),
                    prefix], check=True, capture_output=True)
    return prefix + ".vdb"


def render(lgh, vdb, out, flags):
    if out.endswith("_ref.exr") and os.path.exists(out):
        return
    cmd = [lgh, "explosion", "--vdb", vdb, "--camera", CAMERA, "--width", str(SIZE),
           "--height", str(SIZE), "--density-scale", "4", "--temperature-scale", "1000",
           "--no-domain-offset", "--quiet", "--out", out] + flags
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"ball.py: {' '.join(cmd)} failed: {done.stderr.strip()[-500:]}")


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
    os.makedirs(a.work, exist_ok=True)
    model = ["--backend", "brute", "--lighting-cache", "none", "--step", "0.25"] + a.flags
    for tau in a.taus.split(","):
        vdb = write_ball(a.work, float(tau), a.edge, a.cells, 10 * a.cells // 32)
        base = os.path.join(a.work, f"{a.cells}_{a.edge}_{tau}")
        render(a.lgh, vdb, f"{base}_pt_ref.exr", ["--albedo", "0.7", "--scatter-depth", "0",
                                                 "--backend", "pathtrace", "--spp", str(a.spp)])
        render(a.lgh, vdb, f"{base}_pte_ref.exr", ["--albedo", "0", "--backend", "pathtrace",
                                                  "--spp", str(max(a.spp // 4, 1))])
        render(a.lgh, vdb, f"{base}_{a.tag}.exr", ["--albedo", "0.7", "--scatter-depth", "0"]
               + model)
        render(a.lgh, vdb, f"{base}_{a.tag}_e.exr", ["--albedo", "0"] + model)
        lum = {k: luminance(read_exr(f"{base}_{k}.exr"))
               for k in ("pt_ref", "pte_ref", a.tag, f"{a.tag}_e")}
        ref = lum["pt_ref"] - lum["pte_ref"]
        got = lum[a.tag] - lum[f"{a.tag}_e"]
        yy, xx = np.mgrid[0:SIZE, 0:SIZE]
        c = (SIZE - 1) / 2
        ring = np.hypot(xx - c, yy - c)
        rings = {}
        for lo, hi in RINGS:
            inside = (ring >= lo) & (ring < hi)
            if ref[inside].sum() > 0:
                # The ring's ratio, and its share of the reference's single scattering.
                rings[f"{lo}-{hi}"] = [round(float(got[inside].sum() / ref[inside].sum()), 4),
                                       round(float(ref[inside].sum() / ref.sum()), 4)]
        print(json.dumps({"edge": a.edge, "tau": float(tau), "tag": a.tag,
                          "emission": round(float(lum[f"{a.tag}_e"].sum()
                                                   / lum["pte_ref"].sum()), 4),
                          "single": round(float(got.sum() / ref.sum()), 4), "rings": rings}))


if __name__ == "__main__":
    main()
