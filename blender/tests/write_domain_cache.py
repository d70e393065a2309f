#!/usr/bin/python3
"""A gas domain's cache as Mantaflow writes one, for the add-on's domain tests (bpy 5.2.3 cannot
bake): ``CACHE/data/fluid_data_0001.vdb`` with the grids ``density``, ``flame`` and
``temperature`` (Mantaflow's heat) of lgh's procedural fireball (``lgh.write_procedural``'s raw
grids at ``PREFIX``), voxel ``i`` at ``i × VOXEL`` (Mantaflow's files have no translation); and
``CACHE/made.vdb``, a Volume object's file of the same density and of the temperature Cycles
makes of a domain's flame: ``IGNITION + flame × (MAX − IGNITION)`` where the flame exceeds
0.01, else 0.

    /usr/bin/python3 blender/tests/write_domain_cache.py PREFIX CACHE VOXEL IGNITION MAX

Needs Debian's python3-openvdb (module pyopenvdb) and numpy.
"""
import json
import pathlib
import sys

import numpy as np
import pyopenvdb as vdb


def grid(name, values, voxel):
    g = vdb.FloatGrid()
    g.copyFromArray(np.ascontiguousarray(values, dtype=np.float32), ijk=(0, 0, 0), tolerance=0.0)
    g.name = name
    g.transform = vdb.createLinearTransform(voxel)
    g.gridClass = vdb.GridClass.FOG_VOLUME
    return g


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    prefix, cache = sys.argv[1], pathlib.Path(sys.argv[2])
    voxel, ignition, top = (float(v) for v in sys.argv[3:6])
    meta = json.load(open(prefix + ".json"))
    nx, ny, nz = meta["dims"]

    def raw(name):
        # [i][j][k] = the value at x_i, y_j, z_k (the file is x fastest).
        return np.fromfile(f"{prefix}.{name}.f32", dtype="<f4").reshape(nz, ny, nx) \
            .transpose(2, 1, 0)

    density, kelvin = raw("density"), raw("temperature")
    flame = np.clip(kelvin / kelvin.max(), 0.0, 1.0)
    made = np.where(flame > 0.01, ignition + flame * (top - ignition), 0.0)
    (cache / "data").mkdir(parents=True, exist_ok=True)
    vdb.write(str(cache / "data" / "fluid_data_0001.vdb"),
              grids=[grid("density", density, voxel), grid("flame", flame, voxel),
                     grid("temperature", kelvin / 1000.0, voxel)])
    vdb.write(str(cache / "made.vdb"),
              grids=[grid("density", density, voxel), grid("temperature", made, voxel)])


if __name__ == "__main__":
    main()
