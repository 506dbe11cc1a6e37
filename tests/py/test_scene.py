# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Scene files (zwidth.scene, docs/scenes.md): every bad scene gives one SceneError naming
the file and the key; the loader reads files, text and dicts alike and round-trips through
Scene.to_toml; units are converted to SI (checked against hand-computed factors); the
defaults (substeps, verdict windows, samples) follow the documented rules; the scene files
in scenes/ say what the paper says.
"""
from __future__ import annotations

import math
import pickle
import sys
from pathlib import Path

import numpy as np
import pytest

import zwidth
from zwidth import SceneError, load_scene

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

REPO = Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"
SCENE_FILES = sorted(SCENES.glob("*.toml"))

BASE = """\
[scene]
name = "base"
duration = "10 s"

[plant]
m = "0.1 kg"
b = "23 N*s/m"
T = "0.01 s"

[controller]
K = "100 N/m"
B = "1 N*s/m"
"""


def bad(tmp_path, text, name="bad.toml"):
    """Load text from a file and return the SceneError it must raise."""
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(SceneError) as info:
        load_scene(path)
    return path, info.value


# ---------------------------------------------------------------------------------------
# One clear error per bad scene
# ---------------------------------------------------------------------------------------

# (description, edit of BASE, the key the error must name, words it must contain)
BAD = [
    ("wrong dimension", lambda t: t.replace('m = "0.1 kg"', 'm = "0.1 m"'), "plant.m",
     ["wrong dimension", "'0.1 m'", "mass", "kg"]),
    ("missing units, number", lambda t: t.replace('b = "23 N*s/m"', "b = 23"), "plant.b",
     ["missing units", '"23 N*s/m"']),
    ("missing units, string", lambda t: t.replace('b = "23 N*s/m"', 'b = "23"'), "plant.b",
     ["missing units", '"23 N*s/m"']),
    ("unknown unit", lambda t: t.replace('"0.1 kg"', '"0.1 kgg"'), "plant.m",
     ["cannot read", "kgg"]),
    ("malformed quantity", lambda t: t.replace('"0.1 kg"', '"0.1 kg +"'), "plant.m",
     ["cannot read", "not a number followed by units"]),
    ("unknown key", lambda t: t.replace('K = "100 N/m"', 'Kp = "100 N/m"'), "controller.Kp",
     ["unknown key", "did you mean 'K'"]),
    ("unknown section", lambda t: t + '[frition]\ncoulomb = "1 N"\n', "[frition]",
     ["unknown section", "did you mean [friction]"]),
    ("value outside a section", lambda t: 'speed = "1 m/s"\n' + t, "speed", ["outside any section"]),
    ("table written as array", lambda t: t.replace("[plant]", "[[plant]]"), "plant",
     ["must be a table", "[plant]"]),
    ("array written as table", lambda t: t + '[case]\nlabel = "x"\n', "case",
     ["array of tables", "[[case]]"]),
    ("negative mass", lambda t: t.replace('"0.1 kg"', '"-0.1 kg"'), "plant.m", ["must be > 0"]),
    ("negative damping", lambda t: t.replace('"23 N*s/m"', '"-1 N*s/m"'), "plant.b", ["must be >= 0"]),
    ("zero period", lambda t: t.replace('"0.01 s"', '"0 s"'), "plant.T", ["must be > 0"]),
    ("infinite period", lambda t: t.replace('"0.01 s"', '"inf s"'), "plant.T", ["finite"]),
    ("NaN", lambda t: t.replace('"23 N*s/m"', '"nan N*s/m"'), "plant.b", ["NaN"]),
    ("boolean", lambda t: t.replace('"23 N*s/m"', "true"), "plant.b", ["string with units"]),
    ("no plant", lambda t: t.split("[plant]")[0] + "[controller]" + t.split("[controller]")[1],
     "[plant]", ["missing"]),
    ("m and J", lambda t: t.replace('m = "0.1 kg"', 'm = "0.1 kg"\nJ = "1e-5 kg*m^2"'), "plant.J",
     ["not both"]),
    ("rotary plant, linear units", lambda t: t.replace('m = "0.1 kg"', 'J = "1e-5 kg*m^2"'), "plant.b",
     ["wrong dimension", "N*m*s/rad"]),
    ("no controller", lambda t: t.split("[controller]")[0], "[controller]", ["missing", "alpha"]),
    ("half a controller", lambda t: t.replace('B = "1 N*s/m"\n', ""), "controller.B",
     ["give K and B together"]),
    ("both controller forms", lambda t: t + "alpha = 1.0\n", "controller.alpha", ["not both"]),
    ("alpha with units", lambda t: t.replace('K = "100 N/m"\nB = "1 N*s/m"', 'alpha = "1 N/m"\nbeta = 0.5'),
     "controller.alpha", ["dimensionless"]),
    ("stiction below Coulomb", lambda t: t + '[friction]\ncoulomb = "0.3 N"\nstiction = "0.2 N"\n',
     "friction.stiction", ["must be >= coulomb"]),
    ("no friction at all", lambda t: t + "[friction]\n", "friction.coulomb", ["both are 0"]),
    ("delay too long", lambda t: t + "[delay]\nsamples = 65\n", "delay.samples", ["1..64", "65"]),
    ("delay not whole", lambda t: t + "[delay]\nsamples = 2.0\n", "delay.samples", ["whole number"]),
    ("delay missing", lambda t: t + "[delay]\n", "delay.samples", ["missing"]),
    ("quantization, neither", lambda t: t + "[quantization]\n", "[quantization]", ["resolution", "counts"]),
    ("quantization, both", lambda t: t + '[quantization]\nresolution = "1 um"\ncounts = "1e6 / m"\n',
     "quantization.counts", ["not both"]),
    ("counts of the wrong kind", lambda t: t + '[quantization]\ncounts = "4096 / turn"\n',
     "quantization.counts", ["wrong dimension"]),
    ("saturation zero", lambda t: t + '[saturation]\nforce_max = "0 N"\n', "saturation.force_max",
     ["must be > 0"]),
    ("filter cutoff in s", lambda t: t + '[velocity_filter]\ncutoff = "20 s"\n', "velocity_filter.cutoff",
     ["wrong dimension", "Hz"]),
    ("empty hand", lambda t: t + "[hand]\n", "[hand]", ["mass, stiffness or damping"]),
    ("hand released before grasp", lambda t: t + '[hand]\nmass = "1 kg"\ngrasp = "2 s"\nrelease = "1 s"\n',
     "hand.release", ["after grasp"]),
    ("wall side", lambda t: t + '[wall]\nposition = "0 m"\nstiffness = "1 N/m"\nside = "up"\n', "wall.side",
     ['"upper"', '"lower"']),
    ("wall without stiffness", lambda t: t + '[wall]\nposition = "0 m"\n', "wall.stiffness", ["missing"]),
    ("knob with a controller",
     lambda t: t + '[knob]\npitch = "1 mm"\ncount = 3\nk_detent = "1 N/m"\nk_end = "2 N/m"\n',
     "[controller]", ["[knob] sets the gains"]),
    ("knob of one position",
     lambda t: t.split("[controller]")[0] + '[knob]\npitch = "1 mm"\ncount = 1\nk_detent = "1 N/m"\nk_end = "2 N/m"\n',
     "knob.count", [">= 2"]),
    ("schedule not from 0",
     lambda t: t.split("[controller]")[0] + '[[schedule]]\nat = "1 s"\nK = "1 N/m"\nB = "0 N*s/m"\n',
     "schedule[1].at", ["starts at 0"]),
    ("schedule going back",
     lambda t: t.split("[controller]")[0] + '[[schedule]]\nat = "0 s"\nK = "1 N/m"\nB = "0 N*s/m"\n'
               '[[schedule]]\nat = "0 s"\nK = "2 N/m"\nB = "0 N*s/m"\n',
     "schedule[2].at", ["after the previous"]),
    ("integrator without a continuous effect", lambda t: t + "[integrator]\nsubsteps = 5\n", "[integrator]",
     ["only friction and a hand"]),
    ("integrator with both", lambda t: t + '[friction]\ncoulomb = "1 N"\n[integrator]\nsubsteps = 5\nstep = "1 ms"\n',
     "integrator.step", ["not both"]),
    ("too many substeps", lambda t: t + '[friction]\ncoulomb = "1 N"\n[integrator]\nsubsteps = 100001\n',
     "integrator.substeps", ["1..100000"]),
    ("one verdict window", lambda t: t + "[verdict]\nwindows = 1\n", "verdict.windows", [">= 2"]),
    ("verdict windows longer than the run", lambda t: t + '[verdict]\nwindow = "6 s"\n', "verdict.window",
     ["8 windows of 600 samples", "1000"]),
    ("case without label", lambda t: t + '[[case]]\nb = "1 N*s/m"\n', "case[1].label", ["missing"]),
    ("duplicate labels", lambda t: t + '[[case]]\nlabel = "P2"\n[[case]]\nlabel = "P2"\n', "case[2].label",
     ["duplicate", "case[1]"]),
    ("case overriding the other mass", lambda t: t + '[[case]]\nlabel = "a"\nJ = "1 kg*m^2"\n', "case[1].J",
     ["override m"]),
    ("case with half the other gain form", lambda t: t + '[[case]]\nlabel = "a"\nalpha = 1.0\n', "case[1].beta",
     ["alpha and beta together"]),
    ("case with a bad key", lambda t: t + '[[case]]\nlabel = "a"\nwall = "1 m"\n', "case[1].wall",
     ["unknown key", "[[case]] takes"]),
    ("case with a bad value", lambda t: t + '[[case]]\nlabel = "a"\nT = "-1 s"\n', "case[1].T", ["must be > 0"]),
    ("zero duration", lambda t: t.replace('"10 s"', '"0 s"'), "scene.duration", ["must be > 0"]),
    ("duration in metres", lambda t: t.replace('"10 s"', '"10 m"'), "scene.duration", ["wrong dimension"]),
]


@pytest.mark.parametrize("edit, key, words", [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_bad_scene_one_clear_error(tmp_path, edit, key, words):
    text = edit(BASE)
    path, err = bad(tmp_path, text)
    msg = str(err)
    assert isinstance(err, ValueError)
    assert err.source == str(path) and err.key == key
    assert msg.startswith(f"{path}: {key}: "), msg   # file first, then the key
    assert msg.count("\n") == 0                       # one line, one problem
    for w in words:
        assert w in msg, (w, msg)


def test_invalid_toml_names_the_file_and_line(tmp_path):
    path, err = bad(tmp_path, BASE + "foo bar\n")
    assert err.key is None and str(err).startswith(f"{path}: invalid TOML")
    assert f"line {BASE.count(chr(10)) + 1}," in str(err)


def test_unreadable_and_non_utf8_files(tmp_path):
    with pytest.raises(SceneError, match="cannot read the scene file"):
        load_scene(tmp_path / "missing.toml")
    path = tmp_path / "latin1.toml"
    path.write_bytes(BASE.encode() + b'\n[scene]\ndescription = "\xe9"\n')
    with pytest.raises(SceneError, match="not UTF-8"):
        load_scene(path)


def test_text_and_dict_sources_are_named(tmp_path):
    with pytest.raises(SceneError, match=r"^<string>: plant\.m: "):
        load_scene(BASE.replace('"0.1 kg"', '"0.1 m"'))
    doc = tomllib.loads(BASE)
    doc["plant"]["m"] = "0.1 m"
    with pytest.raises(SceneError, match=r"^<dict>: plant\.m: "):
        load_scene(doc)
    with pytest.raises(SceneError, match=r"^mine: plant\.m: "):
        load_scene(doc, name="mine")


def test_scene_error_pickles():
    err = SceneError("a.toml", "plant.m", "must be > 0")
    back = pickle.loads(pickle.dumps(err))
    assert (back.source, back.key, back.problem, str(back)) == (err.source, err.key, err.problem, str(err))


# ---------------------------------------------------------------------------------------
# Values the C core would refuse, or could not hold, are the loader's error
# ---------------------------------------------------------------------------------------

DBL_MAX = sys.float_info.max
KNOB = '[knob]\npitch = "{pitch}"\ncount = {count}\nk_detent = "1 N/m"\nk_end = "2 N/m"\n'


def no_controller(t):
    return t.split("[controller]")[0]


# (description, edit of BASE, the key the error must name, words it must contain)
LIMITS = [
    # more samples than a case may have (2**28), or duration / T = inf
    ("T of 1 ns for 10 s", lambda t: t.replace('"0.01 s"', '"1 ns"'), "scene.duration",
     ["1e+10 samples", "268,435,456", "2**28", "373 GiB", "lengthen T"]),
    ("T of 1e-300 s", lambda t: t.replace('"0.1 kg"', '"1e-300 kg"').replace('"23 N*s/m"', '"0 N*s/m"')
     .replace('"0.01 s"', '"1e-300 s"'), "scene.duration", ["1e+301 samples", "2**28"]),
    ("duration / T overflows", lambda t: t.replace('"0.1 kg"', '"1e-300 kg"').replace('"23 N*s/m"', '"0 N*s/m"')
     .replace('"0.01 s"', '"1e-300 s"').replace('"10 s"', '"1e10 s"'), "scene.duration", ["inf samples", "2**28"]),
    ("one sample over the cap", lambda t: t.replace('"0.01 s"', '"1 s"').replace('"10 s"', f'"{2 ** 28 + 1} s"'),
     "scene.duration", ["2**28"]),
    ("window / T overflows", lambda t: t.replace('"0.01 s"', '"1 ms"') + '[verdict]\nwindow = "1e308 s"\n',
     "verdict.window", ["inf samples", "longer than the run (10000)"]),
    ("step index past the simulator's count", lambda t: t + '[reference]\nto = "1 mm"\nat = "1e20 s"\n',
     "reference.at", ["1e+20 s / 0.01 s = 1e+22 samples", "2**53", "within the duration"]),
    ("step index overflows", lambda t: t.replace('"0.01 s"', '"1e-300 s"').replace('"0.1 kg"', '"1e-300 kg"')
     .replace('"23 N*s/m"', '"0 N*s/m"').replace('"10 s"', '"1e-290 s"') + '[reference]\nto = "1 mm"\nat = "1e10 s"\n',
     "reference.at", ["inf samples", "2**53"]),
    ("integrator step / T overflows", lambda t: t + '[friction]\ncoulomb = "1 N"\n[integrator]\nstep = "1e-320 s"\n',
     "integrator.step", ["inf substeps per sample", "100000"]),
    ("integrator step too short", lambda t: t + '[friction]\ncoulomb = "1 N"\n[integrator]\nstep = "1 ns"\n',
     "integrator.step", ["1e+07 substeps per sample", "100000"]),
    # plants outside zw_device's range (each of m, b, T valid on its own)
    ("plant out of range", lambda t: t.replace('"0.1 kg"', '"1e-300 kg"').replace('"23 N*s/m"', '"1e10 N*s/m"')
     .replace('"0.01 s"', '"1 s"'), "[plant]", ["delta = b T/m = inf overflows", "m = 1e-300 kg",
                                                 "b = 1e+10 N*s/m", "T = 1 s", "change m, b or T"]),
    ("subnormal mass", lambda t: t.replace('"0.1 kg"', '"1e-320 kg"'), "plant.m",
     ["m = 9.99989e-321 kg is too small", "normal double"]),
    ("subnormal period", lambda t: t.replace('"0.01 s"', '"1e-320 s"'), "plant.T", ["T = 9.99989e-321 s is too small"]),
    ("m/T^2 overflows", lambda t: t.replace('"0.1 kg"', '"1e300 kg"').replace('"0.01 s"', '"1e-5 s"'), "[plant]",
     ["m/T^2 = inf overflows", "change m or T"]),
    ("case plant out of range", lambda t: t + '[[case]]\nlabel = "a"\nm = "1e-300 kg"\nb = "1e11 N*s/m"\n',
     "case[1]", ["delta = b T/m", "change m, b or T"]),
    # quantization finer than a double can count
    ("resolution too fine", lambda t: t + '[quantization]\nresolution = "1e-320 m"\n', "quantization.resolution",
     ["too small", "1/resolution = inf"]),
    # knob sizes
    ("knob with 3e9 positions", lambda t: no_controller(t) + KNOB.format(pitch="1 mm", count=3_000_000_000),
     "knob.count", ["at most 1,000,000", "3,000,000,000"]),
    ("knob beyond the doubles", lambda t: no_controller(t) + KNOB.format(pitch="1e303 m", count=1_000_000),
     "knob.pitch", ["last detent", "finite"]),
    # angles: pint reads rad as a plain number
    ("cutoff in rad/s", lambda t: t + '[velocity_filter]\ncutoff = "100 rad/s"\n', "velocity_filter.cutoff",
     ["angle", "Hz (cycles per second)", "15.9155 Hz"]),
    ("cutoff in rpm", lambda t: t + '[velocity_filter]\ncutoff = "30 rpm"\n', "velocity_filter.cutoff",
     ["angle", "Hz (cycles per second)", "0.5 Hz"]),
    ("cutoff in deg/s", lambda t: t + '[velocity_filter]\ncutoff = "360 deg/s"\n', "velocity_filter.cutoff",
     ["1 Hz"]),
    ("cutoff in turn/s", lambda t: t + '[velocity_filter]\ncutoff = "2 turn/s"\n', "velocity_filter.cutoff",
     ["2 Hz"]),
]


@pytest.mark.parametrize("edit, key, words", [b[1:] for b in LIMITS], ids=[b[0] for b in LIMITS])
def test_values_the_core_cannot_take_are_named(tmp_path, edit, key, words):
    path, err = bad(tmp_path, edit(BASE))
    msg = str(err)
    assert err.key == key and msg.startswith(f"{path}: {key}: "), msg
    assert msg.count("\n") == 0
    for w in words:
        assert w in msg, (w, msg)


def test_sample_cap_is_inclusive():
    scene = load_scene(BASE.replace('"0.01 s"', '"1 s"').replace('"10 s"', f'"{2 ** 28} s"'))
    assert scene.cases[0].samples == zwidth.scene.MAX_SAMPLES == 2 ** 28    # loading allocates nothing


def test_extreme_plant_scales_convert_the_gains_like_the_core():
    # m/T = 1e100 and m/T^2 = 1e-100 are normal doubles although T^2 = 1e400 overflows
    text = (BASE.replace('"0.1 kg"', '"1e300 kg"').replace('"23 N*s/m"', '"0 N*s/m"')
            .replace('"0.01 s"', '"1e200 s"').replace('"10 s"', '"1e203 s"')
            .replace('K = "100 N/m"\nB = "1 N*s/m"', "alpha = 2.0\nbeta = 0.5"))
    p = load_scene(text).cases[0].params
    assert p["K"] == pytest.approx(2e-100, rel=1e-15) and p["B"] == pytest.approx(0.5e100, rel=1e-15)


def test_plant_check_is_zwidth_device():
    # what load_scene refuses is what zwidth.Device refuses, and the reverse
    for m, b, T in [(1e-300, 1e10, 1.0), (1e300, 0.0, 1e-10), (1e-320, 1.0, 0.01), (0.1, 1e-320, 0.01),
                    (1e-300, 0.0, 1e-300), (1.0, 1e300, 1e8)]:
        text = f'[plant]\nm = "{m!r} kg"\nb = "{b!r} N*s/m"\nT = "{T!r} s"\n[controller]\nK = "0 N/m"\nB = "0 N*s/m"\n'
        text += f'[scene]\nduration = "{100 * T!r} s"\n'
        try:
            zwidth.Device(m, b, T)
        except zwidth.ZwidthError:
            with pytest.raises(SceneError, match="plant"):
                load_scene(text)
        else:
            assert load_scene(text).cases[0].params["m"] == m


def test_rk4_limit_is_evaluated_as_the_core_does():
    # zw_sim_init tests rate * (T / n) <= 2.5; rate * T / n rounds differently near the limit
    def scene(b, T, n):
        return (f'[plant]\nm = "1 kg"\nb = "{b!r} N*s/m"\nT = "{T!r} s"\n[controller]\nK = "0 N/m"\n'
                f'B = "0 N*s/m"\n[friction]\ncoulomb = "1 N"\n[integrator]\nsubsteps = {n}\n')

    def core_accepts(params):
        try:
            zwidth._core.Simulator(params)
        except ValueError:
            return False
        return True

    # 2125 * 0.02 / 17 == 2.5 but 2125 * (0.02 / 17) > 2.5: the core refuses, so must the loader
    assert 2125.0 * 0.02 / 17 <= 2.5 < 2125.0 * (0.02 / 17)
    p = load_scene(scene(2125.0, 0.02, 18)).cases[0].params
    assert not core_accepts({**p, "substeps": 17})
    with pytest.raises(SceneError, match=r"integrator\.substeps: 17 substeps .* use at least 18"):
        load_scene(scene(2125.0, 0.02, 17))
    # 7500.000000000001 * 0.001 / 3 > 2.5 but the core's order gives <= 2.5: both accept
    b = 7500.000000000001
    assert b * 0.001 / 3 > 2.5 >= b * (0.001 / 3)
    p = load_scene(scene(b, 0.001, 3)).cases[0].params
    assert (p["b"], p["T"], p["substeps"]) == (b, 0.001, 3) and core_accepts(p)


def test_angles_in_frequencies_and_rotary_velocities():
    # a frequency in Hz or 1/s is taken as cycles per second
    for cutoff, hz in (("1.2 kHz", 1200.0), ("50 / s", 50.0), ("20 Hz", 20.0)):
        _, p = one(BASE + f'[velocity_filter]\ncutoff = "{cutoff}"\n')
        assert p["cutoff_hz"] == pytest.approx(hz, rel=1e-15)
    rotary = ('[plant]\nJ = "1e-5 kg*m^2"\nb = "1e-3 N*m*s/rad"\nT = "0.01 s"\n[controller]\n'
              'K = "0.1 N*m/rad"\nB = "0 N*m*s/rad"\n')
    # a rotary velocity is an angle per time: rad/s, deg/s, turn/s, rpm (2 pi / 60 rad/s)
    for v, rad_s in (("3 rad/s", 3.0), ("90 deg/s", math.pi / 2), ("0.5 turn/s", math.pi),
                     ("1 rpm", 2 * math.pi / 60), ("30 rpm", math.pi)):
        _, p = one(rotary + f'[initial]\nv = "{v}"\n')
        assert p["v_init"] == pytest.approx(rad_s, rel=1e-14), v
        _, p = one(rotary + f'[hand]\nstiffness = "1 N*m/rad"\nto = "1 rad"\nspeed = "{v}"\n')
        assert p["hand_speed"] == pytest.approx(rad_s, rel=1e-14), v
    # ... and Hz or 1/s is ambiguous there (10 rad/s or 10 turns per second?)
    for v in ("10 Hz", "10 / s", "10 rad/rad/s"):
        with pytest.raises(SceneError, match=r"initial\.v: .* ambiguous .* rad/s"):
            load_scene(rotary + f'[initial]\nv = "{v}"\n')
        with pytest.raises(SceneError, match=r"hand\.speed: .* ambiguous"):
            load_scene(rotary + f'[hand]\nstiffness = "1 N*m/rad"\nspeed = "{v}"\n')
    # a translational velocity has no angle to confuse
    _, p = one(BASE + '[initial]\nv = "2 mm/s"\n')
    assert p["v_init"] == pytest.approx(0.002, rel=1e-15)


# ---------------------------------------------------------------------------------------
# Units: SI values from hand-computed factors
# ---------------------------------------------------------------------------------------


def one(text):
    scene = load_scene(text)
    assert len(scene.cases) == 1
    return scene, scene.cases[0].params


def test_units_are_converted_to_si():
    text = BASE.replace('"0.1 kg"', '"100 g"').replace('"23 N*s/m"', '"0.023 N*s/mm"').replace(
        '"0.01 s"', '"10 ms"').replace('"100 N/m"', '"0.1 N/mm"') + (
        '[reference]\nfrom = "1 cm"\nto = "2 inch"\nat = "0.5 min"\n'
        '[saturation]\nforce_max = "0.2 lbf"\n'
        '[velocity_filter]\ncutoff = "1.2 kHz"\n'
        '[quantization]\nresolution = "10 um"\n')
    scene, p = one(text)
    assert scene.rotary is False
    assert p["m"] == pytest.approx(0.1, rel=1e-15)
    assert p["b"] == pytest.approx(23.0, rel=1e-15)
    assert p["T"] == pytest.approx(0.01, rel=1e-15)
    assert p["K"] == pytest.approx(100.0, rel=1e-15)
    assert p["x_eq_before"] == pytest.approx(0.01, rel=1e-15)
    assert p["x_eq_after"] == pytest.approx(2 * 0.0254, rel=1e-15)       # inch = 25.4 mm exactly
    assert p["t_step"] == pytest.approx(30.0, rel=1e-15)
    assert p["force_max"] == pytest.approx(0.2 * 4.4482216152605, rel=1e-12)  # lbf, by definition
    assert p["cutoff_hz"] == pytest.approx(1200.0, rel=1e-15)
    assert p["counts_per_unit"] == pytest.approx(1e5, rel=1e-12)


def test_rotary_units_are_radians():
    text = """
[plant]
J = "85.78e-7 kg*m^2"
b = "2.197e-3 N*m*s/rad"
T = "0.02 s"
[knob]
first = "-90 deg"
pitch = "0.125 turn"
count = 5
k_detent = "0.25 N*m/rad"
k_end = "0.4 N*m"
damping = "-1.36e-3 N*m*s/rad"
[quantization]
counts = "4096 / turn"
[initial]
v = "60 rpm"
"""
    scene, p = one(text)
    assert scene.rotary and scene.units["position"] == "rad" and scene.units["force"] == "N*m"
    assert p["m"] == pytest.approx(85.78e-7, rel=1e-15)
    assert p["knob_first"] == pytest.approx(-math.pi / 2, rel=1e-15)
    assert p["knob_pitch"] == pytest.approx(math.pi / 4, rel=1e-15)
    assert p["knob_k_end"] == 0.4          # rad is dimensionless: N*m and N*m/rad are the same
    assert p["counts_per_unit"] == pytest.approx(4096 / (2 * math.pi), rel=1e-14)
    assert p["v_init"] == pytest.approx(2 * math.pi, rel=1e-14)   # 60 rpm = one turn a second
    assert scene.cases[0].normalized is None   # the knob sets the gains


def test_rotary_position_in_metres_is_an_error():
    text = """
[plant]
J = "1e-5 kg*m^2"
b = "1e-3 N*m*s/rad"
T = "0.01 s"
[controller]
K = "0.1 N*m/rad"
B = "0 N*m*s/rad"
[reference]
to = "1 m"
"""
    with pytest.raises(SceneError, match=r"reference\.to: wrong dimension: '1 m' is not an angle"):
        load_scene(text)
    with pytest.raises(SceneError, match=r"reference\.to: missing units in '1'"):
        load_scene(text.replace('"1 m"', '"1"'))


def test_normalized_gains_use_each_case_plant():
    text = BASE.replace('K = "100 N/m"\nB = "1 N*s/m"', "alpha = 5.0\nbeta = 1.0") + (
        '[[case]]\nlabel = "a"\n'
        '[[case]]\nlabel = "b"\nm = "0.2 kg"\nT = "0.02 s"\n'
        '[[case]]\nlabel = "c"\nbeta = -2.0\n'
        '[[case]]\nlabel = "d"\nK = "7 N/m"\nB = "3 N*s/m"\n')
    scene = load_scene(text)
    a, b, c, d = scene.cases
    # K = alpha m / T^2, B = beta m / T, by hand:
    assert (a.params["K"], a.params["B"]) == pytest.approx((5000.0, 10.0), rel=1e-15)
    assert (b.params["K"], b.params["B"]) == pytest.approx((2500.0, 10.0), rel=1e-15)
    assert (c.params["K"], c.params["B"]) == pytest.approx((5000.0, -20.0), rel=1e-15)   # key by key
    assert (d.params["K"], d.params["B"]) == (7.0, 3.0)        # the other form replaces both
    assert a.normalized == pytest.approx((2.3, 5.0, 1.0), rel=1e-15)
    assert b.normalized == pytest.approx((23 * 0.02 / 0.2, 5.0, 1.0), rel=1e-15)
    assert d.normalized == pytest.approx((2.3, 7 * 1e-4 / 0.1, 3 * 0.01 / 0.1), rel=1e-15)


# ---------------------------------------------------------------------------------------
# Defaults
# ---------------------------------------------------------------------------------------


def test_defaults_of_a_minimal_scene():
    scene, p = one(BASE.replace('[scene]\nname = "base"\nduration = "10 s"\n', ""))
    assert scene.name == "scene" and scene.duration == 10.0 and scene.linear
    assert p["effects"] == 0 and "substeps" not in p
    assert (p["x_init"], p["v_init"], p["x_eq_before"], p["x_eq_after"], p["t_step"]) == (0, 0, 0, 0, 0)
    case = scene.cases[0]
    # 10 s at T = 0.01 s: 1000 samples; 8 windows covering the second half: 1000 // 16 = 62 each
    assert (case.samples, case.windows, case.window, case.tolerance) == (1000, 8, 62, None)
    assert case.label == "scene"


def test_file_name_is_the_default_name(tmp_path):
    path = tmp_path / "my-scene.toml"
    path.write_text(BASE.replace('name = "base"\n', ""))
    assert load_scene(path).name == "my-scene"


@pytest.mark.parametrize("duration, T, samples", [("10 s", "0.01 s", 1000), ("1 s", "0.03 s", 34),
                                                  ("0.3 s", "0.1 s", 3), ("1 ms", "1 s", 1)])
def test_samples_cover_the_duration(duration, T, samples):
    text = BASE.replace('"10 s"', f'"{duration}"').replace('"0.01 s"', f'"{T}"') + "[verdict]\nwindow = \"1 s\"\nwindows = 2\n"
    if samples < 2:
        with pytest.raises(SceneError, match="windows"):
            load_scene(text)
        return
    text = text.replace('window = "1 s"', f'window = "{T}"')
    assert load_scene(text).cases[0].samples == samples


def test_verdict_settings():
    scene, _ = one(BASE + '[verdict]\nwindow = "1 s"\nwindows = 3\ntolerance = "1 mm"\n')
    c = scene.cases[0]
    assert (c.window, c.windows, c.tolerance) == (100, 3, 0.001)
    scene, _ = one(BASE + "[verdict]\nwindows = 5\n")
    assert (scene.cases[0].window, scene.cases[0].windows) == (100, 5)   # 1000 // (2 * 5)


HAND = '[hand]\nmass = "{mh}"\nstiffness = "{kh}"\ndamping = "{bh}"\n'


@pytest.mark.parametrize("plant, hand, extra, n", [
    # b/m = 230 /s, T = 0.01: 2.3 / 0.05 = 46 substeps
    (("0.1 kg", "23 N*s/m", "0.01 s"), None, '[friction]\ncoulomb = "1 N"\n', 46),
    # slow plant: 0.01 * 1 / 0.05 = 0.2 -> the floor of 10
    (("1 kg", "1 N*s/m", "0.01 s"), None, '[friction]\ncoulomb = "1 N"\n', 10),
    # hand spring dominates: sqrt(1e4 / (0.5 + 0.5)) = 100 /s -> 1 / 0.05 = 20
    (("0.5 kg", "0 N*s/m", "0.01 s"), ("0.5 kg", "1e4 N/m", "0 N*s/m"), "", 20),
    # hand damping dominates: (1 + 99) / (0.1 + 0.9) = 100 /s vs b/m = 10 /s -> 20
    (("0.1 kg", "1 N*s/m", "0.01 s"), ("0.9 kg", "0 N/m", "99 N*s/m"), "", 20),
    # the knob drive: b/J = 2.197e-3 / 85.78e-7 = 256.12 /s, T = 0.02: 5.1224 / 0.05 -> 103
    (("85.78e-7 kg*m^2", "2.197e-3 N*m*s/rad", "0.02 s"), ("1e-6 kg*m^2", "0.1 N*m/rad", "1e-4 N*m*s/rad"), "", 103),
])
def test_default_substeps(plant, hand, extra, n):
    mass_key = "J" if "m^2" in plant[0] else "m"
    text = f'[plant]\n{mass_key} = "{plant[0]}"\nb = "{plant[1]}"\nT = "{plant[2]}"\n'
    text += "[controller]\nK = \"0 {}\"\nB = \"0 {}\"\n".format(*(("N*m/rad", "N*m*s/rad") if mass_key == "J" else ("N/m", "N*s/m")))
    if hand:
        text += HAND.format(mh=hand[0], kh=hand[1], bh=hand[2])
    text += extra
    _, p = one(text)
    assert p["substeps"] == n


@pytest.mark.parametrize("integrator, n", [("substeps = 7", 7), ('step = "0.3 ms"', 33),   # 10/0.3 = 33.3
                                           ('step = "0.35 ms"', 29), ('step = "1 s"', 1)])    # 28.6; >= 1
def test_integrator_step_rounds_to_whole_substeps(integrator, n):
    _, p = one(BASE + f'[friction]\ncoulomb = "1 N"\n[integrator]\n{integrator}\n')
    assert p["substeps"] == n


def test_too_few_substeps_for_rk4(tmp_path):
    # m = 0.1 kg, b = 0; hand 0.1 kg, k_h = 4e4 N/m, b_h = 20 N s/m: |s| <= 20/0.2 +
    # sqrt(4e4/0.2) = 547.2 /s; T = 0.01 s: RK4 needs h |s| <= 2.5, so n >= 2.19 -> 3
    text = BASE.replace('"23 N*s/m"', '"0 N*s/m"') + HAND.format(mh="0.1 kg", kh="4e4 N/m", bh="20 N*s/m")
    _, p = one(text + "[integrator]\nsubsteps = 3\n")
    assert p["substeps"] == 3 and zwidth._core.Simulator(p).run(1)["x"][0] == 0.0
    with pytest.raises(ValueError, match="ZW_ERR_ARG"):      # the loader mirrors zw_sim_init
        zwidth._core.Simulator({**p, "substeps": 2})
    _, err = bad(tmp_path, text + "[integrator]\nsubsteps = 2\n")
    assert err.key == "integrator.substeps" and "use at least 3" in str(err)


def test_effect_bits_follow_the_sections():
    for path in SCENE_FILES:
        scene = load_scene(path)
        expected = sum(zwidth._core.SIM_EFFECTS[e] for e in scene.effects)
        text = path.read_text()
        named = [e for e in zwidth._core.SIM_EFFECTS if f"[{e}]" in text]
        assert sorted(scene.effects) == sorted(named)
        assert all(c.params["effects"] == expected for c in scene.cases)


def test_hand_defaults_and_infinities():
    _, p = one(BASE + '[initial]\nx = "5 mm"\n[hand]\nstiffness = "10 N/m"\n')
    assert p["hand_from"] == p["hand_to"] == 0.005            # from the initial position
    assert p["hand_t_release"] == math.inf and p["hand_speed"] == math.inf
    assert (p["hand_mass"], p["hand_damping"], p["hand_t_grasp"]) == (0.0, 0.0, 0.0)


# ---------------------------------------------------------------------------------------
# Round trips
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("path", SCENE_FILES, ids=[p.name for p in SCENE_FILES])
def test_file_text_dict_and_to_toml_load_the_same_scene(path):
    text = path.read_text()
    from_file = load_scene(path)
    assert from_file.source == str(path)
    assert load_scene(text) == from_file
    assert load_scene(tomllib.loads(text)) == from_file
    again = load_scene(from_file.to_toml())
    assert again == from_file
    for c1, c2 in zip(again.cases, from_file.cases):   # bit for bit, not approximately
        assert c1.params.keys() == c2.params.keys()
        for k in c1.params:
            assert np.array_equal(c1.params[k], c2.params[k]), k


def test_schedule_round_trip_and_with_duration():
    text = BASE.split("[controller]")[0] + (
        '[[schedule]]\nat = "0 s"\nK = "100 N/m"\nB = "1 N*s/m"\n'
        '[[schedule]]\nat = "2 s"\nK = "50 N/m"\nB = "2 N*s/m"\n')
    scene = load_scene(text)
    np.testing.assert_array_equal(scene.cases[0].params["schedule"], [[0, 100, 1], [2, 50, 2]])
    assert load_scene(scene.to_toml()) == scene
    longer = scene.with_duration(30.0)
    assert longer.duration == 30.0 and longer.cases[0].samples == 3000 and longer.cases[0].window == 187
    assert longer != scene and longer.with_duration(10.0) == scene


def test_case_lookup_and_repr():
    scene = load_scene(SCENES / "paper-fig15.toml")
    assert scene.labels == tuple(f"P{i}" for i in range(1, 13))
    assert scene.case("P8").params["b"] == 30.0
    with pytest.raises(KeyError, match="P13"):
        scene.case("P13")
    assert "12 cases" in repr(scene) and "linear" in repr(scene)


# ---------------------------------------------------------------------------------------
# The paper's scenes say what the paper says
# ---------------------------------------------------------------------------------------


def test_fig15_points_follow_the_paper():
    """Section V-A: m = 0.1 kg, T = 0.01 s, b = 23, 30, 50; step 0 -> 1 m; the roles of the
    points as the text describes them (verdicts from zwidth's exact and legacy regions)."""
    scene = load_scene(SCENES / "paper-fig15.toml")
    pts = {c.label: c for c in scene.cases}
    for label, c in pts.items():
        p = c.params
        assert (p["m"], p["T"], p["x_eq_before"], p["x_eq_after"], p["t_step"]) == (0.1, 0.01, 0.0, 1.0, 0.0)
        i = int(label[1:])
        assert p["b"] == {1: 23.0, 2: 30.0, 3: 50.0}[(i - 1) // 4 + 1]
    delta = {k: c.normalized[0] for k, c in pts.items()}
    alpha = {k: c.normalized[1] for k, c in pts.items()}
    beta = {k: c.normalized[2] for k, c in pts.items()}
    exact = {k: bool(zwidth.check(delta[k], alpha[k], beta[k])) for k in pts}
    legacy = {k: bool(zwidth.check(delta[k], alpha[k], beta[k], region="legacy")) for k in pts}
    for k in ("P6", "P8", "P10", "P12"):
        assert legacy[k] and not exact[k], k
    assert (alpha["P2"], beta["P2"]) == (alpha["P8"], beta["P8"]) and exact["P2"]
    assert alpha["P3"] < 0 and beta["P4"] < -delta["P4"]
    assert beta["P9"] == 0 and exact["P9"]
    assert beta["P11"] < 0 and alpha["P11"] > alpha["P9"] and exact["P11"]
    assert [exact[f"P{i}"] for i in range(1, 13)] == [True, True, False, False, True, False, True,
                                                      False, True, False, True, False]
    # margins that 1000 samples decide: every spectral radius at least 0.0135 from 1
    rho = [float(zwidth.spectral_radius(delta[k], alpha[k], beta[k])) for k in pts]
    assert min(abs(r - 1.0) for r in rho) >= 0.0135


def test_knob_scenes_follow_the_paper():
    """Section V-B-4: J, b, T of the short-circuited drive; ES/IPS/VD of each plan; the exact
    plan stable at both stiffnesses, the legacy one's end stiffness not (analysis)."""
    plans = {"exact": (0.4, 0.25, -1.36e-3), "legacy": (0.46, 0.29, 0.03e-3)}
    for plan, (es, ips, vd) in plans.items():
        scene = load_scene(SCENES / f"knob-{plan}.toml")
        p = scene.cases[0].params
        assert scene.rotary and set(scene.effects) == {"knob", "hand"}
        assert (p["m"], p["b"], p["T"]) == (85.78e-7, 2.197e-3, 0.02)
        assert (p["knob_k_end"], p["knob_k_detent"], p["knob_damping"]) == (es, ips, vd)
        assert p["knob_count"] == 5 and p["knob_pitch"] == pytest.approx(math.pi / 4, rel=1e-15)
        dev = zwidth.Device.rotary(p["m"], p["b"], p["T"])
        assert bool(dev.is_stable(ips, vd))
        assert bool(dev.is_stable(es, vd)) == (plan == "exact")
        assert bool(dev.is_stable(es, vd, region="legacy"))      # what the legacy plan relied on
    a = load_scene(SCENES / "knob-exact.toml").cases[0].params
    b = load_scene(SCENES / "knob-legacy.toml").cases[0].params
    assert {k: v for k, v in a.items() if k.startswith("hand_")} == \
        {k: v for k, v in b.items() if k.startswith("hand_")}      # the same hand for both


def test_dimensionless_unit_is_a_wrong_dimension_not_missing_units():
    """Review 4 nit: "10 percent" for a mass said "missing units" (it has a unit, one that
    cancels to a plain number)."""
    with pytest.raises(SceneError) as e:
        load_scene({"plant": {"m": "10 percent", "b": "1 N*s/m", "T": "1 ms"},
                    "controller": {"K": "1 N/m", "B": "0 N*s/m"}})
    assert e.value.key == "plant.m" and "wrong dimension" in e.value.problem and "plain number" in e.value.problem
