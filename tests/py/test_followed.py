# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""Small things the new-user trial (issue 24) found wrong when followed: zwidth.plot after
``import zwidth`` alone, and the benchmark report's run from an interpreter without zwidth."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_plot_and_modbus_after_import_zwidth_alone():
    pytest.importorskip("matplotlib")
    code = ("import sys, zwidth\n"
            "assert 'zwidth.plot' not in sys.modules and 'matplotlib' not in sys.modules\n"
            "fig = zwidth.plot.region(5.122, point=(-1.5, 23))\n"
            "print(type(fig).__name__)\n"
            "try:\n    zwidth.no_such_name\nexcept AttributeError as exc:\n    print(exc)\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                       env={"MPLBACKEND": "Agg", **__import__("os").environ})
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines() == ["Figure", "module 'zwidth' has no attribute 'no_such_name'"]


def test_report_without_its_packages_is_a_usage_error():
    # -S: no site-packages, so neither numpy nor zwidth is importable
    r = subprocess.run([sys.executable, "-S", str(ROOT / "bench/report/generate.py"), "--quick"],
                       capture_output=True, text=True, timeout=60, env={"PATH": "/usr/bin:/bin"})
    assert r.returncode == 2 and r.stdout == "", (r.returncode, r.stdout, r.stderr)
    assert "Traceback" not in r.stderr and "is not importable" in r.stderr and ".venv/bin/python" in r.stderr
