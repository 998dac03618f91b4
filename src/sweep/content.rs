//! Resuming by content: a run whose result is already in the finished result file `OUT` is not
//! run again. Each run's *content key* is a hash of what decides its row — the resolved,
//! validated scene (chain arrays, initial state, `[run]` settings: engine, method, tolerances,
//! until, every, seed), the `[measure]` and `[stop]` settings and the beadchain version — and
//! `OUT.meta` keeps the key of every row ([`super::csv::meta_text`]). A rerun takes a row of `OUT`
//! whose key equals a run's key, under the run's own index and parameters, whatever changed
//! elsewhere in the sweep file; a run whose scene changed (a value, a CSV file it reads, the
//! base scene) has another key and runs again.

use super::csv::{self, field, split_fields};
use super::expand::RunPoint;
use super::{fnv1a, SweepSpec};
use crate::scene::Scene;
use std::collections::BTreeMap;
use std::path::Path;

impl SweepSpec {
    /// The content key of a run with the resolved scene `scene` (module docs): 64-bit FNV-1a of
    /// the scene's exact bytes (bincode; its TOML form if that fails), the measures, the stops
    /// and the beadchain version.
    pub fn content_key(&self, scene: &Scene) -> u64 {
        let mut b = format!(
            "beadchain {} sweep content 1\nmeasure {:?}\nstop {:?}\nscene\n",
            env!("CARGO_PKG_VERSION"),
            self.measure,
            self.stop
        )
        .into_bytes();
        match bincode::serde::encode_to_vec(scene, bincode::config::standard()) {
            Ok(x) => b.extend(x),
            Err(_) => b.extend(crate::scene::show::to_toml(scene).into_bytes()),
        }
        fnv1a(&b)
    }
}

/// The rows of the finished result `out` that runs of `mine` (with their content keys) take as
/// they are: for each run whose key a row of `out` has (keys from `OUT.meta`), that row's result
/// fields (`status` onwards) after the run's own index and parameters. Nothing is taken from a
/// result without keys (an older beadchain's), one that cannot be read, or one whose result
/// columns (after the parameters) differ from `columns`' (e.g. `--timing` changed).
pub fn reusable_rows(
    spec: &SweepSpec,
    mine: &[(RunPoint, u64)],
    out: &Path,
    columns: &str,
) -> BTreeMap<usize, String> {
    let mut taken = BTreeMap::new();
    let keys = csv::read_keys(out);
    if keys.is_empty() {
        return taken;
    }
    let Ok(old) = csv::read_result(out, false) else {
        return taken;
    };
    let (Ok(new_cols), Ok(old_cols)) = (split_fields(columns), split_fields(&old.columns)) else {
        return taken;
    };
    let tail = new_cols.len() - 1 - spec.param_columns().len();
    if old_cols.len() < tail + 1
        || old_cols[old_cols.len() - tail..] != new_cols[new_cols.len() - tail..]
    {
        return taken;
    }
    let mut by_key: BTreeMap<u64, &String> = BTreeMap::new();
    for (i, k) in &keys {
        if let Some(row) = old.rows.get(i) {
            by_key.entry(*k).or_insert(row);
        }
    }
    for (run, key) in mine {
        let Some(row) = by_key.get(key) else { continue };
        let Ok(f) = split_fields(row) else { continue };
        if f.len() != old_cols.len() {
            continue;
        }
        let mut fields = run.fields(spec);
        fields.extend(f[f.len() - tail..].iter().map(|x| field(x)));
        taken.insert(run.index, fields.join(","));
    }
    taken
}
