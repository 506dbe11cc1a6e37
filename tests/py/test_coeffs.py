# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zw_coeffs_init against the 60-digit reference (coeffs.h).

Proves: every field of zw_coeffs (e, c1, c2, d12, s, g and hs = (2/c2)/sigma) is within
ZW_COEF_ULPS ulps (parsed from coeffs.h) of the exact function value at the given delta,
over a dense log grid (>= 2000 points per precision, from 0 and the subnormals up to 1e300 /
1e38) plus every hard case of math.md; that the literal formulas really are as bad as the
notes say where the careful ones are fine; the limits at +inf; the error paths; and the
mathematical property the C error budget relies on (relative condition numbers <= 2).
"""
import math

import mpmath
import numpy as np
import pytest
from mpmath import mp, mpf

import reference as ref
from conftest import COEF_ULPS, E

FIELDS = ("e", "c1", "c2", "d12", "s", "g", "hs")


def _hard_cases(fmt):
    """math.md's hard cases, in this precision."""
    k = ref.constants()
    rnd = lambda x: ref.round_to(x, fmt)  # noqa: E731
    out = [0.0, fmt.tiny, 2 * fmt.tiny, 1000 * fmt.tiny, fmt.min_normal, ref.step(fmt.min_normal, -1, fmt),
           10.0, 1e6, 1e19, 1.8e19, 1.9e19]
    if fmt.p == 53:
        out += [1e-320, 1e-300, 1e154, 1.3e154, 1.35e154, 1.4e154, 1e300, 1e-16, 1e-20, 1e-21]
    else:
        out += [1e-45, 1e-40, 1e-38, 1e30, 1e37, 1e38, 1e-8, 1e-7]
    out += [10.0 ** -i for i in range(1, 13)]
    for c in ("delta0", "delta1", "delta2", "deltaK1", "deltaK2", "deltaB", "deltaKM"):
        out += [ref.step(rnd(k[c]), j, fmt) for j in range(-3, 4)]
    # the series / closed-form switch at delta = 2, and sigma's power-of-two steps
    out += [ref.step(2.0, j, fmt) for j in range(-20, 21)] + [1.999, 2.001, 1.99, 2.01]
    for p in (0, 1, 2, 3, 10, 20, 60):
        out += [ref.step(2.0 ** p, j, fmt) for j in (-1, 0, 1)]
    return [rnd(x) for x in out]


def delta_grid(fmt, n=2200):
    """0, subnormals, a log grid (1e-300..1e300 double, 1e-45..1e38 float) and the hard cases."""
    hi = 300 if fmt.p == 53 else 38
    lo = -300 if fmt.p == 53 else -45
    grid = [ref.round_to(mpf(10) ** mpf(x), fmt) for x in np.linspace(lo, hi, n)]
    grid += [math.ldexp(1.0, fmt.emin_sub + i) for i in range(0, fmt.p, 3)]  # subnormals
    return sorted(set(g for g in grid + _hard_cases(fmt) if g >= 0 and math.isfinite(g)))


def field_errors(zw, delta):
    """ulp distance of every field at delta (plus the raw struct); also checks delta,
    delta_relerr and sigma exactly."""
    st, co = zw.coeffs(delta)
    assert st == E["ZW_OK"], (delta, zw.status_name(st))
    r = ref.coeffs(delta)
    fmt = zw.fmt
    assert co.delta == delta and co.delta_relerr == 0
    # sigma: a power of two, 1 for delta <= 1, else >= delta
    sig = co.sigma
    assert math.frexp(sig)[0] == 0.5, ("sigma not a power of two", delta, sig)
    assert (sig == 1.0) if delta <= 1 else (sig >= delta), ("sigma", delta, sig)
    exact = {"e": r.e, "c1": r.c1, "c2": r.c2, "d12": r.d12, "s": r.s, "g": r.g,
             "hs": r.h / ref.exact(sig)}  # hs * sigma = 2 / c2 exactly (sigma is a power of two)
    return {f: ref.ulp_distance(getattr(co, f), exact[f], fmt) for f in FIELDS}, co


def test_coefficients_within_declared_ulps_on_dense_grid(zw):
    """Every field within ZW_COEF_ULPS ulps on >= 2000 deltas plus every hard case; the
    worst error per field is printed and reported in the assertion message."""
    grid = delta_grid(zw.fmt)
    assert len(grid) >= 2000
    worst = {f: (0, None) for f in FIELDS}
    for d in grid:
        errs, _ = field_errors(zw, d)
        for f, e in errs.items():
            if e > worst[f][0]:
                worst[f] = (e, d)
    table = ", ".join(f"{f} {w[0]} ulp (delta={w[1]!r})" for f, w in worst.items())
    print(f"\n[{zw.name}] {len(grid)} deltas, worst error per field: {table}")
    bad = {f: w for f, w in worst.items() if w[0] > COEF_ULPS}
    assert not bad, f"[{zw.name}] fields over ZW_COEF_ULPS={COEF_ULPS}: {bad}; all: {table}"


def test_top_binade_of_delta(zw):
    """delta in the top binade (up to the largest finite value): still ZW_OK with every field
    within ZW_COEF_ULPS; sigma is the least power of two >= delta, capped at the largest
    finite one; hs = (2/c2)/sigma is within ZW_COEF_ULPS where that is finite and +inf where
    it exceeds the largest finite value, and then the checks answer ZW_ERR_RANGE instead of
    a verdict (coeffs.h)."""
    fmt = zw.fmt
    top_pow2 = math.ldexp(1.0, (1023 if fmt.p == 53 else 127))
    top = [ref.step(fmt.max, -j, fmt) for j in (0, 1, 1000)] + [top_pow2, fmt.max / 4]
    problems = []
    for d in top:
        st, co = zw.coeffs(d)
        if st != E["ZW_OK"]:
            problems.append((d, zw.status_name(st)))
            continue
        r = ref.coeffs(d)
        for f in ("e", "c1", "c2", "d12", "s", "g"):
            err = ref.ulp_distance(getattr(co, f), getattr(r, f), fmt)
            if err > COEF_ULPS:
                problems.append((d, f, err))
        want_sigma = math.ldexp(1.0, min(math.ceil(math.log2(d)), 1023 if fmt.p == 53 else 127))
        if co.sigma != want_sigma:
            problems.append((d, "sigma", co.sigma, want_sigma))
        true_hs = r.h / ref.exact(co.sigma)
        if true_hs > ref.exact(fmt.max):
            if co.hs != math.inf:
                problems.append((d, "hs should overflow to +inf", co.hs))
            if zw.check(co, 1.0, 0.0)[0] != E["ZW_ERR_RANGE"]:
                problems.append((d, "check should answer ZW_ERR_RANGE"))
        elif ref.ulp_distance(co.hs, true_hs, fmt) > COEF_ULPS:
            problems.append((d, "hs", co.hs, co.sigma))
    assert not problems, f"[{zw.name}] {problems}"


def test_reference_series_matches_literal():
    """Reference self-check: the Taylor series and the extra-precision literal formulas agree
    to 50 digits where both are used (1e-19 .. 1e-3), so the switch at 1e-20 is seamless."""
    for d in (1e-19, 1e-15, 1e-10, 1e-6, 1e-3):
        assert ref.coeffs_literal_series_gap(d) < mpf("1e-50"), d


def test_reference_factored_f_matches_expanded():
    """Reference self-check: f(beta) from the expanded eq (10) (the reference's choice) equals
    the factored form of math.md, also next to the corner beta -> -delta."""
    for d in (0.01, 1.0, 3.0, 50.0):
        for b in (-d * (1 - 1e-12), -d / 2, 0.3, 1.5):
            x, y = ref.f_hyperbola(d, b), ref.f_hyperbola_factored(d, b)
            assert abs(x - y) <= mpf("1e-45") * abs(y), (d, b)


def test_literal_formulas_are_far_worse(zw):
    """zw_coeffs_literal cancels where math.md says (float d12 at delta = 0.01, double d12 at
    delta = 1e-6: no correct digit left, >= 10 % wrong; math.md measured 73 % and 3.6e2 with
    one libm) while zw_coeffs_init stays within ZW_COEF_ULPS at the same delta: that is what
    the careful formulas buy."""
    d = zw.r(0.01) if zw.name == "float" else 1e-6
    st, c1, c2, d12 = zw.coeffs_literal(d)
    assert st == E["ZW_OK"]
    r = ref.coeffs(d)
    rel = {k: float(abs(ref.exact(v) - x) / x) for k, v, x in (("c1", c1, r.c1), ("c2", c2, r.c2), ("d12", d12, r.d12))}
    errs, _ = field_errors(zw, d)
    print(f"\n[{zw.name}] delta={d}: literal relative errors {rel}; careful ulps {errs}")
    assert rel["d12"] > 0.1, f"literal d12 unexpectedly accurate: {rel}"
    assert rel["d12"] > 1e5 * COEF_ULPS * zw.fmt.eps, rel
    assert max(errs.values()) <= COEF_ULPS, errs


def test_literal_formulas_agree_where_well_conditioned(zw):
    """zw_coeffs_literal is the literal formula, not something else: at delta = 10 (no
    cancellation, no overflow) it is within a few ulps of the reference."""
    st, c1, c2, d12 = zw.coeffs_literal(10.0)
    assert st == E["ZW_OK"]
    r = ref.coeffs(10.0)
    for v, x in ((c1, r.c1), (c2, r.c2), (d12, r.d12)):
        assert ref.ulp_distance(v, x, zw.fmt) <= 8


def test_infinite_delta_gives_documented_limits(zw):
    """delta = +inf: e = c1 = c2 = d12 = s = 0, g = 1, sigma = hs = +inf (coeffs.h)."""
    st, co = zw.coeffs(math.inf)
    assert st == E["ZW_OK"]
    assert (co.e, co.c1, co.c2, co.d12, co.s, co.g) == (0, 0, 0, 0, 0, 1)
    assert co.sigma == math.inf and co.hs == math.inf and co.delta == math.inf


def test_zero_delta_exact_values(zw):
    """delta = 0 and -0.0 (in [0, inf]): e = c1 = c2 = 1, d12 = 0, s = 2, g = 1/2, hs = 2."""
    for d in (0.0, -0.0):
        st, co = zw.coeffs(d)
        assert st == E["ZW_OK"], d
        assert (co.e, co.c1, co.c2, co.d12, co.s, co.g, co.sigma, co.hs) == (1, 1, 1, 0, 2, 0.5, 1, 2), d


@pytest.mark.parametrize("delta,status", [(math.nan, "ZW_ERR_NAN"), (-1.0, "ZW_ERR_DELTA"), (-1e-300, "ZW_ERR_DELTA"),
                                          (-math.inf, "ZW_ERR_DELTA"), (-1e30, "ZW_ERR_DELTA")])
def test_invalid_delta_rejected_and_output_failsafe(zw, delta, status):
    """NaN -> ZW_ERR_NAN (2), negative -> ZW_ERR_DELTA (7); every output is NaN (fail-safe:
    a check on the struct refuses with ZW_ERR_NAN)."""
    if zw.name == "float" and delta == -1e-300:
        delta = -zw.fmt.tiny
    st, _ = zw.coeffs(delta)
    assert st == E[status], (delta, zw.status_name(st))
    assert zw.failsafe()
    st, co = zw.coeffs(delta)
    assert zw.check(co, 0.1, 0.0)[0] == E["ZW_ERR_NAN"] and zw.failsafe()
    st, *_ = zw.coeffs_literal(delta)
    assert st == E[status] and zw.failsafe()


def test_null_output_rejected(zw):
    """A NULL output pointer gives ZW_ERR_NULL."""
    assert zw.lib.zw_coeffs_init(None, 1.0) == E["ZW_ERR_NULL"]


def test_status_names(zw):
    """zw_status_name returns the enumerator's own name, and ZW_UNKNOWN otherwise."""
    for name, v in E.items():
        if name.startswith("ZW_ERR_") or name == "ZW_OK":
            assert zw.status_name(v) == name
    assert zw.status_name(12345) == "ZW_UNKNOWN"


def test_relative_condition_numbers_at_most_two():
    """The C checks budget a relative error of delta as at most 2x relative error in every
    coefficient field (internal.h, zw_eb_coef) and delta e^-delta <= 1/e absolute in e.
    Verify |d ln F / d ln delta| <= 2 for c1, c2, d12, s, g, 2/c2 on 1e-12 .. 1e12."""
    worst = 0
    with mp.workdps(40):
        for t in np.linspace(math.log(1e-12), math.log(1e12), 120):
            for name in ("c1", "c2", "d12", "s", "g", "h"):
                k = abs(mp.diff(lambda x: mp.log(getattr(ref.coeffs(mp.exp(x)), name)), mpf(t)))
                worst = max(worst, k)
                assert k <= 2 + mpf("1e-20"), (name, math.exp(t), k)
            d = mp.exp(mpf(t))
            assert d * mp.exp(-d) <= 1 / mp.e
    print(f"\nworst relative condition number of a coefficient field in delta: {mpmath.nstr(worst, 6)}")
