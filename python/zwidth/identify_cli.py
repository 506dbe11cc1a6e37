# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""``zwidth identify LOG.csv``: the plant from a log, its box and the box's certified limits.

cli.main hands the ``identify`` subcommand here (the parser's options are built by
:func:`add_parser`).  The fit is :func:`zwidth.identify.identify`; docs/identify.md.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional, Union

from ._kernels import ZwidthError

#: --lag's value -> identify's lag=
_LAG_CHOICE: Dict[Optional[str], Union[bool, str]] = {None: False, "faster": True, "either": "either"}
#: identified, but no box to certify (the model does not fit, m or b not identified, a lag)
EXIT_NO_BOX = 6

DESCRIPTION = """\
Identify the plant from a log of an experiment: the drive's gains off, it plays a known
command (steps, a chirp or a PRBS: zwidth.identify.excitation) and logs, every tick, the
command and the position it measures.  Fits m (or J) and b exactly on the sampled model, the
delay in whole samples (0..--max-delay), and, when asked, an actuator lag, Coulomb friction
and a spring; prints each with its confidence interval, checks the residual, and gives the
plant box at a joint level (every plant the log allows) with the gains certified for the
whole box.  docs/identify.md explains the experiment, the model and the intervals."""

EPILOG = """\
the log: a CSV file with a header row (lines starting with # skipped) or a .npz; columns
  by name: --command (default 'command'), --position (default 'position'), and --time
  (seconds) or --index (sample numbers); with neither, rows are consecutive samples and
  --T is needed.  Missing samples (gaps) are left out, repeated rows dropped.
examples:
  zwidth identify run.csv --time t --T 1e-3 --counts-per-unit 6366.2
  zwidth identify run.csv --T 5e-4 --force-constant 0.052 --friction --json
  zwidth identify run.csv --T 1e-3 --velocity-filter lowpass:100Hz --plot fit.png
--json keys: command, loop (the box's; absent without a box), identification (estimates
  {name: value, lo, hi, level, standard_error, identified}, delay, delay_rss,
  plausible_delays, fit {rms, floor, rho1, explained, ok, reason}, warnings, T, samples,
  rotary, dof), box ({m|J, b, T, delay, stiffness, level} or null), limits (K_mmax, B_at,
  converged, worst), limits_command, no_box (why, when there is none).
exit status: 0 identified with a box, 3 the log cannot be used (the message names the
  column), 6 identified but no box (the model does not fit, m or b not identified by the
  excitation, or a lag was found: a box is certified without one)."""


def add_parser(sub: Any, formatter: Any) -> argparse.ArgumentParser:
    """Add the ``identify`` subcommand to cli's subparsers."""
    from .identify import DEFAULT_BOX_LEVEL, DEFAULT_LEVEL, MAX_DELAY
    from .cli import _number
    p: argparse.ArgumentParser = sub.add_parser(
        "identify", help="fit m, b, delay (lag, friction, spring) to a log; the box and its limits",
        description=DESCRIPTION, epilog=EPILOG, formatter_class=formatter, allow_abbrev=False)
    p.add_argument("log", metavar="LOG", help="the experiment's log: .csv (header row) or .npz")
    cols = p.add_argument_group("the log's columns")
    cols.add_argument("--command", dest="command_column", default="command", metavar="NAME",
                      help="the commanded force [N] or torque [N m] (or current, with --force-constant)")
    cols.add_argument("--position", dest="position_column", default="position", metavar="NAME",
                      help="the measured position [m] or [rad] (or counts, with --counts-per-unit)")
    cols.add_argument("--time", metavar="NAME", help="time stamps [s]")
    cols.add_argument("--index", metavar="NAME", help="sample numbers (instead of --time)")
    p.add_argument("--T", type=_number, metavar="S", help="sampling period [s] (default: from --time)")
    p.add_argument("--rotary", action="store_true", help="a rotary device: J, N m, rad")
    p.add_argument("--counts-per-unit", type=_number, metavar="N",
                   help="the position is in encoder counts, N per m (or per rad)")
    p.add_argument("--force-constant", type=_number, default=1.0, metavar="KT",
                   help="force (torque) per unit of the command, e.g. N/A for a current command")
    p.add_argument("--force-limit", type=_number, metavar="F",
                   help="the drive's force ceiling: a log that sits at it is refused (saturated)")
    p.add_argument("--max-delay", type=int, default=3, metavar="N",
                   help=f"try delays 0..N samples (0..{MAX_DELAY}; default 3): the best fit's is reported, every "
                        f"one the log cannot reject widens the intervals, and the box takes the largest")
    p.add_argument("--delay", type=int, metavar="N", help="fix the delay instead of choosing it")
    model = p.add_argument_group("what else to fit (default: m, b and the delay only)")
    model.add_argument("--lag", nargs="?", const="faster", choices=("faster", "either"), metavar="faster|either",
                       help="an actuator (current-loop) lag tau, taken as faster than the mechanics (tau <= m/b, "
                            "the default) or 'either' (the model is symmetric in tau and m/b)")
    model.add_argument("--friction", action="store_true", help="Coulomb friction F_c")
    model.add_argument("--spring", action="store_true", help="a spring k (a return spring, a cable)")
    p.add_argument("--level", type=_number, default=DEFAULT_LEVEL, metavar="P",
                   help=f"confidence level of each interval (default {DEFAULT_LEVEL})")
    p.add_argument("--box-level", type=_number, default=DEFAULT_BOX_LEVEL, metavar="P",
                   help=f"joint level of the box (default {DEFAULT_BOX_LEVEL})")
    p.add_argument("--velocity-filter", metavar="SPEC",
                   help="the drive's velocity filter, for the box's limits (as in zwidth limits)")
    p.add_argument("--differentiator", choices=("backward", "tustin"), default="backward",
                   help="the drive's velocity estimate, for the box's limits")
    p.add_argument("--plot", metavar="FILE", help="draw the command, the fit and the residual (.png, .svg)")
    p.add_argument("--dpi", type=_number, default=100.0, help="resolution of a PNG plot (default 100)")
    p.add_argument("--progress", action="store_true", help="a line per delay fitted, on stderr")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=None, needs_gains=False, parser=p)
    return p


def main(args: argparse.Namespace, sub: argparse.ArgumentParser) -> int:
    """Run ``zwidth identify``; returns the exit status."""
    from .cli import EXIT_INVALID, EXIT_OK, EXIT_PLOT, _emit, _Outcome, _PlotError, _velocity_filter, _write_figure
    try:
        from .identify import IdentifyError, identify, read_log
    except ImportError as exc:       # scipy
        print(f"zwidth identify: error: needs scipy ({exc}): pip install zwidth[identify]", file=sys.stderr)
        return EXIT_INVALID
    if args.time is not None and args.index is not None:
        sub.error("give --time or --index, not both")
    if not 0.0 < args.dpi < math.inf:
        sub.error(f"argument --dpi: must be > 0, got {args.dpi:g}")
    if args.plot and Path(args.plot).suffix.lower() not in (".png", ".pdf", ".svg", ".eps", ".ps"):
        sub.error(f"argument --plot: {args.plot!r} must end in .png, .pdf, .svg, .eps or .ps")
    loop: Dict[str, Any] = {"differentiator": args.differentiator}
    vf = _velocity_filter(args)
    if vf is not None:
        loop["velocity_filter"] = vf
    try:
        columns = read_log(args.log, time=args.time, index=args.index, command=args.command_column,
                           position=args.position_column)
        ident = identify(columns["position"], columns["command"], args.T, time=columns.get("time"),
                         index=columns.get("index"), counts_per_unit=args.counts_per_unit,
                         force_constant=args.force_constant, force_limit=args.force_limit,
                         max_delay=args.max_delay, delay=args.delay,
                         lag=_LAG_CHOICE[args.lag], friction=args.friction,
                         spring=args.spring, level=args.level, rotary=args.rotary, progress=args.progress)
    except IdentifyError as exc:
        where = f" (column {exc.column!r})" if exc.column and exc.column not in ("T", "level") else ""
        print(f"zwidth identify: error: cannot identify from {args.log}{where}: {exc}", file=sys.stderr)
        return EXIT_INVALID
    lines = ident.lines()
    data: Dict[str, Any] = {"identification": ident.as_dict()}
    status = EXIT_OK
    box_loop = None
    try:
        box = ident.box(args.box_level, **loop)
    except IdentifyError as exc:
        lines.append(f"No box: {exc}")
        data["box"] = None
        data["no_box"] = str(exc)
        status = EXIT_NO_BOX
    except ZwidthError as exc:
        lines.append(f"No box: the identified box is outside what zwidth certifies: {exc}")
        data["box"] = None
        data["no_box"] = str(exc)
        status = EXIT_NO_BOX
    else:
        box_loop = box.loop
        lines += _box_lines(box, args, data)
    if args.plot:
        try:
            _write_figure(lambda plot: plot.identification(ident), Path(args.plot), int(args.dpi))
        except _PlotError as exc:
            print(f"zwidth identify: error: cannot plot: {exc}", file=sys.stderr)
            return EXIT_PLOT
        lines.append(f"Plot: {args.plot}")
    _emit(_Outcome(status, data, lines), "identify", None, args.json, sys.stdout, loop=box_loop)
    return status


def _box_lines(box: Any, args: argparse.Namespace, data: Dict[str, Any]) -> List[str]:
    """The box, its certified limits and the command that reproduces them."""
    sym = box.mass_symbol
    ext = box.extremes()
    data["box"] = {sym: [box.m.lo, box.m.hi], "b": [box.b.lo, box.b.hi], "T": box.T,
                   "delay": box.loop.delay, "stiffness": [box.stiffness.lo, box.stiffness.hi],
                   "level": args.box_level}
    data["limits"] = {"K_mmax": ext.K_mmax, "B_at": ext.B_at, "converged": ext.converged,
                      "worst": {sym: ext.m_worst, "b": ext.b_worst}}
    units = ("N m/rad", "N m s/rad") if box.rotary else ("N/m", "N s/m")
    out = [f"Box at joint level {100 * args.box_level:g} %: {box!r}",
           f"  certified for every plant of the box: K <= {ext.K_mmax:.6g} {units[0]} at B = {ext.B_at:.6g} "
           f"{units[1]} (worst plant {sym} = {ext.m_worst:.6g}, b = {ext.b_worst:.6g})"
           + ("" if ext.converged else "; the search stopped at its budget: the bound is safe, not tight")]
    cmd = f"zwidth limits --{sym} {box.m.lo:.9g}:{box.m.hi:.9g} --b {box.b.lo:.9g}:{box.b.hi:.9g} --T {box.T:g} " \
          f"--delay {box.loop.delay}"
    if box.stiffness.hi > 0.0:
        cmd += f" --stiffness {box.stiffness.lo:.9g}:{box.stiffness.hi:.9g}"
    if args.velocity_filter:
        cmd += f" --velocity-filter {args.velocity_filter}"
    if args.differentiator != "backward":
        cmd += f" --differentiator {args.differentiator}"
    out.append(f"  the box's limits and certificate: {cmd}")
    data["limits_command"] = cmd
    return out
