"""The fixtures of the add-on's tests: the engine registered, the fireball written once."""
import pytest

from scenes import bpy, missing, write_fireball


@pytest.fixture(scope="session", autouse=True)
def engine():
    if bpy is None:
        missing("bpy", "pip install bpy==5.2.3 under Python 3.13")
    import lgh_blender

    lgh_blender.register()
    yield
    lgh_blender.unregister()


@pytest.fixture(scope="session")
def fireball(tmp_path_factory):
    return write_fireball(tmp_path_factory.mktemp("fireball"))


_status = {}


def pytest_sessionfinish(session, exitstatus):
    _status["exit"] = int(exitstatus)


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config):
    """Leaves without Python's teardown, with pytest's own status: PyPI's bpy 5.2.3 ships a
    broken Mantaflow that crashes the interpreter's exit once a fluid domain was evaluated
    (``test_domain.py``), after every test has passed or failed and been reported."""
    import os
    import sys

    if "exit" in _status:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(_status["exit"])
