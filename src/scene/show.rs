//! The resolved scene as plain text (`beadchain scene show`): every per-bead and per-contact
//! value after the builders (`alternate`, `random`, `taper`, ...) and the unit conversion
//! (paper eqs. 10–11), in computer units.
//!
//! - [`to_toml`]: a complete dimensionless scene file with explicit arrays. Parsing it gives the
//!   same chain, initial state and run settings bit for bit (floats are written in Rust's
//!   shortest round-trip form), so a physical or randomly built scene can be frozen, shared or
//!   edited as plain numbers. The unit scales of a physical scene stay in its description.
//! - [`to_csv`]: one row per bead (`bead,mass,u0,v0,force`) with the values of the contact to its
//!   right (`exponent,prefactor,precompression,restitution`; empty on the last bead, and
//!   `restitution` empty for a soft contact), readable by `pandas.read_csv` without options.

use super::Scene;
use crate::model::Wall;
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

fn wall(w: &Wall) -> String {
    let mut parts = Vec::new();
    match w.restitution {
        Some(e) => {
            parts.push("hard = true".to_string());
            parts.push(format!("restitution = {}", num(e)));
        }
        None => {
            parts.push(format!("exponent = {}", num(w.exponent)));
            parts.push(format!("prefactor = {}", num(w.prefactor)));
        }
    }
    if w.precompression != 0.0 || w.restitution.is_none() {
        parts.push(format!("precompression = {}", num(w.precompression)));
    }
    format!("{{ {} }}", parts.join(", "))
}

/// The scene as a dimensionless TOML scene file with explicit arrays (module docs).
pub fn to_toml(s: &Scene) -> String {
    let c = &s.chain;
    let mut o = String::new();
    let _ = writeln!(
        o,
        "# resolved scene `{}`: computer units, every value explicit",
        s.name
    );
    let _ = writeln!(o, "[scene]\nname = {}", quoted(&s.name));
    let _ = writeln!(o, "description = {}", quoted(&s.description));
    let _ = writeln!(o, "seed = {}\n", s.seed);
    let _ = writeln!(o, "[chain]\nbeads = {}", c.mass.len());
    let _ = writeln!(o, "mass = {}", array(&c.mass));
    let _ = writeln!(o, "exponent = {}", array(&c.exponent));
    let _ = writeln!(o, "prefactor = {}", array(&c.prefactor));
    if let Some(p) = &c.precompression {
        let _ = writeln!(o, "precompression = {}", array(p));
    }
    let _ = writeln!(o, "\n[initial]\ndisplacement = {}", array(&s.u0));
    let _ = writeln!(o, "velocity = {}", array(&s.v0));
    if let Some(f) = &c.field {
        let _ = writeln!(o, "\n[field]\nforce = {}", array(f));
    }
    if c.left_wall.is_some() || c.right_wall.is_some() {
        let _ = writeln!(o, "\n[walls]");
        for (side, w) in [("left", &c.left_wall), ("right", &c.right_wall)] {
            if let Some(w) = w {
                let _ = writeln!(o, "{side} = {}", wall(w));
            }
        }
    }
    if let Some(h) = &c.hard {
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
    o
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
