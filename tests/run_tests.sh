#!/usr/bin/env bash
# run_tests.sh: the test harness (run it as ./run.sh test, which sets the environment).
#   ./run.sh test                 every test
#   ./run.sh test --bless CASE    run the regression case CASE, check its physics and, only
#                                 if that passes, copy its outputs to tests/ref/CASE/
#                                 (review the diff with git before committing it)
#   ./run.sh test --suite NAME    only tests/suites/NAME.sh (after a full run: the suites read
#                                 the regression cases' outputs in tests/work)
# Prints one "ok N - name" / "not ok N - name" line per test, diagnostics on "#" lines,
# and ends with "N passed, N failed". Exit status 1 if any test failed.
# Environment: TEST_JOBS=N runs N jobs (regression cases, suites) at a time (default 2; the
# output does not depend on it); TEST_TIMES=1 prints each job's wall and processor seconds.
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
# this checkout's solves on a process's command line (its edp/solve.edp by absolute path, as
# run.sh starts it), as an extended regular expression: the tests that look for processes
# left running must not see another checkout's
root_solve_pattern="(^| )$(printf '%s' "$root" | sed 's/[][\.*^$+?(){}|]/\\&/g')/edp/solve\.edp "
cd "$root" || exit 1
PYTHON="${PYTHON:-/usr/bin/python3}"
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
# which one a step uses depends on a round-off residual test, not on the physics), nor the
# versions that made the run (suite_version changes with every commit).
numeric_view() {
  grep -v -e '^time_' -e '^check_' -e '^newton_factorizations ' -e '^newton_low_rank_corrections ' -e '^newton_refinements ' \
    -E -e '^(# )?(suite|freefem|gmsh)_version ' "$1"
}

# compare_numeric MODE REF NEW ABS REL [EXCLUDED FIELD...]: numdiff (MODE -q quiet or
# -S statistics) with a per-column absolute floor ABS * the column's scale in REF (ABS alone
# for an all-zero column). The scale of a column is its largest |value|, or that of its
# family, the columns of one unit named in the header (the last comment line before the
# data): velocities, stresses, energies, forces, displacements. A column that is zero up to
# the solver's tolerance (lambda_nu of a run that never reaches the bound, the contact work
# in free flight) is then compared at the scale of its unit, not at that of its own noise;
# velocities at least at g, stresses at least at p(g) (the largest of the reference's nodes:
# its contact.txt's columns g and force_scale).
compare_numeric() {
  local mode="$1" ref="$2" new="$3" abs="$4" rel="$5"; shift 5
  local args=() field floor scales
  # the law's scales, from the reference's contact.txt: the largest g and p(g) of its nodes
  scales="$(awk '/^#/ { header = $0; next }
    !n { n = split(substr(header, 3), h); for (i = 1; i <= n; i++) column[h[i]] = i }
    column["g"] && $column["g"] > g { g = $column["g"] } column["force_scale"] && $column["force_scale"] > s { s = $column["force_scale"] }
    END { print g + 0, s + 0 }' "$(dirname "$ref")/contact.txt" 2> /dev/null)"
  while read -r field floor; do args+=(-a "$floor:$field"); done < <(
    awk -v abs="$abs" -v gScale="${scales% *}" -v stressScale="${scales#* }" '
      BEGIN { split("v_nu v_tau v_x v_y v_tau2 v_z", a); for (k in a) fam[a[k]] = "velocity"
              split("p_nu lambda_nu lambda_tau friction_bound lambda_tau2", a); for (k in a) fam[a[k]] = "stress"
              split("kinetic elastic numerical_dissipation viscous_dissipation contact_dissipation external_work kinetic_jump elastic_jump", a)
              for (k in a) fam[a[k]] = "energy"
              split("normal_force tangential_force tangential_force2", a); for (k in a) fam[a[k]] = "force"
              split("u_x u_y u_z", a); for (k in a) fam[a[k]] = "displacement" }
      /^#/ { if (!data) { header = $0 }; next }
      { if (!data) { data = 1; nh = split(header, h); for (i = 2; i <= nh; i++) family[i - 1] = fam[h[i]] }
        for (i = 1; i <= NF; i++) if ($i + 0 == $i) { v = $i < 0 ? -$i : $i; if (v == v && v < 1e300 && v > m[i]) m[i] = v; if (i > n) n = i } }
      END { fm["velocity"] = gScale + 0; fm["stress"] = stressScale + 0      # at least the scales of the law: g and p(g)
            for (i = 1; i <= n; i++) if (family[i] != "" && m[i] > fm[family[i]]) fm[family[i]] = m[i]
            for (i = 1; i <= n; i++) { s = family[i] != "" ? fm[family[i]] : m[i]; printf "%d %.3e\n", i, (s > 0 ? abs * s : abs) } }' "$ref")
  for field in "$@"; do args+=(-X "1:$field" -X "2:$field"); done
  numdiff "$mode" -r "$rel" "${args[@]}" "$ref" "$new"
}

# same_outputs RUN AGAIN: the output files of RUN and of AGAIN (RUN repeated from its scene.scene
# and mesh.msh) are identical but for the lines that name the runs' own files (scene, out, mesh,
# mesh_source, scene_file; nx, ny, nz, which read none with -mesh) and the timings; prints the
# files that differ
# (the error estimates too: a run repeated with -mesh has the coarsened mesh as its companion,
# not the structured one with half the cells; docs/design.md, "Error estimates")
own_files() { grep -v -E '^(# )?(scene|out|mesh|mesh_source|scene_file|nx|ny|nz|time_[a-z_]*|error_estimate_[a-zA-Z0-9_]*) ' "$1"; }
same_outputs() {
  local f status=0
  for f in "${OUTPUT_FILES[@]}"; do cmp -s <(own_files "$1/$f") <(own_files "$2/$f") || { echo "$f"; status=1; }; done
  return $status
}

# field_numbers FILE NAME...: the numbers of the named columns of FILE's header (the last
# comment line before its data)
field_numbers() {
  local file="$1"; shift
  awk -v names="$*" '/^#/ { header = $0; next }
    { m = split(substr(header, 3), h, " "); n = split(names, want, " ")
      for (i = 1; i <= n; i++) for (j = 1; j <= m; j++) if (h[j] == want[i]) printf "%s%d", (found++ ? " " : ""), j
      print ""; exit }' "$file"
}

# scene_agreement NAME OPTIONS...: the run tests/work/NAME (made with OPTIONS when it is not
# there: a regression case's is used as it is) against the script Newton and the full-system
# Newton of the same OPTIONS, to 1e-9 (suites 60 and 70)
scene_agreement() {
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
# --suite NAME: only the topic suite tests/suites/NAME.sh, on the outputs of the regression
# cases an earlier full run left in tests/work (a developer's shortcut; ./run.sh test runs all)
only=""
if [ "${1:-}" = "--suite" ] && [ $# = 2 ] && [ -f "tests/suites/$2.sh" ]; then only="$2"; shift 2; fi
[ $# -eq 0 ] || { echo "usage: run_tests.sh [--bless CASE | --suite NAME]" >&2; exit 2; }
max_jobs="${TEST_JOBS:-2}"                             # (checked before anything is removed)
[[ "$max_jobs" =~ ^[0-9]{1,3}$ ]] && max_jobs=$((10#$max_jobs)) && [ "$max_jobs" -ge 1 ] && [ "$max_jobs" -le 64 ] \
  || { echo "run_tests.sh: TEST_JOBS must be a whole number from 1 to 64, not '$max_jobs'" >&2; exit 2; }
[ -n "$only" ] || find "$work" -mindepth 1 -delete      # the harness's own folder: start clean

echo "# FreeFem++: $(command -v FreeFem++-nw), gmsh $(gmsh --version 2>&1 | head -1), numdiff $(numdiff --version 2>/dev/null | head -1 | awk '{print $2}')"

coarse_options=(-nx 8 -ny 4 -dt 0.1)
# expect_failure NAME CODE REGEX OPTIONS...
expect_failure() {
  local name="$1" code="$2" regex="$3"; shift 3
  local out="$work/fail-$job-$count" diag="$work/fail-$job.diag"
  rm -rf "$out"
  if printf '%s\n' "$@" | grep -qx -- -out; then solve "$@" > "$diag" 2>&1; else solve -out "$out" "$@" > "$diag" 2>&1; fi
  local rc=$?
  local status=0
  if [ "$rc" != "$code" ]; then echo "exit code $rc, expected $code" >> "$diag"; status=1; fi
  if ! grep -Eq "$regex" "$diag"; then echo "message does not match /$regex/" >> "$diag"; status=1; fi
  if [ -e "$out" ] || compgen -G "$out.partial*" > /dev/null; then echo "results were written in $out" >> "$diag"; status=1; fi
  report $status "refused: $name" "$diag"
}
coarse=("${coarse_options[@]}")
# case_tests NAME: the regression case NAME, two tests: it runs and passes its physics checks,
# then its outputs match its blessed reference (numdiff)
case_tests() {
  local name="$1" diag="$work/$1.diag" status=0 f ref excluded
  : > "$diag"
  if ! run_case "$name"; then status=1; cat "$work/$name.log" > "$diag"; fi
  report $status "$name: runs and passes the physics checks" "$diag"
  : > "$diag"; status=0
  for f in "${OUTPUT_FILES[@]}"; do
    ref="tests/ref/$name/$f"
    if [ ! -f "$ref" ]; then
      echo "missing reference $ref (create it with ./run.sh test --bless $name)" >> "$diag"; status=1; continue
    fi
    if [ ! -f "$work/$name/$f" ]; then echo "no output $work/$name/$f" >> "$diag"; status=1; continue; fi
    # the run's file laid out as the reference, by column and key name (a new column is not
    # compared, a missing one fails)
    numeric_view "$work/$name/$f" > "$work/$name.$f.new"
    if ! "$PYTHON" tests/ref_view.py "$ref" "$work/$name.$f.new" > "$work/$name.$f.cmp" 2> "$work/$name.$f.view"; then
      status=1; cat "$work/$name.$f.view" >> "$diag"; continue
    fi
    excluded=()
    [ "$f" = history.txt ] && read -r -a excluded < <(field_numbers "$ref" residual energy_residual)
    if ! compare_numeric -q "$ref" "$work/$name.$f.cmp" "${case_abs[$name]}" "${case_rel[$name]}" "${excluded[@]}" > /dev/null 2>&1; then
      status=1
      echo "$f differs from $ref (abs ${case_abs[$name]} x column scale, rel ${case_rel[$name]}); first differences:" >> "$diag"
      compare_numeric -S "$ref" "$work/$name.$f.cmp" "${case_abs[$name]}" "${case_rel[$name]}" "${excluded[@]}" 2>&1 | head -12 >> "$diag"
    fi
  done
  report $status "$name: matches tests/ref/$name" "$diag"
}

# ---- the jobs: each regression case (physics, then numdiff against the blessed reference),
# then each topic suite, in the order of their names (tests/suites/NN-*.sh, sourced: they use
# the variables and functions above). The suites start once every case has ended: they read
# the cases' outputs in tests/work. TEST_JOBS jobs run at a time (default 2, the cores of the
# machine the suite is measured on; 1: one after the other), each in a subshell of its own,
# its output held in tests/work/.jobs and printed once the jobs before it have been, its tests
# numbered on from theirs: the output is the same as one job at a time. A job writes files of
# its own in tests/work (named by the suite, or by the job: expect_failure's). TEST_TIMES=1:
# each job's wall time and processor time (its processes', user and system) on a '#' line
# after its output.
jobs_dir="$work/.jobs"
job_names=()
start_job() { # start_job INDEX: job INDEX in the background: INDEX.out, INDEX.err, then INDEX.tally, INDEX.end
  local index="$1"
  {
    (
      job="${job_names[$index]}" count=0 passed=0 failed=0
      start="$(date +%s.%N)"
      # shellcheck disable=SC1090
      case "$job" in
        [0-9]*) source "tests/suites/$job.sh" ;;
        *) case_tests "$job" ;;
      esac
      # the wall time and the processor time of the job and its processes (times: the last line)
      times > "$jobs_dir/$index.times"              # (not in a $(...): a subshell of its own)
      echo "$count $passed $failed $(awk -v a="$start" -v b="$(date +%s.%N)" '{ for (i = 1; i <= NF; i++) { split($i, ms, /[ms]/); c += 60 * ms[1] + ms[2] } }
        END { printf "%.1f %.1f", b - a, c }' "$jobs_dir/$index.times")" > "$jobs_dir/$index.tally"
    ) > "$jobs_dir/$index.out" 2> "$jobs_dir/$index.err" < /dev/null
    echo "$?" > "$jobs_dir/$index.end"
  } &
}
print_job() { # print_job INDEX: its output, its tests numbered on from $count, counted
  local index="$1" n p f seconds cpu
  awk -v base="$count" '/^(not )?ok [0-9]+ - / { match($0, /[0-9]+/); $0 = substr($0, 1, RSTART - 1) (base + substr($0, RSTART, RLENGTH)) substr($0, RSTART + RLENGTH) } { print }' \
    "$jobs_dir/$index.out"
  cat "$jobs_dir/$index.err" >&2
  if [ -f "$jobs_dir/$index.tally" ] && read -r n p f seconds cpu < "$jobs_dir/$index.tally"; then
    count=$((count + n)); passed=$((passed + p)); failed=$((failed + f))
    [ "${TEST_TIMES:-}" != 1 ] || echo "# time: ${job_names[$index]} $seconds s, processor $cpu s"
  else                                      # the job stopped before its end (exit, set -u)
    count=$((count + $(grep -cE '^(not )?ok [0-9]+ - ' "$jobs_dir/$index.out")))
    passed=$((passed + $(grep -cE '^ok [0-9]+ - ' "$jobs_dir/$index.out")))
    failed=$((failed + $(grep -cE '^not ok [0-9]+ - ' "$jobs_dir/$index.out")))
    echo "job ${job_names[$index]} stopped before its end, exit status $(cat "$jobs_dir/$index.end")" > "$jobs_dir/$index.stopped"
    report 1 "${job_names[$index]}: ran to its end" "$jobs_dir/$index.stopped"
  fi
}
run_jobs() { # run_jobs NAME...: these jobs, max_jobs at a time, printed in their order
  local first="${#job_names[@]}" next shown running=0 waited i
  job_names+=("$@")
  next=$first; shown=$first
  while [ "$shown" -lt "${#job_names[@]}" ]; do
    while [ "$running" -lt "$max_jobs" ] && [ "$next" -lt "${#job_names[@]}" ]; do
      start_job "$next"; next=$((next + 1)); running=$((running + 1))
    done
    # a job whose wrapper was killed never writes INDEX.end: once no job is left to wait for
    # (wait -n: 127), every job started without one counts as stopped
    waited=0; wait -n || waited=$?
    if [ "$waited" = 127 ]; then
      for ((i = shown; i < next; i++)); do [ -e "$jobs_dir/$i.end" ] || echo "killed" > "$jobs_dir/$i.end"; done
      running=0
    else
      running=$((running - 1))
    fi
    while [ "$shown" -lt "$next" ] && [ -e "$jobs_dir/$shown.end" ]; do print_job "$shown"; shown=$((shown + 1)); done
  done
}
rm -rf "$jobs_dir"; mkdir -p "$jobs_dir"
[ -n "$only" ] || run_jobs "${case_names[@]}"
suites=()
for suite in tests/suites/[0-9]*.sh; do
  suite="$(basename "$suite" .sh)"
  [ -z "$only" ] || [ "$suite" = "$only" ] && suites+=("$suite")
done
run_jobs "${suites[@]}"

echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
