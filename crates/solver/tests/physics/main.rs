//! The solver's physics, checked through its library alone (no file, figure
//! or web crate is built for them: `cargo test -p vibroatlas-solver`). Each
//! module names the issue whose contract it checks.

/// The shipped scenes' systems and a recording observer.
mod common;

/// The exact flow against the RK4 integrator, impact by impact.
mod agreement;
/// Closed forms: the free oscillator's amplitude, the single stop's (1, n)
/// orbits and their impact speeds, the classification of textbook cells.
mod closed_form;
/// The quantities against an independent dense Runge–Kutta integration.
mod dense;
/// Corners of the parameter space: every cell ends labelled or unresolved
/// within its budget, finite and reproducible.
mod extremes;
/// Random parameters: finite states, no stop penetrated, no energy gained at
/// an impact.
mod properties;
