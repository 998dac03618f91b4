"""Scenes: from TOML (file or text), presets, or Python values; the resolved chain; units."""

from __future__ import annotations

import math
import operator
import os
from dataclasses import dataclass
from typing import Any, Mapping, Optional

import numpy as np

from . import _beadchain

# Keyword arguments of Scene(...) and the TOML table each belongs to (see docs/scenes.md).
_KEYS = {
    "scene": ("name", "description", "seed"),
    "chain": ("beads", "mass", "exponent", "prefactor", "precompression",
              "precompression_force", "precompression_force_si", "radius", "law", "damping",
              "damping_si", "restitution", "impact_speed", "impact_speed_si"),
    "initial": ("velocity", "displacement", "striker", "striker_right", "pulse", "velocity_si",
                "striker_si", "striker_right_si", "solitary", "equilibrium", "mode"),
    "field": ("force", "gravity", "force_si", "gravity_si"),
    "run": ("until", "every", "until_si", "every_si", "rtol", "atol", "method", "engine"),
}
_TABLES = ("walls", "units", "hard", "output")
_WHERE = {k: t for t, ks in _KEYS.items() for k in ks}


@dataclass(frozen=True)
class Units:
    """Unit scales of a physical scene (paper eqs. 10-11): time unit ``beta`` (s), mass unit
    ``m0`` (kg), ``mu`` (order of magnitude of the prefactor) and ``n0`` (typical exponent).

    Computer -> SI: time ``t * beta`` (s), velocity ``v / beta`` (m/s), displacement ``u`` (m,
    unchanged), energy ``E * m0 / beta**2`` (J), mass ``m * m0`` (kg), prefactor
    ``a * m0 / beta**2``. The values are the scene's own, in full precision (snapshot format 4
    stores them; files of formats 1-3 keep seven significant digits in the description), as
    the CLI's ``--units si`` uses.
    """

    beta: float
    m0: float
    mu: float
    n0: float

    def time(self, t):
        """SI time (s) of computer time ``t``."""
        return np.asarray(t) * self.beta

    def velocity(self, v):
        """SI velocity (m/s) of computer velocity ``v``."""
        return np.asarray(v) / self.beta

    def displacement(self, u):
        """SI displacement (m): lengths are not rescaled."""
        return np.asarray(u)

    def energy(self, e):
        """SI energy (J) of computer energy ``e``."""
        return np.asarray(e) * (self.m0 / self.beta**2)

    def mass(self, m):
        """SI mass (kg) of computer mass ``m``."""
        return np.asarray(m) * self.m0


@dataclass(frozen=True)
class Chain:
    """The resolved chain (computer units): ``mass`` (N,), ``exponent``, ``prefactor`` (N-1,),
    ``precompression`` (N-1,) or None, ``field`` (N,) or None, ``law`` ("elastic" or the damped
    law's name) and ``damping`` (N-1,) or None, walls (dicts or None), ``hard_restitution``
    (N-1,, NaN where the contact is soft) or None, ``units`` (:class:`Units`, physical scenes
    only) and ``radius``: the sphere radii in metres of a physical scene whose ``[units].radius``
    is one number or one per bead (None otherwise; dimensionless radii are folded into masses
    and prefactors)."""

    mass: np.ndarray
    exponent: np.ndarray
    prefactor: np.ndarray
    precompression: Optional[np.ndarray]
    field: Optional[np.ndarray]
    law: str
    damping: Optional[np.ndarray]
    damping_walls: Optional[tuple]
    left_wall: Optional[dict]
    right_wall: Optional[dict]
    hard_restitution: Optional[np.ndarray]
    collapse_interval: Optional[float]
    units: Optional[Units]
    radius: Optional[np.ndarray]

    @property
    def n_beads(self) -> int:
        return len(self.mass)

    def _summary(self) -> list:
        """``(label, text)`` rows of the one-line repr and the HTML table."""
        rows = [("beads", str(self.n_beads)), ("mass", _span(self.mass)),
                ("exponent", _span(self.exponent)), ("prefactor", _span(self.prefactor)),
                ("law", self.law)]
        if self.precompression is not None:
            rows.append(("precompression", _span(self.precompression)))
        if self.damping is not None:
            rows.append(("damping", _span(self.damping)))
        if self.field is not None:
            rows.append(("field", _span(self.field)))
        walls = [w for w, x in (("left", self.left_wall), ("right", self.right_wall)) if x]
        if walls:
            rows.append(("walls", "+".join(walls)))
        if self.hard_restitution is not None:
            rows.append(("hard contacts", str(int(np.isfinite(self.hard_restitution).sum()))))
        rows.append(("units", "physical" if self.units is not None else "computer"))
        return rows

    def __repr__(self) -> str:
        """One line: beads, mass, exponent and prefactor (one value or min..max), law, and
        what else the chain has; the arrays are its attributes."""
        return _one_line("Chain", self._summary())

    def _repr_html_(self) -> str:
        return _html_table("Chain", self._summary())

    def mass_si(self) -> np.ndarray:
        """Masses in kg (physical scenes)."""
        return _need_units(self.units, "mass_si").mass(self.mass)


def _span(x) -> str:
    """An array as one value (all equal) or ``min..max``; a scalar as itself."""
    a = np.asarray(x, dtype=float)
    a = a[~np.isnan(a)]
    if a.size == 0:
        return "nan"
    lo, hi = float(a.min()), float(a.max())
    return f"{lo:.6g}" if lo == hi else f"{lo:.6g}..{hi:.6g}"


def _one_line(cls: str, rows: list) -> str:
    """``Cls(label=text, ...)``: the one-line repr of ``(label, text)`` rows."""
    return f"{cls}(" + ", ".join(f"{k.replace(' ', '_')}={v}" for k, v in rows) + ")"


def _html_table(cls: str, rows: list) -> str:
    """A small HTML table of ``(label, text)`` rows (notebooks' ``_repr_html_``)."""
    import html

    body = "".join(
        f"<tr><th style='text-align:left'>{html.escape(k)}</th>"
        f"<td style='text-align:left'>{html.escape(str(v))}</td></tr>"
        for k, v in rows
    )
    return f"<table><caption style='text-align:left'><b>{html.escape(cls)}</b></caption>{body}</table>"


def _need_units(units: Optional[Units], what: str) -> Units:
    if units is None:
        raise _beadchain.SceneError(
            f"{what}: the scene is dimensionless (computer units only); SI values need a "
            'physical scene ([units] system = "physical")'
        )
    return units


def _masked_data(key: str, v: np.ma.MaskedArray) -> np.ndarray:
    """The data of a masked array; SceneError naming ``key`` when any value is masked."""
    mask = np.ma.getmaskarray(v)
    if mask.any():
        first = tuple(int(i) for i in np.argwhere(mask)[0]) if mask.ndim else ()
        where = f" (first at index {first[0] if len(first) == 1 else first})" if first else ""
        raise _beadchain.SceneError(
            f"{key}: expected numbers, got a masked array with {int(mask.sum())} masked "
            f"value(s){where}; fill them (.filled(x)) or leave them out"
        )
    return np.ma.getdata(v)


def _plain(key: str, v: Any) -> Any:
    """A keyword's value, checked: NumPy 0-d arrays as scalars, masked arrays
    as their data (refused when a value is masked); arrays of another shape, or values of
    another type, raise an error naming ``key`` and what was expected."""
    if isinstance(v, np.ma.MaskedArray):
        v = _masked_data(key, v)
    if isinstance(v, np.ndarray):
        if v.ndim == 0:
            return v.item()
        if v.ndim != 1:
            raise TypeError(f"{key}: expected a number or a 1-D array (one value per bead or "
                            f"contact), got an array of shape {v.shape}")
        if v.dtype.kind not in "biuf":
            raise TypeError(f"{key}: expected an array of numbers, got dtype {v.dtype}")
        return v
    if isinstance(v, Mapping):
        return {k: _plain(f"{key}.{k}", x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_plain(f"{key}[{i}]", x) for i, x in enumerate(v)]
    if v is None or isinstance(v, (bool, int, float, str, np.generic)):
        return v
    raise TypeError(f"{key}: expected a number, string, array, list or dict, got "
                    f"{type(v).__name__}")


def _scalar(key: str, x: Any) -> Any:
    """A scalar option (``every=``, ``until=``...): a NumPy 0-d array as its value, a masked
    one refused; an array of another shape raises TypeError naming ``key``."""
    if isinstance(x, np.ma.MaskedArray):
        x = _masked_data(key, x)
    if isinstance(x, np.ndarray):
        if x.ndim != 0:
            raise TypeError(f"{key}: expected a number, got an array of shape {x.shape}")
        return x.item()
    return x


def _count(key: str, x: Any) -> Optional[int]:
    """A count option (``max_steps=``, ``max_output_bytes=``, an index): None, or an integer
    >= 0. A whole float (``1e6``) is taken as its integer and a NumPy 0-d array as its value;
    another type raises TypeError, a negative, fractional or non-finite value ValueError, each
    naming ``key``."""
    x = _scalar(key, x)
    if x is None:
        return None
    if isinstance(x, (bool, np.bool_)):
        raise TypeError(f"{key}: expected an integer, got {x!r}")
    if isinstance(x, (float, np.floating)):
        if not (math.isfinite(x) and float(x).is_integer()):
            raise ValueError(f"{key} = {x!r} must be a whole number >= 0")
        x = int(x)
    else:
        try:
            x = operator.index(x)
        except TypeError:
            raise TypeError(f"{key}: expected an integer, got {type(x).__name__}") from None
    if x < 0:
        raise ValueError(f"{key} = {x} must be >= 0")
    if x >= 2**64:
        raise ValueError(f"{key} = {x} must be below 2**64")
    return x


def _scene_from_state(state: bytes, text: Optional[str], base_dir: str = ".") -> "Scene":
    """Unpickles a :class:`Scene` (see ``Scene.__reduce__``)."""
    return Scene._wrap(_beadchain.Scene._from_state(state), text, base_dir)


def _toml_plain(key: str, v: Any) -> Any:
    """An override value as plain Python (bool, int, float, str, lists, dicts): NumPy arrays as
    lists, NumPy scalars as their values (:func:`_plain`'s checks, naming ``key``)."""
    v = _plain(key, v)
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, Mapping):
        return {k: _toml_plain(f"{key}.{k}", x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_toml_plain(f"{key}[{i}]", x) for i, x in enumerate(v)]
    if v is None:
        raise TypeError(f"{key}: None is not a value (leave the key out instead)")
    return v


def _is_file_name(s: str) -> bool:
    """Whether ``Scene.from_toml``'s str argument names a file, not TOML text: one line that
    names an existing file or ends in ``.toml`` (a path may hold ``=`` or start with ``[``),
    or that has neither ``=`` nor a leading ``[`` (no TOML: a file, missing or not)."""
    if "\n" in s or "\r" in s:
        return False
    if s.lower().endswith(".toml") or os.path.isfile(s):
        return True
    return "=" not in s and not s.lstrip().startswith("[")


class Scene:
    """A validated scene: chain, initial state and run settings.

    Make one with :meth:`Scene.from_toml` (file path or TOML text), :meth:`Scene.preset`, or
    from Python values::

        Scene(mass=np.ones(1000), exponent=2.5, prefactor=1.0, striker=1.0, until=800.0)

    Keywords are the scene file's keys (docs/scenes.md): ``name``, ``description``, ``seed``;
    ``beads``, ``mass``, ``exponent``, ``prefactor``, ``precompression``, ``radius``, ``law``,
    ``damping``...; ``velocity``, ``displacement``, ``striker``, ``striker_right``, ``pulse``,
    ``solitary`` (a dict ``{"at": K, "velocity": v_m}`` or a list of them, docs/studies.md);
    ``force``, ``gravity``; ``until``, ``every``, ``rtol``, ``atol``, ``method``, ``engine`` (and
    their ``*_si`` twins); whole tables as dicts: ``walls``, ``units``, ``hard``, ``output``.
    Values are numbers, arrays (one per bead or per contact) or builder dicts. They are passed
    as tables (plain Python values, NumPy arrays as lists) to the same parser and validator as
    a scene file: bad values raise :class:`SceneError` (a ``ValueError``) with the CLI's
    one-line message naming the key, bead or contact; a value of another type (None inside a
    dict or list, an object) raises ``TypeError`` naming it. Keys whose value is None are left
    out. :attr:`source` is the TOML text of those tables.
    """

    # `_file`: the scene file it was read from (None otherwise): an output may not replace it
    __slots__ = ("_s", "_text", "_dir", "_file")

    def __init__(self, **kwargs: Any):
        tables: dict = {t: {} for t in (*_KEYS, *_TABLES)}
        origin = str(kwargs.get("name") or "scene")
        for k, v in kwargs.items():
            if v is None and (k in _TABLES or k in _WHERE):
                continue  # left out, as documented (units=None: no [units] table)
            if k in _TABLES:
                if not isinstance(v, Mapping):
                    raise TypeError(f"Scene(): {k} must be a dict (the [{k}] table)")
                tables[k] = _plain(f"{origin}: [{k}]", dict(v))
            elif k in _WHERE:
                tables[_WHERE[k]][k] = _plain(f"{origin}: [{_WHERE[k]}].{k}", v)
            else:
                raise TypeError(f"Scene(): unexpected keyword {k!r}")
        # Keys whose value is None are left out (a table's too: walls={"left": None}), and so
        # are tables with no keys.
        doc = {t: {k: _toml_plain(f"{origin}: [{t}].{k}", x) for k, x in items.items()
                   if x is not None}
               for t, items in tables.items() if items}
        self._s, self._text = _beadchain.Scene._from_tables(doc, origin, ".")
        self._dir = "."
        self._file = None

    @classmethod
    def _wrap(cls, s, text: Optional[str] = None, base_dir: str = ".") -> "Scene":
        obj = cls.__new__(cls)
        obj._s = s
        obj._text = text
        obj._dir = base_dir
        obj._file = None
        return obj

    @classmethod
    def from_toml(cls, path_or_text, name: Optional[str] = None) -> "Scene":
        """A scene from a TOML file (path) or from TOML text. A ``pathlib.Path`` (any
        ``os.PathLike``) is always a file; a str is a file when it is one line that names an
        existing file or ends in ``.toml`` (whatever characters the path holds, ``=`` or
        ``[`` included) or has no ``=`` and no leading ``[``, else TOML text. ``name`` names
        text in messages (default ``"scene"``; it is also the default scene name)."""
        if not isinstance(path_or_text, (str, os.PathLike)):
            raise TypeError(f"Scene.from_toml: expected a path or TOML text (str), got "
                            f"{type(path_or_text).__name__}")
        if isinstance(path_or_text, os.PathLike) or (
            isinstance(path_or_text, str) and _is_file_name(path_or_text)
        ):
            path = os.fsdecode(os.fspath(path_or_text))
            if not os.path.exists(path):
                raise _beadchain.SceneError(f"{path}: cannot read scene file: no such file")
            with open(path, encoding="utf-8") as f:
                text = f.read()
            scene = cls._wrap(_beadchain.Scene._load(path), text,
                              os.path.dirname(os.path.abspath(path)))
            scene._file = os.path.abspath(path)
            return scene
        text = str(path_or_text)
        return cls._wrap(_beadchain.Scene._from_text(text, name or "scene", "."), text)

    @classmethod
    def preset(cls, name: str) -> "Scene":
        """A built-in preset (``presets()`` lists them; the CLI's ``beadchain scenes``)."""
        return cls._wrap(_beadchain.Scene._preset(name), _beadchain._preset_toml(name))

    @property
    def name(self) -> str:
        return self._s.name

    @property
    def description(self) -> str:
        return self._s.description

    @property
    def n_beads(self) -> int:
        return self._s.n_beads

    @property
    def seed(self) -> int:
        return self._s.seed

    @property
    def warnings(self) -> list:
        """The validator's warnings (the CLI prints them as ``beadchain: warning: ...``)."""
        return self._s.warnings

    @property
    def u0(self) -> np.ndarray:
        """Initial displacements, shape (N,)."""
        return self._s.u0

    @property
    def v0(self) -> np.ndarray:
        """Initial velocities, shape (N,)."""
        return self._s.v0

    @property
    def run_settings(self) -> dict:
        """The ``[run]`` settings (None: the default applies)."""
        return self._s.run_settings

    @property
    def until(self) -> float:
        return self._s.run_settings["until"]

    @property
    def units(self) -> Optional[Units]:
        """Unit scales of a physical scene; None for a dimensionless one."""
        u = self._s._units
        return None if u is None else Units(**u)

    @property
    def is_physical(self) -> bool:
        return self.units is not None

    @property
    def chain(self) -> Chain:
        """The resolved chain (arrays in computer units; see :class:`Chain`)."""
        d = self._s._chain
        units = self.units
        return Chain(units=units, radius=self._radius(units), **d)

    def _radius(self, units: Optional[Units]) -> Optional[np.ndarray]:
        if units is None or self._text is None:
            return None
        try:
            import tomllib  # Python >= 3.11
        except ImportError:  # pragma: no cover
            return None
        r = tomllib.loads(self._text).get("units", {}).get("radius")
        if isinstance(r, (int, float)):
            return np.full(self.n_beads, float(r))
        if isinstance(r, list) and len(r) == self.n_beads:
            return np.asarray(r, dtype=float)
        return None

    @property
    def source(self) -> Optional[str]:
        """The TOML text this scene was made from (file, text, preset, or the tables of Python
        values written as TOML); None for a scene read from a snapshot."""
        return self._text

    def to_toml(self) -> str:
        """The resolved scene as TOML (every array written out)."""
        return self._s.to_toml()

    def with_overrides(self, overrides: Mapping[str, Any]) -> "Scene":
        """A new scene: this one's TOML source with the sweep's dotted keys written in, e.g.
        ``s.with_overrides({"chain.exponent.segments.0.value": 2.4, "scene.seed": 7})``.

        Keys and values as in a sweep file's ``[set]`` (docs/sweeps.md): ``"chain.exponent"`` is
        ``exponent`` in ``[chain]``, further parts walk into inline tables and numbers index
        arrays; values are numbers, strings, bools, lists, dicts or NumPy arrays. The sweep's
        own functions write them in (in the order given) and the scene parser and validator
        read the result, so every check and message is the sweep's: a key that cannot be
        written raises :class:`SceneError` naming it (``with_overrides: "chain.exponent.base":
        the base scene's `chain.exponent` is a number, not a table``), an unknown key the
        parser's (``with_overrides: (chain.beadz=3): striker: [chain].beadz: unknown key``).
        The name stays unless ``"scene.name"`` is given; CSV files resolve against the scene
        file's directory. A scene read from a snapshot (no source) starts from
        :meth:`to_toml`.
        """
        if not isinstance(overrides, Mapping):
            raise TypeError("with_overrides: expected a dict of dotted keys, e.g. "
                            f"{{'chain.exponent': 2.4}}, got {type(overrides).__name__}")
        items = []
        for k, v in overrides.items():
            if not isinstance(k, str):
                raise TypeError(f"with_overrides: keys are dotted scene keys such as "
                                f"'chain.exponent', got {k!r}")
            items.append((k, _toml_plain(f'with_overrides: "{k}"', v)))
        text = self._text if self._text is not None else self.to_toml()
        s, new_text = self._s._with_overrides(text, items, self._dir)
        return Scene._wrap(s, new_text, self._dir)

    def __repr__(self) -> str:
        return f"Scene(name={self.name!r}, n_beads={self.n_beads}, until={self.until})"

    def _repr_html_(self) -> str:
        rs = self.run_settings
        rows = [("name", self.name), ("description", self.description),
                ("beads", str(self.n_beads)), ("until", f"{self.until:g}"),
                ("every", "first and last frame" if rs.get("every") is None
                 else f"{rs['every']:g}"),
                ("units", "physical" if self.is_physical else "computer")]
        return _html_table("Scene", rows)

    @classmethod
    def _coerce(cls, scene: Any, what: str = "run") -> "Scene":
        """``scene`` as a :class:`Scene`: a Scene as it is; a path (``os.PathLike``, or a str
        ending in ``.toml``) reads that scene file; any other str names a preset
        (:meth:`preset`; a misspelt name gives the nearest ones)."""
        if isinstance(scene, Scene):
            return scene
        if isinstance(scene, os.PathLike) or (
            isinstance(scene, str) and scene.lower().endswith(".toml")
        ):
            return cls.from_toml(scene if isinstance(scene, os.PathLike) else str(scene))
        if isinstance(scene, str):
            if _beadchain._preset_toml(scene) is None:
                near = _beadchain._nearest_presets(scene)
                hint = ("did you mean " + " or ".join(repr(n) for n in near) + "?") if near \
                    else "presets() lists them"
                raise _beadchain.SceneError(
                    f"{what}: unknown preset {scene!r}; {hint} (a scene file needs a path "
                    "ending in .toml, or pathlib.Path)"
                )
            return cls.preset(scene)
        raise TypeError(f"{what}: scene: expected a Scene, a preset name or a .toml path, got "
                        f"{type(scene).__name__}")

    # --- pickling and equality ------------------------------------------------------------
    def __reduce__(self):
        """Pickled (and deep-copied) as the resolved scene's exact bytes (every array, the
        contact law, ``[run]`` and ``[output]``, the warnings) and its source text."""
        return (_scene_from_state, (self._s._state(), self._text, self._dir))

    def __eq__(self, other: object) -> bool:
        """Equal when the resolved scenes are (source text and origin aside)."""
        if not isinstance(other, Scene):
            return NotImplemented
        return bytes(self._s._state()) == bytes(other._s._state())

    def __hash__(self) -> int:
        return hash(bytes(self._s._state()))


def presets() -> list:
    """The built-in presets as a list of ``(name, description)``."""
    return _beadchain.presets()
