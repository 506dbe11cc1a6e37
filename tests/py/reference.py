# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Independent high-precision reference for the zwidth tests (mpmath, 60 significant digits).

Nothing here copies the C implementation.  Every quantity comes from its *definition*
(the paper's equations as restated in shared/notes/math.md), evaluated in mpmath with
enough working precision that the cancellations the C code has to engineer around do not
matter:

* coefficients e, c1, c2, d12 from the literal eqs (3), (4) at 60 + 3*log10(1/delta) digits
  (and from the Taylor series for delta < 1e-20, where even that would be wasteful);
* stability from the Jury conditions on p(z) (or p(r z)) evaluated on the *exact* binary
  inputs, with a rigorous margin/scale test and escalating precision (60, 150, 400, 1500
  digits): a condition whose margin still vanishes at 1500 digits is an exact identity (the
  point lies on the boundary), hence not strictly stable; p(1) = (c1 + c2) alpha is decided
  by the sign of alpha (an identity of the definitions, checked in test_region.py); the
  Jury reference itself is cross-checked against mpmath.polyroots in test_margin.py; a
  rigorous float64 pre-screen (stable_batch) settles points far from every boundary;
* spectral radius from mpmath.polyroots with extra precision;
* extremes from the paper's closed forms (19)-(32) at 60 digits (cross-checked against a
  direct numerical maximisation of min{f, L}), interval ends from the quadratic
  N(beta) - alpha D(beta) = 0 (cancellation-free root formula, extra digits for large delta);
* critical constants by root finding (findroot on the defining equations).

Binary inputs are converted exactly (mpf(float) is exact), and results are rounded to
float32/float64 by our own correctly-rounding routine (subnormals included) so that ulp
distances are exact ordinal distances.
"""
from __future__ import annotations

import functools
import math
import multiprocessing
import os
import struct
from collections import namedtuple

import mpmath
import numpy as np
from mpmath import mp, mpf

mp.dps = 60
DPS = 60

# ---------------------------------------------------------------------------------------
# Binary floating formats, exact rounding and ulp distances
# ---------------------------------------------------------------------------------------


class Fmt(namedtuple("Fmt", "name p emin_sub max np_type int_type bits")):
    """A binary format: p = significand bits (with the hidden one), emin_sub = exponent of
    the smallest subnormal, max = largest finite value."""

    @property
    def u(self):
        """Unit roundoff 2^-p."""
        return 2.0 ** -self.p

    @property
    def eps(self):
        """Machine epsilon 2^(1-p) (one ulp of 1)."""
        return 2.0 ** (1 - self.p)

    @property
    def tiny(self):
        """Smallest positive subnormal."""
        return math.ldexp(1.0, self.emin_sub)

    @property
    def min_normal(self):
        return math.ldexp(1.0, self.emin_sub + self.p - 1)


DOUBLE = Fmt("double", 53, -1074, float.fromhex("0x1.fffffffffffffp+1023"), np.float64, np.int64, 64)
FLOAT = Fmt("float", 24, -149, float.fromhex("0x1.fffffep+127"), np.float32, np.int32, 32)
FORMATS = {"double": DOUBLE, "float": FLOAT}


def exact(x):
    """Exact mpf of a binary float (Python float, numpy scalar) or pass an mpf through."""
    if isinstance(x, mpf):
        return x
    return mpf(float(x))


def round_to(x, fmt):
    """Round an mpf (or anything mpf() accepts) to the nearest value of fmt, ties to even,
    with gradual underflow and overflow to +-inf.  Returns a Python float holding that value
    exactly (float32 values are exact in a Python float)."""
    x = mpf(x)
    if mpmath.isnan(x):
        return math.nan
    if mpmath.isinf(x):
        return float(x)
    if x == 0:
        return 0.0
    _, E = mpmath.frexp(x)  # x = m 2^E, 1/2 <= |m| < 1
    qe = max(E - fmt.p, fmt.emin_sub)  # exponent of the quantum (ulp) at x
    n = mpmath.ldexp(x, -qe)  # exact scaling
    fl = int(mpmath.floor(n))
    frac = n - fl
    if frac > 0.5 or (frac == 0.5 and fl % 2 == 1):
        fl += 1
    try:
        v = math.ldexp(fl, qe)
    except OverflowError:
        return math.copysign(math.inf, fl)
    if abs(v) > fmt.max:
        return math.copysign(math.inf, v)
    return v


def ordinal(x, fmt):
    """Integer position of the fmt value x on the line of fmt values (+0 and -0 both 0)."""
    if fmt.p == 53:
        i = struct.unpack("<q", struct.pack("<d", float(x)))[0]
        mask = (1 << 63) - 1
    else:
        i = struct.unpack("<i", struct.pack("<f", float(x)))[0]
        mask = (1 << 31) - 1
    return i if i >= 0 else -(i & mask)


def from_ordinal(k, fmt):
    """Inverse of ordinal()."""
    mag = abs(int(k))
    if fmt.p == 53:
        v = struct.unpack("<d", struct.pack("<Q", mag))[0]
    else:
        v = struct.unpack("<f", struct.pack("<I", mag))[0]
    return -v if k < 0 else v


def step(x, k, fmt):
    """x moved by k ulps (k may be negative); the value k places away on the fmt line."""
    return from_ordinal(ordinal(x, fmt) + int(k), fmt)


def ulp_distance(computed, ref, fmt):
    """Ordinal distance between a computed fmt value and the exact reference rounded to fmt.
    NaN against non-NaN is infinitely far."""
    c = float(computed)
    r = round_to(ref, fmt)
    if math.isnan(c) or math.isnan(r):
        return 0 if (math.isnan(c) and math.isnan(r)) else math.inf
    return abs(ordinal(c, fmt) - ordinal(r, fmt))


def ulp_of(x, fmt):
    """Spacing of fmt values at |x| (the quantum of x's binade), as a Python float."""
    x = abs(float(x))
    if x == 0 or x < fmt.min_normal:
        return fmt.tiny
    _, E = math.frexp(x)
    return math.ldexp(1.0, E - fmt.p)


def np_ordinal(a, fmt):
    """Vectorised ordinal() for a numpy array already of fmt's dtype."""
    i = np.asarray(a, dtype=fmt.np_type).view(fmt.int_type).astype(np.int64)
    mask = (1 << (fmt.bits - 1)) - 1
    return np.where(i >= 0, i, -(i & mask))


def np_from_ordinal(k, fmt):
    """Vectorised from_ordinal(); returns an array of fmt's dtype."""
    k = np.asarray(k, dtype=np.int64)
    mag = np.abs(k)
    sign = np.where(k < 0, np.int64(1) << (fmt.bits - 1), 0)
    bits = (mag | sign)
    if fmt.bits == 32:
        return bits.astype(np.uint32).view(np.float32)
    return bits.astype(np.uint64).view(np.float64)


def np_step(a, k, fmt):
    """Vectorised step(): a moved by k ulps (k scalar or array)."""
    return np_from_ordinal(np_ordinal(a, fmt) + k, fmt)


# ---------------------------------------------------------------------------------------
# Coefficient functions, eqs (3), (4)
# ---------------------------------------------------------------------------------------

RefCoeffs = namedtuple("RefCoeffs", "delta e c1 c2 d12 s g h")
RefCoeffs.__doc__ = """Exact coefficients at delta: s = c1 + c2, g = c1 / s, h = 2 / c2."""

_SERIES_BELOW = mpf("1e-20")


def _dps(dps):
    return max(DPS, mp.dps) if dps is None else dps


def _key(delta):
    return delta if isinstance(delta, mpf) else float(delta)


@functools.lru_cache(maxsize=200_000)
def _coeffs_cached(key, dps):
    with mp.workdps(dps + 10):
        d = mpf(key)
        if mpmath.isnan(d) or d < 0:
            raise ValueError("delta must be >= 0")
        if mpmath.isinf(d):
            z = mpf(0)
            return RefCoeffs(d, z, z, z, z, z, mpf(1), mpf("inf"))
        if d == 0:
            one = mpf(1)
            return RefCoeffs(d, one, one, one, mpf(0), mpf(2), mpf("0.5"), mpf(2))
        if d < _SERIES_BELOW:
            # Taylor series straight from the definitions (math.md); 8 terms are far more
            # than enough: the n-th term is below delta^n < 1e-160 for n >= 8.
            e = mp.exp(-d)
            c1 = 2 * mp.fsum((-d) ** n / mp.factorial(n + 2) for n in range(10))
            c2 = 2 * mp.fsum((-1) ** k * (k - 1) * d ** (k - 2) / mp.factorial(k) for k in range(2, 12))
            d12 = 2 * mp.fsum((-1) ** k * (2 - k) * d ** (k - 2) / mp.factorial(k) for k in range(3, 13))
        else:
            # Literal definitions; c1 - c2 and the numerators lose about 3 log10(1/delta)
            # digits to cancellation for small delta, so we add that many.
            extra = 10 + (int(3 * -mpmath.log10(d)) if d < 1 else 0)
            with mp.workdps(dps + 10 + extra):
                e = mp.exp(-d)
                c1 = 2 * (d - 1 + e) / (d * d)
                c2 = 2 * (1 - e - d * e) / (d * d)
                d12 = c1 - c2
        s = c1 + c2
        g = c1 / s
        h = 2 / c2
    return RefCoeffs(d, e, c1, c2, d12, s, g, h)


def p1_identity_gap(delta, alpha, beta):
    """|p(1) - (c1 + c2) alpha| / scale from the literal polynomial (reference self-check)."""
    (p0, p1, p2, p3), (s0, s1, s2, s3) = char_poly(delta, alpha, beta)
    co = coeffs(delta)
    return abs(p0 + p1 + p2 + p3 - co.s * exact(alpha)) / (s0 + s1 + s2 + s3)


def coeffs(delta, dps=None):
    """Exact coefficient values (as mpf accurate to ~dps digits, default: the current
    working precision, at least 60) at the exact delta."""
    return _coeffs_cached(_key(delta), _dps(dps))


def coeffs_literal_series_gap(delta, dps=None):
    """Relative difference between the series and the (extra-precision) literal evaluation
    at a delta where both apply: a self-check of the reference."""
    dps = _dps(dps)
    d = exact(delta)
    with mp.workdps(dps + 10):
        e = mp.exp(-d)
        ser = (2 * mp.fsum((-d) ** n / mp.factorial(n + 2) for n in range(40)),
               2 * mp.fsum((-1) ** k * (k - 1) * d ** (k - 2) / mp.factorial(k) for k in range(2, 42)),
               2 * mp.fsum((-1) ** k * (2 - k) * d ** (k - 2) / mp.factorial(k) for k in range(3, 43)))
    lit = coeffs(d, dps)
    return max(abs(a - b) / abs(b) for a, b in zip(ser, (lit.c1, lit.c2, lit.d12)))


# ---------------------------------------------------------------------------------------
# Characteristic polynomial and the Jury conditions, eqs (7)-(9)
# ---------------------------------------------------------------------------------------


def char_poly(delta, alpha, beta, dps=None):
    """Coefficients [2, a1, a2, a3] of p(z) (exact inputs), and matching magnitude scales
    (sum of the absolute values of the terms) for error bounds."""
    dps = _dps(dps)
    co = coeffs(delta, dps)
    with mp.workdps(dps + 10):
        a, b = exact(alpha), exact(beta)
        a1 = co.c1 * (a + b) - 2 * (1 + co.e)
        a2 = co.c2 * a + (co.c2 - co.c1) * b + 2 * co.e
        a3 = -co.c2 * b
        s1 = co.c1 * (abs(a) + abs(b)) + 2 * (1 + co.e)
        s2 = co.c2 * abs(a) + abs(co.c2 - co.c1) * abs(b) + 2 * co.e
        s3 = co.c2 * abs(b)
    return (mpf(2), a1, a2, a3), (mpf(2), s1, s2, s3)


def jury_margins(delta, alpha, beta, r=1, dps=None):
    """The four Jury margins of p(r z) (each must be > 0 for all roots |z| < r) with a
    magnitude scale each: list of (margin, scale)."""
    dps = _dps(dps)
    (p0, p1, p2, p3), (s0, s1, s2, s3) = char_poly(delta, alpha, beta, dps)
    with mp.workdps(dps + 10):
        r = exact(r)
        b0, b1, b2, b3 = p0 * r ** 3, p1 * r ** 2, p2 * r, p3
        S0, S1, S2, S3 = s0 * r ** 3, s1 * r ** 2, s2 * r, s3
        S = S0 + S1 + S2 + S3
        if r == 1:
            # p(1) = (c1 + c2) alpha identically (the terms in beta and e cancel, see
            # p1_identity_gap): use the product, whose sign is exact even when alpha is
            # subnormal and delta huge (p(1) ~ 1e-620 relative to its terms).
            co = coeffs(delta, dps)
            p1 = co.s * exact(alpha)
        else:
            p1 = b0 + b1 + b2 + b3
        return [
            (p1, S),                                      # P(1) > 0
            (b0 - b1 + b2 - b3, S),                       # -P(-1) > 0
            (b0 - abs(b3), S0 + S3),                      # |b3| < b0
            (b0 * b0 - b3 * b3 - abs(b0 * b2 - b3 * b1),  # b0^2 - b3^2 > |b0 b2 - b3 b1|
             S0 * S0 + S3 * S3 + S0 * S2 + S3 * S1),
        ]


_ESCALATE = (60, 150, 400, 1500)


def roots_within(delta, alpha, beta, r=1):
    """True iff every root of p(z) at the exact inputs satisfies |z| < r (strictly).

    Decided by the Jury conditions on p(r z): at each precision a margin counts only if it
    exceeds 1e-(dps-12) times its scale (far above the evaluation error); otherwise the
    precision is raised.  Margins that vanish at 1500 digits are exact zeros (products of
    binary inputs and the transcendental coefficients cannot come closer to zero than about
    1e-1000 of their scale otherwise; the zeros are identities such as beta = 2 at
    delta = 0), so the point is not strictly inside.  p(1) = (c1 + c2) alpha is decided by
    the sign of alpha."""
    if r == 1 and not exact(alpha) > 0:
        return False  # p(1) = (c1 + c2) alpha <= 0: a root at or beyond z = 1
    for dps in _ESCALATE:
        tol = mpf(10) ** (-(dps - 12))
        undecided = False
        for m, S in jury_margins(delta, alpha, beta, r, dps):
            if m <= -tol * S:
                return False
            if m < tol * S:
                undecided = True
        if not undecided:
            return True
    return False


def stable(delta, alpha, beta):
    """The true verdict: all poles strictly inside the unit circle."""
    return roots_within(delta, alpha, beta, 1)


def jury_relative_margin(delta, alpha, beta, r=1):
    """min over the Jury conditions of margin / scale (negative: violated).  A measure of how
    far the decision is from its rounding band."""
    return min(m / S for m, S in jury_margins(delta, alpha, beta, r))


def spectral_radius(delta, alpha, beta, dps=None):
    """(rho, roots) of p(z) at the exact inputs from mpmath.polyroots."""
    dps = _dps(dps)
    p, _ = char_poly(delta, alpha, beta, dps)
    with mp.workdps(dps):
        for steps in (200, 2000):
            try:
                roots = mp.polyroots(list(p), maxsteps=steps, extraprec=3 * dps)
                break
            except mpmath.libmp.NoConvergence:
                continue
        else:
            raise RuntimeError("polyroots did not converge")
        rho = max(abs(z) for z in roots)
    return rho, roots


def radius_condition(delta, alpha, beta, roots):
    """Relative condition number of rho w.r.t. relative perturbations of the coefficients
    of p (and hence of c1, c2, e): sum |p_k| |z|^(3-k) / (|z| |p'(z)|) at the largest root.
    Returns (kappa, sep) where sep is the distance of that root to the nearest other root
    (relative to max(1, |z|))."""
    p, _ = char_poly(delta, alpha, beta)
    z = max(roots, key=abs)
    num = sum(abs(pk) * abs(z) ** (3 - k) for k, pk in enumerate(p))
    dp = 3 * p[0] * z ** 2 + 2 * p[1] * z + p[2]
    others = [w for w in roots if w is not z]
    sep = min(abs(z - w) for w in others) / max(1, abs(z))
    if abs(z) == 0 or dp == 0:
        return mpf("inf"), sep
    return num / (abs(z) * abs(dp)), sep


# ---------------------------------------------------------------------------------------
# The region's boundary curves, eq (10)
# ---------------------------------------------------------------------------------------


def f_hyperbola(delta, beta, dps=None):
    """f(beta) from the expanded eq (10), evaluated with 40 + log10(delta) extra digits (and
    coefficients to match) so that the cancellations of its numerator near beta = -delta and
    of c1 beta + 2 for large delta are harmless.  (The factored form of
    math.md is only used to cross-check this in the tests.)"""
    dps = _dps(dps)
    # c1 beta + 2 cancels like 1/delta next to beta = -delta for large delta: add those digits
    d = exact(delta)
    dps += 40 + (int(mpmath.log10(d)) if d > 1 else 0)
    co = coeffs(delta, dps)
    with mp.workdps(dps):
        b = exact(beta)
        num = -(co.c1 + co.c2) * co.c2 * b * b + 2 * (co.c1 + co.e * co.c2) * b + 4 * (1 - co.e)
        den = (co.c1 * b + 2) * co.c2
        return num / den


def f_hyperbola_factored(delta, beta, dps=None):
    """f(beta) from the factored form (math.md), for the cross-check only."""
    dps = _dps(dps)
    co = coeffs(delta, dps)
    with mp.workdps(dps + 10):
        b = exact(beta)
        return co.s * (b + co.delta) * (2 - co.c2 * b) / ((co.c1 * b + 2) * co.c2)


def line(delta, beta, dps=None):
    """L(beta) = 4 (1 + e) / d12 - 2 beta (+inf at delta = 0)."""
    dps = _dps(dps)
    co = coeffs(delta, dps)
    if co.d12 == 0:
        return mpf("inf")
    with mp.workdps(dps + 10):
        return 4 * (1 + co.e) / co.d12 - 2 * exact(beta)


def line_end(delta, dps=None):
    """beta where the line meets alpha = 0: 2 (1 + e) / d12 (+inf at delta = 0)."""
    dps = _dps(dps)
    co = coeffs(delta, dps)
    if co.d12 == 0:
        return mpf("inf")
    return 2 * (1 + co.e) / co.d12


def constraint_truth(delta, alpha, beta):
    """Which constraints of eq (10) the exact point violates: dict name -> True (violated),
    False (satisfied) or None (not defined there).

    DAMPING beta <= -delta; STIFFNESS alpha <= 0; HYPERBOLA (only for beta > -delta, where
    f is the boundary) beta >= 2/c2 or alpha >= f(beta); LINE alpha >= L(beta) (never at
    delta = 0)."""
    co = coeffs(delta)
    d, a, b = co.delta, exact(alpha), exact(beta)
    out = {"DAMPING": b <= -d, "STIFFNESS": a <= 0}
    if b > -d:
        out["HYPERBOLA"] = bool(b >= co.h or a >= f_hyperbola(delta, beta))
    else:
        out["HYPERBOLA"] = None
    if co.d12 == 0:
        out["LINE"] = False
    else:
        with mp.workdps(DPS + 10):
            out["LINE"] = bool(co.d12 * (a / 2 + b) >= 2 * (1 + co.e))
    return out


# ---------------------------------------------------------------------------------------
# Extremes, eqs (19)-(32)
# ---------------------------------------------------------------------------------------


def hyperbola_top(delta, dps=None):
    """(alpha1, beta1), eqs (19), (20).  beta1's factor 1 - sqrt(1 + y), y = e c1/c2, is
    taken as -y / (1 + sqrt(1 + y)) so that it keeps its digits for large delta (where y is
    ~ e^-delta delta and 60 digits would not be enough)."""
    dps = _dps(dps)
    co = coeffs(delta, dps)
    with mp.workdps(dps + 20):
        e, c1, c2 = co.e, co.c1, co.c2
        alpha1 = 2 * (c1 + c2 - mp.sqrt(c2 * (e * c1 + c2))) ** 2 / (c1 ** 2 * c2)
        y = e * c1 / c2
        beta1 = (2 / c1) * y / (1 + mp.sqrt(1 + y))
    return alpha1, beta1


def corner(delta, dps=None):
    """(alpha2, beta2), eqs (21), (22): where the line meets the hyperbola (delta > delta0)."""
    dps = _dps(dps)
    co = coeffs(delta, dps)
    with mp.workdps(dps + 20):
        e, c1, c2, d12 = co.e, co.c1, co.c2, co.d12
        alpha2 = 8 * (c1 - (2 + e) * c2) / d12 ** 2
        beta2 = 2 * ((3 + e) * c2 - (1 - e) * c1) / d12 ** 2
    return alpha2, beta2


def extremes(delta, dps=None):
    """dict with alpha_mmax, beta_at, at_corner, alpha_p_max, beta_mmax (eqs (24)-(32))."""
    dps = _dps(dps)
    co = coeffs(delta, dps)
    k = constants()
    a1, b1 = hyperbola_top(delta, dps)
    at_corner = co.delta > k["delta1"]
    if at_corner:
        am, bm = corner(delta, dps)
    else:
        am, bm = a1, b1
    with mp.workdps(dps + 10):
        ap = -2 * mp.expm1(-co.delta) / co.c2   # 1 - e would cancel to 0 for tiny delta
        bmax = 2 / co.c2
        if co.d12 != 0:
            ap = min(ap, 4 * (1 + co.e) / co.d12)
            bmax = min(bmax, 2 * (1 + co.e) / co.d12)
    return dict(alpha_mmax=am, beta_at=bm, at_corner=at_corner, alpha_p_max=ap, beta_mmax=bmax)


def alpha_max_at(delta, beta):
    """sup alpha stable at this beta: min{f, L} on -delta < beta < beta_mmax, else 0; with
    the name of the active curve ('hyperbola', 'line' or None)."""
    co = coeffs(delta)
    b = exact(beta)
    bmax = extremes(delta)["beta_mmax"]
    if not (-co.delta < b < bmax):
        return mpf(0), None
    f = f_hyperbola(delta, beta)
    L = line(delta, beta)
    return (f, "hyperbola") if f <= L else (L, "line")


def beta_interval(delta, alpha, dps=None):
    """(lo, hi, nonempty) of beta stable at this alpha.  The hyperbola part solves the
    quadratic N(beta) - alpha D(beta) = 0 (N, D numerator and denominator of f in eq (10));
    the line gives beta < (L-intercept - alpha) / 2."""
    dps = _dps(dps)
    d = exact(delta)
    dps += 30 + (int(mpmath.log10(d)) if d > 1 else 0)  # as in f_hyperbola
    co = coeffs(delta, dps)
    a = exact(alpha)
    if a <= 0:
        return mpf(0), mpf(0), False
    with mp.workdps(dps):
        e, c1, c2 = co.e, co.c1, co.c2
        q2 = -(c1 + c2) * c2
        q1 = 2 * (c1 + e * c2) - a * c1 * c2
        q0 = 4 * (1 - e) - 2 * a * c2
        disc = q1 * q1 - 4 * q2 * q0
        if disc <= 0:
            return mpf(0), mpf(0), False
        q = -(q1 + mpmath.sign(q1) * mp.sqrt(disc)) / 2  # the two roots without cancellation
        lo, hi = sorted((q / q2, q0 / q))
        if co.d12 != 0:
            hi = min(hi, 2 * (1 + e) / co.d12 - a / 2)
    if not lo < hi:
        return mpf(0), mpf(0), False
    return lo, hi, True


def alpha_max_numeric(delta, dps=40, iters=260):
    """max over beta of min{f, L} by golden-section search (no closed form used): a
    cross-check of the closed forms.  Returns (alpha, beta)."""
    co = coeffs(delta)
    with mp.workdps(dps):
        lo = -co.delta
        hi = extremes(delta)["beta_mmax"]

        def F(b):
            v = f_hyperbola(delta, b)
            if co.d12 != 0:
                v = min(v, line(delta, b))
            return v

        phi = (mp.sqrt(5) - 1) / 2
        x1, x2 = hi - phi * (hi - lo), lo + phi * (hi - lo)
        f1, f2 = F(x1), F(x2)
        for _ in range(iters):
            if f1 < f2:
                lo, x1, f1 = x1, x2, f2
                x2 = lo + phi * (hi - lo)
                f2 = F(x2)
            else:
                hi, x2, f2 = x2, x1, f1
                x1 = hi - phi * (hi - lo)
                f1 = F(x1)
        b = (lo + hi) / 2
        return F(b), b


# ---------------------------------------------------------------------------------------
# Critical constants by root finding
# ---------------------------------------------------------------------------------------


def _alpha1(d):
    return hyperbola_top(d)[0]


def _beta1(d):
    return hyperbola_top(d)[1]


def _alpha2(d):
    return corner(d)[0]


def _beta2(d):
    return corner(d)[1]


@functools.lru_cache(maxsize=1)
def constants():
    """The critical NPDs and values, each from its defining equation (solved at 60 digits,
    accurate to well over 40):

    delta0: (1 + d)(1 + e^-d)^2 = 4              delta1: beta1(d) = beta2(d)
    delta2: beta2(d) = 0                           deltaK1/K2: d/dd [alpha_mmax(d)/d] = 0
    deltaB: d/dd [beta_mmax(d)/d] = 0 (beta_mmax = 2/c2 there)
    deltaKM < deltaK1: alpha_mmax(d)/d = alpha_mmax(deltaK2)/deltaK2.
    deltaBb > delta0: d/dd [2 (1 + e) / d12] = 0 (local min of beta_mmax itself)."""
    with mp.workdps(DPS):
        k = {}
        k["delta0"] = mp.findroot(lambda d: (1 + d) * (1 + mp.exp(-d)) ** 2 - 4, mpf("2.3"))
        k["delta1"] = mp.findroot(lambda d: _beta1(d) - _beta2(d), mpf("3.66"))
        k["delta2"] = mp.findroot(_beta2, mpf("3.72"))
        k["deltaK1"] = mp.findroot(lambda d: mp.diff(lambda x: _alpha1(x) / x, d), mpf("1.04"))
        k["deltaK2"] = mp.findroot(lambda d: mp.diff(lambda x: _alpha2(x) / x, d), mpf("5.77"))
        k["deltaB"] = mp.findroot(lambda d: mp.diff(lambda x: 2 / coeffs(x).c2 / x, d), mpf("1.79"))
        k["kmax_local_max"] = _alpha2(k["deltaK2"]) / k["deltaK2"]
        k["kmax_local_min"] = _alpha1(k["deltaK1"]) / k["deltaK1"]
        k["deltaKM"] = mp.findroot(lambda d: _alpha1(d) / d - k["kmax_local_max"], mpf("0.226"))
        # not in the header: beta_mmax = 2 (1 + e) / d12 falls on (delta0, deltaBb) and rises
        # beyond, so B_mmax against b (m, T fixed) turns there too.
        k["deltaBb"] = mp.findroot(lambda d: mp.diff(line_end, d), mpf("3.2"))
    return k


# ---------------------------------------------------------------------------------------
# Real units, Section IV
# ---------------------------------------------------------------------------------------


def normalize(m, b, T, K=0, B=0, dps=None):
    """(delta, alpha, beta) from the exact real inputs: b T / m, K T^2 / m, B T / m."""
    dps = _dps(dps)
    with mp.workdps(dps + 10):
        m, b, T, K, B = (exact(x) for x in (m, b, T, K, B))
        return b * T / m, K * T * T / m, B * T / m


def k_mmax(m, b, T):
    """K_mmax = (m / T^2) alpha_mmax(b T / m) at the exact real inputs."""
    d, _, _ = normalize(m, b, T)
    return exact(m) / exact(T) ** 2 * extremes(d)["alpha_mmax"]


def b_mmax(m, b, T):
    """B_mmax = (m / T) beta_mmax(b T / m) at the exact real inputs."""
    d, _, _ = normalize(m, b, T)
    return exact(m) / exact(T) * extremes(d)["beta_mmax"]


# ---------------------------------------------------------------------------------------
# Batch verdicts: a rigorous float64 pre-screen in front of the mpmath Jury test
# ---------------------------------------------------------------------------------------

JOBS = int(os.environ.get("ZW_TEST_JOBS", os.cpu_count() or 1))


def pmap(func, items, min_parallel=400):
    """map(func, items) over JOBS forked worker processes when there is enough work (the
    reference is pure Python/mpmath; the workers inherit the warm caches)."""
    items = list(items)
    if JOBS <= 1 or len(items) < min_parallel:
        return [func(x) for x in items]
    with multiprocessing.get_context("fork").Pool(JOBS) as pool:
        return pool.map(func, items, chunksize=max(1, len(items) // (8 * JOBS)))


def _stable_tuple(t):
    return stable(*t)


PRESCREEN_SAFETY = 64  # the float64 evaluation errs by < ~12 u * scale; we demand 64 u * scale


def stable_batch(deltas, alphas, betas, stats=None):
    """Vectorised stable() for arrays of binary inputs.

    The Jury margins are first evaluated in float64 with the *reference* coefficients
    (60-digit values rounded to float64, relative error <= u).  A Wilkinson-style count of
    the roundings bounds the float64 error of each margin by ~12 u times the margin's scale
    (sum of the magnitudes of its terms, >= 2), so any margin beyond 64 u * scale has a
    certain sign.  Points with every margin clearly positive are stable, with any clearly
    negative unstable; everything else (points within ~1e-14 of a boundary, huge delta or
    huge gains where float64 could over/underflow) goes to the mpmath test stable().
    `stats`, if a dict, receives the count of mpmath evaluations."""
    d = np.asarray(deltas, dtype=np.float64)
    a = np.asarray(alphas, dtype=np.float64)
    b = np.asarray(betas, dtype=np.float64)
    n = len(d)
    out = np.zeros(n, dtype=bool)
    undecided = np.ones(n, dtype=bool)
    uniq, inv = np.unique(d, return_inverse=True)
    cf = np.array([[float(getattr(coeffs(x), f)) for f in ("e", "c1", "c2")] for x in uniq.tolist()])
    e, c1, c2 = cf[inv, 0], cf[inv, 1], cf[inv, 2]
    ok = (d <= 1e12) & (np.abs(a) <= 1e100) & (np.abs(b) <= 1e100)
    with np.errstate(all="ignore"):
        a1 = c1 * (a + b) - 2 * (1 + e)
        a2 = c2 * a + (c2 - c1) * b + 2 * e
        a3 = -c2 * b
        s1 = c1 * (np.abs(a) + np.abs(b)) + 2 * (1 + e)
        s2 = c2 * np.abs(a) + (c1 - c2) * np.abs(b) + 2 * e
        s3 = c2 * np.abs(b)
        S = 2 + s1 + s2 + s3
        J = [(np.where(a > 0, 1.0, -1.0), 1.0),  # p(1) = (c1 + c2) alpha: the sign of alpha
             (2 - a1 + a2 - a3, S), (2 - np.abs(a3), 2 + s3),
             (4 - a3 * a3 - np.abs(2 * a2 - a3 * a1), 4 + s3 * s3 + 2 * s2 + s3 * s1)]
        tol = PRESCREEN_SAFETY * DOUBLE.u
        pos = np.ones(n, dtype=bool)
        neg = np.zeros(n, dtype=bool)
        for m, s in J:
            good = np.isfinite(m) & np.isfinite(s)
            ok &= good
            pos &= m > tol * s
            neg |= m < -tol * s
    out[ok & pos] = True
    undecided = ok & ~pos & ~neg | ~ok
    idx = np.nonzero(undecided)[0]
    out[idx] = pmap(_stable_tuple, list(zip(d[idx].tolist(), a[idx].tolist(), b[idx].tolist())))
    if stats is not None:
        stats["mpmath"] = stats.get("mpmath", 0) + len(idx)
        stats["total"] = stats.get("total", 0) + n
    return out
