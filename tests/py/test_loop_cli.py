# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The loop options of the command line: --delay, --velocity-filter, --differentiator.
Run as a user runs them (the installed entry point); numbers equal to the Python API's."""
from __future__ import annotations

import json

import pytest

import zwidth
from test_cli import run, run_json

USER = ("--m", "0.12", "--b", "0.8", "--T", "1e-3", "--K", "5e4", "--B", "50")


def test_new_user_case_is_unstable_with_one_sample_of_delay():
    unstated = run("check", *USER)   # the trial's command: no verdict for a loop nobody stated
    assert unstated.returncode == 2 and unstated.stdout == ""
    assert "--delay 0 for the paper's ideal loop" in unstated.stderr and "--delay 1" in unstated.stderr
    ideal = run_json("check", *USER, "--delay", "0", code=0)
    assert ideal["verdict"] == "stable" and ideal["loop"]["ideal"] is True
    late = run_json("check", *USER, "--delay", "1", code=1)
    assert late["verdict"] == "unstable" and late["loop"]["delay"] == 1
    assert late["deciding"].startswith("complex pair at ") and late["deciding"].endswith(" Hz")
    assert late["ideal_loop"] == {"verdict": "stable", "stable": True,
                                  "spectral_radius": pytest.approx(ideal["spectral_radius"], rel=0, abs=0)}
    dev = zwidth.Device(0.12, 0.8, 1e-3, delay=1)
    assert late["spectral_radius"] == float(dev.spectral_radius(5e4, 50.0))
    assert late["K_max"] == float(dev.k_max(50.0)) and late["B_range"]["nonempty"] is False
    assert late["K_max"] < zwidth.Device(0.12, 0.8, 1e-3).k_max(50.0)   # the loop's, not the ideal's
    text = run("check", *USER, "--delay", "1")
    assert text.returncode == 1
    assert "Loop: 1 sample delay" in text.stdout and "warning: the ideal-loop analysis" in text.stdout


def test_filter_and_differentiator_shown_and_equal_to_the_api():
    obj = run_json("check", *USER, "--delay", "1", "--velocity-filter", "lowpass:30Hz",
                   "--differentiator", "tustin", code=1)
    assert obj["loop"]["text"] == "1 sample delay, low-pass 30 Hz, tustin differentiator"
    dev = zwidth.Device(0.12, 0.8, 1e-3, delay=1, velocity_filter=("lowpass", 30.0), differentiator="tustin")
    assert obj["stable"] == bool(dev.is_stable(5e4, 50.0))
    assert obj["spectral_radius"] == float(dev.spectral_radius(5e4, 50.0))
    # a gentle pair that a 1-sample delay and a 30 Hz filter keep stable
    ok = run_json("check", "--m", "0.12", "--b", "0.8", "--T", "1e-3", "--K", "2000", "--B", "20",
                  "--delay", "1", "--velocity-filter", "lowpass:30Hz", code=0)
    assert ok["verdict"] == "stable"
    avg = run_json("check", "--delta", "0.5", "--alpha", "0.1", "--beta", "0.2", "--velocity-filter", "average:4",
                   "--delay", "0", code=0)
    assert avg["stable"] == bool(zwidth.check(0.5, 0.1, 0.2, average=4)) and avg["loop"]["average"] == 4
    pole = run_json("check", "--delta", "0.5", "--alpha", "0.1", "--beta", "0.2", "--velocity-filter", "pole:0.8",
                    "--delay", "2")
    assert pole["spectral_radius"] == float(zwidth.spectral_radius(0.5, 0.1, 0.2, delay=2, filter_pole=0.8))


def test_ideal_options_give_todays_output():
    a = run("check", *USER, "--delay", "0")
    b = run("check", *USER, "--delay", "0", "--differentiator", "backward", "--velocity-filter", "none")
    assert a.stdout == b.stdout and a.returncode == b.returncode == 0
    assert a.stdout.startswith("Loop: the paper's ideal loop (delay 0, backward difference, no velocity filter)\n")


@pytest.mark.parametrize("args, option", [
    (("--delay", "9"), "--delay"),
    (("--delay", "-1"), "--delay"),
    (("--velocity-filter", "lowpass:600Hz"), "--velocity-filter"),   # above Nyquist (500 Hz)
    (("--velocity-filter", "lowpass:0Hz"), "--velocity-filter"),
    (("--velocity-filter", "average:0"), "--velocity-filter"),
    (("--velocity-filter", "average:17"), "--velocity-filter"),
    (("--velocity-filter", "pole:1.5"), "--velocity-filter"),
])
def test_invalid_loop_values_exit_3_naming_the_option(args, option):
    r = run("check", *USER, "--delay", "0", *args)
    assert r.returncode == 3, (r.stdout, r.stderr)
    assert f"invalid value of {option}" in r.stderr


@pytest.mark.parametrize("args, words", [
    (("--velocity-filter", "bandpass:3"), "unknown velocity filter"),
    (("--velocity-filter", "lowpass:fast"), "cut-off in Hz"),
    (("--differentiator", "central"), "invalid choice"),
    (("--delay", "1.5"), "invalid int"),
])
def test_bad_loop_syntax_exits_2(args, words):
    r = run("check", *USER, *args)
    assert r.returncode == 2 and words in r.stderr, r.stderr


def test_hz_needs_a_real_plant():
    r = run("check", "--delta", "1", "--alpha", "0.3", "--beta", "0.1", "--velocity-filter", "lowpass:30Hz")
    assert r.returncode == 2 and "needs the period" in r.stderr


def test_limits_of_a_loop():
    obj = run_json("limits", "--m", "0.12", "--b", "0.8", "--T", "1e-3", "--delay", "1")
    dev = zwidth.Device(0.12, 0.8, 1e-3, delay=1)
    ex = dev.extremes()
    assert obj["K_mmax"] == float(ex.K_mmax) and obj["B_mmax"] == float(ex.B_mmax)
    assert obj["ideal_loop"]["K_mmax"] == float(dev.ideal().extremes().K_mmax)
    assert obj["legacy"] is None and obj["loop"]["delay"] == 1 and 0 < obj["K_mmax_kept"] < 1
    text = run("limits", "--m", "0.12", "--b", "0.8", "--T", "1e-3", "--delay", "1").stdout
    assert "Limits of this loop (1 sample delay" in text and "% of the ideal loop" in text


def test_advise_a_loop():
    r = run("advise", *USER, "--delay", "1", "--velocity-filter", "lowpass:100Hz")
    assert r.returncode == 1, r.stderr
    assert "What the loop costs" in r.stdout and "by delay:" in r.stdout and "keeps most" in r.stdout
    assert "set B in" not in r.stdout          # no B is stable at K = 50 kN/m with this loop
    obj = run_json("advise", *USER, "--delay", "1", "--velocity-filter", "lowpass:100Hz", code=1)
    inf = zwidth.Device(0.12, 0.8, 1e-3, delay=1, velocity_filter=("lowpass", 100.0)).loop_influence()
    assert obj["loop_influence"]["K_mmax"] == float(inf.K_mmax)
    assert obj["gains"]["verdict"] == "unstable" and obj["gains"]["suggestions"][0]["change"] == "K"


# plot device / influence of a delayed loop: test_plot.py::test_cli_plots_a_delayed_filtered_loop


def test_plot_region_of_a_loop(tmp_path):
    out = tmp_path / "loop.png"
    r = run("plot", "region", *USER, "--delay", "1", "--velocity-filter", "lowpass:100Hz", "-o", out)
    assert r.returncode == 0, r.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 20000


def test_region_option_with_a_loop_is_a_usage_error():
    r = run("check", *USER, "--delay", "1", "--region", "legacy")
    assert r.returncode == 2 and "ideal loop" in r.stderr


def test_help_explains_the_loop_options():
    r = run("check", "--help")
    for words in ("--delay N", "--velocity-filter SPEC", "lowpass:30Hz", "average:4", "tustin"):
        assert words in r.stdout
