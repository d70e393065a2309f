"""Stubs of the package ``lgh``; written by ``lgh-py/stubs.py`` from `lgh explosion`'s
and `lgh gi`'s flags: do not edit by hand."""
import os
from typing import Callable, Literal, Sequence

import numpy as np
import numpy.typing as npt

from ._lgh import FrameRender as FrameRender
from ._lgh import Hierarchy as Hierarchy
from ._lgh import RenderError as RenderError
from ._lgh import __version__ as __version__
from ._lgh import explosion_settings as explosion_settings
from ._lgh import gi_settings as gi_settings
from ._lgh import write_procedural as write_procedural

_Value = str | int | float | Sequence[str | int | float] | os.PathLike[str]

def render_explosion(
    vdb: str | os.PathLike[str],
    *,
    progress: Callable[[str, int, int], object] | None = ...,
    threads: int | None = ...,
    frames: _Value | None = ...,  # Frames to render, `A..B` inclusive (e.g. 50..56): one image each, `OUT_NNNN.exr`
    emission_grid: _Value | None = ...,  # The grid emission follows (Blender: temperature; or flame, heat) (default temperature)
    density_grid: _Value | None = ...,  # Smoke density grid (default density)
    flame_grid: _Value | None = ...,  # Grid multiplying the emission; `none` for none
    emission_model: Literal['blender', 'planck'] | None = ...,  # Emission model (default blender)
    emission_interpolation: Literal['temperature', 'attributes'] | None = ...,  # How the emission between voxel centres follows the grids: `temperature`, the emission of the interpolated temperature
    temperature_scale: _Value | None = ...,  # Kelvin per unit of the emission grid (Blender's Principled Volume temperature: 1000) (default 1000)
    flame_temperature: _Value | None = ...,  # `IGNITION,MAX`: the emission grid is a Blender fluid domain's `flame` (0..1), read as Cycles reads the domain's `temperature` attribute: `IGNITION + flam
    emission_scale: _Value | None = ...,  # Blender's blackbody intensity (model blender) or k_e (model planck) (default 1)
    min_temperature: _Value | None = ...,  # No emission at or below this temperature (kelvin): the lights are the hotter voxels [default: 0 with --emission-model blender, whose Principled Volume emit
    density_scale: _Value | None = ...,  # Extinction per unit density (Blender's Principled Volume density) (default 1)
    albedo: _Value | None = ...,  # Single-scattering albedo σ_s/σ_t (Blender's default scattering colour: 0.5) (default 0.5)
    no_domain_offset: bool | None = ...,  # Don't place frames by Blender's config/config_NNNN.uni domain offset
    backend: Literal['lgh', 'brute', 'lightcuts', 'lightcuts-deterministic', 'pathtrace'] | None = ...,  # Renderer (default lgh)
    alpha: _Value | None = ...,  # The paper's α (backend lgh) (default 2)
    prune: _Value | None = ...,  # Weak-light pruning (paper Sec. 6): the hierarchy skips, below its top level, the lights dimmer than this fraction of the frame's brightest light (their energy still
    shadows: Literal['cubemap', 'raymarch', 'raymarch-volumes', 'volumes', 'none'] | None = ...,  # Shadows of the lights: shadow rays marched to every light (with the lighting cache, the default, mar
    shadow_memory: _Value | None = ...,  # Memory the cube maps may take, in GB (maps that would need more are refused before any work) [default: 8 GiB, or 3/4 of the available memory if less]
    sampled_depths: bool | None = ...,  # Cube maps store optical depth sampled at fixed distances (`--shadow-depths`, 4 by default), as the paper does, instead of adaptive knots
    shadow_depths: _Value | None = ...,  # Cube-map texels store the least-squares fit of the optical depth at n fixed distances D/n
    shadow_knots: _Value | None = ...,  # Knots a cube-map texel stores, 2 to 16: the transmittance at K distances placed per texel where it changes (adaptive deep shadow maps; 2 bytes each, so the de
    point_shadows: bool | None = ...,  # Cube maps trace coarse lights as points through the plain density instead of as volume lights through the prefiltered density (eq. 6): the flickering variant o
    near_field: Literal['voxel', 'clamp'] | None = ...,  # The voxel lights' near field: `voxel` makes each level-0 light the uniform emitting voxel it stands for (its intensity what its cell emits, i
    coarse_spread: Literal['centre', 'averaged'] | None = ...,  # How coarse lights (levels ≥ 1) are weighted: `centre` takes eq. (3) at each light's centre as the paper prints it (up to 2% bright out
    step: _Value | None = ...,  # Step along camera rays, in voxels (smaller is more accurate and slower) (default 1)
    shadow_step: _Value | None = ...,  # Step along shadow rays, in voxels (smaller is more accurate and slower) [default: 1, or 2 for lgh demo]
    pixel_samples: _Value | None = ...,  # Camera rays per side of a pixel, 1 to 8: N×N rays through the centres of N×N sub-pixels, averaged — a one-pixel box filter (Cycles' "Box" filter, width 1), w
    emission_samples: _Value | None = ...,  # Camera rays per side of a pixel for the emission alone, 1 to 8: where more than --pixel-samples, each pixel's emission (and what the smoke absorbs of it)
    pixel_tolerance: _Value | None = ...,  # With --pixel-samples adaptive: the luminance difference between neighbouring rays that refines their pixels, as a share of the image's mean luminance (smal
    lighting_cache: Literal['none', 'coarse'] | None = ...,  # Lighting cache for the hierarchy's coarse levels: their in-scattered light computed once per frame at grid vertices over the smoke and in
    cache_spacing: _Value | None = ...,  # Distance between the lighting cache's vertices: `auto` (cells of --cache-depth optical depth across the densest smoke, 0.25 to 4 voxels) or voxels (0.25 to 1
    cache_depth: _Value | None = ...,  # With --cache-spacing auto: the optical depth across a cell of the densest smoke (the 99th percentile of its density); the interpolation's error grows with it (
    cache_level: _Value | None = ...,  # The first level of the hierarchy the lighting cache holds (finer levels are shaded at every sample), or `auto`: 0 where a camera ray's footprint at the volume'
    cache_level0: Literal['auto', 'ratio', 'light', 'far-light'] | None = ...,  # Where the lighting cache holds level 0: `ratio` caches only its shadows (the ratio of shadowed to unshadowed light at
    cache_near: _Value | None = ...,  # With level 0 cached as a ratio or far light: the reach, in voxels (at least 0.9), of its near part, summed at every sample; beyond it level 0's unshadowed (or f
    scatter_spacing: _Value | None = ...,  # With --scatter-depth and the lighting cache: scattering depths 2 and up compute their fluence on a grid this many voxels apart (1 to 8), every level cached
    scattered_light: Literal['merged', 'grid'] | None = ...,  # With --scatter-depth, the lighting cache and ray-marched shadows: how the render takes in the scattered light (default merged)
    shadow_skip: _Value | None = ...,  # Skip the lights' shadows in a frame whose smoke is so thin that skipping them adds at most this share of the emitted light to its scattered light: a bound from
    scatter_depth: _Value | None = ...,  # Depths of scattered light (paper Sec. 5): 0 is single scattering; n adds lights for light scattered 1..=n times, so paths of up to n + 1 scattering events (t
    scatter_stop: _Value | None = ...,  # Stop adding scattering depths when the next one, predicted from the last two (the light falls by a nearly steady factor a depth), would add less than this sha
    scatter_skip: _Value | None = ...,  # Skip the whole scattering pass when a sample of the smoky voxels predicts that its first depth would add less than this share of the emitted light (0: never s
    scatter_tail: Literal['dropped', 'geometric'] | None = ...,  # With a stopping share (--scatter-depth auto): the depths beyond the last, added as a geometric series of the last depth's lights by i
    scatter_shares: bool | None = ...,  # Also report each depth's share of the image (renders the emission, each depth's lights and the geometric tail's alone: n + 2 more renders, one more with a tai
    spp: _Value | None = ...,  # Paths per pixel (backend pathtrace) (default 64)
    max_scatter: _Value | None = ...,  # Scattering events per path (backend pathtrace; 1 = the marcher's single scattering) (default 1)
    width: _Value | None = ...,  # Image width in pixels (default 640)
    height: _Value | None = ...,  # Image height in pixels (default 360)
    camera: _Value | None = ...,  # Camera `EX,EY,EZ,TX,TY,TZ[,FOV]` (eye, target, vertical field of view in degrees; default: framed on the smoke of all frames, seen from the front)
    camera_up: _Value | None = ...,  # With --camera: the camera's up direction `UX,UY,UZ` (default: the world's up, --up)
    camera_shift: _Value | None = ...,  # Lens shift `SX,SY`: the image plane moved right and up by these fractions of the image's larger side, the view direction kept (Blender's camera Shift X and Y
    background: _Value | None = ...,  # The world's constant radiance `R,G,B` (linear) seen behind the smoke, through it: Blender's world colour × strength
    scene: _Value | None = ...,  # Opaque surfaces around the smoke: an OBJ scene (with its MTL; diffuse albedo, Phong's `kd`) in the cache's world units, lit by the fire through the smoke and shadowe
    up: Literal['y', 'z'] | None = ...,  # The world's up axis (Blender: z) (default z)
    allow_dark: bool | None = ...,  # Render even when no frame has a light
    quiet: bool | None = ...,  # Don't show progress
) -> npt.NDArray[np.float32] | dict[int, npt.NDArray[np.float32]]:
    """`lgh explosion --vdb VDB` with the settings given, rendered into memory."""

def render_gi(
    obj: str | os.PathLike[str],
    *,
    progress: Callable[[str, int, int], object] | None = ...,
    threads: int | None = ...,
    missing_textures: Literal['error', 'grey'] | None = ...,  # What a missing texture file does: `error` (naming it) or `grey` (its material's colour is grey, 0.5, and a warning names it) (default er
    normals: Literal['vertex', 'face'] | None = ...,  # Which normals shade a face: `vertex`, the OBJ's `vn` interpolated (the face's normal where a face names none), or `face`, every face its own nor
    light: _Value | None = ...,  # A primary light, repeatable: `point:X,Y,Z,R,G,B`, `spot:X,Y,Z,DX,DY,DZ,ANGLE,R,G,B` or `sun:DX,DY,DZ,R,G,B` (intensities in W/sr, the sun's irradiance in W/m²)
    vpls: _Value | None = ...,  # VPLs to trace (at least; whole light paths are kept) (default 100000)
    bounces: _Value | None = ...,  # Surfaces a light path may meet, each one depositing a VPL (default 3)
    seed: _Value | None = ...,  # Seed of the light paths (default 1)
    shadow_samples: _Value | None = ...,  # Shadow samples k of a coarse light (on average with `--sample-allocation adaptive` or `intensity`)
    coarse_shadows: Literal['gaussian', 'representatives'] | None = ...,  # How a coarse light's k shadow samples are placed: `representatives` (k of the VPLs it stands for, beyond the paper; `docs/gi
    sample_allocation: Literal['uniform', 'intensity', 'adaptive'] | None = ...,  # How `--coarse-shadows representatives` shares the samples among coarse lights: `adaptive`, per shading point in prop
    max_shadow_samples: _Value | None = ...,  # The most representatives one coarse light gets, 1 to 64 (`adaptive`: rounded down to a power of two; default 32; `intensity`: default 16; refused where
    no_shadows: bool | None = ...,  # No shadow rays: every VPL reaches every point it faces
    aggregation: Literal['buckets', 'isotropic'] | None = ...,  # How the hierarchy aggregates the VPLs: `isotropic`, the paper's one hierarchy of isotropic points, or `buckets`, one hierarchy per dom
    lightcuts_error: _Value | None = ...,  # Lightcuts' relative error ε (Walter et al.'s 2%), for `--backend lightcuts` and `lgh bench gi --lightcuts` (default 0.02)
    width: _Value | None = ...,  # Image width in pixels (default 640)
    height: _Value | None = ...,  # Image height in pixels (default 360)
    camera: _Value | None = ...,  # Camera `EX,EY,EZ,TX,TY,TZ[,FOV]` (default: straight along −z at the scene's box, y up, its front face filling a 40° vertical field of view)
    specular_depth: _Value | None = ...,  # The most mirrors and glass surfaces (MTL `illum` 3–9) a camera or light path follows by reflection and refraction, 0 to 32; a path's branch carrying under 1
    lobe_error: _Value | None = ...,  # Backend lgh, with the default coarse shading (`--coarse-shadows representatives`, `--sample-allocation adaptive`): at a Phong point whose lobe is too sharp for
    point_error: _Value | None = ...,  # Backend lgh, with the default coarse shading: the bound on each shading point's error (0.1 is 10% of its light)
    blend_at: Literal['representative', 'centre'] | None = ...,  # Backend lgh, with the default coarse shading: where a coarse light's blending weight B_ℓ is taken
    candidates: _Value | None = ...,  # Backend lgh, with the default coarse shading: the representatives each shadow ray of a coarse light chooses among: 1, 2, 4, 8 or 16
    quiet: bool | None = ...,  # Don't show progress
    alpha: _Value | None = ...,  # The paper's α (backend lgh) (default 4)
    backend: Literal['lgh', 'brute', 'lightcuts'] | None = ...,  # Many-lights method (default lgh)
    no_direct: bool | None = ...,  # Only the VPLs' indirect light (what `lgh bench gi` compares): no direct light from the primary lights, no emitters seen
    area_strata: _Value | None = ...,  # Strata per side of an area light's direct-light pattern: N² shadow rays per emissive triangle and shading point, a pattern fixed per surface point (no flicker)
) -> npt.NDArray[np.float32]:
    """`lgh gi --obj OBJ` with the settings given, rendered into memory."""
