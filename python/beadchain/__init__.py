"""beadchain: one-dimensional granular chains with Hertz-like contacts, from Python.

A thin layer over the Rust library (the same parser, validator, engines and snapshot files as
the ``beadchain`` command)::

    import numpy as np, beadchain as bc
    scene = bc.Scene(mass=np.ones(1000), exponent=2.5, striker=1.0, until=800.0, every=10.0)
    r = bc.run(scene)                 # r.t (F,), r.u, r.v (F, N), r.events, r.stats
    e = r.energy()                    # kinetic, potential, total per frame
    s = bc.Scene.preset("interface_3.0_2.5")
    r = bc.run(s, every=10.0); r.v_si  # m/s (physical scenes)

See docs/python.md.
"""

from ._analyze import analyze
from ._beadchain import RunError, SceneError, SnapshotError, __version__
from ._run import Run, Simulation, State, Stop, load, run
from ._scene import Chain, Scene, Units, presets
from ._study import (SweepTable, accuracy, bands, breather, check, equilibrium, modal_energies,
                     modes, sweep, sweep_run, sweep_size)

__all__ = [
    "Chain", "Run", "RunError", "Scene", "SceneError", "Simulation", "SnapshotError", "State",
    "Stop", "Units", "__version__", "accuracy", "analyze", "bands", "breather", "check", "equilibrium", "load", "modal_energies",
    "modes", "presets",
    "run", "sweep", "sweep_run", "SweepTable",
    "sweep_size",
]
