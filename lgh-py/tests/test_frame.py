"""``lgh.FrameRender``: a frame made ready once renders any camera as ``render_explosion`` does,
bit for bit — the prepared camera, and others after it (the lighting cache filled by one
camera's rays is the same for the next: each brick is computed once, the same whoever asks);
bad arguments are ``ValueError``s.
"""
import numpy as np
import pytest

import lgh
from test_explosion import fire_frame

# Fixed where ``auto`` would depend on the camera: every camera then renders with the same
# settings as a render of its own.
SETTINGS = dict(width=40, height=24, pixel_samples=1, emission_samples=2, cache_level=1,
                albedo=0.7, scatter_depth="auto")
FRONT = (0.53, -2.16, 0.455, 0.53, 0.34, 0.455, 40)
SIDE = (-1.7, 0.34, 0.6, 0.53, 0.34, 0.455, 35)


def test_every_camera_is_render_explosions_image_bit_for_bit():
    vdb = fire_frame(56)
    frame = lgh.FrameRender(vdb, camera=FRONT, **SETTINGS)
    assert frame.size == (40, 24) and frame.lights > 0
    np.testing.assert_array_equal(frame.render(),
                                  lgh.render_explosion(vdb, camera=FRONT, **SETTINGS))
    side = frame.render(SIDE, camera_up=(0, 0, 1), camera_shift=(0.05, 0))
    want = lgh.render_explosion(vdb, **dict(SETTINGS, camera=SIDE, camera_up=(0, 0, 1),
                                            camera_shift=(0.05, 0)))
    assert np.mean(side) > 0
    np.testing.assert_array_equal(side, want)
    small = frame.render(",".join(map(str, FRONT)), width=20, height=12)
    assert small.shape == (12, 20, 3)
    np.testing.assert_array_equal(
        small, lgh.render_explosion(vdb, **dict(SETTINGS, camera=FRONT, width=20, height=12)))
    # The prepared camera again, after the others: the same bits.
    np.testing.assert_array_equal(frame.render(),
                                  lgh.render_explosion(vdb, camera=FRONT, **SETTINGS))


def test_bad_arguments_are_value_errors(tmp_path):
    vdb = fire_frame(56)
    with pytest.raises(ValueError, match="--frames: a prepared frame is one file"):
        lgh.FrameRender(vdb, frames="55..56")
    with pytest.raises(ValueError, match="pathtrace"):
        lgh.FrameRender(vdb, backend="pathtrace")
    with pytest.raises(FileNotFoundError):
        lgh.FrameRender(tmp_path / "missing.vdb")
    frame = lgh.FrameRender(vdb, **SETTINGS)
    with pytest.raises(ValueError, match="give camera too"):
        frame.render(width=10)
    with pytest.raises(ValueError, match="give camera too"):
        frame.render(camera_up=(0, 0, 1))
    with pytest.raises(ValueError, match="--camera"):
        frame.render((0, 0, 5))
    with pytest.raises(ValueError, match="not camera_roll"):
        frame.render(FRONT, camera_roll=30)
    with pytest.raises(ValueError, match="eye is at the target"):
        frame.render((0, 0, 0, 0, 0, 0))
