//! The paper's experiments (`paper-hertz-like-interfaces.tex`): each builds a scene, runs an
//! engine and measures it with the observables of [`crate::analysis`]. Used by
//! `beadchain validate`, `beadchain sweep` (its runs and stop rule) and the paper benches.
//!
//! - [`paper`]: generated Table-1 scenes, the watched run that stops when the leading pulse
//!   reaches a bead, interface/impurity/disorder runs and the `E_refl` collapse (Secs. 3, 5).
//! - [`quick`]: the reduced checks of `beadchain validate --quick`.
//! - [`periodic`]: periodic chains with the windowed tracker (Sec. 4, Figs. 10–14).
//! - [`transfer`]: bead-to-bead energy transfer ratio in disordered chains (Sec. 5.2, Fig. 23).
//! - [`composite`]: composite mass–exponent interfaces (Sec. 6, Fig. 25).
//! - [`wavelength`]: Fig. 2 wave width; [`timings`]: the Fig. 5 gap timings;
//!   [`impurities`]: Figs. 16–17; [`appendix`]: appendices A and B.
//! - [`breather`], [`floquet`]: discrete breathers by shooting on the period map, their
//!   Floquet multipliers (issue 35, part 4).

pub mod appendix;
pub mod breather;
pub mod composite;
pub mod floquet;
pub mod impurities;
pub mod paper;
pub mod periodic;
pub mod quick;
pub mod timings;
pub mod transfer;
pub mod wavelength;
