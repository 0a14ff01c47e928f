#!/usr/bin/env bash
# The command-line steps of the tutorial "From finite-element matrices to an FRF"
# (docs/tutorials/fe-to-frf.md shows them from the markers below) and its Python script, run by
# the documentation build in a scratch directory laid out as the repository's root: build/hbf
# and examples/ are links there. The figures the page shows are the ones written here.
# Usage: run.sh WORK_DIR HBF REPOSITORY PYTHON
source "$(dirname "$0")/../scratch.sh" "$@"
# [mesh]
python3 examples/systems/block/make_block.py --nx 6 --ny 2 --nz 2 --height 0.03 --out bar
# [/mesh]
cp "$here/bar.toml" "$here/force.mtx" bar/
# [frf]
build/hbf frf --config bar/bar.toml --out bar/frf.csv --summary bar/frf.json \
    --plot bar/frf.png --plot-contacts bar/states.png
# [/frf]
# [modes]
build/hbf modes --config bar/bar.toml --amin 4e-8 --amax 6e-7 --out bar/mode.csv \
    --plot bar/mode.png --plot-damping bar/damping.png
# [/modes]
# [track]
build/hbf track --config bar/bar.toml --param fe --range 0.3:0.9 --harmonics 3 \
    --out bar/track.csv --plot bar/track.png
# [/track]
"$python" "$here/bar.py"
