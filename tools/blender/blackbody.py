"""Measures Cycles' blackbody colour as a volume sees it: the table of `lgh_volume::blender_blackbody`.

Principled Volume colours its blackbody emission with Cycles' blackbody function *unclamped*: at
low temperatures the colour lies outside the Rec. 709 gamut and a channel is negative (800 K:
green and blue), and Cycles keeps that negative emission. The Blackbody *node* clamps the same
function at 0 (its output `max(colour, 0)`), so an emission plane fed by the node — how this
script measured before — cannot see it. Here each temperature is a unit cube of Principled Volume
(density 0, blackbody intensity 1, the temperature socket at T and no attribute): pure emission
`σ T⁴ c(T)` with `σ = 5.670373e-14 / π` (Cycles' Stefan–Boltzmann scale), integrated over the
cube's depth. One more cube emits white at a known strength, the calibration of depth and film:

    c(T) = pixel(T) / pixel(white) · strength / (σ T⁴)

All cubes go in one orthographic render (box filter, a 32-bit linear EXR); each colour is the mean
of its cube's four central pixels, and `spread` is the largest distance of one of those four
from their mean (0 for a noise-free render). The colour printed is linear Rec. 709, normalised as Cycles normalises
it (luminance about 1).

    blender -b --factory-startup --python tools/blender/blackbody.py -- --table | grep ^BLACKBODY
    python3.13 tools/blender/blackbody.py -- --table | grep ^BLACKBODY      # PyPI's bpy
    blender -b --factory-startup --python tools/blender/blackbody.py -- 1000 1500 6500

`--table` measures the table's temperatures: 246 steps of 5 mired, 1250 mired (800 K) to 25 mired
(40000 K). The output is one line `BLACKBODY {json}`: the Blender version, `colours` as
`[kelvin, [r, g, b]]`, and `spread`.
"""

import json
import math
import os
import sys
import tempfile

import bpy

# Cycles' Stefan–Boltzmann scale in Principled Volume (float32 there; the difference is 1e-7).
SIGMA = 5.670373e-8 * 1e-6 / math.pi
# The calibration cube's emission strength (white).
WHITE = 1.0
# Pixels a cube's pitch, and the pitch in units (cubes are 1 unit).
PIXELS = 6
PITCH = 1.5


def temperatures(argv):
    if argv == ["--table"]:
        return [1e6 / (1250 - 5 * i) for i in range(246)]
    return [float(t) for t in argv]


def cube(name, location, material):
    bpy.ops.mesh.primitive_cube_add(size=1, location=location)
    obj = bpy.context.active_object
    obj.name = name
    obj.data.materials.append(material)


def volume_material(kelvin):
    """Principled Volume emitting its blackbody at `kelvin` (or white, for None) and nothing else."""
    mat = bpy.data.materials.new(f"bb{kelvin}")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    vol = nodes.new("ShaderNodeVolumePrincipled")
    vol.inputs["Density"].default_value = 0.0
    vol.inputs["Density Attribute"].default_value = ""
    vol.inputs["Temperature Attribute"].default_value = ""
    if kelvin is None:
        vol.inputs["Blackbody Intensity"].default_value = 0.0
        vol.inputs["Emission Strength"].default_value = WHITE
        vol.inputs["Emission Color"].default_value = (1, 1, 1, 1)
    else:
        vol.inputs["Blackbody Intensity"].default_value = 1.0
        vol.inputs["Temperature"].default_value = kelvin
        vol.inputs["Emission Strength"].default_value = 0.0
    mat.node_tree.links.new(vol.outputs[0], out.inputs["Volume"])
    return mat


def setup(count):
    """The scene: `count` cubes on a square grid and an orthographic camera over them."""
    scene = bpy.context.scene
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    cols = math.ceil(math.sqrt(count))
    extent = cols * PITCH
    camera = bpy.data.cameras.new("camera")
    camera.type = "ORTHO"
    camera.ortho_scale = extent
    cam = bpy.data.objects.new("camera", camera)
    scene.collection.objects.link(cam)
    cam.location = (0, 0, 5)
    scene.camera = cam
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 4
    if hasattr(scene.cycles, "use_adaptive_sampling"):
        scene.cycles.use_adaptive_sampling = False
    if hasattr(scene.cycles, "use_denoising"):
        scene.cycles.use_denoising = False
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 1.0
    scene.render.resolution_x = scene.render.resolution_y = cols * PIXELS
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.world = bpy.data.worlds.new("black")
    scene.world.color = (0, 0, 0)
    if bpy.app.version < (5, 0, 0):
        scene.world.use_nodes = False
    else:  # 5.x shades the world by its nodes, a grey Background by default: none at all
        scene.world.use_nodes = True
        scene.world.node_tree.nodes.clear()
    return cols, extent


def centre(index, cols, extent):
    """Cube `index`'s centre in the plane, and the first of its central pixels."""
    c, r = index % cols, index // cols
    x = (c + 0.5) * PITCH - extent / 2
    y = (r + 0.5) * PITCH - extent / 2
    return (x, y, 0), (c * PIXELS + PIXELS // 2 - 1, r * PIXELS + PIXELS // 2 - 1)


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    temps = temperatures(argv)
    if not temps:
        sys.exit("blackbody.py: give temperatures in kelvin, or --table")
    kelvins = [None] + temps
    cols, extent = setup(len(kelvins))
    pixels_at = []
    for i, kelvin in enumerate(kelvins):
        location, first = centre(i, cols, extent)
        cube(f"cube{i}", location, volume_material(kelvin))
        pixels_at.append(first)
    scene = bpy.context.scene
    scene.render.filepath = os.path.join(tempfile.mkdtemp(), "blackbody.exr")
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(scene.render.filepath)
    width = image.size[0]
    px = list(image.pixels)
    means, spread = [], 0.0
    for x0, y0 in pixels_at:
        quad = []
        for dy in (0, 1):
            for dx in (0, 1):
                k = 4 * ((y0 + dy) * width + x0 + dx)
                quad.append(px[k : k + 3])
        mean = [sum(q[a] for q in quad) / 4 for a in range(3)]
        spread = max(spread, max(abs(q[a] - mean[a]) for q in quad for a in range(3)))
        means.append(mean)
    white = means[0]
    colours = []
    for kelvin, mean in zip(temps, means[1:]):
        scale = SIGMA * kelvin**4
        colours.append([kelvin, [mean[a] / white[a] * WHITE / scale for a in range(3)]])
    print(
        "BLACKBODY "
        + json.dumps(
            {
                "blender": bpy.app.version_string,
                "through": "Principled Volume (unclamped)",
                "white": white,
                "spread": spread,
                "colours": colours,
            }
        )
    )


main()
