# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Independent reference for the general loop (loop.h), in mpmath.

Nothing here uses a transfer function.  The sampled loop is written as a time-domain
state-space model, one sample at a time, exactly as a drive runs it (shared/notes/
general-loop.md, "Timing, stated exactly"):

* plant m x'' + b x' = F behind a zero-order hold, normalized (time in samples,
  y = T x', u = F T^2 / m): one period is the matrix exponential of
  [[0, 1, 0], [0, -delta, 1], [0, 0, 0]] (mpmath.expm, no closed-form coefficients);
* the raw velocity estimate T v_k: backward x_k - x_{k-1}, or Tustin
  2 (x_k - x_{k-1}) - T v_{k-1};
* the filter: none, first-order low-pass vf_k = a vf_{k-1} + (1 - a) v_k, or the mean of
  the last n raw estimates;
* the controller output c_k = -(alpha x_k + beta vf_k), applied over [(k+d)T, (k+d+1)T)
  through a delay line of d stored outputs.

The closed loop's characteristic polynomial is det(zI - A(alpha, beta)) by the
Faddeev-LeVerrier recursion at 80 digits.  Stability labels are the roots' moduli
(mpmath.polyroots) or, where many points are labelled, the Schur-Cohn recursion on the same
polynomial at 60 digits (cross-checked against polyroots in the tests).
"""
from __future__ import annotations

import functools

import mpmath
from mpmath import mp, mpf

import reference as ref

DPS = 80


def _plant_step(delta):
    """(phi_xx, phi_xy, gam_x, phi_yy, gam_y) of one ZOH period, from expm."""
    m = mpmath.matrix([[0, 1, 0], [0, -delta, 1], [0, 0, 0]])
    e = mpmath.expm(m)
    return e[0, 0], e[0, 1], e[0, 2], e[1, 1], e[1, 2]


def closed_loop_matrix(delta, alpha, beta, delay=0, differentiator="backward", filter="none",
                       pole=0, average=1):
    """A of x_{k+1} = A x_k for the sampled loop (all arguments exact mpf or binary floats)."""
    delta, alpha, beta, a = (ref.exact(v) for v in (delta, alpha, beta, pole))
    names = ["x", "y", "xm1"]
    if differentiator == "tustin":
        names.append("raw")
    if filter == "lowpass":
        names.append("lp")
    hist = average - 1 if filter == "average" else 0
    names += [f"h{i}" for i in range(1, hist + 1)]
    names += [f"c{i}" for i in range(1, delay + 1)]
    idx = {n: i for i, n in enumerate(names)}
    size = len(names)

    def unit(n):
        v = [mpf(0)] * size
        v[idx[n]] = mpf(1)
        return v

    def lin(*terms):  # sum of coef * vector
        out = [mpf(0)] * size
        for coef, vec in terms:
            for i in range(size):
                out[i] += coef * vec[i]
        return out

    X = unit("x")
    if differentiator == "tustin":
        raw = lin((2, X), (-2, unit("xm1")), (-1, unit("raw")))
    else:
        raw = lin((1, X), (-1, unit("xm1")))
    if filter == "lowpass":
        est = lin((a, unit("lp")), (1 - a, raw))
    elif filter == "average":
        est = lin(*([(mpf(1) / average, raw)] + [(mpf(1) / average, unit(f"h{i}")) for i in range(1, hist + 1)]))
    else:
        est = raw
    c = lin((-alpha, X), (-beta, est))
    u = c if delay == 0 else unit(f"c{delay}")
    pxx, pxy, gx, pyy, gy = _plant_step(delta)
    rows = {
        "x": lin((pxx, X), (pxy, unit("y")), (gx, u)),
        "y": lin((pyy, unit("y")), (gy, u)),
        "xm1": X,
    }
    if "raw" in idx:
        rows["raw"] = raw
    if "lp" in idx:
        rows["lp"] = est
    for i in range(1, hist + 1):
        rows[f"h{i}"] = raw if i == 1 else unit(f"h{i - 1}")
    for i in range(1, delay + 1):
        rows[f"c{i}"] = c if i == 1 else unit(f"c{i - 1}")
    return mpmath.matrix([rows[n] for n in names])


def charpoly(a):
    """Monic det(zI - A), highest power first (Faddeev-LeVerrier)."""
    n = a.rows
    coeffs = [mpf(1)]
    m = mpmath.zeros(n, n)
    ident = mpmath.eye(n)
    for k in range(1, n + 1):
        m = a * m + coeffs[-1] * ident
        am = a * m
        coeffs.append(-sum(am[i, i] for i in range(n)) / k)
    return coeffs


@functools.lru_cache(maxsize=None)
def loop_parts(delta, delay=0, differentiator="backward", filter="none", pole=0.0, average=1):
    """(D, Na, Nb) of det(zI - A) = D + alpha Na + beta Nb, monic, highest power first, at
    the state dimension (which may exceed the loop's degree by roots at 0).  Affinity in
    (alpha, beta) is checked at a fourth point."""
    with mp.workdps(DPS):
        def cp(al, be):
            return charpoly(closed_loop_matrix(delta, al, be, delay, differentiator, filter, pole, average))
        d = cp(0, 0)
        na = [p - q for p, q in zip(cp(1, 0), d)]
        nb = [p - q for p, q in zip(cp(0, 1), d)]
        check = cp(mpf(3) / 7, mpf(-5) / 11)
        for i, v in enumerate(check):
            pred = d[i] + mpf(3) / 7 * na[i] - mpf(5) / 11 * nb[i]
            assert abs(v - pred) <= mpf(10) ** (-DPS + 15) * (1 + abs(d[i]) + abs(na[i]) + abs(nb[i]))
    return tuple(d), tuple(na), tuple(nb)


def loop_poly(parts, alpha, beta, degree=None):
    """p = D + alpha Na + beta Nb at exact (alpha, beta), trimmed to degree (dropping the
    trailing coefficients of the extra roots at 0, which must vanish)."""
    d, na, nb = parts
    p = [x + ref.exact(alpha) * y + ref.exact(beta) * w for x, y, w in zip(d, na, nb)]
    if degree is not None:
        extra = len(p) - 1 - degree
        for v in p[len(p) - extra:]:
            assert abs(v) < mpf(10) ** (-DPS + 20), "an extra root is not at 0"
        p = p[: degree + 1]
    return p


def schur_stable(p, dps=60):
    """Strict Schur stability of the real polynomial p (highest first) by the Schur-Cohn
    recursion at dps digits: every reflection coefficient |p_n / p_0| < 1.  Returns
    (stable, min margin 1 - |k|) so callers can see how close the decision was."""
    with mp.workdps(dps):
        q = [mpf(v) for v in p]
        margin = mpf(1)
        while len(q) > 1:
            if q[0] == 0:
                return False, mpf(0)
            k = q[-1] / q[0]
            margin = min(margin, 1 - abs(k))
            if abs(k) >= 1:
                return False, margin
            q = [q[i] - k * q[len(q) - 1 - i] for i in range(len(q) - 1)]
        return True, margin


def spectral_radius(p, dps=50):
    """(rho, theta) of the root of largest modulus, by mpmath.polyroots."""
    with mp.workdps(dps):
        # drop exact zero roots: polyroots converges slowly on multiple roots at 0
        q = list(p)
        while len(q) > 1 and q[-1] == 0:
            q.pop()
        if len(q) == 1:
            return mpf(0), mpf(0)
        roots = mpmath.polyroots(q, maxsteps=400, extraprec=2 * dps)
        top = max(roots, key=abs)
        return abs(top), abs(mpmath.arg(top))
