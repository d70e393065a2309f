"""Writes ``python/lgh/__init__.pyi``: the package's stubs, with ``render_explosion``'s and
``render_gi``'s keyword arguments made from ``lgh explosion``'s and ``lgh gi``'s own flags
(``lgh._lgh.explosion_settings()``, ``gi_settings()``), so that
an editor completes and checks them. ``tests/test_stubs.py`` fails when the committed file is
not what this writes.

    python lgh-py/stubs.py          # after pip install ./lgh-py
"""
import pathlib

STUB = pathlib.Path(__file__).resolve().parent / "python" / "lgh" / "__init__.pyi"


def params(settings):
    """One stub line a setting: its keyword, type and the help's first sentence."""
    out = []
    for name, takes_value, default, choices, help in settings:
        if not takes_value:
            kind = "bool"
        elif choices:
            kind = "Literal[" + ", ".join(repr(c) for c in choices) + "]"
        else:
            kind = "_Value"
        shown = f" (default {default})" if default is not None else ""
        out.append(f"    {name}: {kind} | None = ...,  # {help}{shown}"[:200].rstrip())
    return out


def stubs():
    from lgh._lgh import explosion_settings, gi_settings

    lines = [
        '"""Stubs of the package ``lgh``; written by ``lgh-py/stubs.py`` from `lgh explosion`\'s',
        'and `lgh gi`\'s flags: do not edit by hand."""',
        "import os",
        "from typing import Callable, Literal, Sequence",
        "",
        "import numpy as np",
        "import numpy.typing as npt",
        "",
        "from ._lgh import FrameRender as FrameRender",
        "from ._lgh import Hierarchy as Hierarchy",
        "from ._lgh import RenderError as RenderError",
        "from ._lgh import __version__ as __version__",
        "from ._lgh import explosion_settings as explosion_settings",
        "from ._lgh import gi_settings as gi_settings",
        "from ._lgh import write_procedural as write_procedural",
        "",
        "_Value = str | int | float | Sequence[str | int | float] | os.PathLike[str]",
        "",
        "def render_explosion(",
        "    vdb: str | os.PathLike[str],",
        "    *,",
        "    progress: Callable[[str, int, int], object] | None = ...,",
        "    threads: int | None = ...,",
        *params(explosion_settings()),
        ") -> npt.NDArray[np.float32] | dict[int, npt.NDArray[np.float32]]:",
        '    """`lgh explosion --vdb VDB` with the settings given, rendered into memory."""',
        "",
        "def render_gi(",
        "    obj: str | os.PathLike[str],",
        "    *,",
        "    progress: Callable[[str, int, int], object] | None = ...,",
        "    threads: int | None = ...,",
        *params(gi_settings()),
        ") -> npt.NDArray[np.float32]:",
        '    """`lgh gi --obj OBJ` with the settings given, rendered into memory."""',
        "",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    STUB.write_text(stubs())
    print(f"wrote {STUB}")
