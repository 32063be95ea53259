//! The coexisting attractors of one parameter point ([`attractors`]), each
//! with its labels, a state on it, its stability and its basin fraction (see
//! `grid::attractors` for the sampling and the grouping); and the JSON object
//! of `attractors --json` ([`Attractors::to_json`]).

use crate::error::Result;
use crate::error::{Opt, RequestError};
use crate::record::CellRecord;
use crate::sim::{parameters_of, Sim, Start};
use grid::attractors::{find, Attractor, Sampling};
use grid::{Begin, Observer};
use serde::Serialize;
use serde_json::Value;
use solver::System;
use std::collections::BTreeMap;

/// Most samples one run may take.
pub const MAX_SAMPLES: usize = 1_000_000;

/// The attractors of one point to find.
#[derive(Debug, Clone)]
pub struct AttractorsRequest {
    /// The simulation options (the point is the scene's values with `set`).
    pub sim: Sim,
    /// Where the point is: the scene's values ([`Start::Initial`]), or the
    /// parameters of a stored cell with its file's settings
    /// ([`Start::Cell`]); a start state is refused, the attractors sample
    /// their own.
    pub point: Start,
    /// Start states sampled, how, and where (the box).
    pub sampling: Sampling,
    /// Worker threads.
    pub threads: usize,
}

impl AttractorsRequest {
    /// The attractors of the point of `sim`, sampled as
    /// [`Sampling::default`], on one thread per core.
    pub fn new(sim: Sim) -> AttractorsRequest {
        AttractorsRequest {
            sim,
            point: Start::Initial,
            sampling: Sampling::default(),
            threads: crate::threads(None).unwrap_or(1),
        }
    }
}

/// The attractors found.
#[derive(Debug, Clone)]
pub struct Attractors {
    /// The system at the point.
    pub system: System,
    /// The sampling.
    pub sampling: Sampling,
    /// The attractors, the most frequent first.
    pub found: Vec<Attractor>,
    /// A warning about the point (the scene differs from a stored one).
    pub warning: Option<String>,
    /// Which stored cell `--at` took, where it is off the values given
    /// ([`crate::Origin::note`]).
    pub note: Option<String>,
}

/// Finds the coexisting attractors of a point, reporting each sample done to
/// `observer` (which may stop the search).
pub fn attractors(r: &AttractorsRequest, observer: &dyn Observer) -> Result<Attractors> {
    if let Start::State(_) = r.point {
        let what = "the attractors sample their own start states: give a stored cell or the scene's point";
        return Err(RequestError::option(Opt::State).text(what).into());
    }
    let (s, origin) = r.sim.setup_from(&r.point)?;
    let k = r.sampling.samples;
    if k == 0 || k > MAX_SAMPLES {
        return Err(RequestError::option(Opt::Samples).text(format!("expected 1 to {MAX_SAMPLES}, got {k}")).into());
    }
    let (x, v) = (r.sampling.x, r.sampling.v);
    if !(x.is_finite() && v.is_finite() && x >= 0.0 && v >= 0.0) {
        return Err(RequestError::option(Opt::Box)
            .text(format!("expected X,V (two numbers >= 0), got '{x},{v}'"))
            .into());
    }
    let cs = s.cell_setup(0)?;
    observer.begin(&Begin { total: k as u64, done: 0, lines: &[], prior: None, line_len: 1, threads: r.threads });
    let found = find(&cs, &[], &r.sampling, r.threads, observer);
    observer.finish();
    let found = found?;
    let system = cs.system(&[])?;
    let (warning, note) = origin.map_or((None, None), |o| (o.warning, o.note));
    Ok(Attractors { system, sampling: r.sampling, found, warning, note })
}

impl Attractors {
    /// The names of the labelled masses.
    pub fn masses(&self) -> Vec<String> {
        self.system.model.labelled_masses()
    }

    /// An attractor's labels, one per labelled mass.
    pub fn labels(&self, at: &Attractor) -> Vec<String> {
        (0..self.system.model.labels.len()).map(|i| at.cell.labels[i].to_string()).collect()
    }

    /// The mass whose start states [`Attractors::basin`] gives: the first labelled one.
    pub fn basin_mass(&self) -> usize {
        self.system.model.labels.first().map_or(0, |l| l.mass)
    }

    /// The sampled start states that reach `at`, as `(x, v)` of
    /// [`Attractors::basin_mass`] (at t = 0).
    pub fn basin(&self, at: &Attractor) -> Vec<(f64, f64)> {
        let (mass, m) = (self.basin_mass(), self.system.dof());
        let state = |i: usize| grid::attractors::sample(&self.system, &self.sampling, i);
        at.members.iter().map(|&i| state(i)).map(|y| (y[mass], y[m + mass])).collect()
    }

    /// An attractor's basin fraction.
    pub fn fraction(&self, at: &Attractor) -> f64 {
        at.count as f64 / self.sampling.samples as f64
    }

    /// The attractors as their report ([`AttractorsReport`]).
    pub fn report(&self) -> AttractorsReport {
        let masses = self.masses();
        let attractors = self
            .found
            .iter()
            .map(|at| AttractorReport {
                record: CellRecord::of(&masses, &[], &at.cell),
                fraction: self.fraction(at),
                count: at.count,
                state: at.cell.final_state.clone(),
                start: at.start.clone(),
            })
            .collect();
        AttractorsReport {
            scene: self.system.model.name.clone(),
            parameters: parameters_of(&self.system),
            samples: self.sampling.samples,
            seed: self.sampling.seed,
            sample_box: SampleBox { x: self.sampling.x, v: self.sampling.v },
            attractors,
        }
    }

    /// The JSON object of the attractors (the contract of `attractors --json`).
    pub fn to_json(&self) -> Value {
        crate::report::to_value(&self.report())
    }
}

/// The JSON of a point's attractors (the contract of `attractors --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttractorsReport {
    /// The scene's name.
    pub scene: String,
    /// Every parameter of the point's model.
    pub parameters: BTreeMap<String, f64>,
    /// Start states sampled.
    pub samples: usize,
    /// The seed of the sampling.
    pub seed: u64,
    /// The half-widths of the box the start states were drawn from.
    #[serde(rename = "box")]
    pub sample_box: SampleBox,
    /// The attractors found, largest basin first.
    pub attractors: Vec<AttractorReport>,
}

/// The box of start states: positions within `±x`, velocities within `±v`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SampleBox {
    /// Half-width in position.
    pub x: f64,
    /// Half-width in velocity.
    pub v: f64,
}

/// One attractor found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttractorReport {
    /// Its classification, labels, stability, reason, final state and
    /// section points ([`CellRecord`]; no quantities are measured).
    #[serde(flatten)]
    pub record: CellRecord,
    /// The share of the samples that reached it.
    pub fraction: f64,
    /// The samples that reached it.
    pub count: usize,
    /// Its final state, from the first sample that reached it (the record's
    /// `final_state`, under the name `attractors --json` first gave it).
    pub state: Vec<f64>,
    /// That sample's start state.
    pub start: Vec<f64>,
}
