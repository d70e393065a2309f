#!/usr/bin/env python3
"""The table of `lgh_core::near_field`'s `ESCAPE`: how much more of a uniform emitting voxel's
light reaches a point at distance u (voxels) from its centre through uniform smoke of optical
depth tau a voxel, than the voxel light's model gives it — the voxel's mean of 1/r^2 (G(u),
`voxel_falloff`) times the transmittance to the voxel's centre, e^(-tau u), that the shadow ray
applies:

    R(u, tau) = F(u, tau) / (G(u) e^(-tau u)),
    F(u, tau) = mean over the directions of x (|x| = u) of  int_voxel e^(-tau |x - y|) / |x - y|^2 dy,

the unit voxel centred at the origin. In polar coordinates around x, the inner integral is
int_{S^2} (e^(-tau r_in(w)) - e^(-tau r_out(w))) / tau dw, [r_in, r_out] the chord of the ray
x + r w through the voxel (r_in = 0 inside it; r_out - r_in at tau = 0). Both sets of
directions are Fibonacci spheres (NX points x, NW rays w). R(u, 0) = 1; R(0, tau) G(0) is the
centre's fluence K(tau) of `CENTRE_FLUENCE`.

Prints the Rust table: u = 0, 1/8, ..., 4 (rows), tau = 0, 1/4, ..., 8 (columns).

    python3 tools/near_field/voxel_escape.py [NX NW]      (numpy; 256 32768: a few minutes)
"""
import sys

import numpy as np


def fibonacci(n):
    """n nearly uniform unit vectors (the Fibonacci sphere)."""
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    r = np.sqrt(1.0 - z * z)
    phi = i * np.pi * (3.0 - np.sqrt(5.0))
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], -1)


def chords(x, w):
    """[r_in, r_out] of the rays x + r w (r >= 0) through the unit voxel [-1/2, 1/2]^3, for
    points x (P, 3) and directions w (W, 3): two (P, W) arrays, both 0 for a ray that misses."""
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / w
        t1 = (-0.5 - x[:, None, :]) * inv[None]
        t2 = (0.5 - x[:, None, :]) * inv[None]
    lo = np.nan_to_num(np.minimum(t1, t2), nan=-np.inf).max(-1)
    hi = np.nan_to_num(np.maximum(t1, t2), nan=np.inf).min(-1)
    lo = np.maximum(lo, 0.0)
    hit = hi > lo
    return np.where(hit, lo, 0.0), np.where(hit, hi, 0.0)


def escape(us, taus, nx, nw):
    """R(u, tau) for every u in us (rows) and tau in taus (columns)."""
    xs, ws = fibonacci(nx), fibonacci(nw)
    out = np.zeros((len(us), len(taus)))
    for a, u in enumerate(us):
        r_in, r_out = chords(xs * u, ws)
        g = (r_out - r_in).mean() * 4.0 * np.pi
        for b, tau in enumerate(taus):
            if tau == 0.0:
                out[a, b] = 1.0
                continue
            f = ((np.exp(-tau * r_in) - np.exp(-tau * r_out)) / tau).mean() * 4.0 * np.pi
            out[a, b] = f / (g * np.exp(-tau * u))
        print(f"u = {u:.3f}: G = {g:.5f}", file=sys.stderr)
    return out


def print_table(name, rows, digits):
    """A Rust constant `name` of f32 rows, each value formatted by `digits` (a format spec)."""
    print("#[rustfmt::skip]")
    print(f"const {name}: [[f32; {len(rows[0])}]; {len(rows)}] = [")
    for row in rows:
        print("    [" + ", ".join(f"{v:{digits}}" for v in row) + "],")
    print("];")


def main():
    nx, nw = (int(sys.argv[1]), int(sys.argv[2])) if len(sys.argv) > 2 else (256, 32768)
    us, taus = np.arange(33) / 8.0, np.arange(33) / 4.0
    print_table("ESCAPE", escape(us, taus, nx, nw), ".6")


if __name__ == "__main__":
    main()
