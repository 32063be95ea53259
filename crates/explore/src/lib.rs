//! The interactive atlas (`vibroatlas explore`, `va.explore`): a local web
//! page over an atlas file, on 127.0.0.1 only. The page is a thin client of
//! the engine: every colour, legend, cell, zoom and figure comes from the
//! libraries through its JSON API (`api.rs`, its queries and answers in
//! `wire.rs`; docs/explore.md), which a
//! script may call as well.
//!
//! | route | what |
//! |---|---|
//! | `GET /` | the page (and its two assets, served from the binary) |
//! | `GET /api/atlas` | grid, axes with symbols, sweeps, masses, views, label tables with colours |
//! | `GET /api/map`, `/api/legend` | a view's colours per cell (bytes), its legend rows |
//! | `GET /api/at` | one cell's stored labels, class and reason (its text, and `reason_detail` with its numbers) in every sweep (hover) |
//! | `GET /api/cell` | the object of `cell --from FILE --sweep S --at … --json` |
//! | `GET /api/orbit` | the object of `orbit --from FILE --sweep S --at … --json` (Floquet multipliers) |
//! | `GET /api/cell/portrait.png`, `/api/cell/sections.png` | the cell's pictures |
//! | `GET /api/attractors` | the coexisting attractors of the cell's parameters |
//! | `GET /api/basins/plan`, `/api/basins` | a basin map proposed for the cell (axes, estimated time); the basins over a grid of its states |
//! | `GET /api/zoom/plan` | a zoom's estimated time, timed on a 3 × 3 zoom of the box |
//! | `POST /api/zoom`, `GET`/`DELETE /api/jobs/ID` | a zoom in the background, its progress, its cancel |
//! | `GET /api/figure` | a view drawn by `render` (PNG, SVG, PDF; print sizes) |
//! | `GET /api/curves`, `/api/files/ID` | stored bifurcation curves; an atlas's file |
#![deny(missing_docs)]

mod api;
mod guard;
mod head;
mod state;
mod wire;

pub use state::Selected;
use state::State;
use std::net::{Ipv4Addr, SocketAddr, TcpListener};
use std::path::PathBuf;
use std::sync::Arc;

/// What to explore.
#[derive(Debug, Clone)]
pub struct ExploreRequest {
    /// The atlas file.
    pub file: PathBuf,
    /// The port on 127.0.0.1 (0: a free one).
    pub port: u16,
    /// Worker threads of the zooms and attractor searches.
    pub threads: usize,
}

/// Why the explorer could not start.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExploreError {
    /// The file is not an atlas, or is damaged.
    #[error(transparent)]
    Atlas(#[from] store::StoreError),
    /// The file is one shard of an atlas.
    #[error("{file}: shard {shard} of an atlas, whose other lines are missing; explore the merged atlas")]
    Shard {
        /// The file.
        file: String,
        /// Its shard.
        shard: grid::Shard,
    },
    /// The port cannot be listened on (in use, or not allowed).
    #[error("port {port} on 127.0.0.1 cannot be listened on")]
    Port {
        /// The port asked for.
        port: u16,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The server's threads could not start.
    #[error("cannot start the server: {0}")]
    Start(#[source] std::io::Error),
}

/// A running explorer: its URL, until [`Server::stop`] (or drop).
pub struct Server {
    url: String,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    thread: Option<std::thread::JoinHandle<()>>,
    state: Arc<State>,
}

impl Server {
    /// The page's address, `http://127.0.0.1:PORT/`.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// The cell last clicked in the page, if any (what `cell --from` runs
    /// again).
    pub fn selected(&self) -> Option<Selected> {
        self.state.selected()
    }

    /// Stops serving: running zooms are cancelled (they leave no file) and
    /// the zooms' files are removed.
    pub fn stop(mut self) {
        self.shutdown();
    }

    fn shutdown(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        self.state.cancel_all();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
        self.state.remove_files();
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.shutdown();
    }
}

/// Most threads computing the page's requests at once.
const BLOCKING: usize = 8;

/// Opens the atlas (checked whole, as `inspect --verify` checks it) and
/// serves its page on 127.0.0.1.
pub fn serve(r: &ExploreRequest) -> Result<Server, ExploreError> {
    let loaded = store::read(&r.file)?;
    store::check_finished(&r.file, &loaded)?;
    if let Some(shard) = loaded.info.shard.filter(|s| !s.is_whole()) {
        return Err(ExploreError::Shard { file: r.file.display().to_string(), shard });
    }
    let listener = TcpListener::bind(SocketAddr::from((Ipv4Addr::LOCALHOST, r.port)))
        .map_err(|source| ExploreError::Port { port: r.port, source })?;
    let port = listener.local_addr().map_err(ExploreError::Start)?.port();
    listener.set_nonblocking(true).map_err(ExploreError::Start)?;
    // Curves stored in the atlas are checked now, as the rest of the file.
    let curves = match store::read_curves(&r.file) {
        Err(store::StoreError::Kind { found: store::OtherKind::NoCurves, .. }) => Vec::new(),
        read => read?,
    };
    let state = Arc::new(State::new(r.file.clone(), loaded.atlas, curves, r.threads).map_err(ExploreError::Start)?);
    // A bounded pool: two threads serve, at most BLOCKING compute (cells,
    // figures, files; more wait, up to state::BUSY_LIMIT).
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .max_blocking_threads(BLOCKING)
        .enable_io()
        .enable_time()
        .build()
        .map_err(ExploreError::Start)?;
    let (tx, rx) = tokio::sync::oneshot::channel::<()>();
    let app = api::router(state.clone(), port);
    let thread = std::thread::Builder::new()
        .name("explore".into())
        .spawn(move || {
            runtime.block_on(async move {
                let Ok(listener) = tokio::net::TcpListener::from_std(listener) else { return };
                let Ok(listener) = head::screened(listener) else { return };
                let (stopping, stopped) = tokio::sync::watch::channel(false);
                let serving = axum::serve(listener, app).with_graceful_shutdown({
                    let mut stopped = stopped.clone();
                    async move {
                        let _ = stopped.changed().await;
                    }
                });
                // Stopped, the server lets open requests finish for at most
                // state::STOP_WAIT, then leaves them.
                let give_up = {
                    let mut stopped = stopped;
                    async move {
                        let _ = stopped.changed().await;
                        tokio::time::sleep(state::STOP_WAIT).await;
                    }
                };
                tokio::spawn(async move {
                    let _ = rx.await;
                    let _ = stopping.send(true);
                });
                tokio::select! {
                    _ = serving => {}
                    _ = give_up => {}
                }
            });
            runtime.shutdown_timeout(state::STOP_WAIT);
        })
        .map_err(ExploreError::Start)?;
    Ok(Server { url: format!("http://127.0.0.1:{port}/"), stop: Some(tx), thread: Some(thread), state })
}
