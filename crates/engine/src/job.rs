//! A run on another thread as its caller follows it ([`Job`]): the Python
//! module's runs and the explorer's zooms are each one.

use grid::{Begin, Observer};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// A run on another thread as its caller follows it: the cells done of the
/// total (the job is the run's [`Observer`]), a request to stop it, the
/// seconds it has computed, and, once it has ended, its outcome `T` (what the
/// caller makes of the run's result or error).
#[derive(Debug)]
pub struct Job<T> {
    done: AtomicU64,
    total: AtomicU64,
    cancel: AtomicBool,
    /// When it started computing (not while it waited its turn), and its
    /// seconds once ended.
    clock: Mutex<(Option<Instant>, Option<f64>)>,
    outcome: Mutex<Option<T>>,
    ended: Condvar,
}

impl<T> Default for Job<T> {
    fn default() -> Job<T> {
        Job {
            done: AtomicU64::new(0),
            total: AtomicU64::new(0),
            cancel: AtomicBool::new(false),
            clock: Mutex::new((None, None)),
            outcome: Mutex::new(None),
            ended: Condvar::new(),
        }
    }
}

impl<T: Clone> Job<T> {
    /// A job not yet begun.
    pub fn new() -> Job<T> {
        Job::default()
    }

    /// `(done, total)` cells (a total of 0 when not yet known).
    pub fn progress(&self) -> (u64, u64) {
        (self.done.load(Ordering::Relaxed), self.total.load(Ordering::Relaxed))
    }

    /// Asks the run to stop before its next cell ([`Observer::cancelled`]).
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// Marks the start of its computation.
    pub fn start_clock(&self) {
        lock(&self.clock).0 = Some(Instant::now());
    }

    /// Seconds it has computed: all of them once ended, 0 before its clock
    /// starts.
    pub fn seconds(&self) -> f64 {
        match *lock(&self.clock) {
            (_, Some(s)) => s,
            (Some(t0), None) => t0.elapsed().as_secs_f64(),
            (None, None) => 0.0,
        }
    }

    /// Ends it with `outcome`: its clock stops, and every caller waiting
    /// ([`Job::wait`]) wakes.
    pub fn end(&self, outcome: T) {
        {
            let mut clock = lock(&self.clock);
            clock.1 = Some(clock.0.map_or(0.0, |t0| t0.elapsed().as_secs_f64()));
        }
        *lock(&self.outcome) = Some(outcome);
        self.ended.notify_all();
    }

    /// Its outcome, once it has ended.
    pub fn outcome(&self) -> Option<T> {
        lock(&self.outcome).clone()
    }

    /// Waits until it ends, at most `timeout` (forever when `None`);
    /// whether it has ended.
    pub fn wait(&self, timeout: Option<Duration>) -> bool {
        let guard = lock(&self.outcome);
        let running = |o: &mut Option<T>| o.is_none();
        match timeout {
            Some(t) => self.ended.wait_timeout_while(guard, t, running).map_or(true, |(g, _)| g.is_some()),
            None => self.ended.wait_while(guard, running).map_or(true, |g| g.is_some()),
        }
    }
}

impl<T: Send> Observer for Job<T> {
    fn begin(&self, work: &Begin<'_>) {
        self.total.store(work.total, Ordering::Relaxed);
        self.done.store(work.done, Ordering::Relaxed);
    }
    fn advance(&self, cells: u64) {
        self.done.fetch_add(cells, Ordering::Relaxed);
    }
    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}

/// A lock, whether or not a thread panicked holding it (what it guards is
/// replaced whole, never left half-changed).
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    /// A job counts what its run reports, stops it when asked, and wakes
    /// its waiter with the outcome; a wait that times out says so.
    #[test]
    fn a_job_follows_its_run() {
        let job = Arc::new(Job::<u32>::new());
        job.begin(&Begin { total: 10, done: 2, lines: &[], prior: None, line_len: 1, threads: 1 });
        job.advance(3);
        assert_eq!(job.progress(), (5, 10));
        assert!(!job.cancelled() && !job.wait(Some(Duration::from_millis(1))) && job.seconds() == 0.0);
        job.cancel();
        assert!(job.cancelled());
        job.start_clock();
        let theirs = Arc::clone(&job);
        let run = std::thread::spawn(move || theirs.end(7));
        assert!(job.wait(None));
        run.join().unwrap();
        assert_eq!(job.outcome(), Some(7));
        let seconds = job.seconds();
        assert!(seconds >= 0.0 && seconds.to_bits() == job.seconds().to_bits(), "its clock stopped");
    }
}
