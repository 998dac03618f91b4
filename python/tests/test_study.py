"""check() and sweep(): the CLI's results, DataFrame-ready, through executors."""

import concurrent.futures as cf
import csv

import numpy as np
import pytest

import beadchain as bc
from conftest import ROOT, run_cli

GRID = ROOT / "data" / "sweeps" / "reflection_grid.toml"


def test_check_passes_on_the_striker():
    r = bc.check(bc.Scene.preset("striker"))
    assert r["passed"] is True and r["tol"] == pytest.approx(1e-5, rel=1e-12, abs=0)
    c = r["criteria"]
    assert len(c["what"]) == len(c["value"]) == len(c["bound"]) == len(c["holds"]) >= 1
    assert all(c["holds"]) and all(v <= b for v, b in zip(c["value"], c["bound"]))
    assert r["deviation"]["rel_v"] < 1e-5
    assert r["at_rest"] is False


def test_check_of_a_chain_at_rest_is_against_its_scales():
    # the hybrid engine holds the equilibrium exactly, the dense reference moves by round-off:
    # compared against the scales L, V (measured 1.6e-15), not sensitive, no leading wave
    r = bc.check(bc.Scene.preset("gravity_column_at_rest"))
    assert r["passed"] is True and r["at_rest"] is True and r["sensitive"] is False
    assert max(r["deviation"]["rel_u"], r["deviation"]["rel_v"]) <= 1e-12  # abs tol of L, V
    assert not any("leading-wave" in w for w in r["criteria"]["what"])


def test_check_bound_is_tol_or_ten_times_the_sensitivity():
    # D <= max(tol, 10 S) (src/check.rs): with a tiny tol the scene counts as sensitive and the
    # trajectory bound is 10 S; with the default tol (1000 rtol) it is tol.
    tight = bc.check(bc.Scene.preset("striker"), rtol=1e-4, tol=1e-12)
    s = tight["sensitivity"]
    assert tight["sensitive"] is True
    assert tight["criteria"]["bound"][0] == pytest.approx(10 * max(s["rel_u"], s["rel_v"]), rel=1e-12, abs=0)
    plain = bc.check(bc.Scene.preset("striker"), rtol=1e-4)
    assert plain["sensitive"] is False
    assert plain["criteria"]["bound"][0] == pytest.approx(0.1, rel=1e-12, abs=0)


def _cli_rows(cli, tmp_path):
    code, _, err = run_cli(cli, "sweep", GRID, "--out", tmp_path / "g.csv")
    assert code == 0, err
    with open(tmp_path / "g.csv") as f:
        return list(csv.DictReader(f))


def test_sweep_matches_the_cli(cli, tmp_path):
    rows = _cli_rows(cli, tmp_path)
    seen = []
    res = bc.sweep(GRID, progress=lambda d, n: seen.append((d, n)))
    assert seen[-1] == (9, 9) and len(seen) == 9
    assert list(res["run"]) == list(range(9))
    for i, row in enumerate(rows):
        # swept values come back as numbers (issue 36: they were the CSV text '2.5')
        assert res["chain.exponent.base"][i] == float(row["chain.exponent.base"])
        assert res["status"][i] == row["status"] == "ok"
        for k in ("t_end", "energy_error", "left_fraction"):
            # the CLI writes the shortest round-trip form: the same double
            assert res[k][i] == pytest.approx(float(row[k]), rel=0, abs=0)
        assert res["steps"][i] == int(row["steps"]) and res["fragments"][i] == int(row["fragments"])


def test_sweep_through_executors_gives_the_same_columns():
    plain = bc.sweep(GRID)
    with cf.ThreadPoolExecutor(max_workers=2) as ex:
        threads = bc.sweep(GRID, executor=ex)
    with cf.ProcessPoolExecutor(max_workers=2) as ex:
        procs = bc.sweep(GRID, executor=ex)
    for k in plain:
        assert list(threads[k]) == list(plain[k]) and list(procs[k]) == list(plain[k])
    assert bc.sweep_size(GRID) == 9
    assert bc.sweep_run(GRID, 4)["left_fraction"] == plain["left_fraction"][4]


def test_bad_sweep_raises_before_running(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text('scene = "striker"\n[grid]\n"chain.mass" = [1.0, -1.0]\n')
    with pytest.raises(bc.SceneError) as e:
        bc.sweep(p)
    assert "mass" in str(e.value) and "\n" not in str(e.value)
    with pytest.raises(bc.SceneError):
        bc.sweep_run(GRID, 99)


def test_accuracy_matches_the_clis_table(cli, tmp_path):
    args = dict(engines=["hybrid"], methods=["radau5", "dop853"], rtols=[1e-4, 1e-6, 1e-8],
                until=30.0)
    r = bc.accuracy(bc.Scene.preset("striker"), **args)
    rows = r["rows"]
    assert r["reference"]["rtol"] == 1e-8 and r["until"] == 30.0
    assert set(rows["method"]) == {"radau5", "dop853"} and set(rows["engine"]) == {"hybrid"}
    code, _, err = run_cli(cli, "accuracy", "striker", "--engines", "hybrid", "--methods",
                           "radau5,dop853", "--rtols", "1e-4,1e-6,1e-8", "--until", "30",
                           "--out", tmp_path, "--quiet")
    assert code == 0, err
    with open(tmp_path / "accuracy.csv") as f:
        table = [row for row in csv.DictReader(f) if not row.get("engine", "").startswith("#")]
    by_key = {(row["engine"], row["method"], float(row["rtol"])): row for row in table}
    for i in range(len(rows["rtol"])):
        row = by_key[(rows["engine"][i], rows["method"][i], rows["rtol"][i])]
        assert float(row["err_v"]) == pytest.approx(rows["err_v"][i], rel=1e-6, abs=1e-300)
        assert int(row["steps"]) == rows["steps"][i]
    # the error falls with the tolerance
    for m in ("radau5", "dop853"):
        e = [rows["error"][i] for i in range(len(rows["rtol"])) if rows["method"][i] == m
             and not rows["is_reference"][i]]
        assert e == sorted(e, reverse=True)


def test_accuracy_rejects_bad_options():
    with pytest.raises(bc.SceneError):
        bc.accuracy(bc.Scene.preset("striker"), rtols=[2.0])
    with pytest.raises(bc.SceneError):
        bc.accuracy(bc.Scene.preset("striker"), methods=["euler"])


def test_wrong_exception_types_sweep_run_negative_index():
    with pytest.raises(ValueError, match=r"^sweep_run: index = -1 must be >= 0$"):
        bc.sweep_run(GRID, -1)
    with pytest.raises(bc.SceneError, match="run 9 does not exist"):
        bc.sweep_run(GRID, 9.0)
    with pytest.raises(ValueError, match=r"^max_steps = -1 must be >= 0$"):
        bc.accuracy("striker", max_steps=-1)


def test_study_functions_fail_on_a_preset_name(tmp_path):
    # every study function takes a scene as run() does: a Scene, a preset name or a file
    for f in (bc.check, bc.modes, bc.equilibrium, bc.bands, bc.accuracy):
        with pytest.raises(bc.SceneError, match=r"^\w+: unknown preset 'strikr'; did you mean "
                                                r"'striker'\?"):
            f("strikr")
    with pytest.raises(bc.SceneError, match="unknown preset 'strikr'"):
        bc.breather("strikr", 2.25)
    with pytest.raises(bc.SceneError, match="unknown preset 'strikr'"):
        bc.modal_energies("strikr", tmp_path / "x.snap")
    with pytest.raises(TypeError, match="^check: scene: expected a Scene, a preset name"):
        bc.check(3)
    check = bc.check("striker", until=20.0)
    assert check == bc.check(bc.Scene.preset("striker"), until=20.0) and check["passed"]
    dimer = bc.Scene.preset("dimer_dispersion")
    np.testing.assert_array_equal(bc.modes("dimer_dispersion")["omega"], bc.modes(dimer)["omega"])
    np.testing.assert_array_equal(bc.bands("dimer_dispersion")["gaps"], bc.bands(dimer)["gaps"])
    col = bc.Scene.preset("gravity_column_at_rest")
    np.testing.assert_array_equal(bc.equilibrium("gravity_column_at_rest")["u"],
                                  bc.equilibrium(col)["u"])
    path = tmp_path / "dimer.toml"
    path.write_text(dimer.source)
    r = bc.run(dimer, until=2.0, every=1.0)
    np.testing.assert_array_equal(bc.modal_energies(path, r)["energy"],
                                  bc.modal_energies(dimer, r)["energy"])
