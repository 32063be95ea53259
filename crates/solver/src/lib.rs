//! The vibroatlas solver: exact event-driven simulation of piecewise-linear
//! vibro-impact systems under harmonic forcing, and n-p-q classification.
//!
//! Physics stages, one private module each: `system` (matrices of
//! `M x'' + C x' + K x = Σ_k (P_k sin kφ + Q_k cos kφ) + L`, stop gaps, friction contacts), `mode`
//! (the linear system with held stops and stuck or slipping contacts), `flow`
//! (exact modal flow and RK4, event location), `impact` (Newton's law with
//! momentum exchange), `chatter` and `stick` (accumulation, sticking,
//! stick/slip), `soft` (soft stops' contacts), `simulate` (the event loop, period by period, with exact
//! tangent maps). Classification: `executor` (the phases of one cell and its
//! budget), `period` (period detection), `acceleration` (Newton acceleration
//! of transients), `label` (classes, n-p-q labels), `lyapunov`, `circle`
//! (closed curves of the period section, rotation numbers), `section`
//! (impact sections). Stability, public modules: [`floquet`] (multipliers,
//! kinds of bifurcation), [`orbit`], [`continuation`] and [`arclength`]
//! (branches and located bifurcations), [`curve`] (bifurcations followed in
//! a plane of two parameters); `newton` (fixed points of period and
//! half maps) is re-exported. [`reference`](mod@reference) holds closed-form
//! answers shared by tests and benches. No I/O, no threads.
//!
//! # Public API
//!
//! - Set-up: a [`System`] is built from an evaluated scene model; an
//!   [`Accuracy`] comes from a [`Preset`] and its knobs are changed only
//!   through [`Accuracy::set`], within each [`Knob`]'s limits; a [`Method`] picks the
//!   integrator.
//! - Cells: [`run_cell`] and [`run_cell_with_sections`] give a [`CellResult`]:
//!   its [`Class`], a [`MassLabel`] ([`Label`] of [`Count`]s) per labelled
//!   mass, [`Mask`]s of stops that chattered or stuck, [`Symmetry`],
//!   stability, and an [`Unresolved`] reason where it has no class.
//! - Motions: a [`Simulator`] runs period by period ([`PeriodRecord`]) and
//!   tells an [`EventObserver`] what happens ([`EventKind`]), or [`Halt`]s.
//! - Stability: [`orbit_of_cell`] and [`solve`] find periodic orbits,
//!   [`multipliers`] their Floquet multipliers, [`Exponent`] the largest
//!   Lyapunov exponent of any motion, with its confidence [`Interval`].
//!
//! ```
//! let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../configs/multi-stop.toml")).unwrap();
//! let scene = scene::Scene::parse(&text).unwrap();
//! let model = scene.evaluate(&[("omega".into(), 0.33), ("delta".into(), 0.6)]).unwrap();
//! let y0 = model.initial_state();
//! let sys = solver::System::new(model).unwrap();
//! let cell = solver::run_cell(&sys, &solver::Accuracy::default(), solver::Method::Exact, &y0);
//! assert_eq!(cell.class, solver::Class::Periodic);
//! // M1 hits A12 (its p-stop) and A1 (its q-stop) four times per period.
//! assert_eq!(cell.labels[0].to_string(), "1-4-4");
//! assert!(cell.multiplier.unwrap() < 1.0);
//! ```
#![deny(missing_docs)]
#![deny(clippy::float_cmp)]

mod acceleration;
mod accuracy;
pub mod arclength;
mod budget;
mod chatter;
mod circle;
pub mod contact;
pub mod continuation;
pub mod curve;
mod error;
mod executor;
mod extremum;
pub mod floquet;
mod flow;
mod grazing;
mod impact;
mod label;
mod lyapunov;
mod mode;
mod newton;
mod number;
pub mod orbit;
mod period;
pub mod proximity;
pub mod quantity;
pub mod reference;
mod section;
mod simulate;
mod soft;
mod spectral;
mod stick;
mod system;
#[cfg(test)]
mod testing;

pub use accuracy::{Accuracy, Knob, KnobKind, Preset};
pub use circle::Rotation;
pub use error::SolverError;
pub use executor::{
    run_cell, run_cell_measured, run_cell_with_sections, CellResult, Departure, ImpactSections, Unresolved,
};
pub use floquet::{multipliers, Bifurcation};
pub use flow::Method;
pub use label::{Class, Count, Label, Mask, MassLabel, Symmetry};
pub use lyapunov::{Exponent, Flights, Interval, Stretch};
/// Matrix type of Jacobians and monodromy matrices.
pub use nalgebra::DMatrix;
/// Column vector type of states passed to observers.
pub use nalgebra::DVector;
pub use newton::{solve, Limits, MapKind, Solution};
/// Complex numbers of Floquet multipliers.
pub use num_complex::Complex64;
pub use orbit::{orbit_of_cell, Orbit, OrbitError};
pub use section::Points;
pub use simulate::{EventKind, EventObserver, Halt, Ignore, PeriodRecord, Segment, Simulator};
pub use system::{System, ADMISSIBLE_PENETRATION, FASTEST_FORCING, LARGEST_MAGNITUDE};
