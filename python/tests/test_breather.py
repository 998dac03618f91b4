"""``bc.breather`` (issue 35, part 4): a gap breather of a precompressed dimer chain through the
Python layer, periodic, with symplectic Floquet multipliers, saved as a runnable scene."""

import numpy as np
import pytest

import beadchain as bc

DIMER = """[chain]
beads = 16
mass = { alternate = [1.0, 0.5] }
precompression_force = 0.1
[walls]
left = {}
right = {}
[initial]
equilibrium = true
[run]
until = 1.0
"""


def test_gap_breather_is_periodic_and_stable():
    d = bc.breather(bc.Scene.from_toml(DIMER), 2.25, step=0.01)
    assert abs(d["frequency"] - 2.25) <= 1e-12
    assert d["mode"] == 8 and d["mode_frequency"] > 2.25
    assert d["residual"] <= 1e-10  # period map, max-norm over u and v
    assert d["amplitude"] > 0.05
    m = d["multipliers"]
    assert m.shape == (32,) and np.iscomplexobj(m)
    assert d["reciprocity_error"] <= 1e-8
    assert max(d["unit_pair_error"]) <= 1e-8
    # the pair at 1's time-shift and energy vectors (a Jordan block: docs/studies.md)
    assert len(d["unit_pair_vectors"]) == 2 and max(d["unit_pair_vectors"]) <= 1e-8
    assert d["stable"] and d["max_modulus"] <= 1 + 1e-6
    s = d["scene"]
    # the saved scene starts from the breather, at rest
    r = bc.run(s, until=d["period"], every=None)
    assert np.max(np.abs(r.u[-1] - d["u"])) <= 1e-10
    assert np.max(np.abs(r.v[-1])) <= 1e-10


def test_breather_collapsed_to_the_equilibrium_raises():
    # above the optical band (top mode 2.772, soft: its branch falls in frequency) the
    # continuation only finds the equilibrium: an error, not a "solution" of amplitude 1e-11
    s = bc.Scene.preset("dimer_dispersion")
    with pytest.raises(bc.SceneError, match=r"dimer_dispersion: the continuation to omega = 2\.8 "
                       r"collapsed to the equilibrium at omega = .* the branch from the linear "
                       r"mode at omega 2\.772158 exists only below it"):
        bc.breather(s, 2.8, floquet=False)
