# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""ctypes bindings of the zwidth shared libraries for the Python reference tests.

The structs mirror csrc/include/zwidth/*.h field by field (zw_real is c_double in
libzwidth_d_shared.so and c_float in libzwidth_f_shared.so; bool is c_bool,
uint_least16_t is c_uint16, enums are c_int).  The libraries are looked up in $ZW_LIB_DIR
(default: <repo>/build).  Numeric #defines and enum values are parsed from the headers so
that the tests never restate them.

Every wrapper returns (status, outputs...) and pre-fills its output buffers with the byte
pattern SENTINEL, so `zw.untouched()` can tell whether the last call wrote anything, and
`zw.failsafe()` whether it wrote the fail-safe values status.h promises on error (verdicts
not stable, limits 0, ranges empty, rho +inf, plants and gains NaN).
"""
from __future__ import annotations

import ctypes
import math
import os
import re
from ctypes import POINTER, byref, c_bool, c_char_p, c_int, c_uint16
from pathlib import Path

import numpy as np
import pytest

import reference as ref

REPO = Path(__file__).resolve().parents[2]
INCLUDE = REPO / "csrc" / "include" / "zwidth"
LIB_DIR = Path(os.environ.get("ZW_LIB_DIR", REPO / "build"))
LIB_NAMES = {"double": "libzwidth_d_shared.so", "float": "libzwidth_f_shared.so"}
SENTINEL = 0xA5

# ---------------------------------------------------------------------------------------
# Header parsing
# ---------------------------------------------------------------------------------------


def _header_text():
    return "\n".join(p.read_text() for p in sorted(INCLUDE.glob("*.h")))


def header_defines():
    """Numeric #defines of the public headers as decimal strings (ZW_R(x) unwrapped), so the
    reference can read them at full precision: {'ZW_DELTA0': '2.3105...', 'ZW_COEF_ULPS': '4'}."""
    out = {}
    for name, val in re.findall(r"^#define\s+(ZW_\w+)\s+(.+?)\s*(?:/\*.*)?$", _header_text(), re.M):
        m = re.fullmatch(r"ZW_R\(([-+0-9.eE]+)\)|([-+0-9.eE]+)", val.strip())
        if m:
            out[name] = m.group(1) or m.group(2)
    return out


def header_enums():
    """Enumerator values of the public headers: {'ZW_ERR_NAN': 2, 'ZW_BOUND_LINE': 8, ...}."""
    return {k: int(v) for k, v in re.findall(r"\b(ZW_[A-Z0-9_]+)\s*=\s*(-?\d+)", _header_text())}


DEFINES = header_defines()
E = header_enums()  # status codes, bounds, regions, trends
COEF_ULPS = int(DEFINES["ZW_COEF_ULPS"])

# ---------------------------------------------------------------------------------------
# Struct mirrors
# ---------------------------------------------------------------------------------------


def _structs(real):
    class Coeffs(ctypes.Structure):
        _fields_ = [(n, real) for n in ("delta", "e", "c1", "c2", "d12", "s", "g", "sigma", "hs",
                                        "delta_relerr")]

    class Verdict(ctypes.Structure):
        _fields_ = [("stable", c_bool), ("marginal", c_bool), ("deciding", c_int), ("violated", c_uint16)]

    class Extremes(ctypes.Structure):
        _fields_ = [("alpha_mmax", real), ("beta_at_alpha_mmax", real), ("at_corner", c_bool),
                    ("alpha_p_max", real), ("beta_mmax", real), ("beta_mmin", real), ("alpha_mmin", real)]

    class Device(ctypes.Structure):
        _fields_ = [("m", real), ("b", real), ("T", real), ("k_scale", real), ("b_scale", real),
                    ("co", Coeffs)]

    class DeviceExtremes(ctypes.Structure):
        _fields_ = [("K_mmax", real), ("B_at_K_mmax", real), ("at_corner", c_bool), ("K_p_max", real),
                    ("B_mmax", real), ("B_mmin", real), ("K_mmin", real)]

    class Influence(ctypes.Structure):
        _fields_ = ([(n, real) for n in ("delta", "K_mmax", "B_mmax", "m_K1", "m_K2", "K_mmax_at_m_K2",
                                         "K_mmax_at_m_K1", "m_K_match", "T_B", "T_0", "m_0", "m_B",
                                         "b_0", "b_BB")]
                    + [(n, c_int) for n in ("K_vs_m", "K_vs_b", "K_vs_T", "B_vs_m", "B_vs_b", "B_vs_T")]
                    + [("best_m_for_K", real)])

    return Coeffs, Verdict, Extremes, Device, DeviceExtremes, Influence


_INFLUENCE_LIMITS = ("K_mmax", "B_mmax", "K_mmax_at_m_K2", "K_mmax_at_m_K1")


def _leaves(obj):
    """(name, value) of every scalar in a ctypes struct, array or simple value."""
    if isinstance(obj, ctypes.Structure):
        for name, _ in obj._fields_:
            v = getattr(obj, name)
            if isinstance(v, (ctypes.Structure, ctypes.Array)):
                yield from ((f"{name}.{n}", x) for n, x in _leaves(v))
            else:
                yield name, v
    elif isinstance(obj, ctypes.Array):
        yield from ((str(i), x) for i, x in enumerate(obj))
    else:
        yield "", obj.value


def _is_failsafe(obj, kind):
    """Does obj hold the fail-safe value of its kind (see ZW._out)?"""
    if kind == "verdict":
        bad = E["ZW_BOUND_INVALID"]
        return (obj.stable, obj.marginal, obj.deciding, obj.violated) == (False, False, bad, bad)
    if kind == "influence":
        unknown = E["ZW_TREND_UNKNOWN"]
        for name, v in _leaves(obj):
            if name in _INFLUENCE_LIMITS:
                ok = v == 0
            elif name.endswith("_vs_m") or name.endswith("_vs_b") or name.endswith("_vs_T"):
                ok = v == unknown
            else:
                ok = math.isnan(v)
            if not ok:
                return False
        return True
    for _, v in _leaves(obj):
        if isinstance(v, bool):
            ok = v is False
        elif kind == "nan":
            ok = math.isnan(v)
        elif kind == "inf":
            ok = v == math.inf
        else:
            ok = v == 0 and kind in ("zero", "false")
        if not ok:
            return False
    return True


def _loop_limit(name):
    return int(re.search(rf"#define\s+{name}\s+(\d+)u", _header_text()).group(1))


LOOP_MAX_DELAY = _loop_limit("ZW_LOOP_MAX_DELAY")
LOOP_MAX_AVERAGE = _loop_limit("ZW_LOOP_MAX_AVERAGE")
PLANT_MAX_ORDER = 3  # ZW_PLANT_MAX_ORDER (plant.h)
LOOP_N = PLANT_MAX_ORDER + LOOP_MAX_DELAY + LOOP_MAX_AVERAGE + 1  # ZW_LOOP_MAX_DEGREE + 1 entries


def _loop_structs(real, Coeffs):
    """Mirrors of loop.h."""

    class LoopSpec(ctypes.Structure):
        _fields_ = [("delay", ctypes.c_uint), ("differentiator", c_int), ("filter", c_int),
                    ("filter_pole", real), ("average", ctypes.c_uint)]

    class PlantSpec(ctypes.Structure):
        _fields_ = [(n, real) for n in ("delta", "kappa", "lambda_", "delta_relerr", "kappa_relerr",
                                        "lambda_relerr")]

    q = PLANT_MAX_ORDER

    class Plant(ctypes.Structure):
        """zw_plant (plant.h)."""
        _fields_ = ([("spec", PlantSpec), ("order", ctypes.c_uint),
                     ("den", real * (q + 1)), ("den_err", real * (q + 1)),
                     ("num", real * q), ("num_err", real * q),
                     ("den_s", real * (q + 1)), ("den_s_err", real * (q + 1)),
                     ("num_s", real * q), ("num_s_err", real * q), ("c", Coeffs),
                     ("den_w", real * (q + 1)), ("den_w_err", real * (q + 1))])

    class Loop(ctypes.Structure):
        _fields_ = ([("c", Coeffs), ("spec", LoopSpec), ("degree", ctypes.c_uint)]
                    + [(n, real * LOOP_N) for n in ("D", "D_err", "Na", "Na_err", "Nb", "Nb_err",
                                                    "Ds", "Ds_err", "Nas", "Nas_err", "Nbs", "Nbs_err")]
                    + [("alpha_relerr", real), ("beta_relerr", real), ("plant", Plant)])

    Loop.Plant, Loop.PlantSpec = Plant, PlantSpec

    class LoopVerdict(ctypes.Structure):
        _fields_ = [("stable", c_bool), ("marginal", c_bool), ("deciding", c_int), ("theta", real)]

    class LoopWorkspace(ctypes.Structure):
        """zw_loop_workspace (scratch: row, row_err, root re/im pairs, radius), followed by a
        guard area that the library must leave alone (a mirror smaller than the C struct
        fails ws_intact() instead of corrupting memory)."""
        _fields_ = [("row", real * LOOP_N), ("row_err", real * LOOP_N),
                    ("root", real * (2 * (LOOP_N - 1))), ("radius", real * (LOOP_N - 1)),
                    # the limits' state and the root test's plant values (about 660 B double, 370 float)
                    ("limits", ctypes.c_ubyte * 768),
                    ("guard", ctypes.c_ubyte * 256)]

    return LoopSpec, Loop, LoopVerdict, LoopWorkspace


def as_dict(s):
    """A ctypes struct as a plain dict (nested structs as dicts)."""
    out = {}
    for name, _ in s._fields_:
        v = getattr(s, name)
        out[name] = as_dict(v) if isinstance(v, ctypes.Structure) else v
    return out


# ---------------------------------------------------------------------------------------
# The wrapper
# ---------------------------------------------------------------------------------------


class _Suffixed:
    """The float library exports every function as zw_name_f (zwidth/precision.h: a
    precision mismatch fails at link time); this looks lib.zw_name up as zw_name + suffix,
    so the tests use the declared names for both precisions."""

    def __init__(self, cdll, suffix):
        self._cdll, self._suffix = cdll, suffix

    def __getattr__(self, name):
        fn = getattr(self._cdll, name + self._suffix)
        setattr(self, name, fn)  # one function object per name, so restype/argtypes stick
        return fn



class ZW:
    """One precision of the library.  Attributes: name ('double'/'float'), fmt (the
    reference's binary format), real (ctypes type), np (numpy type), u (unit roundoff),
    lib (the CDLL), and the struct classes."""

    def __init__(self, name):
        self.name = name
        self.fmt = ref.FORMATS[name]
        self.real = ctypes.c_double if name == "double" else ctypes.c_float
        self.np = self.fmt.np_type
        self.u = self.fmt.u
        path = LIB_DIR / LIB_NAMES[name]
        if not path.exists():
            pytest.fail(f"{path} not found: build with cmake (see tests/py/conftest.py) or set ZW_LIB_DIR",
                        pytrace=False)
        self.lib = _Suffixed(ctypes.CDLL(str(path)), "_f" if name == "float" else "")
        (self.Coeffs, self.Verdict, self.Extremes, self.Device, self.DeviceExtremes,
         self.Influence) = _structs(self.real)
        self._outs = []
        R, P = self.real, POINTER
        C, V, D = self.Coeffs, self.Verdict, self.Device
        sigs = {
            "zw_status_name": (c_char_p, [c_int]),
            "zw_coeffs_init": (c_int, [P(C), R]),
            "zw_coeffs_literal": (c_int, [R, P(R), P(R), P(R)]),
            "zw_check": (c_int, [P(C), R, R, P(V)]),
            "zw_check_region": (c_int, [c_int, P(C), R, R, P(V)]),
            "zw_check_proportional": (c_int, [P(C), R, P(V)]),
            "zw_char_poly": (c_int, [P(C), R, R, P(R)]),
            "zw_spectral_radius": (c_int, [P(C), R, R, P(R)]),
            "zw_radius_within": (c_int, [P(C), R, R, R, P(c_bool)]),
            "zw_extremes_compute": (c_int, [P(C), P(self.Extremes)]),
            "zw_hyperbola_top": (c_int, [P(C), P(R), P(R)]),
            "zw_corner": (c_int, [P(C), P(R), P(R)]),
            "zw_alpha_max": (c_int, [P(C), R, P(R)]),
            "zw_beta_interval": (c_int, [P(C), R, P(R), P(R), P(c_bool)]),
            "zw_device_init": (c_int, [P(D), R, R, R]),
            "zw_device_normalize": (c_int, [P(D), R, R, P(R), P(R)]),
            "zw_device_check": (c_int, [P(D), R, R, P(V)]),
            "zw_device_check_region": (c_int, [c_int, P(D), R, R, P(V)]),
            "zw_device_spectral_radius": (c_int, [P(D), R, R, P(R)]),
            "zw_device_radius_within": (c_int, [P(D), R, R, R, P(c_bool)]),
            "zw_device_extremes_compute": (c_int, [P(D), P(self.DeviceExtremes)]),
            "zw_device_k_max": (c_int, [P(D), R, P(R)]),
            "zw_device_b_range": (c_int, [P(D), R, P(R), P(R), P(c_bool)]),
            "zw_device_influence": (c_int, [P(D), P(self.Influence)]),
        }
        for fname, (res, args) in sigs.items():
            fn = getattr(self.lib, fname)
            fn.restype, fn.argtypes = res, args
        self.LoopSpec, self.Loop, self.LoopVerdict, self.LoopWorkspace = _loop_structs(R, C)
        L = self.Loop
        # one scratch for every call of this wrapper (the tests call one at a time)
        self.ws = self.LoopWorkspace()
        ctypes.memset(byref(self.ws), SENTINEL, ctypes.sizeof(self.ws))  # needs no init
        W = P(self.LoopWorkspace)
        loop_sigs = {
            "zw_loop_lowpass_pole": (c_int, [R, R, P(R)]),
            "zw_loop_init": (c_int, [P(L), P(C), P(self.LoopSpec)]),
            "zw_loop_poly": (c_int, [P(L), R, R, P(R), P(ctypes.c_uint)]),
            "zw_loop_check": (c_int, [P(L), W, R, R, P(self.LoopVerdict)]),
            "zw_loop_is_stable": (c_int, [P(L), W, R, R, P(c_bool)]),
            "zw_loop_radius_within": (c_int, [P(L), W, R, R, R, P(c_bool)]),
            "zw_loop_spectral_radius": (c_int, [P(L), W, R, R, P(R), P(R)]),
        }
        self.loop_fn = {}
        for fname, (res, args) in loop_sigs.items():
            fn = self.symbol(fname)
            fn.restype, fn.argtypes = res, args
            self.loop_fn[fname] = fn

    def symbol(self, fname):
        """The library's function fname (the one place that knows the symbol naming)."""
        return getattr(self.lib, fname)

    # -- helpers -------------------------------------------------------------------------

    def __repr__(self):
        return f"ZW({self.name})"

    def r(self, x):
        """x rounded to this precision (round to nearest, overflow to inf), as a Python float."""
        with np.errstate(over="ignore"):
            return float(self.np(x))

    def _out(self, ctype, failsafe):
        """A sentinel-filled output whose fail-safe value is `failsafe`: "nan", "zero" (every
        real 0, every flag false), "inf", "false", "verdict" or "influence"."""
        obj = ctype()
        ctypes.memset(byref(obj), SENTINEL, ctypes.sizeof(obj))
        self._outs.append((obj, failsafe))
        return obj

    def _begin(self):
        self._outs = []

    def untouched(self):
        """True iff every output buffer of the last call still holds the sentinel bytes."""
        return all(bytes(memoryview(o).cast("B")) == bytes([SENTINEL]) * ctypes.sizeof(o) for o, _ in self._outs)

    def failsafe(self):
        """True iff every output of the last call holds its fail-safe value (status.h)."""
        return all(_is_failsafe(o, kind) for o, kind in self._outs)

    def status_name(self, st):
        return self.lib.zw_status_name(st).decode()

    # -- coeffs.h ------------------------------------------------------------------------

    def coeffs(self, delta):
        self._begin()
        co = self._out(self.Coeffs, "nan")
        return self.lib.zw_coeffs_init(byref(co), delta), co

    def coeffs_literal(self, delta):
        self._begin()
        a, b, c = (self._out(self.real, "nan") for _ in range(3))
        st = self.lib.zw_coeffs_literal(delta, byref(a), byref(b), byref(c))
        return st, a.value, b.value, c.value

    # -- region.h ------------------------------------------------------------------------

    def check(self, co, alpha, beta):
        self._begin()
        v = self._out(self.Verdict, "verdict")
        return self.lib.zw_check(byref(co), alpha, beta, byref(v)), v

    def check_region(self, region, co, alpha, beta):
        self._begin()
        v = self._out(self.Verdict, "verdict")
        return self.lib.zw_check_region(region, byref(co), alpha, beta, byref(v)), v

    def check_proportional(self, co, alpha):
        self._begin()
        v = self._out(self.Verdict, "verdict")
        return self.lib.zw_check_proportional(byref(co), alpha, byref(v)), v

    def check_many(self, co, alphas, betas, region=None):
        """Vectorised zw_check / zw_check_region over arrays: returns
        (status, stable, marginal, deciding, violated) numpy arrays."""
        n = len(alphas)
        st = np.empty(n, np.int32)
        stab = np.empty(n, bool)
        marg = np.empty(n, bool)
        dec = np.empty(n, np.int32)
        vio = np.empty(n, np.int32)
        v = self.Verdict()
        pv = byref(v)
        pc = byref(co)
        if region is None:
            fn = self.lib.zw_check
            for i, (a, b) in enumerate(zip(alphas.tolist(), betas.tolist())):
                st[i] = fn(pc, a, b, pv)
                stab[i], marg[i], dec[i], vio[i] = v.stable, v.marginal, v.deciding, v.violated
        else:
            fn = self.lib.zw_check_region
            for i, (a, b) in enumerate(zip(alphas.tolist(), betas.tolist())):
                st[i] = fn(region, pc, a, b, pv)
                stab[i], marg[i], dec[i], vio[i] = v.stable, v.marginal, v.deciding, v.violated
        return st, stab, marg, dec, vio

    # -- margin.h ------------------------------------------------------------------------

    def char_poly(self, co, alpha, beta):
        self._begin()
        p = self._out(self.real * 4, "nan")
        return self.lib.zw_char_poly(byref(co), alpha, beta, p), list(p)

    def spectral_radius(self, co, alpha, beta):
        self._begin()
        rho = self._out(self.real, "inf")
        return self.lib.zw_spectral_radius(byref(co), alpha, beta, byref(rho)), rho.value

    def radius_within(self, co, alpha, beta, r):
        self._begin()
        w = self._out(c_bool, "false")
        return self.lib.zw_radius_within(byref(co), alpha, beta, r, byref(w)), w.value

    # -- loop.h --------------------------------------------------------------------------

    def loop_spec(self, delay=0, differentiator="backward", filter="none", pole=0.0, average=0):
        kinds = {"backward": E["ZW_DIFF_BACKWARD"], "tustin": E["ZW_DIFF_TUSTIN"]}
        filters = {"none": E["ZW_VFILTER_NONE"], "lowpass": E["ZW_VFILTER_LOWPASS"],
                   "average": E["ZW_VFILTER_AVERAGE"]}
        return self.LoopSpec(delay, kinds.get(differentiator, differentiator),
                             filters.get(filter, filter), pole, average)

    def lowpass_pole(self, f_c, T):
        a = self.real(7.0)
        return self.loop_fn["zw_loop_lowpass_pole"](f_c, T, byref(a)), a.value

    def loop(self, co, spec):
        """(status, zw_loop) for coefficients co and a LoopSpec.  The struct sits in front
        of a guard area that must stay untouched: a mirror of zw_loop smaller than the C
        struct (a field added to loop.h and not here) fails here instead of corrupting the
        heap."""

        class Guarded(ctypes.Structure):
            _fields_ = [("loop", self.Loop), ("guard", ctypes.c_ubyte * 256)]

        g = Guarded()
        ctypes.memset(byref(g), SENTINEL, ctypes.sizeof(g))
        st = self.loop_fn["zw_loop_init"](byref(g.loop), byref(co), byref(spec))
        assert bytes(g.guard) == bytes([SENTINEL]) * 256, "zw_loop is larger than its ctypes mirror"
        lp = self.Loop()
        ctypes.memmove(byref(lp), byref(g.loop), ctypes.sizeof(lp))
        return st, lp

    def ws_intact(self):
        """The guard behind the workspace mirror is untouched (the mirror is large enough)."""
        return bytes(self.ws.guard) == bytes([SENTINEL]) * 256

    def loop_poly(self, lp, alpha, beta):
        p = (self.real * LOOP_N)()
        deg = ctypes.c_uint(99)
        st = self.loop_fn["zw_loop_poly"](byref(lp), alpha, beta, p, byref(deg))
        return st, list(p)[: deg.value + 1]

    def loop_check(self, lp, alpha, beta):
        v = self.LoopVerdict()
        ctypes.memset(byref(v), SENTINEL, ctypes.sizeof(v))
        st = self.loop_fn["zw_loop_check"](byref(lp), byref(self.ws), alpha, beta, byref(v))
        assert self.ws_intact(), "zw_loop_workspace is larger than its ctypes mirror"
        return st, v

    def loop_check_many(self, lp, alphas, betas):
        """zw_loop_check over arrays: (status, stable, marginal, deciding, theta) arrays."""
        n = len(alphas)
        st = np.empty(n, np.int32)
        stab = np.empty(n, bool)
        marg = np.empty(n, bool)
        dec = np.empty(n, np.int32)
        th = np.empty(n)
        v = self.LoopVerdict()
        pv, pl, pw, fn = byref(v), byref(lp), byref(self.ws), self.loop_fn["zw_loop_check"]
        for i, (a, b) in enumerate(zip(np.asarray(alphas).tolist(), np.asarray(betas).tolist())):
            st[i] = fn(pl, pw, a, b, pv)
            stab[i], marg[i], dec[i], th[i] = v.stable, v.marginal, v.deciding, v.theta
        return st, stab, marg, dec, th

    def loop_is_stable(self, lp, alpha, beta):
        """(status, bool): the fast path, zw_loop_is_stable."""
        s = c_bool(True)
        return self.loop_fn["zw_loop_is_stable"](byref(lp), byref(self.ws), alpha, beta, byref(s)), s.value

    def loop_radius_within(self, lp, alpha, beta, r):
        w = c_bool(True)
        return self.loop_fn["zw_loop_radius_within"](byref(lp), byref(self.ws), alpha, beta, r, byref(w)), w.value

    def loop_spectral_radius(self, lp, alpha, beta):
        rho, th = self.real(-1.0), self.real(-1.0)
        st = self.loop_fn["zw_loop_spectral_radius"](byref(lp), byref(self.ws), alpha, beta, byref(rho), byref(th))
        return st, rho.value, th.value

    # -- extremes.h ----------------------------------------------------------------------

    def extremes(self, co):
        self._begin()
        x = self._out(self.Extremes, "zero")
        return self.lib.zw_extremes_compute(byref(co), byref(x)), x

    def hyperbola_top(self, co):
        self._begin()
        a, b = self._out(self.real, "zero"), self._out(self.real, "zero")
        return self.lib.zw_hyperbola_top(byref(co), byref(a), byref(b)), a.value, b.value

    def corner(self, co):
        self._begin()
        a, b = self._out(self.real, "zero"), self._out(self.real, "zero")
        return self.lib.zw_corner(byref(co), byref(a), byref(b)), a.value, b.value

    def alpha_max(self, co, beta):
        self._begin()
        a = self._out(self.real, "zero")
        return self.lib.zw_alpha_max(byref(co), beta, byref(a)), a.value

    def beta_interval(self, co, alpha):
        self._begin()
        lo, hi, ne = self._out(self.real, "zero"), self._out(self.real, "zero"), self._out(c_bool, "false")
        st = self.lib.zw_beta_interval(byref(co), alpha, byref(lo), byref(hi), byref(ne))
        return st, lo.value, hi.value, ne.value

    # -- device.h ------------------------------------------------------------------------

    def device(self, m, b, T):
        self._begin()
        d = self._out(self.Device, "nan")
        return self.lib.zw_device_init(byref(d), m, b, T), d

    def device_normalize(self, d, K, B):
        self._begin()
        a, b = self._out(self.real, "nan"), self._out(self.real, "nan")
        return self.lib.zw_device_normalize(byref(d), K, B, byref(a), byref(b)), a.value, b.value

    def device_check(self, d, K, B):
        self._begin()
        v = self._out(self.Verdict, "verdict")
        return self.lib.zw_device_check(byref(d), K, B, byref(v)), v

    def device_check_region(self, region, d, K, B):
        self._begin()
        v = self._out(self.Verdict, "verdict")
        return self.lib.zw_device_check_region(region, byref(d), K, B, byref(v)), v

    def device_spectral_radius(self, d, K, B):
        self._begin()
        rho = self._out(self.real, "inf")
        return self.lib.zw_device_spectral_radius(byref(d), K, B, byref(rho)), rho.value

    def device_radius_within(self, d, K, B, r):
        self._begin()
        w = self._out(c_bool, "false")
        return self.lib.zw_device_radius_within(byref(d), K, B, r, byref(w)), w.value

    def device_extremes(self, d):
        self._begin()
        x = self._out(self.DeviceExtremes, "zero")
        return self.lib.zw_device_extremes_compute(byref(d), byref(x)), x

    def device_k_max(self, d, B):
        self._begin()
        k = self._out(self.real, "zero")
        return self.lib.zw_device_k_max(byref(d), B, byref(k)), k.value

    def device_b_range(self, d, K):
        self._begin()
        lo, hi, ne = self._out(self.real, "zero"), self._out(self.real, "zero"), self._out(c_bool, "false")
        st = self.lib.zw_device_b_range(byref(d), K, byref(lo), byref(hi), byref(ne))
        return st, lo.value, hi.value, ne.value

    def device_influence(self, d):
        self._begin()
        x = self._out(self.Influence, "influence")
        return self.lib.zw_device_influence(byref(d), byref(x)), x


_LOADED = {}


def load(name):
    if name not in _LOADED:
        _LOADED[name] = ZW(name)
    return _LOADED[name]


@pytest.fixture(scope="session", params=["double", "float"])
def zw(request):
    """The library in one precision (the whole suite runs once per precision)."""
    return load(request.param)
