//! Readable names of CSV columns for axis and colour-bar labels (issue 36): a sweep's columns are
//! dotted scene keys (`chain.exponent.segments.0.value`, docs/sweeps.md) and result names
//! (`left_fraction`, `gamma`); [`readable`] turns them into `exponent n (segment 0)`, `left
//! fraction E_left/E_total`. A name it does not know is returned as written (a user's own
//! column), so a label is never wrong, at worst raw. `--xlabel`, `--ylabel` and `--zlabel`
//! replace any of them.

/// Scene keys `table.key` and their quantity (the per-bead/per-contact values of docs/scenes.md).
const QUANTITIES: &[(&str, &str)] = &[
    ("chain.beads", "beads N"),
    ("chain.mass", "mass m"),
    ("chain.exponent", "exponent n"),
    ("chain.prefactor", "prefactor a"),
    ("chain.precompression", "precompression Δ"),
    ("chain.radius", "radius R"),
    ("chain.damping", "damping"),
    ("chain.restitution", "restitution e"),
    ("chain.impact_speed", "impact speed"),
    ("initial.displacement", "displacement u(0)"),
    ("initial.velocity", "velocity v(0)"),
    ("initial.striker", "striker velocity v0"),
    ("initial.striker_right", "right striker velocity"),
    ("field.force", "force W"),
    ("field.gravity", "gravity g"),
    ("run.until", "end time"),
    ("run.every", "output interval"),
    ("run.rtol", "rtol"),
    ("run.atol", "atol"),
    ("scene.seed", "seed"),
];

/// Whole names: result columns of `beadchain sweep` (docs/sweeps.md) and keys of inline tables.
const COLUMNS: &[(&str, &str)] = &[
    ("initial.pulse.velocity", "pulse velocity"),
    ("initial.pulse.beads", "pulse length l (beads)"),
    ("left_fraction", "left fraction E_left/E_total"),
    ("v_ratio", "|v_out/v_in|"),
    ("gamma", "decay rate γ"),
    ("gamma_se", "decay rate γ, standard error"),
    ("fragments", "fragments"),
    ("energy_error", "energy error |E_end − E_0|/|E_0|"),
    ("t_end", "end time"),
    ("wall_seconds", "wall time [s]"),
];

/// The readable name of a column (see the module docs); unknown names unchanged.
pub fn readable(key: &str) -> String {
    if let Some((_, name)) = COLUMNS.iter().find(|(k, _)| *k == key) {
        return (*name).to_string();
    }
    let parts: Vec<&str> = key.split('.').collect();
    if parts.len() < 2 {
        return key.to_string();
    }
    let (head, si) = match parts[1].strip_suffix("_si") {
        Some(h) => (format!("{}.{h}", parts[0]), true),
        None => (format!("{}.{}", parts[0], parts[1]), false),
    };
    let Some((_, quantity)) = QUANTITIES.iter().find(|(k, _)| *k == head) else {
        return key.to_string();
    };
    let Some(q) = builder(&parts[2..]) else {
        return key.to_string();
    };
    let mut quals = vec![q];
    if si {
        quals.push("SI".into());
    }
    quals.retain(|q| !q.is_empty());
    if quals.is_empty() {
        (*quantity).to_string()
    } else {
        format!("{quantity} ({})", quals.join(", "))
    }
}

/// The qualifier of a builder path below a scene key (docs/scenes.md, "Builders"): `""` for
/// none, `None` for a path it does not know.
fn builder(rest: &[&str]) -> Option<String> {
    let index = |s: &str| s.parse::<usize>().ok();
    Some(match rest {
        [] => String::new(),
        ["base"] => "base".into(),
        ["start"] => "builder start".into(),
        ["segments", k, "value"] => format!("segment {}", index(k)?),
        ["segments", k, "from"] => format!("segment {} first index", index(k)?),
        ["segments", k, "to"] => format!("segment {} last index", index(k)?),
        ["alternate", k] => format!("alternate {}", index(k)?),
        ["random", "mean"] => "random mean".into(),
        ["random", "eps"] => "random ε".into(),
        ["taper", "q"] => "taper q".into(),
        ["taper", "from"] => "taper start".into(),
        ["impurity", "value"] => "impurity".into(),
        ["impurity", "at"] => "impurity position".into(),
        ["impurity", "s"] => "impurity size s".into(),
        ["gaussian", "sigma"] => "Gaussian noise σ".into(),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::readable;

    #[test]
    fn names() {
        assert_eq!(readable("chain.exponent"), "exponent n");
        assert_eq!(
            readable("chain.exponent.alternate.1"),
            "exponent n (alternate 1)"
        );
        assert_eq!(readable("chain.damping_si"), "damping (SI)");
        assert_eq!(readable("initial.pulse.velocity"), "pulse velocity");
        assert_eq!(
            readable("chain.exponent.segments.x.value"),
            "chain.exponent.segments.x.value"
        );
        assert_eq!(readable("left_fraction"), "left fraction E_left/E_total");
        assert_eq!(readable("n1"), "n1");
    }
}
