# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""docs/plant-loop.md's statement of what a hand does to the region, followed as written:
hand damping raises K_max at every B of a grid; a hand's mass alone or stiffness alone
lowers it slightly at some B (the doc's figures, to the digits it prints)."""
from __future__ import annotations

import numpy as np
import pytest

import zwidth

PLANT = (0.12, 0.8, 1e-3)   # m = 0.12 kg, b = 0.8 N s/m, T = 1 ms


def k_max(delay, B, hand=None):
    kw = {} if hand is None else {"hand": hand}
    return float(zwidth.Device(*PLANT, delay=delay, **kw).k_max(B))


def test_hand_mass_or_stiffness_alone_lowers_k_max_somewhere():
    assert round(k_max(0, 0.0), 1) == 1601.8 and round(k_max(0, 0.0, (0.05, 0.0, 0.0)), 1) == 1601.3
    assert round(k_max(0, 200.0)) == 37398 and round(k_max(0, 200.0, (0.0, 0.0, 100.0))) == 37321
    assert round(k_max(1, 100.0), 1) == 7.6 and k_max(1, 100.0, (0.0, 0.0, 100.0)) == 0.0


@pytest.mark.parametrize("delay", [0, 1])
def test_hand_damping_raises_k_max_at_every_b(delay):
    inside = 0
    for B in np.linspace(0.0, 200.0, 21):
        without, damped = k_max(delay, B), k_max(delay, B, (0.0, 5.0, 0.0))
        assert damped > without if without > 0 else damped >= 0, B   # outside the B range: 0
        inside += without > 0
    assert inside >= 10   # the grid covers the B range, not only its outside
