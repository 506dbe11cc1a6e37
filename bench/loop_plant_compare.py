# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""The general loop on a zw_plant against the library before it (issue 16): the ideal plant
must give the same verdicts and limits (or better).  Loads two builds' shared libraries by
ctypes with opaque buffers for zw_loop and its workspace (their layouts differ):

    python3 bench/loop_plant_compare.py OLD_BUILD_DIR NEW_BUILD_DIR [N_LOOPS] [--verify]

(--verify: every verdict mismatch against tests/py/loop_reference.py at 60 digits; needs mpmath)

Prints, per precision: verdict mismatches (and how many of them either side called
marginal), alpha_max ratios new/old, extremes ratios."""
import ctypes
import math
import random
import sys
from ctypes import byref, c_bool, c_int, c_uint

BUF = 1 << 15


def load(path, real, suffix):
    lib = ctypes.CDLL(path)

    class Coeffs(ctypes.Structure):
        _fields_ = [(n, real) for n in ("delta", "e", "c1", "c2", "d12", "s", "g", "sigma", "hs",
                                        "delta_relerr")]

    class Spec(ctypes.Structure):
        _fields_ = [("delay", c_uint), ("differentiator", c_int), ("filter", c_int),
                    ("filter_pole", real), ("average", c_uint)]

    class Verdict(ctypes.Structure):
        _fields_ = [("stable", c_bool), ("marginal", c_bool), ("deciding", c_int), ("theta", real)]

    class Ext(ctypes.Structure):
        _fields_ = [(n, real) for n in ("alpha_mmax", "beta_at_alpha_mmax", "alpha_p_max",
                                        "beta_mmax", "beta_mmin")]

    f = lambda n: getattr(lib, n + suffix)
    return lib, Coeffs, Spec, Verdict, Ext, f


class Lib:
    def __init__(self, build, prec):
        real = ctypes.c_float if prec == "f" else ctypes.c_double
        name = f"{build}/libzwidth_{prec}_shared.so"
        self.real = real
        self.lib, self.Coeffs, self.Spec, self.Verdict, self.Ext, f = load(name, real, "_f" if prec == "f" else "")
        self.coeffs_init = f("zw_coeffs_init")
        self.loop_init = f("zw_loop_init")
        self.check = f("zw_loop_check")
        self.amax = f("zw_loop_alpha_max")
        self.ext = f("zw_loop_extremes_compute")
        self.check.argtypes = [ctypes.c_void_p, ctypes.c_void_p, real, real, ctypes.c_void_p]
        self.amax.argtypes = [ctypes.c_void_p, ctypes.c_void_p, real, ctypes.c_void_p]
        self.coeffs_init.argtypes = [ctypes.c_void_p, real]
        self.loop = ctypes.create_string_buffer(BUF)
        self.ws = ctypes.create_string_buffer(BUF)

    def build(self, delta, spec):
        co = self.Coeffs()
        assert self.coeffs_init(byref(co), delta) == 0
        sp = self.Spec(*spec)
        return self.loop_init(self.loop, byref(co), byref(sp))

    def verdict(self, a, b):
        v = self.Verdict()
        st = self.check(self.loop, self.ws, a, b, byref(v))
        return st, v.stable, v.marginal

    def alpha_max(self, b):
        r = self.real(0)
        st = self.amax(self.loop, self.ws, b, byref(r))
        return st, r.value

    def extremes(self):
        e = self.Ext()
        st = self.ext(self.loop, self.ws, byref(e))
        return st, (e.alpha_mmax, e.alpha_p_max, e.beta_mmax, e.beta_mmin)


def random_spec(rng):
    d = rng.randint(0, 8)
    diff = rng.randint(0, 1)
    filt = rng.choice([0, 0, 1, 2])
    pole = rng.choice([0.0, 0.3, 0.8, 0.95]) if filt == 1 else 0.0
    avg = rng.randint(1, 16 if rng.random() < 0.3 else 4) if filt == 2 else 0
    if filt == 2 and diff == 1 and avg % 2 == 0:
        avg += 1
    return (d, diff, filt, pole, avg)


def verify(mismatches):
    """Each mismatch against the 60-digit reference of tests/py/loop_reference.py (the loop's
    state-space definition): the side that says stable must be right."""
    import os
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "py"))
    import loop_reference as lr
    wrong = 0
    for prec, delta, (d, diff, filt, pole, avg), a, b, new_stable in mismatches:
        kw = dict(delay=d, differentiator=("backward", "tustin")[diff],
                  filter=("none", "lowpass", "average")[filt], pole=pole, average=avg or 1)
        parts = lr.loop_parts(delta, **kw)
        stable, _ = lr.schur_stable(lr.loop_poly(parts, a, b), dps=60)
        if new_stable and not stable:
            wrong += 1
            print(f"  WRONG: {prec} delta={delta!r} spec={(d, diff, filt, pole, avg)} alpha={a!r} beta={b!r}")
    print(f"mismatches verified against the 60-digit reference: {len(mismatches)}, wrong 'stable': {wrong}")


mismatches = []


def main():
    old_dir, new_dir = sys.argv[1], sys.argv[2]
    n_loops = int(sys.argv[3]) if len(sys.argv) > 3 and sys.argv[3].isdigit() else 200
    for prec in ("d", "f"):
        old, new = Lib(old_dir, prec), Lib(new_dir, prec)
        rng = random.Random(16)
        checks = mism = mism_marg = new_stable = 0
        amax_n = amax_lower = amax_higher = 0
        worst_lo = worst_hi = 0.0
        ext_n = ext_diff = ext_better = 0
        ext_worst = 0.0
        for i in range(n_loops):
            delta = 10 ** rng.uniform(-4, 2)
            spec = random_spec(rng)
            s1, s2 = old.build(delta, spec), new.build(delta, spec)
            assert s1 == s2, (delta, spec, s1, s2)
            if s1 != 0:
                continue
            betas = [rng.uniform(-delta, 3 * (1 + delta)) for _ in range(4)] + [0.0]
            for b in betas:
                (sa, a_old), (sb, a_new) = old.alpha_max(b), new.alpha_max(b)
                assert sa == sb == 0
                amax_n += 1
                if a_old > 0 or a_new > 0:
                    r = a_new / a_old - 1 if a_old > 0 else math.inf
                    if r < 0:
                        amax_lower += 1
                        worst_lo = min(worst_lo, r)
                    elif r > 0:
                        amax_higher += 1
                        worst_hi = max(worst_hi, r)
                scale = max(a_old, a_new, 0.01)
                for _ in range(6):
                    a = scale * rng.uniform(0.0, 1.6)
                    if rng.random() < 0.3:  # near the limit
                        a = scale * (1 + rng.choice([-1, 1]) * 10 ** rng.uniform(-12, -2))
                    vo, vn = old.verdict(a, b), new.verdict(a, b)
                    checks += 1
                    if vo[1] != vn[1]:
                        mism += 1
                        new_stable += vn[1]
                        r = lambda x: float(new.real(x).value)  # the values the library was given
                        mismatches.append((prec, r(delta), spec, r(a), r(b), vn[1]))
                        if vo[2] or vn[2]:
                            mism_marg += 1
                        else:
                            print(f"  {prec} mismatch outside the band: delta={delta!r} spec={spec} "
                                  f"alpha={a!r} beta={b!r} old={vo} new={vn}")
            if i % 4 == 0:
                (so, eo), (sn, en) = old.extremes(), new.extremes()
                assert so == sn, (so, sn)
                ext_n += 1
                for k, (x, y) in enumerate(zip(eo, en)):
                    if x != y:
                        ext_diff += 1
                        ext_better += (y < x) if k == 3 else (y > x)  # beta_mmin: lower is wider
                        ext_worst = max(ext_worst, abs(y - x) / max(abs(x), 1e-300))
        print(f"{prec}: {checks} checks, {mism} verdict mismatches ({new_stable} stable only in the new, "
              f"{mism_marg} marginal on one side, {mism - mism_marg} outside the band); alpha_max at {amax_n} betas: "
              f"{amax_lower} lower (worst {worst_lo:.2e}), {amax_higher} higher (worst {worst_hi:.2e}); "
              f"extremes of {ext_n} loops: {ext_diff} fields differ ({ext_better} of them wider in the new; worst rel {ext_worst:.2e})")


if __name__ == "__main__":
    main()
    if "--verify" in sys.argv:
        verify(mismatches)
