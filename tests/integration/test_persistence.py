# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""zwidth-drive --state-file: applying and saving gains are separate; saved settings
survive a restart; a corrupted image (truncated, a bit flipped, in both copies) applies
nothing uncertified: the last good copy, or the power-up block with the gains off, and
the reason readable in RESTORE_REASON."""
from __future__ import annotations

import pytest

from test_commission import PAPER_OPTS, status
from zwmb_harness import E, ModbusException, f32, start_drive  # noqa: F401 (fixture)

SAVE = 0x5A7E
CMD = E["ZW_REG_COMMAND"]


def restore_regs(d):
    with d.client() as c:
        return c.read(E["ZW_REG_RESTORE_SOURCE"], 2)


def test_saved_settings_survive_a_restart_and_bad_images_apply_nothing(start_drive, tmp_path):
    state = tmp_path / "drive.state"
    d = start_drive("--state-file", str(state))
    p = d.tune("commission", *PAPER_OPTS, "--sigma", "0.9")
    assert p.returncode == 0, p.stderr
    with d.client() as c:
        c.set_gains(0.40, -1.36e-3)          # applied ...
        assert not state.exists()            # ... not saved
        c.write1(CMD, SAVE)
        first = state.read_bytes()
        c.set_gains(0.30, -1.0e-3)
        c.write1(CMD, SAVE)                  # the first copy becomes drive.state.prev
    assert (tmp_path / "drive.state.prev").read_bytes() == first
    assert len(first) == 734 and first[:6] == b"ZWNV\x00\x03"
    assert state.stat().st_mode & 0o077 == 0
    d.stop()

    d = start_drive("--state-file", str(state))  # restart: block and gains back
    s = status(d)
    assert s["cert"]["sigma"] == f32(0.9) and s["gains"] == {"K": f32(0.30), "B": f32(-1.0e-3)}
    assert restore_regs(d) == [1, 0]
    d.stop()

    good = state.read_bytes()
    state.write_bytes(good[:-1])  # truncated: the last good copy
    d = start_drive("--state-file", str(state))
    s = status(d)
    assert s["cert"]["sigma"] == f32(0.9) and s["gains"] == {"K": f32(0.40), "B": f32(-1.36e-3)}
    assert restore_regs(d) == [2, E["ZW_REASON_IMAGE_FORMAT"]]
    d.stop()

    bad = bytearray(good)
    bad[20] ^= 0x04
    state.write_bytes(bytes(bad))
    prev = bytearray(first)
    prev[70] ^= 0x80  # a bit of the saved K
    (tmp_path / "drive.state.prev").write_bytes(bytes(prev))
    d = start_drive("--state-file", str(state))  # both bad: the power-up block, gains off
    s = status(d)
    assert s["cert"]["sigma"] == f32(0.8) and s["gains"] == {"K": 0.0, "B": 0.0}
    assert restore_regs(d) == [0, E["ZW_REASON_IMAGE_CRC"]]
    assert "stored settings refused (ZW_REASON_IMAGE_CRC)" in d.log()


def test_save_needs_consent_and_storage(start_drive, tmp_path):
    d = start_drive(commissioning=False)  # no --state-file either
    with d.client() as c:
        with pytest.raises(ModbusException) as ei:
            c.write1(CMD, SAVE)
        assert ei.value.code == 3 and c.refusal() == ("ZW_REASON_NO_CONSENT", 3)
    d2 = start_drive()
    with d2.client() as c:
        with pytest.raises(ModbusException) as ei:
            c.write1(CMD, SAVE)
        assert ei.value.code == 3 and c.refusal() == ("ZW_REASON_NO_STORAGE", 3)
