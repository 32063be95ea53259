//! Text summaries of atlases (after a run, and `vibroatlas inspect`).

use grid::hysteresis::zones;
use grid::Atlas;
use solver::Class;

/// Prints grid, per-sweep class and label counts, hysteresis, and speed.
pub fn print_summary(atlas: &Atlas, secs: f64, threads: usize) {
    let m = &atlas.meta;
    let p = &m.plane;
    println!("scene     {} (preset {}, integrator {})", m.scene_name, m.preset, m.integrator);
    println!("grid      {} x {} = {} cells, continuation along {}", p.x, p.y, p.cells(), p.along.name());
    let computed: usize = atlas.maps.iter().map(|mp| mp.cells.iter().flatten().count()).sum();
    if secs > 0.0 {
        println!("time      {secs:.2} s on {threads} threads, {:.0} cells/s", computed as f64 / secs);
    }
    for map in &atlas.maps {
        let cells: Vec<_> = map.cells.iter().flatten().collect();
        let count = |c: Class| cells.iter().filter(|x| x.class == c).count();
        println!(
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
            println!("  {mass:<6} {}{more}", shown.join(", "));
        }
    }
    if let Some(h) = atlas.hysteresis() {
        let z = zones(&h, p.x.count, p.y.count);
        let n: usize = h.iter().map(|&v| v as usize).sum();
        println!("hysteresis {n} cells in {} zones (largest {:?})", z.len(), &z[..z.len().min(5)]);
    }
}
