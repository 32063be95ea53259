//! What a run tells its caller while it computes, and how the caller stops
//! it: an [`Observer`] (the CLI's progress bar, Python's tqdm loop, the
//! explorer's job, nothing), the one trait every run of the grid and the
//! engine reports to.

/// The work of a plane run, told once before the first cell.
#[derive(Debug, Clone, Copy)]
pub struct Begin<'a> {
    /// Cells of the run (this shard's, every sweep).
    pub total: u64,
    /// Cells already done (kept by a journal).
    pub done: u64,
    /// The line of each job, in the order the workers take them.
    pub lines: &'a [usize],
    /// Each job's probed cost in forcing periods, when probed
    /// ([`crate::schedule::probe`]).
    pub prior: Option<&'a [f64]>,
    /// Cells per line.
    pub line_len: usize,
    /// Worker threads.
    pub threads: usize,
}

/// Receives a run's progress; may ask it to stop. Every method has a default
/// that does nothing.
pub trait Observer: Sync {
    /// The run starts.
    fn begin(&self, _work: &Begin<'_>) {}
    /// `cells` more cells are done (from any worker thread).
    fn advance(&self, _cells: u64) {}
    /// Job `job` (an index into [`Begin::lines`]) is done.
    fn line_done(&self, _job: usize) {}
    /// Every cell is done (the file may still be written).
    fn finish(&self) {}
    /// Something the user should know that does not stop the run.
    fn warn(&self, _message: &str) {}
    /// Whether the run should stop; asked before every cell.
    fn cancelled(&self) -> bool {
        false
    }
}

/// An observer that shows nothing and never stops the run.
#[derive(Debug, Default, Clone, Copy)]
pub struct Quiet;
impl Observer for Quiet {}
