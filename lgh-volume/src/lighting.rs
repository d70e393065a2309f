//! The light arriving at one shading point: the paper's eq. (1),
//! `L(x) = Σ_ℓ Σ_i V(x, p_ℓi) g(d) B_ℓ(d) I_ℓi`, with the lights a many-lights backend selects
//! and the visibility of [`crate::shadow`] (ARCHITECTURE.md, "lgh-volume").
//!
//! [`Lights::incident`] is the one per-point lighting function of the crate: the ray marcher
//! calls it at every scattering step, and so will the multiple-scattering pass (the fluence at a
//! voxel) and surface shading (with a BRDF as the response). The core never computes `V`
//! (ARCHITECTURE.md, "lgh-core"); this is where it is applied.

use lgh_core::glam::Vec3;
use lgh_core::{
    falloff, LightSample, ManyLights, NearField, QueryError, ShadingPoint, ISOTROPIC_PHASE,
};

use crate::shadow::{ShadowQuery, Visibility};
use crate::voxel_smoke::LightSmoke;

/// The lights a renderer shades with: a many-lights backend and the fall-off `g` of the light
/// model: `g(d) = 1 / max(d, h0)²` for a point light (the paper's Sec. 6, ARCHITECTURE.md "From a
/// VDB file to an EXR", step 3; for explosions `h0` is the voxel size), and for a voxel light
/// seen from a point in a medium the voxel's mean of `1/r²` ([`NearField`],
/// [`lgh_core::near_field`]).
#[derive(Clone, Debug)]
pub struct Lights<B> {
    /// The many-lights method.
    pub backend: B,
    /// `h0`: where the inverse-square fall-off is clamped, and the side of a voxel light.
    pub h0: f32,
    /// Whether the level-0 lights are points ([`NearField::Clamp`], what [`new`](Self::new)
    /// makes) or voxels ([`NearField::Voxel`], what an explosion's lights are by default).
    pub near_field: NearField,
    /// The smoke in each voxel light's own voxel, by the light's index in `backend`, which sets
    /// the escape of its light ([`with_smoke`](Self::with_smoke)); `None`: the smoke at the
    /// shading point.
    pub smoke: Option<LightSmoke>,
}

impl<B: ManyLights> Lights<B> {
    /// `backend`'s lights with the fall-off clamped at `h0`.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::lgh_core::{BruteForce, PointLight, ShadingPoint};
    /// use lgh_volume::lighting::{LightScratch, Lights};
    /// use lgh_volume::render::RenderStats;
    /// use lgh_volume::shadow::Visibility;
    ///
    /// let one = BruteForce::new(&[PointLight::new(Vec3::ZERO, Vec3::splat(4.0))])?;
    /// let lights = Lights::new(one, 0.1);
    /// let at = ShadingPoint::in_medium(Vec3::new(2.0, 0.0, 0.0));
    /// let (mut scratch, mut stats) = (LightScratch::default(), RenderStats::default());
    /// let l = lights.incident(&at, &Visibility::None, |_| Vec3::ONE, &mut scratch, &mut stats)?;
    /// assert_eq!(l, Vec3::splat(1.0)); // I / d² = 4 / 2²
    /// assert_eq!((stats.shading_points, stats.lights_evaluated), (1, 1));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn new(backend: B, h0: f32) -> Self {
        Lights {
            backend,
            h0,
            near_field: NearField::Clamp,
            smoke: None,
        }
    }

    /// The same lights with the level-0 lights' near field `near_field`: with
    /// [`NearField::Voxel`], a level-0 light at distance `d` from a point in a medium gives
    /// `I · G(d)`, the mean of `1/r²` over a voxel of side `h0` (`7.674/h0²` at its centre),
    /// instead of `I / max(d, h0)²`. Surfaces and coarse lights keep the point's fall-off.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::lgh_core::{BruteForce, NearField, PointLight, ShadingPoint};
    /// use lgh_volume::lighting::{LightScratch, Lights};
    /// use lgh_volume::render::RenderStats;
    /// use lgh_volume::shadow::Visibility;
    ///
    /// let one = BruteForce::new(&[PointLight::new(Vec3::ZERO, Vec3::ONE)])?;
    /// let h = 0.5;
    /// let (mut scratch, mut stats) = (LightScratch::default(), RenderStats::default());
    /// let mut at_centre = |lights: &Lights<BruteForce>| {
    ///     let p = ShadingPoint::in_medium(Vec3::ZERO);
    ///     lights.incident(&p, &Visibility::None, |_| Vec3::ONE, &mut scratch, &mut stats)
    /// };
    /// let point = at_centre(&Lights::new(one.clone(), h))?;
    /// let voxel = at_centre(&Lights::new(one, h).with_near_field(NearField::Voxel))?;
    /// assert_eq!(point.x * h * h, 1.0); // clamped: 1/h²
    /// assert!((voxel.x * h * h - 7.674).abs() < 1e-3); // the voxel's mean of 1/r²
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn with_near_field(mut self, near_field: NearField) -> Self {
        self.near_field = near_field;
        self
    }

    /// The same lights with the smoke of each voxel light's own voxel, listed by the lights'
    /// index in the backend (`crate::voxel_smoke`, [`VoxelSmoke::of_lights`](crate::voxel_smoke::VoxelSmoke::of_lights)): a
    /// voxel light in a medium is shaded with the [`escape`](lgh_core::near_field::escape) of
    /// its light through smoke of its own voxel's optical depth or the shading point's, the
    /// thinner. Without it (`None`, what [`new`](Self::new) makes), through the smoke at the
    /// shading point: the same in uniform smoke, and an over-count where a point in dense smoke
    /// sees a light in thin smoke. (The thinner of the two, not the light's alone: across a
    /// steep edge of smoke the shadow ray to a dense voxel's centre crosses less of its smoke
    /// than the uniform voxel's half, which the escape already makes up for: with the light's
    /// alone, the demo's explosion at 32³, 4.7 optical depths a voxel of soot, gave each depth
    /// up to 0.77 of the one before, above its albedo of 0.75; with the thinner, 0.753 at depth
    /// 16 — the direction-averaged kernel still over-counts a face neighbour's light at a
    /// voxel's centre there, by 1/0.63.)
    ///
    /// ```
    /// use lgh_volume::grid::DenseGrid;
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::lgh_core::{BruteForce, NearField, PointLight};
    /// use lgh_volume::lighting::{LightScratch, Lights};
    /// use lgh_volume::render::RenderStats;
    /// use lgh_volume::shadow::Visibility;
    /// use lgh_volume::voxel_smoke::VoxelSmoke;
    /// use lgh_volume::Medium;
    ///
    /// let h = 0.5;
    /// let clear = DenseGrid::zeros([4, 4, 4], h, Vec3::ZERO); // the light's voxel: no smoke
    /// let medium = Medium::new(1.0, 3.0, 1e-4, 1000.0)?;
    /// let at = clear.centre(1, 1, 1);
    /// let one = BruteForce::new(&[PointLight::new(at, Vec3::ONE)])?;
    /// let voxel = Lights::new(one, h).with_near_field(NearField::Voxel);
    /// let smoke = VoxelSmoke::of(&clear, &clear, &medium).of_lights([at]); // light 0's voxel
    /// let own = voxel.clone().with_smoke(Some(smoke));
    /// let (mut scratch, mut stats) = (LightScratch::default(), RenderStats::default());
    /// let x = clear.centre(2, 1, 1); // a voxel over, in smoke of σ_t = 4 (τ = 2)
    /// let none = &Visibility::None;
    /// let mut at = |l: &Lights<BruteForce>| l.in_scattered(x, 1.0, 4.0, none, &mut scratch, &mut stats);
    /// let (own, point) = (at(&own)?, at(&voxel)?);
    /// assert!(point.x > 1.3 * own.x); // the point's dense smoke taken for the light's
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn with_smoke(mut self, smoke: Option<LightSmoke>) -> Self {
        self.smoke = smoke;
        self
    }

    /// `backend` with these lights' fall-off (`h0` and near field): the same light model over
    /// another selection of the lights (some levels of a hierarchy, say).
    #[must_use]
    pub(crate) fn with_backend<C: ManyLights>(&self, backend: C) -> Lights<C> {
        Lights {
            backend,
            h0: self.h0,
            near_field: self.near_field,
            smoke: self.smoke.clone(),
        }
    }

    /// The fall-off the lights are shaded with at `point`, where the extinction is `sigma_t`:
    /// [`NearField::falloff_in`] in a medium, with the [`escape`](lgh_core::near_field::escape)
    /// of voxel lights' light through their own voxel's smoke ([`with_smoke`](Self::with_smoke);
    /// without it, the point's) and their near field centred where their cell emits
    /// (`crate::voxel_light`, "The near field's centre"; the shadow ray still ends at the
    /// light's position), a point's `1/max(d, h0)²` on a surface.
    #[inline(always)]
    fn falloff_at(&self, point: &ShadingPoint, sigma_t: f32) -> impl Fn(&LightSample) -> f32 + '_ {
        let (h0, near_field) = (self.h0, self.near_field);
        let medium = point.normal.is_none();
        let smoke = self.smoke.as_ref();
        let here = sigma_t * h0;
        let x = point.position;
        move |l: &LightSample| {
            if medium {
                // Only a level-0 voxel light reads its voxel's smoke (`falloff_in`); the
                // thinner of its voxel's and the point's (`with_smoke`). Its near field is
                // centred at its cell's emission centroid (`crate::voxel_light`).
                let (tau, d) = match smoke {
                    Some(s) if l.level == 0 && near_field == NearField::Voxel => {
                        let c = s.centroid_of(l.index);
                        let d = if c == Vec3::ZERO {
                            l.distance
                        } else {
                            (x - (l.position + c)).length()
                        };
                        (s.of_light(l.index).min(here), d)
                    }
                    Some(_) => (0.0, l.distance),
                    None => (here, l.distance),
                };
                near_field.falloff_in(l.level, d, h0, tau)
            } else {
                falloff(l.distance, h0)
            }
        }
    }

    /// `Σ_lights f(light) · I · g(d) · V(x, light)` at `point`: every light the backend selects
    /// (its intensity already weighted by `B_ℓ(d)`), times `response(light)` — the phase
    /// function or BRDF × cosine towards it, `Vec3::ONE` for the bare incident light — times the
    /// fall-off `g` ([`with_near_field`](Self::with_near_field); at a point in a medium, voxel
    /// lights' near field as in clear air: [`in_scattered`](Self::in_scattered) takes the
    /// smoke's extinction, through which their light escapes), times the visibility `V`.
    /// Counted into `stats`;
    /// `scratch` holds the lights while their visibility is evaluated together, and is reused
    /// from call to call.
    ///
    /// Each term is `(I · f) · (g · V)`, summed in the backend's order, whatever the visibility
    /// (`V = 1` without shadows, where `g · 1 = g` exactly): the same bits whether `V` is evaluated per light or for all
    /// lights at once.
    pub fn incident(
        &self,
        point: &ShadingPoint,
        visibility: &Visibility,
        response: impl FnMut(&LightSample) -> Vec3,
        scratch: &mut LightScratch,
        stats: &mut crate::stats::RenderStats,
    ) -> Result<Vec3, QueryError> {
        self.incident_in(point, 0.0, visibility, response, scratch, stats)
    }

    /// [`incident`](Self::incident) at a point in a medium whose extinction is `sigma_t`, which
    /// sets the escape of voxel lights' light through the smoke
    /// ([`escape`](lgh_core::near_field::escape); 0: clear air).
    fn incident_in(
        &self,
        point: &ShadingPoint,
        sigma_t: f32,
        visibility: &Visibility,
        mut response: impl FnMut(&LightSample) -> Vec3,
        scratch: &mut LightScratch,
        stats: &mut crate::stats::RenderStats,
    ) -> Result<Vec3, QueryError> {
        let g = self.falloff_at(point, sigma_t);
        let term = |l: &LightSample, f: Vec3, v: f32| (l.intensity * f) * (g(l) * v);
        if visibility.is_none() {
            let sum = self
                .backend
                .illuminate(point, &mut |l: &LightSample| term(l, response(l), 1.0))?;
            stats.shading_points += 1;
            stats.lights_evaluated += u64::from(sum.lights);
            return Ok(sum.radiance);
        }
        if self.backend.selection_follows_shader() {
            // Lightcuts: each light's visibility when it is shaded, one shadow ray at a time.
            let mut samples = 0;
            let sum = self.backend.illuminate(point, &mut |l: &LightSample| {
                scratch.lights.clear();
                scratch.lights.push(l);
                samples += visibility.transmittances(
                    point.position,
                    &scratch.lights,
                    &mut scratch.visibility,
                );
                term(l, response(l), scratch.visibility[0])
            })?;
            stats.shading_points += 1;
            stats.lights_evaluated += u64::from(sum.lights);
            stats.shadow_samples += samples;
            return Ok(sum.radiance);
        }
        self.gather(point, sigma_t, visibility, response, scratch, stats)?;
        // Summed in the backend's order, as the backend sums what a shader returns.
        let mut radiance = Vec3::ZERO;
        for (&(weighted, g, _), &v) in scratch.unshadowed.iter().zip(&scratch.visibility) {
            radiance += weighted * (g * v);
        }
        Ok(radiance)
    }

    /// The lights `point` sees, gathered into `scratch` with their unshadowed terms, then their
    /// visibility evaluated together (shadow rays eight abreast).
    fn gather(
        &self,
        point: &ShadingPoint,
        sigma_t: f32,
        visibility: &Visibility,
        mut response: impl FnMut(&LightSample) -> Vec3,
        scratch: &mut LightScratch,
        stats: &mut crate::stats::RenderStats,
    ) -> Result<(), QueryError> {
        let g = self.falloff_at(point, sigma_t);
        scratch.lights.clear();
        scratch.unshadowed.clear();
        let sum = self.backend.illuminate(point, &mut |l: &LightSample| {
            scratch.lights.push(l);
            scratch
                .unshadowed
                .push((l.intensity * response(l), g(l), l.distance));
            Vec3::ZERO
        })?;
        stats.shading_points += 1;
        stats.lights_evaluated += u64::from(sum.lights);
        stats.shadow_samples +=
            visibility.transmittances(point.position, &scratch.lights, &mut scratch.visibility);
        Ok(())
    }

    /// The [`incident`](Self::incident) light at `x` from every direction (the bare light,
    /// `f = 1`), the same lights unshadowed (`V = 1`), their far part
    /// `Σ_j far(d_j) I_j g_j` (`d_j` light `j`'s distance; 0 without `far`) and its light
    /// `Σ_j far(d_j) I_j g_j V_j`, and the flux vector
    /// `F = Σ_j lum(I_j g_j V_j) ω_j`, with `ω_j` the unit direction from light `j` to `x`: what
    /// the lighting cache needs to follow a shadow's gradient (`∇_x τ_j ≈ σ_t(x) ω_j`, so
    /// `∇L ≈ −σ_t F`) and to keep level 0 as a ratio (`lighting_cache`, `near_part`). The flux
    /// is 0 without shadows, where nothing shadows the gradient, and for backends whose
    /// selection follows the shader (Lightcuts), which the cache does not serve. `sigma_t` is
    /// the extinction at `x` (the escape of voxel lights' light through it:
    /// [`escape`](lgh_core::near_field::escape)).
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::lgh_core::{BruteForce, PointLight};
    /// use lgh_volume::lighting::{LightScratch, Lights};
    /// use lgh_volume::render::RenderStats;
    /// use lgh_volume::shadow::Visibility;
    ///
    /// let one = BruteForce::new(&[PointLight::new(Vec3::ZERO, Vec3::splat(4.0))])?;
    /// let lights = Lights::new(one, 0.1);
    /// let (mut scratch, mut stats) = (LightScratch::default(), RenderStats::default());
    /// let x = Vec3::new(2.0, 0.0, 0.0);
    /// let far = Some(|d: f32| if d > 1.0 { 0.5 } else { 0.0 });
    /// let at = lights.incident_flux(x, 0.0, &Visibility::None, far, &mut scratch, &mut stats)?;
    /// assert_eq!((at.light, at.unshadowed, at.flux), (Vec3::ONE, Vec3::ONE, Vec3::ZERO));
    /// assert_eq!((at.far, at.far_light), (Vec3::splat(0.5), Vec3::splat(0.5)));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn incident_flux(
        &self,
        x: Vec3,
        sigma_t: f32,
        visibility: &Visibility,
        far: Option<impl Fn(f32) -> f32>,
        scratch: &mut LightScratch,
        stats: &mut crate::stats::RenderStats,
    ) -> Result<IncidentFlux, QueryError> {
        let point = ShadingPoint::in_medium(x);
        if visibility.is_none() || self.backend.selection_follows_shader() {
            let light =
                self.incident_in(&point, sigma_t, visibility, |_| Vec3::ONE, scratch, stats)?;
            let none = &Visibility::None;
            let unshadowed = if visibility.is_none() {
                light
            } else {
                self.incident_in(&point, sigma_t, none, |_| Vec3::ONE, scratch, stats)?
            };
            let far_fn = far;
            let far = match &far_fn {
                Some(far) => {
                    let far = |l: &LightSample| Vec3::splat(far(l.distance));
                    self.incident_in(&point, sigma_t, none, far, scratch, stats)?
                }
                None => Vec3::ZERO,
            };
            // The far part's light: its unshadowed light where nothing shadows it.
            let far_light = match (&far_fn, visibility.is_none()) {
                (_, true) => far,
                (Some(far), false) => {
                    let far = |l: &LightSample| Vec3::splat(far(l.distance));
                    self.incident_in(&point, sigma_t, visibility, far, scratch, stats)?
                }
                (None, false) => Vec3::ZERO,
            };
            return Ok(IncidentFlux {
                light,
                unshadowed,
                far,
                far_light,
                flux: Vec3::ZERO,
            });
        }
        self.gather(&point, sigma_t, visibility, |_| Vec3::ONE, scratch, stats)?;
        let mut split = IncidentFlux::default();
        let terms = scratch.unshadowed.iter().zip(&scratch.visibility);
        for ((&(weighted, g, d), &v), &p) in terms.zip(scratch.lights.positions()) {
            let term = weighted * (g * v);
            let unshadowed = weighted * g;
            split.light += term;
            split.unshadowed += unshadowed;
            if let Some(far) = &far {
                let w = far(d);
                split.far += unshadowed * w;
                split.far_light += term * w;
            }
            split.flux += (x - p).normalize_or_zero() * lgh_core::luminance(term);
        }
        Ok(split)
    }

    /// The light in-scattered at `x` in a medium, per unit solid angle: `scale` (`σ_s`, or
    /// `h³ σ_s` for a voxel's light) times the isotropic phase function `1/4π` times the
    /// [`incident`](Self::incident) light, at a point where the extinction is `sigma_t` (which
    /// sets the escape of voxel lights' light through it:
    /// [`escape`](lgh_core::near_field::escape)). The phase is the shader's response, so every backend
    /// shades what an isotropic point scatters, `I g V / 4π`: the values an error-bounded
    /// backend (Lightcuts) compares with its bounds, which are of that light
    /// (`lgh_core::reflected` at an isotropic point); shading `I g V` refined its cut as if ε
    /// were 4π larger.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::lgh_core::{BruteForce, PointLight};
    /// use lgh_volume::lighting::{LightScratch, Lights};
    /// use lgh_volume::render::RenderStats;
    /// use lgh_volume::shadow::Visibility;
    ///
    /// let one = BruteForce::new(&[PointLight::new(Vec3::ZERO, Vec3::splat(4.0))])?;
    /// let lights = Lights::new(one, 0.1);
    /// let (mut scratch, mut stats) = (LightScratch::default(), RenderStats::default());
    /// let x = Vec3::new(2.0, 0.0, 0.0);
    /// let l = lights.in_scattered(x, 3.0, 4.0, &Visibility::None, &mut scratch, &mut stats)?;
    /// let want = 3.0 / (4.0 * std::f32::consts::PI); // σ_s · (I / d²) / 4π
    /// assert!((l - Vec3::splat(want)).abs().max_element() < 1e-6);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn in_scattered(
        &self,
        x: Vec3,
        scale: f32,
        sigma_t: f32,
        visibility: &Visibility,
        scratch: &mut LightScratch,
        stats: &mut crate::stats::RenderStats,
    ) -> Result<Vec3, QueryError> {
        let point = ShadingPoint::in_medium(x);
        let phase = Vec3::splat(ISOTROPIC_PHASE);
        Ok(self.incident_in(&point, sigma_t, visibility, |_| phase, scratch, stats)? * scale)
    }

    /// [`in_scattered`](Self::in_scattered) unshadowed (`V = 1`), each light's term weighted
    /// by `weight(distance)`: a part of the light, such as a lighting cache's near part
    /// (`near_part`), whose weights and the far part's sum to 1.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::lgh_core::{BruteForce, PointLight};
    /// use lgh_volume::lighting::{LightScratch, Lights};
    /// use lgh_volume::render::RenderStats;
    /// use lgh_volume::shadow::Visibility;
    ///
    /// let two = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// let lights = Lights::new(BruteForce::new(&two)?, 0.1);
    /// let (mut scratch, mut stats) = (LightScratch::default(), RenderStats::default());
    /// let (x, none) = (Vec3::new(3.0, 0.0, 0.0), &Visibility::None);
    /// let all = lights.in_scattered(x, 1.0, 0.0, none, &mut scratch, &mut stats)?;
    /// let near = |d: f32| if d < 2.5 { 1.0 } else { 0.0 }; // the light at 2 only
    /// let part = lights.unshadowed_part(x, 1.0, 0.0, near, &mut scratch, &mut stats)?;
    /// assert!((part / all - Vec3::splat(0.25 / (0.25 + 1.0 / 9.0))).abs().max_element() < 1e-6);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn unshadowed_part(
        &self,
        x: Vec3,
        scale: f32,
        sigma_t: f32,
        weight: impl Fn(f32) -> f32,
        scratch: &mut LightScratch,
        stats: &mut crate::stats::RenderStats,
    ) -> Result<Vec3, QueryError> {
        let none = &Visibility::None;
        Ok(self.in_scattered_part(x, sigma_t, none, weight, scratch, stats)? * scale)
    }

    /// [`in_scattered`](Self::in_scattered) at a scale of 1 (times the scale, it is the voxel's
    /// in-scattered light), each light's term weighted by `weight(distance)`: a part of the
    /// light with its shadows, such as the near part of a lighting cache that
    /// keeps level 0's far part as light ([`Level0Form::FarLight`](crate::lighting_cache::Level0Form::FarLight)).
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::lgh_core::{BruteForce, PointLight};
    /// use lgh_volume::lighting::{LightScratch, Lights};
    /// use lgh_volume::render::RenderStats;
    /// use lgh_volume::shadow::Visibility;
    ///
    /// let two = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// let lights = Lights::new(BruteForce::new(&two)?, 0.1);
    /// let (mut scratch, mut stats) = (LightScratch::default(), RenderStats::default());
    /// let (x, none) = (Vec3::new(3.0, 0.0, 0.0), &Visibility::None);
    /// let near = |d: f32| if d < 2.5 { 1.0 } else { 0.0 };
    /// let far = |d: f32| 1.0 - near(d);
    /// let all = lights.in_scattered(x, 1.0, 0.0, none, &mut scratch, &mut stats)?;
    /// let a = lights.in_scattered_part(x, 0.0, none, near, &mut scratch, &mut stats)?;
    /// let b = lights.in_scattered_part(x, 0.0, none, far, &mut scratch, &mut stats)?;
    /// assert!((a + b - all).abs().max_element() < 1e-7);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn in_scattered_part(
        &self,
        x: Vec3,
        sigma_t: f32,
        visibility: &Visibility,
        weight: impl Fn(f32) -> f32,
        scratch: &mut LightScratch,
        stats: &mut crate::stats::RenderStats,
    ) -> Result<Vec3, QueryError> {
        let point = ShadingPoint::in_medium(x);
        let phase = |l: &LightSample| Vec3::splat(ISOTROPIC_PHASE * weight(l.distance));
        self.incident_in(&point, sigma_t, visibility, phase, scratch, stats)
    }
}

/// The light at a point in a medium as the lighting cache keeps it
/// ([`Lights::incident_flux`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IncidentFlux {
    /// `Σ_j I_j g_j V_j`: the incident light.
    pub light: Vec3,
    /// `Σ_j I_j g_j`: the same lights unshadowed.
    pub unshadowed: Vec3,
    /// `Σ_j far(d_j) I_j g_j`: their far part, unshadowed (`near_part`).
    pub far: Vec3,
    /// `Σ_j far(d_j) I_j g_j V_j`: their far part's light, shadowed (`near_part`).
    pub far_light: Vec3,
    /// `Σ_j lum(I_j g_j V_j) ω_j`: the flux vector (0 without shadows).
    pub flux: Vec3,
}

/// A shading point's lights, gathered so that their visibility can be evaluated together;
/// reused from shading point to shading point so that a render allocates per row, not per point.
#[derive(Clone, Debug, Default)]
pub struct LightScratch {
    lights: ShadowQuery,
    /// `I · f(light)`, the fall-off `g(d)` and the distance `d` of each light.
    unshadowed: Vec<(Vec3, f32, f32)>,
    visibility: Vec<f32>,
}
