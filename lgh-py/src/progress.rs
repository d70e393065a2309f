//! A render watched from Python: its progress reported to an optional callback, and the render
//! stopped by Ctrl-C or by an exception the callback raises.
//!
//! The callback is called as `callback(phase, done, total)` with the phase's label
//! (`"scattering"`, `"shadow maps"`, `"rendering"`, `"scatter shares"`), at each phase's start
//! and end and at most every 0.1 s between, from the library's worker threads, each taking the
//! GIL for the call.
//!
//! Stopping: the library checks nothing, so [`Watch`] stops it where it reports — at the next
//! row, light or chunk of voxels any worker finishes, its report unwinds that worker with
//! [`Stopped`] (`resume_unwind`: no panic message, no hook), rayon carries the unwinding to the
//! render's caller, and [`watched`] turns it back into the exception that asked for the stop.
//! The render into memory writes nothing and keeps no state between calls, so nothing is left
//! half done. Ctrl-C is seen by the calling (main) thread, which alone may run Python's signal
//! handlers: it waits for the render on another thread, checking for signals every 50 ms.

use std::panic::{self, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use lgh_volume::progress::{Phase, Progress};
use pyo3::prelude::*;

/// Between two calls of the callback within a phase, at least this long.
const INTERVAL: Duration = Duration::from_millis(100);

/// Between two checks for Ctrl-C while a render runs.
const SIGNALS: Duration = Duration::from_millis(50);

/// The unwinding payload that stops a render (never seen outside [`watched`]).
struct Stopped;

/// A [`Progress`] that reports to an optional Python callable and stops the render once asked.
pub struct Watch {
    callback: Option<Py<PyAny>>,
    /// The command's progress bars on stderr, where asked for instead of a callback.
    bars: Option<lgh_cli::Bars>,
    /// The current phase's label and its total.
    phase: Mutex<(&'static str, u64)>,
    done: AtomicU64,
    last: Mutex<Instant>,
    /// Set once the render is to stop: the next report unwinds.
    stop: AtomicBool,
    /// Why it stops: the first exception (the callback's, or `KeyboardInterrupt`).
    error: Mutex<Option<PyErr>>,
}

impl Watch {
    /// Reports to `callback`, if any, else to the command's progress bars if `bars`.
    pub fn new(callback: Option<Py<PyAny>>, bars: bool) -> Self {
        Watch {
            bars: (bars && callback.is_none()).then(|| lgh_cli::Bars::new(false)),
            callback,
            phase: Mutex::new((Phase::Render.label(), 0)),
            done: AtomicU64::new(0),
            last: Mutex::new(Instant::now()),
            stop: AtomicBool::new(false),
            error: Mutex::new(None),
        }
    }

    /// Stops the render for `error` (the first reason is kept).
    fn stop_for(&self, error: PyErr) {
        if let Ok(mut e) = self.error.lock() {
            e.get_or_insert(error);
        }
        self.stop.store(true, Ordering::SeqCst);
    }

    /// Unwinds this worker if the render is to stop.
    fn stop_here(&self) {
        if self.stop.load(Ordering::SeqCst) {
            panic::resume_unwind(Box::new(Stopped));
        }
    }

    /// Calls the callback now (`force`) or if [`INTERVAL`] has passed since the last call.
    fn report(&self, force: bool) {
        let Some(callback) = &self.callback else {
            return;
        };
        {
            let Ok(mut last) = self.last.lock() else {
                return;
            };
            if !force && last.elapsed() < INTERVAL {
                return;
            }
            *last = Instant::now();
        }
        let Ok((phase, total)) = self.phase.lock().map(|p| *p) else {
            return;
        };
        let done = self.done.load(Ordering::Relaxed).min(total);
        if self.stop.load(Ordering::SeqCst) {
            return;
        }
        // No lock is held across the call: the callback may let the GIL go to another worker
        // thread that reports meanwhile.
        let result = Python::attach(|py| callback.call1(py, (phase, done, total)));
        if let Err(e) = result {
            self.stop_for(e);
        }
    }
}

impl Watch {
    /// A phase labelled `label` begins with `total` steps.
    fn begin_labelled(&self, label: &'static str, total: u64) {
        self.stop_here();
        if let Ok(mut p) = self.phase.lock() {
            *p = (label, total);
        }
        self.done.store(0, Ordering::Relaxed);
        self.report(true);
        self.stop_here();
    }

    /// `steps` more steps of the current phase are done.
    fn advance_steps(&self, steps: u64) {
        self.stop_here();
        self.done.fetch_add(steps, Ordering::Relaxed);
        if let Some(bars) = &self.bars {
            Progress::advance(bars, steps);
        }
        self.report(false);
        self.stop_here();
    }

    /// The phase has ended (also while its work unwinds: report, never unwind again here).
    fn end_phase(&self) {
        if !self.stop.load(Ordering::SeqCst) {
            self.report(true);
        }
    }
}

impl Progress for Watch {
    fn begin(&self, phase: Phase, total: u64) {
        if let Some(bars) = &self.bars {
            Progress::begin(bars, phase, total);
        }
        self.begin_labelled(phase.label(), total);
    }

    fn advance(&self, steps: u64) {
        self.advance_steps(steps);
    }

    fn end(&self, phase: Phase) {
        if let Some(bars) = &self.bars {
            Progress::end(bars, phase);
        }
        self.end_phase();
    }
}

/// The GI render's progress: its phases' labels, the same reports and the same stops.
impl lgh_vpl::gi::GiProgress for Watch {
    fn begin(&self, phase: lgh_vpl::gi::GiPhase, rows: u64) {
        if let Some(bars) = &self.bars {
            lgh_vpl::gi::GiProgress::begin(bars, phase, rows);
        }
        self.begin_labelled(phase.label(), rows);
    }

    fn advance(&self, rows: u64) {
        self.advance_steps(rows);
    }

    fn end(&self, phase: lgh_vpl::gi::GiPhase) {
        if let Some(bars) = &self.bars {
            lgh_vpl::gi::GiProgress::end(bars, phase);
        }
        self.end_phase();
    }
}

/// Runs `render(&watch)` on another thread with the GIL released, this thread checking for
/// Ctrl-C meanwhile; a stop (Ctrl-C, or the callback's exception) is that exception. A panic
/// that is not a stop goes on unwinding (PyO3 raises it as `PanicException`).
pub fn watched<T: Send>(
    py: Python<'_>,
    watch: &Watch,
    render: impl FnOnce(&Watch) -> T + Send,
) -> PyResult<T> {
    let outcome = py.detach(|| {
        std::thread::scope(|s| {
            let worker = s.spawn(|| panic::catch_unwind(AssertUnwindSafe(|| render(watch))));
            while !worker.is_finished() {
                std::thread::sleep(SIGNALS);
                if let Err(e) = Python::attach(|py| py.check_signals()) {
                    watch.stop_for(e);
                }
            }
            worker.join().unwrap_or_else(Err)
        })
    });
    // An exception the callback raised at the very end stops nothing: raise it all the same.
    let error = watch.error.lock().ok().and_then(|mut e| e.take());
    match (outcome, error) {
        (Ok(_), Some(e)) => Err(e),
        (Ok(value), None) => Ok(value),
        (Err(payload), Some(e)) if payload.is::<Stopped>() => Err(e),
        (Err(payload), _) => panic::resume_unwind(payload),
    }
}
