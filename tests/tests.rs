//! Integration tests, one module per concern. Each test names the issue whose
//! contract it checks.

mod agreement;
mod atlas;
mod bad_input;
mod basins;
mod cli;
mod closed_form;
mod dense;
mod docs;
mod drilldown;
mod edges;
mod extremes;
mod figures;
mod file_checks;
mod friction;
mod integrity;
mod limits;
mod palette;
mod print;
mod progress;
mod properties;
mod quantities;
mod run_safety;
mod soft;
mod stability;
mod streams_and_files;
mod symbols;
mod util;
mod zoom;
