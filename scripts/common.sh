# Sourced by the scripts: configure and build hbfriction in a build directory.
# Usage: build_project BUILD_DIR BUILD_TYPE [extra cmake args...]
build_project() {
  local dir=$1 type=$2
  shift 2
  local jobs
  jobs=$(nproc 2>/dev/null || echo 2)
  cmake -S "$ROOT" -B "$dir" -DCMAKE_BUILD_TYPE="$type" "$@" >/dev/null
  cmake --build "$dir" --parallel "$jobs" -- --no-print-directory >/dev/null \
    || cmake --build "$dir" --parallel 1   # on failure, rebuild serially to show the error
}
