# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""Simulated verdicts a user can trust (issue 14; findings of
shared/reviews/2026-12-sim-review.md, each a test that failed on the code before the fix):

1. a scene that never excites the loop is "undecided: nothing excites the loop" (exit 5),
   not "stable" (exit 0);
2. Coulomb friction and stiction keep RK4's 4th order: each stop located inside its
   substep, against a reference that solves every piece and every stop in closed form
   (mpmath, sim_reference.friction_trajectory); negligible friction leaves the paper's P8
   unstable;
3. a verdict window shorter than the loop's slowest oscillation is "undecided: run at least
   N s", N from the loop's poles (and the run of that length decides, rightly);
4. every simulated verdict comes with the linear part's verdict, and one line naming the
   effect where they differ; the linear part of a plant held by a stiff hand against an
   independent discretization (scipy expm, numpy eigenvalues);
5. quantization: the verdict counts the limit cycle in counts, whatever the tolerance;
6. smaller: no subnormal velocities in a settled quantized run, a hand too stiff is
   reported under hand.stiffness, a run's memory is stated and bounded (no second copy), the
   knob scenes' comment states the hand's real effect.
"""
from __future__ import annotations

import json
import math
import re
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import sim_reference as R
import zwidth
from test_cli import run
from zwidth import _core
from zwidth import sim as zsim

REPO = Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"


def plant(m="0.1 kg", b="30 N*s/m", T="0.01 s"):
    return {"m": m, "b": b, "T": T}


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


# ---------------------------------------------------------------------------------------
# 1. Nothing excites the loop
# ---------------------------------------------------------------------------------------

UNEXCITED = """
[scene]
duration = "1 s"
[plant]
m = "0.1 kg"
b = "30 N*s/m"
T = "1 ms"
[controller]
K = "500000 N/m"
B = "0 N*s/m"
"""


def test_unexcited_scene_is_undecided_with_its_own_exit_status(tmp_path):
    """Review 3/issue 1: K = 500 kN/m (spectral radius above 1) at rest at its equilibrium
    printed "stable" and exited 0."""
    sims = zwidth.simulate(UNEXCITED)
    v = sims[0].verdict
    assert v.outcome == "undecided" and v.undecided_because == "unexcited"
    assert v.reason.startswith("nothing excites the loop")
    assert not sims[0].linear.stable and not sims[0].analytic.stable
    r = run("simulate", str(write(tmp_path, "rest.toml", UNEXCITED)), "--no-progress")
    assert r.returncode == 5, (r.returncode, r.stdout, r.stderr)
    assert "nothing excites the loop" in r.stdout
    # The same scene with a step: decided, unstable, exit 1.
    stepped = UNEXCITED + '[reference]\nto = "1 mm"\n'
    r = run("simulate", str(write(tmp_path, "step.toml", stepped)), "--no-progress")
    assert r.returncode == 1 and "nothing excites" not in r.stdout


def test_motion_inside_the_tolerance_is_not_stable():
    """A run whose whole motion stays inside the verdict tolerance shows no settling (the
    loop may be growing inside it): undecided, "below tolerance", exit 5; with a tolerance
    the motion crossed, the same run decides."""
    doc = {"scene": {"duration": "1 s"}, "plant": plant(T="1 ms"),
           "controller": {"K": "2000 N/m", "B": "1 N*s/m"}, "reference": {"to": "2 mm"},
           "verdict": {"tolerance": "5 mm"}}
    v = zwidth.simulate(doc)[0].verdict
    assert v.outcome == "undecided" and v.undecided_because == "below tolerance", v
    assert v.reason.startswith("never moved more than the tolerance")
    doc["verdict"]["tolerance"] = "0.01 mm"
    assert zwidth.simulate(doc)[0].verdict.outcome == "stable"
    # the C criterion alone: a record inside the tolerance is UNDECIDED, never STABLE
    x = 1e-9 * np.minimum(np.arange(400.0), 100.0)
    assert _core.sim_judge(x, 50, 4, 1e-6)["outcome"] == "undecided"
    assert _core.sim_judge(x, 50, 4, 1e-8)["outcome"] == "stable"


def test_unexcited_rotary_unit_slip_is_undecided():
    """The review's unit slip ("0.4 N*m/deg", 57x the intended stiffness) at rest."""
    doc = {"scene": {"duration": "2 s"}, "plant": {"J": "85.78e-7 kg*m^2", "b": "2.197e-3 N*m*s/rad", "T": "0.02 s"},
           "controller": {"K": "0.4 N*m/deg", "B": "0 N*m*s/rad"}}
    s = zwidth.simulate(doc)[0]
    assert s.verdict.outcome == "undecided" and not s.linear.stable


def test_held_by_stiction_is_not_stable():
    """A plant stiction holds never moves: the run says nothing about the loop either."""
    doc = {"scene": {"duration": "1 s"}, "plant": plant(T="1 ms"),
           "controller": {"K": "2000 N/m", "B": "1 N*s/m"}, "reference": {"to": "2 mm"},
           "friction": {"coulomb": "3 N", "stiction": "5 N"}}
    s = zwidth.simulate(doc)[0]
    assert np.ptp(s.x) == 0.0 and s.verdict.outcome == "undecided"


# ---------------------------------------------------------------------------------------
# 2. Friction at the promised order
# ---------------------------------------------------------------------------------------

FRICTION = dict(m=0.1, b=2.0, T=1e-3, K=2000.0, B=1.0, x_init=0.0, v_init=0.0, x_eq_before=0.0,
                x_eq_after=0.01, t_step=0.0, coulomb=3.0, stiction=5.0)


def friction_run(scene, substeps, n):
    p = dict(scene, effects=_core.SIM_EFFECTS["friction"], substeps=substeps)
    return _core.Simulator(p).run(n, ["x", "v"])


@pytest.mark.parametrize("scene", [FRICTION, dict(FRICTION, b=20.0, coulomb=1.0, stiction=1.0),
                                   dict(FRICTION, v_init=0.3, x_eq_after=0.0)],
                         ids=["review", "damped-no-stiction", "sliding-start"])
def test_friction_converges_at_fourth_order(scene):
    """Max |x - x_ref| over 100 samples with stops inside substeps, against the closed-form
    reference (every stop solved exactly at 40 digits), for 1 .. 16 substeps: each doubling
    divides the error by 16 (>= 12, order >= 3.6) while it is above rounding.  The stop at
    the substep's end divided it by 2 (first order)."""
    n = 100
    xs, _, stops = R.friction_trajectory(scene, n)
    assert stops >= 1
    xr = np.array([float(x) for x in xs])
    scale = float(np.abs(xr).max())
    errs = [float(np.abs(friction_run(scene, s, n)["x"] - xr).max()) / scale for s in (1, 2, 4, 8, 16)]
    ratios = [a / b for a, b in zip(errs, errs[1:]) if b > 1e-14]
    assert len(ratios) >= 3, errs
    assert all(q >= 12.0 for q in ratios), (errs, ratios)
    print(f"\n[friction convergence] rel err {' '.join(f'{e:.2e}' for e in errs)}; ratios {R.fmt_ratio(ratios)}")


def test_friction_default_substeps_accurate():
    """The review's friction scene with the loader's default substeps: 4.9e-5 m max error
    (0.3 % of the swing) before; now within 1e-9 of the swing."""
    doc = {"scene": {"duration": "0.1 s"}, "plant": plant(b="2 N*s/m", T="1 ms"),
           "controller": {"K": "2000 N/m", "B": "1 N*s/m"}, "reference": {"to": "10 mm"},
           "friction": {"coulomb": "3 N", "stiction": "5 N"}}
    s = zwidth.simulate(doc)[0]
    xs, _, _ = R.friction_trajectory(s.params, len(s.x))
    xr = np.array([float(x) for x in xs])
    assert np.abs(s.x - xr).max() <= 1e-9 * np.ptp(xr), np.abs(s.x - xr).max()


def test_negligible_friction_leaves_p8_unstable():
    """Review 3c: P8 (spectral radius 1.0253) with 1e-9 N of friction was "stable" at the
    default 60 substeps: every reversal (each sample) lost one substep of acceleration."""
    doc = {"scene": {"duration": "2 s"}, "plant": plant(), "controller": {"alpha": 0.25, "beta": 7.5},
           "reference": {"to": "1 m"}, "friction": {"coulomb": "1e-9 N"}}
    s = zwidth.simulate(doc)[0]
    assert s.verdict.outcome == "unstable"
    assert s.verdict.growth == pytest.approx(1.0253, rel=2e-3)
    assert not s.linear.stable and s.explanation is None     # both unstable: nothing to explain
    # and the trajectory is the linear loop's (friction 1e-9 N against forces of ~1e3 N)
    lin = zwidth.simulate({k: v for k, v in doc.items() if k != "friction"})[0]
    # (RK4 at 60 substeps: ~1e-5 of the swing; the lost substeps of the old code: 3 % at x[5])
    assert np.abs(s.x[:100] - lin.x[:100]).max() <= 1e-4 * np.abs(lin.x[:100]).max()


def test_stick_slip_scene_matches_the_reviews_event_located_reference():
    """Review 5c: the stick-slip scene's final position, zwidth 24.1264 mm against the
    reviewer's event-located DOP853 24.1220 mm (stops and break-aways of a moving hand
    located in time).  Now 24.1220 mm, and independent of the substeps to 1e-12 m."""
    case = zwidth.load_scene(SCENES / "stick-slip.toml").cases[0]
    finals = [_core.Simulator(dict(case.params, substeps=n)).run(case.samples, ["x"])["x"][-1] for n in (10, 100)]
    assert finals[0] == pytest.approx(24.1220e-3, abs=1e-7)
    assert abs(finals[0] - finals[1]) <= 1e-12


# ---------------------------------------------------------------------------------------
# 3. Runs too short for the slowest mode
# ---------------------------------------------------------------------------------------

SLOW = {"plant": plant(b="0.1 N*s/m", T="1 ms"), "controller": {"K": "10 N/m", "B": "0 N*s/m"},
        "reference": {"to": "1 mm"}}


def test_window_shorter_than_the_oscillation_is_undecided():
    """Review 3b: a stable loop (radius 0.99953, period 0.63 s) run 1 s was "unstable", exit
    1, "did not shrink from 0.00378 to 0.000941".  Now: undecided, run at least N s, N from
    the poles; a run of N s decides "stable"."""
    s = zwidth.simulate({"scene": {"duration": "1 s"}, **SLOW})[0]
    v = s.verdict
    assert v.outcome == "undecided" and v.undecided_because == "too short"
    assert v.reason.startswith(f"run at least {v.required_duration:g} s")
    # Independent: the poles of the mpmath characteristic polynomial (sim_reference).
    delta, alpha, beta = R.normalized(0.1, 0.1, 1e-3, 10.0, 0.0)
    roots = [complex(z) for z in __import__("mpmath").polyroots(R.char_poly(delta, alpha, beta), maxsteps=200,
                                                                extraprec=200)]
    rho = max(abs(z) for z in roots)
    period = max(2 * math.pi / abs(np.angle(z)) for z in roots if abs(np.angle(z)) > 1e-9) * 1e-3
    assert period == pytest.approx(0.628, rel=1e-2)
    decay = math.log(1e-4) / math.log(rho) * 1e-3 / (1 - 1 / 16)
    assert v.required_duration >= max(16 * period, decay)
    assert v.required_duration <= 1.1 * max(16 * period, decay)
    longer = zwidth.simulate({"scene": {"duration": f"{v.required_duration} s"}, **SLOW})[0]
    assert longer.verdict.outcome == "stable" and longer.linear.stable


def test_unstable_slow_loop_too_short_is_undecided_not_stable():
    """A slowly growing oscillation seen through windows shorter than its period."""
    doc = {"scene": {"duration": "1 s"}, "plant": plant(b="0.1 N*s/m", T="1 ms"),
           "controller": {"K": "10 N/m", "B": "-0.2 N*s/m"}, "reference": {"to": "1 mm"}}
    s = zwidth.simulate(doc)[0]
    assert not s.linear.stable and s.verdict.outcome != "stable"


def test_schedule_scene_too_short_for_its_last_segment_is_undecided():
    """Review 3b, the silent nonlinear case: a 3-segment schedule whose last segment is
    stable (period 0.2 s) judged in 31 ms windows was "unstable"."""
    doc = {"scene": {"duration": "0.5 s"}, "plant": plant(b="2 N*s/m", T="1 ms"), "reference": {"to": "10 mm"},
           "schedule": [{"at": "0 s", "K": "2000 N/m", "B": "1 N*s/m"},
                        {"at": "0.1 s", "K": "500 N/m", "B": "0.5 N*s/m"},
                        {"at": "0.2505 s", "K": "100 N/m", "B": "0.1 N*s/m"}]}
    s = zwidth.simulate(doc)[0]
    assert s.linear.stable and s.linear.piece.startswith("the last segment")
    assert s.verdict.outcome == "undecided" and s.verdict.undecided_because == "too short"
    longer = zwidth.simulate(doc, duration=s.verdict.required_duration)[0]
    assert longer.verdict.outcome == "stable"


# ---------------------------------------------------------------------------------------
# 4. The linear part beside every verdict
# ---------------------------------------------------------------------------------------


def scipy_poles(M, c, k, T, K, B):
    """Closed-loop poles of the plant M x'' + c x' + k x = u under the ZOH (scipy's
    cont2discrete) with u = -K x - B (x - x_prev)/T: an independent derivation."""
    from scipy.signal import cont2discrete

    A = np.array([[0.0, 1.0], [-k / M, -c / M]])
    Bc = np.array([[0.0], [1.0 / M]])
    Ad, Bd, *_ = cont2discrete((A, Bc, np.eye(2), np.zeros((2, 1))), T, method="zoh")
    # state (x, v, x_prev)
    gain = np.array([-K - B / T, 0.0, B / T])
    Acl = np.zeros((3, 3))
    Acl[:2, :2] = Ad
    Acl[:2] += Bd @ gain[None, :]
    Acl[2, 0] = 1.0
    return np.linalg.eigvals(Acl)


@pytest.mark.parametrize("name", ["knob-exact", "knob-legacy", "stick-slip", "wall-hand", "paper-fig15"])
def test_every_scene_prints_its_linear_part(name):
    r = run("simulate", str(SCENES / f"{name}.toml"), "--json", "--no-progress")
    obj = json.loads(r.stdout)
    for case in obj["cases"]:
        lp = case["linear_part"]
        assert lp["verdict"] in ("stable", "unstable", "marginal") and lp["spectral_radius"] > 0
    text = run("simulate", str(SCENES / f"{name}.toml"), "--no-progress").stdout
    assert ("linear part" in text) or ("exact region" in text)


def test_knob_linear_part_with_the_hand_against_scipy():
    """The knob's end wall held by the scene's hand (mass, damping and stiffness): the
    review's 0.765 for the 1e-6 kg m^2 hand; the scene comment said 0.999 for 2e-6."""
    s = zwidth.simulate(SCENES / "knob-exact.toml")[0]
    lp = s.linear
    assert lp.piece == "the end walls" and lp.k == pytest.approx(0.1)
    J, b, T = 85.78e-7 + 1e-6, 2.197e-3 + 1e-4, 0.02
    ref = float(np.abs(scipy_poles(J, b, 0.1, T, 0.4, -1.36e-3)).max())
    assert lp.spectral_radius == pytest.approx(ref, rel=1e-9)
    assert ref == pytest.approx(0.765, abs=1e-3)


@pytest.mark.parametrize("name", ["knob-exact", "knob-legacy"])
def test_knob_comment_states_the_hands_real_effect(name):
    """The comment's rho for the heavier hand must be the coupled loop's (mass, damping and
    stiffness), not the bare J + J_h plant's 0.999."""
    text = (SCENES / f"{name}.toml").read_text()
    comment = "\n".join(line for line in text.splitlines() if line.startswith("#"))
    m = re.search(r"with 2e-6 .*?rho (0\.\d+)", comment, re.S)
    assert m, comment
    J, b = 85.78e-7 + 2e-6, 2.197e-3 + 1e-4
    ref = float(np.abs(scipy_poles(J, b, 0.1, 0.02, 0.4, -1.36e-3)).max())
    assert float(m.group(1)) == pytest.approx(ref, abs=1e-3)


def test_linear_part_with_delay_and_filter_matches_the_loop_analysis():
    """closed_loop_matrix's eigenvalues against zwidth's general loop (loop.h) for a delay
    and a low-pass: the same spectral radius."""
    for delay, a in ((1, 0.0), (3, 0.0), (0, 0.6), (2, 0.8)):
        A = zsim.closed_loop_matrix(0.1, 30.0, 0.0, 0.01, 2000.0, 5.0, delay, a)
        rho = float(np.abs(np.linalg.eigvals(A)).max())
        dev = zwidth.Device(0.1, 30.0, 0.01, delay=delay, velocity_filter=("pole", a) if a else None)
        assert rho == pytest.approx(float(dev.spectral_radius(2000.0, 5.0)), rel=1e-9), (delay, a)


def test_effect_that_changes_the_verdict_is_named(tmp_path):
    """Saturation turns P11 (stable) into a sustained oscillation (review 3d); the output
    names saturation beside the linear part's "stable"."""
    doc = {"scene": {"duration": "10 s"}, "plant": plant(b="50 N*s/m"), "controller": {"alpha": 20, "beta": -2.5},
           "reference": {"to": "1 m"}, "saturation": {"force_max": "100 N"}}
    s = zwidth.simulate(doc)[0]
    assert s.linear.stable and s.verdict.outcome == "unstable"
    assert s.explanation is not None and "saturation" in s.explanation
    path = write(tmp_path, "sat.toml", zwidth.load_scene(doc).to_toml())
    r = run("simulate", str(path), "--no-progress")
    assert r.returncode == 1 and "differs:" in r.stdout and "saturation" in r.stdout


def test_stable_only_with_the_effect_named_when_the_linear_loop_grows(tmp_path):
    """Done-when of issue 14: a loop whose linear part grows (negative total damping) held
    by friction simulates stable, exit 0, and the output says friction did it."""
    doc = {"scene": {"duration": "5 s"}, "plant": plant(b="0 N*s/m", T="1 ms"),
           "controller": {"K": "100 N/m", "B": "-0.02 N*s/m"}, "reference": {"to": "10 cm"},
           "friction": {"coulomb": "1 N", "stiction": "1.5 N"}}
    s = zwidth.simulate(doc)[0]
    assert s.verdict.outcome == "stable" and not s.linear.stable and s.linear.spectral_radius > 1
    assert "friction" in s.explanation
    r = run("simulate", str(write(tmp_path, "fr.toml", zwidth.load_scene(doc).to_toml())), "--no-progress")
    assert r.returncode == 0 and "differs:" in r.stdout and "friction" in r.stdout and "unstable" in r.stdout


# ---------------------------------------------------------------------------------------
# 5. Quantization limit cycles in counts
# ---------------------------------------------------------------------------------------


def quantized(delta, alpha, beta, **q):
    return {"scene": {"duration": "10 s"}, "plant": plant(b=f"{delta * 10} N*s/m"),
            "controller": {"alpha": alpha, "beta": beta}, "reference": {"to": "1 m"},
            "quantization": {"resolution": "1 mm", **q}}


def test_limit_cycle_verdict_counts_not_tolerance():
    """Review 3d: P5 (1.45 mm p-p) "stable", P1 (1.64 mm) "unstable", by the tolerance
    against one count.  Now both are a limit cycle of 2 counts, judged by the scene's
    limit_cycle (default 1 count), whatever the tolerance."""
    for d, a, b in ((2.3, 5, 1), (3.0, 7, 2)):
        s = zwidth.simulate(quantized(d, a, b))[0]
        assert s.verdict.counts == 2 and s.verdict.outcome == "unstable", s.verdict
        assert "limit cycle of 2 counts" in s.verdict.reason and "quantization" in s.explanation
        ok = zwidth.simulate(quantized(d, a, b, limit_cycle=2))[0]
        assert ok.verdict.outcome == "stable" and "limit cycle of 2 counts" in ok.verdict.reason
        assert ok.verdict.period is not None and ok.verdict.period > 0


def test_limit_cycle_round_trips_through_toml():
    sc = zwidth.load_scene(quantized(3.0, 7, 2, limit_cycle=3))
    assert sc.cases[0].limit_cycle == 3
    assert zwidth.load_scene(sc.to_toml()).cases[0].limit_cycle == 3
    assert zwidth.load_scene(quantized(3.0, 7, 2)).cases[0].limit_cycle == 1    # the documented default


def test_limit_cycle_key_checked():
    with pytest.raises(zwidth.SceneError) as e:
        zwidth.load_scene(quantized(3.0, 7, 2, limit_cycle=-1))
    assert e.value.key == "quantization.limit_cycle"


# ---------------------------------------------------------------------------------------
# 6. Smaller findings
# ---------------------------------------------------------------------------------------


def test_settled_quantized_run_has_no_subnormal_velocity():
    """Review 2f: 1,962,917 of 2e6 samples had a subnormal v (9.6x slower)."""
    doc = {"scene": {"duration": "60 s"}, "plant": plant(b="2 N*s/m", T="1 ms"),
           "controller": {"K": "2000 N/m", "B": "1 N*s/m"}, "reference": {"to": "7.8125 mm"},
           "quantization": {"counts": "1048576 / m"}}
    s = zwidth.simulate(doc)[0]
    tiny = (s.v != 0) & (np.abs(s.v) < np.finfo(np.float64).tiny)
    assert not tiny.any() and (s.v == 0).sum() > 1000


def test_hand_too_stiff_is_reported_under_hand_stiffness():
    doc = {"plant": plant(), "controller": {"K": "100 N/m", "B": "1 N*s/m"},
           "hand": {"mass": "0.01 kg", "stiffness": "1e20 N/m"}}
    with pytest.raises(zwidth.SceneError) as e:
        zwidth.load_scene(doc)
    assert e.value.key == "hand.stiffness"


def test_memory_is_stated_and_the_run_holds_one_copy(monkeypatch):
    """Review 4b: 12.5 GB at 2.6e8 samples against the documented 10 GiB: with a progress
    bar the chunks were collected and concatenated (the run twice in memory)."""
    doc = {"scene": {"duration": "2000 s"}, "plant": plant(T="1 ms"), "controller": {"K": "100 N/m", "B": "1 N*s/m"},
           "reference": {"to": "1 mm"}}
    scene = zwidth.load_scene(doc)
    need = zsim.memory_bytes(scene.cases[0])
    assert need == 2_000_000 * 5 * 8
    monkeypatch.setattr(zsim, "_CHUNK_WORK", 1_000_000)     # many chunks
    tracemalloc.start()
    try:
        zwidth.simulate(scene, progress=True)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak <= 1.25 * need, (peak, need)


def test_run_larger_than_available_memory_refused_before_it_starts(monkeypatch, tmp_path):
    monkeypatch.setattr(zsim, "available_memory", lambda: 1000)
    with pytest.raises(MemoryError, match="GiB"):
        zwidth.simulate(UNEXCITED)
