//! Normal buckets, an orientation-aware aggregation beyond the paper ([`NormalBuckets`]): the
//! VPLs split by the axis their normal points along most, one hierarchy per bucket, whose coarse
//! lights emit the cosine lobe about their bucket's mean normal, and the render through them
//! ([`render_buckets`]).

use lgh_core::glam::Vec3;
use lgh_core::{
    Blending, BuildError, GridSettings, Illumination, LightingGridHierarchy, PointLight,
    QueryError, ShadingPoint,
};

use super::{point_lights, Indirect};
use crate::render::{render_points, RenderError, Rendered};
use crate::representatives::{Allocation, Representatives};
use crate::scene::Scene;
use crate::vpl::Vpl;
use lgh_image::camera::Pinhole as Camera;

/// An orientation-aware aggregation, beyond the paper: the VPLs split by the axis their normal
/// points along most (±x, ±y, ±z), one hierarchy per bucket, whose coarse lights emit the cosine
/// lobe about their bucket's mean normal. In rooms of axis-aligned walls each bucket's normals
/// agree, and the lobe the isotropic aggregation loses is kept at every level.
pub struct NormalBuckets {
    buckets: Vec<Bucket>,
}

/// The VPLs of one bucket.
struct Bucket {
    /// Index in the VPL slice of each of the bucket's lights.
    vpl: Vec<u32>,
    /// Unit mean normal of its VPLs.
    normal: Vec3,
    lgh: LightingGridHierarchy,
    /// Its coarse lights' representative VPLs, if they shade through them.
    reps: Option<Representatives>,
}

impl NormalBuckets {
    /// Builds one hierarchy per non-empty bucket of `vpls`, with `settings`.
    ///
    /// Errors: those of [`LightingGridHierarchy::build`].
    pub fn build(vpls: &[Vpl], settings: &GridSettings) -> Result<Self, BuildError> {
        let lights = point_lights(vpls);
        let mut members: [Vec<u32>; 6] = Default::default();
        for (i, v) in vpls.iter().enumerate() {
            members[usize::from(v.orientation())].push(i as u32);
        }
        let mut buckets = Vec::new();
        for vpl in members.into_iter().filter(|m| !m.is_empty()) {
            let own: Vec<PointLight> = vpl.iter().map(|&i| lights[i as usize]).collect();
            let normal = vpl
                .iter()
                .map(|&i| vpls[i as usize].normal)
                .sum::<Vec3>()
                .normalize_or_zero();
            let lgh = LightingGridHierarchy::build(&own, settings)?;
            buckets.push(Bucket {
                vpl,
                normal,
                lgh,
                reps: None,
            });
        }
        Ok(NormalBuckets { buckets })
    }

    /// The same buckets, their coarse lights shaded through representative VPLs, as many as
    /// `allocation` says
    /// ([`Representatives`]) instead of Gaussian samples about their mean normal's lobe.
    #[must_use]
    pub fn with_representatives(mut self, allocation: Allocation) -> Self {
        for b in &mut self.buckets {
            b.reps = Some(Representatives::build_with(&b.lgh, allocation));
        }
        self
    }

    /// The buckets queried at α = `alpha`: each bucket's blending, computed once for every
    /// point ([`LghBackend::new`](lgh_core::LghBackend::new) does the same for one hierarchy).
    ///
    /// Errors: [`QueryError`] for an invalid α.
    pub fn at(&self, alpha: f32) -> Result<BucketsAt<'_>, QueryError> {
        let blendings = self
            .buckets
            .iter()
            .map(|b| b.lgh.blending(alpha))
            .collect::<Result<_, _>>()?;
        Ok(BucketsAt {
            buckets: self,
            blendings,
        })
    }
}

/// [`NormalBuckets`] at one α ([`NormalBuckets::at`]).
pub struct BucketsAt<'a> {
    buckets: &'a NormalBuckets,
    blendings: Vec<Blending>,
}

impl BucketsAt<'_> {
    /// What `point` receives from every bucket, shaded by `shader`.
    ///
    /// Errors: those of the hierarchies' queries.
    pub fn illuminate(
        &self,
        point: &ShadingPoint,
        shader: &Indirect<'_>,
    ) -> Result<Illumination, QueryError> {
        let mut radiance = Vec3::ZERO;
        let mut lights = 0;
        for (b, blending) in self.buckets.buckets.iter().zip(&self.blendings) {
            lights += b.lgh.query(point.position, blending, |s| {
                radiance += match (&b.reps, s.level) {
                    (Some(reps), 1..) => {
                        let of = reps.of(s.level, s.index).iter();
                        shader.shade_representatives(
                            point,
                            s,
                            of.map(|&i| b.vpl[i as usize] as usize),
                        )
                    }
                    _ => {
                        let vpl = (s.level == 0)
                            .then(|| b.lgh.input_index(s.index))
                            .flatten()
                            .map(|i| b.vpl[i] as usize);
                        shader.shade_oriented(point, s, vpl, Some(b.normal))
                    }
                };
            })?;
        }
        Ok(Illumination { radiance, lights })
    }
}

/// The indirect light `shader` gives each pixel through the normal buckets at one α.
///
/// Errors: as [`render_lgh`](super::render_lgh).
pub fn render_buckets(
    scene: &Scene,
    camera: &Camera,
    buckets: &BucketsAt<'_>,
    shader: &Indirect<'_>,
    progress: impl Fn(usize) + Sync,
) -> Result<Rendered, RenderError> {
    render_points(scene, camera, |p| buckets.illuminate(p, shader), progress)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::indirect::tests::{rel_rmse, Fixture};

    /// The orientation-aware aggregation against the paper's isotropic one, both against brute
    /// force over every VPL with the same shadow rays, at α = 1, 4, 16 in the room. Measured
    /// (32×24): isotropic 78%, 55%, 42%; buckets 28%, 1.7%, 0.60%. Without shadow rays (40×30)
    /// the buckets gave 27%, 2.0%, 0.09%: what is left is the hierarchy's own approximation
    /// (with isotropic VPLs and no shadows the single hierarchy gives 1.6% and 0.08% at
    /// α = 4, 16: its lobe loss is what the buckets remove). Asserted: the buckets win at every
    /// α, and meet issue 14's targets, ≤ 3% at α = 4 and ≤ 1% at α = 16.
    #[test]
    fn normal_buckets_beat_isotropic_aggregation() {
        let f = Fixture::new();
        let buckets = NormalBuckets::build(&f.vpls, &GridSettings::default()).unwrap();
        let (shader, camera) = (f.shader(), Fixture::camera(32, 24));
        let exact = f.exact(&shader, &camera);
        for (alpha, target) in [(1.0f32, 1.0), (4.0, 0.03), (16.0, 0.01)] {
            let iso = rel_rmse(&f.isotropic(&shader, &camera, alpha), &exact);
            let at = buckets.at(alpha).unwrap();
            let oriented = render_buckets(&f.scene, &camera, &at, &shader, |_| {});
            let oriented = rel_rmse(&oriented.unwrap(), &exact);
            println!("alpha {alpha}: isotropic {iso:.4}, buckets {oriented:.4}");
            assert!(oriented < iso, "α = {alpha}: {oriented} against {iso}");
            assert!(oriented <= target, "α = {alpha}: {oriented}");
        }
    }
}
