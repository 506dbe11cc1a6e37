# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Client for the zwidth drive-side gain register map, for Python tuning scripts.

A drive running zwidth serves the register map of ``csrc/include/zwidth/regmap.h`` over
Modbus (``zwidth-drive`` on a PC, the firmware's own stack on a drive).  The drive is the
only judge of a gain pair: it checks every write against its sealed certified block (plant,
stiffness fraction sigma, radius bound r, absolute bounds, step limits) and refuses, with a
reason, anything that is not provably stable.  This module only speaks the map: it encodes
floats, sends one request per gain change, reads back what the drive holds, and names the
drive's reasons.  It never re-decides a verdict.

    from zwidth.modbus import Drive

    with Drive("127.0.0.1", 1502) as drive:
        print(drive.status().limits.K_cert)            # certified K ceiling [N/m]
        result = drive.set_gains(K=0.30, B=-1.0e-3)     # one write-multiple request
        if not result.accepted:
            print(result.reason)                        # e.g. "ZW_REASON_ABOVE_SIGMA"
        print(drive.save())                             # SAVE: restored at power-up

Why pymodbus rather than bindings to a C Modbus client: pymodbus is a well-kept,
pure-Python Modbus library, so a tuning script needs no compiled extension (no libmodbus,
no compiler, works in any virtualenv); the only C that matters, the certification, runs on
the drive.  Tested with pymodbus 3.16.1 (unit keyword ``device_id``, pymodbus 3.10 on) and
3.6.9 (``slave``, older releases); the keyword is picked from the installed release:

    pymodbus>=3.6

Units: a linear device uses m [kg], b [N s/m], K [N/m], B [N s/m]; a rotary one reads m as
the inertia J [kg m^2], b [N m s/rad], K [N m/rad], B [N m s/rad].  T is in seconds.  Every
float crosses the wire as IEEE-754 binary32 over two registers, high word first ("ABCD")
or, on a drive that serves CDAB (``zwidth-drive --word-order cdab``), low word first: the
client follows the drive's WORD_ORDER register (``Drive(word_order="auto")``, the default;
``"abcd"`` or ``"cdab"`` insist on one and refuse a drive that speaks the other).  The
block's CRC and the commissioning MAC are over the ABCD words in both orders.  Read-back
values are the binary32 roundings of what was written.

A commissioning refused after its UNLOCK (at the nonce, block, MAC or SEAL step) leaves the
output off: the UNLOCK set the gains to (0, 0), and neither the refusal nor ABORT brings the
old ones back.  ``CommissionResult.message`` says so, with how to set gains again.

Other clients may share the drive.  Whether a request was accepted is always decided by
the drive's answer to that request.  The refusal reason is read from the drive's "last
refusal" registers right after the refused request and attributed to it only when the
exception code stored there equals the one our request received; otherwise another
client's refusal came in between and the reason is reported as ``REASON_UNKNOWN``
(a refusal by another client with the same exception code in that window cannot be told
apart).  ``commission`` reads the block back after SEAL and raises DriveError if the
drive is not in operation with exactly the block it sent.

A block may hold plant ranges (map version 4): ``commission(m=(0.10, 0.14), ...)`` or
``m="0.10:0.14"`` makes the drive certify every later gain write for every plant of the box
(``status().plant.ranged``; the live limits are then box bounds, NaN where the drive has no
box form).

Commissioning (map version 3) needs the drive's consent (its commissioning enable input;
``zwidth-drive --commissioning``) and its key: ``commission(..., key=load_key(path))``
MACs the drive's fresh nonce and the block with HMAC-SHA256 (``hmac`` and ``hashlib`` of
the standard library) under the drive's 32-byte key, kept in a file of 64 hex digits that
only its owner can read (``umask 077; openssl rand -hex 32 > drive.key``).

Errors: ``ConnectionError`` (with host:port) when the drive cannot be reached or does not
answer in time; ``ValueError`` (naming the argument) for arguments that cannot be sent;
``DriveError`` when the drive refuses a request that is not a gain or commissioning write
(for instance a status read), is not a zwidth drive at all, or ends up sealed with a block
other than the one ``commission`` sent.
"""
from __future__ import annotations

import hashlib
import hmac
import inspect
import math
import numbers
import os
import stat
import struct
import warnings
from dataclasses import dataclass
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

# Requirement (for tools/requirements-test.txt): pymodbus>=3.6 -- tested with 3.6.9 and 3.16.1.

__all__ = [
    "Drive",
    "DriveError",
    "Status",
    "Plant",
    "Policy",
    "Gains",
    "Limits",
    "State",
    "Counters",
    "Refusal",
    "Loop",
    "GainResult",
    "CommissionResult",
    "SaveResult",
    "Staircase",
    "REG",
    "REASONS",
    "REASON_UNKNOWN",
    "EXCEPTIONS",
    "CMD",
    "MAGIC",
    "MAP_VERSION",
    "CERT_WORDS",
    "KEY_BYTES",
    "AUTH_NONCE_WORDS",
    "AUTH_MAC_WORDS",
    "BOX_CERT_WORDS",
    "load_key",
    "auth_message",
    "auth_mac",
    "crc16_modbus",
    "crc16_words",
    "float_to_words",
    "words_to_float",
    "u32_from_words",
    "reason_name",
    "unit_keyword",
]

# ---------------------------------------------------------------------------------------
# The register map (regmap.h).  Restated here, not parsed at run time; tests/modbus_py
# checks every value against the header.
# ---------------------------------------------------------------------------------------

MAGIC = 0x5A57
MAP_VERSION = 5  # 5: the box certificate window (4: plant ranges, 3: consent and a MAC)
CERT_WORDS = 34  # words 0x0040..0x0061 covered by the CRC
KEY_BYTES = 32  # the drive's commissioning key (HMAC-SHA256)
AUTH_NONCE_WORDS = 8  # ZW_REG_NONCE
AUTH_MAC_WORDS = 16  # ZW_REG_MAC
BOX_CERT_WORDS = 324  # ZW_REG_BOX_CERT: a ranged block's box certificate (box_cert.h)

REG: Dict[str, int] = {
    "MAGIC": 0x0000,
    "VERSION": 0x0001,
    "MODE": 0x0002,
    "SEALED": 0x0003,
    "LAST_REASON": 0x0004,
    "LAST_EXCEPTION": 0x0005,
    "ACCEPTED": 0x0006,
    "REFUSED": 0x0008,
    "K": 0x0010,
    "B": 0x0012,
    "LIVE_K_MAX": 0x0020,
    "LIVE_K_CERT": 0x0022,
    "LIVE_B_LO": 0x0024,
    "LIVE_B_HI": 0x0026,
    "LIVE_K_MMAX": 0x0028,
    "LIVE_B_AT_KMMAX": 0x002A,
    "LIVE_RHO": 0x002C,
    "LIVE_DELTA": 0x002E,
    "STATE_X": 0x0030,
    "STATE_V": 0x0032,
    "STATE_F": 0x0034,
    "STATE_STEP": 0x0036,
    "LIVE_POLE": 0x0038,
    "CERT_M": 0x0040,
    "CERT_B": 0x0042,
    "CERT_T": 0x0044,
    "CERT_SIGMA": 0x0046,
    "CERT_R": 0x0048,
    "CERT_K_MIN": 0x004A,
    "CERT_K_MAX": 0x004C,
    "CERT_B_MIN": 0x004E,
    "CERT_B_MAX": 0x0050,
    "CERT_DK_MAX": 0x0052,
    "CERT_DB_MAX": 0x0054,
    "CERT_DELAY": 0x0056,
    "CERT_VFILTER": 0x0058,
    "CERT_VF_PARAM": 0x005A,
    "CERT_DIFF": 0x005C,
    "CERT_M_HI": 0x005E,
    "CERT_B_HI": 0x0060,
    "CERT_CRC": 0x0062,
    "COMMAND": 0x0064,
    "CONSENT": 0x0080,
    "RESTORE_SOURCE": 0x0081,
    "RESTORE_REASON": 0x0082,
    "WORD_ORDER": 0x0083,
    "PRECISION": 0x0084,
    "NONCE": 0x0088,
    "MAC": 0x0090,
    "BOX_CERT": 0x0100,
    "BOX_CERT_B": 0x0102,  # its breakpoints, then levels (binary32)
    "BOX_CERT_NODES": 0x0144,
    "COUNT": 0x0244,
}

CMD: Dict[str, int] = {"UNLOCK1": 0xC0DE, "UNLOCK2": 0x5AFE, "SEAL": 0x5EA1, "ABORT": 0xAB07,
                       "SAVE": 0x5A7E}

REASONS: Dict[int, str] = {
    0: "ZW_REASON_NONE",
    1: "ZW_REASON_BAD_FUNCTION",
    2: "ZW_REASON_MALFORMED",
    3: "ZW_REASON_UNMAPPED",
    4: "ZW_REASON_READ_ONLY",
    5: "ZW_REASON_HALF_FLOAT",
    6: "ZW_REASON_LOCKED",
    7: "ZW_REASON_NOT_SEALED",
    8: "ZW_REASON_NOT_FINITE",
    9: "ZW_REASON_K_BELOW_MIN",
    10: "ZW_REASON_K_ABOVE_MAX",
    11: "ZW_REASON_B_BELOW_MIN",
    12: "ZW_REASON_B_ABOVE_MAX",
    13: "ZW_REASON_K_STEP",
    14: "ZW_REASON_B_STEP",
    15: "ZW_REASON_UNSTABLE",
    16: "ZW_REASON_ABOVE_SIGMA",
    17: "ZW_REASON_RADIUS",
    18: "ZW_REASON_BAD_COMMAND",
    19: "ZW_REASON_CRC",
    20: "ZW_REASON_BAD_POLICY",
    21: "ZW_REASON_FPENV",
    22: "ZW_REASON_BAD_DELAY",
    23: "ZW_REASON_BAD_FILTER",
    24: "ZW_REASON_BAD_FILTER_PARAM",
    25: "ZW_REASON_BAD_DIFFERENTIATOR",
    26: "ZW_REASON_LOOP_NEVER_STABLE",
    27: "ZW_REASON_NO_CONSENT",
    28: "ZW_REASON_RNG",
    29: "ZW_REASON_AUTH",
    30: "ZW_REASON_ABOVE_CEILING",
    31: "ZW_REASON_PLANT_MISMATCH",
    32: "ZW_REASON_SUBNORMAL",
    33: "ZW_REASON_ONLY_OFF",
    34: "ZW_REASON_NO_CEILINGS",
    35: "ZW_REASON_NO_STORAGE",
    36: "ZW_REASON_STORAGE",
    37: "ZW_REASON_IMAGE_FORMAT",
    38: "ZW_REASON_IMAGE_CRC",
    39: "ZW_REASON_LOOP_MISMATCH",
    40: "ZW_REASON_BOX_BUDGET",
    41: "ZW_REASON_BOX_RADIUS",
    42: "ZW_REASON_BOX_CERT",
    43: "ZW_REASON_OUTSIDE_CERT",
}

# The reason reported for a refusal whose "last refusal" registers were overwritten by
# another client's refusal before we read them (see the module docstring).
REASON_UNKNOWN = "ZW_REASON_UNKNOWN"

# Modbus exception codes by their names in the Modbus Application Protocol specification
# (as the C tools print them); regmap.h spells 0x02 and 0x03 ZW_MB_ILLEGAL_ADDRESS and
# ZW_MB_ILLEGAL_VALUE, and 0x04 ZW_MB_SERVER_FAILURE.
EXCEPTIONS: Dict[int, str] = {
    0: "OK",
    0x01: "ILLEGAL_FUNCTION",
    0x02: "ILLEGAL_DATA_ADDRESS",
    0x03: "ILLEGAL_DATA_VALUE",
    0x04: "SERVER_DEVICE_FAILURE",
}

# Readable blocks of the map (start, count); the gaps between them are unmapped.
_BLOCK_HEAD = (0x0000, 10)   # magic .. refused counter
_BLOCK_GAINS = (0x0010, 4)   # K, B
_BLOCK_LIVE = (0x0020, 16)   # live limits
_BLOCK_STATE = (0x0030, 10)  # device state, and the low-pass pole in force
_BLOCK_CERT = (0x0040, CERT_WORDS + 1)  # certified block and its CRC

_CERT_FIELDS = ("m", "b", "T", "sigma", "r", "k_min", "k_max", "b_min", "b_max", "dk_max",
                "db_max", "delay", "vfilter", "vf_param", "differentiator", "m_hi", "b_hi")
# keyed by the block's float fields (0.0 == 0: a whole float finds its name)
_VFILTERS: Dict[float, str] = {0.0: "none", 1.0: "lowpass", 2.0: "average"}
_DIFFERENTIATORS: Dict[float, str] = {0.0: "backward", 1.0: "tustin"}

_FLT_MAX = struct.unpack(">f", b"\x7f\x7f\xff\xff")[0]


def _velocity_filter_fields(spec: Any) -> Tuple[float, float]:
    """(VFILTER, VF_PARAM) of a velocity filter given as None / "none", ("lowpass", f_c),
    "lowpass:30Hz" / "lowpass:30", ("average", n) or "average:4"."""
    if spec is None or spec == "none":
        return 0.0, 0.0
    if isinstance(spec, str) and ":" in spec:
        kind, _, param = spec.partition(":")
        param = param[:-2] if kind == "lowpass" and param.endswith("Hz") else param
        try:
            spec = (kind, float(param) if kind == "lowpass" else int(param))
        except ValueError:
            raise ValueError(f"velocity_filter {spec!r}: cannot read its parameter") from None
    if isinstance(spec, tuple) and len(spec) == 2 and spec[0] == "lowpass":
        f_c = _real("velocity_filter cut-off", spec[1])
        if not (f_c > 0 and math.isfinite(f_c)):
            raise ValueError(f"velocity_filter cut-off must be > 0 Hz, got {spec[1]!r}")
        return 1.0, f_c
    if isinstance(spec, tuple) and len(spec) == 2 and spec[0] == "average":
        n = spec[1]
        if isinstance(n, bool) or not isinstance(n, numbers.Integral) or not 1 <= int(n) <= 16:
            raise ValueError(f"velocity_filter average length must be an integer in 1..16, got {n!r}")
        return 2.0, float(n)
    raise ValueError("velocity_filter must be None, 'none', ('lowpass', f_c), 'lowpass:30Hz', "
                     f"('average', n) or 'average:4', got {spec!r}")


def unit_keyword(method: Callable[..., Any]) -> str:
    """Name of the unit-identifier keyword of a pymodbus client method: "device_id" from
    pymodbus 3.10 on, "slave" before."""
    params = inspect.signature(method).parameters
    return "device_id" if "device_id" in params else "slave"


def load_key(path: "os.PathLike[str] | str") -> bytes:
    """The drive's commissioning key from a file of 64 hex digits (whitespace around them
    ignored).  ValueError when the file is not a regular file, is not owned by this user,
    can be read or written by the group or others (chmod 600 it), or does not hold exactly
    64 hex digits; OSError when it cannot be opened (a symbolic link is not followed)."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0))
    try:
        st = os.fstat(fd)  # the open file itself: nothing can swap it after the check
        if not stat.S_ISREG(st.st_mode):
            raise ValueError(f"key file {path}: not a regular file")
        if hasattr(os, "geteuid") and st.st_uid != os.geteuid():
            raise ValueError(f"key file {path}: not owned by this user")
        if st.st_mode & 0o077:
            raise ValueError(f"key file {path}: accessible by group or others (mode "
                             f"{stat.S_IMODE(st.st_mode):03o}); chmod 600 it")
        text = os.read(fd, 256)
    finally:
        os.close(fd)
    digits = text.strip()
    if len(digits) != 2 * KEY_BYTES or any(c not in b"0123456789abcdefABCDEF" for c in digits):
        raise ValueError(f"key file {path}: must hold exactly 64 hex digits (a 32-byte key: "
                         f"openssl rand -hex 32)")
    return bytes.fromhex(digits.decode("ascii"))


def auth_message(nonce: Sequence[int], block: Sequence[int],
                 box_cert: Optional[Sequence[int]] = None) -> bytes:
    """The message a commissioning client MACs (zw_regmap_auth_message): the map version,
    the 8 nonce words, the 34 block words with their CRC and the 324 words of the box
    certificate window (None: all 0, no certificate), every word high byte first."""
    cert = [0] * BOX_CERT_WORDS if box_cert is None else list(box_cert)
    if len(nonce) != AUTH_NONCE_WORDS or len(block) != CERT_WORDS + 1 or len(cert) != BOX_CERT_WORDS:
        raise ValueError(f"auth_message needs {AUTH_NONCE_WORDS} nonce words, "
                         f"{CERT_WORDS + 1} block words and {BOX_CERT_WORDS} certificate words")
    words = [MAP_VERSION, *nonce, *block, *cert]
    return struct.pack(f">{len(words)}H", *words)


def auth_mac(key: bytes, nonce: Sequence[int], block: Sequence[int],
             box_cert: Optional[Sequence[int]] = None) -> List[int]:
    """HMAC-SHA256 of auth_message(nonce, block, box_cert) under key, as the 16 words of
    ZW_REG_MAC."""
    if not isinstance(key, (bytes, bytearray)) or len(key) != KEY_BYTES:
        raise ValueError(f"key must be {KEY_BYTES} bytes (load_key(path))")
    digest = hmac.new(bytes(key), auth_message(nonce, block, box_cert), hashlib.sha256).digest()
    return list(struct.unpack(">16H", digest))


def reason_name(code: int) -> str:
    """Name of a zw_reason code as in regmap.h ("ZW_REASON_UNSTABLE"); unknown codes give
    "ZW_REASON_UNKNOWN(<code>)"."""
    return REASONS.get(code, f"ZW_REASON_UNKNOWN({code})")


# ---------------------------------------------------------------------------------------
# Encoding: binary32 ABCD, u32 high word first, CRC-16/MODBUS
# ---------------------------------------------------------------------------------------


def _real(name: str, value: object) -> float:
    """``value`` as a Python float, or ValueError naming the argument."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be a real number, got {value!r}")
    return float(value)


def float_to_words(value: float, name: str = "value") -> Tuple[int, int]:
    """Encode a number as IEEE-754 binary32 in two 16-bit registers, high word first
    ("ABCD").  The value is rounded to the nearest binary32 (ties to even); NaN and the
    infinities pass through unchanged (the drive, not the client, refuses them).

    Raises ValueError naming ``name`` when the value is not a real number or is finite but
    beyond the binary32 range (|value| > 3.4028235e38 after rounding)."""
    x = _real(name, value)
    try:
        raw = struct.pack(">f", x)
    except OverflowError:
        raise ValueError(
            f"{name} = {x!r} does not fit a binary32 register (|{name}| <= {_FLT_MAX!r})"
        ) from None
    hi, lo = struct.unpack(">HH", raw)
    return hi, lo


def words_to_float(hi: int, lo: int) -> float:
    """Decode two registers, high word first ("ABCD"), as IEEE-754 binary32 (returned as a
    Python float, exactly)."""
    value: float = struct.unpack(">f", struct.pack(">HH", hi & 0xFFFF, lo & 0xFFFF))[0]
    return value


def u32_from_words(hi: int, lo: int) -> int:
    """Decode an unsigned 32-bit counter from two registers, high word first."""
    return ((hi & 0xFFFF) << 16) | (lo & 0xFFFF)


def crc16_modbus(data: bytes, crc: int = 0xFFFF) -> int:
    """CRC-16/MODBUS (reflected polynomial 0xA001, initial value 0xFFFF, no final XOR) of a
    byte string.  The standard check value: crc16_modbus(b"123456789") == 0x4B37."""
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def crc16_words(words: Sequence[int]) -> int:
    """CRC-16/MODBUS of 16-bit words, each fed high byte first: what the drive expects in
    ZW_REG_CERT_CRC over the 34 words of the certified block (zw_crc16_words in C)."""
    data = bytearray()
    for w in words:
        if not 0 <= w <= 0xFFFF:
            raise ValueError(f"words must be 16-bit values, got {w!r}")
        data += bytes(((w >> 8) & 0xFF, w & 0xFF))
    return crc16_modbus(bytes(data))


def _plant_of(block: Dict[str, float]) -> "Plant":
    """The block's plant; M_HI = B_HI = 0 is the point block's shorthand."""
    m_hi, b_hi = block["m_hi"], block["b_hi"]
    if m_hi == 0.0 and b_hi == 0.0:
        m_hi, b_hi = block["m"], block["b"]
    return Plant(block["m"], block["b"], block["T"], m_hi, b_hi)


def _range(name: str, value: Any) -> Tuple[Any, Any]:
    """m or b as (lower end, upper end): a number (a point), a (lo, hi) pair or "lo:hi"."""
    if isinstance(value, str):
        parts = value.split(":")
        if len(parts) > 2:
            raise ValueError(f"{name} must be a number, (lo, hi) or 'lo:hi', got {value!r}")
        try:
            return float(parts[0]), float(parts[1])
        except ValueError:
            raise ValueError(f"{name} must be a number, (lo, hi) or 'lo:hi', got {value!r}") from None
    if isinstance(value, (tuple, list)):
        if len(value) != 2:
            raise ValueError(f"{name} must be a number, (lo, hi) or 'lo:hi', got {value!r}")
        return value[0], value[1]
    return value, value


def _words_of(block: Sequence[int], addr: int, base: int) -> Tuple[int, int]:
    i = addr - base
    return block[i], block[i + 1]


def _f(block: Sequence[int], addr: int, base: int) -> float:
    return words_to_float(*_words_of(block, addr, base))


# ---------------------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Plant:
    """The plant of the certified block: m [kg] (or J [kg m^2]), b [N s/m] (or
    [N m s/rad]), T [s].  A block holding ranges (map version 4) certifies every plant with
    m in [m, m_hi] and b in [b, b_hi]; a point block has m_hi == m and b_hi == b (also
    when the drive holds the shorthand M_HI = B_HI = 0)."""

    m: float
    b: float
    T: float
    m_hi: float = math.nan
    b_hi: float = math.nan

    @property
    def ranged(self) -> bool:
        """True when the block certifies a box of plants rather than one plant."""
        return self.m_hi != self.m or self.b_hi != self.b


@dataclass(frozen=True)
class Policy:
    """The certification policy of the block: sigma (fraction of K_max(B), 1), r (spectral
    radius bound, 1), K bounds k_min, k_max [N/m], B bounds b_min, b_max [N s/m], largest
    change per accepted write dk_max [N/m] and db_max [N s/m], and the block's CRC."""

    sigma: float
    r: float
    k_min: float
    k_max: float
    b_min: float
    b_max: float
    dk_max: float
    db_max: float
    crc: int


@dataclass(frozen=True)
class Loop:
    """The loop the drive runs, as its certified block describes it (map version 2).

    delay: samples between the measurement and the force it produces; velocity_filter:
    "none", "lowpass" (first order, cut-off cutoff_hz [Hz]; pole: the a = exp(-2 pi f_c T)
    the drive certifies and applies, read from ZW_REG_LIVE_POLE, NaN unsealed) or
    "average" (moving average over average samples); differentiator: "backward" or
    "tustin".  A value the block holds that is none of these reads as "unknown(<value>)"
    (a block being staged in commissioning mode)."""

    delay: float
    velocity_filter: str
    cutoff_hz: float
    average: int
    differentiator: str
    pole: float

    @property
    def ideal(self) -> bool:
        """The paper's loop: no delay, backward difference, no filter."""
        return self.delay == 0 and self.velocity_filter == "none" and self.differentiator == "backward"


@dataclass(frozen=True)
class Gains:
    """The active gains: stiffness K [N/m] and damping B [N s/m]; (0, 0) is output off."""

    K: float
    B: float


@dataclass(frozen=True)
class Limits:
    """Live limits computed by the drive at the active gains (all NaN without a sealed
    block).  Named as K_max / K_mmax elsewhere (``zwidth.Device``, ``zwidth-tune status
    --json``); the lowercase names of earlier releases (``k_max``, ``k_cert``, ``b_lo``,
    ``b_hi``, ``k_mmax``, ``b_at_k_mmax``) still read, with a DeprecationWarning.

    K_max: K_max at the current B [N/m] (exact region); K_cert: certified K ceiling at the
    current B [N/m]: the largest K (a binary32) that passes all the certification rules
    that depend on K at this B -- K <= the block's k_max, K <= sigma K_max(B), stable,
    spectral radius < r -- as found by the drive's search (a scan down from
    min(sigma K_max(B), k_max) and a bisection); 0 when no K qualifies.  The k_min and step
    rules are not applied, so a write of K_cert can still be refused by them.  B_lo, B_hi:
    the stable B interval at the current K [N s/m] (both 0 when K = 0); K_mmax: largest
    stable K of the plant [N/m]; B_at_K_mmax: the B that attains it [N s/m]; rho: spectral
    radius at the current gains (1); delta = b T / m (1)."""

    K_max: float
    K_cert: float
    B_lo: float
    B_hi: float
    K_mmax: float
    B_at_K_mmax: float
    rho: float
    delta: float

    def _old(self, old: str, new: str) -> float:
        warnings.warn(f"Limits.{old} is deprecated: use Limits.{new}", DeprecationWarning,
                      stacklevel=3)
        value: float = getattr(self, new)
        return value

    @property
    def k_max(self) -> float:
        """Deprecated alias of K_max."""
        return self._old("k_max", "K_max")

    @property
    def k_cert(self) -> float:
        """Deprecated alias of K_cert."""
        return self._old("k_cert", "K_cert")

    @property
    def b_lo(self) -> float:
        """Deprecated alias of B_lo."""
        return self._old("b_lo", "B_lo")

    @property
    def b_hi(self) -> float:
        """Deprecated alias of B_hi."""
        return self._old("b_hi", "B_hi")

    @property
    def k_mmax(self) -> float:
        """Deprecated alias of K_mmax."""
        return self._old("k_mmax", "K_mmax")

    @property
    def b_at_k_mmax(self) -> float:
        """Deprecated alias of B_at_K_mmax."""
        return self._old("b_at_k_mmax", "B_at_K_mmax")


@dataclass(frozen=True)
class State:
    """Device state reported by the firmware: position x [m or rad], velocity v [m/s or
    rad/s], commanded force f [N or N m], step (samples since power-up); all 0 until the
    control loop first reports."""

    x: float
    v: float
    f: float
    step: int


@dataclass(frozen=True)
class Counters:
    """Counts since power-up: accepted gain changes and refused requests (u32, wrap)."""

    accepted: int
    refused: int


@dataclass(frozen=True)
class Refusal:
    """The last refused request: reason name from regmap.h ("ZW_REASON_NONE" if none yet)
    and the Modbus exception code sent for it (0 if none)."""

    reason: str
    exception: int


@dataclass(frozen=True)
class Staircase:
    """The box certificate in force (map version 5), as the drive shows it: step i
    certifies every K' in (0, K[i]] at every B in [B[i], B[i+1]] for every plant of the
    block's box; ``nodes``: the size of its proof."""

    B: Tuple[float, ...]
    K: Tuple[float, ...]
    nodes: int

    def level(self, B: float) -> float:
        """The certified level at B (the larger one on a breakpoint; 0 outside)."""
        if not self.B[0] <= B <= self.B[-1]:
            return 0.0
        return max(k for k, lo, hi in zip(self.K, self.B, self.B[1:]) if lo <= B <= hi)


@dataclass(frozen=True)
class Status:
    """Everything the drive shows, read in six requests (one per mapped block, so not an
    atomic snapshot).

    mode: "operation" or "commissioning"; sealed: a certified block is in force (CRC
    valid).  plant and policy come from the certified-block registers: the sealed block in
    operation mode, the block being written in commissioning mode (the live limits stay
    those of the sealed block until SEAL)."""

    mode: str
    sealed: bool
    plant: Plant
    policy: Policy
    gains: Gains
    limits: Limits
    state: State
    counters: Counters
    last_refusal: Refusal
    version: int
    loop: Loop
    #: The box certificate in force (None: a point block, or a ranged one without).
    staircase: Optional[Staircase] = None


@dataclass(frozen=True)
class GainResult:
    """Outcome of a gain write.

    accepted: the drive applied the pair (decided by the response to our write alone);
    reason: regmap.h name of the refusal reason ("ZW_REASON_NONE" when accepted,
    REASON_UNKNOWN when another client's refusal overwrote the drive's "last refusal"
    registers before they were read); exception: Modbus exception code of the response
    (0 when accepted; 0x03 ILLEGAL_DATA_VALUE value refused, 0x02 ILLEGAL_DATA_ADDRESS
    address/mode refused); K [N/m], B [N s/m]: the gains the drive holds afterwards, read
    back (binary32 values)."""

    accepted: bool
    reason: str
    exception: int
    K: float
    B: float


@dataclass(frozen=True)
class CommissionResult:
    """Outcome of commissioning.

    accepted: the new block is sealed and the drive is back in operation (gains off, 0/0);
    reason / exception: as in GainResult, for the first refused step; stage: the step that
    was refused ("unlock", "write", "mac", "seal") or "done"; crc: the CRC-16/MODBUS sent for the
    block; aborted: after a refusal the client sent ABORT, so the drive went back to the
    last sealed block (and to operation); output_off: the gains read back afterwards are
    (0, 0) -- after an accepted SEAL, and after a refusal that came once the UNLOCK had
    turned the output off (the refusal and ABORT do not bring the old gains back: set them
    again with ``set_gains``); message: all that in words (also ``str(result)``)."""

    accepted: bool
    reason: str
    exception: int
    stage: str
    crc: int
    aborted: bool
    output_off: bool = False
    message: str = ""
    #: The box certificate sent with a ranged block (zwidth.box.BoxCertificate; None for a
    #: point block, or when commission(certificate=None) sent none).
    certificate: Any = None

    def __str__(self) -> str:
        return self.message or repr(self)


@dataclass(frozen=True)
class SaveResult:
    """Outcome of SAVE (``Drive.save()``).

    accepted: the drive wrote its sealed block and the active gains to its non-volatile
    storage (restored at power-up); reason / exception: as in GainResult
    ("ZW_REASON_NO_STORAGE": the drive has no storage, ``zwidth-drive`` without
    ``--state-file``; "ZW_REASON_STORAGE": the storage failed; "ZW_REASON_NOT_SEALED";
    "ZW_REASON_NO_CONSENT"; "ZW_REASON_BAD_COMMAND": in commissioning mode); crc: the CRC of
    the block in force, K, B: the gains, read back after the SAVE; message: in words (also
    ``str(result)``)."""

    accepted: bool
    reason: str
    exception: int
    crc: int
    K: float
    B: float
    message: str = ""

    def __str__(self) -> str:
        return self.message or repr(self)


_SAVE_HINTS = {
    "ZW_REASON_NO_STORAGE": "the drive has no non-volatile storage (zwidth-drive --state-file PATH)",
    "ZW_REASON_STORAGE": "the drive's storage reported a failure; the previous saved copy is unchanged",
    "ZW_REASON_NOT_SEALED": "the drive has no sealed block to save: commission one first",
    "ZW_REASON_NO_CONSENT": "the drive does not consent (its commissioning enable input is off)",
    "ZW_REASON_BAD_COMMAND": "the drive is in commissioning mode: finish (SEAL) or ABORT first",
}


class DriveError(RuntimeError):
    """The drive refused a request the client needed (e.g. a status read), the server is
    not a zwidth drive, or commissioning sealed a block other than the one sent (another
    client wrote in between; exception 0).  ``exception`` is the Modbus exception code (0 if not applicable),
    ``reason`` the regmap.h reason name when known."""

    def __init__(self, message: str, exception: int = 0, reason: str = ""):
        super().__init__(message)
        self.exception = exception
        self.reason = reason


# ---------------------------------------------------------------------------------------
# The client
# ---------------------------------------------------------------------------------------


class Drive:
    """A zwidth drive over Modbus TCP.

    host: address of the drive (default 127.0.0.1); port: TCP port (default 1502, what
    zwidth-drive listens on); unit: Modbus unit (device) identifier, 0..255 (default 1);
    timeout: seconds to wait for a connection or a response (default 1.0); word_order:
    "auto" (default: as the drive's WORD_ORDER register says), "abcd" (high word first) or
    "cdab" (low word first); with "abcd" or "cdab" a drive that speaks the other order is
    refused (DriveError) rather than misread.

    Use as a context manager (``with Drive(...) as d:``) or call ``connect()``/``close()``;
    methods connect on first use.  Connecting checks the map's magic (0x5A57) and version
    (1).  Requests are never retried (a gain write or a command is not idempotent)."""

    def __init__(self, host: str = "127.0.0.1", port: int = 1502, unit: int = 1,
                 timeout: float = 1.0, word_order: str = "auto"):
        if not isinstance(host, str) or not host:
            raise ValueError(f"host must be a non-empty string, got {host!r}")
        if isinstance(port, bool) or not isinstance(port, int) or not 1 <= port <= 65535:
            raise ValueError(f"port must be an integer in 1..65535, got {port!r}")
        if isinstance(unit, bool) or not isinstance(unit, int) or not 0 <= unit <= 255:
            raise ValueError(f"unit must be an integer in 0..255, got {unit!r}")
        if word_order not in ("auto", "abcd", "cdab"):
            raise ValueError(f"word_order must be 'auto', 'abcd' or 'cdab', got {word_order!r}")
        t = _real("timeout", timeout)
        if not (t > 0 and math.isfinite(t)):
            raise ValueError(f"timeout must be > 0 seconds and finite, got {timeout!r}")
        self.host = host
        self.port = port
        self.unit = unit
        self.timeout = t
        self._client: Any = None  # pymodbus ModbusTcpClient (imported on connect)
        self._unit_kw = "device_id"
        self.word_order = word_order  # as asked; the drive's order once connected: self._cdab
        self._cdab = word_order == "cdab"

    # -- connection ---------------------------------------------------------------------

    @property
    def address(self) -> str:
        """"host:port" of the drive."""
        return f"{self.host}:{self.port}"

    def connect(self) -> "Drive":
        """Open the TCP connection and check that the server is a zwidth drive (magic and
        map version).  ConnectionError if it cannot be reached, DriveError if it answers
        but is not a zwidth drive of map version 1."""
        if self._client is not None:
            return self
        try:  # imported here: a script that only uses the encoders does not need pymodbus
            from pymodbus.client import ModbusTcpClient
        except ImportError as exc:
            raise ImportError("zwidth.modbus.Drive needs pymodbus: pip install 'pymodbus>=3.6'"
                              ) from exc

        client: Any = ModbusTcpClient(self.host, port=self.port, timeout=self.timeout, retries=0,
                                      reconnect_delay=0)
        if not client.connect():
            client.close()
            raise ConnectionError(
                f"cannot connect to the zwidth drive at {self.address} "
                f"(nothing listening, or no answer within {self.timeout} s)")
        self._client = client
        self._unit_kw = unit_keyword(client.read_holding_registers)
        try:
            head = self._read(REG["MAGIC"], 2)
        except DriveError as exc:
            self.close()
            raise DriveError(f"{self.address} is not a zwidth drive (reading the magic "
                             f"register gave exception {exc.exception})",
                             exc.exception) from None
        except BaseException:
            self.close()
            raise
        if head[0] != MAGIC or head[1] != MAP_VERSION:
            self.close()
            raise DriveError(f"{self.address} is not a zwidth drive of map version "
                             f"{MAP_VERSION} (magic 0x{head[0]:04X}, version {head[1]})")
        order = self._read(REG["WORD_ORDER"], 1)[0]  # one register: the same in both orders
        names = {0: "abcd", 1: "cdab"}
        if order not in names:
            self.close()
            raise DriveError(f"{self.address} reports word order {order} (neither 0 ABCD nor 1 CDAB)")
        if self.word_order != "auto" and names[order] != self.word_order:
            self.close()
            raise DriveError(
                f"{self.address} sends floats {'low' if order else 'high'} word first "
                f"({names[order].upper()}); this client was asked for {self.word_order.upper()} "
                f"(Drive(..., word_order={names[order]!r}) or the default 'auto')")
        self._cdab = order == 1
        return self

    def close(self) -> None:
        """Close the connection (idempotent)."""
        if self._client is not None:
            try:
                self._client.close()
            finally:
                self._client = None

    def __enter__(self) -> "Drive":
        return self.connect()

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return (f"Drive({self.host!r}, {self.port}, unit={self.unit}, timeout={self.timeout}, "
                f"word_order={self.word_order!r})")

    def _pairs(self, words: Sequence[int], n: Optional[int] = None) -> List[int]:
        """words with the two words of each of the first n (default all) swapped when the
        drive speaks CDAB: ABCD <-> the drive's wire order (the swap is its own inverse)."""
        out = list(words)
        if self._cdab:
            end = len(out) if n is None else n
            for i in range(0, end - 1, 2):
                out[i], out[i + 1] = out[i + 1], out[i]
        return out

    # -- raw requests -------------------------------------------------------------------

    def _call(self, what: str, fn: Callable[..., Any], *args: Any, **kwargs: Any) -> Tuple[Any, int]:
        """Run one pymodbus request; returns (response, exception_code)."""
        from pymodbus.exceptions import ModbusException

        try:
            kwargs[self._unit_kw] = self.unit
            rsp = fn(*args, **kwargs)
        except ModbusException as exc:
            self.close()
            raise ConnectionError(f"zwidth drive at {self.address}: {what} got no valid "
                                  f"answer within {self.timeout} s ({exc})") from None
        except OSError as exc:
            self.close()
            raise ConnectionError(f"zwidth drive at {self.address}: {what}: {exc}") from None
        code = getattr(rsp, "exception_code", None) if rsp is not None else None
        if rsp is None or isinstance(rsp, ModbusException) or (rsp.isError() and not code):
            # pymodbus < 3.7 returns (rather than raises) ModbusIOException on a lost link
            self.close()
            raise ConnectionError(f"zwidth drive at {self.address}: {what} got no valid "
                                  f"answer within {self.timeout} s ({rsp})")
        if rsp.isError():
            return rsp, int(code)  # type: ignore[arg-type]  # isError() with a code
        return rsp, 0

    def _read(self, addr: int, count: int) -> List[int]:
        """Read ``count`` holding registers from ``addr`` (0x03); DriveError if refused."""
        rsp, exc = self._call(f"read of {count} registers at 0x{addr:04X}",
                              self._client_or_connect().read_holding_registers, addr,
                              count=count)
        if exc:
            raise DriveError(f"zwidth drive at {self.address} refused reading {count} "
                             f"registers at 0x{addr:04X} (exception {exc})", exc)
        regs = list(rsp.registers)[:count]
        if len(regs) != count:
            raise ConnectionError(f"zwidth drive at {self.address}: read of {count} "
                                  f"registers at 0x{addr:04X} returned {len(regs)}")
        return regs

    def _write_many(self, addr: int, words: Sequence[int]) -> int:
        """Write registers in one 0x10 request; returns the exception code (0 accepted)."""
        _, exc = self._call(f"write of {len(words)} registers at 0x{addr:04X}",
                            self._client_or_connect().write_registers, addr, list(words))
        return exc

    def _write_one(self, addr: int, word: int) -> int:
        """Write one register with 0x06; returns the exception code (0 accepted)."""
        _, exc = self._call(f"write of register 0x{addr:04X}",
                            self._client_or_connect().write_register, addr, word)
        return exc

    def _client_or_connect(self) -> Any:
        if self._client is None:
            self.connect()
        return self._client

    def _refusal_reason(self, exc: int) -> str:
        """The reason of our request just refused with exception ``exc``: the drive's last
        reason if its last exception is ``exc``, else REASON_UNKNOWN (another client's
        refusal came in between; the C tool zwidth-tune does the same)."""
        reason, last_exc = self._read(REG["LAST_REASON"], 2)
        return reason_name(reason) if last_exc == exc else REASON_UNKNOWN

    # -- public API ---------------------------------------------------------------------

    def status(self) -> Status:
        """Read the whole map (six read requests, one per mapped block; of the box
        certificate its steps, not its proof).  DriveError if the drive refuses a read."""
        head = self._read(*_BLOCK_HEAD)
        head = head[:6] + self._pairs(head[6:])  # the two u32 counters
        gains = self._pairs(self._read(*_BLOCK_GAINS))
        live = self._pairs(self._read(*_BLOCK_LIVE))
        state = self._pairs(self._read(*_BLOCK_STATE))
        cert = self._pairs(self._read(*_BLOCK_CERT), CERT_WORDS)  # not the CRC word
        c0 = _BLOCK_CERT[0]
        block = {name: _f(cert, c0 + 2 * i, c0) for i, name in enumerate(_CERT_FIELDS)}
        l0 = _BLOCK_LIVE[0]
        s0 = _BLOCK_STATE[0]
        stairs = self._box_cert_wire(self._read(REG["BOX_CERT"], REG["BOX_CERT_NODES"] - REG["BOX_CERT"]))
        n = stairs[0] if stairs[0] <= 16 else 0
        floats = [words_to_float(stairs[i], stairs[i + 1]) for i in range(2, len(stairs), 2)]
        return Status(
            mode={0: "operation", 1: "commissioning"}.get(head[REG["MODE"]],
                                                          f"unknown({head[REG['MODE']]})"),
            sealed=bool(head[REG["SEALED"]]),
            plant=_plant_of(block),
            policy=Policy(block["sigma"], block["r"], block["k_min"], block["k_max"],
                          block["b_min"], block["b_max"], block["dk_max"], block["db_max"],
                          cert[REG["CERT_CRC"] - c0]),
            gains=Gains(words_to_float(gains[0], gains[1]), words_to_float(gains[2], gains[3])),
            limits=Limits(
                K_max=_f(live, REG["LIVE_K_MAX"], l0),
                K_cert=_f(live, REG["LIVE_K_CERT"], l0),
                B_lo=_f(live, REG["LIVE_B_LO"], l0),
                B_hi=_f(live, REG["LIVE_B_HI"], l0),
                K_mmax=_f(live, REG["LIVE_K_MMAX"], l0),
                B_at_K_mmax=_f(live, REG["LIVE_B_AT_KMMAX"], l0),
                rho=_f(live, REG["LIVE_RHO"], l0),
                delta=_f(live, REG["LIVE_DELTA"], l0),
            ),
            state=State(
                x=_f(state, REG["STATE_X"], s0),
                v=_f(state, REG["STATE_V"], s0),
                f=_f(state, REG["STATE_F"], s0),
                step=u32_from_words(*_words_of(state, REG["STATE_STEP"], s0)),
            ),
            counters=Counters(u32_from_words(head[6], head[7]),
                              u32_from_words(head[8], head[9])),
            last_refusal=Refusal(reason_name(head[REG["LAST_REASON"]]),
                                 head[REG["LAST_EXCEPTION"]]),
            version=head[REG["VERSION"]],
            loop=Loop(
                delay=block["delay"],
                velocity_filter=_VFILTERS.get(block["vfilter"], f"unknown({block['vfilter']})"),
                cutoff_hz=block["vf_param"] if block["vfilter"] == 1.0 else math.nan,
                average=int(block["vf_param"]) if block["vfilter"] == 2.0 and
                math.isfinite(block["vf_param"]) else 0,
                differentiator=_DIFFERENTIATORS.get(block["differentiator"],
                                                    f"unknown({block['differentiator']})"),
                pole=_f(state, REG["LIVE_POLE"], s0),
            ),
            staircase=Staircase(tuple(floats[:n + 1]), tuple(floats[17:17 + n]), stairs[1]) if n else None,
        )

    def gains(self) -> Gains:
        """The active gains K [N/m], B [N s/m] (one read request)."""
        g = self._pairs(self._read(*_BLOCK_GAINS))
        return Gains(words_to_float(g[0], g[1]), words_to_float(g[2], g[3]))

    def set_gains(self, K: Optional[float] = None, B: Optional[float] = None) -> GainResult:
        """Ask the drive for new gains: stiffness K [N/m or N m/rad] and/or damping
        B [N s/m or N m s/rad].

        Both given: K and B go in ONE write-multiple request (0x10, 4 registers at 0x0010),
        so the drive judges them as a pair.  One given: only that float is written (0x10,
        2 registers) and the drive judges it with the other active gain.  The drive
        accepts (0, 0) always (output off); anything else must pass its certification
        (bounds, step limits, stability, sigma, radius), else it refuses and keeps the
        old gains.  The gains are then read back.

        Values are rounded to binary32.  ValueError (naming the argument) when neither is
        given or a value is not a real number or overflows binary32; NaN and infinities
        are sent and refused by the drive (ZW_REASON_NOT_FINITE)."""
        if K is None and B is None:
            raise ValueError("set_gains needs K, B or both")
        words: List[int] = []
        addr = REG["K"] if K is not None else REG["B"]
        if K is not None:
            words += float_to_words(K, "K")
        if B is not None:
            words += float_to_words(B, "B")
        self._client_or_connect()  # the drive's word order is known from here on
        exc = self._write_many(addr, self._pairs(words))
        reason = self._refusal_reason(exc) if exc else REASONS[0]
        now = self.gains()
        return GainResult(accepted=exc == 0, reason=reason, exception=exc, K=now.K, B=now.B)

    def command(self, name: str) -> int:
        """Write one command ("UNLOCK1", "UNLOCK2", "SEAL", "ABORT", "SAVE") to ZW_REG_COMMAND;
        returns the exception code (0 accepted).  ValueError for an unknown name."""
        if name not in CMD:
            raise ValueError(f"command must be one of {sorted(CMD)}, got {name!r}")
        return self._write_one(REG["COMMAND"], CMD[name])

    def commission(self, m: float, b: float, T: float, sigma: float, r: float,
                   k_min: float, k_max: float, b_min: float, b_max: float,
                   dk_max: float, db_max: float, *, delay: int = 0,
                   velocity_filter: Any = None, differentiator: str = "backward",
                   abort_on_refusal: bool = True, key: Optional[bytes] = None,
                   certificate: Any = "auto",
                   certificate_B: Optional[Tuple[float, float]] = None) -> CommissionResult:
        """Install and seal a new certified block.

        m: mass [kg] or inertia J [kg m^2]; b: physical damping [N s/m or N m s/rad];
        either may be a range (map version 4: a pair (lo, hi) or the text "lo:hi"), and the
        drive then certifies every gain write for every plant of that box (it needs r = 1,
        else ZW_REASON_BOX_RADIUS; a write its search cannot prove within its budget is
        refused, ZW_REASON_BOX_BUDGET); a number is a point (upper end = lower end);
        T: sampling period [s]; sigma: fraction of K_max(B) allowed, in (0, 1]; r: spectral
        radius bound, in (0, 1]; k_min, k_max: K bounds [N/m or N m/rad]; b_min, b_max:
        B bounds [N s/m or N m s/rad]; dk_max [N/m], db_max [N s/m]: largest change of K
        and B per accepted write, > 0.

        The loop the drive runs (the drive certifies every gain write for it): delay: d
        samples (0..8); velocity_filter: None or "none", ("lowpass", f_c) / "lowpass:30Hz"
        (first order, cut-off f_c [Hz] < 1 / (2 T); the drive applies the pole
        exp(-2 pi f_c T), shown in status().loop.pole), ("average", n) / "average:4" (moving
        average, n in 1..16); differentiator: "backward" or "tustin".  Defaults: the ideal
        loop.  The drive refuses a bad description at SEAL with a named reason
        (ZW_REASON_BAD_DELAY, _BAD_FILTER, _BAD_FILTER_PARAM, _BAD_DIFFERENTIATOR,
        _LOOP_NEVER_STABLE).

        certificate (map version 5; ranged blocks only): "auto" (default) builds the box
        certificate here, in the drive's precision (its PRECISION register), with
        ``PlantBox(...).certificate(certificate_B, precision=...)``; certificate_B defaults to
        [b_min, b_max] cut to the B the box certifies at half its K_mmax.  The drive verifies
        it at SEAL in bounded time (ZW_REASON_BOX_CERT when it does not prove its claims) and
        every gain write is then a lookup (ZW_REASON_OUTSIDE_CERT for B outside its range).
        A zwidth.box.BoxCertificate is sent as it is; None sends none (the drive then runs
        its box search on every write, unbounded on an MCU).  Building takes seconds; a B
        range with a step nothing proves raises ZwidthError before anything is sent.

        key: the drive's 32-byte commissioning key (``load_key(path)``; ValueError without
        it).  The drive must also consent (its commissioning enable input), else the
        unlock is refused with ZW_REASON_NO_CONSENT.

        Steps: UNLOCK1 and UNLOCK2 (two single writes in a row; the drive turns the output
        off and publishes a fresh nonce), the 34 block words and their CRC-16/MODBUS in one
        write-multiple request, the certificate window (324 words, all 0 for none) in three
        more, the HMAC-SHA256 of nonce, block and certificate (auth_mac) in another, then SEAL (the drive checks the CRC, the MAC and the policy and returns to
        operation with the gains off).  A ranged block's SEAL certifies over its whole
        plant box (about a second on a PC, longer on a drive's MCU): give the Drive a
        timeout that covers it (``Drive(host, timeout=30)``; zwidth-tune waits 30 s for
        SEAL by itself).  The drive is the judge of the policy; the client only checks
        that every value can be sent (ValueError naming the argument otherwise).  If a
        step is refused and abort_on_refusal is true (default), ABORT is sent so the
        drive restores its last sealed block and returns to operation.

        After an accepted SEAL the mode, the SEALED flag, the certified block and its CRC
        are read back: another client (holding the key) could have re-commissioned right
        after, so DriveError (exception 0) naming the CRC sent and the CRC the drive holds
        is raised unless the drive is in operation, sealed, with exactly the 34 words and
        CRC that were written.  (A client without the key that changes the staged block
        before our SEAL makes the SEAL fail the MAC: refused at "seal", ZW_REASON_AUTH.)"""
        vkind, vparam = _velocity_filter_fields(velocity_filter)
        if isinstance(delay, bool) or not isinstance(delay, numbers.Integral) or not 0 <= delay <= 8:
            raise ValueError(f"delay must be an integer in 0..8, got {delay!r}")
        if differentiator not in ("backward", "tustin"):
            raise ValueError(f"differentiator must be 'backward' or 'tustin', got {differentiator!r}")
        m_lo, m_hi = _range("m", m)
        b_lo, b_hi = _range("b", b)
        values = dict(m=m_lo, b=b_lo, T=T, sigma=sigma, r=r, k_min=k_min, k_max=k_max,
                      b_min=b_min, b_max=b_max, dk_max=dk_max, db_max=db_max,
                      delay=float(delay), vfilter=vkind, vf_param=vparam,
                      differentiator=1.0 if differentiator == "tustin" else 0.0,
                      m_hi=m_hi, b_hi=b_hi)
        words: List[int] = []
        for name in _CERT_FIELDS:
            words += float_to_words(values[name], name)
        crc = crc16_words(words)
        if not isinstance(key, (bytes, bytearray)) or len(key) != KEY_BYTES:
            raise ValueError(f"key must be the drive's {KEY_BYTES}-byte commissioning key "
                             f"(load_key(path)), got {type(key).__name__}")
        cert = self._box_certificate(values, velocity_filter, differentiator, certificate, certificate_B)
        box_words = cert.words() if cert is not None else [0] * BOX_CERT_WORDS

        def refused(stage: str, exc: int, abort: bool) -> CommissionResult:
            """abort: the refusal came after the UNLOCK (which turned the output off)."""
            reason = self._refusal_reason(exc)
            aborted = False
            if abort and abort_on_refusal:
                aborted = self.command("ABORT") == 0
            text = (f"commissioning refused at {stage}: {reason} (exception {exc})"
                    + ("; ABORT sent: the last sealed block is back" if aborted else ""))
            off = False
            if abort:
                now = self.gains()
                off = now == Gains(0.0, 0.0)
                text += ("; the output is now off: gains (0, 0) -- the UNLOCK turned it off, and "
                         "neither the refusal nor ABORT brings the old gains back; set them "
                         "again with Drive.set_gains(K=..., B=...)" if off else
                         f"; active gains now K = {now.K:.9g}, B = {now.B:.9g}")
            return CommissionResult(False, reason, exc, stage, crc, aborted, off, text, cert)

        exc = self.command("UNLOCK1")
        if exc:
            return refused("unlock", exc, False)
        exc = self.command("UNLOCK2")
        if exc:
            return refused("unlock", exc, False)
        nonce = self._read(REG["NONCE"], AUTH_NONCE_WORDS)
        mac = auth_mac(bytes(key), nonce, words + [crc], box_words)
        exc = self._write_many(REG["CERT_M"], self._pairs(words) + [crc])  # CRC, MAC: ABCD
        if exc:
            return refused("write", exc, True)
        exc = self._write_window(REG["BOX_CERT"], self._box_cert_wire(box_words))
        if exc:
            return refused("certificate", exc, True)
        exc = self._write_many(REG["MAC"], mac)
        if exc:
            return refused("mac", exc, True)
        exc = self.command("SEAL")
        if exc:
            return refused("seal", exc, True)
        mode, sealed = self._read(REG["MODE"], 2)
        held = self._pairs(self._read(*_BLOCK_CERT), CERT_WORDS)
        held_cert = self._box_cert_wire(self._read_window(REG["BOX_CERT"], BOX_CERT_WORDS))
        if mode != 0 or held != words + [crc] or sealed != 1 or held_cert != box_words:
            raise DriveError(
                f"zwidth drive at {self.address}: after SEAL the drive is not in operation "
                f"with the block this client sent (another client commissioned after us?): "
                f"MODE = {mode}, sent CRC 0x{crc:04X}, drive holds CRC 0x{held[-1]:04X}"
                f"{'' if held[:-1] == words else ' over different words'}, SEALED = {sealed}"
                f"{'' if held_cert == box_words else ', another box certificate'}")
        with_cert = (f" with its box certificate ({cert.leaves} leaves, {len(cert.K)} steps over B in "
                     f"[{cert.B[0]:.6g}, {cert.B[-1]:.6g}])" if cert is not None else "")
        return CommissionResult(True, REASONS[0], 0, "done", crc, False, True,
                                f"commissioned: the drive sealed the block (CRC 0x{crc:04X}){with_cert} and "
                                f"is in operation; the output is off (gains 0, 0) until set_gains", cert)

    def _box_certificate(self, values: Dict[str, float], velocity_filter: Any, differentiator: str,
                         certificate: Any, certificate_B: Optional[Tuple[float, float]]) -> Any:
        """commission()'s box certificate: None for a point block or certificate=None; else
        the one given, or one built in the drive's precision over the block's float plant."""
        from .box import BoxCertificate, PlantBox

        def f32(x: float) -> float:  # the value the drive holds
            return float(struct.unpack(">f", struct.pack(">f", float(x)))[0])

        ranged = f32(values["m_hi"]) != f32(values["m"]) or f32(values["b_hi"]) != f32(values["b"])
        if not ranged or certificate is None:
            if isinstance(certificate, BoxCertificate) or certificate_B is not None:
                raise ValueError("certificate and certificate_B need plant ranges (m or b as (lo, hi))")
            return None
        if isinstance(certificate, BoxCertificate):
            return certificate
        if certificate != "auto":
            raise ValueError(f"certificate must be 'auto', None or a BoxCertificate, got {certificate!r}")
        precision = {4: "float", 8: "double"}.get(self._read(REG["PRECISION"], 1)[0])
        if precision is None:
            raise DriveError(f"zwidth drive at {self.address} reports a precision other than 4 or 8 bytes")
        vkind, vparam = values["vfilter"], values["vf_param"]
        vf = ("lowpass", f32(vparam)) if vkind == 1.0 else ("average", int(vparam)) if vkind == 2.0 else None
        box = PlantBox((f32(values["m"]), f32(values["m_hi"])), (f32(values["b"]), f32(values["b_hi"])),
                       f32(values["T"]), delay=int(values["delay"]), velocity_filter=vf,
                       differentiator=differentiator, method="kharitonov")
        if certificate_B is None:
            lo, hi = box.certificate_range()
            certificate_B = (max(lo, f32(values["b_min"])), min(hi, f32(values["b_max"])))
            if not certificate_B[0] < certificate_B[1]:
                raise ValueError(f"no B within [b_min, b_max] is certified over the box at half its K_mmax "
                                 f"(B in [{lo:.6g}, {hi:.6g}]): give certificate_B")
        return box.certificate(certificate_B, precision=precision)

    def _box_cert_wire(self, words: Sequence[int]) -> List[int]:
        """The certificate's words with its floats in the drive's word order (its own inverse)."""
        lo, hi = REG["BOX_CERT_B"] - REG["BOX_CERT"], REG["BOX_CERT_NODES"] - REG["BOX_CERT"]
        out = list(words)
        out[lo:hi] = self._pairs(out[lo:hi])
        return out

    def _write_window(self, addr: int, words: Sequence[int]) -> int:
        """Write words at addr in requests of at most 123 (FC 0x10's limit); the first
        exception code, 0 when all were accepted."""
        for at in range(0, len(words), 123):
            exc = self._write_many(addr + at, words[at:at + 123])
            if exc:
                return exc
        return 0

    def _read_window(self, addr: int, count: int) -> List[int]:
        """Read count words at addr in requests of at most 125 (FC 0x03's limit)."""
        out: List[int] = []
        for at in range(0, count, 125):
            out += self._read(addr + at, min(125, count - at))
        return out

    def save(self) -> SaveResult:
        """SAVE (0x5A7E to COMMAND): the drive writes its sealed block and the active gains
        to its non-volatile storage (``zwidth-drive --state-file``), which it checks and
        restores at power-up.  Returns a SaveResult (accepted, or the drive's reason, e.g.
        ZW_REASON_NO_STORAGE) with the block's CRC and the gains read back; it raises only
        when the drive cannot be reached (ConnectionError) or refuses a read (DriveError)."""
        exc = self.command("SAVE")
        reason = self._refusal_reason(exc) if exc else REASONS[0]
        crc = self._read(REG["CERT_CRC"], 1)[0]
        now = self.gains()
        if exc == 0:
            text = (f"saved: the drive stored its sealed block (CRC 0x{crc:04X}) and the active "
                    f"gains K = {now.K:.9g}, B = {now.B:.9g}; they are restored at power-up")
        else:
            hint = _SAVE_HINTS.get(reason, "")
            text = f"SAVE refused: {reason} (exception {exc}); nothing was saved" + (f": {hint}" if hint else "")
        return SaveResult(exc == 0, reason, exc, crc, now.K, now.B, text)
