//! beadchain: simulator for one-dimensional granular chains with Hertz-like contacts.
//!
//! See README.md (quick start) and docs/ (scene format: docs/scenes.md, CLI: docs/cli.md,
//! layering: docs/architecture.md). The physics follows `paper-hertz-like-interfaces.tex`
//! (eqs. 1–11 and appendix A).
//!
//! The front door is [`prelude`]: a scene, a run, what watches it.
//!
//! ```
//! use beadchain::prelude::*;
//!
//! let scene = scene::preset("striker")?;              // or scene::load("my_scene.toml")
//! let cfg = RunConfig::from_scene(&scene);             // the scene's [run] settings
//! let mut frames = Recorder::default();                // or a SnapshotWriter, a list of observers
//! let out = engine::run(&scene, &cfg, &mut frames)?;  // to [run] until
//! assert!(out.relative_energy_error() < 1e-6);
//! println!("{} frames, last bead at v = {:.4}", frames.t.len(), out.v[scene.chain.len() - 1]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

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
pub mod names;
pub mod plot;
pub mod prelude;
pub mod progress;
pub mod provenance;
pub mod scene;
pub mod snapshot;
pub mod studies;
pub mod suggest;
pub mod sweep;

pub use provenance::BUILD_COMMIT;
