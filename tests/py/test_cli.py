# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The ``zwidth`` command line, run as a user runs it: the installed entry point (next to
sys.executable) in a subprocess.  Exit codes, --json schemas, numbers equal to the Python
API's, error messages naming the option, and the help text.
"""
from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import zwidth


def _command():
    exe = Path(sys.executable).parent / "zwidth"
    if exe.exists():
        return [str(exe)]
    found = shutil.which("zwidth")
    return [found] if found else [sys.executable, "-m", "zwidth"]


ZW = _command()
# the paper's loop, stated (no command assumes it: test_loop_not_stated)
SHORT = ("--J", "85.78e-7", "--b", "2.197e-3", "--T", "0.02", "--delay", "0")  # the paper's drive, delta = 5.122
LINEAR = ("--m", "0.1", "--b", "30", "--T", "0.01", "--delay", "0")               # the paper's simulation, delta = 3


def run(*args, **kwargs):
    return subprocess.run([*ZW, *map(str, args)], capture_output=True, text=True, timeout=120, **kwargs)


def run_json(*args, code=0):
    r = run(*args, "--json")
    assert r.returncode == code, (r.returncode, r.stdout, r.stderr)
    return json.loads(r.stdout)


def same(json_value, api_value):
    """A JSON number equals the API's value exactly (NaN and infinities are null)."""
    x = float(api_value)
    if not math.isfinite(x):
        return json_value is None
    return isinstance(json_value, float) and json_value == x


# ---------------------------------------------------------------------------------------
# Exit codes
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("args, code", [
    (("limits", *LINEAR), 0),
    (("limits", *SHORT), 0),
    (("check", *SHORT, "--K", "0.39", "--B", "-1.36e-3"), 0),
    (("check", *SHORT, "--K", "0.5", "--B", "-1.36e-3"), 1),
    (("check", *SHORT, "--K=0.5", "--B=-1.36e-3"), 1),
    (("check", "--delta", "5.122", "--delay", "0", "--alpha", "23", "--beta", "-1.5"), 1),
    (("check", "--delta", "5.122", "--delay", "0", "--alpha", "23", "--beta", "-1.5", "--region", "legacy"), 0),
    (("check", "--delta", "5.122", "--delay", "0", "--alpha", "0", "--beta", "0"), 1),  # marginal is not stable
    (("advise", *SHORT), 0),
    (("advise", *SHORT, "--K", "0.39", "--B", "-1.36e-3"), 0),
    (("advise", *SHORT, "--K", "0.5", "--B", "-1.36e-3"), 1),
    (("advise", "--delta", "5.122", "--delay", "0", "--alpha", "23", "--beta", "-1.5"), 1),
])
def test_exit_codes(args, code):
    r = run(*args)
    assert r.returncode == code, (r.stdout, r.stderr)
    assert r.stdout.strip() and not r.stderr


@pytest.mark.parametrize("args, code, words", [
    (("limits", "--m", "-1", "--b", "30", "--T", "0.01", "--delay", "0"), 3, ["--m", "m must be > 0"]),
    (("limits", "--J", "0", "--b", "30", "--T", "0.01", "--delay", "0"), 3, ["--J", "must be > 0"]),
    (("limits", "--m", "0.1", "--b", "-1", "--T", "0.01", "--delay", "0"), 3, ["--b", "b must be >= 0"]),
    (("limits", "--m", "0.1", "--b", "30", "--T", "0", "--delay", "0"), 3, ["--T", "T must be > 0"]),
    (("limits", "--delta", "-1", "--delay", "0"), 3, ["--delta", "delta must be >= 0"]),
    (("check", *LINEAR, "--K", "nan", "--B", "0"), 3, ["--K", "NaN"]),
    (("check", *LINEAR, "--K", "1", "--B", "inf"), 3, ["--B", "finite"]),
    (("limits", "--m", "abc", "--b", "30", "--T", "0.01", "--delay", "0"), 2, ["--m", "'abc'"]),
    (("check", *LINEAR, "--K", "1", "--B", "x1"), 2, ["--B", "'x1'"]),
    (("limits", "--m", "0.1", "--J", "0.1", "--b", "30", "--T", "0.01", "--delay", "0"), 2, ["--J", "--m"]),
    (("limits", *LINEAR, "--delta", "3", "--delay", "0"), 2, ["--delta", "--m"]),
    (("limits", "--m", "0.1", "--b", "30"), 2, ["--T"]),
    (("check", *LINEAR), 2, ["--K", "--B"]),
    (("check", *LINEAR, "--K", "1"), 2, ["--B"]),
    (("check", "--alpha", "1", "--beta", "1"), 2, ["--delta"]),
    (("check", *LINEAR, "--K", "1", "--B", "0", "--region", "nope"), 2, ["--region", "nope"]),
    (("limits",), 2, ["--m", "--delta"]),
    ((), 2, ["check", "limits"]),
    (("plot", "region", "--delta", "3", "--delay", "0", "-o", "x.txt"), 2, ["--output", ".png, .pdf"]),
    (("plot", "extremes", "--delta-min", "0"), 2, ["--delta-min"]),
    (("plot", "device", "--delta", "3", "--delay", "0"), 2, ["real-unit"]),
])
def test_errors_name_the_option(args, code, words):
    r = run(*args, "--json") if args else run()
    assert r.returncode == code, (r.stdout, r.stderr)
    assert r.stdout == ""  # nothing, not even JSON, on failure
    for word in words:
        assert word in r.stderr, (word, r.stderr)
    if code == 2:
        assert "usage:" in r.stderr


# ---------------------------------------------------------------------------------------
# JSON: schemas and the API's numbers
# ---------------------------------------------------------------------------------------

NUM = (float, type(None))
INTERVAL = {"lo": NUM, "hi": NUM, "nonempty": bool}
COMMON = {
    "command": str, "mode": str,
    "plant": {"m": NUM, "b": NUM, "T": NUM, "rotary": bool, "delta": float, "preset": (str, type(None))},
    "units": (dict, type(None)),
    "loop": dict,   # the loop analysed (test_loop_cli.py)
}
SCHEMAS = {
    "check": {**COMMON, "region": str, "verdict": str, "stable": bool, "marginal": bool,
              "deciding": (str, type(None)), "deciding_text": (str, type(None)), "violated": list,
              "exact_stable": bool, "spectral_radius": float, "K": NUM, "B": NUM, "alpha": float,
              "beta": float, "K_max": NUM, "B_range": (dict, type(None)), "alpha_max": float,
              "beta_range": INTERVAL, "delay_1": (dict, type(None))},
    "limits": {**COMMON, "K_mmax": NUM, "B_at_K_mmax": NUM, "K_p_max": NUM, "B_mmax": NUM,
               "B_mmin": NUM, "alpha_mmax": float, "beta_at_alpha_mmax": float,
               "alpha_p_max": float, "beta_mmax": float, "beta_mmin": float, "at_corner": bool,
               "corner": {"alpha": NUM, "beta": NUM}, "delta0": float, "above_delta0": bool,
               "legacy": {"K_mmax": NUM, "B_at_K_mmax": NUM, "alpha_mmax": float,
                          "beta_at_alpha_mmax": float, "region_unsafe": bool,
                          "overstates_K_mmax": bool}, "delay_1": (dict, type(None))},
    "advise": {**COMMON, "influence": dict, "trends": str, "advice": str,
               "gains": (dict, type(None))},
}
GAINS = {"K": NUM, "B": NUM, "alpha": NUM, "beta": NUM, "verdict": str, "stable": bool,
         "marginal": bool, "deciding": (str, type(None)), "spectral_radius": float, "K_max": float,
         "B_range": INTERVAL, "margins": {"sigma": float, "r": float}, "certified": bool,
         "suggestions": list, "delay_1": (dict, type(None))}
SUGGESTION = {"change": str, "lo": NUM, "hi": NUM, "value": NUM, "text": str}
INFLUENCE_INTS = ("K_vs_m", "K_vs_b", "K_vs_T", "B_vs_m", "B_vs_b", "B_vs_T")


def conforms(obj, schema, where="$"):
    assert isinstance(obj, dict), where
    assert set(obj) == set(schema), (where, sorted(set(obj) ^ set(schema)))
    for key, kind in schema.items():
        if isinstance(kind, dict):
            conforms(obj[key], kind, f"{where}.{key}")
        else:
            assert isinstance(obj[key], kind), (f"{where}.{key}", obj[key])


@pytest.mark.parametrize("args", [
    ("check", *SHORT, "--K", "0.39", "--B", "-1.36e-3"),
    ("check", "--delta", "5.122", "--delay", "0", "--alpha", "23", "--beta", "-1.5"),
    ("limits", *LINEAR),
    ("limits", *SHORT),
    ("limits", "--delta", "2", "--delay", "0"),
    ("advise", *SHORT),
    ("advise", *SHORT, "--K", "0.5", "--B", "-1.36e-3"),
    ("advise", "--delta", "5.122", "--delay", "0", "--alpha", "23", "--beta", "-1.5"),
])
def test_json_schema(args):
    command = args[0]
    r = run(*args, "--json")
    assert r.returncode in (0, 1), r.stderr
    obj = json.loads(r.stdout)
    assert r.stdout.count("\n") == 1  # one object on one line
    conforms(obj, SCHEMAS[command])
    assert obj["command"] == command
    normalized = "--delta" in args
    assert obj["mode"] == ("normalized" if normalized else "real")
    assert (obj["units"] is None) == normalized
    if obj["units"] is not None:
        assert set(obj["units"]) == {"m", "b", "T", "K", "B"}
    if command == "check":
        assert obj["verdict"] in ("stable", "unstable", "marginal")
        assert all(isinstance(v, str) for v in obj["violated"])
        if obj["B_range"] is not None:
            conforms(obj["B_range"], INTERVAL)
    if command == "advise":
        assert set(obj["influence"]) == set(zwidth.Influence.__dataclass_fields__) - {"m", "mass_symbol"}
        for key, value in obj["influence"].items():
            assert isinstance(value, int if key in INFLUENCE_INTS else NUM), (key, value)
        if obj["gains"] is not None:
            conforms(obj["gains"], GAINS)
            for s in obj["gains"]["suggestions"]:
                conforms(s, SUGGESTION)


def test_check_json_normalized_line():
    """The paper's Fig. 19(a) point: unstable, decided by the line; every number is the API's."""
    obj = run_json("check", "--delta", "5.122", "--delay", "0", "--alpha", "23", "--beta", "-1.5", code=1)
    v = zwidth.verdict(5.122, 23.0, -1.5)
    assert obj["verdict"] == "unstable" and obj["deciding"] == "line" == v.deciding_name
    assert obj["violated"] == ["line"] and obj["stable"] is False and obj["exact_stable"] is False
    assert same(obj["spectral_radius"], zwidth.spectral_radius(5.122, 23.0, -1.5))
    assert same(obj["alpha_max"], zwidth.alpha_max(5.122, -1.5))
    iv = zwidth.beta_interval(5.122, 23.0)
    assert same(obj["beta_range"]["lo"], iv.lo) and same(obj["beta_range"]["hi"], iv.hi)
    assert obj["K"] is obj["K_max"] is obj["B_range"] is obj["units"] is None
    assert obj["plant"] == {"m": None, "b": None, "T": None, "rotary": False, "delta": 5.122, "preset": None}
    assert obj["loop"]["ideal"] is True


@pytest.mark.parametrize("K, stable", [(0.39, True), (0.5, False)])
def test_check_json_real_matches_api(K, stable):
    obj = run_json("check", *SHORT, "--K", K, "--B", "-1.36e-3", code=0 if stable else 1)
    dev = zwidth.Device.rotary(85.78e-7, 2.197e-3, 0.02)
    v = dev.verdict(K, -1.36e-3)
    assert obj["stable"] is bool(v.stable) is stable
    assert obj["verdict"] == ("stable" if stable else "unstable")
    assert obj["deciding"] == (v.deciding_name or None)
    assert same(obj["spectral_radius"], dev.spectral_radius(K, -1.36e-3))
    assert same(obj["K_max"], dev.k_max(-1.36e-3))
    br = dev.b_range(K)
    assert obj["B_range"]["nonempty"] is bool(br.nonempty)
    assert same(obj["B_range"]["lo"], br.lo) and same(obj["B_range"]["hi"], br.hi)
    n = dev.normalize(K, -1.36e-3)
    assert same(obj["alpha"], n.alpha) and same(obj["beta"], n.beta)
    assert same(obj["plant"]["delta"], dev.delta) and obj["plant"]["rotary"] is True
    assert obj["units"]["K"] == "N m/rad" and obj["units"]["m"] == "kg m^2"


@pytest.mark.parametrize("args, make", [
    (LINEAR, lambda: zwidth.Device(0.1, 30.0, 0.01)),
    (SHORT, lambda: zwidth.Device.rotary(85.78e-7, 2.197e-3, 0.02)),
])
def test_limits_json_matches_api(args, make):
    obj = run_json("limits", *args)
    dev = make()
    lim = dev.extremes()
    for key in ("K_mmax", "B_at_K_mmax", "K_p_max", "B_mmax", "B_mmin"):
        assert same(obj[key], getattr(lim, key)), key
    ext = zwidth.extremes(dev.delta)
    for key in ("alpha_mmax", "beta_at_alpha_mmax", "alpha_p_max", "beta_mmax", "beta_mmin"):
        assert same(obj[key], getattr(ext, key)), key
    assert obj["at_corner"] is bool(lim.at_corner)
    top = zwidth.hyperbola_top(dev.delta)
    m, T = float(dev.m), float(dev.T)
    assert same(obj["legacy"]["K_mmax"], float(top.alpha) * m / T ** 2)
    assert same(obj["legacy"]["B_at_K_mmax"], float(top.beta) * m / T)
    assert obj["legacy"]["region_unsafe"] is obj["above_delta0"] is True  # delta = 3, 5.122
    assert obj["legacy"]["overstates_K_mmax"] is bool(lim.at_corner)
    assert obj["delta0"] == zwidth.DELTA0


def test_limits_json_below_delta0_has_no_corner():
    obj = run_json("limits", "--delta", "2", "--delay", "0")
    assert obj["corner"] == {"alpha": None, "beta": None}  # NaN -> null
    assert obj["legacy"]["region_unsafe"] is False and obj["K_mmax"] is None


def test_advise_json_matches_api():
    obj = run_json("advise", *SHORT, "--K", "0.5", "--B", "-1.36e-3", code=1)
    dev = zwidth.Device.rotary(85.78e-7, 2.197e-3, 0.02)
    inf = dev.influence()
    for key, value in inf.as_dict().items():
        if key == "m":
            continue
        if key in INFLUENCE_INTS:
            assert obj["influence"][key] == int(value), key
        else:
            assert same(obj["influence"][key], value), key
    assert obj["advice"] == inf.advice
    gains = obj["gains"]
    assert gains["verdict"] == "unstable" and same(gains["K_max"], dev.k_max(-1.36e-3))
    assert gains["margins"] == {"sigma": 0.8, "r": 0.999} and gains["certified"] is False
    changes = {s["change"]: s for s in gains["suggestions"]}
    k = changes["K"]
    # the certified K interval at this B ends at sigma K_max(B), the drive's LIVE_K_CERT 0.39420
    assert k["hi"] == pytest.approx(0.8 * float(dev.k_max(-1.36e-3)), rel=1e-9) and k["value"] == k["hi"]
    for K in (k["lo"], k["value"], k["hi"]):  # every end is certified: stable, sigma, radius
        assert bool(dev.is_stable(K, -1.36e-3)) and bool(dev.radius_within(K, -1.36e-3, 0.999))
        assert K <= 0.8 * float(dev.k_max(-1.36e-3))
    assert not bool(dev.radius_within(k["lo"] * 0.99, -1.36e-3, 0.999))  # the lower end is the radius'
    for name in ("b", "T"):  # a suggested plant change certifies the gains as they are
        plant = dict(J=85.78e-7, b=2.197e-3, T=0.02)
        plant[name] = changes[name]["value"]
        moved = zwidth.Device.rotary(plant["J"], plant["b"], plant["T"])
        assert bool(moved.is_stable(0.5, -1.36e-3)) and bool(moved.radius_within(0.5, -1.36e-3, 0.999))
        assert 0.5 <= 0.8 * float(moved.k_max(-1.36e-3))


def test_advise_takes_the_drives_margins():
    """Stable gains above sigma K_max(B) are not certified (exit 1) and get the certified
    value; a looser sigma certifies them; the B suggestion keeps K within sigma K_max(B)."""
    dev = zwidth.Device.rotary(85.78e-7, 2.197e-3, 0.02)
    K, B = 0.3, 0.0  # stable (84 % of K_max(B) = 0.3577), above the drive's 80 %
    assert bool(dev.is_stable(K, B))
    obj = run_json("advise", *SHORT, "--K", str(K), "--B", str(B), code=1)
    assert obj["gains"]["stable"] is True and obj["gains"]["certified"] is False
    changes = {s["change"]: s for s in obj["gains"]["suggestions"]}
    assert changes["K"]["value"] == pytest.approx(0.8 * float(dev.k_max(B)), rel=1e-9)
    lo, hi = changes["B"]["lo"], changes["B"]["hi"]
    for b in np.linspace(lo, hi, 25):
        assert K <= 0.8 * float(dev.k_max(b)) and bool(dev.radius_within(K, b, 0.999))
    assert changes["B"]["lo"] < changes["B"]["value"] == changes["B"]["hi"] < B  # more negative B
    assert run_json("advise", *SHORT, "--K", str(K), "--B", str(B), "--sigma", "0.9",
                    code=0)["gains"]["certified"] is True
    assert run_json("advise", *SHORT, "--K", "0.39", "--B", "-1.36e-3", "--r", "0.9",
                    code=1)["gains"]["certified"] is False  # spectral radius 0.947
    text = run("advise", *SHORT, "--K", str(K), "--B", str(B)).stdout
    assert "sigma = 0.8, r = 0.999): NOT CERTIFIED" in text


@pytest.mark.parametrize("bad", ["0", "1.5", "-0.8"])
def test_advise_refuses_margins_outside_0_1(bad):
    r = run("advise", *SHORT, "--K", "0.39", "--B", "-1.36e-3", "--sigma", bad)
    assert r.returncode == 2 and "--sigma" in r.stderr


def test_preset_names_the_papers_drive_and_nothing_is_filled_in():
    obj = run_json("limits", "--preset", "paper-drive")
    assert obj["plant"]["preset"] == "paper-drive" and obj["plant"]["rotary"] is True
    assert same(obj["K_mmax"], zwidth.Device.rotary(85.78e-7, 2.197e-3, 0.02).extremes().K_mmax)
    assert run_json("limits", "--preset", "paper-drive", "--T", "0.008")["plant"]["T"] == 0.008
    r = run("limits", "--m", "0.12", "--b", "0.8")
    assert r.returncode == 2 and "the plant needs --T (or --preset paper-drive)" in r.stderr
    r = run("limits", "--preset", "paper-drive", "--delta", "3", "--delay", "0")
    assert r.returncode == 2 and "--preset" in r.stderr
    r = run("limits", *SHORT, "--K", "0.39", "--B", "-1.36e-3")  # would be ignored: refused
    assert r.returncode == 2 and "zwidth check" in r.stderr


def test_advise_normalized_uses_unit_plant():
    obj = run_json("advise", "--delta", "5.122", "--delay", "0", code=0)
    inf = zwidth.Device(1.0, 5.122, 1.0).influence()
    assert same(obj["influence"]["m_K2"], inf.m_K2) and obj["gains"] is None


# ---------------------------------------------------------------------------------------
# Human output and help
# ---------------------------------------------------------------------------------------


def test_human_output_units_and_digits():
    lin = run("limits", *LINEAR).stdout
    lim = zwidth.Device(0.1, 30.0, 0.01).extremes()
    assert f"K_mmax   = {float(lim.K_mmax):.6g} N/m at B = {float(lim.B_at_K_mmax):.6g} N s/m" in lin
    rot = run("check", *SHORT, "--K", "0.39", "--B", "-1.36e-3").stdout
    assert "J = 8.578e-06 kg m^2" in rot and "N m/rad" in rot and "N m s/rad" in rot
    assert "STABLE" in rot and "N/m " not in rot
    bad = run("check", "--delta", "5.122", "--delay", "0", "--alpha", "23", "--beta", "-1.5").stdout
    assert "UNSTABLE" in bad and "line" in bad


def test_python_dash_m_is_the_same_command():
    direct = run("limits", *SHORT)
    module = subprocess.run([sys.executable, "-m", "zwidth", "limits", *SHORT], capture_output=True,
                            text=True, timeout=120)
    assert module.returncode == direct.returncode == 0
    assert module.stdout == direct.stdout


def test_help():
    r = run("--help")
    assert r.returncode == 0
    text = " ".join(r.stdout.split())
    assert "A drive renders stiffness K and damping B on a mass m with damping b, sampled every T" in text
    assert "how m, b, T move the limits" in text
    for sub in ("check", "limits", "advise", "plot"):
        assert sub in text
    assert "exit status" in r.stdout
    for code in range(5):
        assert any(line.strip().startswith(f"{code} ") for line in r.stdout.splitlines()), code
    for sub, key in (("check", "spectral_radius"), ("limits", "overstates_K_mmax"),
                     ("advise", "suggestions"), ("plot", "bytes")):
        h = run(sub, "--help")
        assert h.returncode == 0 and key in h.stdout, sub
    assert run("--version").stdout.strip() == f"zwidth {zwidth.__version__}"


def test_json_has_no_nan_tokens():
    """NaN (corner below delta0) and inf (T_B at b = 0) come out as null, strict JSON."""
    for args in (("limits", "--delta", "1", "--delay", "0"), ("advise", "--m", "0.1", "--b", "0", "--T", "0.01", "--delay", "0")):
        out = run(*args, "--json").stdout
        assert "NaN" not in out and "Infinity" not in out
        json.loads(out, parse_constant=lambda c: pytest.fail(f"non-standard constant {c}"))
    obj = run_json("advise", "--m", "0.1", "--b", "0", "--T", "0.01", "--delay", "0")
    assert np.isinf(zwidth.Device(0.1, 0.0, 0.01).influence().T_B) and obj["influence"]["T_B"] is None


# ---------------------------------------------------------------------------------------
# The loop is stated, never assumed (issue 24): the new-user trial's device, m = 0.12 kg,
# b = 0.8 N s/m, T = 1 ms, whose firmware applies the force a sample late and low-passes
# the velocity at 100 Hz
# ---------------------------------------------------------------------------------------

TRIAL = ("--m", "0.12", "--b", "0.8", "--T", "1e-3")
TRIAL_GAINS = ("--K", "50000", "--B", "60")


@pytest.mark.parametrize("args", [
    ("limits", *TRIAL),
    ("check", *TRIAL, *TRIAL_GAINS),
    ("advise", *TRIAL, *TRIAL_GAINS),
    ("check", "--delta", "0.5", "--alpha", "0.1", "--beta", "0.2"),
    ("limits", "--J", "5e-6:5e-5", "--b", "2e-3:2.4e-3", "--T", "0.02"),         # a plant box
    ("check", *TRIAL, *TRIAL_GAINS, "--velocity-filter", "lowpass:100Hz"),     # a filter is not a delay
    ("plot", "device", *TRIAL, "-o", "unused.png"),
])
def test_loop_not_stated(args, tmp_path):
    r = run(*args, cwd=tmp_path)
    assert r.returncode == 2 and r.stdout == "", (r.returncode, r.stdout)
    assert "the loop is not stated" in r.stderr and "--delay 0 for the paper's ideal loop" in r.stderr
    assert "--delay 1" in r.stderr and not (tmp_path / "unused.png").exists()


def test_trial_pair_in_its_loop_and_the_ideal_loops_warning():
    late = run_json("check", *TRIAL, *TRIAL_GAINS, "--delay", "1", "--velocity-filter", "lowpass:100Hz", code=1)
    assert list(late)[:2] == ["command", "loop"] and late["verdict"] == "unstable"
    assert late["loop"]["delay"] == 1 and late["loop"]["cutoff"] == 100.0
    assert late["loop"]["pole"] == pytest.approx(np.exp(-2 * np.pi * 100.0 * 1e-3), rel=1e-15)
    assert late["loop"]["statement"] == ("1 sample delay, backward difference, velocity low-pass 100 Hz "
                                         "(pole 0.533488)")
    dev = zwidth.Device(0.12, 0.8, 1e-3, delay=1, velocity_filter=("lowpass", 100.0))
    assert late["spectral_radius"] == float(dev.spectral_radius(50000.0, 60.0)) > 1
    text = run("check", *TRIAL, *TRIAL_GAINS, "--delay", "1", "--velocity-filter", "lowpass:100Hz")
    assert text.stdout.splitlines()[0] == ("Loop: 1 sample delay, backward difference, velocity low-pass "
                                           "100 Hz (pole 0.533488)")
    # the ideal loop, stated: stable, and the 1-sample verdict with a warning beside it
    ideal = run_json("advise", *TRIAL, *TRIAL_GAINS, "--delay", "0")
    assert ideal["loop"]["delay"] == 0 and ideal["gains"]["stable"] is True
    one = zwidth.Device(0.12, 0.8, 1e-3, delay=1)
    assert ideal["gains"]["delay_1"]["stable"] is False
    assert ideal["gains"]["delay_1"]["spectral_radius"] == float(one.spectral_radius(50000.0, 60.0))
    text = run("check", *TRIAL, *TRIAL_GAINS, "--delay", "0").stdout
    assert text.startswith("Loop: the paper's ideal loop (delay 0, backward difference, no velocity filter)\n")
    assert "with 1 sample of delay" in text and "UNSTABLE" in text and "warning:" in text
    # limits: the 1-sample line beside the ideal loop's, never above the certified delay-1 limit
    lim = run_json("limits", *TRIAL, "--delay", "0")
    assert lim["delay_1"]["K_mmax"] == float(one.extremes().K_mmax) < lim["K_mmax"] / 4
    # the preset carries the paper's loop and says so
    pre = run("limits", "--preset", "paper-drive").stdout.splitlines()[0]
    assert pre == ("Loop: the paper's ideal loop (delay 0, backward difference, no velocity filter), "
                   "from --preset paper-drive")


def test_api_results_carry_their_loop():
    dev = zwidth.Device(0.12, 0.8, 1e-3, delay=1, velocity_filter=("lowpass", 100.0))
    v = dev.verdict(50000.0, 60.0)
    assert v.loop == dev.loop and "1 sample delay" in repr(v) and v.as_dict()["loop"]["delay"] == 1
    assert dev.loop.as_dict()["pole"] == pytest.approx(0.533488, abs=5e-7)
    ideal = zwidth.Device(0.12, 0.8, 1e-3)
    assert "the paper's ideal loop" in repr(ideal) and "the paper's ideal loop" in repr(ideal.verdict(5e4, 60.0))
    assert dev.with_delay(0).loop.delay == 0 and dev.with_delay(0).loop.cutoff == 100.0
    # an errors= override per call: a NaN gain masked, not raised
    assert not bool(dev.is_stable(float("nan"), 60.0, errors="mask"))
    with pytest.raises(zwidth.ZwidthError):
        dev.is_stable(float("nan"), 60.0)
