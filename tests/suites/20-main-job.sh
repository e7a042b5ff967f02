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
