#!/usr/bin/env bash
# Builds the documentation site into BUILD_DIR/docs/html (Sphinx with MyST, Breathe and
# sphinx-gallery, from Debian packages: scripts/install-deps.sh), warnings as errors: a broken
# reference, a missing page, a failing example or a Doxygen warning fails the build.
# The sources are staged in BUILD_DIR/docs/site (docs/, the README and changelog they include,
# the gallery's examples), so the build writes nothing into the source tree.
# Usage: [PYTHON=python3] build-docs.sh BUILD_DIR   (BUILD_DIR: a build of hbfriction with its
# Python package, for the interpreter PYTHON: default /usr/bin/python3)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
[[ $# -eq 1 ]] || { echo "usage: build-docs.sh BUILD_DIR" >&2; exit 2; }
BUILD=$(cd "$1" && pwd)
[[ -x $BUILD/hbf && -d $BUILD/python/hbfriction ]] ||
  { echo "build-docs.sh: $BUILD has no hbf or no Python package (build with -DHBF_PYTHON=ON)" >&2; exit 2; }
OUT=$BUILD/docs
rm -rf "$OUT/site" "$OUT/html" "$OUT/doctrees" "$OUT/doxygen" "$OUT/tutorial" "$OUT/tutorial-wheel"
mkdir -p "$OUT/site/examples" "$OUT/doxygen"
cp -r "$ROOT/docs" "$OUT/site/docs"
cp -r "$ROOT/examples/python" "$OUT/site/examples/python"
mkdir -p "$OUT/site/examples/systems"  # the system files the pages include (small text files)
cp -r "$ROOT/examples/systems/bladed_disk" "$OUT/site/examples/systems/"
cp "$ROOT/README.md" "$ROOT/CHANGELOG.md" "$OUT/site/"

# The C++ API: Doxygen's XML of the public headers, for Breathe.
cat > "$OUT/doxygen/Doxyfile" <<DOXY
PROJECT_NAME = hbfriction
INPUT = $ROOT/include/hbf $BUILD/generated/include/hbf
FILE_PATTERNS = *.hpp
RECURSIVE = NO
GENERATE_XML = YES
GENERATE_HTML = NO
GENERATE_LATEX = NO
OUTPUT_DIRECTORY = $OUT/doxygen
EXTRACT_ALL = YES
QUIET = YES
WARN_IF_UNDOCUMENTED = NO
WARN_AS_ERROR = FAIL_ON_WARNINGS
DOXY
doxygen "$OUT/doxygen/Doxyfile"

# The tutorial's commands and Python script, run as the page shows them; its figures go where
# the page includes them from.
PY=${PYTHON:-/usr/bin/python3}
PYTHONPATH=$BUILD/python${PYTHONPATH:+:$PYTHONPATH} MPLBACKEND=Agg \
  bash "$ROOT/docs/tutorials/fe-to-frf/run.sh" "$OUT/tutorial" "$BUILD/hbf" "$ROOT" "$PY" > "$OUT/tutorial.log" 2>&1 ||
  { cat "$OUT/tutorial.log" >&2; echo "build-docs.sh: the tutorial failed" >&2; exit 1; }
mkdir -p "$OUT/site/docs/_generated/tutorial"
cp "$OUT"/tutorial/bar/*.png "$OUT/site/docs/_generated/tutorial/"
PYTHONPATH=$BUILD/python${PYTHONPATH:+:$PYTHONPATH} MPLBACKEND=Agg \
  bash "$ROOT/docs/tutorials/bladed-disk/run.sh" "$OUT/tutorial-wheel" "$BUILD/hbf" "$ROOT" "$PY" > "$OUT/tutorial-wheel.log" 2>&1 ||
  { cat "$OUT/tutorial-wheel.log" >&2; echo "build-docs.sh: the bladed-disk tutorial failed" >&2; exit 1; }
mkdir -p "$OUT/site/docs/_generated/tutorial-wheel"
cp "$OUT"/tutorial-wheel/wheel/*.png "$OUT/site/docs/_generated/tutorial-wheel/"

export HBF_SOURCE_DIR=$ROOT
export HBF_EXECUTABLE=$BUILD/hbf
export HBF_DOXYGEN_XML=$OUT/doxygen/xml
export PYTHONPATH=$BUILD/python${PYTHONPATH:+:$PYTHONPATH}
export MPLBACKEND=Agg
"$PY" -m sphinx -W --keep-going -q -b html -d "$OUT/doctrees" "$OUT/site/docs" "$OUT/html"
echo "build-docs.sh: $OUT/html/index.html"
