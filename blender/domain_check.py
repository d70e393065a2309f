"""The add-on's reading of a Mantaflow gas domain against the Blender that can bake one: Debian's
Blender 3.4.1 bakes a small fire (a 2-unit cube domain, 24 cells a side, an icosphere flowing
fire and smoke; plain, with Noise ×2, adaptive, adaptive with Noise) to OpenVDB and renders the domain with Cycles
(1,024 samples, emission and absorption only, a one-pixel box filter, 64×48); then

- ``made_vs_domain``: Cycles 3.4.1's image of a Volume object holding the temperature
  ``lgh_blender/domain.py`` says Cycles makes of the flame, placed where it says Cycles puts the
  domain's voxels, against Cycles' image of the domain (0: the add-on reads the domain as
  Cycles does; Cycles' noise, ``cycles_noise``, is the floor);
- ``lgh_vs_cycles``: the add-on's job of the same domain in bpy 5.2.3 (which cannot bake or load
  a cache, but reads the files), rendered by ``lgh.render_explosion`` with Cycles 3.x's
  interpolation of the temperature, against Cycles' image of the domain.

    target/py313/bin/python blender/domain_check.py      # prints JSON, one record per domain

Needs /usr/bin/blender (3.4.1), bpy 5.2.3, ``lgh`` and Debian's python3-openvdb. The same file
runs inside Blender 3.4.1 (``blender -b --python blender/domain_check.py -- MODE ...``).
"""
import contextlib
import json
import math
import os
import pathlib
import subprocess
import sys
import tempfile
from types import SimpleNamespace

HERE = pathlib.Path(__file__).resolve().parent
#: The environment before bpy 5.2.3 is imported, which points OCIO at its own configuration
#: (too new for Blender 3.4.1's OpenColorIO).
ENVIRONMENT = dict(os.environ)
BLENDER = "/usr/bin/blender"
#: Each domain's flags and the frame rendered: the adaptive domain's frame 2 starts at cell
#: (1, 1, 0) of the whole domain, the adaptive domain with Noise's frame 1 at (2, 2, 0) (their
#: config files' offsets; a noise cell is half a base cell).
CASES = {"base": ([], 6), "noise": (["--noise"], 6), "adaptive": (["--adaptive"], 2),
         "adaptive_noise": (["--adaptive", "--noise"], 1)}
#: The domain: a 2-unit cube at LOCATION, 24 cells a side, baked to frame FRAMES.
LOCATION, RESOLUTION, FRAMES = (0.3, 0.2, 1.0), 24, 6
CAMERA = dict(location=(0.3, -4.0, 0.6), rotation=(88.0, 0.0, 3.0), fov=35.0)
SIZE = (64, 48)


# ---- Inside Blender 3.4.1 -------------------------------------------------------------------

def fire_material(data):
    """Density 4, black scattering and absorption colours (absorption 4 per unit density, no
    scattering), blackbody intensity 1 at 1000 K per unit of temperature, given to ``data``."""
    sys.path.insert(0, str(HERE / "tests"))
    from shading import principled

    principled(data, {"Density": 4.0, "Color": (0, 0, 0, 1), "Absorption Color": (0, 0, 0, 1),
                      "Blackbody Intensity": 1.0, "Temperature": 1000.0})


def look(bpy, scene):
    """The camera, a black world, the render's size: for Cycles and the add-on alike."""
    from mathutils import Euler

    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    cam.location = CAMERA["location"]
    cam.rotation_euler = Euler([math.radians(a) for a in CAMERA["rotation"]])
    cam.data.sensor_fit, cam.data.angle = "VERTICAL", math.radians(CAMERA["fov"])
    world = bpy.data.worlds.new("black")
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    for n in world.node_tree.nodes:
        if n.type == "BACKGROUND":
            n.inputs["Strength"].default_value = 0.0
    scene.world = world
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = *SIZE, 100


def domain_cube(bpy, noise, adaptive):
    """The domain: settings first, its cache directory last (most settings free the cache)."""
    bpy.ops.mesh.primitive_cube_add(size=2.0, location=LOCATION)
    domain = bpy.context.object
    domain.name = "domain"
    ds = domain.modifiers.new("Fluid", "FLUID")
    ds.fluid_type = "DOMAIN"
    ds = ds.domain_settings
    ds.domain_type, ds.resolution_max, ds.cache_data_format = "GAS", RESOLUTION, "OPENVDB"
    ds.cache_type, ds.use_adaptive_domain, ds.use_noise = "ALL", adaptive, noise
    ds.noise_scale = 2
    ds.cache_frame_start, ds.cache_frame_end = 1, FRAMES
    return domain, ds


def in_blender(mode, args):
    import bpy

    if mode == "bake":
        directory = args[0]
        bpy.ops.wm.read_factory_settings(use_empty=True)
        scene = bpy.context.scene
        scene.frame_start, scene.frame_end = 1, FRAMES
        domain, ds = domain_cube(bpy, "--noise" in args, "--adaptive" in args)
        ds.cache_directory = directory
        bpy.ops.mesh.primitive_ico_sphere_add(radius=0.3, location=(0.3, 0.2, 0.4))
        flow = bpy.context.object
        flow.name = "flow"
        f = flow.modifiers.new("Fluid", "FLUID")
        f.fluid_type = "FLOW"
        f.flow_settings.flow_type, f.flow_settings.flow_behavior = "BOTH", "INFLOW"
        bpy.context.view_layer.objects.active = domain
        data = os.path.join(directory, "noise" if "--noise" in args else "data")
        sys.path.insert(0, str(HERE / "tests"))
        from mantaflow import bake

        bake(domain, data, FRAMES, "domain_check.py")
        return
    directory, out, seed, frame = args[0], args[1], int(args[2]), int(args[3])
    bpy.ops.wm.open_mainfile(filepath=os.path.join(directory, "scene.blend"))
    scene = bpy.context.scene
    bpy.data.objects.remove(bpy.data.objects["flow"], do_unlink=True)
    domain = bpy.data.objects["domain"]
    if mode == "made":
        # The made temperature as a Volume object: Cycles 3.x draws voxel i over [i, i + 1]
        # of the file's index space, so the object sits at the domain box's corner, scaled
        # from the file's voxel to the domain's cell (an adaptive domain's file has a voxel of
        # the domain's size over its frame's cells: 2/23, not 2/24).
        bpy.data.objects.remove(domain, do_unlink=True)
        vol = bpy.data.volumes.new("made")
        vol.filepath = os.path.join(directory, "made.vdb")
        obj = bpy.data.objects.new("made", vol)
        obj.location = [c - 1.0 for c in LOCATION]
        obj.scale = (float(args[4]),) * 3
        scene.collection.objects.link(obj)
        fire_material(vol)
    else:
        domain.data.materials.clear()
        fire_material(domain.data)
    look(bpy, scene)
    r = scene.render
    r.engine = "CYCLES"
    r.image_settings.file_format, r.image_settings.color_depth = "OPEN_EXR", "32"
    r.filepath = out
    cy = scene.cycles
    cy.device, cy.samples, cy.seed = "CPU", 1024, seed
    cy.use_adaptive_sampling = cy.use_denoising = False
    cy.max_bounces = cy.volume_bounces = 0
    cy.pixel_filter_type, cy.filter_width = "BOX", 1.0
    scene.frame_set(frame)
    bpy.ops.render.render(write_still=True)


# ---- In bpy 5.2.3 (a process of its own: freeing a domain there may abort) -----------------

def in_bpy(directory, frame, flags, out):
    """The add-on's job of the domain (built anew, its cache ``directory``), rendered."""
    sys.path.insert(0, str(HERE))
    import bpy
    import numpy as np

    import lgh
    from lgh_blender.scene import job

    # The domain's Fluid modifier is off in the viewport, so that bpy 5.2.3's Mantaflow, which
    # aborts on loading a baked adaptive domain, never evaluates it; the add-on reads the
    # modifier's render switch, as F12 does.
    from lgh_blender import domain as reading

    shown = reading.gas_domain
    reading.gas_domain = lambda obj, final=True: shown(obj, True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    domain, ds = domain_cube(bpy, "--noise" in flags, "--adaptive" in flags)
    domain.modifiers["Fluid"].show_viewport = False
    ds.cache_directory = directory
    fire_material(domain.data)
    look(bpy, scene)
    scene.frame_set(frame)
    read = job(bpy.context.evaluated_depsgraph_get())
    settings = dict(read.settings, emission_interpolation="temperature")  # Cycles 3.x's
    np.save(out, lgh.render_explosion(read.vdb, **settings))
    print(json.dumps({"notes": read.notes}))
    sys.stdout.flush()
    os._exit(0)


# ---- The made temperature's file (Debian's python3-openvdb) -------------------------------

MADE = r"""
import sys, numpy as np, pyopenvdb as vdb
src, dst, suffix, ox, oy, oz = sys.argv[1], sys.argv[2], sys.argv[3], *map(int, sys.argv[4:7])
d, f = vdb.read(src, "density" + suffix), vdb.read(src, "flame" + suffix)
lo, hi = d.evalActiveVoxelBoundingBox()
n = [hi[k] - lo[k] + 1 for k in range(3)]
def dense(g):
    a = np.zeros(n, np.float32); g.copyToArray(a, ijk=lo); return a
flame = dense(f)
made = np.where(flame > 0.01, 1.5 + flame * 1.5, 0.0).astype(np.float32)
out = []
for name, a in (("density", dense(d)), ("temperature", made)):
    g = vdb.FloatGrid(); g.copyFromArray(a, ijk=[lo[k] + (ox, oy, oz)[k] for k in range(3)])
    g.name, g.transform = name, d.transform; out.append(g)
vdb.write(dst, grids=out)
"""


def blender(*args):
    """Blender 3.4.1 running this file with ``args``, in the domain's folder (``args[1]``):
    Mantaflow writes its noise tile, ``waveletNoiseTile.bin``, into the working directory."""
    return subprocess.run([BLENDER, "-b", "--factory-startup", "--python", __file__, "--", *args],
                          capture_output=True, text=True, env=ENVIRONMENT, cwd=args[1])


def main():
    # Blender prints to the process's standard output: keep it for the JSON.
    json_out = os.fdopen(os.dup(1), "w")
    os.dup2(2, 1)
    import numpy as np

    sys.path.insert(0, str(HERE / "tests"))
    from mantaflow import retried
    from scenes import read_exr, rel_rmse

    import lgh
    from lgh_blender.domain import frame_offset

    results = {}
    keep = os.environ.get("LGH_DOMAIN_CHECK_DIR")  # to look at the images after
    with (contextlib.nullcontext(keep) if keep else tempfile.TemporaryDirectory()) as tmp:
        for case, (flags, frame) in CASES.items():
            d = pathlib.Path(tmp) / case
            data = d / ("noise" if "--noise" in flags else "data")
            done, baked = retried(
                d, lambda: blender("bake", str(d), *flags),
                lambda: (data / f"fluid_{data.name}_{frame:04d}.vdb").is_file()
                and (d / "scene.blend").is_file())
            if not done:
                sys.exit(f"domain_check.py: Blender 3.4.1 did not bake the {case} domain:\n"
                         f"{baked.stdout[-1500:]}{baked.stderr[-1500:]}")
            for seed in (1, 2):
                blender("cycles", str(d), str(d / f"cycles{seed}.exr"), str(seed), str(frame))
            suffix = "_noise" if "--noise" in flags else ""
            offset = frame_offset(SimpleNamespace(name=case),
                                  SimpleNamespace(use_adaptive_domain="--adaptive" in flags),
                                  str(d / "data" / f"fluid_data_{frame:04d}.vdb"))
            upres = 2 if "--noise" in flags else 1  # the noise grid's cells of a base cell
            subprocess.run(["/usr/bin/python3", "-c", MADE, str(data /
                            f"fluid_{data.name}_{frame:04d}.vdb"), str(d / "made.vdb"), suffix,
                            *(str(c * upres) for c in offset)], check=True)
            cell = 2.0 / (RESOLUTION * (2 if "--noise" in flags else 1))
            voxel = lgh.inspect(d / "made.vdb")["grids"][0]["voxel_size"][0]
            blender("made", str(d), str(d / "made.exr"), "1", str(frame), str(cell / voxel))
            got = subprocess.run([sys.executable, __file__, "bpy", str(d), str(d / "lgh.npy"),
                                  str(frame), *flags], capture_output=True, text=True, cwd=d)
            if got.returncode != 0:
                sys.exit(f"domain_check.py: the add-on's job failed:\n{got.stderr[-2000:]}")
            c1, c2 = read_exr(d / "cycles1.exr"), read_exr(d / "cycles2.exr")
            image = np.load(d / "lgh.npy")
            results[case] = {
                "cycles_noise": rel_rmse(c2, c1) / math.sqrt(2.0),
                "made_vs_domain": rel_rmse(read_exr(d / "made.exr"), c1),
                "lgh_vs_cycles": rel_rmse(image, c1),
                # Each channel against the same channel (blue is where the blackbody differs).
                "lgh_vs_cycles_rgb": [rel_rmse(image[..., k], c1[..., k]) for k in range(3)],
                "offset": offset,
                "notes": json.loads(got.stdout.strip().splitlines()[-1])["notes"],
            }
            print(case, results[case], file=sys.stderr)
    json.dump(results, json_out, indent=1)
    json_out.write("\n")


if __name__ == "__main__":
    if "--" in sys.argv:  # inside Blender 3.4.1
        rest = sys.argv[sys.argv.index("--") + 1:]
        in_blender(rest[0], rest[1:])
    elif len(sys.argv) > 1 and sys.argv[1] == "bpy":
        in_bpy(sys.argv[2], int(sys.argv[4]), sys.argv[5:], sys.argv[3])
    else:
        main()
