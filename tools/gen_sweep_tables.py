# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""Tables of csrc/src/sweep_tables.h and the proof of their error bounds (docs/numerics.md,
"Per-plant sweeps").

On [0, 2) the sweep evaluates four functions of delta by short Taylor polynomials around
the centres c_j = (j + 1/2)/32 of 64 intervals of width 1/32 (|h| = |delta - c_j| <= 1/64):

    E = exp(-delta)          Q = exp(-delta) P12(delta) = d12/delta
    W = 2 exp(delta)/P2      G = P1 / (P1 + P2)          = c1/(c1 + c2) = g
    (W = 2/c2, so hs = W/sigma)

where P1, P2, P12 are the positive series of coeffs.c (P1 + P2 = 2(e^delta - 1)/delta).
For each function and interval this module computes, with mpmath at 60 digits,
  - the Taylor coefficients a_k (re-expanded Maclaurin series), rounded to double/float;
  - a rigorous bound on the truncated tail, by Cauchy's estimate |a_k| <= M R^-k on the
    disk |z - c| <= R, with M bounded through the positive series: |A(z)| <= A(c + R) and
    |A(z)| >= 2 A(c) - A(c + R) for a series A with non-negative coefficients;
  - the rounding error of Horner's rule without fma (Higham, (5.3)): the computed value is
    sum_k (1 + theta_{2k+1}) a^_k h^k with |theta_m| <= gamma_m = m u / (1 - m u),
    plus the rounding of the coefficients and of h = delta - c;
  - a lower bound of the function on the interval, to make the bound relative.
``python tools/gen_sweep_tables.py`` writes the header and prints the worst bound of each
function (tests/py/test_sweep.py re-derives both from the header).
"""
from __future__ import annotations

import sys
from pathlib import Path

from mpmath import mp, mpf

mp.dps = 60

INTERVALS = 64          # on [0, 2)
WIDTH = mpf(1) / 32     # of an interval
RADIUS = WIDTH / 2      # |h| <= 1/64
FUNCTIONS = ("E", "G", "W", "Q")
TERMS = {"E": 9, "G": 11, "W": 10, "Q": 9}   # Taylor terms per function (degree TERMS - 1)
MACLAURIN_TERMS = 64    # of the positive series, before re-expansion (tail < 4^64/64! at c + R <= 4)
CAUCHY_RADII = [mpf(k) / 8 for k in range(2, 17)]  # R tried for the tail bound
UNIT = {"double": mpf(2) ** -53, "float": mpf(2) ** -24}
OUT = Path(__file__).resolve().parents[1] / "csrc" / "src" / "sweep_tables.h"


def factorial(k):
    return mp.factorial(k)


_MACLAURIN = {}


def maclaurin(name):
    """Maclaurin coefficients of P1, P2, P12 (all positive)."""
    if name not in _MACLAURIN:
        _MACLAURIN[name] = _maclaurin(name)
    return _MACLAURIN[name]


def _maclaurin(name):
    if name == "P1":
        return [2 * mpf(k + 1) / factorial(k + 2) for k in range(MACLAURIN_TERMS)]
    if name == "P2":
        return [2 / factorial(k + 2) for k in range(MACLAURIN_TERMS)]
    if name == "P12":
        return [2 * mpf(k + 1) / factorial(k + 3) for k in range(MACLAURIN_TERMS)]
    if name == "S":  # P1 + P2
        return [2 / factorial(k + 1) for k in range(MACLAURIN_TERMS)]
    raise KeyError(name)


def value(series, x):
    return mp.fsum(b * mpf(x) ** k for k, b in enumerate(series))


def recenter(series, c, n):
    """Taylor coefficients at c of a power series (first n)."""
    return [mp.fsum(series[j] * mp.binomial(j, k) * c ** (j - k) for j in range(k, len(series))) for k in range(n)]


def exp_at(c, n, sign):
    """Taylor coefficients at c of exp(sign z)."""
    return [mp.exp(sign * c) * mpf(sign) ** k / factorial(k) for k in range(n)]


def mul(a, b):
    n = len(a)
    return [mp.fsum(a[i] * b[k - i] for i in range(k + 1)) for k in range(n)]


def div(a, b):
    n = len(a)
    q = []
    for k in range(n):
        q.append((a[k] - mp.fsum(q[i] * b[k - i] for i in range(k))) / b[0])
    return q


def taylor(name, c, n):
    """Exact (60-digit) Taylor coefficients of function name at c, first n."""
    if name == "E":
        return exp_at(c, n, -1)
    if name == "Q":
        return mul(exp_at(c, n, -1), recenter(maclaurin("P12"), c, n))
    if name == "W":
        return div([2 * x for x in exp_at(c, n, 1)], recenter(maclaurin("P2"), c, n))
    if name == "G":
        return div(recenter(maclaurin("P1"), c, n), recenter(maclaurin("S"), c, n))
    raise KeyError(name)


def bound_on_disk(name, c, R):
    """M >= |F(z)| on |z - c| <= R, or None when the lower bound of a denominator fails."""
    if name == "E":
        return mp.exp(R - c)
    if name == "Q":
        return mp.exp(R - c) * value(maclaurin("P12"), c + R)
    if name == "W":
        low = 2 * value(maclaurin("P2"), c) - value(maclaurin("P2"), c + R)
        return None if low <= 0 else 2 * mp.exp(c + R) / low
    if name == "G":
        low = 2 * value(maclaurin("S"), c) - value(maclaurin("S"), c + R)
        return None if low <= 0 else value(maclaurin("P1"), c + R) / low
    raise KeyError(name)


def tail_bound(name, c, n, r):
    """Rigorous bound on sum_{k >= n} |a_k| r^k (Cauchy), the best over CAUCHY_RADII."""
    best = mp.inf
    for R in CAUCHY_RADII:
        if R <= r:
            continue
        M = bound_on_disk(name, c, R)
        if M is None:
            continue
        q = r / R
        best = min(best, M * q ** n / (1 - q))
    return best


def center(j):
    return (mpf(j) + mpf(1) / 2) * WIDTH


def rounded(x, precision):
    """x rounded to nearest double (or float)."""
    f = float(x)
    if precision == "float":
        import numpy as np
        f = float(np.float32(x))
    return f


def gamma(m, u):
    return m * u / (1 - m * u)


def interval_bound(name, j, precision, coefficients=None):
    """(relative error bound, lower bound of F) of the computed F on interval j, from the
    given rounded coefficients (default: rounded here)."""
    u = UNIT[precision]
    c = center(j)
    n = TERMS[name]
    exact = taylor(name, c, n)
    hats = coefficients if coefficients is not None else [rounded(a, precision) for a in exact]
    r = RADIUS * (1 + u)  # |h~| <= |h| (1 + u): h = delta - c rounds at most once
    horner = mp.fsum(gamma(2 * k + 1, u) * abs(mpf(a)) * r ** k for k, a in enumerate(hats))
    coef = mp.fsum(abs(mpf(a) - e) * r ** k for k, (a, e) in enumerate(zip(hats, exact)))
    h_err = u * RADIUS * mp.fsum(k * abs(e) * r ** (k - 1) for k, e in enumerate(exact) if k)
    tail = tail_bound(name, c, n, r)
    absolute = horner + coef + h_err + tail
    low = exact[0] - mp.fsum(abs(e) * r ** k for k, e in enumerate(exact) if k) - tail
    assert low > 0, (name, j)
    return absolute / low / u, low


def table(precision="double"):
    """{function: [[coefficients of interval j] for j]} rounded to the precision."""
    return {name: [[rounded(a, precision) for a in taylor(name, center(j), TERMS[name])]
                   for j in range(INTERVALS)] for name in FUNCTIONS}


def worst_bounds(precision="double"):
    """The worst relative bound (in units of u) of each function over the intervals."""
    return {name: max(interval_bound(name, j, precision)[0] for j in range(INTERVALS)) for name in FUNCTIONS}


def write_header(path: Path = OUT) -> None:
    tab = table("double")
    lines = ["/* sweep_tables.h - generated by tools/gen_sweep_tables.py; do not edit.",
             " * Taylor coefficients (lowest power first) of E = exp(-d), G = g, W = 2/c2 and",
             " * Q = d12/d at the centres c_j = (j + 1/2)/32 of the 64 intervals of [0, 2); the",
             " * error bounds are proved in docs/numerics.md and re-derived by tests/py/test_sweep.py. */",
             "#ifndef ZWIDTH_SWEEP_TABLES_H", "#define ZWIDTH_SWEEP_TABLES_H", "",
             f"#define ZW_SWEEP_INTERVALS {INTERVALS}"]
    lines += [f"#define ZW_SWEEP_TERMS_{name} {TERMS[name]}" for name in FUNCTIONS] + [""]
    for name in FUNCTIONS:
        lines.append(f"static const zw_real zw_sweep_{name.lower()}[ZW_SWEEP_INTERVALS][ZW_SWEEP_TERMS_{name}] = {{")
        for j, row in enumerate(tab[name]):
            lines.append("    {" + ", ".join(f"ZW_R({a!r})" for a in row) + "},")
        lines.append("};")
    lines += ["", "#endif /* ZWIDTH_SWEEP_TABLES_H */", ""]
    path.write_text("\n".join(lines))


if __name__ == "__main__":
    write_header()
    for precision in ("double", "float"):
        print(precision, {k: f"{float(v):.3f} u" for k, v in worst_bounds(precision).items()}, file=sys.stderr)
