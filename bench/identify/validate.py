#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""Validation of zwidth.identify over random simulated plants of known parameters (issue 26).

Each trial draws a plant, simulates the identification experiment with the independent
reference simulator (tests/py/ident_reference.py: RK4 with >= 4096 substeps per sample for
linear plants, the exact piecewise closed form with Coulomb friction; nothing of
zwidth.identify's own code), measures it through an encoder and noise, and fits it with
zwidth.identify.identify using the options that match the trial (lag=, friction=, spring=,
counts_per_unit=, rotary=, max_delay=3).

Plants (family):
  paper   the seed paper's rotary drive: J in {85.78, 102.29, 172.43, 283.21} e-7 kg m^2,
          b in {13.93e-6 (load motor open), 2.197e-3 (short-circuited)} N m s/rad,
          T in {0.02, 0.008, 0.001} s;
  haptic  m log-uniform 0.01..1 kg, b 0.05..20 N s/m, T 1e-4..1e-3 s;
  drive   a servo drive, rotary: J 1e-6..1e-3 kg m^2, b 1e-5..1e-2 N m s/rad,
          T in {62.5, 125, 250, 500, 1000} us.
Model class: plain (m, b), lag (tau 0.1..1 T), spring (natural frequency w_n with
w_n T log-uniform in [30/n, 0.2], so kappa = k T^2/m <= 0.04; drawn only where
delta = b T/m <= 3, inside the box method's delta <= 4, else the trial is plain),
lag+spring, friction (Coulomb F_c 0.5..5 % of the excitation's amplitude; the reference's
closed form has neither lag nor spring with it).  Every trial: delay 0, 1 or 2 samples; an
encoder in 75 % of them (resolution such that the motion spans 50..5000 counts, plus
Gaussian noise of 0..1 count in half of them), else an analog position with Gaussian noise
of 1e-4..1e-2 of the motion; a random encoder offset where there is no spring.

Excitation: zwidth.identify.excitation("prbs", T, n T, A, hold=h, seed=...), n = 2000..4000
samples; the hold h = clip(round(tau_m / (4 T)), 1, 8) from the mechanical time constant
tau_m = m/b, and the amplitude A such that the motion spans a set range (the plant is
homogeneous in (u, F_c, x), so it is simulated once at A = 1 and scaled).  The trial knows
the true plant when it designs this; a user sets hold and amplitude from a rough guess (a
datasheet inertia, a first short run), which is all the design needs.

Reported:
  * coverage of each true parameter by its stated 95 % interval, per parameter and per
    class (model class, plant family, encoder or not), PASS when the observed coverage is
    >= 0.95, with the one-sided 95 % Clopper-Pearson bounds;
  * coverage of the true (m, b[, k]) by Identification.box() (joint level 0.99), whose delay
    must be at least the true one (box() takes the largest delay the log allows);
  * the certified gains of every box, (0.9 K_mmax, B_at) and (0.5 K_mmax, 0) of
    box.extremes(), judged on the TRUE plant with zwidth.Device(m, b, T, delay=, stiffness=,
    actuator_tau=).is_stable: exceptions (must be 0), and whether the box itself certified
    the pair; trials without a box are counted with box()'s reason;
  * the delay chosen right;
  * accuracy (median and 95th percentile of |relative error| of m and b) and time per fit,
    against (a) a plain equation-error ARX least squares on the sampled model,
        x[n+2] - (1+p) x[n+1] + p x[n] = b1 u[n+1-d] + b0 u[n-d]    (d the true delay)
    mapped back by the ZOH formulas p = exp(-b T/m), b1 + b0 = T (1 - p)/b (with a spring,
    the general second-order ARX, mapped back through its poles and DC gain); and (b) a
    generic frequency-response fit: H1 = P_uy / P_uu by scipy.signal.csd / welch (Hann,
    8 segments, linear detrend), bins with coherence > 0.9 below 0.2/T and the PRBS's first null
    (where the zero-order hold attenuates by sinc(f T) >= 0.93), fitted
    to e^{-s theta} / ((tau s + 1)(m s^2 + b s + k)) (k and tau where the trial has them,
    theta free in [0, 5 T]) by scipy.optimize.least_squares on the complex log ratio, from a
    rough guess (the truth times a random factor in [1/2, 2]).  python-control 0.10 has no
    fitting function for an input-output log (control.era needs impulse-response data), so
    (b) is scipy's.

Run:  .venv/bin/python bench/identify/validate.py [--trials 1000] [--seed 1] [--jobs 2]
      [--json OUT] [--quick]
bench/identify/results.txt is this output of the 1000-trial run and results.json its summary
(the per-trial records, 2 MB, left out); bench/report/ident_section.py puts it in REPORT.md.
(needs zwidth with scipy; the exit status is 0 whatever the figures say).
"""
from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")      # one thread per worker: the pool parallelizes

import argparse
import dataclasses
import hashlib
import importlib
import json
import math
import multiprocessing
import platform
import sys
import time
import traceback
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import NDArray

import zwidth

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "tests" / "py"))
import ident_reference as ref  # noqa: E402

zid = importlib.import_module("zwidth.identify")   # the module (zwidth.identify may be the function)
#: The identify.py measured (read once, when it is imported: the workers fork with it).
IDENTIFY_SHA256 = hashlib.sha256(Path(str(zid.__file__)).read_bytes()).hexdigest()

Array = NDArray[np.float64]
LEVEL = 0.95
BOX_LEVEL = 0.99
CLASSES = ("plain", "lag", "spring", "lag+spring", "friction")
FAMILIES = ("paper", "haptic", "drive")
PAPER_J = (85.78e-7, 102.29e-7, 172.43e-7, 283.21e-7)
PAPER_B = (13.93e-6, 2.197e-3)
PAPER_T = (0.02, 0.008, 0.001)
DRIVE_T = (62.5e-6, 125e-6, 250e-6, 500e-6, 1e-3)


# ---- the trials -----------------------------------------------------------------------------------


@dataclasses.dataclass
class Trial:
    index: int
    family: str
    cls: str
    rotary: bool
    m: float
    b: float
    T: float
    delay: int
    k: float
    tau: float
    friction_ratio: float       # F_c / A
    n: int
    hold: int
    prbs_seed: int
    quantized: bool
    counts_span: float          # counts over the motion (quantized trials)
    noise_counts: float         # noise std in counts (quantized trials)
    noise_ratio: float          # noise std / motion (analog trials)
    motion: float               # peak-to-peak motion wanted [m or rad]
    offset_ratio: float         # encoder offset / motion (no spring)
    guess: Tuple[float, ...]    # the rough guess's factors for the FRF fit (m, b, k, tau)

    @property
    def friction(self) -> bool:
        return self.friction_ratio > 0.0

    @property
    def spring(self) -> bool:
        return self.k > 0.0

    @property
    def lag(self) -> bool:
        return self.tau > 0.0


def _log_uniform(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def draw_trial(seed: int, index: int) -> Trial:
    rng = np.random.default_rng([seed, index])
    family = str(rng.choice(FAMILIES, p=[0.2, 0.4, 0.4]))
    if family == "paper":
        rotary, m, b, T = True, float(rng.choice(PAPER_J)), float(rng.choice(PAPER_B)), float(rng.choice(PAPER_T))
    elif family == "haptic":
        rotary, m, b, T = False, _log_uniform(rng, 0.01, 1.0), _log_uniform(rng, 0.05, 20.0), \
            _log_uniform(rng, 1e-4, 1e-3)
    else:
        rotary, m, b, T = True, _log_uniform(rng, 1e-6, 1e-3), _log_uniform(rng, 1e-5, 1e-2), \
            float(rng.choice(DRIVE_T))
    cls = str(rng.choice(CLASSES, p=[0.35, 0.2, 0.15, 0.1, 0.2]))
    delta = b * T / m
    if "spring" in cls and delta > 3.0:
        cls = cls.replace("+spring", "").replace("spring", "plain")
    n = int(rng.integers(2000, 4001))
    k = 0.0
    if "spring" in cls:
        wT = _log_uniform(rng, 30.0 / n, 0.2)
        k = m * (wT / T) ** 2
    tau = float(rng.uniform(0.1, 1.0)) * T if "lag" in cls else 0.0
    friction_ratio = float(rng.uniform(0.005, 0.05)) if cls == "friction" else 0.0
    hold = int(min(8, max(1, round(m / b / (4.0 * T)))))
    quantized = bool(rng.uniform() < 0.75)
    counts_span = _log_uniform(rng, 50.0, 5000.0)
    noise_counts = float(rng.uniform(0.0, 1.0)) if rng.uniform() < 0.5 else 0.0
    noise_ratio = _log_uniform(rng, 1e-4, 1e-2)
    motion = (0.5 if rotary else 0.01) * _log_uniform(rng, 0.3, 3.0)
    offset_ratio = float(rng.uniform(-1.0, 1.0)) if k == 0.0 else 0.0
    guess = tuple(float(math.exp(rng.uniform(-math.log(2.0), math.log(2.0)))) for _ in range(4))
    return Trial(index, family, cls, rotary, m, b, T, int(rng.integers(0, 3)), k, tau, friction_ratio, n, hold,
                 int(rng.integers(0, 2 ** 31)), quantized, counts_span, noise_counts, noise_ratio, motion,
                 offset_ratio, guess)


def unit_command(t: Trial) -> Array:
    out: Array = zid.excitation("prbs", t.T, t.n * t.T, 1.0, hold=t.hold, seed=t.prbs_seed)
    return out


def simulate_all(trials: Sequence[Trial]) -> Dict[int, Array]:
    """The noise-free unit-amplitude positions of every trial, batched by (delay, friction)
    through ident_reference.simulate_many (commands zero-padded: the plant is causal)."""
    out: Dict[int, Array] = {}
    groups: Dict[Tuple[int, bool], List[Trial]] = {}
    for t in trials:
        groups.setdefault((t.delay, t.friction), []).append(t)
    for (delay, _), group in groups.items():
        n_max = max(t.n for t in group)
        U = np.zeros((len(group), n_max))
        for i, t in enumerate(group):
            U[i, :t.n] = unit_command(t)
        X = ref.simulate_many(np.array([t.m for t in group]), np.array([t.b for t in group]),
                              np.array([t.T for t in group]), U, delay=delay,
                              k=np.array([t.k for t in group]), tau=np.array([t.tau for t in group]),
                              coulomb=np.array([t.friction_ratio for t in group]))
        for i, t in enumerate(group):
            out[t.index] = X[i, :t.n].copy()
    return out


@dataclasses.dataclass
class Log:
    command: Array
    position: Array                 # counts when quantized
    counts_per_unit: Optional[float]
    amplitude: float
    coulomb: float


def measure(t: Trial, x_unit: Array) -> Log:
    """Scale the unit response to the wanted motion, add the offset, noise and the encoder."""
    span = float(np.ptp(x_unit))
    A = t.motion / span if span > 0 else 1.0
    x = A * x_unit + t.offset_ratio * t.motion
    rng = np.random.default_rng([t.prbs_seed, 7])
    if t.quantized:
        cpu = t.counts_span / t.motion
        noise = t.noise_counts / cpu
        y = ref.measure(x, cpu, noise, rng)
        return Log(A * unit_command(t), np.rint(y * cpu), cpu, A, t.friction_ratio * A)
    y = ref.measure(x, None, t.noise_ratio * t.motion, rng)
    return Log(A * unit_command(t), y, None, A, t.friction_ratio * A)


# ---- the comparisons ---------------------------------------------------------------------------


def arx_fit(t: Trial, log: Log) -> Dict[str, float]:
    """Plain equation-error least squares on the sampled model with the true delay."""
    x = log.position / (log.counts_per_unit or 1.0)
    u, d, T = log.command, t.delay, t.T
    f = np.zeros_like(u)
    f[d:] = u[:u.size - d]
    n0 = d
    if not t.spring:
        dx = np.diff(x)
        # dx[n+1] = p dx[n] + b1 f[n+1] + b0 f[n], n = n0 .. N-3
        idx = np.arange(n0, x.size - 2)
        A = np.column_stack([dx[idx], f[idx + 1], f[idx]])
        coef, *_ = np.linalg.lstsq(A, dx[idx + 1], rcond=None)
        p, b1, b0 = (float(c) for c in coef)
        if not (0.0 < p < 1.0) or b1 + b0 <= 0.0:
            return {"m": math.nan, "b": math.nan}
        b = T * (1.0 - p) / (b1 + b0)
        return {"m": b * T / (-math.log(p)), "b": b}
    # x[n+2] = -a1 x[n+1] - a2 x[n] + b1 f[n+1] + b0 f[n]
    idx = np.arange(n0, x.size - 2)
    A = np.column_stack([-x[idx + 1], -x[idx], f[idx + 1], f[idx]])
    coef, *_ = np.linalg.lstsq(A, x[idx + 2], rcond=None)
    a1, a2, b1, b0 = (float(c) for c in coef)
    z = np.roots([1.0, a1, a2]).astype(complex)
    if np.any(np.abs(z) >= 1.0) or np.any(np.abs(z) == 0.0) or 1.0 + a1 + a2 <= 0.0:
        return {"m": math.nan, "b": math.nan, "k": math.nan}
    lam = np.log(z) / T
    k = (1.0 + a1 + a2) / (b1 + b0)
    prod, total = float(np.real(lam[0] * lam[1])), float(np.real(lam[0] + lam[1]))
    if k <= 0.0 or prod <= 0.0:
        return {"m": math.nan, "b": math.nan, "k": math.nan}
    m = k / prod
    return {"m": m, "b": -m * total, "k": k}


def frf_fit(t: Trial, log: Log) -> Dict[str, float]:
    """A frequency-response estimate fitted to the continuous model (see the docstring)."""
    from scipy import optimize, signal
    x = log.position / (log.counts_per_unit or 1.0)
    u, T = log.command, t.T
    fs = 1.0 / T
    nper = max(64, x.size // 8)
    f, Puu = signal.welch(u, fs=fs, nperseg=nper, detrend="linear")
    _, Puy = signal.csd(u, x, fs=fs, nperseg=nper, detrend="linear")
    _, coh = signal.coherence(u, x, fs=fs, nperseg=nper, detrend="linear")
    H = Puy / np.where(Puu > 0, Puu, np.inf)
    keep = (f > 0) & (f <= min(0.2 * fs, fs / t.hold)) & (coh > 0.9) & (np.abs(H) > 0)
    if np.count_nonzero(keep) < 6:
        return {"m": math.nan, "b": math.nan}
    w = 2.0 * math.pi * f[keep]
    Hm = H[keep]
    s = 1j * w
    names = ["m", "b"] + ["k"] * t.spring + ["tau"] * t.lag
    true = {"m": t.m, "b": t.b, "k": t.k, "tau": t.tau}
    x0 = [math.log(true[nm] * g) for nm, g in zip(names, t.guess)] + [t.delay + 0.5]

    def model(p: Array) -> Any:
        vals = dict(zip(names, np.exp(p[:-1])))
        den = vals["m"] * s ** 2 + vals["b"] * s + vals.get("k", 0.0)
        if "tau" in vals:
            den = den * (vals["tau"] * s + 1.0)
        return np.exp(-s * p[-1] * T) / den

    def resid(p: Array) -> Array:
        r = np.log(model(p) / Hm)
        return np.concatenate([r.real, r.imag])

    lo = [-np.inf] * len(names) + [0.0]
    hi = [np.inf] * len(names) + [5.0]
    try:
        with np.errstate(all="ignore"):      # a diverging step is the generic fit failing: NaN, counted
            res = optimize.least_squares(resid, np.array(x0), bounds=(lo, hi), method="trf", x_scale="jac")
    except (ValueError, np.linalg.LinAlgError):
        return {"m": math.nan, "b": math.nan}
    out = {nm: float(math.exp(v)) for nm, v in zip(names, res.x[:-1])}
    out["theta_samples"] = float(res.x[-1])
    return out


# ---- one trial -----------------------------------------------------------------------------------


def _estimate_record(e: Any) -> Dict[str, Any]:
    return {"value": e.value, "lo": e.lo, "hi": e.hi, "identified": e.identified,
            "standard_error": e.standard_error}


def run_trial(job: Tuple[Trial, Array]) -> Dict[str, Any]:
    t, x_unit = job
    log = measure(t, x_unit)
    truth: Dict[str, float] = {"m": t.m, "b": t.b}
    if t.spring:
        truth["k"] = t.k
    if t.lag:
        truth["tau"] = t.tau
    if t.friction:
        truth["F_c"] = log.coulomb
    rec: Dict[str, Any] = {"trial": dataclasses.asdict(t), "truth": truth, "amplitude": log.amplitude,
                           "counts_per_unit": log.counts_per_unit}
    rec["trial"]["guess"] = list(t.guess)
    # zwidth.identify
    t0 = time.perf_counter()
    try:
        ident = zid.identify(log.position, log.command, t.T, counts_per_unit=log.counts_per_unit, max_delay=3,
                             lag=t.lag, friction=t.friction, spring=t.spring, rotary=t.rotary)
    except zid.IdentifyError as exc:
        rec["identify_error"] = str(exc)
        ident = None
    rec["identify_seconds"] = time.perf_counter() - t0
    if ident is not None:
        est = {("m" if n == ident.mass_symbol else n): _estimate_record(e) for n, e in ident.estimates.items()}
        rec["estimates"] = est
        rec["delay"] = ident.delay
        rec["delay_rss"] = {str(d): v for d, v in ident.delay_rss.items()}
        rec["fit"] = {"ok": ident.fit.ok, "reason": ident.fit.reason, "rms": ident.fit.rms, "floor": ident.fit.floor,
                      "rho1": ident.fit.rho1}
        rec["warnings"] = list(ident.warnings)
        rec["covered"] = {n: bool(est[n]["lo"] <= v <= est[n]["hi"]) for n, v in truth.items() if n in est}
        rec.update(_box_check(t, ident))
    # the comparisons
    t0 = time.perf_counter()
    rec["arx"] = arx_fit(t, log)
    rec["arx_seconds"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    try:
        rec["frf"] = frf_fit(t, log)
    except Exception as exc:            # a generic fit failing is a figure, not a crash
        rec["frf"] = {"m": math.nan, "b": math.nan, "error": repr(exc)}
    rec["frf_seconds"] = time.perf_counter() - t0
    return rec


def _box_check(t: Trial, ident: Any) -> Dict[str, Any]:
    out: Dict[str, Any] = {}
    try:
        box = ident.box(level=BOX_LEVEL)
    except zid.IdentifyError as exc:
        out["box_error"] = str(exc)
        return out
    k_range = (box.stiffness.lo, box.stiffness.hi)
    inside = {"m": box.m.lo <= t.m <= box.m.hi, "b": box.b.lo <= t.b <= box.b.hi,
              # the box takes the largest delay the log allows: at least the true one
              "k": k_range[0] <= t.k <= k_range[1], "delay": box.loop.delay >= t.delay}
    out["box"] = {"m": [box.m.lo, box.m.hi], "b": [box.b.lo, box.b.hi], "k": list(k_range),
                  "delay": box.loop.delay, "method": box.method, "inside": inside,
                  "contains_truth": all(inside.values())}
    try:
        t0 = time.perf_counter()
        E = box.extremes()
        out["box"]["extremes_seconds"] = time.perf_counter() - t0
    except zwidth.ZwidthError as exc:
        out["box_error"] = f"extremes(): {exc}"
        return out
    true_dev = zwidth.Device(t.m, t.b, t.T, delay=t.delay, actuator_tau=t.tau, stiffness=t.k, rotary=t.rotary)
    pairs = [("0.9 K_mmax at B_at", 0.9 * E.K_mmax, E.B_at), ("0.5 K_mmax at B = 0", 0.5 * E.K_mmax, 0.0)]
    try:
        iv = box.b_range(0.5 * E.K_mmax)
        if iv.nonempty:
            pairs += [("0.5 K_mmax at b_range lo", 0.5 * E.K_mmax, iv.lo),
                      ("0.5 K_mmax at b_range hi", 0.5 * E.K_mmax, iv.hi)]
    except zwidth.ZwidthError as exc:
        out["b_range_error"] = str(exc)
    gains = []
    for label, K, B in pairs:
        certified = bool(box.is_stable(K, B))
        stable = bool(true_dev.is_stable(K, B))
        gains.append({"pair": label, "K": K, "B": B, "box_certifies": certified, "true_stable": stable})
    out["box"]["K_mmax"] = E.K_mmax
    out["box"]["B_at"] = E.B_at
    out["box"]["converged"] = E.converged
    out["gains"] = gains
    return out


def run_trial_safe(job: Tuple[Trial, Array]) -> Dict[str, Any]:
    try:
        return run_trial(job)
    except Exception:                    # a crash of the bench itself: reported, never hidden
        return {"trial": dataclasses.asdict(job[0]), "crash": traceback.format_exc()}


# ---- statistics ----------------------------------------------------------------------------------


def clopper_pearson(hits: int, n: int, conf: float = 0.95) -> Tuple[float, float]:
    """One-sided bounds at ``conf`` each: P(coverage < lo) <= 1 - conf, same for hi."""
    from scipy import stats
    if n == 0:
        return (math.nan, math.nan)
    a = 1.0 - conf
    lo = 0.0 if hits == 0 else float(stats.beta.ppf(a, hits, n - hits + 1))
    hi = 1.0 if hits == n else float(stats.beta.ppf(1.0 - a, hits + 1, n - hits))
    return lo, hi


def _pct(values: Iterable[float], q: float) -> float:
    v = [x for x in values if math.isfinite(x)]
    return float(np.percentile(v, q)) if v else math.nan


def _class_of(rec: Dict[str, Any], key: str) -> str:
    t = rec["trial"]
    if key == "class":
        return str(t["cls"])
    if key == "family":
        return str(t["family"])
    return "encoder" if t["quantized"] else "analog"


def coverage_table(recs: Sequence[Dict[str, Any]]) -> List[Dict[str, Any]]:
    rows: List[Dict[str, Any]] = []
    groups: List[Tuple[str, List[Dict[str, Any]]]] = [("all", list(recs))]
    for key, names in (("class", CLASSES), ("family", FAMILIES), ("encoder", ("encoder", "analog"))):
        for nm in names:
            groups.append((f"{key}={nm}", [r for r in recs if _class_of(r, key) == nm]))
    for label, group in groups:
        fitted = [r for r in group if "covered" in r]
        row: Dict[str, Any] = {"group": label, "trials": len(group), "fitted": len(fitted),
                               "identify_errors": sum(1 for r in group if "identify_error" in r)}
        total_hits = total_n = 0
        for p in ("m", "b", "k", "tau", "F_c"):
            cov = [r["covered"][p] for r in fitted if p in r["covered"]]
            if cov:
                hits = int(sum(cov))
                lo, hi = clopper_pearson(hits, len(cov))
                row[p] = {"hits": hits, "n": len(cov), "coverage": hits / len(cov), "lower95": lo, "upper95": hi,
                          "pass": hits / len(cov) >= LEVEL}
                total_hits += hits
                total_n += len(cov)
        lo, hi = clopper_pearson(total_hits, total_n)
        row["every"] = {"hits": total_hits, "n": total_n, "coverage": total_hits / max(total_n, 1),
                        "lower95": lo, "upper95": hi, "pass": total_n > 0 and total_hits / total_n >= LEVEL}
        row["pass"] = all(row[p]["pass"] for p in ("m", "b", "k", "tau", "F_c") if p in row)
        right = [r["delay"] == r["trial"]["delay"] for r in fitted]
        row["delay_right"] = sum(right) / len(right) if right else math.nan
        rows.append(row)
    return rows


def accuracy_table(recs: Sequence[Dict[str, Any]]) -> List[Dict[str, Any]]:
    rows = []
    for label, group in [("all", list(recs))] + [(f"class={c}", [r for r in recs if r["trial"]["cls"] == c])
                                                  for c in CLASSES]:
        for method in ("zwidth.identify", "ARX least squares", "scipy FRF fit"):
            errs: Dict[str, List[float]] = {"m": [], "b": []}
            fails = 0
            secs: List[float] = []
            for r in group:
                if "crash" in r:
                    continue
                if method == "zwidth.identify":
                    vals = {p: r["estimates"][p]["value"] for p in ("m", "b")} if "estimates" in r else None
                    secs.append(r["identify_seconds"])
                elif method == "ARX least squares":
                    vals = r["arx"]
                    secs.append(r["arx_seconds"])
                else:
                    vals = r["frf"]
                    secs.append(r["frf_seconds"])
                if vals is None or not all(math.isfinite(vals.get(p, math.nan)) for p in ("m", "b")):
                    fails += 1
                    continue
                for p in ("m", "b"):
                    errs[p].append(abs(vals[p] / r["truth"][p] - 1.0))
            rows.append({"group": label, "method": method, "trials": len(secs), "failed": fails,
                         "m_median": _pct(errs["m"], 50), "m_p95": _pct(errs["m"], 95),
                         "b_median": _pct(errs["b"], 50), "b_p95": _pct(errs["b"], 95),
                         "seconds_median": _pct(secs, 50), "seconds_mean": float(np.mean(secs)) if secs else math.nan})
    return rows


def box_summary(recs: Sequence[Dict[str, Any]]) -> Dict[str, Any]:
    with_box = [r for r in recs if "box" in r]
    reasons: Dict[str, int] = {}
    for r in recs:
        if "box_error" in r:
            key = _reason_key(r["box_error"])
            reasons[key] = reasons.get(key, 0) + 1
        elif "identify_error" in r:
            key = "identify raised: " + _reason_key(r["identify_error"])
            reasons[key] = reasons.get(key, 0) + 1
    contains = [r["box"]["contains_truth"] for r in with_box]
    hits = int(sum(contains))
    lo, hi = clopper_pearson(hits, len(contains))
    per_class = {}
    for c in CLASSES:
        cc = [r["box"]["contains_truth"] for r in with_box if r["trial"]["cls"] == c]
        per_class[c] = {"hits": int(sum(cc)), "n": len(cc)}
    gain_rows = [(r, g) for r in with_box for g in r.get("gains", [])]
    exceptions = [{"trial": r["trial"]["index"], "pair": g["pair"], "K": g["K"], "B": g["B"],
                   "box_contains_truth": r["box"]["contains_truth"]}
                  for r, g in gain_rows if g["box_certifies"] and not g["true_stable"]]
    per_pair: Dict[str, Dict[str, int]] = {}
    for _, g in gain_rows:
        tally = per_pair.setdefault(g["pair"], {"checks": 0, "box_certifies": 0, "certified_unstable": 0,
                                                "not_certified": 0, "not_certified_unstable": 0})
        tally["checks"] += 1
        tally["box_certifies"] += int(g["box_certifies"])
        tally["certified_unstable"] += int(g["box_certifies"] and not g["true_stable"])
        tally["not_certified"] += int(not g["box_certifies"])
        tally["not_certified_unstable"] += int(not g["box_certifies"] and not g["true_stable"])
    return {"trials": len(recs), "with_box": len(with_box), "without_box": reasons,
            "contains_truth": {"hits": hits, "n": len(contains), "coverage": hits / max(len(contains), 1),
                               "lower95": lo, "upper95": hi,
                               "pass": bool(contains) and hits / len(contains) >= BOX_LEVEL},
            "contains_per_class": per_class,
            "inside_per_part": {p: int(sum(r["box"]["inside"][p] for r in with_box)) for p in ("m", "b", "k", "delay")},
            "gain_checks": len(gain_rows), "gain_exceptions": exceptions, "gains_per_pair": per_pair,
            "box_errors": [r["box_error"] for r in recs if "box_error" in r and "extremes" in r["box_error"]]}


def _reason_key(text: str) -> str:
    if "actuator lag" in text:
        return "a lag was fitted (box() refuses a lag)"
    if "not identified" in text:
        return "m or b not identified"
    if "does not fit" in text:
        return "the model does not fit (misfit)"
    return text[:100]


# ---- output --------------------------------------------------------------------------------------


def _fmt_cov(c: Optional[Dict[str, Any]]) -> str:
    if not c:
        return "-"
    return f"{c['hits']}/{c['n']} {100 * c['coverage']:.1f}%"


def report(recs: Sequence[Dict[str, Any]], args: argparse.Namespace, sim_seconds: float,
           wall: float) -> Tuple[List[str], Dict[str, Any]]:
    cov = coverage_table(recs)
    acc = accuracy_table(recs)
    box = box_summary(recs)
    crashes = [r for r in recs if "crash" in r]
    lines = [f"zwidth identify validation: {len(recs)} trials, seed {args.seed}, {args.jobs} jobs, "
             f"zwidth {zwidth.__version__}, numpy {np.__version__}, Python {platform.python_version()}, "
             f"{platform.machine()}",
             f"zwidth.identify: {zid.__file__} (sha256 {IDENTIFY_SHA256[:16]})",
             f"reference simulation (ident_reference.simulate_many, batched): {sim_seconds:.1f} s; "
             f"total wall clock {wall:.1f} s", ""]
    lines.append(f"1. Coverage of the true parameters by the stated {100 * LEVEL:g} % intervals "
                 "(hits/n; PASS: observed >= 0.95; lo/hi: one-sided 95 % Clopper-Pearson bounds of the "
                 "coverage over all parameters)")
    head = f"{'group':<20}{'fitted':>7}{'err':>5}  {'m':<16}{'b':<16}{'k':<16}{'tau':<16}{'F_c':<16}" \
           f"{'every':<17}{'lo':>6}{'hi':>6}{'delay ok':>9}  verdict"
    lines += [head, "-" * len(head)]
    for row in cov:
        e = row["every"]
        lines.append(f"{row['group']:<20}{row['fitted']:>7}{row['identify_errors']:>5}  "
                     + "".join(f"{_fmt_cov(row.get(p)):<16}" for p in ("m", "b", "k", "tau", "F_c"))
                     + f"{_fmt_cov(e):<17}{e['lower95']:>6.3f}{e['upper95']:>6.3f}"
                     + f"{100 * row['delay_right']:>8.1f}%  " + ("PASS" if row["pass"] else
                                                                  "FAIL (" + ", ".join(
                                                                      p for p in ("m", "b", "k", "tau", "F_c")
                                                                      if p in row and not row[p]["pass"]) + ")"))
    c = box["contains_truth"]
    lines += ["", f"2. Identification.box() (joint level {BOX_LEVEL}): {box['with_box']} of {box['trials']} trials "
                  f"have a box; it contains the true (m, b, k), with a delay at least the true one, in "
                  f"{c['hits']}/{c['n']} "
                  f"({100 * c['coverage']:.2f} %, one-sided 95 % bounds {c['lower95']:.4f}..{c['upper95']:.4f}): "
                  + ("PASS" if c["pass"] else "FAIL"),
              "   per part inside: " + ", ".join(f"{p} {v}/{c['n']}" for p, v in box["inside_per_part"].items()),
              "   per class: " + ", ".join(f"{k} {v['hits']}/{v['n']}" for k, v in box["contains_per_class"].items()),
              "   no box: " + ("; ".join(f"{v} x {k}" for k, v in
                                          sorted(box["without_box"].items(), key=lambda kv: -kv[1]))
                               or "none")]
    ex = box["gain_exceptions"]
    lines += ["", f"3. Gains of every box judged on the TRUE plant (zwidth.Device with the true delay, lag and "
                  f"spring): {box['gain_checks']} checks; exceptions (the box certifies the pair, the true plant is "
                  f"unstable): {len(ex)}" + ("  PASS" if not ex else "  FAIL")]
    lines.append(f"   {'pair':<28}{'checks':>7}{'box certifies':>15}{'  of them unstable':>19}"
                 f"{'not certified':>15}{'  of them unstable':>19}")
    for label, c in box["gains_per_pair"].items():
        lines.append(f"   {label:<28}{c['checks']:>7}{c['box_certifies']:>15}{c['certified_unstable']:>19}"
                     f"{c['not_certified']:>15}{c['not_certified_unstable']:>19}")
    lines.append("   (0.9 K_mmax, B_at) is certified by extremes(); (0.5 K_mmax, 0) often is not (at small delta B = 0 "
                 "holds little stiffness), so an unstable uncertified pair is no exception; b_range lo/hi: the ends of "
                 "box.b_range(0.5 K_mmax), certified")
    for e in box["box_errors"]:
        lines.append(f"   box error: {e}")
    for e in ex:
        lines.append(f"   EXCEPTION trial {e['trial']}: {e['pair']} K={e['K']:.6g} B={e['B']:.6g} "
                     f"(box contains truth: {e['box_contains_truth']})")
    lines += ["", "4. Accuracy (|relative error|: median, 95th percentile) and time per fit", ""]
    head = f"{'group':<18}{'method':<20}{'trials':>7}{'failed':>7}{'m med':>10}{'m p95':>10}{'b med':>10}" \
           f"{'b p95':>10}{'s/fit med':>11}{'s/fit mean':>11}"
    lines += [head, "-" * len(head)]
    for row in acc:
        lines.append(f"{row['group']:<18}{row['method']:<20}{row['trials']:>7}{row['failed']:>7}"
                     f"{row['m_median']:>10.2e}{row['m_p95']:>10.2e}{row['b_median']:>10.2e}{row['b_p95']:>10.2e}"
                     f"{row['seconds_median']:>11.4f}{row['seconds_mean']:>11.4f}")
    lines += ["", "   ARX: plain equation-error least squares with the true delay (second-order ARX with a spring);",
              "   scipy FRF fit: welch/csd H1 fitted by least_squares to e^{-s theta}/((tau s+1)(m s^2+b s+k))",
              "   from the truth times a factor in [1/2, 2]; python-control 0.10 has no fit of an input-output log."]
    if crashes:
        lines += ["", f"BENCH CRASHES: {len(crashes)}"] + [c["crash"] for c in crashes[:5]]
    diag = diagnosis(recs)
    lines += ["", "5. Misses by cause (trials with at least one true parameter outside its interval)", ""]
    head = f"{'class':<12}{'fitted':>7}{'missing':>8}{'  of them: wrong delay':>23}{'  tau > m/b':>12}" \
           f"{'  m or b not identified':>24}{'  misfit':>9}"
    lines += [head, "-" * len(head)]
    for c, d in diag.items():
        lines.append(f"{c:<12}{d['fitted']:>7}{d['missing']:>8}{d['wrong_delay']:>23}{d['tau_above_m_over_b']:>12}"
                     f"{d['not_identified']:>24}{d['misfit']:>9}")
    lines.append("   tau > m/b: the lag is slower than the mechanical pole; 1/(s (m s + b)(tau s + 1)) is symmetric "
                 "in m/b and tau, so the log cannot tell them apart")
    failures = failing_trials(recs, cov)
    if failures:
        lines += ["", f"6. Trials behind every FAIL ({len(failures)}; the first 80 here, all in the JSON): the "
                      "trial's parameters and what identify said"]
        lines += failures[:80]
    summary = {"identify_sha256": IDENTIFY_SHA256, "coverage": cov, "accuracy": acc, "box": box,
               "misses_by_cause": diag, "crashes": len(crashes), "sim_seconds": sim_seconds,
               "wall_seconds": wall, "trials": len(recs), "seed": args.seed, "jobs": args.jobs}
    return lines, summary


def diagnosis(recs: Sequence[Dict[str, Any]]) -> Dict[str, Dict[str, int]]:
    out: Dict[str, Dict[str, int]] = {}
    for c in CLASSES:
        fitted = [r for r in recs if r["trial"]["cls"] == c and "covered" in r]
        miss = [r for r in fitted if not all(r["covered"].values())]
        out[c] = {"fitted": len(fitted), "missing": len(miss),
                  "wrong_delay": sum(1 for r in miss if r["delay"] != r["trial"]["delay"]),
                  "tau_above_m_over_b": sum(1 for r in miss if r["trial"]["tau"] > r["trial"]["m"] / r["trial"]["b"]),
                  "not_identified": sum(1 for r in miss
                                        if not all(r["estimates"][p]["identified"] for p in ("m", "b"))),
                  "misfit": sum(1 for r in miss if not r["fit"]["ok"])}
    return out


def _describe(r: Dict[str, Any]) -> str:
    t = r["trial"]
    ms = "J" if t["rotary"] else "m"
    parts = [f"trial {t['index']} [{t['family']}, {t['cls']}]: {ms}={t['m']:.6g} b={t['b']:.6g} T={t['T']:.6g} "
             f"delta={t['b'] * t['T'] / t['m']:.4g} delay={t['delay']}"]
    if t["k"] > 0:
        parts.append(f"k={t['k']:.6g} (kappa={t['k'] * t['T'] ** 2 / t['m']:.3g})")
    if t["tau"] > 0:
        parts.append(f"tau={t['tau']:.4g} ({t['tau'] / t['T']:.3f} T)")
    if t["friction_ratio"] > 0:
        parts.append(f"F_c={r['truth']['F_c']:.4g} ({100 * t['friction_ratio']:.2f} % of A)")
    parts.append(f"n={t['n']} hold={t['hold']} "
                 + (f"encoder {t['counts_span']:.0f} counts, noise {t['noise_counts']:.2f} count"
                    if t["quantized"] else f"analog, noise {t['noise_ratio']:.2e} of the motion"))
    out = " ".join(parts)
    if "identify_error" in r:
        return out + f"\n      identify raised: {r['identify_error']}"
    est = "; ".join(f"{p}={e['value']:.6g} [{e['lo']:.6g}, {e['hi']:.6g}]"
                    + ("" if r["covered"].get(p, True) else " MISSES")
                    + ("" if e["identified"] else " (not identified)") for p, e in r["estimates"].items())
    out += f"\n      identify: delay {r['delay']}; {est}; fit: {r['fit']['reason']} (rho1 {r['fit']['rho1']:.2f})"
    if r.get("warnings"):
        out += "\n      warnings: " + " | ".join(r["warnings"])
    return out


def failing_trials(recs: Sequence[Dict[str, Any]], cov: Sequence[Dict[str, Any]]) -> List[str]:
    failing = {row["group"].split("=", 1)[1] for row in cov if row["group"].startswith("class=") and not row["pass"]}
    out = []
    for r in recs:
        if "crash" in r:
            continue
        bad_gain = any(g["box_certifies"] and not g["true_stable"] for g in r.get("gains", []))
        miss = "covered" in r and not all(r["covered"].values())
        if bad_gain or (miss and r["trial"]["cls"] in failing) or "identify_error" in r:
            out.append(("  GAIN EXCEPTION " if bad_gain else "  ") + _describe(r))
    return out


def main(argv: Optional[Sequence[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--trials", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--json", type=Path, default=None, help="write every figure and every trial here")
    ap.add_argument("--quick", action="store_true", help="50 trials (CI)")
    args = ap.parse_args(argv)
    if args.quick:
        args.trials = 50
    t_start = time.perf_counter()
    trials = [draw_trial(args.seed, i) for i in range(args.trials)]
    t0 = time.perf_counter()
    x = simulate_all(trials)
    sim_seconds = time.perf_counter() - t0
    jobs = [(t, x[t.index]) for t in trials]
    recs: List[Dict[str, Any]] = []
    done = 0
    if args.jobs > 1:
        with multiprocessing.get_context("fork" if sys.platform != "win32" else "spawn").Pool(args.jobs) as pool:
            for rec in pool.imap(run_trial_safe, jobs, chunksize=2):
                recs.append(rec)
                done += 1
                if done % 50 == 0:
                    print(f"  {done}/{len(jobs)} trials, {time.perf_counter() - t_start:.0f} s", file=sys.stderr,
                          flush=True)
    else:
        for job in jobs:
            recs.append(run_trial_safe(job))
    wall = time.perf_counter() - t_start
    lines, summary = report(recs, args, sim_seconds, wall)
    print("\n".join(lines))
    if args.json is not None:
        args.json.write_text(json.dumps({"summary": summary, "trials": recs}, separators=(",", ":"),
                                        default=_json_default, allow_nan=True) + "\n")
    return 0


def _json_default(o: Any) -> Any:
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, (np.floating,)):
        return float(o)
    if isinstance(o, np.bool_):
        return bool(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(type(o))


if __name__ == "__main__":
    sys.exit(main())
