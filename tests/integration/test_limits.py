# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zwidth-limits (the main job, tools/demo.sh): the ideal loop's limits and those with a
delay, the verdict of a gain pair for the loop the drive runs, and its exit statuses."""
import re
import subprocess

import pytest

from zwmb_harness import _binary

LIMITS = _binary("zwidth-limits")
pytestmark = pytest.mark.skipif(LIMITS is None, reason="zwidth-limits not built")

PAPER = ["--m", "85.78e-7", "--b", "2.197e-3", "--T", "0.02"]
# Stable for the paper's ideal loop (spectral radius 0.947), not with one sample of delay.
PAIR = ["--K", "0.39", "--B_gain", "-1.36e-3"]


def run(*args):
    return subprocess.run([str(LIMITS), *args], capture_output=True, text=True, timeout=60)


def k_mmax_lines(text):
    """The K_mmax of each limits section (ideal, then delayed), not the legacy claim."""
    return [float(v) for v in re.findall(r"^\s+K_mmax\s+=\s+(\S+) at", text, flags=re.M)]


def test_default_reports_the_delayed_loop_beside_the_ideal():
    r = run()
    assert r.returncode == 0, r.stderr
    assert "Limits with a delay of 1 sample" in r.stdout
    ideal, delayed = k_mmax_lines(r.stdout)
    assert ideal == pytest.approx(0.493379, rel=1e-6)  # paper: 0.4934 N m/rad
    # the paper's drive keeps about a fifth of its stiffness with one sample of delay
    # (alpha_mmax 23.00674 -> 4.98123 against mpmath in tests/py/test_loop_limits_reference.py)
    assert delayed == pytest.approx(ideal * 4.98123 / 23.00674, rel=1e-4)
    assert re.search(r"21\.6\d % of the ideal loop's", r.stdout)


def test_delay_zero_is_the_paper_alone():
    r = run("--delay", "0", *PAPER)
    assert r.returncode == 0 and "delay" not in r.stdout


def test_pair_verdict_follows_the_loop_the_drive_runs():
    ideal = run(*PAPER, *PAIR)
    assert ideal.returncode == 0 and "STABLE" in ideal.stdout
    delayed = run(*PAPER, "--delay", "1", *PAIR)
    assert delayed.returncode == 1, delayed.stdout + delayed.stderr
    assert "with a delay of 1: UNSTABLE" in delayed.stdout
    assert re.search(r"oscillation at 9\.1\d* Hz", delayed.stdout)
    two = run(*PAPER, "--delay", "2")
    assert "Limits with a delay of 2 samples" in two.stdout
    assert k_mmax_lines(two.stdout)[1] < k_mmax_lines(delayed.stdout)[1]


@pytest.mark.parametrize("bad", ["9", "-1", "1.5", "x"])
def test_bad_delay_is_refused(bad):
    r = run("--delay", bad)
    assert r.returncode == 2 and "--delay" in r.stderr and r.stdout == ""
