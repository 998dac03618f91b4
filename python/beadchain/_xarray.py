"""xarray views of runs and snapshot files (optional: needs ``pip install xarray``).

- :func:`run_to_xarray` / :func:`events_to_xarray`: ``Run.to_xarray()`` and
  ``Run.events_to_xarray()``: the frames (dims ``time``, ``bead``), the energies, the chain
  (``bead`` and ``contact`` variables) and the event log (dim ``event``) as
  ``xarray.Dataset``\\ s, eagerly (the Run's own arrays, no copy).
- :class:`BeadchainBackendEntrypoint`: the ``beadchain`` engine of ``xarray.open_dataset``
  (registered under ``[project.entry-points."xarray.backends"]``): a snapshot file opened
  from its index, its frame variables (``u``, ``v``, the energies) read lazily, only the frames
  an index asks for (``group="events"`` opens the event log instead).

Both routes build the dataset with the same function, so ``open_dataset(path,
engine="beadchain")`` equals ``beadchain.load(path).to_xarray()`` (values, coordinates and
attributes). Attributes hold only ``str``, ``int`` and ``float`` values (netCDF-safe, netCDF3
included): booleans as 0/1, integers outside the 32-bit range as float64 (exact up to 2**53)
or else as decimal text, dicts as JSON text; a value that is None is left out.
"""

from __future__ import annotations

import json
import os
import threading
from typing import Any, Callable, Iterable, Optional

import numpy as np

try:
    import xarray as xr
    from xarray.backends import BackendArray, BackendEntrypoint
    from xarray.core import indexing
except ImportError as e:  # tested with xarray hidden (test_xarray.py)
    raise ImportError(
        "beadchain's xarray support needs the xarray package: pip install xarray "
        "(and h5netcdf or scipy for to_netcdf)"
    ) from e

from . import _beadchain

_MAGIC = b"BEADCHN\0"

# Frame variables computed per frame (names in the dataset -> Run.energy() keys).
_ENERGIES = {"E_kinetic": "kinetic", "E_potential": "potential", "E_total": "total"}

_UNITS_NOTE = (
    "computer (paper) units, eqs. 10-11: t_SI = time * beta, v_SI = v / beta, u in metres "
    "unchanged, E_SI = E * m0 / beta**2, mass_SI = mass * m0 (physical scenes: beta, m0 in the "
    "attributes units_beta, units_m0)"
)


def _attr_value(v: Any) -> Any:
    """``v`` as a netCDF-safe attribute value (str, 32-bit int or float: netCDF3 too), or None
    to leave it out."""
    if v is None:
        return None
    if isinstance(v, (bool, np.bool_)):
        return int(v)
    if isinstance(v, (int, np.integer)):
        # netCDF3 (to_netcdf(engine="scipy")) stores 32-bit integers only: a larger one as the
        # float64 that equals it (|v| <= 2**53), else as its decimal text; both lossless
        v = int(v)
        if -(2**31) <= v < 2**31:
            return v
        return float(v) if abs(v) <= 2**53 else str(v)
    if isinstance(v, (float, np.floating)):
        return float(v)
    if isinstance(v, str):
        return v
    if isinstance(v, (list, tuple)) and all(isinstance(x, str) for x in v):
        return "\n".join(v) if v else None
    return json.dumps(v, sort_keys=True, default=_json_default)


def _json_default(x: Any) -> Any:
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(f"not JSON serialisable: {type(x).__name__}")


def _attrs(run) -> dict:
    """Dataset attributes of ``run``: scene, engine settings, file metadata, stats, units."""
    scene = run.scene
    chain = scene.chain
    rs = scene.run_settings
    meta = run.meta
    raw: dict = {
        "scene": scene.name,
        "description": scene.description,
        "n_beads": scene.n_beads,
        "seed": scene.seed,
        "engine": meta.get("engine"),
        "method": meta.get("method"),
        "rtol": meta.get("rtol"),
        "atol": meta.get("atol"),
        "until": rs.get("until"),
        "every": rs.get("every"),
        "law": chain.law,
        "left_wall": chain.left_wall,
        "right_wall": chain.right_wall,
        "damping_walls": None if chain.damping_walls is None else list(chain.damping_walls),
        "collapse_interval": chain.collapse_interval,
        "created_by": meta.get("created_by"),
        "build_commit": meta.get("build_commit"),
        "created_at": meta.get("created_at"),
        "scene_name": scene.name,
        "format_version": meta.get("format_version"),
        "complete": meta.get("complete"),
        "warnings": meta.get("warnings"),
        "scene_warnings": scene.warnings,
        "beadchain_version": meta.get("crate_version") or _beadchain.__version__,
        "unit_system": "physical" if scene.is_physical else "dimensionless",
        "units_note": _UNITS_NOTE,
    }
    if scene.units is not None:
        for k in ("beta", "m0", "mu", "n0"):
            raw[f"units_{k}"] = getattr(scene.units, k)
    for k, x in sorted((run.stats or {}).items()):
        raw[f"stats_{k}"] = x
    out = {}
    for k, x in raw.items():
        x = _attr_value(x)
        if x is not None:
            out[k] = x
    return out


class _Var:
    """One variable before it becomes an ``xarray.Variable``: dims, data, attributes."""

    __slots__ = ("dims", "data", "attrs")

    def __init__(self, dims: tuple, data: Any, attrs: dict):
        self.dims, self.data, self.attrs = dims, data, attrs


def _frame_variables(run) -> dict:
    """Which per-frame variables ``run`` has: name -> (dims, attrs) (data added by caller)."""
    frame = ("time", "bead")
    out = {}
    has_u, has_v, has_dissipated = run._stored()
    if has_u:
        out["u"] = (frame, {"long_name": "displacement", "units": "1", "unit_system": "computer",
                            "note": "SI: metres, unchanged (u_SI = u)"})
    if has_v:
        out["v"] = (frame, {"long_name": "velocity", "units": "1", "unit_system": "computer",
                            "note": "SI: v / beta (m/s)"})
    if has_u and has_v and run.beads is None:
        for name, key in _ENERGIES.items():
            out[name] = (("time",), {"long_name": f"{key} energy", "units": "1",
                                     "unit_system": "computer",
                                     "note": "SI: E * m0 / beta**2 (J)"})
    if has_dissipated:
        out["E_dissipated"] = (("time",), {
            "long_name": "energy dissipated from t = 0 (damped contacts, hard collisions)",
            "units": "1", "unit_system": "computer", "note": "SI: E * m0 / beta**2 (J)"})
    return out


def _dataset(run, frame_data: Callable[[str, tuple], Any]):
    """The dataset of ``run``; ``frame_data(name, shape)`` gives each per-frame variable's data
    (NumPy arrays for ``to_xarray``, lazy arrays for the backend)."""
    scene = run.scene
    chain = scene.chain
    n_frames = len(run.t)
    beads = np.arange(scene.n_beads, dtype=np.int64) if run.beads is None else run.beads
    n_contacts = len(chain.prefactor)
    coords: dict = {
        "time": _Var(("time",), run.t, {"long_name": "time", "units": "1",
                                        "unit_system": "computer", "note": "SI: time * beta (s)"}),
        "bead": _Var(("bead",), beads, {"long_name": "bead index (0-based)"}),
        "contact": _Var(("contact",), np.arange(n_contacts, dtype=np.int64),
                        {"long_name": "contact index: between beads contact and contact + 1"}),
    }
    if scene.units is not None:
        coords["time_si"] = _Var(("time",), scene.units.time(run.t),
                                 {"long_name": "time", "units": "s", "note": "time * beta"})
    data: dict = {}
    for name, (dims, attrs) in _frame_variables(run).items():
        shape = (n_frames, len(beads)) if dims == ("time", "bead") else (n_frames,)
        data[name] = _Var(dims, frame_data(name, shape), attrs)

    def bead_var(x, attrs):
        return _Var(("bead",), np.asarray(x)[beads] if run.beads is not None else x, attrs)

    cu = {"units": "1", "unit_system": "computer"}
    data["mass"] = bead_var(chain.mass, {"long_name": "mass", **cu, "note": "SI: mass * m0 (kg)"})
    if scene.units is not None:
        data["mass_si"] = bead_var(chain.mass_si(), {"long_name": "mass", "units": "kg"})
    if chain.field is not None:
        data["field"] = bead_var(chain.field, {"long_name": "external force on the bead", **cu})
    contact_vars = {
        "exponent": (chain.exponent, {"long_name": "contact law exponent n", "units": "1"}),
        "prefactor": (chain.prefactor, {"long_name": "contact law prefactor a", **cu,
                                        "note": "SI: a * m0 / beta**2"}),
        "precompression": (chain.precompression, {"long_name": "precompression", **cu}),
        "damping": (chain.damping, {"long_name": f"damping ({chain.law})", **cu}),
        "hard_restitution": (chain.hard_restitution, {
            "long_name": "restitution of hard contacts (NaN: soft contact)", "units": "1"}),
    }
    for name, (x, attrs) in contact_vars.items():
        if x is not None:
            data[name] = _Var(("contact",), x, attrs)
    ds = xr.Dataset(
        {k: xr.Variable(v.dims, v.data, v.attrs) for k, v in data.items()},
        coords={k: xr.Variable(v.dims, v.data, v.attrs) for k, v in coords.items()},
        attrs=_attrs(run),
    )
    return ds


def run_to_xarray(run):
    """``Run.to_xarray()``: see there."""
    energy = None

    def frame_data(name: str, shape: tuple):
        nonlocal energy
        if name in ("u", "v"):
            return getattr(run, name)
        if name == "E_dissipated":
            return run.dissipated
        if energy is None:
            energy = run.energy()
        return energy[_ENERGIES[name]]

    return _dataset(run, frame_data)


def events_to_xarray(run):
    """``Run.events_to_xarray()``: see there."""
    ev = run.events
    n = len(ev["t"])
    kind = np.asarray(ev["kind"], dtype=str)
    if n == 0:
        kind = kind.astype("<U1")
    data = {
        "contact": xr.Variable(("event",), np.asarray(ev["contact"]).astype(np.int64), {
            "long_name": "contact index c (between beads c and c + 1; for wall events the bead "
                         "index)"}),
        "kind": xr.Variable(("event",), kind, {"long_name": "event kind"}),
        "rel_velocity": xr.Variable(("event",), np.asarray(ev["rel_velocity"]), {
            "long_name": "relative (approach) velocity at the event", "units": "1",
            "unit_system": "computer", "note": "SI: v / beta (m/s)"}),
        "peak_overlap": xr.Variable(("event",), np.asarray(ev["peak_overlap"]), {
            "long_name": "largest overlap while closed (0 for a closing event)", "units": "1",
            "unit_system": "computer", "note": "SI: metres, unchanged"}),
    }
    coords = {
        "event": xr.Variable(("event",), np.arange(n, dtype=np.int64),
                             {"long_name": "event number in the log"}),
        "time": xr.Variable(("event",), np.asarray(ev["t"]), {
            "long_name": "event time", "units": "1", "unit_system": "computer",
            "note": "SI: time * beta (s)"}),
    }
    if run.scene.units is not None:
        coords["time_si"] = xr.Variable(("event",), run.scene.units.time(ev["t"]),
                                        {"long_name": "event time", "units": "s"})
    return xr.Dataset(data, coords=coords, attrs=_attrs(run))


# --- the backend --------------------------------------------------------------------------


class _Frames:
    """Reads frames of one snapshot file for the lazy arrays.

    Other threads than the opener's (dask's workers) open the file once more for themselves, so
    that they read in parallel (one open file serves one read at a time).
    """

    def __init__(self, path: str, run):
        self.path = path
        self.run = run
        self._owner = threading.get_ident()
        self._local = threading.local()

    def _file(self):
        if self.run is None:
            raise ValueError(f"{self.path}: the dataset was closed")
        if threading.get_ident() == self._owner:
            return self.run._file
        f = getattr(self._local, "file", None)
        if f is None:
            f = self._local.file = _beadchain.load(self.path)["file"]
        return f

    def read(self, name: str, idx: np.ndarray) -> np.ndarray:
        """Variable ``name`` at frames ``idx`` (1-D int array): (k, M) or (k,)."""
        _, u, v, d = self._file().read([int(i) for i in idx])
        m = self.run._n
        if name == "u":
            return u.reshape(len(idx), m)
        if name == "v":
            return v.reshape(len(idx), m)
        if name == "E_dissipated":
            return d
        ke, pe = _beadchain.energies(self.run.scene._s, u, v)
        return {"E_kinetic": ke, "E_potential": pe, "E_total": ke + pe}[name]

    def close(self) -> None:
        self.run = None
        self._local = threading.local()


class _FrameArray(BackendArray):
    """Frame variable ``name`` of a snapshot file, shape (frames, beads) or (frames,): an index
    reads only the frames it selects."""

    def __init__(self, frames: _Frames, name: str, shape: tuple):
        self.frames, self.name = frames, name
        self.shape = shape
        self.dtype = np.dtype(np.float64)

    def __getitem__(self, key):
        return indexing.explicit_indexing_adapter(
            key, self.shape, indexing.IndexingSupport.OUTER, self._raw_indexing_method)

    def _raw_indexing_method(self, key: tuple) -> np.ndarray:
        idx = np.arange(self.shape[0])[key[0]]
        one = np.ndim(idx) == 0
        data = self.frames.read(self.name, np.atleast_1d(idx))
        # The frames are selected; the other axes' keys (outer indexing: at most one array
        # left, so plain NumPy indexing does it) apply to the rest.
        if one:
            return data[0][key[1:]]
        return data[(slice(None), *key[1:])]


def open_snapshot(path, drop_variables: Optional[Iterable[str]] = None,
                  group: Optional[str] = None):
    """The backend's ``open_dataset``: a snapshot file's dataset, frame variables lazy
    (``group="events"``: the event log's dataset)."""
    from ._run import load

    path = os.fspath(path)
    run = load(path)
    if group == "events":
        ds = events_to_xarray(run)
    elif group not in (None, "", "/"):
        raise ValueError(f"{path}: group: expected None or \"events\", got {group!r}")
    else:
        frames = _Frames(path, run)
        ds = _dataset(run, lambda name, shape: indexing.LazilyIndexedArray(
            _FrameArray(frames, name, shape)))
        ds.set_close(frames.close)
    if drop_variables:
        ds = ds.drop_vars(list(drop_variables), errors="ignore")
    return ds


class BeadchainBackendEntrypoint(BackendEntrypoint):
    """``xarray.open_dataset(path, engine="beadchain")``: a beadchain snapshot file (``.snap``,
    any format version ``beadchain.load`` reads) as the dataset of ``Run.to_xarray()``, with
    the frame variables (``u``, ``v``, ``E_*``) read lazily; ``group="events"`` gives the
    dataset of ``Run.events_to_xarray()``."""

    description = "beadchain snapshot files (.snap): frames, energies, chain, event log"
    open_dataset_parameters = ("filename_or_obj", "drop_variables", "group")

    def open_dataset(self, filename_or_obj, *, drop_variables=None, group=None):
        if not isinstance(filename_or_obj, (str, os.PathLike)):
            raise TypeError("engine=\"beadchain\" opens a snapshot file by its path, got "
                            f"{type(filename_or_obj).__name__}")
        return open_snapshot(filename_or_obj, drop_variables=drop_variables, group=group)

    def guess_can_open(self, filename_or_obj) -> bool:
        if not isinstance(filename_or_obj, (str, os.PathLike)):
            return False
        path = os.fspath(filename_or_obj)
        if str(path).endswith(".snap"):
            return True
        try:
            with open(path, "rb") as f:
                return f.read(len(_MAGIC)) == _MAGIC
        except OSError:
            return False
