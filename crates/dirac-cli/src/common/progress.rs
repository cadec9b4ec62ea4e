//! Progress on stderr while a spectrum is computed: a spinner during assembly and
//! factorisation, then a bar of locked eigenpairs updated after every Lanczos restart. Nothing
//! is drawn for solves shorter than a second, with `--quiet`, or when stderr is not a terminal.

use std::io::IsTerminal;
use std::sync::mpsc::{self, RecvTimeoutError, Sender};
use std::thread::{self, JoinHandle};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use qeig::Progress;

/// How long a solve runs before the display appears.
const DELAY: Duration = Duration::from_secs(1);

/// The progress display of one `dirac spectrum` run; cleared when dropped.
pub struct SolveProgress {
    bar: ProgressBar,
    /// Ends the thread that reveals the display after [`DELAY`].
    reveal: Option<(Sender<()>, JoinHandle<()>)>,
}

impl SolveProgress {
    /// Starts the display, unless `quiet` or stderr is not a terminal (then it stays hidden).
    pub fn start(quiet: bool) -> Self {
        let bar = ProgressBar::hidden();
        if quiet || !std::io::stderr().is_terminal() {
            return Self { bar, reveal: None };
        }
        bar.set_style(style("{spinner} {elapsed:>3} {wide_msg}"));
        bar.set_message("assembling and factorising");
        let (stop, stopped) = mpsc::channel();
        let shown = bar.clone();
        let thread = thread::spawn(move || {
            if let Err(RecvTimeoutError::Timeout) = stopped.recv_timeout(DELAY) {
                shown.set_draw_target(ProgressDrawTarget::stderr());
                shown.enable_steady_tick(Duration::from_millis(100));
            }
        });
        Self {
            bar,
            reveal: Some((stop, thread)),
        }
    }

    /// Shows the eigensolver's state (the callback of `spectrum_with_progress`).
    pub fn update(&self, progress: &Progress) {
        if self.reveal.is_none() {
            return;
        }
        let wanted = progress.wanted as u64;
        if self.bar.length() != Some(wanted) {
            self.bar.set_style(style(
                "{spinner} {elapsed:>3} [{bar:24}] {pos}/{len} locked, {wide_msg}",
            ));
            self.bar.set_length(wanted);
        }
        self.bar.set_position((progress.locked as u64).min(wanted));
        self.bar.set_message(format!(
            "round {}, {} restarts, {} operator applications",
            progress.round, progress.restarts, progress.operator_applications
        ));
    }
}

impl Drop for SolveProgress {
    fn drop(&mut self) {
        if let Some((stop, thread)) = self.reveal.take() {
            // The thread ends on the message or on the closed channel; either is fine.
            let _ = stop.send(());
            let _ = thread.join();
        }
        self.bar.finish_and_clear();
    }
}

/// A style from a template (a fixed string, so the fallback is never needed in practice).
fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_spinner())
}
