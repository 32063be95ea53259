//! A validated plan for computing a plane (atlas or sweep) and its execution:
//! journal, one writer thread, atomic HDF5 output, progress reported to an
//! [`Observer`] that may also stop the run.

use crate::error::{chain_text, Opt, RequestError};
use crate::error::{Error, Result};
use crate::sim::Setup;
use grid::{Atlas, CellSetup, Line, Meta, Plane, Shard, SweepKind};
use grid::{Begin, Observer};
use scene::Named;
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;
use store::{fingerprint, journal_path, Journal, RunInfo};

/// Everything a run needs, checked before any work starts.
#[derive(Debug)]
pub struct Plan {
    /// The cells' set-up.
    pub setup: CellSetup,
    /// The run's description (stored in the file).
    pub meta: Meta,
    /// Worker threads.
    pub threads: usize,
    /// This run's shard of the lines, if any.
    pub shard: Option<Shard>,
    /// The file to write (a symbolic link's target), if any.
    pub output: Option<PathBuf>,
    /// Continue from the journal beside the output.
    pub resume: bool,
    /// What made the run (the file's `command` attribute).
    pub command: String,
    /// Files the run reads, never to be overwritten by its output (the scene).
    pub inputs: Vec<PathBuf>,
    /// Estimated cost of each line (see `grid::schedule`), when probed.
    pub cost: Option<Vec<f64>>,
    /// Coexisting attractors to find once the lines are done: the sampling,
    /// and whether only hysteresis cells.
    pub attractors: Option<(grid::attractors::Sampling, bool)>,
    /// The states the continuation chains enter the plane with (a zoom's).
    pub entries: grid::Entries,
    /// The atlas a zoom refines (stored in the file).
    pub parent: Option<store::Parent>,
    /// Whether an interrupted run may be resumed from its journal (an
    /// atlas); a run that cannot (a zoom) removes its journal whenever it
    /// fails, leaving nothing behind.
    pub resumable: bool,
}

/// Worker threads: the option, or every core.
pub fn threads(opt: Option<usize>) -> Result<usize> {
    match opt {
        Some(0) => Err(RequestError::option(Opt::Threads).text("must be >= 1").into()),
        Some(n) if n > 1024 => Err(RequestError::option(Opt::Threads).text(format!("at most 1024, got {n}")).into()),
        Some(n) => Ok(n),
        None => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

/// Bytes one stored cell can take at most.
fn cell_bytes(meta: &Meta) -> u64 {
    let (dim, cap, stops, masses, quantities) = (
        meta.dim as u64,
        meta.section_cap as u64,
        meta.stops.len() as u64,
        meta.masses.len() as u64,
        meta.quantities.len() as u64,
    );
    let (record, label, points) = (
        std::mem::size_of::<grid::CellData>() as u64,
        std::mem::size_of::<solver::Label>() as u64,
        std::mem::size_of::<solver::Points>() as u64,
    );
    // The record + labels + final state + quantities + sections (period: dim
    // values a point, impacts: 1 + dim; one vector each), twice over for the
    // journal line and the file being written.
    let sections = cap * 8 * dim + stops * (points + cap * 8 * (dim + 1));
    2 * (record + label * masses + 8 * dim + 8 * quantities + sections)
}

impl Executed {
    /// The run's file as bytes, written in memory on `threads` threads
    /// ([`store::image`]): what its output holds, or would hold, for a caller
    /// that reads the atlas without a file (Python's `va.atlas` without
    /// `output`).
    pub fn image(&self, threads: usize) -> Result<Vec<u8>> {
        Ok(store::image(&self.atlas, &self.info, threads)?)
    }
}

impl Plan {
    /// Refuses a plane whose results would not fit in memory.
    fn check_memory(&self) -> Result<()> {
        self.check_memory_beside(0, "")
    }

    /// Refuses a plane whose results would not fit in memory beside `held`
    /// bytes that the caller keeps meanwhile (`what`: which, for the message).
    pub fn check_memory_beside(&self, held: u64, what: &str) -> Result<()> {
        // Only the lines of this run's shard are held (shards are balanced by
        // cost: about a share each).
        let p = &self.meta.plane;
        let lines = self.shard.map_or(p.lines(), |s| p.lines().div_ceil(s.n)) as u64;
        let cells = lines.saturating_mul(p.line_len() as u64).saturating_mul(self.meta.sweeps.len() as u64);
        let need = cells.saturating_mul(cell_bytes(&self.meta)).saturating_add(held);
        let have = store::available_memory();
        if need > have / 10 * 8 {
            let why = format!(
                "grid: {} cells x {} sweeps{what} need about {:.1} GiB, more than the {:.1} GiB available; use a coarser grid, more ",
                lines * p.line_len() as u64,
                self.meta.sweeps.len(),
                need as f64 / (1u64 << 30) as f64,
                have as f64 / (1u64 << 30) as f64
            );
            return Err(RequestError::message()
                .text(why)
                .opt(Opt::Shard)
                .text(" parts, or a smaller ")
                .opt(Opt::SectionCap)
                .into());
        }
        Ok(())
    }

    /// Runs the plan, reporting to `observer`; returns the atlas (complete for
    /// this shard) and where the time went. Stopped by the observer
    /// ([`Observer::cancelled`]), it returns [`crate::Error::Cancelled`]
    /// having written no output file and removed its journal.
    pub fn execute(&self, observer: &dyn Observer) -> Result<Executed> {
        let start = Instant::now();
        // Held for the whole run: a second run on the same output is refused.
        let _lock = self.output.as_deref().map(store::OutputLock::acquire).transpose()?;
        if let Some(done) = self.finished_before()? {
            let info = self.info(0.0);
            return Ok(Executed {
                atlas: done,
                info,
                secs: 0.0,
                write_s: 0.0,
                prelude_s: 0.0,
                stream_s: 0.0,
                already: true,
            });
        }
        let ran = self.run(observer, start);
        // A cancelled run is abandoned: its draft took its partial file, its
        // journal goes too (a killed one keeps it, to resume), as does any
        // failed run's that cannot be resumed.
        if let (Err(e), Some(out)) = (&ran, &self.output) {
            if matches!(e, Error::Cancelled) || !self.resumable {
                let _ = std::fs::remove_file(journal_path(out));
            }
        }
        ran
    }

    /// [`Plan::execute`] once the output is locked and not already done.
    fn run(&self, observer: &dyn Observer, start: Instant) -> Result<Executed> {
        let (atlas, journal) = self.open_journal()?;
        let done: Vec<Vec<bool>> = self.meta.sweeps.iter().map(|&s| atlas.lines_done(s)).collect();
        let owns = self.owned();
        let jobs = self.jobs(&done, &owns);
        self.begin(observer, &jobs, &owns);
        let resumed: Vec<(SweepKind, usize)> = self
            .meta
            .sweeps
            .iter()
            .zip(&done)
            .flat_map(|(&s, d)| d.iter().enumerate().filter(|(_, &l)| l).map(move |(l, _)| (s, l)))
            .collect();
        let Kept { mut atlas, journal, draft, prelude_s, stream_s } =
            self.compute(observer, &jobs, atlas, journal, &resumed)?;
        if let Some((sampling, only_hysteresis)) = &self.attractors {
            atlas.attractors = Some(self.find_attractors(&atlas, sampling, *only_hysteresis, &owns, observer)?);
        }
        let elapsed = start.elapsed().as_secs_f64();
        // Asked to stop once the cells were done: nothing is written.
        if observer.cancelled() {
            return Err(crate::Error::Cancelled);
        }
        let mut write_s = 0.0;
        if let (Some(draft), Some(j)) = (draft, journal) {
            let clock = Instant::now();
            self.finish_file(observer, &atlas, draft, j, elapsed)?;
            write_s = clock.elapsed().as_secs_f64();
        }
        Ok(Executed { atlas, info: self.info(elapsed), secs: elapsed, write_s, prelude_s, stream_s, already: false })
    }

    /// What the journal is keyed by: every setting that decides the plan's
    /// lines, in a stable, versioned encoding ([`JournalKey`] as JSON), so
    /// that a journal resumes exactly the run that wrote it.
    fn journal_key(&self) -> String {
        let m = &self.meta;
        let key = JournalKey {
            version: JOURNAL_KEY_VERSION,
            scene: &m.scene_toml,
            overrides: &m.overrides,
            preset: m.preset.name(),
            accuracy: m.accuracy.iter().map(|(k, v)| (k.name(), *v)).collect(),
            integrator: m.integrator.name(),
            x: AxisKey::of(&m.plane.x),
            y: AxisKey::of(&m.plane.y),
            along: m.plane.along.name(),
            sweeps: m.sweeps.iter().map(|s| s.name()).collect(),
            section_cap: m.section_cap,
            shard: self.shard.map(|s| (s.k, s.n)),
            parent: self.parent.as_ref().map(|p| (p.path.as_str(), p.labels_crc32, p.region.as_str())),
            entries: self.entries.0.iter().map(|((s, line), state)| (s.name(), *line, state.as_slice())).collect(),
            quantities: m.quantities.iter().map(|q| q.name.as_str()).collect(),
        };
        // Strings, numbers and sequences only: the encoding cannot fail.
        serde_json::to_string(&key).unwrap_or_default()
    }

    /// The journal beside the output (resumed, or new) and the atlas of the
    /// lines it kept; none without an output.
    fn open_journal(&self) -> Result<(Atlas, Option<Journal>)> {
        let key = fingerprint(&self.journal_key());
        let mut atlas = Atlas::new(self.meta.clone());
        atlas.entries = self.entries.clone();
        let Some(out) = &self.output else { return Ok((atlas, None)) };
        let jp = journal_path(out);
        let (j, lines) = if self.resume {
            Journal::resume(&jp, &key, &self.meta).map_err(journal_advice)?
        } else {
            // Name the file the user asked for; the journal is ours.
            let j =
                Journal::create(&jp, &key).map_err(|e| Error::file(out, "cannot write beside it", Some(e.into())))?;
            (j, Vec::new())
        };
        for l in lines {
            atlas.insert(l);
        }
        Ok((atlas, Some(j)))
    }

    /// The `(sweep, line)` jobs left (`done`: per sweep, the lines kept) of
    /// the lines this run owns, in the order the workers take them: up and
    /// down chains in one pool, the most expensive first where probed (fresh
    /// lines share their cells among the workers: line order is as good).
    fn jobs(&self, done: &[Vec<bool>], owns: &[bool]) -> Vec<(SweepKind, usize)> {
        let mut jobs = Vec::new();
        for line in (0..self.meta.plane.lines()).filter(|&l| owns[l]) {
            for (si, &sweep) in self.meta.sweeps.iter().enumerate() {
                if !done[si][line] {
                    jobs.push((sweep, line));
                }
            }
        }
        match (&self.cost, self.chains()) {
            (Some(cost), true) => grid::schedule::longest_first(&jobs, cost),
            _ => jobs,
        }
    }

    /// Tells the observer the run's work: its cells, those done, and where
    /// probed the jobs' costs (the most expensive come first, so the cells
    /// done are less than their share of the time).
    fn begin(&self, observer: &dyn Observer, jobs: &[(SweepKind, usize)], owns: &[bool]) {
        let plane = &self.meta.plane;
        let owned = owns.iter().filter(|&&o| o).count();
        let total = (owned * plane.line_len() * self.meta.sweeps.len()) as u64;
        let todo = (jobs.len() * plane.line_len()) as u64;
        let lines: Vec<usize> = jobs.iter().map(|j| j.1).collect();
        let prior: Option<Vec<f64>> = self.cost.as_ref().map(|cost| lines.iter().map(|&line| cost[line]).collect());
        observer.begin(&Begin {
            total,
            done: total - todo,
            lines: &lines,
            prior: prior.as_deref(),
            line_len: plane.line_len(),
            threads: self.threads,
        });
    }

    /// Computes the jobs on the workers while one writer thread keeps their
    /// lines. Workers seal their own lines for the journal; the writer
    /// appends whatever has arrived, with one sync per batch, and keeps the
    /// lines. It first creates the output file with all that does not depend
    /// on the results, then writes each chunk of the per-cell datasets once
    /// its lines are kept. A failure of the file is kept for the end: it must
    /// not stop the journal, which keeps the lines for a resume.
    fn compute(
        &self,
        observer: &dyn Observer,
        jobs: &[(SweepKind, usize)],
        atlas: Atlas,
        journal: Option<Journal>,
        resumed: &[(SweepKind, usize)],
    ) -> Result<Kept> {
        let place: std::collections::HashMap<(SweepKind, usize), usize> =
            jobs.iter().enumerate().map(|(i, &job)| (job, i)).collect();
        let sealer = journal.as_ref().map(Journal::sealer);
        let (tx, rx) = std::sync::mpsc::channel::<(Line, Option<store::SealedLine>)>();
        let draft_of = self.output.clone().map(|out| (out, self.meta.clone(), self.threads));
        let resumed = resumed.to_vec();
        let writer = std::thread::spawn(move || keep_lines(atlas, journal, draft_of, &resumed, rx));
        let failed: std::sync::Mutex<Option<Error>> = std::sync::Mutex::new(None);
        let sink = |line: Line| {
            if let Some(&job) = place.get(&(line.sweep, line.index)) {
                observer.line_done(job);
            }
            let sealed = match sealer.as_ref().map(|s| s.seal(&line)).transpose() {
                Ok(s) => s,
                Err(e) => {
                    failed.lock().unwrap_or_else(|p| p.into_inner()).get_or_insert(e.into());
                    None
                }
            };
            // A closed channel means the writer failed; its error is reported below.
            let _ = tx.send((line, sealed));
        };
        let ran = grid::run(&self.meta.plane, &self.setup, jobs, &self.entries, self.threads, observer, &sink);
        drop(tx);
        observer.finish();
        let kept = writer.join().map_err(|_| Error::Internal("the writer thread panicked".into()))??;
        // An error or a cancel drops the draft, which removes its partial file.
        ran?;
        if let Some(e) = failed.into_inner().unwrap_or_else(|p| p.into_inner()) {
            return Err(e);
        }
        Ok(kept)
    }

    /// What the run's file says of the run, `elapsed` seconds long.
    fn info(&self, elapsed: f64) -> RunInfo {
        RunInfo {
            command: self.command.clone(),
            run_time_s: elapsed,
            shard: self.shard,
            history: Vec::new(),
            parent: self.parent.clone(),
        }
    }

    /// Finishes the output file (its rest, after the last line, `elapsed`
    /// seconds into the run) and removes the journal.
    fn finish_file(
        &self,
        observer: &dyn Observer,
        atlas: &Atlas,
        draft: Result<store::Draft, store::StoreError>,
        journal: Journal,
        elapsed: f64,
    ) -> Result<()> {
        let info = self.info(elapsed);
        let kept = |e: store::StoreError| {
            let text = chain_text(&e) + " (the computed lines are kept: ";
            RequestError::message().text(text).opt(Opt::Resume).text(" once it can be written)")
        };
        draft.map_err(kept)?.finish(atlas, &info).map_err(kept)?;
        // A journal removed from outside during the run: the file is
        // complete all the same (exit 0), but a kill would have lost the
        // lines it should have kept.
        let path = journal.path().to_path_buf();
        if !journal.remove()? {
            observer.warn(&format!(
                "{} was removed or replaced during the run (a kill would have lost the computed lines); the output is complete",
                path.display()
            ));
        }
        Ok(())
    }
}

/// A journal that cannot be resumed from, with what to do about it: remove
/// it, or run without resuming.
fn journal_advice(e: store::StoreError) -> Error {
    let advice = match &e {
        store::StoreError::Journal { problem: store::JournalProblem::Damaged { .. }, .. } => {
            ": remove it (the run starts over) or run without "
        }
        store::StoreError::Journal { .. } => "; remove it or run without ",
        _ => return e.into(),
    };
    RequestError::message().text(e.to_string() + advice).opt(Opt::Resume).into()
}

/// The writer thread of a run: creates the output file (`draft_of`: path,
/// set-up, threads), keeps the lines `resumed` from the journal, then every
/// batch of lines that arrives on `rx`: appends it to the journal (one sync),
/// puts it in the atlas and writes the chunks of the file it completes.
fn keep_lines(
    mut atlas: Atlas,
    mut journal: Option<Journal>,
    draft_of: Option<(PathBuf, Meta, usize)>,
    resumed: &[(SweepKind, usize)],
    rx: std::sync::mpsc::Receiver<(Line, Option<store::SealedLine>)>,
) -> Result<Kept> {
    let clock = Instant::now();
    let mut draft = draft_of.map(|(out, meta, threads)| store::Draft::create(&out, &meta, threads));
    let prelude_s = clock.elapsed().as_secs_f64();
    let mut stream_s = 0.0;
    let mut keep = |atlas: &Atlas, kept: &[(SweepKind, usize)]| {
        let clock = Instant::now();
        if let Some(Ok(d)) = draft.as_mut() {
            if let Err(e) = kept.iter().try_for_each(|&(s, l)| d.keep(atlas, s, l)) {
                draft = Some(Err(e));
            }
        }
        stream_s += clock.elapsed().as_secs_f64();
    };
    keep(&atlas, resumed);
    while let Ok(first) = rx.recv() {
        let (lines, sealed): (Vec<Line>, Vec<_>) = std::iter::once(first).chain(rx.try_iter()).unzip();
        if let Some(j) = journal.as_mut() {
            j.append_sealed(sealed.iter().flatten())?;
        }
        let kept: Vec<(SweepKind, usize)> = lines.iter().map(|l| (l.sweep, l.index)).collect();
        for line in lines {
            atlas.insert(line);
        }
        keep(&atlas, &kept);
    }
    Ok(Kept { atlas, journal, draft, prelude_s, stream_s })
}

/// What the writer thread hands back: the lines kept, the journal, and the
/// output file created while the cells computed (with the seconds that took).
struct Kept {
    atlas: Atlas,
    journal: Option<Journal>,
    draft: Option<Result<store::Draft, store::StoreError>>,
    prelude_s: f64,
    stream_s: f64,
}

/// A run's atlas and where its time went.
#[derive(Debug)]
pub struct Executed {
    /// The atlas.
    pub atlas: Atlas,
    /// What the run's file says of the run (its command, time, shard, parent).
    pub info: RunInfo,
    /// Seconds from the start to the last line kept (the file not written).
    pub secs: f64,
    /// Seconds writing the file after the last line.
    pub write_s: f64,
    /// Seconds the writer thread took, at the start, to create the file with
    /// what does not depend on the results (while the workers computed).
    pub prelude_s: f64,
    /// Seconds the writer thread spent writing chunks of lines as they were
    /// kept (while the workers computed).
    pub stream_s: f64,
    /// Whether the output was already the finished file of this run (a
    /// resume with nothing to do: nothing was computed or written).
    pub already: bool,
}

impl Plan {
    /// The plan without the quantities of the steady motion (`--quantities
    /// none`): its cells measure none and its file stores none.
    pub fn without_quantities(&mut self) {
        self.setup.quantities.clear();
        self.meta.quantities.clear();
    }

    /// Keeps only the quantities `names` (in the table's order); an unknown
    /// name is an error naming `quantities` and the names there are. No
    /// names: none (as [`Plan::without_quantities`]).
    pub fn keep_quantities(&mut self, names: &[String]) -> Result<()> {
        if let Some(unknown) = names.iter().find(|n| !self.meta.quantities.iter().any(|q| &q.name == *n)) {
            let known: Vec<&str> = self.meta.quantities.iter().map(|q| q.name.as_str()).collect();
            let why = match unknown.as_str() {
                "all" | "none" => format!(
                    "'{unknown}' stands alone, not among names (give all, none, or names of: {})",
                    known.join(", ")
                ),
                _ => format!("'{unknown}' is not a quantity of this scene (all, none, or of: {})", known.join(", ")),
            };
            return Err(RequestError::option(Opt::Quantities).text(why).into());
        }
        let keep: Vec<usize> =
            (0..self.meta.quantities.len()).filter(|&k| names.contains(&self.meta.quantities[k].name)).collect();
        self.meta.quantities = keep.iter().map(|&k| self.meta.quantities[k].clone()).collect();
        self.setup.quantities = keep;
        Ok(())
    }

    /// A plan for `sweeps` of `plane` with the validated simulation set-up `s`:
    /// no output, shard or resume; callers set what differs.
    pub fn new(s: &Setup, section_cap: usize, plane: Plane, sweeps: Vec<SweepKind>, threads: usize) -> Result<Plan> {
        for axis in [&plane.x, &plane.y].into_iter().filter(|a| a.count > 1) {
            if s.overrides.iter().any(|(name, _)| *name == axis.name) {
                return Err(crate::sim::set_refused(&axis.name, "also an axis of the run"));
            }
        }
        let mut setup = s.cell_setup(section_cap)?;
        let model = setup.scene.evaluate(&setup.base)?;
        let quantities = grid::Quantity::of(&solver::System::new(model.clone())?);
        setup.quantities = (0..quantities.len()).collect();
        let meta = Meta {
            scene_name: model.name.clone(),
            scene_toml: setup.scene.source().to_string(),
            overrides: setup.base.clone(),
            preset: s.preset,
            accuracy: s.accuracy_overrides.clone(),
            integrator: s.method,
            plane,
            sweeps,
            masses: model.labelled_masses(),
            state_masses: model.masses.iter().map(|m| m.name.clone()).collect(),
            label_stops: model
                .labels
                .iter()
                .map(|l| [Some(l.p), l.q].map(|k| k.map_or(String::new(), |k| model.stops[k].name.clone())))
                .collect(),
            stops: model.stops.iter().map(|st| st.name.clone()).collect(),
            stop_normals: setup.scene.stop_normals(),
            stop_laws: setup.scene.stop_laws(),
            dim: 2 * model.masses.len(),
            section_cap,
            notation: grid::Notation::of_scene(&setup.scene),
            quantities,
        };
        Ok(Plan {
            setup,
            meta,
            threads,
            shard: None,
            output: None,
            resume: false,
            command: String::new(),
            inputs: Vec::new(),
            cost: None,
            attractors: None,
            entries: grid::Entries::default(),
            parent: None,
            resumable: true,
        })
    }

    /// Checks, before any work, that the results fit in memory and that every
    /// cell's parameters make a valid scene.
    /// Then estimates the cost of each line (`grid::schedule::probe`) when it
    /// matters: for a shard (split by cost), or for continuation chains on more
    /// than one thread with at least four lines per thread (ordered by cost).
    pub fn check(&mut self) -> Result<()> {
        if let Some(out) = &self.output {
            let inputs: Vec<&std::path::Path> = self.inputs.iter().map(PathBuf::as_path).collect();
            store::check_output(out, &inputs)?;
        }
        if let Some(s) = self.shard {
            let lines = self.meta.plane.lines();
            if s.n > lines {
                let why = format!("N must be at most the {lines} lines of the plane, got {}", s.n);
                return Err(RequestError::option(Opt::Shard).text(why).into());
            }
        }
        self.check_memory()?;
        grid::validate(&self.meta.plane, &self.setup, self.threads)?;
        let lines = self.meta.plane.lines();
        if self.shard.is_some() || (self.chains() && self.threads > 1 && lines >= 4 * self.threads) {
            self.cost = Some(grid::schedule::probe(&self.meta.plane, &self.setup, self.threads)?);
        }
        Ok(())
    }

    /// The coexisting attractors of the cells of this run's lines (only those
    /// where up and down differ, with `only_hysteresis`).
    fn find_attractors(
        &self,
        atlas: &Atlas,
        sampling: &grid::attractors::Sampling,
        only_hysteresis: bool,
        owns: &[bool],
        observer: &dyn Observer,
    ) -> Result<grid::AttractorMap> {
        let p = &self.meta.plane;
        let hyst = atlas.hysteresis();
        if only_hysteresis && hyst.is_none() {
            return Err(RequestError::given(Opt::AttractorsWhere, "hysteresis")
                .text("needs ")
                .opt_given(Opt::Sweep, "both")
                .into());
        }
        let chosen: Vec<usize> = (0..p.cells())
            .filter(|&i| {
                let (line, _) = p.position(i / p.x.count, i % p.x.count);
                owns[line] && hyst.as_ref().is_none_or(|h| !only_hysteresis || h[i] == 1)
            })
            .collect();
        let points: Vec<Vec<(String, f64)>> = chosen.iter().map(|&i| p.params(i / p.x.count, i % p.x.count)).collect();
        let total = (points.len() * sampling.samples) as u64;
        let work = Begin { total, done: 0, lines: &[], prior: None, line_len: 1, threads: self.threads };
        observer.begin(&work);
        let found = grid::attractors::find_all(&self.setup, &points, sampling, self.threads, observer);
        observer.finish();
        let found = found?;
        let mut cells = vec![None; p.cells()];
        for (&i, list) in chosen.iter().zip(found) {
            let masses = self.meta.masses.len();
            cells[i] = Some(
                list.iter()
                    .map(|a| grid::CellAttractor {
                        labels: a.cell.labels[..masses].to_vec(),
                        fraction: a.count as f64 / sampling.samples as f64,
                        section: a.cell.period_section.iter().take(grid::FAMILY_POINTS).map(<[f64]>::to_vec).collect(),
                    })
                    .collect(),
            );
        }
        Ok(grid::AttractorMap { samples: sampling.samples, seed: sampling.seed, cells })
    }

    /// On a resume without a journal, the output when it is already the
    /// finished file of this very run (the same settings and shard): a
    /// cluster job that reruns a finished shard does nothing. Anything else
    /// (no file, another run's, one that is not an atlas) is computed again.
    /// A damaged atlas (a dataset, an attribute) is an error naming it, and
    /// the run's finished file is first checked whole, as the writer checks
    /// it before putting it in place ([`store::check_finished`]).
    fn finished_before(&self) -> Result<Option<Atlas>> {
        let Some(out) = self.output.as_deref().filter(|_| self.resume) else { return Ok(None) };
        if !out.is_file() || journal_path(out).exists() {
            return Ok(None);
        }
        let same_attractors = |a: &Option<grid::AttractorMap>| match (&self.attractors, a) {
            (None, None) => true,
            (Some((s, _)), Some(a)) => a.samples == s.samples && a.seed == s.seed,
            _ => false,
        };
        let loaded = match store::read(out) {
            Ok(loaded) => loaded,
            // A damaged atlas (a dataset, an attribute) is said, never
            // computed again over.
            Err(e) if store::is_atlas(out) => return Err(e.into()),
            Err(_) => return Ok(None),
        };
        if loaded.atlas.meta != self.meta
            || loaded.info.shard != self.shard
            || !same_attractors(&loaded.atlas.attractors)
        {
            return Ok(None);
        }
        store::check_finished(out, &loaded)?;
        Ok(Some(loaded.atlas))
    }

    /// Whether the run computes continuation chains (up or down sweeps).
    fn chains(&self) -> bool {
        self.meta.sweeps.iter().any(|&s| s != SweepKind::Fresh)
    }

    /// The lines this run computes: all, or its shard's (balanced by cost).
    pub fn owned(&self) -> Vec<bool> {
        let lines = self.meta.plane.lines();
        match (self.shard, &self.cost) {
            (Some(s), Some(cost)) => grid::schedule::shard_lines(cost, s.k, s.n),
            // Not probed (check was not called): equal costs deal lines in turn.
            (Some(s), None) => grid::schedule::shard_lines(&vec![1.0; lines], s.k, s.n),
            (None, _) => vec![true; lines],
        }
    }
}

/// The version of [`JournalKey`]'s encoding and of the journal's lines: a
/// journal of another version is not resumed from (its fingerprint
/// differs). 2: the cells' reasons are stored with their numbers.
const JOURNAL_KEY_VERSION: u32 = 2;

/// Every setting that decides a plan's lines, as its journal is keyed.
#[derive(Serialize)]
struct JournalKey<'a> {
    version: u32,
    scene: &'a str,
    overrides: &'a [(String, f64)],
    preset: &'static str,
    accuracy: Vec<(&'static str, f64)>,
    integrator: &'static str,
    x: AxisKey<'a>,
    y: AxisKey<'a>,
    along: &'static str,
    sweeps: Vec<&'static str>,
    section_cap: usize,
    shard: Option<(usize, usize)>,
    parent: Option<(&'a str, u32, &'a str)>,
    entries: Vec<(&'static str, usize, &'a [f64])>,
    /// The quantities measured (none: the key of a run before them).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    quantities: Vec<&'a str>,
}

/// An axis as a journal is keyed: its values and the lattice they snap to.
#[derive(Serialize)]
struct AxisKey<'a> {
    name: &'a str,
    start: f64,
    stop: f64,
    count: usize,
    lattice: &'a [(f64, f64, usize)],
}

impl AxisKey<'_> {
    fn of(a: &grid::Axis) -> AxisKey<'_> {
        let lattice = a.lattice.as_ref().map_or(&[][..], |l| l.levels.as_slice());
        AxisKey { name: &a.name, start: a.start, stop: a.stop, count: a.count, lattice }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{SceneSource, Sim};
    use grid::{Along, Axis};

    /// The journal's key is a versioned encoding of the settings: equal for
    /// equal plans, and changed by each setting that changes the lines.
    #[test]
    fn the_journal_key_changes_with_every_setting_of_the_lines() {
        let s = Sim::new(SceneSource::File("../../configs/multi-stop.toml".into())).setup().unwrap();
        let key = |edit: &dyn Fn(&mut Plan)| {
            let plane = Plane::new(Axis::new("omega", 0.2, 2.5, 4), Axis::new("delta", 0.1, 1.5, 3), Along::X).unwrap();
            let mut plan = Plan::new(&s, 0, plane, vec![SweepKind::Up], 1).unwrap();
            edit(&mut plan);
            plan.journal_key()
        };
        let base = key(&|_| {});
        assert_eq!(base, key(&|_| {}));
        let v: serde_json::Value = serde_json::from_str(&base).unwrap();
        assert_eq!(
            (v["version"].as_u64(), v["x"]["count"].as_u64(), v["along"].as_str()),
            (Some(u64::from(JOURNAL_KEY_VERSION)), Some(4), Some("x"))
        );
        type Edit<'a> = (&'a str, &'a dyn Fn(&mut Plan));
        let edits: [Edit; 8] = [
            ("section cap", &|p| p.meta.section_cap = 5),
            ("shard", &|p| p.shard = Some(Shard { k: 1, n: 2 })),
            ("accuracy", &|p| p.meta.accuracy.push((solver::Knob::MaxPeriods, 900.0))),
            ("overrides", &|p| p.meta.overrides.push(("delta".into(), 0.5))),
            ("sweeps", &|p| p.meta.sweeps = vec![SweepKind::Down]),
            ("axis", &|p| p.meta.plane.x.stop = 2.6),
            ("lattice", &|p| p.meta.plane.y.lattice = Some(grid::Lattice { levels: vec![(0.1, 1.5, 3)] })),
            ("entries", &|p| drop(p.entries.0.insert((SweepKind::Up, 0), vec![0.1; 4]))),
        ];
        for (what, edit) in edits {
            assert_ne!(key(edit), base, "{what}");
        }
    }
}
