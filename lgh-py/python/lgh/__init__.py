"""lgh: millions of point lights through the Lighting Grid Hierarchy (Yuksel & Yuksel 2017).

    >>> import numpy as np, lgh
    >>> rng = np.random.default_rng(1)
    >>> h = lgh.Hierarchy(rng.random((100_000, 3)), np.ones((100_000, 3)), alpha=2.0)
    >>> light = h.probe(rng.random((1_000, 3)) + [0.0, 0.0, 2.0])   # (1000, 3) float32

``render_explosion(vdb, **settings)`` renders a simulation cache as ``lgh explosion`` does,
into an ``(h, w, 3)`` array. ``Hierarchy`` takes numpy arrays (any array-like of shape ``(n, 3)``, converted to float32 once)
and returns them; errors are Python exceptions carrying the library's message: ``ValueError``
for a bad argument, ``lgh.RenderError`` for the rest.
"""
from ._lgh import Hierarchy, RenderError, __version__, render_explosion

__all__ = ["Hierarchy", "RenderError", "__version__", "render_explosion"]
