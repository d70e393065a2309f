"""``lgh.render_explosion`` against ``lgh explosion`` on the same cache and settings: wall-clock
seconds of each, the best of ``--runs`` (the command's include its start and its EXR and PNG;
Python's include turning the image into an array). Both run lgh-cli's code on every core.

    python lgh-py/bench/explosion_vs_cli.py [--vdb FRAME.vdb] [--width 640] [--height 360] [--runs 3]

Prints one JSON object; ``ratio`` is Python's seconds over the command's.
"""
import argparse
import json
import pathlib
import subprocess
import tempfile
import time

import lgh

ROOT = pathlib.Path(__file__).resolve().parents[2]
FIRE = ROOT.parent / "shared/data/volumes/blender_fire_pesichra/data/fluid_data_0056.vdb"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--vdb", default=str(FIRE))
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=360)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--lgh", default=str(ROOT / "target" / "release" / "lgh"))
    a = ap.parse_args()
    python_s, cli_s = [], []
    with tempfile.TemporaryDirectory() as d:
        for _ in range(a.runs):
            t = time.perf_counter()
            lgh.render_explosion(a.vdb, width=a.width, height=a.height)
            python_s.append(time.perf_counter() - t)
            t = time.perf_counter()
            subprocess.run([a.lgh, "explosion", "--vdb", a.vdb, "--out", f"{d}/o.exr", "--width",
                            str(a.width), "--height", str(a.height), "--quiet"], check=True,
                           capture_output=True)
            cli_s.append(time.perf_counter() - t)
    print(json.dumps({"vdb": a.vdb, "width": a.width, "height": a.height, "runs": a.runs,
                      "python_s": min(python_s), "cli_s": min(cli_s),
                      "ratio": min(python_s) / min(cli_s)}, indent=1))


if __name__ == "__main__":
    main()
