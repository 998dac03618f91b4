"""analyze(): `beadchain analyze`'s summary from Python, the CLI's numbers (issue 13)."""

import json

import numpy as np
import pytest

import beadchain as bc
from conftest import run_cli


def _cli_json(cli, path, *args):
    code, out, err = run_cli(cli, "analyze", path, "--json", *args)
    assert code == 0, err
    return json.loads(out)


def _cli_speed(cli, path):
    code, out, err = run_cli(cli, "analyze", path)
    assert code == 0, err
    line = next(l for l in out.splitlines() if l.startswith("speed: "))
    return float(line.split()[1])


def test_analyze_of_a_striker_run_gives_the_clis_numbers(cli, tmp_path):
    p = tmp_path / "s.snap"
    r = bc.run(bc.Scene.preset("striker"), out=p)
    a = bc.analyze(r)
    j = _cli_json(cli, p)
    same = dict(rel=1e-12, abs=0)
    # the CLI prints the shortest round-trip form: the same doubles
    assert a["e0"] == pytest.approx(j["energy_initial"], **same)
    assert a["e_end"] == pytest.approx(j["energy_final"], **same)
    assert a["e_ref"] == pytest.approx(j["energy_reference"], **same)
    assert a["e_in"] == pytest.approx(j["wave_energy_in"], **same) and a["e_in_error"] is None
    assert (a["gaps"], a["fragments"], a["steady"]) == (
        j["gaps_final"], j["fragments_final"], j["steady_state_final"])
    d, jd = a["decay"], j["decay_fit"]
    assert a["decay_error"] is None and (a["fit_from"], a["fit_to"]) == (jd["from"], jd["to"])
    for k in ("a", "gamma", "gamma_stderr", "r2"):
        assert d[k] == pytest.approx(jd[k], **same), k
    assert d["points"] == jd["points"]
    track, lw = a["track"], j["leading_wave"]
    assert {len(c) for c in track.values()} == {len(lw)} and len(lw) > 50
    for k in ("t", "position", "energy", "peak_velocity"):
        np.testing.assert_allclose(track[k], [p[k] for p in lw], rtol=1e-12, atol=0)
    for k in ("peak_bead", "first", "last"):
        assert list(track[k]) == [p[k] for p in lw], k
    # speed: the CLI prints 7 significant digits (rtol 5e-7); the striker's solitary wave
    # moves 1.21 beads per unit time (data/scenes/striker.toml), within 5 % (abs 0.06)
    assert a["speed_error"] is None and a["speed_points"] == d["points"]
    assert a["speed"] == pytest.approx(_cli_speed(cli, p), rel=5e-7, abs=0)
    assert a["speed"] == pytest.approx(1.21, rel=0.05, abs=0.06)
    # the file gives the same dict as the run it was written from
    f = bc.analyze(p)
    assert f["warnings"] == []
    assert f["speed"] == a["speed"] and f["e_in"] == a["e_in"]
    np.testing.assert_array_equal(f["track"]["energy"], track["energy"])


def test_analyze_track_is_dataframe_ready():
    a = bc.analyze(bc.run(bc.Scene.preset("striker"), every=5.0))
    cols = a["track"]
    assert all(isinstance(c, np.ndarray) and c.ndim == 1 for c in cols.values())
    assert {len(c) for c in cols.values()} == {len(cols["t"])}
    assert {"t", "position", "energy", "first", "last", "peak_bead", "width"} <= set(cols)
    assert list(cols["width"]) == list(cols["last"] - cols["first"] + 1)
    pd = pytest.importorskip("pandas")
    assert pd.DataFrame(cols).shape == (len(cols["t"]), len(cols))


def test_analyze_interface_split_sums_to_the_total(cli, tmp_path):
    p = tmp_path / "i.snap"
    r = bc.run(bc.Scene.preset("interface_3.0_2.5"), every=10.0, out=p)
    a = bc.analyze(r, interface=50)
    i = a["interface"]
    assert i["k"] == 50 and i["t"] == r.t[-1]
    # left + right is the final frame's energy (abs 1e-14 of E0 scale, rel 1e-12)
    assert i["energy_left"] + i["energy_right"] == pytest.approx(a["e_end"], rel=1e-12,
                                                                 abs=1e-14 * a["e_ref"])
    assert i["reflected_fraction"] + i["transmitted_fraction"] == pytest.approx(1.0, rel=1e-12,
                                                                                abs=1e-12)
    assert 0.0 < i["reflected_fraction"] < 1.0 and i["reflected_fraction_error"] is None
    j = _cli_json(cli, p, "--interface", "50")["interface"]
    for k in ("energy_left", "energy_right", "reflected_fraction", "reflected_wave_energy",
              "v_in", "v_out", "velocity_ratio"):
        assert i[k] == pytest.approx(j[k], rel=1e-12, abs=0), k
    assert a["fit_from"] == 60.0


def test_analyze_velocity_ratio_of_unresolved_peaks_is_none_with_the_reason(cli, tmp_path):
    """The defect: |v_out/v_in| was the ratio of the largest samples however sparse the frames
    (0.600 with a frame every 200 time units on interface_3.0_2.5, 0.727 every 10)."""
    p = tmp_path / "i.snap"
    r = bc.run(bc.Scene.preset("interface_3.0_2.5"), every=200.0, out=p)
    i = bc.analyze(r, interface=50)["interface"]
    assert i["velocity_ratio"] is None and i["velocity_ratio_sampling_error"] is None
    assert i["velocity_ratio_error"].startswith("not resolved by the frames: v_in")
    j = _cli_json(cli, p, "--interface", "50")["interface"]
    assert j["velocity_ratio"] is None and j["velocity_ratio_error"] == i["velocity_ratio_error"]
    r = bc.run(bc.Scene.preset("interface_3.0_2.5"), every=10.0)
    i = bc.analyze(r, interface=50)["interface"]
    # resolved: 0.726984 (abs 1e-6), sampling error about 1e-6
    assert i["velocity_ratio"] == pytest.approx(0.726984, rel=0, abs=1e-6)
    assert 0.0 <= i["velocity_ratio_sampling_error"] < 1e-5 and i["velocity_ratio_error"] is None


def test_analyze_bad_interface_raises_the_clis_error(cli, tmp_path):
    p = tmp_path / "s.snap"
    r = bc.run(bc.Scene.preset("striker"), out=p)
    for k in (0, 100):
        with pytest.raises(ValueError) as e:
            bc.analyze(r, interface=k)
        msg = str(e.value)
        code, _, err = run_cli(cli, "analyze", p, "--interface", k)
        assert code == 2
        cli_msg = err.strip().removeprefix("beadchain: error: ")
        assert cli_msg == "--" + msg == "--interface must be in 1..100"
        with pytest.raises(ValueError, match=r"^interface must be in 1\.\.100$"):
            bc.analyze(p, interface=k)


def test_analyze_names_why_values_are_missing():
    # a chain at rest: no energy scale, no leading wave, no fit; reasons, not NaN
    s = bc.Scene.from_toml("[chain]\nbeads = 5\n[run]\nuntil = 1.0\nevery = 0.5\n")
    a = bc.analyze(bc.run(s), interface=2)
    assert a["e_ref"] == 0.0
    assert a["speed"] is None and "too few for the fit range" in a["speed_error"]
    assert "fit_from/fit_to" in a["speed_error"] and "--fit" not in a["speed_error"]
    assert a["decay"] is None and a["decay_error"] == a["speed_error"]
    assert a["relative_change"] is None and "energy scale is 0" in a["relative_change_error"]
    assert a["e_in"] is None and a["e_in_error"] == (
        "the leading wave never reaches position 1 (k/2, at most 10) before the interface bead k = 2")
    assert a["interface"]["reflected_fraction"] is None
    assert a["interface"]["reflected_fraction_error"] == "the total energy is 0"
    assert len(a["track"]["t"]) == 0
    for v in a.values():
        assert not (isinstance(v, float) and np.isnan(v))


def test_wrong_exception_types_interface_negative(tmp_path):
    # a negative (or huge) interface is outside 1..N as 0 is: the same ValueError, not
    # OverflowError
    p = tmp_path / "s.snap"
    r = bc.run(bc.Scene.preset("striker"), out=p)
    for k in (-1, -(2**70), 2**64, 2**70, np.int64(-3)):
        for what in (r, p):
            with pytest.raises(ValueError, match=r"^interface must be in 1\.\.100$"):
                bc.analyze(what, interface=k)
    with pytest.raises(TypeError, match="^interface: expected a bead index"):
        bc.analyze(r, interface=1.5)
    assert bc.analyze(r, interface=np.int64(50))["interface"]["k"] == 50
