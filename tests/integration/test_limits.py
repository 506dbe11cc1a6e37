# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zwidth-limits (the main job, tools/demo.sh): the ideal loop's limits and those with a
delay, the verdict of a gain pair for the loop the drive runs, and its option names and
exit statuses, which are those of the Python `zwidth` command (nothing filled in)."""
import re
import subprocess

import pytest

from zwmb_harness import _binary

LIMITS = _binary("zwidth-limits")
pytestmark = pytest.mark.skipif(LIMITS is None, reason="zwidth-limits not built")

PAPER = ["--J", "85.78e-7", "--b", "2.197e-3", "--T", "0.02"]
# Stable for the paper's ideal loop (spectral radius 0.947), not with one sample of delay.
PAIR = ["--K", "0.39", "--B", "-1.36e-3"]


def run(*args):
    return subprocess.run([str(LIMITS), *args], capture_output=True, text=True, timeout=60)


def k_mmax_lines(text):
    """The K_mmax of each limits section (ideal, then delayed), not the legacy claim."""
    return [float(v) for v in re.findall(r"^\s+K_mmax\s+=\s+(\S+) ", text, flags=re.M)]


def test_default_reports_the_delayed_loop_beside_the_ideal():
    r = run("--preset", "paper-drive")
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


@pytest.mark.parametrize("bad, status", [("9", 3), ("-1", 3), ("1.5", 2), ("x", 2)])
def test_bad_delay_is_refused(bad, status):
    r = run(*PAPER, "--delay", bad)
    assert r.returncode == status and "--delay" in r.stderr and r.stdout == ""


@pytest.mark.parametrize("args, named", [
    ([], "--m (or --J), --b, --T"),
    (["--m", "0.12", "--b", "0.8"], "--T"),
    (["--J", "1e-5", "--T", "1e-3"], "--b"),
])
def test_nothing_is_filled_in(args, named):
    """The paper's drive is used only when asked for; a missing value is a usage error
    naming the option (as `zwidth limits`)."""
    r = run(*args)
    assert r.returncode == 2 and r.stdout == ""
    assert f"the plant needs {named}" in r.stderr


def test_gains_come_in_pairs_and_have_zwidths_names():
    r = run(*PAPER, "--K", "0.39")
    assert r.returncode == 2 and "both --K and --B" in r.stderr
    r = run(*PAPER, "--K", "0.39", "--B_gain", "0")
    assert r.returncode == 2 and "--B_gain is now --B" in r.stderr
    r = run(*PAPER, "--m", "1e-5")
    assert r.returncode == 2 and "not allowed with argument --J" in r.stderr


@pytest.mark.parametrize("args, option", [
    (["--m", "-0.12", "--b", "0.8", "--T", "1e-3"], "--m"),
    (["--J", "1e-5", "--b", "-1", "--T", "1e-3"], "--b"),
    (["--m", "0.12", "--b", "0.8", "--T", "0"], "--T"),
])
def test_invalid_values_exit_3_naming_the_option(args, option):
    r = run(*args)
    assert r.returncode == 3 and f"invalid value of {option}" in r.stderr and r.stdout == ""


def test_preset_is_said_and_options_override_it():
    r = run("--preset", "paper-drive", "--T", "0.008", "--delay", "0")
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("Preset paper-drive")
    assert "T = 0.008 s" in r.stdout and "N m/rad" in r.stdout
    assert run("--preset", "other").returncode == 2


def test_exit_status_1_for_an_unstable_pair_as_zwidth_check():
    r = run(*PAPER, "--K", "0.5", "--B", "-1.36e-3")  # above K_max(B) = 0.49275
    assert r.returncode == 1 and "UNSTABLE" in r.stdout


@pytest.mark.parametrize("args", [
    [],
    ["--m", "0.12", "--b", "0.8"],
    ["--preset", "paper-drive"],
    ["--preset", "paper-drive", "--K", "0.39", "--B", "-1.36e-3"],
    ["--preset", "paper-drive", "--K", "0.5", "--B", "-1.36e-3"],
    ["--preset", "paper-drive", "--K", "0.39", "--B", "-1.36e-3", "--delay", "1"],
    ["--preset", "paper-drive", "--K", "0.39"],
    ["--m", "-0.12", "--b", "0.8", "--T", "1e-3"],
    ["--m", "0.12", "--b", "0.8", "--T", "1e-3", "--delay", "9"],
    ["--m", "0.12", "--b", "0.8", "--T", "1e-3", "--delay", "x"],
])
def test_same_exit_status_as_the_python_command(args, capsys):
    """One set of names and exit statuses: zwidth-limits exits as `zwidth check` (with
    gains) or `zwidth limits` (without) given the same options."""
    cli = pytest.importorskip("zwidth.cli")
    command = "check" if "--K" in args else "limits"
    try:
        python_status = cli.main([command, *args])
    except SystemExit as exc:  # argparse's usage errors
        python_status = exc.code
    capsys.readouterr()
    assert run(*args).returncode == python_status
