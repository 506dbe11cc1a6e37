# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Plant boxes of the general loop (box.h, box_loop.c) and the ideal plant's enclosure over
a delta interval (plant_box.h), against mpmath at 50+ digits.

* zw_plant_enclose: for random intervals over delta = 1e-8..1e3 (widths from a few ulps to
  a factor 30), every exact coefficient (literal formulas at 90 digits) at 60 deltas inside
  the interval, its ends included, lies within value +- err; the d12 peak bracket of
  plant_box.c / box.c has the signs the proof in docs/box.md needs.
* zw_box_loop_k_max: over a 7 x 7 grid of plants of each box, every K in (0, K_lower] at 12
  points is stable (the loop's definition, Schur-Cohn at 50 digits: loop_limits' reference),
  and K_lower is below each plant's true K_max(B) (bisection at 50 digits from K_lower);
  the tightness K_lower / grid min is printed (pytest -s) and bounded.
"""
from __future__ import annotations

import ctypes
import random
from ctypes import POINTER, byref, c_bool, c_int, c_uint

import mpmath
import pytest
from mpmath import mp, mpf

from test_loop_limits_reference import RefLoop
from conftest import E, LOOP_N  # noqa: F401

DPS = 50
MAX_ORDER = 3


def _types(zw):
    R = zw.real

    class PlantSpec(ctypes.Structure):
        _fields_ = [(n, R) for n in ("delta", "kappa", "lambda_", "delta_relerr", "kappa_relerr",
                                     "lambda_relerr")]

    class Plant(ctypes.Structure):
        _fields_ = [("spec", PlantSpec), ("order", c_uint),
                    ("den", R * (MAX_ORDER + 1)), ("den_err", R * (MAX_ORDER + 1)),
                    ("num", R * MAX_ORDER), ("num_err", R * MAX_ORDER),
                    ("den_s", R * (MAX_ORDER + 1)), ("den_s_err", R * (MAX_ORDER + 1)),
                    ("num_s", R * MAX_ORDER), ("num_s_err", R * MAX_ORDER),
                    ("c", zw.Coeffs),
                    ("den_w", R * (MAX_ORDER + 1)), ("den_w_err", R * (MAX_ORDER + 1))]

    class Box(ctypes.Structure):
        _fields_ = [(n, R) for n in ("m_lo", "m_hi", "b_lo", "b_hi", "T", "k_lo", "k_hi", "m_h_lo", "m_h_hi",
                                     "b_h_lo", "b_h_hi", "k_h_lo", "k_h_hi", "tau_lo", "tau_hi")]

    class DLSpec(ctypes.Structure):
        _fields_ = [("delay", c_uint), ("differentiator", c_int), ("filter", c_int),
                    ("cutoff_hz", R), ("pole", R), ("average", c_uint)]

    class Cell(ctypes.Structure):
        _fields_ = [(n, R) for n in ("m_lo", "m_hi", "b_lo", "b_hi", "K_lo", "K_hi", "B_lo", "B_hi", "k_lo",
                                     "k_hi")]

    class Scratch(ctypes.Structure):  # larger than zw_box_loop_scratch in both precisions
        _fields_ = [("bytes", ctypes.c_ubyte * 16384)]

    class Work(ctypes.Structure):
        _fields_ = [("cells", POINTER(Cell)), ("scratch", POINTER(Scratch)), ("capacity", ctypes.c_uint32),
                    ("max_evals", ctypes.c_uint32), ("rel_tol", R)]

    class Bound(ctypes.Structure):
        _fields_ = [("K_lower", R), ("K_upper", R), ("m_worst", R), ("b_worst", R),
                    ("evals", ctypes.c_uint32), ("converged", c_bool), ("k_worst", R)]

    P, W = POINTER, POINTER(zw.LoopWorkspace)
    sigs = {
        "zw_plant_enclose": [P(Plant), R, R],
        "zw_box_loop_work_init": [P(Work), P(Cell), ctypes.c_uint32, P(Scratch)],
        "zw_box_loop_k_max": [P(Box), P(DLSpec), W, R, P(Work), P(Bound)],
    }
    for f, args in sigs.items():
        fn = zw.symbol(f)
        fn.argtypes, fn.restype = args, c_int
    return Plant, Box, DLSpec, Cell, Work, Bound, Scratch


def _exact(x):
    return mpf(float(x))


def _ref_coeffs(d):
    """e, c1, c2, d12, s of the ideal plant at the exact delta d > 0 (literal, 90 digits)."""
    with mp.workdps(90):
        e = mp.exp(-d)
        c1 = 2 * (d - 1 + e) / d ** 2
        c2 = 2 * (1 - e - d * e) / d ** 2
        return e, c1, c2, c1 - c2, c1 + c2


def test_enclosure_contains_every_delta(zw):
    Plant = _types(zw)[0]
    rng = random.Random(16)
    worst = 0.0
    for case in range(120):
        lo = zw.r(10 ** rng.uniform(-8, 3))
        width = 10 ** rng.uniform(-15, 1.5) if case % 4 else 0.0
        hi = zw.r(lo * (1 + width))
        if case == 5:
            lo, hi = zw.r(2.5), zw.r(2.9)  # around the d12 peak
        p = Plant()
        st = zw.symbol("zw_plant_enclose")(byref(p), lo, hi)
        assert st == E["ZW_OK"], (lo, hi, zw.status_name(st))
        assert p.order == 2
        for k in range(61):
            d = _exact(lo) + (_exact(hi) - _exact(lo)) * k / 60
            e, c1, c2, d12, s = _ref_coeffs(d)
            want = {
                ("num", 0): c1, ("num", 1): c2,
                ("den", 0): mpf(2), ("den", 1): -2 * (1 + e), ("den", 2): 2 * e,
                ("den_s", 0): 4 * (1 + e), ("den_s", 1): 4 * (1 - e), ("den_s", 2): mpf(0),
                ("num_s", 0): d12, ("num_s", 1): s,
                ("den_w", 0): mpf(2), ("den_w", 1): 2 * (1 - e), ("den_w", 2): mpf(0),
            }
            for (name, i), v in want.items():
                mid = _exact(getattr(p, name)[i])
                err = _exact(getattr(p, name + "_err")[i])
                assert abs(v - mid) <= err, (name, i, lo, hi, float(d), float(v), float(mid), float(err))
                if hi == lo and abs(v) > mpf("1e-25"):  # relative: away from underflow (e at 1e3)
                    worst = max(worst, float(err / abs(v)))
    print(f"\n{zw.name}: point intervals: worst relative radius {worst:.2e} ({worst / zw.u:.0f} u)")
    assert worst < 200 * zw.u


def test_d12_peak_bracket():
    """d12 = 2 f / delta^2 rises while g = 4 - delta - (delta^2 + 3 delta + 4) e^-delta > 0
    and falls after (docs/box.md): g changes sign inside [2.6875, 2.6885], and the peak value
    is below the bound 0.2787032 used."""
    with mp.workdps(DPS):
        g = lambda d: 4 - d - (d * d + 3 * d + 4) * mp.exp(-d)  # noqa: E731
        assert g(mpf("2.6875")) > 0 > g(mpf("2.6885"))
        peak = mp.findroot(g, mpf("2.688"))
        d12 = lambda d: 2 * ((d + 2) * mp.exp(-d) + d - 2) / d ** 2  # noqa: E731
        assert d12(peak) < mpf("0.2787032")
        assert all(g(mpf(x) / 100) > 0 for x in range(1, 268))  # one sign change only (sampled)


# ---------------------------------------------------------------------------------------
# Box K_max against the reference over a grid of plants
# ---------------------------------------------------------------------------------------

CASES = [
    # (box m_lo, m_hi, b_lo, b_hi, T), spec, B
    ((1.0e-5, 1.4e-5, 2.0e-3, 2.4e-3, 0.02), dict(delay=1), 1e-4),
    ((2.0e-5, 9.0e-5, 2.0e-3, 2.4e-3, 0.02), dict(delay=1), 0.0),
    ((1.0e-5, 1.2e-5, 2.0e-3, 2.2e-3, 0.02), dict(delay=1, pole=0.6), 1e-4),
    ((0.10, 0.14, 0.5, 0.8, 0.001), dict(delay=2), 5e-3),
    ((1.0e-5, 1.2e-5, 2.0e-3, 2.2e-3, 0.02), dict(average=3), 1e-4),
    ((1.0e-5, 1.2e-5, 2.0e-3, 2.2e-3, 0.02), dict(tustin=True, delay=1), 1e-3),  # Tustin: stable beta > 0 for odd d
]


def _spec(DLSpec, zw, d):
    s = DLSpec()
    s.delay = d.get("delay", 0)
    s.differentiator = 1 if d.get("tustin") else 0
    if "pole" in d:
        s.filter, s.pole = 1, zw.r(d["pole"])
    elif "average" in d:
        s.filter, s.average = 2, d["average"]
    return s


@pytest.mark.parametrize("case", range(len(CASES)))
def test_box_k_max_never_above(zw, case):
    Plant, Box, DLSpec, Cell, Work, Bound, Scratch = _types(zw)
    (m_lo, m_hi, b_lo, b_hi, T), sd, B = CASES[case]
    box = Box(zw.r(m_lo), zw.r(m_hi), zw.r(b_lo), zw.r(b_hi), zw.r(T))
    cells = (Cell * 4096)()
    work, scratch = Work(), Scratch()
    assert zw.symbol("zw_box_loop_work_init")(byref(work), cells, 4096, byref(scratch)) == E["ZW_OK"]
    out = Bound()
    st = zw.symbol("zw_box_loop_k_max")(byref(box), byref(_spec(DLSpec, zw, sd)), byref(zw.ws), zw.r(B),
                                        byref(work), byref(out))
    assert st == E["ZW_OK"], zw.status_name(st)
    assert 0 < out.K_lower <= out.K_upper
    K = _exact(out.K_lower)
    least = None
    with mp.workdps(DPS):
        for i in range(7):
            for j in range(7):
                m = _exact(box.m_lo) + (_exact(box.m_hi) - _exact(box.m_lo)) * i / 6
                b = _exact(box.b_lo) + (_exact(box.b_hi) - _exact(box.b_lo)) * j / 6
                delta, alpha, beta = b * _exact(box.T) / m, K * _exact(box.T) ** 2 / m, _exact(B) * _exact(box.T) / m
                ref = RefLoop(delta, sd.get("pole", 0.0), delay=sd.get("delay", 0), tustin=sd.get("tustin", False),
                              average=sd.get("average"))
                for k in range(1, 13):  # every K in (0, K_lower]: sampled
                    assert ref.stable(alpha * k / 12, beta), (case, i, j, k)
                sup = ref.alpha_sup_above(alpha, beta, rel=mpf("1e-12")) * m / _exact(box.T) ** 2
                least = sup if least is None else min(least, sup)
    tight = float(K / least)
    print(f"\n{zw.name} case {case}: K_lower / grid min = {tight:.6f}, converged {out.converged}, evals {out.evals}")
    assert K <= least
    assert tight > (0.99 if zw.name == "float" else 0.995)
