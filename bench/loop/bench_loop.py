# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Benchmark of the general loop's guarded check (issue 12), not a test.

For loops of degree 3..26: the C check (zw_loop_check) and its boolean fast path
(zw_loop_is_stable) per call (wall time and callgrind instructions, host, double) against
numpy's batched eigvals on the companion matrices of the same loops,
and false "stable" verdicts of each on points crowded at the boundary (1..1e4 ulps, labelled
by the 50-digit mpmath reference of tests/py/loop_reference.py).

Usage: ZW_LIB_DIR=build python bench/loop/bench_loop.py [--quick]
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "tests" / "py"))
import conftest as cf  # noqa: E402
import loop_reference as lr  # noqa: E402
import test_loop_reference as tlr  # noqa: E402

QUICK = "--quick" in sys.argv
BUILD = Path(os.environ.get("ZW_LIB_DIR", REPO / "build"))
SPECS = [
    dict(delay=0),
    dict(delay=2, differentiator="tustin"),
    dict(delay=1, differentiator="tustin", filter="lowpass", pole=0.8),
    dict(delay=8),
    dict(delay=3, filter="average", average=8),
    dict(delay=8, filter="average", average=8),
    dict(delay=8, filter="average", average=16),
]
DELTA = 0.5


def build_driver(tmp):
    exe = Path(tmp) / "loop_driver"
    subprocess.run(["cc", "-O2", "-std=c99", "-I", str(REPO / "csrc/include"),
                    str(REPO / "bench/loop/loop_driver.c"), str(BUILD / "libzwidth_d.a"), "-lm", "-o", str(exe)],
                   check=True)
    return exe


def driver_args(spec, n, box):
    kinds = {"backward": 0, "tustin": 1}
    filters = {"none": 0, "lowpass": 1, "average": 2}
    return [str(DELTA), str(spec.get("delay", 0)), str(kinds[spec.get("differentiator", "backward")]),
            str(filters[spec.get("filter", "none")]), str(spec.get("pole", 0.0)), str(spec.get("average", 0)),
            str(n)] + [repr(x) for x in box]


def callgrind_ir(exe, args):
    if not shutil.which("valgrind"):
        return None
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "cg.out"
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", str(exe)] + args,
                       check=True, capture_output=True)
        for line in out.read_text().splitlines():
            if line.startswith("summary:") or line.startswith("totals:"):
                return int(line.split()[1])
    return None


def box_for(zw, lp):
    """alpha in [0, 2 alpha_max(beta = 0.2)], beta in [-delta, 1.5]: about half stable."""
    a = 1e-6
    while zw.loop_check(lp, a, 0.2)[1].stable and a < 1e6:
        a *= 1.5
    return (2 * a, -DELTA, 1.5)


def eigvals_stable(lp, alphas, betas):
    n = lp.degree
    d, na, nb = (np.array(getattr(lp, k)[: n + 1]) for k in ("D", "Na", "Nb"))
    p = d[None, :] + alphas[:, None] * na[None, :] + betas[:, None] * nb[None, :]
    comp = np.zeros((len(alphas), n, n))
    comp[:, 0, :] = -p[:, 1:] / p[:, :1]
    comp[:, np.arange(1, n), np.arange(n - 1)] = 1.0
    t0 = time.perf_counter()
    rho = np.abs(np.linalg.eigvals(comp)).max(axis=1)
    return rho < 1, (time.perf_counter() - t0) / len(alphas)


def run_driver(exe, spec, n, box, fast=False):
    """(ns per call, stable fraction, marginal fraction, ns per stable call)."""
    args = driver_args(spec, n, box) + (["fast"] if fast else [])
    return tuple(map(float, subprocess.run([str(exe)] + args, check=True, capture_output=True,
                                           text=True).stdout.split()))


def ir_per_call(exe, spec, box, fast=False, n_cg=2000):
    extra = ["fast"] if fast else []
    ir0 = callgrind_ir(exe, driver_args(spec, 1, box) + extra)
    ir1 = callgrind_ir(exe, driver_args(spec, n_cg + 1, box) + extra)
    return (ir1 - ir0) / n_cg if ir0 and ir1 else float("nan")


def driver_points(box, n=20000):
    """The driver's points (its linear congruential generator)."""
    seed = 1
    al, be = [], []
    for _ in range(n):
        seed = (seed * 1103515245 + 12345) % 2 ** 32
        al.append((seed >> 8) / 16777216.0 * box[0])
        seed = (seed * 1103515245 + 12345) % 2 ** 32
        be.append(box[1] + (seed >> 8) / 16777216.0 * (box[2] - box[1]))
    return np.array(al), np.array(be)


def boundary_counts(zw, lp, spec, rng, count, steps=6):
    """Points crowded at the boundary (1..1e4 ulps both sides, mpmath labels): (points,
    false stable C, false stable eigvals, false unstable C, false unstable eigvals)."""
    parts = tlr.ref_parts(zw, DELTA, spec)
    n = lp.degree
    pa, pb, truth = [], [], []
    for gain, g_b, a, b in tlr.boundary_points(zw, parts, n, rng, count):
        for k in tlr.STEPS[:steps]:
            for sign in (1, -1):
                g = g_b + sign * k * float(np.spacing(abs(g_b)))
                pt = (g, b) if gain == 0 else (a, g)
                pa.append(pt[0])
                pb.append(pt[1])
                truth.append(tlr.label(parts, n, *pt))
    fs_c = fs_e = fu_c = fu_e = mismatch = 0
    if pa:
        eig_ok, _ = eigvals_stable(lp, np.array(pa), np.array(pb))
        for a_, b_, t, e in zip(pa, pb, truth, eig_ok):
            c = zw.loop_check(lp, a_, b_)[1].stable
            mismatch += int(zw.loop_is_stable(lp, a_, b_) != (0, c))
            fs_c += int(c and not t)
            fu_c += int(t and not c)
            fs_e += int(bool(e) and not t)
            fu_e += int(t and not bool(e))
    boundary_counts.mismatch = mismatch  # fast path against the check (read by the report)
    return len(pa), fs_c, fs_e, fu_c, fu_e


def main():
    zw = cf.load("double")
    rng = np.random.default_rng(3)
    with tempfile.TemporaryDirectory() as tmp:
        exe = build_driver(tmp)
        print(f"{'loop':34s} {'deg':>3s} {'check ns':>8s} {'fast ns':>7s} {'Ir chk':>7s} {'Ir fast':>7s} "
              f"{'eig ns':>7s} {'x chk':>5s} {'x fast':>6s} {'stbl%':>5s} {'marg%':>5s} | "
              f"{'pts':>4s} {'FS C':>4s} {'FS eig':>6s} {'FU C':>4s} {'FU eig':>6s}")
        for spec in SPECS:
            lp = tlr.make_loop(zw, DELTA, spec)
            box = box_for(zw, lp)
            n_time = 20000 if QUICK else 100000
            ns, stable_frac, marg_frac, _ = run_driver(exe, spec, n_time, box)
            ns_fast = run_driver(exe, spec, n_time, box, fast=True)[0]
            ir = ir_per_call(exe, spec, box)
            ir_fast = ir_per_call(exe, spec, box, fast=True)
            _, eig_s = eigvals_stable(lp, *driver_points(box))
            pts, fs_c, fs_e, fu_c, fu_e = boundary_counts(zw, lp, spec, rng, 3 if QUICK else 8)
            print(f"{tlr.spec_id(spec):34s} {lp.degree:3d} {ns:8.0f} {ns_fast:7.0f} {ir:7.0f} {ir_fast:7.0f} "
                  f"{eig_s * 1e9:7.0f} {eig_s * 1e9 / ns:5.1f} {eig_s * 1e9 / ns_fast:6.1f} "
                  f"{100 * stable_frac:5.1f} {100 * marg_frac:5.2f} | {pts:4d} {fs_c:4d} {fs_e:6d} {fu_c:4d} {fu_e:6d}",
                  flush=True)


if __name__ == "__main__":
    main()
