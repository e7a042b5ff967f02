#!/usr/bin/python3
"""Check one output folder of edp/solve.edp against the physics (docs/design.md,
"End-of-run checks" and "Energy identity").

Reads only the text outputs (nothing of the solver), so it is an independent check:
  constraint and complementarity (original problem), the penalty law (penalty problem),
  the friction cone and the direction of friction, p_nu = p(v_nu) + lambda_nu,
  the discrete energy balance of every step recomputed from its terms, the contact
  dissipation of the last step recomputed from contact.txt, the zone counts.
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

    def count(self, key):
        """A whole number of summary.txt, -1 when it is not there."""
        return self.summary.integer(key) if key in self.summary else -1

    def check_contact(self, rtol):
        c, cnu, g, mu = self.c, self.real("cnu"), self.real("g"), self.real("mu")
        vn, vt, pn, ln, lt = c["v_nu"], c["v_tau"], c["p_nu"], c["lambda_nu"], c["lambda_tau"]
        if self.other_law:
            # a law other than the paper's (edp/plugins/contactlaw.hpp changed): the friction
            # bound is the run's own, and the stresses set the force scale
            bound = c["friction_bound"]
            scale = max(np.abs(pn).max(), 1.0)
        else:
            scale = cnu * g if cnu * g > 0 else 1.0            # p(g): the force scale
            damped = cnu * np.maximum(vn, 0.0)
            bound = mu * damped
            err = np.abs(pn - damped - ln).max()
            self.expect(err <= rtol * scale, f"p_nu != p(v_nu) + lambda_nu: {err:.3e}")
            err = np.abs(c["friction_bound"] - bound).max()
            self.expect(err <= rtol * scale, f"friction_bound != mu p(v_nu): {err:.3e}")
        if self.params["problem"] == "original":
            viol = np.maximum(vn - g, 0.0).max() / g
            self.expect(viol <= rtol, f"constraint v_nu <= g violated by {viol:.3e} g")
            neg = np.maximum(-ln, 0.0).max() / scale
            self.expect(neg <= rtol, f"negative multiplier lambda_nu: {neg:.3e} p(g)")
            comp = np.abs(ln * (vn - g)).max() / (scale * g)
            self.expect(comp <= rtol, f"complementarity lambda_nu (v_nu - g) = {comp:.3e} p(g) g")
        else:
            # compliant form eps lambda_nu = (v_nu - g)_+, in velocity units (dividing by eps
            # would amplify the round-off of v_nu by 1/eps)
            eps = self.real("eps")
            err = np.abs(eps * ln - np.maximum(vn - g, 0.0)).max() / g
            self.expect(err <= rtol, f"penalty law eps lambda_nu = (v_nu - g)_+ off by {err:.3e} g")
        over = (np.abs(lt) - bound).max() / scale
        self.expect(over <= rtol, f"friction cone |lambda_tau| <= mu p(v_nu) violated by {over:.3e} p(g)")
        slip = np.abs(vt) > 1e-6 * g
        if slip.any():
            gap = np.abs(np.abs(lt[slip]) - bound[slip]).max() / scale
            self.expect(gap <= rtol, f"sliding nodes off the friction bound by {gap:.3e} p(g)")
            opposed = (lt[slip] * vt[slip] < 0) & (bound[slip] > rtol * scale)
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
        before = np.concatenate(([0.0], energy[:-1]))         # u0 = v0 = 0
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

    def check_zones(self, expected):
        want = [int(x) for x in expected.split(",")]
        got = [self.zones[k] for k in self.ZONES]
        self.expect(got == want, f"zones free,damped-slip,damped-stick,bound-slip,bound-stick = {got}, expected {want}")

    def check_column(self):
        """Known answer: sum of the equations with w = (0,1) gives, exactly,
        sum_i w_i p_nu_i = q L + (1/k) m(v_n - v_{n-1}, e_y), q = load T; and by Cauchy-Schwarz
        |m(dv, e_y)| <= sqrt(2 numerical_dissipation) sqrt(rho |Omega|). The column is uniaxial,
        so each node carries p_nu = q and v_nu = min(q/c_nu, g) up to that inertia term.
        kinetic_jump = 1/2 m(v_n - v_{n-1}, v_n - v_{n-1}) of the last step."""
        c, h = self.c, self.h
        q = self.real("load") * self.real("T")
        cnu, g, rho, dt = self.real("cnu"), self.real("g"), self.real("rho"), self.real("dt")
        length = c["weight"].sum()
        area = length * (self.f["y"].max() - self.f["y"].min())
        inertia = math.sqrt(2 * h["kinetic_jump"][-1] * rho * area) / dt            # force bound
        total = np.sum(c["weight"] * c["p_nu"])
        self.expect(abs(total - q * length) <= inertia + 1e-12 * q * length,
                    f"total contact force {total:.15e} != q L = {q * length:.15e} (inertia bound {inertia:.3e})")
        # per node: twice the inertia force per unit length of the last step (measured
        # unevenness: 1.002), plus the inertia force per unit length of the column while
        # it accelerated towards the bound, rho Ly load/c_nu: the viscoelastic body keeps
        # a memory of it once v_nu = g holds (measured there: 0.05 of it), plus round-off
        height = area / length
        slack = 2 * inertia / length + rho * height * self.real("load") / cnu + 1e-10 * q
        err_p = np.abs(c["p_nu"] - q).max()
        self.expect(err_p <= slack, f"p_nu differs from q = {q} by {err_p:.3e} > {slack:.3e}")
        vexact = min(q / cnu, g)
        err_v = np.abs(c["v_nu"] - vexact).max()
        self.expect(err_v <= slack / cnu + 1e-10 * g, f"v_nu differs from min(q/c_nu, g) = {vexact} by {err_v:.3e}")
        self.expect(np.abs(c["lambda_tau"]).max() == 0.0 or self.real("mu") > 0, "lambda_tau != 0 without friction")

    def compare_tables(self, other_folder, name, families, exact, rtol):
        """Columns of one family (velocities, stresses, displacements, energy terms, forces)
        differ by at most rtol of the family's scale, so that a column that is round-off in
        both runs (lambda_nu before any node reaches the bound, lambda_tau without friction)
        is compared as such; the `exact` columns (zone counts and boundaries) are equal."""
        a = suite.read_table(os.path.join(self.folder, name))
        b = suite.read_table(os.path.join(other_folder, name))
        if not self.expect(a.data.shape == b.data.shape, f"{name}: shapes differ {a.data.shape} {b.data.shape}"):
            return
        for family in families:
            scale = max(max(np.abs(a[col]).max(), np.abs(b[col]).max()) for col in family)
            scale = max(scale, 1e-300)
            for col in family:
                err = np.abs(a[col] - b[col]).max() / scale
                self.expect(err <= rtol, f"{name} {col}: difference {err:.3e} of the scale of {'/'.join(family)}"
                            f" > {rtol:g} vs {other_folder}")
        for col in exact:
            x, y = a[col], b[col]
            differ = ~((x == y) | (np.isnan(x) & np.isnan(y)))
            self.expect(not differ.any(), f"{name} {col}: differs at {int(differ.sum())} steps vs {other_folder}")

    def compare(self, other_folder, rtol):
        self.compare_tables(other_folder, "contact.txt",
                            (("v_nu", "v_tau"), ("p_nu", "lambda_nu", "lambda_tau")), (), rtol)
        self.compare_tables(other_folder, "fields.txt", (("u_x", "u_y"), ("v_x", "v_y")), (), rtol)
        # the histories, when both folders have them
        for name, families, exact in (
                ("history.txt", (("kinetic", "elastic", "numerical_dissipation", "viscous_dissipation",
                                  "contact_dissipation", "external_work", "kinetic_jump", "elastic_jump"),), ()),
                ("contact_history.txt", (("normal_force", "tangential_force"),), self.ZONES + ("x_B", "x_C"))):
            if os.path.isfile(os.path.join(self.folder, name)) and os.path.isfile(os.path.join(other_folder, name)):
                self.compare_tables(other_folder, name, families, exact, rtol)


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
        if args.zones:
            check.check_zones(args.zones)
        if args.column:
            check.check_column()
        if args.compare:
            check.compare(args.compare, args.rtol)
    for failure in check.failures:
        print(f"  {args.folder}: {failure}")
    sys.exit(1 if check.failures else 0)


if __name__ == "__main__":
    suite.run_tool("check_results.py", main)
