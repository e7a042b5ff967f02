#!/usr/bin/python3
"""The deformed body over time, from the VTK time series of a run (edp/solve.edp -vtk N).

  animate.py RUN_DIR            (./run.sh animate RUN_DIR)

Reads RUN_DIR/vtk/fields.pvd and its .vtu files (at most FRAMES of them, evenly spread,
the first and the last included) and writes RUN_DIR/figures/animation.gif (Pillow), and
animation.mp4 too when ffmpeg is on the PATH. Each frame, shaped to the body: the deformed
mesh (one magnification factor for every frame, given in the title) coloured by the von
Mises stress on one scale for every frame, the
undeformed outline, the contact nodes coloured by zone, x [m] and y [m] (docs/figures.md).
Every frame is read and checked first (a .vtu that is not one, nan or inf in a value drawn,
a zone code out of range: refused, naming the file); the files are written all or nothing
(figurefiles.FigureFiles), never over a file of figures/ that figures.list does not list. Prints
the files written.

A 3D run (summary.txt: dimension 3) needs no vtk/: its animation is Gamma3 seen from outside
(face3d.ContactFace), each node's cell in the colour of its zone at each recorded step of
contact_nodes_history.txt, the nodes per zone against t below (animation3).
"""
import argparse
import contextlib
import io
import os
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import matplotlib.animation as manimation
import matplotlib.collections as mcollections
import matplotlib.colors as mcolors
import matplotlib.tri as mtri
import numpy as np

import face3d
import figurefiles
import gamma3
import runfiles
import style

plt = style.pyplot()
FRAMES, FPS, DPI = 100, 10, 80          # at most 100 frames, 10 a second, 80 pixels an inch
LEGEND = (5, 1.5)                       # the zones' legend: up to 5 columns of 1.5 inches


def save_animation(fig, draw, count, files, written):
    """The frames draw(0 .. count-1) of fig as the GIF written[0] (Pillow) and the MP4
    written[1] (ffmpeg), each into a new file of files (figurefiles.FigureFiles: never through a
    symbolic link), then put into place (files.commit()); returns written."""
    from PIL import Image
    size = [int(side * DPI) for side in fig.get_size_inches()]
    frames = []
    with contextlib.ExitStack() as stack:
        movie = None
        if len(written) > 1:
            target = stack.enter_context(files.open(written[1]))
            movie = manimation.FFMpegWriter(fps=FPS, extra_args=["-pix_fmt", "yuv420p", "-f", "mp4"])
            # ffmpeg writes into the new file through this process's descriptor of it (no name it could follow)
            stack.enter_context(movie.saving(fig, f"/proc/{os.getpid()}/fd/{target.fileno()}", DPI))
        for k in range(count):
            draw(k)
            frame = io.BytesIO()
            fig.savefig(frame, format="rgba", dpi=DPI)
            frames.append(Image.frombuffer("RGBA", size, frame.getbuffer(), "raw", "RGBA", 0, 1))
            if movie:
                movie.grab_frame()
    with files.open(written[0]) as gif:
        frames[0].save(gif, format="GIF", save_all=True, append_images=frames[1:], duration=int(1000 / FPS), loop=0)
    plt.close(fig)
    files.commit()
    return written


def time_series(folder, zones):
    """[(t, Vtu)] of the run's vtk/ folder, at most FRAMES of them, all on the same mesh, their
    zone codes those of the run's zones (style.run_zones)."""
    vtk = os.path.join(folder, "vtk")
    if not os.path.isdir(vtk) or not os.listdir(vtk):          # a run without -vtk N may leave it empty
        raise runfiles.InputError(f"{folder} has no vtk/ time series: run with -vtk N")
    series = runfiles.read_pvd(os.path.join(vtk, "fields.pvd"))
    chosen = np.unique(np.linspace(0, len(series) - 1, min(len(series), FRAMES)).round().astype(int))
    frames = [(series[i][0], runfiles.read_vtu(series[i][1])) for i in chosen]
    for (_, first), (t, frame) in zip(frames, frames[1:]):
        if not np.array_equal(first.triangles, frame.triangles):
            raise runfiles.InputError(f"{frame.path}: the mesh at t = {t:g} is not that of {first.path}")
    for _, vtu in frames:                                         # every value drawn, checked before drawing
        array(vtu, "u", 2)
        colour_values(vtu)
        zone_codes(vtu, zones)
    return frames


def array(vtu, name, columns=None):
    """A point-data array of a frame (its first columns), checked to hold finite numbers:
    InputError naming the .vtu file otherwise."""
    if name not in vtu.point_data:
        raise runfiles.InputError(f"{vtu.path}: no point data '{name}' (it has {' '.join(vtu.point_data)})")
    values = vtu.point_data[name]
    values = values if columns is None else values.reshape(len(vtu.xy), -1)[:, :columns]
    if not np.isfinite(values).all():
        raise runfiles.InputError(f"{vtu.path}: point data '{name}' holds {values[~np.isfinite(values)][0]!r}, "
                               "not a finite number")
    return values


def zone_codes(vtu, zones):
    """The zone code of each point of a frame (contact_zone: -1 off Gamma3, else the code of
    one of the run's zones)."""
    zone = array(vtu, "contact_zone")
    bad = ~np.isin(zone, np.arange(-1, len(zones)))
    if bad.any():
        raise runfiles.InputError(f"{vtu.path}: contact_zone = {zone[bad][0]:g}, not one of -1..{len(zones) - 1}")
    return zone.astype(int)


def colour_values(vtu):
    """The values the body is coloured by: the von Mises stress."""
    return array(vtu, "von_mises"), "von Mises stress [GPa]"


def animate(folder):
    """Write the animation of the run in folder; return the paths written."""
    out = os.path.join(runfiles.run_folder(folder), "figures")
    written = [os.path.join(out, name) for name in ("animation.gif", "animation.mp4")[:2 if shutil.which("ffmpeg") else 1]]
    files = figurefiles.FigureFiles(written)                  # refuses to draw over a file not ours
    fig, draw, count = (animation3 if runfiles.run_dimension(folder) == 3 else animation2)(folder)
    return save_animation(fig, draw, count, files, written)


def animation2(folder):
    """The animation of a 2D run, from its vtk/ time series: (the figure, draw(k) drawing
    frame k into it, the number of frames)."""
    zones = style.run_zones(folder)
    frames = time_series(folder, zones)
    xy, triangles = frames[0][1].xy, frames[0][1].triangles
    largest = max(np.hypot(*array(vtu, "u", 2).T).max() for _, vtu in frames)
    factor = style.magnification(np.ptp(xy, axis=0).max(), largest)
    moved = [xy + factor * array(vtu, "u", 2) for _, vtu in frames]
    label = colour_values(frames[0][1])[1]
    largest = max(float(np.abs(colour_values(vtu)[0]).max()) for _, vtu in frames)
    stress = style.scales(runfiles.read_table(os.path.join(folder, "contact.txt"))).stress
    norm = style.least_norm([largest], max(stress, largest), low=0.0)      # from 0; round-off drawn flat
    scale = "true scale" if factor == 1 else f"displacements magnified {factor:g} times"
    name = os.path.basename(os.path.normpath(os.path.abspath(folder)))
    fig, ax = style.body_figure(np.concatenate([xy] + moved), f"{name} ({scale})\nt = {frames[-1][0]:.4g} s",
                                legend=(len(zones), *LEGEND), box=(5.6, 3.9), right=1.6)
    limits, title = (ax.get_xlim(), ax.get_ylim()), ax.get_title().rsplit("\n", 1)[0]
    fig.set_size_inches(*even_pixels(fig.get_size_inches()))
    fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap="viridis"), ax=ax, label=label, shrink=0.8)
    fig.legend(handles=style.zone_patches(zones), loc="lower center", ncol=style.legend_columns(fig, *LEGEND),
               fontsize=7)
    outline = xy[gamma3.boundary_edges(triangles)]

    def draw(k):
        t, vtu = frames[k]
        ax.clear()
        ax.tripcolor(mtri.Triangulation(*moved[k].T, triangles), colour_values(vtu)[0], norm=norm, cmap="viridis",
                     shading="gouraud")
        ax.add_collection(mcollections.LineCollection(outline, colors="0.6", linewidths=0.8))
        zone = zone_codes(vtu, zones)
        on = zone >= 0
        ax.scatter(*moved[k][on].T, c=[style.zone_color(z) for z in zone[on]], s=12, edgecolors="k",
                   linewidths=0.3, zorder=3)
        ax.set_xlim(*limits[0])
        ax.set_ylim(*limits[1])
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_title(f"{title}\nt = {t:.4g} s")

    draw(len(frames) - 1)                               # the layout for the widest title
    fig.tight_layout(rect=(0, (0.1 + 0.2 * legend_rows(fig, len(zones))) / fig.get_figheight(), 1, 1))   # the zones' legend below
    return fig, draw, len(frames)


def animation3(folder):
    """The animation of a 3D run: its contact face seen from outside (face3d.ContactFace),
    each node's cell in the colour of its zone at each recorded step of
    contact_nodes_history.txt (at most FRAMES of them, evenly spread, the first and the last
    included), the nodes of each zone against t below, a line at the frame's t: (the figure,
    draw(k) drawing frame k into it, the number of frames)."""
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.patches import Patch
    name = os.path.basename(os.path.normpath(os.path.abspath(folder)))
    contact = runfiles.read_table(os.path.join(folder, "contact.txt"))
    mesh = os.path.join(folder, "mesh.msh")
    face = face3d.ContactFace(runfiles.read_msh3(mesh), contact, mesh)
    xyz = np.column_stack(contact.finite("x", "y", "z"))
    _, t, codes = runfiles.node_history(folder, len(contact), xyz)
    zones = style.run_zones(folder)
    chosen = np.unique(np.linspace(0, len(t) - 1, min(len(t), FRAMES)).round().astype(int))
    counts = np.array([[np.sum(row == zone.code) for zone in zones] for row in codes])
    width, left, legend, title, below, history = 8.0, 0.7, 2.2, 0.75, 0.5, 1.6     # inches
    w, h = face.extent() + 0.08 * face.extent().max()               # with the margins of face3d.face_axes
    map_width = width - left - legend - 0.2
    map_height = min(map_width * h / w, 4.5)
    map_width = map_height * w / h
    height = title + map_height + below + 0.35 + history + below
    fig = plt.figure(figsize=even_pixels((width, height)))
    width, height = fig.get_size_inches()

    def box(x, y, w_, h_):                                          # inches from the top left -> figure fraction
        return (x / width, 1 - (y + h_) / height, w_ / width, h_ / height)
    ax = fig.add_axes(box(left, title, map_width, map_height))
    lower = fig.add_axes(box(left, title + map_height + below + 0.35, width - left - legend - 0.2, history))
    quads, owners = face.cells()
    cells = PolyCollection(quads, linewidths=0.4)
    ax.add_collection(cells)
    ax.add_collection(LineCollection(face.uv[face.edges()], colors="w", linewidths=0.5, alpha=0.7))
    ax.plot(*face.uv.T, "o", color="k", markersize=2, markeredgewidth=0)
    face3d.face_axes(ax, face)
    for zone, column in zip(zones, counts.T):
        lower.plot(t, column, color=zone.color)
    now = lower.axvline(t[0], color="k", linewidth=1)
    lower.set_xlabel("t [s]")
    lower.set_ylabel("nodes")
    lower.set_title("nodes per zone on $\\Gamma_3$", fontsize=8)
    colors = np.array([mcolors.to_rgba(zone.color) for zone in zones])

    def draw(k):
        step = chosen[k]
        filled = colors[codes[step][owners]]
        cells.set_facecolor(filled)
        cells.set_edgecolor(filled)
        now.set_xdata([t[step], t[step]])
        if ax.get_legend():
            ax.get_legend().remove()
        ax.legend(handles=[Patch(color=zone.color, label=f"{zone.name}: {style.nodes(count)}")
                           for zone, count in zip(zones, counts[step])], fontsize=7, loc="upper left",
                  bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
        ax.set_title(f"{name}: zones on $\\Gamma_3$ at t = {t[step]:.4g} s\n{face.view}", fontsize=8)

    return fig, draw, len(chosen)


def even_pixels(size):
    """The figure size (inches) rounded to whole, even numbers of pixels at DPI (video
    encoders want even widths and heights)."""
    return [2 * round(side * DPI / 2) / DPI for side in size]


def legend_rows(fig, entries):
    """The rows of the zones' legend (its entries) across the figure's bottom."""
    return -(-entries // style.legend_columns(fig, *LEGEND))


def main():
    runfiles.check_arguments("animate.py")                 # a name not in UTF-8: refused before anything
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", metavar="RUN_DIR")
    for path in animate(parser.parse_args().folder):
        print(path)


if __name__ == "__main__":
    runfiles.run_tool("animate.py", main, code=2, cleanup=figurefiles.abort_pending)
