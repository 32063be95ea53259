//! Ctrl-C (SIGINT), SIGTERM and SIGHUP (the terminal closed) for the
//! commands that end cleanly on them (`explore`, `zoom`, `study`): the signal only
//! sets a flag, which the command polls or its observer reports as a cancel.

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

extern "C" fn on_signal(_: libc::c_int) {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// Routes SIGINT, SIGTERM and SIGHUP to the flag (instead of ending the process).
pub fn install() {
    // SAFETY: sets the disposition of three signals to a handler that only
    // stores to an atomic.
    unsafe {
        for signal in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            libc::signal(signal, on_signal as *const () as libc::sighandler_t);
        }
    }
}

/// Whether a signal came.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// An observer that also stops when a signal came.
pub struct Stoppable<O>(pub O);

impl<O: engine::Observer> engine::Observer for Stoppable<O> {
    fn begin(&self, work: &engine::Begin<'_>) {
        self.0.begin(work);
    }
    fn advance(&self, cells: u64) {
        self.0.advance(cells);
    }
    fn line_done(&self, job: usize) {
        self.0.line_done(job);
    }
    fn finish(&self) {
        self.0.finish();
    }
    fn warn(&self, message: &str) {
        self.0.warn(message);
    }
    fn cancelled(&self) -> bool {
        requested() || self.0.cancelled()
    }
}
