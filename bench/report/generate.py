#!/usr/bin/env python3

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""What accuracy costs in time: one report across every method, precision and target.

Runs everything in one go on the machine at hand and writes bench/REPORT.md (and prints
it): the C methods (double and float, timed and counted with callgrind), the Python peers,
the coefficient and extremes accuracy, the MCU view (tools/footprint.sh and an emulated
Cortex-M4F under QEMU) and the simulation benchmark.  Every figure comes from this run;
the only numbers typed in are the claims (CLAIMS below), which the run checks.

    .venv/bin/python bench/report/generate.py            # full run, writes bench/REPORT.md
    .venv/bin/python bench/report/generate.py --quick    # CI: seconds; fails on a broken claim

--quick uses small sizes, skips the timing-only parts (callgrind, footprint.sh, the
simulation benchmark, the 1e6-point timings), writes the report to the build directory
instead of bench/REPORT.md, and exits 1 if any measured error exceeds its claim.  The full
run exits 1 on a broken claim as well (and still writes the report, which says so).
Exit status 2: a build or a tool failed.

Needs: cmake and a C compiler (the harness), numpy and mpmath (the reference), the zwidth
package (its Python rows); optional, each row says when it was skipped: python-control,
valgrind (instructions per call), gcc-arm-none-eabi + libnewlib-arm-none-eabi and
qemu-system-arm (the MCU view), zwidth._core.Simulator (the simulation row).
"""
from __future__ import annotations

import argparse
import concurrent.futures
import math
import os
import platform
import re
import shutil
import subprocess
import sys
import time
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

try:
    import mpmath
    import numpy as np
    import zwidth  # noqa: F401  (every method of the report calls it)
except ImportError as exc:  # a usage error, said as one: not a traceback
    print(f"generate.py: {exc.name or exc} is not importable by {sys.executable}: the report needs "
          f"numpy, mpmath and the zwidth package (pip install . into the interpreter, e.g. "
          f"tools/test.sh's .venv: .venv/bin/python bench/report/generate.py --quick)", file=sys.stderr)
    sys.exit(2)

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "bench", "python"))

import dataset as ds  # noqa: E402
import mcu  # noqa: E402
import bench_check as bc  # noqa: E402  (the numpy / python-control peers, timing helpers)
from mpmath import mp, mpf  # noqa: E402

DOUBLE, FLOAT = ds.DOUBLE, ds.FLOAT
PAPER_DELTA = 2.197e-3 * 0.02 / 85.78e-7   # the paper's drive (short-circuited load)

# ------------------------------------------------------------------------------ claims
# What the report claims for each method, stated once.  --quick (and the full run) fail
# when a measurement breaks one.  Boundary errors are in ulps of the method's precision
# at the boundary (dataset.boundary_ulps); value errors in ulps of the value.
#   (row id, metric, "<=" or ">=", bound, why)
CLAIMS: List[Tuple[str, str, str, float, str]] = [
    # the product: guarded verdicts, values within a few ulps
    ("c.check.double", "false_stable", "<=", 0, "the guard never calls an unstable point stable"),
    ("cert.tightness", "max_ratio", "<=", 1.0, "a certificate's level is never above the true box limit"),
    ("cert.m4f", "verify_max_instructions", "<=", 8.4e6, "SEAL's verification within 50 ms at 168 MHz"),
    ("ident.coverage.plain", "m", ">=", 0.95, "the stated 95 % intervals of m cover the truth (plain plants)"),
    ("ident.coverage.plain", "b", ">=", 0.95, "the stated 95 % intervals of b cover the truth (plain plants)"),
    ("c.check.double", "worst_ulps", "<=", 32, "false unstable only within the rounding band"),
    ("c.check.float", "false_stable", "<=", 0, "the guard never calls an unstable point stable"),
    ("c.check.float", "worst_ulps", "<=", 32, "false unstable only within the rounding band"),
    ("py.zwidth.check", "false_stable", "<=", 0, "the same C core through the bindings"),
    ("py.zwidth.check", "worst_ulps", "<=", 32, "the same C core through the bindings"),
    ("mcu.check.float", "false_stable", "<=", 0, "the guard holds with newlib's libm on the target"),
    ("mcu.check.float", "worst_ulps", "<=", 32, "the guard holds with newlib's libm on the target"),
    ("c.jury.double", "false_stable", "<=", 0, "zw_radius_within is guarded like zw_check"),
    ("c.jury.float", "false_stable", "<=", 0, "zw_radius_within is guarded like zw_check"),
    ("c.jury.double", "worst_ulps", "<=", 2.0 ** 24, "its guard bounds the Jury margins, not the boundary: "
     "a wider band where the margins are flat"),
    ("c.jury.float", "worst_ulps", "<=", 2.0 ** 24, "its guard bounds the Jury margins, not the boundary: "
     "a wider band where the margins are flat"),
    ("c.k_max.double", "value_ulps", "<=", 8, "K_max(B) within a few ulps of the boundary"),
    ("c.k_max.float", "value_ulps", "<=", 8, "K_max(B) within a few ulps of the boundary"),
    ("py.zwidth.k_max", "value_ulps", "<=", 8, "K_max(B) within a few ulps of the boundary"),
    ("mcu.k_max.float", "value_ulps", "<=", 8, "K_max(B) on the target within a few ulps"),
    ("coef.series.double", "ulps", "<=", 4, "ZW_COEF_ULPS, the accuracy the guard budgets for"),
    ("coef.series.float", "ulps", "<=", 4, "ZW_COEF_ULPS, the accuracy the guard budgets for"),
    ("mcu.coef.float", "ulps", "<=", 4, "newlib's expf / expm1f keep ZW_COEF_ULPS"),
    ("ext.c.double", "ulps", "<=", 8, "alpha_mmax, alpha_p_max, beta_mmax within a few ulps"),
    ("ext.c.float", "ulps", "<=", 8, "alpha_mmax, alpha_p_max, beta_mmax within a few ulps"),
    ("mcu.ext.float", "ulps", "<=", 8, "extremes on the target within a few ulps"),
    # the peers: unguarded, so wrong both ways near the boundary; upper bounds on how much
    ("c.check_literal.double", "false_stable_frac", "<=", 0.05, "literal coefficients void the guard"),
    ("c.check_literal.double", "worst_ulps", "<=", 2.0 ** 40, "literal c2 cancels: ~1e-4 relative at delta = 1e-6"),
    ("c.check_literal.float", "false_stable_frac", "<=", 0.05, "literal coefficients void the guard"),
    ("c.check_literal.float", "worst_ulps", "<=", 2.0 ** 26, "literal coefficients in float: off by up to a few times the value"),
    ("coef.literal.double", "d12_rel", ">=", 0.10, "the literal formulas lose everything (d12 > 10 % wrong somewhere)"),
    ("coef.literal.float", "d12_rel", ">=", 0.10, "the literal formulas lose everything (d12 > 10 % wrong somewhere)"),
    ("c.jury_plain.double", "false_stable_frac", "<=", 0.10, "unguarded: only points within rounding reach can be misjudged"),
    ("c.jury_plain.double", "worst_ulps", "<=", 2.0 ** 30, "unguarded Jury margins, rounded coefficients"),
    ("c.jury_plain.float", "false_stable_frac", "<=", 0.10, "unguarded: only points within rounding reach can be misjudged"),
    ("c.jury_plain.float", "worst_ulps", "<=", 2.0 ** 20, "unguarded Jury margins, rounded coefficients"),
    ("c.radius.double", "false_stable_frac", "<=", 0.10, "unguarded: only points within rounding reach can be misjudged"),
    ("c.radius.double", "worst_ulps", "<=", 2.0 ** 30, "root finding: near double roots the error is sqrt(u)"),
    ("c.radius.float", "false_stable_frac", "<=", 0.10, "unguarded: only points within rounding reach can be misjudged"),
    ("c.radius.float", "worst_ulps", "<=", 2.0 ** 20, "root finding: near double roots the error is sqrt(u)"),
    ("py.numpy_closed", "false_stable_frac", "<=", 0.10, "unguarded, literal coefficients"),
    ("py.numpy_closed", "worst_ulps", "<=", 2.0 ** 54, "f's expanded numerator cancels near beta = -delta: "
     "off by up to the whole value"),
    ("py.eigvals", "false_stable_frac", "<=", 0.10, "unguarded, literal coefficients"),
    ("py.eigvals", "worst_ulps", "<=", 2.0 ** 40, "literal coefficients (~1e-4 relative at delta = 1e-6)"),
    ("py.roots", "false_stable_frac", "<=", 0.10, "unguarded, literal coefficients"),
    ("py.roots", "worst_ulps", "<=", 2.0 ** 40, "literal coefficients (~1e-4 relative at delta = 1e-6)"),
    ("py.control", "false_stable_frac", "<=", 0.10, "unguarded: c2d and poles in double"),
    ("py.control", "worst_ulps", "<=", 2.0 ** 20, "unguarded: c2d and poles in double"),
    ("py.sim", "false_stable_frac", "<=", 0.15, "a finite record cannot see a growth slower than its length"),
    ("py.mpmath", "false_stable", "<=", 0, "50 digits decide every point of the set"),
    ("py.mpmath", "false_unstable", "<=", 0, "50 digits decide every point of the set"),
    # the general loop (loop.h; bench/report/loop_section.py)
    ("loop.check", "false_stable", "<=", 0, "the general loop's guard never calls an unstable point stable"),
    ("loop.fast", "mismatch", "<=", 0, "zw_loop_is_stable gives zw_loop_check's verdict on every point"),
    # the measurement itself
    ("mcu.calibration", "ok", ">=", 1, "the instruction counter counts a known block exactly"),
    ("ref.self_check", "jury_disagree", "<=", 0, "reference roots at 50 digits agree with the Jury reference"),
]


def log(msg: str) -> None:
    print(f"[report] {msg}", file=sys.stderr, flush=True)


# ------------------------------------------------------------------------------ formatting

def fmt_time(seconds: Optional[float]) -> str:
    return "—" if seconds is None or not math.isfinite(seconds) else bc.per_point(seconds)


def fmt_ulps(x: Optional[float]) -> str:
    if x is None:
        return "—"
    if not math.isfinite(x):
        return "inf"
    return f"{x:.0f}" if x < 1e5 else f"{x:.2g}"


def fmt_int(x: Optional[float]) -> str:
    return "—" if x is None else f"{x:,.0f}"


def fmt_ratio(x: float) -> str:
    return f"{x:.3g}x"


def md_table(head: Sequence[str], rows: Sequence[Sequence[Any]], align: str = "") -> str:
    al = align or ("l" * len(head))
    sep = ["---:" if c == "r" else "---" for c in al]
    out = ["| " + " | ".join(head) + " |", "|" + "|".join(sep) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


# ------------------------------------------------------------------------------ C side

def build_harness(work: str) -> Tuple[str, str, str]:
    """Configure and build zwreport_d / zwreport_f (Release) in work/cmake."""
    bdir = os.path.join(work, "cmake")
    gen = ["-G", "Ninja"] if shutil.which("ninja") else []
    cfg = ["cmake", "-S", ROOT, "-B", bdir, *gen, "-DCMAKE_BUILD_TYPE=Release", "-DZW_BUILD_TESTS=OFF",
           "-DZW_BUILD_SHARED=OFF", "-DZW_BUILD_HOST=ON"]
    for cmd in (cfg, ["cmake", "--build", bdir, "--target", "zwreport_d", "zwreport_f"]):
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)} failed:\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    flags = "?"
    cache = os.path.join(bdir, "CMakeCache.txt")
    cc = "?"
    with open(cache, encoding="utf-8") as fh:
        for line in fh:
            if line.startswith("CMAKE_C_FLAGS_RELEASE:"):
                flags = line.split("=", 1)[1].strip()
            if line.startswith("CMAKE_C_COMPILER:"):
                cc = line.split("=", 1)[1].strip()
    ver = subprocess.run([cc, "--version"], capture_output=True, text=True).stdout.splitlines()
    return bdir, f"{ver[0] if ver else cc}; {flags} -ffp-contract=off", cc


def run(cmd: Sequence[str], timeout: float = 3600) -> str:
    p = subprocess.run(list(cmd), capture_output=True, text=True, timeout=timeout)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited {p.returncode}: {p.stderr[-1000:]}")
    return p.stdout


def harness_verdicts(exe: str, points: str) -> Dict[str, np.ndarray]:
    rows = [ln.split() for ln in run([exe, "verdicts", points]).splitlines() if ln and ln[0] != "#"]
    cols = list(zip(*rows))
    i = lambda k: np.array(cols[k], dtype=int)  # noqa: E731
    h = lambda k: np.array([float.fromhex(x) for x in cols[k]])  # noqa: E731
    return {"check_st": i(1), "check": i(2).astype(bool), "check_marg": i(3).astype(bool),
            "literal_st": i(4), "literal": i(5).astype(bool), "jury_st": i(6), "jury": i(7).astype(bool),
            "jury_plain_st": i(8), "jury_plain": i(9).astype(bool), "radius_st": i(10), "rho": h(11),
            "k_max_st": i(12), "k_max": h(13)}


def harness_coeffs(exe: str, deltas: str) -> Dict[str, np.ndarray]:
    rows = [ln.split() for ln in run([exe, "coeffs", deltas]).splitlines() if ln and ln[0] != "#"]
    cols = list(zip(*rows))
    h = lambda k: np.array([float.fromhex(x) for x in cols[k]])  # noqa: E731
    i = lambda k: np.array(cols[k], dtype=int)  # noqa: E731
    return {"delta": h(0), "st": i(1), "e": h(2), "c1": h(3), "c2": h(4), "d12": h(5), "lit_st": i(6),
            "lit_c1": h(7), "lit_c2": h(8), "lit_d12": h(9), "ext_st": i(10), "alpha_mmax": h(11),
            "beta_at": h(12), "alpha_p_max": h(13), "beta_mmax": h(14)}


def harness_times(exe: str, points: str, repeats: int) -> Dict[str, float]:
    out = {}
    for ln in run([exe, "time", points, str(repeats)]).splitlines():
        name, ns = ln.split()
        out[name] = float(ns) * 1e-9
    return out


def callgrind_counts(exe: str, points: str, methods: Sequence[str], calls: int) -> Dict[str, float]:
    """Instructions per call: (Ir(calls) - Ir(0)) / calls, Ir from callgrind's summary."""
    def ir(method: str, n: int) -> int:
        p = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", exe, "count",
                            method, str(n), points], capture_output=True, text=True)
        m = re.search(r"Collected\s*:\s*(\d+)", p.stderr)
        if p.returncode != 0 or not m:
            raise RuntimeError(f"callgrind {method} {n} failed: {p.stderr[-600:]}")
        return int(m.group(1))
    jobs = [(methods[0], 0)] + [(m, calls) for m in methods]
    with concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        res = list(pool.map(lambda j: ir(*j), jobs))
    base = res[0]
    return {m: (r - base) / calls for m, r in zip(methods, res[1:])}


# ------------------------------------------------------------------------------ Python peers

def mpmath_roots_stable(d: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """What one writes with mpmath: 50 digits, the paper's formulas, polyroots."""
    out = np.zeros(len(d), dtype=bool)
    with mp.workdps(50):
        for i, (x, y, z) in enumerate(zip(d.tolist(), a.tolist(), b.tolist())):
            D, A, B = mpf(x), mpf(y), mpf(z)
            e = mp.exp(-D)
            c1 = 2 * (D - 1 + e) / D ** 2
            c2 = 2 * (1 - e - D * e) / D ** 2
            p = [2, c1 * (A + B) - 2 * (1 + e), c2 * A + (c2 - c1) * B + 2 * e, -c2 * B]
            try:
                out[i] = max(abs(r) for r in mp.polyroots(p, maxsteps=200, extraprec=50)) < 1
            except mpmath.libmp.NoConvergence:
                out[i] = False
    return out


class SimPeer:
    """A step response over SIM_SAMPLES samples through zwidth._core.Simulator (the C
    simulator of the simulation issue), judged by zwidth._core.sim_judge: stable when the
    last window's peak-to-peak amplitude is below SIM_TOL; "undecided" (still decaying, or
    not yet growing) counts as not stable, as a tuning script that must be sure would."""
    SAMPLES, WINDOW, WINDOWS, TOL = 20000, 2000, 4, 1e-9

    def __init__(self) -> None:
        from zwidth import _core  # noqa: WPS433
        self.Simulator = _core.Simulator
        self.judge = _core.sim_judge
        self.undecided = 0

    def stable(self, d: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        out = np.zeros(len(d), dtype=bool)
        for i, (x, y, z) in enumerate(zip(d.tolist(), a.tolist(), b.tolist())):
            sim = self.Simulator({"m": 1.0, "b": x, "T": 1.0, "K": y, "B": z, "x_init": 0.0, "v_init": 0.0,
                                  "x_eq_before": 0.0, "x_eq_after": 1.0, "t_step": 0.0})
            pos = sim.run(self.SAMPLES, ["x"])["x"]
            v = self.judge(pos, self.WINDOW, self.WINDOWS, self.TOL)
            out[i] = v["outcome"] == "stable"
            self.undecided += v["outcome"] == "undecided"
        return out


def literal_extremes(delta: np.ndarray, dtype: Any) -> Dict[str, np.ndarray]:
    """The paper's closed forms (19)-(32) with the literal coefficients, in numpy."""
    d = delta.astype(dtype)
    one, two = dtype(1), dtype(2)
    with np.errstate(all="ignore"):
        e = np.exp(-d)
        c1 = two * (d - one + e) / (d * d)
        c2 = two * (one - e - d * e) / (d * d)
        d12 = c1 - c2
        a1 = two * (c1 + c2 - np.sqrt(c2 * (e * c1 + c2))) ** 2 / (c1 ** 2 * c2)
        a2 = dtype(8) * (c1 - (two + e) * c2) / d12 ** 2
        amm = np.where(d > dtype(3.659361627421783507), a2, a1)
        ap = np.minimum(two * (one - e) / c2, dtype(4) * (one + e) / d12)
        bm = np.minimum(two / c2, two * (one + e) / d12)
    return {"alpha_mmax": amm, "alpha_p_max": ap, "beta_mmax": bm}


def grid_search_kmax(delta: float, n: int = 64) -> float:
    """alpha_mmax without zwidth: eigenvalues on an n x n grid of (alpha, beta) around the
    region (the box a user would guess: alpha in (0, 4 delta + 8), beta in (-delta, delta + 3)),
    the largest stable alpha found."""
    al = np.linspace(0, 4 * delta + 8, n + 1)[1:]
    be = np.linspace(-delta, delta + 3, n + 2)[1:-1]
    A, B = np.meshgrid(al, be)
    st = bc.eigvals_stable(delta, A.ravel(), B.ravel())
    return float(A.ravel()[st].max()) if st.any() else 0.0


# ------------------------------------------------------------------------------ the run

class Report:
    def __init__(self, args: argparse.Namespace) -> None:
        self.a = args
        self.work = os.path.abspath(args.build_dir)
        os.makedirs(self.work, exist_ok=True)
        self.res: Dict[str, Dict[str, Any]] = {}   # row id -> metrics
        self.notes: List[str] = []
        self.skipped: List[str] = []
        self.times: Dict[str, float] = {}          # phase -> seconds
        self.sim_section = ""
        self.ident_section = ""

    def phase(self, name: str, t0: float) -> None:
        self.times[name] = time.perf_counter() - t0
        log(f"{name}: {self.times[name]:.1f} s")

    # ---- section 1 ------------------------------------------------------------------
    def points(self) -> None:
        t0 = time.perf_counter()
        a = self.a
        self.pts = ds.make_points(a.points)
        self.ptsf = ds.as_float(self.pts)
        self.points_file = os.path.join(self.work, "points.txt")
        ds.write_points(self.points_file, self.pts)
        self.phase("point set", t0)
        t0 = time.perf_counter()
        p, pf = self.pts, self.ptsf
        self.ref_d = ds.reference(p["delta"], p["alpha"], p["beta"], self.work)
        moved = (pf["alpha"] != p["alpha"]) | (pf["beta"] != p["beta"]) | (pf["delta"] != p["delta"])
        self.ref_f = {k: (v.copy() if isinstance(v, np.ndarray) and v.shape == moved.shape else v)
                      for k, v in self.ref_d.items()}
        idx = np.nonzero(moved)[0]
        if len(idx):
            sub = ds.reference(pf["delta"][idx], pf["alpha"][idx], pf["beta"][idx], self.work)
            for k in ("stable", "rho", "how"):
                self.ref_f[k][idx] = sub[k]
            self.ref_f["jury_disagree"] = int(self.ref_d["jury_disagree"]) + int(sub["jury_disagree"])
        self.kref_d = ds.reference_kmax(p["delta"], p["beta"])
        self.kref_f = list(self.kref_d)
        sub_k = ds.reference_kmax(pf["delta"][idx], pf["beta"][idx])
        for j, i in enumerate(idx.tolist()):
            self.kref_f[i] = sub_k[j]
        self.n_moved = len(idx)
        self.res["ref.self_check"] = {"jury_disagree": int(self.ref_d["jury_disagree"]) +
                                      (int(sub["jury_disagree"]) if len(idx) else 0)}
        self.phase("reference (mpmath roots at 50 digits)", t0)

    def c_accuracy(self) -> None:
        t0 = time.perf_counter()
        self.bdir, self.cflags, _ = build_harness(self.work)
        self.exe = {"double": os.path.join(self.bdir, "zwreport_d"), "float": os.path.join(self.bdir, "zwreport_f")}
        for prec, fmt in (("double", DOUBLE), ("float", FLOAT)):
            v = harness_verdicts(self.exe[prec], self.points_file)
            p = self.pts if prec == "double" else self.ptsf
            truth = (self.ref_d if prec == "double" else self.ref_f)["stable"]
            args = (truth, p["delta"], p["alpha"], p["beta"], fmt)
            self.res[f"c.check.{prec}"] = ds.score(v["check"], *args, refused=v["check_st"] != 0)
            self.res[f"c.check.{prec}"]["marginal_of_fu"] = int((v["check_marg"] & truth & ~v["check"]).sum())
            self.res[f"c.check_literal.{prec}"] = ds.score(v["literal"], *args, refused=v["literal_st"] != 0)
            self.res[f"c.jury.{prec}"] = ds.score(v["jury"], *args, refused=v["jury_st"] != 0)
            self.res[f"c.jury_plain.{prec}"] = ds.score(v["jury_plain"], *args, refused=v["jury_plain_st"] != 0)
            self.res[f"c.radius.{prec}"] = ds.score(v["rho"] < 1, *args, refused=v["radius_st"] != 0)
            kref = self.kref_d if prec == "double" else self.kref_f
            ok = v["k_max_st"] == 0
            ul = ds.kmax_ulps(p["delta"][ok], v["k_max"][ok], p["beta"][ok], [kref[i] for i in np.nonzero(ok)[0]], fmt)
            self.res[f"c.k_max.{prec}"] = {"value_ulps": float(ul.max()) if len(ul) else 0.0,
                                          "refused": int((~ok).sum()), "n": len(ok)}
        self.phase("C verdicts and scores", t0)

    def c_timing(self) -> None:
        t0 = time.perf_counter()
        a = self.a
        self.ctime = {prec: harness_times(self.exe[prec], self.points_file, a.c_repeats) for prec in self.exe}
        self.phase("C timing", t0)
        self.cir: Dict[str, Dict[str, float]] = {}
        if a.quick or a.no_callgrind:
            self.skipped.append("instructions per call (callgrind): skipped in this run (--quick / --no-callgrind)")
            return
        if not shutil.which("valgrind"):
            self.skipped.append("instructions per call: valgrind is not installed (apt-get install valgrind)")
            return
        t0 = time.perf_counter()
        methods = run([self.exe["double"], "methods"]).split()
        for prec in self.exe:
            self.cir[prec] = callgrind_counts(self.exe[prec], self.points_file, methods, a.callgrind_calls)
        self.phase("callgrind", t0)

    def py_methods(self) -> None:
        """Accuracy on the set (double inputs) and time per point on 1e6-point arrays."""
        t0 = time.perf_counter()
        a = self.a
        import zwidth  # noqa: WPS433
        self.zw = zwidth
        try:
            import control  # noqa: WPS433
            self.ct: Any = control
        except ImportError:
            self.ct = None
            self.skipped.append("python-control: not installed (its row is skipped)")
        try:
            self.sim: Optional[SimPeer] = SimPeer()
        except Exception as exc:  # noqa: BLE001 - any failure to set it up means: skip
            self.sim = None
            self.skipped.append(f"simulation row: zwidth._core.Simulator is not available ({type(exc).__name__}: "
                                f"{exc}); it comes with the simulation issue")
        p, truth = self.pts, self.ref_d["stable"]
        d, al, be = p["delta"], p["alpha"], p["beta"]
        n = len(d)

        def subset(k: int) -> np.ndarray:
            return np.unique(np.linspace(0, n - 1, min(k, n)).astype(int))

        def sc(rid: str, pred: np.ndarray, idx: Optional[np.ndarray] = None) -> None:
            ix = np.arange(n) if idx is None else idx
            self.res[rid] = ds.score(pred, truth[ix], d[ix], al[ix], be[ix], DOUBLE)

        sc("py.zwidth.check", np.asarray(zwidth.check(d, al, be)))
        sc("py.numpy_closed", np.asarray(bc.closed_form_stable(d, al, be)))
        sc("py.eigvals", np.asarray(bc.eigvals_stable(d, al, be)))
        ir = subset(a.roots_subset)
        sc("py.roots", bc.roots_stable(d[ir], al[ir], be[ir]), ir)
        self.sub = {"py.roots": len(ir)}
        if self.ct is not None:
            ic = subset(a.control_subset)
            ones = np.ones(len(ic))
            sc("py.control", bc.control_stable_per_plant(self.ct, ones, d[ic], ones, al[ic], be[ic]), ic)
            self.sub["py.control"] = len(ic)
        if self.sim is not None:
            try:
                isim = subset(a.sim_subset)
                sc("py.sim", self.sim.stable(d[isim], al[isim], be[isim]), isim)
                self.res["py.sim"]["undecided"] = self.sim.undecided
                self.sub["py.sim"] = len(isim)
            except Exception as exc:  # noqa: BLE001
                self.skipped.append(f"simulation row: the Simulator failed ({type(exc).__name__}: {exc})")
                self.sim = None
        im = subset(a.mpmath_subset)
        sc("py.mpmath", mpmath_roots_stable(d[im], al[im], be[im]), im)
        self.sub["py.mpmath"] = len(im)
        self.phase("Python methods: accuracy", t0)

        # Timing: (one) one plant, the paper's drive, box-sampled gains; (many) the set tiled,
        # every point with its plant's delta.
        t0 = time.perf_counter()
        nt = a.time_points
        rng = np.random.default_rng(7)
        ex = zwidth.extremes(PAPER_DELTA)
        one_a = rng.uniform(0.0, 1.3 * float(ex.alpha_mmax), nt)
        one_b = -PAPER_DELTA + rng.uniform(0.0, 1.0, nt) * (float(ex.beta_mmax) + PAPER_DELTA)
        # shuffled, so that no two neighbours share a plant: the bindings cache the last
        # plant's coefficients, and this scenario is the one where that cache never hits
        rep = rng.permutation(np.resize(np.arange(n), nt))
        many = (d[rep], al[rep], be[rep])
        T: Dict[str, Dict[str, Tuple[float, int]]] = {"one": {}, "many": {}}

        def tv(key: str, scen: str, fn: Callable[[], Any], k: int, repeats: int) -> None:
            (wall, _), _ = bc.best_of(fn, repeats)
            T[scen][key] = (wall / k, k)

        D1 = PAPER_DELTA
        tv("py.zwidth.check", "one", lambda: zwidth.check(D1, one_a, one_b), nt, a.repeats)
        tv("py.zwidth.check", "many", lambda: zwidth.check(*many), nt, a.repeats)
        tv("py.numpy_closed", "one", lambda: bc.closed_form_stable(D1, one_a, one_b), nt, a.repeats)
        tv("py.numpy_closed", "many", lambda: bc.closed_form_stable(*many), nt, a.repeats)
        tv("py.eigvals", "one", lambda: bc.eigvals_stable(D1, one_a, one_b), nt, a.eig_repeats)
        tv("py.eigvals", "many", lambda: bc.eigvals_stable(*many), nt, a.eig_repeats)
        k = min(a.roots_subset, nt)
        tv("py.roots", "one", lambda: bc.roots_stable(D1, one_a[:k], one_b[:k]), k, a.slow_repeats)
        tv("py.roots", "many", lambda: bc.roots_stable(many[0][:k], many[1][:k], many[2][:k]), k, a.slow_repeats)
        if self.ct is not None:
            k = min(a.control_subset, nt)
            ones = np.ones(k)
            tv("py.control", "one", lambda: bc.control_stable_one_plant(self.ct, 1.0, D1, 1.0, one_a[:k], one_b[:k]),
               k, a.slow_repeats)
            tv("py.control", "many", lambda: bc.control_stable_per_plant(self.ct, ones, many[0][:k], ones,
                                                                         many[1][:k], many[2][:k]), k, a.slow_repeats)
        sim = self.sim
        if sim is not None:
            k = min(a.sim_subset, nt)
            tv("py.sim", "one", lambda: sim.stable(np.full(k, D1), one_a[:k], one_b[:k]), k, 1)
            tv("py.sim", "many", lambda: sim.stable(many[0][:k], many[1][:k], many[2][:k]), k, 1)
        k = min(a.mpmath_subset, nt)
        tv("py.mpmath", "one", lambda: mpmath_roots_stable(np.full(k, D1), one_a[:k], one_b[:k]), k, 1)
        tv("py.mpmath", "many", lambda: mpmath_roots_stable(many[0][:k], many[1][:k], many[2][:k]), k, 1)
        # k_max in Python: zwidth.alpha_max and the numpy closed form min{f, L}
        tv("py.zwidth.k_max", "many", lambda: zwidth.alpha_max(many[0], many[2]), nt, a.repeats)
        tv("py.numpy_kmax", "many", lambda: bc.closed_form_alpha_max(many[0], many[2]), nt, a.repeats)
        self.ptime = T
        self.phase("Python methods: timing", t0)
        # k_max accuracy of the Python rows
        kz = np.asarray(zwidth.alpha_max(d, be))
        kn = np.asarray(bc.closed_form_alpha_max(d, be))
        self.res["py.zwidth.k_max"] = {"value_ulps": float(ds.kmax_ulps(d, kz, be, self.kref_d, DOUBLE).max())}
        self.res["py.numpy_kmax"] = {"value_ulps": float(ds.kmax_ulps(d, kn, be, self.kref_d, DOUBLE).max())}

    # ---- section 2 ------------------------------------------------------------------
    BANDS = [("0, subnormal", 0.0, 2.3e-308), ("to 1e-8", 2.3e-308, 1e-8), ("1e-8 .. 1e-2", 1e-8, 1e-2),
             ("1e-2 .. 2", 1e-2, 2.0), ("2 .. 1e3", 2.0, 1e3), ("1e3 .. max", 1e3, math.inf)]

    def coefficients(self) -> None:
        t0 = time.perf_counter()
        a = self.a
        self.coef: Dict[str, Any] = {}
        for prec, fmt in (("double", DOUBLE), ("float", FLOAT)):
            deltas = ds.coefficient_deltas(fmt, a.coef_deltas)
            path = os.path.join(self.work, f"deltas-{prec}.txt")
            ds.write_deltas(path, deltas)
            c = harness_coeffs(self.exe[prec], path)
            r = ds.reference_coeffs(deltas)
            lit = literal_extremes(deltas, np.float64 if prec == "double" else np.float32)
            cols: Dict[str, np.ndarray] = {}
            for fld in ("e", "c1", "c2", "d12"):
                cols[f"series.{fld}"] = ds.value_ulps(c[fld], r[fld], fmt)
                if fld != "e":
                    cols[f"literal.{fld}"] = ds.value_ulps(c[f"lit_{fld}"], r[fld], fmt)
                    cols[f"literal_rel.{fld}"] = ds.relative_error(c[f"lit_{fld}"], r[fld])
            ok = c["ext_st"] == 0   # refused (ZW_ERR_RANGE: alpha_mmax ~ 4 delta overflows): not scored
            for fld in ("alpha_mmax", "alpha_p_max", "beta_mmax"):
                cols[f"ext.{fld}"] = np.where(ok, ds.value_ulps(np.where(ok, c[fld], 0.0), r[fld], fmt), 0.0)
                cols[f"extlit.{fld}"] = ds.value_ulps(lit[fld].astype(float), r[fld], fmt)
                cols[f"extlit_rel.{fld}"] = ds.relative_error(lit[fld].astype(float), r[fld])
            self.coef[prec] = {"deltas": deltas, "cols": cols, "refc": r, "ext_refused": deltas[~ok]}
            self.res[f"coef.series.{prec}"] = {"ulps": max(float(cols[f"series.{f}"].max()) for f in ("e", "c1", "c2", "d12"))}
            self.res[f"coef.literal.{prec}"] = {"d12_rel": float(np.nanmax(cols["literal_rel.d12"]))}
            self.res[f"ext.c.{prec}"] = {"ulps": max(float(cols[f"ext.{f}"].max())
                                                     for f in ("alpha_mmax", "alpha_p_max", "beta_mmax"))}
        # timing of the Python extremes (per delta) and a grid search by eigenvalues
        zw = self.zw
        nt = a.time_points
        # distinct deltas (log-uniform over the set's range), so every element is a new plant
        dl = 10 ** np.random.default_rng(11).uniform(-6, 4, nt)
        (w, _), _ = bc.best_of(lambda: zw.extremes(dl), a.repeats)
        self.ext_time = {"py.zwidth.extremes": w / nt}
        (w, _), _ = bc.best_of(lambda: literal_extremes(dl, np.float64), a.repeats)
        self.ext_time["py.numpy_literal_extremes"] = w / nt
        gd = np.unique(self.pts["delta"])[:: max(1, len(np.unique(self.pts["delta"])) // a.grid_plants)][: a.grid_plants]
        t1 = time.perf_counter()
        found = [grid_search_kmax(x) for x in gd.tolist()]
        self.ext_time["py.grid_search"] = (time.perf_counter() - t1) / len(gd)
        exact = [ds.ref.extremes(x)["alpha_mmax"] for x in gd.tolist()]
        rel = ds.relative_error(found, exact)
        self.grid = {"plants": len(gd), "worst_rel": float(rel.max()), "median_rel": float(np.median(rel))}
        self.phase("coefficients and extremes", t0)

    # ---- section 3 ------------------------------------------------------------------
    def mcu_view(self) -> None:
        t0 = time.perf_counter()
        a = self.a
        self.fp: Optional[Dict[str, Any]] = None
        self.mcu: Optional[Dict[str, Any]] = None
        if a.quick:
            self.skipped.append("flash and stack (tools/footprint.sh): skipped in --quick (tools/test.sh runs it)")
        else:
            try:
                self.fp = mcu.footprint()
            except Exception as exc:  # noqa: BLE001
                self.skipped.append(f"flash and stack: tools/footprint.sh failed ({exc})")
        miss = mcu.missing_tools()
        if miss or a.no_mcu:
            why = "--no-mcu" if a.no_mcu else f"{', '.join(miss)} not installed (apt-get install qemu-system-arm gcc-arm-none-eabi libnewlib-arm-none-eabi)"
            self.skipped.append(f"emulated Cortex-M4F (instructions, float error on the target): {why}")
            return
        work = os.path.join(self.work, "mcu")
        os.makedirs(work, exist_ok=True)
        k = min(a.mcu_points, len(self.pts["delta"]))
        idx = np.unique(np.linspace(0, len(self.pts["delta"]) - 1, k).astype(int))
        P = np.stack([self.ptsf["delta"][idx], self.ptsf["alpha"][idx], self.ptsf["beta"][idx]], axis=1)
        deltas = self.coef["float"]["deltas"]
        mcu.write_data(os.path.join(work, "mcu_data.c"), P, deltas.tolist(), a.mcu_count)
        elf_a, flags = mcu.build(work, "ACCURACY")
        acc = mcu.run_accuracy(elf_a)
        elf_c, _ = mcu.build(work, "COUNT")
        cnt = mcu.run_count(elf_c, work)
        pts = acc["points"]
        st = np.array([x[0] for x in pts])
        stable = np.array([x[1] for x in pts], dtype=bool)
        kst = np.array([x[3] for x in pts])
        kv = np.array([x[4] for x in pts])
        truth = self.ref_f["stable"][idx]
        pf = self.ptsf
        self.res["mcu.check.float"] = ds.score(stable, truth, pf["delta"][idx], pf["alpha"][idx], pf["beta"][idx],
                                               FLOAT, refused=st != 0)
        okk = kst == 0
        ik = idx[okk]
        self.res["mcu.k_max.float"] = {"value_ulps": float(ds.kmax_ulps(pf["delta"][ik], kv[okk], pf["beta"][ik], [self.kref_f[i] for i in ik.tolist()], FLOAT).max()),
                                       "refused": int((~okk).sum())}
        r = self.coef["float"]["refc"]
        D = acc["deltas"]
        cu = max(float(ds.value_ulps([x[j + 1] for x in D], r[f], FLOAT).max()) for j, f in enumerate(("e", "c1", "c2", "d12")))
        okx = [i for i, x in enumerate(D) if x[5] == 0]   # extremes refused (ZW_ERR_RANGE): not scored
        eu = max(float(ds.value_ulps([D[i][j] for i in okx], [r[f][i] for i in okx], FLOAT).max())
                 for j, f in ((6, "alpha_mmax"), (8, "alpha_p_max"), (9, "beta_mmax")))
        self.res["mcu.coef.float"] = {"ulps": cu}
        self.res["mcu.ext.float"] = {"ulps": eu}
        self.res["mcu.calibration"] = {"ok": 1 if cnt["calibration_ok"] else 0}
        qv = subprocess.run([mcu.QEMU, "--version"], capture_output=True, text=True).stdout.splitlines()
        self.mcu = {"points": len(idx), "deltas": len(deltas), "counts": cnt, "flags": flags,
                    "qemu": qv[0] if qv else "?"}
        self.phase("MCU view", t0)

    # ---- section 4 ------------------------------------------------------------------
    def simulation(self) -> str:
        script = os.path.join(ROOT, "bench", "sim", "bench_sim.py")
        if not os.path.exists(script):
            return ("_Pending: bench/sim/bench_sim.py (simulation issue) does not exist yet; this "
                    "section will include its output (samples per second by effect, error against step "
                    "size) once it does._")
        if self.a.quick:
            return "_Skipped in --quick: the simulation benchmark is timing only (run the full report)._"
        t0 = time.perf_counter()
        p = subprocess.run([sys.executable, script], capture_output=True, text=True, cwd=ROOT)
        self.phase("simulation benchmark", t0)
        if p.returncode != 0:
            last = (p.stderr.strip().splitlines() or ["no message"])[-1]
            self.skipped.append(f"simulation benchmark: bench/sim/bench_sim.py exited {p.returncode} ({last})")
            return f"_Not run: bench/sim/bench_sim.py exited {p.returncode} ({last})._"
        # its headings become sub-headings of this section
        body = re.sub(r"^(#+) ", lambda m: "#" * (len(m.group(1)) + 2) + " ", p.stdout.strip(), flags=re.M)
        return f"Output of `bench/sim/bench_sim.py`, run by this report:\n\n{body}"

    # ---- claims -----------------------------------------------------------------------
    def general_loop(self) -> str:
        """The general loop's section (loop_section.py); skipped without the shared library."""
        import loop_section as ls
        t0 = time.perf_counter()
        try:
            rows = ls.measure(self.a.quick, not (self.a.quick or self.a.no_callgrind) and bool(shutil.which("valgrind")))
        except (OSError, subprocess.CalledProcessError) as exc:
            self.skipped.append(f"general loop: skipped ({exc}; set ZW_LIB_DIR to a build with the shared libraries)")
            return "_Skipped in this run: the shared library was not found (ZW_LIB_DIR)._"
        self.res.update(ls.results(rows))
        self.phase("general loop", t0)
        m4f: Dict[int, Dict[str, float]] = {}
        if not self.a.no_mcu:
            t0 = time.perf_counter()
            try:
                m4f = ls.mcu_counts(self.a.quick)
            except (OSError, RuntimeError, subprocess.CalledProcessError) as exc:
                self.skipped.append(f"general loop on the Cortex-M4F: skipped ({exc})")
            self.phase("general loop on the Cortex-M4F (QEMU)", t0)
        return ls.section(rows, md_table, fmt_int, m4f)

    def box_certificates(self) -> str:
        """Ranged certification (cert_section.py): host search, size, verify, tightness."""
        import cert_section as cs
        t0 = time.perf_counter()
        rows = cs.measure(self.a.quick)
        self.res.update(cs.results(rows))
        self.phase("box certificates", t0)
        mcu_text = ""
        if not self.a.no_mcu:
            t0 = time.perf_counter()
            try:
                mcu_text, counts = cs.mcu_tables()
                self.res["cert.m4f"] = counts
            except (OSError, RuntimeError, subprocess.CalledProcessError, subprocess.TimeoutExpired) as exc:
                self.skipped.append(f"box certificates on the Cortex-M4F: skipped ({exc})")
            self.phase("box certificates on the Cortex-M4F (QEMU)", t0)
        return cs.section(rows, md_table, mcu_text)

    def identification(self) -> str:
        """Identification (ident_section.py): the committed 1,000-trial validation's summary."""
        import ident_section as ids
        s = ids.load()
        self.res.update(ids.results(s))
        return ids.section(s, md_table)

    def check_claims(self) -> List[Tuple[str, str, str, float, str, Optional[float], Optional[bool]]]:
        out = []
        for rid, metric, op, bound, why in CLAIMS:
            val = self.res.get(rid, {}).get(metric)
            ok = None if val is None else (val <= bound if op == "<=" else val >= bound)
            out.append((rid, metric, op, bound, why, val, ok))
        return out


# ------------------------------------------------------------------------------ writing

ROW_NAMES = {
    "check": "closed form, guarded (`zw_check`)",
    "check_literal": "closed form on literal coefficients (harness)",
    "jury": "Jury on p(z), guarded (`zw_radius_within`, r = 1)",
    "jury_plain": "Jury conditions (9), unguarded (harness)",
    "radius": "spectral radius < 1 (`zw_spectral_radius`)",
}
PY_NAMES = {
    "py.zwidth.check": "zwidth.check (Python, the C core)",
    "py.numpy_closed": "numpy closed form (10), literal coefficients",
    "py.eigvals": "numpy eigvals, batched (N, 3, 3)",
    "py.roots": "numpy.roots per point",
    "py.control": "python-control per point (c2d, feedback, poles)",
    "py.sim": "simulated step response (zwidth._core.Simulator)",
    "py.mpmath": "mpmath polyroots, 50 digits, per point",
}


def write_report(R: Report, claims: List[Any], elapsed: float) -> str:
    a = R.a
    info = bc.machine()
    res = R.res
    L: List[str] = []
    w = L.append
    w("# What accuracy costs in time")
    w("")
    w(f"Generated by `bench/report/generate.py`{' --quick' if a.quick else ''} in {elapsed:.0f} s; do not edit by hand. "
      "Every figure below was measured in that one run; the claims (last section) are the only "
      "numbers typed in, and the run checks them.")
    w("")
    w(f"- machine: {info['cpu']}, {info['cpu_count']} CPUs; {info['platform']}")
    w(f"- C: {R.cflags}; Python {info['python']}, numpy {info['numpy']}, "
      f"python-control {getattr(R.ct, '__version__', 'absent')}, mpmath {__import__('mpmath').__version__}")
    n = len(R.pts["delta"])
    w(f"- point set: {n:,} points over {len(np.unique(R.pts['delta']))} plants (seed {ds.SEED}), "
      f"{int(R.ref_d['stable'].sum()):,} stable; {int((R.pts['kind'] != 'box').sum()):,} crowded at a boundary "
      f"(half at float, half at double resolution); {R.n_moved:,} points move when rounded to float and are "
      "judged at their float values for the float rows (bench/report/dataset.py)")
    w(f"- reference: roots of p(z) at 50 digits (mpmath.polyroots) at the exact inputs; "
      f"{int((R.ref_d['how'] == 2).sum())} ties decided by the Jury test at escalating precision; cross-check "
      f"against the tests' Jury reference: {res['ref.self_check']['jury_disagree']} disagreements")
    w("")

    # ---- summary
    w("## Which to pick")
    w("")
    for line in summary(R):
        w(f"- {line}")
    w("")

    # ---- section 1
    w("## 1. Deciding stability: accuracy against time")
    w("")
    w("False stable: unstable in the reference, called stable (the dangerous error). False "
      "unstable: stable, called unstable. Worst boundary error: the largest distance between a "
      "wrongly judged point and the true boundary, in ulps of the method's precision (so the "
      "method's boundary is off by at least that much somewhere). Refused: an error status "
      "(counted as not stable). C times: best of "
      f"{a.c_repeats} passes over the {n:,} points, one call each; 'one plant' = coefficients given "
      "(a drive checking gains), 'plant per point' = coefficients computed in the call. Instructions: "
      "callgrind (x86-64), (Ir(N calls) - Ir(0 calls)) / N over the first "
      f"{a.callgrind_calls} points. Both include the harness loop and its indirect call: "
      f"{fmt_time(R.ctime['double']['noop'])} and {fmt_ir(R, 'double', 'noop')} instructions (a call that does nothing). "
      "Python times: best of several runs on arrays of the size given (per-point loops on a subset).")
    w("")
    head = ["method", "precision", "time/point, one plant", "time/point, plant per point",
            "instructions/call (one plant / plant per point)", "false stable", "false unstable", "refused",
            "worst boundary error (ulps)", "points judged"]
    rows = []
    for key in ("check", "check_literal", "jury", "jury_plain", "radius"):
        for prec in ("double", "float"):
            r = res[f"c.{key}.{prec}"]
            t1 = R.ctime[prec].get(key)
            t2 = R.ctime[prec].get(f"{key}_new_plant")
            ir = fmt_ir(R, prec, key)
            if f"{key}_new_plant" in R.ctime[prec]:
                ir += " / " + fmt_ir(R, prec, f"{key}_new_plant")
            rows.append([ROW_NAMES[key], prec, fmt_time(t1), fmt_time(t2), ir, r["false_stable"], r["false_unstable"],
                         r["refused"], fmt_ulps(r["worst_ulps"]), f"{r['n']:,}"])
    if "mcu.check.float" in res:
        r = res["mcu.check.float"]
        cnt = R.mcu["counts"]["calls"]
        rows.append(["`zw_check` on Cortex-M4F (QEMU, newlib libm)", "float", "—", "—",
                     f"{np.mean(cnt['zw_check']):.0f} / {np.mean(cnt['zw_check']) + np.mean(cnt['zw_coeffs_init']):.0f} (Arm)",
                     r["false_stable"], r["false_unstable"], r["refused"], fmt_ulps(r["worst_ulps"]), f"{r['n']:,}"])
    for key in ("py.zwidth.check", "py.numpy_closed", "py.eigvals", "py.roots", "py.control", "py.sim", "py.mpmath"):
        if key not in res:
            continue
        r = res[key]
        t1, k1 = R.ptime["one"].get(key, (None, 0))
        t2, k2 = R.ptime["many"].get(key, (None, 0))
        rows.append([PY_NAMES[key], "double", f"{fmt_time(t1)} ({k1:,} pts)", f"{fmt_time(t2)} ({k2:,} pts)", "—",
                     r["false_stable"], r["false_unstable"], r["refused"], fmt_ulps(r["worst_ulps"]), f"{r['n']:,}"])
    w(md_table(head, rows, "llrrrrrrrr"))
    w("")
    rc = res["c.check.double"]
    w(f"The guarded closed form's false-unstable verdicts are all marginal (double: "
      f"{rc['marginal_of_fu']} of {rc['false_unstable']}; float: {res['c.check.float']['marginal_of_fu']} of "
      f"{res['c.check.float']['false_unstable']}).")
    if "py.sim" in res:
        w(f"The simulation row: {SimPeer.SAMPLES:,} samples per point, {res['py.sim']['undecided']} of "
          f"{res['py.sim']['n']} runs undecided (counted not stable).")
    w("")
    w("### K_max at a given B (the largest stable stiffness)")
    w("")
    w("Worst error over every point of the set, as the distance of the computed point (K_max(B), B) "
      "from the true boundary min{f, L} (60 digits) in ulps, along K or along B, whichever is nearer "
      "(near the ends of the damping range K_max falls to 0 through a difference of rounded terms, so "
      "its own ulps say little there; a K_max of 0 counts by the distance of B from the end).")
    w("")
    rows = []
    for prec in ("double", "float"):
        r = res[f"c.k_max.{prec}"]
        rows.append(["`zw_device_k_max` (C)", prec, fmt_time(R.ctime[prec].get("k_max")), fmt_ir(R, prec, "k_max"),
                     fmt_ulps(r["value_ulps"]), r["refused"]])
    if "mcu.k_max.float" in res:
        cnt = R.mcu["counts"]["calls"]["zw_device_k_max"]
        rows.append(["`zw_device_k_max` on Cortex-M4F (QEMU)", "float", "—", f"{np.mean(cnt):.0f} (Arm)",
                     fmt_ulps(res["mcu.k_max.float"]["value_ulps"]), res["mcu.k_max.float"]["refused"]])
    rows.append(["zwidth.alpha_max (Python, the C core)", "double", fmt_time(R.ptime["many"]["py.zwidth.k_max"][0]), "—",
                 fmt_ulps(res["py.zwidth.k_max"]["value_ulps"]), 0])
    rows.append(["numpy closed form min{f, L}, literal coefficients", "double",
                 fmt_time(R.ptime["many"]["py.numpy_kmax"][0]), "—", fmt_ulps(res["py.numpy_kmax"]["value_ulps"]), 0])
    w(md_table(["method", "precision", "time/point", "instructions/call", "worst boundary error (ulps)", "refused"], rows, "llrrrr"))
    w("")

    # ---- section 2
    w("## 2. Coefficients and extremes")
    w("")
    w("Worst error against mpmath (60 digits), in ulps of each value, per range of delta "
      f"({len(R.coef['double']['deltas'])} deltas in double from 0 to 1e300, {len(R.coef['float']['deltas'])} "
      "in float to 1e38: a log grid, denser over [1e-3, 10]). Series: `zw_coeffs_init` (the product); "
      "literal: the paper's formulas (3), (4) (`zw_coeffs_literal`), with the relative error in "
      "parentheses where it is large.")
    w("")
    for prec in ("double", "float"):
        co = R.coef[prec]
        dl = co["deltas"]
        head = [f"{prec}"] + [b[0] for b in Report.BANDS] + ["whole range"]
        rows = []
        for fld in ("e", "c1", "c2", "d12"):
            for kind in ("series", "literal"):
                if kind == "literal" and fld == "e":
                    continue
                u = co["cols"][f"{kind}.{fld}"]
                rel = co["cols"].get(f"literal_rel.{fld}") if kind == "literal" else None
                rows.append([f"{fld}, {kind}"] + band_cells(dl, u, rel) + [cell(u, rel, np.ones(len(u), bool))])
        for fld in ("alpha_mmax", "alpha_p_max", "beta_mmax"):
            u = co["cols"][f"ext.{fld}"]
            rows.append([f"{fld}, `zw_extremes_compute`"] + band_cells(dl, u, None) + [cell(u, None, np.ones(len(u), bool))])
            u = co["cols"][f"extlit.{fld}"]
            rel = co["cols"][f"extlit_rel.{fld}"]
            rows.append([f"{fld}, paper's closed forms on literal coefficients (numpy)"] + band_cells(dl, u, rel)
                        + [cell(u, rel, np.ones(len(u), bool))])
        w(md_table(head, rows, "l" + "r" * (len(head) - 1)))
        w("")
    ref_d, ref_f = R.coef["double"]["ext_refused"], R.coef["float"]["ext_refused"]
    w("beta at alpha_mmax is left out: it crosses zero at delta2, where only an absolute error "
      "means anything (tests/py/test_extremes.py bounds it against the scale of its terms). "
      f"`zw_extremes_compute` refuses (ZW_ERR_RANGE) {len(ref_d)} deltas in double"
      + (f" (from {ref_d.min():.3g})" if len(ref_d) else "") + f" and {len(ref_f)} in float"
      + (f" (from {ref_f.min():.3g})" if len(ref_f) else "")
      + ", where an extreme overflows; those are not scored.")
    w("")
    rows = []
    for prec in ("double", "float"):
        for key, name in (("coeffs_init", "`zw_coeffs_init` (series / careful)"), ("coeffs_literal", "`zw_coeffs_literal`"),
                          ("extremes", "`zw_extremes_compute` (coefficients given)"), ("device_init", "`zw_device_init` (real units)")):
            rows.append([name, prec, fmt_time(R.ctime[prec].get(key)), fmt_ir(R, prec, key)])
    if R.mcu:
        cnt = R.mcu["counts"]["calls"]
        for key in ("zw_coeffs_init", "zw_extremes_compute", "zw_device_init"):
            rows.append([f"`{key}` on Cortex-M4F (QEMU)", "float", "—", f"{np.mean(cnt[key]):.0f} (Arm)"])
    rows.append(["zwidth.extremes (Python, per delta, 1e6-array)", "double", fmt_time(R.ext_time["py.zwidth.extremes"]), "—"])
    rows.append(["numpy closed forms on literal coefficients (per delta)", "double",
                 fmt_time(R.ext_time["py.numpy_literal_extremes"]), "—"])
    rows.append([f"alpha_mmax by a 64 x 64 grid of numpy eigvals (per plant; worst error {R.grid['worst_rel']:.1%}, "
                 f"median {R.grid['median_rel']:.1%}, {R.grid['plants']} plants)", "double",
                 fmt_time(R.ext_time["py.grid_search"]), "—"])
    w(md_table(["what", "precision", "time/call", "instructions/call"], rows, "llrr"))
    w("")
    lit_t = R.ctime["double"]["coeffs_literal"]
    ser_t = R.ctime["double"]["coeffs_init"]
    w(f"The careful coefficients cost {fmt_ratio(ser_t / lit_t)} the literal ones in double "
      f"({fmt_time(ser_t)} against {fmt_time(lit_t)}), "
      f"{fmt_ratio(R.ctime['float']['coeffs_init'] / R.ctime['float']['coeffs_literal'])} in float.")
    w("")

    # ---- section 3
    w("## 3. The MCU view")
    w("")
    if R.fp:
        fp = R.fp
        w(f"Flash and stack from `tools/footprint.sh` ({fp['compiler']}, -Os, float build), run by this "
          f"report{'' if fp['targets_met'] else ' (it reports a missed target)'}:")
        w("")
        img = fp["image"]
        rows = [["zwidth code + constants linked into a firmware (coeffs, check, extremes; --gc-sections)",
                 fmt_b(fp["linked"].get("m4f")), fmt_b(fp["linked"].get("m0"))],
                ["libm pulled in (expf, expm1f, sqrtf, ...)", fmt_b(img.get("libm (maths functions)", {}).get("m4f")),
                 fmt_b(img.get("libm (maths functions)", {}).get("m0"))],
                ["libgcc (soft float on the M0)", fmt_b(img.get("libgcc (soft-float / double helpers)", {}).get("m4f")),
                 fmt_b(img.get("libgcc (soft-float / double helpers)", {}).get("m0"))]]
        for f in ("zw_check", "zw_device_k_max", "zw_coeffs_init", "zw_extremes_compute"):
            s = fp["stack"].get(f, {})
            rows.append([f"stack, worst call chain of `{f}` (libraries excluded)", fmt_b(s.get("m4f")), fmt_b(s.get("m0"))])
        w(md_table(["", "Cortex-M4F (hard FPU)", "Cortex-M0 (soft float)"], rows, "lrr"))
        w("")
    if R.mcu:
        m = R.mcu
        cnt = m["counts"]
        w(f"Executed instructions on an emulated Cortex-M4F ({m['qemu']}, machine mps2-an386), image "
          f"built with footprint.sh's flags (`{m['flags']}`) and newlib nano's libm. Method: "
          "`-singlestep -d exec,nochain` logs one line per executed instruction; the instructions of one "
          "call are counted between two calls of a marker function, without the caller's own (bench/report/mcu.py). "
          f"Check of the method: a hand-written block of {mcu.CALIBRATION} instructions counted "
          f"{cnt['calibration']} ({'exact' if cnt['calibration_ok'] else 'NOT EXACT'}). Instructions, not cycles: "
          f"QEMU does not model the M4's timing. Over {len(cnt['calls']['zw_check'])} points of the set:")
        w("")
        rows = []
        for f in mcu.COUNTED_CALLS:
            v = cnt["calls"][f]
            rows.append([f"`{f}`", min(v), f"{np.mean(v):.0f}", max(v)])
        w(md_table(["call", "min", "mean", "max"], rows, "lrrr"))
        w("")
        rc, rk = res["mcu.check.float"], res["mcu.k_max.float"]
        w(f"The float error those builds buy, measured on the emulated target over {m['points']:,} points "
          f"and {m['deltas']} deltas: `zw_check` {rc['false_stable']} false stable, {rc['false_unstable']} false "
          f"unstable (worst {fmt_ulps(rc['worst_ulps'])} ulps from the boundary); `zw_device_k_max` within "
          f"{fmt_ulps(rk['value_ulps'])} ulps; coefficients within {fmt_ulps(res['mcu.coef.float']['ulps'])} ulps and "
          f"extremes within {fmt_ulps(res['mcu.ext.float']['ulps'])} ulps with newlib's expf / expm1f.")
        w("")
        w("Not measured: instruction counts on the Cortex-M0 (QEMU's M0 board, microbit, is not set up here).")
        w("")

    # ---- section: general loop
    w("## General loop (loop.h): methods against accuracy and time, per degree")
    w("")
    w(R.loop_section)
    w("")

    # ---- section: ranged certification
    w("## Ranged certification: box certificates (box_cert.h)")
    w("")
    w(R.cert_section)
    w("")

    # ---- section: identification
    w("## Identification: from a log to a box (zwidth.identify)")
    w("")
    w(R.ident_section)
    w("")

    # ---- section 4
    w("## 4. Simulation")
    w("")
    w(R.sim_section)
    w("")

    # ---- claims
    w("## Claims checked by this run")
    w("")
    w("Stated once in `bench/report/generate.py` (CLAIMS); `generate.py --quick` (CI) fails when a "
      "measurement breaks one.")
    w("")
    rows = []
    for rid, metric, op, bound, why, val, ok in claims:
        rows.append([rid, metric, f"{op} {fmt_claim(bound)}", "—" if val is None else fmt_claim(val),
                     "skipped" if ok is None else ("holds" if ok else "**BROKEN**"), why])
    w(md_table(["row", "metric", "claim", "measured", "verdict", "why"], rows, "lllrll"))
    w("")
    if R.skipped:
        w("Skipped in this run:")
        w("")
        for s in R.skipped:
            w(f"- {s}")
        w("")
    w("Run time by phase: " + ", ".join(f"{k} {v:.1f} s" for k, v in R.times.items()) + ".")
    w("")
    return "\n".join(L)


def fmt_b(x: Optional[int]) -> str:
    return "—" if x is None else f"{x:,} B"


def fmt_claim(x: float) -> str:
    if isinstance(x, float) and not x.is_integer():
        return f"{x:.3g}"
    return f"{x:.3g}" if abs(x) >= 1e5 else f"{x:.0f}"


def fmt_ir(R: Report, prec: str, key: str) -> str:
    v = R.cir.get(prec, {}).get(key)
    return "—" if v is None else f"{v:,.0f}"


def cell(u: np.ndarray, rel: Optional[np.ndarray], m: np.ndarray) -> str:
    if not m.any():
        return "—"
    worst = float(u[m].max())
    s = fmt_ulps(worst)
    if rel is not None:
        r = float(np.nanmax(rel[m]))
        if r >= 1e-6:
            s += f" (rel. {r:.2g})" if math.isfinite(r) else " (rel. inf)"
    return s


def band_cells(deltas: np.ndarray, u: np.ndarray, rel: Optional[np.ndarray]) -> List[str]:
    return [cell(u, rel, (deltas >= lo) & (deltas < hi)) for _, lo, hi in Report.BANDS]


def summary(R: Report) -> List[str]:
    """The 'which to pick' lines, derived from the measured rows."""
    res, out = R.res, []
    # DSP / firmware: of the C float methods that called no unstable point stable, the
    # cheapest (instructions when callgrind ran, else time); the target's own figures beside.
    keys = ("check", "jury", "jury_plain", "radius", "check_literal")
    cost = (lambda k: R.cir["float"][k]) if R.cir.get("float") else (lambda k: R.ctime["float"][k] * 1e9)
    unit = "x86-64 instructions (callgrind)" if R.cir.get("float") else "ns"
    safe = [k for k in keys if res[f"c.{k}.float"]["false_stable"] == 0]
    if safe:
        best = min(safe, key=cost)
        rb = res[f"c.{best}.float"]
        alt = [f"{short(k)} {fmt_ratio(cost(k) / cost(best))}" for k in safe if k != best]
        unsafe = [f"{short(k)} {fmt_ratio(cost(k) / cost(best))} the cost, {res[f'c.{k}.float']['false_stable']} false stable"
                  for k in keys if k not in safe]
        line = (f"**DSP / firmware: {ROW_NAMES[best]}, float.** The cheapest C method that called no unstable point "
                f"stable in float: {fmt_cost(cost(best), unit)} per check"
                + (f" (other safe ones: {', '.join(alt)})" if alt else "")
                + (f"; {np.mean(R.mcu['counts']['calls']['zw_check']):.0f} Arm instructions on a Cortex-M4F, plus "
                   f"{np.mean(R.mcu['counts']['calls']['zw_coeffs_init']):.0f} once per plant for the coefficients"
                   if R.mcu and best == "check" else "")
                + f". 0 false stable of {rb['n']:,} points"
                + (" (and 0 on the emulated target with newlib's libm)" if res.get("mcu.check.float", {}).get("false_stable") == 0 else "")
                + f", false unstable only within {fmt_ulps(rb['worst_ulps'])} float ulps of the boundary."
                + (f" The unguarded ones call unstable points stable ({'; '.join(unsafe)})." if unsafe else "")
                + (f" Flash {fmt_b(R.fp['linked'].get('m4f'))} (M4F) / {fmt_b(R.fp['linked'].get('m0'))} (M0) with the "
                   f"extremes, stack {fmt_b(R.fp['stack']['zw_check']['m4f'])} / {fmt_b(R.fp['stack']['zw_check']['m0'])}."
                   if R.fp else ""))
        out.append(line)
    # Tuning script: Python, one plant, no false stable, fastest.
    T1 = R.ptime["one"]
    cands = [k for k in T1 if k in res and k.startswith("py.") and res[k].get("false_stable", 1) == 0]
    if cands:
        best = min(cands, key=lambda k: T1[k][0])
        worst_alt = [k for k in ("py.eigvals", "py.roots", "py.control") if k in T1]
        ratio = ", ".join(f"{PY_NAMES[k].split(' (')[0].split(',')[0]} {fmt_ratio(T1[k][0] / T1[best][0])}" for k in worst_alt)
        fs = [f"{PY_NAMES[k].split(',')[0].split(' (')[0]} {res[k]['false_stable']}" for k in ("py.numpy_closed", "py.eigvals", "py.roots", "py.control")
              if k in res and res[k]["false_stable"] > 0]
        out.append(f"**Tuning script (one plant, many gains): {PY_NAMES[best]}.** {fmt_time(T1[best][0])} per gain pair "
                   f"on a {R.ptime['one'][best][1]:,}-point array, 0 false stable; the peers take {ratio} the time"
                   + (f", and call unstable points stable (false stable: {'; '.join(fs)})" if fs else "") + ".")
    # Design sweep: many plants, the extremes per plant.
    tz = R.ext_time["py.zwidth.extremes"]
    dd = R.coef["double"]
    rel = dd["cols"]["extlit_rel.alpha_mmax"]
    small = (dd["deltas"] >= 1e-8) & (dd["deltas"] < 1e-2) & np.isfinite(rel)
    nonfinite = int((~np.isfinite(rel)).sum())
    out.append(f"**Design sweep (many plants): zwidth.extremes / Device on arrays, double.** {fmt_time(tz)} per plant "
               f"for all the extremes, within {fmt_ulps(res['ext.c.double']['ulps'])} ulps over delta from 0 to 1e300; "
               f"a 64 x 64 eigenvalue grid search takes {fmt_ratio(R.ext_time['py.grid_search'] / tz)} as long and is "
               f"{R.grid['worst_rel']:.1%} off; the paper's closed forms on literal coefficients take "
               f"{fmt_ratio(R.ext_time['py.numpy_literal_extremes'] / tz)} the time but are off by up to "
               f"{float(rel[small].max()) if small.any() else float('nan'):.2g} (relative) for delta in [1e-8, 1e-2) and give "
               f"inf or NaN at {nonfinite} of {len(rel)} deltas. A check with a new plant per point costs "
               f"{fmt_time(R.ptime['many']['py.zwidth.check'][0])} (zwidth.check).")
    # Double or float on a host: instructions (stable across runs) when callgrind ran, else time.
    if R.cir.get("float") and R.cir.get("double"):
        cd_, cf_, what = R.cir["double"]["check"], R.cir["float"]["check"], "instructions (callgrind)"
    else:
        cd_, cf_, what = R.ctime["double"]["check"], R.ctime["float"]["check"], "time"
    out.append(f"**Double or float?** On a host, double: a float check costs {fmt_ratio(cf_ / cd_)} the {what} "
               f"of a double one, and the band widens from "
               f"{fmt_ulps(res['c.check.double']['worst_ulps'])} double ulps (up to "
               f"{res['c.check.double']['worst_ulps'] * DOUBLE.eps:.1g} relative) to "
               f"{fmt_ulps(res['c.check.float']['worst_ulps'])} float ulps (up to "
               f"{res['c.check.float']['worst_ulps'] * FLOAT.eps:.1g}). On an MCU with a single-precision FPU, "
               "float: double is software there.")
    return out


def short(key: str) -> str:
    return ROW_NAMES[key].split(" (")[0]


def fmt_cost(v: float, unit: str) -> str:
    return f"{v:,.0f} {unit}" if unit != "ns" else f"{v:.3g} ns"


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__.split("\n\n", 1)[1])
    p.add_argument("--quick", action="store_true", help="CI size (seconds); fails on a broken claim")
    p.add_argument("--build-dir", default=os.path.join(ROOT, "build-report"),
                   help="where the harness is built and the data files go (default: build-report)")
    p.add_argument("--output", help="the report (default: bench/REPORT.md; --quick: BUILD_DIR/REPORT-quick.md)")
    p.add_argument("--points", type=int, default=20000, help="size of the point set (default 20000)")
    p.add_argument("--time-points", type=int, default=1_000_000, help="array size of the Python timings")
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--eig-repeats", type=int, default=2)
    p.add_argument("--slow-repeats", type=int, default=2)
    p.add_argument("--c-repeats", type=int, default=15)
    p.add_argument("--roots-subset", type=int, default=20000)
    p.add_argument("--control-subset", type=int, default=1000)
    p.add_argument("--sim-subset", type=int, default=1000)
    p.add_argument("--mpmath-subset", type=int, default=200)
    p.add_argument("--callgrind-calls", type=int, default=2048)
    p.add_argument("--coef-deltas", type=int, default=1200)
    p.add_argument("--grid-plants", type=int, default=40)
    p.add_argument("--mcu-points", type=int, default=4000)
    p.add_argument("--mcu-count", type=int, default=64, help="points whose calls are counted on the MCU")
    p.add_argument("--no-callgrind", action="store_true")
    p.add_argument("--no-mcu", action="store_true")
    a = p.parse_args(argv)
    if a.quick:
        a.points = min(a.points, 1600)
        a.time_points = min(a.time_points, 20000)
        a.repeats, a.eig_repeats, a.slow_repeats, a.c_repeats = 2, 1, 1, 3
        a.roots_subset = min(a.roots_subset, 1600)
        a.control_subset = min(a.control_subset, 100)
        a.sim_subset = min(a.sim_subset, 100)
        a.mpmath_subset = min(a.mpmath_subset, 40)
        a.coef_deltas = min(a.coef_deltas, 300)
        a.grid_plants = min(a.grid_plants, 4)
        a.mcu_points = min(a.mcu_points, 1600)
        a.mcu_count = min(a.mcu_count, 8)
    t_start = time.perf_counter()
    R = Report(a)
    try:
        R.points()
        R.c_accuracy()
        R.c_timing()
        R.py_methods()
        R.coefficients()
        R.mcu_view()
        R.sim_section = R.simulation()
        R.loop_section = R.general_loop()
        R.cert_section = R.box_certificates()
        R.ident_section = R.identification()
    except (RuntimeError, subprocess.TimeoutExpired) as exc:
        print(f"generate.py: {exc}", file=sys.stderr)
        return 2
    claims = R.check_claims()
    text = write_report(R, claims, time.perf_counter() - t_start)
    out = a.output or (os.path.join(R.work, "REPORT-quick.md") if a.quick else os.path.join(ROOT, "bench", "REPORT.md"))
    with open(out, "w", encoding="utf-8") as fh:
        fh.write(text)
    print(text)
    log(f"wrote {out}")
    broken = [c for c in claims if c[6] is False]
    for rid, metric, op, bound, why, val, _ in broken:
        print(f"generate.py: CLAIM BROKEN: {rid} {metric} = {val} (claim {op} {bound}: {why})", file=sys.stderr)
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
