#!/usr/bin/env bash
# semloc-benchmark's shards: a small benchmark (a sweep of two values, 5 runs) run whole, then
# cut into shards run through GNU parallel (one shard, two, one per run, uneven) and merged:
# results.csv (its timing columns aside) and curves.csv must be the unsharded bytes; merges of
# overlapping, incomplete or mismatched shards are refused, naming them.
#   check_benchmark_shards.sh <semloc-benchmark> <source dir> <scratch dir>
set -euo pipefail
app=$1 src=$2 out=$3
rm -rf "$out" && mkdir -p "$out" && cd "$out"
command -v parallel > /dev/null || { echo "FAIL: GNU parallel is not installed (bash .ci/setup)"; exit 1; }
cat > bench.ini <<INI
[Benchmark]
runs = 5
variants = $src/config/localize/semantic.ini
simulate_ini = $src/config/simulate/simulate.ini
max_steps = 40
particles = 300
jobs = 1
output_dir = whole
sweep = MetricMap_semanticMap_00_likelihoodOpts.sigma_range_m: 0.5, 1.0
INI
"$app" bench.ini > whole.log

# results.csv without its timing columns.
strip() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i ~ /^(total_update_s|mean_update_us_per_particle|wall_time_s)$/) drop[i] = 1 }
           { line = ""; for (i = 1; i <= NF; i++) if (!(i in drop)) line = line (line == "" ? "" : ",") $i; print line }' "$1"
}
[ "$(head -1 whole/results.csv | tr ',' '\n' | grep -c wall_time_s)" = 1 ] || { echo "FAIL: no wall_time_s column"; exit 1; }
[ "$(wc -l < whole/results.csv)" = 11 ] || { echo "FAIL: whole/results.csv: not 5 runs x 2 values"; exit 1; }

check_cut() {  # name, then the shards' runs (A:B each)
  local name=$1; shift
  rm -rf "shards_$name" && mkdir "shards_$name"
  parallel "$app" bench.ini --runs {} -o "shards_$name/{#}" ::: "$@" > "shards_$name.log"
  "$app" --merge shards_"$name"/* -o "merged_$name" > "merge_$name.log"
  if ! diff <(strip whole/results.csv) <(strip "merged_$name/results.csv") > /dev/null; then
    echo "FAIL: $name: the merged results.csv differs from the unsharded one"
    diff <(strip whole/results.csv) <(strip "merged_$name/results.csv") | head
    exit 1
  fi
  cmp whole/curves.csv "merged_$name/curves.csv" || { echo "FAIL: $name: curves.csv differs"; exit 1; }
  echo "cut $name ($*): the unsharded results"
}
check_cut one 1:5
check_cut two 1:2 3:5
check_cut each 1:1 2:2 3:3 4:4 5:5
check_cut uneven 1:1 2:5

# With scenarios: each scenario's runs in the shard, each scenario's outputs merged.
cat > scenario.ini <<INI
[Scenario]
description = a detector of 8 m
[SemanticDetector]
max_range_m = 8
INI
sed -e 's/^output_dir = whole/output_dir = whole_sc/' -e '/^sweep/d' bench.ini > sc.ini
echo "scenarios = scenario.ini" >> sc.ini
"$app" sc.ini > whole_sc.log
parallel "$app" sc.ini --runs {} -o "shards_sc/{#}" ::: 1:3 4:5 > shards_sc.log
"$app" --merge shards_sc/* -o merged_sc > merge_sc.log
diff <(strip whole_sc/scenario/results.csv) <(strip merged_sc/scenario/results.csv) > /dev/null ||
  { echo "FAIL: scenarios: the merged results.csv differs"; exit 1; }
cmp whole_sc/scenarios.csv merged_sc/scenarios.csv || { echo "FAIL: scenarios.csv differs"; exit 1; }
echo "scenarios (1:3 4:5): the unsharded results"
# A shard never replaces a whole benchmark's outputs (here its output_dir, no -o), nor the reverse.
if "$app" sc.ini --runs 1:2 > refused.log 2>&1; then echo "FAIL: a shard replaced whole_sc"; exit 1; fi
grep -qF "output directory 'whole_sc' holds a whole benchmark of 5 runs (scenarios.csv)" refused.log ||
  { echo "FAIL: the refusal did not name what whole_sc holds"; cat refused.log; exit 1; }
cmp whole_sc/scenarios.csv merged_sc/scenarios.csv || { echo "FAIL: whole_sc changed"; exit 1; }

refused() {  # expected message, then the arguments
  local expect=$1; shift
  if "$app" "$@" > refused.log 2>&1; then
    echo "FAIL: accepted: $*"; exit 1
  fi
  grep -qF "$expect" refused.log || { echo "FAIL: '$*' did not say: $expect"; cat refused.log; exit 1; }
  echo "refused: $* ($expect)"
}
"$app" bench.ini --runs 2:3 -o overlap > /dev/null
refused "the shards 'shards_two/1' (runs 1..2) and 'overlap' (runs 2..3) overlap on run 2" \
  --merge shards_two/1 overlap shards_two/2 -o bad
refused "runs 3..5 of the 5 are in no shard" --merge shards_two/1 -o bad
sed 's/^runs = 5/runs = 6/' bench.ini > other.ini
"$app" other.ini --runs 3:6 -o other > /dev/null
refused "are not of one benchmark" --merge shards_two/1 other -o bad
refused "a shard is runs A:B with 1 <= A <= B <= 5" bench.ini --runs 4:6 -o bad
# Refused before anything is printed (no "N runs x M variants" line first).
refused "a shard is runs A:B with 1 <= A <= B <= 5" bench.ini --runs 1:99999 -o bad
[ "$(wc -l < refused.log)" = 1 ] || { echo "FAIL: --runs 1:99999 printed before refusing:"; cat refused.log; exit 1; }
refused "is not a shard of semloc-benchmark" --merge shards_two/1 whole -o bad
[ ! -e bad ] || { echo "FAIL: a refused merge wrote 'bad'"; exit 1; }
echo "benchmark shards OK"
