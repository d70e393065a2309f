//! Building one level ℓ ≥ 1 of the hierarchy: the splat of eqs. (1), (2), (4) and (5).
//!
//! A level's input is a set of lights sorted so that each level-ℓ cell is a contiguous run, each
//! light given by its position inside its cell in cell units (`f ∈ [0, 1]³`, the trilinear
//! coordinates), its RGB intensity and luminance. The level's vertices are the corners of the occupied
//! cells ("levels are sparse": a vertex exists only if a light lies in one of its eight cells).
//!
//! Moments are accumulated relative to each vertex in cell units (offsets in `[−1, 1]`), never in
//! world coordinates, so the variance `E[o²] − E[o]²` loses nothing to cancellation far from the
//! origin. Each cell first sums its lights into eight local corner accumulators, in input order;
//! vertices then add the partial sums of their cells, in cell order. Both orders are fixed by the
//! sort, so a level is bit-identical whatever the thread count.

use alloc::vec;
use alloc::vec::Vec;
use glam::Vec3;

use crate::bricks::BrickIndex;
use crate::grid::{Clustering, LightPosition};
use crate::light::{luminance, GridLight, LevelKind, LevelLights};
use crate::math::sqrt;
use crate::morton;

/// Corner `k` of a cell is at offset `(k & 1, (k >> 1) & 1, k >> 2)`.
const CORNER: [[f32; 8]; 3] = [
    [0., 1., 0., 1., 0., 1., 0., 1.],
    [0., 0., 1., 1., 0., 0., 1., 1.],
    [0., 0., 0., 0., 1., 1., 1., 1.],
];

/// Splits a sorted sequence of per-light cell codes into runs: the distinct cell codes and the
/// start of each run (with a final end marker).
pub(crate) fn runs(codes: impl Iterator<Item = u64>) -> (Vec<u64>, Vec<u32>) {
    let mut cells = Vec::new();
    let mut starts = Vec::new();
    let mut n = 0u32;
    for code in codes {
        if cells.last() != Some(&code) {
            cells.push(code);
            starts.push(n);
        }
        n += 1;
    }
    starts.push(n);
    (cells, starts)
}

/// Which vertices each cell touches; fixed as long as the lights do not move.
#[derive(Clone, Debug)]
pub(crate) struct Topology {
    /// `cell_starts[c]..cell_starts[c + 1]` are the input lights of cell `c`.
    pub cell_starts: Vec<u32>,
    /// Morton codes of the vertices, increasing; vertex `i` is light `i` of the level.
    pub vertex_codes: Vec<u64>,
    /// Vertex index of corner `k` of cell `c`.
    pub cell_vertices: Vec<[u32; 8]>,
    /// Vertex lookup for queries.
    pub index: BrickIndex,
}

impl Topology {
    /// Topology of the cells `cells` (sorted codes) whose lights are the runs `cell_starts`.
    pub fn new(cells: &[u64], cell_starts: Vec<u32>) -> Self {
        let mut vertex_codes = Vec::new();
        morton::corner_codes(cells, &mut vertex_codes);
        let index = BrickIndex::from_sorted_codes(&vertex_codes);
        let cell_vertices = cells
            .iter()
            .map(|&code| {
                let c = morton::decode(code);
                let mut ids = [0u32; 8];
                for (k, id) in ids.iter_mut().enumerate() {
                    let k = k as u32;
                    *id = index
                        .rank([c[0] + (k & 1), c[1] + ((k >> 1) & 1), c[2] + (k >> 2)])
                        .expect("every corner of an occupied cell is a vertex");
                }
                ids
            })
            .collect();
        Topology {
            cell_starts,
            vertex_codes,
            cell_vertices,
            index,
        }
    }
}

/// The per-light input of a splat, in the level's sorted order.
pub(crate) struct SplatInput<'a> {
    /// Position inside the light's level-ℓ cell, in cell units.
    pub frac: &'a [[f32; 3]],
    /// RGB intensity.
    pub intensity: &'a [Vec3],
    /// Luminance of `intensity`.
    pub luminance: &'a [f32],
    /// Spread of each input light itself, in squared cell units (building from the previous level).
    pub extra_variance: Option<&'a [Vec3]>,
}

/// The splat's variants ([`GridSettings::clustering`](crate::GridSettings::clustering) and
/// [`position`](crate::GridSettings::position)): the paper's unless measuring its flickering
/// alternatives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub(crate) struct SplatVariant {
    pub clustering: Clustering,
    pub position: LightPosition,
}

impl SplatVariant {
    pub fn of(settings: &crate::grid::GridSettings) -> Self {
        SplatVariant {
            clustering: settings.clustering,
            position: settings.position,
        }
    }
}

/// Nearest-vertex clustering's weights of a light at `f` in its cell: 1 on the corner nearest
/// `f` (ties to the upper one), 0 on the others.
#[inline(always)]
fn nearest_weights(f: [f32; 3]) -> [f32; 8] {
    let k =
        usize::from(f[0] >= 0.5) | usize::from(f[1] >= 0.5) << 1 | usize::from(f[2] >= 0.5) << 2;
    let mut w = [0.0; 8];
    w[k] = 1.0;
    w
}

#[inline(always)]
fn weights(f: [f32; 3]) -> [f32; 8] {
    let wx = [1.0 - f[0], f[0]];
    let wy = [1.0 - f[1], f[1]];
    let wz = [1.0 - f[2], f[2]];
    let mut w = [0.0; 8];
    for (k, wk) in w.iter_mut().enumerate() {
        *wk = wx[k & 1] * wy[(k >> 1) & 1] * wz[k >> 2];
    }
    w
}

/// Splats the input onto the level's vertices and returns its lights: intensity (eq. 1),
/// illumination centre (eq. 2), variance (eq. 4) and size (eq. 5). `h` is the level's spacing,
/// `origin` its (shared) origin, `threshold` its weak-light threshold and `variant` the paper's
/// splat or one of its flickering alternatives.
pub(crate) fn splat(
    topo: &Topology,
    input: &SplatInput<'_>,
    h: f64,
    origin: [f64; 3],
    threshold: f32,
    variant: SplatVariant,
) -> LevelLights {
    // The clustering chosen once, outside the loops over the lights (one copy of the splat
    // per weighting, so the paper's pays no branch per light).
    match variant.clustering {
        Clustering::Trilinear => splat_with(topo, input, h, origin, threshold, variant, weights),
        Clustering::NearestVertex => {
            splat_with(topo, input, h, origin, threshold, variant, nearest_weights)
        }
    }
}

/// [`splat`] with the light-to-vertex weights `weights`: the sums of eqs. (1), (2) and (4) over
/// the lights, the centres (eq. 2), the sums of eq. (5) about them, then each vertex's light.
fn splat_with(
    topo: &Topology,
    input: &SplatInput<'_>,
    h: f64,
    origin: [f64; 3],
    threshold: f32,
    variant: SplatVariant,
    weights: impl Fn([f32; 3]) -> [f32; 8] + Copy,
) -> LevelLights {
    let sums = moment_sums(topo, input, weights);
    let mean = centres(&sums);
    let sum_s = size_sums(topo, input, &mean, weights);
    let nv = topo.vertex_codes.len();
    let lights = (0..nv).map(|i| {
        let at = match variant.position {
            LightPosition::IlluminationCentre => mean[i],
            LightPosition::GridVertex => [0.0; 3],
        };
        let position = world_position(morton::decode(topo.vertex_codes[i]), at, origin, h);
        let (variance, size) = variance_and_size(&sums, sum_s[i], mean[i], i, h as f32);
        GridLight {
            position,
            intensity: sums.intensity[i],
            variance,
            size,
            luminance: luminance(sums.intensity[i]),
        }
    });
    LevelLights::from_lights(lights, LevelKind::Grid, threshold)
}

/// Each vertex's sums over the lights it gathers, offsets `o` from the vertex in cell units
/// and `v = w ‖I‖` (so `Σ v` is the luminance the vertex gathers).
struct MomentSums {
    /// `Σ w I`: the vertex's intensity (eq. 1).
    intensity: Vec<Vec3>,
    /// `Σ v`.
    weight: Vec<f32>,
    /// `Σ v o`: the centre's numerator (eq. 2).
    first: Vec<[f32; 3]>,
    /// `Σ v (o² + extra)`: the variance's (eq. 4).
    second: Vec<[f32; 3]>,
}

/// Pass 1 (eqs. 1, 2, 4): every cell's lights summed into its eight corners
/// ([`cell_moment_sums`]), the cells' sums then added to their vertices, in cell order.
fn moment_sums(
    topo: &Topology,
    input: &SplatInput<'_>,
    weights: impl Fn([f32; 3]) -> [f32; 8] + Copy,
) -> MomentSums {
    let nv = topo.vertex_codes.len();
    let mut sums = MomentSums {
        intensity: vec![Vec3::ZERO; nv],
        weight: vec![0.0f32; nv],
        first: vec![[0.0f32; 3]; nv],
        second: vec![[0.0f32; 3]; nv],
    };
    for (c, ids) in topo.cell_vertices.iter().enumerate() {
        let (start, end) = (
            topo.cell_starts[c] as usize,
            topo.cell_starts[c + 1] as usize,
        );
        let cell = cell_moment_sums(input, start, end, weights);
        for (k, &id) in ids.iter().enumerate() {
            let id = id as usize;
            sums.intensity[id] += Vec3::new(cell.ai[0][k], cell.ai[1][k], cell.ai[2][k]);
            sums.weight[id] += cell.av[k];
            for a in 0..3 {
                sums.first[id][a] += cell.am1[a][k];
                sums.second[id][a] += cell.am2[a][k];
            }
        }
    }
    sums
}

/// One cell's sums of [`MomentSums`] at its eight corners, by axis then corner.
struct CellMomentSums {
    ai: [[f32; 8]; 3],
    av: [f32; 8],
    am1: [[f32; 8]; 3],
    am2: [[f32; 8]; 3],
}

/// The lights `start..end` of one cell summed, in input order, into its eight corners.
#[inline(always)]
fn cell_moment_sums(
    input: &SplatInput<'_>,
    start: usize,
    end: usize,
    weights: impl Fn([f32; 3]) -> [f32; 8],
) -> CellMomentSums {
    let mut ai = [[0.0f32; 8]; 3];
    let mut av = [0.0f32; 8];
    let mut am1 = [[0.0f32; 8]; 3];
    let mut am2 = [[0.0f32; 8]; 3];
    for j in start..end {
        let f = input.frac[j];
        let intensity = input.intensity[j].to_array();
        let lum = input.luminance[j];
        let extra = input.extra_variance.map_or([0.0; 3], |e| e[j].to_array());
        let w = weights(f);
        for k in 0..8 {
            let v = w[k] * lum;
            av[k] += v;
            for a in 0..3 {
                ai[a][k] += w[k] * intensity[a];
                let o = f[a] - CORNER[a][k];
                am1[a][k] += v * o;
                am2[a][k] += v * (o * o + extra[a]);
            }
        }
    }
    CellMomentSums { ai, av, am1, am2 }
}

/// The illumination centres (eq. 2) relative to their vertices, in cell units: `Σ v o / Σ v`
/// (the vertex itself where it gathers no luminance).
fn centres(sums: &MomentSums) -> Vec<[f32; 3]> {
    (0..sums.weight.len())
        .map(|i| {
            let v = sums.weight[i];
            let m1 = sums.first[i];
            if v > 0.0 {
                [m1[0] / v, m1[1] / v, m1[2] / v]
            } else {
                [0.0; 3]
            }
        })
        .collect()
}

/// Pass 2 (eq. 5 needs the centre first): each vertex's `Σ v ‖o − mean‖`, every cell's lights
/// summed into its eight corners, the cells' sums then added to their vertices, in cell order.
fn size_sums(
    topo: &Topology,
    input: &SplatInput<'_>,
    mean: &[[f32; 3]],
    weights: impl Fn([f32; 3]) -> [f32; 8],
) -> Vec<f32> {
    let mut sum_s = vec![0.0f32; topo.vertex_codes.len()];
    for (c, ids) in topo.cell_vertices.iter().enumerate() {
        let (start, end) = (
            topo.cell_starts[c] as usize,
            topo.cell_starts[c + 1] as usize,
        );
        let mut centre = [[0.0f32; 8]; 3];
        for (k, &id) in ids.iter().enumerate() {
            for a in 0..3 {
                centre[a][k] = CORNER[a][k] + mean[id as usize][a];
            }
        }
        let mut acc = [0.0f32; 8];
        for j in start..end {
            let f = input.frac[j];
            let lum = input.luminance[j];
            let w = weights(f);
            for k in 0..8 {
                let dx = f[0] - centre[0][k];
                let dy = f[1] - centre[1][k];
                let dz = f[2] - centre[2][k];
                acc[k] += w[k] * lum * sqrt(dx * dx + dy * dy + dz * dz);
            }
        }
        for (k, &id) in ids.iter().enumerate() {
            sum_s[id as usize] += acc[k];
        }
    }
    sum_s
}

/// The world position of the point `at` (cell units) from vertex `q` of the grid of spacing `h`
/// at `origin`, in f64 and then rounded.
#[inline]
fn world_position(q: [u32; 3], at: [f32; 3], origin: [f64; 3], h: f64) -> Vec3 {
    Vec3::new(
        (origin[0] + (q[0] as f64 + at[0] as f64) * h) as f32,
        (origin[1] + (q[1] as f64 + at[1] as f64) * h) as f32,
        (origin[2] + (q[2] as f64 + at[2] as f64) * h) as f32,
    )
}

/// Vertex `i`'s per-axis variance (eq. 4: `Σ v o² / Σ v − mean²`, never below 0) and size
/// (eq. 5: `sum_s / Σ v`), both scaled from cell units by `hf = h`; zero where it gathers no
/// luminance.
#[inline]
fn variance_and_size(sums: &MomentSums, sum_s: f32, m: [f32; 3], i: usize, hf: f32) -> (Vec3, f32) {
    let v = sums.weight[i];
    if v > 0.0 {
        let m2 = sums.second[i];
        let var = Vec3::new(
            (m2[0] / v - m[0] * m[0]).max(0.0),
            (m2[1] / v - m[1] * m[1]).max(0.0),
            (m2[2] / v - m[2] * m[2]).max(0.0),
        );
        ((var * hf) * hf, sum_s / v * hf)
    } else {
        (Vec3::ZERO, 0.0)
    }
}
