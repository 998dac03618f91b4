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


def test_equilibrium_gaps_are_a_scene_warning():
    # Six beads between walls, the left three pulled left, the right three right: contact 2 is
    # left without force at rest, and Python's Scene reports it as the CLI does.
    text = ("[scene]\nname = \"split\"\n[chain]\nbeads = 6\n[field]\n"
            "force = [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0]\n[walls]\nleft = {}\nright = {}\n"
            "[initial]\nequilibrium = true\n[run]\nuntil = 10.0\nevery = 1.0\n")
    s = bc.Scene.from_toml(text)
    gaps = [w for w in s.warnings if "gaps at rest" in w]
    assert gaps == ["split: [initial].equilibrium: gaps at rest (no force: the beads are apart "
                    "or just touching): contact 2 (beads 2-3)"]
    # a column on its wall under gravity, below a ceiling it does not reach: only the ceiling
    col = bc.Scene.from_toml(
        "[scene]\nname = \"split\"\n[chain]\nbeads = 5\n[field]\ngravity = 1.0\n[walls]\n"
        "left = {}\nright = { precompression = -1.0 }\n[initial]\nequilibrium = true\n"
        "[run]\nuntil = 1.0\n")
    assert [w for w in col.warnings if "gaps at rest" in w] == [
        "split: [initial].equilibrium: gaps at rest (no force: the beads are apart or just "
        "touching): the right wall (bead 4)"]


def test_bands_of_the_dimer_match_the_closed_form_gap():
    # dimer_dispersion: masses 1 and 0.5, n = 2.5, a = 1, every contact at force 0.1, so
    # k = n(n-1) a Δ^(n-2) with Δ = (0.1/2.5)^(1/1.5); acoustic band [0, √(2k/m1)], optical
    # band [√(2k/m2), √(2k(1/m1 + 1/m2))]
    b = bc.bands(bc.Scene.preset("dimer_dispersion"), points=11)
    delta = (0.1 / 2.5) ** (1 / 1.5)
    k = 2.5 * 1.5 * delta ** 0.5
    edges = np.array([[0.0, math.sqrt(2 * k)], [math.sqrt(4 * k), math.sqrt(6 * k)]])
    top = edges[1, 1]
    assert b["omega"].shape == (2, 11) and b["q"].shape == (11,)
    assert list(b["mass"]) == [1.0, 0.5]
    # ω² to abs tol 1e-12 of omega_max² (round-off leaves ω = √ε·ω_max at q = 0), rel tol 0
    assert np.max(np.abs(b["edges"] ** 2 - edges ** 2)) <= 1e-12 * top ** 2
    assert b["gaps"].shape == (1, 2)
    assert np.max(np.abs(b["gaps"][0] - [edges[0, 1], edges[1, 0]])) <= 1e-12 * top
    # the dimer's ω(q) at every sample (monoatomic-cell formula in cos q), same tolerance
    q = b["q"]
    s = 2 * k * (1 / 1.0 + 1 / 0.5)
    disc = np.sqrt(s * s - 8 * k * k * (1 - np.cos(q)) / 0.5)
    exact2 = np.array([(s - disc) / 2, (s + disc) / 2])
    assert np.max(np.abs(b["omega"] ** 2 - exact2)) <= 1e-12 * top ** 2
    with pytest.raises(bc.SceneError, match="a cell of 50 beads from bead 0 needs 50 contacts"):
        bc.bands(bc.Scene.preset("dimer_dispersion"), cell=50)


def test_bins_out_of_range_raise_value_error_not_abort():
    # a huge count aborted the interpreter on allocation; 0 became 1 silently; -1 overflowed
    for bins in (10**15, 0, -1):
        with pytest.raises(ValueError, match=rf"bins = {bins}: expected 1 to 1000000 bins"):
            bc.modes("dimer_dispersion", bins=bins)
    assert len(bc.modes("dimer_dispersion", bins=3)["dos_counts"]) == 3


def test_bands_arguments_out_of_range_raise_value_error_not_abort():
    # points=10**15 aborted the interpreter on allocation; negative cell/start overflowed
    for kw, msg in ((dict(points=10**15), "points: expected 2 to 100000"),
                    (dict(cell=-1), "cell: expected 1 to"),
                    (dict(start=-1), "start: expected 0 to")):
        with pytest.raises(ValueError, match=msg):
            bc.bands("dimer_dispersion", **kw)
    with pytest.raises(bc.SceneError, match=r"first bead 100000 \(start\) is past the last contact"):
        bc.bands("dimer_dispersion", start=100000)
    # the library's advice names Python's keyword
    s = bc.Scene(beads=6, mass=[1.0, 2.0, 3.0, 4.0, 5.0, 6.0], precompression=0.01, until=1.0)
    with pytest.raises(bc.SceneError, match=r"give the cell size \(cell=\)"):
        bc.bands(s)


def test_study_integers_beyond_64_bits_raise_value_error_naming_them():
    # bins=2**70 raised an unnamed OverflowError ("Python int too large to convert to C long")
    for kw in (dict(bins=2**70),):
        with pytest.raises(ValueError, match="bins = "):
            bc.modes("dimer_dispersion", **kw)
    for key in ("points", "cell", "start"):
        with pytest.raises(ValueError, match=f"{key} = "):
            bc.bands("dimer_dispersion", **{key: 2**70})


def test_check_tol_must_be_finite_and_positive():
    # tol=inf made the trajectory bound infinite (a check that cannot fail), as the CLI refuses
    for tol in (float("inf"), float("nan"), -1.0, 0.0):
        with pytest.raises(ValueError, match="tol = "):
            bc.check("striker", until=5.0, tol=tol)
