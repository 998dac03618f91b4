"""A parameter study from Python: the energy a solitary wave leaves behind at an exponent
interface n1 = 3.0 -> n2, over n2 (paper Fig. 7's question, one row of its grid).

Each run is the preset `interface_3.0_2.5` with the exponent of contacts 50.. replaced
(`Scene.with_overrides`, with a sweep file's dotted key `chain.exponent.segments.0.value`); the
reflected energy is the library's interface split (`bc.analyze(run, interface=50)`, as
`beadchain analyze --interface 50`): the energy left of the interface at the end, kinetic and
potential, as a fraction of the total. A progress bar goes to standard error.

The runs are independent: a `concurrent.futures` executor spreads them over processes (pass
`--jobs N`); Dask's and Ray's executors take the same `executor.map` call.

    python examples/reflected_energy.py [--jobs N]
"""

import concurrent.futures as cf
import sys
import time

import beadchain as bc

N2 = [2.2, 2.4, 2.5, 2.6, 2.8, 3.0, 3.2, 3.5, 4.0]
INTERFACE = 50


def reflected(n2: float) -> tuple:
    """(n2, reflected energy fraction, steps) of one run."""
    base = bc.Scene.preset("interface_3.0_2.5")
    scene = base.with_overrides({"chain.exponent.segments.0.value": n2,
                                 "scene.name": f"interface_3.0_{n2}"})
    run = bc.run(scene, every=scene.until)   # first and last frame only
    split = bc.analyze(run, interface=INTERFACE)["interface"]
    return n2, float(split["reflected_fraction"]), run.stats["steps"]


def bar(done: int, total: int, t0: float) -> None:
    width = 30
    k = width * done // total
    sys.stderr.write(f"\r[{'#' * k}{'.' * (width - k)}] {done}/{total} "
                     f"{time.perf_counter() - t0:5.1f} s")
    sys.stderr.flush()


def main(argv: list) -> None:
    jobs = int(argv[argv.index("--jobs") + 1]) if "--jobs" in argv else 1
    t0 = time.perf_counter()
    rows = []
    if jobs > 1:
        with cf.ProcessPoolExecutor(max_workers=jobs) as ex:
            futures = [ex.submit(reflected, n2) for n2 in N2]
            for i, f in enumerate(cf.as_completed(futures), 1):
                rows.append(f.result())
                bar(i, len(N2), t0)
    else:
        for i, n2 in enumerate(N2, 1):
            rows.append(reflected(n2))
            bar(i, len(N2), t0)
    sys.stderr.write("\n")
    rows.sort()
    print(f"{'n2':>5}  {'reflected':>10}  {'steps':>6}")
    for n2, frac, steps in rows:
        print(f"{n2:5.2f}  {frac:10.3e}  {steps:6d}")
    same = dict((n2, f) for n2, f, _ in rows)[3.0]
    # n2 = n1: no interface, nothing is reflected (up to the wave's own tail).
    assert same < 5e-3, same
    assert max(f for _, f, _ in rows) > 10 * same


if __name__ == "__main__":
    main(sys.argv[1:])
