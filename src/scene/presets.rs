//! Presets: one scene per paper experiment, embedded from `data/scenes/*.toml` with
//! `include_str!` so they work from any directory. `beadchain scenes` lists them.

use super::error::SceneError;
use super::parse::{parse_full, Parsed};
use super::plausible::BeadMaterial;
use super::Scene;
use std::path::Path;

/// One embedded preset scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PresetInfo {
    /// Preset name (the file stem in `data/scenes/`, also `[scene].name`).
    pub name: &'static str,
    /// One-line description (the file's `[scene].description`), naming the paper figure.
    pub description: &'static str,
    /// The TOML text.
    pub toml: &'static str,
}

static PRESETS: &[PresetInfo] = &[
    PresetInfo {
        name: "striker",
        description: "Uniform chain of 100 beads, n = 2.5, struck at bead 0 with v = 1 (paper eq. 8; the set-up of every figure)",
        toml: include_str!("../../data/scenes/striker.toml"),
    },
    PresetInfo {
        name: "interface_3.0_3.5",
        description: "Exponent interface n1 = 3.0 -> n2 = 3.5 at bead 50 (contacts 50.. use n2), 150 Table-1 steel beads, striker 0.11 m/s (paper Figs. 4-5, labels fig3 and fig4)",
        toml: include_str!("../../data/scenes/interface_3.0_3.5.toml"),
    },
    PresetInfo {
        name: "interface_3.0_2.5",
        description: "Exponent interface n1 = 3.0 -> n2 = 2.5 at bead 50, 150 Table-1 steel beads, striker 0.11 m/s: reflection and a multipulse train (paper Fig. 6, label fig:large_small)",
        toml: include_str!("../../data/scenes/interface_3.0_2.5.toml"),
    },
    PresetInfo {
        name: "solitary_interface_3.0_2.5",
        description: "The exact n = 3.0 solitary wave (peak 0.0874 m/s, the energy of a 0.11 m/s striker) launched at bead 20 into the 3.0 -> 2.5 interface at bead 50, 150 Table-1 steel beads: reflection and multipulse train without a striker's transient (paper Fig. 6 set-up)",
        toml: include_str!("../../data/scenes/solitary_interface_3.0_2.5.toml"),
    },
    PresetInfo {
        name: "interface_3.5_3.0_perturbed",
        description: "Interface n1 = 3.5 -> n2 = 3.0 at bead 50 with Gaussian exponent noise sigma/dn = 0.05, n > 2 enforced, Table-1 steel beads (paper eq. B.1, Fig. 28)",
        toml: include_str!("../../data/scenes/interface_3.5_3.0_perturbed.toml"),
    },
    PresetInfo {
        name: "periodic_2.5_3.0",
        description: "Periodic exponents n_a = 2.5, n_b = 3.0 (contact 0 has n_a), Table-1 steel beads: pairwise collective motion (paper Fig. 10)",
        toml: include_str!("../../data/scenes/periodic_2.5_3.0.toml"),
    },
    PresetInfo {
        name: "periodic_decay_2.5_2.555",
        description: "Periodic exponents n_a = 2.5, n_b = 2.555, Table-1 steel beads: exponential decay of the leading wave (paper Fig. 11)",
        toml: include_str!("../../data/scenes/periodic_decay_2.5_2.555.toml"),
    },
    PresetInfo {
        name: "periodic_breather_2.5_2.635",
        description: "Periodic exponents n_a = 2.5, n_b = 2.635 (first decay-rate minimum), Table-1 steel beads: confined wave with periodically changing shape (paper Fig. 13)",
        toml: include_str!("../../data/scenes/periodic_breather_2.5_2.635.toml"),
    },
    PresetInfo {
        name: "periodic_breather_4.0_5.0",
        description: "Periodic exponents n_a = 4.0, n_b = 5.0 (second decay-rate minimum), Table-1 steel beads: breathing confined wave (paper Fig. 14)",
        toml: include_str!("../../data/scenes/periodic_breather_4.0_5.0.toml"),
    },
    PresetInfo {
        name: "impurity_s1_3.0_3.5",
        description: "Impurity of s = 1 contact (contact 50, beads 50-51) with n_imp = 3.5 in a n = 3.0 chain of Table-1 steel beads (paper Fig. 16 top)",
        toml: include_str!("../../data/scenes/impurity_s1_3.0_3.5.toml"),
    },
    PresetInfo {
        name: "impurity_s1_3.0_2.5",
        description: "Impurity of s = 1 contact (contact 50) with n_imp = 2.5 in a n = 3.0 chain of Table-1 steel beads (paper Fig. 16 bottom)",
        toml: include_str!("../../data/scenes/impurity_s1_3.0_2.5.toml"),
    },
    PresetInfo {
        name: "impurity_s5_4.0_2.5",
        description: "Impurity of s = 5 contacts (contacts 50-54) with n_imp = 2.5 in a n = 4.0 chain of Table-1 steel beads: collective quasi-particle of 6 beads (paper Figs. 17-18)",
        toml: include_str!("../../data/scenes/impurity_s5_4.0_2.5.toml"),
    },
    PresetInfo {
        name: "disorder_2.5_0.04",
        description: "Disordered exponents n = 2.5 + 0.04 r, r uniform in [-1, 1) (eq. 19), contacts 0-19 monodisperse, N = 1000 Table-1 steel beads, seed 1 (paper Figs. 19-20)",
        toml: include_str!("../../data/scenes/disorder_2.5_0.04.toml"),
    },
    PresetInfo {
        name: "composite_mass_exponent",
        description: "Composite interface at bead 50: n 3.0 -> 2.5 (contacts 50..) and mass m2/m1 = 1/2 (beads 51.., half density, same prefactor), Table-1 steel (paper Figs. 24-25)",
        toml: include_str!("../../data/scenes/composite_mass_exponent.toml"),
    },
    PresetInfo {
        name: "tapered",
        description: "Tapered chain: radii R_(i+1) = (1 - 0.05) R_i from bead 20 on, masses ~ R^3, Hertz prefactors ~ sqrt(2 R_i R_j / (R_i + R_j)) (paper Sec. 1)",
        toml: include_str!("../../data/scenes/tapered.toml"),
    },
    PresetInfo {
        name: "rectangular_pulse",
        description: "Rectangular initial pulse: beads 0-4 move with v = 1 (l = 5), n = 2.5: splits into a train of l pulses (paper Sec. 3.2)",
        toml: include_str!("../../data/scenes/rectangular_pulse.toml"),
    },
    PresetInfo {
        name: "two_strikers",
        description: "Strikers from both ends (bead 0 at +1, bead 100 at -1), 101 beads, n = 2.5: head-on solitary-wave collision at bead 50",
        toml: include_str!("../../data/scenes/two_strikers.toml"),
    },
    PresetInfo {
        name: "hertz_spheres_physical",
        description: "100 stainless-steel spheres of Table 1 (R = 4 mm, Y = 226 GPa, sigma = 0.3, rho = 7650 kg/m^3) in physical units, striker 0.11 m/s (paper Sec. 2)",
        toml: include_str!("../../data/scenes/hertz_spheres_physical.toml"),
    },
    PresetInfo {
        name: "wall_reflection",
        description: "Solitary wave (n = 2.5, 60 beads) reflected by a rigid right wall with the chain's contact law",
        toml: include_str!("../../data/scenes/wall_reflection.toml"),
    },
    PresetInfo {
        name: "gravity_on_wall",
        description: "Six beads resting on a left wall under gravity g = 1 (static overlaps), top bead pushed down with v = 0.5: persistent contacts",
        toml: include_str!("../../data/scenes/gravity_on_wall.toml"),
    },
    PresetInfo {
        name: "newtons_cradle_hard",
        description: "Newton's cradle with hard elastic contacts: bead 0 hits five touching beads at rest; the last bead leaves with the striker's velocity (hybrid engine only)",
        toml: include_str!("../../data/scenes/newtons_cradle_hard.toml"),
    },
    PresetInfo {
        name: "damped_striker",
        description: "Striker chain of 100 Hertz beads with viscoelastic contacts (pair restitution 0.9 at impact speed 1): a decaying pulse, energy balance with the dissipated energy",
        toml: include_str!("../../data/scenes/damped_striker.toml"),
    },
    PresetInfo {
        name: "damped_column",
        description: "Ten beads falling under gravity g = 1 onto a wall with viscoelastic contacts (pair restitution 0.6 at impact speed 1): they come to rest as a column",
        toml: include_str!("../../data/scenes/damped_column.toml"),
    },
    PresetInfo {
        name: "gapped_chain",
        description: "Striker v = 1 into 1000 uniform beads (n = 2.5, a = m = 1) separated by gaps of 1 (precompression -1): every collision is an isolated two-body collision (velocity exchange), the pulse crosses the chain bead by bead",
        toml: include_str!("../../data/scenes/gapped_chain.toml"),
    },
    PresetInfo {
        name: "granular_gas",
        description: "1-D soft granular gas: 1000 beads, random masses 1 +- 0.9 and velocities 0 +- 1 (uniform, seed 7), gaps of 1 (precompression -1), soft walls with the chain's law (n = 2.5): collision rate, kinetic temperature, velocity distribution",
        toml: include_str!("../../data/scenes/granular_gas.toml"),
    },
    PresetInfo {
        name: "dimer_dispersion",
        description: "Precompressed dimer chain: 40 beads of masses 1 and 0.5 alternating (n = 2.5, a = 1) between soft walls, every contact at force 0.1: acoustic and optical bands with a gap (beadchain plot dispersion); starts in its lowest optical mode, amplitude 1e-4",
        toml: include_str!("../../data/scenes/dimer_dispersion.toml"),
    },
    PresetInfo {
        name: "dimer_gap_breather",
        description: "The discrete gap breather of a precompressed dimer chain: 16 beads of masses 1 and 0.5 (n = 2.5, a = 1) between soft walls, every contact at force 0.1, omega = 2.25 in the gap below the optical band (beadchain breather, stored as [initial] displacements): it returns to itself every period T = 2.7925",
        toml: include_str!("../../data/scenes/dimer_gap_breather.toml"),
    },
    PresetInfo {
        name: "gravity_column_at_rest",
        description: "20 beads of random masses 1 +- 0.5 (seed 3) resting on a left wall under gravity g = 1, [initial] equilibrium = true: contact k carries g times the mass above it, and the column stays at rest",
        toml: include_str!("../../data/scenes/gravity_column_at_rest.toml"),
    },
];

/// Every preset, the default (`striker`) first.
pub fn presets() -> &'static [PresetInfo] {
    PRESETS
}

/// Name of the default preset.
pub const DEFAULT_PRESET: &str = "striker";

/// Load a preset by name. Presets contain no `{ file = ... }` references; messages name the
/// preset as `preset:NAME`.
pub fn preset(name: &str) -> Result<Scene, SceneError> {
    preset_with_material(name).map(|(s, _)| s)
}

/// [`preset`] with the SI bead material of a physical preset
/// ([`super::parse::parse_with_material`]).
pub fn preset_with_material(name: &str) -> Result<(Scene, Option<BeadMaterial>), SceneError> {
    preset_full(name).map(|p| (p.scene, p.material))
}

/// [`preset`] with the bead material and the warnings of its construction ([`Parsed`]).
pub fn preset_full(name: &str) -> Result<Parsed, SceneError> {
    match PRESETS.iter().find(|p| p.name == name) {
        Some(p) => {
            parse_full(p.toml, Path::new("."), &format!("preset:{}", p.name)).map(|mut parsed| {
                parsed.scene.name = p.name.to_string();
                parsed
            })
        }
        None => Err(SceneError::NotFound {
            spec: super::error::one_line(name),
            presets: PRESETS
                .iter()
                .map(|p| p.name)
                .collect::<Vec<_>>()
                .join(", "),
        }),
    }
}
