#!/usr/bin/env python3
"""Statistics of every grid of an OpenVDB file from the official library, as JSON.

Used by lgh's tests as the oracle for its own VDB reader. Needs Debian's python3-openvdb
(module pyopenvdb) and libopenvdb-tools (vdb_print): grids whose value type the Python binding
cannot load (int32, …) are described from `vdb_print -l` instead, without a sum.

    /usr/bin/python3 vdb_stats.py FILE.vdb
"""
import json
import math
import re
import subprocess
import sys


def vdb_print(path):
    """Per grid, what `vdb_print -l` says: name, type, active voxels, bbox, min, max."""
    out = subprocess.run(["vdb_print", "-l", path], check=True, capture_output=True, text=True).stdout
    grids = []
    for block in out.split("\nName: ")[1:]:
        g = {"name": block.splitlines()[0].strip()}
        m = re.search(r"Type: Tree_(\w+?)_5_4_3", block)
        g["value_type"] = m.group(1) if m else None
        m = re.search(r"Number of active voxels:\s+([\d,]+)", block)
        g["active_voxels"] = int(m.group(1).replace(",", "")) if m else 0
        m = re.search(r"Bounding box of active voxels: \[(-?\d+), (-?\d+), (-?\d+)\] -> \[(-?\d+), (-?\d+), (-?\d+)\]", block)
        if m:
            v = [int(x) for x in m.groups()]
            g["bbox_min"], g["bbox_max"] = v[:3], v[3:]
        for key in ("Min", "Max"):
            m = re.search(key + r" value: (-?[\d.e+-]+|-?inf|nan)\s*$", block, re.MULTILINE)
            if m:  # scalar grids only; vector grids print a vector here
                g[key.lower()] = float(m.group(1))
        grids.append(g)
    return grids


def main(path):
    import pyopenvdb as vdb

    result = []
    for g in vdb_print(path):
        entry = dict(g)
        if g["value_type"] in ("float", "vec3s"):
            grid = vdb.read(path, g["name"])
            total = 0.0
            lo, hi = math.inf, -math.inf
            for item in grid.citerOnValues():
                v = item.value
                if not isinstance(v, float):
                    v = math.sqrt(sum(float(c) * float(c) for c in v))
                total += v * item.count
                lo, hi = min(lo, v), max(hi, v)
            entry["sum"] = total
            entry["min"], entry["max"] = lo, hi
            entry["active_voxels"] = grid.activeVoxelCount()
            (a, b) = grid.evalActiveVoxelBoundingBox()
            entry["bbox_min"], entry["bbox_max"] = list(a), list(b)
            entry["voxel_size"] = list(grid.transform.voxelSize())
        result.append(entry)
    def finite(v):
        # JSON has no infinities: write non-finite numbers as strings.
        if isinstance(v, float) and not math.isfinite(v):
            return str(v)
        return v

    json.dump({"grids": [{k: finite(v) for k, v in g.items()} for g in result]}, sys.stdout)


if __name__ == "__main__":
    main(sys.argv[1])
