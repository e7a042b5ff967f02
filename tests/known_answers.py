"""known_answers.py: the known answers tests/check_results.py checks a run against:
--column, the frictionless column pressed by its load (the column scenes; docs/design.md,
"Scenes"), and --slide, the oblique slide at the bound (oblique-slide3d; "Three
dimensions"). Each reads the run's own law from its columns (g, damped_response,
force_scale, friction_bound, the statuses and zones) and its loads from scene.scene
(runfiles.SceneLoads: the load history h(t), the body force, the initial velocity); nothing
here inverts or differentiates p. A mixin of check_results.Checks (it uses
checker.Checker's outputs and allowances, and Checks3D.tetrahedra).
"""
import os

import numpy as np

import runfiles
from checker import ROUNDOFF, FRAME, Refusal, worst


class KnownAnswers:
    """check_column (with column_applies, check_pressed, column_rate, check_uniaxial_strain) and
    check_slide."""

    def column_applies(self):
        """Refusal when the column's known answer does not apply to the run's load history: a
        history that pulls the column (q L + f0 |Omega| < 0) at a step before one that presses
        it. Pulled, the column leaves the foundation as a free body: the contact depends on the
        velocity only (no gap, no adhesion), so nothing holds it, and the momentum the pull gave
        it carries it on after the push begins, until it lands with an impact. The known
        answer (check_column) is that of a column pressed from rest, whose momentum stays that
        of the known answer: for this history it holds neither in flight (every node free
        although pressed) nor after the landing (the impact's waves)."""
        loads, h = runfiles.SceneLoads(self.folder), self.h
        length = self.c["weight"].sum()
        area = length * (self.f["y"].max() - self.f["y"].min())
        total = self.real("load") * loads.h(h["t"]) * length - loads.body_force[1] * area
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
        """Known answer of the column scene, for the run's own damped response, bound and
        loads. Summing the equations with w = (0,1) gives, at every step, exactly:
        sum_i w_i p_nu_i = q L + |Omega| (-f0_y) - (1/k) m(v_n - v_{n-1}, e_y), q = load h(t_n),
        and by Cauchy-Schwarz |m(dv, e_y)| <= sqrt(2 kinetic_jump) sqrt(rho |Omega|)
        (kinetic_jump = 1/2 m(dv, dv)). While pulled (q < 0) every node is free; released
        (q = 0 after a push) p_nu = 0 within the inertia force. At T, pressed, v_nu = min(p^-1(q),
        g) node by node, read without inverting p: a damped node (normal status 1) has p(v_nu)
        = q (its damped_response) and lambda_nu = 0, a node at the bound (status 2) v_nu = g and
        p(g) <= q (its damped_response), and no node is free. The column is uniaxial when that
        answer is the same at every node (one g, or every node damped): then each node carries
        p_nu = q. Where g(x) makes it differ between nodes, the body shears and carries load
        between them: only v_nu = g(x) at the nodes at the bound is known, and only when every
        node is at the bound. A body force makes the stress vary along the height, which the
        viscoelastic law couples to the width: then only the total force is known. In 3D
        (column3d) the same holds with w = (0,1,0), L the area of Gamma3 and |Omega| = L times
        the height: the forces below are per unit area."""
        c, h, ch = self.c, self.h, self.ch
        loads = runfiles.SceneLoads(self.folder)
        load, T, dt, rho = self.real("load"), self.real("T"), self.real("dt"), self.real("rho")
        length = c["weight"].sum()
        area = length * (self.f["y"].max() - self.f["y"].min())
        weight = -loads.body_force[1] * area                  # f0 pressing the column down
        force_scale = float(c["force_scale"].max()) * length
        # every step: the total contact force, and the free nodes of the pulled steps
        q_steps = load * loads.h(h["t"])
        inertia_steps = np.sqrt(2 * h["kinetic_jump"] * rho * area) / dt
        # round-off of each step's sum: of its terms, the force itself, the load, the inertia
        # force and, on free nodes of a column that flies away, the damping slope times the
        # velocity (p_nu = K_n v_nu + m cancels to 0: stress_terms), for Gamma3 K_n L |v|
        # (|v| the rms velocity); times lambda/E where the volumetric stiffness is the larger
        # (near nu = 0.5 the matrix S sums terms lambda/E times larger than the stresses)
        slope = self.damping_slope() * length
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
            self.expect((ch["zone_free"][pulled] == len(c)).all(), "pulled steps: a node is not free")
        q = load * float(loads.h(T)) + weight / length
        stress_roundoff = ROUNDOFF * self.stress_terms(c["v_nu"])
        if q == 0 and (q_steps * length + weight > 0).any():
            # released: the compressed column expands (E eps + mu eps' = 0) and lifts off; p_nu = q = 0
            # up to the inertia force per unit length of the last step, as when pressed
            excess, err_p, allow = worst(np.abs(c["p_nu"]), 2 * inertia_steps[-1] / length + stress_roundoff)
            self.expect(excess <= 0, f"released (q = 0): p_nu = {err_p:.3e} > {allow:.3e} (inertia and round-off)")
            return
        if q < 0:
            scale = c["force_scale"]                                # p(g), 1 where it is 0
            excess, value, allow = worst(np.abs(c["p_nu"]) / scale, stress_roundoff / scale)
            self.expect(excess <= rtol, f"pulled (q = {q}): p_nu = {value:.3e} p(g) != 0 (round-off allowance {allow:.1e})")
            self.expect((c["v_nu"] <= 0).all() and (c["normal_status"] == 0).all(),
                        f"pulled (q = {q}): a node is not free (v_nu max {c['v_nu'].max():.3e})")
            return
        if weight != 0:
            return          # a body force makes the stress vary along the height: not uniaxial
        self.check_pressed(q, rtol, inertia_steps, stress_roundoff, area / length, q_steps)

    def check_pressed(self, q, rtol, inertia_steps, stress_roundoff, height, q_steps):
        """check_column at T for a column pressed from rest (q > 0, no body force): each node
        damped with p(v_nu) = q and lambda_nu = 0, or at the bound with v_nu = g and p(g) <= q;
        p_nu = q where the answer is uniform; the uniaxial strains (check_uniaxial_strain) when
        pressed at every step. The stresses within the inertia of the last step (twice its
        force per unit length: measured unevenness 1.002), plus the inertia force per unit
        length of the column while it accelerated along its answer, rho Ly max |dv_nu/dt|
        (column_rate: the viscoelastic body keeps a memory of it once v_nu = g holds, measured
        there 0.05 of it), plus the solver's tolerance 1e-10 q, plus round-off."""
        c, g, rho = self.c, self.c["g"], self.real("rho")
        length = c["weight"].sum()
        normal = c["normal_status"]
        damped, bound = normal == 1, normal == 2
        if not self.expect((damped | bound).all(), f"pressed (q = {q}): {int(np.sum(~(damped | bound)))} free nodes"):
            return
        # the round-off of v_nu: of the terms it is computed from (velocity_terms: a column held
        # at the bound with p' = 0 computes v_nu = g from terms of k q L/(rho |Omega|)); that of
        # p(v_nu) is it times the slope
        velocity_roundoff = ROUNDOFF * (np.abs(c["v_nu"]) + self.normal_velocity_terms())
        response_roundoff = stress_roundoff + self.damping_slope() * velocity_roundoff
        rate = self.column_rate()
        slack = 2 * inertia_steps[-1] / length + rho * height * rate + 1e-10 * q
        excess, err, allow = worst(np.where(bound, c["damped_response"] - q, 0.0), np.where(bound, slack + response_roundoff, 0.0))
        self.expect(excess <= 0, f"a node at the bound has p(g) = {err + q:.6e} above q = {q} by {err:.3e} > {allow:.3e} "
                    "(inertia and round-off): the known answer min(p^-1(q), g) puts it below the bound")
        excess, err, allow = worst(np.where(bound, np.abs(c["v_nu"] - g) / g, 0.0), np.where(bound, velocity_roundoff / g, 0.0))
        self.expect(excess <= 0, f"a node at the bound: v_nu = g off by {err:.3e} g (round-off allowance {allow:.1e})")
        if not (np.ptp(g) == 0 or damped.all()):
            self.expect(bool(bound.all()), "the known answer min(p^-1(q), g(x)) differs between nodes and not every "
                        "node is at the bound: no known answer (the body shears)")
            return
        excess, err_p, allow = worst(np.abs(c["p_nu"] - q), slack + stress_roundoff)
        self.expect(excess <= 0, f"p_nu differs from q = {q} by {err_p:.3e} > {allow:.3e} (inertia {slack:.3e} and "
                    "round-off)")
        excess, err, allow = worst(np.where(damped, np.abs(c["damped_response"] - q), 0.0),
                                   np.where(damped, slack + response_roundoff, 0.0))
        node = int(np.argmax(np.where(damped, np.abs(c["damped_response"] - q), 0.0)))
        self.expect(excess <= 0, f"a damped node's p(v_nu) differs from q = {q} by {err:.3e} > {allow:.3e} (inertia and "
                    f"round-off) at x = {c['x'][node]}: v_nu = {c['v_nu'][node]} is not p^-1(q)")
        excess, err, allow = worst(np.where(damped, np.abs(c["lambda_nu"]), 0.0), np.where(damped, slack + stress_roundoff, 0.0))
        self.expect(excess <= 0, f"a damped node carries lambda_nu = {err:.3e} > {allow:.3e} (inertia and round-off)")
        friction = np.abs(c["lambda_tau"]).max() + (np.abs(c["lambda_tau2"]).max() if self.dim == 3 else 0.0)
        self.expect(friction == 0.0 or self.real("mu") > 0, "lambda_tau != 0 without friction")
        if (q_steps > 0).all():
            # the stress error of each step: its inertia bound, and that of the acceleration
            # along the known answer (absolute, per unit length)
            self.check_uniaxial_strain(q_steps, 2 * inertia_steps / length + rho * height * rate)

    def column_rate(self):
        """The largest |dv_nu/dt| of the run: between consecutive recorded steps of
        contact_nodes_history.txt (every step up to 200 steps), the first from rest (v_nu = 0
        at t = 0) when the scene gives no initial velocity: the column's acceleration along its
        known answer."""
        nodes = len(self.c)
        nh = runfiles.read_table(os.path.join(self.folder, "contact_nodes_history.txt"))
        v, t = nh["v_nu"].reshape(-1, nodes), nh["t"].reshape(-1, nodes)[:, 0]
        if not any(runfiles.SceneLoads(self.folder).initial_velocity):
            v, t = np.vstack([np.zeros(nodes), v]), np.r_[0.0, t]
        return float((np.abs(np.diff(v, axis=0)) / np.diff(t)[:, None]).max()) if len(t) > 1 else 0.0

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
        node. At every recorded step where every node is at the bound and slipping (normal status
        2, tangential status 1):
        - per node, the law's friction bound mu p(v_nu) (friction_bound) is Tresca's mu p(g)
          (p(g) the law's force_scale) to rtol p(g);
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
        each with every node at the bound and slipping (the block stiff or not: only the slip directions
        enter). Measured on oblique-slide3d (20 steps): |lambda_tau| off by 3e-14 p(g) at most,
        |sin| 5e-14, spread 1.5e-2 rad at step 1, 3e-6 from step 8, |F| = 1 - 2e-5 at step 1
        and 1 - 1e-12 at T, the square law 41% above, the mean velocity 1.9e-5 m/s off 0.6
        against a bound of 1.7e-4 m/s."""
        if not self.expect(self.dim == 3, "--slide: not a 3D run (summary.txt: dimension 3)"):
            return
        if not self.expect(self.params["problem"] == "original", "--slide: the known answer mu p(g) is the original "
                           "problem's (the penalty problem's bound is mu p(v_nu), v_nu > g at the bound)"):
            return
        c, mu = self.c, self.real("mu")
        nodes, weight = len(c), c["weight"]
        g, pg = c["g"], c["force_scale"]                     # the law's g and p(g) at each node
        bound = mu * pg                                      # Tresca's mu p(g) at each node
        total = float(np.sum(weight * bound))                # the Tresca force mu p(g) A
        scale = float(np.sum(weight * pg))                   # p(g) A, the stresses' rtol
        if not self.expect(float(np.sum(weight * c["friction_bound"])) > 0, "--slide: the friction bound is 0 at "
                           "every node at T: no friction to check"):
            return
        # one frame for every node (a flat Gamma3): the nodes' forces add as vectors in (t1, t2)
        frame = np.stack([c[name] for name in FRAME], 1)
        spread = np.abs(frame - frame[0]).max()
        if not self.expect(spread <= 1e-12, f"--slide: the nodes' frames differ by {spread:.3e} (a curved Gamma3, or "
                           "Dirichlet conditions that turn a node's frame): the tangential forces do not add as vectors"):
            return
        t1, t2 = frame[0, 3:6], frame[0, 6:9]
        nh = runfiles.read_table(os.path.join(self.folder, "contact_nodes_history.txt"))
        if not self.expect(len(nh) % nodes == 0, f"contact_nodes_history.txt: {len(nh)} rows for {nodes} nodes"):
            return

        def rows(name):
            return nh[name].reshape(-1, nodes)
        steps = rows("step")[:, 0].astype(int)
        sliding = ((rows("normal_status") == 2) & (rows("tangential_status") == 1)).all(1)
        if not self.expect(sliding.any(), "--slide: no recorded step has every node at the bound and slipping"):
            return
        ch = self.ch
        deviation = {}                                       # step -> sum_i w_i mu p(g) |d_i - e0| (+ 1e-8)
        loads = runfiles.SceneLoads(self.folder)
        v0 = np.array(loads.initial_velocity)
        launch = np.array([v0 @ t1, v0 @ t2])                # V in (t1, t2)
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
            tresca = (np.abs(rows("friction_bound")[row] - bound) / pg).max()
            first("tresca", tresca <= rtol, f"--slide, step {step}: the friction bound mu p(v_nu) of the nodes sliding "
                  f"at the bound differs from Tresca's mu p(g) by {tresca:.3e} p(g) (bound {rtol:g})")
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
            if np.hypot(*launch) > 0:
                e0 = launch / np.hypot(*launch)
                deviation[step] = float(np.sum(weight * bound * (np.hypot(*(slip - e0).T) + 1e-8))) + rtol * scale
        # the mean tangential velocity at T against the rigid body, when every step slid at the bound
        dt, count = self.real("dt"), len(self.h)
        tangential_load = [abs(np.dot(loads.body_force, t)) for t in (t1, t2)]
        if not self.expect(np.hypot(*launch) > 0, "--slide: the scene gives no tangential "
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
        if not self.expect(not missing, f"--slide: the rigid-body answer needs every step recorded with every node "
                           f"at the bound and slipping; not step {missing[0] if missing else ''} ({len(missing)} steps)"):
            return
        rigid = (speed0 - total * dt * count / mass) * launch / speed0
        off = float(np.hypot(*(mean - rigid)))
        allowed = dt / mass * sum(deviation.values()) + roundoff
        self.expect(rigid @ launch > 0, f"--slide: the rigid block stops before T (V - mu p(g) A T/m = "
                    f"{speed0 - total * dt * count / mass:.6e}): no free slide to check")
        self.expect(off <= allowed, f"--slide: the mean tangential velocity at T ({mean[0]:.12e}, {mean[1]:.12e}) is "
                    f"{off:.3e} m/s off the rigid-body answer V - mu p(g) A T/m = {speed0 - total * dt * count / mass:.12e} "
                    f"along the launch (bound {allowed:.3e}: the slip directions' deviation from it)")
