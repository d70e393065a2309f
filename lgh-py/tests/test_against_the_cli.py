"""The Python package against the Rust library as the command line runs it: `lgh probes` on the
same lights and points gives the same bits as ``Hierarchy.probe`` (both are lgh-core's build and
``probe``; the numbers only pass through PLY files and numpy).

Needs the `lgh` binary (``cargo build -p lgh-cli``; ``LGH_BIN`` names another): skipped with a
message without it, and a failure where ``LGH_REQUIRE_ALL`` is set (``.ci/run``).
"""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import lgh

ROOT = pathlib.Path(__file__).resolve().parents[2]


def lgh_binary():
    named = os.environ.get("LGH_BIN")
    candidates = [pathlib.Path(named)] if named else [
        ROOT / "target" / "release" / "lgh", ROOT / "target" / "debug" / "lgh"]
    for c in candidates:
        if c.is_file():
            return c
    if os.environ.get("LGH_REQUIRE_ALL"):
        pytest.fail(f"no lgh binary at {candidates} (cargo build -p lgh-cli)")
    pytest.skip(f"SKIPPED: no lgh binary at {candidates} (cargo build -p lgh-cli)")


def write_ply(path, columns):
    names = list(columns)
    n = len(columns[names[0]])
    header = "ply\nformat binary_little_endian 1.0\n" f"element vertex {n}\n"
    header += "".join(f"property float {c}\n" for c in names) + "end_header\n"
    rows = np.stack([np.asarray(columns[c], dtype="<f4") for c in names], axis=1)
    path.write_bytes(header.encode() + rows.tobytes())


def read_ply(path):
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    lines = data[:end].decode().splitlines()
    assert "format binary_little_endian 1.0" in lines, lines
    n = next(int(l.split()[2]) for l in lines if l.startswith("element vertex"))
    props = [l.split() for l in lines if l.startswith("property")]
    assert all(p[1] == "float" for p in props), props
    names = [p[2] for p in props]
    rows = np.frombuffer(data[end:], dtype="<f4", count=n * len(names)).reshape(n, len(names))
    return {c: rows[:, k] for k, c in enumerate(names)}


def test_probe_is_the_command_lines_bit_for_bit(tmp_path):
    binary = lgh_binary()
    rng = np.random.default_rng(5)
    p = rng.random((20000, 3), dtype=np.float32) * 4.0
    i = rng.random((20000, 3), dtype=np.float32)
    x = rng.random((3000, 3), dtype=np.float32) * 6.0 - 1.0
    write_ply(tmp_path / "lights.ply", {"x": p[:, 0], "y": p[:, 1], "z": p[:, 2],
                                         "r": i[:, 0], "g": i[:, 1], "b": i[:, 2]})
    write_ply(tmp_path / "points.ply", {"x": x[:, 0], "y": x[:, 1], "z": x[:, 2]})
    for alpha in ["1", "2", "4"]:
        out = tmp_path / f"out{alpha}.ply"
        subprocess.run([str(binary), "probes", "--lights", str(tmp_path / "lights.ply"),
                        "--points", str(tmp_path / "points.ply"), "--out", str(out),
                        "--alpha", alpha, "--quiet"], check=True)
        cli = read_ply(out)
        want = np.stack([cli["r"], cli["g"], cli["b"]], axis=1)
        got = lgh.Hierarchy(p, i, alpha=float(alpha)).probe(x)
        np.testing.assert_array_equal(got, want)
