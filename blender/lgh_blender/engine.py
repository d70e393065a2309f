"""The render engine ``LGH``: F12 (and ``blender -b scene.blend -E LGH -f N``) renders the scene's
Volume object lit by its own fire through the lighting grid hierarchy, with nothing to restate:
:mod:`.scene` reads the camera, the resolution and the Principled Volume, ``lgh`` renders, and
the image is the render result. What the scene asks for that LGH does not render is named in
Blender's report, once each; what it cannot render at all is the report's one error, and no
image is written.
"""
import bpy

from . import preview, room, sampling
from .errors import Refused
from .pixels import rgba_rows_up
from .scene import job


#: The last final render's report: ``(level, message)`` pairs, as Blender's report shows them
#: (for scripts and tests; Blender's own report is the user's).
last_report = []


class _Stopped(Exception):
    """Esc pressed: the render stops within a row."""


def region(render, image):
    """The render region of ``render`` (Output > Render Region) cut from the whole ``image``
    (rows from the top); the whole image without one. Blender's region is ``border × size``,
    truncated (``disprect``), y from the bottom."""
    if not render.use_border:
        return image
    h, w, _ = image.shape
    x0, x1 = int(render.border_min_x * w), int(render.border_max_x * w)
    y0, y1 = int(render.border_min_y * h), int(render.border_max_y * h)
    # Rows from the top: the region's rows from the bottom are h - y1 .. h - y0.
    return image[h - y1:h - y0, x0:x1]


def render_job(the_job, progress=None, threads=None):
    """``lgh.render_explosion`` of a :class:`~.scene.Job` (``threads``: Blender's fixed thread
    count, else every core)."""
    import lgh

    return lgh.render_explosion(the_job.vdb, progress=progress, threads=threads,
                                **the_job.settings)


class LGHRenderEngine(bpy.types.RenderEngine):
    """The lighting grid hierarchy's render of a fire: final renders and the viewport."""

    bl_idname = "LGH"
    bl_label = "LGH"
    bl_use_preview = False
    bl_use_shading_nodes_custom = False

    def say(self, level, message):
        """Reports ``message`` in Blender's report and in :data:`last_report`."""
        last_report.append((level, message))
        self.report({level}, message)

    def render(self, depsgraph):
        last_report.clear()
        try:
            self._render(depsgraph)
        except Exception as e:
            # A fault of the add-on: said in the report, never a crash of Blender (an exception
            # out of RenderEngine.render makes Blender 5.2 write a missing result and fault).
            import traceback

            traceback.print_exc()
            self.say("ERROR", f"LGH: {type(e).__name__}: {e}")

    def _render(self, depsgraph):
        scene = depsgraph.scene
        try:
            the_job = job(depsgraph)
        except Refused as e:
            self.say("ERROR", f"LGH: {e}")
            return
        r = scene.render
        threads = r.threads if r.threads_mode == "FIXED" else None
        phases = {"scattering": 0.0, "shadow maps": 0.1, "rendering": 0.2, "scatter shares": 0.9}

        def progress(phase, done, total):
            if self.test_break():
                raise _Stopped()
            start = phases.get(phase, 0.0)
            self.update_stats("", f"LGH: {phase} {done}/{total}")
            self.update_progress(start + (0.8 if phase == "rendering" else 0.1)
                                 * (done / total if total else 1.0))

        import lgh

        with room.Room(depsgraph, the_job.meshes, the_job.local, the_job.notes) as walls:
            for note in dict.fromkeys(the_job.notes):
                self.say("WARNING", f"LGH does not render {note}")
            if walls is not None:
                the_job = the_job.with_settings(dict(the_job.settings, scene=walls))
            try:
                image = render_job(the_job, progress, threads)
            except _Stopped:
                return
            except (ValueError, FileNotFoundError, lgh.RenderError) as e:
                self.say("ERROR", f"LGH: {e}")
                return
        image = region(scene.render, image)
        h, w, _ = image.shape
        # The result's coordinates are the region's own (0, 0: its lower left corner).
        result = self.begin_result(0, 0, w, h)
        try:
            result.layers[0].passes["Combined"].rect.foreach_set(rgba_rows_up(image))
        finally:
            self.end_result(result)

    def __del__(self):
        # The viewport's engine is freed: its preview stops at its next report.
        state = getattr(self, "_lgh_preview", None)
        if state is not None:
            state["progressive"].stop()

    def view_update(self, context, depsgraph):
        preview.update(self, context, depsgraph)

    def view_draw(self, context, depsgraph):
        preview.draw(self, context, depsgraph)


#: Panels of Blender's own UI shown for LGH: the camera, the render's format, the material's and
#: the world's (LGH reads what they set; Cycles' panels need Cycles).
PANELS = (
    "RENDER_PT_format", "RENDER_PT_frame_range", "RENDER_PT_output",
    "DATA_PT_lens", "DATA_PT_camera", "DATA_PT_camera_dof",
    "DATA_PT_context_volume", "DATA_PT_volume_file", "DATA_PT_volume_grids",
    "DATA_PT_volume_render", "MATERIAL_PT_preview", "EEVEE_MATERIAL_PT_context_material",
    "EEVEE_MATERIAL_PT_volume", "EEVEE_MATERIAL_PT_surface", "EEVEE_WORLD_PT_surface",
    "WORLD_PT_context_world",
)


def panels():
    """The panel classes above that this Blender has."""
    return [getattr(bpy.types, name) for name in PANELS if hasattr(bpy.types, name)]


def register():
    sampling.register()
    bpy.utils.register_class(LGHRenderEngine)
    for panel in panels():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if engines is not None:
            engines.add("LGH")


def unregister():
    for panel in panels():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if engines is not None:
            engines.discard("LGH")
    bpy.utils.unregister_class(LGHRenderEngine)
    sampling.unregister()
