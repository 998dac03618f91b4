"""`Scene.with_overrides` (issue 36, item 5): the sweep's dotted keys applied by the sweep's own
Rust functions (same key walk, parser, validator and messages), one-line errors naming the key."""

import pickle

import numpy as np
import pytest

import beadchain as bc

KEY = "chain.exponent.segments.0.value"


def test_override_equals_the_edited_toml_and_leaves_the_original_alone():
    base = bc.Scene.preset("interface_3.0_2.5")
    s = base.with_overrides({KEY: 2.4})
    text = base.source.replace("value = 2.5 }", "value = 2.4 }")
    assert text != base.source
    assert s == bc.Scene.from_toml(text)
    assert s.name == base.name and s.n_beads == 150
    assert list(s.chain.exponent[48:52]) == [3.0, 3.0, 2.4, 2.4]   # contacts 50.. (from = 50)
    assert list(base.chain.exponent[48:52]) == [3.0, 3.0, 2.5, 2.5]
    assert s != base
    # the source is the overridden TOML: overrides chain, and Scene.from_toml reads it back
    t = s.with_overrides({"chain.beads": 80, "scene.seed": 7})
    assert (t.n_beads, t.seed, t.chain.exponent[50]) == (80, 7, 2.4)
    assert bc.Scene.from_toml(t.source) == t
    assert s.with_overrides({"scene.name": "other"}).name == "other"


def test_values_of_every_kind_and_numpy_values():
    s = bc.Scene.preset("striker")
    a = s.with_overrides({"chain.beads": np.int64(20), "initial.striker": np.float64(0.5),
                          "chain.mass": np.linspace(1.0, 2.0, 20), "run.method": "dop853",
                          "chain.exponent": {"base": 2.5, "segments": [{"from": 10, "value": 3.0}]}})
    assert a.n_beads == 20 and a.v0[0] == 0.5
    np.testing.assert_array_equal(a.chain.mass, np.linspace(1.0, 2.0, 20))
    assert a.chain.exponent[10] == 3.0 and a.chain.exponent[9] == 2.5
    assert a.run_settings["method"] == "dop853"
    # no override: the same scene
    assert s.with_overrides({}) == s


def test_a_sweep_point_and_the_same_overrides_give_the_same_run(tmp_path):
    # [set] and the grid values of reflection_grid.toml's run 5 (n1 = 3.0, n2 = 3.5), without
    # the sweep's early stop: the same scene, hence the same run bit for bit
    sw = tmp_path / "one.toml"
    sw.write_text('scene = "striker"\n[set]\n"chain.beads" = 20\n"run.until" = 15.0\n'
                  '[grid]\n"chain.exponent" = [3.0]\n"initial.striker" = [0.5]\n')
    row = bc.sweep_run(sw, 0)
    s = bc.Scene.preset("striker").with_overrides(
        {"chain.beads": 20, "run.until": 15.0, "chain.exponent": 3.0, "initial.striker": 0.5})
    r = bc.run(s)
    assert row["status"] == "ok"
    assert row["steps"] == r.stats["steps"] and row["t_end"] == r.t[-1] == 15.0
    e = r.energy()["total"]
    assert row["energy_error"] == pytest.approx(abs(e[-1] - e[0]) / abs(e[0]), rel=1e-12, abs=0)


def _sweep_error(tmp_path, body):
    p = tmp_path / "bad.toml"
    p.write_text('scene = "striker"\n' + body)
    with pytest.raises(bc.SceneError) as e:
        bc.sweep(p)
    return str(e.value)


def test_errors_name_the_key_with_the_sweeps_messages(tmp_path):
    s = bc.Scene.preset("striker")

    def err(ov, exc=bc.SceneError):
        with pytest.raises(exc) as e:
            s.with_overrides(ov)
        msg = str(e.value)
        assert "\n" not in msg and msg.startswith("with_overrides: "), msg
        return msg

    # unknown key: the parser's message, as in a sweep
    m = err({"chain.beadz": 3})
    assert m.startswith("with_overrides: (chain.beadz=3): striker: [chain].beadz: unknown key"), m
    sweep_m = _sweep_error(tmp_path, '[set]\n"chain.beadz" = 3\n')
    assert m.split("[chain].beadz: ", 1)[1] == sweep_m.split("[chain].beadz: ", 1)[1]
    # a key that cannot be written: the sweep's words
    m = err({"chain.exponent.base": 2.5})
    want = "the base scene's `chain.exponent` is a number, not a table"
    assert m == f'with_overrides: "chain.exponent.base": {want}', m
    assert _sweep_error(tmp_path, '[set]\n"chain.exponent.base" = 2.5\n').endswith(want)
    m = err({"chain": 1})
    assert m.startswith('with_overrides: "chain": expected a quoted dotted scene key'), m
    i25 = bc.Scene.preset("interface_3.0_2.5")
    with pytest.raises(bc.SceneError) as e:
        i25.with_overrides({"chain.exponent.segments.3.value": 2.0})
    assert str(e.value) == ('with_overrides: "chain.exponent.segments.3.value": '
                            "`chain.exponent.segments` has 1 entries, index 3 is out of range")
    # an invalid value: the validator's message, naming key and contact
    m = err({"chain.exponent": 0.5})
    assert "[chain].exponent: contact 0: exponent must be > 1" in m, m
    # values that are not TOML values, and keys that are not strings
    m = err({"initial.striker": object()}, TypeError)
    assert '"initial.striker"' in m and "object" in m, m
    m = err({"initial.striker": None}, TypeError)
    assert '"initial.striker"' in m and "None" in m, m
    m = err({1: 2.0}, TypeError)
    assert "keys are dotted scene keys" in m, m
    with pytest.raises(TypeError):
        s.with_overrides([("chain.beads", 3)])


def test_csv_files_resolve_next_to_the_scene_file_and_survive_pickling(tmp_path, monkeypatch):
    (tmp_path / "m.csv").write_text("".join(f"{1.0 + i / 10}\n" for i in range(10)))
    (tmp_path / "c.toml").write_text('[chain]\nmass = { file = "m.csv" }\nexponent = 2.5\n'
                                     '[initial]\nstriker = 1.0\n[run]\nuntil = 5.0\n')
    monkeypatch.chdir(tmp_path.parent)
    s = bc.Scene.from_toml(tmp_path / "c.toml")
    t = s.with_overrides({"initial.striker": 0.5})
    np.testing.assert_array_equal(t.chain.mass, s.chain.mass)
    u = pickle.loads(pickle.dumps(t)).with_overrides({"run.until": 6.0})
    assert u.until == 6.0 and u.v0[0] == 0.5
    np.testing.assert_array_equal(u.chain.mass, 1.0 + np.arange(10) / 10)


def test_a_scene_without_source_starts_from_its_resolved_toml(tmp_path):
    bc.run("striker", out=tmp_path / "x.snap", record=False)
    s = bc.load(tmp_path / "x.snap").scene
    assert s.source is None
    t = s.with_overrides({"run.until": 10.0})
    assert t.until == 10.0 and t.n_beads == 100
    np.testing.assert_array_equal(t.v0, s.v0)


def test_run_scene_carries_the_input_scenes_source(tmp_path, monkeypatch):
    # Run.scene (and Simulation.scene) is the scene that ran: its source, its overrides and
    # from_toml(source) carry the until/every the run's options gave it
    s = bc.Scene(beads=8, exponent=2.5, striker=1.0, until=50.0)
    for ran in (bc.run(s, until=5.0, every=1.0).scene,
                bc.Simulation(s, until=5.0, every=1.0).scene):
        assert ran.until == 5.0 and ran.run_settings["every"] == 1.0
        t = ran.with_overrides({"scene.seed": 3})
        assert t.seed == 3 and t.until == 5.0 and t.run_settings["every"] == 1.0
        assert bc.Scene.from_toml(ran.source) == ran
    assert bc.run(s).scene.source == s.source  # nothing changed: the text as it was
    # a physical scene whose source gives until_si/every_si: the computer-unit values replace them
    phys = bc.Scene.preset("hertz_spheres_physical")
    for ran in (bc.run(phys, until=50.0, every=25.0).scene,
                bc.Simulation(phys, until=50.0).scene,
                bc.Simulation(phys, every_si=1e-5).scene):
        assert bc.Scene.from_toml(ran.source) == ran
        assert ran.with_overrides({"scene.seed": 3}).run_settings == ran.run_settings
    # CSV files still resolve next to the scene file
    (tmp_path / "m.csv").write_text("".join(f"{1.0 + i / 10}\n" for i in range(10)))
    (tmp_path / "c.toml").write_text('[chain]\nmass = { file = "m.csv" }\nexponent = 2.5\n'
                                     '[initial]\nstriker = 1.0\n[run]\nuntil = 5.0\n')
    monkeypatch.chdir(tmp_path.parent)
    ran = bc.run(tmp_path / "c.toml", until=2.0).scene
    t = ran.with_overrides({"initial.striker": 0.5})
    assert t.until == 2.0 and t.v0[0] == 0.5
    np.testing.assert_array_equal(t.chain.mass, 1.0 + np.arange(10) / 10)
