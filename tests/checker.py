"""checker.py: what the checks of tests/check_results.py share: a run folder's outputs read
(Checker.load) and the round-off allowances of its comparisons.

Every comparison with a bound allows for round-off: ROUNDOFF (256 ulps) times the magnitude
of the terms the compared quantities are computed from (velocity_terms, stress_terms), never
a fixed tolerance. The law is the run's own: contact.txt carries what it gave each node (g,
damped_response = p(v_nu), force_scale = p(g) or 1 where p(g) = 0, friction_bound, the
statuses and zone), and the run's zones are the columns zone_* of its contact_history.txt
(runfiles.zone_names); nothing here derives p, g(x), the friction bound, a status or a zone
again.
"""
import os

import numpy as np

import runfiles

# The columns of contact_history.txt that are nan where there is none: the zone boundaries
# x_B, x_C (node positions) and their estimates between the nodes (nan in 3D too)
ZONE_BOUNDARY_COLUMNS = ("x_B", "x_C", "x_B_estimate", "x_C_estimate")

FILES = ("contact.txt", "fields.txt", "history.txt", "contact_history.txt", "summary.txt")
FRAME = ("n_x", "n_y", "n_z", "t1_x", "t1_y", "t1_z", "t2_x", "t2_y", "t2_z")     # contact.txt in 3D
LAW = ("g", "damped_response", "force_scale", "friction_bound", "normal_status", "tangential_status", "zone")
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
    """The value that passes its round-off allowance the most (arrays of one shape, or
    scalars): (that value - its allowance, the value, the allowance)."""
    values, allowance = (np.ravel(np.asarray(a, dtype=float)) for a in np.broadcast_arrays(values, allowance))
    k = int(np.argmax(values - allowance))
    return float(values[k] - allowance[k]), float(values[k]), float(allowance[k])


class Refusal(Exception):
    """A check that was asked for does not apply to the run (exit 2, one line saying why)."""


class Checker:
    """The outputs of one run folder (load) and the magnitudes its checks allow round-off of;
    expect() records a failed check's message in failures, after where (what a check of
    another table than contact.txt starts its messages with)."""

    def __init__(self, folder):
        self.folder = folder
        self.failures = []
        self.where = ""

    def expect(self, condition, message):
        if not condition:
            self.failures.append(self.where + message)
        return condition

    def load(self):
        """Read the outputs; False (with the failures) when a file or a column is missing, the
        row counts are not those summary.txt announces, or its zones (zone_columns: the columns
        zone_* of contact_history.txt) are not the keys zone_* of summary.txt."""
        for name in FILES:
            if not self.expect(os.path.isfile(os.path.join(self.folder, name)), f"missing {name}"):
                return False
        self.c = runfiles.read_table(os.path.join(self.folder, "contact.txt"))
        self.params = self.c.params
        self.h = runfiles.read_table(os.path.join(self.folder, "history.txt"))
        self.f = runfiles.read_table(os.path.join(self.folder, "fields.txt"))
        self.ch = runfiles.read_table(os.path.join(self.folder, "contact_history.txt"))
        self.summary = runfiles.read_summary(os.path.join(self.folder, "summary.txt"))
        self.dim = runfiles.run_dimension(self.folder)
        if self.dim == 3:           # the columns a 3D run adds (docs/design.md, "Three dimensions")
            for name, table, columns in (("contact.txt", self.c, ("z", "v_tau2", "lambda_tau2") + FRAME),
                                         ("fields.txt", self.f, ("z", "u_z", "v_z")),
                                         ("contact_history.txt", self.ch, ("tangential_force2",))):
                for column in columns:
                    self.expect(column in table, f"{name} lacks column {column} (a 3D run)")
        for name in ("x", "v_nu", "v_tau", "p_nu", "lambda_nu", "lambda_tau", "weight") + LAW:
            self.expect(name in self.c, f"contact.txt lacks column {name}")
        for name in ("step", "t", "iterations", "residual", "kinetic", "elastic", "numerical_dissipation",
                     "viscous_dissipation", "contact_dissipation", "external_work", "energy_residual",
                     "kinetic_jump", "elastic_jump"):
            self.expect(name in self.h, f"history.txt lacks column {name}")
        for name in ("x", "y", "u_x", "u_y", "v_x", "v_y", "von_mises"):
            self.expect(name in self.f, f"fields.txt lacks column {name}")
        # every table finite where the solver writes finite numbers (the zone boundaries may be nan),
        # with the rows summary.txt announces
        for name, table, rows in (("contact.txt", self.c, "contact_nodes"), ("fields.txt", self.f, "vertices"),
                                  ("history.txt", self.h, "steps"), ("contact_history.txt", self.ch, "steps")):
            finite = table.data if name != "contact_history.txt" else \
                table.data[:, [k for k, column in enumerate(table.columns) if column not in ZONE_BOUNDARY_COLUMNS]]
            self.expect(bool(np.isfinite(finite).all()), f"{name} holds non-finite numbers"
                        + (" (beyond " + ", ".join(ZONE_BOUNDARY_COLUMNS) + ", nan where there is none)"
                           if name == "contact_history.txt" else ""))
            self.expect(str(len(table)) == self.summary[rows],
                        f"{name} has {len(table)} rows, summary.txt says {rows} {self.summary[rows]}")
        self.zone_columns = runfiles.zone_names(self.ch.columns)
        self.expect(self.zone_columns, "contact_history.txt has no zone_* column (the zones of the run)")
        keys = runfiles.zone_names(self.summary)
        self.expect(keys == self.zone_columns,
                    (f"summary.txt's zones {' '.join(keys)}" if keys else "summary.txt has no zone_* key") + " but "
                    f"contact_history.txt has the columns {' '.join(self.zone_columns) or '(none)'}")
        if not self.failures:
            for name, high in (("normal_status", 2), ("tangential_status", 1), ("zone", len(self.zone_columns) - 1)):
                self.c.codes(name, 0, high)
        return not self.failures

    def real(self, key):
        return self.params.real(key)

    def plane_strain(self):
        return self.dim == 2 and self.params["plane"] == "strain"

    def elastic_lambda(self):
        """B's volumetric coefficient (docs/design.md, "The discrete problem"): E nu/(1-nu^2) in
        plane stress (sigma_zz = 0), E nu/((1+nu)(1-2nu)) in plane strain (eps_zz = 0) and in
        3D (lambda3, the isotropic law itself)."""
        E, nu = self.real("E"), self.real("nu")
        return E * nu / ((1 + nu) * (1 - 2 * nu)) if self.dim == 3 or self.plane_strain() else E * nu / (1 - nu ** 2)

    def second_tangent(self, table, *names):
        """The columns v_tau2, lambda_tau2 (names) of a 3D table; zeros in 2D, where a node has
        one tangent: then |(v_tau, v_tau2)| = |v_tau| exactly."""
        return [table[name] if self.dim == 3 else np.zeros(len(table["x"])) for name in names]

    def count(self, key):
        """A whole number of summary.txt."""
        return self.summary.integer(key)

    def body(self):
        """|Omega| (the triangles' area, per unit thickness in 2D, or the tetrahedra's volume)
        and the squared mean element size h^2 of mesh.msh (a triangle is h^2/2, a tetrahedron
        h^3/6)."""
        if not hasattr(self, "_body"):
            mesh = runfiles.read_msh(os.path.join(self.folder, "mesh.msh"), self.dim)
            if self.dim == 3:
                measure = float(np.abs(np.linalg.det(mesh.xyz[mesh.tetrahedra[:, 1:]]
                                                      - mesh.xyz[mesh.tetrahedra[:, :1]])).sum()) / 6
                h2 = (6 * measure / len(mesh.tetrahedra)) ** (2 / 3)
            else:
                p = mesh.xy[mesh.triangles]
                measure = float(np.abs(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])).sum()) / 2
                h2 = 2 * measure / len(mesh.triangles)
            self._body = measure, h2
        return self._body

    def damping_slope(self):
        """The damping slope K_n = p'(g) that the solver folds into its matrix S (docs/design.md,
        "Condensation"), which the round-off allowances need: the largest of contact.txt's
        column damping_slope."""
        return float(np.abs(self.c["damping_slope"]).max())

    def velocity_terms(self, force, kinetic, slope=0.0):
        """The magnitude of the terms a contact velocity is computed from, at a step of total
        contact force `force` (normal or tangential) and kinetic energy `kinetic`: the body's
        rms velocity sqrt(2 kinetic/(rho |Omega|)), and the velocity the contact stresses alone
        give it in one step (c = c_free - Dw m, docs/design.md "Condensation"): their force over
        what holds the body's rigid motion along them, its inertia rho |Omega|/k and, normal to
        Gamma3, the damping slope of Gamma3 (slope = K_n L) that the solver folds into S; plus
        g. A body held only by the foundation with p' = 0 gives k |force|/(rho |Omega|): a
        column at the bound that computes v_nu = g from terms of 1e5 m/s."""
        rho, k, g = self.real("rho"), self.real("dt"), float(self.c["g"].max())
        mass = rho * self.body()[0]
        return g + np.sqrt(2 * np.maximum(kinetic, 0.0) / mass) + k * np.abs(force) / (mass + k * slope)

    def normal_velocity_terms(self, step=-1):
        """velocity_terms of the normal velocities at a step (index into the histories; T by
        default)."""
        return self.velocity_terms(self.ch["normal_force"][step], self.h["kinetic"][step],
                                   self.damping_slope() * float(np.sum(self.c["weight"])))

    def stress_terms(self, v_nu, c=None, step=-1):
        """The magnitude of the terms each node's contact stresses are computed from: |p_nu|,
        |lambda_nu|, |lambda_tau| themselves (the damped response is p_nu - lambda_nu), and
        the damping slope times the velocity, K_n (|v_nu| + the velocity terms): the solver
        writes a normal stress as p_nu = K_n v_nu + m (docs/design.md, "Condensation"), which
        cancels to 0 on a free node of a body flying away. c: the nodes' columns at the step
        (contact.txt's at T by default)."""
        c = self.c if c is None else c
        second, = self.second_tangent(c, "lambda_tau2")
        stress = np.abs(c["p_nu"]) + np.abs(c["lambda_nu"]) + np.hypot(c["lambda_tau"], second)
        return stress + self.damping_slope() * (np.abs(v_nu) + self.normal_velocity_terms(step))
