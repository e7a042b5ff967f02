#!/usr/bin/python3
"""Figures of the paper's section 5 from the outputs of edp/solve.edp.

One function per figure, named after the paper's figure; each reads the text outputs
by column name and writes PNG files. Usage:
  figures.py --results DIR --out DIR [NAME ...]     (NAME: fig2 fig3 fig4; default all)
DIR/paper-original and DIR/paper-penalty are the outputs of ./run.sh.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
import numpy as np  # noqa: E402

STYLE = {
    "figure.figsize": (11, 4),
    "figure.dpi": 110,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "font.size": 9,
    "lines.linewidth": 1.2,
    "lines.markersize": 3,
}
PROBLEMS = ("original", "penalty")


def read_table(path):
    """Parameters (# key value), columns (last # line) and data of an output file."""
    params, columns = {}, None
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            words = line[1:].split()
            if len(words) == 2:
                params[words[0]] = words[1]
            columns = words
    data = np.loadtxt(path, comments="#", ndmin=2)
    return params, {name: data[:, i] for i, name in enumerate(columns)}


def read_msh22_triangles(path):
    """Triangles (0-based node indices) of a gmsh MSH 2.2 file."""
    with open(path) as f:
        lines = f.read().split("\n")
    start = lines.index("$Elements")
    count = int(lines[start + 1])
    triangles = []
    for line in lines[start + 2:start + 2 + count]:
        words = line.split()
        if words[1] == "2":                      # element type 2: 3-node triangle
            ntags = int(words[2])
            triangles.append([int(w) - 1 for w in words[3 + ntags:6 + ntags]])
    return np.array(triangles)


def fig2_deformed(results, out):
    """Fig. 2: deformed configuration at T, true scale, with the contact line y = 0."""
    fig, axes = plt.subplots(1, 2, sharey=True)
    for ax, problem in zip(axes, PROBLEMS):
        folder = os.path.join(results, f"paper-{problem}")
        _, f = read_table(os.path.join(folder, "fields.txt"))
        triangles = read_msh22_triangles(os.path.join(folder, "mesh.msh"))
        tri = mtri.Triangulation(f["x"] + f["u_x"], f["y"] + f["u_y"], triangles)
        ax.triplot(tri, color="0.3", linewidth=0.3)
        ax.axhline(0.0, color="tab:red", linewidth=1.0, label="undeformed contact line y = 0")
        ax.set_aspect("equal")
        ax.set_title(f"{problem} problem: deformed mesh at T (true scale)")
        ax.set_xlabel("x [m]")
        ax.legend(loc="upper right")
    axes[0].set_ylabel("y [m]")
    return save(fig, out, "fig2_deformed")


def fig3_contact_reactions(results, out):
    """Fig. 3: normal pressure p_nu = p(v_nu) + lambda_nu and tangential stress on Gamma3 at T."""
    fig, axes = plt.subplots(1, 2, sharey=True)
    for ax, problem in zip(axes, PROBLEMS):
        p, c = read_table(os.path.join(results, f"paper-{problem}", "contact.txt"))
        ax.plot(c["x"], c["p_nu"], "o-", label=r"$p_\nu = p(v_\nu) + \lambda_\nu$")
        ax.plot(c["x"], c["p_nu"] - c["lambda_nu"], "--", label=r"damped response $p(v_\nu)$")
        ax.plot(c["x"], c["lambda_nu"], ":", label=r"multiplier $\lambda_\nu$")
        ax.plot(c["x"], c["lambda_tau"], "s-", label=r"tangential stress $\lambda_\tau$")
        ax.plot(c["x"], c["friction_bound"], "k-", linewidth=0.8, label=r"friction bound $\mu p(v_\nu)$")
        ax.plot(c["x"], -c["friction_bound"], "k-", linewidth=0.8)
        ax.set_title(f"{problem} problem: contact stresses on $\\Gamma_3$ at T = {p['T']}")
        ax.set_xlabel("x [m]")
        ax.legend()
    axes[0].set_ylabel("stress [GPa]")
    return save(fig, out, "fig3_contact_reactions")


def zone_edges(c):
    """Node counts and x-extent of the zones AB (damped, slip), BC (bound, slip), CD (stick)."""
    normal, tangential = c["normal_status"], c["tangential_status"]
    zones = {"AB": (normal == 1) & (tangential == 1), "BC": (normal == 2) & (tangential == 1),
             "CD": (normal > 0) & (tangential == 0)}
    return {name: (int(mask.sum()), c["x"][mask]) for name, mask in zones.items()}


def fig4_velocities(results, out):
    """Fig. 4: normal and tangential velocity on Gamma3 at T, with the bound g and the zones."""
    fig, axes = plt.subplots(1, 2, sharey=True)
    for ax, problem in zip(axes, PROBLEMS):
        p, c = read_table(os.path.join(results, f"paper-{problem}", "contact.txt"))
        g = float(p["g"])
        ax.plot(c["x"], c["v_nu"], "o-", label=r"$v_\nu$")
        ax.plot(c["x"], c["v_tau"], "s-", label=r"$v_\tau$")
        ax.axhline(g, color="k", linewidth=0.8, linestyle="--", label=f"bound g = {g}")
        for (name, (count, xs)), color in zip(zone_edges(c).items(), ("tab:green", "tab:orange", "tab:purple")):
            if count:
                ax.axvspan(xs.min(), xs.max(), color=color, alpha=0.12)
                ax.text(0.5 * (xs.min() + xs.max()), 1.12 * g, f"{name}: {count} nodes", ha="center", fontsize=8)
        ax.set_ylim(top=1.25 * g)
        ax.set_title(f"{problem} problem: velocities on $\\Gamma_3$ at T = {p['T']}")
        ax.set_xlabel("x [m]")
        ax.legend(loc="lower left")
    axes[0].set_ylabel("velocity [m/s]")
    return save(fig, out, "fig4_velocities")


def save(fig, out, name):
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, name + ".png")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


FIGURES = {"fig2": fig2_deformed, "fig3": fig3_contact_reactions, "fig4": fig4_velocities}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--results", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("names", nargs="*", help="figures to draw: " + " ".join(FIGURES))
    args = parser.parse_args()
    unknown = [n for n in args.names if n not in FIGURES]
    if unknown:
        sys.exit(f"figures.py: error: unknown figure {unknown[0]}; figures: {' '.join(FIGURES)}")
    plt.rcParams.update(STYLE)
    for name in args.names or FIGURES:
        print(f"figures.py: {name} -> {FIGURES[name](args.results, args.out)}")


if __name__ == "__main__":
    main()
