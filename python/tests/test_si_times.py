"""Issue 32 item 6 (Python part): `until_si`/`every_si` of run() and Simulation, as the CLI's
`--until-si`/`--every-si` (seconds divided by the scene's time unit)."""

import subprocess

import numpy as np
import pytest

import beadchain as bc


def test_until_si_every_si_missing_in_python_matches_cli(cli, tmp_path):
    s = bc.Scene.preset("hertz_spheres_physical")
    path = tmp_path / "c.snap"
    code = subprocess.run(
        [cli, "run", "hertz_spheres_physical", "-q", "--until-si", "1e-4", "--every-si", "1e-5",
         "--out", path], capture_output=True, text=True)
    assert code.returncode == 0, code.stderr
    c = bc.load(path)
    r = bc.run(s, until_si=1e-4, every_si=1e-5)
    assert len(r.t) == 11
    np.testing.assert_array_equal(r.t, c.t)   # same division, same frame times: bit for bit
    np.testing.assert_array_equal(r.u, c.u)
    np.testing.assert_array_equal(r.v, c.v)
    np.testing.assert_allclose(r.t_si[-1], 1e-4, rtol=1e-12, atol=0)
    sim = bc.Simulation(s, until_si=1e-4, every_si=1e-5)
    assert sim.advance().reason == "reached"
    f = sim.frames()
    np.testing.assert_array_equal(f.t, c.t)
    np.testing.assert_array_equal(f.v, c.v)


def test_until_si_every_si_missing_in_python_errors():
    phys = bc.Scene.preset("hertz_spheres_physical")
    with pytest.raises(bc.SceneError) as e:
        bc.run(phys, until=10.0, until_si=1e-4)
    assert str(e.value) == ("hertz_spheres_physical: until_si: give until (computer units) or "
                            "until_si (seconds), not both")
    with pytest.raises(bc.SceneError, match="every_si: give every .* not both"):
        bc.Simulation(phys, every=1.0, every_si=1e-5)
    plain = bc.Scene(beads=5, striker=1.0, until=5.0)
    with pytest.raises(bc.SceneError) as e:
        bc.run(plain, every_si=1e-5)
    assert str(e.value).startswith("scene: every_si: the scene is dimensionless (computer units "
                                   "only); SI times need a physical scene"), str(e.value)


def test_non_positive_si_times_are_refused_as_given():
    """The defect: until_si=-1 was converted first and refused as 'until = -1104091.3… must be
    positive and finite' (computer units, under the plain key); as the CLI's --until-si now."""
    phys = bc.Scene.preset("hertz_spheres_physical")
    for kw, got in ((dict(until_si=-1.0), "-1"), (dict(every_si=0.0), "0"),
                    (dict(until_si=float("nan")), "NaN")):
        key = next(iter(kw))
        with pytest.raises(bc.SceneError) as e:
            bc.run(phys, **kw)
        assert str(e.value) == (f"hertz_spheres_physical: {key}: must be a finite number > 0 "
                                f"(seconds), got {got}")
