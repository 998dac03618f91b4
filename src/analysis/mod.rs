//! Analysis of chain states and frames, as in the paper (`paper-hertz-like-interfaces.tex`):
//! observables computed from `(chain, u, v)`, frames or event logs. Nothing here starts an
//! engine; observers ([`window::WindowWatch`], [`SteadyStateStop`]) only watch a run that their
//! caller drives. The paper's experiments, which build scenes and run engines, are in
//! [`crate::experiments`].
//!
//! - [`wave`]: pulse detection (beads above 0.1 % of the pulse's peak |v|, Sec. 3.2), wave energy
//!   (eq. 13), leading-wave tracking over frames.
//! - [`interface`]: reflected/transmitted energy split at an interface bead, peak-velocity ratio
//!   `|v_out/v_in|` (Sec. 5.1, Fig. 18).
//! - [`decay`]: the leading wave's decay rate `γ`, one definition for `analyze` and `plot
//!   energy`.
//! - [`fit`]: least-squares exponential decay `E(x) = a e^{−γx}` (Sec. 5.2, eq. 20 ff.) and
//!   ordinary multilinear least squares (the Table 2 fit, eq. 21).
//! - [`window`]: windowed wave energy behind the front, its decay and periods (Sec. 4,
//!   Figs. 10–14; the periodic-chain runs are [`crate::experiments::periodic`]).
//! - [`wavelength`]: the continuum solitary wave (Nesterenko) and a measured profile's widths
//!   and fitted wavelength (Sec. 2, Fig. 2).
//! - [`timings`]: gap openings/closings at an interface from frames or the event log, and the
//!   freeze / two-body exchange times `t1 … t5` (Sec. 3.1, Figs. 4–5).
//! - [`state`]: the steady-state criterion of appendix A (also as a run stop condition) and
//!   fragmentation statistics (open gaps, fragments and their velocities), and the final
//!   fragments of a state where no pair can collide again (`run --stop-when-fragmented`).
//! - [`gas`]: collision rate from the event log, kinetic temperature per frame, velocity
//!   distribution (gases: `granular_gas`).
//! - [`modal`]: the energy of each linear mode in every frame (`modes --snapshot`, FPUT).
//! - [`summary`]: the whole summary of a run's frames (`beadchain analyze`, Python's
//!   `analyze()`): energies, the leading wave's speed and decay fit, the interface split.
//!
//! **Energy convention.** The paper writes the wave energy (eq. 13) as `Σ m v² + Σ a δⁿ`, without
//! the ½ of the kinetic energy. We use the physical energy `Σ ½ m v² + Σ a δⁿ` everywhere (the
//! same as [`crate::model::Chain::energy`], which the engines conserve); all reported quantities
//! are ratios (`E/E₀`, `E_refl/E_in`), so the paper's omission only changes the weight of the
//! potential part of a wave (about 30-40 % of a solitary wave's energy at any instant), not the
//! ratios once pulses are compared at like moments.

pub mod decay;
pub mod fit;
pub mod gas;
pub mod interface;
pub mod modal;
pub mod state;
pub mod summary;
pub mod timings;
pub mod wave;
pub mod wavelength;
pub mod window;

pub use decay::{decay_fit, FitError, FitRange};
pub use fit::{fit_exponential, least_squares, ExpFit, LinearFit};
pub use interface::{
    energy_split, velocity_ratio, EnergySplit, PeakWatch, RatioError, SampledPeak, VelocityRatio,
};
pub use state::{
    final_fragments, fragmentation, is_steady_state, run_until_fragmented, Fragment, Fragmentation,
    Fragmented, SteadyStateStop,
};
pub use summary::{summarize, Summary, SummaryError, SummaryOptions};
pub use wave::{
    detect_pulses, leading_pulse, track_leading, wave_energy, Pulse, TrackPoint, WaveOptions,
};

/// Why an analysis could not be done.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AnalysisError {
    /// Too few data points for the requested fit.
    #[error("need at least {need} data points for the fit, got {got}")]
    TooFewPoints {
        /// Points required.
        need: usize,
        /// Points given.
        got: usize,
    },
    /// A value that must be positive and finite was not (e.g. an energy before taking its log).
    #[error("{what} must be positive and finite, got {value} (point {index})")]
    NotPositive {
        /// Which quantity.
        what: &'static str,
        /// Index of the offending point.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The fit's normal equations are singular (e.g. all x equal).
    #[error("the least-squares problem is singular (degenerate data)")]
    Singular,
    /// Array lengths disagree.
    #[error("length mismatch: {0}")]
    Length(String),
    /// Nothing to analyse (e.g. no pulse found).
    #[error("{0}")]
    NotFound(String),
}
