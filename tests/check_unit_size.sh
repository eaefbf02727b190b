#!/usr/bin/env bash
# Single-purpose units (docs/design.md, "Layout"): no source of the library or the tools over
# 600 lines, and no function anywhere over the .clang-tidy limit of readability-function-size.
#   bash tests/check_unit_size.sh <build dir with compile_commands.json> [clang-tidy]
set -euo pipefail
cd "$(dirname "$0")/.."
build=$1
tidy=${2:-clang-tidy}
max_lines=600
status=0

while IFS= read -r f; do
    n=$(wc -l <"$f")
    if [ "$n" -gt "$max_lines" ]; then
        echo "$f: $n lines (at most $max_lines: split it by concept)"
        status=1
    fi
done < <(find libsemloc libsemloc_tools apps -name '*.cpp' -o -name '*.h' | sort)

# Every translation unit the build compiles (library, tools, tests, benchmarks), checked by
# .clang-tidy's readability-function-size alone.
mapfile -t units < <(sed -n 's/^ *"file": "\(.*\)",*$/\1/p' "$build/compile_commands.json" | sort -u)
if [ ${#units[@]} -eq 0 ]; then
    echo "no translation unit in $build/compile_commands.json"
    exit 1
fi
out=$("$tidy" -p "$build" --quiet --checks='-*,readability-function-size' "${units[@]}" 2>/dev/null |
      grep -E 'warning: .*readability-function-size' || true)
if [ -n "$out" ]; then
    echo "$out"
    status=1
fi
[ "$status" -eq 0 ] && echo "${#units[@]} translation units: every source <= $max_lines lines, every function within .clang-tidy's limits"
exit "$status"
