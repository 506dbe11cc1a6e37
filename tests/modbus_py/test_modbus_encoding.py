# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""zwidth.modbus without a server: float and counter encoding, CRC-16/MODBUS, the tables
restated from regmap.h (checked against the header), argument errors."""
from __future__ import annotations

import ctypes
import math
import re
import struct

import pytest

from mb_support import BUILD_DIR, HEADERS, LOOPBACK, REPO, TEST_KEY, free_port, write_key
from zwidth import modbus as zm

# ---------------------------------------------------------------------------------------
# The header, parsed here (the module itself parses nothing at run time)
# ---------------------------------------------------------------------------------------

HEADER_TEXT = "".join(h.read_text() for h in HEADERS)


def header_enum(typedef: str) -> dict:
    """NAME -> value of a `typedef enum <typedef> { ... }` block."""
    m = re.search(r"typedef enum %s \{(.*?)\}" % typedef, HEADER_TEXT, re.S)
    assert m, typedef
    body = re.sub(r"/\*.*?\*/", "", m.group(1), flags=re.S)
    return {name: int(value, 0) for name, value in re.findall(r"(\w+)\s*=\s*(0x[0-9A-Fa-f]+|\d+)", body)}


def header_anon_enum_with(first: str) -> dict:
    """NAME -> value of the anonymous `enum { ... }` that contains `first`."""
    for m in re.finditer(r"enum \{(.*?)\}", HEADER_TEXT, re.S):
        body = re.sub(r"/\*.*?\*/", "", m.group(1), flags=re.S)
        if first in body:
            return {n: int(v, 0) for n, v in re.findall(r"(\w+)\s*=\s*(0x[0-9A-Fa-f]+|\d+)", body)}
    raise AssertionError(first)


def header_define(name: str) -> int:
    m = re.search(r"#define %s (0x[0-9A-Fa-f]+|\d+)u?" % name, HEADER_TEXT)
    assert m, name
    return int(m.group(1), 0)


def test_reason_names_match_the_header():
    assert {v: k for k, v in header_enum("zw_reason").items()} == zm.REASONS


def test_register_addresses_match_the_header():
    regs = header_anon_enum_with("ZW_REG_MAGIC")
    assert {k[len("ZW_REG_"):]: v for k, v in regs.items()} == zm.REG


def test_commands_and_constants_match_the_header():
    cmds = {name: header_define("ZW_CMD_" + name) for name in ("UNLOCK1", "UNLOCK2", "SEAL", "ABORT", "SAVE")}
    assert cmds == zm.CMD
    assert header_define("ZW_REGMAP_MAGIC") == zm.MAGIC
    assert header_define("ZW_REGMAP_VERSION") == zm.MAP_VERSION
    assert header_define("ZW_CERT_WORDS") == zm.CERT_WORDS
    assert header_define("ZW_AUTH_NONCE_WORDS") == zm.AUTH_NONCE_WORDS
    assert header_define("ZW_AUTH_MAC_WORDS") == zm.AUTH_MAC_WORDS
    codes = header_enum("zw_mb_exception")
    assert sorted(codes.values()) == sorted(zm.EXCEPTIONS)


# The exception names of the Modbus Application Protocol specification V1.1b3, section 7.
SPEC_EXCEPTIONS = {0x01: "ILLEGAL_FUNCTION", 0x02: "ILLEGAL_DATA_ADDRESS",
                   0x03: "ILLEGAL_DATA_VALUE", 0x04: "SERVER_DEVICE_FAILURE"}


def test_exception_names_are_the_spec_names_the_c_tools_print():
    assert {k: v for k, v in zm.EXCEPTIONS.items() if k} == SPEC_EXCEPTIONS
    assert zm.EXCEPTIONS[0] == "OK"
    host = REPO / "csrc" / "host" / "zw_mbhost.c"
    if not host.is_file():
        pytest.skip(f"{host} not present")
    m = re.search(r"zw_exception_name\(unsigned code\)\s*\{(.*?)\n\}", host.read_text(), re.S)
    assert m, "zw_exception_name not found in zw_mbhost.c"
    printed = {int(c, 0): n for c, n in re.findall(r'case (0x[0-9A-Fa-f]+): return "(\w+)";',
                                                    m.group(1))}
    assert {k: printed[k] for k in SPEC_EXCEPTIONS} == SPEC_EXCEPTIONS


def test_reason_name_of_unknown_code():
    assert zm.reason_name(16) == "ZW_REASON_ABOVE_SIGMA"
    assert zm.reason_name(999) == "ZW_REASON_UNKNOWN(999)"


# ---------------------------------------------------------------------------------------
# CRC-16/MODBUS
# ---------------------------------------------------------------------------------------


def test_crc_standard_check_value():
    assert zm.crc16_modbus(b"123456789") == 0x4B37
    assert zm.crc16_modbus(b"") == 0xFFFF


def test_crc_of_words_feeds_high_byte_first():
    data = b"12345678"
    words = list(struct.unpack(">4H", data))
    assert zm.crc16_words(words) == zm.crc16_modbus(data)
    assert zm.crc16_words([0x3132]) != zm.crc16_words([0x3231])


def test_crc_words_must_be_16_bit():
    with pytest.raises(ValueError, match="16-bit"):
        zm.crc16_words([0x10000])


def test_crc_agrees_with_the_c_library():
    lib_path = BUILD_DIR / "libzwidth_d_shared.so"
    if not lib_path.is_file():
        pytest.skip(f"{lib_path} not built")
    lib = ctypes.CDLL(str(lib_path))
    if not hasattr(lib, "zw_crc16_words"):
        pytest.skip("zw_crc16_words not in the library yet")
    lib.zw_crc16_words.restype = ctypes.c_uint16
    lib.zw_crc16_words.argtypes = [ctypes.POINTER(ctypes.c_uint16), ctypes.c_size_t]
    words = []
    for x in (85.78e-7, 2.197e-3, 0.02, 0.8, 0.999, 0.0, 10.0, -0.01, 0.01, 1.0, 0.01):
        words += zm.float_to_words(x)
    arr = (ctypes.c_uint16 * len(words))(*words)
    assert lib.zw_crc16_words(arr, len(words)) == zm.crc16_words(words)


# ---------------------------------------------------------------------------------------
# binary32 ABCD and u32
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("value, words", [
    (1.0, (0x3F80, 0x0000)),
    (-2.0, (0xC000, 0x0000)),
    (0.0, (0x0000, 0x0000)),
    (-0.0, (0x8000, 0x0000)),
    (0.40, (0x3ECC, 0xCCCD)),
    (float("inf"), (0x7F80, 0x0000)),
])
def test_float_words_high_word_first(value, words):
    assert zm.float_to_words(value) == words
    assert struct.pack(">f", zm.words_to_float(*words)) == struct.pack(">f", value)


def test_float_round_trip_is_binary32_rounding():
    for x in (0.40, -1.36e-3, 85.78e-7, 2.197e-3, 1e-40, 3.4028235e38):
        assert zm.words_to_float(*zm.float_to_words(x)) == struct.unpack(">f", struct.pack(">f", x))[0]
    assert math.isnan(zm.words_to_float(*zm.float_to_words(float("nan"))))


def test_float_overflow_and_type_errors_name_the_argument():
    with pytest.raises(ValueError, match=r"^K = 1e\+39 .*binary32"):
        zm.float_to_words(1e39, "K")
    with pytest.raises(ValueError, match="^B must be a real number"):
        zm.float_to_words("0.1", "B")
    with pytest.raises(ValueError, match="^sigma must be a real number"):
        zm.float_to_words(True, "sigma")


def test_u32_high_word_first():
    assert zm.u32_from_words(0x0001, 0x0002) == 0x00010002
    assert zm.u32_from_words(0xFFFF, 0xFFFF) == 0xFFFFFFFF


# ---------------------------------------------------------------------------------------
# Arguments and connection errors (no server)
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("kwargs, name", [
    (dict(port=0), "port"), (dict(port=70000), "port"), (dict(port="1502"), "port"),
    (dict(unit=256), "unit"), (dict(timeout=0), "timeout"), (dict(timeout=float("inf")), "timeout"),
    (dict(host=""), "host"),
])
def test_drive_arguments(kwargs, name):
    with pytest.raises(ValueError, match=f"^{name} "):
        zm.Drive(**kwargs)


def test_set_gains_arguments_checked_before_any_request():
    d = zm.Drive(LOOPBACK, free_port(), timeout=0.5)  # nothing listens: must not be reached
    with pytest.raises(ValueError, match="K, B or both"):
        d.set_gains()
    with pytest.raises(ValueError, match="^K must be a real number"):
        d.set_gains(K="0.3", B=0.0)
    with pytest.raises(ValueError, match=r"^B = -1e\+40"):
        d.set_gains(K=0.3, B=-1e40)
    with pytest.raises(ValueError, match="^db_max must be a real number"):
        d.commission(8.578e-6, 2.197e-3, 0.02, 0.8, 1.0, 0.0, 1.0, -0.01, 0.01, 1.0, None)
    with pytest.raises(ValueError, match="command must be one of"):
        d.command("OPEN")
    block = (8.578e-6, 2.197e-3, 0.02, 0.8, 1.0, 0.0, 1.0, -0.01, 0.01, 1.0, 0.01)
    with pytest.raises(ValueError, match="^delay must be an integer in 0..8"):
        d.commission(*block, delay=9)
    with pytest.raises(ValueError, match="^delay must be an integer in 0..8"):
        d.commission(*block, delay=1.0)
    with pytest.raises(ValueError, match="^differentiator must be"):
        d.commission(*block, differentiator="forward")
    with pytest.raises(ValueError, match="^key must be the drive's 32-byte"):
        d.commission(*block)
    with pytest.raises(ValueError, match="^key must be the drive's 32-byte"):
        d.commission(*block, key=TEST_KEY[:16])
    for bad in ("lowpass", ("lowpass", 0.0), "lowpass:abcHz", ("average", 17), "average:0",
                ("pole", 0.5)):
        with pytest.raises(ValueError, match="velocity_filter"):
            d.commission(*block, velocity_filter=bad)


def test_velocity_filter_fields():
    assert zm._velocity_filter_fields(None) == (0.0, 0.0)
    assert zm._velocity_filter_fields("none") == (0.0, 0.0)
    assert zm._velocity_filter_fields("lowpass:30Hz") == (1.0, 30.0)
    assert zm._velocity_filter_fields("lowpass:12.5") == (1.0, 12.5)
    assert zm._velocity_filter_fields(("lowpass", 30)) == (1.0, 30.0)
    assert zm._velocity_filter_fields("average:4") == (2.0, 4.0)
    assert zm._velocity_filter_fields(("average", 16)) == (2.0, 16.0)


def test_connection_error_names_host_and_port():
    pytest.importorskip("pymodbus", reason="pymodbus not installed (tools/requirements-test.txt)")
    port = free_port()
    with pytest.raises(ConnectionError, match=f"{LOOPBACK}:{port}"):
        with zm.Drive(LOOPBACK, port, timeout=0.5) as d:
            d.status()


def test_import_zwidth_does_not_load_the_modbus_client():
    """pymodbus is an optional extra: the analysis package must import without it."""
    import subprocess
    import sys

    code = "import sys, zwidth; print('pymodbus' in sys.modules, 'zwidth.modbus' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]


# ---------------------------------------------------------------------------------------
# commissioning key and MAC (map version 3)
# ---------------------------------------------------------------------------------------


def test_auth_message_agrees_with_the_c_library():
    lib_path = BUILD_DIR / "libzwidth_d_shared.so"
    if not lib_path.is_file():
        pytest.skip(f"{lib_path} not built")
    lib = ctypes.CDLL(str(lib_path))
    lib.zw_regmap_auth_message.restype = None
    nonce = [0xA100 + i for i in range(8)]
    block = [(0x0100 * i + 0xFF - i) & 0xFFFF for i in range(35)]
    box = [(0x9E37 * (i + 1)) & 0xFFFF for i in range(zm.BOX_CERT_WORDS)]
    out = (ctypes.c_uint8 * 736)()
    lib.zw_regmap_auth_message((ctypes.c_uint16 * 8)(*nonce), (ctypes.c_uint16 * 35)(*block),
                               (ctypes.c_uint16 * zm.BOX_CERT_WORDS)(*box), out)
    assert bytes(out) == zm.auth_message(nonce, block, box)
    assert zm.auth_message(nonce, block)[:2] == b"\x00\x05"
    # no certificate: 324 zero words at the end
    lib.zw_regmap_auth_message((ctypes.c_uint16 * 8)(*nonce), (ctypes.c_uint16 * 35)(*block),
                               (ctypes.c_uint16 * zm.BOX_CERT_WORDS)(), out)
    assert bytes(out) == zm.auth_message(nonce, block)
    with pytest.raises(ValueError):
        zm.auth_message(nonce, block, box[:-1])


def test_box_certificate_words_agree_with_the_c_library():
    """BoxCertificate.words() (python/zwidth/box.py) against zw_box_cert_encode of the same
    certificate, through the bindings' wire form and the C encoder."""
    lib_path = BUILD_DIR / "libzwidth_d_shared.so"
    if not lib_path.is_file():
        pytest.skip(f"{lib_path} not built")
    import zwidth

    cert = zwidth.PlantBox((0.95 * 85.78e-7, 1.05 * 85.78e-7), 2.197e-3, 0.02).certificate(
        (-1e-3, 1e-3), steps=4, leaves=64)

    class ZwBoxCert(ctypes.Structure):
        _fields_ = [("n_steps", ctypes.c_uint16), ("n_nodes", ctypes.c_uint16),
                    ("B", ctypes.c_float * 17), ("K", ctypes.c_float * 16),
                    ("nodes", ctypes.c_uint16 * 256)]

    c = ZwBoxCert()
    c.n_steps, c.n_nodes = len(cert.K), len(cert.nodes)
    for i, v in enumerate(cert.B):
        c.B[i] = v
    for i, v in enumerate(cert.K):
        c.K[i] = v
    for j, code in enumerate(cert.nodes):
        c.nodes[j // 4] |= code << (4 * (j % 4))
    lib = ctypes.CDLL(str(lib_path))
    out = (ctypes.c_uint16 * zm.BOX_CERT_WORDS)()
    lib.zw_box_cert_encode(ctypes.byref(c), out)
    assert list(out) == cert.words()
    assert len(cert.words()) * 2 == cert.size_bytes


def test_auth_mac_is_rfc4231_hmac_sha256():
    """The MAC is plain HMAC-SHA256 over the message: RFC 4231 test case 2 through the
    same primitive, then the packing into 16 big-endian words."""
    import hashlib
    import hmac
    want = bytes.fromhex("5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843")
    assert hmac.new(b"Jefe", b"what do ya want for nothing?", hashlib.sha256).digest() == want
    nonce, block = [1] * 8, [2] * 35
    mac = zm.auth_mac(TEST_KEY, nonce, block)
    digest = hmac.new(TEST_KEY, zm.auth_message(nonce, block), hashlib.sha256).digest()
    assert mac == [int.from_bytes(digest[2 * i:2 * i + 2], "big") for i in range(16)]
    with pytest.raises(ValueError, match="key must be 32 bytes"):
        zm.auth_mac(b"short", nonce, block)


def test_load_key_refuses_unsafe_files(tmp_path):
    good = write_key(tmp_path / "k")
    assert zm.load_key(good) == TEST_KEY
    for mode in (0o640, 0o604, 0o620, 0o644):
        with pytest.raises(ValueError, match="accessible by group or others"):
            zm.load_key(write_key(tmp_path / f"k{mode:o}", mode=mode))
    link = tmp_path / "link"
    link.symlink_to(good)
    with pytest.raises(OSError):
        zm.load_key(link)
    bad = tmp_path / "bad"
    bad.write_text("00" * 31 + "\n")
    bad.chmod(0o600)
    with pytest.raises(ValueError, match="exactly 64 hex digits"):
        zm.load_key(bad)
    bad.write_text("zz" * 32)
    with pytest.raises(ValueError, match="exactly 64 hex digits"):
        zm.load_key(bad)
    with pytest.raises(ValueError, match="not a regular file"):
        zm.load_key(tmp_path)
