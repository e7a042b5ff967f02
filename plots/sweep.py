#!/usr/bin/python3
"""A parameter study: one option of edp/solve.edp over a list of values (README.md, "Sweeps").

  ./run.sh sweep -NAME V1,V2,... [solve options] -out DIR [-plot Q1,Q2,...] [-jobs N]

The swept option comes first: any option of edp/options.txt that takes a value (mu, dt,
load, cnu, eps, nx, solver, scene, ...), but -out. The values are separated by commas (a
value holds no comma, space or '#'). The other options are given to every run as they are.
Runs ./run.sh solve once per value, N at a time (-jobs; default: the cores this process may
use), each into its own run folder DIR/NAME-VALUE (for a value of other characters than
letters, digits, '.', '+' and '-', longer than 100 or ending in '.log':
DIR/NAME_K_VALUE, K its place in the list and its other characters written '_'). Then:

  DIR/sweep.txt       '#' lines (the command line, 'swept NAME', the columns), then a row per
                      value in the order given: value run status (ok or failed) exit_code, the
                      run at T: normal_force tangential_force (the last line of its
                      contact_history.txt), zone_* (the zone keys of its summary.txt, by name),
                      x_B x_C (contact_history.txt), iterations_total iterations_max
                      (summary.txt), and wall_time (seconds, measured here around the solve
                      process, for a failed case too); nan where a failed case has no value
  DIR/sweep.png       the -plot quantities (columns of sweep.txt; default normal_force,x_C)
                      against the value, the failed cases marked
  DIR/NAME-VALUE.log  what the solve of a failed case printed (its message: 'error: ...')
  DIR/sweep.complete  written last: the entries of DIR that the sweep wrote

Values are checked by solve itself: a value it refuses (out of range, not a number, a -dt
that does not divide T, ...) is a failed row (exit_code 2) whose log holds solve's message,
and the other values still run. The sweep checks its own input before anything runs (exit 2,
nothing written): the swept option, its list (no empty value, none twice), the names of the
other options, -out, -plot, -jobs.

DIR follows the run folders' rules (docs/design.md, "Output files"): the sweep locks DIR
(flock; a second sweep or a run on DIR is refused at once, exit 7), writes everything into
DIR.partial.PID and exchanges it with DIR at the end in one rename. An existing DIR is
replaced only if it is empty or holds a finished sweep and nothing else: the entries its
sweep.complete lists, each run folder holding only its run.complete's files (and the figures
its figures/figures.list names). The replaced sweep loses only those; anything else keeps it
as DIR.kept.PID (a note says so). A failure or a signal removes DIR.partial.PID, the runs
under way (they remove their own folders) and the folders the sweep made: DIR stays as it was.
The runs' files name the folder they were written in (out, mesh, scene_file):
DIR.partial.PID/NAME-VALUE.

Exit: 0 every value ran; 1 some value failed (its row says failed; sweep.txt and sweep.png
written); 2 bad input; 7 DIR cannot be made, is not a sweep's (a folder or file of yours, a
single run), is held by another sweep or run, or got files of yours during the sweep;
128 + n stopped by signal n.
"""
import collections
import ctypes
import errno
import fcntl
import math
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import textwrap
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "edp"))

import numpy as np

import figurefiles
import runfiles
import style

TOOL = "sweep.py"
RUN_SH = os.path.join(runfiles.ROOT, "run.sh")
SWEEP_OPTIONS = ("out", "plot", "jobs")            # the sweep's own; every other one goes to solve
HELP = ("-help", "-h", "--help")
MOST_JOBS = 1024
# the columns of sweep.txt: the case, then the run's quantities (zone_* from its summary.txt,
# by name, between the forces and x_B), then the wall time
CASE_COLUMNS = ("value", "run", "status", "exit_code")
HISTORY_COLUMNS = ("normal_force", "tangential_force")
AFTER_ZONES = ("x_B", "x_C", "iterations_total", "iterations_max", "wall_time")
DEFAULT_PLOT = ("normal_force", "x_C")
COMPLETE = "sweep.complete"
COMPLETE_SIGNATURE = ("# sweep.complete: written last by plots/sweep.py (./run.sh sweep), once every run had ended "
                      "and sweep.txt and sweep.png were written; the entries of this folder that the sweep wrote:")
PLAIN_VALUE = re.compile(r"[A-Za-z0-9.+-]{1,100}", re.ASCII)
SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT, signal.SIGUSR1, signal.SIGUSR2, signal.SIGALRM,
           signal.SIGXCPU)   # those that end a process by default, as the solver's (docs/design.md, "Output files")


def refuse(message):
    runfiles.refuse(TOOL, message)                 # exit 2, nothing written


def fail(code, message):
    """Stop the sweep: 'sweep.py: error: MESSAGE', exit code; main's cleanup removes what it made."""
    print(f"{TOOL}: error: {message}", file=sys.stderr)
    raise SystemExit(code)


def note(message):
    print(f"{TOOL}: note: {message}", file=sys.stderr)


# ---------------------------------------------------------------- the command line
Arguments = collections.namedtuple("Arguments", "name values others out plot jobs")
Case = collections.namedtuple("Case", "index value name")   # name: the run folder's, in DIR


def usage():
    print(__doc__)


def parse(argv):
    """The sweep's command line, checked (refuse: exit 2) before anything is written."""
    options = runfiles.option_table()[0]
    names = "-" + ", -".join(name for name in options if name not in SWEEP_OPTIONS) + "; the sweep's own: -out, -plot, -jobs"

    def option_word(word):                         # an option where a value should be
        return word in HELP or (word[:1] == "-" and (word[1:] in options or word[1:] in SWEEP_OPTIONS))

    if any(word in HELP for word in argv):
        usage()
        sys.exit(0)
    if not argv or argv[0][:1] != "-" or len(argv[0]) < 2:
        refuse("give the swept option and its values first: ./run.sh sweep -NAME V1,V2,... [solve options] -out DIR "
               "(./run.sh sweep -help)")
    name = argv[0][1:]
    if name == "out":
        refuse("option -out is the sweep's folder DIR (each run's -out is DIR/NAME-VALUE): it cannot be swept")
    if name in SWEEP_OPTIONS:
        refuse(f"option -{name} is the sweep's own: it cannot be swept; give the swept option first")
    if name not in options:
        refuse(f"unknown option '-{runfiles.shown(name)}' to sweep; options are {names}")
    if options[name].type == "flag":
        refuse(f"option -{name} is a flag (on when given): it takes no values to sweep")
    if len(argv) < 2 or option_word(argv[1]):
        refuse(f"option -{name} needs a list of values, V1,V2,..." + (f", got the option '{argv[1]}'" if len(argv) > 1 else ""))
    values = argv[1].split(",")
    numeric = options[name].type in ("real", "int")
    seen = {}
    for k, value in enumerate(values, 1):
        if not value:
            refuse(f"the list of -{name} '{runfiles.shown(argv[1])}' has an empty value (value {k}): "
                   "give V1,V2,... without empty ones")
        if any(c.isspace() for c in value) or "#" in value:
            refuse(f"value '{runfiles.shown(value)}' of -{name} holds a space or a '#': sweep.txt's columns are "
                   "separated by spaces and '#' starts a comment there; rename the file")
        key = value
        if numeric:
            try:
                number = float(value)
                key = number if math.isfinite(number) else value
            except ValueError:
                pass                                # (solve refuses it: a failed row)
        if key in seen:
            first = values[seen[key] - 1]
            refuse(f"the list of -{name} gives the same value twice (value {seen[key]}, {runfiles.shown(first)}, and value "
                   f"{k}, {runfiles.shown(value)}" + (": the same number" if value != first else "") + "): give each value once")
        seen[key] = k
    others, given, out, plot, jobs = [], set(), None, DEFAULT_PLOT, None
    i = 2
    while i < len(argv):
        word = argv[i]
        other = word[1:]
        if word[:1] != "-" or len(word) < 2:
            before = argv[i - 1][1:]
            if i > 2 and before in options and options[before].type == "flag":
                refuse(f"option -{before} is a flag: it takes no value, got '{runfiles.shown(word)}'")
            refuse(f"expected an option -name, got '{runfiles.shown(word)}'; options are {names}")
        if other == name:
            refuse(f"option -{name} is the swept one: give its values once, in the list after it")
        if other not in options and other not in SWEEP_OPTIONS:
            refuse(f"unknown option '-{runfiles.shown(other)}'; options are {names}")
        if other in given:
            refuse(f"option -{other} is given twice")
        given.add(other)
        if other in options and options[other].type == "flag":
            others.append(word)
            i += 1
            continue
        if i + 1 >= len(argv):
            refuse(f"option -{other} needs a value")
        value = argv[i + 1]
        if not value:
            refuse(f"option -{other} has an empty value")
        if option_word(value):
            refuse(f"option -{other} needs a value, got the option '{value}'")
        if other == "out":
            out = value
        elif other == "plot":
            plot = parse_plot(value)
        elif other == "jobs":
            if not re.fullmatch(r"[0-9]{1,4}", value, re.ASCII) or not 1 <= int(value) <= MOST_JOBS:
                refuse(f"option -jobs = '{runfiles.shown(value)}' must be a whole number from 1 to {MOST_JOBS}")
            jobs = int(value)
        else:
            others += [word, value]
        i += 2
    if out is None:
        refuse("option -out DIR is missing: the folder of the sweep (its runs go into DIR/NAME-VALUE)")
    if jobs is None:
        jobs = max(1, len(os.sched_getaffinity(0)))
    return Arguments(name, values, others, check_out(out), plot, jobs)


def parse_plot(text):
    """The quantities of -plot: columns of sweep.txt that hold numbers."""
    quantities = text.split(",")
    known = HISTORY_COLUMNS + AFTER_ZONES
    for k, quantity in enumerate(quantities, 1):
        if not quantity:
            refuse(f"option -plot '{runfiles.shown(text)}' has an empty name (name {k})")
        if quantity not in known and not re.fullmatch(r"zone_[A-Za-z0-9_]+", quantity, re.ASCII):
            refuse(f"option -plot: '{runfiles.shown(quantity)}' is not a quantity of sweep.txt; quantities are "
                   f"{', '.join(HISTORY_COLUMNS)}, zone_NAME (the runs' zones, e.g. zone_bound_slip), {', '.join(AFTER_ZONES)}")
        if quantities.index(quantity) != k - 1:
            refuse(f"option -plot names {quantity} twice")
    return tuple(quantities)


def check_out(out):
    """DIR as given, without trailing slashes; refused (exit 2) where no sweep can go."""
    folder = out.rstrip("/") or "/"
    base = os.path.basename(folder)
    if folder == "/" or base in (".", "..") or folder.startswith("-"):
        refuse(f"option -out = '{runfiles.shown(out)}' is not a usable folder name (give a new folder, or the folder "
               "of an earlier sweep, e.g. results/sweep-mu)")
    if len(os.fsencode(base)) + len(".partial.") + 10 > 255:
        refuse(f"option -out: its last part is {len(os.fsencode(base))} bytes long; with the sweep's '.partial.<pid>' "
               "it would pass the system's limit of 255 bytes a name; give a shorter name")
    if os.path.islink(folder):
        refuse(f"option -out = '{runfiles.shown(out)}' is a symbolic link: the suite does not write through one; "
               "give the folder it points to")
    ancestor = os.path.dirname(os.path.abspath(folder))
    while True:
        for marker, what in (("run.complete", "a run"), (COMPLETE, "a sweep")):
            if os.path.isfile(os.path.join(ancestor, marker)):
                refuse(f"option -out = '{runfiles.shown(out)}' lies inside {runfiles.shown(ancestor)}, the folder of "
                       f"{what} of this suite ({marker}): what the sweep put there would keep that folder from being "
                       "replaced; choose a folder outside it")
        if os.path.dirname(ancestor) == ancestor:
            return folder
        ancestor = os.path.dirname(ancestor)


def cases_of(arguments):
    """A Case per value: its run folder's name in DIR, safe for any value text and distinct
    (a plain value: NAME-VALUE; another: NAME_K_..., K its place in the list)."""
    cases = []
    for k, value in enumerate(arguments.values, 1):
        if PLAIN_VALUE.fullmatch(value) and not value.endswith(".log"):
            folder = f"{arguments.name}-{value}"
        else:
            folder = f"{arguments.name}_{k}_" + re.sub(r"[^A-Za-z0-9.+-]", "_", value, flags=re.ASCII)[:80]
        cases.append(Case(k, value, folder))
    return cases


# ---------------------------------------------------------------- the folder DIR
def foreign_in_run(folder):
    """What a run folder holds that its run.complete does not list (a later run would refuse
    to replace it: edp/plugins/runtools/runfolder.cpp, whyNotReplaceable), as names in it."""
    listed = runfiles.completed_files(folder)
    if listed is None:
        return ["(no run.complete)"]
    listed = set(listed) | {"run.complete"}
    foreign = []
    for entry in sorted(os.scandir(folder), key=lambda e: e.name):
        if not entry.is_dir(follow_symlinks=False):
            if entry.name not in listed:
                foreign.append(entry.name)
        elif entry.name == "vtk":
            foreign += [f"vtk/{f.name}" for f in os.scandir(entry.path)
                        if f.is_dir(follow_symlinks=False) or f"vtk/{f.name}" not in listed]
        elif entry.name == "figures":
            drawn, ours = figures_drawn(entry.path)
            foreign += [f"figures/{f.name}" for f in os.scandir(entry.path)
                        if f.is_dir(follow_symlinks=False)
                        or not (f.name in drawn or (f.name == figurefiles.FIGURES_LIST and ours))]
        else:
            foreign.append(entry.name + "/")
    return foreign


def figures_drawn(figures):
    """The figures a figures/ folder's figures.list names, and whether that list is the suite's."""
    try:
        fd = os.open(figures, runfiles.FOLDER | os.O_NOFOLLOW)
    except OSError:
        return set(), False
    try:
        drawn, data = figurefiles.figures_listed(fd, figures)
        return drawn or set(), data is not None
    except runfiles.InputError:
        return set(), False
    finally:
        os.close(fd)


def why_not_replaceable(folder):
    """'' when a sweep may replace the folder (empty, or a finished sweep and nothing else);
    else why not."""
    try:
        entries = sorted(os.scandir(folder), key=lambda e: e.name)
    except OSError as error:
        return f"cannot be read ({error.strerror})"
    if not entries:
        return ""
    listed = runfiles.completed_files(folder, COMPLETE)
    if listed is None:
        if runfiles.completed_files(folder) is not None:
            return "holds the results of one run (run.complete), not of a sweep"
        return f"is a folder that does not hold a sweep of this suite (no {COMPLETE})"
    listed = {name for name in listed if "/" not in name}
    foreign = []
    for entry in entries:
        if entry.name == COMPLETE:
            continue
        if entry.name not in listed:
            foreign.append(entry.name)
        elif entry.is_dir(follow_symlinks=False):
            foreign += [f"{entry.name}/{name}" for name in foreign_in_run(entry.path)]
    if foreign:
        more = f" and {len(foreign) - 5} more" if len(foreign) > 5 else ""
        return ("holds files that this suite did not write there ("
                + ", ".join(runfiles.shown(name) for name in foreign[:5]) + more + ")")
    return ""


def remove_run(folder):
    """Remove what a run folder's run.complete lists (and the figures its figures.list names),
    then the folder if that emptied it."""
    for name in (runfiles.completed_files(folder) or []) + ["run.complete"]:
        with_errors_ignored(os.unlink, os.path.join(folder, name))
    figures = os.path.join(folder, "figures")
    if os.path.isdir(figures) and not os.path.islink(figures):
        drawn, ours = figures_drawn(figures)
        for name in sorted(drawn) + ([figurefiles.FIGURES_LIST] if ours else []):
            with_errors_ignored(os.unlink, os.path.join(figures, name))
    for inside in ("figures", "vtk", ""):
        with_errors_ignored(os.rmdir, os.path.join(folder, inside) if inside else folder)


def remove_sweep(folder):
    """Empty a replaced sweep folder by its own lists; True when it is gone."""
    for name in runfiles.completed_files(folder, COMPLETE) or []:
        path = os.path.join(folder, name)
        if "/" in name:
            continue
        if os.path.isdir(path) and not os.path.islink(path):
            remove_run(path)
        else:
            with_errors_ignored(os.unlink, path)
    with_errors_ignored(os.unlink, os.path.join(folder, COMPLETE))
    return with_errors_ignored(os.rmdir, folder)


def with_errors_ignored(step, path):
    try:
        step(path)
        return True
    except OSError:                                # gone already, not ours, not empty
        return False


def exchange(a, b):
    """Exchange the folders a and b in one rename (renameat2, RENAME_EXCHANGE); False where the
    system or the file system cannot."""
    try:
        renameat2 = ctypes.CDLL(None, use_errno=True).renameat2
    except AttributeError:
        return False
    renameat2.argtypes = (ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint)
    at_cwd, rename_exchange = -100, 2
    if renameat2(at_cwd, os.fsencode(a), at_cwd, os.fsencode(b), rename_exchange) == 0:
        return True
    number = ctypes.get_errno()
    if number in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):
        return False
    raise OSError(number, os.strerror(number), a)


class Folder:
    """The sweep's DIR: locked for the whole sweep, built in DIR.partial.PID, exchanged with
    DIR at the end; close() (on any failure or signal) removes what the sweep made."""

    def __init__(self, out):
        self.out = out
        self.parent, self.base = os.path.dirname(out), os.path.basename(out)
        self.partial = f"{out}.partial.{os.getpid()}"
        self.made, self.made_out, self.partial_made, self.lock = [], False, False, None

    def open(self):
        """Make the parent folders and DIR.partial.PID, lock DIR (made empty if missing), and
        check that a sweep may replace it."""
        missing, parent = [], self.parent
        while parent and not os.path.isdir(parent):
            missing.append(parent)
            parent = os.path.dirname(parent)
        for folder in reversed(missing):
            try:
                os.mkdir(folder)
            except OSError as error:
                if os.path.lexists(folder):
                    fail(7, f"option -out = '{runfiles.shown(self.out)}': {runfiles.shown(folder)} exists and is not a folder")
                fail(7, f"cannot create the folder {runfiles.shown(folder)} (for -out): {error.strerror}")
            self.made.append(folder)
        try:
            os.mkdir(self.partial)                 # before the lock: a refused sweep can name who holds DIR
        except OSError as error:
            fail(7, f"cannot create the folder {runfiles.shown(self.partial)}: {error.strerror}")
        self.partial_made = True
        self.take_lock()
        for pid, entry in self.others(alive=False):
            note(f"{runfiles.shown(os.path.join(self.parent, entry))} is left from a sweep or run that was killed "
                 f"(process {pid} no longer runs); it holds no results, and you may delete it")
        why = why_not_replaceable(self.out)
        if why:
            fail(7, f"option -out = '{runfiles.shown(self.out)}' {why}: it is not replaced; choose another -out")

    def take_lock(self):
        """flock DIR (made empty when missing: a lock needs a folder); taken again when the
        folder at DIR changed between its open and the lock."""
        for _ in range(8):
            try:
                os.mkdir(self.out)
                self.made_out = True
            except FileExistsError:
                pass
            except OSError as error:
                fail(7, f"cannot create the folder {runfiles.shown(self.out)}: {error.strerror}")
            try:
                fd = os.open(self.out, runfiles.FOLDER | os.O_NOFOLLOW)
            except FileNotFoundError:
                continue
            except OSError as error:
                if os.path.islink(self.out):
                    fail(2, f"option -out = '{runfiles.shown(self.out)}' is a symbolic link: the suite does not write "
                            "through one; give the folder it points to")
                if os.path.exists(self.out) and not os.path.isdir(self.out):
                    fail(7, f"option -out = '{runfiles.shown(self.out)}' exists and is not a folder")
                fail(7, f"cannot open the folder {runfiles.shown(self.out)}: {error.strerror}")
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                holders = " ".join(str(pid) for pid, _ in self.others(alive=True))
                fail(7, f"option -out = '{runfiles.shown(self.out)}': another sweep or run"
                        + (f" (process {holders})" if holders else "") + " is writing it; wait for it, or choose another -out")
            try:
                now = os.lstat(self.out)
            except FileNotFoundError:
                now = None
            held = os.fstat(fd)
            if now is not None and (now.st_dev, now.st_ino) == (held.st_dev, held.st_ino):
                self.lock = fd
                return
            os.close(fd)
        fail(7, f"option -out = '{runfiles.shown(self.out)}': the folder keeps changing (other sweeps replace it); try again")

    def others(self, alive):
        """(pid, name) of the DIR.partial.PID beside DIR of other processes, running or gone."""
        prefix = self.base + ".partial."
        found = []
        try:
            names = os.listdir(self.parent or ".")
        except OSError:
            return found
        for name in sorted(names):
            if not name.startswith(prefix) or not name[len(prefix):].isdigit():
                continue
            pid = int(name[len(prefix):])
            if pid == os.getpid() or pid <= 0:
                continue
            try:
                os.kill(pid, 0)
                running = True
            except ProcessLookupError:
                running = False
            except PermissionError:
                running = True
            if running == alive:
                found.append((pid, name))
        return found

    def commit(self, entries):
        """Write sweep.complete (listing entries), check DIR again, exchange DIR.partial.PID
        with DIR, and empty the sweep it replaced. Signals wait until it is done."""
        text = "\n".join([COMPLETE_SIGNATURE] + list(entries)) + "\n"
        with runfiles.new_file(os.path.join(self.partial, COMPLETE)) as f:
            f.write(text.encode())
        for name in ("sweep.txt", "sweep.png", COMPLETE, ""):
            sync(os.path.join(self.partial, name) if name else self.partial)
        why = why_not_replaceable(self.out)
        if why:
            fail(7, f"option -out = '{runfiles.shown(self.out)}' {why} (put there during the sweep): it is not replaced, "
                    "and the new sweep is removed")
        signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)
        if exchange(self.partial, self.out):
            replaced = self.partial
        else:                                      # two renames: DIR is missing for a moment
            replaced = f"{self.out}.replaced.{os.getpid()}"
            os.rename(self.out, replaced)
            os.rename(self.partial, self.out)
        self.partial_made, self.made, self.made_out = False, [], False
        sync(self.parent or ".")
        if not remove_sweep(replaced):
            kept = f"{self.out}.kept.{os.getpid()}"
            os.rename(replaced, kept)
            note(f"the sweep that {runfiles.shown(self.out)} held kept files it did not list (put there during the "
                 f"sweep): they are in {runfiles.shown(kept)}; the new sweep is in {runfiles.shown(self.out)}")
        self.close()
        signal.pthread_sigmask(signal.SIG_UNBLOCK, SIGNALS)

    def close(self):
        """Remove what the sweep made and has not committed: DIR.partial.PID, DIR made empty,
        the parent folders it made; release the lock."""
        if self.partial_made:
            shutil.rmtree(self.partial, ignore_errors=True)
            self.partial_made = False
        if self.made_out:
            with_errors_ignored(os.rmdir, self.out)
            self.made_out = False
        for folder in reversed(self.made):
            with_errors_ignored(os.rmdir, folder)
        self.made = []
        if self.lock is not None:
            os.close(self.lock)
            self.lock = None


def sync(path):
    try:
        fd = os.open(path, os.O_RDONLY | os.O_CLOEXEC)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


# ---------------------------------------------------------------- the runs
class Runs:
    """The solves under way: pid -> (case, process, start); stop() ends them (each removes
    what it created)."""

    def __init__(self):
        self.running = {}

    def stop(self):
        for _, process, _ in self.running.values():
            with_errors_ignored(lambda _: process.terminate(), None)
        for _, process, _ in self.running.values():
            process.wait()
        self.running = {}


Outcome = collections.namedtuple("Outcome", "exit_code wall_time")


def run_cases(arguments, cases, folder, runs):
    """Run the solves, arguments.jobs at a time, in the order of the list; a progress line for
    each as it ends. {case: Outcome}."""
    pending, outcomes = list(cases), {}
    while pending or runs.running:
        while pending and len(runs.running) < arguments.jobs:
            case = pending.pop(0)
            log = os.open(os.path.join(folder.partial, case.name + ".log"), runfiles.NEW_FILE, 0o666)
            command = [RUN_SH, "solve", *arguments.others, f"-{arguments.name}", case.value,
                       "-out", os.path.join(folder.partial, case.name)]
            start = time.monotonic()
            try:
                process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT)
            finally:
                os.close(log)
            runs.running[process.pid] = (case, process, start)
        pid, status = os.waitpid(-1, 0)
        end = time.monotonic()
        if pid not in runs.running:
            continue
        case, process, start = runs.running[pid]
        process.returncode = os.waitstatus_to_exitcode(status)
        del runs.running[pid]
        code = process.returncode if process.returncode >= 0 else 128 - process.returncode
        outcomes[case] = Outcome(code, end - start)
        what = "ok" if code == 0 else f"failed (exit {code}): {error_line(folder.partial, case)}"
        print(f"sweep: -{arguments.name} {runfiles.shown(case.value)}: {what} [{end - start:.2f} s]", flush=True)
    return outcomes


def error_line(partial, case):
    """The message of a failed solve: the last 'error: ...' line of its log (else its last line)."""
    try:
        lines = [line for line in runfiles.read_lines(os.path.join(partial, case.name + ".log")) if line.strip()]
    except runfiles.InputError:
        return "(no log)"
    errors = [line for line in lines if "error:" in line]
    return runfiles.shown((errors or lines or ["(nothing printed)"])[-1], 200)


def quantities(folder):
    """The quantities of a finished run at T: {column: value}, the zones by name."""
    runfiles.run_folder(folder)
    summary = runfiles.read_summary(folder)
    history = runfiles.read_table(os.path.join(folder, "contact_history.txt"))
    found = {column: float(history[column][-1]) for column in HISTORY_COLUMNS + ("x_B", "x_C")}
    found.update({zone: summary.integer(zone) for zone in runfiles.zone_names(summary)})
    found.update({key: summary.integer(key) for key in ("iterations_total", "iterations_max")})
    return found


# ---------------------------------------------------------------- sweep.txt and sweep.png
def table(arguments, cases, outcomes, found):
    """The columns and rows of sweep.txt."""
    zones = []
    for case in cases:
        zones += [name for name in runfiles.zone_names(found.get(case, {})) if name not in zones]
    columns = CASE_COLUMNS + HISTORY_COLUMNS + tuple(zones) + AFTER_ZONES
    rows = []
    for case in cases:
        ok = case in found
        values = dict(found.get(case, {}), wall_time=outcomes[case].wall_time)
        rows.append([case.value, case.name, "ok" if ok else "failed", outcomes[case].exit_code]
                    + [values.get(column, math.nan) for column in columns[len(CASE_COLUMNS):]])
    return columns, rows


def draw(arguments, columns, rows, partial, command):
    """sweep.png: each -plot quantity against the value (a numeric axis for a real or int
    option whose values are all numbers, log when they are positive and span 100 or more;
    else one place per value, in the order given); failed cases marked at the bottom."""
    from matplotlib.transforms import blended_transform_factory
    plt = style.pyplot()
    option = runfiles.option_table()[0][arguments.name]
    texts = [row[0] for row in rows]
    try:
        xs = np.array([float(text) for text in texts]) if option.type in ("real", "int") else None
    except ValueError:
        xs = None
    if xs is None or not np.isfinite(xs).all():
        xs = np.arange(len(rows), dtype=float)
        categorical = True
    else:
        categorical = False
    logarithmic = not categorical and (xs > 0).all() and xs.max() >= 100 * xs.min()
    status = np.array([row[2] for row in rows])
    # the natural scales of the quantities (style.scales: forces p(g) |Gamma3|; x_B, x_C the
    # extent of Gamma3), from the runs that finished: round-off between runs is drawn flat
    tables = [runfiles.read_table(os.path.join(partial, row[1], "contact.txt")) for row in rows
              if row[2] == "ok" and os.path.isfile(os.path.join(partial, row[1], "contact.txt"))]
    least = {}
    if tables:
        force = style.scales(*tables).force
        extent = max(float(np.ptp(t.finite("x")[0])) for t in tables)
        least = {"normal_force": force, "tangential_force": force, "tangential_force2": force, "x_B": extent, "x_C": extent}
    fig, axes = plt.subplots(len(arguments.plot), 1, figsize=(7.5, 1.3 + 2.3 * len(arguments.plot)),
                             sharex=True, squeeze=False)
    for ax, quantity in zip(axes[:, 0], arguments.plot):
        at_bottom = blended_transform_factory(ax.transData, ax.transAxes)
        if quantity not in columns:
            ax.text(0.5, 0.5, f"no run has the quantity {quantity}", transform=ax.transAxes, ha="center", va="center")
        else:
            ys = np.array([float(row[columns.index(quantity)]) for row in rows])
            good = (status == "ok") & np.isfinite(ys)
            order = np.argsort(xs[good], kind="stable") if not categorical else np.arange(good.sum())
            ax.plot(xs[good][order], ys[good][order], "o" if categorical else "o-", color="tab:blue", markersize=5,
                    label=quantity)                # (no line between the places of words)
            empty = (status == "ok") & ~np.isfinite(ys)
            if empty.any():
                ax.plot(xs[empty], np.full(empty.sum(), 0.06), "o", mfc="none", color="0.4", markersize=6,
                        transform=at_bottom, clip_on=False, label=f"{quantity} = nan (ok run)")
        failed = status == "failed"
        if failed.any():
            ax.plot(xs[failed], np.full(failed.sum(), 0.06), "x", color="tab:red", markersize=8, mew=2,
                    transform=at_bottom, clip_on=False, label="failed")
            for x, row in zip(xs[failed], [row for row in rows if row[2] == "failed"]):
                ax.annotate(f"exit {row[3]}", (x, 0.06), xycoords=at_bottom, xytext=(4, 4), textcoords="offset points",
                            fontsize=7, color="tab:red")
        ax.set_ylabel(quantity)
        ax.legend(fontsize=7)
        if quantity in least:
            style.least_span(ax, least[quantity])
    bottom = axes[-1, 0]
    if logarithmic:
        bottom.set_xscale("log")
    if categorical:
        bottom.set_xticks(xs)
        bottom.set_xticklabels([runfiles.shown(text, 24) for text in texts], rotation=20 if len(rows) > 4 else 0)
    bottom.set_xlabel(f"-{arguments.name}")
    title = textwrap.fill(runfiles.shown(command, 400), 95)
    axes[0, 0].set_title(title, fontsize=8)
    return style.save(fig, partial, "sweep")


# ---------------------------------------------------------------- the sweep
def main(state):
    def stop(number, _frame):                      # (runfiles.run_tool's, noting the signal for cleanup)
        state["signal"] = number
        raise SystemExit(128 + number)
    for number in SIGNALS:
        signal.signal(number, stop)
    runfiles.check_arguments(TOOL)                 # a name not in UTF-8, a control character: refused
    arguments = parse(sys.argv[1:])
    cases = cases_of(arguments)
    command = "./run.sh sweep " + shlex.join(sys.argv[1:])
    folder = state["folder"] = Folder(arguments.out)
    folder.open()
    runs = state["runs"] = Runs()
    outcomes = run_cases(arguments, cases, folder, runs)
    found, entries = {}, []
    for case in cases:
        log = os.path.join(folder.partial, case.name + ".log")
        if outcomes[case].exit_code == 0:
            try:
                found[case] = quantities(os.path.join(folder.partial, case.name))
                os.unlink(log)                     # (an ok run's log: its results say more)
            except runfiles.InputError as error:   # a run that exited 0 but whose files cannot be read
                with open(log, "a") as f:
                    f.write(f"{TOOL}: the run's files cannot be read: {error}\n")
        if os.path.isdir(os.path.join(folder.partial, case.name)):
            entries.append(case.name)
        if case not in found:
            entries.append(case.name + ".log")
    columns, rows = table(arguments, cases, outcomes, found)
    # what made the runs (their summary.txt's versions; one line each value when they differ)
    summaries = [runfiles.read_summary(os.path.join(folder.partial, row[1], "summary.txt")) for row in rows
                 if row[2] == "ok" and os.path.isfile(os.path.join(folder.partial, row[1], "summary.txt"))]
    versions = []
    for key in ("suite_version", "freefem_version", "gmsh_version"):
        values = [s.get(key) for s in summaries if s.get(key)]
        versions += [f"{key} {value}" for value in dict.fromkeys(values)]     # each once, in the runs' order
    runfiles.write_table(os.path.join(folder.partial, "sweep.txt"),
                         [f"sweep: {command}", f"swept {arguments.name}"] + versions
                         + ["one row per value, in the order given: the run at T (nan: a failed run; wall_time: seconds, "
                            "measured around the solve process)"],
                         columns, rows)
    draw(arguments, columns, rows, folder.partial, command)
    folder.commit(entries + ["sweep.txt", "sweep.png"])
    failed = [row for row in rows if row[2] == "failed"]
    for row in failed:
        print(f"{TOOL}: error: -{arguments.name} {runfiles.shown(row[0])} failed (exit {row[3]}); its log: "
              f"{runfiles.shown(os.path.join(arguments.out, row[1] + '.log'))}", file=sys.stderr)
    print(f"sweep: {len(rows)} runs, {len(failed)} failed -> {arguments.out}/sweep.txt, {arguments.out}/sweep.png")
    return 1 if failed else 0


def cleanup(state):
    """Whatever ended the sweep: stop the runs under way, remove what it made and did not commit."""
    signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)
    if state.get("signal"):
        print(f"{TOOL}: stopped by signal {state['signal']}: the runs under way stopped, and what the sweep made is "
              "removed (-out as it was)", file=sys.stderr)
    if state.get("runs"):
        state["runs"].stop()
    if state.get("folder"):
        state["folder"].close()


if __name__ == "__main__":
    shared = {}
    sys.exit(runfiles.run_tool(TOOL, lambda: main(shared), code=1, cleanup=lambda: cleanup(shared)))
