//! Whole-run benchmark of the hybrid engine: cost per traversed bead from 10³ to 10⁵ beads
//! (flat = linear in chain length), and hybrid vs dense side by side at 10³ (to wave exit) and
//! 10⁴ (over the first 300 time units, the same window for both; the dense cost per unit time
//! is constant, so the ratio holds for the whole traversal). Run:
//! `cargo bench --bench hybrid_scaling` (prints markdown tables; ~3 minutes).

mod common;
use beadchain::integrate::Method;
use beadchain::scene::Engine;

fn main() {
    if std::env::args().any(|a| a == "--list") {
        println!("hybrid_scaling: bench");
        return;
    }
    let rtol = 1e-8;
    println!("Uniform striker chain, n = 2.5, hybrid + radau5, rtol {rtol:.0e}, atol {:.0e}, to wave exit\n", rtol * 1e-2);
    println!("| beads | t_end | wall time (s) | µs per traversed bead | active bead-steps per traversed bead | events | largest cluster | energy error |");
    println!("|---|---|---|---|---|---|---|---|");
    for n in [1_000usize, 10_000, 100_000] {
        let until = common::exit_time(n);
        let scene = common::striker(n, 2.5, until);
        let o = common::run(&scene, Engine::Hybrid, Method::Radau5, rtol, until);
        let events: u64 = o.events_total();
        println!(
            "| {n} | {until:.0} | {:.3} | {:.2} | {:.1} | {events} | {} | {:.2e} |",
            o.wall_seconds,
            1e6 * o.wall_seconds / n as f64,
            o.stats.bead_steps as f64 / n as f64,
            o.largest_cluster,
            o.relative_energy_error()
        );
    }
    println!("\nHybrid vs dense, same rtol, side by side\n");
    println!("| beads | window | hybrid (s) | dense (s) | speed-up | energy error hybrid | energy error dense |");
    println!("|---|---|---|---|---|---|---|");
    for (n, until) in [(1_000usize, common::exit_time(1_000)), (10_000, 300.0)] {
        let scene = common::striker(n, 2.5, until);
        let h = common::run(&scene, Engine::Hybrid, Method::Radau5, rtol, until);
        let d = common::run(&scene, Engine::Dense, Method::Radau5, rtol, until);
        println!(
            "| {n} | 0 .. {until:.0} | {:.3} | {:.3} | {:.0}x | {:.2e} | {:.2e} |",
            h.wall_seconds,
            d.wall_seconds,
            d.wall_seconds / h.wall_seconds,
            h.relative_energy_error(),
            d.relative_energy_error()
        );
    }
}
