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

For a linear scene (no effect, or only a delay of up to 8 samples and a velocity low-pass)
the analysis covers the loop: ``Simulation.analytic`` is zwidth's exact verdict of the loop
simulated (zwidth.loop, with the simulator's own filter pole) and ``agrees`` compares the
two; ``Simulation.note`` warns when the paper's ideal loop would say otherwise.
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

__all__ = ["simulate", "Simulation", "SimulationSet", "SimVerdict", "SIGNALS", "EFFECT_SIGNALS", "work"]

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
}

_LINEAR_BITS = sum(EFFECTS[e] for e in LINEAR_EFFECTS)


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
    vf = ("pole", float(filter_pole)) if effects & EFFECTS["velocity_filter"] else None
    return Device(params["m"], params["b"], params["T"], rotary=rotary, delay=delay, velocity_filter=vf)


def loop_words(params: Mapping[str, Any], dev: Device) -> str:
    """The simulated loop in words, its low-pass by the scene's cut-off (and the pole used)."""
    text = dev.loop.describe()
    if dev.loop.filter == "lowpass" and "cutoff_hz" in params:
        text = text.replace(f"low-pass pole {float(dev.loop.pole):g}",
                            f"low-pass {float(params['cutoff_hz']):g} Hz, pole {float(dev.loop.pole):.6g}")
    return text


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
        what = "grew" if aw > a1 else "did not shrink"
        return (f"not dying out: peak-to-peak {what} from {a1:.3g} to {aw:.3g} {unit} over {span} "
                f"(x {g:.6g} per sample)")
    return (f"still decaying (x {g:.6g} per sample) but {aw:.3g} {unit} > tolerance {tolerance:.3g} "
            f"{unit} in the last window: run longer")


def judge(x: NDArray[np.float64], case: Case, T: float, unit: str = "") -> SimVerdict:
    """The simulated verdict of a position record with the case's verdict settings."""
    x = np.asarray(x, dtype=np.float64)
    tolerance = case.tolerance
    if tolerance is None:
        finite = x[np.isfinite(x)]
        scale = float(finite.max()) - float(finite.min()) if finite.size else 0.0
        if not math.isfinite(scale):   # finite positions spanning more than DBL_MAX
            scale = float(np.finfo(np.float64).max)
        tolerance = DEFAULT_RELATIVE_TOLERANCE * scale
    r = dict(_core.sim_judge(x, case.window, case.windows, tolerance))
    nonfinite = int(r["first_nonfinite"])
    r["first_nonfinite"] = nonfinite if nonfinite < len(x) else None
    outcome = str(r["outcome"])
    return SimVerdict(outcome=outcome, amplitude_first=float(r["amplitude_first"]),
                      amplitude_last=float(r["amplitude_last"]), growth=float(r["growth"]),
                      reason=_reason(outcome, r, case.window, case.windows, tolerance, T, unit),
                      window=case.window, windows=case.windows, tolerance=float(tolerance),
                      first_nonfinite=r["first_nonfinite"])


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
    parts: Dict[str, List[NDArray[np.float64]]] = {k: [] for k in names}
    done = 0
    while done < n:
        step = min(chunk, n - done)
        piece = sim.run(step, names)
        for k in names:
            parts[k].append(piece[k])
        done += step
        bar.update(step)
    return {k: np.concatenate(v) if v else np.empty(0) for k, v in parts.items()}


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
    verdict = judge(data["x"], case, case.T, units["x"])
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
                note = (f"the paper's ideal loop (zwidth check without the loop options) is stable at these "
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
                      units={k: units[k] for k in names}, case=case, ideal=ideal, note=note, device=dev)


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

