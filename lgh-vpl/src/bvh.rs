//! A bounding volume hierarchy over a mesh's triangles: closest-hit and any-hit ray queries.
//!
//! **Build**: top-down binned surface-area heuristic (16 bins per axis over the triangles'
//! centroid bounds; cost `1 + (A_L N_L + A_R N_R) / A` against a leaf's `N`, as in pbrt-v3).
//! Leaves hold at most [`MAX_LEAF`] triangles. At depth ≥ 64 (the root is depth 0), or where
//! every centroid coincides, a node is split at its median instead, so no tree is deeper than
//! 64 + 32 levels and the traversal stack is a fixed array. The build partitions the triangles'
//! boxes themselves (so each pass reads memory in order), is serial and deterministic: the same
//! mesh always gives the same tree.
//!
//! **Layout**: nodes flattened depth-first into one array (32 bytes each; the left child follows
//! its parent, the right child's index is stored); the leaves' triangles copied in leaf order.
//!
//! **Queries**: stack traversal, near child first by the sign of the ray direction on the node's
//! split axis; the watertight ray–triangle test of Woop, Benthin and Wald (JCGT 2013), as pbrt-v3
//! writes it, so a ray through a shared edge or vertex of a closed mesh never slips through.
//! Two departures from pbrt, both for coplanar overlapping faces (common in real meshes), whose
//! hits differ by an ulp: the slab test widens the best hit's `t` as well as the box's far
//! distance by `1 + 2γ₃`, and the triangle test compares `t` itself with `t_max`, not the scaled
//! `t` with `t_max·det`. With pbrt's tests rounding lost the nearer face on 3 of 200,000 random
//! rays in Sponza; with these, the closest hit agrees bit for bit with a loop over every triangle
//! with the same test (the tests check it on random triangles with coplanar overlaps, the bench
//! on Sponza). Hits count for `0 < t < t_max` (the ray's parameter); a hit at `t` barely above 0
//! on the surface a ray starts from, or barely below `t_max` on the surface it ends on, is
//! possible, so a shadow ray from one surface to another (to a VPL, which lies on a surface) must
//! have both ends moved slightly off their surfaces.

use lgh_core::glam::{Vec3, Vec3A};

use crate::mesh::Mesh;

/// The largest number of triangles in a leaf.
pub const MAX_LEAF: usize = 8;

// A leaf's triangle count is stored in a `u16`, and 0 marks interior nodes.
const _: () = assert!(MAX_LEAF >= 1 && MAX_LEAF <= u16::MAX as usize);

/// Bins per axis of the binned SAH.
const BINS: usize = 16;

/// Nodes at depth ≥ this (the root is depth 0) are split at the median instead of by the SAH.
const MAX_SAH_DEPTH: u32 = 64;

/// Traversal stack size: at most `MAX_SAH_DEPTH` SAH levels plus 32 median levels (2³² leaves).
const STACK: usize = 128;

/// A ray `origin + t·dir` for `0 < t < t_max`, prepared for box and triangle tests.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    origin: Vec3,
    dir: Vec3,
    t_max: f32,
    inv_dir: Vec3,
    /// The axes permuted so that `dir[k[2]]` has the largest magnitude (Woop's `kz`).
    k: [usize; 3],
    /// Woop's shear `(S_x, S_y, S_z)` = `(−d_x/d_z, −d_y/d_z, 1/d_z)` in the permuted axes.
    shear: Vec3,
}

impl Ray {
    /// The ray from `origin` along `dir` (any non-zero length; `t` is in units of it), unbounded.
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3) -> Ray {
        let a = dir.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let (kx, ky) = ((kz + 1) % 3, (kz + 2) % 3);
        let dz = dir[kz];
        Ray {
            origin,
            dir,
            t_max: f32::INFINITY,
            inv_dir: dir.recip(),
            k: [kx, ky, kz],
            shear: Vec3::new(-dir[kx] / dz, -dir[ky] / dz, 1.0 / dz),
        }
    }

    /// The open segment from `origin` to `target` (`dir = target − origin`, `t_max = 1`).
    #[must_use]
    pub fn segment(origin: Vec3, target: Vec3) -> Ray {
        Ray {
            t_max: 1.0,
            ..Ray::new(origin, target - origin)
        }
    }

    /// The ray's origin.
    #[must_use]
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// The ray's direction (as given, not normalised).
    #[must_use]
    pub fn dir(&self) -> Vec3 {
        self.dir
    }

    /// The end of the ray's parameter range (exclusive).
    #[must_use]
    pub fn t_max(&self) -> f32 {
        self.t_max
    }

    /// True if the ray can hit anything: finite origin, finite non-zero direction, `t_max > 0`
    /// (NaN is not).
    fn is_valid(&self) -> bool {
        self.origin.is_finite()
            && self.dir.is_finite()
            && self.dir != Vec3::ZERO
            && self.t_max > 0.0
    }

    /// `(t, u, v)` where the ray meets the triangle `corners` for `0 < t < t_max`, either side;
    /// `(u, v)` are the barycentric weights of corners 1 and 2. Watertight (see the module docs).
    #[must_use]
    pub fn hit_triangle(&self, corners: &[Vec3; 3], t_max: f32) -> Option<(f32, f32, f32)> {
        let [kx, ky, kz] = self.k;
        let s = self.shear;
        // Corners relative to the origin, permuted and sheared so the ray is the +z axis.
        let p = corners.map(|c| {
            let c = c - self.origin;
            Vec3::new(c[kx] + s.x * c[kz], c[ky] + s.y * c[kz], c[kz])
        });
        let edge = |a: Vec3, b: Vec3| a.x * b.y - a.y * b.x;
        let (mut e0, mut e1, mut e2) = (edge(p[1], p[2]), edge(p[2], p[0]), edge(p[0], p[1]));
        if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
            // On an edge in f32: decide in f64, as Woop et al. do, so neighbours agree.
            let edge64 = |a: Vec3, b: Vec3| {
                (f64::from(a.x) * f64::from(b.y) - f64::from(a.y) * f64::from(b.x)) as f32
            };
            (e0, e1, e2) = (edge64(p[1], p[2]), edge64(p[2], p[0]), edge64(p[0], p[1]));
        }
        if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
            return None;
        }
        let det = e0 + e1 + e2;
        if det == 0.0 {
            return None;
        }
        let t_scaled = (e0 * p[0].z + e1 * p[1].z + e2 * p[2].z) * s.z;
        // Behind the origin: t_scaled and det of opposite signs (or t_scaled zero).
        if (det < 0.0 && t_scaled >= 0.0) || (det > 0.0 && t_scaled <= 0.0) {
            return None;
        }
        // t itself against t_max, not t_scaled against t_max·det as pbrt does: both round, and
        // a t one ulp below t_max could be refused, so the closest of two coplanar faces lost.
        let inv = 1.0 / det;
        let t = t_scaled * inv;
        (t > 0.0 && t < t_max).then_some((t, e1 * inv, e2 * inv))
    }

    /// True if the ray enters the box `lo..hi` before `t_max`, both far ends widened by
    /// `1 + 2γ₃` so rounding cannot cull a hit on the box's face, nor one a few ulps nearer than
    /// the best so far (a coplanar overlapping face). NaN slab ends (`0 · ∞`: a zero direction
    /// component with the origin on the slab's plane, where the ray runs inside the closed slab)
    /// are ignored, which is conservative; the other slabs still count.
    #[inline]
    fn hits_box(&self, lo: Vec3, hi: Vec3, t_max: f32) -> bool {
        // 1 + 2γ₃ with γₙ = nε/(1 − nε), ε = 2⁻²⁴: pbrt's robust slab test.
        const WIDEN: f32 =
            1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);
        // Near and far planes by the sign of 1/dir (so of a zero component too), not by min and
        // max of the two ends, which would turn (NaN, ±∞) into a slab of ±∞ that culls the box.
        let negative = self.inv_dir.cmplt(Vec3::ZERO);
        let t_near = (Vec3::select(negative, hi, lo) - self.origin) * self.inv_dir;
        let t_far = (Vec3::select(negative, lo, hi) - self.origin) * self.inv_dir;
        // f32::max and f32::min return the other operand for a NaN: NaN ends drop out.
        let near = t_near.x.max(t_near.y).max(t_near.z).max(0.0);
        let far = t_far.x.min(t_far.y).min(t_far.z).min(t_max);
        near <= far * WIDEN
    }
}

/// The closest hit of a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Index of the triangle in [`Mesh::triangles`].
    pub triangle: u32,
    /// Barycentric weight of the triangle's corner 1.
    pub u: f32,
    /// Barycentric weight of the triangle's corner 2.
    pub v: f32,
}

/// A flattened node: a box and either its triangles (`count > 0`: `offset..offset + count` in
/// leaf order) or its children (`count == 0`: left at the next index, right at `offset`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    offset: u32,
    count: u16,
    axis: u8,
}

impl Node {
    /// True for a leaf, which holds triangles; an interior node holds two children.
    fn is_leaf(&self) -> bool {
        self.count > 0
    }

    /// The index of an interior node's right child (its left child is the node after it).
    fn right_child(&self) -> usize {
        self.offset as usize
    }

    /// The leaf-order indices of a leaf's triangles.
    fn triangles(&self) -> std::ops::Range<usize> {
        self.offset as usize..self.offset as usize + self.count as usize
    }
}

/// A bounding volume hierarchy over the triangles of a [`Mesh`] (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// The triangles' corners in leaf order.
    corners: Vec<[Vec3; 3]>,
    /// The mesh's index of each triangle in leaf order.
    ids: Vec<u32>,
}

impl Bvh {
    /// Builds the hierarchy over `mesh`'s triangles.
    #[must_use]
    pub fn new(mesh: &Mesh) -> Bvh {
        Bvh::build(mesh.triangles().len(), |id| mesh.corners(id))
    }

    /// Builds the hierarchy over `n` triangles (at most `u32::MAX`), triangle `id`'s corners
    /// being `corners(id)`. No triangles give an empty hierarchy, without nodes, that no ray hits
    /// (a [`Mesh`] always has a triangle, but a leaf of none would read as an interior node).
    fn build(n: usize, corners: impl Fn(u32) -> [Vec3; 3]) -> Bvh {
        if n == 0 {
            return Bvh {
                nodes: Vec::new(),
                corners: Vec::new(),
                ids: Vec::new(),
            };
        }
        let prims: Vec<Prim> = (0..n as u32)
            .map(|id| {
                let [a, b, c] = corners(id).map(Vec3A::from);
                let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
                Prim {
                    lo,
                    hi,
                    centroid: 0.5 * (lo + hi),
                    id,
                }
            })
            .collect();
        let mut builder = Builder {
            prims,
            nodes: Vec::with_capacity(2 * n.div_ceil(MAX_LEAF).max(1)),
        };
        builder.node(0, n, 0);
        let Builder { prims, nodes } = builder;
        Bvh {
            nodes,
            corners: prims.iter().map(|p| corners(p.id)).collect(),
            ids: prims.iter().map(|p| p.id).collect(),
        }
    }

    /// Number of nodes.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Depth of the tree (1 for a single leaf, 0 for an empty tree).
    #[must_use]
    pub fn depth(&self) -> usize {
        let mut deepest = 0;
        let mut stack = Vec::new();
        if !self.nodes.is_empty() {
            stack.push((0usize, 1usize));
        }
        while let Some((i, d)) = stack.pop() {
            deepest = deepest.max(d);
            let node = &self.nodes[i];
            if !node.is_leaf() {
                stack.push((i + 1, d + 1));
                stack.push((node.right_child(), d + 1));
            }
        }
        deepest
    }

    /// The closest hit along `ray` for `0 < t < ray.t_max()`, or `None`.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_vpl::{Bvh, Mesh, Ray, DEFAULT_MATERIAL};
    ///
    /// // The unit cube, seen from x = -5.
    /// let mesh = Mesh::cuboid(Vec3::ZERO, Vec3::ONE, DEFAULT_MATERIAL)?;
    /// let bvh = Bvh::new(&mesh);
    /// let hit = bvh.intersect(&Ray::new(Vec3::new(-5.0, 0.5, 0.5), Vec3::X)).unwrap();
    /// assert!((hit.t - 5.0).abs() < 1e-6);
    /// assert_eq!(mesh.face_normal(hit.triangle), -Vec3::X);
    /// // Beside the cube, or stopped short of it: no hit.
    /// assert!(bvh.intersect(&Ray::new(Vec3::new(-5.0, 2.0, 0.5), Vec3::X)).is_none());
    /// assert!(!bvh.occluded(Vec3::new(-5.0, 0.5, 0.5), Vec3::new(-1.0, 0.5, 0.5)));
    /// # Ok::<(), lgh_vpl::MeshError>(())
    /// ```
    #[must_use]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        self.intersect_where(ray, |_, _, _| true)
    }

    /// [`intersect`](Self::intersect) among the hits `keep(triangle, u, v)` accepts: the
    /// others are passed through (cut-outs, [`crate::Mesh::covers`]).
    #[must_use]
    pub fn intersect_where(&self, ray: &Ray, keep: impl Fn(u32, f32, f32) -> bool) -> Option<Hit> {
        let mut best = None;
        self.traverse(ray, |t_max, i| {
            let (t, u, v) = ray.hit_triangle(&self.corners[i], t_max)?;
            if !keep(self.ids[i], u, v) {
                return None;
            }
            best = Some(Hit {
                t,
                triangle: self.ids[i],
                u,
                v,
            });
            Some(t)
        });
        best
    }

    /// True if any triangle meets the open segment from `origin` to `target` (an any-hit
    /// query, for shadow rays: move both ends slightly off the surfaces they lie on, the one the
    /// ray leaves and, for a VPL, the one it ends on). False when `origin == target` or either is
    /// not finite.
    #[must_use]
    pub fn occluded(&self, origin: Vec3, target: Vec3) -> bool {
        self.occluded_where(origin, target, |_, _, _| true)
    }

    /// [`occluded`](Self::occluded) by the hits `keep(triangle, u, v)` accepts.
    #[must_use]
    pub fn occluded_where(
        &self,
        origin: Vec3,
        target: Vec3,
        keep: impl Fn(u32, f32, f32) -> bool,
    ) -> bool {
        let ray = Ray::segment(origin, target);
        let mut hit = false;
        self.traverse(&ray, |t_max, i| {
            let (_, u, v) = ray.hit_triangle(&self.corners[i], t_max)?;
            if !keep(self.ids[i], u, v) {
                return None;
            }
            hit = true;
            // A zero t_max ends the traversal at once.
            Some(0.0)
        });
        hit
    }

    /// Visits the leaf triangles (leaf-order indices) whose boxes `ray` enters before the current
    /// `t_max`, starting from `ray.t_max()`. `visit(t_max, i)` returns `None` to leave `t_max`
    /// as it is, or `Some(t)` to make `t` the new `t_max` (the `t < t_max` of an accepted hit);
    /// `Some(t)` with `t <= 0`, such as `Some(0.0)`, stops the traversal at once.
    #[inline]
    fn traverse(&self, ray: &Ray, mut visit: impl FnMut(f32, usize) -> Option<f32>) {
        if !ray.is_valid() || self.nodes.is_empty() {
            return;
        }
        let negative = [ray.dir.x < 0.0, ray.dir.y < 0.0, ray.dir.z < 0.0];
        let mut t_max = ray.t_max;
        let mut stack = [0u32; STACK];
        let mut top = 0;
        let mut index = 0usize;
        loop {
            let node = &self.nodes[index];
            if ray.hits_box(node.lo, node.hi, t_max) {
                if !node.is_leaf() {
                    let (left, right) = (index + 1, node.right_child());
                    let (near, far) = if negative[node.axis as usize] {
                        (right, left)
                    } else {
                        (left, right)
                    };
                    stack[top] = far as u32;
                    top += 1;
                    index = near;
                    continue;
                }
                for i in node.triangles() {
                    if let Some(t) = visit(t_max, i) {
                        t_max = t;
                        if t_max <= 0.0 {
                            return;
                        }
                    }
                }
            }
            if top == 0 {
                return;
            }
            top -= 1;
            index = stack[top] as usize;
        }
    }
}

/// A triangle's box, its centre and its index in the mesh, for the build.
#[derive(Clone, Copy)]
struct Prim {
    lo: Vec3A,
    hi: Vec3A,
    centroid: Vec3A,
    id: u32,
}

/// An empty box.
const EMPTY: (Vec3A, Vec3A) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);

/// Half the surface area of the box `lo..hi` (0 for an empty box).
fn half_area((lo, hi): (Vec3A, Vec3A)) -> f32 {
    let d = (hi - lo).max(Vec3A::ZERO);
    d.x * d.y + d.y * d.z + d.z * d.x
}

/// The union of two boxes.
fn union(a: (Vec3A, Vec3A), b: (Vec3A, Vec3A)) -> (Vec3A, Vec3A) {
    (a.0.min(b.0), a.1.max(b.1))
}

/// The top-down build. The primitives themselves are partitioned (not indices to them), so every
/// pass over a node reads memory in order; they end in leaf order.
struct Builder {
    prims: Vec<Prim>,
    nodes: Vec<Node>,
}

impl Builder {
    /// Builds the node over `prims[start..end]` (not empty) and its subtree; returns its index.
    fn node(&mut self, start: usize, end: usize, depth: u32) -> u32 {
        let index = self.nodes.len();
        self.nodes.push(Node::default());
        let (mut bounds, mut centres) = (EMPTY, EMPTY);
        for p in &self.prims[start..end] {
            bounds = union(bounds, (p.lo, p.hi));
            centres = union(centres, (p.centroid, p.centroid));
        }
        let n = end - start;
        let sah = (depth < MAX_SAH_DEPTH)
            .then(|| self.sah_split(start, end, bounds, centres))
            .flatten();
        let mid = match sah {
            Some((cost, mid)) if n > MAX_LEAF || cost < n as f32 => Some(mid),
            None if n > MAX_LEAF => Some(self.median_split(start, end, centres)),
            _ => None,
        };
        let (lo, hi) = (Vec3::from(bounds.0), Vec3::from(bounds.1));
        self.nodes[index] = match mid {
            None => Node {
                lo,
                hi,
                offset: start as u32,
                count: n as u16,
                axis: 0,
            },
            Some((axis, mid)) => {
                self.node(start, mid, depth + 1);
                let right = self.node(mid, end, depth + 1);
                Node {
                    lo,
                    hi,
                    offset: right,
                    count: 0,
                    axis,
                }
            }
        };
        index as u32
    }

    /// The cheapest binned SAH split of `prims[start..end]`: its cost and `(axis, mid)` after
    /// partitioning the primitives around it; `None` if the centroids coincide on every axis.
    fn sah_split(
        &mut self,
        start: usize,
        end: usize,
        bounds: (Vec3A, Vec3A),
        centres: (Vec3A, Vec3A),
    ) -> Option<(f32, (u8, usize))> {
        let extent = centres.1 - centres.0;
        // Axes without extent bin everything into bin 0 and are skipped below.
        let scale = Vec3A::select(
            extent.cmpgt(Vec3A::ZERO),
            Vec3A::splat(BINS as f32) / extent,
            Vec3A::ZERO,
        );
        let bin = |c: Vec3A, axis: usize| {
            (((c[axis] - centres.0[axis]) * scale[axis]) as usize).min(BINS - 1)
        };
        // All three axes binned in one pass.
        let mut boxes = [[EMPTY; BINS]; 3];
        let mut counts = [[0usize; BINS]; 3];
        for p in &self.prims[start..end] {
            for axis in 0..3 {
                let b = bin(p.centroid, axis);
                boxes[axis][b] = union(boxes[axis][b], (p.lo, p.hi));
                counts[axis][b] += 1;
            }
        }
        let parent = half_area(bounds);
        let mut best: Option<(f32, usize, usize)> = None;
        for axis in (0..3).filter(|&a| extent[a] > 0.0) {
            let (boxes, counts) = (&boxes[axis], &counts[axis]);
            // right[i]: area × count of bins i + 1 ..; NaN when they are empty.
            let mut right = [0.0f32; BINS];
            let (mut acc, mut count) = (EMPTY, 0);
            for i in (1..BINS).rev() {
                acc = union(acc, boxes[i]);
                count += counts[i];
                right[i - 1] = if count > 0 {
                    half_area(acc) * count as f32
                } else {
                    f32::NAN
                };
            }
            let (mut acc, mut count) = (EMPTY, 0);
            for i in 0..BINS - 1 {
                acc = union(acc, boxes[i]);
                count += counts[i];
                let cost = 1.0 + (half_area(acc) * count as f32 + right[i]) / parent;
                // Both sides non-empty (an empty right side made the cost NaN).
                if count > 0 && cost.is_finite() && best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, axis, i));
                }
            }
        }
        let (cost, axis, split) = best?;
        let slice = &mut self.prims[start..end];
        let mut mid = 0;
        for i in 0..slice.len() {
            if bin(slice[i].centroid, axis) <= split {
                slice.swap(i, mid);
                mid += 1;
            }
        }
        Some((cost, (axis as u8, start + mid)))
    }

    /// Splits `prims[start..end]` at its median centroid on the widest centroid axis (ties by
    /// triangle index, so it is deterministic); returns `(axis, mid)`.
    fn median_split(&mut self, start: usize, end: usize, centres: (Vec3A, Vec3A)) -> (u8, usize) {
        let axis = (centres.1 - centres.0).max_position();
        let mid = (end - start) / 2;
        self.prims[start..end].select_nth_unstable_by(mid, |a, b| {
            a.centroid[axis]
                .total_cmp(&b.centroid[axis])
                .then(a.id.cmp(&b.id))
        });
        (axis as u8, start + mid)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Triangle;
    use lgh_core::random::SplitMix64;
    use lgh_core::Material;

    const GREY: Material = Material::Lambert {
        albedo: Vec3::splat(0.5),
    };

    /// A mesh of separate triangles.
    fn soup(corners: &[[Vec3; 3]]) -> Mesh {
        let positions = corners.iter().flatten().copied().collect();
        let triangles = (0..corners.len() as u32)
            .map(|i| Triangle {
                vertices: [3 * i, 3 * i + 1, 3 * i + 2],
                normals: None,
                texcoords: None,
                material: 0,
            })
            .collect();
        Mesh::new(positions, vec![], triangles, vec![GREY]).unwrap()
    }

    /// `n` random triangles in the cube [−5, 5]³: most small, some long and thin, some large;
    /// a clump of 40 identical ones (coincident centroids, for the median split); and 400
    /// overlapping ones in the plane z = 0.3, whose hits differ by an ulp or two (rounding, not
    /// geometry), so that only the very closest agrees with brute force bit for bit.
    fn random_soup(n: usize, seed: u64) -> Vec<[Vec3; 3]> {
        let mut rng = SplitMix64(seed);
        let mut tris: Vec<[Vec3; 3]> = (0..n)
            .map(|i| {
                let size = match i % 10 {
                    0 => 4.0,
                    1 | 2 => 1.5,
                    _ => 0.4,
                };
                let c = rng.next_in(Vec3::splat(-5.0), Vec3::splat(5.0));
                let mut corner = || c + rng.next_in(Vec3::splat(-size), Vec3::splat(size));
                [corner(), corner(), corner()]
            })
            .collect();
        let same = [Vec3::ZERO, Vec3::X, Vec3::Y];
        tris.extend(std::iter::repeat_n(same, 40));
        let (lo, hi) = (Vec3::new(-4.0, -4.0, 0.3), Vec3::new(4.0, 4.0, 0.3));
        tris.extend((0..400).map(|_| {
            let c = rng.next_in(lo, hi);
            let mut corner =
                || c + rng.next_in(Vec3::new(-2.0, -2.0, 0.0), Vec3::new(2.0, 2.0, 0.0));
            [corner(), corner(), corner()]
        }));
        tris
    }

    /// The closest hit over every triangle, in index order (ties keep the lowest index).
    fn brute_closest(ray: &Ray, tris: &[[Vec3; 3]]) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        for (i, c) in tris.iter().enumerate() {
            let t_max = best.map_or(ray.t_max(), |h| h.t);
            if let Some((t, u, v)) = ray.hit_triangle(c, t_max) {
                best = Some(Hit {
                    t,
                    triangle: i as u32,
                    u,
                    v,
                });
            }
        }
        best
    }

    #[test]
    fn closest_hits_and_occlusion_match_brute_force_on_random_rays() {
        let tris = random_soup(3000, 7);
        let mesh = soup(&tris);
        let bvh = Bvh::new(&mesh);
        assert!(bvh.depth() <= 96, "depth {}", bvh.depth());
        let mut rng = SplitMix64(11);
        let (mut hits, mut occluded) = (0, 0);
        for i in 0..4000 {
            // Rays from inside and outside the soup's box; every 8th axis-aligned (zero
            // direction components); every 4th a bounded segment.
            let origin = rng.next_in(Vec3::splat(-8.0), Vec3::splat(8.0));
            let mut dir = rng.next_in(Vec3::splat(-1.0), Vec3::ONE);
            if i % 8 == 0 {
                dir = Vec3::new(dir.x, 0.0, 0.0);
            }
            let ray = if i % 4 == 1 {
                Ray::segment(origin, origin + dir * 6.0)
            } else {
                Ray::new(origin, dir)
            };
            let got = bvh.intersect(&ray);
            let want = brute_closest(&ray, &tris);
            match (got, want) {
                (None, None) => {}
                (Some(g), Some(w)) => {
                    hits += 1;
                    // Same test on the same corners: the same t, bit for bit. On a tie the
                    // BVH may report another triangle at the same t.
                    assert_eq!(g.t, w.t, "ray {i}");
                    if g.triangle != w.triangle {
                        let again = ray.hit_triangle(&tris[g.triangle as usize], f32::INFINITY);
                        assert_eq!(again.map(|h| h.0), Some(g.t), "ray {i}");
                    } else {
                        assert_eq!((g.u, g.v), (w.u, w.v), "ray {i}");
                    }
                }
                _ => panic!("ray {i}: bvh {got:?}, brute force {want:?}"),
            }
            let target = origin + dir * 3.0;
            let segment = Ray::segment(origin, target);
            let any = tris.iter().any(|c| segment.hit_triangle(c, 1.0).is_some());
            assert_eq!(bvh.occluded(origin, target), any, "segment {i}");
            occluded += usize::from(any);
        }
        // The test means something only if both outcomes are common.
        assert!((1000..3500).contains(&hits), "{hits} hits");
        assert!((500..3500).contains(&occluded), "{occluded} occluded");
    }

    #[test]
    fn rays_from_inside_a_closed_box_never_escape() {
        let mesh = Mesh::cuboid(Vec3::splat(-1.0), Vec3::new(2.0, 1.0, 3.0), GREY).unwrap();
        let bvh = Bvh::new(&mesh);
        let mut rng = SplitMix64(3);
        let centre = Vec3::new(0.1, 0.05, 0.2);
        // Straight at every corner (three faces, six triangles meet there) and at the middle of
        // every edge, then random directions.
        let (lo, hi) = mesh.bounds();
        let mut targets: Vec<Vec3> = (0..8)
            .map(|i| {
                Vec3::select(
                    lgh_core::glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0),
                    hi,
                    lo,
                )
            })
            .collect();
        for a in 0..8 {
            for b in a + 1..8 {
                targets.push(0.5 * (targets[a] + targets[b]));
            }
        }
        targets.extend((0..2000).map(|_| rng.next_in(Vec3::splat(-1.0), Vec3::ONE)));
        for target in targets {
            let ray = Ray::new(centre, target - centre);
            assert!(bvh.intersect(&ray).is_some(), "escaped towards {target}");
        }
    }

    #[test]
    fn triangle_test_reports_t_and_barycentrics() {
        let c = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        let ray = Ray::new(Vec3::new(0.5, 0.25, 3.0), Vec3::new(0.0, 0.0, -2.0));
        let (t, u, v) = ray.hit_triangle(&c, f32::INFINITY).unwrap();
        assert_eq!((t, u, v), (1.5, 0.25, 0.125));
        // Either side; not past t_max; not behind the origin.
        let back = Ray::new(Vec3::new(0.5, 0.25, -3.0), Vec3::Z);
        assert_eq!(back.hit_triangle(&c, f32::INFINITY).map(|h| h.0), Some(3.0));
        assert_eq!(back.hit_triangle(&c, 3.0), None);
        assert_eq!(
            Ray::new(Vec3::new(0.5, 0.25, 1.0), Vec3::Z).hit_triangle(&c, 9.0),
            None
        );
        // A hit at t is reported exactly when t < t_max: for t_max one ulp above t, not at t.
        let mut rng = SplitMix64(9);
        let mut checked = 0;
        for _ in 0..5000 {
            let corners = [(); 3].map(|_| rng.next_in(Vec3::splat(-1.0), Vec3::ONE));
            // Aimed inside the triangle (each weight 1/9 to 2/3), so nearly all hit.
            let w = rng.next_in(Vec3::splat(0.25), Vec3::ONE);
            let target = (w.x * corners[0] + w.y * corners[1] + w.z * corners[2]) / w.element_sum();
            let origin = rng.next_in(Vec3::splat(-3.0), Vec3::splat(3.0));
            let ray = Ray::new(origin, target - origin);
            if let Some(hit) = ray.hit_triangle(&corners, f32::INFINITY) {
                let above = f32::from_bits(hit.0.to_bits() + 1);
                assert_eq!(ray.hit_triangle(&corners, above), Some(hit));
                assert_eq!(ray.hit_triangle(&corners, hit.0), None);
                checked += 1;
            }
        }
        assert!(checked > 4900, "{checked}");
    }

    #[test]
    fn rays_in_the_plane_of_a_box_face_hit_and_nan_slabs_are_ignored() {
        // A triangle standing on z = 0 with its bottom edge along y. Rays along x with zero y and
        // z components (of either sign) run in the plane of its box's face z = 0, where the slab
        // test computes 0 · ∞ = NaN, and meet that edge at t = 1.
        let tri = [
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(1.0, 0.0, 2.0),
        ];
        let bvh = Bvh::new(&soup(&[tri]));
        for dir in [Vec3::X, Vec3::new(1.0, -0.0, -0.0)] {
            let ray = Ray::new(Vec3::ZERO, dir);
            assert_eq!(
                ray.hit_triangle(&tri, f32::INFINITY).map(|h| h.0),
                Some(1.0)
            );
            assert_eq!(bvh.intersect(&ray).map(|h| h.t), Some(1.0), "{dir}");
            assert!(bvh.occluded(Vec3::ZERO, 2.0 * dir), "{dir}");
        }
        // The NaN slab (z) drops out, the others still count: y keeps this box off the ray.
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        let (lo, hi) = (Vec3::new(5.0, 5.0, -1.0), Vec3::new(6.0, 6.0, 0.0));
        assert!(!ray.hits_box(lo, hi, f32::INFINITY));
        assert!(ray.hits_box(Vec3::new(lo.x, -1.0, lo.z), hi, f32::INFINITY));
    }

    #[test]
    fn an_empty_hierarchy_has_no_nodes_and_hits_nothing() {
        let empty = Bvh::build(0, |_| unreachable!());
        assert_eq!((empty.node_count(), empty.depth()), (0, 0));
        assert_eq!(empty.intersect(&Ray::new(Vec3::ZERO, Vec3::X)), None);
        assert!(!empty.occluded(Vec3::ZERO, Vec3::X));
    }

    #[test]
    fn degenerate_rays_hit_nothing_and_builds_are_deterministic() {
        let mesh = soup(&random_soup(500, 1));
        let bvh = Bvh::new(&mesh);
        assert_eq!(bvh, Bvh::new(&mesh));
        for (o, d) in [
            (Vec3::ZERO, Vec3::ZERO),
            (Vec3::splat(f32::NAN), Vec3::X),
            (Vec3::ZERO, Vec3::new(f32::INFINITY, 0.0, 0.0)),
        ] {
            assert_eq!(bvh.intersect(&Ray::new(o, d)), None);
        }
        assert!(!bvh.occluded(Vec3::ZERO, Vec3::ZERO));
        // A single triangle is a single leaf.
        let one = Bvh::new(&soup(&[[Vec3::ZERO, Vec3::X, Vec3::Y]]));
        assert_eq!((one.node_count(), one.depth()), (1, 1));
    }
}
