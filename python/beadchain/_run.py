"""Runs: ``run()``, ``load()``, :class:`Run` (frames as NumPy arrays, events, stats, energies,
SI units) and :class:`Simulation` (the steppable engine)."""

from __future__ import annotations

import os
from typing import Any, Callable, Iterable, NamedTuple, Optional

import numpy as np

from . import _beadchain
from ._scene import (Scene, Units, _count, _html_table, _masked_data, _need_units,
                     _one_line, _scalar, _span)


_UNREAD = object()


class Run:
    """Frames of a run (or of a snapshot file) and what the engine reported.

    Attributes: ``t`` (F,), ``u`` and ``v`` (F, N) arrays in computer units (``u``/``v`` are
    None when a snapshot does not store that field; with an output selection N is the number of
    stored beads, listed in ``beads``); ``events``: a dict of columns (``t``, ``contact``,
    ``kind``, ``rel_velocity``, ``peak_overlap``) that ``pandas.DataFrame`` takes as it is;
    ``stats``: counters and energies; ``scene``: the :class:`Scene` that ran; ``dissipated``:
    energy dissipated up to each frame by damped contacts and hard collisions (scenes that can
    lose energy: a dissipative law or hard contacts/walls; None for the others and for snapshot
    files before format 4, which did not store it).
    A loaded snapshot reads its frames when ``u``/``v`` are first used; ``frames(index)`` reads
    only the frames asked for. ``meta``: the engine settings (``engine``, ``method``, ``rtol``,
    ``atol``) of :func:`run` and :func:`load` runs, and a snapshot's metadata (:func:`load`).
    ``to_xarray()`` and ``events_to_xarray()`` give ``xarray.Dataset`` objects.
    """

    def __init__(self, raw: dict, scene: Scene, meta: Optional[dict] = None, file: Any = None):
        self._n = raw["n"]
        self._file = file
        if file is None:
            self.t: np.ndarray = raw["t"]
            self._u = None if raw["u"] is None else raw["u"].reshape(len(self.t), self._n)
            self._v = None if raw["v"] is None else raw["v"].reshape(len(self.t), self._n)
        else:  # frames are read from the file when first used
            self.t = raw["times"]
            self._u = self._v = _UNREAD
        self._dissipative = raw.get("dissipative", False)
        self._dissipated = raw.get("dissipated") if file is None else _UNREAD
        ev = raw["events"]
        ev["kind"] = np.asarray(ev["kind"], dtype=str)
        self.events: dict = ev
        self.stats: dict = raw.get("stats") or {}
        self.beads: Optional[np.ndarray] = (
            None if raw.get("beads") is None else np.asarray(raw["beads"], dtype=np.int64)
        )
        self.scene: Scene = scene
        self.meta: dict = meta or {}

    @property
    def dissipated(self) -> Optional[np.ndarray]:
        """Energy dissipated from t = 0 up to each frame (F,), computer units: damped contacts
        and hard collisions (None when the scene cannot lose energy or the file predates
        format 4)."""
        if self._dissipated is _UNREAD:
            self._read_all()
        return self._dissipated

    def _read_all(self) -> None:
        if self._u is _UNREAD or self._dissipated is _UNREAD:
            _, u, v, d = self._file.read(list(range(len(self.t))))
            self._dissipated = d if self._dissipative else None
            shape = (len(self.t), self._n)
            self._u = None if u is None else u.reshape(shape)
            self._v = None if v is None else v.reshape(shape)

    @property
    def u(self) -> Optional[np.ndarray]:
        """Displacements (F, N) (a loaded snapshot reads its frames on first use)."""
        self._read_all()
        return self._u

    @property
    def v(self) -> Optional[np.ndarray]:
        """Velocities (F, N) (a loaded snapshot reads its frames on first use)."""
        self._read_all()
        return self._v

    def frames(self, index) -> tuple:
        """``(t, u, v)`` of the frames ``index`` (an int, slice or list of ints) without reading
        the others from a loaded snapshot (``u``/``v`` (k, N); None when not stored)."""
        idx = np.arange(len(self.t))[index]
        one = np.ndim(idx) == 0
        idx = np.atleast_1d(idx)
        if self._file is not None and self._u is _UNREAD:
            t, u, v, _ = self._file.read([int(i) for i in idx])
            shape = (len(idx), self._n)
            u = None if u is None else u.reshape(shape)
            v = None if v is None else v.reshape(shape)
        else:
            t = self.t[idx]
            u = None if self.u is None else self.u[idx]
            v = None if self.v is None else self.v[idx]
        if one:
            return t[0], None if u is None else u[0], None if v is None else v[0]
        return t, u, v

    def __len__(self) -> int:
        return len(self.t)

    def _stored(self) -> tuple:
        """``(u, v, dissipated)``: which per-frame arrays the run has, without reading a loaded
        snapshot's frames."""
        if self._file is not None and self._u is _UNREAD:
            _, u, v, _ = self._file.read([])
            dissipated = self._dissipative and self.meta.get("format_version", 0) >= 4
            return u is not None, v is not None, bool(dissipated)
        return self.u is not None, self.v is not None, self.dissipated is not None

    # --- xarray ---------------------------------------------------------------------------
    def to_xarray(self):
        """The run as an ``xarray.Dataset`` (needs ``pip install xarray``; docs/python.md).

        Dims ``time`` (frames) and ``bead`` (the stored beads), ``contact`` (N-1 contacts).
        Coordinates ``time`` (computer units), ``bead`` (0-based indices), ``contact``, and
        for physical scenes ``time_si`` (s). Data variables: ``u``, ``v`` (time, bead) when
        stored; ``E_kinetic``, ``E_potential``, ``E_total`` (time) when every bead's ``u`` and
        ``v`` are stored, ``E_dissipated`` (time) when :attr:`dissipated` is not None; the
        chain per bead (``mass``, and ``mass_si``, ``field`` where the scene has them) and per contact (``exponent``, ``prefactor``, ``precompression``, ``damping``,
        ``hard_restitution`` where present). Attributes: scene name and description, engine,
        method, rtol, atol (runs of :func:`run` and :func:`load`), until, every, the snapshot's
        metadata, ``stats_*``, and the unit scales ``units_beta``, ``units_m0``... of physical
        scenes; only str, int and float values (netCDF-safe, netCDF3 too: an integer outside
        32 bits as float64 where exact, else as decimal text). Every variable has ``units`` in
        its attributes (``"1"`` with ``unit_system = "computer"``: paper units).

        Eager: the variables are the Run's own arrays (no copy; a loaded snapshot's frames are
        read first). For lazy frames open the file with
        ``xarray.open_dataset(path, engine="beadchain")``. The event log is
        :meth:`events_to_xarray`.
        """
        from . import _xarray

        return _xarray.run_to_xarray(self)

    def events_to_xarray(self):
        """The event log as an ``xarray.Dataset`` on dim ``event``: coordinates ``event``
        (0, 1, ...), ``time`` (and ``time_si`` for physical scenes); variables ``contact``
        (int64), ``kind`` (str), ``rel_velocity``, ``peak_overlap``; the attributes of
        :meth:`to_xarray`. ``xarray.open_dataset(path, engine="beadchain", group="events")``
        gives the same from a snapshot file."""
        from . import _xarray

        return _xarray.events_to_xarray(self)

    def __getstate__(self) -> dict:
        """Pickled (and deep-copied) as its arrays: a loaded snapshot's frames are read first,
        the file itself is not part of the pickle."""
        if self._file is not None:
            self._read_all()
        state = dict(self.__dict__)
        state["_file"] = None
        return state

    def _summary(self) -> list:
        """``(label, text)`` rows of the one-line repr and the HTML table (a loaded snapshot's
        frames are not read)."""
        rows = [("scene", repr(self.scene.name)), ("frames", str(len(self.t)))]
        if len(self.t):
            rows.append(("t", _span(self.t)))
        rows += [("beads", str(self._n)), ("events", str(len(self.events["t"])))]
        for k in ("engine", "method", "rtol"):
            if self.meta.get(k) is not None:
                rows.append((k, f"{self.meta[k]:g}" if k == "rtol" else str(self.meta[k])))
        if self._file is not None:
            rows.append(("frames read", "no" if self._u is _UNREAD else "yes"))
        return rows

    def __repr__(self) -> str:
        """One line: scene, frame count and time span, stored beads, events, engine settings
        (the arrays are the attributes)."""
        return _one_line("Run", self._summary())

    def _repr_html_(self) -> str:
        return _html_table("Run", self._summary())

    # --- energies -------------------------------------------------------------------------
    def energy(self, units: str = "computer") -> dict:
        """Energy of every frame: ``kinetic``, ``potential`` (contacts, walls and field),
        ``total`` and, for dissipative runs, ``dissipated`` (up to the frame) and ``balance``
        (total + dissipated, constant up to the integration error). ``units="si"`` gives joules
        (physical scenes only)."""
        if self.u is None or self.v is None or self.beads is not None:
            raise _beadchain.SceneError(
                f"{self.scene.name}: energy() needs every bead's u and v in the frames "
                "(this snapshot stores an output selection)"
            )
        ke, pe = _beadchain.energies(self.scene._s, self.u.reshape(-1), self.v.reshape(-1))
        out = {"kinetic": ke, "potential": pe, "total": ke + pe}
        if self.dissipated is not None:
            out["dissipated"] = self.dissipated
            out["balance"] = out["total"] + self.dissipated
        if units == "si":
            scale = self._units("energy(units='si')")
            return {k: scale.energy(x) for k, x in out.items()}
        if units != "computer":
            raise ValueError(f"units: expected \"computer\" or \"si\", got {units!r}")
        return out

    def energy_si(self) -> dict:
        """``energy(units="si")``: joules."""
        return self.energy(units="si")

    # --- SI units -------------------------------------------------------------------------
    def _units(self, what: str) -> Units:
        return _need_units(self.scene.units, f"{self.scene.name}: {what}")

    @property
    def t_si(self) -> np.ndarray:
        """Frame times in seconds (``t * beta``; physical scenes only)."""
        return self._units("t_si").time(self.t)

    @property
    def u_si(self) -> Optional[np.ndarray]:
        """Displacements in metres (lengths are not rescaled; physical scenes only); None when
        the run does not store ``u`` (as :attr:`u`)."""
        units = self._units("u_si")
        return None if self.u is None else units.displacement(self.u)

    @property
    def v_si(self) -> Optional[np.ndarray]:
        """Velocities in m/s (``v / beta``; physical scenes only); None when the run does not
        store ``v`` (as :attr:`v`)."""
        units = self._units("v_si")
        return None if self.v is None else units.velocity(self.v)


def _progress_bar(name: str) -> Callable[[float, float], None]:
    """The bar of ``progress=True``: tqdm's (``tqdm.auto``) when tqdm is installed, else a
    one-line text bar on standard error (redrawn at most every 0.1 s). ``close()`` ends it."""
    return _Bar(name)


class _Bar:
    def __init__(self, name: str):
        self.name = name
        self.bar: Any = None
        self.t = 0.0
        self.until = 0.0
        self.drawn = 0.0

    def __call__(self, t: float, until: float) -> None:
        if self.bar is None:
            self.until = float(until)
            try:
                from tqdm.auto import tqdm
            except ImportError:
                self.bar = False
            else:
                self.bar = tqdm(total=self.until, desc=self.name, unit="t",
                                bar_format="{l_bar}{bar}| t={n:.4g}/{total:.4g} "
                                           "[{elapsed}<{remaining}]")
        t = min(max(float(t), self.t), self.until)
        if self.bar is False:
            self.t = t
            import time

            now = time.monotonic()
            if now - self.drawn >= 0.1 or t >= self.until:
                self.drawn = now
                self._draw()
        else:
            self.bar.update(t - self.t)
            self.t = t

    def _draw(self) -> None:
        import sys

        frac = self.t / self.until if self.until > 0 else 1.0
        k = int(30 * frac)
        sys.stderr.write(f"\r{self.name}: [{'#' * k}{'.' * (30 - k)}] {int(100 * frac):3d}% "
                         f"t={self.t:.4g}/{self.until:.4g}")
        sys.stderr.flush()

    def close(self) -> None:
        if self.bar is False:
            import sys

            self._draw()
            sys.stderr.write("\n")
            sys.stderr.flush()
        elif self.bar is not None:
            self.bar.close()


def run(
    scene: Scene | str | os.PathLike,
    engine: Optional[str] = None,
    method: Optional[str] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    every: Optional[float] = None,
    until: Optional[float] = None,
    out: Optional[str | os.PathLike] = None,
    record: bool = True,
    max_steps: Optional[int] = None,
    observers: Iterable[Callable[[float, np.ndarray, np.ndarray], Any]] = (),
    until_si: Optional[float] = None,
    every_si: Optional[float] = None,
    max_output_bytes: Optional[int] = None,
    progress: bool | Callable[[float, float], Any] = False,
) -> Run:
    """Runs ``scene`` to its end time and returns a :class:`Run`.

    ``scene``: a :class:`Scene`, a preset name (``run("striker")`` is
    ``run(Scene.preset("striker"))``; a misspelt name raises :class:`SceneError` naming the
    nearest presets) or a scene file (``pathlib.Path``, or a str ending in ``.toml``).

    Every option left at None takes the scene's ``[run]`` setting, else the CLI's default:

    - ``engine``: ``"hybrid"`` (default) or ``"dense"``;
    - ``method``: ``"auto"`` (default), ``"radau5"``, ``"dop853"`` or ``"verlet"``;
    - ``rtol``: 1e-8; ``atol``: rtol/1e4 (at least 1e-15), relative to the run's scales;
    - ``every``: output interval (default: first and last frame only);
    - ``until``: end time in computer units (the scene's ``[run] until``);
    - ``out``: also write the snapshot file ``beadchain run --out`` writes (None: no file;
      the scene file or a CSV file it reads raises :class:`SceneError`, as the CLI refuses);
    - ``record``: keep the frames in memory (False with ``out`` for long runs);
    - ``max_steps``: abort after this many accepted steps (None: no limit);
    - ``observers``: callables ``f(t, u, v)`` called at every frame;
    - ``until_si``, ``every_si``: ``until``/``every`` in seconds (physical scenes; the CLI's
      ``--until-si``/``--every-si``); giving both ``until`` and ``until_si`` is an error;
    - ``max_output_bytes``: the limit of the estimated output (default 10 GiB, the CLI's);
    - ``progress``: ``True`` draws a progress bar on standard error (tqdm's when tqdm is
      installed, else a text bar); a callable ``f(t, until)`` is called with the engine time at
      every frame, between frames at most every 0.2 s of wall time (never per step), and once
      at the end (``t`` = the end time). Its exception stops the run and is raised.

    The scene's ``[output]`` table applies as in ``beadchain run``: only its ``beads`` and
    ``fields`` are kept (in memory and in ``out``), and a run that would write more than its
    ``frames_max`` frames is refused before it starts. So is a run whose estimated output (the
    frames kept or written, ``beadchain run``'s estimate) is above ``max_output_bytes``; an
    allocation that fails anyway raises MemoryError.

    The GIL is released while the engine runs; Ctrl-C stops it and raises KeyboardInterrupt
    (an ``out`` file is then not written). Bad options raise :class:`SceneError` with the CLI's
    message; an engine failure raises :class:`RunError`.
    """
    scene = Scene._coerce(scene, "run")
    if out is not None and scene._file is not None:
        _beadchain._check_run_out(os.fspath(out), scene._file)
    if progress is True:
        bar = _progress_bar(scene.name)
        f: Optional[Callable] = bar
    elif progress is False or progress is None:
        bar = f = None
    elif callable(progress):
        bar, f = None, progress
    else:
        raise TypeError(f"run: progress: expected True, False or a callable f(t, until), got "
                        f"{type(progress).__name__}")
    try:
        raw = _run_raw(scene, f, engine, method, rtol, atol, every, until, out, record,
                       max_steps, observers, until_si, every_si, max_output_bytes)
        if f is not None:
            f(raw["stats"]["t_end"], raw["scene"].run_settings["until"])
    finally:
        if bar is not None:
            bar.close()
    ran = _ran_scene(scene, raw["scene"])
    keys = ("engine", "method", "rtol", "atol", "crate_version", "build_commit", "created_by")
    return Run(raw, ran, {k: raw[k] for k in keys})


def _ran_scene(given: Scene, ran) -> Scene:
    """The :class:`Scene` that ran (``ran``: ``given`` with ``[run]`` until/every as the run's
    options set them), its source ``given``'s with those values written in, so that
    ``source``, ``with_overrides`` and ``from_toml(source)`` are the scene that ran."""
    text = given._text
    before, after = given.run_settings, ran.run_settings
    until, every = (before[k] != after[k] for k in ("until", "every"))
    if text is not None and (until or every):
        text = ran._ran_source(text, until, every)
    return Scene._wrap(ran, text, given._dir)


def _run_raw(scene, progress, engine, method, rtol, atol, every, until, out, record, max_steps,
             observers, until_si, every_si, max_output_bytes) -> dict:
    return _beadchain.run(
        scene._s, engine=engine, method=method, rtol=_scalar("rtol", rtol),
        atol=_scalar("atol", atol), every=_scalar("every", every), until=_scalar("until", until),
        out=None if out is None else os.fspath(out), record=record,
        max_steps=_count("max_steps", max_steps), observers=list(observers),
        until_si=_scalar("until_si", until_si), every_si=_scalar("every_si", every_si),
        max_output_bytes=_count("max_output_bytes", max_output_bytes), progress=progress,
    )


def load(path: str | os.PathLike) -> Run:
    """Opens a snapshot file written by ``beadchain run`` (or ``run(out=...)``) as a
    :class:`Run`: the same numbers, bit for bit. Only the header, the frame times, the event
    log and the summary are read here; the frames when ``u``/``v`` are first used, or
    selected ones with ``Run.frames(index)``. ``meta`` holds the engine settings, the
    command that wrote it, its provenance (``crate_version``, ``build_commit`` and
    ``created_at``, None where the file does not record them), the format version and any
    reader warnings (an unfinished file)."""
    raw = _beadchain.load(os.fspath(path))
    keys = ("engine", "method", "rtol", "atol", "created_by", "crate_version", "build_commit",
            "created_at", "format_version", "complete", "warnings")
    return Run(raw, Scene._wrap(raw["scene"]), {k: raw[k] for k in keys}, file=raw["file"])


class Stop(NamedTuple):
    """Why :meth:`Simulation.advance` returned, at engine time ``t``: ``reason`` is
    ``"reached"`` (the requested time), ``"frame"`` (a frame was just recorded) or ``"event"``
    (a gap just opened or closed: ``event`` holds its log record ``t``, ``contact``, ``kind``,
    ``rel_velocity``, ``peak_overlap``) when :meth:`Simulation.pause_at` asked for it, or
    ``"requested"`` (an observer asked to stop). After any reason but ``"reached"``, advancing
    again goes on from there."""

    reason: str
    t: float
    event: Optional[dict] = None


class State(NamedTuple):
    """Every bead at time ``t``: displacements ``u`` and velocities ``v`` (N,)."""

    t: float
    u: np.ndarray
    v: np.ndarray

    def _summary(self) -> list:
        return [("t", f"{self.t:g}"), ("beads", str(len(self.u))), ("u", _span(self.u)),
                ("v", _span(self.v))]

    def __repr__(self) -> str:
        """One line: ``t``, the bead count and the ranges (min..max) of ``u`` and ``v``."""
        return _one_line("State", self._summary())

    def _repr_html_(self) -> str:
        return _html_table("State", self._summary())


class Simulation:
    """A scene advanced in pieces (the library's steppable engine).

    ``Simulation(scene, engine=None, method=None, rtol=None, atol=None, every=None,
    until=None, record=True, observers=(), until_si=None, every_si=None)``: options as
    :func:`run` (every bead and both fields are kept: ``[output]`` applies to :func:`run`).
    Then ``advance(t)``
    (returns a :class:`Stop`), ``state`` (a :class:`State`), ``set_velocities(v)`` between
    advances, ``add_observer(f)`` (``f(t, u, v)`` called at frames, not per step), ``stats()``
    and ``frames()`` (a :class:`Run` of the frames so far). Advancing in pieces gives the same
    frames as one :func:`run`, until a state is changed. After an engine failure the
    simulation stays failed (``advance`` raises :class:`RunError` naming the time) until
    ``set_velocities`` gives it a valid state; no frame is ever non-finite.
    """

    def __init__(self, scene: Scene | str | os.PathLike, engine: Optional[str] = None, method: Optional[str] = None,
                 rtol: Optional[float] = None, atol: Optional[float] = None,
                 every: Optional[float] = None, until: Optional[float] = None,
                 record: bool = True,
                 observers: Iterable[Callable[[float, np.ndarray, np.ndarray], Any]] = (),
                 until_si: Optional[float] = None, every_si: Optional[float] = None):
        scene = Scene._coerce(scene, "Simulation")
        self._sim = _beadchain.Simulation(
            scene._s, engine=engine, method=method, rtol=_scalar("rtol", rtol),
            atol=_scalar("atol", atol), every=_scalar("every", every),
            until=_scalar("until", until), record=record, observers=list(observers),
            until_si=_scalar("until_si", until_si), every_si=_scalar("every_si", every_si),
        )
        self.scene = _ran_scene(scene, self._sim.scene)
        self._chunks: list = []

    def _summary(self) -> list:
        engine, method, rtol, _, every = self._sim._settings
        return [("scene", repr(self.scene.name)), ("beads", str(self.scene.n_beads)),
                ("t", f"{self.time:g}"), ("until", f"{self.until:g}"), ("engine", engine),
                ("method", method), ("rtol", f"{rtol:g}"),
                ("every", "none" if every is None else f"{every:g}")]

    def __repr__(self) -> str:
        """One line: scene, beads, engine clock ``t``, end time and engine settings."""
        return _one_line("Simulation", self._summary())

    def _repr_html_(self) -> str:
        return _html_table("Simulation", self._summary())

    def pause_at(self, frames: bool = False, events: bool = False) -> None:
        """Makes later :meth:`advance` calls return after every frame (``frames``) and after
        every gap opening or closing (``events``; the hybrid engine logs events, the dense one
        does not). Pausing changes no number of the run: stepping event by event gives the
        frames and the event log of one :func:`run`. Default: no pauses."""
        self._sim.pause_at(frames=frames, events=events)

    def advance(self, until: Optional[float] = None) -> Stop:
        """Advances to ``until`` (default: the run's end time), or to the next pause
        (:meth:`pause_at`); returns why it stopped (:class:`Stop`). ``until`` must be a time
        from the engine clock (:attr:`time`: advancing to it returns at once) to the run's end
        (:attr:`until`): NaN, infinities, later or earlier times raise :class:`SceneError` (a
        ``ValueError``) naming the value and the range, and leave the simulation as it was."""
        reason, t, event = self._sim.advance(_scalar("until", until))
        return Stop(reason, t, event)

    @property
    def time(self) -> float:
        """The engine clock."""
        return self._sim.time

    @property
    def until(self) -> float:
        """The run's end time."""
        return self._sim.until

    @property
    def state(self) -> State:
        """Every bead at the engine clock."""
        return State(*self._sim.state)

    def set_velocities(self, v) -> None:
        """New velocities (N,) at the engine clock; the integration restarts there. ``v``: real
        numbers, one per bead (an array of another shape, a 1-D one of another length too, or
        of bools, complex numbers or objects, raises TypeError naming the shape or dtype; a
        masked value, a non-finite one or a kinetic energy that overflows SceneError)."""
        key = f"{self.scene.name}: set_velocities: v"
        if isinstance(v, np.ma.MaskedArray):
            v = _masked_data(key, v)
        a = np.asarray(v)
        n = self.scene.n_beads
        if a.dtype.kind not in "iuf":
            raise TypeError(f"{key}: expected real numbers (an array of shape ({n},)), got "
                            f"dtype {a.dtype}")
        if a.ndim != 1 or a.shape[0] != n:
            raise TypeError(f"{key}: expected an array of shape ({n},) (one velocity per bead), "
                            f"got shape {a.shape}")
        self._sim.set_velocities(np.ascontiguousarray(a, dtype=np.float64))

    def add_observer(self, f: Callable[[float, np.ndarray, np.ndarray], Any]) -> None:
        """Calls ``f(t, u, v)`` at every later frame."""
        self._sim.add_observer(f)

    def stats(self) -> dict:
        """Counters and energies at the engine clock (the keys of ``run().stats``, and
        ``t_reference``, ``energy_reference``, ``momentum_reference``, ``energy_injected``).

        ``relative_energy_error`` is measured from the last state :meth:`set_velocities` gave
        (before any, from t = 0): ``|E + E_d - E_ref - E_d,ref| / S``, so the energy a
        ``set_velocities`` call adds or removes is not counted as an integration error; it is
        summed in ``energy_injected``. ``energy_initial`` and ``momentum_initial`` stay those of
        t = 0; ``energy_reference`` and ``momentum_reference`` are those of the reference
        state, at ``t_reference``."""
        return self._sim.stats()

    def frames(self) -> Run:
        """The frames recorded so far, as a :class:`Run`."""
        raw = self._sim._take_frames()
        if len(raw["t"]) or not self._chunks:
            self._chunks.append(raw)
        if len(self._chunks) > 1:
            merged = dict(self._chunks[-1])
            for k in ("t", "u", "v"):
                merged[k] = np.concatenate([c[k] for c in self._chunks])
            dis = [c["dissipated"] for c in self._chunks if c["dissipated"] is not None]
            merged["dissipated"] = np.concatenate(dis) if dis else None
            merged["events"] = {
                k: np.concatenate([np.asarray(c["events"][k]) for c in self._chunks])
                for k in self._chunks[-1]["events"]
            }
            self._chunks = [merged]
        raw = dict(self._chunks[0])
        raw["events"] = {k: np.asarray(v) for k, v in raw["events"].items()}
        raw["stats"] = self.stats()
        return Run(raw, self.scene)
