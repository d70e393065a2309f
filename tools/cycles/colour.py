"""The comparison's scenes channel by channel (issue 54): each scene's red, green and blue means
and relative RMSE against a converged Cycles image, for one or two `lgh` binaries (before and
after a change), the figures of docs/cycles.md's "Colour" section.

    python3 tools/cycles/colour.py --work cycles-compare                 # Blender 3.4.1
    python3 tools/cycles/colour.py --work cycles-compare-52 --bpy python3.13 --settings default,attributes
    python3 tools/cycles/colour.py ... --before /path/to/older/lgh       # and a binary before

The scenes, the medium and the Cycles scene are compare.py's (tools/cycles/README.md); the
reference is one Cycles render of --ref-spp samples (4096: a channel's mean is far steadier
than a pixel), reused from --work when it is there. Prints a JSON object and a Markdown table.
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import compare  # noqa: E402
from compare import LGH_SETTINGS, ROOT, SCENES, Runner, channels, log, rel_rmse  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scenes", default="fireball64,explosion128,fire56")
    p.add_argument("--work", default="cycles-compare")
    p.add_argument("--blender", default=shutil.which("blender") or "blender")
    p.add_argument("--bpy", default=None, help="a Python with PyPI's bpy, instead of blender")
    p.add_argument("--lgh", default=os.path.join(ROOT, "target/release/lgh"))
    p.add_argument("--before", default=None, help="an older lgh binary, compared the same way")
    p.add_argument("--export-grids",
                   default=os.path.join(ROOT, "target/release/examples/export_grids"))
    p.add_argument("--shared-data", default=os.path.join(ROOT, "..", "shared", "data"))
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--bounces", type=int, default=128)
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--settings", default="default")
    a = p.parse_args()
    ask = ([a.bpy, "-c", "import bpy; print('Blender', bpy.app.version_string)"] if a.bpy
           else [a.blender, "--version"])
    version = subprocess.run(ask, stdout=subprocess.PIPE, text=True).stdout
    major = re.search(r"Blender (\d+)\.", version)
    a.shift_half_voxel = bool(major and int(major.group(1)) < 4)
    r = Runner(a)
    # `lgh compare` of the current code measures every image (an older one may lack a key).
    compare.LGH = a.lgh
    binaries = [("after", a.lgh)] + ([("before", a.before)] if a.before else [])
    out = {"blender": version.strip().splitlines()[0] if version else None,
           "reference_spp": a.ref_spp, "scenes": {}}
    for name in a.scenes.split(","):
        scene = SCENES[name]
        vdb = r.vdb(name, scene)
        if vdb is None:
            continue
        ref = r.cycles(name, vdb, scene, a.ref_spp, 1, 128, 128)["out"]
        rows = {}
        for setting in a.settings.split(","):
            for which, binary in binaries:
                key = f"{setting}/{which}"
                # Each binary's renders under its own name in --work (Runner renders with
                # its arguments' lgh).
                r.a = argparse.Namespace(**{**vars(a), "lgh": binary})
                # The binary's time in the name: a rebuilt lgh renders again, not reused.
                stamp = int(os.path.getmtime(binary))
                q = r.lgh(f"{name}_{which}_{stamp}", vdb, scene, setting, 128, 128)
                e, mean, rgb = rel_rmse(q["out"], ref)
                rows[key] = {"rel_rmse": e, "mean_ratio": mean, **rgb,
                             "args": LGH_SETTINGS[setting]}
                log(f"{name} {key}: {rows[key]}")
        out["scenes"][name] = rows
    print(json.dumps(out, indent=1))
    print(f"\n| scene | lgh | luminance error | R / G / B error (%) |"
          f" R / G / B mean vs Cycles (%) |", file=sys.stderr)
    print("|---|---|---|---|---|", file=sys.stderr)
    for name, rows in out["scenes"].items():
        for key, row in rows.items():
            print(f"| {name} | {key} | {100 * row['rel_rmse']:.2f}% | "
                  f"{channels(row['rel_rmse_rgb'])} | {channels(row['mean_ratio_rgb'], 1.0)} |",
                  file=sys.stderr)


if __name__ == "__main__":
    main()
