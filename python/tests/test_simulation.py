"""Simulation: advance in pieces, state, set_velocities, observers."""

import numpy as np
import pytest

import beadchain as bc


def test_advancing_in_pieces_gives_the_frames_of_one_run():
    scene = bc.Scene.preset("striker")
    whole = bc.run(scene, every=5.0)
    sim = bc.Simulation(scene, every=5.0)
    assert sim.advance(33.0) == bc.Stop("reached", 33.0)
    assert sim.time == 33.0
    assert sim.advance() == bc.Stop("reached", 100.0)
    r = sim.frames()
    np.testing.assert_array_equal(r.t, whole.t)
    np.testing.assert_array_equal(r.u, whole.u)
    np.testing.assert_array_equal(r.v, whole.v)
    for k in whole.events:
        np.testing.assert_array_equal(r.events[k], whole.events[k])


def test_state_and_set_velocities():
    scene = bc.Scene(beads=50, striker=1.0, until=200.0, every=10.0)
    sim = bc.Simulation(scene)
    sim.advance(20.0)
    st = sim.state
    assert st.t == 20.0 and st.u.shape == (50,) and st.v.shape == (50,)
    # momentum is carried by the wave
    assert st.v.sum() == pytest.approx(1.0, rel=1e-9, abs=0)
    v = st.v.copy()
    v[49] = -0.5  # a second striker from the right end
    sim.set_velocities(v)
    # to rounding: a cluster holds its beads' velocities in its centre-of-mass frame, v - v_cm,
    # and adds v_cm back on reading (1 ulp at bead 23 here; was exact equality, which held only
    # where no cluster's frame rounded)
    np.testing.assert_allclose(sim.state.v, v, rtol=0, atol=4 * np.spacing(np.abs(v).max()))
    sim.advance()
    assert sim.stats()["momentum_final"] == pytest.approx(0.5, rel=1e-9, abs=1e-12)
    f = sim.frames()
    assert f.t[0] == 0.0 and f.t[-1] == 200.0 and len(f.t) == 21


def test_set_velocities_checks_its_input():
    """A 1-D array of the wrong length is an array of another shape: TypeError naming the
    shape, as documented (it was SceneError, while shape (1, 10) gave TypeError)."""
    sim = bc.Simulation(bc.Scene(beads=10, striker=1.0, until=5.0))
    with pytest.raises(TypeError) as e:
        sim.set_velocities(np.zeros(9))
    assert str(e.value) == ("scene: set_velocities: v: expected an array of shape (10,) (one "
                            "velocity per bead), got shape (9,)")
    v = np.zeros(10)
    v[3] = np.nan
    with pytest.raises(bc.SceneError) as e:
        sim.set_velocities(v)
    assert "bead 3: velocity must be finite" in str(e.value)


def test_set_velocities_refuses_an_energy_that_overflows():
    """The defect: velocities of 1e155 were taken (their kinetic energy overflows f64), which
    Scene(velocity=...) refuses; stats() then gave an infinite energy and a NaN error, and the
    injected energy stayed infinite for the rest of the simulation."""
    sim = bc.Simulation(bc.Scene(beads=10, striker=1.0, until=30.0, every=5.0))
    sim.advance(5.0)
    before = sim.state
    with pytest.raises(bc.SceneError) as e:
        sim.set_velocities(np.full(10, 1e155))
    assert "kinetic energy overflows f64" in str(e.value), str(e.value)
    np.testing.assert_array_equal(sim.state.v, before.v)
    sim.set_velocities(before.v)
    assert np.isfinite(sim.stats()["energy_injected"])


def test_observers_see_frames_not_steps():
    seen = []
    sim = bc.Simulation(bc.Scene.preset("striker"), every=20.0,
                        observers=[lambda t, u, v: seen.append(t)])
    sim.advance(50.0)
    sim.add_observer(lambda t, u, v: seen.append(-t))
    sim.advance()
    assert seen == [0.0, 20.0, 40.0, 60.0, -60.0, 80.0, -80.0, 100.0, -100.0]
    assert sim.stats()["steps"] > 100  # many steps, few calls


def test_advance_beyond_the_end_is_refused():
    sim = bc.Simulation(bc.Scene(beads=10, striker=1.0, until=5.0))
    with pytest.raises(bc.SceneError) as e:
        sim.advance(6.0)
    assert "beyond the run's end time 5" in str(e.value)


def test_pausing_at_every_frame_and_event_changes_nothing():
    scene = bc.Scene.preset("striker")
    whole = bc.run(scene, every=5.0)
    sim = bc.Simulation(scene, every=5.0)
    sim.pause_at(frames=True, events=True)
    frames, events = [], []
    while True:
        stop = sim.advance()
        if stop.reason == "frame":
            assert sim.time == stop.t and stop.event is None
            frames.append(stop.t)
        elif stop.reason == "event":
            events.append(stop.event)
        else:
            assert stop == bc.Stop("reached", 100.0)
            break
    np.testing.assert_array_equal(frames, whole.t)
    r = sim.frames()
    np.testing.assert_array_equal(r.u, whole.u)
    np.testing.assert_array_equal(r.v, whole.v)
    # every logged event came back once, in order, as the log holds it
    assert len(events) == len(whole.events["t"]) > 100
    for k in ("t", "contact", "rel_velocity", "peak_overlap"):
        np.testing.assert_array_equal([e[k] for e in events], whole.events[k])
    assert [e["kind"] for e in events] == list(whole.events["kind"])


def test_bad_advance_argument_leaves_the_simulation_failed():
    # a refused target (NaN, not finite, beyond the end, before the clock) is a ValueError
    # naming it and the valid range; it changes nothing, and a later valid advance works
    scene = bc.Scene(beads=10, exponent=2.5, striker=1.0, until=30.0)
    sim = bc.Simulation(scene)
    sim.advance(5.0)
    for bad in (31.0, float("nan")):
        with pytest.raises(ValueError):
            sim.advance(bad)
        assert sim.advance(5.0) == bc.Stop("reached", 5.0)  # not failed: it goes on
    for bad, why in ((31.0, "until = 31 is beyond the run's end time 30"),
                     (float("nan"), "until = nan is not a number"),
                     (float("inf"), "until = inf is not finite"),
                     (float("-inf"), "until = -inf is not finite"),
                     (4.0, "until = 4 is before the engine clock t = 5"),
                     (-1.0, "until = -1 is before the engine clock t = 5")):
        with pytest.raises(ValueError) as e:
            sim.advance(bad)
        msg = str(e.value)
        assert isinstance(e.value, bc.SceneError) and "\n" not in msg, msg
        assert msg.startswith(f"scene: advance: {why}"), msg
        assert msg.endswith("expected a time from t = 5 (the engine clock) to 30 (the run's "
                            "end time)"), msg
        assert sim.time == 5.0
    # advancing to the clock itself returns at once (the default after the end does too)
    assert sim.advance(5.0) == bc.Stop("reached", 5.0)
    assert sim.advance(np.float64(10.0)) == bc.Stop("reached", 10.0)
    ref = bc.Simulation(scene)
    ref.advance(10.0)
    np.testing.assert_array_equal(sim.state.u, ref.state.u)
    np.testing.assert_array_equal(sim.state.v, ref.state.v)
    assert sim.advance() == bc.Stop("reached", 30.0) and sim.advance() == bc.Stop("reached", 30.0)
    fresh = bc.Simulation(scene)
    with pytest.raises(ValueError, match=r"^scene: advance: until = -1 is before the engine "
                                         r"clock t = 0 "):
        fresh.advance(-1.0)
    assert fresh.advance(1.0) == bc.Stop("reached", 1.0)


def test_set_velocities_misleading_message_or_no_error():
    sim = bc.Simulation(bc.Scene(beads=10, exponent=2.5, striker=1.0, until=30.0))
    sim.advance(2.0)
    before = sim.state
    v = before.v.copy()
    with pytest.raises(TypeError) as e:
        sim.set_velocities(v.reshape(1, -1))
    msg = str(e.value)
    assert msg == ("scene: set_velocities: v: expected an array of shape (10,) (one velocity per "
                   "bead), got shape (1, 10)"), msg
    for bad, dtype in ((v + 1j, "complex128"), (v > 0, "bool"),
                       (np.array(["0"] * 10), "<U1"), (np.array([None] * 10), "object")):
        with pytest.raises(TypeError) as e:
            sim.set_velocities(bad)
        assert str(e.value) == ("scene: set_velocities: v: expected real numbers (an array of "
                                f"shape (10,)), got dtype {dtype}"), str(e.value)
    # the same dtypes Scene(...) refuses
    for bad in (v + 1j, v > 0):
        with pytest.raises((TypeError, ValueError)):
            bc.Scene(beads=10, exponent=2.5, velocity=bad, until=30.0)
    np.testing.assert_array_equal(sim.state.v, before.v)  # nothing was set
    sim.set_velocities(list(v))          # a list of floats, ints: as before
    sim.set_velocities(np.zeros(10, dtype=np.int32))
    assert np.all(sim.state.v == 0.0)
