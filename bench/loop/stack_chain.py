# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""Worst call-chain stack of each public zw_loop_* function from gcc's -fcallgraph-info=su
(.ci) output: frames summed along every path of the static call graph (as tools/footprint.sh
does for the core; calls into libm/libgcc count as 0 here).  Usage: stack_chain.py FILE.ci"""
import re
import sys
from functools import lru_cache

text = open(sys.argv[1]).read()
frames, edges = {}, {}
for m in re.finditer(r'node:\s*\{\s*title:\s*"([^"]+)"\s*label:\s*"([^"]*)"', text):
    title, label = m.groups()
    b = re.search(r"(\d+) bytes", label)
    frames[title] = int(b.group(1)) if b else 0
for m in re.finditer(r'edge:\s*\{\s*sourcename:\s*"([^"]+)"\s*targetname:\s*"([^"]+)"', text):
    edges.setdefault(m.group(1), []).append(m.group(2))


@lru_cache(maxsize=None)
def depth(f):
    return frames.get(f, 0) + max((depth(g) for g in edges.get(f, [])), default=0)


for f in sorted(frames):
    name = f.split(":")[-1]
    if name.startswith("zw_loop_"):
        print(f"{name:28s} {depth(f):6d} B")
