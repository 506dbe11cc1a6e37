# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zwidth-limits (the main job, tools/demo.sh): the ideal loop's limits and those with a
delay, the verdict of a gain pair for the loop the drive runs (always stated, never
assumed: --delay is required but for --preset paper-drive), and its option names and exit
statuses, which are those of the Python `zwidth` command (nothing filled in)."""
import re
import subprocess

import pytest

from zwmb_harness import _binary

LIMITS = _binary("zwidth-limits")
pytestmark = pytest.mark.skipif(LIMITS is None, reason="zwidth-limits not built")

PAPER = ["--J", "85.78e-7", "--b", "2.197e-3", "--T", "0.02"]
IDEAL = ["--delay", "0"]
# The new-user trial's haptic device (issue 24): its firmware applies the force one sample
# late and low-passes the velocity at 100 Hz.
HAPTIC = ["--m", "0.12", "--b", "0.8", "--T", "0.001"]
HAPTIC_LOOP = ["--delay", "1", "--velocity-filter", "lowpass:100Hz"]
NOT_STATED = ("the loop is not stated: give --delay N (--delay 0 for the paper's ideal loop; "
              "most firmware computes during the period and applies at the next tick: --delay 1)")
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


def test_preset_names_its_loop_on_the_first_line():
    r = run("--preset", "paper-drive")
    assert r.stdout.splitlines()[0] == ("Loop: the paper's ideal loop (delay 0, backward difference, "
                                        "no velocity filter), from --preset paper-drive")
    assert "proportional only" not in r.stdout and "(stiffness only): K < 0.357709" in r.stdout


def test_delay_zero_is_the_paper_loop_with_one_sample_beside():
    r = run("--delay", "0", *PAPER)
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[0] == ("Loop: the paper's ideal loop (delay 0, backward difference, "
                                        "no velocity filter)")
    assert "Limits with a delay of 1 sample (most firmware;" in r.stdout


@pytest.mark.parametrize("extra", [[], ["--velocity-filter", "lowpass:100Hz"], ["--K", "50000", "--B", "60"]])
def test_missing_delay_is_a_usage_error_that_says_what_to_give(extra):
    r = run(*HAPTIC, *extra)
    assert r.returncode == 2 and r.stdout == ""
    assert f"zwidth-limits: error: {NOT_STATED}" in r.stderr


def haptic_python_k_mmax():
    zwidth = pytest.importorskip("zwidth")
    return zwidth.Device(0.12, 0.8, 0.001, delay=1, velocity_filter=("lowpass", 100.0)).extremes().K_mmax


def test_trial_pair_is_unstable_in_the_loop_the_device_runs():
    """Issue 24's trial: (50000, 60) on the haptic device.  Without the loop: exit 2.  With
    the device's loop: UNSTABLE, exit 1, the loop named first, its K_mmax that of the
    Python Device for the same loop (C against Python, not a number copied here)."""
    assert run(*HAPTIC, "--K", "50000", "--B", "60").returncode == 2
    r = run(*HAPTIC, *HAPTIC_LOOP, "--K", "50000", "--B", "60")
    assert r.returncode == 1, r.stdout + r.stderr
    assert r.stdout.splitlines()[0] == ("Loop: 1 sample delay, backward difference, velocity "
                                        "low-pass 100 Hz (pole 0.533488)")
    assert re.search(r"^Gains K = 50000 N/m, B = 60 N s/m with a delay of 1 sample, velocity "
                     r"low-pass 100 Hz \(pole 0\.533488\): UNSTABLE$", r.stdout, re.M), r.stdout
    ideal, loop = k_mmax_lines(r.stdout)
    assert ideal == pytest.approx(83425, rel=1e-5)
    assert loop == pytest.approx(haptic_python_k_mmax(), rel=1e-6)
    assert "stable only in the paper's ideal loop" not in r.stdout


def test_ideal_loop_pair_unstable_with_one_sample_is_warned():
    r = run(*HAPTIC, "--delay", "0", "--K", "50000", "--B", "60")
    assert r.returncode == 0, r.stdout + r.stderr  # the verdict of the loop stated
    assert "Gains K = 50000 N/m, B = 60 N s/m: STABLE" in r.stdout
    m = re.search(r"^  with 1 sample of delay \(most firmware\): UNSTABLE, K_max\(B\) = (\S+) N/m$",
                  r.stdout, re.M)
    assert m, r.stdout
    assert re.search(r"^warning: this pair is stable only in the paper's ideal loop", r.stdout, re.M)
    zwidth = pytest.importorskip("zwidth")
    assert float(m.group(1)) == pytest.approx(float(zwidth.Device(0.12, 0.8, 0.001, delay=1).k_max(60.0)),
                                              rel=1e-5)
    # a pair stable with the delay too: no warning
    r = run(*HAPTIC, "--delay", "0", "--K", "500", "--B", "0")
    assert r.returncode == 0 and "with 1 sample of delay (most firmware): STABLE" in r.stdout
    assert "warning" not in r.stdout


@pytest.mark.parametrize("spec, words", [
    ("lowpass:1.5kHz", None),  # above Nyquist (500 Hz): invalid value, exit 3
    ("average:4", "velocity moving average of 4 samples"),
    ("pole:0.533488", "velocity low-pass pole 0.533488"),
    ("none", "no velocity filter"),
])
def test_velocity_filter_spelling_is_the_python_clis(spec, words):
    r = run(*HAPTIC, "--delay", "1", "--velocity-filter", spec)
    if words is None:
        assert r.returncode == 3 and "--velocity-filter" in r.stderr, r.stderr
        return
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[0] == f"Loop: 1 sample delay, backward difference, {words}"


def test_tustin_and_bad_filter_spellings():
    r = run(*HAPTIC, "--delay", "0", "--differentiator", "tustin")
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[0] == "Loop: no delay, tustin differentiator, no velocity filter"
    assert "Limits with no delay, tustin differentiator (the loop stated;" in r.stdout
    for bad in ("lowpass:100rad/s", "lowpass", "median:3"):
        r = run(*HAPTIC, "--delay", "1", "--velocity-filter", bad)
        assert r.returncode == 2 and "--velocity-filter" in r.stderr and r.stdout == ""
    assert run(*HAPTIC, "--delay", "1", "--differentiator", "forward").returncode == 2


def test_pair_verdict_follows_the_loop_the_drive_runs():
    ideal = run(*PAPER, *IDEAL, *PAIR)
    assert ideal.returncode == 0 and "STABLE" in ideal.stdout
    delayed = run(*PAPER, "--delay", "1", *PAIR)
    assert delayed.returncode == 1, delayed.stdout + delayed.stderr
    assert "with a delay of 1 sample: UNSTABLE" in delayed.stdout
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
    r = run(*PAPER, *IDEAL, "--K", "0.39")
    assert r.returncode == 2 and "both --K and --B" in r.stderr
    r = run(*PAPER, *IDEAL, "--K", "0.39", "--B_gain", "0")
    assert r.returncode == 2 and "--B_gain is now --B" in r.stderr
    r = run(*PAPER, *IDEAL, "--m", "1e-5")
    assert r.returncode == 2 and "not allowed with argument --J" in r.stderr


@pytest.mark.parametrize("args, option", [
    (["--m", "-0.12", "--b", "0.8", "--T", "1e-3"], "--m"),
    (["--J", "1e-5", "--b", "-1", "--T", "1e-3"], "--b"),
    (["--m", "0.12", "--b", "0.8", "--T", "0"], "--T"),
])
def test_invalid_values_exit_3_naming_the_option(args, option):
    r = run(*args, *IDEAL)
    assert r.returncode == 3 and f"invalid value of {option}" in r.stderr and r.stdout == ""


def test_preset_is_said_and_options_override_it():
    r = run("--preset", "paper-drive", "--T", "0.008", "--delay", "0")
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[1].startswith("Preset paper-drive")
    # a loop option given: the loop is the user's, not said to come from the preset
    assert "from --preset" not in r.stdout.splitlines()[0]
    assert "T = 0.008 s" in r.stdout and "N m/rad" in r.stdout
    assert run("--preset", "other").returncode == 2


def test_exit_status_1_for_an_unstable_pair_as_zwidth_check():
    r = run(*PAPER, *IDEAL, "--K", "0.5", "--B", "-1.36e-3")  # above K_max(B) = 0.49275
    assert r.returncode == 1 and "UNSTABLE" in r.stdout


@pytest.mark.parametrize("args", [
    [],
    ["--m", "0.12", "--b", "0.8"],
    ["--preset", "paper-drive"],
    ["--preset", "paper-drive", "--K", "0.39", "--B", "-1.36e-3"],
    ["--preset", "paper-drive", "--K", "0.5", "--B", "-1.36e-3"],
    ["--preset", "paper-drive", "--K", "0.39", "--B", "-1.36e-3", "--delay", "1"],
    ["--preset", "paper-drive", "--K", "0.39"],
    ["--m", "-0.12", "--b", "0.8", "--T", "1e-3", "--delay", "0"],
    ["--m", "0.12", "--b", "0.8", "--T", "1e-3"],
    ["--m", "0.12", "--b", "0.8", "--T", "1e-3", "--K", "50000", "--B", "60"],
    ["--m", "0.12", "--b", "0.8", "--T", "1e-3", "--K", "50000", "--B", "60", "--delay", "1",
     "--velocity-filter", "lowpass:100Hz"],
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
