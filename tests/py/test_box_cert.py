# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Box certificates from Python (PlantBox.certificate, box_cert.h) against mpmath.

* Every claim of a certificate of the paper drive +-5 % with one sample of delay holds at
  50 digits: on a grid of plants and B in each step, the level and half of it are Schur
  stable (the closed loop's characteristic polynomial from loop_reference, built from expm).
* Float and double certificates verify in their own precision; a damaged one is refused
  with its fault; a B range with an unprovable step and bad arguments raise clearly.
* `zwidth limits` with plant ranges prints the drive's certificate.
"""
from __future__ import annotations

import json
import subprocess
import sys

import pytest
from mpmath import mpf

import zwidth
from loop_reference import loop_parts, loop_poly, schur_stable

T = 0.02
M = (0.95 * 85.78e-7, 1.05 * 85.78e-7)
BP = (0.95 * 2.197e-3, 1.05 * 2.197e-3)


@pytest.fixture(scope="module")
def delay_box():
    return zwidth.PlantBox(M, BP, T, delay=1)


@pytest.fixture(scope="module")
def delay_cert(delay_box):
    return delay_box.certificate((-1e-3, 2e-3))


def test_claims_hold_at_50_digits(delay_cert):
    c = delay_cert
    assert len(c.K) == 16 and c.leaves <= 512 and c.precision == "float"
    checked = 0
    for i, (lo, hi, K, up) in enumerate(c.steps()):
        assert 0.0 < K <= up, (i, K, up)
        for m in (M[0], sum(M) / 2, M[1]):
            for b in (BP[0], BP[1]):
                parts = loop_parts(mpf(b) * T / mpf(m), delay=1)
                for B in (lo, (lo + hi) / 2, hi):
                    for frac in (1, 2):
                        alpha = mpf(K) / frac * T * T / mpf(m)
                        beta = mpf(B) * T / mpf(m)
                        stable, margin = schur_stable(loop_poly(parts, alpha, beta))
                        assert stable, (i, m, b, B, K / frac, margin)
                        checked += 1
    assert checked == 16 * 3 * 2 * 3 * 2


def test_precisions_and_damage(delay_box, delay_cert):
    assert delay_box.verify_certificate(delay_cert) == "ok"
    d = delay_box.certificate((-1e-3, 2e-3), precision="double")
    assert d.precision == "double" and delay_box.verify_certificate(d) == "ok"
    # levels raised 1.5x: some leaf cannot be proven
    raised = zwidth.BoxCertificate(d.B, tuple(1.5 * k for k in d.K), d.K_upper, d.nodes, "double", d.leaves,
                                   d.tests, 0.0, 0.0)
    assert delay_box.verify_certificate(raised) == "a leaf fails"
    short = zwidth.BoxCertificate(d.B, d.K, d.K_upper, d.nodes[:-1], "double", d.leaves, d.tests, 0.0, 0.0)
    assert delay_box.verify_certificate(short) == "bad node"
    # the same certificate for a wider box claims too much there
    wider = zwidth.PlantBox((0.5 * M[0], M[1]), BP, T, delay=1)
    assert wider.verify_certificate(d) != "ok"
    assert delay_cert.size_bytes == 648
    assert delay_cert.level(delay_cert.B[0] - 1e-9) == 0.0
    assert delay_cert.level(delay_cert.B[3]) == max(delay_cert.K[2], delay_cert.K[3])


def test_errors(delay_box):
    with pytest.raises(zwidth.ZwidthError, match=r"step [12] \(B in .* is proven at no K"):
        delay_box.certificate((-1e-3, 6e-3), steps=4, leaves=64)
    with pytest.raises(ValueError, match="precision"):
        delay_box.certificate((-1e-3, 1e-3), precision="half")
    with pytest.raises(ValueError, match="lo < hi"):
        delay_box.certificate((1e-3, -1e-3))
    with pytest.raises(ValueError, match="steps"):
        delay_box.certificate((-1e-3, 1e-3), steps=17)
    with pytest.raises(ValueError, match="leaves"):
        delay_box.certificate((-1e-3, 1e-3), leaves=513)


def test_default_range_ideal_box():
    box = zwidth.PlantBox((2e-5, 1.5e-4), 2.197e-3, T)
    c = box.certificate()
    x = box.extremes()
    assert box.verify_certificate(c) == "ok"
    # the default range is the B certified at half of K_mmax; no level above K_mmax's bracket
    assert c.B[0] < x.B_at < c.B[-1]
    assert max(c.K) <= x.K_upper_at * (1 + 1e-6)


def test_cli_limits_prints_certificate():
    args = [sys.executable, "-m", "zwidth", "limits", "--m", "8.15e-6:9.0e-6", "--b", "2.197e-3", "--T", "0.02",
            "--delay", "1"]
    p = subprocess.run(args, capture_output=True, text=True, check=True)
    assert "Drive certificate (float, 16 steps" in p.stdout
    p = subprocess.run(args + ["--json"], capture_output=True, text=True, check=True)
    cert = json.loads(p.stdout)["certificate"]
    assert len(cert["steps"]) == 16 and cert["bytes"] == 648
    assert all(0 < s["K"] <= s["K_upper"] for s in cert["steps"])
