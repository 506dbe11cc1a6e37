# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""The per-plant sweep (csrc/src/sweep.c, zwidth/sweep.h) against its proof and mpmath.

1. The tables in sweep.c are the generator's (tools/gen_sweep_tables.py), and the
   error bound the generator proves for them (Cauchy tail, Horner rounding, coefficient
   and h rounding) is re-derived here from the header's own numbers, both precisions.
2. Every field (e, g, hs, d12) against a 50-digit reference over a dense grid and the hard
   cases, both precisions: within the proved relative bounds (docs/numerics.md) and within
   ZW_COEF_ULPS = 4 ulps, the budget the checks assume.
3. Verdicts: never stable for a point the exact Jury test at 60+ digits calls unstable
   (points crowded at the boundary, a delta per point), and equal to zw_check's away from
   the rounding band; the fail-safe and error paths.
"""
from __future__ import annotations

import ctypes
import math
import re
import sys
from pathlib import Path

import numpy as np
import pytest
from mpmath import mp, mpf

import reference as ref
from conftest import LIB_DIR, LIB_NAMES

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "tools"))
import gen_sweep_tables as gen  # noqa: E402

TABLES = REPO / "csrc" / "src" / "sweep.c"  # the generated block
# Proved relative bounds in units of u (docs/numerics.md section 7; the generator's, rounded up)
BOUND_BELOW_2 = {"e": 2.1, "g": 2.4, "hs": 4.8, "d12": 5.3}
BOUND_ABOVE_2 = {"e": 2.1, "g": 5.4, "hs": 6.5, "d12": 7.2}
BUDGET = 2 * 4                # 2 ZW_COEF_ULPS u: what the checks assume of every field
ZW_OK = 0


class Fields(ctypes.Structure):
    pass


def load(precision):
    path = LIB_DIR / LIB_NAMES[precision]
    if not path.exists():
        pytest.fail(f"{path} not found: build with cmake or set ZW_LIB_DIR", pytrace=False)
    lib = ctypes.CDLL(str(path))
    real = ctypes.c_double if precision == "double" else ctypes.c_float
    suffix = "" if precision == "double" else "_f"

    class F(ctypes.Structure):
        _fields_ = [(n, real) for n in ("e", "g", "hs", "d12", "sigma")]

    init = getattr(lib, "zw_sweep_fields_init" + suffix)
    init.restype, init.argtypes = ctypes.c_int, [ctypes.POINTER(F), real]
    many = getattr(lib, "zw_sweep_check_many" + suffix)
    P = ctypes.POINTER
    many.restype = ctypes.c_int
    many.argtypes = [ctypes.c_size_t, P(real), ctypes.c_ssize_t, P(real), ctypes.c_ssize_t, P(real),
                     ctypes.c_ssize_t, P(ctypes.c_bool), P(ctypes.c_size_t)]
    return lib, real, F, init, many


@pytest.fixture(scope="module", params=["double", "float"])
def sweep(request):
    return (request.param, *load(request.param))


# ---------------------------------------------------------------------------------------
# 1. The tables and their proof
# ---------------------------------------------------------------------------------------


def header_tables():
    """The literals of sweep.c's generated block: piece rows, q's coefficients, the X_k."""
    text = TABLES.read_text()
    out = {}
    for name in gen.FUNCTIONS:
        block = re.search(rf"zw_sweep_{name.lower()}\[2\]\[ZW_SWEEP_TERMS\] = \{{(.*?)\n\}};", text, re.S).group(1)
        out[name] = [re.findall(r"ZW_R\(([^)]*)\)", row) for row in re.findall(r"\{([^}]*)\}", block)]
    macro = re.search(r"#define ZW_SWEEP_EXP_Q\(h\) (.*)", text).group(1)
    out["q"] = list(reversed(re.findall(r"ZW_R\(([^)]*)\)", macro)))  # lowest power first
    block = re.search(r"zw_sweep_exp_x\[ZW_SWEEP_EXP_ENTRIES\] = \{(.*?)\n\};", text, re.S).group(1)
    out["x"] = re.findall(r"ZW_R\(([^)]*)\)", block)
    return out


def as_precision(text, precision):
    """The literal as the compiler reads it: correctly rounded to double or float."""
    return gen.as_precision(text, precision)


@pytest.fixture(scope="module")
def tables():
    return header_tables()


def test_tables_are_the_generators(tables):
    text = TABLES.read_text()
    block = text[text.index(gen.BEGIN):text.index(gen.END) + len(gen.END)]
    assert block == gen.tables_text()  # regenerate with tools/gen_sweep_tables.py
    for name in gen.FUNCTIONS:
        assert len(tables[name]) == gen.PIECES and all(len(r) == gen.PIECE_TERMS for r in tables[name])
    assert len(tables["q"]) == gen.EXP_TERMS and len(tables["x"]) == gen.EXP_ENTRIES


@pytest.mark.parametrize("precision", ["double", "float"])
def test_proved_bounds_of_the_tables(tables, precision):
    """The bounds of the proof, re-derived from sweep.c's own numbers as the compiler reads
    them: every piece polynomial (Cauchy tail of T_N, exact Chebyshev bound of T_N - p^,
    Horner's rounding, h's rounding), the exponential (every X_k), and the fields built on
    them (below 2 and the closed forms on [2, 64)) within the bounds the tests below use,
    all within the checks' budget of 8 u."""
    worst = {}
    for name in gen.FUNCTIONS:
        for p in range(gen.PIECES):
            hats = [as_precision(s, precision) for s in tables[name][p]]
            worst[f"{name}[{p}]"] = float(gen.piece_bound(name, p, precision, hats))
    e_bound = gen.exp_bound(precision, [as_precision(s, precision) for s in tables["x"]],
                            [as_precision(s, precision) for s in tables["q"]])
    u = gen.UNIT[precision]
    q = max(worst[f"Q[{p}]"] for p in range(gen.PIECES))
    below = {"e": float(e_bound), "g": max(worst[f"G[{p}]"] for p in range(gen.PIECES)),
             "hs": max(worst[f"W[{p}]"] for p in range(gen.PIECES)), "d12": float(((1 + q * u) * (1 + u) - 1) / u)}
    above = {k: float(v) for k, v in gen.closed_form_bounds(precision, e_bound).items()}
    print(f"\n{precision}: proved bounds (u): {worst}, exp {float(e_bound):.3f}; fields below 2 {below}, "
          f"on [2, 64) {above}")
    for field in BOUND_BELOW_2:
        assert below[field] <= BOUND_BELOW_2[field] <= BUDGET, (field, below)
        assert above[field] <= BOUND_ABOVE_2[field] <= BUDGET, (field, above)


def test_tail_and_sup_bounds_are_not_vacuous():
    """The estimates themselves: the Cauchy tail really bounds the next Taylor terms, and
    the Chebyshev sum bounds the polynomial it is applied to (at many points)."""
    for name in gen.FUNCTIONS:
        for p in range(gen.PIECES):
            c = gen.piece_centre(p)
            n = 30
            more = gen.taylor(name, c, n + 10)
            tail = mp.fsum(abs(a) * gen.PIECE_RADIUS ** k for k, a in enumerate(more) if k >= n)
            assert tail <= gen.tail_bound(name, c, n, gen.PIECE_RADIUS), (name, p)
    rng = np.random.default_rng(5)
    for _ in range(5):
        poly = [mpf(float(x)) for x in rng.normal(size=9)]
        bound = gen.sup_bound(poly, gen.PIECE_RADIUS)
        for h in np.linspace(-0.5, 0.5, 201):
            assert abs(mp.polyval(poly[::-1], mpf(float(h)))) <= bound


# ---------------------------------------------------------------------------------------
# 2. The fields against mpmath
# ---------------------------------------------------------------------------------------


def exact_fields(delta):
    with mp.workdps(50):
        d = ref.exact(delta)
        if d == 0:
            return {"e": mpf(1), "g": mpf(1) / 2, "w": mpf(2), "d12": mpf(0)}
        co = ref.coeffs(delta)
        return {"e": co.e, "g": co.c1 / (co.c1 + co.c2), "w": 2 / co.c2, "d12": co.d12}


def deltas(precision):
    rng = np.random.default_rng(15)
    np_type = np.float64 if precision == "double" else np.float32
    grid = np.exp(rng.uniform(math.log(1e-12), math.log(63.99), 1500))
    edges = np.arange(0, 64, 1 / 32)  # every interval's end, and a step either side
    hard = [0.0, 1e-300 if precision == "double" else 1e-40, 2.0 ** -20, 1.0, 2.0, 63.5, 64.0, 100.0, 1e3,
            2.3105713567536940]
    values = np.concatenate([grid, edges, hard]).astype(np_type)
    ups = np.nextafter(values, np_type(np.inf))
    downs = np.nextafter(values[values > 0], np_type(0))
    return np.unique(np.concatenate([values, ups, downs]))


def test_fields_against_mpmath(sweep):
    precision, lib, real, F, init, many = sweep
    u = 2.0 ** -53 if precision == "double" else 2.0 ** -24
    worst = {}
    worst_ulps = {}
    for d in deltas(precision):
        f = F()
        assert init(ctypes.byref(f), real(float(d))) == ZW_OK, d
        ex = exact_fields(float(d))
        below = float(d) < 2.0
        for field, key in (("e", "e"), ("g", "g"), ("hs", "w"), ("d12", "d12")):
            got = mpf(getattr(f, field)) * (mpf(f.sigma) if field == "hs" else 1)
            want = ex[key]
            if want == 0:
                assert got == 0
                continue
            rel = abs(got - want) / want / u
            if float(d) < 64.0:  # beyond: zw_coeffs_init, whose budget is ZW_COEF_ULPS
                limit = (BOUND_BELOW_2 if below else BOUND_ABOVE_2)[field]
                # a subnormal d12 (delta below ~1e-308) is bounded absolutely, as in coeffs.h
                if not (field == "d12" and abs(float(getattr(f, field))) < np.finfo(
                        np.float64 if precision == "double" else np.float32).tiny):
                    assert rel <= limit, (precision, field, float(d), float(rel))
            stored = float(getattr(f, field))
            ulps = ref.ulp_distance(stored, want / (mpf(f.sigma) if field == "hs" else 1), ref.FORMATS[precision])
            worst_ulps[field] = max(worst_ulps.get(field, 0), float(ulps))
            if float(d) < 64.0 and abs(stored) >= np.finfo(np.float32).tiny:
                worst[field] = max(worst.get(field, 0), float(rel))
    print(f"\n{precision}: worst relative error (u) {({k: round(v, 2) for k, v in worst.items()})}, "
          f"ulps {({k: round(v, 2) for k, v in worst_ulps.items()})}")
    assert max(worst_ulps.values()) <= 4  # ZW_COEF_ULPS, as zw_coeffs_init


def test_fields_error_paths_fail_safe(sweep):
    precision, lib, real, F, init, many = sweep
    for bad, status in ((math.nan, "ZW_ERR_NAN"), (-1.0, "ZW_ERR_DELTA"), (math.inf, "ZW_ERR_INF")):
        f = F(1.0, 1.0, 1.0, 1.0, 1.0)
        st = init(ctypes.byref(f), real(bad))
        assert st != ZW_OK
        assert all(math.isnan(getattr(f, n)) for n in ("e", "g", "hs", "d12", "sigma"))
    assert init(None, real(1.0)) != ZW_OK


# ---------------------------------------------------------------------------------------
# 3. Verdicts
# ---------------------------------------------------------------------------------------


def run_many(sweep, d, a, b):
    precision, lib, real, F, init, many = sweep
    np_type = np.float64 if precision == "double" else np.float32
    d, a, b = (np.ascontiguousarray(x, dtype=np_type) for x in (d, a, b))
    out = np.zeros(len(d), dtype=np.bool_)
    first = ctypes.c_size_t(12345)
    P = ctypes.POINTER(real)
    st = many(len(d), d.ctypes.data_as(P), 1, a.ctypes.data_as(P), 1, b.ctypes.data_as(P), 1,
              out.ctypes.data_as(ctypes.POINTER(ctypes.c_bool)), ctypes.byref(first))
    return st, out, first.value


def boundary_points(precision, n=1500, seed=3):
    """A delta per point, (alpha, beta) within 1e-9 relative of the exact boundary
    (on either side), plus random points; the truth from the Jury test at 60+ digits."""
    rng = np.random.default_rng(seed)
    np_type = np.float64 if precision == "double" else np.float32
    d = np.exp(rng.uniform(math.log(1e-6), math.log(63.0), n)).astype(np_type)
    beta = np.empty(n, dtype=np_type)
    alpha = np.empty(n, dtype=np_type)
    for i, di in enumerate(d):
        ex = ref.extremes(float(di))
        bt = -float(di) + rng.uniform(0.02, 0.98) * (float(ex["beta_mmax"]) + float(di))
        top, _ = ref.alpha_max_at(float(di), bt)
        jitter = 1.0 + rng.choice([-1, 1]) * 10.0 ** rng.uniform(-9 if precision == "double" else -5, -1)
        beta[i], alpha[i] = bt, float(top) * jitter
    return d, alpha, beta


def test_never_stable_when_unstable(sweep):
    precision = sweep[0]
    d, a, b = boundary_points(precision)
    st, stable, _ = run_many(sweep, d, a, b)
    assert st == ZW_OK
    truth = np.array([ref.stable(float(x), float(y), float(z)) for x, y, z in zip(d, a, b)])
    false_stable = int((stable & ~truth).sum())
    print(f"\n{precision}: {len(d)} points at the boundary, a delta each: {int(stable.sum())} stable, "
          f"{int(truth.sum())} truly stable, false stable {false_stable}")
    assert false_stable == 0
    assert stable.sum() >= 0.9 * truth.sum()  # stable points are found (the band is narrow)


def test_equals_zw_check_away_from_the_band():
    """double: the sweep's verdicts are zwidth.check's (the one-delta path) bit for bit away
    from the rounding band (both guarded, with different roundings near the boundary)."""
    import zwidth
    rng = np.random.default_rng(7)
    n = 20000
    d = np.exp(rng.uniform(math.log(1e-4), math.log(200.0), n))
    ex = zwidth.extremes(d)
    a = rng.uniform(0, 1.3, n) * ex.alpha_mmax
    b = -d + rng.uniform(0, 1, n) * (ex.beta_mmax + d)
    fast = zwidth.check(d, a, b)                      # a plant per point: the sweep
    one = np.array([bool(zwidth.check(float(x), float(y), float(z))) for x, y, z in zip(d, a, b)])
    rho = zwidth.spectral_radius(d, a, b)
    away = np.abs(rho - 1.0) > 1e-9
    assert np.array_equal(fast[away], one[away])
    assert int((fast & ~one).sum()) <= int((~away).sum())


def test_bindings_vector_build_equals_the_library():
    """zwidth.check on a plant per point runs an AVX-512 (with fma) or AVX2 build of sweep.c
    where the CPU has one (bindings/sweep_avx*.c): the same proved bounds (an fma rounds
    once where the proof counts two roundings), so its verdicts are the portable library's
    away from the rounding band, and never stable for an unstable point of the boundary set;
    checked on random points through every route (tables, closed forms, zw_coeffs_init), in
    blocks of every mix."""
    import zwidth
    sweep = ("double", *load("double"))
    d, a, b = boundary_points("double")
    truth = np.array([ref.stable(float(x), float(y), float(z)) for x, y, z in zip(d, a, b)])
    assert not (zwidth.check(d, a, b) & ~truth).any()
    rng = np.random.default_rng(11)
    n = 20000
    d2 = np.exp(rng.uniform(math.log(1e-6), math.log(500.0), n))
    d2[rng.random(n) < 0.5] *= 0.01  # blocks all in the tables, and mixed ones
    ex = zwidth.extremes(d2)
    a2 = rng.uniform(0, 1.3, n) * ex.alpha_mmax
    b2 = -d2 + rng.uniform(0, 1, n) * (ex.beta_mmax + d2)
    for dd, aa, bb in ((d, a, b), (d2, a2, b2), (d2[:1000:3], a2[:1000:3], b2[:1000:3])):
        st, lib_verdict, _ = run_many(sweep, dd, aa, bb)
        assert st == ZW_OK
        away = np.abs(zwidth.spectral_radius(dd, aa, bb) - 1.0) > 1e-12
        fast = zwidth.check(dd, aa, bb)
        assert np.array_equal(fast[away], lib_verdict[away])


def test_error_paths_name_the_point_and_fail_safe(sweep):
    d = np.array([1.0, 2.5, -1.0, 3.0])
    st, out, first = run_many(sweep, d, np.ones(4), np.zeros(4))
    assert st != ZW_OK and first == 2 and not out.any()
    st, out, first = run_many(sweep, np.array([1.0, 70.0]), np.array([1.0, math.nan]), np.zeros(2))
    assert st != ZW_OK and first == 1 and not out.any()
    st, out, first = run_many(sweep, np.array([0.5, 3.0, 100.0]), np.array([0.1, 1.0, 1.0]), np.zeros(3))
    assert st == ZW_OK and out.all()  # small gains at every kind of delta: stable
