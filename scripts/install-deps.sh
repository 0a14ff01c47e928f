#!/usr/bin/env bash
# Installs every build and test dependency of hbfriction from Debian packages (Debian 12),
# and any extra packages named as arguments (e.g. scripts/fuzz.sh adds clang's).
# Usage: install-deps.sh [EXTRA_PACKAGE...]
# Idempotent: when everything is present it prints nothing and exits 0.
# Works as root, or as a normal user through sudo.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libeigen3-dev libfftw3-dev libceres-dev
  catch2 libcli11-dev nlohmann-json3-dev libtomlplusplus-dev
  libsundials-dev gnuplot-nox
  libspectra-dev  # sparse eigensolver of the modal receptance (header-only)
  libopenmpi-dev openmpi-bin  # hbf map under mpirun (optional for a build: HBF_MPI=OFF); its test runs 2 ranks
  python3  # examples/systems/beam/make_beam.py (standard library only), checked by the tests
  python3-dev pybind11-dev python3-numpy  # the Python bindings (python/: import hbfriction)
  python3-pytest python3-scipy python3-matplotlib  # their tests (tests/python) and examples (examples/python)
  python3-sphinx python3-myst-parser python3-breathe doxygen python3-sphinx-rtd-theme
  python3-sphinx-gallery  # the documentation site (scripts/build-docs.sh, built by the tests)
  "$@"
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

if [[ $(id -u) -eq 0 ]]; then
  SUDO=()
elif command -v sudo >/dev/null 2>&1; then
  SUDO=(sudo)
else
  echo "install-deps.sh: missing packages (${missing[*]}) and not root, and sudo is not available" >&2
  exit 1
fi

echo "install-deps.sh: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" apt-get update -qq
"${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
