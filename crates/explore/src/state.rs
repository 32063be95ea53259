//! What the explorer holds: the atlases it shows (the file it was given,
//! then every zoom's child, each with its parent) and the zooms running in
//! the background, each an [`engine::Observer`] that counts its cells and
//! may be cancelled.

use grid::Atlas;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc::{sync_channel, SyncSender, TrySendError};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// Most zooms waiting for the zoom worker; one more is refused (503).
pub(crate) const ZOOM_QUEUE: usize = 8;
/// Most requests computing or waiting for a blocking thread (cells, figures,
/// files); one more is refused (503).
pub(crate) const BUSY_LIMIT: usize = 32;
/// How long stopping waits for running work to end before it leaves it.
pub(crate) const STOP_WAIT: Duration = Duration::from_millis(1200);

/// The cell last clicked in the page (the last `/api/cell` answered): what
/// `cell --from FILE --sweep SWEEP --at NAME=VALUE,…` runs again.
#[derive(Debug, Clone, PartialEq)]
pub struct Selected {
    /// The atlas file the cell is stored in (a zoom's child is a temporary
    /// file of the explorer, removed when it stops).
    pub file: PathBuf,
    /// The sweep clicked (`up`, `down`, `fresh`).
    pub sweep: String,
    /// The plane's parameter values as the page gave them.
    pub at: Vec<(String, f64)>,
}

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
    /// The CRC-32 of the file's bytes when read: a file edited in place
    /// (its size, inode and time kept) is refused, not served.
    pub bytes_crc32: Option<u32>,
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
        let bytes_crc32 = std::fs::read(&path).ok().map(|b| crc32fast::hash(&b));
        Opened { labels_crc32: store::labels_crc32(&atlas), path, atlas, parent, boxes, identity, bytes_crc32 }
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

/// A zoom running in the background: its outcome is where it ended.
pub(crate) type Job = engine::Job<Phase>;

/// Where zoom `job` is: [`Phase::Running`] until it ends.
pub(crate) fn phase(job: &Job) -> Phase {
    job.outcome().unwrap_or(Phase::Running)
}

/// The share of zoom `job`'s cells done, 0 to 1 (1 once done).
pub(crate) fn share(job: &Job) -> f64 {
    match (phase(job), job.progress()) {
        (Phase::Done(_), _) => 1.0,
        (_, (_, 0)) => 0.0,
        (_, (done, total)) => (done as f64 / total as f64).min(1.0),
    }
}

/// Asks zoom `job` to stop (it ends within a cell per worker, leaving
/// nothing); whether it was running.
pub(crate) fn stop(job: &Job) -> bool {
    job.cancel();
    phase(job) == Phase::Running
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

/// A zoom for the worker.
type Task = Box<dyn FnOnce() + Send>;

/// The one thread that runs zooms, one after the other (each on every
/// worker thread of the engine), fed by a queue of [`ZOOM_QUEUE`].
pub(crate) struct Worker {
    queue: Mutex<Option<SyncSender<Task>>>,
}

/// Why a zoom was not queued.
pub(crate) enum NotQueued {
    /// The queue is full.
    Full,
    /// The server is stopping.
    Stopped,
}

impl Worker {
    /// The worker, started (an error when the OS gives no thread).
    fn start() -> std::io::Result<Worker> {
        let (tx, rx) = sync_channel::<Task>(ZOOM_QUEUE);
        std::thread::Builder::new().name("explore-zoom".into()).spawn(move || {
            for task in rx {
                task();
            }
        })?;
        Ok(Worker { queue: Mutex::new(Some(tx)) })
    }

    /// Queues a zoom.
    pub fn submit(&self, task: Task) -> Result<(), NotQueued> {
        let queue = lock(&self.queue);
        let tx = queue.as_ref().ok_or(NotQueued::Stopped)?;
        tx.try_send(task).map_err(|e| match e {
            TrySendError::Full(_) => NotQueued::Full,
            TrySendError::Disconnected(_) => NotQueued::Stopped,
        })
    }

    /// Takes no more zooms; the thread ends once the queued ones have (each
    /// cancelled, they end at once).
    fn close(&self) {
        lock(&self.queue).take();
    }
}

/// Everything the server holds.
pub(crate) struct State {
    atlases: Mutex<Vec<Arc<Opened>>>,
    jobs: Mutex<Vec<Arc<Job>>>,
    /// The zooms' thread.
    pub zooms: Worker,
    /// Requests computing on, or waiting for, a blocking thread.
    pub busy: AtomicUsize,
    /// Set when the server stops: long requests end at once.
    pub stopping: AtomicBool,
    /// The bifurcation curves stored in the explored file (checked when it
    /// was opened).
    curves: Vec<store::Curve>,
    /// The private folder of the zooms' files, made at the first zoom
    /// ([`State::zoom_dir`]) and removed when the server stops.
    dir: Mutex<Option<tempfile::TempDir>>,
    /// Worker threads of a zoom or an attractor search.
    pub threads: usize,
    /// The cell last clicked.
    selected: Mutex<Option<Selected>>,
}

impl State {
    /// The state of an explorer of `atlas` and its `curves`, read from
    /// `path` (an error when the zooms' thread cannot be had).
    pub fn new(path: PathBuf, atlas: Atlas, curves: Vec<store::Curve>, threads: usize) -> std::io::Result<State> {
        Ok(State {
            atlases: Mutex::new(vec![Arc::new(Opened::new(path, atlas, None))]),
            jobs: Mutex::new(Vec::new()),
            zooms: Worker::start()?,
            busy: AtomicUsize::new(0),
            stopping: AtomicBool::new(false),
            curves,
            dir: Mutex::new(None),
            threads,
            selected: Mutex::new(None),
        })
    }

    /// Records the cell clicked.
    pub fn select(&self, cell: Selected) {
        *lock(&self.selected) = Some(cell);
    }

    /// The cell last clicked, if any.
    pub fn selected(&self) -> Option<Selected> {
        lock(&self.selected).clone()
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
    /// none).
    pub fn curves(&self) -> &[store::Curve] {
        &self.curves
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

    /// Cancels every job, takes no more, and waits for them to end (each
    /// within a cell per worker) for at most [`STOP_WAIT`].
    pub fn cancel_all(&self) {
        self.stopping.store(true, Ordering::Relaxed);
        self.zooms.close();
        let jobs: Vec<Arc<Job>> = lock(&self.jobs).clone();
        jobs.iter().for_each(|j| {
            j.cancel();
        });
        let until = Instant::now() + STOP_WAIT;
        while jobs.iter().any(|j| phase(j) == Phase::Running) && Instant::now() < until {
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// The folder of the zooms' files: made at the first call, under the
    /// system's temporary folder with a name no one can guess, readable by
    /// its user alone, and never one that was there before (a predictable
    /// name let another user plant a link that led the zooms' files into a
    /// folder the user never named).
    pub fn zoom_dir(&self) -> std::io::Result<PathBuf> {
        let mut dir = lock(&self.dir);
        if let Some(made) = dir.as_ref() {
            return Ok(made.path().to_path_buf());
        }
        let mut b = tempfile::Builder::new();
        #[cfg(unix)]
        b.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o700));
        Ok(dir.insert(b.prefix("vibroatlas-explore-").tempdir()?).path().to_path_buf())
    }

    /// Removes the zooms' files (the user saved what they keep).
    pub fn remove_files(&self) {
        if let Some(dir) = lock(&self.dir).take() {
            let _ = dir.close();
        }
    }
}
