//! Output selection of a run (issue 14): which beads and which fields the FRAME sections store,
//! and the cap on the number of frames. Recorded in the snapshot header
//! (`crate::snapshot::Header::output`, format version 3; older files store everything), so every reader knows what a frame holds.
//!
//! - **Beads** (`run --beads LIST`): comma-separated items, each a 0-based bead index `I`, a
//!   half-open range `A:B` (beads `A, A+1, …, B−1`, as Rust's `A..B` and Python's `A:B`) or a
//!   stepped range `A:B:STEP` (`A, A+STEP, …` below `B`); `A` defaults to 0 and `B` to the
//!   bead count `N` (`10:` is bead 10 to the end). The selected beads are stored in increasing
//!   index order whatever the order of the items; a bead selected twice, an index `≥ N`, an
//!   empty range or an empty list is an error. A selection of every bead is stored as "all".
//! - **Fields** (`run --fields u,v`): `u` (displacements), `v` (velocities) or both (default).
//! - **Frames** (`run --frames-max K`): a run that would write more than `K` frames is refused
//!   before it starts (no silent thinning); the cap is kept so `resume --until` is checked too.
//!
//! A FRAME then holds `k`, `t`, `u` of the selected beads (if stored), `v` of the selected
//! beads (if stored): `L = 16 + 8·M·F` bytes for `M` beads and `F` fields.
//!
//! A scene setting (`[output]`, `run --beads/--fields`); the snapshot format re-exports it.

use serde::{Deserialize, Serialize};

/// Why a `--beads` / `--fields` value or a stored output selection is refused (one line,
/// without the option name).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SelectionError {
    /// A `--fields` item other than `u` or `v`.
    #[error("unknown field '{0}': expected u, v or u,v (displacements, velocities)")]
    UnknownField(String),
    /// A `--fields` item given twice.
    #[error("field {0} is given twice")]
    FieldTwice(String),
    /// A stored selection lists no bead.
    #[error("the output selection lists no bead")]
    NoBead,
    /// A stored selection's beads are not strictly increasing.
    #[error("the output selection's beads are not strictly increasing")]
    NotIncreasing,
    /// A stored selection names a bead beyond the chain.
    #[error("the output selection names bead {last} but the chain has {n} beads")]
    BeyondChain {
        /// The last bead listed.
        last: u64,
        /// Beads in the chain.
        n: u64,
    },
    /// An empty `--beads` value.
    #[error("empty selection: give bead indices or ranges A:B")]
    Empty,
    /// An item that selects no bead (`A >= B`).
    #[error("'{0}' selects no bead (A:B is half-open: A < B)")]
    SelectsNone(String),
    /// A bead selected by two items.
    #[error("bead {0} is selected twice")]
    Twice(u64),
    /// An item that is not `I`, `A:B` or `A:B:STEP`.
    #[error(
        "invalid item '{0}': expected a bead index I, a range A:B or A:B:STEP (0-based, B excluded)"
    )]
    InvalidItem(String),
    /// A zero `STEP`.
    #[error("'{0}': STEP must be at least 1")]
    ZeroStep(String),
    /// A single bead index `>= N`.
    #[error(
        "bead {bead} is out of range: the chain has {n} beads (indices 0 to {})",
        n.saturating_sub(1)
    )]
    BeadOutOfRange {
        /// The index given.
        bead: u64,
        /// Beads in the chain.
        n: u64,
    },
    /// A range beyond the chain.
    #[error(
        "range '{item}' is out of range: the chain has {n} beads (indices 0 to {}; B may be at most N)",
        n.saturating_sub(1)
    )]
    RangeOutOfRange {
        /// The item as given.
        item: String,
        /// Beads in the chain.
        n: u64,
    },
}

/// The fields a frame stores.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Fields {
    /// Displacements and velocities (every file before format version 3).
    #[default]
    Both,
    /// Displacements `u` only.
    U,
    /// Velocities `v` only.
    V,
}

impl Fields {
    /// True when displacements are stored.
    pub fn has_u(self) -> bool {
        self != Fields::V
    }

    /// True when velocities are stored.
    pub fn has_v(self) -> bool {
        self != Fields::U
    }

    /// Number of fields stored (1 or 2).
    pub fn count(self) -> u64 {
        u64::from(self.has_u()) + u64::from(self.has_v())
    }

    /// `u,v`, `u` or `v` (the `--fields` spelling).
    pub fn name(self) -> &'static str {
        match self {
            Fields::Both => "u,v",
            Fields::U => "u",
            Fields::V => "v",
        }
    }

    /// Parses a `--fields` value: `u`, `v`, `u,v` or `v,u`.
    pub fn parse(spec: &str) -> Result<Fields, SelectionError> {
        let (mut u, mut v) = (false, false);
        for item in spec.split(',') {
            let slot = match item.trim() {
                "u" => &mut u,
                "v" => &mut v,
                other => return Err(SelectionError::UnknownField(other.to_string())),
            };
            if *slot {
                return Err(SelectionError::FieldTwice(item.trim().to_string()));
            }
            *slot = true;
        }
        Ok(match (u, v) {
            (true, true) => Fields::Both,
            (true, false) => Fields::U,
            _ => Fields::V,
        })
    }
}

/// What the frames of a snapshot store (see the module docs).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Selection {
    /// Stored bead indices, strictly increasing, each below `N`; `None`: every bead.
    pub beads: Option<Vec<u64>>,
    /// Stored fields.
    pub fields: Fields,
    /// The `--frames-max` cap of the run (`None`: no cap).
    pub frames_max: Option<u64>,
}

impl Selection {
    /// True when the frames hold every bead and both fields (as every file before version 3).
    pub fn is_full(&self) -> bool {
        self.beads.is_none() && self.fields == Fields::Both
    }

    /// Number of beads stored per frame, of a chain of `n` beads.
    pub fn bead_count(&self, n: u64) -> u64 {
        self.beads.as_ref().map_or(n, |b| b.len() as u64)
    }

    /// Real index of the `j`-th stored bead.
    pub fn bead(&self, j: usize) -> u64 {
        self.beads.as_ref().map_or(j as u64, |b| b[j])
    }

    /// Numbers stored per frame besides the frame number and `t` (`None` on overflow).
    pub fn values_per_frame(&self, n: u64) -> Option<u64> {
        self.bead_count(n).checked_mul(self.fields.count())
    }

    /// Payload length of a FRAME section of format `version` (`None` on overflow): frame
    /// number and `t` (versions 1–3), then the dissipated energy (version 4), then the values.
    pub fn frame_payload_len(&self, n: u64, version: u32) -> Option<u64> {
        let lead = if version >= 4 { 24 } else { 16 };
        self.values_per_frame(n)?.checked_mul(8)?.checked_add(lead)
    }

    /// Errors unless the bead list is non-empty, strictly increasing and below `n` (a header
    /// that breaks this is corrupt).
    pub fn check(&self, n: u64) -> Result<(), SelectionError> {
        let Some(b) = &self.beads else {
            return Ok(());
        };
        if b.is_empty() {
            return Err(SelectionError::NoBead);
        }
        if b.windows(2).any(|w| w[0] >= w[1]) {
            return Err(SelectionError::NotIncreasing);
        }
        match b.last() {
            Some(&last) if last >= n => Err(SelectionError::BeyondChain { last, n }),
            _ => Ok(()),
        }
    }

    /// The stored beads (of a chain of `n`) as `--beads` would spell them (`10:20`,
    /// `0:100:10`, `3,10,20`), or `all`; long lists are shortened to their first items and a
    /// count.
    pub fn beads_text(&self, n: u64) -> String {
        let Some(b) = &self.beads else {
            return "all".into();
        };
        let runs = runs(b);
        let shown: Vec<String> = runs.iter().take(6).map(|r| run_text(r, n)).collect();
        if runs.len() > shown.len() {
            format!("{},… ({} items)", shown.join(","), runs.len())
        } else {
            shown.join(",")
        }
    }

    /// `beads 10:20 (10 of 100), fields u` for messages and `inspect`.
    pub fn describe(&self, n: u64) -> String {
        format!(
            "beads {} ({} of {n}), fields {}",
            self.beads_text(n),
            self.bead_count(n),
            self.fields.name()
        )
    }
}

/// Arithmetic runs `(first, step, count)` of a strictly increasing list (greedy).
fn runs(b: &[u64]) -> Vec<(u64, u64, u64)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let step = if i + 1 < b.len() { b[i + 1] - b[i] } else { 1 };
        let mut j = i + 1;
        while j < b.len() && b[j] - b[j - 1] == step {
            j += 1;
        }
        let count = (j - i) as u64;
        if count == 2 && step != 1 {
            out.push((b[i], 1, 1)); // two far-apart beads read better as a list
            i += 1;
        } else {
            out.push((b[i], step, count));
            i = j;
        }
    }
    out
}

/// `first:end:step` with the half-open end one step after the last bead (at most `n`).
fn run_text(&(first, step, count): &(u64, u64, u64), n: u64) -> String {
    let end = (first + step * count).min(n);
    match (count, step) {
        (1, _) => first.to_string(),
        (_, 1) => format!("{first}:{end}"),
        _ => format!("{first}:{end}:{step}"),
    }
}

/// Parses a `--beads` value for a chain of `n` beads (grammar in the module docs): the sorted
/// bead list, or `None` when it selects every bead. Errors are one line without the option.
pub fn parse_beads(spec: &str, n: u64) -> Result<Option<Vec<u64>>, SelectionError> {
    if spec.trim().is_empty() {
        return Err(SelectionError::Empty);
    }
    let mut list = Vec::new();
    for item in spec.split(',') {
        let item = item.trim();
        let (a, b, step) = parse_item(item, n)?;
        if a >= b {
            return Err(SelectionError::SelectsNone(item.to_string()));
        }
        list.extend((a..b).step_by(step as usize));
    }
    list.sort_unstable();
    if let Some(w) = list.windows(2).find(|w| w[0] == w[1]) {
        return Err(SelectionError::Twice(w[0]));
    }
    Ok(if list.len() as u64 == n {
        None
    } else {
        Some(list)
    })
}

/// One item: `(A, B, STEP)` of the half-open range it selects.
fn parse_item(item: &str, n: u64) -> Result<(u64, u64, u64), SelectionError> {
    let bad = || SelectionError::InvalidItem(item.to_string());
    let num = |s: &str, default: u64| -> Result<u64, SelectionError> {
        match s.trim() {
            "" => Ok(default),
            t => t.parse::<u64>().map_err(|_| bad()),
        }
    };
    let parts: Vec<&str> = item.split(':').collect();
    let (a, b, step) = match parts[..] {
        [i] if !i.is_empty() => {
            let i = num(i, 0)?;
            (i, i.saturating_add(1), 1)
        }
        [a, b] => (num(a, 0)?, num(b, n)?, 1),
        [a, b, s] => (num(a, 0)?, num(b, n)?, num(s, 1)?),
        _ => return Err(bad()),
    };
    if step == 0 {
        return Err(SelectionError::ZeroStep(item.to_string()));
    }
    let single = parts.len() == 1;
    if a >= n && single {
        return Err(SelectionError::BeadOutOfRange { bead: a, n });
    }
    if a >= n || (!single && b > n) {
        return Err(SelectionError::RangeOutOfRange {
            item: item.to_string(),
            n,
        });
    }
    Ok((a, b, step))
}
