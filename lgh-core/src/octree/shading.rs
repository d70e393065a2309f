//! Shading through the light octree with an absolute error bound (§4.2.2, Fig. 6; §4.3.2; §4.4).
//!
//! One traversal per term of eq. (1) — the paper runs the diffuse and the specular algorithm
//! "mainly independently" (§4.4):
//! - **Diffuse** (Fig. 6): a node of at most three lights is summed exactly; a node whose box
//!   diagonal reaches the point (`Δd_max ≥ d`) is opened; otherwise, if its bound (eq. 10) is below
//!   the threshold `T`, it goes on the *error list* and will be shaded by its virtual light, else it
//!   is opened. Opening a leaf sums its lights exactly.
//! - **Specular** (§4.3.2): the same descent with the maximal contribution (eq. 6); a node below
//!   `T` goes on the list of *ignored contributions* and is not shaded at all.
//!
//! After the descent, while the listed bounds sum above `T`, the node with the largest bound is
//! taken off the list and treated one level lower. So each term's absolute error at a point is at
//! most `T` (per colour channel: a node's bound is taken for its largest channel), whatever the
//! number of nodes listed — the paper's guarantee that no pixel errs by more than the threshold.

use alloc::collections::BinaryHeap;
use alloc::vec::Vec;
use glam::Vec3;

use super::bounds::{diffuse_bound, specular_bound, virtual_cosines, NodeView};
use super::{LightOctree, OctreeNode};
use crate::error::QueryError;
use crate::many_lights::{
    Illumination, LightSample, Lobe, ManyLights, Material, Shader, ShadingPoint,
};
use crate::ranked::Ranked;

/// Nodes with at most this many lights are summed exactly: evaluating a bound and a virtual light
/// costs about as much as three or four lights (§4.2.1).
pub const EXACT_SUM_LIGHTS: usize = 3;

/// The light octree as a [`ManyLights`] backend, with the absolute error threshold `T` of §4.
///
/// The guarantee holds for shaders that evaluate [`reflected`](crate::reflection::reflected) (the
/// unoccluded eq. (1)); shadows can only lower a node's true value, so with visibility the
/// specular maximal contribution stays an upper bound (§6.1) but the diffuse bound does not.
///
/// Lights are presented to the shader as [`LightSample`]s: input lights with `level` 0 and
/// `index` into [`LightOctree::lights`]; virtual lights with `level` 1, `index` of the node in
/// [`LightOctree::nodes`] and `size` its box diagonal. Each carries the [`Lobe`] it is shaded for.
///
/// Within its threshold of brute force:
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::reflection::reflected;
/// use lgh_core::{
///     BruteForce, LightOctree, LightSample, ManyLights, Material, OctreeBackend, OctreeSettings,
///     PointLight, ShadingPoint,
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
/// let tree = LightOctree::build(&lights, &OctreeSettings::default())?;
/// let threshold = 0.01; // about 9 % of the exact value here
/// let octree = OctreeBackend::new(&tree, threshold)?.illuminate(&point, &mut { shade })?;
/// assert!((octree.radiance - exact.radiance).abs().max_element() <= threshold);
/// assert!(octree.lights < 64);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct OctreeBackend<'a> {
    tree: &'a LightOctree,
    threshold: f32,
}

/// Which term a traversal bounds.
#[derive(Clone, Copy, Debug)]
enum Term {
    /// `k_d (N·L)` with the surface normal, or the phase function `1/4π` in a medium (`None`).
    Diffuse { normal: Option<Vec3>, kd: Vec3 },
    /// `k_s (R·E)ⁿ`.
    Specular {
        normal: Vec3,
        ks: Vec3,
        exponent: f32,
    },
}

impl Term {
    fn lobe(&self, point: &ShadingPoint) -> Lobe {
        match (self, point.normal) {
            (Term::Diffuse { .. }, None) => Lobe::All,
            (Term::Diffuse { .. }, Some(_)) => Lobe::Diffuse,
            (Term::Specular { .. }, _) => Lobe::Specular,
        }
    }

    /// The node's bound for its largest channel, or `None` if the node must be opened.
    #[inline]
    fn bound(&self, point: &ShadingPoint, node: &OctreeNode) -> Option<f32> {
        let view = NodeView::new(point.position, node.light.position, node.diagonal())?;
        Some(match *self {
            Term::Diffuse { normal: None, kd } => {
                (kd * node.light.intensity).max_element() * diffuse_bound(&view, 1.0, 0.0)
            }
            Term::Diffuse {
                normal: Some(n),
                kd,
            } => {
                let (cos_theta, _) = virtual_cosines(point, n, view.dir);
                (kd * node.light.intensity).max_element()
                    * diffuse_bound(&view, cos_theta, view.angle)
            }
            Term::Specular {
                normal,
                ks,
                exponent,
            } => {
                let (_, cos_alpha) = virtual_cosines(point, normal, view.dir);
                (ks * node.light.intensity).max_element()
                    * specular_bound(&view, cos_alpha, exponent)
            }
        })
    }
}

impl<'a> OctreeBackend<'a> {
    /// The backend for `tree` with absolute threshold `threshold` (radiance units, per channel;
    /// finite and > 0).
    pub fn new(tree: &'a LightOctree, threshold: f32) -> Result<Self, QueryError> {
        Ok(OctreeBackend {
            tree,
            threshold: QueryError::check_threshold(threshold)?,
        })
    }

    /// The octree.
    #[must_use]
    pub fn tree(&self) -> &'a LightOctree {
        self.tree
    }

    /// The threshold `T`.
    #[must_use]
    pub fn threshold(&self) -> f32 {
        self.threshold
    }

    /// The terms of eq. (1) the material has, checked against the point.
    fn terms(point: &ShadingPoint) -> Result<[Option<Term>; 2], QueryError> {
        let unit = |v: Vec3| v.is_finite() && (v.length_squared() - 1.0).abs() < 1e-3;
        let surface = |needs_view: bool| match point.normal {
            Some(n) if unit(n) && (!needs_view || point.view.is_some_and(unit)) => Ok(n),
            _ => Err(QueryError::InvalidSurface),
        };
        Ok(match point.material {
            Material::Isotropic => [
                Some(Term::Diffuse {
                    normal: None,
                    kd: Vec3::splat(crate::many_lights::ISOTROPIC_PHASE),
                }),
                None,
            ],
            Material::Lambert { albedo } => [
                Some(Term::Diffuse {
                    normal: Some(surface(false)?),
                    kd: albedo,
                }),
                None,
            ],
            Material::Phong { kd, ks, exponent } => {
                let specular = ks != Vec3::ZERO;
                let normal = surface(specular)?;
                [
                    (kd != Vec3::ZERO).then_some(Term::Diffuse {
                        normal: Some(normal),
                        kd,
                    }),
                    specular.then_some(Term::Specular {
                        normal,
                        ks,
                        exponent,
                    }),
                ]
            }
        })
    }

    /// One traversal for `term`: exact sums and virtual lights go to the shader, the result
    /// accumulates in `out`.
    fn traverse<S: Shader>(
        &self,
        point: &ShadingPoint,
        term: &Term,
        shader: &mut S,
        out: &mut Illumination,
        stack: &mut Vec<u32>,
        list: &mut BinaryHeap<Ranked<()>>,
    ) {
        let nodes = self.tree.nodes();
        let lobe = term.lobe(point);
        let threshold = f64::from(self.threshold);
        let mut listed_sum = 0.0f64;
        stack.clear();
        list.clear();
        stack.push(0);
        loop {
            while let Some(i) = stack.pop() {
                let node = &nodes[i as usize];
                if node.count() <= EXACT_SUM_LIGHTS {
                    self.sum_exactly(point, node, lobe, shader, out);
                    continue;
                }
                match term.bound(point, node) {
                    Some(bound) if bound < self.threshold => {
                        listed_sum += f64::from(bound);
                        list.push(Ranked::new(bound, i, ()));
                    }
                    _ => self.open(point, i, lobe, shader, out, stack),
                }
            }
            if listed_sum <= threshold {
                break;
            }
            // The listed bounds sum above T: treat the largest one level lower.
            let Some(largest) = list.pop() else { break };
            listed_sum -= f64::from(largest.key());
            self.open(point, largest.index(), lobe, shader, out, stack);
        }
        if matches!(term, Term::Diffuse { .. }) {
            for entry in list.iter() {
                let node = &nodes[entry.index() as usize];
                out.radiance += shader.shade(&LightSample {
                    level: 1,
                    size: node.diagonal(),
                    ..LightSample::point(
                        entry.index(),
                        node.light.position,
                        node.light.intensity,
                        point.position,
                        lobe,
                    )
                });
                out.lights += 1;
            }
        }
        // Specular: the listed nodes are the ignored contributions; they are not shaded.
    }

    /// Opens node `i`: its children go on the stack, or a leaf's lights are summed.
    fn open<S: Shader>(
        &self,
        point: &ShadingPoint,
        i: u32,
        lobe: Lobe,
        shader: &mut S,
        out: &mut Illumination,
        stack: &mut Vec<u32>,
    ) {
        let node = &self.tree.nodes()[i as usize];
        if node.is_leaf() {
            self.sum_exactly(point, node, lobe, shader, out);
        } else {
            // Reversed, so the first child is popped first.
            stack.extend((node.first_child..node.first_child + u32::from(node.children)).rev());
        }
    }

    /// Shades every light of `node`.
    fn sum_exactly<S: Shader>(
        &self,
        point: &ShadingPoint,
        node: &OctreeNode,
        lobe: Lobe,
        shader: &mut S,
        out: &mut Illumination,
    ) {
        for (k, light) in self.tree.lights_of(node).iter().enumerate() {
            out.radiance += shader.shade(&LightSample::point(
                node.start + k as u32,
                light.position,
                light.intensity,
                point.position,
                lobe,
            ));
        }
        out.lights += node.count() as u32;
    }
}

impl ManyLights for OctreeBackend<'_> {
    fn name(&self) -> &'static str {
        "octree"
    }

    fn illuminate<S: Shader>(
        &self,
        point: &ShadingPoint,
        shader: &mut S,
    ) -> Result<Illumination, QueryError> {
        QueryError::check_point(point.position)?;
        let terms = Self::terms(point)?;
        let mut out = Illumination::default();
        if self.tree.nodes().is_empty() {
            return Ok(out);
        }
        let mut stack = Vec::with_capacity(64);
        let mut list = BinaryHeap::with_capacity(64);
        for term in terms.iter().flatten() {
            self.traverse(point, term, shader, &mut out, &mut stack, &mut list);
        }
        Ok(out)
    }
}
