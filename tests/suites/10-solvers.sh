# The solvers against each other: the full-system Newton, the fixed point, loose tolerances, the kernel, the law defined once, the safeguards.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
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
# plots/stability.sh runs (other scenes, r, meshes, time steps), for both solvers; where
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
grep -v '^damping ' edp/scenes/paper.scene > "$work/steep.scene"; echo "damping table 0 0 0.01 0 0.02 5 0.05 5 0.06 1000" >> "$work/steep.scene"
rc=0; solve -scene "$work/steep.scene" -T 0.5 -solver fixedpoint -out "$work/steep" > "$work/steep.log" 2>&1 || rc=$?
[ "$rc" = 4 ] && [ ! -e "$work/steep" ] && grep -Eq "^error: step 1 \(t = 0.01\): the contact solver did not converge after [0-9]+ iterations \(the fixed point stalled: .*\), residual [0-9.e+-]+ > tol 1e-10; no results written" "$work/steep.log" \
  && [ "$(sed -n 's/.*after \([0-9]*\) iterations.*/\1/p' "$work/steep.log")" -lt 500 ] \
  || { echo "steep table, fixed point: exit $rc" >> "$diag"; cat "$work/steep.log" >> "$diag"; status=1; }
# Newton gets past the step where the sweeps stall: its first two steps (later steps of this table,
# whose slope reaches 1e5, stall Newton too, at a step and residual round-off decides: step 3 at
# 2e-10 with fused multiply-adds; docs/stability.md)
solve -scene "$work/steep.scene" -T 0.02 -out "$work/steep-newton" >> "$diag" 2>&1 \
  && "$PYTHON" tests/check_results.py "$work/steep-newton" >> "$diag" 2>&1 \
  || { echo "steep table, Newton: did not converge" >> "$diag"; status=1; }
# a large penalty eps: eps times the round-off of lambda_nu is no violation of the penalty law
solve -scene paper -nx 16 -ny 8 -T 0.2 -problem penalty -eps 1e6 -out "$work/eps1e6" >> "$diag" 2>&1 \
  && "$PYTHON" tests/check_results.py "$work/eps1e6" >> "$diag" 2>&1 || { echo "-eps 1e6 failed" >> "$diag"; status=1; }
report $status "fixed point at -tol 1e-4: the paper's zones (statuses settled); a stalled fixed point stops at once with exit 4 and says so (Newton converges there); -eps 1e6 passes the penalty check" "$diag"

# ---- the compiled kernel (edp/plugins/kernel/): its linear algebra against FreeFEM's
# UMFPACK, its instances, and its Newton against the script Newton of edp/lib/solvers.idp
diag="$work/kernel.diag"; : > "$diag"
if "${FREEFEM[@]}" tests/kernel_check.edp > "$diag" 2>&1 && grep -q "kernel_check: all checks passed" "$diag"; then
  report 0 "kernel: solve, Delassus matrix, both halves of the back-substitution = UMFPACK, products and the record of a step = FreeFEM, to 1e-12; a second instance solves alone, the first unchanged"
else
  report 1 "kernel: solve, Delassus matrix, both halves of the back-substitution = UMFPACK, products and the record of a step = FreeFEM, to 1e-12; a second instance solves alone, the first unchanged" "$diag"
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
12|contactKernelBoundTable: as many g as points of the grid
13|contactKernelNodes: both a bound profile and a bound table are set
14|contactKernelBoundTable: the axes are two of x, y, z
10|contactKernelSolve without a successful contactKernelFactorize
11|contactKernelNewtonStep without a successful contactKernelFactorize
5|contactKernelRecord: call contactKernelRecordStart
6|contactKernelParameter: unknown parameter 'gravity'
7|contactKernelSolve without a successful contactKernelFactorize
8|contactKernelColumn: the table nodal has no column 'v_normal'
9|contactKernelDelete: instance 0 is the current one
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
# ---- the law is defined once (edp/plugins/contactlaw.hpp). One copy of the suite whose
# contactlaw.hpp alone is changed, built once (its runtools, whose sources are the suite's, is
# the suite's build, copied): the walkthrough's Exercise 1 (p(r) = c_nu r_+^2 in the linear
# family, by the page's sed), four faults each switched on by LAW_FAULT=K, and Exercise 1b's
# damping family (its edit taken from the page). Every run of the copy starts from its folder:
# its freefem++.pref loads its own kernel.
other="$work/otherlaw"
law="$other/edp/plugins/contactlaw.hpp"
rm -rf "$other" && mkdir -p "$other/meshes" && cp -r edp run.sh freefem++.pref "$other/" && cp meshes/*.geo "$other/meshes/"
rm -rf "$other/edp/plugins/build" && mkdir -p "$other/edp/plugins/build" \
  && cp edp/plugins/build/runtools.so edp/plugins/build/runtools.so.cksum "$other/edp/plugins/build/"
sed -i -e 's|^  return P.cnu \* r; *// Linear$|  return P.cnu * r * r;   // Linear|' \
       -e 's|^  return P.cnu; *// Linear$|  return 2 * P.cnu * r;   // Linear|' "$law"
[ "$(diff edp/plugins/contactlaw.hpp "$law" | grep -c '^>')" = 2 ] \
  && echo "the quadratic law written into $law" > "$work/otherlaw-edit.diag" \
  || echo "could not write the quadratic law into $law (the linear case of dampedResponse, dampedResponseSlope)" > "$work/otherlaw-edit.diag"
# the faults: p' that does not match p (Exercise 1 with the slope forgotten), a zone function
# out of 0..4, a negative friction bound, a bound g that leaves the range of its profile's
# points between them
"$PYTHON" - "$law" > "$work/otherlaw-faults.diag" 2>&1 <<'PY'
import sys
p = sys.argv[1]
s = open(p).read()
for old, new in (
        ("#include <vector>\n", "#include <vector>\n#include <cstdlib>\n"
         "inline bool lawFault(int k) { const char *f = std::getenv(\"LAW_FAULT\"); return f && std::atoi(f) == k; }\n"),
        ("  return 2 * P.cnu * r;   ", "  return lawFault(1) ? P.cnu : 2 * P.cnu * r;   "),
        ("return normal > 0 ? 2 * normal - tangential : 0;",
         "return normal > 0 ? (lawFault(2) ? 2 * normal + tangential : 2 * normal - tangential) : 0;"),
        ("{ return P.mu * dampedResponse(P, vn); }", "{ return (lawFault(3) ? -1 : 1) * P.mu * dampedResponse(P, vn); }"),
        ("  return keptBetween(P.profileG[a0], P.profileG[a1], s);",
         "  return keptBetween(P.profileG[a0], P.profileG[a1], s) * (lawFault(4) ? 1 + 4 * s * (1 - s) : 1);")):
    assert old in s, "not found: " + old
    s = s.replace(old, new, 1)
open(p, "w").write(s)
PY
law_faults=$?
"$PYTHON" - docs/walkthrough.md "$law" > "$work/family-edit.diag" 2>&1 <<'PY' || echo "could not apply the walkthrough's edit" >> "$work/family-edit.diag"
# the family's functions before struct DampingFamily, its row after the table family's row:
# the code blocks after the page's markers "exercise 1b: the functions" and "... the row"
import sys
doc, path = open(sys.argv[1]).read(), sys.argv[2]
law = open(path).read()
def block(marker):
    start = doc.index("```cpp\n", doc.index("<!-- exercise 1b: " + marker + " -->")) + len("```cpp\n")
    return doc[start:doc.index("```", start)]
anchor, row = "struct DampingFamily {", '  {"table", '
assert law.count(anchor) == 1 and law.count(row) == 1, "contactlaw.hpp has not one struct DampingFamily and one table row"
law = law.replace(anchor, block("the functions") + "\n" + anchor)
at = law.index("\n", law.index(row)) + 1
open(path, "w").write(law[:at] + block("the row") + law[at:])
PY
family_edit=$?

# Exercise 1: the new law gives the same new results with the default compiled Newton and its
# script view, the same as the scene key damping power 1000 2 with the suite as it is, the
# outputs follow the new law, and they differ from the paper law's
diag="$work/otherlaw.diag"; cat "$work/otherlaw-edit.diag" > "$diag"; status=0
grep -q '^could not' "$diag" && status=1
otherlaw_options=(-nx 16 -ny 8 -dt 0.05 -cnu 1000)
for kernel in compiled script; do
  (cd "$other" && bash run.sh solve "${otherlaw_options[@]}" -kernel "$kernel" -out "$root/$work/otherlaw-$kernel") > "$work/otherlaw-$kernel.log" 2>&1
  rc=$?; cat "$work/otherlaw-$kernel.log" >> "$diag"; [ "$rc" = 0 ] || status=1
  [ "$kernel" = compiled ] && otherlaw_compiled_rc=$rc
done
solve "${otherlaw_options[@]}" -out "$work/otherlaw-paper" >> "$diag" 2>&1 || status=1
grep -v '^damping' edp/scenes/paper.scene > "$work/otherlaw.scene"; echo "damping power 1000 2" >> "$work/otherlaw.scene"
solve -scene "$work/otherlaw.scene" "${otherlaw_options[@]}" -out "$work/otherlaw-scene" >> "$diag" 2>&1 || status=1
"$PYTHON" tests/check_results.py "$work/otherlaw-script" --compare "$work/otherlaw-compiled" --rtol 1e-9 >> "$diag" 2>&1 \
  || { echo "the script view differs from the compiled Newton, or a law-independent check failed" >> "$diag"; status=1; }
"$PYTHON" tests/check_results.py "$work/otherlaw-scene" --compare "$work/otherlaw-compiled" --rtol 1e-9 >> "$diag" 2>&1 \
  || { echo "the scene key damping power 1000 2 differs from the edited law" >> "$diag"; status=1; }
# p_nu - lambda_nu = 1000 (v_nu)_+^2 on every node, and not the paper's 1000 (v_nu)_+
awk '!/^#/ { vn = $2 > 0 ? $2 : 0; d = $4 - $5 - 1000 * vn * vn; if (d < 0) d = -d; if (d > 1e-9) bad++; n++ }
     END { if (!n || bad) { print "contact.txt does not follow p = 1000 (v_nu)_+^2 on " bad + 0 " of " n " nodes"; exit 1 } }' \
  "$work/otherlaw-compiled/contact.txt" >> "$diag" || status=1
"$PYTHON" tests/check_results.py "$work/otherlaw-compiled" --compare "$work/otherlaw-paper" --rtol 1e-6 > /dev/null 2>&1 \
  && { echo "the quadratic law gives the paper law's results" >> "$diag"; status=1; }
report $status "a law changed only in edp/plugins/contactlaw.hpp (p = c r^2): compiled = script Newton = damping power 1000 2 to 1e-9, outputs follow it" "$diag"
# a law the solvers cannot use is refused when the run starts (exit 3, no output)
law_refused() { # law_refused K NAME REGEX [OPTION...]: the copy's law with fault K switched on
  local fault="$1" name="$2" regex="$3" diag="$work/otherlaw-$2.diag" status=0 rc=0
  cat "$work/otherlaw-faults.diag" > "$diag"; [ "$law_faults" = 0 ] || status=1
  (cd "$other" && LAW_FAULT="$fault" bash run.sh solve "${otherlaw_options[@]}" "${@:4}" -out "$root/$work/otherlaw-$name") >> "$diag" 2>&1 || rc=$?
  [ "$rc" = 3 ] || { echo "exit code $rc, expected 3" >> "$diag"; status=1; }
  grep -Eq "$regex" "$diag" || { echo "message does not match /$regex/" >> "$diag"; status=1; }
  [ -e "$work/otherlaw-$name" ] && { echo "results were written" >> "$diag"; status=1; }
  report $status "refused: a law with $name in edp/plugins/contactlaw.hpp" "$diag"
}
law_refused 1 "a slope that does not match p" \
  "the law of edp/plugins/contactlaw.hpp cannot be used: p'.* but the difference quotient of p there is"
law_refused 2 "a zone out of 0..4" "cannot be used: zone\(2, 1\) is not a zone 0..4"
law_refused 3 "a negative friction bound" "cannot be used: the friction bound is not finite and >= 0"
law_refused 4 "a bound profile not kept between its points" \
  "cannot be used: velocityBound gives g = .* at the bound_profile's middle x = 1, between points of values 0.03 to 0.07" -scene bound-profile
# the copy without a fault switched on is the law itself (Exercise 1's): its run of the paper
# scene above (otherlaw-compiled, the copy's options and its default kernel) ran to its end
status=0; [ "$otherlaw_compiled_rc" = 0 ] && [ "$law_faults" = 0 ] || status=1
cat "$work/otherlaw-faults.diag" "$work/otherlaw-compiled.log" > "$work/otherlaw-nofault.diag"
report $status "the copy of the law with its four faults switched off runs (the faults come from LAW_FAULT alone)" "$work/otherlaw-nofault.diag"

# ---- a damping family added in edp/plugins/contactlaw.hpp alone (docs/walkthrough.md,
# Exercise 1b): the page's own edit, taken from it, applied to the copy above (a family of its
# own: the copy's other changes are the linear family's and switched-off faults). The scene
# key it makes is read and checked with no other change, -cnu overrides its C, the default
# Newton, its script view and the fixed point solve it and agree, and the outputs'
# damped_response follows the new p, C R0 (e^(v_nu/R0) - 1).
diag="$work/family.diag"; cat "$work/family-edit.diag" > "$diag"; status=0
[ "$family_edit" = 0 ] || status=1
grep -v '^damping ' edp/scenes/paper.scene > "$work/family.scene"; echo "damping exponential 50 0.05" >> "$work/family.scene"
family_options=(-scene "$root/$work/family.scene" -nx 16 -ny 8 -dt 0.05)
while IFS='|' read -r name options; do   # from the copy's folder: its freefem++.pref loads its own kernel
  # shellcheck disable=SC2086
  (cd "$other" && bash run.sh solve "${family_options[@]}" $options -out "$root/$work/family-$name") >> "$diag" 2>&1 \
    || { echo "the run $name ($options) failed" >> "$diag"; status=1; }
done <<'RUNS'
newton|
script|-kernel script
fixedpoint|-solver fixedpoint
cnu25|-cnu 25
RUNS
# tests/check_results.py reads the law from the runs' own columns: the new family needs nothing of it
"$PYTHON" tests/check_results.py "$work/family-script" --compare "$work/family-newton" --rtol 1e-9 >> "$diag" 2>&1 \
  || { echo "the script view differs from the compiled Newton" >> "$diag"; status=1; }
"$PYTHON" tests/check_results.py "$work/family-fixedpoint" --compare "$work/family-newton" --rtol 1e-8 >> "$diag" 2>&1 \
  || { echo "the fixed point differs from the compiled Newton" >> "$diag"; status=1; }
"$PYTHON" - "$work/family-newton" "$work/family-cnu25" >> "$diag" 2>&1 <<'PY' || status=1
# damped_response = C R0 (e^(v_nu/R0) - 1) (C = 50, and 25 with -cnu 25; R0 = 0.05) and
# p_nu - lambda_nu = damped_response at every node of contact.txt and contact_nodes_history.txt,
# and nodes where it is far from the paper's C v_nu
import math, sys
def rows(path):
    names, out = [], []
    for line in open(path):
        if line.startswith("#"):
            names = line[1:].split()
        else:
            out.append(dict(zip(names, map(float, line.split()))))
    return out
for folder, C in ((sys.argv[1], 50.0), (sys.argv[2], 25.0)):
    for file in ("contact.txt", "contact_nodes_history.txt"):
        stiff = 0
        for row in rows(folder + "/" + file):
            v = max(row["v_nu"], 0.0)
            p = C * 0.05 * math.expm1(v / 0.05)
            if abs(row["damped_response"] - p) > 1e-12 * max(p, 1.0):
                sys.exit(f"{folder}/{file}: damped_response {row['damped_response']} != C R0 (e^(v_nu/R0) - 1) = {p} at v_nu = {v}")
            if abs(row["p_nu"] - row["lambda_nu"] - p) > 1e-9 * max(abs(row["p_nu"]), 1.0):
                sys.exit(f"{folder}/{file}: p_nu - lambda_nu = {row['p_nu'] - row['lambda_nu']} != p(v_nu) = {p} at v_nu = {v}")
            stiff += p > 1.5 * C * v
        if not stiff:
            sys.exit(f"{folder}/{file}: no node where the new p differs from the paper's C v_nu")
PY
# the new family's numbers are checked when the scene is read, and the families' list names it
for line in "damping exponential 50 0|damping exponential: R0 must be > 0, got 0" "damping cubic 3|damping table r0 p0 r1 p1 ..., or damping exponential C R0"; do
  grep -v '^damping ' edp/scenes/paper.scene > "$work/family-bad.scene"; echo "${line%%|*}" >> "$work/family-bad.scene"
  rc=0; (cd "$other" && bash run.sh solve -scene "$root/$work/family-bad.scene" -out "$root/$work/family-bad") > "$work/family-bad.log" 2>&1 || rc=$?
  [ "$rc" = 3 ] && grep -qF "${line#*|}" "$work/family-bad.log" && grep -q "family-bad.scene:[0-9][0-9]*: " "$work/family-bad.log" \
    || { echo "'${line%%|*}': exit $rc, expected 3 and '${line#*|}': $(cat "$work/family-bad.log")" >> "$diag"; status=1; }
done
report $status "a damping family added in edp/plugins/contactlaw.hpp alone (the walkthrough's Exercise 1b, its edit taken from the page): its scene key read and checked, -cnu overrides its C, compiled = script Newton to 1e-9, fixed point to 1e-8, damped_response = the new p" "$diag"
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

