//! What long computations (table builds, accuracy reports, exports, renders) report their
//! progress to, and ask whether to stop.
//!
//! Any `Fn(done, total) + Sync` closure is a [`Progress`] that never asks to stop, so a caller
//! that only wants a bar passes a closure. A front end that can be interrupted (Python's
//! Ctrl-C, a server whose client has gone) answers [`Progress::cancelled`] too: a bare stop flag
//! (`AtomicBool`), or [`Until`] to keep reporting.

use std::sync::atomic::{AtomicBool, Ordering};

/// Where a long computation reports `(done, total)` units of work, and asks, between units,
/// whether to stop.
///
/// `update` is called from worker threads, and calls may arrive out of order: keep the largest
/// `done`. A computation that sees [`cancelled`](Progress::cancelled) return `true` winds down
/// and returns [`Error::Cancelled`](crate::Error::Cancelled), never a partial result.
pub trait Progress<N = usize>: Sync {
    /// `done` of `total` units of work are finished.
    fn update(&self, done: N, total: N);

    /// Whether the work should stop; asked between units of work (a table row, a render tile).
    fn cancelled(&self) -> bool {
        false
    }
}

impl<N, F: Fn(N, N) + Sync> Progress<N> for F {
    fn update(&self, done: N, total: N) {
        self(done, total)
    }
}

/// A stop flag alone: reports nowhere, and is cancelled once set.
impl<N> Progress<N> for AtomicBool {
    fn update(&self, _: N, _: N) {}

    fn cancelled(&self) -> bool {
        self.load(Ordering::Relaxed)
    }
}

/// `progress`, cancelled as well once `stop` is set: how a caller that watches for an
/// interruption on its own thread tells work running on others to stop.
pub struct Until<'a, P: ?Sized> {
    /// Where the updates go, and whose own cancellation still counts.
    pub progress: &'a P,
    /// Set to stop the work.
    pub stop: &'a AtomicBool,
}

impl<N, P: Progress<N> + ?Sized> Progress<N> for Until<'_, P> {
    fn update(&self, done: N, total: N) {
        self.progress.update(done, total)
    }

    fn cancelled(&self) -> bool {
        self.stop.load(Ordering::Relaxed) || self.progress.cancelled()
    }
}

/// A [`Progress`] of two closures: `update(done, total)` and `cancelled()`.
pub struct Hooks<U, C> {
    /// Hears `(done, total)`.
    pub update: U,
    /// Answers whether to stop.
    pub cancelled: C,
}

impl<N, U: Fn(N, N) + Sync, C: Fn() -> bool + Sync> Progress<N> for Hooks<U, C> {
    fn update(&self, done: N, total: N) {
        (self.update)(done, total)
    }

    fn cancelled(&self) -> bool {
        (self.cancelled)()
    }
}

/// One of `of` equal shares of a larger computation (the `index`-th, from 0), reporting to
/// `progress` as a part of the whole: `(done, total)` of this share is heard as
/// `(index · total + done, of · total)`. Its cancellation is `progress`'s.
pub struct Share<'a, P: ?Sized> {
    /// The whole computation's progress.
    pub progress: &'a P,
    /// Which share this is, from 0.
    pub index: usize,
    /// How many shares the whole has.
    pub of: usize,
}

impl<P: Progress + ?Sized> Progress for Share<'_, P> {
    fn update(&self, done: usize, total: usize) {
        self.progress
            .update(self.index * total + done, self.of * total)
    }

    fn cancelled(&self) -> bool {
        self.progress.cancelled()
    }
}

/// `progress`'s cancellation alone: updates sent here are dropped (a last step whose bar the
/// caller has already ended).
pub struct Silent<'a, P: ?Sized>(pub &'a P);

impl<P: Progress + ?Sized> Progress for Silent<'_, P> {
    fn update(&self, _: usize, _: usize) {}

    fn cancelled(&self) -> bool {
        self.0.cancelled()
    }
}

/// A [`Progress`] that reports nowhere and never stops.
pub const NONE: &dyn Progress<usize> = &|_: usize, _: usize| {};

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    #[test]
    fn a_closure_reports_and_never_stops() {
        let seen = AtomicUsize::new(0);
        let p = |d: usize, _: usize| {
            seen.fetch_max(d, Ordering::Relaxed);
        };
        let progress: &dyn Progress = &p;
        progress.update(3, 10);
        progress.update(2, 10);
        assert_eq!(seen.load(Ordering::Relaxed), 3);
        assert!(!progress.cancelled());
    }

    #[test]
    fn until_stops_once_its_flag_is_set_and_forwards_updates() {
        let seen = AtomicUsize::new(0);
        let p = |d: usize, _: usize| {
            seen.store(d, Ordering::Relaxed);
        };
        let stop = AtomicBool::new(false);
        let until = Until {
            progress: &p,
            stop: &stop,
        };
        until.update(5, 9);
        assert_eq!(seen.load(Ordering::Relaxed), 5);
        assert!(!until.cancelled());
        stop.store(true, Ordering::Relaxed);
        assert!(until.cancelled());
        // An inner progress that asks to stop is heard through the adapter too.
        let never = AtomicBool::new(false);
        let outer = Until {
            progress: &until,
            stop: &never,
        };
        assert!(Progress::<usize>::cancelled(&outer));
    }

    #[test]
    fn a_stop_flag_is_a_silent_progress_cancelled_once_set() {
        let stop = AtomicBool::new(false);
        let progress: &dyn Progress<u64> = &stop;
        progress.update(1, 2);
        assert!(!progress.cancelled());
        stop.store(true, Ordering::Relaxed);
        assert!(progress.cancelled());
    }

    #[test]
    fn a_share_reports_its_part_of_the_whole_and_hears_a_stop() {
        let seen = std::sync::Mutex::new(Vec::new());
        let p = |d: usize, t: usize| seen.lock().unwrap().push((d, t));
        let stop = AtomicBool::new(false);
        let until = Until {
            progress: &p,
            stop: &stop,
        };
        let second = Share {
            progress: &until,
            index: 1,
            of: 2,
        };
        second.update(3, 10);
        assert_eq!(*seen.lock().unwrap(), [(13, 20)]);
        assert!(!second.cancelled());
        stop.store(true, Ordering::Relaxed);
        assert!(second.cancelled());
    }
}
