//! Text summaries of atlases (after a run, and `vibroatlas inspect`).

use crate::out::outln;
use grid::Atlas;
use scene::Named;

/// Prints grid, per-sweep class and label counts, hysteresis, and speed.
pub fn print_summary(atlas: &Atlas, secs: f64, threads: usize) -> anyhow::Result<()> {
    let m = &atlas.meta;
    let p = &m.plane;
    let summary = engine::Summary::of(atlas);
    outln!("scene     {} (preset {}, integrator {})", m.scene_name, m.preset.name(), m.integrator.name());
    outln!("grid      {} x {} = {} cells, continuation along {}", p.x, p.y, p.cells(), p.along.name());
    if secs > 0.0 {
        let rate = crate::progress::thousands((summary.computed() as f64 / secs).round() as u64);
        outln!("time      {} on {threads} threads, {rate} cells/s", crate::progress::duration(secs));
    }
    for s in &summary.sweeps {
        let [periodic, quasiperiodic, chaotic, unresolved] = s.classes;
        outln!(
            "sweep     {}: {} cells computed; periodic {periodic}, quasiperiodic {quasiperiodic}, chaotic {chaotic}, unresolved {unresolved}",
            s.sweep.name(),
            s.computed,
        );
        for (mass, legend) in m.masses.iter().zip(&s.labels) {
            let shown: Vec<String> = legend.iter().take(12).map(|(l, c)| format!("{l} {c}")).collect();
            let more = if legend.len() > 12 { format!(", … {} more", legend.len() - 12) } else { String::new() };
            outln!("  {mass:<6} {}{more}", shown.join(", "));
        }
        for (kind, n) in s.reasons.iter().take(5) {
            outln!("  why U  {n} x {kind}");
        }
    }
    if let Some((n, z)) = &summary.hysteresis {
        outln!("hysteresis {n} cells in {} zones (largest {:?})", z.len(), &z[..z.len().min(5)]);
    }
    Ok(())
}
