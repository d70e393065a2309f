"""Images against a reference, their mean apart from their structure: for each image, on
luminance averaged over blocks of `--block` × `--block` pixels (a box filter, edges repeated,
which takes most of a path tracer's noise away), the ratio of its mean to the reference's, its
relative RMSE (RMSE over the reference's mean, `lgh compare`'s measure), and the relative RMSE
once it is scaled to the reference's mean — its structure alone; and the same of each channel
(`*_rgb`, each channel against the reference's).

On an image whose light is concentrated (smoky64: 96% of it in a tenth of the pixels), a relative
RMSE takes an error of the mean `sqrt(<R^2>) / <R>` times (3.7 there): the third figure says what
is left when the mean is right. A block wider than a pixel also hides what the pixel filter errs
by (the dev fire's default image, 2.19% from Cycles 3.4.1 a pixel, is 0.82% at 5 × 5): `--block
1` keeps it. docs/cycles.md ("The grid's loss, depth by depth") uses it:

    target/py313/bin/python tools/cycles/structure.py REFERENCE.exr IMAGE.exr [IMAGE.exr ...]

Prints one JSON line per image. Needs numpy and OpenEXR (compare.py's).
"""
import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare  # noqa: E402  (tools/cycles/compare.py: the EXR reader and luminance)


def block_means(a, n):
    """`a` averaged over the `n` × `n` pixels around each pixel (edges repeated)."""
    if n <= 1:
        return a
    p = n // 2
    padded = np.pad(a, ((p, n - 1 - p), (p, n - 1 - p)), mode="edge")
    windows = np.lib.stride_tricks.sliding_window_view(padded, (n, n))
    return windows.mean(axis=(2, 3))


def read(path):
    """`path`'s linear RGB; exits with a message where it cannot be read."""
    try:
        return compare.read_exr(path)
    except OSError as e:
        sys.exit(f"structure.py: {path}: {e}")


def structure(img, ref):
    """(mean ratio, relative RMSE, relative RMSE of `img` scaled to `ref`'s mean)."""
    scale = img.mean() / ref.mean()
    rmse = np.sqrt(((img - ref) ** 2).mean()) / ref.mean()
    scaled = np.sqrt(((img / scale - ref) ** 2).mean()) / ref.mean()
    return float(scale), float(rmse), float(scaled)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("reference")
    p.add_argument("images", nargs="+")
    p.add_argument("--block", type=int, default=5, help="pixels a side averaged (default 5)")
    a = p.parse_args()
    if a.block < 1:
        sys.exit("structure.py: --block must be at least 1")
    ref = read(a.reference)
    ref_lum = block_means(compare.luminance(ref), a.block)
    if ref_lum.mean() <= 0:
        sys.exit(f"structure.py: {a.reference} is black")
    ref_rgb = [block_means(ref[..., c], a.block) for c in range(3)]
    gain = float(np.sqrt((ref_lum ** 2).mean()) / ref_lum.mean())
    for path in a.images:
        img = read(path)
        if img.shape != ref.shape:
            sys.exit(f"structure.py: {path} is {img.shape[1]}x{img.shape[0]}, "
                     f"the reference {ref.shape[1]}x{ref.shape[0]}")
        mean, rmse, scaled = structure(block_means(compare.luminance(img), a.block), ref_lum)
        # Each channel the same way (null where the reference's channel is black).
        rgb = [structure(block_means(img[..., c], a.block), r) if r.mean() > 0 else (None,) * 3
               for c, r in enumerate(ref_rgb)]
        print(json.dumps({"image": path, "block": a.block, "mean_ratio": mean, "rel_rmse": rmse,
                          "rel_rmse_scaled": scaled, "mean_error_gain": gain,
                          "mean_ratio_rgb": [c[0] for c in rgb],
                          "rel_rmse_rgb": [c[1] for c in rgb],
                          "rel_rmse_scaled_rgb": [c[2] for c in rgb]}))


if __name__ == "__main__":
    main()
