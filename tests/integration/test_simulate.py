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


def test_simulated_plant_runs_the_drives_loop(start_drive):
    """With --delay and --velocity-filter the simulated plant runs that loop, the one the
    gains are certified for: every sampled state equals zwidth's own simulator's run of
    that loop (gains switched at the step the drive took them), and not the ideal loop's."""
    import numpy as np
    import zwidth

    J, b, T, x0 = 85.78e-7, 2.197e-3, 0.02, 0.01
    K, B = 0.05, 1e-4
    d = start_drive("--simulate", "--speed", "20", "--x0", str(x0), "--delay", "1",
                    "--velocity-filter", "average:3", "--differentiator", "tustin")
    with d.client() as c:
        c.set_gains(K, B)
        seen = []
        end = time.monotonic() + 0.4
        while time.monotonic() < end:
            seen.append(state(c))
            time.sleep(0.01)
    moved = [s for s in seen if s[0] != f32(x0)]
    assert len(moved) >= 5, seen
    last = max(s[3] for s in seen) + 1

    def run(extra, switch):
        doc = {"scene": {"duration": f"{(last + 1) * T} s"}, "plant": {"J": f"{J} kg*m^2", "b": f"{b} N*m*s/rad",
                                                                       "T": f"{T} s"},
               "initial": {"x": f"{x0} rad"},
               "schedule": [{"at": "0 s", "K": "0 N*m/rad", "B": "0 N*m*s/rad"},
                            {"at": f"{switch * T} s", "K": f"{f32(K)!r} N*m/rad", "B": f"{f32(B)!r} N*m*s/rad"}],
               "verdict": {"tolerance": "1 rad"}}
        doc.update(extra)
        return zwidth.simulate(doc)[0]

    def matches(sim_run):
        return all(f32(float(sim_run.x[k])) == x and f32(float(sim_run.force[k]) + 0.0) == F
                   for x, _, F, k in seen if k < len(sim_run.x))

    # the gains switched after the last sample still at rest (the force reaches x two steps
    # later with the delay) and before the first that moved
    first = min(k for x, _, _, k in moved)
    rest = max([k for x, _, _, k in seen if x == f32(x0) and k < first], default=0)
    candidates = range(max(1, rest - 2), first + 1)
    loop = {"delay": {"samples": 1}, "average": {"samples": 3}, "differentiator": {"kind": "tustin"}}
    found = [s0 for s0 in candidates if matches(run(loop, s0))]
    assert found, "no switching step reproduces the drive's samples with its loop"
    assert not any(matches(run({}, s0)) for s0 in candidates), \
        "the ideal loop reproduces them too: the drive did not run its own loop"
