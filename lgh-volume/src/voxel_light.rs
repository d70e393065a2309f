//! What a voxel light emits: the emission over its voxel's cell, not at its centre.
//!
//! The paper's level-0 light of voxel `i` is a point of intensity `I0 = j(T_i) h³` (Sec. 6.1),
//! the emission at the voxel's centre times its volume. The renderers between the lights — the
//! march's emission along a camera ray and the path tracer — see `j(T(x))` of the trilinearly
//! interpolated temperature, and `j` is steeply convex in `T` (about `T⁴` and faster in the
//! visible band), so between two voxel centres it lies below the interpolation of their values:
//! on the 24³ ball of the scattering tests the centres' `Σ_i j(T_i) h³` exceeds the integral of
//! the emission field by 20%.
//!
//! A voxel light ([`NearField::Voxel`](lgh_core::NearField)) is the uniform emitting voxel of
//! `lgh_core::near_field`, and its intensity is what its cell emits: `I0 = ∫_cell j(T(x)) dx`,
//! with `T` (and the flame factor) interpolated as [`Volume::emission`] does. The cells tile the
//! grid, so the lights hold the emission over their cells, whatever the convexity — up to the
//! quadrature (0.2%; up to 3.4% in a cell that the cut-off at `T_min` crosses, 0.22% of the
//! total on the test ball).
//!
//! # Which cells are lights
//!
//! The paper's lights are the voxels hotter than `T_min`. A cell beside them emits too: its
//! temperature, interpolated, rises above `T_min` towards its hot neighbour, and with the
//! `attributes` interpolation ([`EmissionInterpolation::Attributes`]) the neighbour's `j(T_i)`
//! blends into it at up to half weight on the shared face. With lights at the hot voxels
//! alone those cells' light was lost: on Blender fires baked at 64³, 0.7% of the emitted power
//! with `attributes` and 0.1% with `temperature` (fire64 and smoky64; measured by summing
//! [`Volume::cell_emission`] over every voxel against over the lights), and the smoke they lit
//! 0.25–0.4% darker against lgh's path tracer. So a light stands at every voxel whose cell
//! emits, or whose centre does ([`Volume::emitting_cells`]): the lights hold the whole
//! emission, up to the quadrature. (The dev fire: 56,861 lights → 79,626, most of the new ones
//! dim; its lighting cache takes a quarter longer.) A cell whose centre emits but whose cell
//! does not (a peak just above `T_min`, sharper than the nodes) is a dark voxel light, and a
//! light of [`NearField::Clamp`](lgh_core::NearField), which takes the centres' emission.
//!
//! # Quadrature
//!
//! Inside a cell, the trilinear interpolation has eight pieces: the half-cells on either side
//! of the centre along each axis. Each half gets a two-point Gauss–Legendre rule per axis
//! (exact for cubics along each axis), four points per axis, 64 per cell, with equal weights.
//! The temperature at the 64 points is the separable contraction of the 3³ voxels around the
//! centre (clamped at the grid's faces, as the interpolation holds the outermost values to the
//! faces), then `j` is evaluated 64 times.
//!
//! # The near field's centre
//!
//! The uniform voxel of `lgh_core::near_field` spreads its light evenly over the cell. Where
//! the emission is steep across a cell — a flame's edge, a hot core's flank, the cut-off at
//! `T_min` — most of the cell's light leaves from one side of it, and a point within a voxel or
//! two of that side sees more of it than a uniform cube centred on the voxel gives: on a ball
//! whose temperature ends at the smoke's edge (`tools/near_field/ball.py`, single scattering
//! against lgh's path tracer) the last voxels were 16% over at two optical depths a voxel, its
//! centre 4–5% under. So a voxel light's near field — its fall-off and its escape's distance
//! — is centred at the luminance centroid of its cell's emission ([`Volume::cell_centroid`]),
//! by the same 64 nodes; its position in the hierarchy and its shadow ray's end stay at the
//! voxel's centre. The ball's edge comes to within 3% (0.97–0.99), and smoky64's single
//! scattering, 6.6% from the path tracer in structure (5×5-pixel means), to 3.6%
//! (docs/cycles.md, "The lighting cache's level 0 in dense smoke"). One centroid serves the
//! three channels, by luminance: where the temperature falls at 1,500 K green falls faster
//! than red, which it does not follow. The lights of scattered light are centred on their
//! voxels (their sources are `σ_s` times the fluence, not the emission), a merged light at its
//! emission's centroid scaled by the emission's share of its light.

use lgh_core::glam::Vec3;

use crate::grid::DenseGrid;
use crate::medium::{EmissionInterpolation, Medium, Volume};

/// Gauss–Legendre nodes of two points per half-cell, in voxel units from the centre:
/// `∓1/4 ∓ 1/(4√3)`. Each carries a quarter of the cell's width.
const NODES: [f32; 4] = [
    -0.25 - 0.144_337_57,
    -0.25 + 0.144_337_57,
    0.25 - 0.144_337_57,
    0.25 + 0.144_337_57,
];

/// Linear interpolation weights of each node on the voxels at offsets −1, 0, +1.
const WEIGHTS: [[f32; 3]; 4] = {
    let mut w = [[0.0f32; 3]; 4];
    let mut n = 0;
    while n < 4 {
        let s = NODES[n];
        w[n] = if s < 0.0 {
            [-s, 1.0 + s, 0.0]
        } else {
            [0.0, 1.0 - s, s]
        };
        n += 1;
    }
    w
};

/// `grid`'s values at the 4³ quadrature nodes of voxel `(i, j, k)`'s cell, x fastest.
fn at_nodes(grid: &DenseGrid, ijk: [usize; 3]) -> [f32; 64] {
    let around = around(grid.dims, ijk);
    contract(&around.map(|plane| plane.map(|row| row.map(|v| grid.data[v]))))
}

/// The 3³ voxels around voxel `(i, j, k)` (clamped at the grid's faces, as the interpolation
/// holds the outermost values), `[z][y][x]`, as linear indices.
fn around(dims: [usize; 3], [i, j, k]: [usize; 3]) -> [[[usize; 3]; 3]; 3] {
    let [nx, ny, nz] = dims;
    let near = |c: usize, n: usize| [c.saturating_sub(1), c, (c + 1).min(n - 1)];
    let (xs, ys, zs) = (near(i, nx), near(j, ny), near(k, nz));
    zs.map(|z| ys.map(|y| xs.map(|x| (z * ny + y) * nx + x)))
}

/// The values at the 4³ quadrature nodes of a cell, x fastest, of the field interpolated
/// trilinearly from `values`, the 3³ voxels around it (`[z][y][x]`).
fn contract(values: &[[[f32; 3]; 3]; 3]) -> [f32; 64] {
    // Contract x, then y, then z: 36 + 48 + 64 values.
    let mut x_done = [[[0.0f32; 4]; 3]; 3];
    for (c, plane) in values.iter().enumerate() {
        for (b, row) in plane.iter().enumerate() {
            for (a, w) in WEIGHTS.iter().enumerate() {
                x_done[c][b][a] = w[0] * row[0] + w[1] * row[1] + w[2] * row[2];
            }
        }
    }
    let mut y_done = [[[0.0f32; 4]; 4]; 3];
    for c in 0..3 {
        for (b, w) in WEIGHTS.iter().enumerate() {
            for a in 0..4 {
                let v = &x_done[c];
                y_done[c][b][a] = w[0] * v[0][a] + w[1] * v[1][a] + w[2] * v[2][a];
            }
        }
    }
    let mut out = [0.0f32; 64];
    for (c, w) in WEIGHTS.iter().enumerate() {
        for b in 0..4 {
            for a in 0..4 {
                out[(c * 4 + b) * 4 + a] =
                    w[0] * y_done[0][b][a] + w[1] * y_done[1][b][a] + w[2] * y_done[2][b][a];
            }
        }
    }
    out
}

/// `mask` grown by one voxel either way along `axis` (0 = x) on a grid of `dims`, x fastest.
fn dilate(mask: &[bool], dims: [usize; 3], axis: usize) -> Vec<bool> {
    let stride = [1, dims[0], dims[0] * dims[1]][axis];
    let n = dims[axis];
    (0..mask.len())
        .map(|i| {
            let c = (i / stride) % n;
            mask[i] || (c > 0 && mask[i - stride]) || (c + 1 < n && mask[i + stride])
        })
        .collect()
}

/// The luminance-weighted mean position of the 4³ quadrature nodes carrying `emission` (x
/// fastest), in voxels from the cell's centre; zero where nothing is emitted.
fn centroid(emission: &[Vec3; 64]) -> Vec3 {
    let (mut weight, mut sum) = (0.0f32, Vec3::ZERO);
    for (n, &j) in emission.iter().enumerate() {
        let w = lgh_core::luminance(j).max(0.0);
        weight += w;
        sum += w * Vec3::new(NODES[n % 4], NODES[(n / 4) % 4], NODES[n / 16]);
    }
    if weight > 0.0 {
        sum / weight
    } else {
        Vec3::ZERO
    }
}

impl Volume {
    /// The mean emission over voxel `idx`'s cell (the cube of side `h` around its centre), of
    /// the temperature and flame interpolated as [`emission`](Self::emission) does: what a voxel
    /// light emits per unit volume (module documentation). Equal to
    /// [`voxel_emission`](Self::voxel_emission) where the temperature is uniform around the
    /// voxel; below it at a hot peak, above it beside one.
    ///
    /// ```
    /// use lgh_volume::{procedural, Medium};
    ///
    /// let volume = procedural::ball(16, 0.7, 3000.0);
    /// let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0)?;
    /// let t = &volume.temperature;
    /// let centre = t.index(8, 8, 8); // near the hot core's peak
    /// let (cell, point) = (volume.cell_emission(&medium, centre), volume.voxel_emission(&medium, centre));
    /// assert!(cell.x < point.x); // the emission is convex in T: the peak's cell is dimmer
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn cell_emission(&self, medium: &Medium, idx: usize) -> Vec3 {
        self.cell_light(medium, idx).0
    }

    /// Where in voxel `idx`'s cell its light is emitted: the centroid of the emission over the
    /// cell, `∫_cell x L(j(x)) dx / ∫_cell L(j(x)) dx` by luminance `L`, by the quadrature of
    /// [`cell_emission`](Self::cell_emission), in voxels from the centre (each coordinate within
    /// ±0.41, the outermost nodes'); zero where the cell emits nothing. A voxel light's near field
    /// is centred there (module documentation, "The near field's centre").
    ///
    /// ```
    /// use lgh_volume::{procedural, Medium};
    ///
    /// let volume = procedural::ball(16, 0.7, 3000.0);
    /// let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0)?;
    /// let t = &volume.temperature;
    /// // A voxel on the hot core's +x flank: its cell emits more on the side of the core.
    /// let c = volume.cell_centroid(&medium, t.index(10, 8, 8));
    /// assert!(c.x < -0.01 && c.x > -0.5, "{c}");
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn cell_centroid(&self, medium: &Medium, idx: usize) -> Vec3 {
        self.cell_light(medium, idx).1
    }

    /// [`cell_emission`](Self::cell_emission) and [`cell_centroid`](Self::cell_centroid) of
    /// voxel `idx` from one evaluation of its cell's emission at the 4³ quadrature nodes: a
    /// voxel light's intensity per unit volume and its near field's centre.
    pub(crate) fn cell_light(&self, medium: &Medium, idx: usize) -> (Vec3, Vec3) {
        let t = &self.temperature;
        let ijk = t.voxel(idx);
        if let Some(colour) = self.colour.as_deref() {
            // Linear in each channel: the cell's mean is each channel's mean (before the
            // clamp of negative channels, which a trilinear RGB field of positive voxels
            // never needs); the centroid weighs each node's clamped colour.
            let [r, g, b] = colour.each_ref().map(|g| at_nodes(g, ijk));
            let mean = |c: &[f32; 64]| c.iter().sum::<f32>() / 64.0;
            let cell = medium.colour_emission(Vec3::new(mean(&r), mean(&g), mean(&b)));
            let nodes: [Vec3; 64] =
                std::array::from_fn(|n| medium.colour_emission(Vec3::new(r[n], g[n], b[n])));
            return (cell, centroid(&nodes));
        }
        let flame = self.flame.as_ref().map(|f| at_nodes(f, ijk));
        let nodes: [Vec3; 64] = if medium.interpolation == EmissionInterpolation::Attributes {
            // The voxels' emission interpolated, channel by channel, times the flame's.
            let voxels = around(t.dims, ijk);
            let j = voxels.map(|p| p.map(|r| r.map(|v| medium.emission_at(t.data[v]))));
            let channel = |c: usize| contract(&j.map(|p| p.map(|r| r.map(|e| e[c]))));
            let [r, g, b] = [channel(0), channel(1), channel(2)];
            std::array::from_fn(|n| {
                let f = flame.map_or(1.0, |f| f[n].max(0.0));
                Vec3::new(r[n], g[n], b[n]) * f
            })
        } else {
            let temperature = at_nodes(t, ijk);
            std::array::from_fn(|n| {
                let j = medium.emission_at(temperature[n]);
                match &flame {
                    Some(f) if j != Vec3::ZERO => j * f[n].max(0.0),
                    _ => j,
                }
            })
        };
        (nodes.iter().sum::<Vec3>() / 64.0, centroid(&nodes))
    }

    /// Whether voxel `idx`'s cell emits: its [`cell_emission`](Self::cell_emission) is not
    /// zero. A voxel light stands at every such cell (module documentation, "Which cells are
    /// lights"), whether or not its centre emits ([`voxel_emits`](Self::voxel_emits)).
    ///
    /// ```
    /// use lgh_volume::{procedural, Medium};
    ///
    /// let volume = procedural::ball(16, 0.7, 3000.0);
    /// let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0)?;
    /// // A voxel just outside the hot core: its centre is below T_min, its cell is not.
    /// let edge = (0..volume.temperature.data.len())
    ///     .find(|&i| !volume.voxel_emits(&medium, i) && volume.cell_emits(&medium, i));
    /// assert!(edge.is_some());
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn cell_emits(&self, medium: &Medium, idx: usize) -> bool {
        self.cell_emission(medium, idx).max_element() > 0.0
    }

    /// Which voxels of the temperature's grid are lights, by linear index: those whose cell
    /// emits ([`cell_emits`](Self::cell_emits)) or whose centre does
    /// ([`voxel_emits`](Self::voxel_emits), the paper's lights, which
    /// [`NearField::Clamp`](lgh_core::NearField) takes at their centres). Only cells within one
    /// voxel of a value that emits ([`value_emits`](Self::value_emits)) are integrated: a
    /// cell's emission is interpolated from the 3³ voxels around it, and a blend of values at
    /// or below `T_min` (or of black colours) emits nothing.
    ///
    /// ```
    /// use lgh_volume::{procedural, Medium};
    ///
    /// let volume = procedural::ball(16, 0.7, 3000.0);
    /// let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0)?;
    /// let cells = volume.emitting_cells(&medium);
    /// for (i, &light) in cells.iter().enumerate() {
    ///     let emits = volume.cell_emits(&medium, i) || volume.voxel_emits(&medium, i);
    ///     assert_eq!(light, emits);
    /// }
    /// let (cells, centres) = (
    ///     cells.iter().filter(|&&e| e).count(),
    ///     volume.emitting_voxels(&medium),
    /// );
    /// assert!(cells > centres, "{cells} cells, {centres} centres");
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn emitting_cells(&self, medium: &Medium) -> Vec<bool> {
        let t = &self.temperature;
        let mut near: Vec<bool> = t
            .data
            .iter()
            .map(|&v| self.value_emits(medium, v))
            .collect();
        for axis in 0..3 {
            near = dilate(&near, t.dims, axis);
        }
        near.iter()
            .enumerate()
            .map(|(i, &near)| near && (self.voxel_emits(medium, i) || self.cell_emits(medium, i)))
            .collect()
    }

    /// The mean density over voxel `idx`'s cell, of the density interpolated trilinearly as the
    /// march and the path tracer see it: the smoke that scatters in the cell. `(1/8, 3/4, 1/8)` of the voxel and
    /// its neighbours along each axis; equal to the voxel's value where the density is linear
    /// around it, below it on a peak. (The scattering pass keeps the centre's value: the cell's
    /// mean, measured, took a path-traced ball further from the path tracer; docs/shadows.md.)
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::{procedural, DenseGrid, Volume};
    ///
    /// let volume = procedural::ball(16, 0.5, 2500.0);
    /// let d = &volume.density;
    /// let centre = d.index(8, 8, 8); // the density is 1 − r/0.8: a peak at the middle
    /// assert!(volume.cell_density(centre) < d.data[centre]);
    /// // A density linear in x: every inner cell's mean is its centre's value.
    /// let mut ramp = DenseGrid::zeros([5; 3], 0.1, Vec3::ZERO);
    /// for (n, v) in ramp.data.iter_mut().enumerate() {
    ///     *v = 1.0 + (n % 5) as f32;
    /// }
    /// let linear = Volume::new(ramp.clone(), ramp.clone());
    /// let inner = ramp.index(2, 2, 2);
    /// assert!((linear.cell_density(inner) - ramp.data[inner]).abs() < 1e-6);
    /// ```
    #[must_use]
    pub fn cell_density(&self, idx: usize) -> f32 {
        let d = &self.density;
        at_nodes(d, d.voxel(idx)).iter().sum::<f32>() / 64.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Voxel `idx`'s cell as the midpoints of `n³` sub-cells: each one's offset from the centre
    /// in voxels and the emission there.
    fn midpoints(volume: &Volume, medium: &Medium, idx: usize, n: usize) -> Vec<(Vec3, Vec3)> {
        let t = &volume.temperature;
        let [i, j, k] = t.voxel(idx);
        let c = t.centre(i, j, k);
        let mut points = Vec::with_capacity(n * n * n);
        for a in 0..n {
            for b in 0..n {
                for e in 0..n {
                    let o = (Vec3::new(a as f32, b as f32, e as f32) + 0.5) / n as f32 - 0.5;
                    points.push((o, volume.emission(medium, c + o * t.voxel_size)));
                }
            }
        }
        points
    }

    /// The mean of `volume.emission` over voxel `idx`'s cell by the midpoint rule on `n³`
    /// points.
    fn midpoint(volume: &Volume, medium: &Medium, idx: usize, n: usize) -> [f64; 3] {
        let points = midpoints(volume, medium, idx, n);
        let mut sum = [0.0f64; 3];
        for (_, v) in &points {
            for (s, x) in sum.iter_mut().zip(v.to_array()) {
                *s += f64::from(x);
            }
        }
        sum.map(|s| s / points.len() as f64)
    }

    /// The lowest and highest temperature of the 3³ voxels around `idx` (clamped at the faces):
    /// the range the interpolation takes in its cell.
    fn temperature_range(volume: &Volume, idx: usize) -> (f32, f32) {
        let t = &volume.temperature;
        let [i, j, k] = t.voxel(idx);
        let mut range = (f32::INFINITY, f32::NEG_INFINITY);
        for c in k.saturating_sub(1)..=(k + 1).min(t.dims[2] - 1) {
            for b in j.saturating_sub(1)..=(j + 1).min(t.dims[1] - 1) {
                for a in i.saturating_sub(1)..=(i + 1).min(t.dims[0] - 1) {
                    let v = t.get(a, b, c);
                    range = (range.0.min(v), range.1.max(v));
                }
            }
        }
        range
    }

    #[test]
    fn the_nodes_weigh_each_neighbour_as_the_interpolation_does() {
        for (w, s) in WEIGHTS.iter().zip(NODES) {
            assert_eq!(w.iter().sum::<f32>(), 1.0);
            assert!((w[2] - w[0] - s).abs() < 1e-7, "{w:?} at {s}");
        }
        // Symmetric about the centre, as the rule's nodes are.
        assert_eq!(NODES[0], -NODES[3]);
        assert_eq!(NODES[1], -NODES[2]);
    }

    #[test]
    fn the_quadrature_matches_a_fine_midpoint_rule() {
        // The ball's steepest voxels: the hot core's edge (3000 K at the centre, 1000 K at
        // radius 0.47) and the peak. 64 Gauss points against 24³ midpoints: the midpoint
        // rule's own error is O(1/24²) of the curvature, well under the 0.2% asked.
        let volume = crate::procedural::ball(24, 0.7, 3000.0);
        let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0).unwrap();
        let t = &volume.temperature;
        let mut checked = 0;
        for idx in 0..t.data.len() {
            if volume.voxel_emission(&medium, idx).x <= 0.0 {
                continue;
            }
            let got = volume.cell_emission(&medium, idx);
            let want = midpoint(&volume, &medium, idx, 24);
            // The emission stops at T_min (a step from j(T_min) to 0): where that boundary
            // crosses a cell, neither rule is exact: the Gauss rule errs there by up to 3.4% (a
            // channel of one cell, measured), by 0.2% elsewhere.
            let crossed = temperature_range(&volume, idx).0 <= medium.min_temperature;
            let bound = if crossed { 5e-2 } else { 2e-3 };
            // Each channel against the cell's brightest (a faint channel's relative error means
            // nothing to the image).
            let scale = want.iter().fold(0.0f64, |a, &b| a.max(b));
            for (g, w) in got.to_array().into_iter().zip(want) {
                let err = (f64::from(g) - w).abs() / scale;
                assert!(err < bound, "voxel {idx}: {got} vs {want:?}");
            }
            checked += usize::from(!crossed);
        }
        assert!(checked > 80, "{checked}");
    }

    /// The luminance centroid of `volume.emission` over voxel `idx`'s cell by the midpoint rule
    /// on `n³` points, in voxels from its centre.
    fn midpoint_centroid(volume: &Volume, medium: &Medium, idx: usize, n: usize) -> [f64; 3] {
        let (mut weight, mut sum) = (0.0f64, [0.0f64; 3]);
        for (o, j) in midpoints(volume, medium, idx, n) {
            let w = f64::from(lgh_core::luminance(j).max(0.0));
            weight += w;
            for (s, x) in sum.iter_mut().zip(o.to_array()) {
                *s += w * f64::from(x);
            }
        }
        sum.map(|s| if weight > 0.0 { s / weight } else { 0.0 })
    }

    #[test]
    fn the_emission_centroid_matches_a_fine_midpoint_rule() {
        // The ball's cells, where the emission is steep: the 64 Gauss points' weighted mean
        // against 24³ midpoints', to a hundredth of a voxel (the centroid moves a near field
        // whose fall-off changes by about 2% for a hundredth of a voxel at half a voxel).
        let volume = crate::procedural::ball(24, 0.7, 3000.0);
        let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0).unwrap();
        let t = &volume.temperature;
        let (mut checked, mut moved) = (0, 0);
        for idx in 0..t.data.len() {
            if volume.voxel_emission(&medium, idx).x <= 0.0
                || temperature_range(&volume, idx).0 <= medium.min_temperature
            {
                continue;
            }
            let got = volume.cell_centroid(&medium, idx);
            let want = midpoint_centroid(&volume, &medium, idx, 24);
            for (g, w) in got.to_array().into_iter().zip(want) {
                assert!(
                    (f64::from(g) - w).abs() < 1e-2,
                    "voxel {idx}: {got} vs {want:?}"
                );
            }
            checked += 1;
            moved += usize::from(got.length() > 0.05);
        }
        assert!(checked > 80 && moved > 10, "{checked} cells, {moved} moved");
    }

    /// Voxel `idx`'s cell as `n³` midpoints ([`midpoints`]): each point and its emission's
    /// luminance times its volume.
    fn cell_points(volume: &Volume, medium: &Medium, idx: usize, n: usize) -> Vec<(Vec3, f64)> {
        let t = &volume.temperature;
        let [i, j, k] = t.voxel(idx);
        let (c, h) = (t.centre(i, j, k), t.voxel_size);
        let dv = f64::from(h).powi(3) / f64::from(n as u32).powi(3);
        midpoints(volume, medium, idx, n)
            .into_iter()
            .map(|(o, j)| (c + o * h, f64::from(lgh_core::luminance(j).max(0.0)) * dv))
            .collect()
    }

    /// The luminance of the fluence at `x` from a cell's `points` in uniform smoke of
    /// extinction `sigma_t`: `∫_cell L(j(y)) e^{−σ_t‖x − y‖} / ‖x − y‖² dy` — the exact answer
    /// of the model a voxel light stands for.
    fn cell_fluence(points: &[(Vec3, f64)], x: Vec3, sigma_t: f32) -> f64 {
        points
            .iter()
            .map(|&(y, w)| {
                let r = f64::from(x.distance(y));
                w * (-f64::from(sigma_t) * r).exp() / (r * r)
            })
            .sum()
    }

    #[test]
    fn a_near_field_centred_at_the_centroid_follows_a_steep_cells_fluence() {
        use lgh_core::NearField;
        // Voxel lights of the cells whose emission is steepest (the ball's hot core's flanks
        // and its cut-off at T_min: the centroid at least a tenth of a voxel off the centre,
        // 160 cells), at 1, 1.5 and 2 voxels from the centre in 14 directions, in clear air
        // and in smoke of one optical depth a voxel: the voxel light's fluence (its cell's
        // power, the near field of a uniform voxel, the shadow ray's transmittance to the
        // voxel's centre) against the cell's exact fluence, with the near field centred at the
        // voxel's centre and at its emission's centroid. What remains with the centroid is the
        // emission's shape about it — these cells emit from a corner or a face, not uniformly
        // — and, in smoke, the shadow ray's end at the centre (measured: clear air 13.6 / 4.4
        // / 2.3% RMS against 75 / 43 / 30% centred; smoke 47 / 39 / 37% against 168 / 104 /
        // 81%; the shadow's difference `e^{−σ(‖x − c‖ − ‖x − p‖)}` taken in halves it, but
        // darkened smoky64 against Cycles, 7.99 → 9.11% a pixel, so it is not applied). The
        // bounds leave 14–18% headroom over those in clear air, 17–49% in smoke (the ratio to
        // the centred field's 0.5, 0.46 at 2 voxels: a margin of 9% there); the centroid on
        // the wrong side (measured: 310 / 125 / 72% clear, 643 / 280 / 158% in smoke), or none,
        // fails them several times over.
        let volume = crate::procedural::ball(12, 0.7, 3000.0);
        let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0).unwrap();
        let t = &volume.temperature;
        let h = t.voxel_size;
        let mut directions = vec![];
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            directions.extend([axis, -axis]);
        }
        for s in 0..8 {
            let sign = |b: usize| if (s >> b) & 1 == 0 { 1.0 } else { -1.0 };
            directions.push(Vec3::new(sign(0), sign(1), sign(2)).normalize());
        }
        let distances = [1.0f32, 1.5, 2.0];
        // Squared relative errors, centred and at the centroid, and their count, by distance.
        let mut errors = [[[0.0f64; 3]; 3]; 2];
        let mut cells = 0;
        for idx in 0..t.data.len() {
            let c = volume.cell_centroid(&medium, idx);
            if c.length() < 0.1 {
                continue;
            }
            cells += 1;
            let points = cell_points(&volume, &medium, idx, 20);
            // The cell's power by the same midpoints: this test is of the near field's shape;
            // the quadrature's own error is the tests' above.
            let power: f64 = points.iter().map(|&(_, w)| w).sum();
            let [i, j, k] = t.voxel(idx);
            let p = t.centre(i, j, k);
            for (tau, errors) in [0.0f32, 1.0].into_iter().zip(&mut errors) {
                let sigma_t = tau / h;
                for (&d, e) in distances.iter().zip(errors.iter_mut()) {
                    for &u in &directions {
                        let x = p + u * d * h;
                        let exact = cell_fluence(&points, x, sigma_t);
                        let shadow = f64::from((-sigma_t * x.distance(p)).exp());
                        let error = |centre: Vec3| {
                            let g = NearField::Voxel.falloff_in(0, x.distance(centre), h, tau);
                            power * f64::from(g) * shadow / exact - 1.0
                        };
                        e[0] += error(p).powi(2);
                        e[1] += error(p + c * h).powi(2);
                        e[2] += 1.0;
                    }
                }
            }
        }
        assert!(cells > 100, "{cells} steep cells");
        let rms = |e: [f64; 3]| [(e[0] / e[2]).sqrt(), (e[1] / e[2]).sqrt()];
        let clear_air = [0.16, 0.05, 0.027];
        for (k, d) in distances.iter().enumerate() {
            let [centred, centroid] = rms(errors[0][k]);
            assert!(
                centroid < clear_air[k] && centroid < 0.25 * centred,
                "clear air, {d} voxels: RMS {centroid} at the centroid, {centred} centred"
            );
            let [centred, centroid] = rms(errors[1][k]);
            assert!(
                centroid < 0.55 && centroid < 0.5 * centred,
                "τ = 1, {d} voxels: RMS {centroid} at the centroid, {centred} centred"
            );
        }
    }

    #[test]
    fn cells_of_interpolated_emission_are_exact() {
        // Each grid interpolated on its own (Cycles 4.x and later): the emission field is
        // trilinear in the voxels' j(T_i) — no step at T_min inside a cell, the cut-off is per
        // voxel — so the cell's Gauss rule and the midpoint rule on 24³ points are both exact,
        // up to f32 rounding (bound 1e-5 of the brightest channel, as for RGB cells).
        let volume = crate::procedural::ball(12, 0.7, 3000.0);
        let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0)
            .unwrap()
            .with_interpolation(EmissionInterpolation::Attributes);
        let t = &volume.temperature;
        let brightest = (0..t.data.len())
            .map(|i| volume.voxel_emission(&medium, i).max_element())
            .fold(0.0f32, f32::max);
        let mut lit = 0;
        for idx in 0..t.data.len() {
            let got = volume.cell_emission(&medium, idx);
            let want = midpoint(&volume, &medium, idx, 24);
            for (g, w) in got.to_array().into_iter().zip(want) {
                let err = (f64::from(g) - w).abs() / f64::from(brightest);
                assert!(err < 1e-5, "voxel {idx}: {got} vs {want:?}");
            }
            lit += usize::from(got.x > 0.0);
        }
        assert!(lit > 100, "{lit}");
    }

    #[test]
    fn cells_hold_the_emission_fields_total() {
        // The cells tile the grid: Σ cell means × h³ = ∫ j over the grid's box (sampled finely),
        // while the centres' values overshoot it (the convexity the module documents).
        let volume = crate::procedural::ball(12, 0.7, 3000.0);
        let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0).unwrap();
        let t = &volume.temperature;
        let lum = |v: Vec3| f64::from(lgh_core::luminance(v));
        let cells: f64 = (0..t.data.len())
            .map(|i| lum(volume.cell_emission(&medium, i)))
            .sum();
        let centres: f64 = (0..t.data.len())
            .map(|i| lum(volume.voxel_emission(&medium, i)))
            .sum();
        let mut field = 0.0;
        for i in 0..t.data.len() {
            let m = midpoint(&volume, &medium, i, 12);
            let w = lgh_core::LUMINANCE_WEIGHTS;
            field += f64::from(w.x) * m[0] + f64::from(w.y) * m[1] + f64::from(w.z) * m[2];
        }
        // 0.22% measured: the cells that the cut-off at T_min crosses (above).
        assert!((cells / field - 1.0).abs() < 4e-3, "{cells} vs {field}");
        assert!(centres / field > 1.05, "{centres} vs {field}");
    }

    #[test]
    fn an_rgb_cell_is_the_mean_of_its_trilinear_colour() {
        // The ball's blackbody emission at the voxels, read back as an RGB emission: trilinear
        // in each channel, so the 1/8–3/4–1/8 stencil is the cell's exact mean, and so is the
        // midpoint rule on 24³ points, whose sub-cells split each linear piece evenly: both
        // agree to f32 rounding (1.7e-7 of the brightest channel, measured; bound 1e-5).
        let ball = crate::procedural::ball(12, 0.7, 3000.0);
        let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0).unwrap();
        let channel = |c: usize| {
            let mut g = ball.temperature.clone();
            for (i, v) in g.data.iter_mut().enumerate() {
                *v = ball.voxel_emission(&medium, i)[c] * 1e3;
            }
            g
        };
        let rgb = Volume::with_colour(ball.density.clone(), [0, 1, 2].map(channel)).unwrap();
        let unit = Medium::new(0.5, 4.5, 1e-3, 1e6).unwrap(); // no cut applies to a colour
        let brightest = (0..rgb.temperature.data.len())
            .map(|i| rgb.voxel_emission(&unit, i).max_element())
            .fold(0.0f32, f32::max);
        for idx in 0..rgb.temperature.data.len() {
            let got = rgb.cell_emission(&unit, idx);
            let want = midpoint(&rgb, &unit, idx, 24);
            for (g, w) in got.to_array().into_iter().zip(want) {
                let err = (f64::from(g) - w).abs() / f64::from(brightest);
                assert!(err < 1e-5, "voxel {idx}: {got} vs {want:?}");
            }
        }
        // A light at every cell the trilinear colour reaches: the coloured voxels and the
        // cells beside them, which their colour blends into.
        let lights = crate::ExplosionLights::new(&[&rgb], &unit).unwrap();
        let n = rgb.temperature.data.len();
        let hot = (0..n).filter(|&i| ball.voxel_emits(&medium, i)).count();
        let cells = (0..n).filter(|&i| rgb.cell_emits(&unit, i)).count();
        assert_eq!((lights.lights().len(), lights.lit()), (cells, cells));
        assert!(cells > hot, "{cells} cells, {hot} coloured voxels");
    }

    #[test]
    fn uniform_temperature_gives_the_centres_emission() {
        let mut volume = crate::procedural::ball(6, 0.7, 3000.0);
        volume.temperature.data.fill(2000.0);
        let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0).unwrap();
        for idx in [0, 7, 100, 215] {
            let (cell, point) = (
                volume.cell_emission(&medium, idx),
                volume.voxel_emission(&medium, idx),
            );
            assert!((cell - point).abs().max_element() <= 1e-5 * point.max_element());
        }
    }
}
