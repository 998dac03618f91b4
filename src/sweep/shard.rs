//! `--shard K/M`: which runs a shard runs, and the result files a shard must not overwrite.

use super::csv;
use super::expand::RunPoint;
use super::SweepError;

/// `--shard K/M`: the runs with `index % M == K − 1` (K is 1-based).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// 1-based shard number.
    pub k: usize,
    /// Number of shards.
    pub m: usize,
}

impl std::str::FromStr for Shard {
    type Err = SweepError;
    fn from_str(s: &str) -> Result<Self, SweepError> {
        let bad = |why: &str| SweepError::Options(format!("--shard {s}: {why}"));
        let (k, m) = s
            .split_once('/')
            .ok_or_else(|| bad("expected K/M, e.g. 3/8"))?;
        let k: usize = k.trim().parse().map_err(|_| bad("K is not a number"))?;
        let m: usize = m.trim().parse().map_err(|_| bad("M is not a number"))?;
        if m == 0 || k == 0 || k > m {
            return Err(bad("need 1 <= K <= M"));
        }
        Ok(Shard { k, m })
    }
}

impl Shard {
    /// Whether run `index` belongs to this shard.
    pub fn contains(&self, index: usize) -> bool {
        index % self.m == self.k - 1
    }
}

/// A shard's `--out` that holds the result of this same sweep (its spec line) with rows of
/// runs outside the shard (the whole sweep's result, another shard's) is refused before
/// anything runs: writing the shard's rows there would drop them.
pub(super) fn check_other_shards(
    (out, shard): (&std::path::Path, Option<Shard>),
    spec_line: &str,
    mine: &[RunPoint],
) -> Result<(), SweepError> {
    let Some(shard) = shard else {
        return Ok(());
    };
    let Ok(old) = csv::read_result(out, false) else {
        return Ok(());
    };
    let same_sweep = csv::spec_part(&old.spec_line) == spec_line;
    let others: Vec<usize> = old
        .rows
        .keys()
        .copied()
        .filter(|i| mine.binary_search_by_key(i, |r| r.index).is_err())
        .collect();
    match (same_sweep, others.first()) {
        (true, Some(first)) => Err(SweepError::Csv {
            file: out.display().to_string(),
            line: 0,
            message: format!(
                "it holds {} rows of this sweep that shard {}/{} does not run (run {first} \
                 first); writing the shard's result there would drop them: give the shard its \
                 own --out (and `beadchain merge` the shards)",
                others.len(),
                shard.k,
                shard.m
            ),
        }),
        _ => Ok(()),
    }
}
