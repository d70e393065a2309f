#!/usr/bin/env python3
"""Writes lgh-core/src/blend/spread_table.rs: eq. (3)'s blended fall-off averaged over a coarse
light's spread, `k(ρ, σ) = E[B̂(‖y − δ‖) / ‖y − δ‖²]` with `‖y‖ = ρ`, in units of the level's
radius `r_ℓ` (lgh-core/src/blend/spread.rs documents the model; its test recomputes every entry).

    python3 tools/hierarchy/spread_table.py            # rewrites the table (standard library only)

`B̂` is eq. (3)'s ramp of a middle level (rising from 0 at ρ = ½ to 1 at 1, falling to 0 at 2)
or of the top level (rising, then 1); `δ` is drawn from the radial density `∝ 1 − a²/R²` on the
ball of radius `R = √7 σ` (per-axis variance σ²). Each entry is a one-dimensional integral over
the shell radius `a` of the shell's mean, which is closed-form: for a sphere of radius `a` about a
point at distance `u`, the distance `d` is uniform in `d²` on `[|u − a|, u + a]`, so the mean of
`f(d)` is `(1 / 2ua) ∫ f(d) d dd`, and with `f = B̂/d²` the integrand `B̂(d)/d` is a sum of
`c₀/d + c₁` pieces. The integral over `a` is Gauss–Legendre (24 nodes) between the radii where a
piece begins or ends, so every entry is exact to about 1e-12 before it is rounded to f32.
"""
import math
import os
import sys

RHO_STEPS = 32          # table rows a unit of ρ
SIGMA_STEPS = 32        # table columns a unit of σ
SIGMA_MAX = 1.0         # σ = s / r_ℓ ≤ h_ℓ / r_ℓ = 1/α; above it σ is clamped (α < 1)
MIDDLE_RHO_MAX = 5.0    # beyond 2 + √7 σ_max ≈ 4.65 the middle shape is 0
TOP_RHO_MAX = 8.0       # beyond it the top shape is the series of spread.rs
R_PER_SIGMA = math.sqrt(7.0)
KINKS = {"middle": (0.5, 1.0, 2.0), "top": (0.5, 1.0)}


def antiderivative(shape, d):
    """F(d) = ∫_0^d B̂(t)/t dt, closed form piece by piece."""
    if d <= 0.5:
        return 0.0
    if d <= 1.0:
        return 2.0 * (d - 0.5) - math.log(2.0 * d)
    f1 = 1.0 - math.log(2.0)
    if shape == "top":
        return f1 + math.log(d)
    if d <= 2.0:
        return f1 + 2.0 * math.log(d) - (d - 1.0)
    return math.log(2.0)


def ramp(shape, d):
    rise = 2.0 * d - 1.0
    w = rise if shape == "top" else min(rise, 2.0 - d)
    return min(max(w, 0.0), 1.0)


def shell_mean(shape, u, a):
    """Mean of B̂(d)/d² over the sphere of radius a about a point at distance u."""
    if a == 0.0:
        return ramp(shape, u) / (u * u) if u > 0.0 else 0.0
    if u == 0.0:
        return ramp(shape, a) / (a * a)
    lo, hi = abs(u - a), u + a
    return (antiderivative(shape, hi) - antiderivative(shape, lo)) / (2.0 * u * a)


NODES = None


def gauss_legendre(n):
    """Nodes and weights on [-1, 1] by Newton's iteration on P_n."""
    xs, ws = [], []
    for i in range(1, n + 1):
        x = math.cos(math.pi * (i - 0.25) / (n + 0.5))
        for _ in range(100):
            p0, p1 = 1.0, x
            for k in range(2, n + 1):
                p0, p1 = p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k
            dp = n * (x * p1 - p0) / (x * x - 1.0)
            dx = p1 / dp
            x -= dx
            if abs(dx) < 1e-16:
                break
        xs.append(x)
        ws.append(2.0 / ((1.0 - x * x) * dp * dp))
    return xs, ws


def k(shape, rho, sigma):
    """The averaged blended fall-off k(ρ, σ), in units of r_ℓ."""
    if sigma == 0.0:
        return ramp(shape, rho) / (rho * rho) if rho > 0.0 else 0.0
    big_r = R_PER_SIGMA * sigma
    cuts = {0.0, big_r}
    for kink in KINKS[shape]:
        for a in (kink - rho, rho - kink, kink + rho):
            if 0.0 < a < big_r:
                cuts.add(a)
    if 0.0 < rho < big_r:
        cuts.add(rho)
    cuts = sorted(cuts)
    xs, ws = NODES
    num = den = 0.0
    for a0, a1 in zip(cuts, cuts[1:]):
        half, mid = 0.5 * (a1 - a0), 0.5 * (a1 + a0)
        for x, w in zip(xs, ws):
            a = mid + half * x
            density = a * a * (1.0 - (a / big_r) ** 2)
            num += w * half * density * shell_mean(shape, rho, a)
            den += w * half * density
    return num / den


def table(shape, rho_max):
    rows = []
    for i in range(int(rho_max * RHO_STEPS) + 1):
        rho = i / RHO_STEPS
        rows.append([k(shape, rho, j / SIGMA_STEPS) for j in range(int(SIGMA_MAX * SIGMA_STEPS) + 1)])
    return rows


def rust_array(name, rows, doc):
    out = [f"/// {doc}", "#[rustfmt::skip]", f"pub(super) static {name}: [[f32; {len(rows[0])}]; {len(rows)}] = ["]
    for row in rows:
        out.append("    [" + ", ".join(f"{float(repr_f32(v))!r}" if v else "0.0" for v in row) + "],")
    out.append("];")
    return "\n".join(out)


def repr_f32(v):
    """The shortest decimal that rounds to the same f32 as v."""
    import struct
    f = struct.unpack("f", struct.pack("f", v))[0]
    for digits in range(6, 12):
        s = f"{f:.{digits}g}"
        if struct.unpack("f", struct.pack("f", float(s)))[0] == f:
            return s
    return repr(f)


def main():
    global NODES
    NODES = gauss_legendre(24)
    here = os.path.dirname(os.path.abspath(__file__))
    path = os.path.join(here, "..", "..", "lgh-core", "src", "blend", "spread_table.rs")
    middle = table("middle", MIDDLE_RHO_MAX)
    top = table("top", TOP_RHO_MAX)
    text = "\n".join([
        "// Written by tools/hierarchy/spread_table.py; do not edit. spread.rs's tests recompute every entry.",
        "//",
        f"// Rows ρ = i / {RHO_STEPS}, columns σ = j / {SIGMA_STEPS} (both in units of r_ℓ); f32.",
        "",
        rust_array("MIDDLE", middle, "`k(ρ, σ)` of a level below the top (eq. 3's ramp rises and falls)."),
        "",
        rust_array("TOP", top, "`k(ρ, σ)` of the top level (eq. 3's ramp rises and stays 1)."),
        "",
    ])
    with open(path, "w") as f:
        f.write(text)
    print(f"spread_table.py: wrote {os.path.normpath(path)} ({len(middle)} + {len(top)} rows)", file=sys.stderr)


if __name__ == "__main__":
    main()
