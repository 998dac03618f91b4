"""Provenance (issue 36 item 2): the `.npz` export's `provenance` entry read by NumPy without
pickle, the xarray attributes (version, build commit, date when recorded, command, scene,
engine settings), and files written before the commit was recorded."""

import json
import pathlib
import re

import numpy as np
import pytest

import beadchain as bc
from beadchain import _beadchain

from conftest import ROOT, run_cli

COMMIT = re.compile(r"^([0-9a-f]{40}(-dirty)?|unknown)$")
PROVENANCE_ATTRS = ("beadchain_version", "build_commit", "created_by", "scene_name", "engine",
                    "method", "rtol", "atol")


def test_build_commit_has_the_form_of_a_commit():
    assert COMMIT.match(_beadchain.__build_commit__), _beadchain.__build_commit__


def test_npz_provenance_loads_without_pickle(cli, tmp_path):
    code, _, err = run_cli(cli, "run", "striker", "--until", "2", "--out", "s.snap", "-q",
                           "--timing", cwd=tmp_path)
    assert code == 0, err
    code, _, err = run_cli(cli, "export", "s.snap", "--out", "w.npz", cwd=tmp_path)
    assert code == 0, err
    z = np.load(tmp_path / "w.npz", allow_pickle=False)
    p = z["provenance"]
    assert p.shape == () and p.dtype.kind == "U"
    d = json.loads(str(p))
    assert set(d) == {"version", "commit", "created_at", "created_by", "scene", "engine",
                      "method", "rtol", "atol", "exported_by"}
    assert COMMIT.match(d["commit"]) and d["version"] == bc.__version__
    assert re.match(r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ$", d["created_at"]), d
    assert d["created_by"].endswith("run striker --until 2 --out s.snap -q --timing")
    assert d["exported_by"].endswith("export s.snap --out w.npz")
    assert (d["scene"], d["engine"], d["method"]) == ("striker", "hybrid", "auto")
    assert (d["rtol"], d["atol"]) == (1e-8, 1e-12)
    assert z["u"].shape == (3, 100)
    # The snapshot read from Python says the same.
    r = bc.load(tmp_path / "s.snap")
    assert r.meta["build_commit"] == d["commit"] and r.meta["created_at"] == d["created_at"]
    pytest.importorskip("xarray")
    ds = r.to_xarray()
    assert ds.attrs["created_at"] == d["created_at"]
    assert ds.attrs["build_commit"] == d["commit"]


def test_xarray_attrs_hold_the_provenance(tmp_path):
    pytest.importorskip("xarray")
    path = tmp_path / "s.snap"
    ran = bc.run("striker", until=1.0, out=path)
    for ds in (ran.to_xarray(), bc.load(path).to_xarray()):
        a = ds.attrs
        assert all(k in a for k in PROVENANCE_ATTRS), sorted(a)
        assert a["build_commit"] == _beadchain.__build_commit__
        assert a["beadchain_version"] == bc.__version__
        assert a["created_by"] == "python: beadchain.run(striker)"
        assert (a["scene_name"], a["engine"], a["method"]) == ("striker", "hybrid", "auto")
        assert (a["rtol"], a["atol"]) == (1e-8, 1e-12)
        # Python runs record no date: their files stay identical run to run.
        assert "created_at" not in a
    again = tmp_path / "t.snap"
    bc.run("striker", until=1.0, out=again)
    assert again.read_bytes() == path.read_bytes()


def test_files_before_provenance_still_load():
    pytest.importorskip("xarray")
    r = bc.load(pathlib.Path(ROOT) / "data" / "golden" / "v4_no_provenance.snap")
    assert r.meta["build_commit"] is None and r.meta["created_at"] is None
    assert r.meta["crate_version"] == "0.1.0"
    a = r.to_xarray().attrs
    assert "build_commit" not in a and "created_at" not in a
    assert a["scene_name"] == "four_beads" and a["beadchain_version"] == "0.1.0"
