# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Fixtures for the zwidth.modbus tests.

Run from the repository root, with the package installed (tools/test.sh runs pip install .):

    .venv/bin/python -m pytest tests/modbus_py -q

The live tests start ``zwidth-drive`` from $ZW_BUILD_DIR (default <repo>/build) on a free
127.0.0.1 port (never another address), wait for it with a deadline, and kill it in a
``finally``; they are skipped when the binary is not built (libmodbus missing).
"""
from __future__ import annotations

import subprocess
import time

import pytest

from mb_support import DRIVE_BIN, LOOPBACK, PAPER_PLANT, POLICY, START_TIMEOUT, \
    drive_options, free_port, listening, stop, write_key


@pytest.fixture
def start_drive(tmp_path):
    """start_drive(block=dict(...) | None) -> port: start zwidth-drive on a free loopback
    port with that certified block (default: the paper's plant with POLICY; None starts it
    unsealed), consenting to commissioning with mb_support.TEST_KEY unless
    commissioning=False; every drive started is stopped at the end of the test."""
    pytest.importorskip("pymodbus", reason="pymodbus not installed (tools/requirements-test.txt)")
    if not DRIVE_BIN.is_file():
        pytest.skip(f"{DRIVE_BIN} not built (needs libmodbus; set ZW_BUILD_DIR)")
    procs = []

    key_file = write_key(tmp_path / "drive.key")

    def start(block: dict | None = "default", extra=(), commissioning: bool = True) -> int:
        if block == "default":
            block = {**PAPER_PLANT, **POLICY}
        if commissioning:
            extra = ("--commissioning", "--key-file", str(key_file), *extra)
        last_log = ""
        for attempt in range(3):  # a free port can be taken between probe and bind
            port = free_port()
            log = tmp_path / f"drive-{port}.log"
            cmd = [str(DRIVE_BIN), "--host", LOOPBACK, "--port", str(port),
                   *drive_options(block), *extra]
            with open(log, "wb") as fh:
                proc = subprocess.Popen(cmd, stdout=fh, stderr=subprocess.STDOUT,
                                        stdin=subprocess.DEVNULL)
            procs.append(proc)
            deadline = time.monotonic() + START_TIMEOUT
            while time.monotonic() < deadline:
                if proc.poll() is not None:
                    break
                if listening(port):
                    return port
                time.sleep(0.02)
            stop(proc)
            last_log = log.read_text(errors="replace")
            if proc.returncode == 2:  # bad arguments: retrying will not help
                break
        pytest.fail(f"zwidth-drive did not start ({' '.join(cmd)}):\n{last_log}")

    start.procs = procs
    try:
        yield start
    finally:
        for proc in procs:
            stop(proc)


@pytest.fixture
def drive_port(start_drive) -> int:
    """A running drive with the paper's plant and POLICY; its port."""
    return start_drive()
