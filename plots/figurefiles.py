"""figurefiles.py: the figures a tool draws into run folders' figures/, written all or
nothing and never through a symbolic link, and listed in figures/figures.list
(docs/figures.md, "The figures/ folder"). A later solve into the run folder replaces it only
if figures.list names every file of figures/, and removes those with it; the names it may
hold are those of edp/figures.txt (runfiles.figure_names). Imported by plots/run_figures.py
and plots/animate.py, which give abort_pending to runfiles.run_tool as its cleanup.
"""
import functools
import os
import stat

from runfiles import FOLDER, NEW_FILE, InputError, figure_names, is_link, lstat_mode, open_folder, shown

FIGURES_LIST = "figures.list"
FIGURES_SIGNATURE = "# figures.list: the figures plots/ of this suite drew here; they go with the run's results"


def figures_listed(folder, out):
    """The names the figures.list of a figures/ folder (descriptor `folder`, named `out` in
    messages) gives, those of figure_names() only, and its bytes: (None, None) when there is
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
    return {name for name in lines[1:] if name in figure_names()}, data


class FigureFiles:
    """The figures one tool draws into run folders' figures/ (paths OUT/figures/NAME, NAME
    of figure_names()), written all or nothing and never through a symbolic link. Made before
    anything is drawn, it opens each run folder (open_folder: not a link, nor reached through
    one that a run folder holds) and its figures/ (O_NOFOLLOW), and keeps them open: what it
    then writes goes into those folders even if a path is changed meanwhile. It refuses
    (InputError naming the file) a figures/, figures.list or figure that is a symbolic link,
    and a path that holds anything but a figure figures.list lists: a file of the user's is
    never overwritten. open() and save() write each figure to a new file
    OUT/figures/.STEM.tmp.PID.EXT (O_EXCL, O_NOFOLLOW); commit() then writes each
    figures.list anew (a temporary renamed onto it) and renames the temporaries into place.
    abort() (abort_pending, on any failure) removes the temporaries, puts back the
    figures.list files it changed, and removes a figures/ it made: the folders are left as
    they were."""

    pending = []            # the FigureFiles not yet committed or aborted (abort_pending aborts them)

    def __init__(self, paths):
        self.paths = list(dict.fromkeys(paths))
        self.folders = sorted({os.path.dirname(path) for path in self.paths})
        for path in self.paths:
            if os.path.basename(path) not in figure_names():
                raise ValueError(f"{path}: not one of the figures the suite draws ({' '.join(figure_names())})")
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


def abort_pending():
    """Abort every drawing not yet committed (runfiles.run_tool's cleanup: whatever ended the
    tool, the folders are left as they were)."""
    for pending in list(FigureFiles.pending):
        pending.abort()
