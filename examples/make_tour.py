"""Writes examples/tour.ipynb (no stored outputs): python examples/make_tour.py [out.ipynb]

The notebook is generated so that its cells stay reviewable as plain Python here; edit this
file and run it again rather than editing the .ipynb by hand. examples/run_notebook.py executes
the notebook headless and checks the numbers it prints against the library's.
"""

import pathlib

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

CELLS = [
    ("md", """# A tour of `beadchain` from Python

Three short parts, each ending in one machine-readable line that `examples/run_notebook.py`
(run by `.ci/run`) checks against numbers it computes with the library itself:

1. paper Fig. 6: a solitary wave crossing the exponent interface n1 = 3.0 → n2 = 2.5
   (preset `interface_3.0_2.5`), and the reflected/transmitted energy from `analyze`;
2. a small disorder ensemble (preset `disorder_2.5_0.04`, shortened to 200 beads), the decay
   rate of each run, their mean and its standard error;
3. a `Simulation` stepped event by event (gap openings and closings)."""),
    ("code", """import time

import matplotlib.pyplot as plt
import numpy as np

import beadchain as bc

%matplotlib inline
t_start = time.perf_counter()"""),
    ("md", """## 1. Paper Fig. 6: the 3.0 → 2.5 interface

150 Table-1 steel beads, the exponent changes from 3.0 to 2.5 at contact 50 (bead 50), striker
0.11 m/s. The map shows every bead's kinetic energy over time (log colour scale, SI units):
part of the wave is reflected, the rest is transmitted as a multipulse train."""),
    ("code", """scene = bc.Scene.preset("interface_3.0_2.5")
run = bc.run(scene, every=10.0)
ke = 0.5 * scene.chain.mass_si() * run.v_si**2          # J, per bead and frame
fig, ax = plt.subplots(figsize=(7, 4.5))
img = ax.imshow(np.log10(np.maximum(ke, ke.max() * 1e-8)), aspect="auto", origin="lower",
                extent=(-0.5, scene.n_beads - 0.5, 0.0, run.t_si[-1] * 1e3),
                cmap="magma", interpolation="nearest")
ax.axvline(49.5, color="cyan", lw=0.8, ls="--", label="interface (bead 50)")
ax.set(xlabel="bead", ylabel="time (ms)", title="n1 = 3.0 → n2 = 2.5 (paper Fig. 6)")
fig.colorbar(img, ax=ax, label="log10 kinetic energy (J)")
ax.legend(loc="upper left", fontsize=8)
plt.show()"""),
    ("code", """split = bc.analyze(run, interface=50)["interface"]
print(f"{len(run.t)} frames of {scene.n_beads} beads, t_end = {run.t_si[-1] * 1e3:.3f} ms")
print(f"reflected_fraction={split['reflected_fraction']!r} "
      f"transmitted_fraction={split['transmitted_fraction']!r}")"""),
    ("md", """## 2. A disorder ensemble and its decay rate

Exponents n = 2.5 + 0.04 r (r uniform in [-1, 1), paper eq. 19; contacts 0–19 kept at 2.5 so
the wave forms first). The preset has 1000 beads; here 200 beads to t = 6000 (the leading wave
is near bead 200 by then), 6 seeds. `analyze` fits E/E_ref = a exp(−γ x) to the leading wave's
energy over positions 20 … N − 10; γ is the decay rate per bead."""),
    ("code", """SEEDS = [1, 2, 3, 4, 5, 6]
base = bc.Scene.preset("disorder_2.5_0.04")


def short_disorder(seed):
    # the sweep files' dotted keys (docs/sweeps.md): [scene] seed, [chain] beads, [run] ...
    return base.with_overrides({"scene.seed": seed, "chain.beads": 200, "run.until": 6000.0,
                                "run.every": 20.0,
                                "scene.name": f"disorder_2.5_0.04_n200_seed{seed}"})


gammas = []
fig, ax = plt.subplots(figsize=(6, 3.5))
for seed in SEEDS:
    a = bc.analyze(bc.run(short_disorder(seed)))
    gammas.append(a["decay"]["gamma"])
    ax.semilogy(a["track"]["position"], a["track"]["energy"] / a["e_ref"], lw=0.8,
                label=f"seed {seed}")
    print(f"seed {seed}: gamma = {a['decay']['gamma']:.4e} ± {a['decay']['gamma_stderr']:.1e} "
          f"per bead (r2 = {a['decay']['r2']:.3f})")
ax.set(xlabel="leading-wave position (bead)", ylabel="E / E_ref")
ax.legend(fontsize=7, ncol=2)
plt.show()"""),
    ("code", """g = np.array(gammas)
mean, sem = float(g.mean()), float(g.std(ddof=1) / np.sqrt(len(g)))
print(f"seeds={','.join(map(str, SEEDS))} gammas={','.join(repr(x) for x in gammas)}")
print(f"decay_rate_mean={mean!r} sem={sem!r}")"""),
    ("md", """## 3. Stepping a `Simulation` event by event

`pause_at(events=True)` makes `advance()` return at every gap opening or closing that the
hybrid engine logs; stepping changes no number (the event log equals one `run()`'s)."""),
    ("code", """sim = bc.Simulation(bc.Scene.preset("striker"))
sim.pause_at(events=True)
first = []
n_events, by_kind = 0, {}
while (stop := sim.advance()).reason == "event":
    n_events += 1
    by_kind[stop.event["kind"]] = by_kind.get(stop.event["kind"], 0) + 1
    if len(first) < 5:
        first.append(stop.event)
        e = stop.event
        print(f"event {n_events - 1}: {e['kind']:>6} at contact {e['contact']}, t = {stop.t:.6f}")
print(f"stopped: {stop.reason} at t = {stop.t}")
print(f"events={n_events} opens={by_kind.get('open', 0)} closes={by_kind.get('close', 0)}")
print(f"first_kinds={','.join(e['kind'] for e in first)} "
      f"first_times={','.join(repr(e['t']) for e in first)}")
print(f"notebook ran in {time.perf_counter() - t_start:.1f} s")"""),
]


def build() -> nbformat.NotebookNode:
    nb = new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nb.metadata["language_info"] = {"name": "python"}
    nb.cells = [new_markdown_cell(src) if kind == "md" else new_code_cell(src)
                for kind, src in CELLS]
    for i, cell in enumerate(nb.cells):
        cell["id"] = f"cell-{i:02d}"   # stable ids: regenerating gives the same file
    return nb


if __name__ == "__main__":
    import sys

    default = pathlib.Path(__file__).with_name("tour.ipynb")
    out = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else default
    nbformat.write(build(), str(out))
    print(f"wrote {out}")
