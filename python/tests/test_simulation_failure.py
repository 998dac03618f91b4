"""Issue 32 item 9: after an engine failure a Simulation stays failed (it raised, then a second
advance() returned Stop('reached') with NaN frames) until a valid state is set."""

import numpy as np
import pytest

import beadchain as bc


def failing():
    # A bead hitting a wall whose damping time is 1e25 at t = 0.5: its contact relaxes far below
    # one ulp of t there, so both engines stop ("step size too small"). (Three beads with
    # damping 1e30 were used until the hybrid engine learnt to integrate overdamped contacts
    # between beads, issue 32 item 13: they now stick, as in the dense engine.)
    return bc.Simulation(bc.Scene(beads=2, law="viscoelastic", damping=1e-3, precompression=-0.5,
                                  velocity=[0.0, 1.0],
                                  walls={"right": {"precompression": -0.5, "damping": 1e25}},
                                  until=10.0, every=1.0))


def test_advance_after_error_returns_garbage():
    sim = failing()
    with pytest.raises(bc.RunError, match="step size .* too small"):
        sim.advance()
    t_fail = sim.time
    with pytest.raises(bc.RunError) as e:
        sim.advance()
    msg = str(e.value)
    assert "\n" not in msg
    assert msg.startswith(f"scene: advance: the simulation failed at t = "), msg
    assert "stays failed" in msg and "set_velocities(v)" in msg, msg
    with pytest.raises(bc.RunError, match="stays failed"):
        sim.advance(5.0)  # and again: no silent recovery
    assert sim.time == t_fail
    f = sim.frames()
    assert np.all(np.isfinite(f.u)) and np.all(np.isfinite(f.v))
    assert np.all(np.isfinite(sim.state.u)) and np.all(np.isfinite(sim.state.v))


def test_advance_after_error_recovers_after_set_velocities():
    sim = failing()
    with pytest.raises(bc.RunError):
        sim.advance()
    sim.set_velocities(np.zeros(2))  # nothing moves: a valid state the engine can go on from
    stop = sim.advance()
    assert stop.reason == "reached" and stop.t == 10.0
    f = sim.frames()
    assert np.all(np.isfinite(f.u)) and np.all(np.isfinite(f.v))
    assert f.t[-1] == 10.0
