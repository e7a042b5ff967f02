"""face3d.py: Gamma3 of a 3D run seen from outside, for its figures and animation
(docs/figures.md, "The figures of a 3D run"): the face in its own plane coordinates
(ContactFace: the nodes, their frames and cells), its axes and zones, and the body's outer
surface and its edges. Imported by the scripts of plots/, which put edp/ (runfiles) on the
path.
"""
import numpy as np

import runfiles
import style


def nearest_rows(points, targets):
    """For each target (a row of coordinates), the row of the nearest of points and its
    distance: (rows, distances)."""
    points, targets = np.asarray(points, dtype=float), np.asarray(targets, dtype=float)
    rows, distances = np.empty(len(targets), dtype=int), np.empty(len(targets))
    for start in range(0, len(targets), 256):                  # a block of targets at a time
        block = np.linalg.norm(points[None, :, :] - targets[start:start + 256, None, :], axis=2)
        rows[start:start + 256] = np.argmin(block, axis=1)
        distances[start:start + 256] = block[np.arange(len(block)), rows[start:start + 256]]
    return rows, distances


def surface_frame(normal):
    """The frame (n, t1, t2) of a unit normal by the solver's rule (docs/design.md, "Three
    dimensions"): t1 the coordinate axis least aligned with n (the first of those within 1e-9
    of the least |n_k|) made orthogonal to it, t2 = n x t1, so that t1 x t2 = n."""
    n = np.asarray(normal, dtype=float) / np.linalg.norm(normal)
    axis = np.eye(3)[int(np.flatnonzero(np.abs(n) <= np.abs(n).min() + 1e-9)[0])]
    t1 = axis - axis.dot(n) * n
    t1 /= np.linalg.norm(t1)
    return n, t1, np.cross(n, t1)


def direction_name(vector):
    """'x', '-z' for a coordinate axis, else '(0.707, 0, 0.707)'."""
    for k, name in enumerate("xyz"):
        if abs(abs(vector[k]) - 1) < 1e-9:
            return name if vector[k] > 0 else "\N{MINUS SIGN}" + name
    return "(" + ", ".join(f"{value:.3g}".replace("-", "\N{MINUS SIGN}") for value in vector + 0.0) + ")"


class ContactFace:
    """Gamma3 of a 3D run (the boundary triangles of label 1 of its mesh) seen from outside,
    in its own plane coordinates: the mean normal n of the contact nodes (their normals
    weighted by their weights, from contact.txt) points towards the viewer, and a point p
    has the coordinates (p.t1, p.t2) of the frame of n (surface_frame: on a face y = 0, n =
    (0, -1, 0), t1 = x and t2 = z, the face seen from below). uv: (nodes, 2) those of the
    contact nodes, in the order of contact.txt; triangles: (faces, 3) rows of contact.txt;
    mesh_rows: the row of mesh.xyz of each node; labels: the axis labels; view: how the face
    is seen; folded: whether a curved Gamma3 overlaps itself in this view (a triangle seen
    from inside). source: the mesh's file, for messages."""

    def __init__(self, mesh, contact, source="the mesh"):
        c = contact
        xyz = np.column_stack(c.finite("x", "y", "z"))
        faces = mesh.faces[mesh.face_labels == runfiles.labels()["GammaContact"]]
        if not len(faces):
            raise runfiles.InputError(f"{source} has no contact surface (physical surface 1)")
        on = np.unique(faces)
        rows, distances = nearest_rows(mesh.xyz[on], xyz)
        size = max(float(np.ptp(mesh.xyz, axis=0).max()), 1e-300)
        far = np.flatnonzero(distances > 1e-6 * size)
        if far.size:
            raise runfiles.InputError(f"{c.path}:{c.lines[far[0]]}: the node ({', '.join(f'{v:g}' for v in xyz[far[0]])}) "
                                      "is not a node of the mesh's contact surface (physical surface 1)")
        if len(set(rows)) != len(rows) or len(rows) != len(on):
            raise runfiles.InputError(f"{c.path}: {len(xyz)} rows for the {len(on)} nodes of the mesh's contact "
                                      "surface, not one a node")
        self.mesh_rows = on[rows]                                               # of each node, in mesh.xyz
        local = np.full(len(mesh.xyz), -1)
        local[self.mesh_rows] = np.arange(len(rows))
        self.triangles = local[faces]
        self.frames = np.stack([np.column_stack(c.finite(*(f"{axis}_{k}" for k in "xyz")))
                                for axis in ("n", "t1", "t2")], axis=1)          # (nodes, 3 axes, 3)
        weights = c.finite("weight")[0]
        mean = weights @ self.frames[:, 0]
        if np.linalg.norm(mean) <= 1e-9 * max(weights.sum(), 1e-300):          # a closed surface
            mean = self.frames[0, 0]
        self.normal, self.t1, self.t2 = surface_frame(mean)
        self.uv = np.c_[xyz @ self.t1, xyz @ self.t2]
        self.labels = tuple(f"{direction_name(t)} [m]" for t in (self.t1, self.t2))
        self.view = (f"seen from outside (mean normal {direction_name(self.normal)} towards the viewer; "
                     f"across: {direction_name(self.t1)}, up: {direction_name(self.t2)})")
        p = xyz[self.triangles]
        area = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])                   # twice the area, along its normal
        outward = np.sign(np.einsum("ij,ij->i", area, self.frames[self.triangles, 0].sum(axis=1)))
        self.folded = bool(np.any(outward * (area @ self.normal) < -1e-9 * np.abs(area).max()))

    def tangential(self, first, second):
        """The tangential vectors first t1_i + second t2_i of the nodes (their own frames), in
        the face's plane coordinates: (nodes, 2)."""
        vectors = first[:, None] * self.frames[:, 1] + second[:, None] * self.frames[:, 2]
        return np.c_[vectors @ self.t1, vectors @ self.t2]

    def edges(self):
        """The edges of the triangles of Gamma3, once each: (edges, 2) rows of uv."""
        t = self.triangles
        return np.unique(np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1), axis=0)

    def cells(self):
        """Each node's cell, halfway to its neighbours (the median dual cell): from each
        triangle, for each corner, the quadrilateral corner, midpoint of an edge, centroid,
        midpoint of the other edge. (quadrilaterals (3 faces, 4, 2), the node of each)."""
        p = self.uv[self.triangles]
        centroid = p.mean(axis=1)
        quads = [np.stack([p[:, k], 0.5 * (p[:, k] + p[:, (k + 1) % 3]), centroid, 0.5 * (p[:, k] + p[:, (k + 2) % 3])],
                          axis=1) for k in range(3)]
        return np.concatenate(quads), self.triangles.T.ravel()

    def extent(self):
        """Width and height of the face in its plane coordinates (at least 1e-12)."""
        return np.maximum(np.ptp(self.uv, axis=0), 1e-12)


def face_axes(ax, face, margin=0.04):
    """The axes set to show the face: its plane coordinates at equal aspect, a margin of
    `margin` of its size, the axis labels, no grid."""
    low, high = face.uv.min(axis=0), face.uv.max(axis=0)
    pad = margin * (high - low).max()
    ax.set_xlim(low[0] - pad, high[0] + pad)
    ax.set_ylim(low[1] - pad, high[1] + pad)
    ax.set_aspect("equal")
    ax.grid(False)
    ax.set_xlabel(face.labels[0])
    ax.set_ylabel(face.labels[1])


def draw_face_zones(ax, face, zones, nodes_size=2.5):
    """The zone of every node of Gamma3 over the face: each node's cell (ContactFace.cells)
    in its zone's colour, the triangles' edges in white, the nodes as black dots."""
    from matplotlib.collections import LineCollection, PolyCollection
    quads, owners = face.cells()
    filled = [style.zone_color(z) for z in np.asarray(zones)[owners]]
    ax.add_collection(PolyCollection(quads, facecolors=filled, edgecolors=filled, linewidths=0.4))
    ax.add_collection(LineCollection(face.uv[face.edges()], colors="w", linewidths=0.5, alpha=0.7))
    ax.plot(*face.uv.T, "o", color="k", markersize=nodes_size, markeredgewidth=0)
    face_axes(ax, face)


def outer_surface(tetrahedra, xyz):
    """The boundary of a body of tetrahedra: its triangles (faces of one tetrahedron only),
    each ordered counterclockwise seen from outside. (triangles, 3) rows of xyz."""
    corners = ((0, 1, 2, 3), (0, 1, 3, 2), (0, 2, 3, 1), (1, 2, 3, 0))
    faces = np.concatenate([tetrahedra[:, list(k[:3])] for k in corners])
    opposite = np.concatenate([tetrahedra[:, k[3]] for k in corners])
    _, first, counts = np.unique(np.sort(faces, axis=1), axis=0, return_index=True, return_counts=True)
    keep = np.sort(first[counts == 1])
    faces, opposite = faces[keep], opposite[keep]
    p = xyz[faces]
    inward = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), xyz[opposite] - p[:, 0]) > 0
    faces[inward] = faces[inward][:, [0, 2, 1]]
    return faces


def feature_edges(triangles, xyz, angle=30.0):
    """The edges of a closed surface (triangles, outward) where it bends by more than
    `angle` degrees (the edges of a box), or that bound it: (edges, 2) rows of xyz."""
    p = xyz[triangles]
    normals = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    owner = np.tile(np.arange(len(triangles)), 3)
    order = np.lexsort(edges.T[::-1])
    edges, owner = edges[order], owner[order]
    same = np.all(edges[1:] == edges[:-1], axis=1)
    kept = [edges[i] for i in np.flatnonzero(same)
            if normals[owner[i]] @ normals[owner[i + 1]] < np.cos(np.radians(angle))]
    single = np.ones(len(edges), dtype=bool)
    single[1:] &= ~same
    single[:-1] &= ~same
    kept += list(edges[single])
    return np.array(kept, dtype=int).reshape(-1, 2)
