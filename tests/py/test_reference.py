# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Self-checks of the reference's binary-format helpers (reference.py).

Proves that round_to is the correctly rounded (ties-to-even, gradual underflow, overflow to
inf) conversion to float32/float64, and that ulp_distance is the ordinal distance on the
line of representable values (0 and -0 coincide, subnormals count one quantum each, the
distance across zero adds up), so the ulp figures of the other tests mean what they say.
"""
import math

import numpy as np
import pytest
from mpmath import mp, mpf

import reference as ref


@pytest.mark.parametrize("name", ["double", "float"])
def test_round_to_is_correct_rounding(name):
    """Points 0.3, 0.5 and 0.7 of the way between neighbours round to the nearest one (the
    even one on a tie), in the normal and the subnormal range, near overflow and at 0."""
    fmt = ref.FORMATS[name]
    rng = np.random.default_rng(0)
    xs = [fmt.tiny, 3 * fmt.tiny, fmt.min_normal, ref.step(fmt.min_normal, -1, fmt), 1.0, 2.0,
          ref.step(fmt.max, -1, fmt)]
    xs += [float(fmt.np_type(10.0 ** e)) for e in rng.uniform(math.log10(fmt.tiny), math.log10(fmt.max) - 1, 300)]
    for x in xs:
        y = ref.step(x, 1, fmt)
        with mp.workdps(400):
            lo, hi = mpf(x), mpf(y)
            assert ref.round_to(lo + (hi - lo) * mpf("0.3"), fmt) == x
            assert ref.round_to(lo + (hi - lo) * mpf("0.7"), fmt) == y
            even = x if ref.ordinal(x, fmt) % 2 == 0 else y
            assert ref.round_to((lo + hi) / 2, fmt) == even
            assert ref.round_to(-(lo + hi) / 2, fmt) == -even
    assert ref.round_to(0, fmt) == 0
    assert ref.round_to(mpf(fmt.tiny) / 3, fmt) == 0  # below half the smallest subnormal
    assert ref.round_to(mpf(fmt.max) * 2, fmt) == math.inf


def test_round_to_float_matches_numpy():
    """float32 rounding agrees with numpy's (correctly rounded) double -> float cast,
    subnormals included."""
    rng = np.random.default_rng(1)
    for x in list(10.0 ** rng.uniform(-46, 38.5, 2000)) + [1e-45, 7e-46, 1.1754942e-38]:
        assert ref.round_to(mpf(x), ref.FLOAT) == float(np.float32(x)), x


@pytest.mark.parametrize("name", ["double", "float"])
def test_ulp_distance_is_ordinal(name):
    """ulp_distance: 0 for -0 vs +0, 1 between neighbours (also across the subnormal /
    normal border), 2 from -tiny to +tiny, k for k steps."""
    fmt = ref.FORMATS[name]
    assert ref.ulp_distance(-0.0, 0, fmt) == 0
    assert ref.ulp_distance(fmt.tiny, -mpf(fmt.tiny), fmt) == 2
    for x in (0.0, fmt.tiny, ref.step(fmt.min_normal, -1, fmt), 1.0, -3.5, 1e30):
        for k in (1, 5, 1000):
            assert ref.ulp_distance(ref.step(x, k, fmt), mpf(x), fmt) == k
    a = np.array([0.0, fmt.tiny, 1.0, -2.0], dtype=fmt.np_type)
    assert (ref.np_ordinal(ref.np_step(a, 3, fmt), fmt) - ref.np_ordinal(a, fmt) == 3).all()
    assert ref.ulp_distance(math.nan, 1, fmt) == math.inf
