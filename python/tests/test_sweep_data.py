"""Sweeps as data (issue 36, item 3): numeric swept columns, the CLI's result file written from
Python bit for bit, and resume by content (unchanged points are not run again)."""

import os
import time

import numpy as np
import pytest

import beadchain as bc
from conftest import ROOT, run_cli

GRID = ROOT / "data" / "sweeps" / "reflection_grid.toml"

# 3 x 2 grid x 2 seeds = 12 runs of 30 beads, random masses from bead 5 on (tests/sweep.rs)
SEEDED = """scene = "striker"
[set]
"chain.beads" = 30
"run.until" = 40.0
"run.every" = 0.5
"chain.mass" = { random = { mean = 1.0, eps = 0.0 }, start = 5 }
[grid]
"chain.mass.random.eps" = [0.0, 0.1, 0.4]
"chain.beads" = [30, 40]
[seeds]
key = "scene.seed"
values = [3, 4]
[measure]
fragments = true
[stop]
margin = 4
"""


def _seeded(tmp_path):
    p = tmp_path / "seeded.toml"
    p.write_text(SEEDED.replace('"chain.beads" = 30\n', "", 1))
    return p


def test_swept_keys_and_seeds_are_numbers(tmp_path):
    t = bc.sweep(_seeded(tmp_path))
    eps, beads, seed = t["chain.mass.random.eps"], t["chain.beads"], t["scene.seed"]
    assert eps.dtype == np.float64 and beads.dtype == np.int64 and seed.dtype == np.int64
    # grid keys in alphabetical order, the last fastest, then the seeds
    assert list(beads) == [30] * 6 + [40] * 6 and list(seed) == [3, 4] * 6
    assert list(eps) == [0.0, 0.0, 0.1, 0.1, 0.4, 0.4] * 2
    assert t["steps"].dtype == np.int64 and t["fragments"].dtype == np.int64
    assert t["t_end"].dtype == np.float64 and t["status"] == ["ok"] * 12
    row = bc.sweep_run(_seeded(tmp_path), 5)
    assert (type(row["chain.mass.random.eps"]), type(row["chain.beads"]), type(row["scene.seed"])) \
        == (float, int, int)
    assert (row["chain.mass.random.eps"], row["chain.beads"], row["scene.seed"]) == (0.4, 30, 4)
    pd = pytest.importorskip("pandas")
    df = pd.DataFrame(t)
    assert df["scene.seed"].dtype.kind == "i" and df["chain.mass.random.eps"].dtype.kind == "f"
    assert df.groupby("scene.seed")["fragments"].count().to_dict() == {3: 6, 4: 6}


def test_sweep_out_is_the_clis_file_bit_for_bit(cli, tmp_path):
    code, _, err = run_cli(cli, "sweep", GRID, "--out", tmp_path / "cli.csv", "--jobs", "1")
    assert code == 0, err
    t = bc.sweep(GRID, out=tmp_path / "py.csv")
    assert (t.skipped, t.ran, t.written) == (0, 9, True)
    for ext in ("", ".meta"):
        assert (tmp_path / f"py.csv{ext}").read_bytes() == (tmp_path / f"cli.csv{ext}").read_bytes()
    # the columns are those of a sweep without out=
    plain = bc.sweep(GRID)
    assert (plain.skipped, plain.ran, plain.written) == (0, 9, False)
    for k in plain:
        assert list(plain[k]) == list(t[k]), k


def test_rerun_skips_every_point_and_rewrites_nothing(cli, tmp_path):
    out = tmp_path / "r.csv"
    bc.sweep(GRID, out=out)
    before = out.read_bytes(), (tmp_path / "r.csv.meta").read_bytes()
    stamps = os.stat(out).st_mtime_ns, os.stat(tmp_path / "r.csv.meta").st_mtime_ns
    time.sleep(0.02)
    calls = []
    again = bc.sweep(GRID, out=out, progress=lambda d, n: calls.append(d))
    assert (again.skipped, again.ran, again.written) == (9, 0, False)
    assert calls == [], "nothing ran"
    assert (out.read_bytes(), (tmp_path / "r.csv.meta").read_bytes()) == before
    assert (os.stat(out).st_mtime_ns, os.stat(tmp_path / "r.csv.meta").st_mtime_ns) == stamps
    for k in again:
        assert list(again[k]) == list(bc.sweep(GRID)[k]), k
    # the CLI takes the file Python wrote the same way
    code, stdout, err = run_cli(cli, "sweep", GRID, "--out", out)
    assert code == 0, err
    assert "9 runs: 0 resumed, 9 skipped" in stdout and "0 run now" in stdout, stdout
    assert "is up to date (unchanged)" in stdout, stdout
    assert out.read_bytes() == before[0]


def test_a_changed_value_reruns_only_its_points(cli, tmp_path):
    out = tmp_path / "r.csv"
    bc.sweep(GRID, out=out)
    old = out.read_text().splitlines()
    changed = tmp_path / "grid.toml"
    # n2 = 3.5 -> 4.0: runs 2, 5, 8 (the last n2 of each n1) change
    text = GRID.read_text()
    assert text.count("[2.5, 3.0, 3.5]  # n2") == 1
    changed.write_text(text.replace("[2.5, 3.0, 3.5]  # n2", "[2.5, 3.0, 4.0]  # n2"))
    ran = []
    t = bc.sweep(changed, out=out, progress=lambda d, n: ran.append(d))
    assert (t.skipped, t.ran, t.written) == (6, 3, True)
    assert list(t["chain.exponent.segments.0.value"]) == [2.5, 3.0, 4.0] * 3
    new = out.read_text().splitlines()
    for i in (0, 1, 3, 4, 6, 7):
        assert new[1 + i] == old[1 + i], i
    for i in (2, 5, 8):
        assert new[1 + i] != old[1 + i] and new[1 + i].split(",")[2] == "4.0", new[1 + i]
    code, _, err = run_cli(cli, "sweep", changed, "--out", tmp_path / "fresh.csv")
    assert code == 0, err
    assert out.read_bytes() == (tmp_path / "fresh.csv").read_bytes()
    assert (tmp_path / "r.csv.meta").read_bytes() == (tmp_path / "fresh.csv.meta").read_bytes()
