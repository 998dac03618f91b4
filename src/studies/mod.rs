//! Studies: special initial conditions and derived quantities of the chain model that the scene
//! layer builds on (layer 2: imports `model` and `linalg` only).
//!
//! - [`solitary`]: the exact travelling (solitary) wave of the discrete sonic-vacuum chain.

pub mod solitary;
