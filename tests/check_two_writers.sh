#!/usr/bin/env bash
# Two writers into one output, started at the same instant, 20 tries for each tool
# (semloc-localize, semloc-benchmark shards, semloc-calibrate): exactly one succeeds, the other
# fails at once naming the first one's process, and the output is the winner's, whole.
#   check_two_writers.sh <bin dir> <source dir> <scratch dir> [tries]
set -euo pipefail
bin=$1 src=$2 out=$3 tries=${4:-20}
rm -rf "$out" && mkdir -p "$out" && cd "$out"
loc=$src/config/localize
"$bin/semloc-simulate" "$src/config/simulate/simulate.ini" -o data.rawlog --seed 1 > /dev/null

# steps.csv without its timing column (update_us).
steps() { cut -d, -f1-13,15- "$1/steps.csv"; }

# race TOOL-ARGS-A -- TOOL-ARGS-B: both released at once; sets rcA rcB pidA pidB.
race() {
  local a=() b=()
  while [ "$1" != "--" ]; do a+=("$1"); shift; done
  shift
  b=("$@")
  rm -f go
  (while [ ! -e go ]; do sleep 0.005; done; exec "${a[@]}") > a.log 2>&1 &
  pidA=$!
  (while [ ! -e go ]; do sleep 0.005; done; exec "${b[@]}") > b.log 2>&1 &
  pidB=$!
  touch go
  set +e
  wait "$pidA"; rcA=$?
  wait "$pidB"; rcB=$?
  set -e
}

# The loser must fail naming the winner; prints the winner (A or B).
winner() {
  local what=$1
  if [ "$rcA" = 0 ] && [ "$rcB" != 0 ]; then
    grep -q "is in use by process $pidA" b.log || { echo "FAIL: $what: the loser does not name process $pidA:"; cat b.log; exit 1; }
    echo A
  elif [ "$rcB" = 0 ] && [ "$rcA" != 0 ]; then
    grep -q "is in use by process $pidB" a.log || { echo "FAIL: $what: the loser does not name process $pidB:"; cat a.log; exit 1; }
    echo B
  else
    echo "FAIL: $what: exit codes $rcA and $rcB (exactly one must succeed)" >&2
    cat a.log b.log >&2
    exit 1
  fi
}

# semloc-localize: seeds 1 and 2 into one directory.
for s in 1 2; do
  "$bin/semloc-localize" "$loc/semantic.ini" data.rawlog -o "ref$s" -q -s "$s" -n 3000 > /dev/null
done
wins=""
for i in $(seq "$tries"); do
  rm -rf out
  race "$bin/semloc-localize" "$loc/semantic.ini" data.rawlog -o out -q -s 1 -n 3000 -- \
       "$bin/semloc-localize" "$loc/semantic.ini" data.rawlog -o out -q -s 2 -n 3000
  w=$(winner "localize try $i") || exit 1
  ref=$([ "$w" = A ] && echo ref1 || echo ref2)
  diff <(steps out) <(steps "$ref") > /dev/null || { echo "FAIL: localize try $i: out/steps.csv is not the winner's"; exit 1; }
  wins+=$w
done
echo "localize: $tries tries, one writer each (winners $wins)"

# semloc-benchmark: two shards of one benchmark into one directory.
cat > bench.ini <<INI
[Benchmark]
runs = 2
variants = $loc/semantic.ini
simulate_ini = $src/config/simulate/simulate.ini
max_steps = 100
particles = 1000
jobs = 1
output_dir = whole
INI
wins=""
for i in $(seq "$tries"); do
  rm -rf shard
  race "$bin/semloc-benchmark" bench.ini --runs 1:1 -o shard -- \
       "$bin/semloc-benchmark" bench.ini --runs 2:2 -o shard
  w=$(winner "benchmark try $i") || exit 1
  run=$([ "$w" = A ] && echo 1 || echo 2)
  grep -qx "first $run" shard/shard.txt && grep -qx "last $run" shard/shard.txt ||
    { echo "FAIL: benchmark try $i: shard.txt is not the winner's runs $run:$run"; exit 1; }
  [ "$(ls shard/runs | grep -c '\.txt$')" = 1 ] && [ -e "shard/runs/run_00000$run.txt" ] ||
    { echo "FAIL: benchmark try $i: the run files are not the winner's alone"; ls shard/runs; exit 1; }
  wins+=$w
done
echo "benchmark shards: $tries tries, one writer each (winners $wins)"

# semloc-calibrate: two bases into one calibrated ini.
cal() {
  "$bin/semloc-calibrate" data.rawlog --world "$src/maps/paper_50x50.yaml" --ground-truth data_gt.txt \
    --consistency-seeds 0 --base "$loc/$1.ini" -o "$2"
}
cal semantic ref_semantic.ini > /dev/null 2>&1
cal semantic_basic ref_semantic_basic.ini > /dev/null 2>&1
cmp -s ref_semantic.ini ref_semantic_basic.ini && { echo "FAIL: the two bases calibrate alike"; exit 1; }
wins=""
for i in $(seq "$tries"); do
  rm -f cal.ini
  race "$bin/semloc-calibrate" data.rawlog --world "$src/maps/paper_50x50.yaml" --ground-truth data_gt.txt \
         --consistency-seeds 0 --base "$loc/semantic.ini" -o cal.ini -- \
       "$bin/semloc-calibrate" data.rawlog --world "$src/maps/paper_50x50.yaml" --ground-truth data_gt.txt \
         --consistency-seeds 0 --base "$loc/semantic_basic.ini" -o cal.ini
  w=$(winner "calibrate try $i") || exit 1
  ref=$([ "$w" = A ] && echo ref_semantic.ini || echo ref_semantic_basic.ini)
  cmp -s cal.ini "$ref" || { echo "FAIL: calibrate try $i: cal.ini is not the winner's"; exit 1; }
  wins+=$w
done
echo "calibrate: $tries tries, one writer each (winners $wins)"
