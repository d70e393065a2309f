//! A C ABI over `lgh-core`: the Lighting Grid Hierarchy (Yuksel & Yuksel 2017) for engines that
//! speak C — Unreal, Godot and Unity native plugins, in-house C++ engines.
//!
//! The header `include/lgh.h` is generated from this file by cbindgen and committed; the test
//! `tests/header.rs` regenerates it and fails when the committed one is stale. Each function's
//! Rust example (a doctest calling it as C would) sits in a `#[cfg_attr(any(doc, doctest), doc
//! = ...)]` attribute, which cbindgen does not copy: the header keeps the C documentation only.
//! The API, in the order an engine calls it:
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
///
/// Three fields hold sentinels: `h1 == 0` derives the spacing, `has_origin == 0` takes the
/// lights' bounding-box minimum for the origin, and `max_level == -1` lets the library choose
/// the top level. [`lgh_settings_default`] sets all three and prunes nothing.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LghSettings {
    /// `sizeof(LghSettings)` as the caller compiled it.
    pub struct_size: u32,
    /// [`LGH_ABI_VERSION`] as the caller compiled it.
    pub version: u32,
    /// The level-1 grid spacing `h1`: positive and finite, or the sentinel 0 (the default;
    /// `-0.0` too) to derive it by the paper's Sec. 6.4 rule (halve a cell over the lights' box
    /// until the level-1 vertices with light outnumber the lights). Negative, NaN or infinite:
    /// `LGH_STATUS_INVALID_ARGUMENT`.
    pub h1: f32,
    /// A flag for `origin`: 0 (the default): no origin given, the grids' origin is the
    /// lights' bounding-box minimum and `origin` is not read; any other value: the grids'
    /// origin is `origin`.
    pub has_origin: u32,
    /// The grids' origin (finite; a vertex of every level), read only where `has_origin` is
    /// non-zero.
    pub origin: [f32; 3],
    /// The top level `ℓ_max`: 0 to 21, or the sentinel -1 (the default) to let the library
    /// choose the lowest level whose one cell holds every light. Any other value:
    /// `LGH_STATUS_INVALID_ARGUMENT`.
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

/// [`LghSettings::h1`]'s sentinel: derive `h1` by the paper's Sec. 6.4 rule (`None` in
/// [`GridSettings::h1`]). Compared with `==`, so `-0.0` means it too.
const H1_DERIVED: f32 = 0.0;

/// [`LghSettings::max_level`]'s sentinel: let the library choose `ℓ_max` (`None` in
/// [`GridSettings::max_level`]).
const MAX_LEVEL_CHOSEN: i32 = -1;

/// [`LghSettings::has_origin`]'s value for "no origin given" (`None` in
/// [`GridSettings::origin`]); any other value gives one.
const NO_ORIGIN: u32 = 0;

/// The core's settings from the caller's, checked: the C sentinels become `Option`s here and go
/// no further in.
fn grid_settings(s: &LghSettings) -> Result<GridSettings, Failure> {
    let own = std::mem::size_of::<LghSettings>() as u32;
    if s.struct_size != own || s.version != LGH_ABI_VERSION {
        let message = format!(
            "settings of size {} and version {}, where this library has {own} and {LGH_ABI_VERSION}",
            s.struct_size, s.version
        );
        return Err(Failure(LghStatus::VersionMismatch, message));
    }
    Ok(GridSettings {
        h1: spacing_from_c(s.h1)?,
        origin: origin_from_c(s.has_origin, s.origin),
        max_level: top_level_from_c(s.max_level)?,
        prune_below: s.prune_below,
        ..GridSettings::default()
    })
}

/// [`LghSettings::h1`] as the core's `h1`: [`H1_DERIVED`] → `None` (the Sec. 6.4 rule), a
/// positive finite spacing → `Some`, anything else an error.
fn spacing_from_c(h1: f32) -> Result<Option<f32>, Failure> {
    if h1 == H1_DERIVED {
        Ok(None)
    } else if h1.is_finite() && h1 > 0.0 {
        Ok(Some(h1))
    } else {
        let message = format!("h1 {h1} must be positive and finite, or 0 (automatic)");
        Err(Failure(LghStatus::InvalidArgument, message))
    }
}

/// [`LghSettings::max_level`] as the core's `ℓ_max`: [`MAX_LEVEL_CHOSEN`] → `None` (the library
/// chooses), 0 to [`lgh_core::MAX_LEVEL`] → `Some`, anything else an error.
fn top_level_from_c(max_level: i32) -> Result<Option<u8>, Failure> {
    match max_level {
        MAX_LEVEL_CHOSEN => Ok(None),
        l if (0..=i32::from(lgh_core::MAX_LEVEL)).contains(&l) => Ok(Some(l as u8)),
        l => {
            let message = format!("max_level {l} must be 0 to 21, or -1 (automatic)");
            Err(Failure(LghStatus::InvalidArgument, message))
        }
    }
}

/// [`LghSettings::has_origin`] and `origin` as the core's origin: [`NO_ORIGIN`] → `None` (the
/// lights' bounding-box minimum), any other flag → `Some(origin)` (checked by the build).
fn origin_from_c(has_origin: u32, origin: [f32; 3]) -> Option<Vec3> {
    (has_origin != NO_ORIGIN).then(|| Vec3::from(origin))
}

/// The core's settings as C holds them, each `None` as its sentinel: the inverse of
/// [`grid_settings`] for the fields C has.
fn c_settings(g: &GridSettings) -> LghSettings {
    LghSettings {
        struct_size: std::mem::size_of::<LghSettings>() as u32,
        version: LGH_ABI_VERSION,
        h1: g.h1.unwrap_or(H1_DERIVED),
        has_origin: u32::from(g.origin.is_some()),
        origin: g.origin.map_or([0.0; 3], |o| o.to_array()),
        max_level: g.max_level.map_or(MAX_LEVEL_CHOSEN, i32::from),
        prune_below: g.prune_below,
    }
}

/// The layout version this library was built with ([`LGH_ABI_VERSION`]).
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
assert_eq!(lgh_capi::lgh_abi_version(), lgh_capi::LGH_ABI_VERSION);
```
"#
)]
#[no_mangle]
#[must_use]
pub extern "C" fn lgh_abi_version() -> u32 {
    LGH_ABI_VERSION
}

/// The message of the calling thread's last failed call (an empty string if none failed): a
/// NUL-terminated string owned by the library, valid until the thread's next failed call.
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
use lgh_capi::*;
use std::ffi::CStr;

// SAFETY: NULL is refused with a status, never written.
assert_eq!(unsafe { lgh_settings_default(std::ptr::null_mut()) }, LghStatus::NullArgument);
// SAFETY: the library's string, live until this thread's next failure.
let message = unsafe { CStr::from_ptr(lgh_last_error()) }.to_str()?;
assert_eq!(message, "lgh_settings_default: out is NULL");
# Ok::<(), Box<dyn std::error::Error>>(())
```
"#
)]
#[no_mangle]
#[must_use]
pub extern "C" fn lgh_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// Fills `out` with the default settings and this library's `struct_size` and `version`: `h1`
/// derived (`h1 = 0`), the origin the lights' bounding-box minimum (`has_origin = 0`), the top
/// level chosen (`max_level = -1`), no pruning (`prune_below = 0`).
///
/// # Safety
/// `out` must be NULL or point to writable memory for one [`LghSettings`].
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
use lgh_capi::*;
use std::mem::MaybeUninit;

let mut s = MaybeUninit::<LghSettings>::uninit();
// SAFETY: room for one LghSettings.
assert_eq!(unsafe { lgh_settings_default(s.as_mut_ptr()) }, LghStatus::Ok);
// SAFETY: filled by the call.
let s = unsafe { s.assume_init() };
// The three sentinels: derive h1, the lights' box for the origin, choose ℓ_max.
assert_eq!((s.h1, s.has_origin, s.max_level), (0.0, 0, -1));
assert_eq!(s.version, LGH_ABI_VERSION);
```
"#
)]
#[no_mangle]
pub unsafe extern "C" fn lgh_settings_default(out: *mut LghSettings) -> LghStatus {
    guard("lgh_settings_default", || {
        non_null(out, "out")?;
        let settings = c_settings(&GridSettings::default());
        // SAFETY: out is not NULL and, by the caller's promise, writable.
        unsafe { out.write(settings) };
        Ok(())
    })
}

/// Builds a hierarchy over `count` point lights: `positions` and `intensities` hold `3 * count`
/// floats each (x, y, z; r, g, b), intensities finite with a non-negative luminance (a channel
/// may be negative: a colour outside Rec. 709's gamut, as Blender's blackbody below about 1900 K).
/// `settings` may be NULL for the defaults. On success `*out` is the new hierarchy, to be freed with
/// [`lgh_hierarchy_destroy`]; on failure `*out` is NULL.
///
/// # Safety
/// The arrays must hold `3 * count` readable floats (or be NULL with `count` 0); `settings` must
/// be NULL or point to an [`LghSettings`]; `out` must point to writable memory for a pointer.
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
use lgh_capi::*;
use std::ptr::null_mut;

let (positions, intensities) = ([0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0], [1.0f32; 6]);
let mut s = std::mem::MaybeUninit::<LghSettings>::uninit();
// SAFETY: room for one LghSettings, filled by the call.
let s = unsafe { (lgh_settings_default(s.as_mut_ptr()), s.assume_init()).1 };
let (mut h, bad) = (null_mut(), LghSettings { max_level: 22, ..s });
// SAFETY: two lights' arrays, live settings and a writable handle.
let status = unsafe { lgh_hierarchy_create(positions.as_ptr(), intensities.as_ptr(), 2, &bad, &mut h) };
assert_eq!((status, h.is_null()), (LghStatus::InvalidArgument, true)); // ℓ_max ≤ 21
let good = LghSettings { h1: 0.5, ..s };
// SAFETY: as above.
let status = unsafe { lgh_hierarchy_create(positions.as_ptr(), intensities.as_ptr(), 2, &good, &mut h) };
assert_eq!((status, h.is_null()), (LghStatus::Ok, false));
# // SAFETY: made above, not used after.
# unsafe { lgh_hierarchy_destroy(h) };
```
"#
)]
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
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
# use lgh_capi::*;
# use std::ptr::{null, null_mut};
# let h = lgh_capi::doctest::two_lights();
// SAFETY: `h` was made by lgh_hierarchy_create and is not used after.
unsafe { lgh_hierarchy_destroy(h) };
// SAFETY: NULL is allowed (nothing is freed).
unsafe { lgh_hierarchy_destroy(null_mut()) };
```
"#
)]
#[no_mangle]
pub unsafe extern "C" fn lgh_hierarchy_destroy(hierarchy: *mut LghHierarchy) {
    // SAFETY: the caller's promise.
    unsafe { free(hierarchy) }
}

/// Gives the hierarchy's light count, top level, `h1` and `h0`.
///
/// # Safety
/// `hierarchy` must be NULL or a live hierarchy; `out` NULL or writable for one [`LghInfo`].
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
# use lgh_capi::*;
# use std::ptr::{null, null_mut};
# let h = lgh_capi::doctest::two_lights();
let mut info = LghInfo::default();
// SAFETY: a live hierarchy and a writable LghInfo.
assert_eq!(unsafe { lgh_hierarchy_info(h, &mut info) }, LghStatus::Ok);
assert_eq!(info.light_count, 2);
assert_eq!(info.h0, info.h1 / 2.0);
# // SAFETY: made above, not used after.
# unsafe { lgh_hierarchy_destroy(h) };
```
"#
)]
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
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
# use lgh_capi::*;
# use std::ptr::{null, null_mut};
# let h = lgh_capi::doctest::two_lights();
let hotter = [2.0f32, 1.0, 0.5, 0.0, 0.0, 0.0];
// SAFETY: a live hierarchy and 3 · count floats.
assert_eq!(unsafe { lgh_hierarchy_update_intensities(h, hotter.as_ptr(), 2) }, LghStatus::Ok);
// One light short of the hierarchy's two: refused, the hierarchy unchanged.
// SAFETY: as above.
let status = unsafe { lgh_hierarchy_update_intensities(h, hotter.as_ptr(), 1) };
assert_eq!(status, LghStatus::InvalidArgument);
# // SAFETY: made above, not used after.
# unsafe { lgh_hierarchy_destroy(h) };
```
"#
)]
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
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
# use lgh_capi::*;
# use std::ptr::{null, null_mut};
# let h = lgh_capi::doctest::two_lights();
let moved = [0.0f32, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 2.0, 0.0];
// SAFETY: a live hierarchy and 3 · count floats in each array.
let status = unsafe { lgh_hierarchy_rebuild(h, moved.as_ptr(), [1.0f32; 9].as_ptr(), 3) };
assert_eq!(status, LghStatus::Ok);
let mut info = LghInfo::default();
// SAFETY: a live hierarchy and a writable LghInfo.
assert_eq!(unsafe { lgh_hierarchy_info(h, &mut info) }, LghStatus::Ok);
assert_eq!(info.light_count, 3);
# // SAFETY: made above, not used after.
# unsafe { lgh_hierarchy_destroy(h) };
```
"#
)]
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
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
# use lgh_capi::*;
# use std::ptr::{null, null_mut};
# let h = lgh_capi::doctest::two_lights();
let mut b = null_mut();
// SAFETY: a live hierarchy and a writable handle.
assert_eq!(unsafe { lgh_blending_create(h, -1.0, &mut b) }, LghStatus::InvalidArgument);
assert!(b.is_null());
// SAFETY: as above.
assert_eq!(unsafe { lgh_blending_create(h, 2.0, &mut b) }, LghStatus::Ok);
assert!(!b.is_null());
# // SAFETY: made above, not used after.
# unsafe { (lgh_blending_destroy(b), lgh_hierarchy_destroy(h)) };
```
"#
)]
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
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
# use lgh_capi::*;
# use std::ptr::{null, null_mut};
# let (h, b) = lgh_capi::doctest::two_lights_blended();
// SAFETY: `b` was made by lgh_blending_create and is not used after.
unsafe { lgh_blending_destroy(b) };
// SAFETY: NULL is allowed (nothing is freed).
unsafe { lgh_blending_destroy(null_mut()) };
# // SAFETY: made above, not used after.
# unsafe { lgh_hierarchy_destroy(h) };
```
"#
)]
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
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
# use lgh_capi::*;
# use std::ptr::{null, null_mut};
# let (h, b) = lgh_capi::doctest::two_lights_blended();
use std::ffi::c_void;

/// Each light's blended intensity, unshaded.
unsafe extern "C" fn intensity(light: *const LghLight, _: *mut c_void, out: *mut f32) {
    // SAFETY: lgh_sum passes a live light and three writable floats.
    unsafe { out.copy_from_nonoverlapping((*light).intensity.as_ptr(), 3) };
}
let (x, mut rgb, mut n) = ([50.0f32, 0.0, 0.0], [0.0f32; 3], 0u32);
// SAFETY: live objects, a point, a callback as above and writable outputs.
let status = unsafe { lgh_sum(h, b, x.as_ptr(), Some(intensity), null_mut(), rgb.as_mut_ptr(), &mut n) };
assert_eq!(status, LghStatus::Ok);
// Far away, the blended levels carry the lights' total intensity.
assert!(n >= 1 && rgb.iter().all(|&c| (c - 2.0).abs() < 1e-5));
# // SAFETY: made above, not used after.
# unsafe { (lgh_blending_destroy(b), lgh_hierarchy_destroy(h)) };
```
"#
)]
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
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
# use lgh_capi::*;
# use std::ptr::{null, null_mut};
# let (h, b) = lgh_capi::doctest::two_lights_blended();
let (x, mut needed) = ([0.5f32, 0.0, 0.0], 0usize);
// SAFETY: live objects and a point; no buffer, with capacity 0.
let status = unsafe { lgh_gather(h, b, x.as_ptr(), null_mut(), 0, &mut needed) };
assert_eq!((status, needed), (LghStatus::BufferTooSmall, 2)); // both lights, at level 0
let mut lights = vec![LghLight::default(); needed];
// SAFETY: room for `needed` lights.
let status = unsafe { lgh_gather(h, b, x.as_ptr(), lights.as_mut_ptr(), needed, &mut needed) };
assert_eq!(status, LghStatus::Ok);
assert!(lights.iter().all(|l| l.level == 0 && l.distance == 0.5));
# // SAFETY: made above, not used after.
# unsafe { (lgh_blending_destroy(b), lgh_hierarchy_destroy(h)) };
```
"#
)]
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
#[cfg_attr(
    any(doc, doctest),
    doc = r#"
# Example (Rust)

```
# use lgh_capi::*;
# use std::ptr::{null, null_mut};
# let (h, b) = lgh_capi::doctest::two_lights_blended();
use lgh_core::glam::Vec3;
use lgh_core::{falloff, GridSettings, LightingGridHierarchy, PointLight};

let (points, mut rgb) = ([0.5f32, 2.0, 0.0, 9.0, 1.0, 3.0], [0.0f32; 6]);
// SAFETY: live objects and 3 · 2 floats in and out.
assert_eq!(unsafe { lgh_probe_batch(h, b, points.as_ptr(), 2, rgb.as_mut_ptr()) }, LghStatus::Ok);
// The Rust API's sum, bit for bit.
let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
let shade = |s: &lgh_core::LightSample| s.intensity * falloff(s.distance, lgh.h0());
let (sum, _) = lgh.query_sum(Vec3::new(9.0, 1.0, 3.0), &lgh.blending(2.0)?, shade)?;
assert_eq!(sum.to_array(), rgb[3..]);
# // SAFETY: made above, not used after.
# unsafe { (lgh_blending_destroy(b), lgh_hierarchy_destroy(h)) };
# Ok::<(), Box<dyn std::error::Error>>(())
```
"#
)]
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

/// What the functions' Rust examples start from, made once here instead of in hidden lines of
/// each: not part of the C API (cbindgen exports only `extern "C"` functions and their types).
#[doc(hidden)]
pub mod doctest {
    use super::*;

    /// A hierarchy of two lights, at the origin and at x = 1, of intensity 1 each, with the
    /// default settings; the example frees it.
    #[must_use]
    pub fn two_lights() -> *mut LghHierarchy {
        let (positions, intensities) = ([0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0], [1.0f32; 6]);
        let mut h = core::ptr::null_mut();
        // SAFETY: two lights' arrays of six floats each, the default settings (NULL) and a
        // writable handle.
        let made = unsafe {
            lgh_hierarchy_create(
                positions.as_ptr(),
                intensities.as_ptr(),
                2,
                core::ptr::null(),
                &mut h,
            )
        };
        assert_eq!(made, LghStatus::Ok);
        h
    }

    /// [`two_lights`] and its blending of eq. (3) at the paper's α = 2; the example frees both.
    #[must_use]
    pub fn two_lights_blended() -> (*mut LghHierarchy, *mut LghBlending) {
        let h = two_lights();
        let mut b = core::ptr::null_mut();
        // SAFETY: `h` is the live hierarchy just made and `b` a writable handle.
        assert_eq!(
            unsafe { lgh_blending_create(h, 2.0, &mut b) },
            LghStatus::Ok
        );
        (h, b)
    }
}
