# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Achievable extremes (extremes.h) against the 60-digit reference.

Reference: the paper's closed forms (19)-(32) evaluated at 60 digits (cross-checked here
against a direct golden-section maximisation of min{f, L}), interval ends from the
quadratic N(beta) - alpha D(beta) = 0 solved by mpmath.polyroots, truth of a point from the
Jury test (reference.stable).

Tolerances (stated; K_* below):
* quantities without cancellation (alpha_mmax, alpha_p_max, beta_mmax, hyperbola top):
  K_ULPS ulps;
* beta_at_alpha_mmax and the corner, which pass through zero (beta2 at delta2, alpha2 at
  delta0): K_ULPS u times the magnitude scale of their closed forms;
* alpha_max(beta) = min{f, L}: f is known to K_ULPS u (1 + (2/c2) / |2/c2 - beta|) relative
  (2/c2 - beta cancels at the right end), L to K_ULPS u (4 (1+e)/d12 + 2 |beta|) absolute;
* beta interval ends: the alpha tolerance above divided by |d alpha / d beta| there, plus
  K_ULPS u |beta|.
"""
import math

import mpmath
import numpy as np
from mpmath import mp, mpf

import reference as ref
from conftest import E

K_ULPS = 8  # measured worst 5 ulps (see the printouts)


def _huge(fmt):
    """A few huge deltas where alpha_mmax ~ 4 delta is still finite."""
    return [1e12, 1e100, 1e300] if fmt.p == 53 else [1e12, 1e19, 1e30]


def extreme_deltas(fmt):
    """0, tiny, a log grid 1e-8 .. 1e6, a few huge deltas, and the critical deltas +- 2 ulps."""
    k = ref.constants()
    rnd = lambda x: ref.round_to(x, fmt)  # noqa: E731
    ds = [0.0, fmt.tiny, 1e-30, 5.1224, 5.122, 2.049, 0.01299] + _huge(fmt)
    ds += [rnd(10 ** x) for x in np.linspace(-8, 6, 260)]
    for c in ("delta0", "delta1", "delta2", "deltaK1", "deltaK2", "deltaB", "deltaKM"):
        ds += [ref.step(rnd(k[c]), j, fmt) for j in range(-2, 3)]
    return sorted(set(rnd(x) for x in ds))


def ulps(got, exact, fmt):
    return ref.ulp_distance(got, exact, fmt)


def test_reference_closed_forms_match_numeric_maximum():
    """Reference self-check: the closed forms (19)-(25) give the maximum of min{f, L}
    found by golden-section search (no closed form involved), on both branches."""
    for d in (0.0, 0.01, 1.0, 2.0, 2.5, 3.5, 3.7, 4.0, 5.1224, 50.0):
        ex = ref.extremes(d)
        a, b = ref.alpha_max_numeric(d)
        assert abs(a - ex["alpha_mmax"]) / ex["alpha_mmax"] < mpf("1e-25"), d
        assert abs(b - ex["beta_at"]) < mpf("1e-12"), d


def test_extremes_compute(zw):
    """zw_extremes_compute on [0, 1e6]: alpha_mmax, alpha_p_max, beta_mmax within K_ULPS
    ulps; beta_at_alpha_mmax within K_ULPS u of its scale; at_corner iff delta > delta1
    (except within 2 ulps of delta1); beta_mmin = -delta and alpha_mmin = 0 exactly."""
    fmt = zw.fmt
    d1 = ref.constants()["delta1"]
    worst = {"alpha_mmax": 0, "alpha_p_max": 0, "beta_mmax": 0, "beta_at": 0.0}
    problems = []
    for d in extreme_deltas(fmt):
        st, co = zw.coeffs(d)
        st, x = zw.extremes(co)
        assert st == E["ZW_OK"], d
        r = ref.extremes(d)
        for f, cf in (("alpha_mmax", "alpha_mmax"), ("alpha_p_max", "alpha_p_max"), ("beta_mmax", "beta_mmax")):
            e = ulps(getattr(x, cf), r[f], fmt)
            worst[f] = max(worst[f], e)
            if e > K_ULPS:
                problems.append((d, f, getattr(x, cf), float(r[f]), e))
        scale = _beta_at_scale(d)
        eb = float(abs(mpf(x.beta_at_alpha_mmax) - r["beta_at"]) / scale) / zw.u
        worst["beta_at"] = max(worst["beta_at"], eb)
        if eb > K_ULPS:
            problems.append((d, "beta_at", x.beta_at_alpha_mmax, float(r["beta_at"]), eb))
        if abs(ref.ordinal(d, fmt) - ref.ordinal(ref.round_to(d1, fmt), fmt)) > 2 and x.at_corner != r["at_corner"]:
            problems.append((d, "at_corner", x.at_corner))
        if x.beta_mmin != -d or x.alpha_mmin != 0:
            problems.append((d, "mmin", x.beta_mmin, x.alpha_mmin))
    print(f"\n[{zw.name}] extremes worst: {worst} (ulps; beta_at in u of its scale)")
    assert not problems, problems[:8]


def _beta_at_scale(d):
    """Magnitude scale of beta_at_alpha_mmax's closed form (its terms before cancelling)."""
    co = ref.coeffs(d)
    if ref.extremes(d)["at_corner"]:
        return 2 * ((3 + co.e) * co.c2 + (1 - co.e) * co.c1) / co.d12 ** 2
    return abs(ref.hyperbola_top(d)[1])


def test_hyperbola_top_and_corner(zw):
    """zw_hyperbola_top (every delta; ZW_ERR_RANGE where alpha1 ~ 2 delta^2 overflows) within
    K_ULPS ulps; zw_corner (delta > delta0) within K_ULPS u of the scale of eqs (21), (22)
    (alpha2 -> 0 at delta0, beta2 -> 0 at delta2)."""
    fmt = zw.fmt
    d0 = ref.constants()["delta0"]
    worst = [0, 0, 0.0, 0.0]
    problems = []
    for d in extreme_deltas(fmt):
        _, co = zw.coeffs(d)
        st, a1, b1 = zw.hyperbola_top(co)
        ra1, rb1 = ref.hyperbola_top(d)
        if ra1 > fmt.max:  # alpha1 ~ 2 delta^2 does not fit: ZW_ERR_RANGE, outputs fail-safe 0
            assert st == E["ZW_ERR_RANGE"] and zw.failsafe(), (d, zw.status_name(st))
            continue
        assert st == E["ZW_OK"], (d, zw.status_name(st))
        e1, e2 = ulps(a1, ra1, fmt), ulps(b1, rb1, fmt)
        # beta1 ~ e / c2 for large delta: once e = exp(-delta) is subnormal its field holds
        # only COEF_ULPS ulps *absolute*, which beta1 inherits (scaled by beta1 / e).
        r = ref.coeffs(d)
        e_room = 0
        if 0 < r.e < fmt.min_normal:
            e_room = float(abs(rb1) / r.e * 4 * fmt.tiny / ref.ulp_of(float(rb1), fmt))
        worst[0] = max(worst[0], e1)
        if not e_room:
            worst[1] = max(worst[1], e2)
        if e1 > K_ULPS or e2 > K_ULPS + e_room:
            problems.append(("top", d, a1, float(ra1), e1, b1, float(rb1), e2))
        if d > d0 and ref.ordinal(d, fmt) - ref.ordinal(ref.round_to(d0, fmt), fmt) > 1:
            st, a2, b2 = zw.corner(co)
            assert st == E["ZW_OK"], d
            ra2, rb2 = ref.corner(d)
            c = ref.coeffs(d)
            sa = 8 * (c.c1 + (2 + c.e) * c.c2) / c.d12 ** 2
            sb = 2 * ((3 + c.e) * c.c2 + (1 - c.e) * c.c1) / c.d12 ** 2
            ea = float(abs(mpf(a2) - ra2) / sa) / zw.u
            eb = float(abs(mpf(b2) - rb2) / sb) / zw.u
            worst[2], worst[3] = max(worst[2], ea), max(worst[3], eb)
            if ea > K_ULPS or eb > K_ULPS:
                problems.append(("corner", d, a2, float(ra2), ea, b2, float(rb2), eb))
    print(f"\n[{zw.name}] hyperbola top worst ulps (alpha1, beta1 while e is normal) {worst[:2]}; "
          f"corner worst (alpha2, beta2) in u of scale {worst[2]:.3g}, {worst[3]:.3g}")
    assert not problems, problems[:8]


def test_corner_domain_error(zw):
    """zw_corner gives ZW_ERR_DOMAIN for delta <= delta0 (outputs fail-safe 0), ZW_OK above."""
    fmt = zw.fmt
    d0 = ref.round_to(ZW_DELTA0(), fmt)
    for d in (0.0, fmt.tiny, 0.5, 1.0, 2.3, ref.step(d0, -1, fmt), d0):
        _, co = zw.coeffs(d)
        st, _, _ = zw.corner(co)
        assert st == E["ZW_ERR_DOMAIN"] and zw.failsafe(), (d, zw.status_name(st))
    for d in (ref.step(d0, 2, fmt), 2.4, 5.0, 1e6):
        _, co = zw.coeffs(d)
        assert zw.corner(co)[0] == E["ZW_OK"], d


def ZW_DELTA0():
    from conftest import DEFINES
    return mpf(DEFINES["ZW_DELTA0"])


def test_limits_small_delta(zw):
    """delta -> 0: alpha_mmax -> 12 - 8 sqrt 2, beta_at -> 2 sqrt 2 - 2, beta_mmax -> 2 (to a
    few ulps at delta = 0 and 1e-30), and beta_mmax ~ 2 + 4 delta / 3 (slope to 1e-3 at
    delta = 1e-4 in double, 1e-2 at 1e-3 in float)."""
    fmt = zw.fmt
    for d in (0.0, zw.r(1e-30)):
        _, co = zw.coeffs(d)
        _, x = zw.extremes(co)
        assert ulps(x.alpha_mmax, 12 - 8 * mp.sqrt(2), fmt) <= 4
        assert ulps(x.beta_at_alpha_mmax, 2 * mp.sqrt(2) - 2, fmt) <= 4
        assert ulps(x.beta_mmax, 2, fmt) <= 2
    d = zw.r(1e-4 if zw.name == "double" else 1e-3)
    _, co = zw.coeffs(d)
    _, x = zw.extremes(co)
    slope = (x.beta_mmax - 2) / d
    assert abs(slope - 4 / 3) < (1e-3 if zw.name == "double" else 1e-2), slope


def test_limits_large_delta(zw):
    """delta -> inf: alpha_mmax ~ 4 delta + 4 and beta_at -> -delta (beta_at + delta ~ 4/delta)."""
    for d in (1e4, 1e6, 1e8):
        d = zw.r(d)
        _, co = zw.coeffs(d)
        st, x = zw.extremes(co)
        assert st == E["ZW_OK"]
        assert abs(x.alpha_mmax - (4 * d + 4)) <= 16 / d + 8 * zw.u * 4 * d, (d, x.alpha_mmax)
        assert abs(x.beta_at_alpha_mmax + d) <= 8 / d + 8 * zw.u * d, (d, x.beta_at_alpha_mmax)
        assert x.at_corner


def test_beta_at_sign_change_at_delta2(zw):
    """beta_at_alpha_mmax > 0 just below delta2 and < 0 just above it (1e-9 relative in
    double, 1e-5 in float), and its sign matches the reference wherever |beta_at| exceeds
    its tolerance."""
    d2 = ref.constants()["delta2"]
    rel = mpf("1e-9") if zw.name == "double" else mpf("1e-5")
    for d, sign in ((zw.r(d2 * (1 - rel)), 1), (zw.r(d2 * (1 + rel)), -1)):
        _, co = zw.coeffs(d)
        _, x = zw.extremes(co)
        assert x.beta_at_alpha_mmax * sign > 0, (d, x.beta_at_alpha_mmax)


def test_branch_switch_at_delta1(zw):
    """at_corner switches from false to true across delta1 and alpha_mmax, beta_at are
    continuous there (both branches give the same point at delta1)."""
    d1 = ref.constants()["delta1"]
    rel = mpf("1e-9") if zw.name == "double" else mpf("1e-5")
    lo, hi = zw.r(d1 * (1 - rel)), zw.r(d1 * (1 + rel))
    _, clo = zw.coeffs(lo)
    _, chi = zw.coeffs(hi)
    _, xlo = zw.extremes(clo)
    _, xhi = zw.extremes(chi)
    assert not xlo.at_corner and xhi.at_corner
    assert abs(xhi.alpha_mmax - xlo.alpha_mmax) <= 1e3 * float(rel) * xlo.alpha_mmax
    assert abs(xhi.beta_at_alpha_mmax - xlo.beta_at_alpha_mmax) <= 1e3 * float(rel)


# ---------------------------------------------------------------------------------------
# alpha_max(beta) and the beta interval
# ---------------------------------------------------------------------------------------

ALPHA_MAX_DELTAS = [0.0, 1e-12, 0.01299, 0.3, 1.0, 2.0, 2.049, 2.31, 2.32, 3.0, 3.66, 3.72, 4.5, 5.1224, 20.0, 1e3, 1e6]


def _alpha_tol(d, beta, alpha, which, fmt):
    """Absolute tolerance of alpha_max at beta (module docstring), plus K_ULPS underflow
    quanta (the smallest subnormal) for results in the subnormal range."""
    co = ref.coeffs(d)
    b = ref.exact(beta)
    u = fmt.u
    if which == "hyperbola":
        return K_ULPS * u * abs(alpha) * (1 + co.h / max(abs(co.h - b), u * co.h)) + K_ULPS * fmt.tiny
    return K_ULPS * u * (4 * (1 + co.e) / co.d12 + 2 * abs(b)) + K_ULPS * fmt.tiny


def _betas(zw, d, rng):
    fmt = zw.fmt
    ex = ref.extremes(d)
    bm = ex["beta_mmax"]
    w = float(bm) + d
    out = [zw.r(x) for x in rng.uniform(-d - 0.05 * w, float(bm) + 0.05 * w, 40)]
    out += [ref.step(zw.r(-d), k, fmt) for k in (-1, 0, 1, 2, 5, 1000)]
    out += [ref.step(ref.round_to(bm, fmt), k, fmt) for k in (-1000, -3, -1, 0, 1, 3)]
    out += [ref.step(ref.round_to(ex["beta_at"], fmt), k, fmt) for k in (-1, 0, 1)]
    return out


def test_alpha_max(zw):
    """zw_alpha_max(beta) = min{f, L} on (-delta, beta_mmax), 0 outside, within the stated
    tolerance; just inside (alpha_max - 2 tol) is stable and just outside (alpha_max + 2 tol)
    unstable in the reference."""
    rng = np.random.default_rng(17)
    fmt = zw.fmt
    worst, problems, checked = 0.0, [], 0
    for d in ALPHA_MAX_DELTAS + _huge(fmt):
        d = zw.r(d)
        _, co = zw.coeffs(d)
        for b in _betas(zw, d, rng):
            st, got = zw.alpha_max(co, b)
            assert st == E["ZW_OK"], (d, b)
            exact, which = ref.alpha_max_at(d, b)
            if which is None:  # outside (-delta, beta_mmax): 0, except within a few ulps of beta_mmax
                near_end = abs(ref.exact(b) - ref.extremes(d)["beta_mmax"]) <= 8 * zw.u * abs(ref.exact(b))
                if got != 0 and not (near_end and got <= _alpha_tol(d, b, 0, "line", fmt)):
                    problems.append(("nonzero outside", d, b, got))
                continue
            tol = _alpha_tol(d, b, exact, which, fmt)
            err = abs(mpf(got) - exact)
            worst = max(worst, float(err / tol) * K_ULPS)
            if err > tol:
                problems.append((d, b, got, float(exact), which, float(err / tol) * K_ULPS))
                continue
            checked += 1
            t = 2 * tol
            inside, outside = ref.round_to(mpf(got) - t, fmt), ref.round_to(mpf(got) + t, fmt)
            inside = ref.step(got, -1, fmt) if inside == got else inside
            outside = ref.step(got, 1, fmt) if outside == got else outside
            if inside > 0 and not ref.stable(d, inside, b):
                problems.append(("inside unstable", d, b, inside))
            if ref.stable(d, outside, b):
                problems.append(("outside stable", d, b, outside))
    print(f"\n[{zw.name}] alpha_max: {checked} betas, worst error {worst:.3g} (in units of u times the stated scale)")
    assert not problems, problems[:8]


def _dalpha(d, beta, which):
    """|d alpha / d beta| of the active boundary at beta: one-sided difference towards the
    inside, step 1e-6 of the distance x = beta + delta to the corner (x is floored at
    1e-40 |beta|, below the reference's own resolution of beta next to -delta)."""
    if which == "line":
        return mpf(2)
    b, dd = ref.exact(beta), ref.exact(d)
    x = max(b + dd, abs(b) * mpf("1e-40"), mpf("1e-300"))
    h = x * mpf("1e-6")
    with mp.workdps(40 + max(0, int(mpmath.log10((abs(dd) + 1) / h)))):
        return abs(ref.f_hyperbola(d, x + h - dd) - ref.f_hyperbola(d, x - dd)) / h


def test_beta_interval(zw):
    """zw_beta_interval(alpha): nonempty iff 0 < alpha < alpha_mmax (away from alpha_mmax by
    64 u); the ends within the stated tolerance; the midpoint stable and the ends pushed out
    by twice their tolerance unstable in the reference; alpha <= 0 gives lo = hi = 0."""
    rng = np.random.default_rng(23)
    fmt = zw.fmt
    problems, checked, worst = [], 0, 0.0
    for d in ALPHA_MAX_DELTAS + _huge(fmt):
        d = zw.r(d)
        _, co = zw.coeffs(d)
        am = ref.extremes(d)["alpha_mmax"]
        alphas = [zw.r(float(am) * x) for x in list(rng.uniform(0, 1, 25)) + [1e-9, 1e-3, 0.999, 1 - 1e-5, 1.0 + 1e-4, 1.5]]
        alphas += [0.0, -1.0, fmt.tiny * 4]
        for a in alphas:
            st, lo, hi, ne = zw.beta_interval(co, a)
            assert st == E["ZW_OK"], (d, a)
            rlo, rhi, rne = ref.beta_interval(d, a)
            if a <= 0:
                if ne or lo != 0 or hi != 0:
                    problems.append(("alpha <= 0", d, a, lo, hi, ne))
                continue
            if abs(ref.exact(a) - am) <= 64 * zw.u * am:
                continue
            if ne != rne:
                if not (0 < a < fmt.min_normal):
                    problems.append(("nonempty", d, a, ne, rne))
                continue
            if not ne:
                if lo != 0 or hi != 0:
                    problems.append(("empty but lo/hi set", d, a, lo, hi))
                continue
            wl = "hyperbola"
            wh = "line" if (co.d12 != 0 and rhi == ref.line_end(d) - ref.exact(a) / 2) else "hyperbola"
            tl = K_ULPS * zw.u * abs(rlo) + _alpha_tol(d, rlo, a, wl, fmt) / _dalpha(d, rlo, wl)
            th = K_ULPS * zw.u * abs(rhi) + _alpha_tol(d, rhi, a, wh, fmt) / _dalpha(d, rhi, wh)
            el, eh = abs(mpf(lo) - rlo) / tl, abs(mpf(hi) - rhi) / th
            worst = max(worst, float(max(el, eh)) * K_ULPS)
            if el > 1 or eh > 1:
                problems.append((d, a, lo, float(rlo), hi, float(rhi), float(el), float(eh)))
                continue
            checked += 1
            if rhi - rlo > 4 * (tl + th):
                mid = ref.round_to((mpf(lo) + mpf(hi)) / 2, fmt)
                if not ref.stable(d, a, mid):
                    problems.append(("mid unstable", d, a, mid))
            for bb in (ref.round_to(mpf(lo) - 2 * tl, fmt), ref.round_to(mpf(hi) + 2 * th, fmt)):
                if ref.stable(d, a, bb):
                    problems.append(("outside end stable", d, a, bb))
    print(f"\n[{zw.name}] beta_interval: {checked} alphas, worst end error {worst:.3g} (u times the stated scale)")
    assert checked > 300
    assert not problems, problems[:8]


def test_extremes_error_paths(zw):
    """delta = inf -> ZW_ERR_INF, NaN/inf beta or alpha -> ZW_ERR_NAN/ZW_ERR_INF, NULL ->
    ZW_ERR_NULL; outputs fail-safe (limits 0, ranges empty)."""
    _, co = zw.coeffs(1.0)
    _, co_inf = zw.coeffs(math.inf)
    for call in (lambda: zw.extremes(co_inf), lambda: zw.hyperbola_top(co_inf), lambda: zw.corner(co_inf),
                 lambda: zw.alpha_max(co_inf, 0.1), lambda: zw.beta_interval(co_inf, 0.1)):
        st, *_ = call()
        assert st == E["ZW_ERR_INF"] and zw.failsafe(), zw.status_name(st)
    for call, s in ((lambda: zw.alpha_max(co, math.nan), "ZW_ERR_NAN"), (lambda: zw.alpha_max(co, math.inf), "ZW_ERR_INF"),
                    (lambda: zw.beta_interval(co, math.nan), "ZW_ERR_NAN"),
                    (lambda: zw.beta_interval(co, math.inf), "ZW_ERR_INF")):
        st, *_ = call()
        assert st == E[s] and zw.failsafe(), zw.status_name(st)
    assert zw.lib.zw_extremes_compute(None, None) == E["ZW_ERR_NULL"]
