//! Shared helpers of the output-selection CLI tests (`output_selection.rs`,
//! `output_selection_readers.rs`): frame bits, exit checks, a striker run with options.
#![allow(dead_code)]

use super::common::bc;
use beadchain::snapshot::Frame;
use std::path::Path;
use std::process::Output;

pub fn bits(f: &Frame) -> Vec<u64> {
    std::iter::once(f.t.to_bits())
        .chain(f.u.iter().map(|x| x.to_bits()))
        .chain(f.v.iter().map(|x| x.to_bits()))
        .collect()
}

pub fn ok(o: &Output) {
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `beadchain run striker` (the 100-bead preset) to t = 20 with frames every 1, plus `extra`.
pub fn run_striker(dir: &Path, out: &str, extra: &[&str]) -> Output {
    let mut args = vec![
        "run", "striker", "--until", "20", "--every", "1", "-q", "--out", out,
    ];
    args.extend_from_slice(extra);
    bc(dir, &args)
}

/// Payload length of the HEADER section (bytes 16..24 of the file).
pub fn header_len(bytes: &[u8]) -> u64 {
    u64::from_le_bytes(bytes[16..24].try_into().unwrap())
}
