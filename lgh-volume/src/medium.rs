//! The participating medium and one frame of it (paper Secs. 3, 6.1): smoke density and
//! temperature ([`Volume`]), and how they absorb, scatter and emit ([`Medium`]): see
//! ARCHITECTURE.md, "lgh-volume".

use std::sync::{Arc, OnceLock};

use lgh_core::glam::Vec3;
use lgh_core::spectrum::BlackbodyTable;

use crate::error::{check_setting, RenderError};
use crate::grid::DenseGrid;

/// Smoke density and temperature of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Volume {
    /// Smoke density ρ (dimensionless, 0..1 in the procedural explosion).
    pub density: DenseGrid,
    /// Temperature, in kelvin times [`Medium::temperature_scale`].
    pub temperature: DenseGrid,
    /// A factor on the emission (Blender's `flame` grid, 0..1), on the temperature's grid; `None`
    /// is 1 everywhere.
    pub flame: Option<DenseGrid>,
    /// An RGB emission read as it is, in place of the blackbody (a vec3 `emission` grid, as
    /// Houdini writes and Cycles reads through Principled Volume's Emission Color), on the
    /// temperature's grid: `j = k_e · (r, g, b)` ([`Medium::colour_emission`]), `k_e` Cycles'
    /// Emission Strength. With it, [`temperature`](Self::temperature) holds each voxel's
    /// largest channel (what frames the camera and bounds the path tracer), and the flame
    /// factor, which scales the blackbody, is not applied. Made by
    /// [`with_colour`](Self::with_colour).
    pub colour: Option<Box<[DenseGrid; 3]>>,
}

impl Volume {
    /// A frame of density and temperature, without a flame factor.
    #[must_use]
    pub fn new(density: DenseGrid, temperature: DenseGrid) -> Self {
        Volume {
            density,
            temperature,
            flame: None,
            colour: None,
        }
    }

    /// A frame whose emission is the RGB grids `colour` as they are ([`Volume::colour`]), all
    /// three on one layout (else [`RenderError::ColourOffGrid`]); the temperature grid becomes
    /// each voxel's largest channel.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::{DenseGrid, Medium, Volume};
    ///
    /// let mut red = DenseGrid::zeros([2, 2, 2], 0.5, Vec3::ZERO);
    /// red.data[0] = 3.0;
    /// let dark = DenseGrid::zeros([2, 2, 2], 0.5, Vec3::ZERO);
    /// let volume = Volume::with_colour(dark.clone(), [red, dark.clone(), dark.clone()])?;
    /// let medium = Medium::new(1.0, 1.0, 2.0, 1000.0)?; // k_e = 2; no temperature cut applies
    /// assert_eq!(volume.voxel_emission(&medium, 0), Vec3::new(6.0, 0.0, 0.0));
    /// assert_eq!(volume.temperature.data[0], 3.0);
    /// assert!(!volume.voxel_emits(&medium, 1));
    /// let coarse = DenseGrid::zeros([1, 1, 1], 1.0, Vec3::ZERO);
    /// assert!(Volume::with_colour(dark.clone(), [coarse, dark.clone(), dark]).is_err());
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn with_colour(density: DenseGrid, colour: [DenseGrid; 3]) -> Result<Self, RenderError> {
        let [r, g, b] = &colour;
        if !(r.same_layout(g) && r.same_layout(b)) {
            return Err(RenderError::ColourOffGrid { frame: None });
        }
        Ok(Volume::coloured(density, colour))
    }

    /// [`with_colour`](Self::with_colour) for channels known to share one layout.
    pub(crate) fn coloured(density: DenseGrid, colour: [DenseGrid; 3]) -> Self {
        let [r, g, b] = &colour;
        let mut largest = r.clone();
        for ((l, &g), &b) in largest.data.iter_mut().zip(&g.data).zip(&b.data) {
            *l = l.max(g).max(b);
        }
        Volume {
            density,
            temperature: largest,
            flame: None,
            colour: Some(Box::new(colour)),
        }
    }

    /// Emission `j(x)` at world position `x` (trilinear temperature and flame, or colour).
    #[must_use]
    pub fn emission(&self, medium: &Medium, x: Vec3) -> Vec3 {
        if let Some([r, g, b]) = self.colour.as_deref() {
            return medium.colour_emission(Vec3::new(r.sample(x), g.sample(x), b.sample(x)));
        }
        let j = match medium.interpolation {
            EmissionInterpolation::Temperature => medium.emission_at(self.temperature.sample(x)),
            EmissionInterpolation::Attributes => {
                self.temperature.corners(x).map_or(Vec3::ZERO, |(idx, w)| {
                    let data = &self.temperature.data;
                    (0..8).fold(Vec3::ZERO, |a, c| {
                        a + medium.emission_at(data[idx[c]]) * w[c]
                    })
                })
            }
        };
        match &self.flame {
            Some(f) if j != Vec3::ZERO => j * f.sample(x).max(0.0),
            _ => j,
        }
    }

    /// Emission of voxel `idx` of the temperature grid (at its centre).
    #[must_use]
    pub fn voxel_emission(&self, medium: &Medium, idx: usize) -> Vec3 {
        if let Some([r, g, b]) = self.colour.as_deref() {
            return medium.colour_emission(Vec3::new(r.data[idx], g.data[idx], b.data[idx]));
        }
        let j = medium.emission_at(self.temperature.data[idx]);
        match &self.flame {
            Some(f) => j * f.data[idx].max(0.0),
            None => j,
        }
    }

    /// Whether a value of the [`temperature`](Self::temperature) grid emits under `medium`:
    /// hotter than `T_min` ([`Medium::emits`]), or with a [`colour`](Self::colour), a largest
    /// channel above 0 and `k_e > 0`.
    #[must_use]
    pub fn value_emits(&self, medium: &Medium, value: f32) -> bool {
        match self.colour {
            Some(_) => value > 0.0 && medium.emission > 0.0,
            None => medium.emission_at(value) != Vec3::ZERO,
        }
    }

    /// How many voxels emit at their centres ([`voxel_emits`](Self::voxel_emits)): the paper's
    /// lights `S0` of this frame (lgh's voxel lights stand at every emitting cell too,
    /// [`emitting_cells`](Self::emitting_cells)).
    #[must_use]
    pub fn emitting_voxels(&self, medium: &Medium) -> usize {
        (0..self.temperature.data.len())
            .filter(|&i| self.voxel_emits(medium, i))
            .count()
    }

    /// Whether voxel `idx` emits at its centre: its [`voxel_emission`](Self::voxel_emission) is
    /// not zero (the paper's lights; see [`emitting_cells`](Self::emitting_cells) for lgh's).
    #[must_use]
    pub fn voxel_emits(&self, medium: &Medium, idx: usize) -> bool {
        self.voxel_emission(medium, idx).max_element() > 0.0
    }

    /// World box of the voxels with smoke or emission: what a camera should frame.
    #[must_use]
    pub fn active_bounds(&self) -> Option<(Vec3, Vec3)> {
        union(
            self.density.active_bounds(),
            self.temperature.active_bounds(),
        )
    }
}

/// The smallest box holding both (either may be absent).
fn union(a: Option<(Vec3, Vec3)>, b: Option<(Vec3, Vec3)>) -> Option<(Vec3, Vec3)> {
    match (a, b) {
        (Some(a), Some(b)) => Some((a.0.min(b.0), a.1.max(b.1))),
        (a, b) => a.or(b),
    }
}

/// `acc` grown by `frame`'s [`active_bounds`](Volume::active_bounds): [`framing_bounds`] one
/// frame at a time.
#[must_use]
pub fn grow_framing(acc: Option<(Vec3, Vec3)>, frame: &Volume) -> Option<(Vec3, Vec3)> {
    union(acc, frame.active_bounds())
}

/// What a camera should frame for a sequence: the union of the frames'
/// [`active_bounds`](Volume::active_bounds), or the first frame's whole grid when no frame has
/// smoke or emission (`None` for no frames).
#[must_use]
pub fn framing_bounds(frames: &[&Volume]) -> Option<(Vec3, Vec3)> {
    let active = frames.iter().fold(None, |acc, v| grow_framing(acc, v));
    active.or_else(|| frames.first().map(|v| v.density.bounds()))
}

/// How emission follows temperature.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum EmissionModel {
    /// `j = k_e · B(T)`: Planck's radiance through CIE 1931 to linear sRGB, in W / (sr m²)
    /// (luminance = CIE Y), times `k_e` (1 / length).
    #[default]
    Planck,
    /// Blender's Principled Volume: `j = k_e · 10⁻⁶ σ T⁴ / π · c(T)`, where `c(T)` is
    /// Cycles' blackbody colour as its volumes emit it (luminance about 1, a channel negative
    /// below about 1900 K; measured: [`crate::blender_blackbody`]) and `k_e` is Blender's blackbody intensity
    /// (times the flame grid, see [`Volume::flame`]). Blender mixes `1 → T⁴` by that intensity;
    /// the constant term (`10⁻⁶ σ / π ≈ 2·10⁻¹⁴`) is dropped.
    Blender,
}

/// How the emission between voxel centres follows the grids (Cycles changed it between 3.x and
/// 4.x; docs/cycles.md, "Against Cycles 5.2.3 LTS").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum EmissionInterpolation {
    /// The emission of the interpolated temperature, `j(T(x)) · flame(x)` (Cycles 3.x).
    #[default]
    Temperature,
    /// Each grid interpolated on its own: the trilinear interpolation of the voxels' emission
    /// `j(T_i)`, times the interpolated flame (Cycles 4.x and later, whose stochastic
    /// interpolation averages each attribute's voxel values). `j` is convex in `T`, so this is
    /// the brighter between voxels: on the dev fire's thin flames 6%.
    Attributes,
}

/// Stefan–Boltzmann constant σ in W / (m² K⁴).
const STEFAN_BOLTZMANN: f32 = 5.670_374e-8;

/// The largest emission [`Medium::emission_at`] returns, per channel: an `f32`'s largest value
/// over 8, so that the colour (channels up to 4.7 times the luminance) times it stays finite.
/// A render that sums such values overflows anyway, and the image writers refuse it.
pub const MAX_EMISSION: f32 = f32::MAX / 8.0;

/// `v` with every channel above [`MAX_EMISSION`] (∞ included) set to it. Not `Vec3::min`, which
/// would turn a NaN into `MAX_EMISSION` too and hide a bug the tests must see.
fn saturate(v: Vec3) -> Vec3 {
    let max = Vec3::splat(MAX_EMISSION);
    Vec3::select(v.cmpgt(max), max, v)
}

/// The participating medium (ARCHITECTURE.md, "Medium"): `σ_a = κ_a ρ`, `σ_s = κ_s ρ`, isotropic phase
/// function, and emission `j = k_e · blackbody(T)` (W / (m³ sr), linear sRGB) where `T > T_min`,
/// with `T` = temperature scale × the temperature grid's value.
#[derive(Clone, Debug, PartialEq)]
pub struct Medium {
    /// κ_a: absorption per unit density (1 / world unit).
    pub absorption: f32,
    /// κ_s: scattering per unit density (1 / world unit).
    pub scattering: f32,
    /// k_e: scale of the blackbody emission (1 / world unit).
    pub emission: f32,
    /// T_min: no emission at or below this temperature (kelvin).
    pub min_temperature: f32,
    /// Kelvin per unit of the temperature grid (1 for grids in kelvin; Blender's default
    /// Principled Volume temperature is 1000 K per unit of its `temperature` grid).
    pub temperature_scale: f32,
    /// How emission follows temperature.
    pub model: EmissionModel,
    /// How the emission between voxel centres follows the grids.
    pub interpolation: EmissionInterpolation,
    /// The process's one table ([`blackbody_table`]), shared by every medium.
    table: Arc<BlackbodyTable>,
}

/// The blackbody table of every medium, 500 K to 12,000 K by 1 K: built once per process and
/// shared — about 11,500 integrals of Planck's law against the CIE functions, 86 ms on one core
/// of this machine (`cargo bench -p lgh-core --bench core -- blackbody`; 417 ms when each entry
/// computed the functions again): a viewport preview or a Python session pays it once, not for
/// every medium. It depends on no setting, so sharing it changes no value.
fn blackbody_table() -> Arc<BlackbodyTable> {
    static TABLE: OnceLock<Arc<BlackbodyTable>> = OnceLock::new();
    let table = TABLE
        .get_or_init(|| Arc::new(BlackbodyTable::new(500.0, 12_000.0, 1.0).expect("valid range")));
    Arc::clone(table)
}

impl Medium {
    /// A medium; errors on negative or non-finite coefficients.
    pub fn new(
        absorption: f32,
        scattering: f32,
        emission: f32,
        min_temperature: f32,
    ) -> Result<Self, RenderError> {
        for (name, v) in [
            ("absorption", absorption),
            ("scattering", scattering),
            ("emission", emission),
            ("minimum temperature", min_temperature),
        ] {
            check_setting(v.is_finite() && v >= 0.0, name, v, "must be finite and ≥ 0")?;
        }
        Ok(Medium {
            absorption,
            scattering,
            emission,
            min_temperature,
            temperature_scale: 1.0,
            model: EmissionModel::Planck,
            interpolation: EmissionInterpolation::Temperature,
            table: blackbody_table(),
        })
    }

    /// The same medium with temperature in other units: `T = scale × value` (finite, > 0).
    pub fn with_temperature_scale(mut self, scale: f32) -> Result<Self, RenderError> {
        self.temperature_scale = check_setting(
            scale.is_finite() && scale > 0.0,
            "temperature scale",
            scale,
            "must be finite and > 0",
        )?;
        Ok(self)
    }

    /// The same medium with another emission model.
    #[must_use]
    pub fn with_model(mut self, model: EmissionModel) -> Self {
        self.model = model;
        self
    }

    /// The same medium with the emission between voxels interpolated as `interpolation` says.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::medium::EmissionInterpolation;
    /// use lgh_volume::{DenseGrid, Medium, Volume};
    ///
    /// // Two voxels at 1000 K and 3000 K; halfway between them:
    /// let mut t = DenseGrid::zeros([2, 1, 1], 1.0, Vec3::ZERO);
    /// t.data = vec![1000.0, 3000.0];
    /// let volume = Volume::new(t.clone(), t);
    /// let medium = Medium::new(1.0, 1.0, 1.0, 0.0)?;
    /// let mid = Vec3::new(0.5, 0.0, 0.0);
    /// let of_t = volume.emission(&medium, mid); // j(2000 K)
    /// let attributes = medium.clone().with_interpolation(EmissionInterpolation::Attributes);
    /// let of_j = volume.emission(&attributes, mid); // (j(1000 K) + j(3000 K)) / 2
    /// let want = (medium.emission_at(1000.0) + medium.emission_at(3000.0)) / 2.0;
    /// assert!((of_j - want).abs().max_element() <= 1e-6 * want.max_element());
    /// assert!(of_j.y > 2.0 * of_t.y); // j is convex in T
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn with_interpolation(mut self, interpolation: EmissionInterpolation) -> Self {
        self.interpolation = interpolation;
        self
    }

    /// Whether a voxel whose temperature grid holds `value` emits (`T` finite, hotter than
    /// `T_min` and than 0 K).
    #[must_use]
    pub fn emits(&self, value: f32) -> bool {
        let kelvin = value * self.temperature_scale;
        kelvin > self.min_temperature && kelvin > 0.0 && kelvin.is_finite()
    }

    /// Emission `j(T)` for the temperature grid's `value`, in W / (m³ sr) (zero at or below
    /// `T_min`): finite with a non-negative luminance for every `value` (a property test over
    /// the whole `f32` range, below); what does not fit an `f32` is held at [`MAX_EMISSION`].
    /// Blender's model keeps its blackbody's negative channels below about 1900 K, as Cycles'
    /// volumes do ([`crate::blender_blackbody`]).
    #[must_use]
    pub fn emission_at(&self, value: f32) -> Vec3 {
        if !self.emits(value) || self.emission == 0.0 {
            return Vec3::ZERO;
        }
        let kelvin = value * self.temperature_scale;
        match self.model {
            EmissionModel::Planck => {
                saturate(saturate(self.table.radiance(kelvin)) * self.emission)
            }
            EmissionModel::Blender => {
                // c(T), Cycles' blackbody colour as measured (held below 800 K and above
                // 40000 K, as Cycles holds it below 800 K).
                let c = crate::blender_blackbody::colour(kelvin);
                // k_e 10⁻⁶ σ T⁴ / π in f64: T⁴ overflows an f32 above 1.4·10⁹ K.
                let t2 = f64::from(kelvin).powi(2);
                let total = f64::from(self.emission) * 1e-6 * f64::from(STEFAN_BOLTZMANN)
                    / core::f64::consts::PI
                    * t2
                    * t2;
                c * total.min(f64::from(MAX_EMISSION)) as f32
            }
        }
    }

    /// Emission `j = k_e · rgb` of an RGB emission ([`Volume::colour`]): negative and NaN
    /// channels are 0, what does not fit an `f32` is held at [`MAX_EMISSION`]; no temperature
    /// cut and no emission model apply.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::Medium;
    ///
    /// let medium = Medium::new(1.0, 1.0, 0.5, 800.0)?;
    /// let j = medium.colour_emission(Vec3::new(2.0, -1.0, f32::NAN));
    /// assert_eq!(j, Vec3::new(1.0, 0.0, 0.0));
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn colour_emission(&self, rgb: Vec3) -> Vec3 {
        let positive = Vec3::from_array(rgb.to_array().map(|c| if c > 0.0 { c } else { 0.0 }));
        saturate(saturate(positive) * self.emission)
    }

    /// Extinction `σ_t = (κ_a + κ_s) ρ`.
    #[must_use]
    pub fn extinction(&self, density: f32) -> f32 {
        (self.absorption + self.scattering) * density
    }

    /// The single-scattering albedo `κ_s/(κ_a + κ_s)`: the share of the light a voxel takes
    /// out of a beam that it sends on (0 for a medium that takes none). It bounds how much of
    /// a scattering depth's power the next can hold: of the light that leaves depth `k`, at
    /// most all is extinct in the smoke, and this share of it scatters (paper Sec. 5's
    /// `I^k = h³ σ_s/(4π) · Φ^{k−1}`, `Φ` the fluence the extinct light came from).
    ///
    /// ```
    /// use lgh_volume::Medium;
    ///
    /// assert_eq!(Medium::new(1.0, 3.0, 1e-4, 1000.0)?.albedo(), 0.75);
    /// assert_eq!(Medium::new(0.0, 0.0, 1e-4, 1000.0)?.albedo(), 0.0);
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn albedo(&self) -> f32 {
        let extinction = self.absorption + self.scattering;
        if extinction > 0.0 {
            self.scattering / extinction
        } else {
            0.0
        }
    }

    /// A voxel's scattering cross-section `h³ σ_s = h³ κ_s ρ` (`h` its side): the factor of
    /// paper Sec. 5's `I^k = h³ σ_s/(4π) · Φ^{k−1}` that makes a voxel's fluence the
    /// intensity of its light of scattered light (before the isotropic phase function's 1/4π).
    ///
    /// ```
    /// use lgh_volume::Medium;
    ///
    /// let medium = Medium::new(1.0, 3.0, 1e-4, 1000.0)?;
    /// assert_eq!(medium.voxel_scattering(0.5, 0.25), 0.25f32.powi(3) * 3.0 * 0.5);
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn voxel_scattering(&self, density: f32, voxel_size: f32) -> f32 {
        voxel_size.powi(3) * self.scattering * density
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use proptest::prelude::*;

    #[test]
    fn bad_media_are_errors() {
        assert!(Medium::new(-1.0, 0.0, 0.0, 0.0).is_err());
    }

    #[test]
    fn every_medium_shares_the_one_blackbody_table() {
        let a = Medium::new(1.0, 1.0, 1.0, 0.0).unwrap();
        let b = Medium::new(0.5, 2.0, 3.0, 800.0).unwrap();
        assert!(Arc::ptr_eq(&a.table, &b.table));
        // The table every medium shares is the one its constructor made before.
        let fresh = BlackbodyTable::new(500.0, 12_000.0, 1.0).unwrap();
        assert_eq!(*a.table, fresh);
    }

    /// A medium with `k_e = emission`, sharing one blackbody table (building it is slow).
    fn medium(model: EmissionModel, emission: f32, min_temperature: f32) -> Medium {
        static BASE: std::sync::OnceLock<Medium> = std::sync::OnceLock::new();
        let mut m = BASE
            .get_or_init(|| Medium::new(1.0, 1.0, 1.0, 0.0).unwrap())
            .clone()
            .with_model(model);
        (m.emission, m.min_temperature) = (emission, min_temperature);
        m
    }

    /// The cold voxels of the issue-16 report: `--min-temperature 100` with the Blender model
    /// wrote NaN pixels (a colour normalised by a luminance that underflows). Now a cold voxel
    /// emits a tiny amount of 800 K's colour (red, less a little green and blue, as Cycles),
    /// continuous with the hotter voxels' colour.
    #[test]
    fn cold_voxels_emit_a_little_finite_red() {
        let m = medium(EmissionModel::Blender, 1.0, 0.0);
        let red = crate::blender_blackbody::colour(800.0);
        for kelvin in [0.01, 1.0, 50.0, 100.0, 149.0, 300.0, 599.0] {
            let j = m.emission_at(kelvin);
            assert!(j.is_finite() && j.x > 0.0, "{kelvin} K: {j}");
            let ratio = j / j.x;
            assert!(
                (ratio - red / red.x).abs().max_element() < 1e-6,
                "{kelvin} K: {j}"
            );
        }
        // Continuous across the held colour's edge (800 K, as Blender's node), and T⁴ below it.
        let (a, b) = (m.emission_at(799.999), m.emission_at(800.001));
        assert!(
            (a - b).abs().max_element() <= 1e-4 * b.max_element(),
            "{a} {b}"
        );
        let (c, d) = (m.emission_at(100.0), m.emission_at(200.0));
        assert!((d.x / c.x - 16.0).abs() < 1e-4, "{c} {d}");
    }

    proptest! {
        /// No temperature an `f32` can hold, no emission scale the CLI accepts, no model: the
        /// emission is finite with a non-negative luminance (Planck's: every channel ≥ 0;
        /// Blender's may have a negative channel, as Cycles' volumes do), and zero at or below
        /// `T_min`.
        #[test]
        fn emission_is_finite_over_the_whole_temperature_range(
            bits in any::<u32>(),
            emission in prop_oneof![Just(0.0f32), 1e-12f32..1e12, Just(f32::MAX)],
            min_temperature in prop_oneof![Just(0.0f32), 0.0f32..5000.0],
            blender in any::<bool>(),
        ) {
            let value = f32::from_bits(bits);
            let model = if blender { EmissionModel::Blender } else { EmissionModel::Planck };
            let m = medium(model, emission, min_temperature);
            let j = m.emission_at(value);
            prop_assert!(physical(j, model), "{value} K: {j}");
            if value.partial_cmp(&min_temperature) != Some(std::cmp::Ordering::Greater) {
                prop_assert_eq!(j, Vec3::ZERO);
            }
        }

        /// The same over the temperatures of fires and colder, sampled densely on a log scale.
        #[test]
        fn emission_is_finite_from_0_to_100000_kelvin(
            log_kelvin in -40.0f32..5.0,
            blender in any::<bool>(),
        ) {
            let model = if blender { EmissionModel::Blender } else { EmissionModel::Planck };
            let j = medium(model, 1.0, 0.0).emission_at(10f32.powf(log_kelvin));
            prop_assert!(physical(j, model), "{j}");
        }
    }

    /// Finite, with a luminance ≥ 0; for Planck's model every channel ≥ 0, for Blender's no
    /// channel below −0.21 times the luminance (its blackbody's most negative: green at 800 K,
    /// −0.203) — both up to the smallest normal f32, as a cold voxel's emission is subnormal and
    /// rounds each channel on its own (10⁻⁷ K: red 2·10⁻⁴⁴, green −10⁻⁴⁵).
    fn physical(j: Vec3, model: EmissionModel) -> bool {
        let y = lgh_core::luminance(j);
        let least = match model {
            EmissionModel::Planck => 0.0,
            EmissionModel::Blender => -0.21 * y - f32::MIN_POSITIVE,
        };
        j.is_finite() && y >= -f32::MIN_POSITIVE && j.min_element() >= least
    }
}
