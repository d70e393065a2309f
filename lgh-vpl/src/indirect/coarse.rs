//! How the coarse lights (levels ≥ 1) of a hierarchy over the VPLs are shaded ([`Coarse`]),
//! and the render through that hierarchy ([`render_lgh`]): the paper's volume lights with
//! Gaussian shadow samples (Sec. 6.4, Fig. 11d), or, beyond the paper, the VPLs a coarse light
//! stands for ([`crate::representatives`]), all of them or a prefix whose length each shading
//! point chooses.

use lgh_core::{LghBackend, LightSample, Material, ShadingPoint};

use super::adaptive::{adaptive, BlendAt};
use super::{Cone, Indirect};
use crate::render::{render_points, render_with_shader, RenderError, Rendered};
use crate::representatives::Representatives;
use crate::scene::Scene;
use lgh_image::camera::Pinhole as Camera;

/// How the coarse lights (levels ≥ 1) of a hierarchy over
/// [`point_lights`](super::point_lights) are shaded.
#[derive(Clone, Copy, Debug)]
pub enum Coarse<'a> {
    /// The paper's volume lights: isotropic points with `k` Gaussian shadow samples (Fig. 11d).
    Gaussian,
    /// Through their representative VPLs ([`Indirect::shade_representatives`]).
    Representatives(&'a Representatives),
    /// Through a prefix of their representatives (drawn with
    /// [`Allocation::Nested`](crate::representatives::Allocation::Nested)) whose length each
    /// shading point chooses: `mean` samples per coarse light are shared among the point's
    /// coarse lights in proportion to an unshadowed estimate of what each brings there, shaded
    /// again with more where the point's error may exceed the shader's bound
    /// ([`refine`](super::refine)); each representative blended as `blend` says (the
    /// `indirect::adaptive` module's docs). With representatives that are not nested, every
    /// light uses all of its own (a prefix of a plain systematic draw would be biased).
    Adaptive {
        /// The representatives, nested.
        reps: &'a Representatives,
        /// The mean count per coarse light.
        mean: f32,
        /// Where each light's blending weight is taken.
        blend: BlendAt,
        /// The candidates of each resampled draw, 1 to
        /// [`MAX_CANDIDATES`](super::resample::MAX_CANDIDATES) (1: each draw one representative,
        /// [`resample`](super::resample)).
        candidates: u32,
    },
}

/// The indirect light `shader` gives each pixel through the hierarchy `backend` built over
/// [`point_lights`](super::point_lights) of its VPLs (the paper's isotropic aggregation), its
/// coarse lights shaded as `coarse` says.
///
/// Errors: a point the hierarchy cannot be queried at ([`RenderError::Query`]).
pub fn render_lgh(
    scene: &Scene,
    camera: &Camera,
    backend: &LghBackend<'_>,
    coarse: Coarse<'_>,
    shader: &Indirect<'_>,
    progress: impl Fn(usize) + Sync,
) -> Result<Rendered, RenderError> {
    let lgh = backend.hierarchy();
    if let Coarse::Adaptive {
        reps,
        mean,
        blend,
        candidates,
    } = coarse
    {
        let adaptive =
            |p: &ShadingPoint| adaptive(p, backend, reps, mean, blend, candidates, shader);
        let cone = |p: &ShadingPoint| shader.settings.lobe_error.and_then(|e| Cone::of(p, e));
        let illuminate = |p: &ShadingPoint| {
            let (lit, split, refined) = match (cone(p), p.material) {
                // A glossy lobe too sharp for the hierarchy: its diffuse term through it, its
                // glossy term from the VPLs in the lobe's cone (`super::lobe`).
                (Some(cone), Material::Phong { kd, .. }) => {
                    let diffuse = ShadingPoint {
                        material: Material::Lambert { albedo: kd },
                        ..*p
                    };
                    let (mut lit, refined) = adaptive(&diffuse)?;
                    let (glossy, lights) = shader.glossy_in_cone(p, &cone, lgh);
                    lit.radiance += glossy;
                    lit.lights += lights;
                    (lit, true, refined)
                }
                _ => {
                    let (lit, refined) = adaptive(p)?;
                    (lit, false, refined)
                }
            };
            shader.count_bounded(split, refined);
            Ok(lit)
        };
        return render_points(scene, camera, illuminate, progress);
    }
    let shade = |p: &ShadingPoint, s: &LightSample| {
        fn reps<'r>(
            r: &'r Representatives,
            s: &LightSample,
        ) -> impl ExactSizeIterator<Item = usize> + 'r {
            r.of(s.level, s.index).iter().map(|&i| i as usize)
        }
        match (coarse, s.level) {
            (Coarse::Representatives(r), 1..) => shader.shade_representatives(p, s, reps(r, s)),
            _ => {
                let vpl = (s.level == 0).then(|| lgh.input_index(s.index)).flatten();
                shader.shade(p, s, vpl)
            }
        }
    };
    render_with_shader(scene, camera, backend, shade, progress)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::indirect::tests::{rel_rmse, Fixture};

    /// Representative VPLs (beyond the paper) against the paper's Gaussian shadow samples, both
    /// through the one isotropic hierarchy with k = 9, against brute force over every VPL with
    /// the same shadow rays. Measured (32×24): Gaussian 54.6% and 41.8% at α = 4 and 16 (the
    /// paper's isotropic points), representatives 2.4% and 0.17%. Asserted: representatives win at α = 4
    /// and 16 and meet issue 14's targets there, ≤ 3% and ≤ 1%.
    #[test]
    fn representative_vpls_beat_gaussian_samples() {
        let f = Fixture::new();
        let reps = Representatives::build(&f.lgh, 9);
        let (shader, camera) = (f.shader(), Fixture::camera(32, 24));
        let exact = f.exact(&shader, &camera);
        for (alpha, target) in [(4.0f32, 0.03), (16.0, 0.01)] {
            let gaussian = rel_rmse(&f.isotropic(&shader, &camera, alpha), &exact);
            let backend = LghBackend::new(&f.lgh, alpha).unwrap();
            let coarse = Coarse::Representatives(&reps);
            let drawn = render_lgh(&f.scene, &camera, &backend, coarse, &shader, |_| {});
            let drawn = rel_rmse(&drawn.unwrap(), &exact);
            println!("alpha {alpha}: gaussian {gaussian:.4}, representatives {drawn:.4}");
            assert!(drawn < gaussian, "α = {alpha}: {drawn} against {gaussian}");
            assert!(drawn <= target, "α = {alpha}: {drawn}");
        }
    }
}
