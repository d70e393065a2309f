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

import numpy as np
import pytest

from scenes import (DEV_FIRE, bpy, build, cli, cycles, dev_fire, fov_y, rel_rmse,
                    render)


def test_a_volume_object_renders_as_lgh_explosion_with_the_same_flags(fireball, tmp_path):
    build(fireball)
    image, report = render(tmp_path)
    assert report == [], report
    assert image is not None and image.shape == (32, 48, 3)
    want = cli(tmp_path, fireball, front(0.7))
    assert np.mean(want) > 0
    assert rel_rmse(image, want) <= 1e-5, rel_rmse(image, want)


def test_the_sampling_settings_are_the_commands_flags(fireball, tmp_path):
    """Render Properties > Sampling (``scene.lgh``): Auto leaves the command's own rule, a
    fixed pixel sampling, emission sampling and scatter spacing are ``--pixel-samples``,
    ``--emission-samples`` and ``--scatter-spacing`` (the fireball scatters: its albedo 0.7
    gives the spacing work to do)."""
    scene, _ = build(fireball)
    assert hasattr(bpy.types, "LGH_PT_sampling"), "the Sampling panel is not registered"
    s = scene.lgh
    assert (s.pixel_sampling, s.emission_sampling, s.scatter_grid) == ("AUTO",) * 3
    s.pixel_sampling, s.pixel_samples = "FIXED", 3
    s.emission_sampling, s.emission_samples = "FIXED", 5
    s.scatter_grid, s.scatter_spacing = "FIXED", 1
    image, report = render(tmp_path)
    assert report == [], report
    want = cli(tmp_path, fireball, front(0.7, "--pixel-samples", "3", "--emission-samples", "5",
                                         "--scatter-spacing", "1"))
    auto = cli(tmp_path, fireball, front(0.7), name="auto")
    assert rel_rmse(image, want) <= 1e-5, rel_rmse(image, want)
    assert rel_rmse(want, auto) > 1e-3, "the settings change nothing: the test tests nothing"


def front(albedo, *more):
    """:func:`build`'s default scene said to the command by hand: the camera at (0, -4, 0)
    looking along +Y with Z up; Cycles' Principled Volume of density 4, black absorption and
    colour ``albedo``: extinction 4 per unit density, that albedo; blackbody intensity 1 from
    `temperature` times 1 kelvin; no flame; Blender 5's interpolation of each attribute."""
    return ["--width", "48", "--height", "32",
            "--camera", f"0,-4,0,0,0,0,{fov_y(50.0, 48, 32)}", "--density-scale", "4",
            "--albedo", str(albedo), "--temperature-scale", "1", "--emission-scale", "1",
            "--flame-grid", "none", "--emission-interpolation", "attributes",
            "--no-domain-offset", "--allow-dark", *more]


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
                  "'shiny'", "world's light on the smoke", "volume 'fire2'"]:
        assert named in text, f"{named!r} not in the report:\n{text}"
    assert all(level == "WARNING" for level, _ in report)
    assert len(set(report)) == len(report), "a note said twice"


@pytest.mark.parametrize("case", ["ortho", "missing", "no grid", "no material", "shear"])
def test_bad_input_is_one_error_and_no_image(fireball, tmp_path, case):
    scene, pv = build(fireball)
    want = {"ortho": "orthographic", "missing": "no such file", "no grid": "no attribute 'heat'",
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
    per_channel = [rel_rmse(lgh_image[..., c], reference[..., c]) for c in range(3)]
    print(f"lgh vs Cycles {error:.4f} (R/G/B {per_channel[0]:.4f}/{per_channel[1]:.4f}/"
          f"{per_channel[2]:.4f}), Cycles noise {noise:.4f}, flipped shift {wrong:.4f}")
    assert error <= 1.25 * noise and wrong > 4 * error, (error, noise, wrong)


def test_the_worlds_colour_is_the_background_cycles_sees(fireball, tmp_path):
    """A world of one colour (0.1, 0.2, 0.4) × 1.5 behind smoke that does not scatter (albedo 0:
    the world lights nothing Cycles would show): ``--background 0.15,0.3,0.6``, and Cycles' image
    within its noise at 64 samples (as the camera test above); with *Film > Transparent* no
    background, several times further off."""
    scene, _ = build(fireball, inputs={"Color": (0.0, 0.0, 0.0, 1.0)})
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.1, 0.2, 0.4, 1.0)
    bg.inputs["Strength"].default_value = 1.5
    image, report = render(tmp_path, "lgh")
    assert [m for _, m in report] == [
        "LGH does not render the world's light on the smoke (its colour (0.1, 0.2, 0.4) x 1.5 is the background; "
        "LGH's only light is the fire)"], report
    want = cli(tmp_path, fireball, front(0, "--background", "0.15,0.3,0.6"))
    assert rel_rmse(image, want) <= 1e-5, rel_rmse(image, want)
    reference = cycles(tmp_path, 64, "cycles", seed=1)
    noise = rel_rmse(cycles(tmp_path, 64, "cycles2", seed=2), reference) / math.sqrt(2.0)
    error = rel_rmse(image, reference)
    scene.render.film_transparent = True
    black, _ = render(tmp_path, "transparent")
    wrong = rel_rmse(black, reference)
    print(f"lgh vs Cycles {error:.4f}, Cycles noise {noise:.4f}, no background {wrong:.4f}")
    assert error <= 1.25 * noise and wrong > 4 * error, (error, noise, wrong)


@pytest.mark.parametrize("crop", [True, False])
def test_a_render_region_is_that_region_of_the_whole_image(fireball, tmp_path, crop):
    scene, _ = build(fireball)
    whole, _ = render(tmp_path, "whole")
    r = scene.render
    r.use_border, r.use_crop_to_border = True, crop
    r.border_min_x, r.border_max_x, r.border_min_y, r.border_max_y = 0.25, 0.75, 0.1, 0.6
    part, report = render(tmp_path, f"region-{crop}")
    assert report == [], report
    # Blender's region: border × size, truncated; y from the bottom (rows 32 - 19 .. 32 - 3).
    x0, x1, y0, y1 = 12, 36, 3, 19
    window = whole[32 - y1:32 - y0, x0:x1]
    if crop:
        np.testing.assert_array_equal(part, window)
    else:
        # Uncropped, the image is whole-sized and black outside the region.
        np.testing.assert_array_equal(part[32 - y1:32 - y0, x0:x1], window)
        outside = part.copy()
        outside[32 - y1:32 - y0, x0:x1] = 0
        assert not outside.any()


def test_faces_past_the_last_slot_and_instances(fireball, tmp_path):
    """A face whose material index is past the last slot takes the last (as Cycles clamps it);
    a collection instance is named, not silently left out."""
    scene, _ = build(fireball)
    bpy.ops.mesh.primitive_cube_add(location=(0.0, 3.0, 0.0))
    cube = bpy.context.object
    cube.data.materials.append(bpy.data.materials.new("only"))
    cube.data.polygons[0].material_index = 2
    group = bpy.data.collections.new("group")
    group.objects.link(bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "POINT")))
    instance = bpy.data.objects.new("instancer", None)
    instance.instance_type, instance.instance_collection = "COLLECTION", group
    scene.collection.objects.link(instance)
    image, report = render(tmp_path)
    assert image is not None, report
    assert any("instanced objects 'lamp'" in m for _, m in report), report
