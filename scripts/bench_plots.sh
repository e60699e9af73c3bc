#!/usr/bin/env bash
# Scaling plots for docs/performance.md: runs `hdm bench --json` over slab counts, grid sizes and
# input sizes (the input subdivided 1-to-4, slab count fixed: the baselines' mesh grows, the slab
# model does not) and plots latency, bake time and memory with gnuplot into docs/img/bench_*.png.
# Results already in OUT_DIR are reused.
#
# Usage: scripts/bench_plots.sh [BUILD_DIR] [OUT_DIR]
#   BUILD_DIR  build directory holding bin/hdm (default: build-bench)
#   OUT_DIR    where the JSON results go (default: out/bench)
# Env: SLABS="150 300 1000 ..."  GRIDS="4 8 16 32 64"  SUBDIVIDE="0 1 2"  INPUT_SLABS=1178
#      REPEAT=3  MODEL=data/meshes/bunny00.off
# Needs: jq, gnuplot. Takes about 10 minutes on 2 cores (the 100k-slab bake dominates).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build-bench}
OUT=${2:-out/bench}
HDM="$BUILD/bin/hdm"
MODEL=${MODEL:-data/meshes/bunny00.off}
SLABS=${SLABS:-"150 300 1000 3000 10000 30000"}  # add 100000 for the full sweep (+8 min, 10 GB)
GRIDS=${GRIDS:-"4 8 16 32 64"}
GRID_SLABS=${GRID_SLABS:-300}
SUBDIVIDE=${SUBDIVIDE:-"0 1 2"}
INPUT_SLABS=${INPUT_SLABS:-1178}
REPEAT=${REPEAT:-3}
IMG=docs/img
mkdir -p "$OUT" "$IMG"
[ -x "$HDM" ] || { echo "no $HDM: build the hdm_cli target first" >&2; exit 1; }

# Colour texels are 1 per interval (they are not queried; at 10^5 slabs and 2 per interval they
# alone take ~5 GB). Slab separation in the bake is skipped for every run (it is quadratic-ish at 10^4+ slabs and does
# not change what is measured); the grid sweep uses GRID_SLABS slabs.
for s in $SLABS; do
  f="$OUT/slabs_$s.json"
  [ -s "$f" ] || { echo "slabs $s" >&2; "$HDM" bench --model "$MODEL" --slabs "$s" --repeat "$REPEAT" --no-separate-slabs --texels 1 --json > "$f"; }
done
for g in $GRIDS; do
  f="$OUT/grid_$g.json"
  [ -s "$f" ] || { echo "grid $g" >&2; "$HDM" bench --model "$MODEL" --slabs "$GRID_SLABS" --grid "$g" --repeat "$REPEAT" --no-separate-slabs --texels 1 --json > "$f"; }
done

for k in $SUBDIVIDE; do
  f="$OUT/input_$k.json"
  [ -s "$f" ] || { echo "input subdivided $k times" >&2; "$HDM" bench --model "$MODEL" --slabs "$INPUT_SLABS" --subdivide "$k" --repeat "$REPEAT" --json > "$f"; }
done
irow='[.input_triangles, .slabs, .hdm.coherent_ns.median, .hdm.global_ns.median, .baseline.embree_ns.median,
       .baseline.embree_global_ns.median, .baseline.cgal_closest_ns.median, .baseline.cgal_closest_global_ns.median,
       .ratio_coherent, .ratio_global] | @tsv'
: > "$OUT/inputs.tsv"
for k in $SUBDIVIDE; do jq -r "$irow" "$OUT/input_$k.json" >> "$OUT/inputs.tsv"; done

# One row per run: x slabs grid input_tris coh_med coh_p99 glo_med glo_p99 tick_med emb_med emb_glo_med
#                  bake_s bytes_per_slab bytes_per_sample peak_rss_mb edit_ns
row='[.slabs, .grid, .input_triangles, .hdm.coherent_ns.median, .hdm.coherent_ns.p99,
      .hdm.global_ns.median, .hdm.global_ns.p99, .hdm.tick_ns.median, .baseline.embree_ns.median,
      .baseline.embree_global_ns.median, .bake_s, .bytes_per_slab, .bytes_per_sample, .peak_rss_mb,
      .edit_ns_per_sample] | @tsv'
: > "$OUT/slabs.tsv"
for s in $SLABS; do jq -r "$row" "$OUT/slabs_$s.json" >> "$OUT/slabs.tsv"; done
: > "$OUT/grids.tsv"
for g in $GRIDS; do jq -r "$row" "$OUT/grid_$g.json" >> "$OUT/grids.tsv"; done
sort -n -k1 -o "$OUT/slabs.tsv" "$OUT/slabs.tsv"

gnuplot <<EOF
set terminal pngcairo size 800,600 font ",11"
set grid
set key outside below
set logscale xy
set xlabel "slabs"
set ylabel "ns per query (median over repeats)"
set output "$IMG/bench_latency_vs_slabs.png"
set title "Query latency vs slab count (bunny00, n = 16)"
plot "$OUT/slabs.tsv" u 1:4 w lp lw 2 t "hdm coherent median", \
     "" u 1:5 w lp t "hdm coherent p99", \
     "" u 1:6 w lp lw 2 t "hdm global median", \
     "" u 1:7 w lp t "hdm global p99", \
     "" u 1:9 w lp dt 2 t "Embree closest+inside (path points)", \
     "" u 1:10 w lp dt 2 t "Embree closest+inside (global points)"
set xlabel "input triangles (bunny00 subdivided 1-to-4; the slab model stays at $INPUT_SLABS slabs, n = 16)"
set output "$IMG/bench_latency_vs_input.png"
set title "Query latency vs input size: hdm against the exact queries on the input"
plot "$OUT/inputs.tsv" u 1:3 w lp lw 2 t "hdm coherent median", \
     "" u 1:4 w lp lw 2 t "hdm global median", \
     "" u 1:5 w lp dt 2 t "Embree closest+inside (path points)", \
     "" u 1:6 w lp dt 2 t "Embree closest+inside (global points)", \
     "" u 1:7 w lp dt 3 t "CGAL AABB closest (path points)", \
     "" u 1:8 w lp dt 3 t "CGAL AABB closest (global points)"
set xlabel "grid intervals per slab edge n"
set logscale x 2
set output "$IMG/bench_latency_vs_grid.png"
set title "Query latency vs grid size (bunny00, $GRID_SLABS slabs)"
plot "$OUT/grids.tsv" u 2:4 w lp lw 2 t "hdm coherent median", \
     "" u 2:5 w lp t "hdm coherent p99", \
     "" u 2:6 w lp lw 2 t "hdm global median", \
     "" u 2:9 w lp dt 2 t "Embree closest+inside (path points)"
unset logscale
set logscale xy
set xlabel "slabs"
set ylabel "seconds"
set output "$IMG/bench_bake_vs_slabs.png"
set title "Bake time vs slab count (input subdivided 1-to-4 as needed; labels: input triangles)"
plot "$OUT/slabs.tsv" u 1:11 w lp lw 2 t "bake [s]", \
     "" u 1:11:(sprintf("%dk", \$3/1000)) w labels offset 0,1 notitle
set ylabel "bytes"
set output "$IMG/bench_memory_vs_slabs.png"
set title "Memory vs slab count (n = 16)"
plot "$OUT/slabs.tsv" u 1:12 w lp lw 2 t "bytes per slab (geometry, topology, locator)", \
     "" u 1:13 w lp lw 2 t "bytes per sample (fields, layout, adjacency)", \
     "" u 1:(\$14*1e6) w lp t "peak RSS of the run"
EOF
ls -la "$IMG"/bench_*.png
