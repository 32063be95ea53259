//! `vibroatlas attractors`: the coexisting attractors of one parameter point,
//! each with its label, a state on it, its stability and its basin fraction
//! (see `grid::attractors` for the sampling and the grouping).

use crate::args::AttractorsArgs;
use crate::common::{cell_setup, setup};
use crate::out::outln;
use crate::plan::threads;
use anyhow::{anyhow, bail, Result};
use grid::attractors::{find, sample, Attractor, Sampling};
use serde_json::{json, Value};
use store::write_atomically;

/// Most samples one run may take.
const MAX_SAMPLES: usize = 1_000_000;

/// Runs the command.
pub fn run(a: AttractorsArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    let s = setup(&a.sim)?;
    if a.samples == 0 || a.samples > MAX_SAMPLES {
        bail!("--samples: expected 1 to {MAX_SAMPLES}, got {}", a.samples);
    }
    let (x, v) = a
        .sample_box
        .split_once(',')
        .and_then(|(x, v)| Some((x.trim().parse::<f64>().ok()?, v.trim().parse::<f64>().ok()?)))
        .filter(|(x, v)| x.is_finite() && v.is_finite() && *x >= 0.0 && *v >= 0.0)
        .ok_or_else(|| anyhow!("--box: expected X,V (two numbers >= 0), got '{}'", a.sample_box))?;
    if let Some(png) = &a.png {
        render::Format::of(png)?;
    }
    let sampling = Sampling { samples: a.samples, seed: a.seed, x, v };
    let cs = cell_setup(&s, 0)?;
    let found = find(&cs, &[], &sampling, threads(a.threads)?)?;
    let sys = cs.system(&[])?;
    let masses: Vec<String> = sys.model.labels.iter().map(|l| sys.model.masses[l.mass].name.clone()).collect();
    let label = |at: &Attractor| -> Vec<String> { (0..masses.len()).map(|i| at.cell.labels[i].to_string()).collect() };
    if let Some(png) = &a.png {
        let mass = sys.model.labels.first().map_or(0, |l| l.mass);
        let m = sys.dof();
        let groups: Vec<(String, Vec<(f64, f64)>)> = found
            .iter()
            .map(|at| {
                let pts = at.members.iter().map(|&i| sample(&sys, &sampling, i)).map(|y| (y[mass], y[m + mass]));
                let named: Vec<String> = masses.iter().zip(label(at)).map(|(m, l)| format!("{m} {l}")).collect();
                let name = format!("{} ({:.0} %)", named.join(", "), 100.0 * at.count as f64 / a.samples as f64);
                (name, pts.collect())
            })
            .collect();
        let colours: Vec<String> = found.iter().map(|at| at.cell.labels[0].to_string()).collect();
        let title = format!("{}: basins of attraction at t = 0 ({} samples)", sys.model.name, a.samples);
        let axes =
            (format!("x_{} at t = 0", sys.model.masses[mass].name), format!("v_{}", sys.model.masses[mass].name));
        write_atomically(png, |tmp| render::basins(&groups, &colours, &title, &axes, &page, tmp))?;
    }
    if a.json {
        let list: Vec<Value> = found
            .iter()
            .map(|at| {
                let c = &at.cell;
                json!({
                    "class": c.class.name(),
                    "labels": masses.iter().cloned().zip(label(at).into_iter().map(Value::from)).collect::<serde_json::Map<_, _>>(),
                    "symmetry": c.symmetry.map(|x| x.name()),
                    "fraction": at.count as f64 / a.samples as f64,
                    "count": at.count,
                    "state": c.final_state,
                    "start": at.start,
                    "max_multiplier": c.multiplier,
                    "lyapunov": c.lyapunov,
                })
            })
            .collect();
        let params: serde_json::Map<String, Value> =
            sys.model.parameters.iter().map(|(k, v)| (k.clone(), json!(v))).collect();
        let out = json!({
            "scene": sys.model.name,
            "parameters": params,
            "samples": a.samples,
            "seed": a.seed,
            "box": {"x": x, "v": v},
            "attractors": list,
        });
        outln!("{}", serde_json::to_string(&out)?);
    } else {
        outln!("{} samples (seed {}, box |x| <= {x}, |v| <= {v}): {} attractors", a.samples, a.seed, found.len());
        for at in &found {
            let c = &at.cell;
            let stability = match (c.multiplier, c.lyapunov) {
                (Some(mu), _) => format!("max |multiplier| {mu:.6}"),
                (_, Some(l)) => format!("lyapunov {l:.6}"),
                _ => String::new(),
            };
            let sym = c.symmetry.map_or(String::new(), |x| format!(" {}", x.name()));
            outln!(
                "{:>6.1} %  {}{sym}  {}  ({})",
                100.0 * at.count as f64 / a.samples as f64,
                label(at).join(" "),
                c.class.name(),
                stability
            );
        }
    }
    Ok(())
}
