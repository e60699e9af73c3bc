#!/usr/bin/env bash
# Force-against-time plots for docs/haptics.md: runs `hdm feel --trace` for the slide and thin
# scenarios in proxy and penalty mode and plots them with gnuplot into docs/img/haptics_*.png.
#
# Usage: scripts/haptics_plots.sh [BUILD_DIR] [OUT_DIR]
#   BUILD_DIR  build directory holding bin/hdm (default: build-haptics)
#   OUT_DIR    where the model and traces go (default: out/haptics)
# Env: RATE=1000 (servo rate [Hz]). Needs gnuplot (gnuplot-nox). Takes a few seconds.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build-haptics}
OUT=${2:-out/haptics}
RATE=${RATE:-1000}
HDM="$BUILD/bin/hdm"
IMG=docs/img
mkdir -p "$OUT" "$IMG"
[ -x "$HDM" ] || { echo "no $HDM: build the hdm_cli target first" >&2; exit 1; }
[ -s "$OUT/bunny.hdm" ] || "$HDM" bake data/meshes/bunny00.off -o "$OUT/bunny.hdm" > /dev/null
for s in slide thin; do
  for m in proxy penalty; do
    "$HDM" feel "$OUT/bunny.hdm" --scenario "$s" --mode "$m" --rate "$RATE" --trace "$OUT/${s}_${m}.csv" > /dev/null
  done
done

plot() {  # name title column ylabel
  gnuplot <<GP
set terminal pngcairo size 900,420 font ",10"
set output "$IMG/haptics_$1.png"
set datafile separator ","
set key top right
set grid
set title "$2"
set xlabel "time [s]"
set ylabel "$4"
plot "$OUT/$1_penalty.csv" every ::1 using 1:$3 with lines lw 1.5 lc rgb "#d62728" title "penalty (paper)", \
     "$OUT/$1_proxy.csv" every ::1 using 1:$3 with lines lw 1.5 lc rgb "#1f77b4" title "proxy (god-object)"
GP
}
plot slide "slide: stroke over the bunny's back and back again at 10 cm/s, hand pressing 1 N (${RATE} Hz)" 8 "|force| [N]"
plot thin "thin: push through the bunny's ear with max force 3.3 N, hold, retract (${RATE} Hz)" 9 \
  "force along the first contact direction [N]"
ls -la "$IMG"/haptics_*.png
