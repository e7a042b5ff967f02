#!/usr/bin/env bash
# run_tests.sh: the test harness (run it as ./run.sh test, which sets the environment).
#   ./run.sh test                 every test
#   ./run.sh test --bless CASE    run the regression case CASE, check its physics and, only
#                                 if that passes, copy its outputs to tests/ref/CASE/
#                                 (review the diff with git before committing it)
# Prints one "ok N - name" / "not ok N - name" line per test, diagnostics on "#" lines,
# and ends with "N passed, N failed". Exit status 1 if any test failed.
set -u
tests="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$tests")"
cd "$root" || exit 1
PYTHON="${PYTHON:-/usr/bin/python3}"
FREEFEM=(FreeFem++-nw -ns -v 0)
work=tests/work              # relative, so that outputs do not depend on the checkout's path
mkdir -p "$work"
passed=0 failed=0 count=0

solve() { "${FREEFEM[@]}" edp/solve.edp "$@"; }

report() { # report STATUS NAME [diagnostic file]
  count=$((count + 1))
  if [ "$1" = 0 ]; then
    passed=$((passed + 1)); echo "ok $count - $2"
  else
    failed=$((failed + 1)); echo "not ok $count - $2"
    [ -n "${3:-}" ] && [ -s "$3" ] && sed 's/^/# /' "$3" | head -40
  fi
}

# Outputs without their timing lines, which differ from run to run.
strip_timing() { grep -v '^time_' "$1"; }

trim() { local s="$1"; s="${s#"${s%%[![:space:]]*}"}"; printf '%s' "${s%"${s##*[![:space:]]}"}"; }

declare -A case_options case_abs case_rel case_check
case_names=()
while IFS='|' read -r name options abs rel check; do
  name="$(trim "$name")"
  case "$name" in ''|'#'*) continue ;; esac
  case_names+=("$name")
  case_options[$name]="$(trim "$options")"
  case_abs[$name]="$(trim "$abs")"
  case_rel[$name]="$(trim "$rel")"
  case_check[$name]="$(trim "${check:-}")"
done < tests/cases.txt

# run_case NAME: solve and check physics; leaves the outputs in tests/work/NAME
run_case() {
  local name="$1" log="$work/$1.log"
  # shellcheck disable=SC2086
  if ! solve ${case_options[$name]} -out "$work/$name" > "$log" 2>&1; then
    echo "solve failed:" >> "$log"; return 1
  fi
  # shellcheck disable=SC2086
  "$PYTHON" tests/check_results.py "$work/$name" ${case_check[$name]} >> "$log" 2>&1
}

bless() {
  local name="$1" log="$work/$1.log"
  if [ -z "${case_options[$name]+x}" ]; then echo "run_tests.sh: no case '$name' in tests/cases.txt" >&2; exit 2; fi
  if ! run_case "$name"; then cat "$log" >&2; echo "run_tests.sh: $name fails its physics checks: not blessed" >&2; exit 1; fi
  mkdir -p "tests/ref/$name"
  local f
  for f in contact.txt fields.txt history.txt summary.txt; do
    strip_timing "$work/$name/$f" > "tests/ref/$name/$f"
  done
  echo "run_tests.sh: blessed tests/ref/$name from $work/$name (physics checks passed); review with git diff"
  exit 0
}

if [ "${1:-}" = "--bless" ]; then
  [ $# -eq 2 ] || { echo "usage: run_tests.sh --bless CASE" >&2; exit 2; }
  bless "$2"
fi
[ $# -eq 0 ] || { echo "usage: run_tests.sh [--bless CASE]" >&2; exit 2; }

echo "# FreeFem++: $(command -v FreeFem++-nw), gmsh $(gmsh --version 2>&1 | head -1), numdiff $(numdiff --version 2>/dev/null | head -1 | awk '{print $2}')"

# ---- regression cases: physics, then numdiff against the blessed reference
for name in "${case_names[@]}"; do
  diag="$work/$name.diag"; : > "$diag"
  status=0
  if ! run_case "$name"; then status=1; cat "$work/$name.log" > "$diag"; fi
  report $status "$name: runs and passes the physics checks" "$diag"
  : > "$diag"; status=0
  for f in contact.txt fields.txt history.txt summary.txt; do
    ref="tests/ref/$name/$f"
    if [ ! -f "$ref" ]; then
      echo "missing reference $ref (create it with ./run.sh test --bless $name)" >> "$diag"; status=1; continue
    fi
    if [ ! -f "$work/$name/$f" ]; then echo "no output $work/$name/$f" >> "$diag"; status=1; continue; fi
    strip_timing "$work/$name/$f" > "$work/$name.$f.cmp"
    if ! numdiff -q -a "${case_abs[$name]}" -r "${case_rel[$name]}" "$ref" "$work/$name.$f.cmp" > /dev/null 2>&1; then
      status=1
      echo "$f differs from $ref (abs ${case_abs[$name]}, rel ${case_rel[$name]}); first differences:" >> "$diag"
      numdiff -S -a "${case_abs[$name]}" -r "${case_rel[$name]}" "$ref" "$work/$name.$f.cmp" 2>&1 | head -12 >> "$diag"
    fi
  done
  report $status "$name: matches tests/ref/$name" "$diag"
done

# ---- the full-system Newton gives the same discrete solution as the condensed one
for problem in original penalty; do
  base="paper-coarse-$problem"
  diag="$work/full-$problem.diag"; : > "$diag"
  # shellcheck disable=SC2086
  if solve ${case_options[$base]} -solver full -out "$work/full-$problem" > "$diag" 2>&1 \
     && "$PYTHON" tests/check_results.py "$work/full-$problem" --compare "$work/$base" --rtol 1e-9 >> "$diag" 2>&1; then
    report 0 "full-system Newton = condensed Newton to 1e-9 ($problem)"
  else
    report 1 "full-system Newton = condensed Newton to 1e-9 ($problem)" "$diag"
  fi
done

# ---- runs that must fail: exit code, message, and no results
# expect_failure NAME CODE REGEX OPTIONS...
expect_failure() {
  local name="$1" code="$2" regex="$3"; shift 3
  local out="$work/fail-$count" diag="$work/fail.diag"
  rm -rf "$out" "$out.partial"
  solve -out "$out" "$@" > "$diag" 2>&1
  local rc=$?
  local status=0
  if [ "$rc" != "$code" ]; then echo "exit code $rc, expected $code" >> "$diag"; status=1; fi
  if ! grep -Eq "$regex" "$diag"; then echo "message does not match /$regex/" >> "$diag"; status=1; fi
  if [ -e "$out" ] || [ -e "$out.partial" ]; then echo "results were written in $out" >> "$diag"; status=1; fi
  report $status "refused: $name" "$diag"
}
coarse=(-nx 8 -ny 4 -dt 0.1)
expect_failure "unknown option" 2 "unknown option '-foo'" -foo 1
expect_failure "option without value" 2 "option -dt needs a value" -dt
expect_failure "repeated option" 2 "option -nx is given twice" -nx 8 -nx 9
expect_failure "not a number" 2 "option -dt must be a real number, got 'abc'" -dt abc
expect_failure "dt <= 0" 2 "option -dt = 0 is out of range: it must be > 0" -dt 0
expect_failure "T/dt not whole" 2 "does not divide T" -dt 0.3
expect_failure "nu >= 0.5" 2 "option -nu = 0.5 is out of range: it must be < 0.5" -nu 0.5
expect_failure "unknown problem" 2 "option -problem = 'dual' is not one of original\|penalty" -problem dual
expect_failure "unknown scene" 2 "option -scene = 'moon'" -scene moon
expect_failure "missing mesh file" 3 "cannot read the file" -mesh "$work/no-such.msh"
printf '$MeshFormat\n4.1 0 8\n$EndMeshFormat\n' > "$work/v41.msh"
expect_failure "MSH 4.1 mesh" 3 "not a gmsh MSH 2.2 file; re-export it with: gmsh -2 -format msh22" -mesh "$work/v41.msh"
gmsh -2 -format msh22 -v 0 -setnumber nx 4 -setnumber ny 2 tests/data/unlabelled.geo -o "$work/unlabelled.msh" > /dev/null 2>&1
expect_failure "mesh without physical groups" 3 "has no boundary label" -mesh "$work/unlabelled.msh"
expect_failure "no convergence (maxit 1)" 4 "step 1 \(t = .*\): the contact solver did not converge after 1 iterations .*residual" "${coarse[@]}" -maxit 1

# ---- a failed run leaves earlier results untouched
diag="$work/keep.diag"; : > "$diag"; status=0
rm -rf "$work/keep"
solve "${coarse[@]}" -out "$work/keep" > "$diag" 2>&1 || status=1
cp "$work/keep/contact.txt" "$work/keep.contact.before" 2>/dev/null || status=1
solve "${coarse[@]}" -maxit 1 -out "$work/keep" >> "$diag" 2>&1 && status=1
cmp -s "$work/keep/contact.txt" "$work/keep.contact.before" || { echo "earlier results changed" >> "$diag"; status=1; }
[ -e "$work/keep.partial" ] && { echo "partial folder left behind" >> "$diag"; status=1; }
report $status "a failed run leaves the earlier results untouched" "$diag"

# ---- reproducibility: the same options give byte-identical outputs (timings aside)
diag="$work/repro.diag"; : > "$diag"; status=0
rm -rf "$work/repro" "$work/repro.first"
solve "${coarse[@]}" -out "$work/repro" > "$diag" 2>&1 && mv "$work/repro" "$work/repro.first" || status=1
solve "${coarse[@]}" -out "$work/repro" >> "$diag" 2>&1 || status=1
for f in contact.txt fields.txt history.txt summary.txt; do
  cmp -s <(strip_timing "$work/repro.first/$f") <(strip_timing "$work/repro/$f") || { echo "$f differs between two runs" >> "$diag"; status=1; }
done
report $status "two runs with the same options give identical outputs" "$diag"

echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
