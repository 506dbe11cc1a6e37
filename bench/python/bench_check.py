#!/usr/bin/env python3
"""Points per second: zwidth's stability check and k_max against what a control engineer
would otherwise write, all measured in one run on the same points.

Model (paper eqs (7), (8), (10); docs in /work/shared/notes/math.md): plant 1/(m s^2 + b s)
behind a ZOH, period T, controller H(z) = K + B (1 - z^-1)/T.  Normalized delta = bT/m,
alpha = K T^2/m, beta = B T/m.  Characteristic polynomial
    p(z) = 2 z^3 + a1 z^2 + a2 z - c2 beta,
    a1 = c1 (alpha + beta) - 2 (1 + e),  a2 = c2 alpha + (c2 - c1) beta + 2 e,
    e = exp(-delta), c1 = 2 (delta - 1 + e)/delta^2, c2 = 2 (1 - e - delta e)/delta^2.

Scenarios
    (a) one plant (m = 0.1, b = 30, T = 0.01, so delta = 3) and N gain pairs;
    (b) N points, each with its own delta, log-uniform in [1e-3, 20].
Points: alpha uniform in (0, 1.3 alpha_mmax(delta)), beta uniform in (-delta, beta_mmax(delta))
(ranges from zwidth.extremes), fixed seed; about half of them are stable.

Methods, stability (is the closed loop stable?)
    zwidth check              zwidth.check(delta, alpha, beta) (C loop; delta a scalar in (a))
    zwidth Device.is_stable   (a) only: Device(m, b, T).is_stable(K, B), real units
    numpy closed form         eq (10) vectorized in plain numpy with the paper's literal
                              coefficient formulas: beta > -delta, 0 < alpha < f(beta),
                              alpha < L(beta); no rounding guard
    numpy eigvals, batched    np.linalg.eigvals on the (N, 3, 3) companion matrices of p
                              (chunks of 65536), stable iff max |eigenvalue| < 1
    numpy.roots per point     coefficients in numpy, then np.roots in a Python loop (subset)
    python-control per point  c2d(1/(m s^2 + b s), T, 'zoh'), controller tf, feedback,
                              poles, max |pole| < 1, in a Python loop (subset; in (a) the
                              plant is discretized once, outside the loop)
Methods, k_max (largest stable stiffness at a given damping)
    zwidth Device.k_max(B) (a), zwidth.alpha_max(delta, beta) (both scenarios), and the plain
    numpy closed form min{f(beta), L(beta)}, clipped at 0, 0 for beta <= -delta.

Timing: best of --repeats (fast, whole arrays) or --slow-repeats (per-point loops) with
time.perf_counter; every method starts from the same input arrays (and computes its own
coefficients).  Per-point loops are timed on the first --control-subset / --roots-subset
points and reported as points per second on that subset (the "points" column).

Disagreements: each method's verdict against zwidth.check's on the same points; "away"
counts only points with |spectral radius - 1| > --band (zwidth.spectral_radius), where
every correct method must agree; "all" counts every point (near the boundary zwidth is
guarded and says unstable within a rounding band, the peers are not).  For k_max a
disagreement is a relative difference > --band; "away" there means alpha_max > band *
alpha_mmax(delta) (not at an end of the damping range, where k_max -> 0).

Run (from the repository root):
    .venv/bin/python bench/python/bench_check.py                 # 1e6 points, ~1 min
    .venv/bin/python bench/python/bench_check.py --quick         # CI smoke, < 20 s
    .venv/bin/python bench/python/bench_check.py --json out.json # also write the results
Exit status 0 whatever the targets say (it is a measurement); 2 on bad options.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time
from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np

SEED = 20240521
M, B_PLANT, T = 0.1, 30.0, 0.01          # scenario (a): delta = b T / m = 3
DELTA_RANGE = (1e-3, 20.0)               # scenario (b): log-uniform
EIG_CHUNK = 65536


def log(message: str) -> None:
    print(f"[bench_check] {message}", file=sys.stderr, flush=True)


def import_zwidth(wait_s: float = 60.0) -> Any:
    """import zwidth, retrying for a while: the package may be being rebuilt."""
    deadline = time.monotonic() + wait_s
    while True:
        try:
            import zwidth  # noqa: WPS433
            return zwidth
        except ImportError as exc:  # pragma: no cover - only during a rebuild
            if time.monotonic() > deadline:
                raise
            log(f"import zwidth failed ({exc}); retrying in 3 s")
            time.sleep(3.0)


# --------------------------------------------------------------------------- peers
# Straightforward implementations of the model, as a competent engineer would write them.

def literal_coefficients(delta: Any) -> Tuple[Any, Any, Any]:
    """e, c1, c2 by the paper's formulas (3), (4) (scalar or array delta)."""
    e = np.exp(-delta)
    c1 = 2.0 * (delta - 1.0 + e) / delta**2
    c2 = 2.0 * (1.0 - e - delta * e) / delta**2
    return e, c1, c2


def closed_form_stable(delta: Any, alpha: np.ndarray, beta: np.ndarray) -> np.ndarray:
    """Exact region eq (10) in plain numpy."""
    e, c1, c2 = literal_coefficients(delta)
    d12 = c1 - c2
    f = (-(c1 + c2) * c2 * beta**2 + 2.0 * (c1 + e * c2) * beta + 4.0 * (1.0 - e)) / ((c1 * beta + 2.0) * c2)
    line = 4.0 * (1.0 + e) / d12 - 2.0 * beta
    return (beta > -delta) & (alpha > 0.0) & (alpha < f) & (alpha < line)


def closed_form_alpha_max(delta: Any, beta: np.ndarray) -> np.ndarray:
    """sup alpha stable at beta: min{f(beta), L(beta)}, 0 where none is (plain numpy)."""
    e, c1, c2 = literal_coefficients(delta)
    d12 = c1 - c2
    f = (-(c1 + c2) * c2 * beta**2 + 2.0 * (c1 + e * c2) * beta + 4.0 * (1.0 - e)) / ((c1 * beta + 2.0) * c2)
    line = 4.0 * (1.0 + e) / d12 - 2.0 * beta
    return np.where(beta > -delta, np.maximum(np.minimum(f, line), 0.0), 0.0)


def char_poly_coefficients(delta: Any, alpha: np.ndarray, beta: np.ndarray) -> Tuple[Any, ...]:
    """a1, a2, a3 = -c2 beta of p(z) = 2 z^3 + a1 z^2 + a2 z + a3 (numpy)."""
    e, c1, c2 = literal_coefficients(delta)
    a1 = c1 * (alpha + beta) - 2.0 * (1.0 + e)
    a2 = c2 * alpha + (c2 - c1) * beta + 2.0 * e
    a3 = -c2 * beta
    return a1, a2, a3


def eigvals_radius(delta: Any, alpha: np.ndarray, beta: np.ndarray) -> np.ndarray:
    """Largest |root| of p via batched eigenvalues of the companion matrices."""
    a1, a2, a3 = char_poly_coefficients(delta, alpha, beta)
    n = alpha.shape[0]
    a1, a2, a3 = (np.broadcast_to(a, (n,)) for a in (a1, a2, a3))
    rho = np.empty(n)
    for start in range(0, n, EIG_CHUNK):
        s = slice(start, min(start + EIG_CHUNK, n))
        k = s.stop - s.start
        comp = np.zeros((k, 3, 3))
        comp[:, 0, 0] = -0.5 * a1[s]
        comp[:, 0, 1] = -0.5 * a2[s]
        comp[:, 0, 2] = -0.5 * a3[s]
        comp[:, 1, 0] = 1.0
        comp[:, 2, 1] = 1.0
        rho[s] = np.abs(np.linalg.eigvals(comp)).max(axis=1)
    return rho


def eigvals_stable(delta: Any, alpha: np.ndarray, beta: np.ndarray) -> np.ndarray:
    return eigvals_radius(delta, alpha, beta) < 1.0


def roots_stable(delta: Any, alpha: np.ndarray, beta: np.ndarray) -> np.ndarray:
    """np.roots per point, coefficients computed vectorized first."""
    a1, a2, a3 = char_poly_coefficients(delta, alpha, beta)
    n = alpha.shape[0]
    a1, a2, a3 = (np.broadcast_to(a, (n,)) for a in (a1, a2, a3))
    out = np.empty(n, dtype=bool)
    for i in range(n):
        r = np.roots([2.0, a1[i], a2[i], a3[i]])
        out[i] = np.abs(r).max() < 1.0
    return out


def control_stable_one_plant(ct: Any, m: float, b: float, T: float,
                             K: np.ndarray, B: np.ndarray) -> np.ndarray:
    """python-control, one plant: discretize once, then controller + feedback per gain pair."""
    plant = ct.c2d(ct.tf([1.0], [m, b, 0.0]), T, method="zoh")
    out = np.empty(K.shape[0], dtype=bool)
    for i in range(K.shape[0]):
        k, d = float(K[i]), float(B[i])
        controller = ct.tf([k + d / T, -d / T], [1.0, 0.0], T)   # K + B (1 - z^-1)/T
        loop = ct.feedback(plant * controller, 1)
        out[i] = np.abs(loop.poles()).max() < 1.0
    return out


def control_stable_per_plant(ct: Any, m: np.ndarray, b: np.ndarray, T: np.ndarray,
                             K: np.ndarray, B: np.ndarray) -> np.ndarray:
    """python-control, every point its own plant: c2d, controller, feedback, poles."""
    out = np.empty(K.shape[0], dtype=bool)
    for i in range(K.shape[0]):
        mi, bi, Ti, k, d = float(m[i]), float(b[i]), float(T[i]), float(K[i]), float(B[i])
        plant = ct.c2d(ct.tf([1.0], [mi, bi, 0.0]), Ti, method="zoh")
        controller = ct.tf([k + d / Ti, -d / Ti], [1.0, 0.0], Ti)
        loop = ct.feedback(plant * controller, 1)
        out[i] = np.abs(loop.poles()).max() < 1.0
    return out


# --------------------------------------------------------------------------- timing, formatting

def best_of(fn: Callable[[], Any], repeats: int) -> Tuple[Tuple[float, float], Any]:
    """((wall, cpu) seconds of the fastest run, its result); cpu counts every thread."""
    best, cpu, out = math.inf, math.inf, None
    for _ in range(max(1, repeats)):
        c0, t0 = time.process_time(), time.perf_counter()
        out = fn()
        wall, used = time.perf_counter() - t0, time.process_time() - c0
        if wall < best:
            best, cpu = wall, used
    return (best, cpu), out


def si(x: float) -> str:
    for scale, suffix in ((1e9, " G"), (1e6, " M"), (1e3, " k")):
        if x >= scale:
            return f"{x / scale:.3g}{suffix}"
    return f"{x:.3g}"


def per_point(seconds: float) -> str:
    for scale, unit in ((1.0, "s"), (1e-3, "ms"), (1e-6, "µs")):
        if seconds >= scale:
            return f"{seconds / scale:.3g} {unit}"
    return f"{seconds / 1e-9:.3g} ns"


def machine() -> Dict[str, Any]:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    info: Dict[str, Any] = {
        "platform": platform.platform(), "python": platform.python_version(), "cpu": cpu,
        "cpu_count": os.cpu_count(), "numpy": np.__version__,
    }
    try:
        info["affinity"] = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        pass
    return info


# --------------------------------------------------------------------------- the benchmark

class Bench:
    def __init__(self, args: argparse.Namespace, zw: Any, ct: Optional[Any]) -> None:
        self.args, self.zw, self.ct = args, zw, ct
        self.rows: List[Dict[str, Any]] = []
        self.targets: List[Dict[str, Any]] = []

    def add(self, *, kind: str, scenario: str, method: str, seconds: float, n: int,
            ref: Optional[Dict[str, Any]], away_bad: Optional[int], n_away: Optional[int],
            all_bad: Optional[int], note: str = "") -> Dict[str, Any]:
        row = {"kind": kind, "scenario": scenario, "method": method, "points": n,
               "seconds": seconds, "points_per_s": n / seconds, "s_per_point": seconds / n,
               "zwidth_speedup": (ref["points_per_s"] / (n / seconds)) if ref else None,
               "disagree_away": away_bad, "n_away": n_away, "disagree_all": all_bad, "note": note}
        self.rows.append(row)
        return row

    @staticmethod
    def compare(verdict: np.ndarray, ref: np.ndarray, away: np.ndarray) -> Tuple[int, int, int]:
        diff = verdict != ref
        return int(np.count_nonzero(diff & away)), int(np.count_nonzero(away)), int(np.count_nonzero(diff))

    # ---- stability
    def stability(self, scenario: str, delta: Any, alpha: np.ndarray, beta: np.ndarray,
                  plant: Tuple[Any, Any, Any], K: np.ndarray, B: np.ndarray) -> None:
        a, zw, n = self.args, self.zw, alpha.shape[0]
        one_plant = np.ndim(delta) == 0
        log(f"{scenario}: spectral radius of {n} points (zwidth) for the boundary band")
        rho = zw.spectral_radius(delta, alpha, beta)
        away = np.abs(rho - 1.0) > a.band

        log(f"{scenario}: zwidth")
        t, ref_verdict = best_of(lambda: zw.check(delta, alpha, beta), a.repeats)
        ref = self.add(kind="stability", scenario=scenario, method="zwidth check (C)", seconds=t, n=n,
                       ref=None, away_bad=None, n_away=int(away.sum()), all_bad=None,
                       note=f"{ref_verdict.mean():.1%} stable")
        zw_rows = [ref]
        if one_plant:
            m, b, T_ = plant
            dev = zw.Device(m, b, T_)
            t, v = best_of(lambda: dev.is_stable(K, B), a.repeats)
            zw_rows.append(self.add(kind="stability", scenario=scenario,
                                    method="zwidth Device.is_stable (C)", seconds=t, n=n, ref=ref,
                                    **dict(zip(("away_bad", "n_away", "all_bad"),
                                               self.compare(v, ref_verdict, away))),
                                    note="real units K, B"))

        log(f"{scenario}: numpy closed form")
        t, v = best_of(lambda: closed_form_stable(delta, alpha, beta), a.repeats)
        closed = self.add(kind="stability", scenario=scenario, method="numpy closed form eq (10)",
                          seconds=t, n=n, ref=ref,
                          **dict(zip(("away_bad", "n_away", "all_bad"), self.compare(v, ref_verdict, away))))

        log(f"{scenario}: numpy batched eigvals ({n} points)")
        t, v = best_of(lambda: eigvals_stable(delta, alpha, beta), a.eig_repeats)
        eig = self.add(kind="stability", scenario=scenario, method="numpy eigvals, batched (N,3,3)",
                       seconds=t, n=n, ref=ref,
                       **dict(zip(("away_bad", "n_away", "all_bad"), self.compare(v, ref_verdict, away))))

        k = min(a.roots_subset, n)
        log(f"{scenario}: numpy.roots per point ({k} points)")
        d_sub = delta if one_plant else delta[:k]
        t, v = best_of(lambda: roots_stable(d_sub, alpha[:k], beta[:k]), a.slow_repeats)
        self.add(kind="stability", scenario=scenario, method="numpy.roots per point", seconds=t, n=k,
                 ref=ref, **dict(zip(("away_bad", "n_away", "all_bad"),
                                     self.compare(v, ref_verdict[:k], away[:k]))), note="subset")

        if self.ct is not None:
            k = min(a.control_subset, n)
            log(f"{scenario}: python-control per point ({k} points)")
            if one_plant:
                m, b, T_ = plant
                fn = lambda: control_stable_one_plant(self.ct, m, b, T_, K[:k], B[:k])  # noqa: E731
                note = "subset; c2d once"
            else:
                m, b, T_ = (np.broadcast_to(x, (n,))[:k] for x in plant)
                fn = lambda: control_stable_per_plant(self.ct, m, b, T_, K[:k], B[:k])  # noqa: E731
                note = "subset; c2d per point"
            t, v = best_of(fn, a.slow_repeats)
            self.add(kind="stability", scenario=scenario, method="python-control per point", seconds=t,
                     n=k, ref=ref, **dict(zip(("away_bad", "n_away", "all_bad"),
                                              self.compare(v, ref_verdict[:k], away[:k]))), note=note)

        peers = [r for r in self.rows if r["scenario"] == scenario and r["kind"] == "stability"
                 and not r["method"].startswith("zwidth")]
        for zr in zw_rows:
            vs_eig = zr["points_per_s"] / eig["points_per_s"]
            vs_closed = zr["points_per_s"] / closed["points_per_s"]
            self.targets.append({"scenario": scenario, "kind": "stability", "method": zr["method"],
                                 "x_eigvals": vs_eig, "x_closed_form": vs_closed,
                                 "eigvals_100x": vs_eig >= 100.0, "beats_closed_form": vs_closed > 1.0})
        self.targets.append({"scenario": scenario, "kind": "stability", "method": "peers",
                             "disagree_away": sum(r["disagree_away"] for r in peers + zw_rows[1:]),
                             "zero_away": all(r["disagree_away"] == 0 for r in peers + zw_rows[1:])})

    # ---- k_max
    def k_max(self, scenario: str, delta: Any, beta: np.ndarray,
              plant: Tuple[Any, Any, Any], B: np.ndarray) -> None:
        a, zw, n = self.args, self.zw, beta.shape[0]
        one_plant = np.ndim(delta) == 0
        log(f"{scenario}: k_max")
        band = a.band
        amm = zw.extremes(delta).alpha_mmax

        def disagreements(value: np.ndarray, ref_value: np.ndarray, away: np.ndarray) -> Tuple[int, int, int]:
            bad = np.abs(value - ref_value) > band * np.abs(ref_value)
            return int(np.count_nonzero(bad & away)), int(np.count_nonzero(away)), int(np.count_nonzero(bad))

        t, ref_alpha = best_of(lambda: zw.alpha_max(delta, beta), a.repeats)
        away = ref_alpha > band * amm
        ref = self.add(kind="k_max", scenario=scenario, method="zwidth alpha_max (C)", seconds=t, n=n,
                       ref=None, away_bad=None, n_away=int(away.sum()), all_bad=None,
                       note=f"{(ref_alpha > 0).mean():.1%} nonzero")
        zw_rows = [ref]
        if one_plant:
            m, b, T_ = plant
            dev = zw.Device(m, b, T_)
            t, kmax = best_of(lambda: dev.k_max(B), a.repeats)
            zw_rows.append(self.add(kind="k_max", scenario=scenario, method="zwidth Device.k_max (C)",
                                    seconds=t, n=n, ref=ref,
                                    **dict(zip(("away_bad", "n_away", "all_bad"),
                                               disagreements(kmax * T_**2 / m, ref_alpha, away))),
                                    note="real units B -> K"))

            def closed_real() -> np.ndarray:
                return closed_form_alpha_max(delta, B * T_ / m) * (m / T_**2)
            t, kc = best_of(closed_real, a.repeats)
            value = kc * T_**2 / m
            note = "real units B -> K"
        else:
            t, value = best_of(lambda: closed_form_alpha_max(delta, beta), a.repeats)
            note = ""
        closed = self.add(kind="k_max", scenario=scenario, method="numpy closed form min{f, L}", seconds=t,
                          n=n, ref=ref, note=note,
                          **dict(zip(("away_bad", "n_away", "all_bad"), disagreements(value, ref_alpha, away))))
        for zr in zw_rows:
            vs_closed = zr["points_per_s"] / closed["points_per_s"]
            self.targets.append({"scenario": scenario, "kind": "k_max", "method": zr["method"],
                                 "x_closed_form": vs_closed, "beats_closed_form": vs_closed > 1.0})
        self.targets.append({"scenario": scenario, "kind": "k_max", "method": "peers",
                             "disagree_away": closed["disagree_away"] + sum(r["disagree_away"] for r in zw_rows[1:]),
                             "zero_away": closed["disagree_away"] == 0
                             and all(r["disagree_away"] == 0 for r in zw_rows[1:])})


def sample(zw: Any, rng: np.random.Generator, delta: Any, n: int) -> Tuple[np.ndarray, np.ndarray]:
    ex = zw.extremes(delta)
    alpha = rng.uniform(0.0, 1.0, n) * (1.3 * ex.alpha_mmax)
    beta = -delta + rng.uniform(0.0, 1.0, n) * (ex.beta_mmax + delta)
    # uniform(0, 1) may return exactly 0: keep every point strictly inside the sampling box
    alpha = np.where(alpha > 0.0, alpha, 0.5 * np.asarray(1.3 * ex.alpha_mmax))
    return alpha, beta


def table(rows: List[Dict[str, Any]]) -> str:
    head = ("| scenario | method | points | points/s | time/point | zwidth speed-up "
            "| disagree, away from boundary | disagree, all | note |")
    lines = [head, "|" + "---|" * 9]
    for r in rows:
        speed = "ref" if r["zwidth_speedup"] is None else f"{r['zwidth_speedup']:.3g}x"
        away = "—" if r["disagree_away"] is None else f"{r['disagree_away']} / {r['n_away']}"
        every = "—" if r["disagree_all"] is None else f"{r['disagree_all']} / {r['points']}"
        if r["disagree_away"] is None:
            away = f"(ref; {r['n_away']} away)"
        lines.append(f"| {r['scenario']} | {r['method']} | {r['points']} | {si(r['points_per_s'])} "
                     f"| {per_point(r['s_per_point'])} | {speed} | {away} | {every} | {r['note']} |")
    return "\n".join(lines)


def main(argv: Optional[List[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--points", type=float, default=1e6, help="points per scenario (default 1e6)")
    p.add_argument("--quick", action="store_true", help="small sizes for a CI smoke run (< 20 s)")
    p.add_argument("--json", metavar="PATH", help="also write the results as JSON")
    p.add_argument("--seed", type=int, default=SEED)
    p.add_argument("--repeats", type=int, default=7, help="repeats of the fast methods (best of)")
    p.add_argument("--eig-repeats", type=int, default=3, help="repeats of batched eigvals")
    p.add_argument("--slow-repeats", type=int, default=3, help="repeats of the per-point loops")
    p.add_argument("--roots-subset", type=int, default=20000)
    p.add_argument("--control-subset", type=int, default=1000)
    p.add_argument("--band", type=float, default=1e-6,
                   help="boundary band: |spectral radius - 1| (and k_max relative tolerance)")
    p.add_argument("--no-control", action="store_true", help="skip python-control")
    a = p.parse_args(argv)
    if a.quick:
        a.points = min(a.points, 20000)
        a.roots_subset = min(a.roots_subset, 2000)
        a.control_subset = min(a.control_subset, 100)
        a.repeats = min(a.repeats, 3)
        a.eig_repeats = min(a.eig_repeats, 3)
    n = int(a.points)
    if n < 1 or min(a.repeats, a.eig_repeats, a.slow_repeats, a.roots_subset, a.control_subset) < 1 \
            or not a.band > 0:
        p.error("sizes, repeats and --band must be positive")

    t_start = time.perf_counter()
    zw = import_zwidth()
    ct = None
    if not a.no_control:
        try:
            import control as ct  # noqa: WPS433
        except ImportError:
            log("python-control is not installed: its rows are skipped (pip install control)")
    info = machine()
    info["zwidth"] = getattr(zw, "__version__", "?")
    info["control"] = getattr(ct, "__version__", None) if ct is not None else None

    rng = np.random.default_rng(a.seed)
    bench = Bench(a, zw, ct)

    # (a) one plant, N gain pairs
    delta_a = B_PLANT * T / M
    alpha_a, beta_a = sample(zw, rng, delta_a, n)
    K_a, B_a = alpha_a * (M / T**2), beta_a * (M / T)
    sa = f"(a) delta={delta_a:g}"
    bench.stability(sa, delta_a, alpha_a, beta_a, (M, B_PLANT, T), K_a, B_a)

    # (b) N points, each its own delta (python-control gets m = 0.1, T = 0.01, b = delta m/T)
    lo, hi = DELTA_RANGE
    delta_b = np.exp(rng.uniform(math.log(lo), math.log(hi), n))
    alpha_b, beta_b = sample(zw, rng, delta_b, n)
    m_b, T_b = M, T
    b_b = delta_b * m_b / T_b
    K_b, B_b = alpha_b * (m_b / T_b**2), beta_b * (m_b / T_b)
    sb = "(b) delta per point"
    bench.stability(sb, delta_b, alpha_b, beta_b, (m_b, b_b, T_b), K_b, B_b)

    bench.k_max(sa, delta_a, beta_a, (M, B_PLANT, T), B_a)
    bench.k_max(sb, delta_b, beta_b, (m_b, b_b, T_b), B_b)
    elapsed = time.perf_counter() - t_start

    print("# zwidth: points per second, stability check and k_max\n")
    print(f"- machine: {info['platform']}; {info['cpu']}; {info['cpu_count']} CPUs"
          + (f" ({info['affinity']} usable)" if "affinity" in info else ""))
    print(f"- python {info['python']}, numpy {info['numpy']}, python-control {info['control']}, "
          f"zwidth {info['zwidth']}")
    print(f"- {n} points per scenario, seed {a.seed}; best of {a.repeats} (fast), {a.eig_repeats} "
          f"(eigvals), {a.slow_repeats} (per-point loops); boundary band {a.band:g}; "
          f"run time {elapsed:.1f} s")
    print(f"- (a): m = {M}, b = {B_PLANT}, T = {T} (delta = {delta_a:g}); (b): delta log-uniform in "
          f"[{lo:g}, {hi:g}]; alpha in (0, 1.3 alpha_mmax), beta in (-delta, beta_mmax)\n")
    print("## Stability (is the closed loop stable?)\n")
    print(table([r for r in bench.rows if r["kind"] == "stability"]))
    print("\n## k_max (largest stable K at a given B; normalized: alpha_max at beta)\n")
    print(table([r for r in bench.rows if r["kind"] == "k_max"]))
    print()

    verdicts = []
    for tg in bench.targets:
        if tg["method"] == "peers":
            ok = tg["zero_away"]
            verdicts.append(ok)
            print(f"- {tg['scenario']} {tg['kind']}: zero disagreements away from the boundary: "
                  f"{'MET' if ok else 'NOT MET'} ({tg['disagree_away']})")
            continue
        if "x_eigvals" in tg:
            ok = tg["eigvals_100x"]
            verdicts.append(ok)
            print(f"- {tg['scenario']} {tg['method']}: >= 100x batched eigvals: "
                  f"{'MET' if ok else 'NOT MET'} ({tg['x_eigvals']:.3g}x)")
        ok = tg["beats_closed_form"]
        verdicts.append(ok)
        print(f"- {tg['scenario']} {tg['kind']} {tg['method']}: faster than the numpy closed form: "
              f"{'MET' if ok else 'NOT MET'} ({tg['x_closed_form']:.3g}x)")
    print(f"\nTARGETS: {'ALL MET' if all(verdicts) else 'NOT ALL MET'} "
          f"({sum(verdicts)} of {len(verdicts)} met)")

    if a.json:
        with open(a.json, "w", encoding="utf-8") as fh:
            json.dump({"machine": info, "points": n, "seed": a.seed, "band": a.band,
                       "repeats": {"fast": a.repeats, "eigvals": a.eig_repeats, "loops": a.slow_repeats},
                       "run_seconds": elapsed, "rows": bench.rows, "targets": bench.targets,
                       "all_targets_met": all(verdicts)}, fh, indent=2)
        log(f"wrote {a.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
