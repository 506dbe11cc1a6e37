# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The general loop on a plant with its plant-side parts (zw_loop_init_plant: a spring or a
hand's stiffness kappa, an actuator lag lambda) against a 50-digit mpmath reference.

Reference, from the loop's definition only: the normalized plant x'' + delta x' + kappa x = f,
lambda f' + f = u (lambda = 0: f = u) behind a zero-order hold, one period being the matrix
exponential of the augmented matrix [[A, b], [0, 0]] (mpmath.expm); the controller, delay
line and velocity estimate as a drive runs them (loop_reference.closed_loop_matrix's
recurrences), the closed loop's characteristic polynomial by Faddeev-LeVerrier at 80 digits,
its roots by mpmath.polyroots.  Nothing of the C code's transfer functions is used.

Claims (both precisions):
* verdicts: no false "stable"; a false "unstable" only with the reference's spectral
  radius within BAND of 1 (the rounding band);
* alpha_max(beta): every alpha in (0, alpha_max] sampled is stable (never above the truth),
  and the truth (bisection on the reference) within TIGHT of it (tightness, printed);
* extremes certified (stable at (alpha_mmax, beta_at_alpha_mmax) and below);
* hard cases: critical damping, complex poles of a stiff hand, kappa -> 0 and lambda -> 0
  reduce to the ideal loop's limits, lambda >> 1;
* Hulin et al. (2014): a coupled hand enlarges the region (K_mmax) for the numbers below.
"""
from __future__ import annotations

import ctypes
import math
import random
from ctypes import POINTER, byref, c_int

import mpmath
import pytest
from mpmath import mp, mpf

import loop_reference as lr
import reference as ref
from conftest import E

DPS = 50
BAND = {"double": 1e-7, "float": 1e-2}   # |1 - rho_ref| of an allowed false "unstable"
TIGHT = {"double": 1e-6, "float": 5e-2}  # relative gap of alpha_max below the truth


# ---------------------------------------------------------------------------------------
# Reference
# ---------------------------------------------------------------------------------------


def plant_step(delta, kappa, lam):
    """(Phi, Gamma) of one ZOH period of the normalized plant, by expm of [[A, b], [0, 0]]."""
    delta, kappa, lam = (ref.exact(v) for v in (delta, kappa, lam))
    if lam == 0:
        a = [[0, 1], [-kappa, -delta]]
        b = [0, 1]
    else:
        a = [[0, 1, 0], [-kappa, -delta, 1], [0, 0, -1 / lam]]
        b = [0, 0, 1 / lam]
    n = len(a)
    m = mpmath.zeros(n + 1, n + 1)
    for i in range(n):
        for j in range(n):
            m[i, j] = a[i][j]
        m[i, n] = b[i]
    e = mpmath.expm(m)
    return [[e[i, j] for j in range(n)] for i in range(n)], [e[i, n] for i in range(n)]


def closed_loop(delta, kappa, lam, alpha, beta, delay, tustin, pole, average):
    """A of x_{k+1} = A x_k: plant state, x_{k-1}, the estimate's states, the delay line."""
    alpha, beta, a = (ref.exact(v) for v in (alpha, beta, pole or 0.0))
    phi, gam = plant_step(delta, kappa, lam)
    n = len(phi)
    names = [f"p{i}" for i in range(n)] + ["xm1"]
    if tustin:
        names.append("raw")
    if pole is not None:
        names.append("lp")
    hist = average - 1 if average else 0
    names += [f"h{i}" for i in range(1, hist + 1)] + [f"c{i}" for i in range(1, delay + 1)]
    idx = {k: i for i, k in enumerate(names)}
    size = len(names)

    def unit(k):
        v = [mpf(0)] * size
        v[idx[k]] = mpf(1)
        return v

    def lin(*terms):
        out = [mpf(0)] * size
        for coef, vec in terms:
            for i in range(size):
                out[i] += coef * vec[i]
        return out

    X = unit("p0")
    raw = lin((2, X), (-2, unit("xm1")), (-1, unit("raw"))) if tustin else lin((1, X), (-1, unit("xm1")))
    if pole is not None:
        est = lin((a, unit("lp")), (1 - a, raw))
    elif average:
        est = lin(*([(mpf(1) / average, raw)] + [(mpf(1) / average, unit(f"h{i}")) for i in range(1, hist + 1)]))
    else:
        est = raw
    c = lin((-alpha, X), (-beta, est))
    u = c if delay == 0 else unit(f"c{delay}")
    rows = {f"p{i}": lin(*([(phi[i][j], unit(f"p{j}")) for j in range(n)] + [(gam[i], u)])) for i in range(n)}
    rows["xm1"] = X
    if tustin:
        rows["raw"] = raw
    if pole is not None:
        rows["lp"] = est
    for i in range(1, hist + 1):
        rows[f"h{i}"] = raw if i == 1 else unit(f"h{i - 1}")
    for i in range(1, delay + 1):
        rows[f"c{i}"] = c if i == 1 else unit(f"c{i - 1}")
    return mpmath.matrix([rows[k] for k in names])


class RefLoop:
    """p = D + alpha Na + beta Nb of the reference (affine: checked at a fourth point)."""

    def __init__(self, delta, kappa, lam, delay=0, tustin=False, pole=None, average=0):
        self.args = (delta, kappa, lam)
        self.kw = dict(delay=delay, tustin=tustin, pole=pole, average=average)
        with mp.workdps(80):
            cp = lambda al, be: lr.charpoly(closed_loop(delta, kappa, lam, al, be, **self.kw))
            d = cp(0, 0)
            na = [p - q for p, q in zip(cp(1, 0), d)]
            nb = [p - q for p, q in zip(cp(0, 1), d)]
            chk = cp(mpf(3) / 7, mpf(-5) / 11)
            for i, v in enumerate(chk):
                assert abs(v - (d[i] + mpf(3) / 7 * na[i] - mpf(5) / 11 * nb[i])) < mpf(10) ** -60
        self.parts = (d, na, nb)

    def poly(self, alpha, beta):
        d, na, nb = self.parts
        p = [x + ref.exact(alpha) * y + ref.exact(beta) * w for x, y, w in zip(d, na, nb)]
        while len(p) > 1 and abs(p[-1]) < mpf(10) ** -70:  # roots at 0 of the extra states
            p.pop()
        return p

    def rho(self, alpha, beta):
        """Spectral radius by mpmath.polyroots at DPS digits."""
        return lr.spectral_radius(self.poly(alpha, beta), dps=DPS)[0]

    def stable(self, alpha, beta):
        return lr.schur_stable(self.poly(alpha, beta), dps=DPS)[0]

    def alpha_sup(self, beta, start):
        """The sup of the stable alphas above start (stable) on the line: bisection."""
        lo, hi = mpf(start), mpf(start) * 2 + mpf(10) ** -6
        while self.stable(hi, beta):
            lo, hi = hi, hi * 2
            assert hi < 1e9
        for _ in range(70):
            mid = (lo + hi) / 2
            if self.stable(mid, beta):
                lo = mid
            else:
                hi = mid
        return lo


# ---------------------------------------------------------------------------------------
# The library
# ---------------------------------------------------------------------------------------


class PLoop:
    """zw_loop_init_plant on zw_plant_init of (delta, kappa, lambda)."""

    def __init__(self, zw, delta, kappa, lam, delay=0, tustin=False, pole=None, average=0):
        self.zw = zw
        R = zw.real
        Plant, PlantSpec = zw.Loop.Plant, zw.Loop.PlantSpec
        L = POINTER(zw.Loop)
        for name, args in {"zw_plant_init": [POINTER(Plant), POINTER(PlantSpec)],
                           "zw_loop_init_plant": [L, POINTER(Plant), POINTER(zw.LoopSpec)],
                           "zw_loop_alpha_max": [L, POINTER(zw.LoopWorkspace), R, POINTER(R)]}.items():
            fn = zw.symbol(name)
            fn.argtypes, fn.restype = args, c_int
        self.delta, self.kappa, self.lam = zw.r(delta), zw.r(kappa), zw.r(lam)
        self.pole = zw.r(pole) if pole is not None else None
        self.plant = Plant()
        self.status = zw.symbol("zw_plant_init")(byref(self.plant), byref(PlantSpec(self.delta, self.kappa, self.lam, 0, 0, 0)))
        if self.status != E["ZW_OK"]:
            return
        filt = "none" if pole is None and not average else ("lowpass" if pole is not None else "average")
        spec = zw.loop_spec(delay, "tustin" if tustin else "backward", filt, self.pole or 0.0, average or 0)
        self.loop = zw.Loop()
        self.status = zw.symbol("zw_loop_init_plant")(byref(self.loop), byref(self.plant), byref(spec))
        self.kw = dict(delay=delay, tustin=tustin, pole=self.pole, average=average)

    def ref(self):
        return RefLoop(self.delta, self.kappa, self.lam, **self.kw)

    def verdict(self, alpha, beta):
        st, v = self.zw.loop_check(self.loop, alpha, beta)
        assert st == E["ZW_OK"]
        return v.stable, v.marginal

    def alpha_max(self, beta):
        a = self.zw.real()
        st = self.zw.symbol("zw_loop_alpha_max")(byref(self.loop), byref(self.zw.ws), beta, byref(a))
        assert st == E["ZW_OK"], self.zw.status_name(st)
        return a.value


def make(zw, *args, **kw):
    lp = PLoop(zw, *args, **kw)
    if lp.status == E["ZW_ERR_ARG"] and args[2] > 0:
        pytest.skip("zw_plant_init does not build the actuator lag yet (plant branch)")
    assert lp.status == E["ZW_OK"], zw.status_name(lp.status)
    return lp


# (delta, kappa, lambda, loop) cases: springs, hands (complex poles), critical damping, lags
CASES = [
    (0.5, 0.1, 0.0, dict()),
    (0.05, 2.0, 0.0, dict()),                        # a stiff hand: complex poles
    (0.01, 5.0, 0.0, dict(delay=1)),                 # lightly damped, delayed
    (1.0, 0.25, 0.0, dict()),                        # critical damping delta^2 = 4 kappa
    (0.2, 0.01, 0.0, dict(delay=2, pole=0.5)),
    (0.3, 0.5, 0.0, dict(tustin=True)),
    (0.3, 0.2, 0.0, dict(average=3)),
    (0.5, 0.0, 0.3, dict()),                         # a lag
    (0.5, 0.0, 4.0, dict()),                         # lambda >> 1
    (0.1, 1.0, 1.0, dict(delay=1)),                  # lag and hand
]


def case_id(c):
    return f"d{c[0]}-k{c[1]}-l{c[2]}-" + "-".join(f"{k}{v}" for k, v in c[3].items())


@pytest.mark.parametrize("case", CASES, ids=case_id)
def test_verdicts_against_reference(zw, case):
    delta, kappa, lam, kw = case
    lp = make(zw, delta, kappa, lam, **kw)
    ref_loop = lp.ref()
    rng = random.Random(hash(case_id(case)) & 0xFFFF)
    false_stable = false_unstable = worst_band = 0
    n = 0
    for beta in [0.0, -0.5 * delta, 0.5, 2.0 * (1 + delta)]:
        beta = zw.r(beta)
        amax = lp.alpha_max(beta)
        scale = amax if amax > 0 else 0.5
        for _ in range(12):
            r = rng.random()
            if r < 0.4:
                alpha = scale * (1 + rng.choice([-1, 1]) * 10 ** rng.uniform(-9, -1))
            elif r < 0.9:
                alpha = scale * rng.uniform(-0.2, 2.0)
            else:
                alpha = -kappa * (1 + rng.choice([-1, 1]) * 10 ** rng.uniform(-6, -1))
            alpha = zw.r(alpha)
            stable, marginal = lp.verdict(alpha, beta)
            rho = ref_loop.rho(alpha, beta)
            n += 1
            if stable and rho >= 1:
                false_stable += 1
            if not stable and rho < 1:
                false_unstable += 1
                worst_band = max(worst_band, float(1 - rho))
                assert 1 - rho < BAND[zw.name], (alpha, beta, rho, marginal)
    print(f"\n{zw.name} {case_id(case)}: {n} points, false stable {false_stable}, false unstable "
          f"{false_unstable} (worst 1 - rho {worst_band:.1e})")
    assert false_stable == 0


@pytest.mark.parametrize("case", CASES, ids=case_id)
def test_alpha_max_certified_and_tight(zw, case):
    delta, kappa, lam, kw = case
    lp = make(zw, delta, kappa, lam, **kw)
    ref_loop = lp.ref()
    worst = 0.0
    for beta in [0.0, 0.3, 1.0 + delta]:
        beta = zw.r(beta)
        amax = lp.alpha_max(beta)
        if amax == 0:
            # nothing certified: the reference must be unstable just above alpha = 0 (a stiff
            # plant's region may lie at negative alpha), not merely unproved
            print(f"\n{zw.name} {case_id(case)} beta={beta}: alpha_max 0")
            assert not ref_loop.stable(1e-9, beta) or not ref_loop.stable(1e-3, beta), beta
            continue
        for k in range(1, 17):  # never above the truth: (0, amax] stable
            assert ref_loop.stable(amax * k / 16, beta), (beta, amax, k)
        truth = ref_loop.alpha_sup(beta, amax)
        gap = float((truth - amax) / truth)
        worst = max(worst, gap)
        assert gap < TIGHT[zw.name], (beta, amax, truth)
    print(f"\n{zw.name} {case_id(case)}: alpha_max within {worst:.1e} below the truth")


def test_random_plants_verdicts(zw):
    """Random springs, hands (kappa log-uniform, real and complex poles) and lags (lambda
    log-uniform, half the plants), random delay and velocity estimate; points near the
    boundary and across the plane: no false stable."""
    rng = random.Random(1604)
    n = false_unstable = 0
    for _ in range(40):
        delta = 10 ** rng.uniform(-2, 1)
        kappa = 10 ** rng.uniform(-3, 1.3) if rng.random() < 0.8 else 0.0
        lam = 10 ** rng.uniform(-2, 1) if rng.random() < 0.5 else 0.0
        kw = dict(delay=rng.randint(0, 3), tustin=rng.random() < 0.2)
        if rng.random() < 0.3:
            kw["pole"] = rng.choice([0.2, 0.6, 0.9])
        lp = make(zw, delta, kappa, lam, **kw)
        ref_loop = lp.ref()
        for _ in range(10):
            beta = zw.r(rng.uniform(-delta, 2 * (1 + delta)))
            amax = lp.alpha_max(beta)
            scale = amax if amax > 0 else 1.0
            alpha = zw.r(scale * (1 + rng.choice([-1, 1]) * 10 ** rng.uniform(-8, 0)) if rng.random() < 0.6
                         else rng.uniform(-kappa, 3.0))
            stable, _ = lp.verdict(alpha, beta)
            rho = ref_loop.rho(alpha, beta)
            n += 1
            assert not (stable and rho >= 1), (delta, kappa, lam, kw, alpha, beta, rho)
            if not stable and rho < 1:
                false_unstable += 1
                assert 1 - rho < BAND[zw.name], (delta, kappa, lam, kw, alpha, beta, rho)
    print(f"\n{zw.name}: {n} random points, 0 false stable, {false_unstable} false unstable (in the band)")


@pytest.mark.parametrize("case", [(0.5, 0.1, 0.0, {}), (1.0, 0.25, 0.0, {}), (0.05, 2.0, 0.0, dict(delay=1)),
                                  (0.5, 0.0, 0.3, {}), (0.1, 1.0, 1.0, {})], ids=case_id)
def test_extremes_certified(zw, case):
    """alpha_mmax stable (and below it on its line), alpha_p_max on beta = 0, and the beta
    range at alpha -> 0+ stable inside, in the reference."""
    delta, kappa, lam, kw = case
    lp = make(zw, delta, kappa, lam, **kw)
    ref_loop = lp.ref()
    Ext = type("Ext", (ctypes.Structure,), {"_fields_": [(n, zw.real) for n in (
        "alpha_mmax", "beta_at_alpha_mmax", "alpha_p_max", "beta_mmax", "beta_mmin")]})
    fn = zw.symbol("zw_loop_extremes_compute")
    fn.argtypes, fn.restype = [POINTER(zw.Loop), POINTER(zw.LoopWorkspace), POINTER(Ext)], c_int
    x = Ext()
    assert fn(byref(lp.loop), byref(zw.ws), byref(x)) == E["ZW_OK"]
    assert x.alpha_mmax > 0 and x.beta_mmin < x.beta_mmax
    for k in range(1, 9):
        assert ref_loop.stable(x.alpha_mmax * k / 8, x.beta_at_alpha_mmax)
    if x.alpha_p_max > 0:
        assert ref_loop.stable(x.alpha_p_max, 0.0)
    for k in range(1, 8):
        b = x.beta_mmin + (x.beta_mmax - x.beta_mmin) * k / 8
        assert ref_loop.stable(1e-7, b), b
    # near-optimal: the reference's alpha_sup at beta_at_alpha_mmax is not far above
    truth = ref_loop.alpha_sup(x.beta_at_alpha_mmax, x.alpha_mmax)
    print(f"\n{zw.name} {case_id(case)}: alpha_mmax {x.alpha_mmax:.6g} (reference sup on its line "
          f"{float(truth):.6g}), beta range ({x.beta_mmin:.4g}, {x.beta_mmax:.4g})")
    assert float((truth - x.alpha_mmax) / truth) < TIGHT[zw.name]


def test_kappa_and_lambda_to_zero_reduce_to_ideal(zw):
    """A vanishing spring or lag gives the ideal loop's alpha_max (the truths differ by
    O(kappa), O(lambda))."""
    for delay in (0, 1, 2):
        co_st, co = zw.coeffs(zw.r(0.8))
        st, ideal = zw.loop(co, zw.loop_spec(delay, "backward", "none", 0.0, 0))
        assert st == E["ZW_OK"]
        am = zw.symbol("zw_loop_alpha_max")
        for kappa, lam in ((1e-9, 0.0), (0.0, 1e-9)):
            lp = make(zw, 0.8, kappa, lam, delay=delay)
            for beta in (0.0, 0.4, 1.2):
                a_ideal = zw.real()
                assert am(byref(ideal), byref(zw.ws), zw.r(beta), byref(a_ideal)) == E["ZW_OK"]
                a = lp.alpha_max(zw.r(beta))
                assert abs(a - a_ideal.value) <= {"double": 1e-6, "float": 1e-3}[zw.name] * (1 + a_ideal.value)


def simulate_grows(A, steps=4000):
    """|x_n| / |x_0| after steps of x_{k+1} = A x_k from a generic start (float64)."""
    import numpy as np
    a = np.array(A.tolist(), dtype=float)
    x = np.linspace(1.0, 0.3, a.shape[0])
    n0 = np.linalg.norm(x)
    for _ in range(steps):
        x = a @ x
        nx = np.linalg.norm(x)
        if nx > 1e12 * n0:
            return math.inf
    return float(np.linalg.norm(x) / n0)


@pytest.mark.parametrize("case", [(0.5, 0.1, 0.0, {}), (0.05, 2.0, 0.0, dict(delay=1)), (0.5, 0.0, 0.5, {}),
                                  (0.1, 1.0, 1.0, dict(delay=1))], ids=case_id)
def test_simulation_agrees(zw, case):
    """A direct time-domain simulation of the sampled loop (the exact-ZOH state update, as a
    drive runs it) decays at points the library calls stable and grows at points it calls
    unstable (not marginal), at 0.6 and 1.4 times alpha_max."""
    delta, kappa, lam, kw = case
    lp = make(zw, delta, kappa, lam, **kw)
    for beta in (0.1, 0.5):
        beta = zw.r(beta)
        amax = lp.alpha_max(beta)
        if amax == 0:
            continue
        for f, expect in ((0.6, True), (1.4, False)):
            alpha = zw.r(f * amax)
            stable, marginal = lp.verdict(alpha, beta)
            assert stable == expect and not marginal
            with mp.workdps(30):
                A = closed_loop(lp.delta, lp.kappa, lp.lam, alpha, beta, **lp.kw)
            g = simulate_grows(A)
            assert (g < 1e-3) if stable else (g > 1e3), (alpha, beta, g)


# ---------------------------------------------------------------------------------------
# zwidth.Device and the CLI with plant-side parts
# ---------------------------------------------------------------------------------------

PAPER = dict(m=85.78e-7, b=2.197e-3, T=0.02)  # the paper's drive (rotary: J [kg m^2])


def _zwidth():
    return pytest.importorskip("zwidth")


def _normalized_ref(dev_kw, delay, K, B):
    """The reference's verdict at the exact normalized gains of a Device's (K, B)."""
    m, b, T = PAPER["m"], PAPER["b"], PAPER["T"]
    m_h, b_h, k_h = dev_kw.get("hand", (0.0, 0.0, 0.0))
    with mp.workdps(60):
        M = mpf(m) + mpf(m_h)
        delta = (mpf(b) + mpf(b_h)) * T / M
        kappa = (mpf(dev_kw.get("stiffness", 0.0)) + mpf(k_h)) * mpf(T) ** 2 / M
        lam = mpf(dev_kw.get("actuator_tau", 0.0)) / mpf(T)
        rl = RefLoop(delta, kappa, lam, delay=delay)
        return rl.stable(mpf(K) * mpf(T) ** 2 / M, mpf(B) * mpf(T) / M)


def test_hand_enlarges_the_region():
    """Hulin et al. (2014): a coupled hand enlarges the stable region.  For the paper's drive
    with one sample of delay and a hand of the drive's own inertia, twice its damping and a
    soft spring, K_mmax grows (0.107 -> 0.325 N m/rad); both certified by the reference."""
    zwidth = _zwidth()
    hand = (PAPER["m"], 2 * PAPER["b"], 1e-4)
    plain = zwidth.Device(PAPER["m"], PAPER["b"], PAPER["T"], rotary=True, delay=1)
    held = zwidth.Device(PAPER["m"], PAPER["b"], PAPER["T"], rotary=True, delay=1, hand=hand)
    e0, e1 = plain.extremes(), held.extremes()
    assert float(e1.K_mmax) > 2.5 * float(e0.K_mmax)
    assert _normalized_ref(dict(hand=hand), 1, float(e1.K_mmax) * 0.999, float(e1.B_at_K_mmax))
    # the plain drive's K_mmax is unstable when nothing holds it ... and stable when held
    K = 1.5 * float(e0.K_mmax)
    assert not bool(plain.is_stable(K, float(e0.B_at_K_mmax)))
    assert bool(held.is_stable(K, float(e0.B_at_K_mmax)))
    assert _normalized_ref(dict(hand=hand), 1, K, float(e0.B_at_K_mmax))


def test_device_routes_and_checks_parts():
    """Zero parts are the plain device (same numbers); a stiffness lets small negative K be
    stable (K > -k_p), certified against the reference; bad values are named errors."""
    zwidth = _zwidth()
    args = (PAPER["m"], PAPER["b"], PAPER["T"])
    plain = zwidth.Device(*args, rotary=True, delay=1)
    zero = zwidth.Device(*args, rotary=True, delay=1, actuator_tau=0.0, hand=(0, 0, 0), stiffness=0.0)
    assert not zero.has_plant_parts
    assert float(zero.k_max(1e-4)) == float(plain.k_max(1e-4))
    k_p = 1e-3
    stiff = zwidth.Device(*args, rotary=True, stiffness=k_p)
    assert stiff.has_plant_parts
    assert bool(stiff.is_stable(-0.5 * k_p, 1e-4)) and _normalized_ref(dict(stiffness=k_p), 0, -0.5 * k_p, 1e-4)
    assert not bool(stiff.is_stable(-1.5 * k_p, 1e-4))
    km = float(stiff.k_max(1e-4))
    assert km > 0 and _normalized_ref(dict(stiffness=k_p), 0, km, 1e-4)
    for kw, param, status in ((dict(actuator_tau=-1e-3), "actuator_tau", "ZW_ERR_ARG"),
                              (dict(stiffness=float("nan")), "stiffness", "ZW_ERR_ARG"),
                              (dict(hand=(1.0, -1.0, 0.0)), "hand", "ZW_ERR_DAMPING"),
                              (dict(hand=(-1.0, 0.0, 0.0)), "hand", "ZW_ERR_ARG"),
                              (dict(hand=(1.0, 0.0)), "hand", "ZW_ERR_ARG")):
        with pytest.raises(zwidth.ZwidthError) as exc:
            zwidth.Device(*args, **kw)
        assert exc.value.parameter == param and exc.value.status == status


def test_cli_parts():
    """zwidth limits/check --hand/--stiffness: the general loop's numbers, the options named in
    errors, refused where not supported."""
    _zwidth()
    import json
    import subprocess
    import sys

    def run(*a):
        return subprocess.run([sys.executable, "-m", "zwidth", *a], capture_output=True, text=True)

    r = run("limits", "--preset", "paper-drive", "--delay", "1", "--hand", "8.578e-6,4.394e-3,1e-4", "--json")
    assert r.returncode == 0, r.stderr
    obj = json.loads(r.stdout)
    assert obj["plant"]["hand"] == [8.578e-6, 4.394e-3, 1e-4]
    assert 0.32 < obj["K_mmax"] < 0.33
    r = run("check", "--preset", "paper-drive", "--K", "0.2", "--B", "0.001", "--delay", "1",
            "--hand", "8.578e-6,4.394e-3,1e-4")
    assert r.returncode == 0 and "Plant-side parts" in r.stdout, r.stdout + r.stderr
    r = run("check", "--preset", "paper-drive", "--K", "0.2", "--B", "0.001", "--delay", "1")
    assert r.returncode == 1  # unstable without the hand
    r = run("check", "--preset", "paper-drive", "--K", "0.2", "--B", "0.001", "--stiffness", "-1")
    assert r.returncode != 0 and "--stiffness" in r.stderr
    r = run("advise", "--preset", "paper-drive", "--K", "0.2", "--B", "0.001", "--hand", "1,2")
    assert r.returncode == 2 and "--hand" in r.stderr   # advise takes the parts (test_plant_cli.py)
    r = run("check", "--delta", "1", "--alpha", "1", "--beta", "0", "--stiffness", "1")
    assert r.returncode == 2 and "real-unit plant" in r.stderr


def test_random_plants_alpha_max(zw):
    """alpha_max of random lags, springs and hands (with delay, low-pass): never above the
    reference's sup; the worst gap below it printed."""
    rng = random.Random(2611)
    worst = 0.0
    for _ in range(16):
        delta = 10 ** rng.uniform(-2, 1)
        kappa = 10 ** rng.uniform(-3, 1) if rng.random() < 0.6 else 0.0
        lam = 10 ** rng.uniform(-2, 1) if rng.random() < 0.7 else 0.0
        kw = dict(delay=rng.randint(0, 2))
        if rng.random() < 0.3:
            kw["pole"] = 0.5
        lp = make(zw, delta, kappa, lam, **kw)
        ref_loop = lp.ref()
        for beta in (zw.r(rng.uniform(0, 1 + delta)), 0.0):
            amax = lp.alpha_max(beta)
            if amax == 0:
                assert not ref_loop.stable(1e-9, beta) or not ref_loop.stable(1e-3, beta)
                continue
            for k in (1, 4, 8, 12, 16):
                assert ref_loop.stable(amax * k / 16, beta), (delta, kappa, lam, kw, beta, amax)
            truth = ref_loop.alpha_sup(beta, amax)
            worst = max(worst, float((truth - amax) / truth))
    print(f"\n{zw.name}: random plants' alpha_max within {worst:.1e} below the truth")
    assert worst < TIGHT[zw.name]


def test_rotary_constructor_takes_the_plant_side_parts():
    """Device.rotary forwards the plant-side parts (README's example): the same limits as
    Device(..., rotary=True), and the parts lower K_mmax below the plant without them."""
    zwidth = _zwidth()
    J, b, T = 85.78e-7, 2.197e-3, 0.02
    parts = dict(delay=1, actuator_tau=0.01, hand=(J, 2 * b, 1e-4))
    rot = zwidth.Device.rotary(J, b, T, **parts)
    same = zwidth.Device(J, b, T, rotary=True, **parts)
    assert rot.is_rotary and rot.has_plant_parts and float(rot.actuator_tau) == 0.01
    assert float(rot.extremes().K_mmax) == float(same.extremes().K_mmax)
    assert float(rot.extremes().K_mmax) != float(zwidth.Device.rotary(J, b, T, delay=1).extremes().K_mmax)
