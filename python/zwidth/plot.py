# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Figures of the stability region and its extremes (matplotlib, optional extra "plot").

    region(delta)        the region in the (beta, alpha) plane, paper Figs. 3-5, 18
    extremes()           alpha_mmax, beta_mmax and their ratios against delta, Figs. 8-10
    influence(device)    K_mmax and B_mmax against m, b and T around a plant, Figs. 11-12
    device(device, K, B) a plant's region in real units (K against B), with the advice
    simulation(sims)     simulated responses with their verdicts (Fig. 15); knobs: Fig. 23
    save(fig, path)      PNG, PDF, SVG, EPS or PS by suffix

Every number drawn comes from zwidth's functions (the C core); this module only samples
them on grids and draws.  matplotlib is imported when a function is called, so
``import zwidth.plot`` works without it; the functions then raise ImportError.  Each
returns the matplotlib Figure (created with pyplot, so ``plt.show()`` works; pass
``ax``/``fig`` to draw into your own).
"""
from __future__ import annotations

import dataclasses
import math
import textwrap
from pathlib import Path
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import NDArray

from . import (DELTA0, DELTA1, DELTA2, DELTA_B, DELTA_BB, DELTA_K1, DELTA_K2, alpha_max,
               corner, hyperbola_top, verdict)
from . import check as _check
from . import extremes as _extremes
from .device import Device
from .results import DeviceExtremes, Extremes, LoopVerdict, Verdict
from .scene import EFFECTS

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure, SubFigure

    from .box import PlantBox
    from .identify import Identification
    from .scene import Scene
    from .sim import Simulation, SimulationSet

__all__ = ["region", "loop_region", "extremes", "influence", "device", "simulation", "save",
           "CRITICAL_DELTAS", "FORMATS", "box_region", "plant_region", "device_region",
           "plant_influence", "identification"]

_INSTALL_HINT = "zwidth.plot needs matplotlib: pip install zwidth[plot]"

# Colours: exact region green (paper's dark green), legacy light green, passivity blue.
_EXACT_FILL = "#4caf50"
_EXACT_EDGE = "#1b5e20"
_LEGACY_FILL = "#dcedc8"
_LEGACY_EDGE = "#689f38"
_PASSIVITY_EDGE = "#1565c0"
_VERDICT_COLOURS = {"stable": "#2e7d32", "marginal": "#ef6c00", "unstable": "#c62828"}

#: The critical normalized dampings drawn by :func:`extremes`: (name, TeX label, value, meaning).
CRITICAL_DELTAS: Tuple[Tuple[str, str, float, str], ...] = (
    ("DELTA_K1", r"$\delta_{K1}$", DELTA_K1, r"local min of $\alpha_{mmax}/\delta$"),
    ("DELTA_B", r"$\delta_B$", DELTA_B, r"local min of $\beta_{mmax}/\delta$"),
    ("DELTA0", r"$\delta_0$", DELTA0, "the line starts to bite (legacy region unsafe above)"),
    ("DELTA_BB", r"$\delta_{BB}$", DELTA_BB, r"local min of $\beta_{mmax}$"),
    ("DELTA1", r"$\delta_1$", DELTA1, r"$\alpha_{mmax}$ moves from the hyperbola's top to the corner"),
    ("DELTA2", r"$\delta_2$", DELTA2, r"$\beta$ at $\alpha_{mmax}$ turns negative"),
    ("DELTA_K2", r"$\delta_{K2}$", DELTA_K2, r"local max of $\alpha_{mmax}/\delta$"),
)
_CRITICAL_COLOURS = ("#8e24aa", "#00897b", "#e53935", "#6d4c41", "#fb8c00", "#3949ab", "#c0ca33")


# ---------------------------------------------------------------------------------------
# matplotlib access (lazy)
# ---------------------------------------------------------------------------------------


def _subplots(nrows: int = 1, ncols: int = 1, **kwargs: Any) -> Tuple["Figure", Any]:
    """pyplot.subplots, imported on first use (ImportError with the install hint)."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as exc:
        raise ImportError(_INSTALL_HINT) from exc
    fig, axes = plt.subplots(nrows, ncols, **kwargs)
    return fig, axes


def _axes_grid(fig: Optional["Figure"], nrows: int, ncols: int, figsize: Tuple[float, float],
               margins: Optional[Dict[str, float]] = None) -> Tuple["Figure", List["Axes"]]:
    """A new figure of nrows x ncols axes, or the given one cleared and refilled.  With
    ``margins`` (subplots_adjust's keywords) the layout is fixed instead of constrained:
    constrained layout of many log axes costs seconds per draw."""
    if fig is None:
        fig, _ = _subplots(nrows, ncols, figsize=figsize, layout=None if margins else "constrained")
    else:
        fig.clear()
        fig.subplots(nrows, ncols)
    if margins:
        fig.set_layout_engine("none")
        fig.subplots_adjust(**margins)
    return fig, list(fig.axes)


def _root(fig: Union["Figure", "SubFigure", None]) -> "Figure":
    """The top-level Figure of an Axes' (sub)figure."""
    from matplotlib.figure import Figure
    if fig is None:
        raise ValueError("zwidth.plot: the axes belong to no figure")
    return fig if isinstance(fig, Figure) else fig.figure  # a SubFigure's .figure is the root


def _own_axes(ax: Optional["Axes"], figsize: Tuple[float, float]) -> Tuple["Figure", "Axes"]:
    if ax is not None:
        return _root(ax.get_figure()), ax
    fig, new = _subplots(figsize=figsize, layout="constrained")
    return fig, new


def _proxy(**kwargs: Any) -> Any:
    """A legend handle for artists (contours, fills) that make none themselves."""
    from matplotlib.lines import Line2D
    return Line2D([], [], **kwargs)


def _tidy_log_axes(ax: "Axes") -> None:
    """Label only the decades of log axes (no "2x10^0, 3x10^0, ..." minor labels: they
    clutter narrow ranges and their mathtext made a figure take seconds to lay out);
    minor ticks stay, unlabelled."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter
    plain = FuncFormatter(lambda v, _: f"{v:g}")
    for axis, scale, limits in ((ax.xaxis, ax.get_xscale(), ax.get_xlim()),
                                (ax.yaxis, ax.get_yscale(), ax.get_ylim())):
        lo, hi = sorted(limits)
        if scale != "log" or lo <= 0.0:
            continue
        if hi / lo >= 100.0:
            axis.set_major_locator(LogLocator(base=10.0, numticks=8))
            axis.set_minor_locator(LogLocator(base=10.0, subs=[k / 10 for k in range(2, 10)], numticks=8))
            axis.set_minor_formatter(NullFormatter())
        else:  # under two decades: 1, 2, 5 per decade as plain numbers
            axis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0), numticks=12))
            axis.set_major_formatter(plain)
            axis.set_minor_locator(LogLocator(base=10.0, subs=[k / 10 for k in range(2, 10)], numticks=12))
            axis.set_minor_formatter(NullFormatter())


def _scalar(name: str, value: Any) -> float:
    if np.ndim(value) != 0:
        raise ValueError(f"zwidth.plot: {name} must be a scalar, got shape {np.shape(value)}")
    return float(value)


def _mark_verdict(ax: "Axes", x: float, y: float, v: Union[Verdict, LoopVerdict], what: str) -> List[Any]:
    """A diamond at (x, y) coloured by the verdict, labelled "what: verdict, deciding"."""
    word = v.word
    why = f", {v.deciding_name}" if word != "stable" and v.deciding_name else ""
    return list(ax.plot([x], [y], "D", color=_VERDICT_COLOURS[word], markeredgecolor="black",
                        markersize=9, zorder=9, linestyle="none", label=f"{what}: {word}{why}"))


# ---------------------------------------------------------------------------------------
# The region in the normalized plane
# ---------------------------------------------------------------------------------------


def _outline(ax: "Axes", delta: float, name: str, extent: Tuple[float, float, float, float],
             fill: Optional[str], edge: str, resolution: Tuple[int, int],
             inside_exact: Optional[Any] = None) -> float:
    """A comparison region's outline: contour of check(..., region=name) on a grid over the
    view.  Returns the share of the view's grid cells where it differs from the exact
    region (``inside_exact(bb, aa)``, else where it is inside), to tell whether it can be
    seen at all."""
    x0, x1, y0, y1 = extent
    betas = np.linspace(x0, x1, resolution[0])
    alphas = np.linspace(y0, y1, resolution[1])
    bb, aa = np.meshgrid(betas, alphas)
    inside = np.asarray(_check(delta, aa, bb, region=name), dtype=bool)
    differs = inside if inside_exact is None else inside != inside_exact(bb, aa)
    mask = inside.astype(float)
    if fill is not None:
        ax.contourf(bb, aa, mask, levels=[0.5, 1.5], colors=[fill], zorder=1)
    ax.contour(bb, aa, mask, levels=[0.5], colors=[edge], linestyles="--", linewidths=1.5,
               zorder=4)
    return float(differs.mean())


Point = Tuple[float, float]

#: An overlay covering less than this share of the view is not listed as drawn (it cannot
#: be seen); the legend says so instead.
_VISIBLE_SHARE = 2e-3


def _legend_outside(ax: "Axes", handles: List[Any]) -> None:
    """The legend right of the axes, where it covers no curve or marker."""
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small",
              framealpha=0.9, borderaxespad=0.0)


def region(delta: float, *, overlays: Sequence[str] = ("legacy", "passivity"),
           point: Union[Point, Sequence[Point], None] = None, ax: Optional["Axes"] = None,
           resolution: Tuple[int, int] = (700, 500)) -> "Figure":
    """The exact stability region at delta in the (beta, alpha) plane (paper Figs. 3-5, 18).

    x = beta = B T/m (normalized virtual damping), y = alpha = K T^2/m (normalized virtual
    stiffness).  The exact boundary is ``zwidth.alpha_max(delta, beta)`` over
    (-delta, beta_mmax), filled; the view is the exact region (and ``point``), whatever
    the overlays.  ``overlays`` draws comparison regions as dashed outlines, sampled with
    ``zwidth.check(..., region=name)`` on a ``resolution`` grid over the view: 'legacy'
    (Gil et al., no line; shaded light green where it claims more than the exact region;
    for delta > delta0 it reaches far beyond the view, which the legend says; for delta <=
    delta0 it is the exact region and not drawn) and 'passivity'; any other region name of
    ``zwidth.REGIONS`` works too.  An overlay too small to see is named in the legend as
    such.  Marked: alpha_mmax, the corner where line meets hyperbola (delta > delta0), and
    ``point`` = (beta, alpha) (or a list of such pairs), coloured by its exact verdict.  The
    legend sits right of the axes.  Returns the Figure (``ax``'s, if given).
    """
    delta = _scalar("delta", delta)
    ext = _extremes(delta)  # validates delta (ZwidthError)
    assert isinstance(ext, Extremes)  # the paper's loop (no loop keywords)
    top = hyperbola_top(delta, errors="mask")  # NaN where the legacy top overflows (delta ~ 1e300)
    cor = corner(delta, errors="mask")
    lo, hi = -delta, float(ext.beta_mmax)
    has_corner = math.isfinite(float(cor.alpha))

    # Boundary: alpha_max on a grid that contains the kinks, so the corner stays sharp.
    special = [float(ext.beta_at_alpha_mmax), float(top.beta)] + ([float(cor.beta)] if has_corner else [])
    betas = np.unique(np.concatenate([np.linspace(lo, hi, 2001),
                                      [b for b in special if lo < b < hi]]))
    alphas = np.asarray(alpha_max(delta, betas), dtype=float)

    # View: the exact region and the points.  The legacy region reaches beta ~ delta^2 and
    # alpha ~ delta^2 for large delta; following it would shrink the exact region to a
    # sliver, so it is clipped to the view (and the legend says how far it goes).
    x_lo, x_hi, y_hi = lo, hi, float(ext.alpha_mmax)
    points = [] if point is None else np.asarray(point, dtype=float).reshape(-1, 2).tolist()
    for pb, pa in points:
        x_lo, x_hi, y_hi = min(x_lo, pb), max(x_hi, pb), max(y_hi, pa)
    pad = 0.06 * (x_hi - x_lo)
    extent = (x_lo - pad, x_hi + pad, 0.0, 1.15 * y_hi)

    fig, ax = _own_axes(ax, (9.5, 5.2))
    handles: List[Any] = []
    ax.fill_between(betas, 0.0, alphas, color=_EXACT_FILL, alpha=0.75, linewidth=0, zorder=2)
    ax.plot(betas, alphas, color=_EXACT_EDGE, linewidth=2.0, zorder=5)
    handles.append(_proxy(color=_EXACT_EDGE, linewidth=6, alpha=0.75,
                          label="exact region (eq. (10))"))

    def exact(bb: Any, aa: Any) -> Any:
        return np.asarray(_check(delta, aa, bb), dtype=bool)

    for name in overlays:
        if name == "legacy" and delta <= DELTA0:
            handles.append(_proxy(color="none", label=r"legacy region = exact ($\delta \leq \delta_0$)"))
            continue
        if name == "legacy":
            share = _outline(ax, delta, "legacy", extent, _LEGACY_FILL, _LEGACY_EDGE, resolution, exact)
            label = "legacy region (no line; Gil et al.)"
            if not float(top.alpha) <= extent[3] or bool(_check(delta, 1e-9 * y_hi, extent[1], region="legacy")):
                label += "\n" + (rf"(reaches beyond the view, up to $\alpha$ = {float(top.alpha):.3g})"
                                  if math.isfinite(float(top.alpha)) else "(reaches far beyond the view)")
            edge = _LEGACY_EDGE
        elif name == "passivity":
            share = _outline(ax, delta, "passivity", extent, None, _PASSIVITY_EDGE, resolution)
            label, edge = "passivity (eq. (16))", _PASSIVITY_EDGE
        else:
            share = _outline(ax, delta, name, extent, None, "0.35", resolution)
            label, edge = f"'{name}' region", "0.35"
        if share < _VISIBLE_SHARE:
            handles.append(_proxy(color="none", label=f"{label.split(' (')[0]}: too small to see here"))
        else:
            handles.append(_proxy(color=edge, linestyle="--", label=label))

    where = "corner" if bool(ext.at_corner) else "hyperbola top"
    handles += ax.plot([float(ext.beta_at_alpha_mmax)], [float(ext.alpha_mmax)], "*", color="gold",
                       markeredgecolor="black", markersize=15, zorder=7, linestyle="none",
                       label=rf"$\alpha_{{mmax}}$ = {float(ext.alpha_mmax):.5g} at "
                             rf"$\beta$ = {float(ext.beta_at_alpha_mmax):.4g} ({where})")
    if has_corner:
        handles += ax.plot([float(cor.beta)], [float(cor.alpha)], "o", markerfacecolor="none",
                           markeredgecolor="black", markersize=20, markeredgewidth=1.5, zorder=8,
                           linestyle="none", label="corner: line meets hyperbola")
    for pb, pa in points:
        handles += _mark_verdict(ax, pb, pa, verdict(delta, pa, pb),
                                 rf"($\beta$, $\alpha$) = ({pb:.4g}, {pa:.4g})")

    ax.axvline(0.0, color="0.6", linewidth=0.8, zorder=0)
    ax.set_xlim(extent[0], extent[1])
    ax.set_ylim(extent[2], extent[3])
    ax.set_xlabel(r"$\beta = BT/m$ (normalized virtual damping)")
    ax.set_ylabel(r"$\alpha = KT^2/m$ (normalized virtual stiffness)")
    if delta > DELTA0:
        side = rf"$\delta$ > $\delta_0$ = {DELTA0:.4g}: the line bounds it on the right"
    else:
        side = rf"$\delta \leq \delta_0$ = {DELTA0:.4g}: hyperbola only (legacy region exact)"
    ax.set_title(rf"Stability region, $\delta = bT/m$ = {delta:.4g}" + "\n" + side)
    ax.grid(True, color="0.9", zorder=0)
    _legend_outside(ax, handles)
    return fig


# ---------------------------------------------------------------------------------------
# Extremes against delta
# ---------------------------------------------------------------------------------------


def _mark_criticals(ax: "Axes", lo: float, hi: float) -> None:
    for (_, _, value, _), colour in zip(CRITICAL_DELTAS, _CRITICAL_COLOURS):
        if lo <= value <= hi:
            ax.axvline(value, color=colour, linestyle=":", linewidth=1.2, zorder=1)


def _dot(ax: "Axes", x: float, y: float, colour: str) -> None:
    ax.plot([x], [y], "o", color=colour, markersize=5, zorder=6)


def _zoom(ax: "Axes", bounds: Tuple[float, float, float, float], lo: float, hi: float,
          values: Any, colour: str, dots: Sequence[str]) -> None:
    """An inset on delta in [lo, hi] (linear), for the small dips around delta0; ``dots``
    names the critical deltas (CRITICAL_DELTAS) to mark on the curve."""
    deltas = np.unique(np.concatenate([np.linspace(lo, hi, 400),
                                       [v for _, _, v, _ in CRITICAL_DELTAS if lo <= v <= hi]]))
    inset = ax.inset_axes(bounds)
    inset.plot(deltas, values(deltas), color=colour, linewidth=1.8)
    for name in dots:
        index = [entry[0] for entry in CRITICAL_DELTAS].index(name)
        d = CRITICAL_DELTAS[index][2]
        inset.axvline(d, color=_CRITICAL_COLOURS[index], linestyle=":", linewidth=1.2)
        _dot(inset, d, float(values(np.asarray(d))), _CRITICAL_COLOURS[index])
    inset.set_xlim(lo, hi)
    inset.tick_params(labelsize="x-small")
    inset.set_facecolor("#fafafa")


def extremes(delta_min: float = 1e-3, delta_max: float = 20.0, *,
             fig: Optional["Figure"] = None, points: int = 1500, mark: Optional[float] = None) -> "Figure":
    """The impedance extremes against delta (log axis; paper Figs. 8-10), six panels.

    (a) alpha_mmax and alpha with beta = 0 (proportional control, Fig. 9a);
    (b) alpha_mmax / delta = K_mmax / (b/T): its local min at delta_K1 and max at delta_K2
    make K_mmax go up-down-up in m; (c) beta at alpha_mmax and the normalized apparent
    damping beta + delta (Fig. 8b), negative beyond delta_2; (d) beta_mmax and beta_mmax +
    delta (Fig. 10), dipping after delta_0 to delta_BB; (e) beta_mmax / delta = B_mmax / b,
    local min at delta_B; (f) the ratio alpha_p_max / alpha_mmax (Fig. 9b).  The critical
    deltas of ``CRITICAL_DELTAS`` are dotted vertical lines, explained in the legend below.
    All values from ``zwidth.extremes``.  Draws into ``fig`` if given (it is cleared).
    ``mark``: a plant's delta, a solid black line in every panel (the range widened to hold it).
    """
    delta_min, delta_max = _scalar("delta_min", delta_min), _scalar("delta_max", delta_max)
    if mark is not None:
        mark = _scalar("mark", mark)
        if not 0.0 < mark < math.inf:
            raise ValueError(f"zwidth.plot.extremes: mark must be a delta > 0, got {mark!r}")
        delta_min, delta_max = min(delta_min, mark / 1.5), max(delta_max, mark * 1.5)
    if not (0.0 < delta_min < delta_max and math.isfinite(delta_max)):
        raise ValueError(f"zwidth.plot.extremes: need 0 < delta_min < delta_max < inf, "
                         f"got {delta_min!r}, {delta_max!r}")
    crit = [value for _, _, value, _ in CRITICAL_DELTAS if delta_min <= value <= delta_max]
    deltas = np.unique(np.concatenate([np.geomspace(delta_min, delta_max, points), crit]))
    ex = _extremes(deltas)
    a_max = np.asarray(ex.alpha_mmax, dtype=float)
    b_at = np.asarray(ex.beta_at_alpha_mmax, dtype=float)
    b_max = np.asarray(ex.beta_mmax, dtype=float)
    a_p = np.asarray(ex.alpha_p_max, dtype=float)

    fig, axes = _axes_grid(fig, 3, 2, (11.0, 11.5),
                           dict(left=0.07, right=0.98, top=0.94, bottom=0.16, wspace=0.22, hspace=0.32))
    ax_a, ax_ad, ax_bat, ax_b, ax_bd, ax_ratio = axes
    at = {name: _extremes(value) for name, _, value, _ in CRITICAL_DELTAS}

    ax_a.plot(deltas, a_max, color="C0", linewidth=2, label=r"$\alpha_{mmax}$ (impedance control)")
    ax_a.plot(deltas, a_p, color="C1", linestyle="--", linewidth=1.6,
              label=r"$\alpha_{p,max}$ ($\beta$ = 0, stiffness only)")
    ax_a.set_yscale("log")
    ax_a.set_ylabel(r"$\alpha = KT^2/m$")
    ax_a.set_title(r"(a) largest stable $\alpha$ (Figs. 8a, 9a)")

    ratio_k = a_max / deltas
    ax_ad.plot(deltas, ratio_k, color="C0", linewidth=2, label=r"$\alpha_{mmax}/\delta = K_{mmax}/(b/T)$")
    for name, colour in (("DELTA_K1", _CRITICAL_COLOURS[0]), ("DELTA_K2", _CRITICAL_COLOURS[6])):
        d = {n: v for n, _, v, _ in CRITICAL_DELTAS}[name]
        if delta_min <= d <= delta_max:
            _dot(ax_ad, d, float(at[name].alpha_mmax) / d, colour)
    tail = ratio_k[deltas >= min(0.3, delta_max / 2)]
    ax_ad.set_ylim(0.0, 1.6 * float(np.nanmax(tail)) if tail.size else None)
    ax_ad.set_ylabel(r"$\alpha_{mmax}/\delta$")
    ax_ad.set_title(r"(b) $K_{mmax}$ per $b/T$: up-down-up in $m$ (Eq. (35))")

    ax_bat.plot(deltas, b_at, color="C2", linewidth=2, label=r"$\beta$ at $\alpha_{mmax}$ (NVD)")
    ax_bat.plot(deltas, b_at + deltas, color="C3", linestyle="--", linewidth=1.6,
                label=r"$\beta + \delta$ at $\alpha_{mmax}$ (apparent damping)")
    ax_bat.axhline(0.0, color="0.5", linewidth=0.8)
    if delta_min <= DELTA2 <= delta_max:
        _dot(ax_bat, DELTA2, float(at["DELTA2"].beta_at_alpha_mmax), _CRITICAL_COLOURS[5])
    ax_bat.set_ylabel(r"$\beta = BT/m$")
    ax_bat.set_title(r"(c) damping at $\alpha_{mmax}$ (Fig. 8b)")

    ax_b.plot(deltas, b_max, color="C4", linewidth=2, label=r"$\beta_{mmax}$ (NVD; inset: the dip)")
    ax_b.plot(deltas, b_max + deltas, color="C5", linestyle="--", linewidth=1.6,
              label=r"$\beta_{mmax} + \delta$ (apparent damping)")
    if delta_min <= DELTA_BB <= delta_max:
        _dot(ax_b, DELTA_BB, float(at["DELTA_BB"].beta_mmax), _CRITICAL_COLOURS[3])
    if delta_min <= DELTA0 <= delta_max:
        _dot(ax_b, DELTA0, float(at["DELTA0"].beta_mmax), _CRITICAL_COLOURS[2])
    ax_b.set_yscale("log")
    if delta_min <= 1.5 and delta_max >= 4.5:
        _zoom(ax_b, (0.08, 0.50, 0.36, 0.36), 1.5, 4.5,
              lambda d: np.asarray(_extremes(d).beta_mmax, dtype=float), "C4", ["DELTA0", "DELTA_BB"])
    ax_b.set_ylabel(r"$\beta = BT/m$")
    ax_b.set_title(r"(d) largest stable $\beta$ ($\alpha \to 0^+$; Fig. 10)")

    ratio_b = b_max / deltas
    ax_bd.plot(deltas, ratio_b, color="C4", linewidth=2, label=r"$\beta_{mmax}/\delta = B_{mmax}/b$ (inset: turning points)")
    ax_bd.axhline(1.0, color="0.5", linewidth=0.8)
    if delta_min <= DELTA_B <= delta_max:
        _dot(ax_bd, DELTA_B, float(at["DELTA_B"].beta_mmax) / DELTA_B, _CRITICAL_COLOURS[1])
    if delta_min <= DELTA0 <= delta_max:
        _dot(ax_bd, DELTA0, float(at["DELTA0"].beta_mmax) / DELTA0, _CRITICAL_COLOURS[2])
    if delta_min <= 1.0 and delta_max >= 4.0:
        _zoom(ax_bd, (0.08, 0.14, 0.36, 0.36), 1.0, 4.0,
              lambda d: np.asarray(_extremes(d).beta_mmax, dtype=float) / d, "C4",
              ["DELTA_B", "DELTA0"])
    tail = ratio_b[deltas >= min(0.3, delta_max / 2)]
    ax_bd.set_ylim(0.0, 1.6 * float(np.nanmax(tail)) if tail.size else None)
    ax_bd.set_ylabel(r"$\beta_{mmax}/\delta$")
    ax_bd.set_title(r"(e) $B_{mmax}$ per $b$: falls, rises, falls in $T$ (Eq. (43))")

    ax_ratio.plot(deltas, a_p / a_max, color="C1", linewidth=2,
                  label=r"$\alpha_{p,max}/\alpha_{mmax}$")
    ax_ratio.set_ylim(0.0, 1.05)
    ax_ratio.set_ylabel("ratio")
    ax_ratio.set_title(r"(f) stiffness-only share of $\alpha_{mmax}$ (Fig. 9b)")

    # Legend corners chosen to clear the curves and the insets at the default range.
    corners: Tuple[Any, ...] = ("upper left", "upper right", "lower left", "lower right", "upper right", "upper left")
    for ax, where in zip(axes, corners):
        ax.set_xscale("log")
        _tidy_log_axes(ax)
        ax.set_xlim(delta_min, delta_max)
        _mark_criticals(ax, delta_min, delta_max)
        if mark is not None:
            ax.axvline(mark, color="black", linewidth=1.4, label=rf"your plant: $\delta$ = {mark:.4g}")
        ax.grid(True, which="major", color="0.9")
        ax.legend(loc=where, fontsize="small")
    for ax in axes[-2:]:
        ax.set_xlabel(r"$\delta = bT/m$")
    crit_handles = [_proxy(color=colour, linestyle=":", linewidth=1.5,
                           label=f"{label} = {value:.4g}: {meaning}")
                    for (_, label, value, meaning), colour in zip(CRITICAL_DELTAS, _CRITICAL_COLOURS)
                    if delta_min <= value <= delta_max]
    if crit_handles:
        fig.legend(handles=crit_handles, loc="lower center", ncols=2, fontsize="small",
                   title="critical normalized dampings", bbox_to_anchor=(0.5, 0.005))
    fig.suptitle("Impedance extremes against the normalized physical damping")
    return fig


# ---------------------------------------------------------------------------------------
# Real units: influence of m, b, T and a device's region
# ---------------------------------------------------------------------------------------


def _units(dev: Device) -> Dict[str, str]:
    """The Device's mass symbol and units, typeset for figures (kg m² for kg m^2)."""
    u = {k: v.replace("^2", "²") for k, v in dev.units.items()}
    return {"m": dev.mass_symbol, "m_unit": u["m"], "b_unit": u["b"], "K_unit": u["K"],
            "B_unit": u["B"]}


def _scalar_device(dev: Device, function: str) -> Tuple[float, float, float]:
    if np.ndim(dev.delta) != 0:
        raise ValueError(f"zwidth.plot.{function}: needs a scalar Device (one plant), "
                         f"got arrays of shape {np.shape(dev.delta)}")
    return float(dev.m), float(dev.b), float(dev.T)


def _sweep(value: float, marks: Sequence[float]) -> NDArray[np.float64]:
    """A log grid two decades either side of the plant, widened to hold every mark."""
    known = [v for v in [value, *marks] if math.isfinite(v) and v > 0.0]
    lo = min(known) / 3.0 if known else 1e-3
    hi = max(known) * 3.0 if known else 1.0
    if value > 0.0:
        lo, hi = min(lo, value / 100.0), max(hi, value * 100.0)
    else:
        lo = lo / 30.0  # b = 0: the plant is off the log axis; show the approach to it
    grid = np.geomspace(lo, hi, 600)
    return np.unique(np.concatenate([grid, [v for v in known if lo <= v <= hi]]))


def influence(device: Device, *, fig: Optional["Figure"] = None) -> "Figure":
    """K_mmax and B_mmax against m, b and T around a plant, real units (paper Figs. 11, 12).

    Each column sweeps one of m (or J), b, T over log grids around ``device`` (a scalar
    :class:`zwidth.Device`) with the other two held, via ``Device(array, b, T).extremes()``.
    Marked: the plant (red dot) and the critical values of ``device.influence()``: m_K2
    (local max of K_mmax), m_K1 (local min), m_K_match (where raising m catches up with
    m_K2's K_mmax), m_0 and m_B, b_0 and b_BB, T_B and T_0 (turning points of B_mmax).
    The advice is printed under the panels.  Draws into ``fig`` if given (cleared).
    """
    m, b, T = _scalar_device(device, "influence")
    rot = device.is_rotary
    u = _units(device)
    inf = device.influence()
    f = {k: float(v) for k, v in inf.as_dict().items() if k != "m"}

    fig, axes = _axes_grid(fig, 2, 3, (13.0, 7.8),
                           dict(left=0.06, right=0.99, top=0.93, bottom=0.15, wspace=0.27, hspace=0.3))

    m_marks = {"m_K2": f["m_K2"], "m_K1": f["m_K1"], "m_K_match": f["m_K_match"],
               "m_0": f["m_0"], "m_B": f["m_B"]}
    b_marks = {"b_0": f["b_0"], "b_BB": f["b_BB"]}
    t_marks = {"T_B": f["T_B"], "T_0": f["T_0"]}
    columns: List[Tuple[str, float, Dict[str, float], str, Dict[str, str]]] = [
        (u["m"], m, m_marks, u["m_unit"], {"K": "m_K2 m_K1 m_K_match", "B": "m_0 m_B"}),
        ("b", b, b_marks, u["b_unit"], {"K": "", "B": "b_0 b_BB"}),
        ("T", T, t_marks, "s", {"K": "", "B": "T_B T_0"}),
    ]
    styles = {"m_K2": "C1", "m_K1": "C2", "m_K_match": "C3", "m_0": "C4", "m_B": "C5",
              "b_0": "C4", "b_BB": "C5", "T_B": "C5", "T_0": "C4"}
    for col, (name, value, marks, unit, which) in enumerate(columns):
        grid = _sweep(value, list(marks.values()))
        plants = {0: Device(grid, b, T, rotary=rot), 1: Device(m, grid, T, rotary=rot),
                  2: Device(m, b, grid, rotary=rot)}[col]
        lim = plants.extremes()
        for row, (key, values, plant_value, limit_unit) in enumerate((
                ("K", np.asarray(lim.K_mmax, dtype=float), f["K_mmax"], u["K_unit"]),
                ("B", np.asarray(lim.B_mmax, dtype=float), f["B_mmax"], u["B_unit"]))):
            ax = axes[3 * row + col]
            ax.plot(grid, values, color="C0", linewidth=2, label=f"{key}_mmax")
            for mark in which[key].split():
                at = marks[mark]
                if math.isfinite(at) and at > 0.0:
                    shown = "J" + mark[1:] if rot and mark.startswith("m_") else mark
                    ax.axvline(at, color=styles[mark], linestyle="--", linewidth=1.2,
                               label=f"{shown} = {at:.4g}")
            if key == "K" and col == 0:  # the local max and min themselves
                for mark, level in (("m_K2", f["K_mmax_at_m_K2"]), ("m_K1", f["K_mmax_at_m_K1"])):
                    if marks[mark] > 0.0:
                        ax.plot([marks[mark]], [level], "o", color=styles[mark], markersize=6)
            if value > 0.0:
                ax.plot([value], [plant_value], "o", color="#c62828", markeredgecolor="black",
                        markersize=8, zorder=6, label=f"plant: {name} = {value:.4g}")
            else:
                ax.plot([], [], " ", label=f"plant: {name} = 0 (off the log axis)")
            ax.set_xscale("log")
            ax.set_yscale("log")
            _tidy_log_axes(ax)
            ax.set_xlabel(f"{name} [{unit}]")
            ax.set_ylabel(f"{key}_mmax [{limit_unit}]")
            ax.grid(True, which="major", color="0.9")
            ax.legend(loc="best", fontsize="x-small")
    held = f"{u['m']} = {m:.4g} {u['m_unit']}, b = {b:.4g} {u['b_unit']}, T = {T:.4g} s"
    fig.suptitle(f"Influence of {u['m']}, b and T on K_mmax and B_mmax around the plant "
                 f"{held} (δ = {float(device.delta):.4g})")
    fig.text(0.01, 0.005, "\n".join(textwrap.wrap(inf.trends + ". " + inf.advice, 170)),
             fontsize="small", va="bottom", ha="left")
    return fig


def device(device: Device, K: Optional[float] = None, B: Optional[float] = None, *,
           fig: Optional["Figure"] = None, overlays: Sequence[str] = ("legacy",),
           resolution: Tuple[int, int] = (500, 400)) -> "Figure":
    """A plant's stability region in real units, K against B (paper Fig. 20b).

    The boundary is ``device.k_max(B)`` over (B_mmin, B_mmax) = (-b, B_mmax), filled;
    marked are K_mmax (with the B at it), K_p_max (B = 0) and the B range as K -> 0+, all
    from ``device.extremes()``; ``overlays`` ('legacy', 'passivity', ...) as dashed grid
    contours of ``device.is_stable(..., region=name)``.  With K and B, the gain pair is
    marked, coloured by ``device.verdict``.  The advice of ``device.influence()`` is
    printed under the axes.  Draws into ``fig`` if given (cleared).
    """
    m, b, T = _scalar_device(device, "device")
    u = _units(device)
    if not device.loop.ideal:
        raise ValueError(f"zwidth.plot.device draws the paper's ideal loop; for a loop with "
                         f"{device.loop.describe()} use zwidth.plot.loop_region")
    lim = device.extremes()
    assert isinstance(lim, DeviceExtremes)
    lo, hi = float(lim.B_mmin), float(lim.B_mmax)
    bs = np.unique(np.concatenate([np.linspace(lo, hi, 2001), [float(lim.B_at_K_mmax), 0.0]]))
    bs = bs[(bs >= lo) & (bs <= hi)]
    ks = np.asarray(device.k_max(bs), dtype=float)

    fig, (ax,) = _axes_grid(fig, 1, 1, (9.8, 5.8))
    # View: the exact region and the gains; the legacy overlay (delta > delta0 only; it is
    # the exact region below) is clipped to it, as in region().
    x_lo, x_hi, y_hi = lo, hi, float(lim.K_mmax)
    legacy = "legacy" in overlays and float(device.delta) > DELTA0
    have_gains = K is not None and B is not None
    if have_gains:
        x_lo, x_hi, y_hi = min(x_lo, float(B)), max(x_hi, float(B)), max(y_hi, float(K))  # type: ignore[arg-type]
    pad = 0.06 * (x_hi - x_lo)
    x0, x1, y0, y1 = x_lo - pad, x_hi + pad, 0.0, 1.15 * y_hi

    handles: List[Any] = []
    ax.fill_between(bs, 0.0, ks, color=_EXACT_FILL, alpha=0.75, linewidth=0, zorder=2)
    ax.plot(bs, ks, color=_EXACT_EDGE, linewidth=2.0, zorder=5)
    handles.append(_proxy(color=_EXACT_EDGE, linewidth=6, alpha=0.75, label="stable (exact region)"))
    for name in overlays:
        if name == "legacy" and not legacy:
            handles.append(_proxy(color="none", label="legacy region = exact (δ ≤ δ0)"))
            continue
        bb, kk = np.meshgrid(np.linspace(x0, x1, resolution[0]), np.linspace(y0, y1, resolution[1]))
        inside = np.asarray(device.is_stable(kk, bb, region=name), dtype=bool)
        differs = inside != np.asarray(device.is_stable(kk, bb), dtype=bool) if name == "legacy" else inside
        mask = inside.astype(float)
        edge = {"legacy": _LEGACY_EDGE, "passivity": _PASSIVITY_EDGE}.get(name, "0.35")
        if name == "legacy":
            ax.contourf(bb, kk, mask, levels=[0.5, 1.5], colors=[_LEGACY_FILL], zorder=1)
        ax.contour(bb, kk, mask, levels=[0.5], colors=[edge], linestyles="--", linewidths=1.5, zorder=4)
        label = f"{name} region"
        if name == "legacy":
            top = hyperbola_top(device.delta, errors="mask")
            top_K = float(top.alpha) * m / T ** 2  # unit conversion of the legacy claim
            if not top_K <= y1 or bool(device.is_stable(1e-9 * y_hi, x1, region="legacy")):
                label += (f"\n(reaches beyond the view, up to K = {top_K:.3g})" if math.isfinite(top_K)
                          else "\n(reaches far beyond the view)")
        if float(differs.mean()) < _VISIBLE_SHARE:
            handles.append(_proxy(color="none", label=f"{name} region: too small to see here"))
        else:
            handles.append(_proxy(color=edge, linestyle="--", label=label))

    corner_word = "corner" if bool(lim.at_corner) else "hyperbola top"
    handles += ax.plot([float(lim.B_at_K_mmax)], [float(lim.K_mmax)], "*", color="gold",
                       markeredgecolor="black", markersize=15, zorder=7, linestyle="none",
                       label=f"K_mmax = {float(lim.K_mmax):.4g} at B = {float(lim.B_at_K_mmax):.4g} "
                             f"({corner_word})")
    handles += ax.plot([0.0], [float(lim.K_p_max)], "s", color="white", markeredgecolor="black",
                       markersize=7, zorder=7, linestyle="none",
                       label=f"K_p_max = {float(lim.K_p_max):.4g} (B = 0)")
    handles += ax.plot([lo, hi], [0.0, 0.0], "|", color="black", markersize=14, markeredgewidth=2,
                       zorder=7, linestyle="none",
                       label=f"B range ({lo + 0.0:.4g}, {hi:.4g}) as K -> 0+")
    if have_gains:
        kf, bf = float(K), float(B)  # type: ignore[arg-type]
        handles += _mark_verdict(ax, bf, kf, device.verdict(kf, bf), f"K = {kf:.4g}, B = {bf:.4g}")
    ax.axvline(0.0, color="0.6", linewidth=0.8, zorder=0)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_xlabel(f"B [{u['B_unit']}] (virtual damping)")
    ax.set_ylabel(f"K [{u['K_unit']}] (virtual stiffness)")
    ax.set_title(f"Stable gains for {u['m']} = {m:.4g} {u['m_unit']}, b = {b:.4g} {u['b_unit']}, "
                 f"T = {T:.4g} s\n(δ = bT/{u['m']} = {float(device.delta):.4g})")
    ax.grid(True, color="0.9", zorder=0)
    _legend_outside(ax, handles)
    advice = device.influence().advice
    fig.text(0.01, 0.005, "\n".join(textwrap.wrap("Advice: " + advice, 140)), fontsize="small",
             va="bottom", ha="left")
    fig.get_layout_engine().set(rect=(0.0, 0.07, 1.0, 0.93))  # type: ignore[union-attr, call-arg]
    return fig


# ---------------------------------------------------------------------------------------
# Simulations (zwidth.simulate): responses like paper Fig. 15, the knob like Fig. 23
# ---------------------------------------------------------------------------------------

_SIM_COLOURS = {"stable": "#2e7d32", "unstable": "#c62828", "undecided": "#ef6c00"}
_SHORT = {"stable": "S", "unstable": "US", "undecided": "?", "marginal": "M"}


def _case_title(sim: "Simulation", rotary: bool) -> str:
    """The case's label with its plant and gains (normalized when the gains are constant)."""
    norm = sim.case.normalized
    if norm is None:
        return sim.label
    d, a, b = norm
    return rf"{sim.label}: $\delta$={d:.4g}, $\alpha$={a:.4g}, $\beta$={b:.4g}"


def _verdict_lines(sim: "Simulation", legacy: Optional[bool]) -> Tuple[str, str]:
    """'simulated: unstable (US)' and, for linear cases, the analytic verdicts."""
    v = sim.verdict
    first = f"simulated: {v.outcome} ({_SHORT[v.outcome]})"
    if sim.analytic is None:
        return first, ""
    exact = sim.analytic.word
    second = f"exact: {exact}"
    if legacy is not None:
        second += f" · legacy: {'stable' if legacy else 'unstable'}"
    if sim.agrees is not None:
        second += " ✓" if sim.agrees else " ✗ disagree"
    return first, second


def _legacy_verdict(sim: "Simulation", rotary: bool) -> Optional[bool]:
    if sim.analytic is None or sim.ideal is not None or int(sim.params["effects"]):
        return None  # the legacy region is one of the ideal loop's
    p = sim.params
    dev = Device(p["m"], p["b"], p["T"], rotary=rotary)
    return bool(dev.is_stable(p["K"], p["B"], region="legacy"))


def _pretty(unit: str) -> str:
    """N*m*s/rad -> N m s/rad, kg*m^2 -> kg m²: units as the other figures write them."""
    return unit.replace("*", " ").replace("^2", "²")


def _position_scale(rotary: bool) -> Tuple[float, str]:
    """Factor and unit for drawing positions: degrees for a rotary plant."""
    return (180.0 / math.pi, "deg") if rotary else (1.0, "m")


def _response_panel(ax: "Axes", sim: "Simulation", scene: "Scene") -> None:
    p = sim.params
    scale, unit = _position_scale(scene.rotary)
    t, x = sim.t, sim.x * scale
    colour = _SIM_COLOURS[sim.verdict.outcome]
    ax.plot(t, x, color=colour, linewidth=1.3, label="x (position)")
    x_eq = np.where(t >= p["t_step"], p["x_eq_after"], p["x_eq_before"]) * scale
    if float(p["K"]) != 0.0 or "schedule" in scene.effects:  # without a spring it means nothing
        ax.plot(t, x_eq, color="0.45", linestyle="--", linewidth=1.0, label="equilibrium (reference)")
    marks = [float(p["x_eq_before"]), float(p["x_eq_after"]), float(p["x_init"])]
    effects = scene.effects
    if "wall" in effects:
        ax.axhline(p["wall_position"] * scale, color="#5d4037", linewidth=2.0, label="wall")
        marks.append(float(p["wall_position"]))
    if "hand_target" in sim.signals:
        ax.plot(t, sim.signals["hand_target"] * scale, color="0.5", linestyle=":", linewidth=1.2,
                label="the hand's intended position")
    if "hand" in effects:
        marks += [float(p["hand_from"]), float(p["hand_to"])]
    lo, hi = min(marks) * scale, max(marks) * scale
    finite = x[np.isfinite(x)]
    t_end = float(t[-1]) if len(t) > 1 else 1.0
    if finite.size and (scene.linear or sim.verdict.outcome != "stable"):
        # Unstable responses grow without bound (with effects too: a delay, quantization):
        # show the band around the step, as Fig. 15, and the time until the response leaves
        # it; stable linear ones until they settle.
        span = (hi - lo) or 1.0
        top, bottom = hi + 1.5 * span, lo - 1.5 * span
        outside = np.flatnonzero(~((x >= bottom) & (x <= top)))
        if outside.size:
            ax.set_ylim(bottom, top)
        if sim.verdict.outcome == "unstable" and outside.size:
            t_end = min(t_end, max(4.0 * float(t[outside[0]]), 40 * float(p["T"])))
        elif sim.verdict.outcome == "stable":
            moving = np.flatnonzero(np.abs(x - x_eq) > 0.01 * span)
            if moving.size:
                t_end = min(t_end, max(2.0 * float(t[moving[-1]]), 40 * float(p["T"])))
    ax.set_xlim(float(t[0]), t_end)
    ax.set_xlabel("t [s]")
    ax.set_ylabel(f"x [{unit}]")
    ax.grid(True, color="0.92")
    first, second = _verdict_lines(sim, _legacy_verdict(sim, scene.rotary))
    text = first + ("\n" + second if second else "")
    ax.text(0.98, 0.04, text, transform=ax.transAxes, ha="right", va="bottom", fontsize="small",
            color=colour, bbox=dict(boxstyle="round,pad=0.3", facecolor="white", edgecolor=colour,
                                    alpha=0.9))
    ax.set_title(_case_title(sim, scene.rotary), fontsize="medium")


def _force_panel(ax: "Axes", sim: "Simulation", scene: "Scene",
                 window: Optional[Tuple[float, float]] = None,
                 band: Optional[Tuple[float, float]] = None) -> None:
    """The forces; ``window``: the time span of the response panel above, ``band`` its
    position range: the forces of the samples shown there set the y range (an unstable
    run's forces reach 1e150 by the end; the rest is clipped like the position)."""
    unit = _pretty(sim.units["force"])
    ax.plot(sim.t, sim.force, color="C0", linewidth=1.2, label="force applied")
    names = {"force_command": "controller command", "wall_force": "wall", "hand_force": "hand",
             "friction": "friction"}
    for i, (name, text) in enumerate(names.items()):
        if name in sim.signals:
            ax.plot(sim.t, sim.signals[name], color=f"C{i + 1}", linewidth=1.0, label=text,
                    linestyle="--" if name == "force_command" else "-")
    if window is not None:
        ax.set_xlim(*window)
        shown = (sim.t >= window[0]) & (sim.t <= window[1])
        if band is not None:
            x = sim.x * _position_scale(scene.rotary)[0]
            within = (x >= band[0]) & (x <= band[1])
            first_out = np.flatnonzero(shown & ~within)
            if first_out.size:  # the forces until the position leaves the band
                shown &= np.arange(sim.t.size) <= first_out[0] + 2
        traces = [sim.force] + [sim.signals[n] for n in names if n in sim.signals]
        values = np.concatenate([np.asarray(tr)[shown] for tr in traces])
        values = values[np.isfinite(values)]
        if values.size:
            lo, hi = float(values.min()), float(values.max())
            pad = 0.08 * (hi - lo) or 1.0
            ax.set_ylim(lo - pad, hi + pad)
    ax.set_xlabel("t [s]")
    ax.set_ylabel(f"force [{unit}]")
    ax.grid(True, color="0.92")
    ax.legend(loc="best", fontsize="small")


def _knob_map(sim: "Simulation", positions: NDArray[np.float64]) -> NDArray[np.float64]:
    """The knob's planned stiffness at each position, from the C core's map (one sample
    of a knob-only run started there), so the drawing and the simulation share it."""
    from . import _core
    p = {k: v for k, v in sim.params.items() if k.startswith("knob_")}
    base = {"m": sim.params["m"], "b": sim.params["b"], "T": sim.params["T"],
            "effects": EFFECTS["knob"], **p}
    out = np.empty_like(positions)
    for i, x in enumerate(positions):
        out[i] = _core.Simulator({**base, "x_init": float(x)}).run(1, ["stiffness_planned"])["stiffness_planned"][0]
    return out


def _knob_panels(ax_k: "Axes", ax_x: "Axes", sim: "Simulation", scene: "Scene") -> None:
    p = sim.params
    scale, unit = _position_scale(scene.rotary)
    first, pitch, count = float(p["knob_first"]), float(p["knob_pitch"]), int(p["knob_count"])
    last = first + (count - 1) * pitch
    finite = sim.x[np.isfinite(sim.x)]
    lo = min(first - pitch / 2, float(finite.min()) if finite.size else first)
    hi = max(last + pitch / 2, float(finite.max()) if finite.size else last)
    grid = np.linspace(lo, hi, 3001)
    planned = _knob_map(sim, grid)
    k_unit = _pretty(sim.units["stiffness"])
    colour = _SIM_COLOURS[sim.verdict.outcome]
    ax_k.plot(grid * scale, planned, color="0.2", linewidth=2.0, drawstyle="steps-mid",
              label="planned (knob map)")
    rendered = sim.signals["stiffness"]
    # dots, not a line: consecutive samples are joined by nothing physical, and a line
    # between them draws a fan across the figure whenever the knob jumps
    ax_k.plot(sim.x * scale, rendered, color=colour, alpha=0.6, marker=".", markersize=3,
              linestyle="none", label="rendered: K used at each sample, at the true position")
    ax_k.set_xlabel(f"position [{unit}]")
    ax_k.set_ylabel(f"stiffness [{k_unit}]")
    ax_k.grid(True, color="0.92")
    ax_k.legend(loc="lower left", fontsize="small")
    ax_k.set_title(f"{sim.label}: planned and rendered stiffness (cf. paper Fig. 23)", fontsize="medium")

    ax_x.plot(sim.t, sim.x * scale, color=colour, linewidth=1.3, label="knob position")
    if "hand_target" in sim.signals:
        ax_x.plot(sim.t, sim.signals["hand_target"] * scale, color="0.5", linestyle=":",
                  linewidth=1.2, label="the hand's intended position")
    for i in range(count):
        ax_x.axhline((first + i * pitch) * scale, color="0.8", linewidth=0.8, zorder=0)
    ax_x.set_xlabel("t [s]")
    ax_x.set_ylabel(f"position [{unit}]")
    ax_x.grid(True, color="0.92", axis="x")
    ax_x.legend(loc="lower right", fontsize="small")
    text = (f"simulated: {sim.verdict.outcome}\nES {p['knob_k_end']:.4g}, IPS {p['knob_k_detent']:.4g} "
            f"{k_unit}, VD {p['knob_damping']:.4g} {_pretty(sim.units['damping'])}")
    ax_x.text(0.02, 0.97, text, transform=ax_x.transAxes, ha="left", va="top", fontsize="small",
              color=colour, bbox=dict(boxstyle="round,pad=0.3", facecolor="white", edgecolor=colour, alpha=0.9))
    ax_x.set_title(f"{sim.label}: time response", fontsize="medium")


def simulation(sims: "SimulationSet", *, fig: Optional["Figure"] = None,
               columns: Optional[int] = None) -> "Figure":
    """The responses of a simulated scene (:func:`zwidth.simulate`).

    One panel per case, position against time (paper Fig. 15), with the equilibrium's
    step dashed and a box giving the simulated verdict and, for linear scenes, the exact
    and legacy analytic verdicts (coloured: green stable, red unstable, orange undecided).
    Unstable responses of linear scenes are clipped to a band around the step.  A scene
    with one case also gets a panel of the forces (applied, controller command, wall,
    hand, friction).  A knob scene draws, per case, the planned stiffness against
    position (the knob map) with the stiffness rendered along the run (paper Fig. 23),
    and the time response with the detents.  ``columns``: panels per row (default up to
    4).  Draws into ``fig`` if given (cleared).
    """
    scene = sims.scene
    n = len(sims)
    if n == 0:
        raise ValueError("zwidth.plot.simulation: no simulations to draw")
    if "knob" in scene.effects:
        fig, axes = _axes_grid(fig, n, 2, (13.0, 4.6 * n))
        for i, sim in enumerate(sims):
            _knob_panels(axes[2 * i], axes[2 * i + 1], sim, scene)
    elif n == 1:
        fig, axes = _axes_grid(fig, 2, 1, (9.0, 7.5))
        _response_panel(axes[0], sims[0], scene)
        axes[0].legend(loc="upper left", fontsize="small")
        _force_panel(axes[1], sims[0], scene, window=axes[0].get_xlim(), band=axes[0].get_ylim())
    else:
        ncols = columns or min(4, n)
        if ncols < 1:
            raise ValueError(f"zwidth.plot.simulation: columns must be >= 1, got {columns}")
        nrows = (n + ncols - 1) // ncols
        fig, axes = _axes_grid(fig, nrows, ncols, (3.6 * ncols, 2.9 * nrows + 0.6))
        for ax, sim in zip(axes, sims):
            _response_panel(ax, sim, scene)
        for ax in axes[n:]:
            ax.set_visible(False)
    agree = [s.agrees for s in sims if s.agrees is not None]
    counts = {o: sum(s.verdict.outcome == o for s in sims) for o in ("stable", "unstable", "undecided")}
    summary = ", ".join(f"{c} {o}" for o, c in counts.items() if c)
    if agree:
        summary += f"; simulated = analytic for {sum(agree)} of {len(agree)}"
    fig.suptitle(f"{scene.name}: {scene.description or 'simulated responses'}\n({summary})",
                 fontsize="medium")
    return fig



def loop_region(delta: float, *, delay: int = 0, filter_pole: float = 0.0, average: Optional[int] = None,
                differentiator: str = "backward", point: Union[Point, Sequence[Point], None] = None,
                ax: Optional["Axes"] = None, resolution: Tuple[int, int] = (400, 300),
                T: Optional[float] = None, loop_text: Optional[str] = None, kappa: float = 0.0,
                lambda_: float = 0.0) -> "Figure":
    """How much of the ideal loop's region a real loop keeps, in the (beta, alpha) plane.

    The paper's exact region at delta (grey, its boundary alpha_max) under the region of
    the loop with ``delay``, ``filter_pole`` / ``average`` and ``differentiator`` (blue,
    with its certified alpha_max as a dark blue line), each grid point of ``resolution``
    decided by the guarded check of that loop
    (zwidth.check with the same keywords: exact per point, so the blue area is never larger
    than the true one at the grid's points).  The title gives the share of the ideal
    region's grid points the loop keeps, and the largest alpha on the grid for each.
    ``point`` = (beta, alpha) pairs are marked with the loop's verdict (its oscillation in
    Hz when the period ``T`` [s] is given, else in cycles per sample); ``loop_text``
    replaces the loop's description in the legend (e.g. the cut-off in Hz).  ``kappa`` and
    ``lambda_`` put the loop on a plant with a stiffness and an actuator lag (normalized,
    :func:`zwidth.check`); the grey region stays the paper's plant and loop at delta.
    """
    delta = _scalar("delta", delta)
    kw: Dict[str, Any] = {"delay": delay, "filter_pole": filter_pole, "average": average,
                          "differentiator": differentiator, "kappa": _scalar("kappa", kappa),
                          "lambda_": _scalar("lambda_", lambda_)}
    probe = _check(delta, 0.0, 0.0, **kw)  # validates the loop's keywords (ZwidthError)
    del probe
    ext = _extremes(delta)
    own = _extremes(delta, **kw)  # the loop's own (certified) extremes: the view holds both regions
    lo, hi = min(-delta, float(own.beta_mmin)), max(float(ext.beta_mmax), float(own.beta_mmax))
    width = hi - lo
    nb, na = resolution
    betas = np.linspace(lo - 0.05 * width, hi + 0.05 * width, nb)
    a_lo = -min(1.2 * kw["kappa"], 0.15 * float(own.alpha_mmax)) if kw["kappa"] > 0.0 else 0.0
    alphas = np.linspace(a_lo, 1.1 * max(float(ext.alpha_mmax), float(own.alpha_mmax)), na)
    B, A = np.meshgrid(betas, alphas)
    ideal = np.asarray(_check(delta, A, B), dtype=bool)
    loop = np.asarray(_check(delta, A, B, **kw), dtype=bool)
    fig, ax = _own_axes(ax, (8.0, 5.5))
    extent = (betas[0], betas[-1], alphas[0], alphas[-1])
    ax.imshow(np.where(ideal, 0.85, 1.0), origin="lower", extent=extent, aspect="auto", cmap="gray",
              vmin=0.0, vmax=1.0, interpolation="nearest")
    shown = np.ma.masked_where(~loop, np.ones_like(A))
    ax.imshow(shown, origin="lower", extent=extent, aspect="auto", cmap="Blues", vmin=0.0, vmax=1.6,
              alpha=0.85, interpolation="nearest")
    curve = np.linspace(-delta, float(ext.beta_mmax), 1001)
    ax.plot(curve, np.asarray(alpha_max(delta, curve), dtype=float), color="black", linewidth=1.2)
    curve = np.linspace(float(own.beta_mmin), float(own.beta_mmax), 1001)
    # the loop's certified alpha_max (loop_limits.h): the top of its stable interval above alpha = 0
    ax.plot(curve, np.asarray(alpha_max(delta, curve, errors="mask", **kw), dtype=float), color="#1f4e99",
            linewidth=1.2)
    handles = [_proxy(color="0.6", linewidth=8, label="ideal loop (paper eq (10))"),
               _proxy(color="#4a90d9", linewidth=8, label=f"this loop: {loop_text or _loop_text(kw)}")]
    points = [] if point is None else np.asarray(point, dtype=float).reshape(-1, 2).tolist()
    for pb, pa in points:
        v = verdict(delta, pa, pb, **kw)
        if T is not None and isinstance(v, LoopVerdict):
            v = dataclasses.replace(v, frequency=v.theta / (2 * math.pi * float(T)), frequency_unit="Hz")
        handles += _mark_verdict(ax, pb, pa, v, rf"($\beta$, $\alpha$) = ({pb:.4g}, {pa:.4g})")
    kept = loop.sum() / max(1, ideal.sum())
    top_ideal = float(alphas[ideal.any(axis=1)].max()) if ideal.any() else 0.0
    top_loop = float(alphas[loop.any(axis=1)].max()) if loop.any() else 0.0
    ax.set_title(rf"$\delta$ = {delta:.4g}: the loop keeps {100 * kept:.3g} % of the ideal region "
                 rf"(grid); largest $\alpha$ {top_loop:.4g} vs {top_ideal:.4g}", fontsize=10)
    ax.set_xlabel(r"$\beta$ = B T/m")
    ax.set_ylabel(r"$\alpha$ = K T$^2$/m")
    ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.9)
    return fig


def _loop_text(kw: Dict[str, Any]) -> str:
    from .loop import normalized_loop
    text = normalized_loop("plot.loop_region", kw["delay"], kw["filter_pole"], kw["average"],
                           kw["differentiator"]).describe()
    parts = [f"{k} = {kw[k]:g}" for k in ("kappa", "lambda_") if kw.get(k)]
    return text + (f" on a plant with {', '.join(parts)}" if parts else "")


# ---------------------------------------------------------------------------------------
# A device with plant-side parts (actuator lag, hand, stiffness): against the same device
# without them, real units
# ---------------------------------------------------------------------------------------


def _parts_text(dev: Device) -> str:
    u = {k: v.replace("^2", "²") for k, v in dev.units.items()}
    k_p, tau = float(dev.stiffness), float(dev.actuator_tau)
    m_h, b_h, k_h = (float(v) for v in dev.hand)
    out = []
    if tau != 0.0:
        out.append(f"lag τ = {tau:.4g} s")
    if m_h != 0.0 or b_h != 0.0 or k_h != 0.0:
        out.append(f"hand ({m_h:.3g} {u['m']}, {b_h:.3g} {u['b']}, {k_h:.3g} {u['K']})")
    if k_p != 0.0:
        out.append(f"k_p = {k_p:.4g} {u['K']}")
    return ", ".join(out) or "no plant-side parts"


def plant_region(device: Device, K: Optional[float] = None, B: Optional[float] = None, *,
                 ax: Optional["Axes"] = None, resolution: Tuple[int, int] = (400, 300)) -> "Figure":
    """What the plant-side parts (actuator lag, hand, stiffness) do to the region, real units.

    The region of ``device`` (blue, its loop and its parts) over that of the same plant and
    loop without the parts (grey, ``device.without_plant_parts()``), each grid point of
    ``resolution`` decided by the guarded check (``Device.is_stable``: never stable for an
    unstable point), each with its certified K_max(B) as a line (``Device.k_max``, never
    above the true one).  With a stiffness (k_p + k_h > 0) small negative K are stable: the
    view reaches below K = 0.  K_mmax of both in the title; (B, K) marked with the device's
    verdict when given.  A scalar Device; works for a device without parts too (both equal).
    """
    _scalar_device(device, "plant_region")
    return _real_region(device, device.without_plant_parts(), "without the parts", f"with {_parts_text(device)}",
                        "the plant-side parts make K_mmax {ratio} x that without them", K, B, ax, resolution)


def device_region(device: Device, K: Optional[float] = None, B: Optional[float] = None, *,
                  ax: Optional["Axes"] = None, resolution: Tuple[int, int] = (400, 300)) -> "Figure":
    """The region of the loop a device runs (delay, velocity filter, differentiator, parts),
    real units, beside the paper's ideal loop's for the same plant (grey, ``device.ideal()``).

    As :func:`plant_region`: every grid point by the guarded check, each certified K_max(B)
    as a line, K_mmax of both in the title, (B, K) marked with the device's verdict.
    """
    _scalar_device(device, "device_region")
    return _real_region(device, device.ideal(), "the paper's ideal loop", f"this loop: {device.loop.describe()}",
                        "this loop's K_mmax is {ratio} x the ideal loop's", K, B, ax, resolution)


def _real_region(device: Device, other: Device, other_label: str, this_label: str, ratio_text: str,
                 K: Optional[float], B: Optional[float], ax: Optional["Axes"],
                 resolution: Tuple[int, int]) -> "Figure":
    """device's region (blue) over other's (grey) in (B, K), real units; legend beside the axes."""
    if (K is None) != (B is None):
        raise ValueError("zwidth.plot: give both K and B (or neither)")
    lim, lim0 = device.extremes(), other.extremes()
    u = _units(device)
    b_lo = min(float(lim.B_mmin), float(lim0.B_mmin))
    b_hi = max(float(lim.B_mmax), float(lim0.B_mmax))
    k_hi = 1.08 * max(float(lim.K_mmax), float(lim0.K_mmax))
    spring = float(device.stiffness) + float(device.hand[2])
    k_lo = -min(1.2 * spring, 0.15 * k_hi) if spring > 0.0 else 0.0
    if K is not None and B is not None:
        b_lo, b_hi = min(b_lo, float(B)), max(b_hi, float(B))
        k_lo, k_hi = min(k_lo, float(K)), max(k_hi, 1.05 * float(K))
    width = b_hi - b_lo
    nb, nk = resolution
    Bs = np.linspace(b_lo - 0.05 * width, b_hi + 0.05 * width, nb)
    Ks = np.linspace(k_lo, k_hi, nk)
    BB, KK = np.meshgrid(Bs, Ks)
    this = np.asarray(device.is_stable(KK, BB), dtype=bool)
    theirs = np.asarray(other.is_stable(KK, BB), dtype=bool)
    fig, ax = _own_axes(ax, (10.0, 5.5))
    extent = (Bs[0], Bs[-1], Ks[0], Ks[-1])
    ax.imshow(np.where(theirs, 0.8, 1.0), origin="lower", extent=extent, aspect="auto", cmap="gray",
              vmin=0.0, vmax=1.0, interpolation="nearest")
    ax.imshow(np.ma.masked_where(~this, np.ones_like(KK)), origin="lower", extent=extent, aspect="auto",
              cmap="Blues", vmin=0.0, vmax=1.6, alpha=0.7, interpolation="nearest")
    for dev, l, colour in ((other, lim0, "0.25"), (device, lim, "#1f4e99")):
        curve = np.linspace(float(l.B_mmin), float(l.B_mmax), 801)[1:-1]
        ax.plot(curve, np.asarray(dev.k_max(curve), dtype=float), color=colour, linewidth=1.3)
        ax.plot([float(l.B_at_K_mmax)], [float(l.K_mmax)], "o", color=colour, markersize=6)
    ax.axhline(0.0, color="0.5", linewidth=0.8)
    handles = [_proxy(color="0.7", linewidth=8, label=f"{other_label} (K_mmax {float(lim0.K_mmax):.4g})"),
               _proxy(color="#6fa8dc", linewidth=8, label=f"{this_label} (K_mmax {float(lim.K_mmax):.4g})"),
               _proxy(color="#1f4e99", linewidth=1.3, label="certified K_max(B) (lines)")]
    if K is not None and B is not None:
        handles += _mark_verdict(ax, float(B), float(K), device.verdict(float(K), float(B)),
                                 f"(B, K) = ({float(B):.4g}, {float(K):.4g})")
    ratio = float(lim.K_mmax) / float(lim0.K_mmax) if float(lim0.K_mmax) > 0.0 else math.nan
    ax.set_title(f"{u['m']} = {float(device.m):.4g} {u['m_unit']}, b = {float(device.b):.4g} {u['b_unit']}, "
                 f"T = {float(device.T):.4g} s, loop: {device.loop.describe()}\n"
                 + ratio_text.format(ratio=f"{ratio:.3g}"), fontsize=9)
    ax.set_xlabel(f"B [{u['B_unit']}]")
    ax.set_ylabel(f"K [{u['K_unit']}]")
    _legend_outside(ax, handles)   # the figure's constrained layout makes room for it
    return fig


#: The plant parameters :func:`plant_influence` sweeps: (name in Device.sensitivity, label).
_SWEPT = (("m", "m"), ("b", "b"), ("T", "T"), ("actuator_tau", "τ"), ("m_h", "m_h"), ("b_h", "b_h"),
          ("k_h", "k_h"), ("stiffness", "k_p"))


def _with(device: Device, name: str, grid: NDArray[np.float64]) -> Device:
    """device with one parameter replaced by a grid (the others held)."""
    k_p, tau = device.stiffness, device.actuator_tau
    m_h, b_h, k_h = device.hand
    p = {"m": device.m, "b": device.b, "T": device.T, "actuator_tau": tau, "m_h": m_h, "b_h": b_h, "k_h": k_h,
         "stiffness": k_p}
    p[name] = grid
    return Device(p["m"], p["b"], p["T"], rotary=device.is_rotary, errors="mask", delay=device.loop.delay,
                  velocity_filter=_device_filter(device), differentiator=device.loop.differentiator,
                  actuator_tau=p["actuator_tau"], hand=(p["m_h"], p["b_h"], p["k_h"]), stiffness=p["stiffness"])


def _device_filter(device: Device) -> Any:
    lp = device.loop
    if lp.filter == "lowpass":
        return ("lowpass", lp.cutoff) if lp.cutoff is not None else ("pole", lp.pole)
    return ("average", lp.average) if lp.filter == "average" else None


def plant_influence(device: Device, *, fig: Optional["Figure"] = None, points: int = 60) -> "Figure":
    """How m (J), b, T and the plant-side parts (tau, the hand's m_h, b_h, k_h, the device's
    k_p) move K_mmax and B_mmax around ``device`` (scalar), real units, its loop held.

    One panel per parameter: K_mmax (blue, left axis) and B_mmax (orange, right axis), the
    certified limits of ``Device.extremes`` on a log grid around the value (a part at 0:
    from 1e-4 to 10 times its natural scale: T for tau, m for m_h, m/T for b_h, m/T^2 for
    the stiffnesses, with the value at 0 drawn as a dotted level); the device marked.  The
    slopes at the device are ``device.sensitivity()``'s, printed under the panels.
    """
    m, b, T = _scalar_device(device, "plant_influence")
    u = _units(device)
    sens = device.sensitivity()
    base = {"m": m, "b": b, "T": T, "actuator_tau": float(device.actuator_tau), "m_h": float(device.hand[0]),
            "b_h": float(device.hand[1]), "k_h": float(device.hand[2]), "stiffness": float(device.stiffness)}
    scale = {"m": m, "b": m / T, "T": T, "actuator_tau": T, "m_h": m, "b_h": m / T, "k_h": m / T ** 2,
             "stiffness": m / T ** 2}
    unit = {"m": u["m_unit"], "b": u["b_unit"], "T": "s", "actuator_tau": "s", "m_h": u["m_unit"],
            "b_h": u["b_unit"], "k_h": u["K_unit"], "stiffness": u["K_unit"]}
    here = device.extremes()
    fig, axes = _axes_grid(fig, 2, 4, (15.0, 7.5),
                           dict(left=0.05, right=0.94, top=0.88, bottom=0.17, wspace=0.62, hspace=0.42))
    for ax, (name, label) in zip(axes, _SWEPT):
        value = base[name]
        centre = value if value > 0.0 else scale[name]
        lo, hi = (value / 30.0, value * 30.0) if value > 0.0 else (centre * 1e-4, centre * 10.0)
        grid = np.geomspace(lo, hi, int(points))
        lim = _with(device, name, grid).extremes()
        ax.plot(grid, np.asarray(lim.K_mmax, dtype=float), color="C0", linewidth=2)
        ax.set_xscale("log")
        ax.set_ylabel(f"K_mmax [{u['K_unit']}]", color="C0", fontsize="small")
        twin = ax.twinx()
        twin.plot(grid, np.asarray(lim.B_mmax, dtype=float), color="C1", linewidth=1.5)
        twin.set_ylabel(f"B_mmax [{u['B_unit']}]", color="C1", fontsize="small")
        if value > 0.0:
            ax.plot([value], [float(here.K_mmax)], "o", color="#c62828", markeredgecolor="black", zorder=6)
            twin.plot([value], [float(here.B_mmax)], "s", color="#c62828", markeredgecolor="black", zorder=6)
        else:
            ax.axhline(float(here.K_mmax), color="C0", linestyle=":", linewidth=1)
            twin.axhline(float(here.B_mmax), color="C1", linestyle=":", linewidth=1)
        shown = u["m"] if name == "m" else label
        row = sens["J" if (name == "m" and device.is_rotary) else name]
        ax.set_title(f"{shown} = {value:.3g} {unit[name]}: K_mmax {row['K_trend']}", fontsize="small")
        ax.set_xlabel(f"{shown} [{unit[name]}]" + (" (now 0: dotted)" if value == 0.0 else ""), fontsize="small")
        ax.grid(True, which="major", color="0.9")
    title = (f"K_mmax (blue) and B_mmax (orange) against the plant and its parts around {u['m']} = {m:.4g} "
             f"{u['m_unit']}, b = {b:.4g} {u['b_unit']}, T = {T:.4g} s, {_parts_text(device)}; loop: "
             f"{device.loop.describe()} (certified limits)")
    fig.suptitle("\n".join(textwrap.wrap(title, 150)), fontsize="medium")
    fig.text(0.01, 0.005, "\n".join(textwrap.wrap("; ".join(sens.lines()), 200)), fontsize="x-small",
             va="bottom", ha="left")
    return fig


#: File formats :func:`save` writes, by suffix (vector formats for papers: pdf, svg, eps).
FORMATS = ("png", "pdf", "svg", "eps", "ps")


def save(fig: "Figure", path: Union[str, Path], *, dpi: float = 100.0) -> Path:
    """Write ``fig`` as PNG, PDF, SVG, EPS or PS, chosen by the suffix of ``path``;
    returns the Path.  ``dpi`` applies to PNG (and to images inside vector files).

    Raises ValueError for any other suffix and OSError if the file cannot be written.
    """
    out = Path(path)
    fmt = out.suffix.lower().lstrip(".")
    if fmt not in FORMATS:
        raise ValueError(f"zwidth.plot.save: {out.name!r}: the file must end in "
                         f"{', '.join('.' + f for f in FORMATS[:-1])} or .{FORMATS[-1]}")
    fig.savefig(out, format=fmt, dpi=dpi)
    return out


# ---------------------------------------------------------------------------------------
# A plant box (zwidth.PlantBox): the gains stable for every plant, against the nominal one
# ---------------------------------------------------------------------------------------


def box_region(box: "PlantBox", K: Optional[float] = None, B: Optional[float] = None, *,
               fig: Optional["Figure"] = None, points: int = 161, rel_tol: float = 1e-4) -> "Figure":
    """The gains stable for every plant of ``box``, K against B, beside the nominal plant's.

    Filled: ``box.k_max(B).K_lower`` over B (certified for every plant; searched to
    ``rel_tol``, coarser than the box's own for speed: the curve stays certified, only a
    little lower).  Dashed: the nominal plant's ``k_max(B)`` (middle of the box); thin grey:
    the four corner plants'.  Marked: the box's K_mmax (``box.extremes()``) and, with K and
    B, the gain pair coloured by ``box.verdict``.  Draws into ``fig`` if given (cleared).
    """
    from .box import PlantBox

    coarse = PlantBox(box.m.lo if box.m.lo == box.m.hi else (box.m.lo, box.m.hi),
                      box.b.lo if box.b.lo == box.b.hi else (box.b.lo, box.b.hi), box.T,
                      rotary=box.rotary, capacity=box.capacity, max_evals=box.max_evals,
                      rel_tol=max(rel_tol, box.rel_tol))
    nominal = box.nominal
    u = _units(nominal)
    corners = box.corners()
    lo = -box.b.hi
    hi = max(float(d.extremes().B_mmax) for d in (nominal, *corners))
    bs = np.linspace(lo, hi, int(points))
    k_box = np.array([coarse.k_max(float(b_)).K_lower for b_ in bs])
    k_nom = np.asarray(nominal.k_max(bs), dtype=float)
    x = box.extremes()

    fig, (ax,) = _axes_grid(fig, 1, 1, (7.5, 5.8))
    handles: List[Any] = []
    for i, d in enumerate(corners):
        line, = ax.plot(bs, np.asarray(d.k_max(bs), dtype=float), color="0.6", linewidth=0.8, zorder=3,
                        label="corner plants" if i == 0 else None)
        if i == 0:
            handles.append(line)
    ax.fill_between(bs, 0.0, k_box, color=_EXACT_FILL, alpha=0.75, linewidth=0, zorder=2)
    ax.plot(bs, k_box, color=_EXACT_EDGE, linewidth=2.0, zorder=5)
    handles.append(_proxy(color=_EXACT_EDGE, linewidth=6, alpha=0.75,
                          label="stable for every plant of the box (certified)"))
    handles += ax.plot(bs, k_nom, "--", color=_PASSIVITY_EDGE, linewidth=1.6, zorder=4,
                       label=f"nominal plant {u['m']} = {box.m.mid:.4g}, b = {box.b.mid:.4g}")
    handles += ax.plot([x.B_at], [x.K_mmax], "*", color="gold", markeredgecolor="black", markersize=15,
                       zorder=7, linestyle="none", label=f"box K_mmax = {x.K_mmax:.4g} at B = {x.B_at:.4g}")
    y_hi = max(float(np.max(k_nom)), float(np.max(k_box)))
    if K is not None and B is not None:
        v = box.verdict(float(K), float(B))
        colour = {"stable": _VERDICT_COLOURS["stable"], "unstable": _VERDICT_COLOURS["unstable"]}.get(
            v.word, _VERDICT_COLOURS["marginal"])
        handles += ax.plot([float(B)], [float(K)], "D", color=colour, markeredgecolor="black", markersize=9,
                           zorder=9, linestyle="none", label=f"K = {float(K):.4g}, B = {float(B):.4g}: {v.word}")
        y_hi = max(y_hi, float(K))
    ax.axvline(0.0, color="0.6", linewidth=0.8, zorder=0)
    pad = 0.04 * (hi - lo)
    ax.set_xlim(lo - pad, hi + pad)
    ax.set_ylim(0.0, 1.15 * y_hi)
    ax.set_xlabel(f"B [{u['B_unit']}] (virtual damping)")
    ax.set_ylabel(f"K [{u['K_unit']}] (virtual stiffness)")
    ax.set_title(f"Stable gains for every plant: {u['m']} in [{box.m.lo:.4g}, {box.m.hi:.4g}] {u['m_unit']}, "
                 f"b in [{box.b.lo:.4g}, {box.b.hi:.4g}] {u['b_unit']}, T = {box.T:.4g} s", fontsize="medium")
    ax.grid(True, color="0.9", zorder=0)
    ax.legend(handles=handles, loc="upper right", fontsize="small", framealpha=0.9)
    return fig


def __dir__() -> List[str]:
    """The figures, not the typing names this module imports."""
    return sorted(__all__)


def identification(ident: "Identification", *, fig: Optional["Figure"] = None) -> "Figure":
    """An identification (:func:`zwidth.identify.identify`): the command, the measured
    position with the model's, and the residual against the quantization floor (+-q/sqrt(12)
    dashed when the log is in counts).  Draws into ``fig`` if given (cleared)."""
    fig, (ax_u, ax_x, ax_r) = _axes_grid(fig, 3, 1, (9.0, 8.0))
    t = ident.time
    force = "torque [N m]" if ident.rotary else "force [N]"
    position = "position [rad]" if ident.rotary else "position [m]"
    ax_u.step(t, ident.command, where="post", color="#455a64", lw=0.8)
    ax_u.set_ylabel(f"command, {force}")
    ax_x.plot(t, ident.measured, color="#1565c0", lw=0.9, label="measured")
    ax_x.plot(t, ident.fitted, color="#c62828", lw=0.9, ls="--", label="model")
    ax_x.set_ylabel(position)
    ax_x.legend(loc="upper left", fontsize="small")
    ax_r.plot(t, ident.residual, color="#6a1b9a", lw=0.7)
    if ident.fit.floor > 0.0:
        for sign in (-1.0, 1.0):
            ax_r.axhline(sign * ident.fit.floor, color="#9e9e9e", ls="--", lw=0.8)
    ax_r.set_ylabel("residual")
    ax_r.set_xlabel("time [s]")
    e = ident.estimates
    sym = ident.mass_symbol
    ax_u.set_title(f"{sym} = {e[sym].value:.4g}, b = {e['b'].value:.4g}, delay {ident.delay}; "
                   f"{ident.fit.reason}", fontsize="medium")
    for ax in (ax_u, ax_x, ax_r):
        ax.grid(True, alpha=0.3)
    return fig
