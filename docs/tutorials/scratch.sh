# Sourced by the tutorials' run.sh scripts: checks their arguments (WORK_DIR HBF REPOSITORY
# PYTHON), lays out WORK_DIR as the repository's root (build/hbf and examples/ linked there),
# enters it, and sets `python` (the interpreter) and `here` (the calling script's folder).
set -euo pipefail
[[ $# -eq 4 ]] || { echo "usage: run.sh WORK_DIR HBF REPOSITORY PYTHON" >&2; exit 2; }
python=$4
here=$(cd "$(dirname "${BASH_SOURCE[1]}")" && pwd)
mkdir -p "$1/build"
ln -sfn "$2" "$1/build/hbf"
ln -sfn "$3/examples" "$1/examples"
cd "$1"
