"""Baking a Mantaflow domain inside Blender 3.4.1 (whose Python has neither numpy nor pytest), as
``blender/domain_check.py`` and ``tools/caches/bake.py`` do: in a module of its own that imports
nothing but ``bpy``.
"""
import os
import sys

import bpy


def bake(domain, data, frames, who):
    """Bakes ``domain`` until its cache folder ``data`` holds ``frames`` files, at most five
    tries, then saves the scene beside the cache as ``scene.blend``. Mantaflow's first
    evaluation fails now and then (a grid it has not made yet); baking again in the same
    process then works. ``who`` names the script in what it prints."""
    for _ in range(5):
        try:
            with bpy.context.temp_override(object=domain, active_object=domain):
                bpy.ops.fluid.bake_all()
        except (RuntimeError, SystemError) as e:
            print(f"{who}: the bake failed ({e}); again", file=sys.stderr)
        if os.path.isdir(data) and len(os.listdir(data)) >= frames:
            break
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(os.path.dirname(data), "scene.blend"))
