# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Real units (device.h): the paper's worked examples, safety of real-unit verdicts against
the exact real inputs, conversions, extremes, influence and error paths.

The reference normalizes the *exact* real inputs in mpmath (delta = b T / m, alpha =
K T^2 / m, beta = B T / m at 70 digits, no rounding), so a verdict that is only right for
the rounded normalized image of (K, B) would fail here.
"""
import math

import numpy as np
import pytest
from mpmath import mpf

import reference as ref
from conftest import COEF_ULPS, E

BAND = 64  # ulps of K and B (measured worst printed by the test)
N_REAL = 8000
LADDER = (1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64)


def sig(x, n):
    """x rounded to n significant digits (for comparing with the paper's printed numbers)."""
    return float(f"{x:.{n - 1}e}")


# ---------------------------------------------------------------------------------------
# The paper's worked examples (math.md, "Worked example")
# ---------------------------------------------------------------------------------------

SHORT = dict(m=85.78e-7, b=2.197e-3, T=0.02)


def test_worked_example_short_circuit(zw):
    """b = 2.197e-3, J = 85.78e-7, T = 0.02: delta = 5.1224, K_mmax = 0.4934 at
    B = -1.357e-3 (to the printed digits)."""
    st, d = zw.device(zw.r(SHORT["m"]), zw.r(SHORT["b"]), zw.r(SHORT["T"]))
    assert st == E["ZW_OK"]
    assert round(d.co.delta, 4) == 5.1224
    st, x = zw.device_extremes(d)
    assert st == E["ZW_OK"] and x.at_corner
    assert sig(x.K_mmax, 4) == 0.4934, x.K_mmax
    assert sig(x.B_at_K_mmax, 4) == -1.357e-3, x.B_at_K_mmax


def test_worked_example_legacy_claim_is_unstable(zw):
    """The legacy region's claim, the hyperbola top in real units alpha1 m / T^2 = 0.5806 at
    B = beta1 m / T = 3.46e-5, and the point itself (and just below it) is truly unstable:
    the legacy region calls it stable, zw_device_check does not."""
    m, b, T = (zw.r(SHORT[k]) for k in ("m", "b", "T"))
    st, d = zw.device(m, b, T)
    st, a1, b1 = zw.hyperbola_top(d.co)
    K, B = zw.r(a1 * d.k_scale), zw.r(b1 * d.b_scale)
    assert sig(K, 4) == 0.5806, K
    assert sig(B, 3) == 3.46e-5, B
    for KK, BB in ((zw.r(0.5806), zw.r(3.46e-5)), (K, B), (zw.r(K * (1 - 1e-4)), B)):
        delta, alpha, beta = ref.normalize(m, b, T, KK, BB)
        assert not ref.stable(delta, alpha, beta), (KK, BB)
        st, v = zw.device_check(d, KK, BB)
        assert st == E["ZW_OK"] and not v.stable, (KK, BB)
    st, v = zw.device_check_region(E["ZW_REGION_LEGACY"], d, zw.r(K * (1 - 1e-4)), B)
    assert st == E["ZW_OK"] and v.stable


def test_worked_example_influence(zw):
    """T = 0.02: m_K2 = 76.09e-7 (K_mmax rises by reducing J to it) and m_K_match = 1943.5e-7;
    the plant is on the falling stretch.  T = 0.008: delta = 2.049, J_K2 = 30.44e-7,
    J_K1 = 168.43e-7."""
    m, b = zw.r(SHORT["m"]), zw.r(SHORT["b"])
    st, d = zw.device(m, b, zw.r(0.02))
    st, inf = zw.device_influence(d)
    assert st == E["ZW_OK"]
    assert sig(inf.m_K2, 4) == 76.09e-7, inf.m_K2
    assert sig(inf.m_K_match, 5) == 1943.5e-7, inf.m_K_match
    assert inf.K_vs_m == E["ZW_FALLS"] and inf.best_m_for_K == inf.m_K2
    # reducing J to m_K2 really raises K_mmax (reference), and m_K_match matches it
    assert ref.k_mmax(inf.m_K2, b, zw.r(0.02)) > ref.k_mmax(m, b, zw.r(0.02))
    assert abs(ref.k_mmax(inf.m_K_match, b, zw.r(0.02)) / ref.k_mmax(inf.m_K2, b, zw.r(0.02)) - 1) < 1e-5
    st, d = zw.device(m, b, zw.r(0.008))
    st, inf = zw.device_influence(d)
    assert round(inf.delta, 3) == 2.049
    assert sig(inf.m_K2, 4) == 30.44e-7, inf.m_K2
    assert sig(inf.m_K1, 5) == 168.43e-7, inf.m_K1


def test_worked_example_open_circuit(zw):
    """Load motor open: b = 13.93e-6, T = 0.008: delta = 0.01299, K_mmax = 0.0943."""
    st, d = zw.device(zw.r(85.78e-7), zw.r(13.93e-6), zw.r(0.008))
    assert round(d.co.delta, 5) == 0.01299
    st, x = zw.device_extremes(d)
    assert sig(x.K_mmax, 3) == 0.0943, x.K_mmax


# ---------------------------------------------------------------------------------------
# Real-unit verdicts against the exact real inputs
# ---------------------------------------------------------------------------------------


def _plant(rng, zw):
    m = zw.r(10 ** rng.uniform(-8, 3))
    T = zw.r(10 ** rng.uniform(-6, 0))
    r = rng.random()
    if r < 0.05:
        delta = 0.0
    elif r < 0.35:
        delta = 10 ** rng.uniform(-6, -1)
    elif r < 0.75:
        delta = rng.uniform(0.5, 8)
    else:
        delta = 10 ** rng.uniform(1, 5)
    return m, zw.r(delta * m / T), T


def _real_point(task):
    """Worker: one (m, b, T, K, B) with K in [1e-6, 1e9] (or K <= 0); a quarter spread over
    and around the region, three quarters aimed at the boundary: alpha on min{f, L} within
    1e-17 .. 1e-9 relative, beta anywhere, next to -delta or next to beta_mmax; K and B are
    then rounded, which moves them by about an ulp."""
    name, seed = task
    fmt = ref.FORMATS[name]
    rng = np.random.default_rng(seed)
    rnd = lambda x: ref.round_to(x, fmt)  # noqa: E731

    class Z:
        r = staticmethod(rnd)

    while True:
        m, b, T = _plant(rng, Z)
        delta, _, _ = ref.normalize(m, b, T)
        if delta == 0 and b != 0:
            continue
        ex = ref.extremes(delta)
        am, bm = ex["alpha_mmax"], ex["beta_mmax"]
        kind = rng.integers(0, 4)
        if kind == 0:  # random
            beta = -delta + (bm + delta) * mpf(rng.uniform(-0.2, 1.2))
            alpha = am * mpf(rng.uniform(-0.05, 1.3))
        else:
            if kind == 1:
                beta = -delta + (bm + delta) * mpf(rng.uniform(0, 1))
            elif kind == 2:
                beta = -delta * (1 - mpf(10) ** rng.uniform(-12, -1)) if delta else mpf(10) ** rng.uniform(-9, -1)
            else:
                beta = bm * (1 - mpf(10) ** rng.uniform(-12, -1))
            bound, _ = ref.alpha_max_at(delta, beta)
            alpha = bound * (1 + mpf(10) ** rng.uniform(-17, -9) * rng.choice([-1, 1]))
        K = rnd(alpha * mpf(m) / mpf(T) ** 2)
        B = rnd(beta * mpf(m) / mpf(T))
        if not (K <= 0 or 1e-6 <= K <= 1e9) or not math.isfinite(B):
            continue
        if K < 0 and K > -1e-6:
            continue
        _, a, bb = ref.normalize(m, b, T, K, B)
        return m, b, T, K, B, ref.stable(delta, a, bb), int(kind)


_REAL = {}


@pytest.fixture(scope="module")
def real_run(zw):
    """N_REAL real-unit points with the exact reference verdict and the library's."""
    if zw.name not in _REAL:
        pts = ref.pmap(_real_point, [(zw.name, (77, zw.fmt.p, i)) for i in range(N_REAL)])
        res = []
        for m, b, T, K, B, truth, kind in pts:
            st, d = zw.device(m, b, T)
            assert st == E["ZW_OK"], (m, b, T, zw.status_name(st))
            st, v = zw.device_check(d, K, B)
            assert st == E["ZW_OK"], (m, b, T, K, B, zw.status_name(st))
            res.append((m, b, T, K, B, truth, v.stable, v.marginal, kind))
        _REAL[zw.name] = res
    return _REAL[zw.name]


def test_real_units_no_false_stable(zw, real_run):
    """Zero real-unit points reported stable that are unstable for the exact real inputs
    (K in [1e-6, 1e9], m in [1e-8, 1e3], T in [1e-6, 1], delta from 0 to 1e5)."""
    bad = [p[:5] for p in real_run if p[6] and not p[5]]
    n_stable = sum(p[5] for p in real_run)
    print(f"\n[{zw.name}] real units: {len(real_run)} points, {n_stable} truly stable, false stable {len(bad)}")
    assert n_stable > 0.2 * len(real_run)
    assert not bad, f"false stables (m, b, T, K, B): {bad[:8]}"


def _band_real(task):
    """Worker: smallest ladder k such that moving K and B by k ulps (some corner) makes the
    exact real point unstable, or -1."""
    name, (m, b, T, K, B) = task
    fmt = ref.FORMATS[name]
    for k in LADDER:
        for sk in (1, -1):
            for sb in (1, -1):
                KK, BB = ref.step(K, sk * k, fmt), ref.step(B, sb * k, fmt)
                if (0 < abs(K) < fmt.min_normal) and sk < 0:
                    KK = 0.0
                delta, a, bb = ref.normalize(m, b, T, KK, BB)
                if not ref.stable(delta, a, bb):
                    return k
    return -1


def test_real_units_false_unstable_band(zw, real_run):
    """Every truly stable point reported unstable is marginal and within BAND ulps of K and
    B of a truly unstable point (the rounding of delta, m/T, m/T^2 is part of the guard, so
    the band is a little wider than in the normalized space).  Prints count and worst band."""
    fu = [p for p in real_run if p[5] and not p[6]]
    assert all(p[7] for p in fu), [p[:5] for p in fu if not p[7]][:8]
    bands = ref.pmap(_band_real, [(zw.name, p[:5]) for p in fu], min_parallel=50)
    hist = {k: bands.count(k) for k in sorted(set(bands))}
    print(f"\n[{zw.name}] real units: false unstable {len(fu)} of {sum(p[5] for p in real_run)} stable; "
          f"band histogram (ulps of K, B; -1 = beyond {BAND}) {hist}")
    beyond = [p[:5] for p, k in zip(fu, bands) if k < 0]
    assert not beyond, f"false unstable farther than {BAND} ulps (m, b, T, K, B): {beyond[:8]}"


# ---------------------------------------------------------------------------------------
# Conversions, extremes, K_max, B range
# ---------------------------------------------------------------------------------------


def _plants(zw, n, seed):
    rng = np.random.default_rng(seed)
    return [_plant(rng, zw) for _ in range(n)]


def test_device_fields_and_normalize(zw):
    """k_scale = m/T^2 and b_scale = m/T within 2 ulps, co.delta within 2 ulps of b T / m and
    its declared delta_relerr covers its actual error; the coefficients match co.delta to
    ZW_COEF_ULPS; zw_device_normalize within 4 ulps of K T^2/m and B T/m (exact)."""
    fmt = zw.fmt
    rng = np.random.default_rng(8)
    for m, b, T in _plants(zw, 400, 1):
        st, d = zw.device(m, b, T)
        assert st == E["ZW_OK"]
        assert d.m == m and d.b == b and d.T == T
        delta, _, _ = ref.normalize(m, b, T)
        assert ref.ulp_distance(d.k_scale, mpf(m) / mpf(T) ** 2, fmt) <= 2
        assert ref.ulp_distance(d.b_scale, mpf(m) / mpf(T), fmt) <= 2
        assert ref.ulp_distance(d.co.delta, delta, fmt) <= 2
        if delta:
            assert abs(mpf(d.co.delta) - delta) / delta <= mpf(d.co.delta_relerr), (m, b, T, d.co.delta_relerr)
        rc = ref.coeffs(d.co.delta)
        for f in ("e", "c1", "c2", "d12", "s", "g"):
            assert ref.ulp_distance(getattr(d.co, f), getattr(rc, f), fmt) <= COEF_ULPS
        K = zw.r(10 ** rng.uniform(-6, 9))
        B = zw.r(rng.uniform(-1, 1) * 10 ** rng.uniform(-6, 6))
        st, a, bb = zw.device_normalize(d, K, B)
        if st == E["ZW_OK"]:
            _, ea, eb = ref.normalize(m, b, T, K, B)
            assert ref.ulp_distance(a, ea, fmt) <= 4 and ref.ulp_distance(bb, eb, fmt) <= 4, (m, b, T, K, B)
        else:
            assert st == E["ZW_ERR_RANGE"]


def test_device_extremes(zw):
    """zw_device_extremes_compute against (m/T^2) alpha_mmax(b T/m) etc. at the exact real
    inputs: K_mmax, K_p_max, B_mmax within 16 ulps (the delta rounding enters with a
    condition number <= 2), B_at_K_mmax within 16 u of its scale, B_mmin = -b (2 ulps),
    K_mmin = 0, at_corner iff delta > delta1 (away from delta1)."""
    fmt = zw.fmt
    d1 = ref.constants()["delta1"]
    worst = 0
    for m, b, T in _plants(zw, 300, 2):
        st, d = zw.device(m, b, T)
        st, x = zw.device_extremes(d)
        assert st == E["ZW_OK"]
        delta, _, _ = ref.normalize(m, b, T)
        ex = ref.extremes(delta)
        ks, bs = mpf(m) / mpf(T) ** 2, mpf(m) / mpf(T)
        for got, exact in ((x.K_mmax, ex["alpha_mmax"] * ks), (x.K_p_max, ex["alpha_p_max"] * ks),
                           (x.B_mmax, ex["beta_mmax"] * bs)):
            e = ref.ulp_distance(got, exact, fmt)
            worst = max(worst, e)
            assert e <= 16, (m, b, T, got, float(exact))
        scale = (abs(ex["beta_at"]) + (delta if ex["at_corner"] else 0)) * bs
        assert abs(mpf(x.B_at_K_mmax) - ex["beta_at"] * bs) <= 16 * zw.u * scale, (m, b, T)
        assert ref.ulp_distance(x.B_mmin, -mpf(b), fmt) <= 2 and x.K_mmin == 0
        if abs(delta - d1) > 1e-4 * d1:
            assert x.at_corner == ex["at_corner"]
    print(f"\n[{zw.name}] device extremes worst {worst} ulps")


def test_device_k_max_and_b_range(zw):
    """zw_device_k_max(B) and zw_device_b_range(K) describe the true region: K just below
    K_max(B) (by 1e-9 / 1e-4 relative) is truly stable and just above truly unstable; the
    middle of the B range is stable and its ends pushed out by the same amount unstable."""
    rel = 1e-9 if zw.name == "double" else 1e-4
    rng = np.random.default_rng(4)
    problems = []
    for m, b, T in _plants(zw, 120, 3):
        if b == 0:
            continue
        st, d = zw.device(m, b, T)
        delta, _, _ = ref.normalize(m, b, T)
        ex = ref.extremes(delta)
        bs, ks = mpf(m) / mpf(T), mpf(m) / mpf(T) ** 2
        beta = -delta + (ex["beta_mmax"] + delta) * mpf(rng.uniform(0.1, 0.9))
        B = zw.r(beta * bs)
        st, Kmax = zw.device_k_max(d, B)
        assert st == E["ZW_OK"] and Kmax > 0
        for K, want in ((zw.r(Kmax * (1 - rel)), True), (zw.r(Kmax * (1 + rel)), False)):
            dd, a, bb = ref.normalize(m, b, T, K, B)
            if ref.stable(dd, a, bb) != want:
                problems.append(("k_max", m, b, T, B, K, want))
        K = zw.r(ex["alpha_mmax"] * ks * mpf(rng.uniform(0.05, 0.9)))
        st, lo, hi, ne = zw.device_b_range(d, K)
        assert st == E["ZW_OK"] and ne and lo < hi
        w = hi - lo
        for BB, want in ((zw.r((lo + hi) / 2), True), (zw.r(lo - rel * w), False), (zw.r(hi + rel * w), False),
                         (zw.r(lo + rel * w), True), (zw.r(hi - rel * w), True)):
            dd, a, bb = ref.normalize(m, b, T, K, BB)
            if ref.stable(dd, a, bb) != want:
                problems.append(("b_range", m, b, T, K, lo, hi, BB, want))
    assert not problems, problems[:8]


def test_device_spectral_radius_and_within(zw):
    """zw_device_spectral_radius agrees with the roots at the exact real inputs (to 1e-12 /
    1e-4 relative where the radius is well conditioned) and zw_device_radius_within is never
    true when the exact rho >= r."""
    rng = np.random.default_rng(12)
    tol = 1e-12 if zw.name == "double" else 1e-4
    for m, b, T in _plants(zw, 120, 5):
        st, d = zw.device(m, b, T)
        delta, _, _ = ref.normalize(m, b, T)
        ex = ref.extremes(delta)
        K = zw.r(ex["alpha_mmax"] * mpf(rng.uniform(0.01, 1.3)) * mpf(m) / mpf(T) ** 2)
        B = zw.r((-delta + (ex["beta_mmax"] + delta) * mpf(rng.uniform(-0.1, 1.1))) * mpf(m) / mpf(T))
        _, a, bb = ref.normalize(m, b, T, K, B)
        rho, roots = ref.spectral_radius(delta, a, bb)
        kappa, _ = ref.radius_condition(delta, a, bb, roots)
        st, got = zw.device_spectral_radius(d, K, B)
        assert st == E["ZW_OK"]
        if kappa < 100:
            assert abs(mpf(got) - rho) <= tol * rho, (m, b, T, K, B, got, float(rho))
        for r in (zw.r(rho * (1 + mpf(t))) for t in (-1e-3, -1e-7, 1e-7, 1e-3)):
            if 0 < r:
                st, within = zw.device_radius_within(d, K, B, r)
                assert st == E["ZW_OK"]
                if within:
                    assert ref.roots_within(delta, a, bb, r), (m, b, T, K, B, r)


# ---------------------------------------------------------------------------------------
# Influence (Section IV, Table 1)
# ---------------------------------------------------------------------------------------

_CRIT = ("deltaK1", "deltaK2", "deltaB", "delta0", "delta1", "deltaBb")


def _trend(f, x, at_zero=False):
    """Sign of d f / d x at x by a central (forward at x = 0) difference at 60 digits."""
    x = mpf(x)
    h = abs(x) * mpf("1e-15") if x else mpf("1e-20")
    df = (f(x + h) - f(x)) if at_zero or not x else (f(x + h) - f(x - h))
    return 0 if df == 0 else (1 if df > 0 else -1)


def test_influence_fields(zw):
    """Critical masses/periods (b T / delta_K1, ...) within 4 ulps; the local extremes
    K_mmax_at_m_K2/K1 = (4.5087, 2.6374) b / T; K_mmax and B_mmax equal the device
    extremes; best_m_for_K = m_K2 on the falling stretch else m; b = 0: masses 0, periods
    +inf."""
    fmt = zw.fmt
    k = ref.constants()
    for m, b, T in _plants(zw, 300, 6):
        st, d = zw.device(m, b, T)
        st, x = zw.device_influence(d)
        assert st == E["ZW_OK"]
        _, ext = zw.device_extremes(d)
        assert x.K_mmax == ext.K_mmax and x.B_mmax == ext.B_mmax and x.delta == d.co.delta
        bT = mpf(b) * mpf(T)
        if b == 0:
            assert (x.m_K1, x.m_K2, x.m_K_match, x.m_0, x.m_B) == (0, 0, 0, 0, 0)
            assert x.T_B == math.inf and x.T_0 == math.inf
            assert x.best_m_for_K == m
            continue
        for got, exact in ((x.m_K1, bT / k["deltaK1"]), (x.m_K2, bT / k["deltaK2"]), (x.m_K_match, bT / k["deltaKM"]),
                           (x.m_0, bT / k["delta0"]), (x.m_B, bT / k["deltaB"]),
                           (x.T_B, mpf(m) * k["deltaB"] / mpf(b)), (x.T_0, mpf(m) * k["delta0"] / mpf(b)),
                           (x.K_mmax_at_m_K2, k["kmax_local_max"] * mpf(b) / mpf(T)),
                           (x.K_mmax_at_m_K1, k["kmax_local_min"] * mpf(b) / mpf(T))):
            assert ref.ulp_distance(got, exact, fmt) <= 4, (m, b, T, got, float(exact))
        falling = x.m_K2 < m < x.m_K1
        assert x.best_m_for_K == (x.m_K2 if falling else m)


def test_influence_trends(zw):
    """Each trend field is the sign of the derivative of the reference K_mmax / B_mmax in m,
    b, T (finite differences at 60 digits on the exact real inputs), away from the turning
    points (delta within 1e-6 relative of deltaK1, deltaK2, deltaB, delta0, delta1 and
    deltaBb = 3.2122..., where beta_mmax itself turns: B_mmax against b rises, falls on
    (delta0, deltaBb), rises again - the paper's "increase-decrease-increase")."""
    k = ref.constants()
    problems, checked = [], 0
    for m, b, T in _plants(zw, 150, 7):
        st, d = zw.device(m, b, T)
        st, x = zw.device_influence(d)
        delta, _, _ = ref.normalize(m, b, T)
        if delta and min(abs(delta / k[c] - 1) for c in _CRIT) < 1e-6:
            continue
        checked += 1
        m_, b_, T_ = mpf(m), mpf(b), mpf(T)
        want = {
            "K_vs_m": _trend(lambda v: ref.k_mmax(v, b_, T_), m_),
            "K_vs_b": _trend(lambda v: ref.k_mmax(m_, v, T_), b_, at_zero=(b == 0)),
            "K_vs_T": _trend(lambda v: ref.k_mmax(m_, b_, v), T_),
            "B_vs_m": _trend(lambda v: ref.b_mmax(v, b_, T_), m_),
            "B_vs_b": _trend(lambda v: ref.b_mmax(m_, v, T_), b_, at_zero=(b == 0)),
            "B_vs_T": _trend(lambda v: ref.b_mmax(m_, b_, v), T_),
        }
        for name, w in want.items():
            if getattr(x, name) != w:
                problems.append((m, b, T, float(delta), name, getattr(x, name), w))
    assert checked > 100
    summary = {}
    for p in problems:
        s = summary.setdefault(p[4], [0, math.inf, -math.inf, p[5], p[6]])
        s[0] += 1
        s[1], s[2] = min(s[1], p[3]), max(s[2], p[3])
    msg = "; ".join(f"{name}: {s[0]} wrong (e.g. got {s[3]}, reference {s[4]}) for delta in [{s[1]:.4g}, {s[2]:.4g}]"
                    for name, s in summary.items())
    assert not problems, f"{len(problems)} of {checked} plants: {msg}; first (m, b, T, delta, field, got, want): {problems[0]}"


# ---------------------------------------------------------------------------------------
# Error paths
# ---------------------------------------------------------------------------------------


def test_device_init_error_paths(zw):
    """NaN -> ZW_ERR_NAN, inf -> ZW_ERR_INF, m <= 0 -> ZW_ERR_MASS, T <= 0 -> ZW_ERR_PERIOD,
    b < 0 -> ZW_ERR_DAMPING, delta / m/T / m/T^2 not a finite normal number ->
    ZW_ERR_RANGE; the device struct is all NaN (fail-safe: later calls refuse it)."""
    big = 1e300 if zw.name == "double" else 1e30
    cases = [((math.nan, 1.0, 1.0), "ZW_ERR_NAN"), ((1.0, math.nan, 1.0), "ZW_ERR_NAN"), ((1.0, 1.0, math.nan), "ZW_ERR_NAN"),
             ((math.inf, 1.0, 1.0), "ZW_ERR_INF"), ((1.0, math.inf, 1.0), "ZW_ERR_INF"), ((1.0, 1.0, math.inf), "ZW_ERR_INF"),
             ((0.0, 1.0, 1.0), "ZW_ERR_MASS"), ((-1.0, 1.0, 1.0), "ZW_ERR_MASS"), ((-0.0, 1.0, 1.0), "ZW_ERR_MASS"),
             ((1.0, 1.0, 0.0), "ZW_ERR_PERIOD"), ((1.0, 1.0, -1e-3), "ZW_ERR_PERIOD"),
             ((1.0, -1e-3, 1.0), "ZW_ERR_DAMPING"), ((1.0, -1.0, 1.0), "ZW_ERR_DAMPING"),
             ((1 / big, big, 1.0), "ZW_ERR_RANGE"),          # delta = b T / m overflows
             ((big, 0.0, 1 / big), "ZW_ERR_RANGE"),          # m / T^2 overflows
             ((1 / big, 0.0, big), "ZW_ERR_RANGE")]          # m / T underflows
    for (m, b, T), s in cases:
        st, d = zw.device(zw.r(m), zw.r(b), zw.r(T))
        assert st == E[s] and zw.failsafe(), ((m, b, T), zw.status_name(st), s)
        # a caller that ignored the status is refused at the next call, fail-safe
        for call in (lambda: zw.device_check(d, 1.0, 0.0), lambda: zw.device_k_max(d, 0.0),
                     lambda: zw.device_extremes(d), lambda: zw.device_influence(d)):
            st, *_ = call()
            assert st == E["ZW_ERR_NAN"] and zw.failsafe(), ((m, b, T), zw.status_name(st))
    assert zw.lib.zw_device_init(None, 1.0, 1.0, 1.0) == E["ZW_ERR_NULL"]


def test_device_call_error_paths(zw):
    """NaN / infinite gains -> ZW_ERR_NAN / ZW_ERR_INF, overflowing normalization ->
    ZW_ERR_RANGE, r <= 0 -> ZW_ERR_ARG; outputs fail-safe (verdict not stable, gains NaN, rho
    +inf, within false, limits 0, ranges empty)."""
    st, d = zw.device(zw.r(1e-3), zw.r(0.5), zw.r(1e-3))  # k_scale = 1e3, b_scale = 1
    assert st == E["ZW_OK"]
    big = zw.fmt.max
    for K, B, s in ((math.nan, 0.0, "ZW_ERR_NAN"), (1.0, math.nan, "ZW_ERR_NAN"),
                    (math.inf, 0.0, "ZW_ERR_INF"), (1.0, -math.inf, "ZW_ERR_INF")):
        for call in (lambda: zw.device_normalize(d, K, B), lambda: zw.device_check(d, K, B),
                     lambda: zw.device_check_region(E["ZW_REGION_LEGACY"], d, K, B),
                     lambda: zw.device_spectral_radius(d, K, B), lambda: zw.device_radius_within(d, K, B, 0.9)):
            st, *_ = call()
            assert st == E[s] and zw.failsafe(), (K, B, zw.status_name(st))
    st, d2 = zw.device(zw.r(1e-3), zw.r(0.5), zw.r(10.0))  # k_scale = 1e-5: K / k_scale overflows
    st, *_ = zw.device_normalize(d2, big, 0.0)
    assert st == E["ZW_ERR_RANGE"] and zw.failsafe()
    st, *_ = zw.device_radius_within(d, 1.0, 0.0, 0.0)
    assert st == E["ZW_ERR_ARG"] and zw.failsafe()
    for call in (lambda: zw.device_k_max(d, math.nan), lambda: zw.device_b_range(d, math.nan)):
        st, *_ = call()
        assert st == E["ZW_ERR_NAN"] and zw.failsafe()
    assert zw.lib.zw_device_check(None, 1.0, 1.0, None) == E["ZW_ERR_NULL"]
    assert zw.lib.zw_device_influence(None, None) == E["ZW_ERR_NULL"]


# ---------------------------------------------------------------------------------------
# The Python API's results and errors (issue 15): named flags, named errors, boundary
# ---------------------------------------------------------------------------------------


def test_verdict_deciding_prints_and_compares_by_name():
    import zwidth
    v = zwidth.verdict(5.122, 23.0, -1.5)  # paper Fig. 19(a): beyond the line
    assert v.deciding == "line" and v.deciding == zwidth.Bound.LINE == zwidth.BOUNDS["line"]
    assert str(v.deciding) == "line" and f"{v.deciding}" == "line" and v.deciding != "hyperbola"
    assert repr(v) == ("Verdict(stable=False, marginal=False, deciding='line', violated=['line'], "
                       "loop=\"the paper's ideal loop (delay 0, backward difference, no velocity filter)\")")
    both = zwidth.Device.rotary(85.78e-7, 2.197e-3, 0.02).verdict(0.5, -1.36e-3)
    assert both.deciding == "hyperbola" and str(both.violated) == "hyperbola|line"
    assert zwidth.Bound.LINE in both.violated
    assert zwidth.verdict(5.122, 10.0, 0.0).deciding == zwidth.Bound.NONE == ""
    # arrays keep the bits, which compare with the members elementwise; the repr counts them
    many = zwidth.verdict(5.122, np.array([10.0, 23.0, 30.0]), -1.5)
    np.testing.assert_array_equal(many.deciding == zwidth.Bound.LINE, [False, True, False])
    assert "stable=1 of 3" in repr(many)
    inf = zwidth.Device(0.12, 0.8, 1e-3).influence()
    assert inf.K_vs_m == "rises" == zwidth.Trend.RISES == 1 and "K_vs_T='falls'" in repr(inf)
    lv = zwidth.verdict(5.122, 18.19, -3.17, delay=1)
    assert lv.boundary == "complex" == zwidth.LoopBoundary.COMPLEX


@pytest.mark.parametrize("bad, words", [
    (None, "got None"),
    ("0.12", "got a string ('0.12')"),
    ("abc", "got a string ('abc')"),
    (np.array(["0.1", "0.2"]), "an array of strings"),
    (np.ma.masked_array([0.1, 0.2], [0, 1]), "masked array with masked elements"),
])
def test_inputs_that_are_not_numbers_are_refused_by_name(bad, words):
    import zwidth
    with pytest.raises(TypeError, match=r"zwidth\.Device: m must be a number") as info:
        zwidth.Device(bad, 0.8, 1e-3)
    assert words in str(info.value) and info.value.parameter == "m"
    with pytest.raises(TypeError, match="J must be a number"):
        zwidth.Device.rotary(bad, 0.8, 1e-3)
    with pytest.raises(TypeError, match=r"Device\.is_stable: K must be a number"):
        zwidth.Device(0.12, 0.8, 1e-3).is_stable(bad, 0.0)
    with pytest.raises(TypeError, match=r"zwidth\.check: beta must be a number"):
        zwidth.check(1.0, 1.0, bad)
    # a masked array without masked elements is its data
    assert zwidth.check(np.ma.masked_array([1.0, 2.0], [0, 0]), 1.0, 0.0).tolist() == [True, True]


def test_shape_mismatch_names_the_parameters():
    import zwidth
    with pytest.raises(ValueError, match=r"zwidth\.Device: the shapes of m \(3,\), b \(\), T \(2,\) do not broadcast"):
        zwidth.Device([1.0, 2.0, 3.0], 0.8, [1e-3, 2e-3])
    dev = zwidth.Device.rotary(85.78e-7, 2.197e-3, 0.02)
    with pytest.raises(ValueError, match=r"J \(\), b \(\), T \(\), K \(3,\), B \(2,\) do not broadcast"):
        dev.is_stable([0.1, 0.2, 0.3], [0.0, 1e-3])


def test_sweep_results_print_compactly():
    import zwidth
    lim = zwidth.Device(np.geomspace(1e-3, 1, 200)[:, None], 0.8, np.geomspace(1e-4, 1e-2, 300)).extremes()
    text = repr(lim)
    assert text.count("\n") == 0 and len(text) < 600, text
    assert "K_mmax=array(shape=(200, 300), " in text and "% True" in text
    page = lim._repr_html_()
    assert page.startswith("<table>") and "K_mmax" in page and "shape=(200, 300)" in page
    assert repr(zwidth.extremes([0.013, 2.049, 5.122])).startswith("Extremes(alpha_mmax=[0.70373, 6.09966, 23.0048]")


def test_boundary_as_arrays_has_the_corner_and_the_ends():
    """zwidth.boundary / Device.boundary: the outline as arrays, with the corner exactly
    (against the 50-digit corner of eqs (21), (22)) and alpha = 0 at both ends."""
    import zwidth
    beta, alpha = zwidth.boundary(5.122, points=201)
    assert beta[0] == -5.122 and beta[-1] == zwidth.extremes(5.122).beta_mmax
    assert alpha[0] == 0.0 and alpha[-1] == 0.0 and np.all(np.diff(beta) > 0)
    a2, b2 = ref.corner(5.122)
    i = int(np.argmax(alpha))
    assert abs(beta[i] - float(b2)) <= 8 * abs(math.ulp(float(b2)))
    assert abs(alpha[i] - float(a2)) <= 8 * math.ulp(float(a2))
    for k in (1, 50, 150, 199):  # every point: the 50-digit min{f, L} (near beta_mmax the line
        exact, _ = ref.alpha_max_at(5.122, beta[k])  # L = 4(1+e)/d12 - 2 beta cancels: ulps of 2 beta)
        assert abs(alpha[k] - float(exact)) <= 8 * math.ulp(max(float(exact), 2 * abs(beta[k]))), k
    dev = zwidth.Device.rotary(85.78e-7, 2.197e-3, 0.02)
    B, K = dev.boundary(points=101)
    lim = dev.extremes()
    assert B[0] == lim.B_mmin and B[-1] == lim.B_mmax and K[0] == K[-1] == 0.0
    # K = k_max(B), never above the region: at B_at_K_mmax within rounding below K_mmax
    assert B[int(np.argmax(K))] == lim.B_at_K_mmax
    assert 0.0 <= lim.K_mmax - K.max() <= 4 * math.ulp(float(lim.K_mmax))
    with pytest.raises(ValueError, match="one plant"):
        zwidth.Device([0.1, 0.2], 1.0, 0.01).boundary()
