"""Packs the add-on as a Blender 4.2+ extension: ``lgh_blender/`` with the ``lgh`` wheel (built
from ``lgh-py`` by pip and maturin) bundled, its manifest's ``wheels`` naming it. Install the
zip with Blender's *Preferences > Get Extensions > Install from Disk*, or
``blender --command extension install-file -r user_default ZIP``.

    python blender/pack.py [--out DIR] [--wheel WHEEL]   # writes DIR/lgh-VERSION-linux-x64.zip

``--wheel`` packs a wheel already built instead of building one (pip's ``wheel ./lgh-py``).
"""
import argparse
import pathlib
import re
import subprocess
import sys
import tempfile
import zipfile

HERE = pathlib.Path(__file__).resolve().parent
ADDON = HERE / "lgh_blender"
ROOT = HERE.parent


def build_wheel(into):
    """Builds lgh-py's wheel into the folder ``into``: its path."""
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(into),
                    str(ROOT / "lgh-py")], check=True)
    wheels = sorted(pathlib.Path(into).glob("lgh-*.whl"))
    if len(wheels) != 1:
        sys.exit(f"pack.py: expected one lgh wheel in {into}, found {wheels}")
    return wheels[0]


def manifest_with(wheel_name):
    """The manifest's text with ``wheels`` naming ``wheels/WHEEL``."""
    text = (ADDON / "blender_manifest.toml").read_text()
    text, n = re.subn(r"^wheels = \[\]$", f'wheels = ["./wheels/{wheel_name}"]', text,
                      flags=re.M)
    if n != 1:
        sys.exit("pack.py: blender_manifest.toml has no `wheels = []` line to fill")
    return text


def pack(out_dir, wheel):
    """The extension's zip in ``out_dir``: the add-on's files, the manifest naming ``wheel``,
    and the wheel under ``wheels/``."""
    version = re.search(r'^version = "(.*)"$', (ADDON / "blender_manifest.toml").read_text(),
                        re.M).group(1)
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    out = out_dir / f"lgh-{version}-linux-x64.zip"
    partial = out.with_suffix(".zip.part")
    try:
        with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as z:
            # The add-on's Python files and its manifest: nothing else that lies in the folder.
            for f in sorted(ADDON.glob("*.py")):
                z.write(f, f.name)
            z.writestr("blender_manifest.toml", manifest_with(wheel.name))
            z.write(wheel, f"wheels/{wheel.name}")
        partial.replace(out)  # whole or not at all
    finally:
        partial.unlink(missing_ok=True)
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", default=str(ROOT / "target" / "blender"))
    p.add_argument("--wheel", help="a built lgh wheel to pack instead of building one")
    a = p.parse_args()
    if a.wheel:
        print(pack(a.out, pathlib.Path(a.wheel)))
        return
    with tempfile.TemporaryDirectory() as d:
        print(pack(a.out, build_wheel(d)))


if __name__ == "__main__":
    main()
