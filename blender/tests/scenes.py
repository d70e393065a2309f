"""What the add-on's tests, ``blender/bench.py`` and ``blender/picture.py`` share: scenes built
in bpy (a volume with a Principled Volume, a camera, a black world, the LGH engine), F12 into an
EXR, ``lgh explosion`` with flags written by hand, Cycles as ``tools/cycles`` runs it, and the
missing pieces said (skipped with a message, a failure where ``LGH_REQUIRE_ALL`` is set).
"""
import math
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "blender"))


def missing(what, how):
    if os.environ.get("LGH_REQUIRE_ALL"):
        pytest.fail(f"no {what} ({how})")
    pytest.skip(f"SKIPPED: no {what} ({how})")


try:
    import bpy
    from mathutils import Euler, Matrix, Vector
    from shading import principled  # noqa: F401 (the tests' and the scripts' one)
except ImportError:
    bpy = principled = None

import lgh

FIRE = ROOT.parent / "shared" / "data" / "volumes" / "blender_fire_pesichra" / "data"


def lgh_binary():
    """The `lgh` binary (``$LGH_BIN``, else target/release or target/debug): lgh-py's tests'."""
    sys.path.insert(0, str(ROOT / "lgh-py" / "tests"))
    from test_against_the_cli import lgh_binary as find

    return find()


def read_exr(path):
    import OpenEXR

    with OpenEXR.File(str(path)) as f:
        channels = f.channels()
        if "RGBA" in channels:
            return np.asarray(channels["RGBA"].pixels, dtype=np.float32)[:, :, :3]
        if "RGB" in channels:
            return np.asarray(channels["RGB"].pixels, dtype=np.float32)
        return np.stack([channels[c].pixels for c in "RGB"], axis=-1).astype(np.float32)


def rel_rmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(b ** 2)))


def build(vdb, *, width=48, height=32, eye=(0.0, -4.0, 0.0), rotation=(90.0, 0.0, 0.0),
          lens=50.0, fov=None, shift=(0.0, 0.0), inputs=None, location=(0.0, 0.0, 0.0),
          volume_rotation=(0.0, 0.0, 0.0), scale=1.0, flame=None):
    """A new scene: the volume ``vdb`` with a Principled Volume (``inputs`` set on it; the
    attribute ``flame`` linked to its Blackbody Intensity if given), a perspective camera at
    ``eye`` turned by ``rotation`` (XYZ Euler, degrees) with ``lens`` (or the vertical field of
    view ``fov``, degrees), a black world, the LGH engine."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    vol = bpy.data.volumes.new("fire")
    vol.filepath = str(vdb)
    obj = bpy.data.objects.new("fire", vol)
    obj.location = location
    obj.rotation_euler = Euler([math.radians(a) for a in volume_rotation])
    obj.scale = (scale, scale, scale)
    scene.collection.objects.link(obj)
    pv = principled(vol, inputs, flame)
    view(scene, width, height, eye, rotation, lens, fov, shift)
    return scene, pv


def view(scene, width, height, eye, rotation, lens=50.0, fov=None, shift=(0.0, 0.0)):
    """``scene`` seen by a new perspective camera (:func:`build`'s), in a black world, through
    the LGH engine into a ``width × height`` EXR."""
    world = bpy.data.worlds.new("black")
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    for node in world.node_tree.nodes:
        if node.type == "BACKGROUND":
            node.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
            node.inputs["Strength"].default_value = 0.0
    scene.world = world
    cam = bpy.data.cameras.new("camera")
    cam.lens, cam.shift_x, cam.shift_y = lens, shift[0], shift[1]
    if fov is not None:
        cam.sensor_fit, cam.angle = "VERTICAL", math.radians(fov)
    cam_obj = bpy.data.objects.new("camera", cam)
    cam_obj.location = eye
    cam_obj.rotation_euler = Euler([math.radians(a) for a in rotation])
    scene.collection.objects.link(cam_obj)
    scene.camera = cam_obj
    r = scene.render
    r.engine = "LGH"
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"


def render(tmp_path, name="f12"):
    """F12 (``render.render(write_still=True)``): the EXR's pixels, or ``None`` if no image
    was written; the engine's report."""
    from lgh_blender import engine

    out = tmp_path / f"{name}.exr"
    bpy.context.scene.render.filepath = str(out)
    try:
        bpy.ops.render.render(write_still=True)
    except RuntimeError:
        pass
    return (read_exr(out) if out.is_file() else None), list(engine.last_report)


def cli(tmp_path, vdb, flags, name="cli"):
    out = tmp_path / f"{name}.exr"
    subprocess.run([str(lgh_binary()), "explosion", "--vdb", str(vdb), "--out", str(out),
                    "--quiet", *flags], check=True, capture_output=True)
    return read_exr(out)


def fov_y(lens, width, height, sensor=36.0):
    """The vertical field of view of Blender's default sensor fit (Auto: the sensor width spans
    the larger side), by hand."""
    t = sensor / (2.0 * lens)
    return math.degrees(2.0 * math.atan(t * height / width if width > height else t))


def write_fireball(folder):
    """lgh's procedural fireball (32³) as an OpenVDB file in ``folder``: its path."""
    python = pathlib.Path("/usr/bin/python3")
    ok = python.is_file() and subprocess.run([str(python), "-c", "import pyopenvdb"],
                                             capture_output=True).returncode == 0
    if not ok:
        missing("python3-openvdb", "apt-get install python3-openvdb")
    prefix = pathlib.Path(folder) / "fireball"
    lgh.write_procedural("fireball", 32, 1.0, prefix)
    subprocess.run([str(python), str(ROOT / "tools" / "cycles" / "write_vdb.py"), str(prefix)],
                   check=True, capture_output=True)
    return prefix.with_suffix(".vdb")


#: The dev fire as the Cycles comparison renders it (tools/cycles/compare.py's fire56): density
#: 4, albedo 0.7, the flame attribute as the blackbody intensity, 1000 K per unit temperature,
#: seen from the front with a 40° vertical field of view.
DEV_FIRE = dict(eye=(0.53, -2.16, 0.455), rotation=(90.0, 0.0, 0.0), fov=40.0, flame="flame",
                inputs={"Density": 4.0, "Temperature": 1000.0})


def dev_fire():
    vdb = FIRE / "fluid_data_0056.vdb"
    if not vdb.is_file():
        missing(vdb, "the shared data, ../shared/data")
    return vdb


def use_cycles(scene, samples, seed=1, bounces=0, threads=None):
    """``scene`` set to render with Cycles as ``tools/cycles/render_cycles.py`` does: on the
    CPU, ``samples`` a pixel, no denoiser, no adaptive sampling, no clamping, a one-pixel box
    filter, ``bounces`` volume bounces (none of the other kinds; 128 through transparent
    surfaces), ``threads`` (all: ``None``)."""
    scene.render.engine = "CYCLES"
    cy = scene.cycles
    cy.device, cy.samples, cy.seed = "CPU", samples, seed
    cy.use_adaptive_sampling = cy.use_denoising = False
    cy.max_bounces = cy.volume_bounces = bounces
    cy.transparent_max_bounces = 128
    cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = 0
    cy.sample_clamp_direct = cy.sample_clamp_indirect = 0.0
    cy.pixel_filter_type, cy.filter_width = "BOX", 1.0
    if threads is None:
        scene.render.threads_mode = "AUTO"
    else:
        scene.render.threads_mode, scene.render.threads = "FIXED", threads


def cycles(tmp_path, samples, name, seed=1):
    """The current scene rendered by Cycles (:func:`use_cycles`, single scattering, 2 threads),
    then set back to LGH."""
    scene = bpy.context.scene
    use_cycles(scene, samples, seed, bounces=0, threads=2)
    image, _ = render(tmp_path, name)
    scene.render.engine = "LGH"
    return image


def dev_fire_scene(width, height, **overrides):
    """The engine registered and :data:`DEV_FIRE` built at ``width × height`` (``overrides``
    replace its settings), for ``blender/bench.py`` and ``blender/picture.py``: the scene and
    the file; exits with a message without the shared data."""
    import lgh_blender

    vdb = FIRE / "fluid_data_0056.vdb"
    if not vdb.is_file():
        sys.exit(f"no {vdb} (the shared data)")
    lgh_blender.register()
    scene, _ = build(vdb, width=width, height=height, **dict(DEV_FIRE, **overrides))
    return scene, vdb
