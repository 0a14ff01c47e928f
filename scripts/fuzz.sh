#!/usr/bin/env bash
# libFuzzer targets of hbfriction (tests/fuzz/README.md).
#
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]   fuzz each target (default 60 s, all three)
#   scripts/fuzz.sh --replay [TARGET...]               run each target once on its kept crashes
#                                                      (tests/fuzz/regressions/<target>/) and its
#                                                      seeds: no fuzzing (the test suite's
#                                                      fuzz_replay_* do the same without clang)
#
# TARGET: config (read_system_config), matrix_market (read_matrix_market), cli (run_program,
# always --dry-run); the names fuzz_config etc. work too.
#
# Installs what it needs on Debian 12 (the project's dependencies through install-deps.sh,
# clang and libclang-rt-14-dev itself), configures build-fuzz/ once with clang (tests/fuzz/
# CMakeLists.txt) and builds incrementally. The corpus grows in build-fuzz/corpus/<target>/
# (seeded from examples/systems and tests/fuzz/seeds/<target>/); a crash, timeout, leak or
# out-of-memory input is written to build-fuzz/artifacts/<target>/ and makes the exit code 1
# (keep it as a regression: tests/fuzz/README.md). Logs: build-fuzz/logs/<target>.log.
#
# Environment: HBF_FUZZ_JOBS (build jobs, default nproc), HBF_FUZZ_BUILD_DIR (default
# build-fuzz), HBF_FUZZ_ARGS (more libFuzzer flags, e.g. "-seed=1").
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${HBF_FUZZ_BUILD_DIR:-$ROOT/build-fuzz}
JOBS=${HBF_FUZZ_JOBS:-$(nproc 2>/dev/null || echo 2)}
FUZZ_DIR=$ROOT/tests/fuzz
ALL_TARGETS=(config matrix_market cli)

usage() {
  sed -n '4,9p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

# ---- arguments -------------------------------------------------------------
mode=fuzz
seconds=60
if [[ $# -gt 0 && $1 == --replay ]]; then
  mode=replay
  shift
elif [[ $# -gt 0 && $1 =~ ^[0-9]+$ ]]; then
  seconds=$1
  shift
  [[ $seconds -ge 1 ]] || { echo "fuzz.sh: SECONDS_PER_TARGET must be >= 1" >&2; exit 2; }
elif [[ $# -gt 0 && ( $1 == -h || $1 == --help ) ]]; then
  usage
fi
targets=()
for t in "$@"; do
  t=${t#fuzz_}
  case $t in
    config | matrix_market | cli) targets+=("$t") ;;
    *) echo "fuzz.sh: unknown target '$t': allowed ${ALL_TARGETS[*]}" >&2; exit 2 ;;
  esac
done
[[ ${#targets[@]} -gt 0 ]] || targets=("${ALL_TARGETS[@]}")

# ---- dependencies ----------------------------------------------------------
"$ROOT/scripts/install-deps.sh" clang libclang-rt-14-dev  # clang 14 and its libFuzzer runtime (Debian 12)

# ---- build -----------------------------------------------------------------
if [[ ! -f $BUILD/CMakeCache.txt ]]; then
  echo "== configuring build-fuzz/ (clang, ASan + UBSan + libFuzzer)" >&2
  mkdir -p "$BUILD"
  CC=clang CXX=clang++ cmake -S "$FUZZ_DIR" -B "$BUILD" >"$BUILD/configure.log" 2>&1 \
    || { cat "$BUILD/configure.log" >&2; exit 1; }
fi
echo "== building the fuzz targets in $(basename "$BUILD")/ ($JOBS jobs)" >&2
build_targets=(fuzz_dictionary)
for t in "${targets[@]}"; do build_targets+=("fuzz_$t"); done
if ! cmake --build "$BUILD" --parallel "$JOBS" --target "${build_targets[@]}" >"$BUILD/build.log" 2>&1; then
  tail -n 60 "$BUILD/build.log" >&2
  echo "fuzz.sh: the build failed (whole log: $BUILD/build.log)" >&2
  exit 1
fi

# ---- seeds -----------------------------------------------------------------
# Prints the seed files of a target, one per line.
seeds() {
  local f
  case $1 in
    config) for f in "$ROOT"/examples/systems/*.toml "$ROOT"/examples/systems/beam/*.toml "$FUZZ_DIR"/seeds/config/*; do echo "$f"; done ;;
    matrix_market) for f in "$ROOT"/examples/systems/*.mtx "$ROOT"/examples/systems/beam/*.mtx "$FUZZ_DIR"/seeds/matrix_market/*; do echo "$f"; done ;;
    cli) for f in "$FUZZ_DIR"/seeds/cli/*; do echo "$f"; done ;;
  esac
}
max_len() {
  case $1 in
    cli) echo 4096 ;;
    *) echo 65536 ;;
  esac
}

# Scratch space of the targets (their private directories): emptied before each run.
export TMPDIR=$BUILD/tmp
# UBSan reports are fatal (-fno-sanitize-recover=all); with a stack trace.
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
mkdir -p "$BUILD/logs"

failed=()

# ---- replay ----------------------------------------------------------------
# The seeds in one run of the target, each kept crash in a run of its own (all are reported).
# Prints the lines of a log that say what went wrong.
what_failed() {
  grep -m 4 -E 'ERROR|SUMMARY|runtime error|Assertion|hbf fuzz target|uncaught|terminate called' "$1" \
    | cut -c 1-300 | sed 's/^/     /' >&2 || true
}
if [[ $mode == replay ]]; then
  for t in "${targets[@]}"; do
    rm -rf "$TMPDIR" && mkdir -p "$TMPDIR"
    seed_files=()
    while IFS= read -r f; do [[ -f $f ]] && seed_files+=("$f"); done < <(seeds "$t")
    log=$BUILD/logs/replay_$t.log
    start=$SECONDS
    if [[ ${#seed_files[@]} -gt 0 ]] && ! "$BUILD/fuzz_$t" -timeout=10 -rss_limit_mb=2048 "${seed_files[@]}" >"$log" 2>&1; then
      echo "replay $t: a seed FAILED (log: $log)" >&2
      what_failed "$log"
      failed+=("$t")
    fi
    kept=0 crashing=0
    for f in "$FUZZ_DIR/regressions/$t"/*; do
      [[ -f $f ]] || continue
      kept=$((kept + 1))
      if ! "$BUILD/fuzz_$t" -timeout=10 -rss_limit_mb=2048 "$f" >"$log.regression" 2>&1; then
        crashing=$((crashing + 1))
        echo "replay $t: still fails: ${f#"$ROOT"/}" >&2
        what_failed "$log.regression"
        cat "$log.regression" >>"$log"
      fi
    done
    rm -f "$log.regression"
    [[ $crashing -eq 0 ]] || failed+=("$t")
    echo "replay $t: ${#seed_files[@]} seeds, $kept kept crashes of which $crashing still fail ($((SECONDS - start)) s)"
  done
  [[ ${#failed[@]} -eq 0 ]] || { echo "fuzz.sh: replay failed for ${failed[*]}" >&2; exit 1; }
  exit 0
fi

# ---- fuzz ------------------------------------------------------------------
for t in "${targets[@]}"; do
  corpus=$BUILD/corpus/$t
  artifacts=$BUILD/artifacts/$t
  mkdir -p "$corpus" "$artifacts"
  while IFS= read -r f; do [[ -f $f ]] && cp -n "$f" "$corpus/"; done < <(seeds "$t")
  # The dictionary: the hand-written words (tests/fuzz/<target>.dict), then those generated from
  # the commands and the law registry (fuzz_dictionary: tests/fuzz/dictionary.cpp).
  dict=()
  if [[ -f $FUZZ_DIR/$t.dict ]]; then
    mkdir -p "$BUILD/dict"
    cp "$FUZZ_DIR/$t.dict" "$BUILD/dict/$t.dict"
    case $t in
      cli | config) "$BUILD/fuzz_dictionary" "$t" >>"$BUILD/dict/$t.dict" ;;
    esac
    dict=(-dict="$BUILD/dict/$t.dict")
  fi
  before=$(find "$artifacts" -type f | sort)
  rm -rf "$TMPDIR" && mkdir -p "$TMPDIR"
  log=$BUILD/logs/$t.log
  echo "== fuzzing $t for $seconds s (log: ${log#"$ROOT"/})" >&2
  start=$SECONDS
  status=0
  # shellcheck disable=SC2086  # HBF_FUZZ_ARGS: several flags
  "$BUILD/fuzz_$t" "$corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len="$(max_len "$t")" -artifact_prefix="$artifacts/" -print_final_stats=1 "${dict[@]}" \
    ${HBF_FUZZ_ARGS:-} >"$log" 2>&1 || status=$?
  elapsed=$((SECONDS - start))
  new=$(comm -13 <(echo "$before") <(find "$artifacts" -type f | sort) | sed '/^$/d')
  crashes=$(echo -n "$new" | grep -c . || true)
  # Executions: libFuzzer's final statistics, else its last status line (#N).
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  [[ -n $execs ]] || execs=$(grep -o '^#[0-9]*' "$log" | tail -n 1 | tr -d '#')
  execs=${execs:-0}
  rate=$((execs / (elapsed > 0 ? elapsed : 1)))
  if [[ $status -ne 0 && $crashes -eq 0 ]]; then crashes=1; fi  # a failure that wrote no artifact
  printf '%-14s executions %10s  (%s/s)  crashes %s  time %s s\n' "$t" "$execs" "$rate" "$crashes" "$elapsed"
  if [[ $crashes -gt 0 ]]; then
    failed+=("$t")
    echo "   crash inputs in ${artifacts#"$ROOT"/}/:" >&2
    [[ -z $new ]] || while IFS= read -r f; do echo "     $f" >&2; done <<<"$new"
    what_failed "$log"
  fi
done
[[ ${#failed[@]} -eq 0 ]] || { echo "fuzz.sh: crashes found in ${failed[*]} (see build-fuzz/artifacts/)" >&2; exit 1; }
