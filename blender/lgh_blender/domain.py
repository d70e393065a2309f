"""A Mantaflow smoke/fire domain as LGH renders it: the OpenVDB file its cache holds for the
frame, the attributes its shader can read from that file, and where the file's voxels sit.

Cycles does not read a domain's cache file: it reads the fluid's grids in memory
(``BlenderSmokeLoader``, through ``rna_FluidModifier_*_grid_get``) as a dense texture over the
domain's box. The same numbers are in the file Mantaflow writes for each frame,
``CACHE/data/fluid_data_NNNN.vdb`` (``CACHE/noise/fluid_noise_NNNN.vdb`` with Noise on):

- ``density`` is the file's ``density`` (``density_noise``), ``flame`` its ``flame``
  (``flame_noise``), ``heat`` its ``temperature`` (not with Noise: Cycles' heat is of the base
  resolution and is not read then);
- ``temperature`` is *made* from the flame: ``ignition + flame × (max − ignition)`` where the
  flame exceeds 0.01, else 0 (``rna_FluidModifier_temperature_grid_get``; ignition and max are
  the domain's Fire settings), which ``lgh explosion --flame-temperature IGNITION,MAX`` makes
  of the flame grid.

Placement. Blender sizes a domain's cells from its mesh's box and the object's own scale
(``BKE_fluid``'s ``fluid_modifier_init``): the world's longest side gets Resolution Divisions
cells, each other side ``max(round(side × divisions / longest), 4)``. Cycles draws the dense grid
over the mesh's box, voxel ``i`` centred at ``box_min + (i + 1/2) × cell`` in the object's space
(the file puts voxel ``i`` at ``i × voxel_size``; an adaptive domain's frame starts at its
box's corner, ``res_min`` in ``CACHE/config/config_NNNN.uni``, in cells of the base grid — times
the Noise scale for the noise grids). Measured on a domain baked by
Blender 3.4.1: its Cycles image and that of a Volume object holding the made temperature placed
so are the same image to 0.13% (Cycles' noise).
"""
import gzip
import os

import bpy
from mathutils import Matrix, Vector

from .errors import Refused

def fluid(obj):
    """The Fluid modifier of a mesh object, or ``None``."""
    return next((m for m in obj.modifiers if m.type == "FLUID"), None)


def gas_domain(obj, final=True):
    """The domain settings of a mesh object that is a gas (smoke, fire) domain whose Fluid
    modifier is on for a final render (``final``) or for the viewport, else ``None``."""
    m = fluid(obj)
    if m is None or m.fluid_type != "DOMAIN" or m.domain_settings.domain_type != "GAS":
        return None
    return m.domain_settings if (m.show_render if final else m.show_viewport) else None


class Source:
    """The file a volume renders from: ``path``; ``attributes``, for each attribute its shader
    may read, ``(grid, settings)`` — the file's grid and the settings that read it as that
    attribute; ``matrix``, from the file's space to the world; ``exact``, whether that matrix
    must be a similarity to rounding (else to ``CELL_TOLERANCE``, named); ``settings``, what the
    file's kind asks of every render of it."""

    def __init__(self, name, path, attributes, matrix, exact, settings):
        self.name, self.path, self.attributes = name, path, attributes
        self.matrix, self.exact, self.settings = matrix, exact, settings

    def temperature(self, attribute, material):
        """``(grid, settings)`` of ``attribute`` read as the temperature, else
        :class:`Refused` (naming the shader's ``material``)."""
        if attribute not in self.attributes:
            raise Refused(f"{self.name} has no attribute '{attribute}', which material "
                          f"'{material}' reads (it has: {', '.join(sorted(self.attributes))})")
        return self.attributes[attribute]

    def grid(self, attribute, material, socket):
        """The grid of ``attribute``, read as it is by the shader's input ``socket``; an
        attribute LGH makes from another grid is refused there."""
        grid, settings = self.temperature(attribute, material)
        if settings:
            raise Refused(f"material '{material}': the {socket} reads '{attribute}', which "
                          f"{self.name} makes from its grid '{grid}': LGH makes it for the "
                          "Temperature Attribute only")
        return grid


def cells(obj, ds):
    """``(box_min, cell)`` of a domain in its object's space: the mesh's box corner and the size
    of one voxel of the cache's grid along each axis (``fluid_modifier_init``'s arithmetic)."""
    mesh = obj.original.data
    if len(mesh.vertices) == 0:
        raise Refused(f"fluid domain '{obj.name}' has no vertices: its box is empty")
    lo = Vector([min(v.co[k] for v in mesh.vertices) for k in range(3)])
    hi = Vector([max(v.co[k] for v in mesh.vertices) for k in range(3)])
    extent = hi - lo
    size = [abs(extent[k] * obj.scale[k]) for k in range(3)]
    longest = max(range(3), key=lambda k: size[k])
    if size[longest] <= 0.0:
        raise Refused(f"fluid domain '{obj.name}' has a flat box")
    divisions = ds.resolution_max
    res = [divisions if k == longest else max(int(size[k] * divisions / size[longest] + 0.5), 4)
           for k in range(3)]
    upres = ds.noise_scale if ds.use_noise else 1
    return lo, Vector([extent[k] / (res[k] * upres) for k in range(3)])


def cache_file(obj, ds, frame):
    """The cache's OpenVDB file of scene frame ``frame`` (refused when there is none)."""
    name = f"fluid domain '{obj.name}'"
    if ds.cache_data_format != "OPENVDB":
        raise Refused(f"{name}: its cache is in the {ds.cache_data_format.title()} format: LGH "
                      "reads OpenVDB (Physics > Fluid > Cache > Format Volumes: OpenVDB, then "
                      "bake again)")
    number = frame - getattr(ds, "cache_frame_offset", 0)
    directory = bpy.path.abspath(ds.cache_directory, library=obj.library)
    kind = ("noise", "fluid_noise") if ds.use_noise else ("data", "fluid_data")
    path = os.path.join(directory, kind[0], f"{kind[1]}_{number:04d}.vdb")
    if not os.path.isfile(path):
        raise Refused(f"{name}: no cache for frame {frame} ({path}): bake it (Physics > Fluid > "
                      "Cache > Bake Data" + (" and Bake Noise" if ds.use_noise else "") +
                      ", Format Volumes OpenVDB)")
    return path


def frame_offset(obj, ds, path):
    """Where the frame of ``path`` starts in the domain's base grid (``res_min``, read from its
    ``config/config_NNNN.uni``: gzip of a 204-byte record ending in ``C01``, three int32 at byte
    160); ``(0, 0, 0)`` without the file (a domain that is not adaptive)."""
    name = os.path.basename(path)
    config = os.path.join(os.path.dirname(os.path.dirname(path)), "config",
                          "config_" + name.rsplit("_", 1)[1].split(".")[0] + ".uni")
    if not ds.use_adaptive_domain and not os.path.isfile(config):
        return (0, 0, 0)
    try:
        with gzip.open(config) as f:
            raw = f.read()
    except OSError as e:
        raise Refused(f"fluid domain '{obj.name}': {config}: {e} (an adaptive domain's frame "
                      "offset)") from None
    if len(raw) != 204 or raw[200:204] != b"C01\0":
        raise Refused(f"fluid domain '{obj.name}': {config} is not a Blender fluid config")
    return tuple(int.from_bytes(raw[160 + 4 * k:164 + 4 * k], "little", signed=True)
                 for k in range(3))


def source(obj, ds, frame, inspect):
    """The :class:`Source` of gas domain ``obj`` (settings ``ds``) at scene frame ``frame``;
    ``inspect`` reads a file's grids (``lgh.inspect``)."""
    path = cache_file(obj, ds, frame)
    grids = {g["name"]: g for g in inspect(path)["grids"]}
    suffix = "_noise" if ds.use_noise else ""
    density = grids.get("density" + suffix)
    if density is None:
        raise Refused(f"fluid domain '{obj.name}': {path} has no grid 'density{suffix}' (it "
                      f"has: {', '.join(sorted(grids))})")
    attributes = {"density": ("density" + suffix, {})}
    if "flame" + suffix in grids:
        attributes["flame"] = ("flame" + suffix, {})
        attributes["temperature"] = ("flame" + suffix, {
            "flame_temperature": (ds.flame_ignition, ds.flame_max_temp)})
    if not ds.use_noise and "temperature" in grids:
        attributes["heat"] = ("temperature", {})
    lo, cell = cells(obj, ds)
    voxel = density["voxel_size"][0]
    upres = ds.noise_scale if ds.use_noise else 1
    start = [c * upres + 0.5 for c in frame_offset(obj, ds, path)]
    # File position p is voxel p / voxel of the frame; its centre in the object:
    # lo + (start + p / voxel) cell, start the frame's corner in cells plus a half.
    corner = lo + Vector([start[k] * cell[k] for k in range(3)])
    place = Matrix.Translation(corner) @ Matrix.Diagonal(
        [cell[k] / voxel for k in range(3)] + [1.0])
    return Source(f"fluid domain '{obj.name}'", path, attributes, obj.matrix_world @ place,
                  False, {"no_domain_offset": True})
