#!/usr/bin/env bash
# Runs docs/your-own-data.md as written: every ```sh block, in order, from a scratch copy of the
# repository's layout (build/bin -> the built tools; config/, maps/ linked; data/ copied), and
# checks that
# - every command succeeds;
# - each line of the plain ``` block that follows a ```sh block appears in that block's output;
# - the simulated dataset the walkthrough makes again equals the shipped data/example/, and
#   the real run in data/ is left as it is;
# - the outputs the page shows exist (calibrated inis with their fits, the report with its
#   consistency table, figures).
# Usage: check_walkthrough.sh <source dir> <bin dir> <scratch dir>
set -euo pipefail
src=$1 bin=$2 scratch=$3
doc="$src/docs/your-own-data.md"
# shellcheck source=doc_blocks.sh
source "$(dirname "$0")/doc_blocks.sh"
setup_scratch "$src" "$bin" "$scratch"
fail=0
run_doc_blocks "$doc" "$scratch" 5

if ! diff -r "$src/data" "$scratch/data"; then
  echo "FAIL: the walkthrough's commands do not make the shipped data/ again"; fail=1
fi
own="$scratch/build/own"
for f in calibrated.ini calibration/report.md calibration/fig_residuals.png \
         calibration/fig_detection.png calibration/fig_odometry.png mrclam_run/particles.csv \
         mrclam_figures/run.png mrclam_figures/error.png mrclam_figures/run.gif \
         sim_calibrated.ini run2_calibrated/summary.yaml; do
  [ -s "$own/$f" ] || { echo "FAIL: $own/$f missing or empty"; fail=1; }
done
for ini in calibrated.ini sim_calibrated.ini; do
  for key in sigma_range_m sigma_bearing_deg p_detect_near p_detect_far clutter_per_scan p_confusion; do
    grep -Eq "^$key +=.*// calibrated: " "$own/$ini" || { echo "FAIL: $key is not calibrated in $ini"; fail=1; }
  done
done
# The consistency stage ran on the real run and its table is in the report.
grep -q '^## Consistency' "$own/calibration/report.md" || { echo "FAIL: report.md has no consistency table"; fail=1; }
# The figures the page shows are the ones these commands draw (same size in pixels).
for f in fig_residuals.png fig_detection.png fig_odometry.png; do
  cmp -s <(head -c 24 "$src/docs/figures/own-data/$f") <(head -c 24 "$own/calibration/$f") ||
    { echo "FAIL: docs/figures/own-data/$f is not a figure of this size"; fail=1; }
done
[ "$fail" -eq 0 ] && echo "walkthrough OK"
exit "$fail"
