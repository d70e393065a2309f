#!/usr/bin/env python3
"""lgh against Blender Cycles on real simulation caches, at equal error, at 128x128 and, for the
scenes named by --hd-scenes, measured at 1280x720 too.

The scenes are fires that Blender's own simulator (Mantaflow) baked — the dev fire's frame 56
(`../shared/data`) and the four fires of tools/caches/bake.py (a thin "fire" and a dense
"smoky" one, each at 64 and 128 cells; frame 50 of 60) — each read by both renderers from the
cache's OpenVDB file with tools/cycles/compare.py's medium (extinction 4 x density, albedo 0.7,
blackbody emission of `temperature` x 1000 K times `flame`, 128 volume bounces in Cycles). The
baked fires are seen from -Y, the camera framing the smoke's active box at 40 deg vertically.

    python3 tools/cycles/caches.py [--work cycles-caches] [--bpy target/py313/bin/python] ...

One run measures one Cycles: Debian's `blender` (3.4.1: lgh's settings `default` and `adaptive`)
or, with --bpy, PyPI's bpy (5.2.3: `attributes` and `attributes-adaptive`, the emission
interpolated as Cycles 4.x and later do). The method at 128x128 is compare.py's (its Runner,
files and fits): a converged reference of --ref-seeds x --ref-spp, a ladder of sample counts
fitted by e^2 = a (1/n + 1/N), lgh's error against the truth sqrt(e^2 - a/N), and the Cycles
samples n* = a / e_truth^2 and CPU-seconds (a line through the ladder's) at which Cycles' error
equals lgh's.

At 1280x720 (--hd-scenes) the same is measured, not modelled: a reference of --hd-ref-seeds x
--hd-ref-spp at 1280x720, a ladder there (--hd-ladder) whose errors against it fit the 720p
`a`, lgh's 720p renders against that reference. Cycles' noise in the reference is removed by
the same sqrt(e^2 - a/N), so the reference need not be converged, only its noise known (each
seed against the others checks it). Beside it, compare.py's model (Cycles' error per sample from
the 128x128 ladder, lgh's error its 128x128 error), to check that model at this point.

With --ref-step-rate R (Cycles 3.x and 4.x, which ray-march a volume in steps of R voxels;
Blender's default is 1) every reference is also rendered at step R, and both renderers are
measured against that finer step's image, the truth of the model: Cycles at its default step
errs by sqrt(b^2 + a/n) against it (b the default step's bias), at step R by sqrt(a_R/n), and
its cost at lgh's error is the cheaper of the two (`Truth`; docs/cycles.md, "Cycles 3.4.1's
volume step").

Prints the results as JSON on standard output (what tools/figures records), a Markdown table on
standard error and into WORK/caches-VERSION.md. Every render is kept in --work and reused (delete
a file or its results.json entry to redo it); --only-reference renders the untimed references
and stops; --remeasure renders the timed part again (the ladders, lgh), keeping the references.
Needs what compare.py needs, and the baked fires (python3 tools/caches/bake.py; a scene whose
cache is absent is skipped with a message). Not part of CI: hours on 2 cores.
"""
import argparse
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)

import compare  # noqa: E402  (tools/cycles/compare.py: the method, the files, the fits)

#: The baked fires: name -> (tools/caches/bake.py's folder, frame).
BAKED = {f"{case}{res}": (f"{case}-{res}", 50) for case in ("fire", "smoky") for res in (64, 128)}

#: lgh's settings measured against each Cycles (compare.py's names; the adaptive ones added).
SETTINGS = {
    "3": ["default", "adaptive"],
    "5": ["attributes", "attributes-adaptive"],
}
compare.LGH_SETTINGS.setdefault("adaptive", ["--pixel-samples", "adaptive"])
compare.LGH_SETTINGS.setdefault("attributes-adaptive",
                                ["--emission-interpolation", "attributes",
                                 "--pixel-samples", "adaptive"])

#: The camera's vertical field of view (compare.py's), and the margin around the smoke's box.
FOV_DEGREES = 40.0
MARGIN = 1.1

#: The active box of a grid in world coordinates, by the official library (python3-openvdb).
BOX = r"""
import sys, json, pyopenvdb as vdb
g = vdb.read(sys.argv[1], "density")
lo, hi = g.evalActiveVoxelBoundingBox()
print(json.dumps([g.transform.indexToWorld(lo), g.transform.indexToWorld(hi),
                  g.transform.voxelSize()[0]]))
"""


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def framing(vdb):
    """compare.py's camera string for a cache: from -Y at the centre of the density's active
    box (its voxels' cells), far enough that the box's front fits the vertical field of view
    (and the horizontal one of a square image) with a 10% margin."""
    out = subprocess.run(["/usr/bin/python3", "-c", BOX, vdb], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"caches.py: cannot read {vdb}'s density: {out.stderr.strip()[-500:]}")
    lo, hi, voxel = json.loads(out.stdout)
    lo = [c - voxel / 2 for c in lo]
    hi = [c + voxel / 2 for c in hi]
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    half = [(b - a) / 2 for a, b in zip(lo, hi)]
    distance = half[1] + MARGIN * max(half[0], half[2]) / math.tan(math.radians(FOV_DEGREES / 2))
    eye = (centre[0], centre[1] - distance, centre[2])
    return ",".join(f"{v:.4f}" for v in (*eye, *centre, FOV_DEGREES))


def scenes(a):
    """compare.SCENES entries for the scenes asked for (the baked fires added): name -> scene,
    or a message saying why it is skipped."""
    out = {}
    for name in a.scenes.split(","):
        if name in BAKED:
            folder, frame = BAKED[name]
            vdb = os.path.abspath(os.path.join(a.caches, folder, "data",
                                               f"fluid_data_{frame:04d}.vdb"))
            if not os.path.exists(vdb):
                out[name] = (f"{vdb} is absent: bake it with `python3 tools/caches/bake.py "
                             f"--out {a.caches}`")
                continue
            compare.SCENES[name] = {"vdb": vdb, "flame": True, "temperature_scale": 1000.0,
                                    "camera": framing(vdb)}
        elif name not in compare.SCENES:
            sys.exit(f"caches.py: no scene {name!r} (the baked {', '.join(BAKED)}, or "
                     f"compare.py's {', '.join(compare.SCENES)})")
        elif "kind" in compare.SCENES[name] and not os.access(a.export_grids, os.X_OK):
            sys.exit(f"caches.py: {name} is procedural and its grids are written by "
                     f"{a.export_grids}, which is absent: `cargo build --release -p lgh-volume "
                     f"--example export_grids` (or give --export-grids)")
        out[name] = compare.SCENES[name]
    return out


def ladder_rows(r, name, vdb, scene, counts, ref, width, height):
    rows = []
    for spp in counts:
        c = r.cycles(name, vdb, scene, spp, 0, width, height)
        e, mean, rgb = compare.rel_rmse(c["out"], ref)
        rows.append({"spp": spp, "cpu_s": c["cpu_s"], "wall_s": c["wall_s"], "error": e,
                     "mean_ratio": mean, **rgb})
    return rows


def reference(r, name, vdb, scene, spp, seeds, width, height, step_rate=1.0):
    """The mean of `seeds` Cycles renders of `spp` samples (seeds 1, 2, ...; at another step
    rate than Blender's default 101, 102, ...: a seed's samples at another step are correlated
    with its own, which would hide the step's bias) at width x height, and each seed's error
    against the mean of the others (the reference's own noise, a check of the fitted `a`); and
    the seeds' renders."""
    first = 1 if step_rate == 1.0 else 101
    runs = [r.cycles(name, vdb, scene, spp, first + i, width, height, step_rate)
            for i in range(seeds)]
    rate = compare.step_suffix(step_rate)
    out = os.path.join(r.work, f"{name}_reference_{width}x{height}_{spp * seeds}spp{rate}.exr")
    if not os.path.exists(out):
        compare.write_exr(out, sum(compare.read_exr(q["out"]) for q in runs) / seeds)
    spread = []
    for i, q in enumerate(runs):
        tmp = os.path.join(r.work, f"{name}_others_{width}x{height}.exr")
        compare.write_exr(tmp, sum(compare.read_exr(p["out"]) for j, p in enumerate(runs)
                                   if j != i) / (seeds - 1))
        spread.append(compare.rel_rmse(q["out"], tmp)[0])
        os.remove(tmp)
    return out, spp * seeds, spread, runs


class Truth:
    """What lgh's and Cycles' errors are measured against at one resolution, and what Cycles
    pays for an error.

    Without a finer step (`fine` None) the truth is Cycles' converged image at Blender's default
    volume step rate (1): the reference `ref` of `n_ref` samples, noisy by `a / n_ref`, `a` the
    ladder's fitted noise a sample, and Cycles at `n` samples errs by `sqrt(a / n)`.

    With one (`fine`: reference()'s answer at --ref-step-rate), the truth is that finer step's
    converged image. Cycles 3.x and 4.x ray-march a volume in steps of `rate` voxels, which
    biases their image (docs/cycles.md, "Cycles 3.4.1's volume step"): at Blender's default step
    Cycles errs by `sqrt(b^2 + a / n)` against the truth, `b` its converged image's bias — each
    reference against the other less both references' noise — so it reaches an error `e` at
    `n = a / (e^2 - b^2)` samples, and never where `e <= b`; at the finer step it errs by
    `sqrt(a_f / n)`, `a_f` the finer reference's noise a sample (its seeds against each other),
    at a CPU cost a sample from the finer reference's renders (the ladder's fixed cost kept).
    Cycles' cost at an error is the cheaper of the two."""

    def __init__(self, ref, n_ref, noise, cpu_fit, fine=None, step_rate=1.0, between=None):
        """`fine`: reference()'s answer at `step_rate`; `between`: the default step's reference
        against it (compare.rel_rmse's error, mean ratio and channels)."""
        self.noise, self.cpu_fit, self.step_rate = noise, cpu_fit, step_rate
        self.image, self.var, self.bias, self.fine = ref, noise / n_ref, 0.0, None
        if fine is None:
            return
        f_ref, f_n, f_spread, f_runs = fine
        k = len(f_spread)
        # Each seed against the mean of the others errs by sigma^2 k / (k - 1), sigma^2 a
        # seed's noise; the mean of k seeds by sigma^2 / k.
        f_var = sum(x * x for x in f_spread) * (k - 1) / k ** 3
        e, mean, rgb = between
        self.image, self.var = f_ref, f_var
        self.bias = math.sqrt(max(e * e - noise / n_ref - f_var, 0.0))
        c0 = cpu_fit[0]
        c1 = sum((q["cpu_s"] - c0) / q["spp"] for q in f_runs) / len(f_runs)
        self.fine = {"step_rate": step_rate, "reference": f_ref, "reference_spp": f_n,
                     "reference_noise": math.sqrt(f_var), "reference_seed_spread": f_spread,
                     "cycles_noise_per_spp": f_var * f_n, "cycles_cpu_fit": [c0, c1],
                     "default_step_bias": self.bias, "default_step_mean_ratio": mean,
                     "default_step_mean_ratio_rgb": rgb["mean_ratio_rgb"]}

    @classmethod
    def measured(cls, ref, n_ref, noise, cpu_fit, fine, step_rate):
        """The truth of one resolution: the default step's reference measured against the
        finer one where there is one (`fine`, else None)."""
        between = compare.rel_rmse(ref, fine[0]) if fine is not None else None
        return cls(ref, n_ref, noise, cpu_fit, fine, step_rate, between)

    def cpu_s(self, step_rate, n):
        """Cycles' CPU-seconds for `n` samples at one of the two step rates."""
        c0, c1 = self.fine["cycles_cpu_fit"] if step_rate != 1.0 else self.cpu_fit
        return c0 + c1 * n

    def equal_error(self, e):
        """lgh's error `e` against the reference as its error against the truth, and Cycles at
        that error: {"step_rate", "spp", "cpu_s"} at the cheaper step, or None where lgh's error
        is within the reference's noise (the reference cannot tell) or no step reaches it."""
        truth = math.sqrt(max(e * e - self.var, 0.0))
        ways = self.ways(truth) if truth > 0.0 else []
        return truth, min(ways, key=lambda w: w["cpu_s"]) if ways else None

    def ways(self, truth):
        """Each step at which Cycles reaches the error `truth` against the truth: its samples
        and CPU-seconds there."""
        ways = []
        if truth > self.bias:
            ways.append((1.0, self.noise / (truth ** 2 - self.bias ** 2)))
        if self.fine is not None:
            ways.append((self.step_rate, self.fine["cycles_noise_per_spp"] / truth ** 2))
        return [{"step_rate": r, "spp": n, "cpu_s": self.cpu_s(r, n)} for r, n in ways]


def at_equal_error(truth, e, cpu_s):
    """A row's Cycles columns: lgh's error `e` against `truth`'s reference, and Cycles' samples,
    step and CPU-seconds at that error (None where it cannot tell), over lgh's `cpu_s`."""
    t, cycles = truth.equal_error(e)
    row = {"error_vs_truth": t, "cycles_spp_at_equal_error": cycles and cycles["spp"],
           "cycles_cpu_s_at_equal_error": cycles and cycles["cpu_s"],
           "speedup": cycles and cycles["cpu_s"] / cpu_s}
    if truth.fine is not None:
        row["cycles_step_rate_at_equal_error"] = cycles and cycles["step_rate"]
    return row, cycles


def measure(r, a, name, scene, settings):
    vdb = r.vdb(name, scene)
    ref, n_ref, spread, _ = reference(r, name, vdb, scene, a.ref_spp, a.ref_seeds, 128, 128)
    steps = a.ref_step_rate != 1.0
    fine = (reference(r, name, vdb, scene, a.step_ref_spp or a.ref_spp, a.ref_seeds, 128, 128,
                      a.ref_step_rate) if steps else None)
    hd = name in a.hd_scenes.split(",")
    if hd:
        hd_ref, hd_n_ref, hd_spread, _ = reference(r, name, vdb, scene, a.hd_ref_spp,
                                                   a.hd_ref_seeds, 1280, 720)
        hd_fine = (reference(r, name, vdb, scene, a.hd_ref_spp, a.hd_ref_seeds, 1280, 720,
                             a.ref_step_rate) if steps else None)
    if a.only_reference:
        return None
    ladder = ladder_rows(r, name, vdb, scene, [int(s) for s in a.ladder.split(",")], ref,
                         128, 128)
    noise = compare.fit_noise(ladder, n_ref)
    cpu_fit = compare.fit_cpu(ladder)
    truth = Truth.measured(ref, n_ref, noise, cpu_fit, fine, a.ref_step_rate)
    summary = {"scene": name, "camera": scene.get("camera"), "vdb": vdb,
               "reference_spp": n_ref, "reference_noise": math.sqrt(noise / n_ref),
               "reference_seed_spread": spread, "cycles_noise_per_spp": noise,
               "cycles_cpu_fit_128": list(cpu_fit), "ladder": ladder, "lgh": {}}
    if truth.fine is not None:
        summary["fine_step"] = truth.fine
    if hd:
        hd_ladder = ladder_rows(r, name, vdb, scene, [int(s) for s in a.hd_ladder.split(",")],
                                hd_ref, 1280, 720)
        hd_noise = compare.fit_noise(hd_ladder, hd_n_ref)
        hd_cpu_fit = compare.fit_cpu(hd_ladder)
        hd_truth = Truth.measured(hd_ref, hd_n_ref, hd_noise, hd_cpu_fit, hd_fine,
                                  a.ref_step_rate)
        summary["hd"] = {"reference_spp": hd_n_ref, "reference_noise":
                         math.sqrt(hd_noise / hd_n_ref), "reference_seed_spread": hd_spread,
                         "cycles_noise_per_spp": hd_noise, "cycles_cpu_fit": list(hd_cpu_fit),
                         "ladder": hd_ladder}
        if hd_truth.fine is not None:
            summary["hd"]["fine_step"] = hd_truth.fine
    for setting in settings:
        q = r.lgh(name, vdb, scene, setting, 128, 128)
        e, mean, rgb = compare.rel_rmse(q["out"], truth.image)
        columns, cycles = at_equal_error(truth, e, q["cpu_s"])
        row = {"cpu_s": q["cpu_s"], "wall_s": q["wall_s"], "error": e, "mean_ratio": mean,
               **columns, **rgb}
        if hd:
            h = r.lgh(name, vdb, scene, setting, 1280, 720)
            he, hmean, hrgb = compare.rel_rmse(h["out"], hd_truth.image)
            hd_columns, _ = at_equal_error(hd_truth, he, h["cpu_s"])
            # compare.py's model: Cycles' 720p time at the samples (and step) of the 128x128
            # comparison.
            model = cycles and hd_truth.cpu_s(cycles["step_rate"], cycles["spp"])
            row["hd"] = {"cpu_s": h["cpu_s"], "wall_s": h["wall_s"], "error": he,
                         "mean_ratio": hmean, **hd_columns,
                         "modelled_speedup": model and model / h["cpu_s"], **hrgb}
        summary["lgh"][setting] = row
    try:
        shown = [truth.image, r.lgh(name, vdb, scene, settings[0], 128, 128)["out"],
                 r.lgh(name, vdb, scene, settings[-1], 128, 128)["out"],
                 r.cycles(name, vdb, scene, int(a.ladder.split(",")[-1]), 0, 128, 128)["out"]]
        compare.figure(os.path.join(r.work, f"{name}.png"), shown,
                       [f"Cycles {n_ref} spp", f"lgh {settings[0]}", f"lgh {settings[-1]}",
                        f"Cycles {a.ladder.split(',')[-1]} spp"])
    except ImportError:
        log("no Pillow: no side-by-side figure")
    return summary


def num(v, fmt, unit=""):
    """A figure, or "—" where the reference could not tell (None)."""
    return "—" if v is None else f"{v:{fmt}}{unit}"


def step(row):
    """The text `" at step R"` where Cycles reaches lgh's error for less at the finer step R."""
    rate = row.get("cycles_step_rate_at_equal_error")
    return f" at step {rate:g}" if rate is not None and rate != 1.0 else ""


def table(version, results):
    lines = [f"Cycles {version}; lgh's error is the relative RMSE of luminance against the "
             "truth (the reference's noise removed), R / G / B each channel's against the "
             "reference's (its noise not removed); — where the reference cannot tell.", "",
             "| scene | lgh | lgh CPU-s | error | R / G / B (%) | Cycles spp at that error | "
             "Cycles CPU-s | speed-up | 720p: lgh CPU-s, error, Cycles CPU-s, speed-up "
             "(model) |", "|---|---|---|---|---|---|---|---|---|"]
    for s in results:
        for setting, row in s["lgh"].items():
            hd = row.get("hd")
            hd_text = (f"{hd['cpu_s']:.1f}, {100 * hd['error_vs_truth']:.2f}%, "
                       f"{num(hd['cycles_cpu_s_at_equal_error'], '.0f')}, "
                       f"{num(hd['speedup'], '.1f', '×')} "
                       f"({num(hd['modelled_speedup'], '.1f', '×')})" if hd else "—")
            lines.append(f"| {s['scene']} | {setting} | {row['cpu_s']:.1f} | "
                         f"{100 * row['error_vs_truth']:.2f}% | "
                         f"{compare.channels(row['rel_rmse_rgb'])} | "
                         f"{num(row['cycles_spp_at_equal_error'], '.0f')}{step(row)} | "
                         f"{num(row['cycles_cpu_s_at_equal_error'], '.1f')} | "
                         f"{num(row['speedup'], '.2f', '×')} | "
                         f"{hd_text} |")
    for s in results:
        f = s.get("fine_step")
        if f is not None:
            lines.append(f"\n{s['scene']}: the truth is Cycles at step rate {f['step_rate']:g} "
                         f"({f['reference_spp']} samples, {100 * f['reference_noise']:.2f}% "
                         f"noisy); Blender's default step errs by "
                         f"{100 * f['default_step_bias']:.2f}% against it, its mean "
                         f"{f['default_step_mean_ratio']:.4f} of it (R / G / B "
                         f"{' / '.join(num(m, '.4f') for m in f['default_step_mean_ratio_rgb'])}).")
    return "\n".join(lines) + "\n"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scenes", default="fire56," + ",".join(BAKED))
    p.add_argument("--caches", default=os.path.join(ROOT, "target", "caches"),
                   help="tools/caches/bake.py's --out")
    p.add_argument("--work", default="cycles-caches")
    p.add_argument("--blender", default="/usr/bin/blender")
    compare.add_common_arguments(p)
    p.add_argument("--bounces", type=int, default=128)
    p.add_argument("--ref-spp", type=int, default=2048)
    p.add_argument("--ref-seeds", type=int, default=2)
    p.add_argument("--ladder", default="16,64,256,1024")
    p.add_argument("--hd-scenes", default="fire56",
                   help="the scenes also measured at 1280x720 (comma-separated; '' for none)")
    p.add_argument("--hd-ref-spp", type=int, default=256)
    p.add_argument("--hd-ref-seeds", type=int, default=2)
    p.add_argument("--hd-ladder", default="16,64")
    p.add_argument("--remeasure", action="store_true",
                   help="render the timed part again (the ladders and lgh), keeping the "
                        "untimed references: what a figure's refresh runs")
    p.add_argument("--only-reference", action="store_true",
                   help="render the references and stop (untimed: may run beside other work)")
    p.add_argument("--ref-step-rate", type=float, default=1.0,
                   help="Cycles 3.x and 4.x: also render each reference at this volume step "
                        "rate (e.g. 0.25) and measure both renderers against it, Cycles' "
                        "default step's bias included (docs/cycles.md, \"Cycles 3.4.1's volume "
                        "step\"); 1 (Blender's default): against the default step's reference")
    p.add_argument("--step-ref-spp", type=int, default=None,
                   help="the samples of each seed of the finer step's 128x128 reference "
                        "(default --ref-spp; a finer step costs more a sample)")
    a = p.parse_args()
    if not 0.0 < a.ref_step_rate <= 1.0:
        sys.exit(f"caches.py: --ref-step-rate {a.ref_step_rate:g} is not in (0, 1]: a finer "
                 "step than Blender's default converges the volume's march, a coarser one "
                 "does not")
    if a.step_ref_spp is not None and (a.ref_step_rate == 1.0 or a.step_ref_spp < 1):
        sys.exit("caches.py: --step-ref-spp is the samples (at least 1) of the finer step's "
                 "references: give --ref-step-rate too")
    if a.ref_seeds < 2 or a.hd_ref_seeds < 2:
        sys.exit("caches.py: --ref-seeds and --hd-ref-seeds must be at least 2 (each seed "
                 "against the others measures the reference's noise)")
    compare.LGH = a.lgh
    if not os.access(a.lgh, os.X_OK):
        sys.exit(f"caches.py: no lgh at {a.lgh} (cargo build --release -p lgh-cli)")
    ask = ([a.bpy, "-c", "import bpy; print('Blender', bpy.app.version_string)"] if a.bpy
           else [a.blender, "--version"])
    version = subprocess.run(ask, stdout=subprocess.PIPE, text=True).stdout
    major = version.split("Blender ")[-1].split(".")[0] if "Blender " in version else ""
    if major not in ("3", "4", "5"):
        sys.exit(f"caches.py: no Blender answered ({' '.join(ask)})")
    version = version.split("Blender ")[-1].split()[0]
    if major == "5" and a.ref_step_rate != 1.0:
        sys.exit("caches.py: --ref-step-rate: Blender 5.x integrates volumes without steps "
                 "(unbiased, its default): there is no step to converge")
    # compare.Runner's arguments: Blender 3.x draws voxel i over [i, i+1] (half a voxel off).
    a.shift_half_voxel = major == "3"
    settings = SETTINGS["3" if major == "3" else "5"]
    r = compare.Runner(a)
    if a.remeasure:
        # The ladders are seed 0, the references seeds 1, 2, ...
        r.results = {k: v for k, v in r.results.items()
                     if not (k.startswith("lgh/") or k.endswith("/seed0"))}
    results = []
    for name, scene in scenes(a).items():
        if isinstance(scene, str):
            log(f"caches.py: {name}: skipped: {scene}")
            continue
        s = measure(r, a, name, scene, settings)
        if s is not None:
            r.results[f"caches/{name}"] = s
            r.save()
            results.append(s)
    if a.only_reference:
        return
    text = table(version, results)
    with open(os.path.join(a.work, f"caches-{version}.md"), "w") as f:
        f.write(text)
    log(text)
    json.dump({"blender": version, "threads": a.threads, "scenes": {s["scene"]: s
                                                                    for s in results}},
              sys.stdout, indent=1, allow_nan=False)
    print()


if __name__ == "__main__":
    main()
