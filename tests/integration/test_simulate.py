# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zwidth-drive --simulate: the plant under the active gains, seen through the state
registers."""
from __future__ import annotations

import struct
import time

from zwmb_harness import E, f32, words_float, drive, start_drive  # noqa: F401 (fixtures)


def state(c):
    w = c.read(E["ZW_REG_STATE_X"], 8)
    x, v, F = words_float(w[:6])
    return x, v, F, w[6] << 16 | w[7]


def test_simulated_plant_follows_the_gains(start_drive):
    d = start_drive("--simulate", "--speed", "20", "--x0", "0.01")
    with d.client() as c:
        x, v, F, step = state(c)
        assert x == f32(0.01) and v == 0.0 and F == 0.0  # output off: the plant sits still
        t0 = time.monotonic()
        time.sleep(0.25)
        x1, _, _, step1 = state(c)
        rate = (step1 - step) / (time.monotonic() - t0)
        assert 600 < rate < 1400, rate  # 20 x real time at T = 0.02 s: 1000 steps per second
        assert x1 == f32(0.01)

        c.set_gains(0.2, -5e-4)
        seen = []
        end = time.monotonic() + 0.5
        while time.monotonic() < end:
            seen.append(state(c))
            time.sleep(0.01)
        # every sample obeys F = -K x - B v (float registers) with the gains of its step:
        # the new ones, or the old (0, 0) for a sample taken before the write
        def law(K, B, x, v, F):
            return abs(F - (-K * x - B * v)) <= 1e-6 * (abs(F) + abs(K * x) + abs(B * v)) + 1e-12
        for x, v, F, _ in seen:
            assert law(0.2, -5e-4, x, v, F) or (F == 0.0 and x == f32(0.01)), (x, v, F)
        assert sum(F != 0.0 for _, _, F, _ in seen) >= len(seen) // 2
        assert [s[3] for s in seen] == sorted(s[3] for s in seen)  # steps only go up
        x_end = state(c)[0]
        assert abs(x_end) < 1e-4, x_end  # 500 steps at spectral radius 0.77: settled
