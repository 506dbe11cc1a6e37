# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Interoperability with a Modbus client nobody here wrote: Debian's mbpoll (Modbus TCP)."""
from __future__ import annotations

import json
import re
import shutil
import subprocess

import pytest

from zwmb_harness import LOOPBACK, f32, drive, start_drive  # noqa: F401 (fixtures)

MBPOLL = shutil.which("mbpoll")
pytestmark = pytest.mark.skipif(MBPOLL is None, reason="mbpoll not installed (apt-get install mbpoll)")


def mbpoll(drive, *args):
    cmd = [MBPOLL, "-m", "tcp", "-p", str(drive.port), "-a", "1", "-0", "-o", "1", "-1", *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=15, stdin=subprocess.DEVNULL)


def values(out):
    """{reference: value} from mbpoll's '[32]: \t0.357709' lines."""
    return {int(a): float(b) for a, b in re.findall(r"^\[(\d+)\]:\s+(\S+)", out, re.M)}


def status(drive):
    p = drive.tune("status", "--json")
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def test_mbpoll_reads_live_limits(drive):
    p = mbpoll(drive, "-B", "-t", "4:float", "-r", "32", "-c", "8", LOOPBACK)
    assert p.returncode == 0, (p.stdout, p.stderr)
    got = values(p.stdout)
    live = status(drive)["live"]
    names = ["K_max", "K_cert", "B_lo", "B_hi", "K_mmax", "B_at_K_mmax", "rho", "delta"]
    assert sorted(got) == list(range(32, 48, 2))
    for i, name in enumerate(names):
        # mbpoll prints 6 significant digits
        assert got[32 + 2 * i] == pytest.approx(live[name], rel=1e-5, abs=1e-12), name
    p = mbpoll(drive, "-t", "4:hex", "-r", "0", "-c", "2", LOOPBACK)
    assert p.returncode == 0 and "0x5A57" in p.stdout


def test_mbpoll_sets_gains_and_gets_the_exception(drive):
    # K and B in one request (mbpoll writes the floats with one Write Multiple Registers)
    p = mbpoll(drive, "-B", "-t", "4:float", "-r", "16", LOOPBACK, "--", "0.2", "-0.0005")
    assert p.returncode == 0 and "Written 2 references" in p.stdout, (p.stdout, p.stderr)
    g = status(drive)["gains"]
    assert (f32(g["K"]), f32(g["B"])) == (f32(0.2), f32(-5e-4))
    # a bad pair: the drive answers exception 0x03, mbpoll reports it, nothing changes
    p = mbpoll(drive, "-B", "-t", "4:float", "-r", "16", LOOPBACK, "--", "0.45", "-0.00136")
    assert p.returncode != 0 and "Illegal data value" in p.stderr, (p.stdout, p.stderr)
    s = status(drive)
    assert (f32(s["gains"]["K"]), f32(s["gains"]["B"])) == (f32(0.2), f32(-5e-4))
    assert s["last_refusal"]["reason"] == "ZW_REASON_ABOVE_SIGMA"
    # the registers one by one (16-bit): half a float is an illegal address
    p = mbpoll(drive, "-t", "4", "-r", "16", LOOPBACK, "0")
    assert p.returncode != 0 and "Illegal data address" in p.stderr, (p.stdout, p.stderr)
    p = mbpoll(drive, "-t", "4", "-r", "10", "-c", "2", LOOPBACK)
    assert p.returncode != 0 and "Illegal data address" in p.stderr


def test_mbpoll_cdab_drive(start_drive):
    """--word-order cdab: mbpoll's default word order (without -B, low word first) reads
    and writes the floats; WORD_ORDER reads 1; one-word registers are unchanged."""
    d = start_drive("--word-order", "cdab")
    p = mbpoll(d, "-t", "4:float", "-r", "16", LOOPBACK, "--", "0.2", "-0.0005")
    assert p.returncode == 0, (p.stdout, p.stderr)
    p = mbpoll(d, "-t", "4:float", "-r", "16", "-c", "2", LOOPBACK)
    assert p.returncode == 0, (p.stdout, p.stderr)
    assert values(p.stdout) == {16: pytest.approx(0.2, rel=1e-6), 18: pytest.approx(-0.0005, rel=1e-6)}
    p = mbpoll(d, "-B", "-t", "4:float", "-r", "16", "-c", "2", LOOPBACK)  # the other order: garbage
    assert values(p.stdout)[16] != pytest.approx(0.2, rel=1e-3)
    p = mbpoll(d, "-t", "4", "-r", "0", "-c", "1", LOOPBACK)
    assert values(p.stdout) == {0: 0x5A57}
    p = mbpoll(d, "-t", "4", "-r", "131", "-c", "1", LOOPBACK)
    assert values(p.stdout) == {131: 1}
    # zwidth-tune follows WORD_ORDER: it reads what mbpoll wrote, and writes what mbpoll reads
    p = d.tune("status", "--json")
    assert p.returncode == 0, p.stderr
    assert {k: f32(v) for k, v in json.loads(p.stdout)["gains"].items()} == {"K": f32(0.2), "B": f32(-0.0005)}
    p = d.tune("--word-order", "cdab", "set", "--K", "0.25", "--B", "-0.0004")
    assert p.returncode == 0 and p.stdout.startswith("accepted: active gains K = 0.25"), (p.stdout, p.stderr)
    p = mbpoll(d, "-t", "4:float", "-r", "16", "-c", "2", LOOPBACK)
    assert values(p.stdout) == {16: pytest.approx(0.25, rel=1e-6), 18: pytest.approx(-0.0004, rel=1e-6)}
    # asked for the other order, it says so rather than misread
    p = d.tune("--word-order", "abcd", "status")
    assert p.returncode == 2 and "low word first (CDAB); --word-order abcd says high word first" in p.stderr, p.stderr
