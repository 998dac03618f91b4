"""Tests of run_scene_peers.py's tables (no SciPy run): run by CI's pytest (.ci/run)."""

import argparse
import csv
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_scene_peers as rsp  # noqa: E402


def _args(tmp_path, metric):
    return argparse.Namespace(scene="s", metric=metric, reference="scipy", reference_rtol=1e-13,
                              repeat=3, timeout=10.0, beadchain="hybrid:auto,dense:dop853",
                              from_csv=None, out=str(tmp_path / "t"), beadchain_atol="matched")


def _rows():
    # the scores come from NumPy reductions: np.float64 values, as in a real invocation
    row = lambda solver, rtol, wall, e: dict(solver=solver, rtol=rtol, status="ok", wall=wall,  # noqa: E731
                                             velocity=np.float64(0.3), energy=np.float64(e),
                                             lead=np.float64(1e-2))
    return [row("beadchain hybrid auto", 1e-6, 0.5, 2e-6), row("beadchain hybrid auto", 1e-4, 0.2, 3e-4),
            row("scipy dop853", 1e-6, 4.0, 5e-4)]


def test_csv_numbers_are_plain_floats_not_numpy_reprs(tmp_path):
    """Under NumPy 2 the CSV held `np.float64(2.9e-06)` (written with %r), which no CSV reader
    takes as a number."""
    args = _args(tmp_path, "observables")
    rsp.write(args, args.out, _rows(), "beadchain hybrid auto")
    with open(args.out + ".csv") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("wall_seconds", "velocity_error", "energy_error", "lead_error"):
            float(r[k])  # raises on "np.float64(...)"


def test_energy_metric_rescored_from_an_older_csv(tmp_path):
    """--from-csv reads a CSV of either form and ranks by the energy error alone: the peer's
    5e-4 is matched by the 0.2 s run (3e-4), a 20x speed-up."""
    args = _args(tmp_path, "observables")
    rsp.write(args, args.out, _rows(), "beadchain hybrid auto")
    old = args.out + "-old.csv"
    with open(args.out + ".csv") as f, open(old, "w") as g:
        text = f.read()
        for key in ("2e-06", "0.0003", "0.0005"):  # the energy errors, in the old written form
            text = text.replace("," + key + ",", ",np.float64(%s)," % key)
        g.write(text)
    assert "np.float64(" in open(old).read()
    args = _args(tmp_path, "energy")
    args.from_csv, args.out = old, str(tmp_path / "energy")
    rsp.rescore(args)
    md = open(args.out + ".md").read()
    assert "total-energy error" in md
    assert "| scipy dop853 | 1e-06 | 4.0000 | 5.0e-04 | 0.0001 | 0.2000 | 3.0e-04 | 20.0× |" in md, md


def test_default_atol_is_recorded_and_read_back(tmp_path):
    """With --beadchain-atol default the CSV records beadchain's own atol (rtol/10^4, SciPy's stays
    rtol/100), the header says so, and --from-csv recovers the mode from the CSV."""
    args = _args(tmp_path, "energy")
    args.beadchain_atol = "default"
    rsp.write(args, args.out, _rows(), "beadchain hybrid auto")
    with open(args.out + ".csv") as f:
        atol = {(r["solver"], float(r["rtol"])): float(r["atol_rel"]) for r in csv.DictReader(f)}
    # rel tol 1e-12 on exact decimal ratios
    assert abs(atol[("beadchain hybrid auto", 1e-6)] - 1e-10) <= 1e-12 * 1e-10
    assert abs(atol[("scipy dop853", 1e-6)] - 1e-8) <= 1e-12 * 1e-8
    assert "beadchain atol = its default rtol/10^4" in open(args.out + ".md").read()
    again = _args(tmp_path, "energy")
    again.from_csv, again.out = args.out + ".csv", str(tmp_path / "again")
    rsp.rescore(again)
    assert again.beadchain_atol == "default"
    assert "beadchain atol = its default rtol/10^4" in open(again.out + ".md").read()


def test_speedup_just_below_a_target_is_not_rounded_up(tmp_path):
    """The tables printed speed-ups with no decimal, so the interface's 9.69x against the issue's
    10x target read "10×"; they now keep one decimal below 100x (and walls four)."""
    import run_peers
    assert run_peers.speedup(9.69) == "9.7×"
    assert run_peers.speedup(99.9) == "99.9×"
    assert run_peers.speedup(741.4) == "741×"
    args = _args(tmp_path, "energy")
    rows = _rows()
    rows[2]["wall"] = 0.2 * 9.69  # the 0.2 s run matches the peer's energy error
    rsp.write(args, args.out, rows, "beadchain hybrid auto")
    md = open(args.out + ".md").read()
    assert "| 0.2000 | 3.0e-04 | 9.7× |" in md, md


def test_run_peers_tables_are_remade_from_its_csv(tmp_path):
    """run_peers.py --from-csv re-makes the tables of an earlier invocation without running, with
    beadchain's atol mode read back from the CSV."""
    import run_peers
    src = tmp_path / "r.csv"
    src.write_text(
        "solver,beads,until,rtol,atol_rel,status,wall_seconds,energy_error,repeat\n"
        "beadchain hybrid auto,1000,866.0,1e-06,1e-10,ok,0.015,7e-07,3\n"
        "scipy lsoda,1000,866.0,1e-06,1e-08,ok,0.6786,0.00018,3\n"
        "beadchain hybrid auto,1000,866.0,1e-05,1e-09,ok,0.0109,6.1e-06,3\n")
    args = argparse.Namespace(from_csv=str(src), out=str(tmp_path / "out"), beadchain="hybrid:auto",
                              exponent=2.5, prefactor=1.0, mass=1.0, velocity=1.0)
    run_peers.rewrite(args)
    md = open(args.out + ".md").read()
    assert "beadchain atol = its default" in md, md
    assert "| scipy lsoda | 1e-06 | 0.6786 | 1.8e-04 | 1e-05 | 0.0109 | 6.1e-06 | 62.3× |" in md, md


def _floor_rows():
    # the 1000-bead striker at SciPy rtol 1e-12, as measured against dense DOP853: LSODA's error
    # 2.6e-11 was that reference's own floor
    row = lambda solver, rtol, wall, e, lead=None: dict(  # noqa: E731
        solver=solver, rtol=rtol, status="ok", wall=wall, velocity=np.float64(e),
        energy=np.float64(1e-12), lead=np.float64(e if lead is None else lead))
    return [row("beadchain hybrid auto", 1e-11, 0.0267, 2.6e-11), row("beadchain hybrid auto", 1e-6, 0.0145, 3.7e-7),
            row("scipy lsoda", 1e-12, 2.2256, 2.6e-11), row("scipy lsoda", 1e-6, 0.6792, 9.3e-5),
            # 5x the floor (marked, below 10x) and 20x (resolved)
            row("scipy dop853", 1e-12, 1.8, 1.3e-10, lead=1e-3), row("scipy dop853", 1e-10, 1.0, 5.2e-10, lead=1e-3),
            # more accurate than every beadchain run, and at the floor
            row("scipy vode_bdf_banded", 1e-12, 11.0, 1e-11)]


def test_peer_errors_at_the_reference_floor_are_marked(tmp_path):
    """The striker's and the interface's tables compared every solver at rtol 1e-12 with a
    reference (dense DOP853 at rtol 1e-13) that was itself off by 2.6e-11 (6e-10 on the
    interface): the header now gives the reference's floor (the reference against itself at 10x
    its rtol), and a peer error below 10x that floor is marked instead of read as resolved."""
    args = _args(tmp_path, "velocity")
    args.reference, args.reference_method = "dense", "dop853"
    args.floor = dict(velocity=2.6e-11, lead=2.6e-11, energy=0.0)
    rsp.write(args, args.out, _floor_rows(), "beadchain hybrid auto")
    md = open(args.out + ".md").read()
    assert "reference beadchain dense DOP853 rtol 1e-13; its floor" in md, md
    assert "velocity 2.6e-11, lead energy 2.6e-11" in md, md
    assert "| scipy lsoda | 1e-12 | 2.2256 | 2.6e-11 | 1e-11 | 0.0267 | 2.6e-11 | 83.4× (near the reference floor) |" in md, md
    assert "| scipy lsoda | 1e-06 | 0.6792 | 9.3e-05 | 1e-06 | 0.0145 | 3.7e-07 | 46.8× |" in md, md
    assert "| scipy dop853 | 1e-12 | 1.8000 | 1.3e-10 | 1e-11 | 0.0267 | 2.6e-11 | 67.4× (near the reference floor) |" in md, md
    assert "| scipy dop853 | 1e-10 | 1.0000 | 5.2e-10 | 1e-11 | 0.0267 | 2.6e-11 | 37.5× |" in md, md
    assert "| scipy vode_bdf_banded | 1e-12 | 11.0000 | 1.0e-11 | none as accurate (near the reference floor) |" in md, md
    # the energy metric needs no reference: nothing is marked under it
    args.metric = "energy"
    rsp.write(args, args.out, _floor_rows(), "beadchain hybrid auto")
    assert "near the reference floor" not in open(args.out + ".md").read()


def test_observables_use_the_lead_energy_floor(tmp_path):
    """Under --metric observables (max of the energy and lead-energy errors) a row is marked by
    the lead energy's floor, not the velocity's: a chaotic scene's final velocities differ at
    order one between any two runs, its leading-wave energy much less."""
    args = _args(tmp_path, "observables")
    args.reference, args.reference_method = "dense", "radau5"
    args.floor = dict(velocity=0.3, lead=1e-6, energy=0.0)
    rsp.write(args, args.out, _floor_rows(), "beadchain hybrid auto")
    md = open(args.out + ".md").read()
    # errors are max(energy, lead): 1e-3 and 9.3e-5 are >= 10x the lead floor 1e-6, resolved
    # although the velocity floor is 0.3
    assert "| scipy dop853 | 1e-12 | 1.8000 | 1.0e-03 | 1e-06 | 0.0145 | 3.7e-07 | 124× |" in md, md
    assert "| scipy lsoda | 1e-06 | 0.6792 | 9.3e-05 | 1e-06 | 0.0145 | 3.7e-07 | 46.8× |" in md, md
    # 2.6e-11 < 10x 1e-6: marked
    assert "| scipy lsoda | 1e-12 | 2.2256 | 2.6e-11 | 1e-11 | 0.0267 | 2.6e-11 | 83.4× (near the reference floor) |" in md, md


def test_reference_floor_survives_a_rescore(tmp_path):
    """--from-csv reads the reference, its rtol and its floors back from the CSV; a CSV written
    before the floor check says that neither was recorded, and rewriting it invents neither."""
    args = _args(tmp_path, "observables")
    args.reference, args.reference_method, args.reference_rtol = "dense", "dop853", 1e-12
    args.floor = dict(velocity=5.1e-14, lead=3e-5, energy=0.0)
    rsp.write(args, args.out, _floor_rows(), "beadchain hybrid auto")
    again = _args(tmp_path, "observables")
    again.from_csv, again.out = args.out + ".csv", str(tmp_path / "again")
    rsp.rescore(again)
    md = open(again.out + ".md").read()
    assert "reference beadchain dense DOP853 rtol 1e-12; its floor" in md, md
    assert "velocity 5.1e-14, lead energy 3.0e-05" in md, md
    # the lead floor read back marks 9.3e-5 (< 10x 3e-5) and not 1e-3
    assert "| scipy lsoda | 1e-06 | 0.6792 | 9.3e-05 | 1e-06 | 0.0145 | 3.7e-07 | 46.8× (near the reference floor) |" in md, md
    assert "| scipy dop853 | 1e-12 | 1.8000 | 1.0e-03 | 1e-06 | 0.0145 | 3.7e-07 | 124× |" in md, md
    old = tmp_path / "old.csv"
    with open(args.out + ".csv") as f:
        lines = f.read().splitlines()
    cut = lambda line: ",".join(line.split(",")[:10])  # noqa: E731  (the columns before the check)
    old.write_text("\n".join(cut(x) for x in lines) + "\n")
    older = _args(tmp_path, "velocity")
    older.from_csv, older.out = str(old), str(tmp_path / "older")
    rsp.rescore(older)
    md = open(older.out + ".md").read()
    assert "reference (not recorded in the CSV); its floor was not measured" in md, md
    with open(older.out + ".csv") as f:
        row = next(csv.DictReader(f))
    assert row["reference"] == "" and row["reference_rtol"] == "" and row["reference_floor_lead"] == "", row


def test_floor_is_the_loose_reference_scored_against_the_tight_one():
    """floor_of scores the reference at 10x its rtol like any run, relative to the tight
    reference's values: velocity and lead-energy differences, and 0 for the energy metric."""
    ch = dict(mass=[1.0, 1.0, 1.0], exponent=[2.5, 2.5], prefactor=[1.0, 1.0], u0=[0.0, 0.0, 0.0],
              v0=[1.0, 0.0, 0.0], until=1.0)
    ref = dict(status="ok", u=[0.0, 0.0, 0.0], v=[0.0, 0.0, 1.0])
    loose = dict(status="ok", u=[0.0, 0.0, 0.0], v=[0.0, 1e-3, 2.0])
    f = rsp.floor_of(ch, ref, loose, 10)
    # relative to the tight reference's largest velocity (1) and lead energy (0.5): 1.0 and 3.000001;
    # the other way round they would be 0.5 and 0.75; rel tol 1e-12
    assert abs(f["velocity"] - 1.0) <= 1e-12, f
    assert abs(f["lead"] - (0.5 * (1e-6 + 4.0) - 0.5) / 0.5) <= 1e-12 * 3.0, f
    assert f["energy"] == 0.0


def test_compare_binaries_runs_a_binary_against_itself():
    """compare_binaries.py alternates two binaries and reports identical output for one binary
    given twice (the beadchain CLI of CI's build, BEADCHAIN_CLI)."""
    import subprocess
    binary = os.environ.get("BEADCHAIN_CLI")
    if not binary or not os.path.exists(binary):
        import pytest
        pytest.skip("BEADCHAIN_CLI not set")
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "compare_binaries.py")
    out = subprocess.run([sys.executable, script, binary, binary, "--repeat", "2",
                          "--case", "striker:1e-4"], capture_output=True, text=True, check=True).stdout
    rows = [line for line in out.splitlines() if line.startswith("| striker |")]
    assert len(rows) == 1, out
    cells = [c.strip() for c in rows[0].strip("|").split("|")]
    assert cells[1] == "1e-4" and cells[5] == "yes", rows[0]
    assert float(cells[4]) > 0.0


def test_run_beadchain_reads_the_last_frame_past_the_provenance_lines(tmp_path):
    """The defect: `beadchain export` starts with `# …` provenance lines (issue 36), which
    csv.DictReader took for the header, so every beadchain run of run_scene_peers.py (and of
    wholechain_numba.py) failed with KeyError: 'u'. The striker's last frame is read whole."""
    binary = os.environ.get("BEADCHAIN_CLI")
    if not binary or not os.path.exists(binary):
        import pytest
        pytest.skip("BEADCHAIN_CLI not set")
    args = _args(tmp_path, "velocity")
    args.binary = binary
    res = rsp.run_beadchain(args, "striker", "hybrid", "auto", 1e-6, str(tmp_path))
    assert res["status"] == "ok" and len(res["u"]) == len(res["v"]) == 100
    # the striker's momentum (1 at t = 0) is carried to the end: sum of v to 1e-9 (absolute)
    assert abs(sum(res["v"]) - 1.0) <= 1e-9, sum(res["v"])
