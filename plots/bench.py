#!/usr/bin/python3
"""Tables and charts of the benchmark (plots/bench.sh, ./run.sh bench).

Reads the run folders DIR/runs/NAME that plots/bench.sh makes (summary.txt of edp/solve.edp,
NAME.time with the wall seconds and peak memory of the process, NAME.error and
NAME.solver_error from edp/compare.edp) and writes into DIR
  steps.txt, steps_adapted.txt, steps3d.txt, iterations.txt, work_precision.txt, rates.txt,
  reference.txt   (plain text, '#' header naming the columns)
  bench_cost_per_step.png, bench_work_precision.png, bench_adapted_mesh.png, bench_iterations.png,
  bench_error_estimates.png (each run's own estimates of its errors against the true errors, when
  the runs write them: summary.txt error_estimate_*)
Usage: bench.py --bench DIR --reference RUN_DIR
"""
import argparse
import math
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import runfiles
import style

plt = style.pyplot()
NAN = float("nan")


def run_record(bench, name):
    """What one run measured: its summary (empty if it failed), wall, peak memory, error."""
    folder = os.path.join(bench, "runs", name)
    record = {"name": name, "converged": os.path.isfile(os.path.join(folder, "summary.txt"))}
    record["summary"] = runfiles.read_summary(folder) if record["converged"] else {}
    wall, peak = runfiles.read_process_time(folder + ".time") if os.path.isfile(folder + ".time") else (NAN, NAN)
    record["wall"], record["peak_MB"] = wall, peak / 1024.0
    for key, suffix in (("error", ".error"), ("solver_error", ".solver_error")):
        record[key] = {}
        if os.path.isfile(folder + suffix):
            pairs = runfiles.read_pairs(folder + suffix)
            record[key] = {name: pairs.real(name) for name in pairs}
    return record


def number(text):
    """A summary.txt value as a float, nan when it is not a number."""
    try:
        return float(text)
    except (TypeError, ValueError):
        return NAN


def value(record, key):
    return number(record["summary"].get(key, NAN))


def all_names(bench, prefix):
    """Every run started with this prefix, converged or not (its .time file exists)."""
    runs = os.path.join(bench, "runs")
    found = {n[:-5] for n in os.listdir(runs) if n.endswith(".time") and n.startswith(prefix)}
    return sorted(found)


def steps_table(bench, prefix="steps-", table="steps.txt"):
    """The cost per step of the runs PREFIX-NXxNY-MODE-PROBLEM (2D) or PREFIX-NXxNYxNZ-... (3D)."""
    rows = []
    for name in all_names(bench, prefix):
        m = re.match(re.escape(prefix) + r"(\d+)x(\d+)(x\d+)?-(\w+)-(original|penalty)(.*)", name)
        if not m:
            continue
        r = run_record(bench, name)
        steps = value(r, "steps")
        its = value(r, "iterations_total")
        backsub, median = value(r, "time_backsubstitution"), value(r, "time_step_median")
        umfpack = value(r, "time_backsubstitution_umfpack")
        rows.append([name, f"{m.group(1)}x{m.group(2)}{m.group(3) or ''}", int(value(r, "dofs")) if r["converged"] else -1,
                     int(value(r, "contact_slots")) if r["converged"] else -1, m.group(4), m.group(5),
                     int(steps) if r["converged"] else -1, int(r["converged"]), r["wall"],
                     value(r, "time_mesh"), value(r, "time_assembly"), value(r, "time_factorization"),
                     value(r, "time_condensation"), value(r, "time_record_setup"),
                     backsub, umfpack, median, median / backsub if backsub > 0 else NAN,
                     median / umfpack if umfpack > 0 else NAN,
                     its / steps if steps > 0 else NAN, value(r, "iterations_max"), r["peak_MB"]])
    columns = ("run mesh dofs contact_slots mode problem steps converged wall time_mesh time_assembly time_factorization "
               "time_condensation time_record_setup time_backsubstitution time_backsubstitution_umfpack time_step_median "
               "step_over_floor step_over_umfpack_floor iterations_mean "
               "iterations_max peak_memory_MB").split()
    runfiles.write_table(os.path.join(bench, table),
                      ["cost per time step: time_step_median (CPU s) against the floor time_backsubstitution (one",
                       "back-substitution with the kernel's Cholesky factor of S, measured during the loop, same run) and against",
                       "time_backsubstitution_umfpack (one back-substitution with FreeFEM's default UMFPACK, median of 5,",
                       "same run; nan when not measured); setup times and wall in wall seconds; peak memory of the",
                       "whole FreeFEM process"], columns, rows)
    return columns, rows


def steps_adapted_table(bench):
    """Step / floor on each adapted mesh, from its repeated runs (stepsadapted-RUN-I)."""
    groups = {}
    for name in all_names(bench, "stepsadapted-"):
        m = re.match(r"stepsadapted-(.*)-(\d+)$", name)
        if m:
            groups.setdefault(m.group(1), []).append(run_record(bench, name))
    rows = []
    for mesh, records in sorted(groups.items()):
        ok = [r for r in records if r["converged"]]
        ratios = sorted(value(r, "time_step_median") / value(r, "time_backsubstitution") for r in ok)
        before = sorted(value(r, "time_step_median") / value(r, "time_backsubstitution_before") for r in ok)
        if not ratios:
            rows.append([mesh, -1, -1, 0, NAN, NAN, NAN, NAN, NAN])
            continue
        median = lambda xs: xs[len(xs) // 2] if len(xs) % 2 else 0.5 * (xs[len(xs) // 2 - 1] + xs[len(xs) // 2])
        rows.append([mesh, int(value(ok[0], "vertices")), int(value(ok[0], "contact_slots")), len(ratios),
                     median([value(r, "time_backsubstitution") for r in ok]), median(ratios), ratios[0], ratios[-1],
                     median(before)])
    columns = ("mesh vertices contact_slots runs time_backsubstitution step_over_floor step_over_floor_min "
               "step_over_floor_max step_over_floor_before").split()
    runfiles.write_table(os.path.join(bench, "steps_adapted.txt"),
                      ["cost per time step on the adapted meshes of work_precision.txt, each run again with -mesh",
                       "(the mesh of wp-RUN): the median over the runs of time_step_median / time_backsubstitution (the",
                       "floor measured during the loop, same run), its smallest and largest, and the median against",
                       "time_backsubstitution_before (the floor measured back to back before the loop)"], columns, rows)
    return columns, rows


def iterations_table(bench):
    rows = []
    for name in all_names(bench, "iterations-"):
        m = re.match(r"iterations-(\d+x\d+)-(\w+)-r(.*)", name)
        if not m:
            continue
        r = run_record(bench, name)
        steps = value(r, "steps")
        backsub, median = value(r, "time_backsubstitution"), value(r, "time_step_median")
        rows.append([m.group(2), m.group(1), float(m.group(3)), int(r["converged"]),
                     value(r, "iterations_total") / steps if steps > 0 else NAN, value(r, "iterations_max"),
                     median, backsub, median / backsub if backsub > 0 else NAN,
                     int(value(r, "newton_fallbacks")) if r["converged"] else -1,
                     int(value(r, "fixed_point_sweeps")) if r["converged"] else -1])
    columns = ("mode mesh r converged iterations_mean iterations_max time_step_median time_backsubstitution "
               "step_over_floor newton_fallbacks fixed_point_sweeps").split()
    runfiles.write_table(os.path.join(bench, "iterations.txt"),
                      ["iterations and cost per step against the augmentation factor r (r_j = r/(Dw)_jj; for the fixed",
                       "point does not use r: every residual is read at r = 1), T = 1, k = 0.01; step_over_floor =",
                       "time_step_median / time_backsubstitution (CPU seconds, same run); converged 0: exit 4 at the cap",
                       "(Newton 200, fixed point 2000)"], columns, rows)
    return columns, rows


def final_row(folder):
    """The last row of contact_history.txt (the values at T) as a dict; empty when there is none."""
    path = os.path.join(folder, "contact_history.txt")
    if not os.path.isfile(path):
        return {}
    table = runfiles.read_table(path)
    return {name: float(table[name][-1]) for name in table.columns}


def final_contact(folder):
    """x_B, x_C and the normal force at T (the last row of contact_history.txt; nan if none)."""
    row = final_row(folder)
    return tuple(row.get(k, NAN) for k in ("x_B", "x_C", "normal_force"))


ESTIMATES = ("x_B_estimate", "x_C_estimate")


def final_estimates(folder):
    """x_B_estimate, x_C_estimate at T: the zone boundaries located between the nodes (the last
    row of contact_history.txt, else summary.txt; nan for a run that wrote neither)."""
    row = final_row(folder)
    if all(k in row for k in ESTIMATES):
        return tuple(row[k] for k in ESTIMATES)
    if not os.path.isfile(os.path.join(folder, "summary.txt")):
        return NAN, NAN
    summary = runfiles.read_summary(folder)
    return tuple(number(summary.get(k, NAN)) for k in ESTIMATES)


def floored(error, floor=1e-5):
    """An error drawn on a log axis: at least floor (an exact 0 stays visible), nan kept."""
    return error if math.isnan(error) else max(error, floor)


def larger(a, b):
    """The larger of two errors, nan when either is nan (an error not measured is not small)."""
    return NAN if math.isnan(a) or math.isnan(b) else max(a, b)


# A run's own estimates of its errors (summary.txt, when the run writes them) and the column of
# work_precision.txt each is written to, then the column of the true error it is read against.
ERROR_ESTIMATES = (("error_estimate_v_L2", "estimate_error_L2", "relative_error_L2"),
                   ("error_estimate_normal_force", "estimate_error_normal_force", "relative_error_normal_force"),
                   ("error_estimate_x_B", "estimate_error_x_B", "error_x_B_estimate"),
                   ("error_estimate_x_C", "estimate_error_x_C", "error_x_C_estimate"))


TIME_REFERENCE = "timeref-66x33-dt0.00125"


def work_precision_table(bench, reference):
    rows = []
    ref_contact, ref_estimates = final_contact(reference), final_estimates(reference)
    timeref = os.path.join(bench, "runs", TIME_REFERENCE)
    time_contact, time_estimates = final_contact(timeref), final_estimates(timeref)
    for name in all_names(bench, "wp-"):
        r = run_record(bench, name)
        family = name.split("-")[1]
        if family == "tol":                              # wp-tol-SOLVER-TOL
            family = "tol-" + name.split("-")[2]
        e, se = r["error"], r["solver_error"]
        rel = e.get("error_L2", NAN) / e["norm_L2"] if e.get("norm_L2") else NAN
        srel = se.get("error_L2", NAN) / se["norm_L2"] if se.get("norm_L2") else NAN
        against, against_estimates = (time_contact, time_estimates) if family == "dt" else (ref_contact, ref_estimates)
        folder = os.path.join(bench, "runs", name)
        xb, xc, fn = final_contact(folder) if r["converged"] else (NAN, NAN, NAN)
        xbe, xce = final_estimates(folder) if r["converged"] else (NAN, NAN)
        rows.append([name, family, int(r["converged"]), value(r, "vertices"), r["wall"], e.get("error_L2", NAN), rel,
                     e.get("error_gamma3", NAN), abs(xb - against[0]), abs(xc - against[1]), abs(fn - against[2]) / abs(against[2]),
                     srel, value(r, "time_loop"), abs(xbe - against_estimates[0]), abs(xce - against_estimates[1]),
                     abs(fn - against[2])] + [value(r, key) for key, _, _ in ERROR_ESTIMATES])
    columns = ("run family converged vertices wall error_L2 relative_error_L2 error_gamma3 error_x_B error_x_C "
               "relative_error_normal_force relative_solver_error_L2 time_loop error_x_B_estimate error_x_C_estimate "
               "error_normal_force").split() + [column for _, column, _ in ERROR_ESTIMATES]
    runfiles.write_table(os.path.join(bench, "work_precision.txt"),
                      [f"error at T against the reference {os.path.basename(reference)} (the family dt: against the",
                       f"66x33 run at k = 0.00125, {TIME_REFERENCE}) (edp/compare.edp: ||v - v_ref||_L2(Omega) with the",
                       "consistent mass matrix of the reference mesh, and max |dv_nu| on Gamma3; x_B, x_C and the normal",
                       "force at T from contact_history.txt), against the wall seconds of the whole process, adaptation",
                       "included; relative_solver_error_L2 (the tol family only): the same distance to the 66x33 run",
                       "solved to tol 1e-13, relative; time_loop: wall seconds of the time loop alone (summary.txt);",
                       "error_x_B_estimate, error_x_C_estimate: |x_B_estimate - the reference's x_B_estimate| at T, the same",
                       "for x_C (the zone boundaries located between the nodes; the last row of contact_history.txt, else",
                       "summary.txt; nan when a run has none); error_normal_force: |normal force - the reference's| at T",
                       "(absolute, the unit of contact_history.txt); estimate_error_L2, estimate_error_normal_force,",
                       "estimate_error_x_B, estimate_error_x_C: the run's own estimates of its errors (summary.txt",
                       "error_estimate_v_L2, error_estimate_normal_force, error_estimate_x_B, error_estimate_x_C; nan when",
                       "absent; the first two relative), read against relative_error_L2, relative_error_normal_force,",
                       "error_x_B_estimate, error_x_C_estimate on the uniform and adapted meshes only (families",
                       ", ".join(MESH_FAMILIES) + ": a run estimates its error in space, not the time, eps, tol or solver",
                       "error); family adapt2z: two rounds with -adapt_zones 1e-3 (the mesh refined around x_B, x_C)"],
                      columns, rows)
    return columns, rows


def slope(xs, ys):
    """Least-squares slope of log y against log x (nan with fewer than two points)."""
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x > 0 and y > 0 and not math.isnan(y)]
    if len(pts) < 2:
        return NAN
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sum((p[0] - mx) ** 2 for p in pts)


# The families of the work-precision study, once: name, meaning, the chart's label, marker and
# label offset. The first four differ from the reference by the mesh alone (MESH_FAMILIES):
# their error is the error in space, which a run estimates; the others differ in the time
# step, eps, tol or the solver.
FAMILIES = (("mesh", "uniform meshes", "uniform mesh (k = 0.01)", "o-", ((3, 3), "left")),
            ("adapt1", "adapted meshes, one round", "adapted, 1 round from 33x16 (-adapt_err)", "D-", ((3, -9), "left")),
            ("adapt2", "adapted meshes, two rounds", "adapted, 2 rounds from 33x16 (-adapt_err)", "d-", ((-4, 3), "right")),
            ("adapt2z", "adapted meshes, two rounds, -adapt_zones 1e-3",
             "adapted, 2 rounds from 33x16, -adapt_zones 1e-3 (-adapt_err)", "h-", ((-4, -9), "right")),
            ("dt", "time steps on 66x33", "time step k (66x33, against k = 0.00125)", "s-", ((3, -10), "left")),
            ("full", "full-system Newton", "full-system Newton (66x33)", "^", ((3, 3), "left")),
            ("penalty", "penalty eps", "penalty eps (66x33, against the original reference)", "v-", ((-4, 3), "right")),
            ("tol-newton", "Newton's tol", "Newton, tol 1e-4 ... 1e-10 (66x33)", "P-", ((3, -8), "left")),
            ("tol-fixedpoint", "the fixed point's tol", "fixed point, tol 1e-4 ... 1e-10 (66x33)", "X-", ((-4, -8), "right")))
MESH_FAMILIES = tuple(f[0] for f in FAMILIES[:4])
ADAPTED_FAMILIES = MESH_FAMILIES[1:]
RATE_FAMILIES = tuple((f[0], f[1]) for f in FAMILIES[:4])


def contact_rates(c, rows):
    """The rows FAMILY:QUANTITY of rates.txt (x_B, x_C as node positions and as estimates between
    the nodes, uniform and adapted meshes, in h = vertices^-1/2), and a comment line for each rate
    that could not be fitted, saying why."""
    rate_rows, why = [], []
    for family, meaning in RATE_FAMILIES:
        runs = [r for r in rows if r[c["family"]] == family and r[c["converged"]]]
        for quantity, what in (("x_B", "node"), ("x_B_estimate", "estimate"), ("x_C", "node"),
                               ("x_C_estimate", "estimate")):
            errors = [r[c["error_" + quantity]] for r in runs]
            pts = [(r, e) for r, e in zip(runs, errors) if e > 0]          # nan and exact 0 excluded
            rate = slope([r[c["vertices"]] ** -0.5 for r, _ in pts], [e for _, e in pts])
            wall = -slope([r[c["wall"]] for r, _ in pts], [e for _, e in pts])
            name = f"{family}:{quantity}"
            rate_rows.append([name, len(pts), rate, wall, f"{meaning}, error of {quantity.split('_estimate')[0]} "
                              f"({what}) in m, in h = vertices^-1/2"])
            if math.isnan(rate):
                zeros = sum(1 for e in errors if e == 0)
                missing = sum(1 for e in errors if math.isnan(e))
                why.append(f"{name}: rate nan, {len(pts)} finite nonzero point{'s' if len(pts) != 1 else ''} of "
                           f"{len(runs)} converged run{'s' if len(runs) != 1 else ''} (two needed; {missing} nan, "
                           f"{zeros} exactly 0)")
    return rate_rows, why


def rates_and_margin(bench, reference, columns, rows):
    """rates.txt: the observed rates of the relative L2 error (in h = 1/sqrt(vertices) for the
    meshes, in k for the time steps); reference.txt: the reference's estimated error and its
    margin below the smallest error the table reports; the targets of the adapted meshes."""
    c = {name: i for i, name in enumerate(columns)}
    ok = [r for r in rows if r[c["converged"]] and not math.isnan(r[c["relative_error_L2"]])]
    rate_rows = []
    for family, meaning in RATE_FAMILIES:
        meaning += " (h ~ vertices^-1/2)" if family == "mesh" else ", in h = vertices^-1/2"
        pts = [r for r in ok if r[c["family"]] == family]
        rate = slope([r[c["vertices"]] ** -0.5 for r in pts], [r[c["relative_error_L2"]] for r in pts])
        wall = -slope([r[c["wall"]] for r in pts], [r[c["relative_error_L2"]] for r in pts])
        rate_rows.append([family, len(pts), rate, wall, meaning])
    pts = [r for r in ok if r[c["family"]] == "dt"]
    ks = [float(r[c["run"]].split("-")[-1]) for r in pts]
    rate_rows.append(["dt", len(pts), slope(ks, [r[c["relative_error_L2"]] for r in pts]), NAN,
                      "time steps on 66x33, in k (against k = 0.00125)"])
    why = [f"{r[0]}: rate nan, {r[1]} point{'s' if r[1] != 1 else ''} (two needed)" for r in rate_rows if math.isnan(r[2])]
    contact_rows, contact_why = contact_rates(c, rows)
    rate_rows, why = rate_rows + contact_rows, why + contact_why
    runfiles.write_table(os.path.join(bench, "rates.txt"),
                      ["observed rates: the least-squares slope of log(relative L2 error of v at T) against log h or",
                       "log k (rate), and against log(wall seconds) (per_wall, negated: error ~ wall^-per_wall);",
                       "the rows FAMILY:QUANTITY, QUANTITY one of x_B, x_B_estimate, x_C, x_C_estimate: the same",
                       "least-squares slopes of log|error at T| in m (the columns error_QUANTITY of work_precision.txt:",
                       "the node position, or the estimate between the nodes, against the reference's) against",
                       "log h, h = vertices^-1/2, over the family's converged runs whose error is finite and nonzero",
                       "(points counts them)"] + why,
                      "family points rate per_wall meaning".split(), rate_rows)
    check = run_record(bench, "check-adapted")
    e = check["error"]
    estimate = e.get("error_L2", NAN) / e["norm_L2"] if e.get("norm_L2") else NAN
    space = [r[c["relative_error_L2"]] for r in ok if r[c["family"]] in MESH_FAMILIES]
    smallest = min(space) if space else NAN
    check_estimates = final_estimates(os.path.join(bench, "runs", "check-adapted")) if check["converged"] else (NAN, NAN)
    check_distances = [abs(a - b) for a, b in zip(check_estimates, final_estimates(reference))]
    runfiles.write_table(os.path.join(bench, "reference.txt"),
                      ["the reference's error: estimated as its distance to the check run (twice its -adapt_err; the",
                       "error of an adapted mesh falls like -adapt_err, so the check's error is about twice the",
                       "reference's and the distance about the reference's own), and the margin below the smallest",
                       "error of a uniform or adapted run in work_precision.txt; check_distance_x_B_estimate,",
                       "check_distance_x_C_estimate: |the check's x_B_estimate - the reference's| at T, the same for x_C",
                       "(m): how well the reference itself knows the zone boundaries (nan when a run has none)"],
                      ("reference vertices estimated_relative_error smallest_reported_error margin "
                       "check_distance_x_B_estimate check_distance_x_C_estimate").split(),
                      [[os.path.basename(reference), value(run_record(bench, "reference-adapted"), "vertices"), estimate,
                        smallest, smallest / estimate if estimate > 0 else NAN] + check_distances])
    for r in rate_rows:
        if math.isnan(r[2]):
            print(f"  rate {r[0]:19s} n/a ({r[4]}: {r[1]} point{'s' if r[1] != 1 else ''}, two needed)")
            continue
        per_wall = f", error ~ wall^{-r[3]:.2f}" if not math.isnan(r[3]) else ""
        print(f"  rate {r[0]:19s} {r[2]:6.2f} in h or k{per_wall}  ({r[4]}, {r[1]} points)")
    print(f"  reference: estimated relative error {estimate:.3e}, smallest reported error {smallest:.3e}, "
          f"margin {smallest / estimate if estimate > 0 else NAN:.1f}x")
    print(f"  reference: its x_B and x_C estimates {check_distances[0]:.1e} and {check_distances[1]:.1e} m from the "
          "check run's")
    uniform = [r for r in ok if r[c["run"]] == "wp-mesh-264x132"]
    if uniform:
        target, wall = uniform[0][c["relative_error_L2"]], uniform[0][c["wall"]]
        better = sorted((r[c["wall"]], r[c["run"]], r[c["relative_error_L2"]]) for r in ok
                        if r[c["family"]].startswith("adapt") and r[c["relative_error_L2"]] <= target)
        if better:
            print(f"  target: uniform 264x132 reaches {target:.3e} in {wall:.2f} s; {better[0][1]} reaches {better[0][2]:.3e} "
                  f"in {better[0][0]:.2f} s: {wall / better[0][0]:.1f}x less wall time")
        else:
            print(f"  target: no adapted run reaches the error {target:.3e} of uniform 264x132")
    else:
        print("  target: no uniform 264x132 run to compare with (--quick skips it)")
    print_contact_targets(c, ok, check_distances)


def print_contact_targets(c, ok, check_distances):
    """The runs under 1 s wall whose x_B and x_C are both within the target of the reference's:
    the node positions (2e-3 m, adapted meshes) and the estimates between the nodes (1e-3 m, the
    project's target, uniform and adapted meshes); with none, the closest run under 1 s.
    check_distances: how far the check run's estimates lie from the reference's."""
    for label, suffix, limit, text, families in (("x_B and x_C", "", 2e-3, "2e-3", ADAPTED_FAMILIES),
                                                  ("x_B and x_C estimates", "_estimate", 1e-3, "1e-3", MESH_FAMILIES)):
        fast = sorted(((larger(r[c["error_x_B" + suffix]], r[c["error_x_C" + suffix]]), r[c["wall"]], r[c["run"]])
                       for r in ok if r[c["family"]] in families and r[c["wall"]] < 1), key=lambda t: (math.isnan(t[0]), t))
        met = [t for t in fast if t[0] <= limit]
        where = "adapted" if "mesh" not in families else "uniform or adapted"
        line = ", ".join(f"{run} ({wall:.2f} s, {error:.2e} m)" for error, wall, run in sorted(met, key=lambda t: t[1]))
        if not met:
            line = "none" + (f" (closest: {fast[0][2]}, {fast[0][0]:.2e} m in {fast[0][1]:.2f} s)"
                             if suffix and fast and not math.isnan(fast[0][0]) else "")
        if suffix and larger(*check_distances) > limit:
            line += (f"; the reference's own estimates lie up to {larger(*check_distances):.1e} m from the check "
                     "run's, more than the target (reference.txt)")
        print(f"  {label} within {text} m under 1 s ({where} meshes): {line}")


def chart_cost_per_step(bench, columns, rows, rows3d=()):
    c = {name: i for i, name in enumerate(columns)}
    fig, (left, right) = plt.subplots(1, 2)
    floors, umfpack_floors = {}, {}
    for r in rows:
        if r[c["converged"]]:
            floors.setdefault(r[c["dofs"]], []).append(r[c["time_backsubstitution"]])
            if not math.isnan(r[c["time_backsubstitution_umfpack"]]):
                umfpack_floors.setdefault(r[c["dofs"]], []).append(r[c["time_backsubstitution_umfpack"]])
    floor_pts = sorted((dofs, sorted(f)[len(f) // 2]) for dofs, f in floors.items())   # median per mesh
    umfpack_pts = sorted((dofs, sorted(f)[len(f) // 2]) for dofs, f in umfpack_floors.items())
    highest = 0.0
    for (mode, problem), line in ((("newton", "original"), "o-"), (("newton", "penalty"), "s--"),
                                   (("script", "original"), "D-"), (("full", "original"), "^-"),
                                   (("fixedpoint", "original"), "v-")):
        pts = sorted((r[c["dofs"]], r[c["time_step_median"]]) for r in rows
                     if r[c["mode"]] == mode and r[c["problem"]] == problem and r[c["converged"]]
                     )
        if pts:
            left.loglog(*zip(*pts), line, label=f"{mode}, {problem}")
            highest = max(highest, max(p[1] for p in pts))
    if floor_pts:
        left.loglog(*zip(*floor_pts), "k:", linewidth=2, label="floor: one back-substitution (kernel, Cholesky)")
        left.loglog([p[0] for p in floor_pts], [2 * p[1] for p in floor_pts], color="0.6", linewidth=1,
                    label="2 x floor")
    if umfpack_pts:
        left.loglog(*zip(*umfpack_pts), "k-.", linewidth=1, label="one back-substitution with FreeFEM's UMFPACK")
    pts3d = sorted((r[c["dofs"]], r[c["time_step_median"]], r[c["time_backsubstitution"]]) for r in rows3d if r[c["converged"]])
    if pts3d:                                    # the 3D slab (P1 tetrahedra), its step and its own floor
        left.loglog([p[0] for p in pts3d], [p[1] for p in pts3d], "P-", color="tab:brown", label="3D slab: newton, original")
        left.loglog([p[0] for p in pts3d], [p[2] for p in pts3d], ":", color="tab:brown", linewidth=2, label="3D slab: floor")
        highest = max(highest, max(p[1] for p in pts3d))
    left.set_xlabel("degrees of freedom")
    left.set_ylabel("CPU seconds per time step (median)")
    left.set_title("cost of a time step")
    if highest > 0:
        left.set_ylim(top=highest * 3000)       # room for the legend above the slowest mode
    left.legend(fontsize=6.5, loc="upper left", ncol=2)
    for key, line in (("time_mesh", "v-"), ("time_assembly", "o-"), ("time_factorization", "s-"),
                       ("time_condensation", "^-"), ("time_record_setup", "D-")):
        pts = sorted({(r[c["dofs"]], r[c[key]]) for r in rows
                      if r[c["mode"]] == "newton" and r[c["problem"]] == "original" and r[c["converged"]]})
        if pts:
            right.loglog(*zip(*pts), line, label=key.replace("time_", ""))
    right.set_xlabel("degrees of freedom")
    right.set_ylabel("wall seconds, once per run")
    right.set_title("setup costs (Newton, original)")
    right.legend(fontsize=7)
    return style.save(fig, bench, "bench_cost_per_step")


def parameter_order(name):
    """Sort key of a work-precision run: its mesh size, time step or eps, finest last."""
    numbers = [float(x) for x in re.findall(r"\d+(?:\.\d+)?(?:e-?\d+)?", name.split("-", 2)[-1])]
    if not numbers:
        return 0.0
    return numbers[0] if "mesh" in name else -numbers[0]


def chart_work_precision(bench, columns, rows):
    c = {name: i for i, name in enumerate(columns)}
    fig, (ax, contact_ax, solver_ax) = plt.subplots(1, 3, figsize=(17, 4.8))
    contact_families = []                         # the legend of the middle panel: colour = family, line = quantity
    labels = {f[0]: f[2] for f in FAMILIES}
    # label offsets per family, so that the labels around the 66x33 point do not overlap
    offsets = {f[0]: f[4] for f in FAMILIES}
    for family, marker in ((f[0], f[3]) for f in FAMILIES):
        pts = sorted((r for r in rows if r[c["family"]] == family and r[c["converged"]]
                      and not math.isnan(r[c["relative_error_L2"]])), key=lambda r: parameter_order(r[c["run"]]))
        if not pts:
            continue
        ax.loglog([r[c["wall"]] for r in pts], [r[c["relative_error_L2"]] for r in pts], marker, label=labels[family])
        for r in pts:
            name = r[c["run"]]
            ax.annotate(name.split("-")[-1] if family.startswith("tol") else name.split("-", 2)[-1],
                        (r[c["wall"]], r[c["relative_error_L2"]]),
                        fontsize=6, xytext=offsets[family][0], textcoords="offset points", ha=offsets[family][1])
        if family in MESH_FAMILIES:
            color = ax.get_lines()[-1].get_color()
            walls = [r[c["wall"]] for r in pts]
            contact_ax.loglog(walls, [floored(larger(r[c["error_x_B"]], r[c["error_x_C"]])) for r in pts], marker, color=color)
            contact_ax.loglog(walls, [floored(larger(r[c["error_x_B_estimate"]], r[c["error_x_C_estimate"]])) for r in pts],
                              marker[0] + "--", color=color, markerfacecolor="none")
            contact_ax.loglog(walls, [r[c["relative_error_normal_force"]] for r in pts], marker[0] + ":", color=color,
                              alpha=0.5)
            contact_families.append(plt.Line2D([], [], color=color, marker=marker[0], label=labels[family]))
        if family.startswith("tol"):
            sol = [r for r in pts if r[c["relative_solver_error_L2"]] > 0]
            if sol:
                solver_ax.loglog([r[c["time_loop"]] for r in sol], [r[c["relative_solver_error_L2"]] for r in sol], marker,
                                 label=labels[family])
                for r in sol:
                    solver_ax.annotate("tol " + r[c["run"]].split("-")[-1], (r[c["time_loop"]], r[c["relative_solver_error_L2"]]),
                                       fontsize=6, xytext=(3, 3), textcoords="offset points")
    ax.set_xlabel("wall seconds of the whole run (start-up and adaptation included)")
    ax.set_ylabel(r"$\|v - v_{ref}\|_{L^2(\Omega)} / \|v_{ref}\|$ at T")
    ax.set_title("work and precision (against the adapted reference)")
    ax.legend(fontsize=6)
    contact_ax.axhline(2e-3, color="0.6", linewidth=1)
    contact_ax.axhline(1e-3, color="0.6", linewidth=1, linestyle="--")
    contact_ax.axvline(1, color="0.6", linewidth=1)
    contact_ax.set_xlabel("wall seconds of the whole run")
    contact_ax.set_ylabel("error at T (x_B, x_C in m, floored at 1e-5; force relative)")
    contact_ax.set_title("contact quantities on Gamma3 (grey: 2e-3 m, dashed 1e-3 m, 1 s)")
    quantities = [plt.Line2D([], [], color="k", marker="o", label="x_B, x_C node positions: the larger error (m)"),
                  plt.Line2D([], [], color="k", marker="o", linestyle="--", markerfacecolor="none",
                             label="x_B, x_C estimates between the nodes: the larger error (m)"),
                  plt.Line2D([], [], color="k", marker="o", linestyle=":", alpha=0.5, label="normal force, relative error")]
    contact_ax.set_ylim(top=contact_ax.get_ylim()[1] * 30)   # room for the legend above the points
    contact_ax.legend(handles=contact_families + quantities, fontsize=6, loc="upper right")
    solver_ax.xaxis.set_minor_formatter(plt.NullFormatter())   # a narrow log range: no crowded minor labels
    solver_ax.set_xlabel("wall seconds of the time loop (66x33, 100 steps)")
    solver_ax.set_ylabel("relative L2 distance at T to the same mesh at tol 1e-13")
    solver_ax.set_title("what the tolerance buys each solver")
    solver_ax.legend(fontsize=7)
    return style.save(fig, bench, "bench_work_precision")


def estimate_pairs(columns, rows):
    """(run, quantity, estimated error, true error) for every error a run estimates (ERROR_ESTIMATES)
    where both are finite and positive, in every family but dt: its true error is the time error
    alone (against the 66x33 run at a smaller k), not what a run's estimate of its error is."""
    c = {name: i for i, name in enumerate(columns)}
    pairs = []
    for r in rows:
        if r[c["family"]] not in MESH_FAMILIES or not r[c["converged"]]:
            continue
        for _, estimated, true in ERROR_ESTIMATES:
            a, b = r[c[estimated]], r[c[true]]
            if a > 0 and b > 0 and math.isfinite(a) and math.isfinite(b):
                pairs.append((r[c["run"]], estimated.replace("estimate_error_", ""), a, b))
    return pairs




def chart_error_estimates(bench, pairs):
    """bench_error_estimates.png: each run's estimate of its error against the true error
    (log-log), the diagonal and the band of a factor 3; a note when no run estimates its error."""
    fig, ax = plt.subplots(figsize=(6.4, 5.2))
    if not pairs:
        ax.text(0.5, 0.5, "no estimates in these runs\n(summary.txt has no error_estimate_* key)", ha="center",
                va="center", transform=ax.transAxes)
        ax.set_xticks([])
        ax.set_yticks([])
    else:
        for quantity, marker in (("L2", "o"), ("normal_force", "s"), ("x_B", "^"), ("x_C", "v")):
            pts = [(b, a) for _, q, a, b in pairs if q == quantity]
            if pts:
                ax.loglog(*zip(*pts), marker, linestyle="none", label={"L2": "v, L2(Omega)", "normal_force": "normal force",
                                                                       "x_B": "x_B estimate (m)", "x_C": "x_C estimate (m)"}[quantity])
        values = [p[2] for p in pairs] + [p[3] for p in pairs]
        low, high = min(values) / 5, max(values) * 5
        line = [low, high]
        ax.loglog(line, line, "k-", linewidth=1, label="estimate = true error")
        ax.fill_between(line, [x / 3 for x in line], [3 * x for x in line], color="0.85", zorder=0,
                        label="within a factor 3")
        ax.set_xlim(low, high)
        ax.set_ylim(low, high)
        ax.legend(fontsize=7, loc="upper left")
    ax.set_xlabel("true error at T (against the reference; x_B, x_C: the estimates between the nodes)")
    ax.set_ylabel("the run's own estimate of its error (summary.txt)")
    ax.set_title("estimated against true error (uniform and adapted meshes)", fontsize=9)
    return style.save(fig, bench, "bench_error_estimates")


def print_error_estimates(pairs):
    """The largest ratios estimated/true and true/estimated over the runs that estimate their errors."""
    if not pairs:
        print("  error estimates: no estimates in these runs (no error_estimate_* key in summary.txt)")
        return
    over = max(pairs, key=lambda p: p[2] / p[3])
    under = max(pairs, key=lambda p: p[3] / p[2])
    print(f"  error estimates ({len(pairs)} pairs, uniform and adapted meshes): largest estimated/true {over[2] / over[3]:.2f} "
          f"({over[0]}, {over[1]}), largest true/estimated {under[3] / under[2]:.2f} ({under[0]}, {under[1]})")
    for quantity in ("L2", "normal_force", "x_B", "x_C"):
        ratios = [a / b for _, q, a, b in pairs if q == quantity]
        if ratios:
            inside = sum(1 / 3 <= x <= 3 for x in ratios)
            print(f"    {quantity:13s} estimated/true {min(ratios):.2f} to {max(ratios):.2f}, within a factor 3 on {inside} of {len(ratios)}")


def chart_adapted_mesh(bench, columns, rows):
    """The adapted mesh that first reaches the error of the uniform 264x132 mesh (or the most
    accurate adapted run) beside that uniform mesh: the zones of Gamma3 at T as coloured nodes,
    and a zoom on Gamma3 around x_B."""
    c = {name: i for i, name in enumerate(columns)}
    ok = [r for r in rows if r[c["converged"]] and not math.isnan(r[c["relative_error_L2"]])]
    uniform = [r for r in ok if r[c["run"]] == "wp-mesh-264x132"] or sorted(
        (r for r in ok if r[c["family"]] == "mesh"), key=lambda r: r[c["relative_error_L2"]])[:1]
    adapted = sorted((r for r in ok if r[c["family"]].startswith("adapt")), key=lambda r: r[c["wall"]])
    if not uniform or not adapted:
        return None
    target = uniform[0][c["relative_error_L2"]]
    adapted = [r for r in adapted if r[c["relative_error_L2"]] <= target][:1] or sorted(
        adapted, key=lambda r: r[c["relative_error_L2"]])[:1]
    fig, axes = plt.subplots(2, 2, figsize=(13, 6.2), gridspec_kw={"height_ratios": [2, 1]})
    for col, r in enumerate((adapted[0], uniform[0])):
        folder = os.path.join(bench, "runs", r[c["run"]])
        mesh = runfiles.read_msh22(os.path.join(folder, "mesh.msh"))
        table = runfiles.read_table(os.path.join(folder, "contact.txt"))
        x, y = table["x"], table["y"]
        kinds = style.run_zones(folder)
        zones = table.codes("zone", 0, len(kinds) - 1)
        xb, xc, _ = final_contact(folder)
        for ax, zoom in ((axes[0][col], False), (axes[1][col], True)):
            ax.triplot(mesh.xy[:, 0], mesh.xy[:, 1], mesh.triangles, color="0.3", linewidth=0.15)
            for zone in kinds:
                on = zones == zone.code
                if on.any():
                    ax.scatter(x[on], y[on], s=6 if zoom else 3, color=zone.color, zorder=3,
                               label=zone.name if not zoom else None)
            for edge in (xb, xc):
                if not math.isnan(edge) and edge < 1e299:
                    ax.axvline(edge, color="k", linestyle="--", linewidth=0.6)
            ax.set_aspect("equal")
            if not zoom:                                 # the corners where the solution is singular
                ax.annotate("clamp meets the traction", (0, 1), xytext=(0.25, 1.08), fontsize=7,
                            arrowprops={"arrowstyle": "->", "linewidth": 0.6})
                ax.annotate("clamp meets Gamma3", (0, 0), xytext=(0.25, -0.12), fontsize=7,
                            arrowprops={"arrowstyle": "->", "linewidth": 0.6})
                ax.set_ylim(-0.18, 1.15)
            if zoom:
                ax.set_xlim(0.3, 1.5)
                ax.set_ylim(-0.02, 0.2)
                ax.set_title(f"near Gamma3 (dashed: x_B = {xb:.4f}, x_C = {xc:.4f})", fontsize=8)
            else:
                ax.set_title(f"{r[c['run']]}: {r[c['vertices']]:.0f} vertices, relative L2 error "
                             f"{r[c['relative_error_L2']]:.2e}, {r[c['wall']]:.2f} s", fontsize=9)
                ax.legend(fontsize=6, loc="upper right", markerscale=3)
    return style.save(fig, bench, "bench_adapted_mesh")


def chart_iterations(bench, columns, rows):
    c = {name: i for i, name in enumerate(columns)}
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 4.5))
    styles = {("newton", "66x33"): "o-", ("newton", "132x66"): "o--", ("fixedpoint", "66x33"): "s-",
              ("fixedpoint", "132x66"): "s--"}
    colors = {"newton": "tab:blue", "fixedpoint": "tab:green"}
    for (mode, mesh), line in styles.items():
        pts = sorted((r[c["r"]], r[c["iterations_mean"]], r[c["step_over_floor"]], r[c["converged"]]) for r in rows
                     if r[c["mode"]] == mode and r[c["mesh"]] == mesh)
        ok = [p for p in pts if p[3]]
        if ok:
            left.loglog([p[0] for p in ok], [p[1] for p in ok], line, color=colors[mode], label=f"{mode}, {mesh}")
            right.loglog([p[0] for p in ok], [p[2] for p in ok], line, color=colors[mode], label=f"{mode}, {mesh}")
        for p in pts:
            if not p[3]:
                for ax in (left, right):
                    ax.axvline(p[0], color=colors[mode], linestyle=":", linewidth=1)
    left.set_xlabel("augmentation factor r")
    left.set_ylabel("iterations per time step (mean over the run)")
    left.set_title("iterations against r (dotted: did not converge)")
    left.legend(fontsize=7)
    right.set_xlabel("augmentation factor r")
    right.set_ylabel("median step / one back-substitution (same run)")
    right.set_title("time per step against r, in floors")
    right.axhline(2, color="0.6", linewidth=1)
    right.legend(fontsize=7)
    return style.save(fig, bench, "bench_iterations")


def main():
    runfiles.check_arguments("bench.py")                   # a name not in UTF-8: refused before anything
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bench", required=True)
    parser.add_argument("--reference", required=True)
    args = parser.parse_args()
    runfiles.check_outputs("bench.py", [args.bench])       # not written through a symbolic link
    columns, rows = steps_table(args.bench)
    columns3d, rows3d = steps_table(args.bench, "steps3d-", "steps3d.txt")   # the 3D slab: its own table
    c = {name: i for i, name in enumerate(columns)}
    print(f"  {'run':40s} {'dofs':>7s} {'floor ms':>9s} {'umfpack ms':>10s} {'step ms':>9s} {'ratio':>6s} {'vs umf':>6s} "
          f"{'it/step':>7s} {'setup s':>8s} {'MB':>6s}")
    for r in rows + rows3d:
        setup = (r[c["time_mesh"]] + r[c["time_assembly"]] + r[c["time_factorization"]] + r[c["time_condensation"]]
                 + r[c["time_record_setup"]])
        print(f"  {r[0]:40s} {r[c['dofs']]:7d} {1e3 * r[c['time_backsubstitution']]:9.3f} "
              f"{1e3 * r[c['time_backsubstitution_umfpack']]:10.3f} "
              f"{1e3 * r[c['time_step_median']]:9.3f} {r[c['step_over_floor']]:6.2f} {r[c['step_over_umfpack_floor']]:6.2f} "
              f"{r[c['iterations_mean']]:7.2f} "
              f"{setup:8.2f} {r[c['peak_memory_MB']]:6.0f}")
    chart_cost_per_step(args.bench, columns, rows, rows3d)
    acolumns, arows = steps_adapted_table(args.bench)
    a = {name: i for i, name in enumerate(acolumns)}
    for r in arows:
        print(f"  step / floor on {r[0]:20s} {r[a['vertices']]:7d} vertices, {r[a['contact_slots']]:4d} contact unknowns: "
              f"median {r[a['step_over_floor']]:.2f} ({r[a['step_over_floor_min']]:.2f}-{r[a['step_over_floor_max']]:.2f}, "
              f"{r[a['runs']]} runs); against the floor before the loop {r[a['step_over_floor_before']]:.2f}")
    icolumns, irows = iterations_table(args.bench)
    chart_iterations(args.bench, icolumns, irows)
    wcolumns, wrows = work_precision_table(args.bench, args.reference)
    chart_work_precision(args.bench, wcolumns, wrows)
    w = {name: i for i, name in enumerate(wcolumns)}
    for r in wrows:
        print(f"  {r[0]:28s} {r[w['vertices']]:7.0f} vertices, wall {r[w['wall']]:7.2f} s, relative L2 error "
              f"{r[w['relative_error_L2']]:.3e}, x_B {r[w['error_x_B']]:.1e} m (estimate {r[w['error_x_B_estimate']]:.1e}), "
              f"x_C {r[w['error_x_C']]:.1e} m (estimate {r[w['error_x_C_estimate']]:.1e}), normal force "
              f"{r[w['relative_error_normal_force']]:.1e}"
              + (f", solver error {r[w['relative_solver_error_L2']]:.3e}" if not math.isnan(r[w['relative_solver_error_L2']]) else ""))
    rates_and_margin(args.bench, args.reference, wcolumns, wrows)
    pairs = estimate_pairs(wcolumns, wrows)
    print_error_estimates(pairs)
    chart_error_estimates(args.bench, pairs)
    chart_adapted_mesh(args.bench, wcolumns, wrows)
    ic = {name: i for i, name in enumerate(icolumns)}
    for r in irows:
        print(f"  {r[ic['mode']]:10s} {r[ic['mesh']]:7s} r {r[ic['r']]:<7g} "
              + (f"{r[ic['iterations_mean']]:6.2f} it/step (max {r[ic['iterations_max']]:.0f}), step/floor {r[ic['step_over_floor']]:.2f}"
                 if r[ic["converged"]] else "did not converge"))


if __name__ == "__main__":
    runfiles.run_tool("bench.py", main)
