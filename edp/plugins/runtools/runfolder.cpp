// runfolder.cpp: the run folder as one transaction (docs/design.md, "Output files", which
// says why each step is there). A run locks OUT, writes OUT.partial.<pid>, marks it complete
// (run.complete, naming its files) once every file is checked, and exchanges it with OUT in
// one rename; a failure at any moment removes what the run created and nothing else. Also what
// a failure removes (cleanUp), which the signal handler of messages.cpp calls.
#include "runtools.hpp"
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <set>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

namespace runtools {

// ---------------------------------------------------------------- what the run created
// The signal handler may only make system calls: it reads fixed buffers, each written before
// the flag that lets the handler use it is raised.
namespace {
char partialPathC[4096], outPathC[4096], temporaryC[4096];
// the parent folders of OUT that this run made: prefixes of one path, outermost first (a path
// of 4095 bytes has at most 2048 folders)
char madeParentPathC[4096];
size_t madeParentLength[2048];
volatile sig_atomic_t cleanPartial = 0, cleanOut = 0, madeParents = 0, haveTemporary = 0;

void recordMadeParent(const std::string &folder) {
  if (folder.size() >= sizeof madeParentPathC || madeParents >= 2048) return;
  std::memcpy(madeParentPathC, folder.c_str(), folder.size() + 1);   // extends the folders made before: their bytes stay
  madeParentLength[madeParents] = folder.size();
  madeParents = madeParents + 1;
}
}  // namespace

volatile pid_t runningChild = 0;
volatile pid_t runningRanks = 0;
volatile int ranksFileFd = -1;
volatile sig_atomic_t resultsInPlace = 0;          // the results are in OUT (runFolderFinish): a signal now changes nothing
volatile sig_atomic_t holdSignals = 0, heldSignal = 0;   // a signal held until the work under way is done (messages.cpp)
const char *outFolderText() { return outPathC; }

// ---------------------------------------------------------------- -ranks N: the launching run's file
// The run that started mpirun (runLaunchRanks) and its ranks share one file, which that run made
// in TMPDIR and unlinked at once: it holds it open (ranksFileFd; the ranks open it as
// /proc/<its pid>/fd/<fd>, CONTACT_SUITE_RANK_IDS), so that it goes with that run whatever ends
// it. Each rank appends its process id, a line of digits (registerRank); the first rank appends
// what it created once it holds OUT ("out PATH", "partial PATH", "created" if it made OUT,
// "parents K" for the K folders above OUT it made) and "done" once its results are in OUT
// (tellLauncher). A rank killed outright (SIGKILL: the system's out-of-memory killer) cannot
// remove what it created, and mpirun, stopped or killed, may lose what the ranks print: the
// launching run reads the file when mpirun has ended otherwise than with 0 (ranksEnded), removes
// what is left and says what happened. System calls only: the signal handler calls it too.
namespace {
char launcherText[1 << 16];
struct LauncherFile {
  const char *out = nullptr, *partial = nullptr;
  int parents = 0;
  bool created = false, done = false;
};
bool startsWith(const char *line, const char *prefix) {
  while (*prefix) if (*line++ != *prefix++) return false;
  return true;
}
// the file's lines, in launcherText (each cut at its end); onPid(id) for each line of digits
template <class F> LauncherFile readLauncherFile(F onPid) {
  LauncherFile file;
  long got = 0;
  if (ranksFileFd >= 0) {
    long n;
    while (got < (long)sizeof launcherText - 1 && (n = pread(ranksFileFd, launcherText + got, sizeof launcherText - 1 - got, got)) > 0) got += n;
  }
  launcherText[got] = 0;
  for (long start = 0; start < got;) {
    long end = start;
    while (end < got && launcherText[end] != '\n') end++;
    if (end == got) break;                         // (a line still being written)
    launcherText[end] = 0;
    const char *line = launcherText + start;
    bool digits = *line != 0;
    long id = 0;
    for (const char *c = line; *c && digits; c++) { digits = *c >= '0' && *c <= '9'; id = 10 * id + (*c - '0'); }
    if (digits) { if (id > 1) onPid((pid_t)id); }
    else if (startsWith(line, "out ")) file.out = line + 4;
    else if (startsWith(line, "partial ")) file.partial = line + 8;
    else if (startsWith(line, "parents ")) { file.parents = 0; for (const char *c = line + 8; *c >= '0' && *c <= '9'; c++) file.parents = 10 * file.parents + (*c - '0'); }
    else if (startsWith(line, "created") && line[7] == 0) file.created = true;
    else if (startsWith(line, "done") && line[4] == 0) file.done = true;
    start = end + 1;
  }
  return file;
}
void sayText(const char *text) { if (write(2, text, std::strlen(text)) < 0) {} }
// done() asked every 10 ms, for seconds at most: true once it holds
template <class F> bool pollFor(double seconds, F done) {
  for (int tick = 0; tick < seconds * 100; tick++) {
    if (done()) return true;
    const struct timespec wait = {0, 10000000};
    nanosleep(&wait, nullptr);
  }
  return done();
}
int ranksLeft, ranksSeen;                          // (counted by ranksEnded)
}  // namespace

// -ranks N, the run that started mpirun, on a signal: SIGINT to each rank at once (mpirun passes
// a signal on only after about a second, while the first rank may still write the outputs;
// each rank's handler removes what it created; not SIGTERM, which METIS catches while it
// partitions, and then fails), SIGTERM to mpirun (SIGCONT too: a stopped mpirun would be
// waited for forever); then waits for mpirun. System calls only.
// Once the first rank has its results in OUT ("done"), nothing is stopped: the run ends as it
// would (the earlier OUT removed, MPI ended), for 60 s at most.
void stopRanks() {
  const pid_t launcher = runningRanks;
  if (launcher <= 0) return;
  int status;
  if (readLauncherFile([](pid_t) {}).done && pollFor(60, [&] { return waitpid(launcher, &status, WNOHANG) == launcher; })) {
    runningRanks = 0;
    return;
  }
  readLauncherFile([](pid_t id) { kill(id, SIGINT); });
  kill(launcher, SIGTERM);
  kill(launcher, SIGCONT);
  while (waitpid(launcher, &status, 0) < 0 && errno == EINTR) {}
  runningRanks = 0;
}

// -ranks N, the run that started mpirun, once mpirun has ended with code (its exit code, 128 + n
// after signal n; or, on a signal to this run, 128 + that signal): waits (3 s at most) for ranks
// that outlive a killed mpirun, removes what a rank killed outright left (OUT.partial.<pid>; OUT
// and the folders above it that the run made, if still empty and no other run holds OUT) and
// says what happened where no rank could: a signal that stopped the run ("interrupted"),
// SIGKILL (an error), or results already in OUT (a note; then 0). An error a rank said (its
// exit code), or a crash, it leaves as said. Returns the run's exit code. System calls only.
int ranksEnded(int code) {
  if (ranksFileFd < 0) return code;
  if (code != 0)                                   // (mpirun killed: its ranks end about a second later)
    pollFor(3, [] {
      ranksLeft = 0;
      readLauncherFile([](pid_t id) { if (kill(id, 0) == 0) ranksLeft++; });
      return ranksLeft == 0;
    });
  ranksSeen = 0;                                   // (read after the ranks ended: what they wrote last included)
  const LauncherFile file = readLauncherFile([](pid_t) { ranksSeen++; });
  close(ranksFileFd);
  ranksFileFd = -1;
  if (code == 0) return 0;
  if (ranksSeen == 0 && code < 128) {              // (mpirun -q hides Open MPI's own words)
    sayText("error: mpirun ended (exit code ");
    char digits[12];
    int k = sizeof digits - 1;
    digits[k] = 0;
    for (int c = code; k > 0 && (c > 0 || k == (int)sizeof digits - 1); c /= 10) digits[--k] = (char)('0' + c % 10);
    sayText(digits + k);
    sayText(") before any rank of the run started (Open MPI's reason, which mpirun -q hides: `mpirun -np 2 true` shows it)\n");
    return code;
  }
  struct stat status;
  const bool partialLeft = file.partial && lstat(file.partial, &status) == 0 && S_ISDIR(status.st_mode);
  if (file.done) {                                 // (stopped while the ranks ended MPI: the results are whole)
    sayText("note: the run had finished: its results are complete in ");
    sayText(file.out ? file.out : "its output folder");
    if (partialLeft) { sayText(" (the earlier results it replaced remain in "); sayText(file.partial); sayText(": remove it)"); }
    sayText("\n");
    return 0;
  }
  if (partialLeft) removeTree(file.partial);
  if (file.out) {
    static char folder[4096];
    size_t length = 0;
    while (file.out[length] && length + 1 < sizeof folder) { folder[length] = file.out[length]; length++; }
    folder[length] = 0;
    if (file.created) {                            // OUT, made empty by the run: only if no other run holds it now
      const int fd = open(folder, O_RDONLY | O_DIRECTORY);
      if (fd >= 0) {
        if (flock(fd, LOCK_EX | LOCK_NB) == 0) rmdir(folder);
        close(fd);
      }
    }
    for (int k = 0; k < file.parents; k++) {       // the folders above OUT the run made, innermost first, if still empty
      while (length > 0 && folder[length - 1] != '/') length--;
      while (length > 1 && folder[length - 1] == '/') length--;
      if (length == 0) break;
      folder[length] = 0;
      rmdir(folder);
    }
  }
  const int signal = code > 128 ? code - 128 : 0;
  if (signal == SIGKILL) {
    sayText("error: a process of the run was killed (SIGKILL: the system's out-of-memory killer, or kill -9) before it could say why");
    sayText(file.partial ? "; the run removed its unfinished output folder\n" : "\n");
  }
  else if (signal == SIGINT || signal == SIGTERM || signal == SIGHUP || signal == SIGQUIT || signal == SIGUSR1 || signal == SIGUSR2
           || signal == SIGALRM || signal == SIGVTALRM || signal == SIGPROF || signal == SIGXCPU) {
    sayText("interrupted");
    sayText(file.partial ? ": the run removed its unfinished output folder\n" : "\n");
  }
  return code;
}

void rememberTemporary(const std::string &path) {
  haveTemporary = 0;
  std::snprintf(temporaryC, sizeof temporaryC, "%s", path.c_str());
  haveTemporary = 1;
}
void forgetTemporary(const std::string &path) { if (haveTemporary && path == temporaryC) haveTemporary = 0; }

bool cleanUp() {
  const bool removed = cleanPartial;
  stopRanks();
  if (runningChild > 0) { kill(runningChild, SIGKILL); runningChild = 0; }   // its file is removed below
  if (haveTemporary) { unlink(temporaryC); haveTemporary = 0; }
  if (cleanPartial) removeTree(partialPathC);
  if (cleanOut) rmdir(outPathC);                   // only if still empty
  for (int k = madeParents - 1; k >= 0; k--) {     // only those still empty
    char folder[sizeof madeParentPathC];
    for (size_t i = 0; i < madeParentLength[k]; i++) folder[i] = madeParentPathC[i];
    folder[madeParentLength[k]] = 0;
    rmdir(folder);
  }
  cleanPartial = 0; cleanOut = 0; madeParents = 0;
  return removed;
}

// ---------------------------------------------------------------- what a run folder holds
namespace {
std::string outPath, partialPath;
int lockFd = -1;                                   // flock on OUT while the run holds it
bool createdOut = false;                           // OUT did not exist: made empty here

const char *completeMarker = "run.complete";
const char *completeSignature =
  "# run.complete: written last by edp/solve.edp, once every file listed below was complete and every end-of-run check had passed";
const char *seriesFolder = "vtk";                  // -vtk N: the one subfolder a run writes
// The figures the tools of plots/ draw into OUT/figures/, named in OUT/figures/figures.list: they
// go with their run. Only the names of edp/figures.txt count (runFigureNames): a list that
// names any other file is not followed, so no list can make a run remove a file of the user's.
const char *figuresFolder = "figures", *figuresList = "figures.list";
const char *figuresSignature = "# figures.list: the figures plots/ of this suite drew here; they go with the run's results";
std::set<std::string> figureNames;

std::string parentOf(const std::string &path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
}
void addName(std::string &list, const std::string &name) { list += (list.empty() ? "" : ", ") + name; }

bool plainName(const std::string &name) { return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos; }
// a name run.complete may list: a plain name, or "vtk/NAME"
bool runFileName(const std::string &name) {
  const size_t slash = name.find('/');
  return slash == std::string::npos ? plainName(name) : name.substr(0, slash) == seriesFolder && plainName(name.substr(slash + 1));
}

// the figures a folder's figures.list names; false when there is no list with the suite's
// signature (then figures.list is not ours either)
bool figuresListed(const std::string &folder, std::set<std::string> &listed) {
  listed.clear();
  std::ifstream f(folder + "/" + figuresFolder + "/" + figuresList);
  std::string line;
  if (!f || !std::getline(f, line) || line != figuresSignature) return false;
  while (std::getline(f, line)) if (figureNames.count(line)) listed.insert(line);
  return true;
}
void removeFigures(const std::string &folder) {
  const std::string figures = folder + "/" + figuresFolder;
  std::set<std::string> listed;
  if (figuresListed(folder, listed)) {
    for (const std::string &name : listed) unlink((figures + "/" + name).c_str());
    unlink((figures + "/" + figuresList).c_str());
  }
  rmdir(figures.c_str());                          // only if empty
}

// The files of a folder as run.complete names them; foreign gets what a run never writes
// (other folders, folders inside vtk/, files in figures/ that its figures.list does not name).
bool runFilesOf(const std::string &folder, std::vector<std::string> &files, std::string &foreign) {
  std::vector<std::pair<std::string, bool>> entries, inside;
  if (!listFolder(folder, entries)) return false;
  for (auto &e : entries) {
    if (!e.second) { files.push_back(e.first); continue; }
    if (e.first == figuresFolder && listFolder(folder + "/" + e.first, inside)) {
      std::set<std::string> drawn;
      const bool listOurs = figuresListed(folder, drawn);
      for (auto &f : inside)
        if (f.second || !(f.first == figuresList ? listOurs : drawn.count(f.first) > 0)) addName(foreign, e.first + "/" + f.first);
      continue;
    }
    if (e.first != seriesFolder || !listFolder(folder + "/" + e.first, inside)) { addName(foreign, e.first); continue; }
    for (auto &f : inside)
      if (f.second) addName(foreign, e.first + "/" + f.first);
      else files.push_back(e.first + "/" + f.first);
  }
  return true;
}

// the names a folder's run.complete lists; false if it has none with the suite's signature
bool completeListing(const std::string &folder, std::set<std::string> &listed) {
  listed.clear();
  std::ifstream f(folder + "/" + completeMarker);
  std::string line;
  if (!f || !std::getline(f, line) || line != completeSignature) return false;
  while (std::getline(f, line))
    if (runFileName(line)) listed.insert(line);
  return true;
}

// "" if a run may replace the folder: it is empty, or holds exactly the files of its
// run.complete (and figures its figures.list names); else why not
std::string whyNotReplaceable(const std::string &folder) {
  std::vector<std::pair<std::string, bool>> entries;
  if (!listFolder(folder, entries)) return "cannot be read (" + errorText() + ")";
  if (entries.empty()) return "";
  std::set<std::string> listed;
  if (!completeListing(folder, listed)) return "is a folder that does not hold results of this suite (no run.complete)";
  std::string foreign;
  std::vector<std::string> files;
  if (!runFilesOf(folder, files, foreign)) return "cannot be read (" + errorText() + ")";
  for (auto &name : files)
    if (name != completeMarker && !listed.count(name)) addName(foreign, name);
  if (!foreign.empty()) return "holds files that this suite did not write there (" + foreign + ")";
  return "";
}

// The OUT.partial.<pid> folders beside OUT of other processes: those still running hold OUT
// (named when this run is refused); those gone were killed with SIGKILL and are only noted,
// since a run removes nothing it did not create.
std::string otherRuns(const std::string &out, bool noteGone) {
  const std::string parent = parentOf(out), prefix = out.substr(out.rfind('/') + 1) + ".partial.";
  std::vector<std::pair<std::string, bool>> entries;
  listFolder(parent, entries);
  std::string running;
  for (auto &e : entries) {
    if (!e.second || e.first.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string pid = e.first.substr(prefix.size());
    const long number = std::atol(pid.c_str());
    if (number <= 0 || number == getpid()) continue;
    if (kill((pid_t)number, 0) == 0) addName(running, pid);
    else if (noteGone && errno == ESRCH)
      toStderr("note: " + parent + "/" + e.first + " is left from a run that was killed (process " + std::to_string(number) +
               " no longer runs); it holds no results, and you may delete it\n");
  }
  return running.empty() ? "" : " (process " + running + ")";
}

void syncFolder(const std::string &path) {
  int fd = open(path.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd >= 0) { fsync(fd); close(fd); }
}
}  // namespace

// ---------------------------------------------------------------- the FreeFEM functions
// edp/figures.txt: one name a line, '#' starts a comment line, empty lines are skipped; a name
// is [A-Za-z0-9_][A-Za-z0-9_.-]*, not figures.list; at least one. plots/ reads the same file
// with the same rules (edp/runfiles.py, figure_names).
bool figureName(const std::string &name) {
  auto allowed = [](char c, bool first) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || (!first && (c == '.' || c == '-'));
  };
  if (name.empty() || name == figuresList) return false;
  for (size_t i = 0; i < name.size(); i++) if (!allowed(name[i], i == 0)) return false;
  return true;
}
long runFigureNames(std::string *const &path) {
  struct stat status;
  std::ifstream f(*path);
  if (stat(path->c_str(), &status) != 0 || !S_ISREG(status.st_mode) || !f)
    fail(3, "cannot read " + *path + ", the names of the figures the tools of plots/ may draw into a run folder");
  figureNames.clear();
  std::string line;
  for (long number = 1; std::getline(f, line); number++) {
    if (line.empty() || line[0] == '#') continue;
    if (!figureName(line))
      fail(3, *path + ":" + std::to_string(number) + ": '" + line + "' is not the file name of a figure (one name a line, "
              + "of letters, digits, '_', '.' and '-', not starting with '.' or '-', not figures.list; '#' starts a comment line)");
    figureNames.insert(line);
  }
  if (f.bad()) fail(3, "cannot read " + *path + ": " + errorText());
  if (figureNames.empty()) fail(3, *path + " names no figure");
  return 0;
}

long runFolderOpen(std::string *const &outText) {
  std::string out = *outText;
  while (out.size() > 1 && out.back() == '/') out.pop_back();
  const std::string base = out.substr(out.rfind('/') + 1), parent = parentOf(out);
  if (out == "/" || base == "." || base == ".." || base.empty() || out[0] == '-')
    fail(2, "option -out = '" + *outText + "' is not a usable folder name (give a new or results folder, e.g. results/run)");
  if (hasControlCharacter(out)) fail(2, "option -out holds a control character or a line separator: give a plain folder name");
  if (!validUtf8(out)) fail(2, "option -out = '" + out + "' is not valid UTF-8: give a folder name the suite's tools can read back");
  // refused now rather than when the last file is written: OUT.partial.<pid>/vtk/fields_NNNNNN.vtu
  const size_t longestInside = std::strlen("/vtk/fields_000000.vtu"), suffix = std::strlen(".partial.") + 10;
  if (out.size() + suffix + longestInside >= PATH_MAX)
    fail(2, "option -out is " + std::to_string(out.size()) + " bytes long: the run's files under it would pass the system's limit of "
            + std::to_string(PATH_MAX - 1) + " bytes a path; give a folder of at most " + std::to_string(PATH_MAX - 1 - suffix - longestInside) + " bytes");
  if (base.size() + suffix > NAME_MAX)
    fail(2, "option -out: its last part is " + std::to_string(base.size()) + " bytes long; with the run's '.partial.<pid>' it would pass the "
            + "system's limit of " + std::to_string(NAME_MAX) + " bytes a name; give at most " + std::to_string(NAME_MAX - suffix));
  struct stat status;
  if (lstat(out.c_str(), &status) == 0 && S_ISLNK(status.st_mode))
    fail(7, "option -out = '" + out + "' is a symbolic link: give the folder itself (the suite replaces OUT whole)");
  if (lstat(out.c_str(), &status) == 0 && !S_ISDIR(status.st_mode)) fail(7, "option -out = '" + out + "' exists and is not a folder");
  outPath = out;
  partialPath = out + ".partial." + std::to_string(getpid());
  std::snprintf(outPathC, sizeof outPathC, "%s", outPath.c_str());
  std::snprintf(partialPathC, sizeof partialPathC, "%s", partialPath.c_str());
  if (!makeFolders(parent, recordMadeParent))
    fail(7, "cannot create the output folder " + partialPath + " (option -out = " + out + "): " + errorText()
            + (errno == EEXIST || errno == ENOTDIR ? " (a part of that path is a file)" : ""));
  struct stat parentStatus;
  if (stat(out.c_str(), &status) == 0 && stat(parent.c_str(), &parentStatus) == 0 && status.st_dev != parentStatus.st_dev)
    fail(7, "option -out = '" + out + "' is a mount point: the suite replaces OUT whole; give a folder inside it");
  // before the lock: a run that holds OUT can always be named by its OUT.partial.<pid>
  if (mkdir(partialPath.c_str(), 0777) != 0)
    fail(7, "cannot create the output folder " + partialPath + " (option -out = " + out + "): " + errorText());
  cleanPartial = 1;
  if (mkdir(out.c_str(), 0777) == 0) createdOut = true;   // a lock needs a folder
  else if (errno != EEXIST) fail(7, "cannot create the output folder " + out + ": " + errorText());
  // the lock, on the folder that is OUT once it is held: another run may exchange OUT between
  // the open and the flock
  for (int attempt = 0;; attempt++) {
    lockFd = open(out.c_str(), O_RDONLY | O_DIRECTORY);
    if (lockFd < 0) fail(7, "option -out = '" + out + "' cannot be read (" + errorText() + "): it is not replaced; choose another -out");
    if (flock(lockFd, LOCK_EX | LOCK_NB) != 0) {
      const int lockError = errno;
      close(lockFd); lockFd = -1;
      if (lockError == EWOULDBLOCK)
        fail(7, "option -out = '" + out + "': another run" + otherRuns(out, false) + " is writing it; wait for it, or choose another -out");
      fail(7, "cannot lock the output folder " + out + ": " + std::strerror(lockError));
    }
    struct stat locked, now;
    if (fstat(lockFd, &locked) == 0 && stat(out.c_str(), &now) == 0 && locked.st_ino == now.st_ino && locked.st_dev == now.st_dev)
      break;
    close(lockFd); lockFd = -1;
    if (attempt == 10) fail(7, "option -out = '" + out + "': other runs keep replacing it; wait for them, or choose another -out");
  }
  cleanOut = createdOut;                           // removed on failure only while this run holds it
  // -ranks N: the launching run removes them if this rank is killed outright (ranksEnded)
  tellLauncher("parents " + std::to_string((int)madeParents));
  tellLauncher("out " + outPath);
  tellLauncher("partial " + partialPath);
  if (createdOut) tellLauncher("created");
  // under the lock, so that no other run changes OUT while it is read
  const std::string why = whyNotReplaceable(out);
  if (!why.empty()) fail(7, "option -out = '" + out + "' " + why + ": it is not replaced; choose another -out");
  if (stat(out.c_str(), &status) == 0) chmod(partialPath.c_str(), status.st_mode & 07777);   // OUT keeps its mode
  otherRuns(out, true);
  return 0;
}

namespace {
// the earlier folder, when something stays in it: OUT.kept.<pid> (or where it is, if taken)
std::string keepAside(const std::string &replaced) {
  const std::string kept = outPath + ".kept." + std::to_string(getpid());
  return syscall(SYS_renameat2, AT_FDCWD, replaced.c_str(), AT_FDCWD, kept.c_str(), 1 /* RENAME_NOREPLACE */) == 0 ? kept : replaced;
}

// The earlier OUT, once the new one has taken its place, loses its marker (first: it never
// looks complete again), the files the marker lists, then itself if that empties it. A file
// of the user's put into OUT after its last check is not removed: the folder is kept aside.
void removeReplaced(const std::string &replaced) {
  std::set<std::string> listed;
  if (completeListing(replaced, listed)) unlink((replaced + "/" + completeMarker).c_str());
  std::string stuck, stuckWhy;                     // listed files that could not be removed
  for (const std::string &name : listed)
    if (unlink((replaced + "/" + name).c_str()) != 0 && errno != ENOENT) {
      if (stuck.empty()) stuckWhy = errorText();
      addName(stuck, name);
    }
  rmdir((replaced + "/" + seriesFolder).c_str());  // only if empty
  removeFigures(replaced);
  if (rmdir(replaced.c_str()) == 0) return;
  const int rmdirError = errno;
  if (!stuck.empty()) {
    toStderr("note: the earlier results could not all be removed (" + stuck + ": " + stuckWhy + "); they are kept in "
             + keepAside(replaced) + "; the new ones are in " + outPath + "\n");
    return;
  }
  if (rmdirError != ENOTEMPTY && rmdirError != EEXIST) {
    toStderr("note: the earlier results could not all be removed from " + replaced + " (" + std::strerror(rmdirError)
             + "); the new ones are in " + outPath + "\n");
    return;
  }
  std::vector<std::pair<std::string, bool>> entries;
  listFolder(replaced, entries);
  std::string names;
  for (auto &e : entries) addName(names, e.first);
  toStderr("note: " + names + " appeared in " + outPath + " while this run replaced it: the earlier folder, with only that, is kept as "
           + keepAside(replaced) + "; the new results are in " + outPath + "\n");
}
}  // namespace

long runFolderFinish() {
  if (!cleanPartial || lockFd < 0) fail(7, "runFolderFinish without runFolderOpen");
  // files put into OUT during the run are not ours to remove
  const std::string why = whyNotReplaceable(outPath);
  if (!why.empty())
    fail(7, "option -out = '" + outPath + "' " + why + " since this run started: it is not replaced, and this run's "
            + "results are not kept; run it again with another -out");
  std::vector<std::string> files;
  std::string foreign;
  if (!runFilesOf(partialPath, files, foreign)) fail(7, "cannot read " + partialPath + ": " + errorText());
  std::string marker = std::string(completeSignature) + "\n";
  for (auto &name : files) if (name != completeMarker) marker += name + "\n";
  const std::string path = partialPath + "/" + completeMarker;
  int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
  bool ok = fd >= 0 && writeAll(fd, marker.data(), marker.size()) && fsync(fd) == 0;
  if (fd >= 0) ok = close(fd) == 0 && ok;
  if (!ok) fail(7, "cannot write " + path + ": " + errorText());
  syncFolder(partialPath);
  // One atomic exchange: OUT is never missing, so no other run can take it meanwhile (the
  // earlier OUT, still locked, lands at OUT.partial.<pid>). Where the file system cannot
  // exchange (renameat2 is Linux's, and not every file system has it), two renames.
  // From the exchange until the earlier folder is gone, a signal is held: now it would leave
  // the earlier results half removed at OUT.partial.<pid> (raised at the end: the results are
  // whole, and the run says so and exits 0). (Held by the handler, not blocked: FreeFEM's
  // threads, OpenBLAS's, may take a signal sent to the process.)
  holdSignals = 1;
  std::string replaced = partialPath;
  if (syscall(SYS_renameat2, AT_FDCWD, partialPath.c_str(), AT_FDCWD, outPath.c_str(), 2 /* RENAME_EXCHANGE */) != 0) {
    replaced = outPath + ".replaced." + std::to_string(getpid());
    if (rename(outPath.c_str(), replaced.c_str()) != 0) fail(7, "cannot move the earlier " + outPath + " aside: " + errorText());
    if (rename(partialPath.c_str(), outPath.c_str()) != 0) {
      const std::string renameWhy = errorText();
      rename(replaced.c_str(), outPath.c_str());
      fail(7, "cannot move " + partialPath + " to " + outPath + ": " + renameWhy);
    }
  }
  cleanPartial = 0; cleanOut = 0; madeParents = 0;  // the results are in OUT: nothing to remove on failure
  tellLauncher("done");
  syncFolder(parentOf(outPath));
  removeReplaced(replaced);
  close(lockFd); lockFd = -1;
  resultsInPlace = 1;
  holdSignals = 0;
  if (heldSignal) raise(heldSignal);
  return 0;
}

}  // namespace runtools
