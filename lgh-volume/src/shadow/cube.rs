//! The texel layout of a cube map whose lookups are continuous everywhere, across faces too
//! (paper Sec. 4: the shadow must be continuous in the shading point, or it flickers).
//!
//! Texels sit on the *vertices* of each face's `R × R` grid: face `f` of axis `a` (sign `±`)
//! has `(R + 1)²` texels at the directions `(±1, −1 + 2i/R, −1 + 2j/R)` (in the order axis `a`,
//! then `a + 1`, `a + 2`, modulo 3). A texel on an edge or a corner is stored once per face that
//! holds it, but its direction is the same vector bit for bit on every face (`−1 + 2R/R` is
//! exactly 1), so whatever is traced along it is the same on each, and bilinear interpolation
//! within a face meets the neighbouring face's on the shared edge. A face grid of `R` cells has
//! cells `2/R` wide at unit distance: `2r/R` at distance `r`, which is `h` when `R = 2r/h` (the
//! paper's resolution, `24 (r/h)²` cells in all).

use lgh_core::glam::Vec3;

/// Texels per face side for `R` cells: `R + 1`.
#[inline]
#[must_use]
pub fn side(cells: u32) -> usize {
    cells as usize + 1
}

/// Texels of a whole map of `cells` cells per face side: `6 (R + 1)²`.
#[inline]
#[must_use]
pub fn texels(cells: u32) -> usize {
    6 * side(cells) * side(cells)
}

/// The direction (not normalised) of texel `(i, j)` of face `face` in a map of `cells` cells per
/// face side. Texels shared by two or three faces get the same vector on each.
#[must_use]
pub fn direction(face: usize, i: usize, j: usize, cells: u32) -> Vec3 {
    let c = |n: usize| -1.0 + 2.0 * n as f32 / cells as f32;
    let a = face / 2;
    let sign = if face.is_multiple_of(2) { 1.0 } else { -1.0 };
    let mut v = [0.0f32; 3];
    v[a] = sign;
    v[(a + 1) % 3] = c(i);
    v[(a + 2) % 3] = c(j);
    Vec3::from(v)
}

/// Where a direction lands in a map of `cells` cells per face side: the first of the four texels
/// to interpolate (an index into the map's texels) and the weights `(tx, ty)` towards texel
/// `+1` (next along the face's first axis) and `+side` (next along its second).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Index of the texel at the cell's low corner.
    pub first: usize,
    /// Weight of the texel one further along the face's first axis.
    pub tx: f32,
    /// Weight of the texel one further along the face's second axis.
    pub ty: f32,
}

/// The bilinear footprint of direction `v` (any length but zero) in a map of `cells` cells per
/// face side. The face is the one of `v`'s largest component; on a tie either face gives the same
/// interpolated value, as the texels on their shared edge are the same.
#[inline]
#[must_use]
pub fn footprint(v: Vec3, cells: u32) -> Footprint {
    let a = v.abs();
    let (axis, major) = if a.x >= a.y && a.x >= a.z {
        (0, v.x)
    } else if a.y >= a.z {
        (1, v.y)
    } else {
        (2, v.z)
    };
    let face = 2 * axis + usize::from(major < 0.0);
    let inv = 1.0 / major.abs();
    let half = 0.5 * cells as f32;
    // Grid coordinates in [0, R]: (u + 1) R / 2 with u = v_b / |v_a|.
    let gx = (v[(axis + 1) % 3] * inv + 1.0) * half;
    let gy = (v[(axis + 2) % 3] * inv + 1.0) * half;
    let max = (cells - 1) as f32;
    // Clamped to the face's last cell (a NaN falls to cell 0), so the footprint stays on it.
    let cx = gx.clamp(0.0, max) as usize;
    let cy = gy.clamp(0.0, max) as usize;
    let s = side(cells);
    Footprint {
        first: (face * s + cy) * s + cx,
        tx: (gx - cx as f32).clamp(0.0, 1.0),
        ty: (gy - cy as f32).clamp(0.0, 1.0),
    }
}

/// Bilinear interpolation of `value(texel)` over a footprint in a map of `cells` cells per side.
#[inline]
#[must_use]
pub fn bilinear(f: &Footprint, cells: u32, value: impl Fn(usize) -> f32) -> f32 {
    let s = side(cells);
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let lo = lerp(value(f.first), value(f.first + 1), f.tx);
    let hi = lerp(value(f.first + s), value(f.first + s + 1), f.tx);
    lerp(lo, hi, f.ty)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A map whose texels hold a smooth function of their direction.
    fn map(cells: u32, f: impl Fn(Vec3) -> f32) -> Vec<f32> {
        let s = side(cells);
        let mut out = vec![0.0; texels(cells)];
        for face in 0..6 {
            for j in 0..s {
                for i in 0..s {
                    out[(face * s + j) * s + i] = f(direction(face, i, j, cells).normalize());
                }
            }
        }
        out
    }

    #[test]
    fn texels_reproduce_their_own_values_and_shared_texels_agree() {
        let cells = 5;
        let f = |v: Vec3| v.x * 3.0 + v.y * v.z + 2.0;
        let m = map(cells, f);
        let s = side(cells);
        for face in 0..6 {
            for j in 0..s {
                for i in 0..s {
                    let d = direction(face, i, j, cells);
                    // Looked up along its own direction, scaled, a texel returns its value.
                    let got = bilinear(&footprint(d * 2.5, cells), cells, |t| m[t]);
                    assert!((got - m[(face * s + j) * s + i]).abs() < 1e-5);
                }
            }
        }
        assert_eq!(texels(cells), 6 * 36);
    }

    #[test]
    fn lookups_are_continuous_across_faces_and_converge_at_second_order() {
        // f is smooth on the sphere; the bilinear lookup of its texel samples errs by
        // O(cell²). Continuity: two directions ε apart differ by at most the lookup's
        // Lipschitz constant (the texel differences over a cell, ≤ max|∇f| · cell) times ε;
        // across an edge that holds only if the faces agree there.
        let f = |v: Vec3| (2.0 * v.x).sin() + v.y * v.z + (v.z * 1.5).cos();
        let mut rng = lgh_core::random::SplitMix64(21);
        let mut errs = Vec::new();
        for cells in [8u32, 16, 32] {
            let m = map(cells, f);
            let mut worst = 0.0f32;
            for _ in 0..4000 {
                let v = rng.next_in(Vec3::splat(-1.0), Vec3::splat(1.0));
                if v.length() < 0.1 {
                    continue;
                }
                let got = bilinear(&footprint(v, cells), cells, |t| m[t]);
                worst = worst.max((got - f(v.normalize())).abs());
            }
            errs.push(worst);
            // Directions on the edges between faces, nudged by ε = 10⁻⁶ onto either face: the two
            // faces' lookups must meet. With the two largest components ≥ 0.5 in size, a change
            // of the direction by |Δv| ≤ √3 ε moves the face coordinates v_b/|v_a| by ≤ 6|Δv|,
            // and the bilinear lookup changes by ≤ √2 max|∇f| ≤ √2 · 4.5 per unit of face
            // coordinate: ≤ 66 ε, plus a few ulps of rounding. A face laid out the wrong way
            // round misses by O(1), one misplaced by a texel by O(|∇f| · 2/R).
            let eps = 1e-6;
            for _ in 0..2000 {
                let mut v = rng.next_in(Vec3::splat(-1.0), Vec3::splat(1.0));
                let axis = rng.next_f32() < 0.5;
                let (a, b) = if axis { (1, 2) } else { (2, 1) };
                let size = 0.5 + 0.5 * rng.next_f32();
                v.x = size * v.x.signum();
                v[a] = size * v[a].signum();
                v[b] *= size;
                let mut on_x = v;
                on_x.x *= 1.0 + eps;
                let mut on_other = v;
                on_other[a] *= 1.0 + eps;
                let l = bilinear(&footprint(on_x, cells), cells, |t| m[t]);
                let r = bilinear(&footprint(on_other, cells), cells, |t| m[t]);
                assert!((l - r).abs() < 66.0 * eps + 5e-6, "{v}: {l} vs {r}");
            }
        }
        // Second order: doubling the resolution cuts the error about four times.
        assert!(
            errs[1] < errs[0] / 3.0 && errs[2] < errs[1] / 3.0,
            "{errs:?}"
        );
    }
}
