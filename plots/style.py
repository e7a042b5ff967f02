"""style.py: the look the figures share: matplotlib set up for files (pyplot, STYLE, save),
the zones of a run with their names and colours (run_zones, zone_color, zone_patches,
zone_counts_plot), the paper's segments AB, BC, CD (PAPER_SEGMENTS), the energy terms of
history.txt (energy_terms_plot), labels, and a figure shaped to the body it shows
(magnification, body_figure), and the rule that draws round-off flat: each axis spans at least
a fraction of its quantity's natural scale (Scales, least_span, least_norm, log_floor), with no
offset text. Imported by the scripts of plots/, which put edp/ (runfiles) on the path.
"""
import collections
import os

import numpy as np

import runfiles

STYLE = {
    "figure.figsize": (11, 4),
    "figure.dpi": 100,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "font.size": 9,
    "lines.linewidth": 1.2,
    "lines.markersize": 3,
    "axes.formatter.useoffset": False,      # never an offset ('1e-14+5e-2'): see least_span
}


def pyplot(overrides=None):
    """matplotlib.pyplot on the Agg backend (files only, never a window), with STYLE and then
    the overrides (rcParams)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update(STYLE)
    plt.rcParams.update(overrides or {})
    return plt


def save(fig, out, name, tight_layout=True):
    """Write the figure to OUT/NAME.png (never through a symbolic link: runfiles.new_file),
    close it, return the path."""
    import matplotlib.pyplot as plt
    path = os.path.join(out, name + ".png")
    if tight_layout:
        fig.tight_layout()
    with runfiles.new_file(path) as f:
        fig.savefig(f, format="png")
    plt.close(fig)
    return path


# Round-off is drawn flat (docs/figures.md, "Round-off is drawn flat"). A value computed from
# terms of size S carries round-off of 1e-16 S or more, which an axis fitted to the data alone
# blows up into a pattern: a v_nu = g at every node drawn as a dip of 3.5e-16 under an axis
# labelled '1e-14+5e-2', the 1e-14 noise of the stresses of a free Gamma3 as a zig-zag. So
# every axis and colour scale spans at least LEAST of the natural scale of its quantity
# (Scales), centred on what is drawn, and no axis has an offset (STYLE): a real variation of
# a thousandth of g still fills the axis, round-off is a flat line in its middle.
LEAST = 1e-3                 # the least span of an axis, a fraction of its quantity's scale
LEAST_DISPLACEMENT = 1e-9    # displacements at most this fraction of the body's size: none
ENERGY_DECADES = 12          # an energy axis (log) reaches at most this many decades under its largest term

Scales = collections.namedtuple("Scales", "velocity stress friction force")
Scales.__doc__ = """The natural scales of the quantities of runs (scales()): velocity g, stress p(g),
friction stress mu p(g), force p(g) times the area of Gamma3."""


def scales(*tables):
    """The natural scales (Scales) of the runs of these contact.txt tables, the largest over
    them: velocity the largest g (column g), stress the largest p(g) (column force_scale),
    friction mu p(g) (mu of the parameter lines; p(g) when mu is 0: a frictionless run's
    lambda_tau is round-off of the stresses), force p(g) times the area of Gamma3 (the sum of
    the column weight; per unit thickness in 2D)."""
    velocity = stress = friction = force = 0.0
    for t in tables:
        g, p_g, weight = t.finite("g", "force_scale", "weight")
        mu = t.params.real("mu") if "mu" in t.params else 0.0
        velocity, stress = max(velocity, float(g.max())), max(stress, float(p_g.max()))
        friction = max(friction, (mu if mu > 0 else 1.0) * float(p_g.max()))
        force = max(force, float(p_g.max()) * float(weight.sum()))
    return Scales(velocity, stress, friction, force)


def least_span(ax, scale, axis="y", fraction=LEAST):
    """Widen an axis ('x' or 'y') of ax, and of the axes that share it, to span at least
    fraction * scale (scale: the natural scale of its quantity, Scales), centred on what is
    drawn on them (their data limits), when what is drawn spans less; and turn off its offset
    text. A log axis, or a scale that is not a positive number, is left as it is (offset
    aside). Call it when the axes hold everything they will show: it fixes the limits."""
    which = getattr(ax, axis + "axis")
    formatter = which.get_major_formatter()
    if hasattr(formatter, "set_useOffset"):
        formatter.set_useOffset(False)
    least = fraction * scale
    if not (np.isfinite(least) and least > 0) or which.get_scale() != "linear":
        return
    group = getattr(ax, f"get_shared_{axis}_axes")().get_siblings(ax)
    bounds = np.array([getattr(a.dataLim, "interval" + axis) for a in group], dtype=float)
    bounds = bounds[np.isfinite(bounds).all(axis=1) & (bounds[:, 0] <= bounds[:, 1])]
    low, high = (bounds[:, 0].min(), bounds[:, 1].max()) if len(bounds) else (0.0, 0.0)
    if high - low >= least:
        return
    middle, half = 0.5 * (low + high), 0.5 * least * (1 + 2 * ax.margins()[axis == "y"])
    getattr(ax, f"set_{axis}lim")(middle - half, middle + half)


def least_norm(values, scale, low=None, high=None, fraction=LEAST):
    """A colour scale (matplotlib Normalize) for values, from low to high (by default their
    least and largest), spanning at least fraction * scale (as least_span): widened around
    the values, or only upwards when low is given (a scale from 0)."""
    import matplotlib.colors as mcolors
    values = np.asarray(values, dtype=float)
    fixed = low is not None
    low = float(values.min()) if low is None else float(low)
    high = float(values.max()) if high is None else float(high)
    least = fraction * scale if np.isfinite(fraction * scale) and fraction * scale > 0 else 0.0
    if high - low < least:
        middle = low + 0.5 * least if fixed else 0.5 * (low + high)
        low, high = middle - 0.5 * least, middle + 0.5 * least
    if high <= low:                                  # nothing to go by: a scale of 1 around the value
        low, high = low - 0.5, low + 0.5
    return mcolors.Normalize(low, high)


def log_floor(ax, largest, decades=ENERGY_DECADES):
    """An energy axis (log scale) reaching at most `decades` decades under the largest term
    drawn: what lies further down is round-off of that term, not drawn."""
    if np.isfinite(largest) and largest > 0 and ax.get_ylim()[0] < largest * 10.0 ** -decades:
        ax.set_ylim(bottom=largest * 10.0 ** -decades)


def versions_note(folders, names=None):
    """'runs made by different versions of the suite: A (v1); B (v2)' when the summary.txt of
    the run folders (named by names, by default their folders' names) give different
    suite_version values, the runs of one version together ('A, C (v1); B (v2)'; a run that
    gives none: 'no suite_version'); '' when they agree, or when none gives one (runs made
    before the suite recorded its version)."""
    names = names or [os.path.basename(os.path.normpath(os.path.abspath(folder))) for folder in folders]
    versions = [runfiles.read_summary(folder).get("suite_version") for folder in folders]
    if len(set(versions)) < 2:
        return ""
    groups = {}
    for name, version in zip(names, versions):
        groups.setdefault(version, []).append(runfiles.shown(name, 40))
    return "runs made by different versions of the suite: " + "; ".join(
        f"{', '.join(group)} ({runfiles.shown(version, 40) if version is not None else 'no suite_version'})"
        for version, group in groups.items())


def plain_text(text):
    """Text that matplotlib draws as it is (a '$' not taken for mathtext)."""
    return text.replace("$", "\\$")


def note_versions(fig, folders, names=None):
    """The figure's title says so (versions_note) when the runs it draws were made by
    different versions of the suite."""
    import textwrap
    note = versions_note(folders, names)
    if note:
        lines = textwrap.wrap(plain_text(note), int(fig.get_figwidth() * 14))     # about 14 characters an inch
        fig.suptitle("\n".join(lines), color="tab:red", fontsize=9)


def problem_label(params):
    """'original problem' or 'penalty problem, eps = ...' from a file's parameter lines."""
    if params.get("problem") == "penalty":
        return f"penalty problem, $\\varepsilon$ = {params['eps']}"
    return f"{params.get('problem', '?')} problem"


def nodes(count):
    """'1 node', '2 nodes', ..."""
    return f"{count} node" if count == 1 else f"{count} nodes"


# The zones (docs/figures.md, "The zones") are a run's own: the columns zone_* of its
# contact_history.txt, in the order of their codes (runfiles.zone_columns), which the solver
# names from the law (edp/plugins/contactlaw.hpp). A zone's name in the figures is its
# column's words, its colour that of its code in ZONE_COLORS, the same in every figure.
# Nothing here lists the zones, so that a law with other zones is drawn as it is.
Zone = collections.namedtuple("Zone", "code column name color")
ZONE_COLORS = ("0.6", "tab:green", "tab:olive", "tab:orange", "tab:purple",     # codes 0 to 4
               "tab:red", "tab:brown", "tab:cyan", "tab:pink", "tab:blue")     # (for a law with more zones)


def zone_color(code):
    """The colour of a zone code (ZONE_COLORS, round again past its end)."""
    return ZONE_COLORS[int(code) % len(ZONE_COLORS)]


def zone_name(column):
    """The name of a zone in the figures, its column's words: zone_free 'free',
    zone_bound_slip 'bound, slip'."""
    words = column[len("zone_"):].split("_")
    return ", ".join(part for part in (" ".join(words[:-1]), words[-1]) if part)


def zones(columns):
    """A Zone for each zone column (runfiles.zone_names), the code its place among them."""
    return tuple(Zone(code, column, zone_name(column), zone_color(code)) for code, column in enumerate(columns))


def run_zones(folder):
    """The zones of a run folder (runfiles.zone_columns), a Zone each."""
    return zones(runfiles.zone_columns(folder))


def zone_patches(zones, codes=None, alpha=1.0):
    """Legend handles of the zones (a run's Zones): all of them, or those of the given zone
    codes of nodes, with their node counts."""
    from matplotlib.patches import Patch
    if codes is None:
        return [Patch(color=zone.color, alpha=alpha, label=zone.name) for zone in zones]
    counts = {zone: int(np.sum(np.asarray(codes) == zone.code)) for zone in zones}
    return [Patch(color=zone.color, alpha=alpha, label=f"{zone.name}: {nodes(count)}")
            for zone, count in counts.items() if count]


def zone_counts_plot(ax, h):
    """The nodes of each zone against t, from a contact_history.txt (its columns zone_*)."""
    for zone in zones(runfiles.zone_names(h.columns)):
        ax.plot(h["t"], h[zone.column], color=zone.color, label=zone.name)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("nodes")
    ax.set_title("nodes per zone on $\\Gamma_3$")
    ax.legend(fontsize=7)


# The paper's segments of Gamma3 (section 5), its presentation of the zones: AB damped and
# sliding, BC at the bound and sliding, CD sticking in contact (damped or at the bound); a
# free node is in none. A node's segment comes from its statuses (normal 1 damped, 2 at the
# bound; tangential 0 stick, 1 slip: docs/design.md, "Statuses and zones"); the counts of a
# segment over t, which only the zone counts give (summary.txt, contact_history.txt), from
# the zone columns of those statuses.
Segment = collections.namedtuple("Segment", "name meaning normal tangential columns color")
PAPER_SEGMENTS = (
    Segment("AB", "damped, slip", (1,), (1,), ("zone_damped_slip",), "tab:green"),
    Segment("BC", "at the bound, slip", (2,), (1,), ("zone_bound_slip",), "tab:orange"),
    Segment("CD", "stick", (1, 2), (0,), ("zone_damped_stick", "zone_bound_stick"), "tab:purple"))
PAPER_COLORS = {segment.name: segment.color for segment in PAPER_SEGMENTS}


def paper_segments(c):
    """The paper's segment of each node of a contact.txt, from its statuses ('' for a node in
    none: a free one)."""
    normal, tangential = c.codes("normal_status", 0, 2), c.codes("tangential_status", 0, 1)
    found = np.full(len(normal), "", dtype=object)
    for segment in PAPER_SEGMENTS:
        found[np.isin(normal, segment.normal) & np.isin(tangential, segment.tangential)] = segment.name
    return list(found)


def paper_segment_counts(values):
    """{segment name: its nodes} from zone counts: summary.txt (Values, at T) or the columns of
    a contact_history.txt (a count per step)."""
    def count(column):
        return values.integer(column) if isinstance(values, runfiles.Values) else values[column]
    return {segment.name: sum(count(column) for column in segment.columns) for segment in PAPER_SEGMENTS}


# The energy terms of history.txt (docs/design.md, "Energy identity"): column, label, and
# whether a figure sums it over the steps (the dissipations and the work of a step).
ENERGY_TERMS = (("kinetic", "kinetic", False), ("elastic", "elastic", False),
                ("numerical_dissipation", "numerical dissipation (cumulative)", True),
                ("viscous_dissipation", "viscous dissipation (cumulative)", True),
                ("contact_dissipation", "contact dissipation (cumulative)", True),
                ("external_work", "external work (cumulative)", True))


def energy_terms_plot(ax, h, style="-", labelled=True):
    """The energy terms of a history.txt against t on a log scale (0 is not drawn), a colour
    a term, labelled or not; returns the largest value drawn (for log_floor, once every run
    is drawn)."""
    import matplotlib
    colors = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
    largest = 0.0
    for (column, label, cumulative), color in zip(ENERGY_TERMS, colors):
        values = np.cumsum(h[column]) if cumulative else h[column]
        ax.semilogy(h["t"], values, style, color=color, label=label if labelled else None)
        largest = max(largest, float(np.max(values, initial=0.0)))
    ax.set_xlabel("t [s]")
    ax.set_ylabel("energy per unit thickness [GJ/m]")
    return largest


def magnification(size, largest):
    """The factor (1, 2 or 5 times a power of 10) that shows displacements of at most
    `largest` on a body of extent `size` at about a tenth of it; 1 when they show already (a
    fiftieth of it or more) or are none: at most LEAST_DISPLACEMENT of the size, round-off
    of a body at rest, which a factor of 10^15 would draw as a deformation."""
    if largest <= LEAST_DISPLACEMENT * size or largest >= 0.02 * size:
        return 1.0
    wanted = 0.1 * size / largest
    decade = 10.0 ** np.floor(np.log10(wanted))
    return float(max(step * decade for step in (1, 2, 5) if step * decade <= wanted))


def body_axes(extent, box=(8.0, 6.0), least=2.0):
    """Width and height in inches of axes that show a body of extent (width, height) at equal
    aspect: as large as fits in box, no side under least (a tall column gets tall, narrow axes,
    not a wide figure two thirds empty)."""
    width, height = (max(float(side), 1e-12) for side in extent)
    inches = min(box[0] / width, box[1] / height)
    return max(width * inches, least), max(height * inches, least)


def legend_columns(fig, most=3, width=2.4):
    """How many columns (of `width` inches, at most `most`) a legend across the figure may have."""
    return int(max(1, min(most, fig.get_figwidth() // width)))


def body_figure(points, title, legend=(0, 3, 2.4), box=(8.0, 6.0), right=2.0):
    """A figure and axes for a body whose points (n, 2) it must show, shaped to it (body_axes
    within box; right: inches for a colour bar), x [m] and y [m] at equal aspect, the limits
    those of the points with a margin of a twentieth, the title (its lines wrapped to the
    width), room below for a legend of legend = (entries, most columns, column width) laid
    out as legend_columns() will."""
    import textwrap
    plt = pyplot()
    low, high = np.min(points, axis=0), np.max(points, axis=0)
    margin = 0.05 * (high - low).max()
    low, high = low - margin, high + margin
    width, height = body_axes(high - low, box)
    figure_width = width + right + 0.9
    entries, most, column = legend
    rows = -(-entries // int(max(1, min(most, figure_width // column))))
    lines = [line for part in title.split("\n") for line in textwrap.wrap(part, max(30, int(figure_width * 12)))]
    fig, ax = plt.subplots(figsize=(figure_width, height + 0.9 + 0.2 * len(lines) + 0.22 * rows))
    ax.set_xlim(low[0], high[0])
    ax.set_ylim(low[1], high[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("\n".join(lines))
    return fig, ax
