"""The add-on's figures, as JSON on standard output: the dev fire's frame 56 (the Cycles
comparison's scene, tools/cycles/compare.py's fire56, built in bpy) rendered

- by F12 through the engine ``LGH`` (``render.render``, the scene read, the image handed to
  Blender) and by ``lgh.render_explosion`` with the job's settings in the same process: the
  add-on's overhead, ``f12.overhead`` = F12's time / the library's - 1 (each the best of
  ``--repeat``, the two run in turn so that a drift of the machine's speed falls on both);
- in the viewport's progressive preview at ``--preview`` (640×360), run first (the process's
  first render, as a viewport's is): the seconds from the start to the first
  (quarter-resolution) image and to the full-quality one, and the same after the
  view turns (``view_first_s``, ``view_full_s``: the prepared frames render the new view).

    python blender/bench.py [--width 320 --height 180] [--preview 640x360] [--repeat 3]

Needs bpy (5.2.3 under Python 3.13), the ``lgh`` package and the shared data.
"""
import argparse
import json
import os
import pathlib
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE / "tests"))


def best_in_turn(fs, repeat):
    """The best seconds of each of ``fs``, run in turn ``repeat`` times."""
    times = [[] for _ in fs]
    for _ in range(repeat):
        for f, ts in zip(fs, times):
            t = time.perf_counter()
            f()
            ts.append(time.perf_counter() - t)
    return [min(ts) for ts in times]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--height", type=int, default=180)
    p.add_argument("--preview", default="640x360")
    p.add_argument("--repeat", type=int, default=3)
    a = p.parse_args()
    os.environ.pop("LGH_REQUIRE_ALL", None)

    import bpy
    import scenes
    from lgh_blender import engine, preview
    from lgh_blender.scene import job

    scene, _ = scenes.dev_fire_scene(a.width, a.height)
    # The preview first: the process's first render (the blackbody table not yet built).
    the_job = job(bpy.context.evaluated_depsgraph_get())
    w, h = (int(x) for x in a.preview.split("x"))
    view = the_job.with_settings(dict(the_job.settings, width=w, height=h))
    marks = []
    prepared = preview.Prepared()

    def timed(j, progress):
        image = prepared.render(j, progress)
        marks.append(time.perf_counter())
        return image

    progressive = preview.Progressive(timed)
    t0 = time.perf_counter()
    progressive.restart(view)
    progressive.wait()
    first, full = marks[0] - t0, marks[-1] - t0
    # Another view of the same scene: the prepared frames render it.
    marks.clear()
    turned = view.with_settings(
        dict(view.settings, camera=(1.2, -2.0, 0.7, 0.53, 0.34, 0.455, 40)))
    t0 = time.perf_counter()
    progressive.restart(turned)
    progressive.wait()
    with tempfile.TemporaryDirectory() as d:
        scene.render.filepath = str(pathlib.Path(d) / "f12.exr")

        def f12():
            bpy.ops.render.render(write_still=False)
            if any(level == "ERROR" for level, _ in engine.last_report):
                sys.exit(f"bench.py: {engine.last_report}")

        f12_s, library_s = best_in_turn([f12, lambda: engine.render_job(the_job)], a.repeat)

    print(json.dumps({
        "scene": "fire56", "threads": os.cpu_count(),
        "f12": {"width": a.width, "height": a.height, "addon_s": round(f12_s, 3),
                "library_s": round(library_s, 3), "overhead": round(f12_s / library_s - 1, 4)},
        "preview": {"width": w, "height": h, "first_s": round(first, 3),
                    "full_s": round(full, 3), "view_first_s": round(marks[0] - t0, 3),
                    "view_full_s": round(marks[-1] - t0, 3)},
    }))


if __name__ == "__main__":
    main()
