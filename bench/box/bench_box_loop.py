#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""Certifying a plant box of the loop a drive runs (one sample of delay; csrc/src/box_loop.c)
against a dense grid search.

For random boxes around the paper's rotary drive (b = 2.197e-3 N m s/rad, T = 0.02 / 0.008 /
0.001 s, delta = b T / m from 0.05 to 40, m spanning up to a factor 16, b +- 5 %), d samples of
delay (default 1), and B inside the nominal plant's band at K -> 0+:

  certified   PlantBox(..., delay=1).k_max(B): K_lower (every K in (0, K_lower] stable at
              every plant, proven), the worst plant found and its K_max (K_upper).
  grid G x G  Device(m_grid, b_grid, T, delay=1).k_max(B), min over the grid (corners in).

Reported: time per box (median), and how often the grid's minimum is above K_upper (a K in
between passes every grid plant yet is unstable at the worst plant: verified with
Device.is_stable), with the largest relative overestimate.

Run:  python bench/box/bench_box_loop.py [--boxes N] [--seed S] [--markdown FILE]
"""
from __future__ import annotations

import argparse
import math
import random
import statistics
import time
from typing import List

import numpy as np

import zwidth

B_PAPER = 2.197e-3
GRIDS = (2, 11, 51)


def _hand_box(delay: int) -> str:
    """A drive-like device with a spring and a coupled hand in ranges (box.h's plant-side
    parts): the certified K_max against the corners and grids of the folded (M, Bp, Kp)."""
    m, b, T, B = (0.1, 0.14), (0.5, 0.8), 0.001, 5.0
    hand = ((0.25, 0.5), (1.0, 3.0), (100.0, 600.0))
    box = zwidth.PlantBox(m, b, T, delay=delay, stiffness=(0.0, 50.0), hand=hand)
    t0 = time.perf_counter()
    k = box.k_max(B)
    t = time.perf_counter() - t0
    M, Bp, Kp = box.totals
    lines = [f"\nHand box (m {m[0]:g}..{m[1]:g}, b {b[0]:g}..{b[1]:g}, k_p 0..50, hand m_h {hand[0][0]:g}..{hand[0][1]:g}, "
             f"b_h {hand[1][0]:g}..{hand[1][1]:g}, k_h {hand[2][0]:g}..{hand[2][1]:g}, T {T:g}, d = {delay}, B {B:g}): "
             f"certified K_lower {k.K_lower:.6g} (K_upper {k.K_upper:.6g} at M = {k.m_worst:.4g}, Kp = {k.k_worst:.4g}) "
             f"in {1e3 * t:.0f} ms ({k.evals} cell tests);"]
    for g in (2, 11):
        mm, bb, kk = np.meshgrid(np.linspace(M.lo, M.hi, g), np.linspace(Bp.lo, Bp.hi, g), np.linspace(Kp.lo, Kp.hi, g))
        t0 = time.perf_counter()
        kg = float(np.min(box._device(mm.ravel(), bb.ravel(), kk.ravel()).k_max(B)))
        lines.append(f"  {g} x {g} x {g} grid of the folded plants: min {kg:.6g} in {1e3 * (time.perf_counter() - t0):.0f} ms "
                     f"(K_lower / min {k.K_lower / kg:.4f})")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--boxes", type=int, default=40)
    ap.add_argument("--seed", type=int, default=16)
    ap.add_argument("--delay", type=int, default=1)
    ap.add_argument("--markdown", default=None)
    args = ap.parse_args()
    rnd = random.Random(args.seed)
    t_cert: List[float] = []
    t_grid = {g: [] for g in GRIDS}
    fooled = {g: 0 for g in GRIDS}
    over = {g: 0.0 for g in GRIDS}
    gaps: List[float] = []
    n = 0
    while n < args.boxes:
        T = rnd.choice([0.02, 0.008, 0.001])
        b_mid = B_PAPER * 10 ** rnd.uniform(-0.5, 0.5)
        delta_mid = 10 ** (rnd.uniform(-0.1, 0.9) if n % 2 else rnd.uniform(-1.3, 1.6))
        m_mid = b_mid * T / delta_mid
        spread = 10 ** rnd.uniform(-1.5, math.log10(3.0))  # m_hi / m_lo up to 16
        m_lo, m_hi = m_mid / (1 + spread), m_mid * (1 + spread)
        b_lo, b_hi = b_mid * 0.95, b_mid * 1.05
        nom = zwidth.Device(m_mid, b_mid, T, delay=args.delay).extremes()
        B = float(nom.B_mmin) + rnd.uniform(0.05, 0.9) * (float(nom.B_mmax) - float(nom.B_mmin))
        box = zwidth.PlantBox(m=(m_lo, m_hi), b=(b_lo, b_hi), T=T, delay=args.delay)
        t0 = time.perf_counter()
        k = box.k_max(B)
        t_cert.append(time.perf_counter() - t0)
        if not k.K_lower > 0:
            continue
        n += 1
        gaps.append(k.gap)
        for g in GRIDS:
            mm, bb = np.meshgrid(np.linspace(m_lo, m_hi, g), np.linspace(b_lo, b_hi, g))
            t0 = time.perf_counter()
            kg = float(np.min(zwidth.Device(mm.ravel(), bb.ravel(), T, delay=args.delay).k_max(B)))
            t_grid[g].append(time.perf_counter() - t0)
            if kg > k.K_upper * (1 + 1e-12):
                K_bad = 0.5 * (kg + k.K_upper)
                dev = zwidth.Device(k.m_worst, k.b_worst, T, delay=args.delay)
                if not bool(dev.is_stable(K_bad, B)):
                    fooled[g] += 1
                over[g] = max(over[g], (kg - k.K_upper) / k.K_upper)
    ms = lambda xs: 1e3 * statistics.median(xs)  # noqa: E731
    rows = [f"| certified search (`PlantBox(delay={args.delay}).k_max`, rel_tol 1e-4) | {ms(t_cert):.1f} ms "
            f"(max {1e3 * max(t_cert):.0f} ms) | 0 (proven) | never above; gap median {statistics.median(gaps):.1e}, "
            f"max {max(gaps):.1e} |"]
    for g in GRIDS:
        rows.append(f"| {g} x {g} grid of `Device(..., delay={args.delay}).k_max` | {ms(t_grid[g]):.2f} ms | "
                    f"{fooled[g]} of {n} | {100 * over[g]:.3g} % |")
    text = "\n".join(["| method | time per box (median) | boxes where it certifies an unstable pair | "
                      "worst overestimate of the box's K_max |", "|---|---|---|---|"] + rows)
    # a box with an interior minimum in m (found by scanning K_max(J) at b = 2.197e-3, T = 0.02)
    m_lo, m_hi, b_lo, b_hi, T, B = 3e-5, 1.5e-4, 2.1e-3, 2.3e-3, 0.02, 7.5e-4
    box = zwidth.PlantBox(m=(m_lo, m_hi), b=(b_lo, b_hi), T=T, delay=args.delay)
    t0 = time.perf_counter()
    k = box.k_max(B)
    extra = [f"\nInterior minimum (m {m_lo:g}..{m_hi:g}, b {b_lo:g}..{b_hi:g}, T {T:g}, B {B:g}): certified "
             f"K_lower {k.K_lower:.6g} (K_upper {k.K_upper:.6g} at m = {k.m_worst:.4g}) in "
             f"{1e3 * (time.perf_counter() - t0):.0f} ms;"]
    for g in GRIDS:
        mm, bb = np.meshgrid(np.linspace(m_lo, m_hi, g), np.linspace(b_lo, b_hi, g))
        kg = float(np.min(zwidth.Device(mm.ravel(), bb.ravel(), T, delay=args.delay).k_max(B)))
        bad = kg > k.K_upper and not bool(zwidth.Device(k.m_worst, k.b_worst, T, delay=args.delay).is_stable(
            0.5 * (kg + k.K_upper), B))
        extra.append(f"  {g} x {g} grid: min {kg:.6g}, {'certifies an unstable pair' if bad else 'safe here'} "
                     f"(overestimate {100 * max(0.0, kg - k.K_upper) / k.K_upper:.3g} %)")
    text += "\n".join(extra)
    text += "\n" + _hand_box(args.delay)
    print(text)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
