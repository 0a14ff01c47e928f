#!/usr/bin/env bash
# Command 1 of the README: installs the dependencies, builds hbfriction (Release) and
# computes the default FRF of the paper's friction absorber (LuGre, harmonic balance) into
# results/default.csv, with its JSON summary in results/default.json. Then registers the Python
# package built in build/python with the system's python3 (a .pth file in the user's
# site-packages, like pip's editable install) and computes the same FRF from Python.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
source "$ROOT/scripts/common.sh"

"$ROOT/scripts/install-deps.sh"
echo "== building (Release) in build/" >&2
build_project "$ROOT/build" Release -DHBF_PYTHON_REQUIRED=ON
mkdir -p "$ROOT/results"
echo "== hbf frf (paper's absorber: r = 0.1, wa = 1, mu = 0.2, fe = 0.5, exact Coulomb: HB at H = 10, every point polished by the event-exact solver)" >&2
"$ROOT/build/hbf" frf --out "$ROOT/results/default.csv" --summary "$ROOT/results/default.json"
echo "== wrote results/default.csv ($(($(wc -l <"$ROOT/results/default.csv") - 1)) points) and results/default.json; first rows:" >&2
head -n 6 "$ROOT/results/default.csv"

# The Python package: `import hbfriction` from any directory, with Debian's interpreter (whose
# NumPy the bindings were built against). The .pth file names build/python, so a rebuild is
# picked up; `cmake --install build --component python` copies the package instead (README).
python=/usr/bin/python3
[[ -x $python ]] || python=$(command -v python3)
site=$("$python" -m site --user-site)
pth="$site/hbfriction-build.pth"
if [[ -L $pth || ( -e $pth && ! -f $pth ) ]]; then
  echo "== $pth exists and is not a regular file: left alone; use PYTHONPATH=$ROOT/build/python" >&2
else
  mkdir -p "$site"
  printf '%s\n' "$ROOT/build/python" >"$pth.tmp.$$" && mv -f "$pth.tmp.$$" "$pth"
  echo "== Python: $pth points $python at build/python; the same FRF from Python:" >&2
  "$python" -c "import hbfriction; b = hbfriction.frf(hbfriction.absorber()); print('hbfriction.frf(hbfriction.absorber()): %d points, largest y1_max = %.9g' % (len(b), b.y1_max.max()))"
fi
