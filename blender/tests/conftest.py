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
