#!/usr/bin/env bash
# Runs docs/auv-own-log.md as written: every ```sh block, in order, from a scratch copy of the
# repository's layout (doc_blocks.sh), and checks that
# - every command succeeds, and each line of the plain ``` block after a ```sh block appears in
#   that block's output;
# - the simulated survey the page makes again equals the shipped data/auv_survey/;
# - the calibrated ini holds every key the page says semloc-calibrate fits, with its comment.
# Usage: check_auv_walkthrough.sh <source dir> <bin dir> <scratch dir>
set -euo pipefail
src=$1 bin=$2 scratch=$3
doc="$src/docs/auv-own-log.md"
# shellcheck source=doc_blocks.sh
source "$(dirname "$0")/doc_blocks.sh"
setup_scratch "$src" "$bin" "$scratch"
fail=0
run_doc_blocks "$doc" "$scratch" 4

if ! diff -r "$src/data" "$scratch/data"; then
  echo "FAIL: the page's commands do not make the shipped data/ again"; fail=1
fi
ini="$scratch/build/auv/calibrated.ini"
for key in sigma_range_m p_detect_near p_detect_far clutter_per_scan sigma_deg p_outlier sigma_m a1 a3; do
  grep -Eq "^$key +=.*// calibrated: " "$ini" || { echo "FAIL: $key is not calibrated in $ini"; fail=1; }
done
grep -q '^## sideScanMap' "$scratch/build/auv/calibration/report.md" ||
  { echo "FAIL: report.md has no side-scan section"; fail=1; }
[ "$fail" -eq 0 ] && echo "AUV walkthrough OK"
exit "$fail"
