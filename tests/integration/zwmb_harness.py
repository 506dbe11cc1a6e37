# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Harness of the Modbus integration tests: start zwidth-drive, run zwidth-tune, talk raw
Modbus TCP.  The test modules import the fixtures from here (there is no conftest.py, so
that this suite and tests/py, whose modules import their own conftest, can run in one
pytest session).

The binaries are looked up in $ZW_BUILD_DIR (default <repo>/build), at its top or under
csrc/host/.  Every server listens on 127.0.0.1 only, on a port the kernel picks
(--port 0; the drive prints it), and is stopped (SIGTERM, then SIGKILL) in a finally.
Every wait has a timeout.
"""
from __future__ import annotations

import os
import re
import signal
import socket
import struct
import subprocess
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("ZW_BUILD_DIR", REPO / "build"))
HEADER = REPO / "csrc" / "include" / "zwidth" / "regmap.h"
# regmap.h is the entry point; its parts hold the reasons and commands (map version 3)
HEADERS = [HEADER] + [HEADER.with_name(f"regmap_{p}.h") for p in ("codec", "policy", "commission", "persist")]
# The test drives' commissioning key (nothing secret): 64 hex digits in a mode-600 file.
TEST_KEY_HEX = bytes(range(0x40, 0x60)).hex()
LOOPBACK = "127.0.0.1"


def _binary(name):
    for p in (BUILD / name, BUILD / "csrc" / "host" / name):
        if p.is_file() and os.access(p, os.X_OK):
            return p
    return None


DRIVE = _binary("zwidth-drive")
TUNE = _binary("zwidth-tune")

if DRIVE is None or TUNE is None:
    pytest.skip(f"zwidth-drive / zwidth-tune not built in {BUILD} (needs libmodbus-dev; "
                "set ZW_BUILD_DIR)", allow_module_level=True)


def _enums():
    """Enumerators (NAME = value) and numeric macros (#define NAME value[u]) of regmap.h."""
    text = "".join(h.read_text() for h in HEADERS)
    num = r"(0x[0-9A-Fa-f]+|\d+)[uU]?\b"
    out = {k: int(v, 0) for k, v in re.findall(r"\b(ZW_[A-Z0-9_]+)\s*=\s*" + num, text)}
    out.update({k: int(v, 0) for k, v in re.findall(r"^#define\s+(ZW_[A-Z0-9_]+)\s+" + num, text, re.M)})
    return out


E = _enums()  # register addresses, reasons, exceptions, commands, from regmap.h
REASON_NAME = {v: k for k, v in E.items() if k.startswith("ZW_REASON_")}


def f32(x):
    """x rounded to binary32, as a Python float."""
    return struct.unpack(">f", struct.pack(">f", x))[0]


def float_words(*values):
    out = []
    for v in values:
        hi, lo = struct.unpack(">HH", struct.pack(">f", v))
        out += [hi, lo]
    return out


def words_float(words):
    return [struct.unpack(">f", struct.pack(">HH", words[i], words[i + 1]))[0]
            for i in range(0, len(words), 2)]


# ---------------------------------------------------------------------------------------
# The drive process
# ---------------------------------------------------------------------------------------


class Drive:
    """One zwidth-drive process; its stderr goes to a file (read with .log())."""

    def __init__(self, tmp_path: Path, args, rtu=False, commissioning=True):
        self.log_path = tmp_path / f"drive-{time.monotonic_ns()}.log"
        self.key_file = write_key(tmp_path / "drive.key")
        if commissioning:  # the enable input on, and the key a client must hold
            args = ["--commissioning", "--key-file", str(self.key_file), *args]
        self._log = open(self.log_path, "wb")
        cmd = [str(DRIVE)] + list(args)
        if not rtu:
            cmd += ["--host", LOOPBACK, "--port", "0"]
        self.proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                     stderr=self._log)
        self.port = None
        if rtu:
            self._wait_for(r"serving Modbus RTU on")
        else:
            m = self._wait_for(r"serving Modbus TCP on 127\.0\.0\.1:(\d+)")
            self.port = int(m.group(1))

    def _wait_for(self, pattern, timeout=5.0):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            m = re.search(pattern, self.log())
            if m:
                return m
            if self.proc.poll() is not None:
                raise AssertionError(f"zwidth-drive exited with {self.proc.returncode}: {self.log()}")
            time.sleep(0.01)
        raise AssertionError(f"zwidth-drive did not print {pattern!r} within {timeout} s: {self.log()}")

    def log(self):
        return self.log_path.read_text(errors="replace")

    def alive(self):
        return self.proc.poll() is None

    def stop(self, sig=signal.SIGTERM, timeout=5.0):
        """Stop with sig; returns the exit status (SIGKILL after timeout)."""
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
            try:
                self.proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(timeout=timeout)
        self._log.close()
        return self.proc.returncode

    # -- clients ---------------------------------------------------------------------------

    def tune(self, *args, timeout=10.0):
        """zwidth-tune against this drive; commission gets the drive's key file, and up to
        120 s: a ranged block's box search takes 2 s in Release and 10x that under ASan."""
        if "commission" in args:
            timeout = max(timeout, 120.0)
            if "--key-file" not in args:
                args = (*args, "--key-file", str(self.key_file))
        return run_tune("--port", str(self.port), *args, timeout=timeout)

    def client(self, timeout=3.0):
        return MBClient(self.port, timeout)


def write_key(path: Path, hex_digits: str = TEST_KEY_HEX, mode: int = 0o600) -> Path:
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, mode)
    try:
        os.write(fd, hex_digits.encode() + b"\n")
    finally:
        os.close(fd)
    os.chmod(path, mode)
    return path


def run_tune(*args, timeout=10.0):
    return subprocess.run([str(TUNE), "--host", LOOPBACK, *args], capture_output=True, text=True,
                          timeout=timeout, stdin=subprocess.DEVNULL)


@pytest.fixture
def start_drive(tmp_path):
    """start_drive(*args) -> Drive; every drive started is stopped at the end, and must
    have exited 0 on SIGTERM."""
    drives = []

    def start(*args, rtu=False, commissioning=True):
        d = Drive(tmp_path, args, rtu=rtu, commissioning=commissioning)
        drives.append(d)
        return d

    try:
        yield start
    finally:
        codes = [(d, d.stop()) for d in drives]
        for d, rc in codes:
            assert rc == 0, f"zwidth-drive exit status {rc} on SIGTERM; log:\n{d.log()}"


@pytest.fixture
def drive(start_drive):
    """The paper's drive, sealed with the default block."""
    return start_drive()


# ---------------------------------------------------------------------------------------
# A raw Modbus TCP client (no library: every byte on the wire is the test's)
# ---------------------------------------------------------------------------------------


class ModbusException(Exception):
    def __init__(self, function, code):
        super().__init__(f"exception 0x{code:02X} to function 0x{function:02X}")
        self.function, self.code = function, code


class MBClient:
    def __init__(self, port, timeout=3.0):
        self.sock = socket.create_connection((LOOPBACK, port), timeout=timeout)
        self.sock.settimeout(timeout)
        self.tid = 0

    def close(self):
        self.sock.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def recv_exact(self, n):
        buf = b""
        while len(buf) < n:
            chunk = self.sock.recv(n - len(buf))
            if not chunk:
                raise ConnectionError(f"connection closed after {len(buf)} of {n} bytes")
            buf += chunk
        return buf

    def send_pdu(self, pdu: bytes, unit=1):
        self.tid = (self.tid + 1) & 0xFFFF
        self.sock.sendall(struct.pack(">HHHB", self.tid, 0, len(pdu) + 1, unit) + pdu)
        return self.tid

    def recv_pdu(self, tid=None, unit=1):
        head = self.recv_exact(7)
        rtid, proto, length, runit = struct.unpack(">HHHB", head)
        assert proto == 0 and runit == unit and 2 <= length <= 254, head
        if tid is not None:
            assert rtid == tid, (rtid, tid)
        return self.recv_exact(length - 1)

    def raw(self, pdu: bytes, unit=1) -> bytes:
        """Send one PDU, return the response PDU (normal or exception) as bytes."""
        return self.recv_pdu(self.send_pdu(pdu, unit), unit)

    def call(self, pdu: bytes) -> bytes:
        rsp = self.raw(pdu)
        if rsp[0] & 0x80:
            assert rsp[0] == (pdu[0] | 0x80) and len(rsp) == 2, rsp
            raise ModbusException(pdu[0], rsp[1])
        assert rsp[0] == pdu[0], rsp
        return rsp

    def read(self, addr, count):
        rsp = self.call(struct.pack(">BHH", 3, addr, count))
        assert rsp[1] == 2 * count and len(rsp) == 2 + 2 * count, rsp
        return list(struct.unpack(f">{count}H", rsp[2:]))

    def write(self, addr, words):
        rsp = self.call(struct.pack(f">BHHB{len(words)}H", 0x10, addr, len(words), 2 * len(words), *words))
        assert rsp == struct.pack(">BHH", 0x10, addr, len(words)), rsp

    def write1(self, addr, value):
        rsp = self.call(struct.pack(">BHH", 6, addr, value))
        assert rsp == struct.pack(">BHH", 6, addr, value), rsp

    def gains(self):
        return tuple(words_float(self.read(E["ZW_REG_K"], 4)))

    def set_gains(self, K, B):
        self.write(E["ZW_REG_K"], float_words(K, B))

    def refusal(self):
        """(reason name, exception) of the last refusal."""
        r, x = self.read(E["ZW_REG_LAST_REASON"], 2)
        return REASON_NAME.get(r, r), x

    def counters(self):
        w = self.read(E["ZW_REG_ACCEPTED"], 4)
        return (w[0] << 16 | w[1]), (w[2] << 16 | w[3])
