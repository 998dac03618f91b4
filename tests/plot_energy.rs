//! `beadchain plot energy` (issue 14): the two-sided decay fit at an interface (`--interface`),
//! its errors, and decade ticks on the log axis, read back from the SVG text and standard output.
//!
//! Text needs a TrueType font at run time (CI installs DejaVu Sans); without one the figures
//! have no text and the text assertions are skipped with a note (the numeric ones still run).

mod common;
mod plot_support;

use beadchain::analysis::FitRange;
use beadchain::plot::{self, energy, EnergyOptions};
use beadchain::snapshot::Snapshot;
use plot_support::*;

#[test]
fn energy_interface_fits_each_side_separately() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let (g1, g2, kk) = (0.02, 0.08, 30);
    let path = write_snap(d, "e.snap", &chain60(), &decaying_pulse(60, kk, g1, g2));
    let snap = Snapshot::open(&path).expect("open");
    let opts = EnergyOptions {
        interface: Some(kk),
        log: true,
        ..Default::default()
    };
    let e = energy::energy(&snap, &opts).expect("energy");
    // defaults 20..50 split at the interface: positions 20 to below 30, and 30 to 50
    assert_eq!(e.fits.len(), 2);
    assert_eq!(e.fits[0].range, FitRange::below(20.0, 30.0));
    assert_eq!(e.fits[1].range, FitRange::inclusive(30.0, 50.0));
    for (s, g) in e.fits.iter().zip([g1, g2]) {
        let f = s.fit.as_ref().expect("fit");
        // exact exponentials: γ to 1e-9 absolute (5e-8 relative)
        assert!((f.gamma - g).abs() < 1e-9, "{}: {f:?}", s.range);
    }
    assert_eq!(
        (
            e.fits[0].fit.as_ref().unwrap().n,
            e.fits[1].fit.as_ref().unwrap().n
        ),
        (10, 21)
    );
    // one fit across the interface mixes both rates (what --interface avoids)
    let across = energy::energy(&snap, &EnergyOptions::default()).expect("energy");
    let g = across.fits[0].fit.as_ref().expect("fit").gamma;
    assert!(
        g > g1 + 0.01 && g < g2 - 0.01,
        "across the interface: γ = {g}"
    );
    // the figure shows both fits (legend entries), the CLI prints both
    let e_out = d.join("e.svg");
    plot::write_figure(&e, &e_out).expect("write");
    if let Some(l) = texts(&e_out) {
        assert!(
            l.iter()
                .any(|s| s.starts_with("fit x 20 to below 30: γ = 2.0000e-2")),
            "{l:?}"
        );
        assert!(
            l.iter()
                .any(|s| s.starts_with("fit x 30 to 50: γ = 8.0000e-2")),
            "{l:?}"
        );
    }
    let o = common::bc(
        d,
        &[
            "plot",
            "energy",
            "e.snap",
            "--interface",
            "30",
            "--out",
            "c.png",
        ],
    );
    common::assert_ok(&o);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("decay fit over positions 20 to below 30: gamma = 2.000000e-2"),
        "{out}"
    );
    assert!(
        out.contains("decay fit over positions 30 to 50: gamma = 8.000000e-2"),
        "{out}"
    );
}

/// `plot energy --interface` errors name the option (bead out of range, a fit range with beads
/// on one side only).
#[test]
fn energy_interface_errors_name_the_option() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    write_snap(d, "e.snap", &chain60(), &decaying_pulse(60, 30, 0.02, 0.08));
    let e = ["plot", "energy", "e.snap", "--out", "x.png", "--interface"];
    fails(
        d,
        &[&e[..], &["0"]].concat(),
        "--interface: bead 0 is out of range",
    );
    fails(
        d,
        &[&e[..], &["60"]].concat(),
        "--interface: bead 60 is out of range",
    );
    fails(
        d,
        &[&e[..], &["40", "--from", "45"]].concat(),
        "--interface 40: the fit range --from 45 --to 50 must contain beads on both sides",
    );
}

#[test]
fn log_energy_axis_ticks_at_decades() {
    // before: `plot energy --log` ticked 0.993, 0.994, … (plotters' linear ticks of log10 E)
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    write_snap(d, "e.snap", &chain60(), &decaying_pulse(60, 30, 0.1, 0.2));
    ok(d, &["plot", "energy", "e.snap", "--log", "--out", "e.svg"]);
    let Some(l) = texts(&d.join("e.svg")) else {
        return;
    };
    // E/E0 runs from 1 down to exp(-3 - 0.2*29) = 1.5e-4: decades 1e-4 .. 1
    let y: Vec<&String> = l
        .iter()
        .filter(|s| s.parse::<f64>().is_ok_and(|v| v > 0.0 && v <= 1.0))
        .filter(|s| s.contains('e') || s.contains('.') || *s == "1")
        .collect();
    let want = ["1e-4", "1e-3", "0.01", "0.1", "1"];
    for w in want {
        assert!(y.iter().any(|s| *s == w), "no decade {w}: {l:?}");
    }
    for s in &y {
        let v: f64 = s.parse().unwrap();
        // a decade: log10 within 1e-12 (absolute) of an integer
        assert!(
            (v.log10() - v.log10().round()).abs() < 1e-12,
            "{s} in {l:?}"
        );
    }
}
