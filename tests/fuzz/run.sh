#!/usr/bin/env bash
# A short run of every libFuzzer target (docs/testing.md, "Fuzzing"):
#   bash tests/fuzz/run.sh [seconds per target, default 60]
# Builds the targets in build-asan/ (clang, ASan + UBSan; the directory tests/sanitize.sh
# builds, see tests/sanitizer_env.sh), runs each from its seed corpus
# tests/fuzz/corpus/<target>/ plus a working corpus kept in build-asan/fuzz/corpus/<target>/,
# prints libFuzzer's figures (runs, cov, ft, corpus) and fails if any target crashed, leaked,
# hung or ran out of memory (the input is saved as build-asan/fuzz/<target>-crash-*, -leak-*,
# -timeout-*, -oom-*).
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
seconds=${1:-60}
source tests/sanitizer_env.sh
targets=(world ini deserialize import_odometry import_detections import_ground_truth
         import_landmarks)
semloc_configure
cmake --build "$SEMLOC_ASAN_DIR" -j2 --target "${targets[@]/#/fuzz_}"

out=$root/$SEMLOC_ASAN_DIR/fuzz
failed=()
summary=()
for t in "${targets[@]}"; do
    mkdir -p "$out/corpus/$t"
    # fuzz_ini runs from config/, where the seeds' relative paths (../maps/...) resolve.
    wd=$root
    [ "$t" = ini ] && wd=$root/config
    echo "[semloc] fuzz_$t for ${seconds} s"
    rc=0
    (cd "$wd" && "$out/fuzz_$t" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 \
        -print_final_stats=1 -artifact_prefix="$out/$t-" "$out/corpus/$t" \
        "$root/tests/fuzz/corpus/$t") >"$out/$t.log" 2>&1 || rc=$?
    last=$(grep -E '^#[0-9]+' "$out/$t.log" | tail -1 || true)
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/$t.log")
    summary+=("fuzz_$t: ${runs:-?} runs; last: ${last:-none}")
    if [ "$rc" -ne 0 ]; then
        failed+=("fuzz_$t")
        tail -60 "$out/$t.log"
    fi
done
printf '[semloc] %s\n' "${summary[@]}"
if [ ${#failed[@]} -gt 0 ]; then
    echo "[semloc] FAILED: ${failed[*]} (logs and inputs in $out)"
    exit 1
fi
echo "[semloc] fuzzing: no crash, leak, hang or out-of-memory"
