# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Plant-side parts (issue 16: actuator lag tau, hand (m_h, b_h, k_h), stiffness k_p) in
the normalized API (kappa=, lambda_=), the sensitivities (Device.sensitivity, zwidth
advise), the figures (zwidth plot, zwidth.plot.plant_region / plant_influence).

References: the 50-digit state-space loop of test_loop_plant_ref.RefLoop (expm of the
augmented ZOH matrix, Faddeev-LeVerrier, Schur-Cohn; nothing of the C code's transfer
functions), and for K_mmax its sup over beta of the bisected stable alpha (golden section),
differenced with the library's steps.
"""
from __future__ import annotations

import json
import math
import subprocess

import numpy as np
import pytest
from mpmath import mp, mpf

import zwidth
from test_cli import run, run_json
from test_loop_plant_ref import RefLoop

J, b, T = 85.78e-7, 2.197e-3, 0.02   # the paper's drive (rotary)
HAND = (J, 2 * b, 1e-4)
DRIVE = ("--preset", "paper-drive")


def _normalized(tau=0.0, hand=(0.0, 0.0, 0.0), k_p=0.0):
    """(delta, kappa, lambda, M) of the paper's drive with these parts (plant.h)."""
    m_h, b_h, k_h = hand
    M = J + m_h
    return (b + b_h) * T / M, (k_p + k_h) * T ** 2 / M, tau / T, M


# ---------------------------------------------------------------------------------------
# The normalized API: kappa=, lambda_= against real units and the reference
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("delay", [0, 1])
@pytest.mark.parametrize("parts", [dict(tau=1e-3), dict(k_p=1e-3), dict(hand=HAND),
                                   dict(tau=1e-2, hand=HAND, k_p=2e-3)])
def test_real_units_agree_with_normalized(delay, parts):
    """A Device with tau, a hand and k_p and the normalized functions at the corresponding
    (delta, kappa, lambda) give the same limits after scaling by M/T^2 and M/T (the Device's
    are pulled inward by its unit conversion's rounding, a few ulps)."""
    delta, kappa, lam, M = _normalized(**parts)
    dev = zwidth.Device.rotary(J, b, T, delay=delay, actuator_tau=parts.get("tau", 0.0),
                               hand=parts.get("hand"), stiffness=parts.get("k_p", 0.0))
    n = zwidth.extremes(delta, delay=delay, kappa=kappa, lambda_=lam)
    e = dev.extremes()
    for real, norm, scale in ((e.K_mmax, n.alpha_mmax, T ** 2 / M), (e.B_mmax, n.beta_mmax, T / M),
                              (e.B_mmin, n.beta_mmin, T / M), (e.K_p_max, n.alpha_p_max, T ** 2 / M)):
        assert float(real) * scale == pytest.approx(float(norm), rel=1e-9, abs=1e-12)
    # the beta of the top of a smooth maximum is known to ~sqrt(u) only (flat in beta)
    assert float(e.B_at_K_mmax) * T / M == pytest.approx(float(n.beta_at_alpha_mmax), rel=1e-6, abs=1e-9)
    Bs = np.linspace(float(e.B_mmin), float(e.B_mmax), 23)[1:-1]
    a = np.asarray(zwidth.alpha_max(delta, Bs * T / M, delay=delay, kappa=kappa, lambda_=lam))
    assert np.asarray(dev.k_max(Bs)) * T ** 2 / M == pytest.approx(a, rel=1e-9, abs=1e-12)
    Ks = np.linspace(0.05, 0.9, 7) * float(e.K_mmax)
    iv = zwidth.beta_interval(delta, Ks * T ** 2 / M, delay=delay, kappa=kappa, lambda_=lam)
    dv = dev.b_range(Ks)
    assert np.asarray(dv.lo) * T / M == pytest.approx(np.asarray(iv.lo), rel=1e-9, abs=1e-12)
    assert np.asarray(dv.hi) * T / M == pytest.approx(np.asarray(iv.hi), rel=1e-9, abs=1e-12)
    # verdicts: the same points, in either units
    KK, BB = np.meshgrid(np.linspace(-0.1, 1.2, 9) * float(e.K_mmax), np.linspace(-1.2, 1.2, 9) * float(e.B_mmax))
    real_v = np.asarray(dev.is_stable(KK, BB))
    norm_v = np.asarray(zwidth.check(delta, KK * T ** 2 / M, BB * T / M, delay=delay, kappa=kappa, lambda_=lam))
    differ = real_v != norm_v   # only within rounding of the boundary
    rho = np.asarray(dev.spectral_radius(KK, BB))
    assert np.all(np.abs(1.0 - rho[differ]) < 1e-9)


@pytest.mark.parametrize("delta,kappa,lam,delay", [(0.5, 0.1, 0.0, 0), (0.05, 0.0, 0.5, 1), (2.0, 0.3, 0.2, 1),
                                                   (0.2, 1e-3, 3.0, 0)])
def test_normalized_against_reference(delta, kappa, lam, delay):
    """check (kappa=, lambda_=) never calls an unstable point stable; alpha_max is
    certified (just below it stable, just above not, by the reference)."""
    ref = RefLoop(delta, kappa, lam, delay=delay)
    ext = zwidth.extremes(delta, delay=delay, kappa=kappa, lambda_=lam)
    rng = np.random.default_rng(16)
    alphas = rng.uniform(-0.2, 1.3, 40) * float(ext.alpha_mmax)
    betas = rng.uniform(float(ext.beta_mmin) - 0.2, 1.2 * float(ext.beta_mmax), 40)
    got = np.asarray(zwidth.check(delta, alphas, betas, delay=delay, kappa=kappa, lambda_=lam))
    for a, be, g in zip(alphas, betas, got):
        truth = ref.stable(float(a), float(be))
        assert not (g and not truth), (a, be)
        if truth and not g:   # a false "unstable" only within the rounding band
            assert abs(1 - ref.rho(float(a), float(be))) < 1e-7
    for be in np.linspace(float(ext.beta_mmin), float(ext.beta_mmax), 6)[1:-1]:
        am = float(zwidth.alpha_max(delta, be, delay=delay, kappa=kappa, lambda_=lam))
        assert ref.stable(am * (1 - 1e-9), be) and not ref.stable(am * (1 + 1e-6), be)


def test_kappa_lambda_zero_is_the_paper_plant_and_errors_name_them():
    deltas = np.array([0.01, 0.5, 5.0])
    assert np.array_equal(zwidth.extremes(deltas, delay=1, kappa=0.0, lambda_=0.0).alpha_mmax,
                          zwidth.extremes(deltas, delay=1).alpha_mmax)
    assert np.array_equal(zwidth.alpha_max(deltas, 0.1, kappa=0.0), zwidth.alpha_max(deltas, 0.1))
    # tiny parts move the limits continuously from the ideal plant's
    small = zwidth.extremes(deltas, kappa=1e-9, lambda_=1e-9).alpha_mmax
    assert np.asarray(small) == pytest.approx(np.asarray(zwidth.extremes(deltas).alpha_mmax), rel=1e-6)
    assert isinstance(zwidth.verdict(0.5, 0.2, 0.1, kappa=0.1), zwidth.LoopVerdict)
    with pytest.raises(zwidth.ZwidthError) as err:
        zwidth.check(0.5, 0.2, 0.1, kappa=-1.0)
    assert err.value.parameter == "kappa" and "kappa" in str(err.value)
    with pytest.raises(zwidth.ZwidthError) as err:
        zwidth.alpha_max(0.5, 0.1, lambda_=float("nan"))
    assert err.value.parameter == "lambda_"
    masked = zwidth.alpha_max(0.5, 0.1, lambda_=np.array([0.1, -1.0]), errors="mask")
    assert math.isfinite(masked[0]) and math.isnan(masked[1])
    with pytest.raises(ValueError, match="exact region"):
        zwidth.check(0.5, 0.2, 0.1, kappa=0.1, region="legacy")
    # with stiffness the z = 1 boundary is alpha = -kappa: small negative alphas are stable
    assert bool(zwidth.check(0.5, -0.05, 0.2, kappa=0.1)) and not bool(zwidth.check(0.5, -0.15, 0.2, kappa=0.1))


# ---------------------------------------------------------------------------------------
# Sensitivities against finite differences of the reference's K_mmax
# ---------------------------------------------------------------------------------------


def _ref_k_mmax(dev):
    """K_mmax of a scalar Device with parts by the reference: sup over beta (golden section)
    of the sup of stable alpha (bisection), scaled by M/T^2.  The library's values only
    bracket the searches; every end used is decided by the reference."""
    k_p, tau = float(dev.stiffness), float(dev.actuator_tau)
    m_h, b_h, k_h = (float(v) for v in dev.hand)
    m, bb, TT = float(dev.m), float(dev.b), float(dev.T)
    with mp.workdps(40):
        M = mpf(m) + mpf(m_h)
        ref = RefLoop((mpf(bb) + mpf(b_h)) * TT / M, (mpf(k_p) + mpf(k_h)) * mpf(TT) ** 2 / M, mpf(tau) / TT,
                      delay=dev.loop.delay)
        lim = dev.extremes()
        a0 = mpf(float(lim.K_mmax)) * mpf(TT) ** 2 / M
        b0 = mpf(float(lim.B_at_K_mmax)) * TT / M

        def sup(beta):
            lo, hi = a0 * mpf("0.98"), a0 * mpf("1.02")
            assert ref.stable(lo, beta) and not ref.stable(hi, beta)
            while hi - lo > a0 * mpf(10) ** -13:
                mid = (lo + hi) / 2
                lo, hi = (mid, hi) if ref.stable(mid, beta) else (lo, mid)
            return lo

        g = (mp.sqrt(5) - 1) / 2
        w = (mpf(float(lim.B_mmax)) - mpf(float(lim.B_mmin))) * TT / M * mpf("0.03")
        x0, x3 = b0 - w, b0 + w
        x1, x2 = x3 - g * (x3 - x0), x0 + g * (x3 - x0)
        f1, f2 = sup(x1), sup(x2)
        for _ in range(34):
            if f1 > f2:
                x3, x2, f2 = x2, x1, f1
                x1 = x3 - g * (x3 - x0)
                f1 = sup(x1)
            else:
                x0, x1, f1 = x1, x2, f2
                x2 = x0 + g * (x3 - x0)
                f2 = sup(x2)
        return float(max(f1, f2) * M / mpf(TT) ** 2)


def _shifted(name, value):
    kw = dict(delay=1, actuator_tau=1e-3, hand=HAND, stiffness=0.0)
    if name == "actuator_tau":
        kw["actuator_tau"] = value
    elif name == "b_h":
        kw["hand"] = (HAND[0], value, HAND[2])
    elif name == "stiffness":
        kw["stiffness"] = value
    return zwidth.Device.rotary(J, b, T, **kw)


@pytest.mark.parametrize("name", ["actuator_tau", "b_h", "stiffness"])
def test_sensitivity_against_reference_differences(name):
    """dK_mmax/dp of Device.sensitivity (delay 1, lag 1 ms, a hand) equals the same finite
    difference of the reference's K_mmax: central for tau and b_h, one-sided from 0 for k_p."""
    dev = _shifted("none", 0.0)
    sens = dev.sensitivity()
    row = sens[name]
    h, v = row["step"], row["value"]
    if row["one_sided"]:
        f = [_ref_k_mmax(_shifted(name, v + k * h)) for k in (0, 1, 2)]
        ref = (-3 * f[0] + 4 * f[1] - f[2]) / (2 * h)
    else:
        ref = (_ref_k_mmax(_shifted(name, v + h)) - _ref_k_mmax(_shifted(name, v - h))) / (2 * h)
    scale = sens.K_mmax / max(v, h)   # the slope's natural size
    assert row["dK_mmax"] == pytest.approx(ref, rel=1e-4, abs=1e-6 * scale)


def test_sensitivity_matches_the_papers_trends_on_the_ideal_plant():
    """On the paper's plant the numerical trends of m, b, T equal the closed-form ones of
    Device.influence (paper Section IV), at plants on either side of its turning points."""
    for m in (1e-7, 85.78e-7, 1e-3):
        dev = zwidth.Device.rotary(m, b, T)
        inf = dev.influence()
        sens = dev.sensitivity()
        sign = {"rises": 1, "falls": -1, "flat": 0}
        for name, field in (("J", "K_vs_m"), ("b", "K_vs_b"), ("T", "K_vs_T")):
            assert sign[sens[name]["K_trend"]] == int(getattr(inf, field)), (m, name)
        for name, field in (("J", "B_vs_m"), ("b", "B_vs_b"), ("T", "B_vs_T")):
            assert sign[sens[name]["B_trend"]] == int(getattr(inf, field)), (m, name)
        # the hand's mass enters only through M = J + m_h: the same slope as J
        assert sens["m_h"]["dK_mmax"] == pytest.approx(sens["J"]["dK_mmax"], rel=1e-3)


def test_hand_enlarges_the_region_in_the_sensitivity_sign():
    """Hulin et al. (2014): coupling a hand enlarges the region.  On the drive with one
    sample of delay and nothing attached, the slopes from 0 of the hand's damping and
    stiffness are positive (K_mmax rises), and the whole hand more than doubles K_mmax."""
    plain = zwidth.Device.rotary(J, b, T, delay=1)
    sens = plain.sensitivity()
    assert sens["b_h"]["one_sided"] and sens["b_h"]["dK_mmax"] > 0 and sens["b_h"]["K_trend"] == "rises"
    assert sens["k_h"]["dK_mmax"] > 0
    held = zwidth.Device.rotary(J, b, T, delay=1, hand=HAND)
    assert float(held.extremes().K_mmax) > 2.5 * float(plain.extremes().K_mmax)
    # and a lag costs: K_mmax falls with tau from 0
    assert sens["actuator_tau"]["dK_mmax"] < 0


# ---------------------------------------------------------------------------------------
# The command line: advise and plot with plant-side parts
# ---------------------------------------------------------------------------------------

PARTS = ("--delay", "1", "--actuator-tau", "1e-3", "--hand", f"{J},{2 * b},1e-4")


def test_advise_with_parts_reports_the_sensitivities():
    obj = run_json("advise", *DRIVE, *PARTS)
    dev = zwidth.Device.rotary(J, b, T, delay=1, actuator_tau=1e-3, hand=HAND)
    sens = dev.sensitivity()
    rows = {r["name"]: r for r in obj["sensitivity"]["parameters"]}
    assert set(rows) == {"J", "b", "T", "actuator_tau", "m_h", "b_h", "k_h", "stiffness"}
    for name in rows:
        assert rows[name]["dK_mmax"] == sens[name]["dK_mmax"]
    assert obj["K_mmax"] == float(dev.extremes().K_mmax)
    assert obj["without_plant_parts"]["K_mmax"] == float(zwidth.Device.rotary(J, b, T, delay=1).extremes().K_mmax)
    assert rows["b_h"]["K_trend"] == "rises" and rows["actuator_tau"]["K_trend"] == "falls"
    assert "numerical" in obj["sensitivity"]["method"]
    text = run("advise", *DRIVE, *PARTS, "--K", "0.2", "--B", "1e-3")
    assert text.returncode == 0, text.stderr
    assert "numerical: finite differences of the certified limits" in text.stdout
    assert "hand damping b_h" in text.stdout and "CERTIFIED" in text.stdout
    # gains beyond the region: not certified, with what to change
    bad = run_json("advise", *DRIVE, *PARTS, "--K", "0.5", "--B", "1e-3", code=1)
    assert bad["gains"]["certified"] is False and bad["gains"]["suggestions"]


@pytest.mark.parametrize("kind", ["region", "device", "influence"])
def test_plot_with_parts_writes_the_figure(tmp_path, kind):
    out = tmp_path / f"{kind}.png"
    obj = run_json("plot", kind, *DRIVE, *PARTS, "--K", "0.2", "--B", "1e-3", "-o", out)
    assert obj["file"] == str(out) and out.stat().st_size > 10_000 and obj["bytes"] == out.stat().st_size
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_plot_refusals_and_help():
    r = run("plot", "extremes", "--stiffness", "1")
    assert r.returncode == 2 and "plot region" in r.stderr
    r = run("check", "--m", "0.1:0.2", "--b", "1", "--T", "1e-3", "--K", "1", "--B", "0", "--actuator-tau", "1e-3")
    assert r.returncode == 2 and "certified without an actuator lag" in r.stderr
    help_text = run("plot", "--help").stdout
    assert "with plant-side parts" in help_text and "tau, m_h, b_h, k_h and k_p" in help_text


def test_python_figures(tmp_path):
    plt = pytest.importorskip("matplotlib.pyplot")
    import zwidth.plot as zp
    dev = zwidth.Device.rotary(J, b, T, stiffness=2e-2)
    fig = zp.plant_region(dev, K=0.3, B=0.0)
    ax = fig.axes[0]
    assert ax.get_ylim()[0] < 0.0   # a stiffness makes small negative K stable: the view shows them
    zp.save(fig, tmp_path / "r.svg")
    plt.close(fig)
    fig = zp.loop_region(0.5, delay=1, kappa=0.05, lambda_=0.3, point=(0.3, 0.2))
    zp.save(fig, tmp_path / "n.png")
    plt.close(fig)
    assert (tmp_path / "r.svg").stat().st_size > 10_000 and (tmp_path / "n.png").stat().st_size > 10_000


def test_normalized_options_equal_the_api_and_the_real_units():
    """--kappa / --lambda (normalized plant) give the API's numbers, and the real-unit
    device with the corresponding parts the same limits after scaling."""
    delta, kappa, lam, M = _normalized(tau=1e-2, hand=HAND, k_p=2e-3)
    norm = ("--delta", repr(delta), "--kappa", repr(kappa), "--lambda", repr(lam), "--delay", "1")
    lim = run_json("limits", *norm)
    ext = zwidth.extremes(delta, delay=1, kappa=kappa, lambda_=lam)
    assert lim["alpha_mmax"] == float(ext.alpha_mmax) and lim["beta_mmax"] == float(ext.beta_mmax)
    assert lim["plant"]["kappa"] == kappa and lim["plant"]["lambda"] == lam
    real = run_json("limits", *DRIVE, "--delay", "1", "--actuator-tau", "1e-2", "--hand", f"{J},{2 * b},1e-4",
                    "--stiffness", "2e-3")
    assert real["K_mmax"] * T ** 2 / M == pytest.approx(lim["alpha_mmax"], rel=1e-9)
    chk = run_json("check", *norm, "--alpha", "0.5", "--beta", "1.0", code=0)
    assert chk["stable"] == bool(zwidth.check(delta, 0.5, 1.0, delay=1, kappa=kappa, lambda_=lam))
    assert chk["alpha_max"] == float(zwidth.alpha_max(delta, 1.0, delay=1, kappa=kappa, lambda_=lam))
    bad = run_json("check", *norm, "--alpha", str(2 * float(ext.alpha_mmax)), "--beta", "1.0", code=1)
    assert bad["stable"] is False
    adv = run_json("advise", *norm)
    assert adv["K_mmax"] == pytest.approx(float(ext.alpha_mmax), rel=1e-12)   # m = T = 1: K = alpha
    r = run("check", *norm, "--alpha", "0.5", "--beta", "1.0", "--kappa", "-1")
    assert r.returncode == 3 and "--kappa" in r.stderr
    r = run("check", *DRIVE, "--K", "0.2", "--B", "1e-3", "--lambda", "0.1")
    assert r.returncode == 2 and "--actuator-tau" in r.stderr
    r = run("check", "--delta", "1", "--alpha", "1", "--beta", "0", "--hand", "1,1,1")
    assert r.returncode == 2 and "--kappa" in r.stderr


def test_simulated_linear_part_with_hand_and_lag_has_the_guarded_verdict():
    """A scene with [actuator] tau and a holding [hand]: the linear part's verdict is the
    general loop's (Device with actuator_tau and hand), and agrees with its eigenvalues."""
    m, bp, TT = 0.1, 2.0, 1e-3
    doc = {"scene": {"duration": "1 s"}, "plant": {"m": f"{m} kg", "b": f"{bp} N*s/m", "T": f"{TT} s"},
           "initial": {"x": "1 mm"}, "actuator": {"tau": "2 ms"},
           "hand": {"mass": "0.05 kg", "damping": "3 N*s/m", "stiffness": "500 N/m"}}
    dev = zwidth.Device(m, bp, TT, actuator_tau=2e-3, hand=(0.05, 3.0, 500.0))
    lim = dev.extremes()
    for K, stable in ((0.5 * float(lim.K_mmax), True), (1.3 * float(lim.K_mmax), False)):
        doc["controller"] = {"K": f"{K} N/m", "B": f"{float(lim.B_at_K_mmax)} N*s/m"}
        lin = zwidth.simulate(doc)[0].linear
        assert lin.verdict is not None and bool(lin.verdict.stable) is stable
        assert bool(lin.verdict.stable) == bool(dev.is_stable(K, float(lim.B_at_K_mmax)))
        assert lin.spectral_radius == pytest.approx(float(dev.spectral_radius(K, float(lim.B_at_K_mmax))), rel=1e-7)
