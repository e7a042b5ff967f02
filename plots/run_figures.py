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
straight along x, otherwise the arc length; a Gamma3 in pieces (the mesh's contact lines
that do not join) is drawn in pieces, its gaps left blank. The zones are shaded from the
nodes' statuses wherever they lie, never in an assumed order.

Prints the files written, one a line; a note on stderr for each figure a run's files do not
allow. All or nothing (suite.FigureFiles): nothing is drawn over a file of figures/ that
figures.list does not list, and a failure leaves every figures/ as it was. Corrupt inputs
(a status or zone code out of its range, nan or inf in a value drawn) are refused.
"""
import argparse
import functools
import os
import sys

import matplotlib.collections as mcollections
import matplotlib.colors as mcolors
import matplotlib.tri as mtri
import numpy as np

import suite

plt = suite.pyplot()
ZONE_COLORS = {zone.code: zone.color for zone in suite.ZONES}


class Run:
    """A run folder: its name, contact.txt at T, mesh, law (suite.RunScene, from its
    scene.scene), the zone code of each contact node, where the nodes lie along Gamma3
    (position, axis label) and the piece of Gamma3 each lies on (suite.contact_pieces)."""

    def __init__(self, folder):
        self.folder = suite.run_folder(folder)
        self.name = os.path.basename(os.path.normpath(os.path.abspath(folder)))
        self.contact = c = suite.read_table(self.file("contact.txt"))
        c.finite(*CONTACT_DRAWN)
        self.mesh = suite.read_msh22(self.file("mesh.msh"))
        self.law = suite.RunScene(folder, c.params, required=True)
        self.zones = suite.zone_codes(c.codes("normal_status", 0, 2), c.codes("tangential_status", 0, 1))
        self.position, self.axis = suite.contact_position(self.mesh, c["x"], c["y"])
        self.pieces = suite.contact_pieces(self.mesh, c["x"], c["y"])

    def file(self, name):
        return os.path.join(self.folder, name)

    def figure(self, name):
        """The path of a figure of this run: RUN_DIR/figures/NAME."""
        return os.path.join(self.folder, "figures", name)


CONTACT_DRAWN = ("x", "y", "v_nu", "p_nu", "lambda_nu", "lambda_tau", "friction_bound")   # contact.txt


def contact_panels(fig_title, runs, shade):
    """Three panels along Gamma3 at T (v_nu and g; p_nu; lambda_tau and the friction bound)
    for each run, one colour per run, the zones of the first shaded when shade."""
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(11, 8.5))
    for run, color in zip(runs, plt.rcParams["axes.prop_cycle"].by_key()["color"]):
        c = run.contact
        s, v_nu, g, p_nu, lambda_nu, lambda_tau, bound = suite.along_gamma3(
            run.position, run.pieces, c["v_nu"], run.law.g(c["x"]), c["p_nu"], c["lambda_nu"], c["lambda_tau"],
            c["friction_bound"])                        # broken across the gaps between pieces of Gamma3
        name = "" if shade else f"{run.name}: "
        axes[0].plot(s, v_nu, "o-", color=color, label=f"{name}$v_\\nu$")
        axes[0].plot(s, g, "--", color=color, linewidth=0.8, label=f"{name}bound g")
        axes[1].plot(s, p_nu, "o-", color=color, label=f"{name}$p_\\nu = p(v_\\nu) + \\lambda_\\nu$")
        axes[1].plot(s, p_nu - lambda_nu, ":", color=color, label=f"{name}damped response $p(v_\\nu)$")
        axes[2].plot(s, lambda_tau, "o-", color=color, label=f"{name}$\\lambda_\\tau$")
        axes[2].plot(s, bound, "--", color=color, linewidth=0.8, label=f"{name}$\\pm$ friction bound")
        axes[2].plot(s, -bound, "--", color=color, linewidth=0.8)
    for ax, unit in zip(axes, ("velocity [m/s]", "pressure [GPa]", "tangential stress [GPa]")):
        ax.set_ylabel(unit)
        handles = ax.get_legend_handles_labels()[0]
        if shade:
            suite.shade_stretches(ax, suite.stretches(runs[0].position, runs[0].zones, runs[0].pieces), ZONE_COLORS)
            handles += suite.zone_patches(runs[0].zones, alpha=0.3) if ax is axes[0] else []
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes[2].set_xlabel(runs[0].axis if len({run.axis for run in runs}) == 1 else "position along $\\Gamma_3$ [m]")
    axes[0].set_title(fig_title)
    return fig


def contact_at_T(run):
    """v_nu with g, p_nu, lambda_tau with +-friction_bound along Gamma3 at T, zones shaded."""
    p = run.contact.params
    return contact_panels(f"{run.name}: contact on $\\Gamma_3$ at T = {p['T']} ({suite.problem_label(p)})", [run], True)


def compare_contact(runs):
    """The contact quantities at T of several runs, overlaid (into the first run's figures/)."""
    return contact_panels(f"contact on $\\Gamma_3$ at T: {', '.join(run.name for run in runs)}", runs, False)


def histories(run):
    """Against t: the contact forces, the nodes per zone, the energy terms, the energy balance."""
    h = suite.read_table(run.file("contact_history.txt"))
    e = suite.read_table(run.file("history.txt"))
    h.finite("t", "normal_force", "tangential_force", *(zone.column for zone in suite.ZONES))
    e.finite("t", "energy_residual", *(column for column, _, _ in suite.ENERGY_TERMS))
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
    return fig


def deformed(run):
    """The deformed mesh at T (magnified when the displacements are small, the factor in the
    title), coloured by the von Mises stress (by |v| without that column), the undeformed
    outline in grey, the contact nodes by zone; the figure shaped to the body."""
    f = suite.read_table(run.file("fields.txt"))
    xy, u = np.column_stack(f.finite("x", "y")), np.column_stack(f.finite("u_x", "u_y"))
    if len(xy) != len(run.mesh.xy):
        raise suite.InputError(f"{f.path}: {len(xy)} vertices, but {len(run.mesh.xy)} in mesh.msh")
    factor = suite.magnification(np.ptp(xy, axis=0).max(), np.hypot(*u.T).max())
    moved = xy + factor * u
    if "von_mises" in f:
        values, label = f.finite("von_mises")[0], "von Mises stress [GPa]"
    else:
        values, label = np.hypot(*f.finite("v_x", "v_y")), "|v| [m/s] (fields.txt has no von_mises)"
    scale = "true scale" if factor == 1 else f"displacements magnified {factor:g} times"
    fig, ax = suite.body_figure(np.r_[xy, moved], f"{run.name}: deformed at T = {f.params['T']} ({scale}), "
                                                  "contact nodes by zone", legend=(1 + len(set(run.zones)), 3, 2.4))
    shown = ax.tripcolor(mtri.Triangulation(*moved.T, run.mesh.triangles), values, shading="gouraud", cmap="viridis")
    fig.colorbar(shown, ax=ax, label=label, shrink=0.8)
    edges = suite.boundary_edges(run.mesh.triangles)
    ax.add_collection(mcollections.LineCollection(xy[edges], colors="0.6", linewidths=0.8, label="undeformed outline"))
    nodes = suite.nearest(xy, np.c_[run.contact["x"], run.contact["y"]])
    ax.scatter(*moved[nodes].T, c=[ZONE_COLORS[z] for z in run.zones], s=14, edgecolors="k", linewidths=0.4, zorder=3)
    handles = ax.get_legend_handles_labels()[0] + suite.zone_patches(run.zones)
    ax.legend(handles=handles, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12),
              ncol=suite.legend_columns(fig, 3, 2.4))
    return fig


def zone_history(run):
    """contact_nodes_history.txt as (t of the recorded steps, zones (steps, nodes)), the
    nodes in the order of contact.txt."""
    h = suite.read_table(run.file("contact_nodes_history.txt"))
    steps, nodes = np.unique(h["step"]), len(run.contact)
    if len(h) != len(steps) * nodes or not np.array_equal(h["node"], np.tile(np.arange(nodes), len(steps))):
        raise suite.InputError(f"{h.path}: not {nodes} rows (nodes 0 to {nodes - 1}) for each of its {len(steps)} steps")
    zones = h.codes("zone", 0, len(suite.ZONES) - 1)
    return h.finite("t")[0][::nodes], zones.reshape(len(steps), nodes)


def steps_against_t(t, values):
    """The path (values, times) of values recorded at the times t (one a step) drawn as steps
    up the t axis: each value held from the time before its own (0 before the first) to its
    own, as the rows of zone_map() are."""
    before = np.r_[min(0.0, t[0]), t[:-1]]
    return np.repeat(values, 2), np.c_[before, t].ravel()


def boundary_label(values, name, meaning, none, edges):
    """The legend entry of x_B or x_C: what it means, or, where its line cannot be seen,
    why: no value at any step, or the same value at every step on the map's edge."""
    found = values[np.isfinite(values)]
    if not found.size:
        return f"{name}: {none} at any step"
    if np.ptp(found) == 0 and (found[0] <= edges[0] or found[0] >= edges[-1]):
        return f"{name}: {found[0]:g} at every step{'' if found.size == values.size else ' that has one'} ({meaning})"
    return f"{name}: {meaning}"


def zone_map(run):
    """The zone of every contact node (columns, at its position along Gamma3; the gaps between
    pieces of Gamma3 blank) at every recorded step (rows: a step's zones drawn from the
    previous recorded time to its own), with the steps of x_B(t) and x_C(t) of
    contact_history.txt over it when the position is x."""
    t, zones = zone_history(run)
    edges, columns = suite.map_columns(run.position, run.pieces)
    fig, ax = plt.subplots(figsize=(10, 6))
    ax.grid(False)
    colors = mcolors.ListedColormap([zone.color for zone in suite.ZONES])
    norm = mcolors.BoundaryNorm(np.arange(len(suite.ZONES) + 1) - 0.5, len(suite.ZONES))
    shown = np.ma.masked_array(zones[:, columns], mask=np.tile(columns < 0, (len(t), 1)))
    ax.pcolormesh(edges, np.r_[min(0.0, t[0]), t], shown, cmap=colors, norm=norm)
    handles = suite.zone_patches()
    if run.axis == "x [m]":
        h = suite.read_table(run.file("contact_history.txt"))
        for column, style, color, meaning, none in (
                ("x_B", "-", "k", "first node at the bound", "no node at the bound"),
                ("x_C", "--", "tab:blue", "first sticking node in contact", "no sticking node in contact")):
            values = h[column]
            if np.isinf(values).any():
                raise suite.InputError(f"{h.path}: {column} is infinite at a step")
            label = boundary_label(values, f"${column[0]}_{column[2]}$", meaning, none, edges)
            handles += ax.plot(*steps_against_t(h.finite("t")[0], values), style, color=color, linewidth=1.5,
                               label=label)
    pad = 0.015 * (edges[-1] - edges[0])           # a line at the map's edge (x_B = 0) stays in sight
    ax.set_xlim(edges[0] - pad, edges[-1] + pad)
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_xlabel(run.axis)
    ax.set_ylabel("t [s]")
    ax.set_title(f"{run.name}: zones on $\\Gamma_3$ against t" + (", gaps between its pieces blank"
                                                                   if len(set(run.pieces)) > 1 else ""))
    return fig


# The figures of one run and the files each needs beyond contact.txt, mesh.msh and scene.scene.
FIGURES = (("contact_at_T", contact_at_T, ()), ("histories", histories, ("contact_history.txt", "history.txt")),
           ("deformed", deformed, ("fields.txt",)),
           ("zone_map", zone_map, ("contact_nodes_history.txt", "contact_history.txt")))


def plan(runs):
    """[(path, function drawing it)] of every figure the runs' files allow (a note on stderr
    for each one left out), and compare_contact.png into the first one's figures/ when there
    are several."""
    figures = []
    for run in runs:
        for name, figure, needs in FIGURES:
            missing = [need for need in needs if not os.path.isfile(run.file(need))]
            if missing:
                print(f"run_figures.py: {run.folder}: no {name}.png ({' and '.join(missing)} missing)", file=sys.stderr)
            else:
                figures.append((run.figure(name + ".png"), functools.partial(figure, run)))
    if len(runs) > 1:
        figures.append((runs[0].figure("compare_contact.png"), functools.partial(compare_contact, runs)))
    return figures


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folders", nargs="+", metavar="RUN_DIR")
    runs = [Run(folder) for folder in parser.parse_args().folders]      # every folder checked first
    figures = plan(runs)
    files = suite.FigureFiles([path for path, _ in figures])            # refuses to draw over a file not ours
    for path, figure in figures:
        files.save(figure(), path)
    files.commit()
    for path, _ in figures:
        print(path)


if __name__ == "__main__":
    suite.run_tool("run_figures.py", main, code=2)
