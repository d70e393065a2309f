//! Lightcuts (B. Walter et al., *Lightcuts: a scalable approach to illumination*, SIGGRAPH 2005),
//! the baseline the LGH paper compares against (Fig. 10).
//!
//! A binary *light tree*: every node is a cluster with its total intensity, its lights' bounding
//! box and one *representative* light. A *cut* is a set of nodes whose clusters partition the
//! lights; each cluster in it is shaded as its total intensity placed at its representative. The
//! cut starts at the root and its cluster with the largest error bound is replaced by its two
//! children while that bound exceeds ε (2 % by default) of the cut's current estimate and the cut
//! is smaller than the maximum size (1000 by default).
//!
//! The error bound of a cluster is Walter's `M_ub G_ub V_ub I_C`: `V_ub = 1`, `G_ub = 1/d_min²`
//! with `d_min` the distance from the point to the box, and `M_ub` the material term of
//! [`reflected`](crate::reflection::reflected) bounded over the box: `N·L ≤ z_max / d_min` with
//! `z_max` the largest `N·(y − x)` over the box's corners, and likewise `R·E = L·E'` with `E'` the
//! view direction mirrored about the normal. A single light is exact (bound 0).
//!
//! Tree construction is top-down (split at the median along the box's longest axis), not Walter's
//! greedy bottom-up pairing; representatives are chosen as Walter does — one child's
//! representative, picked at random with probability proportional to the child's intensity (a
//! seeded hash, so the tree is reproducible) — or as the brightest light of the cluster, the
//! deterministic variant.
//!
//! Either way a cluster's representative is one of its children's, and as in Walter et al. (§4)
//! refining a cluster shades only the other child: the child that inherits the representative
//! gets the parent's estimate scaled by `I_child / I_C` per channel, which is the same value when
//! the shader is linear in the light's intensity (any physical shader is) and does not depend on
//! [`LightSample::size`] (the cluster's extent, which differs between parent and child).
//! [`LightcutsSettings::reuse_representative`] turns this off for other shaders.

use alloc::collections::BinaryHeap;
use alloc::vec::Vec;
use glam::Vec3;

use crate::error::{BuildError, QueryError};
use crate::light::{validate_lights, Channels, PointLight};
use crate::many_lights::{
    Illumination, LightSample, Lobe, ManyLights, Material, Shader, ShadingPoint,
};
use crate::random::SplitMix64;
use crate::ranked::Ranked;

/// How a cluster's representative light is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Representative {
    /// Walter et al.: one of the children's representatives, at random with probability
    /// proportional to the child's `‖I‖₁`, from a hash of `seed` and the node.
    Stochastic {
        /// Seed of the choice.
        seed: u64,
    },
    /// The brightest light (largest `‖I‖₁`) of the cluster: deterministic, no seed.
    Brightest,
}

/// A node of the light tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Cluster {
    /// Total intensity `I_C` of the cluster's lights.
    pub intensity: Vec3,
    /// The bounding box `(lo, hi)` of its lights.
    pub bounds: (Vec3, Vec3),
    /// Index of the representative light in [`LightTree::lights`].
    pub representative: u32,
    /// The children, `None` for a single light.
    pub children: Option<[u32; 2]>,
}

impl Cluster {
    /// Walter's error bound `M_ub G_ub I_C` of the cluster at `point` (its largest channel): no
    /// light of the cluster, nor the cluster shaded at its representative, reflects more there.
    /// Zero for a single light, which is exact; infinite for a point inside the box (unless
    /// the cluster is dark in every channel).
    #[must_use]
    pub fn error_bound(&self, point: &ShadingPoint) -> f32 {
        match self.children {
            None => 0.0,
            Some(_) => {
                let m = cluster_bound(point, self.bounds.0, self.bounds.1);
                // A dark channel bounds nothing: 0, not 0 · ∞ = NaN, which glam's
                // `max_element` may return and which ranks below every bound (x86's NaN is
                // negative), so that a cluster around the point was never refined.
                Vec3::select(
                    self.intensity.cmpgt(Vec3::ZERO),
                    self.intensity * m,
                    Vec3::ZERO,
                )
                .max_element()
            }
        }
    }
}

/// Walter et al.'s binary light tree.
#[derive(Clone, Debug, PartialEq)]
pub struct LightTree {
    lights: Vec<PointLight>,
    nodes: Vec<Cluster>,
}

impl LightTree {
    /// Builds the tree over `lights` (positions finite, intensities finite and ≥ 0; none makes an
    /// empty tree).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{LightTree, PointLight, Representative};
    ///
    /// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let tree = LightTree::build(&lights, Representative::Stochastic { seed: 7 })?;
    /// let root = &tree.clusters()[0];
    /// assert_eq!(root.intensity, Vec3::splat(64.0)); // I_C: the cluster's total intensity
    /// assert_eq!(tree.clusters().len(), 2 * 64 - 1); // a binary tree over 64 lights
    /// // Seeded: the same seed, the same representatives.
    /// let again = LightTree::build(&lights, Representative::Stochastic { seed: 7 })?;
    /// assert_eq!(tree, again);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn build(
        lights: &[PointLight],
        representative: Representative,
    ) -> Result<Self, BuildError> {
        validate_lights(lights, Channels::NonNegative)?;
        let mut order: Vec<u32> = (0..lights.len() as u32).collect();
        let mut nodes: Vec<Cluster> = Vec::with_capacity(2 * lights.len());
        let mut ranges: Vec<(usize, usize)> = Vec::with_capacity(2 * lights.len());
        if !lights.is_empty() {
            ranges.push((0, lights.len()));
        }
        // Top-down: node k covers order[ranges[k]]; children get larger indices than parents.
        let mut k = 0;
        while k < ranges.len() {
            let (start, end) = ranges[k];
            let run = &mut order[start..end];
            let (lo, hi) = run.iter().fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), &i| {
                    let p = lights[i as usize].position;
                    (lo.min(p), hi.max(p))
                },
            );
            let children = if run.len() > 1 {
                let e = hi - lo;
                let axis = if e.x >= e.y && e.x >= e.z {
                    0
                } else if e.y >= e.z {
                    1
                } else {
                    2
                };
                let mid = run.len() / 2;
                run.select_nth_unstable_by(mid, |&a, &b| {
                    let (pa, pb) = (lights[a as usize].position, lights[b as usize].position);
                    pa[axis].total_cmp(&pb[axis]).then(a.cmp(&b))
                });
                let first = ranges.len() as u32;
                ranges.push((start, start + mid));
                ranges.push((start + mid, end));
                Some([first, first + 1])
            } else {
                None
            };
            nodes.push(Cluster {
                intensity: Vec3::ZERO,
                bounds: (lo, hi),
                representative: run[0],
                children,
            });
            k += 1;
        }
        // Bottom-up: intensities and representatives.
        let norm = |i: u32| lights[i as usize].intensity.element_sum();
        for k in (0..nodes.len()).rev() {
            let Some([a, b]) = nodes[k].children else {
                nodes[k].intensity = lights[nodes[k].representative as usize].intensity;
                continue;
            };
            let (ca, cb) = (&nodes[a as usize], &nodes[b as usize]);
            let (ra, rb) = (ca.representative, cb.representative);
            let pick_a = match representative {
                Representative::Brightest => norm(ra) >= norm(rb),
                Representative::Stochastic { seed } => {
                    let (wa, wb) = (ca.intensity.element_sum(), cb.intensity.element_sum());
                    let u = (SplitMix64::mix(seed ^ SplitMix64::mix(k as u64)) >> 40) as f32
                        * (1.0 / (1u64 << 24) as f32);
                    wa + wb <= 0.0 || u * (wa + wb) < wa
                }
            };
            nodes[k].intensity = ca.intensity + cb.intensity;
            nodes[k].representative = if pick_a { ra } else { rb };
        }
        Ok(LightTree {
            lights: lights.to_vec(),
            nodes,
        })
    }

    /// The lights, in input order.
    #[must_use]
    pub fn lights(&self) -> &[PointLight] {
        &self.lights
    }

    /// The clusters, the root first (empty without lights); children after their parent.
    #[must_use]
    pub fn clusters(&self) -> &[Cluster] {
        &self.nodes
    }
}

/// Lightcuts' parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightcutsSettings {
    /// Relative error ε: a cluster is refined while its bound exceeds ε times the cut's estimate.
    pub relative_error: f32,
    /// The largest cut.
    pub max_cut: usize,
    /// Reuse a refined cluster's estimate for the child that shares its representative (one
    /// shader call per refinement instead of two; see the module docs for what it assumes of the
    /// shader).
    pub reuse_representative: bool,
}

impl LightcutsSettings {
    /// Checks ε (finite and > 0) and the largest cut (≥ 1), before any tree is built.
    ///
    /// ```
    /// use lgh_core::LightcutsSettings;
    ///
    /// assert!(LightcutsSettings::default().check().is_ok());
    /// let none = LightcutsSettings { max_cut: 0, ..Default::default() };
    /// assert!(none.check().is_err());
    /// ```
    pub fn check(&self) -> Result<(), QueryError> {
        let e = QueryError::check_threshold(self.relative_error)?;
        if self.max_cut == 0 {
            return Err(QueryError::InvalidThreshold { threshold: e });
        }
        Ok(())
    }
}

impl Default for LightcutsSettings {
    /// Walter et al.'s 2 % and 1000, reusing representatives.
    fn default() -> Self {
        LightcutsSettings {
            relative_error: 0.02,
            max_cut: 1000,
            reuse_representative: true,
        }
    }
}

/// Lightcuts as a [`ManyLights`] backend.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::reflection::reflected;
/// use lgh_core::{
///     BruteForce, LightSample, LightTree, LightcutsBackend, LightcutsSettings, ManyLights,
///     Material, PointLight, Representative, ShadingPoint,
/// };
///
/// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
/// let lights: Vec<PointLight> = (0..64u32)
///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
///     .map(|p| PointLight::new(p, Vec3::ONE))
///     .collect();
/// // A diffuse floor below the lights, shaded with eq. (1) (no shadows here).
/// let point = ShadingPoint {
///     position: Vec3::new(1.5, -20.0, 1.5),
///     normal: Some(Vec3::Y),
///     geometric: None,
///     view: Some(Vec3::Y),
///     material: Material::Lambert { albedo: Vec3::splat(0.8) },
/// };
/// let shade = |s: &LightSample| reflected(&point, s.position, s.intensity, s.lobe);
/// let exact = BruteForce::new(&lights)?.illuminate(&point, &mut { shade })?;
/// let tree = LightTree::build(&lights, Representative::Brightest)?;
/// let cuts = LightcutsBackend::new(&tree, LightcutsSettings::default())?;
/// let approx = cuts.illuminate(&point, &mut { shade })?;
/// // Walter's 2 % bounds each cluster of the cut; with so few equal lights the cut goes down to
/// // single lights, which are exact.
/// let error = ((approx.radiance - exact.radiance) / exact.radiance).abs().max_element();
/// assert!(error < 0.02, "{error}");
/// assert!(approx.lights <= 64);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct LightcutsBackend<'a> {
    tree: &'a LightTree,
    settings: LightcutsSettings,
}

/// The material bound `M_ub` of a cluster box seen from a point, per unit intensity and with the
/// `1/d_min²` of `G_ub` folded in; infinite if the point is in the box.
fn cluster_bound(point: &ShadingPoint, lo: Vec3, hi: Vec3) -> Vec3 {
    let x = point.position;
    let d_min2 = (lo - x).max(x - hi).max(Vec3::ZERO).length_squared();
    if d_min2 == 0.0 {
        return Vec3::INFINITY;
    }
    let g = 1.0 / d_min2;
    let d_min = crate::math::sqrt(d_min2);
    // Largest `a·(y − x)` over the box, divided by d_min: bounds `a·L` for every light in it.
    let cos_bound = |a: Vec3| {
        let c = 0.5 * (lo + hi) - x;
        let h = 0.5 * (hi - lo);
        ((a.dot(c) + a.abs().dot(h)) / d_min).clamp(0.0, 1.0)
    };
    match (point.material, point.normal) {
        (Material::Isotropic, _) => Vec3::splat(g * crate::many_lights::ISOTROPIC_PHASE),
        (Material::Lambert { albedo }, Some(n)) => albedo * (g * cos_bound(n)),
        (Material::Phong { kd, ks, exponent }, Some(n)) => {
            let mut m = kd * cos_bound(n);
            if let Some(e) = point.view {
                let mirrored = 2.0 * n.dot(e) * n - e;
                m += ks * libm::powf(cos_bound(mirrored), exponent);
            }
            m * g
        }
        (_, None) => Vec3::ZERO,
    }
}

impl<'a> LightcutsBackend<'a> {
    /// Lightcuts over `tree` (ε finite and > 0, `max_cut` ≥ 1).
    pub fn new(tree: &'a LightTree, settings: LightcutsSettings) -> Result<Self, QueryError> {
        settings.check()?;
        Ok(LightcutsBackend { tree, settings })
    }

    /// The cluster `k` entering the cut, ranked by its bound, with its estimate: the shader at
    /// the representative with the cluster's intensity.
    fn enter<S: Shader>(&self, point: &ShadingPoint, k: u32, shader: &mut S) -> Ranked<Vec3> {
        let c = &self.tree.nodes[k as usize];
        let position = self.tree.lights[c.representative as usize].position;
        let estimate = shader.shade(&LightSample {
            size: (c.bounds.1 - c.bounds.0).length(),
            ..LightSample::point(
                c.representative,
                position,
                c.intensity,
                point.position,
                Lobe::All,
            )
        });
        self.ranked(point, k, estimate)
    }

    /// The child `k` of `parent` that shares its representative, entering the cut with the
    /// parent's estimate scaled by the intensity ratio (no shader call).
    fn inherit(&self, point: &ShadingPoint, k: u32, parent: &Ranked<Vec3>) -> Ranked<Vec3> {
        let (c, p) = (
            &self.tree.nodes[k as usize],
            &self.tree.nodes[parent.index() as usize],
        );
        // I_child ≤ I_C per channel; a dark channel of the parent is dark in the child too.
        let ratio = Vec3::select(
            p.intensity.cmpgt(Vec3::ZERO),
            c.intensity / p.intensity,
            Vec3::ZERO,
        );
        self.ranked(point, k, parent.item * ratio)
    }

    fn ranked(&self, point: &ShadingPoint, k: u32, estimate: Vec3) -> Ranked<Vec3> {
        Ranked::new(self.tree.nodes[k as usize].error_bound(point), k, estimate)
    }
}

impl ManyLights for LightcutsBackend<'_> {
    fn name(&self) -> &'static str {
        "lightcuts"
    }

    /// The cut is refined by the shaded estimates.
    fn selection_follows_shader(&self) -> bool {
        true
    }

    fn illuminate<S: Shader>(
        &self,
        point: &ShadingPoint,
        shader: &mut S,
    ) -> Result<Illumination, QueryError> {
        QueryError::check_point(point.position)?;
        let mut out = Illumination::default();
        if self.tree.nodes.is_empty() {
            return Ok(out);
        }
        let root = self.enter(point, 0, shader);
        let mut total = root.item;
        let mut cut = BinaryHeap::from([root]);
        let mut calls = 1u32;
        while cut.len() < self.settings.max_cut {
            let Some(&top) = cut.peek() else { break };
            // NaN-safe: refine unless the bound is known to be small enough.
            if top.key() <= self.settings.relative_error * total.max_element() {
                break;
            }
            // A single light has bound 0, so only a NaN estimate gets a leaf here.
            let Some(kids) = self.tree.nodes[top.index() as usize].children else {
                break;
            };
            cut.pop();
            total -= top.item;
            let parent = &self.tree.nodes[top.index() as usize];
            for k in kids {
                let shared = parent.representative == self.tree.nodes[k as usize].representative;
                let entry = if shared && self.settings.reuse_representative {
                    self.inherit(point, k, &top)
                } else {
                    calls += 1;
                    self.enter(point, k, shader)
                };
                total += entry.item;
                cut.push(entry);
            }
        }
        // Summed afresh in heap order (which depends only on the input, so deterministic), not
        // from the running total, which cancellation may have eroded.
        out.radiance = cut.iter().fold(Vec3::ZERO, |acc, e| acc + e.item);
        out.lights = calls;
        Ok(out)
    }
}
