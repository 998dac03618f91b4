"""run(), load(), energies, events, stats; identical numbers to the CLI's snapshot files."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import beadchain as bc
from conftest import cli_error, run_cli


@pytest.fixture(scope="module")
def striker_run():
    return bc.run(bc.Scene.preset("striker"), every=10.0)


def test_run_returns_frames_as_arrays(striker_run):
    r = striker_run
    assert r.t.shape == (11,) and r.u.shape == (11, 100) and r.v.shape == (11, 100)
    np.testing.assert_allclose(r.t, np.arange(11) * 10.0, rtol=0, atol=0)
    np.testing.assert_array_equal(r.u[0], r.scene.u0)
    np.testing.assert_array_equal(r.v[0], r.scene.v0)
    assert r.u.dtype == np.float64 and r.u.flags.c_contiguous
    # The (F, N) arrays are views of the one buffer the frames were collected into.
    assert r.u.base is not None and r.u.base.shape == (1100,)


def test_energy_per_frame_is_conserved(striker_run):
    e = striker_run.energy()
    assert set(e) == {"kinetic", "potential", "total"}
    np.testing.assert_allclose(e["total"], np.full(11, 0.5), rtol=1e-7, atol=0)
    np.testing.assert_allclose(e["kinetic"] + e["potential"], e["total"], rtol=1e-15, atol=0)
    assert e["kinetic"][0] == pytest.approx(0.5, rel=0, abs=0)
    assert e["potential"][0] == pytest.approx(0.0, rel=0, abs=0)
    s = striker_run.stats
    assert s["relative_energy_error"] < 1e-7 and s["t_end"] == 100.0
    assert s["momentum_final"] == pytest.approx(1.0, rel=1e-9, abs=0)


def test_events_are_dataframe_ready_columns(striker_run):
    ev = striker_run.events
    assert set(ev) == {"t", "contact", "kind", "rel_velocity", "peak_overlap"}
    n = len(ev["t"])
    assert n > 90 and all(len(ev[k]) == n for k in ev)
    assert set(ev["kind"]) <= {"close", "open", "hard_collision", "wall_close", "wall_open"}
    assert np.all(np.diff(ev["t"]) >= 0)
    assert sum(striker_run.stats["events_by_kind"].values()) == n
    # closings at tolerance-level speeds (a loose --atol): none at the default tolerances
    assert striker_run.stats["slow_closings"] == 0


def test_cli_snapshot_reads_back_with_identical_numbers(cli, tmp_path, striker_run):
    code, out, err = run_cli(cli, "run", "striker", "--every", "10", "--out", "s.snap", cwd=tmp_path)
    assert code == 0, err
    r = bc.load(tmp_path / "s.snap")
    np.testing.assert_array_equal(r.t, striker_run.t)
    np.testing.assert_array_equal(r.u, striker_run.u)  # bit for bit
    np.testing.assert_array_equal(r.v, striker_run.v)
    for k in striker_run.events:
        np.testing.assert_array_equal(r.events[k], striker_run.events[k])
    assert r.meta["complete"] and r.meta["engine"] == "hybrid"
    assert r.stats["energy_final"] == striker_run.stats["energy_final"]


def test_out_writes_the_clis_snapshot(cli, tmp_path, striker_run):
    p = tmp_path / "py.snap"
    r = bc.run(bc.Scene.preset("striker"), every=10.0, out=p, record=False)
    assert r.t.shape == (0,) and p.exists()
    code, text, err = run_cli(cli, "inspect", p)
    assert code == 0 and "11" in text, err
    back = bc.load(p)
    np.testing.assert_array_equal(back.u, striker_run.u)
    np.testing.assert_array_equal(back.v, striker_run.v)
    assert back.meta["created_by"].startswith("python: beadchain.run(")


def test_bad_run_option_message_is_the_clis(cli, tmp_path):
    with pytest.raises(bc.SceneError) as e:
        bc.run(bc.Scene.preset("striker"), rtol=2.0)
    assert str(e.value) == cli_error(cli, "run", "striker", "--rtol", "2", cwd=tmp_path)
    with pytest.raises(bc.SceneError) as e:
        bc.run(bc.Scene.preset("striker"), engine="fast")
    assert str(e.value) == 'engine: expected "hybrid" or "dense", got "fast"'


def test_failed_run_leaves_no_output(tmp_path):
    p = tmp_path / "x.snap"
    with pytest.raises(bc.RunError) as e:
        bc.run(bc.Scene.preset("striker"), out=p, max_steps=10)
    assert "striker: run failed" in str(e.value)
    assert os.listdir(tmp_path) == []


def test_dense_engine_agrees_with_hybrid(striker_run):
    d = bc.run(bc.Scene.preset("striker"), engine="dense", every=10.0)
    np.testing.assert_allclose(d.v, striker_run.v, rtol=0, atol=1e-5)
    assert len(d.events["t"]) == 0


def test_observers_are_called_at_frames():
    seen = []
    bc.run(bc.Scene.preset("striker"), every=25.0, observers=[lambda t, u, v: seen.append((t, v[0]))])
    assert [t for t, _ in seen] == [0.0, 25.0, 50.0, 75.0, 100.0] and seen[0][1] == 1.0


def test_observer_exception_propagates():
    def boom(t, u, v):
        if t > 0:
            raise RuntimeError("stop here")
    with pytest.raises(RuntimeError, match="stop here"):
        bc.run(bc.Scene.preset("striker"), every=10.0, observers=[boom])


def _long_scene():
    return bc.Scene(beads=200_000, striker=1.0, until=2.0e5)


def test_gil_is_released_while_the_engine_runs():
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)
            time.sleep(0.005)

    th = threading.Thread(target=count)
    th.start()
    try:
        bc.run(bc.Scene(beads=20_000, striker=1.0, until=2.0e4), record=False)
    finally:
        done.set()
        th.join()
    assert len(ticks) > 5


def test_ctrl_c_stops_a_run_cleanly(tmp_path):
    p = tmp_path / "long.snap"
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    t0 = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        bc.run(_long_scene(), out=p, record=False)
    elapsed = time.monotonic() - t0
    timer.cancel()
    assert elapsed < 3.0, elapsed  # the whole run takes far longer
    assert os.listdir(tmp_path) == []  # neither the output nor its temporary


def test_load_rejects_a_non_snapshot(tmp_path):
    p = tmp_path / "x.snap"
    p.write_bytes(b"not a snapshot at all")
    with pytest.raises(bc.SnapshotError) as e:
        bc.load(p)
    assert "not a beadchain snapshot" in str(e.value) and isinstance(e.value, OSError)


def test_dissipative_run_reports_dissipated_energy():
    s = bc.Scene(beads=20, striker=1.0, until=40.0, every=1.0, law="linear_dashpot", damping=0.05)
    r = bc.run(s)
    e = r.energy()
    assert e["dissipated"][-1] > 0.0 and e["dissipated"][0] == 0.0
    np.testing.assert_allclose(e["balance"], np.full(len(r.t), 0.5), rtol=1e-6, atol=0)


def test_help_states_the_defaults():
    doc = bc.run.__doc__
    for s in ('"hybrid"`` (default)', '"auto"`` (default)', "1e-8", "rtol/1e4", "first and last frame"):
        assert s in doc, s


def test_load_reads_an_output_selection(cli, tmp_path, striker_run):
    code, _, err = run_cli(cli, "run", "striker", "--every", "10", "--beads", "0:100:10",
                           "--fields", "v", "--out", "sel.snap", cwd=tmp_path)
    assert code == 0, err
    r = bc.load(tmp_path / "sel.snap")
    assert list(r.beads) == list(range(0, 100, 10)) and r.u is None
    np.testing.assert_array_equal(r.v, striker_run.v[:, ::10])
    with pytest.raises(bc.SceneError):
        r.energy()


def test_load_opens_without_reading_frames_and_reads_selected_ones(tmp_path, striker_run):
    p = tmp_path / "s.snap"
    bc.run(bc.Scene.preset("striker"), every=10.0, out=p, record=False)
    r = bc.load(p)
    assert r._u is bc._run._UNREAD  # nothing read yet
    np.testing.assert_array_equal(r.t, striker_run.t)
    t, u, v = r.frames(-1)
    assert t == 100.0 and u.shape == (100,)
    np.testing.assert_array_equal(v, striker_run.v[-1])
    t, u, v = r.frames([0, 5])
    np.testing.assert_array_equal(u, striker_run.u[[0, 5]])
    np.testing.assert_array_equal(r.v, striker_run.v)  # now everything
    np.testing.assert_array_equal(r.frames(slice(2, 4))[2], striker_run.v[2:4])


def test_snapshots_store_the_dissipated_energy(cli, tmp_path):
    """Format-4 frames carry E_d: a file written by the CLI and one written by run(out=...) give
    the same E_d as the run itself (bit for bit); conservative scenes give None."""
    s = bc.Scene(beads=20, striker=1.0, until=40.0, every=1.0, law="linear_dashpot", damping=0.05)
    r = bc.run(s, out=tmp_path / "py.snap")
    from_py = bc.load(tmp_path / "py.snap")
    np.testing.assert_array_equal(from_py.dissipated, r.dissipated)
    code, _, err = run_cli(cli, "run", "damped_striker", "--every", "10", "--out", "d.snap",
                           cwd=tmp_path)
    assert code == 0, err
    d = bc.load(tmp_path / "d.snap")
    e = d.energy()
    assert e["dissipated"][0] == 0.0 and e["dissipated"][-1] > 0.05 * e["total"][0]
    # E + E_d is conserved: rtol 1e-6 (default tolerances), atol 0
    np.testing.assert_allclose(e["balance"], np.full(len(d.t), e["total"][0]), rtol=1e-6, atol=0)
    assert bc.load(tmp_path / "d.snap").dissipated is not None  # without reading u, v first
    bc.run(bc.Scene.preset("striker"), until=10.0, out=tmp_path / "c.snap", record=False)
    assert bc.load(tmp_path / "c.snap").dissipated is None


def test_hard_collision_losses_are_dissipated_energy(tmp_path):
    # Newton's cradle with inelastic hard contacts (e = 0.5): every collision loses energy,
    # and E + E_d stays E0 (abs 1e-12, rel 1e-9) in memory and in the snapshot file.
    scene = bc.Scene(beads=4, striker=1.0, until=20.0, every=1.0, hard={"contacts": "all", "restitution": 0.5})
    out = tmp_path / "h.snap"
    r = bc.run(scene, out=out)
    for run in (r, bc.load(out)):
        e = run.energy()
        assert run.dissipated is not None and run.dissipated[-1] > 0.1 * e["total"][0]
        np.testing.assert_allclose(e["total"] + run.dissipated, e["total"][0],
                                   rtol=1e-9, atol=1e-12)


def test_wrong_exception_types_negative_counts():
    s = bc.Scene(beads=10, exponent=2.5, striker=1.0, until=5.0, every=1.0)
    for key in ("max_steps", "max_output_bytes"):
        with pytest.raises(ValueError, match=rf"^{key} = -1 must be >= 0$"):
            bc.run(s, **{key: -1})
        with pytest.raises(ValueError, match=rf"^{key} = {2**64} must be below 2\*\*64$"):
            bc.run(s, **{key: 2**64})
        with pytest.raises(ValueError, match=rf"^{key} = 1\.5 must be a whole number >= 0$"):
            bc.run(s, **{key: 1.5})
        for bad in ("10", True, [1]):
            with pytest.raises(TypeError, match=rf"^{key}: expected an integer, got "):
                bc.run(s, **{key: bad})
    # a whole float is its integer (max_output_bytes=1e6), a NumPy integer or 0-d array too
    ref = bc.run(s)
    for limit in (1e6, np.int64(10**6), np.array(10**6), np.float32(1e6)):
        np.testing.assert_array_equal(bc.run(s, max_output_bytes=limit).v, ref.v)
    with pytest.raises(bc.SceneError, match="above the limit of"):
        bc.run(s, max_output_bytes=1e2)
    with pytest.raises(bc.RunError):
        bc.run(s, max_steps=2.0)


def test_dense_engine_on_hard_walls_message_names_cli_flag():
    # the refusal names Python's keywords (engine="hybrid"), never the CLI's flags
    hard = {"right": {"hard": True, "restitution": 0.8}}
    s = bc.Scene(beads=5, striker=1.0, walls=hard, engine="dense", until=5.0)
    for f in (bc.run, bc.Simulation):
        with pytest.raises(bc.SceneError) as e:
            f(s)
        assert str(e.value) == (
            'scene: [run].engine: "dense" cannot run this scene: it declares hard contacts or '
            'walls, which only the hybrid engine handles (set engine = "hybrid" in the scene, '
            'or pass engine="hybrid")')
    assert bc.run(s, engine="hybrid").stats["t_end"] == 5.0
    s = bc.Scene(beads=5, striker=1.0, walls=hard, until=5.0)
    with pytest.raises(bc.SceneError) as e:
        bc.run(s, engine="dense")
    assert str(e.value) == (
        'scene: engine="dense" cannot run this scene: it declares hard contacts or walls, which '
        'only the hybrid engine handles; pass engine="hybrid"')
    damped = bc.Scene(beads=5, striker=1.0, law="viscoelastic", damping=0.1, until=5.0)
    for kw, want in (({}, '[run].method: "verlet"'), ({"method": "verlet"}, 'method="verlet"')):
        scene = damped.with_overrides({"run.method": "verlet"}) if not kw else damped
        with pytest.raises(bc.SceneError) as e:
            bc.run(scene, **kw)
        msg = str(e.value)
        assert want in msg and "--" not in msg and "radau5" in msg, msg
