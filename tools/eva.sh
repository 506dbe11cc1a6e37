#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
#
# tools/eva.sh - run-time-error analysis of the gated core modules with Frama-C's Eva
# (Debian's frama-c-base, installed by tools/bootstrap.sh); docs/eva.md explains it.
#
# Usage:  tools/eva.sh [--keep] [DRIVER...]   (--keep: leave the full Eva logs in build-eva/;
#         DRIVER: analyse these drivers instead of tests/eva/eva_*.c, e.g. a pending one)
#
# One analysis per driver, tests/eva/eva_*.c: a driver calls every public function of the
# modules named on its "eva-modules:" line with every input unconstrained (NaN and
# infinities included) and reads every output afterwards, so an alarm is a possible
# run-time error (invalid access, uninitialized read, signed overflow, invalid shift or
# conversion, ...) or an output some path leaves unwritten.  Its "eva-split-return:" and
# "eva-slevel:" lines give the per-function options of that analysis ({f}: the suffix of
# public names in the build, _f for float), "eva-precision:" its -eva-precision (3 when
# absent) and "eva-options:" any further Eva options; its "eva-support:" line names modules
# it calls into that another driver covers (compiled and analysed here too, alarms count,
# but not required to be reached); its "eva-defines:" line, preprocessor options.
# Two runs of each:
#   double  -machdep x86_64  (LP64: a host, the Python bindings)
#   float   -machdep x86_32  (ILP32: the data model of a Cortex-M firmware) -DZW_REAL_FLOAT
# Every alarm a run leaves must be listed in tests/eva/expected_alarms.txt (run, file,
# function, kind, property: no line numbers) with the key of its argument in docs/eva.md,
# and every listed one must still occur: fails (exit 1) on a new alarm, on a listed alarm
# that is gone, on a key without its row in docs/eva.md, on an Eva warning or error, or
# when a function of a driver's modules is not reached; exit 2 when Frama-C is missing.
# Time: see docs/eva.md (per run; ZW_EVA_JOBS runs at a time, default 2).
set -euo pipefail
cd "$(dirname "$0")/.."

# The drivers; their modules are the gated ones of tools/misra.sh.  A module is added by
# naming it on a driver's "eva-modules:" line (a new area: a new driver file).
DRIVERS=(tests/eva/eva_*.c)

# A driver's header line "eva-KEY: value" (empty when absent).
driver_line() { sed -n "s/^ \* eva-$2: *//p" "$1" | head -n 1; }

# Options, explained in docs/eva.md.  $1: the driver, $2: the suffix of public names in this
# build (_f in the float build, zwidth/precision.h).
eva_options() {
    local driver=$1 f=$2 split slevel precision extra
    split=$(driver_line "$driver" split-return)
    slevel=$(driver_line "$driver" slevel)
    precision=$(driver_line "$driver" precision)
    extra=$(driver_line "$driver" options)
    printf '%s\n' -eva -warn-special-float none -eva-precision "${precision:-3}" -eva-split-return auto
    [ -z "$split" ] || printf '%s\n' -eva-split-return-function "${split//\{f\}/$f}"
    [ -z "$slevel" ] || printf '%s\n' -eva-slevel-function "${slevel//\{f\}/$f}"
    [ -z "$extra" ] || printf '%s\n' $extra
}

keep=0
case "${1:-}" in
    "") ;;
    --keep) keep=1; shift ;;
    -h|--help) sed -n '2,/^[^#]/{/^#/p}' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "eva.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) ;;
esac
case "${1:-}" in
    "") ;;
    -*) echo "eva.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) DRIVERS=("$@") ;;
esac

if ! command -v frama-c >/dev/null 2>&1; then
    echo "eva.sh: frama-c is missing (tools/bootstrap.sh installs frama-c-base)" >&2
    exit 2
fi

if [ "$keep" = 1 ]; then
    out=build-eva
    mkdir -p "$out"
else
    out=$(mktemp -d "${TMPDIR:-/tmp}/zw-eva.XXXXXX")
    trap 'rm -rf "$out"' EXIT
fi

run() { # run DRIVER NAME MACHDEP DEFINES SUFFIX
    local driver=$1 name=$2 machdep=$3 defines=$4 suffix=$5 options sources=() module
    for module in $(driver_line "$driver" modules) $(driver_line "$driver" support); do
        sources+=("csrc/src/$module.c")
    done
    mapfile -t options < <(eva_options "$driver" "$suffix")
    defines="$defines $(driver_line "$driver" defines)"
    local start=$SECONDS
    frama-c -machdep "$machdep" -cpp-extra-args="-Icsrc/include -Icsrc/src $defines" \
        "${sources[@]}" tests/eva/libm_spec.c "$driver" "${options[@]}" \
        -then -metrics -metrics-eva-cover -report-csv "$out/$name.csv" >"$out/$name.log" 2>&1 &&
        echo $((SECONDS - start)) >"$out/$name.seconds"
}
# Every run (driver x build) is an independent Frama-C process: ZW_EVA_JOBS of them at a
# time (default 2, the cores of the CI machine), each started as soon as one ends.
jobs_max=${ZW_EVA_JOBS:-2}
analyses=()
names=()
for driver in "${DRIVERS[@]}"; do
    area=$(basename "$driver" .c)
    area=${area#eva_}
    if [ -z "$(driver_line "$driver" modules)" ]; then
        echo "eva.sh: $driver has no 'eva-modules:' line" >&2
        exit 2
    fi
    analyses+=("$area:$(driver_line "$driver" modules | tr ' ' ',')")
done
for driver in "${DRIVERS[@]}"; do
    area=$(basename "$driver" .c)
    area=${area#eva_}
    for build in double float; do
        while [ "$(jobs -rp | wc -l)" -ge "$jobs_max" ]; do
            wait -n || true
        done
        if [ "$build" = double ]; then
            run "$driver" "$area-double" x86_64 "" "" &
        else
            run "$driver" "$area-float" x86_32 "-DZW_REAL_FLOAT" _f &
        fi
        names+=("$area-$build")
    done
done
wait || true
for name in "${names[@]}"; do
    # a run that failed wrote no time
    if [ ! -f "$out/$name.seconds" ]; then
        echo "eva.sh: frama-c failed on the run $name; its log:" >&2
        tail -n 20 "$out/$name.log" >&2
        exit 2
    fi
done
echo "eva.sh: all runs done in $SECONDS s of wall time ($jobs_max at a time)"

python3 - "$out" "${analyses[@]}" <<'PY'
import collections, csv, os, re, sys

out = sys.argv[1]
runs = []
for analysis in sys.argv[2:]:
    area, mods = analysis.split(":")
    for precision in ("double", "float"):
        runs.append((f"{area}-{precision}", mods.split(",")))

# The alarms a run is known to leave, each argued in docs/eva.md under its key (a line:
# run, file, function, kind, property, key; tab-separated; '#' comments).  A run must leave
# exactly these: a new alarm fails, and so does a listed one that no longer occurs.
BASELINE = "tests/eva/expected_alarms.txt"
expected = collections.defaultdict(collections.Counter)
keys = {}
docs = open("docs/eva.md", encoding="utf-8").read()
failed = False
for number, line in enumerate(open(BASELINE, encoding="utf-8"), 1):
    line = line.rstrip("\n")
    if not line.strip() or line.startswith("#"):
        continue
    fields = line.split("\t")
    if len(fields) != 6 or not re.fullmatch(r"[A-Z]\d+", fields[5]):
        print(f"eva: {BASELINE}:{number}: not 'run file function kind property key'")
        failed = True
        continue
    if f"| {fields[5]} |" not in docs:
        print(f"eva: {BASELINE}:{number}: key {fields[5]} has no row in docs/eva.md")
        failed = True
    expected[fields[0]][tuple(fields[1:5])] += 1
    keys[(fields[0],) + tuple(fields[1:5])] = fields[5]

for name, modules in runs:
    log = open(os.path.join(out, name + ".log"), encoding="utf-8").read()
    m = re.search(r"(\d+) alarms? generated by the analysis|No alarm", log)
    count = int(m.group(1)) if m and m.group(1) else 0
    eva_problems = re.search(r"by the Eva analyzer:\s+(\d+) errors?\s+(\d+) warnings?", log)
    # a run with no message at all says so in other words (then there is no count to read)
    clean = re.search(r"No errors or warnings raised during the analysis", log)
    eva_errors, eva_warnings = ((int(eva_problems.group(1)), int(eva_problems.group(2))) if eva_problems
                                else (0, 0) if clean else (1, 0))
    # Every property Eva could not prove (its alarms, and any unproved annotation of ours),
    # from the report's CSV, keyed without line numbers (edits elsewhere move them); but
    # not the assigns/from clauses of library functions without a body (nextafterf,
    # signbit): their contracts are taken as given (docs/eva.md), Eva cannot check them.
    found = collections.Counter()
    with open(os.path.join(out, name + ".csv"), encoding="utf-8", newline="") as f:
        for row in csv.DictReader(f, delimiter="\t"):
            if row["property kind"] in ("assigns clause", "from clause"):
                continue
            if "Unknown" in row["status"] or "Invalid" in row["status"]:
                prop = " ".join(row["property"].split())
                found[(row["file"], row["function"], row["property kind"], prop)] += 1
    # Coverage of our own functions (metrics: "name: N stmts out of M"; a static inline
    # function of a header appears once per file as name_0, name_1, ...; the float build
    # renames the public ones to name_f).
    stmts = {}
    for fname, done, total in re.findall(r"^  (\w+): (\d+) stmts out of (\d+)", log, re.M):
        stmts[fname] = (int(done), int(total))
    defined = set()
    for module in modules:
        src = open(f"csrc/src/{module}.c", encoding="utf-8").read()
        defined.update(re.findall(r"^[A-Za-z][\w \*]*?\b(\w+)\([^;]*?\)\s*\n\{", src, re.M))
    unreached = sorted(f for f in defined if f not in stmts and f + "_f" not in stmts)
    done = sum(stmts.get(f, stmts.get(f + "_f", (0, 0)))[0] for f in defined)
    total = sum(stmts.get(f, stmts.get(f + "_f", (0, 0)))[1] for f in defined)
    known = expected.get(name, collections.Counter())
    new = found - known
    gone = known - found
    seconds = open(os.path.join(out, name + ".seconds"), encoding="utf-8").read().strip()
    print(f"eva {name} ({seconds} s): {count} alarm(s), {sum(known.values())} of them listed in {BASELINE}; "
          f"Eva {eva_errors} error(s), {eva_warnings} warning(s); "
          f"{len(defined) - len(unreached)}/{len(defined)} functions of the modules reached, "
          f"{done}/{total} of their statements")
    for (file, function, kind, prop), n in sorted(new.items()):
        print(f"  new alarm ({n}x) {file} {function}: {kind}: {prop}")
        print(f"    baseline line: {name}\t{file}\t{function}\t{kind}\t{prop}\tKEY")
    for (file, function, kind, prop), n in sorted(gone.items()):
        print(f"  listed alarm gone ({n}x) {file} {function}: {kind}: {prop}: remove it from {BASELINE}")
    if unreached:
        print("  not reached: " + ", ".join(unreached))
    # the log's count cross-checks the CSV (alarms in the log but none in the CSV: the
    # report failed; the log also counts redundant alarms Eva removed, so not equal)
    if new or gone or (count > 0) != (sum(found.values()) > 0) or eva_errors or eva_warnings or unreached:
        failed = True
if failed:
    print("eva: FAILED (docs/eva.md: fix the code, or prove the alarm away, or argue it there and list it)", file=sys.stderr)
    sys.exit(1)
print(f"eva: every alarm is one listed in {BASELINE} (argued in docs/eva.md), every function of the modules reached, in both builds of every driver")
PY
