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
Options add: expected zone counts, the known answer of the column scene, and
agreement with another output folder of the same discrete problem.

Usage: check_results.py DIR [--zones FREE,DAMPED_SLIP,DAMPED_STICK,BOUND_SLIP,BOUND_STICK] [--column]
                            [--compare OTHER_DIR] [--rtol 1e-9] [--other-law]
--other-law: the run solves another law than the paper's (a changed contactlaw.hpp): the
checks that restate p(r) = c_nu r_+ are skipped, the friction cone uses friction_bound.
Prints one line per failed check and exits 1 if any failed (or, on an unreadable
input, one error line); exits 2 when plots/suite.py cannot be imported (run it through
./run.sh, which sets PYTHONPATH).
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
        plane stress (sigma_zz = 0), E nu/((1+nu)(1-2nu)) in plane strain (eps_zz = 0)."""
        E, nu = self.real("E"), self.real("nu")
        return E * nu / ((1 + nu) * (1 - 2 * nu)) if self.plane_strain() else E * nu / (1 - nu ** 2)

    def count(self, key):
        """A whole number of summary.txt, -1 when it is not there."""
        return self.summary.integer(key) if key in self.summary else -1

    def check_contact(self, rtol):
        c, law, mu = self.c, self.scene, self.real("mu")
        vn, vt, pn, ln, lt = c["v_nu"], c["v_tau"], c["p_nu"], c["lambda_nu"], c["lambda_tau"]
        g = law.g(c["x"])                                      # the bound at each node
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
            err = (np.abs(pn - damped - ln) / scale).max()
            self.expect(err <= rtol, f"p_nu != p(v_nu) + lambda_nu: {err:.3e} p(g)")
            err = (np.abs(c["friction_bound"] - bound) / scale).max()
            self.expect(err <= rtol, f"friction_bound != mu p(v_nu): {err:.3e} p(g)")
        if self.params["problem"] == "original":
            viol = (np.maximum(vn - g, 0.0) / g).max()
            self.expect(viol <= rtol, f"constraint v_nu <= g violated by {viol:.3e} g")
            neg = (np.maximum(-ln, 0.0) / scale).max()
            self.expect(neg <= rtol, f"negative multiplier lambda_nu: {neg:.3e} p(g)")
            # each node: lambda_nu = 0 or v_nu = g, in relative terms (scale-free: a node far
            # below the bound, as in a free flight, does not amplify the round-off of lambda_nu)
            comp = np.minimum(np.abs(ln) / scale, np.abs(vn - g) / g).max()
            self.expect(comp <= rtol, f"complementarity min(|lambda_nu|/p(g), |v_nu - g|/g) = {comp:.3e}")
        else:
            # compliant form eps lambda_nu = (v_nu - g)_+, in velocity units (dividing by eps
            # would amplify the round-off of v_nu by 1/eps), relative to g or, for a large eps,
            # to eps p(g) (eps times the round-off of lambda_nu is no violation)
            eps = self.real("eps")
            err = (np.abs(eps * ln - np.maximum(vn - g, 0.0)) / np.maximum(g, eps * scale)).max()
            self.expect(err <= rtol, f"penalty law eps lambda_nu = (v_nu - g)_+ off by {err:.3e} g")
        over = ((np.abs(lt) - bound) / scale).max()
        self.expect(over <= rtol, f"friction cone |lambda_tau| <= mu p(v_nu) violated by {over:.3e} p(g)")
        slip = np.abs(vt) > 1e-6 * g
        if slip.any():
            gap = (np.abs(np.abs(lt[slip]) - bound[slip]) / scale[slip]).max()
            self.expect(gap <= rtol, f"sliding nodes off the friction bound by {gap:.3e} p(g)")
            opposed = (lt[slip] * vt[slip] < 0) & (bound[slip] > rtol * scale[slip])
            self.expect(not opposed.any(), f"{int(opposed.sum())} sliding nodes with lambda_tau against v_tau")
        normal = np.where(vn <= 0, 0, np.where(vn >= g * (1 - 1e-6), 2, 1))
        tangential = np.where(np.abs(vt) <= 1e-6 * g, 0, 1)
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
        self.expect(abs(ch["normal_force"][-1] - force) <= rtol * max(abs(force), scale),
                    f"contact_history normal_force {ch['normal_force'][-1]} != sum w p_nu = {force}")
        tforce = np.sum(c["weight"] * lt)
        self.expect(abs(ch["tangential_force"][-1] - tforce) <= rtol * max(abs(tforce), scale),
                    f"contact_history tangential_force {ch['tangential_force'][-1]} != sum w lambda_tau = {tforce}")
        at_bound = c["x"][normal == 2]
        sticking = c["x"][(normal > 0) & (tangential == 0)]
        for name, xs in (("x_B", at_bound), ("x_C", sticking)):
            want = xs.min() if len(xs) else np.nan
            got = ch[name][-1]
            self.expect((np.isnan(want) and np.isnan(got)) or got == want, f"contact_history {name} = {got}, contact.txt gives {want}")

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
        worst = (np.abs(balance) / largest).max()
        self.expect(worst <= rtol, f"discrete energy balance off by {worst:.3e} (relative to the largest term)")
        # the solver's own residual column (and its maximum in summary.txt) says the same:
        # both are round-off, so they agree to rtol (a residual column off by more than
        # that is a wrong balance in the solver, or a wrong column)
        reported = h["energy_residual"]
        off = np.abs(reported - np.abs(balance) / largest).max()
        self.expect(off <= rtol, f"energy_residual column differs from the recomputed balance by {off:.3e}")
        if "check_energy_residual" in self.summary:
            self.expect(self.summary.real("check_energy_residual") == reported.max(),
                        "summary check_energy_residual != max of history energy_residual")
        parts = h["kinetic_jump"] + h["elastic_jump"] - h["numerical_dissipation"]
        self.expect(np.abs(parts).max() <= rtol * largest.max(), "kinetic_jump + elastic_jump != numerical_dissipation")
        for name in ("kinetic", "elastic", "numerical_dissipation", "viscous_dissipation", "contact_dissipation",
                     "kinetic_jump", "elastic_jump"):
            low = (h[name] / largest).min()
            self.expect(low >= -rtol, f"{name} negative ({low:.3e})")
        tol = self.real("tol")
        self.expect((h["residual"] <= tol).all(), "a step's residual is above -tol")
        self.expect((h["iterations"] >= 1).all(), "a step reports no iteration")
        # last step: contact dissipation from contact.txt
        c = self.c
        mine = dt * np.sum(c["weight"] * (c["p_nu"] * c["v_nu"] + c["lambda_tau"] * c["v_tau"]))
        theirs = h["contact_dissipation"][-1]
        self.expect(abs(mine - theirs) <= rtol * max(largest[-1], 1e-300),
                    f"contact dissipation of the last step: contact.txt gives {mine:.15e}, history {theirs:.15e}")

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
        for name in ("x", "y", "v_nu", "v_tau", "p_nu", "lambda_nu", "lambda_tau", "normal_status", "tangential_status"):
            self.expect((nh[name][last] == c[name]).all(), f"contact_nodes_history.txt at T: {name} differs from contact.txt")

    def check_stress(self, rtol):
        """fields.txt's von_mises, recomputed: sigma = A eps(v) + B eps(u) on each triangle (P1:
        constant), its von Mises measure, averaged at each vertex with the triangles' areas."""
        f, mesh = self.f, suite.read_msh22(os.path.join(self.folder, "mesh.msh"))
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
        worst = np.abs(mine - f["von_mises"]).max()
        self.expect(worst <= rtol * max(np.abs(mine).max(), 1e-300),
                    f"von_mises: fields.txt differs from its recomputation by {worst:.3e} (largest {np.abs(mine).max():.3e})")

    def check_zones(self, expected):
        want = [int(x) for x in expected.split(",")]
        got = [self.zones[k] for k in self.ZONES]
        self.expect(got == want, f"zones free,damped-slip,damped-stick,bound-slip,bound-stick = {got}, expected {want}")

    def check_column(self, rtol):
        """Known answer of the column scene, for the run's own damped response p, bound g(x)
        and load history h(t) (its scene.scene). Summing the equations with w = (0,1) gives,
        at every step, exactly: sum_i w_i p_nu_i = q L + |Omega| (-f0_y) - (1/k) m(v_n - v_{n-1}, e_y),
        q = load h(t_n), and by Cauchy-Schwarz |m(dv, e_y)| <= sqrt(2 kinetic_jump) sqrt(rho |Omega|)
        (kinetic_jump = 1/2 m(dv, dv)). While pulled (q < 0) every node is free. At T, pressed,
        the column is uniaxial when the known answer v_nu = min(p^-1(q), g(x)) is the same at
        every node: then each node carries p_nu = q. Where g(x) makes it differ between
        nodes, the body shears and carries load between them: only v_nu = g(x) at the nodes
        at the bound is known, and only when every node is at the bound. A body force makes
        the stress vary along the height, which the viscoelastic law couples to the width:
        then only the total force is known."""
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
        # round-off grows with the stiffness of the volumetric term (lambda/E, large near nu = 0.5)
        roundoff = 1e-12 * max(1.0, self.elastic_lambda() / self.real("E")) * force_scale
        off = np.abs(ch["normal_force"] - (q_steps * length + weight)) - inertia_steps - roundoff
        worst = int(np.argmax(off))
        self.expect(off[worst] <= 0, f"step {worst + 1}: total contact force {ch['normal_force'][worst]:.15e} != "
                    f"q L = {q_steps[worst] * length + weight:.15e} (inertia bound {inertia_steps[worst]:.3e})")
        pulled = q_steps * length + weight < 0
        if pulled.any():
            force = np.abs(ch["normal_force"][pulled]).max() / force_scale
            self.expect(force <= rtol, f"pulled steps: a normal force of {force:.3e} p(g) L")
            self.expect((ch["zone_free"][pulled] == len(c["x"])).all(), "pulled steps: a node is not free")
        q = load * float(law.h(T)) + weight / length
        if q < 0:
            self.expect((np.abs(c["p_nu"]) / law.p(g)).max() <= rtol,
                        f"pulled (q = {q}): p_nu = {np.abs(c['p_nu']).max():.3e} != 0")
            self.expect((c["v_nu"] <= 0).all() and (c["normal_status"] == 0).all(),
                        f"pulled (q = {q}): a node is not free (v_nu max {c['v_nu'].max():.3e})")
            return
        if weight != 0:
            return          # a body force makes the stress vary along the height: not uniaxial
        inertia = inertia_steps[-1]
        free = law.inverse(q)
        vexact = np.minimum(free, g)
        uniform = vexact.max() == vexact.min()
        if not uniform:
            self.expect(bool((free >= g).all()), "the known answer min(p^-1(q), g(x)) differs between nodes and "
                        "not every node is at the bound: no known answer (the body shears)")
            err = (np.abs(c["v_nu"] - g) / g).max()
            self.expect(err <= 1e-10, f"every node at the bound, v_nu = g(x): off by {err:.3e} g")
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
        err_p = np.abs(c["p_nu"] - q).max()
        self.expect(err_p <= slack, f"p_nu differs from q = {q} by {err_p:.3e} > {slack:.3e}")
        err_v = np.abs(c["v_nu"] - vexact)
        allowed = np.where(free < g, slack / law.slope(free), 0.0) + 1e-10 * g
        worst = int(np.argmax(err_v - allowed))
        self.expect((err_v <= allowed).all(), f"v_nu differs from min(p^-1(q), g) = {vexact[worst]} by "
                    f"{err_v[worst]:.3e} > {allowed[worst]:.3e} at x = {c['x'][worst]}")
        self.expect(np.abs(c["lambda_tau"]).max() == 0.0 or self.real("mu") > 0, "lambda_tau != 0 without friction")
        if (q_steps > 0).all():
            # the stress error of each step: its inertia bound, and that of the acceleration
            # along the known answer (absolute, per unit length)
            self.check_uniaxial_strain(q_steps, 2 * inertia_steps / length + rho * height * rate)

    def check_uniaxial_strain(self, q_steps, stress_error):
        """The column pressed at every step is in uniaxial stress, sigma_yy = -q(t_n), sigma_xx =
        sigma_xy = 0, up to inertia: its strain is uniform, and the scheme's backward Euler on
        the two equations sigma_xx = 0, sigma_yy = -q of the Kelvin-Voigt law (docs/design.md,
        "The discrete problem") gives eps_xx and eps_yy at T exactly, for plane stress or plane strain. The
        displacement of fields.txt must be affine, with those strains, to the bound that the
        stress error of each step (stress_error: its inertia) leaves at T through the same
        recurrence (e_n = R e_{n-1} + S dq_n, |e_n| <= |R| |e_{n-1}| + |S| dq_n in the infinity
        norm: an early step's error fades with the law's memory), plus round-off. Measured:
        1e-10 relative after 20 steps, against a bound of 8e-8 there; the two planes differ
        by 4% (eps_yy) and 20% (eps_xx), and lambda 1e-5 off moves eps_xx by 6e-6."""
        E, nu, mu1, mu2, k = self.real("E"), self.real("nu"), self.real("muv"), self.real("eta"), self.real("dt")
        plane_strain, lam = self.plane_strain(), self.elastic_lambda()
        shear = E / (1 + nu)
        exx = eyy = 0.0
        lhs = np.array([[mu1 + mu2 + k * (lam + shear), mu1 + k * lam], [mu1 + k * lam, mu1 + mu2 + k * (lam + shear)]])
        # e_n = R e_{n-1} + S q_n for e = (eps_xx, eps_yy): the rates L^-1 (C e - (0, q)), e += k rate
        C = np.array([[-(lam + shear), -lam], [-lam, -(lam + shear)]])
        R = np.eye(2) + k * np.linalg.solve(lhs, C)
        S = k * np.linalg.solve(lhs, np.array([0.0, -1.0]))
        bound = 0.0
        for q, dq in zip(q_steps, stress_error):   # the rates (b, a) of eps_xx, eps_yy at step n
            rhs = np.array([-lam * (exx + eyy) - shear * exx, -q - lam * (exx + eyy) - shear * eyy])
            b, a = np.linalg.solve(lhs, rhs)
            exx, eyy = exx + k * b, eyy + k * a
            bound = np.abs(R).sum(1).max() * bound + np.abs(S).max() * dq
        tolerance = bound / abs(eyy) + 1e-9
        f = self.f
        basis = np.c_[np.ones(len(f)), f["x"], f["y"]]
        cx = np.linalg.lstsq(basis, f["u_x"], rcond=None)[0]
        cy = np.linalg.lstsq(basis, f["u_y"], rcond=None)[0]
        affine = max(np.abs(basis @ cx - f["u_x"]).max(), np.abs(basis @ cy - f["u_y"]).max()) / abs(eyy)
        self.expect(affine <= tolerance, f"uniaxial column: the displacement is not affine (off by {affine:.3e} of eps_yy, "
                    f"inertia bound {tolerance:.3e})")
        for name, got, want in (("eps_xx", cx[1], exx), ("eps_yy", cy[2], eyy)):
            self.expect(abs(got - want) <= tolerance * abs(want), f"uniaxial column ({'plane strain' if plane_strain else 'plane stress'}): "
                        f"{name} = {got:.12e}, the Kelvin-Voigt law gives {want:.12e} (inertia bound {tolerance:.3e} relative)")

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
        self.compare_tables(other_folder, "contact.txt",
                            (("v_nu", "v_tau"), ("p_nu", "lambda_nu", "lambda_tau")), (), rtol,
                            floors=(float(g.max()), float(scene.p(g).max())))
        self.compare_tables(other_folder, "fields.txt", (("u_x", "u_y"), ("v_x", "v_y")), (), rtol)
        # the histories, when both folders have them; the total forces at least at the scale of
        # p(g) over the whole of Gamma3 (a run whose forces are round-off compares as such)
        force_floor = float(scene.p(g).max()) * float(np.abs(c["weight"]).sum())
        for name, families, exact, floors in (
                ("history.txt", (("kinetic", "elastic", "numerical_dissipation", "viscous_dissipation",
                                  "contact_dissipation", "external_work", "kinetic_jump", "elastic_jump"),), (), None),
                ("contact_history.txt", (("normal_force", "tangential_force"),), self.ZONES + ("x_B", "x_C"),
                 (force_floor,))):
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
    parser.add_argument("--compare", help="another output folder that must agree to --rtol")
    parser.add_argument("--other-law", action="store_true",
                        help="the run solves another law than the paper's p(r) = c_nu r_+ (a changed "
                             "edp/plugins/contactlaw.hpp): skip the checks that restate the paper's law")
    args = parser.parse_args()
    check = Checker(args.folder, other_law=args.other_law)
    if check.load():
        check.check_contact(args.rtol)
        check.check_energy(args.rtol)
        check.check_series()
        check.check_stress(args.rtol)
        if args.zones:
            check.check_zones(args.zones)
        if args.column:
            check.check_column(args.rtol)
        if args.compare:
            check.compare(args.compare, args.rtol)
    for failure in check.failures:
        print(f"  {args.folder}: {failure}")
    sys.exit(1 if check.failures else 0)


if __name__ == "__main__":
    suite.run_tool("check_results.py", main)
