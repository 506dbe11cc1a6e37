#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
#
# The Python release artifacts, as a user gets them:
#   1. python -m build: the sdist, then the wheel built from that sdist unpacked in a
#      temporary directory (build's default), in an isolated environment with only
#      pyproject.toml's build requirements, so a file the sdist lacks fails the build;
#   2. the sdist's file list: what the build needs is there (and LICENSE, CHANGELOG.md),
#      no build tree, virtualenv, cache, test or benchmark;
#   3. twine check --strict on both (metadata, the README rendered as PyPI would);
#   4. the wheel installed into a fresh virtualenv and its `zwidth` command run from
#      outside the source tree (--version must print the version of version.h).
# Prints the wheel's and the sdist's sizes.
#
# Usage: tools/dist_check.sh [OUT]   (OUT keeps the artifacts; default: a temporary
#        directory, removed afterwards).  Needs build and twine (tools/requirements-test.txt)
#        in .venv, and PyPI or pip's cache for the isolated build and the wheel's dependencies.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-.venv/bin/python}
T=$(mktemp -d "${TMPDIR:-/tmp}/zw-dist.XXXXXX")
trap 'rm -rf "$T"' EXIT
OUT=${1:-$T/dist}
fail() { echo "dist_check: FAIL: $*" >&2; exit 1; }
VERSION=$(sed -n 's/^#define ZW_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9]*\)$/\2/p' \
    csrc/include/zwidth/version.h | paste -sd.)

rm -rf "$OUT"
"$PY" -m build --outdir "$OUT" . >"$T/build.log" 2>&1 || { tail -n 40 "$T/build.log"; fail "python -m build"; }
grep -q "Building wheel from sdist" "$T/build.log" || fail "the wheel was not built from the sdist"
SDIST=$OUT/zwidth-$VERSION.tar.gz
WHEEL=$(ls "$OUT"/zwidth-"$VERSION"-*.whl 2>/dev/null | head -n 1)
[ -f "$SDIST" ] || fail "no $SDIST (python -m build wrote: $(ls "$OUT"))"
[ -n "$WHEEL" ] || fail "no wheel of version $VERSION (python -m build wrote: $(ls "$OUT"))"

tar tzf "$SDIST" | sed "s|^zwidth-$VERSION/||" >"$T/sdist.txt"
for f in pyproject.toml CMakeLists.txt PKG-INFO README.md CHANGELOG.md LICENSE LICENSES/Apache-2.0.txt \
         cmake/zwidthInstall.cmake csrc/include/zwidth/version.h bindings/zwidth_core.cpp \
         python/zwidth/__init__.py python/zwidth/py.typed; do
    grep -qx "$f" "$T/sdist.txt" || fail "the sdist lacks $f"
done
# Every firmware module the CMake build lists must be in it (a new module is, by rule).
for m in $(tools/core_modules.sh | sed 's|[^ ]*|csrc/src/&.c|g'); do
    grep -qx "$m" "$T/sdist.txt" || fail "the sdist lacks $m"
done
if grep -E '(^|/)(build[^/]*|\.venv|__pycache__|\.pytest_cache|\.mypy_cache|\.hypothesis|\.git)/|^(tests|bench|tools)/|\.pyc$' \
        "$T/sdist.txt" >"$T/stray.txt"; then
    head -n 20 "$T/stray.txt" >&2; fail "the sdist holds $(wc -l <"$T/stray.txt") files it should not (above)"
fi

"$PY" -m twine check --strict "$SDIST" "$WHEEL" >"$T/twine.log" 2>&1 || { cat "$T/twine.log"; fail "twine check"; }

"$PY" -m zipfile -l "$WHEEL" >"$T/wheel.txt"
grep -q "dist-info/licenses/LICENSE" "$T/wheel.txt" || fail "the wheel carries no LICENSE"
grep -q "zwidth/_core\..*\.so" "$T/wheel.txt" || fail "the wheel has no compiled zwidth._core"
python3 -m venv "$T/venv"
"$T/venv/bin/python" -m pip install -q --disable-pip-version-check "$WHEEL" >"$T/pip.log" 2>&1 ||
    { cat "$T/pip.log"; fail "pip install of the wheel into a fresh virtualenv"; }
got=$(cd "$T" && "$T/venv/bin/zwidth" --version)
[ "$got" = "zwidth $VERSION" ] || fail "the installed zwidth --version printed '$got', expected 'zwidth $VERSION'"
(cd "$T" && "$T/venv/bin/zwidth" limits --m 0.1 --b 30 --T 0.01 --delay 0 >/dev/null) || fail "zwidth limits from the wheel"
(cd "$T" && "$T/venv/bin/python" -c 'import zwidth, sys; sys.exit(0 if zwidth.check(3.0, 1.0, 0.5) else 1)') ||
    fail "zwidth.check from the wheel"

size() { awk -v b="$(stat -c %s "$1")" 'BEGIN { printf "%.0f", b / 1024 }'; }
echo "dist_check: sdist $(basename "$SDIST") $(size "$SDIST") KiB ($(wc -l <"$T/sdist.txt") files), wheel $(basename "$WHEEL") $(size "$WHEEL") KiB; built from the sdist, twine check passed, the wheel's zwidth runs in a fresh virtualenv"
