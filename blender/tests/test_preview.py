"""The viewport's progressive preview, through its Python API (bpy in background mode has no
viewport to draw in): a quarter-resolution image first, then the full one; a new view restarts
it and stops the render it replaces; the viewport's camera is the camera object's when the
viewport looks through it (its projection matrix from ``Object.calc_matrix_camera``).
"""
import threading

import numpy as np
import pytest

from scenes import build, bpy


def test_the_viewport_through_the_camera_is_the_cameras_render(fireball):
    from lgh_blender import camera, preview

    scene, _ = build(fireball, eye=(1.0, -6.0, 1.5), rotation=(78.0, 20.0, -8.0),
                     shift=(0.1, 0.05), width=64, height=40)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    cam = scene.camera.evaluated_get(depsgraph)
    want = camera.settings(scene, cam)
    window = cam.calc_matrix_camera(depsgraph, x=64, y=40)
    got = preview.viewport_camera(cam.matrix_world.inverted(), window, 64, 40)
    assert got.keys() == want.keys()
    for key in want:
        np.testing.assert_allclose(np.ravel(got[key]), np.ravel(want[key]), rtol=0, atol=1e-5,
                                   err_msg=key)
    # An orthographic view is no preview.
    scene.camera.data.type = "ORTHO"
    depsgraph = bpy.context.evaluated_depsgraph_get()
    cam = scene.camera.evaluated_get(depsgraph)
    ortho = cam.calc_matrix_camera(depsgraph, x=64, y=40)
    assert preview.viewport_camera(cam.matrix_world.inverted(), ortho, 64, 40) is None


def test_a_quarter_resolution_first_then_full_and_a_new_view_restarts(fireball):
    from lgh_blender import engine, preview
    from lgh_blender.scene import job

    build(fireball, width=64, height=40)
    the_job = job(bpy.context.evaluated_depsgraph_get())
    sizes, release = [], threading.Event()

    def render(j, progress):
        sizes.append((j.settings["width"], j.settings["height"]))
        return engine.render_job(j, progress)

    p = preview.Progressive(render)
    p.restart(the_job)
    p.wait()
    assert sizes == [(16, 10), (64, 40)] and p.passes_done == 2 and p.error is None
    # The last pass is the final render's image.
    np.testing.assert_array_equal(p.image, engine.render_job(the_job))

    # A new view while the first pass renders: the old render stops at its next report and
    # the preview ends with the new view's images.
    started = threading.Event()

    def slow(j, progress):
        def hold(*a):
            started.set()
            release.wait(10)
            progress(*a)
        return engine.render_job(j, hold)

    p = preview.Progressive(slow)
    p.restart(the_job)
    assert started.wait(30)
    other = the_job.with_settings(dict(the_job.settings, camera=(0, -5, 0, 0, 0, 0, 30)))
    p._render = render
    sizes.clear()
    p.restart(other)
    release.set()
    p.wait()
    assert sizes == [(16, 10), (64, 40)] and p.passes_done == 2
    np.testing.assert_array_equal(p.image, engine.render_job(other))


def test_a_bad_view_is_an_error_not_an_image(fireball):
    from lgh_blender import preview
    from lgh_blender.scene import job

    build(fireball, width=32, height=20)
    the_job = job(bpy.context.evaluated_depsgraph_get())
    bad = the_job.with_settings(dict(the_job.settings, camera=(0, 0, 0, 0, 0, 0, 30)))
    from lgh_blender import engine

    p = preview.Progressive(lambda j, progress: engine.render_job(j, progress))
    p.restart(bad)
    p.wait()
    assert p.image is None and "eye is at the target" in p.error


def test_a_new_view_renders_the_prepared_frames_again(fireball):
    """Each pass's frame is prepared once: a second view renders both passes from the frames
    the first view prepared, and its image is that prepared frame's render of the new view."""
    import lgh
    from lgh_blender import preview
    from lgh_blender.scene import job

    build(fireball, width=64, height=40)
    first = job(bpy.context.evaluated_depsgraph_get())
    second = first.with_settings(dict(first.settings, camera=(1, -5, 0.5, 0, 0, 0, 30)))
    prepared = preview.Prepared()
    p = preview.Progressive(prepared.render)
    p.restart(first)
    p.wait()
    assert prepared.prepared == 2 and p.passes_done == 2
    p.restart(second)
    p.wait()
    assert prepared.prepared == 2 and p.passes_done == 2 and p.error is None
    frame = lgh.FrameRender(first.vdb, **first.settings)
    view = {k: second.settings[k] for k in ("camera_up", "width", "height")}
    np.testing.assert_array_equal(p.image, frame.render(second.settings["camera"], **view))
    # Another scene's settings prepare again.
    third = first.with_settings(dict(first.settings, density_scale=2.0))
    p.restart(third)
    p.wait()
    assert prepared.prepared == 4
