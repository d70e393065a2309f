"""The render engine ``LGH`` in Blender (PyPI's ``bpy``, Blender as a Python module): scenes
built here, rendered with F12's operator, against ``lgh explosion`` given by hand the flags
that say the same scene; every unsupported setting named in the report; every bad input one
error and no image.

The fireball is lgh's procedural volume written as an OpenVDB file (``lgh.write_procedural`` and
``tools/cycles/write_vdb.py``, which needs Debian's python3-openvdb); the dev fire is the shared
data's. Without bpy, the `lgh` binary, python3-openvdb or the shared data each test is skipped
with a message, a failure where ``LGH_REQUIRE_ALL`` is set (``.ci/run``).
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
except ImportError:
    bpy = None

import lgh

FIRE = ROOT.parent / "shared" / "data" / "volumes" / "blender_fire_pesichra" / "data"


@pytest.fixture(scope="module", autouse=True)
def engine():
    if bpy is None:
        missing("bpy", "pip install bpy==5.2.3 under Python 3.13")
    import lgh_blender

    lgh_blender.register()
    yield
    lgh_blender.unregister()


def lgh_binary():
    named = os.environ.get("LGH_BIN")
    candidates = [pathlib.Path(named)] if named else [
        ROOT / "target" / "release" / "lgh", ROOT / "target" / "debug" / "lgh"]
    for c in candidates:
        if c.is_file():
            return c
    missing(f"lgh binary at {candidates}", "cargo build -p lgh-cli")


@pytest.fixture(scope="module")
def fireball(tmp_path_factory):
    python = pathlib.Path("/usr/bin/python3")
    ok = python.is_file() and subprocess.run([str(python), "-c", "import pyopenvdb"],
                                             capture_output=True).returncode == 0
    if not ok:
        missing("python3-openvdb", "apt-get install python3-openvdb")
    prefix = tmp_path_factory.mktemp("fireball") / "fireball"
    lgh.write_procedural("fireball", 32, 1.0, prefix)
    subprocess.run([str(python), str(ROOT / "tools" / "cycles" / "write_vdb.py"), str(prefix)],
                   check=True, capture_output=True)
    return prefix.with_suffix(".vdb")


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
    mat = bpy.data.materials.new("fire")
    if bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nodes = mat.node_tree.nodes
    for n in list(nodes):
        nodes.remove(n)
    out = nodes.new("ShaderNodeOutputMaterial")
    pv = nodes.new("ShaderNodeVolumePrincipled")
    settings = {"Density": 4.0, "Color": (0.7, 0.7, 0.7, 1.0),
                "Absorption Color": (0.0, 0.0, 0.0, 1.0), "Blackbody Intensity": 1.0,
                "Temperature": 1.0}
    settings.update(inputs or {})
    for k, v in settings.items():
        pv.inputs[k].default_value = v
    mat.node_tree.links.new(pv.outputs["Volume"], out.inputs["Volume"])
    if flame is not None:
        attr = nodes.new("ShaderNodeAttribute")
        attr.attribute_name = flame
        mat.node_tree.links.new(attr.outputs["Fac"], pv.inputs["Blackbody Intensity"])
    vol.materials.append(mat)
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
    return scene, pv


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


def test_a_volume_object_renders_as_lgh_explosion_with_the_same_flags(fireball, tmp_path):
    build(fireball)
    image, report = render(tmp_path)
    assert report == [], report
    assert image is not None and image.shape == (32, 48, 3)
    # The same scene said to the command by hand: the camera at (0, -4, 0) looking along +Y
    # with Z up; Cycles' Principled Volume of density 4, colour 0.7, black absorption:
    # extinction 4 per unit density, albedo 0.7; blackbody intensity 1 from `temperature`
    # times 1 kelvin; no flame; Blender 5's interpolation of each attribute.
    flags = ["--width", "48", "--height", "32",
             "--camera", f"0,-4,0,0,0,0,{fov_y(50.0, 48, 32)}", "--density-scale", "4",
             "--albedo", "0.7", "--temperature-scale", "1", "--emission-scale", "1",
             "--flame-grid", "none", "--emission-interpolation", "attributes",
             "--no-domain-offset", "--allow-dark"]
    want = cli(tmp_path, fireball, flags)
    assert np.mean(want) > 0
    assert rel_rmse(image, want) <= 1e-5, rel_rmse(image, want)


def test_roll_shift_and_a_moved_volume_are_the_same_image_in_the_volumes_space(fireball,
                                                                              tmp_path):
    """A camera rolled 30° and shifted, with the volume translated, turned and scaled 2×: the
    command renders it from the camera moved into the file's space, the extinction and the
    emission per unit of the file's length doubled."""
    build(fireball, eye=(1.0, -7.0, 2.0), rotation=(80.0, 30.0, 10.0), shift=(0.1, -0.05),
          location=(1.0, 0.5, 2.0), volume_rotation=(0.0, 0.0, 90.0), scale=2.0)
    image, report = render(tmp_path)
    assert report == [], report
    scene = bpy.context.scene
    cam = scene.camera
    m = bpy.data.objects["fire"].matrix_world.inverted()
    eye = m @ cam.matrix_world.translation
    rot = cam.matrix_world.to_3x3()
    forward = (m.to_3x3() @ -rot.col[2]).normalized()
    up = (m.to_3x3() @ rot.col[1]).normalized()
    target = eye + forward
    # Blender's shift is in units of the larger side (48 px wide, sensor fit Auto): as lgh's.
    flags = ["--width", "48", "--height", "32",
             "--camera", ",".join(f"{v:.9g}" for v in (*eye, *target, fov_y(50.0, 48, 32))),
             "--camera-up", ",".join(f"{v:.9g}" for v in up), "--camera-shift=0.1,-0.05",
             "--density-scale", "8", "--albedo", "0.7", "--temperature-scale", "1",
             "--emission-scale", "2", "--flame-grid", "none",
             "--emission-interpolation", "attributes", "--no-domain-offset", "--allow-dark"]
    want = cli(tmp_path, fireball, flags)
    assert np.mean(want) > 0
    assert rel_rmse(image, want) <= 1e-5, rel_rmse(image, want)


def test_a_mesh_is_the_room_the_fire_lights(fireball, tmp_path):
    """A floor under the fire, turned with the volume: the command's image with the same floor
    written by hand as an OBJ in the file's space (the volume moved up by 1 and turned 90°
    about Z: the floor at z = -1.2 in the world is at z = -2.2 in the file), its Principled
    BSDF's base colour as Kd."""
    scene, _ = build(fireball, eye=(0.0, -5.0, 1.0), rotation=(80.0, 0.0, 0.0),
                     location=(0.0, 0.0, 1.0), volume_rotation=(0.0, 0.0, 90.0))
    bpy.ops.mesh.primitive_plane_add(size=6.0, location=(0.0, 0.0, -1.2))
    floor = bpy.data.materials.new("floor")
    if bpy.app.version < (5, 0, 0):
        floor.use_nodes = True
    bsdf = floor.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.6, 0.5, 0.4, 1.0)
    bsdf.inputs["Specular IOR Level"].default_value = 0.0
    bpy.context.object.data.materials.append(floor)
    image, report = render(tmp_path)
    assert report == [], report
    (tmp_path / "floor.mtl").write_text("newmtl floor\nKd 0.6 0.5 0.4\n")
    # The plane's corners in the world, turned by -90° about Z and moved down by 1.
    corners = [(-3, -3), (3, -3), (3, 3), (-3, 3)]
    obj = ["mtllib floor.mtl", "usemtl floor"]
    obj += [f"v {y} {-x} -2.2" for x, y in corners] + ["f 1 2 3", "f 1 3 4"]
    (tmp_path / "floor.obj").write_text("\n".join(obj) + "\n")
    cam = scene.camera.matrix_world
    m = bpy.data.objects["fire"].matrix_world.inverted()
    eye = m @ cam.translation
    forward = (m.to_3x3() @ -cam.to_3x3().col[2]).normalized()
    up = (m.to_3x3() @ cam.to_3x3().col[1]).normalized()
    flags = ["--width", "48", "--height", "32",
             "--camera", ",".join(f"{v:.9g}" for v in (*eye, *(eye + forward),
                                                       fov_y(50.0, 48, 32))),
             "--camera-up", ",".join(f"{v:.9g}" for v in up),
             "--scene", str(tmp_path / "floor.obj"), "--density-scale", "4", "--albedo", "0.7",
             "--temperature-scale", "1", "--flame-grid", "none",
             "--emission-interpolation", "attributes", "--no-domain-offset", "--allow-dark"]
    want = cli(tmp_path, fireball, flags)
    floor_only = cli(tmp_path, fireball, [f for f in flags if f not in ("--scene",
                                          str(tmp_path / "floor.obj"))], "no-floor")
    # The floor lit by the fire fills the image's lower rows, dark without it.
    lit, dark = float(np.mean(want[-8:])), float(np.mean(floor_only[-8:]))
    print(f"floor rows {lit:.3g} vs {dark:.3g}")
    assert lit > 2 * dark, ("the floor is not in the picture", lit, dark)
    assert rel_rmse(image, want) <= 1e-5, rel_rmse(image, want)


def test_what_lgh_does_not_render_is_named_once_in_the_report(fireball, tmp_path):
    scene, pv = build(fireball, inputs={"Anisotropy": 0.3, "Color": (0.9, 0.5, 0.5, 1.0),
                                        "Emission Strength": 2.0})
    tree = pv.id_data
    noise = tree.nodes.new("ShaderNodeTexNoise")
    tree.links.new(noise.outputs["Fac"], pv.inputs["Temperature"])
    bpy.data.objects["camera"].data.dof.use_dof = True
    lamp = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "POINT"))
    scene.collection.objects.link(lamp)
    bpy.ops.mesh.primitive_cube_add(location=(5.0, 5.0, 0.0))
    shiny = bpy.data.materials.new("shiny")
    if bpy.app.version < (5, 0, 0):
        shiny.use_nodes = True
    shiny.node_tree.nodes["Principled BSDF"].inputs["Metallic"].default_value = 1.0
    bpy.context.object.data.materials.append(shiny)
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.1, 0.2, 0.3, 1)
    vol2 = bpy.data.objects.new("fire2", bpy.data.volumes.new("fire2"))
    vol2.data.filepath = str(fireball)
    scene.collection.objects.link(vol2)
    image, report = render(tmp_path)
    assert image is not None
    text = "\n".join(m for _, m in report)
    for named in ["anisotropy 0.3", "coloured Color", "Emission Strength 2",
                  "Noise Texture node driving the Principled Volume's Temperature",
                  "depth of field", "lamp 'lamp'", "metallic and specular part of material "
                  "'shiny'", "world's colour", "volume 'fire2'"]:
        assert named in text, f"{named!r} not in the report:\n{text}"
    assert all(level == "WARNING" for level, _ in report)
    assert len(set(report)) == len(report), "a note said twice"


@pytest.mark.parametrize("case", ["ortho", "missing", "no grid", "no material", "shear"])
def test_bad_input_is_one_error_and_no_image(fireball, tmp_path, case):
    scene, pv = build(fireball)
    want = {"ortho": "orthographic", "missing": "no such file", "no grid": "no grid 'heat'",
            "no material": "has no material", "shear": "non-uniform scale"}[case]
    if case == "ortho":
        scene.camera.data.type = "ORTHO"
    elif case == "missing":
        bpy.data.objects["fire"].data.filepath = str(tmp_path / "gone.vdb")
    elif case == "no grid":
        pv.inputs["Temperature Attribute"].default_value = "heat"
    elif case == "no material":
        bpy.data.objects["fire"].data.materials.clear()
    elif case == "shear":
        bpy.data.objects["fire"].scale = (1.0, 2.0, 1.0)
    image, report = render(tmp_path, case.replace(" ", "_"))
    assert image is None, "an image was written"
    errors = [m for level, m in report if level == "ERROR"]
    assert len(errors) == 1 and want in errors[0], report
    assert not list(tmp_path.glob("*.exr"))


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


def test_the_dev_fire_through_the_add_on_is_the_commands_image(tmp_path):
    vdb = dev_fire()
    build(vdb, width=64, height=36, **DEV_FIRE)
    image, report = render(tmp_path)
    assert report == [], report
    # The study's own flags (tools/cycles/compare.py) and Blender 5's interpolation.
    flags = ["--width", "64", "--height", "36", "--camera", "0.53,-2.16,0.455,0.53,0.34,0.455,40",
             "--density-scale", "4", "--albedo", "0.7", "--temperature-scale", "1000",
             "--emission-interpolation", "attributes", "--no-domain-offset"]
    want = cli(tmp_path, vdb, flags)
    assert np.mean(want) > 0
    assert rel_rmse(image, want) <= 1e-5, rel_rmse(image, want)


def cycles(tmp_path, samples, name, seed=1):
    """The current scene rendered by Cycles on the CPU: ``samples`` per pixel, no denoiser, no
    adaptive sampling, a one-pixel box filter (as ``tools/cycles/render_cycles.py``)."""
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    cy = scene.cycles
    cy.device, cy.samples, cy.seed = "CPU", samples, seed
    cy.use_adaptive_sampling = cy.use_denoising = False
    cy.max_bounces = cy.volume_bounces = 0
    cy.pixel_filter_type, cy.filter_width = "BOX", 1.0
    scene.render.threads_mode, scene.render.threads = "FIXED", 2
    image, _ = render(tmp_path, name)
    scene.render.engine = "LGH"
    return image


def test_the_cameras_roll_and_shift_are_cycles(fireball, tmp_path):
    """Blender's own renderer, Cycles, sees the same picture through a rolled, shifted camera
    with the vertical sensor fit: the fire glowing without scattering (albedo 0). At 64 samples
    a pixel Cycles' own noise is about 5.5% (two seeds' images differ by √2 that; it halves
    from 16 samples, so it is noise, not a difference of the images), and lgh's image is within
    it: their RMSE is at most 1.25 times that of a second Cycles seed against the first
    divided by √2. The same scene with the shift's sign flipped in lgh's camera — the mistake
    this guards against — is several times further off."""
    scene, _ = build(fireball, eye=(0.5, -5.0, 1.0), rotation=(80.0, 25.0, 5.0),
                     shift=(0.12, -0.08), inputs={"Color": (0.0, 0.0, 0.0, 1.0)})
    scene.camera.data.sensor_fit = "VERTICAL"
    lgh_image, report = render(tmp_path, "lgh")
    assert report == [], report
    reference = cycles(tmp_path, 64, "cycles", seed=1)
    noise = rel_rmse(cycles(tmp_path, 64, "cycles2", seed=2), reference) / math.sqrt(2.0)
    error = rel_rmse(lgh_image, reference)
    scene.camera.data.shift_x, scene.camera.data.shift_y = -0.12, 0.08
    flipped, _ = render(tmp_path, "flipped")
    wrong = rel_rmse(flipped, reference)
    print(f"lgh vs Cycles {error:.4f}, Cycles noise {noise:.4f}, flipped shift {wrong:.4f}")
    assert error <= 1.25 * noise and wrong > 4 * error, (error, noise, wrong)
