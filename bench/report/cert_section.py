# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Ranged certification (box certificates, box_cert.h) in the report: the host's search
time, the certificate's size, its verification on the host and on an emulated Cortex-M4F
(tools/m4f_box_cert.sh, whose tables are embedded), and its tightness: each step's level
against the least point K_max over a grid of plants and of B in the step (Device.k_max, the
point limit tested against mpmath; an independent algorithm from the interval proof)."""
from __future__ import annotations

import os
import re
import statistics
import subprocess
from typing import Any, Dict, List, Tuple

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

#: bench/modbus/bench_regmap_box.c's boxes (the M4F benchmark's): (name, m, b, delay, B range)
BOXES: List[Tuple[str, Tuple[float, float], Tuple[float, float], int, Tuple[float, float]]] = [
    ("paper drive +-5 %", (0.95 * 85.78e-7, 1.05 * 85.78e-7), (0.95 * 2.197e-3, 1.05 * 2.197e-3), 0, (-1e-3, 3e-3)),
    ("m 2e-5..1.5e-4", (2e-5, 1.5e-4), (2.197e-3, 2.197e-3), 0, (-1e-3, 4e-3)),
    ("paper drive +-5 %, delay 1", (0.95 * 85.78e-7, 1.05 * 85.78e-7), (0.95 * 2.197e-3, 1.05 * 2.197e-3), 1,
     (-1e-3, 2e-3)),
]
T = 0.02


def _grid_min(m: Tuple[float, float], b: Tuple[float, float], delay: int, B_lo: float, B_hi: float, n: int) -> float:
    import numpy as np
    import zwidth
    least = float("inf")
    Bs = np.linspace(B_lo, B_hi, 5)
    for mi in np.linspace(m[0], m[1], n):
        for bi in np.linspace(b[0], b[1], n if b[1] > b[0] else 1):
            k = zwidth.Device(float(mi), float(bi), T, delay=delay).k_max(Bs)
            least = min(least, float(np.min(k)))
    return least


def measure(quick: bool) -> List[Dict[str, Any]]:
    import zwidth
    rows = []
    for name, m, b, delay, (lo, hi) in BOXES:
        box = zwidth.PlantBox(m, b, T, delay=delay)
        c = box.certificate((lo, hi))
        ratios = [k / _grid_min(m, b, delay, s_lo, s_hi, 5 if quick else 21) for s_lo, s_hi, k, _ in c.steps()]
        rows.append({"name": name, "delay": delay, "B": (lo, hi), "leaves": c.leaves, "tests": c.tests,
                     "build_s": c.build_seconds, "verify_s": c.verify_seconds, "bytes": c.size_bytes,
                     "tight_min": min(ratios), "tight_median": statistics.median(ratios),
                     "tight_max": max(ratios), "K_top": max(c.K)})
    return rows


def results(rows: List[Dict[str, Any]]) -> Dict[str, Dict[str, float]]:
    """For the claims: the least level / reference ratio over all steps (never above 1)."""
    return {"cert.tightness": {"max_ratio": max(r["tight_max"] for r in rows),
                               "worst_step_ratio": min(r["tight_min"] for r in rows)}}


def mcu_tables() -> Tuple[str, Dict[str, float]]:
    """tools/m4f_box_cert.sh's output (its tables), and the largest verify count."""
    p = subprocess.run(["bash", os.path.join(ROOT, "tools", "m4f_box_cert.sh")], capture_output=True, text=True,
                       timeout=600)
    if p.returncode == 77:
        raise OSError("tools/m4f_box_cert.sh: " + (p.stdout + p.stderr).strip().splitlines()[-1])
    if p.returncode != 0:
        raise RuntimeError(f"tools/m4f_box_cert.sh exited {p.returncode}: {p.stdout[-400:]}{p.stderr[-400:]}")
    lines = p.stdout.splitlines()
    tables = [ln for ln in lines if ln.startswith("|")]
    worst = 0.0
    for ln in tables:
        cells = [c.strip() for c in ln.strip("|").split("|")]
        if len(cells) > 2 and cells[2].isdigit():
            worst = max(worst, float(cells[2]))
    return "\n".join(lines), {"verify_max_instructions": worst}


def section(rows: List[Dict[str, Any]], md_table, mcu_text: str) -> str:
    head = ["box", "B range", "leaves", "host search", "host verify", "size", "level / reference: worst step",
            "median step"]
    body = [[r["name"], f"[{r['B'][0]:g}, {r['B'][1]:g}]", r["leaves"], f"{r['build_s'] * 1e3:.0f} ms",
             f"{r['verify_s'] * 1e3:.2f} ms", f"{r['bytes']} B", f"{r['tight_min']:.3f}", f"{r['tight_median']:.3f}"]
            for r in rows]
    out = ["A ranged block's limits are proven on the host and only checked on the drive: `PlantBox.certificate()` "
           "(float, 16 steps, at most 512 leaves) searches, `zw_box_cert_verify` walks the proof with at most 512 "
           "interval tests and no search (box_cert.h; docs/design/box-certificate.md). Tightness: each step's level "
           "over the least point K_max (`Device.k_max`, tested against mpmath) on a grid of plants and 5 B per step; "
           "never above 1. The steps at the ends of a B range keep least (K_max falls steeply there). The valley box "
           "(an interior minimum in m, ideal loop) keeps about half: the Kharitonov leaves are loose there, and box.c's "
           "closed-form bound has no B-interval form yet.", "",
           md_table(head, body, "lrrrrrrr"), ""]
    mcu_text = re.sub(r"^(#+) ", lambda m: "#" * (len(m.group(1)) + 1) + " ", mcu_text, flags=re.M)
    out.append(mcu_text if mcu_text else "_The Cortex-M4F run was skipped (see the skipped list)._")
    return "\n".join(out)
