"""Executes examples/tour.ipynb headless (nbclient) and checks what it prints against the
library: the numbers are recomputed here with the package API, not read back from the notebook.

    python examples/run_notebook.py [--timeout SECONDS] [--save executed.ipynb] [--notebook X]

The kernel is this interpreter (`sys.executable`): a kernelspec named `python3` is written to a
temporary directory put first on JUPYTER_PATH for this process only (nothing is installed into
the user's or the environment's Jupyter directories), and an extra in-memory cell checks that
the kernel imported the same `beadchain` as this script. Needs nbclient, nbformat, ipykernel and
matplotlib. Exit status 0 and a last line `notebook: all checks passed` when every check holds.
"""

from __future__ import annotations

import json
import math
import os
import pathlib
import re
import sys
import tempfile
import time

NOTEBOOK = pathlib.Path(__file__).with_name("tour.ipynb")
if "--notebook" in sys.argv:   # another copy (the tests' mutants), run in examples/ all the same
    NOTEBOOK = pathlib.Path(sys.argv[sys.argv.index("--notebook") + 1]).resolve()


def kernel_dir(root: pathlib.Path) -> None:
    """A `python3` kernelspec running this interpreter, under root/kernels/python3."""
    spec = root / "kernels" / "python3"
    spec.mkdir(parents=True)
    (spec / "kernel.json").write_text(json.dumps({
        "argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
        "display_name": "Python 3 (run_notebook.py)", "language": "python",
    }))


def execute(timeout: int, save: str | None) -> tuple:
    """(stdout text of every code cell, joined; seconds)."""
    import nbformat
    from nbclient import NotebookClient

    nb = nbformat.read(str(NOTEBOOK), as_version=4)
    for cell in nb.cells:  # the committed notebook holds no outputs
        assert cell.cell_type != "code" or (not cell.outputs and cell.execution_count is None), \
            f"{NOTEBOOK.name}: cell {cell.get('id')} has stored outputs; regenerate it"
    nb.cells.append(nbformat.v4.new_code_cell(
        "import sys, beadchain\n"
        "print(f'kernel_python={sys.executable} beadchain_file={beadchain.__file__}')"))
    t0 = time.perf_counter()
    NotebookClient(nb, timeout=timeout, kernel_name="python3",
                   resources={"metadata": {"path": str(pathlib.Path(__file__).parent)}}).execute()
    seconds = time.perf_counter() - t0
    if save:
        nbformat.write(nb, save)
    text = "".join(o.get("text", "") for c in nb.cells if c.cell_type == "code"
                   for o in c.outputs if o.output_type == "stream" and o.name == "stdout")
    return text, seconds


def field(text: str, key: str) -> str:
    m = re.findall(rf"(?:^|\s){re.escape(key)}=(\S+)", text, flags=re.M)
    assert len(m) == 1, f"expected one '{key}=' in the notebook's output, found {len(m)}:\n{text}"
    return m[0]


def close(got: float, want: float, rel: float, what: str) -> None:
    assert math.isclose(got, want, rel_tol=rel, abs_tol=0.0), \
        f"{what}: notebook {got!r}, library {want!r}"


def check_interface(text: str) -> None:
    import beadchain as bc

    refl = float(field(text, "reflected_fraction"))
    trans = float(field(text, "transmitted_fraction"))
    run = bc.run(bc.Scene.preset("interface_3.0_2.5"), every=10.0)
    split = bc.analyze(run, interface=50)["interface"]
    close(refl, split["reflected_fraction"], 1e-12, "reflected_fraction")
    close(trans, split["transmitted_fraction"], 1e-12, "transmitted_fraction")
    assert 0.0 < refl < 1.0 and 0.0 < trans < 1.0, (refl, trans)
    assert abs(refl + trans - 1.0) < 1e-9, (refl, trans)
    # the value of validate --quick and tests/test_examples.py (0.529 of E0 at n2 = 2.5)
    assert abs(refl - 0.529) < 1e-3, refl
    print(f"part 1: reflected_fraction={refl:.6f} transmitted_fraction={trans:.6f} "
          "= analyze(run, interface=50) to 1e-12")


def short_disorder(seed: int):
    """The notebook's shortened disorder scene, built here independently."""
    import beadchain as bc

    text = bc.Scene.preset("disorder_2.5_0.04").source
    for old, new in (("seed = 1", f"seed = {seed}"), ("beads = 1000", "beads = 200"),
                     ("until = 33000.0", "until = 6000.0"), ("every = 150.0", "every = 20.0")):
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    scene = bc.Scene.from_toml(text)
    assert scene.seed == seed and scene.n_beads == 200 and scene.until == 6000.0
    return scene


def check_ensemble(text: str) -> None:
    import beadchain as bc

    seeds = [int(s) for s in field(text, "seeds").split(",")]
    gammas = [float(g) for g in field(text, "gammas").split(",")]
    mean, sem = float(field(text, "decay_rate_mean")), float(field(text, "sem"))
    assert len(seeds) >= 4 and len(set(seeds)) == len(seeds) == len(gammas), (seeds, gammas)
    want = []
    for seed, g in zip(seeds, gammas):
        a = bc.analyze(bc.run(short_disorder(seed)))
        assert a["decay"] is not None, (seed, a.get("decay_error"))
        want.append(a["decay"]["gamma"])
        close(g, want[-1], 1e-12, f"gamma of seed {seed}")
        assert g > 0.0, (seed, g)                  # the disordered chain takes energy away
    n = len(want)
    want_mean = sum(want) / n
    want_sem = math.sqrt(sum((x - want_mean) ** 2 for x in want) / (n - 1) / n)
    close(mean, want_mean, 1e-12, "decay_rate_mean")
    close(sem, want_sem, 1e-9, "sem")
    assert 0.0 < sem < mean, (mean, sem)           # the seeds differ; the mean is resolved
    print(f"part 2: {n} seeds, decay_rate_mean={mean:.4e} sem={sem:.1e} per bead "
          "= analyze()['decay']['gamma'] per seed to 1e-12")


def check_events(text: str) -> None:
    import beadchain as bc

    n = int(field(text, "events"))
    kinds = field(text, "first_kinds").split(",")
    times = [float(t) for t in field(text, "first_times").split(",")]
    whole = bc.run(bc.Scene.preset("striker"))
    log = whole.events
    assert n == len(log["t"]) > 0, (n, len(log["t"]))
    by_kind = whole.stats["events_by_kind"]
    opens, closes = int(field(text, "opens")), int(field(text, "closes"))
    assert (opens, closes) == (by_kind["open"], by_kind["close"]), (opens, closes, by_kind)
    assert opens + closes == n, (opens, closes, n)     # the striker chain has no walls
    assert len(kinds) == len(times) == min(5, n), (kinds, times)
    assert kinds == list(log["kind"][:len(kinds)]), (kinds, list(log["kind"][:5]))
    assert times == [float(t) for t in log["t"][:len(times)]], (times, log["t"][:5])
    assert times == sorted(times), times
    print(f"part 3: events={n} (opens={opens} closes={closes}), the first {len(kinds)} kinds "
          "and times = run()'s event log exactly")


def main(argv: list) -> None:
    timeout = int(argv[argv.index("--timeout") + 1]) if "--timeout" in argv else 300
    save = argv[argv.index("--save") + 1] if "--save" in argv else None
    with tempfile.TemporaryDirectory() as tmp:
        kernel_dir(pathlib.Path(tmp))
        os.environ["JUPYTER_PATH"] = os.pathsep.join(
            [tmp] + [p for p in os.environ.get("JUPYTER_PATH", "").split(os.pathsep) if p])
        text, seconds = execute(timeout, save)
    print(f"notebook: {NOTEBOOK.name} executed headless in {seconds:.1f} s")
    import beadchain as bc

    kernel = re.search(r"kernel_python=(\S+) beadchain_file=(\S+)", text)
    assert kernel, text
    assert kernel[2] == bc.__file__, (kernel[2], bc.__file__)
    t0 = time.perf_counter()
    check_interface(text)
    check_ensemble(text)
    check_events(text)
    print(f"notebook: checks recomputed in {time.perf_counter() - t0:.1f} s")
    print("notebook: all checks passed")


if __name__ == "__main__":
    main(sys.argv[1:])
