//! The benchmark of `vibroatlas bench`: atlas throughput on each thread count
//! (fresh and both sweeps, best of repeated runs, every run checked to give
//! the same atlas) and the speed/accuracy trade of every preset and of RK4
//! against the `precise` reference (in rounds of every setting, best kept).
//!
//! ```no_run
//! use engine::bench::{throughput, trade, BenchRequest};
//!
//! let mut request = BenchRequest::new(24);
//! request.repeat = 1;
//! request.trade_rounds = Some(1);
//! let rows = throughput(&request, &mut |row| Ok::<(), engine::Error>(println!("{} cells/s", row.cells_per_s)))?;
//! let trade = trade(&request)?;
//! println!("{}", engine::bench::Bench { grid: 24, throughput: rows, trade }.to_json());
//! # Ok::<(), engine::Error>(())
//! ```

use crate::error::SceneLoadError;
use crate::error::{Error, Result};
use crate::error::{Opt, RequestError};
use crate::plan::Plan;
use crate::sim::{SceneSource, Setup};
use grid::Quiet;
use grid::{Along, Atlas, Axis, Plane, SweepKind};
use scene::Scene;
use serde::Serialize;
use serde_json::Value;
use solver::{Accuracy, Class, Knob, Method, Preset};

/// The reference scene (the shipped multi-stop scene), the default of a bench.
/// `reference-scene.toml` is a link to `configs/multi-stop.toml`: the crate's
/// package carries the scene itself (`cargo package` follows the link).
pub const REFERENCE_SCENE: &str = include_str!("reference-scene.toml");

/// A setting of the trade: preset, integrator, and the accuracy knobs it
/// overrides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setting {
    /// The setting's name in the table.
    pub name: &'static str,
    /// The preset it starts from.
    pub preset: Preset,
    /// The integrator.
    pub method: Method,
    /// Accuracy knobs replacing the preset's.
    pub knobs: &'static [(Knob, f64)],
}

/// A setting of the exact solver.
const fn exact(name: &'static str, preset: Preset, knobs: &'static [(Knob, f64)]) -> Setting {
    Setting { name, preset, method: Method::Exact, knobs }
}

/// A setting of the RK4 integrator, at standard tolerances.
const fn rk4(name: &'static str, knobs: &'static [(Knob, f64)]) -> Setting {
    Setting { name, preset: Preset::Standard, method: Method::Rk4, knobs }
}

/// The exact solver at the default preset: the setting of the throughput.
pub const STANDARD: Setting = exact("standard", Preset::Standard, &[]);

/// The reference of the trade.
pub const PRECISE: Setting = exact("precise", Preset::Precise, &[]);

/// The literature's method, the setting all others are compared with for speed.
pub const RK4: Setting = rk4("rk4 h=0.01", &[(Knob::Rk4Step, 0.01), (Knob::Newton, 0.0)]);

/// `standard` without the early end of chaotic records: the setting that
/// agrees with `precise` at least as well as [`RK4`] does.
pub const EQUAL: Setting = exact("standard chaos_check=0", Preset::Standard, &[(Knob::ChaosCheck, 0.0)]);

/// Settings of the trade, in table order. The RK4 rows are the literature's
/// method: RK4 with step-back refinement and a plainly simulated transient
/// (standard tolerances, no Newton); the last row shows what Newton adds to RK4.
/// `standard chaos_check=0` is standard without the early end of chaotic
/// records (the default of `standard` before it was measured to agree with
/// `precise` at least as well as RK4).
pub const SETTINGS: [Setting; 7] = [
    exact("fast", Preset::Fast, &[]),
    STANDARD,
    EQUAL,
    PRECISE,
    RK4,
    rk4("rk4 h=0.001", &[(Knob::Rk4Step, 0.001), (Knob::Newton, 0.0)]),
    rk4("rk4 h=0.01 newton", &[(Knob::Rk4Step, 0.01)]),
];

/// Settings of the paper's comparison ([`BenchRequest::paper`]), in table
/// order: `standard`, [`EQUAL`], the reference (timed in the first round only)
/// and the literature's method.
pub const PAPER: [Setting; 4] = [STANDARD, EQUAL, PRECISE, RK4];

/// Grid size of the paper's comparison unless one is given: 128 x 128 = 16 384
/// fresh cells, about 6 s of `standard` on one thread of the 2-core VM of
/// docs/performance.md (about 2 700 cells/s a thread: 4.6 s on 112 x 112) and
/// two and a half minutes of [`RK4`] (about 110).
pub const PAPER_GRID: usize = 128;

/// Most runs of each measurement a bench takes (`--repeat`, `--trade-repeat`).
pub const MAX_REPEAT: usize = 100;

/// Rounds of the paper's comparison unless others are asked for.
pub const PAPER_ROUNDS: usize = 4;

/// Seconds a round of each side should take at least for a steady ratio:
/// a shorter run's time is swayed by the machine's slow spells.
pub const STEADY_SECONDS: f64 = 5.0;

/// The sweeps of the throughput, by name: fresh cells, and both continuations.
pub fn sweeps() -> [(&'static str, Vec<SweepKind>); 2] {
    [("fresh", vec![SweepKind::Fresh]), ("both", vec![SweepKind::Up, SweepKind::Down])]
}

/// What to measure.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchRequest {
    /// The scene (it must have the parameters `omega` and `delta`).
    pub scene: SceneSource,
    /// Grid size N: N x N cells of the plane ω ∈ [0.1, 3.05], δ ∈ [0.05, 2].
    pub grid: usize,
    /// Thread counts of the throughput, in order (the trade runs on the largest).
    pub threads: Vec<usize>,
    /// Timed repetitions of each throughput measurement (the best is kept).
    pub repeat: usize,
    /// Rounds of the trade, each timing every setting once in table order
    /// (the best of each is kept); `None`: no trade.
    pub trade_rounds: Option<usize>,
    /// The trade is the paper's comparison ([`PAPER`]): `standard` and
    /// [`EQUAL`] against the literature's method only, the reference timed
    /// once, instead of every setting of [`SETTINGS`] in every round.
    pub paper: bool,
}

impl BenchRequest {
    /// The reference scene on an N x N grid, on 1 and 2 threads, best of 3,
    /// no trade.
    pub fn new(grid: usize) -> BenchRequest {
        BenchRequest {
            scene: SceneSource::Text(REFERENCE_SCENE.to_string()),
            grid,
            threads: vec![1, 2],
            repeat: 3,
            trade_rounds: None,
            paper: false,
        }
    }

    /// Refuses counts out of range (each error names its option).
    pub fn check(&self) -> Result<()> {
        let refuse = RequestError::option;
        if self.threads.is_empty() || self.threads.iter().any(|t| !(1..=1024).contains(t)) {
            let why = format!("expected a comma-separated list of counts 1..1024, got {:?}", self.threads);
            return Err(refuse(Opt::Threads).text(why).into());
        }
        if let Some(t) = self.threads.iter().enumerate().find_map(|(i, t)| self.threads[..i].contains(t).then_some(t)) {
            let why = format!("{t} given twice; give each count once");
            return Err(refuse(Opt::Threads).text(why).into());
        }
        if !(2..=2000).contains(&self.grid) {
            return Err(refuse(Opt::Grid).text(format!("must be in 2..=2000, got {}", self.grid)).into());
        }
        if !(1..=MAX_REPEAT).contains(&self.repeat) {
            return Err(refuse(Opt::Repeat).text(format!("must be 1 to {MAX_REPEAT}, got {}", self.repeat)).into());
        }
        if let Some(r) = self.trade_rounds.filter(|r| !(1..=MAX_REPEAT).contains(r)) {
            return Err(refuse(Opt::TradeRepeat).text(format!("must be 1 to {MAX_REPEAT}, got {r}")).into());
        }
        Ok(())
    }

    /// The scene, checked to have the parameters of the plane.
    pub fn scene(&self) -> Result<Scene> {
        let scene = match &self.scene {
            SceneSource::File(p) => {
                let text = crate::sim::read_text(p).map_err(|cause| SceneLoadError::Read { path: p.clone(), cause })?;
                Scene::parse(&text)
            }
            SceneSource::Text(text) => Scene::parse(text),
            SceneSource::Stored(p) => Scene::parse(&store::stored_scene(p)?),
        }
        .map_err(|cause| SceneLoadError::Invalid { origin: "scene".into(), cause })?;
        for name in ["omega", "delta"] {
            scene.check_parameter(name, "").map_err(|e| {
                crate::sim::unknown(RequestError::option(Opt::Scene), e).text(" (bench maps the omega-delta plane)")
            })?;
        }
        Ok(scene)
    }

    /// The N x N plane of the bench.
    pub fn plane(&self) -> Result<Plane> {
        let n = self.grid;
        let axis = |text: String| Axis::parse(&text, "grid").map_err(|e| crate::grid_error(e, &[("grid", Opt::Grid)]));
        Ok(Plane::new(axis(format!("omega=0.1:3.05:{n}"))?, axis(format!("delta=0.05:2:{n}"))?, Along::X)?)
    }

    /// Checked request, scene and plane.
    fn prepare(&self) -> Result<(Scene, Plane)> {
        self.check()?;
        Ok((self.scene()?, self.plane()?))
    }
}

/// One throughput measurement (a row of `bench --json`'s `throughput`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Throughput {
    /// `fresh` or `both`.
    pub sweep: &'static str,
    /// Worker threads.
    pub threads: usize,
    /// Cells computed (every sweep).
    pub cells: usize,
    /// Seconds of the best run.
    pub seconds: f64,
    /// Cells per second of the best run.
    pub cells_per_s: f64,
    /// Cells/s over the first thread count's, per thread ratio.
    pub efficiency: f64,
}

/// One setting's measured speed and agreement with the reference.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TradeRow {
    /// The setting's name.
    pub setting: &'static str,
    /// Cells per second.
    pub cells_per_s: f64,
    /// Share of cells whose class and labels equal the reference's.
    pub label_agreement: f64,
    /// Share of cells whose class equals the reference's.
    pub class_agreement: f64,
    /// Median of the largest |Δ final state| component against the reference.
    pub median_state_error: f64,
    /// Forcing periods simulated over the grid.
    pub periods: u64,
    /// Thread time per forcing period, µs.
    pub us_per_period: f64,
    /// Periods simulated in cells without a period.
    pub nonperiodic_periods: u64,
    /// Seconds of each round of the trade, in order (the best gives
    /// `cells_per_s`).
    pub round_seconds: Vec<f64>,
}

impl TradeRow {
    /// Share of the periods simulated in cells without a period.
    pub fn nonperiodic_share(&self) -> f64 {
        self.nonperiodic_periods as f64 / self.periods.max(1) as f64
    }
}

/// The trade: every setting of [`SETTINGS`] (or of [`PAPER`]), in table order.
#[derive(Debug, Clone, PartialEq)]
pub struct Trade {
    /// Worker threads of every run.
    pub threads: usize,
    /// One row per setting.
    pub rows: Vec<TradeRow>,
}

impl Trade {
    /// Cells/s of the literature's method ([`RK4`]), the base of the speed-ups.
    pub fn rk4_cells_per_s(&self) -> Option<f64> {
        self.rows.iter().find(|r| r.setting == RK4.name).map(|r| r.cells_per_s)
    }

    /// The rows as reported, each with its speed-up over RK4 and that
    /// speed-up's spread over the rounds.
    pub fn report(&self) -> Vec<TradeReportRow> {
        let base = self.rk4_cells_per_s();
        self.rows
            .iter()
            .map(|r| TradeReportRow {
                row: r.clone(),
                speedup_vs_rk4: base.map(|b| r.cells_per_s / b),
                speedup_spread: self.spread(r),
                speedup_median: self.median(r),
            })
            .collect()
    }

    /// The least and the largest speed-up of `row` over RK4 among the
    /// rounds, each round's against RK4's of the same round (the machine's
    /// slow spells fall on both); `None` without RK4.
    pub fn spread(&self, row: &TradeRow) -> Option<[f64; 2]> {
        let ratios = self.round_ratios(row)?;
        ratios
            .into_iter()
            .fold(None, |acc: Option<[f64; 2]>, q| Some(acc.map_or([q, q], |[lo, hi]| [lo.min(q), hi.max(q)])))
    }

    /// The median of `row`'s speed-ups over RK4, each round's against RK4's
    /// of the same round (the mean of the middle two of an even count);
    /// `None` without RK4.
    pub fn median(&self, row: &TradeRow) -> Option<f64> {
        let mut ratios = self.round_ratios(row)?;
        ratios.sort_by(f64::total_cmp);
        let k = ratios.len();
        (k > 0).then(|| (ratios[(k - 1) / 2] + ratios[k / 2]) / 2.0)
    }

    /// `row`'s speed-up over RK4 in each round it was timed in.
    fn round_ratios(&self, row: &TradeRow) -> Option<Vec<f64>> {
        let rk4 = self.rows.iter().find(|r| r.setting == RK4.name)?;
        Some(rk4.round_seconds.iter().zip(&row.round_seconds).map(|(b, s)| b / s).collect())
    }
}

/// A row of the trade as `bench --trade --json` reports it: the setting's
/// measurements and its cells/s over those of the RK4 baseline.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TradeReportRow {
    /// The measurements.
    #[serde(flatten)]
    pub row: TradeRow,
    /// Cells/s over RK4's, when RK4 was measured.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speedup_vs_rk4: Option<f64>,
    /// The least and largest speed-up over RK4 among the rounds
    /// ([`Trade::spread`]), when RK4 was measured.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speedup_spread: Option<[f64; 2]>,
    /// The median speed-up over RK4 among the rounds ([`Trade::median`]),
    /// when RK4 was measured.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speedup_median: Option<f64>,
}

/// The JSON of a bench (the contract of `bench --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BenchReport {
    /// Grid size N.
    pub grid: usize,
    /// The trade's rows (empty without one).
    pub trade: Vec<TradeReportRow>,
    /// Throughput rows, by sweep then thread count.
    pub throughput: Vec<Throughput>,
    /// Always empty: the replay of the scheduler that filled it is
    /// `cargo bench --bench replay`.
    pub simulated: [f64; 0],
}

/// A bench's results.
#[derive(Debug, Clone, PartialEq)]
pub struct Bench {
    /// Grid size N.
    pub grid: usize,
    /// Throughput rows, by sweep then thread count.
    pub throughput: Vec<Throughput>,
    /// The trade, if measured.
    pub trade: Option<Trade>,
}

impl Bench {
    /// The JSON object of `bench --json`: `grid`, `trade` (empty without one),
    /// `throughput`, and `simulated`, always empty (the replay of the
    /// scheduler that filled it is `cargo bench --bench replay`).
    pub fn to_json(&self) -> Value {
        crate::report::to_value(&self.report())
    }

    /// The bench as its report ([`BenchReport`]).
    pub fn report(&self) -> BenchReport {
        BenchReport {
            grid: self.grid,
            trade: self.trade.as_ref().map_or_else(Vec::new, Trade::report),
            throughput: self.throughput.clone(),
            simulated: [],
        }
    }
}

/// Measures throughput and, with [`BenchRequest::trade_rounds`], the trade.
pub fn bench(request: &BenchRequest) -> Result<Bench> {
    let throughput = throughput(request, &mut |_| Ok::<(), Error>(()))?;
    Ok(Bench { grid: request.grid, throughput, trade: trade(request)? })
}

/// Throughput of every sweep ([`sweeps`]) on every thread count, each the
/// best of [`BenchRequest::repeat`] runs; `each` sees every row as it is
/// measured (its error, of the caller's type, ends the bench). An error if
/// any two runs of a sweep, on any thread count, give different atlases.
pub fn throughput<E: From<Error>>(
    request: &BenchRequest,
    each: &mut dyn FnMut(&Throughput) -> Result<(), E>,
) -> Result<Vec<Throughput>, E> {
    let (scene, plane) = request.prepare()?;
    let mut rows = Vec::new();
    for (name, sweeps) in sweeps() {
        let mut base = None;
        // Every run, on any thread count, must give the same atlas bit for bit.
        let mut first: Option<Atlas> = None;
        for &t in &request.threads {
            let m = best_of(request.repeat, &mut first, || run_plane(&scene, &plane, &sweeps, STANDARD, t))?;
            let (seconds, count) = (m.secs, cells(&m.atlas));
            let rate = count as f64 / seconds;
            let (t0, r0) = *base.get_or_insert((t, rate));
            let efficiency = rate / r0 / (t as f64 / t0 as f64);
            let row = Throughput { sweep: name, threads: t, cells: count, seconds, cells_per_s: rate, efficiency };
            each(&row)?;
            rows.push(row);
        }
    }
    Ok(rows)
}

/// The trade on the largest thread count, fresh cells, in
/// [`BenchRequest::trade_rounds`] rounds of every setting once (a slow spell
/// of a shared machine falls on all settings alike, not on every run of
/// one), the best of each setting kept; `None` without rounds. The paper's
/// comparison ([`BenchRequest::paper`]) times the settings of [`PAPER`], the
/// reference in the first round only.
pub fn trade(request: &BenchRequest) -> Result<Option<Trade>> {
    let Some(rounds) = request.trade_rounds else { return Ok(None) };
    let (scene, plane) = request.prepare()?;
    let t = *request.threads.iter().max().unwrap_or(&1);
    let fresh = [SweepKind::Fresh];
    let settings: &[Setting] = if request.paper { &PAPER } else { &SETTINGS };
    let mut runs: Vec<Option<Measured>> = settings.iter().map(|_| None).collect();
    let mut seconds: Vec<Vec<f64>> = settings.iter().map(|_| Vec::with_capacity(rounds)).collect();
    for round in 0..rounds {
        for ((best, secs), &setting) in runs.iter_mut().zip(&mut seconds).zip(settings) {
            if request.paper && round > 0 && setting == PRECISE {
                continue;
            }
            let m = run_plane(&scene, &plane, &fresh, setting, t)?;
            secs.push(m.secs);
            keep_faster(best, m)?;
        }
    }
    let measured: Vec<Measured> =
        runs.into_iter().map(|best| best.ok_or_else(|| Error::Internal("no run".into()))).collect::<Result<_>>()?;
    let reference = settings
        .iter()
        .zip(&measured)
        .find(|(s, _)| s.name == PRECISE.name)
        .map(|(_, m)| &m.atlas)
        .ok_or_else(|| Error::Internal("no reference setting".into()))?;
    let rows = settings
        .iter()
        .zip(&measured)
        .zip(seconds)
        .map(|((setting, m), secs)| trade_row(setting, m, reference, t, secs))
        .collect();
    Ok(Some(Trade { threads: t, rows }))
}

/// The row of `setting`, measured as `m` (the best of rounds that took
/// `round_seconds`) on `threads` threads, against `reference`.
fn trade_row(setting: &Setting, m: &Measured, reference: &Atlas, threads: usize, round_seconds: Vec<f64>) -> TradeRow {
    let (labels, classes, median) = compare(reference, &m.atlas);
    // Work per forcing period, in thread time: what the integrator costs.
    let total = periods(&m.atlas, |_| true);
    TradeRow {
        setting: setting.name,
        cells_per_s: cells(&m.atlas) as f64 / m.secs,
        label_agreement: labels,
        class_agreement: classes,
        median_state_error: median,
        periods: total,
        us_per_period: 1e6 * m.secs * threads as f64 / total.max(1) as f64,
        // Cells without a period: the records every method simulates in full.
        nonperiodic_periods: periods(&m.atlas, |c| c != Class::Periodic),
        round_seconds,
    }
}

/// A run's atlas and its seconds.
struct Measured {
    atlas: Atlas,
    secs: f64,
}

/// One run of `sweeps` of `plane` at `setting`, on `threads` threads, no file.
fn run_plane(scene: &Scene, plane: &Plane, sweeps: &[SweepKind], setting: Setting, threads: usize) -> Result<Measured> {
    let mut accuracy = Accuracy::preset(setting.preset);
    for &(knob, value) in setting.knobs {
        accuracy.set(knob, value)?;
    }
    let s = Setup {
        scene: scene.clone(),
        overrides: Vec::new(),
        accuracy,
        accuracy_overrides: Vec::new(),
        preset: setting.preset,
        method: setting.method,
    };
    let plan = Plan::new(&s, 0, plane.clone(), sweeps.to_vec(), threads)?;
    let m = plan.execute(&Quiet)?;
    Ok(Measured { atlas: m.atlas, secs: m.secs })
}

/// Keeps in `best` the faster of it and `m`, once `m`'s atlas is checked to
/// equal `best`'s: results are deterministic, however often they are computed.
fn keep_faster(best: &mut Option<Measured>, m: Measured) -> Result<()> {
    if let Some(b) = best.as_ref() {
        same_atlas(&b.atlas, &m.atlas)?;
    }
    if best.as_ref().is_none_or(|b| m.secs < b.secs) {
        *best = Some(m);
    }
    Ok(())
}

/// An error unless two runs of the same grid gave the same atlas, bit for
/// bit, naming the first cell that differs. Where `==` says they differ,
/// compared again in their `Debug` form, which writes every number as the
/// shortest decimal that reads back to its bits: `==` is false wherever a
/// cell holds a NaN (a quantity of a motion that could not be followed),
/// however alike the runs.
fn same_atlas(a: &Atlas, b: &Atlas) -> Result<()> {
    fn same<T: PartialEq + std::fmt::Debug>(x: &T, y: &T) -> bool {
        x == y || format!("{x:?}") == format!("{y:?}")
    }
    let differ = |what: String| {
        Err(Error::Internal(format!(
            "results differ between runs of the same grid ({what}): the solver is not deterministic"
        )))
    };
    let nx = a.meta.plane.x.count;
    for (ma, mb) in a.maps.iter().zip(&b.maps) {
        let mut cells = ma.cells.iter().zip(&mb.cells).enumerate();
        if let Some((k, _)) = cells.find(|(_, (ca, cb))| !same(ca, cb)) {
            return differ(format!("the {} sweep's cell at row {}, column {}", ma.sweep, k / nx, k % nx));
        }
    }
    let sweeps = |x: &Atlas| x.maps.iter().map(|m| (m.sweep, m.cells.len())).collect::<Vec<_>>();
    let rest = same(&sweeps(a), &sweeps(b))
        && same(&a.meta, &b.meta)
        && same(&a.attractors, &b.attractors)
        && same(&a.entries, &b.entries);
    if !rest {
        return differ("their sweeps, description, attractors or entries".into());
    }
    Ok(())
}

/// The fastest of `repeat` (>= 1) runs, each checked to give the same atlas,
/// which must also equal `first` (set by the first call when `None`), whatever
/// the thread count.
fn best_of(repeat: usize, first: &mut Option<Atlas>, mut run: impl FnMut() -> Result<Measured>) -> Result<Measured> {
    let mut best = None;
    for _ in 0..repeat {
        keep_faster(&mut best, run()?)?;
    }
    let best = best.ok_or_else(|| Error::Internal("no run".into()))?;
    same_atlas(first.get_or_insert_with(|| best.atlas.clone()), &best.atlas)?;
    Ok(best)
}

/// Cells of every sweep of `a`.
fn cells(a: &Atlas) -> usize {
    a.maps.iter().map(|m| m.cells.len()).sum()
}

/// Forcing periods simulated over the cells of `a` whose class passes `keep`
/// (Newton, stability and section work included).
pub fn periods(a: &Atlas, keep: impl Fn(Class) -> bool) -> u64 {
    a.maps.iter().flat_map(|m| m.cells.iter().flatten()).filter(|c| keep(c.class)).map(|c| c.periods).sum()
}

/// Label agreement, class agreement and median state error of `m` against `reference`.
fn compare(reference: &Atlas, m: &Atlas) -> (f64, f64, f64) {
    let pairs: Vec<_> = reference.maps[0]
        .cells
        .iter()
        .zip(&m.maps[0].cells)
        .filter_map(|(a, b)| Some((a.as_ref()?, b.as_ref()?)))
        .collect();
    let total = pairs.len().max(1) as f64;
    let labels = pairs.iter().filter(|(a, b)| a.class == b.class && a.labels == b.labels).count() as f64 / total;
    let classes = pairs.iter().filter(|(a, b)| a.class == b.class).count() as f64 / total;
    let mut errs: Vec<f64> = pairs
        .iter()
        .map(|(a, b)| a.final_state.iter().zip(&b.final_state).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max))
        .collect();
    errs.sort_by(f64::total_cmp);
    (labels, classes, errs.get(errs.len() / 2).copied().unwrap_or(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_trade_table_has_its_reference_and_baseline() {
        let names: Vec<&str> = SETTINGS.iter().map(|s| s.name).collect();
        assert!(names.contains(&PRECISE.name) && names.contains(&RK4.name) && names.contains(&STANDARD.name));
        let mut unique = names.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), names.len(), "names are unique: {names:?}");
        for s in &SETTINGS {
            let mut accuracy = Accuracy::preset(s.preset);
            for &(knob, value) in s.knobs {
                accuracy.set(knob, value).unwrap_or_else(|e| panic!("{}: {e}", s.name));
            }
        }
    }

    /// The median of the rounds' speed-ups: the middle one of an odd count,
    /// the mean of the middle two of an even one, each round's RK4 time over
    /// the setting's of the same round.
    #[test]
    fn the_median_speedup_pairs_each_round_with_rk4s() {
        let row = |setting, round_seconds: Vec<f64>| TradeRow {
            setting,
            cells_per_s: 1.0,
            label_agreement: 1.0,
            class_agreement: 1.0,
            median_state_error: 0.0,
            periods: 1,
            us_per_period: 1.0,
            nonperiodic_periods: 0,
            round_seconds,
        };
        let trade = |rk4: Vec<f64>, standard: Vec<f64>| Trade {
            threads: 1,
            rows: vec![row(STANDARD.name, standard), row(RK4.name, rk4)],
        };
        // Ratios 10, 30, 20: median 20 (not the ratio of the medians' times).
        let odd = trade(vec![10.0, 60.0, 20.0], vec![1.0, 2.0, 1.0]);
        assert_eq!(odd.median(&odd.rows[0]), Some(20.0));
        assert_eq!(odd.spread(&odd.rows[0]), Some([10.0, 30.0]));
        let even = trade(vec![10.0, 60.0, 20.0, 40.0], vec![1.0, 2.0, 1.0, 1.0]);
        assert_eq!(even.median(&even.rows[0]), Some(25.0));
        assert_eq!(even.median(&even.rows[1]), Some(1.0));
        let without = Trade { threads: 1, rows: vec![row(STANDARD.name, vec![1.0])] };
        assert_eq!(without.median(&without.rows[0]), None);
    }

    /// Two runs are the same where every bit is, a NaN quantity included
    /// (which `==` takes for a difference even from itself: rounds of the
    /// trade on 112 x 112 cells stopped so at RK4's second, two of its cells
    /// out of the event budget with their quantities NaN), and
    /// differ where one bit of one cell does, named by its sweep and place.
    #[test]
    fn runs_that_agree_bit_for_bit_are_the_same_nan_or_not() {
        let (scene, plane) = BenchRequest::new(3).prepare().unwrap();
        let mut a = run_plane(&scene, &plane, &[SweepKind::Fresh], STANDARD, 1).unwrap().atlas;
        a.maps[0].cells[5].as_mut().unwrap().quantities[0] = f64::NAN;
        let b = a.clone();
        assert!(a != b, "== is false for a NaN");
        same_atlas(&a, &b).unwrap();
        let mut c = a.clone();
        let state = &mut c.maps[0].cells[5].as_mut().unwrap().final_state[0];
        *state = f64::from_bits(state.to_bits() ^ 1);
        let why = same_atlas(&a, &c).unwrap_err().to_string();
        assert!(why.contains("the fresh sweep's cell at row 1, column 2"), "{why}");
    }

    #[test]
    fn requests_out_of_range_name_their_option() {
        let error = |f: fn(&mut BenchRequest)| {
            let mut r = BenchRequest::new(8);
            f(&mut r);
            r.check().unwrap_err().at_fault()
        };
        assert_eq!(error(|r| r.grid = 1), Some(Opt::Grid));
        assert_eq!(error(|r| r.threads = vec![0]), Some(Opt::Threads));
        assert_eq!(error(|r| r.threads.clear()), Some(Opt::Threads));
        assert_eq!(error(|r| r.repeat = 0), Some(Opt::Repeat));
        assert_eq!(error(|r| r.trade_rounds = Some(0)), Some(Opt::TradeRepeat));
        assert!(BenchRequest::new(8).check().is_ok());
    }

    #[test]
    fn json_keeps_the_shape_of_bench_json() {
        let row = Throughput { sweep: "fresh", threads: 1, cells: 4, seconds: 2.0, cells_per_s: 2.0, efficiency: 1.0 };
        let trade = Trade {
            threads: 1,
            rows: vec![TradeRow {
                setting: RK4.name,
                cells_per_s: 3.0,
                label_agreement: 1.0,
                class_agreement: 1.0,
                median_state_error: 0.0,
                periods: 10,
                us_per_period: 1.0,
                nonperiodic_periods: 2,
                round_seconds: vec![2.0, 1.0],
            }],
        };
        let j = Bench { grid: 2, throughput: vec![row], trade: Some(trade) }.to_json();
        use serde_json::json;
        let mut keys: Vec<&String> = j.as_object().unwrap().keys().collect();
        keys.sort();
        assert_eq!(keys, ["grid", "simulated", "throughput", "trade"]);
        assert_eq!(j["simulated"], json!([]));
        assert_eq!(j["trade"][0]["speedup_vs_rk4"], 1.0);
        assert_eq!(j["trade"][0]["speedup_spread"], json!([1.0, 1.0]));
        assert_eq!(j["trade"][0]["speedup_median"], 1.0);
        assert_eq!(j["trade"][0]["round_seconds"], json!([2.0, 1.0]));
        assert_eq!(j["throughput"][0]["cells"], 4);
        let none = Bench { grid: 2, throughput: Vec::new(), trade: None }.to_json();
        assert_eq!(none["trade"], json!([]));
    }
}
