#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
#
# Tag every file that lacks its licensing information with the project's two SPDX lines
#     SPDX-FileCopyrightText: 2026 The zwidth authors
#     SPDX-License-Identifier: Apache-2.0
# in a comment at its top (after a shebang; above the file's own first comment), then
# check the whole tree with `reuse lint` (REUSE 3.3).  Idempotent: a file that carries the
# tags already, in any form, is left alone, as is one covered by REUSE.toml (images,
# empty marker files, reports a generator rewrites whole), so it can be re-run after every
# merge to tag what the merge brought in.
#
# The files come from `reuse lint` itself (every file git does not ignore that lacks a
# tag); the comment style from the table below, so the result does not depend on
# reuse's guess.  A file of a kind the table does not know stops the run with its name:
# give it a style here, or an entry in REUSE.toml if it cannot carry a comment.
#
# Usage: tools/spdx.sh [--check]   (--check: tag nothing, only run reuse lint)
# Needs reuse (PyPI, tools/requirements-test.txt); uses .venv/bin/reuse when present.
set -euo pipefail
cd "$(dirname "$0")/.."
REUSE=${REUSE:-$( [ -x .venv/bin/reuse ] && echo .venv/bin/reuse || echo reuse )}
PY=${PYTHON:-$( [ -x .venv/bin/python ] && echo .venv/bin/python || echo python3 )}

if [ "${1:-}" != --check ]; then
    untagged=$({ "$REUSE" lint --json || true; } | "$PY" -c '
import json, sys
bad = json.load(sys.stdin)["non_compliant"]
print("\n".join(sorted(set(bad["missing_licensing_info"]) | set(bad["missing_copyright_info"]))))')
    declare -A by_style=()
    unknown=()
    while IFS= read -r f; do
        [ -n "$f" ] || continue
        case "$f" in
            *.c|*.h|*.cpp|*.hpp|*.c.in|*.h.in|*.ld) style=c ;;
            *.md) style=html ;;
            *.py|*.pyi|*.sh|*.cmake|*/CMakeLists.txt|CMakeLists.txt|*.toml|*.txt|*.ini|*.cfg|*.in|*.yml|*.yaml|.gitignore|*/.gitignore|.ci/*) style=python ;;
            *) unknown+=("$f"); continue ;;
        esac
        by_style[$style]+="$f"$'\n'
    done <<<"$untagged"
    if [ ${#unknown[@]} -gt 0 ]; then
        printf 'spdx.sh: no comment style known for %s (add one to tools/spdx.sh, or the file to REUSE.toml)\n' "${unknown[@]}" >&2
        exit 1
    fi
    for style in "${!by_style[@]}"; do
        mapfile -t files < <(printf '%s' "${by_style[$style]}")
        "$REUSE" annotate --template zwidth --copyright "The zwidth authors" --year 2026 \
            --copyright-prefix spdx --license Apache-2.0 --skip-existing --style "$style" "${files[@]}" |
            sed 's/^/spdx.sh: /'
    done
fi
"$REUSE" lint --lines || { echo "spdx.sh: reuse lint failed (run tools/spdx.sh to tag the files above)" >&2; exit 1; }
echo "spdx.sh: reuse lint: every file carries its copyright and license"
