"""``lgh.render_gi`` against ``lgh gi``: the same settings give the same image, bit for bit
(both run lgh-cli's code), on the repository's own Cornell box with a mirror and glass
(``tests/data/cornell-specular``); every bad input is one exception with the command's
message; Ctrl-C and the callback's exception stop it.
"""
import subprocess

import numpy as np
import pytest

import lgh
from test_against_the_cli import ROOT, lgh_binary
from test_explosion import read_exr

CORNELL = ROOT / "tests" / "data" / "cornell-specular" / "cornell-specular.obj"
SETTINGS = dict(vpls=2000, width=40, height=30, camera=(0, 1, 3.9, 0, 1, 0, 39))
FLAGS = ["--vpls", "2000", "--width", "40", "--height", "30", "--camera", "0,1,3.9,0,1,0,39"]


def test_the_image_is_the_commands_bit_for_bit(tmp_path):
    out = tmp_path / "gi.exr"
    subprocess.run([str(lgh_binary()), "gi", "--obj", str(CORNELL), "--out", str(out),
                    "--quiet", *FLAGS], check=True, capture_output=True)
    want = read_exr(out)
    got = lgh.render_gi(CORNELL, **SETTINGS)
    assert got.dtype == np.float32 and got.shape == (30, 40, 3)
    assert np.mean(got) > 0
    np.testing.assert_array_equal(got, want)
    # The same bits on one thread; a list of lights is the repeated flag.
    np.testing.assert_array_equal(lgh.render_gi(CORNELL, threads=1, **SETTINGS), want)
    two = lgh.render_gi(CORNELL, light=["point:0,1.5,0,2,2,2", "point:0.5,1,0.5,1,1,1"],
                        no_direct=True, **SETTINGS)
    assert two.shape == (30, 40, 3) and np.mean(two) > 0


def test_bad_input_is_one_exception_with_the_commands_message(tmp_path):
    with pytest.raises(FileNotFoundError, match="--obj"):
        lgh.render_gi(tmp_path / "missing.obj")
    with pytest.raises(ValueError, match="--out: a render into memory writes no files"):
        lgh.render_gi(CORNELL, out=str(tmp_path / "x.exr"))
    with pytest.raises(ValueError, match="--light"):
        lgh.render_gi(CORNELL, light="lamp:1,2,3")
    with pytest.raises(ValueError, match="--camera"):
        lgh.render_gi(CORNELL, camera=(0, 1, 3.9))
    with pytest.raises(ValueError, match="alpha"):
        lgh.render_gi(CORNELL, alpha=-1)
    with pytest.raises(ValueError, match="--no-such-setting"):
        lgh.render_gi(CORNELL, no_such_setting=1)
    assert not any(tmp_path.iterdir())


def test_progress_and_a_stop():
    calls = []
    image = lgh.render_gi(CORNELL, progress=lambda *a: calls.append(a), **SETTINGS)
    assert calls and all(0 <= done <= total for _, done, total in calls)
    assert {"rendering"} <= {phase for phase, _, _ in calls}, calls
    np.testing.assert_array_equal(image, lgh.render_gi(CORNELL, **SETTINGS))

    def refuse(phase, done, total):
        raise RuntimeError(f"stopped in {phase}")

    with pytest.raises(RuntimeError, match="stopped in"):
        lgh.render_gi(CORNELL, progress=refuse, **SETTINGS)
