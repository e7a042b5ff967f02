#!/usr/bin/python3
"""Tables of the paper's section 5 from the outputs of edp/solve.edp.

Usage:
  tables.py --results DIR
writes
  DIR/zones.txt               one row per run: the zones on Gamma3 at T next to the paper's
  DIR/eps-study/eps_study.txt one row per eps: ||v_eps - v|| at T against DIR/paper-original,
                              and the least-squares slope of log(error) vs log(eps) on the
                              smallest eps (header lines '# slope_tail' and '# tail_eps')
  DIR/choices/choices.txt     one row per run of DIR/choices: its differences at T from the
                              paper run of the same problem (DIR/paper-original or -penalty)
and prints a short version of each on stdout.
  tables.py --compare REF RUN [RUN ...]
prints the differences at T of each RUN folder from the REF folder (same columns as
choices.txt).
  tables.py --successive RUN1 RUN2 [RUN3 ...]
prints the differences at T between successive runs (RUN1 - RUN2, RUN2 - RUN3, ...),
e.g. runs with halved time steps, and the observed order of convergence
log(d_i/d_i+1)/log(dt_i/dt_i+1) of max|dv_nu| on Gamma3, which needs no exact solution.
When the runs compared were made by different versions of the suite (the suite_version of
their summary.txt), a line says so first ("tables.py: note: runs made by different versions
of the suite: ..."); nothing is said when they agree or give none.

The files are plain text: '#' header lines (key value), then one '#' line naming the
columns; floats are written with repr (full precision), rows in a fixed order.
DIR is the results folder of ./run.sh: paper-original, paper-penalty (required),
choices/* and eps-study/eps-* (whatever is there). Exits 1 with a message when a
required file is missing or the meshes of the compared runs differ, and refuses 3D runs
(tests/check_results.py --compare reads those); exits 2 at once on a name that is not UTF-8
(or holds a control character) and on a --results folder that is a symbolic link (the tables
are never written through one).
"""
import argparse
import math
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import numpy as np

import runfiles
import style

PAPER_AB, PAPER_BC = 15, 29     # paper section 5: zone AB 15 nodes, zone BC 29 nodes
TAIL = 4                        # the slope is fitted on the TAIL smallest eps
COORDINATE_TOL = 1e-12          # node coordinates of two runs must agree to this (m)


def fail(message):
    raise runfiles.InputError(message)


def consistent_mass_norm2(xy, triangles, values):
    """Sum over components of e' M e, M the consistent P1 mass matrix (no density):
    per triangle (|T|/12) * (sum_i e_i^2 + (sum_i e_i)^2), exact for P1 fields."""
    p0, p1, p2 = (xy[triangles[:, i]] for i in range(3))
    area = 0.5 * np.abs((p1[:, 0] - p0[:, 0]) * (p2[:, 1] - p0[:, 1]) - (p2[:, 0] - p0[:, 0]) * (p1[:, 1] - p0[:, 1]))
    total = 0.0
    for e in np.atleast_2d(values.T):            # one velocity component at a time
        local = e[triangles]                     # (triangles, 3)
        total += float(np.sum(area / 12.0 * (np.sum(local**2, axis=1) + np.sum(local, axis=1)**2)))
    return total


def run_folders(results):
    """(name, folder) of every run: the paper scene, the choices, the eps study (numeric order)."""
    runs = []
    for name in ("paper-original", "paper-penalty"):
        folder = os.path.join(results, name)
        if not os.path.isfile(os.path.join(folder, "summary.txt")):
            fail(f"missing {folder}/summary.txt (run ./run.sh first)")
        runs.append((name, folder))
    for group, key in (("choices", lambda n: n), ("eps-study", eps_index)):
        parent = os.path.join(results, group)
        if not os.path.isdir(parent):
            continue
        names = [n for n in os.listdir(parent) if os.path.isfile(os.path.join(parent, n, "summary.txt"))]
        if group == "eps-study":
            names = [n for n in names if re.fullmatch(r"eps-\d+", n)]
        runs += [(f"{group}/{n}", os.path.join(parent, n)) for n in sorted(names, key=key)]
    return runs


def eps_index(name):
    return int(name.split("-")[1])


def mesh_label(summary):
    """A one-word name of the mesh: the generated structured mesh, or the -mesh file's name."""
    source = summary.get("mesh_source", "")
    match = re.search(r"nx (\d+) ny (\d+)", source)
    if source.startswith("gmsh ") and match:
        return f"structured-{match.group(1)}x{match.group(2)}"
    return os.path.basename(source) or "unknown"


def zones_table(results):
    rows = []
    for name, folder in run_folders(results):
        s = runfiles.read_summary(folder)
        history = runfiles.read_table(os.path.join(folder, "contact_history.txt"))
        penalty = s["problem"] == "penalty"
        segments = style.paper_segment_counts(s)
        rows.append([
            name, s["problem"], s.real("eps") if penalty else math.nan, s.real("dt"), mesh_label(s),
            s.integer("contact_nodes") - sum(segments.values()), segments["AB"], segments["BC"], segments["CD"],
            float(history["x_B"][-1]), float(history["x_C"][-1]), PAPER_AB, PAPER_BC])
    path = os.path.join(results, "zones.txt")
    runfiles.write_table(path, ["zones on Gamma3 at T (summary.txt) and zone boundaries at T (last line of contact_history.txt)",
                             "; ".join(f"{segment.name} {' + '.join(segment.columns)}" for segment in style.PAPER_SEGMENTS)
                             + "; free the other contact nodes; eps nan for the original problem"],
                      "run problem eps dt mesh free AB BC CD x_B x_C paper_AB paper_BC".split(), rows)
    print(f"tables.py: zones on Gamma3 at T -> {path}")
    print(f"  {'run':34s} {'eps':>7s} {'dt':>6s} {'mesh':24s} {'free':>4s} {'AB':>3s} {'BC':>3s} {'CD':>3s} {'x_B':>7s} {'x_C':>7s}   paper AB BC")
    for r in rows:
        print(f"  {r[0]:34s} {r[2]:7.0e} {r[3]:6g} {r[4]:24s} {r[5]:4d} {r[6]:3d} {r[7]:3d} {r[8]:3d} {r[9]:7.4f} {r[10]:7.4f}   {r[11]:5d} {r[12]:2d}")
    return rows


def mesh_of(folder):
    """Nodes (x, y in file order) and triangles of a run's mesh.msh."""
    mesh = runfiles.read_msh22(os.path.join(folder, "mesh.msh"))
    return mesh.xy, mesh.triangles


def velocity_field(folder, xy):
    """(v_x, v_y) at every node of fields.txt, after checking that its rows are the mesh nodes."""
    fields = runfiles.read_table(os.path.join(folder, "fields.txt"))
    coordinates = np.column_stack(fields.finite("x", "y"))
    if coordinates.shape != xy.shape or np.max(np.abs(coordinates - xy)) > COORDINATE_TOL:
        fail(f"{folder}/fields.txt: its rows are not the nodes of the reference mesh")
    return np.column_stack(fields.finite("v_x", "v_y"))


def compare_runs(reference, folder):
    """Zones of a run and its differences at T from a reference run: max over Gamma3 nodes of
    |dv_nu| and |dv_tau|, max over all nodes of |dv|, and ||dv||_L2(Omega) with the consistent
    mass matrix when both runs have the same triangles (nan otherwise: on two different
    triangulations of the same nodes the difference is not a P1 field of either)."""
    s = runfiles.read_summary(runfiles.run_folder(folder))
    contact_ref = runfiles.read_table(os.path.join(runfiles.run_folder(reference), "contact.txt"))
    contact = runfiles.read_table(os.path.join(folder, "contact.txt"))
    for table in (contact_ref, contact):
        table.finite("x", "v_nu", "v_tau")
    if len(contact["x"]) != len(contact_ref["x"]) or np.max(np.abs(contact["x"] - contact_ref["x"])) > COORDINATE_TOL:
        fail(f"{folder}: its Gamma3 nodes are not those of {reference}")
    xy, triangles = mesh_of(reference)
    run_xy, run_triangles = mesh_of(folder)
    if run_xy.shape != xy.shape or np.max(np.abs(run_xy - xy)) > COORDINATE_TOL:
        fail(f"{folder}: its mesh nodes are not those of {reference}")
    difference = velocity_field(folder, xy) - velocity_field(reference, xy)
    same_triangles = run_triangles.shape == triangles.shape and np.array_equal(np.sort(run_triangles, axis=1), np.sort(triangles, axis=1))
    return {"run": folder, "problem": s["problem"], "dt": s.real("dt"),
            **style.paper_segment_counts(s),
            "max_dv_nu_gamma3": float(np.max(np.abs(contact["v_nu"] - contact_ref["v_nu"]))),
            "max_dv_tau_gamma3": float(np.max(np.abs(contact["v_tau"] - contact_ref["v_tau"]))),
            "max_dv_nodes": float(np.max(np.hypot(difference[:, 0], difference[:, 1]))),
            "error_L2": math.sqrt(consistent_mass_norm2(xy, triangles, difference)) if same_triangles else math.nan}


COMPARE_COLUMNS = ("run", "reference", "problem", "dt", "AB", "BC", "CD",
                   "max_dv_nu_gamma3", "max_dv_tau_gamma3", "max_dv_nodes", "error_L2")


def choices_table(results):
    rows = []
    for name, folder in run_folders(results):
        if name.startswith("choices/"):
            problem = runfiles.read_summary(folder)["problem"]
            row = compare_runs(os.path.join(results, f"paper-{problem}"), folder)
            row.update(run=name, reference=f"paper-{problem}")
            rows.append(row)
    if not rows:
        return rows
    path = os.path.join(results, "choices", "choices.txt")
    runfiles.write_table(path, ["each run of choices/ against the paper run of the same problem, at T: zones on Gamma3,",
                             "max over Gamma3 nodes of |dv_nu| and |dv_tau|, max over all nodes of |dv| (m/s), and ||dv||_L2(Omega)",
                             "(consistent P1 mass matrix; nan when the two runs have different triangles)"],
                      COMPARE_COLUMNS, [[row[c] for c in COMPARE_COLUMNS] for row in rows])
    print(f"tables.py: the open choices, against the paper runs -> {path}")
    print_comparison(rows)
    return rows


def print_comparison(rows, orders=None):
    width = max([34] + [len(r["run"]) for r in rows])
    print(f"  {'run':{width}s} {'dt':>8s} AB BC CD {'max|dv_nu|':>10s} {'max|dv_tau|':>11s} {'max|dv|':>10s} {'L2':>10s}"
          + ("  order" if orders else ""))
    for i, r in enumerate(rows):
        line = (f"  {r['run']:{width}s} {r['dt']:8g} {r['AB']:2d} {r['BC']:2d} {r['CD']:2d} {r['max_dv_nu_gamma3']:10.3e}"
                f" {r['max_dv_tau_gamma3']:11.3e} {r['max_dv_nodes']:10.3e} {r['error_L2']:10.3e}")
        if orders and i > 0:
            line += f"  {orders[i - 1]:5.2f}"
        print(line)


def successive_differences(folders):
    """Differences between successive runs (each against the next one) and the observed
    order of max|dv_nu| on Gamma3 between successive differences."""
    rows = []
    for coarse, fine in zip(folders, folders[1:]):
        row = compare_runs(fine, coarse)
        row["run"] = f"{coarse} - {os.path.basename(os.path.normpath(fine))}"
        rows.append(row)
    orders = []
    for a, b in zip(rows, rows[1:]):
        ratio = a["dt"] / b["dt"]
        ok = ratio != 1 and a["max_dv_nu_gamma3"] > 0 and b["max_dv_nu_gamma3"] > 0
        orders.append(math.log(a["max_dv_nu_gamma3"] / b["max_dv_nu_gamma3"]) / math.log(ratio) if ok else math.nan)
    return rows, orders


def eps_study_table(results):
    reference = os.path.join(results, "paper-original")
    xy, triangles = mesh_of(reference)
    area = consistent_mass_norm2(xy, triangles, np.ones((len(xy), 1)))
    span = xy.max(axis=0) - xy.min(axis=0)
    if abs(area - span[0] * span[1]) > 1e-12 * span[0] * span[1]:   # ||1||^2 = |Omega| for the rectangle
        fail(f"mass matrix check: ||1||^2 = {area!r}, expected the area {span[0] * span[1]!r}")
    v_ref = velocity_field(reference, xy)
    contact_ref = runfiles.read_table(os.path.join(reference, "contact.txt"))
    rows = []
    for name, folder in run_folders(results):
        if not name.startswith("eps-study/"):
            continue
        s = runfiles.read_summary(folder)
        run_xy, _ = mesh_of(folder)
        if run_xy.shape != xy.shape or np.max(np.abs(run_xy - xy)) > COORDINATE_TOL:
            fail(f"{folder}/mesh.msh: not the mesh of {reference}")
        difference = velocity_field(folder, xy) - v_ref
        contact = runfiles.read_table(os.path.join(folder, "contact.txt"))
        if len(contact["x"]) != len(contact_ref["x"]) or np.max(np.abs(contact["x"] - contact_ref["x"])) > COORDINATE_TOL:
            fail(f"{folder}/contact.txt: not the Gamma3 nodes of {reference}")
        rows.append([s.real("eps"), math.sqrt(consistent_mass_norm2(xy, triangles, difference)),
                     float(np.max(np.abs(contact["v_nu"] - contact_ref["v_nu"]))),
                     *(style.paper_segment_counts(s)[name] for name in ("AB", "BC"))])
    if not rows:
        print("tables.py: no eps-study runs; eps_study.txt not written")
        return rows
    rows.sort(key=lambda r: -r[0])
    tail = sorted(rows, key=lambda r: r[0])[:TAIL]
    tail_eps = sorted(r[0] for r in tail)
    slope = math.nan
    if len(tail) >= 2 and all(r[1] > 0 for r in tail):
        slope = float(np.polyfit(np.log([r[0] for r in tail]), np.log([r[1] for r in tail]), 1)[0])
    path = os.path.join(results, "eps-study", "eps_study.txt")
    runfiles.write_table(path, ["reference paper-original", "norm consistent_P1_mass_matrix",
                             "error_L2 = ||v_eps - v||_L2(Omega) at T (consistent P1 mass matrix, no density); "
                             "error_gamma3_max = max over Gamma3 nodes of |v_nu,eps - v_nu| at T",
                             f"slope_tail {slope!r}", f"tail_eps {','.join(repr(e) for e in tail_eps)}"],
                      "eps error_L2 error_gamma3_max zone_AB zone_BC".split(), rows)
    print(f"tables.py: penalty eps study against paper-original -> {path}")
    print(f"  {'eps':>7s} {'error_L2':>10s} {'max|dv_nu|':>10s}  AB  BC")
    for r in rows:
        print(f"  {r[0]:7.0e} {r[1]:10.3e} {r[2]:10.3e} {r[3]:3d} {r[4]:3d}")
    print(f"  slope of log(error_L2) vs log(eps) on eps = {', '.join(f'{e:g}' for e in tail_eps)}: {slope:.4f}")
    return rows


def main():
    runfiles.check_arguments("tables.py")                  # a name not in UTF-8: refused before anything
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--results", help="the results folder of ./run.sh")
    mode.add_argument("--compare", nargs="+", metavar="FOLDER", help="REF RUN [RUN ...]: run folders")
    mode.add_argument("--successive", nargs="+", metavar="FOLDER", help="RUN1 RUN2 [RUN3 ...]: run folders")
    args = parser.parse_args()
    runfiles.check_outputs("tables.py", [args.results])    # not written through a symbolic link
    folders = args.compare or args.successive
    if folders:
        if len(folders) < 2:
            fail("--compare and --successive need at least two run folders")
        for folder in folders:
            if not os.path.isfile(os.path.join(folder, "contact.txt")):
                fail(f"no run in {runfiles.shown(folder)}")
            if runfiles.run_dimension(folder) == 3:
                fail(f"{runfiles.shown(folder)} is a 3D run: tables.py compares 2D runs (triangles, v_x v_y); compare 3D runs "
                     "with ./run.sh compare -a RUN -ref REF (the L2 distance of v at T), or /usr/bin/python3 "
                     "tests/check_results.py RUN --compare REF --rtol R (every column, v_tau2 and v_z too, within R of "
                     "its scale; R, 1e-9 by default, is also the slack of the physics checks)")
        note = style.versions_note(folders, [runfiles.shown(folder) for folder in folders])
        if note:
            print(f"tables.py: note: {note}")
        if args.compare:
            print(f"tables.py: differences at T from {folders[0]}")
            print_comparison([compare_runs(folders[0], folder) for folder in folders[1:]])
        else:
            rows, orders = successive_differences(folders)
            print("tables.py: differences at T between successive runs (dt: of the first run of each pair; "
                  "order: of max|dv_nu| between successive differences)")
            print_comparison(rows, orders)
        return
    if not os.path.isdir(args.results):
        fail(f"no folder {runfiles.shown(args.results)}")
    runs = run_folders(args.results)
    note = style.versions_note([folder for _, folder in runs], [name for name, _ in runs])
    if note:
        print(f"tables.py: note: {note}")
    zones_table(args.results)
    eps_study_table(args.results)
    choices_table(args.results)


if __name__ == "__main__":
    runfiles.run_tool("tables.py", main)
