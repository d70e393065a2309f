//! A C ABI over `lgh-core`: the Lighting Grid Hierarchy (Yuksel & Yuksel 2017) for engines that
//! speak C — Unreal, Godot and Unity native plugins, in-house C++ engines.
//!
//! The header `include/lgh.h` is generated from this file by cbindgen and committed; the test
//! `tests/header.rs` regenerates it and fails when the committed one is stale. The API, in the
//! order an engine calls it:
//!
//! 1. [`lgh_settings_default`] fills an [`LghSettings`] (its `struct_size` and `version` say which
//!    layout the caller was compiled with);
//! 2. [`lgh_hierarchy_create`] builds a hierarchy from arrays of positions and RGB intensities
//!    (the paper's Sec. 3: levels `ℓ ≥ 1` of grid lights gathered by trilinear weights, eq. 1);
//! 3. [`lgh_hierarchy_update_intensities`] each frame where only the intensities change (the
//!    cheap path: the grids stay, bit-identical to a fresh build), or
//!    [`lgh_hierarchy_rebuild`] where the lights move;
//! 4. [`lgh_blending_create`] makes the blending of eq. (3) for an α (the paper's 2 by default:
//!    level ℓ's lights shade points within `r_ℓ = α h_ℓ` fully and fade out by `2 r_ℓ`);
//! 5. queries: [`lgh_sum`] sums a caller's shading callback over the lights a point sees (the
//!    callback applies visibility and the BRDF, eq. 1's `V` and `f`), [`lgh_gather`] copies those
//!    lights into a caller-owned buffer (for engines that shade on the GPU), and
//!    [`lgh_probe_batch`] gives the unshadowed light `Σ B_ℓ I g(d)` at many points at once.
//!
//! **Errors.** Every function that can fail returns an [`LghStatus`]; [`lgh_last_error`] gives the
//! message of the calling thread's last failure. No panic crosses the boundary: one would be
//! a bug in this library, reported as [`LghStatus::Panic`].
//!
//! **Threads.** Queries read their hierarchy and blending only: any number of threads may query
//! the same objects at once. Creating, updating, rebuilding and destroying need exclusive access
//! to the object they change: no query may run on it meanwhile. Results do not depend on the
//! thread that computes them.
//!
//! **Memory.** Queries allocate nothing (the core's queries do not; [`lgh_gather`] writes into the
//! caller's buffer); the objects are owned by the library until destroyed.

#![deny(unsafe_op_in_unsafe_fn)]
#![warn(missing_docs)]

use std::cell::RefCell;
use std::ffi::{c_char, c_void, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

use lgh_core::glam::Vec3;
use lgh_core::{
    falloff, Blending, BuildError, GridSettings, LightSample, LightingGridHierarchy, PointLight,
    QueryError,
};

/// The layout version of [`LghSettings`] this library was built with; a caller built against
/// another is refused ([`LghStatus::VersionMismatch`]).
pub const LGH_ABI_VERSION: u32 = 1;

/// What a call did.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LghStatus {
    /// Done.
    Ok = 0,
    /// A pointer that must not be NULL was NULL.
    NullArgument = 1,
    /// A value was out of range: a count, an alignment, α, a non-finite or negative number
    /// ([`lgh_last_error`] says which).
    InvalidArgument = 2,
    /// [`lgh_gather`]'s buffer holds fewer lights than the point sees: the count it needs is
    /// written, the lights are not.
    BufferTooSmall = 3,
    /// The caller's [`LghSettings`] has another `struct_size` or `version` than this library's.
    VersionMismatch = 4,
    /// The blending was made for the hierarchy before a rebuild changed its grids: make a new
    /// one.
    BlendingMismatch = 5,
    /// A bug in this library (a panic caught at the boundary); the message says where.
    Panic = 6,
}

/// How a hierarchy is built; [`lgh_settings_default`] fills the defaults.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LghSettings {
    /// `sizeof(LghSettings)` as the caller compiled it.
    pub struct_size: u32,
    /// [`LGH_ABI_VERSION`] as the caller compiled it.
    pub version: u32,
    /// The level-1 grid spacing `h1`; 0: the paper's Sec. 6.4 rule (halve a cell over the
    /// lights' box until the level-1 vertices with light outnumber the lights).
    pub h1: f32,
    /// Non-zero: the grids' origin is `origin`; 0: the lights' bounding-box minimum.
    pub has_origin: u32,
    /// The grids' origin where `has_origin` is non-zero.
    pub origin: [f32; 3],
    /// The top level `ℓ_max` (0 to 21); −1: the lowest level whose one cell holds every light.
    pub max_level: i32,
    /// Lights whose luminance is below this are skipped at every level but the top one (the
    /// paper's weak-light pruning); 0: none.
    pub prune_below: f32,
}

/// What [`lgh_hierarchy_info`] reports.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LghInfo {
    /// Input lights.
    pub light_count: usize,
    /// The top level `ℓ_max`.
    pub max_level: u32,
    /// The level-1 spacing `h1`.
    pub h1: f32,
    /// `h0 = h1 / 2`, where [`lgh_probe_batch`] clamps the fall-off `1/d²`.
    pub h0: f32,
}

/// One light a point sees, as [`lgh_sum`]'s callback and [`lgh_gather`] give it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LghLight {
    /// The light's position: an input light's, or a grid light's illumination centre `p_ℓi`.
    pub position: [f32; 3],
    /// The intensity to shade with, the blending weight applied: `B_ℓ(d) I_ℓi`.
    pub intensity: [f32; 3],
    /// The distance `d` from the point.
    pub distance: f32,
    /// The blending weight `B_ℓ(d)` (already in `intensity`).
    pub weight: f32,
    /// The level ℓ (0: an input light).
    pub level: u32,
    /// The light's index within its level (at level 0, the lights' order inside the
    /// hierarchy, not the input order).
    pub index: u32,
    /// The size `s_ℓi` of the light's positions (eq. 5); 0 at level 0.
    pub size: f32,
    /// The per-axis variance `σ²_ℓi` of the positions it stands for (eq. 4); 0 at level 0.
    pub variance: [f32; 3],
}

/// A shading callback: writes the radiance that `light` contributes at the queried point into
/// `out_rgb` (three floats; zero them for no contribution), visibility and BRDF included.
/// `user` is the pointer given to [`lgh_sum`].
pub type LghShadeFn =
    Option<unsafe extern "C" fn(light: *const LghLight, user: *mut c_void, out_rgb: *mut f32)>;

/// A hierarchy of point lights (opaque).
pub struct LghHierarchy {
    lgh: LightingGridHierarchy,
    settings: GridSettings,
}

/// The blending of eq. (3) for one α and one build of a hierarchy (opaque).
pub struct LghBlending {
    blending: Blending,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

/// An error: its status and message.
struct Failure(LghStatus, String);

impl From<BuildError> for Failure {
    fn from(e: BuildError) -> Self {
        Failure(LghStatus::InvalidArgument, e.to_string())
    }
}

impl From<QueryError> for Failure {
    fn from(e: QueryError) -> Self {
        let status = match e {
            QueryError::BlendingMismatch => LghStatus::BlendingMismatch,
            _ => LghStatus::InvalidArgument,
        };
        Failure(status, e.to_string())
    }
}

/// Runs `body`, catching a panic, and records the message of a failure for [`lgh_last_error`].
fn guard(name: &str, body: impl FnOnce() -> Result<(), Failure>) -> LghStatus {
    let result = catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Err(Failure(LghStatus::Panic, format!("internal error: {what}")))
    });
    match result {
        Ok(()) => LghStatus::Ok,
        Err(Failure(status, message)) => {
            let text = format!("{name}: {message}").replace('\0', " ");
            LAST_ERROR.with(|e| *e.borrow_mut() = CString::new(text).unwrap_or_default());
            status
        }
    }
}

/// `Err(NullArgument)` naming `what` if `p` is NULL.
fn non_null<T>(p: *const T, what: &str) -> Result<(), Failure> {
    if p.is_null() {
        return Err(Failure(LghStatus::NullArgument, format!("{what} is NULL")));
    }
    Ok(())
}

/// Boxes `object` and writes the handle into `*out`, the caller's to free with [`free`].
///
/// # Safety
/// `out` must be non-NULL and writable for a pointer.
unsafe fn hand_out<T>(out: *mut *mut T, object: T) {
    // SAFETY: the caller's promise.
    unsafe { out.write(Box::into_raw(Box::new(object))) };
}

/// Frees a handle made by [`hand_out`] (NULL: nothing).
///
/// # Safety
/// `handle` must be NULL or from [`hand_out`], not yet freed and not used after.
unsafe fn free<T>(handle: *mut T) {
    if !handle.is_null() {
        // SAFETY: made by Box::into_raw in hand_out, freed once (the caller's promise).
        drop(unsafe { Box::from_raw(handle) });
    }
}

/// `count` triples of floats at `p` as vectors (NULL allowed for none).
///
/// # Safety
/// `p` must point to `3 * count` readable floats, or be NULL with `count` 0.
unsafe fn triples<'a>(p: *const f32, count: usize, what: &str) -> Result<&'a [[f32; 3]], Failure> {
    if count == 0 {
        return Ok(&[]);
    }
    non_null(p, what)?;
    if !p.cast::<[f32; 3]>().is_aligned() {
        let message = format!("{what} is not aligned to a float");
        return Err(Failure(LghStatus::InvalidArgument, message));
    }
    if count > lgh_core::MAX_LIGHTS {
        let message = format!("{count} {what} is more than {}", lgh_core::MAX_LIGHTS);
        return Err(Failure(LghStatus::InvalidArgument, message));
    }
    // SAFETY: the caller promises 3·count floats at p (count ≤ MAX_LIGHTS, so no overflow), and
    // p is aligned and not NULL.
    Ok(unsafe { std::slice::from_raw_parts(p.cast::<[f32; 3]>(), count) })
}

/// The lights of `count` positions and intensities.
///
/// # Safety
/// As [`triples`], for both arrays.
unsafe fn point_lights(
    positions: *const f32,
    intensities: *const f32,
    count: usize,
) -> Result<Vec<PointLight>, Failure> {
    // SAFETY: passed on from the caller.
    let (p, i) = unsafe {
        (
            triples(positions, count, "positions")?,
            triples(intensities, count, "intensities")?,
        )
    };
    let light = |(p, i): (&[f32; 3], &[f32; 3])| PointLight::new(Vec3::from(*p), Vec3::from(*i));
    Ok(p.iter().zip(i).map(light).collect())
}

/// The core's settings from the caller's, checked.
fn grid_settings(s: &LghSettings) -> Result<GridSettings, Failure> {
    let own = std::mem::size_of::<LghSettings>() as u32;
    if s.struct_size != own || s.version != LGH_ABI_VERSION {
        let message = format!(
            "settings of size {} and version {}, where this library has {own} and {LGH_ABI_VERSION}",
            s.struct_size, s.version
        );
        return Err(Failure(LghStatus::VersionMismatch, message));
    }
    let bad = |message: String| Err(Failure(LghStatus::InvalidArgument, message));
    let h1 = match s.h1 {
        0.0 => None,
        h if h.is_finite() && h > 0.0 => Some(h),
        h => {
            return bad(format!(
                "h1 {h} must be positive and finite, or 0 (automatic)"
            ))
        }
    };
    let max_level = match s.max_level {
        -1 => None,
        l if (0..=i32::from(lgh_core::MAX_LEVEL)).contains(&l) => Some(l as u8),
        l => return bad(format!("max_level {l} must be 0 to 21, or -1 (automatic)")),
    };
    Ok(GridSettings {
        h1,
        origin: (s.has_origin != 0).then(|| Vec3::from(s.origin)),
        max_level,
        prune_below: s.prune_below,
        ..GridSettings::default()
    })
}

/// The layout version this library was built with ([`LGH_ABI_VERSION`]).
#[no_mangle]
pub extern "C" fn lgh_abi_version() -> u32 {
    LGH_ABI_VERSION
}

/// The message of the calling thread's last failed call (an empty string if none failed): a
/// NUL-terminated string owned by the library, valid until the thread's next failed call.
#[no_mangle]
pub extern "C" fn lgh_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// Fills `out` with the default settings (automatic `h1`, origin and top level, no pruning) and
/// this library's `struct_size` and `version`.
///
/// # Safety
/// `out` must be NULL or point to writable memory for one [`LghSettings`].
#[no_mangle]
pub unsafe extern "C" fn lgh_settings_default(out: *mut LghSettings) -> LghStatus {
    guard("lgh_settings_default", || {
        non_null(out, "out")?;
        let d = GridSettings::default();
        let settings = LghSettings {
            struct_size: std::mem::size_of::<LghSettings>() as u32,
            version: LGH_ABI_VERSION,
            h1: d.h1.unwrap_or(0.0),
            has_origin: 0,
            origin: [0.0; 3],
            max_level: d.max_level.map_or(-1, i32::from),
            prune_below: d.prune_below,
        };
        // SAFETY: out is not NULL and, by the caller's promise, writable.
        unsafe { out.write(settings) };
        Ok(())
    })
}

/// Builds a hierarchy over `count` point lights: `positions` and `intensities` hold `3 * count`
/// floats each (x, y, z; r, g, b), intensities finite and non-negative. `settings` may be NULL
/// for the defaults. On success `*out` is the new hierarchy, to be freed with
/// [`lgh_hierarchy_destroy`]; on failure `*out` is NULL.
///
/// # Safety
/// The arrays must hold `3 * count` readable floats (or be NULL with `count` 0); `settings` must
/// be NULL or point to an [`LghSettings`]; `out` must point to writable memory for a pointer.
#[no_mangle]
pub unsafe extern "C" fn lgh_hierarchy_create(
    positions: *const f32,
    intensities: *const f32,
    count: usize,
    settings: *const LghSettings,
    out: *mut *mut LghHierarchy,
) -> LghStatus {
    guard("lgh_hierarchy_create", || {
        non_null(out, "out")?;
        // SAFETY: out is not NULL and writable (the caller's promise).
        unsafe { out.write(std::ptr::null_mut()) };
        let settings = if settings.is_null() {
            GridSettings::default()
        } else {
            // SAFETY: not NULL, and an LghSettings by the caller's promise.
            grid_settings(unsafe { &*settings })?
        };
        // SAFETY: the caller's promise on the arrays.
        let lights = unsafe { point_lights(positions, intensities, count)? };
        let lgh = LightingGridHierarchy::build(&lights, &settings)?;
        // SAFETY: as above.
        unsafe { hand_out(out, LghHierarchy { lgh, settings }) };
        Ok(())
    })
}

/// Frees a hierarchy made by [`lgh_hierarchy_create`] (NULL: nothing). Blendings made for it
/// stay valid objects, to be freed on their own.
///
/// # Safety
/// `hierarchy` must be NULL or a hierarchy from [`lgh_hierarchy_create`] not yet freed, with no
/// call using it meanwhile or after.
#[no_mangle]
pub unsafe extern "C" fn lgh_hierarchy_destroy(hierarchy: *mut LghHierarchy) {
    // SAFETY: the caller's promise.
    unsafe { free(hierarchy) }
}

/// Gives the hierarchy's light count, top level, `h1` and `h0`.
///
/// # Safety
/// `hierarchy` must be NULL or a live hierarchy; `out` NULL or writable for one [`LghInfo`].
#[no_mangle]
pub unsafe extern "C" fn lgh_hierarchy_info(
    hierarchy: *const LghHierarchy,
    out: *mut LghInfo,
) -> LghStatus {
    guard("lgh_hierarchy_info", || {
        non_null(hierarchy, "hierarchy")?;
        non_null(out, "out")?;
        // SAFETY: both non-NULL and valid by the caller's promise.
        let lgh = unsafe { &(*hierarchy).lgh };
        let info = LghInfo {
            light_count: lgh.len(),
            max_level: u32::from(lgh.max_level()),
            h1: lgh.h1(),
            h0: lgh.h0(),
        };
        // SAFETY: as above.
        unsafe { out.write(info) };
        Ok(())
    })
}

/// Replaces every light's intensity (`3 * count` floats, `count` the hierarchy's light count, in
/// the input order): the cheap per-frame path, which keeps the grids; the hierarchy is then the
/// same, bit for bit, as one built afresh with these intensities. On failure it is unchanged.
///
/// # Safety
/// `hierarchy` must be NULL or a live hierarchy that no other thread uses during the call;
/// `intensities` must hold `3 * count` readable floats.
#[no_mangle]
pub unsafe extern "C" fn lgh_hierarchy_update_intensities(
    hierarchy: *mut LghHierarchy,
    intensities: *const f32,
    count: usize,
) -> LghStatus {
    guard("lgh_hierarchy_update_intensities", || {
        non_null(hierarchy, "hierarchy")?;
        // SAFETY: the caller's promise on the array.
        let values = unsafe { triples(intensities, count, "intensities")? };
        let values: Vec<Vec3> = values.iter().map(|&v| Vec3::from(v)).collect();
        // SAFETY: not NULL, live and not shared during the call (the caller's promise).
        let h = unsafe { &mut *hierarchy };
        h.lgh.update_intensities(&values)?;
        Ok(())
    })
}

/// Rebuilds the hierarchy over new lights (`count` may differ from before) with the settings it
/// was created with: for lights that move. Blendings made before must be made anew
/// ([`LghStatus::BlendingMismatch`] where the grids changed). On failure it is unchanged.
///
/// # Safety
/// As [`lgh_hierarchy_update_intensities`], and `positions` as `intensities`.
#[no_mangle]
pub unsafe extern "C" fn lgh_hierarchy_rebuild(
    hierarchy: *mut LghHierarchy,
    positions: *const f32,
    intensities: *const f32,
    count: usize,
) -> LghStatus {
    guard("lgh_hierarchy_rebuild", || {
        non_null(hierarchy, "hierarchy")?;
        // SAFETY: the caller's promise on the arrays.
        let lights = unsafe { point_lights(positions, intensities, count)? };
        // SAFETY: not NULL, live and not shared during the call (the caller's promise).
        let h = unsafe { &mut *hierarchy };
        h.lgh = LightingGridHierarchy::build(&lights, &h.settings)?;
        Ok(())
    })
}

/// Makes the blending of eq. (3) for `alpha` (> 0, finite; the paper uses 2) and this build of
/// `hierarchy`, to be freed with [`lgh_blending_destroy`]; on failure `*out` is NULL.
///
/// # Safety
/// `hierarchy` must be NULL or a live hierarchy; `out` must be writable for a pointer.
#[no_mangle]
pub unsafe extern "C" fn lgh_blending_create(
    hierarchy: *const LghHierarchy,
    alpha: f32,
    out: *mut *mut LghBlending,
) -> LghStatus {
    guard("lgh_blending_create", || {
        non_null(out, "out")?;
        // SAFETY: out is not NULL and writable (the caller's promise).
        unsafe { out.write(std::ptr::null_mut()) };
        non_null(hierarchy, "hierarchy")?;
        // SAFETY: not NULL and live (the caller's promise).
        let blending = unsafe { &(*hierarchy).lgh }.blending(alpha)?;
        // SAFETY: as above.
        unsafe { hand_out(out, LghBlending { blending }) };
        Ok(())
    })
}

/// Frees a blending made by [`lgh_blending_create`] (NULL: nothing).
///
/// # Safety
/// `blending` must be NULL or a blending from [`lgh_blending_create`] not yet freed, with no
/// call using it meanwhile or after.
#[no_mangle]
pub unsafe extern "C" fn lgh_blending_destroy(blending: *mut LghBlending) {
    // SAFETY: the caller's promise.
    unsafe { free(blending) }
}

/// The light of a [`LightSample`] as C sees it.
fn c_light(s: &LightSample) -> LghLight {
    LghLight {
        position: s.position.to_array(),
        intensity: s.intensity.to_array(),
        distance: s.distance,
        weight: s.weight,
        level: u32::from(s.level),
        index: s.index,
        size: s.size,
        variance: s.variance.to_array(),
    }
}

/// The hierarchy, the blending and the point of a query, checked.
///
/// # Safety
/// Each pointer NULL or valid for its type (`x`: three floats).
unsafe fn query_args<'a>(
    hierarchy: *const LghHierarchy,
    blending: *const LghBlending,
    x: *const f32,
) -> Result<(&'a LightingGridHierarchy, &'a Blending, Vec3), Failure> {
    non_null(hierarchy, "hierarchy")?;
    non_null(blending, "blending")?;
    // SAFETY: the caller's promise: x is NULL or three floats.
    let x = unsafe { triples(x, 1, "x")? }[0];
    // SAFETY: not NULL and live (the caller's promise).
    unsafe { Ok((&(*hierarchy).lgh, &(*blending).blending, Vec3::from(x))) }
}

/// Sums `shade`'s radiance over the lights that point `x` (three floats) sees, in the
/// hierarchy's order, into `out_rgb` (three floats), and the number of lights into `*out_lights`
/// (if not NULL): eq. (1), `Σ_ℓ Σ_i f V g B_ℓ I_ℓi`, with the callback's `f V g`. Safe to call
/// from many threads at once on the same objects.
///
/// # Safety
/// `hierarchy` and `blending` NULL or live; `x` NULL or three readable floats; `out_rgb` NULL or
/// three writable floats; `out_lights` NULL or writable; `shade` safe to call with a light, `user`
/// and three writable floats.
#[no_mangle]
pub unsafe extern "C" fn lgh_sum(
    hierarchy: *const LghHierarchy,
    blending: *const LghBlending,
    x: *const f32,
    shade: LghShadeFn,
    user: *mut c_void,
    out_rgb: *mut f32,
    out_lights: *mut u32,
) -> LghStatus {
    guard("lgh_sum", || {
        // SAFETY: the caller's promise on the pointers.
        let (lgh, blending, x) = unsafe { query_args(hierarchy, blending, x)? };
        let Some(shade) = shade else {
            return Err(Failure(LghStatus::NullArgument, "shade is NULL".into()));
        };
        non_null(out_rgb, "out_rgb")?;
        let (sum, n) = lgh.query_sum(x, blending, |s| {
            let light = c_light(s);
            let mut rgb = [0.0f32; 3];
            // SAFETY: the callback's contract (the caller's promise); both pointers are live.
            unsafe { shade(&light, user, rgb.as_mut_ptr()) };
            Vec3::from(rgb)
        })?;
        // SAFETY: out_rgb is three writable floats, out_lights NULL or writable.
        unsafe {
            std::ptr::copy_nonoverlapping(sum.to_array().as_ptr(), out_rgb, 3);
            if !out_lights.is_null() {
                out_lights.write(n);
            }
        }
        Ok(())
    })
}

/// Copies the lights that point `x` sees (each with its blended intensity and distance) into
/// `out` (room for `capacity`), in the hierarchy's order, and their number into `*out_count`.
/// Where they are more than `capacity`, nothing is copied, `*out_count` is the number needed and
/// the status [`LghStatus::BufferTooSmall`]. Allocates nothing; safe to call from many threads
/// at once on the same objects.
///
/// # Safety
/// As [`lgh_sum`]; `out` NULL (with `capacity` 0) or writable for `capacity` lights;
/// `out_count` writable.
#[no_mangle]
pub unsafe extern "C" fn lgh_gather(
    hierarchy: *const LghHierarchy,
    blending: *const LghBlending,
    x: *const f32,
    out: *mut LghLight,
    capacity: usize,
    out_count: *mut usize,
) -> LghStatus {
    guard("lgh_gather", || {
        // SAFETY: the caller's promise on the pointers.
        let (lgh, blending, x) = unsafe { query_args(hierarchy, blending, x)? };
        non_null(out_count, "out_count")?;
        if capacity > 0 {
            non_null(out, "out")?;
        }
        // Counted first, so that a buffer too small is left untouched.
        let needed = lgh.query(x, blending, |_| {})? as usize;
        // SAFETY: out_count is writable.
        unsafe { out_count.write(needed) };
        if needed > capacity {
            let message = format!("the point sees {needed} lights, the buffer holds {capacity}");
            return Err(Failure(LghStatus::BufferTooSmall, message));
        }
        let mut k = 0;
        lgh.query(x, blending, |s| {
            // SAFETY: k < needed ≤ capacity: within the caller's buffer.
            unsafe { out.add(k).write(c_light(s)) };
            k += 1;
        })?;
        Ok(())
    })
}

/// The unshadowed light `Σ_ℓ Σ_i B_ℓ(d) I_ℓi / max(d, h0)²` (a light probe: no visibility, no
/// BRDF; `h0` from [`lgh_hierarchy_info`]) at `count` points (`points`: `3 * count` floats) into
/// `out_rgb` (`3 * count` floats). The points are computed in order, one after the other; an
/// engine may split a batch across its own threads. Safe to call from many threads at once on
/// the same objects.
///
/// # Safety
/// As [`lgh_sum`]; `points` and `out_rgb` hold `3 * count` readable and writable floats.
#[no_mangle]
pub unsafe extern "C" fn lgh_probe_batch(
    hierarchy: *const LghHierarchy,
    blending: *const LghBlending,
    points: *const f32,
    count: usize,
    out_rgb: *mut f32,
) -> LghStatus {
    guard("lgh_probe_batch", || {
        non_null(hierarchy, "hierarchy")?;
        non_null(blending, "blending")?;
        // SAFETY: the caller's promise on the arrays.
        let points = unsafe { triples(points, count, "points")? };
        if count > 0 {
            non_null(out_rgb, "out_rgb")?;
            if !out_rgb.cast::<[f32; 3]>().is_aligned() {
                let message = "out_rgb is not aligned to a float".to_string();
                return Err(Failure(LghStatus::InvalidArgument, message));
            }
        }
        // SAFETY: not NULL and live (the caller's promise).
        let (lgh, blending) = unsafe { (&(*hierarchy).lgh, &(*blending).blending) };
        // Everything checked before anything is written: a failure leaves `out_rgb` as it was.
        lgh_core::LghBackend::with_blending(lgh, *blending)?;
        for (k, p) in points.iter().enumerate() {
            QueryError::check_point(Vec3::from(*p))
                .map_err(|e| Failure(LghStatus::InvalidArgument, format!("point {k}: {e}")))?;
        }
        let h0 = lgh.h0();
        for (k, p) in points.iter().enumerate() {
            let shade = |s: &LightSample| s.intensity * falloff(s.distance, h0);
            let (sum, _) = lgh.query_sum(Vec3::from(*p), blending, shade)?;
            // SAFETY: k < count: within the caller's 3·count floats.
            unsafe { out_rgb.add(3 * k).cast::<[f32; 3]>().write(sum.to_array()) };
        }
        Ok(())
    })
}
