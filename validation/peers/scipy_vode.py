"""SciPy VODE (BDF, banded Jacobian) on the uniform striker chain, as in the paper's appendix A.

State interleaved as (u_0, v_0, u_1, v_1, ...) so the Jacobian of z' = F(z) is banded
(lower and upper bandwidth 3); VODE builds it by finite differences over the band.
Prints one line: wall seconds and relative total-energy error at t_end.
Usage: python scipy_vode.py N T_END RTOL ATOL
"""
import sys
import time

import numpy as np
from scipy.integrate import ode

N = int(sys.argv[1])
T_END = float(sys.argv[2])
RTOL = float(sys.argv[3])
ATOL = float(sys.argv[4])
EXP, A = 2.5, 1.0  # exponent and prefactor; unit masses, striker v0 = 1


def rhs(_t, y):
    u = y[0::2]
    d = np.maximum(u[:-1] - u[1:], 0.0)
    f = EXP * A * d ** (EXP - 1.0)
    acc = np.zeros(N)
    acc[:-1] -= f
    acc[1:] += f
    out = np.empty_like(y)
    out[0::2] = y[1::2]
    out[1::2] = acc
    return out


def energy(y):
    u, v = y[0::2], y[1::2]
    d = np.maximum(u[:-1] - u[1:], 0.0)
    return 0.5 * np.dot(v, v) + np.sum(A * d**EXP)


y0 = np.zeros(2 * N)
y0[1] = 1.0
e0 = energy(y0)
r = ode(rhs).set_integrator(
    "vode", method="bdf", rtol=RTOL, atol=ATOL, nsteps=10**9, lband=3, uband=3
)
r.set_initial_value(y0, 0.0)
t0 = time.perf_counter()
r.integrate(T_END)
dt = time.perf_counter() - t0
ok = r.successful()
print(f"vode {RTOL:g} {ATOL:g} {dt:.3f} {abs(energy(r.y) - e0) / e0:.3e} {'ok' if ok else 'FAILED'}")
