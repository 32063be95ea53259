//! What the explorer holds: the atlases it shows (the file it was given,
//! then every zoom's child, each with its parent) and the zooms running in
//! the background, each an [`engine::Observer`] that counts its cells and
//! may be cancelled.

use grid::Atlas;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

/// An atlas the page can show.
pub(crate) struct Opened {
    /// Its file.
    pub path: PathBuf,
    /// Its cells.
    pub atlas: Atlas,
    /// The atlas it is a box of, and the box (`omega=… delta=…`).
    pub parent: Option<(usize, String)>,
    /// The boxes from the explored file to it, in order (empty for the file).
    pub boxes: Vec<String>,
    /// The CRC-32 of its labels (`store::labels_crc32`).
    pub labels_crc32: u32,
    /// The file as it was when read: a rewritten file is refused, not read.
    pub identity: Option<Identity>,
}

/// What tells a file from the one that replaces it: device, inode, length,
/// modification time.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Identity(u64, u64, u64, Option<std::time::SystemTime>);

impl Identity {
    /// The identity of the file at `path` now (`None` when it cannot be read).
    pub fn of(path: &std::path::Path) -> Option<Identity> {
        use std::os::unix::fs::MetadataExt;
        let m = std::fs::metadata(path).ok()?;
        Some(Identity(m.dev(), m.ino(), m.len(), m.modified().ok()))
    }
}

impl Opened {
    /// An atlas read from `path`, now: the file explored, or the box
    /// `region` of atlas `parent` (with its own `boxes` from the file).
    pub fn new(path: PathBuf, atlas: Atlas, parent: Option<(usize, &Opened, String)>) -> Opened {
        let identity = Identity::of(&path);
        let (parent, boxes) = match parent {
            None => (None, Vec::new()),
            Some((id, of, region)) => {
                let mut boxes = of.boxes.clone();
                boxes.push(region.clone());
                (Some((id, region)), boxes)
            }
        };
        Opened { labels_crc32: store::labels_crc32(&atlas), path, atlas, parent, boxes, identity }
    }

    /// Whether its file is still the one read.
    pub fn unchanged(&self) -> bool {
        self.identity.is_some() && Identity::of(&self.path) == self.identity
    }
}

/// Where a zoom is.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Phase {
    /// Computing.
    Running,
    /// Done: the child's atlas id.
    Done(usize),
    /// Refused or failed, with the message.
    Failed(String),
    /// Cancelled: nothing left behind.
    Cancelled,
}

impl Phase {
    /// `running`, `done`, `failed` or `cancelled`.
    pub fn name(&self) -> &'static str {
        match self {
            Phase::Running => "running",
            Phase::Done(_) => "done",
            Phase::Failed(_) => "failed",
            Phase::Cancelled => "cancelled",
        }
    }
}

/// A zoom running in the background.
pub(crate) struct Job {
    total: AtomicU64,
    done: AtomicU64,
    cancel: AtomicBool,
    phase: Mutex<Phase>,
}

impl Job {
    fn new() -> Job {
        Job {
            total: AtomicU64::new(0),
            done: AtomicU64::new(0),
            cancel: AtomicBool::new(false),
            phase: Mutex::new(Phase::Running),
        }
    }

    /// The share of its cells done, 0 to 1.
    pub fn progress(&self) -> f64 {
        let total = self.total.load(Ordering::Relaxed);
        match self.phase() {
            Phase::Done(_) => 1.0,
            _ if total == 0 => 0.0,
            _ => (self.done.load(Ordering::Relaxed) as f64 / total as f64).min(1.0),
        }
    }

    /// Its phase.
    pub fn phase(&self) -> Phase {
        lock(&self.phase).clone()
    }

    /// Asks it to stop (it ends within a cell per worker, leaving nothing);
    /// whether it was running.
    pub fn cancel(&self) -> bool {
        self.cancel.store(true, Ordering::Relaxed);
        self.phase() == Phase::Running
    }

    /// Sets where it ended.
    pub fn end(&self, phase: Phase) {
        *lock(&self.phase) = phase;
    }
}

impl engine::Observer for Job {
    fn begin(&self, work: &engine::Begin<'_>) {
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

/// A request's long work (an attractor search), stopped when its client
/// goes away (the guard of its handler is dropped) or the server stops.
pub(crate) struct Request {
    gone: Arc<AtomicBool>,
    state: Arc<State>,
}

/// Held by a request's handler: dropped (the client went away, or the
/// answer was sent), it stops the request's work.
pub(crate) struct Guard(Arc<AtomicBool>);

impl Drop for Guard {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

impl Request {
    /// The work of a request of `state`, and the guard its handler holds.
    pub fn new(state: Arc<State>) -> (Request, Guard) {
        let gone = Arc::new(AtomicBool::new(false));
        (Request { gone: gone.clone(), state }, Guard(gone))
    }
}

impl engine::Observer for Request {
    fn cancelled(&self) -> bool {
        self.gone.load(Ordering::Relaxed) || self.state.stopping.load(Ordering::Relaxed)
    }
}

/// A lock, whether or not a thread panicked holding it (what it guards
/// is replaced whole, never left half-changed).
pub(crate) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// Everything the server holds.
pub(crate) struct State {
    atlases: Mutex<Vec<Arc<Opened>>>,
    jobs: Mutex<Vec<Arc<Job>>>,
    /// Held by the zoom that computes: zooms run one after the other, each
    /// on every worker thread.
    pub zoom_slot: Mutex<()>,
    /// Set when the server stops: long requests end at once.
    pub stopping: AtomicBool,
    /// The bifurcation curves stored in the explored file, read once asked for.
    curves: std::sync::OnceLock<Vec<store::Curve>>,
    /// The folder of the zooms' files (removed when the server stops).
    pub dir: PathBuf,
    /// Worker threads of a zoom or an attractor search.
    pub threads: usize,
}

impl State {
    /// The state of an explorer of `atlas`, read from `path`.
    pub fn new(path: PathBuf, atlas: Atlas, threads: usize) -> State {
        static SERVERS: AtomicU64 = AtomicU64::new(0);
        let n = SERVERS.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("vibroatlas-explore-{}-{n}", std::process::id()));
        State {
            atlases: Mutex::new(vec![Arc::new(Opened::new(path, atlas, None))]),
            jobs: Mutex::new(Vec::new()),
            zoom_slot: Mutex::new(()),
            stopping: AtomicBool::new(false),
            curves: std::sync::OnceLock::new(),
            dir,
            threads,
        }
    }

    /// Atlas `id`.
    pub fn atlas(&self, id: usize) -> Option<Arc<Opened>> {
        lock(&self.atlases).get(id).cloned()
    }

    /// Adds an atlas; its id.
    pub fn add(&self, opened: Opened) -> usize {
        let mut all = lock(&self.atlases);
        all.push(Arc::new(opened));
        all.len() - 1
    }

    /// The bifurcation curves stored in the explored file (none where it has
    /// none), read on the first call.
    pub fn curves(&self) -> &[store::Curve] {
        self.curves.get_or_init(|| {
            let root = lock(&self.atlases)[0].path.clone();
            store::read_curves(&root).unwrap_or_default()
        })
    }

    /// Starts a job; its id.
    pub fn start_job(&self) -> (usize, Arc<Job>) {
        let mut jobs = lock(&self.jobs);
        let job = Arc::new(Job::new());
        jobs.push(job.clone());
        (jobs.len() - 1, job)
    }

    /// Job `id`.
    pub fn job(&self, id: usize) -> Option<Arc<Job>> {
        lock(&self.jobs).get(id).cloned()
    }

    /// Cancels every running job and waits for them to end (each within a
    /// cell per worker; at most a minute).
    pub fn cancel_all(&self) {
        self.stopping.store(true, Ordering::Relaxed);
        let jobs: Vec<Arc<Job>> = lock(&self.jobs).clone();
        jobs.iter().for_each(|j| {
            j.cancel();
        });
        let until = std::time::Instant::now() + std::time::Duration::from_secs(60);
        while jobs.iter().any(|j| j.phase() == Phase::Running) && std::time::Instant::now() < until {
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
    }

    /// Removes the zooms' files (the user saved what they keep).
    pub fn remove_files(&self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}
