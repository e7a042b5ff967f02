// spawn.cpp: other programs, without a shell (an argument vector: a value of the user's is never
// read as a command): gmsh, the restart of a 3D run with -Ddimension=3. Also the guard
// against command-line arguments FreeFem++ itself would act on, which the plugin runs as it
// is loaded (docs/design.md, "Command line").
#include "runtools.hpp"
#include <sys/stat.h>
#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <set>
#include <sstream>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace runtools {

namespace {
// An argument vector for exec*: the strings' characters, then the null pointer (args must outlive it)
std::vector<char *> execArguments(const std::vector<std::string> &args) {
  std::vector<char *> argv;
  for (auto &a : args) argv.push_back(const_cast<char *>(a.c_str()));
  argv.push_back(nullptr);
  return argv;
}

// Forks a child that runs start() (system calls only, then an exec; the child exits 127 if
// that returns): the signals' default actions there (defaultSignals), deathSignal when the run
// dies, even from SIGKILL; running names it before the run's handler can take a signal (every
// signal blocked across the fork). Waits for it; returns waitpid's status, or -1 if it could not
// fork. (running stays set: the caller clears it.)
template <class Start> int forkAndWait(volatile pid_t &running, int deathSignal, Start start) {
  const pid_t parent = getpid();
  sigset_t all, before;
  sigfillset(&all);
  sigprocmask(SIG_BLOCK, &all, &before);
  const pid_t child = fork();
  if (child < 0) { sigprocmask(SIG_SETMASK, &before, nullptr); return -1; }
  if (child == 0) {
    defaultSignals();
    sigprocmask(SIG_SETMASK, &before, nullptr);
    prctl(PR_SET_PDEATHSIG, deathSignal);
    if (getppid() != parent) _exit(127);           // the run died before prctl
    start();
    _exit(127);
  }
  running = child;
  sigprocmask(SIG_SETMASK, &before, nullptr);
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {}
  return status;
}

// The child's standard output and error go into log. The child stops with the run: the signal
// handler kills it (runningChild), and PR_SET_PDEATHSIG kills it when the run dies otherwise,
// even from SIGKILL. Returns its exit status, 128 + the signal that ended it, or 127 when it
// could not be started.
int spawnAndWait(const std::string &file, const std::vector<std::string> &args, const std::string &log = "/dev/null") {
  std::vector<char *> argv = execArguments(args);
  const int status = forkAndWait(runningChild, SIGKILL, [&] {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) return;
    dup2(fd, 1); dup2(fd, 2);
    if (fd > 2) close(fd);
    execvp(file.c_str(), argv.data());
  });
  runningChild = 0;
  if (status < 0) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::vector<std::string> ownArguments() {
  std::ifstream f("/proc/self/cmdline", std::ios::binary);
  std::vector<std::string> args;
  std::string arg;
  while (std::getline(f, arg, '\0')) args.push_back(arg);
  return args;
}

// CONTACT_SUITE_RESTART = this process's id marks the restart's own -Ddimension=3
const char *restartVariable = "CONTACT_SUITE_RESTART";

// FreeFem++'s lexer reads an argument that starts with '-' or 'D' and whose first '=' comes
// after its fourth character as a macro definition, named by its characters from the third to
// that '=' ("-DexportSystem=..." but also "Dxcout=..."), wherever it stands
bool freefemMacro(const std::string &a) {
  if (a.empty() || (a[0] != '-' && a[0] != 'D')) return false;
  const size_t equal = a.find('=');
  return equal != std::string::npos && equal > 3;
}
// FreeFem++'s own options (its getprog), read wherever they stand too; run.sh's list is the same
bool freefemOption(const std::string &a, bool &takesValue) {
  static const std::set<std::string> withValue = {"-v", "-f", "-fglut", "-glut", "-gff", "-check_plugin"};
  static const std::set<std::string> alone = {"-nw", "-ng", "-wg", "-md", "-ne", "-cd", "-cdtmp", "-jc", "-ns", "-nowait",
                                              "-nc", "-log", "-wait", "-?"};
  takesValue = withValue.count(a) > 0;
  return takesValue || alone.count(a) > 0;
}

// What a program writes first (its standard output and error, the first line, blanks trimmed),
// run as spawnAndWait runs it, into a temporary file; "" when it cannot start or does not exit 0.
std::string firstLineOf(const std::vector<std::string> &args) {
  char path[] = "/tmp/contact-suite-output.XXXXXX";
  const int fd = mkstemp(path);
  if (fd < 0) return "";
  close(fd);
  rememberTemporary(path);                         // removed if a signal ends the run meanwhile
  const int status = spawnAndWait(args[0], args, path);
  std::ifstream f(path);
  std::string text;
  std::getline(f, text);
  unlink(path);
  forgetTemporary(path);
  if (status != 0) return "";
  const size_t first = text.find_first_not_of(" \t\r"), last = text.find_last_not_of(" \t\r");
  return first == std::string::npos ? "" : text.substr(first, last - first + 1);
}

// A version as one word of the outputs, in printable ASCII: the ends' blanks (a CR) cut, any
// other byte outside '!'..'~' (a blank, a control, a byte of another encoding) made '_', at most
// 100 characters; "unknown" when nothing is left.
std::string versionWord(std::string text) {
  const size_t first = text.find_first_not_of(" \t\r\n"), last = text.find_last_not_of(" \t\r\n");
  text = first == std::string::npos ? "" : text.substr(first, std::min<size_t>(last - first + 1, 100));
  for (char &c : text) if ((unsigned char)c <= ' ' || (unsigned char)c >= 0x7f) c = '_';
  return text.empty() ? "unknown" : text;
}

}  // namespace

// The suite's version (docs/design.md, "Output files"): in a git checkout of repository,
// `git describe --always --dirty` (read-only: --no-optional-locks takes no index lock);
// else the first line of repository/VERSION, the version written at release; else unknown.
std::string suiteVersion(const std::string &repository) {
  std::string version, release;
  const bool checkout = access((repository + "/.git").c_str(), F_OK) == 0;
  if (checkout)
    version = firstLineOf({"git", "--no-optional-locks", "-C", repository, "describe", "--always", "--dirty"});
  if (!version.empty()) return versionWord(version);
  std::ifstream f(repository + "/VERSION");
  std::getline(f, release);
  // a checkout git would not read (another user's: "dubious ownership"), or no git: the release,
  // marked as not checked against the commit
  return versionWord(release) + (checkout ? "+commit-unknown" : "");
}

// gmsh's version, as `gmsh --version` prints it. Starting gmsh costs about 0.07 s, a tenth of
// a small run, and every run records the version: it is kept in cacheFolder/gmsh-version.txt
// with the identity of the gmsh it came from (its path on PATH, the file that resolves to, its
// size, modification time and inode), and asked again when that changes; written whole (a
// temporary file renamed), not at all where the folder cannot be written, and read only as a
// small regular file whose version is one word. Not kept for a gmsh that is a script or
// resolves to another program (a launcher). (A gmsh whose shared library alone is replaced
// keeps the version cached: remove meshes/build/gmsh-version.txt, or the folder.)
std::string gmshVersion(const std::string &cacheFolder) {
  std::string binary, key;
  const char *path = std::getenv("PATH");
  std::stringstream folders(path ? path : "");
  std::string folder;
  while (binary.empty() && std::getline(folders, folder, ':')) {
    const std::string candidate = (folder.empty() ? "." : folder) + "/gmsh";
    if (access(candidate.c_str(), X_OK) != 0) continue;
    binary = candidate;                               // the gmsh a run starts
    // kept only for a program of its own: the file it resolves to is named gmsh... and is an
    // ELF binary (a script or a launcher such as snap may start another gmsh each time)
    char *resolved = realpath(candidate.c_str(), nullptr);
    const std::string target = resolved ? resolved : "";
    std::free(resolved);
    struct ::stat info;
    char magic[4] = {0, 0, 0, 0};
    std::ifstream head(target, std::ios::binary);
    head.read(magic, 4);
    const size_t slash = target.rfind('/');
    if (!target.empty() && ::stat(target.c_str(), &info) == 0 && S_ISREG(info.st_mode) && target.compare(slash + 1, 4, "gmsh") == 0
        && magic[0] == 0x7f && magic[1] == 'E' && magic[2] == 'L' && magic[3] == 'F')
      key = candidate + " " + target + " " + std::to_string((long long)info.st_size) + " " + std::to_string((long long)info.st_mtim.tv_sec)
            + "." + std::to_string((long long)info.st_mtim.tv_nsec) + " " + std::to_string((unsigned long long)info.st_ino);
  }
  const std::string cache = cacheFolder + "/gmsh-version.txt";
  struct ::stat cached;
  if (!key.empty() && !cacheFolder.empty() && ::stat(cache.c_str(), &cached) == 0 && S_ISREG(cached.st_mode) && cached.st_size <= 4096) {
    std::ifstream in(cache);
    std::string cachedKey, cachedVersion;
    if (std::getline(in, cachedKey) && std::getline(in, cachedVersion) && cachedKey == key && !cachedVersion.empty()
        && versionWord(cachedVersion) == cachedVersion && cachedVersion != "unknown")
      return cachedVersion;
  }
  const std::string version = versionWord(firstLineOf({"gmsh", "--version"}));
  if (!key.empty() && !cacheFolder.empty() && version != "unknown" && makeFolders(cacheFolder)) {
    const std::string temporary = cache + "." + std::to_string(getpid());
    std::ofstream out(temporary);
    out << key << "\n" << version << "\n";
    out.close();
    if (!out || std::rename(temporary.c_str(), cache.c_str()) != 0) std::remove(temporary.c_str());
  }
  return version;
}


// An option value of the user's that reads like a macro or an option of FreeFem++ (a file
// named "-DNAME=...") would change the script or run FreeFEM code: every such argument is
// refused (exit 2) as the plugin is loaded, on the script's first line, before any code of it
// runs. The restart's own argument is the one exception.
void checkCommandLine() {
  const std::vector<std::string> args = ownArguments();
  const char *marker = std::getenv(restartVariable);
  const bool restarted = marker && std::string(marker) == std::to_string(getpid());
  unsetenv(restartVariable);                       // not for the processes this run starts
  const bool onRanks = std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr;   // under mpirun (by runLaunchRanks, or by hand)
  size_t script = 0;                               // the script: FreeFEM's first argument that is not its option
  for (size_t i = 1; i < args.size() && script == 0; i++) {
    bool takesValue = false;
    if (freefemOption(args[i], takesValue)) i += takesValue;
    else if (!freefemMacro(args[i])) script = i;
  }
  for (size_t i = 1; i < args.size(); i++) {
    const std::string &a = args[i];
    bool takesValue = false;
    if (restarted && i + 1 == args.size() && a == "-Ddimension=3") continue;
    if (onRanks && i + 2 >= args.size() && (a == "-Ddimension=3" || a == "-DranksMode=1")) continue;
    if (onRanks && (a == "-Ddimension=3" || a == "-DranksMode=1"))   // (by hand under mpirun, not among the last two)
      fail(2, "the argument '" + a + "' under mpirun: give -DranksMode=1 (and -Ddimension=3 for a 3D body) as the last arguments, "
              + "after the suite's options (docs/design.md, \"Across ranks\")");
    if (freefemMacro(a))
      fail(2, "the argument '" + a + "' would be read by FreeFem++ as a macro definition (an argument that starts with '-' or 'D' "
              + "and has an '=' after its fourth character, wherever it stands), which could change the script: the suite refuses it"
              + (i > script && script > 0 && i > 1 && args[i - 1][0] == '-' ? " (as the value of " + args[i - 1] + ": rename that file or folder)" : ""));
    if (script > 0 && i > script && freefemOption(a, takesValue))
      fail(2, "the argument '" + a + "' is an option of FreeFem++ itself, which it reads wherever it stands: give it before the "
              + "script, or, as a value of an option of the suite, rename that file or folder");
  }
}

// ---------------------------------------------------------------- the FreeFEM functions
// gmsh -2 (-3 for a .geo with a Physical Volume) -format msh22 -v 0 -setnumber NAME VALUE ...
// GEO -o OUT; the mesh it writes is removed if the run fails meanwhile
long runGmsh(std::string *const &geo, std::string *const &out, std::string *const &numbers) {
  std::vector<std::string> args = {"gmsh", runGeoDimension(geo) == 3 ? "-3" : "-2", "-format", "msh22", "-v", "0"};
  std::stringstream in(*numbers);
  std::string name, value;
  while (in >> name >> value) { args.push_back("-setnumber"); args.push_back(name); args.push_back(value); }
  args.push_back(*geo); args.push_back("-o"); args.push_back(*out);
  rememberTemporary(*out);
  return spawnAndWait("gmsh", args);
}

// A 3D scene needs the script read again with -Ddimension=3, a macro definition, which only
// the command line can give: this program again, in this process (execv), with the same
// arguments and that one. Returns only if that fails (1).
long runRestartWith(std::string *const &extra) {
  std::vector<std::string> args = ownArguments();
  if (args.empty()) return 1;
  args.push_back(*extra);
  setenv(restartVariable, std::to_string(getpid()).c_str(), 1);
  std::fflush(nullptr);
  execv("/proc/self/exe", execArguments(args).data());
  return 1;
}

// -ranks N: this run again on N MPI ranks, in this process (execvp): mpirun -q -np N [--oversubscribe
// beyond the cores] FreeFem++-mpi -nw, the same arguments, then -DranksMode=1 (edp/solve.edp
// loads the ranks' kernel) and, for a 3D body, -Ddimension=3. mpirun's exit code is the run's.
// Returns only if mpirun cannot be started (1), the run's file of its ranks cannot be made (3),
// more ranks than cores would not fit this machine's available memory at 60 MB each (4), or
// PETSC_OPTIONS names an options file that cannot be read (5).
long runLaunchRanks(const long &count, const long &dimension) {
  if (std::getenv("OMPI_COMM_WORLD_SIZE")) return 2;   // already under mpirun, without -DranksMode=1
  std::vector<std::string> own = ownArguments();
  if (own.empty()) return 1;
  // PETSC_OPTIONS naming an options file that cannot be read: PETSc would fail as it starts, on
  // every rank, with a traceback before the suite could say it
  if (const char *options = std::getenv("PETSC_OPTIONS")) {
    std::istringstream words(options);
    std::string word, file;
    while (words >> word)
      if ((word == "-options_file" || word == "-options_file_yaml") && words >> file && access(file.c_str(), R_OK) != 0) return 5;
  }
  const long cores = sysconf(_SC_NPROCESSORS_ONLN);
  // beyond the cores, every rank is on this machine: each takes at least 60 MB (FreeFEM and
  // PETSc, before the mesh), and ranks beyond its memory would stop it before any could refuse
  if (count > cores) {
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    long long kilobytes = -1;
    while (meminfo >> key) {
      if (key == "MemAvailable:") { meminfo >> kilobytes; break; }
      meminfo.ignore(1 << 10, '\n');
    }
    if (kilobytes >= 0 && count * 60LL * 1024 > kilobytes) return 4;
  }
  std::vector<std::string> args = {"mpirun", "-q", "-np", std::to_string(count)};   // -q: no banner when a rank fails
  if (count > cores) args.push_back("--oversubscribe");
  args.push_back("FreeFem++-mpi");
  args.push_back("-nw");
  for (size_t i = 1; i < own.size(); i++) {
    if (own[i] == "-Ddimension=3" && i + 1 == own.size()) continue;   // (the restart's: given again below)
    args.push_back(own[i]);
  }
  args.push_back("-DranksMode=1");
  if (dimension == 3) args.push_back("-Ddimension=3");
  if (geteuid() == 0) {                            // Open MPI refuses root unless told twice
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  }
  // the ranks write their ids into a file of this run (registerRank): on a signal, the handler
  // stops them at once (stopRanks); mpirun is a child of this run, which waits for it and
  // exits with its code (128 + the signal's number after a signal, as a run of one process)
  const char *tmp = std::getenv("TMPDIR");
  std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/contact-ranks-XXXXXX";
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back(0);
  const int fd = mkstemp(name.data());
  if (fd < 0) return 3;                            // (the run's file cannot be made: TMPDIR)
  unlink(name.data());                             // (held open: it goes with this run, whatever ends it)
  ranksFileFd = fd;
  setenv("CONTACT_SUITE_RANK_IDS", ("/proc/" + std::to_string(getpid()) + "/fd/" + std::to_string(fd)).c_str(), 1);
  std::vector<char *> argv = execArguments(args);
  std::fflush(nullptr);
  // (SIGTERM when this run dies, even by SIGKILL: mpirun stops the ranks)
  const int status = forkAndWait(runningRanks, SIGTERM, [&] { execvp("mpirun", argv.data()); });
  if (status < 0) { close(fd); ranksFileFd = -1; return 1; }
  holdSignals = 1;                                 // (from here on, a signal is held: the end below is the run's, whole)
  runningRanks = 0;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {   // mpirun could not be started
    close(fd); ranksFileFd = -1;
    holdSignals = 0;
    if (heldSignal) raise(heldSignal);
    return 1;
  }
  std::fflush(nullptr);
  std::_Exit(ranksEnded(WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status)));   // (runfolder.cpp)
}

// the first rank of a run that runLaunchRanks started: a line appended to that run's file
// (runfolder.cpp: what it created, and when its results are in place)
void tellLauncher(const std::string &line) {
  const char *file = std::getenv("CONTACT_SUITE_RANK_IDS");
  if (!file || !std::getenv("OMPI_COMM_WORLD_SIZE")) return;
  const int fd = open(file, O_WRONLY | O_APPEND);
  if (fd < 0) return;
  const std::string text = line + "\n";
  if (write(fd, text.data(), text.size()) < 0) {}
  close(fd);
}

// a rank of a run that runLaunchRanks started: its process id appended to that run's file
void registerRank() {
  const char *file = std::getenv("CONTACT_SUITE_RANK_IDS");
  if (!file || !std::getenv("OMPI_COMM_WORLD_SIZE")) return;
  const int fd = open(file, O_WRONLY | O_APPEND);
  if (fd < 0) return;
  const std::string line = std::to_string(getpid()) + "\n";
  if (write(fd, line.data(), line.size()) < 0) {}
  close(fd);
}

}  // namespace runtools
