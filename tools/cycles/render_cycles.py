"""Renders an OpenVDB volume in Blender Cycles the way `lgh explosion` renders it: the scene of
the Cycles comparison (tools/cycles/README.md). Run inside Blender:

    blender -b --factory-startup --python tools/cycles/render_cycles.py -- \
        --vdb F.vdb --out O.exr --spp 256 [--seed 0] [--width 128 --height 128] [--threads 2] \
        [--camera 0,-4,0,0,0,0,40] [--density-scale 4] [--albedo 0.7] [--temperature-scale 1] \
        [--flame] [--bounces 128] [--shift-half-voxel] [--step-rate R]

The scene: the volume object alone (Principled Volume: density attribute `density` times
--density-scale, scattering colour --albedo, absorption colour black, so sigma_t =
density-scale * density and the albedo is --albedo; blackbody intensity 1 with temperature
--temperature-scale times the attribute `temperature`, times the attribute `flame` with
--flame), a black world, a pinhole camera (vertical field of view, degrees), Cycles on the CPU
with --bounces volume bounces (Blender's default is 0: single scattering only), no denoiser, no
clamping, no adaptive sampling, a one-pixel box filter, a linear 32-bit OpenEXR.

--step-rate sets Cycles' volume step rate (Render > Volumes > Step Rate; Blender's default 1):
Cycles 3.x and 4.x ray-march volumes in steps of that many voxels, and their image depends on it;
Blender 5.x's default (unbiased) volume integration does not step, unless the scene asks for the
biased one.

--shift-half-voxel moves the object by half a voxel down each axis: Blender 3.x draws voxel i
over the cell [i, i+1] where OpenVDB (and lgh, and Blender 5.x) put its value at i.

Prints one line `CYCLES {json}` with the render's wall and CPU seconds (this process, all
threads; scene sync included).
"""
import argparse
import json
import math
import resource
import sys
import time

import bpy
from mathutils import Vector


def args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="render_cycles.py")
    p.add_argument("--vdb", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--spp", type=int, required=True)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--width", type=int, default=128)
    p.add_argument("--height", type=int, default=128)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--camera", default="0,-4,0,0,0,0,40")
    p.add_argument("--density-scale", type=float, default=4.0)
    p.add_argument("--albedo", type=float, default=0.7)
    p.add_argument("--temperature-scale", type=float, default=1.0)
    p.add_argument("--flame", action="store_true")
    p.add_argument("--bounces", type=int, default=128)
    p.add_argument("--shift-half-voxel", action="store_true")
    p.add_argument("--step-rate", type=float, default=1.0)
    return p.parse_args(argv)


def main():
    a = args()
    scene = bpy.context.scene
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)

    vol = bpy.data.volumes.new("smoke")
    vol.filepath = a.vdb
    obj = bpy.data.objects.new("smoke", vol)
    scene.collection.objects.link(obj)
    if a.shift_half_voxel:
        vol.grids.load()
        g = vol.grids["density"]
        h = abs(g.matrix_object[0][0])
        obj.location = (-0.5 * h, -0.5 * h, -0.5 * h)

    mat = bpy.data.materials.new("smoke")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    for n in list(nodes):
        nodes.remove(n)
    out = nodes.new("ShaderNodeOutputMaterial")
    pv = nodes.new("ShaderNodeVolumePrincipled")
    pv.inputs["Color"].default_value = (a.albedo, a.albedo, a.albedo, 1.0)
    pv.inputs["Density"].default_value = a.density_scale
    pv.inputs["Density Attribute"].default_value = "density"
    pv.inputs["Absorption Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    pv.inputs["Emission Strength"].default_value = 0.0
    pv.inputs["Blackbody Intensity"].default_value = 1.0
    pv.inputs["Temperature"].default_value = a.temperature_scale
    pv.inputs["Temperature Attribute"].default_value = "temperature"
    if a.flame:
        attr = nodes.new("ShaderNodeAttribute")
        attr.attribute_name = "flame"
        links.new(attr.outputs["Fac"], pv.inputs["Blackbody Intensity"])
    links.new(pv.outputs["Volume"], out.inputs["Volume"])
    vol.materials.append(mat)

    world = bpy.data.worlds.new("black")
    world.color = (0.0, 0.0, 0.0)
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = False
    else:
        # Blender 5.x always shades the world with its node tree (a grey Background by
        # default, which lit the whole image): make its background black.
        world.use_nodes = True
        for node in world.node_tree.nodes:
            if node.type == "BACKGROUND":
                node.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
                node.inputs["Strength"].default_value = 0.0
    scene.world = world

    c = [float(v) for v in a.camera.split(",")]
    eye, target = Vector(c[0:3]), Vector(c[3:6])
    fov = c[6] if len(c) > 6 else 40.0
    cam = bpy.data.cameras.new("camera")
    cam.sensor_fit = "VERTICAL"
    cam.angle = math.radians(fov)
    cam.clip_start, cam.clip_end = 1e-3, 1e4
    cam_obj = bpy.data.objects.new("camera", cam)
    scene.collection.objects.link(cam_obj)
    cam_obj.location = eye
    cam_obj.rotation_euler = (target - eye).to_track_quat("-Z", "Z").to_euler()
    scene.camera = cam_obj

    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y, r.resolution_percentage = a.width, a.height, 100
    r.threads_mode, r.threads = "FIXED", a.threads
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    r.filepath = a.out
    r.use_persistent_data = False
    scene.view_settings.view_transform = "Standard"
    cy = scene.cycles
    cy.device = "CPU"
    cy.samples = a.spp
    cy.seed = a.seed
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.max_bounces = a.bounces
    cy.volume_bounces = a.bounces
    cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = 0
    cy.transparent_max_bounces = a.bounces
    cy.volume_step_rate = a.step_rate
    # A finer step needs more of them: the default cap (1,024) would cut the march short.
    cy.volume_max_steps = max(1024, int(math.ceil(1024 / a.step_rate)))
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0

    t0, c0 = time.time(), resource.getrusage(resource.RUSAGE_SELF)
    bpy.ops.render.render(write_still=True)
    t1, c1 = time.time(), resource.getrusage(resource.RUSAGE_SELF)
    cpu = (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime)
    print("CYCLES " + json.dumps({"version": bpy.app.version_string, "spp": a.spp, "seed": a.seed,
                                   "width": a.width, "height": a.height, "threads": a.threads,
                                   "step_rate": a.step_rate,
                                   "wall_s": round(t1 - t0, 3), "cpu_s": round(cpu, 3),
                                   "out": a.out}))


main()
