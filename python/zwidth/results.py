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
import enum
import html
from typing import Any, Dict, Iterator, Mapping, Type, TypeVar

import numpy as np

from . import _core

_BOUND_NAMES = {int(bit): name for name, bit in _core.BOUNDS.items()}
_TREND_WORDS = {-1: "falls", 0: "is flat", 1: "rises"}


class _Named:
    """Mixin: print as the lower-case name ('hyperbola', 'line|hyperbola') and compare
    equal to that name as well as to the integer code."""

    def _text(self) -> str:
        raise NotImplementedError

    def __str__(self) -> str:
        return self._text()

    def __format__(self, spec: str) -> str:
        return format(self._text(), spec)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, str):
            return self._text() == other
        return int(self) == other  # type: ignore[call-overload, no-any-return]

    def __ne__(self, other: object) -> bool:
        return not self == other

    def __hash__(self) -> int:
        return hash(int(self))  # type: ignore[call-overload]


class Bound(_Named, enum.IntFlag):
    """The constraints of the exact region (paper eq (10)) and passivity: the bits of
    ``Verdict.deciding`` and ``Verdict.violated``.  A member prints as its name
    (``str(Bound.LINE) == 'line'``, a combination as 'hyperbola|line', none as '') and
    compares equal to its name and to its integer bit."""

    NONE = 0
    DAMPING = int(_core.BOUNDS["damping"])      #: beta > -delta (B > -b)
    STIFFNESS = int(_core.BOUNDS["stiffness"])  #: alpha > 0 (K > 0)
    HYPERBOLA = int(_core.BOUNDS["hyperbola"])  #: alpha < f(beta)
    LINE = int(_core.BOUNDS["line"])            #: alpha < L(beta), delta > delta0
    PASSIVITY = int(_core.BOUNDS["passivity"])  #: K T/2 < b - |B| (region 'passivity')

    def _text(self) -> str:
        return "|".join(_BOUND_NAMES[int(bit)] for bit in sorted(_BOUND_NAMES) if int(self) & bit)

    def __repr__(self) -> str:
        return f"Bound({self._text()!r})" if int(self) else "Bound.NONE"


class LoopBoundary(_Named, enum.IntEnum):
    """Where the root of largest modulus of a general loop crosses the unit circle
    (``LoopVerdict.boundary``); prints as 'z=1', 'z=-1', 'complex' or 'none'."""

    NONE = int(_core.LOOP_BOUNDARIES["none"])
    Z_PLUS_1 = int(_core.LOOP_BOUNDARIES["z=1"])    #: static divergence
    Z_MINUS_1 = int(_core.LOOP_BOUNDARIES["z=-1"])  #: oscillation at the Nyquist frequency
    COMPLEX = int(_core.LOOP_BOUNDARIES["complex"])  #: a complex pair: oscillation at its frequency

    def _text(self) -> str:
        return {0: "none", 1: "z=1", 2: "z=-1", 3: "complex"}[int(self)]

    def __repr__(self) -> str:
        return f"LoopBoundary({self._text()!r})"


class Trend(_Named, enum.IntEnum):
    """The sign of a limit's derivative against m, b or T at a plant (``Influence.K_vs_m``
    ...): prints as 'falls', 'is flat' or 'rises'; compares equal to -1, 0, +1 too."""

    FALLS = -1
    FLAT = 0
    RISES = 1

    def _text(self) -> str:
        return _TREND_WORDS[int(self)]

    def __repr__(self) -> str:
        return f"Trend({self._text()!r})"


def _named(kind: Any, value: Any) -> Any:
    """A scalar code as its named member (arrays stay integer codes, which compare with
    the members elementwise: ``v.deciding == Bound.LINE``)."""
    if value is None or np.ndim(value) != 0 or isinstance(value, kind):
        return value
    return kind(int(value))


#: Arrays longer than this print as a summary (shape, range) instead of their values.
_SHORT_ARRAY = 8


def _summary(value: "np.ndarray[Any, Any]") -> str:
    """array(shape=(200, 300), 0.0123..4.56, 3 NaN): a sweep's result at a glance."""
    head = f"array(shape={value.shape}"
    if value.size == 0:
        return head + ")"
    if value.dtype.kind == "b":
        return head + f", {100.0 * float(value.mean()):.3g} % True)"
    if value.dtype.kind in "iu":
        return head + f", {int(value.min())}..{int(value.max())})"
    if value.dtype.kind == "f":
        finite = value[np.isfinite(value)]
        text = head + (f", {float(finite.min()):.4g}..{float(finite.max()):.4g}" if finite.size else "")
        nan = int(np.isnan(value).sum())
        return text + (f", {nan} NaN)" if nan else ")")
    return head + f", dtype={value.dtype})"


def _format(value: Any) -> str:
    if isinstance(value, np.ndarray):
        if value.size > _SHORT_ARRAY:
            return _summary(value)
        # 6 significant digits, as for scalars
        return np.array2string(value, separator=", ", threshold=_SHORT_ARRAY, edgeitems=2,
                               formatter={"float_kind": lambda v: f"{v:.6g}"})
    if isinstance(value, _Named):
        return repr(str(value))
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
        """The fields by name (values as stored: numpy scalars or arrays); a verdict's
        ``loop`` as the loop's own dict (:meth:`zwidth.Loop.as_dict`)."""
        out = {f.name: getattr(self, f.name) for f in self._result_fields()}
        for f in dataclasses.fields(self):
            if f.metadata.get("as_dict") and getattr(self, f.name) is not None:
                out[f.name] = getattr(self, f.name).as_dict()
        return out

    def __repr__(self) -> str:
        parts = []
        for f in dataclasses.fields(self):
            if f.metadata.get("as_dict"):   # a verdict's loop, in words (none when built by hand)
                parts += [_loop_repr(getattr(self, f.name)).lstrip(", ")] if getattr(self, f.name) is not None else []
            elif f.repr:
                parts.append(f"{f.name}={_format(getattr(self, f.name))}")
        return f"{type(self).__name__}({', '.join(parts)})"

    def _repr_html_(self) -> str:
        """A table for notebooks: one row per field, arrays summarized (shape, range)."""
        doc = (type(self).__doc__ or "").strip().split("\n")[0]
        rows = "".join(f"<tr><th style='text-align:left'>{html.escape(f.name)}</th>"
                       f"<td style='text-align:left'><code>{html.escape(_format(getattr(self, f.name)))}</code></td></tr>"
                       for f in dataclasses.fields(self) if f.repr)
        return (f"<table><caption style='text-align:left'><b>{type(self).__name__}</b> "
                f"{html.escape(doc)}</caption>{rows}</table>")

    @classmethod
    def from_outputs(cls: Type[R], outputs: Mapping[str, Any], **extra: Any) -> R:
        """Build from a kernel's outputs (extra keys ignored) plus ``extra`` fields."""
        names = {f.name for f in dataclasses.fields(cls) if f.init}
        return cls(**{k: v for k, v in outputs.items() if k in names}, **extra)


def _loop_repr(loop: Any) -> str:
    """', loop=...' of a verdict's repr: the loop it judged, in words."""
    return "" if loop is None else f", loop={loop.statement()!r}"


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
    deciding: the first violated constraint, a :class:`zwidth.Bound` (prints and compares
              as its name: ``v.deciding == 'line'``; ``Bound.NONE`` when stable); for
              arrays the integer bits (``v.deciding == zwidth.Bound.LINE`` elementwise).
    violated: every violated or unprovable constraint, a :class:`zwidth.Bound`
              combination ('hyperbola|line'); for arrays the integer bits.
    status:   the C core's status code per element (0 = ok; see ``zwidth.STATUS_NAMES``);
              with ``errors="mask"`` it tells which elements were invalid.
    """

    stable: Any
    marginal: Any
    deciding: Any
    violated: Any
    status: Any
    #: the loop this verdict is for (:class:`zwidth.Loop`; None only when built by hand):
    #: printed by repr and in as_dict(), not unpacked with the fields
    loop: Any = dataclasses.field(default=None, metadata={"result": False, "as_dict": True})

    def __post_init__(self) -> None:
        object.__setattr__(self, "deciding", _named(Bound, self.deciding))
        object.__setattr__(self, "violated", _named(Bound, self.violated))

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
            text = f"Verdict(stable={bool(self.stable)}, marginal={bool(self.marginal)}"
            if not self.stable:
                violated = [name for bit, name in _BOUND_NAMES.items() if int(self.violated) & bit]
                text += f", deciding={str(self.deciding)!r}, violated={violated}"
            return text + _loop_repr(self.loop) + ")"
        stable = np.asarray(self.stable)
        codes = np.asarray(self.deciding)
        counts = ", ".join(f"{_BOUND_NAMES[int(c)]}: {int((codes == c).sum())}"
                           for c in np.unique(codes) if int(c) in _BOUND_NAMES)
        return (f"Verdict(shape={stable.shape}, stable={int(stable.sum())} of {stable.size}, "
                f"marginal={int(np.asarray(self.marginal).sum())}"
                + (f", deciding={{{counts}}}" if counts else "") + _loop_repr(self.loop) + ")")


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
class Boundary(Result):
    """The exact region's outline at one delta as arrays, beta ascending from -delta to
    beta_mmax, alpha = alpha_max(beta) (0 at both ends, which the region does not
    contain); the hyperbola's top and the corner where the line meets it (delta > delta0)
    are among the points, so the corner stays sharp.  ``beta, alpha = boundary`` unpacks."""

    beta: Any
    alpha: Any


@dataclasses.dataclass(frozen=True, repr=False)
class DeviceBoundary(Result):
    """A plant's region as arrays in real units: B [N s/m] ascending from B_mmin = -b to
    B_mmax, K = K_max(B) [N/m] (rotary: N m s/rad, N m/rad), the point of K_mmax and the
    corner included.  ``B, K = dev.boundary()`` unpacks."""

    B: Any
    K: Any


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

    def __post_init__(self) -> None:
        for name in ("K_vs_m", "K_vs_b", "K_vs_T", "B_vs_m", "B_vs_b", "B_vs_T"):
            object.__setattr__(self, name, _named(Trend, getattr(self, name)))

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
               :class:`zwidth.LoopBoundary` ('z=1', 'z=-1', 'complex', 'none' when
               stable; integer codes for arrays); see ``deciding_name``.
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
    #: the loop this verdict is for (:class:`zwidth.Loop`; None only when built by hand):
    #: printed by repr and in as_dict(), not unpacked with the fields
    loop: Any = dataclasses.field(default=None, metadata={"result": False, "as_dict": True})

    def __post_init__(self) -> None:
        object.__setattr__(self, "boundary", _named(LoopBoundary, self.boundary))

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
            return text + _loop_repr(self.loop) + ")"
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
