#!/usr/bin/python3
"""Read the VTK time series of a run (OUT/vtk/, written with -vtk N) back with the VTK library
itself (Debian's python3-vtk9, the reader ParaView is built on), and check it against the
run's text outputs:
  fields.pvd lists step 0, every N steps and the last, at their physical times;
  every file it lists is read by vtkXMLUnstructuredGridReader: the mesh's vertices and
  triangles, point arrays u, v (3 components), von_mises and contact_zone;
  the last frame equals fields.txt (coordinates, u, v, von_mises) to round-off, and its
  contact_zone is the zone of contact_nodes_history.txt's last step on Gamma3, -1 elsewhere.
Usage: check_vtk.py RUN_DIR. Prints one line per failed check and exits 1 if any failed.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

import runfiles


def read_frame(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    arrays = {name: vtk_to_numpy(grid.GetPointData().GetArray(name)) for name in ("u", "v", "von_mises", "contact_zone")
              if grid.GetPointData().GetArray(name) is not None}
    cells = vtk_to_numpy(grid.GetCells().GetData()) if grid.GetNumberOfCells() else np.empty(0)
    return grid, vtk_to_numpy(grid.GetPoints().GetData()) if grid.GetNumberOfPoints() else np.empty((0, 3)), arrays, cells


def main():
    if len(sys.argv) != 2:
        raise runfiles.InputError("usage: check_vtk.py RUN_DIR")
    folder = sys.argv[1]
    failures = []

    def expect(condition, message):
        if not condition:
            failures.append(message)
        return condition

    fields = runfiles.read_table(os.path.join(folder, "fields.txt"))
    summary = runfiles.read_summary(os.path.join(folder, "summary.txt"))
    steps, every, dt = summary.integer("steps"), summary.integer("vtk"), summary.real("dt")
    mesh = runfiles.read_msh22(os.path.join(folder, "mesh.msh"))
    series = runfiles.read_pvd(os.path.join(folder, "vtk", "fields.pvd"))
    wanted = sorted({n for n in range(0, steps + 1) if n % every == 0} | {steps})
    expect([os.path.basename(file) for _, file in series] == [f"fields_{n:06d}.vtu" for n in wanted],
           "fields.pvd does not list steps 0, every N and the last")
    expect(all(abs(t - n * dt) <= 1e-12 * max(1, n * dt) for (t, _), n in zip(series, wanted)),
           "fields.pvd: a timestep is not step * dt")
    for _, file in series:
        grid, points, arrays, cells = read_frame(file)
        expect(grid.GetNumberOfPoints() == len(fields) and grid.GetNumberOfCells() == len(mesh.triangles),
               f"{os.path.basename(file)}: {grid.GetNumberOfPoints()} points and {grid.GetNumberOfCells()} cells, the "
               f"mesh has {len(fields)} and {len(mesh.triangles)}")
        expect(sorted(arrays) == ["contact_zone", "u", "v", "von_mises"], f"{os.path.basename(file)}: point arrays {sorted(arrays)}")
    if failures:
        return report(folder, failures)
    last_frame = series[-1][1]
    grid, points, arrays, cells = read_frame(last_frame)
    triangles = cells.reshape(-1, 4)
    expect((triangles[:, 0] == 3).all() and (np.sort(triangles[:, 1:], 1) == np.sort(mesh.triangles, 1)).all(),
           "the last frame's triangles are not the mesh's")
    scale = lambda a: max(np.abs(a).max(), 1e-300)
    for name, mine in (("x", points[:, 0]), ("y", points[:, 1]), ("u_x", arrays["u"][:, 0]), ("u_y", arrays["u"][:, 1]),
                       ("v_x", arrays["v"][:, 0]), ("v_y", arrays["v"][:, 1]), ("von_mises", arrays["von_mises"])):
        worst = np.abs(mine - fields[name]).max()
        expect(worst <= 1e-14 * scale(fields[name]), f"last frame: {name} differs from fields.txt by {worst:.3e}")
    expect(np.abs(points[:, 2]).max() == 0 and np.abs(arrays["u"][:, 2]).max() == 0, "last frame: z components not 0")
    history = runfiles.read_table(os.path.join(folder, "contact_nodes_history.txt"))
    at_end = history["step"] == history["step"].max()
    zone = np.full(len(fields), -1)
    for x, y, z in zip(history["x"][at_end], history["y"][at_end], history["zone"][at_end]):
        zone[np.argmin((fields["x"] - x) ** 2 + (fields["y"] - y) ** 2)] = int(z)
    expect((arrays["contact_zone"] == zone).all(), "last frame: contact_zone is not the zones of contact_nodes_history.txt at T")
    return report(folder, failures)


def report(folder, failures):
    for failure in failures:
        print(f"  {folder}: {failure}")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    runfiles.run_tool("check_vtk.py", main)
