//! `vibroatlas study`: one atlas per value of a parameter, each with its map,
//! and a contact sheet comparing them.

use crate::args::{SimArgs, StudyArgs};
use crate::common::setup;
use crate::out::outln;
use crate::plan::{threads, Plan};
use anyhow::{anyhow, bail, Context, Result};
use grid::{Along, Axis, Plane, Study, SweepKind};
use render::View;
use store::write_atomically;

/// Runs the command.
pub fn run(a: StudyArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    let text =
        std::fs::read_to_string(&a.study).with_context(|| format!("cannot read study file {}", a.study.display()))?;
    let study = Study::parse(&text).map_err(|e| anyhow!("{}: {e}", a.study.display()))?;
    let scene_path = a.study.parent().unwrap_or(std::path::Path::new(".")).join(&study.scene);
    let sweeps = SweepKind::parse_set(&study.sweep, "sweep")?;
    let plane = Plane::new(Axis::parse(&study.x, "x")?, Axis::parse(&study.y, "y")?, Along::parse(&study.along)?)?;
    if [&plane.x.name, &plane.y.name].contains(&&study.parameter) {
        bail!(
            "{}: parameter '{}' is also an axis of the study's plane; vary another parameter",
            a.study.display(),
            study.parameter
        );
    }
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
                preset: Some(a.preset),
                accuracy: Vec::new(),
                integrator: None,
            };
            let s = setup(&sim)?;
            let mut plan = Plan::new(&s, a.run.section_cap, plane.clone(), sweeps.clone(), threads)?;
            plan.output = Some(a.output.join(format!("{}.h5", study.stem(v))));
            plan.quiet = a.run.quiet;
            plan.check()?;
            Ok((v, plan))
        })
        .collect::<Result<Vec<_>>>()?;
    let mut panels = Vec::new();
    for (v, plan) in plans {
        let (atlas, secs) = plan.execute(&study.stem(v))?;
        let png = a.output.join(format!("{}.png", study.stem(v)));
        write_atomically(&png, |tmp| render::map(&atlas, View::Sweep(sweeps[0]), 0, &[], &page, tmp))?;
        if !a.run.quiet {
            outln!(
                "{}: {} cells in {secs:.1} s -> {}",
                study.stem(v),
                plan.meta.plane.cells() * sweeps.len(),
                png.display()
            );
        }
        panels.push((format!("{} = {v}", study.parameter), atlas));
    }
    let sheet = a.output.join("contact-sheet.png");
    write_atomically(&sheet, |tmp| render::sheet(&panels, sweeps[0], 0, &page, tmp))?;
    outln!("wrote {}", sheet.display());
    Ok(())
}
