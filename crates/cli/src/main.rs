//! `vibroatlas`: command-line entry point. Parses arguments into validated
//! plans, calls the library crates, prints results; every error is one line on
//! stderr and exit code 2.

mod args;
mod atlas;
mod bench;
mod cell;
mod common;
mod continue_cmd;
mod inspect;
mod merge;
mod orbit;
mod plan;
mod progress;
mod render_cmd;
mod study;
mod summary;
mod sweep;

use clap::Parser;

fn main() {
    let cli = args::Cli::parse();
    let result = match cli.command {
        args::Command::Cell(a) => cell::run(a),
        args::Command::Sweep(a) => sweep::run(a),
        args::Command::Atlas(a) => atlas::run(a),
        args::Command::Study(a) => study::run(a),
        args::Command::Render(a) => render_cmd::run(a),
        args::Command::Merge(a) => merge::run(a),
        args::Command::Inspect(a) => inspect::run(a),
        args::Command::Bench(a) => bench::run(a),
        args::Command::Orbit(a) => orbit::run(a),
        args::Command::Continue(a) => continue_cmd::run(a),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(2);
    }
}
