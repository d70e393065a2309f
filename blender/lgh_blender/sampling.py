"""The engine's own render settings (Render Properties > Sampling, ``scene.lgh``): how finely
LGH samples what the .blend describes. Each is *Auto* by default — ``lgh explosion``'s own rule
— or a fixed value; the final render and the preview's full-quality pass both use them.

- **Pixel samples**: camera rays per side of a pixel, ``N × N`` rays through the centres of
  ``N × N`` sub-pixels averaged: a one-pixel box filter, as Cycles' *Box* filter of width 1
  draws (``--pixel-samples``). Auto takes the fewest, at most 4, for which a sub-pixel covers
  at most three quarters of a voxel at the volume's centre.
- **Emission samples**: camera rays per side of a pixel for the emission alone, where more
  than the pixel samples: a thin flame's emission varies far below a voxel, the light the smoke
  scatters as the smoke does, and an emission ray reads no light (``--emission-samples``). Auto
  takes the fewest, at most 8 and at least the pixel samples, for which an emission sub-pixel
  covers at most a quarter of a voxel.
- **Scatter spacing**: the grid, in voxels, on which multiple scattering's deeper depths
  compute their light (``--scatter-spacing``; paper Sec. 5). Auto takes 4, 2 or 1, at least 9
  cells across the smoke.

Finer values come nearer the converged image and cost more; docs/blender.md races Auto and a
fixed 4 / 2 against Cycles 5.2.3 (``blender/race.py --sampling auto,4/2``).
"""
import bpy

#: (identifier, name, description) of the two ways each setting is chosen.
AUTO = ("AUTO", "Auto", "lgh explosion's own rule (see the setting's description)")
FIXED = ("FIXED", "Fixed", "The value given here")


def _choice(name, description):
    """How a setting is chosen: Auto or Fixed."""
    return bpy.props.EnumProperty(name=name, description=description, items=[AUTO, FIXED],
                                  default="AUTO")


def _fixed(name, description):
    """A setting's fixed value: 1 to 8."""
    return bpy.props.IntProperty(name=name, description=description, default=2, min=1, max=8)


class LGHSettings(bpy.types.PropertyGroup):
    """``scene.lgh``: see the module's text."""

    pixel_sampling: _choice(
        "Pixel Samples",
        "Camera rays per side of a pixel: auto (the fewest, at most 4, for which a sub-pixel "
        "covers at most 3/4 of a voxel) or fixed")
    pixel_samples: _fixed(
        "Rays per Side",
        "N: N x N camera rays through the centres of N x N sub-pixels, averaged (a one-pixel "
        "box filter, as Cycles' Box filter of width 1). The render's rays cost about N "
        "squared as much")
    emission_sampling: _choice(
        "Emission Samples",
        "Camera rays per side of a pixel for the emission alone: auto (the fewest, at most 8 "
        "and at least the pixel samples, for which a sub-pixel covers at most a quarter of a "
        "voxel) or fixed")
    emission_samples: _fixed(
        "Emission Rays per Side",
        "N: the emission alone is the box filter of N x N rays that read no light, where N is "
        "more than the pixel samples (thin flames vary below a voxel); a fraction of a lit "
        "ray's cost")
    scatter_grid: _choice(
        "Scatter Spacing",
        "The grid of multiple scattering's deeper depths: auto (4, 2 or 1 voxels, at least 9 "
        "cells across the smoke) or fixed")
    scatter_spacing: _fixed(
        "Voxels",
        "Distance between the scattering grid's points, in voxels (1: every voxel; finer is "
        "more accurate and slower)")


def settings(scene):
    """``lgh.render_explosion``'s keyword arguments for ``scene``'s LGH settings: none for Auto
    (the library's default), the value where Fixed. A scene without them (the add-on's
    settings unregistered) gets none."""
    s = getattr(scene, "lgh", None)
    if s is None:
        return {}
    out = {}
    if s.pixel_sampling == "FIXED":
        out["pixel_samples"] = s.pixel_samples
    if s.emission_sampling == "FIXED":
        out["emission_samples"] = s.emission_samples
    if s.scatter_grid == "FIXED":
        out["scatter_spacing"] = s.scatter_spacing
    return out


class LGH_PT_sampling(bpy.types.Panel):
    """Render Properties > Sampling, for LGH."""

    bl_idname = "LGH_PT_sampling"
    bl_label = "Sampling"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"LGH"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        s = context.scene.lgh
        layout.prop(s, "pixel_sampling")
        row = layout.row()
        row.active = s.pixel_sampling == "FIXED"
        row.prop(s, "pixel_samples")
        layout.prop(s, "emission_sampling")
        row = layout.row()
        row.active = s.emission_sampling == "FIXED"
        row.prop(s, "emission_samples")
        layout.prop(s, "scatter_grid")
        row = layout.row()
        row.active = s.scatter_grid == "FIXED"
        row.prop(s, "scatter_spacing")


CLASSES = (LGHSettings, LGH_PT_sampling)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.lgh = bpy.props.PointerProperty(type=LGHSettings)


def unregister():
    del bpy.types.Scene.lgh
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
