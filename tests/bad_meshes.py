#!/usr/bin/python3
"""Write malformed or degenerate variants of a good gmsh MSH 2.2 mesh, for the tests of the
mesh checker (edp/plugins/runtools/meshcheck.cpp, runCheckMesh). Usage:
  bad_meshes.py GOOD.msh OUTDIR
writes OUTDIR/NAME.msh for each NAME of VARIANTS (one problem each)."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import runfiles


def variants(mesh_text):
    """NAME -> text of the mesh with one problem."""
    lines = mesh_text.split("\n")
    at = {name: lines.index("$" + name) for name in ("Nodes", "Elements")}
    nodes = lines[at["Nodes"] + 2:at["Nodes"] + 2 + int(lines[at["Nodes"] + 1])]
    elements = lines[at["Elements"] + 2:at["Elements"] + 2 + int(lines[at["Elements"] + 1])]
    head = lines[:at["Nodes"]]

    def write(node_lines, element_lines):
        return "\n".join(head + ["$Nodes", str(len(node_lines))] + node_lines + ["$EndNodes", "$Elements",
                                 str(len(element_lines))] + element_lines + ["$EndElements", ""])

    labels = runfiles.labels()
    contact = str(labels["GammaContact"])
    triangles = [e for e in elements if e.split()[1] == "2"]
    lines_of = [e for e in elements if e.split()[1] == "1"]
    contact_line = next(e for e in lines_of if e.split()[3] == contact)

    def clockwise(e):
        w = e.split()
        w[-1], w[-2] = w[-2], w[-1]
        return " ".join(w)

    def scaled(factor, factor_y=None):
        out = []
        for n in nodes:
            w = n.split()
            fy = factor if factor_y is None else factor_y
            out.append(" ".join([w[0], repr(float(w[1]) * factor), repr(float(w[2]) * fy), w[3]]))
        return out

    last_id = max(int(e.split()[0]) for e in elements)
    # the edges of the triangles, and the interior ones (two triangles)
    count = {}
    for t in triangles:
        a, b, c = t.split()[-3:]
        for p, q in ((a, b), (b, c), (c, a)):
            count[tuple(sorted((p, q)))] = count.get(tuple(sorted((p, q))), 0) + 1
    interior = sorted(e for e, n in count.items() if n == 2)[len(count) // 4]
    traction = str(labels["GammaTraction"])

    def folded():
        """Move a vertex of an interior edge across it: a triangle turns over onto its neighbour."""
        a, b = interior
        xy = {n.split()[0]: (float(n.split()[1]), float(n.split()[2])) for n in nodes}
        third = next(t.split()[-3:] for t in triangles if a in t.split()[-3:] and b in t.split()[-3:])
        c = next(k for k in third if k not in (a, b))
        mx, my = (xy[a][0] + xy[b][0]) / 2, (xy[a][1] + xy[b][1]) / 2
        moved = []
        for n in nodes:
            w = n.split()
            if w[0] == c:
                w[1], w[2] = repr(xy[c][0] + 1.3 * (mx - xy[c][0])), repr(xy[c][1] + 1.3 * (my - xy[c][1]))
            moved.append(" ".join(w))
        return moved

    def renamed(old, new):
        def swap(line, first):
            w = line.split()
            return " ".join([new if (k >= first and x == old) else x for k, x in enumerate(w)])
        return [swap(n, 0) if n.split()[0] == old else n for n in nodes], [swap(e, 3 + int(e.split()[2])) for e in elements]
    xy = {n.split()[0]: (float(n.split()[1]), float(n.split()[2])) for n in nodes}
    last_node = max(int(n.split()[0]) for n in nodes)

    def node_at(x, y):
        return min(xy, key=lambda k: (xy[k][0] - x) ** 2 + (xy[k][1] - y) ** 2)

    def added(points, triangle_nodes, line_nodes):
        """New nodes at points (numbered after the last), triangles and lines tagged 7 on
        them (a node is an existing id, or the index of a new point as an int)."""
        ids = {k: str(last_node + 1 + k) for k in range(len(points))}
        name = lambda k: ids[k] if isinstance(k, int) else k
        new_nodes = [f"{ids[k]} {x!r} {y!r} 0" for k, (x, y) in enumerate(points)]
        new_elements = [f"{last_id + 1 + k} 2 2 1 1 " + " ".join(map(name, t)) for k, t in enumerate(triangle_nodes)]
        new_elements += [f"{last_id + 1 + len(triangle_nodes) + k} 1 2 7 7 " + " ".join(map(name, e))
                         for k, e in enumerate(line_nodes)]
        return new_nodes, new_elements

    def two_bodies():
        """A second copy of the body, shifted by (0.5, 0.3), with its own nodes and elements."""
        shift = {n.split()[0]: str(int(n.split()[0]) + last_node) for n in nodes}
        copy_nodes = [" ".join([shift[w[0]], repr(float(w[1]) + 0.5), repr(float(w[2]) + 0.3), w[3]])
                      for w in (n.split() for n in nodes)]
        copy_elements = []
        for e in elements:
            w = e.split()
            first = 3 + int(w[2])
            copy_elements.append(" ".join([str(int(w[0]) + last_id)] + w[1:first] + [shift[k] for k in w[first:]]))
        return write(nodes + copy_nodes, elements + copy_elements)

    def loose_triangle():
        """A triangle of its own inside another one, with lines tagged 7: a second body."""
        corners = [xy[k] for k in triangles[len(triangles) // 2].split()[-3:]]
        cx, cy = sum(p[0] for p in corners) / 3, sum(p[1] for p in corners) / 3
        points = [(cx + 0.3 * (p[0] - cx), cy + 0.3 * (p[1] - cy)) for p in corners]
        new_nodes, new_elements = added(points, [(0, 1, 2)], [(0, 1), (1, 2), (2, 0)])
        return write(nodes + new_nodes, elements + new_elements)

    def slit():
        """A hanging node m halfway along an interior edge (a, b): the triangle on one side is cut
        in two at m, so that (a, b), (a, m), (m, b) are boundary edges; lines tagged 7 give them
        labels. The body is cut along (a, b)."""
        a, b = interior
        cut = next(t for t in triangles if a in t.split()[-3:] and b in t.split()[-3:])
        d = next(k for k in cut.split()[-3:] if k not in (a, b))
        middle = ((xy[a][0] + xy[b][0]) / 2, (xy[a][1] + xy[b][1]) / 2)
        new_nodes, new_elements = added([middle], [(a, 0, d), (0, b, d)], [(a, b), (a, 0), (0, b)])
        return write(nodes + new_nodes, [e for e in elements if e != cut] + new_elements)

    def arm_over_body():
        """Two triangles on the top edge (p, q), the second folded back over the body: one body,
        no fold at a shared edge, but its boundary crosses the top of the body."""
        p, q = node_at(1.0, 1.0), node_at(1.25, 1.0)
        new_nodes, new_elements = added([(1.05, 1.5), (0.6, 0.6)], [(p, q, 0), (p, 0, 1)], [(q, 0), (0, 1), (1, p)])
        top = [e for e in lines_of if set(e.split()[-2:]) == {p, q}]
        return write(nodes + new_nodes, [e for e in elements if e not in top] + new_elements)

    w = contact_line.split()
    undefined = " ".join(w[:-1] + ["999999"])
    quad = f"{last_id + 1} 3 2 1 1 " + " ".join(triangles[0].split()[-3:] + [triangles[1].split()[-1]])
    order2 = f"{last_id + 1} 9 2 1 1 " + " ".join(triangles[0].split()[-3:] * 2)
    return {
        "clockwise": write(nodes, lines_of + [clockwise(t) for t in triangles]),
        "undefined-node": write(nodes, [e if e != contact_line else undefined for e in elements]),
        "twice-listed-edge": write(nodes, elements + [" ".join([str(last_id + 1)] + w[1:])]),
        "quadrangle": write(nodes, elements + [quad]),
        "order-2": write(nodes, elements + [order2]),
        "micrometres": write(scaled(1e-6), elements),
        # 2.5e7 times longer: the extent is 2e8 times the shortest edge, refused (above 1e8) but
        # still one that FreeFEM's reader could load (from about 1e9 it exhausts the memory)
        "long-and-thin": write(scaled(2.5e7, 1), elements),
        "unused-node": write(nodes + [f"{len(nodes) + 1000} 0.5 0.5 0"], elements),
        "truncated": mesh_text[:len(mesh_text) // 2],
        "overlap": write(nodes, elements + [f"{last_id + 1} 2 2 1 1 " + " ".join(list(interior) + [triangles[0].split()[-1]])]),
        "folded": write(folded(), elements),
        "interior-traction": write(nodes, elements + [f"{last_id + 1} 1 2 {traction} {traction} " + " ".join(interior)]),
        "interior-contact": write(nodes, elements + [f"{last_id + 1} 1 2 {contact} {contact} " + " ".join(interior)]),
        "gap-in-contact": write(nodes, [e for e in elements if e != contact_line]),
        "64-bit-id": write(*renamed(nodes[-1].split()[0], "4294967297")),
        "two-bodies": two_bodies(),
        "loose-triangle": loose_triangle(),
        "slit": slit(),
        "arm-over-body": arm_over_body(),
    }


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: bad_meshes.py GOOD.msh OUTDIR")
    text = "\n".join(runfiles.read_lines(sys.argv[1]))
    os.makedirs(sys.argv[2], exist_ok=True)
    for name, mesh in variants(text).items():
        with open(os.path.join(sys.argv[2], name + ".msh"), "w") as f:
            f.write(mesh)


if __name__ == "__main__":
    runfiles.run_tool("bad_meshes.py", main)
