"""How far lgh's default image of a procedural scene is from lgh's own finest — what a quality
setting could still buy — on ``blender/race.py``'s scene (the same volume, medium and camera
at 128×128, Blender 5's interpolation): the error of the default image, and of 4×4 rays a pixel
alone, against 4×4 rays a pixel (8×8 for the emission), half-voxel steps, no lighting cache and
scattering depths down to 0.1% — by ``lgh compare``, the race's measure (RMSE of luminance over the reference's mean),
and each channel's (``*_rgb``).

    target/py313/bin/python tools/cycles/settings_gap.py [--scene explosion] [--resolution 128]

Prints JSON. Needs the ``lgh`` package, the release ``lgh`` and Debian's python3-openvdb. About 5
minutes on 2 cores for the explosion (the finest image is most of it).
"""
import argparse
import json
import pathlib
import subprocess
import sys
import tempfile

import lgh

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import compare  # noqa: E402 (tools/cycles' one measure: lgh compare)
FINEST = {"pixel_samples": 4, "emission_samples": 8, "step": 0.5, "lighting_cache": "none",
          "scatter_stop": 0.001}


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

        def render(name, **more):
            path = str(pathlib.Path(d) / f"{name}.exr")
            compare.write_exr(path, lgh.render_explosion(prefix.with_suffix(".vdb"), **settings,
                                                         **more))
            return path

        finest = render("finest", **FINEST)
        out = {"scene": a.scene, "resolution": a.resolution, "finest": FINEST}
        for name, more in (("default", {}), ("pixel_samples_4", {"pixel_samples": 4})):
            error, _, rgb = compare.rel_rmse(render(name, **more), finest)
            out[f"{name}_vs_finest"] = error
            out[f"{name}_vs_finest_rgb"] = rgb["rel_rmse_rgb"]
    json.dump(out, sys.stdout)
    print()


if __name__ == "__main__":
    main()
