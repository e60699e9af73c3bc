#!/usr/bin/env bash
# Runs a command and prints its resident memory over time, one line every 0.2 s:
# "<seconds since start> <VmRSS in MiB>" (stdout); the command's own output goes to stderr.
# Usage: scripts/rss_timeline.sh COMMAND [ARGS...] > rss.dat
# docs/performance.md#peak-memory-of-a-100000-slab-bake plots two of these with gnuplot.
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: $0 COMMAND [ARGS...]" >&2; exit 2; }
"$@" >&2 &
pid=$!
t0=$(date +%s.%N)
while kill -0 "$pid" 2>/dev/null; do
  kb=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
  [ -n "$kb" ] && awk -v t0="$t0" -v now="$(date +%s.%N)" -v kb="$kb" 'BEGIN {printf "%.2f %.1f\n", now - t0, kb / 1024}'
  sleep 0.2
done
wait "$pid"
