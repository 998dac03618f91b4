#!/usr/bin/env python3
"""The cost of a gap event: two beadchain binaries side by side on the event-bound workloads.

Runs every scene with every binary (alternating, median of --repeat runs of the time `run`
prints: integration only) and writes a Markdown table to stdout (and --csv): time, time per
collision, integration steps, rejected steps, exact two-body contacts (binaries that have them),
energy error |E_end - E_0|/E_0, and, for the gapped chain with gaps of 1 (every collision an
isolated equal-mass exchange), the final velocities' largest deviation from the exact result
(all beads at rest but the last, which leaves at the striker's speed).

    python3 validation/peers/event_cost.py --old OLD_BINARY [--new target/release/beadchain]
        [--rtol R] [--new-rtol R_NEW] [--scenes A,B] [--hard]

--hard adds, per scene, the new binary on the same scene with `[hard] contacts = "all"`
(instantaneous elastic collisions: beadchain's own event-driven limit, the cost of an event
without any integration; its collision count differs, as a soft contact lasts a while).

Scenes: validation/peers/scenes/*.toml (the issue's workloads) and the presets gapped_chain and
granular_gas. No third-party packages.
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = [
    os.path.join(HERE, "scenes", "pair_2.5.toml"),
    os.path.join(HERE, "scenes", "gapped_10k_1.0.toml"),
    os.path.join(HERE, "scenes", "gapped_10k_0.1.toml"),
    os.path.join(HERE, "scenes", "gas_10k.toml"),
    "gapped_chain",
    "granular_gas",
]


def run_once(binary, scene, rtol, out):
    """One `run`: returns the parsed summary and the final velocities (wide export)."""
    args = [binary, "run", scene, "--out", out]
    if rtol:
        args += ["--rtol", rtol]
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"{binary} run {scene}: {p.stderr.strip()}")
    text = p.stdout
    r = {}
    m = re.search(r"in ([0-9.]+) s: (\d+) steps \((\d+) rejected\)", text)
    r["time"], r["steps"], r["rejected"] = float(m.group(1)), int(m.group(2)), int(m.group(3))
    m = re.search(r"events: (.*)", text)
    ev = dict((k, int(v)) for k, v in re.findall(r"(\w+) (\d+)", m.group(1))) if m else {}
    r["collisions"] = ev.get("close", 0) + ev.get("hard_collision", 0)
    m = re.search(r"exact two-body contacts: (\d+) \((\d+) handed", text)
    r["exact"] = f"{m.group(1)} ({m.group(2)})" if m else "-"
    m = re.search(r"energy ([0-9.e+-]+) -> ([0-9.e+-]+)", text)
    e0, e1 = float(m.group(1)), float(m.group(2))
    r["energy_error"] = abs(e1 - e0) / e0
    return r


def final_velocities(binary, snap):
    p = subprocess.run([binary, "export", snap, "--layout", "wide"],
                       capture_output=True, text=True, check=True)
    rows = [l for l in p.stdout.splitlines() if l and not l.startswith("t")]
    last = [float(x) for x in rows[-1].split(",")]
    n = (len(last) - 1) // 2
    return last[1 + n:]


def hard_variant(scene, d):
    """The scene with every contact hard (a copy in `d`); refused where it sets [hard] itself."""
    with open(scene) as f:
        text = f.read()
    if re.search(r"^\s*\[hard\]", text, re.M):
        raise SystemExit(f"{scene}: already has a [hard] table; --hard adds its own")
    out = os.path.join(d, os.path.basename(scene).removesuffix(".toml") + "_hard.toml")
    with open(out, "w") as f:
        f.write(text.rstrip("\n") + '\n[hard]\ncontacts = "all"\n')
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--old", required=True, help="the binary before (path)")
    ap.add_argument("--new", default=os.path.join(HERE, "..", "..", "target", "release", "beadchain"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--rtol", default=None, help="passed to every run (default: the scene's)")
    ap.add_argument("--new-rtol", default=None,
                    help="the new binary's rtol instead of --rtol (a comparison at equal or better "
                         "error, where the new binary is more accurate at the same rtol)")
    ap.add_argument("--scenes", default=None, help="comma-separated subset (paths or presets)")
    ap.add_argument("--csv", default=None)
    ap.add_argument("--hard", action="store_true",
                    help="also run the new binary with [hard] contacts = \"all\" (the hard-contact limit)")
    a = ap.parse_args()
    scenes = a.scenes.split(",") if a.scenes else SCENES
    bins = [("old", a.old), ("new", a.new)]
    rtols = {"old": a.rtol, "new": a.new_rtol or a.rtol}
    rows = []
    with tempfile.TemporaryDirectory() as d:
        for sc in scenes:
            if not sc.endswith(".toml"):
                # a preset the old binary may not know: its resolved scene, for both
                shown = subprocess.run([a.new, "scene", "show", sc], capture_output=True,
                                       text=True, check=True).stdout
                sc = os.path.join(d, sc + ".toml")
                with open(sc, "w") as f:
                    f.write(shown)
            runs = [(k, b, sc) for k, b in bins]
            if a.hard:
                runs.append(("hard", a.new, hard_variant(sc, d)))
            res = {k: [] for k, _, _ in runs}
            for _ in range(a.repeat):
                for k, b, s in runs:
                    res[k].append(run_once(b, s, rtols.get(k), os.path.join(d, f"{k}.bin")))
            for k, b, _ in runs:
                r = dict(res[k][-1])
                r["time"] = statistics.median(x["time"] for x in res[k])
                r["scene"] = os.path.basename(sc).removesuffix(".toml")
                r["binary"] = k
                r["rtol"] = "-" if k == "hard" else (rtols[k] or "scene's")
                r["exact_v_error"] = "-"
                if r["scene"] == "gapped_10k_1.0" or r["scene"] == "gapped_chain":
                    v = final_velocities(b, os.path.join(d, f"{k}.bin"))
                    exact = [0.0] * (len(v) - 1) + [1.0]
                    r["exact_v_error"] = f"{max(abs(x - y) for x, y in zip(v, exact)):.1e}"
                rows.append(r)
    print(f"| scene | binary | rtol | time (s) | µs per collision | collisions | steps | rejected | "
          f"exact pairs (handed over) | energy error | final-v error vs exact |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        per = 1e6 * r["time"] / r["collisions"] if r["collisions"] else float("nan")
        print(f"| {r['scene']} | {r['binary']} | {r['rtol']} | {r['time']:.4f} | {per:.2f} | {r['collisions']} | "
              f"{r['steps']} | {r['rejected']} | {r['exact']} | {r['energy_error']:.1e} | "
              f"{r['exact_v_error']} |")
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    sys.exit(main())
