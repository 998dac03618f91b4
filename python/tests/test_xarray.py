"""Issue 36 item 1: xarray views of runs (``Run.to_xarray()``, ``Run.events_to_xarray()``), the
``beadchain`` engine of ``xarray.open_dataset`` (lazy frames) and the netCDF round trip.

Every comparison is exact (``assert_array_equal``, ``xr.testing.assert_identical``): the
datasets hold the Run's arrays, or the same numbers read from the same file; energies are the
same library function of the same frames."""

import sys
import threading

import numpy as np
import pytest

xr = pytest.importorskip("xarray")

import beadchain as bc  # noqa: E402
from beadchain import _xarray as bc_xarray  # noqa: E402
from beadchain._xarray import BeadchainBackendEntrypoint  # noqa: E402

from conftest import ROOT, run_cli  # noqa: E402


def _netcdf_engine(engine="h5netcdf"):
    """``engine`` for ``to_netcdf``, the test skipped when its package is not installed
    (CI installs h5netcdf and h5py; scipy writes netCDF3, where int64 values become int32)."""
    if engine == "h5netcdf":
        pytest.importorskip("h5netcdf")
        pytest.importorskip("h5py")   # h5netcdf >= 1.8 leaves h5py optional; it writes with it
    else:
        pytest.importorskip("scipy")
    return engine


def _striker(**kw):
    return bc.Scene(mass=np.linspace(1.0, 2.0, 30), exponent=2.5, prefactor=1.0, striker=1.0,
                    until=20.0, every=2.0, **kw)


def _assert_same_values(a, b):
    """Every variable and coordinate of ``a`` and ``b`` equal exactly (attributes aside)."""
    assert set(a.variables) == set(b.variables)
    assert a.sizes == b.sizes
    for k in a.variables:
        assert a[k].dims == b[k].dims, k
        np.testing.assert_array_equal(a[k].values, b[k].values, err_msg=k)


def _assert_attrs_netcdf_safe(ds):
    for attrs in [ds.attrs, *(ds[k].attrs for k in ds.variables)]:
        for k, v in attrs.items():
            assert type(v) in (str, int, float), (k, v)
            assert type(v) is not int or -(2**31) <= v < 2**31, (k, v)  # netCDF3: int32


# --- to_xarray ----------------------------------------------------------------------------


def test_to_xarray_dims_coords_attrs_and_values():
    s = _striker()
    r = bc.run(s)
    ds = r.to_xarray()
    n, f = s.n_beads, len(r.t)
    assert dict(ds.sizes) == {"time": f, "bead": n, "contact": n - 1}
    assert set(ds.coords) == {"time", "bead", "contact"}
    assert set(ds.data_vars) == {"u", "v", "E_kinetic", "E_potential", "E_total", "mass",
                                 "exponent", "prefactor"}
    assert ds.u.dims == ("time", "bead") and ds.E_total.dims == ("time",)
    assert ds.mass.dims == ("bead",) and ds.exponent.dims == ("contact",)
    np.testing.assert_array_equal(ds.time.values, r.t)
    np.testing.assert_array_equal(ds.bead.values, np.arange(n))
    np.testing.assert_array_equal(ds.contact.values, np.arange(n - 1))
    np.testing.assert_array_equal(ds.u.values, r.u)
    np.testing.assert_array_equal(ds.v.values, r.v)
    e = r.energy()
    for name, key in (("E_kinetic", "kinetic"), ("E_potential", "potential"),
                      ("E_total", "total")):
        np.testing.assert_array_equal(ds[name].values, e[key])
    c = s.chain
    np.testing.assert_array_equal(ds.mass.values, c.mass)
    np.testing.assert_array_equal(ds.exponent.values, c.exponent)
    np.testing.assert_array_equal(ds.prefactor.values, c.prefactor)
    for k in ("time", "u", "v", "E_total", "mass", "prefactor"):
        assert ds[k].attrs["units"] == "1" and ds[k].attrs["unit_system"] == "computer", k
    a = ds.attrs
    assert a["scene"] == "scene" and a["n_beads"] == n and a["unit_system"] == "dimensionless"
    assert (a["engine"], a["method"]) == ("hybrid", "auto")
    assert a["rtol"] == 1e-8 and a["atol"] == 1e-12   # the documented defaults, exactly
    assert a["until"] == 20.0 and a["every"] == 2.0
    assert a["stats_steps"] == r.stats["steps"]
    assert a["law"] == "elastic"
    _assert_attrs_netcdf_safe(ds)
    assert "time_si" not in ds.coords   # dimensionless scene


def test_to_xarray_settings_given_to_run():
    r = bc.run(_striker(), engine="dense", method="dop853", rtol=1e-6)
    a = r.to_xarray().attrs
    assert (a["engine"], a["method"], a["rtol"], a["atol"]) == ("dense", "dop853", 1e-6, 1e-10)


def test_to_xarray_physical_scene_has_si_coordinates():
    s = bc.Scene.preset("hertz_spheres_physical")
    r = bc.run(s, until_si=1e-4, every_si=2e-5)
    ds = r.to_xarray()
    assert ds.time_si.dims == ("time",) and ds.time_si.attrs["units"] == "s"
    np.testing.assert_array_equal(ds.time_si.values, r.t_si)
    np.testing.assert_array_equal(ds.mass_si.values, s.chain.mass_si())
    assert ds.mass_si.attrs["units"] == "kg"
    u = s.units
    assert (ds.attrs["units_beta"], ds.attrs["units_m0"], ds.attrs["units_mu"],
            ds.attrs["units_n0"]) == (u.beta, u.m0, u.mu, u.n0)
    assert ds.attrs["unit_system"] == "physical"
    _assert_attrs_netcdf_safe(ds)


def test_to_xarray_output_selection():
    s = _striker(output={"beads": "0:30:5", "fields": "v"})
    r = bc.run(s)
    ds = r.to_xarray()
    np.testing.assert_array_equal(ds.bead.values, [0, 5, 10, 15, 20, 25])
    assert "u" not in ds and "E_total" not in ds   # energies need every bead's u and v
    np.testing.assert_array_equal(ds.v.values, r.v)
    np.testing.assert_array_equal(ds.mass.values, s.chain.mass[::5])
    assert ds.sizes["contact"] == 29


def test_to_xarray_dissipated_and_damping():
    s = bc.Scene.preset("damped_striker")
    r = bc.run(s, until=10.0, every=2.0)
    ds = r.to_xarray()
    assert r.dissipated is not None
    np.testing.assert_array_equal(ds.E_dissipated.values, r.dissipated)
    np.testing.assert_array_equal(ds.damping.values, s.chain.damping)
    assert ds.attrs["law"] == s.chain.law


def test_events_to_xarray():
    r = bc.run(bc.Scene.preset("newtons_cradle_hard"))
    ev = r.events
    assert len(ev["t"]) > 0
    ds = r.events_to_xarray()
    assert dict(ds.sizes) == {"event": len(ev["t"])}
    np.testing.assert_array_equal(ds.event.values, np.arange(len(ev["t"])))
    np.testing.assert_array_equal(ds.time.values, ev["t"])
    np.testing.assert_array_equal(ds.contact.values, ev["contact"])
    assert ds.contact.dtype == np.int64
    np.testing.assert_array_equal(ds.kind.values, ev["kind"])
    np.testing.assert_array_equal(ds.rel_velocity.values, ev["rel_velocity"])
    np.testing.assert_array_equal(ds.peak_overlap.values, ev["peak_overlap"])
    _assert_attrs_netcdf_safe(ds)


def test_to_xarray_without_xarray_says_how_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "xarray", None)   # import xarray raises ImportError
    monkeypatch.delitem(sys.modules, "beadchain._xarray", raising=False)
    monkeypatch.delattr(bc, "_xarray", raising=False)   # so that it is imported again
    r = bc.run(_striker())
    with pytest.raises(ImportError, match="pip install xarray"):
        r.to_xarray()
    with pytest.raises(ImportError, match="pip install xarray"):
        r.events_to_xarray()


# --- the backend --------------------------------------------------------------------------


def test_backend_is_registered():
    assert "beadchain" in xr.backends.list_engines()


def test_open_dataset_equals_to_xarray(tmp_path):
    path = tmp_path / "s.snap"
    r = bc.run(_striker(), out=path)
    with xr.open_dataset(path, engine="beadchain") as ds:
        xr.testing.assert_identical(ds, bc.load(path).to_xarray())
        _assert_same_values(ds, r.to_xarray())   # the in-memory run: the same numbers
        for k in ("engine", "method", "rtol", "atol", "scene", "until", "every"):
            assert ds.attrs[k] == r.to_xarray().attrs[k], k
        assert ds.attrs["complete"] == 1 and ds.attrs["format_version"] == 4
        _assert_attrs_netcdf_safe(ds)
    with xr.open_dataset(path, engine="beadchain", group="events") as ev:
        xr.testing.assert_identical(ev, bc.load(path).events_to_xarray())


def test_open_dataset_of_cli_snapshot(cli, tmp_path):
    path = tmp_path / "c.snap"
    code, _, err = run_cli(cli, "run", "hertz_spheres_physical", "-q", "--until-si", "1e-4",
                           "--every-si", "2e-5", "--out", path)
    assert code == 0, err
    with xr.open_dataset(path, engine="beadchain") as ds:
        xr.testing.assert_identical(ds, bc.load(path).to_xarray())
        assert "time_si" in ds.coords
    r = bc.run(bc.Scene.preset("hertz_spheres_physical"), until_si=1e-4, every_si=2e-5)
    with xr.open_dataset(path, engine="beadchain") as ds:
        _assert_same_values(ds, r.to_xarray())


def test_open_dataset_is_lazy_and_indexes_like_numpy(tmp_path, monkeypatch):
    path = tmp_path / "s.snap"
    r = bc.run(_striker(), out=path)
    reads = []
    orig = bc_xarray._Frames.read

    def counting(self, name, idx):
        reads.append((name, list(idx)))
        return orig(self, name, idx)

    monkeypatch.setattr(bc_xarray._Frames, "read", counting)
    with xr.open_dataset(path, engine="beadchain", cache=False) as ds:
        assert reads == []   # opening reads no frame
        assert not ds.u.variable._in_memory and not ds.E_total.variable._in_memory
        np.testing.assert_array_equal(ds.u.isel(time=-1).values, r.u[-1])
        assert reads == [("u", [len(r.t) - 1])]   # one frame read, not the file
        np.testing.assert_array_equal(ds.u.isel(time=[3, 1], bead=slice(2, 9, 3)).values,
                                      r.u[[3, 1]][:, 2:9:3])
        np.testing.assert_array_equal(ds.v.isel(time=slice(None, None, -2), bead=[4, 0]).values,
                                      r.v[::-2][:, [4, 0]])
        np.testing.assert_array_equal(ds.v.isel(time=2, bead=7).values, r.v[2, 7])
        np.testing.assert_array_equal(ds.E_kinetic.isel(time=[0, -1]).values,
                                      r.energy()["kinetic"][[0, -1]])
        np.testing.assert_array_equal(ds.u.sel(time=r.t[4]).values, r.u[4])


def test_open_dataset_reads_from_other_threads(tmp_path):
    path = tmp_path / "s.snap"
    r = bc.run(_striker(), out=path)
    out = {}
    with xr.open_dataset(path, engine="beadchain", cache=False) as ds:
        def work():
            out["v"] = ds.v.isel(time=5).values

        t = threading.Thread(target=work)
        t.start()
        t.join()
    np.testing.assert_array_equal(out["v"], r.v[5])


def test_open_dataset_options(tmp_path):
    path = tmp_path / "s.snap"
    bc.run(_striker(), out=path)
    with xr.open_dataset(path, engine="beadchain", drop_variables=["u", "E_total"]) as ds:
        assert "u" not in ds and "E_total" not in ds and "v" in ds
    with pytest.raises(ValueError, match="group"):
        xr.open_dataset(path, engine="beadchain", group="nope")
    with xr.open_dataset(path) as ds:   # recognised without engine=
        assert ds.attrs["scene"] == "scene" and "u" in ds
    b = BeadchainBackendEntrypoint()
    assert b.guess_can_open(path) and b.guess_can_open(str(path))
    other = tmp_path / "x.nc"
    other.write_bytes(b"CDF\x01")
    assert not b.guess_can_open(other)
    renamed = tmp_path / "snapshot.bin"
    renamed.write_bytes(path.read_bytes())
    assert b.guess_can_open(renamed)   # by the magic bytes


@pytest.mark.parametrize("name", ["v1.snap", "v2.snap", "v3_selection.snap"])
def test_open_dataset_of_older_formats(name):
    """The golden files of formats 1-3 (no E_dissipated; v3: a selection of v only)."""
    path = ROOT / "data" / "golden" / name
    r = bc.load(path)
    with xr.open_dataset(path, engine="beadchain") as ds:
        xr.testing.assert_identical(ds, r.to_xarray())
        assert "E_dissipated" not in ds
        np.testing.assert_array_equal(ds.v.values, r.v)
        assert ("u" in ds) == (r.u is not None)


def test_open_dataset_of_every_preset(tmp_path):
    """Every preset, run for a few frames into a file: the file opens, equals ``to_xarray()``
    of ``load()`` (and of the in-memory run, values exactly), and its event log opens."""
    names = [name for name, _ in bc.presets()]
    assert len(names) >= 20
    for name in names:
        s = bc.Scene.preset(name)
        path = tmp_path / f"{name}.snap"
        r = bc.run(s, until=2.0, every=0.5, out=path)
        with xr.open_dataset(path, engine="beadchain") as ds:
            assert ds.sizes["time"] == len(r.t) == 5, name
            xr.testing.assert_identical(ds, bc.load(path).to_xarray())
            _assert_same_values(ds, r.to_xarray())
            _assert_attrs_netcdf_safe(ds)
        with xr.open_dataset(path, engine="beadchain", group="events") as ev:
            _assert_same_values(ev, r.events_to_xarray())


# --- netCDF -------------------------------------------------------------------------------


@pytest.mark.parametrize("engine", ["h5netcdf", "scipy"])
@pytest.mark.parametrize("preset", ["hertz_spheres_physical", "newtons_cradle_hard",
                                    "damped_striker", None])
def test_netcdf_round_trip(tmp_path, preset, engine):
    engine = _netcdf_engine(engine)
    if preset is None:
        s = _striker(output={"beads": "1:30:7", "fields": "u"})
        r = bc.run(s)
    else:
        r = bc.run(bc.Scene.preset(preset), until=3.0, every=0.5)
    path = tmp_path / "r.nc"
    ds = r.to_xarray()
    ds.to_netcdf(path, engine=engine)
    with xr.open_dataset(path, engine=engine) as back:
        xr.testing.assert_identical(back, ds)
    ev = r.events_to_xarray()
    path_ev = tmp_path / "ev.nc"
    ev.to_netcdf(path_ev, engine=engine)
    with xr.open_dataset(path_ev, engine=engine) as back:
        xr.testing.assert_identical(back, ev)


def test_netcdf_round_trip_from_open_dataset(tmp_path):
    engine = _netcdf_engine()
    snap = tmp_path / "s.snap"
    bc.run(bc.Scene.preset("gapped_chain"), until=4.0, every=1.0, out=snap)
    nc = tmp_path / "s.nc"
    with xr.open_dataset(snap, engine="beadchain") as ds:
        ds.to_netcdf(nc, engine=engine)
        with xr.open_dataset(nc, engine=engine) as back:
            xr.testing.assert_identical(back, ds)


def test_empty_event_log_and_round_trip(tmp_path):
    engine = _netcdf_engine()
    r = bc.run(bc.Scene(beads=5, until=2.0))   # at rest: no event
    ev = r.events_to_xarray()
    assert dict(ev.sizes) == {"event": 0}
    path = tmp_path / "ev.nc"
    ev.to_netcdf(path, engine=engine)
    with xr.open_dataset(path, engine=engine) as back:
        xr.testing.assert_identical(back, ev)


def test_to_xarray_of_simulation_frames():
    sim = bc.Simulation(_striker())
    sim.advance(10.0)
    sim.advance()
    f = sim.frames()
    ds = f.to_xarray()
    _assert_same_values(ds, bc.run(_striker()).to_xarray())   # pieces = one run, bit for bit
    assert "engine" not in ds.attrs   # a Simulation's Run carries no engine settings
    _assert_attrs_netcdf_safe(ds)


def test_to_xarray_attrs_not_netcdf3_safe(tmp_path):
    # netCDF3 (scipy) stores 32-bit integers only: a larger one is the float64 that equals it
    # (up to 2**53), else its decimal text; both give the integer back exactly
    engine = _netcdf_engine("scipy")
    for seed, want in ((2**31 - 1, 2**31 - 1), (2**31, float(2**31)), (2**40, float(2**40)),
                       (2**53, float(2**53)), (2**53 + 1, str(2**53 + 1)),
                       (2**63 - 1, str(2**63 - 1))):
        r = bc.run(bc.Scene(beads=5, exponent=2.5, striker=1.0, until=3.0, seed=seed))
        ds = r.to_xarray()
        got = ds.attrs["seed"]
        assert type(got) is type(want) and got == want, (seed, got)
        assert int(got) == seed
        _assert_attrs_netcdf_safe(ds)
        path = tmp_path / f"s{seed}.nc"
        ds.to_netcdf(path, engine=engine)
        with xr.open_dataset(path, engine=engine) as back:
            xr.testing.assert_identical(back, ds)
            assert int(back.attrs["seed"]) == seed
