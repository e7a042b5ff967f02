#!/usr/bin/env bash
# lab.sh: run the commands of docs/lab.md as a student types them, then check the numbers
# the sheet states.
#   bash tests/lab.sh [LOG]      (from anywhere; tests/run_tests.sh runs it)
# Every ```sh block of docs/lab.md runs, in order, in one bash (-e, -o pipefail, as one
# student's shell: the sheet's variables and functions carry over), from the repository
# root, with TMPDIR a fresh temporary folder: the sheet's `export LAB=$(mktemp -d)` makes
# its folder there, and the whole folder is removed at the end. A command that fails stops
# the run with the number and the first line of its block. Blocks marked otherwise
# (```text, ```) are not run; an indented ```sh block, or one marked bash or shell, is
# refused, so that no command of the sheet goes untested. The output of the commands goes
# to LOG (default: the temporary folder's, removed). Exit 0 when every block ran and every
# check passed; otherwise one line per problem on stderr and exit 1.
set -u
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
sheet="$root/docs/lab.md"
tmp="$(mktemp -d)" || exit 1
trap 'rm -rf "$tmp"' EXIT
log="${1:-$tmp/lab.log}"
case "$log" in /*) ;; *) log="$PWD/$log" ;; esac
: > "$log" || exit 1

# The script: a prologue, then each block preceded by the assignment of its number and
# first line (shell-quoted), then a line that hands $LAB back.
cat > "$tmp/lab-script.sh" <<'EOF'
set -eo pipefail
lab_block=0 lab_first='(before the first block)'
trap 'lab_rc=$?; [ "$lab_rc" = 0 ] || echo "block $lab_block of docs/lab.md failed (exit $lab_rc): $lab_first" >&2' EXIT
EOF
awk -v q="'" '
  function quote(s) { gsub(q, q "\\" q q, s); return q s q }
  /^[ \t]+```[ \t]*(sh|bash|shell)[ \t]*$/ { print "lab.sh: docs/lab.md:" NR ": an indented ```sh block would not be run: unindent it" > "/dev/stderr"; bad = 1; next }
  !inside && /^```[ \t]*(bash|shell|console)[ \t]*$/ { print "lab.sh: docs/lab.md:" NR ": mark the commands to run ```sh (or ```text for the rest)" > "/dev/stderr"; bad = 1; next }
  !inside && /^```sh[ \t]*$/ { inside = 1; blocks++; first = ""; start = NR; next }
  inside && /^```/ { inside = 0; if (first == "") { print "lab.sh: docs/lab.md:" start ": an empty ```sh block" > "/dev/stderr"; bad = 1 }; next }
  inside {
    if (first == "" && $0 !~ /^[ \t]*(#|$)/) { first = $0; print "lab_block=" blocks " lab_first=" quote(first) }
    print; next
  }
  END {
    if (inside) { print "lab.sh: docs/lab.md:" start ": a ```sh block is not closed" > "/dev/stderr"; bad = 1 }
    if (!blocks) { print "lab.sh: docs/lab.md has no ```sh block" > "/dev/stderr"; bad = 1 }
    exit bad
  }' "$sheet" >> "$tmp/lab-script.sh" || exit 1
echo 'printf %s "$LAB" > "$LAB_PATH_FILE"' >> "$tmp/lab-script.sh"

cd "$root" || exit 1
# what git sees in the work tree (ignored files aside), to check that the sheet writes
# nothing into the repository
repository_state() { git status --porcelain --untracked-files=all 2>/dev/null || true; }
before="$(repository_state)"
export TMPDIR="$tmp" LAB_PATH_FILE="$tmp/lab.path"
unset LAB
if ! bash "$tmp/lab-script.sh" >> "$log" 2>&1 < /dev/null; then
  grep '^block [0-9]* of docs/lab.md failed' "$log" | tail -n 1 | sed 's/^/lab.sh: /' >&2
  tail -n 6 "$log" | grep -v '^block [0-9]* of docs/lab.md failed' | sed 's/^/  | /' >&2
  exit 1
fi
if [ "$(repository_state)" != "$before" ]; then
  echo "lab.sh: the sheet's commands changed the repository (git status):" >&2
  diff <(printf '%s\n' "$before") <(repository_state) | sed 's/^/  | /' >&2
  exit 1
fi
LAB="$(cat "$LAB_PATH_FILE")"
case "$LAB" in "$tmp"/?*) ;; *) echo "lab.sh: the sheet's LAB is '$LAB', not a fresh folder under TMPDIR (export LAB=\$(mktemp -d))" >&2; exit 1 ;; esac

# ---- the numbers docs/lab.md states, from the runs it made
problems=0
problem() { echo "lab.sh: docs/lab.md says $1" >&2; problems=$((problems + 1)); }
key() { awk -v k="$2" '$1 == k { print $2 }' "$LAB/$1/summary.txt" 2>/dev/null; }
# keys RUN KEY=VALUE ...: keys of RUN/summary.txt
keys() {
  local run="$1" pair; shift
  for pair in "$@"; do
    [ "$(key "$run" "${pair%%=*}")" = "${pair#*=}" ] || problem "${pair%%=*} ${pair#*=} for \$LAB/$run (the run has '$(key "$run" "${pair%%=*}")')"
  done
}
# column RUN FILE NAME LOW HIGH [ROWS]: every value of a named column (of the last ROWS rows) is in [LOW, HIGH]
column() {
  local run="$1" file="$2" name="$3" low="$4" high="$5" rows="${6:-0}"
  awk -v name="$name" -v low="$low" -v high="$high" -v rows="$rows" '
    /^#/ { header = $0; next }
    { line[++n] = $0 }
    END {
      m = split(substr(header, 3), column, " "); for (j = 1; j <= m; j++) if (column[j] == name) c = j
      if (!c || !n) exit 1
      for (i = (rows > 0 && rows < n ? n - rows + 1 : 1); i <= n; i++) { split(line[i], f, " "); if (!(f[c] + 0 >= low && f[c] + 0 <= high)) exit 1 }
    }' "$LAB/$run/$file" 2>/dev/null || problem "$name in [$low, $high] in \$LAB/$run/$file${6:+ (last $6 rows)}"
}
# named RUN FILE NAME,NAME,...: the named columns of RUN/FILE, one data row a line (exit 1 for a
# missing file or column)
named() {
  awk -v names="$3" '/^#/ { header = $0; next }
    !started { started = 1; n = split(names, want, ","); m = split(substr(header, 3), h, " ")
      for (i = 1; i <= n; i++) { pick[i] = 0; for (j = 1; j <= m; j++) if (h[j] == want[i]) pick[i] = j; if (!pick[i]) exit 1 } }
    { line = ""; for (i = 1; i <= n; i++) line = line (i > 1 ? " " : "") $pick[i]; print line }' "$LAB/$1/$2" 2>/dev/null
}
said() { grep -qF -- "$1" "$log" || problem "the output shows '$1'"; }
zones() { keys "$1" zone_free="$2" zone_damped_slip="$3" zone_damped_stick="$4" zone_bound_slip="$5" zone_bound_stick="$6"; }

# 1. the tour
zones free 33 0 0 0 0
column free contact.txt p_nu -1e-13 1e-13
column free contact.txt v_nu -10 0
column free contact.txt lambda_tau 0 0
zones damped 0 8 1 0 0
column damped contact.txt v_nu 0.01999999835 0.01999999845
column damped contact.txt p_nu 0.999999915 0.999999925
zones bound 0 0 0 8 1
column bound contact.txt lambda_nu 7.4999999 7.5000001
column bound contact.txt v_nu 0.04999999999 0.05000000001
column bound contact.txt p_nu 9.9999999 10.0000001
[ "$(named bound contact_history.txt t,zone_bound_slip | awk '$2 > 0 { printf "%g", $1; exit }')" = 0.25 ] || problem "the column's nodes go from damped to the bound at t = 0.25"
zones stick 0 0 9 0 0
column stick contact.txt friction_bound 0.39 0.42
column stick contact.txt v_tau -1e-14 1e-14
column stick contact.txt lambda_tau 0.315 0.325 1
column stick contact.txt friction_bound 0.415 0.425 1
zones paper 1 7 0 14 11
column paper contact.txt p_nu 0 10.3
# the zone map: no node at the bound at t = 0.2, the first ones at the right end at t = 0.25
[ "$(named paper contact_history.txt t,zone_bound_slip,zone_bound_stick,x_B \
      | awk '$1 == 0.2 || $1 == 0.25 { printf "%g %d %s; ", $1, $2 + $3, ($4 == "nan" ? "nan" : ($4 + 0 > 1.9 ? "right" : $4)) }')" = "0.2 0 nan; 0.25 2 right; " ] \
  || problem "the first nodes reach the bound at t = 0.25, at the right end"
column penalty contact.txt v_nu 0.050149849 0.050149851
column penalty contact.txt lambda_nu 7.49250 7.49252
keys penalty check_constraint=0 check_complementarity=0
# 2. penalty against multiplier
for row in "1e-2 5.000e-02" "1e-3 7.308e-03" "1e-4 7.659e-04" "1e-5 7.695e-05" "1e-6 7.699e-06" "1e-8 7.700e-08" "1e-10 7.700e-10"; do
  eps="${row% *}"
  grep -q "eps/eps-$eps  .* ${row#* }  " "$log" || problem "max|dv_nu| ${row#* } at eps = $eps"
done
zones eps/eps-1e-2 1 6 0 13 13
column eps/eps-1e-2 contact.txt v_nu 0.099 0.1 1
for eps in 1e-3 1e-4 1e-5 1e-6 1e-8 1e-10; do zones "eps/eps-$eps" 1 7 0 14 11; done
for run in paper eps/eps-1e-2 eps/eps-1e-3 eps/eps-1e-4 eps/eps-1e-5 eps/eps-1e-6 eps/eps-1e-8 eps/eps-1e-10; do
  n="$(key "$run" iterations_total)"; [ -n "$n" ] && [ "$n" -ge 36 ] && [ "$n" -le 39 ] || problem "36 to 39 iterations for \$LAB/$run (it has '$n')"
done
keys paper iterations_total=38
keys literal/eps-1e-4 iterations_total=39 zone_damped_slip=7 zone_bound_slip=14 zone_bound_stick=11
# the literal row at 1e-8 and 1e-10, with the safeguard and without it (its solve ran to exit 0,
# or the block would have stopped): the compliant row's zones and solution
for run in literal/eps-1e-8 literal/eps-1e-10 literal-off; do zones "$run" 1 7 0 14 11; done
keys eps/eps-1e-8 iterations_total=38 newton_fallbacks=1
keys eps/eps-1e-10 iterations_total=38 newton_fallbacks=1
keys literal/eps-1e-8 newton_fallbacks=1
keys literal/eps-1e-10 newton_fallbacks=1
# within RUN KEY LOW HIGH: KEY of RUN/summary.txt is in [LOW, HIGH]
within() {
  local n; n="$(key "$1" "$2")"
  [ -n "$n" ] && [ "$n" -ge "$3" ] && [ "$n" -le "$4" ] || problem "$2 in [$3, $4] for \$LAB/$1 (it has '$n')"
}
# the counts of the literal row are decided by round-off (which solves from scratch stop above
# the tolerance, which low-rank solves are refined): the sheet states ranges. At most one
# correction a step, in the steps whose solve from scratch stops above the tolerance: five at
# 1e-10 (43 measured, with -O2 and with -O2 -march=native -ffp-contract=fast), at 1e-8 a subset
# of those, the residual there being smaller, like 1/eps (39 and 40 measured)
within literal/eps-1e-8 iterations_total 38 43
within literal/eps-1e-10 iterations_total 40 46
# "some twenty" refined low-rank solves for the literal row (22 to 27 measured), "none or almost
# none" for the compliant row (0 measured)
for run in literal/eps-1e-8 literal/eps-1e-10; do within "$run" newton_refinements 10 40; done
for run in eps/eps-1e-8 eps/eps-1e-10; do within "$run" newton_refinements 0 3; done
# tables.py: the literal runs at 1e-10 within round-off of the compliant one (about 1e-14
# measured; the sheet says "about 1e-14, far below what the tolerance allows": checked below 1e-12)
for run in literal/eps-1e-10 literal-off; do
  awk -v run="/$run" 'NF == 9 && substr($1, length($1) - length(run) + 1) == run {
       n++; if (!($3 == 7 && $4 == 14 && $5 == 11 && $8 + 0 < 1e-12 && $9 + 0 < 1e-12)) bad = 1 }
     END { exit bad || n != 1 }' "$log" \
    || problem "tables.py finds \$LAB/$run within round-off (below 1e-12) of \$LAB/eps/eps-1e-10, zones 7 14 11"
done
# the log of step 7 of the literal row at 1e-10 (the sheet's only 'step 7/7'): iteration 2, with
# the pieces iteration 1 found, at the round-off of a solve from scratch, "a few 1e-7" (3.8e-7 to
# 5.2e-7 measured; checked in [1e-9, 1e-5], as its digits are round-off's), far above the
# tolerance; iteration 3, the correction with the same pieces, at round-off (about 1.5e-15
# measured; "below 1e-12")
awk '/^  iteration 0 / { split("", line) }
     /^  iteration [0-9]+: / { i = $2; sub(/:/, "", i); line[i] = $0 }
     /^step 7\/7 \(t = 0\.35\): / {
       seen++
       if ($6 == "3" && line[2] ~ /; changed: none$/ && line[3] ~ /; changed: none$/) {
         r2 = line[2]; sub(/.*: residual /, "", r2); sub(/;.*/, "", r2)
         r3 = line[3]; sub(/.*: residual /, "", r3); sub(/;.*/, "", r3)
         if (r2 + 0 >= 1e-9 && r2 + 0 <= 1e-5 && r3 + 0 < 1e-12) ok = 1
       } }
     END { exit !(seen == 1 && ok) }' "$log" \
  || problem "step 7 of \$LAB/literal-log takes 3 iterations: iteration 2 (changed: none) at a residual of a few 1e-7 (in [1e-9, 1e-5]), iteration 3 (changed: none) below 1e-12"
# 3. Newton against the fixed point
[ "$(named solvers/newton history.txt iterations | tr '\n' ' ')" = "2 2 " ] || problem "Newton takes 2 then 2 iterations"
[ "$(named solvers/fixedpoint history.txt iterations | tr '\n' ' ')" = "15 15 " ] || problem "the fixed point takes 15 and 15 iterations"
keys solvers/fixedpoint-T1 iterations_total=323 iterations_max=17 fixed_point_sweeps=646
awk 'NF == 9 && $1 ~ /\/solvers\/fixedpoint-T1/ { n++; if (!($8 + 0 < 1e-11)) bad = 1 } END { exit bad || n != 1 }' "$log" \
  || problem "the fixed point agrees with Newton to about 1e-12"
said "  iteration 0 (the previous step's multipliers, this step's load): residual 1.024e-01; slots: damped 32, stick 9, slip 22"
said "  iteration 1: residual 5.739e-02 (the Newton iterate did not lower the merit: one fixed-point iteration instead); changed: stick +16, slip -16"
# said_small PREFIX SUFFIX BOUND: a line PREFIX R SUFFIX with R below BOUND (a residual at round-off)
said_small() {
  awk -v prefix="$1" -v suffix="$2" -v bound="$3" '
    index($0, prefix) == 1 && substr($0, length($0) - length(suffix) + 1) == suffix {
      r = substr($0, length(prefix) + 1, length($0) - length(prefix) - length(suffix)); if (r + 0 < bound + 0) found = 1 }
    END { exit !found }' "$log" || problem "the output shows '$1R$2' with R below $3"
}
said_small "  iteration 2: residual " "; changed: none" 1e-14
said "  iteration 0 (the previous step's multipliers, this step's load): residual 4.485e-01; slots: damped 15, bound 17, stick 16, slip 15"
said "  iteration 2: residual 1.018e-02; changed: damped +1, bound -1"
said "step 6/8 (t = 0.3): 3 iterations"
said "  iteration 2: residual 5.218e-04; changed: none"
said "  iteration 3: residual 1.199e-07; changed: none"
said_small "  iteration 4: residual " "; changed: none" 1e-12
# 4. the exercises
# factorization counts are decided by round-off: "a few" for the paper's law; the power law
# changes its Newton matrix at every iteration, so factorizations and low-rank corrections
# add up to at least its iterations (which of the two a change gets is round-off's: 67 and 2
# at 1e-12 here, 56 and 13 with Prescott BLAS kernels), most of them factorizations
for tol in 1e-6 1e-10 1e-12; do
  keys "ex1/linear/tol-$tol" iterations_total=38
  n="$(key "ex1/linear/tol-$tol" newton_factorizations)"; [ -n "$n" ] && [ "$n" -ge 1 ] && [ "$n" -le 5 ] || problem "a few factorizations (1 to 5) for \$LAB/ex1/linear/tol-$tol (it has '$n')"
done
for pair in 1e-6=53 1e-10=66 1e-12=69; do
  run="ex1/power/tol-${pair%=*}"; keys "$run" iterations_total="${pair#*=}"
  n="$(key "$run" newton_factorizations)"; c="$(key "$run" newton_low_rank_corrections)"
  [ -n "$n" ] && [ -n "$c" ] && [ $((n + c)) -ge "${pair#*=}" ] && [ $((2 * n)) -gt "${pair#*=}" ] \
    || problem "newton_factorizations + newton_low_rank_corrections at least the ${pair#*=} iterations, most of them factorizations, for \$LAB/$run (it has '$n' and '$c')"
done
zones ex2/load-2.5 1 17 15 0 0
zones ex2/load-10 1 7 0 14 11
zones ex2/load-40 1 3 0 27 2
column ex2/load-2.5 contact_history.txt normal_force 3.28 3.29 1
[ "$(named ex2/load-2.5 contact_history.txt x_B | tail -n 1)" = nan ] || problem "x_B is nan at load 2.5"
column ex2/load-10 contact_history.txt normal_force 13.85 13.86 1
column ex2/load-40 contact_history.txt normal_force 60.50 60.51 1
grep -q 'ex3/dt-0.05 - dt-0.025 .* 1\.20$' "$log" && grep -q 'ex3/dt-0.025 - dt-0.0125 .* 1\.12$' "$log" || problem "the orders 1.20 then 1.12"
for dt in 0.1 0.05 0.025 0.0125; do zones "ex3/dt-$dt" 1 7 0 14 11; done
# the sweeps: every value ran, and each row of sweep.txt is its run's own (tests/check_sweep.py)
for sweep in "eps eps 1e-2,1e-3,1e-4,1e-5,1e-6,1e-8,1e-10" "literal eps 1e-4,1e-8,1e-10" "ex1/linear tol 1e-6,1e-10,1e-12" \
             "ex1/power tol 1e-6,1e-10,1e-12" "ex2 load 2.5,10,40" "ex3 dt 0.1,0.05,0.025,0.0125"; do
  set -- $sweep
  /usr/bin/python3 "$root/tests/check_sweep.py" "$LAB/$1" "$2" "$3" >&2 || problem "a row per value of -$2 ($3) in \$LAB/$1/sweep.txt, each its run's"
done
# 5. seeing a run
[ "$(ls "$LAB/see/vtk" 2>/dev/null | grep -c '^fields_[0-9]*\.vtu$')" = 11 ] || problem "11 frames in \$LAB/see/vtk"
[ -s "$LAB/see/figures/animation.gif" ] || problem "\$LAB/see/figures/animation.gif"
named see fields.txt u_x,u_y | awk '{ u = sqrt($1 * $1 + $2 * $2); if (u > max) max = u } END { exit !(max > 0.14 && max < 0.145) }' \
  || problem "the displacements reach 0.14 m in \$LAB/see"
for file in paper/figures/contact_at_T.png paper/figures/zone_map.png eps/eps-1e-2/figures/compare_contact.png; do
  [ -s "$LAB/$file" ] || problem "\$LAB/$file"
done
# 6. three dimensions
zones slide 0 0 0 25 0
named slide contact.txt lambda_tau,lambda_tau2,v_tau,v_tau2 \
  | awk '{ n++; lt = sqrt($1^2 + $2^2); vt = sqrt($3^2 + $4^2); if (lt < 1 - 1e-9 || lt > 1 + 1e-9 || vt < 0.599 || vt > 0.601) bad = 1 }
         END { exit bad || n != 25 }' || problem "|lambda_tau| = 1 and |v_tau| = 0.6 on the 25 nodes of \$LAB/slide"
said "friction stress (0.7071, 0.7071), length 1.000000"
said "3D: normal force per unit depth 13.8350, x_B 0.500, x_C 1.375"
said "2D: normal force 13.8320, x_B 0.500, x_C 1.500"

[ "$problems" = 0 ]
