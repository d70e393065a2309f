"""Baking a Mantaflow domain with Blender 3.4.1, as ``blender/domain_check.py`` and
``tools/caches/bake.py`` do: ``bake`` inside Blender (whose Python has neither numpy nor
pytest: this module imports nothing else at its top), ``retried`` in the Python that drives it.
"""
import os
import shutil
import sys


def retried(directory, run, baked, tries=6):
    """Runs Blender's bake (``run()``, which returns its completed process) into ``directory``,
    made anew for each try, until ``baked()`` says the files are there, at most ``tries`` times:
    Blender 3.4.1's bake fails every other run on this machine, and always into a directory it
    must make. Returns whether it baked and the last run (for its output)."""
    for _ in range(tries):
        shutil.rmtree(directory, ignore_errors=True)
        directory.mkdir(parents=True)
        last = run()
        if baked():
            return True, last
    return False, last


def bake(domain, data, frames, who):
    """Bakes ``domain`` until its cache folder ``data`` holds ``frames`` files, at most five
    tries, then saves the scene beside the cache as ``scene.blend``. Mantaflow's first
    evaluation fails now and then (a grid it has not made yet); baking again in the same
    process then works. ``who`` names the script in what it prints."""
    import bpy

    for _ in range(5):
        try:
            with bpy.context.temp_override(object=domain, active_object=domain):
                bpy.ops.fluid.bake_all()
        except (RuntimeError, SystemError) as e:
            print(f"{who}: the bake failed ({e}); again", file=sys.stderr)
        if os.path.isdir(data) and len(os.listdir(data)) >= frames:
            break
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(os.path.dirname(data), "scene.blend"))
