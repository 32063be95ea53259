//! The coexisting attractors of one parameter point ([`attractors`]), each
//! with its labels, a state on it, its stability and its basin fraction (see
//! `grid::attractors` for the sampling and the grouping); and the JSON object
//! of `attractors --json` ([`Attractors::to_json`]).

use crate::error::{Opt, RequestError};
use crate::observer::{Begin, Observed, Observer};
use crate::sim::{parameters_json, Sim};
use anyhow::{bail, Result};
use grid::attractors::{find, Attractor, Sampling};
use serde_json::{json, Value};
use solver::System;

/// Most samples one run may take.
pub const MAX_SAMPLES: usize = 1_000_000;

/// The attractors of one point to find.
#[derive(Debug, Clone)]
pub struct AttractorsRequest {
    /// The simulation options (the point is the scene's values with `set`).
    pub sim: Sim,
    /// Start states sampled, how, and where (the box).
    pub sampling: Sampling,
    /// Worker threads.
    pub threads: usize,
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
}

/// Finds the coexisting attractors of a point, reporting each sample done to
/// `observer` (which may stop the search).
pub fn attractors(r: &AttractorsRequest, observer: &dyn Observer) -> Result<Attractors> {
    let s = r.sim.setup()?;
    let k = r.sampling.samples;
    if k == 0 || k > MAX_SAMPLES {
        bail!(RequestError::option(Opt::Samples).text(format!("expected 1 to {MAX_SAMPLES}, got {k}")));
    }
    let (x, v) = (r.sampling.x, r.sampling.v);
    if !(x.is_finite() && v.is_finite() && x >= 0.0 && v >= 0.0) {
        bail!(RequestError::option(Opt::Box).text(format!("expected X,V (two numbers >= 0), got '{x},{v}'")));
    }
    let cs = s.cell_setup(0)?;
    observer.begin(&Begin { total: k as u64, done: 0, lines: &[], prior: None, line_len: 1, threads: r.threads });
    let found = find(&cs, &[], &r.sampling, r.threads, &Observed(observer));
    observer.finish();
    let found = found?;
    let system = cs.system(&[])?;
    Ok(Attractors { system, sampling: r.sampling, found })
}

impl Attractors {
    /// The names of the labelled masses.
    pub fn masses(&self) -> Vec<String> {
        let m = &self.system.model;
        m.labels.iter().map(|l| m.masses[l.mass].name.clone()).collect()
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

    /// The JSON object of the attractors (the contract of `attractors --json`).
    pub fn to_json(&self) -> Value {
        let masses = self.masses();
        let list: Vec<Value> = self
            .found
            .iter()
            .map(|at| {
                let c = &at.cell;
                json!({
                    "class": c.class.name(),
                    "labels": masses.iter().cloned().zip(self.labels(at).into_iter().map(Value::from)).collect::<serde_json::Map<_, _>>(),
                    "symmetry": c.symmetry.map(|x| x.name()),
                    "fraction": self.fraction(at),
                    "count": at.count,
                    "state": c.final_state,
                    "start": at.start,
                    "max_multiplier": c.multiplier,
                    "lyapunov": c.lyapunov,
                })
            })
            .collect();
        json!({
            "scene": self.system.model.name,
            "parameters": parameters_json(&self.system),
            "samples": self.sampling.samples,
            "seed": self.sampling.seed,
            "box": {"x": self.sampling.x, "v": self.sampling.v},
            "attractors": list,
        })
    }
}
