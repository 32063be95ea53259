//! `vibroatlas`: command-line entry point. Parses arguments into validated
//! plans, calls the library crates, prints results; every error is one line on
//! stderr and exit code 2. Nothing printed can panic (see [`out`]): a closed or
//! full standard error drops the line, and the exit code is the work's.

mod args;
mod atlas;
mod attractors;
mod basins;
mod bench;
mod cell;
mod common;
mod continue_cmd;
mod curve;
mod eta;
mod explore;
mod figure;
mod flags;
mod inspect;
mod interrupt;
mod merge;
mod orbit;
mod out;
mod progress;
mod render_cmd;
mod study;
mod summary;
mod sweep;
mod zoom;

/// The allocator: mimalloc, faster than the system's on the small matrices
/// and vectors the solver makes at every event (docs/performance.md).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{CommandFactory, FromArgMatches};

/// The command line's grammar: every option that takes a value also takes
/// one that starts with '-' (`--seed -1`, `--shard -1/2`, `--box -1,-1`), so
/// that the value's own check refuses it, naming the option (clap would name
/// no option: "unexpected argument '-1'").
///
/// A command that starts from a stored cell (`--from FILE.h5`) needs no
/// scene file: the file's stored scene is taken.
fn grammar() -> clap::Command {
    args::Cli::command().mut_subcommands(|c| {
        let from = c.get_arguments().any(|a| a.get_id() == "from");
        let attractors = c.get_name() == "attractors";
        c.mut_args(|a| match a.get_long().is_some() && a.get_action().takes_values() {
            true => a.allow_hyphen_values(true),
            false => a,
        })
        .mut_args(|a| match (a.get_id() == "scene", from) {
            (true, true) => a.required(false).required_unless_present("from"),
            // Without --from the file is the scene's only source.
            (true, false) => a.help("Scene file (TOML)"),
            _ => a,
        })
        // The attractors sample their own start states: --state is refused
        // there (naming it), and not offered.
        .mut_args(|a| match attractors && a.get_id() == "state" {
            true => a.hide(true),
            false => a,
        })
    })
}

/// A file grown past the process's size limit (`ulimit -f`) is a write
/// error like a full disk (EFBIG, "File too large"): reported, the journal
/// kept for `--resume`, instead of the signal SIGXFSZ ending the process
/// without a word.
fn ignore_file_size_signal() {
    // SAFETY: sets a signal's disposition, before any other thread exists.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

/// The one line of a command line that does not parse (clap's message up
/// to its usage and tips, the missing arguments it lists on the lines after
/// the first included).
fn parse_error(e: &clap::Error) -> String {
    if matches!(e.kind(), ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand | ErrorKind::MissingSubcommand) {
        let names: Vec<String> = args::Cli::command().get_subcommands().map(|c| c.get_name().to_string()).collect();
        return format!("a command is needed: {}", names.join(", "));
    }
    let text = e.to_string();
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("tip:") && !l.starts_with("For more"))
        .filter(|l| !l.is_empty())
        .collect();
    let message = lines.join(" ");
    let message = message.trim_start_matches("error: ");
    // clap's tip of the name meant (a value, a flag, a command) kept in the one line.
    let meant = [ContextKind::SuggestedValue, ContextKind::SuggestedArg, ContextKind::SuggestedSubcommand]
        .into_iter()
        .find_map(|k| match e.get(k) {
            Some(ContextValue::String(s)) => Some(s.clone()),
            Some(ContextValue::Strings(s)) => s.first().cloned(),
            _ => None,
        });
    match (message.is_empty(), meant) {
        (true, _) => "invalid arguments".into(),
        (false, Some(m)) => format!("{message} (did you mean '{m}'?)"),
        (false, None) => message.into(),
    }
}

fn main() {
    ignore_file_size_signal();
    let cli = match grammar().try_get_matches().and_then(|m| args::Cli::from_arg_matches(&m)) {
        Ok(cli) => cli,
        // Help and version go to standard output as clap renders them; one
        // that cannot be written (a full disk) is an error like any output.
        Err(e) if !e.use_stderr() => {
            use std::io::Write;
            match e.print().and_then(|()| std::io::stdout().flush()) {
                Ok(()) => std::process::exit(0),
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
                Err(e) => {
                    out::error(&format!("standard output: {e}"));
                    std::process::exit(2);
                }
            }
        }
        Err(e) => {
            out::error(&format!("{} (see vibroatlas --help)", parse_error(&e)));
            std::process::exit(2);
        }
    };
    // Commands whose result is a file: what they print reports it.
    if matches!(
        cli.command,
        args::Command::Atlas(_)
            | args::Command::Zoom(_)
            | args::Command::Study(_)
            | args::Command::Merge(_)
            | args::Command::Render(_)
            | args::Command::Basins(_)
    ) {
        out::reports_only();
    }
    let result = match cli.command {
        args::Command::Cell(a) => cell::run(a),
        args::Command::Sweep(a) => sweep::run(a),
        args::Command::Atlas(a) => atlas::run(a),
        args::Command::Zoom(a) => zoom::run(a),
        args::Command::Explore(a) => explore::run(a),
        args::Command::Study(a) => study::run(a),
        args::Command::Render(a) => render_cmd::run(a),
        args::Command::Merge(a) => merge::run(a),
        args::Command::Inspect(a) => inspect::run(a),
        args::Command::Bench(a) => bench::run(a),
        args::Command::Orbit(a) => orbit::run(a),
        args::Command::Continue(a) => continue_cmd::run(a),
        args::Command::Attractors(a) => attractors::run(a),
        args::Command::Basins(a) => basins::run(a),
        args::Command::Curve(a) => curve::run(a),
        args::Command::Curves(a) => curve::run_curves(a),
    };
    if let Err(e) = result {
        out::error(&flags::message(&e));
        std::process::exit(2);
    }
}
