#!/usr/bin/python3
"""Tables of plots/stability.sh: one line per point, the cross-method agreement, the
hopeless settings and a summary, from the records runs/SWEEP/ID.rec and the summary.txt
of each converged run.

Usage: stability_tables.py --results DIR        (DIR = results/stability)
Writes DIR/SWEEP.txt for every sweep, DIR/agreement.txt, DIR/hopeless.txt and
DIR/summary.txt; exits 1 if an agreement pair or a hopeless setting failed its check.

Failure modes (column mode):
  ok         converged, every end-of-run check passed (exit 0)
  cycling    iteration cap; the residual at the failing step repeats exactly with a
             period p of 2 to 4 iterations (probes at cap-1 ... cap-4)
  stuck      iteration cap; the residual repeats every iteration (the iterate no longer moves)
  floor      iteration cap with a residual within 100 tol that no longer decreases: the
             round-off floor of the residual is above tol
  diverging  iteration cap; residual(cap) > 10 residual(cap/2)
  stalled    iteration cap; residual(cap) between 0.5 and 10 times residual(cap/2)
  slow       iteration cap; residual(cap) < 0.5 residual(cap/2): still converging
  cap        iteration cap, not classified (the probes failed at another step)
  nonfinite  exit 5 (non-finite residual, velocity or stress)
  check      exit 9 (an end-of-run check failed)
  timeout    killed by the time limit of the sweep
  error      any other exit
"""
import argparse
import glob
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import numpy as np

import runfiles

AGREEMENT_RTOL = 1e-8
METHOD_OPTIONS = ("solver", "safeguard", "penaltyform", "r", "maxit", "out")
# The paper box of the brief: mu 0..1.5, load 1..100 (0.1x to 10x), k 1e-4..0.2, eps >= 1e-12.
COLUMNS = ("id body method problem solver safeguard penaltyform nx ny T dt mu load eps r maxit exit mode period "
           "fail_step fail_iterations fail_residual half_residual iter_mean iter_max steps fallbacks sweeps "
           "check_constraint check_penalty_law check_energy_residual wall_s").split()


def read_record(path):
    """One record ID.rec of plots/stability.sh ('key=value' lines), with the options of its
    run: given (from its command line) and opts (all of them, runfiles.effective_options)."""
    record = runfiles.Values(path)
    for line in runfiles.read_lines(path):
        key, _, value = line.partition("=")
        record[key] = value
    words = record["options"].split()
    given = {words[i].lstrip("-"): words[i + 1] for i in range(0, len(words) - 1, 2)}
    try:
        record["opts"] = runfiles.effective_options(given)
    except runfiles.InputError as error:
        raise runfiles.InputError(f"{path}: {error}") from None
    record["given"] = given
    return record


def method_name(o):
    prefix = "orig" if o["problem"] == "original" else "pen"
    if o["solver"] == "newton":
        form = [o["penaltyform"]] if o["problem"] == "penalty" else []
        view = ["script"] if o["kernel"] == "script" else []
        return "-".join([prefix, "newton"] + view + form + [o["safeguard"]])
    if o["solver"] == "fixedpoint":
        return f"{prefix}-fixedpoint"
    return f"{prefix}-{o['solver']}"


def same(a, b):
    return a == b or abs(a - b) <= 1e-9 * max(abs(a), abs(b))


def classify(record):
    """mode, period, failing step, its iterations, residual, residual at cap/2."""
    code = record.integer("exit")
    none = (float("nan"),) * 4
    if code == 0:
        return ("ok", 0) + none
    if code in (124, 137):
        return ("timeout", 0) + none
    failure = runfiles.solver_failure(record["message"])
    fail = (failure.step, failure.iterations, failure.residual) if failure else (float("nan"),) * 3
    if code == 5:
        return ("nonfinite", 0) + fail + (float("nan"),)
    if code == 9:
        return ("check", 0) + none
    if code == 4 and failure and "stalled" in failure.mode:     # the fixed point's own stall test
        return ("stalled", 0) + fail + (float("nan"),)
    if code != 4 or not failure or "iteration cap" not in failure.mode:
        return ("error", 0) + none
    step, iterations, residual = fail
    probes = {}
    for item in filter(None, record["probes"].split(",")):
        cap, pstep, pres = item.split(":")
        if pstep != "ok" and int(pstep) == step and pres != "-":
            probes[int(cap)] = float(pres)
    cap = iterations
    half = probes.get(cap // 2, float("nan"))
    tol = record["opts"].real("tol")
    period = next((d for d in range(1, 5) if cap - d in probes and same(probes[cap - d], residual)), 0)
    if residual <= 100 * tol and (period or half <= 2 * residual):
        mode = "floor"
    elif period == 1:
        mode = "stuck"
    elif period:
        mode = "cycling"
    elif math.isnan(half):
        mode = "cap"
    elif residual > 10 * half:
        mode = "diverging"
    elif residual >= 0.5 * half:
        mode = "stalled"
    else:
        mode = "slow"
    return (mode, period) + fail + (half,)


def fmt(value):
    if isinstance(value, str):
        return value if value else "-"
    if isinstance(value, (int, np.integer)):
        return str(value)
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "nan"
    return f"{value:.6g}"


def build_rows(results):
    rows = []
    for path in sorted(glob.glob(os.path.join(results, "runs", "*", "*.rec"))):
        record = read_record(path)
        o = record["opts"]
        folder = path[:-4]
        converged = record["exit"] == "0" and os.path.isfile(os.path.join(folder, "summary.txt"))
        summary = runfiles.read_summary(folder) if converged else runfiles.Values(folder)
        mode, period, step, iterations, residual, half = classify(record)

        def num(key):
            return summary.real(key) if key in summary else float("nan")
        steps = num("steps")
        row = {"sweep": record["sweep"], "id": record["id"], "body": record["given"].get("scene", "paper"),
               "method": method_name(o), "problem": o["problem"],
               "solver": o["solver"], "safeguard": o["safeguard"], "penaltyform": o["penaltyform"],
               "nx": o.integer("nx"), "ny": o.integer("ny"), "T": o.real("T"), "dt": o.real("dt"),
               "mu": o.real("mu"), "load": o.real("load"), "eps": o.real("eps"), "r": o.real("r"),
               "maxit": o.integer("maxit"), "exit": record.integer("exit"), "mode": mode, "period": period,
               "fail_step": step, "fail_iterations": iterations, "fail_residual": residual, "half_residual": half,
               "iter_mean": num("iterations_total") / steps if steps else float("nan"),
               "iter_max": num("iterations_max"), "steps": steps, "fallbacks": num("newton_fallbacks"),
               "sweeps": num("fixed_point_sweeps"), "check_constraint": num("check_constraint"),
               "check_penalty_law": num("check_penalty_law"), "check_energy_residual": num("check_energy_residual"),
               "wall_s": record.real("wall"), "folder": folder, "record": record}
        rows.append(row)
    return rows


def write_sweep(path, rows, title):
    runfiles.write_table(path, [title, "written by plots/stability_tables.py from runs/*/*.rec; mode: see its docstring;",
                             "iter_mean = iterations_total/steps, iter_max = iterations_max (converged runs);",
                             "fail_*: the failing step, its iteration count and residual; half_residual: the residual",
                             "of the same step with -maxit cap/2; period: of an exact cycle (0 none); wall_s: seconds"],
                      COLUMNS, [[fmt(row[c]) for c in COLUMNS] for row in rows])


def physics_key(row):
    o = row["record"]["opts"]
    return tuple(sorted((k, v) for k, v in o.items()
                        if k not in METHOD_OPTIONS and not (k == "eps" and o["problem"] == "original")
                        and k != "penaltyform"))


def method_rank(row):
    o = row["record"]["opts"]
    default = (o["solver"] == "newton" and o["safeguard"] == "on" and o["penaltyform"] == "compliant"
               and o.real("r") == 1.0)
    return (0 if default else 1, o["solver"] != "newton", row["sweep"], row["id"])


def max_difference(folder, other, floors):
    """Largest relative differences of the columns compared: scale = the column's largest
    |value|, and the same with the scale at least the law's scale of the column (p(g) for
    stresses, g for velocities), so that a column that is zero up to round-off (lambda_tau
    when mu = 0) does not count as a difference of 1."""
    plain, floored = 0.0, 0.0
    for name, cols in (("contact.txt", ("v_nu", "v_tau", "p_nu", "lambda_nu", "lambda_tau")),
                       ("fields.txt", ("u_x", "u_y", "v_x", "v_y"))):
        a = runfiles.read_table(os.path.join(folder, name))
        b = runfiles.read_table(os.path.join(other, name))
        for col in cols:
            x, y = a[col], b[col]
            scale = max(np.abs(x).max(), np.abs(y).max(), 1e-300)
            diff = np.abs(x - y).max()
            plain = max(plain, diff / scale)
            floored = max(floored, diff / max(scale, floors.get(col, 0.0)))
    return plain, floored


def agreement(rows):
    groups = {}
    for row in rows:
        if row["mode"] == "ok" and row["sweep"] != "hopeless":
            groups.setdefault(physics_key(row), []).append(row)
    pairs = []
    for key, members in groups.items():
        seen, unique = set(), []
        for row in sorted(members, key=method_rank):
            mkey = tuple(row["record"]["opts"][k] for k in ("solver", "safeguard", "penaltyform", "r"))
            if mkey not in seen:
                seen.add(mkey)
                unique.append(row)
        if len(unique) < 2:
            continue
        reference = unique[0]
        law = runfiles.read_table(os.path.join(reference["folder"], "contact.txt"))     # the law's scales: g, p(g)
        g, force = float(law["g"].max()), float(law["force_scale"].max())
        floors = {"v_nu": g, "v_tau": g, "v_x": g, "v_y": g, "p_nu": force, "lambda_nu": force, "lambda_tau": force}
        for other in unique[1:]:
            differences = runfiles.compare_runs(reference["folder"], other["folder"], AGREEMENT_RTOL)
            plain, floored = max_difference(reference["folder"], other["folder"], floors)
            pairs.append((reference, other, plain, floored, not differences, floored <= AGREEMENT_RTOL))
    return pairs


def label(row):
    return f"{row['method']}(r={fmt(row['r'])})"


def write_agreement(path, pairs):
    with open(path, "w") as f:
        f.write("# cross-method agreement: every converged run against the reference run of the same discrete\n")
        f.write("# problem (same scene, mesh, T, k, mu, load, tol; eps for the penalty), i.e. differing only in\n")
        f.write("# -solver, -safeguard, -penaltyform, -r, -maxit. Reference: Newton with safeguards, compliant\n")
        f.write("# form, r = 1 when it converged. Columns compared: contact.txt v_nu v_tau p_nu lambda_nu\n")
        f.write("# lambda_tau, fields.txt u_x u_y v_x v_y.\n")
        f.write("#   max_rel: largest relative difference, scale = the column's largest |value|; check_results = 1\n")
        f.write(f"#     if tests/check_results.py --compare (edp/runfiles.py, compare_runs) passes at --rtol {AGREEMENT_RTOL:g}\n")
        f.write("#   max_rel_floor: the same with the scale at least p(g) (force_scale: stresses) or g (velocities):\n")
        f.write("#     a column that is zero up to round-off (lambda_tau at mu = 0) is not a difference of 1\n")
        f.write(f"#   ok = max_rel_floor <= {AGREEMENT_RTOL:g}\n")
        f.write("# problem nx ny T dt mu load eps reference other other_sweep other_id max_rel check_results max_rel_floor ok\n")
        for ref, other, plain, floored, passed, ok in pairs:
            eps = fmt(ref["eps"]) if ref["problem"] == "penalty" else "-"
            f.write(" ".join([ref["problem"], fmt(ref["nx"]), fmt(ref["ny"]), fmt(ref["T"]), fmt(ref["dt"]),
                              fmt(ref["mu"]), fmt(ref["load"]), eps, label(ref), label(other), other["sweep"],
                              other["id"], f"{plain:.3e}", "1" if passed else "0", f"{floored:.3e}",
                              "1" if ok else "0"]) + "\n")


def write_hopeless(path, rows):
    checks = []
    with open(path, "w") as f:
        f.write("# hopeless settings: each must exit non-zero, print its error message and leave no output folder\n")
        f.write("# (neither OUT nor OUT.partial.PID). ok = all three. The message follows on the next line.\n")
        f.write("# id exit mode message_printed output_left ok options\n")
        for row in rows:
            rec = row["record"]
            printed = bool(rec["message"])
            left = rec["output_left"] == "1"
            ok = row["exit"] != 0 and printed and not left
            checks.append(ok)
            f.write(f"{row['id']} {row['exit']} {row['mode']} {int(printed)} {int(left)} {int(ok)} "
                    f"{rec['options'].replace(' ', '~')}\n")
            f.write(f"#   {rec['message']}\n")
    return checks


def command_line(row):
    return "./run.sh solve " + row["record"]["options"]


def write_summary(path, rows, pairs, hopeless_checks, results):
    lines = ["# plots/stability.sh summary (plots/stability_tables.py)"]
    sweeps = sorted({r["sweep"] for r in rows})
    lines.append(f"points {len(rows)}")
    lines.append(f"converged {sum(r['mode'] == 'ok' for r in rows)}")
    lines.append(f"wall_runs_sum {sum(r['wall_s'] for r in rows):.1f}")
    lines.append("")
    lines.append("# per sweep and method: points, converged, failures by mode, mean and max iterations per step")
    lines.append("# sweep method points ok failures iter_mean(median over converged) iter_max(max) wall_sum")
    for sweep in sweeps:
        methods = sorted({r["method"] for r in rows if r["sweep"] == sweep})
        for method in methods:
            sel = [r for r in rows if r["sweep"] == sweep and r["method"] == method]
            ok = [r for r in sel if r["mode"] == "ok"]
            modes = {}
            for r in sel:
                if r["mode"] != "ok":
                    modes[r["mode"]] = modes.get(r["mode"], 0) + 1
            fails = ",".join(f"{m}:{n}" for m, n in sorted(modes.items())) or "-"
            mean = np.median([r["iter_mean"] for r in ok]) if ok else float("nan")
            mx = max((r["iter_max"] for r in ok), default=float("nan"))
            lines.append(f"{sweep} {method} {len(sel)} {len(ok)} {fails} {fmt(mean)} {fmt(mx)} "
                         f"{sum(r['wall_s'] for r in sel):.1f}")
    lines.append("")
    lines.append(f"agreement_pairs {len(pairs)}")
    lines.append(f"agreement_failed {sum(not p[5] for p in pairs)}")
    lines.append(f"agreement_check_results_failed {sum(not p[4] for p in pairs)}")
    if pairs:
        lines.append(f"agreement_max_rel_floor {max(p[3] for p in pairs):.3e}")
        lines.append(f"agreement_max_rel {max(p[2] for p in pairs):.3e}")
        kinds = {}
        for ref, other, plain, floored, passed, ok in pairs:
            k = other["method"] + ("_other_r" if other["r"] != ref["r"] and other["solver"] == "newton" else "")
            kinds.setdefault(k, []).append((floored, plain, passed))
        lines.append("# by method of the other run: pairs, largest max_rel_floor, largest max_rel, check_results failures")
        for k, v in sorted(kinds.items()):
            lines.append(f"agreement {k} {len(v)} {max(x[0] for x in v):.3e} {max(x[1] for x in v):.3e} "
                         f"{sum(not x[2] for x in v)}")
    lines.append("")
    lines.append(f"hopeless_settings {len(hopeless_checks)}")
    lines.append(f"hopeless_failed_loudly {sum(hopeless_checks)}")
    lines.append("")
    for solver, shipped in (("newton", 50), ("fixedpoint", 500)):
        lines.append(f"# failures of the {solver} default inside the paper box (mu 0..1.5, load 1..100, k 1e-4..0.2,")
        lines.append(f"# eps >= 1e-12): safeguards on, compliant form, r = 1 (box sweep: maxit {shipped} as")
        lines.append("# shipped; the other sweeps: their cap), with the command line that reproduces each")
        defaults = [r for r in rows if r["sweep"] not in ("hopeless", "mesh", "bodies") and r["solver"] == solver
                    and r["safeguard"] == "on" and r["penaltyform"] == "compliant" and r["r"] == 1.0
                    and 0 <= r["mu"] <= 1.5 and 1 <= r["load"] <= 100 and 1e-4 <= r["dt"] <= 0.2
                    and r["eps"] >= 1e-12]
        failed = [r for r in defaults if r["mode"] != "ok"]
        prefix = "" if solver == "newton" else "fixedpoint_"
        lines.append(f"{prefix}default_points {len(defaults)}")
        lines.append(f"{prefix}default_failures {len(failed)}")
        for r in failed:
            lines.append(f"#   {r['sweep']} {r['id']} {r['mode']}: {r['record']['message']}")
            lines.append(f"#   {command_line(r)}")
    bodies = [r for r in rows if r["sweep"] == "bodies"]
    if bodies:
        lines.append("")
        lines.append("# the hard bodies at the defaults of each method (bodies sweep): failures per method")
        for method in sorted({r["method"] for r in bodies}):
            sel = [r for r in bodies if r["method"] == method]
            lines.append(f"bodies_failures {method} {sum(r['mode'] != 'ok' for r in sel)} of {len(sel)}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--results", required=True, help="the stability folder (results/stability)")
    args = parser.parse_args()
    rows = build_rows(args.results)
    if not rows:
        print(f"stability_tables.py: error: no records in {args.results}/runs", file=sys.stderr)
        sys.exit(1)
    for sweep in sorted({r["sweep"] for r in rows}):
        sel = [r for r in rows if r["sweep"] == sweep]
        sel.sort(key=lambda r: (r["method"], r["nx"] * r["ny"], r["eps"], r["r"], -r["dt"], r["mu"], r["load"], r["id"]))
        write_sweep(os.path.join(args.results, f"{sweep}.txt"), sel, f"sweep {sweep}: one line per point")
    pairs = agreement(rows)
    write_agreement(os.path.join(args.results, "agreement.txt"), pairs)
    hopeless = [r for r in rows if r["sweep"] == "hopeless"]
    checks = write_hopeless(os.path.join(args.results, "hopeless.txt"), hopeless)
    write_summary(os.path.join(args.results, "summary.txt"), rows, pairs, checks, args.results)
    bad_pairs = sum(not p[5] for p in pairs)
    print(f"stability: {len(rows)} points, {sum(r['mode'] == 'ok' for r in rows)} converged; agreement "
          f"{len(pairs) - bad_pairs}/{len(pairs)} pairs within {AGREEMENT_RTOL:g}"
          + (f" (largest {max(p[3] for p in pairs):.1e}; check_results.py --compare without a floor: "
             f"{sum(not p[4] for p in pairs)} fail)" if pairs else "")
          + f"; hopeless settings failing loudly {sum(checks)}/{len(checks)}")
    sys.exit(1 if bad_pairs or not all(checks) else 0)


if __name__ == "__main__":
    runfiles.run_tool("stability_tables.py", main)
