//! Progress bars on stderr, only when stderr is a terminal and the user did not ask for quiet.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar of `len` steps, hidden when quiet or when stderr is not a terminal.
pub fn bar(len: u64, what: &str, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden());
    }
    let b = ProgressBar::new(len);
    b.set_style(
        ProgressStyle::with_template("{msg} {wide_bar} {pos}/{len} ({eta} left)")
            .expect("valid template"),
    );
    b.set_message(what.to_string());
    b
}

/// The libraries' progress ([`lgh_volume::Progress`], [`lgh_vpl::gi::GiProgress`]) as one bar a phase on stderr: labelled by
/// the phase (the render's by `render_label` if given), hidden when quiet or when the phase has
/// nothing to count.
pub struct Bars {
    quiet: bool,
    render_label: Option<String>,
    bar: std::sync::Mutex<Option<ProgressBar>>,
}

impl Bars {
    /// Bars on stderr, none when `quiet`.
    pub fn new(quiet: bool) -> Self {
        Bars {
            quiet,
            render_label: None,
            bar: std::sync::Mutex::new(None),
        }
    }

    /// The render's bar labelled `label` (a frame's number, say) instead of "rendering".
    pub fn with_render_label(mut self, label: String) -> Self {
        self.render_label = Some(label);
        self
    }

    fn current(&self) -> std::sync::MutexGuard<'_, Option<ProgressBar>> {
        self.bar
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

impl Bars {
    /// A phase labelled `label` begins with `total` steps: its bar, hidden when it has none.
    fn begin_bar(&self, label: &str, total: u64) {
        *self.current() = Some(bar(total, label, self.quiet || total == 0));
    }

    fn advance_bar(&self, steps: u64) {
        if let Some(b) = self.current().as_ref() {
            b.inc(steps);
        }
    }

    fn end_bar(&self) {
        if let Some(b) = self.current().take() {
            b.finish_and_clear();
        }
    }
}

impl lgh_volume::Progress for Bars {
    fn begin(&self, phase: lgh_volume::Phase, total: u64) {
        let label = match (phase, &self.render_label) {
            (lgh_volume::Phase::Render, Some(label)) => label.as_str(),
            _ => phase.label(),
        };
        self.begin_bar(label, total);
    }

    fn advance(&self, steps: u64) {
        self.advance_bar(steps);
    }

    fn end(&self, _: lgh_volume::Phase) {
        self.end_bar();
    }
}

/// lgh-vpl's progress of a global-illumination render ([`lgh_vpl::gi::GiProgress`]), the same
/// way: one bar a phase.
impl lgh_vpl::gi::GiProgress for Bars {
    fn begin(&self, phase: lgh_vpl::gi::GiPhase, rows: u64) {
        self.begin_bar(phase.label(), rows);
    }

    fn advance(&self, rows: u64) {
        self.advance_bar(rows);
    }

    fn end(&self, _: lgh_vpl::gi::GiPhase) {
        self.end_bar();
    }
}
