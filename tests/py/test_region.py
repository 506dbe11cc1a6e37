# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zw_check and the other regions against the true verdict (region.h).

The data set: >= 100k points (delta, alpha, beta) per precision, over ~330 deltas (0, tiny,
subnormal, 1e-3 .. 1, densely around delta0 .. delta2 and the other critical deltas +- a few
ulps, up to 1e6, and a few huge ones: 1e100, 1e300 in double, 1e19, 1e30 in float).  Half
of the points are spread over a box around the region; the other half are crowded within
1e-9 relative (or 0..4 ulps) of a boundary: the hyperbola alpha = f(beta), the line
alpha = L(beta), beta = -delta, alpha = 0, and the right end (beta = 2/c2 or the line's
alpha = 0 end).

True verdict: the Jury conditions on p(z) at the exact binary inputs (reference.stable,
escalating 60/150/400 digits), behind a rigorous float64 pre-screen that only settles points
whose every Jury margin is > 64 u times its scale away from zero
(reference.stable_batch; the pre-screen is cross-checked against mpmath below, and the Jury
reference against mpmath.polyroots in test_margin.py).

Proves: zero unstable points reported stable (both precisions); every stable point reported
unstable is marginal and lies within BAND ulps (in alpha and beta) of a truly unstable
point; stable verdicts are clean (not marginal, nothing violated); for clearly unstable
points `deciding` and `violated` name exactly the truly violated constraints; the legacy
region is right below delta0 and wrong above it (paper Fig. 3, Fig. 19); the passivity,
delta = 0, delta -> inf and small-delta regions are safe for their own formulas; the
passivity region implies stability; zw_check_proportional agrees with beta = 0.
"""
import ctypes
import math
import time
from fractions import Fraction

import numpy as np
import pytest
from mpmath import mp, mpf

import reference as ref
from conftest import E

BAND = 32  # ulps of alpha and beta (measured worst: 16 double, 6 float; the brief allows 64)
N_POINTS = 100_000
LADDER = tuple(k for k in (1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64) if k <= BAND)

BOUNDS = {"DAMPING": E["ZW_BOUND_DAMPING"], "STIFFNESS": E["ZW_BOUND_STIFFNESS"],
          "HYPERBOLA": E["ZW_BOUND_HYPERBOLA"], "LINE": E["ZW_BOUND_LINE"]}


# ---------------------------------------------------------------------------------------
# Data set
# ---------------------------------------------------------------------------------------


def dataset_deltas(fmt, rng):
    """~330 deltas of this precision: the spread math.md asks for."""
    k = ref.constants()
    rnd = lambda x: ref.round_to(x, fmt)  # noqa: E731
    if fmt.p == 53:
        tiny = [0.0, fmt.tiny, 1e-310, 1e-300, 1e-200, 1e-100, 1e-30, 1e-20, 1e-16, 1e-12, 1e-8, 1e-6, 1e-4]
        huge = [1e8, 1e12, 1e100, 1e300]
    else:
        tiny = [0.0, fmt.tiny, 1e-40, 1e-38, 1e-30, 1e-20, 1e-12, 1e-8, 1e-6, 1e-4]
        huge = [1e8, 1e12, 1e19, 1e30]
    ds = tiny + huge
    ds += list(10 ** rng.uniform(-3, 0, 60)) + list(rng.uniform(1, 2, 20)) + list(rng.uniform(2, 4, 110))
    ds += list(10 ** rng.uniform(math.log10(4), 6, 80))
    for c in ("delta0", "delta1", "delta2", "deltaK1", "deltaK2", "deltaB"):
        ds += [ref.step(rnd(k[c]), j, fmt) for j in (-2, -1, 0, 1, 2)]
    ds += [2.0, ref.step(2.0, -1, fmt), ref.step(2.0, 1, fmt), 5.122]
    return sorted(set(rnd(x) for x in ds))


class _Gen:
    """Point generator for one delta (reference values from mpmath, rounded to fmt)."""

    def __init__(self, fmt, delta, rng):
        self.fmt, self.d, self.rng = fmt, delta, rng
        self.co = ref.coeffs(delta)
        ex = ref.extremes(delta)
        self.amax = float(ex["alpha_mmax"])
        self.bmax = ex["beta_mmax"]
        self.delta0 = ref.constants()["delta0"]
        self.has_line = delta > self.delta0
        self.bcorner = ref.corner(delta)[1] if self.has_line else None
        self.lend = ref.line_end(delta)

    def f(self, beta):
        return ref.f_hyperbola(self.d, beta)

    def L(self, beta):
        with mp.workdps(30):
            return 4 * (1 + self.co.e) / self.co.d12 - 2 * mpf(beta)

    def bound(self, beta):
        """min{f, L}, the alpha boundary at beta (inside -delta < beta < beta_mmax)."""
        v = self.f(beta)
        return min(v, self.L(beta)) if self.co.d12 != 0 else v

    def rnd(self, x):
        return ref.round_to(x, self.fmt)

    def perturb(self, v):
        """v (mpf) moved by a relative 1e-17 .. 1e-9 (either sign), or rounded and moved by
        -4 .. 4 ulps, then rounded to fmt."""
        rng = self.rng
        if rng.random() < 0.5:
            t = 10 ** rng.uniform(-17, -9) * (1 if rng.random() < 0.5 else -1)
            with mp.workdps(40):
                return self.rnd(mpf(v) * (1 + mpf(t)))
        return ref.step(self.rnd(v), int(rng.integers(-4, 5)), self.fmt)

    def uniform_beta(self, lo, hi):
        with mp.workdps(30):
            return self.rnd(mpf(lo) + (mpf(hi) - mpf(lo)) * mpf(self.rng.random()))

    def random_points(self, n):
        """n points spread over a box around the region (beta from -delta - w/4 to
        beta_mmax + w/4, alpha from -0.05 to 1.3 alpha_mmax, 30 % log-spread down to 1e-8)."""
        rng, d = self.rng, self.d
        bm = float(self.bmax)
        w = bm + d
        b = rng.uniform(-d - w / 4, bm + w / 4, n)
        a = np.where(rng.random(n) < 0.7, self.amax * rng.uniform(-0.05, 1.3, n),
                     self.amax * 10 ** rng.uniform(-8, 0.1, n))
        return a.astype(self.fmt.np_type).astype(float), b.astype(self.fmt.np_type).astype(float)

    def crowded_point(self):
        rng, d = self.rng, self.d
        kinds = ["hyperbola", "damping", "alpha0", "right"] + (["line"] if self.has_line else [])
        weights = [0.35, 0.15, 0.1, 0.2] + ([0.2] if self.has_line else [])
        weights = np.array(weights) / sum(weights)
        kind = kinds[rng.choice(len(kinds), p=weights)]
        right = self.bcorner if self.has_line else self.co.h
        if kind == "hyperbola" and self.rnd(right) <= ref.step(-d, 1, self.fmt):
            kind = "line"  # huge delta: the hyperbola's part of the boundary has no interior floats
        if kind == "hyperbola":
            b = self.uniform_beta(-d, right)
            if not (-d < b):
                b = ref.step(-d, 1, self.fmt)
            return self.perturb(self.f(b)), b, kind
        if kind == "line":
            b = self.uniform_beta(self.bcorner, self.lend)
            return self.perturb(self.L(b)), b, kind
        if kind == "damping":
            b = self.perturb(mpf(-d) if d else mpf(10) ** rng.uniform(-30, -1) * (1 if rng.random() < 0.5 else -1))
            gap = mpf(b) + d
            bb = b if gap > 0 else (float(-d + abs(gap)) if gap < 0 else ref.step(-d, 1, self.fmt))
            return self.rnd(self.bound(bb) * rng.uniform(0, 1.5)), b, kind
        if kind == "alpha0":
            b = self.uniform_beta(-d, self.bmax)
            r = rng.random()
            if r < 0.3:
                a = 0.0
            elif r < 0.6:
                a = self.fmt.tiny * int(rng.integers(-3, 4))
            else:
                a = self.amax * 10 ** rng.uniform(-40, -1) * (1 if rng.random() < 0.7 else -1)
            return self.rnd(a), b, kind
        # right end: 2/c2 or the line's alpha = 0 end
        use_line = self.has_line and (rng.random() < 0.75 or not math.isfinite(self.rnd(self.co.h)))
        end = self.lend if use_line else self.co.h
        b = self.perturb(end)
        if mpf(b) < self.bmax and mpf(b) > -d:
            a = self.bound(b) * rng.uniform(0, 1.5)
        else:  # mirror: an alpha of the size the boundary has as far inside
            mb = self.rnd(2 * mpf(end) - mpf(b))
            a = (self.bound(mb) if -d < mb < self.bmax else mpf(self.fmt.tiny)) * rng.uniform(0, 1.5)
        return self.rnd(a), b, kind


def _delta_points(task):
    """Worker: the points of one delta (its own seeded generator, so the data set does not
    depend on how the work is split)."""
    fmt_name, d, seed, i, per = task
    g = _Gen(ref.FORMATS[fmt_name], d, np.random.default_rng([seed, i]))
    a, b = g.random_points(per // 2)
    crowd = [g.crowded_point() for _ in range(per - per // 2)]
    A = list(a) + [c[0] for c in crowd]
    B = list(b) + [c[1] for c in crowd]
    K = ["random"] * (per // 2) + [c[2] for c in crowd]
    return [d] * per, A, B, K


def build_dataset(fmt, seed):
    """(delta, alpha, beta, kind) arrays: N_POINTS points, half random, half crowded."""
    deltas = dataset_deltas(fmt, np.random.default_rng(seed))
    per = -(-N_POINTS // len(deltas))
    parts = ref.pmap(_delta_points, [(fmt.name, d, seed, i, per) for i, d in enumerate(deltas)], min_parallel=2)
    D, A, B, K = ([x for p in parts for x in p[j]] for j in range(4))
    return np.array(D), np.array(A, dtype=float), np.array(B, dtype=float), np.array(K)


class Run:
    """The data set of one precision with the reference verdict and the library's verdicts."""

    def __init__(self, zw):
        t0 = time.time()
        self.zw = zw
        fmt = zw.fmt
        self.d, self.a, self.b, self.kind = build_dataset(fmt, seed=20240 + fmt.p)
        t1 = time.time()
        self.stats = {}
        self.ref = ref.stable_batch(self.d, self.a, self.b, self.stats)
        t2 = time.time()
        n = len(self.d)
        self.st = np.empty(n, np.int32)
        self.stable = np.empty(n, bool)
        self.marg = np.empty(n, bool)
        self.dec = np.empty(n, np.int32)
        self.vio = np.empty(n, np.int32)
        self.legacy = np.empty(n, bool)
        self.legacy_marg = np.empty(n, bool)
        for d in np.unique(self.d).tolist():
            idx = np.nonzero(self.d == d)[0]
            st, co = zw.coeffs(d)
            assert st == E["ZW_OK"]
            (self.st[idx], self.stable[idx], self.marg[idx], self.dec[idx],
             self.vio[idx]) = zw.check_many(co, self.a[idx], self.b[idx])
            _, self.legacy[idx], self.legacy_marg[idx], _, _ = zw.check_many(
                co, self.a[idx], self.b[idx], region=E["ZW_REGION_LEGACY"])
        t3 = time.time()
        self.timing = (t1 - t0, t2 - t1, t3 - t2)

    def where(self, mask, limit=8):
        idx = np.nonzero(mask)[0][:limit]
        return [(float(self.d[i]), float(self.a[i]), float(self.b[i]), str(self.kind[i])) for i in idx]


_RUNS = {}


@pytest.fixture(scope="module")
def run(zw):
    if zw.name not in _RUNS:
        _RUNS[zw.name] = Run(zw)
    return _RUNS[zw.name]


# ---------------------------------------------------------------------------------------
# The exact region
# ---------------------------------------------------------------------------------------


def test_dataset_shape(run):
    """The data set has the promised size, spread and crowding (guards the other tests)."""
    n = len(run.d)
    kinds = {str(k): int((run.kind == k).sum()) for k in np.unique(run.kind)}
    print(f"\n[{run.zw.name}] {n} points over {len(np.unique(run.d))} deltas, kinds {kinds}; "
          f"reference: {run.stats['mpmath']} points needed mpmath; "
          f"time gen/ref/C = {run.timing[0]:.1f}/{run.timing[1]:.1f}/{run.timing[2]:.1f} s")
    assert n >= N_POINTS
    assert (run.kind != "random").sum() >= n // 2 - 1
    assert all(kinds.get(k, 0) > 2000 for k in ("hyperbola", "line", "damping", "alpha0", "right"))
    assert 0.2 < run.ref.mean() < 0.8, "reference verdicts should be mixed"
    assert (run.st == E["ZW_OK"]).all(), run.where(run.st != E["ZW_OK"])


def test_no_unstable_point_called_stable(run):
    """ZERO points that are unstable in the reference but reported stable."""
    bad = run.stable & ~run.ref
    print(f"\n[{run.zw.name}] false stable: {int(bad.sum())} of {len(bad)}")
    assert not bad.any(), f"[{run.zw.name}] {int(bad.sum())} false stables, e.g. (delta, alpha, beta, kind): {run.where(bad)}"


def test_false_unstable_points_are_marginal_and_within_band(run):
    """Every stable point reported unstable says marginal = true and lies within BAND ulps
    of an unstable point: moving alpha and beta by at most BAND ulps (some corner of that
    square; a boundary that meets the square puts a corner outside) makes it unstable in the
    reference.  A subnormal coordinate counts as one step from zero (flush-to-zero rule,
    below).  Prints the count and the worst band found."""
    fmt = run.zw.fmt
    fu = run.ref & ~run.stable
    not_marg = fu & ~run.marg
    idx = np.nonzero(fu)[0]
    band = np.full(len(idx), -1)
    a = run.a[idx].astype(fmt.np_type)
    b = run.b[idx].astype(fmt.np_type)
    dd = run.d[idx]
    # Search order of the corners: the C's violated bits hint at the way out (the reference
    # alone decides); all four corners are tried at each k before k grows.
    v = run.vio[idx]
    up = (v & (E["ZW_BOUND_HYPERBOLA"] | E["ZW_BOUND_LINE"])) != 0
    sa1 = np.where(up | ((v & E["ZW_BOUND_STIFFNESS"]) == 0), 1, -1)
    sb1 = np.where((v & E["ZW_BOUND_DAMPING"]) != 0, -1, 1)
    orders = [(sa1, sb1), (sa1, -sb1), (-sa1, sb1), (-sa1, -sb1)]
    left = np.arange(len(idx))
    # Flush-to-zero rule: the C core budgets one underflow quantum (the smallest normal
    # number) per operation, so that it stays safe on FPUs that flush subnormals to zero
    # (internal.h, ZW_ETA).  A subnormal alpha or beta is therefore one step from zero:
    # such points count as band 1 when zeroing the subnormal coordinate makes them unstable.
    sub_a = (np.abs(a) < fmt.min_normal) & (a != 0)
    sub_b = (np.abs(b) < fmt.min_normal) & (b != 0)
    ftz = np.nonzero(sub_a | sub_b)[0]
    if len(ftz):
        aa = np.where(sub_a[ftz], 0.0, a[ftz].astype(np.float64))
        bb = np.where(sub_b[ftz], 0.0, b[ftz].astype(np.float64))
        hit = ~ref.stable_batch(dd[ftz], aa, bb)
        band[ftz[hit]] = 1
        left = np.setdiff1d(left, ftz[hit])
    for k in LADDER:
        for sa, sb in orders:
            if not len(left):
                break
            aa = ref.np_step(a[left], sa[left] * k, fmt).astype(np.float64)
            bb = ref.np_step(b[left], sb[left] * k, fmt).astype(np.float64)
            hit = ~ref.stable_batch(dd[left], aa, bb)
            band[left[hit]] = k
            left = left[~hit]
    worst = int(band.max()) if len(band) and (band >= 0).all() else (None if not len(band) else -1)
    hist = {k: int((band == k).sum()) for k in LADDER if (band == k).any()}
    kinds = run.kind[idx]
    per_kind = {str(k): int(band[kinds == k].max()) for k in np.unique(kinds) if (band[kinds == k] >= 0).all()}
    n_stable = int(run.ref.sum())
    print(f"\n[{run.zw.name}] false unstable: {len(idx)} of {n_stable} stable points "
          f"({100 * len(idx) / max(n_stable, 1):.2f} %), by kind "
          f"{ {str(k): int(((run.kind == k) & fu).sum()) for k in np.unique(run.kind)} }; band histogram (ulps) {hist}; "
          f"worst band {worst} ulps, per kind {per_kind}")
    assert not not_marg.any(), f"false unstable without marginal: {run.where(not_marg)}"
    outside = fu.copy()
    outside[idx[band >= 0]] = False
    assert not outside.any(), f"false unstable farther than {BAND} ulps from the boundary: {run.where(outside)}"


def test_stable_verdicts_are_clean(run):
    """A stable verdict is not marginal and names no constraint."""
    s = run.stable
    assert not run.marg[s].any()
    assert (run.dec[s] == E["ZW_BOUND_NONE"]).all() and (run.vio[s] == 0).all()


def test_unstable_verdicts_name_a_violated_constraint(run):
    """An unstable verdict has deciding != NONE and deciding among the violated bits; the
    exact region never sets the passivity bit."""
    u = ~run.stable
    dec, vio = run.dec[u], run.vio[u]
    assert (dec != 0).all()
    assert ((vio & dec) == dec).all()
    assert ((vio & E["ZW_BOUND_PASSIVITY"]) == 0).all()


def _clear_truth(d, a, b, fmt):
    """The constraint truths at (delta, alpha, beta) if none of them changes when alpha and
    beta move by 1e-6 relative (and alpha is 0 or at least the smallest normal number: the
    C core budgets one underflow quantum per operation, so a subnormal alpha > 0 is
    legitimately unprovable); else None."""
    t = ref.constraint_truth(d, a, b)
    if 0 < abs(a) < fmt.min_normal:
        return None
    for sa in (1 - 1e-6, 1 + 1e-6):
        for sb in (1 - 1e-6, 1 + 1e-6):
            bb = b * sb if b != 0 else (sb - 1) * 1e-300
            if ref.constraint_truth(d, mpf(a) * sa, mpf(bb)) != t:
                return None
    return t


def test_clearly_unstable_points_name_truly_violated_constraints(run):
    """For clearly unstable points (no constraint changes its truth within 1e-6 relative)
    `violated` is exactly the set of truly violated constraints (HYPERBOLA left free where
    beta <= -delta or alpha <= 0, where f is not the boundary) and `deciding` is the first of
    them in the enum order."""
    rng = np.random.default_rng(7)
    fmt = run.zw.fmt
    cand = np.nonzero(~run.ref)[0]
    cand = rng.choice(cand, size=min(5000, len(cand)), replace=False)
    checked, problems = 0, []
    for i in cand.tolist():
        d, a, b = run.d[i], run.a[i], run.b[i]
        t = _clear_truth(d, a, b, fmt)
        if t is None:
            continue
        checked += 1
        truly = {name for name, v in t.items() if v}
        got = {name for name, bit in BOUNDS.items() if run.vio[i] & bit}
        free = {"HYPERBOLA"} if (t["HYPERBOLA"] is None or a <= 0) else set()
        first = min(BOUNDS[n] for n in truly) if truly else None
        if (got - free) != (truly - free) or run.dec[i] != first:
            dec = [name for name, bit in BOUNDS.items() if run.dec[i] == bit]
            problems.append((float(d), float(a), float(b), sorted(truly), sorted(got), dec))
    print(f"\n[{run.zw.name}] clearly unstable points checked: {checked}, mismatches {len(problems)}")
    assert checked > 2000
    assert not problems, f"{len(problems)} mismatches (delta, alpha, beta, truly, violated, deciding): {problems[:8]}"


def test_reference_p1_identity():
    """Reference self-check: p(1) = (c1 + c2) alpha (used to decide the first Jury condition
    by the sign of alpha) holds to 1e-55 of the terms' scale for random inputs."""
    rng = np.random.default_rng(1)
    for _ in range(200):
        d = float(10 ** rng.uniform(-10, 6))
        a, b = rng.uniform(-5, 5) * (1 + d), rng.uniform(-d - 2, d + 5)
        assert ref.p1_identity_gap(d, a, b) < mpf("1e-55")


def test_prescreen_agrees_with_mpmath(run):
    """Reference self-check: on 1500 points the float64 pre-screen settled, the full mpmath
    Jury test gives the same verdict."""
    rng = np.random.default_rng(11)
    idx = rng.choice(len(run.d), size=1500, replace=False)
    for i in idx.tolist():
        assert ref.stable(run.d[i], run.a[i], run.b[i]) == run.ref[i], (run.d[i], run.a[i], run.b[i])


# ---------------------------------------------------------------------------------------
# Legacy, passivity and the approximate regions
# ---------------------------------------------------------------------------------------


def test_legacy_region_right_below_delta0(run):
    """For delta < delta0 the legacy region (no line) is the exact region: no false stables
    against the reference, and the same verdict as zw_check wherever neither is marginal."""
    below = run.d < float(ref.constants()["delta0"]) * (1 - 1e-6)
    bad = below & run.legacy & ~run.ref
    assert not bad.any(), run.where(bad)
    both = below & ~run.marg & ~run.legacy_marg
    diff = both & (run.legacy != run.stable)
    assert not diff.any(), run.where(diff)


def test_legacy_region_wrong_above_delta0(run):
    """For delta > delta0 the legacy region calls truly unstable points stable (paper
    Fig. 3): it happens for the data set, and only above delta0."""
    d0 = float(ref.constants()["delta0"])
    wrong = run.legacy & ~run.ref
    print(f"\n[{run.zw.name}] legacy false stables above delta0: {int(wrong.sum())}")
    assert wrong[run.d > d0].sum() > 100
    assert not wrong[run.d < d0 * (1 - 1e-6)].any()


@pytest.mark.parametrize("beta,alpha", [(-1.5, 23.0), (4.0, 15.0), (10.0, 5.0)])
def test_paper_fig19_points(zw, beta, alpha):
    """The three points the paper tested at delta = 5.122 (Fig. 18, 19): inside the legacy
    region, truly unstable, and zw_check says unstable."""
    st, co = zw.coeffs(5.122)
    a, b = zw.r(alpha), zw.r(beta)
    assert not ref.stable(co.delta, a, b)
    st, v = zw.check_region(E["ZW_REGION_LEGACY"], co, a, b)
    assert st == E["ZW_OK"] and v.stable
    st, v = zw.check(co, a, b)
    assert st == E["ZW_OK"] and not v.stable and v.deciding == E["ZW_BOUND_LINE"]


def _region_formula(region, d, a, b):
    """The approximate regions' own formulas, evaluated exactly in rationals."""
    d, a, b = Fraction(d), Fraction(a), Fraction(b)
    if region == "ZW_REGION_PASSIVITY":
        return 0 < a / 2 < d - abs(b)
    if region == "ZW_REGION_DELTA0":
        return b > 0 and 0 < a < (-2 * b * b + 4 * b) / (b + 2)
    if region == "ZW_REGION_DELTA_INF":
        return b > -d and 0 < a / 2 < d - b
    if region == "ZW_REGION_SMALL":
        return 0 < a / 2 < d + b
    raise ValueError(region)


def _region_points(zw, rng, region, n=2500):
    """Points aimed at one approximate region's boundary (60 %: the boundary +- 3 ulps),
    inside it (20 %) and around it (20 %)."""
    fmt = zw.fmt
    out = []
    for _ in range(n):
        d = zw.r(10 ** rng.uniform(-6, 3)) if rng.random() < 0.9 else 0.0
        w = max(d, 1e-3)
        if region == "ZW_REGION_DELTA0":
            b = zw.r(rng.uniform(-0.2, 2.2))
            bound = (-2 * b * b + 4 * b) / (b + 2)
        elif region == "ZW_REGION_PASSIVITY":
            b = zw.r(rng.uniform(-1.2, 1.2) * w)
            bound = 2 * (d - abs(b))
        elif region == "ZW_REGION_DELTA_INF":
            b = zw.r(rng.uniform(-1.2, 1.5) * w)
            bound = 2 * (d - b)
        else:
            b = zw.r(rng.uniform(-1.2, 1.5) * w)
            bound = 2 * (d + b)
        r = rng.random()
        if r < 0.6:
            a = ref.step(zw.r(bound), int(rng.integers(-3, 4)), fmt)
        elif r < 0.8:
            a = zw.r(bound * rng.uniform(0, 1))
        else:
            a = zw.r(rng.uniform(-0.1, 1.5) * max(abs(bound), 1e-3))
        out.append((d, a, b))
    return out


@pytest.mark.parametrize("region", ["ZW_REGION_PASSIVITY", "ZW_REGION_DELTA0", "ZW_REGION_DELTA_INF", "ZW_REGION_SMALL"])
def test_approximate_regions_safe_for_their_own_formula(zw, region):
    """Each approximate region is guarded against its own boundary: stable only where its
    formula (evaluated exactly) holds; unstable where it holds only with marginal = true;
    passivity-stable points are also truly stable (passivity implies stability)."""
    rng = np.random.default_rng(sum(map(ord, region)))
    problems, n_stable = [], 0
    for d, a, b in _region_points(zw, rng, region):
        st, co = zw.coeffs(d)
        st, v = zw.check_region(E[region], co, a, b)
        assert st == E["ZW_OK"]
        truth = _region_formula(region, d, a, b)
        n_stable += v.stable
        if v.stable and not truth:
            problems.append(("stable outside", d, a, b))
        if not v.stable and truth and not v.marginal:
            problems.append(("unstable inside, not marginal", d, a, b))
        if region == "ZW_REGION_PASSIVITY" and v.stable and not ref.stable(d, a, b):
            problems.append(("passivity-stable but unstable", d, a, b))
    assert n_stable > 300
    assert not problems, problems[:8]


def test_passivity_region_implies_stability(run, zw):
    """Over the whole data set: passivity says stable => truly stable."""
    bad = []
    for d in np.unique(run.d).tolist():
        idx = np.nonzero(run.d == d)[0]
        _, co = zw.coeffs(d)
        _, stab, _, _, _ = zw.check_many(co, run.a[idx], run.b[idx], region=E["ZW_REGION_PASSIVITY"])
        bad += [i for i in idx[stab & ~run.ref[idx]]]
    assert not bad, [(run.d[i], run.a[i], run.b[i]) for i in bad[:8]]


def test_proportional_agrees_with_beta_zero(zw):
    """zw_check_proportional(alpha) gives the verdict of zw_check(alpha, beta = 0), is never
    stable for a truly unstable point, and its limit sits at alpha_p_max (eqs (27), (29))."""
    rng = np.random.default_rng(5)
    fmt = zw.fmt
    problems = []
    for d in [0.0, 1e-8, 0.01, 0.5, 2.3, 3.7, zw.r(ref.constants()["delta2"]), 3.8, 5.0, 100.0, 1e6]:
        d = zw.r(d)
        st, co = zw.coeffs(d)
        apm = ref.extremes(d)["alpha_p_max"]
        alphas = [ref.step(ref.round_to(apm, fmt), k, fmt) for k in range(-6, 7)]
        alphas += [zw.r(float(apm) * x) for x in rng.uniform(-0.2, 1.5, 40)] + [0.0, fmt.tiny]
        for a in alphas:
            s1, v1 = zw.check_proportional(co, a)
            s2, v2 = zw.check(co, a, 0.0)
            assert s1 == s2 == E["ZW_OK"]
            truth = ref.stable(d, a, 0.0)
            if v1.stable and not truth:
                problems.append(("false stable", d, a))
            if not (v1.marginal or v2.marginal) and v1.stable != v2.stable:
                problems.append(("differs from beta = 0", d, a, v1.stable, v2.stable))
            if v1.stable != truth and not v1.marginal:
                problems.append(("wrong, not marginal", d, a))
    assert not problems, problems[:8]


# ---------------------------------------------------------------------------------------
# Error paths
# ---------------------------------------------------------------------------------------


def test_check_error_paths(zw):
    """NaN -> ZW_ERR_NAN, infinite alpha/beta or delta -> ZW_ERR_INF, NULL -> ZW_ERR_NULL,
    an unknown region -> ZW_ERR_ARG; the verdict is fail-safe (not stable,
    ZW_BOUND_INVALID)."""
    _, co = zw.coeffs(1.0)
    _, co_inf = zw.coeffs(math.inf)
    cases = [((co, math.nan, 0.1), "ZW_ERR_NAN"), ((co, 0.1, math.nan), "ZW_ERR_NAN"),
             ((co, math.inf, 0.1), "ZW_ERR_INF"), ((co, 0.1, -math.inf), "ZW_ERR_INF"),
             ((co_inf, 0.1, 0.1), "ZW_ERR_INF")]
    for args, status in cases:
        st, _ = zw.check(*args)
        assert st == E[status] and zw.failsafe(), (args[1:], zw.status_name(st))
        st, _ = zw.check_region(E["ZW_REGION_LEGACY"], *args)
        assert st == E[status] and zw.failsafe(), (args[1:], zw.status_name(st))
    st, _ = zw.check_proportional(co, math.nan)
    assert st == E["ZW_ERR_NAN"] and zw.failsafe()
    st, _ = zw.check_region(99, co, 0.1, 0.1)
    assert st == E["ZW_ERR_ARG"] and zw.failsafe()
    assert zw.lib.zw_check(None, 0.1, 0.1, ctypes.byref(zw.Verdict())) == E["ZW_ERR_NULL"]
    assert zw.lib.zw_check(co, 0.1, 0.1, None) == E["ZW_ERR_NULL"]


def test_huge_delta_edge(zw):
    """delta in the top binade (hs may overflow there): verdicts stay safe."""
    fmt = zw.fmt
    problems = []
    for d in (ref.step(fmt.max, -1, fmt), math.ldexp(1.0, 1023 if fmt.p == 53 else 127) * 1.5):
        d = zw.r(d)
        st, co = zw.coeffs(d)
        for a, b in ((d, -d / 2), (d, 0.0), (2 * (d / 4), d / 4), (1.0, -d / 2), (zw.r(d * 1.9), zw.r(-d * 0.05))):
            a, b = zw.r(a), zw.r(b)
            if not (math.isfinite(a) and math.isfinite(b)):
                continue
            st, v = zw.check(co, a, b)
            if st == E["ZW_OK"] and v.stable and not ref.stable(d, a, b):
                problems.append((d, a, b))
    assert not problems
