"""Real simulation caches, none made by lgh: Blender's own fire simulator (Mantaflow) bakes them,
so anyone can make them again. Debian's Blender 3.4.1 bakes (PyPI's bpy 5.2.3 cannot: its
Mantaflow neither bakes nor loads a cache in background mode).

    python3 tools/caches/bake.py [--out target/caches] [--cases fire,smoky] [--resolutions 64,128]
                                 [--frames 1..60] [--blender /usr/bin/blender]

Each case × resolution goes to ``OUT/CASE-RES/``: ``scene.blend`` (the domain, its flow, the
material Quick Smoke gives it), ``data/fluid_data_NNNN.vdb`` (the OpenVDB cache: ``density``,
``flame``, ``heat``, ...) and ``bake.json`` (Blender's version, the settings, the seconds it
took). A case already baked with the same settings is kept. The cases:

- **fire**: *Object > Quick Effects > Quick Smoke* with *Fire + Smoke* on a 0.4-unit icosphere
  at the bottom of its domain (Blender's defaults otherwise): thin flames in thin smoke, as the
  dev fire;
- **smoky**: the same with three times the smoke from the flow (``density``) and from burning
  (``flame_smoke``), and a slower burn (``burning_rate``): dense smoke over the flames.

Run inside Blender (``blender -b --factory-startup --python tools/caches/bake.py -- bake DIR
CASE RES FIRST LAST``) it bakes one; run by ``python3`` it drives Blender, one process a case,
in the case's folder (Mantaflow writes ``waveletNoiseTile.bin`` into the working directory).
"""
import argparse
import json
import os
import pathlib
import shutil
import subprocess
import sys
import time

#: What each case changes of Quick Smoke's defaults: the flow's settings, the domain's.
CASES = {
    "fire": ({}, {}),
    "smoky": ({"density": 3.0}, {"flame_smoke": 3.0, "burning_rate": 0.5}),
}


# ---- Inside Blender 3.4.1 -------------------------------------------------------------------

def bake(directory, case, resolution, first, last):
    import bpy

    flow_settings, domain_settings = CASES[case]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = first, last
    bpy.ops.mesh.primitive_ico_sphere_add(radius=0.4, location=(0.0, 0.0, 0.0))
    flow = bpy.context.view_layer.objects.active
    flow.name = "flow"
    flow.select_set(True)  # Quick Smoke works on the selection (an override does not reach it)
    bpy.ops.object.quick_smoke(style="BOTH")
    domain = next(o for o in scene.objects if o.name != "flow")
    domain.name = "domain"
    f = next(m for m in flow.modifiers if m.type == "FLUID").flow_settings
    for key, value in flow_settings.items():
        setattr(f, key, value)
    ds = next(m for m in domain.modifiers if m.type == "FLUID").domain_settings
    for key, value in domain_settings.items():
        setattr(ds, key, value)
    # Most domain settings free the cache (and delete its files): the cache's own last.
    ds.resolution_max, ds.cache_data_format, ds.cache_type = resolution, "OPENVDB", "ALL"
    ds.cache_frame_start, ds.cache_frame_end = first, last
    ds.cache_directory = directory
    data = os.path.join(directory, "data")
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "blender" / "tests"))
    from mantaflow import bake as bake_domain

    bake_domain(domain, data, last - first + 1, "bake.py")


# ---- Driving Blender --------------------------------------------------------------------------

def frames(text):
    try:
        a, b = (int(x) for x in text.split(".."))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: FIRST..LAST, e.g. 1..60") from None
    if not 1 <= a <= b:
        raise argparse.ArgumentTypeError(f"{text!r}: 1 <= FIRST <= LAST")
    return a, b


def listed(kind, allowed=None):
    def parse(text):
        items = [x for x in text.split(",") if x]
        bad = [x for x in items if (allowed is not None and x not in allowed)
               or (allowed is None and not (x.isdigit() and 8 <= int(x) <= 512))]
        if not items or bad:
            raise argparse.ArgumentTypeError(
                f"{text!r}: {kind}, comma-separated"
                + (f" of {', '.join(allowed)}" if allowed else ", 8 to 512"))
        return items if allowed else [int(x) for x in items]
    return parse


def main():
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "blender" / "tests"))
    from mantaflow import retried

    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", default="target/caches", type=pathlib.Path)
    p.add_argument("--cases", default="fire,smoky", type=listed("cases", list(CASES)))
    p.add_argument("--resolutions", default="64,128", type=listed("resolutions"))
    p.add_argument("--frames", default="1..60", type=frames)
    p.add_argument("--blender", default="/usr/bin/blender")
    a = p.parse_args()
    if not (os.path.isfile(a.blender) and os.access(a.blender, os.X_OK)):
        sys.exit(f"bake.py: no Blender at {a.blender} (Debian: apt-get install blender)")
    version = subprocess.run([a.blender, "--version"], capture_output=True,
                             text=True).stdout.split("\n")[0].strip()
    # Blender's own Python must not see another's (bpy's OCIO, a venv's paths).
    env = {k: v for k, v in os.environ.items() if k in ("PATH", "HOME", "LANG", "TMPDIR")}
    first, last = a.frames
    for case in a.cases:
        for res in a.resolutions:
            d = (a.out / f"{case}-{res}").resolve()
            want = {"blender": version, "case": case, "resolution": res,
                    "frames": [first, last], "flow": CASES[case][0], "domain": CASES[case][1]}
            record = d / "bake.json"
            if record.is_file():
                done = json.loads(record.read_text())
                if {k: done.get(k) for k in want} == want:
                    print(f"bake.py: {d} is baked already", file=sys.stderr)
                    continue
            print(f"bake.py: baking {case} at {res} cells, frames {first}..{last} into {d}",
                  file=sys.stderr)
            start = time.monotonic()
            baked, run = retried(
                d,
                lambda: subprocess.run(
                    [a.blender, "-b", "--factory-startup", "--python", __file__, "--", "bake",
                     str(d), case, str(res), str(first), str(last)],
                    capture_output=True, text=True, env=env, cwd=d),
                lambda: (d / "data" / f"fluid_data_{last:04d}.vdb").is_file()
                and (d / "scene.blend").is_file())
            if not baked:
                shutil.rmtree(d, ignore_errors=True)
                sys.exit(f"bake.py: Blender did not bake {case} at {res}:\n"
                         f"{run.stdout[-1500:]}{run.stderr[-1500:]}")
            (d / "waveletNoiseTile.bin").unlink(missing_ok=True)
            want["seconds"] = round(time.monotonic() - start, 1)
            tmp = record.with_suffix(".json.tmp")
            tmp.write_text(json.dumps(want, indent=1) + "\n")
            tmp.replace(record)
            print(f"bake.py: {d}: {want['seconds']} s", file=sys.stderr)


if __name__ == "__main__":
    if "--" in sys.argv:  # inside Blender
        args = sys.argv[sys.argv.index("--") + 1:]
        bake(args[1], args[2], int(args[3]), int(args[4]), int(args[5]))
    else:
        main()
