#!/usr/bin/python3
"""independent_solver.py: an independent NumPy implementation of the discrete dynamic
frictional contact problem (docs/design.md, "The discrete problem"; Barboteu, Ouafik,
Sofonea 2018), used to cross-check the FreeFEM code (edp/solve.edp) on small meshes.

WHAT IT SOLVES
  Plane stress or plane strain (--plane), P1 triangles, velocity v as unknown, backward Euler with k = T/N,
  u_n = u_{n-1} + k v_n, u0 = v0 = 0. For every step n and every w in V_h:
    (1/k) m(v_n - v_{n-1}, w) + a(v_n, w) + b(u_{n-1} + k v_n, w)
      + sum_i w_i [ (p(v_nu_i) + lambda_nu_i) w_nu(x_i) + lambda_tau_i w_tau(x_i) ] = f_n(w)
  m = int rho v.w (consistent P1 mass), a = int muv div div + eta eps:eps,
  b = int lambda div div + E/(1+nu) eps:eps (lambda = E nu/(1-nu^2) in plane stress,
  E nu/((1+nu)(1-2nu)) in plane strain), f_n(w) = int_{GammaTraction} (0,-load t_n).w,
  p(r) = cnu max(r,0). Contact is nodal on the GammaContact nodes, weight w_i = half the
  length of the adjacent GammaContact edges, outward normal (0,-1): v_nu = -v_y, v_tau = v_x.
    original: v_nu <= g, lambda_nu >= 0, lambda_nu (v_nu - g) = 0
    penalty : lambda_nu = max(v_nu - g, 0)/eps
    friction: |lambda_tau| <= mu p(v_nu), lambda_tau = mu p(v_nu) v_tau/|v_tau| if v_tau != 0
  A Dirichlet-fixed component carries no contact unknown. Scenes (fixed components):
    paper : GammaLeft x and y, GammaRight x;   column: GammaLeft x.
  The boundary labels are named as in edp/lib/forms.idp, which gives their numbers.

HOW (independent of the FreeFEM code; written from docs/design.md and the paper only)
  * the files (the MSH 2.2 mesh, the tables of a run, the label numbers) are read with
    edp/runfiles.py; own element matrices (gradients of barycentric coordinates, Voigt
    form with engineering shear), dense global matrices;
  * Dirichlet components are removed from the unknowns (no penalty/tgv);
  * each step is solved by a semismooth Newton method on the FULL, uncondensed system
    (free velocities + one lambda_nu per normal slot + one lambda_tau per tangential
    slot), with the Fischer-Burmeister function for the normal complementarity of the
    original problem, a max() equation for the penalty problem and the projection
    (Alart-Curnier) equation for friction, scaled by the nodal stiffness
    1/(w_i (S^-1)_jj); generalized Jacobians are formed explicitly and solved with
    numpy.linalg.solve; full steps first, then (if needed) a restart with a
    backtracking line search on |F|^2;
  * the problem is piecewise linear, so once the Newton iterate is close (1e-6), the
    piece it selects (active/inactive normal, damping on/off, zero bound/stick/slip+/-)
    is solved exactly as one linear saddle-point system; multipliers that vanish on
    that piece are exactly 0;
  * the result is accepted only if it satisfies the ORIGINAL conditions (equilibrium,
    constraint, sign, complementarity, friction cone, and per node either stick
    (v_tau = 0) or slip (lambda_tau = mu p(v_nu) sign v_tau), the smaller violation),
    each relative to its natural scale, to --tol (default 1e-12); otherwise Newton
    goes on; a step that fails within --maxit is reported and the program exits 4.
  Nothing of a FreeFEM run is read except, in --compare mode, its parameters
  (summary.txt, contact.txt header) and its mesh (mesh.msh); its results are read only
  to be compared with.

USAGE
  /usr/bin/python3 tests/independent_solver.py --mesh FILE.msh [--scene paper|column]
      [--problem original|penalty] [--plane stress|strain] [--T 1] [--dt 0.05] [--rho 2e-6] [--E 100] [--nu 0.2]
      [--muv 0.25] [--eta 0.5] [--load 10] [--cnu 50] [--g 0.05] [--mu 0.4] [--eps 2e-5]
      [--tol 1e-12] [--maxit 100] --out DIR
    writes DIR/contact.txt (x v_nu v_tau p_nu lambda_nu lambda_tau, GammaContact nodes sorted
    by x) and DIR/fields.txt (x y u_x u_y v_x v_y, all nodes in the file's node order),
    floats in full precision, '#' header lines (parameters, then the column names).
  /usr/bin/python3 tests/independent_solver.py --compare FREEFEM_RUN_DIR [--rtol 1e-9]
      [--out DIR]
    takes the parameters from FREEFEM_RUN_DIR/summary.txt and the contact.txt header,
    the mesh from FREEFEM_RUN_DIR/mesh.msh, solves, and prints per column the max abs
    difference relative to the column's max abs value (contact.txt: v_nu v_tau p_nu
    lambda_nu lambda_tau and what the law gives each node, g damped_response force_scale
    zone, derived here on its own; fields.txt: u_x u_y v_x v_y). Exit 1 if any exceeds rtol.
  Exit status: 0 ok, 1 comparison failed, 2 bad usage/input, 4 a step did not converge.
Only numpy is needed.
"""
import argparse
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import numpy as np

import runfiles

SCENES = {
    # boundary label (its name in edp/lib/forms.idp) -> fixed components (0 = x, 1 = y)
    "paper": {"GammaLeft": (0, 1), "GammaRight": (0,)},
    "column": {"GammaLeft": (0,)},
}
TRACTION_DIRECTION = (0.0, -1.0)     # f2 = load * t * (0, -1) on GammaTraction, both scenes
DEFAULTS = dict(scene="paper", problem="original", plane="stress", T=1.0, dt=0.05, rho=2e-6, E=100.0,
                nu=0.2, muv=0.25, eta=0.5, load=10.0, cnu=50.0, g=0.05, mu=0.4, eps=2e-5)
PARAM_KEYS = ["scene", "problem", "plane", "T", "dt", "rho", "E", "nu", "muv", "eta", "load",
              "cnu", "g", "mu", "eps"]


InputError = runfiles.InputError


class ConvergenceError(Exception):
    pass


# ----------------------------------------------------------------------------- assembly
def assemble(xy, tri, prm):
    """Dense global mass M, viscosity A, elasticity B; dof 2*node + component."""
    nd = 2 * len(xy)
    M, A, B = np.zeros((nd, nd)), np.zeros((nd, nd)), np.zeros((nd, nd))

    def voigt(lam, g):
        # coefficient lam on div*div, g on eps:eps = e11 f11 + e22 f22 + 2 e12 f12;
        # with engineering shear gamma = 2 e12: 2 e12 f12 = gamma_u gamma_w / 2
        return np.array([[lam + g, lam, 0.0], [lam, lam + g, 0.0], [0.0, 0.0, g / 2.0]])

    E, nu = prm["E"], prm["nu"]
    # plane stress (the paper's, sigma_zz = 0) or plane strain (eps_zz = 0): B's lambda
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)) if prm["plane"] == "strain" else E * nu / (1.0 - nu * nu)
    Dela = voigt(lam, E / (1.0 + nu))
    Dvis = voigt(prm["muv"], prm["eta"])
    mloc = np.array([[2.0, 1.0, 1.0], [1.0, 2.0, 1.0], [1.0, 1.0, 2.0]]) / 12.0
    used = np.zeros(len(xy), dtype=bool)
    for t in tri:
        used[t] = True
        P = xy[t]
        J = np.array([P[1] - P[0], P[2] - P[0]]).T          # columns: edge vectors
        det = np.linalg.det(J)
        area = 0.5 * abs(det)
        if area <= 0:
            raise InputError("degenerate triangle %s" % t)
        # gradients of barycentric coordinates
        Jinv = np.linalg.inv(J)                               # rows: grad of ref coords
        g1, g2 = Jinv[0], Jinv[1]
        grads = np.array([-g1 - g2, g1, g2])                  # 3 x 2
        Bm = np.zeros((3, 6))
        for a in range(3):
            Bm[0, 2 * a] = grads[a, 0]
            Bm[1, 2 * a + 1] = grads[a, 1]
            Bm[2, 2 * a] = grads[a, 1]
            Bm[2, 2 * a + 1] = grads[a, 0]
        dofs = np.array([[2 * v, 2 * v + 1] for v in t]).ravel()
        ix = np.ix_(dofs, dofs)
        B[ix] += area * Bm.T @ Dela @ Bm
        A[ix] += area * Bm.T @ Dvis @ Bm
        Ml = np.zeros((6, 6))
        Ml[0::2, 0::2] = mloc
        Ml[1::2, 1::2] = mloc
        M[ix] += prm["rho"] * area * Ml
    if not used.all():
        raise InputError("%d mesh node(s) belong to no triangle" % (~used).sum())
    return M, A, B


def boundary_data(xy, edges, elab, scene):
    labels = runfiles.labels()
    contact, traction = labels["GammaContact"], labels["GammaTraction"]
    nn = len(xy)
    fixed = np.zeros(2 * nn, dtype=bool)
    for name, comps in SCENES[scene].items():
        for e in edges[elab == labels[name]]:
            for v in e:
                for c in comps:
                    fixed[2 * v + c] = True
    weight = np.zeros(nn)
    trac = np.zeros(2 * nn)
    for e, lab in zip(edges, elab):
        L = np.linalg.norm(xy[e[1]] - xy[e[0]])
        if lab == contact:
            weight[e] += 0.5 * L
        elif lab == traction:
            for v in e:               # consistent P1 integral of a constant: L/2 per node
                trac[2 * v] += 0.5 * L * TRACTION_DIRECTION[0]
                trac[2 * v + 1] += 0.5 * L * TRACTION_DIRECTION[1]
    for name, lab in labels.items():
        if not (elab == lab).any():
            raise InputError("mesh has no boundary label %d (%s)" % (lab, name))
    cnodes = np.unique(edges[elab == contact].ravel())
    cnodes = cnodes[np.lexsort((xy[cnodes, 1], xy[cnodes, 0]))]   # sorted by x
    return fixed, weight, trac, cnodes


# ----------------------------------------------------------------------------- solver
class Problem:
    def __init__(self, xy, tri, edges, elab, prm):
        self.prm = prm
        self.xy = xy
        N = int(round(prm["T"] / prm["dt"]))
        if N < 1 or abs(N * prm["dt"] - prm["T"]) > 1e-9 * prm["T"]:
            raise InputError("dt does not divide T")
        self.N, self.k = N, prm["T"] / N
        self.M, self.A, self.B = assemble(xy, tri, prm)
        self.fixed, weight, self.trac, self.cnodes = boundary_data(xy, edges, elab, prm["scene"])
        nd = 2 * len(xy)
        self.free = np.flatnonzero(~self.fixed)
        nf = len(self.free)
        pos = -np.ones(nd, dtype=int)
        pos[self.free] = np.arange(nf)
        # normal slots: contact nodes whose y component is free; tangential: x free
        self.nslot = [v for v in self.cnodes if pos[2 * v + 1] >= 0]
        self.tslot = [v for v in self.cnodes if pos[2 * v] >= 0]
        # Cn v_free = v_nu at normal slots (= -v_y); Ct v_free = v_tau (= v_x)
        self.Cn = np.zeros((len(self.nslot), nf))
        self.Ct = np.zeros((len(self.tslot), nf))
        for i, v in enumerate(self.nslot):
            self.Cn[i, pos[2 * v + 1]] = -1.0
        for i, v in enumerate(self.tslot):
            self.Ct[i, pos[2 * v]] = 1.0
        self.wn = weight[self.nslot]
        self.wt = weight[self.tslot]
        # tangential slot -> index of its node's normal slot (or -1: v_nu fixed at 0)
        nidx = {v: i for i, v in enumerate(self.nslot)}
        self.t2n = np.array([nidx.get(v, -1) for v in self.tslot], dtype=int)
        k = self.k
        S = self.M / k + self.A + k * self.B
        ff = np.ix_(self.free, self.free)
        self.S = S[ff]
        self.Mf, self.Bf = self.M[self.free], self.B[self.free]      # rows of free dofs
        self.tracf = self.trac[self.free]
        # scale of the complementarity/projection equations per slot (any r > 0 gives the
        # same solution): the inverse nodal compliance, 1/(w_i (S^-1)_jj), i.e. the
        # contact stress that produces a unit velocity at that node
        dSinv = np.diag(np.linalg.inv(self.S))
        self.cn = 1.0 / (dSinv[pos[[2 * v + 1 for v in self.nslot]]] * np.maximum(self.wn, 1e-300))
        self.ct = 1.0 / (dSinv[pos[[2 * v for v in self.tslot]]] * np.maximum(self.wt, 1e-300))
        self.nf = nf

    # p(r) and the friction bound s = mu p(v_nu) per tangential slot
    def bound(self, vnu):
        p = self.prm
        vn_t = np.where(self.t2n >= 0, vnu[self.t2n] if len(vnu) else 0.0, 0.0)
        return p["mu"] * p["cnu"] * np.maximum(vn_t, 0.0), vn_t

    def residual(self, x, rhs, jac=False):
        """Residual F(x) of the semismooth system and (optionally) a generalized Jacobian.
        Contact rows are multiplied by the node weight so that all rows are forces."""
        p = self.prm
        nf, nN, nT = self.nf, len(self.nslot), len(self.tslot)
        v, ln, lt = x[:nf], x[nf:nf + nN], x[nf + nN:]
        vnu, vtau = self.Cn @ v, self.Ct @ v
        cnu, g, mu = p["cnu"], p["g"], p["mu"]
        Hn = (vnu > 0).astype(float)
        pnu = cnu * np.maximum(vnu, 0.0) + ln
        Fv = self.S @ v - rhs + self.Cn.T @ (self.wn * pnu) + self.Ct.T @ (self.wt * lt)
        # normal rows
        if p["problem"] == "original":
            a, b = ln, self.cn * (g - vnu)
            rho_ = np.sqrt(a * a + b * b)
            Fn = self.wn * (a + b - rho_)
        else:
            Fn = self.wn * (ln - np.maximum(vnu - g, 0.0) / p["eps"])
        # friction rows: lt = proj_[-s,s](lt + r vtau)
        s, vn_t = self.bound(vnu)
        z = lt + self.ct * vtau
        proj = np.clip(z, -s, s)
        Ft = self.wt * (lt - proj)
        F = np.concatenate([Fv, Fn, Ft])
        if not jac:
            return F
        n = nf + nN + nT
        J = np.zeros((n, n))
        J[:nf, :nf] = self.S + self.Cn.T @ ((self.wn * cnu * Hn)[:, None] * self.Cn)
        J[:nf, nf:nf + nN] = self.Cn.T * self.wn
        J[:nf, nf + nN:] = self.Ct.T * self.wt
        iN = np.arange(nf, nf + nN)
        if p["problem"] == "original":
            safe = rho_ > 0
            da = np.where(safe, 1.0 - a / np.where(safe, rho_, 1.0), 1.0 - 1.0 / np.sqrt(2.0))
            db = np.where(safe, 1.0 - b / np.where(safe, rho_, 1.0), 1.0 - 1.0 / np.sqrt(2.0))
            J[iN, iN] = self.wn * da
            J[nf:nf + nN, :nf] = (self.wn * db * (-self.cn))[:, None] * self.Cn
        else:
            J[iN, iN] = self.wn
            J[nf:nf + nN, :nf] = (-self.wn * (vnu > g) / p["eps"])[:, None] * self.Cn
        iT = np.arange(nf + nN, n)
        inside = np.abs(z) < s              # stick: residual = -r vtau
        up = (~inside) & (z >= 0)           # slip +: residual = lt - s; else slip -: lt + s
        J[iT, iT] = self.wt * np.where(inside, 0.0, 1.0)
        rowsT = np.zeros((nT, nf))
        rowsT -= (self.wt * np.where(inside, self.ct, 0.0))[:, None] * self.Ct
        ds = mu * cnu * (vn_t > 0)          # d s / d vnu
        for i in range(nT):
            j = self.t2n[i]
            if j >= 0 and not inside[i]:
                sgn = -1.0 if up[i] else 1.0   # d(-s)/dvnu for up, d(+s)/dvnu for dn
                rowsT[i] += self.wt[i] * sgn * ds[i] * self.Cn[j]
        J[nf + nN:, :nf] = rowsT
        return F, J

    def kkt_error(self, x, rhs):
        """Residuals of the original conditions, each relative to its natural scale."""
        p = self.prm
        nf, nN = self.nf, len(self.nslot)
        v, ln, lt = x[:nf], x[nf:nf + nN], x[nf + nN:]
        vnu, vtau = self.Cn @ v, self.Ct @ v
        pnu = p["cnu"] * np.maximum(vnu, 0.0) + ln
        cf = self.Cn.T @ (self.wn * pnu) + self.Ct.T @ (self.wt * lt)
        Sv = self.S @ v
        Fv = Sv - rhs + cf
        # round-off scale of the equilibrium rows: the size of the terms that cancel
        # (|S||v| componentwise; for the penalty, lambda_nu = v_nu/eps - g/eps)
        mag = np.abs(self.S) @ np.abs(v) + np.abs(rhs) + np.abs(cf)
        if p["problem"] == "penalty" and nN:
            on = vnu > p["g"]
            mag = mag + np.abs(self.Cn.T) @ (self.wn * on * (np.abs(vnu) + p["g"]) / p["eps"])
        fscale = max(mag.max(), 1e-300)
        err = {"equilibrium": np.abs(Fv).max() / fscale}
        g = p["g"]
        pscale = max(p["cnu"] * g, np.abs(pnu).max() if nN else 0.0, 1e-300)
        if nN and p["problem"] == "original":
            err["constraint"] = np.maximum(vnu - g, 0).max() / g
            err["sign"] = np.maximum(-ln, 0).max() / pscale
            err["complementarity"] = np.abs(ln * (vnu - g)).max() / (pscale * g)
        elif nN:
            err["penalty"] = np.abs(ln - np.maximum(vnu - g, 0) / p["eps"]).max() / pscale
        if len(lt):
            s, _ = self.bound(vnu)
            err["cone"] = np.maximum(np.abs(lt) - s, 0).max() / pscale
            # friction law per node: either stick (v_tau = 0) or slip (lambda_tau = s
            # sign(v_tau)); the error is the smaller of the two violations
            vscale = max(np.abs(v).max(), g)
            as_stick = np.abs(vtau) / vscale
            as_slip = np.abs(lt - s * np.sign(vtau)) / pscale
            err["friction_law"] = np.minimum(as_stick, as_slip).max()
        return max(err.values()), err

    def branch_solve(self, x, rhs):
        """Exact solve on the branch (piece) of the piecewise-linear system selected by x:
        per normal slot active (v_nu = g) or not (lambda_nu = 0), penalty on or off,
        damping on or off; per tangential slot zero bound (lambda_tau = 0), stick
        (v_tau = 0) or slip (lambda_tau = +-mu cnu v_nu). Multipliers that vanish on the
        branch are set to exactly zero. Returns the new x."""
        p = self.prm
        nf, nN, nT = self.nf, len(self.nslot), len(self.tslot)
        v, ln, lt = x[:nf], x[nf:nf + nN], x[nf + nN:]
        vnu, vtau = self.Cn @ v, self.Ct @ v
        cnu, g, mu = p["cnu"], p["g"], p["mu"]
        Hn = vnu > 0
        K = self.S + self.Cn.T @ ((self.wn * cnu * Hn)[:, None] * self.Cn)
        b = rhs.copy()
        if p["problem"] == "original":
            act = np.flatnonzero(ln + self.cn * (vnu - g) > 0)
        else:
            act = np.zeros(0, dtype=int)
            Hg = vnu > g               # lambda_nu = (v_nu - g)/eps on this branch
            K = K + self.Cn.T @ ((self.wn * Hg / p["eps"])[:, None] * self.Cn)
            b = b + self.Cn.T @ (self.wn * Hg * g / p["eps"])
        s, vn_t = self.bound(vnu)
        z = lt + self.ct * vtau
        zero = s <= 0
        stick = (~zero) & (np.abs(z) < s)
        slip = (~zero) & (~stick)
        sgn = np.sign(z)
        for i in np.flatnonzero(slip):   # lambda_tau = sgn mu cnu v_nu(node), v_nu > 0 here
            j = self.t2n[i]
            K = K + np.outer(self.Ct[i], self.wt[i] * sgn[i] * mu * cnu * self.Cn[j])
        st = np.flatnonzero(stick)
        na, ns = len(act), len(st)
        n = nf + na + ns
        Mx = np.zeros((n, n))
        Mx[:nf, :nf] = K
        Mx[:nf, nf:nf + na] = (self.Cn[act] * self.wn[act][:, None]).T
        Mx[nf:nf + na, :nf] = self.Cn[act]
        Mx[:nf, nf + na:] = (self.Ct[st] * self.wt[st][:, None]).T
        Mx[nf + na:, :nf] = self.Ct[st]
        r = np.concatenate([b, np.full(na, g), np.zeros(ns)])
        y = np.linalg.solve(Mx, r)
        vn = y[:nf]
        vnu_new = self.Cn @ vn
        ln_new = np.zeros(nN)
        if p["problem"] == "original":
            ln_new[act] = y[nf:nf + na]
        else:
            ln_new[Hg] = (vnu_new[Hg] - g) / p["eps"]
        lt_new = np.zeros(nT)
        lt_new[st] = y[nf + na:]
        for i in np.flatnonzero(slip):
            lt_new[i] = sgn[i] * mu * cnu * vnu_new[self.t2n[i]]
        return np.concatenate([vn, ln_new, lt_new])

    def solve_step(self, x0, rhs, tol, maxit):
        """Semismooth Newton on the full system: full steps for the first maxit//4
        iterations; if that has not converged, restart from x0 with a backtracking line
        search on |F|^2. Once the Newton iterate satisfies the conditions to 1e-6, the
        branch it selects is solved exactly (branch_solve); that solution is accepted
        when it satisfies all original conditions to tol (it then IS the solution of
        the piecewise-linear system: it lies on the branch it was computed on)."""
        x = x0.copy()
        F, J = self.residual(x, rhs, jac=True)
        fscale = max(np.abs(rhs).max(), 1e-300)
        hist = []
        pure = max(maxit // 4, 1)
        for it in range(1, maxit + 1):
            if it == pure + 1:
                x = x0.copy()
                F, J = self.residual(x, rhs, jac=True)
            dx = np.linalg.solve(J, -F)
            phi0 = np.dot(F, F)
            t = 1.0
            while it > pure:
                xn = x + t * dx
                Fn = self.residual(xn, rhs)
                if np.dot(Fn, Fn) < (1 - 1e-4 * t) * phi0 or t < 1e-10 or phi0 < (1e-15 * fscale) ** 2:
                    break
                t *= 0.5
            else:
                xn = x + dx
            x = xn
            F, J = self.residual(x, rhs, jac=True)
            e, _ = self.kkt_error(x, rhs)
            hist.append(e)
            if e < 1e-6:
                xb = self.branch_solve(x, rhs)
                eb, _ = self.kkt_error(xb, rhs)
                hist[-1] = (e, eb)
                if eb < tol:
                    return xb, it, eb
        raise ConvergenceError("no convergence after %d iterations; last KKT errors (newton, "
                               "branch solve): %s" % (maxit, hist[-3:]))

    def run(self, tol=1e-12, maxit=100, verbose=False):
        p = self.prm
        nd = 2 * len(self.xy)
        k = self.k
        u = np.zeros(nd)
        vold = np.zeros(nd)
        x = np.zeros(self.nf + len(self.nslot) + len(self.tslot))
        self.iterations, self.worst = [], 0.0
        for n in range(1, self.N + 1):
            t = n * k
            rhs = self.Mf @ vold / k - self.Bf @ u + p["load"] * t * self.tracf
            try:
                x, it, e = self.solve_step(x, rhs, tol, maxit)
            except ConvergenceError as err:
                raise ConvergenceError("step %d (t = %g): %s" % (n, t, err))
            self.iterations.append(it)
            self.worst = max(self.worst, e)
            v = np.zeros(nd)
            v[self.free] = x[:self.nf]
            u = u + k * v
            vold = v
            if verbose:
                print("step %3d t %.4f iterations %2d kkt %.2e" % (n, t, it, e))
        self.u, self.v, self.x = u, vold, x
        return self

    def contact_table(self):
        p = self.prm
        nf, nN = self.nf, len(self.nslot)
        ln_all = dict(zip(self.nslot, self.x[nf:nf + nN]))
        lt_all = dict(zip(self.tslot, self.x[nf + nN:]))
        rows = []
        for v in self.cnodes:
            vnu, vtau = 0.0 - self.v[2 * v + 1], self.v[2 * v]   # 0.0 - : no "-0"
            ln, lt = ln_all.get(v, 0.0), lt_all.get(v, 0.0)
            damped, g = p["cnu"] * max(vnu, 0.0), p["g"]
            # what the law gives the node (docs/design.md, "Statuses and zones"), derived here on its own
            normal = 0 if vnu <= 0 else (2 if vnu >= g * (1 - 1e-6) else 1)
            tangential = 0 if abs(vtau) <= 1e-6 * g else 1
            zone = 0 if normal == 0 else 2 * normal - tangential
            rows.append([self.xy[v, 0], vnu, vtau, damped + ln, ln, lt, g, damped, p["cnu"] * g or 1.0, zone])
        return np.array(rows)

    def fields_table(self):
        return np.column_stack([self.xy, self.u[0::2], self.u[1::2], self.v[0::2], self.v[1::2]])


def write_solution(out, prm, contact_rows, field_rows):
    """OUT/contact.txt and OUT/fields.txt, in the format of the suite's tables."""
    comments = ["%s %s" % (kk, prm[kk]) for kk in PARAM_KEYS]
    runfiles.write_table(os.path.join(out, "contact.txt"), comments, CONTACT_COLS, contact_rows)
    runfiles.write_table(os.path.join(out, "fields.txt"), comments, FIELD_COLS, field_rows)


def solve(mesh, prm, tol, maxit, verbose=False):
    m = runfiles.read_msh22(mesh)
    t0 = time.time()
    pb = Problem(m.xy, m.triangles, m.lines, m.line_labels, prm).run(tol, maxit, verbose)
    return pb, time.time() - t0


# ----------------------------------------------------------------------------- compare
def to_params(d, where):
    """The parameters PARAM_KEYS of a run from the runfiles.Values d of one of its files."""
    prm = {}
    for kk in PARAM_KEYS:
        if kk not in d:
            raise InputError("%s: parameter '%s' missing" % (where, kk))
        prm[kk] = d[kk] if kk in ("scene", "problem", "plane") else d.real(kk)
    return prm


def compare(run_dir, rtol, tol, maxit, out):
    summ = runfiles.read_summary(os.path.join(run_dir, "summary.txt"))
    theirs_c = runfiles.read_table(os.path.join(run_dir, "contact.txt"))
    prm = to_params(summ, "summary.txt")
    prm2 = to_params(theirs_c.params, "contact.txt header")
    for kk in PARAM_KEYS:
        if prm[kk] != prm2[kk]:
            raise InputError("parameter %s differs: summary.txt %s, contact.txt %s" % (kk, prm[kk], prm2[kk]))
    if prm["scene"] not in SCENES or prm["problem"] not in ("original", "penalty") or prm["plane"] not in ("stress", "strain"):
        raise InputError("unsupported scene/problem/plane %s/%s/%s" % (prm["scene"], prm["problem"], prm["plane"]))
    theirs_f = runfiles.read_table(os.path.join(run_dir, "fields.txt"))
    print("parameters: " + " ".join("%s=%s" % (kk, prm[kk]) for kk in PARAM_KEYS))
    mesh = os.path.join(run_dir, "mesh.msh")
    print("mesh: %s" % mesh)
    pb, elapsed = solve(mesh, prm, tol, maxit)
    print("independent solve: %d steps, %d dofs (%d free), %d contact nodes, Newton iterations "
          "total %d max %d, worst KKT error %.2e, %.3f s"
          % (pb.N, 2 * len(pb.xy), pb.nf, len(pb.cnodes), sum(pb.iterations),
             max(pb.iterations), pb.worst, elapsed))
    mine_c, mine_f = pb.contact_table(), pb.fields_table()
    if out:
        write_solution(out, prm, mine_c, mine_f)
    if len(theirs_c) != mine_c.shape[0] or len(theirs_f) != mine_f.shape[0]:
        raise InputError("row counts differ: contact %d vs %d, fields %d vs %d"
                         % (len(theirs_c), mine_c.shape[0], len(theirs_f), mine_f.shape[0]))
    geo = max(np.abs(theirs_c["x"] - mine_c[:, 0]).max(),
              np.abs(theirs_f["x"] - mine_f[:, 0]).max(),
              np.abs(theirs_f["y"] - mine_f[:, 1]).max())
    if geo > 1e-12:
        raise InputError("node coordinates/order differ (max %.3g)" % geo)
    worst = 0.0
    for fname, theirs, mine, names in (
            ("contact.txt", theirs_c, mine_c, CONTACT_COLS),
            ("fields.txt", theirs_f, mine_f, FIELD_COLS)):
        for j, name in enumerate(names):
            if name in ("x", "y"):
                continue
            a = theirs[name]
            b = mine[:, j]
            diff = np.abs(a - b).max()
            # a column against its largest value, but at least FAMILY_FLOOR times its family's:
            # a column of round-off only (lambda_nu where no node reaches the bound) is not
            # divided by that round-off
            family = next((f for f in FAMILIES if name in f), (name,))
            big = max(np.abs(theirs[other]).max() for other in family if other in names)
            own = np.abs(a).max()
            scale = max(own, FAMILY_FLOOR * big, 1e-300)
            rel = diff / scale
            worst = max(worst, rel)
            print("%-12s %-11s max|diff| %.3e  scale %.3e%s  rel %.3e  %s"
                  % (fname, name, diff, scale, " (floor)" if scale > own else "", rel, "ok" if rel <= rtol else "EXCEEDS rtol"))
    print("worst relative difference %.3e (rtol %g): %s" % (worst, rtol, "PASS" if worst <= rtol else "FAIL"))
    return 0 if worst <= rtol else 1


CONTACT_COLS = ["x", "v_nu", "v_tau", "p_nu", "lambda_nu", "lambda_tau", "g", "damped_response", "force_scale", "zone"]
# the components of one quantity (the same families as tests/independent_solver3d.py)
FAMILIES = (("v_nu", "v_tau", "g"), ("p_nu", "lambda_nu", "lambda_tau", "damped_response", "force_scale"), ("u_x", "u_y"),
            ("v_x", "v_y"), ("zone",))
FAMILY_FLOOR = 1e-4
FIELD_COLS = ["x", "y", "u_x", "u_y", "v_x", "v_y"]


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mesh")
    ap.add_argument("--compare", metavar="FREEFEM_RUN_DIR")
    ap.add_argument("--rtol", type=float, default=1e-9)
    ap.add_argument("--scene", default=DEFAULTS["scene"], choices=sorted(SCENES))
    ap.add_argument("--problem", default=DEFAULTS["problem"], choices=["original", "penalty"])
    ap.add_argument("--plane", default=DEFAULTS["plane"], choices=["stress", "strain"])
    for kk in PARAM_KEYS[3:]:
        ap.add_argument("--" + kk, type=float, default=DEFAULTS[kk])
    ap.add_argument("--tol", type=float, default=1e-12)
    ap.add_argument("--maxit", type=int, default=100)
    ap.add_argument("--verbose", action="store_true")
    ap.add_argument("--out")
    a = ap.parse_args(argv)
    try:
        if a.compare:
            return compare(a.compare, a.rtol, a.tol, a.maxit, a.out)
        if not a.mesh or not a.out:
            ap.error("--mesh and --out are required (or --compare DIR)")
        prm = {kk: getattr(a, kk) for kk in PARAM_KEYS}
        for kk in ("T", "dt", "rho", "E", "g", "eps"):
            if not prm[kk] > 0:
                raise InputError("--%s must be > 0" % kk)
        pb, elapsed = solve(a.mesh, prm, a.tol, a.maxit, a.verbose)
        write_solution(a.out, prm, pb.contact_table(), pb.fields_table())
        print("%d steps, Newton iterations total %d max %d, worst KKT error %.2e, %.3f s; results in %s"
              % (pb.N, sum(pb.iterations), max(pb.iterations), pb.worst, elapsed, a.out))
        return 0
    except ConvergenceError as error:
        print("independent_solver: %s" % error, file=sys.stderr)
        return 4


if __name__ == "__main__":
    sys.exit(runfiles.run_tool("independent_solver", lambda: main(sys.argv[1:]), code=2))
