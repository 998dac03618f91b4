#!/usr/bin/env python3
"""Two beadchain binaries side by side: the integration time `beadchain run` prints, the binaries
alternated run by run in one invocation, median and fastest of --repeat runs each, and whether
their final frames and event logs are identical (a change meant to be bit-identical).

Usage: python3 validation/peers/compare_binaries.py OLD NEW [--repeat 11]
       [--case SCENE:RTOL ...]   (default: the peer scenes at a loose and a tight rtol)
"""
import argparse
import hashlib
import os
import re
import statistics
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_CASES = [
    os.path.join(HERE, "striker_1000.toml") + ":" + r
    for r in ("3e-3", "1e-3", "1e-6", "1e-10", "1e-12")
] + ["interface_3.0_2.5:1e-5", "interface_3.0_2.5:1e-6", "periodic_decay_2.5_2.555:1e-3",
     "periodic_decay_2.5_2.555:3e-5"]


def run(binary, scene, rtol, snap):
    out = subprocess.run([binary, "run", scene, "--rtol", rtol, "--out", snap],
                         capture_output=True, text=True, check=True).stdout
    return float(re.search(r" in ([0-9.eE+-]+) s:", out).group(1))


def digest(binary, snap):
    """Hash of the exported frames and event log, without the provenance comment lines
    (`#`: they name the snapshot file and the command line, which differ between the two runs)."""
    h = hashlib.sha256()
    for extra in ([], ["--events"]):
        out = subprocess.run([binary, "export", snap] + extra, capture_output=True,
                             check=True).stdout
        h.update(b"".join(l for l in out.splitlines(keepends=True) if not l.startswith(b"#")))
    return h.hexdigest()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--repeat", type=int, default=11)
    ap.add_argument("--case", action="append", help="SCENE:RTOL (repeatable)")
    args = ap.parse_args()
    print("| scene | rtol | old median / fastest (s) | new median / fastest (s) | new/old (fastest) "
          "| identical output |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        snaps = [os.path.join(tmp, "old.snap"), os.path.join(tmp, "new.snap")]
        for case in args.case or DEFAULT_CASES:
            scene, rtol = case.rsplit(":", 1)
            walls = ([], [])
            for _ in range(args.repeat):
                for k, b in enumerate((args.old, args.new)):
                    walls[k].append(run(b, scene, rtol, snaps[k]))
            same = digest(args.new, snaps[0]) == digest(args.new, snaps[1])
            cells = ["%.4f / %.4f" % (statistics.median(w), min(w)) for w in walls]
            # the printed time has 0.1 ms resolution: a run below it has no ratio
            ratio = "%.2f" % (min(walls[1]) / min(walls[0])) if min(walls[0]) > 0 else "—"
            print("| %s | %s | %s | %s | %s | %s |" % (
                os.path.basename(scene), rtol, cells[0], cells[1], ratio,
                "yes" if same else "NO"), flush=True)


if __name__ == "__main__":
    main()
