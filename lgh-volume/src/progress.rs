//! Progress of long work, reported to whoever asked for it: a phase begins with its count of
//! steps, steps are done, the phase ends. The library never prints; the CLI draws bars.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, PoisonError};

/// The phases of a frame's render ([`FrameRender`](crate::FrameRender)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Multiple scattering (paper Sec. 5): steps are voxels of every depth.
    Scattering,
    /// Tracing the deep-shadow cube maps (paper Sec. 4): steps are lights.
    ShadowMaps,
    /// The image: steps are rows.
    Render,
    /// Each scattering depth's share of the image: steps are rows of every render.
    ScatterShares,
    /// Adaptive pixels' second pass (`PixelRefinement::Adaptive`), after [`Phase::Render`]:
    /// steps are the pixels refined.
    Refinement,
}

impl Phase {
    /// A short label for a progress bar.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Phase::Scattering => "scattering",
            Phase::ShadowMaps => "shadow maps",
            Phase::Render => "rendering",
            Phase::ScatterShares => "scatter shares",
            Phase::Refinement => "refining pixels",
        }
    }
}

/// Receives the progress of long work. Every method has an empty default, and `()` reports
/// nowhere. Calls come from worker threads (hence `Sync`); a phase's steps add up to the total
/// given at its start.
///
/// ```
/// use std::sync::atomic::{AtomicU64, Ordering};
/// use lgh_volume::progress::{Phase, Progress};
///
/// #[derive(Default)]
/// struct Count(AtomicU64);
/// impl Progress for Count {
///     fn advance(&self, steps: u64) {
///         self.0.fetch_add(steps, Ordering::Relaxed);
///     }
/// }
/// let count = Count::default();
/// count.begin(Phase::Render, 3);
/// count.advance(3);
/// assert_eq!(count.0.load(Ordering::Relaxed), 3);
/// ```
pub trait Progress: Sync {
    /// `phase` begins, with `total` steps (0 when it has nothing to count).
    fn begin(&self, phase: Phase, total: u64) {
        let _ = (phase, total);
    }
    /// `steps` more steps of the current phase are done.
    fn advance(&self, steps: u64) {
        let _ = steps;
    }
    /// `phase` has ended (also when it failed).
    fn end(&self, phase: Phase) {
        let _ = phase;
    }
}

impl Progress for () {}

/// One phase as a [`Recorder`] heard it: begun with `total` steps, `steps` of them reported.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Heard {
    /// The phase.
    pub phase: Phase,
    /// The steps it began with.
    pub total: u64,
    /// The steps reported done in it.
    pub steps: u64,
}

/// A [`Progress`] that keeps what it heard, phase by phase in the order they began: for a test
/// of what a caller is told, or a caller that reports after the work. Steps reported before any
/// phase began are not kept.
///
/// ```
/// use lgh_volume::progress::{Heard, Phase, Progress, Recorder};
///
/// let recorder = Recorder::default();
/// recorder.begin(Phase::Render, 3);
/// recorder.advance(2);
/// recorder.advance(1);
/// recorder.end(Phase::Render);
/// let render = Heard { phase: Phase::Render, total: 3, steps: 3 };
/// assert_eq!(recorder.heard(), [render]);
/// ```
#[derive(Debug, Default)]
pub struct Recorder(Mutex<Vec<Heard>>);

impl Recorder {
    /// The phases heard so far, in the order they began.
    #[must_use]
    pub fn heard(&self) -> Vec<Heard> {
        self.phases().clone()
    }

    /// The phases, whether or not a thread panicked while it held them (what it had recorded
    /// stays).
    fn phases(&self) -> std::sync::MutexGuard<'_, Vec<Heard>> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

impl Progress for Recorder {
    fn begin(&self, phase: Phase, total: u64) {
        self.phases().push(Heard {
            phase,
            total,
            steps: 0,
        });
    }

    fn advance(&self, steps: u64) {
        if let Some(last) = self.phases().last_mut() {
            last.steps += steps;
        }
    }
}

/// `progress`'s steps only: the parts of a phase reported as one (its begin and end are the
/// caller's), counted in rows — a render's [`Phase::Refinement`], whose steps are pixels, is
/// left out.
pub(crate) struct Steps<'p> {
    progress: &'p dyn Progress,
    refining: AtomicBool,
}

impl<'p> Steps<'p> {
    pub(crate) fn new(progress: &'p dyn Progress) -> Self {
        Steps {
            progress,
            refining: AtomicBool::new(false),
        }
    }
}

impl Progress for Steps<'_> {
    fn begin(&self, phase: Phase, _: u64) {
        if phase == Phase::Refinement {
            self.refining.store(true, Ordering::Relaxed);
        }
    }

    fn advance(&self, steps: u64) {
        if !self.refining.load(Ordering::Relaxed) {
            self.progress.advance(steps);
        }
    }

    fn end(&self, phase: Phase) {
        if phase == Phase::Refinement {
            self.refining.store(false, Ordering::Relaxed);
        }
    }
}

/// Runs `work` as `phase` of `total` steps of `progress`, giving it the per-step callback the
/// renderers take; the phase ends whether or not the work succeeded.
pub(crate) fn phase<T>(
    progress: &dyn Progress,
    phase: Phase,
    total: u64,
    work: impl FnOnce(&(dyn Fn(usize) + Sync)) -> T,
) -> T {
    progress.begin(phase, total);
    let out = work(&|n| progress.advance(n as u64));
    progress.end(phase);
    out
}
