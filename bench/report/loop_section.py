"""The general loop (loop.h, issue 12) in the report: methods against accuracy and time,
per degree.  The measurements are bench/loop/bench_loop.py's (one implementation): the C
check (zw_loop_check) and its boolean fast path (zw_loop_is_stable) timed by its driver and
counted by callgrind, numpy's batched eigvals and np.roots on the same loops, and false
"stable" / "unstable" counts of each on points crowded at the boundary (1..1e4 ulps both
sides), labelled by the 50-digit mpmath Schur-Cohn reference of tests/py/loop_reference.py.
Needs the shared library (ZW_LIB_DIR, default build/) for the ctypes calls and the labels."""
from __future__ import annotations

import os
import sys
import tempfile
import time
from typing import Any, Dict, List

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "bench", "loop"))


def measure(quick: bool, callgrind: bool) -> List[Dict[str, Any]]:
    import bench_loop as bl  # noqa: E402 (also puts tests/py on the path)
    zw = bl.cf.load("double")
    rng = np.random.default_rng(3)
    rows = []
    specs = bl.SPECS[:2] + bl.SPECS[3:4] + bl.SPECS[-1:] if quick else bl.SPECS
    with tempfile.TemporaryDirectory() as tmp:
        exe = bl.build_driver(tmp)
        for spec in specs:
            lp = bl.tlr.make_loop(zw, bl.DELTA, spec)
            box = bl.box_for(zw, lp)
            n_time = 5000 if quick else 100000
            ns, stable_frac, marg_frac, _ = bl.run_driver(exe, spec, n_time, box)
            ns_fast = bl.run_driver(exe, spec, n_time, box, fast=True)[0]
            ir = bl.ir_per_call(exe, spec, box) if callgrind else None
            ir_fast = bl.ir_per_call(exe, spec, box, fast=True) if callgrind else None
            al, be = bl.driver_points(box, 2000 if quick else 20000)
            _, eig_s = bl.eigvals_stable(lp, al, be)
            n = lp.degree
            d, na, nb = (np.array(getattr(lp, k)[: n + 1]) for k in ("D", "Na", "Nb"))
            k = 200 if quick else 2000
            t0 = time.perf_counter()
            for a_, b_ in zip(al[:k], be[:k]):
                np.max(np.abs(np.roots(d + a_ * na + b_ * nb)))
            roots_s = (time.perf_counter() - t0) / k
            pts, fs_c, fs_e, fu_c, fu_e = bl.boundary_counts(zw, lp, spec, rng, 2 if quick else 8)
            rows.append(dict(spec=bl.tlr.spec_id(spec), degree=n, ns=ns, ns_fast=ns_fast, ir=ir, ir_fast=ir_fast,
                             eig_ns=eig_s * 1e9, roots_ns=roots_s * 1e9, stable=stable_frac, marginal=marg_frac,
                             pts=pts, fs_c=fs_c, fs_e=fs_e, fu_c=fu_c, fu_e=fu_e))
    return rows


def results(rows: List[Dict[str, Any]]) -> Dict[str, Dict[str, float]]:
    """The claim rows: loop.check (false stable of the guarded check), loop.fast (its speed-up
    over batched eigvals at degree <= 18, the loops the Routh array settles)."""
    res = {"loop.check": {"false_stable": float(sum(r["fs_c"] for r in rows))},
           "loop.eigvals": {"false_stable": float(sum(r["fs_e"] for r in rows))}}
    low = [r["eig_ns"] / r["ns_fast"] for r in rows if r["degree"] <= 18]
    if low:
        res["loop.fast"] = {"speedup_min_deg18": float(min(low))}
    return res


def section(rows: List[Dict[str, Any]], md_table, fmt_int) -> str:
    L: List[str] = []
    w = L.append
    w("Loops of degree 3 to 26 (delta = 0.5; delay, Tustin, low-pass and moving averages), points drawn "
      "uniformly over alpha in [0, 2 alpha_max(0.2)], beta in [-delta, 1.5] (about a fifth to two fifths "
      "stable).  Host, double, one core; ns per call from bench/loop/loop_driver.c, Ir from callgrind; "
      "numpy batched eigvals on the companion matrices of the same loops, np.roots per point.  "
      "False stable / false unstable: points 1 to 1e4 ulps from the boundary on both sides, labelled by "
      "the 50-digit mpmath Schur-Cohn reference.")
    w("")
    head = ["loop", "degree", "check ns", "fast ns", "check Ir", "fast Ir", "eigvals ns (batched)", "roots ns",
            "eigvals / fast", "stable %", "boundary pts", "FS check", "FS eigvals", "FU check", "FU eigvals"]
    body = []
    for r in rows:
        body.append([f"`{r['spec']}`", r["degree"], f"{r['ns']:.0f}", f"{r['ns_fast']:.0f}",
                     fmt_int(r["ir"]) if r["ir"] is not None else "—",
                     fmt_int(r["ir_fast"]) if r["ir_fast"] is not None else "—",
                     f"{r['eig_ns']:.0f}", f"{r['roots_ns']:.0f}", f"{r['eig_ns'] / r['ns_fast']:.1f}x",
                     f"{100 * r['stable']:.0f}", r["pts"], r["fs_c"], r["fs_e"], r["fu_c"], r["fu_e"]])
    w(md_table(head, body, "lrrrrrrrrrrrrrr"))
    w("")
    w("The check: a Routh test with running error bounds on the bilinear parts, then (where it cannot "
      "tell) a root-inclusion test on Aberth roots; the full verdict also runs Aberth for the deciding "
      "boundary of a not-stable point, which the fast path `zw_loop_is_stable` skips (same verdict for "
      "every input).  Where Routh settles the point the fast path is 13 to 45 times faster than batched "
      "eigvals up to degree 18.  At degree 26 (delay 8, average over 16) the running bound of the Routh "
      "array grows about 7x per row while the true error grows about 1.5x per row (the rows' errors are "
      "correlated, the bound treats them as independent), so nearly every point goes to the root test "
      "and the check costs about what eigvals does: the issue's 20x is not met there.  Its false "
      "unstable verdicts are all marked marginal and within tests/py/test_loop_reference.py's stated "
      "band; eigvals (unguarded, on the same rounded coefficients) calls some unstable points stable.")
    w("")
    w("Not measured here: Cortex-M4F instructions per call of the general loop under QEMU (the "
      "mcu.py driver counts the ideal loop's calls only).  Stack and flash of the loop modules: "
      "section 3 and docs/footprint.md.")
    return "\n".join(L)
