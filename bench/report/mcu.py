# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""The MCU view of the report: flash and stack from tools/footprint.sh, executed
instructions and the float results on an emulated Cortex-M4F (QEMU mps2-an386).

Flash and stack: tools/footprint.sh --no-write is run and its Markdown tables are read
(no second implementation of its measurements).

Instructions: bench/report/mcu/mcu_main.c is built with the compile flags footprint.sh
uses (read from the script, so they cannot drift apart), linked with newlib (nano) and
libm, and run under qemu-system-arm -M mps2-an386 with
    -singlestep -d exec,nochain
which makes every translation block one guest instruction and logs every block executed
(nochain: chained blocks would bypass the log).  So the log has one line per executed
instruction, with the symbol of its PC.  The driver calls report_marker() between the
measured calls; the instructions of one call are the log lines between two markers
whose symbol is not the driver's own (main, report_marker): the callee and everything it
calls, from its first instruction to its return, without the caller's argument set-up.
The method is checked on every run against a hand-written block of exactly 605
instructions (an IT block, a counted loop, a call and two kinds of return).
Considered and not used: QEMU TCG plugins (Debian's qemu-system-arm is built with plugin
support but ships no plugins and no qemu-plugin.h), the DWT cycle counter (QEMU 7.2 does
not emulate it: DWT_CYCCNT reads 0), -icount with SysTick (SysTick counts the 25 MHz
system clock, so with -icount shift=0 one tick is 40 instructions: not exact).
QEMU counts instructions, not cycles: the Cortex-M4's cycles per instruction (1 for most,
more for loads, divisions, branches and the FPU's vdiv/vsqrt, 14 cycles) are not modelled.
"""
from __future__ import annotations

import os
import re
import shutil
import struct
import subprocess
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MCU_DIR = os.path.join(ROOT, "bench", "report", "mcu")
FOOTPRINT = os.path.join(ROOT, "tools", "footprint.sh")
CORE = ("status", "coeffs", "region", "margin", "extremes", "device")
CALIBRATION = 605          # instructions of report_calibration + report_calib_leaf
DRIVER_SYMBOLS = {"main", "report_marker", "report_count_done"}
COUNTED_CALLS = ("zw_coeffs_init", "zw_check", "zw_device_init", "zw_device_k_max", "zw_extremes_compute")
QEMU = "qemu-system-arm"
CROSS = "arm-none-eabi-gcc"


def missing_tools() -> List[str]:
    return [t for t in (QEMU, CROSS) if shutil.which(t) is None]


# ------------------------------------------------------------------------------ footprint

def _tables(md: str) -> List[List[List[str]]]:
    """Every Markdown table of md as a list of rows of cells (separator rows dropped)."""
    tables, cur = [], []
    for line in md.splitlines():
        if line.startswith("|"):
            cells = [c.strip().strip("*").strip() for c in line.strip().strip("|").split("|")]
            if not all(re.fullmatch(r":?-+:?", c) for c in cells):
                cur.append(cells)
        elif cur:
            tables.append(cur)
            cur = []
    if cur:
        tables.append(cur)
    return tables


def _int(cell: str) -> Optional[int]:
    m = re.match(r"\d+", cell.replace(",", ""))
    return int(m.group(0)) if m else None


def footprint() -> Dict[str, Any]:
    """Run tools/footprint.sh --no-write and pick the report's figures from its tables."""
    proc = subprocess.run(["bash", FOOTPRINT, "--no-write"], cwd=ROOT, capture_output=True, text=True)
    if proc.returncode not in (0, 1):  # 1: a footprint target missed, the figures still stand
        raise RuntimeError(f"tools/footprint.sh failed ({proc.returncode}): {proc.stderr.strip()[-400:]}")
    md = proc.stdout
    out: Dict[str, Any] = {"targets_met": proc.returncode == 0, "linked": {}, "stack": {}, "image": {}}
    cc = re.search(r"- Compiler: `([^`]*)`", md)
    out["compiler"] = cc.group(1) if cc else "?"
    for t in _tables(md):
        head = t[0]
        if head[0] == "target" and "measured" in head:
            for row in t[1:]:
                if "as linked into a firmware" in row[0]:
                    key = "m4f" if "Cortex-M4F float" in row[0] else "m0" if "Cortex-M0 float" in row[0] else None
                    if key:
                        out["linked"][key] = _int(row[2])
        elif head[0] == "public function":
            cols = {name: i for i, name in enumerate(head)}
            for row in t[1:]:
                name = row[0].split(" ")[0]
                out["stack"][name] = {"m4f": _int(row[cols["Cortex-M4F float"]]),
                                      "m0": _int(row[cols["Cortex-M0 float"]])}
        elif head[0] == "origin":
            cols = {name: i for i, name in enumerate(head)}
            for row in t[1:]:
                out["image"][row[0]] = {"m4f": _int(row[cols["Cortex-M4F float"]]),
                                        "m0": _int(row[cols["Cortex-M0 float"]])}
    return out


def _footprint_flags() -> Tuple[str, str]:
    """(CFLAGS, Cortex-M4F float target flags) as tools/footprint.sh defines them."""
    text = open(FOOTPRINT, encoding="utf-8").read()
    cflags = re.search(r'^CFLAGS="([^"]*)"', text, re.M)
    m4f = re.search(r'^TFLAGS\[m4f\]="([^"]*)"', text, re.M)
    if not cflags or not m4f:
        raise RuntimeError("cannot read CFLAGS / TFLAGS[m4f] from tools/footprint.sh")
    # -fstack-usage writes .su files next to the objects: footprint.sh's business, not ours.
    return " ".join(f for f in cflags.group(1).split() if f != "-fstack-usage"), m4f.group(1)


# ------------------------------------------------------------------------------ image

def _literal(x: float) -> str:
    return f"ZW_R({float(x).hex()})"


def write_data(path: str, points: np.ndarray, deltas: Sequence[float], n_count: int) -> None:
    """mcu_data.c: the points (delta, alpha, beta rows) and deltas as zw_real literals
    (hexadecimal, exact; the float build rounds them like the host's float program)."""
    with open(path, "w", encoding="ascii") as fh:
        fh.write("/* Generated by bench/report/mcu.py: the report's points for the MCU image. */\n")
        fh.write('#include "zwidth/real.h"\n\n')
        fh.write(f"const unsigned long mcu_n_points = {len(points)}u;\n")
        fh.write(f"const unsigned long mcu_n_count = {n_count}u;\n")
        fh.write(f"const unsigned long mcu_n_deltas = {len(deltas)}u;\n")
        fh.write("const zw_real mcu_points[][3] = {\n")
        for d, a, b in points.tolist():
            fh.write(f"    {{{_literal(d)}, {_literal(a)}, {_literal(b)}}},\n")
        fh.write("};\nconst zw_real mcu_deltas[] = {\n")
        for d in deltas:
            fh.write(f"    {_literal(d)},\n")
        fh.write("};\n")


def build(work: str, mode: str) -> Tuple[str, str]:
    """Link the image for mode ('ACCURACY' or 'COUNT'); returns (elf path, flags used)."""
    cflags, tflags = _footprint_flags()
    elf = os.path.join(work, f"report_{mode.lower()}.elf")
    cmd = ([CROSS] + cflags.split() + tflags.split() + [f"-DREPORT_MODE_{mode}",
           "-I" + os.path.join(ROOT, "csrc", "include"), "-I" + MCU_DIR,
           "-nostartfiles", "-specs=nano.specs", "-specs=nosys.specs", "-Wl,--gc-sections",
           "-T", os.path.join(MCU_DIR, "mps2_an386.ld"),
           os.path.join(MCU_DIR, "startup.c"), os.path.join(MCU_DIR, "mcu_main.c"), os.path.join(MCU_DIR, "counting.c"),
           os.path.join(work, "mcu_data.c")]
           + [os.path.join(ROOT, "csrc", "src", f"{m}.c") for m in CORE] + ["-lm", "-o", elf])
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"MCU image build failed:\n{' '.join(cmd)}\n{proc.stderr[-2000:]}")
    return elf, f"{cflags} {tflags}"


def _qemu(elf: str, extra: Sequence[str], timeout: float) -> str:
    cmd = [QEMU, "-M", "mps2-an386", "-nographic", "-monitor", "none", "-serial", "none",
           "-semihosting-config", "enable=on,target=native", *extra, "-kernel", elf]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited {proc.returncode}: {(proc.stdout + proc.stderr)[-800:]}")
    return proc.stdout + proc.stderr


def _real(hexbytes: str) -> float:
    return struct.unpack(">f", bytes.fromhex(hexbytes))[0]


def run_accuracy(elf: str) -> Dict[str, Any]:
    """Parse the accuracy image's output: per point (status, stable, marginal, k status,
    k_max) and per delta (status, e, c1, c2, d12, extremes status, 4 extremes)."""
    text = _qemu(elf, [], timeout=600)
    if "accuracy done" not in text:
        raise RuntimeError(f"MCU accuracy run did not finish: {text[-400:]}")
    pts, dls = [], []
    for line in text.splitlines():
        f = line.split()
        if f and f[0] == "P":
            pts.append((int(f[2], 16), int(f[3], 16), int(f[4], 16), int(f[5], 16), _real(f[6])))
        elif f and f[0] == "D":
            dls.append((int(f[2], 16), *[_real(x) for x in f[3:7]], int(f[7], 16), *[_real(x) for x in f[8:12]]))
    return {"points": pts, "deltas": dls}


def count_segments(trace: Iterable[str]) -> List[int]:
    """Instructions executed between consecutive entries of report_marker, from a QEMU
    "-d exec,nochain" trace (lines "Trace ... [...] symbol"); the driver's own symbols
    (DRIVER_SYMBOLS) are not counted."""
    segments: List[int] = []
    count, started, in_marker = 0, False, False
    for line in trace:
        if not line.startswith("Trace "):
            continue
        sym = line.rsplit("]", 1)[-1].strip()
        if sym == "report_marker":
            # Only the first instruction of the marker starts a segment (the marker body is
            # one or two instructions, all with this symbol).
            if not in_marker:
                if started:
                    segments.append(count)
                started, count = True, 0
            in_marker = True
            continue
        in_marker = False
        if started and sym not in DRIVER_SYMBOLS:
            count += 1
    return segments


def run_count(elf: str, work: str) -> Dict[str, Any]:
    """Executed instructions per call (list per function) and the calibration count."""
    log = os.path.join(work, "trace.log")
    _qemu(elf, ["-singlestep", "-d", "exec,nochain", "-D", log], timeout=600)
    with open(log, encoding="ascii", errors="replace") as fh:
        segments = count_segments(fh)
    os.remove(log)
    # Segments: five calls per point, then the calibration.
    *calls, calib = segments
    per = {name: calls[i::len(COUNTED_CALLS)] for i, name in enumerate(COUNTED_CALLS)}
    return {"calls": per, "calibration": calib, "calibration_ok": calib == CALIBRATION}

