# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Raw Modbus TCP against zwidth-drive: exceptions for bad requests, framing the server must
survive (unknown function codes, inconsistent lengths, half frames, vanished clients,
garbage), and several clients writing and reading at once."""
from __future__ import annotations

import random
import socket
import struct
import threading
import time

import pytest

from zwmb_harness import E, LOOPBACK, ModbusException, f32, float_words, drive, start_drive  # noqa: F401 (fixtures)

K_REG, B_REG = E["ZW_REG_K"], E["ZW_REG_B"]


def closed_by_peer(sock):
    """True when the server closed the connection (orderly or by reset), without answering."""
    try:
        return sock.recv(16) == b""
    except ConnectionResetError:
        return True


def expect_exception(client, pdu, code, reason):
    with pytest.raises(ModbusException) as ei:
        client.call(pdu)
    assert ei.value.code == code, (pdu.hex(), ei.value.code)
    assert client.refusal() == (reason, code), pdu.hex()


def test_half_float_write_refused_0x02(drive):
    with drive.client() as c:
        c.set_gains(0.2, -5e-4)
        hi, lo = float_words(0.1)
        # one register of K (0x10 with quantity 1), the low word of K, one word of B via 0x06
        expect_exception(c, struct.pack(">BHHBH", 0x10, K_REG, 1, 2, hi), 2, "ZW_REASON_HALF_FLOAT")
        expect_exception(c, struct.pack(">BHHBH", 0x10, K_REG + 1, 1, 2, lo), 2, "ZW_REASON_HALF_FLOAT")
        expect_exception(c, struct.pack(">BHH", 0x06, B_REG, hi), 2, "ZW_REASON_HALF_FLOAT")
        # K and the high word of B: the pair would be split
        expect_exception(c, struct.pack(">BHHB3H", 0x10, K_REG, 3, 6, hi, lo, 0), 2,
                         "ZW_REASON_HALF_FLOAT")
        assert c.gains() == (f32(0.2), f32(-5e-4))


def test_unmapped_and_read_only_refused_0x02(drive):
    with drive.client() as c:
        expect_exception(c, struct.pack(">BHH", 3, 0x000A, 2), 2, "ZW_REASON_UNMAPPED")
        expect_exception(c, struct.pack(">BHH", 3, 0x0063, 1), 2, "ZW_REASON_UNMAPPED")
        expect_exception(c, struct.pack(">BHH", 3, 0xFFFF, 2), 2, "ZW_REASON_UNMAPPED")
        expect_exception(c, struct.pack(">BHHBH", 0x10, 0x0070, 1, 2, 1), 2, "ZW_REASON_UNMAPPED")
        expect_exception(c, struct.pack(">BHH", 6, 0x0000, 1), 2, "ZW_REASON_READ_ONLY")
        expect_exception(c, struct.pack(">BHHB2H", 0x10, 0x0020, 2, 4, 0, 0), 2, "ZW_REASON_READ_ONLY")
        # the certified block is locked outside commissioning
        expect_exception(c, struct.pack(">BHHB2H", 0x10, E["ZW_REG_CERT_SIGMA"], 2, 4, *float_words(0.9)),
                         2, "ZW_REASON_LOCKED")
        assert c.read(0, 2) == [0x5A57, 5]


def test_nan_refused_0x03(drive):
    with drive.client() as c:
        nan = [0x7FC0, 0x0000]
        expect_exception(c, struct.pack(">BHHB4H", 0x10, K_REG, 4, 8, *nan, 0, 0), 3, "ZW_REASON_NOT_FINITE")
        expect_exception(c, struct.pack(">BHHB2H", 0x10, B_REG, 2, 4, 0x7F80, 0), 3, "ZW_REASON_NOT_FINITE")
        assert c.gains() == (0.0, 0.0)


def test_unsupported_functions_0x01_and_stream_stays_in_step(drive):
    """Function codes the map does not serve, including the ones behind the libmodbus
    advisories (0x17 with inconsistent address/quantity: CVE-2022-0367), get 0x01; the
    MBAP length frames them, so the next request on the same connection is understood."""
    with drive.client() as c:
        pdus = [
            bytes([0x2B, 0x0E, 0x01, 0x00]),                      # read device identification
            bytes([0x08, 0x00, 0x00, 0x12, 0x34]),                # diagnostics (echo)
            bytes([0x11]),                                        # report server id
            bytes([0x01, 0x00, 0x00, 0x00, 0x10]),                # read coils
            bytes([0x04, 0x00, 0x10, 0x00, 0x04]),                # read input registers
            bytes([0x16, 0x00, 0x10, 0xFF, 0xFF, 0x00, 0x00]),    # mask write
            struct.pack(">BHHHHB2H", 0x17, 0xFFF0, 0x7D, 0xFFFF, 0x01, 2, 0x4242, 0x4242),
            bytes([0x17]) + bytes(9),
            bytes([0x0F, 0x00, 0x00, 0x00, 0x08, 0x01, 0xFF]),    # write coils
            bytes([0x7F]) + bytes(40),
        ]
        for pdu in pdus:
            rsp = c.raw(pdu)
            assert rsp == bytes([pdu[0] | 0x80, 1]), (pdu.hex(), rsp.hex())
            assert c.read(0, 1) == [0x5A57]
        assert c.refusal() == ("ZW_REASON_BAD_FUNCTION", 1)


def test_inconsistent_lengths_refused_and_stream_stays_in_step(drive):
    """Requests whose own fields disagree with the MBAP length or with themselves, and the
    minimal-length requests of upstream issue 837: refused 0x03 MALFORMED, nothing read
    out of bounds, the next frame on the connection served."""
    with drive.client() as c:
        c.set_gains(0.2, -5e-4)
        w = float_words(0.1, -1e-4)
        pdus = [
            bytes([0x03]),                                               # function code only
            bytes([0x03, 0x00]),
            bytes([0x03, 0x00, 0x10, 0x00]),
            bytes([0x03, 0x00, 0x10, 0x00, 0x04, 0x00, 0x00]),           # trailing bytes
            bytes([0x03, 0x00, 0x10, 0x00, 0x00]),                       # quantity 0
            bytes([0x03, 0x00, 0x00, 0x00, 0x7E]),                       # quantity 126 > 125
            bytes([0x06, 0x00, 0x60]),                                   # short write single
            bytes([0x10]),
            bytes([0x10, 0x00, 0x10, 0x00, 0x04]),                       # no byte count
            struct.pack(">BHHB4H", 0x10, K_REG, 4, 16, *w),              # byte count > data
            struct.pack(">BHHB4H", 0x10, K_REG, 4, 6, *w),               # byte count < data
            struct.pack(">BHHB4H", 0x10, K_REG, 3, 8, *w),               # quantity != count/2
            struct.pack(">BHHB4H", 0x10, K_REG, 0, 0, *w),
        ]
        for pdu in pdus:
            rsp = c.raw(pdu)
            assert rsp == bytes([pdu[0] | 0x80, 3]), (pdu.hex(), rsp.hex())
            assert c.refusal() == ("ZW_REASON_MALFORMED", 3)
        assert c.gains() == (f32(0.2), f32(-5e-4))


def test_pipelined_requests_in_one_segment(drive):
    with drive.client() as c:
        frames = b""
        for tid in range(1, 6):
            pdu = struct.pack(">BHH", 3, 0, 2)
            frames += struct.pack(">HHHB", tid, 0, len(pdu) + 1, 7) + pdu
        c.sock.sendall(frames)
        for tid in range(1, 6):
            head = c.recv_exact(7)
            assert struct.unpack(">HHHB", head) == (tid, 0, 7, 7)  # tid and unit id echoed
            assert c.recv_exact(6) == bytes([3, 4, 0x5A, 0x57, 0, 5])


def test_not_modbus_tcp_closes_only_that_connection(drive):
    with drive.client() as bad, drive.client() as good:
        bad.sock.sendall(b"GET / HTTP/1.1\r\nHost: x\r\n\r\n")  # protocol id 0x2F20
        assert closed_by_peer(bad.sock)
        bad2 = drive.client()
        bad2.sock.sendall(struct.pack(">HHHB", 1, 0, 300, 1) + bytes(299))  # length > 254
        assert closed_by_peer(bad2.sock)
        bad2.close()
        assert good.read(0, 1) == [0x5A57]
    assert "not Modbus TCP" in drive.log()


def test_client_killed_mid_frame(drive):
    """Half an MBAP header then close; half a frame then an abortive close (RST); half a
    frame and silence: the server keeps serving everyone else at once, and drops the
    stalled client after the frame timeout."""
    with drive.client() as good:
        s = socket.create_connection((LOOPBACK, drive.port), timeout=3)
        s.sendall(b"\x00\x01\x00")
        s.close()
        s = socket.create_connection((LOOPBACK, drive.port), timeout=3)
        s.sendall(struct.pack(">HHHB", 2, 0, 11, 1) + bytes([0x10, 0x00, 0x10]))
        s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
        s.close()
        stalled = socket.create_connection((LOOPBACK, drive.port), timeout=3)
        stalled.sendall(struct.pack(">HHHB", 3, 0, 11, 1) + bytes([0x10, 0x00, 0x10, 0x00]))
        t0 = time.monotonic()
        for _ in range(5):
            assert good.read(0, 1) == [0x5A57]
        assert time.monotonic() - t0 < 0.4  # not held up by the stalled frame
        stalled.settimeout(3)
        assert closed_by_peer(stalled)  # dropped after --frame-timeout (500 ms)
        assert time.monotonic() - t0 < 2.5
        stalled.close()
        good.set_gains(0.1, 0.0)
        assert good.gains() == (f32(0.1), 0.0)
    assert drive.alive()
    assert "incomplete frame timed out" in drive.log()


def test_client_vanishes_before_its_answer(drive):
    """Requests sent, socket closed before reading the answers: nothing breaks."""
    for _ in range(20):
        s = socket.create_connection((LOOPBACK, drive.port), timeout=3)
        pdu = struct.pack(">BHH", 3, 0x20, 16)
        s.sendall((struct.pack(">HHHB", 1, 0, 6, 1) + pdu) * 4)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
        s.close()
    with drive.client() as c:
        assert c.read(0, 2) == [0x5A57, 5]
    assert drive.alive()
    assert "refused the connection" not in drive.log()


def test_garbage_burst(drive):
    """Random bytes, random MBAP frames with random PDUs, truncated frames, on many
    connections: the drive stays up, keeps serving, and the gains do not move."""
    rng = random.Random(20240611)
    with drive.client() as c:
        c.set_gains(0.2, -5e-4)
        accepted_before = c.counters()[0]
    for i in range(60):
        s = socket.create_connection((LOOPBACK, drive.port), timeout=3)
        kind = i % 4
        if kind == 0:
            blob = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 600)))
        elif kind == 1:  # well-framed, random PDU of any function code but 0x06/0x10
            fc = rng.choice([f for f in range(256) if f not in (0x06, 0x10)])
            pdu = bytes([fc]) + bytes(rng.randrange(256) for _ in range(rng.randrange(0, 60)))
            blob = struct.pack(">HHHB", i, 0, len(pdu) + 1, 1) + pdu
        elif kind == 2:  # well-framed writes of random words to the gains or the block
            n = rng.randrange(1, 30)
            addr = rng.choice([0x0010, 0x0011, 0x0012, 0x0040, 0x0060, 0x0000])
            words = [rng.randrange(0x10000) for _ in range(n)]
            pdu = struct.pack(f">BHHB{n}H", 0x10, addr, n, (2 * n + rng.choice([0, 0, 1, -1])) & 0xFF, *words)
            blob = struct.pack(">HHHB", i, 0, len(pdu) + 1, 1) + pdu
        else:  # a valid frame cut anywhere
            pdu = struct.pack(">BHHB4H", 0x10, K_REG, 4, 8, *float_words(0.3, -1e-3))
            frame = struct.pack(">HHHB", i, 0, len(pdu) + 1, 1) + pdu
            blob = frame[: rng.randrange(1, len(frame))]
        try:
            s.sendall(blob)
        except OSError:
            pass
        s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
        s.close()
    assert drive.alive()
    with drive.client() as c:
        assert c.read(0, 2) == [0x5A57, 5]
        assert c.gains() == (f32(0.2), f32(-5e-4))
        assert c.counters()[0] == accepted_before
        c.set_gains(0.25, -5e-4)  # and it still takes a good write
        assert c.gains() == (f32(0.25), f32(-5e-4))


def test_concurrent_clients_never_see_a_mixed_pair(drive):
    """Writers on their own connections write whole pairs (some accepted, some refused),
    readers read K and B in one request: every pair read is one that was accepted, never
    K of one write with B of another, and the accepted counter matches the writes that
    were answered normally."""
    good = [(0.10, -2e-4), (0.20, -5e-4), (0.30, -1e-3), (0.15, 0.0), (0.25, -8e-4)]
    bad = [(0.45, -1.36e-3), (0.30, 0.004), (11.0, 0.0), (0.2, 0.02)]
    allowed = {(f32(k), f32(b)) for k, b in good} | {(0.0, 0.0)}
    stop = time.monotonic() + 1.5
    errors, seen, accepted = [], set(), [0]
    lock = threading.Lock()

    def writer(seed):
        rng = random.Random(seed)
        n_ok = 0
        try:
            with drive.client(timeout=5) as c:
                while time.monotonic() < stop:
                    K, B = rng.choice(good + bad)
                    try:
                        c.set_gains(K, B)
                        n_ok += 1
                        assert (K, B) in good, (K, B)
                    except ModbusException as e:
                        assert (K, B) in bad and e.code == 3, (K, B, e.code)
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(repr(e))
        with lock:
            accepted[0] += n_ok

    def reader():
        try:
            with drive.client(timeout=5) as c:
                while time.monotonic() < stop:
                    pair = c.gains()
                    with lock:
                        seen.add(pair)
                    if pair not in allowed:
                        errors.append(f"mixed or refused pair read back: {pair}")
        except Exception as e:  # noqa: BLE001
            errors.append(repr(e))

    threads = [threading.Thread(target=writer, args=(s,)) for s in range(4)]
    threads += [threading.Thread(target=reader) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=15)
        assert not t.is_alive(), "client thread hung"
    assert not errors, errors[:5]
    assert len(seen) >= 3, seen  # the readers did see the writers' changes
    with drive.client() as c:
        assert c.counters()[0] == accepted[0]
