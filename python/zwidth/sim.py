# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Time-domain simulation of scenes (paper Fig. 13): :func:`simulate`.

Each case of a scene (:mod:`zwidth.scene`) runs in the C core (sim.h) through
``zwidth._core.Simulator``: the plant behind a zero-order hold, sampled every T, the
impedance controller, and only the effects the scene asks for.  Without an effect every
sample is the exact discrete-time solution; friction and a hand bring an RK4 integrator.

The simulated verdict (:class:`SimVerdict`) is the C core's ``zw_sim_judge`` on the true
position: the last ``windows`` windows of ``window`` samples each (by default 8 windows,
DEFAULT_WINDOWS, covering the run's second half), their peak-to-peak amplitudes A_1
(oldest) .. A_w:

    unstable   the position overflowed (a sample is not finite)
    stable     otherwise, if A_w <= tolerance: settled (default tolerance: 1e-3 of the
               position's peak-to-peak over the whole run)
    unstable   otherwise, unless the amplitudes strictly shrink window by window
               (A_{i+1} < A_i for every i): a growing or sustained oscillation, a limit
               cycle or a drift is not dying out
    undecided  otherwise: shrinking in every window but not settled yet: run longer

then :func:`judge`'s evidence rules: a run whose position never moved is undecided
("nothing excites the loop"); with quantization the limit cycle in counts decides against
the scene's ``limit_cycle``; and a run whose windows are shorter than the slowest
oscillation of the loop's linear part is undecided, "run at least N s" (N from its poles).

Every case gets its linear part (:class:`LinearPart`, :func:`linear_part`: the loop
without quantization, friction, saturation and switching) and, where the verdicts differ,
``Simulation.explanation`` names the effect.  For a linear scene (no effect, or only a
delay of up to 8 samples and a velocity low-pass) ``Simulation.analytic`` is zwidth's exact
verdict of the loop simulated (zwidth.loop, with the simulator's own filter pole) and
``agrees`` compares the two; ``Simulation.note`` warns when the paper's ideal loop would
say otherwise.
"""
from __future__ import annotations

import csv
import dataclasses
import io
import math
import sys
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import NDArray

from . import _core
from .device import Device
from .loop import MAX_DELAY
from .results import LoopVerdict, Verdict
from .scene import (DEFAULT_RELATIVE_TOLERANCE, EFFECTS, LINEAR_EFFECTS, Case, Scene, SceneError,
                    load_scene, signal_units)

__all__ = ["simulate", "Simulation", "SimulationSet", "SimVerdict", "SIGNALS", "EFFECT_SIGNALS", "work",
           "LinearPart", "linear_part", "memory_bytes", "check_memory"]

#: Every signal the simulator can record (zw_sim_trace fields).
SIGNALS: Tuple[str, ...] = ("t", "x", "v", "x_measured", "force", "force_command", "stiffness",
                            "stiffness_planned", "damping", "velocity_estimate", "wall_force",
                            "friction", "hand_force", "hand_target")
_BASIC = ("t", "x", "v", "x_measured", "force")
#: Per-effect signals recorded into Simulation.signals when the effect is on.
EFFECT_SIGNALS: Dict[str, Tuple[str, ...]] = {
    "quantization": (),                  # x_measured is always recorded
    "friction": ("friction",),
    "delay": ("force_command",),
    "saturation": ("force_command",),
    "velocity_filter": ("velocity_estimate",),   # the filtered v_est the damping used
    "hand": ("hand_force", "hand_target"),
    "wall": ("wall_force", "force_command"),
    "knob": ("stiffness", "stiffness_planned", "damping"),
    "schedule": ("stiffness", "damping"),
    "differentiator": ("velocity_estimate",),
    "average": ("velocity_estimate",),
    "actuator": (),                      # force is the actuator's input (sim.h)
}

_LINEAR_BITS = sum(EFFECTS[e] for e in LINEAR_EFFECTS)
#: Effects outside any linear loop (the actuator lag is linear; the analysis does not cover it yet).
_NONLINEAR_BITS = sum(bit for e, bit in EFFECTS.items() if e not in LINEAR_EFFECTS + ("actuator",))


def analysis_device(params: Mapping[str, Any], rotary: bool, filter_pole: float) -> Optional[Device]:
    """The Device whose loop is the one a case simulates, or None when the analysis does
    not cover it (a nonlinear or time-varying effect, or a delay beyond loop.MAX_DELAY).

    Timing (sim.c against loop.h): the force computed from x_k is applied over
    [(k + d)T, (k + d + 1)T) in both; the simulator's low-pass vf_k = a vf_{k-1} +
    (1 - a)(x_k - x_{k-1})/T is the loop's, with a the simulator's own pole
    (``filter_pole``, exp(-2 pi f_c T) as sim.c rounds it), so the verdict is that of the
    loop run, bit for bit in a (also above the Nyquist frequency, which a drive may do).
    """
    effects = int(params["effects"])
    if effects & ~_LINEAR_BITS:
        return None
    delay = int(params.get("delay_samples", 0)) if effects & EFFECTS["delay"] else 0
    if delay > MAX_DELAY:
        return None
    return Device(params["m"], params["b"], params["T"], rotary=rotary, delay=delay,
                  velocity_filter=_velocity_filter(params, effects, filter_pole),
                  differentiator="tustin" if effects & EFFECTS["differentiator"] else "backward")


def _velocity_filter(params: Mapping[str, Any], effects: int, filter_pole: float) -> Any:
    """The Device's velocity_filter for the simulated one (None: none)."""
    if effects & EFFECTS["velocity_filter"]:
        return ("pole", float(filter_pole))
    if effects & EFFECTS["average"]:
        return ("average", int(params["average_samples"]))
    return None


def loop_words(params: Mapping[str, Any], dev: Device) -> str:
    """The simulated loop in words, its low-pass by the scene's cut-off (and the pole used)."""
    text = dev.loop.describe()
    if dev.loop.filter == "lowpass" and "cutoff_hz" in params:
        text = text.replace(f"low-pass pole {float(dev.loop.pole):g}",
                            f"low-pass {float(params['cutoff_hz']):g} Hz, pole {float(dev.loop.pole):.6g}")
    return text


# ---------------------------------------------------------------------------------------
# The loop's linear part: what the analysis says, for every scene
# ---------------------------------------------------------------------------------------

#: Effects that are not part of any linear loop: each can make the simulated verdict
#: differ from the linear part's, for the reason given (printed where they differ).
NONLINEAR_EXPLANATIONS: Dict[str, Tuple[str, str]] = {
    # effect: (why a linearly unstable loop may simulate stable, why a stable one may not)
    "friction": ("friction dissipates energy and stiction holds the plant: it can stop the "
                 "growth of the unstable linear loop (a stick-slip limit cycle or rest)",
                 "friction makes stick-slip: a limit cycle of the stable linear loop"),
    "saturation": ("saturation bounds the force, so the unstable linear loop's growth is bounded "
                   "(a sustained oscillation at the force limit)",
                   "saturation clips the force: the loop no longer renders the gains analysed"),
    "quantization": ("quantization hides motion below one count from the controller",
                     "quantization creates a limit cycle of a few counts around the equilibrium"),
    "wall": ("the wall is one-sided: the loop switches between free motion and contact",
             "the wall is one-sided: contact and release switch the loop, which can rattle"),
    "knob": ("the knob's stiffness depends on the position: the loop switches between detents, "
             "the negative stiffness between them and the end walls",
             "the knob's stiffness depends on the position: the loop switches between detents, "
             "the negative stiffness between them and the end walls"),
    "schedule": ("the gains change in time: only the last segment is analysed",
                 "the gains change in time: an earlier segment may grow before the last one"),
    "hand": ("the hand's grasp, release and motion change the plant during the run",
             "the hand's grasp, release and motion change the plant during the run"),
}

# Modes whose share of the response fell below this over the judged half are not waited for.
_ALIVE = 1e-3


def _expm(A: NDArray[np.float64]) -> NDArray[np.float64]:
    """exp(A) of a small matrix by scaling and squaring a Taylor series (numpy has no expm;
    here |A| is at most a few hundred and 3x3, where this is accurate to rounding)."""
    norm = float(np.abs(A).sum(axis=1).max())
    s = max(0, int(math.ceil(math.log2(norm))) + 1) if norm > 0 else 0
    A = A / 2.0 ** s
    E = np.eye(len(A))
    term = np.eye(len(A))
    for j in range(1, 21):
        term = term @ A / j
        E = E + term
    for _ in range(s):
        E = E @ E
    return E


def closed_loop_matrix(M: float, c: float, k: float, T: float, K: float, B: float, delay: int,
                       filter_pole: float, *, tustin: bool = False, average: int = 0,
                       tau: float = 0.0) -> NDArray[np.float64]:
    """The closed loop of sim.h without its nonlinear effects, as z_{k+1} = A z_k.

    The plant M x'' + c x' + k x = f (k: a hand's stiffness), with f = u held by the
    zero-order hold, or through an actuator lag tau f' + f = u (tau > 0), discretized
    exactly (matrix exponential of the augmented system); the controller u = -K x - B v_est
    applied `delay` samples later, v_est from the backward difference or Tustin's
    differentiator (tustin), then a low-pass of pole filter_pole (> 0) or a moving average
    over `average` samples (> 1).  The state: the plant's (x, v[, f]), then x_{k-1}, the
    differentiator's last output (Tustin), the low-pass's last output (always kept: a
    zero pole leaves it unused), the last average - 1 differentiator outputs, u_{k-1} ..
    u_{k-delay}.  The equilibrium does not change the poles."""
    lag = tau > 0
    n_plant = 3 if lag else 2
    Ac = np.zeros((n_plant + 1, n_plant + 1))
    Ac[0, 1] = 1.0
    Ac[1, 0], Ac[1, 1] = -k / M, -c / M
    if lag:
        Ac[1, 2], Ac[2, 2], Ac[2, 3] = 1.0 / M, -1.0 / tau, 1.0 / tau
    else:
        Ac[1, 2] = 1.0 / M
    E = _expm(Ac * T)
    Ad, Bd = E[:n_plant, :n_plant], E[:n_plant, n_plant]
    i_prev = n_plant                          # x_{k-1}
    i_diff = i_prev + 1                       # the differentiator's last output
    i_filt = i_diff + 1                       # the low-pass's last output
    i_avg = i_filt + 1                        # average - 1 earlier differentiator outputs
    n_avg = max(0, int(average) - 1)
    i_u = i_avg + n_avg                       # u_{k-1} .. u_{k-delay}
    n = i_u + delay
    e = np.eye(n)
    x = e[0]
    v_d = (x - e[i_prev]) / T                 # rows: linear functions of z_k
    if tustin:
        v_d = 2.0 * v_d - e[i_diff]
    a = float(filter_pole)
    if a > 0:
        v_est = a * e[i_filt] + (1.0 - a) * v_d
    elif average > 1:
        v_est = (v_d + e[i_avg:i_avg + n_avg].sum(axis=0)) / average
    else:
        v_est = v_d
    u = -K * x - B * v_est
    applied = u if delay == 0 else e[i_u + delay - 1]
    A = np.zeros((n, n))
    A[:n_plant] = Ad @ e[:n_plant] + np.outer(Bd, applied)
    A[i_prev] = x
    A[i_diff] = v_d
    A[i_filt] = v_est if a > 0 else 0.0
    if n_avg:
        A[i_avg] = v_d
        A[i_avg + 1:i_avg + n_avg] = e[i_avg:i_avg + n_avg - 1]
    if delay:
        A[i_u] = u
        A[i_u + 1:i_u + delay] = e[i_u:i_u + delay - 1]
    return A


@dataclasses.dataclass(frozen=True)
class LinearPart:
    """The loop a case simulates with its nonlinear effects taken out, and its verdict.

    piece:    which linear loop: "the gains" (constant gains), "the end walls" / "the
              detents" (knob: the worst of the two), "contact with the wall", "the last
              segment" (schedule)
    K, B:     the gains of that piece; m, b, k: the plant (with a hand still holding at the
              end of the run: its mass, damping and stiffness added)
    poles:    the closed loop's poles (numpy eigenvalues of closed_loop_matrix)
    spectral_radius: the largest pole modulus
    verdict:  zwidth's guarded verdict of that loop (Device.verdict, a holding hand and an
              actuator lag as plant-side parts) where the analysis covers it (a delay up to
              loop.MAX_DELAY), else None (the eigenvalues decide)
    stable:   the verdict's, else spectral_radius < 1
    """

    piece: str
    K: float
    B: float
    m: float
    b: float
    k: float
    delay: int
    filter_pole: float
    poles: NDArray[np.complex128] = dataclasses.field(repr=False)
    spectral_radius: float
    verdict: Optional[Union[Verdict, LoopVerdict]] = dataclasses.field(repr=False)
    stable: bool
    tustin: bool = dataclasses.field(default=False, repr=False)
    average: int = dataclasses.field(default=0, repr=False)
    #: the actuator lag [s] (0: none)
    tau: float = dataclasses.field(default=0.0, repr=False)

    @property
    def word(self) -> str:
        if self.verdict is not None:
            return str(self.verdict.word)
        return "stable" if self.stable else "unstable"

    def slowest_period(self, samples: int) -> float:
        """The longest oscillation period [samples] among the modes still alive over the
        judged half of a run of this many samples (0: no oscillating mode)."""
        mags = np.abs(self.poles)
        rho = float(mags.max()) if mags.size else 0.0
        half = max(1, samples // 2)
        period = 0.0
        for z, r in zip(self.poles, mags):
            theta = abs(float(np.angle(z)))
            if r == 0 or theta < 1e-12:
                continue
            if rho > 0 and (r / rho) ** half < _ALIVE:
                continue
            period = max(period, 2 * math.pi / theta)
        return period

    def describe(self, units: Mapping[str, str]) -> str:
        hand = f", with the hand (k_h {self.k:g} {units['stiffness']})" if self.k else ""
        return (f"{self.piece}: K {self.K:g} {units['stiffness']}, B {self.B:g} {units['damping']}{hand}: "
                f"{self.word}, spectral radius {self.spectral_radius:.6g}")


def _pieces(params: Mapping[str, Any], effects: int) -> List[Tuple[str, float, float]]:
    """The linear loops of a case's controller: (name, K, B)."""
    if effects & EFFECTS["knob"]:
        d = float(params["knob_damping"])
        return [("the end walls", float(params["knob_k_end"]), d),
                ("the detents", float(params["knob_k_detent"]), d)]
    if effects & EFFECTS["schedule"]:
        t, K, B = (float(v) for v in np.asarray(params["schedule"])[-1])
        return [(f"the last segment (from {t:g} s)", K, B)]
    pieces = [("the gains", float(params["K"]), float(params["B"]))]
    if effects & EFFECTS["wall"]:
        pieces.append(("contact with the wall", float(params["K"]) + float(params["wall_stiffness"]),
                       float(params["B"]) + float(params["wall_damping"])))
    return pieces


def linear_part(params: Mapping[str, Any], rotary: bool, filter_pole: float, duration: float) -> LinearPart:
    """The case's loop without its nonlinear effects (quantization, friction, saturation,
    the wall's and the knob's switching, the schedule's earlier segments), at the end of
    the run (a hand still holding then adds its mass, damping and stiffness); for several
    pieces (knob, wall) the one of largest spectral radius, so it is stable only if every
    piece is."""
    effects = int(params["effects"])
    m, b, T = float(params["m"]), float(params["b"]), float(params["T"])
    k = 0.0
    held: Optional[Tuple[float, float, float]] = None  # the hand holding at the end, as Device's hand=
    if effects & EFFECTS["hand"] and float(params["hand_t_grasp"]) < duration <= float(params["hand_t_release"]):
        held = (float(params["hand_mass"]), float(params["hand_damping"]), float(params["hand_stiffness"]))
        m += float(params["hand_mass"])
        b += float(params["hand_damping"])
        k = float(params["hand_stiffness"])
    delay = int(params.get("delay_samples", 0)) if effects & EFFECTS["delay"] else 0
    a = float(filter_pole) if effects & EFFECTS["velocity_filter"] else 0.0
    tustin = bool(effects & EFFECTS["differentiator"])
    average = int(params["average_samples"]) if effects & EFFECTS["average"] else 0
    tau = float(params["actuator_tau"]) if effects & EFFECTS["actuator"] else 0.0
    worst: Optional[LinearPart] = None
    for name, K, B in _pieces(params, effects):
        A = closed_loop_matrix(m, b, k, T, K, B, delay, a, tustin=tustin, average=average, tau=tau)
        poles = np.asarray(np.linalg.eigvals(A), dtype=np.complex128)
        rho = float(np.abs(poles).max())
        verdict: Optional[Union[Verdict, LoopVerdict]] = None
        if delay <= MAX_DELAY:
            # a hand still holding and an actuator lag are plant-side parts of the general loop
            # (plant.h): its guarded verdict, as for the plain plant
            dev = Device(float(params["m"]), float(params["b"]), T, rotary=rotary, delay=delay,
                         velocity_filter=_velocity_filter(params, effects, a),
                         differentiator="tustin" if tustin else "backward", actuator_tau=tau, hand=held)
            verdict = dev.verdict(K, B)
            rho = float(dev.spectral_radius(K, B))
        stable = bool(verdict.stable) if verdict is not None else rho < 1.0
        part = LinearPart(piece=name, K=K, B=B, m=m, b=b, k=k, delay=delay, filter_pole=a, poles=poles,
                          spectral_radius=rho, verdict=verdict, stable=stable, tustin=tustin,
                          average=average, tau=tau)
        if worst is None or (worst.stable and not part.stable) or (
                worst.stable == part.stable and part.spectral_radius > worst.spectral_radius):
            worst = part
    assert worst is not None
    return worst


def explain(effects: Sequence[str], simulated: str, linear: LinearPart) -> Optional[str]:
    """One line naming the effect that explains a simulated verdict different from the linear
    part's, or None when they agree (or the simulation is undecided)."""
    if simulated == "undecided" or (simulated == "stable") == linear.stable:
        return None
    causes = [e for e in NONLINEAR_EXPLANATIONS if e in effects]
    if not causes:
        return (f"simulated {simulated} but the linear part is {linear.word}: no nonlinear effect explains "
                f"it: the run is too short or the verdict window too small (--duration)")
    why = "; ".join(NONLINEAR_EXPLANATIONS[e][0 if simulated == "stable" else 1] for e in causes)
    return f"simulated {simulated}, linear part {linear.word}: {why}"


# Work per Simulator.run call when reporting progress (about 0.1 s; see work()).
_CHUNK_WORK = 30_000_000


@dataclasses.dataclass(frozen=True)
class SimVerdict:
    """The simulated verdict of one run (zw_sim_judge on the true position).

    outcome:          'stable' | 'unstable' | 'undecided'
    amplitude_first:  peak-to-peak of the first judged window (position units)
    amplitude_last:   peak-to-peak of the last window
    growth:           (A_last / A_first)^(1/samples between them): the envelope's factor per
                      sample; for a linear scene an estimate of the spectral radius
    reason:           the criterion's finding in words
    window, windows, tolerance:  the settings used (samples, count, position units)
    first_nonfinite:  index of the first overflowed sample, None if none
    """

    outcome: str
    amplitude_first: float
    amplitude_last: float
    growth: float
    reason: str
    window: int = dataclasses.field(default=0, repr=False)
    windows: int = dataclasses.field(default=0, repr=False)
    tolerance: float = dataclasses.field(default=0.0, repr=False)
    first_nonfinite: Optional[int] = dataclasses.field(default=None, repr=False)
    #: why undecided, when the run cannot tell: "unexcited" (nothing moved), "below
    #: tolerance" (it never moved by more than the tolerance), "too short" (see
    #: required_duration), "decaying" (not settled yet); None when decided
    undecided_because: Optional[str] = dataclasses.field(default=None, repr=False)
    #: the duration [s] the loop's slowest mode needs for a verdict (undecided runs), else None
    required_duration: Optional[float] = dataclasses.field(default=None, repr=False)
    #: with [quantization]: the measured motion over the judged windows in counts, and its
    #: period [s] (None: no oscillation seen)
    counts: Optional[int] = dataclasses.field(default=None, repr=False)
    period: Optional[float] = dataclasses.field(default=None, repr=False)

    @property
    def stable(self) -> bool:
        return self.outcome == "stable"

    def as_dict(self) -> Dict[str, Any]:
        return dataclasses.asdict(self)


@dataclasses.dataclass(frozen=True, eq=False)
class Simulation:
    """One simulated case: numpy arrays of the run and its verdicts.

    label:      the case's label
    t, x, v:    time [s], true position and velocity at each sample (m, m/s; rad, rad/s)
    x_measured: the position the controller saw (quantized with [quantization])
    force:      force applied to the plant over [t, t + T) (N; N m for a rotary plant)
    signals:    the per-effect signals of the scene's effects (EFFECT_SIGNALS): friction,
                hand_force, hand_target, wall_force, force_command, stiffness, stiffness_planned,
                damping, velocity_estimate
    verdict:    the simulated verdict (:class:`SimVerdict`)
    analytic:   zwidth's exact verdict of the loop simulated, for a linear scene (no effect:
                a :class:`zwidth.Verdict`; a delay and/or velocity low-pass: a
                :class:`zwidth.LoopVerdict` of that loop), else None
    agrees:     simulated and analytic verdicts agree (None: no analytic verdict, or the
                simulation is undecided)
    params:     the flat scene dict simulated (SI units; see zwidth._core.Simulator)
    units:      unit of each signal
    case:       the :class:`zwidth.scene.Case`
    ideal:      for a delay / low-pass scene, the paper's ideal loop's verdict at the same
                gains (what ``zwidth check`` without loop options says), else None
    note:       a warning in words when the ideal loop's verdict and this loop's differ (or
                when the analysis does not cover the loop), else None
    """

    label: str
    t: NDArray[np.float64] = dataclasses.field(repr=False)
    x: NDArray[np.float64] = dataclasses.field(repr=False)
    v: NDArray[np.float64] = dataclasses.field(repr=False)
    x_measured: NDArray[np.float64] = dataclasses.field(repr=False)
    force: NDArray[np.float64] = dataclasses.field(repr=False)
    signals: Dict[str, NDArray[np.float64]] = dataclasses.field(repr=False)
    verdict: SimVerdict
    analytic: Optional[Union[Verdict, LoopVerdict]]
    agrees: Optional[bool]
    params: Dict[str, Any] = dataclasses.field(repr=False)
    units: Dict[str, str] = dataclasses.field(repr=False)
    case: Case = dataclasses.field(repr=False)
    ideal: Optional[Verdict] = dataclasses.field(default=None, repr=False)
    note: Optional[str] = dataclasses.field(default=None, repr=False)
    #: the Device (plant and loop) whose verdict ``analytic`` is, else None
    device: Optional[Device] = dataclasses.field(default=None, repr=False)
    #: the loop's linear part (every scene): its verdict beside the simulated one
    linear: Optional[LinearPart] = dataclasses.field(default=None, repr=False)
    #: one line naming the effect that explains a simulated verdict different from the
    #: linear part's, else None
    explanation: Optional[str] = dataclasses.field(default=None, repr=False)

    def __repr__(self) -> str:
        analytic = "None" if self.analytic is None else self.analytic.word
        return (f"Simulation({self.label!r}, {len(self.t)} samples, T={self.params['T']:g} s, "
                f"verdict={self.verdict.outcome}, growth={self.verdict.growth:.6g}, "
                f"analytic={analytic}, agrees={self.agrees})")

    def __len__(self) -> int:
        return len(self.t)

    @property
    def arrays(self) -> Dict[str, NDArray[np.float64]]:
        """Every recorded signal by name: t, x, v, x_measured, force and the per-effect ones."""
        return {"t": self.t, "x": self.x, "v": self.v, "x_measured": self.x_measured,
                "force": self.force, **self.signals}


class SimulationSet(Tuple[Simulation, ...]):
    """The simulations of a scene, one per case, in the scene's order (a tuple).

    ``sims.by_label("P6")`` finds one; ``sims.scene`` is the :class:`zwidth.scene.Scene`;
    ``to_npz`` / ``to_csv`` write the arrays.
    """

    scene: Scene

    def __new__(cls, simulations: Sequence[Simulation], scene: Scene) -> "SimulationSet":
        self = super().__new__(cls, tuple(simulations))
        self.scene = scene
        return self

    def __getnewargs__(self) -> Tuple[Any, ...]:  # pickling
        return (tuple(self), self.scene)

    def by_label(self, label: str) -> Simulation:
        """The simulation of the case with this label (KeyError if none)."""
        for s in self:
            if s.label == label:
                return s
        raise KeyError(f"no case {label!r} (cases: {', '.join(self.labels)})")

    @property
    def labels(self) -> Tuple[str, ...]:
        return tuple(s.label for s in self)

    @property
    def all_stable(self) -> bool:
        """Every case simulated stable."""
        return all(s.verdict.outcome == "stable" for s in self)

    def __repr__(self) -> str:
        lines = [f"SimulationSet({self.scene.name!r}, {len(self)} case{'s' if len(self) != 1 else ''})"]
        for s in self:
            analytic = "-" if s.analytic is None else s.analytic.word
            lines.append(f"  {s.label:<12} simulated {s.verdict.outcome:<9} growth/sample "
                         f"{s.verdict.growth:<10.6g} analytic {analytic:<9} agrees {s.agrees}")
        return "\n".join(lines)

    def to_npz(self, path: Union[str, Path]) -> Path:
        """Write every case's arrays into one .npz: keys "<label>/<signal>" (t, x, v,
        x_measured, force and the per-effect signals), plus "labels"."""
        out = Path(path)
        arrays: Dict[str, Any] = {"labels": np.array(self.labels)}
        for s in self:
            for name, a in s.arrays.items():
                arrays[f"{s.label}/{name}"] = a
        with open(out, "wb") as f:
            np.savez_compressed(f, **arrays)
        return out

    def to_csv(self, path: Union[str, Path]) -> Path:
        """Write one CSV, one row per sample of every case: a "case" column, then t, x, v,
        x_measured, force and every per-effect signal of the scene (header with units)."""
        out = Path(path)
        names = list(self[0].arrays) if self else list(_BASIC)  # the effects are the scene's: same for all
        units = signal_units(self.scene.rotary)
        with open(out, "w", newline="") as f:
            csv.writer(f).writerow(["case"] + [f"{n} [{units[n]}]" for n in names])
            for s in self:
                text = io.StringIO()
                csv.writer(text).writerow([s.label])
                label = text.getvalue().rstrip("\r\n").replace("%", "%%")
                block = np.column_stack([s.arrays[n] for n in names])
                # %.17g: every double reads back exactly
                np.savetxt(f, block, fmt=label + "," + ",".join(["%.17g"] * len(names)))
        return out


def _reason(outcome: str, r: Mapping[str, Any], window: int, windows: int, tolerance: float,
            T: float, unit: str) -> str:
    a1, aw, g = float(r["amplitude_first"]), float(r["amplitude_last"]), float(r["growth"])
    span = f"the last {windows} windows of {window} samples ({windows * window * T:g} s)"
    if outcome == "stable":
        return (f"settled: peak-to-peak {aw:.3g} {unit} in the last window <= tolerance "
                f"{tolerance:.3g} {unit}")
    if r["first_nonfinite"] is not None and outcome == "unstable" and not math.isfinite(aw):
        return f"the position overflowed at t = {int(r['first_nonfinite']) * T:g} s"
    if outcome == "unstable":
        if aw > a1:
            return (f"not dying out: peak-to-peak grew from {a1:.3g} to {aw:.3g} {unit} over {span} "
                    f"(x {g:.6g} per sample)")
        return (f"not dying out: peak-to-peak went from {a1:.3g} to {aw:.3g} {unit} over {span} but did not "
                f"shrink in every window (a sustained or irregular oscillation)")
    return (f"still decaying (x {g:.6g} per sample) but {aw:.3g} {unit} > tolerance {tolerance:.3g} "
            f"{unit} in the last window: run longer")


def _round_up(seconds: float) -> float:
    """Up to two significant digits (a duration to ask for)."""
    if not (math.isfinite(seconds) and seconds > 0):
        return seconds
    step = 10.0 ** (math.floor(math.log10(seconds)) - 1)
    return math.ceil(seconds / step * (1 - 1e-12)) * step


def _period(x: NDArray[np.float64], T: float) -> Optional[float]:
    """Mean period [s] of an oscillation of x about its mean (from its sign changes), None
    if it crosses fewer than twice."""
    d = x - 0.5 * (float(x.max()) + float(x.min()))
    signs = np.sign(d[d != 0])
    crossings = int(np.count_nonzero(signs[1:] != signs[:-1]))
    return 2.0 * len(x) * T / crossings if crossings >= 2 else None


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


def judge(x: NDArray[np.float64], case: Case, T: float, unit: str = "", *,
          x_measured: Optional[NDArray[np.float64]] = None,
          linear: Optional[LinearPart] = None) -> SimVerdict:
    """The simulated verdict of a position record with the case's verdict settings
    (zw_sim_judge), then the rules that need more than the record (docs/scenes.md, "The
    verdict"):

    - nothing moved (x the same number throughout): undecided, "nothing excites the loop";
    - with [quantization] (``x_measured`` and the case's ``limit_cycle``): the measured
      motion over the judged windows, in counts, n: n <= limit_cycle is stable ("limit
      cycle of n counts", or settled within a count); more, when the position settled to
      the tolerance, is unstable;
    - with the ``linear`` part: when its slowest oscillation still alive is longer than the
      window (a twentieth of the window for a settled run; and the judged windows moved
      more than the tolerance), the windows cannot show a decay: undecided, "run at least
      N s"; a run still decaying gets the duration
      its slowest mode needs to decay 1e4-fold in the same words.
    """
    x = np.asarray(x, dtype=np.float64)
    n = len(x)
    tolerance = case.tolerance
    finite_run = bool(n) and bool(np.isfinite(x.min())) and bool(np.isfinite(x.max()))
    if tolerance is None:
        if finite_run:   # min/max, not a copy of the finite values: runs may be 2 GiB per signal
            scale = float(x.max()) - float(x.min())
        else:
            finite = x[np.isfinite(x)]
            scale = float(finite.max()) - float(finite.min()) if finite.size else 0.0
        if not math.isfinite(scale):   # finite positions spanning more than DBL_MAX
            scale = float(np.finfo(np.float64).max)
        tolerance = DEFAULT_RELATIVE_TOLERANCE * scale
    r = dict(_core.sim_judge(x, case.window, case.windows, tolerance))
    nonfinite = int(r["first_nonfinite"])
    r["first_nonfinite"] = nonfinite if nonfinite < n else None
    outcome = str(r["outcome"])
    reason = _reason(outcome, r, case.window, case.windows, tolerance, T, unit)
    judged = case.window * case.windows
    because: Optional[str] = "decaying" if outcome == "undecided" else None
    required: Optional[float] = None
    counts: Optional[int] = None
    period: Optional[float] = None
    decided_by_counts = False

    if outcome == "undecided" and finite_run and float(r["amplitude_last"]) <= tolerance:
        # zw_sim_judge: settled, but the record never moved by more than the tolerance
        because = "below tolerance"
        reason = (f"never moved more than the tolerance: peak-to-peak "
                  f"{float(x.max()) - float(x.min()):.3g} {unit} over the whole run <= {tolerance:.3g} {unit}, "
                  f"so the run cannot show it settling (a growth may still be inside the tolerance); "
                  f"lower [verdict] tolerance or excite the loop more")
    if finite_run and float(x.min()) == float(x.max()):
        outcome, because = "undecided", "unexcited"
        reason = (f"nothing excites the loop: the position stayed at {float(x[0]):.6g} {unit} for the whole run "
                  f"(it starts at rest where the controller and every effect leave it), so the run says nothing "
                  f"about stability; give [initial] x or v, or a [reference] step")
    elif finite_run and x_measured is not None and case.limit_cycle is not None:
        per_unit = float(case.params["counts_per_unit"])
        xm = np.asarray(x_measured[-judged:], dtype=np.float64)
        counts = int(round((float(xm.max()) - float(xm.min())) * per_unit))
        period = _period(xm, T) if counts else None
        every = f", period {period:.4g} s" if period is not None else ""
        if counts <= case.limit_cycle:
            decided_by_counts = True
            outcome, because = "stable", None
            reason = ("settled within one count: the measured position did not change over "
                      f"{_plural(case.windows, 'window')} ({judged * T:g} s)" if counts == 0 else
                      f"limit cycle of {_plural(counts, 'count')}{every} over the last {judged * T:g} s: within "
                      f"the {_plural(case.limit_cycle, 'count')} [quantization] limit_cycle allows")
        else:
            cycle = f"limit cycle of {_plural(counts, 'count')}{every}, more than the " \
                    f"{_plural(case.limit_cycle, 'count')} [quantization] limit_cycle allows"
            if outcome == "stable":
                decided_by_counts = True
                outcome = "unstable"
                reason = f"{cycle} (the position's own motion is below the tolerance {tolerance:.3g} {unit})"
            elif outcome == "unstable" and float(r["amplitude_last"]) <= 2.0 * float(r["amplitude_first"]):
                reason = f"{cycle}: {reason}"

    if linear is not None and because not in ("unexcited", "below tolerance") and not decided_by_counts and r["first_nonfinite"] is None:
        slowest = linear.slowest_period(n)
        moving = float(np.ptp(x[-judged:])) > tolerance
        # A settled window can only be a slow oscillation's extremum when the window is a small
        # part of its period (under 1e-3 of its peak-to-peak needs window < period / 20).
        short = case.window < slowest if outcome != "stable" else 20 * case.window < slowest
        # The last window starts at n (1 - 1/(2 windows)); a stable loop's slowest mode must have
        # decayed 1e4-fold there (the default tolerance is 1e-3 of the run's range).
        rho = linear.spectral_radius
        decay = (math.log(1e-4) / math.log(rho) / (1 - 1 / (2 * case.windows))) if 0 < rho < 1 else 0.0
        if short and moving:
            required = _round_up(max(2 * case.windows * slowest, decay) * T)
            outcome, because = "undecided", "too short"
            reason = (f"run at least {required:g} s: the linear part's slowest oscillation ({slowest * T:.4g} s "
                      f"period) is longer than the verdict window ({case.window * T:.4g} s), so the windows "
                      f"cannot show whether it grows or decays (default window: duration / {2 * case.windows}; "
                      f"or set [verdict] window >= {_round_up(slowest * T):g} s)")
        elif outcome == "undecided" and decay > 0:
            required = _round_up(max(decay, n + 1) * T)
            reason = f"run at least {required:g} s: {reason[:-len(': run longer')]}" \
                if reason.endswith(": run longer") else f"run at least {required:g} s: {reason}"
        elif outcome == "stable" and rho > 1 and not int(case.params["effects"]) & _NONLINEAR_BITS:
            # Nothing but the linear loop runs, and it grows: a growth still below the
            # tolerance (a slow one, or a mode the run barely excites) is no settling.
            # Required: the time it takes to grow 1e4-fold.
            required = _round_up(max(math.log(1e4) / math.log(rho), n + 1) * T)
            outcome, because = "undecided", "too short"
            reason = (f"run at least {required:g} s: the run settled within the tolerance, but its loop (linear, "
                      f"nothing else on) grows by {rho:.9g} per sample, which needs about that long to show")
    return SimVerdict(outcome=outcome, amplitude_first=float(r["amplitude_first"]),
                      amplitude_last=float(r["amplitude_last"]), growth=float(r["growth"]),
                      reason=reason, window=case.window, windows=case.windows, tolerance=float(tolerance),
                      first_nonfinite=r["first_nonfinite"], undecided_because=because,
                      required_duration=required, counts=counts, period=period)


def work(case: Case) -> int:
    """Rough cost of simulating a case, in units of about 3 ns on a 2020s x86 core: 10 per
    sample for the exact step and the records, plus 4 derivative evaluations per RK4
    substep when friction or a hand is on."""
    continuous = int(case.params["effects"]) & (EFFECTS["friction"] | EFFECTS["hand"])
    per_sample = 10 + (4 * int(case.params.get("substeps", 1)) if continuous else 0)
    return case.samples * per_sample


def _signals_for(effects: int) -> List[str]:
    names = list(_BASIC)
    for name, bit in EFFECTS.items():
        if effects & bit:
            names += [s for s in EFFECT_SIGNALS[name] if s not in names]
    return names


def _run_records(sim: Any, case: Case, names: List[str], bar: Any) -> Dict[str, NDArray[np.float64]]:
    """Run the case's samples, in chunks of about _CHUNK_WORK when a progress bar shows."""
    n = case.samples
    if bar is None:
        data: Dict[str, NDArray[np.float64]] = sim.run(n, names)
        return data
    chunk = max(64, _CHUNK_WORK * n // max(1, work(case)))
    # Each chunk goes straight into the run's arrays: the memory stays that of the arrays
    # plus one chunk (collecting the chunks and concatenating held the run twice).
    out = {k: np.empty(n, dtype=np.float64) for k in names}
    done = 0
    while done < n:
        step = min(chunk, n - done)
        piece = sim.run(step, names)
        for k in names:
            out[k][done:done + step] = piece[k]
        del piece
        done += step
        bar.update(step)
    return out


def memory_bytes(case: Case) -> int:
    """The bytes a case's arrays take (samples x recorded signals x 8): what a run holds for
    it, besides about one progress chunk (docs/scenes.md, "Length of a run")."""
    return case.samples * len(_signals_for(int(case.params["effects"]))) * 8


def available_memory() -> Optional[int]:
    """The memory the system can give without swapping (Linux MemAvailable), None if unknown."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


def check_memory(scene: Scene) -> int:
    """The bytes every case's arrays take together (a SimulationSet keeps them all); a
    MemoryError naming them, before anything runs, when that is more than the system has
    available (an over-committing kernel would otherwise kill the run midway)."""
    total = sum(memory_bytes(c) for c in scene.cases)
    free = available_memory()
    if free is not None and total > free:
        raise MemoryError(f"the {len(scene.cases)} case(s) need {total / 2 ** 30:.3g} GiB for their arrays "
                          f"(samples x signals x 8 bytes), {free / 2 ** 30:.3g} GiB are available")
    return total


def _run_case(case: Case, scene: Scene, bar: Any) -> Simulation:
    params = case.params
    try:
        sim = _core.Simulator(params)
    except ValueError as exc:  # the scene loader checks first; this is the C core's word
        raise SceneError(scene.source, case.label, f"the simulator refused this case: {exc}") from None
    names = _signals_for(int(params["effects"]))
    n = case.samples
    try:
        data = _run_records(sim, case, names, bar)
    except MemoryError:
        gib = n * len(names) * 8 / 2 ** 30
        raise MemoryError(f"case {case.label!r}: {n} samples x {len(names)} signals x 8 bytes = "
                          f"{gib:.3g} GiB do not fit in memory") from None
    rotary = scene.rotary
    units = signal_units(rotary)
    linear = linear_part(params, rotary, sim.filter_pole, case.duration)
    verdict = judge(data["x"], case, case.T, units["x"], x_measured=data["x_measured"], linear=linear)
    explanation = explain(scene.effects, verdict.outcome, linear)
    analytic: Optional[Union[Verdict, LoopVerdict]] = None
    ideal: Optional[Verdict] = None
    agrees: Optional[bool] = None
    note: Optional[str] = None
    dev = analysis_device(params, rotary, sim.filter_pole)
    if dev is not None:
        analytic = dev.verdict(params["K"], params["B"])
        if verdict.outcome != "undecided":
            agrees = verdict.stable == bool(analytic.stable)
        if not dev.loop.ideal:
            words = loop_words(params, dev)
            ideal_verdict = dev.ideal().verdict(params["K"], params["B"])
            assert isinstance(ideal_verdict, Verdict)
            ideal = ideal_verdict
            if bool(ideal.stable) and not bool(analytic.stable):
                note = (f"the paper's ideal loop (zwidth check --delay 0) is stable at these "
                        f"gains, but this loop ({words}) is {analytic.word}: {analytic.deciding_name}")
            elif not bool(ideal.stable) and bool(analytic.stable):
                note = f"the paper's ideal loop is not stable at these gains; this loop ({words}) is stable"
    elif int(params["effects"]) & _LINEAR_BITS and not int(params["effects"]) & ~_LINEAR_BITS:
        note = (f"no analytic verdict: a delay of {int(params.get('delay_samples', 0))} samples is beyond the "
                f"{MAX_DELAY} the loop analysis covers")
    signals = {k: data[k] for k in names if k not in _BASIC}
    return Simulation(label=case.label, t=data["t"], x=data["x"], v=data["v"],
                      x_measured=data["x_measured"], force=data["force"], signals=signals,
                      verdict=verdict, analytic=analytic, agrees=agrees, params=dict(params),
                      units={k: units[k] for k in names}, case=case, ideal=ideal, note=note, device=dev,
                      linear=linear, explanation=explanation)


def simulate(scene: Union[Scene, str, Path, Mapping[str, Any]], *, progress: bool = False,
             duration: Optional[float] = None) -> SimulationSet:
    """Simulate every case of a scene (a :class:`zwidth.scene.Scene`, or anything
    :func:`zwidth.load_scene` reads: a path, TOML text, a dict).

    ``progress=True`` shows a tqdm bar on stderr (the runs then go in chunks of
    ``_CHUNK_WORK`` = 30 million units of :func:`work`, about 0.1 s of computing each);
    ``duration`` [s] overrides the scene's.  Returns a
    :class:`SimulationSet`.  Invalid scenes raise :class:`zwidth.SceneError`.

    >>> sims = simulate("scenes/paper-fig15.toml")           # doctest: +SKIP
    >>> sims.by_label("P6").verdict.outcome, sims.by_label("P6").agrees   # doctest: +SKIP
    ('unstable', True)
    """
    sc = scene if isinstance(scene, Scene) else load_scene(scene)
    if duration is not None:
        d = float(duration)
        if not (math.isfinite(d) and d > 0):
            raise SceneError(sc.source, "scene.duration", f"must be > 0 s and finite, got {duration!r}")
        sc = sc.with_duration(d)
    check_memory(sc)
    bar: Any = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=sum(c.samples for c in sc.cases), unit="sample", unit_scale=True,
                   desc=sc.name, file=sys.stderr, leave=False, dynamic_ncols=True)
    try:
        sims = []
        for case in sc.cases:
            if bar is not None:
                bar.set_postfix_str(case.label, refresh=False)
            sims.append(_run_case(case, sc, bar))
    finally:
        if bar is not None:
            bar.close()
    return SimulationSet(sims, sc)

