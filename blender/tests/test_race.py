"""``blender/race.py``'s ``--sampling``: the engine's Sampling settings it races, and a bad entry
refused before any render."""
import argparse
import importlib.util
import pathlib

import pytest

RACE = pathlib.Path(__file__).resolve().parents[1] / "race.py"


def race():
    spec = importlib.util.spec_from_file_location("race", RACE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_sampling_entries_are_keyed_and_fixed_or_auto():
    assert race().sampling("auto,4/2,auto/1") == [
        ("", {"pixel_samples": None, "scatter_spacing": None}),
        ("_p4s2", {"pixel_samples": 4, "scatter_spacing": 2}),
        ("_pautos1", {"pixel_samples": None, "scatter_spacing": 1}),
    ]


@pytest.mark.parametrize("bad", ["4", "9/2", "0/1", "4/2/1", "four/2", ""])
def test_a_bad_sampling_entry_is_refused(bad):
    with pytest.raises(argparse.ArgumentTypeError, match="auto or PIXELS/SPACING"):
        race().sampling(bad)
