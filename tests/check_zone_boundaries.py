#!/usr/bin/python3
"""Check the zone boundaries of runs, OUT/zone_boundaries.txt (docs/design.md, "Output files"),
against what holds whatever the round-off: the geometry of Gamma3 (read from the run's own
mesh.msh, its boundary elements of label GammaContact), the run's summary.txt, and, asked for,
its x_B_estimate and x_C_estimate, the symmetry of the problem, or another run.

Every run:
  the columns step t kind s x y z; kind 1 (B) or 2 (C); the steps those of the run
  (first_step ...), in order, t = step dt; at the last step, as many rows of each kind as
  summary.txt's boundaries_B and boundaries_C;
  every row on an edge of Gamma3 (within 1e-9 of Gamma3's extent): a boundary edge in 2D, an
  edge of a boundary triangle in 3D;
  2D: s is the position of the row along Gamma3, the figures' arc length (plots/gamma3.py,
  boundary_arc_length) of the edge's end it follows plus the distance from it, to 1e-9 of
  Gamma3's extent: between the positions of the two nodes of its edge; 3D: s is nan.
Options (each for every RUN given):
  --estimates   at the last step, the B row of smallest s has x = x_B_estimate and the C row
                of smallest s x = x_C_estimate (to 1e-12 of Gamma3's extent): the first
                boundary of a flat face ordered by x, interpolated alike (both must exist)
  --mirror X0   at the last step, B and C rows on both sides of x = X0 (Gamma3's lowest point
                on a body symmetric about it), each row's mirror image within half of
                Gamma3's longest edge of a row of its kind on the other side
  --both        at the last step, at least one B row and one C row
  --restart-of WHOLE   RUN continues WHOLE (-restart): its rows are WHOLE's from RUN's first
                step on, the same steps and kinds, s x y z to 1e-9 of Gamma3's extent
Usage: check_zone_boundaries.py [options] RUN... Prints one line per failed check; exit 1 if
any failed.
"""
import argparse
import math
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [os.path.join(ROOT, "edp"), os.path.join(ROOT, "plots")]

import numpy as np

import gamma3
import runfiles

COLUMNS = ["step", "t", "kind", "s", "x", "y", "z"]


class Run:
    """A run folder: its zone_boundaries.txt (rows), summary.txt, and Gamma3 from its mesh.msh:
    points (n, 3), edges (m, 2) of rows of points, extent, longest edge; in 2D the position of
    each point along Gamma3 (arc)."""

    def __init__(self, folder):
        self.folder = folder
        self.summary = runfiles.read_summary(folder)
        self.dim = runfiles.run_dimension(folder)
        self.table = runfiles.read_table(os.path.join(folder, "zone_boundaries.txt"), empty=True)
        contact = runfiles.labels()["GammaContact"]
        mesh = runfiles.read_msh(os.path.join(folder, "mesh.msh"), self.dim)
        if self.dim == 2:
            points, pairs = mesh.xy, mesh.lines[mesh.line_labels == contact]
        else:
            faces = mesh.faces[mesh.face_labels == contact]
            points, pairs = mesh.xyz, np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
        pairs = np.unique(np.sort(pairs, axis=1), axis=0)
        used = np.unique(pairs)
        self.points = np.zeros((len(used), 3))
        self.points[:, :self.dim] = points[used]
        self.edges = np.searchsorted(used, pairs)
        self.extent = float(np.ptp(self.points, axis=0).max())
        self.longest = float(np.linalg.norm(self.points[self.edges[:, 1]] - self.points[self.edges[:, 0]], axis=1).max())
        if self.dim == 2:
            arc = gamma3.boundary_arc_length(mesh)
            self.arc = np.array([arc[node] for node in used])

    def last(self, kind):
        """The rows (x y z s) of that kind at the run's last step."""
        t = self.table
        last = self.summary.integer("first_step") + self.summary.integer("steps") - 1
        return np.column_stack([t["x"], t["y"], t["z"], t["s"]])[(t["step"] == last) & (t["kind"] == kind)]


def check(run, options, failures):
    def expect(condition, message):
        if not condition:
            failures.append(f"{run.folder}/zone_boundaries.txt: {message}")
        return condition

    t = run.table
    if not expect(t.columns == COLUMNS, f"the columns are {' '.join(t.columns)}, not {' '.join(COLUMNS)}"):
        return
    first, steps, dt = run.summary.integer("first_step"), run.summary.integer("steps"), run.summary.real("dt")
    tol = 1e-9 * run.extent
    expect(set(np.unique(t["kind"])) <= {1.0, 2.0}, "a kind other than 1 (B) and 2 (C)")
    expect(bool(np.all((t["step"] >= first) & (t["step"] <= first + steps - 1))), f"a step outside {first} .. {first + steps - 1}")
    expect(bool(np.all(np.diff(t["step"]) >= 0)), "the steps are not in order")
    expect(bool(np.all(np.abs(t["t"] - t["step"] * dt) <= 1e-12 * np.maximum(1, t["step"] * dt))), "a t that is not step dt")
    expect(bool(np.isfinite(np.column_stack([t["x"], t["y"], t["z"]])).all()), "a position that is not finite")
    for kind, key in ((1, "boundaries_B"), (2, "boundaries_C")):
        expect(len(run.last(kind)) == run.summary.integer(key),
               f"{len(run.last(kind))} rows of kind {kind} at the last step, summary.txt's {key} is {run.summary[key]}")
    # every row on an edge of Gamma3; in 2D its s the length along Gamma3 up to it
    a, b = run.points[run.edges[:, 0]], run.points[run.edges[:, 1]]
    along = b - a
    length2 = np.einsum("ij,ij->i", along, along)
    for k in range(len(t)):
        p = np.array([t["x"][k], t["y"][k], t["z"][k]])
        share = np.clip(np.einsum("ij,ij->i", p - a, along) / length2, 0, 1)
        off = np.linalg.norm(a + share[:, None] * along - p, axis=1)
        e = int(np.argmin(off))
        if not expect(off[e] <= tol, f"line {t.lines[k]}: ({p[0]}, {p[1]}, {p[2]}) is {off[e]:.3g} away from every edge of Gamma3"):
            continue
        if run.dim == 3:
            expect(math.isnan(t["s"][k]), f"line {t.lines[k]}: s = {t['s'][k]} in 3D, not nan")
            continue
        i, j = run.edges[e]
        low, high = (i, j) if run.arc[i] <= run.arc[j] else (j, i)
        walked = abs(run.arc[high] - run.arc[low] - np.sqrt(length2[e])) <= tol   # (else the edge closing a loop)
        start = low if walked else high
        s = run.arc[start] + float(np.linalg.norm(p - run.points[start]))
        expect(abs(t["s"][k] - s) <= tol, f"line {t.lines[k]}: s = {t['s'][k]}, but the point is {s} along Gamma3 "
                                          f"(between its nodes at {run.arc[i]} and {run.arc[j]})")
    if options.estimates:
        for kind, key in ((1, "x_B_estimate"), (2, "x_C_estimate")):
            rows, estimate = run.last(kind), run.summary.real(key)
            if expect(len(rows) > 0 and math.isfinite(estimate), f"{key} = {estimate} with {len(rows)} rows of kind {kind} at T"):
                first_row = rows[np.argmin(rows[:, 3])]
                expect(abs(first_row[0] - estimate) <= 1e-12 * run.extent,
                       f"the first row of kind {kind} at T is at x = {first_row[0]}, summary.txt's {key} is {estimate}")
    if options.mirror is not None:
        x0 = options.mirror
        for kind in (1, 2):
            x = run.last(kind)[:, 0] - x0
            if expect(np.any(x < 0) and np.any(x > 0), f"kind {kind} at T: rows at x - X0 = {list(x)}, not on both sides of X0"):
                for value in x:
                    expect(np.abs(x + value).min() <= run.longest / 2,
                           f"kind {kind} at T: the row at x = {value + x0} has no mirror image within {run.longest / 2} "
                           f"on the other side of {x0}")
    if options.both:
        expect(len(run.last(1)) > 0 and len(run.last(2)) > 0, "not both a B and a C row at the last step")
    if options.restart_of:
        whole = runfiles.read_table(os.path.join(options.restart_of, "zone_boundaries.txt"), empty=True)
        mine = np.column_stack([t[c] for c in COLUMNS])
        theirs = np.column_stack([whole[c] for c in COLUMNS])[whole["step"] >= first]
        if expect(mine.shape == theirs.shape and np.array_equal(mine[:, [0, 2]], theirs[:, [0, 2]]),
                  f"not the steps and kinds of {options.restart_of}'s rows from step {first} on"):
            compared = [3, 4, 5, 6] if run.dim == 2 else [4, 5, 6]     # (s: nan in 3D)
            worst = np.abs(mine[:, compared] - theirs[:, compared]).max(initial=0)
            expect(worst <= tol, f"rows differ from {options.restart_of}'s by up to {worst:.3g}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--estimates", action="store_true")
    parser.add_argument("--mirror", type=float)
    parser.add_argument("--both", action="store_true")
    parser.add_argument("--restart-of")
    options = parser.parse_args()
    failures = []
    for folder in options.runs:
        check(Run(folder), options, failures)
    print("\n".join(failures) if failures else f"zone_boundaries.txt checked in {len(options.runs)} run(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(runfiles.run_tool("check_zone_boundaries.py", main))
