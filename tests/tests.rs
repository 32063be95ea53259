//! Integration tests, one module per concern. Each test names the issue whose
//! contract it checks.

mod agreement;
mod atlas;
mod bad_input;
mod cli;
mod closed_form;
mod drilldown;
mod edges;
mod extremes;
mod faults;
mod faults2;
mod faults3;
mod figures;
mod friction;
mod integrity;
mod limits;
mod palette;
mod print;
mod progress;
mod properties;
mod soft;
mod stability;
mod symbols;
mod util;
mod zoom;
