//! Experiments of `validation/REPORT.md` part B (issue 6 items 5, 7, 8): periodic chains with
//! the windowed tracker (`periodic4`, `pairwise`, `breathing`; paper Figs. 10–14), the
//! energy-transfer ratio in disordered chains (`transfer`, Fig. 23) and composite mass–exponent
//! interfaces (`composite`, Fig. 25). Tables go to stdout, data to `validation/data/*.csv`.

use beadchain::experiments::composite::{
    composite_grid, composite_run, contour_crossings, grid_csv, CompositeRow,
};
use beadchain::experiments::periodic::{
    breathing, pair_leader_changes, pairing, periodic_window_run, retention, windowed_gamma,
    PeriodicRun, WIDTHS,
};
use beadchain::experiments::transfer::{bin_samples, transfer_run, transfer_trend, TransferSample};
use beadchain::scene::Engine;
use std::path::PathBuf;
use std::time::Instant;

/// Writes `validation/data/<name>` atomically (temp file + rename).
fn write_data(name: &str, text: &str) -> std::io::Result<()> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("validation/data");
    std::fs::create_dir_all(&dir)?;
    let tmp = dir.join(format!(".{name}.tmp"));
    std::fs::write(&tmp, text)?;
    std::fs::rename(&tmp, dir.join(name))?;
    println!("wrote validation/data/{name}");
    Ok(())
}

/// Result of one experiment (engine, scene or I/O errors).
type Res = Result<(), Box<dyn std::error::Error>>;

/// Runs the experiment `what` if it is one of this file's (`None` otherwise).
pub fn dispatch(what: &str) -> Option<Res> {
    Some(match what {
        "periodic4" => periodic4(),
        "pairwise" => pairwise(),
        "breathing" => breathing_cmd(),
        "transfer" => transfer(),
        "composite" => composite(),
        _ => return None,
    })
}

/// The local minima of `γ(dn)` (W = 12) of one scan, each with the vertex of the parabola
/// through the three points around it.
fn local_minima(na: f64, g12: &[(f64, f64)]) -> Vec<String> {
    g12.windows(3)
        .filter(|w| w[1].1 < w[0].1 && w[1].1 <= w[2].1)
        .map(|w| {
            // vertex of the parabola through the three points around the minimum
            let (x0, x1, x2) = (w[0].0, w[1].0, w[2].0);
            let (y0, y1, y2) = (w[0].1, w[1].1, w[2].1);
            let num = (x1 - x0).powi(2) * (y1 - y2) - (x1 - x2).powi(2) * (y1 - y0);
            let den = (x1 - x0) * (y1 - y2) - (x1 - x2) * (y1 - y0);
            let xv = if den != 0.0 { x1 - 0.5 * num / den } else { x1 };
            format!(
                "dn = {} (n_b = {}, γ = {:.2e}; parabola vertex dn = {xv:.4})",
                w[1].0,
                na + w[1].0,
                w[1].1
            )
        })
        .collect()
}

/// Windowed γ scan over dn for n_a = 2.5 and 4.0, local minima, dense cross-check.
pub fn periodic4() -> Res {
    let t0 = Instant::now();
    let scans: [(f64, &[f64]); 2] = [
        (
            2.5,
            &[
                0.0, 0.02, 0.04, 0.055, 0.08, 0.1, 0.11, 0.12, 0.125, 0.13, 0.1325, 0.135, 0.1375,
                0.14, 0.145, 0.15, 0.17, 0.2, 0.3, 0.5, 1.0,
            ],
        ),
        (
            4.0,
            &[
                0.0, 0.1, 0.2, 0.3, 0.35, 0.4, 0.45, 0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.95, 0.975,
                1.0, 1.025, 1.05, 1.1, 1.2, 1.5, 2.0,
            ],
        ),
    ];
    let mut csv = String::from("na,dn,nb,width,gamma,gamma_se,points,retention,seconds\n");
    println!("windowed tracker: 200 beads, frames tb/2, E0 at front 15, fit fronts 25..190");
    println!("| n_a | dn | γ (W=8) | γ (W=12) ± se | γ (W=20) | E(190)/E(25) W=12 | wall (s) |");
    println!("|---|---|---|---|---|---|---|");
    for (na, dns) in scans {
        let mut g12 = Vec::new();
        for &dn in dns {
            let run = periodic_window_run(na, na + dn, 200, 2.0, None, Engine::Hybrid)?;
            let mut cells = Vec::new();
            for (wi, w) in WIDTHS.iter().enumerate() {
                let ret = retention(&run, wi, 25, 190).unwrap_or(f64::NAN);
                match windowed_gamma(&run, wi) {
                    Ok(f) => {
                        csv.push_str(&format!(
                            "{na},{dn},{},{w},{:.6e},{:.3e},{},{ret:.6},{:.3}\n",
                            na + dn,
                            f.gamma,
                            f.gamma_stderr,
                            f.n,
                            run.seconds
                        ));
                        cells.push(if wi == 1 {
                            g12.push((dn, f.gamma));
                            format!("{:.3e} ± {:.1e}", f.gamma, f.gamma_stderr)
                        } else {
                            format!("{:.3e}", f.gamma)
                        });
                    }
                    Err(e) => cells.push(format!("({e})")),
                }
            }
            println!(
                "| {na} | {dn} | {} | {:.4} | {:.1} |",
                cells.join(" | "),
                retention(&run, 1, 25, 190).unwrap_or(f64::NAN),
                run.seconds
            );
        }
        let minima = local_minima(na, &g12);
        println!(
            "n_a = {na}: local minima of γ (W = 12) for dn > 0: {}",
            minima.join("; ")
        );
    }
    // dense cross-check of one case
    let (na, nb) = (4.0, 5.0);
    let h = periodic_window_run(na, nb, 120, 2.0, None, Engine::Hybrid)?;
    let d = periodic_window_run(na, nb, 120, 2.0, None, Engine::Dense)?;
    let (gh, gd) = (windowed_gamma(&h, 1)?, windowed_gamma(&d, 1)?);
    println!(
        "cross-check {na}/{nb}, 120 beads, W = 12: hybrid γ = {:.4e} ({:.1} s), dense γ = {:.4e} ({:.1} s), retention E(110)/E(25) hybrid {:.6} dense {:.6}",
        gh.gamma,
        h.seconds,
        gd.gamma,
        d.seconds,
        retention(&h, 1, 25, 110).unwrap_or(f64::NAN),
        retention(&d, 1, 25, 110).unwrap_or(f64::NAN)
    );
    write_data("periodic_window.csv", &csv)?;
    println!("periodic4 wall time {:.1} s", t0.elapsed().as_secs_f64());
    Ok(())
}

/// Pairwise collective motion (Fig. 10) against the decaying 2.5/2.555 chain (Fig. 11).
pub fn pairwise() -> Res {
    let t0 = Instant::now();
    println!("pair mismatch max_t |v_i − v_j| / peak while either bead > 10 % of the pair's peak,");
    println!("beads 60..150 of a 200-bead chain, frames tb/20; median over pairs (worst pair)");
    println!("| n_a | n_b | n_a pairs (2j, 2j+1) | n_b pairs (2j+1, 2j+2) | γ (W=12) | wall (s) |");
    println!("|---|---|---|---|---|---|");
    let mut traces = String::from("case,t,v71,v72,v73,v74\n");
    for (na, nb) in [(2.5, 3.0), (2.5, 2.555), (2.5, 2.5), (4.0, 6.0)] {
        let run = periodic_window_run(na, nb, 200, 20.0, Some((60, 150)), Engine::Hybrid)?;
        let g = windowed_gamma(&run, 1).map_or(f64::NAN, |f| f.gamma);
        match pairing(&run, 0.1) {
            Some(((ma, wa), (mb, wb))) => println!(
                "| {na} | {nb} | {:.2} % ({:.2} %) | {:.2} % ({:.2} %) | {g:.2e} | {:.1} |",
                100.0 * ma,
                100.0 * wa,
                100.0 * mb,
                100.0 * wb,
                run.seconds
            ),
            None => println!("| {na} | {nb} | no motion | | | |"),
        }
        let tr: Vec<Vec<f64>> = (71..75).map(|i| run.watch.trace(i)).collect();
        for (f, t) in run.watch.trace_t.iter().enumerate() {
            if tr.iter().any(|b| b[f].abs() > 0.0) {
                traces.push_str(&format!(
                    "{na}/{nb},{t:.6e},{:.6e},{:.6e},{:.6e},{:.6e}\n",
                    tr[0][f], tr[1][f], tr[2][f], tr[3][f]
                ));
            }
        }
    }
    write_data("pairwise_traces.csv", &traces)?;
    println!("pairwise wall time {:.1} s", t0.elapsed().as_secs_f64());
    Ok(())
}

fn periods(p: &[(f64, f64)]) -> String {
    p.iter()
        .map(|(a, w)| format!("{a:.2} ({w:.2})"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Breathing confined waves at the minima (Figs. 13–14) with controls.
pub fn breathing_cmd() -> Res {
    let t0 = Instant::now();
    let beads = 400;
    let mut csv = String::from("case,t,front,e_w8,e_w12,e_w20,peak_bead,peak_v\n");
    println!(
        "{beads} beads, frames tb/40; periods of the window peak velocity / sqrt(E_w20) and of the"
    );
    println!(
        "lag front − peak bead, in beads travelled (relative power), fronts 40..{}",
        beads - 10
    );
    let runs: Vec<PeriodicRun> = [
        (2.5, 2.635),
        (4.0, 5.0),
        (2.5, 2.5),
        (4.0, 4.0),
        (2.5, 2.555),
        (2.5, 3.0),
    ]
    .iter()
    .map(|&(na, nb)| periodic_window_run(na, nb, beads, 40.0, Some((60, 150)), Engine::Hybrid))
    .collect::<Result<_, _>>()?;
    for run in &runs {
        let (na, nb) = (run.na, run.nb);
        println!("case {na}/{nb} (wall {:.1} s):", run.seconds);
        let ret: Vec<String> = (0..WIDTHS.len())
            .map(|wi| {
                format!(
                    "W={}: {:.4}",
                    WIDTHS[wi],
                    retention(run, wi, 25, beads - 10).unwrap_or(f64::NAN)
                )
            })
            .collect();
        println!(
            "  retention E(front {})/E(front 25): {}",
            beads - 10,
            ret.join(", ")
        );
        if let Ok(f) = windowed_gamma(run, 1) {
            println!(
                "  windowed γ (W=12) = {:.3e} ± {:.1e}",
                f.gamma, f.gamma_stderr
            );
        }
        if let Some(b) = breathing(run, 40, beads - 10) {
            println!(
                "  speed {:.4e} beads/time ({:.3} time units per bead); {} frames",
                b.speed,
                1.0 / b.speed,
                b.frames
            );
            println!("  peak-velocity periods: {}", periods(&b.peak_periods));
            println!("  lag periods:           {}", periods(&b.lag_periods));
            println!(
                "  shape |v_peak|/sqrt(E_w20): range/mean {:.3}; once per 2 beads: rel. s.d. {:.4}, periods (4-100 beads) {}",
                b.shape_range,
                b.strobe_rel_sd,
                periods(&b.strobe_periods)
            );
        }
        if let Some(c) = pair_leader_changes(run, 0.1, 0.02) {
            println!("  n_a pairs (2j, 2j+1), beads 60..150: median number of changes of the faster bead while the wave passes (|v| > 10 % of peak, hysteresis 2 %): {c}");
        }
        for p in run.watch.track.iter().step_by(4) {
            csv.push_str(&format!(
                "{na}/{nb},{:.6e},{},{:.6e},{:.6e},{:.6e},{},{:.6e}\n",
                p.t, p.front, p.energy[0], p.energy[1], p.energy[2], p.peak_bead, p.peak_velocity
            ));
        }
    }
    write_data("breathing.csv", &csv)?;
    println!("breathing wall time {:.1} s", t0.elapsed().as_secs_f64());
    Ok(())
}

/// Energy transfer ratio vs n_right − n_left (Fig. 23).
pub fn transfer() -> Res {
    let t0 = Instant::now();
    let (beads, eps, seeds) = (400, 0.04, 4u64);
    let mut csv = String::from("nbar,eps,seed,bead,dn,ratio\n");
    println!(
        "N = {beads}, ε = {eps}, contacts 0..19 uniform, beads 22..{} , seeds 1..={seeds}",
        beads - 20
    );
    for nbar in [2.4, 3.7] {
        let mut all: Vec<TransferSample> = Vec::new();
        for seed in 1..=seeds {
            let (s, secs) = transfer_run(nbar, eps, seed, beads)?;
            let f = transfer_trend(&s)?;
            let (neg, pos): (Vec<_>, Vec<_>) = s.iter().partition(|x| x.dn < 0.0);
            let mean =
                |v: &[&TransferSample]| v.iter().map(|x| x.ratio).sum::<f64>() / v.len() as f64;
            println!(
                "n̄ = {nbar}, seed {seed}: slope d(ratio)/d(dn) = {:.3} ± {:.3}, intercept {:.4}; mean ratio dn<0: {:.4}, dn>0: {:.4}; {} beads, {secs:.1} s",
                f.coef[0],
                f.stderr[0],
                f.coef[1],
                mean(&neg),
                mean(&pos),
                s.len()
            );
            for x in &s {
                csv.push_str(&format!(
                    "{nbar},{eps},{seed},{},{:.6},{:.6e}\n",
                    x.bead, x.dn, x.ratio
                ));
            }
            all.extend(s);
        }
        let f = transfer_trend(&all)?;
        println!(
            "n̄ = {nbar}, pooled: ratio = {:.4} + {:.3} · dn (± {:.3}), residual s.d. {:.4}",
            f.coef[1], f.coef[0], f.stderr[0], f.residual_sd
        );
        println!("| dn bin centre | beads | mean ratio | s.d. |");
        println!("|---|---|---|---|");
        for b in bin_samples(&all, -0.08, 0.08, 8) {
            println!(
                "| {:+.3} | {} | {:.4} | {:.4} |",
                b.centre, b.count, b.mean, b.sd
            );
        }
    }
    write_data("transfer.csv", &csv)?;
    println!("transfer wall time {:.1} s", t0.elapsed().as_secs_f64());
    Ok(())
}

/// Composite mass–exponent interface grid and transition contour (Fig. 25).
/// One Markdown row per Δn of `value` over the mass ratios of the grid.
fn print_rows(rows: &[CompositeRow], dns: &[f64], value: impl Fn(&CompositeRow) -> f64) {
    for &dn in dns {
        let cells: Vec<String> = rows
            .iter()
            .filter(|r| r.dn == dn)
            .map(|r| format!("{:.4}", value(r)))
            .collect();
        println!("| {dn:+.3} | {} |", cells.join(" | "));
    }
}

pub fn composite() -> Res {
    let t0 = Instant::now();
    let dns: Vec<f64> = (0..9).map(|i| -0.5 + 0.125 * i as f64).collect();
    let ratios: Vec<f64> = (-6..=6).map(|k| 2f64.powf(k as f64 / 2.0)).collect();
    let (beads, k) = (150, 50);
    let rows = composite_grid(&dns, &ratios, beads, k)?;
    println!(
        "E_refl/E_in = energy of left-moving pulses left of k (minus the uniform chain's striker"
    );
    println!("rebound), n1 = 3.0, N = {beads}, k = {k}; rows Δn, columns m2/m1");
    println!(
        "| Δn \\ m2/m1 | {} |",
        ratios
            .iter()
            .map(|r| format!("{r:.3}"))
            .collect::<Vec<_>>()
            .join(" | ")
    );
    println!("|---|{}", "---|".repeat(ratios.len()));
    print_rows(&rows, &dns, |r| r.e_refl);
    println!("E_left − E_left(uniform) (the measure of the (n1, n2) grid), same layout:");
    print_rows(&rows, &dns, |r| r.left_excess);
    println!("transmitted plateau width (beads k..k+19 within 25 % of max) at m2/m1 = 1 and 1/2:");
    for &dn in &dns {
        let p: Vec<String> = rows
            .iter()
            .filter(|r| r.dn == dn && (r.mass_ratio == 1.0 || (r.mass_ratio - 0.5).abs() < 1e-12))
            .map(|r| format!("{}", r.plateau))
            .collect();
        println!("  Δn = {dn:+.3}: {}", p.join(", "));
    }
    let worst = rows.iter().map(|r| r.settle.abs()).fold(0.0, f64::max);
    let unreached = rows.iter().filter(|r| !r.reached).count();
    println!("largest |change of E_left| over the last quarter of the runs: {worst:.2e}; runs without front stop: {unreached}");
    // the Δn < 0 rows continued below the paper's range, to follow the contour out of the grid
    let ext: Vec<f64> = (7..=10).map(|k| 2f64.powf(-(k as f64) / 2.0)).collect();
    let neg: Vec<f64> = dns.iter().copied().filter(|d| *d < -0.2).collect();
    let mut rows_ext = composite_grid(&neg, &ext, beads, k)?;
    println!("extension below m2/m1 = 1/8 (Δn < −0.2):");
    for &dn in &neg {
        let cells: Vec<String> = rows_ext
            .iter()
            .filter(|r| r.dn == dn)
            .map(|r| format!("{:.4}: {:.4}", r.mass_ratio, r.e_refl))
            .collect();
        println!("  Δn = {dn:+.3}: {}", cells.join(", "));
    }
    rows_ext.extend(rows.iter().copied());
    for level in [0.05, 0.01, 0.001] {
        let c = contour_crossings(&rows_ext, level);
        let s: Vec<String> = c
            .iter()
            .map(|(d, r)| format!("({d:+.3}, {r:.4})"))
            .collect();
        println!("contour E_refl = {level}: (Δn, m2/m1) = {}", s.join(" "));
    }
    // dense cross-check of one point
    let h = composite_run(3.0, -0.5, 0.5, beads, k, Engine::Hybrid)?;
    let d = composite_run(3.0, -0.5, 0.5, beads, k, Engine::Dense)?;
    println!(
        "cross-check Δn = −0.5, m2/m1 = 0.5: E_left/E hybrid {:.6}, dense {:.6}; left-moving pulses hybrid {:.6}, dense {:.6}; wall {:.1} s / {:.1} s",
        h.left_fraction, d.left_fraction, h.back_fraction, d.back_fraction, h.seconds, d.seconds
    );
    write_data("composite.csv", &grid_csv(&rows))?;
    write_data("composite_ext.csv", &grid_csv(&rows_ext))?;
    println!("composite wall time {:.1} s", t0.elapsed().as_secs_f64());
    Ok(())
}
