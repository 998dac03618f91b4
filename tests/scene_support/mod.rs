//! Shared helpers of the scene tests (`scenes.rs`, `scene_errors.rs`): parse a scene text,
//! expect success or a one-line error, compare floats with absolute and relative tolerances.
#![allow(dead_code)]

use beadchain::scene::{parse_str, Scene, SceneError};
use std::path::Path;

pub fn parse(text: &str) -> Result<Scene, SceneError> {
    parse_str(text, Path::new("."), "t.toml")
}

pub fn ok(text: &str) -> Scene {
    match parse(text) {
        Ok(s) => s,
        Err(e) => panic!("scene should parse: {e}"),
    }
}

/// The error's one-line message; panics if parsing succeeded.
pub fn err(text: &str) -> String {
    match parse(text) {
        Ok(_) => panic!("scene should fail:\n{text}"),
        Err(e) => {
            let m = e.to_string();
            assert!(!m.contains('\n'), "message must be one line: {m:?}");
            m
        }
    }
}

pub fn assert_contains(msg: &str, parts: &[&str]) {
    for p in parts {
        assert!(msg.contains(p), "message {msg:?} should contain {p:?}");
    }
}

/// `|a − b| ≤ abs + rel·|b|`.
pub fn close(a: f64, b: f64, abs: f64, rel: f64) -> bool {
    (a - b).abs() <= abs + rel * b.abs()
}

pub const RUN: &str = "[run]\nuntil = 10.0\n";
