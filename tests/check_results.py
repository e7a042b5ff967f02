#!/usr/bin/python3
"""Check one output folder of edp/solve.edp against the physics (docs/design.md,
"End-of-run checks" and "Energy identity").

Reads only the text outputs (nothing of the solver), so it is an independent check:
  constraint and complementarity (original problem), the penalty law (penalty problem),
  the friction cone and the direction of friction, p_nu = p(v_nu) + lambda_nu,
  the discrete energy balance of every step recomputed from its terms, the contact
  dissipation of the last step recomputed from contact.txt, the zone counts, the rows of
  contact_nodes_history.txt against contact.txt and contact_history.txt, the von Mises
  stress of fields.txt recomputed from the fields and the mesh.
A 3D run (summary.txt: dimension 3; docs/design.md, "Three dimensions") is checked alike,
with the disk friction law (|lambda_tau| = hypot(lambda_tau, lambda_tau2), colinear with
the slip), its tetrahedra and its node frames (contact.txt's velocities are those of
fields.txt in the frame n, t1, t2).
Options add: expected zone counts, the known answer of the column scene (column, column3d),
that of the oblique slide (oblique-slide3d: the disk law's total friction force and the
block's momentum), and agreement with another output folder of the same discrete problem.

Usage: check_results.py DIR [--zones FREE,DAMPED_SLIP,DAMPED_STICK,BOUND_SLIP,BOUND_STICK] [--column] [--slide]
                            [--compare OTHER_DIR] [--rtol 1e-9] [--other-law]
--other-law: the run solves another law than the paper's (a changed contactlaw.hpp): the
checks that restate p(r) = c_nu r_+ are skipped, the friction cone uses friction_bound.
Prints one line per failed check and exits 1 if any failed (or, on an unreadable
input, one error line); exits 2 when plots/suite.py cannot be imported (run it through
./run.sh, which sets PYTHONPATH), and when --column does not apply to the run's load history
(one line saying why: a history that pulls the column before it presses it).
Every comparison with a bound allows for round-off: ROUNDOFF (256 ulps) times the magnitude
of the terms the compared quantities are computed from (velocity_terms, stress_terms,
stiffness_terms), never a fixed tolerance.
"""
import argparse
import math
import os
import sys

import numpy as np

try:
    import suite
except ModuleNotFoundError as error:
    if error.name != "suite":
        raise
    print(f"{os.path.basename(sys.argv[0])}: error: cannot import suite (plots/suite.py): run it through ./run.sh, "
          "or set PYTHONPATH=plots", file=sys.stderr)
    sys.exit(2)

FILES = ("contact.txt", "fields.txt", "history.txt", "contact_history.txt", "summary.txt")
# The round-off allowance of every comparison with a bound: ROUNDOFF times the magnitude of
# the terms the compared quantities are computed from (not of the quantities themselves,
# which may be far smaller after cancellation: a column held at v_nu = g by the constraint
# alone, or flying away at 1e5 m/s, computes v_nu from terms of 1e5 m/s). Each sum of such
# terms, in the solver and here, loses a few ulps of their magnitude: measured up to 5 u
# (u = 2.2e-16, machine epsilon) on the false alarms this allowance removed; 256 u leaves a
# factor of 50 for longer sums (finer meshes) and other floating-point orders, and is 1e-13
# relative: a corruption that a check must catch is 1e4 times larger than the tolerance rtol.
ROUNDOFF = 256 * np.finfo(float).eps


def worst(values, allowance):
    """The value that passes its round-off allowance the most (values and allowance arrays of
    one shape, or scalars): (that value - its allowance, the value, the allowance)."""
    values, allowance = (np.ravel(np.asarray(a, dtype=float)) for a in np.broadcast_arrays(values, allowance))
    k = int(np.argmax(values - allowance))
    return float(values[k] - allowance[k]), float(values[k]), float(allowance[k])


def slopes(law, r):
    """|p'(r)| of the law (a RunScene) at each r: a central difference quotient."""
    r = np.asarray(r, dtype=float)
    step = 1e-7 * np.maximum(np.abs(r), 1e-300)
    return np.abs(law.p(r + step) - law.p(r - step)) / (2 * step)


class Refusal(Exception):
    """A check that was asked for does not apply to the run (exit 2, one line saying why)."""
FRAME = ("n_x", "n_y", "n_z", "t1_x", "t1_y", "t1_z", "t2_x", "t2_y", "t2_z")     # contact.txt in 3D


def run_dimension(summary):
    """2 or 3: summary.txt's 'dimension' (runs from before 3D bodies have none: 2D)."""
    return summary.integer("dimension") if "dimension" in summary else 2


def read_tetrahedra(path):
    """The nodes (n, 3) and the tetrahedra (gmsh type 4; rows of the nodes, in the file's node
    order) of the ASCII gmsh MSH 2.2 file of a 3D run. suite.read_msh22 reads a 2D mesh: it
    would take a 3D mesh's labelled boundary triangles for its cells."""
    lines = suite.read_lines(path)
    sections = {line.strip(): i for i, line in enumerate(lines) if line.startswith("$")}
    try:
        start = sections["$Nodes"]
        ids, xyz = {}, np.empty((int(lines[start + 1]), 3))
        for i, line in enumerate(lines[start + 2:start + 2 + len(xyz)]):
            words = line.split()
            ids[int(words[0])] = i
            xyz[i] = [float(w) for w in words[1:4]]
        start = sections["$Elements"]
        tetrahedra = []
        for line in lines[start + 2:start + 2 + int(lines[start + 1])]:
            words = [int(w) for w in line.split()]
            if words[1] == 4:                                     # 4-node tetrahedron
                tetrahedra.append([ids[n] for n in words[3 + words[2]:7 + words[2]]])
    except (ValueError, IndexError, KeyError) as error:
        raise suite.InputError(f"{path}: not a readable gmsh MSH 2.2 file ({type(error).__name__}: {error})") from None
    if not tetrahedra:
        raise suite.InputError(f"{path}: no tetrahedra in the mesh of a 3D run")
    return xyz, np.array(tetrahedra, dtype=int)


class Checker:
    def __init__(self, folder, other_law=False):
        self.folder = folder
        self.other_law = other_law
        self.failures = []

    def expect(self, condition, message):
        if not condition:
            self.failures.append(message)
        return condition

    def load(self):
        for name in FILES:
            if not self.expect(os.path.isfile(os.path.join(self.folder, name)), f"missing {name}"):
                return False
        self.c = suite.read_table(os.path.join(self.folder, "contact.txt"))
        self.params = self.c.params
        self.h = suite.read_table(os.path.join(self.folder, "history.txt"))
        self.f = suite.read_table(os.path.join(self.folder, "fields.txt"))
        self.ch = suite.read_table(os.path.join(self.folder, "contact_history.txt"))
        self.summary = suite.read_summary(os.path.join(self.folder, "summary.txt"))
        self.scene = suite.RunScene(self.folder, self.params)
        self.dim = run_dimension(self.summary)
        if not self.expect(self.dim in (2, 3), f"summary.txt: dimension {self.dim}, not 2 or 3"):
            return False
        if self.dim == 3:           # the columns a 3D run adds (docs/design.md, "Three dimensions")
            for name, table, columns in (("contact.txt", self.c, ("z", "v_tau2", "lambda_tau2", "friction_bound") + FRAME),
                                         ("fields.txt", self.f, ("z", "u_z", "v_z", "von_mises")),
                                         ("contact_history.txt", self.ch, ("tangential_force2",))):
                for column in columns:
                    self.expect(column in table, f"{name} lacks column {column} (a 3D run)")
        for name in ("x", "v_nu", "v_tau", "p_nu", "lambda_nu", "lambda_tau", "normal_status",
                     "tangential_status", "weight"):
            self.expect(name in self.c, f"contact.txt lacks column {name}")
        for name in ("step", "t", "iterations", "residual", "kinetic", "elastic", "numerical_dissipation",
                     "viscous_dissipation", "contact_dissipation", "external_work", "energy_residual",
                     "kinetic_jump", "elastic_jump"):
            self.expect(name in self.h, f"history.txt lacks column {name}")
        for name in ("x", "y", "u_x", "u_y", "v_x", "v_y"):
            self.expect(name in self.f, f"fields.txt lacks column {name}")
        # every table (suite.read_table requires rows) finite where the solver writes finite
        # numbers (x_B, x_C may be nan), with the rows summary.txt announces
        for name, table, rows in (("contact.txt", self.c, "contact_nodes"), ("fields.txt", self.f, "vertices"),
                                  ("history.txt", self.h, "steps"), ("contact_history.txt", self.ch, "steps")):
            self.expect(name == "contact_history.txt" or bool(np.isfinite(table.data).all()), f"{name} holds non-finite numbers")
            expected = self.summary.get(rows)
            self.expect(expected is None or str(len(table)) == expected,
                        f"{name} has {len(table)} rows, summary.txt says {rows} {expected}")
        return not self.failures

    def real(self, key):
        return self.params.real(key)

    def plane_strain(self):
        return self.params.get("plane", "stress") == "strain"     # runs from before -plane: plane stress

    def elastic_lambda(self):
        """B's volumetric coefficient (docs/design.md, "The discrete problem"): E nu/(1-nu^2) in
        plane stress (sigma_zz = 0), E nu/((1+nu)(1-2nu)) in plane strain (eps_zz = 0) and in
        3D (lambda3, the isotropic law itself)."""
        E, nu = self.real("E"), self.real("nu")
        return E * nu / ((1 + nu) * (1 - 2 * nu)) if self.dim == 3 or self.plane_strain() else E * nu / (1 - nu ** 2)

    def second_tangent(self, table, *names):
        """The columns v_tau2, lambda_tau2 (names) of a 3D table; zeros in 2D, where a node has one
        tangent: then |(v_tau, v_tau2)| = |v_tau| exactly."""
        return [table[name] if self.dim == 3 else np.zeros(len(table)) for name in names]

    def count(self, key):
        """A whole number of summary.txt, -1 when it is not there."""
        return self.summary.integer(key) if key in self.summary else -1

    def body(self):
        """|Omega| (the triangles' area, per unit thickness in 2D, or the tetrahedra's volume)
        and the squared mean element size h^2 of mesh.msh (a triangle is h^2/2, a tetrahedron
        h^3/6)."""
        if not hasattr(self, "_body"):
            path = os.path.join(self.folder, "mesh.msh")
            if self.dim == 3:
                xyz, cells = read_tetrahedra(path)
                measure = float(np.abs(np.linalg.det(xyz[cells[:, 1:]] - xyz[cells[:, :1]])).sum()) / 6
                h2 = (6 * measure / len(cells)) ** (2 / 3)
            else:
                mesh = suite.read_msh22(path)
                p = mesh.xy[mesh.triangles]
                measure = float(np.abs(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])).sum()) / 2
                h2 = 2 * measure / len(mesh.triangles)
            self._body = measure, h2
        return self._body

    def slope_at_bound(self):
        """p'(g) at each node, the damping slope K_n the solver folds into its matrix S
        (docs/design.md, "Condensation"); 0 for another law than the scene's (--other-law)."""
        g = self.scene.g(self.c["x"])
        return np.zeros(len(g)) if self.other_law else slopes(self.scene, g)

    def velocity_terms(self, force, kinetic, slope=0.0):
        """The magnitude of the terms a contact velocity is computed from, at a step of total
        contact force `force` (normal or tangential) and kinetic energy `kinetic`: the body's
        rms velocity sqrt(2 kinetic/(rho |Omega|)), and the velocity the contact stresses alone
        give it in one step (c = c_free - Dw m, docs/design.md "Condensation"): their force over
        what holds the body's rigid motion along them, its inertia rho |Omega|/k and, normal to
        Gamma3, the damping slope p'(g) of Gamma3 (slope = p'(g) L) that the solver folds into S;
        plus g. A body held only by the foundation with p' = 0 gives k |force|/(rho |Omega|): a
        column at the bound that computes v_nu = g from terms of 1e5 m/s."""
        rho, k, g = self.real("rho"), self.real("dt"), float(self.scene.g(self.c["x"]).max())
        mass = rho * self.body()[0]
        return g + np.sqrt(2 * np.maximum(kinetic, 0.0) / mass) + k * np.abs(force) / (mass + k * slope)

    def stress_terms(self, v_nu):
        """The magnitude of the terms each node's contact stresses are computed from: |p_nu|,
        |lambda_nu|, |lambda_tau| themselves, and the damping slope times the velocity,
        p'(g) (|v_nu| + the velocity terms): the solver writes a normal stress as
        p_nu = K_n v_nu + m (docs/design.md, "Condensation"), which cancels to 0 on a free node
        of a body flying away."""
        c, ch, h = self.c, self.ch, self.h
        slope = self.slope_at_bound()
        terms = self.velocity_terms(ch["normal_force"][-1], h["kinetic"][-1], float(np.sum(c["weight"] * slope)))
        second, = self.second_tangent(c, "lambda_tau2")
        stress = np.abs(c["p_nu"]) + np.abs(c["lambda_nu"]) + np.hypot(c["lambda_tau"], second)
        return stress + slope * (np.abs(v_nu) + terms)

    def check_contact(self, rtol):
        c, law, mu = self.c, self.scene, self.real("mu")
        vn, vt, pn, ln, lt = c["v_nu"], c["v_tau"], c["p_nu"], c["lambda_nu"], c["lambda_tau"]
        g = law.g(c["x"])                                      # the bound at each node
        # the round-off allowances (ROUNDOFF): of a normal velocity, of the terms it is computed
        # from (velocity_terms); of a stress, of its terms (stress_terms); of the friction
        # stress and its bound, of both stresses
        terms = self.velocity_terms(self.ch["normal_force"][-1], self.h["kinetic"][-1],
                                    float(np.sum(c["weight"] * self.slope_at_bound())))
        velocity_roundoff = ROUNDOFF * (np.abs(vn) + terms)
        stress_roundoff = ROUNDOFF * self.stress_terms(vn)
        if self.other_law:
            # a law other than the scene's (edp/plugins/contactlaw.hpp changed): the friction
            # bound is the run's own, and the stresses set the force scale
            bound = c["friction_bound"]
            scale = np.full(len(pn), max(np.abs(pn).max(), 1.0))
        else:
            scale = law.p(g)                                   # p(g): the force scale of each node
            scale = np.where(scale > 0, scale, 1.0)
            damped = law.p(vn)
            bound = mu * damped
            # p(v_nu) carries the round-off of v_nu times its slope
            law_roundoff = stress_roundoff + slopes(law, vn) * velocity_roundoff
            excess, err, allow = worst(np.abs(pn - damped - ln) / scale, law_roundoff / scale)
            self.expect(excess <= rtol, f"p_nu != p(v_nu) + lambda_nu: {err:.3e} p(g) (round-off allowance {allow:.1e})")
            excess, err, allow = worst(np.abs(c["friction_bound"] - bound) / scale, mu * law_roundoff / scale)
            self.expect(excess <= rtol, f"friction_bound != mu p(v_nu): {err:.3e} p(g) (round-off allowance {allow:.1e})")
        if self.params["problem"] == "original":
            excess, viol, allow = worst(np.maximum(vn - g, 0.0) / g, velocity_roundoff / g)
            self.expect(excess <= rtol, f"constraint v_nu <= g violated by {viol:.3e} g (round-off allowance {allow:.1e})")
            excess, neg, allow = worst(np.maximum(-ln, 0.0) / scale, stress_roundoff / scale)
            self.expect(excess <= rtol, f"negative multiplier lambda_nu: {neg:.3e} p(g) (round-off allowance {allow:.1e})")
            # each node: lambda_nu = 0 or v_nu = g, in relative terms (scale-free: a node far
            # below the bound, as in a free flight, does not amplify the round-off of lambda_nu),
            # each beyond its round-off
            multiplier, gap = np.abs(ln) / scale - stress_roundoff / scale, np.abs(vn - g) / g - velocity_roundoff / g
            comp = np.minimum(multiplier, gap).max()
            self.expect(comp <= rtol, f"complementarity min(|lambda_nu|/p(g), |v_nu - g|/g) = {comp:.3e} beyond "
                        "their round-off allowances")
        else:
            # compliant form eps lambda_nu = (v_nu - g)_+, in velocity units (dividing by eps
            # would amplify the round-off of v_nu by 1/eps), relative to g or, for a large eps,
            # to eps p(g) (eps times the round-off of lambda_nu is no violation)
            eps = self.real("eps")
            unit = np.maximum(g, eps * scale)
            excess, err, allow = worst(np.abs(eps * ln - np.maximum(vn - g, 0.0)) / unit,
                                       (eps * stress_roundoff + velocity_roundoff) / unit)
            self.expect(excess <= rtol, f"penalty law eps lambda_nu = (v_nu - g)_+ off by {err:.3e} g "
                        f"(round-off allowance {allow:.1e})")
        # |v_tau|, |lambda_tau|: in 3D the lengths of the pairs (t1, t2) of the disk law
        # (docs/design.md, "Three dimensions"); in 2D the absolute values (v_tau2 = lambda_tau2 = 0)
        vt2, lt2 = self.second_tangent(c, "v_tau2", "lambda_tau2")
        speed, stress = np.hypot(vt, vt2), np.hypot(lt, lt2)
        friction_roundoff = (1 + mu) * stress_roundoff / scale      # of |lambda_tau| and of mu p(v_nu)
        excess, over, allow = worst((stress - bound) / scale, friction_roundoff)
        self.expect(excess <= rtol, f"friction cone |lambda_tau| <= mu p(v_nu) violated by {over:.3e} p(g) "
                    f"(round-off allowance {allow:.1e})")
        slip = speed > 1e-6 * g
        if slip.any():
            excess, gap, allow = worst(np.abs(stress[slip] - bound[slip]) / scale[slip], friction_roundoff[slip])
            self.expect(excess <= rtol, f"sliding nodes off the friction bound by {gap:.3e} p(g) "
                        f"(round-off allowance {allow:.1e})")
            if self.dim == 2:
                opposed = (lt[slip] * vt[slip] < 0) & (bound[slip] > rtol * scale[slip])
                self.expect(not opposed.any(), f"{int(opposed.sum())} sliding nodes with lambda_tau against v_tau")
            else:
                # the disk law: lambda_tau = s v_tau/|v_tau| on a sliding node, a vector along the
                # slip, same direction. Across the force, the slip may move by what the solver's
                # tolerance leaves of the velocity (docs/design.md, "Nodal laws": a stress mismatch
                # of tol min(p(g), r g) moves v by tol g at most), so that component is measured
                # relative to g, not to |v_tau| (a node that slips at 1e-6 g may turn by 1e-4)
                pushed = slip & (bound > rtol * scale)
                opposed = pushed & (lt * vt + lt2 * vt2 <= 0)
                self.expect(not opposed.any(), f"{int(opposed.sum())} sliding nodes with lambda_tau against v_tau "
                            "(lambda_tau . v_tau <= 0)")
                pushed &= stress > 0            # (a sliding node without stress is off the bound, above)
                across = np.where(pushed, np.abs(vt * lt2 - vt2 * lt) / np.where(pushed, stress, 1.0) / g, 0.0)
                # round-off: of the tangential velocities' terms (velocity_terms of the friction force)
                tangential = self.velocity_terms(np.hypot(self.ch["tangential_force"][-1], self.ch["tangential_force2"][-1]),
                                                 self.h["kinetic"][-1])
                allowed = rtol + ROUNDOFF * (speed + tangential) / g
                node = int(np.argmax(across - allowed))
                self.expect(across[node] <= allowed[node], f"sliding node {node}: v_tau has a component of "
                            f"{across[node]:.3e} g across lambda_tau (bound {rtol:g} g + round-off "
                            f"{allowed[node] - rtol:.1e} g): the friction stress is not along the slip")
        normal = np.where(vn <= 0, 0, np.where(vn >= g * (1 - 1e-6), 2, 1))
        tangential = np.where(speed <= 1e-6 * g, 0, 1)
        self.expect((normal == c["normal_status"]).all(), "normal_status does not match v_nu")
        self.expect((tangential == c["tangential_status"]).all(), "tangential_status does not match v_tau")
        zones = {
            "zone_free": int((normal == 0).sum()),
            "zone_damped_slip": int(((normal == 1) & (tangential == 1)).sum()),
            "zone_damped_stick": int(((normal == 1) & (tangential == 0)).sum()),
            "zone_bound_slip": int(((normal == 2) & (tangential == 1)).sum()),
            "zone_bound_stick": int(((normal == 2) & (tangential == 0)).sum()),
        }
        for key, value in zones.items():
            self.expect(self.count(key) == value,
                        f"summary {key} = {self.summary.get(key)} but contact.txt gives {value}")
        self.expect(self.count("contact_nodes") == len(vn), "summary contact_nodes != rows of contact.txt")
        self.zones = zones
        # the last line of contact_history.txt describes the same final state
        ch = self.ch
        for key, value in zones.items():
            self.expect(ch[key][-1] == value, f"contact_history {key} = {ch[key][-1]} at T but contact.txt gives {value}")
        self.expect((ch["zone_free"] + ch["zone_damped_slip"] + ch["zone_damped_stick"] + ch["zone_bound_slip"]
                     + ch["zone_bound_stick"] == len(vn)).all(), "contact_history zone counts do not add up to the nodes")
        force = np.sum(c["weight"] * pn)
        scale = np.max(scale)
        # round-off: of the nodes' terms w |stress| (the same numbers summed in another order)
        summed = ROUNDOFF * float(np.sum(c["weight"] * self.stress_terms(vn)))
        self.expect(abs(ch["normal_force"][-1] - force) <= rtol * max(abs(force), scale) + summed,
                    f"contact_history normal_force {ch['normal_force'][-1]} != sum w p_nu = {force}")
        if self.dim == 2:
            tforce = np.sum(c["weight"] * c["lambda_tau"])
            self.expect(abs(ch["tangential_force"][-1] - tforce) <= rtol * max(abs(tforce), scale) + summed,
                        f"contact_history tangential_force {ch['tangential_force'][-1]} != sum w lambda_tau = {tforce}")
        else:
            # the total friction stress as a vector, sum w (lambda_tau t1 + lambda_tau2 t2), on the
            # mean frame of Gamma3 that summary.txt gives (contact_frame_t1, contact_frame_t2)
            t1, t2 = (np.stack([c[f"{t}_{a}"] for a in "xyz"], 1) for t in ("t1", "t2"))
            vector = (c["weight"][:, None] * (c["lambda_tau"][:, None] * t1 + c["lambda_tau2"][:, None] * t2)).sum(0)
            mean = [np.array([float(w) for w in self.summary.get(key, "nan nan nan").split()]) for key in
                    ("contact_frame_t1", "contact_frame_t2")]
            for name, axis in zip(("tangential_force", "tangential_force2"), mean):
                self.expect(axis.shape == (3,) and abs(np.linalg.norm(axis) - 1) <= 1e-12,
                            f"summary.txt: {name}'s axis {axis} is not a unit vector")
                tforce = float(vector @ axis) if axis.shape == (3,) else np.nan
                self.expect(abs(ch[name][-1] - tforce) <= rtol * max(abs(tforce), scale) + summed,
                            f"contact_history {name} {ch[name][-1]} != the friction stress sum w (lambda_tau t1 + "
                            f"lambda_tau2 t2) on {axis} = {tforce}")
            self.expect(abs(mean[0] @ mean[1]) <= 1e-12 if mean[0].shape == mean[1].shape == (3,) else False,
                        "summary.txt: contact_frame_t1 and contact_frame_t2 are not orthogonal")
        at_bound = c["x"][normal == 2]
        sticking = c["x"][(normal > 0) & (tangential == 0)]
        for name, xs in (("x_B", at_bound), ("x_C", sticking)):
            want = xs.min() if len(xs) else np.nan
            got = ch[name][-1]
            self.expect((np.isnan(want) and np.isnan(got)) or got == want, f"contact_history {name} = {got}, contact.txt gives {want}")

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
        scale = max(float(np.abs(v).max()), float(self.scene.g(c["x"]).max()))
        for name, axis in (("v_nu", n), ("v_tau", t1), ("v_tau2", t2)):
            err = np.abs((v * axis).sum(1) - c[name]).max() / scale
            # round-off: of the three products of v (at most scale) with the unit axis
            self.expect(err <= rtol + 3 * ROUNDOFF, f"contact.txt {name} differs from fields.txt's v projected on the "
                        f"node's frame by {err:.3e} of max(|v|, g) = {scale:.3e} (bound {rtol:g})")

    def check_energy(self, rtol):
        h = self.h
        steps = self.summary.integer("steps")
        dt, T = self.real("dt"), self.real("T")
        self.expect(len(h["t"]) == steps == round(T / dt), f"history has {len(h['t'])} steps, expected T/dt")
        self.expect(np.allclose(h["t"], dt * np.arange(1, len(h["t"]) + 1), rtol=1e-12, atol=0), "history t != n dt")
        energy = h["kinetic"] + h["elastic"]
        initial = self.summary.real("initial_kinetic") if "initial_kinetic" in self.summary else 0.0
        self.expect(initial >= 0, f"initial_kinetic negative ({initial})")
        before = np.concatenate(([initial], energy[:-1]))     # u0 = 0, v0 (initial_velocity)
        terms = np.vstack([energy, before, h["numerical_dissipation"], h["viscous_dissipation"],
                           h["contact_dissipation"], h["external_work"]])
        balance = energy - before + h["numerical_dissipation"] + h["viscous_dissipation"] \
            + h["contact_dissipation"] - h["external_work"]
        largest = np.abs(terms).max(axis=0)
        largest[largest == 0] = 1.0
        # round-off, relative to the largest term: the terms themselves, and the stiffness
        # products the solver computes them from, k a(v,v), k^2 b(v,v) and b(u,u): their
        # summands (element by element, before they cancel, as they do for a rigid motion of
        # a body flying away) are the moduli times int |v|^2/h^2 (a P1 element's stiffness
        # entries are its modulus times its measure over h^2), int |v_n|^2 = 2 kinetic/rho and
        # int |u_n|^2 <= (k sum_m<=n (int |v_m|^2)^1/2)^2 (u_0 = 0)
        roundoff = ROUNDOFF * (1 + self.stiffness_terms() / largest)
        excess, off, allow = worst(np.abs(balance) / largest, roundoff)
        self.expect(excess <= rtol, f"discrete energy balance off by {off:.3e} (relative to the largest term; "
                    f"round-off allowance {allow:.1e})")
        # the solver's own residual column (and its maximum in summary.txt) says the same:
        # both are round-off, so they agree to rtol (a residual column off by more than
        # that is a wrong balance in the solver, or a wrong column)
        reported = h["energy_residual"]
        excess, off, allow = worst(np.abs(reported - np.abs(balance) / largest), roundoff)
        self.expect(excess <= rtol, f"energy_residual column differs from the recomputed balance by {off:.3e} "
                    f"(round-off allowance {allow:.1e})")
        if "check_energy_residual" in self.summary:
            self.expect(self.summary.real("check_energy_residual") == reported.max(),
                        "summary check_energy_residual != max of history energy_residual")
        parts = h["kinetic_jump"] + h["elastic_jump"] - h["numerical_dissipation"]
        summands = np.abs(h["kinetic_jump"]) + np.abs(h["elastic_jump"]) + np.abs(h["numerical_dissipation"])
        self.expect((np.abs(parts) <= rtol * largest.max() + ROUNDOFF * summands).all(),
                    "kinetic_jump + elastic_jump != numerical_dissipation")
        for name in ("kinetic", "elastic", "numerical_dissipation", "viscous_dissipation", "contact_dissipation",
                     "kinetic_jump", "elastic_jump"):
            excess, low, allow = worst(-h[name] / largest, roundoff)
            self.expect(excess <= rtol, f"{name} negative ({-low:.3e}; round-off allowance {allow:.1e})")
        tol = self.real("tol")
        self.expect((h["residual"] <= tol).all(), "a step's residual is above -tol")
        # Newton makes at least one iteration a step; the fixed point none where the step's start
        # (the previous multipliers) already meets tol, which the residual column then shows
        least = 0 if self.params.get("solver") == "fixedpoint" else 1
        self.expect((h["iterations"] >= least).all(), "a step reports no iteration")
        # last step: contact dissipation from contact.txt (in 3D both tangents: lambda_tau . v_tau)
        c = self.c
        mine = dt * np.sum(c["weight"] * (c["p_nu"] * c["v_nu"] + c["lambda_tau"] * c["v_tau"]))
        if self.dim == 3:
            mine += dt * np.sum(c["weight"] * c["lambda_tau2"] * c["v_tau2"])
        theirs = h["contact_dissipation"][-1]
        summands = dt * np.sum(c["weight"] * (np.abs(c["p_nu"] * c["v_nu"]) + np.abs(c["lambda_tau"] * c["v_tau"])))
        if self.dim == 3:
            summands += dt * np.sum(c["weight"] * np.abs(c["lambda_tau2"] * c["v_tau2"]))
        self.expect(abs(mine - theirs) <= rtol * max(largest[-1], 1e-300) + ROUNDOFF * summands,
                    f"contact dissipation of the last step: contact.txt gives {mine:.15e}, history {theirs:.15e}")

    def stiffness_terms(self):
        """At each step, the magnitude of the summands of k a(v_n, v_n), k^2 b(v_n, v_n) and
        b(u_n, u_n) (check_energy): (k A + k^2 B) int |v_n|^2/h^2 + B int |u_n|^2/h^2, A and B
        the moduli of a and b (eta + d |mu1|, E/(1+nu) + d |lambda|, d the dimension)."""
        h, k, rho = self.h, self.real("dt"), self.real("rho")
        E, nu, d = self.real("E"), self.real("nu"), self.dim
        stiff = E / (1 + nu) + d * abs(self.elastic_lambda())
        viscous = self.real("eta") + d * abs(self.real("muv"))
        h2 = self.body()[1]
        v2 = 2 * np.maximum(h["kinetic"], 0.0) / rho
        u2 = (k * np.cumsum(np.sqrt(v2))) ** 2
        return ((k * viscous + k * k * stiff) * v2 + stiff * u2) / h2

    ZONES = ("zone_free", "zone_damped_slip", "zone_damped_stick", "zone_bound_slip", "zone_bound_stick")

    def check_series(self):
        """contact_nodes_history.txt: one row per contact node at the steps -every gives (and the
        last); at each, the zone counts of contact_history.txt; at the last, contact.txt exactly."""
        path = os.path.join(self.folder, "contact_nodes_history.txt")
        if not self.expect(os.path.isfile(path), "missing contact_nodes_history.txt"):
            return
        nh, c, steps = suite.read_table(path), self.c, len(self.h)
        every = int(nh.params.real("every")) or max(1, -(-steps // 200))
        recorded = sorted({n for n in range(1, steps + 1) if n % every == 0} | {steps})
        if not self.expect(len(nh) == len(c) * len(recorded),
                           f"contact_nodes_history.txt has {len(nh)} rows, expected {len(c)} nodes x {len(recorded)} steps"):
            return
        step = nh["step"].reshape(len(recorded), len(c))
        self.expect((step == np.array(recorded)[:, None]).all(), "contact_nodes_history.txt: not the steps -every gives")
        zone = nh["zone"].reshape(len(recorded), len(c)).astype(int)
        for row, n in enumerate(recorded):
            counts = [int((zone[row] == z).sum()) for z in range(5)]
            logged = [int(self.ch[k][n - 1]) for k in self.ZONES]
            if not self.expect(counts == logged, f"step {n}: contact_nodes_history.txt zones {counts}, contact_history.txt {logged}"):
                break
        last = slice(len(nh) - len(c), len(nh))
        for name in ("x", "y", "v_nu", "v_tau", "p_nu", "lambda_nu", "lambda_tau", "normal_status", "tangential_status") \
                + (("z", "v_tau2", "lambda_tau2") if self.dim == 3 else ()):
            self.expect((nh[name][last] == c[name]).all(), f"contact_nodes_history.txt at T: {name} differs from contact.txt")

    def stress_field_roundoff(self):
        """The round-off allowance of a stress computed from the fields (von_mises): the
        gradients of P1 fields are differences of vertex values over the element size h, so
        their terms are the moduli times max |u| / h and max |v| / h (large for a body flying
        away, whose rigid motion cancels in them)."""
        f, d = self.f, self.dim
        stiff = self.real("E") / (1 + self.real("nu")) + d * abs(self.elastic_lambda())
        viscous = self.real("eta") + d * abs(self.real("muv"))
        u = max(float(np.abs(f[f"u_{axis}"]).max()) for axis in "xyz"[:d])
        v = max(float(np.abs(f[f"v_{axis}"]).max()) for axis in "xyz"[:d])
        return ROUNDOFF * (stiff * u + viscous * v) / np.sqrt(self.body()[1])

    def check_stress(self, rtol):
        """fields.txt's von_mises, recomputed: sigma = A eps(v) + B eps(u) on each triangle (P1:
        constant), its von Mises measure, averaged at each vertex with the triangles' areas
        (in 3D: on each tetrahedron, averaged with their volumes, check_stress3)."""
        if self.dim == 3:
            return self.check_stress3(rtol)
        f, mesh = self.f, suite.read_msh22(os.path.join(self.folder, "mesh.msh"))
        size = max(float(np.ptp(mesh.xy, axis=0).max()), 1e-300)
        if not self.expect(len(mesh.xy) == len(f) and np.abs(mesh.xy - np.c_[f["x"], f["y"]]).max() <= 1e-12 * size,
                           "fields.txt does not list the vertices of mesh.msh in its order"):
            return
        tri = mesh.triangles
        x, y = f["x"][tri], f["y"][tri]
        area2 = (x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0])
        gx = np.stack([y[:, 1] - y[:, 2], y[:, 2] - y[:, 0], y[:, 0] - y[:, 1]], 1) / area2[:, None]
        gy = np.stack([x[:, 2] - x[:, 1], x[:, 0] - x[:, 2], x[:, 1] - x[:, 0]], 1) / area2[:, None]

        def strain(ux, uy):
            exx, eyy = (gx * ux[tri]).sum(1), (gy * uy[tri]).sum(1)
            return exx, eyy, 0.5 * ((gy * ux[tri]).sum(1) + (gx * uy[tri]).sum(1))
        E, nu, muv, eta = self.real("E"), self.real("nu"), self.real("muv"), self.real("eta")
        plane_strain, lam = self.plane_strain(), self.elastic_lambda()
        ev, eu = strain(f["v_x"], f["v_y"]), strain(f["u_x"], f["u_y"])
        lame = muv * (ev[0] + ev[1]) + lam * (eu[0] + eu[1])
        sxx, syy, sxy = (lame + eta * ev[0] + E / (1 + nu) * eu[0], lame + eta * ev[1] + E / (1 + nu) * eu[1],
                         eta * ev[2] + E / (1 + nu) * eu[2])
        szz = lame if plane_strain else 0 * lame
        vm = np.sqrt(sxx ** 2 - sxx * syy + syy ** 2 + 3 * sxy ** 2 + szz ** 2 - szz * (sxx + syy))
        weight, total = np.zeros(len(f)), np.zeros(len(f))
        for k in range(3):
            np.add.at(weight, tri[:, k], np.abs(area2))
            np.add.at(total, tri[:, k], np.abs(area2) * vm)
        mine = total / weight
        error = np.abs(mine - f["von_mises"]).max()
        self.expect(error <= rtol * max(np.abs(mine).max(), 1e-300) + self.stress_field_roundoff(),
                    f"von_mises: fields.txt differs from its recomputation by {error:.3e} (largest {np.abs(mine).max():.3e})")

    def tetrahedra(self):
        """The mesh of a 3D run: its tetrahedra (rows of fields.txt, which lists the vertices in
        the mesh's order: checked), their gradient operators and volumes. grad[t] solves
        D grad = (f1 - f0, f2 - f0, f3 - f0) for the edges D of tetrahedron t from its vertex 0:
        the gradient of the P1 function of vertex values f, constant on t."""
        f = self.f
        xyz, tet = read_tetrahedra(os.path.join(self.folder, "mesh.msh"))
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

    def check_zones(self, expected):
        want = [int(x) for x in expected.split(",")]
        got = [self.zones[k] for k in self.ZONES]
        self.expect(got == want, f"zones free,damped-slip,damped-stick,bound-slip,bound-stick = {got}, expected {want}")

    def column_applies(self):
        """Refusal when the column's known answer does not apply to the run's load history: a
        history that pulls the column (q L + f0 |Omega| < 0) at a step before one that presses
        it. Pulled, the column leaves the foundation as a free body: the contact depends on the
        velocity only (no gap, no adhesion), so nothing holds it, and the momentum the pull gave
        it carries it on after the push begins, until it lands with an impact. The known
        answer (check_column) is that of a column pressed from rest, whose momentum stays that
        of the known answer: for this history it holds neither in flight (every node free
        although pressed) nor after the landing (the impact's waves)."""
        law, h = self.scene, self.h
        length = self.c["weight"].sum()
        area = length * (self.f["y"].max() - self.f["y"].min())
        total = self.real("load") * law.h(h["t"]) * length - law.body_force[1] * area
        pulled = np.flatnonzero(total < 0)
        pressed = np.flatnonzero(total > ROUNDOFF * abs(self.real("load")) * length)     # (h(t) = 0 up to round-off: not)
        if pulled.size and pressed.size and pressed[-1] > pulled[0]:
            first, later = int(pulled[0]), int(pressed[pressed > pulled[0]][0])
            raise Refusal(f"--column does not apply: the load history pulls the column (step {first + 1}, "
                          f"t = {h['t'][first]:g}) before it presses it (step {later + 1}, t = {h['t'][later]:g}); "
                          "pulled, the column flies off the foundation (the contact depends on the velocity only: no "
                          "gap, no adhesion) and the momentum it gains carries it on after the push begins, so the "
                          "known answer of a column pressed from rest (p_nu = q, v_nu = min(p^-1(q), g)) does not "
                          "hold; check the run without --column")

    def check_column(self, rtol):
        """Known answer of the column scene, for the run's own damped response p, bound g(x)
        and load history h(t) (its scene.scene). Summing the equations with w = (0,1) gives,
        at every step, exactly: sum_i w_i p_nu_i = q L + |Omega| (-f0_y) - (1/k) m(v_n - v_{n-1}, e_y),
        q = load h(t_n), and by Cauchy-Schwarz |m(dv, e_y)| <= sqrt(2 kinetic_jump) sqrt(rho |Omega|)
        (kinetic_jump = 1/2 m(dv, dv)). While pulled (q < 0) every node is free; released (q = 0
        after a push) p_nu = 0 within the inertia force. At T, pressed,
        the column is uniaxial when the known answer v_nu = min(p^-1(q), g(x)) is the same at
        every node: then each node carries p_nu = q. Where g(x) makes it differ between
        nodes, the body shears and carries load between them: only v_nu = g(x) at the nodes
        at the bound is known, and only when every node is at the bound. A body force makes
        the stress vary along the height, which the viscoelastic law couples to the width:
        then only the total force is known. In 3D (column3d) the same holds with w = (0,1,0), L
        the area of Gamma3 and |Omega| = L times the height: the forces below are per unit area."""
        c, h, ch, law = self.c, self.h, self.ch, self.scene
        load, T, dt = self.real("load"), self.real("T"), self.real("dt")
        rho, g = self.real("rho"), law.g(c["x"])
        length = c["weight"].sum()
        area = length * (self.f["y"].max() - self.f["y"].min())
        weight = -law.body_force[1] * area                    # f0 pressing the column down
        force_scale = float(law.p(g).max()) * length
        # every step: the total contact force, and the free nodes of the pulled steps
        q_steps = load * law.h(h["t"])
        inertia_steps = np.sqrt(2 * h["kinetic_jump"] * rho * area) / dt
        # round-off of each step's sum: of its terms, the force itself, the load, the inertia
        # force and, on free nodes of a column that flies away, the damping slope times the
        # velocity (p_nu = K_n v_nu + m cancels to 0: stress_terms), for Gamma3 p'(g) L |v|
        # (|v| the rms velocity); times lambda/E where the volumetric stiffness is the larger
        # (near nu = 0.5 the matrix S sums terms lambda/E times larger than the stresses)
        slope = float(np.sum(c["weight"] * self.slope_at_bound()))
        speed_steps = np.sqrt(2 * np.maximum(h["kinetic"], 0.0) / (rho * area))
        roundoff_steps = ROUNDOFF * max(1.0, self.elastic_lambda() / self.real("E")) * (
            np.abs(ch["normal_force"]) + np.abs(q_steps * length + weight) + inertia_steps + slope * speed_steps)
        off = np.abs(ch["normal_force"] - (q_steps * length + weight)) - inertia_steps - roundoff_steps
        step = int(np.argmax(off))
        self.expect(off[step] <= 0, f"step {step + 1}: total contact force {ch['normal_force'][step]:.15e} != "
                    f"q L = {q_steps[step] * length + weight:.15e} (inertia bound {inertia_steps[step]:.3e}, round-off "
                    f"allowance {roundoff_steps[step]:.1e})")
        pulled = q_steps * length + weight < 0
        if pulled.any():
            excess, force, allow = worst(np.abs(ch["normal_force"][pulled]) / force_scale,
                                         roundoff_steps[pulled] / force_scale)
            self.expect(excess <= rtol, f"pulled steps: a normal force of {force:.3e} p(g) L (round-off allowance "
                        f"{allow:.1e})")
            self.expect((ch["zone_free"][pulled] == len(c["x"])).all(), "pulled steps: a node is not free")
        q = load * float(law.h(T)) + weight / length
        stress_roundoff = ROUNDOFF * self.stress_terms(c["v_nu"])
        if q == 0 and (q_steps * length + weight > 0).any():
            # released: the compressed column expands (E eps + mu eps' = 0) and lifts off; p_nu = q = 0
            # up to the inertia force per unit length of the last step, as when pressed
            excess, err_p, allow = worst(np.abs(c["p_nu"]), 2 * inertia_steps[-1] / length + stress_roundoff)
            self.expect(excess <= 0, f"released (q = 0): p_nu = {err_p:.3e} > {allow:.3e} (inertia and round-off)")
            return
        if q < 0:
            scale = np.where(law.p(g) > 0, law.p(g), 1.0)            # p(g), 1 where it is 0
            excess, value, allow = worst(np.abs(c["p_nu"]) / scale, stress_roundoff / scale)
            self.expect(excess <= rtol, f"pulled (q = {q}): p_nu = {value:.3e} p(g) != 0 (round-off allowance {allow:.1e})")
            self.expect((c["v_nu"] <= 0).all() and (c["normal_status"] == 0).all(),
                        f"pulled (q = {q}): a node is not free (v_nu max {c['v_nu'].max():.3e})")
            return
        if weight != 0:
            return          # a body force makes the stress vary along the height: not uniaxial
        inertia = inertia_steps[-1]
        # the round-off of v_nu: of the terms it is computed from (velocity_terms: a column held
        # at the bound with p' = 0 computes v_nu = g from terms of k q L/(rho |Omega|))
        velocity_roundoff = ROUNDOFF * (np.abs(c["v_nu"]) + self.velocity_terms(ch["normal_force"][-1], h["kinetic"][-1],
                                                                                slope))
        free = law.inverse(q)
        vexact = np.minimum(free, g)
        uniform = vexact.max() == vexact.min()
        if not uniform:
            self.expect(bool((free >= g).all()), "the known answer min(p^-1(q), g(x)) differs between nodes and "
                        "not every node is at the bound: no known answer (the body shears)")
            excess, err, allow = worst(np.abs(c["v_nu"] - g) / g, velocity_roundoff / g)
            self.expect(excess <= 0, f"every node at the bound, v_nu = g(x): off by {err:.3e} g (round-off "
                        f"allowance {allow:.1e})")
            return
        # per node: twice the inertia force per unit length of the last step (measured
        # unevenness: 1.002), plus the inertia force per unit length of the column while
        # it accelerated along the known answer, rho Ly max |dv/dt| (the largest change of
        # min(p^-1(load h(t)), g) over a step, divided by k; load/c_nu for the paper's p and
        # h(t) = t): the viscoelastic body keeps a memory of it once v_nu = g holds (measured
        # there: 0.05 of it), plus round-off
        height = area / length
        times = dt * np.arange(0, round(T / dt) + 1)
        known = np.array([min(law.inverse(max(load * float(law.h(t)) + weight / length, 0.0)), g.max()) for t in times])
        rate = np.abs(np.diff(known)).max() / dt
        slack = 2 * inertia / length + rho * height * rate + 1e-10 * q
        excess, err_p, allow = worst(np.abs(c["p_nu"] - q), slack + stress_roundoff)
        self.expect(excess <= 0, f"p_nu differs from q = {q} by {err_p:.3e} > {allow:.3e} (inertia {slack:.3e} and "
                    "round-off)")
        err_v = np.abs(c["v_nu"] - vexact)
        damped = (free < g) & np.isfinite(free)                  # (p^-1(q) is inf for a table that stays below q)
        allowed = np.where(damped, slack / (law.slope(free) if damped.any() else 1.0), 0.0) + velocity_roundoff
        node = int(np.argmax(err_v - allowed))
        self.expect((err_v <= allowed).all(), f"v_nu differs from min(p^-1(q), g) = {vexact[node]} by "
                    f"{err_v[node]:.3e} > {allowed[node]:.3e} (inertia and round-off) at x = {c['x'][node]}")
        friction = np.abs(c["lambda_tau"]).max() + (np.abs(c["lambda_tau2"]).max() if self.dim == 3 else 0.0)
        self.expect(friction == 0.0 or self.real("mu") > 0, "lambda_tau != 0 without friction")
        if (q_steps > 0).all():
            # the stress error of each step: its inertia bound, and that of the acceleration
            # along the known answer (absolute, per unit length)
            self.check_uniaxial_strain(q_steps, 2 * inertia_steps / length + rho * height * rate)

    def check_uniaxial_strain(self, q_steps, stress_error):
        """The column pressed at every step is in uniaxial stress, sigma_yy = -q(t_n), sigma_xx =
        sigma_xy = 0 (in 3D also sigma_zz = sigma_xz = sigma_yz = 0), up to inertia: its strain is
        uniform, and the scheme's backward Euler on the two equations sigma_xx = 0, sigma_yy = -q
        of the Kelvin-Voigt law (docs/design.md, "The discrete problem"; in 3D "Three
        dimensions", where the lateral strains are equal, eps_zz = eps_xx, and tr eps = 2 eps_xx
        + eps_yy) gives eps_xx and eps_yy at T exactly, for plane stress, plane strain or 3D. The
        displacement of fields.txt must be affine, with those strains, to the bound that the
        stress error of each step (stress_error: its inertia) leaves at T through the same
        recurrence (e_n = R e_{n-1} + S dq_n, |e_n| <= |R| |e_{n-1}| + |S| dq_n in the infinity
        norm: an early step's error fades with the law's memory), plus round-off. Measured:
        1e-10 relative after 20 steps, against a bound of 8e-8 there; the two planes differ
        by 4% (eps_yy) and 20% (eps_xx), and lambda 1e-5 off moves eps_xx by 6e-6. In 3D
        (column3d): 1.7e-10 (eps_xx), 6e-11 (eps_yy) against a bound of 8e-8; plane stress's
        answer is 0.25% (eps_xx) and 0.05% (eps_yy) away."""
        E, nu, mu1, mu2, k = self.real("E"), self.real("nu"), self.real("muv"), self.real("eta"), self.real("dt")
        plane_strain, lam = self.plane_strain(), self.elastic_lambda()
        shear = E / (1 + nu)
        lateral = 2 if self.dim == 3 else 1         # the axes of eps_xx (x, and z in 3D): tr eps = lateral eps_xx + eps_yy
        exx = eyy = 0.0
        lhs = np.array([[lateral * mu1 + mu2 + k * (lateral * lam + shear), mu1 + k * lam],
                        [lateral * (mu1 + k * lam), mu1 + mu2 + k * (lam + shear)]])
        # e_n = R e_{n-1} + S q_n for e = (eps_xx, eps_yy): the rates L^-1 (C e - (0, q)), e += k rate
        C = np.array([[-(lateral * lam + shear), -lam], [-lateral * lam, -(lam + shear)]])
        R = np.eye(2) + k * np.linalg.solve(lhs, C)
        S = k * np.linalg.solve(lhs, np.array([0.0, -1.0]))
        bound = 0.0
        for q, dq in zip(q_steps, stress_error):   # the rates (b, a) of eps_xx, eps_yy at step n
            rhs = np.array([-lam * (lateral * exx + eyy) - shear * exx, -q - lam * (lateral * exx + eyy) - shear * eyy])
            b, a = np.linalg.solve(lhs, rhs)
            exx, eyy = exx + k * b, eyy + k * a
            bound = np.abs(R).sum(1).max() * bound + np.abs(S).max() * dq
        tolerance = bound / abs(eyy) + 1e-9
        f = self.f
        # and the round-off of the least-squares fit: of the displacements' magnitude (over
        # |eps_yy|, as the fit's residual is measured; over the height too for its slopes)
        displacement = float(np.abs(np.stack([f[f"u_{axis}"] for axis in "xyz"[:self.dim]])).max())
        fit_roundoff = ROUNDOFF * displacement / abs(eyy)
        height = max(float(np.ptp(f["y"])), 1e-300)
        axes = ("x", "y", "z") if self.dim == 3 else ("x", "y")
        basis = np.c_[np.ones(len(f)), np.stack([f[axis] for axis in axes], 1)]
        fits = [np.linalg.lstsq(basis, f[f"u_{axis}"], rcond=None)[0] for axis in axes]
        affine = max(np.abs(basis @ fit - f[f"u_{axis}"]).max() for axis, fit in zip(axes, fits)) / abs(eyy)
        self.expect(affine <= tolerance + fit_roundoff, f"uniaxial column: the displacement is not affine (off by {affine:.3e} of eps_yy, "
                    f"inertia bound {tolerance:.3e})")
        model = "3D" if self.dim == 3 else "plane strain" if plane_strain else "plane stress"
        strains = (("eps_xx", fits[0][1], exx), ("eps_yy", fits[1][2], eyy))
        if self.dim == 3:
            strains += (("eps_zz", fits[2][3], exx),)                       # eps_zz = eps_xx
        for name, got, want in strains:
            self.expect(abs(got - want) <= tolerance * abs(want) + fit_roundoff * abs(eyy) / height, f"uniaxial column ({model}): "
                        f"{name} = {got:.12e}, the Kelvin-Voigt law gives {want:.12e} (inertia bound {tolerance:.3e} relative)")

    def check_slide(self, rtol):
        """Known answer of the oblique slide (oblique-slide3d.scene): a block on a flat Gamma3,
        launched along a tangent that is no mesh axis, sliding at the bound v_nu = g on every
        node. At every recorded step where every node is in zone 3 (bound slip):
        - per node, the disk law: |lambda_tau| = mu p(g) to rtol p(g), and lambda_tau along the
          slip v_tau, same direction (lambda_tau is the stress on the slot; the force on the
          body is -w lambda_tau): |sin| of their angle below 1e-8 (the nodes slide at many
          times g, where the solver's velocity tolerance tol g turns v_tau by far less);
        - the total friction force F = (tangential_force, tangential_force2) of
          contact_history.txt, which is sum_i w_i lambda_tau,i (checked against the nodes'
          rows), has the length of the Tresca force mu p(g) A (A = sum w_i, the contact area)
          to within the spread delta of the nodes' slip directions d_i around their weighted
          mean direction e: each lambda_tau,i is mu p(g) times a unit vector within delta
          (+ 1e-8) of e, so F lies in that cone and sum w_i mu p(g) cos(delta) <= |F| <= mu p(g)
          A (cos delta >= 1 - delta^2/2), up to the nodes' rtol p(g); and the force on the body,
          -F, points along -e, within that same angle;
        - a per-component (square) law, which clamps lambda_tau and lambda_tau2 to [-mu p(g),
          mu p(g)] each, would give mu p(g) sum w_i (sign v_tau,i, sign v_tau2,i): it must differ
          from mu p(g) A by more than 30% (sqrt(2) - 1 = 41% for a slip along (1,1)/sqrt(2)),
          or the run does not tell the disk law from it.
        Then the block's momentum: summing the step equation with w = t1 and w = t2 (constant
        tangents; a, b vanish on them, and no Dirichlet condition holds the block) gives
        exactly rho int v_n = rho int v_{n-1} - k F_n in (t1, t2), without a tangential load. So
        its mean tangential velocity at T is V - (k/m) sum_n F_n (m = rho |Omega|, the volume
        from the tetrahedra; checked to round-off with the F_n of contact_history.txt, measured
        3e-13 relative), and the rigid-body answer (V - mu p(g) A T/m) along the launch
        direction e0 = V/|V| holds to (k/m) sum_n |F_n - mu p(g) A e0| <= (k/m) sum_n
        sum_i w_i mu p(g) (|d_i,n - e0| + 1e-8) + rtol p(g) A: it needs every step recorded,
        each with every node in zone 3 (the block stiff or not: only the slip directions
        enter). Measured on oblique-slide3d (20 steps): |lambda_tau| off by 3e-14 p(g) at most,
        |sin| 5e-14, spread 1.5e-2 rad at step 1, 3e-6 from step 8, |F| = 1 - 2e-5 at step 1
        and 1 - 1e-12 at T, the square law 41% above, the mean velocity 1.9e-5 m/s off 0.6
        against a bound of 1.7e-4 m/s."""
        if not self.expect(self.dim == 3, "--slide: not a 3D run (summary.txt: dimension 3)"):
            return
        if not self.expect(self.params["problem"] == "original", "--slide: the known answer mu p(g) is the original "
                           "problem's (the penalty problem's bound is mu p(v_nu), v_nu > g at the bound)"):
            return
        c, law, mu = self.c, self.scene, self.real("mu")
        nodes, weight = len(c), c["weight"]
        g = law.g(c["x"])
        pg = law.p(g)
        bound = mu * pg                                      # mu p(g) at each node
        total = float(np.sum(weight * bound))                # the Tresca force mu p(g) A
        scale = float(np.sum(weight * np.where(pg > 0, pg, 1.0)))         # p(g) A, the stresses' rtol
        if not self.expect(total > 0, f"--slide: mu p(g) A = {total}: no friction to check"):
            return
        # one frame for every node (a flat Gamma3): the nodes' forces add as vectors in (t1, t2)
        frame = np.stack([c[name] for name in FRAME], 1)
        spread = np.abs(frame - frame[0]).max()
        if not self.expect(spread <= 1e-12, f"--slide: the nodes' frames differ by {spread:.3e} (a curved Gamma3, or "
                           "Dirichlet conditions that turn a node's frame): the tangential forces do not add as vectors"):
            return
        t1, t2 = frame[0, 3:6], frame[0, 6:9]
        nh = suite.read_table(os.path.join(self.folder, "contact_nodes_history.txt"))
        if not self.expect(len(nh) % nodes == 0, f"contact_nodes_history.txt: {len(nh)} rows for {nodes} nodes"):
            return

        def rows(name):
            return nh[name].reshape(-1, nodes)
        steps = rows("step")[:, 0].astype(int)
        sliding = (rows("zone") == 3).all(1)
        if not self.expect(sliding.any(), "--slide: no recorded step has every node in zone 3 (bound slip)"):
            return
        ch = self.ch
        deviation = {}                                       # step -> sum_i w_i mu p(g) |d_i - e0| (+ 1e-8)
        launch = None
        given = suite.read_scene(os.path.join(self.folder, "scene.scene")).data.get("initial_velocity")
        if given:
            v0 = np.array([float(w) for w in given[0]] + [0.0] * (3 - len(given[0])))
            launch = np.array([v0 @ t1, v0 @ t2])             # V in (t1, t2)
        failed = set()

        def first(kind, condition, message):
            """expect(), reporting only the first step where a check of this kind fails."""
            if condition or kind in failed:
                return condition
            failed.add(kind)
            return self.expect(condition, message)
        for row in np.flatnonzero(sliding):
            step = int(steps[row])
            vt, vt2, lt, lt2 = rows("v_tau")[row], rows("v_tau2")[row], rows("lambda_tau")[row], rows("lambda_tau2")[row]
            speed, stress = np.hypot(vt, vt2), np.hypot(lt, lt2)
            off = (np.abs(stress - bound) / pg).max()
            first("bound", off <= rtol, f"--slide, step {step}: |lambda_tau| differs from mu p(g) by {off:.3e} p(g) "
                  f"(bound {rtol:g})")
            sine = (np.abs(vt * lt2 - vt2 * lt) / np.maximum(speed * stress, 1e-300)).max()
            along = bool((vt * lt + vt2 * lt2 > 0).all())
            first("along", sine <= 1e-8 and along, f"--slide, step {step}: lambda_tau not along v_tau: |sin| up to "
                  f"{sine:.3e} (bound 1e-8), {'same' if along else 'opposite at some node'} direction")
            slip = np.c_[vt, vt2] / speed[:, None]           # the unit slip directions d_i
            mean = (weight[:, None] * slip).sum(0)
            mean /= np.hypot(*mean)
            delta = float(np.arctan2(np.abs(slip[:, 0] * mean[1] - slip[:, 1] * mean[0]), slip @ mean).max())
            cone = delta + 1e-8                              # lambda_i within 1e-8 of d_i
            force = np.array([ch["tangential_force"][step - 1], ch["tangential_force2"][step - 1]])
            mine = np.array([np.sum(weight * lt), np.sum(weight * lt2)])
            first("sum", np.abs(force - mine).max() <= rtol * total,
                  f"--slide, step {step}: contact_history's force ({force[0]:.15e}, {force[1]:.15e}) != the nodes' "
                  f"sum w lambda_tau ({mine[0]:.15e}, {mine[1]:.15e})")
            length = float(np.hypot(*force))
            low, high = np.cos(min(cone, np.pi / 2)) * total - rtol * scale, total + rtol * scale
            first("length", low <= length <= high, f"--slide, step {step}: the friction force |F| = {length:.15e}, the "
                  f"Tresca force mu p(g) A = {total:.15e}: outside [{low:.15e}, {high:.15e}] (slip directions spread "
                  f"{delta:.3e} rad)")
            angle = float(np.arctan2(abs(force[0] * mean[1] - force[1] * mean[0]), force @ mean))
            first("direction", angle <= cone, f"--slide, step {step}: the friction force on the body -F is {angle:.3e} rad "
                  f"off -(mean slip direction) (bound: the spread {cone:.3e} rad)")
            # the square law: each component clamped on its own, where each slips (both must)
            moving = min(np.abs(vt).min(), np.abs(vt2).min()) / g.max()
            if first("axis", moving > 1e-6, f"--slide, step {step}: a node slides along a mesh axis (a component of "
                     f"{moving:.3e} g): the run does not tell the disk law from the square law"):
                square = np.hypot(np.sum(weight * bound * np.sign(vt)), np.sum(weight * bound * np.sign(vt2)))
                first("square", abs(square / total - 1) > 0.3, f"--slide, step {step}: a square law would give a force "
                      f"of {square:.6e}, within 30% of mu p(g) A = {total:.6e}: the run does not tell the laws apart")
            if launch is not None:
                e0 = launch / np.hypot(*launch)
                deviation[step] = float(np.sum(weight * bound * (np.hypot(*(slip - e0).T) + 1e-8))) + rtol * scale
        # the mean tangential velocity at T against the rigid body, when every step slid at the bound
        dt, count = self.real("dt"), len(self.h)
        tangential_load = [abs(np.dot(law.body_force + [0.0] * (3 - len(law.body_force)), t)) for t in (t1, t2)]
        if not self.expect(launch is not None and np.hypot(*launch) > 0, "--slide: the scene gives no tangential "
                           "initial_velocity: no rigid-body answer"):
            return
        if not self.expect(max(tangential_load) == 0 and self.real("load") == 0, "--slide: a tangential body force or "
                           "a traction (load != 0): the rigid-body answer of a free slide does not apply"):
            return
        mesh = self.tetrahedra()
        if mesh is None:
            return
        tet, _, volume = mesh
        f, rho = self.f, self.real("rho")
        mass = rho * float(volume.sum())
        momentum = np.array([rho * np.sum(volume * np.mean(f[f"v_{axis}"][tet], 1)) for axis in "xyz"])  # rho int v (P1)
        mean = np.array([momentum @ t1, momentum @ t2]) / mass
        speed0 = float(np.hypot(*launch))
        # the momentum identity itself, every step's force of contact_history.txt: round-off
        # (the back-substitution's stiffness terms cancel in the sum; measured 3e-13 relative)
        forces = np.c_[ch["tangential_force"], ch["tangential_force2"]]
        balance = launch - dt / mass * forces.sum(0)
        off = float(np.hypot(*(mean - balance)))
        roundoff = allowed = 1e-10 * (speed0 + dt / mass * np.hypot(*forces.T).sum())
        self.expect(off <= allowed, f"--slide: the mean tangential velocity at T ({mean[0]:.15e}, {mean[1]:.15e}) of "
                    f"fields.txt is {off:.3e} m/s off V - (k/m) sum_n F_n = ({balance[0]:.15e}, {balance[1]:.15e}) of "
                    f"contact_history.txt (bound {allowed:.3e}: round-off): the block's momentum does not balance")
        missing = [n for n in range(1, count + 1) if n not in deviation]
        if not self.expect(not missing, f"--slide: the rigid-body answer needs every step recorded with every node in "
                           f"zone 3; not step {missing[0] if missing else ''} ({len(missing)} steps)"):
            return
        rigid = (speed0 - total * dt * count / mass) * launch / speed0
        off = float(np.hypot(*(mean - rigid)))
        allowed = dt / mass * sum(deviation.values()) + roundoff
        self.expect(rigid @ launch > 0, f"--slide: the rigid block stops before T (V - mu p(g) A T/m = "
                    f"{speed0 - total * dt * count / mass:.6e}): no free slide to check")
        self.expect(off <= allowed, f"--slide: the mean tangential velocity at T ({mean[0]:.12e}, {mean[1]:.12e}) is "
                    f"{off:.3e} m/s off the rigid-body answer V - mu p(g) A T/m = {speed0 - total * dt * count / mass:.12e} "
                    f"along the launch (bound {allowed:.3e}: the slip directions' deviation from it)")

    def compare_tables(self, other_folder, name, families, exact, rtol, floors=None):
        """Columns of one family (velocities, stresses, displacements, energy terms, forces)
        differ by at most rtol of the family's scale, so that a column that is round-off in
        both runs (lambda_nu before any node reaches the bound, lambda_tau without friction)
        is compared as such; the scale is at least the family's floor (g for the contact
        velocities, p(g) for the contact stresses: every stress is round-off when every node
        is free); the `exact` columns (zone counts and boundaries) are equal."""
        a = suite.read_table(os.path.join(self.folder, name))
        b = suite.read_table(os.path.join(other_folder, name))
        if not self.expect(a.data.shape == b.data.shape, f"{name}: shapes differ {a.data.shape} {b.data.shape}"):
            return
        for k, family in enumerate(families):
            scale = max(max(np.abs(a[col]).max(), np.abs(b[col]).max()) for col in family)
            scale = max(scale, floors[k] if floors else 0.0, 1e-300)
            for col in family:
                err = np.abs(a[col] - b[col]).max() / scale
                self.expect(err <= rtol, f"{name} {col}: difference {err:.3e} of the scale of {'/'.join(family)}"
                            f" > {rtol:g} vs {other_folder}")
        for col in exact:
            x, y = a[col], b[col]
            differ = ~((x == y) | (np.isnan(x) & np.isnan(y)))
            self.expect(not differ.any(), f"{name} {col}: differs at {int(differ.sum())} steps vs {other_folder}")

    def compare(self, other_folder, rtol):
        c = suite.read_table(os.path.join(self.folder, "contact.txt"))        # (compare may come without load)
        scene = suite.RunScene(self.folder, c.params)
        g = scene.g(c["x"])
        # a 3D run's added columns (docs/design.md, "Three dimensions") in their families
        three = run_dimension(suite.read_summary(self.folder)) == 3
        extra = (lambda *names: names) if three else (lambda *names: ())
        self.compare_tables(other_folder, "contact.txt",
                            (("v_nu", "v_tau") + extra("v_tau2"),
                             ("p_nu", "lambda_nu", "lambda_tau") + extra("lambda_tau2")), (), rtol,
                            floors=(float(g.max()), float(scene.p(g).max())))
        self.compare_tables(other_folder, "fields.txt", (("u_x", "u_y") + extra("u_z"), ("v_x", "v_y") + extra("v_z")), (), rtol)
        # the histories, when both folders have them; the total forces at least at the scale of
        # p(g) over the whole of Gamma3 (a run whose forces are round-off compares as such)
        force_floor = float(scene.p(g).max()) * float(np.abs(c["weight"]).sum())
        for name, families, exact, floors in (
                ("history.txt", (("kinetic", "elastic", "numerical_dissipation", "viscous_dissipation",
                                  "contact_dissipation", "external_work", "kinetic_jump", "elastic_jump"),), (), None),
                ("contact_history.txt", (("normal_force", "tangential_force") + extra("tangential_force2"),),
                 self.ZONES + ("x_B", "x_C"), (force_floor,))):
            if os.path.isfile(os.path.join(self.folder, name)) and os.path.isfile(os.path.join(other_folder, name)):
                self.compare_tables(other_folder, name, families, exact, rtol, floors=floors)


def zone_counts(text):
    """FREE,DAMPED_SLIP,DAMPED_STICK,BOUND_SLIP,BOUND_STICK: five whole numbers."""
    words = text.split(",")
    if len(words) != 5 or not all(w.strip().isdigit() for w in words):
        raise argparse.ArgumentTypeError(f"'{text}' is not five whole numbers separated by commas")
    return text


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder")
    parser.add_argument("--rtol", type=float, default=1e-9, help="tolerance of every check (relative)")
    parser.add_argument("--zones", type=zone_counts, help="expected FREE,DAMPED_SLIP,DAMPED_STICK,BOUND_SLIP,BOUND_STICK counts")
    parser.add_argument("--column", action="store_true", help="check the column scene's known answer")
    parser.add_argument("--slide", action="store_true", help="check the oblique slide's known answer (3D, every node "
                        "sliding at the bound: the disk law, the total friction force, the block's momentum)")
    parser.add_argument("--compare", help="another output folder that must agree to --rtol")
    parser.add_argument("--other-law", action="store_true",
                        help="the run solves another law than the paper's p(r) = c_nu r_+ (a changed "
                             "edp/plugins/contactlaw.hpp): skip the checks that restate the paper's law")
    args = parser.parse_args()
    check = Checker(args.folder, other_law=args.other_law)
    if check.load():
        if args.column:
            try:
                check.column_applies()
            except Refusal as refusal:
                print(f"check_results.py: error: {suite.shown(args.folder)}: {refusal}", file=sys.stderr)
                sys.exit(2)
        check.check_contact(args.rtol)
        if check.dim == 3:
            check.check_frame(args.rtol)
        check.check_energy(args.rtol)
        check.check_series()
        check.check_stress(args.rtol)
        if args.zones:
            check.check_zones(args.zones)
        if args.column:
            check.check_column(args.rtol)
        if args.slide:
            check.check_slide(args.rtol)
        if args.compare:
            check.compare(args.compare, args.rtol)
    for failure in check.failures:
        print(f"  {args.folder}: {failure}")
    sys.exit(1 if check.failures else 0)


if __name__ == "__main__":
    suite.run_tool("check_results.py", main)
