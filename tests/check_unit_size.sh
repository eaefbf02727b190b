#!/usr/bin/env bash
# Single-purpose units (docs/design.md, "Layout"): no source of the library or the tools over
# 600 lines, and no function of theirs over the .clang-tidy limit of readability-function-size.
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

# Every translation unit of the library, the tools, the apps and the benchmarks that the build
# compiles, checked by .clang-tidy's readability-function-size alone (the tests, a third of the
# units and half of the parsing time, are held to it by the clang-tidy run of each change).
mapfile -t units < <(sed -n 's/^ *"file": "\(.*\)",*$/\1/p' "$build/compile_commands.json" |
                     grep -E "^$PWD/(libsemloc|libsemloc_tools|apps|bench|examples)/" | sort -u)
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
[ "$status" -eq 0 ] && echo "${#units[@]} translation units of the library, tools, apps and benchmarks: every source <= $max_lines lines, every function within .clang-tidy's limits"
exit "$status"
