#!/usr/bin/env python3
"""The table of `lgh_core::near_field::cell_falloff`: the mean of 1/|x - y|^2 over x in one
voxel and y in another, their centres `u` voxels apart (averaged over the directions between
them), for u = 0, 1/32, ..., 4 (unit voxels). Also prints the single voxel's mean at its centre
distance u (`voxel_falloff`'s table) at a few u as a check of the method.

The difference z = x - y of two uniform unit cubes has the density prod(1 - |z_i|) on [-1, 1]^3;
the mean of 1/|p + z|^2 over the sphere |p| = u is k(u, r) = ln((u + r)/|u - r|) / (2 u r),
r = |z|. So the mean is the integral over directions w (8 octants) of the radial integral
int_0^R r^2 prod(1 - r w_i) k(u, r) dr, R = 1 / max(w_i): a polynomial times logarithms, in
closed form below; the directions by the midpoint rule on (theta, phi) (N x N in an octant).

    python3 tools/near_field/cell_falloff.py [N]
"""
import sys
from fractions import Fraction
from itertools import product
from math import comb, factorial

import numpy as np


def radial(u, R, coeffs):
    """int_0^R (sum_m c_m r^m) * (ln(u + r) - ln|u - r|) dr, u > 0, vectorised over R."""
    total = np.zeros_like(R)
    for m, c in coeffs.items():
        # A = int r^m ln(u + r), B = int r^m ln|u - r| (by parts, polynomial division).
        a_poly = sum((-u) ** j * R ** (m - j + 1) / (m - j + 1) for j in range(m + 1))
        A = R ** (m + 1) * np.log(u + R) / (m + 1) - (
            a_poly + (-u) ** (m + 1) * (np.log(u + R) - np.log(u))) / (m + 1)
        b_poly = sum(u ** j * R ** (m - j + 1) / (m - j + 1) for j in range(m + 1))
        diff = np.abs(R - u)
        with np.errstate(divide="ignore", invalid="ignore"):
            edge = np.where(diff > 0, (R ** (m + 1) - u ** (m + 1)) * np.log(diff), 0.0)
        B = (edge + u ** (m + 1) * np.log(u) - b_poly) / (m + 1)
        total = total + c * (A - B)
    return total


def octant(n):
    th = (np.arange(n) + 0.5) * (np.pi / 2) / n
    T, P = np.meshgrid(th, th, indexing="ij")
    w = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)])
    dA = np.sin(T) * (np.pi / 2 / n) ** 2
    return w, dA


def cell_mean(u, n):
    """Two cubes u apart: 8 * octant integral of int r^2 prod(1 - r w_i) k dr."""
    w, dA = octant(n)
    a, b, c = w
    R = 1.0 / np.max(w, axis=0)
    s1, s2, s3 = a + b + c, a * b + b * c + c * a, a * b * c
    if u == 0.0:
        f = R - s1 * R ** 2 / 2 + s2 * R ** 3 / 3 - s3 * R ** 4 / 4
    else:
        # r^2 p(r) k = (1/2u) * r p(r) * (ln(u+r) - ln|u-r|); r p(r) = r - s1 r^2 + s2 r^3 - s3 r^4
        f = radial(u, R, {1: 1.0, 2: -s1, 3: s2, 4: -s3}) / (2 * u)
    return 8 * np.sum(f * dA)


def voxel_mean(u, n):
    """One cube, the point u from its centre: 8 * octant integral of int_0^l r^2 k dr."""
    w, dA = octant(n)
    l = 0.5 / np.max(w, axis=0)
    if u == 0.0:
        f = l
    else:
        f = radial(u, l, {1: np.ones_like(l)}) / (2 * u)
    return 8 * np.sum(f * dA)


def series():
    """c_k = E[r^2k] / (2k + 1) for the difference of two unit cubes, k = 1..6."""
    z = [Fraction(2, (2 * k + 1) * (2 * k + 2)) for k in range(8)]  # E[z^2k], triangular
    out = []
    for n in range(1, 7):
        e = Fraction(0)
        for i, j in product(range(n + 1), repeat=2):
            k = n - i - j
            if k < 0:
                continue
            e += Fraction(factorial(n), factorial(i) * factorial(j) * factorial(k)) * z[i] * z[j] * z[k]
        out.append(e / (2 * n + 1))
    return out


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 1200
    for u in [0.0, 0.5, 1.0, 2.0]:
        print(f"# check: voxel mean at u = {u}: {voxel_mean(u, n):.7f}")
    c = series()
    print("# series c_k = E[r^2k]/(2k+1):", ", ".join(f"{float(x):.10g}" for x in c))
    u = 4.0
    s = 1 + sum(float(ck) / u ** (2 * (k + 1)) for k, ck in enumerate(c))
    print(f"# series at u = 4: {s / u ** 2:.8f}")
    vals = [cell_mean(i / 32, n) for i in range(129)]
    print(f"# table at u = 4: {vals[-1]:.8f}")
    for i in range(0, 129, 4):
        print("    " + " ".join(f"{v:.7f}," for v in vals[i:i + 4]))


if __name__ == "__main__":
    main()
