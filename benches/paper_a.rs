//! Experiments for `validation/REPORT.md` items Fig. 2 (wavelength), Figs. 4–5 (gap timings),
//! Figs. 16–17 (impurity examples, collective impurity beads), appendices A and B. Included from
//! `paper_validation.rs`; subcommands `wavelength`, `timings`, `impurity_examples`, `appendix_a`,
//! `appendix_b`. Each prints a report (redirect to `validation/out_<name>.txt`) and writes
//! `validation/data/<name>.csv` (header row; written to a temporary file and renamed).

use beadchain::analysis::timings::InterfaceTimings;
use beadchain::experiments::appendix::{energy_error, perturbed_interface, Perturbed};
use beadchain::experiments::impurities::{
    collective_impurity, impurity_example, share, PulseKind, PulseRow,
};
use beadchain::experiments::paper::{physical_scene, time_per_bead, PaperError};
use beadchain::experiments::timings::{interface_timing_run, TimingRun};
use beadchain::experiments::wavelength::{measure_wavelength, WavelengthResult};
use beadchain::names::Named;
use beadchain::scene::Engine;
use std::path::PathBuf;
use std::time::Instant;

/// Writes `validation/data/<name>.csv` atomically.
fn write_csv(name: &str, header: &str, rows: &[String]) -> Result<(), PaperError> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("validation/data");
    let io = |e: std::io::Error, p: &std::path::Path| {
        PaperError::Engine(beadchain::engine::EngineError::Observer(format!(
            "writing {}: {e}",
            p.display()
        )))
    };
    std::fs::create_dir_all(&dir).map_err(|e| io(e, &dir))?;
    let path = dir.join(format!("{name}.csv"));
    let tmp = dir.join(format!(".{name}.csv.tmp"));
    let mut text = String::from(header);
    text.push('\n');
    for r in rows {
        text.push_str(r);
        text.push('\n');
    }
    std::fs::write(&tmp, text).map_err(|e| io(e, &tmp))?;
    std::fs::rename(&tmp, &path).map_err(|e| io(e, &path))?;
    println!("wrote {}", path.display());
    Ok(())
}

fn opt(x: Option<f64>) -> String {
    x.map_or("NaN".into(), |v| format!("{v:.6e}"))
}

/// One `data/wavelength.csv` row.
fn wavelength_row(r: &WavelengthResult, n: f64, beads: usize, engine: &str) -> String {
    format!(
        "{n},{beads},{},{},{},{},{},{},{},{},{},{},{},{},{engine}",
        r.lambda_c,
        r.lambda_fit.0,
        r.lambda_fit.1,
        r.fit_rms,
        r.fwhm.0,
        r.fwhm.1,
        r.width_01.0,
        r.width_01.1,
        r.count_01,
        r.tau,
        r.probes.0,
        r.probes.1
    )
}

fn wavelength() -> Result<(), PaperError> {
    let t0 = Instant::now();
    println!("| n | λ_c | λ_fit (j1) | λ_fit (j2) | λ_fit/λ_c | FWHM / cont. | width >0.1% / cont. | beads >0.1% | fit rms | τ | wall (s) |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    let ns = [2.1, 2.25, 2.5, 2.75, 3.0, 3.5, 4.0, 5.0, 6.0];
    for &n in &ns {
        let beads = if n < 2.4 { 400 } else { 200 };
        let r = measure_wavelength(n, beads, Engine::Hybrid, 1e-8, 0.005)?;
        println!(
            "| {n} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} / {:.3} | {:.2} / {:.2} | {:.2} | {:.1e} | {:.4} | {:.1} |",
            r.lambda_c,
            r.lambda_fit.0,
            r.lambda_fit.1,
            r.lambda_fit.0 / r.lambda_c,
            r.fwhm.0,
            r.fwhm.1,
            r.width_01.0,
            r.width_01.1,
            r.count_01,
            r.fit_rms,
            r.tau,
            r.seconds
        );
        rows.push(wavelength_row(&r, n, beads, "hybrid"));
    }
    // cross-check one case with the dense engine
    let r = measure_wavelength(3.0, 200, Engine::Dense, 1e-8, 0.005)?;
    println!(
        "dense cross-check n = 3: λ_fit = {:.4} / {:.4}, FWHM {:.4}, beads >0.1% {:.2}, τ = {:.5}, wall {:.1} s",
        r.lambda_fit.0, r.lambda_fit.1, r.fwhm.0, r.count_01, r.tau, r.seconds
    );
    rows.push(wavelength_row(&r, 3.0, 200, "dense"));
    write_csv(
        "wavelength",
        "n,beads,lambda_c,lambda_fit_j1,lambda_fit_j2,fit_rms,fwhm,fwhm_c,width_01,width_01_c,count_01,tau,j1,j2,engine",
        &rows,
    )?;
    println!("wavelength wall time {:.1} s", t0.elapsed().as_secs_f64());
    Ok(())
}

fn print_timings(label: &str, s: &InterfaceTimings, tau: f64) {
    let t1 = s.t1.unwrap_or(f64::NAN);
    let rel = |x: Option<f64>| x.map_or("—".into(), |v| format!("{:.2}", (v - t1) / tau));
    println!(
        "  {label}: t1 = {}, t2 = {}, t3 = {} (collision ends {}), t4 = {}, t5 = {}",
        opt(s.t1),
        opt(s.t2),
        opt(s.t3),
        opt(s.t3_end),
        opt(s.t4),
        opt(s.t5)
    );
    println!(
        "    (t_i − t1)/τ: t2 {}, t3 {}, t3_end {}, t4 {}, t5 {}",
        rel(s.t2),
        rel(s.t3),
        rel(s.t3_end),
        rel(s.t4),
        rel(s.t5)
    );
}

fn timing_row(engine: &str, src: &str, r: &TimingRun, s: &InterfaceTimings) -> String {
    format!(
        "{engine},{src},{},{},{},{},{},{},{},{},{},{},{},{},{}",
        r.tau,
        r.v_in,
        opt(s.t1),
        opt(s.t2),
        opt(s.t3),
        opt(s.t3_end),
        opt(s.t4),
        opt(s.t5),
        r.frozen1.0 / r.v_in,
        r.frozen1.1 / r.v_in,
        r.frozen2.0 / r.v_in,
        r.frozen2.1 / r.v_in,
        r.outcome.relative_energy_error()
    )
}

fn timings() -> Result<(), PaperError> {
    let t0 = Instant::now();
    let mut rows = Vec::new();
    for engine in [Engine::Hybrid, Engine::Dense] {
        let r = interface_timing_run(3.0, 3.5, 150, 50, engine)?;
        println!(
            "interface 3.0 -> 3.5, N = 150, k = 50, engine {}: τ(n1) = {:.4e}, v_in = {:.4e}, run to t = {:.4e}, energy error {:.1e}, wall {:.2} s",
            engine.name(),
            r.tau,
            r.v_in,
            r.window.last.0,
            r.outcome.relative_energy_error(),
            r.seconds
        );
        print_timings("from sampled overlaps", &r.frames, r.tau);
        let list = |x: &[beadchain::analysis::timings::Transition]| {
            x.iter()
                .take(16)
                .map(|x| {
                    format!(
                        "{}{}@{:.1}",
                        if x.closed { "C" } else { "O" },
                        x.contact,
                        (x.t - r.frames.t1.unwrap_or(0.0)) / r.tau
                    )
                })
                .collect::<Vec<_>>()
                .join(" ")
        };
        println!(
            "    transitions (C/O contact @ (t − t1)/τ), sampled: {}",
            list(&r.transitions)
        );
        if !r.event_transitions.is_empty() {
            println!("    transitions, event log: {}", list(&r.event_transitions));
        }
        rows.push(timing_row(engine.name(), "frames", &r, &r.frames));
        if let Some(ev) = &r.events {
            print_timings("from the hybrid event log", ev, r.tau);
            rows.push(timing_row(engine.name(), "events", &r, ev));
        }
        println!(
            "  frozen state 1 (t2..t3): v49/v_in = {:+.4}, v50/v_in = {:+.4}; frozen state 2 (after the collision): v49/v_in = {:+.4}, v50/v_in = {:+.4}",
            r.frozen1.0 / r.v_in,
            r.frozen1.1 / r.v_in,
            r.frozen2.0 / r.v_in,
            r.frozen2.1 / r.v_in
        );
    }
    write_csv(
        "timings",
        "engine,source,tau,v_in,t1,t2,t3,t3_end,t4,t5,v49_frozen1,v50_frozen1,v49_frozen2,v50_frozen2,energy_error",
        &rows,
    )?;
    println!("timings wall time {:.1} s", t0.elapsed().as_secs_f64());
    Ok(())
}

fn pulse_lines(rows: &[PulseRow]) {
    for p in rows {
        println!(
            "    {:>4} ({:>3}..{:<3}) {:>+8.4} {:>9.5} {:?}",
            p.peak_bead, p.span.0, p.span.1, p.v_rel, p.energy, p.kind
        );
    }
}

fn impurity_examples() -> Result<(), PaperError> {
    let t0 = Instant::now();
    let mut rows = Vec::new();
    for n_imp in [3.5, 2.5] {
        for stop_at in [90, 138] {
            let r = impurity_example(3.0, 1, n_imp, 150, 50, stop_at)?;
            println!(
                "impurity s = 1, n = 3.0, n_imp = {n_imp} (contact 50, beads 50-51), N = 150, leading wave at bead {stop_at}: t = {:.4e}, v_in = {:.4e}, wall {:.2} s",
                r.t_stop, r.v_in, r.seconds
            );
            println!("  pulses (peak bead, span, v/v_in, energy share, kind):");
            pulse_lines(&r.pulses);
            println!(
                "  reflected energy {:.4}, transmitted {:.4}, transmitted pulses above 1 % v_in: {}",
                share(&r.pulses, PulseKind::Reflected),
                share(&r.pulses, PulseKind::Transmitted),
                r.pulses
                    .iter()
                    .filter(|p| p.kind == PulseKind::Transmitted)
                    .count()
            );
            for p in &r.pulses {
                rows.push(format!(
                    "example,3,1,{n_imp},{stop_at},{},{},{},{},{},{:?},,,,",
                    p.peak_bead, p.span.0, p.span.1, p.v_rel, p.energy, p.kind
                ));
            }
        }
    }
    println!(
        "collective impurity beads (n = 4, frames τ/50, window: fastest impurity bead > 0.1 v_in):"
    );
    println!("| n | s | δn | max spread / v_in | mean spread / v_in | peak v / v_in | two-body 2/(s+2) | window (beads of τ) | wall (s) |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for (s, dn) in [(1usize, -0.25), (1, -1.5), (5, -0.25), (5, -1.5)] {
        let c = collective_impurity(4.0, s, dn, 100, 50)?;
        println!(
            "| 4 | {s} | {dn} | {:.4} | {:.4} | {:.4} | {:.4} | {:.1} | {:.1} |",
            c.max_spread, c.mean_spread, c.peak, c.two_body, c.duration_beads, c.seconds
        );
        rows.push(format!(
            "collective,4,{s},{},,,,,,,,{},{},{},{}",
            4.0 + dn,
            c.max_spread,
            c.mean_spread,
            c.peak,
            c.two_body
        ));
    }
    write_csv(
        "impurity_examples",
        "kind,n,s,n_imp,stop_bead,peak_bead,first,last,v_rel,energy,pulse_kind,max_spread,mean_spread,peak_rel,two_body",
        &rows,
    )?;
    println!(
        "impurity_examples wall time {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

fn appendix_a() -> Result<(), PaperError> {
    let t0 = Instant::now();
    let mut rows = Vec::new();
    let exps = [
        1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12,
    ];
    // (label, n1, n2, beads, until in units of τ): uniform chains reach the separated steady
    // state; the 3.0 -> 3.5 interface (k = 50) runs to a fixed time (wave at the end) only, its
    // slow residual waves in the n = 3.5 medium take > 6000 τ to leave (total-energy error only)
    for (label, n1, n2, beads, span) in [
        ("uniform", 2.5, 2.5, 60usize, 20000.0),
        ("uniform", 3.0, 3.0, 30, 20000.0),
        ("interface", 3.0, 3.5, 100, 70.0),
    ] {
        let (ta, tb) = (time_per_bead(n1)?, time_per_bead(n2)?);
        let tau = ta.max(tb);
        let ex = if n1 == n2 {
            format!("{n1}")
        } else {
            format!("{{ base = {n1}, segments = [{{ from = 50, value = {n2} }}] }}")
        };
        let until = tau * span;
        let sc = physical_scene(beads, &ex, 0, until, tau)?;
        println!("{label} {n1} -> {n2}, N = {beads}: steady-state check every τ = {tau:.4e}, until {until:.3e}");
        println!("| sweep | engine | rtol | atol | KE error (A.6) | total-energy error | t_steady | wall (s) | last frame |");
        println!("|---|---|---|---|---|---|---|---|---|");
        for engine in [Engine::Hybrid, Engine::Dense] {
            for sweep in ["rtol", "atol"] {
                for &x in &exps {
                    let (rtol, atol) = if sweep == "rtol" {
                        (x, 1e-15)
                    } else {
                        (1e-13, x)
                    };
                    let r = energy_error(&sc, engine, rtol, atol, until, tau);
                    println!(
                        "| {sweep} | {} | {rtol:.0e} | {atol:.0e} | {:.3e} | {:.3e} | {} | {:.2} | max overlap {:.1e} @{}, worst step {:.1e} @{}{} |",
                        engine.name(),
                        r.ke_error,
                        r.energy_error,
                        opt(r.t_steady),
                        r.seconds,
                        r.max_overlap.0,
                        r.max_overlap.1,
                        r.worst_step.0,
                        r.worst_step.1,
                        r.failure
                            .as_ref()
                            .map_or(String::new(), |f| format!("; failed: {f}"))
                    );
                    rows.push(format!(
                        "{label},{n1},{n2},{beads},{sweep},{},{rtol:e},{atol:e},{},{},{},{},{}",
                        engine.name(),
                        r.ke_error,
                        r.energy_error,
                        opt(r.t_steady),
                        r.seconds,
                        r.failure.is_some()
                    ));
                }
            }
        }
    }
    write_csv(
        "appendix_a",
        "setup,n1,n2,beads,sweep,engine,rtol,atol,ke_error,energy_error,t_steady,wall_s,failed",
        &rows,
    )?;
    println!("appendix_a wall time {:.1} s", t0.elapsed().as_secs_f64());
    Ok(())
}

fn perturbed_line(p: &Perturbed) -> (String, String) {
    let s = &p.timings;
    let t1 = s.t1.unwrap_or(f64::NAN);
    let rel = |x: Option<f64>| x.map_or(f64::NAN, |v| (v - t1) / p.tau);
    let refl = share(&p.pulses, PulseKind::Reflected);
    let trans: Vec<&PulseRow> = p
        .pulses
        .iter()
        .filter(|r| r.kind == PulseKind::Transmitted)
        .collect();
    let primary = trans.iter().map(|r| r.v_rel).fold(0.0, f64::max);
    let secondary = trans
        .iter()
        .filter(|r| r.v_rel < primary)
        .max_by(|a, b| a.v_rel.total_cmp(&b.v_rel));
    let refl_peak = p
        .pulses
        .iter()
        .filter(|r| r.kind == PulseKind::Reflected)
        .map(|r| r.v_rel)
        .fold(0.0, f64::min);
    let n_trans_5 = trans.iter().filter(|r| r.v_rel > 0.05).count();
    let line = format!(
        "| {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.4} | {:.4} | {} | {:+.4} | {} | {} | {:.4} | {:.2} |",
        p.rel_sigma,
        p.seed,
        rel(s.t2),
        rel(s.t3),
        rel(s.t4),
        rel(s.t5),
        p.noise,
        primary,
        secondary.map_or("—".into(), |r| format!("{:+.4} @{}", r.v_rel, r.peak_bead)),
        refl_peak,
        n_trans_5,
        p.plateau,
        refl,
        p.seconds
    );
    let row = format!(
        "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
        p.rel_sigma,
        p.seed,
        rel(s.t2),
        rel(s.t3),
        rel(s.t4),
        rel(s.t5),
        p.noise,
        primary,
        secondary.map_or(f64::NAN, |r| r.v_rel),
        secondary.map_or(f64::NAN, |r| r.peak_bead as f64),
        refl_peak,
        n_trans_5,
        p.plateau,
        refl,
        p.energy_error,
        p.seconds
    );
    (line, row)
}

fn appendix_b() -> Result<(), PaperError> {
    let t0 = Instant::now();
    let mut rows = Vec::new();
    for (n1, n2) in [(3.0, 3.5), (3.0, 2.5), (3.5, 3.0)] {
        let (ta, tb) = (time_per_bead(n1)?, time_per_bead(n2)?);
        println!(
            "interface {n1} -> {n2}, N = 150, k = 50, σ = (σ/Δn)·{:.2}:",
            (n2 - n1).abs()
        );
        println!("| σ/Δn | seed | (t2−t1)/τ | (t3−t1)/τ | (t4−t1)/τ | (t5−t1)/τ | noise / v_in | primary v/v_in | secondary transmitted (v/v_in @bead) | reflected peak v/v_in | transmitted pulses > 5 % | plateau beads | reflected energy | wall (s) |");
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        let mut cases = vec![(0.0, 0u64)];
        for rs in [0.01, 0.05] {
            for seed in 1..=5 {
                cases.push((rs, seed));
            }
        }
        for (rs, seed) in cases {
            let p = perturbed_interface(n1, n2, rs, seed, 150, 50, ta, ta.max(tb))?;
            let (line, row) = perturbed_line(&p);
            println!("{line}");
            rows.push(format!("{n1},{n2},{row}"));
        }
    }
    write_csv(
        "appendix_b",
        "n1,n2,rel_sigma,seed,t2_rel,t3_rel,t4_rel,t5_rel,noise,primary,secondary,secondary_bead,reflected_peak,transmitted_pulses_5pct,plateau,reflected_energy,energy_error,wall_s",
        &rows,
    )?;
    println!("appendix_b wall time {:.1} s", t0.elapsed().as_secs_f64());
    Ok(())
}

/// Runs subcommand `what`; `false` if it is not one of this file's.
pub fn dispatch(what: &str) -> Result<bool, PaperError> {
    match what {
        "wavelength" => wavelength()?,
        "timings" => timings()?,
        "impurity_examples" => impurity_examples()?,
        "appendix_a" => appendix_a()?,
        "appendix_b" => appendix_b()?,
        _ => return Ok(false),
    }
    Ok(true)
}
