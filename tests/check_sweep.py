#!/usr/bin/python3
"""Check a sweep folder of ./run.sh sweep (README.md, "Sweeps") against its own runs.

Usage: check_sweep.py DIR NAME V1,V2,... [--failed V=CODE ...]

sweep.txt must read (edp/runfiles.py, read_table): its header names the sweep's command line
and 'swept NAME', its rows are the values V1,V2,... in that order. A row of a value given
with --failed is 'failed' with the solve's exit code CODE, nan in every quantity of the run,
a finite wall time, no run folder and a log DIR/RUN.log; every other row is 'ok', exit code
0, and its run folder DIR/RUN (a finished run: run.complete) echoes NAME = the value in the
header of its files and holds the row's numbers: normal_force, tangential_force, x_B and x_C of the
last line of its contact_history.txt, every zone_* key of its summary.txt (a column of that
name; a zone column the run lacks is nan), iterations_total and iterations_max; wall_time
finite and positive. sweep.png is a PNG file; sweep.complete lists exactly the other
entries of DIR. Compares numbers as the floats they print (nan equals nan). Prints one line
per problem; exit 1 if any.
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import runfiles

QUANTITY_HISTORY = ("normal_force", "tangential_force", "x_B", "x_C")
QUANTITY_SUMMARY = ("iterations_total", "iterations_max")


def same(a, b):
    a, b = float(a), float(b)
    return a == b or (math.isnan(a) and math.isnan(b))


def main():
    if len(sys.argv) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    folder, name, values = sys.argv[1], sys.argv[2], sys.argv[3].split(",")
    failed = {}
    arguments = sys.argv[4:]
    while arguments:
        if arguments[0] != "--failed" or len(arguments) < 2 or "=" not in arguments[1]:
            print(__doc__, file=sys.stderr)
            return 2
        value, code = arguments[1].rsplit("=", 1)
        failed[value] = code
        arguments = arguments[2:]
    problems = []
    table = runfiles.read_table(os.path.join(folder, "sweep.txt"), dtype=str)
    header = runfiles.read_lines(table.path)
    if not header[0].startswith("# sweep: ./run.sh sweep "):
        problems.append(f"{table.path}: the first line is not the sweep's command line: {header[0]!r}")
    if table.params.get("swept") != name:
        problems.append(f"{table.path}: 'swept {name}' missing (params: {dict(table.params)})")
    if table.columns[:4] != ["value", "run", "status", "exit_code"] or "wall_time" not in table.columns:
        problems.append(f"{table.path}: columns {table.columns}")
    rows = table.rows()
    if [row["value"] for row in rows] != values:
        problems.append(f"{table.path}: values {[row['value'] for row in rows]}, expected {values} in that order")
    numbers = [column for column in table.columns if column not in ("value", "run", "status", "exit_code", "wall_time")]
    for row in rows:
        where = f"{table.path}: row {row['value']}"
        run = os.path.join(folder, row["run"])
        if not math.isfinite(float(row["wall_time"])) or not float(row["wall_time"]) > 0:
            problems.append(f"{where}: wall_time {row['wall_time']}")
        if row["value"] in failed:
            if row["status"] != "failed" or row["exit_code"] != failed[row["value"]]:
                problems.append(f"{where}: {row['status']} with exit code {row['exit_code']}, expected failed with "
                                f"{failed[row['value']]}")
            if any(not math.isnan(float(row[column])) for column in numbers):
                problems.append(f"{where}: a failed case with numbers other than nan")
            if os.path.exists(run):
                problems.append(f"{where}: a failed case with a run folder {run}")
            if not os.path.isfile(run + ".log"):
                problems.append(f"{where}: no log {run}.log")
            continue
        if row["status"] != "ok" or row["exit_code"] != "0":
            problems.append(f"{where}: {row['status']} with exit code {row['exit_code']}, expected ok with 0")
            continue
        try:
            runfiles.run_folder(run)
            summary = runfiles.read_summary(run)
            history = runfiles.read_table(os.path.join(run, "contact_history.txt"))
        except runfiles.InputError as error:
            problems.append(f"{where}: {error}")
            continue
        echoed = history.params.get(name, "(not echoed)")      # (the '# NAME VALUE' lines: the options used)
        try:
            used = echoed == row["value"] or same(echoed, row["value"])
        except ValueError:                          # (words: a choice, a scene)
            used = False
        if not used:
            problems.append(f"{where}: the run {run} used {name} = {echoed}")
        for column in QUANTITY_HISTORY:
            if not same(row[column], history[column][-1]):
                problems.append(f"{where}: {column} {row[column]}, the run's last line has {history[column][-1]!r}")
        zones = runfiles.zone_names(summary)
        for column in zones + QUANTITY_SUMMARY:
            if column not in table.columns or not same(row[column], summary[column]):
                problems.append(f"{where}: {column} {row[column] if column in table.columns else '(no column)'}, "
                                f"the run's summary.txt has {summary[column]}")
        for column in runfiles.zone_names(table.columns):
            if column not in zones and not math.isnan(float(row[column])):
                problems.append(f"{where}: {column} {row[column]}, a zone the run does not have")
    with open(os.path.join(folder, "sweep.png"), "rb") as f:
        if f.read(8) != b"\x89PNG\r\n\x1a\n":
            problems.append(f"{folder}/sweep.png is not a PNG file")
    listed = runfiles.completed_files(folder, "sweep.complete")
    present = sorted(set(os.listdir(folder)) - {"sweep.complete"})
    if listed is None or sorted(listed) != present:
        problems.append(f"{folder}/sweep.complete lists {listed}, the folder holds {present}")
    for problem in problems:
        print(f"check_sweep.py: {problem}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(runfiles.run_tool("check_sweep.py", main))
