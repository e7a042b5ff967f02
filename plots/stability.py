#!/usr/bin/python3
"""Stability maps of plots/stability.sh: where each contact solver converges and how it fails.

One function per map; each reads one table written by plots/stability_tables.py
(results/stability/SWEEP.txt, by column name) and writes stability_NAME.png. Every cell
is one run: its colour is the failure mode (plots/stability_tables.py), its text the
mean / max iterations per step when it converged, or the failing step (s7) and the cycle
period (p2) when it did not. Usage:
  stability.py --results DIR --out DIR [NAME ...]     (NAME: see MAPS; default all)
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import matplotlib.patches as mpatches

import runfiles
import style

# style.STYLE, with smaller text, no grid over the cells, and the legend outside the axes kept
plt = style.pyplot({"font.size": 8, "axes.titlesize": 9, "axes.grid": False, "savefig.bbox": "tight"})
MODE_COLORS = {
    "ok": "#7fc97f", "slow": "#ffff99", "stalled": "#fdc086", "floor": "#80b1d3", "stuck": "#bebada",
    "cycling": "#e41a1c", "diverging": "#984ea3", "cap": "#cccccc", "nonfinite": "#222222",
    "check": "#386cb0", "timeout": "#999999", "error": "#a65628",
}
MODE_TEXT = {
    "ok": "converged", "slow": "cap: still decreasing", "stalled": "no decrease (at the cap, or the fixed point's stall test)", "floor": "cap: round-off floor",
    "stuck": "cap: stuck", "cycling": "cap: cycling", "diverging": "cap: growing", "cap": "cap",
    "nonfinite": "non-finite", "check": "end-of-run check", "timeout": "time limit", "error": "other error",
}
METHOD_ORDER = ["orig-newton-on", "orig-newton-off", "orig-newton-script-on", "orig-fixedpoint", "pen-newton-compliant-on",
                "pen-newton-compliant-off", "pen-newton-literal-on", "pen-newton-literal-off", "pen-fixedpoint"]


def rows_of(results, sweep):
    """The rows of results/SWEEP.txt, one dict column name -> text per run."""
    return runfiles.read_table(os.path.join(results, f"{sweep}.txt"), dtype=str, empty=True).rows()


def cell_text(row):
    if row["mode"] == "ok":
        return f"{float(row['iter_mean']):.1f}\n{int(float(row['iter_max']))}"
    text = f"s{row['fail_step']}" if row["fail_step"] != "nan" else row["mode"][:4]
    if row["mode"] == "cycling":
        text += f"\np{row['period']}"
    return text


def heatmap(ax, rows, xkey, ykey, xlabel, ylabel, xorder=None, yorder=None, xfmt=str, yfmt=str):
    """One cell per row at (row[xkey], row[ykey]); returns the modes drawn."""
    xs = xorder or sorted({r[xkey] for r in rows}, key=float)
    ys = yorder or sorted({r[ykey] for r in rows}, key=float)
    ys = [y for y in ys if any(r[ykey] == y for r in rows)]
    modes = set()
    for r in rows:
        if r[xkey] not in xs or r[ykey] not in ys:
            continue
        i, j = xs.index(r[xkey]), ys.index(r[ykey])
        modes.add(r["mode"])
        ax.add_patch(mpatches.Rectangle((i - 0.5, j - 0.5), 1, 1, facecolor=MODE_COLORS.get(r["mode"], "white"),
                                        edgecolor="white", linewidth=1))
        ax.text(i, j, cell_text(r), ha="center", va="center", fontsize=5.5, linespacing=0.9,
                color="white" if r["mode"] in ("nonfinite", "cycling", "diverging", "check") else "black")
    ax.set_xlim(-0.5, len(xs) - 0.5)
    ax.set_ylim(-0.5, len(ys) - 0.5)
    ax.set_xticks(range(len(xs)))
    ax.set_xticklabels([xfmt(x) for x in xs], rotation=45 if len(xs) > 8 else 0, ha="right" if len(xs) > 8 else "center")
    ax.set_yticks(range(len(ys)))
    ax.set_yticklabels([yfmt(y) for y in ys])
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_aspect("auto")
    return modes


def legend(fig, modes):
    handles = [mpatches.Patch(color=MODE_COLORS[m], label=MODE_TEXT[m]) for m in MODE_COLORS if m in modes]
    fig.legend(handles=handles, loc="center left", fontsize=7, frameon=False, bbox_to_anchor=(1.0, 0.5))


def number(x):
    v = float(x)
    return f"{v:g}"


def methods_present(rows):
    present = {r["method"] for r in rows}
    return [m for m in METHOD_ORDER if m in present] + sorted(present - set(METHOD_ORDER))


def save(fig, out, name):
    print(f"stability.py: wrote {style.save(fig, out, 'stability_' + name, tight_layout=False)}")


def method_map(results, out, sweep, xkey, xlabel, title, name):
    rows = rows_of(results, sweep)
    methods = methods_present(rows)
    ncol = len({r[xkey] for r in rows})
    fig, ax = plt.subplots(figsize=(max(5, 0.45 * ncol + 2.5), 0.42 * len(methods) + 1.6))
    modes = heatmap(ax, rows, xkey, "method", xlabel, "", yorder=methods[::-1], xfmt=number)
    ax.set_title(title)
    legend(fig, modes)
    save(fig, out, name)


def map_eps_method(results, out):
    """Penalty eps x method (reduced mesh 33x16, T = 1, k = 0.01)."""
    method_map(results, out, "eps", "eps", "penalty parameter eps",
               "penalty problem: eps x method (mesh 33x16, T = 1, k = 0.01; cell: mean/max iterations per step)",
               "eps_method")


def map_r_method(results, out):
    """Augmentation r x method (reduced mesh, T = 1, k = 0.01; penalty eps = 2e-5)."""
    method_map(results, out, "r", "r", "augmentation factor r (r_j = r/(Dw)_jj; fixed point r/(D0)_jj)",
               "augmentation r x method (mesh 33x16, T = 1, k = 0.01, penalty eps = 2e-5)", "r_method")


def map_mu_method(results, out):
    """Friction coefficient x method (reduced mesh, T = 1, k = 0.01)."""
    method_map(results, out, "mu", "mu", "friction coefficient mu",
               "friction mu x method (mesh 33x16, T = 1, k = 0.01)", "mu_method")


def map_load_method(results, out):
    """Load x method (reduced mesh, T = 1, k = 0.01; the paper's load is 10)."""
    method_map(results, out, "load", "load", "load (f2 = load t; paper: 10)",
               "load x method (mesh 33x16, T = 1, k = 0.01)", "load_method")


def map_k_method(results, out):
    """Time step x method (reduced mesh; T = 1, T = 0.4 for k <= 1e-3)."""
    method_map(results, out, "k", "dt", "time step k (T = 1; T = 0.4 for k <= 1e-3)",
               "time step k x method (mesh 33x16, mu = 0.4)", "k_method")


def map_k_mu(results, out):
    """Time step x friction, one panel per Newton method (reduced mesh)."""
    rows = rows_of(results, "kmu")
    methods = methods_present(rows)
    fig, axes = plt.subplots(1, len(methods), figsize=(4.2 * len(methods), 3.4), squeeze=False)
    modes = set()
    for ax, method in zip(axes[0], methods):
        sel = [r for r in rows if r["method"] == method]
        xs = sorted({r["dt"] for r in sel}, key=lambda v: -float(v))
        modes |= heatmap(ax, sel, "dt", "mu", "time step k", "mu", xorder=xs, xfmt=number, yfmt=number)
        ax.set_title(method)
    fig.suptitle("k x mu, Newton (mesh 33x16; T = 1, T = 0.4 for k <= 1e-3; cell: mean/max iterations per step)", y=1.02)
    legend(fig, modes)
    save(fig, out, "k_mu")


def map_mesh_r(results, out):
    """Mesh x augmentation r, Newton with and without safeguards (T = 0.05, 5 steps)."""
    rows = rows_of(results, "mesh")
    for r in rows:
        r["mesh"] = f"{r['nx']}x{r['ny']}"
    methods = methods_present(rows)
    meshes = sorted({r["mesh"] for r in rows}, key=lambda m: int(m.split("x")[0]))
    fig, axes = plt.subplots(1, len(methods), figsize=(4.5 * len(methods), 2.8), squeeze=False)
    modes = set()
    for ax, method in zip(axes[0], methods):
        sel = [r for r in rows if r["method"] == method]
        modes |= heatmap(ax, sel, "r", "mesh", "augmentation factor r", "mesh", yorder=meshes, xfmt=number)
        ax.set_title(method)
    fig.suptitle("mesh x r, original problem, Newton (T = 0.05, k = 0.01)", y=1.04)
    legend(fig, modes)
    save(fig, out, "mesh_r")


def map_fixedpoint_mesh_k(results, out):
    """Fixed point: mesh x time step (T = 0.4, maxit 1000)."""
    rows = rows_of(results, "fixedpoint")
    for r in rows:
        r["mesh"] = f"{r['nx']}x{r['ny']}"
    meshes = sorted({r["mesh"] for r in rows}, key=lambda m: int(m.split("x")[0]))
    fig, ax = plt.subplots(figsize=(5, 3.2))
    xs = sorted({r["dt"] for r in rows}, key=lambda v: -float(v))
    modes = heatmap(ax, rows, "dt", "mesh", "time step k", "mesh", xorder=xs, yorder=meshes, xfmt=number)
    ax.set_title("fixed point, original problem (T = 0.4, mu = 0.4, maxit 1000)")
    legend(fig, modes)
    save(fig, out, "fixedpoint_mesh_k")


def map_paper_box(results, out):
    """The defaults of each solver on the paper mesh 66x33 over the paper box (maxit as shipped)."""
    rows = rows_of(results, "box")
    for r in rows:
        r["problem_eps"] = "original" if r["problem"] == "original" else f"penalty eps={float(r['eps']):g}"
        r["mu_load"] = f"mu={float(r['mu']):g} load={float(r['load']):g}"
    solvers = [s for s in ("newton", "fixedpoint") if any(r["solver"] == s for r in rows)]
    grid = [r for r in rows if r["problem"] == "original" or float(r["eps"]) in (2e-5, 1e-12)]
    panels = sorted({r["problem_eps"] for r in grid}, key=lambda p: (p != "original", -float(p.split("=")[1]) if "=" in p else 0))
    eps_lines = {s: [r for r in rows if r["solver"] == s and r["problem"] == "penalty" and float(r["mu"]) == 0.4
                     and float(r["load"]) == 10 and float(r["dt"]) == 0.01] for s in solvers}
    with_line = any(len(v) > 2 for v in eps_lines.values())
    ncol = len(panels) + (1 if with_line else 0)
    fig, axes = plt.subplots(len(solvers), ncol, figsize=(3.9 * ncol, 3.9 * len(solvers)), squeeze=False)
    modes = set()
    ymap = sorted({r["mu_load"] for r in grid}, key=lambda s: tuple(float(w.split("=")[1]) for w in s.split()))
    shipped = {"newton": "Newton, safeguards on, maxit 50", "fixedpoint": "fixed point, maxit 500"}
    for row_axes, solver in zip(axes, solvers):
        for ax, panel in zip(row_axes, panels):
            sel = [r for r in grid if r["problem_eps"] == panel and r["solver"] == solver]
            xs = sorted({r["dt"] for r in sel}, key=lambda v: -float(v))
            modes |= heatmap(ax, sel, "dt", "mu_load", "time step k (T = 0.2 for k <= 1e-3)", "", xorder=xs,
                             yorder=ymap, xfmt=number)
            ax.set_title(f"{shipped[solver]}\n{panel}", fontsize=9)
        if with_line:
            ax = row_axes[-1]
            line = eps_lines[solver]
            if len(line) > 2:
                for r in line:
                    r["row"] = "eps line"
                modes |= heatmap(ax, line, "eps", "row", "penalty eps (mu 0.4, load 10, k 0.01)", "",
                                 yorder=["eps line"], xfmt=number)
                ax.set_title(f"{shipped[solver]}\npenalty, eps line", fontsize=9)
            else:
                ax.axis("off")
    fig.suptitle("defaults (compliant penalty, r = 1) on the paper mesh 66x33; cell: mean/max iterations per step", y=1.01)
    fig.tight_layout()
    legend(fig, modes)
    save(fig, out, "paper_box")


def map_bodies(results, out):
    """The hard bodies (a curved 2D body, a twisted 3D body) at the defaults of each method, over mu."""
    rows = rows_of(results, "bodies")
    bodies = sorted({r["body"] for r in rows})
    methods = methods_present(rows)
    fig, axes = plt.subplots(1, len(bodies), figsize=(4.2 * len(bodies) + 1, 0.42 * len(methods) + 1.8), squeeze=False)
    modes = set()
    for ax, body in zip(axes[0], bodies):
        sel = [r for r in rows if r["body"] == body]
        modes |= heatmap(ax, sel, "mu", "method", "friction coefficient mu", "", yorder=methods[::-1], xfmt=number)
        ax.set_title(f"{body}: each method at its defaults", fontsize=9)
    fig.suptitle("hard bodies; cell: mean/max iterations per step, or the failing step", y=1.02)
    fig.tight_layout()
    legend(fig, modes)
    save(fig, out, "bodies")


MAPS = {
    "eps_method": map_eps_method, "r_method": map_r_method, "k_mu": map_k_mu, "mu_method": map_mu_method,
    "load_method": map_load_method, "k_method": map_k_method, "mesh_r": map_mesh_r,
    "fixedpoint_mesh_k": map_fixedpoint_mesh_k, "paper_box": map_paper_box, "bodies": map_bodies,
}
SOURCES = {"eps_method": "eps", "r_method": "r", "k_mu": "kmu", "mu_method": "mu", "load_method": "load",
           "k_method": "k", "mesh_r": "mesh", "fixedpoint_mesh_k": "fixedpoint", "paper_box": "box",
           "bodies": "bodies"}


def main():
    runfiles.check_arguments("stability.py")               # a name not in UTF-8: refused before anything
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--results", required=True, help="results/stability")
    parser.add_argument("--out", required=True, help="folder of the PNG files")
    parser.add_argument("names", nargs="*", help="maps to draw (default all): " + " ".join(MAPS))
    args = parser.parse_args()
    runfiles.check_outputs("stability.py", [args.out])     # not written through a symbolic link
    unknown = [n for n in args.names if n not in MAPS]
    if unknown:
        print(f"stability.py: error: unknown map {runfiles.shown(unknown[0])} (maps: {' '.join(MAPS)})", file=sys.stderr)
        sys.exit(2)
    os.makedirs(args.out, exist_ok=True)
    for name in args.names or MAPS:
        if not os.path.isfile(os.path.join(args.results, f"{SOURCES[name]}.txt")):
            print(f"stability.py: no {SOURCES[name]}.txt in {runfiles.shown(args.results)}: {name} skipped")
            continue
        MAPS[name](args.results, args.out)


if __name__ == "__main__":
    runfiles.run_tool("stability.py", main)
