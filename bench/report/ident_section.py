# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Identification (zwidth.identify, docs/identify.md) in the report: the figures of the
1,000-trial validation, bench/identify/validate.py, read from its summary
(bench/identify/results.json).  The run takes about 13 minutes on two cores, so the report
embeds its committed summary rather than running it (the summary names the identify.py it
measured by hash); `validate.py --quick` (50 trials, under a minute) re-measures."""
from __future__ import annotations

import json
import os
from typing import Any, Callable, Dict, List, Sequence

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SUMMARY = os.path.join(ROOT, "bench", "identify", "results.json")


def load() -> Dict[str, Any]:
    with open(SUMMARY, encoding="utf-8") as fh:
        data: Dict[str, Any] = json.load(fh)["summary"]
    return data


def results(s: Dict[str, Any]) -> Dict[str, Dict[str, float]]:
    """For the claims: the box's certified gains on the true plant, and the coverage of the
    plain plant's intervals."""
    box = s["box"]
    plain = next(r for r in s["coverage"] if r["group"] == "class=plain")
    return {"ident.gains": {"exceptions": float(len(box["gain_exceptions"])), "checks": float(box["gain_checks"])},
            "ident.coverage.plain": {"m": plain["m"]["coverage"], "b": plain["b"]["coverage"]}}


def _pct(x: Dict[str, Any]) -> str:
    return f"{x['hits']}/{x['n']} ({100 * x['hits'] / x['n']:.1f} %)" if x.get("n") else "-"


def section(s: Dict[str, Any], md_table: Callable[[Sequence[str], List[List[str]]], str]) -> str:
    out: List[str] = []
    w = out.append
    w(f"From `bench/identify/validate.py --trials {s['trials']} --seed {s['seed']} --jobs {s['jobs']}` "
      f"({s['wall_seconds']:.0f} s of wall time; identify.py sha256 {s['identify_sha256'][:16]}), read from "
      "`bench/identify/results.json` (this report does not re-run it: `validate.py --quick` does in under a "
      "minute). Each trial simulates the experiment on a random plant with the independent reference "
      "(`tests/py/ident_reference.py`: RK4 with 4096 substeps per sample, the exact closed form with "
      "friction; not identify's code), through an encoder or an analog sensor with noise, and fits it with the "
      "options that match the trial. Families: the paper's drive, haptic devices (m 0.01..1 kg), servo drives "
      "(J 1e-6..1e-3); delay 0..2; classes plain, lag (0.1..1 T), spring, lag+spring, Coulomb friction.")
    w("")
    w("**Coverage of the true parameters by the 95 % intervals** (PASS: observed >= 0.95):")
    w("")
    rows = []
    for r in s["coverage"]:
        if not r["group"].startswith(("all", "class=")):
            continue
        cells = [_pct(r[p]) if p in r else "-" for p in ("m", "b", "k", "tau", "F_c")]
        rows.append([r["group"], str(r["fitted"]), *cells, f"{100 * r['delay_right']:.1f} %",
                     "PASS" if r["pass"] else "FAIL"])
    w(md_table(["group", "fitted", "m", "b", "k", "tau", "F_c", "delay right", "verdict"], rows))
    w("")
    box = s["box"]
    c = box["contains_truth"]
    why = "; ".join(f"{n} x {k}" for k, n in box["without_box"].items())
    w(f"**Boxes** (`Identification.box()`, joint level 0.99): {box['with_box']} of {box['trials']} trials have "
      f"one; it holds the true plant (with a delay at least the true one: the box takes the largest delay the "
      f"log allows) in {_pct(c)}. No box: {why}.")
    w("")
    exc = box["gain_exceptions"]
    w(f"**Certified gains on the true plant:** four pairs per box ({box['gain_checks']} in all): "
      f"(0.9 K_mmax, B_at), (0.5 K_mmax, 0), and the ends of b_range(0.5 K_mmax), each judged with "
      f"`zwidth.Device` on the true plant (its delay, lag and spring). Of the pairs the box certifies, "
      f"**{len(exc)} are unstable** on the true plant"
      + (" (trials " + ", ".join(sorted({str(e['trial']) for e in exc})) + "; docs/identify.md, Limits)"
         if exc else "") + ".")
    w("")
    w("**Accuracy and time per fit** against a plain equation-error least squares (ARX, given the true "
      "delay) and a generic frequency-response fit (scipy welch/csd H1 fitted by least_squares, from the truth "
      "times a factor in [1/2, 2]; python-control has no fit of an input-output log):")
    w("")
    rows = []
    for r in s["accuracy"]:
        if r["group"] != "all":
            continue
        rows.append([r["method"], f"{r['failed']}", f"{r['m_median']:.2g}", f"{r['m_p95']:.2g}",
                     f"{r['b_median']:.2g}", f"{r['b_p95']:.2g}", f"{1e3 * r['seconds_median']:.3g}"])
    w(md_table(["method", "failed", "m median", "m p95", "b median", "b p95", "ms per fit (median)"], rows))
    return "\n".join(out)
