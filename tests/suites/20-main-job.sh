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

