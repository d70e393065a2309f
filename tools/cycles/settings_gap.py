"""How far lgh's default image of a procedural scene is from lgh's own finest — what a quality
setting could still buy — on ``blender/race.py``'s scene (the same volume, medium and camera
at 128×128, Blender 5's interpolation): relative RMSE of luminance of the default image, and of
4×4 rays a pixel alone, against 4×4 rays a pixel, half-voxel steps, no lighting cache and
scattering depths down to 0.1%.

    target/py313/bin/python tools/cycles/settings_gap.py [--scene explosion] [--resolution 128]

Prints JSON. Needs the ``lgh`` package and Debian's python3-openvdb. About 5 minutes on 2 cores
for the explosion (the finest image is most of it).
"""
import argparse
import json
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

import lgh

HERE = pathlib.Path(__file__).resolve().parent
FINEST = {"pixel_samples": 4, "step": 0.5, "lighting_cache": "none", "scatter_stop": 0.001}


def rel_rmse(a, b):
    """Relative RMSE of luminance (Rec. 709), as ``lgh compare``."""
    w = np.array([0.2126, 0.7152, 0.0722])
    la, lb = a @ w, b @ w
    return float(np.sqrt(np.mean((la - lb) ** 2)) / np.sqrt(np.mean(lb ** 2)))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scene", default="explosion")
    p.add_argument("--resolution", type=int, default=128)
    a = p.parse_args()
    with tempfile.TemporaryDirectory() as d:
        prefix = pathlib.Path(d) / "volume"
        lgh.write_procedural(a.scene, a.resolution, 0.5, prefix)
        subprocess.run(["/usr/bin/python3", str(HERE / "write_vdb.py"), str(prefix)], check=True,
                       capture_output=True)
        settings = dict(width=128, height=128, camera=(0, -4, 0, 0, 0, 0, 40), density_scale=4,
                        albedo=0.7, temperature_scale=1, flame_grid="none",
                        emission_interpolation="attributes", no_domain_offset=True,
                        allow_dark=True)

        def render(**more):
            return lgh.render_explosion(prefix.with_suffix(".vdb"), **settings, **more)

        finest = render(**FINEST)
        out = {"scene": a.scene, "resolution": a.resolution, "finest": FINEST,
               "default_vs_finest": rel_rmse(render(), finest),
               "pixel_samples_4_vs_finest": rel_rmse(render(pixel_samples=4), finest)}
    json.dump(out, sys.stdout)
    print()


if __name__ == "__main__":
    main()
