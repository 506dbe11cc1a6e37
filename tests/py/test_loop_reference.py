# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The general loop (loop.h) against an independent mpmath reference (loop_reference.py).

(a) The C parts D, Na, Nb (z and bilinear) against det(zI - A) of a time-domain
    state-space model of the sampled loop at 80 digits, for every kind and combinations,
    including the C's own error bounds.
(b) Labelled points crowded at the boundary, 1 to 1e4 ulps on both sides, in alpha and in
    beta, over delta 2^-20 .. 1e3, a up to 0.999, d up to 8, both precisions: zero false
    "stable", every false "unstable" marked marginal and within the stated band.
(c) python-control's poles against zw_loop_spectral_radius away from the boundary.

ZW_LOOP_FULL=1 runs the bigger sweep (more plants, kinds and boundary points); the default
is a representative subset that keeps this file well under a minute.
"""
from __future__ import annotations

import math
import os

import control
import mpmath
import numpy as np
import pytest
from mpmath import mp, mpf

import loop_reference as lr
from conftest import load as cf_load

FULL = os.environ.get("ZW_LOOP_FULL") == "1"

# deltas exact in float, so both precisions share the cached reference parts
DELTAS = [2.0 ** -20, 0.5, 5.0, 1000.0]
SPECS = [
    dict(delay=0),
    dict(delay=1),
    dict(delay=3),
    dict(delay=8),
    dict(differentiator="tustin"),
    dict(delay=2, differentiator="tustin"),
    dict(delay=1, filter="lowpass", pole=0.3),
    dict(delay=1, filter="lowpass", pole=0.8),
    dict(delay=2, filter="lowpass", pole=0.999),
    dict(delay=1, differentiator="tustin", filter="lowpass", pole=0.8),
    dict(filter="average", average=1),
    dict(delay=1, filter="average", average=4),
    dict(delay=2, differentiator="tustin", filter="average", average=5),
    dict(delay=8, filter="average", average=16),
]
if FULL:
    SPECS += [dict(delay=d) for d in (2, 4, 5, 6, 7)] + [
        dict(delay=8, differentiator="tustin", filter="average", average=15),
        dict(delay=4, filter="average", average=9),
        dict(delay=8, differentiator="tustin", filter="lowpass", pole=0.999),
    ]


def spec_id(s):
    return "-".join(f"{k}{v}" for k, v in s.items())


def make_loop(zw, delta, spec):
    st, co = zw.coeffs(zw.r(delta))
    assert st == 0
    sp = dict(spec)
    if "pole" in sp:
        sp["pole"] = zw.r(sp["pole"])
    st, lp = zw.loop(co, zw.loop_spec(**sp))
    assert st == 0, zw.status_name(st)
    return lp


def ref_parts(zw, delta, spec):
    sp = dict(spec)
    if "pole" in sp:  # the C takes its stored pole as exact: so does the reference
        sp["pole"] = zw.r(sp["pole"])
    return lr.loop_parts(zw.r(delta), **sp)


def bilinear(p):
    """(1 - s)^n p((1 + s)/(1 - s)), highest power first, in mpmath."""
    n = len(p) - 1
    out = [mpf(0)] * (n + 1)
    for j, c in enumerate(p):  # c z^(n-j) -> c (1 + s)^(n-j) (1 - s)^j
        poly = [mpf(1)]
        for _ in range(n - j):
            poly = [a + b for a, b in zip(poly + [0], [0] + poly)]
        for _ in range(j):
            poly = [b - a for a, b in zip(poly + [0], [0] + poly)]
        for i, v in enumerate(poly):
            out[i] += c * v
    return out


# what the 80-digit reference leaves of an exact zero
REF_NOISE = mpf(10) ** -60

# ---- (a) the parts ------------------------------------------------------------------------


@pytest.mark.parametrize("spec", SPECS, ids=spec_id)
@pytest.mark.parametrize("delta", DELTAS)
def test_parts_match_state_space(zw, delta, spec):
    lp = make_loop(zw, delta, spec)
    n = lp.degree
    parts = ref_parts(zw, delta, spec)
    lead = mpf(lp.D[0])  # the C's leading coefficient is exact (2, 2n): scale the monic reference
    with mp.workdps(lr.DPS):
        for name, ref in zip(("D", "Na", "Nb"), parts):
            ref = [lead * v for v in ref[: n + 1]]
            # the state dimension may exceed the degree by exact roots at 0
            assert all(abs(v) < mpf(10) ** -50 for v in parts[0][n + 1:] + parts[1][n + 1:] + parts[2][n + 1:])
            got, err = getattr(lp, name), getattr(lp, name + "_err")
            for i in range(n + 1):
                assert abs(mpf(got[i]) - ref[i]) <= mpf(err[i]) + REF_NOISE, (name, i, got[i], ref[i], err[i])
            refs = bilinear(ref)
            got, err = getattr(lp, name + "s"), getattr(lp, name + "s_err")
            for i in range(n + 1):
                assert abs(mpf(got[i]) - refs[i]) <= mpf(err[i]) + REF_NOISE, (name + "s", i, got[i], refs[i], err[i])
            # and the bounds are not vacuous: within a few hundred ulps of the largest term
            scale = max(abs(v) for v in ref)
            assert max(getattr(lp, name + "_err")[: n + 1]) <= 1e3 * zw.u * float(scale) + 1e-300


@pytest.mark.parametrize("spec", [SPECS[2], SPECS[5], SPECS[8], SPECS[9], SPECS[12]], ids=spec_id)
def test_poly_annihilates_simulation(spec):
    """A direct simulation of the sampled loop (the state-space step, from a random state)
    satisfies the C polynomial's recurrence sum_j p_j x_(k+n-j) = 0: an independent check of
    the C polynomial that does not go through a determinant."""
    zw = cf_load("double")
    delta, alpha, beta = 0.5, zw.r(0.0625), zw.r(0.375)
    lp = make_loop(zw, delta, spec)
    st, p = zw.loop_poly(lp, alpha, beta)
    n = lp.degree
    with mp.workdps(50):
        a = lr.closed_loop_matrix(delta, alpha, beta, **spec)
        rng = np.random.default_rng(2)
        x = mpmath.matrix([mpf(float(v)) for v in rng.normal(size=a.rows)])
        ys = []
        for _ in range(a.rows + n + 6):
            ys.append(x[0])  # position
            x = a * x
        scale = max(abs(y) for y in ys)
        for k in range(a.rows - n, len(ys) - n):
            res = sum(mpf(p[j]) * ys[k + n - j] for j in range(n + 1))
            mag = sum(abs(mpf(p[j]) * ys[k + n - j]) for j in range(n + 1))
            assert abs(res) <= 64 * zw.u * mag + mpf(10) ** -40 * scale


def test_poly_is_affine_sum_of_parts(zw):
    """zw_loop_poly is D + alpha Na + beta Nb, against the reference at a generic point."""
    spec = dict(delay=2, differentiator="tustin", filter="lowpass", pole=0.3)
    lp = make_loop(zw, 0.5, spec)
    parts = ref_parts(zw, 0.5, spec)
    alpha, beta = zw.r(0.37), zw.r(-0.11)
    st, p = zw.loop_poly(lp, alpha, beta)
    assert st == 0 and len(p) == lp.degree + 1
    ref = lr.loop_poly(parts, alpha, beta, lp.degree)
    scale = sum(abs(v) for v in ref) * lp.D[0]
    for got, want in zip(p, ref):
        assert abs(got - float(want * lp.D[0])) <= 64 * zw.u * float(scale)


# ---- (b) labelled boundary points -----------------------------------------------------------

# Stated false-unstable band, in ulps of the stepped gain, by precision and loop degree
# (measured maxima of the ZW_LOOP_FULL sweep, rounded up to the next power of ten; beyond
# it a stable point is never called unstable).  The Routh array and the Schur-Cohn recursion
# decide most points (the band did not widen on any case of the full sweep when the latter was
# added, and narrowed on six); near the boundary the root-inclusion test takes over, whose band is the roots' own condition
# times the degree.  High degrees in float are the weak case: a moving average over many
# samples puts ~n roots near |z| = alpha^(1/n), and their product of distances makes the
# inclusion disks wide.
def band_ulps(precision, degree):
    if precision == "double":
        return 1e5 if degree <= 12 else 1e6
    return 1e5 if degree <= 12 else 1e7


# Points nearer the boundary than this (relative margin of the Schur-Cohn recursion at 60
# digits) are taken as on it, i.e. not stable (e.g. Tustin with an even-length average has
# a root at exactly -1 for every gain).
ON_BOUNDARY = mpf(10) ** -52


def label(parts, n, alpha, beta):
    stable, margin = lr.schur_stable(lr.loop_poly(parts, alpha, beta, n))
    return bool(stable and margin > ON_BOUNDARY)


def np_rho(parts_f, alpha, beta):
    d, na, nb = parts_f
    p = d + alpha * na + beta * nb
    return np.max(np.abs(np.roots(p)))


def boundary_points(zw, parts, n, rng, count):
    """Up to count (gain index, alpha_b, beta_b) with the boundary between the binary
    neighbours of the returned value in that gain (0: alpha, 1: beta), found from stable
    anchors by doubling along a ray and mp bisection."""
    parts_f = tuple(np.array([float(v) for v in part[: n + 1]]) for part in parts)
    alphas = np.geomspace(1e-7, 1e3, 41)
    betas = np.linspace(-2.0, 4.0, 25)
    anchors = [(a, b) for a in alphas for b in betas if np_rho(parts_f, a, b) < 1 - 1e-6]
    rng.shuffle(anchors)
    out = []
    for a, b in anchors:
        if len(out) >= count:
            break
        a, b = zw.r(a), zw.r(b)
        if not label(parts, n, a, b):
            continue
        gain = int(rng.integers(0, 2))
        direction = 1.0 if gain == 0 else float(rng.choice([-1.0, 1.0]))
        step = max(abs((a, b)[gain]), 1e-3)
        lo = mpf((a, b)[gain])
        hi = None
        for _ in range(60):
            cand = lo + direction * step
            pt = (cand, b) if gain == 0 else (a, cand)
            if not label(parts, n, *pt):
                hi = cand
                break
            lo = cand
            step *= 2
        if hi is None:
            continue
        for _ in range(200):
            mid = (lo + hi) / 2
            pt = (mid, b) if gain == 0 else (a, mid)
            if label(parts, n, *pt):
                lo = mid
            else:
                hi = mid
            if abs(hi - lo) <= mpf(10) ** -45 * max(abs(hi), mpf(10) ** -300):
                break
        if abs(lo) < 1e-20:
            continue  # a boundary at a gain of exactly 0 (z = 1: alpha; z = -1 with Tustin: beta)
            # is the gain's own sign; its ulps are subnormal (test_loop.c covers it)
        out.append((gain, float(lo), a, b))
    return out


STEPS = (1, 3, 10, 100, 1000, 10 ** 4, 10 ** 5, 10 ** 6, 10 ** 7)


def sweep(zw, delta, spec, rng, count):
    """Returns (false_stable, false_unstable_unmarked, worst false-unstable ulps, points)."""
    lp = make_loop(zw, delta, spec)
    n = lp.degree
    parts = ref_parts(zw, delta, spec)
    false_stable, unmarked, worst, total = [], [], 0, 0
    for gain, g_b, a, b in boundary_points(zw, parts, n, rng, count):
        if os.environ.get("ZW_LOOP_DEBUG"):
            print("boundary", gain, g_b, a, b)
        g0 = zw.np(g_b)
        for k in STEPS:
            for sign in (1, -1):
                g = float(g0)
                ulp = float(np.spacing(zw.np(abs(g0))))
                g = zw.r(g + sign * k * ulp)
                pt = (g, b) if gain == 0 else (a, g)
                truth = label(parts, n, *pt)
                st, v = zw.loop_check(lp, *pt)
                assert st == 0
                assert zw.loop_is_stable(lp, *pt) == (0, v.stable)  # the fast path agrees
                total += 1
                if v.stable and not truth:
                    false_stable.append(pt)
                if truth and not v.stable:
                    worst = max(worst, k)
                    if not v.marginal:
                        unmarked.append(pt)
    return false_stable, unmarked, worst, total


CASES = [(d, s) for d in DELTAS for s in SPECS] if FULL else [
    (DELTAS[0], SPECS[1]), (DELTAS[0], SPECS[8]), (DELTAS[1], SPECS[3]), (DELTAS[1], SPECS[5]),
    (DELTAS[1], SPECS[11]), (DELTAS[2], SPECS[0]), (DELTAS[2], SPECS[9]), (DELTAS[3], SPECS[2]),
    (DELTAS[3], SPECS[12]), (DELTAS[1], SPECS[13]),
]


@pytest.mark.parametrize("delta,spec", CASES, ids=[f"{d:g}-{spec_id(s)}" for d, s in CASES])
def test_boundary_labels(zw, delta, spec):
    rng = np.random.default_rng(abs(hash((delta, spec_id(spec), zw.name))) % 2 ** 32)
    lp = make_loop(zw, delta, spec)
    false_stable, unmarked, worst, total = sweep(zw, delta, spec, rng, 6 if FULL else 2)
    assert not false_stable, f"false stable: {false_stable}"
    assert not unmarked, f"unstable verdicts on stable points without marginal: {unmarked}"
    assert worst <= band_ulps(zw.name, lp.degree), f"false-unstable band {worst} ulps > stated"
    print(f"{zw.name} delta={delta:g} {spec_id(spec)} degree {lp.degree}: {total} points, "
          f"false-unstable band {worst} ulps")


def test_reference_labels_agree_with_polyroots():
    """The Schur-Cohn labels against mpmath.polyroots on points near and far from the boundary."""
    rng = np.random.default_rng(5)
    for spec in (SPECS[3], SPECS[9], SPECS[12]):
        parts = lr.loop_parts(0.5, **spec)
        n = len(parts[0]) - 1
        while n > 0 and all(abs(p[n]) < mpf(10) ** -50 for p in parts):
            n -= 1
        for _ in range(6):
            a, b = float(rng.uniform(1e-3, 2)), float(rng.uniform(-0.4, 2))
            rho, _ = lr.spectral_radius(lr.loop_poly(parts, a, b, n))
            if abs(rho - 1) > mpf(10) ** -30:
                assert label(parts, n, a, b) == (rho < 1)


# ---- (c) python-control ----------------------------------------------------------------------


def control_poles(delta, alpha, beta, spec):
    """Closed-loop poles from python-control: plant (ZOH of 1/(s^2 + delta s) in normalized
    time), z^-d, and the controller alpha + beta V(z) from its own definition."""
    plant = control.c2d(control.tf([1.0], [1.0, delta, 0.0]), 1.0, method="zoh")
    z = control.tf([1.0, 0.0], [1.0], 1.0)
    diff = (1 - z ** -1) if spec.get("differentiator", "backward") == "backward" else \
        2 * (z - 1) / (z + 1)
    filt = spec.get("filter", "none")
    if filt == "lowpass":
        a = spec["pole"]
        v = (1 - a) * z / (z - a) * diff
    elif filt == "average":
        n = spec["average"]
        v = sum((z ** -i for i in range(1, n)), control.tf([1.0], [1.0], 1.0)) * diff * (1.0 / n)
    else:
        v = diff
    ctrl = alpha + beta * v
    loop = plant * ctrl * (z ** -spec.get("delay", 0) if spec.get("delay", 0) else 1)
    closed = control.feedback(control.minreal(loop, verbose=False), 1)
    return closed.poles()


@pytest.mark.parametrize("spec", [SPECS[1], SPECS[4], SPECS[7], SPECS[9], SPECS[11], SPECS[12]],
                         ids=spec_id)
def test_spectral_radius_matches_python_control(zw, spec):
    rng = np.random.default_rng(11)
    delta = 0.5
    lp = make_loop(zw, delta, spec)
    checked = 0
    for _ in range(12):
        a, b = zw.r(rng.uniform(1e-3, 1.0)), zw.r(rng.uniform(-0.3, 1.5))
        poles = control_poles(delta, a, b, spec)
        rho_ref = max(abs(poles))
        if abs(rho_ref - 1) < 1e-3:
            continue  # near the boundary the two may disagree on which side
        st, rho, theta = zw.loop_spectral_radius(lp, a, b)
        assert st == 0
        assert rho == pytest.approx(rho_ref, rel=1e-3 if zw.name == "float" else 1e-6)
        st, v = zw.loop_check(lp, a, b)
        assert v.stable == (rho_ref < 1)
        checked += 1
    assert checked >= 6
