# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""Certification over a plant box (box.h) against mpmath at 50+ digits, both precisions.

The reference K_max(B; m, b) is the paper's expanded eq (10) (reference.f_hyperbola and
reference.line, coefficients from the literal definitions) at the exact real inputs; the
box's infimum is a dense grid minimum refined by a golden-section search in m around the
grid's best point (and cross-checked at the worst plants by the roots of p(z)).

Claims tested:
* K_lower never exceeds the true infimum, on random boxes including boxes where K_max(B)
  has an interior minimum in m (paper Section IV: not monotone in m);
* tightness: (infimum - K_lower) / infimum <= 2e-6 (double, the Python defaults of
  zwidth.PlantBox) / 2e-4 (float), measured and printed;
* a "stable" box verdict is true for every plant (roots at the worst plants and a grid),
  an "unstable" one names a plant that is unstable;
* the B range and K_mmax of the box are certified on a grid and close to the grid's;
* the monotonicity facts the enclosure rests on and the d12 peak constants in box.c.
"""
from __future__ import annotations

import ctypes
import math
import random
import re
from ctypes import POINTER, byref, c_bool, c_int, c_uint32
from pathlib import Path

import mpmath
import pytest
from mpmath import mp, mpf

import reference as ref

REPO = Path(__file__).resolve().parents[2]
DPS = 50


# ---------------------------------------------------------------------------------------
# Reference
# ---------------------------------------------------------------------------------------


def k_max_ref(m, b, T, B):
    """sup K stable at B for the plant (m, b, T), exact real inputs, paper's eq (10)."""
    with mp.workdps(DPS + 20):
        m, b, T, B = (ref.exact(x) for x in (m, b, T, B))
        delta, beta = b * T / m, B * T / m
        if not beta + delta > 0:
            return mpf(0)
        alpha = min(ref.f_hyperbola(delta, beta), ref.line(delta, beta))
        return max(mpf(0), alpha) * m / (T * T)


def box_min_ref(box, B, n_m=121, n_b=5):
    """(infimum, m, b) of K_max(B) over the box: a grid, then golden-section refinement in
    m at the best grid b and in b at the best m (a few rounds)."""
    m_lo, m_hi, b_lo, b_hi, T = box
    ms = [m_lo + (m_hi - m_lo) * i / (n_m - 1) for i in range(n_m)]
    bs = [b_lo + (b_hi - b_lo) * j / (n_b - 1) for j in range(n_b)] if b_hi > b_lo else [b_lo]
    best = min(((k_max_ref(m, b, T, B), i, j) for i, m in enumerate(ms) for j, b in enumerate(bs)),
               key=lambda t: t[0])
    k, i, j = best
    m, b = ms[i], bs[j]

    def golden(f, lo, hi, iters=60):
        inv = (math.sqrt(5) - 1) / 2
        c, d = hi - inv * (hi - lo), lo + inv * (hi - lo)
        fc, fd = f(c), f(d)
        for _ in range(iters):
            if fc < fd:
                hi, d, fd = d, c, fc
                c = hi - inv * (hi - lo)
                fc = f(c)
            else:
                lo, c, fc = c, d, fd
                d = lo + inv * (hi - lo)
                fd = f(d)
        return (c, fc) if fc < fd else (d, fd)

    for _ in range(2):
        lo, hi = ms[max(i - 1, 0)], ms[min(i + 1, n_m - 1)]
        m2, k2 = golden(lambda x: k_max_ref(x, b, T, B), lo, hi)
        if k2 < k:
            k, m = k2, m2
        if b_hi > b_lo:
            lo, hi = bs[max(j - 1, 0)], bs[min(j + 1, len(bs) - 1)]
            b2, k2 = golden(lambda x: k_max_ref(m, x, T, B), lo, hi)
            if k2 < k:
                k, b = k2, b2
    return k, m, b


def roots_stable(m, b, T, K, B):
    """All roots of p(z) strictly inside the unit circle (reference.stable, Jury at the
    exact normalized inputs)."""
    with mp.workdps(DPS + 20):
        d, a, be = ref.normalize(m, b, T, K, B)
    return ref.stable(d, a, be)


# ---------------------------------------------------------------------------------------
# ctypes bindings of box.h (both precisions)
# ---------------------------------------------------------------------------------------


class Box:
    def __init__(self, zw):
        R = zw.real
        self.zw = zw

        class PlantBox(ctypes.Structure):
            _fields_ = [("m_lo", R), ("m_hi", R), ("b_lo", R), ("b_hi", R), ("T", R)] + [
                (n, R) for n in ("k_lo", "k_hi", "m_h_lo", "m_h_hi", "b_h_lo", "b_h_hi", "k_h_lo", "k_h_hi",
                                 "tau_lo", "tau_hi")]

        class Cell(ctypes.Structure):
            _fields_ = [("m_lo", R), ("m_hi", R), ("b_lo", R), ("b_hi", R), ("bound", R)]

        class Work(ctypes.Structure):
            _fields_ = [("cells", POINTER(Cell)), ("capacity", c_uint32), ("max_evals", c_uint32),
                        ("rel_tol", R)]

        class Bound(ctypes.Structure):
            _fields_ = [("K_lower", R), ("K_upper", R), ("m_worst", R), ("b_worst", R),
                        ("evals", c_uint32), ("converged", c_bool), ("k_worst", R)]

        class BoxVerdict(ctypes.Structure):
            _fields_ = [("stable", c_bool), ("decided", c_bool), ("K_lower", R), ("m_worst", R),
                        ("b_worst", R)]

        class Extremes(ctypes.Structure):
            _fields_ = [("K_mmax", R), ("B_at", R), ("K_upper_at", R), ("K_mmax_upper", R),
                        ("m_worst", R), ("b_worst", R), ("converged", c_bool)]

        self.PlantBox, self.Cell, self.Work = PlantBox, Cell, Work
        self.Bound, self.Verdict, self.Extremes = Bound, BoxVerdict, Extremes
        P = POINTER
        sigs = {
            "zw_box_k_max": [P(PlantBox), R, P(Work), P(Bound)],
            "zw_box_check": [P(PlantBox), R, R, P(Work), P(BoxVerdict)],
            "zw_box_b_range": [P(PlantBox), R, P(Work), P(R), P(R), P(c_bool)],
            "zw_box_k_mmax": [P(PlantBox), P(Work), P(Extremes)],
            "zw_box_validate": [P(PlantBox)],
        }
        self.fn = {}
        for name, args in sigs.items():
            f = zw.symbol(name)
            f.restype, f.argtypes = c_int, args
            self.fn[name] = f
        double = zw.name == "double"
        self.capacity = 1 << 16
        self.cells = (Cell * self.capacity)()
        self.work = Work(ctypes.cast(self.cells, P(Cell)), self.capacity, 400_000 if double else 100_000,
                         1e-6 if double else 1e-4)

    def box(self, m_lo, m_hi, b_lo, b_hi, T):
        return self.PlantBox(m_lo, m_hi, b_lo, b_hi, T)

    def exact_box(self, box):
        """The box as the library sees it (its values rounded to the precision)."""
        b = self.box(*box)
        return (b.m_lo, b.m_hi, b.b_lo, b.b_hi, b.T)

    def k_max(self, box, B):
        out = self.Bound()
        st = self.fn["zw_box_k_max"](byref(self.box(*box)), B, byref(self.work), byref(out))
        return st, out

    def check(self, box, K, B):
        out = self.Verdict()
        st = self.fn["zw_box_check"](byref(self.box(*box)), K, B, byref(self.work), byref(out))
        return st, out

    def b_range(self, box, K):
        lo, hi, ne = self.zw.real(), self.zw.real(), c_bool()
        st = self.fn["zw_box_b_range"](byref(self.box(*box)), K, byref(self.work), byref(lo), byref(hi),
                                       byref(ne))
        return st, lo.value, hi.value, ne.value

    def k_mmax(self, box):
        out = self.Extremes()
        st = self.fn["zw_box_k_mmax"](byref(self.box(*box)), byref(self.work), byref(out))
        return st, out


@pytest.fixture(scope="module")
def bx(zw):
    return Box(zw)


def tight_tol(zw):
    return 2e-6 if zw.name == "double" else 2e-4


# The paper's rotary plant: b = 2.197e-3, T = 0.02, m_K2 = 7.6e-6, m_K1 = 4.2e-5.
B_PAPER, T_PAPER = 2.197e-3, 0.02


def random_boxes(seed, n):
    """Boxes in delta = 0.05 .. 40 around the paper's plant, some spanning m_K2 .. m_K1
    and beyond (K_max non-monotone in m), with gains B across the stable band."""
    rnd = random.Random(seed)
    out = []
    for _ in range(n):
        T = rnd.choice([0.02, 0.008, 0.001])
        b_mid = B_PAPER * 10 ** rnd.uniform(-0.5, 0.5)
        delta_mid = 10 ** rnd.uniform(-1.3, 1.6)
        m_mid = b_mid * T / delta_mid
        spread_m = 10 ** rnd.uniform(-2, 0.6)
        m_lo, m_hi = m_mid / (1 + spread_m), m_mid * (1 + spread_m)
        spread_b = rnd.choice([0.0, 0.05, 0.3])
        b_lo, b_hi = b_mid * (1 - spread_b), b_mid * (1 + spread_b)
        box = (m_lo, m_hi, b_lo, b_hi, T)
        # a B inside the band of the plant (m_lo, b_lo): from -b_lo up to its B_mmax
        B_hi = float(ref.b_mmax(m_lo, b_lo, T))
        B = -b_lo + rnd.uniform(0.05, 0.9) * (B_hi + b_lo)
        out.append((box, B))
    return out


# Hand-picked boxes where K_max(B) has an interior minimum in m (grid-verified below).
NONMONOTONE = [
    ((2.0e-5, 1.5e-4, B_PAPER, B_PAPER, T_PAPER), 1.0e-3),
    ((5.0e-5, 4.0e-4, B_PAPER, B_PAPER, T_PAPER), 5.0e-4),
    ((2.0e-5, 1.5e-4, 0.9 * B_PAPER, 1.1 * B_PAPER, T_PAPER), 1.0e-3),
]


def _check_bound(bx, zw, box, B, report):
    st, r = bx.k_max(box, B)
    assert st == 0, zw.status_name(st)
    ebox = bx.exact_box(box)
    Bx = zw.r(B)
    inf, m_at, b_at = box_min_ref(ebox, Bx)
    assert mpf(r.K_lower) <= inf, f"K_lower {r.K_lower!r} above the infimum {inf} at {m_at}, {b_at}"
    gap = float((inf - mpf(r.K_lower)) / inf) if inf > 0 else 0.0
    report.append(gap)
    assert gap <= tight_tol(zw), f"gap {gap:.3g} to the infimum {inf} (K_lower {r.K_lower!r})"
    # K_upper is K_max at a plant of the box, so it is >= the infimum (up to its rounding)
    assert mpf(r.K_upper) >= inf * (1 - 64 * zw.u)
    assert ebox[0] <= r.m_worst <= ebox[1] and ebox[2] <= r.b_worst <= ebox[3]
    return r, inf


def test_never_above_the_infimum_random(zw, bx):
    gaps = []
    for box, B in random_boxes(20261201, 8):
        _check_bound(bx, zw, box, B, gaps)
    print(f"\n{zw.name}: 8 random boxes, worst relative gap to the infimum {max(gaps):.3g}")


def test_nonmonotone_in_m(zw, bx):
    gaps = []
    for box, B in NONMONOTONE:
        ebox = bx.exact_box(box)
        Bx = zw.r(B)
        inf, m_at, _ = box_min_ref(ebox, Bx)
        corners = [k_max_ref(m, b, ebox[4], Bx) for m in ebox[:2] for b in ebox[2:4]]
        # the minimum is interior in m: corners alone would overstate the box's K_max
        assert ebox[0] < m_at < ebox[1] and inf < min(corners) * (1 - 1e-4)
        r, _ = _check_bound(bx, zw, box, B, gaps)
        # the worst plant found is the interior one
        assert abs(r.m_worst - m_at) < 0.05 * (ebox[1] - ebox[0])
    print(f"\n{zw.name}: interior minima, worst relative gap {max(gaps):.3g}")


def test_verdicts_against_roots(zw, bx):
    for box, B in NONMONOTONE[:2] + [(b, B) for b, B in random_boxes(7, 3)]:
        st, r = bx.k_max(box, B)
        assert st == 0
        ebox = bx.exact_box(box)
        Bx = zw.r(B)
        inf, m_at, b_at = box_min_ref(ebox, Bx)
        # just below the certified bound: stable, and the roots agree at the worst plants
        K = zw.r(r.K_lower * (1 - 8 * zw.u))
        st, v = bx.check(box, K, B)
        assert st == 0 and v.stable and v.decided
        for m, b in ((m_at, b_at), (r.m_worst, r.b_worst), (ebox[0], ebox[2]), (ebox[1], ebox[3])):
            assert roots_stable(m, b, ebox[4], K, Bx)
        # above the infimum: not stable, and the plant named is unstable by its roots
        K = zw.r(float(inf) * (1 + 1e-3))
        st, v = bx.check(box, K, B)
        assert st == 0 and not v.stable and v.decided
        assert not roots_stable(v.m_worst, v.b_worst, ebox[4], K, Bx)


def _grid_min_over_b(box, B, n_m=61, n_b=5):
    m_lo, m_hi, b_lo, b_hi, T = box
    return min(k_max_ref(m_lo + (m_hi - m_lo) * i / (n_m - 1), b_lo + (b_hi - b_lo) * j / (n_b - 1), T, B)
               for i in range(n_m) for j in range(n_b))


def test_b_range_and_k_mmax(zw, bx):
    box = (5e-6, 5e-5, 2.0e-3, 2.4e-3, 0.02)
    ebox = bx.exact_box(box)
    st, x = bx.k_mmax(box)
    assert st == 0
    # certified at B_at: K_mmax <= the box's K_max there
    inf, _, _ = box_min_ref(ebox, x.B_at)
    assert mpf(x.K_mmax) <= inf
    # close to the best any B achieves on a grid of B (refined around its best)
    Bs = [-2.0e-3 + 4.0e-3 * i / 80 for i in range(81)]
    vals = [(_grid_min_over_b(ebox, zw.r(B), 31, 3), B) for B in Bs]
    _, B0 = max(vals, key=lambda t: t[0])  # refine around the coarse best
    vals += [(_grid_min_over_b(ebox, zw.r(B)), B) for B in (B0 + 5e-5 * k for k in range(-10, 11))]
    best, B_best = max(vals, key=lambda t: t[0])
    assert mpf(x.K_mmax) >= best * (1 - (2e-3 if zw.name == "double" else 5e-3)), (x.K_mmax, best, B_best)
    # the B range at half of it: both ends certified, and not far inside the grid's
    K = zw.r(0.5 * x.K_mmax)
    st, lo, hi, ne = bx.b_range(box, K)
    assert st == 0 and ne and lo < hi
    for B in (lo, hi, 0.5 * (lo + hi)):
        assert box_min_ref(ebox, zw.r(B), n_m=121, n_b=5)[0] > mpf(K)
    step = 1e-3 * (hi - lo)
    assert box_min_ref(ebox, zw.r(lo - step), 81, 5)[0] <= mpf(K)
    assert box_min_ref(ebox, zw.r(hi + step), 81, 5)[0] <= mpf(K)


def test_enclosure_facts():
    """e, c1, c2, s fall and g, h = 2/c2 rise with delta; d12 rises to one peak and falls;
    box.c's bracket of the peak and its upper bound of d12 hold (40 digits)."""
    text = (REPO / "csrc" / "src" / "box.c").read_text()

    def define(name):
        return mpf(re.search(rf"#define {name} ZW_R\(([0-9.eE+-]+)\)", text).group(1))

    peak_lo, peak_hi, d12_max_up = (define(n) for n in ("ZW_BOX_D12_PEAK_LO", "ZW_BOX_D12_PEAK_HI",
                                                        "ZW_BOX_D12_MAX_UP"))
    with mp.workdps(40):
        def d12(d):
            return ref.coeffs(d, 40).d12

        peak = mp.findroot(lambda d: mp.diff(d12, d), 2.7)
        assert peak_lo < peak < peak_hi
        assert d12(peak) < d12_max_up and d12_max_up - d12(peak) < mpf("1e-6")
        prev, prev_d = None, None
        for k in range(1, 1200):
            d = mpf(10) ** (-4 + mpf(k) * 10 / 1200)  # 1e-4 .. 1e6
            c = ref.coeffs(d, 40)
            cur = (c.e, c.c1, c.c2, c.s, c.g, c.h, c.d12)
            if prev is not None:
                assert cur[0] < prev[0] and cur[1] < prev[1] and cur[2] < prev[2] and cur[3] < prev[3]
                assert cur[4] > prev[4] and cur[5] > prev[5]
                if d <= peak:
                    assert cur[6] > prev[6]
                elif prev_d >= peak:
                    assert cur[6] < prev[6]
            prev, prev_d = cur, d


def test_errors_and_failsafe(zw, bx):
    E = {n: v for v, n in ((i, zw.status_name(i)) for i in range(0, 40))}
    cases = [((1e-5, 1e-6, 1e-3, 2e-3, 0.02), "ZW_ERR_BOX"), ((1e-5, 2e-5, 3e-3, 2e-3, 0.02), "ZW_ERR_BOX"),
             ((0.0, 2e-5, 1e-3, 2e-3, 0.02), "ZW_ERR_MASS"), ((1e-5, 2e-5, -1e-3, 2e-3, 0.02), "ZW_ERR_DAMPING"),
             ((1e-5, 2e-5, 1e-3, 2e-3, -0.02), "ZW_ERR_PERIOD"), ((math.nan, 2e-5, 1e-3, 2e-3, 0.02), "ZW_ERR_NAN"),
             ((1e-5, math.inf, 1e-3, 2e-3, 0.02), "ZW_ERR_INF")]
    for box, want in cases:
        st, r = bx.k_max(box, 0.0)
        assert st == E[want]
        assert r.K_lower == 0 and r.K_upper == 0 and not r.converged and math.isnan(r.m_worst)
        st, v = bx.check(box, 1.0, 0.0)
        assert st == E[want] and not v.stable and not v.decided and v.K_lower == 0
        st, lo, hi, ne = bx.b_range(box, 1.0)
        assert st == E[want] and lo == 0 and hi == 0 and not ne
        st, x = bx.k_mmax(box)
        assert st == E[want] and x.K_mmax == 0 and not x.converged


# ---------------------------------------------------------------------------------------
# zwidth.PlantBox (the package, double precision)
# ---------------------------------------------------------------------------------------


def test_plantbox_api():
    zwidth = pytest.importorskip("zwidth")
    box = zwidth.PlantBox.rotary_box((2.0e-5, 1.5e-4), B_PAPER, T_PAPER)
    r = box.k_max(1.0e-3)
    inf, _, _ = box_min_ref((2.0e-5, 1.5e-4, B_PAPER, B_PAPER, T_PAPER), 1.0e-3)
    assert mpf(r.K_lower) <= inf and r.gap <= 2e-6 and r.converged
    assert box.is_stable(r.K_lower * 0.999, 1.0e-3)
    assert not box.is_stable(float(inf) * 1.001, 1.0e-3)
    assert box.verdict(float(inf) * 1.001, 1.0e-3).word == "unstable"
    with pytest.raises(zwidth.ZwidthError) as err:
        zwidth.PlantBox((2.0, 1.0), 1.0, 0.01)
    assert err.value.status == "ZW_ERR_BOX" and err.value.parameter == "m"
    with pytest.raises(zwidth.ZwidthError) as err:
        zwidth.PlantBox((0.1, 0.2), (-1.0, 1.0), 0.01)
    assert err.value.status == "ZW_ERR_DAMPING" and err.value.parameter == "b"
