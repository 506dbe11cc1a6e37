# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zwidth.plot under the Agg backend: the artists each figure holds (curves drawn from the
API's own numbers, marks, legend entries), PNG and SVG files that are valid and not blank,
the install hint without matplotlib, and ``zwidth plot`` writing its file.
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

import zwidth  # noqa: E402
import zwidth.plot as zp  # noqa: E402
from test_cli import SHORT, run  # noqa: E402

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
DRIVE = dict(J=85.78e-7, b=2.197e-3, T=0.02)


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def legend_texts(legend):
    return [t.get_text() for t in legend.get_texts()]


def longest_line(ax):
    return max(ax.get_lines(), key=lambda line: len(line.get_xdata()))


def vertical_lines_at(ax):
    """x positions of the axvlines (2-point lines with equal x)."""
    out = []
    for line in ax.get_lines():
        x = np.asarray(line.get_xdata(), dtype=float)
        if x.size == 2 and x[0] == x[1]:
            out.append(float(x[0]))
    return out


def assert_not_blank_png(path: Path):
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE and len(data) > 5000
    pixels = mpimg.imread(path)
    assert pixels.ndim == 3 and pixels.shape[0] > 100 and pixels.shape[1] > 100
    assert float(pixels[..., :3].std()) > 0.05  # a drawing, not one flat colour


# ---------------------------------------------------------------------------------------
# region
# ---------------------------------------------------------------------------------------


def test_region_above_delta0():
    """delta = 5.122 (paper Fig. 18): exact boundary = alpha_max, legacy and passivity
    outlines, alpha_mmax at the corner, the Fig. 19(a) point unstable by the line."""
    fig = zp.region(5.122, point=(-1.5, 23.0))
    (ax,) = fig.axes
    boundary = longest_line(ax)
    x, y = np.asarray(boundary.get_xdata()), np.asarray(boundary.get_ydata())
    np.testing.assert_array_equal(y, zwidth.alpha_max(5.122, x))
    assert x[0] == -5.122 and x[-1] == zwidth.extremes(5.122).beta_mmax
    assert len(ax.collections) >= 3  # the fill and the two overlay contours (+ legacy shade)
    texts = legend_texts(ax.get_legend())
    assert any(t.startswith("exact region") for t in texts)
    assert any(t.startswith("legacy region") for t in texts)
    assert any(t.startswith("passivity") for t in texts)
    assert any("corner" in t and "alpha_{mmax}" in t for t in texts)
    assert any(t.startswith("corner: line meets hyperbola") for t in texts)
    assert any(t.endswith("unstable, line") for t in texts)
    cor = zwidth.corner(5.122)
    marks = {(float(l.get_xdata()[0]), float(l.get_ydata()[0])) for l in ax.get_lines()
             if len(l.get_xdata()) == 1}
    assert (float(cor.beta), float(cor.alpha)) in marks and (-1.5, 23.0) in marks
    assert "5.122" in ax.get_title() and "delta_0" in ax.get_title()
    # the view is the exact region (and the points); the legacy region reaches beyond it
    # (delta > delta0), which the legend says instead of shrinking the exact region
    ext = zwidth.extremes(5.122)
    assert ax.get_xlim()[1] < 1.2 * float(ext.beta_mmax) and ax.get_ylim()[1] < 1.2 * float(ext.alpha_mmax)
    assert any(t.startswith("legacy region") and "beyond the view" in t for t in texts)


def legend_outside(fig, ax):
    """The legend lies right of the axes: it covers no curve or marker."""
    fig.canvas.draw()
    return ax.get_legend().get_window_extent().x0 >= ax.get_window_extent().x1


@pytest.mark.parametrize("delta", [30.0, 1e6])
def test_region_at_large_delta_shows_the_exact_region(delta):
    """At large delta the legacy region reaches beta ~ delta^2; the axes still follow the
    exact region, which fills the view instead of being a sliver in a corner."""
    fig = zp.region(delta, resolution=(120, 90))
    (ax,) = fig.axes
    ext = zwidth.extremes(delta)
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    width = float(ext.beta_mmax) + delta
    assert x0 >= -delta - 0.1 * width and x1 <= float(ext.beta_mmax) + 0.1 * width
    assert y0 == 0.0 and float(ext.alpha_mmax) < y1 < 1.2 * float(ext.alpha_mmax)
    assert any("beyond the view" in t for t in legend_texts(ax.get_legend()))
    assert legend_outside(fig, ax)


def test_region_legend_lists_only_what_can_be_seen():
    """delta = 0.0067: the legacy region is the exact one and passivity a sub-pixel
    triangle; the legend says so instead of listing them as drawn."""
    fig = zp.region(0.0067, resolution=(200, 150))
    (ax,) = fig.axes
    texts = legend_texts(ax.get_legend())
    assert not any(t.startswith("legacy region (") for t in texts)
    assert any(t.startswith("legacy region = exact") for t in texts)
    assert "passivity: too small to see here" in texts
    assert legend_outside(fig, ax)


def test_region_below_delta0_into_given_axes():
    fig, ax = plt.subplots()
    out = zp.region(2.049, point=(0.0, 1.0), ax=ax, overlays=("passivity",))
    assert out is fig
    texts = legend_texts(ax.get_legend())
    assert not any("corner:" in t for t in texts)  # no corner for delta <= delta0
    assert not any(t.startswith("legacy") for t in texts)
    assert any("hyperbola top" in t for t in texts)
    assert any(t.endswith(": stable") for t in texts)
    assert "hyperbola only" in ax.get_title()


def test_region_rejects_bad_delta():
    with pytest.raises(zwidth.ZwidthError, match="delta"):
        zp.region(-1.0)
    with pytest.raises(ValueError, match="scalar"):
        zp.region(np.array([1.0, 2.0]))


# ---------------------------------------------------------------------------------------
# extremes, influence, device
# ---------------------------------------------------------------------------------------


def test_extremes_panels_and_critical_deltas():
    fig = zp.extremes(points=300)
    assert len(fig.axes) == 6
    d = np.asarray(longest_line(fig.axes[0]).get_xdata())
    np.testing.assert_array_equal(longest_line(fig.axes[0]).get_ydata(), zwidth.extremes(d).alpha_mmax)
    np.testing.assert_array_equal(longest_line(fig.axes[3]).get_ydata(), zwidth.extremes(d).beta_mmax)
    for ax in fig.axes:
        assert ax.get_xscale() == "log"
        xs = vertical_lines_at(ax)
        for name in ("DELTA0", "DELTA1", "DELTA2", "DELTA_K1", "DELTA_K2", "DELTA_B", "DELTA_BB"):
            assert getattr(zwidth, name) in xs, name
        assert ax.get_legend() is not None
    (legend,) = fig.legends
    text = " ".join(legend_texts(legend))
    for label in (r"\delta_0", r"\delta_1", r"\delta_2", r"\delta_{K1}", r"\delta_{K2}",
                  r"\delta_B", r"\delta_{BB}"):
        assert label in text, label
    assert f"{zwidth.DELTA0:.4g}" in text
    assert len(fig.axes[3].child_axes) == 1 and len(fig.axes[4].child_axes) == 1  # the zooms


def test_extremes_narrow_range_draws_only_its_criticals():
    fig = zp.extremes(0.5, 2.0, points=100)
    text = " ".join(legend_texts(fig.legends[0]))
    assert r"\delta_{K1}" in text and r"\delta_{K2}" not in text
    with pytest.raises(ValueError, match="delta_min"):
        zp.extremes(2.0, 1.0)


def test_influence_marks_the_critical_values():
    dev = zwidth.Device.rotary(**DRIVE)
    inf = dev.influence()
    fig = zp.influence(dev)
    assert len(fig.axes) == 6
    k_vs_m = fig.axes[0]
    x = np.asarray(longest_line(k_vs_m).get_xdata())
    np.testing.assert_array_equal(longest_line(k_vs_m).get_ydata(),
                                  zwidth.Device.rotary(x, DRIVE["b"], DRIVE["T"]).extremes().K_mmax)
    assert {float(inf.m_K2), float(inf.m_K1), float(inf.m_K_match)} <= set(vertical_lines_at(k_vs_m))
    assert {float(inf.m_0), float(inf.m_B)} <= set(vertical_lines_at(fig.axes[3]))
    assert {float(inf.b_0), float(inf.b_BB)} <= set(vertical_lines_at(fig.axes[4]))
    assert {float(inf.T_B), float(inf.T_0)} <= set(vertical_lines_at(fig.axes[5]))
    for ax in fig.axes:
        assert any(t.startswith("plant:") for t in legend_texts(ax.get_legend()))
    assert "kg m²" in k_vs_m.get_xlabel() and "N m/rad" in k_vs_m.get_ylabel()
    assert any(inf.advice[:40] in " ".join(t.get_text().split()) for t in fig.texts)
    with pytest.raises(ValueError, match="scalar Device"):
        zp.influence(zwidth.Device([0.1, 0.2], 30.0, 0.01))


@pytest.mark.parametrize("K, word", [(0.39, ": stable"), (0.5, ": unstable")])
def test_device_region_in_real_units(K, word):
    dev = zwidth.Device.rotary(**DRIVE)
    lim = dev.extremes()
    fig = zp.device(dev, K, -1.36e-3)
    (ax,) = fig.axes
    b, k = np.asarray(longest_line(ax).get_xdata()), np.asarray(longest_line(ax).get_ydata())
    np.testing.assert_array_equal(k, dev.k_max(b))
    texts = legend_texts(ax.get_legend())
    assert any(t.startswith(f"K_mmax = {float(lim.K_mmax):.4g}") for t in texts)
    assert any(t.startswith("legacy region") for t in texts)  # delta = 5.122 > delta0
    assert any(word in t for t in texts)
    assert any(t.get_text().startswith("Advice:") for t in fig.texts)
    assert legend_outside(fig, ax)  # the K_mmax star is never under it


def test_device_at_large_delta_follows_the_exact_region():
    """m = 0.01 kg, b = 30 N s/m, T = 0.01 s (delta = 30): the view is the exact region."""
    dev = zwidth.Device(0.01, 30.0, 0.01)
    lim = dev.extremes()
    fig = zp.device(dev, resolution=(120, 90))
    (ax,) = fig.axes
    width = float(lim.B_mmax) - float(lim.B_mmin)
    assert ax.get_xlim()[1] <= float(lim.B_mmax) + 0.1 * width
    assert ax.get_ylim()[1] < 1.2 * float(lim.K_mmax)
    assert any("beyond the view" in t for t in legend_texts(ax.get_legend()))


# ---------------------------------------------------------------------------------------
# Files and the missing-matplotlib path
# ---------------------------------------------------------------------------------------


def test_save_png_and_svg(tmp_path):
    fig = zp.region(5.122, resolution=(200, 150))
    png = zp.save(fig, tmp_path / "region.png", dpi=60)
    assert png == tmp_path / "region.png"
    assert_not_blank_png(png)
    svg = zp.save(fig, tmp_path / "region.SVG")
    text = svg.read_text()
    assert text.lstrip().startswith("<?xml") and "<svg" in text and "</svg>" in text
    pdf = zp.save(fig, tmp_path / "region.pdf")
    assert pdf.read_bytes()[:5] == b"%PDF-"
    assert zp.save(fig, tmp_path / "region.eps").read_bytes()[:4] == b"%!PS"
    with pytest.raises(ValueError, match=r"\.pdf, \.svg"):
        zp.save(fig, tmp_path / "region.txt")


def test_missing_matplotlib_gives_install_hint(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match=r"pip install zwidth\[plot\]"):
        zp.region(3.0)


def test_cli_plot_writes_files(tmp_path):
    r = run("plot", "region", "--delta", "5.122", "--delay", "0", "--alpha", "23", "--beta", "-1.5", "--json",
            cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    obj = json.loads(r.stdout)
    assert obj == {"command": "plot", "loop": zwidth.Loop().as_dict(), "kind": "region",
                   "file": "zwidth-region.png", "format": "png",
                   "bytes": (tmp_path / "zwidth-region.png").stat().st_size}
    assert list(obj)[:2] == ["command", "loop"]
    assert_not_blank_png(tmp_path / "zwidth-region.png")
    out = tmp_path / "device.svg"
    r = run("plot", "device", *SHORT, "--K", "0.39", "--B", "-1.36e-3", "-o", out)
    assert r.returncode == 0, r.stderr
    assert str(out) in r.stdout and "<svg" in out.read_text()
    out = tmp_path / "device.pdf"
    r = run("plot", "device", *SHORT, "-o", out)
    assert r.returncode == 0, r.stderr
    assert out.read_bytes()[:5] == b"%PDF-"


def test_cli_plot_exit_4(tmp_path):
    r = run("plot", "region", "--delta", "3", "--delay", "0", "-o", tmp_path / "missing-dir" / "x.png")
    assert r.returncode == 4 and "cannot write" in r.stderr and r.stdout == ""
    shim = tmp_path / "shim" / "matplotlib"
    shim.mkdir(parents=True)
    (shim / "__init__.py").write_text("raise ImportError('no matplotlib in this test')\n")
    env = {"PYTHONPATH": str(shim.parent), "PATH": "/usr/bin:/bin"}
    r = run("plot", "extremes", "-o", tmp_path / "e.png", env=env)
    assert r.returncode == 4 and "pip install zwidth[plot]" in r.stderr
    assert not (tmp_path / "e.png").exists()


# ---------------------------------------------------------------------------------------
# Simulations
# ---------------------------------------------------------------------------------------

DELAY_SCENE = """
[scene]
name = "delay-quantized"
duration = "1 s"
[plant]
m = "0.12 kg"
b = "0.8 N*s/m"
T = "1 ms"
[controller]
K = "50000 N/m"
B = "50 N*s/m"
[reference]
from = "0 m"
to = "0.01 m"
at = "0.1 s"
[delay]
samples = 1
[quantization]
resolution = "1 um"
"""


def test_unstable_response_with_effects_is_clipped(tmp_path):
    """A delay with quantization (not a linear scene) blows up to ~1e150 m: the position
    panel keeps the band around the step, and the force panel the forces of the samples
    shown there, on the same time axis."""
    scene = tmp_path / "delay.toml"
    scene.write_text(DELAY_SCENE)
    sims = zwidth.simulate(scene)
    assert sims[0].verdict.outcome == "unstable" and not sims.scene.linear
    assert np.nanmax(np.abs(sims[0].x)) > 1e6
    fig = zp.simulation(sims)
    position, force = fig.axes
    assert max(abs(v) for v in position.get_ylim()) < 0.1  # metres around the 10 mm step
    assert position.get_xlim() == force.get_xlim()
    assert max(abs(v) for v in force.get_ylim()) < 1e5


def test_knob_rendered_stiffness_is_dots_not_a_fan():
    fig = zp.simulation(zwidth.simulate(Path(__file__).resolve().parents[2] / "scenes" / "knob-legacy.toml"))
    rendered = [l for l in fig.axes[0].get_lines() if l.get_label().startswith("rendered")]
    assert len(rendered) == 1 and rendered[0].get_linestyle() == "None"
    assert rendered[0].get_marker() == "."


@pytest.mark.parametrize("draw", [lambda: zp.region(1e300, resolution=(60, 40)),
                                  lambda: zp.device(zwidth.Device(1e-300, 0.8, 1e-3), resolution=(60, 40))])
def test_extreme_deltas_draw_where_the_legacy_top_overflows(draw):
    """delta ~ 1e300: the legacy region's top is out of range (NaN); the figure is still
    drawn, the legend saying the legacy region reaches far beyond the view."""
    fig = draw()
    assert any("far beyond the view" in t for t in legend_texts(fig.axes[0].get_legend()))


# ---------------------------------------------------------------------------------------
# Figures for the loop the user runs (issue 24): real units, the ideal loop beside
# ---------------------------------------------------------------------------------------

TRIAL_LOOP = ("--m", "0.12", "--b", "0.8", "--T", "1e-3", "--delay", "1", "--velocity-filter", "lowpass:100Hz")


@pytest.mark.parametrize("kind", ["device", "region", "influence"])
def test_cli_plots_a_delayed_filtered_loop(kind, tmp_path):
    out = tmp_path / f"{kind}.png"
    r = run("plot", kind, *TRIAL_LOOP, "--K", "5000", "--B", "20", "-o", out, "--json")
    assert r.returncode == 0, r.stderr
    obj = json.loads(r.stdout)
    assert obj["loop"]["delay"] == 1 and obj["loop"]["cutoff"] == 100.0 and obj["file"] == str(out)
    assert_not_blank_png(out)


def test_device_region_in_real_units_beside_the_ideal_loop():
    dev = zwidth.Device(0.12, 0.8, 1e-3, delay=1, velocity_filter=("lowpass", 100.0))
    fig = zp.device_region(dev, 5000.0, 20.0)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "B [N s/m]" and ax.get_ylabel() == "K [N/m]"
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    ideal, this = float(dev.ideal().extremes().K_mmax), float(dev.extremes().K_mmax)
    assert labels[0] == f"the paper's ideal loop (K_mmax {ideal:.4g})"
    assert labels[1].startswith("this loop: 1 sample delay") and f"(K_mmax {this:.4g})" in labels[1]
    assert labels[3].endswith("stable") and this < ideal / 5   # the trial's loop keeps about 11 %
    # the view holds the ideal region: K up to its K_mmax, B over its B range
    assert ax.get_ylim()[1] >= ideal and ax.get_xlim()[1] >= float(dev.ideal().extremes().B_mmax)
    # the legend sits right of the axes, not on the curves
    fig.canvas.draw()
    legend_box = ax.get_legend().get_window_extent()
    assert legend_box.x0 >= ax.get_window_extent().x1
    plt.close(fig)


def test_plot_extremes_marks_the_plants_delta(tmp_path):
    fig = zp.extremes(mark=0.00666667)
    for ax in fig.axes[:6]:
        assert any(t.get_text() == r"your plant: $\delta$ = 0.006667" for t in ax.get_legend().get_texts())
    plt.close(fig)
    far = zp.extremes(1e-3, 20.0, mark=100.0)   # the range widens to hold it
    assert far.axes[0].get_xlim()[1] >= 150.0
    plt.close(far)
    r = run("plot", "extremes", "--m", "0.12", "--b", "0.8", "--T", "1e-3", "--delay", "0",
            "-o", tmp_path / "e.png")
    assert r.returncode == 0, r.stderr
    # the figure is the paper's loop's: a delayed loop cannot be drawn there (4: cannot plot)
    r = run("plot", "extremes", *TRIAL_LOOP, "-o", tmp_path / "no.png")
    assert r.returncode == 4 and "plot region" in r.stderr and not (tmp_path / "no.png").exists()
