"""The Python package's cost over the Rust library's, on the same work: a hierarchy over N
lights (default 1M, uniform in a unit cube, random colours) built and probed at M points
(default 100,000), timed in Python (``lgh.Hierarchy`` then ``probe``) and by ``lgh probes`` on
the same numbers (its own "build" and "evaluate" seconds, without reading the PLY files). Both
run lgh-core's build and ``probe`` on every core; the ratio is Python's over Rust's, each the
best of ``--runs``.

    python lgh-py/bench/vs_rust.py [--lights 1000000] [--points 100000] [--runs 3] [--lgh target/release/lgh]

Prints one JSON object.
"""
import argparse
import json
import pathlib
import re
import subprocess
import sys
import tempfile
import time

import numpy as np

import lgh

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))
from test_against_the_cli import write_ply  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lights", type=int, default=1_000_000)
    ap.add_argument("--points", type=int, default=100_000)
    ap.add_argument("--alpha", type=float, default=2.0)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--lgh", default=str(HERE.parents[1] / "target" / "release" / "lgh"))
    a = ap.parse_args()
    rng = np.random.default_rng(1)
    p = rng.random((a.lights, 3), dtype=np.float32)
    i = rng.random((a.lights, 3), dtype=np.float32)
    x = rng.random((a.points, 3), dtype=np.float32) * 1.5 - 0.25

    python_s = []
    for _ in range(a.runs):
        t0 = time.perf_counter()
        h = lgh.Hierarchy(p, i, alpha=a.alpha)
        t1 = time.perf_counter()
        got = h.probe(x)
        t2 = time.perf_counter()
        python_s.append((t1 - t0, t2 - t1))

    rust_s = []
    with tempfile.TemporaryDirectory() as d:
        d = pathlib.Path(d)
        write_ply(d / "l.ply", {"x": p[:, 0], "y": p[:, 1], "z": p[:, 2],
                                "r": i[:, 0], "g": i[:, 1], "b": i[:, 2]})
        write_ply(d / "p.ply", {"x": x[:, 0], "y": x[:, 1], "z": x[:, 2]})
        for _ in range(a.runs):
            o = subprocess.run([a.lgh, "probes", "--lights", str(d / "l.ply"), "--points",
                                str(d / "p.ply"), "--out", str(d / "o.ply"), "--alpha",
                                str(a.alpha), "--quiet"], check=True, capture_output=True,
                               text=True)
            text = o.stdout + o.stderr
            m = re.search(r"build ([0-9.]+) s, evaluate ([0-9.]+) s", text)
            if not m:
                sys.exit(f"lgh probes printed no timings: {text}")
            rust_s.append((float(m.group(1)), float(m.group(2))))
    best = lambda runs: min(runs, key=sum)  # noqa: E731
    (pb, pp), (rb, rp) = best(python_s), best(rust_s)
    print(json.dumps({
        "lights": a.lights, "points": a.points, "alpha": a.alpha, "runs": a.runs,
        "python_build_s": pb, "python_probe_s": pp, "rust_build_s": rb, "rust_probe_s": rp,
        "ratio": (pb + pp) / (rb + rp), "mean_probe": float(got.mean()),
    }, indent=1))


if __name__ == "__main__":
    main()
