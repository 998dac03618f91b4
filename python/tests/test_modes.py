"""``bc.modes`` and ``bc.equilibrium`` (issue 35): closed forms through the Python layer."""

import math

import numpy as np
import pytest

import beadchain as bc

FIXED = """[chain]
beads = 20
precompression = 0.04
[walls]
left = { precompression = 0.04 }
right = { precompression = 0.04 }
[run]
until = 1.0
"""


def test_modes_of_a_chain_between_walls_match_the_closed_form():
    m = bc.modes(bc.Scene.from_toml(FIXED))
    k = 2.5 * 1.5 * math.sqrt(0.04)
    exact = 2 * math.sqrt(k) * np.sin(np.arange(1, 21) * math.pi / 42)
    # abs tol 1e-12 of omega_max
    assert np.max(np.abs(m["omega"] - exact)) <= 1e-12 * exact[-1]
    assert m["shapes"].shape == (20, 20)
    assert m["ends"][0].startswith("fixed")
    assert m["open_contacts"] == []
    w = bc.modes(bc.Scene.from_toml(FIXED), window=(0.0, 0.5))
    assert len(w["omega"]) == int(np.sum(exact <= 0.5))


def test_equilibrium_of_a_gravity_column():
    s = bc.Scene.preset("gravity_column_at_rest")
    e = bc.equilibrium(s)
    mass = np.asarray(s.chain.mass)
    above = np.cumsum(mass[::-1])[::-1][1:]  # mass above contact k (g = 1)
    # rel tol 1e-12
    assert np.max(np.abs(e["contact_force"] - above) / above) <= 1e-12
    assert e["wall_force"][1] is None


def test_an_impossible_balance_raises():
    s = bc.Scene.from_toml("[chain]\nbeads = 3\n[field]\ngravity = 1.0\n[run]\nuntil = 1.0\n")
    with pytest.raises(bc.SceneError, match="no wall holds the chain"):
        bc.equilibrium(s)
