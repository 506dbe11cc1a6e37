# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The scene simulator (sim.h through zwidth._core.Simulator and zwidth.simulate) against
independent references (sim_reference.py): the analytic zero-order-hold solution in
mpmath at 50 digits, scipy's DOP853, and the roots of the characteristic polynomial.

1. The exact-discretization path (a scene with no effect) equals the 50-digit trajectory
   within a running rounding bound (sim_reference.rounding_bound), for delta from 0 to 50.
2. The RK4 path (the "hand" effect with a massless, limp hand: no force, but the plant is
   integrated) converges to the exact path at 4th order and agrees at rounding level for
   many substeps; scipy's DOP853, sample by sample, agrees with the exact path.
3. The 12 points of scenes/paper-fig15.toml: simulated verdicts equal the verdict from the
   roots of p(z); points 6, 8, 10, 12 lie in the legacy region but are unstable; the
   envelope growth per sample matches the spectral radius.
4. A random sweep away from the boundary: simulated verdict == mpmath verdict, never
   undecided.
The float build is not reachable from Python (the bindings are double): tests/c covers it.
Run with -s for the figures (worst errors, convergence ratios, agreement counts).
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from mpmath import mp, mpf

import sim_reference as R
import zwidth
from zwidth import _core

REPO = Path(__file__).resolve().parents[2]
FIG15 = REPO / "scenes" / "paper-fig15.toml"
U = R.U

# Per-sample error of the exact step, in units of u times the magnitudes of the terms each
# component adds up (sim_reference.term_scales), propagated by the closed loop
# (sim_reference.rounding_bound).  An a-priori count for x+ = x + phi_T v + x_gain F,
# v+ = e v + v_gain F, F = K (x_eq - x) - (B/T)(x - x_prev), every operation rounding
# once (a relative error u) and a coefficient within ZW_COEF_ULPS = 4 ulps (<= 8 u):
#   F:          x_eq - x, K *, x - x_prev, B / T, *, -                  -> <= 3 u per term
#   x_gain F:   T/m, * T, * c1/2 (3 u), c1 (8 u), delta = b T/m (2 u; |dln c1/dln delta|
#               <= 1), * F (u), F's 3 u                                 -> 17 u
#   phi_T v:    T * s/2 (u + 8 u + 2 u), * v                            -> 12 u
#   e v:        e (8 u, plus delta's 2 u times delta: term_scales' 1 + delta), * v
#   v_gain F:   T/m, * s/2 (2 u), s (8 u + 2 u), * F, F's 3 u           -> 16 u
#   additions   (two in x, one in v)                                    -> 2 u
# so at most 19 u of each term; 24 u leaves room for second-order terms.  A coefficient
# off by 1e-14 (45 u) fails at half the deltas or more (tried on mutated copies of sim.c).
C_EXACT = 24.0
# Per RK4 substep: x0 + (h/6)(v0 + 2 v1 + 2 v2 + v3) and the stages round each term a few
# times (<= 4 u of s_j); n substeps per sample commit at most n times that.
C_RK4 = 4.0
N_EXACT = 1000
DELTAS = (0.0, 1e-8, 1e-3, 0.5, 2.3, 3.0, 5.0, 50.0)


# Plants (m, T) per delta for the exact-path test (b = delta m / T): the paper's
# simulation plant (0.1 kg, 10 ms), its rotary drive (J = 85.78e-7 kg m^2, 20 ms), and others.
PLANTS = {0.0: (0.1, 0.01), 1e-8: (85.78e-7, 0.02), 1e-3: (2.0, 1e-3), 0.5: (0.1, 0.01),
          2.3: (0.1, 0.01), 3.0: (1.0, 5e-3), 5.0: (85.78e-7, 0.02), 50.0: (0.1, 0.01)}


def scene_at(delta, alpha, beta, m=0.1, T=0.01, **extra):
    """A linear scene with a nonzero initial state and a step of the equilibrium between
    samples 3 and 4 (t_step = 3.5 T: float and exact k T agree on which side)."""
    base = dict(x_init=0.1, v_init=-20.0 * T, x_eq_before=0.2, x_eq_after=1.0, t_step=3.5 * T)
    base.update(extra)
    return R.scene_from_normalized(delta, alpha, beta, m=m, T=T, **base)


def rho_of(scene):
    d, a, b = R.normalized(*(scene[k] for k in ("m", "b", "T", "K", "B")))
    return R.spectral_radius(d, a, b)[0]


def pick_points(delta, seed, wanted):
    """Gain points at delta with spectral radius in each of the `wanted` ranges (mpmath),
    drawn at random from a box around the stability region (deterministic seed)."""
    rng = np.random.default_rng(seed)
    a_top = 0.8 if delta < 0.5 else 4 * delta + 4
    out = []
    for lo, hi in wanted:
        for _ in range(20000):
            alpha = rng.uniform(0, a_top)
            beta = rng.uniform(-delta, delta + 2.5)
            rho = rho_of(scene_at(delta, alpha, beta))
            if lo <= rho <= hi:
                out.append((alpha, beta, rho))
                break
        else:
            raise AssertionError(f"no point with rho in [{lo}, {hi}] at delta {delta}")
    return out


def simulate(scene, n, signals=("x", "v")):
    return _core.Simulator(dict(scene)).run(n, signals)


def errors_against(xs, vs, sim, T):
    """|x_sim - x_ref| and T |v_sim - v_ref| per sample, the difference taken in mpmath."""
    ex = np.array([float(abs(mpf(float(a)) - b)) for a, b in zip(sim["x"], xs)])
    ev = np.array([float(abs(mpf(float(a)) - b)) for a, b in zip(sim["v"], vs)]) * T
    return ex, ev


# ---------------------------------------------------------------------------------------
# The reference checks itself: two derivations of the loop's poles agree
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("delta", DELTAS)
def test_reference_poles_two_ways(delta):
    """Eigenvalues of the closed-loop matrix built from the analytic ZOH step equal the
    roots of math.md's p(z) (so both the trajectory and the verdict references are right)."""
    for alpha, beta, rho in pick_points(delta, 1, [(0.3, 0.97), (1.003, 1.5)]):
        sc = scene_at(delta, alpha, beta)
        with mp.workdps(R.DPS):
            ev = mp.eig(R.closed_loop_matrix(sc))[0]
            d, a, b = R.normalized(*(sc[k] for k in ("m", "b", "T", "K", "B")))
            roots = R.spectral_radius(d, a, b)[1]
            for r in roots:
                assert min(abs(r - z) for z in ev) < mpf(10) ** -30 * max(1, abs(r)), (delta, alpha, beta)


# ---------------------------------------------------------------------------------------
# 1. The exact-discretization path against the 50-digit analytic solution
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("delta", DELTAS)
def test_exact_path_equals_mpmath(delta):
    """x and T v of every sample within C_EXACT u of the running bound: for the stable
    points that is at most C_EXACT u (sum_j ||A^j||) max s, however long the run; for the
    mildly unstable point the bound grows with the solution (rho^k) and the error with it."""
    points = pick_points(delta, 2, [(0.9, 0.97), (0.7, 0.9), (1.003, 1.03)])
    rows = []
    for alpha, beta, rho in points:
        sc = scene_at(delta, alpha, beta, *PLANTS[delta])
        xs, vs, Fs = R.exact_trajectory(sc, N_EXACT)
        sim = simulate(sc, N_EXACT, ("x", "v", "force"))
        ex, ev = errors_against(xs, vs, sim, sc["T"])
        bx, bv, norm_sum, s = R.rounding_bound(sc, xs, vs, 1.0)  # the bound per unit of c
        assert ex[0] == 0 and ev[0] == 0  # the initial state is given exactly
        qx, qv = ex[1:] / bx[1:], ev[1:] / bv[1:]
        # The force trace (in lengths, T^2/m F): F_k inherits alpha e_x,k + beta (e_x,k -
        # e_x,k-1) and rounds its own terms (3 u of each, within C_EXACT u).
        T2m = sc["T"] ** 2 / sc["m"]
        a, b = abs(sc["K"]) * T2m, abs(sc["B"]) * T2m / sc["T"]
        eF = np.array([float(abs(mpf(float(F)) - G)) for F, G in zip(sim["force"], Fs)]) * T2m
        _, _, f = R.magnitudes(sc, xs, vs)
        bF = (a + b) * bx + b * np.concatenate(([0.0], bx[:-1])) + U * f
        qF = eF[1:] / bF[1:]
        ratio = max(qx.max(), qv.max(), qF.max())
        k = int(np.argmax(np.maximum(qx, qv))) + 1
        assert ratio <= C_EXACT, (f"delta {delta} alpha {alpha} beta {beta}: error x {ex[k]:.3g}, T v {ev[k]:.3g} "
                                  f"at sample {k} is {ratio:.3g} times the c = 1 bound (budget {C_EXACT})")
        if rho < 1:
            # the stable loop's bound does not grow with the run
            assert max(bx.max(), bv.max()) <= norm_sum * s.max() * U
        rows.append((float(rho), norm_sum, (np.maximum(ex, ev) / (U * s)).max(), ratio))
    print(f"\n[exact vs mpmath] delta={delta:g}: " + "; ".join(
        f"rho {r:.4f}: sum||A^j|| {sw:.3g}, max err {e:.2f} u*s, {q:.2f} x the c=1 bound (budget {C_EXACT:g})"
        for r, sw, e, q in rows))


def test_exact_path_is_continuable():
    """Running in pieces gives the same samples as one run (the state carries over)."""
    sc = scene_at(2.3, 4.0, 0.5)
    whole = simulate(sc, 500, ("t", "x", "v", "force"))
    sim = _core.Simulator(dict(sc))
    parts = [sim.run(n, ("t", "x", "v", "force")) for n in (1, 0, 3, 196, 300)]
    for key in whole:
        assert np.array_equal(np.concatenate([p[key] for p in parts]), whole[key]), key
    assert sim.k == 500


# ---------------------------------------------------------------------------------------
# 2. Fine-step integration of the continuous plant
# ---------------------------------------------------------------------------------------


def limp_hand(scene, substeps):
    """The same scene integrated by RK4: a hand with no mass, stiffness or damping holds
    the handle all the time (forces exactly 0), which turns the integrator on."""
    return dict(scene, effects=_core.SIM_EFFECTS["hand"], hand_mass=0.0, hand_stiffness=0.0,
                hand_damping=0.0, hand_t_grasp=0.0, hand_t_release=math.inf, hand_from=0.0,
                hand_to=0.0, hand_speed=math.inf, substeps=substeps)


N_RK = 500


@pytest.mark.parametrize("delta", (0.5, 2.3, 5.0))
def test_rk4_converges_at_fourth_order(delta):
    """Max error over the run (relative to max |x|) against the 50-digit solution for
    n = 8 .. 512 substeps: once a h = delta / n <= 0.1 (asymptotic regime) and while the
    error is far above rounding, each doubling of n divides it by 16 +- 1.5 (order
    log2(ratio) in [3.86, 4.13])."""
    (alpha, beta, rho), = pick_points(delta, 3, [(0.8, 0.95)])
    sc = scene_at(delta, alpha, beta)
    xs, vs, _ = R.exact_trajectory(sc, N_RK)
    scale = max(abs(float(x)) for x in xs)
    ns = [8 * 2 ** i for i in range(7)]
    errs = []
    for n in ns:
        ex, _ = errors_against(xs, vs, simulate(limp_hand(sc, n), N_RK), sc["T"])
        errs.append(ex.max() / scale)
    ratios = [a / b for a, b in zip(errs, errs[1:])]
    checked = 0
    for n, e2, q in zip(ns, errs[1:], ratios):
        if delta / n <= 0.1 and e2 > 1e3 * n * U:
            assert 14.5 <= q <= 17.5, (delta, n, errs, ratios)
            checked += 1
    assert checked >= 2, (delta, errs)
    print(f"\n[RK4 convergence] delta={delta:g} rho={float(rho):.3f} n={ns}: rel err "
          + " ".join(f"{e:.2e}" for e in errs) + "; ratios " + R.fmt_ratio(ratios)
          + f" ({checked} in the asymptotic regime)")


@pytest.mark.parametrize("delta", (0.0, 1e-8, 0.5, 2.3, 5.0, 50.0))
def test_rk4_many_substeps_is_rounding_level(delta):
    """With n = 4096 substeps the RK4 path's truncation error is far below its rounding
    bound (4th-order extrapolation of test_rk4_converges: <= 1e-15 of max |x| for
    delta <= 5; at delta = 50 it only touches the velocity mode exp(-a t), gone within the
    sample); what remains is rounding, at most C_RK4 n u per sample in units of the plain
    term scale s_j (|x| + |T v| + the force in lengths), propagated like the exact path's:
    err_k <= C_RK4 n u sum_j |A^(k-1-j)| s_j.
    At delta = 0 (b = 0) RK4 is exact on the quadratic solution, so even n = 1 is
    rounding-level."""
    (alpha, beta, rho), = pick_points(delta, 4, [(0.8, 0.95)])
    sc = scene_at(delta, alpha, beta)
    xs, vs, _ = R.exact_trajectory(sc, N_RK)
    bx, bv, _, _ = R.rounding_bound(sc, xs, vs, 1.0, scales=R.plain_scales)
    cases = (1, 2, 4096) if delta == 0 else (4096,)
    out = []
    for n in cases:
        exact_sim = simulate(sc, N_RK)
        rk = simulate(limp_hand(sc, n), N_RK)
        ex, ev = errors_against(xs, vs, rk, sc["T"])
        ratio = max((ex[1:] / bx[1:]).max(), (ev[1:] / bv[1:]).max()) / n
        assert ratio <= C_RK4, (delta, n, ratio)
        gap = np.abs(rk["x"] - exact_sim["x"]).max() / np.abs(exact_sim["x"]).max()
        out.append(f"n={n}: {ratio:.3f} of n u sum||A^j|| s (budget {C_RK4:g}), |rk - exact path| {gap:.2e} rel")
    print(f"\n[RK4 rounding] delta={delta:g}: " + "; ".join(out))


@pytest.mark.parametrize("delta", (0.0, 1e-3, 0.5, 2.3, 5.0, 50.0))
def test_scipy_dop853_agrees_with_exact_path(delta):
    """solve_ivp (DOP853, rtol 1e-12, atol 1e-16 of the scale) over each sample under the
    ZOH force computed from its own state: the simulator's exact path agrees to 1e-9 of
    max |x| (and of max |v|) over 300 samples."""
    (alpha, beta, rho), = pick_points(delta, 5, [(0.8, 0.95)])
    sc = scene_at(delta, alpha, beta)
    n = 300
    with np.errstate(invalid="ignore", divide="ignore"):  # DOP853's error norm is 0/0 when exact
        x, v, F = R.scipy_trajectory(sc, n)
    sim = simulate(sc, n, ("x", "v", "force"))
    ex = np.abs(x - sim["x"]).max() / np.abs(sim["x"]).max()
    ev = np.abs(v - sim["v"]).max() / np.abs(sim["v"]).max()
    ef = np.abs(F - sim["force"]).max() / np.abs(sim["force"]).max()
    assert ex < 1e-9 and ev < 1e-9 and ef < 1e-9, (delta, ex, ev, ef)
    print(f"\n[scipy DOP853] delta={delta:g} rho={float(rho):.3f}: max rel diff x {ex:.2e}, v {ev:.2e}, F {ef:.2e}")


# ---------------------------------------------------------------------------------------
# 3. The 12 points of paper Fig. 15
# ---------------------------------------------------------------------------------------


def _point_number(label, position):
    found = re.findall(r"\d+", str(label))
    return int(found[-1]) if found else position + 1


@pytest.fixture(scope="module")
def fig15():
    """(number, Simulation, delta, alpha, beta, rho) for the 12 cases of the scene."""
    sims = zwidth.simulate(zwidth.load_scene(FIG15))
    assert len(sims) == 12
    out = []
    for i, s in enumerate(sims):
        p = s.params
        assert p.get("effects", 0) == 0  # a linear scene
        d, a, b = R.normalized(p["m"], p["b"], p["T"], p["K"], p["B"])
        rho = R.spectral_radius(d, a, b)[0]
        out.append((_point_number(s.label, i), s, d, a, b, rho))
    assert sorted(o[0] for o in out) == list(range(1, 13))
    return sorted(out, key=lambda o: o[0])


def test_fig15_points_are_the_papers(fig15):
    """delta = 2.3, 3, 5 (m = 0.1 kg, T = 0.01 s) for points 1-4, 5-8, 9-12, and a step of
    the equilibrium from 0 to 1 m."""
    for num, s, d, a, b, rho in fig15:
        p = s.params
        assert (p["m"], p["T"]) == (0.1, 0.01)
        assert abs(float(d) - (2.3, 3.0, 5.0)[(num - 1) // 4]) < 1e-12, (num, d)
        assert p.get("x_eq_after", 0.0) == 1.0 and p.get("x_eq_before", 0.0) == 0.0


def test_fig15_simulated_verdicts_match_mpmath(fig15):
    """Simulated outcome == the mpmath verdict (all roots of p(z) inside the unit circle),
    the core's analytic verdict agrees too, and 6, 8, 10, 12 are legacy-stable but
    unstable (the paper's point)."""
    rows = []
    for num, s, d, a, b, rho in fig15:
        truth = "stable" if rho < 1 else "unstable"
        legacy = R.legacy_stable(d, a, b)
        assert s.verdict.outcome == truth, (num, s.verdict, float(rho))
        assert bool(s.analytic.stable) == (truth == "stable"), (num, s.analytic)  # zwidth.Verdict
        assert s.agrees is True, num
        if num in (6, 8, 10, 12):
            assert legacy and truth == "unstable", (num, legacy, float(rho))
        rows.append(f"{num}: d={float(d):g} a={float(a):.4g} b={float(b):.4g} rho={float(rho):.5f} "
                    f"legacy={'S' if legacy else 'U'} sim={s.verdict.outcome}")
    print("\n[fig15] " + "\n[fig15] ".join(rows))


def growth_run(p, rho):
    """Envelope growth of the low-level run of scene params p over a window sized so the
    signal stays far from rounding (stable: the transient decays by at most 1e-9) and
    from overflow (unstable: grows by at most 1e250); the first quarter is skipped (the
    non-dominant modes), and the judge compares the 2nd and 4th quarters."""
    r = float(rho)
    limit = math.log(1e-9) / math.log(r) if r < 1 else math.log(1e250) / math.log(r)
    n = int(min(2000, max(40, limit)))
    n -= n % 4
    sc = {k: v for k, v in p.items() if k in ("m", "b", "T", "K", "B", "x_init", "v_init",
                                              "x_eq_before", "x_eq_after", "t_step")}
    x = simulate(sc, n, ("x",))["x"]
    return _core.sim_judge(x, n // 4, 3, 0.0), n


def test_fig15_growth_matches_spectral_radius(fig15):
    """The judge's growth per sample estimates rho.  Low-level runs sized to the signal
    (growth_run): within 1 % for the unstable points (n/2 samples between the judged
    windows), 2 % for the stable ones (their windows are shorter).  The scene's own runs
    (10 s, its [verdict] windows): within 2 % for the unstable points and for the stable
    ones whose last window is still far above rounding (1e-10 m; the others have settled
    to a few ulps and their "growth" is that of rounding noise)."""
    rows = []
    for num, s, d, a, b, rho in fig15:
        v, n = growth_run(s.params, rho)
        g, r = v["growth"], float(rho)
        assert abs(g / r - 1) <= (0.01 if r > 1 else 0.02), (num, g, r, n)
        sv = s.verdict
        if r > 1 or sv.amplitude_last > 1e-10:
            assert abs(sv.growth / r - 1) <= 0.02, (num, sv, r)
            scene_g = f", scene {sv.growth / r:.4f}"
        else:
            scene_g = ", scene settled"
        rows.append(f"{num}: {g / r:.4f} of rho (n={n}{scene_g})")
    print("\n[fig15 growth/rho] " + "; ".join(rows))


# ---------------------------------------------------------------------------------------
# 4. A random sweep away from the boundary
# ---------------------------------------------------------------------------------------


def test_random_sweep_verdicts():
    """~200 random (delta, alpha, beta) with rho outside [0.97, 1.03] (mpmath), on random
    real plants (m, T log-uniform, b, K, B from the normalized point), a unit step from
    rest over 2000 samples judged on two windows of 1000 with tolerance 1e-6 m: a stable
    loop decays by 0.97^1000 ~ 6e-14 between them, an unstable one grows by >= 1.03^1000 ~
    7e12 (or overflows, which the judge calls unstable).  Verdict == mpmath, never
    undecided."""
    rng = np.random.default_rng(2024)
    want = {"stable": 100, "unstable": 100}
    got = {"stable": 0, "unstable": 0}
    agree = undecided = tries = 0
    n = 2000
    while min(want[k] - got[k] for k in want) > 0 or sum(got.values()) < 200:
        tries += 1
        assert tries < 20000
        delta = 0.0 if rng.random() < 0.05 else 10 ** rng.uniform(-3, math.log10(50))
        a_top = 0.8 if delta < 0.5 else 4 * delta + 4
        alpha = rng.uniform(-0.1 * a_top, 1.3 * a_top)
        beta = rng.uniform(-delta - 1, delta + 3)
        m = 10 ** rng.uniform(-3, 1)
        T = 10 ** rng.uniform(-4, -1.5)
        sc = dict(m=m, T=T, b=delta * m / T, K=alpha * m / T ** 2, B=beta * m / T, x_eq_after=1.0)
        d, a, b = R.normalized(sc["m"], sc["b"], sc["T"], sc["K"], sc["B"])
        if a == 0:
            continue
        rho = R.spectral_radius(d, a, b)[0]
        if 0.97 <= rho <= 1.03:
            continue
        truth = "stable" if rho < 1 else "unstable"
        if got[truth] >= want[truth]:
            continue
        got[truth] += 1
        with np.errstate(all="ignore"):
            x = simulate(sc, n, ("x",))["x"]
        v = _core.sim_judge(x, n // 2, 2, 1e-6)
        undecided += v["outcome"] == "undecided"
        assert v["outcome"] == truth, (delta, alpha, beta, float(rho), v)
        agree += 1
    print(f"\n[random sweep] {agree}/{sum(got.values())} agree ({got['stable']} stable, "
          f"{got['unstable']} unstable; {tries} draws), undecided {undecided}")
