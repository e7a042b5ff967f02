"""runfiles.py: the one reader of the files of this suite (docs/design.md, "Output files",
"Scenes"), for every Python tool: plots/, tests/ and the studies. Tables (by column name),
summary.txt, run folders, the zones of a run (zone_columns: its own headers), MSH 2.2
meshes, VTK files, the option table edp/options.txt, scenes and a run's loads (scene data;
the law's values per node are the outputs' columns g, damped_response, force_scale,
friction_bound, the statuses and zone), the solver's failure message, the figure names of
edp/figures.txt, the benchmark's measurements (read_process_time, read_pairs), the
comparison of two runs; and the tools' conventions: run_tool prints an InputError as one
line 'TOOL: error: MESSAGE', names that are not UTF-8 or hold a control character are
refused, files are written never through a symbolic link. A script finds it by itself:
sys.path.insert(0, <repository>/edp).
"""
import collections
import contextlib
import functools
import os
import re
import signal
import stat
import sys
import unicodedata

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))   # the repository
EDP = os.path.join(ROOT, "edp")


# ---------------------------------------------------------------- the tools' conventions
class InputError(Exception):
    """A missing or unreadable input; the message names the file and the problem."""


def run_tool(tool, main, code=1, cleanup=None):
    """Run main() and return what it returns. An InputError, an OSError of a file, or an
    input main() did not expect (IndexError, KeyError, ValueError, ZeroDivisionError) ends the
    tool with one line 'TOOL: error: MESSAGE' on stderr and exit status `code`. SIGTERM and
    SIGHUP end it as SystemExit(128 + n), so that `cleanup` (called whatever ends main(),
    e.g. removing figures not yet put into place) runs for them too."""
    def stop(number, _frame):
        raise SystemExit(128 + number)
    for number in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(number, stop)
    try:
        try:
            return main()
        finally:
            if cleanup:
                cleanup()
    except InputError as error:
        message = str(error)
    except OSError as error:
        message = f"{error.filename}: {error.strerror}" if error.filename else str(error)
    except (IndexError, KeyError, ValueError, ZeroDivisionError) as error:
        message = f"cannot use the input ({type(error).__name__}: {error})"
    print(f"{tool}: error: {message}", file=sys.stderr)
    sys.exit(code)


def refuse(tool, message):
    """End the tool at once: 'TOOL: error: MESSAGE' on stderr, exit status 2 (a bad argument)."""
    print(f"{tool}: error: {message}", file=sys.stderr)
    sys.exit(2)


def shown(value, limit=80):
    """A name as a message shows it: bytes that are not UTF-8 and control or format characters
    as backslash escapes (\\xff, \\n, \\u2028), so that the message stays one printable line,
    cut to its start and end around '...' when longer than `limit` characters."""
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


def check_arguments(tool):
    """Refuse (exit 2, before anything is read or written) a command-line argument that is
    not valid UTF-8 or holds a control character or a line separator: the tools print the
    names they read and write, one a line."""
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
    """Refuse (exit 2) an existing output folder that open_folder refuses (a symbolic link,
    or one reached through a link of a run folder)."""
    for folder in folders:
        if folder is not None and os.path.lexists(folder):
            try:
                os.close(open_folder(folder))
            except InputError as error:
                refuse(tool, str(error))


# ---------------------------------------------------------------- writing, never through a link
FOLDER = os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC
NEW_FILE = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC     # new, never a link's target


def lstat_mode(name, folder):
    """The st_mode of `name` (a link itself) in the folder of descriptor `folder`; None if absent."""
    try:
        return os.stat(name, dir_fd=folder, follow_symlinks=False).st_mode
    except FileNotFoundError:
        return None


def is_link(name, folder):
    mode = lstat_mode(name, folder)
    return mode is not None and stat.S_ISLNK(mode)


def open_folder(path, make=False):
    """A descriptor of the folder `path`, opened a component at a time (missing ones made when
    make), so that a path changed meanwhile cannot send what is written elsewhere. A symbolic
    link on the way is followed only where a user's folders may have one: never as the folder
    itself, nor inside a run folder (one holding run.complete); InputError for those."""
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


@contextlib.contextmanager
def new_file(path):
    """A binary file to write `path` with: its folder opened by open_folder (made if needed),
    a new temporary there (O_EXCL, O_NOFOLLOW) renamed onto path when the block ends without
    an error, removed otherwise. InputError when path is a symbolic link."""
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
            with contextlib.suppress(OSError):
                os.remove(temporary, dir_fd=fd)
        os.close(fd)


def write_table(path, comments, columns, rows):
    """A table in the format of the solver's outputs: a '# ' line per comment, the '#' line
    naming the columns, then the rows; floats with repr (full precision, the same text on
    every run), anything else with str."""
    def text(value):
        if isinstance(value, (float, np.floating)):
            return repr(float(value))
        return str(int(value)) if isinstance(value, np.integer) else str(value)
    lines = [f"# {line}" for line in comments] + ["# " + " ".join(columns)]
    lines += [" ".join(text(value) for value in row) for row in rows]
    with new_file(path) as f:
        f.write(("\n".join(lines) + "\n").encode())


# ---------------------------------------------------------------- text files, tables, summary.txt
def read_lines(path, newline=None):
    """The lines of a text file, split at line feeds only (not at the form feeds, U+2028, ...
    that str.splitlines() also takes for line ends); newline="" keeps a carriage return as a
    character of its line (open's newline)."""
    try:
        with open(path, newline=newline) as f:
            text = f.read()
    except FileNotFoundError:
        raise InputError(f"missing {path}") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a text file") from None
    except OSError as error:
        raise InputError(f"cannot read {path}: {error.strerror}") from None
    return text[:-1].split("\n") if text.endswith("\n") else (text.split("\n") if text else [])


class Values(dict):
    """'name value' pairs of one file (source); a missing name, or a value that is not the
    number asked for, raises InputError naming the file."""

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
    """One table file: params (Values of its '# name value' lines), columns (the names on its
    last '#' line), data (a 2-D array, a row per line), lines (the file's line of each row);
    table[name] is a column, len(table) the number of rows."""

    def __init__(self, path, params, columns, data, lines=None):
        self.path, self.params, self.columns, self.data = path, params, columns, data
        self.lines = np.arange(1, len(data) + 1) if lines is None else np.asarray(lines)

    def __getitem__(self, name):
        if name not in self.columns:
            raise InputError(f"{self.path}: no column {name} (columns: {' '.join(self.columns)})")
        return self.data[:, self.columns.index(name)]

    def __contains__(self, name):
        return name in self.columns

    def __len__(self):
        return self.data.shape[0]

    def finite(self, *names):
        """The columns, each value checked to be finite (InputError naming file, line, column)."""
        for name in names:
            bad = np.flatnonzero(~np.isfinite(self[name]))
            if bad.size:
                raise InputError(f"{self.path}:{self.lines[bad[0]]}: {name} = {float(self[name][bad[0]])!r} is not a finite "
                                 f"number ({bad.size} row{'s' if bad.size > 1 else ''})")
        return [self[name] for name in names]

    def codes(self, name, low, high):
        """The column as whole numbers, each checked to lie in low..high (else InputError)."""
        values = self[name]
        bad = np.flatnonzero(~np.isin(values, np.arange(low, high + 1)))
        if bad.size:
            raise InputError(f"{self.path}:{self.lines[bad[0]]}: {name} = {float(values[bad[0]]):g}, not one of "
                             f"{low}..{high}")
        return values.astype(int)

    def rows(self):
        """One Values (column name -> value) per row."""
        return [Values(self.path, zip(self.columns, row)) for row in self.data]


def read_table(path, dtype=float, empty=False):
    """A table of edp/solve.edp or of the suite's tools: rows of dtype (float, or str for tables
    with words), at least one unless empty. InputError names the first bad line."""
    lines = read_lines(path)
    header = []
    for line in lines:
        if not line.startswith("#"):
            break
        header.append(line[1:].split())
    if not header or not header[-1]:
        raise InputError(f"{path}: no '#' line naming the columns")
    columns = header[-1]
    repeated = sorted({name for name in columns if columns.count(name) > 1})
    if repeated:
        raise InputError(f"{path}: the column {shown(repeated[0])} is named twice in the '#' line naming the columns")
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
        for number, line in rows:
            words = line.split("#", 1)[0].split()
            try:
                [dtype(word) for word in words]
            except ValueError:
                raise InputError(f"{path}:{number}: unreadable numbers in '{shown(line)}'") from None
            if len(words) != len(columns):
                raise InputError(f"{path}:{number}: {len(words)} values for the {len(columns)} columns "
                                 f"{' '.join(columns)}")
        raise InputError(f"{path}: unreadable rows")
    return Table(path, params, columns, data, [number for number, _ in rows])


def read_summary(path):
    """The 'key value' lines of summary.txt (a value may hold spaces); path: the file or the
    run folder."""
    if os.path.isdir(path):
        path = os.path.join(path, "summary.txt")
    summary = Values(path)
    for line in read_lines(path):
        if line.startswith("#") or not line.strip():
            continue
        words = line.split(None, 1)
        if words[0] in summary:
            raise InputError(f"{shown(path)}: the key {shown(words[0])} is given twice")
        summary[words[0]] = words[1].strip() if len(words) > 1 else ""
    return summary


def run_folder(folder):
    """The folder, if a run finished there (it holds summary.txt and run.complete); else
    InputError."""
    if not os.path.isdir(folder):
        raise InputError(f"{shown(folder)}: no such folder")
    missing = [name for name in ("summary.txt", "run.complete") if not os.path.isfile(os.path.join(folder, name))]
    if missing:
        raise InputError(f"{shown(folder)} is not the folder of a finished run (no {' and no '.join(missing)})")
    return folder


def completed_files(folder, marker="run.complete"):
    """The names a folder's marker file lists, one a line after its signature line: run.complete
    (written last by edp/solve.edp: the run's files, those of vtk/ as vtk/NAME) or
    sweep.complete (plots/sweep.py: the entries of a sweep folder). None when the folder has
    no such file written by the suite (a regular file whose first line starts '# MARKER:');
    names with '..' or an empty part are left out (no list can name a file elsewhere)."""
    path = os.path.join(folder, marker)
    if not os.path.isfile(path) or os.path.islink(path):
        return None
    try:
        lines = read_lines(path)
    except InputError:
        return None
    if not lines or not lines[0].startswith(f"# {marker}:"):
        return None
    return [line for line in lines[1:] if line and all(part not in ("", ".", "..") for part in line.split("/"))]


def run_dimension(folder):
    """2 or 3: the 'dimension' line of the run's summary.txt."""
    summary = read_summary(folder)
    if summary["dimension"] not in ("2", "3"):
        raise InputError(f"{summary.source}: dimension = {summary['dimension']!r}, not 2 or 3")
    return int(summary["dimension"])


def zone_names(names):
    """The zones among `names` (a table's columns, the keys of summary.txt): those named
    zone_*, in their order."""
    return tuple(name for name in names if name.startswith("zone_"))


def zone_columns(folder):
    """The zones of a run, in the order of their codes (the column zone of contact.txt and
    contact_nodes_history.txt, contact_zone of the VTK files: 0, 1, ...; docs/design.md,
    "Statuses and zones"): the columns zone_* of its contact_history.txt or, without that
    file (the studies keep the histories of some runs only), the keys zone_* of its
    summary.txt. The solver names them; no Python tool lists them again, so that a law
    with other zones (edp/plugins/contactlaw.hpp) is read and drawn as it is."""
    history = os.path.join(folder, "contact_history.txt")
    if os.path.isfile(history):
        source, names = history, zone_names(read_table(history, empty=True).columns)
    else:
        summary = read_summary(folder)
        source, names = summary.source, zone_names(summary)
    if not names:
        raise InputError(f"{source}: no zone_* {'column' if source == history else 'key'} (the zones of the run)")
    return names


def node_history(folder, nodes, xyz=None):
    """The run's contact_nodes_history.txt as (the table, t of its recorded steps, zones
    (steps, nodes)): `nodes` rows (nodes 0 to nodes - 1, in the order of contact.txt) at each
    recorded step, the column zone a code of the run's zones (zone_columns); with xyz
    (nodes, 3), a 3D run's nodes, checked to be where contact.txt puts them."""
    h = read_table(os.path.join(folder, "contact_nodes_history.txt"))
    steps = np.unique(h["step"])
    if len(h) != len(steps) * nodes or not np.array_equal(h["node"], np.tile(np.arange(nodes), len(steps))):
        raise InputError(f"{h.path}: not {nodes} rows (nodes 0 to {nodes - 1}) for each of its {len(steps)} steps")
    zones = h.codes("zone", 0, len(zone_columns(folder)) - 1)
    if xyz is not None:
        moved = np.abs(np.column_stack(h.finite("x", "y", "z")) - np.tile(xyz, (len(steps), 1))).max(axis=1)
        bad = np.flatnonzero(moved > 1e-9 * max(float(np.ptp(xyz, axis=0).max()), 1e-300))
        if bad.size:
            raise InputError(f"{h.path}:{h.lines[bad[0]]}: node {int(h['node'][bad[0]])} is not where contact.txt puts it")
    return h, h.finite("t")[0][::nodes], zones.reshape(len(steps), nodes)


# ---------------------------------------------------------------- meshes
Mesh = collections.namedtuple("Mesh", "xy ids triangles lines line_labels")
Mesh.__doc__ = """A 2D mesh: xy (nodes, 2) in the file's node order; ids: gmsh node number ->
row; triangles (n, 3) and boundary lines (n, 2) as rows of xy; line_labels: each line's
physical label (its first tag, labels())."""
Mesh3 = collections.namedtuple("Mesh3", "xyz ids tetrahedra faces face_labels")
Mesh3.__doc__ = """A 3D mesh: xyz (nodes, 3); ids; tetrahedra (n, 4) and boundary triangles
faces (n, 3) as rows of xyz; face_labels: each face's physical label (1 the contact surface)."""
ELEMENT_NODES = {15: 1, 1: 2, 2: 3, 4: 4}          # gmsh types: point, line, triangle, tetrahedron


def read_msh22(path):
    return read_msh(path, 2)


def read_msh3(path):
    return read_msh(path, 3)


def read_msh(path, dimension):
    """A gmsh MSH 2.2 mesh (Mesh in 2D, Mesh3 in 3D). Refused (InputError): another format, a
    node number given twice, an element type other than points, lines, triangles and
    tetrahedra, a boundary element without its physical label, no cells."""
    lines = read_lines(path)
    sections = {line.strip(): i for i, line in enumerate(lines) if line.startswith("$")}
    for name in ("$MeshFormat", "$Nodes", "$Elements"):
        if name not in sections:
            raise InputError(f"{path}: not a gmsh MSH 2.2 file (no {name} section)")
    cells, boundary, labels_ = [], [], []
    try:
        version, filetype = lines[sections["$MeshFormat"] + 1].split()[:2]
        if not version.startswith("2.") or filetype != "0":
            raise InputError(f"{path}: not an ASCII gmsh MSH 2.x file (format {version} {filetype})")
        start = sections["$Nodes"]
        ids, xy = {}, np.empty((int(lines[start + 1]), dimension))
        for i, line in enumerate(lines[start + 2:start + 2 + len(xy)]):
            words = line.split()
            ids[int(words[0])] = i
            xy[i] = [float(words[k]) for k in range(1, 1 + dimension)]
        if len(ids) != len(xy):
            raise InputError(f"{path}: a node number is given twice")
        start = sections["$Elements"]
        for line in lines[start + 2:start + 2 + int(lines[start + 1])]:
            words = [int(w) for w in line.split()]
            kind, tags = words[1], words[2]
            if kind not in ELEMENT_NODES:
                raise InputError(f"{path}: element type {kind} (points, lines, triangles and tetrahedra only)")
            nodes = [ids[n] for n in words[3 + tags:3 + tags + ELEMENT_NODES[kind]]]
            if kind == 4 and dimension == 2:
                raise InputError(f"{path}: tetrahedra in the mesh of a 2D run")
            if kind == (2, 4)[dimension - 2]:                               # a cell: triangle, tetrahedron
                cells.append(nodes)
            elif kind == (1, 2)[dimension - 2]:                             # a boundary line, triangle
                if tags < 1:
                    raise InputError(f"{path}: a boundary element without a physical label")
                boundary.append(nodes)
                labels_.append(words[3])
    except (ValueError, IndexError, KeyError) as error:
        raise InputError(f"{path}: not a readable gmsh MSH 2.2 file ({type(error).__name__}: {error})") from None
    if not cells:
        raise InputError(f"{path}: no {'tetrahedra (the mesh of a 3D run)' if dimension == 3 else 'triangles'}")
    kind = Mesh3 if dimension == 3 else Mesh
    return kind(xy, ids, np.array(cells, dtype=int), np.array(boundary, dtype=int).reshape(-1, dimension),
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


# ---------------------------------------------------------------- VTK files (-vtk N)
def read_xml(path):
    import xml.etree.ElementTree as ElementTree   # (only the VTK files need it)
    try:
        return ElementTree.parse(path).getroot()
    except ElementTree.ParseError as error:
        raise InputError(f"{path}: not an XML file ({error})") from None
    except FileNotFoundError:
        raise InputError(f"missing {path}") from None


def vtk_array(path, element, where):
    """The numbers of a DataArray element (named `where` in messages): (n,) or (n, k)."""
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
    """An ASCII VTK XML UnstructuredGrid of triangles as -vtk writes it: Vtu(xy (points, 2),
    triangles (cells, 3), point_data {name: (points,) or (points, k)}, path)."""
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
    """The time series of a ParaView collection: [(t, path of its .vtu)], in the file's order."""
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
Option = collections.namedtuple("Option", "name type range default meaning")   # default None: '-'
Rule = collections.namedtuple("Rule", "option value name default")             # 'when OPTION=VALUE NAME DEFAULT'


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
            raise InputError(f"{path}:{number}: cannot read '{shown(line)}'")
    return tuple(options), tuple(rules)


def option_table():
    """The options of edp/solve.edp (edp/options.txt): ({name: Option} in the file's order,
    [Rule]); a Rule sets the default of Rule.name when Rule.option has Rule.value."""
    options, rules = _option_table()
    return {option.name: option for option in options}, list(rules)


def scene_path(scene):
    """The file of a scene: a name means edp/scenes/NAME.scene, a path (with a '/' or
    '.scene') the file itself, as for edp/solve.edp -scene."""
    if "/" in scene or ".scene" in scene:
        return scene
    return os.path.join(EDP, "scenes", scene + ".scene")


Scene = collections.namedtuple("Scene", "path options data")
Scene.__doc__ = """A scene file: options, the defaults it sets (a line 'NAME VALUE' whose NAME is
an option but scene or out); data, its other lines: key -> [the words after the key], a list
a line (dirichlet, traction, damping, load_history, ...)."""


def read_scene(scene):
    """The scene of a name or a file (scene_path)."""
    path = scene_path(scene)
    options = {name for name in option_table()[0] if name not in ("scene", "out")}
    defaults, data = {}, {}
    for line in read_lines(path):
        words = line.split("#", 1)[0].split()
        if len(words) == 2 and words[0] in options:
            defaults[words[0]] = words[1]
        elif words:
            data.setdefault(words[0], []).append(words[1:])
    return Scene(path, defaults, data)


def effective_options(given, scene=None):
    """The options a run used, as Values: the defaults of edp/options.txt, then the scene's
    (the scene argument, else given["scene"], else the table's), then the given ones (name ->
    value, without the '-'), then the 'when' rules for the options not given. An option with
    no value anywhere is left out: -cnu unless given (its default is the scene's damping C,
    which only the kernel's family table knows; a finished run echoes it in its headers)."""
    options, rules = option_table()
    unknown = [name for name in given if name not in options]
    if unknown:
        raise InputError(f"unknown option -{unknown[0]} (options: {' '.join(options)})")
    values = {name: option.default for name, option in options.items() if option.default is not None}
    read = read_scene(scene or given.get("scene") or values["scene"])
    values.update(read.options)
    values.update(given)
    for rule in rules:
        if rule.name not in given and values.get(rule.option) == rule.value:
            values[rule.name] = rule.default
    return Values(f"the options of a run (scene {read.path})", ((name, values[name]) for name in options if name in values))


class SceneLoads:
    """The loads of a run's scene.scene (the values it used): the load factor h(t) of f2 =
    load h(t) (traction) (load_history: piecewise linear through its points, constant after
    the last; without it h(t) = t), and the body force f0 and initial velocity v_0 as 3
    components (0 where the scene gives none)."""

    def __init__(self, folder):
        self.path = os.path.join(folder, "scene.scene")
        data = read_scene(self.path).data
        self.history = self.numbers(data, "load_history")
        self.body_force, self.initial_velocity = ((self.numbers(data, key) + [0.0] * 3)[:3]
                                                  for key in ("body_force", "initial_velocity"))

    def numbers(self, data, key):
        try:
            return [float(word) for word in data[key][0]] if key in data else []
        except ValueError:
            raise InputError(f"{self.path}: {key} needs numbers") from None

    def h(self, t):
        if not self.history:
            return np.asarray(t, dtype=float)
        return np.interp(t, self.history[0::2], self.history[1::2])


# ---------------------------------------------------------------- the solver's failure message
SolverFailure = collections.namedtuple("SolverFailure", "step t iterations mode residual tol")
FAILURE_MESSAGE = re.compile(r"step (\d+) \(t = ([^)]*)\): the contact solver did not converge after (\d+) "
                             r"iterations \(([^)]*)\), residual (\S+) > tol ([^\s;]+)")


def solver_failure(message):
    """The message of a step that failed (exit 4 or 5; docs/design.md, "Exit codes and
    failure messages"): 'step N (t = T): the contact solver did not converge after I
    iterations (MODE), residual R > tol TOL' as SolverFailure; None for another message."""
    match = FAILURE_MESSAGE.search(message or "")
    if not match:
        return None
    step, t, iterations, mode, residual, tol = match.groups()
    try:
        return SolverFailure(int(step), float(t), int(iterations), mode, float(residual), float(tol))
    except ValueError:
        return None


# ---------------------------------------------------------------- the figures of a run folder
@functools.lru_cache(maxsize=None)
def figure_names():
    """The figures the tools of plots/ may draw into a run folder's figures/: edp/figures.txt,
    the one list (the plugin runtools reads it too, with the same rules: runFigureNames of
    edp/plugins/runtools/runfolder.cpp): one name a line, '#' starts a comment line, empty
    lines are skipped; a name is [A-Za-z0-9_][A-Za-z0-9_.-]*, not figures.list; at least one."""
    path = os.path.join(EDP, "figures.txt")
    names = []
    for number, line in enumerate(read_lines(path, newline=""), 1):
        if not line or line.startswith("#"):
            continue
        if not re.fullmatch(r"[A-Za-z0-9_][A-Za-z0-9_.-]*", line, re.ASCII) or line == "figures.list":
            raise InputError(f"{path}:{number}: '{shown(line)}' is not the file name of a figure (one name a line, of "
                             "letters, digits, '_', '.' and '-', not starting with '.' or '-', not figures.list; '#' "
                             "starts a comment line)")
        names.append(line)
    if not names:
        raise InputError(f"{path} names no figure")
    return tuple(names)


# ---------------------------------------------------------------- the benchmark's measurements
def read_process_time(path):
    """What /usr/bin/time -f "%e %M" -o PATH measured of a process (plots/bench.sh): (its wall
    seconds, its peak memory in KiB), the two numbers of the file's last line (GNU time
    writes 'Command exited with non-zero status N' before them for a process that failed);
    (nan, nan) when that line is not two numbers (time was stopped before it wrote them)."""
    lines = [line for line in read_lines(path) if line.strip()]
    words = lines[-1].split() if lines else []
    try:
        wall, peak = (float(word) for word in words) if len(words) == 2 else (np.nan, np.nan)
    except ValueError:
        wall, peak = np.nan, np.nan
    return wall, peak


def read_pairs(path):
    """The 'name value' pairs of a file's words, as Values (edp/compare.edp prints one line
    'error_L2 E norm_L2 N error_gamma3 G'); empty for an empty file (a comparison that was
    refused: its reason is in its .log)."""
    words = " ".join(read_lines(path)).split()
    if len(words) % 2:
        raise InputError(f"{path}: {len(words)} words, not 'name value' pairs")
    return Values(path, zip(words[0::2], words[1::2]))


# ---------------------------------------------------------------- comparing two runs
def compare_runs(folder, other, rtol):
    """The differences between two runs of the same discrete problem (another solver or
    method) beyond rtol, as messages (none: they agree). Each family of columns (contact
    velocities, contact stresses, u, v, energy terms, total forces) is compared at its scale,
    the largest |value| of its columns in either run, at least the law's scale of the first
    run (its largest g for the velocities, p(g) (force_scale) for the stresses, times the
    contact area for the forces): a column of round-off in both (lambda_nu before any node
    reaches the bound) is compared as such. Zone counts (the columns zone_* of the first run),
    x_B and x_C must be equal. The histories are compared where both runs have them, on the
    steps both made (a run continued with -restart against the whole run: the later steps)."""
    law = read_table(os.path.join(folder, "contact.txt"))
    g, stress = float(law["g"].max()), float(law["force_scale"].max())
    extra = (lambda *names: names) if run_dimension(folder) == 3 else (lambda *names: ())
    failures = []

    def compare(name, families, exact=(), floors=()):
        a, b = read_table(os.path.join(folder, name)), read_table(os.path.join(other, name))
        if "step" in a and "step" in b and len(a) != len(b):     # a run continued (-restart) against the whole run:
            common = np.intersect1d(a["step"], b["step"])          # the steps both made
            if len(common) != min(len(a), len(b)):
                failures.append(f"{name}: the steps of one run are not a part of the other's vs {other}")
                return
            a, b = (Table(t.path, t.params, t.columns, t.data[np.isin(t["step"], common)]) for t in (a, b))
        if a.data.shape != b.data.shape:
            failures.append(f"{name}: shapes differ {a.data.shape} {b.data.shape}")
            return
        for family, floor in zip(families, list(floors) + [0.0] * len(families)):
            scale = max([float(max(np.abs(a[col]).max(), np.abs(b[col]).max())) for col in family] + [floor, 1e-300])
            for col in family:
                err = np.abs(a[col] - b[col]).max() / scale
                if not err <= rtol:
                    failures.append(f"{name} {col}: difference {err:.3e} of the scale of {'/'.join(family)} > {rtol:g} "
                                    f"vs {other}")
        for col in exact + zone_names(a.columns):          # (the zone counts: contact_history.txt)
            differ = ~((a[col] == b[col]) | (np.isnan(a[col]) & np.isnan(b[col])))
            if differ.any():
                failures.append(f"{name} {col}: differs at {int(differ.sum())} steps vs {other}")
    compare("contact.txt", (("v_nu", "v_tau", "g") + extra("v_tau2"),
                            ("p_nu", "lambda_nu", "lambda_tau", "damped_response", "friction_bound", "force_scale")
                            + extra("lambda_tau2")), floors=(g, stress))
    compare("fields.txt", (("u_x", "u_y") + extra("u_z"), ("v_x", "v_y") + extra("v_z")))
    for name, families, exact, floors in (
            ("history.txt", (("kinetic", "elastic", "numerical_dissipation", "viscous_dissipation", "contact_dissipation",
                              "external_work", "kinetic_jump", "elastic_jump"),), (), ()),
            ("contact_history.txt", (("normal_force", "tangential_force") + extra("tangential_force2"),),
             ("x_B", "x_C"), (stress * float(np.abs(law["weight"]).sum()),))):
        if os.path.isfile(os.path.join(folder, name)) and os.path.isfile(os.path.join(other, name)):
            compare(name, families, exact, floors)      # (the studies keep the histories of some runs only)
    return failures
