#!/usr/bin/env bash
# What large maps cost the tools (docs/performance.md, "Large maps"):
#   - a beacon map of 100 000 beacons (the paper world's three and 99 997 on a 29 m grid
#     around it, 10 m below: about 155 answer a ping within the transducer's 200 m), 10 steps of
#     config/simulate/simulate_lbl.ini localized by semantic_lbl.ini with 200 particles on one
#     thread: the filter time per step;
#   - a landmark map of 1 000 000 landmarks (a 4 x 4 km grid, 4 m apart) imported by
#     semloc-import-landmarks (`x y z id` rows, 27 MB) and by semloc-import (`id,label,x,y`
#     rows, 30 MB): the peak resident set and the wall time (/usr/bin/time), beside the
#     same imports of two landmarks (the tools' own memory).
#   bash bench/large_maps.sh [build dir (default build)] [work dir (default /tmp/semloc_large_maps)]
set -euo pipefail
cd "$(dirname "$0")/.."
src=$PWD
bin=$(cd "${1:-build}" && pwd)/bin
work=${2:-/tmp/semloc_large_maps}
rm -rf "$work" && mkdir -p "$work" && cd "$work"

peak() {  # peak RSS [MB] and wall time of a command: "N MB, T s"
    /usr/bin/time -f '%M %e' -o time.txt "$@" >/dev/null 2>run.log || { cat run.log; exit 1; }
    awk '{ printf "%.0f MB, %.1f s", $1 / 1024, $2 }' time.txt
}

# ---- beacons
awk 'BEGIN { print "beacons:" }
     /^beacons:/ { inb = 1; next }
     inb && /^  - / { print; next }
     { inb = 0 }' "$src/maps/paper_50x50_lbl.yaml" > beacons.txt
awk '{ print } /^beacons:/ { exit }' "$src/maps/paper_50x50_lbl.yaml" | sed '$d' > world.yaml
cat beacons.txt >> world.yaml
awk 'BEGIN { n = 0; for (i = 0; i < 317 && n < 99997; i++) for (j = 0; j < 316 && n < 99997; j++) {
         printf "  - {id: %d, x: %.1f, y: %.1f, z: -10}\n", 100 + n, 25.5 + (i - 158) * 29, 25.5 + (j - 158) * 29; n++ } }' >> world.yaml
awk '/^trajectory:/ { on = 1 } on { print }' "$src/maps/paper_50x50_lbl.yaml" >> world.yaml
printf 'base = %s/config/simulate/simulate_lbl.ini\n[Simulation]\nworld_file = %s/world.yaml\nmax_steps = 10\n' \
    "$src" "$work" > sim.ini
printf 'base = %s/config/localize/semantic_lbl.ini\n[LocalizationExperiment]\nmap_file = %s/world.yaml\n' \
    "$src" "$work" > loc.ini
"$bin/semloc-simulate" sim.ini -o beacons.rawlog
"$bin/semloc-localize" loc.ini beacons.rawlog -n 200 -t 1 -q -o beacons_out
awk '/^steps:/ { n = $2 } /^total_update_s:/ { t = $2 }
     END { printf "100 000 beacons: %.2f ms per step (200 particles, 1 thread)\n", 1000 * t / n }' \
    beacons_out/summary.yaml

# ---- landmarks
printf '[Params]\nrandom_seed=123\nnSteps=80\ncircularPath=0\nsquarePathLength=20\nloadLandmarksFromFile=\nodometryNoiseXY_std=0.02\nminSensorDistance=0\nmaxSensorDistance=6\nfieldOfView_deg=180\nstdRange=0.02\nstdYaw_deg=0.5\nstdPitch_deg=0\noutFile=lm.rawlog\noutDir=%s/OUT\nshow_in_3d=false\n[RANDOMSET_1]\nnLandmarks=40\nmin_x=-4\nmax_x=8\nmin_y=-3\nmax_y=8\nmin_z=0\nmax_z=0\n' \
    "$work" > lm.ini
simul-landmarks lm.ini >/dev/null
for n in 2 1000000; do
    awk -v n=$n 'BEGIN { for (i = 1; i <= n; i++) printf "%.3f %.3f 0 %d\n", -1998.5 + 4 * ((i - 1) % 1000), -1998.5 + 4 * int((i - 1) / 1000), i }' > lm_$n.txt
    awk -v n=$n 'BEGIN { print "id,label,x,y"; for (i = 1; i <= n; i++) printf "%d,buoy,%.3f,%.3f\n", i, -1998.5 + 4 * ((i - 1) % 1000), -1998.5 + 4 * int((i - 1) / 1000) }' > lm_$n.csv
done
printf 't,x,y,phi\n1,0,0,0\n2,1,0,0\n3,2,0,0\n' > odom.csv
printf 't,label,range_m,bearing_rad\n1,buoy,3,0.1\n2,,,\n3,buoy,2,0.2\n' > det.csv
printf 't,x,y,phi\n1,5,5,0\n2,6,5,0\n3,7,5,0\n' > gt.csv
for n in 2 1000000; do
    size=$(awk -v b=$(stat -c %s lm_$n.txt) 'BEGIN { printf "%.1f MB", b / 1e6 }')
    echo "semloc-import-landmarks, $n landmarks ($size): $(peak "$bin/semloc-import-landmarks" OUT/lm.rawlog --landmarks lm_$n.txt -o lm_$n.rawlog)"
    size=$(awk -v b=$(stat -c %s lm_$n.csv) 'BEGIN { printf "%.1f MB", b / 1e6 }')
    echo "semloc-import, $n landmarks ($size): $(peak "$bin/semloc-import" -o csv_$n.rawlog --odometry odom.csv --detections det.csv --ground-truth gt.csv --landmarks lm_$n.csv)"
done
