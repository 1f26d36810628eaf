//! Progress bars on stderr for work that takes longer than a moment: drawn only when
//! stderr is a terminal and `--quiet` was not given, so scripts and pipes never see them.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

static QUIET: AtomicBool = AtomicBool::new(false);

/// Silences every progress bar of this process (`--quiet`).
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// A progress bar counting `unit`s (files, topics, bytes); invisible when stderr is not a
/// terminal or `--quiet` was given. Cheap to update from a hot loop: drawing is rate-limited.
pub struct Progress {
    bar: ProgressBar,
}

impl Progress {
    /// A bar of `len` steps, labelled `what` (`"topics"`, `"files"`).
    pub fn new(len: u64, what: &str) -> Progress {
        Progress::styled(len, what, "{prefix} [{bar:30}] {pos}/{len} {msg} ({eta})")
    }

    /// A bar of `len` bytes, labelled `what`.
    pub fn bytes(len: u64, what: &str) -> Progress {
        Progress::styled(
            len,
            what,
            "{prefix} [{bar:30}] {bytes}/{total_bytes} {msg} ({eta})",
        )
    }

    fn styled(len: u64, what: &str, template: &str) -> Progress {
        let visible = !QUIET.load(Ordering::Relaxed) && std::io::stderr().is_terminal();
        let target = if visible {
            ProgressDrawTarget::stderr_with_hz(10)
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(Some(len), target);
        if let Ok(style) = ProgressStyle::with_template(template) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_prefix(what.to_owned());
        // Nothing is drawn for work that ends within a moment.
        bar.enable_steady_tick(Duration::from_millis(250));
        Progress { bar }
    }

    /// Advances by `n` steps.
    pub fn inc(&self, n: u64) {
        self.bar.inc(n);
    }

    /// Sets the text after the counts (the current file or topic).
    pub fn message(&self, msg: impl Into<std::borrow::Cow<'static, str>>) {
        self.bar.set_message(msg);
    }
}

impl Progress {
    /// Runs `f` (which prints) with the bar hidden, so that its lines do not mix.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        self.bar.suspend(f)
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}
