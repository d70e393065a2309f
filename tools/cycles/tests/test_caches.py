"""caches.py's `Truth` against simulated renders whose truth, bias and noise are known.

A Cycles render of `n` samples is modelled as its converged image plus independent Gaussian
noise of relative variance `a / n` a pixel; at Blender's default step its converged image is the
truth times a smooth pattern (the step's bias). Each estimate is checked against the value the
simulation was made with, to a tolerance a few times its statistical spread over 16,384 pixels
(the default step's bias, about 1.7%, is estimated beside references 1.1% and 1.2% noisy:
to about 2%). Needs numpy and OpenEXR (caches.py
imports compare.py, which reads EXR files); lgh-py's `[test]` extra brings both.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import caches  # noqa: E402

PIXELS = (128, 128)
A = 1.0  # Cycles' noise a sample at the default step (relative variance a pixel)
A_FINE = 1.25  # the same at the finer step


def rel(img, ref):
    """Relative RMSE (root mean squared difference over the reference's mean), and the means'
    ratio: `lgh compare`'s two numbers, on one channel."""
    return float(np.sqrt(np.mean((img - ref) ** 2)) / np.mean(ref)), float(img.mean() / ref.mean())


def scene(seed=1):
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0 : PIXELS[0], 0 : PIXELS[1]] / PIXELS[0]
    truth = 1.0 + 0.5 * np.sin(6 * x) * np.cos(4 * y) + 0.2 * rng.random(PIXELS)
    biased = truth * (1.0 + 0.02 * np.cos(9 * x + 3 * y) + 0.009)
    return rng, truth, biased


def render(rng, converged, a, n):
    return converged + rng.normal(0.0, math.sqrt(a / n) * converged.mean(), converged.shape)


def truth_of(rng, truth, biased, n_ref=8192, n_seed=4096, seeds=2, cpu_fine=0.03):
    """caches.Truth as measure() builds it: the default step's reference, the finer step's
    seeds, their spread and costs, the references' error."""
    ref = render(rng, biased, A, n_ref)
    runs = [render(rng, truth, A_FINE, n_seed) for _ in range(seeds)]
    fine = sum(runs) / seeds
    spread = [rel(r, (sum(runs) - r) / (seeds - 1))[0] for r in runs]
    cost = [{"cpu_s": 1.0 + cpu_fine * n_seed, "spp": n_seed}] * seeds
    e, mean = rel(ref, fine)
    # One channel: compare.rel_rmse's channels are that channel's thrice.
    between = (e, mean, {"mean_ratio_rgb": [mean] * 3})
    t = caches.Truth("ref.exr", n_ref, A, (1.0, 0.01), ("fine.exr", n_seed * seeds, spread, cost),
                     0.25, between)
    return t, fine


def close(value, expected, tolerance):
    assert abs(value / expected - 1.0) < tolerance, f"{value} against {expected}"


def test_the_default_steps_bias_and_the_finer_references_noise_are_recovered():
    rng, truth, biased = scene()
    t, fine = truth_of(rng, truth, biased)
    close(t.bias, rel(biased, truth)[0], 0.05)
    close(t.fine["reference_noise"], math.sqrt(A_FINE / 8192), 0.05)
    close(t.fine["cycles_noise_per_spp"], A_FINE, 0.05)
    close(t.fine["default_step_mean_ratio"], biased.mean() / truth.mean(), 0.002)
    assert t.image == "fine.exr" and t.cpu_s(0.25, 100) == 1.0 + 0.03 * 100


def test_an_error_is_measured_against_the_truth_and_costed_at_each_step():
    rng, truth, biased = scene(2)
    t, fine = truth_of(rng, truth, biased)
    # A render whose error against the truth is known: lgh's, say, 5% off in a pattern.
    lgh = truth * (1.0 + 0.05 * np.sin(20 * np.arange(PIXELS[1]) / PIXELS[1]))
    e_truth, cycles = t.equal_error(rel(lgh, fine)[0])
    close(e_truth, rel(lgh, truth)[0], 0.05)
    # Cycles at the default step with 300 samples, and at the finer step with 600: their errors
    # against the finer reference give back those sample counts (to 10%: a count is the noise
    # over a difference of squared errors, each known to about 2%).
    for rate, converged, a, n in ((1.0, biased, A, 300), (0.25, truth, A_FINE, 600)):
        e, _ = t.equal_error(rel(render(rng, converged, a, n), fine)[0])
        way = [w for w in t.ways(e) if w["step_rate"] == rate][0]
        close(way["spp"], n, 0.1)
    assert cycles == min(t.ways(e_truth), key=lambda w: w["cpu_s"])


def test_below_the_default_steps_bias_only_the_finer_step_reaches_an_error():
    rng, truth, biased = scene(3)
    t, fine = truth_of(rng, truth, biased)
    e_truth, cycles = t.equal_error(math.sqrt((0.5 * t.bias) ** 2 + t.var))
    close(e_truth, 0.5 * t.bias, 1e-9)
    assert [w["step_rate"] for w in t.ways(e_truth)] == [0.25]
    assert cycles["step_rate"] == 0.25
    close(cycles["spp"], A_FINE / (0.5 * t.bias) ** 2, 0.06)


def test_without_a_finer_step_the_truth_is_the_default_steps_reference():
    t = caches.Truth("ref.exr", 8192, A, (1.0, 0.01))
    e_truth, cycles = t.equal_error(0.03)
    close(e_truth, math.sqrt(0.03 ** 2 - A / 8192), 1e-12)
    close(cycles["spp"], A / e_truth ** 2, 1e-12)
    assert cycles["step_rate"] == 1.0 and t.image == "ref.exr" and t.fine is None
    # Within the reference's noise the reference cannot tell.
    assert t.equal_error(0.5 * math.sqrt(A / 8192)) == (0.0, None)
