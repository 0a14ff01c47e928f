#!/usr/bin/env bash
# Runs every figure script of examples/paper/ (the paper's figures, reproduced), writing
# the PNGs and CSVs into $1 (default: results/paper/ under the repository root), and prints
# each script's wall time. Needs hbf built (./scripts/run-example.sh) and gnuplot.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
OUT=${1:-$ROOT/results/paper}
for script in "$HERE"/fig*.sh; do
  start=$(date +%s.%N)
  "$script" "$OUT"
  end=$(date +%s.%N)
  awk -v s="$start" -v e="$end" -v n="$(basename "$script")" 'BEGIN { printf "run-all: %-32s %6.1f s\n", n, e - s }' >&2
done
echo "run-all: PNGs and CSVs in $OUT" >&2
