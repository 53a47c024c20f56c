//! Progress bars for long jobs, on standard error.
//!
//! A [`Progress`] counts work from any thread (it is `Sync`), but draws nothing until the job has
//! run for [`REVEAL_AFTER`] and only when standard error is a terminal: quick jobs, pipelines,
//! redirected runs and tests never see a bar.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// How long a job runs before its bar appears: shorter jobs finish without one.
pub const REVEAL_AFTER: Duration = Duration::from_millis(700);

/// Whether standard error is a terminal (the only place a bar is ever drawn).
pub fn stderr_is_terminal() -> bool {
    std::io::stderr().is_terminal()
}

/// A progress bar that shows itself once a job turns out to be long (see the module docs).
pub struct Progress {
    bar: ProgressBar,
    start: Instant,
    /// Whether the bar may be drawn at all.
    enabled: bool,
    revealed: AtomicBool,
    /// Held while [`set`](Self::set) compares and moves the position, so that a report that
    /// lost a race cannot move the bar back.
    setting: Mutex<()>,
}

impl Progress {
    /// A bar for `total` units of work (`None`: unknown, a counter with a rate) named `what`
    /// ("rows", "directions"). `enabled` says whether it may appear; it never does when standard
    /// error is not a terminal.
    pub fn new(total: Option<u64>, what: &str, enabled: bool) -> Self {
        let template = match total {
            Some(_) => {
                format!("{{bar:40.cyan/blue}} {{pos}}/{{len}} {what}, {{elapsed}} elapsed, ~{{eta}} left")
            }
            None => format!("{{spinner}} {{pos}} {what}, {{elapsed}} elapsed"),
        };
        Self::with_template(total, &template, enabled)
    }

    /// A bar for `total` units named `what` that also shows the rate (units per second), for
    /// jobs whose speed is the figure of merit (a render's samples).
    pub fn with_rate(total: u64, what: &str, enabled: bool) -> Self {
        let template = format!(
            "{{bar:40.cyan/blue}} {{percent:>3}}% {{human_pos}}/{{human_len}} {what}, \
             {{per_sec}}, ~{{eta}} left"
        );
        Self::with_template(Some(total), &template, enabled)
    }

    fn with_template(total: Option<u64>, template: &str, enabled: bool) -> Self {
        let bar = ProgressBar::with_draw_target(total, ProgressDrawTarget::hidden());
        if let Ok(style) = ProgressStyle::with_template(template) {
            bar.set_style(style.progress_chars("##-"));
        }
        Progress {
            bar,
            start: Instant::now(),
            enabled: enabled && stderr_is_terminal(),
            revealed: AtomicBool::new(false),
            setting: Mutex::new(()),
        }
    }

    /// Records `n` more units done (callable from any thread).
    pub fn inc(&self, n: u64) {
        self.bar.inc(n);
        self.reveal_if_long();
    }

    /// Records that `done` of `total` units are done (callable from any thread), for jobs that
    /// count for themselves, such as a table build's `progress(done, total)`. A call reporting less
    /// than the bar shows is ignored: worker threads may report out of order.
    pub fn set(&self, done: u64, total: u64) {
        {
            // A poisoned lock guards nothing but the order of updates: carry on.
            let _order = self.setting.lock().unwrap_or_else(|e| e.into_inner());
            if self.bar.length() != Some(total) {
                self.bar.set_length(total);
            }
            if done > self.bar.position() {
                self.bar.set_position(done);
            }
        }
        self.reveal_if_long();
    }

    /// Draws the bar from now on if the job has run for [`REVEAL_AFTER`] (once, from whichever
    /// thread gets there first).
    fn reveal_if_long(&self) {
        if self.enabled
            && !self.revealed.load(Ordering::Relaxed)
            && self.start.elapsed() >= REVEAL_AFTER
            && self
                .revealed
                .compare_exchange(false, true, Ordering::AcqRel, Ordering::Relaxed)
                .is_ok()
        {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
            self.bar.enable_steady_tick(Duration::from_millis(200));
        }
    }

    /// Units done so far.
    #[cfg(test)]
    pub fn position(&self) -> u64 {
        self.bar.position()
    }

    /// Removes the bar (if it was shown).
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        // An error path must not leave a half-drawn bar on the terminal.
        self.bar.finish_and_clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_from_many_threads_and_stays_hidden_when_disabled() {
        use rayon::prelude::*;
        let p = Progress::new(Some(1000), "rows", false);
        (0..1000).into_par_iter().for_each(|_| p.inc(1));
        assert_eq!(p.position(), 1000);
        assert!(p.bar.is_hidden());
        p.finish();
    }

    /// A render reports `(done, total)` from many threads, out of order; the bar keeps the
    /// largest.
    #[test]
    fn a_rate_bar_counts_reports_from_many_threads() {
        use rayon::prelude::*;
        use std::sync::atomic::AtomicU64;
        let p = Progress::with_rate(640, "samples", false);
        let done = AtomicU64::new(0);
        (0..10).into_par_iter().for_each(|_| {
            let d = done.fetch_add(64, Ordering::Relaxed) + 64;
            p.set(d, 640);
        });
        assert_eq!((p.position(), p.bar.length()), (640, Some(640)));
        assert!(p.bar.is_hidden());
        p.finish();
    }

    #[test]
    fn set_takes_the_total_and_never_goes_back() {
        let p = Progress::new(None, "rows", false);
        p.set(3, 10);
        p.set(2, 10);
        assert_eq!((p.position(), p.bar.length()), (3, Some(10)));
        p.set(10, 10);
        assert_eq!(p.position(), 10);
    }
}
