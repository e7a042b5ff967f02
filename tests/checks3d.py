"""checks3d.py: the checks of tests/check_results.py that only a 3D run has (docs/design.md,
"Three dimensions"): each contact node's frame (orthonormal, right-handed, and contact.txt's
velocities those of fields.txt in it), and the von Mises stress recomputed on the
tetrahedra. A mixin of check_results.Checks (it uses checker.Checker's outputs and
allowances).
"""
import os

import numpy as np

import runfiles
from checker import ROUNDOFF


class Checks3D:
    """check_frame, check_stress3 (with tetrahedra, gradient)."""

    def check_frame(self, rtol):
        """3D: each node's frame (n, t1, t2 of contact.txt) is orthonormal and right-handed (t2 =
        n x t1), and its velocities are those of fields.txt at the node in that frame: v_nu =
        n.v, v_tau = t1.v, v_tau2 = t2.v (docs/design.md, "Three dimensions"; computed from v
        itself, also where a Dirichlet condition leaves a node fewer slots)."""
        c, f = self.c, self.f
        n, t1, t2 = (np.c_[c[f"{axis}_x"], c[f"{axis}_y"], c[f"{axis}_z"]] for axis in ("n", "t1", "t2"))
        gram = np.stack([n, t1, t2], 1) @ np.stack([n, t1, t2], 2)       # (nodes, 3, 3): I
        off = np.abs(gram - np.eye(3)).max()
        self.expect(off <= 1e-12, f"contact.txt: a node's frame n, t1, t2 is not orthonormal (off by {off:.3e})")
        handed = np.abs(np.cross(n, t1) - t2).max()
        self.expect(handed <= 1e-12, f"contact.txt: a node's frame is not right-handed, |n x t1 - t2| = {handed:.3e}")
        # the node's row of fields.txt: the vertex at its coordinates
        points, at = np.c_[f["x"], f["y"], f["z"]], np.c_[c["x"], c["y"], c["z"]]
        size = max(float(np.ptp(points, axis=0).max()), 1e-300)
        rows = np.array([int(np.argmin(np.abs(points - p).sum(1))) for p in at])
        away = np.abs(points[rows] - at).max() / size
        if not self.expect(away <= 1e-12, f"contact.txt: a node is no vertex of fields.txt ({away:.3e} of the body's "
                           "size away)"):
            return
        v = np.c_[f["v_x"], f["v_y"], f["v_z"]][rows]
        scale = max(float(np.abs(v).max()), float(c["g"].max()))
        for name, axis in (("v_nu", n), ("v_tau", t1), ("v_tau2", t2)):
            err = np.abs((v * axis).sum(1) - c[name]).max() / scale
            # round-off: of the three products of v (at most scale) with the unit axis
            self.expect(err <= rtol + 3 * ROUNDOFF, f"contact.txt {name} differs from fields.txt's v projected on the "
                        f"node's frame by {err:.3e} of max(|v|, g) = {scale:.3e} (bound {rtol:g})")

    def tetrahedra(self):
        """The mesh of a 3D run: its tetrahedra (rows of fields.txt, which lists the vertices in
        the mesh's order: checked), their gradient operators and volumes. grad[t] solves
        D grad = (f1 - f0, f2 - f0, f3 - f0) for the edges D of tetrahedron t from its vertex 0:
        the gradient of the P1 function of vertex values f, constant on t."""
        f = self.f
        mesh = runfiles.read_msh3(os.path.join(self.folder, "mesh.msh"))
        xyz, tet = mesh.xyz, mesh.tetrahedra
        points = np.c_[f["x"], f["y"], f["z"]]
        size = max(float(np.ptp(xyz, axis=0).max()), 1e-300)
        if not self.expect(len(xyz) == len(f) and np.abs(xyz - points).max() <= 1e-12 * size,
                           "fields.txt does not list the vertices of mesh.msh in its order"):
            return None
        self.expect(self.count("tetrahedra") == len(tet),
                    f"summary tetrahedra = {self.summary.get('tetrahedra')} but mesh.msh has {len(tet)}")
        edges = points[tet[:, 1:]] - points[tet[:, :1]]                 # (t, 3 edges, 3 coordinates)
        volume = np.abs(np.linalg.det(edges)) / 6
        self.expect(bool((volume > 0).all()), "mesh.msh: a tetrahedron of zero volume")
        return tet, edges, volume

    def gradient(self, tet, edges, values):
        """The gradient (t, 3) of the P1 field of vertex values on each tetrahedron."""
        return np.linalg.solve(edges, (values[tet[:, 1:]] - values[tet[:, :1]])[..., None])[..., 0]

    def check_stress3(self, rtol):
        """3D von Mises: on each tetrahedron sigma = A eps(v) + B eps(u), A eps = muv tr(eps) I +
        eta eps, B eps = lambda3 tr(eps) I + E/(1+nu) eps (docs/design.md, "Three dimensions"),
        its measure sqrt(((sxx-syy)^2 + (syy-szz)^2 + (szz-sxx)^2)/2 + 3(sxy^2 + syz^2 + sxz^2)),
        averaged at each vertex over its tetrahedra with their volumes as weights."""
        f, mesh = self.f, self.tetrahedra()
        if mesh is None:
            return
        tet, edges, volume = mesh

        def strain(prefix):       # eps[t, i, j] = (d u_j/d x_i + d u_i/d x_j)/2
            grad = np.stack([self.gradient(tet, edges, f[f"{prefix}_{axis}"]) for axis in "xyz"], 2)
            return 0.5 * (grad + grad.transpose(0, 2, 1))
        E, nu, muv, eta = self.real("E"), self.real("nu"), self.real("muv"), self.real("eta")
        ev, eu = strain("v"), strain("u")
        trace = muv * np.trace(ev, axis1=1, axis2=2) + self.elastic_lambda() * np.trace(eu, axis1=1, axis2=2)
        sigma = trace[:, None, None] * np.eye(3) + eta * ev + E / (1 + nu) * eu
        sxx, syy, szz = sigma[:, 0, 0], sigma[:, 1, 1], sigma[:, 2, 2]
        vm = np.sqrt(((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) / 2
                     + 3 * (sigma[:, 0, 1] ** 2 + sigma[:, 1, 2] ** 2 + sigma[:, 0, 2] ** 2))
        weight, total = np.zeros(len(f)), np.zeros(len(f))
        for k in range(4):
            np.add.at(weight, tet[:, k], volume)
            np.add.at(total, tet[:, k], volume * vm)
        mine = total / weight
        error = np.abs(mine - f["von_mises"]).max()
        self.expect(error <= rtol * max(np.abs(mine).max(), 1e-300) + self.stress_field_roundoff(),
                    f"von_mises: fields.txt differs from its recomputation (tetrahedra) by {error:.3e} "
                    f"(largest {np.abs(mine).max():.3e}, bound {rtol:g} of it)")
