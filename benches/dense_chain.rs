//! Whole-run benchmark of the dense integrators on the 1000-bead striker chain to wave exit
//! (wall time and energy error per method at two tolerances), with the hybrid engine beside
//! them. Run: `cargo bench --bench dense_chain` (prints a markdown table; ~2 minutes).

mod common;
use beadchain::integrate::Method;
use beadchain::names::Named;
use beadchain::scene::Engine;

fn main() {
    if std::env::args().any(|a| a == "--list") {
        println!("dense_chain: bench");
        return;
    }
    let n = 1000;
    let until = common::exit_time(n);
    let scene = common::striker(n, 2.5, until);
    println!("1000-bead striker chain (n = 2.5, m = a = v0 = 1), t = 0 .. {until:.0} (wave exit), atol = rtol/100\n");
    println!(
        "| engine | method | rtol | wall time (s) | steps | bead-steps | relative energy error |"
    );
    println!("|---|---|---|---|---|---|---|");
    for rtol in [1e-6, 1e-9] {
        for (engine, method) in [
            (Engine::Dense, Method::Radau5),
            (Engine::Dense, Method::Dop853),
            (Engine::Hybrid, Method::Radau5),
        ] {
            let o = common::run(&scene, engine, method, rtol, until);
            println!(
                "| {} | {} | {rtol:.0e} | {:.3} | {} | {} | {:.2e} |",
                engine.name(),
                method.name(),
                o.wall_seconds,
                o.stats.steps,
                o.stats.bead_steps,
                o.relative_energy_error()
            );
        }
    }
}
