# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Independent reference simulator of the identification experiment (zwidth.identify).

The experiment: the drive plays a command u_n with its gains off and logs the position it
measures.  The command logged at tick n acts on the plant during [(n + d) T, (n + d + 1) T)
(zero-order hold, d the delay in whole samples; before tick d the force is 0); the position
logged at tick n is x(n T).  The continuous plant:

    m x'' + b x' + k x = f - F_c sign(x'),    tau f' + f = u(t - d T)   (tau = 0: f = u)

with sticking: where x' = 0 and |f - k x| <= F_c the mass stays at rest.

Nothing here uses zwidth.identify's method (a matrix exponential by scipy.linalg.expm and
transfer functions by scipy.signal.ss2tf / lfilter).  Two integrators, checked against each
other and against mpmath closed forms in tests/py/test_ident_reference.py:

* linear plants (F_c = 0, any k and tau): classic fourth-order Runge-Kutta with 2^p
  substeps per sample (p >= 12, more when the plant's fastest rate needs it, so that
  |h lambda| <= 1/4096 and RK4's truncation is below double rounding).  For a linear
  system with an input held over the sample, one RK4 substep of length h *is* the affine map
  z -> z + E z + S u with E = hM + (hM)^2/2 + (hM)^3/6 + (hM)^4/24 and
  S = h (I + hM/2 + (hM)^2/6 + (hM)^3/24) B (the four stages expanded), so the 2^p substeps
  are composed by p doublings (E <- 2E + E E, S <- 2S + E S), carried as the increments E, S
  so that nothing is lost to 1 + small.  The result is the RK4 solution with 2^p substeps,
  exactly as stepping it would give, at the cost of one small matrix product per sample.
* Coulomb friction (no lag, no spring): the exact piecewise closed form.  Within a sample
  the force is constant; with the sign s of the velocity fixed the velocity relaxes
  exponentially, v(t) = e^{-a t} v0 + t phi1(a t) g, x(t) = x0 + t phi1(a t) v0 +
  t^2 phi2(a t) g, a = b/m, g = (f - F_c s)/m, phi1(z) = (1 - e^{-z})/z,
  phi2(z) = (z - 1 + e^{-z})/z^2; where g opposes v the velocity reaches 0 at
  t* = (-v0/g) log1p(z)/z, z = -a v0/g; at rest the mass sticks while |f| <= F_c, else
  moves off in the direction of f (and, starting from rest, cannot reverse within the
  sample).  So a sample has at most two phases.  Friction with a lag or a spring raises
  NotImplementedError.

Positions are returned in position units; ``noise`` (Gaussian, standard deviation in
position units) is added before the quantization to ``counts_per_unit`` (round to the
nearest count, divided back).  :func:`simulate_many` runs many trials at once (parameters of
shape (trials,), commands of shape (trials, n)); :func:`simulate` is one trial.
"""
from __future__ import annotations

import math
from typing import Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["simulate", "simulate_many", "trajectory_many", "measure", "rk4_sample_map", "phi1", "phi2",
           "MIN_DOUBLINGS"]

#: 2^12 = 4096 RK4 substeps per sample at least.
MIN_DOUBLINGS = 12
#: |h lambda| of a substep is kept at or below this (RK4's local error ~ (h lambda)^5 / 120).
MAX_SUBSTEP_RATE = 1.0 / 4096.0

Array = NDArray[np.float64]


# ---- the functions of the closed form -------------------------------------------------------


def phi1(z: ArrayLike) -> Array:
    """(1 - e^{-z}) / z, 1 at z = 0 (expm1 keeps it accurate for small z)."""
    z = np.asarray(z, dtype=float)
    safe = np.where(z == 0.0, 1.0, z)
    out: Array = np.where(z == 0.0, 1.0, -np.expm1(-safe) / safe)
    return out


def phi2(z: ArrayLike) -> Array:
    """(z - 1 + e^{-z}) / z^2, 1/2 at z = 0; its Taylor series sum_k (-z)^k / (k + 2)! for
    |z| < 0.1 (the literal form cancels there)."""
    z = np.asarray(z, dtype=float)
    series = np.zeros_like(z)
    term = np.full_like(z, 0.5)          # (-z)^0 / 2!
    for k in range(14):
        series = series + term
        term = term * (-z) / (k + 3)
    small = np.abs(z) < 0.1
    safe = np.where(small, 1.0, z)
    literal = (safe + np.expm1(-safe)) / (safe * safe)
    out: Array = np.where(small, series, literal)
    return out


def _log1p_over(z: Array) -> Array:
    """log1p(z) / z, 1 at z = 0."""
    safe = np.where(z == 0.0, 1.0, z)
    out: Array = np.where(np.abs(z) < 1e-12, 1.0 - z / 2.0, np.log1p(safe) / safe)
    return out


# ---- linear plants: RK4 with 2^p substeps, composed -------------------------------------------


def rk4_sample_map(m: ArrayLike, b: ArrayLike, T: ArrayLike, *, k: ArrayLike = 0.0,
                   tau: ArrayLike = 0.0, lag: Optional[bool] = None,
                   doublings: Optional[int] = None) -> Tuple[Array, Array, int]:
    """The map of one sample, z_{n+1} = Phi z_n + Gamma u_n, of RK4 with 2^p substeps.

    The state is normalized: z = (x, T x', [T^2 f / m]) and the input u T^2 / m, so every
    entry is O(1); time runs in samples.  ``lag``: use the three-state model (default: when
    any tau > 0; trials with tau = 0 are then not allowed).  Returns (Phi, Gamma, p) with
    Phi of shape (trials, n, n), Gamma (trials, n)."""
    m_, b_, T_, k_, tau_ = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, dtype=float))
                                                 for v in (m, b, T, k, tau)))
    if lag is None:
        lag = bool(np.any(tau_ > 0.0))
    if lag and np.any(tau_ <= 0.0):
        raise ValueError("rk4_sample_map: the lag model needs tau > 0 in every trial")
    trials = m_.size
    a = b_ * T_ / m_              # b T / m
    w2 = k_ * T_ ** 2 / m_        # k T^2 / m
    n = 3 if lag else 2
    M = np.zeros((trials, n, n))
    Bv = np.zeros((trials, n))
    M[:, 0, 1] = 1.0
    M[:, 1, 0] = -w2
    M[:, 1, 1] = -a
    if lag:
        lam = T_ / tau_           # T / tau
        M[:, 1, 2] = 1.0
        M[:, 2, 2] = -lam
        Bv[:, 2] = lam
        rate = np.maximum.reduce([a, np.sqrt(w2), lam, np.ones_like(a)])
    else:
        Bv[:, 1] = 1.0
        rate = np.maximum.reduce([a, np.sqrt(w2), np.ones_like(a)])
    if doublings is None:
        need = float(np.max(rate)) / MAX_SUBSTEP_RATE
        doublings = max(MIN_DOUBLINGS, int(math.ceil(math.log2(need))))
    h = 2.0 ** -doublings
    hM = h * M
    hM2 = hM @ hM
    hM3 = hM2 @ hM
    hM4 = hM3 @ hM
    eye = np.broadcast_to(np.eye(n), hM.shape)
    E = hM + hM2 / 2.0 + hM3 / 6.0 + hM4 / 24.0
    S = h * np.einsum("tij,tj->ti", eye + hM / 2.0 + hM2 / 6.0 + hM3 / 24.0, Bv)
    for _ in range(doublings):
        S = 2.0 * S + np.einsum("tij,tj->ti", E, S)
        E = 2.0 * E + E @ E
    return eye + E, S, doublings


def _forces(u: Array, delay: int) -> Array:
    """The force held over sample j: u[j - d] (0 before tick d)."""
    f = np.zeros_like(u)
    if delay < u.shape[1]:
        f[:, delay:] = u[:, :u.shape[1] - delay]
    return f


def _linear(m: Array, b: Array, T: Array, f: Array, k: Array, tau: Array, x0: Array,
            v0: Array) -> Tuple[Array, Array]:
    trials, n = f.shape
    x = np.empty((trials, n))
    v = np.empty((trials, n))
    for lag in (False, True):
        sel = np.flatnonzero((tau > 0.0) == lag)
        if sel.size == 0:
            continue
        Phi, Gam, _ = rk4_sample_map(m[sel], b[sel], T[sel], k=k[sel], tau=tau[sel], lag=lag)
        g = T[sel] ** 2 / m[sel]
        w = f[sel] * g[:, None]                          # the normalized input u T^2 / m
        z = np.zeros((sel.size, Phi.shape[1]))
        z[:, 0] = x0[sel]
        z[:, 1] = v0[sel] * T[sel]
        xs = np.empty((sel.size, n))
        ys = np.empty((sel.size, n))
        for j in range(n):
            xs[:, j] = z[:, 0]
            ys[:, j] = z[:, 1]
            z = np.einsum("tij,tj->ti", Phi, z) + Gam * w[:, j:j + 1]
        x[sel] = xs
        v[sel] = ys / T[sel][:, None]
    return x, v


# ---- Coulomb friction: the exact piecewise closed form ----------------------------------------


def _advance(x: Array, v: Array, g: Array, a: Array, t: Array) -> Tuple[Array, Array]:
    """Move for time t with the net acceleration at rest g (sign of the velocity fixed)."""
    z = a * t
    p1 = phi1(z)
    x_new = x + t * p1 * v + t * t * phi2(z) * g
    v_new = np.exp(-z) * v + t * p1 * g
    return x_new, v_new


def _from_rest(x: Array, f: Array, m: Array, a: Array, Fc: Array, t: Array) -> Tuple[Array, Array]:
    """At rest for time t under force f: stick while |f| <= F_c, else move off along f (from
    rest the velocity keeps the sign of f - F_c sign f, so it cannot reverse)."""
    s = np.sign(f)
    moves = np.abs(f) > Fc
    g = np.where(moves, (f - Fc * s) / m, 0.0)
    x_new, v_new = _advance(x, np.zeros_like(x), g, a, t)
    return np.where(moves, x_new, x), np.where(moves, v_new, 0.0)


def _friction_sample(x: Array, v: Array, f: Array, m: Array, a: Array, Fc: Array,
                     h: Array) -> Tuple[Array, Array]:
    moving = v != 0.0
    s = np.sign(v)
    g = (f - Fc * s) / m
    # where g opposes v the velocity reaches 0 at t* (z = -a v / g > 0 then)
    opposes = moving & (g * v < 0.0)
    g_safe = np.where(opposes, g, 1.0)
    z = np.where(opposes, -a * v / g_safe, 0.0)
    t_star = np.where(opposes, (-v / g_safe) * _log1p_over(z), np.inf)
    stops = t_star < h
    t1 = np.where(stops, t_star, h)
    x1, v1 = _advance(x, v, g, a, t1)
    v1 = np.where(stops, 0.0, v1)                    # exactly at rest at t*
    # the rest of the sample from rest: where the mass stopped, and where it started at rest
    rest = np.where(moving, np.where(stops, h - t1, 0.0), h)
    at_rest = ~moving | stops
    xr, vr = _from_rest(np.where(moving, x1, x), f, m, a, Fc, rest)
    x_out = np.where(at_rest, xr, x1)
    v_out = np.where(at_rest, vr, v1)
    return x_out, v_out


def _friction(m: Array, b: Array, T: Array, f: Array, Fc: Array, x0: Array,
              v0: Array) -> Tuple[Array, Array]:
    trials, n = f.shape
    a = b / m
    x_log = np.empty((trials, n))
    v_log = np.empty((trials, n))
    x, v = x0.copy(), v0.copy()
    for j in range(n):
        x_log[:, j] = x
        v_log[:, j] = v
        x, v = _friction_sample(x, v, f[:, j], m, a, Fc, T)
    return x_log, v_log


# ---- the entry points ---------------------------------------------------------------------------


def _trials(value: ArrayLike, trials: int, name: str) -> Array:
    a = np.asarray(value, dtype=float)
    if a.ndim == 0:
        return np.full(trials, float(a))
    if a.shape != (trials,):
        raise ValueError(f"{name}: shape {a.shape}, expected () or ({trials},)")
    return a.astype(float)


def trajectory_many(m: ArrayLike, b: ArrayLike, T: ArrayLike, u: ArrayLike, *, delay: int = 0,
                    k: ArrayLike = 0.0, tau: ArrayLike = 0.0, coulomb: ArrayLike = 0.0,
                    x0: ArrayLike = 0.0, v0: ArrayLike = 0.0,
                    method: str = "auto") -> Tuple[Array, Array]:
    """The exact (noise-free) position and velocity at the sample instants, each of shape
    (trials, n).  method: "auto" (RK4 for linear trials, the piecewise closed form with
    friction), "rk4" or "piecewise" (no lag, no spring; F_c may be 0)."""
    U = np.asarray(u, dtype=float)
    if U.ndim == 1:
        U = U[None, :]
    if U.ndim != 2:
        raise ValueError(f"u: shape {U.shape}, expected (n,) or (trials, n)")
    trials = U.shape[0]
    if not (isinstance(delay, (int, np.integer)) and delay >= 0):
        raise ValueError(f"delay: a whole number of samples >= 0, got {delay!r}")
    m_, b_, T_, k_, tau_, Fc, x0_, v0_ = (_trials(val, trials, name) for val, name in (
        (m, "m"), (b, "b"), (T, "T"), (k, "k"), (tau, "tau"), (coulomb, "coulomb"), (x0, "x0"), (v0, "v0")))
    if np.any(m_ <= 0.0) or np.any(T_ <= 0.0) or np.any(b_ < 0.0) or np.any(k_ < 0.0) \
            or np.any(tau_ < 0.0) or np.any(Fc < 0.0):
        raise ValueError("need m > 0, T > 0 and b, k, tau, coulomb >= 0")
    f = _forces(U, int(delay))
    if method not in ("auto", "rk4", "piecewise"):
        raise ValueError(f"method: 'auto', 'rk4' or 'piecewise', got {method!r}")
    friction = bool(np.any(Fc > 0.0))
    if method == "rk4" and friction:
        raise ValueError("method 'rk4' is for linear plants (coulomb = 0)")
    if method == "piecewise" or (method == "auto" and friction):
        if np.any(tau_ > 0.0) or np.any(k_ > 0.0):
            raise NotImplementedError("Coulomb friction with an actuator lag or a spring is not in the reference "
                                      "(its closed form is for m x'' + b x' = f - F_c sign x' only)")
        return _friction(m_, b_, T_, f, Fc, x0_, v0_)
    return _linear(m_, b_, T_, f, k_, tau_, x0_, v0_)


def measure(x: ArrayLike, counts_per_unit: Optional[float] = None, noise: float = 0.0,
            rng: Optional[np.random.Generator] = None) -> Array:
    """What the drive logs of the true position x: x plus Gaussian noise of standard
    deviation ``noise``, then rounded to the nearest count of ``counts_per_unit`` (in position
    units; None: no encoder)."""
    y: Array = np.asarray(x, dtype=float)
    if noise > 0.0:
        if rng is None:
            rng = np.random.default_rng()
        y = y + noise * rng.standard_normal(y.shape)
    if counts_per_unit is not None:
        y = np.round(y * counts_per_unit) / counts_per_unit
    return y


def simulate_many(m: ArrayLike, b: ArrayLike, T: ArrayLike, u: ArrayLike, *, delay: int = 0,
                  k: ArrayLike = 0.0, tau: ArrayLike = 0.0, coulomb: ArrayLike = 0.0,
                  x0: ArrayLike = 0.0, v0: ArrayLike = 0.0, counts_per_unit: Optional[float] = None,
                  noise: float = 0.0, rng: Optional[np.random.Generator] = None,
                  method: str = "auto") -> Array:
    """The logged positions of many trials, shape (trials, n): parameters scalar or of shape
    (trials,), u of shape (trials, n), one delay and one encoder for all."""
    x, _ = trajectory_many(m, b, T, u, delay=delay, k=k, tau=tau, coulomb=coulomb, x0=x0, v0=v0, method=method)
    return measure(x, counts_per_unit, float(noise), rng)


def simulate(m: float, b: float, T: float, u: ArrayLike, *, delay: int = 0, k: float = 0.0,
             tau: float = 0.0, coulomb: float = 0.0, x0: float = 0.0, v0: float = 0.0,
             counts_per_unit: Optional[float] = None, noise: float = 0.0,
             rng: Optional[np.random.Generator] = None, method: str = "auto") -> Array:
    """The position log x_0 .. x_{n-1} of one trial (module docstring for the model):
    u the command per tick, delay in whole samples, k the spring, tau the actuator lag,
    coulomb the Coulomb friction F_c (= the static friction), x0 and v0 the initial state;
    Gaussian noise of standard deviation ``noise`` and then quantization to
    ``counts_per_unit`` (position units, rounded to the nearest count)."""
    U = np.asarray(u, dtype=float)
    if U.ndim != 1:
        raise ValueError(f"u: one-dimensional, got shape {U.shape} (simulate_many takes many trials)")
    out: Array = simulate_many(m, b, T, U[None, :], delay=delay, k=k, tau=tau, coulomb=coulomb, x0=x0, v0=v0,
                               counts_per_unit=counts_per_unit, noise=noise, rng=rng, method=method)[0]
    return out

