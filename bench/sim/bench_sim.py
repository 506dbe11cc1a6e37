#!/usr/bin/env python3

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Samples per second of zwidth's scene simulation against what a control engineer would
otherwise write, and accuracy against time of its integrator, measured in one run.

Part 1, the linear scene: point P5 of paper Fig. 15 (scenes/paper-fig15.toml),
m = 0.1 kg, b = 30 N s/m, T = 0.01 s (delta = 3), K = 7000 N/m, B = 20 N s/m (alpha = 7,
beta = 2: stable, spectral radius ~0.84, a ringing step response), equilibrium stepped
0 -> 1 m at t = 0, 1e6 samples.  Every method simulates the same sampled loop (sim.h):
    F_k = K (x_eq - x_k) - (B/T)(x_k - x_{k-1})          (x_{-1} = x_0)
    x_{k+1} = x_k + T phi v_k + (T^2/m)(c1/2) F_k,  v_{k+1} = e v_k + (T/m) phi F_k,
    phi = (c1 + c2)/2 = (1 - e)/delta,  e = exp(-delta)
as the closed-loop state space with state (x_k, v_k, x_{k-1}) and input x_eq:
    A = [[1 - g K - g B/T, T phi, g B/T], [-h K - h B/T, e, h B/T], [1, 0, 0]],
    Bu = [g K, h K, 0],  C = [1, 0, 0],  D = 0,   g = (T^2/m)(c1/2), h = (T/m) phi,
with c1, c2 from the paper's literal formulas (no cancellation at delta = 3); the plant
part is checked against scipy.signal.cont2discrete (ZOH) of m x'' + b x' = F.
Methods
    zwidth Simulator.run      zwidth._core.Simulator(scene).run(n), signals t and x
                              (and x only); the C loop, GIL released
    zwidth.simulate           the public API on the same scene as TOML text (parsing,
                              every signal, the verdict and the analytic check included)
    scipy.signal.dlsim        on (A, Bu, C, D, T) (a Python loop over samples inside scipy)
    python-control            forced_response on ss(A, Bu, C, D, T)
    scipy.signal.lfilter      the same loop as a transfer function (ss2tf) run by lfilter's
                              C loop: what a competent engineer may reach for; linear only
    plain Python loop         the recurrence above, written out in Python floats
Each method's x is compared with zwidth's (max abs difference).  Target (issue 5): zwidth
bare >= 50x scipy.signal.dlsim.

Part 2, accuracy against time for the nonlinear scenes (friction, a hand, a wall hit by a
hand, stick-slip with quantization): for each substeps value (RK4 steps per sample) the
max |x - x_ref| over the run, x_ref a run at 100x the finest step offered (substeps
100 x max), and the time per sample.  "ref check" is the reference against a run at half
its substeps (an estimate of the reference's own error).  Scenes come from scenes/*.toml
when the file exists (its first case, through zwidth.simulate), else the dicts below.

Part 3, the order of the friction integration: the review's friction scene (m = 0.1 kg,
b = 2 N s/m, T = 1 ms, K = 2000 N/m, B = 1 N s/m, step 0 -> 10 mm, Coulomb 3 N, stiction
5 N, 100 samples) against a reference that solves every piece and every stop in closed
form at 40 digits (tests/py/sim_reference.friction_trajectory, mpmath): max |x - x_ref|
for 1, 2, 4, ... substeps and the observed order log2(e(n) / e(2n)).  Target (issue 14):
order >= 3.6 (RK4's 4) while the error is above rounding; the stop at the end of the
substep it replaced gave 1.

Timing: best of --repeats (fast) or --slow-repeats (Python loops) with time.perf_counter,
the fast methods interleaved with each other.  Ratios are within this one run.

Run (from the repository root):
    .venv/bin/python bench/sim/bench_sim.py              # 1e6 samples, ~40 s
    .venv/bin/python bench/sim/bench_sim.py --quick      # CI smoke, a few seconds
    .venv/bin/python bench/sim/bench_sim.py --markdown   # only the README tables
Needs numpy, scipy and zwidth; python-control optional (its row is skipped without it).
Report on stdout, progress on stderr.  Exit status 0 whatever the targets say; 2 on bad
options.
"""
from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

REPO = Path(__file__).resolve().parents[2]
# The number formats of the project's other benchmark, so the README's tables read alike.
sys.path.insert(0, str(REPO / "bench" / "python"))
from bench_check import cpu_name, per_point as per_sample, si  # noqa: E402
M, B_PLANT, T = 0.1, 30.0, 0.01
K_LIN, B_LIN = 7000.0, 20.0   # point P5 of paper Fig. 15 (scenes/paper-fig15.toml): alpha 7, beta 2
SUBSTEPS = (1, 2, 5, 10, 20, 50, 100)
MAX_SUBSTEPS = 100000   # ZW_SIM_MAX_SUBSTEPS


def log(message: str) -> None:
    print(f"[bench_sim] {message}", file=sys.stderr, flush=True)


def best_of(fn: Callable[[], Any], repeats: int) -> Tuple[float, Any]:
    best, out = math.inf, None
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def machine(zw: Any, ct: Any) -> str:
    cpu = cpu_name()
    import scipy
    return (f"{platform.platform()}; {cpu}; {os.cpu_count()} CPUs; python {platform.python_version()}, "
            f"numpy {np.__version__}, scipy {scipy.__version__}, "
            f"python-control {getattr(ct, '__version__', None) if ct else None}, "
            f"zwidth {getattr(zw, '__version__', '?')}; load average at the start "
            f"{os.getloadavg()[0]:.2f}")


# --------------------------------------------------------------------------- the linear loop

def literal_step(m: float, b: float, T_: float) -> Dict[str, float]:
    """The exact ZOH step of sim.h from the paper's literal c1, c2 (fine at delta = 3)."""
    delta = b * T_ / m
    e = math.exp(-delta)
    c1 = 2.0 * (delta - 1.0 + e) / delta**2
    c2 = 2.0 * (1.0 - e - delta * e) / delta**2
    phi = (c1 + c2) / 2.0
    return {"e": e, "phi_T": T_ * phi, "g": (T_ * T_ / m) * (c1 / 2.0), "h": (T_ / m) * phi}


def closed_loop(m: float, b: float, T_: float, K: float, B: float) -> Tuple[np.ndarray, ...]:
    s = literal_step(m, b, T_)
    e, phi_T, g, h, BT = s["e"], s["phi_T"], s["g"], s["h"], B / T_
    A = np.array([[1.0 - g * K - g * BT, phi_T, g * BT],
                  [-h * K - h * BT, e, h * BT],
                  [1.0, 0.0, 0.0]])
    Bu = np.array([[g * K], [h * K], [0.0]])
    C = np.array([[1.0, 0.0, 0.0]])
    D = np.array([[0.0]])
    return A, Bu, C, D


def zoh_check(m: float, b: float, T_: float) -> float:
    """max |difference| between the literal step and scipy's ZOH of m x'' + b x' = F."""
    from scipy.signal import cont2discrete
    Ad, Bd, *_ = cont2discrete((np.array([[0.0, 1.0], [0.0, -b / m]]), np.array([[0.0], [1.0 / m]]),
                                np.eye(2), np.zeros((2, 1))), T_, method="zoh")
    s = literal_step(m, b, T_)
    ours_A = np.array([[1.0, s["phi_T"]], [0.0, s["e"]]])
    ours_B = np.array([[s["g"]], [s["h"]]])
    return float(max(np.abs(Ad - ours_A).max(), np.abs(Bd - ours_B).max()))


def python_loop(n: int, m: float, b: float, T_: float, K: float, B: float, x_eq: float) -> np.ndarray:
    s = literal_step(m, b, T_)
    e, phi_T, g, h, BT = s["e"], s["phi_T"], s["g"], s["h"], B / T_
    xs = [0.0] * n
    x = v = 0.0
    x_prev = x
    for k in range(n):
        F = K * (x_eq - x) - BT * (x - x_prev)
        xs[k] = x
        x_prev = x
        x, v = x + phi_T * v + g * F, e * v + h * F
    return np.array(xs)


def linear_scene() -> Dict[str, Any]:
    return dict(m=M, b=B_PLANT, T=T, K=K_LIN, B=B_LIN, x_init=0.0, v_init=0.0,
                x_eq_before=0.0, x_eq_after=1.0, t_step=0.0, effects=0)


def linear_toml(n: int) -> str:
    # duration n T; the table counts the samples simulate() returns.
    return f"""
[scene]
name = "bench-linear"
description = "bench_sim.py: the linear loop, 1e6 samples"
duration = "{n * T:.12g} s"
[plant]
m = "{M} kg"
b = "{B_PLANT} N*s/m"
T = "{T} s"
[controller]
K = "{K_LIN} N/m"
B = "{B_LIN} N*s/m"
[reference]
from = "0 m"
to = "1 m"
at = "0 s"
"""


def bench_linear(a: argparse.Namespace, zw: Any, ct: Any) -> Tuple[List[Dict[str, Any]], Dict[str, Any]]:
    from scipy import signal
    core = zw._core
    n = a.samples
    rows: List[Dict[str, Any]] = []
    scene = linear_scene()

    def add(method: str, seconds: float, samples: int, x: Optional[np.ndarray], note: str = "") -> None:
        rows.append({"method": method, "seconds": seconds, "samples": samples,
                     "rate": samples / seconds, "x": x, "note": note})

    # the fast ones, interleaved, best of --repeats
    A, Bu, C, D = closed_loop(M, B_PLANT, T, K_LIN, B_LIN)
    num, den = signal.ss2tf(A, Bu, C, D)
    u = np.ones(n)
    x0 = np.zeros(3)
    fast: Dict[str, Callable[[], np.ndarray]] = {
        "zwidth Simulator.run (t, x)": lambda: core.Simulator(scene).run(n)["x"],
        "zwidth Simulator.run (x only)": lambda: core.Simulator(scene).run(n, ("x",))["x"],
        "scipy.signal.lfilter (transfer function)": lambda: signal.lfilter(num[0], den, u),
    }
    notes = {"zwidth Simulator.run (t, x)": "ref",
             "scipy.signal.lfilter (transfer function)":
                 "ss2tf of the loop; linear scenes only, no per-effect signals"}
    simulate, load = getattr(zw, "simulate", None), getattr(zw, "load_scene", None)
    verdict: List[str] = []
    if simulate is not None and load is not None:
        scene_obj = load(linear_toml(n))   # parsed once, outside the timing

        def public() -> np.ndarray:
            sim = simulate(scene_obj)[0]
            verdict[:] = [sim.verdict.outcome]
            return np.asarray(sim.x)
        fast["zwidth.simulate"] = public
        notes["zwidth.simulate"] = "t, x, v, x_measured, force recorded; verdict and analytic check"
    else:
        log("zwidth.simulate / load_scene are not available in this build: row skipped")
    best = {k: math.inf for k in fast}
    out: Dict[str, np.ndarray] = {}
    log(f"linear: {', '.join(fast)}; {n} samples, best of {a.repeats}, interleaved")
    for _ in range(a.repeats):
        for name, fn in fast.items():
            t0 = time.perf_counter()
            out[name] = fn()
            best[name] = min(best[name], time.perf_counter() - t0)
    for name in fast:
        x = out[name]
        note = notes.get(name, "")
        if name == "zwidth.simulate":
            note += f" (verdict: {verdict[0]})"
        add(name, best[name], len(x), x[:n], note)

    log(f"linear: scipy.signal.dlsim, best of {a.slow_repeats}")
    t, res = best_of(lambda: signal.dlsim((A, Bu, C, D, T), u, x0=x0), a.slow_repeats)
    add("scipy.signal.dlsim", t, n, res[1][:, 0], "state space (x_k, v_k, x_k-1), input x_eq")

    if ct is not None:
        log(f"linear: python-control forced_response, best of {a.slow_repeats}")
        sys_ct = ct.ss(A, Bu, C, D, T)
        t, res = best_of(lambda: ct.forced_response(sys_ct, U=u, X0=x0), a.slow_repeats)
        add("python-control forced_response", t, n, np.asarray(res.outputs).reshape(-1), "same state space")

    log(f"linear: plain Python loop, best of {a.slow_repeats}")
    t, res = best_of(lambda: python_loop(n, M, B_PLANT, T, K_LIN, B_LIN, 1.0), a.slow_repeats)
    add("plain Python loop", t, n, res, "floats, the recurrence written out")

    ref = rows[0]
    x_ref = ref["x"]
    for r in rows:
        r["speedup"] = ref["rate"] / r["rate"] if r["rate"] == r["rate"] else math.nan
        if r["x"] is not None:
            k = min(len(r["x"]), len(x_ref))
            r["diff"] = float(np.max(np.abs(r["x"][:k] - x_ref[:k])))
        else:
            r["diff"] = math.nan
    dl = next(r for r in rows if r["method"] == "scipy.signal.dlsim")
    info = {"zoh_check": zoh_check(M, B_PLANT, T), "x_final": float(x_ref[-1]),
            "x_peak": float(np.max(x_ref)),
            "dlsim_ratio": ref["rate"] / dl["rate"],
            "x_only_ratio": next(r for r in rows if r["method"].endswith("(x only)"))["rate"] / dl["rate"],
            "rho": float(zw.Device(M, B_PLANT, T).spectral_radius(K_LIN, B_LIN)),
            "stable": bool(zw.Device(M, B_PLANT, T).is_stable(K_LIN, B_LIN))}
    return rows, info


def linear_table(rows: List[Dict[str, Any]]) -> str:
    lines = ["| method | samples | samples/s | time/sample | zwidth speed-up | max \\|x - x_zwidth\\| [m] | note |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["rate"] != r["rate"]:
            lines.append(f"| {r['method']} | - | - | - | - | - | {r['note']} |")
            continue
        speed = "ref" if r["note"] == "ref" else f"{r['speedup']:.3g}x"
        note = "" if r["note"] == "ref" else r["note"]
        lines.append(f"| {r['method']} | {r['samples']} | {si(r['rate'])} | {per_sample(1.0 / r['rate'])} "
                     f"| {speed} | {r['diff']:.2g} | {note} |")
    return "\n".join(lines)


# --------------------------------------------------------------------------- accuracy vs time

def base(**kw: Any) -> Dict[str, Any]:
    d: Dict[str, Any] = dict(m=M, b=B_PLANT, T=T, K=2000.0, B=5.0, x_init=0.0, v_init=0.0,
                             x_eq_before=0.0, x_eq_after=0.0, t_step=0.0, effects=0, substeps=1)
    d.update(kw)
    return d


def fallback_scenes(core: Any) -> Dict[str, Tuple[Dict[str, Any], float, str]]:
    """(scene dict, duration [s], what it shows) for each nonlinear scene."""
    fx = core.SIM_EFFECTS
    hand = dict(hand_mass=0.2, hand_stiffness=300.0, hand_damping=2.0, hand_t_grasp=0.2,
                hand_t_release=2.5, hand_from=0.0, hand_to=0.1, hand_speed=0.2)
    return {
        "friction": (base(effects=fx["friction"], x_eq_after=0.01, coulomb=2.0, stiction=3.0),
                     2.0, "10 mm step (20 N) against 2 N Coulomb, 3 N stiction"),
        "hand": (base(effects=fx["hand"], **hand),
                 4.0, "0.2 kg hand, 300 N/m arm, moves 0 -> 0.1 m at 0.2 m/s, lets go at 2.5 s"),
        "wall hit by hand": (base(effects=fx["hand"] | fx["wall"], K=0.0, B=0.0, wall_position=0.05,
                                  wall_stiffness=5000.0, wall_damping=5.0, wall_side=1, **hand),
                             4.0, "free space, wall 5000 N/m at 0.05 m, the hand pushes to 0.1 m"),
        "stick-slip with quantization": (
            base(effects=fx["hand"] | fx["friction"] | fx["quantization"], K=50.0, B=1.0,
                 coulomb=1.0, stiction=2.0, counts_per_unit=1000.0,
                 hand_mass=0.0, hand_stiffness=100.0, hand_damping=1.0, hand_t_grasp=0.0,
                 hand_t_release=math.inf, hand_from=0.0, hand_to=0.3, hand_speed=0.03),
            10.0, "soft arm (100 N/m) drags at 3 cm/s, 2 N stiction / 1 N Coulomb, 1 mm encoder"),
    }


# scenes/ files (written by the scene helper) for each nonlinear scene, first match wins
SCENE_FILES = {
    "friction": ("friction.toml",),
    "hand": ("hand.toml",),
    "wall hit by hand": ("wall-hand.toml", "wall-hit-by-hand.toml", "wall.toml"),
    "stick-slip with quantization": ("stick-slip.toml", "stick-slip-quantization.toml"),
}


def load_scenes(a: argparse.Namespace, zw: Any) -> List[Tuple[str, Dict[str, Any], int, str]]:
    core = zw._core
    out = []
    for name, (scene, duration, what) in fallback_scenes(core).items():
        source = "built in: " + what
        n = int(round(duration / scene["T"]))
        if not a.no_files and getattr(zw, "simulate", None) is not None:
            for fname in SCENE_FILES[name]:
                path = REPO / "scenes" / fname
                if path.is_file():
                    try:
                        sim = zw.simulate(str(path))[0]
                        scene, n = dict(sim.params), len(sim.x)
                        source = f"scenes/{fname}, case {sim.label!r}"
                    except Exception as exc:  # noqa: BLE001 - fall back to the built-in scene
                        log(f"{path}: {exc!r}; using the built-in scene")
                    break
        if a.quick:
            n = min(n, 3000)   # long enough for the stick-slip scene's first slip (1 s at T = 1 ms)
        out.append((name, scene, n, source))
    return out


def run_xv(core: Any, scene: Dict[str, Any], substeps: int, n: int) -> Tuple[np.ndarray, np.ndarray]:
    s = dict(scene)
    s["substeps"] = int(substeps)
    out = core.Simulator(s).run(n, ("x", "v"))
    return np.asarray(out["x"]), np.asarray(out["v"])


def time_run(core: Any, scene: Dict[str, Any], substeps: int, n: int, repeats: int,
             min_time: float) -> float:
    """Seconds per sample: whole runs (init included), repeated to last >= min_time, best of."""
    s = dict(scene)
    s["substeps"] = int(substeps)
    t0 = time.perf_counter()
    core.Simulator(s).run(n, ("x",))
    once = max(time.perf_counter() - t0, 1e-9)
    reps = max(1, int(math.ceil(min_time / once)))

    def go() -> None:
        for _ in range(reps):
            core.Simulator(s).run(n, ("x",))
    best, _ = best_of(go, repeats)
    return best / (reps * n)


def bench_accuracy(a: argparse.Namespace, zw: Any) -> List[Dict[str, Any]]:
    core = zw._core
    rows: List[Dict[str, Any]] = []
    ref_sub = min(100 * max(a.substeps), MAX_SUBSTEPS)
    for name, scene, n, source in load_scenes(a, zw):
        log(f"accuracy: {name} ({n} samples), reference at {ref_sub} substeps")
        x_ref, _ = run_xv(core, scene, ref_sub, n)
        x_half, _ = run_xv(core, scene, max(1, ref_sub // 2), n)
        friction = bool(int(scene.get("effects", 0)) & core.SIM_EFFECTS["friction"])
        t_ref = time_run(core, scene, ref_sub, n, 1, 0.0)
        span = float(np.ptp(x_ref))
        for sub in a.substeps:
            row: Dict[str, Any] = {"scene": name, "source": source, "samples": n, "substeps": sub,
                                   "h": scene["T"] / sub, "span": span, "sliding": None}
            try:
                x, v = run_xv(core, scene, sub, n)
            except ValueError as exc:   # too few substeps for RK4's stability (ZW_SIM_RK4_LIMIT)
                row["refused"] = str(exc).split("[")[-1].rstrip("]")
                rows.append(row)
                continue
            row.update(err=float(np.max(np.abs(x - x_ref))), finite=bool(np.all(np.isfinite(x))),
                       s_per_sample=time_run(core, scene, sub, n, a.repeats, a.min_time))
            if friction:
                row["sliding"] = float(np.mean(v != 0.0))
            rows.append(row)
        rows.append({"scene": name, "source": source, "samples": n, "substeps": ref_sub,
                     "h": scene["T"] / ref_sub, "err": float(np.max(np.abs(x_half - x_ref))),
                     "span": span, "s_per_sample": t_ref, "finite": bool(np.all(np.isfinite(x_ref))),
                     "sliding": None, "ref": True})
    return rows


def accuracy_table(rows: List[Dict[str, Any]]) -> str:
    lines = ["| scene | substeps | step h | max \\|x - x_ref\\| [m] | relative to the motion "
             "| time/sample | samples/s | sliding |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        sub = f"{r['substeps']} (ref check: vs {r['substeps'] // 2})" if r.get("ref") else str(r["substeps"])
        if "refused" in r:
            lines.append(f"| {r['scene']} | {sub} | {per_sample(r['h'])} | refused by zw_sim_init "
                         f"({r['refused']}: RK4 would be unstable at this step) | | | | |")
            continue
        rel = f"{r['err'] / r['span']:.2g}" if r["span"] > 0 else "-"
        err = f"{r['err']:.2g}" if r["finite"] else "not finite"
        sliding = "-" if r["sliding"] is None else f"{100 * r['sliding']:.0f} %"
        lines.append(f"| {r['scene']} | {sub} | {per_sample(r['h'])} | {err} | {rel} "
                     f"| {per_sample(r['s_per_sample'])} | {si(1.0 / r['s_per_sample'])} | {sliding} |")
    return "\n".join(lines)


FRICTION_SCENE = dict(m=0.1, b=2.0, T=1e-3, K=2000.0, B=1.0, x_init=0.0, v_init=0.0, x_eq_before=0.0,
                      x_eq_after=0.01, t_step=0.0, coulomb=3.0, stiction=5.0)


def bench_friction_order(zw: Any, quick: bool) -> List[Dict[str, Any]]:
    """Part 3: the error against the closed-form stick-slip reference per substeps."""
    sys.path.insert(0, str(REPO / "tests" / "py"))
    import sim_reference  # noqa: E402,WPS433

    n = 100
    log("friction order: closed-form reference (mpmath)")
    xs, _, stops = sim_reference.friction_trajectory(FRICTION_SCENE, n)
    x_ref = np.array([float(x) for x in xs])
    rows: List[Dict[str, Any]] = []
    for sub in ((1, 2, 4, 8) if quick else (1, 2, 4, 8, 16, 32, 64)):
        p = dict(FRICTION_SCENE, effects=zw._core.SIM_EFFECTS["friction"], substeps=sub)
        x = zw._core.Simulator(p).run(n, ["x"])["x"]
        err = float(np.max(np.abs(x - x_ref)))
        order = math.log2(rows[-1]["err"] / err) if rows and err > 0 else None
        rows.append({"substeps": sub, "err": err, "order": order, "stops": stops, "span": float(np.ptp(x_ref))})
    return rows


def friction_table(rows: List[Dict[str, Any]]) -> str:
    lines = ["| substeps | max \\|x - x_ref\\| [m] | relative to the motion | order log2(e(n/2)/e(n)) |",
             "|---|---|---|---|"]
    for r in rows:
        order = "-" if r["order"] is None else f"{r['order']:.2f}"
        lines.append(f"| {r['substeps']} | {r['err']:.2g} | {r['err'] / r['span']:.2g} | {order} |")
    return "\n".join(lines)


# --------------------------------------------------------------------------- main

def import_zwidth() -> Any:
    import zwidth  # noqa: WPS433
    if not hasattr(zwidth._core, "Simulator"):
        raise SystemExit("bench_sim: this zwidth has no _core.Simulator (rebuild the extension)")
    return zwidth


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--samples", type=float, default=1e6, help="samples of the linear scene (default 1e6)")
    p.add_argument("--quick", action="store_true", help="small sizes for a CI smoke run (seconds)")
    p.add_argument("--markdown", action="store_true", help="print only the README tables and targets")
    p.add_argument("--repeats", type=int, default=5, help="repeats of the fast methods (best of)")
    p.add_argument("--slow-repeats", type=int, default=2, help="repeats of the Python-loop methods")
    p.add_argument("--substeps", type=str, default=",".join(map(str, SUBSTEPS)),
                   help="substeps values for the accuracy table (comma separated)")
    p.add_argument("--min-time", type=float, default=0.05,
                   help="seconds each accuracy timing lasts at least (runs repeated)")
    p.add_argument("--no-control", action="store_true", help="skip python-control")
    p.add_argument("--no-files", action="store_true", help="ignore scenes/*.toml, use the built-in scenes")
    a = p.parse_args(argv)
    try:
        a.substeps = sorted({int(s) for s in a.substeps.split(",") if s.strip()})
    except ValueError:
        p.error("--substeps wants integers separated by commas")
    if a.quick:
        a.samples = min(a.samples, 20000)
        a.repeats = min(a.repeats, 3)
        a.slow_repeats = 1
        a.min_time = min(a.min_time, 0.005)
        a.substeps = [s for s in a.substeps if s <= 10] or a.substeps[:1]
    a.samples = int(a.samples)
    if a.samples < 10 or min(a.repeats, a.slow_repeats) < 1 or not a.substeps \
            or a.substeps[0] < 1 or 100 * a.substeps[-1] > MAX_SUBSTEPS or not a.min_time >= 0:
        p.error(f"need --samples >= 10, repeats >= 1, substeps in 1 .. {MAX_SUBSTEPS // 100}")

    t_start = time.perf_counter()
    zw = import_zwidth()
    ct: Any = None
    if not a.no_control:
        try:
            import control  # noqa: WPS433
            ct = control
        except ImportError:
            log("python-control is not installed: its row is skipped")

    lin_rows, info = bench_linear(a, zw, ct)
    acc_rows = bench_accuracy(a, zw)
    fric_rows = bench_friction_order(zw, a.quick)
    elapsed = time.perf_counter() - t_start

    met = info["dlsim_ratio"] >= 50.0
    worst_diff = max(r["diff"] for r in lin_rows if r["diff"] == r["diff"])
    target = (f"- {'MET    ' if met else 'NOT MET'} zwidth bare >= 50x scipy.signal.dlsim on {a.samples} "
              f"samples: {info['dlsim_ratio']:.3g}x (t and x recorded; x only: {info['x_only_ratio']:.3g}x); "
              f"every method's trajectory within {worst_diff:.2g} m of zwidth's")
    # The order while the error is above rounding (1e-13 of the motion).
    orders = [r["order"] for r in fric_rows if r["order"] is not None and r["err"] > 1e-13 * r["span"]]
    fric_met = bool(orders) and min(orders) >= 3.6
    target += (f"\n- {'MET    ' if fric_met else 'NOT MET'} friction (stops located inside the substep) "
               f"converges at RK4's order: observed {', '.join(f'{o:.2f}' for o in orders)} (>= 3.6) against "
               f"the closed-form reference, {fric_rows[0]['stops']} stops in {FRICTION_SCENE['T'] * 100:g} s")
    if not a.markdown:
        print("# zwidth scene simulation: samples per second and accuracy against time\n")
        print(f"- machine: {machine(zw, ct)}")
        print(f"- run time {elapsed:.1f} s; best of {a.repeats} (fast, interleaved) / {a.slow_repeats} "
              "(Python loops)")
        print(f"- linear scene: m = {M} kg, b = {B_PLANT} N s/m, T = {T} s, K = {K_LIN} N/m, B = {B_LIN} N s/m "
              f"(zwidth: {'stable' if info['stable'] else 'UNSTABLE'}, spectral radius {info['rho']:.4f}), "
              f"step 0 -> 1 m at t = 0; x peaks at {info['x_peak']:.4g} m, ends at {info['x_final']:.6g} m")
        print(f"- the literal ZOH step vs scipy.signal.cont2discrete: max |difference| {info['zoh_check']:.2g}\n")
    print("## Linear scene: samples per second\n")
    print(linear_table(lin_rows))
    print("\n## Nonlinear scenes: accuracy against time (RK4 substeps per sample)\n")
    print(accuracy_table(acc_rows))
    if not a.markdown:
        print("\nScenes:")
        seen = set()
        for r in acc_rows:
            if r["scene"] not in seen:
                seen.add(r["scene"])
                print(f"- {r['scene']}: {r['samples']} samples; {r['source']}")
        print(f"\nReference: {acc_rows[-1]['substeps'] if acc_rows else '-'} substeps (100x the finest step "
              "offered); time/sample: whole runs through _core.Simulator (x recorded), init included; "
              "refused: zw_sim_init's RK4 stability limit (ZW_SIM_RK4_LIMIT); sliding: share of samples with v != 0 (friction costs RK4 only while sliding)")
    print("\n## Friction: convergence order against the closed-form reference\n")
    print(friction_table(fric_rows))
    print("\n## Targets\n")
    print(target)
    return 0


if __name__ == "__main__":
    sys.exit(main())
