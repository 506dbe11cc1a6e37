# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The general loop from Python (zwidth.check/verdict/... with delay=, filter_pole=,
average=, differentiator=, and Device(..., delay=, velocity_filter=, differentiator=)).

Reference: the characteristic polynomial built here independently from the note's
definitions (general-loop.md, loop.h's transfer functions) in mpmath at 50 digits, with
the coefficients e, c1, c2 of tests/py/reference.py, and its roots by mpmath.polyroots.
"""
from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest

import reference as ref
import zwidth
from zwidth import _core

DPS = 50


def ref_poly(delta, alpha, beta, delay=0, pole=0.0, average=None, differentiator="backward"):
    """p(z) = 2 z^d (z - 1)(z - e) Dv + (c1 z + c2)(alpha Dv + beta Nv), highest power first,
    with T V(z) = Nv / Dv the velocity estimate (mpmath, exact inputs)."""
    with mp.workdps(DPS):
        c = ref.coeffs(delta, dps=DPS)
        P = np.polynomial.Polynomial  # coefficients lowest first, mpf entries
        z = P([mp.mpf(0), mp.mpf(1)])
        one = P([mp.mpf(1)])
        if differentiator == "backward":          # (z - 1) / z
            nv, dv = z - one, z
        else:                                     # 2 (z - 1) / (z + 1)
            nv, dv = 2 * (z - one), z + one
        if average is not None:                   # (1/n) sum_{i<n} z^-i = (sum z^(n-1-i)) / (n z^(n-1))
            s = P([mp.mpf(1)] * average)
            nv, dv = nv * s, dv * P([mp.mpf(0)] * (average - 1) + [mp.mpf(average)])
        elif pole != 0.0:                         # (1 - a) z / (z - a)
            a = mp.mpf(pole)
            nv, dv = nv * (1 - a) * z, dv * (z - a * one)
        zd = P([mp.mpf(0)] * delay + [mp.mpf(1)])
        plant_den = 2 * zd * (z - one) * (z - c.e * one)
        plant_num = P([c.c2, c.c1])
        p = plant_den * dv + plant_num * (mp.mpf(alpha) * dv + mp.mpf(beta) * nv)
        coef = list(p.coef)
        while len(coef) > 1 and coef[-1] == 0:
            coef.pop()
        while len(coef) > 1 and coef[0] == 0:  # a common factor z (the low-pass on z - 1 / z)
            coef.pop(0)
        return coef[::-1]


def ref_radius(*args, **kwargs):
    coef = ref_poly(*args, **kwargs)
    with mp.workdps(DPS):
        roots = mp.polyroots(coef, maxsteps=400, extraprec=200)
        return max(abs(r) for r in roots)


SPECS = [
    dict(delay=1),
    dict(delay=2),
    dict(delay=3, pole=0.3),
    dict(delay=0, pole=0.8),
    dict(delay=1, pole=0.6),
    dict(delay=1, average=4),
    dict(delay=0, average=2),
    dict(delay=1, differentiator="tustin"),
    dict(delay=0, pole=0.5, differentiator="tustin"),
]


def kw(spec):
    out = dict(spec)
    if "pole" in out:
        out["filter_pole"] = out.pop("pole")
    return out


@pytest.mark.parametrize("spec", SPECS, ids=lambda s: ",".join(f"{k}={v}" for k, v in s.items()))
def test_poly_equals_the_independent_construction(spec):
    for delta, alpha, beta in [(0.5, 0.3, 0.2), (3.0, 2.0, -1.0), (1e-3, 0.01, 0.004)]:
        got = zwidth.loop_poly(delta, alpha, beta, **kw(spec))
        want = np.array([float(c) for c in ref_poly(delta, alpha, beta, **spec)])
        # loop.h fixes the degree; a leading zero would be a different (wrong) layout
        assert got.shape == want.shape, (got, want)
        scale = np.max(np.abs(want))
        assert np.max(np.abs(got - want)) <= 1e-13 * scale, (got, want)


@pytest.mark.parametrize("spec", SPECS, ids=lambda s: ",".join(f"{k}={v}" for k, v in s.items()))
def test_verdict_agrees_with_the_roots(spec):
    rng = np.random.default_rng(12 + len(str(spec)))
    n = 40
    delta = 10 ** rng.uniform(-2, 0.7, n)
    alpha = rng.uniform(-0.1, 1.5, n)
    beta = rng.uniform(-0.5, 1.5, n) * delta
    stable = zwidth.check(delta, alpha, beta, **kw(spec))
    v = zwidth.verdict(delta, alpha, beta, **kw(spec))
    rho = zwidth.spectral_radius(delta, alpha, beta, **kw(spec))
    assert isinstance(v, zwidth.LoopVerdict)
    np.testing.assert_array_equal(v.stable, stable)
    decided = 0
    for i in range(n):
        r = float(ref_radius(delta[i], alpha[i], beta[i], **spec))
        assert abs(rho[i] - r) <= 1e-9 * max(1.0, r), (i, rho[i], r)
        if r >= 1.0:
            assert not stable[i], ("stable but rho =", r)        # safety, whatever the margin
            assert v.boundary[i] != 0
        if abs(r - 1.0) > 1e-9:
            assert bool(stable[i]) == (r < 1.0), (i, r)
            decided += 1
        if stable[i]:
            assert v.boundary[i] == 0 and v.theta[i] == 0 and not v.marginal[i]
    assert decided >= n - 2
    assert 0 < int(np.sum(stable)) < n  # the sample spans both sides


def test_deciding_boundary_names_and_frequency():
    # the new user's gains (m 0.12, b 0.8, T 1 ms, K 50 kN/m, B 50 N s/m) in the normalized space
    delta, alpha, beta = 0.8e-3 / 0.12, 5e4 * 1e-6 / 0.12, 50 * 1e-3 / 0.12
    v = zwidth.verdict(delta, alpha, beta, delay=1)
    assert not v.stable and v.deciding_name.startswith("complex pair at ")
    assert 0 < v.theta < math.pi and v.frequency == pytest.approx(v.theta / (2 * math.pi))
    coef = ref_poly(delta, alpha, beta, delay=1)
    with mp.workdps(DPS):
        top = max(mp.polyroots(coef, maxsteps=400, extraprec=200), key=abs)
    assert abs(float(mp.arg(top)) - float(v.theta)) < 1e-6 or abs(float(mp.arg(top)) + float(v.theta)) < 1e-6
    # beyond z = 1: negative stiffness; beyond z = -1: huge damping without delay
    assert zwidth.verdict(1.0, -0.5, 0.2, delay=1).deciding_name == "z=1"
    assert zwidth.verdict(0.1, 0.01, 30.0, filter_pole=0.1).deciding_name in ("z=-1",) or \
        zwidth.verdict(0.1, 0.01, 30.0, filter_pole=0.1).deciding_name.startswith("complex")
    assert zwidth.verdict(1.0, 0.1, 0.1, delay=1).deciding_name == ""


def test_ideal_loop_is_the_closed_form_bit_for_bit():
    rng = np.random.default_rng(5)
    delta = 10 ** rng.uniform(-3, 1, 500)
    alpha = rng.uniform(-1, 30, 500)
    beta = rng.uniform(-3, 10, 500)
    for kwargs in ({}, dict(delay=0, filter_pole=0.0, differentiator="backward")):
        np.testing.assert_array_equal(zwidth.check(delta, alpha, beta, **kwargs),
                                      _core.check(delta, alpha, beta, 0, False)["outputs"]["stable"])
        v = zwidth.verdict(delta, alpha, beta, **kwargs)
        assert isinstance(v, zwidth.Verdict)
        np.testing.assert_array_equal(v.violated, _core.check(delta, alpha, beta, 0, True)["outputs"]["violated"])
        rho = zwidth.spectral_radius(delta, alpha, beta, **kwargs)
        assert np.array_equal(rho, _core.spectral_radius(delta, alpha, beta)["outputs"]["rho"])
        w = zwidth.radius_within(delta, alpha, beta, 0.9, **kwargs)
        np.testing.assert_array_equal(w, _core.radius_within(delta, alpha, beta, 0.9)["outputs"]["within"])
    dev = zwidth.Device(0.1, 30.0, 0.01, delay=0, velocity_filter=None)
    assert dev.loop.ideal
    K = np.linspace(-100, 1e5, 300)
    np.testing.assert_array_equal(dev.is_stable(K, -5.0),
                                  _core.device_check(0.1, 30.0, 0.01, K, -5.0, 0, False)["outputs"]["stable"])


def test_general_path_agrees_with_the_closed_form_on_the_ideal_loop():
    # a low-pass with pole 0 and an average of 1 are the ideal loop through the general path
    rng = np.random.default_rng(7)
    delta = 10 ** rng.uniform(-2, 1, 300)
    alpha = rng.uniform(0, 25, 300)
    beta = rng.uniform(-2, 8, 300)
    closed = zwidth.verdict(delta, alpha, beta)
    for kwargs in (dict(filter_pole=np.zeros(300)), dict(average=1)):
        general = zwidth.verdict(delta, alpha, beta, **kwargs)
        decided = ~np.asarray(closed.marginal) & ~np.asarray(general.marginal)
        np.testing.assert_array_equal(np.asarray(general.stable)[decided], np.asarray(closed.stable)[decided])
        assert decided.sum() >= 295


def test_broadcasting():
    delta = np.array([[0.5], [2.0], [5.0]])
    alpha = np.linspace(0.1, 3, 4)
    poles = np.array([0.0, 0.5, 0.9, 0.3])
    out = zwidth.check(delta, alpha, 0.3, delay=1, filter_pole=poles)
    assert out.shape == (3, 4)
    for i in range(3):
        for j in range(4):
            assert out[i, j] == zwidth.check(float(delta[i, 0]), float(alpha[j]), 0.3, delay=1,
                                             filter_pole=float(poles[j]) or np.array(0.0))
    assert zwidth.spectral_radius(delta, alpha, 0.3, delay=2).shape == (3, 4)
    assert zwidth.radius_within(delta, alpha, 0.3, [0.5, 0.9, 1.0, 2.0], delay=2).shape == (3, 4)
    v = zwidth.verdict(delta, alpha, 0.3, delay=1)
    assert v.stable.shape == v.theta.shape == v.deciding_name.shape == (3, 4)
    assert isinstance(zwidth.check(1.0, 0.5, 0.2, delay=1), np.bool_)
    with pytest.raises(ValueError, match="broadcast"):
        zwidth.check([1.0, 2.0], [0.1, 0.2, 0.3], 0.1, delay=1)


@pytest.mark.parametrize("kwargs, parameter, status", [
    (dict(delay=-1), "delay", "ZW_ERR_DELAY"),
    (dict(delay=9), "delay", "ZW_ERR_DELAY"),
    (dict(delay=1.5), "delay", "ZW_ERR_DELAY"),
    (dict(delay="1"), "delay", "ZW_ERR_DELAY"),
    (dict(filter_pole=1.0), "filter_pole", "ZW_ERR_FILTER"),
    (dict(filter_pole=-0.1), "filter_pole", "ZW_ERR_FILTER"),
    (dict(filter_pole=float("nan")), "filter_pole", "ZW_ERR_NAN"),
    (dict(average=0), "average", "ZW_ERR_FILTER"),
    (dict(average=17), "average", "ZW_ERR_FILTER"),
    (dict(average=4, filter_pole=0.5), "average", "ZW_ERR_FILTER"),
    (dict(differentiator="forward"), "differentiator", "ZW_ERR_ARG"),
])
def test_errors_name_the_parameter(kwargs, parameter, status):
    for f in (zwidth.check, zwidth.verdict, zwidth.spectral_radius):
        with pytest.raises(zwidth.ZwidthError) as info:
            f(1.0, 0.5, 0.2, **kwargs)
        assert info.value.parameter == parameter and info.value.status == status
        assert parameter in str(info.value)


def test_mask_and_region():
    out = zwidth.check(1.0, 0.1, 0.1, filter_pole=[0.5, 1.5], errors="mask")
    assert out.tolist() == [True, False]
    rho = zwidth.spectral_radius(1.0, 0.1, 0.1, filter_pole=[0.5, 1.5], errors="mask")
    assert np.isfinite(rho[0]) and np.isnan(rho[1])
    with pytest.raises(ValueError, match="ideal loop"):
        zwidth.check(1.0, 0.5, 0.2, delay=1, region="legacy")


# ---------------------------------------------------------------------------------------
# Device
# ---------------------------------------------------------------------------------------


def test_new_user_case():
    """Gains the ideal analysis calls stable (rho 0.94) are unstable with one sample of delay."""
    dev = zwidth.Device(0.12, 0.8, 1e-3)
    late = zwidth.Device(0.12, 0.8, 1e-3, delay=1)
    assert dev.is_stable(5e4, 50.0) and dev.spectral_radius(5e4, 50.0) == pytest.approx(0.9411, abs=1e-4)
    assert not late.is_stable(5e4, 50.0)
    v = late.verdict(5e4, 50.0)
    assert isinstance(v, zwidth.LoopVerdict) and v.frequency_unit == "Hz"
    assert v.deciding_name.startswith("complex pair at ") and v.deciding_name.endswith(" Hz")
    assert v.frequency == pytest.approx(v.theta / (2 * math.pi * 1e-3))
    r = float(ref_radius(0.8e-3 / 0.12, 5e4 * 1e-6 / 0.12, 50 * 1e-3 / 0.12, delay=1))
    assert late.spectral_radius(5e4, 50.0) == pytest.approx(r, rel=1e-9) and r > 1.2
    assert late.margin(5e4, 50.0) == pytest.approx(1 - r, rel=1e-8)
    assert "1 sample delay" in repr(late)


def test_device_agrees_with_the_normalized_functions():
    rng = np.random.default_rng(3)
    m = 10 ** rng.uniform(-2, 0, 60)
    b = 10 ** rng.uniform(-1, 1.5, 60)
    T = 10 ** rng.uniform(-4, -2, 60)
    delta = b * T / m
    alpha = rng.uniform(0, 1.2, 60)
    beta = rng.uniform(-0.5, 1.0, 60) * delta + rng.uniform(0, 0.5, 60)
    K, B = alpha * m / T ** 2, beta * m / T
    for delay, vf in ((1, None), (2, ("lowpass", 30.0)), (0, ("average", 3)), (1, ("pole", 0.7))):
        dev = zwidth.Device(m, b, T, delay=delay, velocity_filter=vf)
        pole = 0.0 if dev.filter_pole is None else dev.filter_pole
        average = vf[1] if vf is not None and vf[0] == "average" else None
        n = dev.normalize(K, B)
        rho_n = zwidth.spectral_radius(n.delta, n.alpha, n.beta, delay=delay, filter_pole=pole, average=average)
        rho_d = dev.spectral_radius(K, B)
        np.testing.assert_allclose(rho_d, rho_n, rtol=1e-12)
        away = np.abs(rho_n - 1) > 1e-6
        np.testing.assert_array_equal(np.asarray(dev.is_stable(K, B))[away], (rho_n < 1)[away])
        np.testing.assert_array_equal(
            np.asarray(zwidth.check(n.delta, n.alpha, n.beta, delay=delay, filter_pole=pole, average=average))[away],
            (rho_n < 1)[away])
        assert 0 < int(np.sum(rho_n < 1)) < 60


def test_lowpass_pole_from_the_cutoff():
    T = np.array([1e-4, 1e-3, 0.01])
    dev = zwidth.Device(0.1, 1.0, T, velocity_filter=("lowpass", 30.0))
    with mp.workdps(40):
        want = [float(mp.exp(-2 * mp.pi * 30 * mp.mpf(t))) for t in T]
    np.testing.assert_allclose(dev.filter_pole, want, rtol=4e-16)
    same = zwidth.Device(0.1, 1.0, 1e-3, velocity_filter="lowpass:30Hz")
    assert same.filter_pole == dev.filter_pole[1]


@pytest.mark.parametrize("kwargs, parameter", [
    (dict(velocity_filter=("lowpass", 500.0)), "velocity_filter"),   # = Nyquist at T = 1 ms
    (dict(velocity_filter=("lowpass", 0.0)), "velocity_filter"),
    (dict(velocity_filter=("lowpass", -3.0)), "velocity_filter"),
    (dict(velocity_filter=("average", 0)), "velocity_filter"),
    (dict(velocity_filter=("average", 17)), "velocity_filter"),
    (dict(velocity_filter=("pole", 1.0)), "velocity_filter"),
    (dict(velocity_filter=("bandpass", 3.0)), "velocity_filter"),
    (dict(velocity_filter="lowpass:fast"), "velocity_filter"),
    (dict(velocity_filter=30.0), "velocity_filter"),
    (dict(delay=9), "delay"),
    (dict(delay=-1), "delay"),
    (dict(differentiator="central"), "differentiator"),
])
def test_device_errors_name_the_parameter(kwargs, parameter):
    with pytest.raises(zwidth.ZwidthError) as info:
        zwidth.Device(0.1, 1.0, 1e-3, **kwargs)
    assert info.value.parameter == parameter, str(info.value)


def test_nyquist_named_in_the_message():
    with pytest.raises(zwidth.ZwidthError, match=r"Nyquist .* 500 Hz"):
        zwidth.Device(0.1, 1.0, [1e-4, 1e-3], velocity_filter=("lowpass", 700.0))
    dev = zwidth.Device(0.1, 1.0, [1e-4, 1e-3], velocity_filter=("lowpass", 700.0), errors="mask")
    assert dev.is_stable(100.0, 1.0).tolist()[1] is False
    assert np.isnan(dev.spectral_radius(100.0, 1.0)[1])


def test_closed_forms_of_the_paper_are_refused_for_a_loop():
    dev = zwidth.Device(0.12, 0.8, 1e-3, delay=1)
    with pytest.raises(zwidth.LoopNotSupported) as info:
        dev.influence()
    assert isinstance(info.value, NotImplementedError) and isinstance(info.value, zwidth.ZwidthError)
    assert "1 sample delay" in str(info.value)
    assert dev.ideal().influence().K_mmax > 0 and dev.ideal().loop.ideal
    with pytest.raises(ValueError, match="ideal loop"):
        dev.is_stable(5e4, 50.0, region="legacy")


@pytest.mark.parametrize("spec", [dict(delay=1), dict(delay=2, pole=0.5), dict(delay=1, average=3),
                                  dict(delay=0, pole=0.9)],
                         ids=lambda s: ",".join(f"{k}={v}" for k, v in s.items()))
def test_alpha_max_is_certified_and_tight(spec):
    for delta in (0.05, 1.0, 4.0):
        betas = np.linspace(-0.5 * delta, 1.0, 5)
        amax = zwidth.alpha_max(delta, betas, **kw(spec))
        for beta, a in zip(betas, amax):
            if a == 0.0:
                assert float(ref_radius(delta, 1e-6, beta, **spec)) >= 1 - 1e-9 or \
                    not zwidth.check(delta, 1e-6, beta, **kw(spec))
                continue
            for f in (1e-3, 0.25, 0.5, 0.75, 0.999):
                assert float(ref_radius(delta, f * a, beta, **spec)) < 1, (delta, beta, a, f)
            assert float(ref_radius(delta, a * (1 + 1e-4), beta, **spec)) > 1 - 1e-6, (delta, beta, a)


def test_beta_interval_and_extremes_of_a_loop():
    spec = dict(delay=1, pole=0.5)
    delta = 1.0
    iv = zwidth.beta_interval(delta, 0.2, **kw(spec))
    assert iv.nonempty and iv.lo < iv.hi
    for f in (0.001, 0.3, 0.7, 0.999):
        assert float(ref_radius(delta, 0.2, iv.lo + f * (iv.hi - iv.lo), **spec)) < 1
    w = iv.hi - iv.lo
    assert float(ref_radius(delta, 0.2, iv.hi + 1e-4 * w, **spec)) > 1 - 1e-6
    ex = zwidth.extremes(delta, **kw(spec))
    assert isinstance(ex, zwidth.LoopExtremes)
    ideal = zwidth.extremes(delta)
    assert 0 < ex.alpha_mmax < ideal.alpha_mmax and ex.beta_mmax <= ideal.beta_mmax
    assert float(ref_radius(delta, 0.999 * ex.alpha_mmax, ex.beta_at_alpha_mmax, **spec)) < 1
    assert ex.alpha_p_max == zwidth.alpha_max(delta, 0.0, **kw(spec))


def test_device_limits_of_a_loop():
    m, b, T = 0.12, 0.8, 1e-3
    dev = zwidth.Device(m, b, T, delay=1)
    ex = dev.extremes()
    assert isinstance(ex, zwidth.DeviceLoopExtremes)
    n = zwidth.extremes(b * T / m, delay=1)
    k = m / T ** 2
    assert ex.K_mmax <= n.alpha_mmax * k and ex.K_mmax == pytest.approx(n.alpha_mmax * k, rel=1e-12)
    assert 0 < ex.K_mmax < dev.ideal().extremes().K_mmax
    K_max = dev.k_max([0.0, 20.0, 50.0])
    assert K_max[0] == pytest.approx(ex.K_p_max, rel=1e-12)
    with mp.workdps(DPS):
        for B, K in zip([0.0, 20.0, 50.0], K_max):
            a = mp.mpf(K) * mp.mpf(T) ** 2 / mp.mpf(m)
            r = ref_radius(mp.mpf(b) * mp.mpf(T) / mp.mpf(m), a * (1 - mp.mpf("1e-9")), mp.mpf(B) * mp.mpf(T) / mp.mpf(m),
                           delay=1)
            assert r < 1
    rng = dev.b_range(2000.0)
    assert rng.nonempty and rng.lo < 20 < rng.hi
    assert dev.is_stable(2000.0, np.linspace(rng.lo, rng.hi, 50)[1:-1]).all()
    assert not dev.b_range(5e4).nonempty            # the new user's K: no B works with the delay


def test_loop_influence_of_the_new_users_plant():
    dev = zwidth.Device(0.12, 0.8, 1e-3, delay=1, velocity_filter=("lowpass", 100.0))
    inf = dev.loop_influence()
    assert inf.K_mmax_ideal == dev.ideal().extremes().K_mmax
    assert inf.K_mmax == dev.extremes().K_mmax and 0 < inf.K_mmax_kept < 1
    assert list(inf.delays) == [0, 1, 2, 3] and np.all(np.diff(inf.K_mmax_by_delay) < 0)
    assert 100.0 in inf.cutoffs and inf.K_mmax_at_best_cutoff >= inf.K_mmax
    assert inf.best_cutoff < 500.0 and inf.K_mmax_at_best_cutoff == np.nanmax(inf.K_mmax_by_cutoff)
    assert "keeps" in inf.advice and "Hz keeps most" in inf.advice
    with pytest.raises(ValueError, match="one plant"):
        zwidth.Device([0.1, 0.2], 0.8, 1e-3, delay=1).loop_influence()


def test_device_rounding_is_guarded_near_the_boundary():
    """Bisect K to the verdict's switch at a fixed B; the last K called stable must be stable
    for the exact real inputs (mpmath normalization, no rounding)."""
    m, b, T, B = 0.12, 0.8, 1e-3, 5.0
    for delay, vf in ((1, None), (2, ("pole", 0.6))):
        dev = zwidth.Device(m, b, T, delay=delay, velocity_filter=vf)
        lo, hi = 1.0, 1e6
        assert dev.is_stable(lo, B) and not dev.is_stable(hi, B)
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if mid in (lo, hi):
                break
            lo, hi = (mid, hi) if dev.is_stable(mid, B) else (lo, mid)
        with mp.workdps(DPS):
            delta = mp.mpf(b) * mp.mpf(T) / mp.mpf(m)
            alpha = mp.mpf(lo) * mp.mpf(T) ** 2 / mp.mpf(m)
            beta = mp.mpf(B) * mp.mpf(T) / mp.mpf(m)
            pole = 0.0 if vf is None else vf[1]
            r = ref_radius(delta, alpha, beta, delay=delay, pole=pole)
        assert r < 1, (delay, lo, r)


def test_device_gain_that_underflows_is_refused():
    """A non-zero gain whose normalized value underflows has no relative error bound: the
    kernels go through device_loop.h, which refuses it (masked: not stable, NaN limits)."""
    dev = zwidth.Device(0.12, 0.8, 1e-3, delay=1, errors="mask")
    tiny = 5e-324  # K T^2 / m and B T / m both underflow to 0
    assert dev.is_stable([tiny, 1.0], 0.0).tolist() == [False, True]
    assert np.isnan(dev.spectral_radius(tiny, 0.0))
    assert np.isnan(dev.k_max(tiny)) and float(dev.k_max(0.0)) > 0.0


def test_device_k_max_never_above_the_exact_inputs_limit():
    """Random plants and loops: K_max from real units, normalized exactly (mpmath): just
    below it every root is inside, a little above one is not (the limit is also tight)."""
    rng = np.random.default_rng(11)
    checked = 0
    for _ in range(12):
        m = float(10 ** rng.uniform(-2, 0))
        T = float(10 ** rng.uniform(-4, -2))
        b = float(10 ** rng.uniform(-1, 0.5)) * m / T * 0.5
        B = float(rng.uniform(0.0, 0.8)) * m / T
        delay = int(rng.integers(1, 3))
        cutoff = float(rng.uniform(0.05, 0.4) / T)
        dev = zwidth.Device(m, b, T, delay=delay, velocity_filter=("lowpass", cutoff))
        K = float(dev.k_max(B))
        if K == 0.0:
            continue
        checked += 1
        with mp.workdps(DPS):
            delta = mp.mpf(b) * mp.mpf(T) / mp.mpf(m)
            beta = mp.mpf(B) * mp.mpf(T) / mp.mpf(m)
            alpha = mp.mpf(K) * mp.mpf(T) ** 2 / mp.mpf(m)
            pole = float(dev.filter_pole)
            assert ref_radius(delta, alpha * (1 - mp.mpf("1e-12")), beta, delay=delay, pole=pole) < 1
            assert ref_radius(delta, alpha * mp.mpf("0.5"), beta, delay=delay, pole=pole) < 1
            assert ref_radius(delta, alpha * (1 + mp.mpf("1e-4")), beta, delay=delay, pole=pole) > 1 - mp.mpf("1e-6")
    assert checked >= 8
