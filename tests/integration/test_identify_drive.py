# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zwidth-drive --simulate --identify: the firmware's experiment (ident.h) played on the
simulated plant, then ``zwidth identify`` on its log: the box holds the simulated plant and
the gains it certifies are stable on it; the firmware's limits trip the run and refuse a
request beyond its ceilings."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from zwmb_harness import DRIVE

pytest.importorskip("scipy")
zwidth = pytest.importorskip("zwidth")


def _drive(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(DRIVE), "--simulate", *args], capture_output=True, text=True, timeout=60)


@pytest.mark.parametrize("m, b, T, delay, counts", [
    (0.1, 2.0, 1e-3, 1, 20000.0),      # a haptic device, 1 sample of delay, an encoder
    (85.78e-7, 2.197e-3, 0.02, 0, 0.0),  # the paper's drive (rotary units), ideal loop
    (0.5, 0.3, 5e-4, 2, 0.0),          # a slow, lightly damped drive, 2 samples
])
def test_identify_the_simulated_drive(tmp_path: Path, m: float, b: float, T: float, delay: int,
                                      counts: float) -> None:
    log = tmp_path / "run.csv"
    amplitude = 20 * b * 0.01 if m > 1e-3 else 2e-3
    hold = max(1, min(50, int(0.1 * m / (b * T))))
    args = ["--m", repr(m), "--b", repr(b), "--T", repr(T), "--delay", str(delay), "--x0", "0",
            "--identify", str(log), "--amplitude", repr(amplitude), "--samples", "4000", "--hold", str(hold),
            "--x-window", "10", "--v-max", "100"]
    if counts:
        args += ["--counts-per-unit", repr(counts)]
    run = _drive(*args)
    assert run.returncode == 0, run.stderr
    assert "identification done: 4000 samples" in run.stderr
    cmd = [sys.executable, "-m", "zwidth", "identify", str(log), "--time", "t", "--json"]
    if counts:
        cmd += ["--counts-per-unit", repr(counts)]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr + out.stdout
    data = json.loads(out.stdout)
    assert data["identification"]["delay"] == delay
    (m_lo, m_hi), (b_lo, b_hi) = data["box"]["m"], data["box"]["b"]
    assert m_lo <= m <= m_hi and b_lo <= b <= b_hi
    # the gains the box certifies hold on the plant the drive simulated
    true = zwidth.Device(m, b, T, delay=delay)
    K, B = 0.999 * data["limits"]["K_mmax"], data["limits"]["B_at"]
    assert true.is_stable(K, B)


def test_limits_trip_and_ceilings_refuse(tmp_path: Path) -> None:
    log = tmp_path / "run.csv"
    plant = ["--m", "0.1", "--b", "2", "--T", "1e-3", "--delay", "1", "--x0", "0"]
    tripped = _drive(*plant, "--identify", str(log), "--amplitude", "5", "--x-window", "0.01")
    assert tripped.returncode == 1 and "left the position window" in tripped.stderr
    rows = [r for r in log.read_text().splitlines() if r and not r.startswith(("#", "t,"))]
    n = int(tripped.stderr.split("tripped after ")[1].split()[0])
    assert len(rows) == n and 0 < n < 4000
    # the recorded positions stay in the window; the sample that left it is not logged
    assert all(abs(float(r.split(",")[2])) <= 0.01 for r in rows)
    fast = _drive(*plant, "--identify", str(log), "--amplitude", "5", "--v-max", "0.05")
    assert fast.returncode == 1 and "velocity limit" in fast.stderr
    refused = _drive(*plant, "--identify", str(log), "--amplitude", "5", "--amplitude-max", "2")
    assert refused.returncode == 2 and "refused by the firmware" in refused.stderr
    no_sim = subprocess.run([str(DRIVE), *plant, "--identify", str(log)], capture_output=True, text=True,
                            timeout=60)
    assert no_sim.returncode == 2 and "--simulate" in no_sim.stderr
