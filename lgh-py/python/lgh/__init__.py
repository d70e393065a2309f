"""lgh: millions of point lights through the Lighting Grid Hierarchy (Yuksel & Yuksel 2017).

    >>> import numpy as np, lgh
    >>> rng = np.random.default_rng(1)
    >>> h = lgh.Hierarchy(rng.random((100_000, 3)), np.ones((100_000, 3)), alpha=2.0)
    >>> light = h.probe(rng.random((1_000, 3)) + [0.0, 0.0, 2.0])   # (1000, 3) float32

``render_explosion(vdb, **settings)`` renders a simulation cache as ``lgh explosion`` does,
into an ``(h, w, 3)`` array; ``render_gi(obj, **settings)`` an OBJ scene as ``lgh gi`` does;
``inspect(vdb)`` lists an OpenVDB file's grids as ``lgh inspect --json`` does. ``Hierarchy`` takes numpy arrays (any array-like of shape ``(n, 3)``, converted to float32 once)
and returns them; errors are Python exceptions carrying the library's message: ``ValueError``
for a bad argument, ``lgh.RenderError`` for the rest.
"""
from . import _lgh
from ._lgh import (
    FrameRender, Hierarchy, RenderError, __version__, explosion_settings, gi_settings, inspect,
    write_procedural,
)

__all__ = [
    "FrameRender", "Hierarchy", "RenderError", "__version__", "explosion_settings", "gi_settings",
    "inspect", "render_explosion", "render_gi", "write_procedural",
]


def render_explosion(vdb, *, progress=None, threads=None, **settings):
    return _lgh.render_explosion(vdb, progress=progress, threads=threads, **settings)


def render_gi(obj, *, progress=None, threads=None, **settings):
    return _lgh.render_gi(obj, progress=progress, threads=threads, **settings)


def _settings_doc(settings):
    """The keyword arguments of a render, from the command's own flags."""
    lines = ["", "Settings (keyword arguments; the command's defaults):", ""]
    for name, takes_value, default, choices, help in settings:
        value = "True" if not takes_value else ("|".join(choices) or "value")
        shown = f", default {default}" if default is not None else ""
        lines.append(f"- ``{name}={value}``{shown}: {help}.")
    return "\n".join(lines)


render_explosion.__doc__ = (
    (_lgh.render_explosion.__doc__ or "") + "\n" + _settings_doc(explosion_settings()))
render_gi.__doc__ = (_lgh.render_gi.__doc__ or "") + "\n" + _settings_doc(gi_settings())
