//! Dormand–Prince 8(5,3) (placeholder until the helper's implementation lands).
use super::{IntegrationError, Integrator, Stats, System, Tolerances};
/// Placeholder.
pub struct Dop853 {
    stats: Stats,
    z: Vec<f64>,
}
impl Dop853 {
    /// Placeholder.
    pub fn new(m: usize, _tol: Tolerances) -> Self {
        Self {
            stats: Stats::default(),
            z: vec![0.0; 2 * m],
        }
    }
}
impl Integrator for Dop853 {
    fn reset(&mut self, _sys: &dyn System, _t: f64, _u: &[f64], _v: &[f64]) {}
    fn step(&mut self, _sys: &dyn System, _t_bound: f64) -> Result<f64, IntegrationError> {
        Err(IntegrationError::Budget(0))
    }
    fn t(&self) -> f64 {
        0.0
    }
    fn t_prev(&self) -> f64 {
        0.0
    }
    fn state(&self) -> &[f64] {
        &self.z
    }
    fn dense(&self, _t: f64, _z: &mut [f64]) {}
    fn dense_at(&self, _t: f64, _j: usize) -> f64 { 0.0 }
    fn stats(&self) -> &Stats {
        &self.stats
    }
}
