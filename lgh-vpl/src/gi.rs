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
//! through the BVH ([`crate::indirect`]; coarse lights shaded as [`CoarseShading`] says: the
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
use crate::indirect::lobe::DEFAULT_LOBE_ERROR;
use crate::indirect::refine::DEFAULT_POINT_ERROR;
use crate::indirect::resample::{DEFAULT_CANDIDATES, MAX_CANDIDATES};
use crate::indirect::BlendAt;
use crate::indirect::{
    point_lights, render_buckets, render_input_lights, render_lgh, Coarse, Indirect,
    IndirectSettings, NormalBuckets,
};
use crate::mesh::Mesh;
use crate::primary::{area_lights, PrimaryLight};
use crate::render::{RenderError, Rendered};
use crate::representatives::{Allocation, Representatives, MAX_PER_LIGHT};
use crate::scene::Scene;
use crate::specular::DEFAULT_SPECULAR_DEPTH;
use crate::vpl::{trace, Vpl, VplError, VplSettings, Vpls};
use lgh_image::camera::{CameraError, Pinhole as Camera};

/// How a hierarchy aggregates the VPLs, for the coarse shadings drawn once per light
/// ([`CoarseShading::Gaussian`], [`CoarseShading::Representatives`]); the adaptive shading
/// shares its samples over the one isotropic hierarchy, so it has none to choose.
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
    ///
    /// ```
    /// use lgh_vpl::gi::Aggregation;
    /// assert_eq!(Aggregation::default().name(), "isotropic");
    /// ```
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Aggregation::Isotropic => "isotropic",
            Aggregation::Buckets => "buckets",
        }
    }
}

/// How many representatives each coarse light draws, once per light, with
/// [`CoarseShading::Representatives`] ([`crate::representatives`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PerLight {
    /// The same number for every coarse light.
    Uniform {
        /// Representatives of each light, 1 to [`MAX_PER_LIGHT`].
        samples: u32,
    },
    /// Per light, in proportion to its luminance against its level's mean.
    ByIntensity {
        /// The mean number per light, 1 to [`MAX_PER_LIGHT`].
        mean: f32,
        /// The most one light draws, 1 to [`MAX_PER_LIGHT`].
        max: u32,
    },
}

impl PerLight {
    /// Its name, as `lgh gi --sample-allocation` spells it: `uniform` or `intensity`.
    ///
    /// ```
    /// use lgh_vpl::gi::PerLight;
    /// assert_eq!(PerLight::Uniform { samples: 2 }.name(), "uniform");
    /// assert_eq!(PerLight::ByIntensity { mean: 2.0, max: 16 }.name(), "intensity");
    /// ```
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            PerLight::Uniform { .. } => "uniform",
            PerLight::ByIntensity { .. } => "intensity",
        }
    }

    /// How the representatives are drawn.
    fn allocation(self) -> Allocation {
        match self {
            PerLight::Uniform { samples } => Allocation::Uniform(samples),
            PerLight::ByIntensity { mean, max } => Allocation::ByIntensity { mean, max },
        }
    }
}

/// The settings of [`CoarseShading::Adaptive`], the default: representatives shared per
/// shading point over the one isotropic hierarchy ([`crate::indirect::Coarse::Adaptive`]).
/// [`Default`] is `lgh gi`'s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveShading {
    /// The mean draws per coarse light, shared among a point's coarse lights in proportion
    /// to what each brings there unshadowed: [`MIN_ADAPTIVE_SAMPLES`] to [`MAX_PER_LIGHT`]
    /// (below one, most lights take their draw by roulette). Default
    /// [`DEFAULT_ADAPTIVE_SAMPLES`].
    pub mean_samples: f32,
    /// The most representatives one coarse light has, 1 to [`MAX_PER_LIGHT`], rounded down to
    /// a power of two (the nested prefixes). Default 32: a light that dominates a point may
    /// take many.
    pub max_samples: u32,
    /// The bound ε (relative to a point's reflected light, [`crate::indirect::lobe`]) at
    /// which a glossy lobe too sharp for the hierarchy is split, its VPLs in the lobe's cone
    /// shaded one by one; `None`: the hierarchy alone everywhere. Finite and above 0; default
    /// [`DEFAULT_LOBE_ERROR`].
    pub lobe_error: Option<f32>,
    /// The bound ε on each shading point's error at which its coarse lights are shaded again
    /// with more representatives, while the point's estimated error (1.645 standard errors,
    /// [`crate::indirect::refine`]) exceeds ε of its light; `None`: the mean number
    /// everywhere. Finite and above 0; default [`DEFAULT_POINT_ERROR`].
    pub point_error: Option<f32>,
    /// Where a coarse light's blending weight `B_ℓ` (eq. 3) is taken: at each
    /// representative's own distance (the default: unbiased against brute force) or at the
    /// light's centre ([`BlendAt`]).
    pub blend: BlendAt,
    /// The candidates each of a coarse light's draws looks at, one picked for its shadow ray
    /// by what each gives unshadowed ([`crate::indirect::resample`]): a power of two from 1 to
    /// [`MAX_CANDIDATES`] (so that a light's draws look at a power-of-two prefix of its nested
    /// representatives), 1 drawing each representative on its own. Default
    /// [`DEFAULT_CANDIDATES`].
    pub candidates: u32,
}

impl Default for AdaptiveShading {
    /// [`DEFAULT_ADAPTIVE_SAMPLES`] draws per coarse light on average, at most 32
    /// representatives, the lobe bound [`DEFAULT_LOBE_ERROR`], the point bound
    /// [`DEFAULT_POINT_ERROR`], blended per representative, each draw resampled among
    /// [`DEFAULT_CANDIDATES`].
    fn default() -> Self {
        AdaptiveShading {
            mean_samples: DEFAULT_ADAPTIVE_SAMPLES,
            max_samples: 32,
            lobe_error: Some(DEFAULT_LOBE_ERROR),
            point_error: Some(DEFAULT_POINT_ERROR),
            blend: BlendAt::Representative,
            candidates: DEFAULT_CANDIDATES,
        }
    }
}

/// How [`GiMethod::Lgh`] shades the hierarchy's coarse lights (levels ≥ 1), each way with
/// exactly the settings that apply to it (paper Sec. 6.4, Fig. 11; ARCHITECTURE.md, "From an
/// OBJ to an EXR"). [`Default`] is `lgh gi`'s: [`CoarseShading::adaptive`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CoarseShading {
    /// The paper's (Sec. 6.4, Fig. 11d): each coarse light a volume light, shaded through
    /// `samples` points drawn with its variance σ² (eq. 4), each with a shadow ray.
    Gaussian {
        /// Samples `k` per coarse light, 0 to [`MAX_GAUSSIAN_SAMPLES`]; 0 shades it as a
        /// point (Fig. 11c).
        samples: u32,
        /// How the VPLs are aggregated (with [`Aggregation::Buckets`] each sample emits its
        /// bucket's lobe).
        aggregation: Aggregation,
    },
    /// Beyond the paper: each coarse light shaded through some of the VPLs it stands for,
    /// drawn once per light by weight, each with its own lobe and shadow ray
    /// ([`crate::representatives`]).
    Representatives {
        /// How many each light draws.
        per_light: PerLight,
        /// How the VPLs are aggregated.
        aggregation: Aggregation,
    },
    /// Beyond the paper, the default: representatives shared per shading point over the one
    /// isotropic hierarchy, split lobes and a per-point error bound ([`AdaptiveShading`]).
    Adaptive(AdaptiveShading),
}

impl Default for CoarseShading {
    /// [`CoarseShading::adaptive`].
    fn default() -> Self {
        CoarseShading::adaptive()
    }
}

impl CoarseShading {
    /// The default shading, representatives shared per point, with [`AdaptiveShading`]'s
    /// defaults.
    ///
    /// ```
    /// use lgh_vpl::gi::{Aggregation, CoarseShading, DEFAULT_ADAPTIVE_SAMPLES};
    /// let CoarseShading::Adaptive(a) = CoarseShading::adaptive() else { unreachable!() };
    /// assert_eq!((a.mean_samples, a.max_samples), (DEFAULT_ADAPTIVE_SAMPLES, 32));
    /// assert_eq!(CoarseShading::adaptive().aggregation(), Aggregation::Isotropic);
    /// ```
    #[must_use]
    pub fn adaptive() -> Self {
        CoarseShading::Adaptive(AdaptiveShading::default())
    }

    /// The paper's Gaussian samples (Fig. 11d): 9 per coarse light, one hierarchy.
    ///
    /// ```
    /// use lgh_vpl::gi::{Aggregation, CoarseShading};
    /// assert_eq!(
    ///     CoarseShading::gaussian(),
    ///     CoarseShading::Gaussian { samples: 9, aggregation: Aggregation::Isotropic }
    /// );
    /// ```
    #[must_use]
    pub fn gaussian() -> Self {
        CoarseShading::Gaussian {
            samples: DEFAULT_GAUSSIAN_SAMPLES,
            aggregation: Aggregation::Isotropic,
        }
    }

    /// Representatives drawn once per light in proportion to its luminance: 2 per light on
    /// average, at most 16, one hierarchy.
    ///
    /// ```
    /// use lgh_vpl::gi::{Aggregation, CoarseShading, PerLight};
    /// assert_eq!(
    ///     CoarseShading::by_intensity(),
    ///     CoarseShading::Representatives {
    ///         per_light: PerLight::ByIntensity { mean: 2.0, max: 16 },
    ///         aggregation: Aggregation::Isotropic,
    ///     }
    /// );
    /// ```
    #[must_use]
    pub fn by_intensity() -> Self {
        CoarseShading::Representatives {
            per_light: PerLight::ByIntensity {
                mean: DEFAULT_REPRESENTATIVES as f32,
                max: DEFAULT_MAX_BY_INTENSITY,
            },
            aggregation: Aggregation::Isotropic,
        }
    }

    /// Representatives drawn once per light, 2 for every light, one hierarchy.
    ///
    /// ```
    /// use lgh_vpl::gi::{CoarseShading, PerLight};
    /// let CoarseShading::Representatives { per_light, .. } = CoarseShading::uniform() else {
    ///     unreachable!()
    /// };
    /// assert_eq!(per_light, PerLight::Uniform { samples: 2 });
    /// ```
    #[must_use]
    pub fn uniform() -> Self {
        CoarseShading::Representatives {
            per_light: PerLight::Uniform {
                samples: DEFAULT_REPRESENTATIVES,
            },
            aggregation: Aggregation::Isotropic,
        }
    }

    /// The same shading with `aggregation`, or `None` for the adaptive shading, which has
    /// only the one isotropic hierarchy.
    ///
    /// ```
    /// use lgh_vpl::gi::{Aggregation, CoarseShading};
    /// let buckets = CoarseShading::gaussian().with_aggregation(Aggregation::Buckets);
    /// assert_eq!(buckets.map(|c| c.aggregation()), Some(Aggregation::Buckets));
    /// assert_eq!(CoarseShading::adaptive().with_aggregation(Aggregation::Buckets), None);
    /// ```
    #[must_use]
    pub fn with_aggregation(self, aggregation: Aggregation) -> Option<Self> {
        match self {
            CoarseShading::Gaussian { samples, .. } => Some(CoarseShading::Gaussian {
                samples,
                aggregation,
            }),
            CoarseShading::Representatives { per_light, .. } => {
                Some(CoarseShading::Representatives {
                    per_light,
                    aggregation,
                })
            }
            CoarseShading::Adaptive(_) if aggregation == Aggregation::Isotropic => Some(self),
            CoarseShading::Adaptive(_) => None,
        }
    }

    /// How the VPLs are aggregated: the variant's own, [`Aggregation::Isotropic`] for the
    /// adaptive shading.
    ///
    /// ```
    /// use lgh_vpl::gi::{Aggregation, CoarseShading};
    /// assert_eq!(CoarseShading::default().aggregation(), Aggregation::Isotropic);
    /// ```
    #[must_use]
    pub fn aggregation(&self) -> Aggregation {
        match *self {
            CoarseShading::Gaussian { aggregation, .. }
            | CoarseShading::Representatives { aggregation, .. } => aggregation,
            CoarseShading::Adaptive(_) => Aggregation::Isotropic,
        }
    }

    /// Where the samples lie, as `lgh gi --coarse-shadows` spells it: `gaussian` or
    /// `representatives` (both ways of drawing representatives).
    ///
    /// ```
    /// use lgh_vpl::gi::CoarseShading;
    /// assert_eq!(CoarseShading::gaussian().name(), "gaussian");
    /// assert_eq!(CoarseShading::adaptive().name(), "representatives");
    /// ```
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            CoarseShading::Gaussian { .. } => "gaussian",
            CoarseShading::Representatives { .. } | CoarseShading::Adaptive(_) => "representatives",
        }
    }

    /// Checks every number against its range (the types say the rest).
    ///
    /// Errors: [`GiError::Samples`], [`GiError::LobeError`], [`GiError::PointError`],
    /// [`GiError::Candidates`].
    ///
    /// ```
    /// use lgh_vpl::gi::{AdaptiveShading, CoarseShading, GiError, SampleSetting};
    /// assert!(CoarseShading::default().check().is_ok());
    /// let few = CoarseShading::Adaptive(AdaptiveShading { mean_samples: 0.2, ..Default::default() });
    /// assert!(matches!(
    ///     few.check(),
    ///     Err(GiError::Samples { setting: SampleSetting::AdaptiveMean, .. })
    /// ));
    /// ```
    pub fn check(&self) -> Result<(), GiError> {
        let per_light = MAX_PER_LIGHT as f32;
        let range = |setting: SampleSetting, value: f32, min: f32, max: f32| {
            if value.is_finite() && value >= min && value <= max {
                Ok(())
            } else {
                Err(GiError::Samples {
                    setting,
                    value,
                    min,
                    max,
                })
            }
        };
        let bound = |error: Option<f32>| error.is_none_or(|e| e.is_finite() && e > 0.0);
        match *self {
            CoarseShading::Gaussian { samples, .. } => range(
                SampleSetting::Gaussian,
                samples as f32,
                0.0,
                MAX_GAUSSIAN_SAMPLES as f32,
            ),
            CoarseShading::Representatives {
                per_light: PerLight::Uniform { samples },
                ..
            } => range(SampleSetting::Uniform, samples as f32, 1.0, per_light),
            CoarseShading::Representatives {
                per_light: PerLight::ByIntensity { mean, max },
                ..
            } => {
                range(SampleSetting::IntensityMean, mean, 1.0, per_light)?;
                range(SampleSetting::IntensityMax, max as f32, 1.0, per_light)
            }
            CoarseShading::Adaptive(a) => {
                // A mean shared per point: below one, most lights take their sample by
                // roulette.
                let mean = a.mean_samples;
                range(
                    SampleSetting::AdaptiveMean,
                    mean,
                    MIN_ADAPTIVE_SAMPLES,
                    per_light,
                )?;
                range(
                    SampleSetting::AdaptiveMax,
                    a.max_samples as f32,
                    1.0,
                    per_light,
                )?;
                if !bound(a.lobe_error) {
                    return Err(GiError::LobeError {
                        error: a.lobe_error.unwrap_or_default(),
                    });
                }
                if !bound(a.point_error) {
                    return Err(GiError::PointError {
                        error: a.point_error.unwrap_or_default(),
                    });
                }
                if !(1..=MAX_CANDIDATES).contains(&a.candidates) || !a.candidates.is_power_of_two()
                {
                    return Err(GiError::Candidates {
                        candidates: a.candidates,
                    });
                }
                Ok(())
            }
        }
    }

    /// The Gaussian samples of a coarse light shaded as the paper's volume light
    /// ([`IndirectSettings::gaussian_samples`]): the Gaussian shading's `samples`; for
    /// representatives drawn once per light, the whole part of their (mean) number, what a
    /// light without representatives (one without weight) is shaded with; none for the
    /// adaptive shading, which never shades a coarse light as a volume light.
    fn gaussian_samples(&self) -> u32 {
        match *self {
            CoarseShading::Gaussian { samples, .. } => samples,
            CoarseShading::Representatives {
                per_light: PerLight::Uniform { samples },
                ..
            } => samples,
            CoarseShading::Representatives {
                per_light: PerLight::ByIntensity { mean, .. },
                ..
            } => mean as u32,
            CoarseShading::Adaptive(_) => 0,
        }
    }
}

/// A number of [`CoarseShading`]'s samples, named in [`GiError::Samples`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SampleSetting {
    /// [`CoarseShading::Gaussian`]'s `samples`.
    Gaussian,
    /// [`PerLight::Uniform`]'s `samples`.
    Uniform,
    /// [`PerLight::ByIntensity`]'s `mean`.
    IntensityMean,
    /// [`PerLight::ByIntensity`]'s `max`.
    IntensityMax,
    /// [`AdaptiveShading::mean_samples`].
    AdaptiveMean,
    /// [`AdaptiveShading::max_samples`].
    AdaptiveMax,
}

impl SampleSetting {
    /// Its name in the library: `CoarseShading::Gaussian samples`, `PerLight::ByIntensity
    /// max`, `AdaptiveShading::mean_samples`, ….
    ///
    /// ```
    /// use lgh_vpl::gi::SampleSetting;
    /// assert_eq!(SampleSetting::AdaptiveMean.name(), "AdaptiveShading::mean_samples");
    /// ```
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            SampleSetting::Gaussian => "CoarseShading::Gaussian samples",
            SampleSetting::Uniform => "PerLight::Uniform samples",
            SampleSetting::IntensityMean => "PerLight::ByIntensity mean",
            SampleSetting::IntensityMax => "PerLight::ByIntensity max",
            SampleSetting::AdaptiveMean => "AdaptiveShading::mean_samples",
            SampleSetting::AdaptiveMax => "AdaptiveShading::max_samples",
        }
    }

    /// Whether it is a most (`max`), not a number of samples.
    ///
    /// ```
    /// use lgh_vpl::gi::SampleSetting;
    /// assert!(SampleSetting::AdaptiveMax.is_max() && !SampleSetting::Uniform.is_max());
    /// ```
    #[must_use]
    pub fn is_max(self) -> bool {
        matches!(
            self,
            SampleSetting::IntensityMax | SampleSetting::AdaptiveMax
        )
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
/// [`Default`] is `lgh gi`'s defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GiSettings {
    /// How many VPLs (at least), how many bounces, which seed (also the seed of Lightcuts'
    /// representatives).
    pub vpls: VplSettings,
    /// How [`GiMethod::Lgh`] aggregates the VPLs and shades its coarse lights.
    pub coarse: CoarseShading,
    /// Whether shadow rays are traced (false: every VPL reaches every point it faces).
    pub shadows: bool,
    /// Whether renders add the direct light.
    pub direct: DirectLight,
    /// The most mirrors and glass surfaces a camera or light path follows, 0 to
    /// [`MAX_SPECULAR_DEPTH`] ([`crate::specular`]).
    pub specular_depth: u32,
}

/// The Gaussian samples of [`CoarseShading::gaussian`]: 9, the paper's Fig. 11d.
pub const DEFAULT_GAUSSIAN_SAMPLES: u32 = 9;

/// The representatives a light draws with [`CoarseShading::uniform`], and their mean with
/// [`CoarseShading::by_intensity`]: 2.
pub const DEFAULT_REPRESENTATIVES: u32 = 2;

/// The most representatives one light draws with [`CoarseShading::by_intensity`]: 16.
pub const DEFAULT_MAX_BY_INTENSITY: u32 = 16;

/// The least [`AdaptiveShading::mean_samples`]: 1/4 (shared per point, so below one most
/// lights take their sample by roulette; below a quarter the point bound would do nearly all
/// the work).
pub const MIN_ADAPTIVE_SAMPLES: f32 = 0.25;

/// The mean draws per coarse light of the adaptive shading by default
/// ([`AdaptiveShading::mean_samples`]): 0.35. With the lights that face away left out
/// ([`crate::facing`]) and the ray roulette ([`crate::indirect::resample`]), `lgh bench gi`
/// at α = 4 and 365K VPLs measured, for 0.5, 0.4 and 0.35: Sponza (two runs of three
/// renders each) 2.07%, 2.30% and 2.50% at 52–53×, 52× and 55–58× brute force's speed, the
/// Cornell box (one run each) 1.57%, 1.73% and 1.99% at 100×, 116× and 114×; 0.35 keeps
/// both under the figures the earlier model was measured at (2.68% and 2.29%), at about
/// those figures' speed.
pub const DEFAULT_ADAPTIVE_SAMPLES: f32 = 0.35;

/// The most Gaussian samples of a coarse light ([`CoarseShading::Gaussian`]): 1024.
pub const MAX_GAUSSIAN_SAMPLES: u32 = 1024;

/// The largest [`GiSettings::specular_depth`]: 32. (A camera path's branches carrying at least
/// [`crate::specular::MIN_WEIGHT`] each are at most 1/`MIN_WEIGHT` = 1000, whatever the depth.)
pub const MAX_SPECULAR_DEPTH: u32 = 32;

impl Default for GiSettings {
    /// [`VplSettings::default`] (100,000 VPLs of up to 3 bounces, seed 1),
    /// [`CoarseShading::adaptive`] (representatives shared per point over the one hierarchy,
    /// [`DEFAULT_ADAPTIVE_SAMPLES`] draws per coarse light on average, each resampled among
    /// 4, at most 32 representatives), shadow rays, and the direct light through 4 × 4 strata.
    fn default() -> Self {
        GiSettings {
            vpls: VplSettings::default(),
            coarse: CoarseShading::default(),
            shadows: true,
            direct: DirectLight::default(),
            specular_depth: DEFAULT_SPECULAR_DEPTH,
        }
    }
}

impl GiSettings {
    /// Checks the settings before any work ([`GiScene::prepare`] does too): the coarse
    /// shading's numbers ([`CoarseShading::check`]), the specular depth, 1 to 64 strata. (The
    /// VPL counts are checked by [`trace`].)
    ///
    /// Errors: [`CoarseShading::check`]'s, [`GiError::AreaStrata`], [`GiError::SpecularDepth`].
    ///
    /// ```
    /// use lgh_vpl::gi::{GiError, GiSettings};
    /// assert!(GiSettings::default().check().is_ok());
    /// let deep = GiSettings { specular_depth: 33, ..GiSettings::default() };
    /// assert_eq!(deep.check(), Err(GiError::SpecularDepth { depth: 33 }));
    /// ```
    pub fn check(&self) -> Result<(), GiError> {
        self.coarse.check()?;
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

/// Why a [`GiScene`] could not be prepared or rendered. Messages name the library's settings
/// (`AdaptiveShading::candidates 3: …`); a command line words them with its own flags.
#[derive(Clone, Debug, PartialEq)]
pub enum GiError {
    /// A number of samples of [`CoarseShading`] outside `min..=max`.
    Samples {
        /// Which one.
        setting: SampleSetting,
        /// The rejected value.
        value: f32,
        /// The least allowed.
        min: f32,
        /// The most allowed.
        max: f32,
    },
    /// [`DirectLight::Stratified`]'s strata per side outside 1 to 64.
    AreaStrata {
        /// The rejected value.
        area_strata: u32,
    },
    /// [`AdaptiveShading::lobe_error`] not finite and above 0.
    LobeError {
        /// The rejected value.
        error: f32,
    },
    /// [`AdaptiveShading::point_error`] not finite and above 0.
    PointError {
        /// The rejected value.
        error: f32,
    },
    /// [`AdaptiveShading::candidates`] not a power of two from 1 to [`MAX_CANDIDATES`].
    Candidates {
        /// The rejected value.
        candidates: u32,
    },
    /// [`GiSettings::specular_depth`] over [`MAX_SPECULAR_DEPTH`].
    SpecularDepth {
        /// The rejected value.
        depth: u32,
    },
    /// [`GiMethod::Lightcuts`]' relative error not finite and positive.
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

/// The candidates [`AdaptiveShading::candidates`] takes, in words: "1, 2, 4, 8 or 16".
///
/// ```
/// assert_eq!(lgh_vpl::gi::candidate_values(), "1, 2, 4, 8 or 16");
/// ```
#[must_use]
pub fn candidate_values() -> String {
    let powers: Vec<String> = (0..=MAX_CANDIDATES.ilog2())
        .map(|k| (1u32 << k).to_string())
        .collect();
    match powers.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => powers.join(""),
    }
}

/// A setting of [`GiSettings`] or [`GiMethod`] that a [`GiError`] refuses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GiSetting {
    /// A number of [`CoarseShading`]'s samples.
    Samples(SampleSetting),
    /// [`DirectLight::Stratified`]'s `area_strata`.
    AreaStrata,
    /// [`AdaptiveShading::lobe_error`].
    LobeError,
    /// [`AdaptiveShading::point_error`].
    PointError,
    /// [`AdaptiveShading::candidates`].
    Candidates,
    /// [`GiSettings::specular_depth`].
    SpecularDepth,
    /// [`GiMethod::Lightcuts`]' `relative_error`.
    RelativeError,
}

impl GiSetting {
    /// Its name in the library, with the setting that holds it:
    /// `GiSettings::coarse: AdaptiveShading::candidates`.
    ///
    /// ```
    /// use lgh_vpl::gi::GiSetting;
    /// assert_eq!(GiSetting::SpecularDepth.name(), "GiSettings::specular_depth");
    /// ```
    #[must_use]
    pub fn name(self) -> String {
        match self {
            GiSetting::Samples(s) => format!("GiSettings::coarse: {}", s.name()),
            GiSetting::AreaStrata => {
                "GiSettings::direct: DirectLight::Stratified area_strata".into()
            }
            GiSetting::LobeError => "GiSettings::coarse: AdaptiveShading::lobe_error".into(),
            GiSetting::PointError => "GiSettings::coarse: AdaptiveShading::point_error".into(),
            GiSetting::Candidates => "GiSettings::coarse: AdaptiveShading::candidates".into(),
            GiSetting::SpecularDepth => "GiSettings::specular_depth".into(),
            GiSetting::RelativeError => "GiMethod::Lightcuts relative_error".into(),
        }
    }

    /// Whether the setting is an `Option` whose `None` turns it off (a bound).
    ///
    /// ```
    /// use lgh_vpl::gi::GiSetting;
    /// assert!(GiSetting::PointError.optional() && !GiSetting::Candidates.optional());
    /// ```
    #[must_use]
    pub fn optional(self) -> bool {
        matches!(self, GiSetting::LobeError | GiSetting::PointError)
    }
}

/// A refused setting, in parts, so that a caller with other names for the settings (a command
/// line's flags) can word it with those: the error's message is
/// `{name} {value}: {expected}` (and ` or None` for an [`optional`](GiSetting::optional) one).
#[derive(Clone, Debug, PartialEq)]
pub struct Refusal {
    /// Which setting.
    pub setting: GiSetting,
    /// The rejected value, as the message writes it.
    pub value: String,
    /// What it takes: `expected 1 to 64`.
    pub expected: String,
}

impl GiError {
    /// The refused setting, if the error is one (`None` for the errors of the work itself).
    ///
    /// ```
    /// use lgh_vpl::gi::{GiError, GiSetting};
    /// let r = GiError::SpecularDepth { depth: 40 }.refusal().unwrap();
    /// assert_eq!((r.setting, r.value.as_str(), r.expected.as_str()),
    ///            (GiSetting::SpecularDepth, "40", "expected 0 to 32"));
    /// ```
    #[must_use]
    pub fn refusal(&self) -> Option<Refusal> {
        let (setting, value, expected) = match *self {
            GiError::Samples {
                setting,
                value,
                min,
                max,
            } => (
                GiSetting::Samples(setting),
                value.to_string(),
                format!("expected {min} to {max}"),
            ),
            GiError::AreaStrata { area_strata } => (
                GiSetting::AreaStrata,
                area_strata.to_string(),
                "expected 1 to 64".to_string(),
            ),
            GiError::LobeError { error } => (
                GiSetting::LobeError,
                error.to_string(),
                "expected a positive number (0.01 is 1% of a point's diffuse light)".to_string(),
            ),
            GiError::PointError { error } => (
                GiSetting::PointError,
                error.to_string(),
                "expected a positive number (0.1 is 10% of a point's light)".to_string(),
            ),
            GiError::Candidates { candidates } => (
                GiSetting::Candidates,
                candidates.to_string(),
                format!(
                    "expected {} (1 draws each representative on its own)",
                    candidate_values()
                ),
            ),
            GiError::SpecularDepth { depth } => (
                GiSetting::SpecularDepth,
                depth.to_string(),
                format!("expected 0 to {MAX_SPECULAR_DEPTH}"),
            ),
            GiError::RelativeError { relative_error } => (
                GiSetting::RelativeError,
                relative_error.to_string(),
                "expected a positive number (0.02 is 2%)".to_string(),
            ),
            GiError::Vpl(_) | GiError::Build(_) | GiError::Query(_) | GiError::Render(_) => {
                return None
            }
        };
        Some(Refusal {
            setting,
            value,
            expected,
        })
    }
}

impl std::fmt::Display for GiError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some(r) = self.refusal() {
            let or_none = if r.setting.optional() { " or None" } else { "" };
            return write!(
                f,
                "{} {}: {}{or_none}",
                r.setting.name(),
                r.value,
                r.expected
            );
        }
        match self {
            GiError::Vpl(e) => write!(f, "{e}"),
            GiError::Build(e) => write!(f, "{e}"),
            GiError::Query(e) => write!(f, "{e}"),
            GiError::Render(e) => write!(f, "{e}"),
            // Refusals, written above.
            _ => Ok(()),
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
    /// one by one ([`AdaptiveShading::lobe_error`]).
    pub lobe_split_points: u64,
    /// Shading points whose coarse lights were shaded again with more representatives, their
    /// estimated error over the bound ([`AdaptiveShading::point_error`]).
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
        // The bounds only the adaptive shading reads.
        let adaptive = match settings.coarse {
            CoarseShading::Adaptive(a) => Some(a),
            _ => None,
        };
        let shading = IndirectSettings {
            h0: lgh.h0(),
            gaussian_samples: settings.coarse.gaussian_samples(),
            epsilon: 1e-4 * (hi - lo).length(),
            shadows: settings.shadows,
            lobe_error: adaptive.and_then(|a| a.lobe_error),
            point_error: adaptive.and_then(|a| a.point_error),
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
                    let coarse = match (reps, self.settings.coarse) {
                        (None, _) => Coarse::Gaussian,
                        (Some(reps), CoarseShading::Adaptive(a)) => Coarse::Adaptive {
                            reps,
                            mean: a.mean_samples,
                            blend: a.blend,
                            candidates: a.candidates,
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
            let vpls = &self.traced.vpls;
            let buckets = || NormalBuckets::build(vpls, &GridSettings::default());
            let drawn = |allocation| Representatives::build_for(&self.lgh, allocation, vpls);
            Ok(match self.settings.coarse {
                CoarseShading::Gaussian { aggregation, .. } => match aggregation {
                    Aggregation::Isotropic => LghExtras::Isotropic(None),
                    Aggregation::Buckets => LghExtras::Buckets(buckets()?),
                },
                CoarseShading::Representatives {
                    per_light,
                    aggregation,
                } => match aggregation {
                    Aggregation::Isotropic => {
                        LghExtras::Isotropic(Some(drawn(per_light.allocation())))
                    }
                    Aggregation::Buckets => {
                        LghExtras::Buckets(buckets()?.with_representatives(per_light.allocation()))
                    }
                },
                CoarseShading::Adaptive(a) => {
                    LghExtras::Isotropic(Some(drawn(Allocation::Nested(a.max_samples))))
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
        for coarse in [
            CoarseShading::adaptive(),
            CoarseShading::gaussian(),
            CoarseShading::Gaussian {
                samples: 9,
                aggregation: Aggregation::Buckets,
            },
        ] {
            let aggregation = coarse.aggregation();
            let scene = room(GiSettings {
                coarse,
                shadows: true,
                direct: DirectLight::Off,
                ..GiSettings::default()
            });
            let exact = scene.render(GiMethod::Brute, &camera, &()).unwrap();
            let got = scene
                .render(GiMethod::Lgh { alpha: 256.0 }, &camera, &())
                .unwrap();
            let e = rel_rmse(&got, &exact);
            assert!(e < 1e-5, "{coarse:?}: {e}");
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

    /// Bad settings and parameters are refused before any work, each named as the library
    /// spells it.
    #[test]
    fn bad_settings_are_refused() {
        let with = |coarse| GiSettings {
            coarse,
            ..GiSettings::default()
        };
        let bad = |coarse| with(coarse).check().unwrap_err().to_string();
        let gaussian = |samples| CoarseShading::Gaussian {
            samples,
            aggregation: Aggregation::Isotropic,
        };
        assert!(with(gaussian(MAX_GAUSSIAN_SAMPLES)).check().is_ok());
        assert_eq!(
            bad(gaussian(2000)),
            "GiSettings::coarse: CoarseShading::Gaussian samples 2000: expected 0 to 1024"
        );
        // The adaptive sharing's mean may go below one, down to a quarter; the others' may not.
        let adaptive = |a: AdaptiveShading| CoarseShading::Adaptive(a);
        let mean = |mean_samples| {
            adaptive(AdaptiveShading {
                mean_samples,
                ..AdaptiveShading::default()
            })
        };
        assert!(with(mean(MIN_ADAPTIVE_SAMPLES)).check().is_ok());
        assert!(bad(mean(0.2)).contains("AdaptiveShading::mean_samples 0.2: expected 0.25 to 64"));
        let intensity = |mean, max| CoarseShading::Representatives {
            per_light: PerLight::ByIntensity { mean, max },
            aggregation: Aggregation::Buckets,
        };
        assert!(with(intensity(1.5, 16)).check().is_ok());
        assert!(
            bad(intensity(0.5, 16)).contains("PerLight::ByIntensity mean 0.5: expected 1 to 64")
        );
        assert!(bad(intensity(2.0, 65)).contains("PerLight::ByIntensity max 65"));
        assert!(bad(adaptive(AdaptiveShading {
            max_samples: 0,
            ..AdaptiveShading::default()
        }))
        .contains("AdaptiveShading::max_samples 0"));
        let uniform = CoarseShading::Representatives {
            per_light: PerLight::Uniform { samples: 0 },
            aggregation: Aggregation::Isotropic,
        };
        assert!(bad(uniform).contains("PerLight::Uniform samples 0: expected 1 to 64"));
        // The adaptive shading has no buckets: the type says so.
        assert_eq!(
            CoarseShading::adaptive().with_aggregation(Aggregation::Buckets),
            None
        );
        for (error, name) in [
            (Some(0.0), "lobe_error 0"),
            (Some(f32::NAN), "lobe_error NaN"),
        ] {
            let a = adaptive(AdaptiveShading {
                lobe_error: error,
                ..AdaptiveShading::default()
            });
            assert!(bad(a).contains(name), "{}", bad(a));
        }
        let a = adaptive(AdaptiveShading {
            point_error: Some(-1.0),
            ..AdaptiveShading::default()
        });
        assert_eq!(with(a).check(), Err(GiError::PointError { error: -1.0 }));
        // Candidates: a power of two up to 16.
        let candidates = |candidates| {
            with(adaptive(AdaptiveShading {
                candidates,
                ..AdaptiveShading::default()
            }))
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
        assert!(candidates(3)
            .check()
            .unwrap_err()
            .to_string()
            .contains("AdaptiveShading::candidates 3: expected 1, 2, 4, 8 or 16"));
        // No message names a command-line flag.
        let strata = GiSettings {
            direct: DirectLight::Stratified { area_strata: 0 },
            ..GiSettings::default()
        };
        let e = strata.check().unwrap_err().to_string();
        assert!(e.contains("area_strata 0") && !e.contains("--"), "{e}");
        assert!(GiMethod::Lightcuts {
            relative_error: 0.0
        }
        .check()
        .is_err());
        assert!(GiMethod::Lgh { alpha: f32::NAN }.check().is_err());
        let none = GiScene::prepare(room_mesh(), [] as [PrimaryLight; 0], &GiSettings::default());
        assert_eq!(none.err(), Some(GiError::Vpl(VplError::NoLights)));
    }

    /// `Default` is `lgh gi`'s defaults, as they were before the settings became one enum.
    #[test]
    fn the_default_settings_are_lgh_gi_defaults() {
        let d = GiSettings::default();
        assert_eq!(d.vpls, VplSettings::default());
        assert!(d.shadows && d.specular_depth == DEFAULT_SPECULAR_DEPTH);
        assert_eq!(d.direct, DirectLight::Stratified { area_strata: 4 });
        let CoarseShading::Adaptive(a) = d.coarse else {
            panic!("{:?}", d.coarse)
        };
        assert_eq!(
            a,
            AdaptiveShading {
                mean_samples: 0.35,
                max_samples: 32,
                lobe_error: Some(0.01),
                point_error: Some(0.1),
                blend: BlendAt::Representative,
                candidates: 4,
            }
        );
        assert_eq!(d.coarse.aggregation(), Aggregation::Isotropic);
        // A coarse light is never shaded as a volume light by the adaptive shading.
        assert_eq!(d.coarse.gaussian_samples(), 0);
        assert_eq!(CoarseShading::gaussian().gaussian_samples(), 9);
        assert_eq!(CoarseShading::by_intensity().gaussian_samples(), 2);
    }
}
