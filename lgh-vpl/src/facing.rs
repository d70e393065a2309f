//! Which coarse lights face away from a point: a test, beyond the paper, that spares the
//! adaptive shading the lights whose every VPL lies behind the point.
//!
//! The hierarchy aggregates its input lights as isotropic points (eq. 3), but a VPL emits
//! nothing behind its face ([`Vpl::lobe`]: nothing where `g_j·(x − p_j) ≤ 0`, `g_j` its
//! geometric normal). A coarse light standing for a patch of floor gives nothing to the floor
//! around it, nor to anything beneath it, though its isotropic point says otherwise; on
//! Sponza at α = 4, six in ten of the representatives the adaptive shading looked at faced
//! away from the point (their lobe was zero there).
//!
//! [`Facing`] summarises a light's VPLs (every input light it aggregates with a weight and
//! some light, eqs. 1, 2) once:
//!
//! - the axis `a`, their geometric normals' mean weighted by `w_j ‖I_j‖` (unit);
//! - the plane `lo = min_j a·p_j`, the lowest of them along it;
//! - the spread `δ = max_j ‖g_j − a‖`;
//! - the tilt `τ = max_j ‖n_j − g_j‖` of their shading normals from their faces.
//!
//! Writing `g_j = a + δ_j`, with `‖x − p_j‖ ≤ d + e` (`d` the point's distance from the
//! light's centre, `e` its [`extent`](crate::representatives::Representatives::extent)):
//!
//! `g_j·(x − p_j) = a·x − a·p_j + δ_j·(x − p_j) ≤ (a·x − lo) + δ (d + e) = N`.
//!
//! Where `N < 0` every VPL of the light has `x` behind its face: the light gives `x` nothing
//! at all. A flat patch (`δ = 0`) seen from its own plane has `N = 0`, each VPL's face
//! exactly edge-on — nothing, too, but rounding cannot tell 0 from a hair above. So a light
//! is left out ([`Facing::faces_away`]) where `N` is at most `s`, the rounding's reach (a
//! millionth of the magnitudes, some ten times the f32 rounding of `a·x − lo`), and its
//! VPLs' shading normals lean from their faces by at most [`MAX_TILT`]. A VPL `r` from the
//! point that is left out while in front of its face is then at most `g_j·ω ≤ s / r` in
//! front, its lobe `2 n_j·ω ≤ 2 (s / r + τ)`: for a VPL a centimetre away in a scene tens of
//! metres across, a few thousandths of its lobe's peak — the grazing light of a surface in
//! the point's own plane, which brute force gives too and this test drops. (Nearer VPLs may
//! lose more of theirs, but the fall-off is clamped at `h₀`, so they carry no more light
//! than one at `h₀`.)
//!
//! The adaptive shading ([`Coarse::Adaptive`](crate::indirect::Coarse::Adaptive)) leaves such
//! lights out of the sharing; they keep their place in the budget, so their samples go to the
//! lights that give light.

use lgh_core::glam::{DVec3, Vec3};

use crate::vpl::Vpl;

/// The most a light's VPLs' shading normals may lean from their geometric ones
/// (`‖n_j − g_j‖`) for the light to be left out of a point in its own plane: 10⁻³, so that
/// each VPL it drops gives at most a few thousandths of its lobe's peak (module docs).
/// Flat-shaded VPLs have none.
pub const MAX_TILT: f32 = 1e-3;

/// Where a coarse light's VPLs face (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Facing {
    /// The unit axis `a`: the VPLs' geometric normals' weighted mean.
    pub axis: Vec3,
    /// `lo = min_j a·p_j`: the lowest VPL along the axis.
    pub plane: f32,
    /// `δ = max_j ‖g_j − a‖`, at most 2: how far any VPL's face strays from the axis.
    pub spread: f32,
    /// `τ = max_j ‖n_j − g_j‖`: how far any VPL's shading normal leans from its face.
    pub tilt: f32,
}

impl Facing {
    /// The summary that rules nothing out: any VPL may face any point (a spread of 2).
    pub const ANY: Facing = Facing {
        axis: Vec3::Y,
        plane: 0.0,
        spread: 2.0,
        tilt: 2.0,
    };

    /// The summary of `vpls`, each with its weight (`w_j ‖I_j‖`; those of weight 0 are left
    /// out): [`Facing::ANY`] if none has weight, or if their faces cancel.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_vpl::facing::Facing;
    /// use lgh_vpl::vpl::Vpl;
    ///
    /// let floor = |x: f32| Vpl { position: Vec3::new(x, 0.0, 0.0), normal: Vec3::Y,
    ///     geometric: Vec3::Y, power: Vec3::ONE, albedo: Vec3::ONE, bounce: 1 };
    /// let f = Facing::of([(floor(0.0), 1.0), (floor(0.5), 2.0)].iter().map(|(v, w)| (v, *w)));
    /// assert_eq!(f, Facing { axis: Vec3::Y, plane: 0.0, spread: 0.0, tilt: 0.0 });
    /// assert_eq!(Facing::of(std::iter::empty()), Facing::ANY);
    /// ```
    #[must_use]
    pub fn of<'v>(vpls: impl Iterator<Item = (&'v Vpl, f64)> + Clone) -> Facing {
        let lit = vpls.filter(|(_, w)| *w > 0.0);
        let sum: DVec3 = lit.clone().map(|(v, w)| v.geometric.as_dvec3() * w).sum();
        let Some(axis) = sum.try_normalize() else {
            return Facing::ANY;
        };
        // The plane and the spread about the axis as it is kept, in f32.
        let axis = axis.as_vec3();
        let exact = axis.as_dvec3();
        let (mut plane, mut spread, mut tilt) = (f64::INFINITY, 0.0f64, 0.0f64);
        for (v, _) in lit {
            let g = v.geometric.as_dvec3();
            plane = plane.min(exact.dot(v.position.as_dvec3()));
            spread = spread.max((g - exact).length());
            tilt = tilt.max((v.normal.as_dvec3() - g).length());
        }
        if !plane.is_finite() || !spread.is_finite() || !tilt.is_finite() {
            return Facing::ANY;
        }
        Facing {
            axis,
            plane: round_down(plane),
            spread: round_up(spread).min(2.0),
            tilt: round_up(tilt).min(2.0),
        }
    }

    /// True if every VPL of the light faces away from `x`, `d` from the light's centre
    /// (`‖x − centre‖`, as the caller has it), its VPLs within `extent` of the centre: `N`
    /// below the rounding's reach, and, if not below zero by as much, shading normals
    /// within [`MAX_TILT`] of the faces (module docs).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_vpl::facing::Facing;
    ///
    /// // A patch of floor at y = 0 centred on the origin, its VPLs within 0.1 of it.
    /// let floor = Facing { axis: Vec3::Y, plane: 0.0, spread: 0.0, tilt: 0.0 };
    /// let away = |f: &Facing, x: Vec3| f.faces_away(x, x.length(), 0.1);
    /// assert!(away(&floor, Vec3::new(0.0, -1.0, 0.0))); // beneath it
    /// assert!(away(&floor, Vec3::new(3.0, 0.0, 0.0))); // on its plane: edge-on
    /// assert!(!away(&floor, Vec3::new(3.0, 0.01, 0.0))); // a centimetre above
    /// // Smooth shading: edge-on is not ruled out, beneath is.
    /// let smooth = Facing { tilt: 0.1, ..floor };
    /// assert!(!away(&smooth, Vec3::new(3.0, 0.0, 0.0)));
    /// assert!(away(&smooth, Vec3::new(0.0, -1.0, 0.0)));
    /// // Faces that spread every way rule nothing out, however far below.
    /// assert!(!away(&Facing::ANY, Vec3::new(0.0, -1.0, 0.0)));
    /// assert!(!away(&Facing::ANY, Vec3::new(0.0, -10.0, 0.0)));
    /// ```
    #[must_use]
    #[inline]
    pub fn faces_away(&self, x: Vec3, d: f32, extent: f32) -> bool {
        // A spread of 2 (`ANY`, or faces every way) bounds nothing.
        if self.spread >= 2.0 {
            return false;
        }
        let (n, slack) = self.bound(x, d, extent);
        n < -slack || (n <= slack && self.tilt <= MAX_TILT)
    }

    /// `N` at `x` (module docs) and the rounding's reach `s` about it.
    #[inline]
    fn bound(&self, x: Vec3, d: f32, extent: f32) -> (f32, f32) {
        let reach = d + extent;
        let n = (self.axis.dot(x) - self.plane) + self.spread * reach;
        // The rounding of `a·x` (of the size of `Σ |a_i x_i|`, whatever `a·x` cancels to),
        // of the subtraction in f32, and of the VPLs' own `g_j·ω`: a few ulps of the
        // magnitudes, taken some ten times over.
        let slack = 1e-6 * (self.axis.abs().dot(x.abs()) + self.plane.abs() + reach);
        (n, slack)
    }
}

/// `x` rounded to f32 towards −∞ (finite `x`).
fn round_down(x: f64) -> f32 {
    -round_up(-x)
}

/// `x` rounded to f32 towards +∞ (finite `x`): the nearest f32, or the next one up if that
/// is below (`f32::next_up` is newer than the crate's Rust).
fn round_up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) >= x || !f.is_finite() {
        f
    } else if f == 0.0 {
        f32::from_bits(1)
    } else if f > 0.0 {
        f32::from_bits(f.to_bits() + 1)
    } else {
        f32::from_bits(f.to_bits() - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgh_core::random::SplitMix64;

    /// A unit vector uniform on the sphere (a fixed pseudo-random one).
    fn anywhere(rng: &mut SplitMix64) -> Vec3 {
        loop {
            let v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0;
            if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }

    /// A unit vector at most `cone` radians from `axis` (anywhere for `cone ≥ π`).
    fn near(axis: Vec3, cone: f32, rng: &mut SplitMix64) -> Vec3 {
        loop {
            let v = anywhere(rng);
            if v.dot(axis) >= cone.min(std::f32::consts::PI).cos() {
                return v;
            }
        }
    }

    /// The summary's rounding is on the side of the bound: never above `x` for the plane,
    /// never below it for the spread, and at most one f32 step away.
    #[test]
    fn rounding_is_on_the_side_of_the_bound() {
        let mut rng = SplitMix64(2);
        for _ in 0..10_000 {
            let x = (rng.next_f64() - 0.5) * 10f64.powi((rng.next_f64() * 12.0) as i32 - 6);
            let (down, up) = (round_down(x), round_up(x));
            assert!(
                f64::from(down) <= x && f64::from(up) >= x,
                "{x}: {down} {up}"
            );
            assert!(
                f64::from(up) - f64::from(down) <= 2.0 * f64::from(f32::EPSILON) * x.abs() + 1e-44
            );
        }
        assert_eq!((round_down(0.0), round_up(0.0)), (0.0, 0.0));
        assert_eq!(round_up(1e-50), f32::from_bits(1));
        assert_eq!(round_down(-1e-50), -f32::from_bits(1));
    }

    /// A light left out gives nothing, or only grazing light: over 2,000 pseudo-random
    /// patches (faces within 0°, 5°, 30° or 180° of an axis anywhere on the sphere, flat ones
    /// in their own plane; shading normals on their faces or leaning up to 0.1 rad; positions
    /// within a box; weights random or zero) and 30 points each (in the patch's plane, above
    /// it and beneath it, at distances from inside the patch to a hundred times its size),
    /// wherever [`Facing::faces_away`] says so every lit VPL `r` from the point has a lobe of
    /// at most `2 (s / r + τ)` (module docs; `s` the rounding's reach), and none at all where
    /// `N` is below `−s`. Points beneath, edge-on and kept all occur — the test would catch a
    /// summary that rules out light, and one that rules out nothing.
    #[test]
    fn a_light_that_faces_away_gives_nothing() {
        let mut rng = SplitMix64(11);
        let (mut beneath, mut edge_on, mut kept) = (0, 0, 0);
        for patch in 0..2000 {
            let axis = anywhere(&mut rng);
            let cone = [0.0, 0.09, 0.52, 3.2][patch % 4];
            let tilted = patch % 3 == 0;
            let centre = (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5) * 40.0;
            let size = 0.01 + rng.next_f32();
            let vpls: Vec<(Vpl, f64)> = (0..1 + patch % 9)
                .map(|_| {
                    let offset = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
                    let (offset, geometric) = if cone == 0.0 {
                        (offset - axis * axis.dot(offset), axis)
                    } else {
                        (offset, near(axis, cone, &mut rng))
                    };
                    let normal = if tilted {
                        near(geometric, 0.1, &mut rng)
                    } else {
                        geometric
                    };
                    let v = Vpl {
                        position: centre + offset * size,
                        normal,
                        geometric,
                        power: Vec3::ONE,
                        albedo: Vec3::ONE,
                        bounce: 1,
                    };
                    let w = if rng.next_f32() < 0.1 {
                        0.0
                    } else {
                        f64::from(rng.next_f32())
                    };
                    (v, w)
                })
                .collect();
            let facing = Facing::of(vpls.iter().map(|(v, w)| (v, *w)));
            let lit: Vec<&Vpl> = vpls
                .iter()
                .filter(|(_, w)| *w > 0.0)
                .map(|(v, _)| v)
                .collect();
            let extent = lit
                .iter()
                .map(|v| (v.position - centre).length() * (1.0 + 1e-5))
                .fold(0.0, f32::max);
            for k in 0..30 {
                let dir = anywhere(&mut rng);
                let far = [0.0, 0.5, 2.0, 10.0, 100.0][k % 5] * size;
                let a = facing.axis;
                // In the patch's plane (its floor's case), beneath it, or anywhere.
                let x = match k % 3 {
                    0 => centre + (dir - a * a.dot(dir)) * far,
                    1 => centre - a * far + (dir - a * a.dot(dir)) * far,
                    _ => centre + dir * far,
                };
                let d = (x - centre).length();
                if !facing.faces_away(x, d, extent) {
                    kept += 1;
                    continue;
                }
                let (n, slack) = facing.bound(x, d, extent);
                for v in &lit {
                    let to = x - v.position;
                    let r = to.length();
                    if r == 0.0 {
                        continue;
                    }
                    let lobe = v.lobe(to / r);
                    let grazing = if n < -slack {
                        0.0
                    } else {
                        2.0 * (slack / r + facing.tilt) + 1e-6
                    };
                    assert!(
                        lobe <= grazing,
                        "patch {patch} point {k}: {lobe} > {grazing}"
                    );
                }
                if n < -slack {
                    beneath += 1;
                } else {
                    edge_on += 1;
                }
            }
        }
        println!("{beneath} beneath, {edge_on} edge-on, {kept} kept of 60,000");
        assert!(
            beneath > 1000 && edge_on > 100 && kept > 10_000,
            "{beneath} {edge_on} {kept}"
        );
    }
}
