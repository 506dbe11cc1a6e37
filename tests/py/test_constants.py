# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The critical constants of extremes.h, re-derived by root finding at 60 digits.

Each constant is solved from its defining equation (reference.constants(): findroot on
(1 + d)(1 + e^-d)^2 = 4, beta1 = beta2, beta2 = 0, d/dd[alpha_mmax/d] = 0, ...) and compared
with the decimal string in csrc/include/zwidth/extremes.h to 1e-20 relative.  A second set
of tests checks that each root really is what its comment says (a local min, a sign change,
an independent characterisation), so a root-finder landing on the wrong root would fail.
"""
import mpmath
import pytest
from mpmath import mp, mpf

import reference as ref
from conftest import DEFINES

HEADER_NAMES = {
    "ZW_DELTA0": "delta0",
    "ZW_DELTA1": "delta1",
    "ZW_DELTA2": "delta2",
    "ZW_DELTA_K1": "deltaK1",
    "ZW_DELTA_K2": "deltaK2",
    "ZW_DELTA_B": "deltaB",
    "ZW_DELTA_KM": "deltaKM",
    "ZW_DELTA_BB": "deltaBb",
    "ZW_KMAX_LOCAL_MAX": "kmax_local_max",
    "ZW_KMAX_LOCAL_MIN": "kmax_local_min",
}


@pytest.mark.parametrize("name", sorted(HEADER_NAMES))
def test_header_constant_matches_root(name):
    """The header's decimal value agrees with the re-derived root to 1e-20 relative."""
    assert name in DEFINES, f"{name} missing from the public headers"
    exact = ref.constants()[HEADER_NAMES[name]]
    header = mpf(DEFINES[name])
    rel = abs(header - exact) / abs(exact)
    print(f"{name}: header {DEFINES[name]}  root {mpmath.nstr(exact, 30)}  rel diff {mpmath.nstr(rel, 3)}")
    assert rel < mpf("1e-20"), f"{name}: header {DEFINES[name]} vs root {mpmath.nstr(exact, 30)} (rel {rel})"


def test_roots_are_accurate_to_40_digits():
    """Solving again at 90 digits moves no constant by more than 1e-40 relative (so the 60-digit
    roots used above are good to 40+ digits)."""
    lo = ref.constants()
    with mp.workdps(90):
        d0 = mp.findroot(lambda d: (1 + d) * (1 + mp.exp(-d)) ** 2 - 4, lo["delta0"])
        d2 = mp.findroot(lambda d: ref.corner(d)[1], lo["delta2"])
        dK2 = mp.findroot(lambda d: mp.diff(lambda x: ref.corner(x)[0] / x, d), lo["deltaK2"])
    for hi, name in ((d0, "delta0"), (d2, "delta2"), (dK2, "deltaK2")):
        assert abs(hi - lo[name]) / hi < mpf("1e-40"), name


def test_delta0_is_where_the_line_reaches_the_hyperbola_end():
    """delta0 also solves 2/c2 = 2(1+e)/d12 (the line's alpha = 0 end meets the hyperbola's
    right end, eq (32)): an independent characterisation of the same root."""
    d0 = ref.constants()["delta0"]
    co = ref.coeffs(d0)
    assert abs(2 / co.c2 - 2 * (1 + co.e) / co.d12) < mpf("1e-40")
    for d in (d0 * (1 - mpf("1e-6")), d0 * (1 + mpf("1e-6"))):
        co = ref.coeffs(d)
        line_bites = 2 * (1 + co.e) / co.d12 < 2 / co.c2
        assert line_bites == (d > d0)


def test_delta1_delta2_order_and_meaning():
    """delta0 < delta1 < delta2; at delta1 the top of the hyperbola and the corner coincide
    (alpha1 = alpha2 too); at delta2 beta_at_alpha_mmax changes sign and f(0) = L(0)."""
    k = ref.constants()
    assert k["delta0"] < k["delta1"] < k["delta2"]
    a1, b1 = ref.hyperbola_top(k["delta1"])
    a2, b2 = ref.corner(k["delta1"])
    assert abs(a1 - a2) / a1 < mpf("1e-40") and abs(b1 - b2) < mpf("1e-40")
    eps = mpf("1e-8")
    assert ref.extremes(k["delta2"] * (1 - eps))["beta_at"] > 0
    assert ref.extremes(k["delta2"] * (1 + eps))["beta_at"] < 0
    assert abs(ref.f_hyperbola(k["delta2"], 0) - ref.line(k["delta2"], 0)) < mpf("1e-40")


def test_deltaK_are_local_min_and_max_of_alpha_mmax_over_delta():
    """alpha_mmax/delta has a local min at deltaK1 (< delta1, hyperbola branch) and a local
    max at deltaK2 (> delta1, corner branch) with the header's values; deltaKM < deltaK1
    is where the curve climbs back to the local max."""
    k = ref.constants()
    ratio = lambda d: ref.extremes(d)["alpha_mmax"] / d  # noqa: E731
    h = mpf("1e-4")
    assert k["deltaK1"] < k["delta1"] < k["deltaK2"]
    assert ratio(k["deltaK1"] - h) > ratio(k["deltaK1"]) < ratio(k["deltaK1"] + h)
    assert ratio(k["deltaK2"] - h) < ratio(k["deltaK2"]) > ratio(k["deltaK2"] + h)
    assert abs(ratio(k["deltaK1"]) - k["kmax_local_min"]) < mpf("1e-40")
    assert abs(ratio(k["deltaK2"]) - k["kmax_local_max"]) < mpf("1e-40")
    assert 0 < k["deltaKM"] < k["deltaK1"]
    assert abs(ratio(k["deltaKM"]) - k["kmax_local_max"]) < mpf("1e-40")
    # ... and it is the only crossing below deltaK1: the ratio decreases on (0, deltaK1).
    grid = [k["deltaKM"] * mpf(i) / 8 for i in range(1, 9)] + [k["deltaK1"] * mpf(i) / 8 for i in range(2, 9)]
    vals = [ratio(d) for d in sorted(grid)]
    assert all(x > y for x, y in zip(vals, vals[1:]))


def test_deltaB_is_local_min_of_beta_mmax_over_delta():
    """beta_mmax/delta (= B_mmax / b) has its local min at deltaB < delta0."""
    k = ref.constants()
    ratio = lambda d: ref.extremes(d)["beta_mmax"] / d  # noqa: E731
    h = mpf("1e-4")
    assert k["deltaB"] < k["delta0"]
    assert ratio(k["deltaB"] - h) > ratio(k["deltaB"]) < ratio(k["deltaB"] + h)
