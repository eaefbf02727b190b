#!/usr/bin/env bash
# The AUV survey benchmark (config/benchmark/auv.ini) on its first 4 runs: the side-scan filter
# converges in every run with a position RMSE of at most 1 m and ends at most a fifth of dead
# reckoning's final error; the fixes with the side-scan are at least as good as the fixes
# alone; reading the side-scan's slant ranges as horizontal is worse than reading them slant.
#   check_auv_benchmark.sh <semloc-benchmark> <source dir> <scratch dir>
set -euo pipefail
app=$1 src=$2 out=$3
rm -rf "$out" && mkdir -p "$out" && cd "$out"
cat > auv.ini <<INI
base = $src/config/benchmark/auv.ini
[Benchmark]
runs = 4
jobs = 2
output_dir = results
INI
"$app" auv.ini > bench.log
csv=results/results.csv
# mean over the runs of column $2 for variant $1
mean() {
  awk -F, -v v="$1" -v c="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) col = i; next }
       $3 == v { s += $col; n++ } END { if (n == 0) exit 1; printf "%.6f", s / n }' "$csv"
}
converged=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "converged") col = i; next }
                     $3 == "sidescan" && $col != 1 && $col != "true" { n++ } END { print n + 0 }' "$csv")
ss=$(mean sidescan rmse_m) ssf=$(mean sidescan final_err_m) drf=$(mean dead_reckoning final_err_m)
us=$(mean usbl rmse_m) ssu=$(mean sidescan_usbl rmse_m) hor=$(mean sidescan_horizontal rmse_m)
echo "sidescan rmse $ss final $ssf; dead reckoning final $drf; usbl rmse $us; sidescan_usbl rmse $ssu; horizontal rmse $hor; sidescan runs not converged: $converged"
fail() { echo "FAIL: $*"; exit 1; }
[ "$converged" = 0 ] || fail "the side-scan filter did not converge in $converged runs"
awk -v a="$ss" 'BEGIN { exit !(a <= 1.0) }' || fail "sidescan RMSE $ss m > 1 m"
awk -v a="$ssf" -v b="$drf" 'BEGIN { exit !(5 * a <= b) }' || fail "sidescan final $ssf m > dead reckoning's $drf m / 5"
awk -v a="$ssu" -v b="$us" 'BEGIN { exit !(a <= b) }' || fail "sidescan_usbl RMSE $ssu m > usbl's $us m"
awk -v a="$hor" -v b="$ss" 'BEGIN { exit !(a > b) }' || fail "slant read as horizontal ($hor m) is not worse than slant ($ss m)"
echo "PASS"
