//! Provenance of every output: the beadchain version and the git commit it was built from, and
//! the date of a run.
//!
//! - [`BUILD_COMMIT`]: embedded by `build.rs` at build time: `git rev-parse HEAD` (40 hex digits),
//!   `-dirty` appended when tracked files differed from it, `unknown` when built without git or
//!   outside a repository (a wheel from an sdist); `BEADCHAIN_GIT_COMMIT` at build time
//!   overrides it. `beadchain --version` prints it.
//! - [`recorded_commit`]: what a writer stores: [`BUILD_COMMIT`], or nothing when
//!   `BEADCHAIN_NO_BUILD_COMMIT=1` is set at run time (for byte comparisons across builds:
//!   `validation/compare_presets.sh` sets it for both binaries).
//! - [`utc_now`]: the date of a run, UTC, ISO 8601 to the second (`2026-11-27T18:45:03Z`), or
//!   `SOURCE_DATE_EPOCH` (seconds since 1970) when set. Stored only by runs that record timing
//!   (`run --timing`): identical inputs otherwise give identical bytes.

use std::time::{SystemTime, UNIX_EPOCH};

/// Version of the beadchain crate.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The git commit this build was made from (see the module docs).
pub const BUILD_COMMIT: &str = env!("BEADCHAIN_BUILD_COMMIT");

/// The run-time variable that leaves the commit out of written files.
pub const NO_COMMIT_VAR: &str = "BEADCHAIN_NO_BUILD_COMMIT";

/// `beadchain --version`'s text after the name: version and commit.
pub const LONG_VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("BEADCHAIN_BUILD_COMMIT"),
    ")"
);

/// The commit a writer records: [`BUILD_COMMIT`], or `None` when `BEADCHAIN_NO_BUILD_COMMIT` is
/// set to a value other than empty or `0`.
pub fn recorded_commit() -> Option<String> {
    match std::env::var_os(NO_COMMIT_VAR) {
        Some(v) if !v.is_empty() && v != "0" => None,
        _ => Some(BUILD_COMMIT.to_string()),
    }
}

/// Now (or `SOURCE_DATE_EPOCH` when set to whole seconds) as `YYYY-MM-DDTHH:MM:SSZ`.
pub fn utc_now() -> String {
    let secs = std::env::var("SOURCE_DATE_EPOCH")
        .ok()
        .and_then(|s| s.trim().parse::<i64>().ok())
        .unwrap_or_else(|| match SystemTime::now().duration_since(UNIX_EPOCH) {
            Ok(d) => i64::try_from(d.as_secs()).unwrap_or(i64::MAX),
            Err(e) => -i64::try_from(e.duration().as_secs()).unwrap_or(i64::MAX),
        });
    utc_iso(secs)
}

/// Seconds since 1970-01-01T00:00:00Z as `YYYY-MM-DDTHH:MM:SSZ` (proleptic Gregorian calendar;
/// days to date by H. Hinnant's `civil_from_days`).
pub fn utc_iso(secs: i64) -> String {
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

/// Whether `c` has the form of a recorded commit: 40 lower-case hex digits, optionally
/// followed by `-dirty`, or `unknown`.
pub fn is_commit(c: &str) -> bool {
    let hex = c.strip_suffix("-dirty").unwrap_or(c);
    c == "unknown"
        || (hex.len() == 40 && hex.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f')))
}
