//! "Did you mean": the nearest names to a misspelled one (preset names for `run`, `check`,
//! `accuracy`, `scene show` and sweep files).
//!
//! A candidate is near when its edit distance (Levenshtein: insertions, deletions,
//! substitutions) to the word is at most a third of the word's length, and at least 2; the
//! nearest ones are suggested (at most [`MAX_SUGGESTIONS`], ties in candidate order). When none
//! is near, the candidates that start with the word (3 characters or more) are suggested: a
//! prefix such as `gapped` names `gapped_chain`.

/// Most names suggested at once.
pub const MAX_SUGGESTIONS: usize = 3;

/// Levenshtein distance between `a` and `b`, in characters.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diag = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let up = row[j + 1];
            row[j + 1] = (diag + usize::from(ca != cb)).min(up + 1).min(row[j] + 1);
            diag = up;
        }
    }
    row[b.len()]
}

/// The candidates nearest to `word` (see the module docs); empty when none is near.
pub fn nearest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Vec<&'a str> {
    let candidates: Vec<&str> = candidates.into_iter().collect();
    let limit = (word.chars().count() / 3).max(2);
    let scored: Vec<(usize, &str)> = candidates
        .iter()
        .map(|&c| (edit_distance(word, c), c))
        .filter(|&(d, _)| d <= limit)
        .collect();
    if let Some(best) = scored.iter().map(|&(d, _)| d).min() {
        return scored
            .into_iter()
            .filter(|&(d, _)| d == best)
            .map(|(_, c)| c)
            .take(MAX_SUGGESTIONS)
            .collect();
    }
    if word.chars().count() < 3 {
        return Vec::new();
    }
    candidates
        .into_iter()
        .filter(|c| c.starts_with(word))
        .take(MAX_SUGGESTIONS)
        .collect()
}

/// `did you mean `a`?` / `did you mean `a` or `b`?`; `None` without suggestions.
pub fn did_you_mean(names: &[&str]) -> Option<String> {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    match quoted.split_last() {
        None => None,
        Some((last, [])) => Some(format!("did you mean {last}?")),
        Some((last, rest)) => Some(format!("did you mean {} or {last}?", rest.join(", "))),
    }
}

/// The end of a "no such scene file, and no preset of that name" message for `spec`: the
/// nearest preset names, else where the list is (never the whole list).
pub fn preset_hint(spec: &str) -> String {
    let names = crate::scene::presets().iter().map(|p| p.name);
    match did_you_mean(&nearest(spec, names)) {
        Some(s) => format!("; {s}"),
        None => " (`beadchain scenes` lists the presets)".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances() {
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("strikr", "striker"), 1);
        assert_eq!(edit_distance("same", "same"), 0);
    }

    #[test]
    fn nearest_names() {
        let c = ["striker", "two_strikers", "tapered", "gapped_chain"];
        assert_eq!(nearest("strikr", c), ["striker"]);
        assert_eq!(nearest("two_striker", c), ["two_strikers"]);
        assert_eq!(nearest("gapped", c), ["gapped_chain"]);
        assert!(nearest("nothere.toml", c).is_empty());
        assert!(nearest("x", c).is_empty());
        assert_eq!(did_you_mean(&["a"]).unwrap(), "did you mean `a`?");
        assert_eq!(
            did_you_mean(&["a", "b", "c"]).unwrap(),
            "did you mean `a`, `b` or `c`?"
        );
        assert_eq!(did_you_mean(&[]), None);
    }
}
