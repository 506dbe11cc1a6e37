# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zwidth.modbus against a live zwidth-drive on a free 127.0.0.1 port, and pymodbus itself
as a client that nobody here wrote (interoperability of the exception responses)."""
from __future__ import annotations

import dataclasses
import math
import struct

import pytest

from mb_support import LOOPBACK, PAPER_PLANT, POLICY, TEST_KEY
from zwidth import modbus as zm

TIMEOUT = 2.0  # s, every request


def f32(x: float) -> float:
    """x rounded to binary32, as the drive stores it."""
    return struct.unpack(">f", struct.pack(">f", x))[0]


def drive(port: int, timeout: float = TIMEOUT, **kw) -> zm.Drive:
    return zm.Drive(LOOPBACK, port, timeout=timeout, **kw)


def fields6(c: zm.CommissionResult) -> tuple:
    """The outcome without its words: accepted, reason, exception, stage, crc, aborted."""
    return (c.accepted, c.reason, c.exception, c.stage, c.crc, c.aborted)


# ---------------------------------------------------------------------------------------
# status
# ---------------------------------------------------------------------------------------


def test_status_of_a_fresh_drive(drive_port):
    with drive(drive_port) as d:
        s = d.status()
    assert s.mode == "operation" and s.sealed and s.version == 5
    assert s.plant == zm.Plant(*(f32(PAPER_PLANT[k]) for k in ("m", "b", "T", "m", "b")))
    expected_policy = {k: f32(v) for k, v in POLICY.items()}
    assert {k: getattr(s.policy, k) for k in POLICY} == expected_policy
    words = []
    for key in ("m", "b", "T"):
        words += zm.float_to_words(PAPER_PLANT[key])
    for key in ("sigma", "r", "k_min", "k_max", "b_min", "b_max", "dk_max", "db_max"):
        words += zm.float_to_words(POLICY[key])
    words += [0] * 8  # the ideal loop: delay, filter, parameter, differentiator all 0.0
    words += zm.float_to_words(PAPER_PLANT["m"]) + zm.float_to_words(PAPER_PLANT["b"])  # a point
    assert s.policy.crc == zm.crc16_words(words)
    assert s.loop == zm.Loop(0.0, "none", s.loop.cutoff_hz, 0, "backward", 0.0) and s.loop.ideal
    assert s.gains == zm.Gains(0.0, 0.0)
    # The paper: K_mmax = 0.4934 N m/rad at B = -1.357e-3 N m s/rad, delta = 5.12241.
    assert s.limits.K_mmax == pytest.approx(0.493379, rel=1e-5)
    assert s.limits.B_at_K_mmax == pytest.approx(-1.3567e-3, rel=1e-4)
    assert s.limits.delta == pytest.approx(5.12241, rel=1e-5)
    assert s.limits.K_max == pytest.approx(0.357709, rel=1e-5)  # at B = 0
    assert s.state == zm.State(0.0, 0.0, 0.0, 0)
    assert s.counters == zm.Counters(0, 0)
    assert s.last_refusal == zm.Refusal("ZW_REASON_NONE", 0)


def test_status_is_frozen(drive_port):
    with drive(drive_port) as d:
        s = d.status()
    with pytest.raises(AttributeError):
        s.sealed = False  # type: ignore[misc]


# ---------------------------------------------------------------------------------------
# gain writes
# ---------------------------------------------------------------------------------------


def test_accepted_pair_is_one_change(drive_port):
    with drive(drive_port) as d:
        r = d.set_gains(K=0.30, B=-1.0e-3)
        assert r == zm.GainResult(True, "ZW_REASON_NONE", 0, f32(0.30), f32(-1.0e-3))
        s = d.status()
    assert s.gains == zm.Gains(f32(0.30), f32(-1.0e-3))
    assert s.counters == zm.Counters(accepted=1, refused=0)
    # The live ceiling at the new B is sigma K_max(B) (below k_max = 10).
    assert s.limits.K_cert == pytest.approx(POLICY["sigma"] * s.limits.K_max, rel=1e-6)
    assert s.limits.B_lo < f32(-1.0e-3) < s.limits.B_hi
    assert 0.0 < s.limits.rho < POLICY["r"]


def test_refused_pair_keeps_the_old_gains(drive_port):
    with drive(drive_port) as d:
        assert d.set_gains(K=0.30, B=-1.0e-3).accepted
        # K_max(0) = 0.3577: K = 0.40 with B = 0 is outside the stability region.
        r = d.set_gains(K=0.40, B=0.0)
        assert r == zm.GainResult(False, "ZW_REASON_UNSTABLE", 0x03, f32(0.30), f32(-1.0e-3))
        s = d.status()
    assert s.gains == zm.Gains(f32(0.30), f32(-1.0e-3))
    assert s.counters == zm.Counters(accepted=1, refused=1)
    assert s.last_refusal == zm.Refusal("ZW_REASON_UNSTABLE", 0x03)


@pytest.mark.parametrize("K, B, reason", [
    (float("nan"), 0.0, "ZW_REASON_NOT_FINITE"),
    (0.1, float("inf"), "ZW_REASON_NOT_FINITE"),
    (-0.1, 0.0, "ZW_REASON_K_BELOW_MIN"),
    (11.0, 0.0, "ZW_REASON_K_ABOVE_MAX"),
    (0.1, -0.02, "ZW_REASON_B_BELOW_MIN"),
    (0.1, 0.02, "ZW_REASON_B_ABOVE_MAX"),
])
def test_refusal_reasons_by_name(drive_port, K, B, reason):
    with drive(drive_port) as d:
        r = d.set_gains(K=K, B=B)
    assert (r.accepted, r.reason, r.exception, r.K, r.B) == (False, reason, 0x03, 0.0, 0.0)


def test_single_gain_is_judged_with_the_other(drive_port):
    with drive(drive_port) as d:
        assert d.set_gains(K=0.30, B=-1.0e-3).accepted
        r = d.set_gains(B=-1.2e-3)
        assert r == zm.GainResult(True, "ZW_REASON_NONE", 0, f32(0.30), f32(-1.2e-3))
        r = d.set_gains(K=0.2)
        assert r == zm.GainResult(True, "ZW_REASON_NONE", 0, f32(0.2), f32(-1.2e-3))
        assert d.status().counters.accepted == 3


def test_output_off_always_accepted(drive_port):
    with drive(drive_port) as d:
        assert d.set_gains(K=0.30, B=-1.0e-3).accepted
        assert d.set_gains(K=0.0, B=0.0) == zm.GainResult(True, "ZW_REASON_NONE", 0, 0.0, 0.0)


def test_step_limit(start_drive):
    port = start_drive({**PAPER_PLANT, **POLICY, "dk_max": 0.15})  # steps of 0.1 pass
    with drive(port) as d:
        r = d.set_gains(K=0.30, B=-1.0e-3)
        assert (r.accepted, r.reason, r.K) == (False, "ZW_REASON_K_STEP", 0.0)
        for K in (0.1, 0.2, 0.3):
            assert d.set_gains(K=K, B=-1.0e-3).accepted
        assert d.gains() == zm.Gains(f32(0.3), f32(-1.0e-3))


# ---------------------------------------------------------------------------------------
# The paper's example: J = 85.78e-7 kg m^2, b = 2.197e-3 N m s/rad, T = 0.02 s.
# At B = -1.36e-3 N m s/rad, K_max(B) = 0.49275 N m/rad (K_mmax = 0.4934 at B = -1.3567e-3).
# ---------------------------------------------------------------------------------------


def test_paper_example_sigma_085(start_drive):
    port = start_drive({**PAPER_PLANT, **POLICY, "sigma": 0.85})  # ceiling 0.4188
    with drive(port) as d:
        r = d.set_gains(K=0.40, B=-1.36e-3)
        assert r == zm.GainResult(True, "ZW_REASON_NONE", 0, f32(0.40), f32(-1.36e-3))
        assert d.status().limits.K_cert == pytest.approx(0.85 * 0.492754, rel=1e-5)
        r = d.set_gains(K=0.45, B=-1.36e-3)  # stable (0.45 < 0.4928), but above the fraction
        assert r == zm.GainResult(False, "ZW_REASON_ABOVE_SIGMA", 0x03, f32(0.40), f32(-1.36e-3))


def test_paper_example_sigma_08(start_drive):
    """With sigma = 0.8 the certified ceiling at B = -1.36e-3 is 0.8 x 0.49275 = 0.3942, so
    K = 0.40 is itself refused ABOVE_SIGMA (it would need sigma >= 0.812); 0.39 passes."""
    port = start_drive({**PAPER_PLANT, **POLICY, "sigma": 0.8})
    with drive(port) as d:
        for K in (0.40, 0.45):
            r = d.set_gains(K=K, B=-1.36e-3)
            assert r == zm.GainResult(False, "ZW_REASON_ABOVE_SIGMA", 0x03, 0.0, 0.0)
        r = d.set_gains(K=0.39, B=-1.36e-3)
        assert r == zm.GainResult(True, "ZW_REASON_NONE", 0, f32(0.39), f32(-1.36e-3))
        assert d.status().limits.K_cert == pytest.approx(0.8 * 0.492754, rel=1e-5)


# ---------------------------------------------------------------------------------------
# commissioning
# ---------------------------------------------------------------------------------------

# sigma 0.9 and K <= 0.45 leave K = 0.44 at B = -1.36e-3 (ceiling 0.4435), but its spectral
# radius 0.972 is above r = 0.96.
NEW_BLOCK = dict(m=85.78e-7, b=2.197e-3, T=0.02, sigma=0.9, r=0.96, k_min=0.0, k_max=0.45,
                 b_min=-2.0e-3, b_max=3.0e-3, dk_max=0.5, db_max=5e-3)


def test_commission_an_unsealed_drive(start_drive):
    port = start_drive(None)
    with drive(port) as d:
        s = d.status()
        assert not s.sealed and s.mode == "operation"
        r = d.set_gains(K=0.30, B=-1.0e-3)
        assert (r.accepted, r.reason, r.K, r.B) == (False, "ZW_REASON_NOT_SEALED", 0.0, 0.0)
        assert r.exception in (0x02, 0x03)  # regmap.h does not say which (see the report)

        c = d.commission(**NEW_BLOCK, key=TEST_KEY)
        words = []
        for key in ("m", "b", "T", "sigma", "r", "k_min", "k_max", "b_min", "b_max", "dk_max", "db_max"):
            words += zm.float_to_words(NEW_BLOCK[key])
        words += [0] * 8  # the ideal loop
        words += zm.float_to_words(NEW_BLOCK["m"]) + zm.float_to_words(NEW_BLOCK["b"])  # a point
        assert fields6(c) == (True, "ZW_REASON_NONE", 0, "done", zm.crc16_words(words), False)
        assert c.output_off and "the output is off (gains 0, 0) until set_gains" in str(c)
        s = d.status()
        assert s.sealed and s.mode == "operation" and s.gains == zm.Gains(0.0, 0.0)
        assert s.plant == zm.Plant(f32(85.78e-7), f32(2.197e-3), f32(0.02), f32(85.78e-7), f32(2.197e-3))
        assert not s.plant.ranged
        assert (s.policy.sigma, s.policy.k_max, s.policy.crc) == (f32(0.9), f32(0.45), c.crc)
        assert d.set_gains(K=0.30, B=-1.0e-3).accepted  # rho 0.846
        r = d.set_gains(K=0.44, B=-1.36e-3)
        assert r == zm.GainResult(False, "ZW_REASON_RADIUS", 0x03, f32(0.30), f32(-1.0e-3))


def test_recommission_turns_the_output_off(drive_port):
    with drive(drive_port) as d:
        assert d.set_gains(K=0.30, B=-1.0e-3).accepted
        c = d.commission(**NEW_BLOCK, key=TEST_KEY)
        assert c.accepted and c.stage == "done"
        s = d.status()
        assert s.gains == zm.Gains(0.0, 0.0)
        assert s.policy.k_max == f32(0.45)
        r = d.set_gains(K=0.46, B=-1.36e-3)
        assert (r.accepted, r.reason) == (False, "ZW_REASON_K_ABOVE_MAX")


def test_commission_bad_policy_aborts_to_the_old_block(drive_port):
    with drive(drive_port) as d:
        before = d.status()
        c = d.commission(**{**NEW_BLOCK, "sigma": 1.5}, key=TEST_KEY)
        assert (c.accepted, c.reason, c.exception, c.stage, c.aborted) == \
            (False, "ZW_REASON_BAD_POLICY", 0x03, "seal", True)
        after = d.status()
    assert after.mode == "operation" and after.sealed
    assert after.policy == before.policy and after.plant == before.plant


def test_commission_without_abort_stays_in_commissioning(drive_port):
    with drive(drive_port) as d:
        c = d.commission(**{**NEW_BLOCK, "m": -1.0}, abort_on_refusal=False, key=TEST_KEY)
        assert (c.accepted, c.reason, c.stage, c.aborted) == (False, "ZW_REASON_BAD_POLICY", "seal", False)
        s = d.status()
        assert s.mode == "commissioning" and s.gains == zm.Gains(0.0, 0.0)
        r = d.set_gains(K=0.1, B=0.0)
        assert (r.accepted, r.reason) == (False, "ZW_REASON_NOT_SEALED")
        assert d.command("ABORT") == 0
        assert d.status().mode == "operation"


def block_words(block: dict) -> list:
    """The 34 words of a certified block followed by its CRC, as written to 0x0040 (the
    loop fields from delay, vfilter, vf_param, differentiator; default the ideal loop; the
    upper ends m_hi, b_hi default to m and b, a point block, as commission writes it)."""
    words = []
    for key in ("m", "b", "T", "sigma", "r", "k_min", "k_max", "b_min", "b_max", "dk_max", "db_max"):
        words += zm.float_to_words(block[key])
    for key in ("delay", "vfilter", "vf_param", "differentiator"):
        words += zm.float_to_words(float(block.get(key, 0.0)))
    words += zm.float_to_words(float(block.get("m_hi", block["m"])))
    words += zm.float_to_words(float(block.get("b_hi", block["b"])))
    return words + [zm.crc16_words(words)]


def test_block_replaced_before_seal_fails_the_mac(raw, drive_port, monkeypatch):
    """A second client (no key) writes another valid block with its CRC between our block
    write and our SEAL (review A4 hijack): our MAC no longer matches the staged block, so
    SEAL is refused with ZW_REASON_AUTH, we abort, and the old block stays in force."""
    client, unit = raw
    ours, theirs = block_words(NEW_BLOCK), block_words({**NEW_BLOCK, "sigma": 0.7})
    assert ours[-1] != theirs[-1]
    with drive(drive_port) as d:
        before = d.status()
        command = d.command

        def rival_then(name):
            if name == "SEAL":
                rsp = client.write_registers(0x0040, theirs, **unit)
                assert not rsp.isError()
            return command(name)

        monkeypatch.setattr(d, "command", rival_then)
        c = d.commission(**NEW_BLOCK, key=TEST_KEY)
        assert (c.accepted, c.reason, c.exception, c.stage, c.aborted) == \
            (False, "ZW_REASON_AUTH", 0x03, "seal", True)
        # the UNLOCK turned the output off, and the result says so and how to set gains again
        assert c.output_off and "the output is now off: gains (0, 0)" in c.message
        assert "Drive.set_gains(K=..., B=...)" in str(c)
        s = d.status()
    assert s.sealed and s.mode == "operation"
    assert s.policy == before.policy and s.policy.crc != theirs[-1]


def test_commission_read_back_passes_when_the_rival_writes_the_same_block(raw, drive_port,
                                                                         monkeypatch):
    client, unit = raw
    ours = block_words(NEW_BLOCK)
    with drive(drive_port) as d:
        command = d.command

        def rival_then(name):
            if name == "SEAL":
                assert not client.write_registers(0x0040, ours, **unit).isError()
            return command(name)

        monkeypatch.setattr(d, "command", rival_then)
        c = d.commission(**NEW_BLOCK, key=TEST_KEY)
    assert fields6(c) == (True, "ZW_REASON_NONE", 0, "done", ours[-1], False)


def test_lying_block_with_public_docs_only_is_refused(raw, drive_port):
    """Review A3: UNLOCK1, UNLOCK2, a block that doubles the inertia with sigma = r = 1 and
    wide bounds, its correct CRC, SEAL -- everything public, no key.  The drive consents
    (this fixture turns the enable on) but SEAL is refused with ZW_REASON_AUTH, and after
    ABORT the true plant is still sealed."""
    client, unit = raw
    lie = block_words({**PAPER_PLANT, "m": 2 * 85.78e-7, "sigma": 1.0, "r": 1.0, "k_min": 0.0,
                       "k_max": 1e6, "b_min": -1e3, "b_max": 1e3, "dk_max": 1e6, "db_max": 1e3})
    for cmd in (0xC0DE, 0x5AFE):
        assert not client.write_register(zm.REG["COMMAND"], cmd, **unit).isError()
    assert not client.write_registers(0x0040, lie, **unit).isError()
    rsp = client.write_register(zm.REG["COMMAND"], 0x5EA1, **unit)
    assert rsp.isError() and rsp.exception_code == 0x03
    assert client.read_holding_registers(0x0004, count=1, **unit).registers == [29]  # AUTH
    assert not client.write_register(zm.REG["COMMAND"], 0xAB07, **unit).isError()
    with drive(drive_port) as d:
        s = d.status()
        assert s.mode == "operation" and s.plant == zm.Plant(f32(85.78e-7), f32(2.197e-3), f32(0.02),
                                                                f32(85.78e-7), f32(2.197e-3))
        r = d.set_gains(K=0.34183, B=2.876e-4)  # the review's pair, unstable on the real plant
        assert not r.accepted


def test_commissioning_is_off_by_default(start_drive):
    """Without --commissioning the drive does not consent, even to the key holder."""
    port = start_drive(commissioning=False)
    with drive(port) as d:
        c = d.commission(**NEW_BLOCK, key=TEST_KEY)
        assert (c.accepted, c.reason, c.stage) == (False, "ZW_REASON_NO_CONSENT", "unlock")
        assert d._read(zm.REG["CONSENT"], 1) == [0]
        assert d.status().mode == "operation"


def test_recorded_session_cannot_be_replayed(raw, drive_port, monkeypatch):
    """Record every write of a successful commissioning, then replay them in a new session
    (new nonce): SEAL is refused with ZW_REASON_AUTH."""
    client, unit = raw
    recorded = []
    with drive(drive_port) as d:
        write_many = d._write_many

        def recording(addr, words):
            recorded.append((addr, list(words)))
            return write_many(addr, words)

        monkeypatch.setattr(d, "_write_many", recording)
        assert d.commission(**{**NEW_BLOCK, "sigma": 0.7}, key=TEST_KEY).accepted
        monkeypatch.undo()
        assert d.commission(**NEW_BLOCK, key=TEST_KEY).accepted  # the block in force now
        before = d.status()
    assert [a for a, _ in recorded] == [0x0040, 0x0100, 0x017B, 0x01F6, 0x0090]  # block, window, MAC
    for cmd in (0xC0DE, 0x5AFE):
        assert not client.write_register(zm.REG["COMMAND"], cmd, **unit).isError()
    for addr, words in recorded:
        assert not client.write_registers(addr, words, **unit).isError()
    rsp = client.write_register(zm.REG["COMMAND"], 0x5EA1, **unit)
    assert rsp.isError() and rsp.exception_code == 0x03
    assert client.read_holding_registers(0x0004, count=1, **unit).registers == [29]
    assert not client.write_register(zm.REG["COMMAND"], 0xAB07, **unit).isError()
    with drive(drive_port) as d:
        assert d.status().policy == before.policy


def test_refusal_reason_of_another_client_is_not_taken(raw, drive_port, monkeypatch):
    """Between our refused write and our read of the last-refusal registers a second client
    is refused with another exception code: the reason is unknown, not theirs."""
    client, unit = raw
    with drive(drive_port) as d:
        write_many = d._write_many

        def then_rival_refused(addr, words):
            exc = write_many(addr, words)
            rsp = client.read_holding_registers(0x000A, count=1, **unit)  # unmapped
            assert rsp.isError() and rsp.exception_code == 0x02
            return exc

        monkeypatch.setattr(d, "_write_many", then_rival_refused)
        r = d.set_gains(K=0.45, B=-1.36e-3)  # ours: ZW_REASON_ABOVE_SIGMA, 0x03
        assert r == zm.GainResult(False, zm.REASON_UNKNOWN, 0x03, 0.0, 0.0)
        assert d.status().last_refusal == zm.Refusal("ZW_REASON_UNMAPPED", 0x02)
        # Accepted or not is decided by our own write's answer, not by their refusal.
        r = d.set_gains(K=0.30, B=-1.0e-3)
        assert r == zm.GainResult(True, "ZW_REASON_NONE", 0, f32(0.30), f32(-1.0e-3))
        # Without a rival the reason is ours.
        monkeypatch.setattr(d, "_write_many", write_many)
        r = d.set_gains(K=0.45, B=-1.36e-3)
        assert (r.accepted, r.reason, r.exception) == (False, "ZW_REASON_ABOVE_SIGMA", 0x03)


# ---------------------------------------------------------------------------------------
# errors
# ---------------------------------------------------------------------------------------


def test_drive_gone_is_a_connection_error(start_drive):
    port = start_drive()
    d = drive(port)
    d.connect()
    try:
        for proc in start_drive.procs:
            proc.terminate()
            proc.wait(timeout=5)
        with pytest.raises(ConnectionError, match=f"{LOOPBACK}:{port}"):
            d.status()
    finally:
        d.close()


# ---------------------------------------------------------------------------------------
# pymodbus as a client nobody here wrote
# ---------------------------------------------------------------------------------------


@pytest.fixture
def raw(drive_port):
    from pymodbus.client import ModbusTcpClient

    client = ModbusTcpClient(LOOPBACK, port=drive_port, timeout=TIMEOUT, retries=0)
    assert client.connect()
    try:
        yield client, {zm.unit_keyword(client.read_holding_registers): 1}
    finally:
        client.close()


def test_raw_read_of_the_head(raw):
    client, unit = raw
    rsp = client.read_holding_registers(0x0000, count=10, **unit)
    assert not rsp.isError()
    assert list(rsp.registers[:4]) == [0x5A57, 5, 0, 1]  # magic, map version 5, operation, sealed


def test_raw_bad_pair_is_exception_3(raw):
    client, unit = raw
    words = [*zm.float_to_words(0.45), *zm.float_to_words(-1.36e-3)]  # above 0.85 K_max(B)
    rsp = client.write_registers(0x0010, words, **unit)
    assert rsp.isError() and rsp.exception_code == 0x03
    back = client.read_holding_registers(0x0010, count=4, **unit)
    assert list(back.registers[:4]) == [0, 0, 0, 0]
    why = client.read_holding_registers(0x0004, count=2, **unit)
    assert list(why.registers[:2]) == [16, 0x03]  # ZW_REASON_ABOVE_SIGMA


def test_raw_half_float_is_exception_2(raw):
    client, unit = raw
    hi, lo = zm.float_to_words(0.30)
    rsp = client.write_registers(0x0010, [hi], **unit)  # 0x10, one word of K
    assert rsp.isError() and rsp.exception_code == 0x02
    rsp = client.write_register(0x0013, lo, **unit)  # 0x06, low word of B
    assert rsp.isError() and rsp.exception_code == 0x02
    why = client.read_holding_registers(0x0004, count=2, **unit)
    assert list(why.registers[:2]) == [5, 0x02]  # ZW_REASON_HALF_FLOAT
    back = client.read_holding_registers(0x0010, count=4, **unit)
    assert list(back.registers[:4]) == [0, 0, 0, 0]


def test_raw_unmapped_and_read_only(raw):
    client, unit = raw
    rsp = client.read_holding_registers(0x000A, count=1, **unit)
    assert rsp.isError() and rsp.exception_code == 0x02
    rsp = client.write_register(0x0000, 1, **unit)
    assert rsp.isError() and rsp.exception_code == 0x02
    rsp = client.read_holding_registers(0x0004, count=2, **unit)
    assert list(rsp.registers[:2]) == [4, 0x02]  # ZW_REASON_READ_ONLY


def test_raw_good_pair_then_client_reads_it(raw, drive_port):
    client, unit = raw
    words = [*zm.float_to_words(0.30), *zm.float_to_words(-1.0e-3)]
    rsp = client.write_registers(0x0010, words, **unit)
    assert not rsp.isError()
    with drive(drive_port) as d:  # a second client on the same drive
        assert d.gains() == zm.Gains(f32(0.30), f32(-1.0e-3))


# ---------------------------------------------------------------------------------------
# the loop the drive runs (map version 2)
# ---------------------------------------------------------------------------------------


def test_drive_started_with_a_delay_certifies_for_it(start_drive):
    """The paper's example pair (K = 0.40, B = -1.36e-3) passes the ideal loop (see
    test_status_of_a_fresh_drive's policy) but not a drive that applies its force one
    sample late: refused as unstable; the live limits are those of the delayed loop."""
    ideal_port = start_drive()
    port = start_drive(extra=("--delay", "1"))
    with drive(ideal_port) as d:
        ideal = d.status()
        assert d.set_gains(K=0.40, B=-1.36e-3).accepted
    with drive(port) as d:
        s = d.status()
        assert s.loop == zm.Loop(1.0, "none", s.loop.cutoff_hz, 0, "backward", 0.0)
        assert not s.loop.ideal
        assert 0 < s.limits.K_max < 0.5 * ideal.limits.K_max
        assert 0 < s.limits.K_mmax < ideal.limits.K_mmax
        assert s.limits.B_lo != s.limits.B_lo  # NaN: not computed per write (regmap.h)
        r = d.set_gains(K=0.40, B=-1.36e-3)
        assert (r.accepted, r.reason, r.exception) == (False, "ZW_REASON_UNSTABLE", 0x03)
        k = f32(0.5 * s.limits.K_cert)
        assert d.set_gains(K=k, B=0.0).accepted


def test_commission_with_a_low_pass_filter(start_drive):
    """A drive whose firmware runs a delay and a 5 Hz low-pass takes a block for that loop,
    and refuses one for the ideal loop (a certificate for a loop it does not run)."""
    port = start_drive(extra=("--delay", "1", "--velocity-filter", "lowpass:5Hz"))
    with drive(port) as d:
        c = d.commission(**NEW_BLOCK, key=TEST_KEY)
        assert (c.accepted, c.reason, c.exception) == (False, "ZW_REASON_LOOP_MISMATCH", 0x03)
        c = d.commission(**NEW_BLOCK, delay=1, velocity_filter="lowpass:5Hz", key=TEST_KEY)
        assert c.accepted
        s = d.status()
        assert (s.loop.delay, s.loop.velocity_filter, s.loop.cutoff_hz, s.loop.differentiator) == \
            (1.0, "lowpass", 5.0, "backward")
        # the pole the drive applies: exp(-2 pi f_c T) at the binary32 T, to float accuracy
        import math
        assert s.loop.pole == pytest.approx(math.exp(-2 * math.pi * 5.0 * f32(0.02)), rel=1e-6)
        assert s.policy.crc == c.crc == block_words({**NEW_BLOCK, "delay": 1, "vfilter": 1,
                                                     "vf_param": 5.0})[-1]
        assert d.set_gains(K=f32(0.5 * s.limits.K_cert), B=0.0).accepted


@pytest.mark.parametrize("loop, reason", [
    (dict(delay=1, velocity_filter=("lowpass", 30.0)), "ZW_REASON_BAD_FILTER_PARAM"),  # > 25 Hz
    (dict(velocity_filter="average:2", differentiator="tustin"), "ZW_REASON_LOOP_MISMATCH"),
    (dict(delay=2), "ZW_REASON_LOOP_MISMATCH"),  # valid, but not the firmware's (ideal) loop
])
def test_commission_refuses_a_bad_loop_with_its_reason(drive_port, loop, reason):
    with drive(drive_port) as d:
        before = d.status()
        c = d.commission(**NEW_BLOCK, **loop, key=TEST_KEY)
        assert (c.accepted, c.reason, c.exception, c.stage, c.aborted) == (False, reason, 0x03, "seal", True)
        after = d.status()
    assert after.sealed and after.mode == "operation"
    assert after.loop == before.loop and after.policy == before.policy


def test_an_old_client_cannot_seal_a_version_1_block(raw, drive_port):
    """A map-v1 client writes 22 words and the CRC at 0x0056: the write splits the DELAY
    value (refused) and a SEAL fails the CRC over 30 words."""
    client, unit = raw
    words = block_words(NEW_BLOCK)[:22]
    v1 = words + [zm.crc16_words(words)]
    for name in ("UNLOCK1", "UNLOCK2"):
        assert not client.write_register(zm.REG["COMMAND"], zm.CMD[name], **unit).isError()
    rsp = client.write_registers(0x0040, v1, **unit)
    assert rsp.isError() and rsp.exception_code == 0x02
    assert not client.write_registers(0x0040, words, **unit).isError()
    rsp = client.write_register(0x0056, v1[-1], **unit)
    assert rsp.isError() and rsp.exception_code == 0x02  # half of the DELAY float
    rsp = client.write_register(zm.REG["COMMAND"], zm.CMD["SEAL"], **unit)
    assert rsp.isError() and rsp.exception_code == 0x03
    with drive(drive_port) as d:
        assert d.status().last_refusal == zm.Refusal("ZW_REASON_CRC", 0x03)
        assert d.command("ABORT") == 0


def test_cdab_drive_is_spoken(start_drive):
    """zwidth-drive --word-order cdab: the client follows WORD_ORDER (word_order="auto", or
    "cdab"), so status, set_gains and commission read and write what an ABCD drive does;
    asking for the other order is refused, not misread."""
    abcd, cdab = start_drive(), start_drive(extra=("--word-order", "cdab"))
    with drive(abcd) as a, drive(cdab) as c, drive(cdab, word_order="cdab") as c2:
        sa, sc = a.status(), c.status()
        assert sc == sa and sc.policy.crc == sa.policy.crc and sc.limits.K_mmax == pytest.approx(0.493379, rel=1e-5)
        for d in (a, c2):
            r = d.set_gains(K=0.39, B=-1.36e-3)
            assert r.accepted and (r.K, r.B) == (f32(0.39), f32(-1.36e-3))
            assert d.gains() == zm.Gains(f32(0.39), f32(-1.36e-3))
        assert c.status().limits == a.status().limits and c.status().counters == a.status().counters
        r = c.set_gains(K=0.45)  # above sigma K_max(B): refused, with the reason, in CDAB too
        assert (r.accepted, r.reason, r.K) == (False, "ZW_REASON_ABOVE_SIGMA", f32(0.39))
        res = c.commission(**NEW_BLOCK, key=TEST_KEY)  # CRC and MAC over the ABCD words
        assert res.accepted, res
        assert c.status().policy == zm.Policy(*(f32(NEW_BLOCK[k]) for k in (
            "sigma", "r", "k_min", "k_max", "b_min", "b_max", "dk_max", "db_max")), res.crc)
        assert res.crc == a.commission(**NEW_BLOCK, key=TEST_KEY).crc  # one CRC, either order
    with pytest.raises(zm.DriveError, match=r"low word first \(CDAB\); this client was asked for ABCD"):
        drive(cdab, word_order="abcd").connect()
    with pytest.raises(zm.DriveError, match=r"high word first \(ABCD\)"):
        drive(abcd, word_order="cdab").connect()
    with pytest.raises(ValueError, match="word_order"):
        zm.Drive(LOOPBACK, abcd, word_order="badc")


def test_save_then_restart_restores(start_drive, tmp_path):
    """Drive.save(): the drive stores its block and gains; a drive started again on the same
    state file has them back (RESTORE_SOURCE 1)."""
    from mb_support import stop

    state = tmp_path / "state.bin"
    port = start_drive(extra=("--state-file", str(state)))
    with drive(port) as d:
        assert d.set_gains(K=0.39, B=-1.36e-3).accepted
        r = d.save()
        crc = d.status().policy.crc
    assert isinstance(r, zm.SaveResult) and r.accepted and r.reason == "ZW_REASON_NONE"
    assert (r.crc, r.K, r.B) == (crc, f32(0.39), f32(-1.36e-3))
    assert str(r) == (f"saved: the drive stored its sealed block (CRC 0x{crc:04X}) and the active gains "
                      f"K = {f32(0.39):.9g}, B = {f32(-1.36e-3):.9g}; they are restored at power-up")
    stop(start_drive.procs[-1])
    port = start_drive(extra=("--state-file", str(state)))
    with drive(port) as d:
        assert d.gains() == zm.Gains(f32(0.39), f32(-1.36e-3))
        assert d._read(zm.REG["RESTORE_SOURCE"], 1) == [1]


def test_save_without_storage_says_why(drive_port):
    with drive(drive_port) as d:
        r = d.save()
    assert (r.accepted, r.reason, r.exception) == (False, "ZW_REASON_NO_STORAGE", 0x03)
    assert "nothing was saved" in r.message and "--state-file" in r.message


def test_wrong_key_commission_says_the_output_is_off(drive_port):
    with drive(drive_port) as d:
        assert d.set_gains(K=0.39, B=-1.36e-3).accepted
        c = d.commission(**NEW_BLOCK, key=bytes(32))
        assert (c.accepted, c.reason, c.stage, c.aborted, c.output_off) == \
            (False, "ZW_REASON_AUTH", "seal", True, True)
        assert c.message.startswith("commissioning refused at seal: ZW_REASON_AUTH (exception 3); "
                                    "ABORT sent: the last sealed block is back; the output is now off")
        assert d.gains() == zm.Gains(0.0, 0.0)  # what the message says


def test_limits_names_match_k_max_elsewhere(drive_port):
    """Limits.K_max, K_cert, K_mmax, ... as zwidth.Device and zwidth-tune's JSON name them;
    the old lowercase names still read, with a DeprecationWarning."""
    with drive(drive_port) as d:
        lim = d.status().limits
    assert [f for f in lim.__dataclass_fields__] == ["K_max", "K_cert", "B_lo", "B_hi", "K_mmax",
                                                     "B_at_K_mmax", "rho", "delta"]
    for old, new in (("k_max", "K_max"), ("k_cert", "K_cert"), ("k_mmax", "K_mmax"),
                     ("b_lo", "B_lo"), ("b_hi", "B_hi"), ("b_at_k_mmax", "B_at_K_mmax")):
        with pytest.warns(DeprecationWarning, match=f"Limits.{old} is deprecated: use Limits.{new}"):
            assert getattr(lim, old) == getattr(lim, new)
    with pytest.raises(AttributeError):
        lim.k_max = 1.0  # type: ignore[misc]


# ---------------------------------------------------------------------------------------
# plant ranges (map version 4)
# ---------------------------------------------------------------------------------------

J_PAPER, B_PAPER = PAPER_PLANT["m"], PAPER_PLANT["b"]
# a box inside the drive's nameplate tolerance (5 %); ranges need r = 1 (drive: --max-r 1)
BOX_BLOCK = dict(m=(0.97 * J_PAPER, 1.04 * J_PAPER), b=f"{0.98 * B_PAPER!r}:{1.03 * B_PAPER!r}",
                 T=0.02, sigma=0.8, r=1.0, k_min=0.0, k_max=10.0, b_min=-0.01, b_max=0.01,
                 dk_max=1.0, db_max=0.01)


def test_commission_a_ranged_block(start_drive):
    """A box of plants commissioned through the client without a certificate (map version 4's
    way): the drive shows the ranges, its live limits are box bounds (NaN where it has no
    box form), and its search judges writes for the box."""
    port = start_drive(extra=("--max-r", "1"))
    with drive(port, timeout=30.0) as d:  # a ranged SEAL certifies over the box (modbus.py)
        c = d.commission(**BOX_BLOCK, key=TEST_KEY, certificate=None)
        assert (c.accepted, c.reason, c.stage, c.certificate) == (True, "ZW_REASON_NONE", "done", None)
        s = d.status()
        assert s.staircase is None
        assert s.version == 5 and s.sealed and s.mode == "operation"
        assert s.plant == zm.Plant(f32(0.97 * J_PAPER), f32(0.98 * B_PAPER), f32(0.02),
                                   f32(1.04 * J_PAPER), f32(1.03 * B_PAPER))
        assert s.plant.ranged
        lim = s.limits
        assert math.isnan(lim.B_lo) and math.isnan(lim.B_hi) and math.isnan(lim.rho)
        assert 0.0 < lim.K_cert <= 0.8 * lim.K_max * (1 + 1e-6) and lim.K_mmax > 0.0
        # K_CERT at the current B is accepted; 0.95 K_MAX is stable for every plant (below
        # the box's infimum) but above sigma K_max, and K_MAX x 1.3 unstable somewhere
        r = d.set_gains(K=lim.K_cert, B=0.0)
        assert r.accepted, r.reason
        r = d.set_gains(K=0.95 * lim.K_max, B=0.0)
        assert (r.accepted, r.reason) == (False, "ZW_REASON_ABOVE_SIGMA")
        r = d.set_gains(K=1.3 * lim.K_max, B=0.0)
        assert (r.accepted, r.reason) == (False, "ZW_REASON_UNSTABLE")
        # the paper's example at B = -1.36e-3: within sigma K_max of the lighter plants, not of
        # the box (K_max falls with J here), so refused, and the gains stay
        r = d.set_gains(K=0.40, B=-1.36e-3)
        assert not r.accepted and r.reason in ("ZW_REASON_ABOVE_SIGMA", "ZW_REASON_UNSTABLE")
        assert d.gains() == zm.Gains(f32(lim.K_cert), 0.0)


def test_commission_a_ranged_block_with_its_certificate(start_drive):
    """Map version 5: commission() builds the box certificate in the drive's precision and
    sends it; the drive holds exactly its words, shows its staircase, and every write is a
    lookup.  A certificate that claims more than it proves is refused at SEAL by name, and
    the block in force stays."""
    port = start_drive(extra=("--max-r", "1"))
    with drive(port, timeout=30.0) as d:
        c = d.commission(**BOX_BLOCK, key=TEST_KEY)
        assert (c.accepted, c.reason, c.stage) == (True, "ZW_REASON_NONE", "done"), c.message
        cert = c.certificate
        assert cert is not None and "box certificate" in c.message
        assert cert.precision == {4: "float", 8: "double"}[d._read(zm.REG["PRECISION"], 1)[0]]
        assert d._box_cert_wire(d._read_window(zm.REG["BOX_CERT"], zm.BOX_CERT_WORDS)) == cert.words()
        s = d.status()
        assert s.staircase == zm.Staircase(tuple(map(f32, cert.B)), tuple(map(f32, cert.K)), len(cert.nodes))
        assert BOX_BLOCK["b_min"] <= cert.B[0] < cert.B[-1] <= BOX_BLOCK["b_max"]
        B = 0.5 * (cert.B[5] + cert.B[6])
        level = s.staircase.level(B)
        assert level == cert.level(B) > 0.0
        r = d.set_gains(K=0.79 * level, B=B)
        assert r.accepted, r.reason
        lim = d.status().limits
        assert lim.K_max == f32(level) and lim.B_lo <= B <= lim.B_hi
        r = d.set_gains(K=0.81 * level, B=B)
        assert (r.accepted, r.reason) == (False, "ZW_REASON_ABOVE_SIGMA")
        r = d.set_gains(K=0.1 * level, B=cert.B[-1] + 1e-3)
        assert (r.accepted, r.reason) == (False, "ZW_REASON_OUTSIDE_CERT")
        # a forged certificate: one level raised by half (the MAC is right: the proof is not)
        forged = dataclasses.replace(cert, K=tuple(k * (1.5 if i == 3 else 1.0) for i, k in enumerate(cert.K)))
        r2 = d.commission(**{**BOX_BLOCK, "sigma": 0.7}, key=TEST_KEY, certificate=forged)
        assert (r2.accepted, r2.reason, r2.stage, r2.aborted) == (False, "ZW_REASON_BOX_CERT", "seal", True)
        s = d.status()
        assert s.policy.sigma == f32(0.8) and s.staircase is not None and s.staircase.K == tuple(map(f32, cert.K))
        # a certificate needs ranges
        with pytest.raises(ValueError, match="need plant ranges"):
            d.commission(**{**BOX_BLOCK, "m": J_PAPER, "b": B_PAPER}, key=TEST_KEY, certificate=cert)


def test_ranged_block_with_a_radius_bound_is_refused(start_drive):
    port = start_drive(extra=("--max-r", "1"))
    with drive(port) as d:
        c = d.commission(**{**BOX_BLOCK, "r": 0.999}, key=TEST_KEY)
        assert (c.accepted, c.reason, c.stage, c.aborted) == (False, "ZW_REASON_BOX_RADIUS", "seal", True)
        assert not d.status().plant.ranged  # the power-up block is back


def test_range_arguments_are_checked():
    with pytest.raises(ValueError, match="m must be"):
        zm.Drive(LOOPBACK, 1).commission(**{**BOX_BLOCK, "m": (1.0, 2.0, 3.0)}, key=TEST_KEY)
    with pytest.raises(ValueError, match="b must be"):
        zm.Drive(LOOPBACK, 1).commission(**{**BOX_BLOCK, "b": "1:2:3"}, key=TEST_KEY)
