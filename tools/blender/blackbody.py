"""Measures Blender Cycles' Blackbody node: the table of `lgh_volume::blender_blackbody`.

Renders, for each temperature, a plane whose emission colour is the Blackbody node's output
(strength 1, one sample, the Standard view transform, a 32-bit linear EXR) and prints the
pixel's linear Rec. 709 colour as JSON. The node's output is luminance-normalised already.

    blender -b --factory-startup --python tools/blender/blackbody.py -- --table > blackbody.json
    blender -b --factory-startup --python tools/blender/blackbody.py -- 1250 1750 4500

`--table` measures the table's temperatures: 246 steps of 5 mired, 1250 mired (800 K) to
25 mired (40000 K). Blender 3.4.1 (Debian's `blender`) gives the values of issue 29's table
(1000 K: 4.601, 0.039, 0; 6500 K: 1.043, 0.984, 1.035).
"""

import json
import os
import sys
import tempfile

import bpy


def temperatures(argv):
    if argv == ["--table"]:
        return [1e6 / (1250 - 5 * i) for i in range(246)]
    return [float(t) for t in argv]


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    temps = temperatures(argv)
    scene = bpy.context.scene
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    bpy.ops.mesh.primitive_plane_add(size=10, location=(0, 0, 0))
    plane = bpy.context.active_object
    mat = bpy.data.materials.new("blackbody")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    emission = nodes.new("ShaderNodeEmission")
    blackbody = nodes.new("ShaderNodeBlackbody")
    links = mat.node_tree.links
    links.new(blackbody.outputs[0], emission.inputs["Color"])
    links.new(emission.outputs[0], out.inputs["Surface"])
    plane.data.materials.append(mat)
    camera = bpy.data.cameras.new("camera")
    camera.type = "ORTHO"
    camera.ortho_scale = 2
    cam = bpy.data.objects.new("camera", camera)
    scene.collection.objects.link(cam)
    cam.location = (0, 0, 5)
    scene.camera = cam
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 1
    scene.cycles.device = "CPU"
    if hasattr(scene.cycles, "use_denoising"):
        scene.cycles.use_denoising = False
    scene.render.resolution_x = scene.render.resolution_y = 4
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.world = bpy.data.worlds.new("black")
    scene.world.use_nodes = False
    scene.world.color = (0, 0, 0)
    out_dir = tempfile.mkdtemp()
    result = []
    for i, kelvin in enumerate(temps):
        blackbody.inputs["Temperature"].default_value = kelvin
        scene.render.filepath = os.path.join(out_dir, f"t{i}.exr")
        bpy.ops.render.render(write_still=True)
        image = bpy.data.images.load(scene.render.filepath)
        result.append([kelvin, list(image.pixels[:3])])
        bpy.data.images.remove(image)
    print("BLACKBODY " + json.dumps({"blender": bpy.app.version_string, "colours": result}))


main()
