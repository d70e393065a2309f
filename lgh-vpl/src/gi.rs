//! Global illumination of a mesh as one value, [`GiScene`]: the pipeline of `lgh gi` and
//! `lgh bench gi` (ARCHITECTURE.md, "From an OBJ to an EXR (lgh-vpl)").
//!
//! [`GiScene::prepare`] takes a mesh, the primary lights given beside its emissive faces and
//! the α-independent [`GiSettings`], traces the virtual point lights from the primary lights
//! ([`crate::vpl`]) and builds what every method needs: the VPLs as isotropic points
//! ([`point_lights`]) and their lighting grid hierarchy, whose `h0` clamps every method's
//! singularity (paper Sec. 6.4: the automatic `h1` of VPLs). [`GiScene::render`] then renders
//! any camera through a [`GiMethod`] carrying its own parameters — the hierarchy at α (the
//! paper's Fig. 13 compares α = 1, 4, 16 with brute force), brute force over every VPL (the
//! exact answer of the same model) or Lightcuts at its relative error — with shadow rays
//! through the BVH ([`crate::indirect`]; coarse lights shaded as [`CoarseShadows`] says: the
//! paper's Gaussian samples of Fig. 11d, or representative VPLs), plus the direct light of the
//! primary lights ([`crate::direct`]) when the settings ask for it.
//!
//! What only some methods need — the normal buckets or the representatives of the hierarchy's
//! coarse lights for [`GiMethod::Lgh`], Lightcuts' light tree — is built at the first render
//! that needs it, or earlier by [`GiScene::build_for`] (so that a timed render times only the
//! render). It is built once and kept.

use std::sync::OnceLock;
use std::time::Instant;

use lgh_core::glam::Vec3;
use lgh_core::lightcuts::{LightTree, LightcutsBackend, LightcutsSettings, Representative};
use lgh_core::{
    BruteForce, BuildError, GridSettings, LghBackend, LightingGridHierarchy, PointLight, QueryError,
};

use crate::direct::{render_direct, Direct, DirectSettings};
use crate::indirect::{
    point_lights, render_buckets, render_input_lights, render_lgh, Coarse, Indirect,
    IndirectSettings, NormalBuckets,
};
use crate::indirect::{
    BlendAt, DEFAULT_CANDIDATES, DEFAULT_LOBE_ERROR, DEFAULT_POINT_ERROR, MAX_CANDIDATES,
};
use crate::mesh::Mesh;
use crate::primary::{area_lights, PrimaryLight};
use crate::render::{RenderError, Rendered};
use crate::representatives::{Allocation, Representatives, MAX_PER_LIGHT};
use crate::scene::Scene;
use crate::specular::DEFAULT_SPECULAR_DEPTH;
use crate::vpl::{trace, Vpl, VplError, VplSettings, Vpls};
use lgh_image::camera::{CameraError, Pinhole as Camera};

/// How the hierarchy aggregates the VPLs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Aggregation {
    /// The paper's: one hierarchy, the VPLs aggregated as isotropic points.
    #[default]
    Isotropic,
    /// Beyond the paper: one hierarchy per dominant normal axis, whose coarse lights keep
    /// their bucket's mean-normal lobe ([`NormalBuckets`]).
    Buckets,
}

impl Aggregation {
    /// Its name, as `lgh gi --aggregation` spells it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Aggregation::Isotropic => "isotropic",
            Aggregation::Buckets => "buckets",
        }
    }
}

/// Where a coarse light's `k` shadow samples lie.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CoarseShadows {
    /// The paper's (Fig. 11d): `k` points drawn with the light's variance σ² (eq. 4).
    Gaussian,
    /// Beyond the paper: `k` of the VPLs the light stands for, drawn once per light by weight,
    /// each shaded with its own lobe and shadow ray ([`crate::representatives`]).
    #[default]
    Representatives,
}

impl CoarseShadows {
    /// Its name, as `lgh gi --coarse-shadows` spells it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            CoarseShadows::Gaussian => "gaussian",
            CoarseShadows::Representatives => "representatives",
        }
    }
}

/// How [`CoarseShadows::Representatives`] shares the shadow samples among coarse lights.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SampleAllocation {
    /// `k` for every coarse light.
    Uniform,
    /// Per light, in proportion to its luminance against its level's mean.
    Intensity,
    /// Per shading point, in proportion to what each coarse light brings there unshadowed (a
    /// power-of-two prefix of its nested representatives; [`Coarse::Adaptive`]).
    Adaptive,
}

impl SampleAllocation {
    /// Its name, as `lgh gi --sample-allocation` spells it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            SampleAllocation::Uniform => "uniform",
            SampleAllocation::Intensity => "intensity",
            SampleAllocation::Adaptive => "adaptive",
        }
    }
}

/// Whether a render adds the primary lights' direct light to the VPLs' indirect light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectLight {
    /// Only the VPLs' indirect light (what `lgh bench gi` compares): no direct light, no
    /// emitters seen.
    Off,
    /// The direct light with shadow rays, emitters seen; an area light through an
    /// `area_strata²` stratified pattern fixed per surface point ([`crate::direct`]).
    Stratified {
        /// Strata per side, 1 to 64.
        area_strata: u32,
    },
}

impl Default for DirectLight {
    /// 4 × 4 strata.
    fn default() -> Self {
        DirectLight::Stratified { area_strata: 4 }
    }
}

/// What a [`GiScene`] is prepared with: everything that does not depend on the method.
/// `None` settings take their default for the others ([`sample_allocation`],
/// [`max_shadow_samples`], [`shadow_samples`]); [`Default`] is `lgh gi`'s defaults.
///
/// [`sample_allocation`]: Self::sample_allocation
/// [`max_shadow_samples`]: Self::max_shadow_samples
/// [`shadow_samples`]: Self::shadow_samples
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GiSettings {
    /// How many VPLs (at least), how many bounces, which seed (also the seed of Lightcuts'
    /// representatives).
    pub vpls: VplSettings,
    /// How the hierarchy aggregates the VPLs.
    pub aggregation: Aggregation,
    /// How a coarse light's shadow samples are placed.
    pub coarse_shadows: CoarseShadows,
    /// How representatives are shared among coarse lights (`None`: the default for the
    /// aggregation).
    pub sample_allocation: Option<SampleAllocation>,
    /// Shadow samples `k` of a coarse light (a mean for `Intensity` and `Adaptive`; `None`: the
    /// default for the placement and allocation).
    pub shadow_samples: Option<f32>,
    /// The most representatives one coarse light gets (`None`: the default for the
    /// allocation).
    pub max_shadow_samples: Option<u32>,
    /// Whether shadow rays are traced (false: every VPL reaches every point it faces).
    pub shadows: bool,
    /// Whether renders add the direct light.
    pub direct: DirectLight,
    /// The most mirrors and glass surfaces a camera or light path follows, 0 to
    /// [`MAX_SPECULAR_DEPTH`] ([`crate::specular`]).
    pub specular_depth: u32,
    /// The bound ε (relative to a point's reflected light, [`crate::indirect::lobe`]) at which
    /// [`GiMethod::Lgh`] with its default coarse shading (representatives shared per point,
    /// [`crate::indirect::Coarse::Adaptive`]) splits a glossy lobe too sharp for it, its VPLs
    /// in the lobe's cone shaded one by one; the other coarse shadings and the normal buckets
    /// do not split. `None`: the hierarchy alone everywhere. Finite and above 0.
    pub lobe_error: Option<f32>,
    /// The bound ε on each shading point's error at which [`GiMethod::Lgh`] with its default
    /// coarse shading shades a point's coarse lights again with more representatives, while
    /// the point's estimated error (1.645 standard errors, [`crate::indirect::refine`]) exceeds
    /// ε of its light. `None`: the mean number everywhere. Finite and above 0.
    pub point_error: Option<f32>,
    /// Where [`GiMethod::Lgh`] with its default coarse shading takes a coarse light's blending
    /// weight `B_ℓ`: at each representative's own distance (the default: unbiased against
    /// brute force) or at the light's centre, as in eq. (3) ([`BlendAt`]).
    pub blend: BlendAt,
    /// The candidates each of a coarse light's draws looks at with [`GiMethod::Lgh`]'s default
    /// coarse shading, one picked for its shadow ray by what each gives unshadowed
    /// ([`crate::indirect::resample`]): a power of two from 1 to [`MAX_CANDIDATES`] (so that
    /// a light's draws look at a power-of-two prefix of its nested representatives), 1
    /// drawing each representative on its own.
    pub candidates: u32,
}

/// The least mean [`GiSettings::shadow_samples`] per coarse light that `Adaptive` takes: 1/4
/// (shared per point, so below one most lights take their sample by roulette; below a quarter
/// the point bound would do nearly all the work).
pub const MIN_ADAPTIVE_SAMPLES: f32 = 0.25;

/// The mean draws per coarse light of the adaptive shading by default (`--shadow-samples`
/// with `--sample-allocation adaptive`): 0.35. With the lights that face away left out
/// ([`crate::facing`]) and the ray roulette ([`crate::indirect::resample`]), `lgh bench gi`
/// at α = 4 and 365K VPLs measured, for 0.5, 0.4 and 0.35: Sponza (two runs of three
/// renders each) 2.07%, 2.30% and 2.50% at 52–53×, 52× and 55–58× brute force's speed, the
/// Cornell box (one run each) 1.57%, 1.73% and 1.99% at 100×, 116× and 114×; 0.35 keeps
/// both under the figures the earlier model was measured at (2.68% and 2.29%), at about
/// those figures' speed.
pub const DEFAULT_ADAPTIVE_SAMPLES: f32 = 0.35;

/// The largest [`GiSettings::specular_depth`]: 32. (A camera path's branches carrying at least
/// [`crate::specular::MIN_WEIGHT`] each are at most 1/`MIN_WEIGHT` = 1000, whatever the depth.)
pub const MAX_SPECULAR_DEPTH: u32 = 32;

impl Default for GiSettings {
    /// [`VplSettings::default`] (100,000 VPLs of up to 3 bounces, seed 1), the one hierarchy,
    /// representatives shared per point ([`DEFAULT_ADAPTIVE_SAMPLES`] draws per coarse light
    /// on average, each resampled among 4, at most 32 representatives),
    /// shadow rays, and the direct light through 4 × 4 strata.
    fn default() -> Self {
        GiSettings {
            vpls: VplSettings::default(),
            aggregation: Aggregation::default(),
            coarse_shadows: CoarseShadows::default(),
            sample_allocation: None,
            shadow_samples: None,
            max_shadow_samples: None,
            shadows: true,
            direct: DirectLight::default(),
            specular_depth: DEFAULT_SPECULAR_DEPTH,
            lobe_error: Some(DEFAULT_LOBE_ERROR),
            point_error: Some(DEFAULT_POINT_ERROR),
            blend: BlendAt::default(),
            candidates: DEFAULT_CANDIDATES,
        }
    }
}

impl GiSettings {
    /// The allocation, or its default: `Adaptive` for the one hierarchy, `Intensity` for the
    /// buckets (whose shading has no per-point allocation).
    #[must_use]
    pub fn sample_allocation(&self) -> SampleAllocation {
        self.sample_allocation.unwrap_or(match self.aggregation {
            Aggregation::Isotropic => SampleAllocation::Adaptive,
            Aggregation::Buckets => SampleAllocation::Intensity,
        })
    }

    /// The most representatives of one light, or its default: 32 for `Adaptive` (which shares
    /// the samples per point, so a light that dominates a point may take many), 16 otherwise.
    #[must_use]
    pub fn max_shadow_samples(&self) -> u32 {
        self.max_shadow_samples
            .unwrap_or(match self.sample_allocation() {
                SampleAllocation::Adaptive => 32,
                SampleAllocation::Intensity | SampleAllocation::Uniform => 16,
            })
    }

    /// `k`, or its default: 9 Gaussian samples (the paper's Fig. 11d); representatives,
    /// [`DEFAULT_ADAPTIVE_SAMPLES`] for `Adaptive` (each draw resampled among
    /// [`DEFAULT_CANDIDATES`]), 2 for `Intensity` and `Uniform`.
    #[must_use]
    pub fn shadow_samples(&self) -> f32 {
        let representatives = self.coarse_shadows == CoarseShadows::Representatives;
        self.shadow_samples
            .unwrap_or(match self.sample_allocation() {
                _ if !representatives => 9.0,
                SampleAllocation::Adaptive => DEFAULT_ADAPTIVE_SAMPLES,
                SampleAllocation::Intensity | SampleAllocation::Uniform => 2.0,
            })
    }

    /// Checks the settings before any work ([`GiScene::prepare`] does too): `k` a whole number
    /// from 0 (Gaussian samples, at most 1024) or 1 (representatives, at most
    /// [`MAX_PER_LIGHT`]) unless it is a mean (`Intensity`; `Adaptive`, from
    /// [`MIN_ADAPTIVE_SAMPLES`]); the most
    /// representatives 1 to [`MAX_PER_LIGHT`]; `Adaptive` representatives only with the one
    /// hierarchy; 1 to 64 strata. (The VPL counts are checked by [`trace`].)
    ///
    /// Errors: [`GiError::ShadowSamples`], [`GiError::MaxShadowSamples`], [`GiError::PointError`],
    /// [`GiError::AdaptiveBuckets`], [`GiError::AreaStrata`], [`GiError::SpecularDepth`],
    /// [`GiError::Candidates`].
    pub fn check(&self) -> Result<(), GiError> {
        let representatives = self.coarse_shadows == CoarseShadows::Representatives;
        let allocation = self.sample_allocation();
        let samples = self.shadow_samples();
        let whole = !representatives || allocation == SampleAllocation::Uniform;
        let (min, max) = if representatives && allocation == SampleAllocation::Adaptive {
            // A mean shared per point: below one, most lights take their sample by roulette.
            (MIN_ADAPTIVE_SAMPLES, MAX_PER_LIGHT as f32)
        } else if representatives {
            (1.0, MAX_PER_LIGHT as f32)
        } else {
            (0.0, 1024.0)
        };
        if !(samples.is_finite() && samples >= min && samples <= max)
            || (whole && samples.fract() != 0.0)
        {
            return Err(GiError::ShadowSamples {
                samples,
                whole,
                min,
                max,
                coarse: self.coarse_shadows,
            });
        }
        let most = self.max_shadow_samples();
        if !(1..=MAX_PER_LIGHT).contains(&most) {
            return Err(GiError::MaxShadowSamples { max: most });
        }
        if representatives
            && allocation == SampleAllocation::Adaptive
            && self.aggregation == Aggregation::Buckets
        {
            return Err(GiError::AdaptiveBuckets);
        }
        if let Some(error) = self.lobe_error {
            if !(error.is_finite() && error > 0.0) {
                return Err(GiError::LobeError { error });
            }
        }
        if let Some(error) = self.point_error {
            if !(error.is_finite() && error > 0.0) {
                return Err(GiError::PointError { error });
            }
        }
        if !(1..=MAX_CANDIDATES).contains(&self.candidates) || !self.candidates.is_power_of_two() {
            return Err(GiError::Candidates {
                candidates: self.candidates,
            });
        }
        if self.specular_depth > MAX_SPECULAR_DEPTH {
            return Err(GiError::SpecularDepth {
                depth: self.specular_depth,
            });
        }
        match self.direct {
            DirectLight::Stratified { area_strata } if !(1..=64).contains(&area_strata) => {
                Err(GiError::AreaStrata { area_strata })
            }
            _ => Ok(()),
        }
    }

    /// How the representatives are drawn, for a checked `k`.
    fn allocation(&self) -> Allocation {
        let k = self.shadow_samples();
        match self.sample_allocation() {
            SampleAllocation::Uniform => Allocation::Uniform(k as u32),
            SampleAllocation::Intensity => Allocation::ByIntensity {
                mean: k,
                max: self.max_shadow_samples(),
            },
            SampleAllocation::Adaptive => Allocation::Nested(self.max_shadow_samples()),
        }
    }
}

/// A many-lights method over the VPLs, with its own parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GiMethod {
    /// The lighting grid hierarchy at the paper's α, aggregated and with coarse shadows as the
    /// scene's [`GiSettings`] say.
    Lgh {
        /// α (eq. 3), positive.
        alpha: f32,
    },
    /// Every VPL: the exact answer of the same model.
    Brute,
    /// Lightcuts (Walter et al. 2005), each cluster shaded as its representative VPL.
    Lightcuts {
        /// Relative error ε, positive (Walter et al.'s 0.02).
        relative_error: f32,
    },
}

impl GiMethod {
    /// Its name, as `lgh gi --backend` spells it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            GiMethod::Lgh { .. } => "lgh",
            GiMethod::Brute => "brute",
            GiMethod::Lightcuts { .. } => "lightcuts",
        }
    }

    /// Checks the method's parameters (α or ε finite and positive) before any work.
    ///
    /// Errors: [`GiError::Query`] for α, [`GiError::RelativeError`] for ε.
    pub fn check(self) -> Result<(), GiError> {
        match self {
            GiMethod::Lgh { alpha } => Ok(lgh_core::check_alpha(alpha)?),
            GiMethod::Brute => Ok(()),
            GiMethod::Lightcuts { relative_error } => {
                if relative_error.is_finite() && relative_error > 0.0 {
                    Ok(())
                } else {
                    Err(GiError::RelativeError { relative_error })
                }
            }
        }
    }
}

/// Why a [`GiScene`] could not be prepared or rendered. Messages name the settings as `lgh gi`
/// spells them, as [`crate::primary`]'s do.
#[derive(Clone, Debug, PartialEq)]
pub enum GiError {
    /// `k` outside `min..=max`, or not whole where it must be.
    ShadowSamples {
        /// The rejected `k`.
        samples: f32,
        /// Whether it must be a whole number.
        whole: bool,
        /// The least allowed.
        min: f32,
        /// The most allowed.
        max: f32,
        /// The placement it was given for.
        coarse: CoarseShadows,
    },
    /// The most representatives of one light outside `1..=MAX_PER_LIGHT`.
    MaxShadowSamples {
        /// The rejected value.
        max: u32,
    },
    /// [`SampleAllocation::Adaptive`] representatives with [`Aggregation::Buckets`].
    AdaptiveBuckets,
    /// Strata per side outside 1 to 64.
    AreaStrata {
        /// The rejected value.
        area_strata: u32,
    },
    /// A lobe bound that is not finite and above 0.
    LobeError {
        /// The rejected value.
        error: f32,
    },
    /// A per-point bound that is not finite and above 0.
    PointError {
        /// The rejected value.
        error: f32,
    },
    /// Candidates of a resampled draw not a power of two from 1 to [`MAX_CANDIDATES`].
    Candidates {
        /// The rejected value.
        candidates: u32,
    },
    /// A specular depth over [`MAX_SPECULAR_DEPTH`].
    SpecularDepth {
        /// The rejected value.
        depth: u32,
    },
    /// Lightcuts' relative error not finite and positive.
    RelativeError {
        /// The rejected value.
        relative_error: f32,
    },
    /// No VPLs could be traced (no lights among them).
    Vpl(VplError),
    /// A hierarchy or Lightcuts' tree could not be built.
    Build(BuildError),
    /// An invalid α, or a point a method could not be queried at.
    Query(QueryError),
    /// A render failed.
    Render(RenderError),
}

impl std::fmt::Display for GiError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GiError::ShadowSamples {
                samples,
                whole,
                min,
                max,
                coarse,
            } => write!(
                f,
                "--shadow-samples {samples}: expected {} from {min} to {max} with \
                 --coarse-shadows {}",
                if *whole { "a whole number" } else { "a number" },
                coarse.name()
            ),
            GiError::MaxShadowSamples { max } => write!(
                f,
                "--max-shadow-samples {max}: expected 1 to {MAX_PER_LIGHT}"
            ),
            GiError::AdaptiveBuckets => write!(
                f,
                "--sample-allocation adaptive needs --aggregation isotropic (the buckets take \
                 intensity or uniform)"
            ),
            GiError::AreaStrata { area_strata } => {
                write!(f, "--area-strata {area_strata}: expected 1 to 64")
            }
            GiError::LobeError { error } => write!(
                f,
                "--lobe-error {error}: expected a positive number (0.01 is 1% of a point's diffuse light)"
            ),
            GiError::PointError { error } => write!(
                f,
                "--point-error {error}: expected a positive number (0.1 is 10% of a point's light) or off"
            ),
            GiError::Candidates { candidates } => {
                // The powers of two up to the most: "1, 2, 4, 8 or 16".
                let powers: Vec<String> = (0..=MAX_CANDIDATES.ilog2())
                    .map(|k| (1u32 << k).to_string())
                    .collect();
                let (last, rest) = powers.split_last().expect("1 at least");
                write!(
                    f,
                    "--candidates {candidates}: expected {} or {last} (1 draws each \
                     representative on its own)",
                    rest.join(", ")
                )
            }
            GiError::SpecularDepth { depth } => {
                write!(
                    f,
                    "--specular-depth {depth}: expected 0 to {MAX_SPECULAR_DEPTH}"
                )
            }
            GiError::RelativeError { relative_error } => write!(
                f,
                "--lightcuts-error {relative_error}: expected a positive number (0.02 is 2%)"
            ),
            GiError::Vpl(e) => write!(f, "{e}"),
            GiError::Build(e) => write!(f, "{e}"),
            GiError::Query(e) => write!(f, "{e}"),
            GiError::Render(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for GiError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            GiError::Vpl(e) => Some(e),
            GiError::Build(e) => Some(e),
            GiError::Query(e) => Some(e),
            GiError::Render(e) => Some(e),
            _ => None,
        }
    }
}

impl From<VplError> for GiError {
    fn from(e: VplError) -> Self {
        GiError::Vpl(e)
    }
}

impl From<BuildError> for GiError {
    fn from(e: BuildError) -> Self {
        GiError::Build(e)
    }
}

impl From<QueryError> for GiError {
    fn from(e: QueryError) -> Self {
        GiError::Query(e)
    }
}

impl From<RenderError> for GiError {
    fn from(e: RenderError) -> Self {
        GiError::Render(e)
    }
}

/// The phases of a [`GiScene::render`], for progress.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GiPhase {
    /// The VPLs' indirect light: steps are rows.
    Indirect,
    /// The primary lights' direct light: steps are rows.
    Direct,
}

impl GiPhase {
    /// A short label for a progress bar.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            GiPhase::Indirect => "rendering",
            GiPhase::Direct => "direct light",
        }
    }
}

/// Receives a render's progress: a phase begins with its rows, rows are done, it ends (also
/// when it failed). Every method has an empty default, and `()` reports nowhere. Calls come
/// from worker threads (hence `Sync`).
pub trait GiProgress: Sync {
    /// `phase` begins, with `rows` rows.
    fn begin(&self, phase: GiPhase, rows: u64) {
        let _ = (phase, rows);
    }
    /// `rows` more rows of the current phase are done.
    fn advance(&self, rows: u64) {
        let _ = rows;
    }
    /// `phase` has ended.
    fn end(&self, phase: GiPhase) {
        let _ = phase;
    }
}

impl GiProgress for () {}

/// What the direct light of a render took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectStats {
    /// Seconds.
    pub seconds: f64,
    /// Shadow rays one shading point takes at most ([`Direct::rays_per_point`]).
    pub max_rays_per_point: u64,
}

/// A [`GiScene::render`]: the image and what it took.
#[derive(Clone, Debug, PartialEq)]
pub struct GiRender {
    /// The image (the indirect light, plus the direct light when the settings ask for it), the
    /// pixels shaded and the method's lights per pixel.
    pub rendered: Rendered,
    /// Seconds of the indirect light (the method's per-α setup included).
    pub seconds: f64,
    /// Shadow rays of the indirect light.
    pub shadow_rays: u64,
    /// Shading points where a bound took [`GiMethod::Lgh`]'s default shading deeper:
    /// `lobe_split_points` and `refined_points`, a point in both counted once (0 for other
    /// methods).
    pub bounded_points: u64,
    /// Shading points whose glossy lobe the hierarchy split, its VPLs in the lobe's cone shaded
    /// one by one (`GiSettings::lobe_error`).
    pub lobe_split_points: u64,
    /// Shading points whose coarse lights were shaded again with more representatives, their
    /// estimated error over the bound (`GiSettings::point_error`).
    pub refined_points: u64,
    /// The direct light's cost, if it was rendered.
    pub direct: Option<DirectStats>,
}

impl GiRender {
    /// Shadow rays of the indirect light per shaded pixel.
    #[must_use]
    pub fn shadow_rays_per_point(&self) -> f64 {
        self.shadow_rays as f64 / self.rendered.pixels_shaded.max(1) as f64
    }
}

/// What [`GiMethod::Lgh`] shades through besides the one hierarchy.
enum LghExtras {
    /// The one hierarchy, its coarse lights through these representatives (or, without,
    /// Gaussian samples).
    Isotropic(Option<Representatives>),
    /// The normal buckets' hierarchies instead.
    Buckets(NormalBuckets),
}

/// A mesh's VPLs, traced and ready to render through any [`GiMethod`] (module docs).
///
/// ```
/// use lgh_vpl::gi::{DirectLight, GiMethod, GiScene, GiSettings};
/// use lgh_vpl::lgh_core::glam::Vec3;
/// use lgh_vpl::lgh_core::Material;
/// use lgh_vpl::primary::PrimaryLight;
/// use lgh_vpl::vpl::VplSettings;
/// use lgh_vpl::{Camera, Mesh};
///
/// // A floor and a back wall, a lamp above the floor.
/// let grey = Material::Lambert { albedo: Vec3::splat(0.7) };
/// let v = Vec3::new;
/// let mut mesh = Mesh::quad([v(-1., 0., 1.), v(1., 0., 1.), v(1., 0., -1.), v(-1., 0., -1.)], grey)?;
/// mesh.append(Mesh::quad([v(-1., 0., -1.), v(1., 0., -1.), v(1., 2., -1.), v(-1., 2., -1.)], grey)?)?;
/// let lamp = PrimaryLight::Point { position: v(0.0, 1.5, 0.0), intensity: Vec3::splat(2.0) };
///
/// let settings = GiSettings {
///     vpls: VplSettings { count: 400, ..VplSettings::default() },
///     direct: DirectLight::Off,
///     ..GiSettings::default()
/// };
/// let scene = GiScene::prepare(mesh, [lamp], &settings)?;
/// let camera = Camera::new(v(0.0, 1.0, 3.0), v(0.0, 0.6, 0.0), Vec3::Y, 50.0, 16, 12)?;
/// let brute = scene.render(GiMethod::Brute, &camera, &())?;
/// let lgh = scene.render(GiMethod::Lgh { alpha: 4.0 }, &camera, &())?;
/// // Brute force shades every VPL at every point: the exact answer of the same model.
/// assert_eq!(brute.rendered.mean_lights(), scene.vpls().len() as f64);
/// // The hierarchy at α = 4 is close to it (measured: 4.0% with these 400 VPLs).
/// let e = lgh_image::compare(&lgh.rendered.image, &brute.rendered.image).unwrap();
/// assert!(e.rel_rmse < 0.1, "{}", e.rel_rmse);
/// assert!(lgh.direct.is_none() && lgh.shadow_rays > 0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct GiScene {
    scene: Scene,
    /// The primary lights: the emissive triangles, then the given ones.
    lights: Vec<PrimaryLight>,
    emissive: usize,
    settings: GiSettings,
    traced: Vpls,
    /// The VPLs as isotropic points ([`point_lights`]).
    points: Vec<PointLight>,
    lgh: LightingGridHierarchy,
    shading: IndirectSettings,
    /// Built at the first need ([`GiScene::build_for`]).
    extras: OnceLock<LghExtras>,
    tree: OnceLock<LightTree>,
}

impl GiScene {
    /// Checks `settings`, gathers the primary lights (the mesh's emissive faces, then `lights`),
    /// traces the VPLs from them and builds their hierarchy.
    ///
    /// Errors: those of [`GiSettings::check`]; [`GiError::Vpl`] when there is no light or no
    /// VPL could be traced; [`GiError::Build`] for the hierarchy.
    pub fn prepare(
        mesh: Mesh,
        lights: impl IntoIterator<Item = PrimaryLight>,
        settings: &GiSettings,
    ) -> Result<GiScene, GiError> {
        settings.check()?;
        let mut primary = area_lights(&mesh);
        let emissive = primary.len();
        primary.extend(lights);
        if primary.is_empty() {
            return Err(VplError::NoLights.into());
        }
        let (lo, hi) = mesh.bounds();
        let mut scene = Scene::new(mesh);
        scene.set_specular_depth(settings.specular_depth);
        let mut traced = trace(&scene, &primary, &settings.vpls)?;
        traced.sort_spatially();
        let points = point_lights(&traced.vpls);
        let lgh = LightingGridHierarchy::build(&points, &GridSettings::default())?;
        let shading = IndirectSettings {
            h0: lgh.h0(),
            shadow_samples: settings.shadow_samples() as u32,
            epsilon: 1e-4 * (hi - lo).length(),
            shadows: settings.shadows,
            lobe_error: settings.lobe_error,
            point_error: settings.point_error,
        };
        Ok(GiScene {
            scene,
            lights: primary,
            emissive,
            settings: *settings,
            traced,
            points,
            lgh,
            shading,
            extras: OnceLock::new(),
            tree: OnceLock::new(),
        })
    }

    /// Builds now what `method` needs beyond the VPLs' hierarchy — for [`GiMethod::Lgh`] the
    /// normal buckets or the coarse lights' representatives the settings ask for, for
    /// [`GiMethod::Lightcuts`] the light tree — which [`render`](Self::render) would otherwise
    /// build at its first call. Built once; a second call does nothing.
    ///
    /// Errors: [`GiError::Build`].
    pub fn build_for(&self, method: GiMethod) -> Result<(), GiError> {
        match method {
            GiMethod::Lgh { .. } => self.extras().map(|_| ()),
            GiMethod::Brute => Ok(()),
            GiMethod::Lightcuts { .. } => self.tree().map(|_| ()),
        }
    }

    /// Renders `camera` through `method`: the VPLs' indirect light, then, if the settings ask
    /// for it, the primary lights' direct light added to it. `progress` hears
    /// [`GiPhase::Indirect`] and [`GiPhase::Direct`].
    ///
    /// Errors: [`GiMethod::check`]'s, [`build_for`](Self::build_for)'s, [`GiError::Query`] for
    /// a point a method cannot be queried at, [`GiError::Render`].
    pub fn render(
        &self,
        method: GiMethod,
        camera: &Camera,
        progress: &impl GiProgress,
    ) -> Result<GiRender, GiError> {
        method.check()?;
        self.build_for(method)?;
        let rows = camera.height() as u64;
        let shader = Indirect::new(&self.scene, &self.traced.vpls, self.shading);
        progress.begin(GiPhase::Indirect, rows);
        let t = Instant::now();
        let rendered = self.indirect(method, camera, &shader, |n| progress.advance(n as u64));
        progress.end(GiPhase::Indirect);
        let mut rendered = rendered?;
        let seconds = t.elapsed().as_secs_f64();
        let direct = match self.settings.direct {
            DirectLight::Off => None,
            DirectLight::Stratified { area_strata } => {
                let t = Instant::now();
                let settings = DirectSettings {
                    area_strata,
                    epsilon: self.shading.epsilon,
                };
                let direct = Direct::new(&self.scene, &self.lights, settings);
                progress.begin(GiPhase::Direct, rows);
                let lit = render_direct(&self.scene, camera, &direct, |n| {
                    progress.advance(n as u64);
                });
                progress.end(GiPhase::Direct);
                for (px, d) in rendered.image.pixels.iter_mut().zip(&lit?.image.pixels) {
                    *px += *d;
                }
                Some(DirectStats {
                    seconds: t.elapsed().as_secs_f64(),
                    max_rays_per_point: direct.rays_per_point(),
                })
            }
        };
        Ok(GiRender {
            rendered,
            seconds,
            shadow_rays: shader.shadow_rays(),
            bounded_points: shader.bounded_points(),
            lobe_split_points: shader.lobe_split_points(),
            refined_points: shader.refined_points(),
            direct,
        })
    }

    /// The indirect light through `method`, whose structures are built.
    fn indirect(
        &self,
        method: GiMethod,
        camera: &Camera,
        shader: &Indirect<'_>,
        progress: impl Fn(usize) + Sync,
    ) -> Result<Rendered, GiError> {
        let scene = &self.scene;
        Ok(match method {
            GiMethod::Lgh { alpha } => match self.extras()? {
                LghExtras::Buckets(buckets) => {
                    render_buckets(scene, camera, &buckets.at(alpha)?, shader, progress)?
                }
                LghExtras::Isotropic(reps) => {
                    let backend = LghBackend::new(&self.lgh, alpha)?;
                    let coarse = match (reps, self.settings.allocation()) {
                        (None, _) => Coarse::Gaussian,
                        (Some(reps), Allocation::Nested(_)) => Coarse::Adaptive {
                            reps,
                            mean: self.settings.shadow_samples(),
                            blend: self.settings.blend,
                            candidates: self.settings.candidates,
                        },
                        (Some(reps), _) => Coarse::Representatives(reps),
                    };
                    render_lgh(scene, camera, &backend, coarse, shader, progress)?
                }
            },
            GiMethod::Brute => {
                let brute = BruteForce::new(&self.points)?;
                render_input_lights(scene, camera, &brute, shader, progress)?
            }
            GiMethod::Lightcuts { relative_error } => {
                let settings = LightcutsSettings {
                    relative_error,
                    ..LightcutsSettings::default()
                };
                let cuts = LightcutsBackend::new(self.tree()?, settings)?;
                render_input_lights(scene, camera, &cuts, shader, progress)?
            }
        })
    }

    /// The normal buckets or the representatives, built at the first call.
    fn extras(&self) -> Result<&LghExtras, GiError> {
        get_or_build(&self.extras, || {
            let representatives = self.settings.coarse_shadows == CoarseShadows::Representatives;
            let allocation = self.settings.allocation();
            Ok(match self.settings.aggregation {
                Aggregation::Buckets => {
                    let b = NormalBuckets::build(&self.traced.vpls, &GridSettings::default())?;
                    LghExtras::Buckets(if representatives {
                        b.with_representatives(allocation)
                    } else {
                        b
                    })
                }
                Aggregation::Isotropic => {
                    LghExtras::Isotropic(representatives.then(|| {
                        Representatives::build_for(&self.lgh, allocation, &self.traced.vpls)
                    }))
                }
            })
        })
    }

    /// Lightcuts' light tree over the VPLs, built at the first call (its representatives
    /// seeded by the VPLs' seed).
    fn tree(&self) -> Result<&LightTree, GiError> {
        get_or_build(&self.tree, || {
            let seed = Representative::Stochastic {
                seed: self.settings.vpls.seed,
            };
            Ok(LightTree::build(&self.points, seed)?)
        })
    }

    /// The settings it was prepared with.
    #[must_use]
    pub fn settings(&self) -> &GiSettings {
        &self.settings
    }

    /// The scene: the mesh and its BVH.
    #[must_use]
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The primary lights: the mesh's emissive triangles, then the given lights.
    #[must_use]
    pub fn primary_lights(&self) -> &[PrimaryLight] {
        &self.lights
    }

    /// How many of the primary lights are emissive triangles.
    #[must_use]
    pub fn emissive_lights(&self) -> usize {
        self.emissive
    }

    /// The VPLs, in space's Morton order ([`Vpls::sort_spatially`]).
    #[must_use]
    pub fn vpls(&self) -> &[Vpl] {
        &self.traced.vpls
    }

    /// Light paths traced.
    #[must_use]
    pub fn light_paths(&self) -> u64 {
        self.traced.paths
    }

    /// The singularity clamp of every method: the VPLs' hierarchy's `h0`.
    #[must_use]
    pub fn h0(&self) -> f32 {
        self.lgh.h0()
    }
}

/// `cell`'s value, built by `build` if it has none yet.
fn get_or_build<T>(
    cell: &OnceLock<T>,
    build: impl FnOnce() -> Result<T, GiError>,
) -> Result<&T, GiError> {
    if let Some(value) = cell.get() {
        return Ok(value);
    }
    let value = build()?;
    Ok(cell.get_or_init(|| value))
}

/// `lgh gi`'s default camera: the box `lo..hi` (a mesh's [`bounds`](Mesh::bounds)) seen
/// straight along −z, y up, from where its front face (`z = hi.z`) just fills a 40° vertical
/// field of view — the Cornell box's classic view, through its open side.
///
/// Errors: [`CameraError`] for an image size outside `1..=MAX_IMAGE_SIDE`.
pub fn front_view(
    (lo, hi): (Vec3, Vec3),
    width: usize,
    height: usize,
) -> Result<Camera, CameraError> {
    let fov_y = 40.0f32;
    let tan_y = (0.5 * fov_y).to_radians().tan();
    let tan_x = tan_y * width as f32 / height.max(1) as f32;
    let half = 0.5 * (hi - lo);
    let distance = 1.02 * (half.x / tan_x).max(half.y / tan_y);
    let centre = 0.5 * (lo + hi);
    let eye = Vec3::new(centre.x, centre.y, hi.z + distance);
    Camera::new(eye, centre, Vec3::Y, fov_y, width, height)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::indirect::tests::{lamp, room_mesh};

    fn rel_rmse(a: &GiRender, r: &GiRender) -> f64 {
        lgh_image::compare(&a.rendered.image, &r.rendered.image)
            .unwrap()
            .rel_rmse
    }

    /// The room of the indirect light's tests, its 4,000 VPLs prepared with `settings`' other
    /// fields.
    fn room(settings: GiSettings) -> GiScene {
        let settings = GiSettings {
            vpls: VplSettings {
                count: 4000,
                max_bounces: 2,
                seed: 4,
            },
            ..settings
        };
        GiScene::prepare(room_mesh(), [lamp()], &settings).unwrap()
    }

    /// With α so large that every VPL is inside level 0's influence region, the hierarchy
    /// hands each point every VPL at full weight and no coarse light is shaded: through
    /// `GiScene`, with every aggregation and placement of coarse shadows, its image equals
    /// brute force over every VPL with the same shadow rays and shading up to the order of the
    /// sums — the tolerance 10⁻⁵ of
    /// `the_hierarchy_equals_brute_force_when_every_vpl_is_level_0` (indirect light). The direct
    /// light, the same in both, is off so that it cannot hide a difference.
    #[test]
    fn gi_scene_at_a_large_alpha_equals_brute_force() {
        let camera = crate::indirect::tests::Fixture::camera(24, 18);
        for (aggregation, coarse_shadows) in [
            (Aggregation::Isotropic, CoarseShadows::Representatives),
            (Aggregation::Isotropic, CoarseShadows::Gaussian),
            (Aggregation::Buckets, CoarseShadows::Gaussian),
        ] {
            let scene = room(GiSettings {
                aggregation,
                coarse_shadows,
                shadows: true,
                direct: DirectLight::Off,
                ..GiSettings::default()
            });
            let exact = scene.render(GiMethod::Brute, &camera, &()).unwrap();
            let got = scene
                .render(GiMethod::Lgh { alpha: 256.0 }, &camera, &())
                .unwrap();
            let e = rel_rmse(&got, &exact);
            assert!(e < 1e-5, "{aggregation:?} {coarse_shadows:?}: {e}");
            if aggregation == Aggregation::Isotropic {
                assert_eq!(got.rendered.mean_lights(), scene.vpls().len() as f64);
            }
            assert!(exact.shadow_rays > 0 && exact.direct.is_none());
            assert!(exact.rendered.image.pixels.iter().any(|p| p.x > 0.0));
        }
    }

    /// The direct light adds to the indirect light, pixel by pixel, and Lightcuts builds its
    /// tree on its own at the first render.
    #[test]
    fn direct_light_adds_and_lightcuts_builds_its_tree() {
        let camera = crate::indirect::tests::Fixture::camera(12, 9);
        let indirect = room(GiSettings {
            shadows: true,
            direct: DirectLight::Off,
            ..GiSettings::default()
        });
        let full = room(GiSettings {
            shadows: true,
            ..GiSettings::default()
        });
        let method = GiMethod::Lightcuts {
            relative_error: 0.02,
        };
        let a = indirect.render(method, &camera, &()).unwrap();
        let b = full.render(method, &camera, &()).unwrap();
        assert!(b.direct.unwrap().max_rays_per_point >= 1);
        let brighter = a.rendered.image.pixels.iter().zip(&b.rendered.image.pixels);
        assert!(brighter.clone().all(|(a, b)| b.cmpge(*a).all()));
        assert!(brighter.clone().any(|(a, b)| b.x > a.x));
    }

    /// Bad settings and parameters are refused before any work.
    #[test]
    fn bad_settings_are_refused() {
        let bad = |settings: GiSettings| settings.check().unwrap_err().to_string();
        let gaussian = GiSettings {
            coarse_shadows: CoarseShadows::Gaussian,
            ..GiSettings::default()
        };
        assert!(bad(GiSettings {
            shadow_samples: Some(2000.0),
            ..gaussian
        })
        .contains("--shadow-samples 2000"));
        assert!(bad(GiSettings {
            shadow_samples: Some(1.5),
            sample_allocation: Some(SampleAllocation::Uniform),
            ..GiSettings::default()
        })
        .contains("whole number"));
        // The adaptive sharing's mean may go below one, down to a quarter; the others' may not.
        let mean = |k: f32, allocation| GiSettings {
            shadow_samples: Some(k),
            sample_allocation: Some(allocation),
            ..GiSettings::default()
        };
        assert!(mean(MIN_ADAPTIVE_SAMPLES, SampleAllocation::Adaptive)
            .check()
            .is_ok());
        assert!(bad(mean(0.2, SampleAllocation::Adaptive)).contains("from 0.25 to 64"));
        assert!(bad(mean(0.5, SampleAllocation::Intensity)).contains("from 1 to 64"));
        assert!(bad(GiSettings {
            max_shadow_samples: Some(65),
            ..GiSettings::default()
        })
        .contains("--max-shadow-samples"));
        assert_eq!(
            GiSettings {
                aggregation: Aggregation::Buckets,
                sample_allocation: Some(SampleAllocation::Adaptive),
                ..GiSettings::default()
            }
            .check(),
            Err(GiError::AdaptiveBuckets)
        );
        // Candidates: a power of two up to 16.
        let candidates = |candidates| GiSettings {
            candidates,
            ..GiSettings::default()
        };
        for ok in [1, 2, 4, 8, 16] {
            assert!(candidates(ok).check().is_ok(), "{ok}");
        }
        for no in [0, 3, 6, 32] {
            assert_eq!(
                candidates(no).check(),
                Err(GiError::Candidates { candidates: no })
            );
        }
        assert!(bad(candidates(3)).contains("--candidates 3: expected 1, 2, 4, 8 or 16"));
        assert!(GiMethod::Lightcuts {
            relative_error: 0.0
        }
        .check()
        .is_err());
        assert!(GiMethod::Lgh { alpha: f32::NAN }.check().is_err());
        let none = GiScene::prepare(room_mesh(), [] as [PrimaryLight; 0], &GiSettings::default());
        assert_eq!(none.err(), Some(GiError::Vpl(VplError::NoLights)));
    }
}
