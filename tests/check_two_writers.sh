#!/usr/bin/env bash
# Two writers into one output, 20 tries for each tool (semloc-localize, semloc-benchmark shards,
# semloc-calibrate): the second started while the first holds the output (and, for localize,
# every fourth try both at the same instant): exactly one succeeds, the other fails at once
# naming the first one's process, and the output is the winner's, whole.
#   check_two_writers.sh <bin dir> <source dir> <scratch dir> [tries]
set -euo pipefail
bin=$1 src=$2 out=$3 tries=${4:-20}
rm -rf "$out" && mkdir -p "$out" && cd "$out"
loc=$src/config/localize
"$bin/semloc-simulate" "$src/config/simulate/simulate.ini" -o data.rawlog --seed 1 > /dev/null

# steps.csv without its timing column (update_us).
steps() { cut -d, -f1-13,15- "$1/steps.csv"; }

locks="${TMPDIR:-/tmp}/semloc-locks-$(id -u)"
# Waits until process $1 holds an output lock (its pid on the first line of a lock file);
# fails when it ended first.
wait_locked() {
  for _ in $(seq 15000); do
    grep -qsx "$1" "$locks"/*.lock && return 0
    kill -0 "$1" 2> /dev/null || return 1
    sleep 0.002
  done
  echo "FAIL: process $1 took no output lock within 30 s"; exit 1
}

# race1 --ordered|--at-once TOOL-ARGS-A -- TOOL-ARGS-B: B starts once A holds its output's lock (or,
# --at-once, both are released at the same instant, with work long enough to overlap); sets
# rcA rcB pidA pidB.
race1() {
  local a=() b=() once=0
  [ "$1" = --at-once ] && once=1
  shift
  while [ "$1" != "--" ]; do a+=("$1"); shift; done
  shift
  b=("$@")
  rm -f go
  (while [ ! -e go ]; do sleep 0.005; done; exec "${a[@]}") > a.log 2>&1 &
  pidA=$!
  if [ "$once" = 0 ]; then
    # A holds the output, then stands still (SIGSTOP) until B has ended: B meets the lock
    # however short A's work is.
    touch go
    if ! wait_locked "$pidA" || ! kill -STOP "$pidA" 2> /dev/null; then
      wait "$pidA" || true
      return 1  # A ended before it could be held: the try is made again
    fi
    rm -f go
  fi
  (while [ ! -e go ]; do sleep 0.005; done; exec "${b[@]}") > b.log 2>&1 &
  pidB=$!
  touch go
  set +e
  if [ "$once" = 0 ]; then wait "$pidB"; rcB=$?; kill -CONT "$pidA"; fi
  wait "$pidA"; rcA=$?
  [ "$once" = 0 ] || { wait "$pidB"; rcB=$?; }
  set -e
}

# race, made again (at most 5 times in all) when the first writer ended before it was held.
redone=0
race() {
  until race1 "$@"; do
    redone=$((redone + 1))
    [ "$redone" -le 5 ] || { echo "FAIL: the first writer ended before it could be held, 6 times"; exit 1; }
  done
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
  for n in 1000 10000; do
    "$bin/semloc-localize" "$loc/semantic.ini" data.rawlog -o "ref${s}_$n" -q -s "$s" -n $n > /dev/null
  done
done
wins=""
for i in $(seq "$tries"); do
  rm -rf out
  # Odd tries: seed 1 first; even: seed 2 first; every fourth: both released at once.
  first=$(( i % 2 == 1 ? 1 : 2 )) second=$(( i % 2 == 1 ? 2 : 1 ))
  mode=$([ $(( i % 4 )) = 0 ] && echo --at-once || echo --ordered)
  n=$([ "$mode" = --at-once ] && echo 10000 || echo 1000)
  race $mode "$bin/semloc-localize" "$loc/semantic.ini" data.rawlog -o out -q -s $first -n $n -- \
       "$bin/semloc-localize" "$loc/semantic.ini" data.rawlog -o out -q -s $second -n $n
  w=$(winner "localize try $i") || exit 1
  [ "$mode" = --at-once ] || [ "$w" = A ] || { echo "FAIL: localize try $i: the second writer won"; exit 1; }
  ref=ref$([ "$w" = A ] && echo $first || echo $second)_$n
  diff <(steps out) <(steps "$ref") > /dev/null || { echo "FAIL: localize try $i: out/steps.csv is not the winner's"; exit 1; }
  wins+=$w
done
echo "localize: $tries tries, one writer each (first writer won: $wins)"

# semloc-benchmark: two shards of one benchmark into one directory.
cat > bench.ini <<INI
[Benchmark]
runs = 2
variants = $loc/semantic.ini
simulate_ini = $src/config/simulate/simulate.ini
max_steps = 300
particles = 5000
jobs = 1
output_dir = whole
INI
wins=""
for i in $(seq "$tries"); do
  rm -rf shard
  first=$(( i % 2 == 1 ? 1 : 2 )) second=$(( i % 2 == 1 ? 2 : 1 ))
  race --ordered "$bin/semloc-benchmark" bench.ini --runs $first:$first -o shard -- \
       "$bin/semloc-benchmark" bench.ini --runs $second:$second -o shard
  w=$(winner "benchmark try $i") || exit 1
  [ "$w" = A ] || { echo "FAIL: benchmark try $i: the second writer won"; exit 1; }
  grep -qx "first $first" shard/shard.txt && grep -qx "last $first" shard/shard.txt ||
    { echo "FAIL: benchmark try $i: shard.txt is not the winner's runs $first:$first"; exit 1; }
  [ "$(ls shard/runs | grep -c '\.txt$')" = 1 ] && [ -e "shard/runs/run_00000$first.txt" ] ||
    { echo "FAIL: benchmark try $i: the run files are not the winner's alone"; ls shard/runs; exit 1; }
  wins+=$w
done
echo "benchmark shards: $tries tries, one writer each (first writer won: $wins)"

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
  first=$([ $(( i % 2 )) = 1 ] && echo semantic || echo semantic_basic)
  second=$([ "$first" = semantic ] && echo semantic_basic || echo semantic)
  race --ordered "$bin/semloc-calibrate" data.rawlog --world "$src/maps/paper_50x50.yaml" --ground-truth data_gt.txt \
         --consistency-seeds 0 --base "$loc/$first.ini" -o cal.ini -- \
       "$bin/semloc-calibrate" data.rawlog --world "$src/maps/paper_50x50.yaml" --ground-truth data_gt.txt \
         --consistency-seeds 0 --base "$loc/$second.ini" -o cal.ini
  w=$(winner "calibrate try $i") || exit 1
  [ "$w" = A ] || { echo "FAIL: calibrate try $i: the second writer won"; exit 1; }
  cmp -s cal.ini "ref_$first.ini" || { echo "FAIL: calibrate try $i: cal.ini is not the winner's"; exit 1; }
  wins+=$w
done
echo "calibrate: $tries tries, one writer each (first writer won: $wins)"
echo "first writers that ended before they could be held (tries made again): $redone"
