"""Real units: a plant (m, b, T) and gains (K, B), paper Section IV.

    delta = b T / m,   alpha = K T^2 / m,   beta = B T / m

Units: m in kg, b in N s/m, T in s, K in N/m, B in N s/m.  For a rotary device read m as
the inertia J in kg m^2, K in N m/rad and B in N m s/rad (use :meth:`Device.rotary`).
The rounding of these conversions is carried into the checks' guard, so a real-unit
verdict is as safe as a normalized one.
"""
from __future__ import annotations

from typing import Any, Dict, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from ._kernels import Errors, _as_result, call, region_code
from .results import DeviceExtremes, Influence, Interval, Normalized, Verdict

_PLANT = ("m", "b", "T")


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
    """

    def __init__(self, m: ArrayLike, b: ArrayLike, T: ArrayLike, *, errors: Errors = "raise",
                 rotary: bool = False) -> None:
        self._m: NDArray[np.float64] = np.asarray(m, dtype=np.float64)
        self._b: NDArray[np.float64] = np.asarray(b, dtype=np.float64)
        self._T: NDArray[np.float64] = np.asarray(T, dtype=np.float64)
        self.errors: Errors = errors
        self.is_rotary = rotary  #: J, N m/rad, N m s/rad instead of m, N/m, N s/m
        self._names = ("J", "b", "T") if rotary else _PLANT  # how errors name the parameters
        out, _ = call("Device", _core.device_normalize, self._names, self._plant(), errors, K=0.0, B=0.0)
        self.delta: Any = out["delta"]  #: normalized damping b T / m

    @classmethod
    def rotary(cls, J: ArrayLike, b: ArrayLike, T: ArrayLike, *, errors: Errors = "raise") -> "Device":
        """A rotary plant: inertia J [kg m^2], damping b [N m s/rad], period T [s];
        gains then are K [N m/rad] and B [N m s/rad]."""
        return cls(J, b, T, errors=errors, rotary=True)

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
        return (f"Device({self.mass_symbol}={show(self._m)}, b={show(self._b)}, T={show(self._T)}, "
                f"delta={show(np.asarray(self.delta))})")

    def _plant(self) -> Tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        return self._m, self._b, self._T

    def _call(self, function: str, kernel: Any, names: Tuple[str, ...], gains: Tuple[ArrayLike, ...],
              **options: Any) -> Tuple[Any, Any]:
        return call(f"Device.{function}", kernel, self._names + names, self._plant() + gains, self.errors,
                    **options)

    def normalize(self, K: ArrayLike, B: ArrayLike) -> Normalized:
        """(delta, alpha, beta) = (b T/m, K T^2/m, B T/m) for gains K [N/m], B [N s/m]."""
        out, _ = self._call("normalize", _core.device_normalize, ("K", "B"), (K, B))
        return Normalized.from_outputs(out)

    def is_stable(self, K: ArrayLike, B: ArrayLike, *, region: str = "exact") -> Any:
        """Is the gain pair K [N/m], B [N s/m] stable? (bool; guarded: never True for an
        unstable pair).  ``region`` as in :func:`zwidth.check`."""
        out, _ = self._call("is_stable", _core.device_check, ("K", "B"), (K, B),
                            region=region_code("Device.is_stable", region), full=False)
        return out["stable"]

    def verdict(self, K: ArrayLike, B: ArrayLike, *, region: str = "exact") -> Verdict:
        """:meth:`is_stable` with the reasons (marginal, deciding, violated, status)."""
        out, status = self._call("verdict", _core.device_check, ("K", "B"), (K, B),
                                 region=region_code("Device.verdict", region), full=True)
        return Verdict.from_outputs(out, status=_as_result(status))

    def spectral_radius(self, K: ArrayLike, B: ArrayLike) -> Any:
        """Largest closed-loop pole modulus at K, B (stable iff < 1)."""
        out, _ = self._call("spectral_radius", _core.device_spectral_radius, ("K", "B"), (K, B))
        return out["rho"]

    def margin(self, K: ArrayLike, B: ArrayLike) -> Any:
        """Stability margin 1 - rho: how far the slowest closed-loop pole lies inside the
        unit circle (> 0 stable, <= 0 not; a pole at radius rho decays as rho^n per sample).
        For a certified yes/no use :meth:`is_stable` or :meth:`radius_within`."""
        return 1.0 - self.spectral_radius(K, B)

    def radius_within(self, K: ArrayLike, B: ArrayLike, radius: ArrayLike) -> Any:
        """Do all closed-loop poles lie inside |z| < radius? (bool, guarded, no roots)."""
        out, _ = self._call("radius_within", _core.device_radius_within, ("K", "B", "radius"),
                            (K, B, radius))
        return out["within"]

    def k_max(self, B: ArrayLike) -> Any:
        """sup K [N/m] stable at damping B [N s/m] (0 where no K is)."""
        out, _ = self._call("k_max", _core.device_k_max, ("B",), (B,))
        return out["K_max"]

    def b_range(self, K: ArrayLike) -> Interval:
        """The open interval (lo, hi) of B [N s/m] stable at stiffness K [N/m]."""
        out, _ = self._call("b_range", _core.device_b_range, ("K",), (K,))
        return Interval.from_outputs(out)

    def extremes(self) -> DeviceExtremes:
        """K_mmax, the B at it, K with B = 0, B_mmax and the lower extremes, real units."""
        out, _ = self._call("extremes", _core.device_extremes, (), ())
        return DeviceExtremes.from_outputs(out)

    def influence(self) -> Influence:
        """Critical masses, periods and dampings, trends, and advice (paper Section IV)."""
        out, _ = self._call("influence", _core.device_influence, (), ())
        return Influence.from_outputs(out, m=self.m, mass_symbol=self.mass_symbol)
