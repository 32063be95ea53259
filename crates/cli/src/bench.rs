//! `vibroatlas bench`: parses the options into an [`engine::bench`] request,
//! prints its rows as they are measured (or one JSON object) and draws the
//! trade's `trade.png`.

use crate::args::BenchArgs;
use crate::out::outln;
use anyhow::{anyhow, bail, Context, Result};
use engine::bench::{
    Bench, BenchRequest, Throughput, Trade, EQUAL, PAPER_GRID, PAPER_ROUNDS, RK4, STANDARD, STEADY_SECONDS,
};
use engine::SceneSource;
use store::write_atomically;

/// Runs the command.
pub fn run(a: BenchArgs) -> Result<()> {
    let threads_text = a.threads.clone().unwrap_or_else(|| if a.paper { "1" } else { "1,2" }.to_string());
    let threads: Vec<usize> = threads_text
        .split(',')
        .map(|t| t.trim().parse::<usize>().ok().filter(|&n| (1..=1024).contains(&n)))
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| anyhow!("--threads: expected a comma-separated list of counts 1..1024, got '{threads_text}'"))?;
    let grid = a.grid.unwrap_or(if a.paper { PAPER_GRID } else { 48 });
    let rounds = a.trade_repeat.unwrap_or(if a.paper { PAPER_ROUNDS } else { 1 });
    if rounds == 0 {
        bail!("--trade-repeat: must be >= 1");
    }
    let mut request = BenchRequest::new(grid);
    request.threads = threads;
    request.repeat = a.repeat;
    request.trade_rounds = (a.trade || a.paper).then_some(rounds);
    request.paper = a.paper;
    if let Some(p) = &a.scene {
        request.scene = SceneSource::File(p.clone());
    }
    request.check()?;
    // The trade's figure's folder, made before any work.
    if let Some(dir) = &a.output {
        if !(a.trade || a.paper) {
            bail!("-o: the folder of the trade's figure (trade.png); give --trade or --paper too");
        }
        std::fs::create_dir_all(dir).with_context(|| format!("-o: cannot create {}", dir.display()))?;
    }
    let throughput = if a.paper {
        Vec::new()
    } else {
        let rows = engine::bench::throughput(&request, &mut |row| if a.json { Ok(()) } else { print_throughput(row) })?;
        if !a.json {
            outln!("every run on {threads_text} thread(s) gave the same atlas, bit for bit");
        }
        rows
    };
    let trade = engine::bench::trade(&request)?;
    if let Some(trade) = &trade {
        if !a.json {
            print_trade(grid, trade)?;
            if a.paper {
                print_paper(trade)?;
            }
        }
        if let Some(dir) = &a.output {
            draw_trade(dir, trade, a.json)?;
        }
    }
    if a.json {
        outln!("{}", serde_json::to_string(&Bench { grid, throughput, trade }.to_json())?);
    }
    Ok(())
}

/// The line of one throughput measurement.
fn print_throughput(r: &Throughput) -> Result<()> {
    let (name, t, count, best, rate, efficiency) =
        (r.sweep, r.threads, r.cells, r.seconds, r.cells_per_s, r.efficiency);
    outln!(
        "throughput {name:<5} {t} thread(s): {count} cells in {best:.2} s, {rate:.0} cells/s, parallel efficiency {efficiency:.2}"
    );
    Ok(())
}

/// The trade's table and its speed-ups against the literature's method.
fn print_trade(n: usize, trade: &Trade) -> Result<()> {
    outln!("\ntrade on {n} x {n} fresh cells, {} thread(s), reference: precise (exact)", trade.threads);
    outln!(
        "{:<24} {:>11} {:>16} {:>16} {:>19} {:>10} {:>12} {:>17}",
        "setting",
        "cells/s",
        "label agreement",
        "class agreement",
        "median |d state|",
        "periods",
        "us/period",
        "no-period share"
    );
    for row in &trade.rows {
        outln!(
            "{:<24} {:>11.0} {:>15.2}% {:>15.2}% {:>19.2e} {:>10} {:>12.1} {:>16.1}%",
            row.setting,
            row.cells_per_s,
            100.0 * row.label_agreement,
            100.0 * row.class_agreement,
            row.median_state_error,
            row.periods,
            row.us_per_period,
            100.0 * row.nonperiodic_share()
        );
    }
    if let Some(base) = trade.rk4_cells_per_s() {
        let ratios: Vec<String> =
            trade.rows.iter().map(|r| format!("{} {:.1}x", r.setting, r.cells_per_s / base)).collect();
        outln!("cells/s against {}: {}", RK4.name, ratios.join(", "));
        if trade.rows.iter().any(|r| r.round_seconds.len() > 1) {
            let spread = |r: &engine::bench::TradeRow| {
                trade.spread(r).map(|[lo, hi]| format!("{} {lo:.1}-{hi:.1}x", r.setting)).unwrap_or_default()
            };
            let spreads: Vec<String> = trade.rows.iter().map(spread).collect();
            outln!("each round against {} of the same round: {}", RK4.name, spreads.join(", "));
        }
    }
    Ok(())
}

/// The paper's comparison in words: each setting's median speed-up over the
/// literature's method and its spread, with the agreement each has with
/// `precise`, and a note where `standard`'s rounds were too short for a
/// steady ratio.
fn print_paper(trade: &Trade) -> Result<()> {
    let rk4 = trade.rows.iter().find(|r| r.setting == RK4.name).map_or(f64::NAN, |r| 100.0 * r.label_agreement);
    for row in trade.rows.iter().filter(|r| r.setting == STANDARD.name || r.setting == EQUAL.name) {
        let (Some(median), Some([lo, hi])) = (trade.median(row), trade.spread(row)) else { continue };
        outln!(
            "{} against {} on {} thread(s): {median:.1}x (median of {} round(s), {lo:.1}-{hi:.1}x), label agreement with precise {:.2} % against {rk4:.2} %",
            row.setting,
            RK4.name,
            trade.threads,
            row.round_seconds.len(),
            100.0 * row.label_agreement
        );
    }
    let short = trade
        .rows
        .iter()
        .filter(|r| r.setting == STANDARD.name)
        .flat_map(|r| r.round_seconds.iter())
        .any(|&s| s < STEADY_SECONDS);
    if short {
        outln!("note: a round of standard took less than {STEADY_SECONDS} s: a larger --grid steadies the ratio");
    }
    Ok(())
}

/// Draws `trade.png` in `dir` (agreement against cells/s); says so unless `quiet`.
fn draw_trade(dir: &std::path::Path, trade: &Trade, quiet: bool) -> Result<()> {
    let points: Vec<(String, f64, f64)> =
        trade.rows.iter().map(|r| (r.setting.to_string(), r.cells_per_s, r.label_agreement)).collect();
    let png = dir.join("trade.png");
    write_atomically(&png, |tmp| render::trade(&points, tmp))?;
    if !quiet {
        outln!("wrote {}", png.display());
    }
    Ok(())
}
