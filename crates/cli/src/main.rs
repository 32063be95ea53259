//! `vibroatlas`: command-line entry point. Parses arguments into validated
//! plans, calls the library crates, prints results; every error is one line on
//! stderr and exit code 2. Nothing printed can panic (see [`out`]): a closed or
//! full standard error drops the line, and the exit code is the work's.

mod args;
mod atlas;
mod attractors;
mod bench;
mod cell;
mod common;
mod continue_cmd;
mod curve;
mod figure;
mod flags;
mod inspect;
mod merge;
mod orbit;
mod out;
mod progress;
mod render_cmd;
mod study;
mod summary;
mod sweep;

use clap::Parser;

fn main() {
    let cli = match args::Cli::try_parse() {
        Ok(cli) => cli,
        // Help and version go to standard output as clap prints them.
        Err(e) if !e.use_stderr() => e.exit(),
        Err(e) => {
            // One line: clap's message up to its usage and tips (the missing
            // arguments it lists on the lines after the first included).
            let text = e.to_string();
            let lines: Vec<&str> = text
                .lines()
                .map(str::trim)
                .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("tip:") && !l.starts_with("For more"))
                .filter(|l| !l.is_empty())
                .collect();
            let message = lines.join(" ");
            let message = message.trim_start_matches("error: ");
            out::errln!(
                "error: {} (see vibroatlas --help)",
                if message.is_empty() { "invalid arguments" } else { message }
            );
            std::process::exit(2);
        }
    };
    // Commands whose result is a file: what they print reports it.
    if matches!(
        cli.command,
        args::Command::Atlas(_) | args::Command::Study(_) | args::Command::Merge(_) | args::Command::Render(_)
    ) {
        out::reports_only();
    }
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
        args::Command::Attractors(a) => attractors::run(a),
        args::Command::Curve(a) => curve::run(a),
        args::Command::Curves(a) => curve::run_curves(a),
    };
    if let Err(e) = result {
        out::errln!("error: {}", flags::message(&e));
        std::process::exit(2);
    }
}
