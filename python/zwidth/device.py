# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Real units: a plant (m, b, T) and gains (K, B), paper Section IV.

    delta = b T / m,   alpha = K T^2 / m,   beta = B T / m

Units: m in kg, b in N s/m, T in s, K in N/m, B in N s/m.  For a rotary device read m as
the inertia J in kg m^2, K in N m/rad and B in N m s/rad (use :meth:`Device.rotary`).
The rounding of these conversions is carried into the checks' guard, so a real-unit
verdict is as safe as a normalized one.
"""
from __future__ import annotations

import dataclasses
import math
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from ._kernels import Errors, ZwidthError, _as_result, as_numbers, call, region_code
from .loop import Loop, VelocityFilter, device_loop
from .results import (DeviceBoundary, DeviceExtremes, DeviceLoopExtremes, Influence, Interval, LoopInfluence,
                      LoopVerdict, Normalized, Verdict)

_PLANT = ("m", "b", "T")
#: How errors name the plant-side parts (the kernels' k_p, tau, m_h, b_h, k_h).
_PART_NAMES = ("stiffness", "actuator_tau", "hand m_h", "hand b_h", "hand k_h")


def _plant_parts(actuator_tau: ArrayLike, hand: Any, stiffness: ArrayLike,
                 errors: Errors) -> Tuple[NDArray[np.float64], ...]:
    """(k_p, tau, m_h, b_h, k_h) as arrays, each finite and >= 0 (ZwidthError naming the
    keyword otherwise, with errors="raise"; "mask" leaves it to the C core's per-element
    status)."""
    if hand is None:
        hand = (0.0, 0.0, 0.0)
    if not (isinstance(hand, (tuple, list)) and len(hand) == 3):
        raise ZwidthError(f"zwidth.Device: hand must be (m_h, b_h, k_h) in kg, N s/m, N/m, got {hand!r} "
                          f"[ZW_ERR_ARG]", "ZW_ERR_ARG", "hand", (), {})
    values = (("stiffness", stiffness, "ZW_ERR_ARG", "the device's stiffness k_p [N/m]"),
              ("actuator_tau", actuator_tau, "ZW_ERR_ARG", "the actuator lag tau [s]"),
              ("hand", hand[0], "ZW_ERR_ARG", "the hand's mass m_h [kg]"),
              ("hand", hand[1], "ZW_ERR_DAMPING", "the hand's damping b_h [N s/m]"),
              ("hand", hand[2], "ZW_ERR_ARG", "the hand's stiffness k_h [N/m]"))
    out = []
    for name, value, status, what in values:
        a = as_numbers("Device", name, value)
        if errors == "raise":
            bad = ~(np.isfinite(a) & (a >= 0.0))
            if np.any(bad):
                v = float(np.asarray(a).flat[int(np.flatnonzero(bad)[0])])
                raise ZwidthError(f"zwidth.Device: {name}: {what} must be finite and >= 0, got {v!r} [{status}]",
                                  status, name, (), {name: v})
        out.append(a)
    return tuple(out)


class Device:
    """A plant: mass m [kg] (or inertia J [kg m^2]), damping b [N s/m], period T [s].

    m, b and T may be scalars or arrays; they broadcast with each other and with the
    gains given to the methods, so ``Device(np.geomspace(1e-3, 1, 50), 30, 0.01)``
    sweeps the mass.  Invalid parameters raise :class:`zwidth.ZwidthError` here, naming
    the parameter; with ``errors="mask"`` the device is kept and every result is NaN
    (or False) at the invalid elements.

    >>> dev = Device(0.1, 30.0, 0.01)
    >>> bool(dev.is_stable(K=2000.0, B=-5.0))
    True

    Plant-side parts (issue 16; the general loop decides them, exactly and guarded):
    ``actuator_tau`` [s], the current loop's lag 1 / (tau s + 1) on the force;
    ``hand=(m_h, b_h, k_h)``, a coupled operator of mass [kg], damping [N s/m] and stiffness
    [N/m] (coupled stability: the region of the device held by that hand);
    ``stiffness`` [N/m], the device's own spring k_p.  With any of them the gains are
    normalized by M = m + m_h, and with stiffness the stable K may reach below 0 (K_max
    is still the end of the stable interval (0, K_max)).
    """

    def __init__(self, m: ArrayLike, b: ArrayLike, T: ArrayLike, *, errors: Errors = "raise",
                 rotary: bool = False, delay: int = 0, velocity_filter: VelocityFilter = None,
                 differentiator: str = "backward", actuator_tau: ArrayLike = 0.0,
                 hand: Optional[Tuple[ArrayLike, ArrayLike, ArrayLike]] = None,
                 stiffness: ArrayLike = 0.0) -> None:
        self._names = ("J", "b", "T") if rotary else _PLANT  # how errors name the parameters
        self._m: NDArray[np.float64] = as_numbers("Device", self._names[0], m)
        self._b: NDArray[np.float64] = as_numbers("Device", "b", b)
        self._T: NDArray[np.float64] = as_numbers("Device", "T", T)
        self.errors: Errors = errors
        #: The plant-side parts (k_p, tau, m_h, b_h, k_h), each an array (0: absent).
        self._parts: Tuple[NDArray[np.float64], ...] = _plant_parts(actuator_tau, hand, stiffness, errors)
        self.is_rotary = rotary  #: J, N m/rad, N m s/rad instead of m, N/m, N s/m
        #: The loop the drive runs (:class:`zwidth.loop.Loop`): delay, velocity filter,
        #: differentiator.  The default is the paper's loop.
        self.loop: Loop = device_loop("Device", delay, velocity_filter, differentiator)
        out, _ = call("Device", _core.device_normalize, self._names, self._coupled(), errors, K=0.0, B=0.0)
        self.delta: Any = out["delta"]  #: normalized damping (b + b_h) T / (m + m_h)
        #: The low-pass pole a = exp(-2 pi f_c T) per element (None without a low-pass).
        self.filter_pole: Any = None
        if self.loop.filter == "lowpass" and self.loop.cutoff is not None:
            pole, _ = call("Device", _core.loop_lowpass_pole, ("cutoff", "T"), (self.loop.cutoff, self._T), errors)
            self.filter_pole = pole["pole"]
        elif self.loop.filter == "lowpass":
            a = np.asarray(self.loop.pole, dtype=np.float64)
            if errors == "raise" and not np.all((a >= 0.0) & (a < 1.0)):
                bad = float(a.flat[int(np.flatnonzero(~((a >= 0.0) & (a < 1.0)))[0])])
                raise ZwidthError(f"zwidth.Device: the velocity filter's pole must be in [0, 1), got {bad!r} "
                                  f"[ZW_ERR_FILTER]", "ZW_ERR_FILTER", "velocity_filter", (), {"pole": bad})
            self.filter_pole = _as_result(a)
        if self.filter_pole is not None:  # the loop names its pole too (JSON, repr), not only the cut-off
            self.loop = dataclasses.replace(self.loop, pole=self.filter_pole)

    @classmethod
    def rotary(cls, J: ArrayLike, b: ArrayLike, T: ArrayLike, *, errors: Errors = "raise", delay: int = 0,
               velocity_filter: VelocityFilter = None, differentiator: str = "backward",
               actuator_tau: ArrayLike = 0.0, hand: Optional[Tuple[ArrayLike, ArrayLike, ArrayLike]] = None,
               stiffness: ArrayLike = 0.0) -> "Device":
        """A rotary plant: inertia J [kg m^2], damping b [N m s/rad], period T [s];
        gains then are K [N m/rad] and B [N m s/rad] (a hand's (J_h [kg m^2], b_h
        [N m s/rad], k_h [N m/rad]), stiffness [N m/rad])."""
        return cls(J, b, T, errors=errors, rotary=True, delay=delay, velocity_filter=velocity_filter,
                   differentiator=differentiator, actuator_tau=actuator_tau, hand=hand, stiffness=stiffness)

    def without_plant_parts(self) -> "Device":
        """The same plant and loop (delay, filter, differentiator) without its plant-side
        parts: what the lag, the hand and the spring change is this Device against that one."""
        return Device(self._m, self._b, self._T, errors=self.errors, rotary=self.is_rotary, delay=self.loop.delay,
                      velocity_filter=_filter_of(self.loop), differentiator=self.loop.differentiator)

    def with_delay(self, delay: int) -> "Device":
        """The same plant, plant-side parts, velocity filter and differentiator with another
        delay (the CLI judges an undelayed loop's gains with 1 sample too: most firmware
        applies the force at the next tick)."""
        k_p, tau, m_h, b_h, k_h = self._parts
        return Device(self._m, self._b, self._T, errors=self.errors, rotary=self.is_rotary, delay=delay,
                      velocity_filter=_filter_of(self.loop), differentiator=self.loop.differentiator,
                      actuator_tau=tau, hand=(m_h, b_h, k_h), stiffness=k_p)

    def ideal(self) -> "Device":
        """The same plant with the paper's loop (no delay, no filter, backward difference)
        and without its plant-side parts (no lag, no hand, no spring)."""
        return Device(self._m, self._b, self._T, errors=self.errors, rotary=self.is_rotary)

    @property
    def has_plant_parts(self) -> bool:
        """An actuator lag, a hand or a stiffness is present (any element non-zero)."""
        return any(bool(np.any(p != 0.0)) for p in self._parts)

    def normalized_parts(self) -> Tuple[Any, Any]:
        """(kappa, lambda) = ((k_p + k_h) T^2 / M, tau / T), M = m + m_h: the plant-side parts
        as the normalized functions take them (``zwidth.check(..., kappa=, lambda_=)``; with
        delta and the gains of :meth:`normalize`).  Rounded once each (the Device's own
        checks use the C core's conversion, which carries that rounding in its guard)."""
        k_p, tau, m_h, _, k_h = self._parts
        return (_as_result(np.asarray((k_p + k_h) * self._T ** 2 / (self._m + m_h))),
                _as_result(np.asarray(tau / self._T)))

    @property
    def actuator_tau(self) -> Any:
        """The actuator (current-loop) lag tau [s] (0: none)."""
        return _as_result(self._parts[1])

    @property
    def hand(self) -> Tuple[Any, Any, Any]:
        """The coupled hand (m_h [kg], b_h [N s/m], k_h [N/m]) (zeros: uncoupled)."""
        return _as_result(self._parts[2]), _as_result(self._parts[3]), _as_result(self._parts[4])

    @property
    def stiffness(self) -> Any:
        """The device's own stiffness k_p [N/m] (0: none)."""
        return _as_result(self._parts[0])

    @property
    def _general(self) -> bool:
        """Decided by the general loop: a loop other than the paper's, or plant-side parts."""
        return (not self.loop.ideal) or self.has_plant_parts

    def _coupled(self) -> Tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """(M, Bp, T) = (m + m_h, b + b_h, T): what the gains are normalized by (the plant's
        own arrays, untouched, without plant-side parts)."""
        if not self.has_plant_parts:
            return self._plant()
        return self._m + self._parts[2], self._b + self._parts[3], self._T

    @property
    def m(self) -> Any:
        """Mass [kg] or inertia J [kg m^2] (numpy scalar, or array when given one)."""
        return _as_result(self._m)

    @property
    def b(self) -> Any:
        """Physical damping [N s/m] or [N m s/rad]."""
        return _as_result(self._b)

    @property
    def T(self) -> Any:
        """Sampling period [s]."""
        return _as_result(self._T)

    @property
    def mass_symbol(self) -> str:
        """"J" for a rotary plant, else "m"."""
        return "J" if self.is_rotary else "m"

    @property
    def units(self) -> Dict[str, str]:
        """Units of m (or J), b, T, K and B for this kind of plant."""
        if self.is_rotary:
            return {"m": "kg m^2", "b": "N m s/rad", "T": "s", "K": "N m/rad", "B": "N m s/rad"}
        return {"m": "kg", "b": "N s/m", "T": "s", "K": "N/m", "B": "N s/m"}

    def __repr__(self) -> str:
        def show(a: NDArray[np.float64]) -> str:
            return f"{float(a):.6g}" if a.ndim == 0 else f"array(shape={a.shape})"
        loop = f", loop={self.loop.statement()!r}"  # always named: a verdict is only as good as its loop
        parts = ""
        if self.has_plant_parts:
            k_p, tau, m_h, b_h, k_h = self._parts
            parts = (f", stiffness={show(k_p)}, actuator_tau={show(tau)}, "
                     f"hand=({show(m_h)}, {show(b_h)}, {show(k_h)})")
        return (f"Device({self.mass_symbol}={show(self._m)}, b={show(self._b)}, T={show(self._T)}, "
                f"delta={show(np.asarray(self.delta))}{loop}{parts})")

    def _plant(self) -> Tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        return self._m, self._b, self._T

    def _errors(self, errors: Optional[Errors]) -> Errors:
        """A method's errors= (None: the Device's own)."""
        return self.errors if errors is None else errors

    def _call(self, function: str, kernel: Any, names: Tuple[str, ...], gains: Tuple[ArrayLike, ...],
              errors: Optional[Errors] = None, **options: Any) -> Tuple[Any, Any]:
        return call(f"Device.{function}", kernel, self._names + names, self._plant() + gains,
                    self._errors(errors), **options)

    def _loop_call(self, function: str, kernel: Any, names: Tuple[str, ...], gains: Tuple[ArrayLike, ...],
                   errors: Optional[Errors] = None, **options: Any) -> Tuple[Any, Any]:
        loop = self.loop
        pole_given = loop.cutoff is None and loop.pole is not None
        name, value = ("filter_pole", loop.pole) if pole_given else ("cutoff", 0.0 if loop.cutoff is None else loop.cutoff)
        return call(f"Device.{function}", kernel, self._names + (name,) + _PART_NAMES + names,
                    self._plant() + (value,) + self._parts + gains, self._errors(errors), pole_given=pole_given,
                    **loop.kernel_options(), **options)

    def _ideal_only(self, function: str, what: str) -> None:
        """The paper's closed forms (Section IV) hold for its loop only: refuse rather than
        give the ideal loop's numbers for another."""
        if self._general:
            raise LoopNotSupported(
                f"zwidth.Device.{function}: {what} of a loop with {self.loop.describe()}"
                f"{' and plant-side parts' if self.has_plant_parts else ''} has no closed "
                f"form (the paper's Section IV is about its ideal loop); Device.sensitivity() gives how "
                f"m, b, T and the plant-side parts move K_mmax and B_mmax (numerically, from the certified "
                f"limits), Device.loop_influence() what the loop costs and which filter cut-off keeps most, "
                f"and Device(...).ideal().{function}() the paper's loop", "ZW_ERR_ARG", None, (), {})

    def normalize(self, K: ArrayLike, B: ArrayLike, *, errors: Optional[Errors] = None) -> Normalized:
        """(delta, alpha, beta) = (b T/m, K T^2/m, B T/m) for gains K [N/m], B [N s/m]
        (with a hand: m + m_h and b + b_h in place of m and b).  ``errors`` ("raise" or
        "mask"; every method takes it) overrides the Device's own for this call."""
        out, _ = call("Device.normalize", _core.device_normalize, self._names + ("K", "B"),
                      self._coupled() + (K, B), self._errors(errors))
        return Normalized.from_outputs(out)

    def is_stable(self, K: ArrayLike, B: ArrayLike, *, region: str = "exact", errors: Optional[Errors] = None) -> Any:
        """Is the gain pair K [N/m], B [N s/m] stable? (bool; guarded: never True for an
        unstable pair).  ``region`` as in :func:`zwidth.check`."""
        if self._general:
            self._exact_only("is_stable", region)
            out, _ = self._loop_call("is_stable", _core.device_loop_check, ("K", "B"), (K, B), errors, full=False)
            return out["stable"]
        out, _ = self._call("is_stable", _core.device_check, ("K", "B"), (K, B), errors,
                            region=region_code("Device.is_stable", region), full=False)
        return out["stable"]

    def verdict(self, K: ArrayLike, B: ArrayLike, *, region: str = "exact",
                errors: Optional[Errors] = None) -> Union[Verdict, LoopVerdict]:
        """:meth:`is_stable` with the reasons: a :class:`zwidth.Verdict` (marginal, deciding,
        violated, status) for the paper's loop, a :class:`zwidth.LoopVerdict` (marginal, the
        deciding boundary 'z=1' / 'z=-1' / 'complex pair at X Hz', status) for any other."""
        if self._general:
            self._exact_only("verdict", region)
            out, status = self._loop_call("verdict", _core.device_loop_check, ("K", "B"), (K, B), errors, full=True)
            frequency = out["theta"] / (2.0 * np.pi * self._T)
            return LoopVerdict.from_outputs(out, frequency=_as_result(np.asarray(frequency)),
                                            status=_as_result(status), frequency_unit="Hz", loop=self.loop)
        out, status = self._call("verdict", _core.device_check, ("K", "B"), (K, B), errors,
                                 region=region_code("Device.verdict", region), full=True)
        return Verdict.from_outputs(out, status=_as_result(status), loop=self.loop)

    def spectral_radius(self, K: ArrayLike, B: ArrayLike, *, errors: Optional[Errors] = None) -> Any:
        """Largest closed-loop pole modulus at K, B (stable iff < 1; informational)."""
        if self._general:
            out, _ = self._loop_call("spectral_radius", _core.device_loop_spectral_radius, ("K", "B"), (K, B),
                                     errors)
            return out["rho"]
        out, _ = self._call("spectral_radius", _core.device_spectral_radius, ("K", "B"), (K, B), errors)
        return out["rho"]

    def margin(self, K: ArrayLike, B: ArrayLike, *, errors: Optional[Errors] = None) -> Any:
        """Stability margin 1 - rho: how far the slowest closed-loop pole lies inside the
        unit circle (> 0 stable, <= 0 not; a pole at radius rho decays as rho^n per sample).
        For a certified yes/no use :meth:`is_stable` or :meth:`radius_within`."""
        return 1.0 - self.spectral_radius(K, B, errors=errors)

    def radius_within(self, K: ArrayLike, B: ArrayLike, radius: ArrayLike, *,
                      errors: Optional[Errors] = None) -> Any:
        """Do all closed-loop poles lie inside |z| < radius? (bool, guarded, no roots)."""
        if self._general:
            out, _ = self._loop_call("radius_within", _core.device_loop_radius_within, ("K", "B", "radius"),
                                     (K, B, radius), errors)
            return out["within"]
        out, _ = self._call("radius_within", _core.device_radius_within, ("K", "B", "radius"),
                            (K, B, radius), errors)
        return out["within"]

    def k_max(self, B: ArrayLike, *, errors: Optional[Errors] = None) -> Any:
        """sup K [N/m] stable at damping B [N s/m] (0 where no K is).  For a loop other
        than the paper's: the end of the stable interval (0, K_max) of that loop, certified
        (zw_loop_alpha_max, pulled inward for the unit conversions)."""
        if self._general:
            out, _ = self._loop_call("k_max", _core.device_loop_k_max, ("B",), (B,), errors)
            return out["K_max"]
        out, _ = self._call("k_max", _core.device_k_max, ("B",), (B,), errors)
        return out["K_max"]

    def boundary(self, *, points: int = 1001) -> DeviceBoundary:
        """The region's outline as arrays (one plant): B from -b to B_mmax (``points``
        evenly spaced, plus the B of K_mmax, B = 0 and, for the paper's loop, the corner)
        and K = :meth:`k_max` there (0 at both ends).  ``B, K = dev.boundary()``."""
        if np.ndim(self.delta) != 0:
            raise ValueError("Device.boundary is about one plant; build a Device with scalar m, b, T")
        lim = self.extremes()
        special = [lim.B_at_K_mmax, 0.0]
        if not self._general:
            from .normalized import corner
            special.append(float(corner(self.delta).beta) * float(self._m) / float(self._T))
        lo, hi = float(lim.B_mmin), float(lim.B_mmax)
        grid = np.linspace(lo, hi, max(2, int(points)))
        Bs = np.unique(np.concatenate([grid, [float(b) for b in special if lo < float(b) < hi]]))
        return DeviceBoundary(B=Bs, K=np.asarray(self.k_max(Bs), dtype=float))

    def b_range(self, K: ArrayLike, *, errors: Optional[Errors] = None) -> Interval:
        """The open interval (lo, hi) of B [N s/m] stable at stiffness K [N/m].  For a loop
        other than the paper's: the widest such interval, certified (inside the true one)."""
        if self._general:
            out, _ = self._loop_call("b_range", _core.device_loop_b_range, ("K",), (K,), errors)
            return Interval.from_outputs(out)
        out, _ = self._call("b_range", _core.device_b_range, ("K",), (K,), errors)
        return Interval.from_outputs(out)

    def extremes(self) -> Union[DeviceExtremes, DeviceLoopExtremes]:
        """K_mmax, the B at it, K with B = 0, B_mmax and the lower extremes, real units.
        For a loop other than the paper's a :class:`zwidth.DeviceLoopExtremes` of that loop
        (certified, never beyond the true values)."""
        if self._general:
            out, _ = self._loop_call("extremes", _core.device_loop_extremes, (), ())
            return DeviceLoopExtremes.from_outputs(out)
        out, _ = self._call("extremes", _core.device_extremes, (), ())
        return DeviceExtremes.from_outputs(out)

    def influence(self) -> Influence:
        """Critical masses, periods and dampings, trends, and advice (paper Section IV)."""
        self._ideal_only("influence", "the influence analysis")
        out, _ = self._call("influence", _core.device_influence, (), ())
        return Influence.from_outputs(out, m=self.m, mass_symbol=self.mass_symbol)

    def loop_influence(self, *, cutoffs: Optional[ArrayLike] = None, delays: Sequence[int] = (0, 1, 2, 3)
                       ) -> LoopInfluence:
        """What this Device's loop costs against the paper's loop, and how delay and the
        low-pass cut-off move K_mmax (one plant: scalar m, b, T).

        K_mmax of this loop with each of ``delays``; with a low-pass, K_mmax against the
        cut-off on ``cutoffs`` [Hz] (default: 40 cut-offs on a log grid from Nyquist/200 to
        0.95 Nyquist, plus this one) and the cut-off that keeps most.  Every K_mmax is the
        certified one of zw_loop_extremes_compute; NaN where no gains are stable.  Every
        loop runs on this plant with its plant-side parts (the "ideal loop" is the paper's
        loop on it)."""
        if np.ndim(self.delta) != 0:
            raise ValueError("Device.loop_influence is about one plant; build a Device with scalar m, b, T")
        lp = self.loop

        k_p, tau, m_h, b_h, k_h = self._parts

        def make(delay: int = 0, velocity_filter: VelocityFilter = None, differentiator: str = "backward") -> Device:
            # every loop on this plant, its plant-side parts included
            return Device(self._m, self._b, self._T, rotary=self.is_rotary, errors="mask", delay=delay,
                          velocity_filter=velocity_filter, differentiator=differentiator, actuator_tau=tau,
                          hand=(m_h, b_h, k_h), stiffness=k_p)

        ideal = make().extremes()
        vf: Any = None
        if lp.filter == "lowpass":
            vf = ("lowpass", lp.cutoff) if lp.cutoff is not None else ("pole", lp.pole)
        elif lp.filter == "average":
            vf = ("average", lp.average)
        mine = make(lp.delay, vf, lp.differentiator).extremes()
        by_delay = [float(make(d, vf, lp.differentiator).extremes().K_mmax) for d in delays]
        grid: Any = None
        by_cutoff: Any = None
        best, at_best = math.nan, math.nan
        if lp.filter == "lowpass" or cutoffs is not None:
            nyquist = 0.5 / float(self._T)
            grid = (np.geomspace(nyquist / 200, 0.95 * nyquist, 40) if cutoffs is None
                    else np.asarray(cutoffs, dtype=np.float64).ravel())
            if lp.cutoff is not None and cutoffs is None:
                grid = np.unique(np.append(grid, float(lp.cutoff)))
            by_cutoff = np.asarray(make(lp.delay, ("lowpass", grid), lp.differentiator).extremes().K_mmax)
            if np.isfinite(by_cutoff).any():
                i = int(np.nanargmax(by_cutoff))
                best, at_best = float(grid[i]), float(by_cutoff[i])
        return LoopInfluence(
            K_mmax_ideal=ideal.K_mmax, B_mmax_ideal=ideal.B_mmax, K_mmax=mine.K_mmax, B_mmax=mine.B_mmax,
            K_mmax_kept=float(mine.K_mmax) / float(ideal.K_mmax), delays=np.asarray(delays),
            K_mmax_by_delay=np.asarray(by_delay), cutoffs=grid, K_mmax_by_cutoff=by_cutoff,
            best_cutoff=best, K_mmax_at_best_cutoff=at_best, loop_text=f"this loop ({lp.describe()})")

    def sensitivity(self, *, rel_step: float = 1e-3) -> "PlantSensitivity":
        """How each plant parameter moves K_mmax and B_mmax (one plant: scalar m, b, T):
        m (or J), b, T, the actuator lag tau, the hand's m_h, b_h, k_h and the stiffness k_p.

        Numerical, for any loop and plant (the paper's closed forms, :meth:`influence`, are
        about its ideal loop only): finite differences of the certified limits of
        :meth:`extremes` (never above the true ones, within ~1e-12 of them), each a central
        difference with step h = rel_step * p, or, for a parameter at 0 (an absent part:
        it cannot go below 0), the one-sided second-order difference (-3 f(0) + 4 f(h) -
        f(2h)) / (2 h) with h = rel_step times the parameter's natural scale (T for tau, m
        for m_h, m/T for b and b_h, m/T^2 for k_h and k_p).  Where K_mmax has a kink (its top
        switching between boundaries) the difference is the mean of the two one-sided slopes."""
        if np.ndim(self.delta) != 0:
            raise ValueError("Device.sensitivity is about one plant; build a Device with scalar m, b, T")
        if not (0.0 < rel_step < 0.1):
            raise ValueError(f"zwidth.Device.sensitivity: rel_step must be in (0, 0.1), got {rel_step!r}")
        m, b, T = float(self._m), float(self._b), float(self._T)
        k_p, tau, m_h, b_h, k_h = (float(p) for p in self._parts)
        base = {"m": m, "b": b, "T": T, "actuator_tau": tau, "m_h": m_h, "b_h": b_h, "k_h": k_h, "stiffness": k_p}
        scale = {"m": m, "b": m / T, "T": T, "actuator_tau": T, "m_h": m, "b_h": m / T, "k_h": m / T ** 2,
                 "stiffness": m / T ** 2}
        names = tuple(base)
        rows: List[Dict[str, float]] = []   # the parameter sets, base first
        plan: List[Tuple[str, float, bool, List[int]]] = []  # (name, step, one_sided, indices of the rows)
        rows.append(dict(base))
        for name in names:
            value = base[name]
            one_sided = value == 0.0
            h = rel_step * (scale[name] if one_sided else value)
            shifts = (h, 2.0 * h) if one_sided else (-h, h)
            idx = []
            for shift in shifts:
                row = dict(base)
                row[name] = value + shift
                idx.append(len(rows))
                rows.append(row)
            plan.append((name, h, one_sided, idx))
        col = {k: np.array([r[k] for r in rows]) for k in names}
        trial = Device(col["m"], col["b"], col["T"], rotary=self.is_rotary, errors="mask", delay=self.loop.delay,
                       velocity_filter=_filter_of(self.loop), differentiator=self.loop.differentiator,
                       actuator_tau=col["actuator_tau"], hand=(col["m_h"], col["b_h"], col["k_h"]),
                       stiffness=col["stiffness"])
        if not trial.has_plant_parts:  # keep the paper's plant on its own kernels
            trial = Device(col["m"], col["b"], col["T"], rotary=self.is_rotary, errors="mask",
                           delay=self.loop.delay, velocity_filter=_filter_of(self.loop),
                           differentiator=self.loop.differentiator)
        lim = trial.extremes()
        K = np.asarray(lim.K_mmax, dtype=float)
        Bm = np.asarray(lim.B_mmax, dtype=float)

        def slope(f: NDArray[np.float64], h: float, one_sided: bool, idx: List[int]) -> float:
            if one_sided:
                return float((-3.0 * f[0] + 4.0 * f[idx[0]] - f[idx[1]]) / (2.0 * h))
            return float((f[idx[1]] - f[idx[0]]) / (2.0 * h))

        dK = np.array([slope(K, h, o, i) for _, h, o, i in plan])
        dB = np.array([slope(Bm, h, o, i) for _, h, o, i in plan])
        values = np.array([base[n] for n in names])
        with np.errstate(divide="ignore", invalid="ignore"):
            eK = np.where(values > 0.0, values * dK / K[0], np.nan)
            eB = np.where(values > 0.0, values * dB / Bm[0], np.nan)
        u = self.units
        units = {"m": u["m"], "b": u["b"], "T": "s", "actuator_tau": "s", "m_h": u["m"], "b_h": u["b"],
                 "k_h": u["K"], "stiffness": u["K"]}
        shown = tuple(self.mass_symbol if n == "m" else n for n in names)
        return PlantSensitivity(
            names=shown, values=values, units=tuple(units[n] for n in names), K_mmax=float(K[0]),
            B_mmax=float(Bm[0]), dK_mmax=dK, dB_mmax=dB, elasticity_K=eK, elasticity_B=eB,
            steps=np.array([h for _, h, _, _ in plan]), one_sided=np.array([o for _, _, o, _ in plan]),
            K_unit=u["K"], B_unit=u["B"], loop_text=self.loop.describe())

    def _exact_only(self, function: str, region: str) -> None:
        if region != "exact":
            raise ValueError(f"zwidth.Device.{function}: region {region!r} is one of the paper's regions of "
                             f"its ideal loop; a loop with {self.loop.describe()} has only its exact region")


def _filter_of(loop: Loop) -> VelocityFilter:
    """A Loop's velocity filter as a Device takes it."""
    if loop.filter == "lowpass":
        return ("lowpass", loop.cutoff) if loop.cutoff is not None else ("pole", loop.pole)
    if loop.filter == "average":
        return ("average", loop.average)
    return None


#: What each parameter of :class:`PlantSensitivity` is, in words.
SENSITIVITY_WORDS: Dict[str, str] = {
    "m": "mass m", "J": "inertia J", "b": "damping b", "T": "period T", "actuator_tau": "actuator lag tau",
    "m_h": "hand mass m_h", "b_h": "hand damping b_h", "k_h": "hand stiffness k_h",
    "stiffness": "device stiffness k_p"}


@dataclasses.dataclass(frozen=True)
class PlantSensitivity:
    """How each plant parameter moves K_mmax and B_mmax (:meth:`Device.sensitivity`):
    finite differences of the certified limits (numerical, not the paper's closed forms).

    names: 'm' (or 'J'), 'b', 'T', 'actuator_tau', 'm_h', 'b_h', 'k_h', 'stiffness';
    values and units of each; dK_mmax, dB_mmax: d limit / d parameter (limit unit per
    parameter unit); elasticity_K, elasticity_B: (p / limit) d limit / dp, the % change of
    the limit per % of the parameter (NaN for a parameter at 0); steps h and one_sided (a
    parameter at 0 is differenced forward)."""

    names: Tuple[str, ...]
    values: NDArray[np.float64]
    units: Tuple[str, ...]
    K_mmax: float
    B_mmax: float
    dK_mmax: NDArray[np.float64]
    dB_mmax: NDArray[np.float64]
    elasticity_K: NDArray[np.float64]
    elasticity_B: NDArray[np.float64]
    steps: NDArray[np.float64]
    one_sided: NDArray[np.bool_]
    K_unit: str
    B_unit: str
    loop_text: str
    method: str = ("numerical: finite differences of the certified limits (Device.extremes); central with "
                   "h = 1e-3 p, forward (second order) for a parameter at 0")

    def __getitem__(self, name: str) -> Dict[str, Any]:
        """One parameter's row: value, unit, dK_mmax, dB_mmax, elasticities, trends."""
        i = self.names.index(name)
        return {"name": name, "value": float(self.values[i]), "unit": self.units[i],
                "dK_mmax": float(self.dK_mmax[i]), "dB_mmax": float(self.dB_mmax[i]),
                "elasticity_K": float(self.elasticity_K[i]), "elasticity_B": float(self.elasticity_B[i]),
                "K_trend": _trend(float(self.dK_mmax[i]), float(self.values[i]), float(self.steps[i]), self.K_mmax),
                "B_trend": _trend(float(self.dB_mmax[i]), float(self.values[i]), float(self.steps[i]), self.B_mmax),
                "step": float(self.steps[i]), "one_sided": bool(self.one_sided[i])}

    def rows(self) -> List[Dict[str, Any]]:
        return [self[n] for n in self.names]

    def as_dict(self) -> Dict[str, Any]:
        return {"K_mmax": self.K_mmax, "B_mmax": self.B_mmax, "K_unit": self.K_unit, "B_unit": self.B_unit,
                "loop": self.loop_text, "method": self.method, "parameters": self.rows()}

    def lines(self) -> List[str]:
        """A table in words, one parameter a line."""
        out = []
        for r in self.rows():
            what = SENSITIVITY_WORDS.get(r["name"], r["name"])
            at = f"{r['value']:.4g} {r['unit']}"
            if r["one_sided"]:
                kd = f"dK_mmax/d{r['name']} = {r['dK_mmax']:+.4g} {self.K_unit} per {r['unit']} (from 0)"
                bd = f"dB_mmax/d{r['name']} = {r['dB_mmax']:+.4g}"
            else:
                kd = f"K_mmax {r['elasticity_K']:+.3g} %/%"
                bd = f"B_mmax {r['elasticity_B']:+.3g} %/%"
            out.append(f"{what} = {at}: K_mmax {r['K_trend']}, B_mmax {r['B_trend']} ({kd}; {bd})")
        return out


def _trend(slope: float, value: float, step: float, limit: float) -> str:
    """'rises', 'falls' or 'flat' (the limit moves by < 1e-9 of itself over a step)."""
    if not math.isfinite(slope):
        return "unknown"
    if abs(slope) * step <= 1e-9 * abs(limit):
        return "flat"
    return "rises" if slope > 0.0 else "falls"


class LoopNotSupported(ZwidthError, NotImplementedError):
    """A result of the paper's loop asked of another loop, which this build cannot give
    yet (status 'ZW_ERR_ARG', parameter None)."""
