# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Independent references for the scene simulator (tests/py/test_sim_reference.py).

Nothing here reuses the simulator's formulas.  The plant m x'' + b x' = F with F held
constant over [t, t + h) (zero-order hold) is solved analytically, in mpmath, from its
definition: with a = b/m and E1 = 1 - exp(-a h),

    v(t + h) = exp(-a h) v + (E1 / b) F
    x(t + h) = x + (E1 / a) v + ((a h - E1) / (a b)) F          (b > 0)
    v(t + h) = v + (h / m) F,   x(t + h) = x + h v + (h^2 / (2 m)) F       (b = 0)

and the controller of paper Fig. 13, F_k = K (x_eq_k - x_k) - B (x_k - x_{k-1}) / T with
x_{-1} = x_0, is evaluated on the mpmath state, so the trajectory is the exact sampled
solution for the exact binary inputs (to ~`dps` digits).  The closed loop is linear in
z_k = (x_k, T v_k, x_{k-1}) (every component a length): z_{k+1} = A z_k + input; A gives
the rounding-error bound of the tests.

Stability comes from the characteristic polynomial of notes/math.md,
p(z) = 2 z^3 + a1 z^2 + a2 z - c2 beta, with c1, c2, e from their literal definitions at
extra precision (the literal forms cancel for small delta), its roots by mpmath.polyroots;
the tests cross-check it against the eigenvalues of A (two derivations, one answer).
"""
from __future__ import annotations

import math

import mpmath
import numpy as np
from mpmath import mp, mpf

DPS = 50
U = 2.0 ** -53  # unit roundoff of double


def _guard(x):
    """Extra digits for quantities that cancel like log10(1/x) digits for small x."""
    x = mpf(x)
    return 10 + (int(-mpmath.log10(x)) + 1 if 0 < x < 1 else 0)


# ---------------------------------------------------------------------------------------
# The exact zero-order-hold step of the continuous plant
# ---------------------------------------------------------------------------------------


def zoh_step(m, b, T, dps=DPS):
    """(Ev, Pv, Gx, Gv) of x+ = x + Pv v + Gx F, v+ = Ev v + Gv F for the exact binary
    m, b, T (mpf).  Pv and Gx cancel like a T (Gx like (a T)^2), so they are evaluated at
    dps plus that many digits."""
    m, b, T = mpf(float(m)), mpf(float(b)), mpf(float(T))
    if b == 0:
        return mpf(1), T, T * T / (2 * m), T / m
    with mp.workdps(dps):
        aT = b * T / m
    with mp.workdps(dps + 2 * _guard(aT)):
        a = b / m
        aT = a * T
        E1 = -mpmath.expm1(-aT)
        out = (1 - E1, E1 / a, (aT - E1) / (a * b), E1 / b)
    with mp.workdps(dps):
        return tuple(+x for x in out)


def x_eq_at(scene, k):
    """The reference of sample k: x_eq_after from t_step on (t_k = k T compared exactly:
    the tests keep t_step away from sample instants, where float and exact k T agree)."""
    T = mpf(float(scene["T"]))
    return scene.get("x_eq_after", 0.0) if k * T >= mpf(float(scene.get("t_step", 0.0))) \
        else scene.get("x_eq_before", 0.0)


def exact_trajectory(scene, n, dps=DPS):
    """The exact sampled trajectory of a linear scene (flat scene dict: m, b, T, K, B,
    x_init, v_init, x_eq_before, x_eq_after, t_step) over n samples: lists x, v, F of mpf
    (state at t_k and the force held over [t_k, t_k + T))."""
    Ev, Pv, Gx, Gv = zoh_step(scene["m"], scene["b"], scene["T"], dps)
    with mp.workdps(dps):
        K, B, T = (mpf(float(scene[k])) for k in ("K", "B", "T"))
        BT = B / T
        x = mpf(float(scene.get("x_init", 0.0)))
        v = mpf(float(scene.get("v_init", 0.0)))
        x_prev = x
        xs, vs, Fs = [], [], []
        for k in range(n):
            F = K * (mpf(float(x_eq_at(scene, k))) - x) - BT * (x - x_prev)
            xs.append(x)
            vs.append(v)
            Fs.append(F)
            x_prev = x
            x, v = x + Pv * v + Gx * F, Ev * v + Gv * F
    return xs, vs, Fs


def closed_loop_matrix(scene, dps=DPS):
    """A (3x3 mpmath matrix) of z_{k+1} = A z_k + input, z = (x, T v, x_prev)."""
    Ev, Pv, Gx, Gv = zoh_step(scene["m"], scene["b"], scene["T"], dps)
    with mp.workdps(dps):
        m, T, K, B = (mpf(float(scene[k])) for k in ("m", "T", "K", "B"))
        # F = -K x - (B/T)(x - x_prev) + K x_eq
        fx, fp = -K - B / T, B / T
        return mp.matrix([[1 + Gx * fx, Pv / T, Gx * fp],
                          [T * Gv * fx, Ev, T * Gv * fp],
                          [1, 0, 0]])


def abs_powers(A, n):
    """|A^j| elementwise, j = 0 .. n-1, as an (n, 3, 3) float64 array (a bound needs no
    more precision)."""
    A = np.array(A.tolist(), dtype=float)
    P = np.eye(3)
    out = np.empty((n, 3, 3))
    for j in range(n):
        out[j] = np.abs(P)
        P = A @ P
    return out


def term_scales(scene, xs, vs, n=None):
    """Per sample, the magnitudes of the terms the exact step adds up, in lengths:
        s_x = |x| + phi |T v| + (c1/2) (alpha |x_eq - x| + |beta| |x - x_prev|)
        s_v = e |T v| (1 + delta) + phi (alpha |x_eq - x| + |beta| |x - x_prev|)
    with phi = (1 - e)/delta (T Pv, m Gv / T) and c1/2 = m Gx / T^2 from the exact step;
    e's term carries 1 + delta because e = exp(-delta) turns delta's own rounding (relative
    u's) into delta times as much."""
    x, tv, f = magnitudes(scene, xs, vs, n)
    Ev, Pv, Gx, Gv = (float(c) for c in zoh_step(scene["m"], scene["b"], scene["T"]))
    m, b, T = (float(scene[k]) for k in ("m", "b", "T"))
    delta = b * T / m
    phi, half_c1, phi_v = Pv / T, Gx * m / (T * T), Gv * m / T
    return x + phi * tv + half_c1 * f, Ev * (1 + delta) * tv + phi_v * f


def plain_scales(scene, xs, vs, n=None):
    """s_x = s_v = |x| + |T v| + alpha |x_eq - x| + |beta| |x - x_prev| per sample: the
    scale of an integrator's terms (it sees x, T v and the force at every substep whatever
    the step's coefficients)."""
    x, tv, f = magnitudes(scene, xs, vs, n)
    s = x + tv + f
    return s, s


def magnitudes(scene, xs, vs, n=None):
    """|x|, |T v| and alpha |x_eq - x| + |beta| |x - x_prev| (the force in lengths, T^2/m F)."""
    n = len(xs) if n is None else n
    m, T, K, B = (float(scene[k]) for k in ("m", "T", "K", "B"))
    alpha, beta = abs(K) * T * T / m, abs(B) * T / m
    x = np.array([float(v) for v in xs[:n]])
    tv = T * np.abs(np.array([float(v) for v in vs[:n]]))
    xeq = np.array([float(x_eq_at(scene, k)) for k in range(n)])
    xprev = np.concatenate(([x[0]], x[:-1]))
    return np.abs(x), tv, alpha * np.abs(xeq - x) + beta * np.abs(x - xprev)


def rounding_bound(scene, xs, vs, c, n=None, scales=term_scales):
    """Componentwise bound on the error of (x, T v) at each sample of a computation that
    commits, per sample, at most c u times the magnitude of the terms it adds up
    (`scales`, term_scales by default: d_j <= c u (s_x_j, s_v_j, 0), rounded coefficients
    included),
    propagated exactly by the closed loop (z = (x, T v, x_prev)):
        e_k = sum_{j<k} A^(k-1-j) d_j  =>  |e_k| <= c u sum_{j<k} |A^(k-1-j)| (s_x_j, s_v_j, 0).
    For a stable loop this stays below c u (sum_j ||A^j||) max s: bounded however long
    the run.  Returns (bound_x, bound_Tv, sum_j ||A^j||_inf, max(s_x, s_v))."""
    sx, sv = scales(scene, xs, vs, n)
    n = len(sx)
    P = abs_powers(closed_loop_matrix(scene), n)
    out = []
    for row in (0, 1):
        conv = np.convolve(P[:, row, 0], sx)[: n - 1] + np.convolve(P[:, row, 1], sv)[: n - 1]
        out.append(c * U * np.concatenate(([0.0], conv)))
    return out[0], out[1], P.sum(axis=2).max(axis=1).sum(), np.maximum(sx, sv)


# ---------------------------------------------------------------------------------------
# Characteristic polynomial, spectral radius, regions (notes/math.md)
# ---------------------------------------------------------------------------------------


def normalized(m, b, T, K, B, dps=DPS):
    """(delta, alpha, beta) as mpf from the exact binary inputs."""
    with mp.workdps(dps + 10):
        m, b, T, K, B = (mpf(float(v)) for v in (m, b, T, K, B))
        return b * T / m, K * T * T / m, B * T / m


def coefficients(delta, dps=DPS):
    """(e, c1, c2) from the literal eqs (3), (4), with extra digits for the cancellation."""
    delta = mpf(delta)
    if delta == 0:
        return mpf(1), mpf(1), mpf(1)
    with mp.workdps(dps + 3 * _guard(delta)):
        e = mp.exp(-delta)
        c1 = 2 * (delta - 1 + e) / delta ** 2
        c2 = 2 * (1 - e - delta * e) / delta ** 2
    with mp.workdps(dps):
        return +e, +c1, +c2


def char_poly(delta, alpha, beta, dps=DPS):
    """[2, a1, a2, a3] of p(z) = 2 z^3 + a1 z^2 + a2 z - c2 beta."""
    e, c1, c2 = coefficients(delta, dps)
    with mp.workdps(dps):
        a1 = c1 * (alpha + beta) - 2 * (1 + e)
        a2 = c2 * alpha + (c2 - c1) * beta + 2 * e
        return [mpf(2), a1, a2, -c2 * beta]


def spectral_radius(delta, alpha, beta, dps=DPS):
    """Largest root modulus of p(z) (mpmath.polyroots at dps digits)."""
    p = char_poly(delta, alpha, beta, dps)
    with mp.workdps(dps):
        roots = mp.polyroots(p, maxsteps=400, extraprec=2 * dps)
        return max(abs(z) for z in roots), roots


def legacy_stable(delta, alpha, beta, dps=DPS):
    """The legacy region (Gil et al.): the exact region (10) without the linear bound,
    beta > -delta and 0 < alpha < f(beta), f in the factored form of math.md."""
    e, c1, c2 = coefficients(delta, dps)
    with mp.workdps(dps):
        if not (beta > -delta and alpha > 0):
            return False
        s = c1 + c2
        f = s * (beta + delta) * (2 - c2 * beta) / ((c1 * beta + 2) * c2)
        return alpha < f


# ---------------------------------------------------------------------------------------
# scipy: the continuous plant integrated sample by sample
# ---------------------------------------------------------------------------------------


def scipy_trajectory(scene, n, rtol=1e-12, atol_rel=1e-16):
    """The loop with the plant integrated by scipy.integrate.solve_ivp (DOP853) over each
    sample under the held force computed from scipy's own state.  Returns x, v, F arrays."""
    from scipy.integrate import solve_ivp

    m, b, T, K, B = (float(scene[k]) for k in ("m", "b", "T", "K", "B"))
    x, v = float(scene.get("x_init", 0.0)), float(scene.get("v_init", 0.0))
    x_prev = x
    scale = max(abs(x), abs(scene.get("x_eq_before", 0.0)), abs(scene.get("x_eq_after", 0.0)), 1e-300)
    xs, vs, Fs = np.empty(n), np.empty(n), np.empty(n)
    for k in range(n):
        F = K * (float(x_eq_at(scene, k)) - x) - (B / T) * (x - x_prev)
        xs[k], vs[k], Fs[k] = x, v, F
        x_prev = x
        sol = solve_ivp(lambda t, y, F=F: (y[1], (F - b * y[1]) / m), (0.0, T), (x, v),
                        method="DOP853", rtol=rtol, atol=(atol_rel * scale, atol_rel * scale / T))
        x, v = float(sol.y[0, -1]), float(sol.y[1, -1])
    return xs, vs, Fs


def scene_from_normalized(delta, alpha, beta, m=0.1, T=0.01, **extra):
    """A flat linear scene dict for the normalized point (b, K, B rounded from it)."""
    sc = dict(m=m, T=T, b=delta * m / T, K=alpha * m / T ** 2, B=beta * m / T)
    sc.update(extra)
    return sc


def fmt_ratio(values):
    return " ".join(f"{v:.2f}" if math.isfinite(v) else "-" for v in values)


# ---------------------------------------------------------------------------------------
# Coulomb friction with stiction: every stop located exactly (mpmath, closed form)
# ---------------------------------------------------------------------------------------


def _plant_advance(m, b, h, x, v, F):
    """x(h), v(h) of m x'' + b x' = F (F constant) from (x, v): the analytic solution for
    any mpf h (not only the sampling period)."""
    if b == 0:
        return x + h * v + h * h * F / (2 * m), v + h * F / m
    a = b / m
    E1 = -mpmath.expm1(-a * h)
    return x + (E1 / a) * v + ((a * h - E1) / (a * b)) * F, (1 - E1) * v + (E1 / b) * F


def _stop_after(m, b, v, F):
    """The time t > 0 at which v(t) of m x'' + b x' = F reaches 0, or None (it never does:
    the velocity grows in its direction or decays toward F/b without crossing)."""
    if v == 0:
        return None
    if b == 0:
        t = -m * v / F if F != 0 else None
    else:
        # v(t) = exp(-a t)(v - F/b) + F/b = 0  <=>  exp(-a t) = F / (F - b v)
        r = F / (F - b * v)
        t = -mpmath.log(r) * m / b if 0 < r < 1 else None
    return t if t is not None and t > 0 else None


def friction_trajectory(scene, n, dps=40):
    """The loop with Coulomb friction F_c and stiction F_s (flat scene dict: m, b, T, K, B,
    x_init, v_init, x_eq_before, x_eq_after, t_step, coulomb, stiction) over n samples,
    exact: within each sample the held force F plus the friction -F_c sign(v) is constant,
    so the plant is solved in closed form piece by piece, each stop (v = 0) at the time
    solved from the closed form, then held while |F| <= F_s or slipping toward F.
    Returns lists x, v (mpf) at the sample instants, and the number of stops."""
    stops = 0
    with mp.workdps(dps):
        m, b, T, K, B = (mpf(float(scene[k])) for k in ("m", "b", "T", "K", "B"))
        Fc, Fs = mpf(float(scene["coulomb"])), mpf(float(scene["stiction"]))
        x = mpf(float(scene.get("x_init", 0.0)))
        v = mpf(float(scene.get("v_init", 0.0)))
        x_prev = x
        stuck = v == 0
        xs, vs = [], []
        for k in range(n):
            F = K * (mpf(float(x_eq_at(scene, k))) - x) - (B / T) * (x - x_prev)
            xs.append(x)
            vs.append(v)
            x_prev = x
            left = T
            while left > 0:
                if stuck:
                    if abs(F) <= Fs:
                        break      # held for the rest of the sample
                    direction = mpmath.sign(F)
                    stuck = False
                else:
                    direction = mpmath.sign(v)
                net = F - Fc * direction
                t_stop = _stop_after(m, b, v, net)
                if t_stop is not None and t_stop < left:
                    x, _ = _plant_advance(m, b, t_stop, x, v, net)
                    v = mpf(0)
                    stuck = True
                    stops += 1
                    left -= t_stop
                else:
                    x, v = _plant_advance(m, b, left, x, v, net)
                    left = mpf(0)
    return xs, vs, stops
