//! Command-line arguments as clap structures (raw, before validation).

use clap::{Args, Parser, Subcommand};
use grid::attractors::Sampling;
pub use scene::named_arg as named;
use scene::Named;
use std::path::PathBuf;

/// Maps the dynamics of vibro-impact systems: n-p-q labels of periodic impact
/// motions, chattering and sticking, over parameter planes.
#[derive(Debug, Parser)]
#[command(name = "vibroatlas", version, about)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate one cell (one set of parameters) and classify its steady motion.
    Cell(CellArgs),
    /// Continuation along one parameter (a bifurcation diagram).
    Sweep(SweepArgs),
    /// Map a parameter plane in parallel, fresh or by up/down continuation.
    Atlas(AtlasArgs),
    /// Compute a box of a stored atlas again on a finer grid, its chains entering from the parent.
    Zoom(ZoomArgs),
    /// Explore an atlas in the browser: hover, click a cell for its motion, drag a box to zoom.
    Explore(ExploreArgs),
    /// One atlas per value of a parameter, and a contact sheet comparing them.
    Study(StudyArgs),
    /// Draw the coloured map of an atlas file.
    Render(RenderArgs),
    /// Merge shard files into one atlas.
    Merge(MergeArgs),
    /// Measure throughput on 1 and 2 threads and the speed/accuracy trade.
    Bench(BenchArgs),
    /// Print a summary of an atlas file.
    Inspect(InspectArgs),
    /// Solve one periodic orbit by Newton's method: fixed point, impacts, Floquet multipliers.
    Orbit(OrbitArgs),
    /// Follow one periodic orbit along a parameter and locate its bifurcations.
    Continue(ContinueArgs),
    /// Find the coexisting attractors of one parameter point from sampled initial states.
    Attractors(AttractorsArgs),
    /// Map the basins of attraction of one parameter point over a grid of initial states.
    Basins(BasinsArgs),
    /// Follow a bifurcation (PD, SN, PF, NS, grazing) in a plane of two parameters.
    Curve(CurveArgs),
    /// Find the bifurcation curves of a stored map: seeded where neighbouring labels differ.
    Curves(CurvesArgs),
}

#[derive(Debug, Args)]
pub struct CurvesArgs {
    /// Atlas file.
    pub file: PathBuf,
    /// Kinds of bifurcation looked for, comma-separated.
    #[arg(long, value_parser = named::<solver::Bifurcation>(), value_delimiter = ',', default_value = "pd,sn,pf,ns,grazing")]
    pub kinds: Vec<solver::Bifurcation>,
    /// Most curves found.
    #[arg(long, default_value_t = 8, value_name = "K", allow_negative_numbers = true)]
    pub max: usize,
    /// The sweep whose label boundaries seed the curves (default: every sweep
    /// of the file, so that both ends of hysteresis zones are seeds).
    #[arg(long, value_parser = named::<grid::SweepKind>())]
    pub sweep: Option<grid::SweepKind>,
    /// Output curve file (for render --curves).
    #[arg(short = 'o', long = "output", value_name = "CURVES.h5")]
    pub output: Option<PathBuf>,
    /// Also store the curves in the atlas itself (its `curves` group, replaced
    /// if there is one; `render ATLAS --curves ATLAS` draws them).
    #[arg(long)]
    pub into: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct CurveArgs {
    #[command(flatten)]
    pub sim: SimArgs,
    /// The bifurcation followed.
    #[arg(long, value_parser = named::<solver::Bifurcation>())]
    pub kind: solver::Bifurcation,
    /// Where to start: NAME=VALUE,NAME=VALUE of the two free parameters (the
    /// bifurcation is located near the first value).
    #[arg(long, value_name = "A=VALUE,B=VALUE")]
    pub start: String,
    /// The two free parameters A,B: A is located, B is stepped.
    #[arg(long, value_name = "A,B")]
    pub free: String,
    /// The last value of B (default: the curve is followed both ways from
    /// the start, within the scene's range of B, until it ends, in steps of B
    /// as large as --window).
    #[arg(long, value_name = "VALUE", allow_negative_numbers = true)]
    pub to: Option<f64>,
    /// Steps from the start to --to (the curve takes at most 10 × STEPS + 1
    /// points each way).
    #[arg(long, default_value_t = engine::DEFAULT_STEPS, allow_negative_numbers = true)]
    pub steps: usize,
    /// Half-width of the search for the bifurcation in A around its prediction.
    #[arg(long, default_value_t = engine::DEFAULT_WINDOW, value_name = "W", allow_negative_numbers = true)]
    pub window: f64,
    /// Range of A the curve may take, A=LO:HI (default: the scene's range of
    /// A); B stays between its start and --to.
    #[arg(long, value_name = "A=LO:HI")]
    pub bounds: Option<String>,
    /// Period of the orbit in forcing periods (default: the cell's).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub n: Option<usize>,
    /// Start the first cell, at --start, from this state `x1,x2,…,v1,v2,…`
    /// (default: the scene's initial state): where orbits coexist, the curve
    /// of the one it reaches.
    #[arg(long, value_name = "X…,V…", allow_hyphen_values = true)]
    pub state: Option<String>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Write the curve to a self-describing HDF5 file (for `render --curves`).
    #[arg(short = 'o', long = "output", value_name = "FILE.h5")]
    pub output: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct AttractorsArgs {
    #[command(flatten)]
    pub sim: SimArgs,
    /// The point: with --from, a stored cell's parameters and its run's
    /// settings (the attractors sample their own start states: --state is refused).
    #[command(flatten)]
    pub start: FromArgs,
    /// Initial states sampled.
    #[arg(long, default_value_t = Sampling::default().samples, value_name = "K")]
    pub samples: usize,
    /// Seed of the (deterministic) sampling.
    #[arg(long, default_value_t = Sampling::default().seed)]
    pub seed: u64,
    /// Half-widths X,V of the box of initial positions and velocities.
    #[arg(long = "box", default_value_t = default_box(), value_name = "X,V")]
    pub sample_box: String,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Draw the sampled initial states of the first labelled mass, coloured by
    /// the attractor they reach (.png, .svg or .pdf).
    #[arg(long, value_name = "FILE")]
    pub png: Option<PathBuf>,
    #[command(flatten)]
    pub figure: FigureArgs,
}

#[derive(Debug, Args)]
pub struct BasinsArgs {
    #[command(flatten)]
    pub sim: SimArgs,
    /// The state outside the two axes (and, with --from, the point's parameters).
    #[command(flatten)]
    pub start: FromArgs,
    /// Horizontal axis: a state component and its starts, e.g. x_M2=-2:2:200.
    #[arg(long, value_name = "COMPONENT=START:STOP:COUNT", allow_hyphen_values = true)]
    pub x: String,
    /// Vertical axis: a state component and its starts, e.g. v_M2=-3:3:200.
    #[arg(long, value_name = "COMPONENT=START:STOP:COUNT", allow_hyphen_values = true)]
    pub y: String,
    /// The forcing phase omega t + tau at the start, in radians (default: the scene's tau).
    #[arg(long, value_name = "RADIANS", allow_negative_numbers = true)]
    pub phase: Option<f64>,
    /// Stop a start once it comes within 1e-6 of a stable periodic attractor
    /// already found, rather than running its full record (docs/basins.md).
    #[arg(long)]
    pub early_stop: bool,
    /// The basin file written (netCDF-4/HDF5).
    #[arg(short = 'o', long = "output", value_name = "FILE.h5")]
    pub output: PathBuf,
    /// Also draw the basins (.png, .svg or .pdf).
    #[arg(long, value_name = "FILE")]
    pub png: Option<PathBuf>,
    #[command(flatten)]
    pub figure: FigureArgs,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress bar or progress lines.
    #[arg(long)]
    pub quiet: bool,
}

/// Options shared by every command that simulates a scene.
#[derive(Debug, Args, Clone)]
pub struct SimArgs {
    /// Scene file (TOML). With --from, the scene stored in that file when not given.
    #[arg(required = true)]
    pub scene: Option<PathBuf>,
    /// Override a scene parameter, e.g. `--set omega=0.33` (repeatable, each parameter once).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Accuracy preset (default: standard).
    #[arg(long, value_parser = named::<solver::Preset>())]
    pub preset: Option<solver::Preset>,
    // Its help names every knob of the `knobs!` table, in order.
    #[arg(long = "accuracy", value_name = "KNOB=VALUE", help = accuracy_help())]
    pub accuracy: Vec<String>,
    /// Integrator: exact (closed-form flow, default) or rk4 (fixed step, the literature's method).
    #[arg(long, value_parser = named::<solver::Method>())]
    pub integrator: Option<solver::Method>,
}

/// Where a simulation starts: a cell of a stored atlas or sweep file, or a
/// state given on the command line (default: the scene's initial state).
#[derive(Debug, Args, Clone, Default)]
pub struct FromArgs {
    /// Start from a cell of this atlas or sweep file (its parameters, its
    /// stored states, and its run's preset, knobs and integrator unless given).
    #[arg(long, value_name = "FILE.h5")]
    pub from: Option<PathBuf>,
    /// The cell of --from: the grid cell nearest to NAME=VALUE,NAME=VALUE.
    #[arg(long, value_name = "NAME=VALUE,NAME=VALUE", requires = "from")]
    pub at: Option<String>,
    /// The sweep of --from the cell is taken from: fresh, up or down (default:
    /// the file's first).
    #[arg(long = "sweep", value_parser = named::<grid::SweepKind>(), value_name = "SWEEP", requires = "from")]
    pub from_sweep: Option<grid::SweepKind>,
    /// Start from this state `x1,x2,…,v1,v2,…` at the scene's forcing phase
    /// (t = 0; change the phase with --set on the scene's phase parameter).
    #[arg(long, value_name = "X…,V…", conflicts_with = "from", allow_hyphen_values = true)]
    pub state: Option<String>,
}

#[derive(Debug, Args)]
pub struct CellArgs {
    #[command(flatten)]
    pub sim: SimArgs,
    #[command(flatten)]
    pub start: FromArgs,
    /// Print one JSON object instead of the human-readable summary.
    #[arg(long)]
    pub json: bool,
    /// Write the classified window as CSV (t, every coordinate and velocity).
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
    /// Samples per forcing period in the trace.
    #[arg(long, default_value_t = 200, value_name = "N")]
    pub trace_samples: usize,
    /// Draw the Poincaré sections of the steady motion to a PNG: the period
    /// section (first labelled mass, t = kT) and the impact section of each stop.
    #[arg(long, value_name = "FILE")]
    pub section_png: Option<PathBuf>,
    /// Forcing periods simulated for the section PNG, from the final state.
    #[arg(long, default_value_t = engine::DEFAULT_SECTION_PERIODS, value_name = "N")]
    pub section_periods: usize,
    /// Draw phase portraits (x against v of each mass, stops drawn, impacts
    /// marked) and the time series of the positions with their events, over
    /// the classified window (.png, .svg or .pdf).
    #[arg(long, value_name = "FILE")]
    pub portrait: Option<PathBuf>,
    #[command(flatten)]
    pub figure: FigureArgs,
}

#[derive(Debug, Args)]
pub struct OrbitArgs {
    #[command(flatten)]
    pub sim: SimArgs,
    #[command(flatten)]
    pub start: FromArgs,
    /// Period in forcing periods (default: the period of the simulated cell).
    #[arg(long, value_name = "N")]
    pub n: Option<usize>,
    /// Print one JSON object instead of the human-readable summary.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct ContinueArgs {
    #[command(flatten)]
    pub sim: SimArgs,
    #[command(flatten)]
    pub start: FromArgs,
    /// Parameter to follow, NAME=START:STOP:COUNT (the orbit is found at START).
    #[arg(long, value_name = "NAME=START:STOP:COUNT")]
    pub axis: String,
    /// Period of the orbit in forcing periods (default: the period of the cell at START).
    #[arg(long, value_name = "N")]
    pub n: Option<usize>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Draw the branch (stable solid, unstable light, bifurcations marked) to a PNG.
    #[arg(long, value_name = "FILE")]
    pub png: Option<PathBuf>,
    /// Pseudo-arclength continuation (follows the branch around folds; the grid
    /// step is the largest step) instead of natural continuation on the grid.
    #[arg(long)]
    pub arclength: bool,
    #[command(flatten)]
    pub figure: FigureArgs,
}

/// Options of commands that compute many cells.
#[derive(Debug, Args, Clone)]
pub struct RunArgs {
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Largest number of points kept per raw section per cell.
    #[arg(long, default_value_t = grid::DEFAULT_SECTION_CAP, value_name = "N")]
    pub section_cap: usize,
    /// No progress bar or progress lines.
    #[arg(long)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct AtlasArgs {
    #[command(flatten)]
    pub sim: SimArgs,
    /// Horizontal axis, NAME=START:STOP:COUNT (ascending).
    #[arg(long, value_name = "NAME=START:STOP:COUNT")]
    pub x: String,
    /// Vertical axis, NAME=START:STOP:COUNT (ascending).
    #[arg(long, value_name = "NAME=START:STOP:COUNT")]
    pub y: String,
    #[command(flatten)]
    pub options: engine::AtlasOptions,
    /// Output HDF5 file.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: std::path::PathBuf,
    #[command(flatten)]
    pub run: RunArgs,
}

#[derive(Debug, Args)]
pub struct ExploreArgs {
    /// The atlas file.
    #[arg(value_name = "FILE.h5")]
    pub file: std::path::PathBuf,
    /// Port on 127.0.0.1 (0: a free one; the URL is printed).
    #[arg(long, default_value_t = 8765)]
    pub port: u16,
    /// Do not open a browser; only print the URL.
    #[arg(long)]
    pub no_browser: bool,
    /// Worker threads of zooms and attractor searches (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

#[derive(Debug, Args)]
pub struct ZoomArgs {
    /// The parent atlas.
    #[arg(value_name = "PARENT.h5")]
    pub parent: std::path::PathBuf,
    /// The box along the parent's x axis, NAME=START:STOP:COUNT (ascending, within the parent's).
    #[arg(long, value_name = "NAME=START:STOP:COUNT")]
    pub x: String,
    /// The box along the parent's y axis, NAME=START:STOP:COUNT (ascending, within the parent's).
    #[arg(long, value_name = "NAME=START:STOP:COUNT")]
    pub y: String,
    /// The sweeps computed, among the parent's (default: all of them).
    #[arg(long, value_parser = named::<grid::Sweeps>())]
    pub sweep: Option<grid::Sweeps>,
    /// Compute the box at another value of a scene parameter that is not an
    /// axis, e.g. `--set zeta=0.07` (repeatable): a slice beside the parent's plane.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Output HDF5 file (an atlas that records its parent).
    #[arg(short = 'o', long = "output", value_name = "CHILD.h5")]
    pub output: std::path::PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress bar or summary.
    #[arg(long)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub sim: SimArgs,
    #[command(flatten)]
    pub start: FromArgs,
    /// Swept parameter, NAME=START:STOP:COUNT, run in that order (START > STOP sweeps down).
    #[arg(long, value_name = "NAME=START:STOP:COUNT")]
    pub axis: String,
    /// Run in the given order (default), or up, down, or both directions (each
    /// from the scene's initial state); or a hysteresis loop, down-up or
    /// up-down: the second leg starts from the first leg's end state.
    #[arg(long)]
    #[arg(value_parser = named::<engine::Direction>())]
    pub direction: Option<engine::Direction>,
    /// Output HDF5 file (same layout as an atlas with one row).
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<std::path::PathBuf>,
    /// Bifurcation diagram (.png, .svg or .pdf): up and down sweeps both drawn.
    #[arg(long, value_name = "FILE")]
    pub png: Option<std::path::PathBuf>,
    /// Section points kept per cell for the diagram (dense chaotic bands need
    /// more; overrides --section-cap).
    #[arg(long, value_name = "N")]
    pub points: Option<usize>,
    /// State component of the diagram's period-section panel, e.g. x_M1 or v_M2
    /// (default: the position of the first labelled mass), or a quantity of
    /// the steady motion (max_abs_x_M1: the amplitude–frequency response).
    #[arg(long, value_name = "COMPONENT|QUANTITY")]
    pub variable: Option<String>,
    /// What the diagram's impact panels show: speed or phase.
    #[arg(long, value_parser = named::<render::Impact>(), default_value_t = render::Impact::Speed)]
    pub impact: render::Impact,
    /// Accepted and ignored, for scripts that pass it: an output that exists
    /// and is not a regular file (a device, a pipe) is always refused.
    #[arg(long)]
    pub force: bool,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub run: RunArgs,
    #[command(flatten)]
    pub figure: FigureArgs,
}

#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Shard files to merge.
    #[arg(required = true)]
    pub parts: Vec<std::path::PathBuf>,
    /// Output HDF5 file.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: std::path::PathBuf,
    /// Write the merged file even when shards are missing (their cells stay
    /// `not computed`); without it a missing shard is an error.
    #[arg(long)]
    pub allow_missing: bool,
    /// Accepted and ignored, for scripts that pass it: an output that exists
    /// and is not a regular file (a device, a pipe) is always refused.
    #[arg(long)]
    pub force: bool,
}

#[derive(Debug, Args)]
pub struct InspectArgs {
    /// Atlas file.
    pub file: std::path::PathBuf,
    /// Print the summary as one JSON object (grid, sweeps, class and label
    /// counts, hysteresis zones, run time).
    #[arg(long)]
    pub json: bool,
    /// Check the whole file first: every group, dataset and attribute that
    /// vibroatlas writes for the file's content is read back and compared
    /// (what `atlas --resume` and `merge` check); a difference is an error
    /// naming it.
    #[arg(long)]
    pub verify: bool,
    /// Where a number stored per cell (a quantity of the steady motion:
    /// max_abs_x_M1, power_in; or multiplier, lyapunov) is smallest and
    /// largest over each sweep's plane, and the cells' parameters there.
    #[arg(long, value_name = "NAME")]
    pub quantity: Option<String>,
    /// With --quantity: only this sweep (fresh, up or down).
    #[arg(long, value_name = "SWEEP")]
    pub sweep: Option<String>,
}

/// The printed size of figures: without `--size`, each figure's screen size.
#[derive(Debug, Clone, Args)]
pub struct FigureArgs {
    /// Print size of figures: single (one journal column, 86 mm wide), double
    /// (two columns, 178 mm) or WxH in millimetres (e.g. 120x80); text in
    /// points, never below 6 pt (default: a screen-sized canvas).
    #[arg(long, value_name = "single|double|WxH")]
    pub size: Option<String>,
    /// Body text size in points at a print size (6 to 24; default 8).
    #[arg(long = "font-size", value_name = "PT", allow_negative_numbers = true)]
    pub font_size: Option<f64>,
    /// Resolution of PNG figures at a print size (72 to 1200; default 300).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub dpi: Option<i64>,
}

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Atlas file.
    pub file: std::path::PathBuf,
    /// Output picture: .png, .svg or .pdf.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: std::path::PathBuf,
    /// Labelled mass to draw (default: the first).
    #[arg(long)]
    pub mass: Option<String>,
    /// fresh, up, down, or hysteresis (the labels of up and down where they
    /// differ; with --view of a quantity, its up sweep less its down sweep).
    #[arg(long)]
    #[arg(value_parser = named::<render::View>())]
    pub sweep: Option<render::View>,
    /// labels (default), lyapunov (largest exponent of cells without a period),
    /// multiplier (largest |Floquet multiplier| of periodic cells), attractors
    /// (the number of coexisting attractors, atlas --attractors), basin:ID
    /// (the basin fraction of attractor family ID, followed from cell to cell;
    /// 0 the largest), or a quantity of the steady motion the file stores
    /// (max_abs_x_M1, power_in).
    #[arg(long, default_value = "labels", value_name = "labels|lyapunov|multiplier|attractors|basin:ID|QUANTITY")]
    pub view: String,
    /// Draw one row of the atlas as a bifurcation diagram: the row nearest to
    /// NAME=VALUE of the y axis (a sweep file is drawn as a diagram anyway).
    #[arg(long, value_name = "NAME=VALUE")]
    pub row: Option<String>,
    /// State component of a diagram's period-section panel, e.g. x_M1 or v_M2,
    /// or a stored quantity of the steady motion (max_abs_x_M1).
    #[arg(long, value_name = "COMPONENT|QUANTITY")]
    pub variable: Option<String>,
    /// What a diagram's impact panels show: speed or phase.
    #[arg(long, value_parser = named::<render::Impact>(), default_value_t = render::Impact::Speed)]
    pub impact: render::Impact,
    /// Bifurcation curves (files of `curve -o`) drawn over the label map (repeatable).
    #[arg(long, value_name = "CURVE.h5")]
    pub curves: Vec<PathBuf>,
    /// Contour lines of a continuous view (a quantity, lyapunov, multiplier)
    /// at up to N round levels (1 to 50), marked on its colour bar.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=50))]
    pub contours: Option<u16>,
    #[command(flatten)]
    pub figure: FigureArgs,
}

#[derive(Debug, Args)]
pub struct StudyArgs {
    /// Study file (TOML): scene, parameter, values, axes, sweep.
    pub study: std::path::PathBuf,
    /// Output folder: one atlas and map per value, and contact-sheet.png.
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    pub output: std::path::PathBuf,
    /// Accuracy preset.
    #[arg(long, value_parser = named::<solver::Preset>(), default_value_t = solver::Preset::Standard)]
    pub preset: solver::Preset,
    #[command(flatten)]
    pub run: RunArgs,
    #[command(flatten)]
    pub figure: FigureArgs,
}

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Thread counts to measure, comma-separated [default: 1,2; with --paper: 1].
    #[arg(long)]
    pub threads: Option<String>,
    /// Grid size N (N x N cells of the reference plane ω ∈ [0.1, 3.05], δ ∈ [0.05, 2])
    /// [default: 48; with --paper: 128].
    #[arg(long)]
    pub grid: Option<usize>,
    /// Scene (default: the shipped multi-stop scene).
    #[arg(long)]
    pub scene: Option<std::path::PathBuf>,
    /// Also measure the speed/accuracy trade of every preset and of RK4 against `precise`.
    #[arg(long)]
    pub trade: bool,
    /// Timed repetitions of each throughput measurement (the best is reported).
    #[arg(long, default_value_t = 3)]
    pub repeat: usize,
    /// Rounds of the trade: each times every setting once, in table order (the
    /// best of each setting is reported) [default: 1; with --paper: 4].
    #[arg(long)]
    pub trade_repeat: Option<usize>,
    /// Only the lead over the literature's method, per thread: `standard` and
    /// `standard chaos_check=0` against RK4 h = 0.01 in rounds (`precise`, the
    /// reference of the agreement, timed once), on a grid where each side runs
    /// for seconds; prints each one's median speed-up and its spread. No
    /// throughput.
    #[arg(long, conflicts_with = "trade")]
    pub paper: bool,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Folder for trade.png (the Pareto front of agreement against cells/s).
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    pub output: Option<std::path::PathBuf>,
}

/// The help of `--accuracy`: every knob of [`solver::Knob::ALL`], in order.
fn accuracy_help() -> String {
    let knobs: Vec<&str> = solver::Knob::ALL.iter().map(|k| k.name()).collect();
    format!(
        "Override one accuracy knob, e.g. `--accuracy max_periods=2000` (repeatable, each knob once). Knobs: {}",
        knobs.join(", ")
    )
}

/// The default box of initial states, `X,V` (`--box`).
fn default_box() -> String {
    let s = Sampling::default();
    format!("{},{}", s.x, s.v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::builder::TypedValueParser;
    use clap::CommandFactory;
    use std::ffi::OsStr;

    /// Every name of `T` reads back as its value through the parser.
    fn reads_back<T: Named + Clone + Send + Sync + PartialEq + std::fmt::Debug>() {
        let cmd = Cli::command();
        for &v in T::ALL {
            assert_eq!(named::<T>().parse_ref(&cmd, None, OsStr::new(v.name())).unwrap(), v);
        }
    }

    #[test]
    fn every_value_of_every_named_argument_reads_back() {
        reads_back::<solver::Preset>();
        reads_back::<solver::Method>();
        reads_back::<solver::Bifurcation>();
        reads_back::<grid::SweepKind>();
        reads_back::<grid::Sweeps>();
        reads_back::<grid::Along>();
        reads_back::<engine::AttractorCells>();
        reads_back::<engine::Direction>();
        reads_back::<render::Impact>();
        reads_back::<render::View>();
    }

    /// A mistyped name is refused by clap's error naming the flag, the
    /// values and the closest; a bifurcation's kind reads in either case.
    #[test]
    fn a_mistyped_name_is_refused_with_the_closest_and_the_values() {
        let e = Cli::try_parse_from(["vibroatlas", "cell", "s.toml", "--preset", "precize"]).unwrap_err();
        assert_eq!(e.kind(), clap::error::ErrorKind::InvalidValue);
        let text = e.to_string();
        assert!(text.contains("'precize'") && text.contains("--preset"), "{text}");
        assert!(text.contains("[possible values: fast, standard, precise]"), "{text}");
        assert!(text.contains("a similar value exists: 'precise'"), "{text}");
        let sweep =
            Cli::try_parse_from(["vibroatlas", "sweep", "s.toml", "--axis", "omega=1:2:3", "--direction", "downup"]);
        assert!(sweep.unwrap_err().to_string().contains("'down-up'"));
        let Command::Curve(c) = Cli::try_parse_from([
            "vibroatlas",
            "curve",
            "s.toml",
            "--kind",
            "pd",
            "--start",
            "a=1,b=2",
            "--free",
            "a,b",
        ])
        .unwrap()
        .command
        else {
            panic!("not curve")
        };
        assert_eq!(c.kind, solver::Bifurcation::PeriodDoubling);
    }

    /// `--help` lists each value with the help line of its library doc.
    #[test]
    fn the_help_lists_each_value_with_its_library_help() {
        let mut cli = Cli::command();
        let help = cli.find_subcommand_mut("cell").unwrap().render_long_help().to_string();
        for &p in <solver::Preset as Named>::ALL {
            let line = help.lines().find(|l| l.trim_start().starts_with(&format!("- {}:", p.name())));
            assert!(line.is_some_and(|l| l.ends_with(p.help())), "{help}");
        }
    }

    /// Every command that simulates names every knob of the table in its
    /// `--accuracy` help, and no other.
    #[test]
    fn the_accuracy_help_names_every_knob() {
        let mut cli = Cli::command();
        for name in ["cell", "sweep", "atlas", "basins"] {
            let help = cli.find_subcommand_mut(name).unwrap().render_long_help().to_string();
            let listed = help.split("Knobs: ").nth(1).unwrap().lines().next().unwrap().replace(' ', "");
            let want: Vec<&str> = solver::Knob::ALL.iter().map(|k| k.name()).collect();
            assert_eq!(listed.split(',').collect::<Vec<_>>(), want, "{name}");
        }
    }
}
