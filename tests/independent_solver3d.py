#!/usr/bin/python3
"""independent_solver3d.py: an independent NumPy implementation of the discrete dynamic
frictional contact problem in three dimensions (docs/design.md, "The discrete problem",
"Nodal contact", "Nodal laws", "Three dimensions"; Barboteu, Ouafik, Sofonea 2018), used
to cross-check the FreeFEM code (edp/solve.edp) on small 3D meshes.

WHAT IT SOLVES
  P1 tetrahedra, velocity v as unknown, backward Euler with k = T/N, u_n = u_{n-1} + k v_n,
  u_0 = 0, v_0 = the scene's initial_velocity (uniform, 0 on the Dirichlet components).
  For every step n and every w in V_h:
    (1/k) m(v_n - v_{n-1}, w) + a(v_n, w) + b(u_{n-1} + k v_n, w)
      + sum_i w_i [ (p(v_nu_i) + lambda_nu_i) w.n_i + lambda_tau_i . w_tau(x_i) ] = f_n(w)
  m = int rho v.w (consistent P1 mass), a = int muv div div + eta eps:eps,
  b = int lambda3 div div + E/(1+nu) eps:eps with lambda3 = E nu/((1+nu)(1-2nu)),
  f_n(w) = load h(t_n) int_{label 3} tau.w + int f0.w (tau the scene's unit `traction`,
  h(t) = t or the scene's `load_history`, f0 its `body_force`), p(r) = cnu max(r, 0).
  Only the linear damping is supported (`damping linear C`, C = cnu): a scene with
  `damping power` or `damping table` is refused (exit 2). `bound_profile` (g_i from the
  x of node i) is supported.
  Contact is nodal on the vertices of the label-1 boundary triangles: weight w_i = the
  sum of area/3 over its label-1 triangles, outward normal n_i = the normalized sum of
  area/3 times the outward unit normal of those triangles (outward: away from the fourth
  vertex of the triangle's tetrahedron). The frame (n, t1, t2), right-handed:
    no fixed axis   : t1 = the coordinate axis least aligned with n (the first within 1e-9 of the least |n_k|)
                      made orthogonal to n, t2 = n x t1; slots v.n, v.t1, v.t2 (a pair);
    one fixed axis e: n projected on the plane free of e (refused below half its length),
                      its frame by the rule above; one tangential slot (the interval
                      law), the frame's tangent off e: v.t2 where e = t1 (reported as
                      v_tau2, lambda_tau2), v.t1 where e = t2; for an e that is neither,
                      t2 = e, t1 = t2 x n and the slot v.t1;
    two fixed axes  : n = the free axis on the side of the mesh's normal (refused if
                      more than 60 degrees from it); the normal slot only;
    three           : no slot.
  Fixed axes come from the scene's `dirichlet LABEL x|y|z|xy|xz|yz|xyz` lines (LABEL a
  physical surface tag of the mesh's boundary triangles). Laws, per node:
    original: v_nu <= g, lambda_nu >= 0, lambda_nu (v_nu - g) = 0, p_nu = p(v_nu) + lambda_nu
    penalty : lambda_nu = max(v_nu - g, 0)/eps
    friction: |lambda_tau| <= s = mu p(v_nu), lambda_tau = s v_tau/|v_tau| where v_tau != 0
              (lambda_tau has the direction of v_tau; the force on the body is -w lambda_tau)
              on the disk of a pair, on the interval [-s, s] for one tangential slot.

HOW (independent of the FreeFEM code; written from docs/design.md only)
  * the files (the MSH 2.2 mesh, the scene, the run's tables and summary) are read with
    edp/runfiles.py; the problem is set up in tests/independent_model3d.py (the scene's
    keys, the matrices, the contact nodes' frames and slots), solved here; element
    matrices from the gradients
    of the barycentric coordinates (eps(phi_a e_i):eps(phi_b e_j) =
    (delta_ij g_a.g_b + g_aj g_bi)/2), vectorized over the tetrahedra, dense global
    matrices;
  * Dirichlet components are removed from the unknowns (no tgv);
  * each step is solved by a semismooth Newton method on the FULL, uncondensed system
    (free velocities, one lambda_nu per normal slot, one lambda_tau per tangential slot):
    the Fischer-Burmeister function for the normal complementarity of the original
    problem (evaluated as 2ab/(a + b + |(a, b)|) where a + b > 0, without cancellation),
    a max() row for the penalty problem, and lambda_tau = proj_disk(s)(lambda_tau +
    r v_tau) for friction (the interval for one slot), with its exact generalized
    Jacobian (I - P, P = (s/|y|)(I - e e') on a slip, and the slope of s through v_nu);
    rows are scaled by the node weight and r by the nodal stiffness
    1/(w_i c_j' S^-1 c_j); full Newton steps first, then (if needed) a restart with a
    backtracking line search on |F|^2; a step that still fails is tried again with r
    times 0.1, 10, 0.01, 100 (the solution does not depend on r; Newton may cycle between
    the stick and slip pieces of a disk for one r and not another). The disk's slip piece
    is not linear, so there is no exact piece solve: Newton is iterated until the
    original conditions hold to --tol and then while they improve (quadratic convergence
    reaches round-off within one or two more iterations);
  * the Newton systems: numpy.linalg.solve on the whole dense Jacobian (--linear dense,
    the default up to DENSE_LIMIT unknowns), or (--linear schur, larger meshes) v
    eliminated with S^-1 formed once, the system of the contact dofs and stresses solved,
    and two steps of iterative refinement: the same iterates to round-off, 5x faster on
    slab3d's 16x8x2 mesh;
  * the right-hand side M v_{n-1}/k - B u_{n-1} + f_n is evaluated, and u accumulated,
    in long double: on a thin body B u cancels by several digits (in double, the contact
    velocities of a rotated thin plate moved by 3e-9, against a run wholly in long
    double; the suite's were within 1e-11 of it);
  * a step is accepted only if it satisfies the ORIGINAL conditions, each relative to its
    natural scale, to --tol (default 1e-12): equilibrium, constraint, sign,
    complementarity or the penalty law, the friction cone, and per node either stick
    (|v_tau| = 0) or slip (|lambda_tau| = s and v_tau along lambda_tau, measured as the
    part of v_tau across or against lambda_tau: the change of velocity the law needs, not
    the angle, which round-off decides for a small slip), the smaller violation; a step
    that fails within --maxit (for each r) is reported and the program exits 4.
  Nothing of a FreeFEM run is read except, in --compare mode, its parameters (summary.txt,
  the header lines of contact.txt and fields.txt, scene.scene: the effective scene) and
  its mesh (mesh.msh); its results are read only to be compared with.

USAGE
  /usr/bin/python3 tests/independent_solver3d.py --mesh FILE.msh --scene FILE.scene
      [--problem original|penalty] [--T ..] [--dt ..] [--rho ..] [--E ..] [--nu ..]
      [--muv ..] [--eta ..] [--load ..] [--cnu ..] [--g ..] [--mu ..] [--eps ..]
      [--tol 1e-12] [--maxit 100] [--linear auto|dense|schur] [--verbose] --out DIR
    the parameters default to the scene's lines (`T 1`, ...); writes DIR/contact.txt
    (x y z v_nu v_tau v_tau2 p_nu lambda_nu lambda_tau lambda_tau2, the contact nodes in
    the mesh's order) and DIR/fields.txt (x y z u_x u_y u_z v_x v_y v_z, every node in the
    file's order), floats in full precision, '#' header lines (parameters, then the
    column names).
  /usr/bin/python3 tests/independent_solver3d.py --compare RUN_DIR [--rtol 1e-9] [--out DIR]
      [--tol 1e-12] [--maxit 100] [--linear auto|dense|schur]
    takes the parameters from RUN_DIR/summary.txt (checked against the header lines of
    contact.txt and fields.txt and the values of RUN_DIR/scene.scene), the scene's keys
    from RUN_DIR/scene.scene, the mesh from RUN_DIR/mesh.msh; solves; matches the rows by
    their coordinates (x, y, z); prints per column the max abs difference relative to the
    column's max abs value (contact.txt: v_nu v_tau v_tau2 p_nu lambda_nu lambda_tau
    lambda_tau2, and the weights and the frames n, t1, t2 where the node has the slots
    that use them; fields.txt: u_x u_y u_z v_x v_y v_z). A column is measured against at
    least FAMILY_FLOOR (1e-4) times the largest value of its family (the velocities, the
    stresses, u, v), and a frame component against 1: a column of round-off only
    (lambda_nu where no node reaches the bound, v_z of a plane-strain slab) is not divided
    by its own round-off; such a line says "(floor)". Exit 1 if any exceeds rtol.
  Exit status: 0 ok, 1 comparison failed, 2 bad usage/input (also for a law it does not
  support), 4 a step did not converge.
  Run time: 0.6-4 s on the small 3D runs (column3d, oblique-slide3d, slab3d 8x4x1), 5-15 s
  on slab3d and slab3d-thin at their full meshes (100 steps).
Only numpy is needed (with a long double wider than double for the extra precision above,
as on x86; elsewhere it runs in plain double).
"""
import argparse
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import numpy as np

import runfiles
from independent_model3d import InputError, Model, Scene, read_mesh

PARAM_KEYS = ["problem", "T", "dt", "rho", "E", "nu", "muv", "eta", "load", "cnu", "g", "mu", "eps"]
CONTACT_COLS = ["x", "y", "z", "v_nu", "v_tau", "v_tau2", "p_nu", "lambda_nu", "lambda_tau", "lambda_tau2",
                "g", "damped_response", "force_scale", "zone"]
FIELD_COLS = ["x", "y", "z", "u_x", "u_y", "u_z", "v_x", "v_y", "v_z"]
# --compare measures a column against its largest value, but at least FAMILY_FLOOR times the
# largest value of its family (the components of one quantity): a column that holds only
# round-off (lambda_nu where no node reaches the bound) is not divided by that round-off
FAMILIES = (("v_nu", "v_tau", "v_tau2", "g"), ("p_nu", "lambda_nu", "lambda_tau", "lambda_tau2", "damped_response", "force_scale"),
            ("u_x", "u_y", "u_z"), ("v_x", "v_y", "v_z"), ("zone",))
FAMILY_FLOOR = 1e-4
R_FACTORS = (1.0, 0.1, 10.0, 0.01, 100.0)    # the scales r of the attempts at a step


class ConvergenceError(Exception):
    pass


# ----------------------------------------------------------------------------- solver
class Problem(Model):
    """Model's discrete problem, solved step by step by a semismooth Newton on the full system."""

    def residual(self, x, rhs, jac=False):
        """F(x) of the semismooth system (contact rows times the node weight: forces) and,
        with jac, a generalized Jacobian."""
        p = self.prm
        nN, nT = self.nN, self.nT
        v, ln, lt = self.split(x)
        vc = v[self.cd]
        vnu, vtau = self.Cn @ vc, self.Ct @ vc
        cnu, mu, g = p["cnu"], p["mu"], self.gn
        pnu = cnu * np.maximum(vnu, 0.0) + ln
        Fv = self.S @ v - rhs
        Fv[self.cd] += self.Cn.T @ (self.wn * pnu) + self.Ct.T @ (self.wt * lt)
        if p["problem"] == "original":
            rn = self.rn * self.rfac
            a, b = ln, rn * (g - vnu)
            rho_ = np.sqrt(a * a + b * b)
            # a + b - |(a, b)|, without its cancellation where a + b > 0: 2ab/(a + b + |(a, b)|)
            # (else a constraint violation g - v_nu = b/r far below lambda_nu's round-off is lost)
            pos = a + b > 0
            Fn = self.wn * np.where(pos, 2.0 * a * b / np.where(pos, a + b + rho_, 1.0), a + b - rho_)
        else:
            Fn = self.wn * (ln - np.maximum(vnu - g, 0.0) / p["eps"])
        Ft = np.zeros(nT)
        if jac:
            # the Jacobian in blocks: J = [[S + E Kc E', E Bv], [Rv E', Rl]], E the
            # injection of the contact dofs cd into the free dofs
            nc = nN + nT
            Kc = self.Cn.T @ ((self.wn * cnu * (vnu > 0))[:, None] * self.Cn)
            Rv, Rl = np.zeros((nc, len(self.cd))), np.zeros((nc, nc))
            iN = np.arange(nN)
            if p["problem"] == "original":
                safe = rho_ > 0
                da = np.where(safe, 1.0 - a / np.where(safe, rho_, 1.0), 1.0 - 1.0 / np.sqrt(2.0))
                db = np.where(safe, 1.0 - b / np.where(safe, rho_, 1.0), 1.0 - 1.0 / np.sqrt(2.0))
                Rl[iN, iN] = self.wn * da
                Rv[:nN] = (self.wn * db * (-rn))[:, None] * self.Cn
            else:
                Rl[iN, iN] = self.wn
                Rv[:nN] = (-self.wn * (vnu > g) / p["eps"])[:, None] * self.Cn
        for (j, sl), r in zip(self.groups, self.rg):
            r = r * self.rfac
            w = self.wn[j]
            y = lt[sl] + r * vtau[sl]
            s = mu * cnu * max(vnu[j], 0.0)
            ds = mu * cnu * (vnu[j] > 0)
            ny = np.linalg.norm(y)
            m = len(sl)
            rowsT = nN + np.array(sl)
            if s > 0 and ny <= s:                  # stick: lambda = y, i.e. v_tau = 0
                Ft[sl] = -w * r * vtau[sl]
                if jac:
                    Rv[rowsT] = -w * r * self.Ct[sl]
            else:                                  # slip (or s = 0): lambda = s y/|y|
                e = y / ny if ny > 0 else np.zeros(m)
                Ft[sl] = w * (lt[sl] - s * e)
                if jac:
                    P = (s / ny) * (np.eye(m) - np.outer(e, e)) if ny > 0 else np.zeros((m, m))
                    Rl[np.ix_(rowsT, rowsT)] = w * (np.eye(m) - P)
                    Rv[rowsT] = -w * (r * P @ self.Ct[sl] + np.outer(e, ds * self.Cn[j]))
        F = np.concatenate([Fv, Fn, Ft])
        return (F, (Kc, Rv, Rl)) if jac else F

    def direction(self, F, blocks):
        """The Newton step dx: J dx = -F, J from its blocks (residual)."""
        Kc, Rv, Rl = blocks
        nf, cd = self.nf, self.cd
        nc, ncd = Rl.shape[0], len(cd)
        if self.linear == "dense":
            J = np.zeros((nf + nc, nf + nc))
            J[:nf, :nf] = self.S
            J[np.ix_(cd, cd)] += Kc
            J[cd, nf:] = self.Bv
            J[np.ix_(nf + np.arange(nc), cd)] = Rv
            J[nf:, nf:] = Rl
            try:
                return np.linalg.solve(J, -F)
            except np.linalg.LinAlgError:
                return np.linalg.lstsq(J, -F, rcond=None)[0]
        # dv = S^-1 (-Fv) - S^-1 E (Kc z + Bv dl), z = E' dv: the system of (z, dl)
        K = np.zeros((ncd + nc, ncd + nc))
        K[:ncd, :ncd] = np.eye(ncd) + self.G @ Kc
        K[:ncd, ncd:] = self.G @ self.Bv
        K[ncd:, :ncd] = Rv
        K[ncd:, ncd:] = Rl

        try:
            Kinv = np.linalg.inv(K)
        except np.linalg.LinAlgError:
            Kinv = np.linalg.pinv(K)

        def solve(b):
            y0 = self.Sinv @ b[:nf]
            sol = Kinv @ np.concatenate([y0[cd], b[nf:]])
            z, dl = sol[:ncd], sol[ncd:]
            return np.concatenate([y0 - self.Sinv_cd @ (Kc @ z + self.Bv @ dl), dl])

        def apply(dx):
            dv, dl = dx[:nf], dx[nf:]
            top = self.S @ dv
            top[cd] += Kc @ dv[cd] + self.Bv @ dl
            return np.concatenate([top, Rv @ dv[cd] + Rl @ dl])
        # S^-1 formed explicitly is less accurate than a factorization: two steps of
        # iterative refinement bring the step to the accuracy of the dense solve
        dx = solve(-F)
        for _ in range(2):
            dx += solve(-F - apply(dx))
        return dx

    def kkt_error(self, x, rhs):
        """Residuals of the original conditions, each relative to its natural scale."""
        p = self.prm
        v, ln, lt = self.split(x)
        vc = v[self.cd]
        vnu, vtau = self.Cn @ vc, self.Ct @ vc
        g = self.gn
        pnu = p["cnu"] * np.maximum(vnu, 0.0) + ln
        cf = np.zeros(self.nf)
        cf[self.cd] = self.Cn.T @ (self.wn * pnu) + self.Ct.T @ (self.wt * lt)
        Fv = self.S @ v - rhs + cf
        # round-off scale of the equilibrium rows: the size of the terms that cancel
        if not hasattr(self, "absS"):
            self.absS = np.abs(self.S)
        mag = self.absS @ np.abs(v) + np.abs(rhs) + np.abs(cf)
        if p["problem"] == "penalty":
            on = vnu > g
            mag[self.cd] += np.abs(self.Cn.T) @ (self.wn * on * (np.abs(vnu) + g) / p["eps"])
        err = {"equilibrium": np.abs(Fv).max() / max(mag.max(), 1e-300)}
        gmax = g.max()
        pscale = max(p["cnu"] * gmax, np.abs(pnu).max(), 1e-300)
        if p["problem"] == "original":
            err["constraint"] = (np.maximum(vnu - g, 0) / g).max()
            err["sign"] = np.maximum(-ln, 0).max() / pscale
            err["complementarity"] = (np.abs(ln * (vnu - g)) / g).max() / pscale
        else:
            err["penalty"] = np.abs(ln - np.maximum(vnu - g, 0) / p["eps"]).max() / pscale
        vscale = max(np.abs(v).max(), gmax)
        cone, law = 0.0, 0.0
        for j, sl in self.groups:
            s = p["mu"] * p["cnu"] * max(vnu[j], 0.0)
            lam, vt = lt[sl], vtau[sl]
            cone = max(cone, max(np.linalg.norm(lam) - s, 0.0) / pscale)
            # stick: v_tau = 0; slip: |lambda_tau| = s and v_tau along lambda_tau, measured as
            # the change of v_tau it needs (its part across lambda_tau or against it), not as
            # the angle, which round-off decides for a small slip
            nl = np.linalg.norm(lam)
            as_stick = np.linalg.norm(vt) / vscale
            along = np.dot(vt, lam) / nl if nl > 0 else 0.0
            across = np.linalg.norm(vt - along * lam / nl) if nl > 0 else 0.0
            as_slip = max((across + max(-along, 0.0)) / vscale, abs(nl - s) / pscale)
            law = max(law, min(as_stick, as_slip))
        err["cone"], err["friction_law"] = cone, law
        return max(err.values()), err

    def solve_step(self, x0, rhs, tol, maxit):
        """newton() with the scales r; if it fails, again from x0 with r times 0.1, 10,
        0.01, 100 (the solution does not depend on r, the path of Newton's iterates does:
        a semismooth Newton may cycle between the stick and slip pieces of a disk).
        Returns (x, iterations of all attempts, KKT error)."""
        errors, total = [], 0
        for factor in R_FACTORS:
            self.rfac = factor
            try:
                x, it, e = self.newton(x0, rhs, tol, maxit)
                return x, total + it, e
            except ConvergenceError as err:
                total += maxit
                errors.append("r x %g: %s" % (factor, err))
            finally:
                self.rfac = 1.0
        raise ConvergenceError("; ".join(errors))

    def newton(self, x0, rhs, tol, maxit):
        """Semismooth Newton on the full system: full steps for the first maxit//4
        iterations; if that has not converged, restart from x0 with a backtracking line
        search on |F|^2. Once the original conditions hold to tol, Newton goes on while
        they improve (by half at least, up to 3 more iterations) and the best is kept."""
        x = x0.copy()
        F, J = self.residual(x, rhs, jac=True)
        fscale = max(np.abs(rhs).max(), 1e-300)
        hist = []
        pure = max(maxit // 4, 1)
        best = None
        for it in range(1, maxit + 1):
            if it == pure + 1:
                x = x0.copy()
                F, J = self.residual(x, rhs, jac=True)
            dx = self.direction(F, J)
            if it > pure:
                phi0 = np.dot(F, F)
                t = 1.0
                while True:
                    xn = x + t * dx
                    Fn = self.residual(xn, rhs)
                    if np.dot(Fn, Fn) < (1 - 1e-4 * t) * phi0 or t < 1e-10 or phi0 < (1e-16 * fscale) ** 2:
                        break
                    t *= 0.5
            else:
                xn = x + dx
            x = xn
            F, J = self.residual(x, rhs, jac=True)
            e, _ = self.kkt_error(x, rhs)
            hist.append(e)
            if not np.isfinite(e):
                continue
            if best is not None:
                if e < 0.5 * best[1] and it - best[2] <= 3:
                    best = (x.copy(), e, best[2], it)
                    continue
                return best[0], best[3], best[1]
            if e < tol:
                best = (x.copy(), e, it, it)      # (x, its error, first iteration below tol, its iteration)
        if best is not None:
            return best[0], best[3], best[1]
        raise ConvergenceError("no convergence after %d iterations; last KKT errors: %s"
                               % (maxit, ", ".join("%.2e" % h for h in hist[-3:])))

    def run(self, tol=1e-12, maxit=100, verbose=False):
        """The N steps. The right-hand side M v_{n-1}/k - B u_{n-1} + f_n is evaluated, and u
        accumulated, in long double (80 bits on x86): on a thin body the terms of B u cancel
        by several digits, and in double the rotated thin plate lost 3e-9 of its contact
        velocities to that (against a run done wholly in long double)."""
        p = self.prm
        nd = 3 * len(self.xyz)
        k = self.k
        LD = np.longdouble
        Mf, Bf = self.Mf.astype(LD), self.Bf.astype(LD)
        u = np.zeros(nd, dtype=LD)
        v0 = np.tile(self.scene.initial_velocity, len(self.xyz))
        v0[self.fixed] = 0.0
        vold = v0.astype(LD)
        x = np.concatenate([v0[self.free], np.zeros(self.nN + self.nT)])
        self.iterations, self.worst = [], 0.0
        for n in range(1, self.N + 1):
            t = n * k
            rhs = (Mf @ vold / LD(k) - Bf @ u + LD(p["load"] * self.scene.h(t)) * self.tracf.astype(LD)
                   + self.bodyf.astype(LD)).astype(float)
            try:
                x, it, e = self.solve_step(x, rhs, tol, maxit)
            except ConvergenceError as err:
                raise ConvergenceError("step %d (t = %g): %s" % (n, t, err))
            self.iterations.append(it)
            self.worst = max(self.worst, e)
            v = np.zeros(nd)
            v[self.free] = x[:self.nf]
            vold = v.astype(LD)
            u = u + LD(k) * vold
            if verbose:
                _, errs = self.kkt_error(x, rhs)
                print("step %3d t %.4f iterations %2d kkt %.2e (%s)" % (
                    n, t, it, e, " ".join("%s %.1e" % kv for kv in errs.items())))
        self.u, self.v, self.x = u.astype(float), v, x
        return self


def write_solution(out, prm, contact_rows, field_rows):
    """OUT/contact.txt and OUT/fields.txt, in the format of the suite's tables."""
    comments = ["%s %s" % (kk, prm[kk]) for kk in PARAM_KEYS]
    runfiles.write_table(os.path.join(out, "contact.txt"), comments, CONTACT_COLS, contact_rows)
    runfiles.write_table(os.path.join(out, "fields.txt"), comments, FIELD_COLS, field_rows)


def solve(mesh_path, prm, scene, tol, maxit, linear="auto", verbose=False):
    mesh = read_mesh(mesh_path)
    t0 = time.time()
    pb = Problem(mesh, prm, scene)
    pb.set_linear(linear)
    pb.run(tol, maxit, verbose)
    return pb, time.time() - t0


# ----------------------------------------------------------------------------- compare
def to_params(d, where):
    prm = {}
    for kk in PARAM_KEYS:
        if kk not in d:
            raise InputError("%s: parameter '%s' missing" % (where, kk))
        prm[kk] = d[kk] if kk == "problem" else d.real(kk)
    return prm


def match_rows(mine, theirs, what):
    """The row of `mine` (n x 3 coordinates) of each row of `theirs`; InputError when a
    point has no counterpart within 1e-12 of the extent, or the counts differ."""
    if len(mine) != len(theirs):
        raise InputError("%s: %d rows here, %d in the run" % (what, len(mine), len(theirs)))
    scale = max(np.abs(mine).max(), 1e-300)
    order = np.empty(len(theirs), dtype=int)
    for start in range(0, len(theirs), 256):
        block = theirs[start:start + 256]
        d = np.abs(block[:, None, :] - mine[None, :, :]).max(axis=2)
        order[start:start + 256] = d.argmin(axis=1)
        if d.min(axis=1).max() > 1e-12 * scale:
            raise InputError("%s: a point of the run has no node here (%.3g)" % (what, d.min(axis=1).max()))
    if len(np.unique(order)) != len(order):
        raise InputError("%s: points of the run matched twice" % what)
    return order


def compare(run_dir, rtol, tol, maxit, out, linear="auto"):
    summ = runfiles.read_summary(os.path.join(run_dir, "summary.txt"))
    if summ["dimension"] != "3":
        raise InputError("%s is a %sD run: use tests/independent_solver.py" % (run_dir, summ["dimension"]))
    theirs_c = runfiles.read_table(os.path.join(run_dir, "contact.txt"))
    theirs_f = runfiles.read_table(os.path.join(run_dir, "fields.txt"))
    prm = to_params(summ, "summary.txt")
    for table, name in ((theirs_c, "contact.txt"), (theirs_f, "fields.txt")):
        other = to_params(table.params, name + " header")
        for kk in PARAM_KEYS:
            if prm[kk] != other[kk]:
                raise InputError("parameter %s differs: summary.txt %s, %s %s" % (kk, prm[kk], name, other[kk]))
    if prm["problem"] not in ("original", "penalty"):
        raise InputError("unsupported problem %s" % prm["problem"])
    scene = Scene(os.path.join(run_dir, "scene.scene"))
    for kk in PARAM_KEYS:              # the effective scene holds the values the run used
        if kk in scene.values:
            val = scene.values[kk] if kk == "problem" else float(scene.values[kk])
            if val != prm[kk]:
                raise InputError("parameter %s differs: summary.txt %s, scene.scene %s" % (kk, prm[kk], val))
    if scene.damping is not None and float(scene.damping[1][0]) != prm["cnu"]:
        raise InputError("cnu differs: summary.txt %s, scene.scene damping linear %s" % (prm["cnu"], scene.damping[1][0]))
    print("parameters: " + " ".join("%s=%s" % (kk, prm[kk]) for kk in PARAM_KEYS))
    print("scene: traction %s body_force %s initial_velocity %s dirichlet %s%s%s" % (
        scene.traction.tolist(), scene.body_force.tolist(), scene.initial_velocity.tolist(),
        {k: "".join("xyz"[a] for a in v) for k, v in scene.dirichlet.items()},
        " load_history" if scene.load_history is not None else "",
        " bound_profile" if scene.bound_profile is not None else ""))
    mesh = os.path.join(run_dir, "mesh.msh")
    print("mesh: %s" % mesh)
    pb, elapsed = solve(mesh, prm, scene, tol, maxit, linear)
    print("independent solve: %d steps, %d dofs (%d free), %d contact nodes (%d normal, %d tangential slots), "
          "Newton iterations total %d max %d (%s solves), worst KKT error %.2e, %.3f s"
          % (pb.N, pb.M.shape[0], pb.nf, len(pb.cnodes), pb.nN, pb.nT, sum(pb.iterations),
             max(pb.iterations), pb.linear, pb.worst, elapsed))
    mine_c, mine_f = pb.contact_table(), pb.fields_table()
    if out:
        write_solution(out, prm, mine_c, mine_f)
    oc = match_rows(mine_c[:, :3], np.column_stack([theirs_c["x"], theirs_c["y"], theirs_c["z"]]), "contact.txt")
    of = match_rows(mine_f[:, :3], np.column_stack([theirs_f["x"], theirs_f["y"], theirs_f["z"]]), "fields.txt")
    mine_c, mine_f = mine_c[oc], mine_f[of]
    worst = 0.0
    lines = []

    def check(fname, name, a, b, mask=None, family=0.0, unit=False):
        nonlocal worst
        if mask is not None:
            a, b = a[mask], b[mask]
        diff = np.abs(a - b).max() if len(a) else 0.0
        own = np.abs(a).max() if len(a) else 0.0
        scale = max(own, 1.0 if unit else FAMILY_FLOOR * family, 1e-300)   # frames: unit vectors
        rel = diff / scale if diff > 0 else 0.0
        worst = max(worst, rel)
        lines.append("%-12s %-11s rel %.3e  max|diff| %.3e  scale %.3e%s  %s"
                     % (fname, name, rel, diff, scale, " (floor)" if scale > own else "", "ok" if rel <= rtol else "EXCEEDS rtol"))
    for fname, theirs, mine, names in (("contact.txt", theirs_c, mine_c, CONTACT_COLS),
                                       ("fields.txt", theirs_f, mine_f, FIELD_COLS)):
        for family in FAMILIES:
            cols = [names.index(name) for name in family if name in names]
            if not cols:
                continue
            big = max(np.abs(theirs[names[j]]).max() for j in cols)
            for j in cols:
                check(fname, names[j], theirs[names[j]], mine[:, j], family=big)
    # the discrete problem's data: weights and frames (t1 where the node has a tangential
    # slot, t2 where it has two or one fixed axis; n where it has a slot)
    check("contact.txt", "weight", theirs_c["weight"], pb.weight[oc])
    nt = pb.ntang[oc]
    for d, vec, mask in ((0, "n", nt >= 0), (1, "t1", nt >= 1), (2, "t2", nt >= 1)):
        for a, comp in enumerate("xyz"):
            check("contact.txt", "%s_%s" % (vec, comp), theirs_c["%s_%s" % (vec, comp)], pb.frames[oc, d, a], mask, unit=True)
    print("\n".join(lines))
    print("worst relative difference %.3e (rtol %g): %s" % (worst, rtol, "PASS" if worst <= rtol else "FAIL"))
    return 0 if worst <= rtol else 1


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--compare", metavar="RUN_DIR")
    ap.add_argument("--mesh")
    ap.add_argument("--scene")
    ap.add_argument("--rtol", type=float, default=1e-9)
    ap.add_argument("--problem", choices=["original", "penalty"])
    for kk in PARAM_KEYS[1:]:
        ap.add_argument("--" + kk, type=float)
    ap.add_argument("--tol", type=float, default=1e-12)
    ap.add_argument("--maxit", type=int, default=100)
    ap.add_argument("--linear", choices=["auto", "dense", "schur"], default="auto")
    ap.add_argument("--verbose", action="store_true")
    ap.add_argument("--out")
    a = ap.parse_args(argv)
    try:
        if a.compare:
            return compare(a.compare, a.rtol, a.tol, a.maxit, a.out, a.linear)
        if not a.mesh or not a.scene or not a.out:
            ap.error("--mesh, --scene and --out are required (or --compare RUN_DIR)")
        scene = Scene(a.scene)
        prm = {}
        for kk in PARAM_KEYS:
            given = getattr(a, kk)
            if given is None:
                if kk == "problem":
                    given = scene.values.get("problem", "original")
                elif kk == "cnu" and scene.damping is not None:
                    given = float(scene.damping[1][0])
                elif kk == "g" and scene.bound_profile is not None:
                    given = float(scene.bound_profile[1::2].max())     # not used: g_i from the profile
                elif kk in scene.values:
                    given = float(scene.values[kk])
                else:
                    raise InputError("no value of %s: give --%s or a '%s VALUE' scene line" % (kk, kk, kk))
            prm[kk] = given
        for kk in ("T", "dt", "rho", "E", "g", "eps"):
            if not prm[kk] > 0:
                raise InputError("%s must be > 0" % kk)
        pb, elapsed = solve(a.mesh, prm, scene, a.tol, a.maxit, a.linear, a.verbose)
        write_solution(a.out, prm, pb.contact_table(), pb.fields_table())
        print("%d steps, Newton iterations total %d max %d, worst KKT error %.2e, %.3f s; results in %s"
              % (pb.N, sum(pb.iterations), max(pb.iterations), pb.worst, elapsed, a.out))
        return 0
    except ConvergenceError as error:
        print("independent_solver3d: %s" % error, file=sys.stderr)
        return 4


if __name__ == "__main__":
    sys.exit(runfiles.run_tool("independent_solver3d", lambda: main(sys.argv[1:]), code=2))
