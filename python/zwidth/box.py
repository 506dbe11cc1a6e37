# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""Certification over an uncertain plant: every m in [m_lo, m_hi], b in [b_lo, b_hi].

A drive's load changes (a hand grips or lets go, a tool is mounted), so one (m, b) is not
enough.  :class:`PlantBox` answers for every plant of a box at once, for the paper's ideal
loop, with the C core's branch and bound (csrc/src/box.c, docs/box.md):

* ``is_stable(K, B)`` / ``verdict(K, B)``: stable for every plant (certified), or a plant
  where it is not;
* ``k_max(B)``: the largest K stable at B for every plant, never above the true minimum
  over the box of K_max(B) (``K_lower``), with the worst plant found and its K_max
  (``K_upper``): the true value lies in [K_lower, K_upper];
* ``b_range(K)``: B that keep K stable for every plant (an inner interval);
* ``extremes()``: the largest K that one B makes stable for every plant, and that B.

The loop a drive runs (``delay``, ``velocity_filter``, ``differentiator``, as
:class:`zwidth.Device` takes them) is certified by a second method (csrc/src/box_loop.c:
Kharitonov's theorem on the bilinear image of the characteristic polynomial over sub-boxes
of plants and gains); there "stable at (K, B)" means every K' in (0, K] is stable at B for
every plant, and ``extremes()`` searches B by golden section (certified at the B it ends
on).

Plant-side parts (``stiffness`` k_p, a coupled ``hand`` with ranges of m_h, b_h, k_h) enter
the plant only through M = m + m_h, Bp = b + b_h, Kp = k_p + k_h: the C core folds the box
into ranges of those (sums rounded outward), and the worst plants reported (``m_worst``,
``b_worst``, ``k_worst``) are the totals.  With stiffness only the general-loop method
certifies (``method='kharitonov'``, chosen by ``'auto'``), over the enclosure of the plant
with stiffness (docs/box.md), within delta = Bp T / M <= 4 and kappa = Kp T^2 / M <= 4 (far
beyond a haptic drive's: ZW_ERR_RANGE otherwise).  An actuator-lag range is not supported
yet (``actuator_tau`` other than 0: ZW_ERR_ARG).

A separate class rather than ``Device`` with interval arguments: a ``Device`` broadcasts
over arrays of plants and answers per plant, while a box answers once for all of them
(and runs a search whose budget is part of the answer).
"""
from __future__ import annotations

import dataclasses
import math
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

from . import _core
from ._kernels import STATUS_NAMES, ZwidthError
from .device import Device
from .loop import Loop, VelocityFilter, device_loop
from .results import Interval, Result

RangeLike = Union[float, Sequence[float], "PlantRange"]

#: Budget defaults (larger than the C defaults: host memory is cheap).  With them the
#: relative gap K_upper / K_lower - 1 is below 1e-6 on every box of the reference tests,
#: also where K_max has an interior minimum in m.
DEFAULT_CAPACITY = 1 << 16
DEFAULT_MAX_EVALS = 400_000
DEFAULT_REL_TOL = float(_core.BOX_DEFAULT_REL_TOL)
#: The general loop's defaults: cell tests per certification (one per K bisection step),
#: and the bisections' relative tolerance (1e-4: 20-60 ms per K_max at degree 4).
DEFAULT_LOOP_MAX_EVALS = 100_000
DEFAULT_LOOP_REL_TOL = float(_core.BOX_LOOP_DEFAULT_REL_TOL)


@dataclasses.dataclass(frozen=True)
class PlantRange:
    """A closed range lo..hi of one plant parameter (lo == hi: a point)."""

    lo: float
    hi: float

    def __str__(self) -> str:
        return f"{self.lo:g}:{self.hi:g}"

    @property
    def mid(self) -> float:
        return self.lo + 0.5 * (self.hi - self.lo)


def parse_range(text: str) -> Union[float, PlantRange]:
    """'0.12' -> 0.12, '0.10:0.14' -> PlantRange(0.10, 0.14) (the CLI's --m, --J, --b)."""
    if ":" not in text:
        return float(text)
    lo, sep, hi = text.partition(":")
    if ":" in hi or not lo.strip() or not hi.strip():
        raise ValueError(f"a range is LO:HI, got {text!r}")
    return PlantRange(float(lo), float(hi))


parse_range.__name__ = "number or range LO:HI"  # argparse names the type in its message


def _as_range(name: str, value: RangeLike) -> PlantRange:
    if isinstance(value, PlantRange):
        return value
    if isinstance(value, (int, float)):
        return PlantRange(float(value), float(value))
    items = [float(v) for v in value]
    if len(items) != 2:
        raise ValueError(f"zwidth.PlantBox: {name} must be a number or a pair (lo, hi), got {value!r}")
    return PlantRange(items[0], items[1])


@dataclasses.dataclass(frozen=True, repr=False)
class BoxBound(Result):
    """min over the box of K_max(B): K_lower (certified, never above it) <= true <= K_upper
    (K_max at the worst plant found, m_worst, b_worst); converged: the relative gap is
    within the box's rel_tol; evals: cell bounds computed."""

    K_lower: float
    K_upper: float
    m_worst: float
    b_worst: float
    evals: int
    converged: bool
    k_worst: float = 0.0  #: the worst plant's Kp (0 without stiffness)

    @property
    def gap(self) -> float:
        """Relative gap (K_upper - K_lower) / K_upper (0 when both are 0)."""
        return 0.0 if self.K_upper == 0.0 else (self.K_upper - self.K_lower) / self.K_upper


@dataclasses.dataclass(frozen=True, repr=False)
class BoxVerdict(Result):
    """stable: certified for every plant of the box; decided False: the budget ran out
    first (stable is then False too).  m_worst, b_worst: a plant where the gains are
    unstable (when refuted), else the plant of least K_max found; K_lower: the certified
    lower bound of the box's K_max at this B reached by the search."""

    stable: bool
    decided: bool
    K_lower: float
    m_worst: float
    b_worst: float
    k_worst: float = 0.0

    @property
    def word(self) -> str:
        return "stable" if self.stable else ("unstable" if self.decided else "undecided")


@dataclasses.dataclass(frozen=True, repr=False)
class BoxExtremes(Result):
    """K_mmax: certified, every K in (0, K_mmax) is stable at B = B_at for every plant;
    K_upper_at: K_max(B_at) at the worst plant found (m_worst, b_worst); K_mmax_upper:
    that plant's own K_mmax, which no single B can beat for the whole box."""

    K_mmax: float
    B_at: float
    K_upper_at: float
    K_mmax_upper: float
    m_worst: float
    b_worst: float
    converged: bool
    k_worst: float = 0.0


#: Bytes of a certificate on the wire and in a drive's stored image (box_cert.h's
#: zw_box_cert: 2 counts, 17 breakpoints and 16 levels as binary32, 256 words of nodes).
BOX_CERT_MAX_STEPS = 16
BOX_CERT_NODE_WORDS = 256
BOX_CERT_BYTES = 2 * (2 + 2 * 17 + 2 * 16 + 256)

#: zw_box_cert_fault's names (box_cert.h).
BOX_CERT_FAULTS = ("ok", "bad header", "bad step", "bad node", "bad split", "too many leaves",
                   "unused nodes", "a leaf fails")


@dataclasses.dataclass(frozen=True, repr=False)
class BoxCertificate(Result):
    """A staircase of stiffness limits over B, proven for every plant of a box (box_cert.h).

    Step i: every K' in (0, K[i]] is stable at every B in [B[i], B[i+1]] for every plant,
    with the box's loop.  ``K_upper[i]``: the least point K_max found at the step's ends and
    middle (the level cannot pass it; ``K[i] / K_upper[i]`` is how much the proof keeps).
    ``nodes``: the proof, the preorder of a k-d tree per step (0 a leaf, 1..5 a split of
    m, b, K, B or k_p).  Built and verified in ``precision`` ("float": what a float drive
    checks); ``verify_seconds`` is the host's verification, a drive's is measured by
    tools/m4f_box_cert.sh."""

    B: Tuple[float, ...]
    K: Tuple[float, ...]
    K_upper: Tuple[float, ...]
    nodes: Tuple[int, ...]
    precision: str
    leaves: int
    tests: int
    build_seconds: float
    verify_seconds: float

    @property
    def size_bytes(self) -> int:
        """Its size on the wire and in the stored image (fixed: the largest certificate)."""
        return BOX_CERT_BYTES

    def level(self, B: float) -> float:
        """The certified level at B (the larger one on a breakpoint; 0 outside)."""
        B = float(B)
        if not self.B[0] <= B <= self.B[-1]:
            return 0.0
        return max(k for k, lo, hi in zip(self.K, self.B, self.B[1:]) if lo <= B <= hi)

    def steps(self) -> List[Tuple[float, float, float, float]]:
        """(B_lo, B_hi, K, K_upper) per step."""
        return list(zip(self.B, self.B[1:], self.K, self.K_upper))

    def words(self) -> List[int]:
        """The certificate as the drive's window (ZW_REG_BOX_CERT, map version 5) and stored
        image hold it: n_steps, n_nodes, the 17 breakpoints and 16 levels as binary32 (high
        word first, unused ones 0), the nodes four to a word (lowest nibble first), 324
        words in all."""
        import struct

        B = list(self.B) + [0.0] * (BOX_CERT_MAX_STEPS + 1 - len(self.B))
        K = list(self.K) + [0.0] * (BOX_CERT_MAX_STEPS - len(self.K))
        out = [len(self.K), len(self.nodes)]
        out += list(struct.unpack(f">{2 * len(B + K)}H", struct.pack(f">{len(B + K)}f", *(B + K))))
        packed = [0] * BOX_CERT_NODE_WORDS
        for j, code in enumerate(self.nodes):
            packed[j // 4] |= (int(code) & 0xF) << (4 * (j % 4))
        return out + packed

    def as_wire(self) -> Dict[str, Any]:
        """The fields zw_box_cert holds (for _core.box_cert_verify and a drive)."""
        return {"n_steps": len(self.K), "n_nodes": len(self.nodes), "B": list(self.B), "K": list(self.K),
                "nodes": list(self.nodes)}


HandLike = Tuple[RangeLike, RangeLike, RangeLike]


class PlantBox:
    """Every plant with m in [m_lo, m_hi] and b in [b_lo, b_hi], sampled every T.

    ``m`` and ``b`` are each a number (fixed) or a pair (lo, hi); ``rotary=True`` reads m
    as the inertia J (units N m/rad, N m s/rad).  ``capacity`` (cells of the work list),
    ``max_evals`` (cell bounds per search) and ``rel_tol`` (stop at this relative gap)
    bound each search.  Invalid boxes raise :class:`zwidth.ZwidthError` (status
    ``ZW_ERR_BOX`` for lo > hi).  ``stiffness`` (k_p) and ``hand`` = (m_h, b_h, k_h) are each
    a number or a range, as m and b (module docstring).
    """

    def __init__(self, m: RangeLike, b: RangeLike, T: float, *, rotary: bool = False,
                 capacity: int = DEFAULT_CAPACITY, max_evals: Optional[int] = None,
                 rel_tol: Optional[float] = None, delay: int = 0, velocity_filter: VelocityFilter = None,
                 differentiator: str = "backward", method: str = "auto", stiffness: RangeLike = 0.0,
                 hand: Optional[HandLike] = None, actuator_tau: RangeLike = 0.0) -> None:
        self.m = _as_range("J" if rotary else "m", m)
        self.b = _as_range("b", b)
        self.T = float(T)
        self.rotary = bool(rotary)
        #: Physical stiffness k_p, the hand's (m_h, b_h, k_h) ranges, the lag (0: absent).
        self.stiffness = _as_range("stiffness", stiffness)
        if hand is not None and not (isinstance(hand, (tuple, list)) and len(hand) == 3):
            raise ValueError(f"zwidth.PlantBox: hand must be (m_h, b_h, k_h), each a number or (lo, hi), got {hand!r}")
        h = (0.0, 0.0, 0.0) if hand is None else hand
        self.hand: Tuple[PlantRange, PlantRange, PlantRange] = (
            _as_range("hand m_h", h[0]), _as_range("hand b_h", h[1]), _as_range("hand k_h", h[2]))
        self.actuator_tau = _as_range("actuator_tau", actuator_tau)
        stiff = self.stiffness.hi > 0.0 or self.hand[2].hi > 0.0
        #: The loop (:class:`zwidth.loop.Loop`), as a Device's keywords give it.
        self.loop: Loop = device_loop("PlantBox", delay, velocity_filter, differentiator)
        if method not in ("auto", "closed-form", "kharitonov"):
            raise ValueError(f"zwidth.PlantBox: method must be 'auto', 'closed-form' or 'kharitonov', got {method!r}")
        if method == "closed-form" and not self.loop.ideal:
            raise ValueError("zwidth.PlantBox: the closed form holds for the paper's ideal loop only")
        if method == "closed-form" and stiff:
            raise ValueError("zwidth.PlantBox: the closed form holds for the plant without stiffness only")
        #: 'closed-form' (box.c, the ideal loop) or 'kharitonov' (box_loop.c, any loop).
        self.method = ("closed-form" if self.loop.ideal and not stiff else "kharitonov") if method == "auto" else method
        general = self.method == "kharitonov"
        self.capacity = int(capacity)
        self.max_evals = int(max_evals if max_evals is not None else
                             (DEFAULT_LOOP_MAX_EVALS if general else DEFAULT_MAX_EVALS))
        self.rel_tol = float(rel_tol if rel_tol is not None else (DEFAULT_LOOP_REL_TOL if general else DEFAULT_REL_TOL))
        # validate now (an empty search: B = 0 is always a valid gain)
        if general:
            self._raise(self._call_loop(_core.box_loop_check, 0.0, 0.0, max_evals_override=1), "PlantBox", {})
        else:
            self._raise(self._call(_core.box_k_max, 0.0, max_evals_override=1), "PlantBox", {})

    @classmethod
    def rotary_box(cls, J: RangeLike, b: RangeLike, T: float, **kwargs: Any) -> "PlantBox":
        return cls(J, b, T, rotary=True, **kwargs)

    @property
    def mass_symbol(self) -> str:
        return "J" if self.rotary else "m"

    def __repr__(self) -> str:
        loop = "" if self.loop.ideal else f", loop={self.loop.describe()!r}"
        parts = f", stiffness={self.stiffness}" if self.stiffness.hi > 0.0 else ""
        if any(r.hi > 0.0 for r in self.hand):
            parts += f", hand=({self.hand[0]}, {self.hand[1]}, {self.hand[2]})"
        return f"PlantBox({self.mass_symbol}={self.m}, b={self.b}, T={self.T:g}{parts}{loop})"

    @property
    def parts(self) -> Tuple[float, ...]:
        """box.h's plant-side fields: k_lo, k_hi, m_h_lo, m_h_hi, b_h_lo, b_h_hi, k_h_lo,
        k_h_hi, tau_lo, tau_hi."""
        out: Tuple[float, ...] = ()
        for r in (self.stiffness, *self.hand, self.actuator_tau):
            out += (r.lo, r.hi)
        return out

    @property
    def totals(self) -> Tuple[PlantRange, PlantRange, PlantRange]:
        """The ranges of M = m + m_h, Bp = b + b_h, Kp = k_p + k_h (rounded to nearest;
        the core rounds them outward)."""
        (mh, bh, kh), k = self.hand, self.stiffness
        return (PlantRange(self.m.lo + mh.lo, self.m.hi + mh.hi), PlantRange(self.b.lo + bh.lo, self.b.hi + bh.hi),
                PlantRange(k.lo + kh.lo, k.hi + kh.hi))

    def _device(self, m: float, b: float, k: float = 0.0) -> Device:
        lp = self.loop
        vf: VelocityFilter = None
        if lp.filter == "lowpass":
            vf = ("lowpass", lp.cutoff) if lp.cutoff is not None else ("pole", lp.pole)
        elif lp.filter == "average":
            vf = ("average", lp.average)
        return Device(m, b, self.T, rotary=self.rotary, delay=lp.delay, velocity_filter=vf,
                      differentiator=lp.differentiator, stiffness=k)

    @property
    def nominal(self) -> Device:
        """The plant at the middle of the box (with the box's loop; a hand folded in)."""
        M, Bp, Kp = self.totals
        return self._device(M.mid, Bp.mid, Kp.mid)

    def corners(self) -> Tuple[Device, ...]:
        M, Bp, Kp = self.totals
        ks = (Kp.lo, Kp.hi) if Kp.hi > Kp.lo else (Kp.lo,)
        return tuple(self._device(m, b, k) for m in (M.lo, M.hi) for b in (Bp.lo, Bp.hi) for k in ks)

    # ---- the C calls ------------------------------------------------------------------

    def _call(self, kernel: Any, *gains: float, max_evals_override: Optional[int] = None) -> Dict[str, Any]:
        out: Dict[str, Any] = kernel(self.m.lo, self.m.hi, self.b.lo, self.b.hi, self.T, *gains, self.capacity,
                      self.max_evals if max_evals_override is None else max_evals_override, self.rel_tol,
                      self.parts)
        return out

    def _call_loop(self, kernel: Any, *gains: Any, max_evals_override: Optional[int] = None) -> Dict[str, Any]:
        lp = self.loop
        opts = lp.kernel_options()
        pole_given = lp.cutoff is None and lp.pole is not None
        value = float(lp.pole if pole_given else (lp.cutoff or 0.0))
        out: Dict[str, Any] = kernel(self.m.lo, self.m.hi, self.b.lo, self.b.hi, self.T, opts["delay"],
                                     opts["differentiator"], opts["filter"], value, pole_given, opts["average"],
                                     *gains, self.capacity,
                                     self.max_evals if max_evals_override is None else max_evals_override,
                                     self.rel_tol, self.parts)
        return out

    def _raise(self, out: Dict[str, Any], function: str, gains: Dict[str, float]) -> Dict[str, Any]:
        status = STATUS_NAMES.get(int(out["status"]), "ZW_UNKNOWN")
        if status == "ZW_OK":
            return out
        sym = self.mass_symbol
        values = {f"{sym}_lo": self.m.lo, f"{sym}_hi": self.m.hi, "b_lo": self.b.lo, "b_hi": self.b.hi,
                  "T": self.T, **gains}
        ranges = {sym: self.m, "b": self.b, "stiffness": self.stiffness, "hand m_h": self.hand[0],
                  "hand b_h": self.hand[1], "hand k_h": self.hand[2], "actuator_tau": self.actuator_tau}
        for name in ("stiffness", "hand m_h", "hand b_h", "hand k_h", "actuator_tau"):
            if ranges[name].hi != 0.0 or ranges[name].lo != 0.0:
                values[name + "_lo"], values[name + "_hi"] = ranges[name].lo, ranges[name].hi
        parameter: Optional[str] = None
        negative = next((n for n in ("stiffness", "hand m_h", "hand b_h", "hand k_h", "actuator_tau")
                         if ranges[n].lo < 0.0), None)
        if status == "ZW_ERR_BOX":
            parameter = next((n for n, r in ranges.items() if r.lo > r.hi), "b")
            what = f"{parameter} range must have lo <= hi, got {ranges[parameter]}"
        elif status in ("ZW_ERR_ARG", "ZW_ERR_DAMPING") and negative is not None:
            parameter, what = negative, f"{negative} must be >= 0, got {ranges[negative].lo!r}"
        elif status == "ZW_ERR_ARG" and self.actuator_tau.hi > 0.0:
            parameter, what = "actuator_tau", "an actuator lag range is not supported by the box yet"
        elif status == "ZW_ERR_MASS":
            parameter, what = sym, f"{sym}_lo must be > 0, got {self.m.lo!r}"
        elif status == "ZW_ERR_DAMPING":
            parameter, what = "b", f"b_lo must be >= 0, got {self.b.lo!r}"
        elif status == "ZW_ERR_PERIOD":
            parameter, what = "T", f"T must be > 0, got {self.T!r}"
        elif status in ("ZW_ERR_NAN", "ZW_ERR_INF"):
            parameter = next((n for n, v in values.items() if not math.isfinite(v)), None)
            what = f"{parameter} must be a finite number, got {values.get(parameter or '', float('nan'))!r}"
        elif status == "ZW_ERR_RANGE":
            what = ("the box reaches plants outside the core's range (a corner refused by Device, "
                    "or b_hi T / m_lo above 1e6; with stiffness, delta = Bp T / M or kappa = Kp T^2 / M "
                    "above 4), or a gain overflows once normalized")
        elif status == "ZW_ERR_ARG":
            what = "capacity, max_evals or rel_tol out of range (rel_tol in [0, 1))"
        elif status in ("ZW_ERR_DELAY", "ZW_ERR_FILTER"):
            what = f"the loop is out of range ({status}): {self.loop.describe()}"
        else:
            what = status
        where = "zwidth.PlantBox" if function == "PlantBox" else f"zwidth.PlantBox.{function}"
        raise ZwidthError(f"{where}: {what}", status, parameter, (), values)

    # ---- public API -------------------------------------------------------------------

    def k_max(self, B: float) -> BoxBound:
        """min over the box of K_max(B) (certified lower bound, the worst plant found)."""
        if self.method == "kharitonov":
            out = self._raise(self._call_loop(_core.box_loop_k_max, float(B)), "k_max", {"B": float(B)})
        else:
            out = self._raise(self._call(_core.box_k_max, float(B)), "k_max", {"B": float(B)})
        return BoxBound(float(out["K_lower"]), float(out["K_upper"]), float(out["m_worst"]),
                        float(out["b_worst"]), int(out["evals"]), bool(out["converged"]), float(out["k_worst"]))

    def verdict(self, K: float, B: float) -> BoxVerdict:
        """Is (K, B) stable for every plant of the box?  (general loop: every K' in (0, K];
        K_lower is then K when certified, else 0)"""
        if self.method == "kharitonov":
            out = self._raise(self._call_loop(_core.box_loop_check, float(K), float(B)), "verdict",
                              {"K": float(K), "B": float(B)})
            return BoxVerdict(bool(out["stable"]), bool(out["decided"]), float(K) if out["stable"] else 0.0,
                              float(out["m_worst"]), float(out["b_worst"]), float(out["k_worst"]))
        out = self._raise(self._call(_core.box_check, float(K), float(B)), "verdict",
                          {"K": float(K), "B": float(B)})
        return BoxVerdict(bool(out["stable"]), bool(out["decided"]), float(out["K_lower"]),
                          float(out["m_worst"]), float(out["b_worst"]))

    def is_stable(self, K: float, B: float) -> bool:
        """True only if certified for every plant (undecided counts as not stable)."""
        return self.verdict(K, B).stable

    def b_range(self, K: float) -> Interval:
        """A closed interval of B at which K is stable for every plant (inside the true
        open one; nonempty False when none could be certified)."""
        if self.method == "kharitonov":
            out = self._raise(self._call_loop(_core.box_loop_b_range, float(K)), "b_range", {"K": float(K)})
        else:
            out = self._raise(self._call(_core.box_b_range, float(K)), "b_range", {"K": float(K)})
        return Interval(float(out["B_lo"]), float(out["B_hi"]), bool(out["nonempty"]))

    def certificate(self, B_range: Optional[Tuple[float, float]] = None, *, steps: int = 16,
                    leaves: int = 512, precision: str = "float") -> BoxCertificate:
        """A box certificate for a drive (box_cert.h): ``steps`` equal steps over ``B_range``
        (default: the B range certified over the box at half its K_mmax), at most
        ``leaves`` interval tests in its proof (what the drive runs to verify it), built in
        the drive's ``precision`` ("float" or "double").  The search runs here; the result is
        verified before it is returned.  A B range with a step that nothing proves (B near
        or past the edge of stability) raises ZwidthError naming the step."""
        if precision not in ("float", "double"):
            raise ValueError(f"zwidth.PlantBox.certificate: precision must be 'float' or 'double', got {precision!r}")
        if B_range is None:
            B_range = self.certificate_range()
        lo, hi = (float(B_range[0]), float(B_range[1]))
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ValueError(f"zwidth.PlantBox.certificate: B_range must be finite with lo < hi, got {B_range!r}")
        gains = {"B_lo": lo, "B_hi": hi}
        out = self._raise(self._call_loop(_core.box_cert_build, lo, hi, int(steps), int(leaves),
                                          precision == "float"), "certificate", gains)
        if int(out["failed_step"]) < int(steps):
            i = int(out["failed_step"])
            width = (hi - lo) / int(steps)
            raise ZwidthError(f"zwidth.PlantBox.certificate: step {i} (B in [{lo + i * width:.6g}, "
                              f"{lo + (i + 1) * width:.6g}]) is proven at no K within {int(steps)} x "
                              f"{int(leaves) // int(steps)} leaves (point K_max there {out['K_upper'][i]:.6g}): "
                              "narrow B_range away from the edge of stability, or give fewer steps",
                              "ZW_ERR_DOMAIN", "B_range", (), gains)
        if int(out["verify_status"]) != 0 or int(out["fault"]) != 0:
            raise RuntimeError(f"zwidth.PlantBox.certificate: the certificate built does not verify "
                               f"({BOX_CERT_FAULTS[int(out['fault'])]}): please report this")
        return BoxCertificate(tuple(out["B"]), tuple(out["K"]), tuple(out["K_upper"]), tuple(out["nodes"]),
                              precision, int(out["leaves"]), int(out["tests"]), float(out["build_seconds"]),
                              float(out["verify_seconds"]))

    def certificate_range(self, K_mmax: Optional[float] = None) -> Tuple[float, float]:
        """certificate()'s default B range: the B certified over the box at half of K_mmax
        (computed when not given)."""
        K = self.extremes().K_mmax if K_mmax is None else float(K_mmax)
        iv = self.b_range(0.5 * K)
        if not iv.nonempty:
            raise ZwidthError("zwidth.PlantBox.certificate: no B is certified over the box at half its K_mmax; "
                              "give B_range", "ZW_ERR_DOMAIN", "B_range", (), {})
        return (iv.lo, iv.hi)

    def verify_certificate(self, cert: BoxCertificate) -> str:
        """Verify cert for this box and loop in its precision, as a drive does: "ok" or the
        fault (BOX_CERT_FAULTS)."""
        out = self._raise(self._call_loop(_core.box_cert_verify, cert.as_wire(), cert.precision == "float"),
                          "verify_certificate", {})
        return BOX_CERT_FAULTS[int(out["fault"])]

    def extremes(self) -> BoxExtremes:
        """The largest K one B makes stable for the whole box (certified), and that B."""
        if self.method == "kharitonov":
            # K_mmax_upper: the worst plant's own K_mmax (informational, as for the closed form)
            out = self._raise(self._call_loop(_core.box_loop_k_mmax), "extremes", {})
            own = float(self._device(float(out["m_worst"]), float(out["b_worst"]),
                                     float(out["k_worst"])).extremes().K_mmax)
            return BoxExtremes(float(out["K_mmax"]), float(out["B_at"]), float(out["K_upper_at"]), own,
                               float(out["m_worst"]), float(out["b_worst"]), bool(out["converged"]),
                               float(out["k_worst"]))
        out = self._raise(self._call(_core.box_k_mmax), "extremes", {})
        return BoxExtremes(float(out["K_mmax"]), float(out["B_at"]), float(out["K_upper_at"]),
                           float(out["K_mmax_upper"]), float(out["m_worst"]), float(out["b_worst"]),
                           bool(out["converged"]))
