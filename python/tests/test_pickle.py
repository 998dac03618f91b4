"""Issue 32 item 10: Scene and Run are picklable and deep-copyable (process pools, joblib,
Dask): a Scene as its resolved scene's exact bytes, a Run as its arrays."""

import concurrent.futures as cf
import copy
import pickle

import numpy as np
import pytest

import beadchain as bc


def same_run(a, b, stats=True):
    np.testing.assert_array_equal(a.t, b.t)
    for x, y in ((a.u, b.u), (a.v, b.v), (a.dissipated, b.dissipated)):
        assert (x is None) == (y is None)
        if x is not None:
            np.testing.assert_array_equal(x, y)
    assert a.events.keys() == b.events.keys()
    for k in a.events:
        np.testing.assert_array_equal(a.events[k], b.events[k])
    if stats:  # the wall time differs between two runs
        drop = ("wall_seconds",)
        assert {k: v for k, v in a.stats.items() if k not in drop} == \
            {k: v for k, v in b.stats.items() if k not in drop}
    assert a.scene == b.scene


SCENES = [
    lambda: bc.Scene.preset("damped_striker"),            # a dissipative contact law
    lambda: bc.Scene.preset("hertz_spheres_physical"),    # units
    lambda: bc.Scene(beads=20, striker=1.0, until=20.0, every=1.0,
                     output={"beads": "0:20:2", "fields": "v"}),
]


@pytest.mark.parametrize("make", SCENES)
def test_scene_and_run_cannot_be_pickled_scene_round_trip(make):
    s = make()
    for back in (pickle.loads(pickle.dumps(s)), copy.deepcopy(s), copy.copy(s)):
        assert back == s
        assert back.to_toml() == s.to_toml()
        assert back.source == s.source
        assert back.warnings == s.warnings
        assert back.chain.law == s.chain.law
        assert back.run_settings == s.run_settings
    assert s != bc.Scene(beads=20, striker=1.0, until=20.0)


def test_scene_and_run_cannot_be_pickled_run_overrides_kept():
    r = bc.run(bc.Scene.preset("damped_striker"), until=30.0, every=3.0)
    assert r.scene.until == 30.0  # the scene as it ran, not its source text
    for back in (pickle.loads(pickle.dumps(r)), copy.deepcopy(r)):
        same_run(back, r)
        assert back.scene.until == 30.0 and back.scene.run_settings["every"] == 3.0


def test_scene_and_run_cannot_be_pickled_loaded_run(tmp_path):
    r = bc.run(bc.Scene.preset("damped_striker"), out=tmp_path / "x.snap")
    loaded = bc.load(tmp_path / "x.snap")
    back = pickle.loads(pickle.dumps(loaded))
    same_run(back, r, stats=False)
    assert back.stats == loaded.stats and back.meta == loaded.meta


def test_scene_and_run_cannot_be_pickled_process_pool():
    s = bc.Scene(beads=30, striker=1.0, until=40.0, every=4.0)
    with cf.ProcessPoolExecutor(max_workers=2) as ex:
        futures = [ex.submit(bc.run, s), ex.submit(bc.run, s, every=8.0)]
        a, b = (f.result(timeout=120) for f in futures)
    same_run(a, bc.run(s))
    same_run(b, bc.run(s, every=8.0))


def test_scene_state_that_no_longer_validates_is_refused_before_any_output(tmp_path):
    """A scene from a snapshot or a pickle written by an older version is not re-validated when
    it is read (the data stays readable), so run(), Simulation and the studies validate it before
    they start: a name with a tab (refused since the control-character check) raised only after
    run() had written its output file."""
    from beadchain._scene import _scene_from_state

    good = bc.Scene(name="tab_here", beads=5, striker=1.0, until=5.0)
    state = bytes(good._s._state())
    assert state.count(b"tab_here") == 1
    bad = _scene_from_state(state.replace(b"tab_here", b"tab\there"), None)
    assert bad.name == "tab\there"
    out = tmp_path / "out.snap"
    with pytest.raises(bc.SceneError, match=r'^tab\\there: \[scene\]\.name: "tab\\there" is not'):
        bc.run(bad, out=out)
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(bc.SceneError, match=r"\[scene\]\.name"):
        bc.Simulation(bad)
    # a bad option is still named as the option, not as the scene's key it overrides
    for kw, msg in ((dict(until=-1.0), "until = -1 must be positive and finite"),
                    (dict(every=-2.0), "every = -2 must be positive and finite")):
        with pytest.raises(bc.SceneError) as e:
            bc.run(good, **kw)
        assert str(e.value) == f"tab_here: invalid run configuration: {msg}"
