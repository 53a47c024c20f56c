//! Ctrl-C in long calls: the work runs off the calling thread, which, the GIL released, checks
//! for signals every [`SIGNAL_POLL`] (Python runs signal handlers on the main thread alone) and
//! tells the work to stop when a handler raises. The work stops at its next check and the
//! handler's exception (`KeyboardInterrupt`) is raised in place of a result.

use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::time::Duration;

/// How often the calling thread checks for signals while work runs elsewhere.
pub const SIGNAL_POLL: Duration = Duration::from_millis(20);

/// Runs `work` on rayon's pool while the calling thread, the GIL released, checks for signals
/// every [`SIGNAL_POLL`]: when a handler raises, `stop` is set for `work` to see, and the
/// exception is returned once `work` has wound down. On one of the pool's own threads (a call
/// from a table build's progress callback) `work` just runs.
pub fn interruptible(stop: &AtomicBool, work: impl FnOnce() + Send) -> PyResult<()> {
    if rayon::current_thread_index().is_some() {
        work();
        return Ok(());
    }
    let (done, finished) = channel::<()>();
    rayon::in_place_scope(|scope| {
        scope.spawn(move |_| {
            work();
            drop(done);
        });
        poll_signals(&finished, stop)
    })
}

/// Runs `work` on a thread of its own (its parallel parts on rayon's pool) while the calling
/// thread, the GIL released, checks for signals every [`SIGNAL_POLL`]. When a handler raises,
/// the flag `work` is given is set: `work` hands it to the library as a progress's
/// cancellation (the flag itself, or [`woven::progress::Until`] to keep reporting), the library
/// stops within a unit of its work (a table row, a render tile, a step of a fit), and the
/// exception is raised once `work` has returned, whatever it returned. A panic in `work` is resumed here.
pub fn until_interrupted<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> T + Send,
) -> PyResult<T> {
    let stop = AtomicBool::new(false);
    py.detach(|| {
        std::thread::scope(|scope| {
            let (done, finished) = channel::<()>();
            let stop = &stop;
            let worker = scope.spawn(move || {
                let _done = done; // dropped when `work` returns or unwinds
                work(stop)
            });
            let raised = poll_signals(&finished, stop);
            let out = worker
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            raised.map(|()| out)
        })
    })
}

/// Checks for signals every [`SIGNAL_POLL`] until the work's end is heard on `finished` (its
/// sender dropped): the first exception a handler raises sets `stop` and is returned once the
/// work has ended; later polls only wait.
fn poll_signals(finished: &Receiver<()>, stop: &AtomicBool) -> PyResult<()> {
    let mut raised = Ok(());
    while let Err(RecvTimeoutError::Timeout) = finished.recv_timeout(SIGNAL_POLL) {
        if raised.is_ok() {
            raised = Python::attach(|py| py.check_signals());
            stop.store(raised.is_err(), Ordering::Relaxed);
        }
    }
    raised
}
