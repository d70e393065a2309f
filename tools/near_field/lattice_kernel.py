#!/usr/bin/env python3
"""The table of `lgh_volume::scattering::lattice`'s `CELL_MEAN`: the light a voxel receives
from a uniform emitting voxel near it, as the mean over the receiving voxel (what its smoke
scatters), over the value at the receiving voxel's centre (what the scattering pass computes):

    Q(o, tau) = M(o, tau) / F(|o|, tau),
    M(o, tau) = mean over x in the voxel at offset o of  int_voxel e^(-tau |x - y|) / |x - y|^2 dy,
    F(u, tau) = the same at x on the sphere |x| = u, averaged over its directions: the pass's
                value, `voxel_falloff(u) * escape(u, tau) * e^(-tau u)` (lgh_core::near_field),

the unit voxel centred at the origin, tau the smoke's optical depth a voxel (uniform smoke),
for the offsets o of the receiving voxel's own light (0, 0, 0), a face (1, 0, 0), an edge
(1, 1, 0), a corner (1, 1, 1) and two voxels over (2, 0, 0). In polar coordinates around x the
inner integral is int_{S^2} (e^(-tau r_in(w)) - e^(-tau r_out(w))) / tau dw, as in
voxel_escape.py (its chords and Fibonacci spheres); x runs over the cell midpoints of an
NX^3 grid in the receiving voxel (M) or a Fibonacci sphere of NX^3 points (F).

Prints the Rust table: the five offsets (rows), tau = 0, 1/4, 1/2, 1, 2, 4 (columns).

    python3 tools/near_field/lattice_kernel.py [NX NW]     (numpy; 16 8192: about a minute)
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from voxel_escape import chords, fibonacci, print_table  # noqa: E402

OFFSETS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (1, 1, 1), (2, 0, 0)]
TAUS = [0.0, 0.25, 0.5, 1.0, 2.0, 4.0]


def fluence(xs, ws, taus, chunk=256):
    """The mean over the points xs (P, 3) of the unit voxel's light at each, for each tau."""
    out = np.zeros(len(taus))
    for s in range(0, len(xs), chunk):
        r_in, r_out = chords(xs[s:s + chunk], ws)
        for b, tau in enumerate(taus):
            f = (r_out - r_in) if tau == 0.0 else (np.exp(-tau * r_in) - np.exp(-tau * r_out)) / tau
            out[b] += f.mean(-1).sum() * 4.0 * np.pi
    return out / len(xs)


def main():
    nx, nw = (int(sys.argv[1]), int(sys.argv[2])) if len(sys.argv) > 2 else (16, 8192)
    ws = fibonacci(nw)
    grid = (np.stack(np.meshgrid(*[np.arange(nx)] * 3, indexing="ij"), -1).reshape(-1, 3)
            + 0.5) / nx - 0.5
    sphere = fibonacci(nx ** 3)
    rows = []
    for o in OFFSETS:
        o = np.array(o, dtype=float)
        m = fluence(grid + o, ws, TAUS)
        u = np.linalg.norm(o)
        f = fluence(sphere * u, ws, TAUS)
        rows.append(m / f)
        print(f"offset {o}: M = {m[0]:.5f}, F = {f[0]:.5f} at tau 0", file=sys.stderr)
    print_table("CELL_MEAN", rows, ".5f")


if __name__ == "__main__":
    main()
