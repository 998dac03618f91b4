"""A Simulation and a loaded snapshot used, and dropped, on threads other than their own.

Before, both were pyo3 "unsendable" classes: a call from another thread raised (pyo3 panics
with "is unsendable, but sent to another thread"), and one collected by the garbage collector
on another thread (a reference cycle collected inside an executor's worker) was leaked with
an unraisable "is being dropped on another thread" error.
"""

import concurrent.futures as cf
import gc
import sys

import numpy as np

import beadchain as bc


def test_simulation_advances_on_another_thread():
    scene = bc.Scene.preset("striker")
    whole = bc.run(scene, every=5.0)
    sim = bc.Simulation(scene, every=5.0)
    with cf.ThreadPoolExecutor(max_workers=1) as ex:
        assert ex.submit(sim.advance, 33.0).result() == bc.Stop("reached", 33.0)
    assert sim.advance() == bc.Stop("reached", 100.0)
    r = sim.frames()
    np.testing.assert_array_equal(r.t, whole.t)
    np.testing.assert_array_equal(r.u, whole.u)
    np.testing.assert_array_equal(r.v, whole.v)


def test_loaded_snapshot_reads_on_another_thread(tmp_path):
    out = tmp_path / "s.bcs"
    bc.run(bc.Scene.preset("striker"), every=5.0, out=out)
    run = bc.load(out)
    with cf.ThreadPoolExecutor(max_workers=1) as ex:
        u = ex.submit(lambda: run.u).result()
    np.testing.assert_array_equal(u, bc.load(out).u)


def test_simulation_collected_on_another_thread_is_dropped():
    unraisable = []
    old, sys.unraisablehook = sys.unraisablehook, unraisable.append
    try:
        gc.collect()
        gc.disable()
        sim = bc.Simulation(bc.Scene(beads=10, striker=1.0, until=5.0))
        sim.advance(1.0)
        cycle = [sim]
        cycle.append(cycle)
        del sim, cycle
        with cf.ThreadPoolExecutor(max_workers=1) as ex:
            ex.submit(gc.collect).result()
    finally:
        gc.enable()
        sys.unraisablehook = old
    assert [str(u.exc_value) for u in unraisable] == []
