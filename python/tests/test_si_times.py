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


def test_output_refusals_name_the_times_as_given():
    """The defect: run()'s frame-cap and output-size refusals showed until_si=1e-4 and every_si=
    as 'until = 110.4…, every = 11.04…' (computer units under the plain keys), which a
    physicist who gave seconds cannot recognise; as the CLI's refusals now, they are named as
    given, in seconds then computer units."""
    phys = bc.Scene.preset("hertz_spheres_physical")
    beta = 1e-4 / 110.40913187338107  # the scene's time unit (s), as the CLI prints it
    with pytest.raises(bc.SceneError) as e:
        bc.run(phys.with_overrides({"output.frames_max": 3}), until_si=1e-4, every_si=1e-5)
    msg = str(e.value)
    assert "(until_si = 1.0000e-4 s = 110.40913187338107 computer units, every_si = 1.0000e-5 s = " \
        "11.040913187338107 computer units), more than frames_max 3; use every=55.2" in msg, msg
    assert msg.endswith("use every=55.204565936690535 (every_si=5.0000e-5) or larger, or raise "
                        "output frames_max"), msg
    with pytest.raises(bc.SceneError) as e:
        bc.run(phys, until_si=1e-4, every_si=1e-8, max_output_bytes=1000)
    msg = str(e.value)
    assert "frames of " in msg and ": until_si = 1.0000e-4 s = 110.40913187338107 computer units, " \
        "every_si = 1.0000e-8 s = " in msg, msg
    assert msg.startswith("hertz_spheres_physical: every_si: the output would be about "), msg
    assert "use a larger every_si=, a smaller until_si=, fewer beads" in msg, msg
    # computer units given: the plain key, with the seconds beside it
    with pytest.raises(bc.SceneError) as e:
        bc.run(phys, until=110.0, every=0.01, max_output_bytes=1000)
    assert ": until = 110 (9.9629e-5 s), every = 0.01 (" in str(e.value), str(e.value)
    assert abs(110.0 * beta - 9.9629e-5) < 1e-9
