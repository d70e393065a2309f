"""The viewport's progressive preview: the scene as the viewport sees it, first at a quarter of
the viewport's resolution (a sixteenth of its pixels) with single scattering, one ray a pixel
(its emission's too), a lighting cache 16 voxels apart and two-voxel steps — under a second for the dev fire's frame
56 at 640×360 on two cores —, then at full resolution and full quality (the final render's settings), each
drawn as soon as it is done; a change of the view, the frame or a setting restarts it, and the
render it replaces stops within a row. Each pass's frame is made ready once
(:class:`Prepared`, ``lgh.FrameRender``) and a new view renders only its camera's rays.

The renders run on a worker thread (``lgh`` releases the GIL while it works); ``view_draw``
draws the newest finished image and asks for another draw while a finer one is coming.
:class:`Progressive` holds that logic without Blender's drawing, so that it can be tested in
background mode, where there is no viewport.
"""
import math
import threading

from . import camera, room
from .pixels import rgba_rows_up
from .scene import job

#: The preview's passes: the divisor of the viewport's width and height, and the settings that
#: replace the final render's (the first pass's make it quick: no scattering pass, one ray a
#: pixel — the emission's too, not ``--emission-samples auto``'s finer filter —, the coarsest lighting cache, two-voxel steps — on the dev fire's frame 56 at 160×90
#: its render takes half the time of one-voxel steps and a cache 8 voxels apart, and its mean
#: moves by 1.3%).
PASSES = (
    (4, {"scatter_depth": 0, "pixel_samples": 1, "emission_samples": 1, "cache_spacing": 16,
         "step": 2}),
    (1, {}),
)


def viewport_camera(view_matrix, window_matrix, width, height, local=None):
    """``lgh``'s camera settings for a viewport: its view matrix (world to view) and its
    perspective projection (``window_matrix``), ``width × height`` pixels. ``None`` for an
    orthographic view, which LGH does not render."""
    p = window_matrix
    if abs(p[3][3]) > 0.5:
        return None
    tan_v = 1.0 / p[1][1]
    fov = math.degrees(2.0 * math.atan(tan_v))
    larger = 2.0 * tan_v * max(width / height, 1.0)
    shift = ((p[0][2] / p[0][0]) / larger, (p[1][2] / p[1][1]) / larger)
    return camera.flags(camera.view(view_matrix.inverted()), fov, shift, (width, height), local)


class Progressive:
    """Renders ``job`` (a :class:`~.scene.Job`) at each of :data:`PASSES` in turn on a worker
    thread, keeping the newest image; :meth:`restart` with a new job stops the current one.
    ``render(job, progress)`` renders (``lgh.render_explosion`` through the engine)."""

    def __init__(self, render):
        self._render = render
        self._lock = threading.Lock()
        self._generation = 0
        self._thread = None
        self.image = None
        self.passes_done = 0
        self.error = None

    def restart(self, the_job):
        """Starts over with ``the_job``; the running render stops at its next report."""
        with self._lock:
            self._generation += 1
            generation = self._generation
            self.passes_done, self.error = 0, None
        thread = threading.Thread(target=self._run, args=(the_job, generation), daemon=True)
        self._thread = thread
        thread.start()

    def stop(self):
        """Stops the running render (the engine is freed)."""
        with self._lock:
            self._generation += 1

    def busy(self):
        """Whether a finer image is still coming."""
        return self._thread is not None and self._thread.is_alive()

    def wait(self):
        """Waits for the passes of the current job (tests)."""
        if self._thread is not None:
            self._thread.join()

    def _run(self, the_job, generation):
        def progress(phase, done, total):
            if self._generation != generation:
                raise _Superseded()

        for divisor, quick in PASSES:
            settings = dict(the_job.settings, **quick)
            settings["width"] = max(1, settings["width"] // divisor)
            settings["height"] = max(1, settings["height"] // divisor)
            scaled = the_job.with_settings(settings)
            try:
                image = self._render(scaled, progress)
            except _Superseded:
                return
            except Exception as e:  # shown in the viewport instead of an image
                with self._lock:
                    if self._generation == generation:
                        self.error = str(e)
                return
            with self._lock:
                if self._generation != generation:
                    return
                self.image = image
                self.passes_done += 1


class _Superseded(Exception):
    """A newer view asked for another preview."""


#: The settings that place the view: what a prepared frame renders anew for each view.
VIEW = ("camera", "camera_up", "camera_shift", "width", "height")


class Prepared:
    """The preview's frames made ready once (``lgh.FrameRender``: the frame read, its lights,
    scattering and shadows) for each pass's settings, and rendered from every view after: a
    change of the view costs its camera's rays only; a change of the scene (another job's
    settings) prepares again. ``render(job, progress)`` is :class:`Progressive`'s render."""

    def __init__(self):
        self._lock = threading.Lock()
        self._frames = {}
        self.prepared = 0

    def render(self, the_job, progress):
        import lgh

        settings = the_job.settings
        # The room by its content, not by the path its files were written to this time.
        keyed = {k: v for k, v in settings.items() if k not in VIEW}
        if "scene" in keyed:
            keyed["scene"] = room.digest(keyed["scene"])
        key = (the_job.vdb, repr(sorted(keyed.items())))
        with self._lock:  # a superseded preparation stops at its next report
            frame = self._frames.get(key)
            if frame is None:
                frame = lgh.FrameRender(the_job.vdb, progress=progress, **settings)
                # Two passes' settings, nothing older: a scene change drops the old frames.
                if len(self._frames) >= len(PASSES):
                    self._frames.clear()
                self._frames[key] = frame
                self.prepared += 1
        view = {k: settings[k] for k in VIEW if k in settings}
        return frame.render(view.pop("camera"), progress=progress, **view)


def _state(engine):
    state = getattr(engine, "_lgh_preview", None)
    if state is None:
        prepared = Prepared()
        state = {"progressive": Progressive(prepared.render), "prepared": prepared,
                 "key": None, "job": None, "texture": None, "drawn": None}
        engine._lgh_preview = state
    return state


def update(engine, context, depsgraph):
    """``view_update``: the scene changed (a setting, the frame): read it again."""
    state = _state(engine)
    try:
        the_job = job(depsgraph, view_only=True)
        state["error"] = None
    except Exception as e:  # a refusal, or a fault: said in the viewport, never raised
        state["job"], state["error"] = None, str(e)
        state["key"] = None
        state["progressive"].stop()
        return
    walls = room.Room(depsgraph, the_job.meshes, the_job.local, the_job.notes)
    path = walls.__enter__()
    if path is not None:
        the_job = the_job.with_settings(dict(the_job.settings, scene=path))
        # The files live as long as the jobs that name them (a render may still read them).
        the_job.keep = walls
    state["job"] = the_job
    state["key"] = None  # restart at the next draw


def draw(engine, context, depsgraph):
    """``view_draw``: restart the preview if the view changed, draw the newest image."""
    state = _state(engine)
    region, rv3d = context.region, context.region_data
    if state["job"] is None and state.get("error") is None:
        update(engine, context, depsgraph)
    the_job = state["job"]
    if the_job is None:
        _say(context, f"LGH: {state.get('error')}")
        return
    key = (tuple(map(tuple, rv3d.view_matrix)), tuple(map(tuple, rv3d.window_matrix)),
           region.width, region.height, id(the_job))
    progressive = state["progressive"]
    if key != state["key"]:
        state["key"] = key
        view = viewport_camera(rv3d.view_matrix, rv3d.window_matrix, region.width,
                               region.height, the_job.local)
        if view is None:
            progressive.stop()
            state["ortho"] = True
        else:
            state["ortho"] = False
            settings = {k: v for k, v in the_job.settings.items() if k != "camera_shift"}
            settings.update(view)
            progressive.restart(the_job.with_settings(settings))
    if state.get("ortho"):
        _say(context, "LGH previews perspective views only")
        return
    # Whether a finer image is coming, asked first: an image stored after this is drawn at the
    # redraw it asks for.
    busy = progressive.busy()
    image = progressive.image
    if image is not None:
        _blit(engine, context, state, image)
    if progressive.error is not None:
        _say(context, f"LGH: {progressive.error}")
    if busy:
        engine.tag_redraw()


def _say(context, text):
    """Writes ``text`` at the viewport's lower left corner (an error instead of an image)."""
    import blf

    font = 0
    blf.size(font, 13.0)
    blf.color(font, 1.0, 1.0, 1.0, 1.0)
    blf.position(font, 12.0, 12.0, 0.0)
    blf.draw(font, text)


def _blit(engine, context, state, image):
    """Draws ``image`` (rows from the top) over the viewport, through Blender's colour
    management (``bind_display_space_shader``)."""
    import gpu
    from gpu_extras.presets import draw_texture_2d

    if state["drawn"] is not image:
        h, w, _ = image.shape
        buffer = gpu.types.Buffer("FLOAT", w * h * 4, rgba_rows_up(image))
        state["texture"] = gpu.types.GPUTexture((w, h), format="RGBA16F", data=buffer)
        state["drawn"] = image
    region = context.region
    scene = context.scene
    gpu.state.blend_set("ALPHA_PREMULT")
    engine.bind_display_space_shader(scene)
    draw_texture_2d(state["texture"], (0, 0), region.width, region.height)
    engine.unbind_display_space_shader()
    gpu.state.blend_set("NONE")
