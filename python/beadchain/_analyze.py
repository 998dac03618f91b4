"""``analyze()``: ``beadchain analyze``'s summary of a run or snapshot file (energies, the
leading wave's track, speed and decay fit, fragments, the interface split), DataFrame-ready."""

from __future__ import annotations

import operator
import os
from typing import Optional, Union

import numpy as np

from . import _beadchain
from ._run import Run


def analyze(run_or_path: Union[Run, str, os.PathLike], interface: Optional[int] = None,
            fit_from: Optional[float] = None, fit_to: Optional[float] = None) -> dict:
    """The summary ``beadchain analyze`` prints, of a :class:`Run` (from :func:`run`,
    :func:`load` or ``Simulation.frames()``) or of a snapshot file (a path), as a dict.

    Options (None: the CLI's default):

    - ``interface``: interface bead ``k`` (``1 <= k < N``): energy split at ``k`` in the
      final frame, the reflected pulse and ``|v_out/v_in|``; default None (no interface).
      Out of range: ``ValueError("interface must be in 1..N")``;
    - ``fit_from``: speed and decay fits over leading-wave positions ``>= fit_from`` beads;
      default 20, or ``k + 10`` with an interface;
    - ``fit_to``: ... and ``<= fit_to``; default ``N - 10``.

    Scalars (computer units): ``n``, ``frames``, ``t_first``, ``t_last``, ``e0``, ``e_end``,
    ``e_ref`` (``max(|E0|, energy scale)``), ``relative_change``, ``fit_from``/``fit_to`` (the
    range used), ``speed`` (beads per unit time) and ``speed_points``, ``decay`` (dict ``a``,
    ``gamma``, ``gamma_stderr``, ``r2``, ``points`` of ``E/E_ref = a exp(-gamma x)``),
    ``e_in`` (incoming wave energy), ``gaps``, ``fragments`` (count) and ``fragment_table``
    (columns ``first``, ``last``, ``mass``, ``velocity``), ``steady`` (appendix A criterion),
    ``interface`` (None, or a dict: ``k``, ``t``, ``energy_left``, ``energy_right``,
    ``energy_total``, ``reflected_fraction``, ``transmitted_fraction``,
    ``reflected_wave_energy``, ``reflected_first``/``reflected_last`` (None without a
    reflected pulse), ``v_in``, ``v_out``, ``velocity_ratio`` (None, with
    ``velocity_ratio_error``, where the frames do not resolve the two peaks: a pulse passing
    a bead in fewer than 3 frames), ``velocity_ratio_sampling_error`` (the error the frames'
    sampling leaves in a resolved ratio, estimated)). A value that cannot be
    computed is None and ``<key>_error`` says why (``<key>_error`` is None when the value is
    there); no NaN stands for a missing value. ``track``: the leading wave per frame, equal-length
    NumPy columns ``t``, ``position``, ``energy``, ``peak_velocity``, ``peak_bead``, ``first``,
    ``last``, ``width``: ``pandas.DataFrame(result["track"])``. A path also gives ``warnings``
    (the reader's, e.g. an unfinished file).

    The numbers are those of ``beadchain analyze --json`` on the same frames. A run or file
    without every bead's ``u`` and ``v`` (an output selection) raises ``ValueError``.
    """
    if interface is not None:
        try:
            interface = operator.index(interface)
        except TypeError:
            raise TypeError(f"interface: expected a bead index (an int), got "
                            f"{type(interface).__name__}") from None
        # a bead below 0 or past 2**63 is outside 1..N as 0 is: the library's ValueError
        interface = min(max(interface, -1), 2**63 - 1)
    if isinstance(run_or_path, Run):
        r = run_or_path
        if r.beads is not None or r.u is None or r.v is None:
            raise ValueError(
                f"{r.scene.name}: analyze needs every bead and both fields (energies, leading "
                "wave); this run stores an output selection"
            )
        t = np.ascontiguousarray(r.t, dtype=np.float64)
        u = np.ascontiguousarray(r.u, dtype=np.float64).reshape(-1)
        v = np.ascontiguousarray(r.v, dtype=np.float64).reshape(-1)
        return _beadchain._analyze(r.scene._s, t, u, v, interface=interface,
                                   fit_from=fit_from, fit_to=fit_to)
    return _beadchain._analyze_file(os.fspath(run_or_path), interface=interface,
                                    fit_from=fit_from, fit_to=fit_to)
