#!/usr/bin/python3
"""Figures of any run of edp/solve.edp, drawn into the run's own folder.

  run_figures.py RUN_DIR [RUN_DIR ...]          (./run.sh figures RUN_DIR ...)

A run folder holds summary.txt and run.complete (docs/design.md, "Output files"). Each
RUN_DIR/figures/ receives the figures its files allow (docs/figures.md):
  contact_at_T.png   v_nu and g, p_nu, lambda_tau and the friction bound along Gamma3 at T,
                     the run's own error estimates under the title (summary.txt)
  histories.png      contact forces, nodes per zone, energy terms and balance against t
  deformed.png       the deformed body at T coloured by the von Mises stress
  zone_map.png       the zone of every contact node against its position and t
                     (from contact_nodes_history.txt, when the run wrote it)
With several folders, compare_contact.png (the quantities at T of every run, overlaid)
goes into the first one's figures/. The position along Gamma3 is x where Gamma3 is
straight along x, otherwise the arc length; a Gamma3 in pieces (the mesh's contact lines
that do not join) is drawn in pieces, its gaps left blank. The bound g, the damped response
p(v_nu), the friction bound and the zones are the law's own columns of contact.txt; the zones
are shaded wherever the nodes lie, never in an assumed order.

A 3D run (summary.txt: dimension 3) gets the same files, drawn for its body of tetrahedra
(the functions ending in 3): Gamma3 seen from outside in its own plane coordinates
(face3d.ContactFace) for contact_at_T.png (maps of v_nu, p_nu, |v_tau| with the slip
arrows, and the friction cone) and zone_map.png (the zones at T); the outer surface
deformed, seen from above and below, for deformed.png; the forces in both tangential
directions in histories.png. In compare_contact.png its nodes are dots at their first
coordinate on Gamma3.

Prints the files written, one a line; a note on stderr for each figure a run's files do not
allow. All or nothing (figurefiles.FigureFiles): nothing is drawn over a file of figures/ that
figures.list does not list, and a failure leaves every figures/ as it was. Corrupt inputs
(a status or zone code out of its range, nan or inf in a value drawn) are refused.
"""
import argparse
import functools
import os
import textwrap
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import matplotlib.collections as mcollections
import matplotlib.colors as mcolors
import matplotlib.lines as mlines
import matplotlib.ticker as mticker
import matplotlib.tri as mtri
import numpy as np

import face3d
import figurefiles
import gamma3
import runfiles
import style

plt = style.pyplot()


class Run:
    """A run folder: its name, its zones (zone_types: style.run_zones), contact.txt at T (its
    statuses and zone codes checked), mesh, the statuses and zone code of each contact node
    (normal, tangential, zones), where the nodes lie along Gamma3 (position, axis label), the
    piece of Gamma3 each lies on (gamma3.contact_pieces) and the natural scales of its
    quantities (scales: style.scales, the least spans of its figures' axes)."""

    def __init__(self, folder):
        self.folder = runfiles.run_folder(folder)
        self.name = os.path.basename(os.path.normpath(os.path.abspath(folder)))
        self.dimension = runfiles.run_dimension(folder)
        self.contact = c = runfiles.read_table(self.file("contact.txt"))
        self.normal, self.tangential = c.codes("normal_status", 0, 2), c.codes("tangential_status", 0, 1)
        self.zone_types = style.run_zones(folder)
        self.zones = c.codes("zone", 0, len(self.zone_types) - 1)
        self.scales = style.scales(c)
        if self.dimension == 3:
            self.init3()
            return
        c.finite(*CONTACT_DRAWN)
        self.mesh = runfiles.read_msh22(self.file("mesh.msh"))
        self.position, self.axis = gamma3.contact_position(self.mesh, c["x"], c["y"])
        self.pieces = gamma3.contact_pieces(self.mesh, c["x"], c["y"])

    def init3(self):
        """A 3D run: Gamma3 seen from outside (face3d.ContactFace); for compare_contact, the
        nodes' position is their first coordinate on the face, Gamma3 one piece."""
        c = self.contact
        c.finite(*CONTACT_DRAWN, *CONTACT_DRAWN_3D)
        self.mesh = runfiles.read_msh3(self.file("mesh.msh"))
        self.face = face3d.ContactFace(self.mesh, c, self.file("mesh.msh"))
        self.position, self.axis = self.face.uv[:, 0], self.face.labels[0]
        self.pieces = np.zeros(len(c), dtype=int)

    def file(self, name):
        return os.path.join(self.folder, name)

    def figure(self, name):
        """The path of a figure of this run: RUN_DIR/figures/NAME."""
        return os.path.join(self.folder, "figures", name)


CONTACT_DRAWN = ("x", "y", "v_nu", "p_nu", "lambda_tau", "g", "damped_response", "friction_bound")   # contact.txt
CONTACT_DRAWN_3D = ("z", "v_tau", "v_tau2", "lambda_tau2")                                # and in 3D


def contact_panels(fig_title, runs, shade):
    """Three panels along Gamma3 at T (v_nu and g; p_nu; lambda_tau and the friction bound)
    for each run, one colour per run, the zones of the first shaded when shade."""
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(11, 8.5))
    for run, color in zip(runs, plt.rcParams["axes.prop_cycle"].by_key()["color"]):
        c = run.contact
        if run.dimension == 3:
            nodes_in_panels(axes, run, color, "" if shade else f"{run.name}: ")
            continue
        s, v_nu, g, p_nu, damped, lambda_tau, bound = gamma3.along_gamma3(
            run.position, run.pieces, c["v_nu"], c["g"], c["p_nu"], c["damped_response"], c["lambda_tau"],
            c["friction_bound"])                        # broken across the gaps between pieces of Gamma3
        name = "" if shade else f"{run.name}: "
        axes[0].plot(s, v_nu, "o-", color=color, label=f"{name}$v_\\nu$")
        axes[0].plot(s, g, "--", color=color, linewidth=0.8, label=f"{name}bound g")
        axes[1].plot(s, p_nu, "o-", color=color, label=f"{name}$p_\\nu = p(v_\\nu) + \\lambda_\\nu$")
        axes[1].plot(s, damped, ":", color=color, label=f"{name}damped response $p(v_\\nu)$")
        axes[2].plot(s, lambda_tau, "o-", color=color, label=f"{name}$\\lambda_\\tau$")
        axes[2].plot(s, bound, "--", color=color, linewidth=0.8, label=f"{name}$\\pm$ friction bound")
        axes[2].plot(s, -bound, "--", color=color, linewidth=0.8)
    scales = [run.scales for run in runs]
    for ax, unit, scale in zip(axes, ("velocity [m/s]", "pressure [GPa]", "tangential stress [GPa]"),
                               ("velocity", "stress", "friction")):
        ax.set_ylabel(unit)
        style.least_span(ax, max(getattr(s, scale) for s in scales))      # round-off drawn flat
        handles = ax.get_legend_handles_labels()[0]
        if shade:
            gamma3.shade_stretches(ax, gamma3.stretches(runs[0].position, runs[0].zones, runs[0].pieces),
                                   {zone.code: zone.color for zone in runs[0].zone_types})
            handles += style.zone_patches(runs[0].zone_types, runs[0].zones, alpha=0.3) if ax is axes[0] else []
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes[2].set_xlabel(runs[0].axis if len({run.axis for run in runs}) == 1 else "position along $\\Gamma_3$ [m]")
    axes[0].set_title(fig_title)
    return fig


def nodes_in_panels(axes, run, color, name):
    """The nodes of a 3D run in the panels of contact_panels (compare_contact), each at its
    first coordinate on Gamma3 (ContactFace), as markers, not lines (nodes side by side on
    the face share a position): v_nu and g, p_nu and p(v_nu), the friction stress along
    that coordinate and +- the bound."""
    c, face = run.contact, run.face
    s, dash = run.position, dict(marker="_", linestyle="none", markersize=7, color=color)
    across = face3d.direction_name(face.t1)
    axes[0].plot(s, c["v_nu"], "o", color=color, label=f"{name}$v_\\nu$ (3D, every node)")
    axes[0].plot(s, c["g"], label=f"{name}bound g", **dash)
    axes[1].plot(s, c["p_nu"], "o", color=color, label=f"{name}$p_\\nu = p(v_\\nu) + \\lambda_\\nu$ (3D, every node)")
    axes[1].plot(s, c["damped_response"], ".", color=color, label=f"{name}damped response $p(v_\\nu)$")
    axes[2].plot(s, face.tangential(c["lambda_tau"], c["lambda_tau2"])[:, 0], "o", color=color,
                 label=f"{name}$\\lambda_\\tau$ along {across} (3D, every node)")
    axes[2].plot(s, c["friction_bound"], label=f"{name}$\\pm$ friction bound", **dash)
    axes[2].plot(s, -c["friction_bound"], **dash)


ESTIMATES = (("error_estimate_v_L2", "v", "{:.1e} (relative L$^2$)"),
             ("error_estimate_normal_force", "normal force", "{:.1e} (relative)"),
             ("error_estimate_x_B", "$x_B$", "$\\pm${:.1e} m (rough)"), ("error_estimate_x_C", "$x_C$", "$\\pm${:.1e} m (rough)"))


def estimate_note(run):
    """The run's own error estimates at T (summary.txt, docs/design.md "Error estimates") as a
    line of a title: each finite one, and the companion they come from or why there is none;
    "" for a run written before the suite made them."""
    summary = runfiles.read_summary(run.folder)
    if "error_estimate_source" not in summary:
        return ""
    source = summary["error_estimate_source"]
    shown = []
    for key, name, form in ESTIMATES:
        try:
            value = float(summary.get(key, "nan"))
        except ValueError:
            raise runfiles.InputError(f"{summary.source}: {key} is not a number") from None
        if np.isinf(value) or value < 0:
            raise runfiles.InputError(f"{summary.source}: {key} is {value}, not an error")
        if np.isfinite(value):                        # (no break inside an item)
            shown.append(f"{name} {form.format(value)}".replace(" ", "\u00a0"))
    if not shown:
        text = f"error estimates: none ({source.removeprefix('none: ')})"
    else:
        text = f"estimated error in space ({source.split(',')[0].split(' (')[0]}): {', '.join(shown)}"
    return "\n".join(textwrap.wrap(text, 110, break_long_words=False)).replace("\u00a0", " ")


def contact_at_T(run):
    """v_nu with g, p_nu, lambda_tau with +-friction_bound along Gamma3 at T, zones shaded; the
    run's own error estimates under the title."""
    p = run.contact.params
    note = estimate_note(run)
    return contact_panels(f"{run.name}: contact on $\\Gamma_3$ at T = {p['T']} ({style.problem_label(p)})"
                          + (f"\n{note}" if note else ""), [run], True)


def compare_contact(runs):
    """The contact quantities at T of several runs, overlaid (into the first run's figures/);
    the title says so when the runs were made by different versions of the suite
    (style.versions_note)."""
    note = style.versions_note([run.folder for run in runs], [run.name for run in runs])
    title = f"contact on $\\Gamma_3$ at T: {', '.join(run.name for run in runs)}"
    if note:                                          # wrapped to the figure's width (style.note_versions)
        title += "\n" + "\n".join(textwrap.wrap(style.plain_text(note), 100))
    return contact_panels(title, runs, False)


def histories(run):
    """Against t: the contact forces, the nodes per zone, the energy terms, the energy balance."""
    h = runfiles.read_table(run.file("contact_history.txt"))
    e = runfiles.read_table(run.file("history.txt"))
    h.finite("t", "normal_force", "tangential_force", *(zone.column for zone in run.zone_types))
    e.finite("t", "energy_residual", *(column for column, _, _ in style.ENERGY_TERMS))
    fig, ((forces, zones), (energy, residual)) = plt.subplots(2, 2, figsize=(11, 7))
    forces.plot(h["t"], h["normal_force"], label=r"normal force $\sum_i w_i\, p_{\nu,i}$")
    if run.dimension == 3:
        # the total friction stress as a vector on Gamma3's mean frame (summary.txt)
        second = h.finite("tangential_force2")[0]
        summary = runfiles.read_summary(run.folder)
        try:
            axes = [np.array([float(w) for w in summary[key].split()]) for key in ("contact_frame_t1", "contact_frame_t2")]
        except ValueError:
            raise runfiles.InputError(f"{summary.source}: contact_frame_t1, contact_frame_t2 need numbers") from None
        t1, t2 = (face3d.direction_name(t) for t in axes)
        forces.plot(h["t"], h["tangential_force"], label=f"friction stress on $T_1$ ({t1}): "
                                                          r"$\sum_i w_i\, \mathbf{\lambda}_{\tau,i} \cdot T_1$")
        forces.plot(h["t"], second, "-.", label=f"friction stress on $T_2$ ({t2}): "
                                          r"$\sum_i w_i\, \mathbf{\lambda}_{\tau,i} \cdot T_2$")
        forces.plot(h["t"], np.hypot(h["tangential_force"], second), "k--", label="length of the tangential force")
        forces.set_ylabel("force [GN]")
    else:
        forces.plot(h["t"], h["tangential_force"], label=r"tangential force $\sum_i w_i\, \lambda_{\tau,i}$")
    forces.set_xlabel("t [s]")
    if run.dimension == 2:
        forces.set_ylabel("force per unit thickness [GPa m]")
    forces.set_title(f"{run.name}: contact forces on $\\Gamma_3$")
    forces.legend(fontsize=7)
    style.least_span(forces, run.scales.force)                     # round-off drawn flat
    style.zone_counts_plot(zones, h)
    style.log_floor(energy, style.energy_terms_plot(energy, e))
    if run.dimension == 3:
        energy.set_ylabel("energy [GJ]")
    energy.set_title("energies at $t_n$, cumulative dissipations and work")
    energy.legend(fontsize=7)
    residual.semilogy(e["t"], np.where(e["energy_residual"] > 0, e["energy_residual"], np.nan), "o-", markersize=2)
    residual.set_xlabel("t [s]")
    residual.set_ylabel("|balance| / largest term")
    residual.set_title("energy balance residual of each step")
    return fig


def deformed(run):
    """The deformed mesh at T (magnified when the displacements are small, the factor in the
    title), coloured by the von Mises stress, the undeformed outline in grey, the contact
    nodes by zone; the figure shaped to the body."""
    f = runfiles.read_table(run.file("fields.txt"))
    xy, u = np.column_stack(f.finite("x", "y")), np.column_stack(f.finite("u_x", "u_y"))
    if len(xy) != len(run.mesh.xy):
        raise runfiles.InputError(f"{f.path}: {len(xy)} vertices, but {len(run.mesh.xy)} in mesh.msh")
    factor = style.magnification(np.ptp(xy, axis=0).max(), np.hypot(*u.T).max())
    moved = xy + factor * u
    values, label = f.finite("von_mises")[0], "von Mises stress [GPa]"
    norm = style.least_norm(values, max(run.scales.stress, float(np.abs(values).max())))
    scale = "true scale" if factor == 1 else f"displacements magnified {factor:g} times"
    fig, ax = style.body_figure(np.r_[xy, moved], f"{run.name}: deformed at T = {f.params['T']} ({scale}), "
                                                  "contact nodes by zone", legend=(1 + len(set(run.zones)), 3, 2.4))
    shown = ax.tripcolor(mtri.Triangulation(*moved.T, run.mesh.triangles), values, shading="gouraud", cmap="viridis",
                         norm=norm)
    fig.colorbar(shown, ax=ax, label=label, shrink=0.8)
    edges = gamma3.boundary_edges(run.mesh.triangles)
    ax.add_collection(mcollections.LineCollection(xy[edges], colors="0.6", linewidths=0.8, label="undeformed outline"))
    nodes = gamma3.nearest(xy, np.c_[run.contact["x"], run.contact["y"]])
    ax.scatter(*moved[nodes].T, c=[style.zone_color(z) for z in run.zones], s=14, edgecolors="k", linewidths=0.4, zorder=3)
    handles = ax.get_legend_handles_labels()[0] + style.zone_patches(run.zone_types, run.zones)
    ax.legend(handles=handles, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12),
              ncol=style.legend_columns(fig, 3, 2.4))
    return fig


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
    _, t, zones = runfiles.node_history(run.folder, len(run.contact))
    edges, columns = gamma3.map_columns(run.position, run.pieces)
    fig, ax = plt.subplots(figsize=(10, 6))
    ax.grid(False)
    colors = mcolors.ListedColormap([zone.color for zone in run.zone_types])
    norm = mcolors.BoundaryNorm(np.arange(len(run.zone_types) + 1) - 0.5, len(run.zone_types))
    shown = np.ma.masked_array(zones[:, columns], mask=np.tile(columns < 0, (len(t), 1)))
    ax.pcolormesh(edges, np.r_[min(0.0, t[0]), t], shown, cmap=colors, norm=norm)
    handles = style.zone_patches(run.zone_types)
    if run.axis == "x [m]":
        h = runfiles.read_table(run.file("contact_history.txt"))
        for column, line, color, meaning, none in (
                ("x_B", "-", "k", "first node at the bound", "no node at the bound"),
                ("x_C", "--", "tab:blue", "first sticking node in contact", "no sticking node in contact")):
            values = h[column]
            if np.isinf(values).any():
                raise runfiles.InputError(f"{h.path}: {column} is infinite at a step")
            label = boundary_label(values, f"${column[0]}_{column[2]}$", meaning, none, edges)
            handles += ax.plot(*steps_against_t(h.finite("t")[0], values), line, color=color, linewidth=1.5,
                               label=label)
    pad = 0.015 * (edges[-1] - edges[0])           # a line at the map's edge (x_B = 0) stays in sight
    ax.set_xlim(edges[0] - pad, edges[-1] + pad)
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_xlabel(run.axis)
    ax.set_ylabel("t [s]")
    ax.set_title(f"{run.name}: zones on $\\Gamma_3$ against t" + (", gaps between its pieces blank"
                                                                   if len(set(run.pieces)) > 1 else ""))
    return fig


# ---------------------------------------------------------------- 3D runs
def face_grid(face, maps, width=11.0, highest=4.2, plain=3.0):
    """A figure of `maps` maps of Gamma3 (face3d.ContactFace, at equal aspect, each with its
    colour bar as high as it) and one plain axes after them, laid out by hand in inches for
    the face's shape: one column for a face more than 2.5 times as wide as high (a slab's),
    else two. Returns (fig, [(map axes, colour bar axes)], the plain axes)."""
    left, right, title, below, top = 0.75, 1.2, 0.55, 0.5, 0.75     # margins (inches): labels, colour bar, titles
    w, h = face.extent() + 0.08 * face.extent().max()              # with the margins of face3d.face_axes
    columns = 1 if h < 0.4 * w else 2
    map_width = (width - columns * (left + right)) / columns
    map_height = min(map_width * h / w, highest)
    map_width = map_height * w / h
    slots = [map_height] * maps + [map_height if columns == 2 else plain]
    rows = [max(slots[k:k + columns]) for k in range(0, len(slots), columns)]
    height = top + sum(row + title + below for row in rows)
    fig = plt.figure(figsize=(width, height))

    def box(x, y, w_, h_):                                          # inches from the top left -> figure fraction
        return (x / width, 1 - (y + h_) / height, w_ / width, h_ / height)
    axes = []
    for k, slot in enumerate(slots):
        row, column = divmod(k, columns)
        x, y = column * width / columns + left, top + sum(r + title + below for r in rows[:row]) + title
        if k < maps:
            axes.append((fig.add_axes(box(x, y, map_width, slot)), fig.add_axes(box(x + map_width + 0.12, y, 0.15, slot))))
        else:                                                       # room on its right for a legend
            plain_axes = fig.add_axes(box(x, y, width / columns - left - 2.3, slot))
    for _, bar in axes:
        bar.grid(False)
    fig.no_tight_layout = True                                      # the layout is this one
    return fig, axes, plain_axes


def face_map(fig, axes, run, values, label, title, norm):
    """A quantity at the nodes of Gamma3 over the face (linear on each triangle), the
    triangles' edges in white, a colour bar on the scale norm (style.least_norm: round-off is
    not drawn as a pattern); returns the colour bar."""
    face, (ax, room) = run.face, axes
    shown = ax.tripcolor(mtri.Triangulation(*face.uv.T, face.triangles), values, shading="gouraud", cmap="viridis",
                         norm=norm)
    ax.add_collection(mcollections.LineCollection(face.uv[face.edges()], colors="w", linewidths=0.4, alpha=0.35))
    face3d.face_axes(ax, face)
    ax.set_title(title)
    bar = fig.colorbar(shown, cax=room, label=label)
    bar.formatter.set_useOffset(False)
    return bar


def contact_at_T3(run):
    """A 3D run's contact on Gamma3 at T, the face seen from outside (face3d.ContactFace):
    maps of v_nu (the bound g marked on its colour bar), p_nu, and |v_tau| with the slip
    velocity of each slipping node as an arrow; |lambda_tau| of every node against its friction
    bound (the column friction_bound), coloured by zone."""
    c, face = run.contact, run.face
    p = c.params
    fig, (normal, pressure, slip), cone = face_grid(face, 3)
    v_nu, g = c["v_nu"], c["g"]
    bar = face_map(fig, normal, run, v_nu, "$v_\\nu$ [m/s]", "normal velocity $v_\\nu$\n(red on its scale: the bound g)",
                   norm=mcolors.Normalize(min(v_nu.min(), 0.0), max(v_nu.max(), g.max())))
    for value in sorted({g.min(), g.max()}):                  # the bound (its least and largest on Gamma3)
        bar.ax.axhline(value, xmin=-0.3, xmax=1.0, color="tab:red", linewidth=2.5, clip_on=False, in_layout=False)
        bar.ax.text(-0.4, value, "g", color="tab:red", ha="right", va="center", fontsize=9, fontweight="bold",
                    transform=bar.ax.get_yaxis_transform(), in_layout=False)
    face_map(fig, pressure, run, c["p_nu"], "$p_\\nu$ [GPa]", "normal stress\n$p_\\nu = p(v_\\nu) + \\lambda_\\nu$",
             style.least_norm(c["p_nu"], run.scales.stress))
    velocity = face.tangential(c["v_tau"], c["v_tau2"])
    speed = np.hypot(c["v_tau"], c["v_tau2"])
    slipping = (run.normal > 0) & (run.tangential == 1)       # in contact (normal status 1, 2) and slipping (1)
    longest = float(speed[slipping].max()) if slipping.any() else 0.0
    face_map(fig, slip, run, speed, "$|v_\\tau|$ [m/s]", "slip speed $|v_\\tau|$\narrows: the slip velocity"
             + (f" (longest {longest:.3g} m/s)" if slipping.any() else ": no node slips"),
             norm=style.least_norm(speed, run.scales.velocity, low=0.0))
    if slipping.any():
        edges = face.uv[face.edges()]
        spacing = float(np.median(np.hypot(*(edges[:, 1] - edges[:, 0]).T)))   # the longest arrow: 0.7 of it
        slip[0].quiver(*face.uv[slipping].T, *velocity[slipping].T, color="w", edgecolor="k", linewidth=0.5, angles="xy",
                    scale_units="xy", scale=longest / (0.7 * spacing), pivot="middle", width=0.005, zorder=3, clip_on=False, in_layout=False)
    friction, bound = np.hypot(c["lambda_tau"], c["lambda_tau2"]), c["friction_bound"]
    top = 1.08 * max(float(friction.max()), float(bound.max()), style.LEAST * run.scales.friction)   # round-off drawn flat
    cone.plot([0, top], [0, top], "k--", linewidth=0.8, label="$|\\lambda_\\tau|$ = friction bound: slip")
    cone.scatter(bound, friction, c=[style.zone_color(z) for z in run.zones], s=18, edgecolors="k", linewidths=0.4, zorder=3,
                 clip_on=False)
    cone.set_xlim(0, top)
    cone.set_ylim(0, top)
    cone.set_xlabel("friction bound [GPa]")
    cone.set_ylabel("$|\\lambda_\\tau|$ [GPa]")
    cone.set_title("friction: $|\\lambda_\\tau|$ of each node against its bound" if bound.max() > 0 else
                   "friction: the friction bound is 0 at every node (frictionless)")
    cone.legend(handles=cone.get_legend_handles_labels()[0] + style.zone_patches(run.zone_types, run.zones), fontsize=7,
                loc="upper left", bbox_to_anchor=(1.01, 1.0))
    note = estimate_note(run)
    fig.suptitle(f"{run.name}: contact on $\\Gamma_3$ at T = {p['T']} ({style.problem_label(p)})\n{face.view}"
                 + ("; $\\Gamma_3$ overlaps itself in this view" if face.folded else "") + (f"\n{note}" if note else ""),
                 fontsize=10)
    return fig


def zone_map3(run):
    """The zone of every node of a 3D run's Gamma3 at T over the face seen from outside,
    each node's cell (halfway to its neighbours) in its zone's colour, the counts in the
    legend."""
    face = run.face
    w, h = face.extent()
    height = min(8.0 * h / w, 6.5)
    fig, ax = plt.subplots(figsize=(10.8, max(height, 1.8) + 1.4))
    face3d.draw_face_zones(ax, face, run.zones)
    ax.legend(handles=style.zone_patches(run.zone_types, run.zones), fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0),
              title=f"{style.nodes(len(run.zones))} at T", title_fontsize=7)
    ax.set_title(f"{run.name}: zones on $\\Gamma_3$ at T = {run.contact.params['T']}, each node's cell (halfway to its "
                 f"neighbours) in its zone's colour\n{face.view}"
                 + ("; $\\Gamma_3$ overlaps itself in this view" if face.folded else ""), fontsize=9)
    return fig


VIEWS = ((28, -55, "from above"), (-40, -55, "from below: $\\Gamma_3$, its nodes by zone"))   # elevation, azimuth


def deformed3(run):
    """A 3D run's body at T, its outer surface deformed (magnified as in 2D), each triangle
    coloured by the von Mises stress of its corners, seen from above and
    from below (the contact nodes by zone there), the undeformed edges in grey."""
    from mpl_toolkits.mplot3d import proj3d
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection
    f = runfiles.read_table(run.file("fields.txt"))
    xyz, u = np.column_stack(f.finite("x", "y", "z")), np.column_stack(f.finite("u_x", "u_y", "u_z"))
    if len(xyz) != len(run.mesh.xyz):
        raise runfiles.InputError(f"{f.path}: {len(xyz)} vertices, but {len(run.mesh.xyz)} in mesh.msh")
    size = float(np.ptp(xyz, axis=0).max())
    moved_off = np.flatnonzero(np.abs(xyz - run.mesh.xyz).max(axis=1) > 1e-9 * size)
    if moved_off.size:
        raise runfiles.InputError(f"{f.path}:{f.lines[moved_off[0]]}: not the vertex {moved_off[0] + 1} of mesh.msh")
    factor = style.magnification(size, np.linalg.norm(u, axis=1).max())
    moved = xyz + factor * u
    values, label = f.finite("von_mises")[0], "von Mises stress [GPa]"
    surface = face3d.outer_surface(run.mesh.tetrahedra, xyz)
    outline = xyz[face3d.feature_edges(surface, xyz)]
    norm = style.least_norm(values, max(run.scales.stress, float(np.abs(values).max())))    # round-off is no pattern
    colors = plt.get_cmap("viridis")(norm(values[surface].mean(axis=1)))
    def drawn(points):
        """(x, -z, y): y up in mplot3d's frame, still right-handed (its ticks on the second
        axis show z)."""
        return np.asarray(points)[..., [0, 2, 1]] * [1.0, -1.0, 1.0]
    low, high = drawn(np.r_[xyz, moved]).min(axis=0), drawn(np.r_[xyz, moved]).max(axis=0)
    scale = "true scale" if factor == 1 else f"displacements magnified {factor:g} times"
    fig = plt.figure(figsize=(11, 5.6))
    contact_rows = run.face.mesh_rows
    for k, (elevation, azimuth, title) in enumerate(VIEWS):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d", computed_zorder=False)
        ax.view_init(elevation, azimuth)
        ax.set_xlim(low[0], high[0])
        ax.set_ylim(low[1], high[1])
        ax.set_zlim(low[2], high[2])
        ax.set_box_aspect(np.maximum(high - low, 1e-3 * (high - low).max()))
        screen = np.column_stack(proj3d.proj_transform(*drawn(moved).T, ax.get_proj())[:2])
        a, b, c = (screen[surface[:, corner]] for corner in range(3))
        front = np.cross(b - a, c - a) > 0                     # counterclockwise on the screen: facing the viewer
        ax.add_collection3d(Poly3DCollection(drawn(moved[surface[front]]), facecolors=colors[front],
                                             edgecolors=(0, 0, 0, 0.12), linewidths=0.3, zorder=1))
        ax.add_collection3d(Line3DCollection(drawn(outline), colors="0.55", linewidths=0.7, zorder=2))
        if k == 1:
            seen = np.isin(contact_rows, surface[front])      # on a triangle facing the viewer
            ax.scatter(*drawn(moved[contact_rows[seen]]).T, c=[style.zone_color(z) for z in run.zones[seen]], s=10,
                       edgecolors="k", linewidths=0.3, depthshade=False, zorder=3)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("z [m]")
        ax.yaxis.set_major_formatter(mticker.FuncFormatter(lambda value, _: f"{-value + 0.0:g}"))
        ax.set_zlabel("y [m]")
        for axis, extent in zip((ax.xaxis, ax.yaxis, ax.zaxis), high - low):
            axis.set_major_locator(mticker.MaxNLocator(4 if extent > 0.2 * (high - low).max() else 1))
        ax.tick_params(labelsize=7)
        fig.text(0.03 + 0.43 * k, 0.905, title, fontsize=10)
    handles = [mlines.Line2D([], [], color="0.55", label="undeformed edges")] + style.zone_patches(run.zone_types, run.zones)
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=7)
    fig.subplots_adjust(left=0.0, right=0.86, bottom=0.08, top=0.84, wspace=0.1)
    bar = fig.add_axes((0.905, 0.2, 0.015, 0.6))
    bar.grid(False)
    fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap="viridis"), cax=bar, label=label).formatter.set_useOffset(False)
    fig.suptitle(f"{run.name}: deformed at T = {f.params['T']} ({scale}), coloured by the {label.split(' [')[0]} "
                 "(each surface triangle: the mean of its corners)", fontsize=10)
    fig.no_tight_layout = True                                 # (tight_layout does not place 3D axes)
    return fig


# The figures of one run and the files each needs beyond contact.txt and mesh.msh.
FIGURES = (("contact_at_T", contact_at_T, ()), ("histories", histories, ("contact_history.txt", "history.txt")),
           ("deformed", deformed, ("fields.txt",)),
           ("zone_map", zone_map, ("contact_nodes_history.txt", "contact_history.txt")))
FIGURES_3D = (("contact_at_T", contact_at_T3, ()), ("histories", histories, ("contact_history.txt", "history.txt")),
              ("deformed", deformed3, ("fields.txt",)), ("zone_map", zone_map3, ()))      # at T: from contact.txt


def plan(runs):
    """[(path, function drawing it)] of every figure the runs' files allow (a note on stderr
    for each one left out), and compare_contact.png into the first one's figures/ when there
    are several."""
    figures = []
    for run in runs:
        for name, figure, needs in FIGURES_3D if run.dimension == 3 else FIGURES:
            missing = [need for need in needs if not os.path.isfile(run.file(need))]
            if missing:
                print(f"run_figures.py: {run.folder}: no {name}.png ({' and '.join(missing)} missing)", file=sys.stderr)
            else:
                figures.append((run.figure(name + ".png"), functools.partial(figure, run)))
    if len(runs) > 1:
        figures.append((runs[0].figure("compare_contact.png"), functools.partial(compare_contact, runs)))
    return figures


def main():
    runfiles.check_arguments("run_figures.py")             # a name not in UTF-8: refused before anything
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folders", nargs="+", metavar="RUN_DIR")
    runs = [Run(folder) for folder in parser.parse_args().folders]      # every folder checked first
    figures = plan(runs)
    files = figurefiles.FigureFiles([path for path, _ in figures])            # refuses to draw over a file not ours
    for path, figure in figures:
        fig = figure()
        files.save(fig, path, tight_layout=not getattr(fig, "no_tight_layout", False))
    files.commit()
    for path, _ in figures:
        print(path)


if __name__ == "__main__":
    runfiles.run_tool("run_figures.py", main, code=2, cleanup=figurefiles.abort_pending)
