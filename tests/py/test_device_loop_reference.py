# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Real-unit limits of the drive's loop (device_loop.h through zwidth.Device) against the
independent state-space reference of loop_reference.py at 80 digits.

The plant and gains are normalized here exactly (mpmath: delta = b T / m, alpha =
K T^2 / m, beta = B T / m of the binary64 inputs), so the rounding of the library's own
conversions is what is under test: K_max(B) never above the true sup at the exact beta,
every B of the certified range stable at the exact alpha, and both tight.
"""
from __future__ import annotations

import numpy as np
import pytest
from mpmath import mp, mpf

import loop_reference as lr
import zwidth

LOOPS = [
    dict(delay=1),
    dict(delay=2),
    dict(delay=1, velocity_filter=("lowpass", "f")),   # f: a cut-off drawn per plant
    dict(delay=0, velocity_filter=("average", 3)),
    dict(delay=1, differentiator="tustin"),
]


def exact(x):
    return mpf(float(x))


def stable(parts, m, T, K, B):
    with mp.workdps(lr.DPS):
        alpha = exact(K) * exact(T) ** 2 / exact(m)
        beta = exact(B) * exact(T) / exact(m)
        return lr.schur_stable(lr.loop_poly(parts, alpha, beta))[0]


def cases(seed, n):
    rng = np.random.default_rng(seed)
    for i in range(n):
        loop = dict(LOOPS[i % len(LOOPS)])
        m = float(10 ** rng.uniform(-2, 0))
        T = float(10 ** rng.uniform(-4, -2))
        b = float(10 ** rng.uniform(-1.5, 0.5)) * m / T
        if "velocity_filter" in loop and loop["velocity_filter"][1] == "f":
            loop["velocity_filter"] = ("lowpass", float(rng.uniform(0.03, 0.4) / T))
        yield m, b, T, loop, rng


def reference_parts(dev, m, b, T, loop):
    vf = loop.get("velocity_filter")
    kw = dict(delay=loop.get("delay", 0), differentiator=loop.get("differentiator", "backward"))
    if vf is not None and vf[0] == "lowpass":
        kw.update(filter="lowpass", pole=float(dev.filter_pole))  # the pole the drive applies
    elif vf is not None:
        kw.update(filter="average", average=vf[1])
    with mp.workdps(lr.DPS):
        delta = exact(b) * exact(T) / exact(m)
    return lr.loop_parts(delta, **kw)


@pytest.mark.parametrize("seed", [1, 2])
def test_k_max_in_real_units_is_certified_and_tight(seed):
    checked = 0
    for m, b, T, loop, rng in cases(seed, 10):
        dev = zwidth.Device(m, b, T, **loop)
        parts = reference_parts(dev, m, b, T, loop)
        ex = dev.extremes()
        for B in (0.0, float(rng.uniform(0.05, 0.9)) * ex.B_mmax, float(rng.uniform(-0.9, -0.05)) * b):
            K = float(dev.k_max(B))
            if K == 0.0:
                continue
            checked += 1
            for f in (1.0, 0.999, 0.5, 1e-3):  # (0, K_max] sampled, K_max itself included
                assert stable(parts, m, T, K * f, B), (m, b, T, loop, B, K, f)
            assert not stable(parts, m, T, K * (1 + 1e-4), B), (m, b, T, loop, B, K)
    assert checked >= 15


@pytest.mark.parametrize("seed", [3])
def test_b_range_in_real_units_is_certified_and_tight(seed):
    checked = 0
    for m, b, T, loop, rng in cases(seed, 10):
        dev = zwidth.Device(m, b, T, **loop)
        parts = reference_parts(dev, m, b, T, loop)
        K = float(rng.uniform(0.1, 0.9)) * float(dev.k_max(0.0 if loop.get("differentiator") != "tustin"
                                                             else 0.1 * b))
        if K == 0.0:
            continue
        r = dev.b_range(K)
        if not r.nonempty:
            continue
        checked += 1
        w = r.hi - r.lo
        for B in (r.lo, r.hi, *np.linspace(r.lo, r.hi, 7)[1:-1]):
            assert stable(parts, m, T, K, float(B)), (m, b, T, loop, K, B, r)
        assert not stable(parts, m, T, K, r.hi + 1e-4 * w) and not stable(parts, m, T, K, r.lo - 1e-4 * w)
    assert checked >= 6


def test_extremes_in_real_units_never_beyond():
    for m, b, T, loop, rng in cases(5, 5):
        dev = zwidth.Device(m, b, T, **loop)
        parts = reference_parts(dev, m, b, T, loop)
        ex = dev.extremes()
        assert ex.K_p_max == float(dev.k_max(0.0))
        assert stable(parts, m, T, ex.K_mmax * (1 - 1e-9), ex.B_at_K_mmax), (m, b, T, loop)
        assert -b <= ex.B_mmin < ex.B_mmax
        # just inside the B range as K -> 0+: stable
        K_small = 1e-6 * ex.K_mmax
        assert stable(parts, m, T, K_small, ex.B_mmax * (1 - 1e-3) if ex.B_mmax > 0 else 0.5 * ex.B_mmax)
