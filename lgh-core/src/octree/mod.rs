//! The light hierarchy of Paquette, Poulin & Drettakis (1998, `papers/004_…`), §3: an octree over
//! the point lights, each node standing for the lights below it by a *virtual light*.
//!
//! Construction (§3.2, Table 1): the root is the axis-aligned bounding box of all the lights; a
//! cell is split at its centre into eight while it holds more than `max_leaf` lights and is less
//! than `max_depth` deep. Each node keeps
//! - its virtual light: the summed intensity `I_v = Σ I_i` at the intensity-weighted mean position
//!   `P_v = Σ ‖I_i‖₁ p_i / Σ ‖I_i‖₁` (§3.2 weights by intensity; for RGB intensities the weight is
//!   their 1-norm, as ARCHITECTURE.md at the repository root records; a node of dark lights sits
//!   at their plain mean);
//! - its *minimal bounding box*: the smallest axis-aligned box of its lights, whose diagonal is the
//!   `Δd_max` of the error bounds (§4).
//!
//! Shading with the error bounds of §4 is [`OctreeBackend`] (module `shading`, bounds in `bounds`).

use alloc::vec::Vec;
use glam::Vec3;

use crate::error::BuildError;
use crate::light::{validate_lights, Channels, PointLight};

mod bounds;
mod shading;

pub use shading::{OctreeBackend, EXACT_SUM_LIGHTS};

/// The deepest subdivision the octree allows: 2⁻²⁴ of the root box is below f32 resolution of
/// its coordinates, so deeper cells could not separate lights anyway.
pub const MAX_OCTREE_DEPTH: u8 = 24;

/// How far the octree is subdivided (§3.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OctreeSettings {
    /// A cell holding more lights than this is split (≥ 1).
    pub max_leaf: usize,
    /// The deepest level (the root is level 0), at most [`MAX_OCTREE_DEPTH`]. Coincident lights
    /// end up together in a leaf at this depth.
    pub max_depth: u8,
}

impl Default for OctreeSettings {
    /// Leaves of at most 3 lights, the node size that §4's shading sums exactly anyway; depth 16.
    fn default() -> Self {
        OctreeSettings {
            max_leaf: 3,
            max_depth: 16,
        }
    }
}

/// A node of the light octree.
#[derive(Clone, Debug, PartialEq)]
pub struct OctreeNode {
    /// The virtual light: `I_v = Σ I_i` at `P_v`, the `‖I‖₁`-weighted mean of the lights' positions.
    pub light: PointLight,
    /// The minimal bounding box `(lo, hi)` of the node's lights.
    pub min_box: (Vec3, Vec3),
    /// Depth (the root is 0).
    pub depth: u8,
    /// The node's lights: `lights[start..end]` of [`LightOctree::lights`].
    pub start: u32,
    /// End of the node's lights.
    pub end: u32,
    /// The node's non-empty children: `nodes[first_child..first_child + children]`; none for a
    /// leaf.
    pub first_child: u32,
    /// Number of non-empty children (0 to 8).
    pub children: u8,
}

impl OctreeNode {
    /// Number of lights below the node.
    #[must_use]
    pub fn count(&self) -> usize {
        (self.end - self.start) as usize
    }

    /// Whether the node is a leaf (its lights are summed one by one).
    #[must_use]
    pub fn is_leaf(&self) -> bool {
        self.children == 0
    }

    /// The largest diagonal of the minimal bounding box: `Δd_max` of §4.
    #[must_use]
    pub fn diagonal(&self) -> f32 {
        (self.min_box.1 - self.min_box.0).length()
    }
}

/// Paquette et al.'s light octree over a set of point lights.
#[derive(Clone, Debug, PartialEq)]
pub struct LightOctree {
    /// The lights, reordered so that every node's lights are contiguous.
    lights: Vec<PointLight>,
    /// Nodes, the root first (none without lights); each node's children are contiguous.
    nodes: Vec<OctreeNode>,
    settings: OctreeSettings,
}

impl LightOctree {
    /// Builds the octree of `lights` (positions finite, intensities finite and ≥ 0). No lights
    /// make an empty tree.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{LightOctree, OctreeSettings, PointLight};
    ///
    /// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let tree = LightOctree::build(&lights, &OctreeSettings { max_leaf: 8, max_depth: 16 })?;
    /// let root = tree.root().unwrap();
    /// assert_eq!(root.count(), 64);
    /// assert_eq!(root.light.intensity, Vec3::splat(64.0)); // the virtual light: Σ I_i …
    /// assert_eq!(root.light.position, Vec3::splat(1.5)); // … at their ‖I‖₁-weighted mean
    /// assert!(tree.nodes().iter().all(|n| !n.is_leaf() || n.count() <= 8));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn build(lights: &[PointLight], settings: &OctreeSettings) -> Result<Self, BuildError> {
        if settings.max_leaf == 0 || settings.max_depth > MAX_OCTREE_DEPTH {
            return Err(BuildError::InvalidOctreeSettings {
                max_leaf: settings.max_leaf,
                max_depth: settings.max_depth,
                max: MAX_OCTREE_DEPTH,
            });
        }
        validate_lights(lights, Channels::NonNegative)?;
        let mut tree = LightOctree {
            lights: lights.to_vec(),
            nodes: Vec::new(),
            settings: *settings,
        };
        if lights.is_empty() {
            return Ok(tree);
        }
        let (lo, hi) = crate::grid::bounds(lights);
        tree.nodes.push(tree.node(0, lights.len(), 0));
        // Breadth-first: a node's children are appended together, so they are contiguous.
        let mut next = 0;
        let mut cells = Vec::from([(lo, hi)]);
        while next < tree.nodes.len() {
            let (cell_lo, cell_hi) = cells[next];
            let (start, end, depth) = {
                let n = &tree.nodes[next];
                (n.start as usize, n.end as usize, n.depth)
            };
            if end - start > settings.max_leaf && depth < settings.max_depth {
                let mid = 0.5 * (cell_lo + cell_hi);
                let bounds = tree.split(start, end, mid);
                let first_child = tree.nodes.len();
                for octant in 0..8 {
                    let (s, e) = (bounds[octant], bounds[octant + 1]);
                    if s == e {
                        continue;
                    }
                    let pick = |bit: usize, a: usize| {
                        if octant & bit != 0 {
                            mid[a]
                        } else {
                            cell_lo[a]
                        }
                    };
                    let pick_hi = |bit: usize, a: usize| {
                        if octant & bit != 0 {
                            cell_hi[a]
                        } else {
                            mid[a]
                        }
                    };
                    cells.push((
                        Vec3::new(pick(1, 0), pick(2, 1), pick(4, 2)),
                        Vec3::new(pick_hi(1, 0), pick_hi(2, 1), pick_hi(4, 2)),
                    ));
                    let child = tree.node(s, e, depth + 1);
                    tree.nodes.push(child);
                }
                let children = (tree.nodes.len() - first_child) as u8;
                let node = &mut tree.nodes[next];
                node.first_child = first_child as u32;
                node.children = children;
            }
            next += 1;
        }
        Ok(tree)
    }

    /// Sorts `lights[start..end]` by octant about `mid` (x in bit 0, y in bit 1, z in bit 2, a
    /// light on a mid-plane going to the upper side), stably; returns the nine octant bounds.
    fn split(&mut self, start: usize, end: usize, mid: Vec3) -> [usize; 9] {
        let octant = |p: Vec3| {
            usize::from(p.x >= mid.x)
                | usize::from(p.y >= mid.y) << 1
                | usize::from(p.z >= mid.z) << 2
        };
        let run = &mut self.lights[start..end];
        run.sort_by_key(|l| octant(l.position));
        let mut bounds = [end; 9];
        bounds[0] = start;
        let mut o = 0;
        for (i, l) in run.iter().enumerate() {
            let k = octant(l.position);
            while o < k {
                o += 1;
                bounds[o] = start + i;
            }
        }
        for b in bounds.iter_mut().skip(o + 1) {
            *b = end;
        }
        bounds
    }

    /// The node over `lights[start..end]` (not empty) at `depth`: its virtual light and minimal
    /// box, summed in f64 in light order (deterministic).
    fn node(&self, start: usize, end: usize, depth: u8) -> OctreeNode {
        let run = &self.lights[start..end];
        let (lo, hi) = crate::grid::bounds(run);
        let mut intensity = [0.0f64; 3];
        let mut weighted = [0.0f64; 3];
        let mut plain = [0.0f64; 3];
        let mut weight = 0.0f64;
        for l in run {
            let w = f64::from(l.intensity.x) + f64::from(l.intensity.y) + f64::from(l.intensity.z);
            for a in 0..3 {
                intensity[a] += f64::from(l.intensity[a]);
                weighted[a] += w * f64::from(l.position[a]);
                plain[a] += f64::from(l.position[a]);
            }
            weight += w;
        }
        let position = if weight > 0.0 {
            weighted.map(|v| (v / weight) as f32)
        } else {
            plain.map(|v| (v / run.len() as f64) as f32)
        };
        // Rounding must not take the position out of the box its lights span.
        let position = Vec3::from(position).clamp(lo, hi);
        OctreeNode {
            light: PointLight::new(position, Vec3::from(intensity.map(|v| v as f32))),
            min_box: (lo, hi),
            depth,
            start: start as u32,
            end: end as u32,
            first_child: 0,
            children: 0,
        }
    }

    /// The lights, in the tree's order.
    #[must_use]
    pub fn lights(&self) -> &[PointLight] {
        &self.lights
    }

    /// The nodes, the root first (empty without lights).
    #[must_use]
    pub fn nodes(&self) -> &[OctreeNode] {
        &self.nodes
    }

    /// The root, if there are lights.
    #[must_use]
    pub fn root(&self) -> Option<&OctreeNode> {
        self.nodes.first()
    }

    /// The children of `node`.
    #[must_use]
    pub fn children(&self, node: &OctreeNode) -> &[OctreeNode] {
        let first = node.first_child as usize;
        &self.nodes[first..first + node.children as usize]
    }

    /// The lights below `node`.
    #[must_use]
    pub fn lights_of(&self, node: &OctreeNode) -> &[PointLight] {
        &self.lights[node.start as usize..node.end as usize]
    }

    /// The settings it was built with.
    #[must_use]
    pub fn settings(&self) -> &OctreeSettings {
        &self.settings
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;
    use wasm_bindgen_test::wasm_bindgen_test;

    /// Checks every node against its definition (§3.2) and the tree's structure.
    fn check(tree: &LightOctree) {
        let s = tree.settings();
        for node in tree.nodes() {
            let run = tree.lights_of(node);
            assert!(!run.is_empty());
            // Minimal box: exactly the lights' box.
            assert_eq!(node.min_box, crate::grid::bounds(run));
            // Virtual light: the summed intensity, an f64 sum rounded once to f32 (relative error
            // ≤ 2⁻²⁴ ≈ 6·10⁻⁸; the bound allows 10⁻⁶) …
            let sum = run.iter().fold([0.0f64; 3], |acc, l| {
                [0, 1, 2].map(|a| acc[a] + f64::from(l.intensity[a]))
            });
            for (a, &want) in sum.iter().enumerate() {
                assert!((f64::from(node.light.intensity[a]) - want).abs() <= 1e-6 * want);
            }
            // … at the ‖I‖₁-weighted mean, inside the box.
            let w: f64 = run
                .iter()
                .map(|l| f64::from(l.intensity.element_sum()))
                .sum();
            if w > 0.0 {
                for a in 0..3 {
                    let mean = run
                        .iter()
                        .map(|l| f64::from(l.intensity.element_sum()) * f64::from(l.position[a]))
                        .sum::<f64>()
                        / w;
                    let tol = 1e-6 * (1.0 + mean.abs());
                    assert!((f64::from(node.light.position[a]) - mean).abs() <= tol);
                }
            }
            let p = node.light.position;
            assert!(p.cmpge(node.min_box.0).all() && p.cmple(node.min_box.1).all());
            if node.is_leaf() {
                assert!(node.count() <= s.max_leaf || node.depth == s.max_depth);
            } else {
                // The children split the node's lights, in order, one level deeper.
                let kids = tree.children(node);
                assert_eq!(kids.len(), node.children as usize);
                assert_eq!(kids[0].start, node.start);
                assert_eq!(kids[kids.len() - 1].end, node.end);
                assert!(kids.windows(2).all(|k| k[0].end == k[1].start));
                assert!(kids.iter().all(|k| k.depth == node.depth + 1));
            }
        }
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn nodes_hold_their_virtual_lights_and_minimal_boxes() {
        for (n, max_leaf) in [(1usize, 3usize), (2, 1), (500, 3), (2000, 8)] {
            let lights = crate::testsets::clumped_lights(n, n as u64);
            let settings = OctreeSettings {
                max_leaf,
                ..Default::default()
            };
            let tree = LightOctree::build(&lights, &settings).unwrap();
            check(&tree);
            // Every light once, root first.
            assert_eq!(tree.root().unwrap().count(), n);
            let mut a: Vec<_> = lights
                .iter()
                .map(|l| l.position.to_array().map(f32::to_bits))
                .collect();
            let mut b: Vec<_> = tree
                .lights()
                .iter()
                .map(|l| l.position.to_array().map(f32::to_bits))
                .collect();
            a.sort_unstable();
            b.sort_unstable();
            assert_eq!(a, b);
            // The same lights give the same tree.
            assert_eq!(tree, LightOctree::build(&lights, &settings).unwrap());
        }
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn coincident_lights_stop_at_the_depth_limit() {
        let mut lights = vec![PointLight::new(Vec3::splat(1.5), Vec3::ONE); 50];
        lights.push(PointLight::new(Vec3::splat(2.5), Vec3::ONE));
        let settings = OctreeSettings {
            max_leaf: 3,
            max_depth: 6,
        };
        let tree = LightOctree::build(&lights, &settings).unwrap();
        check(&tree);
        let deepest = tree.nodes().iter().map(|n| n.depth).max().unwrap();
        assert_eq!(deepest, 6);
        assert!(tree.nodes().iter().any(|n| n.is_leaf() && n.count() == 50));
        // All at one point: the box has no extent, every split keeps them together, and the
        // build ends at the depth limit.
        let same = vec![PointLight::new(Vec3::ZERO, Vec3::ONE); 10];
        let tree = LightOctree::build(&same, &settings).unwrap();
        check(&tree);
        assert_eq!(tree.nodes().len(), 7);
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn no_lights_is_an_empty_tree_and_bad_input_an_error() {
        let s = OctreeSettings::default();
        let empty = LightOctree::build(&[], &s).unwrap();
        assert!(empty.root().is_none());
        let nan = [PointLight::new(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::ONE)];
        assert_eq!(
            LightOctree::build(&nan, &s),
            Err(BuildError::NonFinitePosition { index: 0 })
        );
        let negative = [PointLight::new(Vec3::ZERO, Vec3::new(1.0, -1.0, 0.0))];
        assert_eq!(
            LightOctree::build(&negative, &s),
            Err(BuildError::InvalidIntensity { index: 0 })
        );
        let out_of_gamut = [PointLight::new(Vec3::ZERO, Vec3::new(1.0, -0.1, 0.0))];
        assert_eq!(
            LightOctree::build(&out_of_gamut, &s),
            Err(BuildError::NegativeChannel { index: 0 })
        );
        for bad in [
            OctreeSettings {
                max_leaf: 0,
                max_depth: 4,
            },
            OctreeSettings {
                max_leaf: 3,
                max_depth: MAX_OCTREE_DEPTH + 1,
            },
        ] {
            assert!(matches!(
                LightOctree::build(&[], &bad),
                Err(BuildError::InvalidOctreeSettings { .. })
            ));
        }
    }
}
