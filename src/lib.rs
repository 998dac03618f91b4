//! beadchain: simulator for one-dimensional granular chains with Hertz-like contacts.
//!
//! See README.md (quick start) and docs/ (scene format: docs/scenes.md, CLI: docs/cli.md). The
//! physics follows `paper-hertz-like-interfaces.tex` (eqs. 1–11 and appendix A).

// Numerical kernels index several arrays in lock-step; index loops read closer to the formulas.
#![allow(clippy::needless_range_loop)]
// The AVX2 builds of hot kernels are `unsafe fn`s: every unsafe operation inside them still needs
// its own `unsafe` block and SAFETY comment.
#![deny(unsafe_op_in_unsafe_fn)]

pub mod accuracy;
pub mod analysis;
pub mod check;
pub mod engine;
pub mod experiments;
pub mod export;
pub mod files;
pub mod integrate;
pub mod linalg;
pub mod model;
pub mod plot;
pub mod progress;
pub mod scene;
pub mod snapshot;
pub mod studies;
pub mod suggest;
pub mod sweep;
