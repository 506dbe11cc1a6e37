# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""The simulator runs the loops the analysis certifies: Tustin's differentiator
([differentiator]), a moving average of the velocity ([average]), and an actuator
(current-loop) lag ([actuator]), alone and with a delay.

Three implementations checked against one another:
- sim.c (the C simulator: the estimators sample by sample, the lag's force exactly inside
  RK4's stages);
- zwidth.sim.closed_loop_matrix (numpy: the loop as one state-space matrix, the plant with
  its lag discretized by the matrix exponential);
- zwidth's general loop (loop.c: the characteristic polynomial, Schur stability) for the
  estimators the analysis covers.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import zwidth
from zwidth import sim as zsim
from zwidth.scene import SceneError

M, B_PLANT, T = 0.1, 3.0, 1e-3


def scene(extra, K, B, duration="0.2 s", x0="1 mm"):
    doc = {"scene": {"duration": duration}, "plant": {"m": f"{M} kg", "b": f"{B_PLANT} N*s/m", "T": f"{T} s"},
           "controller": {"K": f"{K} N/m", "B": f"{B} N*s/m"}, "initial": {"x": x0}}
    doc.update(extra)
    return doc


LOOPS = [
    ({"differentiator": {"kind": "tustin"}}, dict(tustin=True)),
    ({"average": {"samples": 4}}, dict(average=4)),
    ({"differentiator": {"kind": "tustin"}, "average": {"samples": 3}, "delay": {"samples": 2}},
     dict(tustin=True, average=3, delay=2)),
    ({"actuator": {"tau": "2 ms"}}, dict(tau=2e-3)),
    ({"actuator": {"tau": "0.5 ms"}, "delay": {"samples": 1}, "average": {"samples": 2}},
     dict(tau=5e-4, delay=1, average=2)),
]


@pytest.mark.parametrize("extra,loop", LOOPS, ids=["tustin", "average", "tustin+average+delay", "lag", "lag+delay+average"])
def test_simulated_trajectory_is_the_state_space_loop(extra, loop):
    """Sample by sample, the C simulator's position equals the state-space propagation: to
    rounding without the lag; with it, to RK4's error, which falls 16-fold per halving of the
    substep (4th order: the lag's force is exact inside each stage)."""
    K, B = 3000.0, 0.8
    lag = loop.get("tau", 0.0) > 0
    delay = loop.get("delay", 0)
    A = zsim.closed_loop_matrix(M, B_PLANT, 0.0, T, K, B, delay, 0.0, tustin=loop.get("tustin", False),
                                average=loop.get("average", 0), tau=loop.get("tau", 0.0))
    # the state layout of closed_loop_matrix: x, v[, f], x_prev, ...: x_prev = x0 at rest
    z = np.zeros(len(A))
    z[0] = 1e-3
    z[3 if lag else 2] = 1e-3
    xs = np.empty(200)  # 0.2 s at 1 ms
    for k in range(len(xs)):
        xs[k] = z[0]
        z = A @ z
    scale = float(np.abs(xs).max())
    errors = []
    for substeps in ((10, 20, 40) if lag else (None,)):
        doc = scene(extra, K, B)
        if substeps:
            doc["integrator"] = {"substeps": substeps}
        s = zwidth.simulate(doc)[0]
        errors.append(float(np.abs(xs - s.x).max()))
    if not lag:
        assert errors[0] <= 1e-12 * scale, (errors, scale)
        return
    assert errors[-1] <= 1e-8 * scale, (errors, scale)
    for coarse, fine in zip(errors, errors[1:]):
        assert 10 < coarse / fine < 25, errors


@pytest.mark.parametrize("tustin,average,delay", [(True, 0, 0), (False, 4, 0), (True, 3, 2), (False, 16, 1),
                                                  (True, 1, 0)])
def test_state_space_loop_matches_the_certified_loop(tustin, average, delay):
    """closed_loop_matrix's spectral radius against loop.c's (the characteristic polynomial
    of loop.h, built independently), on stable and unstable gains."""
    vf = ("average", average) if average else None
    dev = zwidth.Device(M, B_PLANT, T, delay=delay, velocity_filter=vf,
                        differentiator="tustin" if tustin else "backward")
    for K, B in ((500.0, 0.2), (3000.0, 0.8), (40000.0, 1.0), (1000.0, -0.5)):
        A = zsim.closed_loop_matrix(M, B_PLANT, 0.0, T, K, B, delay, 0.0, tustin=tustin, average=average)
        rho = float(np.abs(np.linalg.eigvals(A)).max())
        assert rho == pytest.approx(float(dev.spectral_radius(K, B)), rel=1e-7, abs=1e-9), (K, B)


def test_actuator_lag_limits_reduce_to_the_ideal_loop_and_cut_stiffness():
    """A lag of 1e-7 s leaves the ideal loop's poles (to 1e-4); a lag of 3 T makes gains the
    ideal loop certifies unstable (the issue's point: a certificate for a loop nobody runs)."""
    K, B = 3000.0, 0.8
    ideal = float(np.abs(np.linalg.eigvals(zsim.closed_loop_matrix(M, B_PLANT, 0.0, T, K, B, 0, 0.0))).max())
    tiny = float(np.abs(np.linalg.eigvals(zsim.closed_loop_matrix(M, B_PLANT, 0.0, T, K, B, 0, 0.0,
                                                                   tau=1e-7))).max())
    assert tiny == pytest.approx(ideal, abs=1e-4)
    k_max = float(zwidth.Device(M, B_PLANT, T).k_max(B))
    K = 0.9 * k_max
    assert zwidth.Device(M, B_PLANT, T).is_stable(K, B)
    lagged = zwidth.simulate(scene({"actuator": {"tau": f"{3 * T} s"}}, K, B, duration="2 s"))[0]
    assert lagged.linear.spectral_radius > 1 and not lagged.linear.stable
    assert lagged.verdict.outcome == "unstable"


def test_scene_keys_are_checked():
    def bad(extra, where):
        with pytest.raises(SceneError) as e:
            zwidth.load_scene(scene(extra, 1000.0, 0.5))
        assert where in str(e.value), str(e.value)
    bad({"differentiator": {"kind": "backward"}}, "differentiator.kind")
    bad({"average": {"samples": 17}}, "average.samples")
    bad({"average": {"samples": 0}}, "average.samples")
    bad({"average": {"samples": 2}, "velocity_filter": {"cutoff": "30 Hz"}}, "average")
    bad({"actuator": {"tau": "0 s"}}, "actuator.tau")
    bad({"actuator": {"tau": "1 ms"}, "friction": {"coulomb": "0.1 N"}}, "actuator")


def test_growth_below_the_tolerance_is_not_stable():
    """Tustin alone at these gains grows by 1.000025 per sample in its Nyquist mode, which a
    short run barely excites: the run settles within the tolerance, but the loop (nothing
    else on) grows, so the verdict is undecided with the duration that would show it, never
    stable."""
    s = zwidth.simulate(scene({"differentiator": {"kind": "tustin"}}, 2000.0, 0.5, duration="4 s"))[0]
    assert not s.linear.stable and s.linear.spectral_radius > 1
    v = s.verdict
    assert v.outcome == "undecided" and v.undecided_because == "too short", v
    rho = s.linear.spectral_radius
    assert v.required_duration >= math.log(1e4) / math.log(rho) * T
