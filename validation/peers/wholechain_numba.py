#!/usr/bin/env python3
"""A lean whole-chain compiled baseline (issue 33): numba DOP853 and velocity Verlet against beadchain.

The chain comes from `beadchain scene show SCENE` (CSV: per-bead masses, u0, v0; per-contact
exponents n_k, prefactors a_k, precompressions Δ_k), so the kernels integrate exactly the chain
beadchain runs: m_i ü_i = F_{i-1} - F_i, F_k = n_k a_k max(δ_k, 0)^(n_k - 1),
δ_k = Δ_k + u_k - u_{k+1}, state (u, v) of every bead, no events. Walls, fields, hard or damped
contacts are refused.

  - numba DOP853: Hairer's DOP853 (coefficients read from SciPy's
    scipy/integrate/_ivp/dop853_coefficients.py, i.e. those of Hairer's dop853.f), error estimate
    combining the 5th- and 3rd-order estimates as in dop853.f (err5² / sqrt(err5² + 0.01 err3²)),
    Hairer's controller (safety 0.9, step factor within [0.333, 6], beta = 0, no growth right after
    a rejection), Hairer's starting step (hinit), FSAL; tolerance per component
    sk = atol_i + rtol·max(|y_i|, |ynew_i|), atol_i = --atol-ratio·rtol times beadchain's scales
    (L for displacements, V_i per bead for velocities, as in run_scene_peers.py).
  - numba velocity Verlet: fixed step dt = until / ceil(until / dt_requested).
  - beadchain: `beadchain run SCENE --rtol R` (the default: hybrid engine, method auto, default
    atol); final state read with `beadchain export --frame last`; wall time the one `run` prints.

Error: max_i |v_i - v_ref,i| / max_i |v_ref,i| at the end time, against beadchain's dense Radau IIA
at --reference-rtol (atol = rtol/100), whose floor is measured against itself at 10x that rtol;
the numba DOP853 at the same rtol is scored against it as a cross-check (--reference numba uses
that one instead). Wall time: median of --repeat, the repetitions interleaved (round-robin over all
runs); numba timed around the compiled call only, after a warm-up call that compiles.
Writes validation/peers/wholechain-SCENE.csv and .md.

Usage: python3 validation/peers/wholechain_numba.py [--scene interface_3.0_2.5] [--quick]
       [--repeat 3] [--binary PATH] [--rtols ...] [--beadchain-rtols ...] [--verlet-dts ...]
Creates validation/peers/.venv with numpy, scipy and numba from PyPI on first use.
"""
import argparse
import csv
import io
import math
import os
import platform
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
LEVELS = [10.0 ** -k for k in range(2, 11)]


def ensure_venv():
    """Re-executes this script under the venv python, with numpy, scipy and numba installed there."""
    try:
        import numba  # noqa: F401
        import numpy  # noqa: F401
        import scipy  # noqa: F401
        return
    except ImportError:
        pass
    if os.environ.get("WHOLECHAIN_REEXEC"):
        sys.exit("wholechain_numba: numpy/scipy/numba still missing inside %s; delete it and retry" % VENV)
    if not os.path.exists(VPY):
        print("wholechain_numba: creating %s" % VENV, file=sys.stderr)
        subprocess.check_call([sys.executable, "-m", "venv", VENV])
    if subprocess.run([VPY, "-c", "import numba, numpy, scipy"], capture_output=True).returncode != 0:
        print("wholechain_numba: installing numpy, scipy, numba into %s (PyPI)" % VENV, file=sys.stderr)
        subprocess.check_call([VPY, "-m", "pip", "install", "-q", "numpy", "scipy", "numba"])
    os.environ["WHOLECHAIN_REEXEC"] = "1"
    os.execv(VPY, [VPY, os.path.abspath(__file__)] + sys.argv[1:])


# ---------------------------------------------------------------- compiled kernels
def kernels():
    """(dop853, verlet): numba-compiled on first call. Needs numba, numpy and SciPy (coefficients)."""
    import numba
    import numpy as np
    from scipy.integrate._ivp import dop853_coefficients as co
    A, B = np.ascontiguousarray(co.A[:12, :12]), co.B.copy()
    E3, E5 = co.E3[:12].copy(), co.E5[:12].copy()

    @numba.njit(cache=False)
    def accel(u, out, inv_m, na, nm1, pre):
        """out = ü(u): m_i ü_i = F_{i-1} - F_i (n = 2.5 and 3 without pow)."""
        for i in range(u.size):
            out[i] = 0.0
        for k in range(u.size - 1):
            d = pre[k] + u[k] - u[k + 1]
            if d > 0.0:
                e = nm1[k]
                p = d * math.sqrt(d) if e == 1.5 else (d * d if e == 2.0 else d ** e)
                f = na[k] * p
                out[k] -= f
                out[k + 1] += f
        for i in range(u.size):
            out[i] *= inv_m[i]

    @numba.njit(cache=False)
    def rhs(y, out, inv_m, na, nm1, pre):
        n = inv_m.size
        for i in range(n):
            out[i] = y[n + i]
        accel(y[:n], out[n:], inv_m, na, nm1, pre)

    @numba.njit(cache=False)
    def dop853(y0, t_end, rtol, atol, inv_m, na, nm1, pre, max_steps):
        """Hairer's DOP853 over (0, t_end]; returns (y, accepted, rejected, rhs evaluations, ok)."""
        dim = y0.size
        y, yn, ys = y0.copy(), np.empty(dim), np.empty(dim)
        K, acc5, acc3 = np.empty((12, dim)), np.empty(dim), np.empty(dim)
        rhs(y, K[0], inv_m, na, nm1, pre)
        # starting step: Hairer's hinit, order 8
        sk = atol + rtol * np.abs(y)
        dnf, dny = np.sum((K[0] / sk) ** 2), np.sum((y / sk) ** 2)
        h = 1e-6 if dnf <= 1e-10 or dny <= 1e-10 else 0.01 * math.sqrt(dny / dnf)
        h = min(h, t_end)
        ys[:] = y + h * K[0]
        rhs(ys, K[1], inv_m, na, nm1, pre)
        der2 = math.sqrt(np.sum(((K[1] - K[0]) / sk) ** 2)) / h
        der12 = max(der2, math.sqrt(dnf))
        h1 = max(1e-6, 1e-3 * h) if der12 <= 1e-15 else (0.01 / der12) ** 0.125
        h = min(100.0 * h, h1, t_end)
        t, nacc, nrej, nfev, reject, last = 0.0, 0, 0, 2, False, False
        while nacc + nrej < max_steps:
            if t + 1.01 * h >= t_end:
                h, last = t_end - t, True
            if h <= abs(t) * 1e-15:
                return y, nacc, nrej, nfev, False
            for s in range(1, 12):
                ys[:] = y
                for j in range(s):
                    c = h * A[s, j]
                    if c != 0.0:
                        for i in range(dim):
                            ys[i] += c * K[j, i]
                rhs(ys, K[s], inv_m, na, nm1, pre)
            nfev += 11
            yn[:] = y
            acc5[:] = 0.0
            acc3[:] = 0.0
            for j in range(12):
                cb, c5, c3 = h * B[j], E5[j], E3[j]
                for i in range(dim):
                    kji = K[j, i]
                    yn[i] += cb * kji
                    acc5[i] += c5 * kji
                    acc3[i] += c3 * kji
            err5, err3 = 0.0, 0.0
            for i in range(dim):
                sc = atol[i] + rtol * max(abs(y[i]), abs(yn[i]))
                err5 += (acc5[i] / sc) ** 2
                err3 += (acc3[i] / sc) ** 2
            deno = err5 + 0.01 * err3
            err = abs(h) * err5 / math.sqrt((deno if deno > 0.0 else 1.0) * dim)
            fac11 = err ** 0.125
            hnew = h / max(1.0 / 6.0, min(1.0 / 0.333, fac11 / 0.9))
            if err <= 1.0:
                nacc += 1
                t += h
                y[:] = yn
                rhs(y, K[0], inv_m, na, nm1, pre)  # FSAL
                nfev += 1
                if last:
                    return y, nacc, nrej, nfev, True
                if reject:
                    hnew = min(hnew, h)
                reject = False
            else:
                hnew = h / min(1.0 / 0.333, fac11 / 0.9)
                reject, last = True, False
                if nacc >= 1:
                    nrej += 1
            h = min(hnew, t_end)
        return y, nacc, nrej, nfev, False

    @numba.njit(cache=False)
    def verlet(y0, t_end, dt_req, inv_m, na, nm1, pre):
        """Velocity Verlet with dt = t_end / ceil(t_end / dt_req); returns (y, steps)."""
        n = inv_m.size
        steps = int(math.ceil(t_end / dt_req))
        dt = t_end / steps
        u, v, a = y0[:n].copy(), y0[n:].copy(), np.empty(n)
        accel(u, a, inv_m, na, nm1, pre)
        half = 0.5 * dt
        for _ in range(steps):
            for i in range(n):
                v[i] += half * a[i]
                u[i] += dt * v[i]
            accel(u, a, inv_m, na, nm1, pre)
            for i in range(n):
                v[i] += half * a[i]
        return np.concatenate((u, v)), steps

    return dop853, verlet


# ---------------------------------------------------------------- the chain
def chain_of(binary, scene):
    """The resolved chain as NumPy arrays (and end time) from `beadchain scene show`."""
    import numpy as np
    text = subprocess.run([binary, "scene", "show", scene], capture_output=True, text=True, check=True).stdout
    for key in ("[walls]", "[field]", "[hard]", "[damping]", "restitution ="):
        if key in text:
            sys.exit("wholechain_numba: %s: %s is not modelled by the whole-chain kernels" % (scene, key))
    until = float([ln for ln in text.splitlines() if ln.startswith("until = ")][0].split("=")[1])
    rows = list(csv.DictReader(io.StringIO(subprocess.run(
        [binary, "scene", "show", scene, "--format", "csv"], capture_output=True, text=True, check=True).stdout)))
    col = lambda k, rs=rows: np.array([float(r[k] or 0.0) for r in rs])  # noqa: E731
    if any(r.get("restitution") for r in rows):
        sys.exit("wholechain_numba: %s: damped contacts are not modelled" % scene)
    return dict(mass=col("mass"), u0=col("u0"), v0=col("v0"), exponent=col("exponent", rows[:-1]),
                prefactor=col("prefactor", rows[:-1]), pre=col("precompression", rows[:-1]), until=until)


def energy(ch, u, v):
    import numpy as np
    d = np.maximum(ch["pre"] + u[:-1] - u[1:], 0.0)
    return 0.5 * np.dot(ch["mass"], v * v) + np.sum(ch["prefactor"] * d ** ch["exponent"])


def scales(ch):
    """beadchain's characteristic scales of the initial state: L, and V_i per bead (run_scene_peers.py)."""
    import numpy as np
    m, v, a, n = ch["mass"], ch["v0"], ch["prefactor"], ch["exponent"]
    pe = a * np.maximum(ch["pre"] + ch["u0"][:-1] - ch["u0"][1:], 0.0) ** n
    e = energy(ch, ch["u0"], v)
    m_e = min(list(m[m * v * v > 0]) + list(m[:-1][pe > 0]) + list(m[1:][pe > 0]))
    length = max(np.max((e / a) ** (1.0 / n)), np.max(np.abs(ch["pre"])))
    return length, np.sqrt(2.0 * e / np.maximum(m, m_e))


def args_of(ch):
    import numpy as np
    y0 = np.concatenate((ch["u0"], ch["v0"]))
    return y0, (1.0 / ch["mass"], ch["exponent"] * ch["prefactor"], ch["exponent"] - 1.0, ch["pre"])


# ---------------------------------------------------------------- runs
def run_dop853(dop853, ch, rtol, atol_ratio):
    import numpy as np
    y0, p = args_of(ch)
    length, vel = scales(ch)
    atol = atol_ratio * rtol * np.concatenate((np.full(len(ch["mass"]), length), vel))
    t0 = time.perf_counter()
    y, nacc, nrej, nfev, ok = dop853(y0, ch["until"], rtol, atol, *p, 10 ** 9)
    wall = time.perf_counter() - t0
    n = len(ch["mass"])
    return dict(status="ok" if ok else "failed", wall=wall, u=y[:n], v=y[n:], steps=nacc, rejected=nrej,
                rhs=nfev, bead_steps=nacc * n)


def run_verlet(verlet, ch, dt):
    y0, p = args_of(ch)
    t0 = time.perf_counter()
    y, steps = verlet(y0, ch["until"], dt, *p)
    wall = time.perf_counter() - t0
    n = len(ch["mass"])
    return dict(status="ok", wall=wall, u=y[:n], v=y[n:], steps=steps, rejected=0, rhs=steps + 1,
                bead_steps=steps * n)


def run_beadchain(binary, scene, rtol, tmp, extra=()):
    import numpy as np
    snap = os.path.join(tmp, "out.snap")
    cmd = [binary, "run", scene, "--rtol", repr(rtol), "--out", snap] + list(extra)
    for _ in range(30):  # the binary may be being rebuilt (missing, or busy): wait and retry
        try:
            out = subprocess.run(cmd, capture_output=True, text=True)
            break
        except OSError:
            time.sleep(10)
    else:
        return dict(status="error: %s could not be run" % binary)
    if out.returncode != 0:
        return dict(status="error: " + out.stderr.strip().splitlines()[-1] if out.stderr.strip() else "error")
    wall = float(re.search(r" in ([0-9.eE+-]+) s:", out.stdout).group(1))
    st = re.search(r"(\d+) steps \((\d+) rejected\), (\d+) active bead-steps, (\d+) RHS", out.stdout)
    last = subprocess.run([binary, "export", snap, "--frame", "last"], capture_output=True, text=True,
                          check=True).stdout
    # past the export's `# …` provenance lines
    rows = list(csv.DictReader(ln for ln in io.StringIO(last) if not ln.startswith("#")))
    return dict(status="ok", wall=wall, u=np.array([float(r["u"]) for r in rows]),
                v=np.array([float(r["v"]) for r in rows]), steps=int(st.group(1)), rejected=int(st.group(2)),
                bead_steps=int(st.group(3)), rhs=int(st.group(4)))


def velocity_error(res, ref):
    import numpy as np
    return float(np.abs(res["v"] - ref["v"]).max() / np.abs(ref["v"]).max())


# ---------------------------------------------------------------- time to reach an error level
def front(rows):
    """Pareto front of (wall, error): ascending time, strictly decreasing error."""
    out = []
    for r in sorted((r for r in rows if r["status"] == "ok"), key=lambda r: (r["wall"], r["error"])):
        if not out or r["error"] < out[-1]["error"]:
            out.append(r)
    return out


def cheapest(rows, level):
    ok = [r for r in rows if r["status"] == "ok" and r["error"] <= level]
    return min(ok, key=lambda r: r["wall"]) if ok else None


def interpolated(rows, level):
    """log-log interpolation of time against error between neighbouring front points; the
    cheapest run when even it is below `level` (no extrapolation); None when never reached."""
    f = front(rows)
    if not f or f[-1]["error"] > level:
        return None
    if f[0]["error"] <= level:
        return f[0]["wall"]
    for a, b in zip(f, f[1:]):
        if a["error"] > level >= b["error"]:
            w = (math.log(level) - math.log(a["error"])) / (math.log(b["error"]) - math.log(a["error"]))
            return math.exp(math.log(a["wall"]) + w * (math.log(b["wall"]) - math.log(a["wall"])))
    return None


def level_tables(rows):
    codes = [("numba DOP853", "numba dop853"), ("numba Verlet", "numba verlet"), ("beadchain", "beadchain")]
    by = {k: [r for r in rows if r["solver"] == k] for _, k in codes}
    fmt = lambda t: "%.4g" % t if t is not None else "not reached"  # noqa: E731
    def ratio(a, b):
        if a is None or b is None:
            return "—"
        return ("%.1f×" if a >= b else "%.2g×") % (a / b)

    lines = []
    for title, how in (("cheapest measured run whose error is at or below the level", "cheapest"),
                       ("log-log interpolation between neighbouring points of each code's time-error "
                        "front (the cheapest run where even it is below the level; no extrapolation)", "interp")):
        lines += ["", "Time to reach each final-velocity error level, %s:" % title, "",
                  "| error level | numba DOP853 (s) | numba Verlet (s) | beadchain (s) | DOP853 / beadchain "
                  "| Verlet / beadchain |", "|---|---|---|---|---|---|"]
        for lv in LEVELS:
            if how == "cheapest":
                t = {k: (lambda r: r["wall"] if r else None)(cheapest(by[k], lv)) for _, k in codes}
                txt = {k: (lambda r: "%.4g (%s)" % (r["wall"], r["knob"]) if r else "not reached")(
                    cheapest(by[k], lv)) for _, k in codes}
            else:
                t = {k: interpolated(by[k], lv) for _, k in codes}
                txt = {k: fmt(t[k]) for _, k in codes}
            b = t["beadchain"]
            lines.append("| %.0e | %s | %s | %s | %s | %s |" % (
                lv, txt["numba dop853"], txt["numba verlet"], txt["beadchain"],
                ratio(t["numba dop853"], b), ratio(t["numba verlet"], b)))
    return lines


# ---------------------------------------------------------------- main
def machine():
    model = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            model = [ln.split(":", 1)[1].strip() for ln in f if ln.startswith("model name")][0]
    except (OSError, IndexError):
        pass
    import numba
    import numpy
    return "nproc %d, CPU %s, load average %s; Python %s, numba %s, NumPy %s" % (
        os.cpu_count(), model, " ".join("%.2f" % x for x in os.getloadavg()), platform.python_version(),
        numba.__version__, numpy.__version__)


def binary_id(path):
    import hashlib
    with open(path, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()[:12]
    return "sha256 %s…, built %s" % (digest, time.strftime("%Y-%m-%d %H:%M", time.localtime(os.path.getmtime(path))))


def git_state():
    """The checkout's commit, and whether src/ has uncommitted changes (which the binary may include)."""
    def git(*a):
        return subprocess.run(["git", "-C", ROOT] + list(a), capture_output=True, text=True).stdout.strip()
    head = git("rev-parse", "--short", "HEAD") or "unknown"
    dirty = git("status", "--porcelain", "--", "src")
    return "checkout when the tables were written: %s%s" % (head, ", src/ with uncommitted changes" if dirty else "")


def floats(text):
    return [float(x) for x in text.split(",") if x]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default="interface_3.0_2.5")
    ap.add_argument("--binary", default=os.path.join(ROOT, "target", "release", "beadchain"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="one rtol (1e-6) per code, one dt, one repetition")
    ap.add_argument("--rtols", default="1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12,1e-13",
                    help="numba DOP853 tolerances")
    ap.add_argument("--beadchain-rtols", default="1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12")
    ap.add_argument("--verlet-dts", default="0.1,0.03,0.01,0.003,0.001,3e-4,1e-4,3e-5,1e-5,3e-6",
                    help="Verlet steps in units of tau = L/V (beadchain's scales; bead 0's V)")
    ap.add_argument("--verlet-max-seconds", type=float, default=30.0,
                    help="skip a Verlet run whose predicted time (the last one's per step) exceeds this")
    ap.add_argument("--atol-ratios", default="1e-2,1e-4",
                    help="numba DOP853 atol = ratio * rtol * scales, each rtol run with each ratio (1e-2: "
                         "run_scene_peers.py's matched atol; 1e-4: beadchain's default ratio)")
    ap.add_argument("--reference", choices=["dense", "numba"], default="dense",
                    help="beadchain dense Radau IIA or the numba DOP853, at --reference-rtol")
    ap.add_argument("--reference-rtol", type=float, default=1e-13)
    ap.add_argument("--out", help="writes OUT.csv and OUT.md [default: validation/peers/wholechain-SCENE]")
    args = ap.parse_args()
    if args.quick:
        args.rtols, args.beadchain_rtols, args.verlet_dts, args.repeat = "1e-6", "1e-6", "0.003", 1
        args.atol_ratios = args.atol_ratios.split(",")[0]
    ratios = floats(args.atol_ratios)
    name = os.path.basename(args.scene).replace(".toml", "")
    out = args.out or os.path.join(HERE, "wholechain-" + name)
    ch = chain_of(args.binary, args.scene)
    length, vel = scales(ch)
    tau = float(length / vel[0])
    dop853, verlet = kernels()
    binary_start = binary_id(args.binary)
    log = lambda *a: print(*a, file=sys.stderr, flush=True)  # noqa: E731
    t0 = time.perf_counter()
    short = dict(ch, until=ch["until"] * 1e-3)
    run_dop853(dop853, short, 1e-6, ratios[0])
    run_verlet(verlet, short, ch["until"] * 1e-4)
    log("compiled in %.1f s" % (time.perf_counter() - t0))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        rr = args.reference_rtol
        dense = lambda r: run_beadchain(args.binary, args.scene, r, tmp,  # noqa: E731
                                        ["--engine", "dense", "--method", "radau5", "--atol", repr(r / 100)])
        refs = dict(dense=dense(rr), dense10=dense(10 * rr),
                    numba=run_dop853(dop853, ch, rr, ratios[0]),
                    numba10=run_dop853(dop853, ch, 10 * rr, ratios[0]))
        for k, r in refs.items():
            if r["status"] != "ok":
                sys.exit("wholechain_numba: reference run %s: %s" % (k, r["status"]))
        ref = refs[args.reference]
        other = refs["numba" if args.reference == "dense" else "dense"]
        floor = velocity_error(refs[args.reference + "10"], ref)
        agree = velocity_error(other, ref)
        log("reference floor %.1e; the other reference (%s) differs by %.1e" % (floor, "numba DOP853" if
            args.reference == "dense" else "dense Radau IIA", agree))
        jobs = [("numba dop853", "rtol %g atol %g·rtol" % (r, q), r, lambda r=r, q=q: run_dop853(dop853, ch, r, q), q)
                for q in ratios for r in floats(args.rtols)]
        jobs += [("numba verlet", "dt %.3g" % (d * tau), d * tau, lambda d=d: run_verlet(verlet, ch, d * tau), "")
                 for d in floats(args.verlet_dts)]
        jobs += [("beadchain", "rtol %g" % r, r, lambda r=r: run_beadchain(args.binary, args.scene, r, tmp), "")
                 for r in floats(args.beadchain_rtols)]
        # repetitions interleaved (round-robin over the runs), so that a burst of other load on the
        # machine does not hit every repetition of one run
        results, walls, per_step = [None] * len(jobs), [[] for _ in jobs], 0.0
        for rnd in range(args.repeat):
            for i, (solver, knob, value, fn, ratio) in enumerate(jobs):
                if rnd == 0 and solver == "numba verlet" and \
                        per_step * math.ceil(ch["until"] / value) > args.verlet_max_seconds:
                    results[i] = dict(status="skipped (predicted > %g s)" % args.verlet_max_seconds)
                if results[i] is not None and results[i]["status"] != "ok":
                    continue
                results[i] = fn()
                if results[i]["status"] == "ok":
                    walls[i].append(results[i]["wall"])
                    if solver == "numba verlet":  # seconds per step, to skip runs predicted too long
                        per_step = results[i]["wall"] / results[i]["steps"]
            log("round %d of %d done" % (rnd + 1, args.repeat))
        e0 = energy(ch, ch["u0"], ch["v0"])
        for (solver, knob, value, fn, ratio), res, w in zip(jobs, results, walls):
            row = dict(solver=solver, knob=knob, value=value, atol_ratio=ratio, status=res["status"])
            if res["status"] == "ok":
                row.update(wall=statistics.median(w), error=velocity_error(res, ref), steps=res["steps"],
                           rejected=res["rejected"], rhs=res["rhs"], bead_steps=res["bead_steps"],
                           energy_error=float(abs(energy(ch, res["u"], res["v"]) - e0) / e0))
            rows.append(row)
            log({k: v for k, v in row.items()})
    if binary_id(args.binary) != binary_start:
        log("wholechain_numba: WARNING: %s changed during the invocation" % args.binary)
    write(args, out, rows, dict(floor=floor, agree=agree, tau=tau, name=name, binary=binary_start,
                                changed=binary_id(args.binary) != binary_start))


def write(args, out, rows, info):
    keys = ("wall", "error", "energy_error", "steps", "rejected", "rhs", "bead_steps")
    with open(out + ".csv", "w") as f:
        f.write("scene,solver,setting,value,atol_ratio,status,wall_seconds,velocity_error,energy_error,steps,rejected,"
                "rhs_evaluations,bead_steps,repeat,reference,reference_rtol,reference_floor\n")
        for r in rows:
            vals = [repr(float(r[k])) if k in ("wall", "error", "energy_error") else str(r[k])
                    for k in keys if k in r] or [""] * len(keys)
            f.write("%s,%s,%s,%r,%s,%s,%s,%d,%s,%r,%r\n" % (
                args.scene, r["solver"], r["knob"], float(r["value"]), r.get("atol_ratio", ""), r["status"],
                ",".join(vals), args.repeat, args.reference, args.reference_rtol, float(info["floor"])))
    ref = ("beadchain dense Radau IIA" if args.reference == "dense" else "numba DOP853")
    other = "numba DOP853" if args.reference == "dense" else "beadchain dense Radau IIA"
    lines = ["Scene `%s`; command `%s`." % (
        args.scene, " ".join(["python3 validation/peers/wholechain_numba.py"] + sys.argv[1:])), "",
        "- Machine: %s." % machine(),
        "- beadchain: %s (%s; %s)%s." % (os.path.relpath(args.binary, ROOT), info["binary"], git_state(),
                                         "; **the binary changed during the invocation**" if info["changed"] else ""),
        "- Reference: %s at rtol %g (atol rtol/100); its floor (against itself at 10× the rtol) %.1e; "
        "%s at the same rtol differs from it by %.1e." % (ref, args.reference_rtol, info["floor"], other,
                                                           info["agree"]),
        "- Error: max |v - v_ref| / max |v_ref| at t = end. Wall: median of %d (interleaved rounds over all "
        "runs), integration only (numba: the compiled call after a warm-up call that compiles; beadchain: "
        "the time `beadchain run` prints)." % (
            args.repeat),
        "- numba DOP853: atol = ratio·rtol × beadchain's scales, every rtol with every ratio of %s (the "
        "reference's %g). Verlet: dt in computer units (τ = L/V = %.4g). beadchain: `run SCENE --rtol R` "
        "(hybrid engine, method auto, default atol rtol/10⁴)." % (args.atol_ratios, floats(args.atol_ratios)[0],
                                                                   info["tau"]),
        "- Steps: whole-chain steps for numba (bead-steps = steps × beads), cluster steps for beadchain "
        "(bead-steps: the beads each step advances).", "",
        "| code | setting | wall (s) | velocity error | energy error | steps | rejected | RHS evals | bead-steps |",
        "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["status"] != "ok":
            lines.append("| %s | %s | %s | | | | | | |" % (r["solver"], r["knob"], r["status"]))
        else:
            lines.append("| %s | %s | %.4g | %.1e | %.1e | %d | %d | %d | %d |" % (
                r["solver"], r["knob"], r["wall"], r["error"], r["energy_error"], r["steps"], r["rejected"],
                r["rhs"], r["bead_steps"]))
    lines += level_tables(rows)
    text = "\n".join(lines) + "\n"
    with open(out + ".md", "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    ensure_venv()
    main()
