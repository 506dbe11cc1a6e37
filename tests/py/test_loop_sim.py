# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Simulation of scenes whose effects are linear (a delay, a velocity low-pass): the
analytic verdict of the loop simulated sits next to the simulated one, they agree on
random scenes away from the boundary, and the ideal loop's contrary verdict is a warning.

The reference for "away from the boundary" is the spectral radius of the polynomial built
in test_loop_python.ref_poly (mpmath) with the simulator's own pole.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

import zwidth
from zwidth import _core
from test_loop_python import ref_radius


def scene(m, b, T, K, B, *, delay=None, cutoff=None, duration=None, cases=None):
    doc = {
        "scene": {"name": "loop", "duration": f"{duration or 2000 * T} s"},
        "plant": {"m": f"{m!r} kg", "b": f"{b!r} N*s/m", "T": f"{T!r} s"},
        "controller": {"K": f"{K!r} N/m", "B": f"{B!r} N*s/m"},
        "reference": {"from": "0 m", "to": "0.01 m", "at": "0 s"},
    }
    if delay is not None:
        doc["delay"] = {"samples": delay}
    if cutoff is not None:
        doc["velocity_filter"] = {"cutoff": f"{cutoff!r} Hz"}
    if cases is not None:
        doc["case"] = cases
    return doc


def test_new_user_case_warns():
    sims = zwidth.simulate(scene(0.12, 0.8, 1e-3, 5e4, 50.0, delay=1, duration=0.5))
    s = sims[0]
    assert sims.scene.linear and not sims.scene.ideal
    assert s.verdict.outcome == "unstable"
    assert isinstance(s.analytic, zwidth.LoopVerdict) and not s.analytic.stable and s.agrees is True
    assert s.ideal is not None and bool(s.ideal.stable)
    assert "ideal loop" in s.note and "1 sample delay" in s.note and "unstable" in s.note


def test_simulator_pole_is_the_loops():
    sim = _core.Simulator({"m": 0.1, "b": 1.0, "T": 1e-3, "K": 100.0, "B": 1.0, "effects": 16, "cutoff_hz": 30.0})
    assert sim.filter_pole == zwidth.Device(0.1, 1.0, 1e-3, velocity_filter=("lowpass", 30.0)).filter_pole
    assert _core.Simulator({"m": 0.1, "b": 1.0, "T": 1e-3, "K": 100.0, "B": 1.0, "effects": 0}).filter_pole == 0.0


def test_random_linear_scenes_agree():
    rng = np.random.default_rng(2026)
    compared = 0
    checked = 0
    while checked < 40:
        m = float(10 ** rng.uniform(-2, 0))
        T = float(10 ** rng.uniform(-4, -2.5))
        delta = float(10 ** rng.uniform(-2, 0.5))
        b = delta * m / T
        delay = int(rng.integers(1, 4))
        cutoff = None if rng.random() < 0.3 else float(rng.uniform(0.02, 0.4) / T)
        alpha = float(rng.uniform(0.0, 0.8))
        beta = float(rng.uniform(-0.5 * delta, 0.6))
        K, B = alpha * m / T ** 2, beta * m / T
        pole = 0.0 if cutoff is None else math.exp(-2 * math.pi * cutoff * T)
        r = float(ref_radius(b * T / m, K * T ** 2 / m, B * T / m, delay=delay, pole=pole))
        if abs(r - 1) < 0.01 or r < 0.2:
            continue      # near the boundary the run would need to be long; far inside it settles at once
        checked += 1
        # long enough for the envelope to move by e^4 over the judged half
        samples = int(min(200_000, max(2000, 16 / abs(math.log(r)))))
        sims = zwidth.simulate(scene(m, b, T, K, B, delay=delay, cutoff=cutoff, duration=samples * T))
        s = sims[0]
        assert s.analytic is not None and s.device is not None
        assert s.device.loop.delay == delay
        assert bool(s.analytic.stable) == (r < 1), (r, s.analytic)
        if s.verdict.outcome != "undecided":
            compared += 1
            assert s.agrees, (m, b, T, K, B, delay, cutoff, r, s.verdict)
    assert compared >= 35


def test_long_delay_has_no_analytic_verdict_but_says_why():
    s = zwidth.simulate(scene(0.1, 1.0, 1e-3, 100.0, 1.0, delay=12, duration=0.2))[0]
    assert s.analytic is None and s.agrees is None
    assert "12 samples" in s.note


def test_nonlinear_scene_unchanged():
    doc = scene(0.1, 1.0, 1e-3, 100.0, 1.0, delay=1, duration=0.2)
    doc["saturation"] = {"force_max": "5 N"}
    s = zwidth.simulate(doc)[0]
    assert s.analytic is None and s.note is None and not zwidth.simulate(doc).scene.linear


def test_cli_prints_both_verdicts(tmp_path):
    import subprocess
    import sys
    from pathlib import Path

    path = tmp_path / "late.toml"
    path.write_text(
        '[scene]\nname = "late"\nduration = "0.5 s"\n'
        '[plant]\nm = "0.12 kg"\nb = "0.8 N*s/m"\nT = "1 ms"\n'
        '[controller]\nK = "50000 N/m"\nB = "50 N*s/m"\n'
        '[reference]\nfrom = "0 m"\nto = "0.01 m"\nat = "0 s"\n'
        '[delay]\nsamples = 1\n')
    exe = Path(sys.executable).parent / "zwidth"
    r = subprocess.run([str(exe), "simulate", str(path), "--no-progress"], capture_output=True, text=True)
    assert r.returncode == 1, r.stderr
    assert "exact region" in r.stdout and "ideal loop" in r.stdout and "warning:" in r.stdout
    assert "loop analysed: 1 sample delay" in r.stdout
    r = subprocess.run([str(exe), "simulate", str(path), "--no-progress", "--json"], capture_output=True, text=True)
    case = json.loads(r.stdout)["cases"][0]
    assert case["analytic"]["verdict"] == "unstable" and case["analytic"]["ideal_loop"]["verdict"] == "stable"
    assert case["analytic"]["legacy_stable"] is None and case["agrees"] is True and case["note"]
    assert case["analytic"]["loop"]["delay"] == 1
