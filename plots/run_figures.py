#!/usr/bin/python3
"""Figures of any run of edp/solve.edp, drawn into the run's own folder.

  run_figures.py RUN_DIR [RUN_DIR ...]          (./run.sh figures RUN_DIR ...)

A run folder holds summary.txt and run.complete (docs/design.md, "Output files"). Each
RUN_DIR/figures/ receives the figures its files allow (docs/figures.md):
  contact_at_T.png   v_nu and g, p_nu, lambda_tau and the friction bound along Gamma3 at T
  histories.png      contact forces, nodes per zone, energy terms and balance against t
  deformed.png       the deformed body at T coloured by the von Mises stress (or |v|)
  zone_map.png       the zone of every contact node against its position and t
                     (from contact_nodes_history.txt, when the run wrote it)
With several folders, compare_contact.png (the quantities at T of every run, overlaid)
goes into the first one's figures/. The position along Gamma3 is x where Gamma3 is
straight along x, otherwise the arc length. The zones are shaded from the nodes'
statuses wherever they lie, never in an assumed order. Prints the files written.
"""
import argparse
import os

import matplotlib.collections as mcollections
import matplotlib.colors as mcolors
import matplotlib.tri as mtri
import numpy as np

import suite

plt = suite.pyplot()
ZONE_COLORS = {zone.code: zone.color for zone in suite.ZONES}


class Run:
    """A run folder: its name, contact.txt at T, mesh, law (suite.RunScene), the zone code of
    each contact node and where the nodes lie along Gamma3 (position, axis label)."""

    def __init__(self, folder):
        self.folder = suite.run_folder(folder)
        self.name = os.path.basename(os.path.normpath(os.path.abspath(folder)))
        self.contact = c = suite.read_table(self.file("contact.txt"))
        self.mesh = suite.read_msh22(self.file("mesh.msh"))
        self.law = suite.RunScene(folder, c.params)
        self.zones = suite.zone_codes(c["normal_status"], c["tangential_status"])
        self.position, self.axis = suite.contact_position(self.mesh, c["x"], c["y"])

    def file(self, name):
        return os.path.join(self.folder, name)

    def out(self):
        return os.path.join(self.folder, "figures")


def contact_panels(fig_title, runs, shade):
    """Three panels along Gamma3 at T (v_nu and g; p_nu; lambda_tau and the friction bound)
    for each run, one colour per run, the zones of the first shaded when shade."""
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(11, 8.5))
    for run, color in zip(runs, plt.rcParams["axes.prop_cycle"].by_key()["color"]):
        c, s = run.contact, run.position
        name = "" if shade else f"{run.name}: "
        axes[0].plot(s, c["v_nu"], "o-", color=color, label=f"{name}$v_\\nu$")
        axes[0].plot(s, run.law.g(c["x"]), "--", color=color, linewidth=0.8, label=f"{name}bound g")
        axes[1].plot(s, c["p_nu"], "o-", color=color, label=f"{name}$p_\\nu = p(v_\\nu) + \\lambda_\\nu$")
        axes[1].plot(s, c["p_nu"] - c["lambda_nu"], ":", color=color, label=f"{name}damped response $p(v_\\nu)$")
        axes[2].plot(s, c["lambda_tau"], "o-", color=color, label=f"{name}$\\lambda_\\tau$")
        axes[2].plot(s, c["friction_bound"], "--", color=color, linewidth=0.8, label=f"{name}$\\pm$ friction bound")
        axes[2].plot(s, -c["friction_bound"], "--", color=color, linewidth=0.8)
    for ax, unit in zip(axes, ("velocity [m/s]", "pressure [GPa]", "tangential stress [GPa]")):
        ax.set_ylabel(unit)
        handles = ax.get_legend_handles_labels()[0]
        if shade:
            suite.shade_stretches(ax, suite.stretches(runs[0].position, runs[0].zones), ZONE_COLORS)
            handles += suite.zone_patches(runs[0].zones, alpha=0.3) if ax is axes[0] else []
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes[2].set_xlabel(runs[0].axis if len({run.axis for run in runs}) == 1 else "position along $\\Gamma_3$ [m]")
    axes[0].set_title(fig_title)
    return fig


def contact_at_T(run):
    """v_nu with g, p_nu, lambda_tau with +-friction_bound along Gamma3 at T, zones shaded."""
    p = run.contact.params
    fig = contact_panels(f"{run.name}: contact on $\\Gamma_3$ at T = {p['T']} ({suite.problem_label(p)})", [run], True)
    return suite.save(fig, run.out(), "contact_at_T")


def compare_contact(runs):
    """The contact quantities at T of several runs, overlaid (into the first run's figures/)."""
    fig = contact_panels(f"contact on $\\Gamma_3$ at T: {', '.join(run.name for run in runs)}", runs, False)
    return suite.save(fig, runs[0].out(), "compare_contact")


def histories(run):
    """Against t: the contact forces, the nodes per zone, the energy terms, the energy balance."""
    h = suite.read_table(run.file("contact_history.txt"))
    e = suite.read_table(run.file("history.txt"))
    fig, ((forces, zones), (energy, residual)) = plt.subplots(2, 2, figsize=(11, 7))
    forces.plot(h["t"], h["normal_force"], label=r"normal force $\sum_i w_i\, p_{\nu,i}$")
    forces.plot(h["t"], h["tangential_force"], label=r"tangential force $\sum_i w_i\, \lambda_{\tau,i}$")
    forces.set_xlabel("t [s]")
    forces.set_ylabel("force per unit thickness [GPa m]")
    forces.set_title(f"{run.name}: contact forces on $\\Gamma_3$")
    forces.legend(fontsize=7)
    suite.zone_counts_plot(zones, h)
    suite.energy_terms_plot(energy, e)
    energy.set_title("energies at $t_n$, cumulative dissipations and work")
    energy.legend(fontsize=7)
    residual.semilogy(e["t"], np.where(e["energy_residual"] > 0, e["energy_residual"], np.nan), "o-", markersize=2)
    residual.set_xlabel("t [s]")
    residual.set_ylabel("|balance| / largest term")
    residual.set_title("energy balance residual of each step")
    return suite.save(fig, run.out(), "histories")


def deformed(run):
    """The deformed mesh at T (magnified when the displacements are small, the factor in the
    title), coloured by the von Mises stress (by |v| without that column), the undeformed
    outline in grey, the contact nodes by zone."""
    f = suite.read_table(run.file("fields.txt"))
    xy, u = np.c_[f["x"], f["y"]], np.c_[f["u_x"], f["u_y"]]
    if len(xy) != len(run.mesh.xy):
        raise suite.InputError(f"{f.path}: {len(xy)} vertices, but {len(run.mesh.xy)} in mesh.msh")
    factor = suite.magnification(np.ptp(xy, axis=0).max(), np.hypot(*u.T).max())
    moved = xy + factor * u
    if "von_mises" in f:
        values, label = f["von_mises"], "von Mises stress [GPa]"
    else:
        values, label = np.hypot(f["v_x"], f["v_y"]), "|v| [m/s] (fields.txt has no von_mises)"
    fig, ax = plt.subplots(figsize=(10, 6))
    shown = ax.tripcolor(mtri.Triangulation(*moved.T, run.mesh.triangles), values, shading="gouraud", cmap="viridis")
    fig.colorbar(shown, ax=ax, label=label, shrink=0.8)
    edges = suite.boundary_edges(run.mesh.triangles)
    ax.add_collection(mcollections.LineCollection(xy[edges], colors="0.6", linewidths=0.8, label="undeformed outline"))
    nodes = suite.nearest(xy, np.c_[run.contact["x"], run.contact["y"]])
    ax.scatter(*moved[nodes].T, c=[ZONE_COLORS[z] for z in run.zones], s=14, edgecolors="k", linewidths=0.4, zorder=3)
    handles = ax.get_legend_handles_labels()[0] + suite.zone_patches(run.zones)
    ax.legend(handles=handles, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    scale = "true scale" if factor == 1 else f"displacements magnified {factor:g} times"
    ax.set_title(f"{run.name}: deformed at T = {f.params['T']} ({scale}), contact nodes by zone")
    return suite.save(fig, run.out(), "deformed")


def zone_history(run):
    """contact_nodes_history.txt as (t of the recorded steps, zones (steps, nodes)), the
    nodes in the order of contact.txt."""
    h = suite.read_table(run.file("contact_nodes_history.txt"))
    steps, nodes = np.unique(h["step"]), len(run.contact)
    if len(h) != len(steps) * nodes or not np.array_equal(h["node"], np.tile(np.arange(nodes), len(steps))):
        raise suite.InputError(f"{h.path}: not {nodes} rows (nodes 0 to {nodes - 1}) for each of its {len(steps)} steps")
    return h["t"][::nodes], h["zone"].astype(int).reshape(len(steps), nodes)


def zone_map(run):
    """The zone of every contact node (columns, at its position along Gamma3) at every
    recorded step (rows: a step's zones drawn from the previous recorded time to its own),
    with x_B(t) and x_C(t) of contact_history.txt over it when the position is x."""
    t, zones = zone_history(run)
    order = np.argsort(run.position, kind="stable")
    fig, ax = plt.subplots(figsize=(10, 6))
    ax.grid(False)
    colors = mcolors.ListedColormap([zone.color for zone in suite.ZONES])
    norm = mcolors.BoundaryNorm(np.arange(len(suite.ZONES) + 1) - 0.5, len(suite.ZONES))
    ax.pcolormesh(suite.halfway_edges(run.position[order]), np.r_[min(0.0, t[0]), t], zones[:, order],
                  cmap=colors, norm=norm)
    handles = suite.zone_patches()
    if run.axis == "x [m]":
        h = suite.read_table(run.file("contact_history.txt"))
        handles += ax.plot(h["x_B"], h["t"], "k.-", linewidth=1.5, label="$x_B$: first node at the bound")
        handles += ax.plot(h["x_C"], h["t"], ".--", color="tab:blue", linewidth=1.5,
                           label="$x_C$: first sticking node in contact")
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_xlabel(run.axis)
    ax.set_ylabel("t [s]")
    ax.set_title(f"{run.name}: zones on $\\Gamma_3$ against t")
    return suite.save(fig, run.out(), "zone_map")


# The figures of one run and the files each needs beyond contact.txt and mesh.msh.
FIGURES = ((contact_at_T, ()), (histories, ("contact_history.txt", "history.txt")),
           (deformed, ("fields.txt",)), (zone_map, ("contact_nodes_history.txt", "contact_history.txt")))


def draw(run):
    """The figures of one run its files allow; a note for each one left out."""
    written = []
    for figure, needs in FIGURES:
        missing = [name for name in needs if not os.path.isfile(run.file(name))]
        if missing:
            print(f"run_figures.py: {run.folder}: no {figure.__name__} ({' and '.join(missing)} missing)")
        else:
            written.append(figure(run))
    return written


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folders", nargs="+", metavar="RUN_DIR")
    runs = [Run(folder) for folder in parser.parse_args().folders]      # every folder checked first
    written = [path for run in runs for path in draw(run)]
    if len(runs) > 1:
        written.append(compare_contact(runs))
    suite.list_figures(written)
    for path in written:
        print(path)


if __name__ == "__main__":
    suite.run_tool("run_figures.py", main, code=2)
