"""Type stubs of the compiled extension (python/src/*.rs). Use the `beadchain` package's
wrappers; these are its building blocks."""

from typing import Any, Callable, Optional, Sequence

import numpy as np
import numpy.typing as npt

__version__: str

class SceneError(ValueError): ...
class RunError(RuntimeError): ...
class SnapshotError(OSError): ...

_Array = npt.NDArray[np.float64]
_Observer = Callable[[float, _Array, _Array], Any]

class Scene:
    @staticmethod
    def _from_text(text: str, origin: str = "scene", base_dir: str = ".") -> Scene: ...
    @staticmethod
    def _from_tables(
        tables: dict[str, dict[str, Any]], origin: str = "scene", base_dir: str = "."
    ) -> tuple[Scene, str]: ...
    @staticmethod
    def _load(spec: str) -> Scene: ...
    @staticmethod
    def _preset(name: str) -> Scene: ...
    @property
    def name(self) -> str: ...
    @property
    def description(self) -> str: ...
    @property
    def n_beads(self) -> int: ...
    @property
    def seed(self) -> int: ...
    @property
    def warnings(self) -> list[str]: ...
    @property
    def u0(self) -> _Array: ...
    @property
    def v0(self) -> _Array: ...
    @property
    def run_settings(self) -> dict[str, Any]: ...
    @property
    def _chain(self) -> dict[str, Any]: ...
    @property
    def _units(self) -> Optional[dict[str, float]]: ...
    def to_toml(self) -> str: ...
    def _with_overrides(
        self, text: str, overrides: Sequence[tuple[str, Any]], base_dir: str
    ) -> tuple[Scene, str]: ...
    def _ran_source(self, text: str, until: bool, every: bool) -> Optional[str]: ...

class Simulation:
    def __init__(
        self,
        scene: Scene,
        engine: Optional[str] = None,
        method: Optional[str] = None,
        rtol: Optional[float] = None,
        atol: Optional[float] = None,
        every: Optional[float] = None,
        until: Optional[float] = None,
        record: bool = True,
        observers: Sequence[_Observer] = ...,
    ) -> None: ...
    def add_observer(self, f: _Observer) -> None: ...
    def pause_at(self, frames: bool = False, events: bool = False) -> None: ...
    def advance(self, until: Optional[float] = None) -> tuple[str, float, Optional[dict]]: ...
    @property
    def time(self) -> float: ...
    @property
    def until(self) -> float: ...
    @property
    def state(self) -> tuple[float, _Array, _Array]: ...
    def set_velocities(self, v: _Array) -> None: ...
    def stats(self) -> dict[str, Any]: ...
    def _take_frames(self) -> dict[str, Any]: ...
    @property
    def _settings(self) -> tuple[str, str, float, float, Optional[float]]: ...
    @property
    def scene(self) -> Scene: ...

class SnapshotFile:
    def __len__(self) -> int: ...
    def read(
        self, indices: Sequence[int]
    ) -> tuple[_Array, Optional[_Array], Optional[_Array], Optional[_Array]]: ...

def presets() -> list[tuple[str, str]]: ...
def _preset_toml(name: str) -> Optional[str]: ...
def _nearest_presets(name: str) -> list[str]: ...
def run(
    scene: Scene,
    engine: Optional[str] = None,
    method: Optional[str] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    every: Optional[float] = None,
    until: Optional[float] = None,
    out: Optional[str] = None,
    record: bool = True,
    max_steps: Optional[int] = None,
    observers: Sequence[_Observer] = ...,
    until_si: Optional[float] = None,
    every_si: Optional[float] = None,
    max_output_bytes: Optional[int] = None,
    progress: Optional[Callable[[float, float], Any]] = None,
) -> dict[str, Any]: ...
def load(path: str) -> dict[str, Any]: ...
def energies(scene: Scene, u: _Array, v: _Array) -> tuple[_Array, _Array]: ...
def breather(
    scene: Scene,
    frequency: float,
    mode: Optional[int] = None,
    seed_amplitude: float = 1e-3,
    step: float = 0.02,
    tol: float = 1e-11,
    rtol: float = 1e-12,
    floquet: bool = True,
    periods: float = 100.0,
) -> dict[str, Any]: ...
def modes(
    scene: Scene,
    about: str = "equilibrium",
    window: Optional[tuple[float, float]] = None,
    bins: Optional[int] = None,
) -> dict[str, Any]: ...
def bands(
    scene: Scene,
    cell: Optional[int] = None,
    start: int = 0,
    points: int = 201,
    about: str = "equilibrium",
) -> dict[str, Any]: ...
def _modal_energies(
    scene: Scene,
    t: _Array,
    u: _Array,
    v: _Array,
    what: str,
    about: str = "equilibrium",
    window: Optional[tuple[float, float]] = None,
) -> dict[str, Any]: ...
def _modal_energies_file(
    scene: Scene,
    path: str,
    about: str = "equilibrium",
    window: Optional[tuple[float, float]] = None,
) -> dict[str, Any]: ...
def equilibrium(scene: Scene, force: Optional[float] = None) -> dict[str, Any]: ...
def check(
    scene: Scene,
    method: Optional[str] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    until: Optional[float] = None,
    tol: Optional[float] = None,
) -> dict[str, Any]: ...
def _analyze(
    scene: Scene,
    t: _Array,
    u: _Array,
    v: _Array,
    interface: Optional[int] = None,
    fit_from: Optional[float] = None,
    fit_to: Optional[float] = None,
) -> dict[str, Any]:
    """``beadchain analyze``'s summary of frames ``t`` (F,), ``u``, ``v`` flat (F*N).
    Defaults: ``interface`` None (no interface split), ``fit_from`` 20 (or k + 10 with an
    interface k), ``fit_to`` N - 10. Keys as ``beadchain.analyze``; an interface outside
    1..N-1 raises ValueError("interface must be in 1..N")."""
def _analyze_file(
    path: str,
    interface: Optional[int] = None,
    fit_from: Optional[float] = None,
    fit_to: Optional[float] = None,
) -> dict[str, Any]:
    """``_analyze`` of a snapshot file's frames (every bead and both fields stored, else
    ValueError with the CLI's message), plus the reader's ``warnings``. Same defaults."""
def accuracy(
    scene: Scene,
    engines: Optional[Sequence[str]] = None,
    methods: Optional[Sequence[str]] = None,
    rtols: Optional[Sequence[float]] = None,
    verlet_steps: Optional[Sequence[float]] = None,
    atol_ratio: Optional[float] = None,
    until: Optional[float] = None,
    repeat: Optional[int] = None,
    reference_rtol: Optional[float] = None,
    max_steps: Optional[int] = None,
) -> dict[str, Any]: ...
def _sweep_spec(path: str) -> dict[str, Any]: ...
def _sweep_run(path: str, index: int) -> dict[str, Any]: ...
def _sweep_row(path: str, index: int) -> str: ...
def _sweep_reuse(path: str, out: str) -> dict[int, str]: ...
def _sweep_write(path: str, out: str, rows: Sequence[str]) -> bool: ...
def _sweep_table(path: str, rows: Sequence[str]) -> dict[str, list[Any]]: ...
