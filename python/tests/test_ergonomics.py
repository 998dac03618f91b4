"""Issue 36 item 5 (ergonomics): preset names in run(), progress, readable reprs, the energy
error of stats() after set_velocities."""

import io
import sys

import numpy as np
import pytest

import beadchain as bc


# --- run("preset") -----------------------------------------------------------------------
def test_run_accepts_a_preset_name():
    r = bc.run("striker", every=50.0)
    ref = bc.run(bc.Scene.preset("striker"), every=50.0)
    assert r.scene.name == "striker"
    np.testing.assert_array_equal(r.t, ref.t)
    np.testing.assert_array_equal(r.v, ref.v)


def test_run_preset_name_misspelt_names_the_nearest_presets():
    with pytest.raises(bc.SceneError) as e:
        bc.run("strikr")
    assert "unknown preset 'strikr'" in str(e.value)
    assert "'striker'" in str(e.value)


def test_run_accepts_a_toml_path(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(bc.Scene.preset("striker").source)
    for p in (path, str(path)):
        r = bc.run(p, every=50.0)
        assert r.scene.n_beads == bc.Scene.preset("striker").n_beads
    with pytest.raises(bc.SceneError, match="no such file"):
        bc.run(str(tmp_path / "missing.toml"))


def test_simulation_accepts_a_preset_name():
    sim = bc.Simulation("striker")
    assert sim.scene.name == "striker"


# --- progress ----------------------------------------------------------------------------
def test_run_progress_callable_is_called_at_frames_and_the_end():
    calls = []
    bc.run("striker", every=10.0, progress=lambda t, until: calls.append((t, until)))
    ts = [t for t, _ in calls]
    assert all(u == 100.0 for _, u in calls)
    # at least once per frame (0, 10, ..., 100) and at the end
    for frame in np.arange(0.0, 100.0 + 1e-9, 10.0):
        assert any(abs(t - frame) <= 1e-12 for t in ts), frame
    assert ts[-1] == 100.0
    assert ts == sorted(ts)
    # never per step
    steps = bc.run("striker", every=10.0).stats["steps"]
    assert len(calls) < steps


def test_run_progress_true_draws_a_bar(monkeypatch):
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setitem(sys.modules, "tqdm", None)  # the fallback bar (no tqdm)
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    bc.run("striker", every=25.0, progress=True)
    out = err.getvalue()
    assert "100%" in out and "striker" in out


def test_run_progress_true_uses_tqdm(monkeypatch):
    pytest.importorskip("tqdm")
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    bc.run("striker", every=25.0, progress=True)
    assert "100" in err.getvalue()


def test_run_progress_rejects_other_values():
    with pytest.raises(TypeError, match="progress"):
        bc.run("striker", progress=3)


# --- reprs -------------------------------------------------------------------------------
def _one_line_summary(text, *words):
    assert "\n" not in text and len(text) < 200, text
    for w in words:
        assert w in text, (w, text)


def test_simulation_repr_is_a_one_line_summary():
    sim = bc.Simulation("striker", every=10.0)
    sim.advance(20.0)
    _one_line_summary(repr(sim), "Simulation", "striker", "beads=", "t=20", "until=100")
    assert "<table" in sim._repr_html_()


def test_state_repr_is_a_one_line_summary():
    sim = bc.Simulation(bc.Scene(beads=500, striker=1.0, until=50.0))
    sim.advance(10.0)
    _one_line_summary(repr(sim.state), "State", "t=10", "beads=500")
    assert "<table" in sim.state._repr_html_()


def test_chain_repr_is_a_one_line_summary():
    chain = bc.Scene(beads=500, striker=1.0, until=50.0).chain
    _one_line_summary(repr(chain), "Chain", "beads=500", "law=")
    assert "<table" in chain._repr_html_()


def test_run_and_scene_reprs_and_html():
    r = bc.run("striker", every=50.0)
    _one_line_summary(repr(r), "Run", "striker", "frames=3")
    assert "<table" in r._repr_html_()
    assert "<table" in r.scene._repr_html_()


def test_loaded_run_repr_does_not_read_frames(tmp_path):
    bc.run("striker", every=50.0, out=tmp_path / "s.bcs")
    r = bc.load(tmp_path / "s.bcs")
    _one_line_summary(repr(r), "Run", "frames=3")
    assert r._u is not None and r._file is not None
    from beadchain._run import _UNREAD
    assert r._u is _UNREAD


# --- stats() after set_velocities ---------------------------------------------------------
def test_stats_energy_error_after_set_velocities_is_measured_from_the_set_state():
    scene = bc.Scene(beads=50, striker=1.0, until=200.0, every=10.0)
    sim = bc.Simulation(scene)
    sim.advance(20.0)
    before = sim.stats()
    v = sim.state.v.copy()
    v[49] = -0.5  # inject kinetic energy 0.125
    sim.set_velocities(v)
    sim.advance()
    st = sim.stats()
    # the engine's error, not the injected energy (0.2 before the fix: 0.125 over the scale
    # 0.625, the gross energy after the kick)
    assert st["relative_energy_error"] < 1e-6
    assert st["energy_injected"] == pytest.approx(0.125, rel=1e-9, abs=1e-12)
    assert st["energy_reference"] == pytest.approx(before["energy_final"] + 0.125,
                                                   rel=1e-9, abs=1e-12)
    assert st["momentum_reference"] == pytest.approx(0.5, rel=1e-9, abs=1e-12)
    assert st["t_reference"] == 20.0
    # energy_initial stays the scene's energy at t = 0
    assert st["energy_initial"] == pytest.approx(0.5, rel=1e-12, abs=0)
    assert sim.frames().stats["relative_energy_error"] == st["relative_energy_error"]


def test_stats_without_set_velocities_has_the_run_reference():
    sim = bc.Simulation(bc.Scene(beads=50, striker=1.0, until=50.0))
    sim.advance()
    st = sim.stats()
    assert st["energy_reference"] == st["energy_initial"]
    assert st["energy_injected"] == 0.0
    assert st["t_reference"] == 0.0
    r = bc.run(bc.Scene(beads=50, striker=1.0, until=50.0))
    assert r.stats["relative_energy_error"] == st["relative_energy_error"]


def test_scene_path_containing_equals_is_parsed_as_toml(tmp_path, monkeypatch):
    text = bc.Scene(name="chain", beads=6, exponent=2.5, striker=1.0, until=3.0).source
    ref = bc.Scene.from_toml(text)
    for d in ("n=2.5", "[a]", "[x]=y"):
        path = tmp_path / d / "scene.toml"
        path.parent.mkdir()
        path.write_text(text)
        # a pathlib.Path is always a file; so is a str that ends in .toml
        for p in (path, str(path)):
            assert bc.Scene.from_toml(p) == ref
            assert bc.run(p).scene == ref
            assert bc.Simulation(p).scene == ref
        # a str naming an existing file is that file, whatever its name
        other = tmp_path / d / "beads=3"
        other.write_text(text)
        assert bc.Scene.from_toml(str(other)) == ref
        assert bc.run(other).scene == ref
        with pytest.raises(bc.SceneError, match="no such file"):
            bc.run(path.parent / "missing=1.toml")
    monkeypatch.chdir(tmp_path)  # relative: "[a]/scene.toml" starts with "["
    assert bc.Scene.from_toml("[a]/scene.toml") == ref and bc.run("[a]/scene.toml").scene == ref
    # TOML text is still text
    assert bc.Scene.from_toml(text) == ref
    assert bc.Scene.from_toml("[chain]\nbeads = 6\n[run]\nuntil = 3.0").n_beads == 6
