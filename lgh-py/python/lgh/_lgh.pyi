"""Type stubs of the native module ``lgh._lgh`` (re-exported by ``lgh``)."""
import os
from typing import Callable, Literal, Optional, Sequence, TypedDict

import numpy as np
import numpy.typing as npt

__version__: str

class RenderError(Exception):
    """An error of the library that is not a bad argument (``ValueError``) or a missing file
    (``FileNotFoundError``); its message is the library's."""

def render_explosion(
    vdb: str | os.PathLike[str], **settings: object
) -> npt.NDArray[np.float32] | dict[int, npt.NDArray[np.float32]]:
    """``lgh explosion --vdb VDB`` with ``settings`` (``name=value`` is ``--name value``),
    rendered into memory: an (h, w, 3) float32 array, or with ``frames="A..B"`` a dict of them
    by frame number."""

def explosion_settings() -> list[tuple[str, bool, Optional[str], list[str], str]]:
    """Every setting ``render_explosion`` takes: ``(name, takes_value, default, choices, help)``."""

class Gathered(TypedDict):
    """The lights one point sees, one row a light (``Hierarchy.gather``)."""

    position: npt.NDArray[np.float32]  # (k, 3)
    intensity: npt.NDArray[np.float32]  # (k, 3), the blending weight applied
    variance: npt.NDArray[np.float32]  # (k, 3)
    weight: npt.NDArray[np.float32]  # (k,)
    distance: npt.NDArray[np.float32]  # (k,)
    size: npt.NDArray[np.float32]  # (k,)
    level: npt.NDArray[np.uint8]  # (k,)
    index: npt.NDArray[np.uint32]  # (k,)

class Hierarchy:
    """The Lighting Grid Hierarchy (Yuksel & Yuksel 2017) over point lights."""

    def __init__(
        self,
        positions: npt.ArrayLike,
        intensities: npt.ArrayLike,
        *,
        alpha: float = 2.0,
        h1: Optional[float] = None,
        origin: Optional[npt.ArrayLike] = None,
        max_level: Optional[int] = None,
        prune_below: float = 0.0,
    ) -> None: ...
    def probe(
        self,
        points: npt.ArrayLike,
        *,
        progress: Optional[Callable[[int, int], object]] = None,
    ) -> npt.NDArray[np.float32]:
        """The unshadowed light-probe value at each point: an (n, 3) float32 array."""
    def gather(self, point: npt.ArrayLike) -> Gathered:
        """The lights ``point`` sees at every level, with their blending weights."""
    def update_intensities(self, intensities: npt.ArrayLike) -> None:
        """New intensities at the same positions, as many as the lights."""
    def rebuild(self, positions: npt.ArrayLike, intensities: npt.ArrayLike) -> None:
        """Rebuilds over new lights (any count) with the same settings."""
    alpha: float
    coarse_spread: Literal["centre", "averaged"]
    @property
    def h1(self) -> float: ...
    @property
    def h0(self) -> float: ...
    @property
    def max_level(self) -> int: ...
    @property
    def origin(self) -> tuple[float, float, float]: ...
    def __len__(self) -> int: ...

def write_procedural(
    kind: Literal["fireball", "explosion", "ball"],
    resolution: int,
    time: float,
    prefix: str | os.PathLike[str],
) -> None:
    """lgh's procedural volume as raw grids ``PREFIX.json``, ``PREFIX.density.f32``,
    ``PREFIX.temperature.f32`` (``tools/cycles/write_vdb.py`` makes an OpenVDB file of them)."""

def inspect(vdb: str | os.PathLike[str]) -> dict[str, list[dict[str, object]]]:
    """The grids of an OpenVDB file as ``lgh inspect --json`` prints them: ``{"grids": [{"name",
    "value_type", "voxel_size", "active_voxels", "bbox_min", "bbox_max", "min", "max", "sum"},
    ...]}``."""

def render_gi(
    obj: str | os.PathLike[str], **settings: object
) -> npt.NDArray[np.float32]:
    """``lgh gi --obj OBJ`` with ``settings``, rendered into memory: an (h, w, 3) float32
    array."""

def gi_settings() -> list[tuple[str, bool, str | None, list[str], str]]:
    """Every setting of ``render_gi``: ``(name, takes_value, default, choices, help)``."""

class FrameRender:
    """A frame of a simulation cache made ready once (read, lights, scattering, shadows) and
    rendered from many cameras; ``settings`` as ``render_explosion``'s (one file)."""
    def __init__(
        self,
        vdb: str | os.PathLike[str],
        *,
        progress: Optional[Callable[[str, int, int], object]] = None,
        threads: Optional[int] = None,
        **settings: object,
    ) -> None: ...
    def render(
        self,
        camera: Optional[str | Sequence[float]] = None,
        *,
        width: Optional[int] = None,
        height: Optional[int] = None,
        camera_up: Optional[str | Sequence[float]] = None,
        camera_shift: Optional[str | Sequence[float]] = None,
        progress: Optional[Callable[[str, int, int], object]] = None,
    ) -> npt.NDArray[np.float32]:
        """The image of ``camera`` (none: the prepared camera): (h, w, 3) float32."""
    @property
    def size(self) -> tuple[int, int]: ...
    @property
    def lights(self) -> int: ...
