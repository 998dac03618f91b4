"""Tests of wholechain_numba.py: its compiled DOP853 and Verlet against exact two-bead solutions and
energy conservation (skipped when numba or SciPy, whose DOP853 coefficients it reads, is missing),
and its time-to-error-level tables (plain Python, always run).

Run: validation/peers/.venv/bin/python -m pytest validation/peers/test_wholechain_numba.py
(the .venv that `wholechain_numba.py` creates has numba; CI's venv has neither numba nor SciPy, so
the kernel tests skip there)."""

import math
import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import wholechain_numba as wcn  # noqa: E402


@pytest.fixture(scope="module")
def kernels():
    pytest.importorskip("numba")
    pytest.importorskip("scipy")
    return wcn.kernels()


def _chain(mass, u0, v0, exponent, prefactor, pre, until):
    import numpy as np
    arr = lambda x: np.array(x, dtype=float)  # noqa: E731
    return dict(mass=arr(mass), u0=arr(u0), v0=arr(v0), exponent=arr(exponent), prefactor=arr(prefactor),
                pre=arr(pre), until=until)


def _pair_exact(m1, m2, a, v0, pre, t):
    """Two beads, linear contact (n = 2, V = a δ², F = 2 a δ), δ = Δ + u_0 - u_1, bead 0 moving at v0,
    bead 1 at rest, both at u = 0. Relative motion μ δ'' = -2 a δ while δ > 0, μ = m1 m2 / (m1 + m2),
    ω = sqrt(2 a / μ): δ = Δ cos ωt + (v0/ω) sin ωt = R sin(ωt + φ) until it reaches 0 at
    t_c = (π - φ)/ω, then δ' = -R ω (separation at the approach speed R ω: elastic). Returns (u, v)."""
    mu, tot = m1 * m2 / (m1 + m2), m1 + m2
    w = math.sqrt(2.0 * a / mu)
    r, phi = math.hypot(pre, v0 / w), math.atan2(pre, v0 / w)
    t_c = (math.pi - phi) / w
    if t <= t_c:
        d, dd = r * math.sin(w * t + phi), r * w * math.cos(w * t + phi)
    else:
        d, dd = -r * w * (t - t_c), -r * w
    x, vc = m1 * v0 / tot * t, m1 * v0 / tot  # centre of mass
    rel = d - pre  # u_0 - u_1
    return (x + m2 / tot * rel, x - m1 / tot * rel), (vc + m2 / tot * dd, vc - m1 / tot * dd), t_c


def _dop853(dop853, ch, rtol, atol=1e-14):
    import numpy as np
    y0, p = wcn.args_of(ch)
    y, nacc, nrej, nfev, ok = dop853(y0, ch["until"], rtol, np.full(y0.size, atol), *p, 10 ** 7)
    assert ok
    n = len(ch["mass"])
    return y[:n], y[n:], nacc


@pytest.mark.parametrize("pre, v0", [(0.0, 1.3), (0.2, 0.0), (0.1, 0.5)])
def test_dop853_two_bead_linear_contact_matches_the_exact_solution(kernels, pre, v0):
    """Head-on collision (contact time π sqrt(μ / (2a)) for Δ = 0), a precompressed pair released
    from rest, and both; unequal masses; end time 1.5 contact times, past the separation."""
    m1, m2, a = 1.0, 3.0, 0.7
    _, _, t_c = _pair_exact(m1, m2, a, v0, pre, 0.0)
    if pre == 0.0:
        assert t_c == pytest.approx(math.pi * math.sqrt(m1 * m2 / (m1 + m2) / (2.0 * a)), rel=1e-15)
    t_end = 1.5 * t_c
    (u0, u1), (w0, w1), _ = _pair_exact(m1, m2, a, v0, pre, t_end)
    ch = _chain([m1, m2], [0.0, 0.0], [v0, 0.0], [2.0], [a], [pre], t_end)
    u, v, steps = _dop853(kernels[0], ch, 1e-11)
    scale = max(abs(w0), abs(w1))
    assert abs(v[0] - w0) < 1e-8 * scale and abs(v[1] - w1) < 1e-8 * scale, (v, (w0, w1))
    assert abs(u[0] - u0) < 1e-8 * scale * t_end and abs(u[1] - u1) < 1e-8 * scale * t_end, (u, (u0, u1))
    assert steps < 2000


def test_dop853_conserves_energy_on_a_hertz_striker_chain(kernels):
    """20 beads, n = 2.5, striker v = 1, to t = 40 (the wave has crossed the chain and bead 19 has
    left): relative energy change below 5e-9 at rtol 1e-11, momentum exact to rounding."""
    import numpy as np
    n = 20
    ch = _chain([1.0] * n, [0.0] * n, [1.0] + [0.0] * (n - 1), [2.5] * (n - 1), [1.0] * (n - 1), [0.0] * (n - 1),
                40.0)
    u, v, _ = _dop853(kernels[0], ch, 1e-11)
    e0, e1 = wcn.energy(ch, ch["u0"], ch["v0"]), wcn.energy(ch, u, v)
    assert abs(e1 - e0) / e0 < 5e-9  # measured 5.1e-10 (the n = 2.5 contact onsets limit it)
    assert abs(np.sum(v) - 1.0) < 1e-12
    assert v[-1] > 0.5  # the pulse arrived and launched the last bead


def test_verlet_is_second_order_on_the_linear_pair(kernels):
    """Within the contact (smooth motion) halving dt divides the error by ~4."""
    import numpy as np
    m1, m2, a, v0 = 1.0, 3.0, 0.7, 1.3
    _, _, t_c = _pair_exact(m1, m2, a, v0, 0.0, 0.0)
    t_end = 0.7 * t_c
    _, (w0, w1), _ = _pair_exact(m1, m2, a, v0, 0.0, t_end)
    ch = _chain([m1, m2], [0.0, 0.0], [v0, 0.0], [2.0], [a], [0.0], t_end)
    y0, p = wcn.args_of(ch)
    errs = []
    for steps in (200, 400, 800):
        y, taken = kernels[1](y0, t_end, t_end / steps, *p)
        assert taken == steps
        errs.append(np.abs(y[2:] - [w0, w1]).max())
    for e, f in zip(errs, errs[1:]):
        assert 3.5 < e / f < 4.5, errs


def _row(solver, wall, error, knob="x"):
    return dict(solver=solver, knob=knob, status="ok", wall=wall, error=error)


def test_time_to_level_cheapest_and_interpolated():
    rows = [_row("c", 1.0, 1e-2), _row("c", 2.0, 1e-4), _row("c", 3.0, 1e-3),  # the 3 s run is dominated
            _row("c", 8.0, 1e-6), dict(solver="c", knob="y", status="failed")]
    assert wcn.cheapest(rows, 1e-3)["wall"] == 2.0
    assert wcn.cheapest(rows, 1e-7) is None
    assert [r["wall"] for r in wcn.front(rows)] == [1.0, 2.0, 8.0]
    assert wcn.interpolated(rows, 1e-1) == 1.0  # no extrapolation above the loosest run
    assert wcn.interpolated(rows, 1e-3) == pytest.approx(math.sqrt(2.0))  # halfway, log-log
    assert wcn.interpolated(rows, 1e-5) == pytest.approx(4.0)
    assert wcn.interpolated(rows, 1e-7) is None


def test_level_tables_give_ratios_to_beadchain():
    rows = [_row("numba dop853", 0.4, 1e-3, "rtol 1e-6"), _row("numba verlet", 1.0, 1e-3, "dt 1"),
            _row("beadchain", 0.1, 1e-4, "rtol 1e-5"), _row("numba verlet", 0.0044, 1e-2, "dt 9")]
    text = "\n".join(wcn.level_tables(rows))
    assert "| 1e-02 | 0.4 (rtol 1e-6) | 0.0044 (dt 9) | 0.1 (rtol 1e-5) | 4.0× | 0.044× |" in text, text
    assert "| 1e-03 | 0.4 (rtol 1e-6) | 1 (dt 1) | 0.1 (rtol 1e-5) | 4.0× | 10.0× |" in text, text
    assert "| 1e-04 | not reached | not reached | 0.1 (rtol 1e-5) | — | — |" in text, text
