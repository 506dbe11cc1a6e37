# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The loop a real drive runs: computation delay, velocity filter, differentiator (loop.h).

The paper's loop applies F_k = -(K x_k + B v_k) at once with v_k the backward difference.
A drive often applies the force d samples later (d = 1: "compute during the period, apply
at the next tick") and filters the velocity: a first-order low-pass with pole a
(vf_k = a vf_{k-1} + (1 - a) v_k, a = exp(-2 pi f_c T) for a cut-off f_c) or a moving
average over n samples, on the backward difference or on Tustin's differentiator
(v_k = (2/T)(x_k - x_{k-1}) - v_{k-1}).  Its characteristic polynomial stays affine in
(alpha, beta), and the C core decides its stability exactly, with the same rounding guard
as the ideal loop (zw_loop_check).  This module holds the description of such a loop
(:class:`Loop`) and checks its parameters; :func:`zwidth.check` and :class:`zwidth.Device`
take them as keywords.
"""
from __future__ import annotations

import dataclasses
import math
import operator
import re
from typing import Any, Dict, Optional, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from ._kernels import ZwidthError

MAX_DELAY: int = int(_core.LOOP_MAX_DELAY)        #: delay in 0..MAX_DELAY samples
MAX_AVERAGE: int = int(_core.LOOP_MAX_AVERAGE)    #: moving average over 1..MAX_AVERAGE samples
DIFFERENTIATORS: Tuple[str, ...] = tuple(_core.LOOP_DIFFERENTIATORS)
_BOUNDARY_NAMES = {int(code): name for name, code in _core.LOOP_BOUNDARIES.items()}

#: What a Device accepts as velocity_filter.
#: None, ("lowpass", f_c [Hz]), ("pole", a in [0, 1): the drive's stored pole) or
#: ("average", n); also the text forms "lowpass:30Hz", "average:4".
VelocityFilter = Union[None, str, Tuple[str, Any]]


def _error(function: str, parameter: str, status: str, what: str, value: Any) -> ZwidthError:
    return ZwidthError(f"zwidth.{function}: {what} [{status}]", status, parameter, (),
                       {parameter: float(value) if isinstance(value, (int, float)) else math.nan})


def check_delay(function: str, delay: Any) -> int:
    """delay as an int in 0..MAX_DELAY, else ZwidthError naming it."""
    try:
        d = operator.index(delay)
    except TypeError:
        raise _error(function, "delay", "ZW_ERR_DELAY",
                     f"delay must be a whole number of samples in 0..{MAX_DELAY}, got {delay!r}",
                     delay) from None
    if not 0 <= d <= MAX_DELAY:
        raise _error(function, "delay", "ZW_ERR_DELAY",
                     f"delay must be in 0..{MAX_DELAY} samples, got {d}", d)
    return d


def check_differentiator(function: str, differentiator: Any) -> str:
    if differentiator not in DIFFERENTIATORS:
        raise _error(function, "differentiator", "ZW_ERR_ARG",
                     f"differentiator must be one of {', '.join(DIFFERENTIATORS)}, got {differentiator!r}",
                     differentiator)
    return str(differentiator)


def check_average(function: str, average: Any, parameter: str = "average") -> int:
    try:
        n = operator.index(average)
    except TypeError:
        raise _error(function, parameter, "ZW_ERR_FILTER",
                     f"{parameter} must be a whole number of samples in 1..{MAX_AVERAGE}, got {average!r}",
                     average) from None
    if not 1 <= n <= MAX_AVERAGE:
        raise _error(function, parameter, "ZW_ERR_FILTER",
                     f"{parameter} must be in 1..{MAX_AVERAGE} samples, got {n}", n)
    return n


@dataclasses.dataclass(frozen=True)
class Loop:
    """What the drive runs besides the plant and the gains.

    delay:          samples between the measurement x_k and the force it yields (0..8)
    differentiator: 'backward' (the paper's) or 'tustin'
    filter:         'none', 'lowpass' or 'average'
    cutoff:         low-pass cut-off f_c [Hz] (a Device's filter; array allowed), else None
    pole:           low-pass pole a in [0, 1): the normalized functions' filter_pole, or the
                    pole exp(-2 pi f_c T) of a Device's cut-off at its T; else None
    average:        moving-average length n (1..16), else None
    """

    delay: int = 0
    differentiator: str = "backward"
    filter: str = "none"
    cutoff: Any = None
    pole: Any = None
    average: Optional[int] = None

    @property
    def ideal(self) -> bool:
        """The paper's loop: no delay, backward difference, no filter."""
        return self.delay == 0 and self.differentiator == "backward" and self.filter == "none"

    def kernel_options(self) -> Dict[str, Any]:
        """The loop's kind as the _core.loop_* kernels take it."""
        return {"delay": self.delay, "differentiator": int(_core.LOOP_DIFFERENTIATORS[self.differentiator]),
                "filter": int(_core.LOOP_FILTERS[self.filter]), "average": int(self.average or 0)}

    def describe(self) -> str:
        """In words: 'ideal (no delay, backward difference, no filter)', '1 sample delay,
        low-pass 30 Hz', ..."""
        if self.ideal:
            return "ideal (no delay, backward difference, no velocity filter)"
        parts = []
        if self.delay:
            parts.append(f"{self.delay} sample{'s' if self.delay != 1 else ''} delay")
        if self.filter == "lowpass":
            if self.cutoff is not None:
                parts.append(f"low-pass {_values(self.cutoff)} Hz")
            else:
                parts.append(f"low-pass pole {_values(self.pole)}")
        elif self.filter == "average":
            parts.append(f"moving average of {self.average} samples")
        if self.differentiator != "backward":
            parts.append(f"{self.differentiator} differentiator")
        return ", ".join(parts)

    def statement(self) -> str:
        """The whole loop in words, every part named even where it is the paper's (the
        first line of every CLI output; zwidth-limits words it the same): 'the paper's
        ideal loop (delay 0, backward difference, no velocity filter)', '1 sample delay, backward difference, velocity
        low-pass 100 Hz (pole 0.533488)'."""
        delay = "delay 0" if self.delay == 0 else f"{self.delay} sample{'s' if self.delay != 1 else ''} delay"
        diff = "backward difference" if self.differentiator == "backward" else f"{self.differentiator} differentiator"
        if self.filter == "lowpass":
            pole = "" if self.pole is None else f"pole {_values(self.pole)}"
            vf = (f"velocity low-pass {_values(self.cutoff)} Hz" + (f" ({pole})" if pole else "")
                  if self.cutoff is not None else f"velocity low-pass {pole}")
        elif self.filter == "average":
            vf = f"velocity moving average of {self.average} samples"
        else:
            vf = "no velocity filter"
        text = f"{delay}, {diff}, {vf}"
        return f"the paper's ideal loop ({text})" if self.ideal else text

    def as_dict(self) -> Dict[str, Any]:
        c = None if self.cutoff is None else np.asarray(self.cutoff).tolist()
        p = None if self.pole is None else np.asarray(self.pole).tolist()
        return {"delay": self.delay, "differentiator": self.differentiator, "filter": self.filter,
                "cutoff": c, "pole": p, "average": self.average, "ideal": self.ideal,
                "text": self.describe(), "statement": self.statement()}


def _values(x: Any) -> str:
    a = np.asarray(x, dtype=float)
    return f"{float(a):g}" if a.ndim == 0 else f"array(shape={a.shape})"


def normalized_loop(function: str, delay: Any, filter_pole: ArrayLike, average: Any,
                    differentiator: Any) -> Loop:
    """The loop of the normalized functions' keywords (errors name the keyword)."""
    d = check_delay(function, delay)
    diff = check_differentiator(function, differentiator)
    pole = np.asarray(filter_pole, dtype=np.float64)
    has_pole = pole.ndim > 0 or not float(pole) == 0.0   # NaN counts as given (and fails in C)
    if average is not None:
        n = check_average(function, average)
        if has_pole:
            raise _error(function, "average", "ZW_ERR_FILTER",
                         "give either filter_pole (a low-pass) or average (a moving average), not both", n)
        return Loop(delay=d, differentiator=diff, filter="average", average=n)
    if has_pole:
        return Loop(delay=d, differentiator=diff, filter="lowpass", pole=filter_pole)
    return Loop(delay=d, differentiator=diff)


_FREQUENCY = re.compile(r"^\s*([0-9.eE+-]+)\s*(hz|khz)?\s*$", re.IGNORECASE)


def parse_velocity_filter(text: str) -> Tuple[str, Any]:
    """'lowpass:30Hz' -> ('lowpass', 30.0), 'lowpass:1.5kHz' -> ('lowpass', 1500.0),
    'pole:0.83' -> ('pole', 0.83), 'average:4' -> ('average', 4); 'none' -> ('none', None).
    ValueError otherwise."""
    kind, _, value = text.partition(":")
    kind = kind.strip().lower()
    if kind == "none" and not value:
        return ("none", None)
    if kind in ("lowpass", "low-pass"):
        m = _FREQUENCY.match(value)
        if not m:
            raise ValueError(f"a low-pass needs a cut-off in Hz, e.g. lowpass:30Hz, got {text!r}")
        f = float(m.group(1)) * (1e3 if (m.group(2) or "").lower() == "khz" else 1.0)
        return ("lowpass", f)
    if kind == "pole":
        try:
            return ("pole", float(value))
        except ValueError:
            raise ValueError(f"a pole needs a number in [0, 1), e.g. pole:0.83, got {text!r}") from None
    if kind == "average":
        try:
            return ("average", int(value))
        except ValueError:
            raise ValueError(f"a moving average needs a whole number of samples, e.g. average:4, got {text!r}") from None
    raise ValueError(f"unknown velocity filter {text!r}: use lowpass:F_CHz (e.g. lowpass:30Hz), pole:A "
                     f"(e.g. pole:0.83) or average:N (e.g. average:4)")


def device_loop(function: str, delay: Any, velocity_filter: VelocityFilter, differentiator: Any) -> Loop:
    """The loop of a Device's keywords (errors name the keyword).  The cut-off is checked
    against each element's Nyquist frequency by the Device (it needs T)."""
    d = check_delay(function, delay)
    diff = check_differentiator(function, differentiator)
    if velocity_filter is None:
        return Loop(delay=d, differentiator=diff)
    if isinstance(velocity_filter, str):
        try:
            velocity_filter = parse_velocity_filter(velocity_filter)
        except ValueError as exc:
            raise _error(function, "velocity_filter", "ZW_ERR_FILTER", str(exc), math.nan) from None
    if not (isinstance(velocity_filter, tuple) and len(velocity_filter) == 2):
        raise _error(function, "velocity_filter", "ZW_ERR_FILTER",
                     f"velocity_filter must be None, ('lowpass', f_c in Hz) or ('average', n), "
                     f"got {velocity_filter!r}", math.nan)
    kind, value = velocity_filter
    if kind == "none":
        return Loop(delay=d, differentiator=diff)
    if kind == "lowpass":
        return Loop(delay=d, differentiator=diff, filter="lowpass", cutoff=value)
    if kind == "pole":  # the drive's own stored pole a, exactly as it multiplies by it
        return Loop(delay=d, differentiator=diff, filter="lowpass", pole=value)
    if kind == "average":
        return Loop(delay=d, differentiator=diff, filter="average",
                    average=check_average(function, value, "velocity_filter"))
    raise _error(function, "velocity_filter", "ZW_ERR_FILTER",
                 f"unknown velocity filter kind {kind!r} (one of: lowpass, pole, average)", math.nan)


def boundary_name(code: int) -> str:
    """'none', 'z=1', 'z=-1' or 'complex' for a zw_loop_boundary code."""
    return _BOUNDARY_NAMES.get(int(code), "")
