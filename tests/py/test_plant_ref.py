# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zw_plant_init (plant.h) against a 50+-digit reference.

Proves: every coefficient of N, D and of their bilinear images (and D's Taylor
coefficients at z = 1) is within its stated bound of the exact value at the given (delta,
kappa), over a dense grid (delta in [0, 1e6], kappa in [0, 1e6]) and the hard cases
(critical damping +- a few ulps, tiny delta or kappa, kappa -> 0 against the ideal plant);
the bounds also cover a stated input uncertainty; and the discretization's convention
against a direct high-precision integration of the continuous plant under a held input.

The reference forms Phi, Gamma from the augmented matrix exponential expm([[A, b], [0, 0]])
(mpmath at 100 digits, checked against 140 on a sample), D = 2 det(zI - Phi) and
N = 2 C adj(zI - Phi) Gamma through det(zI - Phi + Gamma C) - det(zI - Phi) (the matrix
determinant lemma): nothing of the C code's formulas (poles, series, regimes) is reused.
"""
import ctypes
import math
from ctypes import POINTER, byref, c_int, c_uint

import numpy as np
import pytest
from mpmath import mp, mpf

import reference as ref
from conftest import E, load

MAXO = 3


def plant_struct(R, Coeffs):
    class Spec(ctypes.Structure):
        _fields_ = [(n, R) for n in ("delta", "kappa", "lambda_", "delta_relerr", "kappa_relerr",
                                     "lambda_relerr")]

    class Plant(ctypes.Structure):
        _fields_ = [("spec", Spec), ("order", c_uint),
                    ("den", R * (MAXO + 1)), ("den_err", R * (MAXO + 1)),
                    ("num", R * MAXO), ("num_err", R * MAXO),
                    ("den_s", R * (MAXO + 1)), ("den_s_err", R * (MAXO + 1)),
                    ("num_s", R * MAXO), ("num_s_err", R * MAXO),
                    ("c", Coeffs),
                    ("den_w", R * (MAXO + 1)), ("den_w_err", R * (MAXO + 1))]
    return Spec, Plant


class PlantLib:
    def __init__(self, zw):
        self.zw = zw
        R = zw.real
        self.Spec, self.Plant = plant_struct(R, zw.Coeffs)
        self.init = zw.symbol("zw_plant_init")
        self.init.restype, self.init.argtypes = c_int, [POINTER(self.Plant), POINTER(self.Spec)]
        self.from_coeffs = zw.symbol("zw_plant_from_coeffs")
        self.from_coeffs.restype = c_int
        self.from_coeffs.argtypes = [POINTER(self.Plant), POINTER(zw.Coeffs)]
        self.eval = zw.symbol("zw_plant_eval")
        self.eval.restype = c_int
        self.eval.argtypes = [POINTER(self.Plant), R, R] + [POINTER(R)] * 6

    def plant(self, delta, kappa, lam=0.0, drel=0.0, krel=0.0, lrel=0.0):
        spec = self.Spec(delta, kappa, lam, drel, krel, lrel)
        p = self.Plant()
        st = self.init(byref(p), byref(spec))
        return st, p


@pytest.fixture(scope="module", params=["double", "float"])
def pl(request):
    return PlantLib(load(request.param))


# ---------------------------------------------------------------------------------------
# reference
# ---------------------------------------------------------------------------------------

def _charpoly(M):
    """Coefficients of det(zI - M), highest first (2x2 or 3x3)."""
    n = M.rows
    if n == 2:
        return [mpf(1), -(M[0, 0] + M[1, 1]), M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]]
    tr = M[0, 0] + M[1, 1] + M[2, 2]
    m2 = (M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0] + M[0, 0] * M[2, 2] - M[0, 2] * M[2, 0]
          + M[1, 1] * M[2, 2] - M[1, 2] * M[2, 1])
    return [mpf(1), -tr, m2, -mp.det(M)]


def _bilinear(c):
    """p((1+s)/(1-s)) (1-s)^n for p of degree n (highest first), highest first in s."""
    n = len(c) - 1
    out = [mpf(0)] * (n + 1)
    for i, a in enumerate(c):
        k = n - i  # power of z
        # (1+s)^k (1-s)^(n-k)
        poly = [mpf(1)]
        for _ in range(k):
            poly = [x + y for x, y in zip(poly + [0], [0] + poly)]
        for _ in range(n - k):
            poly = [x - y for x, y in zip(poly + [0], [0] + poly)]
        # poly is lowest power first
        for j, x in enumerate(poly):
            out[n - j] += a * x
    return out


def _taylor1(c):
    """p(1 + w), highest first in w."""
    n = len(c) - 1
    out = [mpf(0)] * (n + 1)
    for i, a in enumerate(c):
        k = n - i
        for j in range(k + 1):
            out[n - j] += a * mp.binomial(k, j)
    return out


def reference(delta, kappa, lam=0.0, dps=100):
    """(den, num, den_s, num_s, den_w) of the exact sampled plant, as mpf lists."""
    with mp.workdps(dps):
        d, k = mpf(delta), mpf(kappa)
        if lam == 0:
            A = mp.matrix([[0, 1], [-k, -d]])
            b = [0, 1]
        else:
            L = mpf(lam)
            A = mp.matrix([[0, 1, 0], [-k, -d, 1], [0, 0, -1 / L]])
            b = [0, 0, 1 / L]
        n = A.rows
        M = mp.zeros(n + 1, n + 1)
        for i in range(n):
            for j in range(n):
                M[i, j] = A[i, j]
            M[i, n] = b[i]
        Ex = mp.expm(M)
        Phi = mp.matrix(n, n)
        for i in range(n):
            for j in range(n):
                Phi[i, j] = Ex[i, j]
        Gam = [Ex[i, n] for i in range(n)]
        GC = mp.matrix(n, n)
        for i in range(n):
            GC[i, 0] = Gam[i]
        dpoly = _charpoly(Phi)
        lemma = _charpoly(Phi - GC)
        den = [2 * x for x in dpoly]
        num = [2 * (y - x) for x, y in zip(dpoly, lemma)][1:]
        return den, num, _bilinear(den), _bilinear(num), _taylor1(den)


def _dps_for(delta, kappa):
    """Digits enough for the reference's own cancellation: P ~ kappa s / 2 cancels
    -log10(kappa) digits, small delta -log10(delta), and the coefficients as small as
    e^-delta (det, b0) need delta log10(e) digits below the largest (capped: beyond 10^-1200
    no zw_real, subnormals included, can be told from 0)."""
    extra = 0
    if kappa > 0:
        extra = max(0, int(-math.log10(kappa)) + 5)
    if delta > 0:
        extra = max(extra, int(-math.log10(delta)) + 5, min(int(delta * 0.4343) + 5, 1200))
    return 80 + extra


FIELDS = ("den", "num", "den_s", "num_s", "den_w")


def check_point(pl, delta, kappa, drel=0.0, krel=0.0, dk=None, lam=0.0, lrel=0.0):
    """Assert every coefficient within its bound; return (field, index, actual, bound, exact)."""
    zw = pl.zw
    st, p = pl.plant(delta, kappa, lam, drel, krel, lrel)
    assert st == E["ZW_OK"], (delta, kappa, lam, zw.status_name(st))
    assert p.order == (3 if lam > 0 else 2)
    if dk is None:
        dk = (delta, kappa, lam)
    dps = _dps_for(dk[0], dk[1])
    if lam > 0:
        dps = max(dps, 80 + min(int(0.4343 / float(dk[2])) + 5, 1200), 80 + int(abs(math.log10(lam))) * 2)
    refs = dict(zip(FIELDS, reference(dk[0], dk[1], dk[2] if len(dk) > 2 else 0.0, dps=dps)))
    ref_err = mpf(10) ** (25 - dps)  # the reference's own cancellation (coefficients <= 4)
    stats = []
    for f in FIELDS:
        vals, errs = getattr(p, f), getattr(p, f + "_err")
        for i, exact in enumerate(refs[f]):
            v, e = vals[i], errs[i]
            actual = abs(mpf(v) - exact)
            assert math.isfinite(e) and actual <= e + ref_err, (zw.name, delta, kappa, lam, f, i, v,
                                                                 float(exact), e, float(actual))
            stats.append((f, i, float(actual), e, float(exact)))
    return stats


def _grid(zw, n):
    lo_k = -12 if zw.name == "double" else -8
    ds = [0.0] + [zw.r(x) for x in np.logspace(-8, 6, n)]
    ks = [zw.r(x) for x in np.logspace(lo_k, 6, n)]
    return ds, ks


def _critical(zw):
    """delta^2 = 4 kappa +- a few ulps, at several delta."""
    fmt = zw.fmt
    out = []
    for d in (1e-6, 1e-3, 0.1, 1.0, 2.0, 3.9, 4.0, 4.1, 10.0, 100.0, 1e3, 1e4):
        d = zw.r(d)
        k = zw.r(mpf(d) ** 2 / 4)
        for j in (-3, -1, 0, 1, 3):
            out.append((d, ref.step(k, j, fmt)))
    return out


def test_grid_within_bounds(pl):
    ds, ks = _grid(pl.zw, 20)
    for d in ds:
        for k in ks:
            check_point(pl, d, k)


def test_critical_damping_within_bounds(pl):
    for d, k in _critical(pl.zw):
        check_point(pl, d, k)


def test_regime_edges(pl):
    """The series / separated / direct switches: h = 2, |w2| = 4, w2 = h^2 / 2."""
    zw, fmt = pl.zw, pl.zw.fmt
    pts = []
    for d in (3.99, 4.0, 4.01, 5.0, 8.0):
        for k in (d * d / 8, d * d / 4 - 4, d * d / 4 + 4, 1e-3, 1.0, 50.0):
            if k > 0:
                pts.append((zw.r(d), zw.r(k)))
    for d in (0.0, 0.5, 1.0, 2.0):
        for k in (d * d / 4 + 4, d * d / 4 - 4):
            if k > 0:
                for j in (-1, 0, 1):
                    pts.append((zw.r(d), ref.step(zw.r(k), j, fmt)))
    for d, k in pts:
        check_point(pl, d, k)


def test_tiny_inputs(pl):
    zw = pl.zw
    tiny = [1e-30, 1e-20, 1e-12] if zw.name == "double" else [1e-20, 1e-12, 1e-8]
    for t in tiny:
        for other in (0.0, t, 1e-3, 1.0, 1e3):
            check_point(pl, zw.r(other), zw.r(t))
            if other > 0:
                check_point(pl, zw.r(t), zw.r(other))


def test_kappa_to_zero_meets_ideal_plant(pl):
    """kappa -> 0 tends to the ideal plant's coefficients (continuity, within the bounds)."""
    zw = pl.zw
    for d in (0.0, 0.01, 1.0, 3.0, 10.0, 1e3):
        st, p0 = pl.plant(zw.r(d), 0.0)
        assert st == E["ZW_OK"]
        st, p1 = pl.plant(zw.r(d), zw.r(1e-30) if zw.name == "double" else zw.r(1e-20))
        assert st == E["ZW_OK"]
        for f in FIELDS:
            for i in range(2 if f.startswith("num") else 3):
                a, b = getattr(p0, f)[i], getattr(p1, f)[i]
                tol = getattr(p0, f + "_err")[i] + getattr(p1, f + "_err")[i] + 1e-18
                assert abs(a - b) <= tol, (d, f, i, a, b, tol)


def test_input_uncertainty_covered(pl):
    """With relerrs (a few u, and wide ones up to the 1/16 allowed), the bounds cover the
    exact plant at the corners and the centre of the input box."""
    zw = pl.zw
    for rel in (8 * zw.u, 1e-4, 0.05):
        for d, k in [(0.3, 2.0), (1.0, 0.25), (3.9, 3.9), (5.0, 6.25), (20.0, 3.0), (0.01, 100.0),
                     (100.0, 2500.0)]:
            d, k = zw.r(d), zw.r(k)
            if pl.plant(d, k, 0.0, rel, rel)[0] == E["ZW_ERR_RANGE"]:
                assert rel > 1e-3, (d, k, rel)  # too wide to bound: refused, never wrong
                continue
            for sd in (-1, 0, 1):
                for sk in (-1, 0, 1):
                    dk = (mpf(d) * (1 + sd * mpf(rel)), mpf(k) * (1 + sk * mpf(rel)), 0)
                    check_point(pl, d, k, drel=rel, krel=rel, dk=dk)


def tightness(zw_name, n=24):
    """(field, bound/actual median, max bound in ulps of the coefficient) over the grid."""
    pl_ = PlantLib(load(zw_name))
    ds, ks = _grid(pl_.zw, n)
    rows = {}
    for d in ds:
        for k in ks:
            for f, i, actual, e, exact in check_point(pl_, d, k):
                ulp = float(ref.ulp_of(exact, pl_.zw.fmt)) if exact != 0 else float(pl_.zw.fmt.tiny)
                rows.setdefault((f, i), []).append((e / max(actual, 1e-300), e / ulp))
    return rows


# ---------------------------------------------------------------------------------------
# the actuator lag (order 3)
# ---------------------------------------------------------------------------------------

def _lams(zw):
    return [zw.r(x) for x in np.logspace(-4, 4, 7)]


def test_lag_grid_within_bounds(pl):
    zw = pl.zw
    ds = [0.0] + [zw.r(x) for x in np.logspace(-6, 4, 6)]
    ks = [0.0] + [zw.r(x) for x in np.logspace(-6, 5, 6)]
    for d in ds:
        for k in ks:
            for lam in _lams(zw):
                check_point(pl, d, k, lam=lam)


def test_lag_meets_a_pole(pl):
    """lambda = 1 / |p| (the lag's pole on a real plant pole) +- a few ulps, and near a
    complex pair's real part."""
    zw, fmt = pl.zw, pl.zw.fmt
    for d, k in [(1.0, 0.1), (3.0, 2.0), (10.0, 1.0), (0.5, 0.0625), (5.0, 6.25), (1e3, 10.0), (1.0, 0.0),
                 (0.2, 4.0)]:
        d, k = zw.r(d), zw.r(k)
        h = mpf(d) / 2
        w2 = h * h - mpf(k)
        poles = [h + mp.sqrt(w2), h - mp.sqrt(w2)] if w2 >= 0 else [h]
        for q in poles:
            if q <= 0:
                continue
            lam = zw.r(1 / q)
            for j in (-2, 0, 2):
                check_point(pl, d, k, lam=ref.step(lam, j, fmt))


def test_lag_limits(pl):
    """lambda -> 0 tends to the order-2 plant times z (a pole at e^-1/lambda -> 0 with a
    nearly cancelling zero); lambda >> 1 puts a pole next to z = 1."""
    zw = pl.zw
    for d, k in [(0.0, 0.0), (0.3, 0.0), (1.0, 2.0), (8.0, 1.0), (0.01, 100.0)]:
        d, k = zw.r(d), zw.r(k)
        for lam in (1e-6, 1e-3, 0.01, 1e4, 1e5):
            check_point(pl, d, k, lam=zw.r(lam))
        st2, p2 = pl.plant(d, k)
        st3, p3 = pl.plant(d, k, zw.r(1e-6))
        assert st2 == st3 == E["ZW_OK"]
        # N3 = z N2 + O(lambda), D3 = z D2 + O(e^-1/lambda)
        for i in range(2):
            assert abs(p3.num[i] - p2.num[i]) <= 1e-5 * (abs(p2.num[0]) + abs(p2.num[1])) + p3.num_err[i] + p2.num_err[i]
        for i in range(3):
            assert abs(p3.den[i] - p2.den[i]) <= p3.den_err[i] + p2.den_err[i]


def test_lag_input_uncertainty_covered(pl):
    zw = pl.zw
    for rel in (8 * zw.u, 0.05):
        for d, k, lam in [(0.3, 2.0, 0.5), (5.0, 6.25, 0.4), (1.0, 0.0, 2.0), (20.0, 3.0, 0.05), (2.5, 1.0, 2.0)]:
            d, k, lam = zw.r(d), zw.r(k), zw.r(lam)
            if pl.plant(d, k, lam, rel, rel, rel)[0] == E["ZW_ERR_RANGE"]:
                assert rel > 1e-3, (d, k, lam, rel)
                continue
            for sl in (-1, 1):
                dk = (mpf(d) * (1 + mpf(rel)), mpf(k) * (1 - mpf(rel)), mpf(lam) * (1 + sl * mpf(rel)))
                check_point(pl, d, k, drel=rel, krel=rel, dk=dk, lam=lam, lrel=rel)


# ---------------------------------------------------------------------------------------
# direct simulation: the convention of N / D
# ---------------------------------------------------------------------------------------

def _simulate(delta, kappa, inputs, lam=0.0, dps=40):
    """x(k) at the sample instants of x'' + delta x' + kappa x = F(t) (F = u, or u through
    the lag lam F' + F = u), u held over each period, integrated by mpmath's Taylor-series
    ODE solver (independent of any matrix exponential)."""
    with mp.workdps(dps):
        d, k = mpf(delta), mpf(kappa)
        x, v, y = mpf(0), mpf(0), mpf(0)
        out = [x]
        for u in inputs:
            uu = mpf(u)
            if lam > 0:
                nu = 1 / mpf(lam)
                f = mp.odefun(lambda t, s: [s[1], s[2] - d * s[1] - k * s[0], nu * (uu - s[2])], 0, [x, v, y])
                x, v, y = f(1)
            else:
                f = mp.odefun(lambda t, s: [s[1], uu - d * s[1] - k * s[0]], 0, [x, v])
                x, v = f(1)
            out.append(x)
        return out


def test_difference_equation_matches_simulation(pl):
    zw = pl.zw
    rng = np.random.default_rng(16)
    for d, k in [(0.5, 2.0), (1.0, 0.25), (0.0, 9.0), (2.0, 0.5)]:
        st, p = pl.plant(zw.r(d), zw.r(k))
        assert st == E["ZW_OK"]
        u = [float(x) for x in rng.uniform(-1, 1, 6)]
        x = _simulate(zw.r(d), zw.r(k), u)
        # D(q) x = N(q) u with D, N scaled by 2: 2 x_{j+2} - 2 tr x_{j+1} + 2 det x_j
        #   = num0 u_{j+1} + num1 u_j
        for j in range(len(u) - 1):
            lhs = p.den[0] * x[j + 2] + p.den[1] * x[j + 1] + p.den[2] * x[j]
            rhs = p.num[0] * u[j + 1] + p.num[1] * u[j]
            scale = sum(abs(c) for c in p.den[:3]) * max(abs(float(y)) for y in x) + 1e-30
            assert abs(lhs - rhs) <= 50 * zw.u * scale + 1e-30, (d, k, j, float(lhs), float(rhs))


def test_lag_difference_equation_matches_simulation(pl):
    zw = pl.zw
    rng = np.random.default_rng(17)
    for d, k, lam in [(0.5, 2.0, 0.3), (1.0, 0.0, 1.0), (0.0, 9.0, 0.1)]:
        st, p = pl.plant(zw.r(d), zw.r(k), zw.r(lam))
        assert st == E["ZW_OK"] and p.order == 3
        u = [float(x) for x in rng.uniform(-1, 1, 6)]
        x = _simulate(zw.r(d), zw.r(k), u, lam=zw.r(lam))
        for j in range(len(u) - 2):
            lhs = sum(p.den[i] * x[j + 3 - i] for i in range(4))
            rhs = sum(p.num[i] * u[j + 2 - i] for i in range(3))
            scale = sum(abs(c) for c in p.den) * max(abs(float(y)) for y in x) + 1e-30
            assert abs(lhs - rhs) <= 50 * zw.u * scale + 1e-30, (d, k, lam, j, float(lhs), float(rhs))


# ---------------------------------------------------------------------------------------
# real units
# ---------------------------------------------------------------------------------------

def test_spec_from_device_relerr_holds(pl):
    """delta, kappa, lambda from real units are within their stated relerr of the exact
    (b + b_h) T / (m + m_h), (k_p + k_h) T^2 / (m + m_h), tau / T, on random devices."""
    zw = pl.zw
    R = zw.real
    fn = zw.symbol("zw_plant_spec_from_device")
    fn.restype = c_int
    fn.argtypes = [R] * 8 + [POINTER(pl.Spec), POINTER(R)]
    rng = np.random.default_rng(18)
    for _ in range(400):
        m, b, T, kp, tau, mh, bh, kh = (zw.r(10.0 ** x) for x in rng.uniform(-4, 3, 8))
        spec, M = pl.Spec(), R()
        st = fn(m, b, T, kp, tau, mh, bh, kh, byref(spec), byref(M))
        assert st == E["ZW_OK"]
        Mx = mpf(m) + mpf(mh)
        exact = {"delta": (mpf(b) + mpf(bh)) * mpf(T) / Mx, "kappa": (mpf(kp) + mpf(kh)) * mpf(T) ** 2 / Mx,
                 "lambda_": mpf(tau) / mpf(T)}
        for name, x in exact.items():
            rel = getattr(spec, name.rstrip("_") + "_relerr") if name != "lambda_" else spec.lambda_relerr
            assert abs(mpf(getattr(spec, name)) - x) <= rel * abs(x), (name, getattr(spec, name), x, rel)
        assert abs(mpf(M.value) - Mx) <= zw.u * Mx


def normwise_table(name, mode):
    """bound / (u max |coef| of the polynomial), median / 90th pct / max per polynomial, over
    the grids docs/numerics.md reports (mode: "o2", "o3" lambda in [0.01, 10], "o3x" the
    extreme lambdas)."""
    pl_ = PlantLib(load(name))
    zw = pl_.zw
    if mode == "o2":
        ds, ks = _grid(zw, 24)
        pts = [(d, k, 0.0) for d in ds for k in ks] + [(d, k, 0.0) for d, k in _critical(zw)]
    else:
        ds = [0.0] + [zw.r(x) for x in np.logspace(-6, 4, 8)]
        ks = [0.0] + [zw.r(x) for x in np.logspace(-6, 5, 8)]
        lams = (0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0) if mode == "o3" else (1e-4, 1e-3, 30.0, 100.0, 1e3, 1e4)
        pts = [(d, k, zw.r(lam)) for d in ds for k in ks for lam in lams]
    rows = {}
    for d, k, lam in pts:
        stats = check_point(pl_, d, k, lam=lam)
        scale = {}
        for f, _, _, _, exact in stats:
            scale[f] = max(scale.get(f, 0.0), abs(exact))
        for f, _, _, e, _ in stats:
            rows.setdefault(f, []).append(e / (zw.u * scale[f]))
    return len(pts), {f: (np.median(v), np.percentile(v, 90), max(v)) for f, v in rows.items()}


if __name__ == "__main__":  # the figures of docs/numerics.md, "Plant-side parts"
    for mode in ("o2", "o3", "o3x"):
        for name in ("double", "float"):
            n, table = normwise_table(name, mode)
            print(name, mode, n, "points:",
                  ", ".join(f"{f} {a:.3g} / {b:.3g} / {c:.3g}" for f, (a, b, c) in table.items()))
