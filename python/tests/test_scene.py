"""Scenes from TOML, presets and Python values: same validator and messages as the CLI."""

import math

import numpy as np
import pytest

import beadchain as bc
from conftest import cli_error

RTOL, ATOL = 1e-12, 0.0


def test_presets_lists_every_builtin_scene():
    names = [n for n, _ in bc.presets()]
    assert "striker" in names and "interface_3.0_2.5" in names
    assert len(names) == len(set(names)) >= 20
    for n in names:
        assert bc.Scene.preset(n).name == n


def test_scene_from_python_values_resolves_the_arrays():
    mass = np.linspace(1.0, 2.0, 1000)
    s = bc.Scene(mass=mass, exponent=2.5, prefactor=1.5, striker=1.0, until=800.0)
    c = s.chain
    assert s.n_beads == 1000 and c.n_beads == 1000
    np.testing.assert_allclose(c.mass, mass, rtol=0, atol=0)  # bit-identical via repr
    np.testing.assert_allclose(c.exponent, np.full(999, 2.5), rtol=0, atol=0)
    np.testing.assert_allclose(c.prefactor, np.full(999, 1.5), rtol=0, atol=0)
    assert c.precompression is None and c.field is None and c.law == "elastic"
    assert s.v0[0] == 1.0 and np.all(s.v0[1:] == 0.0)
    assert s.until == 800.0 and s.units is None and c.units is None and c.radius is None


def test_builders_and_tables_pass_through():
    s = bc.Scene(beads=120, exponent={"base": 3.0, "segments": [{"from": 50, "value": 2.5}]},
                 mass={"base": 1.0, "segments": [{"from": 60, "value": 0.5}]},
                 precompression=0.01, walls={"right": {"exponent": 2.5}}, striker=1.0,
                 until=10.0, every=1.0, rtol=1e-9)
    c = s.chain
    assert list(c.exponent[48:52]) == [3.0, 3.0, 2.5, 2.5]
    assert c.mass[59] == 1.0 and c.mass[60] == 0.5
    np.testing.assert_allclose(c.precompression, np.full(119, 0.01), rtol=RTOL, atol=ATOL)
    assert c.right_wall["exponent"] == 2.5 and c.left_wall is None
    assert s.run_settings["rtol"] == 1e-9 and s.run_settings["every"] == 1.0


def test_from_toml_text_and_path_agree(tmp_path):
    text = "[chain]\nbeads = 30\nexponent = 3.0\n[initial]\nstriker = 0.5\n[run]\nuntil = 5.0\n"
    p = tmp_path / "c30.toml"
    p.write_text(text)
    a, b = bc.Scene.from_toml(text), bc.Scene.from_toml(str(p))
    assert b.name == "c30" and a.name == "scene"
    np.testing.assert_array_equal(a.chain.exponent, b.chain.exponent)
    np.testing.assert_array_equal(a.v0, b.v0)
    c = bc.Scene.from_toml(p)  # pathlib.Path
    assert c.n_beads == 30


def test_bad_mass_message_is_the_clis(cli, tmp_path):
    text = "[chain]\nmass = [1.0, -1.0, 1.0]\n[initial]\nstriker = 1.0\n[run]\nuntil = 10.0\n"
    p = tmp_path / "bad.toml"
    p.write_text(text)
    with pytest.raises(bc.SceneError) as e:
        bc.Scene.from_toml(str(p))
    assert str(e.value) == cli_error(cli, "run", p, "--out", tmp_path / "x.snap")
    assert not (tmp_path / "x.snap").exists()
    assert isinstance(e.value, ValueError)


def test_python_values_get_the_same_message_with_their_name():
    with pytest.raises(bc.SceneError) as e:
        bc.Scene(mass=[1.0, -1.0, 1.0], striker=1.0, until=10.0)
    assert str(e.value) == "scene: [chain].mass: bead 1: mass must be > 0, got -1"
    with pytest.raises(bc.SceneError) as e:
        bc.Scene(name="mine", exponent=[2.5, 0.5], striker=1.0, until=10.0)
    assert str(e.value).startswith("mine: [chain].exponent: contact 1: ")


@pytest.mark.parametrize("kw,key", [
    ({"until": -1.0}, "[run].until"),
    ({"until": float("nan")}, "[run].until"),
    ({"until": 10.0, "rtol": 2.0}, "[run].rtol"),
    ({"until": 10.0, "method": "euler"}, "[run].method"),
])
def test_bad_values_name_their_key(kw, key):
    with pytest.raises(bc.SceneError) as e:
        bc.Scene(beads=10, striker=1.0, **kw)
    assert str(e.value).startswith(f"scene: {key}: ") and "\n" not in str(e.value)


def test_unknown_preset_and_missing_file(cli):
    with pytest.raises(bc.SceneError) as e:
        bc.Scene.preset("no_such_preset")
    assert "no_such_preset" in str(e.value)
    with pytest.raises(bc.SceneError) as e:
        bc.Scene.from_toml("no_such_file.toml")
    assert str(e.value).startswith("no_such_file.toml: ")


def test_unexpected_keyword_is_a_type_error():
    with pytest.raises(TypeError):
        bc.Scene(beads=10, until=1.0, masses=1.0)


def test_physical_scene_units_match_hand_computed_table1_values():
    s = bc.Scene.preset("interface_3.0_2.5")
    u = s.units
    r, rho, y, nu = 4e-3, 7650.0, 2.26e11, 0.3
    m = rho * 4.0 / 3.0 * math.pi * r**3                      # eq. 3 mass
    d = 0.75 * 2.0 * (1.0 - nu**2) / y                         # eq. 4
    a = 2.0 / (5.0 * d) * math.sqrt(r * r / (2.0 * r))         # eq. 3 prefactor
    mu = 10.0 ** math.floor(math.log10(a))
    beta = math.sqrt(m / (mu * 2.5))                           # eq. 10
    # The scales are read from the description (7 significant digits), as the CLI's --units si.
    assert u.mu == pytest.approx(mu, rel=0, abs=0) and u.n0 == 2.5
    assert u.m0 == pytest.approx(m, rel=1e-6, abs=0)
    assert u.beta == pytest.approx(beta, rel=1e-6, abs=0)
    c = s.chain
    np.testing.assert_allclose(c.mass, np.ones(s.n_beads), rtol=1e-14, atol=0)
    np.testing.assert_allclose(c.prefactor, np.full(s.n_beads - 1, a / (mu * 2.5)), rtol=1e-12, atol=0)
    np.testing.assert_allclose(c.mass_si(), np.full(s.n_beads, m), rtol=1e-6, atol=0)
    np.testing.assert_allclose(c.radius, np.full(s.n_beads, r), rtol=0, atol=0)
    # striker_si = 0.11 m/s is stored as 0.11 * beta computer units (docs/scenes.md).
    assert s.v0[0] == pytest.approx(0.11 * beta, rel=1e-6, abs=0)


def test_dimensionless_scene_has_no_si():
    c = bc.Scene.preset("striker").chain
    with pytest.raises(bc.SceneError) as e:
        c.mass_si()
    assert "dimensionless" in str(e.value)


def test_to_toml_round_trips():
    s = bc.Scene.preset("tapered")
    t = bc.Scene.from_toml(s.to_toml(), name="tapered")
    np.testing.assert_allclose(t.chain.mass, s.chain.mass, rtol=0, atol=0)
    np.testing.assert_allclose(t.chain.prefactor, s.chain.prefactor, rtol=0, atol=0)
