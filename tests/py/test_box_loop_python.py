# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""zwidth.PlantBox with the loop a drive runs (delay, filters, Tustin; csrc/src/box_loop.c)
and the CLI's plant ranges with --delay: never above a dense grid of the point limits,
tight against it, the ideal loop through the general path agreeing with the closed form,
and the exit codes.  (The 50-digit reference of the same C functions:
tests/py/test_box_loop_reference.py.)"""
from __future__ import annotations

import numpy as np
import pytest

import zwidth
from test_cli import run, run_json

J, BD, T = (1.0e-5, 1.4e-5), (2.0e-3, 2.4e-3), 0.02


def _grid_min(box, B, n=41):
    """min over an n x n grid (corners in) of the point K_max(B) with the box's loop."""
    mm, bb = np.meshgrid(np.linspace(box.m.lo, box.m.hi, n), np.linspace(box.b.lo, box.b.hi, n))
    dev = box._device(mm.ravel(), bb.ravel())
    return float(np.min(dev.k_max(B)))


@pytest.mark.parametrize("loop,B", [
    (dict(delay=1), 1e-4),
    (dict(delay=1, velocity_filter=("lowpass", 5.0)), 1e-4),
    (dict(delay=2, velocity_filter=("average", 2)), 2e-4),
    (dict(differentiator="tustin"), -1e-4),
])
def test_k_max_never_above_grid_and_tight(loop, B):
    box = zwidth.PlantBox.rotary_box(J, BD, T, **loop)
    assert box.method == "kharitonov"
    k = box.k_max(B)
    g = _grid_min(box, B)
    # the grid's point values are certified themselves (a few ulps below the truth): the box's
    # bound may meet them, never exceed them by more than that band
    assert k.K_lower <= g * (1 + 1e-12)
    assert k.K_lower >= g * (1 - 2e-4), (k, g)
    assert k.K_lower <= k.K_upper
    assert J[0] <= k.m_worst <= J[1] and BD[0] <= k.b_worst <= BD[1]
    print(f"\n{loop}: K_lower / grid min = {k.K_lower / g:.6f} (evals {k.evals})")


def test_ideal_loop_both_paths_agree():
    closed = zwidth.PlantBox.rotary_box(J, BD, T)
    general = zwidth.PlantBox.rotary_box(J, BD, T, method="kharitonov")
    assert closed.method == "closed-form"
    for B in (0.0, 1e-4, 1e-3):
        a, b = closed.k_max(B), general.k_max(B)
        assert b.K_lower <= a.K_upper
        assert abs(b.K_lower / a.K_lower - 1) < 2e-4


def test_verdicts_b_range_extremes():
    box = zwidth.PlantBox.rotary_box(J, BD, T, delay=1)
    k = box.k_max(1e-4)
    assert box.is_stable(0.99 * k.K_lower, 1e-4)
    v = box.verdict(1.05 * k.K_upper, 1e-4)
    assert not v.stable and v.decided
    assert not zwidth.Device.rotary(v.m_worst, v.b_worst, T, delay=1).is_stable(1.05 * k.K_upper, 1e-4)
    r = box.b_range(0.05)
    assert r.nonempty and r.lo < 1e-4 < r.hi
    for B in np.linspace(r.lo, r.hi, 5):
        assert box.is_stable(0.05, float(B))
    x = box.extremes()
    assert x.K_mmax >= k.K_lower and x.K_mmax <= x.K_mmax_upper
    assert box.is_stable(0.999 * x.K_mmax, x.B_at)


def test_errors():
    with pytest.raises(zwidth.ZwidthError):
        zwidth.PlantBox.rotary_box(J, BD, T, delay=9)
    with pytest.raises(ValueError):
        zwidth.PlantBox.rotary_box(J, BD, T, delay=1, method="closed-form")
    with pytest.raises(zwidth.ZwidthError) as exc:
        zwidth.PlantBox.rotary_box((2e-5, 1e-5), BD, T, delay=1)
    assert exc.value.status == "ZW_ERR_BOX"


BOX = ("--J", "1e-5:1.4e-5", "--b", "2.0e-3:2.4e-3", "--T", "0.02", "--delay", "1")


def test_cli_check_with_delay():
    out = run_json("check", *BOX, "--K", "0.05", "--B", "1e-4")
    assert out["verdict"] == "stable" and out["box"]["method"] == "kharitonov"
    assert "delay" in out["box"]["loop"]
    box = zwidth.PlantBox.rotary_box(J, BD, T, delay=1)
    assert out["K_max"]["certified"] == box.k_max(1e-4).K_lower
    bad = run_json("check", *BOX, "--K", "0.2", "--B", "1e-4", code=1)
    assert bad["verdict"] == "unstable"
    w = bad["worst_plant"]
    assert not zwidth.Device.rotary(w["J"], w["b"], T, delay=1).is_stable(0.2, 1e-4)


def test_cli_limits_with_delay():
    r = run("limits", *BOX)
    assert r.returncode == 0 and "1 sample delay" in r.stdout and "K_mmax" in r.stdout


def test_corners_are_not_enough_with_delay():
    """With one sample of delay K_max(B) can have an interior minimum in m too (b = 2.2e-3,
    T = 0.02, B = 7.5e-4: near J = 5.5e-5): a K between the corners' least K_max and the
    worst plant's passes every corner yet is unstable there; the box never certifies it."""
    box = zwidth.PlantBox.rotary_box((3e-5, 1.5e-4), (2.1e-3, 2.3e-3), T, delay=1)
    B = 7.5e-4
    k = box.k_max(B)
    corners = min(float(d.k_max(B)) for d in box.corners())
    assert k.K_upper < corners * (1 - 1e-3)
    assert box.m.lo < k.m_worst < box.m.hi
    K = 0.5 * (corners + k.K_upper)
    assert all(bool(d.is_stable(K, B)) for d in box.corners())
    assert not bool(zwidth.Device.rotary(k.m_worst, k.b_worst, T, delay=1).is_stable(K, B))
    assert not box.is_stable(K, B)
    assert k.K_lower <= k.K_upper and box.is_stable(k.K_lower, B)
