//! `lgh.Hierarchy`: the Lighting Grid Hierarchy (paper Sec. 3) over `(n, 3)` numpy arrays —
//! built by eqs. (1), (2), (4), (5), updated for new intensities or rebuilt for moved lights,
//! and queried by eq. (3)'s blended sum: `probe` is the unshadowed light-probe value
//! `L(x) = Σ B·I·g(d)` at many points (what `lgh_probe_batch` is in C and `lgh probes` on the
//! command line), `gather` the lights one point sees with their blending weights.

use lgh_core::glam::Vec3;
use lgh_core::{
    Blending, CoarseSpread, GridSettings, LghBackend, LightingGridHierarchy, PointLight,
};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

use crate::{arrays, errors, work};

/// The Lighting Grid Hierarchy (Yuksel & Yuksel 2017) over point lights.
///
/// ``positions`` and ``intensities`` are ``(n, 3)`` arrays (any array-like; converted to
/// float32 once): each light's position and RGB intensity (W/sr), every value finite, each
/// light's luminance ≥ 0 (a channel may be negative: Blender's blackbody below about 1900 K).
/// ``alpha`` is the blending's α of eq. (3) (the paper uses 2; larger is closer to the exact
/// sum and slower). ``h1`` (level 1's grid spacing), ``origin`` and ``max_level`` are derived
/// when not given (paper Sec. 6.4); ``prune_below`` skips lights dimmer than it (luminance) at
/// every level but the top. The property ``coarse_spread`` says how coarse lights are weighted:
/// ``"centre"`` (the default: eq. 3 at each light's centre, as the paper prints it) or
/// ``"averaged"`` (eq. 3's blended fall-off averaged over the spread of the lights each stands
/// for: closer to the exact sum, each level's support wider). The build releases the GIL.
///
/// >>> import numpy as np, lgh
/// >>> h = lgh.Hierarchy(np.zeros((1, 3)), np.ones((1, 3)))
/// >>> h.probe([[2.0, 0.0, 0.0]])   # one white light 2 away: 1/4
/// array([[0.25, 0.25, 0.25]], dtype=float32)
#[pyclass(module = "lgh")]
pub struct Hierarchy {
    lgh: LightingGridHierarchy,
    settings: GridSettings,
    alpha: f32,
    coarse_spread: CoarseSpread,
}

/// The [`CoarseSpread`] named `name`.
fn coarse_spread(name: &str) -> PyResult<CoarseSpread> {
    CoarseSpread::from_name(name).ok_or_else(|| {
        PyValueError::new_err(format!(
            "coarse_spread must be \"centre\" or \"averaged\", not {name:?}"
        ))
    })
}

/// The lights of two `(n, 3)` arrays, checked to be as many.
fn lights(
    positions: &Bound<'_, PyAny>,
    intensities: &Bound<'_, PyAny>,
) -> PyResult<Vec<PointLight>> {
    let p = arrays::rows(positions, "positions")?;
    let i = arrays::rows(intensities, "intensities")?;
    arrays::check_len(&i, p.shape()[0], "intensities", "positions has")?;
    let (p, i) = (p.readonly(), i.readonly());
    let lights = arrays::triples(p.as_slice()?)
        .iter()
        .zip(arrays::triples(i.as_slice()?))
        .map(|(&p, &i)| PointLight::new(Vec3::from(p), Vec3::from(i)))
        .collect();
    Ok(lights)
}

/// The hierarchy of `lights`, built with the GIL released.
fn build(
    py: Python<'_>,
    lights: &[PointLight],
    settings: &GridSettings,
) -> PyResult<LightingGridHierarchy> {
    py.detach(|| LightingGridHierarchy::build(lights, settings))
        .map_err(errors::build)
}

#[pymethods]
impl Hierarchy {
    #[new]
    #[pyo3(signature = (positions, intensities, *, alpha = 2.0, h1 = None, origin = None, max_level = None, prune_below = 0.0))]
    fn new(
        positions: &Bound<'_, PyAny>,
        intensities: &Bound<'_, PyAny>,
        alpha: f32,
        h1: Option<f32>,
        origin: Option<&Bound<'_, PyAny>>,
        max_level: Option<i64>,
        prune_below: f32,
    ) -> PyResult<Self> {
        lgh_core::check_alpha(alpha).map_err(errors::query)?;
        let max_level = max_level
            .map(|l| {
                u8::try_from(l).map_err(|_| {
                    PyValueError::new_err(format!(
                        "max_level {l} must be 0 to {}",
                        lgh_core::MAX_LEVEL
                    ))
                })
            })
            .transpose()?;
        let origin = origin
            .map(|o| arrays::point(o, "origin").map(Vec3::from))
            .transpose()?;
        let settings = GridSettings {
            h1,
            origin,
            max_level,
            prune_below,
            ..GridSettings::default()
        };
        let lights = lights(positions, intensities)?;
        let lgh = build(positions.py(), &lights, &settings)?;
        Ok(Hierarchy {
            lgh,
            settings,
            alpha,
            coarse_spread: CoarseSpread::Centre,
        })
    }

    /// The unshadowed light-probe value ``L(x) = Σ B·I·g(d)`` at each of ``points`` (an
    /// ``(n, 3)`` array), ``g(d) = 1 / max(d, h0)²``: an ``(n, 3)`` float32 array, the same bits
    /// on any number of threads. ``progress(done, total)``, if given, is called as the work
    /// goes; Ctrl-C stops it (``KeyboardInterrupt``). The GIL is released while it works.
    ///
    /// >>> import numpy as np, lgh
    /// >>> h = lgh.Hierarchy([[0, 0, 0], [1, 0, 0]], np.ones((2, 3)), alpha=2.0)
    /// >>> h.probe(np.array([[0.5, 0.0, 0.0]])).shape
    /// (1, 3)
    #[pyo3(signature = (points, *, progress = None))]
    fn probe<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        progress: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        // A copy: the caller's own array (already C-contiguous float32) could be written by
        // another Python thread while the GIL is released.
        let points = arrays::rows(points, "points")?;
        let points: Vec<[f32; 3]> = arrays::triples(points.readonly().as_slice()?).to_vec();
        let points = points.as_slice();
        let backend =
            LghBackend::with_blending(&self.lgh, self.blending()?).map_err(errors::query)?;
        let h0 = self.lgh.h0();
        let out = arrays::zeros(py, points.len());
        {
            let mut rw = out.readwrite();
            let slice = rw.as_slice_mut()?;
            let rows = slice.as_chunks_mut::<3>().0;
            work::chunked(py, points, rows, progress, |offset, points, rows| {
                rows.par_iter_mut()
                    .zip(points)
                    .enumerate()
                    .try_for_each(|(k, (row, &p))| {
                        let l = lgh_core::probe(&backend, Vec3::from(p), h0).map_err(|e| {
                            PyValueError::new_err(format!("point {}: {e}", offset + k))
                        })?;
                        *row = l.radiance.to_array();
                        Ok(())
                    })
            })?;
        }
        Ok(out)
    }

    /// The lights ``point`` sees (three numbers) at every level, as a dict of arrays, one row a
    /// light: ``position`` (k, 3: an input light's or a grid light's illumination centre),
    /// ``intensity`` (k, 3: the blending weight applied, ``B_ℓ(d) I``), ``weight`` (``B_ℓ(d)``),
    /// ``distance``, ``level``, ``index`` (in its level), ``size`` and ``variance`` (k, 3: the
    /// spread of the lights a grid light stands for).
    ///
    /// >>> import numpy as np, lgh
    /// >>> h = lgh.Hierarchy([[0, 0, 0], [1, 0, 0]], np.ones((2, 3)))
    /// >>> g = h.gather([0.5, 0.0, 0.0])
    /// >>> g["level"].tolist(), g["distance"].tolist()
    /// ([0, 0], [0.5, 0.5])
    fn gather<'py>(
        &self,
        py: Python<'py>,
        point: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let x = Vec3::from(arrays::point(point, "point")?);
        let blending = self.blending()?;
        let mut seen = Vec::new();
        self.lgh
            .query(x, &blending, |s| seen.push(*s))
            .map_err(errors::query)?;
        let rows =
            |f: &dyn Fn(&lgh_core::LightSample) -> Vec3| -> PyResult<Bound<'py, PyArray2<f32>>> {
                let flat: Vec<f32> = seen.iter().flat_map(|s| f(s).to_array()).collect();
                PyArray1::from_vec(py, flat).reshape([seen.len(), 3])
            };
        let d = PyDict::new(py);
        d.set_item("position", rows(&|s| s.position)?)?;
        d.set_item("intensity", rows(&|s| s.intensity)?)?;
        d.set_item("variance", rows(&|s| s.variance)?)?;
        let column = |f: &dyn Fn(&lgh_core::LightSample) -> f32| {
            PyArray1::from_vec(py, seen.iter().map(f).collect())
        };
        d.set_item("weight", column(&|s| s.weight))?;
        d.set_item("distance", column(&|s| s.distance))?;
        d.set_item("size", column(&|s| s.size))?;
        d.set_item(
            "level",
            PyArray1::from_vec(py, seen.iter().map(|s| s.level).collect()),
        )?;
        d.set_item(
            "index",
            PyArray1::from_vec(py, seen.iter().map(|s| s.index).collect()),
        )?;
        Ok(d)
    }

    /// New intensities (an ``(n, 3)`` array, as many as the lights, in the order given) at the
    /// same positions: the animated fire's per-frame path, without redoing the topology. The
    /// result is the same as a fresh build's. The GIL is released.
    fn update_intensities(
        &mut self,
        py: Python<'_>,
        intensities: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let i = arrays::rows(intensities, "intensities")?;
        arrays::check_len(
            &i,
            self.lgh.len(),
            "intensities",
            "the hierarchy has lights:",
        )?;
        let i = i.readonly();
        let values: Vec<Vec3> = arrays::triples(i.as_slice()?)
            .iter()
            .map(|&v| Vec3::from(v))
            .collect();
        let lgh = &mut self.lgh;
        py.detach(|| lgh.update_intensities(&values))
            .map_err(errors::build)
    }

    /// Rebuilds over new lights (any count) with the settings the hierarchy was made with: for
    /// lights that move. On an error the hierarchy is unchanged. The GIL is released.
    fn rebuild(
        &mut self,
        py: Python<'_>,
        positions: &Bound<'_, PyAny>,
        intensities: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let lights = lights(positions, intensities)?;
        self.lgh = build(py, &lights, &self.settings)?;
        Ok(())
    }

    /// The blending's α of eq. (3); setting it checks it (finite, > 0).
    #[getter]
    fn alpha(&self) -> f32 {
        self.alpha
    }

    #[setter]
    fn set_alpha(&mut self, alpha: f32) -> PyResult<()> {
        lgh_core::check_alpha(alpha).map_err(errors::query)?;
        self.alpha = alpha;
        Ok(())
    }

    /// How coarse lights are weighted, ``"centre"`` or ``"averaged"`` (see the class).
    ///
    /// >>> import numpy as np, lgh
    /// >>> h = lgh.Hierarchy(np.zeros((1, 3)), np.ones((1, 3)))
    /// >>> h.coarse_spread = "averaged"
    /// >>> h.coarse_spread
    /// 'averaged'
    #[getter(coarse_spread)]
    fn get_coarse_spread(&self) -> &'static str {
        self.coarse_spread.name()
    }

    #[setter(coarse_spread)]
    fn set_coarse_spread(&mut self, name: &str) -> PyResult<()> {
        self.coarse_spread = coarse_spread(name)?;
        Ok(())
    }

    /// Level 1's grid spacing ``h1``.
    #[getter]
    fn h1(&self) -> f32 {
        self.lgh.h1()
    }

    /// ``h0 = h1 / 2``, where ``probe`` clamps the fall-off.
    #[getter]
    fn h0(&self) -> f32 {
        self.lgh.h0()
    }

    /// The top level ``ℓ_max``.
    #[getter]
    fn max_level(&self) -> u8 {
        self.lgh.max_level()
    }

    /// The grids' origin (a vertex of every level), as ``(x, y, z)``.
    #[getter]
    fn origin(&self) -> (f32, f32, f32) {
        self.lgh.origin().into()
    }

    /// The input lights' count.
    fn __len__(&self) -> usize {
        self.lgh.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "lgh.Hierarchy({} lights, alpha={}, coarse_spread='{}', h1={}, max_level={})",
            self.lgh.len(),
            self.alpha,
            self.coarse_spread.name(),
            self.lgh.h1(),
            self.lgh.max_level()
        )
    }
}

impl Hierarchy {
    /// The blending `probe` and `gather` use: α and the coarse lights' weighting, for the
    /// lights as they are now (the spreads follow `update_intensities`).
    fn blending(&self) -> PyResult<Blending> {
        self.lgh
            .blending_with(self.alpha, self.coarse_spread)
            .map_err(errors::query)
    }
}
