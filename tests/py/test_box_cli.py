# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""The command line with plant ranges (--J 5e-6:5e-5, python/zwidth/box_cli.py): numbers
equal to zwidth.PlantBox's, exit codes, refusals."""
from __future__ import annotations

import json

import pytest

import zwidth
from test_box_reference import box_min_ref
from test_cli import run, run_json

BOX = ("--J", "5e-6:5e-5", "--b", "2.0e-3:2.4e-3", "--T", "0.02", "--delay", "0")


def test_limits_json_is_plantbox():
    out = run_json("limits", *BOX)
    box = zwidth.PlantBox.rotary_box((5e-6, 5e-5), (2.0e-3, 2.4e-3), 0.02)
    x = box.extremes()
    assert out["mode"] == "box" and out["box"]["mass"] == "J"
    assert out["K_mmax"] == x.K_mmax and out["B_at_K_mmax"] == x.B_at
    assert out["K_p_max"] == box.k_max(0.0).K_lower
    # certified: the box's K_max at that B is at least K_mmax (mpmath)
    inf, _, _ = box_min_ref((5e-6, 5e-5, 2.0e-3, 2.4e-3, 0.02), x.B_at, n_m=121, n_b=5)
    assert out["K_mmax"] <= inf


def test_check_exit_codes():
    stable = run_json("check", *BOX, "--K", "0.2", "--B", "1e-4")
    assert stable["verdict"] == "stable" and stable["B_range"]["nonempty"]
    unstable = run_json("check", *BOX, "--K", "0.25", "--B", "1e-4", code=1)
    assert unstable["verdict"] == "unstable" and not unstable["B_range"]["nonempty"]
    # one plant of the box that is unstable at those gains, by the exact point check
    w = unstable["worst_plant"]
    assert not zwidth.Device.rotary(w["J"], w["b"], 0.02).is_stable(0.25, 1e-4)


def test_refusals():
    r = run("advise", *BOX)
    assert r.returncode == 2 and "plant ranges" in r.stderr
    r = run("limits", "--m", "2:1", "--b", "1", "--T", "0.01", "--delay", "0")
    assert r.returncode == 3 and "lo <= hi" in r.stderr
    r = run("plot", "region", *BOX, "--delay", "1", "-o", "unused.png")
    assert r.returncode == 2 and "ideal loop" in r.stderr
    r = run("limits", *BOX, "--delay", "9")
    assert r.returncode in (2, 3)
    r = run("limits", "--m", "1:2:3", "--b", "1", "--T", "0.01")
    assert r.returncode == 2


def test_plot_region(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "box.png"
    r = run("plot", "region", *BOX, "--K", "0.2", "--B", "1e-4", "-o", str(out), "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["file"] == str(out) and out.stat().st_size > 10_000
