#!/usr/bin/env bash
# Runs every figure script of examples/paper/ (the paper's figures, reproduced), writing
# the PNGs and CSVs into $1 (default: results/paper/ under the repository root), and prints
# each script's wall time and the total. Needs hbf built (./scripts/run-example.sh) and gnuplot.
# The scripts are independent: JOBS of them run at once (default: the number of cores, from
# nproc; JOBS=1 runs them one after the other). The first failing script stops the run with
# its exit status, after the running ones have finished.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
OUT=${1:-$ROOT/results/paper}
JOBS=${JOBS:-$(nproc)}
if ! [[ $JOBS =~ ^[1-9][0-9]*$ ]]; then
  echo "run-all: JOBS = '$JOBS' is out of range: allowed a whole number >= 1" >&2
  exit 2
fi
mkdir -p "$OUT"
now() { date +%s.%N; }
elapsed() { awk -v s="$1" -v e="$2" 'BEGIN { printf "%.1f", e - s }'; }
run_one() {
  local script=$1 start
  start=$(now)
  "$script" "$OUT"
  echo "run-all: $(printf '%-32s' "$(basename "$script")") $(elapsed "$start" "$(now)") s" >&2
}
begin=$(now)
running=0
status=0
# The longest first (measured), so that the last one started is short; any other fig*.sh after.
scripts=()
for name in fig04_09_force_ratio fig12_14_den_hartog fig_law_comparison fig15_16_min_displacement \
            fig10_11_limit_friction fig03_coulomb_frf fig07_08_dahl_lugre_frf fig05_06_friction_loops; do
  [[ -e $HERE/$name.sh ]] && scripts+=("$HERE/$name.sh")
done
for script in "$HERE"/fig*.sh; do
  [[ " ${scripts[*]} " == *" $script "* ]] || scripts+=("$script")
done
for script in "${scripts[@]}"; do
  run_one "$script" &
  running=$((running + 1))
  if ((running >= JOBS)); then
    wait -n || { status=$?; break; }
    running=$((running - 1))
  fi
done
while ((running > 0)); do
  wait -n || { ((status)) || status=$?; }
  running=$((running - 1))
done
if ((status)); then
  echo "run-all: a figure script failed (exit $status); see its message above" >&2
  exit "$status"
fi
echo "run-all: every figure in $(elapsed "$begin" "$(now)") s ($JOBS at a time); PNGs and CSVs in $OUT" >&2
