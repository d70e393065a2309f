//! The library's progress reported to a Python callback: `callback(phase, done, total)` with
//! the phase's label (`"scattering"`, `"shadow maps"`, `"rendering"`, `"scatter shares"`), at
//! each phase's start and end and at most every 0.1 s between. The calls come from the
//! library's worker threads, each taking the GIL for the call; an exception the callback raises
//! is kept and raised when the work returns (the render itself does not stop for it).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use lgh_volume::progress::{Phase, Progress};
use pyo3::prelude::*;

/// Between two calls of the callback within a phase, at least this long.
const INTERVAL: Duration = Duration::from_millis(100);

/// A [`Progress`] that calls a Python callable.
pub struct Callback {
    callback: Py<PyAny>,
    /// The current phase and its total.
    phase: Mutex<(Phase, u64)>,
    done: AtomicU64,
    last: Mutex<Instant>,
    /// The first exception the callback raised.
    error: Mutex<Option<PyErr>>,
}

impl Callback {
    /// Reports to `callback`.
    pub fn new(callback: Py<PyAny>) -> Self {
        Callback {
            callback,
            phase: Mutex::new((Phase::Render, 0)),
            done: AtomicU64::new(0),
            last: Mutex::new(Instant::now()),
            error: Mutex::new(None),
        }
    }

    /// The exception the callback raised, if it raised one.
    pub fn take_error(&self) -> Option<PyErr> {
        self.error.lock().map_or(None, |mut e| e.take())
    }

    /// Calls the callback now (`force`) or if [`INTERVAL`] has passed since the last call.
    fn report(&self, force: bool) {
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
        if self.error.lock().map_or(true, |e| e.is_some()) {
            return;
        }
        // No lock is held across the call: the callback may let the GIL go to another worker
        // thread that reports meanwhile.
        let result = Python::attach(|py| self.callback.call1(py, (phase.label(), done, total)));
        if let (Err(e), Ok(mut error)) = (result, self.error.lock()) {
            error.get_or_insert(e);
        }
    }
}

impl Progress for Callback {
    fn begin(&self, phase: Phase, total: u64) {
        if let Ok(mut p) = self.phase.lock() {
            *p = (phase, total);
        }
        self.done.store(0, Ordering::Relaxed);
        self.report(true);
    }

    fn advance(&self, steps: u64) {
        self.done.fetch_add(steps, Ordering::Relaxed);
        self.report(false);
    }

    fn end(&self, _phase: Phase) {
        self.report(true);
    }
}
