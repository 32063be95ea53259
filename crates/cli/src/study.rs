//! `vibroatlas study`: one atlas per value of a parameter, each with its map,
//! and a contact sheet comparing them.

use crate::args::{SimArgs, StudyArgs};
use crate::common::{cell_setup, setup};
use crate::plan::{command_line, meta, threads, Plan};
use anyhow::{anyhow, Context, Result};
use grid::{Along, Axis, Plane, Study, SweepKind};
use render::View;

/// Runs the command.
pub fn run(a: StudyArgs) -> Result<()> {
    let text =
        std::fs::read_to_string(&a.study).with_context(|| format!("cannot read study file {}", a.study.display()))?;
    let study = Study::parse(&text).map_err(|e| anyhow!("{}: {e}", a.study.display()))?;
    let scene_path = a.study.parent().unwrap_or(std::path::Path::new(".")).join(&study.scene);
    let sweeps = SweepKind::parse_set(&study.sweep, "sweep")?;
    let plane = Plane::new(Axis::parse(&study.x, "x")?, Axis::parse(&study.y, "y")?, Along::parse(&study.along)?)?;
    std::fs::create_dir_all(&a.output).with_context(|| format!("cannot create {}", a.output.display()))?;
    let threads = threads(a.run.threads)?;
    // Validate every value before computing any.
    let plans = study
        .values
        .iter()
        .map(|&v| {
            let mut set: Vec<String> = study.set.iter().map(|(k, x)| format!("{k}={x}")).collect();
            set.push(format!("{}={v}", study.parameter));
            let sim = SimArgs {
                scene: scene_path.clone(),
                set,
                preset: a.preset.clone(),
                accuracy: Vec::new(),
                integrator: "exact".into(),
            };
            let s = setup(&sim)?;
            let cs = cell_setup(&s, a.run.section_cap)?;
            let plan = Plan {
                meta: meta(&cs, &s, plane.clone(), sweeps.clone(), Vec::new())?,
                setup: cs,
                threads,
                shard: None,
                output: Some(a.output.join(format!("{}.h5", study.stem(v)))),
                resume: false,
                quiet: a.run.quiet,
                command: command_line(),
            };
            plan.check_memory()?;
            plan.meta.plane.validate(&plan.setup)?;
            Ok((v, plan))
        })
        .collect::<Result<Vec<_>>>()?;
    let mut panels = Vec::new();
    for (v, plan) in plans {
        let (atlas, secs) = plan.execute(&study.stem(v))?;
        let png = a.output.join(format!("{}.png", study.stem(v)));
        render::map(&atlas, View::Sweep(sweeps[0]), 0, &png)?;
        if !a.run.quiet {
            println!(
                "{}: {} cells in {secs:.1} s -> {}",
                study.stem(v),
                plan.meta.plane.cells() * sweeps.len(),
                png.display()
            );
        }
        panels.push((format!("{} = {v}", study.parameter), atlas));
    }
    let sheet = a.output.join("contact-sheet.png");
    render::sheet(&panels, sweeps[0], 0, &sheet)?;
    println!("wrote {}", sheet.display());
    Ok(())
}
