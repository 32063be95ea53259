//! Integration tests: the binary, its files, figures and pages, one module per
//! concern; each test names the issue whose contract it checks. The solver's
//! physics through its library alone is in `crates/solver/tests/physics`, the
//! explorer's routes in `crates/explore/tests/routes.rs`. Tests marked
//! `#[ignore = "slow: …"]` (over about 5 s each) run in the full suite only
//! (`scripts/test.sh`; `scripts/test.sh --quick` leaves them out).

/// `atlas`, `sweep`, `merge`, `render` and `inspect` end to end; kill and resume.
mod atlas;
/// Bad input: one error line naming the field, exit 2, no panic.
mod bad_input;
/// Basins of attraction over a grid of initial states: threads, shards, readers.
mod basins;
/// `cell` end to end and `bench`'s JSON.
mod cli;
/// The user pages' statements against what the program prints.
mod docs;
/// From a map to a motion: stored cells, hysteresis, attractors, traces.
mod drilldown;
/// Labels at the edges of decisions: convergence, symmetry, long orbits.
mod edges;
/// Figures a paper can print: colours read back at known cells, SVG, PDF.
mod figures;
/// Files that never lie: checksums a reader verifies, merges that name differences.
mod file_checks;
/// Dry friction: stick/slip against closed forms and RK4, the published sequence.
mod friction;
/// Files that verify themselves and readers that validate before indexing; fuzzing.
mod integrity;
/// Every budget bounds every integrator; scene sizes are bounded.
mod limits;
/// No module of a crate imports one that imports it back.
mod modules;
/// The names a user types: the Python stubs offer the library's names.
mod names;
/// Colours that stay apart (CIEDE2000) among each scene's frequent labels.
mod palette;
/// Printed figures: embedded fonts, page sizes, no text under 6 pt.
mod print;
/// `progress:` lines off a terminal.
mod progress;
/// Quantities of the steady motion in atlases, inspect and render.
mod quantities;
/// Run safety: nothing lost, nothing wrong, never a crash.
mod run_safety;
/// Soft stops, constant loads and harmonics against closed forms.
mod soft;
/// Exact Jacobians, Newton orbits, Floquet multipliers, curves.
mod stability;
/// Standard streams, studies, symbolic links, pipes and names.
mod streams_and_files;
/// Parameter symbols and long names in scenes, files and figures.
mod symbols;
/// Helpers: the binary's runs, the shipped scenes' systems.
mod util;
/// `zoom`: a box of a stored atlas computed again from its parent's chains.
mod zoom;
