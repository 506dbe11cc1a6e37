#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
#
# tools/misra.sh - MISRA C:2012 check of the firmware part (cppcheck's MISRA addon).
#
# Usage:  tools/misra.sh [--list]
#   --list   also print every finding (file:line rule [deviated | NOT GATED])
#
# Checks every file of ZW_CORE_SOURCES in CMakeLists.txt (what a firmware links), once
# for the double build and once for the float build (-DZW_REAL_FLOAT), and classifies
# each finding by the file it is in (a header's finding belongs to the header, whichever
# module included it; findings in the C library's headers are not ours and are dropped):
#   deviated    covered by a row of the deviation table in docs/misra.md (rule + file glob)
#   not gated   in a file of NOT_YET_GATED below: counted and printed, does not fail
#   violation   anything else: fails the run
# cppcheck's own checkers (uninitvar, nullPointer, ...) count as findings too, under the
# rule name cppcheck:<id>.  The run also fails when a deviation row matches no finding (a
# stale deviation), and with exit status 2 when cppcheck could not analyse one of our
# files (an #error, a syntax error: the analysis did not see the code).
#
# cppcheck gets the C library headers and the compiler's predefined macros (cc -dM -E),
# so that float.h's FLT_RADIX and the essential types of the library calls are known.
# Debian's addon has no rule texts (MISRA's are licensed): findings show rule numbers
# only, which is all the table needs.
#
# Exit status: 0 clean; 1 a violation or a stale deviation; 2 cppcheck missing or broken.
# About 50 s of CPU: 30 s to 2 min on 2 cores (ZW_JOBS, default 2, parallel cppcheck runs).
set -euo pipefail
cd "$(dirname "$0")/.."

# Modules not yet cleaned: findings are counted and printed but do not fail.  Shrink this
# list as modules are cleaned; a file that matches no pattern is gated.
NOT_YET_GATED=(
)

list=0
case "${1:-}" in
    "") ;;
    --list) list=1 ;;
    -h|--help) sed -n '2,/^[^#]/{/^#/p}' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "misra.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
esac

addon=""
for candidate in /usr/lib/*/cppcheck/addons/misra.py /usr/share/cppcheck/addons/misra.py; do
    [ -f "$candidate" ] && addon=misra && break
done
if ! command -v cppcheck >/dev/null 2>&1 || [ -z "$addon" ]; then
    echo "misra.sh: cppcheck with its MISRA addon is missing (tools/bootstrap.sh installs it)" >&2
    exit 2
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/zw-misra.XXXXXX")
trap 'rm -rf "$work"' EXIT

# The compiler's view: predefined macros and system include directories.
cc -std=c99 -dM -E - </dev/null >"$work/predefined.h"
sys_includes=()
while read -r dir; do sys_includes+=("-I$dir"); done < <(
    cc -std=c99 -E -v - </dev/null 2>&1 | sed -n '/#include <...> search starts here:/,/End of search list./p' |
        sed '1d;$d;s/^ *//')

sources=$(sed -n '/^set(ZW_CORE_SOURCES/,/)/p' CMakeLists.txt | grep -o 'csrc/src/[A-Za-z0-9_]*\.c')
[ -n "$sources" ] || { echo "misra.sh: no ZW_CORE_SOURCES in CMakeLists.txt" >&2; exit 2; }

# One cppcheck run per source and precision; a copy of each source in its own directory
# keeps the .dump files of parallel runs apart and out of the tree.
run_one() {
    local precision=$1 src=$2 def
    local out="$work/$precision-$(basename "$src" .c).txt"
    if [ "$precision" = float ]; then def=-DZW_REAL_FLOAT; else def=-D__STDC_VERSION__=199901L; fi
    cppcheck -q --addon=misra --std=c99 --language=c "$def" --include="$work/predefined.h" \
        -Icsrc/include -Icsrc/src "${sys_includes[@]}" \
        --cppcheck-build-dir="$(mktemp -d "$work/build.XXXXXX")" \
        --template='{file}|{line}|{id}|{message}' "$src" >"$out" 2>&1 || true
    # cppcheck prints the finding lines; keep those only
    grep -E '^[^|]+\|[0-9]+\|' "$out" | sed "s/^/$precision|/" >"$out.findings" || true
}
export -f run_one
export work
export sys_includes_str="${sys_includes[*]}"
for precision in double float; do
    for src in $sources; do printf '%s %s\n' "$precision" "$src"; done
done | xargs -P "${ZW_JOBS:-2}" -n 2 bash -c 'sys_includes=($sys_includes_str); run_one "$0" "$1"'

cat "$work"/*.findings >"$work/all.txt" 2>/dev/null || : >"$work/all.txt"

ZW_NOT_YET_GATED="${NOT_YET_GATED[*]}" ZW_LIST=$list python3 - "$work/all.txt" docs/misra.md <<'PY'
import collections, fnmatch, os, re, sys

findings_path, table_path = sys.argv[1], sys.argv[2]
not_gated = os.environ["ZW_NOT_YET_GATED"].split()
listing = os.environ["ZW_LIST"] == "1"

# The deviation table: rows "| 15.5 | `glob`, `glob` | why | guard |" in docs/misra.md
# (the rule a MISRA C:2012 number or cppcheck:<id>).
deviations = []
for lineno, line in enumerate(open(table_path, encoding="utf-8"), 1):
    m = re.match(r"\s*\|\s*(\d+\.\d+|cppcheck:\w+)\s*\|([^|]*)\|([^|]*)\|([^|]*)\|\s*$", line)
    if not m:
        continue
    globs = re.findall(r"`([^`]+)`", m.group(2))
    if not globs or not m.group(3).strip() or not m.group(4).strip():
        sys.exit(f"{table_path}:{lineno}: a deviation needs a rule, file globs, a reason and a guard")
    deviations.append({"rule": m.group(1), "globs": globs, "line": lineno, "used": 0})

def matches(path, patterns):
    return any(fnmatch.fnmatch(path, p) for p in patterns)

# key (file, line, rule) -> set of precisions; other cppcheck messages on our files
seen = collections.defaultdict(set)
tool_errors = []
for raw in open(findings_path, encoding="utf-8", errors="replace"):
    precision, path, line, ident, message = raw.rstrip("\n").split("|", 4)
    path = os.path.relpath(path) if os.path.isabs(path) and path.startswith(os.getcwd()) else path
    if not path.startswith("csrc/"):
        if ident.startswith("misra-") or path != "nofile":
            continue  # the C library's headers and the predefined macros: not ours
    if ident in ("toomanyconfigs", "missingIncludeSystem", "checkersReport"):
        continue
    if ident in ("preprocessorErrorDirective", "syntaxError", "internalError", "internalAstError",
                 "unknownMacro", "cppcheckError") or not path.startswith("csrc/"):
        tool_errors.append(f"{precision}: {path}:{line}: {ident}: {message}")
        continue
    rule = ident[len("misra-c2012-"):] if ident.startswith("misra-c2012-") else "cppcheck:" + ident
    seen[(path, int(line), rule)].add(precision)

def rule_key(rule):
    if rule.startswith("cppcheck:"):
        return (1, (), rule)
    return (0, tuple(int(x) for x in rule.split(".")), "")

counts = collections.defaultdict(lambda: collections.Counter())
violations = []
for (path, line, rule), precisions in sorted(seen.items()):
    where = "both" if len(precisions) == 2 else next(iter(precisions))
    if matches(path, not_gated):
        kind = "not gated"
    else:
        row = next((d for d in deviations if d["rule"] == rule and matches(path, d["globs"])), None)
        if row is not None:
            row["used"] += 1
            kind = "deviated"
        else:
            kind = "violation"
            violations.append(f"{path}:{line}: MISRA C:2012 rule {rule} ({where})")
    counts[rule][kind] += 1
    if listing:
        print(f"{path}:{line}: rule {rule} [{kind}] ({where})")

print("MISRA C:2012 (cppcheck addon), firmware part, double + float builds")
print(f"{'rule':>22} {'violations':>10} {'deviated':>9} {'not gated':>10}")
for rule in sorted(counts, key=rule_key):
    c = counts[rule]
    print(f"{rule:>22} {c['violation']:>10} {c['deviated']:>9} {c['not gated']:>10}")
total = collections.Counter()
for c in counts.values():
    total.update(c)
print(f"{'total':>22} {total['violation']:>10} {total['deviated']:>9} {total['not gated']:>10}")
print("not yet gated: " + " ".join(not_gated))

status = 0
for v in violations:
    print("violation: " + v, file=sys.stderr)
    status = 1
for d in deviations:
    if d["used"] == 0:
        print(f"{table_path}:{d['line']}: stale deviation: rule {d['rule']} matches no finding in "
              + ", ".join(d["globs"]), file=sys.stderr)
        status = 1
for e in tool_errors:
    print("cppcheck: " + e, file=sys.stderr)
    status = 2
if status == 0:
    print("misra: no finding outside the deviations in the gated files")
sys.exit(status)
PY
