#!/usr/bin/python3
"""Check one output folder of edp/solve.edp against the physics (docs/design.md,
"End-of-run checks" and "Energy identity").

Reads only the text outputs (nothing of the solver), and checks them against the law's own
columns (contact.txt: g, damped_response = p(v_nu), force_scale = p(g), friction_bound, the
statuses and zone; the run's zones: the columns zone_* of contact_history.txt), so that it
holds for any law of edp/plugins/contactlaw.hpp (its damped response, its friction bound,
its zones): the constraint v_nu <= g and complementarity (original problem), the penalty law
(penalty problem), p_nu = damped_response + lambda_nu (the decomposition of the normal
stress, whatever p), the friction cone |lambda_tau| <= friction_bound with equality and the
right direction on sliding nodes (tangential status 1), the zone counts of summary.txt and
contact_history.txt against the column zone, x_B and x_C (the first node at the bound,
normal status 2, and the first sticking node in contact), the discrete energy balance of
every step recomputed from its terms, the contact dissipation of the last step recomputed
from contact.txt, the rows of contact_nodes_history.txt against contact.txt and
contact_history.txt, the von Mises stress of fields.txt recomputed from the fields and the
mesh. The tests' independent solvers derive the law on their own and compare its columns.
A 3D run (summary.txt: dimension 3; docs/design.md, "Three dimensions") is checked alike,
with the disk friction law (|lambda_tau| = hypot(lambda_tau, lambda_tau2), colinear with the
slip), its tetrahedra and its node frames (tests/checks3d.py).
Options add: expected zone counts, the known answers of the column scene (column, column3d)
and of the oblique slide (oblique-slide3d) (tests/known_answers.py), and agreement with
another output folder of the same discrete problem (edp/runfiles.py, compare_runs).

Usage: check_results.py DIR [--zones N0,N1,...] [--column] [--slide] [--compare OTHER_DIR] [--rtol 1e-9]
--zones: the expected node count of each of the run's zones at T, in the order of their
codes (the columns zone_* of contact_history.txt: free, damped-slip, damped-stick,
bound-slip, bound-stick for the law as shipped).
Every check reads the law's own columns, so it holds for a changed contactlaw.hpp too.
Prints one line per failed check and exits 1 if any failed (or, on an unreadable input, one
error line); exits 2 when --column does not apply to the run's load history (one line saying
why: a history that pulls the column before it presses it).
Every comparison with a bound allows for round-off: ROUNDOFF (256 ulps) times the magnitude
of the terms the compared quantities are computed from (tests/checker.py), never a fixed
tolerance.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import numpy as np

import runfiles
from checker import ROUNDOFF, Checker, Refusal, worst
from checks3d import Checks3D
from known_answers import KnownAnswers


class Checks(Checker, Checks3D, KnownAnswers):
    """Every check of a run folder (Checker's outputs and allowances, the 3D checks, the
    known answers); each records its failures."""

    def check_contact(self, rtol):
        """The nodal laws at T (check_law), then the zone counts."""
        stress_roundoff = self.check_law(rtol)
        self.check_zone_counts(rtol, stress_roundoff)

    def check_law(self, rtol, c=None, step=-1, where=""):
        """The nodal laws against the law's columns: p_nu = damped_response + lambda_nu, the
        constraint and complementarity (original) or the penalty law, then the friction cone
        against friction_bound (whatever law gave it). c: the nodes' columns at a step (contact.txt,
        at T, by default), step its index into the histories, where what the messages start
        with. Returns the stresses' round-off allowances."""
        c = self.c if c is None else c
        self.where = where
        vn, pn, ln = c["v_nu"], c["p_nu"], c["lambda_nu"]
        g, scale = c["g"], c["force_scale"]                                  # the law's, at each node
        # the round-off allowances (ROUNDOFF): of a normal velocity, of the terms it is computed
        # from (velocity_terms); of a stress, of its terms (stress_terms)
        velocity_roundoff = ROUNDOFF * (np.abs(vn) + self.normal_velocity_terms(step))
        stress_roundoff = ROUNDOFF * self.stress_terms(vn, c, step)
        excess, err, allow = worst(np.abs(pn - c["damped_response"] - ln) / scale, stress_roundoff / scale)
        self.expect(excess <= rtol, f"p_nu != damped_response + lambda_nu: {err:.3e} p(g) (round-off allowance {allow:.1e})")
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
        self.check_friction(rtol, stress_roundoff, c, step)
        self.where = ""
        return stress_roundoff

    def check_friction(self, rtol, stress_roundoff, c, step):
        """The friction cone |lambda_tau| <= friction_bound, with equality on the sliding nodes
        (tangential status 1) and the stress along the slip. |v_tau|, |lambda_tau|: in 3D the
        lengths of the pairs (t1, t2) of the disk law (docs/design.md, "Three dimensions"); in
        2D the absolute values (v_tau2 = lambda_tau2 = 0)."""
        mu = self.real("mu")
        vt, lt, g, scale, bound = c["v_tau"], c["lambda_tau"], c["g"], c["force_scale"], c["friction_bound"]
        vt2, lt2 = self.second_tangent(c, "v_tau2", "lambda_tau2")
        speed, stress = np.hypot(vt, vt2), np.hypot(lt, lt2)
        friction_roundoff = (1 + mu) * stress_roundoff / scale      # of |lambda_tau| and of mu p(v_nu)
        excess, over, allow = worst((stress - bound) / scale, friction_roundoff)
        self.expect(excess <= rtol, f"friction cone |lambda_tau| <= mu p(v_nu) violated by {over:.3e} p(g) "
                    f"(round-off allowance {allow:.1e})")
        slip = c["tangential_status"] == 1
        if not slip.any():
            return
        excess, gap, allow = worst(np.abs(stress[slip] - bound[slip]) / scale[slip], friction_roundoff[slip])
        self.expect(excess <= rtol, f"sliding nodes off the friction bound by {gap:.3e} p(g) "
                    f"(round-off allowance {allow:.1e})")
        if self.dim == 2:
            opposed = (lt[slip] * vt[slip] < 0) & (bound[slip] > rtol * scale[slip])
            self.expect(not opposed.any(), f"{int(opposed.sum())} sliding nodes with lambda_tau against v_tau")
            return
        # the disk law: lambda_tau = s v_tau/|v_tau| on a sliding node, a vector along the slip,
        # same direction. Across the force, the slip may move by what the solver's tolerance
        # leaves of the velocity (docs/design.md, "Nodal laws": a stress mismatch of
        # tol min(p(g), r g) moves v by tol g at most), so that component is measured relative
        # to g, not to |v_tau| (a node that slips at 1e-6 g may turn by 1e-4)
        pushed = slip & (bound > rtol * scale)
        opposed = pushed & (lt * vt + lt2 * vt2 <= 0)
        self.expect(not opposed.any(), f"{int(opposed.sum())} sliding nodes with lambda_tau against v_tau "
                    "(lambda_tau . v_tau <= 0)")
        pushed &= stress > 0            # (a sliding node without stress is off the bound, above)
        across = np.where(pushed, np.abs(vt * lt2 - vt2 * lt) / np.where(pushed, stress, 1.0) / g, 0.0)
        # round-off: of the tangential velocities' terms (velocity_terms of the friction force)
        tangential = self.velocity_terms(np.hypot(self.ch["tangential_force"][step], self.ch["tangential_force2"][step]),
                                         self.h["kinetic"][step])
        allowed = rtol + ROUNDOFF * (speed + tangential) / g
        node = int(np.argmax(across - allowed))
        self.expect(across[node] <= allowed[node], f"sliding node {node}: v_tau has a component of "
                    f"{across[node]:.3e} g across lambda_tau (bound {rtol:g} g + round-off "
                    f"{allowed[node] - rtol:.1e} g): the friction stress is not along the slip")

    def check_zone_counts(self, rtol, stress_roundoff):
        """The zone counts of summary.txt and of the last line of contact_history.txt are those
        of the column zone (code k: the k-th of the run's zones); x_B and x_C the smallest x of
        a node at the bound (normal status 2) and of a sticking node in contact (normal status
        1 or 2, tangential status 0); the total forces those of the nodes."""
        c, ch = self.c, self.ch
        zone = c["zone"].astype(int)
        zones = {column: int(np.sum(zone == code)) for code, column in enumerate(self.zone_columns)}
        for key, value in zones.items():
            self.expect(self.count(key) == value, f"summary {key} = {self.summary[key]} but contact.txt gives {value}")
            self.expect(ch[key][-1] == value, f"contact_history {key} = {ch[key][-1]} at T but contact.txt gives {value}")
        self.expect(self.count("contact_nodes") == len(c), "summary contact_nodes != rows of contact.txt")
        self.zones = zones
        self.expect((sum(ch[key] for key in self.zone_columns) == len(c)).all(),
                    "contact_history zone counts do not add up to the nodes")
        normal, tangential = c["normal_status"], c["tangential_status"]
        for name, nodes in (("x_B", normal == 2), ("x_C", (normal > 0) & (tangential == 0))):
            xs = c["x"][nodes]
            want, got = (xs.min() if len(xs) else np.nan), ch[name][-1]
            self.expect((np.isnan(want) and np.isnan(got)) or got == want, f"contact_history {name} = {got}, contact.txt gives {want}")
        force = np.sum(c["weight"] * c["p_nu"])
        scale = float(c["force_scale"].max())
        # round-off: of the nodes' terms w |stress| (the same numbers summed in another order)
        summed = ROUNDOFF * float(np.sum(c["weight"] * self.stress_terms(c["v_nu"])))
        self.expect(abs(ch["normal_force"][-1] - force) <= rtol * max(abs(force), scale) + summed,
                    f"contact_history normal_force {ch['normal_force'][-1]} != sum w p_nu = {force}")
        if self.dim == 2:
            tforce = np.sum(c["weight"] * c["lambda_tau"])
            self.expect(abs(ch["tangential_force"][-1] - tforce) <= rtol * max(abs(tforce), scale) + summed,
                        f"contact_history tangential_force {ch['tangential_force'][-1]} != sum w lambda_tau = {tforce}")
            return
        # the total friction stress as a vector, sum w (lambda_tau t1 + lambda_tau2 t2), on the
        # mean frame of Gamma3 that summary.txt gives (contact_frame_t1, contact_frame_t2)
        t1, t2 = (np.stack([c[f"{t}_{a}"] for a in "xyz"], 1) for t in ("t1", "t2"))
        vector = (c["weight"][:, None] * (c["lambda_tau"][:, None] * t1 + c["lambda_tau2"][:, None] * t2)).sum(0)
        try:
            mean = [np.array([float(w) for w in self.summary[key].split()]) for key in ("contact_frame_t1", "contact_frame_t2")]
        except ValueError:
            raise runfiles.InputError(f"{self.summary.source}: contact_frame_t1, contact_frame_t2 need numbers") from None
        for name, axis in zip(("tangential_force", "tangential_force2"), mean):
            if not self.expect(axis.shape == (3,) and abs(np.linalg.norm(axis) - 1) <= 1e-12,
                               f"summary.txt: {name}'s axis {axis} is not a unit vector"):
                continue
            tforce = float(vector @ axis)
            self.expect(abs(ch[name][-1] - tforce) <= rtol * max(abs(tforce), scale) + summed,
                        f"contact_history {name} {ch[name][-1]} != the friction stress sum w (lambda_tau t1 + "
                        f"lambda_tau2 t2) on {axis} = {tforce}")
        self.expect(mean[0].shape == mean[1].shape == (3,) and abs(mean[0] @ mean[1]) <= 1e-12,
                    "summary.txt: contact_frame_t1 and contact_frame_t2 are not orthogonal")

    def check_energy(self, rtol):
        h = self.h
        steps, offset = self.summary.integer("steps"), self.step_offset()
        dt, T = self.real("dt"), self.real("T")
        self.expect(len(h["t"]) == steps == round(T / dt) - offset,
                    f"history has {len(h['t'])} steps, expected T/dt" + (f" - {offset} (the steps before the restart)" if offset else ""))
        self.expect(np.allclose(h["t"], dt * np.arange(offset + 1, offset + len(h["t"]) + 1), rtol=1e-12, atol=0),
                    "history t != n dt")
        energy = h["kinetic"] + h["elastic"]
        initial = self.summary.real("initial_kinetic")
        self.expect(initial >= 0, f"initial_kinetic negative ({initial})")
        if "initial_elastic" in self.summary:                   # u_0: 0 unless -restart
            self.expect(self.summary.real("initial_elastic") >= 0, "initial_elastic negative")
            initial += self.summary.real("initial_elastic")
        before = np.concatenate(([initial], energy[:-1]))     # u0, v0 (initial_velocity, or a restart's)
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
        least = 0 if self.params["solver"] == "fixedpoint" else 1
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
        measure, h2 = self.body()
        v2 = 2 * np.maximum(h["kinetic"], 0.0) / rho
        if self.step_offset() == 0:
            u2 = (k * np.cumsum(np.sqrt(v2))) ** 2             # u_0 = 0
        else:                                                   # a restart: u_n = u_T - k sum_{m > n} v_m
            uT = np.column_stack([self.f[name] for name in ("u_x", "u_y", "u_z")[:d]])
            later = np.concatenate((np.cumsum(np.sqrt(v2)[::-1])[::-1][1:], [0.0]))
            u2 = (np.sqrt(measure) * float(np.abs(uT).max()) * np.sqrt(d) + k * later) ** 2
        return ((k * viscous + k * k * stiff) * v2 + stiff * u2) / h2

    def step_offset(self):
        """The steps before this run's first (a run continued with -restart; 0 otherwise, and in
        runs older than the key first_step)."""
        return self.summary.integer("first_step") - 1 if "first_step" in self.summary else 0

    def check_series(self, rtol):
        """contact_nodes_history.txt: one row per contact node at the steps -every gives (and the
        last), finite; at each, the nodal laws (check_law, with that step's allowances) and the
        zone counts of contact_history.txt; at the last, contact.txt exactly."""
        path = os.path.join(self.folder, "contact_nodes_history.txt")
        if not self.expect(os.path.isfile(path), "missing contact_nodes_history.txt"):
            return
        nh, c, offset = runfiles.read_table(path), self.c, self.step_offset()
        steps = offset + len(self.h)                            # the last step's number
        every = int(nh.params.real("every")) or max(1, -(-steps // 200))
        recorded = sorted({n for n in range(offset + 1, steps + 1) if n % every == 0} | {steps})
        if not self.expect(len(nh) == len(c) * len(recorded),
                           f"contact_nodes_history.txt has {len(nh)} rows, expected {len(c)} nodes x {len(recorded)} steps"):
            return
        if not self.expect(bool(np.isfinite(nh.data).all()), "contact_nodes_history.txt holds non-finite numbers"):
            return
        for name, high in (("normal_status", 2), ("tangential_status", 1), ("zone", len(self.zone_columns) - 1)):
            nh.codes(name, 0, high)
        step = nh["step"].reshape(len(recorded), len(c))
        self.expect((step == np.array(recorded)[:, None]).all(), "contact_nodes_history.txt: not the steps -every gives")
        failures = len(self.failures)
        for row, n in enumerate(recorded[:-1]):       # (the last: contact.txt, checked by check_contact)
            rows = slice(row * len(c), (row + 1) * len(c))
            self.check_law(rtol, {name: nh[name][rows] for name in nh.columns}, n - 1 - offset,
                           f"contact_nodes_history.txt, step {n}: ")
            if len(self.failures) > failures:        # the first step that fails says it
                break
        zone = nh["zone"].reshape(len(recorded), len(c)).astype(int)
        for row, n in enumerate(recorded):
            counts = [int((zone[row] == code).sum()) for code in range(len(self.zone_columns))]
            logged = [int(self.ch[k][n - 1 - offset]) for k in self.zone_columns]
            if not self.expect(counts == logged, f"step {n}: contact_nodes_history.txt zones {counts}, contact_history.txt {logged}"):
                break
        last = slice(len(nh) - len(c), len(nh))
        for name in ("x", "y", "v_nu", "v_tau", "p_nu", "lambda_nu", "lambda_tau", "normal_status", "tangential_status",
                     "zone", "g", "friction_bound", "damped_response", "force_scale") \
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
        f, mesh = self.f, runfiles.read_msh22(os.path.join(self.folder, "mesh.msh"))
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

    def check_zones(self, expected):
        """The node counts of the run's zones at T (check_zone_counts) are `expected` (a list,
        in the order of the zones' codes)."""
        got = [self.zones[k] for k in self.zone_columns]
        if self.expect(len(expected) == len(got), f"--zones gives {len(expected)} counts, the run has {len(got)} zones "
                       f"({','.join(self.zone_columns)})"):
            self.expect(got == expected, f"zones {','.join(self.zone_columns)} = {got}, expected {expected}")

    def compare(self, other_folder, rtol):
        """Agreement with another run of the same discrete problem (runfiles.compare_runs)."""
        for failure in runfiles.compare_runs(self.folder, other_folder, rtol):
            self.expect(False, failure)


def zone_counts(text):
    """N0,N1,...: whole numbers separated by commas, one a zone (their number is the run's:
    check_zones)."""
    words = text.split(",")
    if not all(w.strip().isdigit() for w in words):
        raise argparse.ArgumentTypeError(f"'{text}' is not whole numbers separated by commas")
    return [int(w) for w in words]


def tolerance(text):
    """--rtol: a number > 0 and below 1 (a relative tolerance)."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0 < value < 1:
        raise argparse.ArgumentTypeError(f"'{text}' is not a relative tolerance: a number > 0 and < 1")
    return value


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder")
    parser.add_argument("--rtol", type=tolerance, default=1e-9, help="tolerance of every check (relative, > 0 and < 1)")
    parser.add_argument("--zones", type=zone_counts, help="expected node count of each zone at T, in the order of "
                        "the zone codes (the columns zone_* of contact_history.txt)")
    parser.add_argument("--column", action="store_true", help="check the column scene's known answer")
    parser.add_argument("--slide", action="store_true", help="check the oblique slide's known answer (3D, every node "
                        "sliding at the bound: the disk law, the total friction force, the block's momentum)")
    parser.add_argument("--compare", help="another output folder that must agree to --rtol")
    args = parser.parse_args()
    runfiles.run_folder(args.folder)              # a finished run (summary.txt, run.complete), else one line
    if args.compare:
        runfiles.run_folder(args.compare)
    check = Checks(args.folder)
    if check.load():
        if args.column:
            try:
                check.column_applies()
            except Refusal as refusal:
                print(f"check_results.py: error: {runfiles.shown(args.folder)}: {refusal}", file=sys.stderr)
                sys.exit(2)
        check.check_contact(args.rtol)
        if check.dim == 3:
            check.check_frame(args.rtol)
        check.check_energy(args.rtol)
        check.check_series(args.rtol)
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
    runfiles.run_tool("check_results.py", main)
