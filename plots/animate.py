#!/usr/bin/python3
"""The deformed body over time, from the VTK time series of a run (edp/solve.edp -vtk N).

  animate.py RUN_DIR            (./run.sh animate RUN_DIR)

Reads RUN_DIR/vtk/fields.pvd and its .vtu files (at most FRAMES of them, evenly spread,
the first and the last included) and writes RUN_DIR/figures/animation.gif (Pillow), and
animation.mp4 too when ffmpeg is on the PATH. Each frame: the deformed mesh (one
magnification factor for every frame, given in the title) coloured by the von Mises stress
(by |v| where the files have no von_mises) on one scale for every frame, the undeformed
outline, the contact nodes coloured by zone (docs/figures.md). Prints the files written.
"""
import argparse
import os
import shutil

import matplotlib.animation as manimation
import matplotlib.collections as mcollections
import matplotlib.colors as mcolors
import matplotlib.tri as mtri
import numpy as np

import suite

plt = suite.pyplot()
FRAMES, FPS, DPI = 100, 10, 80          # at most 100 frames, 10 a second, 640 x 400 pixels
ZONE_COLORS = {zone.code: zone.color for zone in suite.ZONES}


def time_series(folder):
    """[(t, Vtu)] of the run's vtk/ folder, at most FRAMES of them, all on the same mesh."""
    vtk = os.path.join(folder, "vtk")
    if not os.path.isdir(vtk) or not os.listdir(vtk):          # a run without -vtk N may leave it empty
        raise suite.InputError(f"{folder} has no vtk/ time series: run with -vtk N")
    series = suite.read_pvd(os.path.join(vtk, "fields.pvd"))
    chosen = np.unique(np.linspace(0, len(series) - 1, min(len(series), FRAMES)).round().astype(int))
    frames = [(series[i][0], suite.read_vtu(series[i][1])) for i in chosen]
    for (_, first), (t, frame) in zip(frames, frames[1:]):
        if not np.array_equal(first.triangles, frame.triangles):
            raise suite.InputError(f"{folder}/vtk: the mesh at t = {t:g} is not that of t = {frames[0][0]:g}")
    return frames


def array(vtu, name, columns=None):
    """A point-data array of a frame, or InputError naming the missing one."""
    if name not in vtu.point_data:
        raise suite.InputError(f"a .vtu file has no point data '{name}' (it has {' '.join(vtu.point_data)})")
    values = vtu.point_data[name]
    return values if columns is None else values.reshape(len(vtu.xy), -1)[:, :columns]


def colour_values(vtu):
    """The values the body is coloured by: the von Mises stress, or |v| without it."""
    if "von_mises" in vtu.point_data:
        return vtu.point_data["von_mises"], "von Mises stress [GPa]"
    return np.hypot(*array(vtu, "v", 2).T), "|v| [m/s]"


def animate(folder):
    """Write the animation of the run in folder; return the paths written."""
    frames = time_series(suite.run_folder(folder))
    xy, triangles = frames[0][1].xy, frames[0][1].triangles
    largest = max(np.hypot(*array(vtu, "u", 2).T).max() for _, vtu in frames)
    factor = suite.magnification(np.ptp(xy, axis=0).max(), largest)
    moved = [xy + factor * array(vtu, "u", 2) for _, vtu in frames]
    low, high = np.min([m.min(axis=0) for m in moved], axis=0), np.max([m.max(axis=0) for m in moved], axis=0)
    margin = 0.05 * (high - low).max()
    label = colour_values(frames[0][1])[1]
    norm = mcolors.Normalize(0.0, max(colour_values(vtu)[0].max() for _, vtu in frames) or 1.0)
    fig, ax = plt.subplots(figsize=(8, 5))
    fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap="viridis"), ax=ax, label=label, shrink=0.8)
    fig.legend(handles=suite.zone_patches(), loc="lower center", ncol=5, fontsize=7)
    scale = "true scale" if factor == 1 else f"displacements magnified {factor:g} times"
    name = os.path.basename(os.path.normpath(os.path.abspath(folder)))
    outline = xy[suite.boundary_edges(triangles)]

    def draw(k):
        t, vtu = frames[k]
        ax.clear()
        ax.tripcolor(mtri.Triangulation(*moved[k].T, triangles), colour_values(vtu)[0], norm=norm, cmap="viridis",
                     shading="gouraud")
        ax.add_collection(mcollections.LineCollection(outline, colors="0.6", linewidths=0.8))
        zone = array(vtu, "contact_zone").astype(int)
        on = zone >= 0
        ax.scatter(*moved[k][on].T, c=[ZONE_COLORS.get(z, "k") for z in zone[on]], s=12, edgecolors="k",
                   linewidths=0.3, zorder=3)
        ax.set_xlim(low[0] - margin, high[0] + margin)
        ax.set_ylim(low[1] - margin, high[1] + margin)
        ax.set_aspect("equal")
        ax.set_title(f"{name}: t = {t:.4g} s ({scale})")

    draw(0)
    fig.tight_layout(rect=(0, 0.06, 1, 1))             # the zones' legend below
    animation = manimation.FuncAnimation(fig, draw, frames=len(frames), interval=1000 / FPS)
    out = os.path.join(folder, "figures")
    os.makedirs(out, exist_ok=True)
    written = [os.path.join(out, "animation.gif")]
    animation.save(written[0], writer=manimation.PillowWriter(fps=FPS), dpi=DPI)
    if shutil.which("ffmpeg"):
        written.append(os.path.join(out, "animation.mp4"))
        animation.save(written[1], writer=manimation.FFMpegWriter(fps=FPS), dpi=DPI)
    plt.close(fig)
    suite.list_figures(written)
    return written


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", metavar="RUN_DIR")
    for path in animate(parser.parse_args().folder):
        print(path)


if __name__ == "__main__":
    suite.run_tool("animate.py", main, code=2)
