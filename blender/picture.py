"""The README's picture: the dev fire's frame 56 (the Cycles comparison's fire56 scene, built in
bpy) rendered by the add-on's engine LGH and by Cycles 5.2.3 in the same scene, side by side
with one tone map (``tools/cycles/compare.py``'s ``figure``), each labelled with its time.

    python blender/picture.py [--width 320 --height 180] [--spp 1024] [--fov 20] [--out docs/blender/fire56-lgh-cycles.png]

Cycles renders as ``tools/cycles/render_cycles.py`` does (CPU, 128 volume bounces, no denoiser,
no adaptive sampling, a one-pixel box filter) at ``--spp`` samples: a picture, not the equal-error
measurement of ``tools/cycles``. Prints the two renders' seconds and their relative RMSE as JSON
(over the three channels, and each channel's).
Needs bpy 5.2.3, ``lgh``, Pillow and the shared data.
"""
import argparse
import json
import os
import pathlib
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE / "tests"))
sys.path.insert(0, str(ROOT / "tools" / "cycles"))


def main():
    # Blender prints to the process's standard output ("Saved: ..."): keep it for the JSON.
    json_out = os.fdopen(os.dup(1), "w")
    os.dup2(2, 1)
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--height", type=int, default=180)
    p.add_argument("--spp", type=int, default=1024)
    p.add_argument("--fov", type=float, default=20.0)
    p.add_argument("--out", default=str(ROOT / "docs" / "blender" / "fire56-lgh-cycles.png"))
    a = p.parse_args()
    os.environ.pop("LGH_REQUIRE_ALL", None)

    import bpy
    import compare
    import scenes

    # The study's scene, the field of view narrowed to the fire.
    scene, _ = scenes.dev_fire_scene(a.width, a.height, fov=a.fov)
    with tempfile.TemporaryDirectory() as d:
        d = pathlib.Path(d)
        t = time.perf_counter()
        lgh_image, report = scenes.render(d, "lgh")
        lgh_s = time.perf_counter() - t
        if lgh_image is None or report:
            sys.exit(f"picture.py: the LGH render reported {report}")
        scenes.use_cycles(scene, a.spp, seed=1, bounces=128)
        t = time.perf_counter()
        cycles_image, _ = scenes.render(d, "cycles")
        cycles_s = time.perf_counter() - t
        out = pathlib.Path(a.out)
        out.parent.mkdir(parents=True, exist_ok=True)
        compare.figure(str(out), [str(d / "lgh.exr"), str(d / "cycles.exr")],
                       [f"LGH (Blender add-on) {lgh_s:.1f} s",
                        f"Cycles 5.2.3, {a.spp} spp, {cycles_s:.0f} s"])
    print(json.dumps({"width": a.width, "height": a.height, "spp": a.spp,
                      "lgh_s": round(lgh_s, 2), "cycles_s": round(cycles_s, 1),
                      "rel_rmse": round(scenes.rel_rmse(lgh_image, cycles_image), 4),
                      "rel_rmse_rgb": [round(scenes.rel_rmse(lgh_image[..., c],
                                                             cycles_image[..., c]), 4)
                                       for c in range(3)],
                      "out": str(out)}), file=json_out)


if __name__ == "__main__":
    main()
