//! Text summaries of atlases (after a run, and `vibroatlas inspect`).

use crate::out::outln;
use grid::hysteresis::zones;
use grid::Atlas;
use solver::Class;

/// Prints grid, per-sweep class and label counts, hysteresis, and speed.
pub fn print_summary(atlas: &Atlas, secs: f64, threads: usize) -> anyhow::Result<()> {
    let m = &atlas.meta;
    let p = &m.plane;
    outln!("scene     {} (preset {}, integrator {})", m.scene_name, m.preset.name(), m.integrator.name());
    outln!("grid      {} x {} = {} cells, continuation along {}", p.x, p.y, p.cells(), p.along.name());
    let computed: usize = atlas.maps.iter().map(|mp| mp.cells.iter().flatten().count()).sum();
    if secs > 0.0 {
        let rate = crate::progress::thousands((computed as f64 / secs).round() as u64);
        outln!("time      {} on {threads} threads, {rate} cells/s", crate::progress::duration(secs));
    }
    for map in &atlas.maps {
        let cells: Vec<_> = map.cells.iter().flatten().collect();
        let count = |c: Class| cells.iter().filter(|x| x.class == c).count();
        outln!(
            "sweep     {}: {} cells computed; periodic {}, quasiperiodic {}, chaotic {}, unresolved {}",
            map.sweep.name(),
            cells.len(),
            count(Class::Periodic),
            count(Class::Quasiperiodic),
            count(Class::Chaotic),
            count(Class::Unresolved)
        );
        for (mi, mass) in m.masses.iter().enumerate() {
            let legend = atlas.legend(map.sweep, mi);
            let shown: Vec<String> = legend.iter().take(12).map(|(l, c)| format!("{l} {c}")).collect();
            let more = if legend.len() > 12 { format!(", … {} more", legend.len() - 12) } else { String::new() };
            outln!("  {mass:<6} {}{more}", shown.join(", "));
        }
        for (kind, n) in engine::reasons(&map.cells).iter().take(5) {
            outln!("  why U  {n} x {kind}");
        }
    }
    if let Some(h) = atlas.hysteresis() {
        let z = zones(&h, p.x.count, p.y.count);
        let n: usize = h.iter().map(|&v| v as usize).sum();
        outln!("hysteresis {n} cells in {} zones (largest {:?})", z.len(), &z[..z.len().min(5)]);
    }
    Ok(())
}
