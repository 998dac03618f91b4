"""``check()`` (hybrid against the dense reference) and ``sweep()`` (a sweep file's runs, in
order, or through any ``concurrent.futures``-style executor)."""

from __future__ import annotations

import operator
import os
from typing import Any, Callable, Optional

import numpy as np

from . import _beadchain
from ._scene import Scene, _count


def check(scene: Scene | str | os.PathLike, method: Optional[str] = None,
          rtol: Optional[float] = None, atol: Optional[float] = None, until: Optional[float] = None,
          tol: Optional[float] = None) -> dict:
    """``beadchain check``: runs ``scene`` with the hybrid engine and with the dense reference
    and judges the difference against the scene's own sensitivity.

    Defaults as :func:`run` (``method="auto"``, ``rtol=1e-8``, ``atol=rtol/1e4``, the scene's
    ``until``); ``tol`` defaults to ``1000 * rtol``. Returns ``passed`` (bool), ``sensitive``,
    ``at_rest`` (the chain is at rest at the end: deviations relative to the scene's scales
    ``L``, ``V``, no leading-wave criterion), ``reference``, ``criteria`` (columns ``what``, ``value``, ``bound``, ``holds``:
    ``pandas.DataFrame(result["criteria"])``), ``deviation`` and ``sensitivity`` (largest
    ``du``, ``dv`` and where).
    """
    scene = Scene._coerce(scene, "check")
    return _beadchain.check(scene._s, method=method, rtol=rtol, atol=atol, until=until, tol=tol)


def sweep_run(path: str | os.PathLike, index: int) -> dict:
    """Runs point ``index`` of the sweep file ``path``: one result row (a dict), the values
    ``beadchain sweep`` writes for it; the swept values as numbers (``int`` or ``float``, as the
    sweep file gives them). Each point is independent of the others, so this is a function to
    hand to an executor."""
    return _beadchain._sweep_run(os.fspath(path), _count("sweep_run: index", index))


def sweep_size(path: str | os.PathLike) -> int:
    """Number of runs of a sweep file (every run's scene is built and checked)."""
    return _beadchain._sweep_spec(os.fspath(path))["runs"]


def _sweep_row(path: str, index: int) -> str:
    """Point ``index``'s CSV row, the bytes ``beadchain sweep`` writes (what :func:`sweep` hands
    to an executor: a module-level function, picklable)."""
    return _beadchain._sweep_row(path, int(index))


class SweepTable(dict):
    """:func:`sweep`'s result: the columns (a ``dict``, ready for ``pandas.DataFrame``), with
    ``skipped`` (runs whose result the ``out`` file already held: not run again), ``ran`` (runs
    done now) and ``written`` (whether ``out`` was written; False when it already held these
    bytes or without ``out``)."""

    skipped: int = 0
    ran: int = 0
    written: bool = False


def _column(vals: list) -> Any:
    """A column as a NumPy array when every value is an int (int64), a number (float64) or a
    bool; else the list (text, or None where a value is missing)."""
    if not vals:
        return np.asarray(vals)
    if all(isinstance(v, bool) for v in vals):
        return np.asarray(vals, dtype=bool)
    if any(v is None or isinstance(v, (bool, str)) for v in vals):
        return vals
    if all(isinstance(v, int) for v in vals):
        return np.asarray(vals, dtype=np.int64)
    if all(isinstance(v, (int, float)) for v in vals):
        return np.asarray(vals, dtype=np.float64)
    return vals


def sweep(path: str | os.PathLike, executor: Any = None,
          progress: Optional[Callable[[int, int], Any]] = None,
          out: Optional[str | os.PathLike] = None) -> SweepTable:
    """Runs every point of the sweep file ``path`` (docs/sweeps.md) and returns the results
    as columns (``run``, one column per swept key, ``status``, ``t_end``, ``energy_error``,
    ``steps``, ``events`` and the ``[measure]`` columns), ready for ``pandas.DataFrame``.

    Swept keys and seeds are numbers: an int64 array where every value is an integer, float64
    where they are numbers (a list where they are text, or where a point leaves a key out:
    None there). Counts (``steps``, ``events``, ``fragments``) are int64, the rest float64 (a
    list with None where an error row has no value).

    ``executor``: None runs the points here one after the other (the GIL is released while
    each runs); any object with ``map(fn, *iterables)`` spreads them: a
    ``concurrent.futures.ThreadPoolExecutor`` or ``ProcessPoolExecutor``, Dask's
    ``distributed.Client.get_executor()``, or Ray's ``ray.util.multiprocessing.Pool``-style
    executors. ``progress(done, total)`` is called after each point (without an executor).

    ``out``: also write the CLI's result file, the bytes of ``beadchain sweep PATH --out OUT``
    (``OUT`` and ``OUT.meta``), and resume by content as the CLI does: points whose result
    ``OUT`` already holds (the same resolved scene, run settings and measures) are not run
    again (``result.skipped``); a file that already holds the result is not rewritten. An
    ``OUT`` or ``OUT.meta`` that is the sweep file, its base scene or a CSV file that reads
    raises :class:`SceneError` before any point runs.

    A bad sweep file raises :class:`SceneError` before anything runs.
    """
    path = os.path.abspath(os.fspath(path))
    spec = _beadchain._sweep_spec(path)
    n = spec["runs"]
    dest = None if out is None else os.fspath(out)
    if dest is not None:
        _beadchain._sweep_check_out(path, dest)
    rows: dict = {} if dest is None else dict(_beadchain._sweep_reuse(path, dest))
    skipped = len(rows)
    todo = [i for i in range(n) if i not in rows]
    if executor is None:
        for i in todo:
            rows[i] = _sweep_row(path, i)
            if progress is not None:
                progress(len(rows), n)
    else:
        rows.update(zip(todo, executor.map(_sweep_row, [path] * len(todo), todo)))
    ordered = [rows[i] for i in range(n)]
    written = False if dest is None else _beadchain._sweep_write(path, dest, ordered)
    table = SweepTable({c: _column(v) for c, v in _beadchain._sweep_table(path, ordered).items()})
    table.skipped, table.ran, table.written = skipped, len(todo), bool(written)
    return table


def accuracy(scene: Scene | str | os.PathLike, engines: Optional[list] = None,
             methods: Optional[list] = None, rtols: Optional[list] = None,
             verlet_steps: Optional[list] = None,
             atol_ratio: Optional[float] = None, until: Optional[float] = None,
             repeat: Optional[int] = None, reference_rtol: Optional[float] = None,
             max_steps: Optional[int] = None) -> dict:
    """``beadchain accuracy``: the work-precision study of ``scene`` against a tight dense
    Radau IIA reference (docs/benchmarks.md). None keeps the CLI's default: ``engines``
    ["hybrid", "dense"], ``methods`` ["radau5", "dop853", "verlet"], ``rtols`` [1e-4, 1e-6,
    1e-8, 1e-10], ``verlet_steps`` [0.1, 0.03, 0.01, 0.003] (in tau = L/V), ``atol_ratio``
    none (each run's atol is what ``run`` uses at that rtol: the scene's, else rtol/1e4),
    ``until`` the scene's, ``repeat`` 1, ``reference_rtol`` the smallest rtol.

    Returns ``rows`` (columns ``engine``, ``method``, ``rtol``, ``atol``, ``err_u``, ``err_v``,
    ``error``, ``energy_error``, ``wall_seconds``, ``steps``, ...: ``pandas.DataFrame(r["rows"])``),
    ``reference``, ``until``, ``tau`` and ``notes``. Writes no file.
    """
    scene = Scene._coerce(scene, "accuracy")
    return _beadchain.accuracy(scene._s, engines=engines, methods=methods, rtols=rtols,
                               verlet_steps=verlet_steps, atol_ratio=atol_ratio, until=until,
                               repeat=_count("repeat", repeat), reference_rtol=reference_rtol,
                               max_steps=_count("max_steps", max_steps))


def _int_arg(key: str, x: Any) -> Optional[int]:
    """``x`` as an integer the extension takes: a ValueError naming ``key`` beyond 62 bits (the
    extension's 64-bit argument raised an unnamed OverflowError)."""
    if x is None:
        return None
    x = operator.index(x)
    if not -2**62 <= x <= 2**62:
        raise ValueError(f"{key} = {x}: out of range")
    return x


def modes(scene: Scene | str | os.PathLike, about: str = "equilibrium",
          window: Optional[tuple] = None, bins: Optional[int] = None) -> dict:
    """``beadchain modes``: the linear modes of ``scene``'s chain about its static equilibrium
    (``about="initial"``: about its initial displacements), docs/studies.md.

    Returns ``omega`` (angular frequencies, increasing), ``omega2``, ``index``, ``shapes``
    (N × M displacements, ``xᵀ M x = 1``), ``participation`` (``(Σx²)²/(N Σx⁴)``),
    ``dos_edges``/``dos_counts`` (density of states, ``bins`` bins), ``mass``, ``overlap``,
    ``stiffness`` (``n(n−1)aδ^{n−2}``, 0 where ``δ <= 0``), ``wall_stiffness``, ``ends`` (the
    boundary conditions in words), ``open_contacts`` and ``state``. ``window=(lo, hi)`` keeps
    the modes with ``lo <= omega <= hi``.
    """
    scene = Scene._coerce(scene, "modes")
    w = None if window is None else (float(window[0]), float(window[1]))
    return _beadchain.modes(scene._s, about=about, window=w, bins=_int_arg("bins", bins))


def bands(scene: Scene | str | os.PathLike, cell: Optional[int] = None, start: int = 0,
          points: int = 201, about: str = "equilibrium") -> dict:
    """``beadchain plot dispersion``'s band structure of ``scene``'s periodic chain: the unit
    cell of ``cell`` beads from bead ``start`` (default: the smallest period of the masses and
    contact stiffnesses) of the chain linearised about its static equilibrium
    (``about="initial"``: its initial displacements), with Bloch conditions, docs/studies.md.

    Returns ``q`` (``points`` wavenumbers per cell on [0, π]), ``omega`` (bands × points,
    angular frequencies), ``edges`` (bands × 2: each band's lowest and highest ω, at q = 0 and
    π), ``gaps`` (k × 2: the top of one band and the bottom of the next, where they do not
    overlap), and the cell's ``mass`` and ``stiffness``.
    """
    scene = Scene._coerce(scene, "bands")
    return _beadchain.bands(scene._s, cell=_int_arg("cell", cell), start=_int_arg("start", start),
                            points=_int_arg("points", points),
                            about=about)


def modal_energies(scene: Scene | str | os.PathLike, run: Any, about: str = "equilibrium",
                   window: Optional[tuple] = None) -> dict:
    """``beadchain modes SCENE --snapshot RUN.snap``: the energy of each linear mode of
    ``scene``'s chain (about its static equilibrium; ``about="initial"``: its initial
    displacements; ``window=(lo, hi)``: only those modes) in every frame of ``run``, a
    :class:`Run` or a snapshot file's path (every bead and both fields stored), docs/studies.md.

    With the mass-orthonormal modes ``x_j``: ``q_j = x_jᵀ M (u − u*)``, ``q̇_j = x_jᵀ M v``,
    ``E_j = ½ (q̇_j² + ω_j² q_j²)``. Returns ``t`` (F,), ``energy`` (F, M): ``E_j`` per frame,
    ``harmonic`` (F,): ``½ vᵀMv + ½ (u − u*)ᵀK(u − u*)``, which ``energy.sum(axis=1)`` equals
    (Parseval) when every mode is kept, ``total`` (F,): the chain's full energy above ``u*``
    at rest, ``omega`` and ``index`` (M,). A run of another bead count raises
    :class:`SceneError` naming the file (or the run's scene).
    """
    scene = Scene._coerce(scene, "modal_energies")
    w = None if window is None else (float(window[0]), float(window[1]))
    if isinstance(run, (str, os.PathLike)):
        return _beadchain._modal_energies_file(scene._s, os.fspath(run), about=about, window=w)
    what = f"run of {run.scene.name}"
    if run.u is None or run.v is None or run.beads is not None:
        raise _beadchain.SceneError(
            f"{what}: modal energies need every bead and both fields stored")
    return _beadchain._modal_energies(
        scene._s, np.ascontiguousarray(run.t, dtype=float),
        np.ascontiguousarray(run.u, dtype=float).ravel(),
        np.ascontiguousarray(run.v, dtype=float).ravel(), what, about=about, window=w)


def breather(scene: Scene | str | os.PathLike, frequency: float, mode: Optional[int] = None,
             seed_amplitude: float = 1e-3, step: float = 0.02, tol: float = 1e-11,
             rtol: float = 1e-12, floquet: bool = True, periods: float = 100.0) -> dict:
    """``beadchain breather``: a discrete breather of ``scene``'s chain at angular frequency
    ``frequency`` (e.g. in a band gap) by Newton's method on the period map (dense engine,
    DOP853 at ``rtol``), continued in frequency from linear mode ``mode`` (default: the mode
    nearest the frequency), docs/studies.md.

    Returns ``frequency``, ``period``, ``mode``, ``mode_frequency``, ``u`` (displacements at
    t = 0; the breather starts from rest), ``amplitude``, ``residual`` (period map, max-norm),
    ``half_residual``, ``steps``, ``runs``; with ``floquet``: ``multipliers`` (complex, by
    decreasing modulus), ``max_modulus`` (other than the pair at 1), ``stable``,
    ``reciprocity_error``, ``unit_pair_error`` (|mean − 1|, |product − 1| of the pair at 1),
    ``unit_pair_vectors`` (the residuals of its time-shift and energy vectors,
    |M ẋ − ẋ|/|ẋ| and |∇Hᵀ M − ∇Hᵀ|/|∇H|); ``scene``: the scene with the breather as its
    initial state, ``periods`` periods with the dense engine (``scene_toml``: its TOML).
    """
    scene = Scene._coerce(scene, "breather")
    d = _beadchain.breather(scene._s, float(frequency), mode=mode,
                            seed_amplitude=float(seed_amplitude), step=float(step),
                            tol=float(tol), rtol=float(rtol), floquet=bool(floquet),
                            periods=float(periods))
    d["scene"] = Scene.from_toml(d["scene_toml"], name=scene.name + "_breather")
    return d


def equilibrium(scene: Scene | str | os.PathLike, force: Optional[float] = None) -> dict:
    """The static equilibrium of ``scene``'s chain under its walls and field (as
    ``[initial] equilibrium = true``; ``force``: the left wall's force, as ``[walls] force``).

    Returns ``u``, ``contact_force``, ``wall_force`` (left, right; ``None`` without a wall),
    ``gaps`` (contacts without force), ``iterations`` and ``right_precompression``. An
    impossible balance raises :class:`SceneError`.
    """
    scene = Scene._coerce(scene, "equilibrium")
    return _beadchain.equilibrium(scene._s, force=force)
