# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""Identify the plant from a log of the drive: m (or J), b, the delay, a lag, friction, a spring.

    >>> ident = identify(position=x, command=u, T=1e-3)          # doctest: +SKIP
    >>> ident.estimates["m"]                                     # doctest: +SKIP
    Estimate(name='m', value=0.1021, lo=0.1012, hi=0.1030, ...)
    >>> box = ident.box()            # a PlantBox with the delay found, for limits and commissioning

The experiment: the drive's gains are off and it plays a known command u_n (force or torque,
or current times a force constant) while logging the position x_n it measures at the same
tick.  The model is the plant zwidth certifies, sampled exactly (zero-order hold):

    m x'' + b x' + k x = f(t) - F_c sign(x'),    tau f' + f = u(t - d T)   (tau = 0: f = u)

with the delay d in whole samples (the command computed at tick n acts from tick n + d, as in
the loop zwidth analyses), the lag tau, the Coulomb friction F_c and the spring k each fitted
only when asked.  For fixed shape parameters (a = b/m, w2 = k/m, tau) the sampled position is
linear in 1/m, F_c/m and the initial state, so the fit is a separable least squares (variable
projection): the linear part exactly by lstsq, the shape by a grid and then
scipy.optimize.least_squares.  This is an output-error fit (the simulated response against the
measured one), unbiased under white measurement noise and quantization, where an equation-error
(ARX) fit is not.  Friction enters as a force opposing the velocity the model predicts (the
signs are iterated to a fixed point); sticking at rest is not modelled, the residual check
shows where it matters.  Each delay 0..max_delay is fitted on the same samples and the one with
the smallest residual is taken.

Intervals: the covariance of the fit, the larger of the classical sigma^2 (J'J)^-1 and a
correlation-robust (Newey-West) sandwich per parameter, with Student's t quantile; m, b, tau
and F_c are fitted in logarithms, so their intervals are positive.  ``box()`` uses a joint level
(Bonferroni over the box's parameters, default 0.99).  docs/identify.md explains the experiment,
the model, the intervals and their limits; bench/identify/validate.py measures their coverage.

Needs scipy (the extra "identify": ``pip install zwidth[identify]``).
"""
from __future__ import annotations

import csv
import dataclasses
import math
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .box import PlantBox
from .device import Device
from .results import Result
from .sim import _expm

__all__ = ["identify", "Identification", "Estimate", "FitCheck", "IdentifyError", "read_log", "excitation",
           "MAX_DELAY", "MIN_SAMPLES", "DEFAULT_LEVEL", "DEFAULT_BOX_LEVEL"]

MAX_DELAY = 8            #: the largest delay a loop may have (cli --delay 0..8)
MIN_SAMPLES = 50         #: fewer samples than this (or 20 per parameter) is too short a log
DEFAULT_LEVEL = 0.95     #: level of each parameter's interval
DEFAULT_BOX_LEVEL = 0.99  #: joint level of the box (Bonferroni over its parameters)
#: A parameter whose interval is wider than this relative to its value is called not identified.
MAX_RELATIVE_HALF_WIDTH = 0.5
#: At most this fraction of the samples may be missing (gaps in the time column), and at
#: most this many (each missing command is one more unknown of the fit).
MAX_MISSING = 0.05
MAX_MISSING_SAMPLES = 64
#: Time stamps may deviate from the grid by this fraction of T.
TIME_TOLERANCE = 0.05
#: A fit (another delay, the lag's mirrored solution) whose extra residual over the best has an
#: F statistic within this is one the log cannot reject (about 5 sigma, generous for the
#: correlated residuals of quantized logs): its delay and parameters stay possible.
PLAUSIBLE_F = 25.0
#: The smallest relative standard error an estimate is given (the precision of a binary32
#: log with margin; real logs' noise gives far more).
MIN_RELATIVE_SE = 1e-6
#: A singular value of the column-scaled Jacobian below this fraction of the largest one is a
#: direction the log does not determine.
UNDETERMINED_SINGULAR = 1e-9
#: Residual lag-1 autocorrelation above this, with the residual well above the quantization
#: floor, means the model misses something (a resonance, backlash, sticking, a wrong T).
MISFIT_RHO = 0.8
MISFIT_FLOOR_RATIO = 3.0
#: Parameters fitted (and given intervals) in logarithms: positive, intervals asymmetric.
_LOG_COORDINATES = ("m", "J", "b", "tau")
#: Fitted without friction, a friction fit that lowers the residual with an F statistic above
#: this (one parameter more; about 5 sigma) means the log has friction the model leaves out.
FRICTION_F = 25.0
#: The search's bounds of log(b T/m): a fit that ends on one has not resolved b/m.
_LOG_AT_BOUNDS = (math.log(1e-9), math.log(1e3))
_GRID = 48               #: points of the grid over log(b/m T) that starts the fit


class IdentifyError(ValueError):
    """A log zwidth cannot identify from: ``column`` names the input (or None), ``reason`` why."""

    def __init__(self, message: str, column: Optional[str] = None) -> None:
        super().__init__(message)
        self.column = column


@dataclasses.dataclass(frozen=True, repr=False)
class Estimate(Result):
    """One identified parameter: value, the interval [lo, hi] at ``level``, its standard error
    (in the fitted coordinate: relative for m, b, tau, F_c), and whether the log determines it."""

    name: str
    value: float
    lo: float
    hi: float
    level: float
    standard_error: float
    identified: bool
    unit: str = dataclasses.field(default="", metadata={"result": False})

    def __str__(self) -> str:
        unit = f" {self.unit}" if self.unit else ""
        tag = "" if self.identified else "  NOT IDENTIFIED"
        return (f"{self.name} = {self.value:.6g}{unit}  [{self.lo:.6g}, {self.hi:.6g}] at "
                f"{100 * self.level:g} %{tag}")


@dataclasses.dataclass(frozen=True, repr=False)
class FitCheck(Result):
    """The residual check: does the model explain the log?

    rms: residual RMS [position unit]; floor: the quantization floor q/sqrt(12) (0 without
    counts); rho1: lag-1 autocorrelation of the residual; explained: 1 - residual/motion
    variance; ok and reason: the verdict in words."""

    rms: float
    floor: float
    rho1: float
    explained: float
    ok: bool
    reason: str


@dataclasses.dataclass(frozen=True, repr=False)
class Identification(Result):
    """What :func:`identify` found.  ``estimates`` by name (m or J, b, and k, tau, F_c when
    fitted), ``delay`` in samples with ``delay_rss`` (residual sum of squares per delay tried),
    ``fit`` (:class:`FitCheck`), ``warnings``, the log's ``T`` and sample count; ``fitted`` and
    ``residual`` are the model's position and the measured minus it, on the log's grid (NaN
    where samples were missing)."""

    estimates: Dict[str, Estimate]
    delay: int
    delay_rss: Dict[int, float]
    fit: FitCheck
    warnings: Tuple[str, ...]
    T: float
    samples: int
    rotary: bool
    dof: int
    time: NDArray[np.float64] = dataclasses.field(metadata={"result": False})
    measured: NDArray[np.float64] = dataclasses.field(metadata={"result": False})
    fitted: NDArray[np.float64] = dataclasses.field(metadata={"result": False})
    command: NDArray[np.float64] = dataclasses.field(metadata={"result": False})
    covariance: NDArray[np.float64] = dataclasses.field(metadata={"result": False})
    #: every fit the log allows (delay, physical values, covariance, degrees of freedom),
    #: the best first: the intervals and the box cover all of them
    plausible: Tuple[Tuple[int, NDArray[np.float64], NDArray[np.float64], int], ...] = dataclasses.field(
        default=(), metadata={"result": False}, repr=False)

    @property
    def plausible_delays(self) -> Tuple[int, ...]:
        """The delays of the fits the log cannot reject (the best one's first)."""
        return tuple(sorted({d for d, *_ in self.plausible}, key=lambda d: (d != self.delay, d))) or (self.delay,)

    @property
    def residual(self) -> NDArray[np.float64]:
        return self.measured - self.fitted

    @property
    def mass_symbol(self) -> str:
        return "J" if self.rotary else "m"

    def lines(self) -> List[str]:
        """The result in words, one line per fact."""
        out = [f"Identified from {self.samples} samples, T = {self.T:g} s:"]
        out += [f"  {e}" for e in self.estimates.values()]
        tried = ", ".join(f"{d}: {rss:.4g}" for d, rss in sorted(self.delay_rss.items()))
        also = [d for d in self.plausible_delays if d != self.delay]
        allowed = f"; {', '.join(map(str, also))} also fit" if also else ""
        out.append(f"  delay = {self.delay} samples{allowed} (residual sum of squares per delay: {tried})")
        f = self.fit
        floor = f", quantization floor {f.floor:.3g}" if f.floor > 0 else ""
        out.append(f"  fit: residual RMS {f.rms:.3g}{floor}, lag-1 autocorrelation {f.rho1:.2f}, "
                   f"explains {100 * f.explained:.4g} % of the motion: {f.reason}")
        out += [f"  warning: {w}" for w in self.warnings]
        return out

    def box(self, level: float = DEFAULT_BOX_LEVEL, **loop: Any) -> PlantBox:
        """The :class:`zwidth.PlantBox` holding the plant at joint ``level``: m and b (and k)
        over their intervals at level 1 - (1 - level)/p each (Bonferroni, p the box's
        parameters) and over every fit the log allows, at the largest delay it allows
        (``plausible_delays``); friction is left out (it only dissipates).  ``loop``:
        the drive's other loop keywords (velocity_filter, differentiator) and PlantBox options.

        Raises IdentifyError when the model does not fit, m or b is not identified, or a lag
        was fitted: the box certification refuses a lag (issue 25), and certifying a box
        without it would certify a loop the drive does not run.  Then :meth:`device` gives the
        plant with its lag for a point check."""
        if not 0.0 < level < 1.0:
            raise ValueError(f"zwidth.Identification.box: level must be in (0, 1), got {level!r}")
        if not self.fit.ok:
            raise IdentifyError(f"no box: the model does not fit the log ({self.fit.reason})")
        missing = [n for n in (self.mass_symbol, "b") if not self.estimates[n].identified]
        if missing:
            raise IdentifyError(f"no box: {', '.join(missing)} not identified by this log (interval wider than "
                                f"+-{100 * MAX_RELATIVE_HALF_WIDTH:g} %); excite longer, stronger or nearer the "
                                f"corner frequency b/(2 pi m)")
        if "tau" in self.estimates:
            tau = self.estimates["tau"]
            raise IdentifyError(f"no box: the log has an actuator lag (tau = {tau.value:.4g} s, [{tau.lo:.4g}, "
                                f"{tau.hi:.4g}]), and a plant box is certified without one (a lag over a box is "
                                f"not built yet); Identification.device() gives the plant with its lag for a "
                                f"point check")
        # k's box is [max(0, lo), hi]: a wide interval is still a bound.  Every fit the log
        # allows contributes its intervals; the delay is the largest one allowed (a delay
        # the log cannot see is assumed, not ignored)
        names = [n for n in (self.mass_symbol, "b", "k") if n in self.estimates]
        each = 1.0 - (1.0 - level) / len(names)
        fits = self.plausible or ((self.delay, np.array([self._fitted_coordinate(n)[0] for n in self.estimates]),
                                   self.covariance, self.dof),)
        iv: Dict[str, Tuple[float, float]] = {}
        for n in names:
            i = self._index(n)
            log = n in _LOG_COORDINATES
            ends = [_interval((float(v[i]), log), c, i, each, dof) for _, v, c, dof in fits]
            iv[n] = (min(a for a, _ in ends), max(b for _, b in ends))
        kwargs: Dict[str, Any] = dict(delay=max(d for d, *_ in fits), rotary=self.rotary)
        if "k" in iv:
            kwargs["stiffness"] = (max(0.0, iv["k"][0]), max(0.0, iv["k"][1]))
        kwargs.update(loop)
        return PlantBox(iv[self.mass_symbol], iv["b"], self.T, **kwargs)

    def device(self, **loop: Any) -> Device:
        """The identified plant at its estimates (with its delay, lag and spring) as a
        :class:`zwidth.Device`, for point checks; ``loop``: the drive's other loop keywords.
        A point estimate is not a certificate: :meth:`box` is."""
        e = self.estimates
        kwargs: Dict[str, Any] = dict(delay=self.delay, rotary=self.rotary)
        if "tau" in e:
            kwargs["actuator_tau"] = e["tau"].value
        if "k" in e:
            kwargs["stiffness"] = max(0.0, e["k"].value)
        kwargs.update(loop)
        return Device(e[self.mass_symbol].value, e["b"].value, self.T, **kwargs)

    # the covariance is over the physical coordinates, in the order of ``estimates``
    def _index(self, name: str) -> int:
        return list(self.estimates).index(name)

    def _fitted_coordinate(self, name: str) -> Tuple[float, bool]:
        """The estimate in the coordinate its interval is in (log for m, b, tau)."""
        e = self.estimates[name]
        log = name in _LOG_COORDINATES
        return (math.log(e.value) if log else e.value, log)

    def as_dict(self) -> Dict[str, Any]:
        out = super().as_dict()
        out["estimates"] = {n: e.as_dict() for n, e in self.estimates.items()}
        out["fit"] = self.fit.as_dict()
        out["delay_rss"] = {str(d): v for d, v in self.delay_rss.items()}
        out["warnings"] = list(self.warnings)
        out["plausible_delays"] = list(self.plausible_delays)
        return out


def _interval(coord: Tuple[float, bool], cov: NDArray[np.float64], i: int, level: float,
              dof: int) -> Tuple[float, float]:
    from scipy import stats
    value, log = coord
    half = float(stats.t.ppf(0.5 + 0.5 * level, max(dof, 1))) * math.sqrt(max(float(cov[i, i]), 0.0))
    lo, hi = value - half, value + half
    if not log:
        return (lo, hi)
    return (math.exp(lo) if lo > -700.0 else 0.0, math.exp(hi) if hi < 700.0 else math.inf)


# ---- the log ----------------------------------------------------------------------------


@dataclasses.dataclass
class _Log:
    u: NDArray[np.float64]          # command on the full grid (0 at missing samples)
    y: NDArray[np.float64]          # position on the full grid (NaN where missing)
    present: NDArray[np.bool_]
    T: float
    warnings: List[str]


def _column(values: ArrayLike, name: str) -> NDArray[np.float64]:
    try:
        a = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise IdentifyError(f"{name}: not numbers ({exc})", name) from None
    if a.ndim != 1:
        raise IdentifyError(f"{name}: must be one-dimensional, got shape {a.shape}", name)
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise IdentifyError(f"{name}: {bad.size} value(s) not finite (NaN or inf), first at sample {bad[0]}",
                            name)
    return a


def _regularize(u: NDArray[np.float64], y: NDArray[np.float64], t: Optional[NDArray[np.float64]],
                index: Optional[NDArray[np.float64]], T: Optional[float]) -> _Log:
    """Put the log on its sample grid: drop repeated rows, hold the command over missing
    samples (their positions are left out of the fit), refuse what is not a sampled log."""
    warnings: List[str] = []
    if t is not None and index is not None:
        raise IdentifyError("give the time or the sample index, not both", "time")
    if t is not None:
        d = np.diff(t)
        if np.any(d < 0):
            i = int(np.flatnonzero(d < 0)[0])
            raise IdentifyError(f"time: decreases at sample {i + 1} ({t[i]:g} -> {t[i + 1]:g} s)", "time")
        steps = d[d > 0]
        if steps.size == 0:
            raise IdentifyError("time: all time stamps are equal", "time")
        T_log = float(np.median(steps))
        if T is None:
            T = T_log
        elif abs(T_log - T) > TIME_TOLERANCE * T:
            raise IdentifyError(f"time: the log is sampled every {T_log:g} s, not T = {T:g} s (a wrong T scales "
                                f"m and b by its square and itself)", "time")
        ticks = (t - t[0]) / T
    elif index is not None:
        if T is None:
            raise IdentifyError("T: a log by sample index needs the sampling period T", "T")
        ticks = index - index[0]
        if np.any(np.diff(ticks) < 0):
            i = int(np.flatnonzero(np.diff(ticks) < 0)[0])
            raise IdentifyError(f"index: decreases at sample {i + 1}", "index")
    else:
        if T is None:
            raise IdentifyError("T: give the sampling period T (or a time column)", "T")
        ticks = np.arange(u.size, dtype=float)
    if not (math.isfinite(T) and T > 0.0):
        raise IdentifyError(f"T: must be > 0 and finite, got {T!r}", "T")
    n_tick = np.rint(ticks)
    off = np.abs(ticks - n_tick)
    if np.any(off > TIME_TOLERANCE):
        i = int(np.flatnonzero(off > TIME_TOLERANCE)[0])
        raise IdentifyError(f"time: not uniform: sample {i} lies {off[i]:.2f} T off the grid of T = {T:g} s",
                            "time")
    k = n_tick.astype(np.int64)
    same = np.flatnonzero(np.diff(k) == 0) + 1
    if same.size:
        clash = same[(u[same] != u[same - 1]) | (y[same] != y[same - 1])]
        if clash.size:
            raise IdentifyError(f"time: sample {int(clash[0])} repeats the time of the one before with other "
                                f"values", "time")
        warnings.append(f"{same.size} repeated sample(s) dropped")
        keep = np.ones(k.size, bool)
        keep[same] = False
        k, u, y = k[keep], u[keep], y[keep]
    n = int(k[-1]) + 1
    missing = n - k.size
    if missing > MAX_MISSING * n:
        raise IdentifyError(f"time: {missing} of {n} samples missing (more than {100 * MAX_MISSING:g} %)", "time")
    U = np.empty(n)
    Y = np.full(n, np.nan)
    present = np.zeros(n, bool)
    present[k] = True
    Y[k] = y
    # a missing sample's command is unknown: the fit estimates it (one more linear
    # coefficient each), and its position is left out
    U[:] = 0.0
    U[k] = u
    if missing > MAX_MISSING_SAMPLES:
        raise IdentifyError(f"time: {missing} samples missing (at most {MAX_MISSING_SAMPLES}: each costs the fit an "
                            f"unknown command)", "time")
    if missing:
        warnings.append(f"{missing} missing sample(s): their commands are fitted as unknowns, their positions "
                        f"left out")
    return _Log(U, Y, present, float(T), warnings)


def read_log(path: Union[str, Path], *, time: Optional[str] = None, index: Optional[str] = None,
             command: str = "command", position: str = "position") -> Dict[str, NDArray[np.float64]]:
    """Read a log: a CSV file with a header row (or a .npz), columns by name.  Returns a dict
    with "command", "position" and "time" or "index" when named.  A missing column, a cell that
    is not a number, or ragged rows raise IdentifyError naming the column (and the row)."""
    path = Path(path)
    wanted = {"command": command, "position": position}
    if time is not None:
        wanted["time"] = time
    if index is not None:
        wanted["index"] = index
    if path.suffix.lower() == ".npz":
        with np.load(path) as data:
            missing = [c for c in wanted.values() if c not in data.files]
            if missing:
                raise IdentifyError(f"{path}: no column {missing[0]!r} (it has {', '.join(data.files)})", missing[0])
            return {k: _column(data[c], c) for k, c in wanted.items()}
    try:
        with open(path, newline="") as fh:
            rows = list(csv.reader(line for line in fh if line.strip() and not line.lstrip().startswith("#")))
    except OSError as exc:
        raise IdentifyError(f"{path}: cannot read ({exc.strerror})") from None
    if not rows:
        raise IdentifyError(f"{path}: empty")
    header = [h.strip() for h in rows[0]]
    cols: Dict[str, int] = {}
    for key, name in wanted.items():
        if name not in header:
            raise IdentifyError(f"{path}: no column {name!r} (the header has {', '.join(header)})", name)
        cols[key] = header.index(name)
    out: Dict[str, List[float]] = {k: [] for k in wanted}
    for r, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise IdentifyError(f"{path}:{r}: {len(row)} fields, the header has {len(header)}")
        for key, c in cols.items():
            try:
                out[key].append(float(row[c]))
            except ValueError:
                raise IdentifyError(f"{path}:{r}: column {wanted[key]!r}: {row[c]!r} is not a number",
                                    wanted[key]) from None
    return {k: _column(v, wanted[k]) for k, v in out.items()}


# ---- the model ----------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class _Shape:
    """Which parts the model has; the shape parameters psi are log(a T), [w2 T^2], [log(tau/T)]."""
    spring: bool
    lag: bool
    friction: bool

    @property
    def n_psi(self) -> int:
        return 1 + int(self.spring) + int(self.lag)

    @property
    def n_states(self) -> int:
        return 2 + int(self.lag)


def _discrete(shape: _Shape, psi: NDArray[np.float64]) -> Tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Exact zero-order-hold sampling of x'' + a x' + w2 x = f, tau f' + f = g u, time in
    units of T (so the matrices stay O(1)); returns (Ad, Bd) for the input g u."""
    a = math.exp(psi[0])
    w2 = float(psi[1]) if shape.spring else 0.0
    n = shape.n_states
    M = np.zeros((n + 1, n + 1))
    M[0, 1] = 1.0
    M[1, 0], M[1, 1] = -w2, -a
    if shape.lag:
        lam = math.exp(-psi[-1])       # 1 / (tau/T)
        M[1, 2] = 1.0
        M[2, 2], M[2, 3] = -lam, lam
    else:
        M[1, 2] = 1.0
    # sim's Taylor expm (to 3e-12 of mpmath's over the fit's range, test_identify.py):
    # scipy.linalg.expm is closer (1e-13), but on a machine whose cores are busy it was
    # measured at 8 ms per 3x3 call instead of 50 us (OpenBLAS's threads contending;
    # OPENBLAS_NUM_THREADS=1 cures it), and the fit calls this thousands of times
    E = _expm(M)
    return E[:n, :n], E[:n, n]


def _responses(shape: _Shape, psi: NDArray[np.float64], inputs: Sequence[NDArray[np.float64]],
               length: int, impulses: Sequence[int] = ()) -> NDArray[np.float64]:
    """Columns: the position's response to each input sequence (from the zero state), to a
    unit input at each of ``impulses`` (the unknown commands of missing samples) and to each
    unit initial state, over ``length`` samples (time in units of T)."""
    from scipy.signal import lfilter, ss2tf
    Ad, Bd = _discrete(shape, psi)
    C = np.zeros((1, shape.n_states))
    C[0, 0] = 1.0
    num, den = ss2tf(Ad, Bd.reshape(-1, 1), C, np.zeros((1, 1)))
    cols = [lfilter(num[0], den, w[:length]) for w in inputs]
    delta = np.zeros(length + 1)
    delta[0] = 1.0
    if len(impulses):
        h = lfilter(num[0], den, delta[:length])
        for j in impulses:
            col = np.zeros(length)
            col[j:] = h[:length - j]
            cols.append(col)
    for i in range(shape.n_states):
        e = np.zeros((shape.n_states, 1))
        e[i, 0] = 1.0
        n_i, d_i = ss2tf(Ad, e, C, np.zeros((1, 1)))
        cols.append(lfilter(n_i[0], d_i, delta)[1:])
    return np.column_stack(cols)


class _Problem:
    """The fit of one delay: samples n >= start (the same for every delay), inputs u[n - d]."""

    def __init__(self, log: _Log, shape: _Shape, delay: int, start: int) -> None:
        self.shape = shape
        self.delay = delay
        self.start = start
        self.w = log.u[start - delay: log.u.size - delay]
        self.unknown = [int(j) for j in np.flatnonzero(~log.present[start - delay: log.u.size - delay])]
        self.y = log.y[start:]
        self.mask = log.present[start:]
        self.signs = np.zeros_like(self.w)

    def inputs(self) -> List[NDArray[np.float64]]:
        return [self.w, -self.signs] if self.shape.friction else [self.w]

    def design(self, psi: NDArray[np.float64]) -> NDArray[np.float64]:
        return _responses(self.shape, psi, self.inputs(), self.w.size, self.unknown)

    def solve(self, psi: NDArray[np.float64]) -> Tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The linear coefficients (g, [g F_c], the unknown commands times g, the initial
        state) and the masked residual."""
        X = self.design(psi)
        coef = np.asarray(np.linalg.lstsq(X[self.mask], self.y[self.mask], rcond=None)[0], dtype=np.float64)
        residual: NDArray[np.float64] = self.y[self.mask] - X[self.mask] @ coef
        return coef, residual

    def predict(self, psi: NDArray[np.float64], coef: NDArray[np.float64]) -> NDArray[np.float64]:
        out: NDArray[np.float64] = self.design(psi) @ coef
        return out

    def update_signs(self, psi: NDArray[np.float64], coef: NDArray[np.float64]) -> bool:
        """Friction's input: the sign of the model's velocity over each sample; True if it changed."""
        x = self.predict(psi, coef)
        s = np.sign(np.diff(x, append=x[-1]))
        changed = bool(np.any(s != self.signs))
        self.signs = s
        return changed


def _fit_shape(problem: _Problem, psi0: NDArray[np.float64]) -> NDArray[np.float64]:
    from scipy.optimize import least_squares
    shape = problem.shape
    lo = np.full(shape.n_psi, -np.inf)
    hi = np.full(shape.n_psi, np.inf)
    lo[0], hi[0] = _LOG_AT_BOUNDS
    if shape.spring:
        lo[1], hi[1] = 0.0, 4.0
    if shape.lag:
        lo[-1], hi[-1] = math.log(1e-4), math.log(1e3)
    x0 = np.clip(psi0, lo + 1e-9, hi - 1e-9)
    res = least_squares(lambda p: problem.solve(p)[1], x0, bounds=(lo, hi), method="trf",
                        x_scale="jac", xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=400)
    out: NDArray[np.float64] = res.x
    return out


def _start(problem: _Problem) -> NDArray[np.float64]:
    """The shape to start from: the best point of a grid over log(a T) (and w2 T^2 with a
    spring, log(tau/T) with a lag), each grid point an exact linear least squares."""
    shape = problem.shape
    springs = ([0.0] + list(np.logspace(-8.0, 0.0, 9 if shape.lag else 17))) if shape.spring else [None]
    lags = [math.log(t) for t in (0.02, 0.1, 0.3, 1.0, 3.0)] if shape.lag else [None]
    best: Tuple[float, NDArray[np.float64]] = (math.inf, np.zeros(shape.n_psi))
    for la in np.linspace(math.log(1e-7), math.log(1e2), _GRID // 2 if shape.lag else _GRID):
        for w2 in springs:
            for lt in lags:
                psi = np.array([la] + ([w2] if w2 is not None else []) + ([lt] if lt is not None else []))
                rss = float(np.sum(problem.solve(psi)[1] ** 2))
                if rss < best[0]:
                    best = (rss, psi)
    return best[1]


def _fit(problem: _Problem, starts: Sequence[NDArray[np.float64]] = ()) -> Tuple[
        NDArray[np.float64], NDArray[np.float64], float]:
    """The shape, the linear coefficients and the residual sum: least squares from each of
    ``starts`` (default: the grid's best), the best kept; friction's signs then iterated."""
    fitted = [_fit_shape(problem, p0) for p0 in (starts or [_start(problem)])]
    psi = min(fitted, key=lambda p: float(np.sum(problem.solve(p)[1] ** 2)))
    if problem.shape.friction:
        for _ in range(12):
            coef, _r = problem.solve(psi)
            if not problem.update_signs(psi, coef):
                break
            psi = _fit_shape(problem, psi)
    coef, r = problem.solve(psi)
    return psi, coef, float(r @ r)


@dataclasses.dataclass
class _Fitted:
    """One delay's fit: the model of the fit's samples as a function of all its parameters
    (the first n_phi are _physical's phi), the parameters found, the residual sum."""
    problem: _Problem
    model: Callable[[NDArray[np.float64]], NDArray[np.float64]]
    params: NDArray[np.float64]
    n_phi: int
    rss: float
    at_bound: Tuple[int, ...] = ()


def _fit_delay(problem: _Problem, starts: Sequence[NDArray[np.float64]]) -> _Fitted:
    shape = problem.shape
    psi, coef, rss = _fit(problem, starts)
    n_phi = shape.n_psi + 1 + int(shape.friction)
    if shape.friction:
        params, model, rss = _refine_coulomb(problem, psi, coef)
    else:
        k = shape.n_psi

        def model(p: NDArray[np.float64]) -> NDArray[np.float64]:
            return problem.predict(p[:k], p[k:])

        params = np.concatenate([psi, coef])
    at_bound = (0,) if min(abs(params[0] - edge) for edge in _LOG_AT_BOUNDS) < 1e-6 else ()
    return _Fitted(problem, model, params, n_phi, rss, at_bound)


# ---- parameters and their covariance --------------------------------------------------------


def _physical(shape: _Shape, T: float, phi: NDArray[np.float64]) -> NDArray[np.float64]:
    """Fitted coordinates phi = (psi, g, [g F_c]) -> (log m, log b, [k], [log tau], [F_c]).
    In units of T the plant is x'' + (b T/m) x' + (k T^2/m) x = (T^2/m) (f - F_c sign x'), so
    a T = b T/m, w2 = k T^2/m and g = T^2/m."""
    la = phi[0]
    i = 1
    w2 = phi[i] if shape.spring else 0.0
    i += int(shape.spring)
    ltau = phi[i] if shape.lag else 0.0
    i += int(shape.lag)
    g = phi[i]
    log_m = 2.0 * math.log(T) - math.log(abs(g))
    m = math.exp(log_m)
    out = [log_m, la + log_m - math.log(T)]
    if shape.spring:
        out.append(w2 * m / T ** 2)
    if shape.lag:
        out.append(ltau + math.log(T))
    if shape.friction:
        out.append(phi[i + 1] / g)      # F_c = (T^2 F_c / m) / (T^2 / m)
    return np.array(out)


def _lag1_autocorrelation(r: NDArray[np.float64]) -> float:
    """The residual's lag-1 autocorrelation (0 for a constant residual)."""
    rc = r - r.mean()
    denom = float(rc @ rc)
    return float(rc[1:] @ rc[:-1]) / denom if denom > 0.0 else 0.0


def _newey_west(J: NDArray[np.float64], r: NDArray[np.float64]) -> NDArray[np.float64]:
    """The Newey-West meat with Bartlett weights over Andrews' (1991) automatic bandwidth
    for an AR(1) residual, 1.1447 (alpha n)^(1/3), alpha = 4 rho^2 / (1 - rho^2)^2, at least
    4 (n/100)^(2/9) and at most n/4: a slowly varying residual (the quantization of slow
    motion is one) gets the long window it needs."""
    n = r.size
    rho = min(0.99, max(0.0, _lag1_autocorrelation(r)))
    alpha = 4.0 * rho * rho / (1.0 - rho * rho) ** 2
    lags = max(1, int(math.ceil(4.0 * (n / 100.0) ** (2.0 / 9.0))), int(math.ceil(1.1447 * (alpha * n) ** (1 / 3))))
    lags = min(lags, max(1, n // 4))
    G = J * r[:, None]
    S = G.T @ G
    for L in range(1, lags + 1):
        w = 1.0 - L / (lags + 1.0)
        C = G[L:].T @ G[:-L]
        S += w * (C + C.T)
    return S


def _covariance(model: Callable[[NDArray[np.float64]], NDArray[np.float64]], params: NDArray[np.float64],
                n_phi: int, y: NDArray[np.float64], mask: NDArray[np.bool_], shape: _Shape,
                T: float, at_bound: Sequence[int] = ()) -> Tuple[NDArray[np.float64], NDArray[np.float64], int]:
    """Covariance of the physical coordinates, their values, and the degrees of freedom.
    ``model(params)`` is the position on the fit's samples; the first ``n_phi`` params are
    the fitted coordinates phi of :func:`_physical`, the rest nuisances (initial state,
    unknown commands).  A physical parameter that depends on an undetermined direction or on
    a phi the search left on its bound (``at_bound``) gets an infinite variance."""
    y_hat = model(params)
    cols = []
    for j in range(params.size):     # central differences (exact for the linear coefficients)
        h = 1e-6 * max(1.0, abs(params[j]))
        dp = np.zeros_like(params)
        dp[j] = h
        cols.append((model(params + dp) - model(params - dp)) / (2.0 * h))
    J = np.column_stack(cols)[mask]
    r = y[mask] - y_hat[mask]
    n, p = J.shape
    dof = n - p
    # the inverse through the SVD of the column-scaled Jacobian: a direction the log does not
    # determine (a tiny singular value) gives its parameters an infinite variance, where a
    # pseudo-inverse would give them none
    norms = np.sqrt(np.sum(J * J, axis=0))
    norms[norms == 0.0] = 1.0
    _, S, Vt = np.linalg.svd(J / norms, full_matrices=False)
    keep = S > UNDETERMINED_SINGULAR * S[0]
    JtJ_inv = ((Vt[keep].T / S[keep] ** 2) @ Vt[keep]) / np.outer(norms, norms)
    k = n_phi
    undetermined = set(j for j in range(k) for i in np.flatnonzero(~keep) if abs(Vt[i, j]) > 1e-6)
    undetermined.update(j for j in at_bound if j < k)
    classical = JtJ_inv * float(r @ r) / max(dof, 1)
    robust = JtJ_inv @ _newey_west(J, r) @ JtJ_inv
    phi = params[:k]
    # the larger of the two per parameter: the robust correlations scaled by the larger SDs
    sd = np.sqrt(np.maximum(np.diag(classical)[:k], np.diag(robust)[:k]))
    base = robust[:k, :k]
    d = np.sqrt(np.maximum(np.diag(base), 1e-300))
    cov_phi = base / np.outer(d, d) * np.outer(sd, sd)
    values = _physical(shape, T, phi)
    D = np.empty((values.size, k))     # Jacobian of the transform (delta method)
    for j in range(k):
        h = 1e-7 * max(1.0, abs(phi[j]))
        dp = np.zeros(k)
        dp[j] = h
        D[:, j] = (_physical(shape, T, phi + dp) - _physical(shape, T, phi - dp)) / (2.0 * h)
    cov = D @ cov_phi @ D.T
    for i in range(values.size):
        if any(D[i, j] != 0.0 for j in undetermined):
            cov[i, :] = cov[:, i] = 0.0
            cov[i, i] = math.inf
    return cov, values, dof


def _phi1(z: float) -> float:
    """(e^z - 1)/z, accurate near 0."""
    return math.expm1(z) / z if z != 0.0 else 1.0


def _phi2(z: float) -> float:
    """(e^z - 1 - z)/z^2, accurate near 0."""
    if abs(z) < 1e-3:
        return 0.5 + z / 6.0 + z * z / 24.0
    return (math.expm1(z) - z) / (z * z)


def _coulomb_positions(a: float, g: float, gF: float, x: float, v: float,
                       w: NDArray[np.float64]) -> NDArray[np.float64]:
    """The exact sampled positions of x'' + a x' = g f - gF sign(x') with sticking (at rest
    while |g f| <= gF), f = w[j] held over sample j, time in units of T: per sample at most
    two exponential pieces, the velocity's zero crossing found in closed form."""
    out = np.empty(w.size)
    for j in range(w.size):
        out[j] = x
        gf = g * float(w[j])
        t = 1.0
        if v == 0.0:
            if abs(gf) <= gF:
                continue
            s = 1.0 if gf > 0.0 else -1.0
        else:
            s = 1.0 if v > 0.0 else -1.0
        c = gf - s * gF                      # the acceleration the forces give (v' = c - a v)
        if c * s < 0.0:                      # decelerating: does v reach 0 within the sample?
            z = a * v / -c
            t_zero = (v / -c) * (math.log1p(z) / z if z != 0.0 else 1.0)
            if t_zero < t:
                x += v * t_zero * _phi1(-a * t_zero) + c * t_zero * t_zero * _phi2(-a * t_zero)
                v = 0.0
                t -= t_zero
                if abs(gf) <= gF:
                    continue
                s = 1.0 if gf > 0.0 else -1.0
                c = gf - s * gF
        e = -a * t
        x += v * t * _phi1(e) + c * t * t * _phi2(e)
        v = v * math.exp(e) + c * t * _phi1(e)
    return out


def _refine_coulomb(problem: _Problem, psi: NDArray[np.float64],
                    coef: NDArray[np.float64]) -> Tuple[NDArray[np.float64], Callable[[NDArray[np.float64]],
                                                                                           NDArray[np.float64]], float]:
    """The friction fit with sticking, exactly (no lag, no spring), from the sign-iterated one:
    params (log a T, g, g F_c, x0, v0); returns them, the model and the residual sum."""
    from scipy.optimize import least_squares

    def model(p: NDArray[np.float64]) -> NDArray[np.float64]:
        return _coulomb_positions(math.exp(p[0]), p[1], p[2], p[3], p[4], problem.w)

    def residual(p: NDArray[np.float64]) -> NDArray[np.float64]:
        out: NDArray[np.float64] = (problem.y - model(p))[problem.mask]
        return out

    # the linear fit's initial state is (x0, x0') in units of T: the same coordinates
    p0 = np.array([psi[0], coef[0], max(coef[1], 0.0), coef[2], coef[3]])
    lo = np.array([_LOG_AT_BOUNDS[0], 0.0, 0.0, -np.inf, -np.inf])
    hi = np.array([_LOG_AT_BOUNDS[1], np.inf, np.inf, np.inf, np.inf])
    res = least_squares(residual, np.clip(p0, lo, hi), bounds=(lo, hi), method="trf", x_scale="jac",
                        xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=200)
    r = residual(res.x)
    return np.asarray(res.x, dtype=np.float64), model, float(r @ r)


# ---- the entry point --------------------------------------------------------------------------


def identify(position: ArrayLike, command: ArrayLike, T: Optional[float] = None, *,
             time: Optional[ArrayLike] = None, index: Optional[ArrayLike] = None,
             counts_per_unit: Optional[float] = None, force_constant: float = 1.0,
             force_limit: Optional[float] = None, max_delay: int = 3, delay: Optional[int] = None,
             lag: Union[bool, str] = False, friction: bool = False, spring: bool = False,
             level: float = DEFAULT_LEVEL, rotary: bool = False,
             progress: Union[bool, Callable[[str], None]] = False) -> Identification:
    """Fit m (J), b, the delay and, when asked, the lag tau, Coulomb friction and a spring k
    to a log of the command and the measured position (module docstring for the model).

    position: measured position (m or rad), or encoder counts with ``counts_per_unit``;
    command: what the firmware commanded each tick, force (N, N m) or current times
    ``force_constant``; T: sampling period [s] (or read from ``time``, in s; ``index``: the
    sample numbers).  Missing samples (gaps in time or index) are left out, repeated ones
    dropped.  ``force_limit``: the drive's force ceiling; a log that sits at it is refused.
    delay: fix the delay instead of choosing it among 0..``max_delay``.  lag: True fits a lag
    tau assumed faster than the mechanics (tau <= m/b, as a current loop is); "either" drops
    that assumption (the model is symmetric in tau and m/b, so m is then often not
    identified: both solutions fit).  level: each
    interval's confidence level.  progress: True prints a line per delay fitted to stderr
    (or a callable takes the lines).  Raises IdentifyError naming the column and the reason."""
    if not 0.0 < level < 1.0:
        raise IdentifyError(f"level: must be in (0, 1), got {level!r}", "level")
    if not (math.isfinite(force_constant) and force_constant > 0.0):
        raise IdentifyError(f"force_constant: must be > 0 and finite, got {force_constant!r}", "force_constant")
    if counts_per_unit is not None and not (math.isfinite(counts_per_unit) and counts_per_unit > 0.0):
        raise IdentifyError(f"counts_per_unit: must be > 0 and finite, got {counts_per_unit!r}", "counts_per_unit")
    if delay is not None:
        if not 0 <= int(delay) <= MAX_DELAY:
            raise IdentifyError(f"delay: must be in 0..{MAX_DELAY}, got {delay!r}", "delay")
        delays = [int(delay)]
    else:
        if not 0 <= int(max_delay) <= MAX_DELAY:
            raise IdentifyError(f"max_delay: must be in 0..{MAX_DELAY}, got {max_delay!r}", "max_delay")
        delays = list(range(int(max_delay) + 1))
    y = _column(position, "position")
    u = _column(command, "command")
    if u.size != y.size:
        raise IdentifyError(f"command: {u.size} samples, position has {y.size}", "command")
    t = None if time is None else _column(time, "time")
    ix = None if index is None else _column(index, "index")
    for name, col in (("time", t), ("index", ix)):
        if col is not None and col.size != y.size:
            raise IdentifyError(f"{name}: {col.size} samples, position has {y.size}", name)
    if lag not in (False, True, "either"):
        raise IdentifyError(f"lag: must be False, True or 'either', got {lag!r}", "lag")
    shape = _Shape(spring=bool(spring), lag=bool(lag), friction=bool(friction))
    need = max(MIN_SAMPLES, 20 * (shape.n_psi + shape.n_states + 1 + int(shape.friction)))
    if y.size < need + max(delays):
        raise IdentifyError(f"position: {y.size} samples is too short a log for this model (needs at least "
                            f"{need + max(delays)})", "position")
    u = u * float(force_constant)
    if force_limit is not None:
        at = int(np.count_nonzero(np.abs(u) >= float(force_limit)))
        if at > 0.01 * u.size:
            raise IdentifyError(f"command: {at} samples at or above the force limit {force_limit:g}: the plant got "
                                f"less than the log says (lower the excitation's amplitude)", "command")
    if np.ptp(u) == 0.0:
        raise IdentifyError("command: constant over the log: it excites nothing (m and b need a changing force; "
                            "play steps, a chirp or a PRBS: zwidth.identify.excitation)", "command")
    log = _regularize(u, y, t, ix, None if T is None else float(T))
    q = 0.0
    if counts_per_unit is not None:
        log.y = log.y / float(counts_per_unit)
        q = 1.0 / float(counts_per_unit)
    Tf = log.T
    yp = log.y[log.present]
    if np.ptp(yp) == 0.0:
        raise IdentifyError("position: constant over the log: the plant did not move (is the output on? "
                            "raise the amplitude)", "position")
    # the fit works in units of T and of the position's spread, so every scale is O(1)
    scale = float(np.std(yp)) or 1.0
    log.y = log.y / scale
    start = max(delays)
    if shape.friction and (shape.lag or shape.spring):
        raise IdentifyError("friction: fitted on the plant without a lag or a spring only (its exact model with "
                            "sticking); drop lag= / spring=, or friction=", "friction")
    if shape.friction and not log.present.all():
        raise IdentifyError("time: friction is not fitted on a log with missing samples (their unknown commands "
                            "would decide where the device sticks)", "time")
    say = progress if callable(progress) else (_stderr if progress else None)
    fits: Dict[int, List[_Fitted]] = {}
    grid_start: List[NDArray[np.float64]] = []
    for d in delays:
        problem = _Problem(log, shape, d, start)
        # the grid once (a delay moves the best shape little), then from it and from the
        # previous delay's optimum
        grid_start = grid_start or [_start(problem)]
        previous = [fits[d - 1][0].params[:shape.n_psi]] if d - 1 in fits else []
        fits[d] = [_fit_delay(problem, grid_start + previous)]
        if shape.lag:
            # 1/(s (m s + b)(tau s + 1)) is symmetric in m/b and tau: fit the mirrored
            # solution too, so that a log that cannot tell them apart says so
            psi = fits[d][0].params[:shape.n_psi].copy()
            psi[0], psi[-1] = -psi[-1], -psi[0]
            fits[d].append(_fit_delay(problem, [psi]))
        if say is not None:
            say(f"zwidth identify: delay {d}: residual RMS "
                f"{math.sqrt(min(f.rss for f in fits[d]) / max(1, int(problem.mask.sum()))) * scale:.4g}")
    candidates = [(d, f) for d in delays for f in fits[d] if lag == "either" or not shape.lag or _lag_faster(f)]
    candidates = [c for c in candidates if c[1].params[shape.n_psi] > 0.0]   # 1/m > 0
    if not candidates:
        raise IdentifyError("position: the fitted plant moves against the command (1/m < 0): is the command's "
                            "or the position's sign reversed?", "position")
    best, chosen = min(candidates, key=lambda c: c[1].rss)
    problem, rss = chosen.problem, chosen.rss
    names = ["J" if rotary else "m", "b"] + ["k"] * shape.spring + ["tau"] * shape.lag + ["F_c"] * shape.friction
    units = (["kg m^2", "N m s/rad"] if rotary else ["kg", "N s/m"]) + \
        [("N m/rad" if rotary else "N/m")] * shape.spring + ["s"] * shape.lag + [("N m" if rotary else "N")] * shape.friction
    n_fit = int(problem.mask.sum())
    # every fit the log cannot reject against the best (F statistic of its extra residual
    # within PLAUSIBLE_F): its delay and its parameters stay possible
    plausible: List[Tuple[int, NDArray[np.float64], NDArray[np.float64], int]] = []
    # a correlated residual holds fewer independent samples: with lag-1 autocorrelation rho
    # (AR(1)) about n (1 - rho)/(1 + rho), and the F statistic shrinks with it (a noise-free
    # encoder log's rounding is such a residual; counting every sample rejected true delays)
    r_best = (problem.y - chosen.model(chosen.params))[problem.mask]
    rho = max(0.0, min(0.99, _lag1_autocorrelation(r_best)))
    effective = (1.0 - rho) / (1.0 + rho)
    for d, f in sorted(candidates, key=lambda c: c[1].rss):
        F = effective * (f.rss - rss) / max(rss / max(n_fit - 1, 1), 1e-300)
        if F <= PLAUSIBLE_F and f.params[shape.n_psi] > 0.0:
            cov_f, values_f, dof_f = _physical_covariance(f, shape, Tf, scale, names)
            plausible.append((d, values_f, cov_f, dof_f))
    _, values, cov, dof = plausible[0]
    estimates: Dict[str, Estimate] = {}
    warnings = list(log.warnings)
    for i, (name, unit) in enumerate(zip(names, units)):
        log_coord = name in _LOG_COORDINATES
        ivs = [_interval((v[i], log_coord), c, i, level, dof_c) for _, v, c, dof_c in plausible]
        lo, hi = min(a for a, _ in ivs), max(b for _, b in ivs)
        value = math.exp(values[i]) if log_coord else values[i]
        se = math.sqrt(max(cov[i, i], 0.0))
        if log_coord:
            half = 0.5 * (math.log(hi) - math.log(lo)) if lo > 0.0 and math.isfinite(hi) else math.inf
        else:
            half = 0.5 * (hi - lo) / max(abs(value), 1e-300)
        estimates[name] = Estimate(name, value, lo, hi, level, se, bool(half <= MAX_RELATIVE_HALF_WIDTH), unit)
    for e in estimates.values():
        if not e.identified:
            warnings.append(f"{e.name} is not identified by this log: its interval spans more than "
                            f"+-{100 * MAX_RELATIVE_HALF_WIDTH:g} % (excite longer, stronger, or nearer the corner "
                            f"frequency b/(2 pi m))")
    other = sorted({d for d, *_ in plausible} - {best})
    if other:
        warnings.append(f"the delay is not clear: {', '.join(map(str, other))} samples fit the log as well as "
                        f"{best}; the intervals cover every fit the log allows, and the box takes the largest "
                        f"delay, {max(other + [best])}")
    if shape.lag and len(plausible) > len({d for d, *_ in plausible}):
        warnings.append("the lag and the mechanical time constant m/b cannot be told apart by this log (the "
                        "model is symmetric in them): the intervals cover both solutions")
    elif shape.lag and lag is True:
        warnings.append(f"the lag is taken as the faster time constant (tau <= m/b: the model is symmetric in "
                        f"them; lag='either' drops the assumption)")
    fitted = np.full(log.y.size, np.nan)
    fitted[start:] = chosen.model(chosen.params)
    fitted *= scale
    measured: NDArray[np.float64] = log.y * scale
    fit = _fit_check(measured[start:][problem.mask], fitted[start:][problem.mask], q)
    if fit.ok and not (shape.friction or shape.lag or shape.spring) and log.present.all():
        fit = _friction_probe(log, best, start, chosen, dof, fit, scale)
    fitted[:start] = np.nan
    return Identification(estimates, best, {d: min(f.rss for f in fs) * scale ** 2 for d, fs in fits.items()}, fit,
                          tuple(warnings), Tf, n_fit, bool(rotary), dof,
                          np.arange(log.y.size, dtype=np.float64) * Tf, measured, fitted,
                          log.u, cov, tuple(plausible))


def _lag_faster(f: _Fitted) -> bool:
    """Is the fit's lag tau at most the mechanical time constant m/b (psi: log(b T/m) first,
    log(tau/T) last)?"""
    return float(f.params[0]) + float(f.params[f.problem.shape.n_psi - 1]) <= 0.0


def _physical_covariance(f: _Fitted, shape: _Shape, T: float, scale: float,
                         names: Sequence[str]) -> Tuple[NDArray[np.float64], NDArray[np.float64], int]:
    """A fit's physical values (log m, log b, [k], [log tau], [F_c]) and their covariance,
    in the log's units, with the floor of MIN_RELATIVE_SE."""
    problem = f.problem
    cov, values, dof = _covariance(f.model, f.params, f.n_phi, problem.y, problem.mask, shape, T, f.at_bound)
    # the position was divided by `scale`, so the fitted g is T^2/(m scale): m, b and k carry
    # 1/scale (log m, log b shift; k scales); F_c = g F_c / g and tau do not
    values[0] -= math.log(scale)
    values[1] -= math.log(scale)
    if shape.spring:
        values[2] /= scale
        cov[2, :] /= scale
        cov[:, 2] /= scale
    # no interval narrower than the log's own precision: a drive logs binary32 (6e-8
    # relative) and the model is computed to about 1e-11, so below MIN_RELATIVE_SE a
    # near-noiseless log would claim more than either holds
    for i, name in enumerate(names):
        scale_i = 1.0 if name in _LOG_COORDINATES else abs(values[i])
        cov[i, i] = max(cov[i, i], (MIN_RELATIVE_SE * scale_i) ** 2)
    return cov, values, dof


def _t(level: float, dof: int) -> float:
    from scipy import stats
    return float(stats.t.ppf(0.5 + 0.5 * level, max(dof, 1)))


def _stderr(line: str) -> None:
    import sys
    print(line, file=sys.stderr, flush=True)


def _fit_check(y: NDArray[np.float64], y_hat: NDArray[np.float64], q: float) -> FitCheck:
    r = y - y_hat
    rms = float(np.sqrt(np.mean(r ** 2)))
    floor = q / math.sqrt(12.0)
    rho1 = _lag1_autocorrelation(r)
    motion = float(np.var(y))
    explained = 1.0 - float(np.mean(r ** 2)) / motion if motion > 0 else 0.0
    # a residual at the arithmetic's own level (a noise-free simulated log) is no misfit
    exact = rms <= 1e-9 * math.sqrt(motion) if motion > 0 else True
    if rho1 > MISFIT_RHO and rms > MISFIT_FLOOR_RATIO * max(floor, 1e-300) and not exact:
        return FitCheck(rms, floor, rho1, explained, False,
                        "the model does not fit: the residual is slow and well above the noise (a resonance, "
                        "backlash, sticking friction, a spring not fitted, or the wrong T)")
    return FitCheck(rms, floor, rho1, explained, True, "the model fits")


def _friction_probe(log: _Log, delay: int, start: int, plain: _Fitted, dof: int, fit: FitCheck,
                    scale: float) -> FitCheck:
    """Fitted without friction, is there friction the model misses?  Coulomb friction left
    out reads as extra damping, so b comes out high and the box certifies gains the device
    cannot hold.  The sign-iterated friction fit at the delay found; a residual drop with an
    F statistic above FRICTION_F says the log has friction, and the fit is not ok."""
    problem = _Problem(log, _Shape(spring=False, lag=False, friction=True), delay, start)
    psi, coef, rss = _fit(problem)
    F = (plain.rss - rss) / max(rss / max(dof - 1, 1), 1e-300)
    if coef[1] > 0.0 and F > FRICTION_F:
        fc = coef[1] / coef[0]
        return dataclasses.replace(fit, ok=False, reason=(
            f"the log has Coulomb friction the model leaves out (about {fc:.3g} N or N m; F = {F:.3g}): "
            f"without it b reads high; fit with friction (--friction)"))
    return fit


# ---- excitations ----------------------------------------------------------------------------


def excitation(kind: str, T: float, duration: float, amplitude: float, *, hold: int = 1,
               f_lo: Optional[float] = None, f_hi: Optional[float] = None, seed: int = 0) -> NDArray[np.float64]:
    """A command to identify with, one value per sample: "prbs" (a +-amplitude pseudo-random
    binary sequence, each level held ``hold`` samples, zero mean over its period), "chirp"
    (a sine sweeping f_lo..f_hi Hz, log-spaced) or "steps" (forward and back: +A, -A, -A, +A,
    so the device returns near where it started)."""
    if not (math.isfinite(T) and T > 0 and math.isfinite(duration) and duration >= 10 * T):
        raise ValueError(f"zwidth.identify.excitation: need T > 0 and duration >= 10 T, got T={T!r}, "
                         f"duration={duration!r}")
    if not (math.isfinite(amplitude) and amplitude > 0):
        raise ValueError(f"zwidth.identify.excitation: amplitude must be > 0, got {amplitude!r}")
    n = int(round(duration / T))
    if kind == "prbs":
        if hold < 1:
            raise ValueError(f"zwidth.identify.excitation: hold must be >= 1, got {hold!r}")
        rng = np.random.default_rng(seed)
        levels = rng.choice([-1.0, 1.0], size=(n + hold - 1) // hold)
        out: NDArray[np.float64] = amplitude * np.repeat(levels, hold)[:n]
        return out
    if kind == "chirp":
        lo = f_lo if f_lo is not None else 1.0 / duration
        hi = f_hi if f_hi is not None else 0.1 / T
        if not 0 < lo < hi <= 0.5 / T:
            raise ValueError(f"zwidth.identify.excitation: need 0 < f_lo < f_hi <= 1/(2T), got {lo!r}, {hi!r}")
        t = np.arange(n) * T
        k = math.log(hi / lo) / duration
        sweep: NDArray[np.float64] = amplitude * np.sin(2 * math.pi * lo * (np.exp(k * t) - 1.0) / k)
        return sweep
    if kind == "steps":
        quarter = max(1, n // 4)
        pattern = np.concatenate([np.full(quarter, 1.0), np.full(2 * quarter, -1.0), np.full(n - 3 * quarter, 1.0)])
        return amplitude * pattern
    raise ValueError(f"zwidth.identify.excitation: kind must be 'prbs', 'chirp' or 'steps', got {kind!r}")


