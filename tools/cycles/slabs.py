"""Uniform slabs at one temperature each, rendered by Blender Cycles and by `lgh explosion`: the
colour of Blender's blackbody emission channel by channel (issue 54), the measurements that
`lgh-volume/tests/blender_colour.rs` holds lgh to.

The slab: 48³ voxels over [-1, 1]³ (voxel centres at the box's faces), density 0.25 (times
--density-scale 4: σ_t = 1), temperature 1 (times --temperature-scale T kelvin), albedo 0 — so
emission and absorption alone, nothing scattered — seen by the comparison's camera (from
(0, -4, 0), 40°) at 16×16; the colour is the mean of the central 4×4 pixels.

    python3 tools/cycles/slabs.py --work slabs                      # Blender 3.4.1 (`blender`)
    python3 tools/cycles/slabs.py --work slabs-52 --bpy python3.13  # 5.2.3 (PyPI's bpy)
    python3 tools/cycles/slabs.py --work slabs --lgh target/release/lgh   # lgh's too
    python3 tools/cycles/slabs.py --pattern alternating --temperatures 1000 ...   # T, 3T layers

Prints one JSON object: the Blender version, and for each temperature Cycles' centre colour
(and lgh's in both emission interpolations, with --lgh) and the spread of Cycles' 16 centre pixels (its noise).
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from compare import read_exr, run_cpu, write_volume  # noqa: E402

TEMPERATURES = [1000, 1250, 1500, 1750, 2000, 3000, 6500]
N = 48
SIZE = 16
CAMERA = "0,-4,0,0,0,0,40"


def write_slab(work, pattern):
    """The slab as export_grids writes a volume (raw f32 grids and a JSON), then a VDB.
    `uniform`: temperature 1 everywhere; `alternating`: 1 and 3 in alternate layers across the
    camera's view (lgh's z, Blender's −y), so that each ray crosses both — where the emission of
    the interpolated temperature (`j(T(x))`, Cycles 3.x as lgh's default models it) and the
    interpolated emission of the voxels (`Σ w_i j(T_i)`, `--emission-interpolation attributes`)
    differ most (by about 1.5×: j is steep in T)."""
    prefix = os.path.join(work, f"slab-{pattern}")
    if os.path.exists(prefix + ".vdb"):
        return prefix + ".vdb"
    h = 2.0 / (N - 1)
    # A checkerboard of ±10⁻⁶ (relative) on each value: OpenVDB stores a constant block as a
    # tile, not voxels, and Cycles draws no tiles (the slab came out black). 10⁻⁶ of T is
    # 4·10⁻⁶ of the emission, far below what is measured here.
    i, j, k = np.indices((N, N, N))
    checker = (1.0 + 1e-6 * (-1.0) ** (i + j + k)).ravel()
    # The file is x fastest, then y, then z: np.indices gives (z, y, x).
    layers = (1.0 + 2.0 * (i % 2)).ravel() if pattern == "alternating" else 1.0
    grids = {"density": 0.25 * checker, "temperature": layers * checker}
    return write_volume(prefix, [N, N, N], h, [-1.0, -1.0, -1.0], grids)


def centre(path):
    img = read_exr(path)
    c = SIZE // 2
    block = img[c - 2 : c + 2, c - 2 : c + 2].reshape(-1, 3)
    return block.mean(axis=0), float(np.abs(block - block.mean(axis=0)).max())


def cycles(a, vdb, kelvin):
    out = os.path.join(a.work, f"cycles_{a.pattern}_{kelvin}K.exr")
    script = os.path.join(HERE, "render_cycles.py")
    cmd = [a.bpy, script, "--"] if a.bpy else [a.blender, "-b", "--factory-startup",
                                                "--python", script, "--"]
    cmd += ["--vdb", vdb, "--out", out, "--spp", str(a.spp), "--width", str(SIZE),
            "--height", str(SIZE), "--threads", str(a.threads), "--camera", CAMERA,
            "--density-scale", "4", "--albedo", "0", "--temperature-scale", str(kelvin),
            "--bounces", "8"]
    # No half-voxel shift for Blender 3.x: it moves a uniform slab, not its centre's colour.
    text, _, _ = run_cpu(cmd)
    version = json.loads([l for l in text.splitlines() if l.startswith("CYCLES ")][-1][7:])
    return out, version["version"]


def lgh(a, vdb, kelvin, interpolation):
    out = os.path.join(a.work, f"lgh_{a.pattern}_{interpolation}_{kelvin}K.exr")
    run_cpu([a.lgh, "explosion", "--vdb", vdb, "--out", out, "--camera", CAMERA, "--width",
             str(SIZE), "--height", str(SIZE), "--density-scale", "4", "--albedo", "0",
             "--temperature-scale", str(kelvin), "--emission-interpolation", interpolation,
             "--no-domain-offset", "--quiet"])
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--work", default="slabs")
    p.add_argument("--blender", default="blender")
    p.add_argument("--bpy", default=None, help="a Python with PyPI's bpy, instead of blender")
    p.add_argument("--lgh", default=None, help="lgh's binary, to render the slabs with it too")
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--pattern", choices=["uniform", "alternating"], default="uniform")
    p.add_argument("--temperatures", default=",".join(map(str, TEMPERATURES)))
    a = p.parse_args()
    os.makedirs(a.work, exist_ok=True)
    vdb = write_slab(a.work, a.pattern)
    result = {"slab": {"voxels": N, "density": 0.25, "density_scale": 4, "albedo": 0,
                       "pattern": a.pattern, "camera": CAMERA, "size": SIZE, "centre": "4x4"},
              "spp": a.spp, "slabs": []}
    for kelvin in [int(t) for t in a.temperatures.split(",")]:
        out, version = cycles(a, vdb, kelvin)
        colour, spread = centre(out)
        result["blender"] = version
        row = {"kelvin": kelvin, "cycles": colour.tolist(), "cycles_spread": spread}
        if a.lgh:
            for interpolation in ["temperature", "attributes"]:
                image = lgh(a, vdb, kelvin, interpolation)
                row[f"lgh_{interpolation}"] = centre(image)[0].tolist()
        result["slabs"].append(row)
        print(f"{kelvin} K: {row}", file=sys.stderr, flush=True)
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
