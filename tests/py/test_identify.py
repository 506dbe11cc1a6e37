# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""zwidth.identify against an independent simulation of the experiment (ident_reference:
closed forms and its own integrator, not identify's expm/lfilter), for the plant, the delay,
the lag, the spring and friction, with quantization and noise; the box it gives contains the
truth and its certified gains are stable on the true plant; every bad log is refused with
the column named; the CLI."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path
from typing import Any, Dict

import numpy as np
import pytest

pytest.importorskip("scipy")

import ident_reference as ref  # noqa: E402
import zwidth  # noqa: E402
from zwidth.identify import IdentifyError, excitation, identify  # noqa: E402

T = 1e-3
M, B_DAMP = 0.1, 2.0


def _log(m: float = M, b: float = B_DAMP, *, seconds: float = 2.0, hold: int = 5, amplitude: float = 1.0,
         seed: int = 1, **plant: Any) -> Dict[str, Any]:
    u = excitation("prbs", T, seconds, amplitude, hold=hold, seed=seed)
    rng = np.random.default_rng(seed + 100)
    x = ref.simulate(m, b, T, u, rng=rng, **plant)
    return {"u": u, "x": x}


def _inside(e: zwidth.identify.Estimate, truth: float) -> bool:
    return e.lo <= truth <= e.hi


def _certified_gains_stable(box: zwidth.PlantBox, truth: zwidth.Device) -> None:
    ext = box.extremes()
    assert ext.K_mmax > 0.0
    for K, Bg in ((0.999 * ext.K_mmax, ext.B_at), (0.5 * ext.K_mmax, 0.0)):
        if box.is_stable(K, Bg):
            assert truth.is_stable(K, Bg), (K, Bg, box, truth)


@pytest.mark.parametrize("delay", [0, 1, 2])
def test_plant_and_delay_recovered(delay: int) -> None:
    log = _log(delay=delay, noise=1e-5)
    ident = identify(log["x"], log["u"], T)
    assert ident.delay == delay
    assert _inside(ident.estimates["m"], M) and _inside(ident.estimates["b"], B_DAMP)
    assert ident.estimates["m"].identified and ident.fit.ok
    assert abs(ident.estimates["m"].value / M - 1) < 1e-3
    box = ident.box()
    assert box.m.lo <= M <= box.m.hi and box.b.lo <= B_DAMP <= box.b.hi
    assert box.loop.delay == delay
    _certified_gains_stable(box, zwidth.Device(M, B_DAMP, T, delay=delay))


def test_quantized_encoder_counts() -> None:
    cpu = 20000.0
    log = _log(delay=1, counts_per_unit=cpu)
    counts = np.round(log["x"] * cpu)
    ident = identify(counts, log["u"], T, counts_per_unit=cpu)
    assert ident.fit.floor == pytest.approx(1 / cpu / math.sqrt(12))
    assert ident.fit.rms < 2 * ident.fit.floor
    assert _inside(ident.estimates["m"], M) and _inside(ident.estimates["b"], B_DAMP)


def test_rotary_paper_drive() -> None:
    J, b, Tp = 85.78e-7, 2.197e-3, 0.02      # the paper's drive (math.md), T = 20 ms
    u = excitation("prbs", Tp, 40.0, 2e-3, hold=1, seed=3)
    x = ref.simulate(J, b, Tp, u, delay=1, noise=1e-4, rng=np.random.default_rng(4))
    ident = identify(x, u, Tp, rotary=True)
    assert set(ident.estimates) == {"J", "b"}
    assert ident.delay == 1
    assert _inside(ident.estimates["J"], J) and _inside(ident.estimates["b"], b)
    box = ident.box()
    assert box.rotary and box.m.lo <= J <= box.m.hi
    _certified_gains_stable(box, zwidth.Device.rotary(J, b, Tp, delay=1))


def test_lag_identified_and_box_refused() -> None:
    tau = 3e-4
    log = _log(delay=1, tau=tau, noise=1e-6)
    ident = identify(log["x"], log["u"], T, lag=True)
    assert _inside(ident.estimates["tau"], tau) and _inside(ident.estimates["m"], M)
    with pytest.raises(IdentifyError, match="lag"):
        ident.box()
    dev = ident.device()
    assert float(dev.actuator_tau) == pytest.approx(ident.estimates["tau"].value)
    assert any("faster time constant" in w for w in ident.warnings)
    # 1/(s (m s + b)(tau s + 1)) is symmetric in m/b and tau: without the assumption that the
    # lag is the faster, the mirrored plant (m/b = 0.3 ms, tau = 50 ms) fits as well
    either = identify(log["x"], log["u"], T, lag="either")
    assert not either.estimates["m"].identified and _inside(either.estimates["m"], M)
    assert any("cannot be told apart" in w for w in either.warnings)


def test_spring() -> None:
    k = 50.0
    log = _log(delay=1, k=k, noise=1e-5)
    ident = identify(log["x"], log["u"], T, spring=True)
    assert _inside(ident.estimates["k"], k) and _inside(ident.estimates["b"], B_DAMP)
    box = ident.box()
    assert box.stiffness.lo <= k <= box.stiffness.hi
    _certified_gains_stable(box, zwidth.Device(M, B_DAMP, T, delay=1, stiffness=k))


def test_friction() -> None:
    fc = 0.03                                 # 3 % of the excitation's amplitude
    log = _log(seconds=4.0, delay=1, coulomb=fc, noise=1e-5)
    plain = identify(log["x"], log["u"], T)
    ident = identify(log["x"], log["u"], T, friction=True)
    assert _inside(ident.estimates["F_c"], fc)
    assert _inside(ident.estimates["b"], B_DAMP)
    # left out, friction reads as damping: the fit without it puts b too high, says so, and
    # gives no box (its gains would not hold)
    assert plain.estimates["b"].lo > B_DAMP
    assert not plain.fit.ok and "friction" in plain.fit.reason
    with pytest.raises(IdentifyError, match="friction"):
        plain.box()
    _certified_gains_stable(ident.box(), zwidth.Device(M, B_DAMP, T, delay=1))


def test_coverage_of_the_intervals() -> None:
    """40 seeded noisy logs: the 95 % intervals cover m and b at least 34 times each (the
    binomial 1 % lower tail for a true 95 %), and the 99 % box holds the plant in all but 2."""
    hits = {"m": 0, "b": 0}
    boxed = 0
    n = 40
    for seed in range(n):
        log = _log(seconds=1.0, seed=seed, delay=1, noise=3e-4)
        ident = identify(log["x"], log["u"], T, max_delay=1)
        hits["m"] += _inside(ident.estimates["m"], M)
        hits["b"] += _inside(ident.estimates["b"], B_DAMP)
        box = ident.box()
        boxed += box.m.lo <= M <= box.m.hi and box.b.lo <= B_DAMP <= box.b.hi
    assert min(hits.values()) >= 34, hits
    assert boxed >= n - 2


def test_missing_and_repeated_samples() -> None:
    log = _log(delay=1, noise=1e-5)
    t = np.arange(log["u"].size) * T
    keep = np.ones(t.size, bool)
    keep[[300, 301, 900, 1500]] = False
    t2, u2, x2 = t[keep], log["u"][keep], log["x"][keep]
    # a repeated row (the logger wrote a sample twice)
    t2, u2, x2 = (np.insert(a, 50, a[50]) for a in (t2, u2, x2))
    ident = identify(x2, u2, time=t2)
    assert any("4 missing" in w for w in ident.warnings) and any("repeated" in w for w in ident.warnings)
    assert ident.samples == t.size - 4 - 3      # minus the missing and the 3 samples before max_delay
    assert _inside(ident.estimates["m"], M) and ident.delay == 1


@pytest.mark.parametrize("case, column, message", [
    ("lengths", "command", "samples, position has"),
    ("nan", "position", "not finite"),
    ("decreasing", "time", "decreases"),
    ("jitter", "time", "not uniform"),
    ("wrong_T", "time", "not T ="),
    ("constant", "command", "constant"),
    ("short", "position", "too short"),
    ("saturated", "command", "force limit"),
    ("still", "position", "did not move"),
    ("clash", "time", "repeats the time"),
    ("reversed", "position", "sign reversed"),
])
def test_bad_logs_refused(case: str, column: str, message: str) -> None:
    log = _log(delay=1, noise=1e-5)
    u, x = log["u"], log["x"]
    t = np.arange(u.size) * T
    kw: Dict[str, Any] = {"time": t}
    if case == "lengths":
        u = u[:-1]
    elif case == "nan":
        x = x.copy()
        x[17] = np.nan
    elif case == "decreasing":
        t = t.copy()
        t[10], t[11] = t[11], t[10]
        kw["time"] = t
    elif case == "jitter":
        kw["time"] = t + np.where(np.arange(t.size) == 40, 0.3 * T, 0.0)
    elif case == "wrong_T":
        kw["T"] = 2 * T
    elif case == "constant":
        u = np.full(u.size, 0.5)
    elif case == "short":
        u, x, kw["time"] = u[:40], x[:40], t[:40]
    elif case == "saturated":
        kw["force_limit"] = 1.0
    elif case == "still":
        x = np.zeros(x.size)
    elif case == "clash":
        kw["time"] = np.insert(t, 5, t[5])
        u, x = np.insert(u, 5, u[5]), np.insert(x, 5, x[5] + 1e-3)
    elif case == "reversed":
        x = -x
    with pytest.raises(IdentifyError, match=message) as info:
        identify(x, u, **kw)
    assert info.value.column == column


def test_not_identified_means_no_box() -> None:
    # a log far shorter than the plant's time constant m/b = 50 s: m and b are not separable
    log = _log(m=10.0, b=0.2, seconds=0.2, hold=50, noise=1e-4, delay=1)
    ident = identify(log["x"], log["u"], T, max_delay=1)
    assert not (ident.estimates["m"].identified and ident.estimates["b"].identified)
    assert any("not identified" in w for w in ident.warnings)
    with pytest.raises(IdentifyError, match="not identified"):
        ident.box()


def test_resonance_does_not_fit() -> None:
    """A second mass on a spring (a resonance the model does not have): the residual check
    says the model does not fit, and no box is given."""
    from scipy.linalg import expm
    m1, m2, k12, c12 = 0.06, 0.04, 400.0, 0.05
    A = np.array([[0, 1, 0, 0], [-k12 / m1, -(B_DAMP + c12) / m1, k12 / m1, c12 / m1],
                  [0, 0, 0, 1], [k12 / m2, c12 / m2, -k12 / m2, -c12 / m2]])
    Bc = np.array([0, 1 / m1, 0, 0])
    E = expm(np.block([[A, Bc[:, None]], [np.zeros((1, 5))]]) * T)
    u = excitation("prbs", T, 2.0, 1.0, hold=5, seed=1)
    s = np.zeros(4)
    x = np.empty(u.size)
    for j in range(u.size):
        x[j] = s[0]
        s = E[:4, :4] @ s + E[:4, 4] * (u[j - 1] if j else 0.0)
    ident = identify(x + np.random.default_rng(0).normal(0, 1e-6, x.size), u, T)
    assert not ident.fit.ok and "does not fit" in ident.fit.reason
    with pytest.raises(IdentifyError, match="does not fit"):
        ident.box()


def test_sampling_matrix_against_mpmath() -> None:
    """The fit's exp(M) (the exact ZOH sampling; zwidth.sim's) against mpmath's at 40
    digits, over the shapes the fit visits: b T/m in 1e-9..1e3, w2 in 0..4, tau/T in
    1e-4..1e3."""
    mpmath = pytest.importorskip("mpmath")
    from zwidth.sim import _expm as _expm_small
    mpmath.mp.dps = 40
    rng = np.random.default_rng(7)
    for _ in range(200):
        n = int(rng.integers(3, 5))
        Mx = np.zeros((n, n))
        Mx[0, 1], Mx[1, 2] = 1.0, 1.0
        Mx[1, 0], Mx[1, 1] = -rng.uniform(0.0, 4.0), -math.exp(rng.uniform(math.log(1e-9), math.log(1e3)))
        if n == 4:
            lam = math.exp(rng.uniform(math.log(1e-3), math.log(1e4)))
            Mx[2, 2], Mx[2, 3] = -lam, lam
        exact = np.array(mpmath.expm(mpmath.matrix(Mx.tolist())).tolist(), dtype=float)
        assert np.max(np.abs(_expm_small(Mx) - exact)) <= 1e-11 * max(1.0, np.max(np.abs(exact)))


def test_excitation() -> None:
    p = excitation("prbs", T, 1.0, 2.0, hold=4, seed=0)
    assert p.size == 1000 and set(np.unique(p)) == {-2.0, 2.0}
    assert np.all(p[:4] == p[0])
    c = excitation("chirp", T, 1.0, 1.0, f_lo=1.0, f_hi=100.0)
    assert np.max(np.abs(c)) <= 1.0 and c.size == 1000
    s = excitation("steps", T, 1.0, 1.0)
    assert s.sum() == 0.0
    for bad in (dict(kind="noise"), dict(kind="prbs", hold=0), dict(kind="chirp", f_hi=1e4)):
        with pytest.raises(ValueError):
            excitation(bad.pop("kind"), T, 1.0, 1.0, **bad)


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "zwidth", "identify", *args], capture_output=True, text=True,
                          timeout=300)


def test_cli(tmp_path: Path) -> None:
    cpu = 20000.0
    log = _log(delay=1, counts_per_unit=cpu)
    csv = tmp_path / "run.csv"
    t = np.arange(log["u"].size) * T
    np.savetxt(csv, np.column_stack([t, log["u"], np.round(log["x"] * cpu)]), delimiter=",",
               header="t,u,counts", comments="")
    out = _cli(str(csv), "--time", "t", "--command", "u", "--position", "counts", "--counts-per-unit", str(cpu),
               "--json")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert data["command"] == "identify" and data["loop"]["delay"] == 1
    m_lo, m_hi = data["box"]["m"]
    assert m_lo <= M <= m_hi
    assert data["identification"]["estimates"]["b"]["lo"] <= B_DAMP
    assert data["limits"]["K_mmax"] > 0 and data["limits_command"].startswith("zwidth limits --m ")
    text = _cli(str(csv), "--time", "t", "--command", "u", "--position", "counts", "--counts-per-unit", str(cpu))
    assert text.stdout.startswith("Loop: 1 sample delay") and "Box at joint level 99 %" in text.stdout
    missing = _cli(str(csv), "--time", "t")
    assert missing.returncode == 3 and "no column 'command'" in missing.stderr
    lagged = _log(delay=1, tau=3e-4, noise=1e-6)
    np.savetxt(csv, np.column_stack([lagged["u"], lagged["x"]]), delimiter=",", header="command,position",
               comments="")
    no_box = _cli(str(csv), "--T", str(T), "--lag")
    assert no_box.returncode == 6 and "No box" in no_box.stdout
    helps = _cli("--help")
    assert "docs/identify.md" in helps.stdout and "--counts-per-unit" in helps.stdout
