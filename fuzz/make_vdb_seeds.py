#!/usr/bin/python3
"""Small OpenVDB seeds for the `vdb` fuzz target, written by the official library.

    /usr/bin/python3 make_vdb_seeds.py FRAME.vdb OUT_DIR

Each seed is a crop of a real frame (the dev Blender fire in ../shared/data): a few grids of
8-24 voxels a side around the fire's hottest voxel, as float, half float and vec3s grids, plus
grids of constant tiles at every level of the 5-4-3 tree. Needs Debian's python3-openvdb.
"""
import os
import sys

import numpy as np
import pyopenvdb as vdb


def crop(grid, lo, size):
    """`grid`'s values over the box `lo`..`lo + size`, as a new grid of the same kind."""
    if isinstance(grid, vdb.Vec3SGrid):
        a = np.zeros(tuple(size) + (3,), dtype=np.float32)
        out = vdb.Vec3SGrid()
    else:
        a = np.zeros(tuple(size), dtype=np.float32)
        out = vdb.FloatGrid()
    grid.copyToArray(a, ijk=lo)
    out.copyFromArray(a, ijk=lo, tolerance=out.zeroValue)
    out.name = grid.name
    out.transform = grid.transform
    out.gridClass = grid.gridClass
    return out


def main(frame, out_dir):
    os.makedirs(out_dir, exist_ok=True)
    # Grid by grid: the binding cannot load the file's int32 `flags` grid.
    wanted = ("temperature", "density", "flame", "velocity")
    by_name = {k: vdb.read(frame, k) for k in wanted}
    meta = vdb.readMetadata(frame)
    temp = by_name["temperature"]
    # The hottest voxel: where the fire (and every interesting grid) is.
    (lo, hi) = temp.evalActiveVoxelBoundingBox()
    centre = [(a + b) // 2 for a, b in zip(lo, hi)]
    n = 0
    for size in (8, 13):
        start = [c - size // 2 for c in centre]
        for names in (["temperature"], ["density", "flame"], ["velocity"], ["density", "temperature", "flame"]):
            for half in (False, True):
                cropped = [crop(by_name[k], start, [size] * 3) for k in names]
                for g in cropped:
                    g.saveFloatAsHalf = half
                path = os.path.join(out_dir, f"crop-{size}-{'-'.join(names)}{'-half' if half else ''}.vdb")
                vdb.write(path, grids=cropped, metadata=meta)
                n += 1
    # Tiles: constant regions of 8³ (a leaf-sized tile), 128³ and 4096³ voxels.
    for edge in (8, 128, 4096):
        g = vdb.FloatGrid(background=0.0)
        g.fill((0, 0, 0), (edge - 1, edge - 1, edge - 1), 0.5, True)
        g.fill((edge, 0, 0), (edge, 0, 0), 2.0, True)  # and one voxel in a leaf
        g.name = "density"
        g.transform = temp.transform
        path = os.path.join(out_dir, f"tiles-{edge}.vdb")
        vdb.write(path, grids=[g])
        n += 1
    print(f"{n} VDB seeds in {out_dir}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
