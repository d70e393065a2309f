#!/usr/bin/env python3
"""The hierarchy's own error at a given α on the simplest cloud there is: a uniform cubic lattice
of equal point lights, unshadowed, against brute force — `lgh probes` (eq. 3's sum with the
point fall-off `1/max(d, h0)²`) at random points inside the lattice, across its edge and outside
it. docs/cycles.md ("The hierarchy's α-2 error, taken apart") quotes it:

    python3 tools/hierarchy/lattice_probes.py [--lgh target/release/lgh] [--n 32] [--alpha 2,4,8]

Prints one JSON line per region and α: the ratio of the summed light to brute force's, the mean,
minimum and maximum of the per-point ratios, and their RMS distance from 1. Standard library only
(the point clouds are written as ASCII PLY, `lgh probes`' binary output read with `struct`); the
random points are drawn with a fixed seed, so the figures repeat.
"""
import argparse
import json
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile


def write_ply(path, points, rgb=None):
    """`points` (and, if given, an intensity each) as an ASCII PLY `lgh probes` reads."""
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\n" % len(points))
        f.write("property float x\nproperty float y\nproperty float z\n")
        if rgb is not None:
            f.write("property float r\nproperty float g\nproperty float b\n")
        f.write("end_header\n")
        for i, p in enumerate(points):
            extra = " %g %g %g" % rgb[i] if rgb is not None else ""
            f.write("%r %r %r%s\n" % (p[0], p[1], p[2], extra))


def read_red(path):
    """The `r` of each point of `lgh probes`' binary output (float properties, `r` among them,
    little-endian); exits with a message where the file is not that."""
    with open(path, "rb") as f:
        data = f.read()
    marker = b"end_header\n"
    if marker not in data:
        sys.exit(f"lattice_probes.py: {path}: not a PLY file")
    end = data.index(marker) + len(marker)
    lines = data[:end].decode(errors="replace").splitlines()
    props = [line.split() for line in lines if line.startswith("property")]
    vertex = [line.split() for line in lines if line.startswith("element vertex")]
    if ("format binary_little_endian 1.0" not in lines or not vertex
            or any(p[1] != "float" for p in props) or ["property", "float", "r"] not in props):
        sys.exit(f"lattice_probes.py: {path}: expected a little-endian binary PLY of floats with r")
    n, stride = int(vertex[0][2]), 4 * len(props)
    r = props.index(["property", "float", "r"])
    if len(data) < end + n * stride:
        sys.exit(f"lattice_probes.py: {path}: truncated")
    return [struct.unpack_from("<f", data, end + i * stride + 4 * r)[0] for i in range(n)]


def regions(n, rng):
    """Probe points: deep inside the lattice, across its whole box and just beyond, and 3 to 10
    spacings outside one face."""
    inner = [tuple(rng.uniform(n / 4, 3 * n / 4 - 1) for _ in range(3)) for _ in range(2000)]
    across = [tuple(rng.uniform(-2, n + 1) for _ in range(3)) for _ in range(4000)]
    outside = [(rng.uniform(-10, -3), rng.uniform(0, n - 1), rng.uniform(0, n - 1)) for _ in range(1000)]
    return {"inside": inner, "across": across, "outside": outside}


def run(lgh, args):
    """`lgh probes` with `args`; exits with its message where it fails."""
    try:
        p = subprocess.run([lgh, "probes", "--quiet", *args], capture_output=True, text=True)
    except OSError as e:
        sys.exit(f"lattice_probes.py: cannot run {lgh}: {e}")
    if p.returncode != 0:
        sys.exit(f"lattice_probes.py: lgh probes failed (exit status {p.returncode}): "
                 f"{p.stderr.strip() or 'no message'}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                epilog="Usage as docs/cycles.md quotes it: " + __doc__.split("\n\n")[1].strip())
    p.add_argument("--lgh", default="target/release/lgh", help="the lgh binary")
    p.add_argument("--n", type=int, default=32, help="lights a side of the lattice (spacing 1)")
    p.add_argument("--alpha", default="2,4", help="the α to measure, comma-separated")
    p.add_argument("--max-level", type=int, default=None,
                   help="the hierarchy's top level (default: lgh's; lower keeps only the finest "
                        "levels' transitions)")
    a = p.parse_args()
    lgh = a.lgh if os.sep in a.lgh else (shutil.which(a.lgh) or a.lgh)
    if not (os.path.isfile(lgh) and os.access(lgh, os.X_OK)):
        sys.exit(f"lattice_probes.py: no lgh binary at {a.lgh} (cargo build --release -p lgh-cli)")
    if a.n < 4:
        sys.exit("lattice_probes.py: --n must be at least 4")
    try:
        alphas = [float(x) for x in a.alpha.split(",")]
    except ValueError:
        sys.exit(f"lattice_probes.py: --alpha wants numbers separated by commas, not {a.alpha!r}")
    if not all(x > 0 and x == x and x != float("inf") for x in alphas):
        sys.exit(f"lattice_probes.py: every --alpha must be a finite number above 0: {a.alpha}")
    lights = [(float(i), float(j), float(k)) for i in range(a.n) for j in range(a.n) for k in range(a.n)]
    rng = random.Random(1)
    with tempfile.TemporaryDirectory() as tmp:
        write_ply(os.path.join(tmp, "lights.ply"), lights, [(1.0, 1.0, 1.0)] * len(lights))
        # h1 = 2: the lattice's spacing is h0, the voxel size of an explosion's lights.
        common = ["--lights", os.path.join(tmp, "lights.ply"), "--h1", "2"]
        if a.max_level is not None:
            common += ["--max-level", str(a.max_level)]
        for name, points in regions(a.n, rng).items():
            probes = os.path.join(tmp, f"{name}.ply")
            write_ply(probes, points)
            exact = os.path.join(tmp, f"{name}_brute.ply")
            run(lgh, common + ["--points", probes, "--out", exact, "--backend", "brute"])
            want = read_red(exact)
            for alpha in alphas:
                out = os.path.join(tmp, f"{name}_{alpha}.ply")
                run(lgh, common + ["--points", probes, "--out", out, "--alpha", str(alpha)])
                got = read_red(out)
                ratios = [g / w for g, w in zip(got, want)]
                rms = (sum((r - 1.0) ** 2 for r in ratios) / len(ratios)) ** 0.5
                print(json.dumps({
                    "region": name, "alpha": alpha, "max_level": a.max_level, "points": len(points),
                    "sum_ratio": round(sum(got) / sum(want), 5),
                    "mean_ratio": round(sum(ratios) / len(ratios), 5),
                    "min_ratio": round(min(ratios), 5), "max_ratio": round(max(ratios), 5),
                    "rms": round(rms, 5)}), flush=True)


if __name__ == "__main__":
    main()
