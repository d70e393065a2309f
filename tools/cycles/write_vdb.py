#!/usr/bin/python3
"""Turns `export_grids`' raw grids into an OpenVDB file that Blender Cycles and `lgh explosion`
both read: grids `density` and `temperature` (kelvin), the world turned from the procedural
volumes' +Y up to Blender's +Z up, (x, y, z) -> (x, -z, y), so the box stays [-1, 1]^3.

Voxel i's value sits at the transform of i, OpenVDB's convention (and lgh's, and Cycles 5.x's;
Cycles 3.x draws voxel i over the cell [i, i+1] instead: `render_cycles.py --shift-half-voxel`).

    /usr/bin/python3 tools/cycles/write_vdb.py OUT_PREFIX   # reads OUT_PREFIX.json, writes OUT_PREFIX.vdb

Needs Debian's python3-openvdb (module pyopenvdb) and numpy.
"""
import json
import sys

import numpy as np
import pyopenvdb as vdb


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    prefix = sys.argv[1]
    meta = json.load(open(prefix + ".json"))
    nx, ny, nz = meta["dims"]
    h = float(meta["voxel_size"])
    x0, y0, z0 = meta["origin"]
    if meta.get("up", "y") != "y":
        sys.exit("write_vdb.py: expected a +Y-up volume")
    grids = []
    for name in meta["grids"]:
        raw = np.fromfile(f"{prefix}.{name}.f32", dtype="<f4")
        if raw.size != nx * ny * nz:
            sys.exit(f"{prefix}.{name}.f32: {raw.size} values, expected {nx * ny * nz}")
        # [i][j][k] = value at x_i, y_j, z_k (the file is x fastest).
        xyz = raw.reshape(nz, ny, nx).transpose(2, 1, 0)
        # Blender's index (I, J, K) holds lgh's (I, K, nz - 1 - J): X = x, Y = -z, Z = y.
        zup = np.ascontiguousarray(xyz.transpose(0, 2, 1)[:, ::-1, :])
        g = vdb.FloatGrid()
        g.copyFromArray(zup, ijk=(0, 0, 0), tolerance=0.0)
        g.name = name
        # OpenVDB's matrices act on row vectors: the translation is the last row.
        g.transform = vdb.createLinearTransform(
            [[h, 0, 0, 0], [0, h, 0, 0], [0, 0, h, 0], [x0, -z0 - h * (nz - 1), y0, 1]]
        )
        g.gridClass = vdb.GridClass.FOG_VOLUME
        grids.append(g)
    vdb.write(prefix + ".vdb", grids=grids)
    print(f"wrote {prefix}.vdb: {[g.name for g in grids]}, {nx}x{nz}x{ny} voxels of {h}")


if __name__ == "__main__":
    main()
