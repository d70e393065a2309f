"""A Mantaflow gas domain through the LGH engine: its cache file for the frame, read as Cycles
reads the domain — the temperature made of the flame with the domain's ignition and maximum,
voxel ``i`` centred at ``box_min + (i + 1/2) × cell`` in the object — is the image of a Volume
object holding that made temperature, placed there (what Cycles 3.4.1 was measured to draw to
0.13%: ``lgh_blender/domain.py``). bpy 5.2.3 cannot bake, so the cache is written here as
Mantaflow writes one (``write_domain_cache.py``, Debian's python3-openvdb).

PyPI's bpy 5.2.3 ships a broken Mantaflow: a render's depsgraph that evaluates a domain aborts
the process ("can't clean grid cache"), as does freeing a domain that the render evaluated. So
the domain is read by the add-on's :func:`~lgh_blender.scene.job` through the viewport's
depsgraph and rendered by ``lgh.render_explosion``, which is what the engine's F12 does with the
job (the Volume object's F12 is the comparison); each test removes its domain before the next
scene is built.
"""
import math
import subprocess

import pytest
from scenes import ROOT, bpy, missing, principled, rel_rmse, render, view

import lgh

if bpy is not None:
    from lgh_blender.errors import Refused
    from lgh_blender.scene import job

#: The cache's voxel (not the domain's cell, 2/32: the file's space is scaled into the world),
#: and the domain's Fire settings (not Blender's defaults, 1.5 and 3).
VOXEL, IGNITION, MAX_TEMPERATURE = 0.1, 1.2, 2.8


@pytest.fixture
def cache(tmp_path_factory):
    """A new cache for each test: changing most of a domain's settings (its format, ...) frees
    its cache, deleting the files."""
    folder = tmp_path_factory.mktemp("domain")
    python = "/usr/bin/python3"
    ok = subprocess.run([python, "-c", "import pyopenvdb"], capture_output=True).returncode == 0
    if not ok:
        missing("python3-openvdb", "apt-get install python3-openvdb")
    prefix = folder / "fireball"
    lgh.write_procedural("fireball", 32, 1.0, prefix)
    subprocess.run([python, str(ROOT / "blender" / "tests" / "write_domain_cache.py"),
                    str(prefix), str(folder / "cache"), str(VOXEL), str(IGNITION),
                    str(MAX_TEMPERATURE)], check=True, capture_output=True)
    return folder / "cache"


def build_domain(cache, *, location=(0.3, 0.2, 1.0), rotation=(0.0, 0.0, 30.0), scale=1.5,
                 inputs=None):
    """A new scene: a cube domain (its mesh ±1, 32 cells a side) of ``cache`` moved, turned
    (degrees) and scaled, with a Principled Volume (1000 K per unit of temperature), seen
    from the front. The domain object and its node."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_cube_add(size=2.0)
    obj = bpy.context.object
    obj.name = "domain"
    obj.location = location
    obj.rotation_euler = [math.radians(a) for a in rotation]
    obj.scale = scale if isinstance(scale, tuple) else (scale,) * 3
    fluid = obj.modifiers.new("Fluid", "FLUID")
    fluid.fluid_type = "DOMAIN"
    ds = fluid.domain_settings
    ds.domain_type, ds.resolution_max, ds.cache_data_format = "GAS", 32, "OPENVDB"
    ds.cache_type = "ALL"  # baked: nothing simulated (nor written) on a change of frame
    ds.flame_ignition, ds.flame_max_temp = IGNITION, MAX_TEMPERATURE
    ds.cache_frame_start, ds.cache_frame_end = 1, 1
    # Last: a change of most settings frees the cache, deleting the directory's files.
    ds.cache_directory = str(cache)
    pv = principled(obj.data, dict({"Temperature": 1000.0}, **(inputs or {})))
    view(scene, 48, 32, eye=(0.3, -6.0, 1.0), rotation=(90.0, 0.0, 0.0))
    scene.frame_set(1)
    return obj, pv


@pytest.fixture
def domain(cache):
    """:func:`build_domain` as a factory; the domain removed after the test (see the module's
    text)."""
    built = []

    def make(**kwargs):
        built.append(build_domain(cache, **kwargs))
        return built[-1]

    yield make
    for name in ("domain",) * bool(built):
        if name in bpy.data.objects:
            bpy.data.objects.remove(bpy.data.objects[name], do_unlink=True)


def domain_job():
    """The add-on's reading of the current scene, through the viewport's depsgraph."""
    return job(bpy.context.evaluated_depsgraph_get())


def test_a_domain_is_the_volume_of_its_made_temperature_placed_as_cycles_places_it(cache,
                                                                                   domain,
                                                                                   tmp_path):
    obj, _ = domain()
    read = domain_job()
    assert read.notes == [], read.notes
    image = lgh.render_explosion(read.vdb, **read.settings)
    assert image.shape == (32, 48, 3) and image.mean() > 0
    # The same smoke as a Volume object: the file of the made temperature, voxel i (at
    # i × VOXEL in the file) centred at the box's corner + (i + 1/2) cells, cell = 2/32.
    cell = 2.0 / 32
    from mathutils import Matrix, Vector

    place = obj.matrix_world @ Matrix.Translation(Vector((-1.0 + cell / 2,) * 3)) \
        @ Matrix.Scale(cell / VOXEL, 4)
    material = obj.data.materials[0]
    bpy.data.objects.remove(obj, do_unlink=True)
    vol = bpy.data.volumes.new("made")
    vol.filepath = str(cache / "made.vdb")
    vol.materials.append(material)
    made = bpy.data.objects.new("made", vol)
    made.matrix_world = place
    bpy.context.scene.collection.objects.link(made)
    want, report = render(tmp_path, "made")
    assert report == [], report
    assert rel_rmse(image, want) <= 1e-5, rel_rmse(image, want)


def test_the_domains_attributes_are_its_grids(domain):
    _, pv = domain()
    settings = domain_job().settings
    assert (settings["emission_grid"], settings["flame_temperature"]) == \
        ("flame", (pytest.approx(IGNITION), pytest.approx(MAX_TEMPERATURE)))
    # The add-on places an adaptive domain's frame itself (frame_offset): lgh reads no config.
    assert settings["flame_grid"] == "none" and settings["no_domain_offset"] is True
    # heat is the file's `temperature`, read as it is.
    pv.inputs["Temperature Attribute"].default_value = "heat"
    settings = domain_job().settings
    assert settings["emission_grid"] == "temperature" and "flame_temperature" not in settings
    # The made temperature is a temperature only.
    pv.inputs["Density Attribute"].default_value = "temperature"
    with pytest.raises(Refused, match="makes from its grid 'flame'"):
        domain_job()
    pv.inputs["Density Attribute"].default_value = "smoke"
    with pytest.raises(Refused, match="no attribute 'smoke'"):
        domain_job()


def test_cells_that_are_not_cubes_are_named(domain):
    # 2 × 2 × 2.1 world units: 32 cells along z, round(2 × 32 / 2.1) = 30 along x and y, so
    # cells of 2/30 against 2.1/32: 1.6% apart.
    domain(rotation=(0.0, 0.0, 0.0), scale=(1.0, 1.0, 1.05))
    notes = domain_job().notes
    assert any("1.6% from cubes" in n for n in notes), notes


def test_a_domain_off_for_the_viewport_is_no_volume(domain):
    obj, _ = domain()
    obj.modifiers["Fluid"].show_viewport = False
    with pytest.raises(Refused, match="no volume to render"):
        domain_job()


@pytest.mark.parametrize("case", ["frame", "format"])
def test_a_domain_without_a_cache_is_refused(domain, case):
    obj, _ = domain()
    ds = obj.modifiers["Fluid"].domain_settings
    want = {"frame": "no cache for frame 2", "format": "LGH reads OpenVDB"}[case]
    if case == "frame":
        bpy.context.scene.frame_set(2)
    else:
        ds.cache_data_format = "UNI"
    with pytest.raises(Refused, match=want):
        domain_job()


def test_noise_and_a_frame_offset_name_their_files(cache):
    """With Noise on, the upsampled cache's file (turning Noise on in bpy 5.2.3's Mantaflow
    aborts: the settings are given as plain values)."""
    from types import SimpleNamespace

    from lgh_blender.domain import cache_file

    obj = SimpleNamespace(name="domain", library=None)
    ds = SimpleNamespace(cache_data_format="OPENVDB", cache_frame_offset=0,
                         cache_directory=str(cache), use_noise=False, use_adaptive_domain=False)
    assert cache_file(obj, ds, 1) == str(cache / "data" / "fluid_data_0001.vdb")
    ds.cache_frame_offset = 9
    assert cache_file(obj, ds, 10) == str(cache / "data" / "fluid_data_0001.vdb")
    ds.use_noise = True
    with pytest.raises(Refused, match=r"noise/fluid_noise_0001.vdb\): bake it .* Bake Noise"):
        cache_file(obj, ds, 10)



def test_an_adaptive_frames_corner_is_its_config_files(tmp_path):
    """``res_min`` of ``config/config_NNNN.uni`` (gzip of 204 bytes ending in ``C01``, three
    int32 at byte 160), as Blender writes it; none without the file; a damaged one refused."""
    import gzip
    import struct
    from types import SimpleNamespace

    from lgh_blender.domain import frame_offset

    obj, ds = SimpleNamespace(name="domain"), SimpleNamespace(use_adaptive_domain=False)
    vdb = tmp_path / "data" / "fluid_data_0007.vdb"
    assert frame_offset(obj, ds, str(vdb)) == (0, 0, 0)
    (tmp_path / "config").mkdir()
    config = tmp_path / "config" / "config_0007.uni"
    record = bytearray(204)
    record[160:172] = struct.pack("<3i", 2, 1, 0)
    record[200:204] = b"C01\0"
    config.write_bytes(gzip.compress(bytes(record)))
    ds.use_adaptive_domain = True
    assert frame_offset(obj, ds, str(vdb)) == (2, 1, 0)
    config.write_bytes(gzip.compress(bytes(record[:100])))
    with pytest.raises(Refused, match="not a Blender fluid config"):
        frame_offset(obj, ds, str(vdb))
