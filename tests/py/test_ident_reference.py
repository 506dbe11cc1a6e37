# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The identification experiment's reference simulator (ident_reference.py) against
textbook closed forms evaluated in mpmath at 40 digits, and its two integrators (RK4 with
2^p substeps for linear plants, the piecewise closed form with Coulomb friction) against
each other:

1. mass-damper step x(t) = F/b (t - m/b (1 - e^{-b t/m})), delta = bT/m from 1e-5 to 5,
   with delays; both integrators;
2. the damped spring: the step and the free response, under- and overdamped;
3. the lag: the step response of 1/(m s^2 (s + a)(tau s + 1)) by partial fractions, and a
   PRBS with lag, spring and delay against the exact sampled map (mpmath.expm, 40 digits);
4. RK4 converges at fourth order in the substep and is converged at the default p;
5. friction: sticking at |F| <= F_c, a push (the step with F - F_c), coasting to a stop at
   the closed-form time and place, a reversal, symmetry and dissipation;
6. measurement: quantization to the nearest count, noise of the stated deviation,
   simulate_many == simulate per trial.
"""
from __future__ import annotations

import math
from typing import Callable, List

import mpmath
import numpy as np
import pytest
from mpmath import mp, mpf

import ident_reference as R

DPS = 40
#: The simulator runs in double precision: positions agree to this, relative to the motion.
TOL = 1e-12


def _mp_series(f: Callable[[mpf], mpf], T: float, n: int, delay: int = 0) -> np.ndarray:
    """f at t = (j - delay) T for the samples j (0 before the force starts), in mpmath."""
    with mp.workdps(DPS):
        return np.array([float(f((j - delay) * mpf(T))) if j > delay else 0.0 for j in range(n)])


def _rel(x: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


# ---- 1. the mass-damper ------------------------------------------------------------------------


@pytest.mark.parametrize("m,b,T", [(0.1, 2.0, 1e-3), (1.0, 0.05, 1e-4), (85.78e-7, 2.197e-3, 0.02),
                                   (0.01, 20.0, 1e-3), (85.78e-7, 13.93e-6, 0.008)])
@pytest.mark.parametrize("delay", [0, 2])
def test_mass_damper_step(m: float, b: float, T: float, delay: int) -> None:
    F, n = 0.7, 300

    def x(t: mpf) -> mpf:
        return mpf(F) / b * (t - mpf(m) / b * (1 - mpmath.exp(-mpf(b) * t / m)))

    ref = _mp_series(x, T, n, delay)
    u = np.full(n, F)
    for method in ("rk4", "piecewise"):
        got = R.simulate(m, b, T, u, delay=delay, method=method)
        assert np.all(got[:delay + 1] == 0.0)
        assert _rel(got, ref) < TOL, (method, _rel(got, ref))


def test_mass_damper_initial_state() -> None:
    m, b, T, x0, v0, n = 0.3, 1.5, 5e-4, 0.01, -0.2, 400

    def x(t: mpf) -> mpf:
        return mpf(x0) + mpf(v0) * m / b * (1 - mpmath.exp(-mpf(b) * t / m))

    with mp.workdps(DPS):
        ref = np.array([float(x(j * mpf(T))) for j in range(n)])
    for method in ("rk4", "piecewise"):
        got = R.simulate(m, b, T, np.zeros(n), x0=x0, v0=v0, method=method)
        assert _rel(got - x0, ref - x0) < TOL


# ---- 2. the spring -----------------------------------------------------------------------------


def _oscillator(m: float, b: float, k: float, x0: float, v0: float, F: float) -> Callable[[mpf], mpf]:
    """x(t) of m x'' + b x' + k x = F from (x0, v0): equilibrium F/k plus the free motion
    e^{-a t/2} (c cos(w t) + s sin(w t)/w), or cosh/sinh when overdamped."""
    a = mpf(b) / m
    disc = a * a / 4 - mpf(k) / m
    e0 = mpf(x0) - mpf(F) / k
    slope = mpf(v0) + a / 2 * e0

    def x(t: mpf) -> mpf:
        if disc < 0:
            w = mpmath.sqrt(-disc)
            free = e0 * mpmath.cos(w * t) + slope * mpmath.sin(w * t) / w
        else:
            w = mpmath.sqrt(disc)
            free = e0 * mpmath.cosh(w * t) + slope * mpmath.sinh(w * t) / w
        return mpf(F) / k + mpmath.exp(-a * t / 2) * free

    return x


@pytest.mark.parametrize("m,b,k,T", [(0.1, 2.0, 400.0, 1e-3), (0.05, 0.1, 2000.0, 2e-4),
                                     (0.2, 30.0, 50.0, 1e-3)])   # under-, lightly, overdamped
def test_spring_step(m: float, b: float, k: float, T: float) -> None:
    F, n, delay = 1.3, 500, 1
    ref = _mp_series(_oscillator(m, b, k, 0.0, 0.0, F), T, n, delay)
    got = R.simulate(m, b, T, np.full(n, F), delay=delay, k=k)
    assert _rel(got, ref) < TOL


def test_spring_free_response() -> None:
    m, b, k, T, n = 0.1, 0.5, 900.0, 1e-3, 600
    x = _oscillator(m, b, k, 0.002, 0.3, 0.0)
    with mp.workdps(DPS):
        ref = np.array([float(x(j * mpf(T))) for j in range(n)])
    got = R.simulate(m, b, T, np.zeros(n), k=k, x0=0.002, v0=0.3)
    assert _rel(got, ref) < TOL


# ---- 3. the lag ----------------------------------------------------------------------------------


@pytest.mark.parametrize("m,b,tau,T", [(0.1, 2.0, 3e-4, 1e-3), (0.5, 0.2, 1e-4, 1e-3),
                                       (85.78e-7, 2.197e-3, 0.004, 0.008)])
def test_lag_step(m: float, b: float, tau: float, T: float) -> None:
    """X(s) = F lam / (m s^2 (s + a)(s + lam)), lam = 1/tau: A/s^2 + B/s + C/(s + a) + D/(s + lam)."""
    F, n, delay = 0.9, 300, 1
    with mp.workdps(DPS):
        a, lam = mpf(b) / m, 1 / mpf(tau)
        A = 1 / (a * lam)
        B = -(a + lam) / (a * lam) ** 2
        C = 1 / (a * a * (lam - a))
        D = 1 / (lam * lam * (a - lam))
        gain = mpf(F) * lam / m

    def x(t: mpf) -> mpf:
        return gain * (A * t + B + C * mpmath.exp(-a * t) + D * mpmath.exp(-lam * t))

    ref = _mp_series(x, T, n, delay)
    got = R.simulate(m, b, T, np.full(n, F), delay=delay, tau=tau)
    assert _rel(got, ref) < TOL


def _exact_sampled(m: float, b: float, k: float, tau: float, T: float, u: np.ndarray, delay: int) -> np.ndarray:
    """The exact ZOH map of the plant with lag and spring, mpmath.expm of the augmented
    matrix at 40 digits (a reference for the reference, not its method)."""
    with mp.workdps(DPS):
        M = mpmath.zeros(4, 4)
        M[0, 1] = 1
        M[1, 0], M[1, 1], M[1, 2] = -mpf(k) / m, -mpf(b) / m, 1 / mpf(m)
        M[2, 2], M[2, 3] = -1 / mpf(tau), 1 / mpf(tau)
        E = mpmath.expm(M * mpf(T))
        z = mpmath.matrix([0, 0, 0])
        out = []
        for j in range(u.size):
            out.append(float(z[0]))
            f = mpf(float(u[j - delay])) if j >= delay else mpf(0)
            z = mpmath.matrix([sum(E[i, c] * z[c] for c in range(3)) + E[i, 3] * f for i in range(3)])
    return np.array(out)


def test_prbs_lag_spring_delay_against_expm() -> None:
    m, b, k, tau, T, delay = 0.08, 1.2, 300.0, 4e-4, 1e-3, 2
    u = np.random.default_rng(7).choice([-1.0, 1.0], 80).repeat(2)
    ref = _exact_sampled(m, b, k, tau, T, u, delay)
    got = R.simulate(m, b, T, u, delay=delay, k=k, tau=tau)
    assert _rel(got, ref) < TOL


# ---- 4. RK4's order ------------------------------------------------------------------------------


def test_rk4_fourth_order_and_converged() -> None:
    m, b, k, tau, T = 0.05, 3.0, 0.0, 2e-4, 1e-3     # delta = 0.06, lam = 5: the lag is the fast mode
    Phi_ref, Gam_ref, p_ref = R.rk4_sample_map(m, b, T, k=k, tau=tau)
    assert p_ref >= R.MIN_DOUBLINGS
    with mp.workdps(DPS):
        M = mpmath.matrix([[0, 1, 0, 0], [0, -mpf(b) * T / m, 1, 0], [0, 0, -mpf(T) / tau, mpf(T) / tau],
                           [0, 0, 0, 0]])
        E = mpmath.expm(M)
        exact = np.array([[float(E[i, j]) for j in range(4)] for i in range(3)])
    err_default = float(np.max(np.abs(np.column_stack([Phi_ref[0], Gam_ref[0]]) - exact)))
    assert err_default < 1e-14
    errors: List[float] = []
    for p in (5, 6, 7, 8):
        Phi, Gam, _ = R.rk4_sample_map(m, b, T, k=k, tau=tau, doublings=p)
        errors.append(float(np.max(np.abs(np.column_stack([Phi[0], Gam[0]]) - exact))))
    ratios = [errors[i] / errors[i + 1] for i in range(len(errors) - 1)]
    assert all(14.0 < r < 18.0 for r in ratios), ratios     # halving h divides the error by 2^4


# ---- 5. friction ---------------------------------------------------------------------------------


@pytest.mark.parametrize("F", [0.0, 0.3, -0.3, 0.5, -0.5])
def test_friction_sticks(F: float) -> None:
    x = R.simulate(0.1, 2.0, 1e-3, np.full(200, F), coulomb=0.5, x0=0.25)
    assert np.all(x == 0.25)


def test_friction_zero_equals_linear() -> None:
    u = np.random.default_rng(3).choice([-1.0, 1.0], 400).repeat(3)
    for m, b, T in ((0.1, 2.0, 1e-3), (85.78e-7, 2.197e-3, 0.008), (0.8, 0.05, 1e-4)):
        a = R.simulate(m, b, T, u, delay=1, method="piecewise", v0=0.01)
        c = R.simulate(m, b, T, u, delay=1, method="rk4", v0=0.01)
        assert _rel(a, c) < TOL


def test_friction_push_from_rest() -> None:
    m, b, T, F, Fc, n = 0.2, 1.0, 1e-3, 0.8, 0.3, 400

    def x(t: mpf) -> mpf:
        g = mpf(F) - mpf(Fc)
        return g / b * (t - mpf(m) / b * (1 - mpmath.exp(-mpf(b) * t / m)))

    ref = _mp_series(x, T, n, 1)
    got = R.simulate(m, b, T, np.full(n, F), delay=1, coulomb=Fc)
    assert _rel(got, ref) < TOL
    neg = R.simulate(m, b, T, np.full(n, -F), delay=1, coulomb=Fc)
    assert np.array_equal(neg, -got)


def test_friction_coasts_to_a_stop() -> None:
    """v(t) = (v0 + Fc/b) e^{-a t} - Fc/b stops at t* = ln(1 + b v0/Fc)/a, then sticks (u = 0)."""
    m, b, T, Fc, v0, n = 0.1, 0.4, 1e-3, 0.1, 0.3, 600
    with mp.workdps(DPS):
        a, c = mpf(b) / m, mpf(Fc) / b
        t_stop = mpmath.log(1 + mpf(v0) / c) / a

        def x(t: mpf) -> mpf:
            t = min(t, t_stop)
            return (mpf(v0) + c) * (1 - mpmath.exp(-a * t)) / a - c * t

        ref = np.array([float(x(j * mpf(T))) for j in range(n)])
    assert float(t_stop) < 0.5 * n * T
    x_got, v_got = R.trajectory_many(m, b, T, np.zeros((1, n)), coulomb=Fc, v0=v0)
    assert _rel(x_got[0], ref) < TOL
    stopped = np.arange(n) * T > float(t_stop)
    assert np.all(v_got[0][stopped] == 0.0) and np.all(v_got[0][~stopped] > 0.0)
    assert np.all(np.diff(v_got[0]) <= 0.0)
    # friction only dissipates: it stops short of the frictionless coast v0 m / b
    assert x_got[0][-1] < v0 * m / b


def test_friction_reversal() -> None:
    """Moving forward, pushed back with |F| > Fc: decelerate with (-F - Fc), pass through 0 and
    accelerate back with (-F + Fc), in the same sample."""
    m, b, T, F, Fc, v0, n = 0.1, 0.4, 1e-3, 0.5, 0.1, 0.2, 300
    with mp.workdps(DPS):
        a = mpf(b) / m
        g1 = (-mpf(F) - Fc) / m
        g2 = (-mpf(F) + Fc) / m
        t1 = mpmath.log(1 - a * mpf(v0) / g1) / a                # v0 e^{-a t} + g1 (1 - e^{-a t})/a = 0

        def x(t: mpf) -> mpf:
            def move(x0: mpf, v: mpf, g: mpf, s: mpf) -> mpf:
                return x0 + v * (1 - mpmath.exp(-a * s)) / a + g * (s - (1 - mpmath.exp(-a * s)) / a) / a
            if t <= t1:
                return move(mpf(0), mpf(v0), g1, t)
            return move(move(mpf(0), mpf(v0), g1, t1), mpf(0), g2, t - t1)

        ref = np.array([float(x(j * mpf(T))) for j in range(n)])
    got = R.simulate(m, b, T, np.full(n, -F), coulomb=Fc, v0=v0)
    assert _rel(got, ref) < TOL
    assert got[-1] < 0.0


def test_friction_symmetry_and_scaling() -> None:
    u = np.random.default_rng(5).choice([-1.0, 1.0], 300).repeat(4)
    x = R.simulate(0.05, 0.5, 1e-3, u, delay=2, coulomb=0.04, v0=0.01)
    assert np.array_equal(R.simulate(0.05, 0.5, 1e-3, -u, delay=2, coulomb=0.04, v0=-0.01), -x)
    # homogeneous of degree 1 in (u, F_c, v0): a power of 2 scales exactly
    assert np.array_equal(R.simulate(0.05, 0.5, 1e-3, 4 * u, delay=2, coulomb=0.16, v0=0.04), 4 * x)


def test_friction_with_lag_or_spring_not_implemented() -> None:
    u = np.ones(20)
    with pytest.raises(NotImplementedError):
        R.simulate(0.1, 1.0, 1e-3, u, coulomb=0.1, tau=1e-4)
    with pytest.raises(NotImplementedError):
        R.simulate(0.1, 1.0, 1e-3, u, coulomb=0.1, k=10.0)


# ---- 6. measurement and batching -------------------------------------------------------------------


def test_quantization_and_noise() -> None:
    u = np.random.default_rng(1).choice([-1.0, 1.0], 2000).repeat(2)
    exact = R.simulate(0.1, 2.0, 1e-3, u)
    cpu = 1000.0 / np.ptp(exact)
    q = R.simulate(0.1, 2.0, 1e-3, u, counts_per_unit=cpu)
    counts = q * cpu
    assert np.allclose(counts, np.round(counts), atol=1e-6)
    assert np.max(np.abs(q - exact)) <= 0.5 / cpu * (1 + 1e-9)
    sigma = 1e-3 * np.ptp(exact)
    noisy = R.simulate(0.1, 2.0, 1e-3, u, noise=sigma, rng=np.random.default_rng(2))
    assert abs(np.std(noisy - exact) / sigma - 1.0) < 0.05
    again = R.simulate(0.1, 2.0, 1e-3, u, noise=sigma, rng=np.random.default_rng(2))
    assert np.array_equal(noisy, again)


def test_many_equals_one() -> None:
    rng = np.random.default_rng(4)
    n = 300
    U = rng.choice([-1.0, 1.0], (4, n))
    m = np.array([0.1, 0.02, 0.5, 85.78e-7])
    b = np.array([2.0, 0.3, 8.0, 2.197e-3])
    T = np.array([1e-3, 2e-4, 1e-3, 0.008])
    k = np.array([0.0, 100.0, 0.0, 0.0])
    tau = np.array([0.0, 1e-4, 5e-4, 0.0])              # lagged and unlagged trials together
    many = R.simulate_many(m, b, T, U, delay=1, k=k, tau=tau)
    for i in range(4):
        one = R.simulate(float(m[i]), float(b[i]), float(T[i]), U[i], delay=1, k=float(k[i]), tau=float(tau[i]))
        assert _rel(many[i], one) < TOL       # the batch's substeps suit its fastest trial
    fr = R.simulate_many(m[[0, 2]], b[[0, 2]], T[[0, 2]], U[[0, 2]], coulomb=np.array([0.05, 0.0]))
    assert np.array_equal(fr[1], R.simulate(0.5, 8.0, 1e-3, U[2], method="piecewise"))
    assert math.isfinite(float(fr.sum()))
