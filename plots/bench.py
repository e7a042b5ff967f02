#!/usr/bin/python3
"""Tables and charts of the benchmark (tests/bench.sh, ./run.sh bench).

Reads the run folders DIR/runs/NAME that tests/bench.sh makes (summary.txt of edp/solve.edp,
NAME.time with the wall seconds and peak memory of the process, NAME.error and
NAME.solver_error from edp/compare.edp) and writes into DIR
  steps.txt, iterations.txt, work_precision.txt   (plain text, '#' header naming the columns)
  bench_cost_per_step.png, bench_work_precision.png, bench_iterations.png
Usage: bench.py --bench DIR --reference RUN_DIR
"""
import argparse
import math
import os
import re

import suite

plt = suite.pyplot()
NAN = float("nan")


def run_record(bench, name):
    """What one run measured: its summary (empty if it failed), wall, peak memory, error."""
    folder = os.path.join(bench, "runs", name)
    record = {"name": name, "converged": os.path.isfile(os.path.join(folder, "summary.txt"))}
    record["summary"] = suite.read_summary(folder) if record["converged"] else {}
    wall, peak = NAN, NAN
    if os.path.isfile(folder + ".time"):
        words = open(folder + ".time").read().split()
        try:
            wall, peak = float(words[-2]), float(words[-1]) / 1024.0
        except (ValueError, IndexError):
            pass
    record["wall"], record["peak_MB"] = wall, peak
    for key, suffix in (("error", ".error"), ("solver_error", ".solver_error")):
        record[key] = {}
        if os.path.isfile(folder + suffix):
            words = open(folder + suffix).read().split()
            record[key] = {words[i]: float(words[i + 1]) for i in range(0, len(words) - 1, 2)}
    return record


def value(record, key):
    try:
        return float(record["summary"].get(key, NAN))
    except ValueError:
        return NAN


def all_names(bench, prefix):
    """Every run started with this prefix, converged or not (its .time file exists)."""
    runs = os.path.join(bench, "runs")
    found = {n[:-5] for n in os.listdir(runs) if n.endswith(".time") and n.startswith(prefix)}
    return sorted(found)


def steps_table(bench):
    rows = []
    for name in all_names(bench, "steps-"):
        m = re.match(r"steps-(\d+)x(\d+)-(\w+)-(original|penalty)(.*)", name)
        if not m:
            continue
        r = run_record(bench, name)
        steps = value(r, "steps")
        its = value(r, "iterations_total")
        backsub, median = value(r, "time_backsubstitution"), value(r, "time_step_median")
        umfpack = value(r, "time_backsubstitution_umfpack")
        rows.append([name, f"{m.group(1)}x{m.group(2)}", int(value(r, "dofs")) if r["converged"] else -1,
                     int(value(r, "contact_slots")) if r["converged"] else -1, m.group(3), m.group(4),
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
    suite.write_table(os.path.join(bench, "steps.txt"),
                      ["cost per time step: time_step_median (CPU s) against the floor time_backsubstitution (one",
                       "back-substitution with the kernel's Cholesky factor of S, median of 21, same run) and against",
                       "time_backsubstitution_umfpack (one back-substitution with FreeFEM's default UMFPACK, median of 5,",
                       "same run; nan when not measured); setup times and wall in wall seconds; peak memory of the",
                       "whole FreeFEM process"], columns, rows)
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
    suite.write_table(os.path.join(bench, "iterations.txt"),
                      ["iterations and cost per step against the augmentation factor r (r_j = r/(Dw)_jj; for the fixed",
                       "point does not use r: every residual is read at r = 1), T = 1, k = 0.01; step_over_floor =",
                       "time_step_median / time_backsubstitution (CPU seconds, same run); converged 0: exit 4 at the cap",
                       "(Newton 200, fixed point 2000)"], columns, rows)
    return columns, rows


def work_precision_table(bench, reference):
    rows = []
    for name in all_names(bench, "wp-"):
        r = run_record(bench, name)
        family = name.split("-")[1]
        if family == "tol":                              # wp-tol-SOLVER-TOL
            family = "tol-" + name.split("-")[2]
        e, se = r["error"], r["solver_error"]
        rel = e.get("error_L2", NAN) / e["norm_L2"] if e.get("norm_L2") else NAN
        srel = se.get("error_L2", NAN) / se["norm_L2"] if se.get("norm_L2") else NAN
        rows.append([name, family, int(r["converged"]), r["wall"], e.get("error_L2", NAN), rel, e.get("error_gamma3", NAN),
                     srel, value(r, "time_loop")])
    columns = "run family converged wall error_L2 relative_error_L2 error_gamma3 relative_solver_error_L2 time_loop".split()
    suite.write_table(os.path.join(bench, "work_precision.txt"),
                      [f"error at T against the reference {os.path.basename(reference)} (edp/compare.edp:",
                       "||v - v_ref||_L2(Omega) with the consistent mass matrix of the reference mesh, and max |dv_nu| on",
                       "Gamma3), against the wall seconds of the whole process; relative_solver_error_L2 (the tol family",
                       "only): the same distance to the 66x33 run solved to tol 1e-13, relative; time_loop: wall seconds",
                       "of the time loop alone (summary.txt)"], columns, rows)
    return columns, rows


def chart_cost_per_step(bench, columns, rows):
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
    for (mode, problem), style in ((("newton", "original"), "o-"), (("newton", "penalty"), "s--"),
                                   (("script", "original"), "D-"), (("full", "original"), "^-"),
                                   (("fixedpoint", "original"), "v-")):
        pts = sorted((r[c["dofs"]], r[c["time_step_median"]]) for r in rows
                     if r[c["mode"]] == mode and r[c["problem"]] == problem and r[c["converged"]]
                     )
        if pts:
            left.loglog(*zip(*pts), style, label=f"{mode}, {problem}")
            highest = max(highest, max(p[1] for p in pts))
    if floor_pts:
        left.loglog(*zip(*floor_pts), "k:", linewidth=2, label="floor: one back-substitution (kernel, Cholesky)")
        left.loglog([p[0] for p in floor_pts], [2 * p[1] for p in floor_pts], color="0.6", linewidth=1,
                    label="2 x floor")
    if umfpack_pts:
        left.loglog(*zip(*umfpack_pts), "k-.", linewidth=1, label="one back-substitution with FreeFEM's UMFPACK")
    left.set_xlabel("degrees of freedom")
    left.set_ylabel("CPU seconds per time step (median)")
    left.set_title("cost of a time step")
    if highest > 0:
        left.set_ylim(top=highest * 300)        # room for the legend above the slowest mode
    left.legend(fontsize=7, loc="upper right")
    for key, style in (("time_mesh", "v-"), ("time_assembly", "o-"), ("time_factorization", "s-"),
                       ("time_condensation", "^-"), ("time_record_setup", "D-")):
        pts = sorted({(r[c["dofs"]], r[c[key]]) for r in rows
                      if r[c["mode"]] == "newton" and r[c["problem"]] == "original" and r[c["converged"]]})
        if pts:
            right.loglog(*zip(*pts), style, label=key.replace("time_", ""))
    right.set_xlabel("degrees of freedom")
    right.set_ylabel("wall seconds, once per run")
    right.set_title("setup costs (Newton, original)")
    right.legend(fontsize=7)
    return suite.save(fig, bench, "bench_cost_per_step")


def parameter_order(name):
    """Sort key of a work-precision run: its mesh size, time step or eps, finest last."""
    numbers = [float(x) for x in re.findall(r"\d+(?:\.\d+)?(?:e-?\d+)?", name.split("-", 2)[-1])]
    if not numbers:
        return 0.0
    return numbers[0] if "mesh" in name else -numbers[0]


def chart_work_precision(bench, columns, rows):
    c = {name: i for i, name in enumerate(columns)}
    fig, (ax, solver_ax) = plt.subplots(1, 2, figsize=(12, 4.5))
    labels = {"mesh": "mesh h (k = 0.01)", "dt": "time step k (66x33)", "full": "full-system Newton (66x33)",
              "penalty": "penalty eps (66x33, against the original reference)",
              "tol-newton": "Newton, tol 1e-4 ... 1e-10 (66x33)", "tol-fixedpoint": "fixed point, tol 1e-4 ... 1e-10 (66x33)"}
    # label offsets per family, so that the labels around the 66x33 point do not overlap
    offsets = {"mesh": ((3, 3), "left"), "dt": ((3, -10), "left"), "full": ((3, 3), "left"),
               "penalty": ((-4, 3), "right"), "tol-newton": ((3, -8), "left"), "tol-fixedpoint": ((-4, -8), "right")}
    for family, marker in (("mesh", "o-"), ("dt", "s-"), ("full", "^"), ("penalty", "v-"),
                           ("tol-newton", "P-"), ("tol-fixedpoint", "X-")):
        pts = sorted(((r[c["wall"]], r[c["relative_error_L2"]], r[c["run"]], r[c["relative_solver_error_L2"]],
                       r[c["time_loop"]]) for r in rows
                      if r[c["family"]] == family and r[c["converged"]] and not math.isnan(r[c["relative_error_L2"]])),
                     key=lambda p: parameter_order(p[2]))
        if not pts:
            continue
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker, label=labels[family])
        for p in pts:
            ax.annotate(p[2].split("-")[-1] if family.startswith("tol") else p[2].split("-", 2)[-1], (p[0], p[1]),
                        fontsize=6, xytext=offsets[family][0], textcoords="offset points", ha=offsets[family][1])
        if family.startswith("tol"):
            sol = [p for p in pts if p[3] > 0]
            if sol:
                solver_ax.loglog([p[4] for p in sol], [p[3] for p in sol], marker, label=labels[family])
                for p in sol:
                    solver_ax.annotate("tol " + p[2].split("-")[-1], (p[4], p[3]), fontsize=6, xytext=(3, 3),
                                       textcoords="offset points")
    ax.set_xlabel("wall seconds of the whole run (FreeFEM start-up included)")
    ax.set_ylabel(r"$\|v - v_{ref}\|_{L^2(\Omega)} / \|v_{ref}\|$ at T")
    ax.set_title("work and precision (against the fine reference)")
    ax.legend(fontsize=7)
    solver_ax.set_xlabel("wall seconds of the time loop (66x33, 100 steps)")
    solver_ax.set_ylabel("relative L2 distance at T to the same mesh at tol 1e-13")
    solver_ax.set_title("what the tolerance buys each solver")
    solver_ax.legend(fontsize=7)
    return suite.save(fig, bench, "bench_work_precision")


def chart_iterations(bench, columns, rows):
    c = {name: i for i, name in enumerate(columns)}
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 4.5))
    styles = {("newton", "66x33"): "o-", ("newton", "132x66"): "o--", ("fixedpoint", "66x33"): "s-",
              ("fixedpoint", "132x66"): "s--"}
    colors = {"newton": "tab:blue", "fixedpoint": "tab:green"}
    for (mode, mesh), style in styles.items():
        pts = sorted((r[c["r"]], r[c["iterations_mean"]], r[c["step_over_floor"]], r[c["converged"]]) for r in rows
                     if r[c["mode"]] == mode and r[c["mesh"]] == mesh)
        ok = [p for p in pts if p[3]]
        if ok:
            left.loglog([p[0] for p in ok], [p[1] for p in ok], style, color=colors[mode], label=f"{mode}, {mesh}")
            right.loglog([p[0] for p in ok], [p[2] for p in ok], style, color=colors[mode], label=f"{mode}, {mesh}")
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
    return suite.save(fig, bench, "bench_iterations")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bench", required=True)
    parser.add_argument("--reference", required=True)
    args = parser.parse_args()
    columns, rows = steps_table(args.bench)
    c = {name: i for i, name in enumerate(columns)}
    print(f"  {'run':40s} {'dofs':>7s} {'floor ms':>9s} {'umfpack ms':>10s} {'step ms':>9s} {'ratio':>6s} {'vs umf':>6s} "
          f"{'it/step':>7s} {'setup s':>8s} {'MB':>6s}")
    for r in rows:
        setup = (r[c["time_mesh"]] + r[c["time_assembly"]] + r[c["time_factorization"]] + r[c["time_condensation"]]
                 + r[c["time_record_setup"]])
        print(f"  {r[0]:40s} {r[c['dofs']]:7d} {1e3 * r[c['time_backsubstitution']]:9.3f} "
              f"{1e3 * r[c['time_backsubstitution_umfpack']]:10.3f} "
              f"{1e3 * r[c['time_step_median']]:9.3f} {r[c['step_over_floor']]:6.2f} {r[c['step_over_umfpack_floor']]:6.2f} "
              f"{r[c['iterations_mean']]:7.2f} "
              f"{setup:8.2f} {r[c['peak_memory_MB']]:6.0f}")
    chart_cost_per_step(args.bench, columns, rows)
    icolumns, irows = iterations_table(args.bench)
    chart_iterations(args.bench, icolumns, irows)
    wcolumns, wrows = work_precision_table(args.bench, args.reference)
    chart_work_precision(args.bench, wcolumns, wrows)
    for r in wrows:
        print(f"  {r[0]:28s} wall {r[3]:7.2f} s  relative L2 error {r[5]:.3e}  max |dv_nu| on Gamma3 {r[6]:.3e}"
              + (f"  solver error {r[7]:.3e}" if not math.isnan(r[7]) else ""))
    ic = {name: i for i, name in enumerate(icolumns)}
    for r in irows:
        print(f"  {r[ic['mode']]:10s} {r[ic['mesh']]:7s} r {r[ic['r']]:<7g} "
              + (f"{r[ic['iterations_mean']]:6.2f} it/step (max {r[ic['iterations_max']]:.0f}), step/floor {r[ic['step_over_floor']]:.2f}"
                 if r[ic["converged"]] else "did not converge"))


if __name__ == "__main__":
    suite.run_tool("bench.py", main)
