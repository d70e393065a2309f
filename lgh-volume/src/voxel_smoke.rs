//! The smoke in each voxel light's own voxel: what sets the escape of its light
//! (`lgh_core::near_field::escape`).
//!
//! A voxel light's light leaves its voxel through that voxel's smoke, and a shadow ray to its
//! centre attenuates all of it as if it came from the centre: the escape `R(u, τ)` corrects
//! that for a uniform voxel in uniform smoke of `τ` optical depths a voxel. The `τ` that
//! matters is the light's own voxel's, `σ_t(c) h` at its centre `c`: where the smoke varies
//! from voxel to voxel, the shading point's extinction is another voxel's, and a point in dense
//! soot lit by a light in clear air took the dense voxel's escape — up to 3× at 4.7 optical
//! depths a voxel (the demo's soot at 32³), which made each depth of scattered light brighter
//! than the one before. [`VoxelSmoke`] holds `τ` at every voxel centre of the lights' grid, and
//! [`LightSmoke`] each light's, listed by its index in a many-lights backend, so that a light is
//! shaded with its own voxel's, or the point's where that is thinner (`Lights::with_smoke`).
//!
//! Both also hold where each light's cell emits — the offset of its emission's centroid from
//! the voxel's centre (`crate::voxel_light`, "The near field's centre") — at which its near
//! field is centred; a voxel given none is centred on itself.

use std::sync::Arc;

use lgh_core::glam::Vec3;

use crate::grid::{unflatten, DenseGrid};
use crate::medium::Medium;

/// `τ = σ_t h` at the centre of every voxel of a light grid, and where each voxel light's cell
/// emits (module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelSmoke {
    /// The optical depth a voxel at each centre, on the lights' layout (shared by the smoke
    /// with and without centroids).
    depth: Arc<DenseGrid>,
    /// Each light voxel's emission centroid, from its centre (world units), by the voxel's
    /// linear index, strictly ascending ([`with_centroids`](Self::with_centroids)); a voxel
    /// absent is centred on itself.
    centroids: Vec<(usize, Vec3)>,
}

impl VoxelSmoke {
    /// The smoke of `density` (on any layout, sampled trilinearly) at the centres of `layout`'s
    /// voxels (its values are not read), in optical depths of one of `layout`'s voxels.
    ///
    /// ```
    /// use lgh_volume::grid::DenseGrid;
    /// use lgh_volume::voxel_smoke::VoxelSmoke;
    /// use lgh_volume::Medium;
    /// use lgh_volume::lgh_core::glam::Vec3;
    ///
    /// let mut density = DenseGrid::zeros([4, 4, 4], 0.5, Vec3::ZERO);
    /// let at = density.index(1, 2, 3);
    /// density.data[at] = 2.0;
    /// let medium = Medium::new(1.0, 3.0, 1e-4, 1000.0)?; // σ_t = 4 ρ
    /// let smoke = VoxelSmoke::of(&density, &density, &medium);
    /// assert_eq!(smoke.at(density.centre(1, 2, 3)), 4.0); // 4 · 2 · 0.5
    /// assert_eq!(smoke.at(density.centre(0, 0, 0)), 0.0);
    /// assert_eq!(smoke.at(Vec3::splat(-9.0)), 0.0); // outside: clear air
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn of(layout: &DenseGrid, density: &DenseGrid, medium: &Medium) -> Self {
        let h = layout.voxel_size;
        let [nx, ny, nz] = layout.dims;
        let data = if density.same_layout(layout) {
            density
                .data
                .iter()
                .map(|&rho| medium.extinction(rho) * h)
                .collect()
        } else {
            (0..nx * ny * nz)
                .map(|v| {
                    let [i, j, k] = unflatten(v, layout.dims);
                    medium.extinction(density.sample(layout.centre(i, j, k))) * h
                })
                .collect()
        };
        let depth = DenseGrid {
            dims: layout.dims,
            voxel_size: h,
            origin: layout.origin,
            data,
        };
        VoxelSmoke {
            depth: Arc::new(depth),
            centroids: Vec::new(),
        }
    }

    /// `τ` of the voxel whose cell holds `p` (a light's position: its voxel's centre); 0
    /// outside the grid.
    #[inline]
    #[must_use]
    pub fn at(&self, p: Vec3) -> f32 {
        self.voxel_of(p).map_or(0.0, |v| self.depth.data[v])
    }

    /// The linear index of the voxel whose cell holds `p`; `None` outside the grid.
    #[inline]
    fn voxel_of(&self, p: Vec3) -> Option<usize> {
        let g = &self.depth;
        let u = ((p - g.origin) / g.voxel_size).round();
        let [nx, ny, nz] = g.dims;
        let inside =
            u.cmpge(Vec3::ZERO).all() && u.cmplt(Vec3::new(nx as f32, ny as f32, nz as f32)).all();
        inside.then(|| g.index(u.x as usize, u.y as usize, u.z as usize))
    }

    /// The same smoke, with the near field of each voxel light in `centroids` — the voxel's
    /// linear index and its emission centroid's offset from its centre, in world units
    /// ([`Volume::cell_centroid`](crate::Volume::cell_centroid) times the voxel size) —
    /// centred there (`crate::voxel_light`, "The near field's centre"), replacing any given
    /// before. Voxels not listed are centred on themselves; of a voxel listed twice, the
    /// first offset counts.
    ///
    /// ```
    /// use lgh_volume::grid::DenseGrid;
    /// use lgh_volume::voxel_smoke::VoxelSmoke;
    /// use lgh_volume::Medium;
    /// use lgh_volume::lgh_core::glam::Vec3;
    ///
    /// let density = DenseGrid::zeros([4, 4, 4], 0.5, Vec3::ZERO);
    /// let smoke = VoxelSmoke::of(&density, &density, &Medium::new(1.0, 3.0, 1e-4, 1000.0)?);
    /// let offset = Vec3::new(0.1, 0.0, -0.05);
    /// let smoke = smoke.with_centroids([(density.index(1, 2, 3), offset)]);
    /// assert_eq!(smoke.centroid_at(density.centre(1, 2, 3)), offset);
    /// assert_eq!(smoke.centroid_at(density.centre(0, 0, 0)), Vec3::ZERO);
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn with_centroids(mut self, centroids: impl IntoIterator<Item = (usize, Vec3)>) -> Self {
        let mut centroids: Vec<(usize, Vec3)> = centroids.into_iter().collect();
        centroids.sort_by_key(|&(v, _)| v);
        centroids.dedup_by_key(|&mut (v, _)| v);
        self.centroids = centroids;
        self
    }

    /// The same smoke with every voxel light's near field centred on its voxel: the lights of
    /// scattered light, whose sources are not the emission.
    ///
    /// ```
    /// use lgh_volume::{procedural, ExplosionLights, Medium};
    /// use lgh_volume::lgh_core::glam::Vec3;
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let lights = ExplosionLights::new(&[&volume], &Medium::new(2.0, 6.0, 1e-4, 1000.0)?)?;
    /// let smoke = lights.smoke().unwrap();
    /// let t = &volume.temperature;
    /// let flank = t.centre(20, 16, 16); // the hot core's flank: its cell emits off-centre
    /// assert_ne!(smoke.centroid_at(flank), Vec3::ZERO);
    /// assert_eq!(smoke.without_centroids().centroid_at(flank), Vec3::ZERO);
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn without_centroids(&self) -> Self {
        VoxelSmoke {
            depth: Arc::clone(&self.depth),
            centroids: Vec::new(),
        }
    }

    /// The emission centroid's offset from voxel `idx`'s centre (linear index, world units),
    /// if one was given ([`with_centroids`](Self::with_centroids)).
    ///
    /// ```
    /// use lgh_volume::grid::DenseGrid;
    /// use lgh_volume::voxel_smoke::VoxelSmoke;
    /// use lgh_volume::Medium;
    /// use lgh_volume::lgh_core::glam::Vec3;
    ///
    /// let density = DenseGrid::zeros([4, 4, 4], 0.5, Vec3::ZERO);
    /// let smoke = VoxelSmoke::of(&density, &density, &Medium::new(1.0, 3.0, 1e-4, 1000.0)?)
    ///     .with_centroids([(7, Vec3::X * 0.1)]);
    /// assert_eq!(smoke.centroid_of_voxel(7), Some(Vec3::X * 0.1));
    /// assert_eq!(smoke.centroid_of_voxel(8), None);
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn centroid_of_voxel(&self, idx: usize) -> Option<Vec3> {
        self.centroids
            .binary_search_by_key(&idx, |&(v, _)| v)
            .ok()
            .map(|k| self.centroids[k].1)
    }

    /// The emission centroid's offset from the centre of the voxel whose cell holds `p` (world
    /// units): where that voxel light's near field is centred, less its position; zero where
    /// none was given and outside the grid (example at
    /// [`with_centroids`](Self::with_centroids)).
    #[must_use]
    pub fn centroid_at(&self, p: Vec3) -> Vec3 {
        self.voxel_of(p)
            .and_then(|v| self.centroid_of_voxel(v))
            .unwrap_or(Vec3::ZERO)
    }

    /// `τ` of the voxel of each of `positions`, in their order ([`at`](Self::at)): the smoke of
    /// a backend's level-0 lights listed by their index, read per light as one load
    /// ([`LightSmoke`]).
    ///
    /// ```
    /// use lgh_volume::grid::DenseGrid;
    /// use lgh_volume::voxel_smoke::VoxelSmoke;
    /// use lgh_volume::Medium;
    /// use lgh_volume::lgh_core::glam::Vec3;
    ///
    /// let mut density = DenseGrid::zeros([4, 4, 4], 0.5, Vec3::ZERO);
    /// let at = density.index(1, 2, 3);
    /// density.data[at] = 2.0;
    /// let smoke = VoxelSmoke::of(&density, &density, &Medium::new(1.0, 3.0, 1e-4, 1000.0)?);
    /// let lights = smoke.of_lights([density.centre(0, 0, 0), density.centre(1, 2, 3)]);
    /// assert_eq!((lights.of_light(0), lights.of_light(1)), (0.0, 4.0));
    /// assert_eq!(lights.of_light(2), 0.0); // no such light: clear air
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn of_lights(&self, positions: impl IntoIterator<Item = Vec3>) -> LightSmoke {
        if self.centroids.is_empty() {
            // Every light centred on itself: none listed (a light beyond the list is).
            return LightSmoke {
                depth: positions.into_iter().map(|p| self.at(p)).collect(),
                centroid: Arc::new([]),
            };
        }
        let (depth, centroid): (Vec<f32>, Vec<Vec3>) = positions
            .into_iter()
            .map(|p| {
                let v = self.voxel_of(p);
                let centroid = v.and_then(|v| self.centroid_of_voxel(v));
                (
                    v.map_or(0.0, |v| self.depth.data[v]),
                    centroid.unwrap_or(Vec3::ZERO),
                )
            })
            .unzip();
        LightSmoke {
            depth: depth.into(),
            centroid: centroid.into(),
        }
    }
}

/// `τ` of each level-0 light's own voxel and its emission centroid, listed by the light's index in its backend
/// ([`LightSample::index`](lgh_core::LightSample::index)): what `Lights` reads for every voxel
/// light it shades. Each backend numbers its lights its own way (the hierarchy in its order,
/// brute force and Lightcuts in their input's, the light octree in its nodes'): list the
/// positions of the backend the lights are shaded with, in its order ([`VoxelSmoke::of_lights`]);
/// an index beyond the list reads clear air. A light's smoke beside its index costs one load from an array in the
/// backend's order (the hierarchy's lights of a cell lie together), where a lookup in the
/// frame's grid by the light's position missed the cache on every light: on the dev fire it
/// was a quarter of the frame (docs/cycles.md, "Real simulation caches").
#[derive(Clone, Debug, PartialEq)]
pub struct LightSmoke {
    depth: Arc<[f32]>,
    /// Each light's emission centroid, from its position (world units).
    centroid: Arc<[Vec3]>,
}

impl LightSmoke {
    /// `τ` of the voxel of light `index` (0, clear air, for an index beyond the list).
    #[inline]
    #[must_use]
    pub fn of_light(&self, index: u32) -> f32 {
        self.depth.get(index as usize).copied().unwrap_or(0.0)
    }

    /// The emission centroid of light `index`'s cell, from its position, where its near field
    /// is centred (zero, its position, beyond the list).
    ///
    /// ```
    /// use lgh_volume::grid::DenseGrid;
    /// use lgh_volume::voxel_smoke::VoxelSmoke;
    /// use lgh_volume::Medium;
    /// use lgh_volume::lgh_core::glam::Vec3;
    ///
    /// let density = DenseGrid::zeros([4, 4, 4], 0.5, Vec3::ZERO);
    /// let smoke = VoxelSmoke::of(&density, &density, &Medium::new(1.0, 3.0, 1e-4, 1000.0)?)
    ///     .with_centroids([(density.index(1, 2, 3), Vec3::Y * 0.1)]);
    /// let lights = smoke.of_lights([density.centre(0, 0, 0), density.centre(1, 2, 3)]);
    /// assert_eq!(lights.centroid_of(0), Vec3::ZERO);
    /// assert_eq!(lights.centroid_of(1), Vec3::Y * 0.1);
    /// assert_eq!(lights.centroid_of(2), Vec3::ZERO); // no such light
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[inline]
    #[must_use]
    pub fn centroid_of(&self, index: u32) -> Vec3 {
        self.centroid
            .get(index as usize)
            .copied()
            .unwrap_or(Vec3::ZERO)
    }
}
