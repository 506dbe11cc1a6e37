# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""zwidth.PlantBox with stiffness and a hand (box.h's plant-side parts): never above a grid of
the point limits of zwidth.Device with the same parts, the method chosen, the refusals, and
box_cli's plant-side options.  (The 50-digit reference of the C functions:
tests/py/test_box_hand_reference.py.)"""
from __future__ import annotations

import argparse

import numpy as np
import pytest

import zwidth
from zwidth import box_cli
from zwidth.box import PlantRange

M, BD, T = (0.1, 0.14), (0.5, 0.8), 0.001


def _grid_min(box, B, n=7):
    """min over an n^3 grid (corners in) of the point K_max(B) of the folded plants."""
    Mr, Br, Kr = box.totals
    mm, bb, kk = np.meshgrid(np.linspace(Mr.lo, Mr.hi, n), np.linspace(Br.lo, Br.hi, n),
                             np.linspace(Kr.lo, Kr.hi, n))
    dev = box._device(mm.ravel(), bb.ravel(), kk.ravel())
    return float(np.min(dev.k_max(B)))


@pytest.mark.parametrize("parts,loop", [
    (dict(stiffness=(0.0, 2000.0)), dict(delay=1)),
    (dict(stiffness=800.0), dict()),
    (dict(hand=((0.25, 0.5), (1.0, 3.0), (100.0, 600.0))), dict(delay=1)),
])
def test_k_max_never_above_grid(parts, loop):
    box = zwidth.PlantBox(M, BD, T, **parts, **loop)
    assert box.method == "kharitonov"
    k = box.k_max(5.0)
    g = _grid_min(box, 5.0)
    assert 0 < k.K_lower <= g * (1 + 1e-12)
    assert k.K_lower >= 0.98 * g, (k, g)
    Kr = box.totals[2]
    assert Kr.lo * (1 - 1e-12) <= k.k_worst <= Kr.hi * (1 + 1e-12)  # the fold rounds outward
    assert box.is_stable(0.99 * k.K_lower, 5.0)
    assert not box.is_stable(1.05 * k.K_upper, 5.0)
    print(f"\n{parts}: K_lower / grid min = {k.K_lower / g:.6f} (evals {k.evals})")


def test_hand_without_stiffness_keeps_the_closed_form():
    hand = zwidth.PlantBox(M, BD, T, hand=((0.25, 0.5), (1.0, 3.0), 0.0))
    total = zwidth.PlantBox((0.35, 0.64), (1.5, 3.8), T)
    assert hand.method == total.method == "closed-form"
    a, b = hand.k_max(5.0), total.k_max(5.0)
    assert a.K_lower <= b.K_upper and abs(a.K_lower / b.K_lower - 1) < 1e-9
    assert 0.35 * (1 - 1e-12) <= a.m_worst <= 0.64 * (1 + 1e-12)  # the totals, rounded outward


def test_refusals():
    with pytest.raises(ValueError, match="without stiffness"):
        zwidth.PlantBox(M, BD, T, stiffness=10.0, method="closed-form")
    with pytest.raises(zwidth.ZwidthError, match="lag") as e:
        zwidth.PlantBox(M, BD, T, actuator_tau=1e-4)
    assert e.value.status == "ZW_ERR_ARG" and e.value.parameter == "actuator_tau"
    with pytest.raises(zwidth.ZwidthError, match="lo <= hi") as e:
        zwidth.PlantBox(M, BD, T, stiffness=(2.0, 1.0))
    assert e.value.status == "ZW_ERR_BOX" and e.value.parameter == "stiffness"
    with pytest.raises(zwidth.ZwidthError, match=">= 0") as e:
        zwidth.PlantBox(M, BD, T, hand=(0.0, (-1.0, 1.0), 0.0))
    assert e.value.parameter == "hand b_h"
    with pytest.raises(zwidth.ZwidthError, match="kappa") as e:  # k T^2 / m = 5
        zwidth.PlantBox(M, BD, T, stiffness=5e5)
    assert e.value.status == "ZW_ERR_RANGE"
    with pytest.raises(ValueError, match="hand"):
        zwidth.PlantBox(M, BD, T, hand=(0.1, 0.2))  # type: ignore[arg-type]


def _args(**kw):
    base = dict(m=PlantRange(*M), J=None, b=PlantRange(*BD), T=T, K=None, B=None, delay=1,
                velocity_filter=None, differentiator="backward", delta=None, alpha=None, beta=None,
                stiffness=None, hand=None, actuator_tau=None, region="exact")
    base.update(kw)
    return argparse.Namespace(**base)


def test_box_cli_parts():
    assert box_cli.parse_hand("0.2:0.5,1,100:600") == (PlantRange(0.2, 0.5), 1.0, PlantRange(100.0, 600.0))
    with pytest.raises(argparse.ArgumentTypeError):
        box_cli.parse_hand("1,2")
    box = box_cli._box(_args(stiffness="0:2000", hand="0.25:0.5,1:3,100:600"))
    assert box.stiffness == PlantRange(0.0, 2000.0) and box.hand[2] == PlantRange(100.0, 600.0)
    k = box.k_max(5.0)
    out = box_cli.cmd_check(_args(K=0.99 * k.K_lower, B=5.0), box)
    assert out.data["stable"] and "k" in out.data["K_max"]["worst_plant"]
    assert any("hand: m_h in [0.25, 0.5]" in line for line in out.lines)
    assert box_cli._summary(box)["stiffness"] == [0.0, 2000.0]
    # a range in a part alone makes the plant a box
    point = _args(m=0.1, b=0.5)
    assert not box_cli.has_range(point)
    assert box_cli.has_range(_args(m=0.1, b=0.5, stiffness=PlantRange(0.0, 10.0)))
    assert box_cli.has_range(_args(m=0.1, b=0.5, hand=box_cli.parse_hand("0.2:0.5,1,100")))
    assert not box_cli.has_range(_args(m=0.1, b=0.5, hand=(0.2, 1.0, 100.0)))


def test_cli_parts_over_a_range(capsys):
    """cli.main takes --stiffness and --hand ranges (the box path) and refuses a lag with them."""
    import json

    from zwidth import cli
    argv = ["limits", "--m", "0.1", "--b", "0.5", "--T", "0.001", "--delay", "1", "--stiffness", "0:2000", "--json"]
    assert cli.main(argv) == 0
    data = json.loads(capsys.readouterr().out)
    kmmax = data["K_mmax"]
    assert data["box"]["stiffness"] == [0.0, 2000.0]
    # never above the point K_mmax of either end of the spring's range
    for k in (0.0, 2000.0):
        point = zwidth.Device(0.1, 0.5, 0.001, delay=1, stiffness=k).extremes().K_mmax
        assert 0 < kmmax <= float(point) * (1 + 1e-12)
    # a point hand stays on the point path; a range in one of its entries makes a box
    assert cli.main(["check", "--m", "0.1", "--b", "0.5", "--T", "0.001", "--hand", "0.05,1,100",
                     "--K", "2000", "--B", "5", "--delay", "0", "--json"]) == 0
    assert "Plant box" not in capsys.readouterr().out
    with pytest.raises(SystemExit):
        cli.main(["limits", "--m", "0.1", "--b", "0.5", "--T", "0.001", "--stiffness", "0:2000",
                  "--actuator-tau", "1e-3", "--delay", "0"])
    assert "certified without an actuator lag" in capsys.readouterr().err
