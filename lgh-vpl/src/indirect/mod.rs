//! Indirect light from virtual point lights, shaded with visibility (paper Sec. 6.4, Figs. 11,
//! 13): what a surface point receives from the VPLs a many-lights backend hands it.
//!
//! The hierarchy aggregates lights as isotropic points, so each VPL enters it as a point of the
//! isotropic intensity `Φ ρ / 2π` ([`point_lights`]): what carries its flux into the half-space
//! in front of its surface, where everything it lights is. Shading restores what the aggregation
//! lost where it can:
//!
//! - a level-0 light is the VPL itself: its cosine lobe is restored (the factor
//!   `2 max(0, n_v·ω)`, so its flux is unchanged) and one shadow ray through the BVH decides
//!   whether it is seen;
//! - a coarser light stands for many VPLs spread with variance `σ²` (eq. 4): it is a volume
//!   light, shaded as `k` points at `p + σ ⊙ g_j`, each with `1/k` of the intensity and a shadow
//!   ray of its own, where the `g_j` are standard-normal offsets drawn from a sequence seeded by
//!   the light's level and index — the same pattern for that light at every pixel and every
//!   frame, so the soft shadows do not flicker (Fig. 11d; `k = 0` shades it as a point, Fig. 11c).
//!   That is [`Coarse::Gaussian`], the paper's. Beyond the paper, [`Coarse::Representatives`]
//!   shades a coarse light through `k` of the VPLs it stands for instead
//!   ([`crate::representatives`]): on surfaces the Gaussian's samples fall inside walls and
//!   lose the lobes, and err by tens of percent where the representatives err by a few.
//!
//! Backends whose samples are the VPLs themselves — brute force, Lightcuts' representatives —
//! shade each sample as its VPL; the hierarchy shades its coarse lights as [`Coarse`] says, or
//! through [`NormalBuckets`]. The way in is [`crate::gi::GiScene`], which renders through each.
//!
//! Surfaces reflect physically: Lambert `ρ/π`, Phong `k_d/π + k_s (n+2)/2π (R·E)^n`. The VPL
//! singularity is clamped with the core's rule, `1 / max(d, h0)²`: a VPL closer than `h0` to the
//! point it lights gives what it would at `h0`, which drops the short-range part of the light
//! (the bright blotches of unclamped VPLs near corners).
//!
//! The shader is here; the normal buckets are in `buckets` and the strategies for coarse lights
//! in `coarse`, both re-exported here. The modules [`lobe`], [`refine`] and [`resample`] are
//! public, and their items are reached through them only (`indirect::lobe::Cone`).

mod adaptive;
mod buckets;
mod coarse;
pub mod lobe;
pub mod refine;
pub mod resample;
mod roulette;

pub use adaptive::{BlendAt, MIN_SHARE_WEIGHT};
pub(crate) use buckets::render_buckets;
pub use buckets::{BucketsAt, NormalBuckets};
pub(crate) use coarse::render_lgh;
pub use coarse::Coarse;
use lobe::Cone;
use refine::{Tally, WhichVpl};

use std::sync::atomic::{AtomicU64, Ordering};

use lgh_core::glam::Vec3;
use lgh_core::random::SplitMix64;
use lgh_core::{LightSample, ManyLights, PointLight, ShadingPoint};

use crate::brdf::brdf;
use crate::render::{render_with_shader, RenderError, Rendered};
use crate::scene::{in_front, shadow_origin, Scene};
use crate::vpl::Vpl;
use lgh_image::camera::Pinhole as Camera;

/// The hierarchy's input lights for `vpls`: each at its VPL's position with the isotropic
/// intensity `Φ ρ / 2π` that carries its cosine lobe's flux into the half-space in front of it.
#[must_use]
pub fn point_lights(vpls: &[Vpl]) -> Vec<PointLight> {
    vpls.iter()
        .map(|v| PointLight::new(v.position, isotropic_intensity(v)))
        .collect()
}

/// The isotropic intensity `Φ ρ / 2π` a VPL enters the hierarchy with ([`point_lights`]).
#[inline]
fn isotropic_intensity(v: &Vpl) -> Vec3 {
    v.power * v.albedo / (2.0 * std::f32::consts::PI)
}

/// How the VPLs are shaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IndirectSettings {
    /// The singularity clamp `h0`: distances below it count as `h0`.
    pub h0: f32,
    /// Gaussian shadow samples `k` of a coarse light shaded as the paper's volume light
    /// (Sec. 6.4, Fig. 11d): every coarse light with [`Coarse::Gaussian`] and the normal
    /// buckets without representatives, and a coarse light without representatives (one
    /// without weight) otherwise; 0 shades it as a point (Fig. 11c). The representatives'
    /// own numbers are theirs ([`crate::representatives::Allocation`],
    /// [`Coarse::Adaptive`]'s `mean`).
    pub gaussian_samples: u32,
    /// Offset of shadow rays from the surfaces they leave, against self-shadowing.
    pub epsilon: f32,
    /// Whether to trace shadow rays at all (false: every light is seen, as in Paquette et al.'s
    /// experiments; it separates the error of the volume lights' shadows from the rest).
    pub shadows: bool,
    /// The bound ε at which the hierarchy's glossy points are split ([`lobe`]), read by
    /// [`Coarse::Adaptive`] only: `None` shades every point through the hierarchy alone.
    pub lobe_error: Option<f32>,
    /// The bound ε on each point's error at which the hierarchy's adaptive shading
    /// ([`Coarse::Adaptive`], its only reader) takes more samples of the coarse lights
    /// ([`refine`]): `None` takes the mean everywhere.
    pub point_error: Option<f32>,
}

/// A coarse light as [`Indirect::shade_drawn`] shades its representatives.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Drawn<'a> {
    /// The luminance its representatives share: `‖B_ℓ(d) I_ℓi‖` blended at its centre, or
    /// `‖I_ℓi‖` with `blend`.
    pub(crate) luminance: f32,
    /// With each representative blended at its own distance: the blending and the light's
    /// level.
    pub(crate) blend: Option<(&'a lgh_core::Blending, u8)>,
}

impl Drawn<'_> {
    /// The isotropic intensity representative `v`, drawn `times` times, is shaded with at a
    /// point `d` from it, `scale` being the light's luminance over its draws: `I_j · scale ·
    /// times / ‖I_j‖`, times `B_ℓ(d)` blended at its own distance (the estimator of the drawn
    /// weights `w_j ‖I_j‖`: see [`Indirect::shade_drawn`]); zero for a dark VPL.
    #[inline]
    #[must_use]
    pub(crate) fn share(&self, v: &Vpl, d: f32, scale: f32, times: f32) -> Vec3 {
        let own = isotropic_intensity(v);
        let lum = lgh_core::luminance(own);
        match self.blend {
            _ if lum <= 0.0 => Vec3::ZERO,
            None => own * (scale * times / lum),
            Some((blending, level)) => {
                let b = blending.weight(level, d);
                own * (b * scale * times / lum)
            }
        }
    }
}

/// A shadow-ray counter on a cache line of its own.
#[derive(Default)]
#[repr(align(64))]
struct RayCount(AtomicU64);

/// Shades the VPLs of `vpls` at surface points of `scene`.
pub struct Indirect<'a> {
    scene: &'a Scene,
    vpls: &'a [Vpl],
    settings: IndirectSettings,
    /// Shadow rays traced so far, one counter per rayon worker (and a last one for any other
    /// thread): an atomic shared by every thread cost 13% of a render in contention.
    rays: Vec<RayCount>,
    /// Points where a bound took the shading deeper: their glossy lobe split ([`lobe`]) or
    /// their coarse lights shaded again ([`refine`]), each counted once.
    bounded: AtomicU64,
    /// Points whose glossy lobe was split ([`lobe`]).
    split: AtomicU64,
    /// Points whose coarse lights were shaded again with more samples ([`refine`]).
    refined: AtomicU64,
}

impl<'a> Indirect<'a> {
    /// A shader for `vpls` in `scene`.
    #[must_use]
    pub fn new(scene: &'a Scene, vpls: &'a [Vpl], settings: IndirectSettings) -> Self {
        Indirect {
            scene,
            vpls,
            settings,
            rays: (0..=rayon::current_num_threads())
                .map(|_| RayCount::default())
                .collect(),
            bounded: AtomicU64::new(0),
            split: AtomicU64::new(0),
            refined: AtomicU64::new(0),
        }
    }

    /// Shading points where a bound took the shading deeper so far: their glossy lobe split
    /// ([`lobe`]) or their coarse lights shaded again with more samples ([`refine`]).
    #[must_use]
    pub fn bounded_points(&self) -> u64 {
        self.bounded.load(Ordering::Relaxed)
    }

    /// Shading points whose glossy lobe was split so far ([`lobe`]).
    #[must_use]
    pub fn lobe_split_points(&self) -> u64 {
        self.split.load(Ordering::Relaxed)
    }

    /// Counts a shading point whose lobe was `split` and whose coarse lights were `refined`.
    fn count_bounded(&self, split: bool, refined: bool) {
        for (counter, yes) in [(&self.split, split), (&self.refined, refined)] {
            if yes {
                counter.fetch_add(1, Ordering::Relaxed);
            }
        }
        if split || refined {
            self.bounded.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Shading points whose coarse lights were shaded again with more samples so far
    /// ([`refine`]).
    #[must_use]
    pub fn refined_points(&self) -> u64 {
        self.refined.load(Ordering::Relaxed)
    }

    /// Shadow rays this shader has traced.
    #[must_use]
    pub fn shadow_rays(&self) -> u64 {
        self.rays.iter().map(|c| c.0.load(Ordering::Relaxed)).sum()
    }

    /// Counts one shadow ray on the calling thread's counter.
    #[inline]
    fn count_ray(&self) {
        let last = self.rays.len() - 1;
        match rayon::current_thread_index().filter(|&i| i < last) {
            // Only this worker writes its counter: a plain load and store, no locked add.
            Some(i) => {
                let c = &self.rays[i].0;
                c.store(c.load(Ordering::Relaxed) + 1, Ordering::Relaxed);
            }
            None => {
                self.rays[last].0.fetch_add(1, Ordering::Relaxed);
            }
        }
    }

    /// The radiance `light` sends towards the viewer from `point`, visibility included. `vpl`
    /// is the index in the VPL slice of a level-0 light (a backend's own index for brute force,
    /// `LightingGridHierarchy::input_index` for the hierarchy); coarser lights ignore it.
    #[must_use]
    pub fn shade(&self, point: &ShadingPoint, light: &LightSample, vpl: Option<usize>) -> Vec3 {
        self.shade_oriented(point, light, vpl, None)
    }

    /// [`shade`](Self::shade), with the coarse light emitting the cosine lobe about `lobe` (the
    /// mean normal of the VPLs it stands for, [`NormalBuckets`]) instead of isotropically.
    #[must_use]
    pub fn shade_oriented(
        &self,
        point: &ShadingPoint,
        light: &LightSample,
        vpl: Option<usize>,
        lobe: Option<Vec3>,
    ) -> Vec3 {
        let Some(normal) = point.normal else {
            return Vec3::ZERO;
        };
        let from = shadow_origin(point, normal, self.settings.epsilon);
        let facing = |q: Vec3| facing(point, normal, q);
        let occluded = |to: Vec3| self.occluded(from, to);
        if light.level == 0 {
            let Some(v) = vpl.and_then(|i| self.vpls.get(i)) else {
                return Vec3::ZERO;
            };
            return self.shade_vpl(point, normal, v, light.intensity);
        }
        // The coarse light's own lobe, if it has one: 2 max(0, n̄·ω) towards the point.
        let toward = |q: Vec3| match lobe {
            Some(n) => 2.0 * n.dot((point.position - q).normalize_or_zero()).max(0.0),
            None => 1.0,
        };
        let k = self.settings.gaussian_samples;
        if k == 0 || light.variance == Vec3::ZERO {
            if !facing(light.position) || occluded(light.position) {
                return Vec3::ZERO;
            }
            let f = toward(light.position);
            return self.reflect(point, normal, light.position, light.intensity * f);
        }
        let sigma = light.variance.max(Vec3::ZERO).map(f32::sqrt);
        let mut rng = SplitMix64(SplitMix64::mix(
            (u64::from(light.level) << 32) | u64::from(light.index),
        ));
        let share = light.intensity / k as f32;
        let mut sum = Vec3::ZERO;
        for _ in 0..k {
            let mut offset = sigma * gaussian3(&mut rng);
            if let Some(n) = lobe {
                // In front of the surfaces the light stands for: mirrored to the lobe's side,
                // and lifted off the surface as a VPL's own shadow ray is.
                let behind = offset.dot(n).min(0.0);
                offset += n * (self.settings.epsilon - 2.0 * behind);
            }
            let q = light.position + offset;
            let f = toward(q);
            if f > 0.0 && facing(q) && !occluded(q) {
                sum += self.reflect(point, normal, q, share * f);
            }
        }
        sum
    }

    /// A coarse light shaded through its `k` representative VPLs `reps` (indices into this
    /// shader's VPLs; [`Representatives`](crate::representatives::Representatives)), drawn in
    /// proportion to `w_j ‖I_j‖`: each one shaded as at level 0 — its cosine lobe, its shadow
    /// ray — with the intensity `I_j ‖B I_ℓi‖ / (k ‖I_j‖)`, its own colour at the share of the
    /// light's blended luminance it was drawn for (so the estimate of `Σ_j w_j I_j (…)` is
    /// unbiased in every channel).
    /// A VPL drawn `m` times is shaded once, `m` times as bright: one shadow ray. With no
    /// representatives, [`shade`](Self::shade).
    #[must_use]
    pub fn shade_representatives(
        &self,
        point: &ShadingPoint,
        light: &LightSample,
        reps: impl ExactSizeIterator<Item = usize>,
    ) -> Vec3 {
        self.shade_representatives_tallied(point, light, reps, &mut Tally::default())
    }

    /// [`shade_representatives`](Self::shade_representatives), each representative's share
    /// also added to `tally` (unshadowed and shadowed), from which the estimate's variance is
    /// estimated ([`refine`]).
    pub(crate) fn shade_representatives_tallied(
        &self,
        point: &ShadingPoint,
        light: &LightSample,
        reps: impl ExactSizeIterator<Item = usize>,
        tally: &mut Tally,
    ) -> Vec3 {
        let (Some(normal), k) = (point.normal, reps.len()) else {
            return Vec3::ZERO;
        };
        if k == 0 || light.level == 0 {
            return self.shade(point, light, None);
        }
        let light = Drawn {
            luminance: lgh_core::luminance(light.intensity),
            blend: None,
        };
        self.shade_drawn(point, normal, light, reps, tally)
    }

    /// The representatives `reps` (`k ≥ 1` of them, repeats allowed) of a coarse light
    /// described by `light` shaded at `point` (unit shading `normal`): see
    /// [`shade_representatives`](Self::shade_representatives); each share also added to
    /// `tally`.
    pub(crate) fn shade_drawn(
        &self,
        point: &ShadingPoint,
        normal: Vec3,
        light: Drawn<'_>,
        reps: impl ExactSizeIterator<Item = usize>,
        tally: &mut Tally,
    ) -> Vec3 {
        let k = reps.len();
        // Pick j carries its own colour: I_j · ‖B I_ℓ‖ / (k ‖I_j‖), the estimator of the drawn
        // weights w_j ‖I_j‖ (unbiased per channel, not only in luminance); blended at its own
        // distance, I_j · B_ℓ(‖x − p_j‖) ‖I_ℓ‖ / (k ‖I_j‖).
        let scale = light.luminance / k.max(1) as f32;
        let mut shade = |i: usize, times: usize| {
            let Some(v) = self.vpls.get(i) else {
                return Vec3::ZERO;
            };
            let unshadowed = self.unshadowed_drawn(point, normal, light, v, scale, times as f32);
            let lit = self.shadowed(point, normal, v, unshadowed);
            tally.add(times as u32, unshadowed, lit);
            lit
        };
        let mut reps = reps;
        if k == 1 {
            return reps.next().map_or(Vec3::ZERO, |i| shade(i, 1));
        }
        // Repeated picks (a heavy VPL drawn twice) share one shadow ray: sorted, each run once
        // with its multiplicity.
        let mut small = [0usize; 16];
        let mut large = Vec::new();
        let ids: &mut [usize] = if k <= small.len() {
            for (slot, i) in small.iter_mut().zip(reps) {
                *slot = i;
            }
            &mut small[..k]
        } else {
            large.extend(reps);
            &mut large
        };
        ids.sort_unstable();
        ids.chunk_by(|a, b| a == b)
            .map(|run| shade(run[0], run.len()))
            .sum()
    }

    /// VPL `v` with the isotropic intensity `intensity` shaded at `point` (unit `normal`): its
    /// cosine lobe restored (`2 max(0, n_v·ω)`, the flux unchanged) and one shadow ray.
    fn shade_vpl(&self, point: &ShadingPoint, normal: Vec3, v: &Vpl, intensity: Vec3) -> Vec3 {
        let lit = self.unshadowed(point, normal, v, intensity);
        self.shadowed(point, normal, v, lit)
    }

    /// `unshadowed`, the light VPL `v` gives `point` (unit `normal`), through one shadow ray:
    /// a ray only where there is light to hide.
    fn shadowed(&self, point: &ShadingPoint, normal: Vec3, v: &Vpl, unshadowed: Vec3) -> Vec3 {
        if unshadowed == Vec3::ZERO || self.visible(point, normal, v) {
            unshadowed
        } else {
            Vec3::ZERO
        }
    }

    /// What representative `v` of `light`, drawn `times` times, gives `point` (unit
    /// `normal`) unshadowed, `scale` being the light's luminance over its draws: its
    /// [`Drawn::share`] shaded by its lobe, the BRDF and the fall-off, tested for facing first.
    pub(crate) fn unshadowed_drawn(
        &self,
        point: &ShadingPoint,
        normal: Vec3,
        light: Drawn<'_>,
        v: &Vpl,
        scale: f32,
        times: f32,
    ) -> Vec3 {
        // Facing first: most representatives a point looks at face away from it, and their
        // share is never needed.
        let Some((lobe, d)) = self.lobe_towards(point, normal, v) else {
            return Vec3::ZERO;
        };
        let share = light.share(v, d, scale, times);
        if share == Vec3::ZERO {
            return Vec3::ZERO;
        }
        self.reflect(point, normal, v.position, share * lobe)
    }

    /// Whether VPL `v` is seen from `point` (unit shading `normal`): one shadow ray between
    /// the two surfaces, each end offset from its own by ε (always, without shadows).
    fn visible(&self, point: &ShadingPoint, normal: Vec3, v: &Vpl) -> bool {
        let from = shadow_origin(point, normal, self.settings.epsilon);
        let source = v.position + v.geometric * self.settings.epsilon;
        !self.occluded(from, source)
    }

    /// What VPL `v` with isotropic-equivalent intensity `intensity` (its lobe `2 max(0, n·ω)`
    /// in front of its face towards `ω`, [`Vpl::lobe`]) gives `point` (unit `normal`),
    /// unshadowed.
    fn unshadowed(&self, point: &ShadingPoint, normal: Vec3, v: &Vpl, intensity: Vec3) -> Vec3 {
        match self.lobe_towards(point, normal, v) {
            Some((lobe, _)) => self.reflect(point, normal, v.position, intensity * lobe),
            None => Vec3::ZERO,
        }
    }

    /// VPL `v`'s lobe towards `point` (unit `normal`) and its distance from it; `None` where
    /// it gives the point nothing: at the point itself, the point behind its face, or it
    /// behind the point's ([`facing`]).
    #[inline]
    fn lobe_towards(&self, point: &ShadingPoint, normal: Vec3, v: &Vpl) -> Option<(f32, f32)> {
        let to_point = point.position - v.position;
        let d = to_point.length();
        if d == 0.0 {
            return None;
        }
        let lobe = v.lobe(to_point / d);
        (lobe != 0.0 && facing(point, normal, v.position)).then_some((lobe, d))
    }

    /// Whether the mesh hides `to` from `from` (never, without shadows): one counted ray.
    fn occluded(&self, from: Vec3, to: Vec3) -> bool {
        if !self.settings.shadows {
            return false;
        }
        self.count_ray();
        self.scene.occluded(from, to)
    }

    /// Radiance reflected towards the viewer at `point` (unit `normal`) from a point light of
    /// intensity `intensity` at `light`, with the clamped fall-off.
    fn reflect(&self, point: &ShadingPoint, normal: Vec3, light: Vec3, intensity: Vec3) -> Vec3 {
        let to_light = light - point.position;
        let d = to_light.length();
        if d == 0.0 {
            return Vec3::ZERO;
        }
        let l = to_light / d;
        let cos = normal.dot(l);
        if cos <= 0.0 {
            return Vec3::ZERO;
        }
        let brdf = brdf(point, normal, l);
        brdf * intensity * (cos * lgh_core::falloff(d, self.settings.h0))
    }
}

/// Whether `q` is in front of the surface at `point` (unit shading `normal`): a light behind
/// its shading plane gives nothing (`reflect` says so too), one behind its geometric plane is
/// hidden by the surface itself ([`in_front`]); tested first to spare its shadow ray.
#[inline]
fn facing(point: &ShadingPoint, normal: Vec3, q: Vec3) -> bool {
    in_front(point, normal, q - point.position)
}

/// The indirect light `shader` gives each pixel through a backend over [`point_lights`] of
/// the VPLs (in order) whose samples are those input lights: [`lgh_core::BruteForce`], every VPL, the
/// exact answer of the same model; or Lightcuts ([`lgh_core::LightcutsBackend`]), each
/// cluster of its cut shaded as its representative VPL — that VPL's lobe and shadow ray — with
/// the cluster's intensity, as Walter et al. shade a cut. (Lightcuts' error bound does not
/// include the VPLs' lobes, up to 2: a cluster's bound can be up to twice too low.)
///
/// Errors: as [`render_lgh`].
pub(crate) fn render_input_lights<B: ManyLights + Sync>(
    scene: &Scene,
    camera: &Camera,
    backend: &B,
    shader: &Indirect<'_>,
    progress: impl Fn(usize) + Sync,
) -> Result<Rendered, RenderError> {
    let shade = |p: &ShadingPoint, s: &LightSample| shader.shade(p, s, Some(s.index as usize));
    render_with_shader(scene, camera, backend, shade, progress)
}

/// Three independent standard-normal numbers (Box–Muller).
fn gaussian3(rng: &mut SplitMix64) -> Vec3 {
    let mut pair = || {
        let u = 1.0 - rng.next_f32(); // (0, 1]
        let v = rng.next_f32();
        let r = (-2.0 * u.ln()).sqrt();
        let t = std::f32::consts::TAU * v;
        (r * t.cos(), r * t.sin())
    };
    let (a, b) = pair();
    let (c, _) = pair();
    Vec3::new(a, b, c)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use crate::primary::PrimaryLight;
    use crate::vpl::{trace, VplSettings};
    use lgh_core::{BruteForce, GridSettings, LghBackend, LightingGridHierarchy, Material};
    /// A room: floor, back wall and left wall of a 2-unit box, and a block on the floor that
    /// casts shadows.
    pub(crate) fn room_mesh() -> Mesh {
        let grey = Material::Lambert {
            albedo: Vec3::splat(0.7),
        };
        let red = Material::Lambert {
            albedo: Vec3::new(0.7, 0.1, 0.1),
        };
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let mut mesh = Mesh::quad(
            [
                v(-1., 0., 1.),
                v(1., 0., 1.),
                v(1., 0., -1.),
                v(-1., 0., -1.),
            ],
            grey,
        )
        .unwrap();
        mesh.append(
            Mesh::quad(
                [
                    v(-1., 0., -1.),
                    v(1., 0., -1.),
                    v(1., 2., -1.),
                    v(-1., 2., -1.),
                ],
                grey,
            )
            .unwrap(),
        )
        .unwrap();
        mesh.append(
            Mesh::quad(
                [
                    v(-1., 0., 1.),
                    v(-1., 0., -1.),
                    v(-1., 2., -1.),
                    v(-1., 2., 1.),
                ],
                red,
            )
            .unwrap(),
        )
        .unwrap();
        mesh.append(Mesh::cuboid(v(0.1, 0.0, -0.4), v(0.6, 0.8, 0.1), grey).unwrap())
            .unwrap();
        mesh
    }

    /// The room's lamp, near the ceiling.
    pub(crate) fn lamp() -> PrimaryLight {
        PrimaryLight::Point {
            position: Vec3::new(-0.3, 1.8, 0.3),
            intensity: Vec3::splat(2.0),
        }
    }

    /// The room, lit by its lamp's 4,000 VPLs.
    fn room() -> (Scene, Vec<Vpl>) {
        let scene = Scene::new(room_mesh());
        let settings = VplSettings {
            count: 4000,
            max_bounces: 2,
            seed: 4,
        };
        let vpls = trace(&scene, &[lamp()], &settings).unwrap().vpls;
        (scene, vpls)
    }

    /// The room's VPLs, their point lights and single hierarchy, and the shading settings.
    pub(crate) struct Fixture {
        pub(super) scene: Scene,
        pub(super) vpls: Vec<Vpl>,
        lights: Vec<PointLight>,
        pub(super) lgh: LightingGridHierarchy,
    }

    impl Fixture {
        pub(super) fn new() -> Fixture {
            let (scene, vpls) = room();
            let lights = point_lights(&vpls);
            let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
            Fixture {
                scene,
                vpls,
                lights,
                lgh,
            }
        }

        pub(super) fn shader(&self) -> Indirect<'_> {
            let settings = IndirectSettings {
                h0: self.lgh.h0(),
                gaussian_samples: 9,
                epsilon: 1e-4,
                shadows: true,
                lobe_error: None,
                point_error: None,
            };
            Indirect::new(&self.scene, &self.vpls, settings)
        }

        /// [`shader`](Self::shader) without shadow rays.
        pub(super) fn unshadowed_shader(&self) -> Indirect<'_> {
            let settings = IndirectSettings {
                shadows: false,
                ..self.shader().settings
            };
            Indirect::new(&self.scene, &self.vpls, settings)
        }

        /// The surface points the room's camera ([`camera`](Self::camera)`(w, h)`) sees, row by
        /// row, each with its unit shading normal.
        pub(crate) fn seen(&self, w: usize, h: usize) -> Vec<(ShadingPoint, Vec3)> {
            let camera = Self::camera(w, h);
            (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .filter_map(|(px, py)| {
                    let (origin, dir) = camera.ray(px, py);
                    let (point, _) = self.scene.trace(origin, dir)?;
                    let normal = point.normal?;
                    Some((point, normal))
                })
                .collect()
        }

        /// The room from the front, `w × h`.
        pub(crate) fn camera(w: usize, h: usize) -> Camera {
            let (eye, target) = (Vec3::new(0.4, 1.2, 3.0), Vec3::new(0.0, 0.6, 0.0));
            Camera::new(eye, target, Vec3::Y, 50.0, w, h).unwrap()
        }

        /// Brute force over every VPL: the reference.
        pub(super) fn exact(&self, shader: &Indirect<'_>, camera: &Camera) -> Rendered {
            let brute = BruteForce::new(&self.lights).unwrap();
            render_input_lights(&self.scene, camera, &brute, shader, |_| {}).unwrap()
        }

        pub(super) fn isotropic(
            &self,
            shader: &Indirect<'_>,
            camera: &Camera,
            alpha: f32,
        ) -> Rendered {
            let backend = LghBackend::new(&self.lgh, alpha).unwrap();
            render_lgh(
                &self.scene,
                camera,
                &backend,
                Coarse::Gaussian,
                shader,
                |_| {},
            )
            .unwrap()
        }
    }

    /// The sum of every pixel's channels: the image's light, whose ratio compares two
    /// renders' means.
    pub(super) fn light_sum(r: &Rendered) -> f64 {
        r.image
            .pixels
            .iter()
            .map(|p| f64::from(p.element_sum()))
            .sum()
    }

    /// A pool of `n` threads.
    pub(super) fn pool(n: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    }

    pub(super) fn rel_rmse(a: &Rendered, r: &Rendered) -> f64 {
        lgh_image::compare(&a.image, &r.image).unwrap().rel_rmse
    }

    /// With α so large that every VPL is inside level 0's influence region, the hierarchy
    /// hands each point every VPL at full weight: its image equals brute force over every VPL
    /// with the same shadow rays and shading, up to the order of the sums (tolerance 10⁻⁵).
    /// (At α = 1, 4, 16 the isotropic aggregation errs by tens of percent here, the normal
    /// buckets by 28%, 1.7% and 0.6%: `normal_buckets_beat_isotropic_aggregation`.)
    #[test]
    fn the_hierarchy_equals_brute_force_when_every_vpl_is_level_0() {
        let f = Fixture::new();
        let (shader, camera) = (f.shader(), Fixture::camera(24, 18));
        let exact = f.exact(&shader, &camera);
        let got = f.isotropic(&shader, &camera, 256.0);
        assert_eq!(got.mean_lights(), f.vpls.len() as f64);
        let e = rel_rmse(&got, &exact);
        assert!(e < 1e-5, "{e}");
        assert!(exact.image.pixels.iter().any(|p| p.x > 0.0));
    }

    /// A VPL lights only the side its normal faces, and a wall between hides it.
    #[test]
    fn a_vpl_lights_its_front_and_is_hidden_by_walls() {
        let grey = Material::Lambert {
            albedo: Vec3::splat(0.5),
        };
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let wall = Mesh::quad(
            [
                v(-1., 0.5, -1.),
                v(1., 0.5, -1.),
                v(1., 0.5, 1.),
                v(-1., 0.5, 1.),
            ],
            grey,
        )
        .unwrap();
        let scene = Scene::new(wall);
        let vpl = Vpl {
            position: Vec3::new(0.0, 1.0, 0.0),
            normal: Vec3::NEG_Y,
            geometric: Vec3::NEG_Y,
            power: Vec3::ONE,
            albedo: Vec3::ONE,
            bounce: 1,
        };
        let lights = point_lights(&[vpl]);
        let settings = IndirectSettings {
            h0: 0.01,
            gaussian_samples: 9,
            epsilon: 1e-4,
            shadows: true,
            lobe_error: None,
            point_error: None,
        };
        let shader = Indirect::new(&scene, std::slice::from_ref(&vpl), settings);
        let at = |y: f32, n: Vec3| ShadingPoint {
            position: Vec3::new(0.2, y, 0.0),
            normal: Some(n),
            geometric: None,
            view: Some(n),
            material: grey,
        };
        let sample = |x: Vec3| {
            LightSample::point(
                0,
                lights[0].position,
                lights[0].intensity,
                x,
                lgh_core::Lobe::All,
            )
        };
        // Facing the VPL, below it, above the wall: lit.
        let lit = at(0.75, Vec3::Y);
        assert!(shader.shade(&lit, &sample(lit.position), Some(0)).x > 0.0);
        // Below the wall: hidden.
        let hidden = at(0.25, Vec3::Y);
        assert_eq!(
            shader.shade(&hidden, &sample(hidden.position), Some(0)),
            Vec3::ZERO
        );
        // Above the VPL, behind its lobe: dark.
        let behind = at(1.5, Vec3::NEG_Y);
        assert_eq!(
            shader.shade(&behind, &sample(behind.position), Some(0)),
            Vec3::ZERO
        );
    }
}
