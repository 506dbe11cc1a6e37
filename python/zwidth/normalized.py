# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The normalized space: delta = b T/m, alpha = K T^2/m, beta = B T/m (paper Sections II, III).

Every function broadcasts its array arguments like a numpy ufunc (float64 in; results of
the broadcast shape, numpy scalars for scalar inputs) and runs its loop in C.  Invalid
input raises :class:`zwidth.ZwidthError` naming the parameter, or, with
``errors="mask"``, gives NaN (float results) or False (boolean results) at those elements.
"""
from __future__ import annotations

import dataclasses
from typing import Any, Optional, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from ._kernels import Errors, ZwidthError, _as_result, as_numbers, call, region_code
from .loop import Loop, normalized_loop
from .results import Boundary, BoundaryPoint, Coefficients, Extremes, Interval, LoopExtremes, LoopVerdict, Verdict

_DAB = ("delta", "alpha", "beta")
#: The normalized plant of the loop kernels: delta, the low-pass pole, kappa, lambda.
_DPKL = ("delta", "filter_pole", "kappa", "lambda_")
_DPAB = _DPKL + ("alpha", "beta")

_LOOP_DOC = """
    The loop: ``delay`` samples between measuring x_k and applying its force (0..8),
    ``filter_pole`` a in [0, 1) of a first-order low-pass on the velocity
    (a = exp(-2 pi f_c T); 0: none; broadcasts like delta) or ``average`` n (1..16) for a
    moving average instead, ``differentiator`` 'backward' (the paper's) or 'tustin'.  The
    defaults are the paper's loop, decided by the closed form (10); any other loop by the
    guarded test of its characteristic polynomial (zw_loop_check), as safe: never stable
    for an unstable point.

    The plant-side parts (plant.h; docs/plant-loop.md), normalized by the plant's mass
    M = m + m_h: ``kappa`` = (k_p + k_h) T^2 / M, a stiffness (a return spring, a hand's),
    ``lambda_`` = tau / T, an actuator (current-loop) lag 1 / (tau s + 1) on the force;
    delta is then (b + b_h) T / M and the gains alpha = K T^2 / M, beta = B T / M (the
    values :meth:`zwidth.Device.normalize` gives for a Device with ``stiffness``, ``hand``,
    ``actuator_tau``).  Both 0 (the default) is the paper's plant; either > 0 is decided by
    the general loop, as above."""


@dataclasses.dataclass(frozen=True)
class _General:
    """The loop of the keywords and the normalized plant-side parts (kappa, lambda_)."""

    loop: Loop
    kappa: NDArray[np.float64]
    lambda_: NDArray[np.float64]

    @property
    def parts(self) -> bool:
        """A stiffness or an actuator lag present (some element non-zero, or NaN)."""
        return bool(np.any(self.kappa != 0.0)) or bool(np.any(self.lambda_ != 0.0))

    @property
    def ideal(self) -> bool:
        """The paper's loop on the paper's plant: its closed forms apply."""
        return self.loop.ideal and not self.parts

    def plant(self, delta: ArrayLike) -> Tuple[ArrayLike, ...]:
        """The loop kernels' plant inputs, in the order of _DPKL."""
        return (delta, _pole(self.loop), self.kappa, self.lambda_)

    def describe(self) -> str:
        parts = []
        if bool(np.any(self.kappa != 0.0)):
            parts.append(f"kappa = {_values(self.kappa)}")
        if bool(np.any(self.lambda_ != 0.0)):
            parts.append(f"lambda = {_values(self.lambda_)}")
        return self.loop.describe() + (f" on a plant with {', '.join(parts)}" if parts else "")


def _values(x: NDArray[np.float64]) -> str:
    return f"{float(x):g}" if x.ndim == 0 else f"array(shape={x.shape})"


def plant_parts(function: str, kappa: ArrayLike, lambda_: ArrayLike, errors: Errors
                ) -> Tuple[NDArray[np.float64], NDArray[np.float64]]:
    """kappa and lambda_ as arrays, each finite and >= 0 (ZwidthError naming it, with
    errors="raise"; "mask" leaves it to the C core's per-element status)."""
    out = []
    for name, value, what in (("kappa", kappa, "the normalized stiffness (k_p + k_h) T^2 / M"),
                              ("lambda_", lambda_, "the normalized actuator lag tau / T")):
        a = as_numbers(function, name, value)
        if errors == "raise":
            bad = ~(np.isfinite(a) & (a >= 0.0))
            if np.any(bad):
                v = float(np.asarray(a).flat[int(np.flatnonzero(bad)[0])])
                raise ZwidthError(f"zwidth.{function}: {name}: {what} must be finite and >= 0, got {v!r} "
                                  f"[ZW_ERR_ARG]", "ZW_ERR_ARG", name, (), {name: v})
        out.append(a)
    return out[0], out[1]


def _general(function: str, delay: Any, filter_pole: ArrayLike, average: Any, differentiator: Any,
             kappa: ArrayLike, lambda_: ArrayLike, errors: Errors, region: str = "exact") -> _General:
    g = _General(normalized_loop(function, delay, filter_pole, average, differentiator),
                 *plant_parts(function, kappa, lambda_, errors))
    if not g.ideal and region != "exact":
        raise ValueError(f"zwidth.{function}: region {region!r} is one of the paper's regions of its ideal "
                         f"loop; a loop with {g.describe()} has only its exact region")
    return g


def _pole(loop: Loop) -> ArrayLike:
    return 0.0 if loop.pole is None else loop.pole


def check(delta: ArrayLike, alpha: ArrayLike, beta: ArrayLike, *, region: str = "exact",
          delay: int = 0, filter_pole: ArrayLike = 0.0, average: Optional[int] = None,
          differentiator: str = "backward", kappa: ArrayLike = 0.0,
        lambda_: ArrayLike = 0.0, errors: Errors = "raise") -> Any:
    """Is (alpha, beta) stable for a plant with normalized damping delta? (bool)

    The exact region, paper eq (10), with a rounding-error guard: True only if the point
    is stable for every value within the bound; a stable point within a few ulps of the
    boundary may be called unstable (see :func:`verdict`, ``marginal``).  ``region``
    selects one of the paper's comparison regions instead: 'legacy' (Gil et al., eq (10)
    without the line: contains unstable points for delta > delta0), 'passivity' (eq (16)),
    'delta0' (eq (17)), 'delta_inf' (eqs (14), (15)), 'small' (eq (18)).  Only 'exact' and
    'passivity' certify stability.
    """
    g = _general("check", delay, filter_pole, average, differentiator, kappa, lambda_, errors, region)
    if not g.ideal:
        out, _ = call("check", _core.loop_check, _DPAB, g.plant(delta) + (alpha, beta), errors,
                      full=False, **g.loop.kernel_options())
        return out["stable"]
    out, _ = call("check", _core.check, _DAB, (delta, alpha, beta), errors,
                  region=region_code("check", region), full=False)
    return out["stable"]


def verdict(delta: ArrayLike, alpha: ArrayLike, beta: ArrayLike, *, region: str = "exact",
            delay: int = 0, filter_pole: ArrayLike = 0.0, average: Optional[int] = None,
            differentiator: str = "backward", kappa: ArrayLike = 0.0,
        lambda_: ArrayLike = 0.0, errors: Errors = "raise") -> Union[Verdict, LoopVerdict]:
    """Like :func:`check`, with the reasons: a :class:`Verdict` (stable, marginal,
    deciding, violated, status) for the paper's loop, a :class:`LoopVerdict` (stable,
    marginal, the deciding boundary 'z=1' / 'z=-1' / complex pair and its frequency in
    cycles per sample, status) for any other."""
    g = _general("verdict", delay, filter_pole, average, differentiator, kappa, lambda_, errors, region)
    if not g.ideal:
        out, status = call("verdict", _core.loop_check, _DPAB, g.plant(delta) + (alpha, beta), errors,
                           full=True, **g.loop.kernel_options())
        return LoopVerdict.from_outputs(out, frequency=out["theta"] / (2.0 * np.pi),
                                        status=_as_result(status), loop=g.loop)
    out, status = call("verdict", _core.check, _DAB, (delta, alpha, beta), errors,
                       region=region_code("verdict", region), full=True)
    return Verdict.from_outputs(out, status=_as_result(status), loop=g.loop)


def spectral_radius(delta: ArrayLike, alpha: ArrayLike, beta: ArrayLike, *, delay: int = 0,
                    filter_pole: ArrayLike = 0.0, average: Optional[int] = None,
                    differentiator: str = "backward", kappa: ArrayLike = 0.0,
        lambda_: ArrayLike = 0.0, errors: Errors = "raise") -> Any:
    """Largest pole modulus of the closed loop, paper eqs (7), (8) (stable iff < 1).
    Informational: verdicts never rest on it (use :func:`check`)."""
    g = _general("spectral_radius", delay, filter_pole, average, differentiator, kappa, lambda_, errors)
    if not g.ideal:
        out, _ = call("spectral_radius", _core.loop_spectral_radius, _DPAB, g.plant(delta) + (alpha, beta),
                      errors, **g.loop.kernel_options())
        return out["rho"]
    out, _ = call("spectral_radius", _core.spectral_radius, _DAB, (delta, alpha, beta), errors)
    return out["rho"]


def radius_within(delta: ArrayLike, alpha: ArrayLike, beta: ArrayLike, radius: ArrayLike, *,
                  delay: int = 0, filter_pole: ArrayLike = 0.0, average: Optional[int] = None,
                  differentiator: str = "backward", kappa: ArrayLike = 0.0,
        lambda_: ArrayLike = 0.0, errors: Errors = "raise") -> Any:
    """Do all closed-loop poles lie strictly inside |z| < radius? (bool, guarded)

    Decided by the Jury conditions on p(radius z) without root finding; True only if it
    holds for every value within the rounding bound.  radius must be finite and > 0.
    """
    g = _general("radius_within", delay, filter_pole, average, differentiator, kappa, lambda_, errors)
    if not g.ideal:
        out, _ = call("radius_within", _core.loop_radius_within, _DPAB + ("radius",),
                      g.plant(delta) + (alpha, beta, radius), errors, **g.loop.kernel_options())
        return out["within"]
    out, _ = call("radius_within", _core.radius_within, _DAB + ("radius",),
                  (delta, alpha, beta, radius), errors)
    return out["within"]


for _f in (check, verdict, spectral_radius, radius_within):
    _f.__doc__ = (_f.__doc__ or "") + _LOOP_DOC


def loop_poly(delta: ArrayLike, alpha: ArrayLike, beta: ArrayLike, *, delay: int = 0,
              filter_pole: ArrayLike = 0.0, average: Optional[int] = None,
              differentiator: str = "backward", kappa: ArrayLike = 0.0,
        lambda_: ArrayLike = 0.0, errors: Errors = "raise") -> Any:
    """The loop's characteristic polynomial p(z) = D + alpha Na + beta Nb (loop.h),
    highest power first, along a new trailing axis of length degree + 1 (the degree is
    fixed by delay, average and differentiator, and 1 more with a low-pass)."""
    g = _general("loop_poly", delay, filter_pole, average, differentiator, kappa, lambda_, errors)
    out, _ = call("loop_poly", _core.loop_poly, _DPAB, g.plant(delta) + (alpha, beta), errors,
                  **g.loop.kernel_options())
    degree = np.asarray(out["degree"])
    coefficients = np.asarray(out["coefficients"])
    top = int(degree.max()) if degree.size else 0
    return _as_result(coefficients[..., coefficients.shape[-1] - 1 - top:])


def char_poly(delta: ArrayLike, alpha: ArrayLike, beta: ArrayLike, *, errors: Errors = "raise") -> Any:
    """Characteristic polynomial coefficients [2, a1, a2, -c2 beta], highest power first,
    along a new trailing axis of length 4 (paper eq (7))."""
    out, _ = call("char_poly", _core.char_poly, _DAB, (delta, alpha, beta), errors)
    return out["coefficients"]


def coefficients(delta: ArrayLike, *, errors: Errors = "raise") -> Coefficients:
    """e, c1, c2, d12, s, g at delta (accurate to a few ulps for every delta >= 0)."""
    out, _ = call("coefficients", _core.coefficients, ("delta",), (delta,), errors)
    return Coefficients.from_outputs(out)


def coefficients_literal(delta: ArrayLike, *, errors: Errors = "raise") -> Coefficients:
    """c1, c2, d12 by the paper's literal formulas, which cancel for small delta and
    overflow for large: for comparison only; e, s and g are NaN."""
    out, _ = call("coefficients_literal", _core.coefficients_literal, ("delta",), (delta,), errors)
    nan = out["c1"] * float("nan")
    return Coefficients(e=nan, c1=out["c1"], c2=out["c2"], d12=out["d12"], s=nan, g=nan)


def extremes(delta: ArrayLike, *, delay: int = 0, filter_pole: ArrayLike = 0.0, average: Optional[int] = None,
             differentiator: str = "backward", kappa: ArrayLike = 0.0,
        lambda_: ArrayLike = 0.0, errors: Errors = "raise") -> Union[Extremes, LoopExtremes]:
    """alpha_mmax (and the beta at it), alpha with beta = 0, beta_mmax, lower extremes.

    For a loop other than the paper's (the keywords of :func:`check`) a
    :class:`LoopExtremes` of that loop, by D-decomposition (zw_loop_extremes_compute):
    certified, never beyond the true values."""
    g = _general("extremes", delay, filter_pole, average, differentiator, kappa, lambda_, errors)
    if not g.ideal:
        out, _ = call("extremes", _core.loop_extremes, _DPKL, g.plant(delta), errors, **g.loop.kernel_options())
        return LoopExtremes.from_outputs(out)
    out, _ = call("extremes", _core.extremes, ("delta",), (delta,), errors)
    return Extremes.from_outputs(out)


def hyperbola_top(delta: ArrayLike, *, errors: Errors = "raise") -> BoundaryPoint:
    """Top of the hyperbola alpha = f(beta), eqs (19), (20): the legacy region's
    alpha_mmax, and the exact one for delta <= delta1."""
    out, _ = call("hyperbola_top", _core.hyperbola_top, ("delta",), (delta,), errors)
    return BoundaryPoint.from_outputs(out)


def corner(delta: ArrayLike, *, errors: Errors = "raise") -> BoundaryPoint:
    """Corner where the line meets the hyperbola, eqs (21), (22); NaN for delta <= delta0,
    where the line lies outside the hyperbola."""
    out, _ = call("corner", _core.corner, ("delta",), (delta,), errors, domain_is_nan=True)
    return BoundaryPoint.from_outputs(out)


def alpha_max(delta: ArrayLike, beta: ArrayLike, *, delay: int = 0, filter_pole: ArrayLike = 0.0,
              average: Optional[int] = None, differentiator: str = "backward", kappa: ArrayLike = 0.0,
        lambda_: ArrayLike = 0.0, errors: Errors = "raise") -> Any:
    """sup alpha stable at this beta: min(f(beta), L(beta)), 0 outside (-delta, beta_mmax).

    For a loop other than the paper's (the keywords of :func:`check`): the end of the
    stable interval (0, alpha_max) on the line beta = const of that loop, certified (every
    alpha below it is stable, and it is never above the true one; zw_loop_alpha_max)."""
    g = _general("alpha_max", delay, filter_pole, average, differentiator, kappa, lambda_, errors)
    if not g.ideal:
        out, _ = call("alpha_max", _core.loop_alpha_max, _DPKL + ("beta",), g.plant(delta) + (beta,), errors,
                      **g.loop.kernel_options())
        return out["alpha_max"]
    out, _ = call("alpha_max", _core.alpha_max, ("delta", "beta"), (delta, beta), errors)
    return out["alpha_max"]


def boundary_betas(delta: float, beta_mmax: float, points: int, special: Any) -> Any:
    """points betas from -delta to beta_mmax, with the special ones (kinks) inside."""
    grid = np.linspace(-delta, beta_mmax, max(2, int(points)))
    inside = [float(b) for b in special if -delta < float(b) < beta_mmax]
    return np.unique(np.concatenate([grid, inside]))


def boundary(delta: float, *, points: int = 1001) -> Boundary:
    """The exact region's outline at one delta as arrays: beta from -delta to beta_mmax
    (``points`` evenly spaced, plus the hyperbola's top, the point of alpha_mmax and the
    corner) and alpha = :func:`alpha_max` there, 0 at both ends.  Draw it with
    ``plt.fill_between(*zwidth.boundary(5.122))``."""
    if np.ndim(delta) != 0:
        raise ValueError(f"zwidth.boundary: delta must be a scalar (one region), got shape {np.shape(delta)}")
    ext = extremes(delta)
    assert isinstance(ext, Extremes)
    top, cor = hyperbola_top(delta, errors="mask"), corner(delta)
    betas = boundary_betas(float(delta), float(ext.beta_mmax), points,
                           [top.beta, cor.beta, ext.beta_at_alpha_mmax])
    return Boundary(beta=betas, alpha=np.asarray(alpha_max(delta, betas), dtype=float))


def beta_interval(delta: ArrayLike, alpha: ArrayLike, *, delay: int = 0, filter_pole: ArrayLike = 0.0,
                  average: Optional[int] = None, differentiator: str = "backward", kappa: ArrayLike = 0.0,
        lambda_: ArrayLike = 0.0,
                  errors: Errors = "raise") -> Interval:
    """The open interval of beta stable at this alpha (nonempty False where none).

    For a loop other than the paper's the stable set of beta may be several intervals;
    this is the widest, certified (inside the true one; zw_loop_beta_interval)."""
    g = _general("beta_interval", delay, filter_pole, average, differentiator, kappa, lambda_, errors)
    if not g.ideal:
        out, _ = call("beta_interval", _core.loop_beta_interval, _DPKL + ("alpha",), g.plant(delta) + (alpha,),
                      errors, **g.loop.kernel_options())
        return Interval.from_outputs(out)
    out, _ = call("beta_interval", _core.beta_interval, ("delta", "alpha"), (delta, alpha), errors)
    return Interval.from_outputs(out)


def loop_boundary(delta: float, *, delay: int = 0, filter_pole: float = 0.0, average: Optional[int] = None,
                  differentiator: str = "backward", kappa: ArrayLike = 0.0,
        lambda_: ArrayLike = 0.0, points: int = 2001) -> BoundaryPoint:
    """The complex-pair boundary curve (alpha(theta), beta(theta)) of a loop for theta on a
    grid of ``points`` in (0, pi) (zw_loop_boundary_point; NaN where the curve has an
    asymptote).  Informational (plots): limits come from :func:`alpha_max`."""
    g = _general("loop_boundary", delay, filter_pole, average, differentiator, kappa, lambda_, "raise")
    theta = np.linspace(0.0, np.pi, int(points) + 2)[1:-1]
    out, _ = call("loop_boundary", _core.loop_boundary_point, _DPKL + ("theta",), g.plant(delta) + (theta,),
                  "mask", **g.loop.kernel_options())
    return BoundaryPoint.from_outputs(out)


_PARTS_DOC = """
    ``kappa`` (= (k_p + k_h) T^2 / M) and ``lambda_`` (= tau / T) put the loop on a plant with
    a stiffness and an actuator lag (plant.h), as in :func:`check`; 0 is the paper's plant."""

for _g in (loop_poly, extremes, alpha_max, beta_interval, loop_boundary):
    _g.__doc__ = (_g.__doc__ or "") + _PARTS_DOC
