#!/usr/bin/python3
"""Figures of the paper's section 5 from the outputs of edp/solve.edp.

One function per figure, named after the paper's figure (or, for the figures the
paper does not have, after what they show); each reads the text outputs by column
name and writes PNG files. Usage:
  figures.py --results DIR --out DIR [NAME ...]     (NAME: see FIGURES; default all)
Prints 'figures.py: NAME -> PATH' for each figure drawn. A NAME that is not a figure, or
results that are missing, end it with one line on stderr and exit status 2 (./run.sh figures
passes here the arguments that are not run folders, hence "no run folder ... and no figure").
DIR/paper-original, DIR/paper-penalty, DIR/eps-study and DIR/scenes/NAME (the scenes
unloading, cylinder, bound-profile, power-damping of edp/scenes/) are the outputs of
./run.sh; fig5 also reads DIR/eps-study/eps_study.txt, written by plots/tables.py.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import matplotlib.tri as mtri
import numpy as np

import gamma3
import runfiles
import style

plt = style.pyplot()
PROBLEMS = ("original", "penalty")


def paper_runs(results):
    """The folders of the paper scene's runs, DIR/paper-original and DIR/paper-penalty."""
    return [os.path.join(results, f"paper-{problem}") for problem in PROBLEMS]


def paper_scales(results):
    """The natural scales (style.Scales) of the paper runs' quantities: the least spans of
    the axes (round-off drawn flat)."""
    return style.scales(*(runfiles.read_table(os.path.join(folder, "contact.txt")) for folder in paper_runs(results)))


def gamma3_length(*tables):
    """The extent along x of Gamma3 in these contact.txt tables: the scale of a position on it."""
    x = np.concatenate([t.finite("x")[0] for t in tables])
    return float(np.ptp(x))


def fig2_deformed(results, out):
    """Fig. 2: deformed configuration at T, true scale, with the contact line y = 0."""
    fig, axes = plt.subplots(1, 2, sharey=True)
    for ax, problem in zip(axes, PROBLEMS):
        folder = os.path.join(results, f"paper-{problem}")
        f = runfiles.read_table(os.path.join(folder, "fields.txt"))
        p = f.params
        triangles = runfiles.read_msh22(os.path.join(folder, "mesh.msh")).triangles
        tri = mtri.Triangulation(f["x"] + f["u_x"], f["y"] + f["u_y"], triangles)
        ax.triplot(tri, color="0.3", linewidth=0.3)
        ax.axhline(0.0, color="tab:red", linewidth=1.0, label="undeformed contact line y = 0")
        ax.set_aspect("equal")
        ax.set_title(f"{style.problem_label(p)}: deformed mesh at T (true scale)")
        ax.set_xlabel("x [m]")
        ax.legend(loc="upper right")
    axes[0].set_ylabel("y [m]")
    style.note_versions(fig, paper_runs(results))
    return style.save(fig, out, "fig2_deformed")


def fig3_contact_reactions(results, out):
    """Fig. 3: normal pressure p_nu = p(v_nu) + lambda_nu and tangential stress on Gamma3 at T."""
    fig, axes = plt.subplots(1, 2, sharey=True)
    for ax, problem in zip(axes, PROBLEMS):
        c = runfiles.read_table(os.path.join(results, f"paper-{problem}", "contact.txt"))
        p = c.params
        ax.plot(c["x"], c["p_nu"], "o-", label=r"$p_\nu = p(v_\nu) + \lambda_\nu$")
        ax.plot(c["x"], c["p_nu"] - c["lambda_nu"], "--", label=r"damped response $p(v_\nu)$")
        ax.plot(c["x"], c["lambda_nu"], ":", label=r"multiplier $\lambda_\nu$")
        ax.plot(c["x"], c["lambda_tau"], "s-", label=r"tangential stress $\lambda_\tau$")
        ax.plot(c["x"], c["friction_bound"], "k-", linewidth=0.8, label=r"friction bound $\mu p(v_\nu)$")
        ax.plot(c["x"], -c["friction_bound"], "k-", linewidth=0.8)
        ax.set_title(f"{style.problem_label(p)}: contact stresses on $\\Gamma_3$ at T = {p['T']}")
        ax.set_xlabel("x [m]")
        ax.legend(loc="center right", fontsize=8)   # the band between p(g) and lambda_nu on CD is empty
    axes[0].set_ylabel("stress [GPa]")
    style.least_span(axes[0], paper_scales(results).stress)     # (the axes share y)
    style.note_versions(fig, paper_runs(results))
    return style.save(fig, out, "fig3_contact_reactions")


def bound_line(ax, c, **line):
    """The bound g of the column g of a contact.txt: a horizontal line labelled with its value
    where it is the same at every node, else g(x); returns its largest value."""
    g = c.finite("g")[0]
    if np.ptp(g) == 0:
        ax.axhline(g[0], label=f"bound g = {g[0]:g}", **line)
    else:
        ax.plot(c["x"], g, label="bound g(x)", **line)
    return float(g.max())


def fig4_velocities(results, out):
    """Fig. 4: normal and tangential velocity on Gamma3 at T, with the bound g and the zones,
    shaded from the nodes' statuses wherever they lie (a zone may come in several stretches)
    and labelled once each, over its widest stretch."""
    fig, axes = plt.subplots(1, 2, sharey=True)
    labels = []
    for ax, problem in zip(axes, PROBLEMS):
        c = runfiles.read_table(os.path.join(results, f"paper-{problem}", "contact.txt"))
        p = c.params
        ax.plot(c["x"], c["v_nu"], "o-", label=r"$v_\nu$")
        ax.plot(c["x"], c["v_tau"], "s-", label=r"$v_\tau$")
        g = bound_line(ax, c, color="k", linewidth=0.8, linestyle="--")
        segments = style.paper_segments(c)
        found = gamma3.stretches(c["x"], segments)
        gamma3.shade_stretches(ax, found, style.PAPER_COLORS, alpha=0.12)
        labels.append((ax, found, {name: f"{name}: {style.nodes(segments.count(name))}" for name in style.PAPER_COLORS}, g))
        ax.set_title(f"{style.problem_label(p)}: velocities on $\\Gamma_3$ at T = {p['T']}")
        ax.set_xlabel("x [m]")
        ax.legend(loc="center right")          # CD: v_nu = g, v_tau = 0 leave this corner empty
    axes[0].set_ylabel("velocity [m/s]")
    g = max(g for *_, g in labels)
    style.least_span(axes[0], paper_scales(results).velocity)
    bottom = axes[0].get_ylim()[0]                        # of both curves: the axes are shared
    axes[0].set_ylim(top=max(1.25 * g, bottom + (g - bottom) / 0.86))    # g at most 86 % up: the labels above
    style.note_versions(fig, paper_runs(results))
    fig.tight_layout()
    for ax, found, texts, _ in labels:
        gamma3.label_stretches(ax, found, texts, (0.93, 0.885, 0.84))
    return style.save(fig, out, "fig4_velocities")


def require(path, producer):
    """The path, or an InputError naming the missing input and what writes it."""
    if not os.path.isfile(path):
        raise runfiles.InputError(f"missing {path} (written by {producer})")
    return path


def eps_study_runs(results):
    """{eps: folder} of the runs of DIR/eps-study (eps from the '# eps' line of contact.txt)."""
    parent = os.path.join(results, "eps-study")
    runs = {}
    for name in sorted(os.listdir(parent)) if os.path.isdir(parent) else []:
        path = os.path.join(parent, name, "contact.txt")
        if os.path.isfile(path):
            runs[runfiles.read_table(path).params.real("eps")] = os.path.join(parent, name)
    return runs


def fig5_penalty_convergence(results, out, shown=(1e-1, 1e-2, 1e-3, 1e-5)):
    """Fig. 5: v_nu on Gamma3 at T for several eps and the original problem (left);
    ||v_eps - v||_L2(Omega) at T against eps, from eps_study.txt, with the fitted tail slope (right)."""
    e = runfiles.read_table(require(os.path.join(results, "eps-study", "eps_study.txt"), "plots/tables.py"))
    study = e.params
    runs = eps_study_runs(results)
    fig, (left, right) = plt.subplots(1, 2)
    colors = plt.cm.viridis(np.linspace(0.0, 0.85, len(shown)))
    for eps, color in zip(shown, colors):
        if eps in runs:
            c = runfiles.read_table(os.path.join(runs[eps], "contact.txt"))
            left.plot(c["x"], c["v_nu"], "o-", color=color, markersize=2, label=f"penalty, $\\varepsilon$ = {eps:g}")
    c = runfiles.read_table(require(os.path.join(results, "paper-original", "contact.txt"), "./run.sh"))
    p = c.params
    left.plot(c["x"], c["v_nu"], "k-", linewidth=2.5, zorder=0, label="original problem")
    bound_line(ax=left, c=c, color="tab:red", linewidth=0.8, linestyle="--")
    left.set_title(f"normal velocity on $\\Gamma_3$ at T = {p['T']}")
    left.set_xlabel("x [m]")
    left.set_ylabel(r"$v_\nu$ [m/s]")
    left.legend(loc="upper left", fontsize=7)
    style.least_span(left, style.scales(c).velocity)
    right.loglog(e["eps"], e["error_L2"], "o", markersize=6, label="penalty runs")
    try:
        tail = np.array([float(t) for t in study["tail_eps"].split(",")])
    except ValueError:
        raise runfiles.InputError(f"{e.path}: tail_eps = {study['tail_eps']!r} is not a list of numbers") from None
    slope = study.real("slope_tail")
    on_tail = np.isin(e["eps"], tail)
    intercept = np.mean(np.log(e["error_L2"][on_tail]) - slope * np.log(e["eps"][on_tail]))
    span = np.array([tail.min(), tail.max()])
    right.loglog(span, np.exp(intercept) * span**slope, "k-", linewidth=0.8,
                 label=f"least-squares fit on the {on_tail.sum()} smallest $\\varepsilon$")
    right.text(0.05, 0.92, f"fitted slope {slope:.4f}", transform=right.transAxes, fontsize=10)
    right.set_title(f"penalty solution against the original one ({study['reference']}) at T")
    right.set_xlabel(r"penalty parameter $\varepsilon$")
    right.set_ylabel(r"$\|v_\varepsilon - v\|_{L^2(\Omega)}$, consistent mass matrix [m$^2$/s]")
    right.legend(loc="lower right")
    style.note_versions(fig, [os.path.join(results, "paper-original")] + [runs[eps] for eps in sorted(runs, reverse=True)])
    return style.save(fig, out, "fig5_penalty_convergence")


def applied_normal_load(folder, params, t):
    """The total traction pushing toward the foundation, load h(t) |Gamma2| (traction . n),
    where the run's scene.scene gives one contact normal (not auto); else None."""
    data = runfiles.read_scene(os.path.join(folder, "scene.scene")).data
    if data.get("contact_normal", [["auto"]])[0] == ["auto"]:
        return None
    try:
        traction, normal = (np.array([float(w) for w in data[key][0]]) for key in ("traction", "contact_normal"))
    except ValueError:
        raise runfiles.InputError(f"{folder}/scene.scene: traction and contact_normal need numbers") from None
    mesh = runfiles.read_msh22(os.path.join(folder, "mesh.msh"))
    edges = mesh.lines[mesh.line_labels == runfiles.labels()["GammaTraction"]]
    d = mesh.xy[edges[:, 0]] - mesh.xy[edges[:, 1]]
    length = float(np.sum(np.hypot(d[:, 0], d[:, 1])))
    return params.real("load") * runfiles.SceneLoads(folder).h(t) * length * float(traction @ (normal / np.hypot(*normal)))


def contact_forces_history(results, out):
    """Total contact forces on Gamma3 against t: sum_i w_i p_nu,i and sum_i w_i lambda_tau,i."""
    fig, (left, right) = plt.subplots(1, 2)
    for problem, line in zip(PROBLEMS, ("-", "--")):
        h = runfiles.read_table(os.path.join(results, f"paper-{problem}", "contact_history.txt"))
        p = h.params
        left.plot(h["t"], h["normal_force"], line, label=style.problem_label(p))
        right.plot(h["t"], h["tangential_force"], line, label=style.problem_label(p))
    folder = os.path.join(results, "paper-original")
    h = runfiles.read_table(os.path.join(folder, "contact_history.txt"))
    applied = applied_normal_load(folder, h.params, h["t"])
    if applied is not None:
        left.plot(h["t"], applied, "k:", linewidth=0.8, label=r"applied traction $\int_{\Gamma_2} f_2 \cdot \nu_{\Gamma_3}$")
    left.set_title(r"normal force $\sum_i w_i\, p_{\nu,i}$ on $\Gamma_3$")
    right.set_title(r"tangential force $\sum_i w_i\, \lambda_{\tau,i}$ on $\Gamma_3$")
    for ax in (left, right):
        ax.set_xlabel("t [s]")
        ax.set_ylabel("force per unit thickness [GPa m]")
        ax.legend()
        style.least_span(ax, paper_scales(results).force)
    style.note_versions(fig, paper_runs(results))
    return style.save(fig, out, "contact_forces_history")


def energy_history(results, out):
    """Discrete energy balance (docs/design.md, "Energy identity"): the energies and the cumulative
    dissipations and work against t (left, log scale), the per-step residual (right)."""
    fig, (left, right) = plt.subplots(1, 2)
    largest = 0.0
    for problem, line in zip(PROBLEMS, ("-", "--")):
        h = runfiles.read_table(os.path.join(results, f"paper-{problem}", "history.txt"))
        largest = max(largest, style.energy_terms_plot(left, h, line, labelled=problem == "original"))
        residual = np.where(h["energy_residual"] > 0, h["energy_residual"], np.nan)   # log scale: 0 is not drawn
        right.semilogy(h["t"], residual, line, marker="o", markersize=2, label=style.problem_label(h.params))
    left.plot([], [], "k-", label="original problem")
    left.plot([], [], "k--", label="penalty problem")
    left.set_title("energies at $t_n$ and cumulative dissipations and work")
    left.legend(fontsize=7, loc="lower right")
    right.set_title("energy balance residual of each step (relative to its largest term)")
    right.set_xlabel("t [s]")
    right.set_ylabel("|balance| / largest term")
    right.legend()
    style.log_floor(left, largest)
    style.note_versions(fig, paper_runs(results))
    return style.save(fig, out, "energy_history")


def zone_boundaries(results, out):
    """Zone boundaries x_B (first node at the bound) and x_C (first sticking node in contact)
    against t (left; dashed, the original problem's estimates between the nodes), and the zone
    counts AB, BC, CD (right); nan (not drawn) where absent."""
    fig, (left, right) = plt.subplots(1, 2)
    tables = []
    for problem, line in zip(PROBLEMS, ({"linestyle": "-"}, {"linestyle": "none", "marker": "o", "markersize": 2.5})):
        tables.append(runfiles.read_table(os.path.join(results, f"paper-{problem}", "contact.txt")))
        h = runfiles.read_table(os.path.join(results, f"paper-{problem}", "contact_history.txt"))
        name = style.problem_label(h.params)
        left.plot(h["t"], h["x_B"], color="tab:orange", label=f"$x_B$, {name}", **line)
        left.plot(h["t"], h["x_C"], color="tab:purple", label=f"$x_C$, {name}", **line)
        if problem == PROBLEMS[0] and "x_B_estimate" in h.columns:   # between the nodes (docs/design.md)
            left.plot(h["t"], h["x_B_estimate"], color="tab:orange", linestyle="--", linewidth=0.8,
                      label=f"$x_B$ between the nodes, {name}")
            left.plot(h["t"], h["x_C_estimate"], color="tab:purple", linestyle="--", linewidth=0.8,
                      label=f"$x_C$ between the nodes, {name}")
        counts = style.paper_segment_counts(h)
        for segment in style.PAPER_SEGMENTS:
            right.plot(h["t"], counts[segment.name], color=segment.color,
                       label=f"{segment.name} ({segment.meaning}), {problem}", **line)
    left.set_title("zone boundaries on $\\Gamma_3$")
    left.set_xlabel("t [s]")
    left.set_ylabel("x [m]")
    left.legend(fontsize=7)
    right.set_title("nodes per zone on $\\Gamma_3$")
    right.set_xlabel("t [s]")
    right.set_ylabel("nodes")
    right.legend(fontsize=7)
    style.least_span(left, gamma3_length(*tables))
    style.note_versions(fig, paper_runs(results))
    return style.save(fig, out, "zone_boundaries")


# ---------------------------------------------------------------- the scenes of edp/scenes/
SCENES = ("unloading", "cylinder", "bound-profile", "power-damping")


def scene_run(results, name):
    """DIR/scenes/NAME (written by ./run.sh), its contact.txt and contact_history.txt."""
    folder = os.path.join(results, "scenes", name)
    require(os.path.join(folder, "summary.txt"), f"./run.sh (the run of edp/scenes/{name}.scene)")
    c = runfiles.read_table(os.path.join(folder, "contact.txt"))
    return folder, c, runfiles.read_table(os.path.join(folder, "contact_history.txt"))


def scene_unloading(results, out):
    """The unloading scene: the contact force follows the load up and down (left), the zones
    form while it rises and free up while it falls (right)."""
    folder, c, h = scene_run(results, "unloading")
    fig, (left, right) = plt.subplots(1, 2)
    left.plot(h["t"], h["normal_force"], label=r"normal force $\sum_i w_i\, p_{\nu,i}$")
    left.plot(h["t"], h["tangential_force"], label=r"tangential force $\sum_i w_i\, \lambda_{\tau,i}$")
    twin = left.twinx()
    twin.plot(h["t"], runfiles.SceneLoads(folder).h(h["t"]), "k:", linewidth=0.8)
    twin.set_ylabel("load factor h(t) (dotted)")
    left.set_xlabel("t [s]")
    left.set_ylabel("force per unit thickness [GPa m]")
    left.set_title(f"loaded, then unloaded: f2 = {c.params['load']} h(t)")
    left.legend(fontsize=7)
    style.least_span(left, style.scales(c).force)
    style.least_span(twin, 1.0)                          # h(t): a factor
    style.zone_counts_plot(right, h)
    return style.save(fig, out, "scene_unloading")


def scene_cylinder(results, out):
    """The cylinder scene: the deformed half cylinder near its lowest point (left, with the
    zones of its contact nodes) and the velocities and stresses along the arc at T, relative
    to the node's bound g and force scale p(g) (right)."""
    folder, c, h = scene_run(results, "cylinder")
    f = runfiles.read_table(os.path.join(folder, "fields.txt"))
    mesh = runfiles.read_msh22(os.path.join(folder, "mesh.msh"))
    fig, (left, right) = plt.subplots(1, 2)
    tri = mtri.Triangulation(f["x"] + f["u_x"], f["y"] + f["u_y"], mesh.triangles)
    left.triplot(tri, color="0.6", linewidth=0.3)
    zones = style.run_zones(folder)
    zone, touching = c.codes("zone", 0, len(zones) - 1), c.codes("normal_status", 0, 2) > 0
    for z in zones:                                     # the nodes in contact (normal status 1 or 2)
        mask = (zone == z.code) & touching
        if mask.any():
            left.plot(c["x"][mask], c["y"][mask], "o", color=z.color, label=f"{z.name}: {int(mask.sum())} nodes")
    left.set_aspect("equal")
    left.set_xlabel("x [m] (at T, displaced)")
    left.set_ylabel("y [m]")
    left.set_title("deformed mesh at T, contact nodes by zone (undeformed)")
    left.legend(fontsize=7, loc="upper left")
    g, scale = c.finite("g", "force_scale")
    right.plot(c["x"], c["v_nu"] / g, "o-", markersize=5, label=r"$v_\nu / g$")
    right.plot(c["x"], c["p_nu"] / scale, "s--", markersize=2, label=r"$p_\nu / p(g)$ (= $v_\nu / g$ where damped: p is linear)")
    right.plot(c["x"], c["lambda_tau"] / scale, "^-", label=r"$\lambda_\tau / p(g)$")
    right.axhline(1.0, color="k", linewidth=0.8, linestyle="--", label="the bound")
    right.set_xlabel("x [m] of the contact node")
    right.set_title(f"along the arc at T = {c.params['T']} (each node its own normal)")
    right.legend(fontsize=7)
    style.least_span(right, 1.0)                         # ratios to g and p(g)
    return style.save(fig, out, "scene_cylinder")


def scene_bound_profile(results, out):
    """The bound-profile scene: v_nu at T under g(x) rising along Gamma3 (left) and the
    boundary x_B of the zone at the bound against t, with the paper's constant g (right)."""
    folder, c, h = scene_run(results, "bound-profile")
    paper = os.path.join(results, "paper-original")
    fig, (left, right) = plt.subplots(1, 2)
    left.plot(c["x"], c["v_nu"], "o-", label=r"$v_\nu$, bound-profile")
    left.plot(c["x"], c.finite("g")[0], "k--", linewidth=0.8, label="g(x) (bound_profile)")
    pc = runfiles.read_table(os.path.join(paper, "contact.txt"))
    left.plot(pc["x"], pc["v_nu"], ".", color="0.5", label=fr"$v_\nu$, paper (g = {pc['g'].max():g})")
    left.set_xlabel("x [m]")
    left.set_ylabel("velocity [m/s]")
    left.set_title(f"normal velocity on $\\Gamma_3$ at T = {c.params['T']}")
    left.legend(fontsize=7)
    ph = runfiles.read_table(os.path.join(paper, "contact_history.txt"))
    right.plot(h["t"], h["x_B"], label="$x_B$, bound-profile")
    right.plot(ph["t"], ph["x_B"], color="0.5", label="$x_B$, paper")
    right.set_xlabel("t [s]")
    right.set_ylabel("x [m]")
    right.set_title("first node at the bound, $x_B$")
    right.legend(fontsize=7)
    style.least_span(left, style.scales(c, pc).velocity)
    style.least_span(right, gamma3_length(c, pc))
    style.note_versions(fig, [folder, paper])
    return style.save(fig, out, "scene_bound_profile")


def damped_response(folder):
    """The damped response p(r) the law gave the run's nodes, 0 <= r <= g: the pairs (v_nu,
    damped_response) of contact_nodes_history.txt at every recorded step (and of contact.txt
    at T), sorted by v_nu (r, p(r)), and the largest g."""
    rows = [runfiles.read_table(os.path.join(folder, name)) for name in ("contact_nodes_history.txt", "contact.txt")]
    r, p, g = (np.concatenate([table.finite(column)[0] for table in rows]) for column in ("v_nu", "damped_response", "g"))
    kept = (r >= 0) & (r <= g)
    r, order = np.unique(r[kept], return_index=True)
    return r, p[kept][order], float(g.max())


def scene_power_damping(results, out):
    """The power-damping scene: p(r) = C r^2 with the paper's p(g), as the law gave it to the
    contact nodes over the run, the damped response of every node at T on it (left), and v_nu
    along Gamma3 against the paper's (right)."""
    folder, c, h = scene_run(results, "power-damping")
    paper = os.path.join(results, "paper-original")
    pc = runfiles.read_table(os.path.join(paper, "contact.txt"))
    r, p, g = damped_response(folder)
    fig, (left, right) = plt.subplots(1, 2)
    left.plot(r, p, "-", label="p(r), power-damping")
    left.plot(*damped_response(paper)[:2], "--", color="0.5", label="p(r), paper")
    left.plot(c["v_nu"], c["damped_response"], "o", label=r"$(v_\nu, p(v_\nu))$ of the nodes at T")
    left.set_xlabel("normal velocity r [m/s]")
    left.set_ylabel("damped response [GPa]")
    left.set_title("the damped response")
    left.legend(fontsize=7)
    right.plot(c["x"], c["v_nu"], "o-", label=r"$v_\nu$, power-damping")
    right.plot(pc["x"], pc["v_nu"], ".", color="0.5", label=r"$v_\nu$, paper")
    bound_line(right, c, color="k", linewidth=0.8, linestyle="--")
    right.set_xlabel("x [m]")
    right.set_ylabel("velocity [m/s]")
    right.set_title(f"normal velocity on $\\Gamma_3$ at T = {c.params['T']}")
    right.legend(fontsize=7)
    scales = style.scales(c, pc)
    style.least_span(left, scales.velocity, "x")
    style.least_span(left, scales.stress)
    style.least_span(right, scales.velocity)
    style.note_versions(fig, [folder, paper])
    return style.save(fig, out, "scene_power_damping")


FIGURES = {"fig2": fig2_deformed, "fig3": fig3_contact_reactions, "fig4": fig4_velocities,
           "fig5": fig5_penalty_convergence, "contact_forces_history": contact_forces_history,
           "energy_history": energy_history, "zone_boundaries": zone_boundaries,
           "scene_unloading": scene_unloading, "scene_cylinder": scene_cylinder,
           "scene_bound_profile": scene_bound_profile, "scene_power_damping": scene_power_damping}


def main():
    runfiles.check_arguments("figures.py")                 # a name not in UTF-8: refused before anything
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--results", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("names", nargs="*", help="figures to draw: " + " ".join(FIGURES))
    args = parser.parse_args()
    runfiles.check_outputs("figures.py", [args.out])       # not written through a symbolic link
    unknown = [n for n in args.names if n not in FIGURES]
    if unknown:
        raise runfiles.InputError(f"no run folder '{runfiles.shown(unknown[0])}' and no figure named {runfiles.shown(unknown[0])} "
                               f"(figures: {' '.join(FIGURES)})")
    for problem in PROBLEMS:
        if not os.path.isfile(os.path.join(args.results, f"paper-{problem}", "summary.txt")):
            raise runfiles.InputError(f"no results in {runfiles.shown(args.results)}/paper-{problem}: run ./run.sh first")
    for name in args.names or FIGURES:
        print(f"figures.py: {name} -> {FIGURES[name](args.results, args.out)}")


if __name__ == "__main__":
    runfiles.run_tool("figures.py", main, code=2)
