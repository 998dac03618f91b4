"""``bc.modal_energies`` (issue 35, part 3): the energy per linear mode of a run's frames, from
a :class:`Run` or a snapshot file; Parseval's identity; a run of another chain is refused."""

import numpy as np
import pytest

import beadchain as bc

SINGLE_MODE = """[chain]
beads = 16
mass = { alternate = [1.0, 0.5] }
precompression_force = 0.1
[walls]
left = {}
right = {}
[initial]
equilibrium = true
mode = { index = 5, amplitude = 1e-7 }
[run]
until = 40.0
every = 0.25
engine = "dense"
method = "dop853"
rtol = 1e-12
atol = 1e-20
"""


def test_a_single_mode_run_stays_in_its_mode(tmp_path):
    s = bc.Scene.from_toml(SINGLE_MODE)
    r = bc.run(s, out=str(tmp_path / "r.snap"))
    d = bc.modal_energies(s, r)
    e = d["energy"]
    assert e.shape == (161, 16) and d["t"].shape == (161,)
    assert list(d["index"]) == list(range(16))
    # other modes: abs tol 0, rel tol 1e-9 of E_5; E_5 constant: abs tol 0, rel tol 1e-8
    # (measured 3.5e-13 and 4e-11)
    assert np.all(np.delete(e, 5, axis=1).max(axis=1) <= 1e-9 * e[:, 5])
    assert np.max(np.abs(e[:, 5] - e[0, 5])) <= 1e-8 * e[0, 5]
    # Parseval: abs tol 0, rel tol 1e-12
    assert np.max(np.abs(e.sum(axis=1) - d["harmonic"]) / d["harmonic"]) <= 1e-12
    # the snapshot file gives the same numbers, bit for bit
    f = bc.modal_energies(s, str(tmp_path / "r.snap"))
    assert np.array_equal(f["energy"], e) and np.array_equal(f["total"], d["total"])


def test_a_run_of_another_chain_is_refused(tmp_path):
    s = bc.Scene.from_toml(SINGLE_MODE)
    short = bc.Scene.from_toml(SINGLE_MODE.replace("beads = 16", "beads = 12"))
    path = tmp_path / "short.snap"
    r = bc.run(short, out=str(path))
    with pytest.raises(bc.SceneError, match=r"short\.snap: the run has 12 beads, the chain of "
                                            r"the modes 16"):
        bc.modal_energies(s, str(path))
    with pytest.raises(bc.SceneError, match="the run has 12 beads"):
        bc.modal_energies(s, r)
