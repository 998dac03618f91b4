//! Static equilibrium of a chain under its walls and field (issue 35, part 2).
//!
//! At rest, eq. 7 is the force balance `0 = W_i + F_{i−1} − F_i` of every bead, with `F_{−1}`
//! the left wall's force `F_L`, `F_{N−1}` the right wall's `F_R` and `F_c = n a δ_c^{n−1}` the
//! contact forces. It gives every force from one unknown, `F_L`:
//!
//! ```text
//! F_c = F_L + P_c,   P_c = Σ_{i ≤ c} W_i,   F_R = F_L + P_{N−1},
//! ```
//!
//! and each loaded element (a contact or a soft wall) has the overlap `δ = (F/(n a))^{1/(n−1)}`
//! (hard ones: `δ = 0`). The overlaps are tied to the displacements by eq. 6
//! (`δ_L = Δ_L − u_0`, `δ_c = Δ_c + u_c − u_{c+1}`, `δ_R = Δ_R + u_{N−1}`), which sum to the
//! compatibility condition `h(F_L) = δ_L + Σ δ_c + δ_R = Δ_L + Σ Δ_c + Δ_R`:
//!
//! - one wall, or none: the free end carries no force, which fixes `F_L` (`F_L = −P_{N−1}`
//!   with a left wall, `F_L = 0` otherwise); no wall needs `Σ W_i = 0`.
//! - two walls: `h` increases monotonically with `F_L`, and the scalar equation is solved by
//!   Newton's method (`h' = Σ δ/((n−1) F)`), safeguarded by bisection, from the touching state
//!   (the smallest `F_L` at which no force is negative). With `[walls] force = F0` the left wall's
//!   force is imposed and the right wall's `Δ_R` follows from the condition instead.
//!
//! A negative force is an impossible balance (a field pulling beads off a free end, or the
//! chain off its only wall): an error naming the contact or wall. An element whose force is zero
//! is touching (`δ = 0`) or, where the walls leave slack, open: the beads it separates are
//! reported as gaps. The displacements then follow by summing the overlaps from the wall (from
//! bead 0's given displacement without walls).

use super::StudyError;
use crate::model::{Chain, Wall};

/// A load-bearing element: the left wall, a contact, or the right wall.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Law {
    n: f64,
    a: f64,
    hard: bool,
}

impl Law {
    fn of_wall(w: &Wall) -> Self {
        Self {
            n: w.exponent,
            a: w.prefactor,
            hard: w.restitution.is_some(),
        }
    }

    /// Overlap `δ` at force `f ≥ 0` (0 for a hard element or no force).
    fn overlap(&self, f: f64) -> f64 {
        if self.hard || f <= 0.0 {
            0.0
        } else {
            (f / (self.n * self.a)).powf(1.0 / (self.n - 1.0))
        }
    }

    /// `dδ/dF` at force `f > 0`.
    fn compliance(&self, f: f64) -> f64 {
        if self.hard || f <= 0.0 {
            0.0
        } else {
            self.overlap(f) / ((self.n - 1.0) * f)
        }
    }
}

/// The precompression `Δ = (F/(n a))^{1/(n−1)}` at which a contact of law `(n, a)` carries `F`.
pub fn overlap_for_force(n: f64, a: f64, force: f64) -> f64 {
    Law { n, a, hard: false }.overlap(force)
}

/// The chain at rest.
#[derive(Clone, Debug, PartialEq)]
pub struct Equilibrium {
    /// Displacements `u` (N).
    pub u: Vec<f64>,
    /// Contact forces `F_c ≥ 0` (N−1).
    pub contact_force: Vec<f64>,
    /// Forces of the left and right walls (`None` without a wall).
    pub wall_force: [Option<f64>; 2],
    /// Contacts that carry no force (their beads touch or are apart).
    pub gaps: Vec<usize>,
    /// Newton iterations (0 when the balance is statically determinate).
    pub iterations: usize,
    /// The right wall's precompression `Δ_R` that the imposed force requires (`Some` with an
    /// imposed force only).
    pub right_precompression: Option<f64>,
}

/// The elements in order (left wall, contacts, right wall) with their force offsets `P`
/// (element force = `F_L + P`).
struct Elements {
    law: Vec<Law>,
    offset: Vec<f64>,
    /// Index of contact 0 in `law` (1 with a left wall).
    first: usize,
    /// `Δ_L + Σ Δ_c + Δ_R`, excluding the right wall's when `Δ_R` is unknown.
    total: f64,
    /// Scale of the forces (for the zero tolerance).
    scale: f64,
    /// Net field force `Σ W_i`.
    net: f64,
}

fn elements(chain: &Chain) -> Elements {
    let nb = chain.len();
    let w = chain.field.clone().unwrap_or_else(|| vec![0.0; nb]);
    let mut law = Vec::with_capacity(nb + 1);
    let mut offset = Vec::with_capacity(nb + 1);
    let mut total = 0.0;
    if let Some(wl) = &chain.left_wall {
        law.push(Law::of_wall(wl));
        offset.push(0.0);
        total += wl.precompression;
    }
    let first = law.len();
    let mut p = 0.0;
    for c in 0..nb - 1 {
        p += w[c];
        law.push(Law {
            n: chain.exponent[c],
            a: chain.prefactor[c],
            hard: chain.hard_restitution(c).is_some(),
        });
        offset.push(p);
        total += chain.precompression.as_ref().map_or(0.0, |d| d[c]);
    }
    p += w[nb - 1];
    if let Some(wr) = &chain.right_wall {
        law.push(Law::of_wall(wr));
        offset.push(p);
        total += wr.precompression;
    }
    let scale = w.iter().map(|x| x.abs()).sum::<f64>();
    Elements {
        law,
        offset,
        first,
        total,
        scale,
        net: p,
    }
}

/// The name of element `e` in messages.
fn element_name(el: &Elements, e: usize, nb: usize) -> String {
    if e < el.first {
        "the left wall".to_string()
    } else if e - el.first < nb - 1 {
        let c = e - el.first;
        format!("contact {c} (beads {c}-{})", c + 1)
    } else {
        "the right wall".to_string()
    }
}

/// The state at rest of `chain`; `u_ref` gives bead 0's displacement when no wall fixes it.
/// `imposed`: the left wall's force `F0` (`[walls] force`), which needs both walls and sets the
/// right wall's precompression ([`Equilibrium::right_precompression`]).
pub fn equilibrium(
    chain: &Chain,
    u_ref: &[f64],
    imposed: Option<f64>,
) -> Result<Equilibrium, StudyError> {
    let nb = chain.len();
    let (left, right) = (chain.left_wall.is_some(), chain.right_wall.is_some());
    let mut el = elements(chain);
    let net = el.net;
    let tol = 64.0 * f64::EPSILON * (el.scale + imposed.unwrap_or(0.0).abs());
    let (f_left, iterations) = match (left, right, imposed) {
        (true, true, Some(f0)) => (f0, 0),
        (_, _, Some(_)) => {
            return Err(StudyError::new(
                "an imposed wall force needs both walls ([walls] left and right)",
            ))
        }
        (true, true, None) => solve_two_walls(&el, tol)?,
        (true, false, None) => (-net, 0),
        (false, true, None) => (0.0, 0),
        (false, false, None) => {
            if net.abs() > tol {
                return Err(StudyError::new(format!(
                    "no wall holds the chain: the field's net force {net:.6e} accelerates it (no static equilibrium)"
                )));
            }
            (0.0, 0)
        }
    };
    // Element forces, checked.
    let mut force: Vec<f64> = el.offset.iter().map(|p| f_left + p).collect();
    for (e, f) in force.iter_mut().enumerate() {
        if *f < -tol {
            return Err(StudyError::new(impossible(&el, e, *f, nb, left, right)));
        }
        if *f <= tol {
            *f = 0.0;
        }
    }
    let delta: Vec<f64> = el
        .law
        .iter()
        .zip(&force)
        .map(|(l, f)| l.overlap(*f))
        .collect();
    let mut right_precompression = None;
    if imposed.is_some() {
        let wr = chain.right_wall.as_ref().expect("checked: two walls");
        let total_delta: f64 = delta.iter().sum();
        let others = el.total - wr.precompression;
        right_precompression = Some(total_delta - others);
        el.total = total_delta;
    }
    let u = displacements(chain, &el, &delta, u_ref, right_precompression);
    check_held(chain, &el, (&u, &delta), right_precompression)?;
    let contact_force = force[el.first..el.first + nb - 1].to_vec();
    let gaps = (0..nb - 1).filter(|&c| contact_force[c] == 0.0).collect();
    Ok(Equilibrium {
        u,
        contact_force,
        wall_force: [
            left.then(|| force[0]),
            right.then(|| force[force.len() - 1]),
        ],
        gaps,
        iterations,
        right_precompression,
    })
}

/// The displacements `u` hold the balance's overlaps `delta`: each loaded element's overlap as
/// `u` gives it back (`Δ_c + u_c − u_{c+1}`, `Δ_L − u_0`, `u_{N−1} + Δ_R`) within `1e-3` of its
/// own. Where an exponent near 1 needs overlaps `(F/(n a))^{1/(n−1)}` below the rounding of the
/// displacements they are summed into (n = 1.01: `1e-98` against `u ≈ 0.4`), they are lost and
/// the forces come out wrong by order one, so the state at rest is refused rather than returned
/// unbalanced. (A force criterion refused balanced states: the rounding of long sums times a
/// stiff wall's stiffness is a force error without consequence, `tests/equilibrium.rs`.)
fn check_held(
    chain: &Chain,
    el: &Elements,
    (u, delta): (&[f64], &[f64]),
    right_pre: Option<f64>,
) -> Result<(), StudyError> {
    let nb = u.len();
    let pre = |c: usize| chain.precompression.as_ref().map_or(0.0, |d| d[c]);
    let held = |e: usize| -> f64 {
        if e < el.first {
            chain.left_wall.as_ref().map_or(0.0, |w| w.precompression) - u[0]
        } else if e - el.first < nb - 1 {
            let c = e - el.first;
            pre(c) + u[c] - u[c + 1]
        } else {
            let dr = right_pre.or(chain.right_wall.as_ref().map(|w| w.precompression));
            u[nb - 1] + dr.unwrap_or(0.0)
        }
    };
    for (e, (&d, law)) in delta.iter().zip(&el.law).enumerate() {
        if d <= 0.0 || law.hard {
            continue;
        }
        let back = held(e);
        if (back - d).abs() > 1e-3 * d {
            return Err(StudyError::new(format!(
                "the state at rest cannot be held by the displacements: {} needs the overlap {d:.3e}, below the rounding of the displacements (up to {:.3e}; it comes back as {back:.3e}); an exponent near 1 needs overlaps (F/(n a))^(1/(n-1)) too small to represent",
                element_name(el, e, nb),
                u.iter().fold(0.0f64, |m, x| m.max(x.abs()))
            )));
        }
    }
    Ok(())
}

/// The message of a negative force at element `e`.
fn impossible(el: &Elements, e: usize, f: f64, nb: usize, left: bool, right: bool) -> String {
    let name = element_name(el, e, nb);
    let why = if e < el.first || (e == el.law.len() - 1 && right) {
        "the field pulls the chain off this wall"
    } else if left && !right {
        "the field pulls the beads beyond it off the free right end"
    } else {
        "the field pulls the beads before it off the free left end"
    };
    format!("impossible static balance: {name} would carry the tensile force {f:.6e} ({why}); contacts only push")
}

/// Two walls: the left wall's force `F_L` with `h(F_L) = Δ_total` (module docs).
fn solve_two_walls(el: &Elements, tol: f64) -> Result<(f64, usize), StudyError> {
    let h = |f: f64| -> (f64, f64) {
        el.law
            .iter()
            .zip(&el.offset)
            .fold((0.0, 0.0), |(s, ds), (l, p)| {
                let fe = f + p;
                (s + l.overlap(fe), ds + l.compliance(fe))
            })
    };
    // The touching state: the smallest F_L at which no element pulls.
    let f_min = el.offset.iter().fold(0.0f64, |m, p| m.max(-p));
    let target = el.total;
    if h(f_min).0 >= target {
        return Ok((f_min, 0));
    }
    if el.law.iter().all(|l| l.hard) {
        return Err(StudyError::new(format!(
            "no static balance: every contact and wall is hard, and the precompressions overlap by {target:.6e}"
        )));
    }
    // Bracket [lo, hi] with h(lo) < target ≤ h(hi).
    let (mut lo, mut hi) = (f_min, f_min + el.scale.max(tol).max(1e-300));
    while h(hi).0 < target {
        lo = hi;
        hi = f_min + 2.0 * (hi - f_min);
        if !hi.is_finite() {
            return Err(StudyError::new(
                "no static balance: the wall force diverges",
            ));
        }
    }
    let mut f = hi;
    for it in 1..=300 {
        let (v, dv) = h(f);
        if v < target {
            lo = f;
        } else {
            hi = f;
        }
        let mut next = if dv > 0.0 {
            f - (v - target) / dv
        } else {
            f64::NAN
        };
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - f).abs() <= 4.0 * f64::EPSILON * f.abs() || hi - lo <= 4.0 * f64::EPSILON * hi {
            return Ok((next, it));
        }
        f = next;
    }
    Err(StudyError::new(
        "Newton's method did not converge in 300 iterations",
    ))
}

/// Displacements from the overlaps `delta` of the elements (module docs): summed from the left
/// wall, or back from the right wall, or from `u_ref[0]` without walls. With two walls the
/// slack `Δ_total − Σ δ` (≤ 0, where the walls leave room) opens the last unloaded element.
fn displacements(
    chain: &Chain,
    el: &Elements,
    delta: &[f64],
    u_ref: &[f64],
    right_pre: Option<f64>,
) -> Vec<f64> {
    let nb = chain.len();
    let pre = |c: usize| chain.precompression.as_ref().map_or(0.0, |d| d[c]);
    let mut d = delta.to_vec();
    if chain.left_wall.is_some() && chain.right_wall.is_some() {
        let slack = el.total - d.iter().sum::<f64>();
        if slack < 0.0 && right_pre.is_none() {
            // Open the last element without force (the walls are apart).
            let e = (0..d.len())
                .rev()
                .find(|&e| d[e] == 0.0)
                .unwrap_or(d.len() - 1);
            d[e] += slack;
        }
    }
    let mut u = vec![0.0; nb];
    if let Some(wl) = &chain.left_wall {
        u[0] = wl.precompression - d[0];
    } else if let Some(wr) = &chain.right_wall {
        let dr = right_pre.unwrap_or(wr.precompression);
        u[nb - 1] = d[d.len() - 1] - dr;
        for c in (0..nb - 1).rev() {
            u[c] = u[c + 1] - pre(c) + d[el.first + c];
        }
        return u;
    } else {
        u[0] = u_ref.first().copied().unwrap_or(0.0);
    }
    for c in 0..nb - 1 {
        u[c + 1] = u[c] + pre(c) - d[el.first + c];
    }
    u
}
