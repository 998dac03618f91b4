//! Whole-run benchmark of the hybrid engine on paper presets (interfaces, periodic decay, disorder): time and
//! active bead-steps per traversed bead. Run: `cargo bench --bench presets` (~1 minute).

mod common;
use beadchain::engine::RunConfig;
use beadchain::scene::{self, Engine};

fn main() {
    if std::env::args().any(|a| a == "--list") {
        println!("presets: bench");
        return;
    }
    println!("| preset | beads | t_end | wall time (s) | µs per bead | active bead-steps per bead | events | largest cluster | energy error |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for name in [
        "interface_3.0_3.5",
        "interface_3.0_2.5",
        "impurity_s5_4.0_2.5",
        "periodic_decay_2.5_2.555",
        "disorder_2.5_0.04",
    ] {
        let s = scene::preset(name).expect("preset");
        let mut cfg = RunConfig::from_scene(&s);
        cfg.engine = Engine::Hybrid;
        cfg.every = None;
        let o = common::run(&s, cfg.engine, cfg.method, cfg.rtol, cfg.until);
        let n = s.chain.len();
        let events: u64 = o.events_total();
        println!(
            "| {name} | {n} | {:.4e} | {:.3} | {:.1} | {:.1} | {events} | {} | {:.2e} |",
            cfg.until,
            o.wall_seconds,
            1e6 * o.wall_seconds / n as f64,
            o.stats.bead_steps as f64 / n as f64,
            o.largest_cluster,
            o.relative_energy_error()
        );
    }
}
