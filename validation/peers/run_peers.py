#!/usr/bin/env python3
"""beadchain against SciPy on a uniform striker chain, measured side by side in one invocation.

Peers (all on the same chain, to the same end time, at matched tolerances):
  - SciPy ode('vode', method='bdf', with_jacobian=True, lband=3, uband=3): the paper's appendix A
    set-up. The state is INTERLEAVED, z = (u_0, v_0, u_1, v_1, ...): in the ordering (u, v) of
    eq. A.3 the Jacobian [[0, I], [K, 0]] is not banded (the identity block sits N columns off the
    diagonal); interleaved, du_i/dt = v_i couples index 2i to 2i+1 and dv_i/dt = f_i(u_{i-1},
    u_i, u_{i+1}) couples 2i+1 to 2i-2 and 2i+2, so the Jacobian is banded with lower and upper
    bandwidth 3. VODE builds it by finite differences over the band.
  - solve_ivp LSODA (same band), Radau (jac_sparsity = the band, sparse finite differences),
    DOP853 (explicit).
  - beadchain run --engine hybrid and --engine dense (release binary), reading the energies with
    `beadchain inspect` and the integration wall time from `beadchain run`'s output.

Matched tolerances: rtol the same; atol per component = atol_rel * L for displacements and
atol_rel * V for velocities, with L = (E/a)^(1/n), V = sqrt(2E/m) beadchain's characteristic scales
(beadchain's --atol is relative to exactly these scales), atol_rel = rtol/100. With
--beadchain-atol default, beadchain runs with --rtol alone, i.e. at its own default atol rtol/10^4
(what a user gets; the comparison is at equal or better measured error either way).

Wall time: integration only (SciPy: around integrate/solve_ivp inside the worker; beadchain: the
time `beadchain run` prints), median over --repeat runs. Each SciPy run is a subprocess killed
after --timeout seconds (recorded as "timeout").

Outputs validation/peers/results.csv (one row per solver and tolerance) and
validation/peers/results.md (wall-time ratio peer / beadchain hybrid at the same rtol, and energy
errors). Creates validation/peers/.venv with numpy and scipy from PyPI on first use.

Usage: python3 validation/peers/run_peers.py [--quick] [--beads N] [--exponent n] [--prefactor a]
       [--mass m] [--velocity v0] [--until T] [--rtols 1e-6,1e-8,1e-10,1e-12] [--hybrid-rtols ...] [--repeat K]
       [--timeout S] [--binary PATH]
"""
import argparse
import csv
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
VENV = os.path.join(HERE, ".venv")
VPY = os.path.join(VENV, "bin", "python")
PEERS = ["vode_bdf_banded", "lsoda", "radau", "dop853"]


def ensure_venv(script=None):
    """Re-executes `script` (default: this file) under the venv python (created with numpy +
    scipy if missing)."""
    try:
        import numpy  # noqa: F401
        import scipy  # noqa: F401
        return
    except ImportError:
        pass
    if os.path.abspath(sys.executable) == os.path.abspath(VPY):
        sys.exit("run_peers: numpy/scipy missing inside the venv; delete %s and retry" % VENV)
    if not os.path.exists(VPY):
        print("run_peers: creating %s (numpy, scipy from PyPI)" % VENV, file=sys.stderr)
        subprocess.check_call([sys.executable, "-m", "venv", VENV])
        subprocess.check_call([VPY, "-m", "pip", "install", "-q", "numpy", "scipy"])
    os.execv(VPY, [VPY, script or os.path.abspath(__file__)] + sys.argv[1:])


# ---------------------------------------------------------------- SciPy worker (one run)
def worker(spec):
    import numpy as np
    from scipy.integrate import ode, solve_ivp
    from scipy.sparse import diags

    n, p, a, m, v0 = spec["beads"], spec["exponent"], spec["prefactor"], spec["mass"], spec["velocity"]
    t_end, rtol, atol_u, atol_v = spec["until"], spec["rtol"], spec["atol_u"], spec["atol_v"]

    def rhs(_t, z):
        u = z[0::2]
        d = np.maximum(u[:-1] - u[1:], 0.0)
        f = p * a * d ** (p - 1.0)
        acc = np.zeros(n)
        acc[:-1] -= f
        acc[1:] += f
        out = np.empty_like(z)
        out[0::2] = z[1::2]
        out[1::2] = acc / m
        return out

    def energy(z):
        u, v = z[0::2], z[1::2]
        d = np.maximum(u[:-1] - u[1:], 0.0)
        return 0.5 * m * np.dot(v, v) + np.sum(a * d ** p)

    z0 = np.zeros(2 * n)
    z0[1] = v0
    atol = np.empty(2 * n)
    atol[0::2] = atol_u
    atol[1::2] = atol_v
    e0 = energy(z0)
    method = spec["method"]
    t0 = time.perf_counter()
    if method == "vode_bdf_banded":
        r = ode(rhs).set_integrator(
            "vode", method="bdf", with_jacobian=True, rtol=rtol, atol=atol,
            nsteps=10**9, lband=3, uband=3,
        )
        r.set_initial_value(z0, 0.0)
        r.integrate(t_end)
        ok, z, nfev = r.successful(), r.y, -1
    else:
        kw = {}
        if method == "lsoda":
            kw = dict(method="LSODA", lband=3, uband=3)
        elif method == "radau":
            kw = dict(method="Radau", jac_sparsity=diags([1.0] * 7, range(-3, 4), shape=(2 * n, 2 * n)))
        elif method == "dop853":
            kw = dict(method="DOP853")
        sol = solve_ivp(rhs, (0.0, t_end), z0, rtol=rtol, atol=atol, t_eval=[t_end], **kw)
        ok, z, nfev = sol.success, sol.y[:, -1], int(sol.nfev)
    wall = time.perf_counter() - t0
    print(json.dumps({"wall": wall, "energy_error": abs(energy(z) - e0) / e0, "ok": bool(ok), "nfev": nfev}))


# ---------------------------------------------------------------- driver
def scales(args):
    e = 0.5 * args.mass * args.velocity ** 2
    return (e / args.prefactor) ** (1.0 / args.exponent), math.sqrt(2.0 * e / args.mass)


def run_scipy(args, method, rtol):
    length, vel = scales(args)
    spec = dict(
        beads=args.beads, exponent=args.exponent, prefactor=args.prefactor, mass=args.mass,
        velocity=args.velocity, until=args.until, rtol=rtol, method=method,
        atol_u=rtol / 100 * length, atol_v=rtol / 100 * vel,
    )
    try:
        out = subprocess.run(
            [sys.executable, os.path.abspath(__file__), "--worker", json.dumps(spec)],
            capture_output=True, text=True, timeout=args.timeout,
        )
    except subprocess.TimeoutExpired:
        return {"status": "timeout"}
    if out.returncode != 0:
        return {"status": "error: " + out.stderr.strip().splitlines()[-1][:80] if out.stderr.strip() else "error"}
    res = json.loads(out.stdout.strip().splitlines()[-1])
    res["status"] = "ok" if res["ok"] else "failed"
    return res


def run_beadchain(args, engine, rtol, tmp, method="auto"):
    scene = os.path.join(tmp, "chain.toml")
    with open(scene, "w") as f:
        f.write("[chain]\nbeads = %d\nmass = %r\nexponent = %r\nprefactor = %r\n"
                "[initial]\nstriker = %r\n[run]\nuntil = %r\n"
                % (args.beads, args.mass, args.exponent, args.prefactor, args.velocity, args.until))
    snap = os.path.join(tmp, "out.snap")
    cmd = [args.binary, "run", scene, "--engine", engine, "--method", method, "--rtol", repr(rtol),
           "--out", snap] + atol_args(args, rtol)
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
    except subprocess.TimeoutExpired:
        return {"status": "timeout"}
    if out.returncode != 0:
        return {"status": "error: " + out.stderr.strip()[:80]}
    wall = float(re.search(r" in ([0-9.eE+-]+) s:", out.stdout).group(1))
    ins = subprocess.run([args.binary, "inspect", snap], capture_output=True, text=True, check=True)
    mt = re.search(r"energy:\s+first frame ([^,]+), last frame (\S+)", ins.stdout)
    e0, e1 = float(mt.group(1)), float(mt.group(2))
    return {"status": "ok", "wall": wall, "energy_error": abs(e1 - e0) / abs(e0), "nfev": -1}


def atol_args(args, rtol):
    """beadchain's --atol: rtol/100 like the SciPy runs (--beadchain-atol matched), or none, i.e.
    beadchain's own default rtol/10^4 (--beadchain-atol default)."""
    return ["--atol", repr(rtol / 100)] if args.beadchain_atol == "matched" else []


def beadchain_atol(args, rtol):
    """The relative atol a beadchain run uses (crate::integrate::default_atol for 'default')."""
    return rtol / 100 if args.beadchain_atol == "matched" else max(rtol * 1e-4, min(1e-14, rtol))


def atol_note(args):
    """How the tables' header describes the tolerances."""
    if args.beadchain_atol == "matched":
        return "atol = rtol/100 (scaled) for every solver"
    return "SciPy atol = rtol/100 (scaled); beadchain atol = its default rtol/10^4 (only --rtol given)"


def speedup(x):
    """A speed-up as the tables print it: one decimal below 100x, so that a ratio just below a
    target (9.69x against 10x) is not rounded up to it."""
    return "%.1f×" % x if x < 99.95 else "%.0f×" % x


def measure(fn, repeat):
    walls, res = [], None
    for _ in range(repeat):
        res = fn()
        if res["status"] != "ok":
            return res
        walls.append(res["wall"])
    res["wall"] = statistics.median(walls)
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--quick", action="store_true", help="100 beads, one tolerance, 1 repetition")
    ap.add_argument("--beads", type=int, default=1000)
    ap.add_argument("--exponent", type=float, default=2.5)
    ap.add_argument("--prefactor", type=float, default=1.0)
    ap.add_argument("--mass", type=float, default=1.0)
    ap.add_argument("--velocity", type=float, default=1.0)
    ap.add_argument("--until", type=float, help="end time [default: wave exit, N/1.21 + 40 for the default chain]")
    ap.add_argument("--rtols", default="1e-6,1e-8,1e-10,1e-12")
    ap.add_argument("--hybrid-rtols", default="1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12",
                    help="extra beadchain hybrid tolerances for the equal-or-better-error comparison")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--timeout", type=float, default=120.0, help="per SciPy/beadchain run, seconds")
    ap.add_argument("--peers", default=",".join(PEERS))
    ap.add_argument("--beadchain", default="hybrid:auto,hybrid:radau5,dense:dop853",
                    help="beadchain runs ENGINE:METHOD, comma-separated; the first is the one the "
                         "ratios and the equal-or-better-error table refer to (default: the CLI default)")
    ap.add_argument("--beadchain-atol", choices=["matched", "default"], default="matched",
                    help="beadchain's atol: rtol/100 like SciPy's (matched) or beadchain's own default "
                         "rtol/10^4 (default: what `beadchain run --rtol R` uses)")
    ap.add_argument("--binary", default=os.path.join(ROOT, "target", "release", "beadchain"))
    ap.add_argument("--out", default=os.path.join(HERE, "results"), help="writes OUT.csv and OUT.md")
    ap.add_argument("--from-csv", help="re-make OUT.md (and OUT.csv) from this CSV of an earlier "
                                       "invocation of the default chain (no run)")
    args = ap.parse_args()
    if args.worker:
        return worker(json.loads(args.worker))
    if args.from_csv:
        return rewrite(args)
    if args.quick:
        args.beads, args.repeat, args.rtols, args.hybrid_rtols = 100, 1, "1e-8", "1e-7,1e-8,1e-9"
    if args.until is None:
        default = (args.exponent, args.prefactor, args.mass, args.velocity) == (2.5, 1.0, 1.0, 1.0)
        if not default:
            sys.exit("run_peers: give --until for a non-default chain (wave exit time)")
        # Solitary wave speed 1.21 beads per time unit for the default chain (data/scenes/striker.toml).
        args.until = args.beads / 1.21 + 40.0
    if not os.path.exists(args.binary):
        subprocess.check_call(["cargo", "build", "--release", "--manifest-path", os.path.join(ROOT, "Cargo.toml")])
    rtols = [float(x) for x in args.rtols.split(",")]
    peers = [p for p in args.peers.split(",") if p]
    bead_runs = [tuple(x.split(":")) for x in args.beadchain.split(",") if x]
    args.main_solver = "beadchain %s %s" % bead_runs[0]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for rtol in rtols:
            for engine, method in bead_runs:
                res = measure(lambda: run_beadchain(args, engine, rtol, tmp, method), args.repeat)
                rows.append(dict(solver="beadchain %s %s" % (engine, method), rtol=rtol, **res))
                print(rows[-1], file=sys.stderr, flush=True)
            for p in peers:
                res = measure(lambda: run_scipy(args, p, rtol), args.repeat)
                rows.append(dict(solver="scipy " + p, rtol=rtol, **res))
                print(rows[-1], file=sys.stderr, flush=True)
        extra = [float(x) for x in args.hybrid_rtols.split(",") if x]
        for rtol in extra:
            if rtol in rtols:
                continue
            res = measure(lambda: run_beadchain(args, bead_runs[0][0], rtol, tmp, bead_runs[0][1]),
                          args.repeat)
            rows.append(dict(solver=args.main_solver, rtol=rtol, **res))
            print(rows[-1], file=sys.stderr, flush=True)
    write_outputs(args, rows)


def atol_mode_of(table):
    """`matched` or `default`: the --beadchain-atol of an invocation, read from its CSV rows
    (beadchain rows at `atol_rel = rtol/100` were run matched)."""
    for r in table:
        if r["solver"].startswith("beadchain") and float(r["atol_rel"]) != float(r["rtol"]) / 100:
            return "default"
    return "matched"


def rewrite(args):
    """The tables of an earlier invocation's CSV (no run); beadchain's atol mode is read from the
    CSV's `atol_rel` column."""
    with open(args.from_csv) as f:
        table = list(csv.DictReader(f))
    rows = []
    for r in table:
        row = dict(solver=r["solver"], rtol=float(r["rtol"]), status=r["status"])
        if r["status"] == "ok":
            row.update(wall=float(r["wall_seconds"]), energy_error=float(r["energy_error"]))
        rows.append(row)
    args.beads, args.until, args.repeat = int(table[0]["beads"]), float(table[0]["until"]), int(table[0]["repeat"])
    args.beadchain_atol = atol_mode_of(table)
    args.main_solver = "beadchain %s %s" % tuple(args.beadchain.split(",")[0].split(":"))
    write_outputs(args, rows)


def write_outputs(args, rows):
    with open(args.out + ".csv", "w") as f:
        f.write("solver,beads,until,rtol,atol_rel,status,wall_seconds,energy_error,repeat\n")
        for r in rows:
            atol = beadchain_atol(args, r["rtol"]) if r["solver"].startswith("beadchain") else r["rtol"] / 100
            f.write("%s,%d,%r,%r,%r,%s,%s,%s,%d\n" % (
                r["solver"], args.beads, args.until, r["rtol"], atol, r["status"],
                repr(r["wall"]) if "wall" in r else "", repr(r["energy_error"]) if "energy_error" in r else "",
                args.repeat))
    hyb = {r["rtol"]: r for r in rows if r["solver"] == args.main_solver and r["status"] == "ok"}
    lines = [
        "Uniform striker chain: %d beads, n = %g, a = %g, m = %g, v0 = %g, until %g; %s; "
        "median of %d; python %s" % (args.beads, args.exponent, args.prefactor, args.mass, args.velocity,
                                     args.until, atol_note(args), args.repeat, sys.version.split()[0]),
        "",
        "| solver | rtol | wall time (s) | ratio to %s | relative energy error |" % args.main_solver,
        "|---|---|---|---|---|",
    ]
    for r in rows:
        if r["status"] != "ok":
            lines.append("| %s | %g | %s | | |" % (r["solver"], r["rtol"], r["status"]))
            continue
        h = hyb.get(r["rtol"])
        ratio = speedup(r["wall"] / max(h["wall"], 1e-4)) if h else ""
        lines.append("| %s | %g | %.4f | %s | %.1e |" % (r["solver"], r["rtol"], r["wall"], ratio, r["energy_error"]))
    # Equal or better energy error: for every peer run, the cheapest hybrid run (any rtol) whose
    # energy error is at most the peer's.
    hyb_all = [r for r in rows if r["solver"] == args.main_solver and r["status"] == "ok"]
    lines += [
        "",
        "At equal or better energy error (cheapest hybrid run, any rtol, with energy error <= the peer's):",
        "",
        "| solver | rtol | wall time (s) | energy error | hybrid rtol | hybrid wall (s) | hybrid energy error | speed-up |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r["solver"] == args.main_solver or r["status"] != "ok":
            continue
        ok = [h for h in hyb_all if h["energy_error"] <= r["energy_error"]]
        if not ok:
            lines.append("| %s | %g | %.4f | %.1e | none as accurate | | | |" % (
                r["solver"], r["rtol"], r["wall"], r["energy_error"]))
            continue
        h = min(ok, key=lambda h: h["wall"])
        lines.append("| %s | %g | %.4f | %.1e | %g | %.4f | %.1e | %s |" % (
            r["solver"], r["rtol"], r["wall"], r["energy_error"], h["rtol"], h["wall"],
            h["energy_error"], speedup(r["wall"] / max(h["wall"], 1e-4))))
    text = "\n".join(lines) + "\n"
    with open(args.out + ".md", "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    if "--worker" not in sys.argv:
        ensure_venv()
    else:
        ensure_venv()
    main()
