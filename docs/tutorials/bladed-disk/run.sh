#!/usr/bin/env bash
# The command-line steps of the tutorial "A bladed disk with an under-platform damper"
# (docs/tutorials/bladed-disk.md shows them from the markers below) and its Python script, run
# by the documentation build in a scratch directory laid out as the repository's root: build/hbf
# and examples/ are links there. The figures the page shows are the ones written here.
# Usage: run.sh WORK_DIR HBF REPOSITORY PYTHON
source "$(dirname "$0")/../scratch.sh" "$@"
# [mesh]
python3 examples/systems/bladed_disk/make_sector.py --out wheel
# [/mesh]
# [families]
build/hbf nodal-diameters --config wheel/sector.toml --modes 3 --out wheel/families.csv --plot wheel/families.png
# [/families]
# [frf]
build/hbf frf --config wheel/sector.toml --out wheel/frf.csv --summary wheel/frf.json --plot wheel/frf.png
# [/frf]
# [load]
build/hbf map --config wheel/sector.toml --param mu --contact 1 --values log:20:2000:9 \
    --error-points 0 --out wheel/load.csv --summary wheel/load.json
# [/load]
# [orders]
build/hbf map --config wheel/sector.toml --param cyclic.engine_order --values 0:12:13 --wmax 7400 \
    --error-points 0 --out wheel/orders.csv --summary wheel/orders.json --plot wheel/orders.png
# [/orders]
# [modes]
build/hbf modes --config wheel/sector.toml --out wheel/mode.csv --plot wheel/mode.png \
    --plot-synthesis wheel/synthesis.png
# [/modes]
"$python" "$here/wheel.py"
