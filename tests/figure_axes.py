#!/usr/bin/python3
"""Round-off is drawn flat (docs/figures.md, "Round-off is drawn flat"): the axes of the
figures checked on their matplotlib objects, not their pixels.

  figure_axes.py RUN_DIR [RUN_DIR ...]     every figure plots/run_figures.py draws for each run,
                                           compare_contact of them all, and frames of the
                                           animation (plots/animate.py; 2D: with a vtk/ series)
  figure_axes.py --paper RUN_DIR           the paper's figures of plots/figures.py (fig3, fig4,
                                           the histories, the zone boundaries and the scenes'
                                           figures), every run of them this one

Nothing is written. Each figure is drawn (canvas.draw) and then every axis of every axes,
colour bars and 3D axes included, is checked:
  - no offset text: its ScalarFormatter has offset 0 (never '1e-14+5e-2');
  - a linear axis labelled in a unit of the contact quantities spans at least a thousandth of
    the runs' natural scale of it, read from their contact.txt: [m/s] the largest g (column
    g); [GPa] the least of p(g) (column force_scale) and mu p(g) when mu > 0; [GPa m] and
    [GN] p(g) times the area of Gamma3 (the sum of column weight).
Prints one line a failure, 'figure_axes.py: N figures, M axes checked' at the end; exit
status 1 on any failure.
"""
import os
import re
import sys

here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [os.path.join(here, "edp"), os.path.join(here, "plots")]

import matplotlib
matplotlib.use("Agg")                   # files only, as plots/style.py sets it
import matplotlib.pyplot as plt
from matplotlib.ticker import ScalarFormatter

import runfiles

FRACTION = 1e-3          # the least span the docs promise, a fraction of the natural scale
failures = []
checked = {"figures": 0, "axes": 0}


def natural_least(folders):
    """{unit: least span} from the contact.txt of the runs (the largest scale over them)."""
    g = p_g = friction = force = 0.0
    for folder in folders:
        c = runfiles.read_table(os.path.join(folder, "contact.txt"))
        mu = c.params.real("mu")
        g, p_g = max(g, c["g"].max()), max(p_g, c["force_scale"].max())
        friction = max(friction, (mu if mu > 0 else 1.0) * c["force_scale"].max())
        force = max(force, c["force_scale"].max() * c["weight"].sum())
    stress = min(p_g, friction)
    return {"m/s": FRACTION * g, "GPa": FRACTION * stress, "GPa m": FRACTION * force, "GN": FRACTION * force}


def check(fig, what, least):
    """Draw the figure, then check every axis of every axes of it (see the module's text)."""
    fig.canvas.draw()
    checked["figures"] += 1
    for k, ax in enumerate(fig.axes):
        for name in ("xaxis", "yaxis", "zaxis"):
            axis = getattr(ax, name, None)
            if axis is None:
                continue
            checked["axes"] += 1
            label = axis.get_label_text()
            where = f"{what}: axes {k} ({ax.get_title() or label or 'untitled'!r}), {name} {label!r}"
            formatter = axis.get_major_formatter()
            if isinstance(formatter, ScalarFormatter) and formatter.offset != 0:
                failures.append(f"{where}: offset text {formatter.get_offset()!r}")
            unit = re.search(r"\[([^\]]+)\]\s*$", label)
            if unit and unit.group(1) in least and axis.get_scale() == "linear":
                low, high = sorted(axis.get_view_interval())
                if high - low < least[unit.group(1)] * (1 - 1e-9):
                    failures.append(f"{where}: spans {high - low:.3g} [{unit.group(1)}], "
                                    f"less than the least {least[unit.group(1)]:.3g}")


def run_figures(folders):
    import animate
    import run_figures as rf
    runs = [rf.Run(folder) for folder in folders]
    for run in runs:
        least = natural_least([run.folder])
        for name, figure, needs in rf.FIGURES_3D if run.dimension == 3 else rf.FIGURES:
            if all(os.path.isfile(run.file(need)) for need in needs):
                fig = figure(run)
                check(fig, f"{run.name}/{name}", least)
                plt.close(fig)
        if run.dimension == 3 or os.path.isdir(run.file("vtk")):
            fig, draw, count = (animate.animation3 if run.dimension == 3 else animate.animation2)(run.folder)
            for frame in sorted({0, count - 1}):
                draw(frame)
                check(fig, f"{run.name}/animation, frame {frame}", least)
            plt.close(fig)
    if len(runs) > 1:
        check(rf.compare_contact(runs), "compare_contact", natural_least(folders))


def paper_figures(folder):
    """The paper's figures of plots/figures.py, the run in folder standing for every run they
    read (a results folder of links to it)."""
    import tempfile
    import figures
    import style
    drawn = []
    style.save = lambda fig, out, name, tight_layout=True: drawn.append((name, fig)) or name   # not written
    least = natural_least([folder])
    with tempfile.TemporaryDirectory() as results:
        os.makedirs(os.path.join(results, "scenes"))
        for name in ("paper-original", "paper-penalty", *(f"scenes/{scene}" for scene in figures.SCENES)):
            os.symlink(os.path.abspath(folder), os.path.join(results, name))
        for name in ("fig3", "fig4", "contact_forces_history", "energy_history", "zone_boundaries", "scene_unloading",
                     "scene_cylinder", "scene_bound_profile", "scene_power_damping"):
            figures.FIGURES[name](results, results)
    for name, fig in drawn:
        check(fig, f"figures.py {name}", least)
        plt.close(fig)


def main():
    args = sys.argv[1:]
    if args[:1] == ["--paper"] and len(args) == 2:
        paper_figures(args[1])
    elif args and not args[0].startswith("-"):
        run_figures(args)
    else:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    for failure in failures:
        print(f"figure_axes.py: {failure}")
    print(f"figure_axes.py: {checked['figures']} figures, {checked['axes']} axes checked, {len(failures)} failures")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
