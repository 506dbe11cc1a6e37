# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""The ``zwidth`` command with plant ranges: ``--m 0.10:0.14`` (or ``--J``, ``--b``).

A range makes the plant a :class:`zwidth.PlantBox`; ``check``, ``limits`` and
``plot region`` then answer for every plant of the box, for the paper's ideal loop or the
loop given by --delay, --velocity-filter and --differentiator (``plot region``: ideal only).
cli.main hands such command lines to :func:`main` here; everything else stays in cli.py.

Plant-side parts over a box: ``--stiffness K_P`` and ``--hand M_H,B_H,K_H`` (each a number
or LO:HI; cli.parse_hand is the --hand type) make the box's plant the
coupled one (certified by the general loop's method); ``--actuator-tau`` is refused over a
box (cli.main says so; the lag's box enclosure is not built).
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple, Union

from .box import PlantBox, PlantRange, parse_range
from .cli import (EXIT_INVALID, EXIT_OK, EXIT_PLOT, EXIT_UNSTABLE, _emit, _fmt, _Outcome, _PlotError,
                  _apply_preset, _Usage, _velocity_filter, _write_figure, parse_hand, require_loop)
from ._kernels import ZwidthError

_RANGE_OPTIONS = ("m", "J", "b")
_COMMANDS = ("check", "limits", "plot")


def _part(value: Any) -> Union[float, PlantRange]:
    """A part's option value: a number, a PlantRange, or its text (LO:HI)."""
    if value is None:
        return 0.0
    if isinstance(value, str):
        return parse_range(value)
    if isinstance(value, PlantRange):
        return value
    return float(value)


def has_range(args: argparse.Namespace) -> bool:
    """Does any plant option hold a range LO:HI (--m, --J, --b, --stiffness, --hand's entries)?"""
    hand = getattr(args, "hand", None)
    return (any(isinstance(getattr(args, n, None), PlantRange) for n in _RANGE_OPTIONS + ("stiffness",))
            or (isinstance(hand, tuple) and any(isinstance(v, PlantRange) for v in hand)))


def _box(args: argparse.Namespace) -> PlantBox:
    _apply_preset(args)  # --preset paper-drive with a range (--hand 0:1e-6,0,0): the drive's m, b, T
    require_loop(args)
    norm = [f"--{n}" for n in ("delta", "alpha", "beta") if getattr(args, n, None) is not None]
    if norm:
        raise _Usage(f"plant ranges are in real units: {', '.join(norm)} cannot be combined with them")
    missing = [name for name, ok in (("--m (or --J)", args.m is not None or args.J is not None),
                                     ("--b", args.b is not None), ("--T", args.T is not None)) if not ok]
    if missing:
        raise _Usage(f"the plant box needs {', '.join(missing)}")
    if (args.K is None) != (args.B is None):
        raise _Usage("give both --K and --B (or neither)")
    rotary = args.J is not None
    hand_arg = getattr(args, "hand", None)
    hand: Optional[Tuple[Union[float, PlantRange], ...]] = None
    if hand_arg is not None:
        hand = parse_hand(hand_arg) if isinstance(hand_arg, str) else tuple(_part(v) for v in hand_arg)
    return PlantBox(args.J if rotary else args.m, args.b, args.T, rotary=rotary, delay=args.delay,
                    velocity_filter=_velocity_filter(args), differentiator=args.differentiator,
                    stiffness=_part(getattr(args, "stiffness", None)),
                    hand=None if hand is None else (hand[0], hand[1], hand[2]),
                    actuator_tau=_part(getattr(args, "actuator_tau", None)))


def _has_parts(box: PlantBox) -> bool:
    return box.stiffness.hi > 0.0 or any(r.hi > 0.0 for r in box.hand)


def _units(box: PlantBox) -> Dict[str, str]:
    if box.rotary:
        return {"m": "kg m^2", "b": "N m s/rad", "K": "N m/rad", "B": "N m s/rad"}
    return {"m": "kg", "b": "N s/m", "K": "N/m", "B": "N s/m"}


def _header(box: PlantBox) -> str:
    u = _units(box)
    text = (f"Plant box: {box.mass_symbol} in [{_fmt(box.m.lo)}, {_fmt(box.m.hi)}] {u['m']}, "
            f"b in [{_fmt(box.b.lo)}, {_fmt(box.b.hi)}] {u['b']}, T = {_fmt(box.T)} s")
    if box.stiffness.hi > 0.0:
        text += f"\n  device stiffness k_p in [{_fmt(box.stiffness.lo)}, {_fmt(box.stiffness.hi)}] {u['K']}"
    if any(r.hi > 0.0 for r in box.hand):
        mh, bh, kh = box.hand
        text += (f"\n  hand: m_h in [{_fmt(mh.lo)}, {_fmt(mh.hi)}] {u['m']}, b_h in [{_fmt(bh.lo)}, "
                 f"{_fmt(bh.hi)}] {u['b']}, k_h in [{_fmt(kh.lo)}, {_fmt(kh.hi)}] {u['K']} "
                 f"(worst plants below are the totals M, Bp, Kp)")
    return text


def _summary(box: PlantBox) -> Dict[str, Any]:
    out = {"mass": box.mass_symbol, "m_lo": box.m.lo, "m_hi": box.m.hi, "b_lo": box.b.lo,
           "b_hi": box.b.hi, "T": box.T, "rotary": box.rotary, "loop": box.loop.describe(),
           "method": box.method}
    if _has_parts(box):
        out["stiffness"] = [box.stiffness.lo, box.stiffness.hi]
        out["hand"] = [[r.lo, r.hi] for r in box.hand]
    return out


def _plant(box: PlantBox, m: float, b: float, k: float) -> Dict[str, float]:
    out = {box.mass_symbol: m, "b": b}
    if _has_parts(box):
        out["k"] = k
    return out


def _plant_text(box: PlantBox, m: float, b: float, k: float) -> str:
    text = f"{box.mass_symbol} = {_fmt(m)}, b = {_fmt(b)}"
    return text + (f", k = {_fmt(k)}" if _has_parts(box) else "")


def cmd_check(args: argparse.Namespace, box: PlantBox) -> _Outcome:
    if args.K is None:
        raise _Usage("check needs the gains: --K and --B")
    if getattr(args, "region", "exact") != "exact":
        raise _Usage("plant ranges are certified in the exact region only (no --region)")
    K, B = float(args.K), float(args.B)
    v = box.verdict(K, B)
    k = box.k_max(B)
    br = box.b_range(K) if K > 0 else None
    u, sym = _units(box), box.mass_symbol
    data = {"verdict": v.word, "stable": v.stable, "decided": v.decided, "K": K, "B": B,
            "worst_plant": _plant(box, v.m_worst, v.b_worst, v.k_worst),
            "K_max": {"certified": k.K_lower, "at_worst_plant": k.K_upper, "gap": k.gap,
                      "worst_plant": _plant(box, k.m_worst, k.b_worst, k.k_worst), "converged": k.converged},
            "B_range": None if br is None else {"lo": br.lo, "hi": br.hi, "nonempty": br.nonempty}}
    lines = [_header(box), f"Gains: K = {_fmt(K)} {u['K']}, B = {_fmt(B)} {u['B']}",
             f"Verdict for every plant of the box: {v.word.upper()}"]
    if v.stable:
        if not math.isnan(v.m_worst):
            lines.append(f"  least K_max found at {_plant_text(box, v.m_worst, v.b_worst, v.k_worst)}")
    elif v.decided:
        lines.append(f"  unstable at {_plant_text(box, v.m_worst, v.b_worst, v.k_worst)}")
    else:
        lines.append("  undecided: the search budget ran out (counts as not stable)")
    lines.append(f"  K_max over the box at this B >= {_fmt(k.K_lower)} {u['K']} (certified; "
                 f"{_fmt(k.K_upper)} at the worst plant, gap {k.gap:.2g})")
    if br is not None:
        lines.append("  B range over the box at this K: " + (
            f"{_fmt(br.lo)} <= B <= {_fmt(br.hi)} {u['B']} (certified)" if br.nonempty
            else "none certified"))
    return _Outcome(EXIT_OK if v.stable else EXIT_UNSTABLE, data, lines)


def cmd_limits(args: argparse.Namespace, box: PlantBox) -> _Outcome:
    x = box.extremes()
    kp = box.k_max(0.0)
    nom = box.nominal.extremes()
    u, sym = _units(box), box.mass_symbol
    M, Bp, Kp = box.totals
    data = {"K_mmax": x.K_mmax, "B_at_K_mmax": x.B_at, "K_upper_at": x.K_upper_at,
            "K_mmax_upper": x.K_mmax_upper, "worst_plant": _plant(box, x.m_worst, x.b_worst, x.k_worst),
            "converged": x.converged, "K_p_max": kp.K_lower,
            "nominal": {**_plant(box, M.mid, Bp.mid, Kp.mid), "K_mmax": float(nom.K_mmax),
                        "B_at_K_mmax": float(nom.B_at_K_mmax)}}
    lines = [_header(box), "", "Limits for every plant of the box (certified, never above the true ones)",
             f"  K_mmax   = {_fmt(x.K_mmax)} {u['K']} at B = {_fmt(x.B_at)} {u['B']}",
             f"    worst plant {_plant_text(box, x.m_worst, x.b_worst, x.k_worst)} "
             f"(its own K_mmax {_fmt(x.K_mmax_upper)}: no single B does better)",
             f"  K with B = 0 (stiffness only): K < {_fmt(kp.K_lower)} {u['K']}",
             f"  nominal plant ({_plant_text(box, M.mid, Bp.mid, Kp.mid)}): "
             f"K_mmax = {_fmt(nom.K_mmax)} {u['K']} at B = {_fmt(nom.B_at_K_mmax)} {u['B']}"]
    lines += _certificate_lines(box, x.K_mmax, data, u)
    return _Outcome(EXIT_OK, data, lines)


def _certificate_lines(box: PlantBox, K_mmax: float, data: Dict[str, Any], u: Dict[str, str]) -> List[str]:
    """The drive's certificate (PlantBox.certificate, float, over the B certified at half of
    K_mmax: its default range): its steps, or why none."""
    try:
        c = box.certificate(box.certificate_range(K_mmax))
    except ZwidthError as exc:
        data["certificate"] = {"error": str(exc)}
        return ["", f"Drive certificate (float): not built: {exc}"]
    data["certificate"] = {"steps": [{"B_lo": lo, "B_hi": hi, "K": k, "K_upper": up} for lo, hi, k, up in c.steps()],
                           "leaves": c.leaves, "bytes": c.size_bytes, "build_seconds": c.build_seconds,
                           "verify_seconds": c.verify_seconds, "precision": c.precision}
    lines = ["", f"Drive certificate (float, {len(c.K)} steps, {c.leaves} leaves, {c.size_bytes} bytes; "
                 f"built in {c.build_seconds:.2f} s, verified in {1e3 * c.verify_seconds:.2f} ms here):",
             f"  {'B from':>12} {'B to':>12} {'K certified':>12} {'point K_max':>12}  kept"]
    for lo, hi, k, up in c.steps():
        kept = k / up if up > 0.0 else 0.0
        lines.append(f"  {_fmt(lo):>12} {_fmt(hi):>12} {_fmt(k):>12} {_fmt(up):>12}  {kept:.0%}")
    lines.append(f"  every K' in (0, K] is proven stable over its B step for every plant ({u['K']}, {u['B']});"
                 " 'point K_max' is the least of the box's corners and centre there")
    return lines


def cmd_plot(args: argparse.Namespace, box: PlantBox) -> _Outcome:
    if args.kind != "region":
        raise _Usage(f"plot {args.kind} does not take plant ranges; 'plot region' draws the box's region")
    if box.method == "kharitonov":
        raise _Usage("plot region of a plant box is drawn for the paper's ideal loop only")
    out = Path(args.output or "zwidth-region.png")
    K = None if args.K is None else float(args.K)
    B = None if args.B is None else float(args.B)
    _write_figure(lambda plot: plot.box_region(box, K, B), out, args.dpi)
    data = {"kind": "region", "file": str(out), "format": out.suffix.lower().lstrip("."),
            "bytes": out.stat().st_size}
    return _Outcome(EXIT_OK, data, [f"wrote {out} (region of the plant box, {data['bytes']} bytes)"])


def main(args: argparse.Namespace, sub: argparse.ArgumentParser) -> int:
    """cli.main's branch for plant ranges; same exit codes and error reporting."""
    try:
        if args.command not in _COMMANDS:
            raise _Usage(f"plant ranges (LO:HI) work with check, limits and plot region, not {args.command}")
        if args.command == "plot":
            if not 0.0 < args.dpi < math.inf:
                raise _Usage(f"argument --dpi: must be > 0, got {args.dpi:g}")
            suffix = Path(args.output).suffix.lower() if args.output else ".png"
            if suffix not in (".png", ".svg"):
                raise _Usage(f"argument -o/--output: {args.output!r} must end in .png or .svg")
        box = _box(args)
        handler = {"check": cmd_check, "limits": cmd_limits, "plot": cmd_plot}[args.command]
        outcome = handler(args, box)
    except _Usage as exc:
        sub.error(str(exc))  # exits 2
    except ZwidthError as exc:
        print(f"zwidth {args.command}: error: invalid input: {exc}", file=sys.stderr)
        return EXIT_INVALID
    except _PlotError as exc:
        print(f"zwidth plot: error: cannot plot: {exc}", file=sys.stderr)
        return EXIT_PLOT
    if args.json:
        outcome.data = {"mode": "box", "box": _summary(box), "units": _units(box), **outcome.data}
    _emit(outcome, args.command, None, args.json, sys.stdout, loop=box.loop)
    return int(outcome.status)


__all__: List[str] = ["has_range", "main", "parse_hand"]
