//! Scenes: a chain, its initial state and run settings, as read from a TOML file.
//!
//! Entry points: [`load`] (file path or preset name), [`parse_str`], [`validate()`], [`presets()`] /
//! [`preset`]. Value forms and builders live in [`values`], the physical-unit conversion (paper
//! eqs. 3–4, 10–11) in [`units`]. The key reference below is also in
//! docs/scenes.md ("Scene files").
//!
//!
//! A scene is one TOML file (or a preset name: `beadchain scenes` lists them). Every key below is
//! optional unless marked **required**; unknown keys and tables are errors. Errors are one line
//! naming the file and the key path (`scene.toml: [chain].mass: expected 100 values (one per bead),
//! got 99`), the bead/contact index, or the CSV file and line.
//!
//! ```toml
//! [scene]
//! name = "my_chain"        # default: file stem (preset name for presets)
//! description = "..."      # default: ""
//! seed = 0                 # seed of every random builder, 0..=2^63-1 (TOML integer), default 0
//!
//! [chain]
//! beads = 100              # N >= 2; default: length of the first explicit array/CSV
//! mass = 1.0               # per bead (N values), default 1.0
//! exponent = 2.5           # per contact (N-1 values), default 2.5; must be > 1 (warning below 2)
//! prefactor = 1.0          # per contact, a in V = a*delta^n, default 1.0
//! precompression = 0.0     # per contact, Delta; absent (or all zeros) = no precompression code path
//! precompression_force = 0.1  # instead of precompression: every contact's Delta = (F0/(n a))^(1/(n-1)), walls' too
//! precompression_force_si = 5.0  # physical scenes: the same force in newtons
//! radius = 1.0             # per bead, optional dimensionless sphere radii (see "Tapered chains")
//!
//! [initial]
//! displacement = 0.0       # per bead u(0), default 0
//! velocity = 0.0           # per bead v(0), default 0
//! pulse = { beads = 5, velocity = 1.0 }   # beads 0..l-1 get velocity v (rectangular pulse)
//! striker = 1.0            # sets bead 0's velocity to +v
//! striker_right = 1.0      # sets bead N-1's velocity to -v (strikers from both ends)
//! solitary = { at = 50, velocity = 1.0 }  # exact solitary wave centred at bead 50 (docs/studies.md)
//! equilibrium = true       # u(0) = the static equilibrium under walls and field (not with displacement)
//! mode = { index = 3, amplitude = 1e-4 }  # adds linear mode 3 (0 = lowest), largest bead displacement 1e-4
//!
//! [field]                  # constant external force W_i; absent (or all zeros) = no field code path
//! force = 0.0              # per bead W_i; positive = towards increasing u (default 0)
//! gravity = 9.81           # adds W_i = -m_i * g: pulls towards decreasing u, i.e. onto a left wall
//!
//! [walls]                  # rigid walls (default: free ends)
//! left  = { exponent = 2.5, prefactor = 1.0, precompression = 0.0 }  # acts on bead 0
//! right = { exponent = 2.5, prefactor = 1.0, precompression = 0.0 }  # acts on bead N-1
//! force = 0.5              # static force of the left wall (needs both walls and [initial] equilibrium): sets the right wall's precompression
//! force_si = 3.0           # physical scenes: the same force in newtons
//!
//! [run]
//! until = 150.0            # REQUIRED end time (computer units), > 0
//! every = 1.0              # output interval; default: only first and last frame
//! rtol = 1e-8              # relative tolerance in (0, 1); default 1e-8
//! atol = 1e-10             # absolute tolerance in (0, 1), relative to the run's scales; default rtol/1e4 (at least 1e-15)
//! method = "auto"          # "auto" (default) | "radau5" | "dop853" | "verlet"
//! engine = "dense"         # "dense" | "hybrid" (default "hybrid"; `--engine` overrides)
//! ```
//!
//! Initial velocities are applied in the order `velocity`, `pulse`, `striker`, `striker_right` (later
//! ones overwrite); the `solitary` waves (docs/studies.md) are added last. Wall defaults: `exponent` and `prefactor` of the adjacent end contact
//! (physical scenes: the Hertz sphere–flat prefactor, see below), `precompression = 0`
//! (overlap `Δ_L − u_0` on the left, `Δ_R + u_{N−1}` on the right; negative = initial gap).
//!
//! ### Value forms
//!
//! Every per-bead or per-contact key (`mass`, `exponent`, `prefactor`, `precompression`, `radius`,
//! `displacement`, `velocity`, `force`, and the physical `[units]` material keys) takes:
//!
//! | form | meaning |
//! |---|---|
//! | `2.5` | every entry equal |
//! | `[1.0, 2.0, ...]` | exactly N (per bead) or N−1 (per contact) numbers |
//! | `{ file = "x.csv" }` | one number per line, path relative to the scene file; blank lines and `#` lines skipped |
//! | `{ base = ..., ... }` | a builder table (below) |
//!
//! Contact `k` joins beads `k` and `k+1`. Builder keys, applied in this order:
//!
//! | key | meaning | default |
//! |---|---|---|
//! | `base` | number, array or `{ file }` to start from | `random.mean`, else `alternate[0]`, else the key's default |
//! | `start` | first index where `alternate`/`random` apply | 0 |
//! | `alternate = [x, y, ...]` | periodic values from `start` on (§4) | — |
//! | `random = { mean, eps }` | `mean + eps·r`, `r` uniform in `[−1, 1)`, from `start` on (eq. 19) | — |
//! | `taper = { q, from }` | entry `i ≥ from` multiplied by `(1−q)^(i−from)` | `from = 0` |
//! | `segments = [{ from, to, value }]` | set indices `from..=to` (inclusive) | `from = 0`, `to` = last |
//! | `impurity = { at, s, value }` (or an array of them) | set `s` consecutive indices from `at` | `s = 1` |
//! | `gaussian = { sigma, min }` | add `N(0, σ²)` to every entry, redrawn until `> min` (eq. B.1) | `min = 2.0` |
//!
//! Random draws use `ChaCha8Rng::seed_from_u64(seed)` with one stream per key path (FNV-1a hash of
//! e.g. `[chain].exponent`), so results are identical on every platform and independent of other
//! keys; Gaussians use Box–Muller.
//!
//! Examples (the presets use all of them):
//!
//! ```toml
//! exponent = { base = 3.0, segments = [{ from = 50, value = 3.5 }] }        # interface at bead 50
//! exponent = { base = 3.0, impurity = { at = 50, s = 5, value = 2.5 } }     # impurity of s = 5 contacts
//! exponent = { alternate = [2.5, 3.0] }                                    # periodic n_a / n_b
//! exponent = { random = { mean = 2.5, eps = 0.04 }, start = 20 }           # disorder, contacts 0..19 = 2.5
//! exponent = { base = 3.5, segments = [{ from = 50, value = 3.0 }], gaussian = { sigma = 0.025 } }
//! mass = { base = 1.0, segments = [{ from = 51, value = 0.5 }] }           # mass interface
//! radius = { base = 1.0, taper = { q = 0.05, from = 20 } }                 # tapered chain
//! ```
//!
//! ### Tapered chains (dimensionless radii)
//!
//! If `[chain].radius` is given (dimensionless scenes), masses and prefactors follow the spheres:
//! `mass_i ← mass_i · R_i³` and `a_k ← a_k · sqrt(2 R_k R_{k+1} / (R_k + R_{k+1}))` (eq. 3 up to
//! the material constant), so `R = 1` everywhere reproduces `mass` and `prefactor` exactly. With
//! `radius = { base = 1.0, taper = { q, from = k } }`, `R_{i+1} = (1−q) R_i` from bead `k` on.
//!
//! ### Physical units
//!
//! ```toml
//! [units]
//! system = "physical"      # "dimensionless" (default) | "physical" | "computer" (scene show)
//! time_scale = "paper"     # "paper" (default): eq. 10 rescaling | "si": kg, s, m unchanged
//! radius = 4.0e-3          # REQUIRED per bead, m
//! young = 2.26e11          # REQUIRED per bead, Pa
//! poisson = 0.3            # REQUIRED per bead, in (-1, 0.5]
//! density = 7650.0         # REQUIRED per bead, kg/m^3
//! m0 = 2.05e-3             # typical mass (kg), default: mass of bead 0
//! n0 = 2.5                 # typical exponent, default 2.5 (one clock for all exponents)
//! mu = 1e9                 # order of magnitude of a, default: 10^floor(log10 a) of contact 0
//! wall_young = 2.26e11     # wall material for the default wall prefactor, default: the end bead's
//! wall_poisson = 0.3
//! viscosity_shear = 1.5e3  # per bead, Pa·s, with viscosity_bulk and [chain] law = "viscoelastic":
//! viscosity_bulk = 1.5e3   # Brilliantov et al.'s A (see scene::damping); default: none
//! ```
//!
//! Masses `m = ρ·4/3·πR³`, Hertz prefactors `a = 2/(5D)·sqrt(R_i R_{i+1}/(R_i+R_{i+1}))`,
//! `D = 3/4[(1−σ_i²)/Y_i + (1−σ_{i+1}²)/Y_{i+1}]` (eqs. 3–4; a wall is a sphere of infinite
//! radius: `2/(5D)·sqrt(R)`). The prefactor keeps this sphere value for every exponent (as in the
//! paper). `[chain].exponent` (default 2.5) and `precompression` (metres) are allowed;
//! `[chain].mass`, `prefactor` and `radius` are not. Time is rescaled `t = β t̃`,
//! `β = sqrt(m0/(μ n0))` (eq. 10); lengths stay in metres. Eq. 11 is then eq. 7 with computer mass
//! `m/m0`, computer prefactor `a/(μ n0)` (= `ã/n0`), force `W β²/m0`, velocity `v β`, time `t/β`,
//! energy `E β²/m0`. The resolved scene's description records `β`, `m0`, `μ`, `n0`.
//!
//! `system = "computer"` (what `scene show` writes for a physical scene, [`show`]): explicit
//! computer-unit values under the dimensionless rules, with the four scales `m0` (kg),
//! `time_unit` (s), `mu`, `n0` given (all required), so SI output and `--until-si` still work.
//!
//! Plain keys always mean computer units. Physical scenes also accept SI twins, converted with
//! `β`: `[initial] striker_si`, `striker_right_si`, `velocity_si` (m/s), `pulse.velocity_si`,
//! `solitary.velocity_si` (m/s), `solitary.energy_si` (J, `E β²/m0`); `[run] until_si`,
//! `every_si` (s); `[field] force_si` (N), `gravity_si` (m/s²); `[chain]
//! precompression_force_si`, `[walls] force_si` (N, `W β²/m0`);
//! `[walls].left/right.prefactor_si` (SI prefactor). Giving both a key and its twin is an error.
//!
//! **The paper's striker value.** For the Table 1 steel beads (R = 4 mm, Y = 2.26·10¹¹ Pa,
//! σ = 0.3, ρ = 7650 kg/m³): m = 2.0508 g (Table 1: 2.05 g, consistent), D = 6.0398·10⁻¹² Pa⁻¹,
//! a = 2.9618·10⁹, μ = 10⁹, ã = 2.9618, and with n0 = 2.5, β = 9.0572·10⁻⁷ s (computer prefactor
//! 1.18471). The paper writes v⁽⁰⁾ = 1·10⁷ in computer units and "approximately 0.11 m s⁻²". Since
//! velocities scale as ṽ = v·β, 0.11 m/s is 9.96·10⁻⁸ ≈ 1·10⁻⁷ computer units and 1·10⁻⁷ is
//! 0.1104 m/s, while 1·10⁷ would be 1.1·10¹³ m/s. The printed value lost the minus sign of its
//! exponent (and the unit is m s⁻¹): the paper's striker is 1·10⁻⁷ computer units = 0.11 m/s. We
//! therefore take SI velocities through `striker_si = 0.11` (preset `hertz_spheres_physical`); the
//! solitary wave then crosses 100 beads (0.8 m) in about 1.75 ms (≈ 460 m/s).
//!
//! **Units matter for mixed exponents.** With one prefactor for every exponent, the force ratio of
//! two contacts at the same overlap is `δ^(n1−n2)`, which depends on the length unit: the
//! similarity law holds only for a uniform exponent. In the paper's units overlaps are ~10⁻⁶ m, in
//! a dimensionless `v = a = 1` scene ~1. Measured (velocity Verlet, 120 beads, interface at bead
//! 50): the energy fraction reflected at a 3.0 → 2.5 interface is 0.25 % dimensionless but 34 % in
//! the paper's units (the paper reports strong reflection); 3.0 → 3.5 gives 0.15 % in both. So
//! every preset with mixed exponents (interfaces, impurities, periodic, disorder, composite) is a
//! physical scene of Table 1 steel beads with `striker_si = 0.11`; the uniform-exponent presets
//! (`striker`, `tapered`, `rectangular_pulse`, `two_strikers`, `wall_reflection`,
//! `gravity_on_wall`) stay dimensionless, which by the similarity law loses nothing.
//!
//! ### Effects are declared
//!
//! `precompression` and `[field]` map to `None` in the chain when absent **or when every entry is
//! exactly zero**, so the force kernel without them runs; walls exist only when declared.
//!
//! ### Validation
//!
//! Errors: N < 2 (or more than 10⁷ beads), mass ≤ 0, exponent ≤ 1, prefactor ≤ 0 (each naming the
//! bead/contact index), any non-finite number (TOML `nan`/`inf` included), wrong array lengths,
//! `until`/`every` ≤ 0, `rtol`/`atol` outside (0, 1), physical radius/density/Young ≤ 0, Poisson
//! outside (−1, 0.5], builder ranges outside the chain. Warnings: exponent < 2 at some contact
//! ("force not C¹"), every bead at rest with no force, `every > until`.
//!
//! ### Presets (`data/scenes/`)
//!
//! | preset | experiment |
//! |---|---|
//! | `striker` | Uniform chain of 100 beads, n = 2.5, struck at bead 0 with v = 1 (paper eq. 8; the set-up of every figure) |
//! | `interface_3.0_3.5` | Exponent interface n1 = 3.0 -> n2 = 3.5 at bead 50 (contacts 50.. use n2), 150 Table-1 steel beads, striker 0.11 m/s (paper Figs. 4-5, labels fig3 and fig4) |
//! | `interface_3.0_2.5` | Exponent interface n1 = 3.0 -> n2 = 2.5 at bead 50, 150 Table-1 steel beads, striker 0.11 m/s: reflection and a multipulse train (paper Fig. 6, label fig:large_small) |
//! | `solitary_interface_3.0_2.5` | The exact n = 3.0 solitary wave (peak 0.0874 m/s, the energy of a 0.11 m/s striker) launched at bead 20 into the 3.0 -> 2.5 interface at bead 50, 150 Table-1 steel beads: reflection and multipulse train without a striker's transient (paper Fig. 6 set-up) |
//! | `interface_3.5_3.0_perturbed` | Interface n1 = 3.5 -> n2 = 3.0 at bead 50 with Gaussian exponent noise sigma/dn = 0.05, n > 2 enforced, Table-1 steel beads (paper eq. B.1, Fig. 28) |
//! | `periodic_2.5_3.0` | Periodic exponents n_a = 2.5, n_b = 3.0 (contact 0 has n_a), Table-1 steel beads: pairwise collective motion (paper Fig. 10) |
//! | `periodic_decay_2.5_2.555` | Periodic exponents n_a = 2.5, n_b = 2.555, Table-1 steel beads: exponential decay of the leading wave (paper Fig. 11) |
//! | `periodic_breather_2.5_2.635` | Periodic exponents n_a = 2.5, n_b = 2.635 (first decay-rate minimum), Table-1 steel beads: confined wave with periodically changing shape (paper Fig. 13) |
//! | `periodic_breather_4.0_5.0` | Periodic exponents n_a = 4.0, n_b = 5.0 (second decay-rate minimum), Table-1 steel beads: breathing confined wave (paper Fig. 14) |
//! | `impurity_s1_3.0_3.5` | Impurity of s = 1 contact (contact 50, beads 50-51) with n_imp = 3.5 in a n = 3.0 chain of Table-1 steel beads (paper Fig. 16 top) |
//! | `impurity_s1_3.0_2.5` | Impurity of s = 1 contact (contact 50) with n_imp = 2.5 in a n = 3.0 chain of Table-1 steel beads (paper Fig. 16 bottom) |
//! | `impurity_s5_4.0_2.5` | Impurity of s = 5 contacts (contacts 50-54) with n_imp = 2.5 in a n = 4.0 chain of Table-1 steel beads: collective quasi-particle of 6 beads (paper Figs. 17-18) |
//! | `disorder_2.5_0.04` | Disordered exponents n = 2.5 + 0.04 r, r uniform in [-1, 1) (eq. 19), contacts 0-19 monodisperse, N = 1000 Table-1 steel beads, seed 1 (paper Figs. 19-20) |
//! | `composite_mass_exponent` | Composite interface at bead 50: n 3.0 -> 2.5 (contacts 50..) and mass m2/m1 = 1/2 (beads 51.., half density, same prefactor), Table-1 steel (paper Figs. 24-25) |
//! | `tapered` | Tapered chain: radii R_(i+1) = (1 - 0.05) R_i from bead 20 on, masses ~ R^3, Hertz prefactors ~ sqrt(2 R_i R_j / (R_i + R_j)) (paper Sec. 1) |
//! | `rectangular_pulse` | Rectangular initial pulse: beads 0-4 move with v = 1 (l = 5), n = 2.5: splits into a train of l pulses (paper Sec. 3.2) |
//! | `two_strikers` | Strikers from both ends (bead 0 at +1, bead 100 at -1), 101 beads, n = 2.5: head-on solitary-wave collision at bead 50 |
//! | `hertz_spheres_physical` | 100 stainless-steel spheres of Table 1 (R = 4 mm, Y = 226 GPa, sigma = 0.3, rho = 7650 kg/m^3) in physical units, striker 0.11 m/s (paper Sec. 2) |
//! | `wall_reflection` | Solitary wave (n = 2.5, 60 beads) reflected by a rigid right wall with the chain's contact law |
//! | `gravity_on_wall` | Six beads resting on a left wall under gravity g = 1 (static overlaps), top bead pushed down with v = 0.5: persistent contacts |

mod arrays;
mod builder;
mod ctx;
pub(crate) use ctx::{fnv1a, type_name};
mod damping;
pub mod error;
pub(crate) mod hard;
mod initial;
mod keys;
mod load;
mod material;
mod output;
pub mod parse;
pub mod plausible;
pub mod presets;
pub mod selection;
mod settings;
pub mod show;
mod solitary;
mod statics;
mod tables;
pub mod units;
pub mod validate;
pub mod values;
mod walls;

pub use error::SceneError;
pub use load::{load, load_full, load_with_material};
pub use parse::{parse_str, Parsed};
pub use presets::{preset, presets, PresetInfo};
pub use units::UnitScales;
pub use validate::validate;

use crate::integrate::Method;
use crate::model::Chain;
use crate::names::Named;
use serde::{Deserialize, Serialize};

/// Which engine runs a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Engine {
    /// Whole-chain integration, no events (the cross-check path).
    Dense,
    /// Event-driven: analytic free flight, implicit cluster integration (the default).
    #[default]
    Hybrid,
}

impl Named for Engine {
    const WHAT: &'static str = "engine";
    const ALL: &'static [Self] = &[Engine::Hybrid, Engine::Dense];
    fn name(self) -> &'static str {
        match self {
            Engine::Dense => "dense",
            Engine::Hybrid => "hybrid",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Engine::Dense => "Whole-chain integration, no events (the cross-check path)",
            Engine::Hybrid => "Event-driven: free beads fly analytically, clusters are integrated",
        }
    }
}
crate::display_and_from_str!(Engine);

/// Run settings of a scene (`[run]` table). `None` means "use the documented default".
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct RunSettings {
    /// End time (computer units), > 0.
    pub until: f64,
    /// Output interval; `None` writes only the first and last frame.
    pub every: Option<f64>,
    /// Relative tolerance.
    pub rtol: Option<f64>,
    /// Absolute tolerance (relative to the run's characteristic scales).
    pub atol: Option<f64>,
    /// Integration method.
    pub method: Option<Method>,
    /// Engine.
    pub engine: Option<Engine>,
    /// The `[output]` table (output selection of `run`; see `output.rs`). Not serialized: the
    /// snapshot header records the selection a run used.
    #[serde(skip)]
    pub output: Option<selection::Selection>,
}

/// A fully resolved scene: every per-bead and per-contact array expanded.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    /// Short name (file stem or preset name).
    pub name: String,
    /// Free-text description.
    pub description: String,
    /// The chain physics.
    pub chain: Chain,
    /// Initial displacements, length `N`.
    pub u0: Vec<f64>,
    /// Initial velocities, length `N`.
    pub v0: Vec<f64>,
    /// Run settings.
    pub run: RunSettings,
    /// Seed of every random generator the scene used (stored so runs can be reproduced).
    pub seed: u64,
    /// Conversion to SI of a physical scene (`[units] system = "physical"`): the scene is
    /// simulated in the paper's computer units (eqs. 10–11); `None` for a dimensionless scene.
    #[serde(default)]
    pub units: Option<UnitScales>,
}
