# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The ``zwidth`` command: check gains, print limits and advice, draw figures.

Every number printed comes from zwidth's functions (the C core); this module parses,
formats and chooses exit codes.  ``python -m zwidth`` runs the same :func:`main`.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import sys
import textwrap
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, TextIO, Tuple, Union

from numpy.typing import NDArray

import numpy as np

from . import (BOUNDS, DELTA0, REGIONS, Device, ZwidthError, __version__, alpha_max, beta_interval,
               corner, extremes, hyperbola_top, spectral_radius, verdict)
from .box import PlantRange, parse_range
from .device import SENSITIVITY_WORDS, LoopNotSupported
from .normalized import plant_parts
from .results import Extremes
from .loop import DIFFERENTIATORS, Loop, normalized_loop, parse_velocity_filter

EXIT_OK = 0        #: stable, or the command succeeded
EXIT_UNSTABLE = 1  #: the checked gains are not (provably) stable
EXIT_USAGE = 2     #: bad command line (argparse)
EXIT_INVALID = 3   #: invalid values (zwidth.ZwidthError)
EXIT_PLOT = 4      #: cannot plot: matplotlib missing or file not writable

DESCRIPTION = """\
A drive renders stiffness K and damping B on a mass m with damping b, sampled every T;
zwidth says which (K, B) are stable for that plant (exact region of Wang et al. 2024)
and how m, b, T move the limits."""

EPILOG = """\
plant and gains (check, limits, advise, plot):
  real units (default): --m M (kg) or --J J (kg m^2, rotary), --b (N s/m | N m s/rad),
    --T (s), gains --K (N/m | N m/rad) and --B (N s/m | N m s/rad); nothing is filled in:
    a missing option is an error, unless --preset paper-drive names the paper's drive
    (J = 85.78e-7, b = 2.197e-3, T = 0.02; options given override it)
  normalized instead:   --delta = bT/m, --alpha = K T^2/m, --beta = B T/m

exit status:
  0  stable, or success
  1  the checked gains are not stable (check; advise with gains); marginal counts as not
  2  usage error (unknown option, bad number, missing or conflicting options)
  3  invalid values (m <= 0, T <= 0, b < 0, NaN, ...): the message names the option
  4  cannot plot (matplotlib missing: pip install zwidth[plot]; file not writable)
  simulate: 0 every case simulated stable, 1 some unstable, 5 none unstable but some
    undecided, 3 an invalid scene file or a run too large for memory

simulate takes a scene file instead of a plant (docs/scenes.md): 'zwidth simulate --help'.
identify takes a log of the drive and gives the plant box it measured (docs/identify.md):
'zwidth identify --help'; exit 6 when it identified the plant but has no box to certify.

every verdict and limit is for a stated loop: --delay N is required (0 the paper's ideal
loop, 1 most firmware: the force applied at the next tick), with --velocity-filter and
--differentiator where they apply; --preset paper-drive carries the paper's loop.

examples:
  zwidth limits --m 0.12 --b 0.8 --T 1e-3 --delay 1 --velocity-filter lowpass:100Hz
  zwidth check --J 85.78e-7 --b 2.197e-3 --T 0.02 --K 0.39 --B -1.36e-3 --delay 0
  zwidth check --delta 5.122 --alpha 23 --beta -1.5 --delay 0 --json
  zwidth limits --J 5e-6:5e-5 --b 2.0e-3:2.4e-3 --T 0.02 --delay 1   (ranges: every plant of the box, docs/box.md)
  zwidth advise --preset paper-drive --K 0.5 --B -1.36e-3
  zwidth plot region --delta 5.122 --alpha 23 --beta -1.5 --delay 0 -o region.png
  zwidth simulate scenes/paper-fig15.toml --plot fig15.png
  zwidth identify run.csv --time t --counts-per-unit 6366.2 --plot fit.png

'zwidth SUBCOMMAND --help' lists the keys of each subcommand's --json output."""

_PLANT_KEYS = """\
--json prints one JSON object (floats as numbers, NaN as null).  Common keys:
  command  the subcommand
  mode     "real" or "normalized" (--delta)
  plant    {m, b, T: number|null (null in normalized mode; m is J with --J),
            rotary: bool, delta: number, preset: "paper-drive"|null}
  units    {m, b, T, K, B: unit strings} or null in normalized mode
  loop     the loop analysed (--delay, --velocity-filter, --differentiator): {delay,
           differentiator, filter: "none"|"lowpass"|"average", cutoff (Hz) | null,
           pole | null, average | null, ideal: bool, text}
  With a loop other than the paper's (ideal false) every verdict and limit is that
  loop's; check adds ideal_loop {verdict, stable, spectral_radius}, limits adds
  ideal_loop {K_mmax, B_mmax, alpha_mmax, beta_mmax} and K_mmax_kept (legacy, corner,
  at_corner null), advise gives loop_influence (Device.loop_influence) instead of
  influence and trends (null)."""

_CHECK_EPILOG = _PLANT_KEYS + """
check keys:
  region         the region checked (--region)
  verdict        "stable" | "unstable" | "marginal" (within rounding of a boundary:
                 not proved stable)
  stable, marginal  bool;  exact_stable  bool, the exact region's verdict
  deciding       name of the first violated constraint (damping, stiffness, hyperbola,
                 line, passivity) or null;  deciding_text  it in words, or null
  violated       list of every violated (or unprovable) constraint
  spectral_radius  largest closed-loop pole modulus (stable iff < 1)
  K, B           the gains (null in normalized mode);  alpha, beta  normalized gains
  K_max          sup K stable at this B, exact region (null in normalized mode)
  B_range        {lo, hi, nonempty}: stable B at this K (null in normalized mode)
  alpha_max      sup alpha stable at this beta;  beta_range  {lo, hi, nonempty}
exit status 0 only when the gains are stable in --region (only exact and passivity
certify stability)."""

_LIMITS_EPILOG = _PLANT_KEYS + """
limits keys (real-unit ones null in normalized mode):
  K_mmax, B_at_K_mmax   largest stable K (a supremum) and the B at it
  K_p_max               largest stable K with B = 0
  B_mmax, B_mmin        stable B range as K -> 0+ (B_mmin = -b)
  alpha_mmax, beta_at_alpha_mmax, alpha_p_max, beta_mmax, beta_mmin  the same, normalized
  at_corner             K_mmax sits on the corner of hyperbola and line (delta > delta1)
  corner                {alpha, beta} where line meets hyperbola (null values: none)
  delta0, above_delta0  the critical delta0 and whether delta > delta0
  legacy                {K_mmax, B_at_K_mmax (null in normalized mode), alpha_mmax,
                         beta_at_alpha_mmax, region_unsafe: bool (delta > delta0: the
                         legacy region contains unstable gains), overstates_K_mmax: bool}"""

_ADVISE_EPILOG = _PLANT_KEYS + """
advise keys:
  influence   every field of Device.influence(): delta, K_mmax, B_mmax, m_K1, m_K2,
              K_mmax_at_m_K2, K_mmax_at_m_K1, m_K_match, T_B, T_0, m_0, m_B, b_0, b_BB,
              best_m_for_K (numbers), K_vs_m, K_vs_b, K_vs_T, B_vs_m, B_vs_b, B_vs_T
              (ints: -1 falls, 0 flat, +1 rises).  In normalized mode the plant is taken
              as m = 1, T = 1, b = delta: masses and periods are then multiples of the
              plant's m and T, dampings of m/T.
  trends, advice   strings
  gains       null without gains, else {K, B, alpha, beta, verdict, stable, marginal,
              deciding, spectral_radius, K_max, B_range: {lo, hi, nonempty},
              margins: {sigma, r}, certified: bool (stable, K <= sigma K_max(B) and every
              pole inside |z| < r: what the drive accepts),
              suggestions: [{change: "K"|"B"|"m"|"b"|"T", lo: number|null,
              hi: number|null, value: number|null, text}]}: for gains that are not
              certified, the certified interval of K at this B and of B at this K (closed,
              both ends certified) with the value nearest the current one, and the nearest
              certified m, b, T on a log grid
with plant-side parts (--actuator-tau, --hand, --stiffness, or --kappa, --lambda):
  influence, trends null; numerical influence instead (finite differences of the
  certified limits: Device.sensitivity()):
  sensitivity {K_mmax, B_mmax, K_unit, B_unit, loop, method, parameters: [{name ("m"|"J",
              "b", "T", "actuator_tau", "m_h", "b_h", "k_h", "stiffness"), value, unit,
              dK_mmax, dB_mmax (limit per parameter unit), elasticity_K, elasticity_B
              (% per %; null for a part at 0), K_trend, B_trend ("rises"|"falls"|"flat"),
              step, one_sided (a part at 0: forward difference)}]}
  K_mmax, B_mmax, B_at_K_mmax   this device's certified limits
  without_plant_parts {K_mmax, B_mmax}   the same plant and loop without the parts
  loop_influence   null for the paper's loop, else as without parts (every loop on this plant)
exit status 1 when gains are given and are not certified (not stable, or outside the
margins --sigma, default 0.8, and --r, default 0.999)."""

_PLOT_EPILOG = """\
kinds:
  region     the region in the (beta, alpha) plane with the legacy and passivity
             regions (needs the plant; gains, if given, are marked); with --delay,
             --velocity-filter or --differentiator: the ideal loop's region and the one
             your loop keeps (each grid point decided by the guarded check of that loop)
  extremes   alpha_mmax, beta_mmax and ratios against delta (no plant; --delta-min/max)
  influence  K_mmax and B_mmax against m, b and T around a real-unit plant
  device     a real-unit plant's stable (K, B) region, its limits and the advice
with plant-side parts (--actuator-tau, --hand, --stiffness; real-unit plant, any loop):
  region, device  the (B, K) region with the parts over the same plant and loop without
             them (each grid point by the guarded check; certified K_max(B) lines)
  influence  K_mmax and B_mmax against m, b, T, tau, m_h, b_h, k_h and k_p, one panel
             each (certified limits; the slopes of 'zwidth advise')
--json keys: command, kind, file, format ("png"|"pdf"|"svg"|"eps"|"ps"), bytes."""

_SIMULATE_DESCRIPTION = """\
Simulate a scene in the time domain (paper Fig. 13): the plant behind a zero-order hold,
sampled every T, the impedance controller and only the effects the scene file asks for
(quantization, friction, delay, saturation, velocity filter, hand, wall, knob, schedule,
Tustin's differentiator, a moving average of the velocity, an actuator lag).
Prints each case's simulated verdict beside the analytic verdict of the loop's linear part
(every scene: the loop without quantization, friction, saturation, the wall's or knob's
switching; for linear scenes, no effect or only [delay] of up to 8 samples,
[velocity_filter], [differentiator] and [average], zwidth's exact verdict of the loop simulated and whether they agree;
with a delay or filter also the paper's ideal loop's verdict), and where they differ one
line naming the effect that explains it.  Optionally writes the arrays and a figure."""

_SIMULATE_EPILOG = """\
the scene file (TOML; every key, unit and default in docs/scenes.md):
  [scene] name, description, duration   [plant] m | J, b, T   [controller] K, B | alpha, beta
  [reference] from, to, at   [initial] x, v   effects: [quantization] [friction] [delay]
  [saturation] [velocity_filter] [hand] [wall] [knob] [[schedule]]
  [differentiator] kind = "tustin"   [average] samples   [actuator] tau
  [integrator] substeps | step   [verdict] tolerance, window, windows   [[case]] label + overrides
  Values with units are strings: "0.1 kg", "23 N*s/m", "85.78e-7 kg*m^2", "45 deg".

verdict of a case (zw_sim_judge on the position; default: 8 windows over the run's second half):
  unstable   the position overflowed
  undecided  "nothing excites the loop": the position never moved (give [initial] or a step)
  stable     otherwise, the last window's peak-to-peak <= tolerance (default 1e-3 of the run's range)
  unstable   otherwise, unless the peak-to-peak strictly shrinks from each window to the next
             (a growing or sustained oscillation, a limit cycle, a drift: not dying out)
  undecided  shrinking in every window but not settled: "run at least N s"
  then: with [quantization] the measured motion over those windows in counts decides: at most
  limit_cycle counts (default 1) is stable ("limit cycle of n counts"), more is unstable; and
  "undecided: run at least N s" when the linear part's slowest oscillation is longer than a
  window (N from its poles: windows of one period, and its decay below the tolerance)

output files:
  --out RUN.npz   every case's arrays: keys "<label>/<signal>" (t, x, v, x_measured, force and
                  the per-effect signals), and "labels"
  --out RUN.csv   one row per sample: case, then the signals (header with units)
  --plot FIG.png|.svg  responses with simulated and analytic verdicts (paper Fig. 15); for a
                  knob, planned and rendered stiffness against position (Fig. 23)
  A progress bar goes to stderr for long runs (--no-progress: none).

--json keys:
  command   "simulate"
  scene     {name, description, file, duration, rotary, linear, effects: [names], units}
  cases     [{label, description, samples, T, duration, params (the flat scene dict, SI
             units; infinities as null), normalized: {delta, alpha, beta} | null,
             verdict: {outcome, amplitude_first, amplitude_last, growth, reason, window,
             windows, tolerance, first_nonfinite, undecided_because ("unexcited" | "below
             tolerance" | "too short" | "decaying" | null), required_duration (s | null), counts, period
             (quantized: the limit cycle's counts and period | null)}, analytic: {verdict, stable, marginal,
             deciding, spectral_radius, loop (as in 'zwidth check --help'), legacy_stable
             (null with a delay or filter), ideal_loop: {verdict, stable} | null} | null
             (nonlinear scenes), agrees: bool | null, note: a warning | null,
             linear_part: {piece, K, B, m, b, k, verdict, stable, spectral_radius},
             explanation: the effect that explains simulated != linear part | null}]
  summary   {cases, stable, unstable, undecided, compared, agree}
  memory    bytes of every case's arrays together (stated before the run on stderr from 1 GiB)
  out, plot  the files written, or null

exit status (the simulated verdicts, of the loop with all its effects; the linear part's
verdict is printed beside them and does not change it):
  0  every case simulated stable
  1  some case simulated unstable
  5  no case unstable, but some undecided (nothing excites the loop, or the run is too short)
  2  usage error (bad option, --out not .npz/.csv or its directory missing or not writable,
     --plot not .png/.svg); checked before simulating
  3  invalid scene: the message names the file and the key; or out of memory (a case may
     have at most 2**28 samples, and its arrays must fit in memory)
  4  cannot plot (matplotlib missing: pip install zwidth[plot]; file not writable)
  130  interrupted (Ctrl-C)

examples:
  zwidth simulate scenes/paper-fig15.toml --plot fig15.png
  zwidth simulate scenes/knob-legacy.toml --out knob.npz --plot knob.png
  zwidth simulate scenes/wall-hand.toml --duration "5 s" --json"""

# Progress bar for runs of about a second or more (zwidth.sim.work units, ~3 ns each).
_PROGRESS_WORK = 300_000_000

_BOUND_TEXT = {
    "damping": "damping: beta > -delta (B > -b: the total damping b + B must stay positive)",
    "stiffness": "stiffness: alpha > 0 (K > 0)",
    "hyperbola": "hyperbola: alpha < f(beta), the curved upper bound of paper eq (10)",
    "line": ("line: alpha < L(beta) = 4(1 + e)/d12 - 2 beta, the straight bound of eq (10) "
             "that appears for delta > delta0 (the legacy region misses it)"),
    "passivity": "passivity: K T/2 < b - |B| (eq (16))",
}


#: Why a verdict or limit needs the loop stated (exit 2 when it is not).
LOOP_NOT_STATED = ("the loop is not stated: give --delay N, the samples between measuring the position "
                   "and applying its force (--delay 0 for the paper's ideal loop; most firmware computes "
                   "during the period and applies at the next tick: --delay 1), and --velocity-filter if "
                   "the velocity is filtered (lowpass:100Hz, average:4); --preset paper-drive states the "
                   "paper's loop")


class _Usage(Exception):
    """A usage error found after parsing (reported through parser.error, exit 2)."""


class _PlotError(Exception):
    """Cannot plot (exit 4)."""


@dataclasses.dataclass
class _Outcome:
    """What a subcommand found: exit status, the --json object, the human-readable lines."""

    status: int
    data: Dict[str, Any]
    lines: List[str]


def _number(text: str) -> float:
    return float(text)


_number.__name__ = "number"  # argparse says "invalid number value: 'abc'"


def _fmt(x: Any) -> str:
    return f"{float(x) + 0.0:.6g}"  # + 0.0: print -0 (beta_mmin = -delta at delta = 0) as 0


def _jsonable(value: Any) -> Any:
    """numpy scalars to Python; NaN and infinities to None (JSON has no such numbers)."""
    if isinstance(value, dict):
        return {k: _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return [_jsonable(v) for v in value.tolist()]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        f = float(value)
        return f if math.isfinite(f) else None
    return value


# ---------------------------------------------------------------------------------------
# The plant: real units or normalized
# ---------------------------------------------------------------------------------------


@dataclasses.dataclass
class _Plant:
    """What the options describe.  Real mode has a Device; normalized mode only delta."""

    delta: float
    device: Optional[Device]
    K: Optional[float] = None      # gains as given (real mode)
    B: Optional[float] = None
    alpha: Optional[float] = None  # gains as given (normalized mode) or normalized image
    beta: Optional[float] = None
    loop: Loop = dataclasses.field(default_factory=Loop)  # what the drive runs (--delay, ...)
    preset: Optional[str] = None   # --preset, when the plant came from one
    loop_from_preset: bool = False  # no --delay: the preset's loop
    kappa: float = 0.0             # normalized plant-side parts (--kappa, --lambda; normalized mode)
    lambda_: float = 0.0

    @property
    def real(self) -> bool:
        return self.device is not None

    @property
    def rotary(self) -> bool:
        return self.device is not None and self.device.is_rotary

    @property
    def has_gains(self) -> bool:
        return self.alpha is not None

    def units(self) -> Optional[Dict[str, str]]:
        return None if self.device is None else self.device.units

    @property
    def mass(self) -> str:
        return "m" if self.device is None else self.device.mass_symbol

    def summary(self) -> Dict[str, Any]:
        dev = self.device
        return {"m": None if dev is None else dev.m, "b": None if dev is None else dev.b,
                "T": None if dev is None else dev.T, "rotary": self.rotary, "delta": self.delta,
                "preset": self.preset,
                **({"actuator_tau": dev.actuator_tau, "hand": list(dev.hand), "stiffness": dev.stiffness}
                   if dev is not None and self.parts else {}),
                **({"kappa": self.kappa, "lambda": self.lambda_} if dev is None and self.parts else {})}

    def loop_kwargs(self) -> Dict[str, Any]:
        """The normalized functions' loop keywords, with the plant's kappa and lambda_ (of
        --kappa, --lambda, or of a device's parts: (k_p + k_h) T^2 / M, tau / T)."""
        lp = self.loop
        kappa, lam = self.kappa, self.lambda_
        if self.device is not None and self.device.has_plant_parts:
            kappa, lam = self.device.normalized_parts()
        return {"delay": lp.delay, "differentiator": lp.differentiator,
                "filter_pole": 0.0 if lp.pole is None else lp.pole, "average": lp.average,
                "kappa": kappa, "lambda_": lam}

    @property
    def parts(self) -> bool:
        """Plant-side parts present (--actuator-tau, --hand, --stiffness, or --kappa, --lambda
        normalized): the general loop."""
        if self.device is None:
            return self.kappa != 0.0 or self.lambda_ != 0.0
        return self.device.has_plant_parts

    @property
    def general(self) -> bool:
        """Decided by the general loop: another loop than the paper's, or plant-side parts."""
        return (not self.loop.ideal) or self.parts

    def parts_text(self) -> str:
        d = self.device
        if not self.parts:
            return ""
        if d is None:
            out = ([f"stiffness kappa = (k_p + k_h) T^2/M = {_fmt(self.kappa)}"] if self.kappa else []) + (
                [f"actuator lag lambda = tau/T = {_fmt(self.lambda_)}"] if self.lambda_ else [])
            return "\nPlant-side parts (normalized): " + "; ".join(out) + " (M = m + m_h)"
        u = self.units() or {}
        m_h, b_h, k_h = d.hand
        out = []
        if float(d.actuator_tau) != 0.0:
            out.append(f"actuator lag tau = {_fmt(d.actuator_tau)} s")
        if float(d.stiffness) != 0.0:
            out.append(f"device stiffness k_p = {_fmt(d.stiffness)} {u['K']}")
        if float(m_h) != 0.0 or float(b_h) != 0.0 or float(k_h) != 0.0:
            out.append(f"hand m_h = {_fmt(m_h)} {u['m']}, b_h = {_fmt(b_h)} {u['b']}, k_h = {_fmt(k_h)} {u['K']}")
        return "\nPlant-side parts: " + "; ".join(out) + f" (gains normalized by {self.mass} + m_h)"

    def header(self) -> str:
        """The plant (the loop is the line before it: loop_line, printed by _emit)."""
        loop = self.parts_text()
        if self.device is None:
            return f"Plant (normalized): delta = bT/m = {_fmt(self.delta)}" + loop
        u = self.units() or {}
        d = self.device
        preset = "" if self.preset is None else f"Preset {self.preset}: the paper's drive, load motor short-circuited\n"
        held = any(float(v) != 0.0 for v in d.hand[:2])
        ratio = f"(b + b_h)T/({self.mass} + m_h)" if held else f"bT/{self.mass}"
        return (preset + f"Plant: {self.mass} = {_fmt(d.m)} {u['m']}, b = {_fmt(d.b)} {u['b']}, "
                f"T = {_fmt(d.T)} s  ->  delta = {ratio} = {_fmt(self.delta)}" + loop)

    def gains_text(self) -> str:
        if self.device is None:
            return f"alpha = {_fmt(self.alpha)}, beta = {_fmt(self.beta)}"
        u = self.units() or {}
        return f"K = {_fmt(self.K)} {u['K']}, B = {_fmt(self.B)} {u['B']}"


#: Named plants for --preset (only when asked for: nothing is filled in silently).
PRESETS: Dict[str, Dict[str, float]] = {
    # the paper's experimental drive, load motor short-circuited (rotary)
    "paper-drive": {"J": 85.78e-7, "b": 2.197e-3, "T": 0.02},
}


def _apply_preset(args: argparse.Namespace) -> None:
    """Fill the plant options the preset names where they were not given (the options
    given override it); refused with a normalized plant."""
    name = getattr(args, "preset", None)
    if name is None:
        return
    norm_given = [f"--{n}" for n in ("delta", "alpha", "beta") if getattr(args, n) is not None]
    if norm_given:
        raise _Usage(f"--preset {name} is a real-unit plant: it cannot be combined with {', '.join(norm_given)}")
    preset = PRESETS[name]
    if getattr(args, "delay", None) is None:
        args.delay = 0  # the paper's drive runs the paper's loop: the preset states it
        args.loop_from_preset = True
    if args.m is None and args.J is None:
        args.J = preset["J"]
    for key in ("b", "T"):
        if getattr(args, key) is None:
            setattr(args, key, preset[key])


def _plant(args: argparse.Namespace, *, need_plant: bool = True) -> Optional[_Plant]:
    """Build the plant from the options (usage errors as _Usage, values as ZwidthError)."""
    _apply_preset(args)
    real_given = [f"--{n}" for n in ("m", "J", "b", "T", "K", "B") if getattr(args, n) is not None]
    norm_given = [f"--{n}" for n in ("delta", "alpha", "beta") if getattr(args, n) is not None]
    if real_given and norm_given:
        raise _Usage(f"give either a real-unit plant or a normalized one: {', '.join(real_given)} "
                     f"cannot be combined with {', '.join(norm_given)}")
    if not real_given and not norm_given:
        if need_plant:
            raise _Usage("no plant: give --m (or --J), --b and --T (or --preset paper-drive), or --delta "
                         "for the normalized space")
        return None
    norm_parts = [o for o, n in (("--kappa", "kappa"), ("--lambda", "lambda_")) if getattr(args, n, None) is not None]
    if norm_parts and real_given:
        raise _Usage(f"{', '.join(norm_parts)} describe a normalized plant (with --delta); a real-unit plant takes "
                     f"--actuator-tau, --hand, --stiffness")
    if norm_given:
        parts_given = [f"--{n.replace('_', '-')}" for n in ("actuator_tau", "hand", "stiffness")
                       if getattr(args, n, None) is not None]
        if parts_given:
            raise _Usage(f"{', '.join(parts_given)} need a real-unit plant (--m or --J, --b, --T); normalized, "
                         f"give --kappa (k_p + k_h) T^2/M and --lambda tau/T")
        if args.delta is None:
            raise _Usage("--alpha and --beta need --delta")
        if (args.alpha is None) != (args.beta is None):
            raise _Usage("give both --alpha and --beta (or neither)")
        require_loop(args, normalized=True)
        extremes(args.delta)  # validates delta (ZwidthError naming it)
        kappa = getattr(args, "kappa", None) or 0.0
        lam = getattr(args, "lambda_", None) or 0.0
        plant_parts(args.command, kappa, lam, "raise")  # validates them (ZwidthError naming them)
        return _Plant(delta=float(args.delta), device=None, alpha=args.alpha, beta=args.beta,
                      loop=_normalized_loop(args), kappa=float(kappa), lambda_=float(lam))
    missing = [name for name, ok in (("--m (or --J)", args.m is not None or args.J is not None),
                                     ("--b", args.b is not None), ("--T", args.T is not None))
               if not ok]
    if missing:
        raise _Usage(f"the plant needs {', '.join(missing)} (or --preset paper-drive)")
    if (args.K is None) != (args.B is None):
        raise _Usage("give both --K and --B (or neither)")
    require_loop(args)
    loop_options = _device_loop_options(args)
    parts = _plant_part_options(args)
    dev = (Device(args.J, args.b, args.T, rotary=True, **loop_options, **parts) if args.J is not None
           else Device(args.m, args.b, args.T, **loop_options, **parts))
    plant = _Plant(delta=float(dev.delta), device=dev, K=args.K, B=args.B, loop=dev.loop,
                   preset=getattr(args, "preset", None), loop_from_preset=getattr(args, "loop_from_preset", False))
    if args.K is not None:
        n = dev.normalize(args.K, args.B)
        plant.alpha, plant.beta = float(n.alpha), float(n.beta)
    return plant


def require_loop(args: argparse.Namespace, *, normalized: bool = False) -> None:
    """Every verdict and limit is for a stated loop: --delay (or a preset's loop), else a
    usage error saying what to give and why (never the paper's loop by default). A
    mistyped loop option is named first, as zwidth-limits does."""
    if getattr(args, "velocity_filter", None) is not None:
        vf = _velocity_filter(args)
        if normalized and vf is not None and vf[0] == "lowpass":
            raise _Usage(_HZ_NEEDS_PERIOD)
    if getattr(args, "delay", None) is None:
        raise _Usage(LOOP_NOT_STATED)


def loop_line(loop: Loop, from_preset: bool = False) -> str:
    """The first line of every output: the loop judged, in full."""
    return f"Loop: {loop.statement()}" + (", from --preset paper-drive" if from_preset else "")


def _velocity_filter(args: argparse.Namespace) -> Optional[Tuple[str, Any]]:
    if args.velocity_filter is None:
        return None
    try:
        kind, value = parse_velocity_filter(args.velocity_filter)
    except ValueError as exc:
        raise _Usage(f"argument --velocity-filter: {exc}") from None
    return None if kind == "none" else (kind, value)


def _device_loop_options(args: argparse.Namespace) -> Dict[str, Any]:
    return {"delay": args.delay, "velocity_filter": _velocity_filter(args),
            "differentiator": args.differentiator}


def parse_hand(text: str) -> Tuple[Union[float, PlantRange], ...]:
    """--hand M_H,B_H,K_H: three numbers (one hand), or any of them a range LO:HI (a box of
    hands: check and limits over every plant of it, box_cli)."""
    parts = text.split(",")
    if len(parts) != 3:
        raise argparse.ArgumentTypeError(f"--hand needs M_H,B_H,K_H (kg, N s/m, N/m; each a number or LO:HI), "
                                         f"got {text!r}")
    try:
        return tuple(parse_range(v) for v in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--hand needs M_H,B_H,K_H (each a number or LO:HI), got {text!r}") from None


def _plant_part_options(args: argparse.Namespace) -> Dict[str, Any]:
    """The Device keywords of --actuator-tau, --hand, --stiffness (absent: none)."""
    out: Dict[str, Any] = {}
    if getattr(args, "actuator_tau", None) is not None:
        out["actuator_tau"] = args.actuator_tau
    if getattr(args, "hand", None) is not None:
        out["hand"] = args.hand
    if getattr(args, "stiffness", None) is not None:
        out["stiffness"] = args.stiffness
    return out


_HZ_NEEDS_PERIOD = ("argument --velocity-filter: a cut-off in Hz needs the period: give a real-unit plant "
                    "(--m, --b, --T), or the pole in the normalized space (pole:A, A = exp(-2 pi f_c T))")


def _normalized_loop(args: argparse.Namespace) -> Loop:
    vf = _velocity_filter(args)
    if vf is not None and vf[0] == "lowpass":
        raise _Usage(_HZ_NEEDS_PERIOD)
    pole = vf[1] if vf is not None and vf[0] == "pole" else 0.0
    average = vf[1] if vf is not None and vf[0] == "average" else None
    return normalized_loop("check", args.delay, pole, average, args.differentiator)


def _option_of(exc: ZwidthError) -> Optional[str]:
    """The command-line option of the parameter an error names (J for a rotary plant)."""
    if exc.parameter in ("velocity_filter", "filter_pole", "average", "cutoff"):
        return "--velocity-filter"
    if exc.parameter in ("actuator_tau", "stiffness"):
        return f"--{exc.parameter.replace('_', '-')}"
    if exc.parameter in ("kappa", "lambda_"):
        return f"--{exc.parameter.rstrip('_')}"
    if exc.parameter is not None and exc.parameter.startswith("hand"):
        return "--hand"
    return None if exc.parameter is None else f"--{exc.parameter}"


# ---------------------------------------------------------------------------------------
# Subcommands: each returns an _Outcome (exit status, JSON object, human text)
# ---------------------------------------------------------------------------------------


def _interval(iv: Any) -> Dict[str, Any]:
    return {"lo": iv.lo, "hi": iv.hi, "nonempty": bool(iv.nonempty)}


def _violated(v: Any) -> List[str]:
    return [name for name, bit in BOUNDS.items() if int(v.violated) & bit]


_LOOP_BOUNDARY_TEXT = {
    "z=1": "a real root leaves the unit circle at z = 1 (static divergence: the stiffness drifts away)",
    "z=-1": "a real root leaves the unit circle at z = -1 (oscillation at the Nyquist frequency 1/(2T))",
    "complex": "a complex pair of roots leaves the unit circle (oscillation at {f})",
}


def _loop_deciding_text(v: Any) -> Optional[str]:
    name = str(v.deciding_name)
    if not name:
        return None
    if name.startswith("complex"):
        return _LOOP_BOUNDARY_TEXT["complex"].format(f=name[len("complex pair at "):])
    return _LOOP_BOUNDARY_TEXT.get(name, name)


def cmd_check_loop(args: argparse.Namespace, plant: _Plant) -> _Outcome:
    """check for a loop other than the paper's: the guarded verdict of that loop, the
    deciding boundary, its spectral radius, and the ideal loop's verdict beside it."""
    if args.region != "exact":
        raise _Usage(f"--region {args.region} is one of the paper's regions of its ideal loop; a loop with "
                     f"{plant.loop.describe()} has only its exact region")
    dev, d = plant.device, plant.delta
    alpha, beta = float(plant.alpha), float(plant.beta)  # type: ignore[arg-type]
    if dev is not None:
        K, B = float(plant.K), float(plant.B)  # type: ignore[arg-type]
        v = dev.verdict(K, B)
        rho = dev.spectral_radius(K, B)
        ideal_v = dev.ideal().verdict(K, B)
        ideal_rho = dev.ideal().spectral_radius(K, B)
    else:
        kw = plant.loop_kwargs()
        v = verdict(d, alpha, beta, **kw)
        rho = spectral_radius(d, alpha, beta, **kw)
        ideal_v = verdict(d, alpha, beta)
        ideal_rho = spectral_radius(d, alpha, beta)
    word = v.word
    deciding = str(v.deciding_name) or None
    text = _loop_deciding_text(v)
    k_max: Any = None
    b_range: Any = None
    if dev is not None:
        k_max = dev.k_max(B)
        b_range = _interval(dev.b_range(K))
    kw = plant.loop_kwargs() if dev is None else _device_pole_kwargs(plant)
    # the normalized functions on the plant's (delta, kappa, lambda): informational beside the
    # device's own certified K_max / B range (its kappa, lambda rounded once more here)
    a_max: Any = alpha_max(d, beta, **kw)
    beta_range: Any = _interval(beta_interval(d, alpha, **kw))
    data = {
        "region": "exact", "verdict": word, "stable": bool(v.stable),
        "marginal": bool(v.marginal), "deciding": deciding, "deciding_text": text, "violated": [],
        "exact_stable": bool(v.stable), "spectral_radius": rho,
        "K": plant.K, "B": plant.B, "alpha": alpha, "beta": beta,
        "K_max": k_max, "B_range": b_range, "alpha_max": a_max, "beta_range": beta_range,
        "ideal_loop": {"verdict": ideal_v.word, "stable": bool(ideal_v.stable), "spectral_radius": ideal_rho},
    }
    lines = [plant.header(), f"Gains: {plant.gains_text()}"
             + (f"  ->  alpha = {_fmt(alpha)}, beta = {_fmt(beta)}" if plant.real else "")]
    lines.append(f"Verdict (exact, this loop): {word.upper()}")
    if text:
        lines += textwrap.wrap(f"deciding boundary: {text}", 92, initial_indent="  ", subsequent_indent="    ")
    if word == "marginal":
        lines.append("  marginal: within rounding error of the boundary, so not proved stable")
    lines.append(f"  spectral radius = {_fmt(rho)} (stable iff < 1)")
    lines.append(f"  the paper's ideal loop (no delay, no filter{', no plant-side parts' if plant.parts else ''}) would be {ideal_v.word} here "
                 f"(spectral radius {_fmt(ideal_rho)})")
    if bool(ideal_v.stable) and not bool(v.stable):
        lines.append(f"  warning: the ideal-loop analysis calls these gains stable; the loop the drive runs "
                     f"({plant.loop.describe()}{', with its plant-side parts' if plant.parts else ''}) does not")
    if dev is not None:
        u = plant.units() or {}
        lines.append(f"  K_max at this B = {_fmt(k_max)} {u['K']} (this loop)")
        lines.append("  B range at this K: " + (f"{_fmt(b_range['lo'])} < B < {_fmt(b_range['hi'])} {u['B']}"
                                                 if b_range["nonempty"] else "none (no B is stable at this K)")
                     + " (this loop; the widest stable interval)")
    else:
        lines.append(f"  alpha_max at this beta = {_fmt(a_max)} (this loop)")
        lines.append("  beta range at this alpha: " + (
            f"{_fmt(beta_range['lo'])} < beta < {_fmt(beta_range['hi'])}"
            if beta_range["nonempty"] else "none (no beta is stable at this alpha)") + " (this loop)")
    data["delay_1"], more = _delay1_check(plant, bool(v.stable))
    lines += more
    return _Outcome(EXIT_OK if bool(v.stable) else EXIT_UNSTABLE, data, lines)


_DELAY1 = "with 1 sample of delay (most firmware applies the force at the next tick)"


def _delay1_check(plant: _Plant, stable: bool) -> Tuple[Optional[Dict[str, Any]], List[str]]:
    """For a loop stated without delay: the same gains with 1 sample of delay (the JSON
    object and the lines; a warning when only the undelayed loop is stable).  None, [] for
    a delayed loop."""
    if plant.loop.delay != 0:
        return None, []
    if plant.device is not None:
        d1 = plant.device.with_delay(1)
        K, B = float(plant.K), float(plant.B)  # type: ignore[arg-type]
        v, rho, limit = d1.verdict(K, B), d1.spectral_radius(K, B), d1.k_max(B)
        limit_text = f"K_max at this B = {_fmt(limit)} {(plant.units() or {})['K']}"
        data = {"verdict": v.word, "stable": bool(v.stable), "spectral_radius": rho, "K_max": limit}
    else:
        kw = {**_device_pole_kwargs(plant), "delay": 1}
        alpha, beta = float(plant.alpha), float(plant.beta)  # type: ignore[arg-type]
        v = verdict(plant.delta, alpha, beta, **kw)
        rho, limit = spectral_radius(plant.delta, alpha, beta, **kw), alpha_max(plant.delta, beta, **kw)
        limit_text = f"alpha_max at this beta = {_fmt(limit)}"
        data = {"verdict": v.word, "stable": bool(v.stable), "spectral_radius": rho, "alpha_max": limit}
    lines = [f"  {_DELAY1}: {v.word.upper()} (spectral radius {_fmt(rho)}; {limit_text})"]
    if stable and not bool(v.stable):
        lines += textwrap.wrap("warning: these gains are stable only if the force is applied in the sample "
                               "its position is measured in (--delay 0); with 1 sample of delay they are not. "
                               "Check when your firmware applies the force.", 92,
                               initial_indent="  ", subsequent_indent="    ")
    return data, lines


def _delay1_limits(plant: _Plant, K_mmax: float) -> Tuple[Optional[Dict[str, Any]], List[str]]:
    """For a loop stated without delay: the same plant's limits with 1 sample of delay
    (JSON object, lines); K_mmax is this loop's (real units, or alpha_mmax normalized)."""
    if plant.loop.delay != 0:
        return None, []
    if plant.device is not None:
        x: Any = plant.device.with_delay(1).extremes()
        u = plant.units() or {}
        top, at = float(x.K_mmax), float(x.B_at_K_mmax)
        text = f"K_mmax = {_fmt(top)} {u['K']} at B = {_fmt(at)} {u['B']}"
        data = {"K_mmax": top, "B_at_K_mmax": at, "B_mmax": float(x.B_mmax)}
    else:
        x = extremes(plant.delta, **{**_device_pole_kwargs(plant), "delay": 1})
        top, at = float(x.alpha_mmax), float(x.beta_at_alpha_mmax)
        text = f"alpha_mmax = {_fmt(top)} at beta = {_fmt(at)}"
        data = {"alpha_mmax": top, "beta_at_alpha_mmax": at, "beta_mmax": float(x.beta_mmax)}
    share = f" ({100 * top / K_mmax:.4g} % of this loop's)" if K_mmax > 0.0 else ""
    return data, ["", f"{_DELAY1[0].upper()}{_DELAY1[1:]}, certified:", f"  {text}{share}"]


def _device_pole_kwargs(plant: _Plant) -> Dict[str, Any]:
    """The normalized loop keywords of a real-unit plant (its low-pass as the pole a)."""
    kw = plant.loop_kwargs()
    if plant.device is not None and plant.device.filter_pole is not None:
        kw["filter_pole"] = float(plant.device.filter_pole)
    return kw


@dataclasses.dataclass
class _ScaledExtremes:
    """A device's extremes in normalized units (cmd_limits_loop with plant-side parts)."""

    alpha_mmax: float
    beta_at_alpha_mmax: float
    alpha_p_max: float
    beta_mmax: float
    beta_mmin: float


def cmd_limits_loop(args: argparse.Namespace, plant: _Plant) -> _Outcome:
    """limits of a loop other than the paper's, beside the ideal loop's."""
    d, dev = plant.delta, plant.device
    kw = _device_pole_kwargs(plant)
    ideal = extremes(float(dev.ideal().delta)) if dev is not None and plant.parts else extremes(d)
    computed = extremes(d, **kw) if dev is None or not plant.parts else None
    real: Dict[str, Any] = dict.fromkeys(("K_mmax", "B_at_K_mmax", "K_p_max", "B_mmax", "B_mmin"))
    ideal_real: Dict[str, Any] = dict.fromkeys(("K_mmax", "B_mmax"))
    if dev is not None:
        lim = dev.extremes()
        real = {k: getattr(lim, k) for k in real}
        il = dev.ideal().extremes()
        ideal_real = {"K_mmax": il.K_mmax, "B_mmax": il.B_mmax}
    ext: Any  # the loop's extremes, or the device's scaled to normalized units
    if computed is None:
        # with plant-side parts: the normalized values of the device's certified limits
        # (scales M / T^2 and M / T, M = m + m_h), and the share of the ideal K_mmax in real units
        norm = dev.normalize(1.0, 1.0)  # type: ignore[union-attr]
        ka, kb = float(norm.alpha), float(norm.beta)
        ext = _ScaledExtremes(float(real["K_mmax"]) * ka, float(real["B_at_K_mmax"]) * kb,
                              float(real["K_p_max"]) * ka, float(real["B_mmax"]) * kb, float(real["B_mmin"]) * kb)
        kept = float(real["K_mmax"]) / float(ideal_real["K_mmax"])
    else:
        ext = computed
        kept = float(ext.alpha_mmax) / float(ideal.alpha_mmax)
    data = {
        **real,
        "alpha_mmax": ext.alpha_mmax, "beta_at_alpha_mmax": ext.beta_at_alpha_mmax,
        "alpha_p_max": ext.alpha_p_max, "beta_mmax": ext.beta_mmax, "beta_mmin": ext.beta_mmin,
        "at_corner": None, "corner": None, "delta0": DELTA0, "above_delta0": d > DELTA0, "legacy": None,
        "ideal_loop": {**ideal_real, "alpha_mmax": ideal.alpha_mmax, "beta_mmax": ideal.beta_mmax},
        "K_mmax_kept": kept,
    }
    lines = [plant.header(), "", f"Limits of this loop ({plant.loop.describe()}; certified, D-decomposition)"]
    if dev is not None:
        u = plant.units() or {}
        lines += [
            f"  K_mmax   = {_fmt(real['K_mmax'])} {u['K']} at B = {_fmt(real['B_at_K_mmax'])} {u['B']}",
            f"  K with B = 0 (stiffness only): K < {_fmt(real['K_p_max'])} {u['K']}",
            f"  B range  : {_fmt(real['B_mmin'])} < B < {_fmt(real['B_mmax'])} {u['B']} (as K -> 0+)",
            f"  the paper's ideal loop: K_mmax = {_fmt(ideal_real['K_mmax'])} {u['K']}, "
            f"B_mmax = {_fmt(ideal_real['B_mmax'])} {u['B']}",
        ]
    else:
        lines += [
            f"  alpha_mmax = {_fmt(ext.alpha_mmax)} at beta = {_fmt(ext.beta_at_alpha_mmax)}",
            f"  alpha with beta = 0 (stiffness only): alpha < {_fmt(ext.alpha_p_max)}",
            f"  beta range : {_fmt(ext.beta_mmin)} < beta < {_fmt(ext.beta_mmax)} (as alpha -> 0+)",
            f"  the paper's ideal loop: alpha_mmax = {_fmt(ideal.alpha_mmax)}, beta_mmax = {_fmt(ideal.beta_mmax)}",
        ]
    lines.append(f"  this loop keeps {100 * kept:.4g} % of the ideal loop's largest stiffness"
                 + (" (the paper's loop on the same device without its plant-side parts)" if plant.parts else ""))
    data["delay_1"], more = _delay1_limits(plant, float(real["K_mmax"] if dev is not None else ext.alpha_mmax))
    lines += more
    return _Outcome(EXIT_OK, data, lines)


def cmd_check(args: argparse.Namespace, plant: _Plant) -> _Outcome:
    """Verdict of one gain pair, with the deciding constraint, radius and local limits."""
    if plant.general:
        return cmd_check_loop(args, plant)
    region = args.region
    dev, d = plant.device, plant.delta
    alpha, beta = float(plant.alpha), float(plant.beta)  # type: ignore[arg-type]
    if dev is not None:
        K, B = float(plant.K), float(plant.B)  # type: ignore[arg-type]
        v = dev.verdict(K, B, region=region)
        exact_v = v if region == "exact" else dev.verdict(K, B)
        rho = dev.spectral_radius(K, B)
        k_max: Any = dev.k_max(B)
        b_range: Any = _interval(dev.b_range(K))
    else:
        v = verdict(d, alpha, beta, region=region)
        exact_v = v if region == "exact" else verdict(d, alpha, beta)
        rho = spectral_radius(d, alpha, beta)
        k_max, b_range = None, None
    a_max = alpha_max(d, beta)
    beta_range = _interval(beta_interval(d, alpha))
    word = v.word
    deciding = str(v.deciding_name) or None
    text_of = _BOUND_TEXT.get(deciding or "") if region == "exact" else (
        f"the {deciding} bound of the '{region}' region" if deciding else None)
    data = {
        "region": region, "verdict": word, "stable": bool(v.stable), "marginal": bool(v.marginal),
        "deciding": deciding, "deciding_text": text_of if deciding else None,
        "violated": _violated(v), "exact_stable": bool(exact_v.stable), "spectral_radius": rho,
        "K": plant.K, "B": plant.B, "alpha": alpha, "beta": beta,
        "K_max": k_max, "B_range": b_range, "alpha_max": a_max, "beta_range": beta_range,
    }
    lines = [plant.header(), f"Gains: {plant.gains_text()}"
             + (f"  ->  alpha = {_fmt(alpha)}, beta = {_fmt(beta)}" if plant.real else "")]
    lines.append(f"Verdict ({region} region): {word.upper()}")
    if deciding:
        lines += textwrap.wrap(f"deciding constraint: {text_of}", 92, initial_indent="  ",
                               subsequent_indent="    ")
        others = [n for n in data["violated"] if n != deciding]
        if others:
            lines.append(f"  also violated: {', '.join(others)}")
    if word == "marginal":
        lines.append("  marginal: within rounding error of the boundary, so not proved stable")
    if region not in ("exact", "passivity"):
        lines.append(f"  note: the '{region}' region does not certify stability; exact region: "
                     f"{exact_v.word}")
    lines.append(f"  spectral radius = {_fmt(rho)} (stable iff < 1)")
    if dev is not None:
        u = plant.units() or {}
        lines.append(f"  K_max at this B = {_fmt(k_max)} {u['K']} (exact region)")
        lines.append("  B range at this K: " + (f"{_fmt(b_range['lo'])} < B < {_fmt(b_range['hi'])} {u['B']}"
                                                 if b_range["nonempty"] else "none (no B is stable at this K)"))
    else:
        lines.append(f"  alpha_max at this beta = {_fmt(a_max)} (exact region)")
        lines.append("  beta range at this alpha: " + (
            f"{_fmt(beta_range['lo'])} < beta < {_fmt(beta_range['hi'])}"
            if beta_range["nonempty"] else "none (no beta is stable at this alpha)"))
    data["delay_1"], more = _delay1_check(plant, bool(v.stable))
    lines += more
    return _Outcome(EXIT_OK if bool(v.stable) else EXIT_UNSTABLE, data, lines)


def cmd_limits(args: argparse.Namespace, plant: _Plant) -> _Outcome:
    """Largest stable K and B, the B range and what the legacy region would claim."""
    if plant.general:
        return cmd_limits_loop(args, plant)
    d, dev = plant.delta, plant.device
    ext = extremes(d)
    assert isinstance(ext, Extremes)  # the paper's loop
    top = hyperbola_top(d)
    cor = corner(d)
    real: Dict[str, Any] = dict.fromkeys(("K_mmax", "B_at_K_mmax", "K_p_max", "B_mmax", "B_mmin"))
    legacy_K: Any = None
    legacy_B: Any = None
    if dev is not None:
        lim = dev.extremes()
        real = {k: getattr(lim, k) for k in real}
        # The legacy claim is the hyperbola's top; m/T^2 and m/T only convert its units.
        legacy_K = float(top.alpha) * float(dev.m) / float(dev.T) ** 2
        legacy_B = float(top.beta) * float(dev.m) / float(dev.T)
    above = d > DELTA0
    overstates = bool(ext.at_corner)
    data = {
        **real,
        "alpha_mmax": ext.alpha_mmax, "beta_at_alpha_mmax": ext.beta_at_alpha_mmax,
        "alpha_p_max": ext.alpha_p_max, "beta_mmax": ext.beta_mmax, "beta_mmin": ext.beta_mmin,
        "at_corner": bool(ext.at_corner), "corner": {"alpha": cor.alpha, "beta": cor.beta},
        "delta0": DELTA0, "above_delta0": above,
        "legacy": {"K_mmax": legacy_K, "B_at_K_mmax": legacy_B, "alpha_mmax": top.alpha,
                   "beta_at_alpha_mmax": top.beta, "region_unsafe": above,
                   "overstates_K_mmax": overstates},
    }
    where = "corner of hyperbola and line" if overstates else "top of the hyperbola"
    lines = [plant.header(), "", "Limits (exact region, paper eq (10))"]
    if dev is not None:
        u = plant.units() or {}
        lines += [
            f"  K_mmax   = {_fmt(real['K_mmax'])} {u['K']} at B = {_fmt(real['B_at_K_mmax'])} {u['B']} ({where})",
            f"  K with B = 0 (stiffness only): K < {_fmt(real['K_p_max'])} {u['K']}"
            + (" (none is stable)" if float(real["K_p_max"]) <= 0.0 else ""),
            f"  B range  : {_fmt(real['B_mmin'])} < B < {_fmt(real['B_mmax'])} {u['B']} (as K -> 0+)",
        ]
        claim = f"K_mmax = {_fmt(legacy_K)} {u['K']} at B = {_fmt(legacy_B)} {u['B']}"
    else:
        lines += [
            f"  alpha_mmax = {_fmt(ext.alpha_mmax)} at beta = {_fmt(ext.beta_at_alpha_mmax)} ({where})",
            f"  alpha with beta = 0 (stiffness only): alpha < {_fmt(ext.alpha_p_max)}"
            + (" (none is stable)" if float(ext.alpha_p_max) <= 0.0 else ""),
            f"  beta range : {_fmt(ext.beta_mmin)} < beta < {_fmt(ext.beta_mmax)} (as alpha -> 0+)",
        ]
        claim = f"alpha_mmax = {_fmt(top.alpha)} at beta = {_fmt(top.beta)}"
    if overstates:
        judgement = (f"unsafe: that point is unstable, and so are other gains it admits "
                     f"(delta > delta0 = {_fmt(DELTA0)})")
    elif above:
        judgement = (f"the same maximum, but unsafe: it admits unstable gains "
                     f"(delta > delta0 = {_fmt(DELTA0)})")
    else:
        judgement = f"exact here (delta <= delta0 = {_fmt(DELTA0)})"
    lines += [f"  legacy region (no line) would claim {claim}", f"    -> {judgement}"]
    data["delay_1"], more = _delay1_limits(plant, float(real["K_mmax"] if dev is not None else ext.alpha_mmax))
    lines += more
    return _Outcome(EXIT_OK, data, lines)


def cmd_advise_loop(args: argparse.Namespace, plant: _Plant) -> _Outcome:
    """advise for a loop other than the paper's: what the loop costs, how delay and the
    low-pass cut-off move K_mmax, and for gains what to change (this loop's limits)."""
    if plant.device is not None:
        dev = plant.device
    else:
        lp = plant.loop
        vf: Any = None if lp.filter == "none" else (("pole", lp.pole) if lp.filter == "lowpass" else ("average", lp.average))
        dev = Device(1.0, plant.delta, 1.0, delay=lp.delay, velocity_filter=vf, differentiator=lp.differentiator)
    inf = dev.loop_influence()
    ku = f" {plant.units()['K']}" if plant.real else ""  # type: ignore[index]
    fu = " Hz" if plant.real else " cycles/sample"
    data: Dict[str, Any] = {"loop_influence": inf.as_dict(), "advice": inf.advice,
                            "influence": None, "trends": None, "gains": None}
    lines = [plant.header(), "", f"What the loop costs (K_mmax certified for each loop{'' if plant.real else '; normalized: m = T = 1'})"]
    lines.append(f"  ideal loop K_mmax = {_fmt(inf.K_mmax_ideal)}{ku}; this loop {_fmt(inf.K_mmax)}{ku} "
                 f"({100 * float(inf.K_mmax_kept):.4g} % kept)")
    lines.append("  by delay: " + ", ".join(f"{int(d)} sample{'s' if int(d) != 1 else ''}: {_fmt(k)}{ku}"
                                           for d, k in zip(inf.delays, inf.K_mmax_by_delay)))
    if inf.cutoffs is not None and math.isfinite(float(inf.K_mmax_at_best_cutoff)):
        lines.append(f"  low-pass: of {len(inf.cutoffs)} cut-offs up to Nyquist, {_fmt(inf.best_cutoff)}{fu} keeps "
                     f"most: K_mmax = {_fmt(inf.K_mmax_at_best_cutoff)}{ku}")
    return _Outcome(_advise_gains(args, plant, dev, " with this loop", data, lines), data, lines)


#: The margins the drive certifies with (docs/modbus.md: zwidth-drive, zwidth-tune commission
#: --paper-defaults): K <= sigma K_max(B) and every pole inside |z| < r.
DEFAULT_SIGMA = 0.8
DEFAULT_R = 0.999


@dataclasses.dataclass(frozen=True)
class _Margins:
    """Gains are certified when stable, K <= sigma K_max(B) and all poles inside |z| < r,
    the rules of the drive's register map (regmap.h)."""

    sigma: float = DEFAULT_SIGMA
    r: float = DEFAULT_R

    def text(self) -> str:
        return f"sigma = {self.sigma:g}, r = {self.r:g}"

    def certified(self, dev: Device, K: Any, B: Any) -> Any:
        """Elementwise: stable, K <= sigma K_max(B), all poles within r (guarded checks)."""
        K, B = np.broadcast_arrays(np.asarray(K, dtype=float), np.asarray(B, dtype=float))
        ok = np.asarray(dev.is_stable(K, B), dtype=bool)
        ok &= K <= self.sigma * np.asarray(dev.k_max(B), dtype=float)
        ok &= np.asarray(dev.radius_within(K, B, self.r), dtype=bool)
        return ok


def _margins(args: argparse.Namespace) -> _Margins:
    sigma, r = getattr(args, "sigma", DEFAULT_SIGMA), getattr(args, "r", DEFAULT_R)
    for name, value in (("--sigma", sigma), ("--r", r)):
        if not 0.0 < value <= 1.0:
            raise _Usage(f"argument {name}: must be in (0, 1], got {value:g}")
    return _Margins(sigma, r)


def _run_around(ok: NDArray[np.bool_], i: int) -> Tuple[int, int]:
    """The run of True in ok nearest to index i: (first, last) indices, or (-1, -1)."""
    good = np.flatnonzero(ok)
    if good.size == 0:
        return -1, -1
    j = int(good[np.argmin(np.abs(good - i))])
    lo = j
    while lo > 0 and ok[lo - 1]:
        lo -= 1
    hi = j
    while hi + 1 < ok.size and ok[hi + 1]:
        hi += 1
    return lo, hi


def _refine(edge: float, outside: float, good: Callable[[float], bool]) -> float:
    """Move a certified end (good(edge)) toward the uncertified neighbour by bisection,
    keeping it certified: the returned value passes good()."""
    for _ in range(40):
        mid = 0.5 * (edge + outside)
        if mid in (edge, outside):
            break
        if good(mid):
            edge = mid
        else:
            outside = mid
    return edge


def _certified_interval(grid: NDArray[np.float64], ok: NDArray[np.bool_], current: float,
                        good: Callable[[float], bool], below: float, above: float
                        ) -> Optional[Tuple[float, float, float]]:
    """The certified run of a 1-D grid nearest to current, its ends refined by bisection
    toward the next grid point (below / above: the uncertified values beyond the grid's
    ends): (lo, hi, the value in [lo, hi] nearest to current), or None."""
    i = int(np.argmin(np.abs(grid - current)))
    first, last = _run_around(ok, i)
    if first < 0:
        return None
    lo = _refine(float(grid[first]), float(grid[first - 1]) if first > 0 else below, good)
    hi = _refine(float(grid[last]), float(grid[last + 1]) if last + 1 < grid.size else above, good)
    return lo, hi, min(max(current, lo), hi)


def _advise_gains(args: argparse.Namespace, plant: _Plant, dev: Device, what: str, data: Dict[str, Any],
                  lines: List[str]) -> int:
    """advise's verdict and suggestions for the given gains (none given: nothing), appended to
    data and lines; the exit status (unstable when the gains are not certified)."""
    if not plant.has_gains:
        return EXIT_OK
    margins = _margins(args)
    _, _, v, certified, suggestions, data["gains"] = _gains_advice(plant, dev, what, margins)
    lines += ["", f"Gains {plant.gains_text()}: {v.word.upper()}"
              + (f" ({v.deciding_name})" if v.deciding_name else "")
              + f"; margins {margins.text()}: " + ("CERTIFIED" if certified else "NOT CERTIFIED")]
    lines += [f"   - {x['text']}" for x in suggestions]
    data["gains"]["delay_1"], more = _delay1_check(plant, certified)
    lines += more
    return EXIT_OK if certified else EXIT_UNSTABLE


def _gains_advice(plant: _Plant, dev: Device, which_loop: str, margins: _Margins
                  ) -> Tuple[float, float, Any, bool, List[Dict[str, Any]], Dict[str, Any]]:
    """The plant's gains on dev (real or normalized): (K, B, verdict, certified,
    suggestions, the "gains" JSON object).  Gains that are not certified (not stable, or
    outside the margins) get the certified K interval at this B and the certified B
    interval at this K, each with the value nearest the current one (which_loop ends
    their text); the list is the object's own."""
    K = float(plant.K) if plant.real else float(plant.alpha)  # type: ignore[arg-type]
    B = float(plant.B) if plant.real else float(plant.beta)  # type: ignore[arg-type]
    v = dev.verdict(K, B)
    k_max, b_range = dev.k_max(B), dev.b_range(K)
    certified = bool(margins.certified(dev, K, B))
    Kn, Bn = ("K", "B") if plant.real else ("alpha", "beta")
    kunit = f" {plant.units()['K']}" if plant.real else ""  # type: ignore[index]
    bunit = f" {plant.units()['B']}" if plant.real else ""  # type: ignore[index]
    suggestions: List[Dict[str, Any]] = []
    if not certified:
        k_cap = margins.sigma * float(k_max)
        if k_cap > 0.0:
            grid = np.linspace(0.0, k_cap, 2001)[1:]
            found = _certified_interval(grid, margins.certified(dev, grid, B), K,
                                        lambda k: bool(margins.certified(dev, k, B)), 0.0, k_cap)
            if found is not None:
                lo, hi, best = found
                suggestions.append({
                    "change": "K", "lo": lo, "hi": hi, "value": best,
                    "text": f"set {Kn} = {_fmt(best)}{kunit} (certified for {Kn} in [{_fmt(lo)}, {_fmt(hi)}] "
                            f"at this {Bn}{which_loop})"})
        if bool(b_range.nonempty):
            grid = np.linspace(float(b_range.lo), float(b_range.hi), 2003)[1:-1]
            found = _certified_interval(grid, margins.certified(dev, K, grid), B,
                                        lambda bb: bool(margins.certified(dev, K, bb)),
                                        float(b_range.lo), float(b_range.hi))
            if found is not None:
                lo, hi, best = found
                suggestions.append({
                    "change": "B", "lo": lo, "hi": hi, "value": best,
                    "text": f"set {Bn} = {_fmt(best)}{bunit} (certified for {Bn} in [{_fmt(lo)}, {_fmt(hi)}] "
                            f"at this {Kn}{which_loop})"})
    gains = {"K": plant.K, "B": plant.B, "alpha": plant.alpha, "beta": plant.beta,
             "verdict": v.word, "stable": bool(v.stable), "marginal": bool(v.marginal),
             "deciding": str(v.deciding_name) or None, "spectral_radius": dev.spectral_radius(K, B),
             "K_max": k_max, "B_range": _interval(b_range),
             "margins": {"sigma": margins.sigma, "r": margins.r}, "certified": certified,
             "suggestions": suggestions}
    return K, B, v, certified, suggestions, gains


def _advise_device(plant: _Plant) -> Device:
    if plant.device is not None:
        return plant.device
    return Device(1.0, plant.delta, 1.0)  # normalized: m = T = 1, so K = alpha, B = beta


def _plant_changes(plant: _Plant, K: float, B: float, margins: _Margins) -> List[Dict[str, Any]]:
    """Nearest m, b and T on log grids (three decades either way) at which the gains as
    they are would be certified (stable and within the margins)."""
    dev = plant.device
    if dev is None:
        return []  # normalized gains move with m and T: only alpha and beta changes make sense
    m, b, T = float(dev.m), float(dev.b), float(dev.T)
    u = plant.units() or {}
    factors = np.geomspace(1e-3, 1e3, 2401)
    out: List[Dict[str, Any]] = []
    for name, value in ((plant.mass, m), ("b", b), ("T", T)):
        base = value if value > 0.0 else m / T  # b = 0: search b in units of m/T
        grid = base * factors
        plant_with: Tuple[Any, Any, Any] = {plant.mass: (grid, b, T), "b": (m, grid, T),
                                            "T": (m, b, grid)}[name]
        trial = Device(*plant_with, rotary=plant.rotary)
        ok = margins.certified(trial, K, B)
        if not ok.any():
            continue
        distance = np.abs(np.log(grid / base))
        distance[~ok] = np.inf
        best = float(grid[int(np.argmin(distance))])
        unit = {plant.mass: u["m"], "b": u["b"], "T": "s"}[name]
        ratio = f"{best / value:.3g} x now; " if value > 0.0 else ""
        out.append({"change": "m" if name == "J" else name, "lo": None, "hi": None, "value": best,
                    "text": f"keep the gains, set {name} = {_fmt(best)} {unit} "
                            f"({ratio}the nearest certified value on a log grid)"})
    return out


def _sensitivity_advice(sens: Any) -> str:
    """Which parameter raises K_mmax most, and which lowers it most, per % (elasticity);
    parts at 0 by their slope."""
    rows = [r for r in sens.rows() if math.isfinite(r["elasticity_K"])]
    out = []
    if rows:
        up = max(rows, key=lambda r: r["elasticity_K"])
        down = min(rows, key=lambda r: r["elasticity_K"])
        if up["elasticity_K"] > 0.0:
            out.append(f"raising {SENSITIVITY_WORDS.get(up['name'], up['name'])} raises K_mmax most "
                       f"({up['elasticity_K']:+.3g} % per %)")
        if down["elasticity_K"] < 0.0:
            out.append(f"raising {SENSITIVITY_WORDS.get(down['name'], down['name'])} lowers it most "
                       f"({down['elasticity_K']:+.3g} % per %)")
    absent = [r for r in sens.rows() if r["one_sided"] and r["K_trend"] in ("rises", "falls")]
    if absent:
        out.append("adding " + ", ".join(f"{SENSITIVITY_WORDS.get(r['name'], r['name'])} "
                                          f"({r['K_trend'].replace('rises', 'raises').replace('falls', 'lowers')} it)"
                                          for r in absent))
    return "; ".join(out) + "." if out else "no parameter moves K_mmax measurably."


def _loop_filter(loop: Loop) -> Any:
    """A normalized plant's loop filter as a Device takes it (a low-pass by its pole)."""
    if loop.filter == "lowpass":
        return ("pole", loop.pole)
    return ("average", loop.average) if loop.filter == "average" else None


def cmd_advise_plant(args: argparse.Namespace, plant: _Plant) -> _Outcome:
    """advise for a device with plant-side parts: what they cost or give against the same
    device without them, how every parameter moves K_mmax and B_mmax (numerical
    sensitivities of the certified limits), what the loop costs, and for gains what to change."""
    dev = plant.device
    note = ""
    if dev is None:  # normalized: m = T = 1, so b = delta, k_p = kappa, tau = lambda, K = alpha, B = beta
        dev = Device(1.0, plant.delta, 1.0, delay=plant.loop.delay, velocity_filter=_loop_filter(plant.loop),
                     differentiator=plant.loop.differentiator, actuator_tau=plant.lambda_, stiffness=plant.kappa)
        note = ("  (normalized: m = T = 1, so b = delta, k_p = kappa, tau = lambda, K = alpha, B = beta; the units "
                "printed are those of m = 1 kg, T = 1 s)")
    u = plant.units() or {"K": "", "B": ""}
    lim, plain = dev.extremes(), dev.without_plant_parts().extremes()
    sens = dev.sensitivity()
    inf = dev.loop_influence() if not plant.loop.ideal else None
    K, Kp = float(lim.K_mmax), float(plain.K_mmax)
    data: Dict[str, Any] = {
        "sensitivity": sens.as_dict(), "advice": _sensitivity_advice(sens),
        "without_plant_parts": {"K_mmax": plain.K_mmax, "B_mmax": plain.B_mmax},
        "K_mmax": lim.K_mmax, "B_mmax": lim.B_mmax, "B_at_K_mmax": lim.B_at_K_mmax,
        "loop_influence": None if inf is None else inf.as_dict(), "influence": None, "trends": None, "gains": None}
    lines = [plant.header(), "",
             "Influence (numerical: finite differences of the certified limits; the paper's closed forms "
             "are about its ideal plant)" + note,
             f"  K_mmax = {_fmt(K)} {u['K']} at B = {_fmt(lim.B_at_K_mmax)} {u['B']}, B_mmax = {_fmt(lim.B_mmax)} "
             f"{u['B']}",
             f"  without the plant-side parts: K_mmax = {_fmt(Kp)} {u['K']}, B_mmax = {_fmt(plain.B_mmax)} {u['B']}"
             + (f" (the parts {'enlarge' if K > Kp else 'shrink'} K_mmax by {100 * abs(K / Kp - 1):.3g} %)"
                if Kp > 0.0 else "")]
    lines += [f"  {line}" for line in sens.lines()]
    lines += textwrap.wrap(f"advice: {data['advice']}", 92, initial_indent="  ", subsequent_indent="          ")
    if inf is not None:
        lines.append(f"  this loop keeps {100 * float(inf.K_mmax_kept):.4g} % of the paper's loop's K_mmax on this "
                     f"plant; by delay: " + ", ".join(f"{int(d)}: {_fmt(k)}" for d, k in
                                                       zip(inf.delays, inf.K_mmax_by_delay)) + f" {u['K']}")
    return _Outcome(_advise_gains(args, plant, dev, " with these parts", data, lines), data, lines)


def cmd_advise(args: argparse.Namespace, plant: _Plant) -> _Outcome:
    """Influence of m, b, T on the limits, critical values, advice; gains: what to change."""
    if plant.parts:
        return cmd_advise_plant(args, plant)
    if not plant.loop.ideal:
        return cmd_advise_loop(args, plant)
    dev = _advise_device(plant)
    inf = dev.influence()
    fields = {k: v for k, v in inf.as_dict().items() if k != "m"}
    M = plant.mass
    trends = inf.trends
    data: Dict[str, Any] = {"influence": fields, "trends": trends, "advice": inf.advice, "gains": None}
    if plant.real:
        u = plant.units() or {}
        mu, tu, bu, ku = f" {u['m']}", " s", f" {u['b']}", f" {u['K']}"
        scale_note = ""
    else:
        mu = tu = bu = ku = ""
        scale_note = "  (normalized: m = T = 1, b = delta; masses in units of m, periods of T, dampings of m/T)"
    lines = [plant.header(), "", "Influence (paper Section IV)" + scale_note]
    lines += [f"  {part.strip()}" for part in trends.split(";")]
    if plant.delta > 0.0:
        pad = " " * len(f"  K_mmax against {M}: ")
        lines += [
            f"  K_mmax against {M}: rises to {M}_K2 = {_fmt(inf.m_K2)}{mu} (local max {_fmt(inf.K_mmax_at_m_K2)}{ku}),",
            f"{pad}falls to {M}_K1 = {_fmt(inf.m_K1)}{mu} (local min {_fmt(inf.K_mmax_at_m_K1)}{ku}),",
            f"{pad}regains the local max at {M}_K_match = {_fmt(inf.m_K_match)}{mu}",
            f"  B_mmax against {M}: turns at {M}_0 = {_fmt(inf.m_0)} and {M}_B = {_fmt(inf.m_B)}{mu}",
            f"  B_mmax against T: turns at T_B = {_fmt(inf.T_B)} and T_0 = {_fmt(inf.T_0)}{tu}",
        ]
    else:
        lines.append(f"  no turning points in {M} or T: b = 0 gives delta = 0 for every {M} and T")
    lines.append(f"  B_mmax against b: turns at b_0 = {_fmt(inf.b_0)} and b_BB = {_fmt(inf.b_BB)}{bu}")
    lines += textwrap.wrap(f"advice: {inf.advice}", 92, initial_indent="  ", subsequent_indent="          ")
    status = EXIT_OK
    if plant.has_gains:
        margins = _margins(args)
        K, B, v, certified, suggestions, data["gains"] = _gains_advice(plant, dev, "", margins)
        word, k_max = v.word, data["gains"]["K_max"]
        Kn, Bn = ("K", "B") if plant.real else ("alpha", "beta")
        kunit = f" {plant.units()['K']}" if plant.real else ""  # type: ignore[index]
        if not certified:
            status = EXIT_UNSTABLE
            suggestions += _plant_changes(plant, K, B, margins)
        lines += ["", f"Gains {plant.gains_text()}: {word.upper()}"
                  + (f" ({v.deciding_name})" if v.deciding_name else "")
                  + f", spectral radius {_fmt(data['gains']['spectral_radius'])}"]
        if float(k_max) > 0.0:
            lines.append(f"  {Kn} is {100.0 * K / float(k_max):.4g} % of {Kn}_max = {_fmt(k_max)}{kunit} at this {Bn}")
        lines.append(f"  margins as the drive certifies ({Kn} <= sigma {Kn}_max({Bn}), spectral radius < r; "
                     f"{margins.text()}): " + ("CERTIFIED" if certified else "NOT CERTIFIED"))
        if not certified and suggestions:
            lines.append("  to certify them:")
            lines += [f"   - {s['text']}" for s in suggestions]
        elif not certified:
            lines.append("  no change of one gain or of m, b or T (within 1e-3..1e3 x) certifies them")
        data["gains"]["delay_1"], more = _delay1_check(plant, certified)
        lines += more
    return _Outcome(status, data, lines)


def _write_figure(draw: Callable[[Any], Any], out: Path, dpi: int) -> None:
    """Draw a figure with zwidth.plot under the Agg backend (``draw(plot)`` returns it),
    write it to ``out`` and close it; _PlotError when matplotlib or the file fails."""
    try:
        import matplotlib
        matplotlib.use("Agg")  # no display needed, and none is used
        from . import plot
    except ImportError:
        raise _PlotError("matplotlib is not installed: pip install zwidth[plot]") from None
    fig = draw(plot)
    try:
        plot.save(fig, out, dpi=dpi)
    except OSError as exc:
        raise _PlotError(f"cannot write {out}: {exc.strerror or exc}") from None
    finally:
        import matplotlib.pyplot as plt
        plt.close(fig)


def cmd_plot(args: argparse.Namespace, plant: Optional[_Plant]) -> _Outcome:
    """Draw one figure with zwidth.plot under the Agg backend and write it."""
    kind = args.kind
    out = Path(args.output or f"zwidth-{kind}.png")

    def draw(plot: Any) -> Any:
        if kind == "extremes":
            return plot.extremes(args.delta_min, args.delta_max, mark=None if plant is None else plant.delta)
        if kind in ("region", "device") and plant is not None and plant.parts and plant.device is not None:
            # real units: the region with the lag / hand / spring over the same device without them
            return plot.plant_region(plant.device, plant.K, plant.B)
        if kind in ("region", "device") and plant is not None and plant.device is not None and plant.general:
            # real units: the region of the loop the device runs over the paper's ideal loop's
            return plot.device_region(plant.device, plant.K, plant.B)
        if kind == "influence" and plant is not None and plant.device is not None and (plant.parts or plant.general):
            return plot.plant_influence(plant.device)   # numerical: any loop
        if kind == "region":
            assert plant is not None
            point = None if not plant.has_gains else (float(plant.beta), float(plant.alpha))  # type: ignore[arg-type]
            if plant.general:  # another loop, or a normalized plant with --kappa / --lambda
                kw = plant.loop_kwargs()
                if plant.device is not None and plant.device.filter_pole is not None:
                    kw["filter_pole"] = float(plant.device.filter_pole)
                T = None if plant.device is None else float(plant.device.T)
                return plot.loop_region(plant.delta, point=point, T=T, loop_text=plant.loop.describe(), **kw)
            return plot.region(plant.delta, point=point)
        assert plant is not None and plant.device is not None and not plant.general   # the paper's loop
        if kind == "influence":
            return plot.influence(plant.device)
        return plot.device(plant.device, plant.K, plant.B)

    _write_figure(draw, out, args.dpi)
    data = {"kind": kind, "file": str(out), "format": out.suffix.lower().lstrip("."),
            "bytes": out.stat().st_size}
    return _Outcome(EXIT_OK, data, [f"wrote {out} ({kind}, {data['bytes']} bytes)"])


def _simulate_outputs(args: argparse.Namespace) -> Tuple[Optional[Path], Optional[Path]]:
    """Check --out and --plot before simulating (usage errors)."""
    out = Path(args.out) if args.out else None
    fig = Path(args.plot) if args.plot else None
    if out is not None and out.suffix.lower() not in (".npz", ".csv"):
        raise _Usage(f"argument --out: {args.out!r} must end in .npz or .csv")
    if fig is not None and fig.suffix.lower() not in (".png", ".svg"):
        raise _Usage(f"argument --plot: {args.plot!r} must end in .png or .svg")
    if out is not None:
        problem = _unwritable(out)
        if problem:
            raise _Usage(f"argument --out: cannot write {out}: {problem}")
    if fig is not None:
        problem = _unwritable(fig)
        if problem:
            raise _PlotError(f"cannot write {fig}: {problem}")
    return out, fig


def _unwritable(path: Path) -> Optional[str]:
    """Why a file cannot be written there (checked before a long run), or None."""
    parent = path.parent
    if path.is_dir():
        return "it is a directory"
    if not parent.is_dir():
        return f"no directory {parent}" if not parent.exists() else f"{parent} is not a directory"
    if path.exists() and not os.access(path, os.W_OK):
        return "the file is not writable"
    if not path.exists() and not os.access(parent, os.W_OK | os.X_OK):
        return f"the directory {parent} is not writable"
    return None


def _simulation_json(sim: Any, rotary: bool) -> Dict[str, Any]:
    analytic = None
    p = sim.params
    if sim.analytic is not None:
        dev = sim.device
        ideal = dev.loop.ideal
        analytic = {"verdict": sim.analytic.word, "stable": bool(sim.analytic.stable),
                    "marginal": bool(sim.analytic.marginal),
                    "deciding": str(sim.analytic.deciding_name) or None,
                    "spectral_radius": dev.spectral_radius(p["K"], p["B"]),
                    "loop": dev.loop.as_dict(),
                    "legacy_stable": bool(dev.is_stable(p["K"], p["B"], region="legacy")) if ideal else None,
                    "ideal_loop": None if sim.ideal is None else {
                        "verdict": sim.ideal.word, "stable": bool(sim.ideal.stable)}}
    norm = sim.case.normalized
    params = {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in p.items()}
    return {"label": sim.label, "description": sim.case.description, "samples": len(sim.t),
            "T": p["T"], "duration": sim.case.duration, "params": params,
            "normalized": None if norm is None else dict(zip(("delta", "alpha", "beta"), norm)),
            "verdict": sim.verdict.as_dict(), "analytic": analytic, "agrees": sim.agrees,
            "note": sim.note, "linear_part": None if sim.linear is None else {
                "piece": sim.linear.piece, "K": sim.linear.K, "B": sim.linear.B, "m": sim.linear.m,
                "b": sim.linear.b, "k": sim.linear.k, "verdict": sim.linear.word, "stable": sim.linear.stable,
                "spectral_radius": sim.linear.spectral_radius},
            "explanation": sim.explanation}


#: simulate: no case unstable but some undecided (a run that cannot tell is not "stable")
EXIT_UNDECIDED = 5


def _bytes(n: int) -> str:
    return f"{n / 2 ** 30:.3g} GiB" if n >= 2 ** 30 else f"{n / 2 ** 20:.3g} MiB"


def _linear_words(sim: Any) -> str:
    """What the linear part leaves out of the case's loop."""
    from .scene import EFFECTS
    fx = int(sim.params["effects"])
    words = {"quantization": "quantization", "friction": "friction", "saturation": "saturation",
             "wall": "the wall's switching", "knob": "the knob's switching", "schedule": "earlier segments"}
    left = [w for e, w in words.items() if fx & EFFECTS[e]]
    return "without " + ", ".join(left) if left else "the loop simulated"


def _simulated_loops(sims: Any) -> str:
    """simulate's first line: the loop each case analyses, as its scene file states it (its
    [delay], [velocity_filter], [average], [differentiator]; none of them: the paper's loop)."""
    def text(s: Any) -> str:
        dev = s.device
        if dev is None:
            return f"{int(s.params.get('delay_samples', 0))} samples delay: simulated only (the analysis takes up to 8)"
        loop: Loop = dev.loop
        if loop.filter == "lowpass" and "cutoff_hz" in s.params:  # name the scene's cut-off beside its pole
            loop = dataclasses.replace(loop, cutoff=float(s.params["cutoff_hz"]))
        return loop.statement()
    texts = [text(s) for s in sims]
    if len(set(texts)) <= 1:
        return f"Loop: {texts[0] if texts else 'none (no case)'} (as the scene states it)"
    return "Loop (as the scene states it, per case): " + "; ".join(f"{s.label}: {t}" for s, t in zip(sims, texts))


def _growth(v: Any) -> str:
    # A settled run has decayed to rounding: its envelope ratio says nothing.
    return "(settled)" if v.outcome == "stable" else _fmt(v.growth)


def cmd_simulate(args: argparse.Namespace) -> _Outcome:
    """Simulate every case of a scene file; verdicts, files, figure."""
    from .scene import load_scene, parse_quantity
    from .sim import check_memory, simulate, work

    out, fig_path = _simulate_outputs(args)
    seconds: Optional[float] = None
    if args.duration is not None:
        try:
            seconds = parse_quantity(args.duration, "time", what="--duration")
        except ValueError as exc:
            raise _Usage(f"argument --duration: {getattr(exc, 'problem', exc)}") from None
        if not (math.isfinite(seconds) and seconds > 0.0):
            raise _Usage(f"argument --duration: must be > 0 s and finite, got {args.duration!r}")
    scene = load_scene(Path(args.scene))
    if seconds is not None:
        scene = scene.with_duration(seconds)
    total = sum(work(c) for c in scene.cases)
    memory = check_memory(scene)      # stated (and refused when it does not fit) before the run
    if memory >= 2 ** 30:
        print(f"zwidth simulate: {len(scene.cases)} case(s), {sum(c.samples for c in scene.cases):,} samples: "
              f"{memory / 2 ** 30:.3g} GiB of arrays", file=sys.stderr)
    sims = simulate(scene, progress=not args.no_progress and total >= _PROGRESS_WORK)

    counts = {o: sum(s.verdict.outcome == o for s in sims) for o in ("stable", "unstable", "undecided")}
    compared = [bool(s.agrees) for s in sims if s.agrees is not None]
    data: Dict[str, Any] = {
        "scene": {"name": scene.name, "description": scene.description, "file": scene.source,
                  "duration": scene.duration, "rotary": scene.rotary, "linear": scene.linear,
                  "effects": list(scene.effects), "units": scene.units},
        "cases": [_simulation_json(s, scene.rotary) for s in sims],
        "summary": {"cases": len(sims), **counts, "compared": len(compared), "agree": sum(compared)},
        "memory": memory, "out": None, "plot": None,
    }
    pos = scene.units["position"]
    plural = "s" if len(sims) != 1 else ""
    lines = [_simulated_loops(sims),
             f"Scene {scene.name} ({scene.source})" + (f": {scene.description}" if scene.description else ""),
             f"  {'rotary' if scene.rotary else 'translational'} plant; effects: "
             + (", ".join(scene.effects) if scene.effects else "none (the ideal loop: exact solution)")
             + f"; {len(sims)} case{plural}, {_fmt(scene.duration)} s each; {_bytes(memory)} of arrays", ""]
    width = max([4] + [len(s.label) for s in sims])
    last_column = "legacy region" if scene.ideal else "ideal loop"
    if scene.linear:
        lines.append(f"  {'case':<{width}}  {'delta':>7} {'alpha':>8} {'beta':>8}  {'simulated':<10} "
                     f"{'growth/sample':>13}  {'exact region':<12} {'agrees':<6}  {last_column}")
    else:
        lines.append(f"  {'case':<{width}}  {'simulated':<10} {'growth/sample':>13}  "
                     f"{'final x [' + pos + ']':>16}  {'linear part':<12} {'radius':>8}")
    for s in sims:
        v = s.verdict
        if scene.linear:
            d, a, b = s.case.normalized or (math.nan, math.nan, math.nan)
            exact = s.analytic.word if s.analytic is not None else "-"
            agrees = {True: "yes", False: "NO", None: "-"}[s.agrees]
            analytic = data["cases"][sims.index(s)]["analytic"] or {}
            if scene.ideal:
                other = "stable" if analytic.get("legacy_stable") else "unstable"
            else:
                other = (analytic.get("ideal_loop") or {}).get("verdict", "-")
            lines.append(f"  {s.label:<{width}}  {_fmt(d):>7} {_fmt(a):>8} {_fmt(b):>8}  {v.outcome:<10} "
                         f"{_growth(v):>13}  {exact:<12} {agrees:<6}  {other}")
        else:
            lp = s.linear
            assert lp is not None   # simulate() gives every case its linear part
            lines.append(f"  {s.label:<{width}}  {v.outcome:<10} {_growth(v):>13}  {_fmt(s.x[-1]):>16}  "
                         f"{lp.word:<12} {lp.spectral_radius:>8.4g}")
    if scene.linear and not scene.ideal and sims and sims[0].device is not None:
        from .sim import loop_words
        lines.append(f"  loop analysed: {loop_words(sims[0].params, sims[0].device)}; 'ideal loop' is what "
                     f"zwidth check says with --delay 0")
    for s in sims:
        if s.verdict.outcome != "stable" or not scene.linear:
            lines += textwrap.wrap(f"{s.label}: {s.verdict.outcome}: {s.verdict.reason}", 92, initial_indent="  ",
                                   subsequent_indent="      ")
        if not scene.linear and s.linear is not None:
            lines += textwrap.wrap(f"{s.label}: linear part ({_linear_words(s)}): {s.linear.describe(scene.units)}",
                                   92, initial_indent="  ", subsequent_indent="      ")
        if s.explanation:
            lines += textwrap.wrap(f"{s.label}: differs: {s.explanation}", 92, initial_indent="  ",
                                   subsequent_indent="      ")
        if s.note:
            lines += textwrap.wrap(f"warning: {s.label}: {s.note}", 92, initial_indent="  ",
                                   subsequent_indent="      ")
    summary = ", ".join(f"{c} {o}" for o, c in counts.items() if c)
    if compared:
        summary += f"; simulated = analytic (exact region) for {sum(compared)} of {len(compared)}"
    lines += ["", f"  {len(sims)} case{plural}: {summary}"]

    if out is not None:
        try:
            if out.suffix.lower() == ".npz":
                sims.to_npz(out)
            else:
                sims.to_csv(out)
        except OSError as exc:
            raise _Usage(f"argument --out: cannot write {out}: {exc.strerror or exc}") from None
        data["out"] = str(out)
        lines.append(f"wrote {out} ({out.stat().st_size} bytes)")
    if fig_path is not None:
        _write_figure(lambda plot: plot.simulation(sims), fig_path, args.dpi)
        data["plot"] = str(fig_path)
        lines.append(f"wrote {fig_path} ({fig_path.stat().st_size} bytes)")
    status = EXIT_UNSTABLE if counts["unstable"] else EXIT_UNDECIDED if counts["undecided"] else EXIT_OK
    return _Outcome(status, data, lines)


# ---------------------------------------------------------------------------------------
# Parser and main
# ---------------------------------------------------------------------------------------


def _add_plant_options(p: argparse.ArgumentParser) -> None:
    real = p.add_argument_group("plant and gains in real units (default)")
    mass = real.add_mutually_exclusive_group()
    mass.add_argument("--m", type=parse_range, metavar="M", help="mass [kg] (or a range LO:HI, box.py)")
    mass.add_argument("--J", type=parse_range, metavar="J",
                      help="inertia [kg m^2] of a rotary device (units then N m s/rad, N m/rad)")
    real.add_argument("--b", type=parse_range, metavar="b", help="physical damping [N s/m] (>= 0; or LO:HI)")
    real.add_argument("--T", type=_number, metavar="T", help="sampling period [s] (> 0)")
    real.add_argument("--K", type=_number, metavar="K", help="virtual stiffness [N/m]")
    real.add_argument("--B", type=_number, metavar="B", help="virtual damping [N s/m]")
    real.add_argument("--preset", choices=sorted(PRESETS),
                      help="a named plant: paper-drive is the paper's drive (--J 85.78e-7 --b 2.197e-3 "
                           "--T 0.02); options given override it")
    norm = p.add_argument_group("normalized space instead (not with the options above)")
    norm.add_argument("--delta", type=_number, metavar="DELTA", help="normalized damping bT/m (>= 0)")
    norm.add_argument("--alpha", type=_number, metavar="ALPHA", help="normalized stiffness K T^2/m")
    norm.add_argument("--beta", type=_number, metavar="BETA", help="normalized damping B T/m")
    norm.add_argument("--kappa", type=_number, metavar="KAPPA",
                      help="normalized plant stiffness (k_p + k_h) T^2/M, M = m + m_h (>= 0; default 0)")
    norm.add_argument("--lambda", dest="lambda_", type=_number, metavar="LAMBDA",
                      help="normalized actuator lag tau/T (>= 0; default 0: none)")
    lp = p.add_argument_group(
        "the loop the drive runs (--delay is required: nothing is assumed; no filter and the backward "
        "difference unless given)")
    lp.add_argument("--delay", type=int, default=None, metavar="N",
                    help="samples between measuring x_k and applying its force, 0..8: 0 is the paper's "
                         "ideal loop, 1 what most firmware does (computed during the period, applied at "
                         "the next tick); required, except with --preset paper-drive (the paper's loop)")
    lp.add_argument("--velocity-filter", metavar="SPEC",
                    help="lowpass:30Hz (first-order, cut-off in Hz; real units), pole:0.83 (its pole "
                         "a = exp(-2 pi f_c T)), average:4 (moving average over n = 1..16 samples)")
    lp.add_argument("--differentiator", choices=DIFFERENTIATORS, default="backward",
                    help="velocity estimate: backward difference (the paper's) or tustin")
    pp = p.add_argument_group(
        "plant-side parts (real-unit plant; default none; the gains are then normalized by m + m_h)")
    pp.add_argument("--actuator-tau", type=_number, metavar="S",
                    help="actuator (current-loop) lag: the force reaches the plant through 1/(S s + 1), S in s")
    pp.add_argument("--hand", type=parse_hand, metavar="M_H,B_H,K_H",
                    help="a coupled hand (coupled stability): mass [kg], damping [N s/m], stiffness [N/m]; "
                         "any of them a range LO:HI certifies check and limits for every hand in it")
    pp.add_argument("--stiffness", type=parse_range, metavar="K_P",
                    help="the device's own stiffness (a return spring, a cable) [N/m] (or a range LO:HI)")
    p.add_argument("--json", action="store_true", help="print one JSON object (keys below)")


def _wrap(text: str) -> str:
    return textwrap.fill(text, 88)


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of the ``zwidth`` command."""
    fmt = argparse.RawDescriptionHelpFormatter
    parser = argparse.ArgumentParser(prog="zwidth", description=DESCRIPTION, epilog=EPILOG,
                                     formatter_class=fmt, allow_abbrev=False)
    parser.add_argument("--version", action="version", version=f"zwidth {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="{check,limits,advise,plot,simulate,identify}",
                                required=True)

    p = sub.add_parser("check", help="is the gain pair stable? why not? (exit 1 if not)",
                       description=_wrap("Check one gain pair: verdict, deciding constraint, "
                                         "spectral radius, K_max at this B and the B range at this K."),
                       epilog=_CHECK_EPILOG, formatter_class=fmt, allow_abbrev=False)
    _add_plant_options(p)
    p.add_argument("--region", choices=REGIONS, default="exact",
                   help="region to check in (default exact; legacy, delta0, delta_inf and small "
                        "are the paper's comparisons and certify nothing)")
    p.set_defaults(handler=cmd_check, needs_gains=True, parser=p)

    p = sub.add_parser("limits", help="largest stable K and B, the B range, the legacy claim",
                       description=_wrap("The impedance extremes of the plant (paper Sections III, "
                                         "IV) and what the legacy region would claim."),
                       epilog=_LIMITS_EPILOG, formatter_class=fmt, allow_abbrev=False)
    _add_plant_options(p)
    p.set_defaults(handler=cmd_limits, needs_gains=False, parser=p)

    p = sub.add_parser("advise", help="how m, b, T move the limits; with gains, what to change",
                       description=_wrap("Trends of K_mmax and B_mmax in m, b and T, the critical "
                                         "masses, periods and dampings, and advice (paper Section "
                                         "IV); with gains, what to change to make them stable.  With "
                                         "plant-side parts (an actuator lag, a hand, a stiffness): how "
                                         "m, b, T, tau, m_h, b_h, k_h and k_p move K_mmax and B_mmax, "
                                         "numerically from the certified limits."),
                       epilog=_ADVISE_EPILOG, formatter_class=fmt, allow_abbrev=False)
    _add_plant_options(p)
    mg = p.add_argument_group("margins the advice certifies with (those of the drive, docs/modbus.md)")
    mg.add_argument("--sigma", type=_number, default=DEFAULT_SIGMA, metavar="SIGMA",
                    help=f"stiffness fraction: K <= sigma K_max(B) (default {DEFAULT_SIGMA})")
    mg.add_argument("--r", type=_number, default=DEFAULT_R, metavar="R",
                    help=f"spectral-radius bound: every pole inside |z| < r (default {DEFAULT_R})")
    p.set_defaults(handler=cmd_advise, needs_gains=False, parser=p)

    p = sub.add_parser("plot", help="draw a figure (PNG, PDF, SVG, EPS; needs matplotlib)",
                       description="Draw a figure with zwidth.plot (matplotlib, Agg backend).",
                       epilog=_PLOT_EPILOG, formatter_class=fmt, allow_abbrev=False)
    p.add_argument("kind", choices=("region", "extremes", "influence", "device"))
    p.add_argument("-o", "--output", metavar="FILE",
                   help="output file, .png, .pdf, .svg, .eps or .ps (default zwidth-KIND.png)")
    p.add_argument("--dpi", type=_number, default=100.0, help="resolution of PNG files (default 100)")
    p.add_argument("--delta-min", type=_number, default=1e-3, help="extremes: smallest delta (default 1e-3)")
    p.add_argument("--delta-max", type=_number, default=20.0, help="extremes: largest delta (default 20)")
    _add_plant_options(p)
    p.set_defaults(handler=cmd_plot, needs_gains=False, parser=p)

    p = sub.add_parser("simulate", help="simulate a scene file in time (exit 1 if a case is unstable, 5 undecided)",
                       description=_SIMULATE_DESCRIPTION, epilog=_SIMULATE_EPILOG, formatter_class=fmt,
                       allow_abbrev=False)
    p.add_argument("scene", metavar="SCENE.toml", help="the scene file (docs/scenes.md; examples in scenes/)")
    p.add_argument("--out", metavar="FILE", help="write the arrays: .npz (numpy) or .csv")
    p.add_argument("--plot", metavar="FILE", help="draw the responses: .png or .svg (needs matplotlib)")
    p.add_argument("--dpi", type=_number, default=100.0, help="resolution of a PNG plot (default 100)")
    p.add_argument("--duration", metavar="TIME",
                   help="simulate this long instead of the scene's duration (\"20 s\", \"500 ms\"; "
                        "a bare number is seconds)")
    p.add_argument("--no-progress", action="store_true",
                   help="no progress bar (otherwise one on stderr for long runs)")
    p.add_argument("--json", action="store_true", help="print one JSON object (keys below)")
    p.set_defaults(handler=None, needs_gains=False, parser=p)
    from . import identify_cli   # zwidth identify LOG.csv (its options and runner live there)
    identify_cli.add_parser(sub, fmt)
    return parser


def _emit(outcome: _Outcome, command: str, plant: Optional[_Plant], as_json: bool, stream: TextIO,
          loop: Optional[Loop] = None) -> None:
    """Print the outcome: JSON (the loop right after the command) or text (the loop on the
    first line).  ``loop``: the loop judged when there is no _Plant (a plant box)."""
    if plant is not None:
        loop = plant.loop
    if as_json:
        head: Dict[str, Any] = {"command": command}
        if loop is not None:
            head["loop"] = loop.as_dict()
        if plant is not None and command != "plot":
            head.update(mode="real" if plant.real else "normalized", plant=plant.summary(),
                        units=plant.units())
        print(json.dumps(_jsonable({**head, **outcome.data}), allow_nan=False), file=stream)
    else:
        first = [] if loop is None else [loop_line(loop, plant is not None and plant.loop_from_preset)]
        print("\n".join(first + outcome.lines), file=stream)


_NUMBER_OPTIONS = frozenset({"--m", "--J", "--b", "--T", "--K", "--B", "--delta", "--alpha",
                              "--beta", "--dpi", "--delta-min", "--delta-max",
                              "--sigma", "--r", "--kappa", "--lambda", "--stiffness", "--actuator-tau"})


def _join_negative_numbers(argv: Sequence[str]) -> List[str]:
    """'--B -1.36e-3' -> '--B=-1.36e-3': argparse before Python 3.13 takes a negative
    number in exponent notation for an option and reports a missing value."""
    out: List[str] = []
    i = 0
    while i < len(argv):
        token = argv[i]
        if token in _NUMBER_OPTIONS and i + 1 < len(argv) and argv[i + 1].startswith("-"):
            try:
                float(argv[i + 1])
            except ValueError:
                pass
            else:
                out.append(f"{token}={argv[i + 1]}")
                i += 2
                continue
        if token == "--":
            out.extend(argv[i:])
            break
        out.append(token)
        i += 1
    return out


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Run the ``zwidth`` command line; returns the exit status (see ``zwidth --help``)."""
    parser = build_parser()
    args = parser.parse_args(_join_negative_numbers(sys.argv[1:] if argv is None else argv))
    sub: argparse.ArgumentParser = args.parser
    plant: Optional[_Plant] = None
    if args.command == "simulate":
        return _main_simulate(args, sub)
    if args.command == "identify":
        from . import identify_cli
        return identify_cli.main(args, sub)
    from . import box_cli  # plant ranges (--m 0.10:0.14): every plant of a box
    parts_given = [f"--{n.replace('_', '-')}" for n in ("actuator_tau", "hand", "stiffness")
                   if getattr(args, n, None) is not None]
    if box_cli.has_range(args) and getattr(args, "actuator_tau", None) is not None:
        sub.error("--actuator-tau: a plant range is certified without an actuator lag (the lag's box "
                  "enclosure is not built); give --m, --b, --stiffness, --hand as single values to use it")
    if parts_given and args.command == "plot" and args.kind == "extremes":
        sub.error(f"{', '.join(parts_given)}: plot extremes draws the paper's ideal plant over delta; for a "
                  f"plant with parts use 'plot region' or 'plot influence' with --m/--J, --b, --T")
    if box_cli.has_range(args):
        return box_cli.main(args, sub)
    try:
        if args.command == "plot":
            if not 0.0 < args.dpi < math.inf:
                raise _Usage(f"argument --dpi: must be > 0, got {args.dpi:g}")
            suffix = Path(args.output).suffix.lower() if args.output else ".png"
            if suffix not in (".png", ".pdf", ".svg", ".eps", ".ps"):
                raise _Usage(f"argument -o/--output: {args.output!r} must end in .png, .pdf, .svg, .eps or .ps")
            if args.kind == "extremes":
                if not 0.0 < args.delta_min < args.delta_max < math.inf:
                    raise _Usage(f"need 0 < --delta-min < --delta-max < inf, got "
                                 f"{args.delta_min:g} and {args.delta_max:g}")
                plant = _plant(args, need_plant=False)   # if given: its delta is marked
                if plant is not None and plant.general:
                    raise LoopNotSupported(
                        f"plot extremes draws the paper's ideal loop over delta; for a loop with "
                        f"{plant.loop.describe()} draw 'plot region' or 'plot influence' with the same options",
                        "ZW_ERR_ARG", None, (), {})
            else:
                plant = _plant(args)
                if args.kind in ("influence", "device") and plant is not None and not plant.real:
                    raise _Usage(f"plot {args.kind} needs a real-unit plant (--m or --J, --b, --T)")
        else:
            plant = _plant(args)
            if args.command == "limits" and plant is not None and plant.has_gains:
                raise _Usage("limits takes no gains (they would be ignored): 'zwidth check' or "
                             "'zwidth advise' checks --K/--B")
            if args.needs_gains and plant is not None and not plant.has_gains:
                raise _Usage(f"{args.command} needs the gains: --K and --B (or --alpha and --beta with --delta)")
        assert plant is not None or args.command == "plot"
        outcome = args.handler(args, plant)
    except _Usage as exc:
        sub.error(str(exc))  # exits 2
    except LoopNotSupported as exc:
        print(f"zwidth {args.command}: error: not available: {exc}", file=sys.stderr)
        return EXIT_PLOT if args.command == "plot" else EXIT_INVALID   # a figure it cannot draw
    except ZwidthError as exc:
        option = _option_of(exc)
        where = f"invalid value of {option}: " if option else "invalid input: "
        print(f"zwidth {args.command}: error: {where}{exc}", file=sys.stderr)
        return EXIT_INVALID
    except _PlotError as exc:
        print(f"zwidth plot: error: cannot plot: {exc}", file=sys.stderr)
        return EXIT_PLOT
    _emit(outcome, args.command, plant, args.json, sys.stdout)
    return int(outcome.status)


def _main_simulate(args: argparse.Namespace, sub: argparse.ArgumentParser) -> int:
    from .scene import SceneError
    try:
        if not 0.0 < args.dpi < math.inf:
            raise _Usage(f"argument --dpi: must be > 0, got {args.dpi:g}")
        outcome = cmd_simulate(args)
    except _Usage as exc:
        sub.error(str(exc))  # exits 2
    except SceneError as exc:
        print(f"zwidth simulate: error: invalid scene: {exc}", file=sys.stderr)
        return EXIT_INVALID
    except ZwidthError as exc:  # the loader checks the plants first; should not happen
        print(f"zwidth simulate: error: invalid scene {args.scene}: {exc}", file=sys.stderr)
        return EXIT_INVALID
    except MemoryError as exc:
        why = str(exc) or "a case's arrays do not fit in memory"
        print(f"zwidth simulate: error: out of memory: {why}; shorten the duration (--duration) or "
              f"lengthen T", file=sys.stderr)
        return EXIT_INVALID
    except _PlotError as exc:
        print(f"zwidth simulate: error: cannot plot: {exc}", file=sys.stderr)
        return EXIT_PLOT
    except KeyboardInterrupt:
        print("zwidth simulate: interrupted", file=sys.stderr)
        return 130
    _emit(outcome, "simulate", None, args.json, sys.stdout)
    return int(outcome.status)
