//! The contact threshold `θ` (module docs of [`super`], "Thresholds"): `ε·L` with
//! `ε = max(atol, rtol^p)`, lowered where a damped contact would dissipate more than `ε` of the
//! energy scale before it closes.

use crate::model::damped::DampingLaw;
use crate::model::{Chain, Scales};

/// The contact threshold `θ` of the module docs: `ε·L`, lowered for damped contacts.
pub fn threshold(chain: &Chain, rtol: f64, atol: f64, scales: &Scales) -> f64 {
    let eps = contact_threshold(chain, rtol, atol);
    let theta = eps * scales.length;
    let Some(d) = &chain.damping else {
        return theta;
    };
    let budget = eps * scales.energy / scales.velocity;
    if !(budget > 0.0 && budget.is_finite()) {
        return theta;
    }
    let bound = |coef: f64, n: f64, a: f64| {
        let b = match d.law {
            DampingLaw::Viscoelastic => (budget / (coef * n * a)).powf(1.0 / (n - 1.0)),
            DampingLaw::LinearDashpot => budget / coef,
        };
        if coef > 0.0 && b.is_finite() && b >= 0.0 {
            b
        } else {
            f64::INFINITY
        }
    };
    let contacts = (d.contact.iter().enumerate())
        .filter(|&(c, _)| chain.hard_restitution(c).is_none())
        .map(|(c, &coef)| bound(coef, chain.exponent[c], chain.prefactor[c]));
    let walls = [
        (&chain.left_wall, d.left_wall),
        (&chain.right_wall, d.right_wall),
    ]
    .into_iter()
    .filter_map(|(w, coef)| {
        w.as_ref()
            .filter(|w| w.restitution.is_none())
            .map(|w| (w, coef))
    })
    .map(|(w, coef)| bound(coef, w.exponent, w.prefactor));
    contacts.chain(walls).fold(theta, f64::min)
}

/// The relative contact threshold `ε = θ/L = max(atol, rtol^p)` of the module docs.
pub fn contact_threshold(chain: &Chain, rtol: f64, atol: f64) -> f64 {
    let n_min = chain
        .exponent
        .iter()
        .enumerate()
        .filter(|&(c, _)| chain.hard_restitution(c).is_none())
        .fold(f64::INFINITY, |m, (_, &n)| m.min(n));
    let p = if n_min.is_finite() {
        (1.0 / (n_min - 1.0)).max(1.0)
    } else {
        1.0
    };
    atol.max(rtol.powf(p))
}
