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
use crate::light::{luminance, GridLight, LevelLights};
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

/// [`splat`] with the light-to-vertex weights `weights`.
fn splat_with(
    topo: &Topology,
    input: &SplatInput<'_>,
    h: f64,
    origin: [f64; 3],
    threshold: f32,
    variant: SplatVariant,
    weights: impl Fn([f32; 3]) -> [f32; 8] + Copy,
) -> LevelLights {
    let nv = topo.vertex_codes.len();
    let mut sum_i = vec![Vec3::ZERO; nv];
    let mut sum_v = vec![0.0f32; nv];
    let mut sum_m1 = vec![[0.0f32; 3]; nv];
    let mut sum_m2 = vec![[0.0f32; 3]; nv];

    // Pass 1: Σ w I, Σ v, Σ v o, Σ v (o² + extra) with v = w ‖I‖ and o the offset from the vertex.
    for (c, ids) in topo.cell_vertices.iter().enumerate() {
        let (start, end) = (
            topo.cell_starts[c] as usize,
            topo.cell_starts[c + 1] as usize,
        );
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
        for (k, &id) in ids.iter().enumerate() {
            let id = id as usize;
            sum_i[id] += Vec3::new(ai[0][k], ai[1][k], ai[2][k]);
            sum_v[id] += av[k];
            for a in 0..3 {
                sum_m1[id][a] += am1[a][k];
                sum_m2[id][a] += am2[a][k];
            }
        }
    }

    // Illumination centres relative to their vertices, in cell units.
    let mean: Vec<[f32; 3]> = (0..nv)
        .map(|i| {
            let v = sum_v[i];
            if v > 0.0 {
                [sum_m1[i][0] / v, sum_m1[i][1] / v, sum_m1[i][2] / v]
            } else {
                [0.0; 3]
            }
        })
        .collect();

    // Pass 2 (eq. 5 needs the centre first): Σ v ‖o − mean‖.
    let mut sum_s = vec![0.0f32; nv];
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

    let hf = h as f32;
    let lights = (0..nv).map(|i| {
        let q = morton::decode(topo.vertex_codes[i]);
        let v = sum_v[i];
        let m = mean[i];
        let at = match variant.position {
            LightPosition::IlluminationCentre => m,
            LightPosition::GridVertex => [0.0; 3],
        };
        let position = Vec3::new(
            (origin[0] + (q[0] as f64 + at[0] as f64) * h) as f32,
            (origin[1] + (q[1] as f64 + at[1] as f64) * h) as f32,
            (origin[2] + (q[2] as f64 + at[2] as f64) * h) as f32,
        );
        let (variance, size) = if v > 0.0 {
            let var = Vec3::new(
                (sum_m2[i][0] / v - m[0] * m[0]).max(0.0),
                (sum_m2[i][1] / v - m[1] * m[1]).max(0.0),
                (sum_m2[i][2] / v - m[2] * m[2]).max(0.0),
            );
            ((var * hf) * hf, sum_s[i] / v * hf)
        } else {
            (Vec3::ZERO, 0.0)
        };
        GridLight {
            position,
            intensity: sum_i[i],
            variance,
            size,
            luminance: luminance(sum_i[i]),
        }
    });
    LevelLights::from_lights(lights, false, threshold)
}
