"""independent_model3d.py: the discrete problem of tests/independent_solver3d.py, its
own (docs/design.md, "The discrete problem", "Nodal contact", "Three dimensions"): the
scene's keys (Scene), the P1 matrices on the tetrahedra (assemble), the contact nodes'
weights, normals and frames (face_normals, node_frame), and Model, the unknowns, slots and
constant blocks of one run, with its tables (contact_table, fields_table). The mesh and the
scene file are read with edp/runfiles.py; the Newton that solves the steps is
tests/independent_solver3d.py. Written from docs/design.md only, not from the solver.
"""
import numpy as np

import runfiles

InputError = runfiles.InputError
CONTACT_LABEL, TRACTION_LABEL = 1, 3          # docs/design.md, "Three dimensions" (box.geo's tags)
AXES = {"x": 0, "y": 1, "z": 2}
DENSE_LIMIT = 800                             # set_linear("auto"): the whole Jacobian up to this size


def read_mesh(path):
    """Nodes (n x 3), tetrahedra, boundary triangles and their physical labels of an ASCII
    gmsh MSH 2.2 file (runfiles.read_msh3: other element types than points, lines,
    triangles and tetrahedra refused)."""
    mesh = runfiles.read_msh3(path)
    return mesh.xyz, mesh.tetrahedra, mesh.faces, mesh.face_labels


# ----------------------------------------------------------------------------- scene
class Scene:
    """The keys of a scene file that define the problem (docs/design.md, "Scenes", "Three
    dimensions"): dirichlet, traction, body_force, initial_velocity, load_history,
    bound_profile, damping, contact_normal; `values` holds its other 'NAME VALUE' lines
    (option defaults, geometry). The file is read with runfiles.read_scene, the keys
    interpreted here."""

    def __init__(self, path):
        read = runfiles.read_scene(path)
        self.path = path
        self.dirichlet = {}
        self.traction = None
        self.body_force = np.zeros(3)
        self.initial_velocity = np.zeros(3)
        self.load_history = None
        self.bound_profile = None
        self.damping = None
        self.contact_normal = None
        self.values = dict(read.options)
        for key, lines in read.data.items():
            for rest in lines:
                try:
                    self.read(key, rest, "%s: %s" % (path, key))
                except ValueError:
                    raise InputError("%s: %s: unreadable number in '%s'" % (path, key, " ".join(rest))) from None
        if self.traction is None:
            raise InputError("%s: no traction line" % path)
        if self.damping is not None and self.damping[0] != "linear":
            raise InputError("%s: damping %s: only the linear damping p(r) = cnu max(r, 0) is supported"
                             % (path, self.damping[0]))

    def read(self, key, rest, where):
        """One line KEY REST... of the scene."""
        if key == "dirichlet":
            if len(rest) != 2 or not rest[1] or any(c not in AXES for c in rest[1]):
                raise InputError("%s: expected LABEL x|y|z|xy|xz|yz|xyz" % where)
            self.dirichlet[int(rest[0])] = sorted({AXES[c] for c in rest[1]})
        elif key in ("traction", "body_force", "initial_velocity"):
            vec = np.array([float(w) for w in rest])
            if len(vec) != 3:
                raise InputError("%s: expected 3 numbers (a 3D scene)" % where)
            if key == "traction":
                norm = np.linalg.norm(vec)
                if not norm > 0:
                    raise InputError("%s: a zero direction" % where)
                self.traction = vec / norm
            else:
                setattr(self, key, vec)
        elif key in ("load_history", "bound_profile"):
            pts = np.array([float(w) for w in rest])
            if len(pts) < 2 or len(pts) % 2:
                raise InputError("%s: expected pairs of numbers" % where)
            setattr(self, key, pts)
        elif key == "damping":
            self.damping = (rest[0], [float(w) for w in rest[1:]])
        elif key == "contact_normal":
            self.contact_normal = None if rest == ["auto"] else np.array([float(w) for w in rest])
            if self.contact_normal is not None and len(self.contact_normal) != 3:
                raise InputError("%s: expected auto or 3 numbers" % where)
        elif len(rest) == 1:
            self.values[key] = rest[0]
        else:
            raise InputError("%s: cannot read '%s'" % (where, " ".join(rest)))

    def h(self, t):
        return t if self.load_history is None else float(np.interp(t, self.load_history[0::2],
                                                                   self.load_history[1::2]))


# ----------------------------------------------------------------------------- assembly
def assemble(xyz, tets, prm):
    """Dense M, A, B (dof 3 * node + component) and the body-force integral per unit f0."""
    nn = len(xyz)
    nd = 3 * nn
    P = xyz[tets]                                          # (nt, 4, 3)
    J = np.stack([P[:, 1] - P[:, 0], P[:, 2] - P[:, 0], P[:, 3] - P[:, 0]], axis=2)   # columns: edges
    det = np.linalg.det(J)
    vol = np.abs(det) / 6.0
    if not (vol > 0).all():
        raise InputError("a tetrahedron of zero volume")
    G = np.linalg.inv(J)                                   # rows: gradients of the ref. coordinates
    grads = np.concatenate([-G.sum(axis=1, keepdims=True), G], axis=1)     # (nt, 4, 3): g_a
    gg = np.einsum("tai,tbi->tab", grads, grads)           # g_a . g_b
    I3 = np.eye(3)
    div = np.einsum("tai,tbj->taibj", grads, grads)         # g_a,i g_b,j  (div div)
    # eps(phi_a e_i) : eps(phi_b e_j) = (delta_ij g_a.g_b + g_a,j g_b,i) / 2
    epseps = 0.5 * (np.einsum("ij,tab->taibj", I3, gg) + np.einsum("taj,tbi->taibj", grads, grads))
    E, nu = prm["E"], prm["nu"]
    lam3 = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    Kb = vol[:, None, None, None, None] * (lam3 * div + E / (1.0 + nu) * epseps)
    Ka = vol[:, None, None, None, None] * (prm["muv"] * div + prm["eta"] * epseps)
    mloc = (np.ones((4, 4)) + np.eye(4)) / 20.0
    Km = prm["rho"] * vol[:, None, None, None, None] * np.einsum("ab,ij->aibj", mloc, I3)[None]
    dofs = (3 * tets[:, :, None] + np.arange(3)[None, None, :]).reshape(len(tets), 12)
    rows = np.repeat(dofs, 12, axis=1).ravel()
    cols = np.tile(dofs, (1, 12)).ravel()
    flat = rows * nd + cols
    mats = []
    for K in (Km, Ka, Kb):
        out = np.zeros(nd * nd)
        np.add.at(out, flat, K.reshape(len(tets), 144).ravel())
        mats.append(out.reshape(nd, nd))
    body = np.zeros(nn)
    np.add.at(body, tets.ravel(), np.repeat(vol / 4.0, 4))     # int phi_a = vol/4
    used = np.zeros(nn, dtype=bool)
    used[tets.ravel()] = True
    if not used.all():
        raise InputError("%d mesh node(s) belong to no tetrahedron" % (~used).sum())
    return mats[0], mats[1], mats[2], body


def face_normals(xyz, tets, faces):
    """Unit outward normals and areas of boundary triangles (outward: away from the fourth
    vertex of the tetrahedron that has the face)."""
    opposite = {}
    for t in tets:
        for a in range(4):
            f = tuple(sorted(np.delete(t, a)))
            opposite.setdefault(f, []).append(t[a])
    normals, areas = np.zeros((len(faces), 3)), np.zeros(len(faces))
    for k, f in enumerate(faces):
        key = tuple(sorted(f))
        if key not in opposite or len(opposite[key]) != 1:
            raise InputError("boundary triangle %s is not a face of exactly one tetrahedron" % list(f))
        c = np.cross(xyz[f[1]] - xyz[f[0]], xyz[f[2]] - xyz[f[0]])
        area = 0.5 * np.linalg.norm(c)
        if not area > 0:
            raise InputError("boundary triangle %s has zero area" % list(f))
        n = c / (2.0 * area)
        if np.dot(n, xyz[opposite[key][0]] - xyz[f[0]]) > 0:
            n = -n
        normals[k], areas[k] = n, area
    return normals, areas


def node_frame(nsum, weight, fixed, node, xyz):
    """The frame (n, t1, t2) and the tangential slots of a contact node (the frame's
    directions 1 and/or 2; None: no slot at all) (docs/design.md, "Three dimensions")."""
    norm = np.linalg.norm(nsum)
    where = "contact node at (%g, %g, %g)" % tuple(xyz)
    if norm < 0.5 * weight:
        raise InputError("%s: the boundary turns by more than 120 degrees" % where)
    n = nsum / norm
    fixed_axes = [a for a in range(3) if fixed[a]]
    free_axes = [a for a in range(3) if not fixed[a]]

    def standard(n):
        e = np.eye(3)[int(np.flatnonzero(np.abs(n) <= np.abs(n).min() + 1e-9)[0])]   # least aligned, the first within 1e-9
        t1 = e - np.dot(e, n) * n
        t1 /= np.linalg.norm(t1)
        return t1, np.cross(n, t1)
    if len(fixed_axes) == 0:
        t1, t2 = standard(n)
        return n, t1, t2, [1, 2]
    if len(fixed_axes) == 1:
        e = np.eye(3)[fixed_axes[0]]
        m = n - np.dot(n, e) * e
        if np.linalg.norm(m) < 0.5:
            raise InputError("%s: the free velocity is no normal velocity" % where)
        n = m / np.linalg.norm(m)
        t1, t2 = standard(n)
        if abs(np.dot(t1, e)) > 1 - 1e-12:
            return n, t1, t2, [2]
        if abs(np.dot(t2, e)) > 1 - 1e-12:
            return n, t1, t2, [1]
        t2 = e
        return n, np.cross(t2, n), t2, [1]
    if len(fixed_axes) == 2:
        f = np.eye(3)[free_axes[0]]
        c = np.dot(n, f)
        if abs(c) < 0.5:
            raise InputError("%s: the free component is no normal velocity" % where)
        n = np.sign(c) * f
        t1, t2 = standard(n)
        return n, t1, t2, []
    t1, t2 = standard(n)
    return n, t1, t2, None                                    # no slot at all


# ----------------------------------------------------------------------------- one run's unknowns
class Model:
    """The discrete problem of one run: M, A, B, the free dofs (Dirichlet components
    removed), the contact nodes (weights, frames, slots), g at each node, the scales of the
    Newton rows; the run's state (u, v, x) once solved (independent_solver3d.Problem.run)."""

    def __init__(self, mesh, prm, scene):
        xyz, tets, tris, tlab = mesh
        self.prm, self.scene, self.xyz = prm, scene, xyz
        N = int(round(prm["T"] / prm["dt"]))
        if N < 1 or abs(N * prm["dt"] - prm["T"]) > 1e-9 * prm["T"]:
            raise InputError("dt does not divide T")
        self.N, self.k = N, prm["T"] / N
        nn = len(xyz)
        nd = 3 * nn
        self.M, self.A, self.B, body = assemble(xyz, tets, prm)
        # Dirichlet components
        fixed = np.zeros((nn, 3), dtype=bool)
        for label, comps in scene.dirichlet.items():
            if not (tlab == label).any():
                raise InputError("the mesh has no boundary triangle of the Dirichlet label %d" % label)
            for f in tris[tlab == label]:
                fixed[np.ix_(f, comps)] = True
        for label in (CONTACT_LABEL, TRACTION_LABEL):
            if not (tlab == label).any():
                raise InputError("the mesh has no boundary triangle of label %d" % label)
        self.fixed = fixed.ravel()
        # traction (per unit load and h) and body force
        trac = np.zeros((nn, 3))
        tf = tris[tlab == TRACTION_LABEL]
        _, tarea = face_normals(xyz, tets, tf)
        for f, a in zip(tf, tarea):
            trac[f] += a / 3.0 * scene.traction
        self.trac = trac.ravel()
        self.body = (body[:, None] * scene.body_force[None, :]).ravel()
        # contact nodes: weights, normals, frames
        cf = tris[tlab == CONTACT_LABEL]
        cn_, carea = face_normals(xyz, tets, cf)
        self.cnodes = np.unique(cf.ravel())
        weight, nsum = np.zeros(nn), np.zeros((nn, 3))
        for f, nrm, a in zip(cf, cn_, carea):
            weight[f] += a / 3.0
            nsum[f] += a / 3.0 * nrm
        self.weight = weight[self.cnodes]
        frames, ntang, self.tdirs = [], [], []
        for v in self.cnodes:
            n, t1, t2, dirs = node_frame(nsum[v], weight[v], fixed[v], v, xyz[v])
            nt = -1 if dirs is None else len(dirs)
            self.tdirs.append(dirs or [])
            if scene.contact_normal is not None:      # the mesh's normal, before any projection
                N_, m = scene.contact_normal, nsum[v] / np.linalg.norm(nsum[v])
                if np.dot(m, N_) < 0.999 * np.linalg.norm(N_):
                    raise InputError("contact node at (%g, %g, %g): normal %s is not the scene's contact_normal %s"
                                     % (tuple(xyz[v]) + (m, N_)))
            frames.append((n, t1, t2))
            ntang.append(nt)
        self.frames = np.array(frames)                       # (nc, 3, 3): n, t1, t2
        self.ntang = np.array(ntang)
        if (self.ntang < 0).all():
            raise InputError("no contact slot: every contact node is fixed")
        # g per node
        if scene.bound_profile is not None:
            g_node = np.interp(xyz[self.cnodes, 0], scene.bound_profile[0::2], scene.bound_profile[1::2])
        else:
            g_node = np.full(len(self.cnodes), prm["g"])
        # free dofs
        self.free = np.flatnonzero(~self.fixed)
        nf = self.nf = len(self.free)
        pos = -np.ones(nd, dtype=int)
        pos[self.free] = np.arange(nf)
        # slots: normal (one per node with a free component); tangential (t1, t2)
        self.nnodes = np.flatnonzero(self.ntang >= 0)        # contact-node index of each normal slot
        nN = len(self.nnodes)
        tslot_node, tslot_dir = [], []
        self.groups = []                                     # (normal slot, [tangential slots])
        for j, c in enumerate(self.nnodes):
            sl = []
            for d in self.tdirs[c]:
                sl.append(len(tslot_node))
                tslot_node.append(c)
                tslot_dir.append(d)
            if sl:
                self.groups.append((j, sl))
        nT = len(tslot_node)
        self.nN, self.nT = nN, nT
        # contact dofs (free dofs of the contact nodes) and the slot rows on them
        cd = sorted({pos[3 * v + a] for v in self.cnodes for a in range(3) if pos[3 * v + a] >= 0})
        self.cd = np.array(cd, dtype=int)
        loc = {d: i for i, d in enumerate(cd)}

        def rows(nodes, dirs):
            R = np.zeros((len(nodes), len(cd)))
            for i, (c, d) in enumerate(zip(nodes, dirs)):
                v = self.cnodes[c]
                for a in range(3):
                    if pos[3 * v + a] >= 0:
                        R[i, loc[pos[3 * v + a]]] = self.frames[c, d, a]
            return R
        self.Cn = rows(self.nnodes, [0] * nN)                # v_nu  = Cn v[cd]
        self.Ct = rows(tslot_node, tslot_dir)                # v_tau = Ct v[cd]
        self.wn = self.weight[self.nnodes]
        self.wt = self.weight[np.array(tslot_node, dtype=int)] if nT else np.zeros(0)
        self.gn = g_node[self.nnodes]
        self.g_node = g_node
        k = self.k
        S = self.M / k + self.A + k * self.B
        self.S = S[np.ix_(self.free, self.free)]
        self.Mf, self.Bf = self.M[self.free], self.B[self.free]
        self.tracf, self.bodyf = self.trac[self.free], self.body[self.free]
        # scales: r_j = 1/(w c_j' S^-1 c_j), the stress that makes a unit velocity at slot j
        C = np.zeros((nN + nT, nf))
        C[:, self.cd] = np.vstack([self.Cn, self.Ct])
        d = np.einsum("ij,ji->i", C, np.linalg.solve(self.S, C.T))
        self.rn = 1.0 / (self.wn * d[:nN])
        self.rg = [1.0 / (self.weight[self.nnodes[j]] * d[nN + np.array(sl)].mean()) for j, sl in self.groups]
        self.rfac = 1.0                                      # the factor on them of the current attempt
        # the constant block of the Jacobian: d(equilibrium rows on cd)/d(lambda)
        self.Bv = np.hstack([self.Cn.T * self.wn, self.Ct.T * self.wt])
        self.linear = None
        self.set_linear("auto")

    def set_linear(self, how):
        """How Newton's linear systems are solved: 'dense', the whole Jacobian by
        numpy.linalg.solve, or 'schur', v eliminated with S^-1 (formed once) and the
        system of the contact dofs and stresses solved (the same iterates, to
        round-off, for larger meshes); 'auto': dense up to DENSE_LIMIT unknowns."""
        n = self.nf + self.nN + self.nT
        if how == "auto":
            how = "dense" if n <= DENSE_LIMIT else "schur"
        self.linear = how
        if how == "schur" and not hasattr(self, "Sinv"):
            self.Sinv = np.linalg.inv(self.S)
            self.Sinv_cd = self.Sinv[:, self.cd]               # S^-1 E
            self.G = self.Sinv_cd[self.cd]                     # E' S^-1 E

    def split(self, x):
        nf, nN = self.nf, self.nN
        return x[:nf], x[nf:nf + nN], x[nf + nN:]

    def contact_table(self):
        """x y z v_nu v_tau v_tau2 p_nu lambda_nu lambda_tau lambda_tau2 per contact node."""
        p = self.prm
        _, ln, lt = self.split(self.x)
        nc = len(self.cnodes)
        lam_n, lam_t = np.zeros(nc), np.zeros((nc, 2))
        lam_n[self.nnodes] = ln
        for j, sl in self.groups:
            c = self.nnodes[j]
            for k, slot in enumerate(sl):
                lam_t[c, self.tdirs[c][k] - 1] = lt[slot]
        V = self.v.reshape(-1, 3)[self.cnodes]
        vel = np.einsum("cda,ca->cd", self.frames, V) + 0.0
        damped = p["cnu"] * np.maximum(vel[:, 0], 0.0)
        pnu = damped + lam_n
        pnu[self.ntang < 0] = 0.0
        # what the law gives each node (docs/design.md, "Statuses and zones"), derived here on its own
        g = self.g_node
        normal = np.where(vel[:, 0] <= 0, 0, np.where(vel[:, 0] >= g * (1 - 1e-6), 2, 1))
        tangential = (np.hypot(vel[:, 1], vel[:, 2]) > 1e-6 * g).astype(int)
        zone = np.where(normal == 0, 0, 2 * normal - tangential)
        scale = np.where(p["cnu"] * g > 0, p["cnu"] * g, 1.0)
        return np.column_stack([self.xyz[self.cnodes], vel, pnu, lam_n, lam_t, g, damped, scale, zone])

    def fields_table(self):
        return np.column_stack([self.xyz, self.u.reshape(-1, 3), self.v.reshape(-1, 3)])
