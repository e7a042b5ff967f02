# The main job (./run.sh): tables, figures, the paper's zones, the eps rate.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
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


# ---- the zone boundaries between the nodes (docs/design.md, "Output files"): x_B_estimate
# and x_C_estimate at T lie between the zone's first node (x_B, x_C) and its neighbour of next
# smaller x on Gamma3, equal the last row of contact_history.txt, and are nan in 3D
diag="$work/zone-estimates.diag"; : > "$diag"; status=0
"$PYTHON" - "$work" >> "$diag" 2>&1 <<'PY' || status=1
import math, os, sys
sys.path.insert(0, "edp")
import numpy as np
import runfiles
work = sys.argv[1]
failures = []
for run in ("paper-original", "paper-penalty", "column-bound", "bound-profile", "unloading", "cylinder"):
    folder = os.path.join(work, run)
    summary = runfiles.read_summary(folder)
    x = np.sort(runfiles.read_table(os.path.join(folder, "contact.txt"))["x"])
    history = runfiles.read_table(os.path.join(folder, "contact_history.txt"))
    for node, estimate in (("x_B", "x_B_estimate"), ("x_C", "x_C_estimate")):
        at, value = summary.real(node), summary.real(estimate)
        if math.isnan(at):                           # no such zone at T: nan for both
            if not (math.isnan(value) and math.isnan(history[estimate][-1])):
                failures.append(f"{run}: {estimate} = {value}, where there is no {node}")
            continue
        left = x[x < at].max() if np.any(x < at) else at
        if not left <= value <= at:
            failures.append(f"{run}: {estimate} = {value} not between the node before {node} ({left}) and {node} = {at}")
        if history[estimate][-1] != value:
            failures.append(f"{run}: {estimate} of summary.txt ({value}) is not the last row of contact_history.txt ({history[estimate][-1]})")
summary = runfiles.read_summary(os.path.join(work, "slab3d"))
for key in ("x_B_estimate", "x_C_estimate"):
    if summary[key] != "nan":
        failures.append(f"slab3d: {key} = {summary[key]}, expected nan in 3D")
print("\n".join(failures))
sys.exit(1 if failures else 0)
PY
report $status "zone boundaries between the nodes: x_B_estimate, x_C_estimate between the zone's first node and the one before it, or on it where it is Gamma3's first (paper, both problems, a column, a bound profile, unloading, the cylinder), nan in 3D" "$diag"

# ---- every run states its error (docs/design.md, "Error estimates"): on the paper scene the
# estimates of v at T and of the normal force lie within a factor 3 of the run's distance to
# the run on a mesh twice finer (132x66; for an order p between 1 and 2 that distance is 1/2
# to 3/4 of the true error, docs/performance.md, "Error estimates"), from the structured
# companion and from a coarsened one (the same mesh given with -mesh); -estimate off and a
# -restart run have none and say why; in 3D the zone estimates are nan, the others finite;
# the companion's mesh is not left in the run folder
diag="$work/error-estimates.diag"; : > "$diag"; status=0
rm -rf "$work/estimate-fine" "$work/estimate-mesh" "$work/estimate-off" "$work/estimate-restart"
solve -nx 132 -ny 66 -quiet -out "$work/estimate-fine" >> "$diag" 2>&1 || status=1
solve -mesh "$work/paper-original/mesh.msh" -quiet -out "$work/estimate-mesh" >> "$diag" 2>&1 || status=1
solve -nx 16 -ny 8 -T 0.1 -estimate off -quiet -out "$work/estimate-off" >> "$diag" 2>&1 || status=1
solve -restart "$work/estimate-off" -T 0.2 -estimate on -quiet -out "$work/estimate-restart" >> "$diag" 2>&1 || status=1
for run in paper-original estimate-mesh; do
  "${FREEFEM[@]}" edp/compare.edp -a "$work/$run" -ref "$work/estimate-fine" > "$work/$run.distance" 2>> "$diag" || status=1
done
"$PYTHON" - "$work" >> "$diag" 2>&1 <<'PY' || status=1
import math, os, sys
sys.path.insert(0, "edp")
import runfiles
work = sys.argv[1]
failures = []
fine = runfiles.read_table(os.path.join(work, "estimate-fine", "contact_history.txt"))["normal_force"][-1]
for run, source in (("paper-original", "companion 33x16 "), ("estimate-mesh", "companion: the run's mesh coarsened")):
    folder = os.path.join(work, run)
    summary = runfiles.read_summary(folder)
    if not summary["error_estimate_source"].startswith(source):
        failures.append(f"{run}: error_estimate_source '{summary['error_estimate_source']}', expected '{source}...'")
    words = open(os.path.join(work, run + ".distance")).read().split()
    distance = dict(zip(words[::2], map(float, words[1::2])))
    force = runfiles.read_table(os.path.join(folder, "contact_history.txt"))["normal_force"][-1]
    for key, true in (("error_estimate_v_L2", distance["error_L2"] / distance["norm_L2"]),
                      ("error_estimate_normal_force", abs(force - fine) / abs(force))):
        estimate = summary.real(key)
        if not (true / 3 <= estimate <= 3 * true):
            failures.append(f"{run}: {key} = {estimate}, the distance to 132x66 is {true}: not within a factor 3")
    for key in ("error_estimate_x_B", "error_estimate_x_C"):
        if not summary.real(key) > 0:
            failures.append(f"{run}: {key} = {summary[key]}, expected a positive number")
    if os.path.exists(os.path.join(folder, "companion.msh")):
        failures.append(f"{run}: companion.msh left in the run folder")
for run, why in (("estimate-off", "none: -estimate off"), ("estimate-restart", "none: a -restart run")):
    summary = runfiles.read_summary(os.path.join(work, run))
    if not summary["error_estimate_source"].startswith(why):
        failures.append(f"{run}: error_estimate_source '{summary['error_estimate_source']}', expected '{why}...'")
    for key in ("error_estimate_v_L2", "error_estimate_normal_force", "error_estimate_x_B", "error_estimate_x_C"):
        if summary[key] != "nan":
            failures.append(f"{run}: {key} = {summary[key]}, expected nan")
summary = runfiles.read_summary(os.path.join(work, "slab3d"))
if not summary["error_estimate_source"].startswith("companion 8x4x1 "):
    failures.append(f"slab3d: error_estimate_source '{summary['error_estimate_source']}'")
if not (summary.real("error_estimate_v_L2") > 0 and summary.real("error_estimate_normal_force") > 0):
    failures.append("slab3d: the estimates of v and of the normal force are not positive numbers")
if summary["error_estimate_x_B"] != "nan" or summary["error_estimate_x_C"] != "nan":
    failures.append("slab3d: the zone boundary estimates are not nan in 3D")
print("\n".join(failures))
sys.exit(1 if failures else 0)
PY
# a companion that fails (its entries out of scale, where the run's are not: -rho 3e19 on 8x4)
# or is not coarse enough (the half disk at 1x2, whose companion 1x1 has as many vertices)
# leaves the run whole: exit 0, nothing of the companion's error on the standard output, the
# estimates nan and the source saying why; the script Newton's own counts stay the run's
for run in "-nx 8 -ny 4 -T 0.02 -rho 3e19|stopped: the material data" "-scene halfdisk -nx 1 -ny 2 -T 0.04|is not coarse enough"; do
  options="${run%%|*}"; why="${run#*|}"
  rm -rf "$work/estimate-odd"
  # shellcheck disable=SC2086
  if solve $options -quiet -out "$work/estimate-odd" > "$work/estimate-odd.out" 2>> "$diag"; then
    grep -q "^error_estimate_source none: .*$why" "$work/estimate-odd/summary.txt" && grep -q "^error_estimate_v_L2 nan" "$work/estimate-odd/summary.txt" \
      || { echo "$options: $(grep error_estimate_source "$work/estimate-odd/summary.txt")"; status=1; } >> "$diag"
    ! grep -q "rror" "$work/estimate-odd.out" || { echo "$options: the companion's error on the standard output"; cat "$work/estimate-odd.out"; status=1; } >> "$diag"
  else echo "$options: the run failed with its companion" >> "$diag"; status=1; fi
done
for estimate in on off; do
  solve -nx 8 -ny 4 -T 0.05 -kernel script -estimate "$estimate" -quiet -out "$work/estimate-script-$estimate" >> "$diag" 2>&1 || status=1
done
cmp -s <(grep -E '^newton_(factorizations|retries) ' "$work/estimate-script-on/summary.txt") <(grep -E '^newton_(factorizations|retries) ' "$work/estimate-script-off/summary.txt") \
  || { echo "the script Newton's counts differ with the companion"; status=1; } >> "$diag"
report $status "error estimates: v at T and the normal force within a factor 3 of the distance to a mesh twice finer (structured and coarsened companions); none, and why, with -estimate off, -restart, a companion that fails or is not coarse enough (the run whole, nothing on its output); nan zone estimates in 3D; no companion mesh left behind; the script's counts the run's own" "$diag"
