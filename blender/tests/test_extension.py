"""The add-on packed as a Blender 4.2+ extension (``blender/pack.py``) installs into Blender
(PyPI's ``bpy`` 5.2.3) as a user would install it — *Install from Disk*, here the operator
behind it — with the bundled ``lgh`` wheel installed into the extension's site-packages, and
registers the engine ``LGH``. Blender runs in a child process whose home is a temporary folder,
so nothing of the machine's Blender configuration is read or changed.

The wheel is ``$LGH_WHEEL`` (``.ci/run`` builds it once, for this and for the venv), else the
newest in ``lgh-py/target/wheels`` or ``target/wheels``: without one, or without bpy, the test
is skipped with a message, a failure where ``LGH_REQUIRE_ALL`` is set.
"""
import os
import pathlib
import subprocess
import sys
import tomllib
import zipfile

import pytest

from scenes import ROOT, missing

import pack  # noqa: E402  (blender/, on the path by scenes)


def wheel():
    named = os.environ.get("LGH_WHEEL")
    if named:
        return pathlib.Path(named)
    found = [w for d in (ROOT / "lgh-py" / "target" / "wheels", ROOT / "target" / "wheels")
             for w in d.glob("lgh-*.whl")]
    if not found:
        missing("lgh wheel", "pip wheel --no-deps -w target/wheels ./lgh-py, or LGH_WHEEL")
    return max(found, key=lambda p: p.stat().st_mtime)


INSTALL = """
import os, sys, bpy
result = bpy.ops.extensions.package_install_files(
    filepath=sys.argv[1], repo="user_default", enable_on_install=True)
assert result == {"FINISHED"}, result
bpy.context.scene.render.engine = "LGH"
site = bpy.utils.user_resource("EXTENSIONS", path=".local")
installed = [r for r, _, files in os.walk(site) if "_lgh.abi3.so" in files]
print("ENGINE", bpy.context.scene.render.engine)
print("WHEEL", installed)
"""


def test_the_extension_installs_with_its_wheel_and_registers_the_engine(tmp_path):
    try:
        import bpy  # noqa: F401
    except ImportError:
        missing("bpy", "pip install bpy==5.2.3 under Python 3.13")
    zip_path = pack.pack(tmp_path, wheel())
    with zipfile.ZipFile(zip_path) as z:
        names = set(z.namelist())
        manifest = tomllib.loads(z.read("blender_manifest.toml").decode())
    assert {"__init__.py", "engine.py", "scene.py", "camera.py", "preview.py"} <= names
    assert manifest["id"] == "lgh" and manifest["type"] == "add-on"
    assert manifest["blender_version_min"] == "4.2.0"
    [bundled] = manifest["wheels"]
    assert bundled.removeprefix("./") in names
    assert not list(tmp_path.glob("*.part")), "a partial zip was left"

    home = tmp_path / "home"
    home.mkdir()
    env = dict(os.environ, HOME=str(home))
    env.pop("BLENDER_USER_RESOURCES", None)
    out = subprocess.run([sys.executable, "-c", INSTALL, str(zip_path)], env=env,
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "ENGINE LGH" in out.stdout, out.stdout + out.stderr
    wheel_line = next(line for line in out.stdout.splitlines() if line.startswith("WHEEL"))
    assert str(home) in wheel_line and "site-packages/lgh" in wheel_line, wheel_line
