//! The vibroatlas solver: exact event-driven simulation of piecewise-linear
//! vibro-impact systems under harmonic forcing, and n-p-q classification.
//!
//! Physics stages, one module each (private unless named below): `system`
//! (matrices of `M x'' + C x' + K x = P sin(ωt+τ)`, stop gaps, friction
//! contacts), [`mode`] (the linear system with held stops and stuck or
//! slipping contacts), [`flow`] (exact modal flow and RK4, event location),
//! `impact` (Newton's law with momentum exchange), `chatter` and `stick`
//! (accumulation, sticking, stick/slip), `simulate` (the event loop, period by
//! period, with exact tangent maps), `classify` (period detection, labels).
//! Stability: `newton` (fixed points of period and half maps), [`floquet`]
//! (multipliers, kinds of bifurcation), [`orbit`], [`continuation`] and
//! [`arclength`] (branches and located bifurcations), [`lyapunov`].
//! [`reference`](mod@reference) holds closed-form answers shared by tests and benches. No
//! I/O, no threads.
//!
//! The public API: a [`System`] is built from an evaluated scene model; a cell
//! is run by [`run_cell`] (or [`run_cell_with_sections`]) with an [`Accuracy`]
//! (from a [`Preset`], knobs checked by [`Accuracy::set`]) and a [`Method`],
//! giving a [`CellResult`] (its [`Class`], [`MassLabel`]s of [`Count`]s,
//! [`Symmetry`], stability); a [`Simulator`] runs period by period for
//! observers ([`Observer`], [`EventKind`]); [`orbit_of_cell`] and [`solve`]
//! find periodic orbits, [`multipliers`] their Floquet multipliers.
//!
//! ```
//! let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../configs/multi-stop.toml")).unwrap();
//! let scene = scene::Scene::parse(&text).unwrap();
//! let model = scene.evaluate(&[("omega".into(), 2.5), ("delta".into(), 1.2)]).unwrap();
//! let y0 = model.initial_state();
//! let sys = solver::System::new(model).unwrap();
//! let cell = solver::run_cell(&sys, &solver::Accuracy::default(), solver::Method::Exact, &y0);
//! assert_eq!(cell.labels[0].to_string(), "1-0-0");
//! ```
#![deny(missing_docs)]
#![deny(clippy::float_cmp)]

mod accuracy;
pub mod arclength;
mod chatter;
mod classify;
pub mod continuation;
mod error;
pub mod floquet;
pub mod flow;
mod impact;
pub mod lyapunov;
pub mod mode;
mod newton;
pub mod orbit;
pub mod reference;
mod section;
mod simulate;
mod stick;
mod system;

pub use accuracy::{Accuracy, Preset, LIMITS};
pub use classify::{run_cell, run_cell_with_sections, CellResult, Class, Count, MassLabel, Symmetry};
pub use error::SolverError;
pub use floquet::{multipliers, Bifurcation};
pub use flow::Method;
/// Matrix type of Jacobians and monodromy matrices.
pub use nalgebra::DMatrix;
/// Column vector type of states passed to observers.
pub use nalgebra::DVector;
pub use newton::{solve, MapKind, Solution};
/// Complex numbers of Floquet multipliers.
pub use num_complex::Complex64;
pub use orbit::{orbit_of_cell, Orbit, OrbitError};
pub use simulate::{EventKind, Halt, Ignore, Observer, PeriodRecord, Simulator};
pub use system::System;
