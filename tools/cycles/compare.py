#!/usr/bin/env python3
"""lgh against Blender Cycles at equal error: the comparison of tools/cycles/README.md.

For each scene: write the volume as OpenVDB (both renderers read that file), render a converged
Cycles reference (several seeds averaged), a ladder of Cycles renders at rising samples per
pixel, and lgh with the settings under test; then the relative RMSE of luminance of each against
the reference, and the Cycles samples and CPU-seconds at which Cycles' own error equals lgh's.

    python3 tools/cycles/compare.py [--scenes fireball64,explosion128,fire56] [--work DIR] ...

Needs: Blender (`blender`, 3.x or later, on PATH or --blender), Debian's python3-openvdb (for
/usr/bin/python3), a Python with numpy and OpenEXR (this script), and a release build of lgh
(`cargo build --release -p lgh-cli`, and `-p lgh-volume --example export_grids`). Not part of CI:
a run takes about an hour on 2 cores. Every render is kept in --work and reused when it exists
(delete a file to redo it); results go to WORK/results.json and a Markdown table on stdout.

How the error is read. Each Cycles render's error against the reference includes the
reference's own noise. With a per-pixel variance `a` per sample, a render of n samples against
a reference of N samples errs by e(n)^2 = a (1/n + 1/N) (independent noise), so `a` is fitted
over the ladder, Cycles' error against the true image is sqrt(a/n), and lgh's, measured as e,
is sqrt(e^2 - a/N) (lgh has no noise). Cycles reaches lgh's error at n* = a / (e^2 - a/N)
samples, whose CPU-seconds come from a straight-line fit of the ladder's CPU-seconds in n.

At 1280x720 a converged Cycles image would take hours on 2 cores: Cycles is timed there at a
few samples (CPU-seconds per sample and fixed cost from the fit), and its error per sample is
taken from the 128x128 ladder (a pixel's noise does not depend on the image size; the pixels
are smaller at 720p, each averaging less of the image, so this is an approximation); lgh's
error is likewise its 128x128 error. Both are said in the output.
"""
import argparse
import json
import math
import os
import re
import resource
import shutil
import subprocess
import sys
import time

import numpy as np
import OpenEXR
import Imath

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

# The scenes: how to make the OpenVDB file, and the medium both renderers use.
SCENES = {
    # The older soft fireball (lgh_volume::procedural::procedural) at 64^3, t = 0.5 s.
    "fireball64": {"kind": "fireball", "res": 64, "time": 0.5},
    # The demo's explosion (lgh_volume::procedural::explosion) at 128^3, t = 0.5 s.
    "explosion128": {"kind": "explosion", "res": 128, "time": 0.5},
    # The dev fire's frame 56 (Blender's own cache: density, temperature and flame).
    "fire56": {"vdb": "volumes/blender_fire_pesichra/data/fluid_data_0056.vdb", "flame": True,
               "temperature_scale": 1000.0,
               # From the front (-Y, Blender's Z up) at the centre of its smoke.
               "camera": "0.53,-2.16,0.455,0.53,0.34,0.455,40"},
}
# The medium of the comparison (the issue's): sigma_t = 4 density, albedo 0.7, blackbody
# emission from a kelvin temperature grid, camera at (0, -4, 0) looking at the origin, 40 deg.
MEDIUM = {"density_scale": 4.0, "albedo": 0.7}
CAMERA = "0,-4,0,0,0,0,40"

# lgh's settings under test: name -> extra arguments of `lgh explosion`.
LGH_SETTINGS = {
    # lgh explosion's defaults (Blender's model without a temperature cut-off, multiple
    # scattering until a depth adds less than 1%, voxel lights, coarse lights' shadows as
    # volume lights, the lighting cache, rays a pixel by --pixel-samples auto).
    "default": [],
    # The same with a 2x2 box filter over each pixel, as Cycles' one-pixel box.
    "box2": ["--pixel-samples", "2"],
    # The defaults with the emission between voxels as Cycles 4.x and later interpolate it
    # (each grid on its own): what Cycles 5.2 renders.
    "attributes": ["--emission-interpolation", "attributes"],
    # The defaults before coarse lights were shadowed as volume lights and pixels box-filtered
    # by default: coarse lights' shadows as points, pixel centres.
    "points": ["--shadows", "raymarch", "--pixel-samples", "1"],
    # Slower and closer: depths down to 0.1%, every light at every sample, half-voxel steps.
    "fine": ["--scatter-stop", "0.001", "--lighting-cache", "none", "--step", "0.5"],
    # Single scattering, as lgh explosion rendered by default before.
    "single": ["--scatter-depth", "0", "--min-temperature", "800"],
    # The best before: the paper's point lights, 8 depths at every voxel, 800 K cut.
    "paper-d8": ["--scatter-depth", "8", "--near-field", "clamp", "--scatter-spacing", "1",
                 "--min-temperature", "800"],
}


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def read_exr(path):
    f = OpenEXR.InputFile(path)
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    pt = Imath.PixelType(Imath.PixelType.FLOAT)
    ch = [np.frombuffer(f.channel(c, pt), dtype=np.float32).reshape(h, w) for c in "RGB"]
    return np.stack(ch, axis=-1).astype(np.float64)


def write_exr(path, rgb):
    h, w, _ = rgb.shape
    header = OpenEXR.Header(w, h)
    f32 = Imath.Channel(Imath.PixelType(Imath.PixelType.FLOAT))
    header["channels"] = {c: f32 for c in "RGB"}
    out = OpenEXR.OutputFile(path + ".tmp", header)
    out.writePixels({c: rgb[..., i].astype(np.float32).tobytes() for i, c in enumerate("RGB")})
    out.close()
    os.replace(path + ".tmp", path)


def write_volume(prefix, dims, voxel_size, origin, grids):
    """A +Y-up volume as lgh-volume's `export` writes one — `PREFIX.NAME.f32` for each of
    `grids` (name -> values, x fastest: an (nz, ny, nx) array or flat) and `PREFIX.json` —
    turned into `PREFIX.vdb` by write_vdb.py (Debian's python3-openvdb, /usr/bin/python3).
    Returns the VDB's path."""
    nx, ny, nz = dims
    for name, values in grids.items():
        flat = np.asarray(values, dtype="<f4").ravel()
        if flat.size != nx * ny * nz:
            sys.exit(f"write_volume: grid {name} has {flat.size} values, not {nx}x{ny}x{nz}")
        flat.tofile(f"{prefix}.{name}.f32")
    meta = {"dims": list(dims), "voxel_size": voxel_size, "origin": list(origin), "up": "y",
            "grids": list(grids)}
    with open(prefix + ".json", "w") as f:
        json.dump(meta, f)
    run_cpu(["/usr/bin/python3", os.path.join(HERE, "write_vdb.py"), prefix])
    return prefix + ".vdb"


def luminance(rgb):
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


LGH = os.path.join(ROOT, "target/release/lgh")


def rel_rmse(img, ref):
    """(relative RMSE of luminance by `lgh compare`, the project's one metric; mean ratio; the
    same channel by channel: {"rel_rmse_rgb", "mean_ratio_rgb"} as `lgh compare --json` gives
    them)."""
    diff = img + ".diff.png"
    out = subprocess.run([LGH, "compare", "--json", "--diff", diff, img, ref],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if out.returncode != 0:
        sys.exit(f"lgh compare {img} {ref}: {out.stderr.strip()}")
    os.remove(diff)
    a, b = luminance(read_exr(img)), luminance(read_exr(ref))
    j = json.loads(out.stdout)
    rgb = {k: j[k] for k in ("rel_rmse_rgb", "mean_ratio_rgb", "mean_rgb", "reference_mean_rgb")}
    return float(j["rel_rmse"]), float(np.mean(a) / np.mean(b)), rgb


def channels(values, off=0.0, scale=100.0):
    """Three channels' figures as "r / g / b" (a missing channel as –)."""
    return " / ".join("–" if v is None else f"{scale * (v - off):+.1f}" if off else
                      f"{scale * v:.1f}" for v in values)


def run_cpu(cmd, **kw):
    """Runs cmd; returns (stdout+stderr, wall seconds, CPU-seconds of the child)."""
    c0, t0 = resource.getrusage(resource.RUSAGE_CHILDREN), time.time()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw)
    c1, t1 = resource.getrusage(resource.RUSAGE_CHILDREN), time.time()
    if p.returncode != 0:
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout[-3000:]}")
    cpu = (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime)
    return p.stdout, t1 - t0, cpu


def step_suffix(step_rate):
    """What a file's or a result's name adds for Cycles' volume step rate: nothing at Blender's
    default 1 (the names of before it), `_r0.25` at 0.25."""
    return "" if step_rate == 1.0 else f"_r{step_rate:g}"


class Runner:
    def __init__(self, a):
        self.a = a
        self.work = a.work
        os.makedirs(self.work, exist_ok=True)
        self.results_path = os.path.join(self.work, "results.json")
        self.results = json.load(open(self.results_path)) if os.path.exists(
            self.results_path) else {}

    def save(self):
        json.dump(self.results, open(self.results_path + ".tmp", "w"), indent=1)
        os.replace(self.results_path + ".tmp", self.results_path)

    def vdb(self, name, scene):
        if "vdb" in scene:
            path = os.path.join(self.a.shared_data, scene["vdb"])
            if not os.path.exists(path):
                log(f"{name}: {path} is absent (--shared-data): skipped")
                return None
            return path
        prefix = os.path.join(self.work, name)
        if not os.path.exists(prefix + ".vdb"):
            run_cpu([self.a.export_grids, scene["kind"], str(scene["res"]), str(scene["time"]),
                     prefix])
            run_cpu(["/usr/bin/python3", os.path.join(HERE, "write_vdb.py"), prefix])
        return prefix + ".vdb"

    def scene_args(self, scene):
        return {"camera": scene.get("camera", CAMERA) or CAMERA,
                "temperature_scale": scene.get("temperature_scale", 1.0),
                "flame": scene.get("flame", False)}

    def cycles(self, name, vdb, scene, spp, seed, width, height, step_rate=1.0):
        """One Cycles render (kept and reused): `step_rate` is Cycles' volume step rate, whose
        default 1 keeps the files' and results' names of before it."""
        rate = step_suffix(step_rate)
        key = f"cycles/{name}/{width}x{height}/{spp}spp/seed{seed}{rate}"
        out = os.path.join(self.work,
                           f"{name}_cycles_{width}x{height}_{spp}spp_s{seed}{rate}.exr")
        if key in self.results and os.path.exists(out):
            return self.results[key]
        s = self.scene_args(scene)
        script = os.path.join(HERE, "render_cycles.py")
        if self.a.bpy:
            # Blender as a Python module (PyPI's bpy): the script runs in that Python.
            cmd = [self.a.bpy, script, "--"]
        else:
            cmd = [self.a.blender, "-b", "--factory-startup", "--python", script, "--"]
        cmd += ["--vdb", vdb, "--out", out, "--spp", str(spp), "--seed", str(seed),
                "--width", str(width), "--height", str(height), "--threads",
                str(self.a.threads), "--camera", s["camera"],
                "--density-scale", str(MEDIUM["density_scale"]),
                "--albedo", str(MEDIUM["albedo"]),
                "--temperature-scale", str(s["temperature_scale"]),
                "--bounces", str(self.a.bounces), "--step-rate", str(step_rate)]
        if s["flame"]:
            cmd.append("--flame")
        if self.a.shift_half_voxel:
            cmd.append("--shift-half-voxel")
        log(f"cycles {name} {width}x{height} {spp} spp seed {seed}"
            + (f" step rate {step_rate:g}" if rate else ""))
        text, wall, cpu = run_cpu(cmd)
        line = [l for l in text.splitlines() if l.startswith("CYCLES ")][-1]
        r = json.loads(line[len("CYCLES "):])
        r["process_cpu_s"] = cpu
        r["out"] = out
        self.results[key] = r
        self.save()
        return r

    def reference(self, name, vdb, scene):
        runs = [self.cycles(name, vdb, scene, self.a.ref_spp, 1 + i, 128, 128)
                for i in range(self.a.ref_seeds)]
        n_ref = self.a.ref_spp * self.a.ref_seeds
        out = os.path.join(self.work, f"{name}_reference_{n_ref}spp.exr")
        if not os.path.exists(out):
            write_exr(out, sum(read_exr(r["out"]) for r in runs) / len(runs))
        # Each seed against the mean of the others: the noise of one seed's image (plus the
        # others' mean), a check of the model e^2 = a (1/n + 1/N) on the reference itself.
        spread = []
        for i, r in enumerate(runs):
            others = [read_exr(q["out"]) for j, q in enumerate(runs) if j != i]
            tmp = os.path.join(self.work, f"{name}_others_{i}.exr")
            write_exr(tmp, sum(others) / len(others))
            spread.append(rel_rmse(r["out"], tmp)[0])
            os.remove(tmp)
        return out, n_ref, spread

    def lgh(self, name, vdb, scene, setting, width, height):
        key = f"lgh/{name}/{width}x{height}/{setting}"
        out = os.path.join(self.work, f"{name}_lgh_{width}x{height}_{setting}.exr")
        if key in self.results and os.path.exists(out):
            return self.results[key]
        s = self.scene_args(scene)
        cmd = [self.a.lgh, "explosion", "--vdb", vdb, "--out", out, "--camera", s["camera"],
               "--width", str(width), "--height", str(height), "--threads",
               str(self.a.threads), "--density-scale", str(MEDIUM["density_scale"]),
               "--albedo", str(MEDIUM["albedo"]), "--temperature-scale",
               str(s["temperature_scale"]), "--no-domain-offset", "--quiet"]
        cmd += LGH_SETTINGS[setting]
        log(f"lgh {name} {width}x{height} {setting}")
        text, wall, cpu = run_cpu(cmd)
        r = {"setting": setting, "args": LGH_SETTINGS[setting], "wall_s": round(wall, 3),
             "cpu_s": round(cpu, 3), "out": out, "summary": text.strip().splitlines()[-1:]}
        self.results[key] = r
        self.save()
        return r


def figure(path, images, labels):
    """Side by side, one tone map for all (the first image's 99.5th percentile of luminance
    to white, then sRGB), each labelled below: a PNG for the docs (needs Pillow)."""
    from PIL import Image, ImageDraw
    imgs = [read_exr(f) for f in images]
    white = np.quantile(luminance(imgs[0]), 0.995)
    tiles = []
    for img in imgs:
        x = np.clip(img / white, 0.0, 1.0)
        srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
        tiles.append((srgb * 255 + 0.5).astype(np.uint8))
    h, w, _ = tiles[0].shape
    band = 18
    out = Image.new("RGB", (w * len(tiles), h + band), (0, 0, 0))
    draw = ImageDraw.Draw(out)
    for i, (t, label) in enumerate(zip(tiles, labels)):
        out.paste(Image.fromarray(t), (i * w, 0))
        draw.text((i * w + 4, h + 3), label, fill=(255, 255, 255))
    out.save(path)


def fit_noise(ladder, n_ref):
    """Least squares of e^2 = a (1/n + 1/N) over the ladder: a."""
    x = np.array([1.0 / r["spp"] + 1.0 / n_ref for r in ladder])
    y = np.array([r["error"] ** 2 for r in ladder])
    return float(x @ y / (x @ x))


def fit_cpu(ladder):
    """CPU-seconds = c0 + c1 n over the ladder (least squares)."""
    n = np.array([r["spp"] for r in ladder], dtype=float)
    c = np.array([r["cpu_s"] for r in ladder])
    c1, c0 = np.polyfit(n, c, 1)
    return float(c0), float(c1)


def add_common_arguments(p):
    """The arguments compare.py and caches.py share: the programs run and where they run."""
    p.add_argument("--bpy", default=None,
                   help="a Python with PyPI's bpy (Blender as a module, e.g. 5.2.3 under Python "
                        "3.13): Cycles runs there instead of --blender")
    p.add_argument("--lgh", default=os.path.join(ROOT, "target/release/lgh"))
    p.add_argument("--export-grids",
                   default=os.path.join(ROOT, "target/release/examples/export_grids"),
                   help="lgh-volume's export_grids example, which writes the procedural volumes "
                        "(fireball64, explosion128) for Cycles: `cargo build --release "
                        "-p lgh-volume --example export_grids`")
    p.add_argument("--shared-data", default=os.path.join(ROOT, "..", "shared", "data"))
    p.add_argument("--threads", type=int, default=2)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scenes", default="fireball64,explosion128,fire56")
    p.add_argument("--work", default="cycles-compare")
    p.add_argument("--blender", default=shutil.which("blender") or "blender")
    add_common_arguments(p)
    p.add_argument("--bounces", type=int, default=128,
                   help="Cycles' volume (and total) bounces (Blender's default volume: 0)")
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--ref-seeds", type=int, default=4)
    p.add_argument("--ladder", default="16,64,256,1024")
    p.add_argument("--hd-spp", default="2,8", help="Cycles' samples timed at 1280x720")
    p.add_argument("--settings", default=",".join(LGH_SETTINGS))
    p.add_argument("--no-hd", action="store_true", help="skip the 1280x720 rows")
    p.add_argument("--hd-settings", default="default",
                   help="the lgh settings also rendered at 1280x720")
    p.add_argument("--only-reference", action="store_true",
                   help="render the references and stop (nothing timed: run it beside other work)")
    p.add_argument("--shift-half-voxel", action="store_true",
                   help="Blender 3.x: voxel i drawn over [i, i+1] (off by half a voxel)")
    a = p.parse_args()
    global LGH
    LGH = a.lgh
    if a.shift_half_voxel is False:
        ask = ([a.bpy, "-c", "import bpy; print('Blender', bpy.app.version_string)"] if a.bpy
               else [a.blender, "--version"])
        v = subprocess.run(ask, stdout=subprocess.PIPE, text=True).stdout
        m = re.search(r"Blender (\d+)\.", v)
        if m and int(m.group(1)) < 4:
            log(f"Blender {m.group(1)}.x: shifting the volume by half a voxel (OpenVDB's placement)")
            a.shift_half_voxel = True
    r = Runner(a)
    table = []
    for name in a.scenes.split(","):
        scene = SCENES[name]
        vdb = r.vdb(name, scene)
        if vdb is None:
            continue
        ref, n_ref, spread = r.reference(name, vdb, scene)
        if a.only_reference:
            continue
        ladder = []
        for spp in [int(s) for s in a.ladder.split(",")]:
            c = r.cycles(name, vdb, scene, spp, 0, 128, 128)
            e, mean, rgb = rel_rmse(c["out"], ref)
            ladder.append({"spp": spp, "cpu_s": c["cpu_s"], "wall_s": c["wall_s"], "error": e,
                           "mean_ratio": mean, **rgb})
        noise = fit_noise(ladder, n_ref)
        c0, c1 = fit_cpu(ladder)
        ref_noise = math.sqrt(noise / n_ref)
        hd = None
        if not a.no_hd:
            runs = [r.cycles(name, vdb, scene, int(s), 0, 1280, 720) for s in a.hd_spp.split(",")]
            hd = fit_cpu([{"spp": q["spp"], "cpu_s": q["cpu_s"]} for q in runs])
        rows = []
        for setting in a.settings.split(","):
            q = r.lgh(name, vdb, scene, setting, 128, 128)
            e, mean, rgb = rel_rmse(q["out"], ref)
            true_e = math.sqrt(max(e * e - noise / n_ref, 0.0))
            n_star = noise / true_e ** 2 if true_e > 0 else float("inf")
            cyc_cpu = c0 + c1 * n_star
            row = {"setting": setting, "cpu_s": q["cpu_s"], "wall_s": q["wall_s"],
                   "error": e, "error_vs_truth": true_e, "mean_ratio": mean,
                   "cycles_spp_at_equal_error": n_star, "cycles_cpu_s_at_equal_error": cyc_cpu,
                   "speedup_128": cyc_cpu / q["cpu_s"], **rgb}
            if hd is not None and setting in a.hd_settings.split(","):
                h = r.lgh(name, vdb, scene, setting, 1280, 720)
                hd_cpu = hd[0] + hd[1] * n_star
                row.update({"cpu_s_720p": h["cpu_s"], "cycles_cpu_s_720p_at_equal_error": hd_cpu,
                            "speedup_720p": hd_cpu / h["cpu_s"]})
            rows.append(row)
        summary = {"scene": name, "reference_spp": n_ref, "reference_noise": ref_noise,
                   "reference_seed_spread": spread, "cycles_noise_per_spp": noise,
                   "cycles_cpu_fit_128": [c0, c1], "cycles_cpu_fit_720p": hd,
                   "ladder": ladder, "lgh": rows}
        try:
            shown = [ref, r.lgh(name, vdb, scene, "box2", 128, 128)["out"],
                     r.lgh(name, vdb, scene, "default", 128, 128)["out"],
                     r.cycles(name, vdb, scene, 256, 0, 128, 128)["out"]]
            figure(os.path.join(r.work, f"{name}.png"), shown,
                   [f"Cycles {n_ref} spp", "lgh --pixel-samples 2", "lgh default", "Cycles 256 spp"])
        except ImportError:
            log("no Pillow: no side-by-side figure")
        r.results[f"summary/{name}"] = summary
        r.save()
        table.append(summary)
    for s in table:
        print(f"\n### {s['scene']} (reference: {s['reference_spp']} spp, noise "
              f"{100 * s['reference_noise']:.2f}%)\n")
        print("| renderer | CPU-s 128² | error vs reference | error vs truth | mean / reference |"
              " R / G / B error (%) | R / G / B mean vs reference (%) |"
              " Cycles spp at equal error | Cycles CPU-s | speed-up 128² | speed-up 720p |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for l in s["ladder"]:
            true_e = math.sqrt(s["cycles_noise_per_spp"] / l["spp"])
            print(f"| Cycles {l['spp']} spp | {l['cpu_s']:.1f} | {100 * l['error']:.2f}% | "
                  f"{100 * true_e:.2f}% | {l['mean_ratio']:.3f} | "
                  f"{channels(l['rel_rmse_rgb'])} | {channels(l['mean_ratio_rgb'], 1.0)} |"
                  " | | | |")
        for row in s["lgh"]:
            hd = f"{row['speedup_720p']:.1f}×" if "speedup_720p" in row else "—"
            print(f"| lgh {row['setting']} | {row['cpu_s']:.1f} | {100 * row['error']:.2f}% | "
                  f"{100 * row['error_vs_truth']:.2f}% | {row['mean_ratio']:.3f} | "
                  f"{channels(row['rel_rmse_rgb'])} | {channels(row['mean_ratio_rgb'], 1.0)} | "
                  f"{row['cycles_spp_at_equal_error']:.0f} | "
                  f"{row['cycles_cpu_s_at_equal_error']:.1f} | {row['speedup_128']:.2f}× | {hd} |")


if __name__ == "__main__":
    main()
