# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Shared constants and helpers of tests/modbus_py (a module with a unique name, so that
it never collides with another directory's conftest)."""
from __future__ import annotations

import os
import socket
import subprocess
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
HEADER = REPO / "csrc" / "include" / "zwidth" / "regmap.h"
# regmap.h is the entry point; its parts (map version 3) hold the reasons and commands
HEADERS = [HEADER] + [HEADER.with_name(f"regmap_{part}.h") for part in ("codec", "policy", "commission", "persist")]
BUILD_DIR = Path(os.environ.get("ZW_BUILD_DIR", REPO / "build"))
DRIVE_BIN = BUILD_DIR / "zwidth-drive"
LOOPBACK = "127.0.0.1"

START_TIMEOUT = 10.0  # s, for the drive to listen
STOP_TIMEOUT = 5.0    # s, after SIGTERM before SIGKILL

# The paper's drive, load motor short-circuited: J [kg m^2], b [N m s/rad], T [s].
PAPER_PLANT = dict(m=85.78e-7, b=2.197e-3, T=0.02)
# A policy that the paper's example passes: K = 0.40 N m/rad at B = -1.36e-3 N m s/rad is
# below sigma K_max(B) = 0.85 x 0.49275, K = 0.45 is not.
POLICY = dict(sigma=0.85, r=0.999, k_min=0.0, k_max=10.0, b_min=-0.01, b_max=0.01,
              dk_max=1.0, db_max=0.01)


# The drives these tests start hold this commissioning key (a test key, nothing secret).
TEST_KEY = bytes(range(0x40, 0x60))


def write_key(path: Path, key: bytes = TEST_KEY, mode: int = 0o600) -> Path:
    """A key file as zwidth-drive and load_key want it: 64 hex digits, mode 600."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, mode)
    try:
        os.write(fd, key.hex().encode() + b"\n")
    finally:
        os.close(fd)
    os.chmod(path, mode)
    return path


def free_port() -> int:
    """A TCP port that nothing listens on at the moment (127.0.0.1)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((LOOPBACK, 0))
        return s.getsockname()[1]


def listening(port: int) -> bool:
    try:
        with socket.create_connection((LOOPBACK, port), timeout=0.2):
            return True
    except OSError:
        return False


def stop(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=STOP_TIMEOUT)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(timeout=STOP_TIMEOUT)


def drive_options(block: dict | None) -> list:
    """zwidth-drive options for a certified block (None: --unsealed)."""
    if block is None:
        return ["--unsealed"]
    out = []
    for key, value in block.items():
        out += ["--" + key.replace("_", "-"), repr(float(value))]
    return out
