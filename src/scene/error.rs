//! The scene error type: every variant displays as ONE line naming the scene file (or preset)
//! and the TOML key path (`[chain].mass`), the bead/contact index, or the CSV file and line.

use thiserror::Error;

/// Why a scene could not be loaded, parsed or validated.
///
/// `file` is the scene file as the user named it (or the preset / scene name); `key` is the TOML
/// key path, e.g. `[chain].exponent.segments[0].to`.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SceneError {
    /// The scene file exists but could not be read.
    #[error("{file}: cannot read scene file: {reason}")]
    Io {
        /// Scene file.
        file: String,
        /// OS error text.
        reason: String,
    },
    /// The text is not valid TOML (position is 1-based line and column).
    #[error("{file}:{line}:{column}: malformed TOML: {message}")]
    Syntax {
        /// Scene file.
        file: String,
        /// 1-based line of the error.
        line: usize,
        /// 1-based column (in characters) of the error.
        column: usize,
        /// The TOML parser's message.
        message: String,
    },
    /// A key is unknown, missing, of the wrong type, or has a bad value.
    #[error("{file}: {key}: {message}")]
    Key {
        /// Scene file.
        file: String,
        /// TOML key path.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// One entry of a per-bead or per-contact array is invalid.
    #[error("{file}: {key}: {what} {index}: {message}")]
    Index {
        /// Scene file.
        file: String,
        /// TOML key path of the array.
        key: String,
        /// `"bead"` or `"contact"`.
        what: &'static str,
        /// Bead or contact index (0-based).
        index: usize,
        /// What is wrong.
        message: String,
    },
    /// A `{ file = ... }` CSV could not be read.
    #[error("{file}: {key}: cannot read {csv}: {reason}")]
    CsvIo {
        /// Scene file.
        file: String,
        /// TOML key path that names the CSV.
        key: String,
        /// CSV path as resolved against the scene's directory.
        csv: String,
        /// OS error text.
        reason: String,
    },
    /// A line of a CSV file is not one finite number.
    #[error("{file}: {key}: {csv}:{line}: {message}")]
    Csv {
        /// Scene file.
        file: String,
        /// TOML key path that names the CSV.
        key: String,
        /// CSV path.
        csv: String,
        /// 1-based line number in the CSV.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// `load(spec)`: neither a readable file nor a preset name.
    #[error("{spec}: no such scene file, and no preset of that name (presets: {presets})")]
    NotFound {
        /// What the user asked for.
        spec: String,
        /// Comma-separated preset names.
        presets: String,
    },
}

/// Make user text safe for a one-line message (escapes newlines and other control characters).
pub fn one_line(s: &str) -> String {
    s.chars()
        .flat_map(|c| {
            if c.is_control() {
                c.escape_default().collect::<Vec<_>>()
            } else {
                vec![c]
            }
        })
        .collect()
}

/// The key path (`[scene].seed`) of a `key = value` line, for syntax errors inside a value (an
/// integer too large for 64 bits names its key this way); `None` for other lines.
pub(crate) fn key_at_line(text: &str, line: usize) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    let this = lines.get(line.checked_sub(1)?)?;
    let (key, _) = this.split_once('=')?;
    let key = key.trim();
    let plain = |s: &str| {
        !s.is_empty()
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '"'))
    };
    if !plain(key) {
        return None;
    }
    let table = lines[..line - 1]
        .iter()
        .rev()
        .map(|l| l.trim())
        .find(|l| l.starts_with('[') && l.ends_with(']'))
        .map_or(String::new(), |l| {
            l.trim_matches(|c| c == '[' || c == ']').to_string()
        });
    Some(if table.is_empty() {
        key.to_string()
    } else {
        format!("[{table}].{key}")
    })
}
