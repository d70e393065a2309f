"""The add-on against Cycles 5.2.3 in the same .blend, at equal error (the method of
``tools/cycles/compare.py``): for each scene, one bpy scene — the procedural volume as a Volume
object (``lgh.write_procedural``, ``tools/cycles/write_vdb.py``), density 4, colour 0.7, black
absorption, blackbody from a kelvin temperature grid, a black world, the camera at (0, −4, 0)
looking at the origin with a 40° vertical field, 128×128 — rendered by F12 with the engine LGH
and with Cycles (CPU, 128 volume bounces, no denoiser, a one-pixel box filter): a converged
reference (``--ref-seeds`` × ``--ref-spp``), a ladder of sample counts, LGH once warm (a first
F12 of the scene before the timed one) for each of the engine's Sampling settings asked for
(``--sampling``: ``auto`` or ``PIXELS/SPACING``, the pixel samples and the scatter spacing
fixed, either part ``auto``; the first keyed by the scene's name, the others by
``NAME_pPIXELSsSPACING``). Errors are relative RMSE of luminance (``lgh compare``);
Cycles' noise ``a`` (its error² ≈ a (1/n + 1/N)) is fitted over the ladder, LGH's error against
the truth is ``sqrt(e² − a/N)``, Cycles reaches it at ``n* = a / e_truth²`` samples, whose
CPU-seconds come from a line fitted to the ladder's. CPU-seconds are the process's (user +
system) over each F12.

    target/py313/bin/python blender/race.py [--scenes fireball64,explosion128] [--ref-spp 4096]
        [--sampling auto,4/2]

Prints JSON, one record per scene. Needs bpy 5.2.3, ``lgh``, Debian's python3-openvdb and the
release ``lgh`` (``lgh compare``). About half an hour on 2 cores.
"""
import argparse
import json
import math
import os
import pathlib
import resource
import subprocess
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE / "tests"))
sys.path.insert(0, str(ROOT / "tools" / "cycles"))

#: tools/cycles/compare.py's procedural scenes.
SCENES = {"fireball64": ("fireball", 64), "explosion128": ("explosion", 128)}


def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def timed_render(scenes, folder, name):
    """F12 into ``folder/name.exr``: the file and the CPU-seconds it took."""
    start = cpu()
    image, report = scenes.render(folder, name)
    if image is None:
        sys.exit(f"race.py: {name}: no image ({report})")
    return folder / f"{name}.exr", cpu() - start


def sampling(text):
    """``--sampling``'s entries: ``(key suffix, {"pixel_samples": n or None, "scatter_spacing":
    n or None})``, ``None`` for Auto."""
    out = []
    for entry in text.split(","):
        parts = ["auto", "auto"] if entry == "auto" else entry.split("/")
        if len(parts) != 2 or not all(p == "auto" or (p.isdigit() and 1 <= int(p) <= 8)
                                      for p in parts):
            raise argparse.ArgumentTypeError(
                f"{entry!r}: auto or PIXELS/SPACING, each 1 to 8 or auto")
        fixed = [None if p == "auto" else int(p) for p in parts]
        suffix = "" if fixed == [None, None] else f"_p{parts[0]}s{parts[1]}"
        out.append((suffix, {"pixel_samples": fixed[0], "scatter_spacing": fixed[1]}))
    return out


def set_sampling(scene, chosen):
    """The engine's Sampling settings (``scene.lgh``) as ``chosen`` says."""
    s = scene.lgh
    for grid, name in (("pixel_sampling", "pixel_samples"), ("scatter_grid", "scatter_spacing")):
        setattr(s, grid, "AUTO" if chosen[name] is None else "FIXED")
        if chosen[name] is not None:
            setattr(s, name, chosen[name])


def main():
    json_out = os.fdopen(os.dup(1), "w")  # Blender prints to standard output
    os.dup2(2, 1)
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scenes", default=",".join(SCENES))
    p.add_argument("--size", type=int, default=128)
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--ref-seeds", type=int, default=2)
    p.add_argument("--ladder", default="16,64,256,1024")
    p.add_argument("--sampling", default="auto", type=sampling,
                   help="the engine's Sampling settings to race: auto or PIXELS/SPACING, ...")
    a = p.parse_args()
    os.environ.pop("LGH_REQUIRE_ALL", None)

    import compare
    import lgh_blender
    import numpy as np
    import scenes

    lgh_blender.register()
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in a.scenes.split(","):
            kind, res = SCENES[name]
            d = pathlib.Path(tmp) / name
            d.mkdir()
            prefix = d / "volume"
            scenes.lgh.write_procedural(kind, res, 0.5, prefix)
            subprocess.run(["/usr/bin/python3", str(ROOT / "tools" / "cycles" / "write_vdb.py"),
                            str(prefix)], check=True, capture_output=True)
            scene, _ = scenes.build(prefix.with_suffix(".vdb"), width=a.size, height=a.size,
                                    eye=(0.0, -4.0, 0.0), rotation=(90.0, 0.0, 0.0), fov=40.0)
            scenes.render(d, "warm")
            lghs = []
            for i, (suffix, chosen) in enumerate(a.sampling):
                set_sampling(scene, chosen)
                lghs.append((suffix, chosen, *timed_render(scenes, d, f"lgh{i}")))
            scenes.use_cycles(scene, a.ref_spp, bounces=128)
            seeds = []
            for seed in range(1, a.ref_seeds + 1):
                scene.cycles.seed = seed
                seeds.append(compare.read_exr(str(timed_render(scenes, d, f"ref{seed}")[0])))
            n_ref = a.ref_spp * a.ref_seeds
            ref = str(d / "reference.exr")
            compare.write_exr(ref, np.mean(seeds, axis=0))
            ladder = []
            for spp in (int(s) for s in a.ladder.split(",")):
                scene.cycles.samples, scene.cycles.seed = spp, 100 + spp
                exr, cpu_s = timed_render(scenes, d, f"cycles{spp}")
                ladder.append({"spp": spp, "cpu_s": cpu_s,
                               "error": compare.rel_rmse(str(exr), ref)[0]})
            noise = compare.fit_noise(ladder, n_ref)
            c0, c1 = compare.fit_cpu(ladder)
            for suffix, chosen, lgh_exr, lgh_cpu in lghs:
                e, mean_ratio, rgb = compare.rel_rmse(str(lgh_exr), ref)
                truth2 = e * e - noise / n_ref
                record = {"sampling": chosen, "lgh_cpu_s": lgh_cpu, "lgh_error": e,
                          "lgh_mean_ratio": mean_ratio, "lgh_rel_rmse_rgb": rgb["rel_rmse_rgb"],
                          "reference_spp": n_ref, "cycles_noise_a": noise, "ladder": ladder}
                if truth2 > 0.0:
                    n_star = noise / truth2
                    record.update({"lgh_error_truth": math.sqrt(truth2), "cycles_spp": n_star,
                                   "cycles_cpu_s": c0 + c1 * n_star,
                                   "speedup": (c0 + c1 * n_star) / lgh_cpu})
                results[name + suffix] = record
                print(name + suffix, json.dumps(record), file=sys.stderr)
    json.dump(results, json_out, indent=1)
    json_out.write("\n")
    json_out.flush()
    os._exit(0)


if __name__ == "__main__":
    main()
