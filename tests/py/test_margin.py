# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zw_spectral_radius, zw_radius_within and zw_char_poly against the reference (margin.h).

Reference: the roots of p(z) from mpmath.polyroots at 60 digits (with extra precision) on
the exact binary inputs; "all |z| < r" from the Jury conditions on p(r z) in mpmath
(reference.roots_within), which is itself cross-checked against polyroots here.

Error model for the spectral radius (stated, and asserted): a relative perturbation of
size u of the coefficients of p moves the largest root by about kappa u relative, where
kappa = sum |p_k| |z|^(3-k) / (|z| |p'(z)|) is its condition number; next to a double
root that first-order bound fails and the error grows like sqrt(u) kappa2 with
kappa2 = sqrt(sum |p_k| |z|^(3-k) / (|p''(z)| / 2)) / |z|.  Asserted:
    rel. error <= min(A u (1 + kappa), B sqrt(u) (1 + kappa2)).
"""
import math

import mpmath
import numpy as np
import pytest
from mpmath import mp, mpf

import reference as ref
from conftest import COEF_ULPS, E

A_SIMPLE = 8  # measured worst 1.8 (double), 2.6 (float)
B_DOUBLE = 2  # measured worst 0.72 (double), 0.83 (float)

DELTAS = [0.0, 1e-8, 1e-3, 0.05, 0.5, 1.0, 2.0, 2.31, 3.0, 3.7, 5.122, 10.0, 100.0, 1e4]


def _random_points(zw, rng, n):
    """(delta, alpha, beta) spread over and around the stability region."""
    out = []
    for _ in range(n):
        d = zw.r(DELTAS[rng.integers(len(DELTAS))] * (1 + 0.1 * rng.random()))
        ex = ref.extremes(d)
        am, bm = float(ex["alpha_mmax"]), float(ex["beta_mmax"])
        a = zw.r(rng.uniform(-0.2, 1.5) * am)
        b = zw.r(rng.uniform(-d - 0.3 * (bm + d), bm + 0.3 * (bm + d)))
        out.append((d, a, b))
    return out


def _double_root_points(zw, rng, n):
    """Points (rounded to this precision) where p(z) has a double root: for a random
    (delta, beta) the discriminant of p is a quartic in alpha; its real roots give them."""
    out = []
    while len(out) < n:
        d = zw.r(DELTAS[rng.integers(len(DELTAS))])
        bm = float(ref.extremes(d)["beta_mmax"])
        b = zw.r(rng.uniform(-d, bm))

        def disc(a):
            (p0, p1, p2, p3), _ = ref.char_poly(d, a, b)
            return (18 * p0 * p1 * p2 * p3 - 4 * p1 ** 3 * p3 + p1 ** 2 * p2 ** 2
                    - 4 * p0 * p2 ** 3 - 27 * p0 ** 2 * p3 ** 2)

        xs = [mpf(i) for i in range(5)]
        coef = mp.lu_solve(mp.matrix([[x ** k for k in range(4, -1, -1)] for x in xs]),
                           mp.matrix([disc(x) for x in xs]))
        for r in mp.polyroots(list(coef), maxsteps=200, extraprec=100):
            if abs(mpmath.im(r)) < mpf("1e-30") and abs(mpmath.re(r)) < 1e6:
                a = zw.r(mpmath.re(r))
                if math.isfinite(a):
                    out.append((d, a, b))
    return out[:n]


def _ref_rho(t):
    d, a, b = t
    rho, roots = ref.spectral_radius(d, a, b)
    kappa, sep = ref.radius_condition(d, a, b, roots)
    p, _ = ref.char_poly(d, a, b)
    z = max(roots, key=abs)
    num = sum(abs(pk) * abs(z) ** (3 - k) for k, pk in enumerate(p))
    d2 = abs(6 * p[0] * z + 2 * p[1])
    kappa2 = mp.sqrt(num / (d2 / 2)) / abs(z) if d2 and z else mpf("inf")
    return rho, kappa, kappa2, sep


_DATA = {}


@pytest.fixture(scope="module")
def radius_data(zw):
    """Points (random + near double roots) with the reference rho and condition numbers."""
    if zw.name not in _DATA:
        rng = np.random.default_rng(99 + zw.fmt.p)
        pts = _random_points(zw, rng, 900) + _double_root_points(zw, rng, 120)
        _DATA[zw.name] = (pts, ref.pmap(_ref_rho, pts, min_parallel=50))
    return _DATA[zw.name]


def test_reference_jury_agrees_with_polyroots(radius_data):
    """Reference self-check: the Jury verdict (used as the truth in test_region) equals
    rho < 1 from polyroots on every point here (including points on double roots)."""
    pts, refs = radius_data
    for (d, a, b), (rho, *_rest) in zip(pts, refs):
        if abs(rho - 1) > mpf("1e-40"):
            assert ref.stable(d, a, b) == (rho < 1), (d, a, b, rho)


def test_spectral_radius_accuracy(zw, radius_data):
    """rel. error of zw_spectral_radius <= min(A u (1 + kappa), B sqrt(u) (1 + kappa2))
    (module docstring); the worst ratios to each bound are printed."""
    pts, refs = radius_data
    u = zw.u
    worst_simple, worst_double, problems = 0.0, 0.0, []
    for (d, a, b), (rho, kappa, kappa2, sep) in zip(pts, refs):
        _, co = zw.coeffs(d)
        st, got = zw.spectral_radius(co, a, b)
        assert st == E["ZW_OK"], (d, a, b, zw.status_name(st))
        if rho == 0:
            assert got == 0 or abs(got) < 1e3 * u
            continue
        rel = float(abs(mpf(got) - rho) / rho)
        b1 = A_SIMPLE * u * (1 + float(kappa))
        b2 = B_DOUBLE * math.sqrt(u) * (1 + float(kappa2))
        if b1 <= b2:
            worst_simple = max(worst_simple, rel / (u * (1 + float(kappa))))
        else:
            worst_double = max(worst_double, rel / (math.sqrt(u) * (1 + float(kappa2))))
        if rel > min(b1, b2):
            problems.append((d, a, b, float(rho), got, rel, float(kappa), float(kappa2)))
    print(f"\n[{zw.name}] spectral radius: worst rel.err / (u (1 + kappa)) = {worst_simple:.3g} (A = {A_SIMPLE}), "
          f"worst rel.err / (sqrt(u) (1 + kappa2)) near double roots = {worst_double:.3g} (B = {B_DOUBLE})")
    assert not problems, f"{len(problems)} over the bound (delta, alpha, beta, rho, got, rel, kappa, kappa2): {problems[:6]}"


def test_spectral_radius_decides_like_check(zw, radius_data):
    """Where the reference rho is clearly away from 1 (by 1e3 kappa u), rho < 1 from the
    library agrees with the truth."""
    pts, refs = radius_data
    for (d, a, b), (rho, kappa, *_r) in zip(pts, refs):
        if abs(rho - 1) > 1e3 * zw.u * (1 + float(kappa)):
            _, co = zw.coeffs(d)
            _, got = zw.spectral_radius(co, a, b)
            assert (got < 1) == (rho < 1), (d, a, b, got, rho)


def _radius_cases(zw, radius_data, rng):
    """(delta, alpha, beta, r) with r random in (0.3, 1] or within 1e-12 .. 1e-1 of rho."""
    pts, refs = radius_data
    out = []
    for (d, a, b), (rho, *_r) in zip(pts, refs):
        for _ in range(2):
            if rng.random() < 0.3:
                r = rng.uniform(0.3, 1.0)
            else:
                t = 10 ** rng.uniform(-12 if zw.name == "double" else -7, -1) * rng.choice([-1, 1])
                r = float(rho) * (1 + t)
            r = zw.r(r)
            if 0.3 < r <= 1:
                out.append((d, a, b, r, rho))
    return out


def test_radius_within(zw, radius_data):
    """zw_radius_within is never true when rho >= r (truth from the exact Jury test on
    p(r z)); and true whenever rho < r (1 - 1e-6), except where the decision lies inside
    the rounding band: those exceptions must have a relative Jury margin below 256 u."""
    rng = np.random.default_rng(3)
    cases = _radius_cases(zw, radius_data, rng)
    false_yes, missed, unexplained = [], [], []
    truths = ref.pmap(_within_tuple, [(d, a, b, r) for d, a, b, r, _ in cases], min_parallel=100)
    for (d, a, b, r, rho), truth in zip(cases, truths):
        _, co = zw.coeffs(d)
        st, within = zw.radius_within(co, a, b, r)
        assert st == E["ZW_OK"]
        if within and not truth:
            false_yes.append((d, a, b, r, float(rho)))
        if not within and rho < r * (1 - mpf("1e-6")):
            missed.append((d, a, b, r, float(rho)))
            m = ref.jury_relative_margin(d, a, b, r)
            if m > 256 * zw.u:
                unexplained.append((d, a, b, r, float(rho), float(m)))
    print(f"\n[{zw.name}] radius_within: {len(cases)} cases, false 'within': {len(false_yes)}, "
          f"missed with rho < r(1 - 1e-6): {len(missed)} (all with Jury margin < 256 u: {not unexplained})")
    assert not false_yes, false_yes[:8]
    assert len(missed) <= 0.05 * len(cases)
    assert not unexplained, unexplained[:8]


def _within_tuple(t):
    return ref.roots_within(*t)


def test_radius_within_one_is_check(zw, radius_data):
    """r = 1 asks the stability question: never 'within' for a truly unstable point."""
    pts, refs = radius_data
    for (d, a, b), (rho, *_r) in zip(pts, refs):
        _, co = zw.coeffs(d)
        _, within = zw.radius_within(co, a, b, 1.0)
        if within:
            assert ref.stable(d, a, b), (d, a, b, rho)


def test_char_poly_against_definition(zw, radius_data):
    """p = [2, a1, a2, -c2 beta] (eqs (7), (8)): p[0] is exactly 2, the others within
    (ZW_COEF_ULPS + 4) ulps of the scale of their terms (cancellation is allowed, the
    coefficient fields carry ZW_COEF_ULPS ulps)."""
    pts, _ = radius_data
    worst = 0.0
    for d, a, b in pts:
        _, co = zw.coeffs(d)
        st, p = zw.char_poly(co, a, b)
        assert st == E["ZW_OK"] and p[0] == 2
        exact, scale = ref.char_poly(d, a, b)
        for k in (1, 2, 3):
            err = float(abs(mpf(p[k]) - exact[k]) / scale[k]) / (2 * zw.u)
            worst = max(worst, err)
            assert err <= COEF_ULPS + 4, (d, a, b, k, p[k], float(exact[k]), err)
    print(f"\n[{zw.name}] char_poly: worst error {worst:.3g} ulps of the term scale")


def test_margin_error_paths(zw):
    """r <= 0 -> ZW_ERR_ARG, r NaN -> ZW_ERR_NAN, r infinite -> ZW_ERR_ARG (or ZW_ERR_INF);
    NaN/inf gains -> ZW_ERR_NAN / ZW_ERR_INF; delta = inf -> ZW_ERR_INF; outputs fail-safe (p NaN,
    rho +inf, within false)."""
    _, co = zw.coeffs(1.0)
    _, co_inf = zw.coeffs(math.inf)
    for r, ok in ((0.0, ("ZW_ERR_ARG",)), (-0.5, ("ZW_ERR_ARG",)), (math.nan, ("ZW_ERR_NAN",)),
                  (math.inf, ("ZW_ERR_ARG", "ZW_ERR_INF"))):
        st, _ = zw.radius_within(co, 0.1, 0.1, r)
        assert st in [E[s] for s in ok] and zw.failsafe(), (r, zw.status_name(st))
    for fn in (zw.spectral_radius, zw.char_poly, lambda c, a, b: zw.radius_within(c, a, b, 0.9)):
        for c, a, b, s in ((co, math.nan, 0.1, "ZW_ERR_NAN"), (co, 0.1, math.inf, "ZW_ERR_INF"),
                           (co_inf, 0.1, 0.1, "ZW_ERR_INF")):
            st, *_ = fn(c, a, b)
            assert st == E[s] and zw.failsafe(), (a, b, zw.status_name(st))
