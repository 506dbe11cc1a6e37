# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zwidth-tune against zwidth-drive over Modbus TCP: status, verdicts, exit statuses."""
from __future__ import annotations

import json
import signal
import socket
import subprocess

from zwmb_harness import DRIVE, TUNE, E, LOOPBACK, f32, run_tune, drive, start_drive  # noqa: F401 (fixtures)

PAPER = dict(m=85.78e-7, b=2.197e-3, T=0.02, sigma=0.8, r=0.999, k_min=0.0, k_max=10.0,
             b_min=-0.01, b_max=0.01, dk_max=1.0, db_max=0.01)


def loads(text):
    """zwidth-tune's JSON; its numbers are binary32 registers printed to 9 digits, which
    read back into binary32 exactly."""
    return json.loads(text, parse_float=lambda t: f32(float(t)))


def status(drive):
    p = drive.tune("status", "--json")
    assert p.returncode == 0, p.stderr
    return loads(p.stdout)


def set_gains(drive, *args):
    p = drive.tune("set", *args, "--json")
    assert p.returncode in (0, 3), (p.returncode, p.stdout, p.stderr)
    return p.returncode, loads(p.stdout)


def test_help_and_usage_errors():
    for exe in (DRIVE, TUNE):
        p = subprocess.run([str(exe), "--help"], capture_output=True, text=True, timeout=5)
        assert p.returncode == 0 and "Exit status" in p.stdout
        p = subprocess.run([str(exe), "--no-such-option"], capture_output=True, text=True, timeout=5)
        assert p.returncode == 2 and "unknown option" in p.stderr
    p = subprocess.run([str(TUNE)], capture_output=True, text=True, timeout=5)
    assert p.returncode == 2 and "missing command" in p.stderr
    p = subprocess.run([str(TUNE), "set"], capture_output=True, text=True, timeout=5)
    assert p.returncode == 2 and "--K" in p.stderr
    p = subprocess.run([str(TUNE), "commission", "--m", "1e-5"], capture_output=True, text=True, timeout=5)
    assert p.returncode == 2 and "--sigma" in p.stderr
    p = subprocess.run([str(DRIVE), "--port", "99999"], capture_output=True, text=True, timeout=5)
    assert p.returncode == 2 and "--port" in p.stderr
    p = subprocess.run([str(DRIVE), "--host", "localhost"], capture_output=True, text=True, timeout=5)
    assert p.returncode == 2 and "IPv4" in p.stderr


def test_connection_error_exits_2():
    s = socket.socket()
    s.bind((LOOPBACK, 0))
    port = s.getsockname()[1]
    s.close()  # nothing listens there now
    p = run_tune("--port", str(port), "--timeout", "300", "status", timeout=10)
    assert p.returncode == 2 and "cannot connect" in p.stderr


def test_bad_certified_block_refused_at_startup():
    p = subprocess.run([str(DRIVE), "--host", LOOPBACK, "--port", "0", "--sigma", "1.5"],
                       capture_output=True, text=True, timeout=5)
    assert p.returncode == 2 and "ZW_REASON_BAD_POLICY" in p.stderr


def test_status_of_a_fresh_drive(drive):
    s = status(drive)
    assert s["magic"] == 0x5A57 and s["version"] == 5
    assert s["mode"] == "operation" and s["sealed"] is True
    assert s["gains"] == {"K": 0.0, "B": 0.0}
    for k, v in PAPER.items():
        assert s["cert"][k] == f32(v), k
    assert s["accepted"] == 0 and s["refused"] == 0
    assert s["last_refusal"]["reason"] == "ZW_REASON_NONE"
    # live limits of the paper's drive (K_mmax = 0.4934 at B = -1.357e-3; B = 0: K < 0.3577)
    assert abs(s["live"]["K_mmax"] - 0.493379) < 1e-5
    assert abs(s["live"]["B_at_K_mmax"] + 1.3567e-3) < 1e-7
    assert abs(s["live"]["K_max"] - 0.357709) < 1e-5
    assert abs(s["live"]["delta"] - 5.12241) < 1e-4
    text = drive.tune("status")
    assert text.returncode == 0
    assert "sealed" in text.stdout and "K_mmax = 0.493379" in text.stdout


def test_accepted_pair_inside_limits(drive):
    rc, v = set_gains(drive, "--K", "0.2", "--B", "-5e-4")
    assert rc == 0 and v["verdict"] == "accepted"
    assert (v["K"], v["B"]) == (f32(0.2), f32(-5e-4))
    s = status(drive)
    assert s["gains"] == {"K": f32(0.2), "B": f32(-5e-4)} and s["accepted"] == 1
    # the live limits follow the gains: B interval at K = 0.2, K ceiling at B = -5e-4
    assert s["live"]["B_lo"] < f32(-5e-4) < s["live"]["B_hi"]
    assert abs(s["live"]["K_max"] - 0.407709) < 1e-5
    p = drive.tune("set", "--K", "0.25")  # one float alone: judged with the active B
    assert p.returncode == 0 and p.stdout.startswith("accepted") and "K = 0.25" in p.stdout
    assert "refused" not in drive.log()


def test_pair_outside_refused_and_old_gains_stay(drive):
    assert set_gains(drive, "--K", "0.2", "--B", "-5e-4")[0] == 0
    cases = [
        (("--K", "11", "--B", "0"), "ZW_REASON_K_ABOVE_MAX"),
        (("--K", "-0.1", "--B", "0"), "ZW_REASON_K_BELOW_MIN"),
        (("--K", "0.2", "--B", "0.02"), "ZW_REASON_B_ABOVE_MAX"),
        (("--K", "1.5", "--B", "0"), "ZW_REASON_K_STEP"),          # |dK| = 1.3 > 1 (checked before stability)
        (("--K", "0.3", "--B", "0.004"), "ZW_REASON_UNSTABLE"),    # B above the stable interval
        (("--K", "0.35", "--B", "-5e-4"), "ZW_REASON_ABOVE_SIGMA"),  # stable, but > 0.8 K_max(B)
    ]
    for args, reason in cases:
        rc, v = set_gains(drive, *args)
        assert rc == 3, (args, v)
        assert v["verdict"] == "refused" and v["reason"] == reason and v["exception"] == 3, (args, v)
        assert (v["K"], v["B"]) == (f32(0.2), f32(-5e-4)), (args, v)
    s = status(drive)
    assert s["gains"] == {"K": f32(0.2), "B": f32(-5e-4)}
    assert s["accepted"] == 1 and s["refused"] == len(cases)
    assert s["last_refusal"] == {"reason": "ZW_REASON_ABOVE_SIGMA", "reason_code": 16,
                                 "exception": 3, "exception_name": "ILLEGAL_DATA_VALUE"}
    p = drive.tune("set", "--K", "11", "--B", "0")
    assert p.returncode == 3
    assert p.stdout.startswith("refused: ZW_REASON_K_ABOVE_MAX (exception 0x03")
    # one log line per refused request, with the reason and the exception
    lines = [l for l in drive.log().splitlines() if "refused" in l]
    assert len(lines) == len(cases) + 1
    assert "ZW_REASON_UNSTABLE (exception 0x03 ILLEGAL_DATA_VALUE)" in lines[4]


def test_paper_pair_sigma_08(drive):
    """The paper's drive with sigma 0.8.  K_max(-1.36e-3) = 0.49275, so the certified
    ceiling is 0.8 x 0.49275 = 0.39420: K = 0.39 is accepted, and both K = 0.40 and
    K = 0.45 (stable: below K_max) are refused ABOVE_SIGMA."""
    s = status(drive)
    rc, v = set_gains(drive, "--K", "0.39", "--B", "-1.36e-3")
    assert rc == 0, v
    s = status(drive)
    assert abs(s["live"]["K_max"] - 0.492754) < 1e-5
    assert abs(s["live"]["K_cert"] - 0.8 * 0.492754) < 1e-5
    for K in ("0.40", "0.45"):
        rc, v = set_gains(drive, "--K", K, "--B", "-1.36e-3")
        assert rc == 3 and v["reason"] == "ZW_REASON_ABOVE_SIGMA" and v["exception"] == 3, v
        assert (v["K"], v["B"]) == (f32(0.39), f32(-1.36e-3))


def test_paper_pair_sigma_085(start_drive):
    """With sigma 0.85 the ceiling at B = -1.36e-3 is 0.41884: K = 0.40 is accepted and
    K = 0.45 refused ABOVE_SIGMA."""
    d = start_drive("--sigma", "0.85")
    rc, v = set_gains(d, "--K", "0.40", "--B", "-1.36e-3")
    assert rc == 0 and (v["K"], v["B"]) == (f32(0.40), f32(-1.36e-3)), v
    rc, v = set_gains(d, "--K", "0.45", "--B", "-1.36e-3")
    assert rc == 3 and v["reason"] == "ZW_REASON_ABOVE_SIGMA" and v["exception"] == 3, v


def test_nan_refused_0x03(drive):
    rc, v = set_gains(drive, "--K", "nan", "--B", "0")
    assert rc == 3 and v["reason"] == "ZW_REASON_NOT_FINITE" and v["exception"] == 3
    rc, v = set_gains(drive, "--B", "inf")
    assert rc == 3 and v["reason"] == "ZW_REASON_NOT_FINITE"
    assert status(drive)["gains"] == {"K": 0.0, "B": 0.0}


def test_unsealed_drive_refuses_gains(start_drive):
    d = start_drive("--unsealed")
    s = status(d)
    assert s["sealed"] is False and s["live"]["K_max"] is None  # NaN: no plant
    rc, v = set_gains(d, "--K", "0.1", "--B", "0")
    assert rc == 3 and v["reason"] == "ZW_REASON_NOT_SEALED" and v["exception"] == 2


def test_sigint_stops_cleanly(start_drive):
    d = start_drive("--simulate")
    assert d.stop(signal.SIGINT) == 0


# ---------------------------------------------------------------------------------------
# the loop the drive runs (map version 2)
# ---------------------------------------------------------------------------------------

PAPER_POLICY = ["--m", "85.78e-7", "--b", "2.197e-3", "--T", "0.02", "--sigma", "0.8",
                "--r", "0.999", "--k-min", "0", "--k-max", "10", "--b-min", "-0.01",
                "--b-max", "0.01", "--dk-max", "1", "--db-max", "0.01"]


def test_drive_with_delay_1_certifies_for_its_loop(start_drive):
    """zwidth-drive --delay 1: the pair (0.30, -1.0e-3), accepted by the ideal
    drive, is refused as unstable; status shows the loop and the lower limits."""
    ideal = start_drive()
    d = start_drive("--delay", "1")
    rc, v = set_gains(ideal, "--K", "0.30", "--B", "-1.0e-3")
    assert rc == 0 and v["verdict"] == "accepted"
    rc, v = set_gains(d, "--K", "0.30", "--B", "-1.0e-3")
    assert rc == 3 and v["reason"] == "ZW_REASON_UNSTABLE" and v["exception"] == 3
    s, s0 = status(d), status(ideal)
    assert (s["cert"]["delay"], s["cert"]["vfilter"], s["cert"]["differentiator"]) == (1.0, 0.0, 0.0)
    assert 0 < s["live"]["K_max"] < 0.5 * s0["live"]["K_max"]
    assert 0 < s["live"]["K_mmax"] < s0["live"]["K_mmax"]
    p = d.tune("status")
    assert p.returncode == 0 and "loop       : delay 1, no filter, backward difference" in p.stdout
    k = s["live"]["K_cert"]
    rc, v = set_gains(d, "--K", repr(0.5 * k), "--B", "0")
    assert rc == 0, v


def test_commission_with_delay_and_low_pass(start_drive):
    d = start_drive("--unsealed", "--delay", "1", "--velocity-filter", "lowpass:5Hz")
    # a block for the ideal loop: not the loop this firmware runs
    p = d.tune("commission", *PAPER_POLICY)
    assert p.returncode == 3 and "ZW_REASON_LOOP_MISMATCH" in p.stdout + p.stderr, (p.stdout, p.stderr)
    p = d.tune("commission", *PAPER_POLICY, "--delay", "1", "--velocity-filter", "lowpass:5Hz",
               "--differentiator", "backward")
    assert p.returncode == 0, (p.stdout, p.stderr)
    assert "loop       : delay 1, low-pass 5 Hz (pole 0.533488)" in p.stdout
    s = status(d)
    assert (s["cert"]["delay"], s["cert"]["vfilter"], s["cert"]["vf_param"]) == (1.0, 1.0, 5.0)
    # a bad loop: refused at SEAL with its reason, the block in force kept
    p = d.tune("commission", *PAPER_POLICY, "--velocity-filter", "lowpass:30Hz")  # > Nyquist
    assert p.returncode == 3 and "ZW_REASON_BAD_FILTER_PARAM" in p.stdout + p.stderr, (p.stdout, p.stderr)
    assert status(d)["cert"]["vf_param"] == 5.0


def test_loop_options_are_checked():
    for opts, msg in ((["--delay", "9"], "--delay"), (["--velocity-filter", "lowpass:0"], "--velocity-filter"),
                      (["--velocity-filter", "average:17"], "average"), (["--velocity-filter", "bessel"], "--velocity-filter"),
                      (["--differentiator", "forward"], "--differentiator")):
        for exe, extra in ((DRIVE, ["--port", "0"]), (TUNE, ["commission", *PAPER_POLICY])):
            p = subprocess.run([str(exe), *extra, *opts], capture_output=True, text=True, timeout=5)
            assert p.returncode == 2 and msg in p.stderr, (exe, opts, p.stderr)
    # a loop the drive refuses at power-up: its reason, exit 2
    p = subprocess.run([str(DRIVE), "--host", LOOPBACK, "--port", "0", "--velocity-filter", "average:2",
                        "--differentiator", "tustin"], capture_output=True, text=True, timeout=20)
    assert p.returncode == 2 and "ZW_REASON_LOOP_NEVER_STABLE" in p.stderr


# ---------------------------------------------------------------------------------------
# save, CDAB, a refused commissioning (issue 24)
# ---------------------------------------------------------------------------------------

def test_save_then_restart_restores(start_drive, tmp_path):
    """`zwidth-tune save` stores the sealed block and the gains; a drive started again on
    that state file has both back."""
    state = tmp_path / "drive.state"
    d = start_drive("--state-file", str(state))
    assert set_gains(d, "--K", "0.39", "--B", "-1.36e-3")[0] == 0
    crc = status(d)["cert"]["crc"]
    p = d.tune("save")
    assert p.returncode == 0, (p.stdout, p.stderr)
    assert p.stdout == (f"saved: the drive stored its sealed block (CRC 0x{crc:04X}) and the active "
                        f"gains K = 0.389999986, B = -0.00135999999; they are restored at power-up\n")
    assert state.stat().st_size == 734
    p = d.tune("save", "--json")
    assert p.returncode == 0 and loads(p.stdout) == {"verdict": "saved", "crc": crc, "K": f32(0.39),
                                                     "B": f32(-1.36e-3)}
    d.stop()
    d = start_drive("--state-file", str(state))
    s = status(d)
    assert s["gains"] == {"K": f32(0.39), "B": f32(-1.36e-3)} and s["cert"]["crc"] == crc


def test_save_refused_says_why(drive):
    p = drive.tune("save")
    assert p.returncode == 3
    assert p.stdout == ("refused: ZW_REASON_NO_STORAGE (exception 0x03 ILLEGAL_DATA_VALUE); nothing was "
                        "saved\nthe drive has no non-volatile storage (zwidth-drive --state-file PATH)\n")
    p = drive.tune("save", "--json")
    assert p.returncode == 3 and loads(p.stdout)["reason"] == "ZW_REASON_NO_STORAGE"


def test_cdab_drive_round_trip(start_drive):
    """zwidth-drive --word-order cdab: zwidth-tune follows WORD_ORDER; set and status give what
    they give on an ABCD drive, and a commissioning there seals the same CRC."""
    a, c = start_drive(), start_drive("--word-order", "cdab")
    for d in (a, c):
        assert set_gains(d, "--K", "0.39", "--B", "-1.36e-3") == (0, {"verdict": "accepted", "K": f32(0.39),
                                                                      "B": f32(-1.36e-3), "requests": 1})
        assert set_gains(d, "--K", "0.45")[1]["reason"] == "ZW_REASON_ABOVE_SIGMA"
    assert status(c) == status(a)
    crcs = []
    for d in (a, c):
        p = d.tune("commission", "--paper-defaults", "--sigma", "0.85", "--json")
        assert p.returncode == 0, (p.stdout, p.stderr)
        crcs.append(loads(p.stdout)["crc"])
    assert crcs[0] == crcs[1] == status(c)["cert"]["crc"]
    assert status(c)["cert"]["sigma"] == f32(0.85)
    p = c.tune("--word-order", "abcd", "status")
    assert p.returncode == 2 and "low word first (CDAB)" in p.stderr


def test_commission_refused_at_seal_says_the_output_is_off(start_drive, tmp_path):
    from zwmb_harness import write_key

    d = start_drive()
    assert set_gains(d, "--K", "0.39", "--B", "-1.36e-3")[0] == 0
    wrong = write_key(tmp_path / "wrong.key", "00" * 32)
    p = d.tune("commission", "--paper-defaults", "--key-file", str(wrong))
    assert p.returncode == 3
    lines = p.stdout.splitlines()
    assert lines[0].startswith("refused at seal: ZW_REASON_AUTH (exception 0x03 ILLEGAL_DATA_VALUE); "
                               "we sent ABORT; the drive is now in operation, sealed block CRC 0x")
    assert lines[-1] == ("the output is now off: gains K = 0, B = 0 (the UNLOCK turned it off; the "
                         "refusal and ABORT do not bring the old gains back); set gains again with "
                         "zwidth-tune set --K K --B B")
    assert status(d)["gains"] == {"K": 0.0, "B": 0.0}  # as it says
