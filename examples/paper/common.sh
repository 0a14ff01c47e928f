# Sourced by the examples/paper/fig*.sh scripts (not run on its own).
# Sets ROOT (the repository), HBF (the hbf executable: $HBF or ROOT/build/hbf) and OUT (the
# output directory: the script's first argument or ROOT/results/paper), checks that hbf is
# built and gnuplot is installed, and defines small helpers shared by the scripts.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
HBF=${HBF:-$ROOT/build/hbf}
OUT=${1:-$ROOT/results/paper}
SCRIPT=$(basename "$0" .sh)

exec 3>&2   # the script's standard error, for messages while a command's stderr is redirected
die() { echo "$SCRIPT: error: $*" >&3; exit 1; }

if [[ ! -x $HBF ]]; then
  die "hbf not found at $HBF: build it first (./scripts/run-example.sh) or set HBF=/path/to/hbf"
fi
command -v gnuplot >/dev/null 2>&1 || die "gnuplot not found (./scripts/install-deps.sh installs it)"
mkdir -p "$OUT" || die "cannot create the output directory $OUT"

# hbf ARGS...: runs hbf; on failure names the command and stops the script. Exit code 3 (a
# result written but incomplete, e.g. an unbounded resonance capped at --max-amplitude, which
# several figures show on purpose) goes on: hbf's own warning says what is missing.
hbf() {
  local code=0
  "$HBF" "$@" || code=$?
  if [[ $code -eq 3 ]]; then
    echo "$SCRIPT: note: hbf $1 wrote an incomplete result (exit code 3; see the warning above)" >&3
  elif [[ $code -ne 0 ]]; then
    die "hbf $* failed (exit code $code)"
  fi
}

# plot SCRIPT_TEXT: runs gnuplot on the text (from standard input) with the common settings;
# the text must 'set output'.
plot() {
  { cat <<'GP'
set terminal pngcairo size 1100,750 enhanced font 'Sans,11' linewidth 1.5
set datafile separator ','
set grid lc rgb '#dddddd'
set key top right box opaque
GP
    cat
  } | gnuplot || die "gnuplot failed"
}

# wrote FILE...: reports written files on standard error.
wrote() { for f in "$@"; do echo "$SCRIPT: wrote $f" >&3; done; }
