# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zwidth-tune commission against a second client, and lost connections in the middle of
commissioning: a Modbus TCP proxy between zwidth-tune and the drive acts at a chosen
request (deterministic, no timing)."""
from __future__ import annotations

import json
import socket
import struct
import threading

from zwmb_harness import E, LOOPBACK, f32, float_words, drive, start_drive  # noqa: F401 (fixtures)
from test_commission import PAPER_OPTS, block_words, crc16_words, status

CMD = E["ZW_REG_COMMAND"]


def _recv_exact(sock, n):
    buf = b""
    while len(buf) < n:
        chunk = sock.recv(n - len(buf))
        if not chunk:
            return None
        buf += chunk
    return buf


def _recv_adu(sock):
    head = _recv_exact(sock, 7)
    if head is None:
        return None
    body = _recv_exact(sock, struct.unpack(">H", head[4:6])[0] - 1)
    return None if body is None else head + body


class Proxy:
    """Forwards Modbus TCP frames from zwidth-tune to the drive, one connection at a time.
    hook(pdu, conn_index) runs before a request is forwarded; it returns "forward" or
    "drop" (close the client's connection without forwarding)."""

    def __init__(self, drive_port, hook):
        self.drive_port, self.hook = drive_port, hook
        self.lsock = socket.socket()
        self.lsock.bind((LOOPBACK, 0))
        self.lsock.listen(4)
        self.lsock.settimeout(10)
        self.port = self.lsock.getsockname()[1]
        self.requests = []  # (connection index, request PDU)
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        index = 0
        try:
            while True:
                client, _ = self.lsock.accept()
                with client, socket.create_connection((LOOPBACK, self.drive_port), timeout=5) as up:
                    client.settimeout(10)
                    while True:
                        adu = _recv_adu(client)
                        if adu is None:
                            break
                        self.requests.append((index, adu[7:]))
                        if self.hook(adu[7:], index) == "drop":
                            break
                        up.sendall(adu)
                        rsp = _recv_adu(up)
                        if rsp is None:
                            break
                        client.sendall(rsp)
                index += 1
        except OSError:
            return

    def close(self):
        self.lsock.close()
        self.thread.join(timeout=5)


def _is_command(pdu, value):
    return pdu == struct.pack(">BHH", 6, CMD, value)


def commission_through_proxy(d, hook, *extra):
    """Run `zwidth-tune commission` (the paper's block, sigma 0.9) through a Proxy that
    applies hook to every request; returns (completed process, proxy)."""
    proxy = Proxy(d.port, hook)
    try:
        p = d.tune("commission", *PAPER_OPTS, "--sigma", "0.9", *extra, "--port", str(proxy.port))
    finally:
        proxy.close()
    return p, proxy


def test_block_written_by_another_client_fails_the_mac(start_drive):
    """Review A4/A6: right before our SEAL a second client (no key) replaces the staged block
    with a valid one: our MAC no longer matches, SEAL is refused with ZW_REASON_AUTH, tune
    aborts and says what the drive is doing (read back), and their block is never sealed."""
    d = start_drive("--unsealed")
    theirs = block_words(0.5)

    def hook(pdu, _index):
        if _is_command(pdu, E["ZW_CMD_SEAL"]):
            with d.client() as c:
                c.write(E["ZW_REG_CERT_M"], theirs + [crc16_words(theirs)])
        return "forward"

    p, proxy = commission_through_proxy(d, hook)
    assert p.returncode == 3, (p.stdout, p.stderr)
    assert p.stdout.startswith("refused at seal: ZW_REASON_AUTH"), p.stdout
    assert "we sent ABORT; the drive is now in operation with no sealed block" in p.stdout
    assert "commissioned" not in p.stdout
    s = status(d)
    assert s["sealed"] is False and s["mode"] == "operation"

    p, proxy = commission_through_proxy(d, hook, "--json")
    assert p.returncode == 3, (p.stdout, p.stderr)
    v = json.loads(p.stdout)
    assert (v["verdict"], v["reason"], v["aborted"]) == ("refused", "ZW_REASON_AUTH", True)
    assert v["drive"] == "in operation with no sealed block (gains refused)"


def test_commission_reads_back_mode_block_and_crc(start_drive):
    d = start_drive("--unsealed")
    proxy = Proxy(d.port, lambda pdu, index: "forward")
    try:
        p = d.tune("commission", *PAPER_OPTS, "--sigma", "0.9", "--port", str(proxy.port))
    finally:
        proxy.close()
    assert p.returncode == 0, (p.stdout, p.stderr)
    assert "is in operation (mode, block and CRC read back)" in p.stdout
    pdus = [pdu for _, pdu in proxy.requests]
    seal = pdus.index(struct.pack(">BHH", 6, CMD, E["ZW_CMD_SEAL"]))
    assert struct.pack(">BHH", 3, E["ZW_REG_MAGIC"], 4) in pdus[seal + 1:]  # mode and sealed
    assert struct.pack(">BHH", 3, E["ZW_REG_CERT_M"], 35) in pdus[seal + 1:]
    # the MAC went to the drive before SEAL, over the nonce read after UNLOCK2
    unlock2 = pdus.index(struct.pack(">BHH", 6, CMD, E["ZW_CMD_UNLOCK2"]))
    nonce = pdus.index(struct.pack(">BHH", 3, E["ZW_REG_NONCE"], 8))
    mac = [i for i, q in enumerate(pdus) if q[:5] == struct.pack(">BHH", 0x10, E["ZW_REG_MAC"], 16)]
    assert unlock2 < nonce < mac[0] < seal


def test_commission_reports_an_unlock_right_after_our_seal(start_drive):
    """Review A6, strategy 2: on our SEAL a second client unlocks at once.  The SEAL was
    ours (the MAC proves it), but the drive is in commissioning again: tune must not say
    "in operation", and exits 3."""
    d = start_drive()
    sealed = []

    def hook(pdu, _index):
        if sealed and pdu == struct.pack(">BHH", 3, E["ZW_REG_MAGIC"], 4):
            with d.client() as c:
                c.write1(CMD, E["ZW_CMD_UNLOCK1"])
                c.write1(CMD, E["ZW_CMD_UNLOCK2"])
            sealed.clear()
        if _is_command(pdu, E["ZW_CMD_SEAL"]):
            sealed.append(True)
        return "forward"

    p, _ = commission_through_proxy(d, hook)
    assert p.returncode == 3, (p.stdout, p.stderr)
    assert "is in commissioning mode again: another client unlocked it after us" in p.stderr
    assert "commissioned" not in p.stdout
    assert status(d)["mode"] == "commissioning"


def test_commission_lost_connection_after_unlock_sends_abort(start_drive):
    d = start_drive()  # sealed with the paper's block, sigma 0.8

    def hook(pdu, index):
        # the first connection is cut when the block is written (after UNLOCK2 succeeded)
        if index == 0 and pdu[0] == 0x10 and struct.unpack(">H", pdu[1:3])[0] == E["ZW_REG_CERT_M"]:
            return "drop"
        return "forward"

    p, proxy = commission_through_proxy(d, hook)
    assert p.returncode == 2, (p.stdout, p.stderr)
    assert "cannot write the certified block" in p.stderr and "sent ABORT" in p.stderr, p.stderr
    assert (1, struct.pack(">BHH", 6, CMD, E["ZW_CMD_ABORT"])) in proxy.requests
    s = status(d)
    assert s["mode"] == "operation" and s["sealed"] is True and s["cert"]["sigma"] == f32(0.8)


def test_commission_lost_connection_abort_impossible_is_reported(start_drive):
    d = start_drive()

    def hook(pdu, index):
        # every connection is cut at the block write and at ABORT: the drive stays unlocked
        if (pdu[0] == 0x10 and struct.unpack(">H", pdu[1:3])[0] == E["ZW_REG_CERT_M"]) or \
                _is_command(pdu, E["ZW_CMD_ABORT"]):
            return "drop"
        return "forward"

    p, proxy = commission_through_proxy(d, hook)
    assert p.returncode == 2, (p.stdout, p.stderr)
    assert "could not send ABORT either" in p.stderr, p.stderr
    assert status(d)["mode"] == "commissioning"
    with d.client() as c:
        c.write1(CMD, E["ZW_CMD_ABORT"])


def test_tune_slave_and_float_range_are_usage_errors(drive):
    for args in (["--rtu", "/nonexistent-tty", "--slave", "0", "status"],
                 ["--slave", "248", "--rtu", "/nonexistent-tty", "status"],
                 ["--slave", "256", "status"], ["--slave", "-1", "status"],
                 ["set", "--K", "1e39"], ["set", "--B", "-3.5e38"], ["set", "--K", "1e300"]):
        p = drive.tune(*args)
        assert p.returncode == 2, (args, p.stdout, p.stderr)
        assert p.stdout == "", args
    p = drive.tune("set", "--K", "1e39")
    assert "does not fit a float register" in p.stderr
    # TCP unit ids 0 and 255 are fine (the drive answers any unit id)
    for unit in ("0", "255"):
        p = drive.tune("--slave", unit, "status", "--json")
        assert p.returncode == 0, p.stderr
    # the largest float is a value like any other; NaN and inf still reach the drive
    p = drive.tune("set", "--K", "3.4028234663852886e38")
    assert p.returncode == 3 and "ZW_REASON_K_ABOVE_MAX" in p.stdout, p.stdout
    p = drive.tune("set", "--K", "inf")
    assert p.returncode == 3 and "ZW_REASON_NOT_FINITE" in p.stdout, p.stdout
