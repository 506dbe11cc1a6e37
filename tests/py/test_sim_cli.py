# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""``zwidth simulate`` through its entry point (as test_cli.py runs the command): verdicts,
exit codes, the --json schema, the CSV and NPZ files (bit for bit against the Python API),
plots under the Agg backend, the progress bar; and the API behind it (simulate,
SimulationSet).  Physical checks are against hand-computed statics, not our own output.
"""
from __future__ import annotations

import csv
import json
import math
import os
from pathlib import Path

import numpy as np
import pytest

import zwidth
from test_cli import run

REPO = Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
AGG = {**os.environ, "MPLBACKEND": "Agg"}

FIG15_STABLE = [True, True, False, False, True, False, True, False, True, False, True, False]


def simulate_json(*args, code):
    r = run("simulate", *args, "--json")
    assert r.returncode == code, (r.returncode, r.stdout, r.stderr)
    assert r.stderr == ""
    return json.loads(r.stdout)


# ---------------------------------------------------------------------------------------
# The paper's scenes
# ---------------------------------------------------------------------------------------


def test_fig15_reproduces_the_paper_pattern():
    obj = simulate_json(SCENES / "paper-fig15.toml", code=1)   # six points are unstable
    assert obj["command"] == "simulate"
    assert obj["scene"]["linear"] is True and obj["scene"]["effects"] == []
    cases = obj["cases"]
    assert [c["label"] for c in cases] == [f"P{i}" for i in range(1, 13)]
    assert [c["verdict"]["outcome"] == "stable" for c in cases] == FIG15_STABLE
    assert all(c["verdict"]["outcome"] != "undecided" for c in cases)
    assert all(c["agrees"] is True for c in cases)
    assert [c["analytic"]["stable"] for c in cases] == FIG15_STABLE
    for c in cases:
        legacy_only = c["label"] in ("P6", "P8", "P10", "P12")
        assert c["analytic"]["legacy_stable"] == (c["analytic"]["stable"] or legacy_only)
        assert c["samples"] == 1000 and c["T"] == 0.01
        if c["verdict"]["outcome"] == "unstable":
            # the envelope's growth per sample is the dominant pole's modulus
            assert c["verdict"]["growth"] == pytest.approx(c["analytic"]["spectral_radius"], rel=2e-3)
    assert obj["summary"] == {"cases": 12, "stable": 6, "unstable": 6, "undecided": 0,
                              "compared": 12, "agree": 12}
    assert obj["out"] is None and obj["plot"] is None


def test_fig15_text_output():
    r = run("simulate", SCENES / "paper-fig15.toml")
    assert r.returncode == 1 and r.stderr == ""
    lines = r.stdout.splitlines()
    row = next(line for line in lines if line.strip().startswith("P8 "))
    assert row.split() == ["P8", "3", "0.25", "7.5", "unstable", row.split()[5], "unstable", "yes", "stable"]
    assert "12 cases: 6 stable, 6 unstable; simulated = analytic (exact region) for 12 of 12" in r.stdout


def test_knob_legacy_oscillates_at_the_wall_and_exact_does_not(tmp_path):
    runs = {}
    for plan in ("exact", "legacy"):
        out = tmp_path / f"{plan}.npz"
        obj = simulate_json(SCENES / f"knob-{plan}.toml", "--out", out, code=0 if plan == "exact" else 1)
        with np.load(out) as npz:
            label = str(npz["labels"][0])
            runs[plan] = {k: npz[f"{label}/{k}"] for k in ("t", "x", "stiffness", "stiffness_planned", "hand_force")}
        runs[plan]["json"] = obj["cases"][0]
    exact, legacy = runs["exact"], runs["legacy"]
    assert exact["json"]["verdict"]["outcome"] == "stable"
    assert legacy["json"]["verdict"]["outcome"] in ("unstable", "undecided")   # never settles
    assert exact["json"]["analytic"] is None and exact["json"]["params"]["hand_t_release"] is None  # inf
    last, wall = math.pi, math.radians(200.0)    # fifth detent; where the hand is heading
    tail = {plan: r["x"][r["t"] >= 4.0] for plan, r in runs.items()}
    # exact: at rest against the end wall where the hand's spring and the wall balance:
    # k_h (x_h - x) = k_end (x - p_last)  ->  x = (0.1 * 200 deg + 0.4 * 180 deg) / 0.5 = 184 deg
    assert np.ptp(tail["exact"]) < 1e-6
    assert tail["exact"][-1] == pytest.approx((0.1 * wall + 0.4 * last) / 0.5, rel=1e-6)
    # legacy: rattles across the end wall by tens of degrees, to the end of the run
    assert np.degrees(np.ptp(tail["legacy"])) > 20.0
    assert tail["legacy"].min() < last < tail["legacy"].max()
    assert np.degrees(np.ptp(legacy["x"][legacy["t"] >= 5.0])) > 20.0
    # the stiffness the knob rendered switches between the end wall's and the detents'
    k = legacy["stiffness"][legacy["t"] >= 4.0]
    assert {0.46, 0.29} <= set(np.round(k, 6)) and np.sum(np.diff(k) != 0) > 10


def test_wall_hand_statics(tmp_path):
    out = tmp_path / "wall.npz"
    obj = simulate_json(SCENES / "wall-hand.toml", "--out", out, code=0)
    case = obj["cases"][0]
    assert case["verdict"]["outcome"] == "stable" and case["params"]["substeps"] == 10
    with np.load(out) as npz:
        x, xm = npz["wall-hand/x"], npz["wall-hand/x_measured"]
        wall, hand = npz["wall-hand/wall_force"], npz["wall-hand/hand_force"]
    # at rest the arm (200 N/m toward 40 mm) and the wall (2000 N/m from 20 mm) share the push
    x_rest = 0.020 + 200.0 / 2200.0 * 0.020
    assert x[-1] == pytest.approx(x_rest, rel=1e-9)
    assert wall[-1] == pytest.approx(-2000.0 * (x[-1] - 0.020), rel=1e-9)
    assert hand[-1] == pytest.approx(-wall[-1], rel=1e-9)
    assert np.all(wall <= 0.0) and np.all(wall[xm <= 0.020] == 0.0)   # it never pulls


def test_stick_slip_csv(tmp_path):
    out = tmp_path / "slip.csv"
    obj = simulate_json(SCENES / "stick-slip.toml", "--out", out, code=0)
    assert obj["out"] == str(out)
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    assert header == ["case", "t [s]", "x [m]", "v [m/s]", "x_measured [m]", "force [N]", "friction [N]",
                      "hand_force [N]", "hand_target [m]"]
    assert len(body) == 8000 and {r[0] for r in body} == {"stick-slip"}
    a = np.array([[float(v) for v in r[1:]] for r in body])
    t, x, v, xm, friction = a[:, 0], a[:, 1], a[:, 2], a[:, 3], a[:, 5]
    # the CSV holds the API's numbers exactly (%.17g)
    api = zwidth.simulate(SCENES / "stick-slip.toml")[0]
    assert np.array_equal(x, api.x) and np.array_equal(friction, api.signals["friction"])
    # 10 um encoder: x_measured = floor(x / 10 um) * 10 um
    counts = xm / 1e-5
    assert np.allclose(counts, np.round(counts), rtol=0, atol=1e-6)
    assert np.all(xm <= x + 1e-15) and np.all(x - xm < 1e-5 + 1e-15)
    # friction: at rest within stiction (0.5 N), sliding exactly Coulomb (0.3 N) against v
    stuck = v == 0.0
    assert np.all(np.abs(friction[stuck]) <= 0.5 + 1e-12)
    sliding = ~stuck & (np.abs(friction) > 0)
    assert np.all(np.abs(friction[sliding]) == 0.3)
    # stick-slip: the slider stops again and again while the hand drags it (0 .. 3 s)
    drag = t < 3.0
    stops = np.sum(np.diff(stuck[drag].astype(int)) == 1)
    assert stops >= 3


def test_npz_matches_the_api_bit_for_bit(tmp_path):
    out = tmp_path / "run.npz"
    simulate_json(SCENES / "paper-fig15.toml", "--out", out, code=1)
    sims = zwidth.simulate(SCENES / "paper-fig15.toml")
    with np.load(out) as npz:
        assert list(npz["labels"]) == list(sims.labels)
        for s in sims:
            for name in ("t", "x", "v", "x_measured", "force"):
                assert np.array_equal(npz[f"{s.label}/{name}"], getattr(s, name), equal_nan=True), (s.label, name)


# ---------------------------------------------------------------------------------------
# Plots
# ---------------------------------------------------------------------------------------


def assert_picture(path: Path):
    data = path.read_bytes()
    if path.suffix == ".png":
        assert data[:8] == PNG_SIGNATURE and len(data) > 20000
        mpimg = pytest.importorskip("matplotlib.image")
        pixels = mpimg.imread(path)
        assert pixels.shape[0] > 200 and pixels.shape[1] > 400 and float(pixels[..., :3].std()) > 0.05
    else:
        assert b"<svg" in data[:2000] and len(data) > 20000


@pytest.mark.parametrize("scene, suffix", [("paper-fig15", ".png"), ("knob-legacy", ".png"),
                                           ("wall-hand", ".svg"), ("stick-slip", ".png")])
def test_plot_written(tmp_path, scene, suffix):
    pytest.importorskip("matplotlib")
    out = tmp_path / f"fig{suffix}"
    r = run("simulate", SCENES / f"{scene}.toml", "--plot", out, "--json", "--dpi", "60", env=AGG)
    assert r.returncode in (0, 1), r.stderr
    assert json.loads(r.stdout)["plot"] == str(out)
    assert_picture(out)


def test_plot_labels_verdicts():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import zwidth.plot as zp
    sims = zwidth.simulate(SCENES / "paper-fig15.toml", duration=3.0)
    fig = zp.simulation(sims)
    try:
        panels = [ax for ax in fig.axes if ax.get_visible()]
        assert len(panels) == 12
        texts = {ax.get_title().split(":")[0]: " ".join(t.get_text() for t in ax.texts) for ax in panels}
        assert "simulated: unstable" in texts["P6"] and "exact: unstable" in texts["P6"]
        assert "legacy: stable" in texts["P6"]
        assert "simulated: stable" in texts["P1"] and "exact: stable" in texts["P1"]
        # P2's slowest pole (0.9865) leaves 2 % of the step after 3 s: too short to decide
        assert "simulated: undecided" in texts["P2"] and "disagree" not in texts["P2"]
        # the curve drawn is the simulated position
        line = panels[5].get_lines()[0]
        assert np.array_equal(line.get_ydata(), sims.by_label("P6").x)
    finally:
        plt.close(fig)
    knob = zwidth.simulate(SCENES / "knob-exact.toml")
    fig = zp.simulation(knob)
    try:
        ax_k = fig.axes[0]
        planned = ax_k.get_lines()[0]
        # the planned map: end walls at ES beyond the end detents, +-IPS in between
        assert set(np.round(planned.get_ydata(), 9)) == {0.4, 0.25, -0.25}
        assert "stiffness" in ax_k.get_ylabel()
    finally:
        plt.close(fig)


# ---------------------------------------------------------------------------------------
# Exit codes and errors
# ---------------------------------------------------------------------------------------


def test_invalid_scene_exit_3(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text((SCENES / "paper-fig15.toml").read_text().replace('m = "0.1 kg"', 'm = "0.1 m"'))
    r = run("simulate", path)
    assert r.returncode == 3 and r.stdout == ""
    assert r.stderr.strip() == (f"zwidth simulate: error: invalid scene: {path}: plant.m: wrong dimension: "
                                f"'0.1 m' is not a mass (expected units like kg, e.g. \"0.1 kg\")")
    r = run("simulate", tmp_path / "missing.toml")
    assert r.returncode == 3 and "cannot read the scene file" in r.stderr and r.stdout == ""


@pytest.mark.parametrize("args, words", [
    (("--out", "run.txt"), "must end in .npz or .csv"),
    (("--plot", "fig.pdf"), "must end in .png or .svg"),
    (("--duration", "10 m"), "wrong dimension"),
    (("--duration", "-1 s"), "must be > 0"),
    (("--duration", "soon"), "--duration"),
    (("--dpi", "0"), "--dpi"),
    (("--frobnicate",), "unrecognized arguments"),
])
def test_usage_errors_exit_2(tmp_path, args, words):
    r = run("simulate", SCENES / "wall-hand.toml", *args, cwd=tmp_path)
    assert r.returncode == 2 and words in r.stderr and r.stdout == ""
    assert not list(tmp_path.iterdir())     # nothing written


def test_unwritable_outputs(tmp_path):
    r = run("simulate", SCENES / "wall-hand.toml", "--out", tmp_path / "no" / "run.npz")
    assert r.returncode == 2 and "cannot write" in r.stderr
    pytest.importorskip("matplotlib")
    r = run("simulate", SCENES / "wall-hand.toml", "--plot", tmp_path / "no" / "fig.png", env=AGG)
    assert r.returncode == 4 and "cannot plot" in r.stderr and "cannot write" in r.stderr


def test_missing_matplotlib_exit_4(tmp_path):
    shim = tmp_path / "shim" / "matplotlib"
    shim.mkdir(parents=True)
    (shim / "__init__.py").write_text("raise ImportError('no matplotlib in this test')\n")
    path = os.pathsep.join([str(shim.parent)] + [p for p in [os.environ.get("PYTHONPATH")] if p])
    r = run("simulate", SCENES / "wall-hand.toml", "--plot", tmp_path / "f.png",
            env={**os.environ, "PYTHONPATH": path})
    assert r.returncode == 4 and "pip install zwidth[plot]" in r.stderr
    assert not (tmp_path / "f.png").exists()


@pytest.mark.parametrize("duration, samples", [("2 s", 200), ("500 ms", 50), ("3", 300)])
def test_duration_override(duration, samples):
    obj = simulate_json(SCENES / "paper-fig15.toml", "--duration", duration, code=1)
    assert {c["samples"] for c in obj["cases"]} == {samples}
    assert obj["scene"]["duration"] == samples * 0.01


def test_help():
    r = run("simulate", "--help")
    assert r.returncode == 0
    for words in ("docs/scenes.md", "--out", "--plot", "--duration", "--no-progress", "undecided",
                  "exit status", "--json keys", "legacy_stable", "RUN.npz"):
        assert words in r.stdout, words
    top = run("--help")
    assert "simulate" in top.stdout


# ---------------------------------------------------------------------------------------
# Progress bar
# ---------------------------------------------------------------------------------------

LONG = """\
[scene]
name = "long"
duration = "80 s"
[plant]
m = "0.1 kg"
b = "0.05 N*s/m"
T = "1 ms"
[controller]
K = "0 N/m"
B = "0.5 N*s/m"
[friction]
coulomb = "0.3 N"
stiction = "0.5 N"
[hand]
stiffness = "50 N/m"
to = "30 mm"
speed = "10 mm/s"
[integrator]
substeps = 1000
"""


def test_progress_bar_on_long_runs(tmp_path):
    path = tmp_path / "long.toml"
    path.write_text(LONG)
    r = run("simulate", path)
    assert r.returncode == 0
    assert "sample/s" in r.stderr and "long" in r.stderr      # tqdm, on stderr only
    assert "sample/s" not in r.stdout
    quiet = run("simulate", path, "--no-progress")
    assert quiet.returncode == 0 and quiet.stderr == "" and quiet.stdout == r.stdout
    short = run("simulate", SCENES / "wall-hand.toml")
    assert short.stderr == ""                                  # short runs: no bar


# ---------------------------------------------------------------------------------------
# The Python API behind the command
# ---------------------------------------------------------------------------------------


def test_chunked_run_equals_one_run(capsys):
    scene = zwidth.load_scene(SCENES / "stick-slip.toml")
    whole = zwidth.simulate(scene)
    import zwidth.sim as zs
    old = zs._CHUNK_WORK
    try:
        zs._CHUNK_WORK = 1000        # many chunks: the run continues exactly where it stopped
        pieces = zwidth.simulate(scene, progress=True)
    finally:
        zs._CHUNK_WORK = old
    for name, a in whole[0].arrays.items():
        assert np.array_equal(a, pieces[0].arrays[name]), name
    assert "stick-slip" in capsys.readouterr().err


def test_simulation_set_api():
    sims = zwidth.simulate(SCENES / "paper-fig15.toml", duration=2.0)
    assert isinstance(sims, tuple) and len(sims) == 12 and sims.scene.name == "paper-fig15"
    p6 = sims.by_label("P6")
    assert p6 is sims[5] and p6.verdict.outcome == "unstable" and p6.agrees is True
    assert not p6.analytic.stable and p6.signals == {}          # no effect: no per-effect signal
    assert len(p6) == 200 and p6.t[1] == 0.01 and p6.units["force"] == "N"
    assert not sims.all_stable
    with pytest.raises(KeyError, match="P13"):
        sims.by_label("P13")
    assert "P6" in repr(sims) and "unstable" in repr(p6)
    with pytest.raises(zwidth.SceneError, match="duration"):
        zwidth.simulate(SCENES / "paper-fig15.toml", duration=-1.0)


# ---------------------------------------------------------------------------------------
# Review fixes: limits, texts, outputs, signals
# ---------------------------------------------------------------------------------------

BIG = """\
[scene]
name = "big"
duration = "200 s"
[plant]
m = "0.1 kg"
b = "23 N*s/m"
T = "1 us"
[controller]
K = "100 N/m"
B = "1 N*s/m"
"""


def test_too_long_runs_exit_3_without_a_traceback(tmp_path):
    # over the cap of 2**28 samples: refused by the loader, naming the key and the memory
    path = tmp_path / "huge.toml"
    path.write_text(BIG.replace('"1 us"', '"1 ns"').replace('"200 s"', '"10 s"'))
    r = run("simulate", path)
    assert r.returncode == 3 and r.stdout == "" and "Traceback" not in r.stderr
    assert "scene.duration" in r.stderr and "2**28" in r.stderr and "GiB" in r.stderr
    # under the cap (2e8 samples, 7.5 GiB of arrays) but more than the memory there is
    resource = pytest.importorskip("resource")
    path.write_text(BIG)

    def little_memory():
        resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))

    r = run("simulate", path, "--no-progress", preexec_fn=little_memory)
    assert r.returncode == 3 and r.stdout == "" and "Traceback" not in r.stderr, r.stderr
    assert "zwidth simulate: error: out of memory: case 'big': 200000000 samples" in r.stderr
    assert "shorten the duration" in r.stderr


def test_default_tolerance_of_positions_spanning_more_than_dbl_max():
    case = zwidth.load_scene(SCENES / "paper-fig15.toml").cases[0]
    x = np.where(np.arange(case.samples) % 2 == 0, 1.5e308, -1.5e308)    # span 3e308 = inf
    from zwidth.sim import judge
    v = judge(x, case, case.T, "m")
    assert v.outcome == "unstable" and v.first_nonfinite is None
    assert v.tolerance == zwidth.scene.DEFAULT_RELATIVE_TOLERANCE * np.finfo(np.float64).max


def test_outputs_are_checked_before_simulating(tmp_path, monkeypatch, capsys):
    import zwidth.cli
    import zwidth.sim

    def no_run(*args, **kwargs):
        raise AssertionError("simulated although --out/--plot cannot be written")

    monkeypatch.setattr(zwidth.sim, "simulate", no_run)
    scene = str(SCENES / "wall-hand.toml")
    for out, words in ((tmp_path / "no" / "run.npz", f"no directory {tmp_path / 'no'}"),
                       (tmp_path / "dir.npz", "it is a directory"),
                       (tmp_path / "file.txt" / "run.csv", "is not a directory")):
        (tmp_path / "file.txt").write_text("")
        (tmp_path / "dir.npz").mkdir(exist_ok=True)
        with pytest.raises(SystemExit) as info:
            zwidth.cli.main(["simulate", scene, "--out", str(out)])
        err = capsys.readouterr().err
        assert info.value.code == 2 and "argument --out: cannot write" in err and words in err, err
    # --plot: exit 4 (cannot plot), also before the run
    assert zwidth.cli.main(["simulate", scene, "--plot", str(tmp_path / "no" / "fig.png")]) == 4
    err = capsys.readouterr().err
    assert "cannot plot: cannot write" in err and "no directory" in err
    if os.geteuid() != 0:          # root may write anywhere
        locked = tmp_path / "locked"
        locked.mkdir()
        locked.chmod(0o500)
        try:
            with pytest.raises(SystemExit) as info:
                zwidth.cli.main(["simulate", scene, "--out", str(locked / "run.npz")])
            assert info.value.code == 2 and "not writable" in capsys.readouterr().err
        finally:
            locked.chmod(0o700)


def test_texts_state_the_verdict_rule():
    import zwidth.sim as zs
    n = zwidth.scene.DEFAULT_WINDOWS
    assert n == 8
    doc = " ".join(zs.__doc__.split())
    assert f"by default {n} windows" in doc and "strictly shrink window by window" in doc
    assert "A_w >= A_1" not in doc and "4 windows" not in doc
    sim_doc = " ".join(zs.simulate.__doc__.split())
    assert "million integration steps" not in sim_doc and "30 million units of :func:`work`" in sim_doc
    assert zs._CHUNK_WORK == 30_000_000
    r = run("simulate", "--help")
    assert f"default: {n} windows over the run's second half" in r.stdout
    assert "strictly shrinks" in r.stdout and ">= the first's" not in r.stdout and "4 windows" not in r.stdout


def test_velocity_filter_records_the_velocity_estimate():
    from zwidth.sim import EFFECT_SIGNALS, SIGNALS
    assert "velocity_estimate" in SIGNALS and EFFECT_SIGNALS["velocity_filter"] == ("velocity_estimate",)
    assert zwidth.scene.signal_units(False)["velocity_estimate"] == "m/s"
    assert zwidth.scene.signal_units(True)["velocity_estimate"] == "rad/s"
    text = """
[plant]
m = "0.1 kg"
b = "23 N*s/m"
T = "0.01 s"
[controller]
K = "100 N/m"
B = "2 N*s/m"
[reference]
to = "10 mm"
[quantization]
resolution = "10 um"
[velocity_filter]
cutoff = "5 Hz"
"""
    s = zwidth.simulate(text, duration=2.0)[0]
    v_est = s.signals["velocity_estimate"]
    assert s.units["velocity_estimate"] == "m/s" and len(v_est) == len(s.t) == 200
    # v_est,k = a v_est,k-1 + (1 - a) (x_meas,k - x_meas,k-1)/T, a = exp(-2 pi cutoff T)
    a = math.exp(-2 * math.pi * 5.0 * 0.01)
    dx = np.diff(s.x_measured, prepend=s.x_measured[0]) / 0.01
    expected = np.empty_like(dx)
    prev = 0.0
    for k, d in enumerate(dx):
        prev = a * prev + (1 - a) * d
        expected[k] = prev
    assert np.allclose(v_est, expected, rtol=1e-12, atol=1e-15)
    assert np.abs(v_est).max() > 1e-3                                  # it moved
    # the damping acted on it: F = K (x_eq - x_meas) - B v_est
    assert np.allclose(s.force, 100.0 * (0.01 - s.x_measured) - 2.0 * v_est, rtol=1e-12, atol=1e-12)
