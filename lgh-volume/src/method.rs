//! The many-lights method that shades a frame, with the parameters that belong to it, and the
//! method made ready over one frame's lights ([`FrameBackend`]).
//!
//! The hierarchy (paper Sec. 3) carries its α; Lightcuts (Walter et al. 2005, the rival of the
//! paper's Fig. 10) its ε, largest cut and representatives; brute force (the exact answer of the
//! same light model) nothing. Emission alone — the fire seen through its smoke, no light
//! scattered — is a method too, so that no renderer needs an "absent lights" mode.

use lgh_core::{
    BruteForce, Illumination, LghBackend, LightTree, LightcutsBackend, LightcutsSettings,
    ManyLights, PointLight, QueryError, Representative, Shader, ShadingPoint,
};

use crate::error::RenderError;
use crate::lighting::Lights;
use crate::lights::ExplosionLights;

/// Which many-lights method shades the light the smoke scatters, with its own parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// No lights: the emission seen through the smoke, nothing scattered (and no shadows).
    Emission,
    /// The lighting grid hierarchy (paper Sec. 3) at the paper's α (eq. 3: `r_ℓ = α h_ℓ`).
    Lgh {
        /// The blending radius factor α.
        alpha: f32,
    },
    /// Every light `S0` that shines: the exact answer of the same light model.
    Brute,
    /// Lightcuts (Walter et al. 2005, the paper's Fig. 10 rival) over a light tree of the
    /// frame's lights, shadows ray-marched. Its bounds and representatives need non-negative
    /// channels ([`lgh_core::Channels`]), so the negative channels of Blender's blackbody below
    /// about 1900 K are clamped to 0 for it: its colours are the clamped blackbody's, not
    /// Cycles' (the hierarchy and brute force keep them).
    Lightcuts {
        /// ε and the largest cut (Walter's 2% and 1000 by default).
        settings: LightcutsSettings,
        /// How a cluster's representative is chosen: at random from a seed (Walter's; the
        /// paper's comparison draws a new tree every frame) or the brightest light.
        representative: Representative,
    },
}

impl Default for Method {
    /// The hierarchy at the paper's α = 2.
    fn default() -> Self {
        Method::Lgh { alpha: 2.0 }
    }
}

impl Method {
    /// Walter et al.'s stochastic Lightcuts at 2% with representatives drawn from `seed`.
    ///
    /// ```
    /// use lgh_volume::Method;
    ///
    /// assert_eq!(Method::lightcuts(7).name(), "lightcuts");
    /// ```
    #[must_use]
    pub fn lightcuts(seed: u64) -> Self {
        Method::Lightcuts {
            settings: LightcutsSettings::default(),
            representative: Representative::Stochastic { seed },
        }
    }

    /// The method's name, as in `lgh_core`'s [`ManyLights::name`] (`emission`, `lgh`, `brute`,
    /// `lightcuts`, `lightcuts-deterministic`).
    ///
    /// ```
    /// use lgh_volume::lgh_core::{LightcutsSettings, Representative};
    /// use lgh_volume::Method;
    ///
    /// assert_eq!(Method::Lgh { alpha: 2.0 }.name(), "lgh");
    /// let brightest = Method::Lightcuts {
    ///     settings: LightcutsSettings::default(),
    ///     representative: Representative::Brightest,
    /// };
    /// assert_eq!(brightest.name(), "lightcuts-deterministic");
    /// ```
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Method::Emission => "emission",
            Method::Lgh { .. } => "lgh",
            Method::Brute => "brute",
            Method::Lightcuts {
                representative: Representative::Stochastic { .. },
                ..
            } => "lightcuts",
            Method::Lightcuts {
                representative: Representative::Brightest,
                ..
            } => "lightcuts-deterministic",
        }
    }

    /// The hierarchy's α, for [`Method::Lgh`] only.
    #[must_use]
    pub fn alpha(self) -> Option<f32> {
        match self {
            Method::Lgh { alpha } => Some(alpha),
            _ => None,
        }
    }

    /// Checks the method's own parameters (α of the hierarchy, Lightcuts' ε and cut) before any
    /// work.
    ///
    /// ```
    /// use lgh_volume::Method;
    ///
    /// assert!(Method::Lgh { alpha: 2.0 }.check().is_ok());
    /// assert!(Method::Lgh { alpha: 0.0 }.check().is_err());
    /// assert!(Method::Brute.check().is_ok());
    /// ```
    pub fn check(self) -> Result<(), RenderError> {
        match self {
            Method::Lgh { alpha } => lgh_core::check_alpha(alpha)?,
            Method::Lightcuts { settings, .. } => settings.check()?,
            Method::Emission | Method::Brute => {}
        }
        Ok(())
    }

    /// The method made ready over `lights` as they are now: the hierarchy's blending for α
    /// (once; with the lights' hard-switch variant), brute force's lights that shine, or
    /// Lightcuts' tree.
    pub(crate) fn prepare(self, lights: &ExplosionLights) -> Result<Prepared, RenderError> {
        let lit = || -> Vec<PointLight> {
            lights
                .lights()
                .iter()
                .copied()
                .filter(|l| l.intensity.max_element() > 0.0)
                .collect()
        };
        Ok(match self {
            Method::Emission => Prepared::Emission,
            Method::Lgh { alpha } => {
                let blending = lights
                    .hierarchy()
                    .blending_with(alpha, lights.coarse_spread())?;
                let shading = if lights.variants().hard_switches {
                    blending.with_hard_switches()
                } else {
                    blending
                };
                // Checked once here; the backend is remade per render from the blending.
                LghBackend::with_blending(lights.hierarchy(), shading)?;
                Prepared::Lgh { blending, shading }
            }
            Method::Brute => Prepared::Brute(BruteForce::new(&lit())?),
            Method::Lightcuts {
                settings,
                representative,
            } => {
                // Clamped: see the variant's docs.
                let clamped: Vec<PointLight> = lit()
                    .into_iter()
                    .map(|l| {
                        PointLight::new(l.position, l.intensity.max(lgh_core::glam::Vec3::ZERO))
                    })
                    .collect();
                let tree = LightTree::build(&clamped, representative)?;
                // Checked once here; the backend is remade per query from the tree it owns.
                LightcutsBackend::new(&tree, settings)?;
                Prepared::Lightcuts(Box::new(tree), settings)
            }
        })
    }
}

/// A [`Method`] made ready over one frame's lights, owning what it built (a
/// [`FrameRender`](crate::FrameRender) keeps it beside the lights it was built from).
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub(crate) enum Prepared {
    /// No lights.
    Emission,
    /// The hierarchy's blending for α (eq. 3): the paper's, whose radii the shadows reach,
    /// and the one the lights are shaded with (the same, or its hard-switch variant).
    Lgh {
        /// Eq. (3)'s blending.
        blending: lgh_core::Blending,
        /// The blending of the backend, checked against the hierarchy.
        shading: lgh_core::Blending,
    },
    /// Every light that shines this frame.
    Brute(BruteForce),
    /// Lightcuts over a light tree of the frame's lights.
    Lightcuts(Box<LightTree>, LightcutsSettings),
}

impl Prepared {
    /// The lights to shade with: `lights` (those this was prepared from) through the method,
    /// with their light model: voxel lights of side `h`, or points with the fall-off clamped at
    /// the voxel size (`h0 = h`, paper Sec. 6.1); `None` for emission alone.
    pub(crate) fn lights<'a>(
        &'a self,
        lights: &'a ExplosionLights,
    ) -> Result<Option<Lights<FrameBackend<'a>>>, RenderError> {
        let backend = match self {
            Prepared::Emission => return Ok(None),
            Prepared::Lgh { shading, .. } => {
                FrameBackend::Lgh(LghBackend::with_blending(lights.hierarchy(), *shading)?)
            }
            Prepared::Brute(b) => FrameBackend::Brute(b),
            Prepared::Lightcuts(tree, settings) => FrameBackend::Lightcuts(tree, *settings),
        };
        // Each voxel light's smoke listed by its index in the backend: the hierarchy's order,
        // or that of the lights that shine (brute force, and Lightcuts' tree, whose clusters
        // are shaded at a representative light).
        let smoke = lights.smoke().map(|smoke| match &backend {
            FrameBackend::Lgh(b) => {
                let level0 = b.hierarchy().level(0);
                smoke.of_lights((0..level0.len()).map(|k| level0.position(k)))
            }
            FrameBackend::Brute(b) => smoke.of_lights((0..b.len()).map(|i| b.light(i).0)),
            FrameBackend::Lightcuts(tree, _) => {
                smoke.of_lights(tree.lights().iter().map(|l| l.position))
            }
        });
        Ok(Some(
            Lights::new(backend, lights.voxel_size())
                .with_near_field(lights.near_field())
                .with_smoke(smoke),
        ))
    }
}

/// A [`Method`] made ready over one frame's lights: one type for the renderer, whichever method
/// was chosen. (One value per render, so the variants' size difference costs nothing.)
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum FrameBackend<'a> {
    /// The hierarchy at one α.
    Lgh(LghBackend<'a>),
    /// Every light that shines this frame.
    Brute(&'a BruteForce),
    /// Lightcuts over a light tree of the frame's lights.
    Lightcuts(&'a LightTree, LightcutsSettings),
}

impl ManyLights for FrameBackend<'_> {
    fn name(&self) -> &'static str {
        match self {
            FrameBackend::Lgh(b) => b.name(),
            FrameBackend::Brute(b) => b.name(),
            FrameBackend::Lightcuts(..) => "lightcuts",
        }
    }

    fn selection_follows_shader(&self) -> bool {
        matches!(self, FrameBackend::Lightcuts(..))
    }

    fn illuminate<S: Shader>(
        &self,
        point: &ShadingPoint,
        shader: &mut S,
    ) -> Result<Illumination, QueryError> {
        match self {
            FrameBackend::Lgh(b) => b.illuminate(point, shader),
            FrameBackend::Brute(b) => b.illuminate(point, shader),
            FrameBackend::Lightcuts(tree, settings) => {
                LightcutsBackend::new(tree, *settings)?.illuminate(point, shader)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::{EmissionModel, Medium};
    use crate::procedural;

    /// Blender's blackbody below about 1900 K has a negative blue, which the hierarchy and brute
    /// force keep and Lightcuts, whose bounds need channels ≥ 0, is given clamped: every method
    /// prepares on such a fire.
    #[test]
    fn every_method_prepares_on_a_fire_with_a_negative_blue() {
        let volume = procedural::ball(12, 0.5, 1500.0);
        let medium = Medium::new(1.0, 1.0, 1.0, 0.0)
            .unwrap()
            .with_model(EmissionModel::Blender);
        let lights = ExplosionLights::new(&[&volume], &medium).unwrap();
        assert!(
            lights.lights().iter().any(|l| l.intensity.z < 0.0),
            "the test needs lights with a negative blue"
        );
        for method in [
            Method::Lgh { alpha: 2.0 },
            Method::Brute,
            Method::lightcuts(7),
        ] {
            method.prepare(&lights).unwrap();
        }
    }
}
