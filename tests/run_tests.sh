#!/usr/bin/env bash
# run_tests.sh: the test harness (run it as ./run.sh test, which sets the environment).
#   ./run.sh test                 every test
#   ./run.sh test --bless CASE    run the regression case CASE, check its physics and, only
#                                 if that passes, copy its outputs to tests/ref/CASE/
#                                 (review the diff with git before committing it)
# Prints one "ok N - name" / "not ok N - name" line per test, diagnostics on "#" lines,
# and ends with "N passed, N failed". Exit status 1 if any test failed.
set -u
# A terminating signal stops the processes the harness started (each solve removes what it
# created), once the command running in the foreground returns, then the harness itself.
descendants() { local child; for child in $(cat /proc/"$1"/task/*/children 2>/dev/null); do descendants "$child"; echo "$child"; done; }
stop_harness() {
  trap - TERM INT HUP
  local pid
  for pid in $(descendants $$); do kill -TERM "$pid" 2> /dev/null; done
  wait
  echo "run_tests.sh: stopped by a signal" >&2
  exit "$1"
}
trap 'stop_harness 143' TERM; trap 'stop_harness 130' INT; trap 'stop_harness 129' HUP
tests="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$tests")"
cd "$root" || exit 1
PYTHON="${PYTHON:-/usr/bin/python3}"
export PYTHONPATH="$root/plots${PYTHONPATH:+:$PYTHONPATH}"   # plots/suite.py, as run.sh sets it
FREEFEM=(FreeFem++-nw -ns -v 0)
work=tests/work              # relative, so that outputs do not depend on the checkout's path
mkdir -p "$work"
passed=0 failed=0 count=0

solve() { "${FREEFEM[@]}" edp/solve.edp "$@"; }
OUTPUT_FILES=(contact.txt fields.txt history.txt contact_history.txt summary.txt)

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

# run_case NAME: solve and check physics (and, for --independent cases, agreement with
# tests/independent_solver.py to 1e-9; --independent3d: tests/independent_solver3d.py);
# leaves the outputs in tests/work/NAME
run_case() {
  local name="$1" log="$work/$1.log" check="${case_check[$1]}" independent=0 solver=tests/independent_solver.py
  case " $check " in *" --independent3d "*) independent=1; solver=tests/independent_solver3d.py; check="${check/--independent3d/}" ;; esac
  case " $check " in *" --independent "*) independent=1; check="${check/--independent/}" ;; esac
  # shellcheck disable=SC2086
  if ! solve ${case_options[$name]} -out "$work/$name" > "$log" 2>&1; then
    echo "solve failed:" >> "$log"; return 1
  fi
  # shellcheck disable=SC2086
  "$PYTHON" tests/check_results.py "$work/$name" $check >> "$log" 2>&1 || return 1
  if [ "$independent" = 1 ]; then
    "$PYTHON" "$solver" --compare "$work/$name" --rtol 1e-9 >> "$log" 2>&1 \
      || { echo "disagrees with $solver" >> "$log"; return 1; }
  fi
  return 0
}

# Outputs prepared for numdiff: no timing lines, no round-off-only lines (check_*), and not
# the counts of how the Newton matrix was solved (factorizations or low-rank corrections:
# which one a step uses depends on a round-off residual test, not on the physics).
numeric_view() { grep -v -e '^time_' -e '^check_' -e '^newton_factorizations ' -e '^newton_low_rank_corrections ' -e '^newton_refinements ' "$1"; }

# compare_numeric MODE REF NEW ABS REL [EXCLUDED FIELD...]: numdiff (MODE -q quiet or
# -S statistics) with a per-column absolute floor ABS * the column's scale in REF (ABS alone
# for an all-zero column). The scale of a column is its largest |value|, or that of its
# family, the columns of one unit named in the header (the last comment line before the
# data): velocities, stresses, energies, forces, displacements. A column that is zero up to
# the solver's tolerance (lambda_nu of a run that never reaches the bound, the contact work
# in free flight) is then compared at the scale of its unit, not at that of its own noise;
# velocities at least at g, stresses at least at c_nu g (the parameter lines of REF).
compare_numeric() {
  local mode="$1" ref="$2" new="$3" abs="$4" rel="$5"; shift 5
  local args=() field floor
  while read -r field floor; do args+=(-a "$floor:$field"); done < <(
    awk -v abs="$abs" '
      BEGIN { split("v_nu v_tau v_x v_y v_tau2 v_z", a); for (k in a) fam[a[k]] = "velocity"
              split("p_nu lambda_nu lambda_tau friction_bound lambda_tau2", a); for (k in a) fam[a[k]] = "stress"
              split("kinetic elastic numerical_dissipation viscous_dissipation contact_dissipation external_work kinetic_jump elastic_jump", a)
              for (k in a) fam[a[k]] = "energy"
              split("normal_force tangential_force tangential_force2", a); for (k in a) fam[a[k]] = "force"
              split("u_x u_y u_z", a); for (k in a) fam[a[k]] = "displacement" }
      /^# cnu / { cnu = $3 } /^# g / { g = $3 }
      /^#/ { if (!data) { header = $0 }; next }
      { if (!data) { data = 1; nh = split(header, h); for (i = 2; i <= nh; i++) family[i - 1] = fam[h[i]] }
        for (i = 1; i <= NF; i++) if ($i + 0 == $i) { v = $i < 0 ? -$i : $i; if (v == v && v < 1e300 && v > m[i]) m[i] = v; if (i > n) n = i } }
      END { fm["velocity"] = g + 0; fm["stress"] = cnu * g      # at least the scales of the law: g and p(g)
            for (i = 1; i <= n; i++) if (family[i] != "" && m[i] > fm[family[i]]) fm[family[i]] = m[i]
            for (i = 1; i <= n; i++) { s = family[i] != "" ? fm[family[i]] : m[i]; printf "%d %.3e\n", i, (s > 0 ? abs * s : abs) } }' "$ref")
  for field in "$@"; do args+=(-X "1:$field" -X "2:$field"); done
  numdiff "$mode" -r "$rel" "${args[@]}" "$ref" "$new"
}

bless() {
  local name="$1" log="$work/$1.log"
  if ! run_case "$name"; then cat "$log" >&2; echo "run_tests.sh: $name fails its physics checks: not blessed" >&2; exit 1; fi
  mkdir -p "tests/ref/$name"
  local f
  for f in "${OUTPUT_FILES[@]}"; do
    numeric_view "$work/$name/$f" > "tests/ref/$name/$f"
  done
  echo "run_tests.sh: blessed tests/ref/$name from $work/$name (physics checks passed); review with git diff"
  exit 0
}

if [ "${1:-}" = "--bless" ]; then
  if [ $# -ne 2 ] || [ -z "$2" ] || [ -z "${case_options[$2]+x}" ]; then
    echo "usage: ./run.sh test --bless CASE, CASE one of: ${case_names[*]}" >&2; exit 2
  fi
  bless "$2"
fi
[ $# -eq 0 ] || { echo "usage: run_tests.sh [--bless CASE]" >&2; exit 2; }
find "$work" -mindepth 1 -delete      # the harness's own folder: start clean

echo "# FreeFem++: $(command -v FreeFem++-nw), gmsh $(gmsh --version 2>&1 | head -1), numdiff $(numdiff --version 2>/dev/null | head -1 | awk '{print $2}')"

coarse_options=(-nx 8 -ny 4 -dt 0.1)
# ---- regression cases: physics, then numdiff against the blessed reference
for name in "${case_names[@]}"; do
  diag="$work/$name.diag"; : > "$diag"
  status=0
  if ! run_case "$name"; then status=1; cat "$work/$name.log" > "$diag"; fi
  report $status "$name: runs and passes the physics checks" "$diag"
  : > "$diag"; status=0
  for f in "${OUTPUT_FILES[@]}"; do
    ref="tests/ref/$name/$f"
    if [ ! -f "$ref" ]; then
      echo "missing reference $ref (create it with ./run.sh test --bless $name)" >> "$diag"; status=1; continue
    fi
    if [ ! -f "$work/$name/$f" ]; then echo "no output $work/$name/$f" >> "$diag"; status=1; continue; fi
    numeric_view "$work/$name/$f" > "$work/$name.$f.cmp"
    excluded=()
    [ "$f" = history.txt ] && excluded=(4 11)      # residual, energy_residual
    if ! compare_numeric -q "$ref" "$work/$name.$f.cmp" "${case_abs[$name]}" "${case_rel[$name]}" "${excluded[@]}" > /dev/null 2>&1; then
      status=1
      echo "$f differs from $ref (abs ${case_abs[$name]} x column scale, rel ${case_rel[$name]}); first differences:" >> "$diag"
      compare_numeric -S "$ref" "$work/$name.$f.cmp" "${case_abs[$name]}" "${case_rel[$name]}" "${excluded[@]}" 2>&1 | head -12 >> "$diag"
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

# ---- the fixed point solves the same discrete problem as Newton: the paper scene at the
# defaults (the blessed cases' runs), then points of our own that no sweep of
# tests/stability.sh runs (other scenes, r, meshes, time steps), for both solvers; where
# neither can converge, both fail loudly
for problem in original penalty; do
  diag="$work/fixedpoint-$problem.diag"; : > "$diag"; status=0
  # shellcheck disable=SC2086
  if solve ${case_options[paper-$problem]} -solver fixedpoint -out "$work/fixedpoint-$problem" > "$diag" 2>&1 \
     && "$PYTHON" tests/check_results.py "$work/fixedpoint-$problem" --compare "$work/paper-$problem" --rtol 1e-8 >> "$diag" 2>&1; then
    mean=$(awk '$1 == "iterations_total" { t = $2 } $1 == "steps" { s = $2 } END { printf "%.1f", t / s }' "$work/fixedpoint-$problem/summary.txt")
    awk -v m="$mean" 'BEGIN { exit !(m > 0 && m <= 100) }' || { echo "fixed point: $mean iterations a step (target <= 100)" >> "$diag"; status=1; }
  else
    status=1
  fi
  report $status "fixed point at its defaults = Newton to 1e-8 on the paper scene ($problem), at most 100 iterations a step on average" "$diag"
done
diag="$work/heldout.diag"; : > "$diag"; status=0
# a block whose contact side is a concave arc, with friction (the default Newton of an earlier
# version failed on it)
gmsh -2 -format msh22 -v 0 tests/data/arc.geo -o "$work/arc.msh" > /dev/null 2>&1 || status=1
grep -v -E '^(geometry|contact_normal|nx|ny|Lx|Ly) ' edp/scenes/paper.scene > "$work/arc.scene"
while IFS='|' read -r name options; do
  [ -n "$name" ] || continue
  # shellcheck disable=SC2086
  for solver in newton fixedpoint; do
    solve $options -solver "$solver" -out "$work/heldout-$name-$solver" > "$work/heldout.log" 2>&1 \
      || { echo "$name ($solver) did not converge:" >> "$diag"; tail -n 2 "$work/heldout.log" >> "$diag"; status=1; }
  done
  [ -d "$work/heldout-$name-newton" ] && [ -d "$work/heldout-$name-fixedpoint" ] || continue
  "$PYTHON" tests/check_results.py "$work/heldout-$name-fixedpoint" --compare "$work/heldout-$name-newton" --rtol 1e-8 >> "$diag" 2>&1 \
    || { echo "$name: the two solvers disagree (above)" >> "$diag"; status=1; }
  for solver in newton fixedpoint; do
    mean=$(awk '$1 == "iterations_total" { t = $2 } $1 == "steps" { s = $2 } END { printf "%.1f", t / s }' "$work/heldout-$name-$solver/summary.txt")
    cap=$([ "$solver" = newton ] && echo 10 || echo 100)
    awk -v m="$mean" -v c="$cap" 'BEGIN { exit !(m > 0 && m <= c) }' || { echo "$name ($solver): $mean iterations a step (at most $cap expected)" >> "$diag"; status=1; }
  done
done <<POINTS
concave-arc|-scene $work/arc.scene -mesh $work/arc.msh -T 0.5
r5e-4-40x20|-scene paper -nx 40 -ny 20 -r 5e-4 -T 0.6
r2e3-mu1.2-load30|-scene paper -nx 40 -ny 20 -r 2e3 -mu 1.2 -load 30 -dt 0.025 -T 0.5
cylinder-dt0.02|-scene cylinder -dt 0.02 -T 0.4
unloading-mu0.8|-scene unloading -mu 0.8 -nx 32 -ny 16
power-penalty|-scene power-damping -problem penalty -eps 1e-9 -nx 40 -ny 20 -T 0.5
bound-profile-k0.05|-scene bound-profile -dt 0.05 -nx 50 -ny 25
column-mu0.7|-scene column -mu 0.7 -load 12
POINTS
for solver in newton fixedpoint; do
  rc=0; solve -scene paper -nx 40 -ny 20 -T 0.1 -solver "$solver" -maxit 1 -out "$work/heldout-cap-$solver" > "$work/heldout.log" 2>&1 || rc=$?
  [ "$rc" = 4 ] && [ ! -e "$work/heldout-cap-$solver" ] && grep -Eq "^error: step 1 \(t = 0.01\): the contact solver did not converge after 1 iterations \(iteration cap reached\), residual [0-9.e+-]+ > tol 1e-10; no results written" "$work/heldout.log" \
    || { echo "-maxit 1 ($solver): exit $rc" >> "$diag"; cat "$work/heldout.log" >> "$diag"; status=1; }
done
report $status "held-out points (other scenes, a concave contact arc, r 5e-4 and 2e3, meshes, time steps): Newton and the fixed point converge and agree to 1e-8; a cap they cannot meet fails loudly (exit 4, step, iterations, residual)" "$diag"

# ---- what a loose tolerance, a stalled fixed point and a large eps do
diag="$work/loose.diag"; : > "$diag"; status=0
# -tol 1e-4: the residual alone would stop the fixed point with sticking nodes still slipping
# (zones 15/49/2); a step also waits for the statuses, so the zones are Newton's
solve -scene paper -solver fixedpoint -tol 1e-4 -out "$work/loose-fixedpoint" > "$diag" 2>&1 || status=1
"$PYTHON" tests/check_results.py "$work/loose-fixedpoint" --zones 1,15,0,29,22 --rtol 1e-3 >> "$diag" 2>&1 || status=1   # 10 tol, as the run's own checks
# a steep damping table where the sweeps settle away from a solution: exit 4 at once, saying so
grep -v -E '^(cnu|damping) ' edp/scenes/paper.scene > "$work/steep.scene"; echo "damping table 0 0 0.01 0 0.02 5 0.05 5 0.06 1000" >> "$work/steep.scene"
rc=0; solve -scene "$work/steep.scene" -T 0.5 -solver fixedpoint -out "$work/steep" > "$work/steep.log" 2>&1 || rc=$?
[ "$rc" = 4 ] && [ ! -e "$work/steep" ] && grep -Eq "^error: step 1 \(t = 0.01\): the contact solver did not converge after [0-9]+ iterations \(the fixed point stalled: .*\), residual [0-9.e+-]+ > tol 1e-10; no results written" "$work/steep.log" \
  && [ "$(sed -n 's/.*after \([0-9]*\) iterations.*/\1/p' "$work/steep.log")" -lt 500 ] \
  || { echo "steep table, fixed point: exit $rc" >> "$diag"; cat "$work/steep.log" >> "$diag"; status=1; }
solve -scene "$work/steep.scene" -T 0.5 -out "$work/steep-newton" >> "$diag" 2>&1 && "$PYTHON" tests/check_results.py "$work/steep-newton" >> "$diag" 2>&1 \
  || { echo "steep table, Newton: did not converge" >> "$diag"; status=1; }
# a large penalty eps: eps times the round-off of lambda_nu is no violation of the penalty law
solve -scene paper -nx 16 -ny 8 -T 0.2 -problem penalty -eps 1e6 -out "$work/eps1e6" >> "$diag" 2>&1 \
  && "$PYTHON" tests/check_results.py "$work/eps1e6" >> "$diag" 2>&1 || { echo "-eps 1e6 failed" >> "$diag"; status=1; }
report $status "fixed point at -tol 1e-4: the paper's zones (statuses settled); a stalled fixed point stops at once with exit 4 and says so (Newton converges there); -eps 1e6 passes the penalty check" "$diag"

# ---- the compiled kernel (edp/plugins/contactkernel.cpp): its linear algebra against
# FreeFEM's UMFPACK, and its Newton against the script Newton of edp/lib/contact.idp
diag="$work/kernel.diag"; : > "$diag"
if "${FREEFEM[@]}" tests/kernel_check.edp > "$diag" 2>&1 && grep -q "kernel_check: all checks passed" "$diag"; then
  report 0 "kernel: solve, Delassus matrix, both halves of the back-substitution = UMFPACK, products and the record of a step = FreeFEM, to 1e-12"
else
  report 1 "kernel: solve, Delassus matrix, both halves of the back-substitution = UMFPACK, products and the record of a step = FreeFEM, to 1e-12" "$diag"
fi
# calls in a wrong order stop with the kernel's message (FreeFEM's exit code 8 for an
# execution error), never with a crash or stale data
while IFS='|' read -r misuse expected; do
  diag="$work/kernel-misuse-$misuse.diag"; : > "$diag"; status=0
  "${FREEFEM[@]}" tests/kernel_check.edp -misuse "$misuse" > "$diag" 2>&1 || status=$?
  if [ "$status" = 8 ] && grep -q "$expected" "$diag"; then
    report 0 "kernel misuse $misuse refused: $expected"
  else
    echo "exit code $status, expected 8 and '$expected'" >> "$diag"
    report 1 "kernel misuse $misuse refused: $expected" "$diag"
  fi
done <<'CASES'
1|contactKernelSolve without a successful contactKernelFactorize
2|contactKernelNewton: call contactKernelDelassus after the last contactKernelFactorize
3|contactKernelFactorize: C has 32 rows, but contactKernelNodes gave 34 slots
4|contactKernelNodes: slot numbers must be 0 .. slots-1, each used once
5|contactKernelRecord: call contactKernelRecordStart
6|contactKernelParameter: unknown parameter 'gravity'
CASES
for problem in original penalty; do
  diag="$work/script-$problem.diag"; : > "$diag"; status=0
  if solve -scene paper -problem "$problem" -kernel script -out "$work/script-$problem" > "$diag" 2>&1 \
     && "$PYTHON" tests/check_results.py "$work/script-$problem" --compare "$work/paper-$problem" --rtol 1e-9 >> "$diag" 2>&1; then
    for key in iterations_total iterations_max newton_fallbacks fixed_point_sweeps; do
      a=$(grep "^$key " "$work/script-$problem/summary.txt"); b=$(grep "^$key " "$work/paper-$problem/summary.txt")
      [ -n "$a" ] && [ "$a" = "$b" ] || { echo "script: '$a', compiled: '$b'" >> "$diag"; status=1; }
    done
  else
    status=1
  fi
  report $status "compiled Newton = script Newton: same iterations and fixed-point fallbacks, values to 1e-9 ($problem)" "$diag"
done
# ---- the law is defined once (edp/plugins/contactlaw.hpp): a different damped response,
# p(r) = c_nu r_+^2 written in its linear case in a copy of the suite (the walkthrough's
# exercise 1), gives the same new results with the default compiled Newton and its script
# view, the same as the scene key damping power 1000 2 with the suite as it is, the outputs
# follow the new law, and they differ from the paper law's
diag="$work/otherlaw.diag"; : > "$diag"; status=0
other="$work/otherlaw"
rm -rf "$other" && mkdir -p "$other/meshes" && cp -r edp run.sh freefem++.pref "$other/" && cp meshes/*.geo "$other/meshes/"
rm -rf "$other/edp/plugins/build"
law="$other/edp/plugins/contactlaw.hpp"
sed -i -e 's|^  return P.cnu \* r; *// Linear$|  return P.cnu * r * r;   // Linear|' \
       -e 's|^  return P.cnu; *// Linear$|  return 2 * P.cnu * r;   // Linear|' "$law"
[ "$(diff edp/plugins/contactlaw.hpp "$law" | grep -c '^>')" = 2 ] \
  || { echo "could not write the quadratic law into $law (the linear case of dampedResponse, dampedResponseSlope)" >> "$diag"; status=1; }
otherlaw_options=(-nx 16 -ny 8 -dt 0.05 -cnu 1000)
for kernel in compiled script; do   # from the copy's folder: its freefem++.pref loads its own kernel
  (cd "$other" && bash run.sh solve "${otherlaw_options[@]}" -kernel "$kernel" -out "$root/$work/otherlaw-$kernel") >> "$diag" 2>&1 || status=1
done
solve "${otherlaw_options[@]}" -out "$work/otherlaw-paper" >> "$diag" 2>&1 || status=1
grep -v -e '^damping' -e '^cnu ' edp/scenes/paper.scene > "$work/otherlaw.scene"; echo "damping power 1000 2" >> "$work/otherlaw.scene"
solve -scene "$work/otherlaw.scene" "${otherlaw_options[@]}" -out "$work/otherlaw-scene" >> "$diag" 2>&1 || status=1
"$PYTHON" tests/check_results.py "$work/otherlaw-script" --compare "$work/otherlaw-compiled" --other-law --rtol 1e-9 >> "$diag" 2>&1 \
  || { echo "the script view differs from the compiled Newton, or a law-independent check failed" >> "$diag"; status=1; }
"$PYTHON" tests/check_results.py "$work/otherlaw-scene" --compare "$work/otherlaw-compiled" --rtol 1e-9 >> "$diag" 2>&1 \
  || { echo "the scene key damping power 1000 2 differs from the edited law" >> "$diag"; status=1; }
# p_nu - lambda_nu = 1000 (v_nu)_+^2 on every node, and not the paper's 1000 (v_nu)_+
awk '!/^#/ { vn = $2 > 0 ? $2 : 0; d = $4 - $5 - 1000 * vn * vn; if (d < 0) d = -d; if (d > 1e-9) bad++; n++ }
     END { if (!n || bad) { print "contact.txt does not follow p = 1000 (v_nu)_+^2 on " bad + 0 " of " n " nodes"; exit 1 } }' \
  "$work/otherlaw-compiled/contact.txt" >> "$diag" || status=1
"$PYTHON" tests/check_results.py "$work/otherlaw-compiled" --compare "$work/otherlaw-paper" --other-law --rtol 1e-6 > /dev/null 2>&1 \
  && { echo "the quadratic law gives the paper law's results" >> "$diag"; status=1; }
report $status "a law changed only in edp/plugins/contactlaw.hpp (p = c r^2): compiled = script Newton = damping power 1000 2 to 1e-9, outputs follow it" "$diag"
# a law the solvers cannot use is refused when the run starts (exit 3, no output): p' that
# does not match p (exercise 1 with the slope forgotten), a zone function out of 0..4
law_refused() { # law_refused NAME OLD NEW REGEX: the copy's law with OLD replaced by NEW
  local name="$1" old="$2" new="$3" regex="$4" diag="$work/otherlaw-$1.diag" status=0 rc=0
  cp edp/plugins/contactlaw.hpp "$law"
  OLD="$old" NEW="$new" "$PYTHON" -c 'import os, sys; p = sys.argv[1]; s = open(p).read(); o, n = os.environ["OLD"], os.environ["NEW"]
assert o in s, "not found: " + o; open(p, "w").write(s.replace(o, n))' "$law" > "$diag" 2>&1 || status=1
  (cd "$other" && bash run.sh solve "${otherlaw_options[@]}" -out "$root/$work/otherlaw-$name") >> "$diag" 2>&1 || rc=$?
  [ "$rc" = 3 ] || { echo "exit code $rc, expected 3" >> "$diag"; status=1; }
  grep -Eq "$regex" "$diag" || { echo "message does not match /$regex/" >> "$diag"; status=1; }
  [ -e "$work/otherlaw-$name" ] && { echo "results were written" >> "$diag"; status=1; }
  report $status "refused: a law with $name in edp/plugins/contactlaw.hpp" "$diag"
}
law_refused "a slope that does not match p" "  return P.cnu * r;   " "  return P.cnu * r * r;   " \
  "the law of edp/plugins/contactlaw.hpp cannot be used: p'.* but the difference quotient of p there is"
law_refused "a zone out of 0..4" "return normal > 0 ? 2 * normal - tangential : 0;" "return normal > 0 ? 2 * normal + tangential : 0;" \
  "cannot be used: zone\(2, 1\) is not a zone 0..4"
law_refused "a negative friction bound" "{ return P.mu * dampedResponse(P, vn); }" "{ return -P.mu * dampedResponse(P, vn); }" \
  "cannot be used: the friction bound is not finite and >= 0"
diag="$work/umfpackfloor.diag"; : > "$diag"; status=0
if solve "${coarse_options[@]}" -umfpackfloor on -out "$work/umfpackfloor" > "$diag" 2>&1; then
  for key in time_backsubstitution time_backsubstitution_umfpack time_factorization_umfpack; do
    awk -v k="$key" '$1 == k && $2 > 0 { found = 1 } END { exit !found }' "$work/umfpackfloor/summary.txt" \
      || { echo "no positive $key in summary.txt" >> "$diag"; status=1; }
  done
else
  status=1
fi
report $status "-umfpackfloor on: summary.txt has both floors (kernel and UMFPACK)" "$diag"

# ---- the safeguards (line search, augmentation halving) do not change the discrete
# solution: the fine paper case again with another augmentation
diag="$work/augmentation.diag"; : > "$diag"
if solve -scene paper -nx 132 -ny 66 -r 0.3 -out "$work/fine-r0.3" > "$diag" 2>&1 \
   && "$PYTHON" tests/check_results.py "$work/fine-r0.3" --compare "$work/paper-fine-original" --rtol 1e-9 >> "$diag" 2>&1; then
  report 0 "the solution does not depend on the augmentation r (1 vs 0.3, 132x66)"
else
  report 1 "the solution does not depend on the augmentation r (1 vs 0.3, 132x66)" "$diag"
fi

# ---- the main job (./run.sh): every table and figure, the paper's zones, the eps rate
diag="$work/main.diag"; : > "$diag"; status=0
rm -rf "$work/main"
if RESULTS_DIR="$work/main" bash run.sh > "$diag" 2>&1; then
  "$PYTHON" - "$work/main" >> "$diag" 2>&1 <<'PY' || status=1
import os, sys
import numpy as np
results = sys.argv[1]
failures = []
for name in ("fig2_deformed", "fig3_contact_reactions", "fig4_velocities", "fig5_penalty_convergence",
             "contact_forces_history", "energy_history", "zone_boundaries"):
    path = os.path.join(results, "figures", name + ".png")
    if not (os.path.isfile(path) and os.path.getsize(path) > 10000):
        failures.append(f"missing or empty figure {path}")
rows = [l.split() for l in open(os.path.join(results, "zones.txt")) if not l.startswith("#")]
zones = {r[0]: r for r in rows}
for run in ("paper-original", "paper-penalty", "choices/original-dt0.001", "choices/original-right-diagonal"):
    if run not in zones or (zones[run][6], zones[run][7]) != ("15", "29"):
        failures.append(f"zones.txt: {run} does not give AB/BC = 15/29: {zones.get(run)}")
header = [l for l in open(os.path.join(results, "eps-study", "eps_study.txt")) if l.startswith("# slope_tail")]
slope = float(header[0].split()[2]) if header else float("nan")
if not 0.95 <= slope <= 1.05:
    failures.append(f"eps_study.txt: tail slope {slope} outside [0.95, 1.05]")
print("\n".join(failures))
sys.exit(1 if failures else 0)
PY
else
  status=1
fi
report $status "./run.sh main job: tables, figures, zones 15/29, eps slope in [0.95, 1.05]" "$diag"

# ---- stability: the reduced sweep, the safeguarded penalty at tiny eps, and
# the defaults on the corners of the paper's parameter box
diag="$work/stability.diag"; : > "$diag"; status=0
rm -rf "$work/stability"
if RESULTS_DIR="$work" bash tests/stability.sh --quick > "$diag" 2>&1; then
  line=$(grep -o 'agreement [0-9]*/[0-9]* pairs.*hopeless settings failing loudly [0-9]*/[0-9]*' "$diag" | tail -1)
  agree=$(echo "$line" | sed -n 's/agreement \([0-9]*\)\/\([0-9]*\) pairs.*/\1 \2/p')
  loud=$(echo "$line" | sed -n 's/.*failing loudly \([0-9]*\)\/\([0-9]*\)/\1 \2/p')
  set -- $agree; [ -n "${1:-}" ] && [ "$1" = "$2" ] || { echo "agreement between methods: ${agree:-missing}" >> "$diag"; status=1; }
  set -- $loud; [ -n "${1:-}" ] && [ "$1" = "$2" ] || { echo "hopeless settings failing loudly: ${loud:-missing}" >> "$diag"; status=1; }
  for map in eps_method r_method k_mu paper_box fixedpoint_mesh_k; do
    [ -s "$work/stability/maps/stability_$map.png" ] || { echo "missing map stability_$map.png" >> "$diag"; status=1; }
  done
  for key in default_failures fixedpoint_default_failures; do
    [ "$(awk -v k="$key" '$1 == k { print $2 }' "$work/stability/summary.txt")" = 0 ] || { echo "$key is not 0" >> "$diag"; status=1; }
  done
else
  status=1
fi
report $status "./run.sh stability --quick: methods agree, both solvers' defaults converge in the box, hopeless settings fail loudly, maps drawn" "$diag"

diag="$work/tiny-eps.diag"; : > "$diag"
if solve -problem penalty -eps 1e-10 -out "$work/tiny-eps" > "$diag" 2>&1 \
   && "$PYTHON" tests/check_results.py "$work/tiny-eps" --zones 1,15,0,29,22 >> "$diag" 2>&1; then
  report 0 "the compliant penalty converges at eps = 1e-10 (paper scene, physics checks, zones 15/29)"
else
  report 1 "the compliant penalty converges at eps = 1e-10 (paper scene, physics checks, zones 15/29)" "$diag"
fi

diag="$work/box.diag"; : > "$diag"; status=0
for problem in original penalty; do
  for mu in 0 1.5; do
    for load in 1 100; do
      for k in "0.2 -T 1" "1e-4 -T 0.01"; do
        # shellcheck disable=SC2086
        if ! solve -nx 33 -ny 16 -problem "$problem" -mu "$mu" -load "$load" -dt $k -out "$work/box" >> "$diag" 2>&1 \
           || ! "$PYTHON" tests/check_results.py "$work/box" >> "$diag" 2>&1; then
          echo "failed: -nx 33 -ny 16 -problem $problem -mu $mu -load $load -dt $k" >> "$diag"; status=1
        fi
      done
    done
  done
done
report $status "the defaults converge on the 16 corners of the paper box (mu 0, 1.5; load 1, 100; k 0.2 to T = 1, 1e-4 to T = 0.01)" "$diag"

# ---- every repository path, link and section cited in README.md, docs/ and code comments exists
diag="$work/references.diag"
"$PYTHON" tests/check_references.py > "$diag" 2>&1; report $? "no dangling reference in README.md, docs/ and comments; none to files outside the repository or to issue numbers" "$diag"

# ---- runs that must fail: exit code, message, and no results
# expect_failure NAME CODE REGEX OPTIONS...
expect_failure() {
  local name="$1" code="$2" regex="$3"; shift 3
  local out="$work/fail-$count" diag="$work/fail.diag"
  rm -rf "$out"
  if printf '%s\n' "$@" | grep -qx -- -out; then solve "$@" > "$diag" 2>&1; else solve -out "$out" "$@" > "$diag" 2>&1; fi
  local rc=$?
  local status=0
  if [ "$rc" != "$code" ]; then echo "exit code $rc, expected $code" >> "$diag"; status=1; fi
  if ! grep -Eq "$regex" "$diag"; then echo "message does not match /$regex/" >> "$diag"; status=1; fi
  if [ -e "$out" ] || compgen -G "$out.partial*" > /dev/null; then echo "results were written in $out" >> "$diag"; status=1; fi
  report $status "refused: $name" "$diag"
}
coarse=(-nx 8 -ny 4 -dt 0.1)
expect_failure "unknown option" 2 "unknown option '-foo'" -foo 1
expect_failure "not an option" 2 "expected an option -name, got '12'" 12
expect_failure "option without value" 2 "option -dt needs a value" -dt
expect_failure "repeated option" 2 "option -nx is given twice" -nx 8 -nx 9
expect_failure "real not a number" 2 "option -dt must be a real number, got 'abc'" -dt abc
expect_failure "real half a number" 2 "option -E must be a real number, got '1e'" -E 1e
expect_failure "a 3D mesh for a 2D scene" 3 "option -mesh: 'tests/data/tetrahedron.msh' is a 3D mesh, but the scene .*paper.scene is 2D \\(geometry rectangle, vectors of two components" -mesh tests/data/tetrahedron.msh
expect_failure "a 2D mesh for a 3D scene" 3 "option -mesh: '.*mesh.msh' is a 2D mesh \\(it has no tetrahedra: a 3D mesh needs a Physical Volume.*the scene .*column3d.scene is 3D" -scene column3d -mesh "$work/paper-coarse-original/mesh.msh"
"$PYTHON" tests/bad_meshes3d.py "$work/column3d/mesh.msh" "$work/bad-meshes3d" > /dev/null 2>&1
expect_failure "a folded 3D mesh" 3 "lie on the same side of their common face: the mesh is folded, tangled or overlapping" -scene column3d -mesh "$work/bad-meshes3d/fold.msh"
expect_failure "two 3D nodes at one point" 3 "are at the same point \\(0, 0, 0\\): a crack or duplicated nodes" -scene column3d -mesh "$work/bad-meshes3d/coincident.msh"
expect_failure "a cached mesh without the scene's Dirichlet label" 3 "the scene's dirichlet label 7 is not a physical surface of the mesh" -scene tests/data/column3d-label7.scene
expect_failure "-nz with -mesh" 2 "options -nx, -ny and -nz size the scene's structured mesh; they do not apply with -mesh" -scene column3d -mesh "$work/column3d/mesh.msh" -nz 3
expect_failure "a 3D mesh without the scene's labels" 3 "'tests/data/tetrahedron.msh': the scene's dirichlet label 5 is not a physical surface of the mesh" -scene column3d -mesh tests/data/tetrahedron.msh
expect_failure "a z value in a scene of a 2D geometry" 3 "traction with a z component: a z value, but geometry rectangle is 2D" -scene tests/data/z-in-2d.scene
expect_failure "-plane for a 3D body" 2 "option -plane: plane stress or strain is a 2D model; geometry box is a 3D body" -scene column3d -plane strain
expect_failure "-nz for a 2D body" 2 "option -nz: cells along z, for a 3D body; geometry rectangle is 2D" -nz 3
expect_failure "-adapt for a 3D body" 2 "option -adapt: mesh adaptation is 2D only" -scene column3d -adapt 1
expect_failure "-Ddimension=3 with a 2D scene" 3 "geometry rectangle is 2D, but the run was started with -Ddimension=3" -Ddimension=3
expect_failure "a choice out of its list" 2 "option -plane = 'Strain' is not one of stress\|strain" -plane Strain
expect_failure "real overflows" 2 "option -load = 1e999 is not a finite number" -load 1e999
expect_failure "integer not whole" 2 "option -nx must be a whole number, got '1.5'" -nx 1.5
expect_failure "integer too large" 2 "option -ny = 5000 is out of range: it must be <= 4096" -ny 5000
expect_failure "nx < 1" 2 "option -nx = 0 is out of range: it must be >= 1" -nx 0
expect_failure "T <= 0" 2 "option -T = -1 is out of range: it must be > 0" -T -1
expect_failure "dt <= 0" 2 "option -dt = 0 is out of range: it must be > 0" -dt 0
expect_failure "dt > T" 2 "option -dt = 2 is out of range: it must be <= T = 1" -dt 2
expect_failure "T/dt not whole" 2 "option -dt = 0.3 does not divide T = 1" -dt 0.3
expect_failure "too many steps" 2 "ask for more than 1e6 steps" -dt 1e-7
expect_failure "empty value" 2 "option -mu has an empty value" -mu ''
expect_failure "an option as a value" 2 "option -nx needs a value, got the option '-ny'" -nx -ny 3
# control characters and line separators break readers of the outputs (summary.txt echoes the values)
separator="holds a control character or a line separator"
expect_failure "a vertical tab in -mesh" 2 "option -mesh $separator" -mesh $'a\vb.msh'
expect_failure "a form feed in -scene" 2 "option -scene $separator" -scene $'paper\f'
expect_failure "a record separator (0x1e) in -out" 2 "option -out $separator" -out "$work/a"$'\x1e'b
expect_failure "U+0085 (next line) in -mesh" 2 "option -mesh $separator" -mesh $'a\xc2\x85b.msh'
expect_failure "U+2028 (line separator) in -out" 2 "option -out $separator" -out "$work/a"$'\xe2\x80\xa8'b
grep -v '^#' edp/scenes/column.scene > "$work/separator.scene"; printf 'body_force 0 a\034b\n' >> "$work/separator.scene"
expect_failure "a file separator (0x1c) in a scene's value" 3 "separator.scene:[0-9]+: body_force: value 2 $separator" -scene "$work/separator.scene"
status=0
printf 'a\034b\342\200\250c\n# d\302\205e\f\n' > "$work/separators.txt"
"$PYTHON" -c 'import suite, sys; lines = suite.read_lines(sys.argv[1]); assert lines == ["a\x1cb\u2028c", "# d\x85e\f"], lines' \
  "$work/separators.txt" > "$work/separators.diag" 2>&1 || status=1
report $status "plots/suite.py reads lines split at line feeds only, not at form feeds, 0x1c or U+2028" "$work/separators.diag"
expect_failure "a scene name with a quote and a semicolon" 2 "option -scene = 'x'y; ls': no readable scene file" -scene "x'y; ls"
expect_failure "tol below round-off" 2 "option -tol = 1e-15 is out of range: it must be >= 1e-13" -tol 1e-15
expect_failure "output named ." 2 "option -out = '.' is not a usable folder name" -out .
mkdir -p "$work/userfolder" && touch "$work/userfolder/thesis.tex"
expect_failure "output folder of the user" 7 "does not hold results of this suite" -out "$work/userfolder"
status=0; [ -f "$work/userfolder/thesis.tex" ] || status=1
report $status "a folder of the user's given as -out is left as it was"
printf '$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n' > "$work/truncated.msh"
expect_failure "truncated mesh file" 3 "declares 3 nodes but holds|truncated file" -mesh "$work/truncated.msh"
expect_failure "rho <= 0" 2 "option -rho = 0 is out of range: it must be > 0" -rho 0
expect_failure "E <= 0" 2 "option -E = -100 is out of range: it must be > 0" -E -100
expect_failure "nu >= 0.5" 2 "option -nu = 0.5 is out of range: it must be < 0.5" -nu 0.5
expect_failure "nu < 0" 2 "option -nu = -0.1 is out of range: it must be >= 0" -nu -0.1
expect_failure "muv < 0" 2 "option -muv = -1 is out of range: it must be >= 0" -muv -1
expect_failure "eta < 0" 2 "option -eta = -0.5 is out of range: it must be >= 0" -eta -0.5
expect_failure "cnu < 0" 2 "option -cnu = -50 is out of range: it must be >= 0" -cnu -50
expect_failure "g <= 0" 2 "option -g = 0 is out of range: it must be > 0" -g 0
expect_failure "mu < 0" 2 "option -mu = -0.4 is out of range: it must be >= 0" -mu -0.4
expect_failure "eps <= 0" 2 "option -eps = 0 is out of range: it must be > 0" -eps 0
expect_failure "tol <= 0" 2 "option -tol = -1e-10 is out of range: it must be >= 1e-13" -tol -1e-10
expect_failure "tol too large for the checks" 2 "option -tol = 1 is out of range: it must be <= 1e-4" -tol 1
expect_failure "maxit < 1" 2 "option -maxit = 0 is out of range: it must be >= 1" -maxit 0
expect_failure "r <= 0" 2 "option -r = 0 is out of range: it must be >= 1e-8" -r 0
expect_failure "r above 1e8" 2 "option -r = 1e12 is out of range: it must be <= 1e8" -r 1e12
expect_failure "unknown problem" 2 "option -problem = 'dual' is not one of original\|penalty" -problem dual
expect_failure "unknown solver" 2 "option -solver = 'cg' is not one of newton.fixedpoint.full" -solver cg
expect_failure "unknown safeguard" 2 "option -safeguard = 'maybe' is not one of on.off" -safeguard maybe
expect_failure "unknown kernel" 2 "option -kernel = 'gpu' is not one of compiled.script" -kernel gpu
expect_failure "script kernel with another solver" 2 "option -kernel script applies to -solver newton only" -kernel script -solver full
expect_failure "unknown umfpackfloor" 2 "option -umfpackfloor = 'yes' is not one of on.off" -umfpackfloor yes
expect_failure "unknown penalty form" 2 "option -penaltyform = 'soft' is not one of compliant.literal" -penaltyform soft
expect_failure "unknown scene" 2 "option -scene = 'moon'" -scene moon
expect_failure "scene file with a bad line" 3 "cannot read 'gravity 9.81'" -scene tests/data/bad.scene
grep -v '^nx ' edp/scenes/column.scene > "$work/nx0.scene"; echo "nx 0" >> "$work/nx0.scene"
expect_failure "an option out of range in a scene file" 3 "nx0.scene:[0-9]+: option -nx = 0 is out of range: it must be >= 1 \(a value of the scene file\)" -scene "$work/nx0.scene"
# the option table edp/options.txt is checked when it is read: a copy of edp/ with one line changed
table_refused() { # table_refused NAME OLD NEW REGEX
  local name="$1" old="$2" new="$3" regex="$4" diag="$work/table.diag" status=0 rc=0 copy="$work/table"
  rm -rf "$copy" "$work/table-out" && mkdir -p "$copy/meshes" && cp -r edp "$copy/" && cp meshes/*.geo "$copy/meshes/" && rm -rf "$copy/edp/plugins/build"
  OLD="$old" NEW="$new" "$PYTHON" -c 'import os, sys; p = sys.argv[1]; s = open(p).read(); o, n = os.environ["OLD"], os.environ["NEW"]
assert o in s, "not found: " + o; open(p, "w").write(s.replace(o, n, 1))' "$copy/edp/options.txt" > "$diag" 2>&1 || status=1
  "${FREEFEM[@]}" "$copy/edp/solve.edp" -out "$work/table-out" >> "$diag" 2>&1 || rc=$?
  [ "$rc" = 3 ] || { echo "exit code $rc, expected 3" >> "$diag"; status=1; }
  grep -Eq "$regex" "$diag" || { echo "message does not match /$regex/" >> "$diag"; status=1; }
  { [ -e "$work/table-out" ] || ls -d "$work"/table-out.partial* > /dev/null 2>&1; } && { echo "results were written" >> "$diag"; status=1; }
  report $status "refused: an option table with $name" "$diag"
}
table_refused "a missing option" "tol           real" "tolerance     real" "options.txt has no option -tol, which the scripts need"
table_refused "a malformed range" "nx            int     >=1,<=4096" "nx            int     >=1," "options.txt:[0-9]+: the range of -nx must read"
table_refused "an unknown type" "problem       choice" "problem       choise" "options.txt:[0-9]+: type 'choise' of -problem is not one of"
table_refused "a rule on an unknown option" "when solver=fixedpoint maxit 500" "when solvr=fixedpoint maxit 500" "options.txt:[0-9]+: the rule names an option that is not in the table"
table_refused "a default out of its range" ">=1e-13,<=1e-4      1e-10" ">=1e-13,<=1e-4      1e-20" "options.txt:[0-9]+: the default of -tol"
expect_failure "missing mesh file" 3 "cannot read the file" -mesh "$work/no-such.msh"
printf '$MeshFormat\n4.1 0 8\n$EndMeshFormat\n' > "$work/v41.msh"
expect_failure "MSH 4.1 mesh" 3 "gmsh format 4.1, not 2.2: re-export it with: gmsh -2 -format msh22" -mesh "$work/v41.msh"
printf 'hello\n' > "$work/text.msh"
expect_failure "not a mesh file" 3 "not a gmsh mesh file" -mesh "$work/text.msh"
mesh_of() { gmsh -2 -format msh22 -v 0 -setnumber nx 4 -setnumber ny 2 "tests/data/$1.geo" -o "$work/$1.msh" > /dev/null 2>&1; }
mesh_of unlabelled
expect_failure "mesh without physical curves" 3 "no boundary line with physical tag 1 3 \(Physical Curve 1 contact, 3 traction are required\)" -mesh "$work/unlabelled.msh"
mesh_of flipped
expect_failure "contact boundary on the wrong side" 3 "the scene expects the outward normal \(0, -1\)" -mesh "$work/flipped.msh"
expect_failure "mesh without triangles" 3 "no triangle" -mesh tests/data/no-triangle.msh
expect_failure "zero-area triangle" 3 "has zero area" -mesh tests/data/zero-area.msh
expect_failure "output is a file" 7 "exists and is not a folder" -out tests/cases.txt
expect_failure "output not writable" 7 "cannot create the output folder" -out /proc/no-such-folder
expect_failure "literal penalty at eps = 1e-10 without safeguards" 4 "the contact solver did not converge after .* iterations" -problem penalty -eps 1e-10 -penaltyform literal -safeguard off -nx 33 -ny 16
expect_failure "no convergence (maxit 1)" 4 "step 1 \(t = .*\): the contact solver did not converge after 1 iterations .*residual" "${coarse[@]}" -maxit 1

# ---- scenes (docs/design.md, "Scenes"): every new law on the three Newtons, a run that
# repeats itself from its own folder, the mesh cache, oblique and curved boundaries, bad keys
# compiled = script Newton = full-system Newton to 1e-9, for each scene key: the column cases
# (small already) and the paper-sized scenes on a coarse mesh
scene_agreement() { # scene_agreement NAME OPTIONS...: compiled (tests/work/NAME) against the others
  local name="$1" diag="$work/agree-$1.diag" status=0 variant; shift
  : > "$diag"
  [ -f "$work/$name/summary.txt" ] || solve "$@" -out "$work/$name" >> "$diag" 2>&1 || status=1
  for variant in "-kernel script" "-solver full"; do
    # shellcheck disable=SC2086
    solve "$@" $variant -out "$work/$name-${variant##* }" >> "$diag" 2>&1 || status=1
    "$PYTHON" tests/check_results.py "$work/$name-${variant##* }" --compare "$work/$name" --rtol 1e-9 >> "$diag" 2>&1 || status=1
  done
  report $status "scene $name: compiled Newton = script Newton = full-system Newton to 1e-9" "$diag"
}
# shellcheck disable=SC2086
for name in column-power column-table column-profile-bound column-history-pulled column-body; do scene_agreement "$name" ${case_options[$name]}; done
scene_agreement unloading-coarse -scene unloading -nx 16 -ny 8 -dt 0.05
scene_agreement power-damping-coarse -scene power-damping -nx 16 -ny 8 -dt 0.05
scene_agreement bound-profile-coarse -scene bound-profile -nx 16 -ny 8 -dt 0.05
scene_agreement cylinder-coarse -scene cylinder -nx 12 -dt 0.05

# ---- the PETSc route, a prototype (docs/performance.md, "Three dimensions"): S of a 3D step,
# exported by the macro -DexportSystem, factorized and solved by MUMPS through petsc4py on 2
# ranks, equals the kernel's solve (and x_true) to 1e-9
diag="$work/petsc.diag"; : > "$diag"; status=0
mkdir -p "$work/petsc-system"
solve -scene slab3d -nx 8 -ny 4 -nz 4 -T 0.01 -quiet "-DexportSystem=\"$work/petsc-system\"" -out "$work/petsc-run" >> "$diag" 2>&1 || status=1
mpirun --allow-run-as-root --oversubscribe -np 2 "$PYTHON" tests/petsc_step.py "$work/petsc-system" >> "$diag" 2>&1 || status=1
grep -q "2 rank(s)" "$diag" || { echo "no line from the two ranks" >> "$diag"; status=1; }
report $status "PETSc route (prototype): a 3D step's S solved by MUMPS on 2 ranks = the kernel's solve to 1e-9" "$diag"

# ---- 3D (docs/design.md, "Three dimensions"): the disk law on the three Newtons and the
# fixed point, the slab against the 2D plane-strain solution, a 3D run that repeats itself
scene_agreement slide3d -scene oblique-slide3d
scene_agreement slab3d-coarse -scene slab3d -nx 8 -ny 4 -nz 1 -T 0.2
diag="$work/fixedpoint3d.diag"; : > "$diag"; status=0
for name in slide3d slab3d-coarse; do
  opts=(-scene oblique-slide3d); [ "$name" = slab3d-coarse ] && opts=(-scene slab3d -nx 8 -ny 4 -nz 1 -T 0.2)
  solve "${opts[@]}" -solver fixedpoint -out "$work/$name-fixedpoint" >> "$diag" 2>&1 \
    && "$PYTHON" tests/check_results.py "$work/$name-fixedpoint" --compare "$work/$name" --rtol 1e-8 >> "$diag" 2>&1 || status=1
done
report $status "3D: the fixed point = Newton to 1e-8 (oblique-slide3d, slab3d coarse: the disk's pair update)" "$diag"
# The slab between walls (u_z = 0 on z = 0 and z = Lz) is the plane-strain problem: at T, x_B
# equal and x_C within one mesh spacing of the 2D solution's, and the normal force per depth
# closer to it on the finer mesh (measured: 2.2e-4 then 1.2e-4 relative, 16x8 then 32x16)
diag="$work/slab3d-strain.diag"; : > "$diag"; status=0
previous=1
for n in 16 32; do
  solve -scene slab3d -nx "$n" -ny $((n / 2)) -nz 2 -quiet -out "$work/slab3d-$n" >> "$diag" 2>&1 || status=1
  solve -scene paper -plane strain -nx "$n" -ny $((n / 2)) -quiet -out "$work/slab2d-$n" >> "$diag" 2>&1 || status=1
  verdict=$(awk -v h="$(awk -v n="$n" 'BEGIN { print 2 / n }')" -v previous="$previous" '
    FNR == 1 { file++ } /^#/ { next } { last[file] = $0 }
    END { split(last[1], a); split(last[2], b)
          lz = 0.25; d = a[3] / lz - b[3]; if (d < 0) d = -d; rel = d / b[3]
          xc = a[11] - b[11]; if (xc < 0) xc = -xc
          ok = a[10] == b[10] && xc <= h * 1.000001 && rel < previous
          printf "%s %.3e x_B %s %s x_C %s %s normal force per depth %.9g against %.9g\n", ok ? "ok" : "FAIL", rel, a[10], b[10], a[11], b[11], a[3] / lz, b[3] }' \
    "$work/slab3d-$n/contact_history.txt" "$work/slab2d-$n/contact_history.txt")
  echo "${n}x$((n / 2)): $verdict" >> "$diag"
  case "$verdict" in ok*) previous=$(echo "$verdict" | cut -d' ' -f2) ;; *) status=1 ;; esac
done
report $status "3D: the slab between walls = 2D plane strain (x_B, x_C within one spacing, the normal force converging)" "$diag"
diag="$work/repeat3d.diag"; : > "$diag"; status=0
solve -scene "$work/slide3d/scene.scene" -mesh "$work/slide3d/mesh.msh" -out "$work/slide3d-repeat" >> "$diag" 2>&1 || status=1
for f in "${OUTPUT_FILES[@]}"; do
  cmp -s <(grep -v -E '^(# )?(scene|out|mesh|mesh_source|scene_file|nx|ny|nz|time_[a-z_]*) ' "$work/slide3d/$f") \
         <(grep -v -E '^(# )?(scene|out|mesh|mesh_source|scene_file|nx|ny|nz|time_[a-z_]*) ' "$work/slide3d-repeat/$f") \
    || { echo "$f differs" >> "$diag"; status=1; }
done
report $status "3D: a run repeats itself from its own scene.scene and mesh.msh" "$diag"

# OUT/scene.scene holds the values the run used: with OUT/mesh.msh it repeats the run, command-
# line overrides included (outputs identical but for the lines that name the run's own files
# and the timings)
diag="$work/repeat.diag"; : > "$diag"; status=0
rm -rf "$work/repeat" "$work/repeat2"
solve -scene bound-profile -nx 33 -ny 16 -dt 0.05 -load 20 -mu 0.3 -r 0.5 -out "$work/repeat" >> "$diag" 2>&1 || status=1
solve -scene "$work/repeat/scene.scene" -mesh "$work/repeat/mesh.msh" -out "$work/repeat2" >> "$diag" 2>&1 || status=1
own_files() { grep -v -E '^(# )?(scene|out|mesh|mesh_source|scene_file|nx|ny|time_[a-z_]*) ' "$1"; }
for f in "${OUTPUT_FILES[@]}"; do
  cmp -s <(own_files "$work/repeat/$f") <(own_files "$work/repeat2/$f") || { echo "$f differs" >> "$diag"; status=1; }
done
grep -q '^load 20$' "$work/repeat/scene.scene" && grep -q '^r 0.5$' "$work/repeat/scene.scene" && grep -q '^bound_profile ' "$work/repeat/scene.scene" \
  || { echo "scene.scene lacks the override or the profile" >> "$diag"; status=1; }
# options left at the table's default are not pinned (the fixed point's r follows -solver), nor is g beside a profile
! grep -q -E '^(tol|maxit|solver|g) ' "$work/repeat/scene.scene" || { echo "scene.scene pins a table default or g" >> "$diag"; status=1; }
report $status "a run repeats itself from its OUT/scene.scene and OUT/mesh.msh, command-line overrides included" "$diag"

# -adapt: an adapted mesh (pilot runs, adaptmesh) gives the paper's zones, in order along
# Gamma3, with x_B and x_C within 0.02 m of the fine adapted reference of docs/performance.md
# (0.480, 1.337), passes every physics check, is made again byte for byte, and repeats the
# run from OUT/mesh.msh; a budget it would exceed and a pilot that fails stop the run
diag="$work/adapt.diag"; : > "$diag"; status=0
rm -rf "$work/adapt" "$work/adapt2" "$work/adapt3"
solve -nx 16 -ny 8 -adapt 2 -out "$work/adapt" >> "$diag" 2>&1 || status=1
"$PYTHON" tests/check_results.py "$work/adapt" >> "$diag" 2>&1 || status=1
"$PYTHON" - "$work/adapt" >> "$diag" 2>&1 <<'PY' || status=1
import sys
import suite
run = sys.argv[1]
summary = suite.read_summary(run)
rounds = [int(summary[f"adapt_round_{r}_vertices"]) for r in range(3)]
assert rounds[0] == 153 and rounds[2] == int(summary["vertices"]) and rounds[2] > 4 * rounds[0], rounds
assert summary["mesh_source"].startswith("adaptmesh, 2 rounds at adapt_err 1e-3, from gmsh"), summary["mesh_source"]
table = suite.read_table(run + "/contact.txt")
order = table["x"].argsort()
codes = suite.zone_codes(table["normal_status"][order], table["tangential_status"][order])
sequence = [c for k, c in enumerate(codes) if k == 0 or c != codes[k - 1]]
assert list(sequence) == [0, 1, 3, 4], sequence                  # free, damped-slip, bound-slip, bound-stick
history = suite.read_table(run + "/contact_history.txt")
xb, xc = history["x_B"][-1], history["x_C"][-1]
assert abs(xb - 0.480) < 0.02 and abs(xc - 1.337) < 0.02, (xb, xc)
PY
solve -nx 16 -ny 8 -adapt 2 -out "$work/adapt2" >> "$diag" 2>&1 || status=1
cmp "$work/adapt/mesh.msh" "$work/adapt2/mesh.msh" >> "$diag" 2>&1 || status=1
solve -scene "$work/adapt/scene.scene" -mesh "$work/adapt/mesh.msh" -out "$work/adapt3" >> "$diag" 2>&1 || status=1
for f in contact.txt fields.txt history.txt contact_history.txt; do
  cmp -s <(grep -v '^#' "$work/adapt/$f") <(grep -v '^#' "$work/adapt3/$f") || { echo "$f differs when repeated from OUT/mesh.msh" >> "$diag"; status=1; }
done
grep -q "^mesh_source $work/adapt/mesh.msh (made by the run in $work/adapt/: adaptmesh, 2 rounds at adapt_err 1e-3, from gmsh " "$work/adapt3/summary.txt" \
  || { echo "the repeated run's mesh_source does not say how the mesh was made:"; grep mesh_source "$work/adapt3/summary.txt"; status=1; } >> "$diag"
rm -rf "$work/adapt4"
solve -nx 16 -ny 8 -adapt 1 -adapt_err 0.0005 -adapt_vertices 500 -out "$work/adapt4" > "$work/adapt4.err" 2>&1; code=$?
{ [ "$code" = 2 ] && grep -Eq "(option -adapt_err = 0.0005 would make a mesh of about [0-9]* vertices in round 1|the mesh of adaptation round 1 has [0-9]* vertices), more than -adapt_vertices 500" "$work/adapt4.err" \
  && [ ! -e "$work/adapt4" ] && ! ls -d "$work"/adapt4.partial.* > /dev/null 2>&1; } || { echo "budget: exit $code"; cat "$work/adapt4.err"; status=1; } >> "$diag"
solve -nx 16 -ny 8 -adapt 1 -maxit 1 -out "$work/adapt4" > "$work/adapt4.err" 2>&1; code=$?
{ [ "$code" = 4 ] && grep -q "error: -adapt: the pilot run of round 1 (on the mesh of round 0, 153 vertices) failed with exit code 4: error: step 1" "$work/adapt4.err" \
  && [ ! -e "$work/adapt4" ]; } || { echo "pilot failure: exit $code"; cat "$work/adapt4.err"; status=1; } >> "$diag"
# fewer steps than the five snapshots of a pilot: a frame a step, the last standing for the rest
solve -nx 16 -ny 8 -adapt 1 -T 0.02 -out "$work/adapt5" >> "$diag" 2>&1 || { echo "-adapt with 2 steps failed" >> "$diag"; status=1; }
report $status "-adapt 2: the paper's zones in order, x_B and x_C within 0.02 m, physics checks; the same mesh byte for byte when made again; repeated from OUT/mesh.msh, whose mesh_source still says how it was made; a vertex budget or a failed pilot stops the run (exit 2, 4) with no output; fewer steps than snapshots" "$diag"

# -snapshots N: x, y, u, v at every vertex at the first step at or after j T/N; the last frame
# is fields.txt's u and v; N above the steps gives every step
diag="$work/snapshots.diag"; : > "$diag"; status=0
solve -scene column -snapshots 3 -out "$work/snap" >> "$diag" 2>&1 || status=1
solve -scene column -T 0.2 -snapshots 50 -out "$work/snap2" >> "$diag" 2>&1 || status=1
"$PYTHON" - "$work/snap" "$work/snap2" >> "$diag" 2>&1 <<'PY' || status=1
import sys
import numpy as np
import suite
run, every = sys.argv[1], sys.argv[2]
snap, fields = suite.read_table(run + "/snapshots.txt"), suite.read_table(run + "/fields.txt")
steps = int(suite.read_summary(run)["steps"])
assert snap.columns == "step t x y u_x u_y v_x v_y".split(), snap.columns
wanted = [next(n for n in range(1, steps + 1) if n * 3 >= j * steps) for j in (1, 2, 3)]
assert sorted(set(snap["step"].astype(int))) == wanted, (sorted(set(snap["step"])), wanted)
nv = len(fields["x"])
assert len(snap["step"]) == 3 * nv
last = slice(2 * nv, 3 * nv)
for c in ("x", "y", "u_x", "u_y", "v_x", "v_y"):
    assert np.array_equal(snap[c][last], fields[c]), c
small = suite.read_table(every + "/snapshots.txt")
assert sorted(set(small["step"].astype(int))) == list(range(1, int(suite.read_summary(every)["steps"]) + 1))
PY
report $status "-snapshots N: the first step at or after each j T/N, every vertex, the last frame equal to fields.txt; N above the steps gives every step" "$diag"

# the mesh cache follows the .geo's contents: a copy of the suite with a finer quarterdisk.geo
diag="$work/geo.diag"; : > "$diag"; status=0
copy="$work/geocopy"; rm -rf "$copy" && mkdir -p "$copy/meshes" && cp -r edp run.sh freefem++.pref "$copy/" && cp meshes/*.geo "$copy/meshes/"
(cd "$copy" && "${FREEFEM[@]}" edp/solve.edp -scene cylinder -nx 8 -dt 0.5 -T 0.5 -out before) >> "$diag" 2>&1 || status=1
sed -i 's|^h = R/nx;|h = R/nx/2;|' "$copy/meshes/quarterdisk.geo"
(cd "$copy" && "${FREEFEM[@]}" edp/solve.edp -scene cylinder -nx 8 -dt 0.5 -T 0.5 -out after) >> "$diag" 2>&1 || status=1
a=$(awk '$1 == "vertices" { print $2 }' "$copy/before/summary.txt" 2>/dev/null); b=$(awk '$1 == "vertices" { print $2 }' "$copy/after/summary.txt" 2>/dev/null)
[ -n "$a" ] && [ -n "$b" ] && [ "$b" -gt $((3 * a)) ] || { echo "vertices before $a, after halving h $b" >> "$diag"; status=1; }
# a .geo that includes another: not cached (its checksum does not cover the included file)
cp "$copy/meshes/quarterdisk.geo" "$copy/meshes/body.geo"
printf 'Include "body.geo";\n' > "$copy/meshes/outer.geo"
sed 's|^geometry .*|geometry outer|' edp/scenes/cylinder.scene > "$copy/outer.scene"
(cd "$copy" && "${FREEFEM[@]}" edp/solve.edp -scene outer.scene -nx 8 -dt 0.5 -T 0.5 -out inc1) >> "$diag" 2>&1 || status=1
sed -i 's|^h = R/nx/2;|h = R/nx;|' "$copy/meshes/body.geo"
(cd "$copy" && "${FREEFEM[@]}" edp/solve.edp -scene outer.scene -nx 8 -dt 0.5 -T 0.5 -out inc2) >> "$diag" 2>&1 || status=1
c=$(awk '$1 == "vertices" { print $2 }' "$copy/inc1/summary.txt" 2>/dev/null); d=$(awk '$1 == "vertices" { print $2 }' "$copy/inc2/summary.txt" 2>/dev/null)
[ -n "$c" ] && [ "$c" = "$b" ] && [ "$d" = "$a" ] || { echo "included .geo: vertices $c (expected $b), after editing the included file $d (expected $a)" >> "$diag"; status=1; }
report $status "the mesh cache follows the .geo's contents: halving h in quarterdisk.geo gives a new mesh, an included .geo too" "$diag"

# an oblique contact boundary: the paper's block turned by 30 degrees (tests/data/tilted.geo,
# clamped on its left side, the traction turned with it) gives the same contact values
diag="$work/tilted.diag"; : > "$diag"; status=0
for a in 0 30; do
  gmsh -2 -format msh22 -v 0 -setnumber a "$a" tests/data/tilted.geo -o "$work/tilted$a.msh" > /dev/null 2>&1 || status=1
  grep -v -E '^(dirichlet|traction|contact_normal|nx|ny) ' edp/scenes/paper.scene > "$work/tilted$a.scene"
  awk -v a="$a" 'BEGIN { r = a * atan2(0, -1) / 180; printf "dirichlet 4 xy\ntraction %.17g %.17g\n", sin(r), -cos(r) }' >> "$work/tilted$a.scene"
  solve -scene "$work/tilted$a.scene" -mesh "$work/tilted$a.msh" -dt 0.05 -out "$work/tilted$a" >> "$diag" 2>&1 || status=1
done
paste <(grep -v '^#' "$work/tilted0/contact.txt") <(grep -v '^#' "$work/tilted30/contact.txt") \
  | awk 'NF != 22 { bad = 1 } { for (i = 2; i <= 6; i++) { d = $i - $(i + 11); if (d < 0) d = -d; if (d > m) m = d } }
         END { if (bad || NR == 0 || m > 1e-9) { print "turned by 30 degrees: contact values differ by " m; exit 1 } }' >> "$diag" || status=1
report $status "an oblique contact boundary: the block turned by 30 degrees has the same v_nu, v_tau, p_nu, lambda_nu, lambda_tau to 1e-9" "$diag"

# boundaries where a normal means nothing are refused (exit 3, no output)
gmsh -2 -format msh22 -v 0 tests/data/spike.geo -o "$work/spike.msh" > /dev/null 2>&1
grep -v -E '^(dirichlet|contact_normal) ' edp/scenes/paper.scene > "$work/spike.scene"
expect_failure "a contact boundary that turns by 150 degrees" 3 "turns by more than 120 degrees at \(1, 0\)" -scene "$work/spike.scene" -mesh "$work/spike.msh"
# a bad step is caught at the step, not only at T: g = 1e-12 at one end breaks the
# complementarity (by round-off, relative to g) from step 1 on; the message names the step of
# the largest violation and the first step above the tolerance
grep -v -E '^(g|load_history|T|dt) ' edp/scenes/column.scene > "$work/midrun.scene"
printf 'bound_profile 0 1e-12 1 0.05\nload_history 0 0 0.1 0.1 0.2 -1\nT 0.2\ndt 0.05\n' >> "$work/midrun.scene"
expect_failure "a check that fails before T" 9 "end-of-run check failed: complementarity .* at step [0-9] \\(first above it at step [12]\\);" -scene "$work/midrun.scene"
grep -v -E '^g ' edp/scenes/column.scene > "$work/gprofile.scene"; printf 'bound_profile 0 0.02 1 0.05\n' >> "$work/gprofile.scene"
expect_failure "-g with a bound_profile" 2 "option -g gives one bound for all of Gamma3, but .*gprofile.scene:[0-9]+ gives a bound_profile" -scene "$work/gprofile.scene" -g 0.2
printf 'g 0.05\n' >> "$work/gprofile.scene"
expect_failure "g and bound_profile in one scene" 3 "gprofile.scene:[0-9]+: g gives one bound for all of Gamma3, but the bound_profile of line [0-9]+" -scene "$work/gprofile.scene"
# the same turn at a node whose two edges differ in length 17 times (the lumped normal alone would not see it)
gmsh -2 -format msh22 -v 0 -setnumber turn 150 -setnumber nr 20 -setnumber pr 1.15 tests/data/vee.geo -o "$work/vee.msh" > /dev/null 2>&1
expect_failure "a 150-degree turn between edges of unequal length" 3 "turns by more than 120 degrees at \(0, 0\)" -scene "$work/spike.scene" -mesh "$work/vee.msh" -T 0.1 -dt 0.05
gmsh -2 -format msh22 -v 0 -setnumber nx 10 tests/data/halfdisk.geo -o "$work/halfdisk.msh" > /dev/null 2>&1
grep -v -E '^(dirichlet|contact_normal|geometry) ' edp/scenes/cylinder.scene > "$work/halfdisk.scene"; echo "dirichlet 3 x" >> "$work/halfdisk.scene"
expect_failure "a contact node whose free component is not a normal velocity" 3 "has its x velocity fixed by a dirichlet line, and its normal .* is more than 60 degrees from the free y axis" -scene "$work/halfdisk.scene" -mesh "$work/halfdisk.msh"

# every new key is checked when the scene is read: exit 3 naming the file, line and key
diag="$work/keys.diag"; : > "$diag"; status=0
while IFS='|' read -r line regex; do
  grep -v -E "^(${line%% *}|cnu) " edp/scenes/column.scene > "$work/key.scene"; printf '%s\n' "$line" >> "$work/key.scene"
  case "$line" in damping*) ;; *) echo "damping linear 50" >> "$work/key.scene" ;; esac
  rm -rf "$work/key"; rc=0; solve -scene "$work/key.scene" -out "$work/key" > "$work/key.log" 2>&1 || rc=$?
  { [ "$rc" = 3 ] && grep -Eq "key.scene:[0-9]+: .*$regex" "$work/key.log" && [ ! -e "$work/key" ]; } \
    || { echo "'$line': exit $rc, expected 3 and /$regex/: $(cat "$work/key.log")" >> "$diag"; status=1; }
done <<'KEYS'
load_history 0 0 1|load_history: .*pairs
load_history 0 0 1 1 0.5 2|load_history: point 3 \(0.5, 2\) does not come after the one before
load_history -1 0 1 1|load_history: the times must be >= 0
bound_profile 0 0.05 1 0|bound_profile: every g must be > 0
bound_profile 1 0.05 0 0.06|bound_profile: point 2 \(0, 0.06\) does not come after
damping table 0 0 0.1 2 0.2 1|damping table: p decreases at point 3 \(0.2, 1\)
damping table 0.1 0 0.2 1|damping table: the first point must be \(0, 0\)
damping table 0 0|damping table: at least two points
damping power 1000 0.5|ALPHA must be >= 1
damping cubic 3|damping linear C, damping power C ALPHA
body_force 0|body_force
initial_velocity 0 nan|initial_velocity
contact_normal 0 0|contact_normal
KEYS
grep -v '^cnu ' edp/scenes/column.scene > "$work/key.scene"; printf 'damping linear 50\nload_history 0 0 1 1\nload_history 0 0 1 2\n' >> "$work/key.scene"
rc=0; solve -scene "$work/key.scene" -out "$work/key" > "$work/key.log" 2>&1 || rc=$?
[ "$rc" = 3 ] && grep -q "'load_history' is given a second time" "$work/key.log" || { echo "a repeated load_history: exit $rc" >> "$diag"; status=1; }
printf 'cnu 50\n' >> "$work/key.scene"
rc=0; solve -scene "$work/key.scene" -out "$work/key" > "$work/key.log" 2>&1 || rc=$?
[ "$rc" = 3 ] || { echo "cnu and damping linear together: exit $rc" >> "$diag"; status=1; }
rc=0; solve -scene tests/scenes/column-table.scene -cnu 30 -out "$work/key" > "$work/key.log" 2>&1 || rc=$?
[ "$rc" = 2 ] && grep -q "option -cnu gives C of damping linear or power, but the damping of .* is a table" "$work/key.log" || { echo "-cnu with a table: exit $rc" >> "$diag"; status=1; }
report $status "scene keys: bad load_history, bound_profile, damping, body_force, initial_velocity, contact_normal refused with file, line and key (exit 3); repeats, cnu with damping, -cnu with a table refused" "$diag"

# ---- a failed run leaves earlier results untouched
diag="$work/keep.diag"; : > "$diag"; status=0
rm -rf "$work/keep"
solve "${coarse[@]}" -out "$work/keep" > "$diag" 2>&1 || status=1
cp "$work/keep/contact.txt" "$work/keep.contact.before" 2>/dev/null || status=1
solve "${coarse[@]}" -maxit 1 -out "$work/keep" >> "$diag" 2>&1 && status=1
cmp -s "$work/keep/contact.txt" "$work/keep.contact.before" || { echo "earlier results changed" >> "$diag"; status=1; }
compgen -G "$work/keep.partial*" > /dev/null && { echo "partial folder left behind" >> "$diag"; status=1; }
report $status "a failed run leaves the earlier results untouched" "$diag"
diag="$work/deep.diag"; : > "$diag"; status=0
deep="$work/deep"; for level in $(seq 20); do deep="$deep/$level"; done
rm -rf "$work/deep"; rc=0; solve "${coarse[@]}" -maxit 1 -out "$deep/run" >> "$diag" 2>&1 || rc=$?
[ "$rc" = 4 ] || { echo "exit $rc, expected 4" >> "$diag"; status=1; }
[ -e "$work/deep" ] && { echo "left: $(find "$work/deep" | tail -1)" >> "$diag"; status=1; }
report $status "a failed run removes the 20 parent folders of -out it created" "$diag"

# ---- a run killed by a signal leaves the earlier results untouched and nothing that looks valid;
# a handled signal (TERM, or SEGV of a crash) leaves nothing at all, and the exit status 128 + n
long_run() { # long_run OUT: a solve of about 5 s in the background (long enough to be killed), no core file
  (ulimit -c 0; exec "${FREEFEM[@]}" edp/solve.edp -nx 66 -ny 33 -dt 0.0002 -out "$1") >> "$diag" 2>&1 &
  pid=$!
}
for signal in TERM SEGV KILL; do
  diag="$work/kill.diag"; : > "$diag"; status=0
  rm -rf "$work/kill" "$work"/kill.partial* "$work/kill-new"
  solve "${coarse[@]}" -out "$work/kill" > "$diag" 2>&1 || status=1
  cp -r "$work/kill" "$work/kill.before"
  long_run "$work/kill"
  sleep 0.4
  kill -s "$signal" "$pid" 2>/dev/null || { echo "the run ended before the signal" >> "$diag"; status=1; }
  rc=0; wait "$pid" 2>/dev/null || rc=$?
  [ "$rc" = $((128 + $(kill -l "$signal"))) ] || { echo "the killed run exited $rc" >> "$diag"; status=1; }
  diff -r "$work/kill" "$work/kill.before" >> "$diag" 2>&1 || { echo "earlier results changed" >> "$diag"; status=1; }
  compgen -G "$work/kill.partial*/run.complete" > /dev/null && { echo "a complete-looking $work/kill.partial.* was left" >> "$diag"; status=1; }
  if [ "$signal" != KILL ]; then
    compgen -G "$work/kill.partial*" > /dev/null && { echo "SIG$signal left $work/kill.partial.*" >> "$diag"; status=1; }
    long_run "$work/kill-new/a/run"                 # a new OUT in new folders: none of them is left
    sleep 0.4
    kill -s "$signal" "$pid" 2>/dev/null || { echo "the second run ended before the signal" >> "$diag"; status=1; }
    wait "$pid" 2>/dev/null
    [ -e "$work/kill-new" ] && { echo "SIG$signal left $(find "$work/kill-new")" >> "$diag"; status=1; }
  fi
  rm -rf "$work/kill.before" "$work"/kill.partial* "$work/kill-new"
  report $status "a run killed with SIG$signal leaves the earlier results untouched$([ "$signal" != KILL ] && echo ", nothing else, and exits 128 + n")" "$diag"
done

# ---- reliability: nothing of the user's is touched, runs never mix, every write is checked,
# no shell sees user text, meshes are checked before FreeFEM reads them, signals stop the solve
# contains FILE REGEX: FILE matches REGEX (for the diagnostics)
contains() { grep -Eq "$2" "$1" || { echo "no /$2/ in $1" >> "$diag"; return 1; }; }

diag="$work/userfiles.diag"; : > "$diag"; status=0
d="$work/userfiles"; rm -rf "$d" "$d".*
for sibling in old partial replaced; do mkdir -p "$d.$sibling" && echo "the user's" > "$d.$sibling/notes"; done
solve "${coarse[@]}" -out "$d" >> "$diag" 2>&1 || status=1
solve "${coarse[@]}" -maxit 1 -out "$d" >> "$diag" 2>&1 && status=1
solve "${coarse[@]}" -load 5 -out "$d" >> "$diag" 2>&1 || status=1
for sibling in old partial replaced; do [ "$(cat "$d.$sibling/notes" 2>/dev/null)" = "the user's" ] || { echo "$d.$sibling/notes changed" >> "$diag"; status=1; }; done
cp "$d/contact.txt" "$work/userfiles.contact"; echo "my notes" > "$d/notes.txt"
rc=0; solve "${coarse[@]}" -out "$d" >> "$diag" 2>&1 || rc=$?
[ "$rc" = 7 ] && contains "$diag" "holds files that this suite did not write there \(notes.txt\)" || status=1
[ -f "$d/notes.txt" ] && cmp -s "$d/contact.txt" "$work/userfiles.contact" || { echo "the folder with the user's notes changed" >> "$diag"; status=1; }
rm "$d/notes.txt"; cp -r "$d" "$d.copy"; rm "$d.copy/run.complete"
rc=0; solve "${coarse[@]}" -out "$d.copy" >> "$diag" 2>&1 || rc=$?
[ "$rc" = 7 ] && contains "$diag" "holds a summary.txt but no run.complete" && [ -f "$d.copy/summary.txt" ] || status=1
report $status "data loss: the user's D.old, D.partial, D.replaced and files in D are never touched; D without run.complete is not replaced" "$diag"

# a file put into OUT between the run's last check of OUT and the swap (written there by an
# LD_PRELOAD shim, tests/data/late_file.cpp, at the exchange itself): kept, with a note
diag="$work/latefile.diag"; : > "$diag"; status=0
d="$work/latefile"; rm -rf "$d" "$d".*
g++ -O2 -fPIC -shared tests/data/late_file.cpp -o "$work/late_file.so" -ldl >> "$diag" 2>&1 || status=1
solve "${coarse[@]}" -out "$d" >> "$diag" 2>&1 || status=1
LD_PRELOAD="$root/$work/late_file.so" LATE_FILE=notes.txt solve "${coarse[@]}" -load 5 -out "$d" >> "$diag" 2>&1 || status=1
kept=$(compgen -G "$d.kept.*")
[ -n "$kept" ] && [ "$(ls "$kept")" = notes.txt ] && [ "$(cat "$kept/notes.txt")" = "the user's late notes" ] \
  || { echo "the late file was not kept alone in $d.kept.*: $(ls -d "$d"*)" >> "$diag"; status=1; }
contains "$diag" "note: notes.txt appeared in $d while this run replaced it: .* is kept as $kept; the new results are in $d" || status=1
grep -qx 'load 5' "$d/summary.txt" && [ -f "$d/run.complete" ] && [ ! -e "$d/notes.txt" ] || { echo "the new results are not in $d" >> "$diag"; status=1; }
compgen -G "$d.partial*" > /dev/null && { echo "a partial folder was left" >> "$diag"; status=1; }
report $status "data loss: a file put into OUT just before the swap is kept (OUT.kept.PID, named in a note), the new results are in OUT" "$diag"

diag="$work/concurrent.diag"; : > "$diag"; status=0
for pair in 1 2 3 4 5 6; do
  rm -rf "$work/concurrent"
  solve -nx 16 -ny 8 -dt 0.01 -load 5 -out "$work/concurrent" > "$work/concurrent.a" 2>&1 & a=$!
  solve -nx 16 -ny 8 -dt 0.01 -load 20 -out "$work/concurrent" > "$work/concurrent.b" 2>&1 & b=$!
  ra=0; wait "$a" || ra=$?; rb=0; wait "$b" || rb=$?
  for r in "$ra:a" "$rb:b"; do
    case "${r%%:*}" in 0) ;; 7) contains "$work/concurrent.${r#*:}" "another run \(process [0-9]+\) is writing it" || status=1 ;;
      *) echo "pair $pair: exit ${r%%:*}" >> "$diag"; cat "$work/concurrent.${r#*:}" >> "$diag"; status=1 ;; esac
  done
  [ "$ra" = 0 ] || [ "$rb" = 0 ] || { echo "pair $pair: neither run finished" >> "$diag"; status=1; }
  loads=$(grep -h '^# load ' "$work"/concurrent/*.txt | sort -u | wc -l)
  [ "$loads" = 1 ] && [ -f "$work/concurrent/run.complete" ] || { echo "pair $pair: a mixed or incomplete folder" >> "$diag"; status=1; }
  "$PYTHON" tests/check_results.py "$work/concurrent" >> "$diag" 2>&1 || status=1
  compgen -G "$work/concurrent.partial*" > /dev/null && { echo "pair $pair: a partial folder was left" >> "$diag"; status=1; }
done
report $status "concurrency: 6 pairs of runs on one -out, each complete and unmixed or refused (exit 7, naming the other)" "$diag"

diag="$work/diskfull.diag"; : > "$diag"; status=0; disk="$work/small-disk"; mkdir -p "$disk"
if mount -t tmpfs -o size=400k tmpfs "$disk" 2> "$diag"; then
  solve -nx 16 -ny 8 -dt 0.05 -out "$disk/run" >> "$diag" 2>&1 || status=1
  cp "$disk/run/contact.txt" "$work/diskfull.contact"
  for case in "-nx 132 -ny 66" ""; do   # the mesh does not fit; the mesh fits but fields.txt does not
    rc=0; solve $case -out "$disk/run" >> "$diag" 2>&1 || rc=$?
    [ "$rc" = 7 ] && contains "$diag" "cannot write .*(is the disk full\?|No space left)" || { echo "exit $rc for '$case'" >> "$diag"; status=1; }
  done
  cmp -s "$disk/run/contact.txt" "$work/diskfull.contact" || { echo "earlier results changed" >> "$diag"; status=1; }
  [ "$(ls "$disk")" = run ] || { echo "left in $disk: $(ls "$disk")" >> "$diag"; status=1; }
  umount "$disk"
  report $status "a full disk: exit 7, earlier results untouched, no partial folder" "$diag"
else
  count=$((count + 1)); passed=$((passed + 1))
  echo "ok $count - a full disk: exit 7, earlier results untouched, no partial folder # SKIP cannot mount a tmpfs here (not root?)"
fi

diag="$work/injection.diag"; : > "$diag"; status=0
rm -f "$work/INJECTED"
grep -v '^geometry' edp/scenes/paper.scene > "$work/injection.scene"; echo "geometry x;touch $work/INJECTED" >> "$work/injection.scene"
rc=0; solve -scene "$work/injection.scene" -out "$work/injection" >> "$diag" 2>&1 || rc=$?
[ "$rc" = 3 ] || { echo "exit $rc" >> "$diag"; status=1; }
odd="$work/a b'c\$(touch $work/INJECTED)\`touch $work/INJECTED\`"
rm -rf "$odd"; solve "${coarse[@]}" -out "$odd" >> "$diag" 2>&1 && [ -f "$odd/run.complete" ] || { echo "the odd folder name failed" >> "$diag"; status=1; }
[ -e "$work/INJECTED" ] && { echo "a command ran from data" >> "$diag"; status=1; }
report $status "injection: shell characters in scene values are refused, in -out they name a folder; nothing runs" "$diag"

diag="$work/meshes.diag"; : > "$diag"; status=0
gmsh -2 -format msh22 -v 0 -setnumber nx 8 -setnumber ny 4 meshes/rectangle.geo -o "$work/good.msh" > /dev/null 2>&1
"$PYTHON" tests/bad_meshes.py "$work/good.msh" "$work/bad-meshes" >> "$diag" 2>&1 || status=1
while IFS='|' read -r name regex; do
  rc=0; solve -mesh "$work/bad-meshes/$name.msh" -dt 0.1 -out "$work/bad-mesh" > "$work/bad-mesh.log" 2>&1 || rc=$?
  if [ "$rc" != 3 ] || ! grep -Eq "$regex" "$work/bad-mesh.log" || [ -e "$work/bad-mesh" ]; then
    echo "$name: exit $rc, expected 3 and /$regex/, no results:" >> "$diag"; cat "$work/bad-mesh.log" >> "$diag"; status=1
  fi
done <<'MESHES'
undefined-node|uses node 999999, which is not defined
twice-listed-edge|repeats line element .* listed twice
quadrangle|is a quadrangle \(gmsh type 3\)
order-2|is of order 2 or more \(gmsh type 9\)
micrometres|below the 1e-8 that FreeFEM's mesh reader accepts
long-and-thin|extends over 5e\+07 \(its bounding box\) but its shortest edge is 0.25, more than 1e\+08 times shorter
unused-node|is not a vertex of any triangle
truncated|a truncated file
overlap|lie on the same side of their common edge
folded|lie on the same side of their common edge
interior-traction|lies inside the body, between two triangles
interior-contact|lies inside the body, between two triangles
gap-in-contact|has no line element: give every boundary curve a Physical Curve
64-bit-id|does not fit FreeFEM's 32-bit ids
two-bodies|the triangles form 2 separate pieces
loose-triangle|the triangles form 2 separate pieces
slit|the boundary edges \(nodes [0-9]+ [0-9]+\) and \(nodes [0-9]+ [0-9]+\) cross or overlap
arm-over-body|the boundary edges \(nodes [0-9]+ [0-9]+\) and \(nodes [0-9]+ [0-9]+\) cross or overlap
MESHES
solve -mesh "$work/good.msh" -dt 0.1 -out "$work/good-mesh" >> "$diag" 2>&1 || status=1
solve -mesh "$work/bad-meshes/clockwise.msh" -dt 0.1 -out "$work/clockwise-mesh" >> "$diag" 2>&1 || status=1
for f in contact.txt fields.txt history.txt; do
  cmp -s <(grep -v '^#' "$work/good-mesh/$f") <(grep -v '^#' "$work/clockwise-mesh/$f") || { echo "clockwise triangles change $f" >> "$diag"; status=1; }
done
grep -v '^dirichlet 2' edp/scenes/paper.scene > "$work/dirichlet9.scene"; echo "dirichlet 9 x" >> "$work/dirichlet9.scene"
rc=0; solve -scene "$work/dirichlet9.scene" -mesh "$work/good.msh" -dt 0.1 -out "$work/dirichlet9" >> "$diag" 2>&1 || rc=$?
[ "$rc" = 3 ] && contains "$diag" "dirichlet label 9 is not a physical curve of the mesh" || status=1
cached=$(ls meshes/build/rectangle_*_Lx2_Ly1_8x4.msh 2>/dev/null | head -1)
if [ -n "$cached" ]; then
  head -c 200 "$cached" > "$cached.cut" && mv "$cached.cut" "$cached"   # a truncated cache is made again
  solve "${coarse[@]}" -out "$work/cache" >> "$diag" 2>&1 && [ "$(wc -c < "$cached")" -gt 1000 ] || { echo "a truncated cached mesh" >> "$diag"; status=1; }
fi
report $status "meshes: undefined or unused nodes, repeated edges, overlapping or folded triangles, labels inside the body, gaps, 64-bit ids, two bodies, a loose triangle, a slit, crossing boundaries, quadrangles, order 2, tiny, long and thin, truncated files, missing dirichlet labels refused (exit 3); clockwise triangles reoriented; a bad cache remade" "$diag"

diag="$work/signal.diag"; : > "$diag"; status=0
rm -rf "$work/signal" "$work"/signal.partial*
bash run.sh solve -nx 66 -ny 33 -dt 0.0002 -out "$work/signal" >> "$diag" 2>&1 & pid=$!
sleep 1
kill -TERM "$pid" 2>/dev/null; wait "$pid" 2>/dev/null && status=1
sleep 0.2
pgrep -f -- "-out $work/signal" > /dev/null && { echo "the solve still runs after run.sh was killed" >> "$diag"; pkill -f -- "-out $work/signal"; status=1; }
[ -e "$work/signal" ] || compgen -G "$work/signal.partial*" > /dev/null && { echo "left: $(ls -d "$work"/signal "$work"/signal.partial* 2>/dev/null)" >> "$diag"; status=1; }
report $status "signals: killing ./run.sh solve stops the solve, which removes what it created" "$diag"

diag="$work/messages.diag"; : > "$diag"; status=0
printf '\xEF\xBB\xBF' > "$work/bom.scene"; cat edp/scenes/column.scene >> "$work/bom.scene"
solve -scene "$work/bom.scene" -out "$work/bom" >> "$diag" 2>&1 || { echo "a scene with a byte order mark" >> "$diag"; status=1; }
while IFS='|' read -r line regex; do
  grep -v "^${line%% *} " edp/scenes/column.scene > "$work/message.scene"; printf '%s\n' "$line" >> "$work/message.scene"
  [ "${line%% *}" = load ] && echo "load 10" >> "$work/message.scene"
  rc=0; solve -scene "$work/message.scene" -out "$work/message" > "$work/message.log" 2>&1 || rc=$?
  [ "$rc" = 3 ] && grep -Eq "$regex" "$work/message.log" || { echo "'$line': exit $rc, expected 3 and /$regex/" >> "$diag"; status=1; }
done <<'SCENES'
Lx 0|Lx must be a number > 0, got '0'
load 5|'load' is given a second time
contact_normal 0 -1e400|contact_normal needs two finite numbers
geometry ../rectangle|a name of meshes/NAME.geo
Lx 1e10|Lx 1e10 and Ly 2 with 8 x 16 cells make a mesh that extends over 1e\+10 but whose shortest edge is 0.125, more than 1e\+08 times shorter
SCENES
rc=0; solve "${coarse[@]}" -E 1e300 -out "$work/message" > "$work/message.log" 2>&1 || rc=$?
[ "$rc" = 2 ] && grep -q "give matrix entries up to .*use other units" "$work/message.log" || { echo "-E 1e300: exit $rc" >> "$diag"; status=1; }
rc=0; bash tests/run_tests.sh --bless '' > "$work/message.log" 2>&1 || rc=$?
[ "$rc" = 2 ] && grep -q "usage: ./run.sh test --bless CASE" "$work/message.log" || { echo "--bless '': exit $rc" >> "$diag"; status=1; }
mkdir -p "$work/corrupt/paper-original" "$work/corrupt/paper-penalty"; printf 'garbage\n\001\377\n' > "$work/corrupt/paper-original/summary.txt"
"$PYTHON" plots/tables.py --results "$work/corrupt" > "$work/message.log" 2>&1 && status=1
[ "$(wc -l < "$work/message.log")" = 1 ] && ! grep -q Traceback "$work/message.log" || { echo "tables.py on a corrupt summary:" >> "$diag"; cat "$work/message.log" >> "$diag"; status=1; }
report $status "messages: a byte order mark is read; Lx 0, Lx 1e10 (before gmsh), repeated keys, non-finite numbers, odd names, -E 1e300 named; --bless '' and corrupt inputs give one line" "$diag"

# ---- see a run: -help, the VTK series read back by VTK itself, the Newton log, progress
diag="$work/help.diag"; : > "$diag"; status=0
for flag in -help -h --help; do
  rc=0; solve -scene column "$flag" > "$work/help.txt" 2> "$work/help.err" || rc=$?
  [ "$rc" = 0 ] && [ ! -s "$work/help.err" ] || { echo "$flag: exit $rc" >> "$diag"; cat "$work/help.err" >> "$diag"; status=1; }
done
# every option of edp/options.txt, and the same options as the README's table, with the scene's default
for name in $(awk '!/^#/ && NF >= 5 && $1 != "when" { print $1 }' edp/options.txt); do
  grep -q -- "^  -${name}  " "$work/help.txt" || { echo "-help does not list -${name}" >> "$diag"; status=1; }
done
readme_options=$(awk -F'|' '/^\| `-/ { print $2 }' README.md | grep -o -- '`-[a-zA-Z_]*`' | tr -d '`' | sort | tr '\n' ' ')
help_options=$(grep -o -- '^  -[a-zA-Z_]*' "$work/help.txt" | tr -d ' ' | sort | tr '\n' ' ')
[ "$readme_options" = "$help_options" ] || { echo "README's table: $readme_options; -help: $help_options" >> "$diag"; status=1; }
grep -q -- '^  -nx  8  ' "$work/help.txt" || { echo "-help does not give the column scene's nx 8" >> "$diag"; status=1; }
report $status "-help, -h, --help list every option (edp/options.txt, the README's table) with the scene's defaults, exit 0" "$diag"

diag="$work/vtk.diag"; : > "$diag"; status=0
for scene in column cylinder; do
  rm -rf "$work/vtk-$scene"
  solve -scene "$scene" -nx 8 -T 0.2 -dt 0.05 -vtk 3 -out "$work/vtk-$scene" >> "$diag" 2>&1 || status=1
  "$PYTHON" tests/check_vtk.py "$work/vtk-$scene" >> "$diag" 2>&1 || status=1
  "$PYTHON" tests/check_results.py "$work/vtk-$scene" >> "$diag" 2>&1 || status=1
  ls "$work/vtk-$scene/vtk" | tr '\n' ' ' | grep -qx 'fields.pvd fields_000000.vtu fields_000003.vtu fields_000004.vtu ' \
    || { echo "$scene: vtk/ holds $(ls "$work/vtk-$scene/vtk" | tr '\n' ' ')" >> "$diag"; status=1; }
done
# a run replaced by another: the earlier vtk/ goes with it; a file of the user's in vtk/ is not ours to replace
solve -scene column -nx 8 -T 0.2 -dt 0.05 -out "$work/vtk-column" >> "$diag" 2>&1 || status=1
[ ! -e "$work/vtk-column/vtk" ] || { echo "the earlier vtk/ was left in a replaced folder" >> "$diag"; status=1; }
solve -scene column -nx 8 -T 0.2 -dt 0.05 -vtk 1 -out "$work/vtk-column" >> "$diag" 2>&1 || status=1
touch "$work/vtk-column/vtk/mine.txt"
rc=0; solve -scene column -nx 8 -T 0.2 -dt 0.05 -out "$work/vtk-column" >> "$diag" 2>&1 || rc=$?
[ "$rc" = 7 ] && [ -e "$work/vtk-column/vtk/mine.txt" ] || { echo "a file of the user's in vtk/: exit $rc" >> "$diag"; status=1; }
report $status "-vtk N: fields.pvd and .vtu frames read back by VTK equal fields.txt and the zones; replaced with their run, a user's file kept" "$diag"

diag="$work/log.diag"; : > "$diag"; status=0
rm -rf "$work/log"
solve -scene paper -nx 16 -ny 8 -T 0.2 -dt 0.05 -verbose -out "$work/log" > /dev/null 2> "$work/log.err" || status=1
[ "$(grep -c '^step [0-9]*/4 (t = ' "$work/log.err")" = 4 ] && grep -q '^Solver log: 16 normal slots .* and 15 tangential' "$work/log.err" \
  && grep -q '^  iteration 0 (the previous .*): residual .*; slots: damped 16, stick [0-9]*, slip [0-9]*$' "$work/log.err" \
  && grep -q '^  iteration 1: residual .* (the Newton iterate did not lower the merit: one fixed-point iteration instead); changed: stick +[0-9]*, slip -[0-9]*$' "$work/log.err" \
  || { echo "-verbose:" >> "$diag"; cat "$work/log.err" >> "$diag"; status=1; }
# a run of more than 2 s shows its progress about once a second, on stderr; -quiet none
rm -rf "$work/log"
solve -nx 132 -ny 66 -T 0.6 -dt 0.001 -out "$work/log" > "$work/log.out" 2> "$work/log.err" || status=1
grep -q '^step [0-9]*/600 (t = .*), [0-9]* iterations*; zones: ' "$work/log.err" && ! grep -q '^step' "$work/log.out" \
  || { echo "no progress line in a run whose loop took $(awk '$1 == "time_loop" { print $2 }' "$work/log/summary.txt") s" >> "$diag"; status=1; }
rm -rf "$work/log"
solve -nx 132 -ny 66 -T 0.6 -dt 0.001 -quiet -out "$work/log" > /dev/null 2> "$work/log.err" || status=1
[ ! -s "$work/log.err" ] || { echo "-quiet printed:" >> "$diag"; head -3 "$work/log.err" >> "$diag"; status=1; }
report $status "-verbose logs each Newton iteration and step; a long run shows progress on stderr, -quiet silences it" "$diag"
grep -v '^#' edp/scenes/column.scene > "$work/quiet.scene"; echo "quiet on" >> "$work/quiet.scene"
expect_failure "a flag given a value in a scene" 3 "quiet.scene:[0-9]+: 'quiet' is a flag of the command line" -scene "$work/quiet.scene"
expect_failure "a flag given a value" 2 "option -quiet is a flag: it takes no value, got 'on'" -quiet on
expect_failure "-help as the value of an option" 2 "option -vtk needs a value, got the option '-help'" -vtk -help
expect_failure "-every below 0" 2 "option -every = -1 is out of range" -every -1

# ---- the lab sheet's commands run as written (docs/lab.md)
# tests/lab.sh runs every ```sh block of the sheet in order, in one shell with a fresh
# temporary $LAB, then checks the numbers the sheet states against the runs it made.
diag="$work/lab.diag"
bash tests/lab.sh "$work/lab.log" > "$diag" 2>&1
report $? "docs/lab.md: every command of the lab sheet runs, and gives the numbers the sheet states" "$diag"
# ---- end lab

# ---- the figures' names: plots/suite.py (FIGURES_DRAWN) and edp/plugins/runtools.cpp (figuresDrawn) list the same
diag="$work/names.diag"; : > "$diag"
py_names=$("$PYTHON" -c 'import suite; print(" ".join(sorted(suite.FIGURES_DRAWN)))' 2>> "$diag")
cpp_names=$(sed -n '/^bool figuresDrawn/,/^}/p' edp/plugins/runtools.cpp | grep -o '"[a-zA-Z_]*\.[a-z0-9]*"' | tr -d '"' | sort | tr '\n' ' ' | sed 's/ $//')
echo "plots/suite.py: $py_names; runtools.cpp: $cpp_names" >> "$diag"
[ -n "$py_names" ] && [ "$py_names" = "$cpp_names" ]; report $? "the names of the figures drawn: the same list in plots/suite.py and edp/plugins/runtools.cpp" "$diag"

# ---- edp/compare.edp (the benchmark's errors): a run against itself is 0, against a finer mesh small
diag="$work/compare.diag"; : > "$diag"; status=0
rm -rf "$work/cmp-a" "$work/cmp-b"
solve -nx 16 -ny 8 -dt 0.1 -out "$work/cmp-a" >> "$diag" 2>&1 || status=1
solve -nx 32 -ny 16 -dt 0.1 -out "$work/cmp-b" >> "$diag" 2>&1 || status=1
self=$("${FREEFEM[@]}" edp/compare.edp -a "$work/cmp-a" -ref "$work/cmp-a" 2>> "$diag")
other=$("${FREEFEM[@]}" edp/compare.edp -a "$work/cmp-a" -ref "$work/cmp-b" 2>> "$diag")
echo "self: $self; against 32x16: $other" >> "$diag"
awk '{ exit !($1 == "error_L2" && $2 == 0 && $6 == 0) }' <<< "$self" || status=1
awk '{ exit !($1 == "error_L2" && $2 > 0 && $2 < 0.1 * $4) }' <<< "$other" || status=1
rm -rf "$work/cmp-c"
solve -nx 16 -ny 8 -dt 0.1 -plane strain -out "$work/cmp-c" >> "$diag" 2>&1 || status=1
"${FREEFEM[@]}" edp/compare.edp -a "$work/cmp-c" -ref "$work/cmp-b" > "$work/cmp-c.out" 2>&1; code=$?
{ [ "$code" = 2 ] && grep -q "the runs differ in -plane" "$work/cmp-c.out"; } || { echo "a plane-strain run against a plane-stress one: exit $code"; cat "$work/cmp-c.out"; status=1; } >> "$diag"
report $status "edp/compare.edp: a run against itself gives 0, against a finer mesh a small error, against another body (-plane strain) refused" "$diag"

# ---- reproducibility: the same options give byte-identical outputs (timings aside)
diag="$work/repro.diag"; : > "$diag"; status=0
rm -rf "$work/repro" "$work/repro.first"
solve "${coarse[@]}" -out "$work/repro" > "$diag" 2>&1 && mv "$work/repro" "$work/repro.first" || status=1
solve "${coarse[@]}" -out "$work/repro" >> "$diag" 2>&1 || status=1
for f in "${OUTPUT_FILES[@]}"; do
  cmp -s <(strip_timing "$work/repro.first/$f") <(strip_timing "$work/repro/$f") || { echo "$f differs between two runs" >> "$diag"; status=1; }
done
report $status "two runs with the same options give identical outputs" "$diag"

# ---- figures for any run (plots)
# ./run.sh figures RUN_DIR ... and ./run.sh animate RUN_DIR (docs/figures.md) on a coarse paper
# run with a VTK time series and a coarse cylinder run (a curved Gamma3: arc length).
diag="$work/figures.diag"; : > "$diag"; status=0
paper="$work/figures-paper" cylinder="$work/figures-cylinder"
rm -rf "$paper" "$cylinder"                  # their figures/ would make the solves refuse the folders
solve "${coarse[@]}" -vtk 2 -out "$paper" >> "$diag" 2>&1 || { echo "the paper run failed" >> "$diag"; status=1; }
solve -scene cylinder -nx 12 -ny 12 -dt 0.1 -out "$cylinder" >> "$diag" 2>&1 || { echo "the cylinder run failed" >> "$diag"; status=1; }
./run.sh figures "$paper" "$cylinder" > "$work/figures.log" 2>> "$diag" || { echo "./run.sh figures failed" >> "$diag"; status=1; }
for file in "$paper"/figures/{contact_at_T,histories,deformed,zone_map,compare_contact}.png \
            "$cylinder"/figures/{contact_at_T,histories,deformed,zone_map}.png; do
  [ -s "$file" ] && grep -qxF "$file" "$work/figures.log" || { echo "$file: missing, empty or not listed" >> "$diag"; status=1; }
done
report $status "figures of any run: the paper scene and the cylinder (curved Gamma3), every figure and the comparison" "$diag"

diag="$work/animate.diag"; : > "$diag"; status=0
./run.sh animate "$paper" > "$work/animate.log" 2>> "$diag" || { echo "./run.sh animate failed" >> "$diag"; status=1; }
"$PYTHON" -c 'import sys; from PIL import Image
frames = Image.open(sys.argv[1]).n_frames
assert frames > 1, f"{frames} frame"' "$paper/figures/animation.gif" >> "$diag" 2>&1 || status=1
[ "$(stat -c %s "$paper/figures/animation.gif" 2>/dev/null || echo 0)" -lt 5000000 ] || { echo "animation.gif: 5 MB or more" >> "$diag"; status=1; }
report $status "animation: a GIF of more than one frame, under 5 MB" "$diag"

diag="$work/figures-refused.diag"; : > "$diag"; status=0
refused() { # refused EXIT REGEX COMMAND...: the command exits EXIT with one line matching REGEX on stderr
  local code="$1" regex="$2" rc=0; shift 2
  "$@" > /dev/null 2> "$work/refused.log" || rc=$?
  [ "$rc" = "$code" ] && [ "$(wc -l < "$work/refused.log")" = 1 ] && grep -Eq "$regex" "$work/refused.log" \
    || { echo "$*: exit $rc, expected $code and one line /$regex/:" >> "$diag"; cat "$work/refused.log" >> "$diag"; status=1; }
}
refused 2 "is not the folder of a finished run" ./run.sh figures "$work"
refused 2 "no such folder" ./run.sh figures "$work/no-such-run/"
refused 2 "has no vtk/ time series: run with -vtk N" ./run.sh animate "$cylinder"
refused 2 "no run folder 'myrun' and no figure named myrun \(figures: fig2 " ./run.sh figures myrun
report $status "figures and animate refuse a folder that is not a run, or a run without vtk/, in one line" "$diag"

# The safety of figures/ (docs/figures.md, "The figures/ folder"), on copies of the paper run.
figs=(plots/run_figures.py) anim=(plots/animate.py)
snapshot() { (cd "$1" 2>/dev/null && ls -A && md5sum -- * 2>/dev/null) || echo "no $1"; }   # the folder as it is
unchanged() { # unchanged FOLDER SNAPSHOT WHAT: the folder is as the snapshot says
  snapshot "$1" | cmp -s - "$2" || { echo "$3: $1 changed:" >> "$diag"; snapshot "$1" | diff "$2" - >> "$diag"; status=1; }
}
diag="$work/figures-safe.diag"; : > "$diag"; status=0
a="$work/figures-a" b="$work/figures-b"
rm -rf "$a" "$b"; cp -r "$paper" "$a"; cp -r "$paper" "$b"; rm -rf "$b/figures"
echo "mine" > "$a/figures/deformed.png"; echo "mine" > "$a/figures/animation.gif"
sed -i '/^deformed.png$/d; /^animation.gif$/d' "$a/figures/figures.list"
snapshot "$a/figures" > "$work/a.before"
refused 2 "figures-a/figures/deformed.png: not a figure this suite drew \(figures.list does not list it\)" "$PYTHON" "${figs[@]}" "$a"
refused 2 "figures-a/figures/animation.gif: not a figure this suite drew" "$PYTHON" "${anim[@]}" "$a"
unchanged "$a/figures" "$work/a.before" "a refused drawing"
rm "$a/figures/deformed.png" "$a/figures/animation.gif"
echo "notes.txt" >> "$a/figures/figures.list"                    # a name the tools never draw
"$PYTHON" "${anim[@]}" "$a" > /dev/null 2>> "$diag" || { echo "animate failed" >> "$diag"; status=1; }
grep -qx "notes.txt" "$a/figures/figures.list" && { echo "figures.list kept notes.txt" >> "$diag"; status=1; }
snapshot "$a/figures" > "$work/a.before"
{ awk '/^#/ || n++ < 3' "$paper/contact_nodes_history.txt"; echo "2 0.2 0"; } > "$b/contact_nodes_history.txt"
refused 2 "figures-b/contact_nodes_history.txt:[0-9]+: 3 values for the 13 columns" "$PYTHON" "${figs[@]}" "$a" "$b"
unchanged "$a/figures" "$work/a.before" "figures A B failing on B"
[ -e "$b/figures" ] && { echo "figures A B failing on B left $b/figures" >> "$diag"; status=1; }
middle="$(ls "$a"/vtk/fields_*.vtu | sed -n 3p)"
head -c 3000 "$paper/vtk/$(basename "$middle")" > "$middle"                             # a corrupt frame
refused 2 "$(basename "$middle"): not an XML file" "$PYTHON" "${anim[@]}" "$a"
unchanged "$a/figures" "$work/a.before" "a failing animate"
for list in "$paper/figures/figures.list" "$cylinder/figures/figures.list" "$a/figures/figures.list"; do
  tail -n +2 "$list" | grep -vxE 'contact_at_T.png|histories.png|deformed.png|zone_map.png|compare_contact.png|animation.gif|animation.mp4' \
    | sed "s|^|$list lists |" >> "$diag"
done
grep -q " lists " "$diag" && status=1
report $status "figures and animate: never over a file figures.list does not list; all or nothing (figures/ as before a failure); figures.list names only the figures drawn" "$diag"

# Corrupt inputs are refused in one line, not drawn.
diag="$work/figures-corrupt.diag"; : > "$diag"; status=0
corrupt() { # corrupt REGEX TOOL FILE AWK: a copy of the paper run with FILE passed through AWK is refused
  local regex="$1" tool="$2" file="$3" program="$4" run="$work/figures-corrupt"
  rm -rf "$run"; cp -r "$paper" "$run"; rm -rf "$run/figures"
  awk "$program" "$paper/$file" > "$run/$file"
  refused 2 "$regex" "$PYTHON" "plots/$tool.py" "$run"
  [ -e "$run/figures" ] && { echo "$file: $run/figures left behind" >> "$diag"; status=1; }
}
row='!/^#/ && !done { done = 1;'
corrupt "contact.txt:[0-9]+: normal_status = 3, not one of 0..2" run_figures contact.txt "$row \$7 = 3 } 1"
corrupt "contact.txt:[0-9]+: tangential_status = 2, not one of 0..1" run_figures contact.txt "$row \$8 = 2 } 1"
corrupt "contact.txt:[0-9]+: p_nu = nan is not a finite number" run_figures contact.txt "$row \$4 = \"nan\" } 1"
corrupt "contact_nodes_history.txt:[0-9]+: zone = 5, not one of 0..4" run_figures contact_nodes_history.txt "$row \$13 = 5 } 1"
corrupt "fields.txt:[0-9]+: von_mises = inf is not a finite number" run_figures fields.txt "$row \$7 = \"inf\" } 1"
corrupt "history.txt:[0-9]+: kinetic = nan is not a finite number" run_figures history.txt "$row \$5 = \"nan\" } 1"
corrupt "fields.pvd: the DataSet of fields_[0-9]+.vtu has timestep nan" animate vtk/fields.pvd '/timestep=/ && !done { done = 1; sub(/timestep="[^"]*"/, "timestep=\"nan\"") } 1'
corrupt "fields_[0-9]+.vtu: point data 'von_mises' holds nan" animate vtk/fields_000002.vtu 'found && !done { done = 1; $1 = "nan" } /Name="von_mises"/ { found = 1 } 1'
rm -f "$work/figures-corrupt/scene.scene"                                   # (a copy of the paper run)
refused 2 "missing .*/scene.scene: the run's law" "$PYTHON" plots/run_figures.py "$work/figures-corrupt"
report $status "figures and animate refuse corrupt inputs in one line (statuses, zones, nan or inf drawn, a pvd timestep, no scene.scene)" "$diag"

# A contact boundary in two pieces (tests/data/twofeet.geo: feet x 0-0.6 and 1.4-2): the
# curves break between them, no node's shading crosses the gap, the zone map leaves it blank.
diag="$work/figures-pieces.diag"; : > "$diag"; status=0
gmsh -2 -format msh22 -v 0 -setnumber h 0.2 tests/data/twofeet.geo -o "$work/twofeet.msh" > /dev/null 2>> "$diag" || status=1
"$PYTHON" - "$work/twofeet.msh" >> "$diag" 2>&1 <<'PY' || status=1
import sys
import numpy as np
import suite
mesh = suite.read_msh22(sys.argv[1])
x, y = mesh.xy[np.unique(mesh.lines[mesh.line_labels == 1])].T
order = np.random.default_rng(1).permutation(len(x))              # in no particular order
x, y = x[order], y[order]
pieces = suite.contact_pieces(mesh, x, y)
assert len(set(pieces)) == 2 and len(set(pieces[x < 1])) == 1 and len(set(pieces[x > 1])) == 1, pieces
s, = suite.along_gamma3(x, pieces)
gap = np.flatnonzero(np.isnan(s))
assert len(gap) == 1 and np.allclose([s[gap[0] - 1], s[gap[0] + 1]], [0.6, 1.4]), s
start, end = suite.node_cells(x, pieces)
assert not ((start < 1.4 - 1e-9) & (end > 0.6 + 1e-9)).any(), (start, end)
assert np.isclose(start.min(), 0) and np.isclose(end.max(), 2), (start, end)
edges, columns = suite.map_columns(x, pieces)
blank = np.flatnonzero(columns < 0)
assert len(blank) == 1 and np.allclose(edges[blank[0]:blank[0] + 2], [0.6, 1.4]), (edges, columns)
assert sorted(columns[columns >= 0]) == list(range(len(x))) and np.all(np.diff(edges) >= 0)
found = suite.stretches(x, [0] * len(x), pieces)
assert np.allclose([(a, b) for _, a, b, _ in found], [(0, 0.6), (1.4, 2)]), found
PY
report $status "a contact boundary in two pieces: curves broken, shading and zone map cells stop at the gap" "$diag"

# A 3D run (docs/figures.md, "The figures of a 3D run"): every figure of a small slab3d run, its
# comparison with the 2D paper run, and its animation (from contact_nodes_history.txt, no vtk/),
# each a PNG or a GIF; corrupt 3D inputs refused in one line, leaving no figures/.
diag="$work/figures-3d.diag"; : > "$diag"; status=0
slab="$work/figures-slab3d"
rm -rf "$slab"
solve -scene slab3d -nx 8 -ny 4 -nz 1 -dt 0.1 -out "$slab" >> "$diag" 2>&1 || { echo "the slab3d run failed" >> "$diag"; status=1; }
./run.sh figures "$slab" "$paper" > "$work/figures-3d.log" 2>> "$diag" || { echo "./run.sh figures (3D and 2D) failed" >> "$diag"; status=1; }
./run.sh animate "$slab" >> "$work/figures-3d.log" 2>> "$diag" || { echo "./run.sh animate (3D) failed" >> "$diag"; status=1; }
for file in "$slab"/figures/{contact_at_T,histories,deformed,zone_map,compare_contact}.png "$slab/figures/animation.gif"; do
  grep -qxF "$file" "$work/figures-3d.log" || { echo "$file: not listed" >> "$diag"; status=1; }
  "$PYTHON" -c 'import sys; from PIL import Image
image = Image.open(sys.argv[1]); kind = image.format; frames = getattr(image, "n_frames", 1); image.verify()
assert kind == sys.argv[1].rsplit(".", 1)[1].upper() and (kind == "PNG" or frames > 1), (kind, frames)' "$file" >> "$diag" 2>&1 \
    || { echo "$file: not a PNG, or a GIF of more than one frame" >> "$diag"; status=1; }
done
broken="$work/figures-slab3d-corrupt"
for case in "run_figures contact.txt 13 nan contact.txt:[0-9]+: v_tau2 = nan is not a finite number" \
            "run_figures fields.txt 9 inf fields.txt:[0-9]+: u_z = inf is not a finite number" \
            "animate contact_nodes_history.txt 14 5 contact_nodes_history.txt:[0-9]+: zone = 5, not one of 0..4"; do
  read -r tool file column value regex <<< "$case"
  rm -rf "$broken"; cp -r "$slab" "$broken"; rm -rf "$broken/figures"
  awk -v c="$column" -v v="$value" '!/^#/ && !done { done = 1; $c = v } 1' "$slab/$file" > "$broken/$file"
  refused 2 "$regex" "$PYTHON" "plots/$tool.py" "$broken"
  [ -e "$broken/figures" ] && { echo "$file: $broken/figures left behind" >> "$diag"; status=1; }
done
report $status "a 3D run: every figure, the comparison with a 2D run and the animation (PNG, GIF); corrupt 3D inputs refused" "$diag"
# ---- end figures

echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
