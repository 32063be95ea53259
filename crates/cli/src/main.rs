//! `vibroatlas`: command-line entry point. Parses arguments into validated
//! plans, calls the library crates, prints results; every error is one line on
//! stderr and exit code 2.

mod args;
mod cell;
mod common;

use clap::Parser;

fn main() {
    let cli = args::Cli::parse();
    let result = match cli.command {
        args::Command::Cell(a) => cell::run(a),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(2);
    }
}
