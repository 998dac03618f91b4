//! Gap openings/closings at an interface and the freeze / two-body exchange times `t1 … t5` of
//! the paper's Sec. 3.1 (Figs. 4–5, interface `n1 = 3.0 → n2 = 3.5` at bead `k = 50`).
//!
//! The paper's text defines the times; with contact `c` between beads `c` and `c+1` (contact
//! `k−1` = beads 49|50 is the last `n1` contact), we read them as:
//! - `t1`: "the initial wave hits the interface … a gap between bead 49 and bead 50 opens": the
//!   first opening of contact `k−1`;
//! - `t2`: start of the first frozen state, "bead 49 freely travelling forward while bead 50 is
//!   travelling backwards": the first time after `t1` when contacts `k−2`, `k−1` and `k` are all
//!   open (beads 49 and 50 both free);
//! - `t3`: "beads 49 and 50 exchange momenta in an elastic two-body collision": the next closing
//!   of contact `k−1` (its reopening, the end of the collision, is `t3_end`);
//! - `t4`: "bead 50 closes the gap to its right neighbour": first closing of contact `k` after `t3`;
//! - `t5`: "bead 49 reaches its left neighbour": first closing of contact `k−2` after `t3`.
//!
//! Openings/closings come from two independent sources: (a) the overlaps `δ_c(t)` sampled every
//! frame (frames `τ/50` apart, `τ` = time per bead of `n1`), a change of sign with hysteresis
//! `θ = 10⁻⁶ · max δ_{k−1}` (a contact is closed above `θ`, open below `−θ`), the time by linear
//! interpolation of the zero crossing; (b) the hybrid engine's event log (handed to [`crate::experiments::timings::Window`]
//! through [`crate::engine::Observer::events`] by [`crate::experiments::timings`]), whose thresholds are `atol · L` (see
//! [`crate::engine::hybrid`]). Source (a) works for both engines (the dense cross-check).

use crate::snapshot::{EventKind, EventRecord};

/// A contact opening (`closed = false`) or closing (`closed = true`) at time `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transition {
    /// Time.
    pub t: f64,
    /// Contact index (between beads `contact` and `contact + 1`).
    pub contact: usize,
    /// `true`: the gap closed (contact starts); `false`: the contact opened.
    pub closed: bool,
}

/// Openings/closings from sampled overlaps: `delta[j][f]` is the overlap of contact
/// `contacts[j]` at frame time `t[f]`; hysteresis `theta` (see the module docs). Sorted by time.
pub fn transitions_from_frames(
    t: &[f64],
    contacts: &[usize],
    delta: &[Vec<f64>],
    theta: f64,
) -> Vec<Transition> {
    let mut out = Vec::new();
    for (j, &c) in contacts.iter().enumerate() {
        let d = &delta[j];
        let mut state: Option<bool> = None;
        for f in 1..d.len().min(t.len()) {
            let now = if d[f] > theta {
                Some(true)
            } else if d[f] < -theta {
                Some(false)
            } else {
                continue;
            };
            if state.is_some() && state != now {
                // the zero crossing just before frame f: the last sign change of δ
                let s = d[f] > 0.0;
                let mut g = f;
                while g > 0 && (d[g - 1] > 0.0) == s {
                    g -= 1;
                }
                let (a, b) = (g.saturating_sub(1), g);
                let tc = if a < b && d[b] != d[a] {
                    t[a] - d[a] * (t[b] - t[a]) / (d[b] - d[a])
                } else {
                    t[b]
                };
                out.push(Transition {
                    t: tc.clamp(t[a], t[b]),
                    contact: c,
                    closed: now == Some(true),
                });
            }
            state = now;
        }
    }
    out.sort_by(|a, b| a.t.total_cmp(&b.t).then(a.contact.cmp(&b.contact)));
    out
}

/// Openings/closings of the given contacts from the hybrid engine's event log.
pub fn transitions_from_events(events: &[EventRecord], contacts: &[usize]) -> Vec<Transition> {
    let mut out: Vec<Transition> = events
        .iter()
        .filter(|e| matches!(e.kind, EventKind::Open | EventKind::Close))
        .filter(|e| contacts.contains(&(e.contact as usize)))
        .map(|e| Transition {
            t: e.t,
            contact: e.contact as usize,
            closed: e.kind == EventKind::Close,
        })
        .collect();
    out.sort_by(|a, b| a.t.total_cmp(&b.t).then(a.contact.cmp(&b.contact)));
    out
}

/// The times `t1 … t5` (module docs); `None` where the event did not happen in the run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InterfaceTimings {
    /// First opening of contact `k−1`.
    pub t1: Option<f64>,
    /// Beads `k−1`, `k` both free (contacts `k−2`, `k−1`, `k` open).
    pub t2: Option<f64>,
    /// Two-body collision of beads `k−1`, `k` starts.
    pub t3: Option<f64>,
    /// ... and ends (contact `k−1` reopens).
    pub t3_end: Option<f64>,
    /// Bead `k` closes the gap to `k+1`.
    pub t4: Option<f64>,
    /// Bead `k−1` closes the gap to `k−2`.
    pub t5: Option<f64>,
}

impl InterfaceTimings {
    /// `[t1, t2, t3, t4, t5]`.
    pub fn as_array(&self) -> [Option<f64>; 5] {
        [self.t1, self.t2, self.t3, self.t4, self.t5]
    }
}

/// Extracts [`InterfaceTimings`] for interface bead `k ≥ 2` from time-ordered transitions.
pub fn interface_timings(tr: &[Transition], k: usize) -> InterfaceTimings {
    let mut out = InterfaceTimings::default();
    if k < 2 {
        return out;
    }
    let first = |c: usize, closed: bool, after: f64| {
        tr.iter()
            .find(|x| x.contact == c && x.closed == closed && x.t > after)
            .map(|x| x.t)
    };
    let Some(t1) = first(k - 1, false, f64::NEG_INFINITY) else {
        return out;
    };
    out.t1 = Some(t1);
    // replay the states of contacts k−2, k−1, k (start: closed, the wave passes them)
    let mut open = [false; 3];
    for x in tr {
        if x.contact + 2 >= k && x.contact <= k {
            open[x.contact + 2 - k] = !x.closed;
        }
        if x.t >= t1 && open.iter().all(|&o| o) {
            out.t2 = Some(x.t);
            break;
        }
    }
    let Some(t2) = out.t2 else { return out };
    out.t3 = first(k - 1, true, t2);
    let Some(t3) = out.t3 else { return out };
    out.t3_end = first(k - 1, false, t3);
    out.t4 = first(k, true, t3);
    out.t5 = first(k - 2, true, t3);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tr(t: f64, contact: usize, closed: bool) -> Transition {
        Transition { t, contact, closed }
    }

    #[test]
    fn frame_transitions_interpolate_zero_crossings() {
        // contact 7: +1 → −1 between t = 1 and 2 (crossing 1.5), back to +3 between 3 and 4
        // (crossing 3.25); values inside ±θ are ignored (no spurious transitions)
        let t = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let d = vec![vec![0.0, 1.0, -1.0, -1.0, 3.0, 1e-9]];
        let x = transitions_from_frames(&t, &[7], &d, 1e-6);
        assert_eq!(x.len(), 2, "{x:?}");
        // linear interpolation: exact to rounding (abs 1e-12)
        assert!((x[0].t - 1.5).abs() < 1e-12 && !x[0].closed && x[0].contact == 7);
        assert!((x[1].t - 3.25).abs() < 1e-12 && x[1].closed);
    }

    #[test]
    fn timings_follow_the_paper_sequence() {
        // k = 50: wave closes 48, 49, 50; 49 opens (t1 = 2), 48 opens (3), 50 opens (4 → t2),
        // 49 closes (6 → t3) and reopens (7), 50 closes (9 → t4), 48 closes (11 → t5)
        let x = [
            tr(0.5, 48, true),
            tr(1.0, 49, true),
            tr(1.5, 50, true),
            tr(2.0, 49, false),
            tr(3.0, 48, false),
            tr(4.0, 50, false),
            tr(6.0, 49, true),
            tr(7.0, 49, false),
            tr(9.0, 50, true),
            tr(11.0, 48, true),
        ];
        let s = interface_timings(&x, 50);
        assert_eq!(
            s.as_array(),
            [Some(2.0), Some(4.0), Some(6.0), Some(9.0), Some(11.0)]
        );
        assert_eq!(s.t3_end, Some(7.0));
        // without the two-body collision: t3, t4, t5 are missing
        let s = interface_timings(&x[..6], 50);
        assert_eq!(s.t2, Some(4.0));
        assert_eq!(s.t3, None);
        assert_eq!(s.t4, None);
    }
}
