//! The event log's peak overlaps of contacts that are closed at `t = 0`
//! (`src/engine/hybrid/eventlog.rs`): found by a review of the SI and export paths.

mod common;
use beadchain::engine::events::EventKind;
use beadchain::integrate::Method;
use beadchain::scene::{self, Engine};
use common::*;
use std::path::Path;

/// The defect: a peak overlap was the largest over each step's interior and end, never a
/// run's first instant, so a contact that starts closed and only opens logged less than its
/// overlap at `t = 0`: three beads pressed by 0.5, the first two flying apart, logged contact
/// 0's peak as 0.49977 (the exact two-bead path gave 0.5), and a soft wall pressed by 0.5
/// logged 0.4987. Now both are the starting overlaps (abs 1e-15).
#[test]
fn contacts_closed_at_the_start_log_their_starting_overlap_as_peak() {
    let s = scene::parse_str(
        "[chain]\nbeads = 3\nprecompression = 0.5\n[initial]\n\
         velocity = [-1.0, 1.0, 0.0]\n[run]\nuntil = 3.0\n",
        Path::new("."),
        "pk3",
    )
    .unwrap();
    let rec = run(&s, &config(Engine::Hybrid, Method::Auto, 1e-8, 1e-12, 3.0)).1;
    let open = rec
        .events
        .iter()
        .find(|e| e.kind == EventKind::Open && e.contact == 0)
        .expect("contact 0 opens");
    assert!((open.peak_overlap - 0.5).abs() < 1e-15, "{open:?}");
    let s = scene::parse_str(
        "[chain]\nbeads = 3\nprecompression = 0.1\n[walls]\nleft = { precompression = 0.5 }\n\
         [initial]\nvelocity = [1.0, 0.0, 0.0]\n[run]\nuntil = 5.0\n",
        Path::new("."),
        "wall",
    )
    .unwrap();
    let rec = run(&s, &config(Engine::Hybrid, Method::Auto, 1e-8, 1e-12, 5.0)).1;
    let open = rec
        .events
        .iter()
        .find(|e| e.kind == EventKind::WallOpen)
        .expect("the left wall opens");
    assert!((open.peak_overlap - 0.5).abs() < 1e-15, "{open:?}");
}
