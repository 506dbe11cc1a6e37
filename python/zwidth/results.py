# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Named results of zwidth's functions.

Each result is a frozen dataclass whose fields are numpy scalars (scalar inputs) or arrays
of the broadcast shape (array inputs).  They unpack like tuples (``lo, hi, ok =
dev.b_range(K)``), convert with ``as_dict()``, and print with 6 significant
digits (units are in each class's docstring; for a rotary device read kg as kg m^2,
N/m as N m/rad and N s/m as N m s/rad).
"""
from __future__ import annotations

import dataclasses
from typing import Any, Dict, Iterator, Mapping, Type, TypeVar

import numpy as np

from . import _core

_BOUND_NAMES = {int(bit): name for name, bit in _core.BOUNDS.items()}
_TREND_WORDS = {-1: "falls", 0: "is flat", 1: "rises"}


def _format(value: Any) -> str:
    if isinstance(value, np.ndarray):
        # 6 significant digits, as for scalars; long arrays are summarized
        return np.array2string(value, separator=", ", threshold=8, edgeitems=2,
                               formatter={"float_kind": lambda v: f"{v:.6g}"})
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.6g}"
    return repr(value)


R = TypeVar("R", bound="Result")


@dataclasses.dataclass(frozen=True, repr=False)
class Result:
    """Base of every result: tuple-like unpacking, ``as_dict()``, readable repr."""

    @classmethod
    def _result_fields(cls) -> Iterator["dataclasses.Field[Any]"]:
        # fields marked result=False are presentation settings, not results
        return (f for f in dataclasses.fields(cls) if f.metadata.get("result", True))

    def __iter__(self) -> Iterator[Any]:
        return (getattr(self, f.name) for f in self._result_fields())

    def as_dict(self) -> Dict[str, Any]:
        """The fields by name (values as stored: numpy scalars or arrays)."""
        return {f.name: getattr(self, f.name) for f in self._result_fields()}

    def __repr__(self) -> str:
        parts = []
        for f in dataclasses.fields(self):
            if f.repr:
                parts.append(f"{f.name}={_format(getattr(self, f.name))}")
        return f"{type(self).__name__}({', '.join(parts)})"

    @classmethod
    def from_outputs(cls: Type[R], outputs: Mapping[str, Any], **extra: Any) -> R:
        """Build from a kernel's outputs (extra keys ignored) plus ``extra`` fields."""
        names = {f.name for f in dataclasses.fields(cls) if f.init}
        return cls(**{k: v for k, v in outputs.items() if k in names}, **extra)


def _verdict_word(stable: Any, marginal: Any) -> Any:
    """'stable', 'marginal' or 'unstable' per element (a str for a scalar verdict)."""
    words = np.where(np.asarray(stable), "stable", np.where(np.asarray(marginal), "marginal", "unstable"))
    return str(words[()]) if words.ndim == 0 else words.astype(object)


@dataclasses.dataclass(frozen=True, repr=False)
class Verdict(Result):
    """A guarded stability verdict.

    stable:   True only if the point is stable for every value within the rounding-error
              bound (an unstable point is never called stable).
    marginal: within the rounding band of a boundary: could not be proved stable.
    deciding: the first violated constraint (a ``zwidth.BOUNDS`` bit, 0 when stable).
    violated: every violated or unprovable constraint, as ``zwidth.BOUNDS`` bits.
    status:   the C core's status code per element (0 = ok; see ``zwidth.STATUS_NAMES``);
              with ``errors="mask"`` it tells which elements were invalid.
    """

    stable: Any
    marginal: Any
    deciding: Any
    violated: Any
    status: Any

    @property
    def word(self) -> Any:
        """'stable', 'marginal' (within the rounding band: not proved stable) or 'unstable'."""
        return _verdict_word(self.stable, self.marginal)

    @property
    def deciding_name(self) -> Any:
        """Name of the deciding constraint ('line', 'hyperbola', ..., '' when stable)."""
        codes = np.asarray(self.deciding)
        names = np.vectorize(lambda c: _BOUND_NAMES.get(int(c), ""), otypes=[object])(codes)
        return names[()] if codes.ndim == 0 else names

    def __repr__(self) -> str:
        if np.ndim(self.stable) == 0:
            if self.status:
                return f"Verdict(invalid: {_core.STATUS_NAMES[int(self.status)]})"
            violated = [name for bit, name in _BOUND_NAMES.items() if int(self.violated) & bit]
            text = f"Verdict(stable={bool(self.stable)}, marginal={bool(self.marginal)}"
            if not self.stable:
                text += f", deciding={self.deciding_name!r}, violated={violated}"
            return text + ")"
        return super().__repr__()


@dataclasses.dataclass(frozen=True, repr=False)
class Coefficients(Result):
    """Coefficient functions of the sampled plant at delta (paper eqs (3), (4)):
    e = exp(-delta), c1, c2, d12 = c1 - c2, s = c1 + c2, g = c1 / s (all dimensionless)."""

    e: Any
    c1: Any
    c2: Any
    d12: Any
    s: Any
    g: Any


@dataclasses.dataclass(frozen=True, repr=False)
class Extremes(Result):
    """Impedance extremes in the normalized space (paper Section III).

    alpha_mmax: largest stable alpha = K T^2/m (a supremum, not attained), at
    beta_at_alpha_mmax; at_corner: it sits on the corner of hyperbola and line
    (delta > delta1) rather than on the hyperbola's top; alpha_p_max: largest alpha with
    beta = 0; beta_mmax: largest stable beta (alpha -> 0+); beta_mmin = -delta and
    alpha_mmin = 0 are the (unattained) lower extremes.
    """

    alpha_mmax: Any
    beta_at_alpha_mmax: Any
    at_corner: Any
    alpha_p_max: Any
    beta_mmax: Any
    beta_mmin: Any
    alpha_mmin: Any


@dataclasses.dataclass(frozen=True, repr=False)
class BoundaryPoint(Result):
    """A point (alpha, beta) of the stability boundary (NaN where it does not exist)."""

    alpha: Any
    beta: Any


@dataclasses.dataclass(frozen=True, repr=False)
class Interval(Result):
    """The open interval (lo, hi) of stable values; nonempty is False (and lo = hi = 0)
    where there is none.  Units: those of the quantity asked for."""

    lo: Any
    hi: Any
    nonempty: Any


@dataclasses.dataclass(frozen=True, repr=False)
class Normalized(Result):
    """A plant and gain pair in the normalized space: delta = b T/m, alpha = K T^2/m,
    beta = B T/m (dimensionless)."""

    delta: Any
    alpha: Any
    beta: Any


@dataclasses.dataclass(frozen=True, repr=False)
class DeviceExtremes(Result):
    """Impedance extremes in real units (paper Section IV; rotary: N m/rad, N m s/rad).

    K_mmax [N/m]: largest stable K (supremum), at B_at_K_mmax [N s/m]; at_corner: on the
    corner of hyperbola and line; K_p_max [N/m]: largest K with B = 0; B_mmax [N s/m]:
    largest stable B (K -> 0+); B_mmin = -b [N s/m] and K_mmin = 0 are not attained.
    """

    K_mmax: Any
    B_at_K_mmax: Any
    at_corner: Any
    K_p_max: Any
    B_mmax: Any
    B_mmin: Any
    K_mmin: Any


@dataclasses.dataclass(frozen=True, repr=False)
class Influence(Result):
    """Where the plant sits on the non-monotonic curves of K_mmax and B_mmax against m, b
    and T (paper Section IV, Table 1).  Masses in kg (rotary: kg m^2), periods in s,
    damping in N s/m, stiffness in N/m.

    K_mmax against m rises on (0, m_K2), falls on (m_K2, m_K1), rises beyond m_K1
    (local max K_mmax_at_m_K2, local min K_mmax_at_m_K1); raising m beats m_K2 only past
    m_K_match.  B_mmax against T falls on (0, T_B), rises on (T_B, T_0), falls beyond;
    against m rises on (0, m_0), falls on (m_0, m_B), rises beyond; against b rises on
    (0, b_0), falls on (b_0, b_BB), rises beyond.  The trends K_vs_m ... B_vs_T are the
    signs (-1 falls, 0 flat, +1 rises) of each limit's derivative at the plant;
    best_m_for_K is the mass that maximizes K_mmax short of m_K_match.
    """

    delta: Any
    K_mmax: Any
    B_mmax: Any
    m_K1: Any
    m_K2: Any
    K_mmax_at_m_K2: Any
    K_mmax_at_m_K1: Any
    m_K_match: Any
    T_B: Any
    T_0: Any
    m_0: Any
    m_B: Any
    b_0: Any
    b_BB: Any
    best_m_for_K: Any
    K_vs_m: Any
    K_vs_b: Any
    K_vs_T: Any
    B_vs_m: Any
    B_vs_b: Any
    B_vs_T: Any
    #: the plant's mass (or inertia), which the advice compares with m_K2
    m: Any = dataclasses.field(default=None, repr=False)
    #: "m", or "J" for a rotary device: the name the sentences use for the mass
    mass_symbol: str = dataclasses.field(default="m", repr=False, metadata={"result": False})

    @property
    def trends(self) -> str:
        """The six trends in words ('K_mmax falls with m, rises with b, ...')."""
        if np.ndim(self.K_vs_m) != 0:
            raise ValueError("trends is a sentence about one plant; index the arrays instead")
        words = [_TREND_WORDS[int(t)] for t in (self.K_vs_m, self.K_vs_b, self.K_vs_T,
                                                self.B_vs_m, self.B_vs_b, self.B_vs_T)]
        M = self.mass_symbol
        return (f"K_mmax {words[0]} with {M}, {words[1]} with b, {words[2]} with T; "
                f"B_mmax {words[3]} with {M}, {words[4]} with b, {words[5]} with T")

    @property
    def advice(self) -> str:
        """Knob-switch advice on the mass (paper Section IV-A, V-B-3), for one plant."""
        if np.ndim(self.K_vs_m) != 0 or self.m is None:
            raise ValueError("advice is about one plant; build a Device with scalar m, b, T")
        M = self.mass_symbol
        if not float(self.delta) > 0.0:
            return f"b = 0: delta = 0 for every {M} and T, so {M} and T scale the limits without turning points."
        if int(self.K_vs_m) < 0:
            return (f"{M} sits on the falling stretch ({M}_K2, {M}_K1) of K_mmax. Reduce {M} to "
                    f"{M}_K2 = {float(self.m_K2):.4g} for K_mmax = {float(self.K_mmax_at_m_K2):.4g} "
                    f"(from {float(self.K_mmax):.4g}); raising {M} only helps past "
                    f"{float(self.m_K_match):.4g}.")
        if float(self.m) < float(self.m_K2):
            return (f"raising {M} toward {M}_K2 = {float(self.m_K2):.4g} raises K_mmax up to "
                    f"{float(self.K_mmax_at_m_K2):.4g}.")
        return f"raising {M} raises K_mmax; so does shortening T."


@dataclasses.dataclass(frozen=True, repr=False)
class LoopVerdict(Result):
    """A guarded stability verdict of a general loop (delay, velocity filter,
    differentiator: :mod:`zwidth.loop`).

    stable:    True only if every root of the loop's characteristic polynomial is inside
               the unit circle for every value within the rounding-error bound.
    marginal:  within the rounding band of a boundary: could not be proved stable.
    boundary:  where the root of largest modulus crosses (or nearly does): a
               ``zwidth.LOOP_BOUNDARIES`` code, 0 ('none') when stable; see ``deciding_name``.
    theta:     for a complex pair, its angle in (0, pi) rad per sample, else 0.
    frequency: theta / (2 pi T) [Hz] for a Device; theta / (2 pi) [cycles per sample] in
               the normalized space.
    status:    the C core's status code per element (0 = ok).
    """

    stable: Any
    marginal: Any
    boundary: Any
    theta: Any
    frequency: Any
    status: Any
    #: "Hz" (a Device) or "cycles/sample" (normalized): the unit of frequency
    frequency_unit: str = dataclasses.field(default="cycles/sample", repr=False, metadata={"result": False})

    @property
    def word(self) -> Any:
        """'stable', 'marginal' (within the rounding band: not proved stable) or 'unstable'."""
        return _verdict_word(self.stable, self.marginal)

    @property
    def deciding_name(self) -> Any:
        """The deciding boundary: 'z=1' (static divergence), 'z=-1' (oscillation at the
        Nyquist frequency), 'complex pair at X Hz' (or cycles/sample), '' when stable."""
        def name(code: Any, freq: Any) -> str:
            kind = _LOOP_BOUNDARY_NAMES.get(int(code), "")
            if kind == "complex":
                return f"complex pair at {float(freq):.6g} {self.frequency_unit}"
            return "" if kind == "none" else kind
        names = np.vectorize(name, otypes=[object])(np.asarray(self.boundary), np.asarray(self.frequency))
        return str(names[()]) if names.ndim == 0 else names

    def __repr__(self) -> str:
        if np.ndim(self.stable) == 0:
            if self.status:
                return f"LoopVerdict(invalid: {_core.STATUS_NAMES[int(self.status)]})"
            text = f"LoopVerdict(stable={bool(self.stable)}, marginal={bool(self.marginal)}"
            if not self.stable:
                text += f", deciding={self.deciding_name!r}"
            return text + ")"
        return super().__repr__()


_LOOP_BOUNDARY_NAMES = {int(code): name for name, code in _core.LOOP_BOUNDARIES.items()}


@dataclasses.dataclass(frozen=True, repr=False)
class LoopExtremes(Result):
    """Impedance extremes of a general loop in the normalized space (loop_limits.h), all
    certified: never beyond the true values.

    alpha_mmax: largest stable alpha = K T^2/m found (a certified limit), at
    beta_at_alpha_mmax; alpha_p_max: largest alpha with beta = 0; beta_mmax, beta_mmin: the
    stable beta range as alpha -> 0+.
    """

    alpha_mmax: Any
    beta_at_alpha_mmax: Any
    alpha_p_max: Any
    beta_mmax: Any
    beta_mmin: Any


@dataclasses.dataclass(frozen=True, repr=False)
class DeviceLoopExtremes(Result):
    """Impedance extremes of a Device's loop in real units (N/m, N s/m; rotary N m/rad,
    N m s/rad), certified and pulled inward for the unit conversions.

    K_mmax: largest stable K found, at B_at_K_mmax; K_p_max: largest K with B = 0;
    B_mmax, B_mmin: the stable B range as K -> 0+.
    """

    K_mmax: Any
    B_at_K_mmax: Any
    K_p_max: Any
    B_mmax: Any
    B_mmin: Any


@dataclasses.dataclass(frozen=True, repr=False)
class LoopInfluence(Result):
    """What a Device's loop costs, and which filter cut-off keeps most (real units: N/m,
    N s/m, Hz; every K_mmax certified, NaN where no gains are stable).

    K_mmax_ideal, B_mmax_ideal: the paper's loop (no delay, no filter, backward difference);
    K_mmax, B_mmax: this loop; K_mmax_kept: K_mmax / K_mmax_ideal.
    delays, K_mmax_by_delay: K_mmax with each delay (this loop's filter and differentiator).
    cutoffs, K_mmax_by_cutoff: with a low-pass, K_mmax against its cut-off (this delay), on a
    log grid below the Nyquist frequency; best_cutoff, K_mmax_at_best_cutoff: the grid's best.
    """

    K_mmax_ideal: Any
    B_mmax_ideal: Any
    K_mmax: Any
    B_mmax: Any
    K_mmax_kept: Any
    delays: Any
    K_mmax_by_delay: Any
    cutoffs: Any
    K_mmax_by_cutoff: Any
    best_cutoff: Any
    K_mmax_at_best_cutoff: Any
    #: the loop in words
    loop_text: str = dataclasses.field(default="", repr=False, metadata={"result": False})

    @property
    def advice(self) -> str:
        """The cost and the filter advice in words."""
        text = (f"{self.loop_text} keeps {100 * float(self.K_mmax_kept):.3g} % of the ideal loop's K_mmax "
                f"({float(self.K_mmax):.4g} of {float(self.K_mmax_ideal):.4g})")
        by_delay = ", ".join(f"{int(d)}: {float(k):.4g}" for d, k in zip(self.delays, self.K_mmax_by_delay))
        text += f"; K_mmax by delay in samples: {by_delay}"
        if self.cutoffs is not None and np.isfinite(float(self.K_mmax_at_best_cutoff)):
            text += (f"; of the low-pass cut-offs tried, {float(self.best_cutoff):.4g} Hz keeps most: "
                     f"K_mmax {float(self.K_mmax_at_best_cutoff):.4g}")
        return text
