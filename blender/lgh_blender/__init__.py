"""LGH for Blender: a render engine (``bl_idname`` ``"LGH"``) that renders a scene's OpenVDB
Volume object lit by its own fire through the Lighting Grid Hierarchy (Yuksel and Yuksel, 2017),
with the package ``lgh`` (``lgh-py``). Pick *LGH* as the render engine and press F12, or run
``blender -b scene.blend -E LGH -f N``; the viewport's *Rendered* shading previews it
progressively. What it reads and what it names instead of rendering: :mod:`.scene`.

A script that puts ``blender/`` on ``sys.path`` imports it and calls :func:`register`; as a
Blender 4.2+ extension (``blender/pack.py`` packs it with the ``lgh`` wheel) Blender does.
"""

bl_info = {
    "name": "LGH",
    "description": "Fires lit by their own light: the Lighting Grid Hierarchy",
    "blender": (4, 2, 0),
    "category": "Render",
}


def register():
    from . import engine

    engine.register()


def unregister():
    from . import engine

    engine.unregister()
