"""suite.py: the Python helpers shared by plots/ and tests/.

Readers of the solver's outputs and of the suite's own tables, the gmsh MSH 2.2 reader,
the table writer, the boundary labels (edp/lib/forms.idp), the option table
(edp/options.txt) and the scenes (edp/scenes/*.scene), the law a run used (RunScene),
the parser of the solver's
failure message, and the figure style. Every tool imports it as `import suite`: run.sh
puts plots/ on PYTHONPATH, and the scripts of plots/ find it next to them.

The files of edp/solve.edp (docs/design.md, "Output files") are plain text: '#' lines
first, '# name value' for every option of the run, then one '#' line naming the columns,
then one row per line (read_table); summary.txt is 'key value' lines after its '#' lines
(read_summary).

On a missing or corrupt input (a missing file, unreadable numbers, a missing column or
key) the readers raise InputError, whose message names the file and what is wrong; a
tool runs its main() through run_tool(), which prints that message as one line and
exits non-zero, without a traceback.
"""
import collections
import contextlib
import functools
import os
import re
import stat
import sys
import unicodedata

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))   # the repository
EDP = os.path.join(ROOT, "edp")


class InputError(Exception):
    """A missing or unreadable input; the message names the file and the problem."""


def run_tool(tool, main, code=1):
    """Run main(); an InputError, or an OSError of a file, ends the tool with the one line
    'TOOL: error: MESSAGE' on stderr and exit status `code`. Whatever ends main() (an error,
    an exception it did not expect, SIGINT, SIGTERM, SIGHUP), the figures it had not yet put
    into place are removed first (FigureFiles.abort)."""
    import signal

    def stop(number, _frame):
        raise SystemExit(128 + number)
    for number in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(number, stop)
    try:
        try:
            return main()
        finally:
            for pending in list(FigureFiles.pending):
                pending.abort()
    except InputError as error:
        message = str(error)
    except OSError as error:
        message = f"{error.filename}: {error.strerror}" if error.filename else str(error)
    except (IndexError, KeyError, ValueError, ZeroDivisionError) as error:   # an input the tool did not expect
        message = f"cannot use the input ({type(error).__name__}: {error})"
    print(f"{tool}: error: {message}", file=sys.stderr)
    sys.exit(code)


def read_lines(path):
    """The lines of a text file, without their line ends: split at line feeds only (open()
    reads CR LF and CR as LF), not at the other characters that str.splitlines() takes for
    line ends (form feeds, U+2028, ...), which a line may hold."""
    try:
        with open(path) as f:
            text = f.read()
        return text[:-1].split("\n") if text.endswith("\n") else (text.split("\n") if text else [])
    except FileNotFoundError:
        raise InputError(f"missing {path}") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a text file") from None
    except OSError as error:
        raise InputError(f"cannot read {path}: {error.strerror}") from None


# ---------------------------------------------------------------- names, folders and files of the user
FOLDER = os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC
NEW_FILE = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC     # a new file, never a link's target


def shown(value, limit=80):
    """A name (a path, an argument) as a message shows it: bytes that are not UTF-8 and
    control or format characters as backslash escapes (\\xff, \\n, \\u2028), so that the
    message stays one printable line, cut to its start and end around '...' when longer than
    `limit` characters."""
    text = os.fsencode(value).decode("utf-8", "surrogateescape") if isinstance(value, (str, bytes)) else str(value)
    pieces = [f"\\x{ord(c) - 0xdc00:02x}" if 0xdc80 <= ord(c) <= 0xdcff          # a byte that is not UTF-8
              else c.encode("unicode_escape").decode("ascii") if unicodedata.category(c)[0] == "C"
              or unicodedata.category(c) in ("Zl", "Zp") else c for c in text]   # (an escape is never cut)
    if sum(map(len, pieces)) <= limit:
        return "".join(pieces)
    head, tail = "", ""
    for piece in pieces:
        if len(head) + len(piece) > limit // 2:
            break
        head += piece
    for piece in reversed(pieces):
        if len(tail) + len(piece) > limit - limit // 2 - 3:
            break
        tail = piece + tail
    return head + "..." + tail


def refuse(tool, message):
    """End the tool at once: 'TOOL: error: MESSAGE' on stderr, exit status 2 (a bad argument)."""
    print(f"{tool}: error: {message}", file=sys.stderr)
    sys.exit(2)


def check_arguments(tool):
    """Refuse (refuse(): exit 2, before anything is read or written) a command-line argument
    that is not valid UTF-8, or that holds a control character or a line separator (the
    tools print the names they read and write one a line), showing it escaped."""
    for argument in sys.argv[1:]:
        raw = os.fsencode(argument)
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            refuse(tool, f"the argument '{shown(raw)}' is not valid UTF-8 (bytes shown as \\xNN): "
                         "give the name in UTF-8 (rename the folder)")
        if any(unicodedata.category(c) in ("Cc", "Zl", "Zp") for c in text):
            refuse(tool, f"the argument '{shown(raw)}' holds a control character or a line separator: "
                         "rename the folder")


def check_outputs(tool, folders):
    """Refuse (refuse(): exit 2) an output folder given on the command line that exists but
    that open_folder refuses: a symbolic link, or one reached through a link of a run folder."""
    for folder in folders:
        if folder is not None and os.path.lexists(folder):
            try:
                os.close(open_folder(folder))
            except InputError as error:
                refuse(tool, str(error))


def lstat_mode(name, folder):
    """The st_mode of `name` in the folder of descriptor `folder` (a link itself, not what it
    points to); None when there is no such name."""
    try:
        return os.stat(name, dir_fd=folder, follow_symlinks=False).st_mode
    except FileNotFoundError:
        return None


def is_link(name, folder):
    mode = lstat_mode(name, folder)
    return mode is not None and stat.S_ISLNK(mode)


def open_folder(path, make=False):
    """A descriptor of the folder `path` that the tools write into, opened one component at a
    time (missing ones made when make), so that what they write there cannot be sent elsewhere
    by a path changed meanwhile. A symbolic link on the way is followed only where a user's
    own folders may have one: never as the folder itself (the last component), nor inside a
    run folder (a folder holding run.complete: a run's figures/ made a link would send the
    figures elsewhere); InputError for those, and for a folder that cannot be opened."""
    fd = os.open("/" if path.startswith("/") else ".", FOLDER)
    parts = [part for part in path.split("/") if part not in ("", ".")]
    try:
        for k, part in enumerate(parts):
            try:
                try:
                    child = os.open(part, FOLDER | os.O_NOFOLLOW, dir_fd=fd)
                except FileNotFoundError:
                    if not make:
                        raise
                    os.mkdir(part, dir_fd=fd)
                    child = os.open(part, FOLDER | os.O_NOFOLLOW, dir_fd=fd)
            except OSError as error:
                if not is_link(part, fd):
                    raise InputError(f"cannot open the folder {shown(path)}: {error.strerror}") from None
                if k == len(parts) - 1:
                    raise InputError(f"{shown(path)} is a symbolic link: the suite does not write through one; "
                                     "give the folder it points to") from None
                if lstat_mode("run.complete", fd) is not None:
                    link = ("/" if path.startswith("/") else "") + "/".join(parts[:k + 1])
                    raise InputError(f"{shown(path)} is reached through {shown(link)}, a symbolic link in a run "
                                     "folder: the suite does not write through one") from None
                try:
                    child = os.open(part, FOLDER, dir_fd=fd)
                except OSError as error:
                    raise InputError(f"cannot open the folder {shown(path)}: {error.strerror}") from None
            os.close(fd)
            fd = child
    except BaseException:
        os.close(fd)
        raise
    return fd


# ---------------------------------------------------------------- output files
class Values(dict):
    """'name value' pairs of one file (text -> text). A missing name, or a value that is
    not the number asked for, raises InputError naming the file."""

    def __init__(self, source, pairs=()):
        super().__init__(pairs)
        self.source = source

    def __missing__(self, name):
        raise InputError(f"{self.source}: no {name!r}")

    def real(self, name):
        return self.number(name, float, "a number")

    def integer(self, name):
        return self.number(name, int, "a whole number")

    def number(self, name, kind, what):
        value = self[name]
        try:
            return kind(value)
        except ValueError:
            raise InputError(f"{self.source}: {name} = {value!r} is not {what}") from None


class Table:
    """One table file: params (Values of its '# name value' lines), columns (the names on
    its last '#' line) and data (a 2-D numpy array, one row per line); table[name] is the
    column of that name, len(table) the number of rows."""

    def __init__(self, path, params, columns, data, lines=None):
        self.path, self.params, self.columns, self.data = path, params, columns, data
        self.lines = np.arange(1, len(data) + 1) if lines is None else np.asarray(lines)   # of each row

    def __getitem__(self, name):
        if name not in self.columns:
            raise InputError(f"{self.path}: no column {name} (columns: {' '.join(self.columns)})")
        return self.data[:, self.columns.index(name)]

    def __contains__(self, name):
        return name in self.columns

    def __len__(self):
        return self.data.shape[0]

    def finite(self, *names):
        """The columns of these names, each value checked to be a finite number (not nan,
        not inf): InputError naming the file, the line and the column otherwise."""
        for name in names:
            bad = np.flatnonzero(~np.isfinite(self[name]))
            if bad.size:
                raise InputError(f"{self.path}:{self.lines[bad[0]]}: {name} = {float(self[name][bad[0]])!r} is not a finite "
                                 f"number ({bad.size} row{'s' if bad.size > 1 else ''})")
        return [self[name] for name in names]

    def codes(self, name, low, high):
        """The column of that name as whole numbers, each checked to lie in low..high:
        InputError naming the file, the line and the value otherwise."""
        values = self[name]
        bad = np.flatnonzero(~np.isin(values, np.arange(low, high + 1)))
        if bad.size:
            raise InputError(f"{self.path}:{self.lines[bad[0]]}: {name} = {float(values[bad[0]]):g}, not one of "
                             f"{low}..{high}")
        return values.astype(int)

    def rows(self):
        """One Values column name -> value per row."""
        return [Values(self.path, zip(self.columns, row)) for row in self.data]


def read_table(path, dtype=float, empty=False):
    """A table written by edp/solve.edp or by the suite's tools: its '#' header lines
    (the last one names the columns), then rows of dtype (float, or str for tables with
    words in them); at least one row unless empty."""
    lines = read_lines(path)
    header = []
    for line in lines:
        if not line.startswith("#"):
            break
        header.append(line[1:].split())
    if not header or not header[-1]:
        raise InputError(f"{path}: no '#' line naming the columns")
    columns = header[-1]
    params = Values(path, (words for words in header[:-1] if len(words) == 2))
    rows = [(number, line) for number, line in enumerate(lines[len(header):], len(header) + 1)
            if line.split("#", 1)[0].strip()]
    if not rows:
        if not empty:
            raise InputError(f"{path}: no data rows (an interrupted or truncated file?)")
        return Table(path, params, columns, np.empty((0, len(columns)), dtype=dtype))
    try:
        data = np.loadtxt([line for _, line in rows], dtype=dtype, comments="#", ndmin=2)
    except ValueError:
        data = None
    if data is None or data.shape[1] != len(columns):
        for number, line in rows:                        # name the first bad line
            words = line.split("#", 1)[0].split()
            try:
                [dtype(word) for word in words]
            except ValueError:
                raise InputError(f"{path}:{number}: unreadable numbers in '{line}'") from None
            if len(words) != len(columns):
                raise InputError(f"{path}:{number}: {len(words)} values for the {len(columns)} columns "
                                 f"{' '.join(columns)}")
        raise InputError(f"{path}: unreadable rows")
    return Table(path, params, columns, data, [number for number, _ in rows])


def read_summary(path):
    """The 'key value' lines of a run's summary.txt (a value may contain spaces); path is
    the file or the run folder."""
    if os.path.isdir(path) or not path.endswith(".txt"):
        path = os.path.join(path, "summary.txt")
    summary = Values(path)
    for line in read_lines(path):
        if line.startswith("#") or not line.strip():
            continue
        words = line.split(None, 1)
        summary[words[0]] = words[1].strip() if len(words) > 1 else ""
    return summary


def run_folder(folder):
    """The folder, if it is the folder of a finished run (it holds summary.txt and
    run.complete, docs/design.md "Output files"); otherwise InputError."""
    if not os.path.isdir(folder):
        raise InputError(f"{shown(folder)}: no such folder")
    missing = [name for name in ("summary.txt", "run.complete") if not os.path.isfile(os.path.join(folder, name))]
    if missing:
        raise InputError(f"{shown(folder)} is not the folder of a finished run (no {' and no '.join(missing)})")
    return folder


def problem_label(params):
    """'original problem' or 'penalty problem, eps = ...' from a file's parameter lines."""
    if params.get("problem") == "penalty":
        return f"penalty problem, $\\varepsilon$ = {params['eps']}"
    return f"{params.get('problem', '?')} problem"


def write_solution(out, comments, contact, fields):
    """The results of an independent solver (tests/independent_solver*.py): OUT/contact.txt and
    OUT/fields.txt, each (columns, rows) after the '# ' lines of comments (write_table)."""
    os.makedirs(out, exist_ok=True)
    for name, (columns, rows) in (("contact.txt", contact), ("fields.txt", fields)):
        write_table(os.path.join(out, name), comments, columns, rows)


def independent_main(program, run, input_errors, convergence_error):
    """The exit code of an independent solver's run(): 2 with 'PROGRAM: error: WHY' on a bad
    input (an exception of input_errors), 4 with 'PROGRAM: WHY' on a step that did not converge."""
    try:
        return run()
    except input_errors as e:
        print("%s: error: %s" % (program, e), file=sys.stderr)
        return 2
    except convergence_error as e:
        print("%s: %s" % (program, e), file=sys.stderr)
        return 4


def write_table(path, comments, columns, rows):
    """A table in the format of the solver's outputs: a '# ' line per comment, the '#' line
    naming the columns, then the rows; floats written with repr (full precision, the same
    text on every run), anything else with str."""
    def text(value):
        if isinstance(value, (float, np.floating)):
            return repr(float(value))
        if isinstance(value, np.integer):
            return str(int(value))
        return str(value)
    lines = [f"# {line}" for line in comments] + ["# " + " ".join(columns)]
    lines += [" ".join(text(value) for value in row) for row in rows]
    with new_file(path) as f:                   # never through a symbolic link
        f.write(("\n".join(lines) + "\n").encode())


# ---------------------------------------------------------------- meshes
Mesh = collections.namedtuple("Mesh", "xy ids triangles lines line_labels")
Mesh.__doc__ = """A gmsh MSH 2.2 mesh. xy: (nodes, 2) coordinates in the file's node order;
ids: gmsh node number -> row of xy; triangles: (triangles, 3) rows of xy; lines: (lines, 2)
rows of xy of the 2-node boundary lines; line_labels: the physical label of each line
(its first tag; the labels are those of labels())."""


def read_msh22(path):
    """The nodes, triangles and labelled boundary lines of an ASCII gmsh MSH 2.2 file."""
    return _read_msh22(path, 2)


Mesh3 = collections.namedtuple("Mesh3", "xyz ids tetrahedra faces face_labels")
Mesh3.__doc__ = """A 3D gmsh MSH 2.2 mesh (docs/design.md, "Three dimensions"). xyz: (nodes, 3)
coordinates in the file's node order; ids: gmsh node number -> row of xyz; tetrahedra:
(tetrahedra, 4) rows of xyz; faces: (faces, 3) rows of xyz of the boundary triangles;
face_labels: the physical label of each (its first tag; 1 the contact surface Gamma3)."""


def read_msh3(path):
    """The nodes, tetrahedra and labelled boundary triangles of an ASCII gmsh MSH 2.2 file of
    a 3D body."""
    return _read_msh22(path, 3)


def _read_msh22(path, dimension):
    """read_msh22 (dimension 2: triangles, boundary lines) or read_msh3 (3: tetrahedra,
    boundary triangles)."""
    lines = read_lines(path)
    sections = {line.strip(): i for i, line in enumerate(lines) if line.startswith("$")}
    for name in ("$MeshFormat", "$Nodes", "$Elements"):
        if name not in sections:
            raise InputError(f"{path}: not a gmsh MSH 2.2 file (no {name} section)")
    try:
        version, filetype = lines[sections["$MeshFormat"] + 1].split()[:2]
        if not version.startswith("2.") or filetype != "0":
            raise InputError(f"{path}: not an ASCII gmsh MSH 2.x file (format {version} {filetype})")
        start = sections["$Nodes"]
        count = int(lines[start + 1])
        ids, xy = {}, np.empty((count, dimension))
        for i, line in enumerate(lines[start + 2:start + 2 + count]):
            words = line.split()
            ids[int(words[0])] = i
            xy[i] = [float(words[k]) for k in range(1, 1 + dimension)]
        start = sections["$Elements"]
        count = int(lines[start + 1])
        triangles, edges, labels_, tetrahedra = [], [], [], []
        for line in lines[start + 2:start + 2 + count]:
            words = [int(w) for w in line.split()]
            kind, ntags = words[1], words[2]
            nodes = [ids[n] for n in words[3 + ntags:]]
            if kind == 2:                                  # 3-node triangle
                triangles.append(nodes[:3])
                if dimension == 3:                         # a boundary face
                    if ntags < 1:
                        raise InputError(f"{path}: a boundary triangle without a physical label")
                    labels_.append(words[3])
            elif kind == 1 and dimension == 2:             # 2-node line
                if ntags < 1:
                    raise InputError(f"{path}: a boundary line without a physical label")
                edges.append(nodes[:2])
                labels_.append(words[3])
            elif kind == 4 and dimension == 3:             # 4-node tetrahedron
                tetrahedra.append(nodes[:4])
    except (ValueError, IndexError, KeyError) as error:
        raise InputError(f"{path}: not a readable gmsh MSH 2.2 file ({type(error).__name__}: {error})") from None
    if dimension == 3:
        if not tetrahedra:
            raise InputError(f"{path}: no tetrahedra (the mesh of a 3D run)")
        return Mesh3(xy, ids, np.array(tetrahedra, dtype=int), np.array(triangles, dtype=int).reshape(-1, 3),
                     np.array(labels_, dtype=int))
    if not triangles:
        raise InputError(f"{path}: no triangles")
    return Mesh(xy, ids, np.array(triangles, dtype=int), np.array(edges, dtype=int).reshape(-1, 2),
                np.array(labels_, dtype=int))


@functools.lru_cache(maxsize=None)
def _labels():
    path = os.path.join(EDP, "lib", "forms.idp")
    found = re.findall(r"^\s*int\s+(Gamma\w+)\s*=\s*(\d+)\s*;", "\n".join(read_lines(path)), re.MULTILINE)
    if not found:
        raise InputError(f"{path}: no 'int GammaNAME = LABEL;' lines")
    return tuple((name, int(label)) for name, label in found)


def labels():
    """The boundary labels named in edp/lib/forms.idp, e.g. {"GammaContact": 1, ...}."""
    return dict(_labels())


def nearest(points, targets):
    """For each target (x, y), the row of the nearest of points (n, 2)."""
    points = np.asarray(points, dtype=float)
    return np.array([int(np.argmin(np.hypot(*(points - target).T))) for target in np.asarray(targets, dtype=float)],
                    dtype=int)


def boundary_edges(triangles):
    """The edges (pairs of nodes) that belong to one triangle only: the boundary of the body."""
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    return unique[counts == 1]


def boundary_arc_length(mesh, label):
    """The arc length along the boundary lines of `label`: {row of mesh.xy: s}. The walk
    starts at the end of smallest (x, y); where the boundary is in pieces, each next piece
    starts from its own end of smallest (x, y), s going on across the straight gap."""
    neighbours = collections.defaultdict(list)
    for a, b in mesh.lines[mesh.line_labels == label]:
        neighbours[a].append(b)
        neighbours[b].append(a)
    s, last, length = {}, None, 0.0
    while len(s) < len(neighbours):
        left = [node for node in neighbours if node not in s]
        ends = [node for node in left if len(neighbours[node]) == 1] or left     # a closed loop has no end
        node = min(ends, key=lambda n: tuple(mesh.xy[n]))
        while node is not None:                             # along the piece, to its other end
            if last is not None:
                length += float(np.hypot(*(mesh.xy[node] - mesh.xy[last])))
            s[node], last = length, node
            node = next((n for n in neighbours[node] if n not in s), None)
    return s


def contact_position(mesh, x, y):
    """Where the contact nodes (x, y) lie along Gamma3, and the axis label: x itself when
    Gamma3 is straight along x (every y the same), otherwise the arc length along the mesh's
    contact boundary (boundary_arc_length), each node taken as the nearest node of it."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if np.ptp(y) <= 1e-9 * max(np.ptp(x), 1e-300):
        return x, "x [m]"
    s = boundary_arc_length(mesh, labels()["GammaContact"])
    if not s:
        raise InputError("the mesh has no contact boundary (physical curve 1)")
    nodes = np.array(sorted(s))
    start = mesh.xy[min(s, key=s.get)]
    return (np.array([s[n] for n in nodes[nearest(mesh.xy[nodes], np.c_[x, y])]]),
            f"arc length along $\\Gamma_3$ from ({start[0]:.3g}, {start[1]:.3g}) [m]")


def read_xml(path):
    """The root element of an XML file."""
    import xml.etree.ElementTree as ElementTree
    try:
        return ElementTree.parse(path).getroot()
    except ElementTree.ParseError as error:
        raise InputError(f"{path}: not an XML file ({error})") from None
    except FileNotFoundError:
        raise InputError(f"missing {path}") from None


def vtk_array(path, element, where):
    """The numbers of a DataArray element of the VTK file path (named `where` in messages):
    (n,) for one component, (n, k) for k."""
    if element is None:
        raise InputError(f"{path}: no {where}")
    if element.get("format", "ascii") != "ascii":
        raise InputError(f"{path}: {where} is not ascii")
    try:
        values = np.array((element.text or "").split(), dtype=float)
        components = int(element.get("NumberOfComponents", "1"))
    except ValueError:
        raise InputError(f"{path}: unreadable numbers in {where}") from None
    if components < 1 or values.size % components:
        raise InputError(f"{path}: {where} has {values.size} values for {components} components")
    return values.reshape(-1, components) if components > 1 else values


Vtu = collections.namedtuple("Vtu", "xy triangles point_data path")


def read_vtu(path):
    """One ASCII VTK XML UnstructuredGrid of triangles, as edp/solve.edp -vtk writes it:
    Vtu(xy (points, 2), triangles (cells, 3), point_data {name: (points,) or (points, k)}, path)."""
    piece = read_xml(path).find("UnstructuredGrid/Piece")
    if piece is None:
        raise InputError(f"{path}: not a VTK UnstructuredGrid file (no UnstructuredGrid/Piece)")
    xy = vtk_array(path, piece.find("Points/DataArray"), "Points")
    if xy.ndim != 2 or xy.shape[1] < 2:
        raise InputError(f"{path}: the Points need 2 or 3 components")
    cells = {name: vtk_array(path, piece.find(f"Cells/DataArray[@Name='{name}']"), f"Cells {name}").astype(int)
             for name in ("connectivity", "offsets", "types")}
    if (cells["types"] != 5).any() or not np.array_equal(cells["offsets"], 3 * np.arange(1, cells["types"].size + 1)):
        raise InputError(f"{path}: the cells are not all triangles (VTK type 5)")
    triangles = cells["connectivity"].reshape(-1, 3)
    if triangles.size and (triangles.min() < 0 or triangles.max() >= len(xy)):
        raise InputError(f"{path}: a cell names a point that does not exist")
    data = {element.get("Name"): vtk_array(path, element, f"PointData {element.get('Name')}")
            for element in piece.findall("PointData/DataArray")}
    for name, values in data.items():
        if len(values) != len(xy):
            raise InputError(f"{path}: PointData {name} has {len(values)} rows for {len(xy)} points")
    return Vtu(xy[:, :2], triangles, data, path)


def read_pvd(path):
    """The time series of a ParaView collection file: [(t, path of its .vtu file)], in the
    file's order."""
    sets = read_xml(path).findall("Collection/DataSet")
    try:
        series = [(float(item.get("timestep")), os.path.join(os.path.dirname(path), item.get("file"))) for item in sets]
    except (TypeError, ValueError):
        raise InputError(f"{path}: a DataSet without a numeric timestep and a file") from None
    if not series:
        raise InputError(f"{path}: no DataSet in its Collection")
    for t, file in series:
        if not np.isfinite(t):
            raise InputError(f"{path}: the DataSet of {os.path.basename(file)} has timestep {t!r}, not a finite number")
    return series


# ---------------------------------------------------------------- options and scenes
Option = collections.namedtuple("Option", "name type range default meaning")
Option.__doc__ = "One option of edp/options.txt; default None where the scene gives it ('-')."
Rule = collections.namedtuple("Rule", "option value name default")
Rule.__doc__ = "A line 'when OPTION=VALUE NAME DEFAULT' of edp/options.txt."


@functools.lru_cache(maxsize=None)
def _option_table():
    path = os.path.join(EDP, "options.txt")
    options, rules = [], []
    for number, line in enumerate(read_lines(path), 1):
        words = line.split(None, 4)
        if not words or line.startswith("#"):
            continue
        if words[0] == "when" and len(words) == 4 and "=" in words[1]:
            option, _, value = words[1].partition("=")
            rules.append(Rule(option, value, words[2], words[3]))
        elif len(words) >= 4:
            name, kind, bounds, default = words[:4]
            options.append(Option(name, kind, bounds, None if default == "-" else default,
                                  words[4] if len(words) > 4 else ""))
        else:
            raise InputError(f"{path}:{number}: cannot read '{line}'")
    return tuple(options), tuple(rules)


def option_table():
    """The command-line options of edp/solve.edp from edp/options.txt: ({name: Option}
    in the file's order, [Rule]). A Rule sets the default of Rule.name when the option
    Rule.option has the value Rule.value and Rule.name was not given."""
    options, rules = _option_table()
    return {option.name: option for option in options}, list(rules)


def scene_path(scene):
    """The file of a scene: a name (paper, column) means edp/scenes/NAME.scene; a path
    (with a '/' or ending in .scene) is the file itself, as for edp/solve.edp -scene."""
    if "/" in scene or ".scene" in scene:
        return scene
    return os.path.join(EDP, "scenes", scene + ".scene")


Scene = collections.namedtuple("Scene", "path options data")
Scene.__doc__ = """A scene file. options: the defaults it sets (a line 'NAME VALUE' whose NAME
is an option, but not scene or out); data: its other lines, key -> list of the words after
the key, one list per line (geometry, Lx, Ly, dirichlet, traction, contact_normal)."""


@functools.lru_cache(maxsize=None)
def _scene(path):
    options = {name for name in option_table()[0] if name not in ("scene", "out")}
    defaults, data = [], []
    for line in read_lines(path):
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        if len(words) == 2 and words[0] in options:
            defaults.append((words[0], words[1]))
        else:
            data.append((words[0], tuple(words[1:])))
    return tuple(defaults), tuple(data)


def read_scene(scene):
    """The scene of a name or a file (scene_path)."""
    path = scene_path(scene)
    defaults, data = _scene(path)
    lines = {}
    for key, words in data:
        lines.setdefault(key, []).append(list(words))
    return Scene(path, dict(defaults), lines)


def effective_options(given, scene=None):
    """The options a run used, as Values: the defaults of edp/options.txt, then those of the
    scene (the scene argument, else given["scene"], else the table's default), then the
    given ones (name -> value as on the command line, without the '-'), then the 'when'
    rules for the options not given. An option that has no value anywhere is left out."""
    options, rules = option_table()
    unknown = [name for name in given if name not in options]
    if unknown:
        raise InputError(f"unknown option -{unknown[0]} (options: {' '.join(options)})")
    values = {name: option.default for name, option in options.items() if option.default is not None}
    path = scene_path(scene or given.get("scene") or values["scene"])
    read = read_scene(path)
    values.update(read.options)
    damping = read.data.get("damping")                  # its C is the default of -cnu (a table has none: 0)
    if damping and damping[0][0] in ("linear", "power") and len(damping[0]) > 1:
        values["cnu"] = damping[0][1]
    elif damping:
        values["cnu"] = "0"
    values.update(given)
    for rule in rules:
        if rule.name not in given and values.get(rule.option) == rule.value:
            values[rule.name] = rule.default
    return Values(f"the options of a run (scene {path})", ((name, values[name]) for name in options if name in values))


# ---------------------------------------------------------------- the law a run used
def piecewise(points, x):
    """The piecewise linear function through points (x0, y0, x1, y1, ...), constant outside."""
    return np.interp(x, points[0::2], points[1::2])


class RunScene:
    """What a run's own scene (OUT/scene.scene, the values it used; params: the run's options,
    for -cnu and -g) says of its law, as docs/design.md states the scene keys: p(r) of its
    damping family, the bound g(x) (bound_profile), the load factor h(t) (load_history) and
    body_force. Written from the documentation, not from the solver (whose law is
    edp/plugins/contactlaw.hpp): tests/check_results.py checks the outputs against it, and
    the figures draw it. A folder without scene.scene: InputError when required, else the
    paper's law with the run's -cnu."""

    def __init__(self, folder, params, required=False):
        path = os.path.join(folder, "scene.scene")
        if required and not os.path.isfile(path):
            raise InputError(f"missing {path}: the run's law (its bound g, its damping) is not known")
        data = read_scene(path).data if os.path.isfile(path) else {}
        def words(key):
            if key not in data:
                return None
            try:
                return [float(w) for w in data[key][0][1 if key == "damping" else 0:]]
            except ValueError:
                raise InputError(f"{path}: {key} needs numbers") from None

        family = data["damping"][0][0] if "damping" in data else "linear"
        numbers = words("damping") or [params.real("cnu")]
        if family == "linear":
            self.p = lambda r: numbers[0] * np.maximum(r, 0.0)
        elif family == "power":
            self.p = lambda r: numbers[0] * np.maximum(r, 0.0) ** numbers[1]
        else:                           # table: through the points from (0, 0), then the last slope
            rs, ps = np.array(numbers[0::2]), np.array(numbers[1::2])
            last = (ps[-1] - ps[-2]) / (rs[-1] - rs[-2])
            self.p = lambda r: np.where(r <= 0, 0.0, np.where(r <= rs[-1], np.interp(r, rs, ps),
                                                               ps[-1] + last * (r - rs[-1])))
        self.family = family
        profile = words("bound_profile")
        g = None if profile else params.real("g")        # with a profile, -g reads "bound_profile"
        self.g = (lambda x: piecewise(profile, x)) if profile else (lambda x: np.full(np.shape(x), g))
        self.body_force = words("body_force") or [0.0, 0.0]
        history = words("load_history")
        self.h = (lambda t: piecewise(history, t)) if history else (lambda t: np.asarray(t, dtype=float))

    def inverse(self, q):
        """r >= 0 with p(r) = q (q >= 0; p nondecreasing, increasing where it is inverted)."""
        lo, hi = 0.0, 1.0
        while self.p(hi) < q:
            if hi > 1e300:
                return np.inf           # p stays below q (a table that ends flat)
            hi *= 2
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if self.p(mid) < q else (lo, mid)
        return 0.5 * (lo + hi)

    def slope(self, r):
        """p'(r) from the left (a difference quotient)."""
        step = 1e-7 * max(r, 1e-300)
        return (self.p(r) - self.p(r - step)) / step


# ---------------------------------------------------------------- the solver's failure message
SolverFailure = collections.namedtuple("SolverFailure", "step t iterations mode residual tol")
FAILURE_MESSAGE = re.compile(r"step (\d+) \(t = ([^)]*)\): the contact solver did not converge after (\d+) "
                             r"iterations \(([^)]*)\), residual (\S+) > tol ([^\s;]+)")


def solver_failure(message):
    """Parse the message of a step that failed (edp/solve.edp, exit 4 or 5), a contract of
    docs/design.md, "Exit codes and failure messages": 'error: step N (t = T): the contact
    solver did not converge after I iterations (MODE), residual R > tol TOL; no results
    written'. Returns
    SolverFailure(step, t, iterations, mode, residual, tol), or None when the message is
    not that one. MODE says why, e.g. 'iteration cap reached', 'non-finite residual'."""
    match = FAILURE_MESSAGE.search(message or "")
    if not match:
        return None
    step, t, iterations, mode, residual, tol = match.groups()
    try:
        return SolverFailure(int(step), float(t), int(iterations), mode, float(residual), float(tol))
    except ValueError:
        return None


# ---------------------------------------------------------------- zones on Gamma3
Zone = collections.namedtuple("Zone", "code column name color")
Zone.__doc__ = """A zone of docs/design.md, "Statuses and zones": its code (the column `zone` of
contact_nodes_history.txt, `contact_zone` of the VTK files), its column of summary.txt and
contact_history.txt, its name and its colour in every figure."""
ZONES = (Zone(0, "zone_free", "free", "0.6"),
         Zone(1, "zone_damped_slip", "damped, slip", "tab:green"),
         Zone(2, "zone_damped_stick", "damped, stick", "tab:olive"),
         Zone(3, "zone_bound_slip", "at the bound, slip", "tab:orange"),
         Zone(4, "zone_bound_stick", "at the bound, stick", "tab:purple"))


def zone_codes(normal_status, tangential_status):
    """The zone code of each contact node from its statuses: 0 free (normal status 0), else
    2 normal - tangential: 1 damped slip, 2 damped stick, 3 bound slip, 4 bound stick."""
    normal = np.asarray(normal_status).astype(int)
    return np.where(normal == 0, 0, 2 * normal - np.asarray(tangential_status).astype(int))


def contact_pieces(mesh, x, y):
    """The piece of Gamma3 each contact node (x, y) lies on, numbered 0, 1, ...: the mesh's
    boundary lines of the contact label (physical curve 1), joined where they share a node,
    make the pieces (one for a connected Gamma3, two for a body standing on two feet). Each
    node is taken as the nearest node of those lines."""
    edges = mesh.lines[mesh.line_labels == labels()["GammaContact"]]
    if not len(edges):
        raise InputError("the mesh has no contact boundary (physical curve 1)")
    parent = {}

    def root(node):
        while parent.setdefault(node, node) != node:
            node = parent[node]
        return node
    for a, b in edges:
        parent[root(a)] = root(b)
    on = np.array(sorted(parent))
    numbers = {}
    piece = {node: numbers.setdefault(root(node), len(numbers)) for node in on}
    return np.array([piece[node] for node in on[nearest(mesh.xy[on], np.c_[x, y])]], dtype=int)


def node_cells(position, pieces=None):
    """The stretch of Gamma3 each node holds, as arrays (start, end): up to halfway to its
    neighbours along Gamma3 on its own piece (contact_pieces; one piece when None), up to its
    own position where it ends its piece. A gap between two pieces belongs to no node."""
    position = np.asarray(position, dtype=float)
    pieces = np.zeros(len(position), dtype=int) if pieces is None else np.asarray(pieces)
    start, end = position.copy(), position.copy()
    for piece in np.unique(pieces):
        nodes_ = np.flatnonzero(pieces == piece)
        nodes_ = nodes_[np.argsort(position[nodes_], kind="stable")]
        halfway = 0.5 * (position[nodes_[1:]] + position[nodes_[:-1]])
        start[nodes_[1:]], end[nodes_[:-1]] = halfway, halfway
    return start, end


def along_gamma3(position, pieces, *columns):
    """position and the columns in the order of position, a nan put between two nodes of
    different pieces of Gamma3: a curve through them is broken across the gaps."""
    order = np.argsort(position, kind="stable")
    cuts = np.flatnonzero(np.diff(np.asarray(pieces)[order]) != 0) + 1
    return [np.insert(np.asarray(column, dtype=float)[order], cuts, np.nan) for column in (position,) + columns]


def map_columns(position, pieces):
    """The columns of a map of the contact nodes along Gamma3 (pcolormesh): their edges, and
    for each column the node it shows (in the order of position), or -1 for a gap between two
    pieces of Gamma3, to be left blank."""
    start, end = node_cells(position, pieces)
    order = np.argsort(position, kind="stable")
    edges, columns = [start[order[0]]], []
    for before, node in zip(np.r_[-1, order[:-1]], order):
        if before >= 0 and pieces[node] != pieces[before]:
            edges.append(start[node])
            columns.append(-1)
        edges.append(end[node])
        columns.append(node)
    return np.array(edges), np.array(columns, dtype=int)


def stretches(position, keys, pieces=None):
    """The stretches of Gamma3 over which consecutive nodes (in the order of position, on
    the same piece of Gamma3) have the same key: [(key, start, end, nodes)], wherever they
    lie, a key perhaps in several stretches. Each node holds the cell of node_cells (halfway
    to its neighbours on its piece); a stretch never spans the gap between two pieces."""
    pieces = np.zeros(len(keys), dtype=int) if pieces is None else np.asarray(pieces)
    start, end = node_cells(position, pieces)
    found = []
    for node in np.argsort(position, kind="stable"):
        if found and found[-1][0] == keys[node] and found[-1][4] == pieces[node]:
            found[-1][2], found[-1][3] = end[node], found[-1][3] + 1
        else:
            found.append([keys[node], start[node], end[node], 1, pieces[node]])
    return [(key, first, last, count) for key, first, last, count, _ in found]


def shade_stretches(ax, found, colors, alpha=0.15):
    """Shade each stretch (of stretches()) whose key has a colour in colors."""
    for key, start, end, _ in found:
        if key in colors:
            ax.axvspan(start, end, color=colors[key], alpha=alpha, linewidth=0)


def label_stretches(ax, found, texts, heights, fontsize=8):
    """Write texts[key] once per key, centred over the widest of its stretches, at the first
    of the heights (fractions of the axes' height) where it overlaps no label written before
    (at the last height when none is free). Call it once the layout and the x limits of ax
    are final."""
    widest = {}
    for key, start, end, _ in found:
        if key in texts and (key not in widest or end - start > widest[key][1] - widest[key][0]):
            widest[key] = (start, end)
    renderer = ax.figure.canvas.get_renderer()
    boxes = []
    for key, (start, end) in sorted(widest.items(), key=lambda item: item[1]):
        for y in heights:
            label = ax.text(0.5 * (start + end), y, texts[key], ha="center", fontsize=fontsize,
                            transform=ax.get_xaxis_transform())
            box = label.get_window_extent(renderer).padded(1)
            if y == heights[-1] or not any(box.overlaps(other) for other in boxes):
                break
            label.remove()
        boxes.append(box)


def nodes(count):
    """'1 node', '2 nodes', ..."""
    return f"{count} node" if count == 1 else f"{count} nodes"


def zone_patches(codes=None, alpha=1.0):
    """Legend handles of the zones: all five, or those of the given zone codes of nodes,
    with their node counts."""
    from matplotlib.patches import Patch
    if codes is None:
        return [Patch(color=zone.color, alpha=alpha, label=zone.name) for zone in ZONES]
    counts = {zone: int(np.sum(np.asarray(codes) == zone.code)) for zone in ZONES}
    return [Patch(color=zone.color, alpha=alpha, label=f"{zone.name}: {nodes(count)}")
            for zone, count in counts.items() if count]


def zone_counts_plot(ax, h):
    """The nodes of each zone against t, from a contact_history.txt."""
    for zone in ZONES:
        ax.plot(h["t"], h[zone.column], color=zone.color, label=zone.name)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("nodes")
    ax.set_title("nodes per zone on $\\Gamma_3$")
    ax.legend(fontsize=7)


# The energy terms of history.txt (docs/design.md, "Energy identity"): column, label, and
# whether a figure shows it summed over the steps (the dissipations and the work of a step).
ENERGY_TERMS = (("kinetic", "kinetic", False), ("elastic", "elastic", False),
                ("numerical_dissipation", "numerical dissipation (cumulative)", True),
                ("viscous_dissipation", "viscous dissipation (cumulative)", True),
                ("contact_dissipation", "contact dissipation (cumulative)", True),
                ("external_work", "external work (cumulative)", True))


def energy_terms_plot(ax, h, style="-", labelled=True):
    """The energy terms of a history.txt against t, on a log scale (0 is not drawn), one
    colour per term, labelled or not."""
    import matplotlib
    colors = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
    for (column, label, cumulative), color in zip(ENERGY_TERMS, colors):
        values = np.cumsum(h[column]) if cumulative else h[column]
        ax.semilogy(h["t"], values, style, color=color, label=label if labelled else None)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("energy per unit thickness [GJ/m]")


def magnification(size, largest):
    """The factor (1, 2 or 5 times a power of 10) that shows displacements of at most
    `largest` on a body of extent `size` at about a tenth of it; 1 when they show already
    (a fiftieth of it or more) or are 0."""
    if largest <= 0 or largest >= 0.02 * size:
        return 1.0
    wanted = 0.1 * size / largest
    decade = 10.0 ** np.floor(np.log10(wanted))
    return float(max(step * decade for step in (1, 2, 5) if step * decade <= wanted))


def body_axes(extent, box=(8.0, 6.0), least=2.0):
    """Width and height in inches of axes that show a body of extent (width, height) at equal
    aspect: as large as fits in box, no side under least (a tall column gets tall, narrow
    axes, not a wide figure two thirds empty)."""
    width, height = (max(float(side), 1e-12) for side in extent)
    inches = min(box[0] / width, box[1] / height)
    return max(width * inches, least), max(height * inches, least)


def legend_columns(fig, most=3, width=2.4):
    """How many columns (of `width` inches, at most `most`) a legend across the figure's
    width may have."""
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


# ---------------------------------------------------------------- three dimensions
def run_dimension(folder):
    """2 or 3: the 'dimension' line of a run's summary.txt (docs/design.md, "Three
    dimensions"); a run of an older version, which has none, is 2D."""
    summary = read_summary(folder)
    value = summary.get("dimension", "2")
    if value not in ("2", "3"):
        raise InputError(f"{summary.source}: dimension = {value!r}, not 2 or 3")
    return int(value)


def nearest_rows(points, targets):
    """For each target (a row of coordinates), the row of the nearest of points and its
    distance: (rows, distances)."""
    points, targets = np.asarray(points, dtype=float), np.asarray(targets, dtype=float)
    rows, distances = np.empty(len(targets), dtype=int), np.empty(len(targets))
    for start in range(0, len(targets), 256):                  # a block of targets at a time
        block = np.linalg.norm(points[None, :, :] - targets[start:start + 256, None, :], axis=2)
        rows[start:start + 256] = np.argmin(block, axis=1)
        distances[start:start + 256] = block[np.arange(len(block)), rows[start:start + 256]]
    return rows, distances


def surface_frame(normal):
    """The frame (n, t1, t2) of a unit normal by the solver's rule (docs/design.md, "Three
    dimensions"): t1 the coordinate axis least aligned with n (the first of those within 1e-9
    of the least |n_k|) made orthogonal to it, t2 = n x t1, so that t1 x t2 = n."""
    n = np.asarray(normal, dtype=float) / np.linalg.norm(normal)
    axis = np.eye(3)[int(np.flatnonzero(np.abs(n) <= np.abs(n).min() + 1e-9)[0])]
    t1 = axis - axis.dot(n) * n
    t1 /= np.linalg.norm(t1)
    return n, t1, np.cross(n, t1)


def direction_name(vector):
    """'x', '-z' for a coordinate axis, else '(0.707, 0, 0.707)'."""
    for k, name in enumerate("xyz"):
        if abs(abs(vector[k]) - 1) < 1e-9:
            return name if vector[k] > 0 else "\N{MINUS SIGN}" + name
    return "(" + ", ".join(f"{value:.3g}".replace("-", "\N{MINUS SIGN}") for value in vector + 0.0) + ")"


class ContactFace:
    """Gamma3 of a 3D run (the boundary triangles of label 1 of its mesh) seen from outside,
    in its own plane coordinates: the mean normal n of the contact nodes (their normals
    weighted by their weights, from contact.txt) points towards the viewer, and a point p
    has the coordinates (p.t1, p.t2) of the frame of n (surface_frame: on a face y = 0, n =
    (0, -1, 0), t1 = x and t2 = z, the face seen from below). uv: (nodes, 2) those of the
    contact nodes, in the order of contact.txt; triangles: (faces, 3) rows of contact.txt;
    mesh_rows: the row of mesh.xyz of each node; labels: the axis labels; view: how the face
    is seen; folded: whether a curved Gamma3 overlaps itself in this view (a triangle seen
    from inside). source: the mesh's file, for messages."""

    def __init__(self, mesh, contact, source="the mesh"):
        c = contact
        xyz = np.column_stack(c.finite("x", "y", "z"))
        faces = mesh.faces[mesh.face_labels == labels()["GammaContact"]]
        if not len(faces):
            raise InputError(f"{source} has no contact surface (physical surface 1)")
        on = np.unique(faces)
        rows, distances = nearest_rows(mesh.xyz[on], xyz)
        size = max(float(np.ptp(mesh.xyz, axis=0).max()), 1e-300)
        far = np.flatnonzero(distances > 1e-6 * size)
        if far.size:
            raise InputError(f"{c.path}:{c.lines[far[0]]}: the node ({', '.join(f'{v:g}' for v in xyz[far[0]])}) is "
                             "not a node of the mesh's contact surface (physical surface 1)")
        if len(set(rows)) != len(rows) or len(rows) != len(on):
            raise InputError(f"{c.path}: {len(xyz)} rows for the {len(on)} nodes of the mesh's contact surface, "
                             "not one a node")
        self.mesh_rows = on[rows]                                               # of each node, in mesh.xyz
        local = np.full(len(mesh.xyz), -1)
        local[self.mesh_rows] = np.arange(len(rows))
        self.triangles = local[faces]
        self.frames = np.stack([np.column_stack(c.finite(*(f"{axis}_{k}" for k in "xyz")))
                                for axis in ("n", "t1", "t2")], axis=1)          # (nodes, 3 axes, 3)
        weights = c.finite("weight")[0]
        mean = weights @ self.frames[:, 0]
        if np.linalg.norm(mean) <= 1e-9 * max(weights.sum(), 1e-300):          # a closed surface
            mean = self.frames[0, 0]
        self.normal, self.t1, self.t2 = surface_frame(mean)
        self.uv = np.c_[xyz @ self.t1, xyz @ self.t2]
        self.labels = tuple(f"{direction_name(t)} [m]" for t in (self.t1, self.t2))
        self.view = (f"seen from outside (mean normal {direction_name(self.normal)} towards the viewer; "
                     f"across: {direction_name(self.t1)}, up: {direction_name(self.t2)})")
        p = xyz[self.triangles]
        area = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])                   # twice the area, along its normal
        outward = np.sign(np.einsum("ij,ij->i", area, self.frames[self.triangles, 0].sum(axis=1)))
        self.folded = bool(np.any(outward * (area @ self.normal) < -1e-9 * np.abs(area).max()))

    def tangential(self, first, second):
        """The tangential vectors first t1_i + second t2_i of the nodes (their own frames), in
        the face's plane coordinates: (nodes, 2)."""
        vectors = first[:, None] * self.frames[:, 1] + second[:, None] * self.frames[:, 2]
        return np.c_[vectors @ self.t1, vectors @ self.t2]

    def edges(self):
        """The edges of the triangles of Gamma3, once each: (edges, 2) rows of uv."""
        t = self.triangles
        return np.unique(np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1), axis=0)

    def cells(self):
        """Each node's cell, halfway to its neighbours (the median dual cell): from each
        triangle, for each corner, the quadrilateral corner, midpoint of an edge, centroid,
        midpoint of the other edge. (quadrilaterals (3 faces, 4, 2), the node of each)."""
        p = self.uv[self.triangles]
        centroid = p.mean(axis=1)
        quads = [np.stack([p[:, k], 0.5 * (p[:, k] + p[:, (k + 1) % 3]), centroid, 0.5 * (p[:, k] + p[:, (k + 2) % 3])],
                          axis=1) for k in range(3)]
        return np.concatenate(quads), self.triangles.T.ravel()

    def extent(self):
        """Width and height of the face in its plane coordinates (at least 1e-12)."""
        return np.maximum(np.ptp(self.uv, axis=0), 1e-12)


def face_axes(ax, face, margin=0.04):
    """The axes set to show the face: its plane coordinates at equal aspect, a margin of
    `margin` of its size, the axis labels, no grid."""
    low, high = face.uv.min(axis=0), face.uv.max(axis=0)
    pad = margin * (high - low).max()
    ax.set_xlim(low[0] - pad, high[0] + pad)
    ax.set_ylim(low[1] - pad, high[1] + pad)
    ax.set_aspect("equal")
    ax.grid(False)
    ax.set_xlabel(face.labels[0])
    ax.set_ylabel(face.labels[1])


def draw_face_zones(ax, face, zones, nodes_size=2.5):
    """The zone of every node of Gamma3 over the face: each node's cell (ContactFace.cells)
    in its zone's colour, the triangles' edges in white, the nodes as black dots."""
    from matplotlib.collections import LineCollection, PolyCollection
    colors = {zone.code: zone.color for zone in ZONES}
    quads, owners = face.cells()
    filled = [colors[int(z)] for z in np.asarray(zones)[owners]]
    ax.add_collection(PolyCollection(quads, facecolors=filled, edgecolors=filled, linewidths=0.4))
    ax.add_collection(LineCollection(face.uv[face.edges()], colors="w", linewidths=0.5, alpha=0.7))
    ax.plot(*face.uv.T, "o", color="k", markersize=nodes_size, markeredgewidth=0)
    face_axes(ax, face)


def node_zones(path, nodes, xyz=None):
    """contact_nodes_history.txt as (the table, t of its recorded steps, zones (steps,
    nodes)): `nodes` rows (nodes 0 to nodes - 1, in the order of contact.txt) at each step,
    zone codes in 0..4; with xyz (nodes, 3), the positions of a 3D run's nodes, checked to be
    those of contact.txt."""
    h = read_table(path)
    steps = np.unique(h["step"])
    if len(h) != len(steps) * nodes or not np.array_equal(h["node"], np.tile(np.arange(nodes), len(steps))):
        raise InputError(f"{h.path}: not {nodes} rows (nodes 0 to {nodes - 1}) for each of its {len(steps)} steps")
    zones = h.codes("zone", 0, len(ZONES) - 1)
    if xyz is not None:
        moved = np.abs(np.column_stack(h.finite("x", "y", "z")) - np.tile(xyz, (len(steps), 1))).max(axis=1)
        bad = np.flatnonzero(moved > 1e-9 * max(float(np.ptp(xyz, axis=0).max()), 1e-300))
        if bad.size:
            raise InputError(f"{h.path}:{h.lines[bad[0]]}: node {int(h['node'][bad[0]])} is not where contact.txt "
                             "puts it")
    return h, h.finite("t")[0][::nodes], zones.reshape(len(steps), nodes)


def outer_surface(tetrahedra, xyz):
    """The boundary of a body of tetrahedra: its triangles (faces of one tetrahedron only),
    each ordered counterclockwise seen from outside. (triangles, 3) rows of xyz."""
    corners = ((0, 1, 2, 3), (0, 1, 3, 2), (0, 2, 3, 1), (1, 2, 3, 0))
    faces = np.concatenate([tetrahedra[:, list(k[:3])] for k in corners])
    opposite = np.concatenate([tetrahedra[:, k[3]] for k in corners])
    _, first, counts = np.unique(np.sort(faces, axis=1), axis=0, return_index=True, return_counts=True)
    keep = np.sort(first[counts == 1])
    faces, opposite = faces[keep], opposite[keep]
    p = xyz[faces]
    inward = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), xyz[opposite] - p[:, 0]) > 0
    faces[inward] = faces[inward][:, [0, 2, 1]]
    return faces


def feature_edges(triangles, xyz, angle=30.0):
    """The edges of a closed surface (triangles, outward) where it bends by more than
    `angle` degrees (the edges of a box), or that bound it: (edges, 2) rows of xyz."""
    p = xyz[triangles]
    normals = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    owner = np.tile(np.arange(len(triangles)), 3)
    order = np.lexsort(edges.T[::-1])
    edges, owner = edges[order], owner[order]
    same = np.all(edges[1:] == edges[:-1], axis=1)
    kept = [edges[i] for i in np.flatnonzero(same)
            if normals[owner[i]] @ normals[owner[i + 1]] < np.cos(np.radians(angle))]
    single = np.ones(len(edges), dtype=bool)
    single[1:] &= ~same
    single[:-1] &= ~same
    kept += list(edges[single])
    return np.array(kept, dtype=int).reshape(-1, 2)


# ---------------------------------------------------------------- figures
STYLE = {
    "figure.figsize": (11, 4),
    "figure.dpi": 100,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "font.size": 9,
    "lines.linewidth": 1.2,
    "lines.markersize": 3,
}


def pyplot(overrides=None):
    """matplotlib.pyplot on the Agg backend (files only, never a window), with STYLE and
    then the overrides (rcParams) applied."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update(STYLE)
    plt.rcParams.update(overrides or {})
    return plt


# ---------------------------------------------------------------- figures in a run folder
# A run folder's figures/ holds what plots/run_figures.py and plots/animate.py drew there and
# figures.list, which names them. edp/plugins/runtools.cpp reads that list (with the same
# signature line): a later solve into the folder replaces it only if every file of figures/ is
# listed, and removes the listed ones with it. FIGURES_DRAWN are the only names the list may
# hold; edp/plugins/runtools.cpp holds the same list (figuresDrawn): change both together.
FIGURES_DRAWN = ("contact_at_T.png", "histories.png", "deformed.png", "zone_map.png", "compare_contact.png",
                 "animation.gif", "animation.mp4")
FIGURES_LIST = "figures.list"
FIGURES_SIGNATURE = "# figures.list: the figures plots/ of this suite drew here; they go with the run's results"


def figures_listed(folder, out):
    """The names the figures.list of a figures/ folder (descriptor `folder`, named `out` in
    messages) gives, those of FIGURES_DRAWN only, and its bytes: (None, None) when there is
    none. InputError when it is a symbolic link, or is there without the signature line."""
    listed = os.path.join(out, FIGURES_LIST)
    try:
        fd = os.open(FIGURES_LIST, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC, dir_fd=folder)
    except FileNotFoundError:
        return None, None
    except OSError:
        fd = None
    if fd is None or not stat.S_ISREG(os.fstat(fd).st_mode):
        if fd is not None:
            os.close(fd)
        if is_link(FIGURES_LIST, folder):
            raise InputError(f"{shown(listed)} is a symbolic link: the suite does not write through one; remove it")
        data = b""
    else:
        with os.fdopen(fd, "rb") as f:
            data = f.read()
    lines = data.decode("utf-8", "replace").split("\n")
    if not data or lines[0] != FIGURES_SIGNATURE:
        raise InputError(f"{shown(listed)} was not written by this suite (no signature line): "
                         "move it away, the figures cannot be listed")
    return {name for name in lines[1:] if name in FIGURES_DRAWN}, data


class FigureFiles:
    """The figures one tool draws into run folders' figures/ (paths OUT/figures/NAME, NAME
    of FIGURES_DRAWN), written all or nothing and never through a symbolic link. Made before
    anything is drawn, it opens each run folder (open_folder: not a link, nor reached through
    one that a run folder holds) and its figures/ (O_NOFOLLOW), and keeps them open: what it
    then writes goes into those folders even if a path is changed meanwhile. It refuses
    (InputError naming the file) a figures/, figures.list or figure that is a symbolic link,
    and a path that holds anything but a figure figures.list lists: a file of the user's is
    never overwritten. open() and save() write each figure to a new file
    OUT/figures/.STEM.tmp.PID.EXT (O_EXCL, O_NOFOLLOW); commit() then writes each
    figures.list anew (a temporary renamed onto it) and renames the temporaries into place.
    abort() (run_tool calls it on any failure) removes the temporaries, puts back the
    figures.list files it changed, and removes a figures/ it made: the folders are left as
    they were."""

    pending = []            # the FigureFiles not yet committed or aborted (run_tool aborts them)

    def __init__(self, paths):
        self.paths = list(dict.fromkeys(paths))
        self.folders = sorted({os.path.dirname(path) for path in self.paths})
        for path in self.paths:
            if os.path.basename(path) not in FIGURES_DRAWN:
                raise ValueError(f"{path}: not one of the figures the suite draws ({' '.join(FIGURES_DRAWN)})")
        self.parents, self.fds, self.listed, self.before = {}, {}, {}, {}
        self.temporaries, self.made, self.lists = {}, [], {}
        FigureFiles.pending.append(self)
        try:
            for out in self.folders:
                self.parents[out] = open_folder(os.path.dirname(out) or ".")
                self.fds[out] = self.open_folder(out)
                self.listed[out], self.before[out] = (figures_listed(self.fds[out], out) if self.fds[out] is not None
                                                      else (None, None))
            for path in self.paths:
                out, name = os.path.split(path)
                mode = lstat_mode(name, self.fds[out]) if self.fds[out] is not None else None
                if mode is not None and stat.S_ISLNK(mode):
                    raise InputError(f"{shown(path)} is a symbolic link: the suite does not write through one; "
                                     "move it away to draw the figure")
                if mode is not None and (name not in (self.listed[out] or set()) or not stat.S_ISREG(mode)):
                    raise InputError(f"{shown(path)}: not a figure this suite drew ({FIGURES_LIST} does not list it); "
                                     "move it away to draw the figure")
        except BaseException:
            self.abort()
            raise

    def open_folder(self, out):
        """The descriptor of the figures/ folder `out` (in its open parent), None when there is
        none; InputError when it is a symbolic link or not a folder."""
        try:
            return os.open(os.path.basename(out), FOLDER | os.O_NOFOLLOW, dir_fd=self.parents[out])
        except FileNotFoundError:
            return None
        except OSError:
            if is_link(os.path.basename(out), self.parents[out]):
                raise InputError(f"{shown(out)} is a symbolic link: the suite does not write through one; remove it "
                                 "(the figures then go into a folder of the run)") from None
            raise InputError(f"{shown(out)} is not a folder: the figures cannot go there") from None

    def open(self, path):
        """A new binary file (a temporary of its figures/, made if needed) to write the figure
        `path` into; commit() puts it into place."""
        out, name = os.path.split(path)
        if path not in self.paths:
            raise ValueError(f"{path}: not among the figures announced")
        if self.fds[out] is None:
            os.mkdir(os.path.basename(out), dir_fd=self.parents[out])
            self.made.append(out)
            self.fds[out] = self.open_folder(out)
        stem, ext = os.path.splitext(name)
        temporary = f".{stem}.tmp.{os.getpid()}{ext}"
        fd = os.open(temporary, NEW_FILE, 0o666, dir_fd=self.fds[out])
        self.temporaries[path] = temporary
        return os.fdopen(fd, "wb")

    def save(self, fig, path, tight_layout=True):
        """Write the matplotlib figure to a new file for path (open), close it; return path."""
        import matplotlib.pyplot as plt
        if tight_layout:
            fig.tight_layout()
        with self.open(path) as f:
            fig.savefig(f, format=os.path.splitext(path)[1][1:])
        plt.close(fig)
        return path

    def commit(self):
        """Name every figure written in its folder's figures.list, then put them into place."""
        for out in self.folders:
            names = {os.path.basename(path) for path in self.temporaries if os.path.dirname(path) == out}
            if names:
                self.lists[out] = self.before[out]
                text = "\n".join([FIGURES_SIGNATURE] + sorted((self.listed[out] or set()) | names)) + "\n"
                replace_in(self.fds[out], FIGURES_LIST, text.encode())
        for path, temporary in list(self.temporaries.items()):
            folder = self.fds[os.path.dirname(path)]
            os.replace(temporary, os.path.basename(path), src_dir_fd=folder, dst_dir_fd=folder)
            del self.temporaries[path]
        FigureFiles.pending.remove(self)
        self.close()

    def abort(self):
        """Remove what this drawing wrote; leave the folders as they were (as far as the
        system lets it: a step that fails does not keep the others from being done)."""
        if self in FigureFiles.pending:
            FigureFiles.pending.remove(self)
        steps = [functools.partial(os.remove, temporary, dir_fd=self.fds[os.path.dirname(path)])
                 for path, temporary in self.temporaries.items()]
        for out, before in self.lists.items():
            steps.append(functools.partial(replace_in, self.fds[out], FIGURES_LIST, before))
        steps += [functools.partial(os.rmdir, os.path.basename(out), dir_fd=self.parents[out]) for out in reversed(self.made)]
        for step in steps:
            try:
                step()
            except OSError:         # gone already, or a figures/ that is not empty
                pass
        self.close()

    def close(self):
        for fd in list(self.fds.values()) + list(self.parents.values()):
            if fd is not None:
                os.close(fd)
        self.fds, self.parents = dict.fromkeys(self.fds), {}


def replace_in(folder, name, data):
    """Make `name` in the folder of descriptor `folder` hold the bytes data (remove it when
    data is None), through a new temporary renamed onto it: a link there is replaced, never
    written through."""
    if data is None:
        os.remove(name, dir_fd=folder)
        return
    temporary = f".{name}.tmp.{os.getpid()}"
    with os.fdopen(os.open(temporary, NEW_FILE, 0o666, dir_fd=folder), "wb") as f:
        try:
            f.write(data)
        except BaseException:
            os.remove(temporary, dir_fd=folder)
            raise
    os.replace(temporary, name, src_dir_fd=folder, dst_dir_fd=folder)


@contextlib.contextmanager
def new_file(path):
    """A binary file to write `path` with, never through a symbolic link: its folder opened by
    open_folder (made if needed), a new temporary there (O_EXCL, O_NOFOLLOW), renamed onto
    path when the block ends without an error, removed otherwise. InputError when path is a
    symbolic link."""
    folder, name = os.path.split(path)
    fd, temporary = open_folder(folder or ".", make=True), None
    try:
        mode = lstat_mode(name, fd)
        if mode is not None and stat.S_ISLNK(mode):
            raise InputError(f"{shown(path)} is a symbolic link: the suite does not write through one; remove it")
        file = os.open(f".{name}.tmp.{os.getpid()}", NEW_FILE, 0o666, dir_fd=fd)
        temporary = f".{name}.tmp.{os.getpid()}"
        with os.fdopen(file, "wb") as f:
            yield f
        os.replace(temporary, name, src_dir_fd=fd, dst_dir_fd=fd)
        temporary = None
    finally:
        if temporary is not None:
            try:
                os.remove(temporary, dir_fd=fd)
            except OSError:
                pass
        os.close(fd)


def save(fig, out, name, tight_layout=True):
    """Write the figure to OUT/NAME.png (OUT made if needed; new_file: never through a
    symbolic link), close it, return the path."""
    import matplotlib.pyplot as plt
    path = os.path.join(out, name + ".png")
    if tight_layout:
        fig.tight_layout()
    with new_file(path) as f:
        fig.savefig(f, format="png")
    plt.close(fig)
    return path
