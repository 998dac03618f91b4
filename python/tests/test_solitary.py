"""Exact solitary waves from Python (``solitary=`` keyword, scene dicts and TOML text): the
same parser as the CLI (docs/studies.md)."""

import numpy as np
import pytest

import beadchain as bc


def test_solitary_keyword_places_the_wave_and_it_travels():
    s = bc.Scene(beads=120, exponent=2.5, solitary={"at": 30, "velocity": 1.0},
                 until=40.0, every=0.01)
    v0 = s.v0
    # Peak velocity v_m at the centre bead: absolute 1e-15.
    assert abs(v0[30] - 1.0) < 1e-15 and np.argmax(v0) == 30
    # Beads ahead at rest and unshifted.
    assert np.all(v0[40:] == 0.0) and np.all(s.u0[40:] == 0.0)
    r = bc.run(s, engine="dense", method="dop853", rtol=1e-13, atol=1e-15)
    # Every bead the wave has passed peaked at v_m: frames 0.01 apart (0.013 bead) sample the
    # peak to about 5e-5 (at 0.05 apart the sampled peaks were up to 1.2e-3 low): abs 2e-4.
    peaks = r.v.max(axis=0)
    assert np.all(np.abs(peaks[31:70] - 1.0) < 2e-4), peaks[31:70]
    assert np.argmax(r.v[-1]) > 60


def test_head_on_waves_from_a_list_are_symmetric():
    s = bc.Scene(beads=101, exponent=3.0, until=30.0, every=1.0,
                 solitary=[{"at": 25, "velocity": 0.5},
                           {"at": 75, "velocity": 0.5, "direction": "left"}])
    r = bc.run(s, engine="dense", method="dop853", rtol=1e-12, atol=1e-14)
    # v_k = -v_{N-1-k} at every frame: absolute 1e-12 (v_m = 0.5).
    np.testing.assert_allclose(r.v, -r.v[:, ::-1], rtol=0, atol=1e-12)


def test_refusal_names_the_contact_where_the_chain_changes():
    with pytest.raises(bc.SceneError, match=r"contact 55 \(beads 55-56\) has exponent 3"):
        bc.Scene(beads=100, exponent={"base": 2.5, "segments": [{"from": 55, "value": 3.0}]},
                 solitary={"at": 50, "velocity": 1.0}, until=1.0)


def test_solitary_preset_loads():
    s = bc.Scene.preset("solitary_interface_3.0_2.5")
    assert s.n_beads == 150 and np.argmax(s.v0) == 20
