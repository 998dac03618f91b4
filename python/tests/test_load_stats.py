"""A snapshot written without ``--timing`` does not record its wall time: ``load()`` said
``wall_seconds = 0.0`` (and the xarray attribute ``stats_wall_seconds = 0.0``), where
``beadchain inspect`` says "not recorded" (an adversarial review). Now None, left out of the
attributes as every None is."""

import subprocess

import pytest

import beadchain as bc


def test_untimed_wall_time_is_none(tmp_path):
    out = tmp_path / "s.snap"
    bc.run("striker", out=out)
    r = bc.load(out)
    assert r.stats["wall_seconds"] is None
    pytest.importorskip("xarray")
    assert "stats_wall_seconds" not in r.to_xarray().attrs


def test_timed_wall_time_is_kept(tmp_path, cli):
    out = tmp_path / "t.snap"
    subprocess.run([cli, "run", "striker", "--out", str(out), "--timing", "-q"], check=True)
    w = bc.load(out).stats["wall_seconds"]
    assert isinstance(w, float) and w > 0.0
