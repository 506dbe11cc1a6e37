# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zwidth-drive: --host validation (libmodbus listens on INADDR_ANY for any address text
starting with '0') and RTU frame spacing (t3.5 after a frame for another slave)."""
from __future__ import annotations

import os
import struct
import subprocess
import time

import pytest

from zwmb_harness import DRIVE, start_drive  # noqa: F401 (fixtures)
from test_rtu import SOCAT, RawRTU, pty_pair, rtu_frame  # noqa: F401 (fixtures)


@pytest.mark.parametrize("host", ["0.1.2.3", "0.0.0.1", "0.255.255.255", "localhost", "127.1",
                                  "00.0.0.0", "::1"])
def test_drive_refuses_hosts_libmodbus_would_widen(host):
    p = subprocess.run([str(DRIVE), "--host", host, "--port", "0"], capture_output=True,
                       text=True, timeout=10, stdin=subprocess.DEVNULL)
    assert p.returncode == 2, (host, p.stderr)
    assert "--host" in p.stderr


def test_drive_logs_the_bound_address(start_drive):
    d = start_drive("-v")  # the harness waits for "serving Modbus TCP on 127.0.0.1:PORT"
    assert d.port > 0


READ_MAGIC = struct.pack(">BHH", 3, 0, 2)
MAGIC_ANSWER = b"\x03\x04\x5a\x57\x00\x04"  # magic, map version 4


@pytest.mark.skipif(SOCAT is None, reason="socat not installed")
@pytest.mark.parametrize("baud", ["19200", "115200"])
def test_rtu_request_after_another_slave_within_10ms_is_served(pty_pair, start_drive, baud):
    drive_tty, client_tty = pty_pair
    d = start_drive("--rtu", drive_tty, "--baud", baud, "--slave", "1", "-v", rtu=True)
    raw = RawRTU(client_tty)
    try:
        served = 0
        for _ in range(5):
            # another slave's request, then ours 6 ms later: well over t3.5 (2.0 ms at
            # 19200 baud, 1.75 ms above), so the drive must not take it for the tail of
            # the other frame (it used to drain for 10 ms)
            os.write(raw.fd, rtu_frame(2, READ_MAGIC))
            time.sleep(0.006)
            if raw.request(1, READ_MAGIC, timeout=1.0) == MAGIC_ANSWER:
                served += 1
        assert served >= 4, (served, d.log())  # one miss allowed for scheduling on a busy host
        # a request glued to the other slave's frame (no gap at all) breaks the framing: it
        # is dropped, and -v says so
        os.write(raw.fd, rtu_frame(2, READ_MAGIC) + rtu_frame(1, READ_MAGIC))
        raw.read_frame(timeout=0.3)
        assert raw.request(1, READ_MAGIC) == MAGIC_ANSWER
    finally:
        raw.close()
    assert d.alive()
    assert "dropped 8 bytes" in d.log() and "(first byte 0x01)" in d.log(), d.log()
