//! The resolved scene as plain text (`beadchain scene show`): every per-bead and per-contact
//! value after the builders (`alternate`, `random`, `taper`, ...) and the unit conversion
//! (paper eqs. 10–11), in computer units.
//!
//! - [`to_toml`]: a complete scene file with explicit arrays. Parsing it gives the same
//!   resolved [`Scene`] (`==`, floats in Rust's shortest round-trip form, so bit for bit) and
//!   therefore the same run: every key a scene can hold is written out — masses, exponents,
//!   prefactors, precompression, the initial state, the field, walls (soft ones with their
//!   damping), the contact law with one damping coefficient per contact (whatever gave it:
//!   `damping`, `restitution` + `impact_speed`, or the material viscosities), `[hard]` with its
//!   collapse interval, `[output]`, and `[run]` (until, every, rtol, atol, method, engine).
//!   A physical scene becomes `[units] system = "computer"` with its four scales (`m0`,
//!   `time_unit`, `mu`, `n0`): the values are in computer units, and the scales still convert
//!   times, velocities and energies to SI (`run`, `inspect`, `export --units si`); the material
//!   keys (`radius`, `young`, ...) and the `_si` keys are gone, having been applied. The note on
//!   the scales that parsing appends to a physical scene's description is left out (parsing
//!   appends it again).
//! - [`to_csv`]: one row per bead (`bead,mass,u0,v0,force`) with the values of the contact to its
//!   right (`exponent,prefactor,precompression,restitution`; empty on the last bead, and
//!   `restitution` empty for a soft contact), readable by `pandas.read_csv` without options.

use super::settings::units_note;
use super::Scene;
use crate::model::Wall;
use crate::names::Named;
use std::fmt::Write as _;

fn num(x: f64) -> String {
    format!("{x:?}")
}

fn array(xs: &[f64]) -> String {
    let items: Vec<String> = xs.iter().map(|&x| num(x)).collect();
    format!("[{}]", items.join(", "))
}

fn quoted(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// A wall's inline table; `damping` is the coefficient of a soft wall in a damped chain (a hard
/// wall's follows from the contacts when parsed).
fn wall(w: &Wall, damping: Option<f64>) -> String {
    let mut parts = Vec::new();
    match w.restitution {
        Some(e) => {
            parts.push("hard = true".to_string());
            parts.push(format!("restitution = {}", num(e)));
        }
        None => {
            parts.push(format!("exponent = {}", num(w.exponent)));
            parts.push(format!("prefactor = {}", num(w.prefactor)));
            if let Some(g) = damping {
                parts.push(format!("damping = {}", num(g)));
            }
        }
    }
    if w.precompression != 0.0 || w.restitution.is_none() {
        parts.push(format!("precompression = {}", num(w.precompression)));
    }
    format!("{{ {} }}", parts.join(", "))
}

/// The description as the scene file gave it: without the note on the unit scales that
/// parsing appends to a physical scene's description.
fn given_description(s: &Scene) -> String {
    let d = s.description.as_str();
    let Some(sc) = &s.units else {
        return d.to_string();
    };
    match d.strip_suffix(units_note(sc).as_str()) {
        Some(rest) => rest.strip_suffix(' ').unwrap_or(rest).to_string(),
        None => d.to_string(),
    }
}

/// The scene as a TOML scene file with explicit arrays in computer units (module docs).
pub fn to_toml(s: &Scene) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "# resolved scene `{}`: computer units, every value explicit",
        s.name
    );
    let _ = writeln!(o, "[scene]\nname = {}", quoted(&s.name));
    let _ = writeln!(o, "description = {}", quoted(&given_description(s)));
    let _ = writeln!(o, "seed = {}", s.seed);
    if let Some(sc) = &s.units {
        let _ = writeln!(
            o,
            "\n[units]  # values below are in computer units; these scales convert them to SI"
        );
        let _ = writeln!(o, "system = \"computer\"\nm0 = {}", num(sc.mass));
        let _ = writeln!(o, "time_unit = {}", num(sc.time));
        let _ = writeln!(o, "mu = {}\nn0 = {}", num(sc.mu), num(sc.n0));
    }
    chain_tables(&mut o, s);
    run_tables(&mut o, s);
    o
}

/// `[chain]` (with the contact law), `[initial]`, `[field]` and `[walls]`.
fn chain_tables(o: &mut String, s: &Scene) {
    let c = &s.chain;
    let _ = writeln!(o, "\n[chain]\nbeads = {}", c.mass.len());
    let _ = writeln!(o, "mass = {}", array(&c.mass));
    let _ = writeln!(o, "exponent = {}", array(&c.exponent));
    let _ = writeln!(o, "prefactor = {}", array(&c.prefactor));
    if let Some(p) = &c.precompression {
        let _ = writeln!(o, "precompression = {}", array(p));
    }
    if let Some(d) = &c.damping {
        let _ = writeln!(o, "law = {}", quoted(d.law.name()));
        let _ = writeln!(o, "damping = {}", array(&d.contact));
    }
    let _ = writeln!(o, "\n[initial]\ndisplacement = {}", array(&s.u0));
    let _ = writeln!(o, "velocity = {}", array(&s.v0));
    if let Some(f) = &c.field {
        let _ = writeln!(o, "\n[field]\nforce = {}", array(f));
    }
    if c.left_wall.is_some() || c.right_wall.is_some() {
        let _ = writeln!(o, "\n[walls]");
        let damping = c.damping.as_ref();
        for (side, w, g) in [
            ("left", &c.left_wall, damping.map(|d| d.left_wall)),
            ("right", &c.right_wall, damping.map(|d| d.right_wall)),
        ] {
            if let Some(w) = w {
                let _ = writeln!(o, "{side} = {}", wall(w, g));
            }
        }
    }
}

/// `[hard]`, `[run]` and `[output]`.
fn run_tables(o: &mut String, s: &Scene) {
    if let Some(h) = &s.chain.hard {
        let (ks, es): (Vec<usize>, Vec<f64>) = h
            .restitution
            .iter()
            .enumerate()
            .filter_map(|(k, e)| e.map(|e| (k, e)))
            .unzip();
        let ks: Vec<String> = ks.iter().map(|k| k.to_string()).collect();
        let _ = writeln!(o, "\n[hard]\ncontacts = [{}]", ks.join(", "));
        let _ = writeln!(o, "restitution = {}", array(&es));
        let _ = writeln!(o, "collapse_interval = {}", num(h.collapse_interval));
    }
    let r = &s.run;
    let _ = writeln!(o, "\n[run]\nuntil = {}", num(r.until));
    if let Some(x) = r.every {
        let _ = writeln!(o, "every = {}", num(x));
    }
    if let Some(x) = r.rtol {
        let _ = writeln!(o, "rtol = {}", num(x));
    }
    if let Some(x) = r.atol {
        let _ = writeln!(o, "atol = {}", num(x));
    }
    if let Some(m) = r.method {
        let _ = writeln!(o, "method = {}", quoted(m.name()));
    }
    if let Some(e) = r.engine {
        let _ = writeln!(o, "engine = {}", quoted(e.name()));
    }
    if let Some(sel) = &r.output {
        let _ = writeln!(o, "\n[output]\nfields = {}", quoted(sel.fields.name()));
        if let Some(b) = &sel.beads {
            let items: Vec<String> = b.iter().map(u64::to_string).collect();
            let _ = writeln!(o, "beads = [{}]", items.join(", "));
        }
        if let Some(k) = sel.frames_max {
            let _ = writeln!(o, "frames_max = {k}");
        }
    }
}

/// The scene's per-bead and per-contact values as CSV (module docs).
pub fn to_csv(s: &Scene) -> String {
    let c = &s.chain;
    let n = c.mass.len();
    let mut o =
        String::from("bead,mass,u0,v0,force,exponent,prefactor,precompression,restitution\n");
    for i in 0..n {
        let force = c.field.as_ref().map_or(0.0, |f| f[i]);
        let _ = write!(
            o,
            "{i},{},{},{},{}",
            num(c.mass[i]),
            num(s.u0[i]),
            num(s.v0[i]),
            num(force)
        );
        if i + 1 < n {
            let pre = c.precompression.as_ref().map_or(0.0, |p| p[i]);
            let e = c.hard_restitution(i).map_or(String::new(), num);
            let _ = write!(
                o,
                ",{},{},{},{e}",
                num(c.exponent[i]),
                num(c.prefactor[i]),
                num(pre)
            );
        } else {
            o.push_str(",,,,");
        }
        o.push('\n');
    }
    o
}
