"""gamma3.py: where the contact nodes of a 2D run lie along Gamma3, for the figures: the
position along it (x, or the arc length of a curved or broken Gamma3), its pieces (the
mesh's contact lines that join), each node's cell (halfway to its neighbours on its piece),
and the stretches of consecutive nodes with the same zone, shaded and labelled
(docs/figures.md, "The figures of one run", "The zones"). Imported by the scripts of plots/,
which put edp/ (runfiles) on the path.
"""
import collections

import numpy as np

import runfiles


def nearest(points, targets):
    """For each target (x, y), the row of the nearest of points (n, 2)."""
    points = np.asarray(points, dtype=float)
    return np.array([int(np.argmin(np.hypot(*(points - target).T))) for target in np.asarray(targets, dtype=float)],
                    dtype=int)


def boundary_edges(triangles):
    """The edges (pairs of nodes) of one triangle only: the boundary of the body."""
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    return unique[counts == 1]


def contact_lines(mesh):
    """The boundary lines of the mesh's contact label (physical curve 1)."""
    lines = mesh.lines[mesh.line_labels == runfiles.labels()["GammaContact"]]
    if not len(lines):
        raise runfiles.InputError("the mesh has no contact boundary (physical curve 1)")
    return lines


def boundary_arc_length(mesh):
    """The arc length along the contact lines: {row of mesh.xy: s}. The walk starts at the end
    of smallest (x, y); where Gamma3 is in pieces, each next piece starts from its own end of
    smallest (x, y), s going on across the straight gap."""
    neighbours = collections.defaultdict(list)
    for a, b in contact_lines(mesh):
        neighbours[a].append(b)
        neighbours[b].append(a)
    s, last, length = {}, None, 0.0
    while len(s) < len(neighbours):
        left = [node for node in neighbours if node not in s]
        ends = [node for node in left if len(neighbours[node]) == 1] or left     # a closed loop has no end
        node = min(ends, key=lambda n: tuple(mesh.xy[n]))
        while node is not None:                             # along the piece, to its other end
            if last is not None:
                length += float(np.hypot(*(mesh.xy[node] - mesh.xy[last])))
            s[node], last = length, node
            node = next((n for n in neighbours[node] if n not in s), None)
    return s


def contact_position(mesh, x, y):
    """Where the contact nodes (x, y) lie along Gamma3, and the axis label: x itself when
    Gamma3 is straight along x (every y the same), otherwise the arc length along the mesh's
    contact lines (boundary_arc_length), each node taken as the nearest node of those."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if np.ptp(y) <= 1e-9 * max(np.ptp(x), 1e-300):
        return x, "x [m]"
    s = boundary_arc_length(mesh)
    nodes = np.array(sorted(s))
    start = mesh.xy[min(s, key=s.get)]
    return (np.array([s[n] for n in nodes[nearest(mesh.xy[nodes], np.c_[x, y])]]),
            f"arc length along $\\Gamma_3$ from ({start[0]:.3g}, {start[1]:.3g}) [m]")


def contact_pieces(mesh, x, y):
    """The piece of Gamma3 each contact node (x, y) lies on, numbered 0, 1, ...: the contact
    lines joined where they share a node (one piece for a connected Gamma3, two for a body on
    two feet); each node is taken as the nearest node of those lines."""
    parent = {}

    def root(node):
        while parent.setdefault(node, node) != node:
            node = parent[node]
        return node
    for a, b in contact_lines(mesh):
        parent[root(a)] = root(b)
    on = np.array(sorted(parent))
    numbers = {}
    piece = {node: numbers.setdefault(root(node), len(numbers)) for node in on}
    return np.array([piece[node] for node in on[nearest(mesh.xy[on], np.c_[x, y])]], dtype=int)


def node_cells(position, pieces=None):
    """The stretch of Gamma3 each node holds, as arrays (start, end): up to halfway to its
    neighbours on its own piece (one piece when None), up to its own position where it ends
    its piece. A gap between two pieces belongs to no node."""
    position = np.asarray(position, dtype=float)
    pieces = np.zeros(len(position), dtype=int) if pieces is None else np.asarray(pieces)
    start, end = position.copy(), position.copy()
    for piece in np.unique(pieces):
        on = np.flatnonzero(pieces == piece)
        on = on[np.argsort(position[on], kind="stable")]
        halfway = 0.5 * (position[on[1:]] + position[on[:-1]])
        start[on[1:]], end[on[:-1]] = halfway, halfway
    return start, end


def along_gamma3(position, pieces, *columns):
    """position and the columns in the order of position, a nan put between two nodes of
    different pieces: a curve through them is broken across the gaps."""
    order = np.argsort(position, kind="stable")
    cuts = np.flatnonzero(np.diff(np.asarray(pieces)[order]) != 0) + 1
    return [np.insert(np.asarray(column, dtype=float)[order], cuts, np.nan) for column in (position,) + columns]


def map_columns(position, pieces):
    """The columns of a map of the nodes along Gamma3 (pcolormesh): their edges, and for each
    column the node it shows (in the order of position), or -1 for a gap between two pieces."""
    start, end = node_cells(position, pieces)
    order = np.argsort(position, kind="stable")
    edges, columns = [start[order[0]]], []
    for before, node in zip(np.r_[-1, order[:-1]], order):
        if before >= 0 and pieces[node] != pieces[before]:
            edges.append(start[node])
            columns.append(-1)
        edges.append(end[node])
        columns.append(node)
    return np.array(edges), np.array(columns, dtype=int)


def stretches(position, keys, pieces=None):
    """The stretches over which consecutive nodes (in the order of position, on one piece)
    have the same key: [(key, start, end, nodes)], wherever they lie, a key perhaps in several
    stretches. Each node holds its cell (node_cells); a stretch never spans a gap."""
    pieces = np.zeros(len(keys), dtype=int) if pieces is None else np.asarray(pieces)
    start, end = node_cells(position, pieces)
    found = []
    for node in np.argsort(position, kind="stable"):
        if found and found[-1][0] == keys[node] and found[-1][4] == pieces[node]:
            found[-1][2], found[-1][3] = end[node], found[-1][3] + 1
        else:
            found.append([keys[node], start[node], end[node], 1, pieces[node]])
    return [(key, first, last, count) for key, first, last, count, _ in found]


def shade_stretches(ax, found, colors, alpha=0.15):
    """Shade each stretch (of stretches()) whose key has a colour in colors."""
    for key, start, end, _ in found:
        if key in colors:
            ax.axvspan(start, end, color=colors[key], alpha=alpha, linewidth=0)


def label_stretches(ax, found, texts, heights, fontsize=8):
    """Write texts[key] once a key, centred over its widest stretch, at the first of the
    heights (fractions of the axes' height) where it overlaps no label written before (the
    last height when none is free). Call it once the layout and x limits are final."""
    widest = {}
    for key, start, end, _ in found:
        if key in texts and (key not in widest or end - start > widest[key][1] - widest[key][0]):
            widest[key] = (start, end)
    renderer = ax.figure.canvas.get_renderer()
    boxes = []
    for key, (start, end) in sorted(widest.items(), key=lambda item: item[1]):
        for y in heights:
            label = ax.text(0.5 * (start + end), y, texts[key], ha="center", fontsize=fontsize,
                            transform=ax.get_xaxis_transform())
            box = label.get_window_extent(renderer).padded(1)
            if y == heights[-1] or not any(box.overlaps(other) for other in boxes):
                break
            label.remove()
        boxes.append(box)
