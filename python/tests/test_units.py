"""SI units of physical scenes, against conversions computed by hand (paper eqs. 3-4, 10)."""

import math

import numpy as np
import pytest

import beadchain as bc

R, RHO, Y, NU = 4e-3, 7650.0, 2.26e11, 0.3


def beta_by_hand(n0=2.5):
    m = RHO * 4.0 / 3.0 * math.pi * R**3
    d = 0.75 * 2.0 * (1.0 - NU**2) / Y
    a = 2.0 / (5.0 * d) * math.sqrt(R / 2.0)
    mu = 10.0 ** math.floor(math.log10(a))
    return m, math.sqrt(m / (mu * n0))


@pytest.fixture(scope="module")
def phys():
    return bc.run(bc.Scene.preset("hertz_spheres_physical"), every=200.0, until=1000.0)


def test_si_arrays(phys):
    # rtol 1e-12: format 4 and Scene.units keep beta in full (before: 7 digits, rtol 1e-6)
    m0, beta = beta_by_hand()
    np.testing.assert_allclose(phys.t_si, phys.t * beta, rtol=1e-12, atol=0)
    np.testing.assert_allclose(phys.v_si, phys.v / beta, rtol=1e-12, atol=0)
    np.testing.assert_array_equal(phys.u_si, phys.u)  # metres in both systems
    # the striker was given as striker_si = 0.11 m/s
    assert phys.v_si[0, 0] == pytest.approx(0.11, rel=1e-12, abs=0)
    assert phys.t_si[-1] == pytest.approx(1000.0 * beta, rel=1e-12, abs=0)


def test_si_energy(phys):
    m0, beta = beta_by_hand()
    e, es = phys.energy(), phys.energy(units="si")
    np.testing.assert_allclose(es["total"], e["total"] * m0 / beta**2, rtol=1e-12, atol=0)
    # kinetic energy of the striker at t = 0: 1/2 m v^2 with v = 0.11 m/s
    assert es["kinetic"][0] == pytest.approx(0.5 * m0 * 0.11**2, rel=1e-12, abs=0)
    assert phys.energy_si()["total"][0] == es["total"][0]


def test_dimensionless_scene_raises_a_clear_error():
    r = bc.run(bc.Scene(beads=10, striker=1.0, until=5.0))
    for what in ("t_si", "u_si", "v_si"):
        with pytest.raises(bc.SceneError) as e:
            getattr(r, what)
        assert str(e.value).startswith(f"scene: {what}: the scene is dimensionless")
    with pytest.raises(bc.SceneError):
        r.energy(units="si")
    with pytest.raises(ValueError):
        r.energy(units="furlongs")


def test_si_force_keys_reach_python():
    # [chain] precompression_force_si (N) through the shared parser: every contact carries
    # F beta^2/m0 in computer units (rtol 1e-12), F newtons back in SI; the chain is the one
    # precompression_force = F beta^2/m0 gives, bit for bit.
    steel = ('[units]\nsystem = "physical"\nradius = 4.0e-3\nyoung = 2.26e11\npoisson = 0.3\n'
             "density = 7650.0\n")
    body = ("[chain]\nbeads = 10\nexponent = 2.5\n{key}\n[walls]\nleft = {{}}\nright = {{}}\n"
            "[initial]\nequilibrium = true\n[run]\nuntil = 1.0\n")
    f_si = 5.0
    s = bc.Scene.from_toml(steel + body.format(key=f"precompression_force_si = {f_si!r}"))
    units = s.chain.units
    want = f_si * units.beta**2 / units.m0
    c = s.chain
    force = c.exponent * c.prefactor * c.precompression ** (c.exponent - 1.0)
    np.testing.assert_allclose(force, want, rtol=1e-12, atol=0)
    np.testing.assert_allclose(force * units.m0 / units.beta**2, f_si, rtol=1e-12, atol=0)
    plain = bc.Scene.from_toml(steel + body.format(key=f"precompression_force = {want!r}"))
    assert np.array_equal(plain.chain.precompression, c.precompression)
    with pytest.raises(bc.SceneError, match="precompression_force_si"):
        bc.Scene.from_toml(body.format(key="precompression_force_si = 1.0"))


def test_si_of_a_field_not_stored_is_none():
    # Run.u_si / Run.v_si are None where Run.u / Run.v are (an [output] selection of fields)
    s = bc.Scene.preset("hertz_spheres_physical")
    beta = s.units.beta
    r = bc.run(s.with_overrides({"output.fields": "v"}), until=100.0, every=50.0)
    assert r.u is None and r.u_si is None
    np.testing.assert_array_equal(r.v_si, r.v / beta)
    r = bc.run(s.with_overrides({"output.fields": "u"}), until=100.0, every=50.0)
    assert r.v is None and r.v_si is None
    np.testing.assert_array_equal(r.u_si, r.u)
    # a dimensionless scene still raises, stored or not
    d = bc.run(bc.Scene(beads=5, striker=1.0, until=2.0, output={"fields": "v"}))
    with pytest.raises(bc.SceneError, match="dimensionless"):
        d.u_si
