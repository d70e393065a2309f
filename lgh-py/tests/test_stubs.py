"""The package's stubs and ``render_explosion``'s docstring name every setting of `lgh
explosion`, from the command's own flags: a flag added to the command without its stub fails
here (``python lgh-py/stubs.py`` writes them)."""
import ast
import pathlib
import sys

import lgh

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
import stubs  # noqa: E402


def test_the_committed_stubs_are_what_stubs_py_writes():
    committed = stubs.STUB.read_text()
    assert committed == stubs.stubs(), "python/lgh/__init__.pyi is stale: run python lgh-py/stubs.py"


def test_every_setting_is_a_keyword_and_in_the_docstring():
    settings = lgh.explosion_settings()
    names = [s[0] for s in settings]
    # The command's flags, the render into memory's alone: no file flags, no --vdb.
    assert {"albedo", "scatter_depth", "scatter_stop", "scatter_skip", "camera", "frames",
            "no_domain_offset", "emission_interpolation", "quiet"} <= set(names)
    assert not {"out", "prepare", "manifest", "resume", "vdb"} & set(names)
    defaults = {s[0]: s[2] for s in settings}
    assert defaults["emission_grid"] == "temperature" and defaults["no_domain_offset"] is None
    tree = ast.parse(stubs.STUB.read_text())
    fn = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "render_explosion")
    assert [a.arg for a in fn.args.kwonlyargs] == ["progress", "threads"] + names
    for name in names:
        assert f"``{name}=" in lgh.render_explosion.__doc__, name


def test_every_gi_setting_is_a_keyword_and_in_the_docstring():
    settings = lgh.gi_settings()
    names = [s[0] for s in settings]
    assert {"light", "vpls", "bounces", "alpha", "backend", "camera", "width", "no_direct",
            "quiet"} <= set(names)
    assert not {"out", "obj"} & set(names)
    tree = ast.parse(stubs.STUB.read_text())
    fn = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "render_gi")
    assert [a.arg for a in fn.args.kwonlyargs] == ["progress", "threads"] + names
    for name in names:
        assert f"``{name}=" in lgh.render_gi.__doc__, name
