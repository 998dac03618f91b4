//! Regenerates the numbers of `validation/REPORT.md` (paper-hertz-like-interfaces.tex) with the
//! hybrid engine on generated physical (Table 1 steel) scenes; the experiments live in
//! `beadchain::experiments::paper`.
//!
//! `cargo bench --bench paper_validation -- [interface|grid|impurity|periodic|disorder [N]|all]`,
//! part A (`benches/paper_a.rs`): `wavelength|timings|impurity_examples|appendix_a|appendix_b`,
//! part B (`benches/paper_b.rs`): `periodic4|pairwise|breathing|transfer|composite`; `all` runs
//! every experiment
//! (a plain program kept under `benches/`: it is a long measurement, not a test).

use beadchain::analysis::least_squares;
use beadchain::experiments::paper::{
    collapse_point, collapse_residual, disorder_gamma, impurity_ratio, interface_run, paper_gamma,
    periodic_gamma, reflection_grid, PaperError, RunInfo,
};
use std::time::Instant;

#[path = "paper_a.rs"]
mod paper_a;
#[path = "paper_b.rs"]
mod paper_b;

fn note(info: &RunInfo) -> String {
    match &info.hybrid_failure {
        Some(e) => format!(" [hybrid failed: {e}; dense engine used]"),
        None => String::new(),
    }
}

fn interfaces() -> Result<(), PaperError> {
    for (n1, n2) in [(3.0, 3.5), (3.0, 2.5)] {
        let r = interface_run(n1, n2, 150, 50)?;
        println!(
            "interface {n1} -> {n2}: N = 150, k = 50, stop t = {:.4e}, wall {:.2} s{}",
            r.t_stop,
            r.info.seconds,
            note(&r.info)
        );
        println!(
            "  E_left/E_total = {:.5}; v_in = {:.4e}; largest backward v = {:.4e} (ratio {:.4})",
            r.left_fraction,
            r.v_in,
            r.v_out,
            r.v_out / r.v_in
        );
        println!("  pulses in the final frame (peak bead, v/v_in, energy share):");
        for (p, e) in &r.pulses {
            println!(
                "    {:>4} {:>+8.4} {:>10.5}",
                p.peak_bead,
                p.peak_velocity / r.v_in,
                e
            );
        }
        if let Some((t, w)) = r.plateau {
            println!("  widest transmitted plateau (t = {t:.4e}): {w} beads within 25% of the max of beads k..k+19");
        }
    }
    Ok(())
}

fn grid() -> Result<(), PaperError> {
    let ns = [2.5, 2.75, 3.0, 3.25, 3.5, 3.75, 4.0];
    let t0 = Instant::now();
    let (pts, _) = reflection_grid(&ns, 120, 50)?;
    println!("| n1 \\ n2 | {} |", ns.map(|x| format!("{x}")).join(" | "));
    println!("|---|---|---|---|---|---|---|---|");
    for &n1 in &ns {
        let row: Vec<String> = pts
            .iter()
            .filter(|q| q.0 == n1)
            .map(|q| format!("{:.4}", q.2))
            .collect();
        println!("| {n1} | {} |", row.join(" | "));
    }
    println!("grid wall time {:.1} s", t0.elapsed().as_secs_f64());
    for p in [0.0, 0.4, 0.8, 1.2, 1.6, 1.65, 1.8, 2.0, 2.2, 2.4] {
        if let Some(sd) = collapse_residual(&pts, p) {
            println!("  p = {p:.2}: residual sd of E_refl(zeta) (cubic in ln zeta) = {sd:.3e}");
        }
    }
    if let Some((p, sd)) = collapse_point(&pts) {
        println!("collapse point p = {p:.2} (residual sd {sd:.2e}); paper 1.65");
    }
    Ok(())
}

fn impurity() -> Result<(), PaperError> {
    let t0 = Instant::now();
    println!("| n | s | dn | |v_out/v_in| | two-body (s+1)m | wall (s) |");
    println!("|---|---|---|---|---|---|");
    for (n, s) in [(4.0, 1usize), (4.0, 5), (3.0, 1), (3.0, 5)] {
        let two = s as f64 / (s as f64 + 2.0);
        for dn in [-1.5, -1.0, -0.5, -0.25, 0.25, 0.5, 1.0] {
            if n + dn < 2.0 {
                continue;
            }
            let (r, info) = impurity_ratio(n, s, dn)?;
            println!(
                "| {n} | {s} | {dn} | {r:.4} | {two:.4} | {:.1} |{}",
                info.seconds,
                note(&info)
            );
        }
    }
    println!("impurity wall time {:.1} s", t0.elapsed().as_secs_f64());
    Ok(())
}

fn disorder(beads: usize) -> Result<(), PaperError> {
    let t0 = Instant::now();
    println!("| n̄ | ε | seed | γ (fit) | ± se | points | paper eq. 21 | wall (s) |");
    println!("|---|---|---|---|---|---|---|---|");
    let (nbars, epss, seeds): (&[f64], &[f64], u64) = if beads >= 1000 {
        (&[2.4, 2.8, 3.2], &[0.014, 0.026, 0.04], 3)
    } else {
        (&[2.5, 3.0], &[0.02, 0.04], 2)
    };
    let (mut rows, mut y) = (Vec::new(), Vec::new());
    for &nbar in nbars {
        for &eps in epss {
            for seed in 1..=seeds {
                let (f, info) = disorder_gamma(nbar, eps, seed, beads)?;
                println!(
                    "| {nbar} | {eps} | {seed} | {:.4e} | {:.1e} | {} | {:.4e} | {:.1} |{}",
                    f.gamma,
                    f.gamma_stderr,
                    f.n,
                    paper_gamma(eps, nbar),
                    info.seconds,
                    note(&info)
                );
                if f.gamma > 0.0 && f.gamma.ln() > -10.0 {
                    rows.push(vec![eps.ln(), nbar, 1.0]);
                    y.push(f.gamma.ln());
                }
            }
        }
    }
    if let Ok(f) = least_squares(&rows, &y) {
        println!(
            "fit log γ = α log ε + B n̄ + C: α = {:.3} ± {:.3}, B = {:.3} ± {:.3}, C = {:.3} ± {:.3} (paper 2.085, -3.511, 10.945)",
            f.coef[0], f.stderr[0], f.coef[1], f.stderr[1], f.coef[2], f.stderr[2]
        );
    }
    println!("disorder wall time {:.1} s", t0.elapsed().as_secs_f64());
    Ok(())
}

fn periodic() -> Result<(), PaperError> {
    let t0 = Instant::now();
    println!("| n_a | dn | γ | ± se | points | wall (s) |");
    println!("|---|---|---|---|---|---|");
    let scans: [(f64, &[f64]); 2] = [
        (
            2.5,
            &[
                0.02, 0.04, 0.055, 0.08, 0.1, 0.12, 0.135, 0.15, 0.17, 0.2, 0.3, 0.5, 1.0,
            ],
        ),
        (
            4.0,
            &[
                0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.2, 1.5, 2.0,
            ],
        ),
    ];
    for (na, dns) in scans {
        for &dn in dns {
            match periodic_gamma(na, na + dn, 200) {
                Ok((f, info)) => println!(
                    "| {na} | {dn} | {:.4e} | {:.1e} | {} | {:.1} |{}",
                    f.gamma,
                    f.gamma_stderr,
                    f.n,
                    info.seconds,
                    note(&info)
                ),
                Err(e) => println!("| {na} | {dn} | {e} | | | |"),
            }
        }
    }
    println!("periodic wall time {:.1} s", t0.elapsed().as_secs_f64());
    Ok(())
}

fn main() -> Result<(), PaperError> {
    // cargo passes `--bench` (and `--list` when listing) before the user's arguments
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    if std::env::args().any(|a| a == "--list") {
        println!("paper_validation: bench");
        return Ok(());
    }
    let what = args.first().cloned().unwrap_or_else(|| "all".into());
    let beads: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(300);
    let all = what == "all";
    // Part A (benches/paper_a.rs) and part B (benches/paper_b.rs); `all` runs every experiment.
    let part_a = [
        "wavelength",
        "timings",
        "impurity_examples",
        "appendix_a",
        "appendix_b",
    ];
    let part_b = [
        "periodic4",
        "pairwise",
        "breathing",
        "transfer",
        "composite",
    ];
    let wanted: Vec<&str> = if all {
        part_a.iter().chain(part_b.iter()).copied().collect()
    } else {
        vec![what.as_str()]
    };
    let mut handled = false;
    for w in wanted {
        handled |= paper_a::dispatch(w)?;
        if let Some(res) = paper_b::dispatch(w) {
            handled = true;
            if let Err(e) = res {
                eprintln!("paper_validation {w}: {e}");
                std::process::exit(1);
            }
        }
    }
    if handled && !all {
        return Ok(());
    }
    if all || what == "interface" {
        interfaces()?;
    }
    if all || what == "grid" {
        grid()?;
    }
    if all || what == "impurity" {
        impurity()?;
    }
    if all || what == "periodic" {
        periodic()?;
    }
    if all || what == "disorder" {
        disorder(beads)?;
    }
    Ok(())
}
