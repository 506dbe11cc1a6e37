# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""One version everywhere: csrc/include/zwidth/version.h defines it, and every place that
shows it must agree: the Python package's metadata, zwidth.__version__, the compiled core,
the ``zwidth`` command, the pkg-config and CMake package files of the C build
($ZW_LIB_DIR, default build/), the host programs' --version, and CHANGELOG.md's newest
release.  A number typed anywhere else fails here at the next release."""
from __future__ import annotations

import importlib.metadata
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import zwidth
from zwidth import _core

REPO = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("ZW_LIB_DIR", REPO / "build"))


def _header_version() -> str:
    text = (REPO / "csrc/include/zwidth/version.h").read_text()
    parts = [re.search(rf"^#define ZW_VERSION_{p} (\d+)$", text, re.M) for p in ("MAJOR", "MINOR", "PATCH")]
    assert all(parts), "version.h lost one of ZW_VERSION_MAJOR/MINOR/PATCH"
    return ".".join(m.group(1) for m in parts if m)


VERSION = _header_version()


def test_version_is_semantic():
    assert re.fullmatch(r"(0|[1-9]\d*)\.(0|[1-9]\d*)\.(0|[1-9]\d*)", VERSION)


def test_python_package_metadata_and_module():
    assert importlib.metadata.version("zwidth") == VERSION
    assert zwidth.__version__ == VERSION
    assert _core.VERSION == VERSION  # ZW_VERSION_STRING as compiled into the extension


def test_pyproject_defines_no_version_of_its_own():
    text = (REPO / "pyproject.toml").read_text()
    project = text.split("[project]", 1)[1].split("\n[", 1)[0]
    assert not re.search(r"^version\s*=", project, re.M)
    assert re.search(r'^dynamic = \["version"\]', project, re.M)


def test_cli_version():
    out = subprocess.run([sys.executable, "-m", "zwidth", "--version"], capture_output=True, text=True,
                         timeout=60, check=True).stdout
    assert out.strip() == f"zwidth {VERSION}"


@pytest.mark.parametrize("pc", ["zwidth.pc", "zwidth_f.pc"])
def test_pkg_config_file(pc):
    path = BUILD / pc
    assert path.exists(), f"{path} missing: configure the C build first (cmake -S . -B build)"
    assert re.search(rf"^Version: {re.escape(VERSION)}$", path.read_text(), re.M)


def test_cmake_package_version_file():
    path = BUILD / "zwidthConfigVersion.cmake"
    assert path.exists(), f"{path} missing: configure the C build first (cmake -S . -B build)"
    assert f'set(PACKAGE_VERSION "{VERSION}")' in path.read_text()


@pytest.mark.parametrize("program", ["zwidth-limits", "zwidth-drive", "zwidth-tune"])
def test_host_program_version(program):
    exe = BUILD / program
    if program != "zwidth-limits" and not exe.exists():
        pytest.skip(f"{program} not built (needs libmodbus)")
    assert exe.exists(), f"{exe} missing: build the C tree first"
    out = subprocess.run([str(exe), "--version"], capture_output=True, text=True, timeout=60, check=True).stdout
    assert out == f"{program} {VERSION}\n"


def test_changelog_newest_release_is_this_version():
    releases = re.findall(r"^## \[(\d+\.\d+\.\d+)\] - \d{4}-\d{2}-\d{2}$", (REPO / "CHANGELOG.md").read_text(), re.M)
    assert releases, "CHANGELOG.md has no release heading '## [X.Y.Z] - YYYY-MM-DD'"
    assert releases[0] == VERSION
