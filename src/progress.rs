//! Progress on stderr for work that can take more than about a second: one helper for every
//! command and library loop (reference renders, acquisition, fitting, sweeps, turntables,
//! light-set preparation).
//!
//! Design rule: drawing is decided once, when a [`Progress`] is made. On a terminal it draws a
//! bar with the count, the elapsed time and an ETA (or a spinner when the amount of work is
//! unknown); when stderr is not a terminal (a pipe, a file, CI) it draws nothing at all, so
//! logs stay clean. Library code takes a `&Progress` and only counts ([`Progress::inc`]);
//! [`Progress::hidden`] is what callers pass when nobody is watching. Counting is thread-safe
//! (rayon workers may call [`Progress::inc`] concurrently) and never changes what is computed.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::Duration;

/// A progress display on stderr, or nothing (see the module doc). Cloning shares the display.
#[derive(Clone, Debug)]
pub struct Progress {
    bar: ProgressBar,
    /// A terminal bar made with length 0: hidden until [`Progress::set_length`].
    deferred: bool,
}

impl Progress {
    /// A bar over `len` steps of `unit` ("tiles", "rows", "view texels", ...), labelled
    /// `what`, with elapsed time and ETA. Hidden when stderr is not a terminal. With
    /// `len == 0` (work whose size the library sets once it starts) nothing is drawn until
    /// [`Progress::set_length`] gives a length: no empty bar, and none at all when the work
    /// turns out to be skipped (a cache hit).
    pub fn bar(len: u64, what: &str, unit: &str) -> Progress {
        if !stderr_is_terminal() {
            return Progress::hidden();
        }
        let target = if len == 0 {
            ProgressDrawTarget::hidden()
        } else {
            ProgressDrawTarget::stderr()
        };
        let bar = ProgressBar::with_draw_target(Some(len), target);
        let template = format!(
            "{{msg}} [{{bar:30}}] {{pos}}/{{len}} {unit}  {{elapsed_precise}} (eta {{eta_precise}})"
        );
        bar.set_style(
            ProgressStyle::with_template(&template)
                .expect("a valid indicatif template")
                .progress_chars("=> "),
        );
        bar.set_message(what.to_string());
        Progress {
            bar,
            deferred: len == 0,
        }
    }

    /// A spinner labelled `what` for work of unknown length. Hidden when stderr is not a
    /// terminal.
    pub fn spinner(what: &str) -> Progress {
        if !stderr_is_terminal() {
            return Progress::hidden();
        }
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        bar.set_style(
            ProgressStyle::with_template("{spinner} {msg}  {elapsed_precise}")
                .expect("a valid indicatif template"),
        );
        bar.set_message(what.to_string());
        bar.enable_steady_tick(Duration::from_millis(120));
        Progress {
            bar,
            deferred: false,
        }
    }

    /// A display that draws nothing; counting on it costs an atomic add.
    pub fn hidden() -> Progress {
        Progress {
            bar: ProgressBar::hidden(),
            deferred: false,
        }
    }

    /// Whether anything is drawn.
    pub fn is_hidden(&self) -> bool {
        self.bar.is_hidden()
    }

    /// Sets the total number of steps (for work whose size is known only once it starts);
    /// a bar made with length 0 on a terminal starts drawing here.
    pub fn set_length(&self, len: u64) {
        self.bar.set_length(len);
        if self.bar.is_hidden() && self.deferred {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    /// Replaces the label.
    pub fn set_message(&self, what: impl Into<String>) {
        self.bar.set_message(what.into());
    }

    /// Counts `n` finished steps.
    pub fn inc(&self, n: u64) {
        self.bar.inc(n);
    }

    /// Steps counted so far (also on a hidden display).
    pub fn position(&self) -> u64 {
        self.bar.position()
    }

    /// Prints `line` above the display (or plainly to stderr when hidden), without tearing it.
    pub fn println(&self, line: impl AsRef<str>) {
        if self.bar.is_hidden() {
            eprintln!("{}", line.as_ref());
        } else {
            self.bar.println(line.as_ref());
        }
    }

    /// Runs `f` with the display cleared from the terminal, then redraws it: for printing
    /// to stdout (a table row) while a display is on stderr, without tearing it.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        self.bar.suspend(f)
    }

    /// Removes the display from the terminal (the work is done or abandoned).
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

fn stderr_is_terminal() -> bool {
    std::io::stderr().is_terminal()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hidden_progress_counts_without_drawing() {
        // Off a terminal (CI, a pipe) every constructor gives a hidden display whose
        // counting is still well defined.
        let p = Progress::bar(10, "work", "steps");
        p.inc(3);
        p.finish();
        assert!(Progress::hidden().is_hidden());
        if !stderr_is_terminal() {
            assert!(p.is_hidden());
            assert!(Progress::spinner("x").is_hidden());
        }
    }
}
