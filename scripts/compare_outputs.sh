#!/usr/bin/env bash
# Runs a fixed set of hbf commands (the default FRF, every example system's FRF, and one run of
# each other study) with one or two hbf binaries and compares the CSVs they write byte for byte.
# For restructurings that must not change behaviour.
#
#   scripts/compare_outputs.sh HBF_BINARY OUT_DIR              # write OUT_DIR/<case>.csv
#   scripts/compare_outputs.sh HBF_A HBF_B OUT_DIR             # both, then compare; exit 1 on a difference
#   scripts/compare_outputs.sh DIR_A HBF_B OUT_DIR             # A's outputs written before (first form)
#
# Run from the repository root. The CSVs only are compared (JSON summaries carry run times), and
# in them every column but `seconds` (a run time).
set -euo pipefail

usage() { echo "usage: $0 HBF_BINARY OUT_DIR | HBF_A HBF_B OUT_DIR" >&2; exit 2; }
[ $# -eq 2 ] || [ $# -eq 3 ] || usage
[ -f examples/systems/absorber.toml ] || { echo "$0: run from the repository root" >&2; exit 2; }

run_all() {  # binary directory
    local hbf=$1 out=$2
    [ -f "$hbf" ] && [ -x "$hbf" ] || { echo "$0: $hbf is not an executable file" >&2; exit 2; }
    mkdir -p "$out"
    [ -z "$(ls -A "$out")" ] || { echo "$0: $out is not empty" >&2; exit 2; }
    local cases=()
    run() {  # name, arguments...
        local name=$1; shift
        cases+=("$name")
        set +e
        "$hbf" "$@" --out "$out/$name.csv" 2>"$out/$name.stderr"
        echo $? >"$out/$name.rc"
        set -e
    }
    run frf_default frf --quiet
    for f in examples/systems/*.toml examples/systems/*/*.toml; do
        run "frf_$(basename "$f" .toml)" frf --config "$f" --quiet
    done
    run frf_dahl frf --law dahl --quiet
    run frf_lugre frf --law lugre --quiet
    run frf_iwan frf --law iwan --harmonics 5 --quiet
    run timeint_sweep timeint --wmin 0.8 --wmax 1.2 --points 3 --quiet
    run modes_default modes --amin 0.01 --amax 10 --quiet
    run track_mu track --fe 1 --param mu --range 0.3:2 --at 0.4,0.5 --quiet
    run optimize_default optimize --quiet
    run map_small map --param fe --values 0.5,1 --quiet
    run analytic_default analytic
    echo "${#cases[@]} cases written to $out"
}

if [ $# -eq 2 ]; then
    run_all "$1" "$2"
    exit 0
fi
if [ -d "$1" ]; then a=$1; else a=$3/a; run_all "$1" "$a"; fi
run_all "$2" "$3/b"
same_csv() {  # a b: byte-identical but for the column `seconds`
    python3 - "$1" "$2" <<'PY'
import sys
def rows(path):
    lines = open(path, 'rb').read().split(b'\n')
    header = lines[0].split(b',')
    drop = header.index(b'seconds') if b'seconds' in header else -1
    return [b','.join(c for i, c in enumerate(line.split(b',')) if i != drop) for line in lines]
sys.exit(0 if rows(sys.argv[1]) == rows(sys.argv[2]) else 1)
PY
}
status=0
for rc in "$a"/*.rc; do
    name=$(basename "$rc" .rc)
    if ! cmp -s "$rc" "$3/b/$name.rc"; then
        echo "DIFFERENT exit code: $name ($(cat "$rc") vs $(cat "$3/b/$name.rc"))"; status=1
    fi
    for f in "$a/$name".csv; do
        [ -e "$f" ] || continue
        if ! same_csv "$f" "$3/b/$name.csv"; then echo "DIFFERENT: $name.csv"; status=1; fi
    done
done
[ $status -eq 0 ] && echo "identical: every exit code and CSV"
exit $status
