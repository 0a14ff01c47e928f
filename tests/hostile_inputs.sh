#!/usr/bin/env bash
# Hostile inputs (issue 13): numbers, flags, files, paths, devices and collisions that a careless
# or hostile user may give hbf. Every case runs in a fresh directory holding a precious file
# (keep.csv) and the case's fixtures, and asserts:
#   - the exit code (2: bad input, found before any work; 1: a failure; 0 where the input is
#     legal, e.g. writing to /dev/null);
#   - a message on standard error naming the offending parameter (a fixed text per case);
#   - for exit 2, nothing on standard output;
#   - the directory afterwards: no file created, none replaced (names, types, inodes and
#     contents compared), and /dev/null and /dev/full still character devices.
# Run as `hostile_inputs.sh HBF SOURCE_DIR [PASS]`. PASS "self" runs the list as the current
# user; "nobody" runs it as the unprivileged user nobody (setpriv, root only: exit 77, skipped,
# otherwise), where permissions apply (a read-only directory); "both" (the default) does both, the
# second only as root. CTest runs the two passes as two tests, in parallel. PASS "largest" runs
# only the bound on the largest H (35 s; CTest label long: hostile_inputs_largest_h).
set -uo pipefail

HBF=$(realpath "${1:?usage: hostile_inputs.sh /path/to/hbf SOURCE_DIR}")
SRC=$(realpath "${2:?usage: hostile_inputs.sh /path/to/hbf SOURCE_DIR}")
PASS=${3:-both}
case $PASS in
  self | both | largest) ;;
  nobody)
    if [[ $(id -u) -ne 0 ]] || ! command -v setpriv >/dev/null ||
      ! setpriv --reuid=nobody --regid=nogroup --clear-groups test -x "$HBF"; then
      echo "hostile inputs: the unprivileged pass needs root, setpriv, and $HBF executable by nobody: skipped"
      exit 77
    fi
    exec setpriv --reuid=nobody --regid=nogroup --clear-groups --reset-env \
      env PATH="$PATH" TMPDIR=/tmp bash "$0" "$HBF" "$SRC" self
    ;;
  *)
    echo "hostile_inputs.sh: PASS = '$PASS' is not one of self, nobody, both, largest" >&2
    exit 2
    ;;
esac
WORK=$(mktemp -d "${TMPDIR:-/tmp}/hbf-hostile.XXXXXX")
chmod 755 "$WORK"
trap 'rm -rf "$WORK"' EXIT
who=$(id -un)
# 1 GB of address space and 60 s per case; a sanitizer build reserves terabytes of shadow memory
# and cannot start under any limit, so there the memory limit is lifted and the time limit is
# ten times longer (instrumented code runs 3-10 times slower: frf --harmonics 100, 34 s in
# Release, took over 60 s under ASan + UBSan at -O1); both said once.
MEMORY_LIMIT=1048576
TIME_LIMIT=60
if ! { (ulimit -v "$MEMORY_LIMIT" && exec "$HBF" --version) >/dev/null 2>&1; } 2>/dev/null; then
  echo "hostile inputs: $HBF does not start under ulimit -v (a sanitizer build?): no memory limit, $((10 * TIME_LIMIT)) s per case" >&2
  MEMORY_LIMIT=unlimited
  TIME_LIMIT=$((10 * TIME_LIMIT))
fi
cases=0
failures=0

# The state of a case directory: every entry with its type, inode and checksum.
state() {
  (cd "$1" && find . -mindepth 1 -printf '%P %y %i\n' | sort &&
    find . -mindepth 1 -type f -exec md5sum {} + 2>/dev/null | sort)
}

fail() {
  echo "FAIL [$who] case $cases: $*" >&2
  echo "  args: ${ARGS[*]}" >&2
  sed 's/^/  stderr: /' "$WORK/err" | head -5 >&2
  failures=$((failures + 1))
}

# expect CODE TEXT SETUP ARGS...: runs hbf ARGS in a fresh directory after the shell snippet
# SETUP ('' for none); checks the exit code, TEXT in standard error, and the directory.
expect() {
  local code=$1 text=$2 setup=$3
  shift 3
  ARGS=("$@")
  cases=$((cases + 1))
  local dir="$WORK/case$cases"
  mkdir -p "$dir" && chmod 777 "$dir"
  echo "precious data of case $cases" >"$dir/keep.csv"
  if [[ -n $setup ]]; then
    (cd "$dir" && eval "$setup") || {
      fail "setup failed: $setup"
      return
    }
  fi
  local before after got
  before=$(state "$dir")
  # Bounded: 1 GB of address space and 60 s per case (issue 28; see TIME_LIMIT above).
  (cd "$dir" && ulimit -v "$MEMORY_LIMIT" && timeout "$TIME_LIMIT" "$HBF" "$@" >"$WORK/out" 2>"$WORK/err" </dev/null)
  got=$?
  after=$(state "$dir")
  [[ $got -ne 124 ]] || fail "timed out ($TIME_LIMIT s)"
  [[ $got -eq $code ]] || fail "exit code $got, expected $code"
  if [[ -n $text ]] && ! grep -qF -- "$text" "$WORK/err"; then fail "standard error lacks '$text'"; fi
  if [[ $code -eq 2 && -s $WORK/out ]]; then fail "exit 2 with output on stdout"; fi
  [[ $before == "$after" ]] || fail "the directory changed: $(diff <(echo "$before") <(echo "$after") | head -4 | tr '\n' ' ')"
  [[ -c /dev/null && -c /dev/full ]] || fail "/dev/null or /dev/full is no longer a character device"
  # Not only the case directory: nothing may appear beside it either.
  local extra
  extra=$(find "$WORK" -mindepth 1 -maxdepth 1 ! -name 'case*' ! -name out ! -name err)
  [[ -z $extra ]] || fail "files created outside the case directory: $extra"
}

SYSTEM='[structure]
mass = [1.0, 0.1]
stiffness = [[1.1, -0.1], [-0.1, 0.1]]
excitation = [0.5, 0.0]
[[contact]]
dof = 1
other_dof = 2
law = "dahl"
friction_limit = 0.2
stiffness = 0.016'
# write_system FILE [EXTRA]: the absorber (Dahl) with EXTRA appended.
write_system() { printf '%s\n%s\n' "$SYSTEM" "${2:-}" >"$1"; }
export SYSTEM
export -f write_system

FAST=(--law dahl --harmonics 3 --wmin 0.9 --wmax 1.0)

# The largest H (max_harmonics, model.hpp): the absorber's exact-Coulomb branch, the costliest
# law there (34 s measured; H = 200 took 524 s and is refused above). A bound on time and
# memory, not on permissions: a pass of its own (label long), as the current user.
if [[ $PASS == largest ]]; then
  expect 0 "" '' frf --harmonics 100 --quiet --out /dev/null
  echo "hostile inputs [$who, largest H]: $cases cases, $failures failed"
  exit $((failures > 0))
fi

# ---- numbers --------------------------------------------------------------------------
for v in nan inf -inf -1 0 abc 1.5.5 0x10 1e-999 ''; do
  expect 2 "--mu" '' frf --mu "$v" --out x.csv
done
for v in nan -1 1e300 1e-300 ''; do expect 2 "--r" '' frf --r "$v" --out x.csv; done
for v in 0 -2 1e13; do expect 2 "--wa" '' frf --wa "$v" --out x.csv; done
for v in 0 -0.5 1e400; do expect 2 "--fe" '' frf --fe "$v" --out x.csv; done
for v in 0 -1 nan; do expect 2 "--wmin" '' frf --wmin "$v" --out x.csv; done
expect 2 "wmax" '' frf --wmin 2 --out x.csv
expect 2 "wmax" '' frf --wmax 0.1 --out x.csv
for v in -1 0.5 101 201 abc 1e3; do expect 2 "--harmonics" '' frf --harmonics "$v" --out x.csv; done
for v in 1 -5 3.5; do expect 2 "--time-samples" '' frf --time-samples "$v" --out x.csv; done
for v in 0 1 1e-20; do expect 2 "--tolerance" '' frf --tolerance "$v" --out x.csv; done
for v in 0 1e-9 100; do expect 2 "--max-step" '' frf --max-step "$v" --out x.csv; done
for v in 0 -1 nan; do expect 2 "--max-amplitude" '' frf --max-amplitude "$v" --out x.csv; done
for v in 0 1e-12 1e9; do expect 2 "--dlft-eps" '' frf --dlft-eps "$v" --out x.csv; done
for v in 0 101 201 1.5; do expect 2 "--excitation-harmonic" '' frf --excitation-harmonic "$v" --out x.csv; done
expect 2 "--harmonics" '' frf --excitation-harmonic 3 --harmonics 2 --out x.csv
for v in -1 x; do expect 2 "--modes" '' frf --modes "$v" --out x.csv; done
for v in 0 -1 'a,b' '1,,2' ''; do expect 2 "--at" '' frf --at "$v" --out x.csv; done
# hbf modes (issue 33): the amplitude range, the mode, the steps, the outputs
for v in nan inf -1 0 abc 1e-999 ''; do expect 2 "--amin" '' modes --amin "$v" --amax 1 --out x.csv; done
for v in 0.05 nan 1e400 ''; do expect 2 "--amax" '' modes --amin 0.1 --amax "$v" --out x.csv; done
expect 2 "--amin is missing: give --amin and --amax together" '' modes --amax 1 --out x.csv
expect 2 "decades: allowed up to 12" '' modes --amin 1e-20 --amax 1 --out x.csv
expect 2 "decades: allowed up to 12" '' modes --amin 1e-300 --amax 1e300 --out x.csv
for v in 0 -1 1.5 abc; do expect 2 "--mode" '' modes --mode "$v" --amin 0.1 --amax 1 --out x.csv; done
expect 2 "mode = 2 is out of range: allowed 1..1" '' modes --mode 2 --amin 0.1 --amax 1 --out x.csv
for v in 0 -1 nan; do expect 2 "--near" '' modes --near "$v" --amin 0.1 --amax 1 --out x.csv; done
expect 2 "--near cannot be combined with --mode" '' modes --near 1 --mode 1 --amin 0.1 --amax 1 --out x.csv
for v in 0 2 nan; do expect 2 "--max-step" '' modes --max-step "$v" --amin 0.1 --amax 1 --out x.csv; done
for v in 1 100001 x; do expect 2 "--max-points" '' modes --max-points "$v" --amin 0.1 --amax 1 --out x.csv; done
expect 2 "--harmonics odd" '' modes --harmonics odd --amin 0.1 --amax 1 --out x.csv
expect 2 "--synthesis-out" '' modes --amin 0.1 --amax 1 --out x.csv --synthesis-out x.csv
expect 2 "--plot-synthesis" '' modes --amin 0.1 --amax 1 --out x.csv --plot-synthesis x.txt
expect 2 "an input of this run" 'write_system s.toml' modes --config s.toml --amin 0.1 --amax 1 --out s.toml
expect 0 "" '' modes --amin 0.01 --amax 10 --quiet --out /dev/null --synthesis-out /dev/null
for v in -1 x 100001; do expect 2 "--modes" '' modes --modes "$v" --amin 0.1 --amax 1 --out x.csv; done
# A chain of 900 masses joined by 899 Jenkins elements: at H = 3 more unknowns than the modes'
# dense Newton system allows, refused before the structure is analysed, naming the H that fits.
chain_system='python3 -c "
n = 900
with open(\"k.mtx\", \"w\") as f:
    f.write(\"%%MatrixMarket matrix coordinate real general\\n\")
    f.write(\"%d %d %d\\n\" % (n, n, 3 * n - 2))
    for i in range(n):
        f.write(\"%d %d 2\\n\" % (i + 1, i + 1))
        if i + 1 < n:
            f.write(\"%d %d -1\\n%d %d -1\\n\" % (i + 1, i + 2, i + 2, i + 1))
with open(\"chain.toml\", \"w\") as f:
    f.write(\"[structure]\\nmass = [%s]\\nstiffness = \\\"k.mtx\\\"\\nexcitation = [1.0%s]\\n\" % (\", \".join([\"1.0\"] * n), \", 0.0\" * (n - 1)))
    for i in range(n - 1):
        f.write(\"[[contact]]\\ndof = %d\\nother_dof = %d\\nlaw = \\\"jenkins\\\"\\nfriction_limit = 0.1\\nstiffness = 1.0\\n\" % (i + 1, i + 2))
"'
expect 2 "makes at least 6293 unknowns for nonlinear modes" "$chain_system" modes --config chain.toml --harmonics 3 --amin 0.01 --amax 1 --out x.csv
for v in bogus ''; do expect 2 "--formulation" '' modes --formulation "$v" --amin 0.1 --amax 1 --out x.csv; done
expect 2 "needs the condensed formulation" '' modes --modes 2 --formulation full --amin 0.1 --amax 1 --out x.csv
expect 0 "" '' modes --formulation condensed --amin 0.01 --amax 10 --quiet --out /dev/null
# Force elements without friction: exponents, degrees and coefficients out of range, a key of
# another law, both a gap and a preload.
FORCE_ELEMENT='[[contact]]
dof = 2'
for case in 'law = "polynomial"|terms = [[2.5, 1.0]]|exponent 2.5' 'law = "polynomial"|terms = [[16, 1.0]]|1..15' \
            'law = "polynomial"|cubic = inf|cubic' 'law = "polynomial"|cubic = 1.0\nfriction_limit = 0.1|friction_limit' \
            'law = "polynomial"|quadratic = 0.0|no term' 'law = "gap"|stiffness = 1.0\ngap = 0.1\npreload = 1.0|preload' \
            'law = "damper"|coefficient = 1.0\nexponent = 0.5|exponent' 'law = "damper"|exponent = 2.0|coefficient' \
            'law = "gap"|stiffness = 1.0\ncubic = 1.0|cubic'; do
  IFS='|' read -r law keys needle <<<"$case"
  extra=$(printf '%s\n%s\n%b' "$FORCE_ELEMENT" "$law" "$keys")
  expect 2 "$needle" "write_system s.toml '$extra'" frf --config s.toml --harmonics 3 --out x.csv
done
expect 2 "--start-frequency" '' modes --start-frequency -1 --amin 0.1 --amax 1 --out x.csv
expect 2 "--xi" '' frf --xi 0.1 --out x.csv
expect 2 "--wb" '' frf --law coulomb --wb 0.4 --out x.csv
expect 2 "--eps" '' frf --law dahl --eps 0.1 --out x.csv
expect 2 "--mu-static" '' frf --law lugre --mu-static 1e13 --out x.csv
# Extreme parameters whose stuck resonance is unbounded (or above the cap): capped, exit 3, never
# stepped over by a large step (issue 28: each gave 10 points and exit 0).
expect 3 "amplitude_cap" '' frf --quiet --r 1e-12
expect 3 "amplitude_cap" '' frf --quiet --law lugre --xi 1e12
expect 3 "amplitude_cap" '' frf --quiet --law lugre --viscous 1e12
expect 3 "amplitude_cap" '' frf --quiet --r 1e-4 --at 0.99,0.999

# timeint, loop, analytic
for v in 0 -1 nan; do expect 2 "--w" '' timeint --w "$v" --out x.csv; done
for v in 0 1; do expect 2 "--rtol" '' timeint --w 1 --rtol "$v" --out x.csv; done
expect 2 "--atol" '' timeint --w 1 --atol -1 --out x.csv
expect 2 "--steady-tol" '' timeint --w 1 --steady-tol 1 --out x.csv
expect 2 "--max-periods" '' timeint --w 1 --max-periods 0 --out x.csv
expect 2 "--max-periods" '' timeint --w 1 --max-periods 1 --out x.csv
expect 2 "--min-periods" '' timeint --w 1 --min-periods 0 --out x.csv
expect 2 "--points" '' timeint --wmin 0.5 --wmax 1 --points 1 --out x.csv
expect 2 "--points" '' timeint --wmin 0.5 --wmax 1 --points 100001 --out x.csv
expect 2 "--sweep" '' timeint --wmin 0.5 --wmax 1 --points 3 --sweep sideways --out x.csv
expect 2 "--method" '' timeint --w 1 --method foo --out x.csv
expect 2 "--method exact" '' timeint --law dahl --w 1 --method exact --out x.csv
expect 2 "--w" '' loop --out x.csv
expect 2 "--w" '' loop --w -1 --out x.csv
for v in 0 2; do expect 2 "--contact" '' loop --w 1 --contact "$v" --out x.csv; done
expect 2 "--law" '' analytic --law jenkins --out x.csv
expect 2 "--points" '' analytic --points 1 --out x.csv

# ---- flags ----------------------------------------------------------------------------
expect 2 "unknown command" '' frobnicate
expect 2 "--frobnicate" '' frf --frobnicate 1 --out x.csv
expect 2 "--mu" '' frf --out x.csv --mu
expect 2 "--law" '' frf --law coulomb --law dahl --out x.csv
expect 2 "not expected: stray" '' frf stray --out x.csv
expect 2 "--law" '' frf --law magic --out x.csv
expect 2 "--exact" '' frf --law dahl --exact on --out x.csv
expect 2 "--exact" '' frf --exact maybe --out x.csv
expect 2 "--exact" '' frf --exact '' --out x.csv
expect 2 "--formulation" '' frf --formulation weird --out x.csv
# --force-scale: a factor > 0 on a --config file's excitation; the preset has --fe
expect 2 "for the paper's absorber set --fe" '' frf --force-scale 2 --out x.csv
for v in 0 -1 nan inf abc; do
  expect 2 "--force-scale" '' frf --config "$SRC/examples/systems/chain3.toml" --force-scale "$v" --out x.csv
done
expect 2 "--overlay-timeint" '' frf --overlay-timeint 5 --out x.csv
expect 2 "--overlay-timeint" '' frf --overlay-timeint 1 --plot p.png --out x.csv
expect 2 "--overlay-out" '' frf --overlay-out o.csv --out x.csv
expect 2 "--config" '' frf --config '' --out x.csv
expect 2 "--mu" 'write_system s.toml' frf --config s.toml --mu 0.3 --out x.csv

# ---- files ----------------------------------------------------------------------------
expect 2 "cannot be read" '' frf --config missing.toml --out x.csv
expect 2 "not a regular file" 'mkdir d.toml' frf --config d.toml --out x.csv
expect 2 "not a regular file" '' frf --config /dev/zero --out x.csv
expect 2 "not a regular file" 'mkfifo f.toml' frf --config f.toml --out x.csv
expect 2 "64 MB" 'truncate -s 65M big.toml' frf --config big.toml --out x.csv
expect 2 "missing table [structure]" ': > empty.toml' frf --config empty.toml --out x.csv
expect 2 "syntax error" 'head -c 3000 /dev/urandom | tr -d "\000" > junk.toml' frf --config junk.toml --out x.csv
expect 2 "deeper than 32" "printf '[%s]\\n' \"\$(printf 'a.%.0s' \$(seq 40000))a\" > deep.toml" frf --config deep.toml --out x.csv
expect 2 "deeper than 32" "printf 'a = %s%s\\n' \"\$(printf '[%.0s' \$(seq 40000))\" \"\$(printf ']%.0s' \$(seq 40000))\" > deep.toml" frf --config deep.toml --out x.csv
expect 2 "structure.colour" 'write_system s.toml; sed -i "2i colour = 1" s.toml' frf --config s.toml --out x.csv
expect 2 "contact[1].law" 'write_system s.toml; sed -i "s/law = \"dahl\"/law = 3/" s.toml' frf --config s.toml --out x.csv
expect 2 "structure.mass" 'write_system s.toml; sed -i "s/mass = \[1.0, 0.1\]/mass = [1.0, -0.1]/" s.toml' frf --config s.toml --out x.csv
expect 2 "not symmetric" 'write_system s.toml; sed -i "s/\[-0.1, 0.1\]\]/[-0.2, 0.1]]/" s.toml' frf --config s.toml --out x.csv
expect 2 "structure.mass" 'write_system s.toml; sed -i "s/mass = \[1.0, 0.1\]/mass = [nan, 0.1]/" s.toml' frf --config s.toml --out x.csv
expect 2 "same direction" "write_system s.toml '[[contact]]
dof = 1
other_dof = 2
law = \"coulomb\"
friction_limit = 0.1'; sed -i 's/law = \"dahl\"/law = \"coulomb\"/; /stiffness = 0.016/d' s.toml" frf --config s.toml --out x.csv
expect 2 "output.report" "write_system s.toml '[output]
report = [1, 1]'" frf --config s.toml --out x.csv
# Issue 28: three exact Coulomb contacts with dependent directions (1-ground, 2-ground, 1-2)
# are refused up front naming them, in frf and timeint alike.
DEPENDENT='printf "[structure]\nmass = [1.0, 1.0]\nstiffness = [[2.0, -1.0], [-1.0, 2.0]]\nexcitation = [1.0, 0.0]\n" > s.toml
for pair in "dof = 1" "dof = 2" "dof = 1\nother_dof = 2"; do printf "[[contact]]\n$pair\nlaw = \"coulomb\"\nfriction_limit = 0.3\n" >> s.toml; done'
expect 2 "contacts 1, 2 (w3 = w1 - w2" "$DEPENDENT" frf --config s.toml --out x.csv
expect 2 "contacts 1, 2 (w3 = w1 - w2" "$DEPENDENT" timeint --w 1 --config s.toml --out x.csv
# Issue 28: two uncoupled undamped oscillators (K = diag(1, 4)), exact Coulomb on DOF 1 only:
# harmonic 4 hits DOF 2's resonance exactly at wmin = 0.5 (the condensed start failed with
# "residual inf", exit 1); DOF 2's own resonance w = 2 inside the band is unbounded: capped.
UNCOUPLED='printf "[structure]\nmass = [1.0, 1.0]\nstiffness = [[1.0, 0.0], [0.0, 4.0]]\nexcitation = [0.2, 1.0]\n[[contact]]\ndof = 1\nlaw = \"coulomb\"\nfriction_limit = 0.3\n" > s.toml'
expect 0 "" "$UNCOUPLED" frf --quiet --config s.toml --wmin 0.5 --wmax 1.8
expect 3 "amplitude_cap" "$UNCOUPLED" frf --quiet --config s.toml --wmin 1.5 --wmax 2.5
expect 2 "output.report" "write_system s.toml '[output]
report = [3]'" frf --config s.toml --out x.csv
expect 0 "negative damping" "write_system s.toml; sed -i '4i damping = [[-0.01, 0.0], [0.0, 0.0]]' s.toml" frf --config s.toml --dry-run --out x.csv
expect 0 "K is indefinite" "write_system s.toml; sed -i 's/mass = \[1.0, 0.1\]/mass = [1.0, 0.1]/; s/\[\[1.1, -0.1\], \[-0.1, 0.1\]\]/[[-1.1, -0.1], [-0.1, 0.1]]/' s.toml" frf --config s.toml --dry-run --out x.csv
expect 2 "frequency.wmin" "write_system s.toml '[frequency]
wmin = -1.0'" frf --config s.toml --out x.csv
MTX='sed -i "s/stiffness = \[\[1.1, -0.1\], \[-0.1, 0.1\]\]/stiffness = \"k.mtx\"/" s.toml'
expect 2 "k.mtx" "write_system s.toml; $MTX" frf --config s.toml --out x.csv
expect 2 "not a regular file" "write_system s.toml; $MTX; mkdir k.mtx" frf --config s.toml --out x.csv
expect 2 "not a regular file" "write_system s.toml; sed -i 's|stiffness = \\[\\[1.1, -0.1\\], \\[-0.1, 0.1\\]\\]|stiffness = \"/dev/zero\"|' s.toml" frf --config s.toml --out x.csv
expect 2 "%%MatrixMarket" "write_system s.toml; $MTX; echo 'hello' > k.mtx" frf --config s.toml --out x.csv
expect 2 "given twice" "write_system s.toml; $MTX; printf '%%%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 1.1\n1 1 1.1\n2 2 0.1\n' > k.mtx" frf --config s.toml --out x.csv
expect 2 "more data than the size line" "write_system s.toml; $MTX; printf '%%%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1.1\n2 2 0.1\n2 1 -0.1\n' > k.mtx" frf --config s.toml --out x.csv
expect 2 "allowed square" "write_system s.toml; $MTX; printf '%%%%MatrixMarket matrix coordinate real symmetric\n3 2 1\n3 1 1.0\n' > k.mtx" frf --config s.toml --out x.csv
expect 2 "index out of range" "write_system s.toml; $MTX; printf '%%%%MatrixMarket matrix coordinate real general\n2 2 1\n3 1 1.0\n' > k.mtx" frf --config s.toml --out x.csv
expect 2 "allowed at most 1000000 rows" "write_system s.toml; $MTX; printf '%%%%MatrixMarket matrix coordinate real general\n20000000 20000000 1\n1 1 1.0\n' > k.mtx" frf --config s.toml --out x.csv
expect 2 "entries = " "write_system s.toml; $MTX; printf '%%%%MatrixMarket matrix coordinate real general\n2 2 99999999999\n1 1 1.0\n' > k.mtx" frf --config s.toml --out x.csv
expect 2 "structure.stiffness" "write_system s.toml; $MTX; printf '%%%%MatrixMarket matrix coordinate real general\n3 3 1\n1 1 1.0\n' > k.mtx" frf --config s.toml --out x.csv

# ---- design studies (hbf map, hbf optimize) ------------------------------------------
expect 2 "--values" '' map "${FAST[@]}" --param fe --values 0.1,nan --out x.csv
expect 2 "--values" '' map "${FAST[@]}" --param fe --values log:0:1:5 --out x.csv
expect 2 "--values" '' map "${FAST[@]}" --param mu --values 1:2:100001 --out x.csv
expect 2 "--values" '' map "${FAST[@]}" --param r --values 1e13 --out x.csv
expect 2 "--param" '' map "${FAST[@]}" --param '' --values 1 --out x.csv
expect 2 "--contact" '' map "${FAST[@]}" --param fe --values 1 --contact 2 --out x.csv
expect 2 "--summary" '' map "${FAST[@]}" --param fe --values 0.1 --out keep.csv --summary keep.csv
expect 2 "--plot" '' map "${FAST[@]}" --param fe --values 0.1 --plot x.png --out x.png
expect 2 "--range" '' optimize "${FAST[@]}" --range 1 --out x.csv
expect 2 "--range" '' optimize "${FAST[@]}" --range 1e300:1e301 --out x.csv
expect 2 "--max-frfs" '' optimize "${FAST[@]}" --scan 13 --max-frfs 5 --out x.csv
expect 2 "--summary" '' optimize "${FAST[@]}" --out keep.csv --summary keep.csv
expect 2 "--method" '' optimize "${FAST[@]}" --method simplex --out x.csv
expect 2 "--method tracking follows" '' optimize "${FAST[@]}" --param mu,wa --method tracking --out x.csv
expect 2 "--max-frfs bounds" '' optimize "${FAST[@]}" --method tracking --max-frfs 50 --out x.csv
expect 2 "--range" '' track "${FAST[@]}" --param mu --range 0.3 --out x.csv
expect 2 "--range" '' track "${FAST[@]}" --param mu --range 0.3:0.3 --out x.csv
expect 2 "--range" '' track "${FAST[@]}" --param mu --range nan:1 --out x.csv
expect 2 "--range" '' track "${FAST[@]}" --param mu --range -1:1 --out x.csv
expect 2 "--param is required" '' track "${FAST[@]}" --range 0.3:1 --out x.csv
expect 2 "--param" '' track "${FAST[@]}" --param zeta --range 0.3:1 --out x.csv
expect 2 "--feature" '' track "${FAST[@]}" --param mu --range 0.3:1 --feature valley --out x.csv
expect 2 "--output" '' track "${FAST[@]}" --param mu --range 0.3:1 --output y7 --out x.csv
expect 2 "--omega" '' track "${FAST[@]}" --param mu --range 0.3:1 --omega 9 --out x.csv
expect 2 "--at" '' track "${FAST[@]}" --param mu --range 0.3:1 --at 2 --out x.csv
expect 2 "--max-step-p" '' track "${FAST[@]}" --param mu --range 0.3:1 --max-step-p 0 --out x.csv
expect 2 "--min-step-p" '' track "${FAST[@]}" --param mu --range 0.3:1 --min-step-p 1 --out x.csv
expect 2 "--max-points" '' track "${FAST[@]}" --param mu --range 0.3:1 --max-points 5 --out x.csv
expect 2 "--of-contact" '' track "${FAST[@]}" --param mu --range 0.3:1 --of-contact 1 --out x.csv
expect 2 "--summary" '' track "${FAST[@]}" --param mu --range 0.3:1 --out keep.csv --summary keep.csv
expect 2 "--overlay" '' map "${FAST[@]}" --param fe --values 0.1 --overlay nothere.csv --out x.csv
expect 2 "an input of this run" '' map "${FAST[@]}" --param fe --values 0.1 --overlay keep.csv --out keep.csv
# Valid inputs whose computation finds nothing: exit 1 with what to do (not exit 2, "bad input").
expect 1 "nothing to track" '' track --param fe --range 1e-9:1e-3 --quiet --out /dev/null
expect 1 "use the golden-section method" '' optimize --method tracking --config "$SRC/examples/systems/den_hartog.toml" --quiet --out /dev/null
# Two interfaces on the same node would carry two contacts there: refused, naming both.
TWO_IFACES='[structure]
mass = [1.0, 1.0, 1.0]
stiffness = [[2.0, 0.0, -1.0], [0.0, 2.0, 0.0], [-1.0, 0.0, 2.0]]
excitation = [1.0, 0.0, 0.0]
[[interface]]
nodes = [[1, 2]]
normal = [0.0, 1.0]
law = "elastic"
friction_coefficient = 0.3
stiffness = 1.0
normal_stiffness = 1.0
preload_pressure = 1.0'
export TWO_IFACES
expect 2 "is also a node DOF of interface[1]" 'printf "%s\n%s\n" "$TWO_IFACES" "$(echo "$TWO_IFACES" | sed -n "/\[\[interface/,\$p")" >t.toml' frf --config t.toml --out x.csv
# An interface law without a normal direction is named as such (it blamed friction_coefficient);
# a rigid interface on nodes with mass names the interface node (the file has no "contact 1").
expect 2 "'jenkins' has no normal direction" 'echo "$TWO_IFACES" | sed "s/\"elastic\"/\"jenkins\"/" >t.toml' frf --config t.toml --out x.csv
expect 2 "contact 1 (interface[1] node 1): direction carries mass" 'echo "$TWO_IFACES" | sed "s/\"elastic\"/\"unilateral\"/;/^stiffness = 1.0/d;/^normal_stiffness/d" >t.toml' frf --config t.toml --out x.csv
# A stiffness entry beyond representable products is refused as such (it was "K_ii singular").
expect 2 "allowed |entry| <= 1e100" 'sed "s/^stiffness = \[\[1.5/stiffness = [[1e300/" "$SRC/examples/systems/liftoff3.toml" >k.toml' frf --config k.toml --out x.csv
# Cyclic symmetry: hbf nodal-diameters and sector files
WHEEL="$SRC/examples/systems/bladed_disk/wheel24.toml"
expect 2 "--config is required" '' nodal-diameters --out x.csv
expect 2 "not a sector" '' nodal-diameters --config "$SRC/examples/systems/chain3.toml" --out x.csv
for v in 0 101 -1 abc; do expect 2 "--harmonics" '' nodal-diameters --config "$WHEEL" --harmonics "$v" --out x.csv; done
expect 2 "--out" 'cp "$WHEEL" w.toml' nodal-diameters --config w.toml --out w.toml
expect 2 "cyclic.sectors" 'sed "s/^sectors = 24/sectors = 1/" "$WHEEL" >w.toml' frf --config w.toml --out x.csv
expect 2 "cyclic.right" 'sed "s/^right = \[5\]/right = [5, 4]/" "$WHEEL" >w.toml' frf --config w.toml --out x.csv
expect 2 "contact[1].neighbour_dof" 'sed "s/^neighbour_dof = 2/neighbour_dof = 9/" "$WHEEL" >w.toml' frf --config w.toml --out x.csv
expect 2 "not available for a sector model" '' timeint --config "$WHEEL" --w 4.5 --out x.csv
expect 2 "allowed an integer 0..23" '' map --config "$WHEEL" --param cyclic.engine_order --values 1.5 --out x.csv
expect 2 "takes integer values" '' track --config "$WHEEL" --param cyclic.engine_order --range 1:3 --out x.csv
expect 2 "modes of nodal diameter 3" '' modes --config "$WHEEL" --mode 9 --out x.csv
expect 2 "not for a sector model" 'sed "s/craig-bampton/macneal/; s#\"sector_#\"$SRC/examples/systems/bladed_disk/sector_#" "$SRC/examples/systems/bladed_disk/sector.toml" >s.toml' frf --config s.toml --out x.csv
expect 2 "not a sector" '' map --config "$SRC/examples/systems/chain3.toml" --param cyclic.engine_order --values 1 --out x.csv
expect 2 "stability" '' frf --config "$WHEEL" --stability on --out x.csv
expect 2 "does not take a sector model" '' frf --config "$WHEEL" --formulation condensed --modes 3 --out x.csv
# --jacobian structured with odd harmonics only names the reason (the structured form keeps every harmonic).
expect 2 "odd_harmonics" '' frf --config "$SRC/examples/systems/liftoff3_rigid.toml" --jacobian structured --harmonics odd:5 --out x.csv
# A frequency far from every stuck mode names none of them (it followed the nearest silently).
expect 2 "no mode of the stuck structure within 10 %" '' modes --near 1e9 --amin 0.01 --amax 1 --out x.csv
# A static load that pulls the contact off the wall: open at rest and at every point (exit 3,
# said); a normal direction that is not a unit vector is refused before any work.
expect 3 "is open at rest and stays open" 'sed "s/^excitation = .*/&\nstatic_load = [0.0, -3.0, 0.0]/" "$SRC/examples/systems/liftoff3.toml" >pull.toml' frf --config pull.toml --quiet --out /dev/null
expect 2 "allowed a unit vector" 'sed "s/^normal_direction = .*/normal_direction = [0.0, 2.0, 0.0]/" "$SRC/examples/systems/liftoff3.toml" >n.toml' frf --config n.toml --out x.csv
# An overlay that is not a regular file is refused before it is read (a FIFO blocked forever,
# /dev/zero read gigabytes, a directory was "empty"); an overlay without a plot is refused.
expect 2 "is not a regular file" 'mkfifo f' map "${FAST[@]}" --param fe --values 0.1 --overlay f --plot p.png --out x.csv
expect 2 "is not a regular file" 'mkfifo f' map "${FAST[@]}" --param fe --values 0.1 --overlay f --plot p.png --dry-run
expect 2 "is not a regular file" '' map "${FAST[@]}" --param fe --values 0.1 --overlay /dev/zero --plot p.png --out x.csv
expect 2 "is not a regular file" '' map "${FAST[@]}" --param fe --values 0.1 --overlay . --plot p.png --out x.csv
expect 2 "add --plot" 'printf "curve,fe,w\n1,0.1,1\n" >t.csv' map "${FAST[@]}" --param fe --values 0.1 --overlay t.csv --out x.csv

# ---- paths ----------------------------------------------------------------------------
expect 2 "--out" '' frf "${FAST[@]}" --out nodir/x.csv
expect 2 "--out" 'mkdir d' frf "${FAST[@]}" --out d
expect 2 "--out" '' frf "${FAST[@]}" --out ''
expect 2 "--summary" '' frf "${FAST[@]}" --out x.csv --summary ''
expect 2 "--summary" '' frf "${FAST[@]}" --out x.csv --summary nodir/s.json
expect 2 "--out" 'ln -s nowhere/x.csv dangling' frf "${FAST[@]}" --out dangling
expect 2 "--summary" '' frf "${FAST[@]}" --out keep.csv --summary keep.csv
expect 2 "--plot" '' frf "${FAST[@]}" --plot x.png --out x.png
expect 2 "--overlay-out" '' frf "${FAST[@]}" --plot p.png --overlay-timeint 3 --overlay-out keep.csv --out keep.csv
expect 2 "--summary" 'ln keep.csv hard.csv' frf "${FAST[@]}" --out keep.csv --summary hard.csv
expect 2 "--summary" 'ln -s keep.csv soft.csv' frf "${FAST[@]}" --out keep.csv --summary soft.csv
expect 2 "--plot" '' frf "${FAST[@]}" --plot x.bmp --out x.csv
expect 2 "--out" '' timeint --w 1 --out nodir/x.csv
expect 2 "--out" 'mkdir d' loop --w 1 --out d
expect 2 "--out" '' analytic --out nodir/x.csv
expect 2 "--out" '' frf "${FAST[@]}" --out - --summary -
expect 2 "standard output" '' frf "${FAST[@]}" --out /dev/stdout --summary -
expect 2 "not an open descriptor" '' frf "${FAST[@]}" --out /dev/fd/987
if [[ $(id -u) -ne 0 ]]; then
  # Permissions bind an unprivileged user only.
  expect 2 "--out" 'mkdir ro; chmod 555 ro' frf "${FAST[@]}" --out ro/x.csv
  expect 2 "--summary" 'mkdir ro; chmod 555 ro' frf "${FAST[@]}" --out x.csv --summary ro/s.json
  expect 2 "cannot be read" 'write_system s.toml; chmod 000 s.toml' frf --config s.toml --out x.csv
fi

# ---- outputs that are inputs, or one new file spelled twice (issue 28) -------------------
# An output may not be any input of the run: the config, a Matrix Market file it names, through
# a symlink or a hard link; in every command that reads a config.
MTXK="write_system s.toml; $MTX; printf '%%%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 1.1\n2 1 -0.1\n2 2 0.1\n' > k.mtx"
expect 2 "an input of this run" 'write_system s.toml' frf --config s.toml --out s.toml
expect 2 "an input of this run" 'write_system s.toml; ln -s s.toml link.toml' frf --config s.toml --out link.toml
expect 2 "an input of this run" 'write_system s.toml; ln -s s.toml link.toml' frf --config link.toml --summary s.toml --out x.csv
expect 2 "an input of this run" 'write_system s.toml; ln s.toml hard.toml' frf --config s.toml --out hard.toml
expect 2 "is structure.stiffness" "$MTXK" frf --config s.toml --summary k.mtx --out x.csv
expect 2 "is structure.stiffness" "$MTXK; ln k.mtx hard.mtx" frf --config s.toml --out hard.mtx
expect 2 "an input of this run" 'write_system s.toml' timeint --config s.toml --w 1 --out s.toml
expect 2 "is structure.stiffness" "$MTXK" timeint --config s.toml --w 1 --out k.mtx
expect 2 "an input of this run" 'write_system s.toml' loop --config s.toml --w 1 --out s.toml
expect 2 "an input of this run" 'write_system s.toml' map --config s.toml --param mu --values 0.2 --out s.toml
expect 2 "an input of this run" 'write_system s.toml' map --config s.toml --param mu --values 0.2 --out x.csv --summary s.toml
expect 2 "an input of this run" 'write_system s.toml' optimize --config s.toml --out s.toml
expect 2 "an input of this run" 'write_system s.toml' track --config s.toml --param fe --range 1:0.9 --out s.toml
# Two outputs naming one new file, spelled differently.
expect 2 "name the same file" '' frf "${FAST[@]}" --out o.csv --summary ./o.csv
expect 2 "name the same file" 'mkdir sub' frf "${FAST[@]}" --out o.csv --summary sub/../o.csv
expect 2 "name the same file" '' frf "${FAST[@]}" --out o.csv --summary /proc/self/cwd/o.csv
expect 2 "name the same file" 'ln -s . here' frf "${FAST[@]}" --out o.csv --summary here/o.csv
expect 2 "name the same file" '' frf "${FAST[@]}" --plot p.png --overlay-timeint 3 --overlay-out ./o.csv --out o.csv
# A FIFO without a reader: refused before the work (it would block forever after it).
expect 2 "FIFO without a reader" 'mkfifo f' frf "${FAST[@]}" --out f
expect 2 "FIFO without a reader" 'mkfifo f' timeint --w 1 --out f
expect 2 "FIFO without a reader" 'mkfifo f' frf "${FAST[@]}" --dry-run --out f

# ---- numbers in files are read whole (issue 28) ----------------------------------------
K1="write_system s.toml; $MTX; printf '%%%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 %s\n2 1 -0.1\n2 2 0.1\n'"
for v in '1,1' '1.1abc' '0x1.1p0' '1.1.1' 'D1'; do
  expect 2 "k.mtx:3: field 3 (value) = '$v' is not a decimal number" "$K1 '$v' > k.mtx" frf --config s.toml --out x.csv
done
for v in nan inf 1e999; do expect 2 "k.mtx:3: field 3 (value) = '$v' is not finite" "$K1 '$v' > k.mtx" frf --config s.toml --out x.csv; done
expect 2 "k.mtx:2: 4 fields: expected 3" "write_system s.toml; $MTX; printf '%%%%MatrixMarket matrix coordinate real symmetric\n2 2 3 9\n1 1 1.1\n2 1 -0.1\n2 2 0.1\n' > k.mtx" frf --config s.toml --out x.csv
expect 2 "k.mtx:3: 4 fields: expected 3" "$K1 '1.1 7' > k.mtx" frf --config s.toml --out x.csv
expect 0 "" "$K1 '1.1D0' > k.mtx" frf --config s.toml --quiet --harmonics 3 --error-points 0 --out /dev/null
for v in '1,5' '1.1abc' '0x1p0' '1.0DD1'; do expect 2 "--mu = '$v' is not a decimal number" '' frf --mu "$v" --out x.csv; done

# ---- devices --------------------------------------------------------------------------
# Legal: written in place, the device survives (the directory is unchanged: nothing in it).
expect 0 "" '' frf "${FAST[@]}" --quiet --out /dev/null --summary /dev/null
expect 0 "" '' analytic --out /dev/null
expect 1 "/dev/full" '' analytic --out /dev/full
expect 1 "/dev/full" '' frf "${FAST[@]}" --quiet --out /dev/full
expect 2 "--plot" '' frf "${FAST[@]}" --out /dev/null --summary /dev/null --plot /dev/null
expect 0 "dry run" '' frf "${FAST[@]}" --dry-run --out x.csv --summary s.json
expect 2 "--dry-run takes no value" '' frf "${FAST[@]}" --dry-run --dry-run=0 --out x.csv

# ---- messages name the parameter, and their advice is right (issue 28) ------------------
expect 2 "s.toml:13: key 'solver.time_samples': 15 is out of range" "write_system s.toml '[solver]
harmonics = 10
time_samples = 15'" frf --config s.toml --out x.csv
FD="write_system s.toml; sed -i 's/^dof = 1\$/force_direction = [1e-300, -1e-300]/; /^other_dof/d; s/law = \"dahl\"/law = \"coulomb\"/; /stiffness = 0.016/d' s.toml"
expect 2 "force_direction has largest entry 1e-300: allowed 1e-100..1e100" "$FD" frf --config s.toml --out x.csv
PAR="write_system s.toml '[[contact]]
force_direction = [-2.0, 2.0]
law = \"coulomb\"
friction_limit = 0.2'; sed -i 's/^dof = 1\$/force_direction = [1.0, -1.0]/; /^other_dof/d; s/law = \"dahl\"/law = \"coulomb\"/; /stiffness = 0.016/d' s.toml"
expect 2 "friction_limit = 0.2 + 2 * 0.2 = 0.6" "$PAR" frf --config s.toml --out x.csv
expect 2 "--at = '1,1,1' lists w = 1 more than once" '' frf "${FAST[@]}" --at 1,1,1 --out x.csv

# ---- bounded time and memory on allowed inputs (issue 28) -------------------------------
# Every case above and below runs under 1 GB of address space and 60 s (expect).
expect 0 "" '' frf --wmin 1e-12 --wmax 1e-11 --quiet --out /dev/null
expect 0 "" '' frf --wmin 1e-6 --wmax 1e-5 --quiet --out /dev/null
expect 2 "Taylor steps" '' frf --wmin 1e-12 --wmax 1e-11 --exact on --out x.csv
expect 2 "Taylor steps" '' timeint --w 1e-9 --method exact --out x.csv
expect 2 "Taylor steps" 'write_system s.toml; sed -i "s/law = \"dahl\"/law = \"jenkins\"/; s/stiffness = 0.016/stiffness = 1e12/" s.toml' frf --config s.toml --exact on --out x.csv
# 100 reported outputs: every output's exact peaks refined (3.8 s; 14.5 s with golden section).
OUTPUTS="write_system s.toml; sed -i 's/law = \"dahl\"/law = \"coulomb\"/; /stiffness = 0.016/d' s.toml; for i in \$(seq 100); do printf '[[output]]\nname = \"o%d\"\nrow = [1.0, 0.0%02d]\n' \$i \$i >> s.toml; done"
expect 0 "" "$OUTPUTS" frf --config s.toml --quiet --out /dev/null
# Far above the resonances (a 1 Hz structure at 10 kHz and beyond): converged and right (the
# closed form and --method exact are checked in tests/test_cli_timeint.cpp), or not converged.
for w in 1e4 1e6 1e9; do
  for m in adams bdf exact; do expect 0 "" '' timeint --w "$w" --method "$m" --quiet --out /dev/null; done
done
expect 0 "" '' loop --w 1e6 --out /dev/null
MANY="write_system s.toml; for i in \$(seq 1000); do printf '[[contact]]\ndof = 1\nlaw = \"dahl\"\nfriction_limit = 0.2\nstiffness = 0.016\n' >> s.toml; done"
expect 2 "MB for the receptances and the preconditioner" "$MANY" frf --config s.toml --out x.csv
expect 2 "MB for the receptances and the preconditioner" "$MANY" frf --config s.toml --dry-run --out x.csv
expect 2 "harmonic-balance unknowns" "$MANY" frf --config s.toml --jacobian dense --out x.csv

# ---- signals, limits, modes and TMPDIR (issue 28): no temporary file is ever left -------
# manual NAME: a fresh directory for a case whose run is not a plain `expect`.
manual() {
  cases=$((cases + 1))
  ARGS=("$1")
  M="$WORK/case$cases"
  mkdir -p "$M" && chmod 777 "$M"
  : >"$WORK/err"
}
leftovers() { find "$M" -name '*.tmp*' | head -3; }
# SIGTERM, SIGINT and SIGHUP during the computation: the frequencies done are written with a
# warning naming the signal (exit 3), and no temporary file is left. The signal is sent once hbf
# itself catches it (/proc's SigCgt of the process running $HBF): a fixed delay raced a slow
# start (a sanitizer build under load took more than a second to install its handler).
handler_installed() {  # PID SIGNAL_NUMBER
  [[ $(readlink "/proc/$1/exe" 2>/dev/null) == "$HBF" ]] || return 1
  local mask
  mask=$(awk '/^SigCgt:/ {print $2}' "/proc/$1/status" 2>/dev/null)
  [[ -n $mask ]] && (((16#$mask >> ($2 - 1)) & 1))
}
for sig in TERM INT HUP; do
  manual "SIG$sig during hbf timeint"
  (cd "$M" && exec "$HBF" timeint --wmin 0.5 --wmax 1.6 --points 400 --out o.csv 2>"$WORK/err") &
  pid=$!
  for _ in $(seq 600); do handler_installed "$pid" "$(kill -l "$sig")" && break; sleep 0.1; done
  handler_installed "$pid" "$(kill -l "$sig")" || fail "SIG$sig: hbf did not catch the signal within 60 s"
  sleep 0.2
  kill -s "$sig" "$pid" 2>/dev/null
  { wait "$pid"; } 2>/dev/null
  got=$?
  [[ -z $(leftovers) ]] || fail "SIG$sig left $(leftovers)"
  [[ $got -eq 3 ]] || fail "SIG$sig: exit $got, expected 3"
  [[ -s $M/o.csv ]] || fail "SIG$sig: the frequencies done were not written"
  grep -qF "interrupted (SIG$sig)" "$WORK/err" || fail "SIG$sig: no warning naming the signal"
done
# A file-size limit (SIGXFSZ): the write fails (exit 1), the old file and no temporary remain.
manual "ulimit -f"
echo "old" >"$M/o.csv"
(cd "$M" && ulimit -f 1 && "$HBF" frf "${FAST[@]}" --quiet --out o.csv 2>"$WORK/err")
got=$?
[[ $got -eq 1 ]] || fail "ulimit -f: exit $got, expected 1"
grep -qF "cannot write output file 'o.csv'" "$WORK/err" || fail "ulimit -f: no message naming o.csv"
[[ $(cat "$M/o.csv") == old ]] || fail "ulimit -f: o.csv changed"
[[ -z $(leftovers) ]] || fail "ulimit -f left $(leftovers)"
# A replaced output keeps its mode.
manual "mode 600 kept"
echo "old" >"$M/o.csv"
chmod 600 "$M/o.csv"
(cd "$M" && "$HBF" frf "${FAST[@]}" --quiet --out o.csv 2>"$WORK/err") || fail "mode: the run failed"
[[ $(stat -c %a "$M/o.csv") == 600 ]] || fail "mode: o.csv is $(stat -c %a "$M/o.csv") after the run, was 600"
# TMPDIR that does not exist: the plot and the CSV are written (nothing goes to TMPDIR).
manual "TMPDIR=/nonexistent"
(cd "$M" && TMPDIR=/nonexistent "$HBF" frf "${FAST[@]}" --quiet --plot p.png --out o.csv 2>"$WORK/err")
got=$?
[[ $got -eq 0 && -s $M/o.csv && -s $M/p.png ]] || fail "TMPDIR=/nonexistent: exit $got, o.csv or p.png missing"
[[ -z $(leftovers) && -z $(find "$M" -name '.*.tmp*') ]] || fail "TMPDIR=/nonexistent left temporary files"
# /dev/tty without a controlling terminal: refused before the work.
if command -v setsid >/dev/null; then
  manual "/dev/tty without a terminal"
  (cd "$M" && setsid "$HBF" frf "${FAST[@]}" --out /dev/tty </dev/null >/dev/null 2>"$WORK/err")
  got=$?
  [[ $got -eq 2 ]] || fail "/dev/tty: exit $got, expected 2"
  grep -qF -- "--out = '/dev/tty' (a character device) cannot be opened" "$WORK/err" || fail "/dev/tty: message"
fi
# A FIFO with a reader gets the whole CSV (held open from the check to the write).
manual "FIFO with a reader"
mkfifo "$M/f"
cat "$M/f" >"$M/read.csv" &
reader=$!
(cd "$M" && "$HBF" frf "${FAST[@]}" --quiet --out f 2>"$WORK/err") || fail "FIFO: the run failed"
wait "$reader"
(cd "$M" && "$HBF" frf "${FAST[@]}" --quiet --out direct.csv 2>>"$WORK/err")
cmp -s "$M/read.csv" "$M/direct.csv" || fail "FIFO: the reader did not get the CSV"

echo "hostile inputs [$who]: $cases cases, $failures failed"
status=$((failures > 0))

# As root: the same list again as an unprivileged user, where permissions apply.
if [[ $PASS == both && $(id -u) -eq 0 ]]; then
  bash "$0" "$HBF" "$SRC" nobody
  got=$?
  if [[ $got -eq 77 ]]; then
    echo "hostile inputs: the unprivileged pass was skipped (nobody cannot run $HBF, or setpriv is missing)"
  elif [[ $got -ne 0 ]]; then
    status=1
  fi
fi
exit $status
