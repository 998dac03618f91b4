"""Overhead of the Python package against the CLI (issue 13): `beadchain.run()` and
`beadchain run` on the 1000-bead striker chain (n = 2.5, a = m = v0 = 1) to wave exit
(t = N/1.21 + 40), default tolerances, writing the same snapshot file.

Times, median of --repeat runs each (interleaved, in one invocation):
- CLI: the whole `beadchain run` process (start, scene parsing, run, snapshot written), and
  the engine's own wall clock (`--timing`, stored in the snapshot);
- Python: the `beadchain.run(scene, out=...)` call (the scene parsed beforehand), and the
  engine's wall clock from the run's stats; the same with frames kept in memory as arrays.

    python validation/peers/python_overhead.py [--cli target/release/beadchain] [--repeat 3]
        [--every 1.0]
"""

import argparse
import os
import statistics
import subprocess
import tempfile
import time

import beadchain as bc

N = 1000
UNTIL = N / 1.21 + 40.0
TOML = f"[chain]\nbeads = {N}\n[initial]\nstriker = 1.0\n[run]\nuntil = {UNTIL!r}\n"


def main() -> None:
    ap = argparse.ArgumentParser()
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--cli", default=os.path.join(here, "..", "..", "target", "release", "beadchain"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--every", type=float, default=None, help="output interval (default: first and last frame)")
    a = ap.parse_args()
    tmp = tempfile.mkdtemp()
    scene_path = os.path.join(tmp, "striker1000.toml")
    with open(scene_path, "w") as f:
        f.write(TOML)
    scene = bc.Scene.from_toml(scene_path)
    every = [] if a.every is None else ["--every", repr(a.every)]
    t = {k: [] for k in ("cli", "cli_engine", "py", "py_engine", "py_mem", "py_mem_engine")}
    for _ in range(a.repeat):
        out = os.path.join(tmp, "cli.snap")
        t0 = time.perf_counter()
        subprocess.run([a.cli, "run", scene_path, "--quiet", "--timing", "--out", out, *every],
                       check=True, stdout=subprocess.DEVNULL)
        t["cli"].append(time.perf_counter() - t0)
        t["cli_engine"].append(bc.load(out).stats["wall_seconds"])
        out = os.path.join(tmp, "py.snap")
        t0 = time.perf_counter()
        r = bc.run(scene, out=out, record=False, every=a.every)
        t["py"].append(time.perf_counter() - t0)
        t["py_engine"].append(r.stats["wall_seconds"])
        t0 = time.perf_counter()
        r = bc.run(scene, every=a.every)
        t["py_mem"].append(time.perf_counter() - t0)
        t["py_mem_engine"].append(r.stats["wall_seconds"])
    med = {k: statistics.median(v) for k, v in t.items()}
    print(f"1000-bead striker to t = {UNTIL:.1f}, every = {a.every}, {len(r.t)} frames, "
          f"median of {a.repeat}")
    print(f"{'':28}{'call/process s':>15}{'engine s':>10}")
    print(f"{'CLI beadchain run --out':28}{med['cli']:15.4f}{med['cli_engine']:10.4f}")
    print(f"{'Python run(out=...)':28}{med['py']:15.4f}{med['py_engine']:10.4f}")
    print(f"{'Python run() in memory':28}{med['py_mem']:15.4f}{med['py_mem_engine']:10.4f}")
    print(f"Python run(out=...) / CLI process: {med['py'] / med['cli']:.3f}; "
          f"engine time ratio: {med['py_engine'] / med['cli_engine']:.3f}")


if __name__ == "__main__":
    main()
