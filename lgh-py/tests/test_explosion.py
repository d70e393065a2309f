"""``lgh.render_explosion`` against ``lgh explosion``: the same settings give the same image, bit
for bit (both run lgh-cli's code; Python's renders into memory instead of an EXR), on the dev
fire's frame 56; and every bad input is one exception with the command's message.

Needs the shared data (``../shared/data``) and the `lgh` binary: skipped with a message without
them, a failure where ``LGH_REQUIRE_ALL`` is set (``.ci/run``).
"""
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import lgh
from test_against_the_cli import ROOT, lgh_binary

FIRE = ROOT.parent / "shared" / "data" / "volumes" / "blender_fire_pesichra" / "data"


def fire_frame(n):
    path = FIRE / f"fluid_data_{n:04d}.vdb"
    if path.is_file():
        return path
    if os.environ.get("LGH_REQUIRE_ALL"):
        pytest.fail(f"no {path} (the shared data)")
    pytest.skip(f"SKIPPED: no {path} (the shared data, ../shared/data)")


def read_exr(path):
    import OpenEXR

    with OpenEXR.File(str(path)) as f:
        channels = f.channels()
        if "RGB" in channels:
            return np.asarray(channels["RGB"].pixels, dtype=np.float32)
        return np.stack([channels[c].pixels for c in "RGB"], axis=-1).astype(np.float32)


def test_the_image_is_the_commands_bit_for_bit(tmp_path):
    binary, vdb = lgh_binary(), fire_frame(56)
    settings = dict(width=40, height=24, pixel_samples=1, scatter_depth="auto", albedo=0.7)
    flags = ["--width", "40", "--height", "24", "--pixel-samples", "1", "--scatter-depth",
             "auto", "--albedo", "0.7"]
    out = tmp_path / "fire.exr"
    subprocess.run([str(binary), "explosion", "--vdb", str(vdb), "--out", str(out), "--quiet",
                    *flags], check=True, capture_output=True)
    want = read_exr(out)
    got = lgh.render_explosion(vdb, **settings)
    assert got.dtype == np.float32 and got.shape == (24, 40, 3)
    assert np.any(got > 0)
    np.testing.assert_array_equal(got, want)
    # A camera as a tuple is the command's comma-separated one.
    cam = (0.53, -2.16, 0.455, 0.53, 0.34, 0.455, 40)
    a = lgh.render_explosion(vdb, camera=cam, width=16, height=16, scatter_depth=0)
    b = lgh.render_explosion(vdb, camera=",".join(map(str, cam)), width=16, height=16,
                             scatter_depth=0)
    np.testing.assert_array_equal(a, b)


def test_bad_input_is_one_exception_with_the_commands_message(tmp_path):
    vdb = fire_frame(56)
    with pytest.raises(FileNotFoundError, match="no such file"):
        lgh.render_explosion(tmp_path / "missing.vdb")
    with pytest.raises(ValueError, match="--no-such-setting"):
        lgh.render_explosion(vdb, no_such_setting=1)
    with pytest.raises(ValueError, match="--out: a render into memory writes no files"):
        lgh.render_explosion(vdb, out=str(tmp_path / "x.exr"))
    with pytest.raises(ValueError, match="--scatter-depth"):
        lgh.render_explosion(vdb, scatter_depth="often")
    with pytest.raises(ValueError, match="--albedo 2 must be in 0..=1"):
        lgh.render_explosion(vdb, albedo=2)
    with pytest.raises(ValueError, match="--camera"):
        lgh.render_explosion(vdb, camera=(0, 0, 5, 0, 0))
    with pytest.raises(FileNotFoundError, match="is a folder"):
        lgh.render_explosion(tmp_path)
    with pytest.raises(FileNotFoundError, match="fluid_data_0057.vdb: no such file"):
        lgh.render_explosion(vdb, frames="56..57")
    with pytest.raises(FileNotFoundError, match="--scene"):
        lgh.render_explosion(vdb, scene=tmp_path / "room.obj")
    with pytest.raises(lgh.RenderError, match="no grid named 'no_such_grid'"):
        lgh.render_explosion(vdb, emission_grid="no_such_grid", width=8, height=8)
    assert not any(tmp_path.iterdir())


def test_inspect_lists_the_grids_as_the_command_does(tmp_path):
    binary, vdb = lgh_binary(), fire_frame(56)
    out = subprocess.run([str(binary), "inspect", "--json", str(vdb)], check=True,
                         capture_output=True, text=True).stdout
    got = lgh.inspect(vdb)
    assert got == json.loads(out)
    names = [g["name"] for g in got["grids"]]
    assert {"density", "flame", "temperature"} <= set(names), names
    with pytest.raises(FileNotFoundError, match="missing.vdb"):
        lgh.inspect(tmp_path / "missing.vdb")
    (tmp_path / "text.vdb").write_text("not a volume")
    with pytest.raises(lgh.RenderError, match="text.vdb"):
        lgh.inspect(tmp_path / "text.vdb")


def test_progress_is_reported_by_phase_and_changes_nothing():
    vdb = fire_frame(56)
    settings = dict(width=24, height=16, scatter_depth=0)
    calls = []
    image = lgh.render_explosion(vdb, progress=lambda *a: calls.append(a), **settings)
    rendering = [c for c in calls if c[0] == "rendering"]
    assert rendering[0][1] == 0 and rendering[-1][1:] == (16, 16), calls  # rows of the image
    assert all(0 <= done <= total for _, done, total in calls)
    np.testing.assert_array_equal(image, lgh.render_explosion(vdb, **settings))
    # Nor does the number of threads (the library's determinism, through Python).
    np.testing.assert_array_equal(image, lgh.render_explosion(vdb, threads=1, **settings))
    with pytest.raises(ValueError, match="threads must be at least 1"):
        lgh.render_explosion(vdb, threads=0, **settings)



def test_adaptive_pixels_report_their_refinement_after_the_rows():
    """``pixel_samples="adaptive"``'s second pass is a phase of its own after the image's rows,
    its steps the refined pixels, and it ends with every one of them done."""
    vdb = fire_frame(56)
    calls = []
    settings = dict(width=48, height=32, scatter_depth=0, pixel_samples="adaptive")
    image = lgh.render_explosion(vdb, progress=lambda *a: calls.append(a), **settings)
    phases = [c[0] for c in calls]
    assert "refining pixels" in phases, calls
    last_row = max(i for i, p in enumerate(phases) if p == "rendering")
    assert phases.index("refining pixels") > last_row, calls
    done, total = calls[-1][1:]
    assert calls[-1][0] == "refining pixels" and done == total > 0, calls
    np.testing.assert_array_equal(image, lgh.render_explosion(vdb, **settings))
    # A stop asked for during the refinement stops it, and the next render is whole.
    refining = []

    def refuse(phase, done, total):
        if phase == "refining pixels":
            refining.append(done)
            raise RuntimeError("stopped while refining")

    with pytest.raises(RuntimeError, match="stopped while refining"):
        lgh.render_explosion(vdb, progress=refuse, **settings)
    assert refining, "the refinement was never reported"
    np.testing.assert_array_equal(image, lgh.render_explosion(vdb, **settings))


def test_an_exception_in_the_callback_or_ctrl_c_stops_the_render():
    """A stop asked for in the first row ends the render long before its rows are done: the
    callback's exception (or ``KeyboardInterrupt``) is what the call raises, and the next
    render is whole and the same as ever."""
    vdb = fire_frame(56)
    settings = dict(width=64, height=256, scatter_depth=0, pixel_samples=2)
    whole = lgh.render_explosion(vdb, **settings)
    rows = []

    def refuse(phase, done, total):
        if phase == "rendering":
            rows.append(done)
            if done > 0:
                raise RuntimeError(f"stopped in {phase}")

    with pytest.raises(RuntimeError, match="stopped in rendering"):
        lgh.render_explosion(vdb, progress=refuse, **settings)
    # The rows done before the stop was seen: the reports come every 0.1 s, and after the
    # first one each worker stops at its next row.
    assert rows and max(rows) < 256, rows

    import _thread
    import threading
    seen = []

    def watch(phase, done, total):
        if phase == "rendering":
            if not seen:
                threading.Timer(0.05, _thread.interrupt_main).start()
            seen.append(done)

    with pytest.raises(KeyboardInterrupt):
        lgh.render_explosion(vdb, progress=watch, **settings)
    assert seen, "the render never began"
    # Stopped, not finished: a whole render ends with its phase's report of every row; a
    # stopped one reports nothing after the stop.
    assert max(seen) < 256, seen
    np.testing.assert_array_equal(lgh.render_explosion(vdb, **settings), whole)
