#!/usr/bin/python3
"""Write faulty variants of a good 3D gmsh MSH 2.2 mesh (tetrahedra), for the tests of the 3D
mesh checker (edp/plugins/runtools/meshcheck.cpp, checkMesh3). Usage:
  bad_meshes3d.py GOOD.msh OUTDIR
writes OUTDIR/fold.msh (an interior node moved out through the body's face: tetrahedra that
overlap their neighbours) and OUTDIR/coincident.msh (a second node at the point of node 1,
used by one of node 1's tetrahedra in its place: a crack)."""
import os
import sys


def main(good, outdir):
    lines = open(good).read().split("\n")
    at = {name: lines.index("$" + name) for name in ("Nodes", "Elements")}
    nodes = lines[at["Nodes"] + 2:at["Nodes"] + 2 + int(lines[at["Nodes"] + 1])]
    elements = lines[at["Elements"] + 2:at["Elements"] + 2 + int(lines[at["Elements"] + 1])]
    head = lines[:at["Nodes"]]

    def write(name, node_lines, element_lines):
        text = "\n".join(head + ["$Nodes", str(len(node_lines))] + node_lines + ["$EndNodes", "$Elements",
                         str(len(element_lines))] + element_lines + ["$EndElements", ""])
        open(os.path.join(outdir, name + ".msh"), "w").write(text)

    xyz = {int(n.split()[0]): [float(v) for v in n.split()[1:4]] for n in nodes}
    boundary = {int(v) for e in elements if e.split()[1] == "2" for v in e.split()[-3:]}
    tets = [e for e in elements if e.split()[1] == "4"]
    top = max(p[2] for p in xyz.values())
    inner = next(i for i in sorted(xyz) if i not in boundary)
    moved = [" ".join([w.split()[0]] + [repr(v) for v in (xyz[inner][:2] + [3 * top])]) if int(w.split()[0]) == inner else w
             for w in nodes]
    write("fold", moved, elements)
    new = max(xyz) + 1
    first = next(k for k, e in enumerate(tets) if "1" in e.split()[-4:])
    w = tets[first].split()
    w[-4:] = [str(new) if v == "1" else v for v in w[-4:]]
    changed = [e if e is not tets[first] else " ".join(w) for e in elements]
    write("coincident", nodes + [" ".join([str(new)] + nodes[0].split()[1:4])], changed)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    os.makedirs(sys.argv[2], exist_ok=True)
    main(sys.argv[1], sys.argv[2])
