//! Command-line arguments as clap structures (raw, before validation).

use clap::{Args, Parser, Subcommand};
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
}

/// Options shared by every command that simulates a scene.
#[derive(Debug, Args, Clone)]
pub struct SimArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Override a scene parameter, e.g. `--set omega=0.33` (repeatable).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Accuracy preset: fast, standard or precise.
    #[arg(long, default_value = "standard")]
    pub preset: String,
    /// Override one accuracy knob, e.g. `--accuracy max_periods=2000` (repeatable).
    /// Knobs: event_tol, contact_tol, stick_velocity, chatter_velocity,
    /// min_transient, max_periods, periodic_tol, n_max, chatter_impacts,
    /// max_events, rk4_step, rk4_min_step.
    #[arg(long = "accuracy", value_name = "KNOB=VALUE")]
    pub accuracy: Vec<String>,
    /// Integrator: exact (closed-form flow) or rk4 (fixed step, the literature's method).
    #[arg(long, default_value = "exact")]
    pub integrator: String,
}

#[derive(Debug, Args)]
pub struct CellArgs {
    #[command(flatten)]
    pub sim: SimArgs,
    /// Print one JSON object instead of the human-readable summary.
    #[arg(long)]
    pub json: bool,
    /// Write the classified window as CSV (t, every coordinate and velocity).
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
    /// Samples per forcing period in the trace.
    #[arg(long, default_value_t = 200, value_name = "N")]
    pub trace_samples: usize,
}
