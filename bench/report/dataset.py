# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The report's point set, its high-precision reference, and the scoring of a method.

Everything here is deterministic (fixed seeds) and evaluated on exact binary inputs.  The
geometry (f, L, extremes, beta interval, coefficients) comes from the project's independent
mpmath reference, tests/py/reference.py (60 digits, from the paper's definitions; nothing
there copies the C).  The reference *verdict* is what the report names: the roots of p(z)
at 50 digits (mpmath.polyroots), stable iff every |z| < 1, with two exact rules where 50
digits cannot decide: alpha <= 0 is unstable (p(1) = (c1 + c2) alpha, an identity), and
|rho - 1| < 1e-40 is decided by the Jury conditions at escalating precision
(reference.stable).  The verdicts are cross-checked against the Jury reference of the
tests (reference.stable_batch) on every point.

The set: groups of points sharing one delta (a plant), deltas log-uniform in
[1e-6, 0.1] (where the literal coefficient formulas cancel), uniform in [0.1, 8] (where
the line bites and alpha_mmax changes branch) and log-uniform in [8, 1e4].  Within a
group, 40 % of the points spread over a box around the region and 60 % crowded at a
boundary: on the curve alpha = min{f, L}(beta) (60 % of them), at beta = -delta (20 %)
and at the right end beta = beta_mmax (20 %).  Half of the crowded points sit on the
float grid, a few float ulps or 1e-7 .. 1e-5 (relative) from the boundary; the other half
at double resolution, a few double ulps or 1e-15 .. 1e-9 away.  Deltas and box points are
float numbers, so both precisions see the same plant.  The float programs read every
value rounded to float (the double-resolution points move by up to half a float ulp,
which keeps them within a few float ulps of the boundary), and are scored against the
reference at the inputs they actually received.
"""
from __future__ import annotations

import hashlib
import math
import os
import sys
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "py"))
import reference as ref  # noqa: E402  (tests/py/reference.py)
from mpmath import mp, mpf  # noqa: E402

SEED = 20240606
GROUP = 40                 # points per delta
REF_DPS = 50               # digits of the reference roots
TIE = mpf(10) ** -40       # |rho - 1| below this: the Jury reference decides
REF_VERSION = "roots50-v1"

DOUBLE, FLOAT = ref.DOUBLE, ref.FLOAT


# ------------------------------------------------------------------------------ the set

def _f32(x: float) -> float:
    return float(np.float32(x))


def _deltas(rng: np.random.Generator, n: int) -> np.ndarray:
    u = rng.random(n)
    lo = 10 ** rng.uniform(-6, -1, n)
    mid = rng.uniform(0.1, 8.0, n)
    hi = 10 ** rng.uniform(math.log10(8.0), 4, n)
    d = np.where(u < 0.25, lo, np.where(u < 0.75, mid, hi))
    return d.astype(np.float32).astype(np.float64)


def _perturb(v: Any, fmt: ref.Fmt, rng: np.random.Generator) -> float:
    """v (mpf) moved a little in fmt: k ulps (|k| <= 6 float, 16 double) or a relative
    1e-7 .. 1e-5 (float) / 1e-15 .. 1e-9 (double), either sign, rounded to fmt."""
    if rng.random() < 0.5:
        k = int(rng.integers(-6, 7)) if fmt is FLOAT else int(rng.integers(-16, 17))
        return ref.step(ref.round_to(v, fmt), k, fmt)
    lo, hi = (-7, -5) if fmt is FLOAT else (-15, -9)
    t = 10 ** rng.uniform(lo, hi) * (1 if rng.random() < 0.5 else -1)
    with mp.workdps(40):
        return ref.round_to(mpf(v) * (1 + mpf(t)), fmt)


def _group(task: Tuple[float, int, int]) -> List[Tuple[float, float, float, str, str]]:
    """The GROUP points of one delta: (delta, alpha, beta, kind, grid)."""
    d, seed, i = task
    rng = np.random.default_rng([seed, i])
    ex = ref.extremes(d)
    amm, bmax = float(ex["alpha_mmax"]), ex["beta_mmax"]
    w = float(bmax) + d
    out = []
    for _ in range(GROUP):
        r = rng.random()
        if r < 0.4:
            a = _f32(rng.uniform(0.0, 1.3 * amm))
            b = _f32(rng.uniform(-d - w / 10, float(bmax) + w / 10))
            out.append((d, a if a > 0 else _f32(0.5 * amm), b, "box", "float"))
            continue
        fmt = FLOAT if rng.random() < 0.5 else DOUBLE
        grid = "float" if fmt is FLOAT else "double"
        r = rng.random()
        if r < 0.6:                                  # the curve min{f, L}
            b = ref.round_to(mpf(-d) + (bmax + d) * mpf(rng.random()), fmt)
            if not -d < b < bmax:
                b = ref.step(-d, 1, fmt)
            amax, _ = ref.alpha_max_at(d, b)
            out.append((d, _perturb(amax, fmt, rng), b, "curve", grid))
        elif r < 0.8:                                # beta = -delta
            b = _perturb(mpf(-d), fmt, rng)
            inside = b if b > -d else -d + abs(b + d) if b != -d else ref.step(-d, 1, fmt)
            amax, _ = ref.alpha_max_at(d, inside)
            a = ref.round_to(amax * mpf(rng.uniform(0.0, 1.5)), fmt)
            out.append((d, a if a > 0 else ref.round_to(amax / 2, fmt), b, "damping", grid))
        else:                                        # beta = beta_mmax
            b = _perturb(bmax, fmt, rng)
            mirror = ref.round_to(2 * bmax - mpf(b), fmt) if b >= bmax else b
            amax, _ = ref.alpha_max_at(d, mirror)
            a = ref.round_to(amax * mpf(rng.uniform(0.0, 1.5)), fmt)
            out.append((d, a if a > 0 else fmt.min_normal, b, "right", grid))
    return out


def make_points(n: int, seed: int = SEED) -> Dict[str, np.ndarray]:
    """About n points (a whole number of delta groups), deterministic for (n, seed)."""
    groups = max(1, -(-n // GROUP))
    deltas = _deltas(np.random.default_rng(seed), groups)
    parts = ref.pmap(_group, [(float(d), seed, i) for i, d in enumerate(deltas)], min_parallel=8)
    rows = [p for part in parts for p in part]
    return {"delta": np.array([r[0] for r in rows]), "alpha": np.array([float(r[1]) for r in rows]),
            "beta": np.array([float(r[2]) for r in rows]), "kind": np.array([r[3] for r in rows]),
            "grid": np.array([r[4] for r in rows])}


def as_float(pts: Dict[str, np.ndarray]) -> Dict[str, np.ndarray]:
    """The same points as the float programs read them (each value rounded to float)."""
    out = dict(pts)
    for k in ("delta", "alpha", "beta"):
        out[k] = pts[k].astype(np.float32).astype(np.float64)
    return out


def write_points(path: str, pts: Dict[str, np.ndarray]) -> None:
    with open(path, "w", encoding="ascii") as fh:
        fh.write("# delta alpha beta (C99 hexadecimal floats), bench/report/dataset.py\n")
        for d, a, b in zip(pts["delta"].tolist(), pts["alpha"].tolist(), pts["beta"].tolist()):
            fh.write(f"{d.hex()} {a.hex()} {b.hex()}\n")


def write_deltas(path: str, deltas: Any) -> None:
    with open(path, "w", encoding="ascii") as fh:
        for d in deltas:
            fh.write(f"{float(d).hex()}\n")


def coefficient_deltas(fmt: ref.Fmt, n: int) -> np.ndarray:
    """The delta grid of section 2: 0, the smallest subnormal, a log grid over the whole
    range of fmt (to 1e300 / 1e38) with a denser part over [1e-3, 10], rounded to fmt."""
    top = 300 if fmt is DOUBLE else 38
    bottom = -300 if fmt is DOUBLE else -38
    grid = np.concatenate([[0.0, fmt.tiny], 10 ** np.linspace(bottom, top, n // 2),
                           10 ** np.linspace(-3, 1, n - n // 2)])
    return np.unique(grid.astype(fmt.np_type).astype(np.float64))


# ------------------------------------------------------------------------------ reference

def _ref_one(t: Tuple[float, float, float]) -> Tuple[bool, float, int]:
    """(stable, rho, how): how 0 = roots at 50 digits, 1 = alpha <= 0, 2 = Jury (tie)."""
    d, a, b = t
    if not a > 0:
        return False, math.nan, 1
    rho, _ = ref.spectral_radius(d, a, b, dps=REF_DPS)
    if abs(rho - 1) < TIE:
        return bool(ref.stable(d, a, b)), float(rho), 2
    return bool(rho < 1), float(rho), 0


def _hash(*arrays: np.ndarray) -> str:
    h = hashlib.sha256(REF_VERSION.encode())
    for a in arrays:
        h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
    return h.hexdigest()[:20]


def reference(d: np.ndarray, a: np.ndarray, b: np.ndarray, cache_dir: Optional[str]) -> Dict[str, Any]:
    """Reference verdicts and spectral radii at these exact inputs (cached on disk by the
    hash of the inputs, so a re-run of the same set does not pay for mpmath again)."""
    key = _hash(d, a, b)
    path = os.path.join(cache_dir, f"reference-{key}.npz") if cache_dir else None
    if path and os.path.exists(path):
        z = np.load(path)
        return {k: z[k] for k in z.files} | {"cached": True}
    res = ref.pmap(_ref_one, list(zip(d.tolist(), a.tolist(), b.tolist())), min_parallel=64)
    out = {"stable": np.array([r[0] for r in res]), "rho": np.array([r[1] for r in res]),
           "how": np.array([r[2] for r in res], dtype=np.int8)}
    # Cross-check against the tests' Jury reference (rigorous pre-screen + escalating mpmath).
    out["jury_disagree"] = np.array(int((ref.stable_batch(d, a, b) != out["stable"]).sum()))
    if path:
        np.savez(path, **out)
    return out | {"cached": False}


def reference_coeffs(deltas: np.ndarray) -> Dict[str, List[Any]]:
    """Exact e, c1, c2, d12 and extremes at each delta (mpf values)."""
    cols: Dict[str, List[Any]] = {k: [] for k in ("e", "c1", "c2", "d12", "alpha_mmax", "beta_at",
                                                  "alpha_p_max", "beta_mmax")}
    for d in deltas.tolist():
        co = ref.coeffs(d)
        for k in ("e", "c1", "c2", "d12"):
            cols[k].append(getattr(co, k))
        if math.isfinite(d):
            ex = ref.extremes(d)
            cols["alpha_mmax"].append(ex["alpha_mmax"])
            cols["beta_at"].append(ex["beta_at"])
            # reference.extremes forms 2 (1 - e) / c2 with 1 - e from exp(-delta) at 70
            # digits, which is 0 for delta below ~1e-70; s delta / c2 is the same quantity
            # (s = c1 + c2 = 2 (1 - e) / delta) from the reference's accurate fields.
            with mp.workdps(ref.DPS + 10):
                ap = co.s * co.delta / co.c2
                if co.d12 != 0:
                    ap = min(ap, 4 * (1 + co.e) / co.d12)
            cols["alpha_p_max"].append(ap)
            cols["beta_mmax"].append(ex["beta_mmax"])
    return cols


def _kmax_one(t: Tuple[float, float]) -> Any:
    return ref.alpha_max_at(t[0], t[1])[0]


def reference_kmax(d: np.ndarray, b: np.ndarray) -> List[Any]:
    """sup alpha stable at beta (mpf), min{f, L} inside (-delta, beta_mmax), else 0."""
    return ref.pmap(_kmax_one, list(zip(d.tolist(), b.tolist())), min_parallel=64)


# ------------------------------------------------------------------------------ scoring

def _distance_one(t: Tuple[float, float, float, str]) -> float:
    """Distance of (delta, alpha, beta) to the boundary of the exact region, in ulps of
    fmt at the boundary value: the least of the distance along alpha (to min{f, L}(beta)),
    along beta (to the ends of the stable beta interval at alpha) and, above the top, to
    alpha_mmax."""
    d, a, b, fname = t
    fmt = ref.FORMATS[fname]
    best = math.inf
    if not a > 0:
        # alpha = 0, e.g. a K_max of 0 ("nothing is stable at this beta"): how far beta is
        # from the ends of the damping range, where the true K_max falls to 0.
        bmax = ref.extremes(d)["beta_mmax"]
        return min(float(abs(mpf(b) + d) / ref.ulp_of(d, fmt)), float(abs(mpf(b) - bmax) / ref.ulp_of(float(bmax), fmt)))
    amax, _ = ref.alpha_max_at(d, b)
    if amax > 0:
        best = min(best, float(abs(mpf(a) - amax) / ref.ulp_of(float(amax), fmt)))
    lo, hi, nonempty = ref.beta_interval(d, a)
    if nonempty:
        for end in (lo, hi):
            best = min(best, float(abs(mpf(b) - end) / ref.ulp_of(float(end), fmt)))
    amm = ref.extremes(d)["alpha_mmax"]
    if a >= amm:
        best = min(best, float((mpf(a) - amm) / ref.ulp_of(float(amm), fmt)))
    return best


def boundary_ulps(d: np.ndarray, a: np.ndarray, b: np.ndarray, fmt: ref.Fmt) -> np.ndarray:
    tasks = [(x, y, z, fmt.name) for x, y, z in zip(d.tolist(), a.tolist(), b.tolist())]
    return np.array(ref.pmap(_distance_one, tasks, min_parallel=64), dtype=float)


def score(pred_stable: np.ndarray, truth: np.ndarray, d: np.ndarray, a: np.ndarray, b: np.ndarray,
          fmt: ref.Fmt, refused: Optional[np.ndarray] = None) -> Dict[str, Any]:
    """False-stable / false-unstable counts and the worst boundary distance (ulps of fmt)
    of a wrong verdict.  A refused point (error status) counts as "not stable"."""
    pred = pred_stable.astype(bool)
    if refused is not None:
        pred = pred & ~refused
    fs = pred & ~truth
    fu = ~pred & truth
    wrong = np.nonzero(fs | fu)[0]
    dist = boundary_ulps(d[wrong], a[wrong], b[wrong], fmt) if len(wrong) else np.zeros(0)
    worst_fs = float(dist[fs[wrong]].max()) if fs.any() else 0.0
    worst_fu = float(dist[fu[wrong]].max()) if fu.any() else 0.0
    return {"n": int(len(truth)), "stable": int(truth.sum()), "false_stable": int(fs.sum()),
            "false_stable_frac": float(fs.sum()) / max(1, len(truth)),
            "false_unstable": int(fu.sum()), "refused": int(refused.sum()) if refused is not None else 0,
            "worst_fs_ulps": worst_fs, "worst_fu_ulps": worst_fu,
            "worst_ulps": max(worst_fs, worst_fu)}


def kmax_ulps(d: np.ndarray, kmax: np.ndarray, b: np.ndarray, exact: Sequence[Any], fmt: ref.Fmt) -> np.ndarray:
    """Error of computed K_max(beta) values as the distance of the point (K_max, beta) from
    the true boundary, in ulps of fmt (boundary_ulps).  Not the ulps of K_max itself: near
    the ends of the damping range K_max falls to 0 through a difference of rounded
    transcendental terms (2/c2 - beta, lambda - beta), so a tiny K_max has an error of a few
    ulps of those terms, which is a few ulps of beta along the boundary."""
    out = np.zeros(len(d))
    wrong = np.nonzero(np.array([not (k == 0 and e == 0) for k, e in zip(kmax.tolist(), exact)], dtype=bool))[0]
    if len(wrong):
        out[wrong] = boundary_ulps(d[wrong], np.maximum(kmax[wrong], 0.0), b[wrong], fmt)
    return out


def value_ulps(computed: Any, exact: Sequence[Any], fmt: ref.Fmt) -> np.ndarray:
    """Ordinal distance (ulps of fmt) between each computed value and the exact value
    rounded to fmt."""
    return np.array([float(ref.ulp_distance(c, e, fmt)) for c, e in zip(computed, exact)], dtype=float)


def relative_error(computed: Any, exact: Sequence[Any]) -> np.ndarray:
    out = []
    for c, e in zip(computed, exact):
        if e == 0:
            out.append(0.0 if c == 0 else math.inf)
        elif not math.isfinite(c):
            out.append(math.inf)
        else:
            out.append(float(abs((mpf(c) - e) / e)))
    return np.array(out, dtype=float)
