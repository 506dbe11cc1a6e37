# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Commissioning end to end: unlock, block, CRC, seal, and the refusals on the way."""
from __future__ import annotations

import json
import struct

import pytest

from zwmb_harness import E, ModbusException, f32, float_words, words_float, drive, start_drive  # noqa: F401 (fixtures)

PAPER_OPTS = ["--m", "85.78e-7", "--b", "2.197e-3", "--T", "0.02", "--r", "0.999",
              "--k-min", "0", "--k-max", "10", "--b-min", "-0.01", "--b-max", "0.01",
              "--dk-max", "1", "--db-max", "0.01"]
CMD = E["ZW_REG_COMMAND"]


def crc16_words(words):
    """CRC-16/MODBUS of 16-bit words fed high byte first (independent of the C code)."""
    crc = 0xFFFF
    for w in words:
        for byte in (w >> 8, w & 0xFF):
            crc ^= byte
            for _ in range(8):
                crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def block_words(sigma, delay=0.0, vfilter=0.0, vf_param=0.0, differentiator=0.0):
    """The 34 words of the block (map v4: plant, policy, the loop (default the ideal loop),
    then the plant's upper ends: a point, as zwidth-tune writes it)."""
    return float_words(85.78e-7, 2.197e-3, 0.02, sigma, 0.999, 0.0, 10.0, -0.01, 0.01, 1.0, 0.01,
                       delay, vfilter, vf_param, differentiator, 85.78e-7, 2.197e-3)


def status(d):
    p = d.tune("status", "--json")
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout, parse_float=lambda t: f32(float(t)))


def test_commissioning_end_to_end(start_drive):
    d = start_drive("--unsealed")
    s = status(d)
    assert s["sealed"] is False and s["mode"] == "operation"
    p = d.tune("set", "--K", "0.1", "--B", "0")
    assert p.returncode == 3 and "ZW_REASON_NOT_SEALED (exception 0x02" in p.stdout

    with d.client() as c:
        # the block is locked outside commissioning; UNLOCK2 needs UNLOCK1 right before it
        with pytest.raises(ModbusException) as ei:
            c.write(E["ZW_REG_CERT_M"], block_words(0.9))
        assert ei.value.code == 2 and c.refusal() == ("ZW_REASON_LOCKED", 2)
        with pytest.raises(ModbusException) as ei:
            c.write1(CMD, E["ZW_CMD_UNLOCK2"])
        assert ei.value.code == 3 and c.refusal() == ("ZW_REASON_BAD_COMMAND", 3)
        c.write1(CMD, E["ZW_CMD_UNLOCK1"])
        with pytest.raises(ModbusException):  # any request but a read in between (here a
            c.set_gains(0.1, 0.0)             # refused one) disarms UNLOCK1
        with pytest.raises(ModbusException):
            c.write1(CMD, E["ZW_CMD_UNLOCK2"])
        assert c.read(E["ZW_REG_MODE"], 1) == [0]
        # reads do not disarm it: a client polling the map cannot block commissioning
        c.write1(CMD, E["ZW_CMD_UNLOCK1"])
        assert c.read(0, 10)[0] == 0x5A57
        c.write1(CMD, E["ZW_CMD_UNLOCK2"])
        assert c.read(E["ZW_REG_MODE"], 1) == [1]
        c.write1(CMD, E["ZW_CMD_ABORT"])
        assert c.read(E["ZW_REG_MODE"], 2) == [0, 0]  # back to operation, still unsealed

    p = d.tune("commission", *PAPER_OPTS, "--sigma", "0.9")
    assert p.returncode == 0, (p.stdout, p.stderr)
    words = block_words(0.9)
    assert f"CRC 0x{crc16_words(words):04X}" in p.stdout
    s = status(d)
    assert s["sealed"] is True and s["mode"] == "operation"
    assert s["cert"]["sigma"] == f32(0.9) and s["cert"]["crc"] == crc16_words(words)
    assert s["gains"] == {"K": 0.0, "B": 0.0}
    # sigma 0.9: ceiling at B = -1.36e-3 is 0.9 x 0.49275 = 0.4435
    p = d.tune("set", "--K", "0.42", "--B", "-1.36e-3")
    assert p.returncode == 0, p.stdout
    p = d.tune("set", "--K", "0.45", "--B", "-1.36e-3")
    assert p.returncode == 3 and "ZW_REASON_ABOVE_SIGMA" in p.stdout

    # a policy the drive refuses at SEAL: reported, commissioning aborted, old block back
    p = d.tune("commission", *PAPER_OPTS, "--sigma", "1.5", "--json")
    assert p.returncode == 3
    v = json.loads(p.stdout)
    assert v.pop("drive").startswith("in operation, sealed block CRC 0x")  # read back
    assert v == {"verdict": "refused", "step": "seal", "reason": "ZW_REASON_BAD_POLICY",
                 "reason_code": 20, "exception": 3, "exception_name": "ILLEGAL_DATA_VALUE",
                 "aborted": True, "gains": {"K": 0, "B": 0}, "output_off": True}
    s = status(d)
    assert s["sealed"] is True and s["mode"] == "operation" and s["cert"]["sigma"] == f32(0.9)
    assert s["gains"] == {"K": 0.0, "B": 0.0}  # unlocking turned the output off

    # a wrong CRC is refused at SEAL; ABORT restores the sealed block
    with d.client() as c:
        c.write1(CMD, E["ZW_CMD_UNLOCK1"])
        c.write1(CMD, E["ZW_CMD_UNLOCK2"])
        assert c.read(E["ZW_REG_MODE"], 1) == [1]
        c.write(E["ZW_REG_CERT_M"], block_words(0.5) + [crc16_words(block_words(0.5)) ^ 1])
        with pytest.raises(ModbusException) as ei:
            c.write1(CMD, E["ZW_CMD_SEAL"])
        assert ei.value.code == 3 and c.refusal() == ("ZW_REASON_CRC", 3)
        # gains are refused while commissioning
        with pytest.raises(ModbusException) as ei:
            c.set_gains(0.1, 0.0)
        assert ei.value.code == 2 and c.refusal() == ("ZW_REASON_NOT_SEALED", 2)
        c.write1(CMD, E["ZW_CMD_ABORT"])
        assert c.read(E["ZW_REG_MODE"], 2) == [0, 1]
        assert words_float(c.read(E["ZW_REG_CERT_SIGMA"], 2)) == [f32(0.9)]
        c.set_gains(0.3, -1e-3)
        assert c.gains() == (f32(0.3), f32(-1e-3))


def test_commission_paper_defaults_and_text_report(start_drive):
    d = start_drive("--unsealed")
    p = d.tune("commission", "--paper-defaults", "--sigma", "0.8")
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("commissioned: the drive sealed our block (CRC 0x")
    assert "operation mode, sealed" in p.stdout
    crc = crc16_words(block_words(0.8))
    assert status(d)["cert"]["crc"] == crc
    # the power-up default block of a sealed drive is the same block, with the same CRC
    d2 = start_drive()
    assert status(d2)["cert"]["crc"] == crc


def test_factory_ceilings_of_the_drive(start_drive):
    """Review A3: no margin (sigma 1, r 1, no step limit) is refused at power-up too, and
    the key holder cannot seal a block that lies about the plant or widens the ceilings."""
    import subprocess
    from zwmb_harness import DRIVE, LOOPBACK
    p = subprocess.run([str(DRIVE), "--host", LOOPBACK, "--port", "0", "--sigma", "1", "--r", "1",
                        "--dk-max", "1e30"], capture_output=True, text=True, timeout=10)
    assert p.returncode == 2 and "ZW_REASON_ABOVE_CEILING" in p.stderr, p.stderr
    d = start_drive()
    for extra, reason in ((["--m", "1.7156e-5"], "ZW_REASON_PLANT_MISMATCH"),   # inertia x2
                          (["--sigma", "1"], "ZW_REASON_ABOVE_CEILING"),
                          (["--r", "1"], "ZW_REASON_ABOVE_CEILING"),
                          (["--k-max", "20"], "ZW_REASON_ABOVE_CEILING"),
                          (["--m", "1e-40"], "ZW_REASON_SUBNORMAL")):
        p = d.tune("commission", "--paper-defaults", *extra, "--json")
        assert p.returncode == 3, (extra, p.stdout, p.stderr)
        v = json.loads(p.stdout)
        assert (v["step"], v["reason"], v["aborted"]) == ("seal", reason, True), extra
    assert status(d)["cert"]["sigma"] == f32(0.8)  # the power-up block is still in force
    p = d.tune("commission", "--paper-defaults", "--m", "8.8e-6", "--sigma", "0.9")  # within 5 %
    assert p.returncode == 0, (p.stdout, p.stderr)


def test_minus_zero_gains_stored_as_zero(drive):
    """Review A2: (-0.0, -0.0) is "off" and reads back as two zero words."""
    with drive.client() as c:
        c.set_gains(0.2, -5e-4)
        c.write(E["ZW_REG_K"], [0x8000, 0, 0x8000, 0])
        assert c.read(E["ZW_REG_K"], 4) == [0, 0, 0, 0]


def test_commission_a_box_of_plants_with_tune(start_drive):
    """Map version 4: `zwidth-tune commission --m LO:HI --b LO:HI` seals a ranged block (the
    drive needs r = 1 in its ceilings); status shows the box; map version 5: with its box
    certificate, which status shows and writes look up; a drive started with ranges
    takes its middle as the nameplate."""
    d = start_drive("--max-r", "1")
    m_lo, m_hi, b_lo, b_hi = 0.97 * 85.78e-7, 1.04 * 85.78e-7, 0.98 * 2.197e-3, 1.03 * 2.197e-3
    p = d.tune("commission", "--paper-defaults", "--r", "1", "--m", f"{m_lo!r}:{m_hi!r}",
               "--b", f"{b_lo!r}:{b_hi!r}")
    assert p.returncode == 0, (p.stdout, p.stderr)
    s = status(d)
    assert (s["cert"]["m"], s["cert"]["m_hi"], s["cert"]["b"], s["cert"]["b_hi"]) == \
        (f32(m_lo), f32(m_hi), f32(b_lo), f32(b_hi))
    # map version 5: the certificate was built in the drive's precision and sent with it
    with d.client() as c:
        precision = {4: "float", 8: "double"}[c.read(E["ZW_REG_PRECISION"], 1)[0]]
    assert "box certificate:" in p.stderr and f"({precision}, 16 steps" in p.stderr, p.stderr
    stairs = s["box_certificate"]
    assert stairs["steps"] == 16 and len(stairs["B"]) == 17 and all(k > 0 for k in stairs["K"])
    assert s["cert"]["b_min"] <= stairs["B"][0] < stairs["B"][-1] <= s["cert"]["b_max"]
    p = d.tune("status")
    assert "a box of plants" in p.stdout and "certificate: 16 steps" in p.stdout, p.stdout
    # writes are lookups: the level at B, and B outside the staircase refused by name
    B_mid = 0.5 * (stairs["B"][7] + stairs["B"][8])
    level = min(stairs["K"][7], stairs["K"][8])
    p = d.tune("set", "--K", repr(0.79 * level), "--B", repr(B_mid), "--json")
    assert p.returncode == 0, (p.stdout, p.stderr)
    p = d.tune("set", "--K", repr(0.5 * level), "--B", repr(stairs["B"][-1] * 1.5 + 1e-3), "--json")
    assert p.returncode == 3 and json.loads(p.stdout)["reason"] == "ZW_REASON_OUTSIDE_CERT", p.stdout
    # --cert-b: the staircase's range as given; without ranges it is a usage error
    p = d.tune("commission", "--paper-defaults", "--r", "1", "--m", f"{m_lo!r}:{m_hi!r}",
               "--cert-b", "-1e-3:2e-3", "--json")
    assert p.returncode == 0, (p.stdout, p.stderr)
    assert status(d)["box_certificate"]["B"][0] == f32(-1e-3)
    p = d.tune("commission", "--paper-defaults", "--cert-b", "-1e-3:2e-3")
    assert p.returncode == 2 and "--cert-b needs plant ranges" in p.stderr, p.stderr
    p = d.tune("commission", "--paper-defaults", "--r", "1", "--m", f"{m_lo!r}:{m_hi!r}", "--cert-b", "2e-3")
    assert p.returncode == 2 and "--cert-b expects LO:HI" in p.stderr, p.stderr
    # r < 1 with ranges: refused by name at SEAL, the block in force stays
    p = d.tune("commission", "--paper-defaults", "--r", "0.999", "--m", f"{m_lo!r}:{m_hi!r}", "--json")
    assert p.returncode == 3 and json.loads(p.stdout)["reason"] == "ZW_REASON_BOX_RADIUS", p.stdout
    assert status(d)["cert"]["m_hi"] == f32(m_hi)
    # a range option that is not LO:HI is a usage error
    p = d.tune("commission", "--paper-defaults", "--m", "1e-6:")
    assert p.returncode == 2
    # a box other than the paper's plant states its loop and its gain bounds (zwidth-drive
    # refuses to start without them, test_drive_options.py)
    d2 = start_drive("--m", "8e-6:9.5e-6", "--r", "1", "--max-r", "1", "--delay", "0",
                     "--k-max", "10", "--b-min", "-0.01", "--b-max", "0.01", "--dk-max", "1",
                     "--db-max", "0.01")
    s2 = status(d2)
    assert (s2["cert"]["m"], s2["cert"]["m_hi"]) == (f32(8e-6), f32(9.5e-6))
    assert s2["live"]["B_lo"] is None  # NaN: no box form per write
