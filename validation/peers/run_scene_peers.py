#!/usr/bin/env python3
"""beadchain against SciPy on any wall-less preset or scene file, side by side in one invocation.

The chain comes from `beadchain scene show SCENE` (every per-bead and per-contact value after the
builders and the unit conversion, computer units), so SciPy integrates exactly the chain beadchain
runs: masses m_i, exponents n_k and prefactors a_k per contact, initial u and v (paper eq. 7,
ü_i = [F_{i-1} - F_i]/m_i with F_k = n_k a_k δ_k^{n_k - 1}, δ_k = max(u_k - u_{k+1}, 0)).

Peers: SciPy ode('vode', bdf, banded Jacobian lband = uband = 3 on the interleaved state),
solve_ivp LSODA (same band) and DOP853, as in run_peers.py. Tolerances are matched: rtol the same;
atol = rtol/100 times beadchain's characteristic scales (L for displacements, V_i per bead for
velocities), and beadchain runs with `--atol rtol/100` (or, with --beadchain-atol default, with
its own default atol rtol/10^4).

Accuracy, at the scene's end time:
  - velocity: max_i |v_i - v_ref,i| / max_i |v_ref,i| against a tight reference (SciPy DOP853 at
    --reference-rtol, atol = reference-rtol/100 scaled; or, with --reference dense, beadchain's
    dense engine with --reference-method, Radau IIA by default, atol = reference-rtol/100, which
    shares no event code with the hybrid one): the metric for non-chaotic scenes;
  - energy: relative total-energy error (a conserved quantity);
  - lead: relative error of the leading-wave energy (beads within --lead-window of the fastest
    bead, kinetic + contact energy) against the reference's: the paper's observable.
For chaotic scenes (disorder, periodic decay: tolerance-level differences grow) give
--metric observables: the equal-or-better comparison then uses max(energy, lead) errors, or
--metric energy: the total-energy error alone (the conserved quantity; on disorder the final
leading-wave energy is itself chaotic, 1e-2 between any two solvers, so it ranks runs by chance).

The reference's own floor: the reference is run again at 10x --reference-rtol and the two are
compared under each metric; the header gives that floor, and a peer error below 10x the floor is
marked "near the reference floor" (its equal-or-better comparison is not resolved). The dense
DOP853 reference used before had such a floor, and an erratic one: at rtol 1e-13 beadchain's dense
DOP853 is off by 2.6e-11, 5.8e-11 and 4.4e-13 on the 1000-bead striker with atol 1e-14, 1e-15 and
1e-16 (6e-10, 1.6e-9, 7e-12 on interface_3.0_2.5), most likely from the force's kink at every
contact onset, which its error estimate does not see, straddled wherever the step sequence puts
it; dense Radau IIA (the default now) at rtol 1e-12 and 1e-13 agrees with itself to 5e-14
(1.8e-12 on the interface). The dense reference runs at atol = rtol/100 whatever --beadchain-atol
says, so both atol choices' tables share it.

--from-csv OUT.csv re-makes OUT.md from an earlier invocation's CSV with another --metric (no run).

Wall time: integration only, median of --repeat runs; runs longer than --timeout are recorded
as "timeout" (a lower bound on their time).

Usage: python3 validation/peers/run_scene_peers.py --scene interface_3.0_2.5
       [--rtols 1e-6,1e-8,1e-10,1e-12] [--metric velocity|observables] [--repeat 3] [--timeout S]
       [--peers vode_bdf_banded,lsoda,dop853] [--beadchain hybrid:auto,...] [--out PREFIX]
       [--metric energy --from-csv validation/peers/scene-SCENE.csv --out PREFIX]
"""
import argparse
import csv
import io
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
from run_peers import (atol_args, atol_mode_of, atol_note, beadchain_atol, ensure_venv,  # noqa: E402
                       measure, speedup)

def chain_of(binary, scene, tmp):
    """The resolved chain (CSV columns as arrays) and the scene file beadchain will run."""
    text = subprocess.run([binary, "scene", "show", scene], capture_output=True, text=True, check=True).stdout
    for key in ("[walls]", "[field]", "[hard]", "precompression ="):
        if key in text:
            sys.exit("run_scene_peers: %s: %s is not supported by the SciPy right-hand side here" % (scene, key))
    path = os.path.join(tmp, "scene.toml")
    with open(path, "w") as f:
        f.write(text)
    until = float([ln for ln in text.splitlines() if ln.startswith("until = ")][0].split("=")[1])
    rows = csv_rows(subprocess.run(
        [binary, "scene", "show", scene, "--format", "csv"], capture_output=True, text=True, check=True).stdout)
    col = lambda k, rs=rows: [float(r[k]) for r in rs]  # noqa: E731
    chain = dict(mass=col("mass"), u0=col("u0"), v0=col("v0"), exponent=col("exponent", rows[:-1]),
                 prefactor=col("prefactor", rows[:-1]), until=until)
    return chain, path


def scales(ch):
    """beadchain's characteristic scales (model.rs `Chain::scales`) of the initial state."""
    import numpy as np
    m, u, v = np.array(ch["mass"]), np.array(ch["u0"]), np.array(ch["v0"])
    n, a = np.array(ch["exponent"]), np.array(ch["prefactor"])
    d = np.maximum(u[:-1] - u[1:], 0.0)
    pe = a * d ** n
    e = 0.5 * np.dot(m, v * v) + pe.sum()
    carriers = list(m[m * v * v > 0]) + list(m[:-1][pe > 0]) + list(m[1:][pe > 0])
    m_e = min(carriers)
    length = max((e / a) ** (1.0 / n))
    return length, np.sqrt(2.0 * e / np.maximum(m, m_e))


def energies(ch, u, v, window):
    """Total energy and leading-wave energy (beads within `window` of the fastest bead)."""
    import numpy as np
    m, n, a = np.array(ch["mass"]), np.array(ch["exponent"]), np.array(ch["prefactor"])
    pe = a * np.maximum(u[:-1] - u[1:], 0.0) ** n
    ke = 0.5 * m * v * v
    k = int(np.argmax(np.abs(v)))
    lo, hi = max(k - window, 0), min(k + window + 1, len(m))
    return ke.sum() + pe.sum(), ke[lo:hi].sum() + pe[lo:hi - 1].sum()


def worker(spec):
    import numpy as np
    from scipy.integrate import ode, solve_ivp
    ch = spec["chain"]
    m, n, a = np.array(ch["mass"]), np.array(ch["exponent"]), np.array(ch["prefactor"])
    na, nm1 = n * a, n - 1.0
    size = len(m)

    def rhs(_t, z):
        u = z[0::2]
        f = na * np.maximum(u[:-1] - u[1:], 0.0) ** nm1
        acc = np.zeros(size)
        acc[:-1] -= f
        acc[1:] += f
        out = np.empty_like(z)
        out[0::2] = z[1::2]
        out[1::2] = acc / m
        return out

    z0 = np.empty(2 * size)
    z0[0::2], z0[1::2] = ch["u0"], ch["v0"]
    atol = np.empty(2 * size)
    atol[0::2], atol[1::2] = spec["atol_u"], spec["atol_v"]
    rtol, t_end, method = spec["rtol"], ch["until"], spec["method"]
    t0 = time.perf_counter()
    if method == "vode_bdf_banded":
        r = ode(rhs).set_integrator("vode", method="bdf", with_jacobian=True, rtol=rtol, atol=atol,
                                    nsteps=10**9, lband=3, uband=3)
        r.set_initial_value(z0, 0.0)
        r.integrate(t_end)
        ok, z = r.successful(), r.y
    else:
        kw = dict(method="LSODA", lband=3, uband=3) if method == "lsoda" else dict(method="DOP853")
        sol = solve_ivp(rhs, (0.0, t_end), z0, rtol=rtol, atol=atol, t_eval=[t_end], **kw)
        ok, z = sol.success, sol.y[:, -1]
    wall = time.perf_counter() - t0
    print(json.dumps({"wall": wall, "ok": bool(ok), "u": list(z[0::2]), "v": list(z[1::2])}))


def run_scipy(args, ch, method, rtol, timeout):
    length, vel = scales(ch)
    spec = dict(chain=ch, rtol=rtol, method=method, atol_u=rtol / 100 * length,
                atol_v=list(rtol / 100 * vel))
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(spec, f)
    try:
        out = subprocess.run([sys.executable, os.path.abspath(__file__), "--worker", f.name],
                             capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"status": "timeout"}
    finally:
        os.unlink(f.name)
    if out.returncode != 0:
        return {"status": "error"}
    res = json.loads(out.stdout.strip().splitlines()[-1])
    res["status"] = "ok" if res.pop("ok") else "failed"
    return res


def csv_rows(text):
    """The rows of a beadchain CSV output, past its `# …` provenance lines."""
    return list(csv.DictReader(line for line in io.StringIO(text) if not line.startswith("#")))


def run_beadchain(args, scene, engine, method, rtol, tmp, atol=None):
    """One beadchain run; `atol` (relative) overrides --beadchain-atol (the reference's)."""
    import re
    snap = os.path.join(tmp, "out.snap")
    atol = ["--atol", repr(atol)] if atol is not None else atol_args(args, rtol)
    cmd = [args.binary, "run", scene, "--engine", engine, "--method", method, "--rtol", repr(rtol),
           "--out", snap] + atol
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
    except subprocess.TimeoutExpired:
        return {"status": "timeout"}
    if out.returncode != 0:
        return {"status": "error"}
    wall = float(re.search(r" in ([0-9.eE+-]+) s:", out.stdout).group(1))
    last = subprocess.run([args.binary, "export", snap, "--frame", "last"], capture_output=True,
                          text=True, check=True).stdout
    rows = csv_rows(last)
    return {"status": "ok", "wall": wall, "u": [float(r["u"]) for r in rows], "v": [float(r["v"]) for r in rows]}


def score(ch, res, ref, window):
    import numpy as np
    if res["status"] != "ok":
        return res
    u, v, vr = np.array(res["u"]), np.array(res["v"]), np.array(ref["v"])
    e0, _ = energies(ch, np.array(ch["u0"]), np.array(ch["v0"]), window)
    e1, lead = energies(ch, u, v, window)
    _, lead_ref = energies(ch, np.array(ref["u"]), vr, window)
    return dict(status="ok", wall=res["wall"], velocity=float(np.abs(v - vr).max() / np.abs(vr).max()),
                energy=abs(e1 - e0) / abs(e0), lead=abs(lead - lead_ref) / abs(lead_ref))


def reference_name(args):
    if getattr(args, "reference_unrecorded", False):
        return "(not recorded in the CSV)"
    if args.reference == "scipy":
        return "SciPy DOP853"
    method = getattr(args, "reference_method", "radau5")
    return "beadchain dense %s" % ("Radau IIA" if method == "radau5" else "DOP853")


def reference_run(args, ch, scene, tmp, rtol):
    """The reference at `rtol` (see --reference); exits when it fails."""
    print("reference: %s rtol %g ..." % (reference_name(args), rtol), file=sys.stderr, flush=True)
    if args.reference == "scipy":
        ref = run_scipy(args, ch, "dop853", rtol, 100 * args.timeout)
    else:
        saved, args.timeout = args.timeout, 100 * args.timeout
        # the reference's atol is rtol/100 whatever --beadchain-atol says: the default's floor of
        # 1e-14 would make the two atol choices' tables use different references
        ref = run_beadchain(args, scene, "dense", args.reference_method, rtol, tmp, atol=rtol / 100)
        args.timeout = saved
    if ref["status"] != "ok":
        sys.exit("run_scene_peers: reference run at rtol %g: %s" % (rtol, ref["status"]))
    return ref


def floor_of(ch, ref, loose, window):
    """The reference's floor under each metric: the looser reference scored against the tight one
    (the energy error needs no reference: its floor is 0)."""
    s = score(ch, dict(loose, wall=0.0), ref, window)
    return dict(velocity=s["velocity"], lead=s["lead"], energy=0.0)


def floor_for(args):
    """The floor of --metric's error (`observables`: the larger one's, the lead energy's)."""
    f = getattr(args, "floor", None) or {}
    if args.metric == "energy":
        return 0.0
    return f.get("velocity", 0.0) if args.metric == "velocity" else f.get("lead", 0.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--scene", default="interface_3.0_2.5")
    ap.add_argument("--rtols", default="1e-6,1e-8,1e-10,1e-12")
    ap.add_argument("--hybrid-rtols", default="1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12")
    ap.add_argument("--metric", choices=["velocity", "observables", "energy"], default="velocity")
    ap.add_argument("--from-csv", help="re-make the tables from this CSV of an earlier invocation (no run)")
    ap.add_argument("--reference-rtol", type=float, default=1e-13)
    ap.add_argument("--reference", choices=["scipy", "dense"], default="scipy",
                    help="reference run: SciPy DOP853 or beadchain's dense engine (no events)")
    ap.add_argument("--reference-method", choices=["radau5", "dop853"], default="radau5",
                    help="the dense engine's method for --reference dense")
    ap.add_argument("--lead-window", type=int, default=10)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--timeout", type=float, default=600.0)
    ap.add_argument("--peers", default="vode_bdf_banded,lsoda,dop853")
    ap.add_argument("--beadchain", default="hybrid:auto,dense:dop853")
    ap.add_argument("--beadchain-atol", choices=["matched", "default"], default="matched",
                    help="beadchain's atol: rtol/100 like SciPy's (matched) or its own default rtol/10^4")
    ap.add_argument("--binary", default=os.path.join(ROOT, "target", "release", "beadchain"))
    ap.add_argument("--out", help="writes OUT.csv and OUT.md [default: validation/peers/scene-SCENE]")
    args = ap.parse_args()
    if args.worker:
        with open(args.worker) as f:
            return worker(json.load(f))
    if args.from_csv:
        return rescore(args)
    out = args.out or os.path.join(HERE, "scene-" + os.path.basename(args.scene).replace(".toml", ""))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        ch, scene = chain_of(args.binary, args.scene, tmp)
        ref = reference_run(args, ch, scene, tmp, args.reference_rtol)
        loose = reference_run(args, ch, scene, tmp, 10 * args.reference_rtol)
        args.floor = floor_of(ch, ref, loose, args.lead_window)
        print("reference floor: %s" % args.floor, file=sys.stderr, flush=True)
        runs = [tuple(x.split(":")) for x in args.beadchain.split(",") if x]
        main_solver = "beadchain %s %s" % runs[0]
        rtols = [float(x) for x in args.rtols.split(",")]
        extra = [float(x) for x in args.hybrid_rtols.split(",") if x and float(x) not in rtols]
        jobs = [(r, "beadchain %s %s" % em, lambda r=r, em=em: run_beadchain(args, scene, em[0], em[1], r, tmp))
                for r in rtols for em in runs]
        jobs += [(r, "scipy " + p, lambda r=r, p=p: run_scipy(args, ch, p, r, args.timeout))
                 for r in rtols for p in args.peers.split(",") if p]
        jobs += [(r, main_solver, lambda r=r: run_beadchain(args, scene, runs[0][0], runs[0][1], r, tmp))
                 for r in extra]
        for rtol, solver, fn in jobs:
            res = score(ch, measure(fn, args.repeat), ref, args.lead_window)
            rows.append(dict(solver=solver, rtol=rtol, **res))
            print({k: v for k, v in rows[-1].items()}, file=sys.stderr, flush=True)
    write(args, out, rows, main_solver)


def err_of(args, r):
    if args.metric == "energy":
        return r["energy"]
    return r["velocity"] if args.metric == "velocity" else max(r["energy"], r["lead"])


def number(text):
    """A float from a CSV cell, also in the `np.float64(x)` form older invocations wrote."""
    return float(text[len("np.float64("):-1] if text.startswith("np.float64(") else text)


def rescore(args):
    """The tables of an earlier invocation's CSV under this --metric (no run), written to --out
    (default: the CSV's own prefix, the CSV rewritten in place)."""
    with open(args.from_csv) as f:
        table = list(csv.DictReader(f))
    out = args.out or args.from_csv[:-len(".csv")]
    rows = []
    for r in table:
        row = dict(solver=r["solver"], rtol=float(r["rtol"]), status=r["status"])
        if r["status"] == "ok":
            row.update(wall=number(r["wall_seconds"]), velocity=number(r["velocity_error"]),
                       energy=number(r["energy_error"]), lead=number(r["lead_error"]))
        rows.append(row)
    args.scene, args.repeat = table[0]["scene"], int(table[0]["repeat"])
    args.beadchain_atol = atol_mode_of(table)
    first = table[0]
    if first.get("reference_rtol"):
        args.reference = "scipy" if first["reference"] == "SciPy DOP853" else "dense"
        args.reference_method = "dop853" if first["reference"].endswith("DOP853") else "radau5"
        args.reference_rtol = float(first["reference_rtol"])
    else:
        args.reference_unrecorded = True
    if first.get("reference_floor_velocity"):
        args.floor = dict(velocity=float(first["reference_floor_velocity"]),
                          lead=float(first["reference_floor_lead"]), energy=0.0)
    runs = [tuple(x.split(":")) for x in args.beadchain.split(",") if x]
    write(args, out, rows, "beadchain %s %s" % runs[0])


def write(args, out, rows, main_solver):
    floor = getattr(args, "floor", None)
    unrecorded = getattr(args, "reference_unrecorded", False)
    ref_cols = ",%s,%s,%s,%s" % ("" if unrecorded else reference_name(args),
                                 "" if unrecorded else repr(args.reference_rtol),
                                 repr(float(floor["velocity"])) if floor else "",
                                 repr(float(floor["lead"])) if floor else "")
    with open(out + ".csv", "w") as f:
        f.write("scene,solver,rtol,atol_rel,status,wall_seconds,velocity_error,energy_error,lead_error,repeat,"
                "reference,reference_rtol,reference_floor_velocity,reference_floor_lead\n")
        for r in rows:
            vals = [repr(float(r[k])) if k in r else "" for k in ("wall", "velocity", "energy", "lead")]
            atol = beadchain_atol(args, r["rtol"]) if r["solver"].startswith("beadchain") else r["rtol"] / 100
            f.write("%s,%s,%r,%r,%s,%s,%d%s\n" % (args.scene, r["solver"], r["rtol"], atol,
                                                  r["status"], ",".join(vals), args.repeat, ref_cols))
    metric = {"velocity": "final velocity error", "energy": "total-energy error",
              "observables": "max(energy error, leading-wave energy error)"}[args.metric]
    if floor:
        floor_note = ("; its floor (the reference against itself at 10x its rtol): velocity %.1e, "
                      "lead energy %.1e" % (floor["velocity"], floor["lead"]))
    else:
        floor_note = "; its floor was not measured (an invocation before the floor check)"
    ref_text = reference_name(args) + ("" if unrecorded else " rtol %g" % args.reference_rtol)
    lines = ["Scene `%s`; %s; reference %s%s; median of %d; "
             "error metric for the comparison: %s" % (args.scene, atol_note(args), ref_text,
                                                     floor_note, args.repeat, metric), "",
             "| solver | rtol | wall (s) | velocity error | energy error | lead-energy error |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        if r["status"] != "ok":
            lines.append("| %s | %g | %s | | | |" % (r["solver"], r["rtol"], r["status"]))
        else:
            lines.append("| %s | %g | %.4f | %.1e | %.1e | %.1e |" % (
                r["solver"], r["rtol"], r["wall"], r["velocity"], r["energy"], r["lead"]))
    hyb = [r for r in rows if r["solver"] == main_solver and r["status"] == "ok"]
    lines += ["", "At equal or better error (%s): the cheapest %s run, any rtol:" % (metric, main_solver), "",
              "| peer | rtol | wall (s) | error | beadchain rtol | beadchain wall (s) | beadchain error | speed-up |",
              "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["solver"] == main_solver:
            continue
        if r["status"] != "ok":
            same = [h for h in hyb if h["rtol"] == r["rtol"]]
            bound = "> %s vs the same rtol" % speedup(args.timeout / max(same[0]["wall"], 1e-4)) if same else ""
            lines.append("| %s | %g | %s (> %g s) | | | | | %s |" % (
                r["solver"], r["rtol"], r["status"], args.timeout, bound))
            continue
        ok = [h for h in hyb if err_of(args, h) <= err_of(args, r)]
        near = " (near the reference floor)" if err_of(args, r) < 10 * floor_for(args) else ""
        if not ok:
            lines.append("| %s | %g | %.4f | %.1e | none as accurate%s | | | |" % (
                r["solver"], r["rtol"], r["wall"], err_of(args, r), near))
            continue
        h = min(ok, key=lambda h: h["wall"])
        lines.append("| %s | %g | %.4f | %.1e | %g | %.4f | %.1e | %s%s |" % (
            r["solver"], r["rtol"], r["wall"], err_of(args, r), h["rtol"], h["wall"], err_of(args, h),
            speedup(r["wall"] / max(h["wall"], 1e-4)), near))
    text = "\n".join(lines) + "\n"
    with open(out + ".md", "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    ensure_venv(os.path.abspath(__file__))
    main()
