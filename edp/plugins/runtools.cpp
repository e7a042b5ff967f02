// runtools.cpp: what a run needs from the operating system, as a FreeFEM plugin (load
// "runtools"), built by ./run.sh into edp/plugins/build/ like the kernel. No shell ever sees
// a value of the user's: files and folders are handled by system calls, gmsh is started with
// an argument vector. (FreeFEM's own cerr writes to the standard output, its exit() prints
// trace lines, its ofstream hides write errors, and it has no wall clock.)
//
// The run folder (docs/design.md, section "Output files"). A run writes OUT.partial.<pid>/,
// holding a lock on OUT/ (flock on the folder itself, created empty if needed) from start to
// end; at the end it writes OUT.partial.<pid>/run.complete, listing its files, and swaps the
// folders in one atomic exchange (renameat2; else OUT -> OUT.replaced.<pid>, OUT.partial.<pid>
// -> OUT), then removes from the replaced one the files its run.complete lists, and the folder
// if that empties it (a file of the user's that arrived just before the swap is kept, as
// OUT.kept.<pid>).
// An existing OUT/ is replaced only if it is empty or holds exactly the files its own
// run.complete lists; a second run on a locked OUT/ is refused. On an error (runError) or
// a signal (SIGINT, SIGTERM, SIGHUP, ..., and those of a crash: SIGSEGV, SIGBUS, SIGABRT, ...),
// the run removes what it created and nothing else.
//
// FreeFEM functions (exit codes: 2 option, 3 scene or mesh data, 7 output folder or file):
//   runError(int code, string message)   remove what the run created, "error: message" on
//       stderr (nothing when empty), exit with code (no FreeFEM trace)
//   runWallClock()                       wall-clock seconds (steady clock)
//   runProcessId()                       this process's id
//   runFileReadable(string path)         1 if path is a regular file this process can read
//   runChecksum(string path)             the POSIX cksum of a file (-1: unreadable)
//   runByteOrderMark(string path)        3 if the file starts with a UTF-8 byte order mark, else 0
//   runOnlyCarriageReturns(string path)  1 if a text file has CR line ends only
//   runControlCharacter(string text)     1 if text holds a control character or a line separator
//   runNotUtf8(string text)              1 if text is not valid UTF-8
//   runEnvironmentSeconds(string name)   the seconds an environment variable gives, -1 if unset
//   runFolderOpen(string out)            lock OUT, check it may be replaced, make OUT.partial.<pid>
//   runFileComplete(string path, int lines)   the file has exactly that many complete lines,
//       and is on the disk (fsync); exit 7 otherwise (a full disk, an I/O error)
//   runCopyFile(string from, string to)  0, or 1 if it cannot be copied completely
//   runCreateFile(string path)           an empty file (exit 7 if it cannot be made)
//   runRemoveFile(string path)           remove a file this run wrote (a temporary copy)
//   runRename(string from, string to)    0, or 1
//   runMakeFolders(string path)          mkdir -p; 0, or 1
//   runFolderFinish()                    run.complete, then OUT.partial.<pid> -> OUT
//   runGmsh(string geo, string out, string numbers)  gmsh -2 (-3 for a 3D .geo) -format msh22 -v 0
//       -setnumber NAME VALUE ... geo -o out; its exit status (127: no gmsh)
//   runCheckMesh(string in, string out, string required, string dirichlet, string what,
//       int fatal)   check a gmsh MSH 2.2 file before FreeFEM reads it (see checkMesh below)
//       and write it to out (unless out is ""), clockwise triangles reoriented; on a problem: exit 3 with
//       "what: why" (fatal), or return 1; exit 7 if out cannot be written
//   runMeshExtentRatio()                 1e8: the largest extent / shortest edge a mesh may have
//   runMeshDimension(string path)        3 if a mesh file has tetrahedra, 2 if not, 0 if unreadable
//   runGeoDimension(string path)         3 if a .geo defines a Physical Volume, else 2
//   runMeshLacksLabel(string path, string labels)   the first label no boundary element carries, or -1
//   runRestartWith(string arg)           this program again in this process, one argument more
//   runSameDomain(string a, string b)    compare.edp: exit 2 unless two checked meshes cover one
//       domain with the same boundary labels
#include "ff++.hpp"
#include "AFunction_ext.hpp"
#include <algorithm>
#include <array>
#include <cerrno>
#include <cfloat>
#include <climits>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dirent.h>
#include <fcntl.h>
#include <fstream>
#include <iostream>
#include <map>
#include <initializer_list>
#include <set>
#include <sstream>
#include <spawn.h>
#include <string>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

extern char **environ;

namespace {

const char *completeMarker = "run.complete";
const char *completeSignature =
  "# run.complete: written last by edp/solve.edp, once every file listed below was complete and every end-of-run check had passed";

// ---------------------------------------------------------------- the run folder's state
// Kept in fixed buffers too, for the signal handler (which may only make system calls).
struct RunFolder {
  std::string out, partial;
  int lock = -1;              // flock on OUT while the run holds it
  bool createdOut = false;    // OUT did not exist: made empty here, removed on failure
  bool partialMade = false;   // OUT.partial.<pid> exists and is ours
};
RunFolder RF;
char partialPathC[4096], outPathC[4096];
// the parent folders of OUT made by this run: prefixes of one path, of these lengths (outermost
// first; a path of 4095 bytes has at most 2048 folders)
char madeParentPathC[4096];
size_t madeParentLength[2048];
char temporaryC[4096];                               // a file this run writes outside OUT (gmsh's mesh)
volatile sig_atomic_t cleanPartial = 0, cleanOut = 0, madeParents = 0, haveTemporary = 0;
volatile pid_t runningChild = 0;                     // a running gmsh or pilot run

void syncBuffers() {
  cleanPartial = 0; cleanOut = 0;
  std::snprintf(partialPathC, sizeof partialPathC, "%s", RF.partial.c_str());
  std::snprintf(outPathC, sizeof outPathC, "%s", RF.out.c_str());
  cleanOut = RF.createdOut && RF.lock >= 0;
  cleanPartial = RF.partialMade;
}

struct Dirent64 { std::uint64_t ino; std::int64_t off; unsigned short reclen; unsigned char type; char name[]; };

// Remove the folder `name` under parent and all it holds, with system calls only (the signal
// handler uses it). Entries are read again after each pass: deleting while reading may skip.
void removeTreeAt(int parent, const char *name, int depth) {
  int fd = openat(parent, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW);
  if (fd < 0) { unlinkat(parent, name, 0); return; }
  char buffer[8192];
  for (int pass = 0; pass < 4; pass++) {
    lseek(fd, 0, SEEK_SET);
    bool any = false;
    long n;
    while ((n = syscall(SYS_getdents64, fd, buffer, sizeof buffer)) > 0)
      for (long pos = 0; pos < n;) {
        Dirent64 *d = reinterpret_cast<Dirent64 *>(buffer + pos);
        pos += d->reclen;
        if (std::strcmp(d->name, ".") == 0 || std::strcmp(d->name, "..") == 0) continue;
        any = true;
        if (d->type == DT_DIR && depth < 8) removeTreeAt(fd, d->name, depth + 1);
        else if (unlinkat(fd, d->name, 0) != 0 && errno == EISDIR && depth < 8) removeTreeAt(fd, d->name, depth + 1);
      }
    if (!any) break;
  }
  close(fd);
  unlinkat(parent, name, AT_REMOVEDIR);
}
void removeTree(const char *path) { removeTreeAt(AT_FDCWD, path, 0); }

// what the run created, and only that
void cleanUp() {
  if (runningChild > 0) { kill(runningChild, SIGKILL); runningChild = 0; }   // our child; its file is removed below
  if (haveTemporary) { unlink(temporaryC); haveTemporary = 0; }
  if (cleanPartial) removeTree(partialPathC);
  if (cleanOut) rmdir(outPathC);                    // only if still empty
  for (int k = madeParents - 1; k >= 0; k--) {     // only those still empty
    char folder[sizeof madeParentPathC];
    for (size_t i = 0; i < madeParentLength[k]; i++) folder[i] = madeParentPathC[i];
    folder[madeParentLength[k]] = 0;
    rmdir(folder);
  }
  cleanPartial = 0; cleanOut = 0; madeParents = 0;
}

// the signals of a crash (a bug, or too little memory: FreeFEM does not check every allocation)
const char *crashName(int signal) {
  switch (signal) {
    case SIGSEGV: return "SIGSEGV"; case SIGBUS: return "SIGBUS"; case SIGFPE: return "SIGFPE"; case SIGILL: return "SIGILL";
    case SIGABRT: return "SIGABRT"; case SIGTRAP: return "SIGTRAP"; case SIGSYS: return "SIGSYS"; default: return nullptr;
  }
}
void say(const char *text) { if (write(2, text, std::strlen(text)) < 0) {} }

// system calls only; then the signal's default action, so that the exit status is 128 + signal
void onSignal(int signal) {
  const bool removed = cleanPartial;
  cleanUp();
  if (signal == SIGXFSZ) {                         // a file could not be written: the output folder's exit code
    say("error: a file of the run grew past the file-size limit (ulimit -f; SIGXFSZ)");
    say(removed ? ": the run removed its unfinished output folder\n" : "\n");
    _exit(7);
  }
  const char *crash = crashName(signal);
  if (crash) { say("error: the run crashed ("); say(crash); say(": a bug, or too little memory)"); }
  else say("interrupted");
  say(removed ? ": the run removed its unfinished output folder\n" : "\n");
  struct sigaction action = {};
  action.sa_handler = SIG_DFL;
  sigaction(signal, &action, nullptr);
  raise(signal);                                   // blocked in here: delivered on return
}

// every signal that ends a process, from the start (an alternate stack: a stack overflow
// can be handled too); a closed standard output (SIGPIPE) does not stop a run
void installSignalHandlers() {
  static char alternate[1 << 18];                  // removeTree's buffers, 8 folder levels deep
  stack_t stack = {};
  stack.ss_sp = alternate;
  stack.ss_size = sizeof alternate;
  sigaltstack(&stack, nullptr);
  struct sigaction action = {};
  action.sa_handler = onSignal;
  action.sa_flags = SA_ONSTACK | SA_RESTART;
  sigemptyset(&action.sa_mask);
  for (int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGPROF, SIGXCPU, SIGXFSZ,
                     SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS})
    sigaction(signal, &action, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
}

// FreeFEM points std::cerr at the standard output: write to file descriptor 2 itself
void toStderr(const std::string &text) {
  std::fflush(nullptr);
  std::fputs(text.c_str(), stderr);
  std::fflush(stderr);
}

// the length of the UTF-8 sequence that starts at s[i] (1 to 4 bytes), or 0 if the bytes there
// are not one (a stray continuation byte, an overlong form, a surrogate, beyond U+10FFFF)
size_t utf8Length(const std::string &s, size_t i) {
  const unsigned char c = s[i];
  if (c < 0x80) return 1;
  const size_t n = c >= 0xC2 && c <= 0xDF ? 2 : (c >= 0xE0 && c <= 0xEF ? 3 : (c >= 0xF0 && c <= 0xF4 ? 4 : 0));
  if (n == 0 || i + n > s.size()) return 0;
  for (size_t k = 1; k < n; k++) if (((unsigned char)s[i + k] & 0xC0) != 0x80) return 0;
  const unsigned char second = s[i + 1];
  if ((c == 0xE0 && second < 0xA0) || (c == 0xED && second > 0x9F) || (c == 0xF0 && second < 0x90) || (c == 0xF4 && second > 0x8F))
    return 0;
  return n;
}
bool validUtf8(const std::string &s) {
  for (size_t i = 0; i < s.size();) { const size_t n = utf8Length(s, i); if (n == 0) return false; i += n; }
  return true;
}

// A message as it may be shown on a terminal: bytes that are not UTF-8 and control characters
// (but line ends) as \xHH, a word (a run without spaces: a value, a path) longer than longWord
// bytes cut in its middle, with its length, and a message longer than longMessage bytes (a
// value of many words) too: a megabyte value is not echoed.
const size_t longWord = 160, longMessage = 1200;
std::string shown(const std::string &text) {
  std::string out, word;
  auto flush = [&]() {
    if (word.size() > longWord) {
      size_t head = 100, tail = 40;
      while (head > 0 && ((unsigned char)word[head] & 0xC0) == 0x80) head--;   // cut between characters
      while (tail > 0 && ((unsigned char)word[word.size() - tail] & 0xC0) == 0x80) tail--;
      word = word.substr(0, head) + "...(" + std::to_string(word.size()) + " bytes)..." + word.substr(word.size() - tail);
    }
    out += word; word.clear();
  };
  for (size_t i = 0; i < text.size();) {
    const unsigned char c = text[i];
    const size_t n = utf8Length(text, i);
    if (c == ' ' || c == '\n') { flush(); out += (char)c; i++; continue; }
    if (n == 0 || c < 0x20 || c == 0x7F) {
      char hex[8]; std::snprintf(hex, sizeof hex, "\\x%02X", (unsigned)c); word += hex; i++; continue;
    }
    word += text.substr(i, n); i += n;
  }
  flush();
  if (out.size() > longMessage) {                    // a long value of many words: the middle cut
    size_t head = 800, tail = 300;
    while (head > 0 && ((unsigned char)out[head] & 0xC0) == 0x80) head--;
    while (tail > 0 && ((unsigned char)out[out.size() - tail] & 0xC0) == 0x80) tail--;
    out = out.substr(0, head) + " ...(" + std::to_string(out.size() - head - tail) + " bytes cut)... " + out.substr(out.size() - tail);
  }
  return out;
}

[[noreturn]] void fail(int code, const std::string &message) {
  std::cout.flush();
  cleanUp();
  if (!message.empty()) toStderr("error: " + shown(message) + "\n");
  std::fflush(nullptr);
  std::_Exit(code);
}

long runError(const long &code, string *const &message) { fail((int)code, *message); }
// one line on the standard error (progress, the Newton log), unbuffered
long runNote(string *const &message) {
  toStderr(shown(*message) + "\n");
  return 0;
}
// the number of seconds an environment variable gives (a number >= 0), or -1 when it is not set
// or empty; any other value: exit 2 naming it
double runEnvironmentSeconds(string *const &name) {
  const char *text = std::getenv(name->c_str());
  if (!text || !*text) return -1;
  char *end = nullptr;
  const double value = std::strtod(text, &end);
  if (!*text || *end || !std::isfinite(value) || value < 0)
    fail(2, "the environment variable " + *name + " = '" + text + "' is not a number of seconds >= 0");
  return value;
}
// 1 if a text is not valid UTF-8 (a file or folder name that the suite's own tools could not
// read back, nor show)
long runNotUtf8(string *const &text) { return validUtf8(*text) ? 0 : 1; }

double runWallClock() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
long runProcessId() { return (long)getpid(); }

long runFileReadable(string *const &path) {
  struct stat status;
  return stat(path->c_str(), &status) == 0 && S_ISREG(status.st_mode) && access(path->c_str(), R_OK) == 0;
}

// POSIX cksum (CRC-32, polynomial 0x04C11DB7, then the length), as `cksum FILE` prints it
long long posixChecksum(const std::string &path) {
  std::uint32_t table[256];
  for (std::uint32_t i = 0; i < 256; i++) {
    std::uint32_t c = i << 24;
    for (int k = 0; k < 8; k++) c = (c & 0x80000000u) ? (c << 1) ^ 0x04C11DB7u : c << 1;
    table[i] = c;
  }
  std::ifstream f(path, std::ios::binary);
  if (!f) return -1;
  std::uint32_t crc = 0;
  unsigned long long length = 0;
  char buffer[65536];
  while (f.read(buffer, sizeof buffer) || f.gcount() > 0) {
    for (std::streamsize i = 0; i < f.gcount(); i++) crc = (crc << 8) ^ table[((crc >> 24) ^ (unsigned char)buffer[i]) & 0xFF];
    length += f.gcount();
  }
  for (unsigned long long n = length; n > 0; n >>= 8) crc = (crc << 8) ^ table[((crc >> 24) ^ (n & 0xFF)) & 0xFF];
  return (long long)(~crc);
}
long runChecksum(string *const &path) { return (long)posixChecksum(*path); }
// 1 if the text file has carriage returns but no line feed (old Mac line ends): FreeFEM's
// getline would read it as one line
long runOnlyCarriageReturns(string *const &path) {
  std::ifstream f(*path, std::ios::binary);
  bool cr = false;
  char ch;
  while (f.get(ch)) { if (ch == '\n') return 0; cr = cr || ch == '\r'; }
  return cr ? 1 : 0;
}
long runByteOrderMark(string *const &path) {
  std::ifstream f(*path, std::ios::binary);
  char head[3] = {0, 0, 0};
  f.read(head, 3);
  return f.gcount() == 3 && std::memcmp(head, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
}

std::string errorText() { return std::strerror(errno); }

// a control character (below 0x20, 0x7F, or U+0080 to U+009F in UTF-8, with U+0085, the next
// line) or a Unicode line or paragraph separator (U+2028, U+2029): each ends a line for some
// reader (Python's splitlines, for one), so no option value may hold one
bool hasControlCharacter(const std::string &text) {
  for (size_t i = 0; i < text.size(); i++) {
    const unsigned char c = text[i], next = i + 1 < text.size() ? text[i + 1] : 0, third = i + 2 < text.size() ? text[i + 2] : 0;
    if (c < 0x20 || c == 0x7F || (c == 0xC2 && next >= 0x80 && next <= 0x9F) || (c == 0xE2 && next == 0x80 && (third == 0xA8 || third == 0xA9)))
      return true;
  }
  return false;
}
long runControlCharacter(string *const &text) { return hasControlCharacter(*text) ? 1 : 0; }

// the entries of a folder (no . and ..), and whether each is a folder; false if unreadable
bool listFolder(const std::string &path, std::vector<std::pair<std::string, bool>> &entries) {
  entries.clear();
  int fd = open(path.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return false;
  char buffer[8192];
  long n;
  while ((n = syscall(SYS_getdents64, fd, buffer, sizeof buffer)) > 0)
    for (long pos = 0; pos < n;) {
      Dirent64 *d = reinterpret_cast<Dirent64 *>(buffer + pos);
      pos += d->reclen;
      if (std::strcmp(d->name, ".") && std::strcmp(d->name, "..")) entries.push_back({d->name, d->type == DT_DIR});
    }
  close(fd);
  std::sort(entries.begin(), entries.end());
  return n == 0;
}

// mkdir -p; with record, the folders it made are removed again if the run fails
bool makeFolders(const std::string &path, bool record = false) {
  std::string partial;
  std::stringstream in(path);
  std::string part;
  if (!path.empty() && path[0] == '/') partial = "/";
  while (std::getline(in, part, '/')) {
    if (part.empty()) continue;
    partial += part;
    if (mkdir(partial.c_str(), 0777) == 0) {
      if (record && partial.size() < sizeof madeParentPathC && madeParents < 2048) {
        std::memcpy(madeParentPathC, partial.c_str(), partial.size() + 1);   // extends the folders made before
        madeParentLength[madeParents] = partial.size();
        madeParents = madeParents + 1;
      }
    }
    else if (errno != EEXIST) return false;
    partial += "/";
  }
  struct stat status;
  return stat(path.c_str(), &status) == 0 && S_ISDIR(status.st_mode);
}
long runMakeFolders(string *const &path) { return makeFolders(*path) ? 0 : 1; }

// A run's files: plain names, and those of its one subfolder, vtk/ (-vtk N), as "vtk/NAME".
const char *seriesFolder = "vtk";
bool plainName(const std::string &name) { return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos; }
bool runFileName(const std::string &name) {
  const size_t slash = name.find('/');
  return slash == std::string::npos ? plainName(name) : name.substr(0, slash) == seriesFolder && plainName(name.substr(slash + 1));
}
// The figures that plots/run_figures.py and plots/animate.py draw into OUT/figures/, listed by
// them in OUT/figures/figures.list (a signature line, then the names): they go with their run.
const char *figuresFolder = "figures", *figuresList = "figures.list";
const char *figuresSignature = "# figures.list: the figures plots/ of this suite drew here; they go with the run's results";
// the only names the tools draw (the same list as FIGURES_DRAWN in plots/suite.py; a test keeps them equal): a list that
// names any other file is not followed
bool figuresDrawn(const std::string &name) {
  static const std::set<std::string> drawn = {"contact_at_T.png", "histories.png", "deformed.png", "zone_map.png",
                                               "compare_contact.png", "animation.gif", "animation.mp4"};
  return drawn.count(name) > 0;
}
std::set<std::string> figuresListed(const std::string &folder) {
  std::set<std::string> listed;
  std::ifstream f(folder + "/" + figuresFolder + "/" + figuresList);
  std::string line;
  if (!f || !std::getline(f, line) || line != figuresSignature) return listed;
  while (std::getline(f, line)) if (figuresDrawn(line)) listed.insert(line);
  return listed;
}
void removeFigures(const std::string &folder) {
  const std::string figures = folder + "/" + figuresFolder;
  for (const std::string &name : figuresListed(folder)) unlink((figures + "/" + name).c_str());
  unlink((figures + "/" + figuresList).c_str());
  rmdir(figures.c_str());                          // only if empty
}

// the files of a folder as run.complete names them (files of vtk/ as "vtk/NAME"); foreign gets
// what a run never writes (other folders, folders inside vtk/, files in figures/ that its
// figures.list does not name)
bool runFilesOf(const std::string &folder, std::vector<std::string> &files, std::string &foreign) {
  std::vector<std::pair<std::string, bool>> entries, inside;
  if (!listFolder(folder, entries)) return false;
  for (auto &e : entries) {
    if (!e.second) { files.push_back(e.first); continue; }
    if (e.first == figuresFolder && listFolder(folder + "/" + e.first, inside)) {
      const std::set<std::string> drawn = figuresListed(folder);
      for (auto &f : inside)
        if (f.second || (f.first != figuresList && !drawn.count(f.first))) foreign += (foreign.empty() ? "" : ", ") + e.first + "/" + f.first;
      continue;
    }
    if (e.first != seriesFolder || !listFolder(folder + "/" + e.first, inside)) { foreign += (foreign.empty() ? "" : ", ") + e.first; continue; }
    for (auto &f : inside)
      if (f.second) foreign += (foreign.empty() ? "" : ", ") + e.first + "/" + f.first;
      else files.push_back(e.first + "/" + f.first);
  }
  return true;
}

// the file names a folder's run.complete lists; false if it has none, or one without this
// suite's signature line
bool completeListing(const std::string &folder, std::set<std::string> &listed) {
  listed.clear();
  std::ifstream f(folder + "/" + completeMarker);
  std::string line;
  if (!f || !std::getline(f, line) || line != completeSignature) return false;
  while (std::getline(f, line))
    if (runFileName(line)) listed.insert(line);
  return true;
}

// "" if the folder may be replaced by a run (empty, or exactly the files of its
// run.complete), else why not
std::string whyNotReplaceable(const std::string &folder) {
  std::vector<std::pair<std::string, bool>> entries;
  if (!listFolder(folder, entries)) return "cannot be read (" + errorText() + ")";
  if (entries.empty()) return "";
  std::set<std::string> listed;
  if (!completeListing(folder, listed)) {
    for (auto &e : entries)
      if (e.first == "summary.txt")
        return "holds a summary.txt but no run.complete (results of an older version of this suite, or of a run "
               "that did not finish)";
    return "is a folder that does not hold results of this suite (no run.complete)";
  }
  std::string foreign;
  std::vector<std::string> files;
  if (!runFilesOf(folder, files, foreign)) return "cannot be read (" + errorText() + ")";
  for (auto &name : files)
    if (name != completeMarker && !listed.count(name)) foreign += (foreign.empty() ? "" : ", ") + name;
  if (!foreign.empty()) return "holds files that this suite did not write there (" + foreign + ")";
  return "";
}

// the processes whose OUT.partial.<pid> folders exist beside OUT
std::string otherRuns(const std::string &out) {
  std::string parent = ".", base = out;
  const size_t slash = out.rfind('/');
  if (slash != std::string::npos) { parent = slash == 0 ? "/" : out.substr(0, slash); base = out.substr(slash + 1); }
  std::vector<std::pair<std::string, bool>> entries;
  listFolder(parent, entries);
  std::string found;
  const std::string prefix = base + ".partial.";
  for (auto &e : entries)
    if (e.second && e.first.compare(0, prefix.size(), prefix) == 0) {
      const std::string pid = e.first.substr(prefix.size());
      const long number = std::atol(pid.c_str());
      if (number > 0 && number != getpid() && kill((pid_t)number, 0) == 0) found += (found.empty() ? "" : ", ") + pid;
    }
  return found.empty() ? "" : " (process " + found + ")";
}

// a note on stderr for each OUT.partial.<pid> of a process that no longer runs (killed with
// SIGKILL): the suite never removes what it did not create in this run
void noteLeftovers(const std::string &out) {
  std::string parent = ".", base = out;
  const size_t slash = out.rfind('/');
  if (slash != std::string::npos) { parent = slash == 0 ? "/" : out.substr(0, slash); base = out.substr(slash + 1); }
  std::vector<std::pair<std::string, bool>> entries;
  listFolder(parent, entries);
  const std::string prefix = base + ".partial.";
  for (auto &e : entries)
    if (e.second && e.first.compare(0, prefix.size(), prefix) == 0) {
      const long number = std::atol(e.first.substr(prefix.size()).c_str());
      if (number > 0 && number != getpid() && kill((pid_t)number, 0) != 0 && errno == ESRCH)
        toStderr("note: " + parent + "/" + e.first + " is left from a run that was killed (process " + std::to_string(number) +
                 " no longer runs); it holds no results, and you may delete it\n");
    }
}

long runFolderOpen(string *const &outText) {
  std::string out = *outText;
  while (out.size() > 1 && out.back() == '/') out.pop_back();
  const size_t slash = out.rfind('/');
  const std::string base = slash == std::string::npos ? out : out.substr(slash + 1);
  if (out == "/" || base == "." || base == ".." || base.empty() || out[0] == '-')
    fail(2, "option -out = '" + *outText + "' is not a usable folder name (give a new or results folder, e.g. results/run)");
  if (hasControlCharacter(out)) fail(2, "option -out holds a control character or a line separator: give a plain folder name");
  if (!validUtf8(out)) fail(2, "option -out = '" + out + "' is not valid UTF-8: give a folder name the suite's tools can read back");
  // the longest path the run writes, OUT.partial.<pid>/vtk/fields_NNNNNN.vtu, within the system's limits
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
  RF = RunFolder();
  RF.out = out;
  RF.partial = out + ".partial." + std::to_string(getpid());
  const std::string parent = slash == std::string::npos ? "." : (slash == 0 ? "/" : out.substr(0, slash));
  madeParents = 0;
  if (!makeFolders(parent, true))
    fail(7, "cannot create the output folder " + RF.partial + " (option -out = " + out + "): " + errorText()
            + (errno == EEXIST || errno == ENOTDIR ? " (a part of that path is a file)" : ""));
  struct stat parentStatus;
  if (stat(out.c_str(), &status) == 0 && stat(parent.c_str(), &parentStatus) == 0 && status.st_dev != parentStatus.st_dev)
    fail(7, "option -out = '" + out + "' is a mount point: the suite replaces OUT whole; give a folder inside it");
  // this run's folder first: a run that holds the lock on OUT can always be named by it
  if (mkdir(RF.partial.c_str(), 0777) != 0)
    fail(7, "cannot create the output folder " + RF.partial + " (option -out = " + out + "): " + errorText());
  RF.partialMade = true;
  syncBuffers();
  for (int attempt = 0; attempt < 2; attempt++) {
    if (stat(out.c_str(), &status) == 0) {
      const std::string why = whyNotReplaceable(out);
      if (!why.empty()) fail(7, "option -out = '" + out + "' " + why + ": it is not replaced; choose another -out");
      break;
    }
    if (mkdir(out.c_str(), 0777) == 0) { RF.createdOut = true; break; }
    if (errno != EEXIST) fail(7, "cannot create the output folder " + out + ": " + errorText());
  }
  // the lock, on the folder that is OUT once we hold it (another run may swap OUT meanwhile)
  for (int attempt = 0;; attempt++) {
    RF.lock = open(out.c_str(), O_RDONLY | O_DIRECTORY);
    if (RF.lock < 0) fail(7, "cannot open the output folder " + out + ": " + errorText());
    if (flock(RF.lock, LOCK_EX | LOCK_NB) != 0) {
      const int lockError = errno;
      close(RF.lock); RF.lock = -1;
      if (lockError == EWOULDBLOCK)
        fail(7, "option -out = '" + out + "': another run" + otherRuns(out) + " is writing it; wait for it, or choose another -out");
      fail(7, "cannot lock the output folder " + out + ": " + std::strerror(lockError));
    }
    struct stat locked, now;
    if (fstat(RF.lock, &locked) == 0 && stat(out.c_str(), &now) == 0 && locked.st_ino == now.st_ino && locked.st_dev == now.st_dev)
      break;
    close(RF.lock); RF.lock = -1;
    if (attempt == 10) fail(7, "option -out = '" + out + "': other runs keep replacing it; wait for them, or choose another -out");
  }
  syncBuffers();
  // under the lock: nobody else writes OUT now, but someone may have before we held it
  if (!RF.createdOut) {
    const std::string why = whyNotReplaceable(out);
    if (!why.empty()) fail(7, "option -out = '" + out + "' " + why + ": it is not replaced; choose another -out");
  }
  if (!RF.createdOut && stat(out.c_str(), &status) == 0) chmod(RF.partial.c_str(), status.st_mode & 07777);   // OUT's mode
  noteLeftovers(out);
  return 0;
}

// 1 if the cached file's POSIX checksum is the number its NAME.cksum holds (0 when either is
// missing, unreadable, or holds anything else)
long runCacheIntact(string *const &path) {
  std::ifstream f(*path + ".cksum");
  long long recorded = -1;
  if (!(f >> recorded) || recorded < 0) return 0;
  std::string rest;
  if (f >> rest) return 0;
  return posixChecksum(*path) == recorded ? 1 : 0;
}

// the line feeds of an open file read to its end, and its last character ('\n' if empty);
// -1 on a read error
long lineFeeds(int fd, char &last) {
  long count = 0;
  char buffer[65536];
  ssize_t n;
  last = '\n';
  while ((n = read(fd, buffer, sizeof buffer)) > 0) {
    for (ssize_t i = 0; i < n; i++) count += buffer[i] == '\n';
    last = buffer[n - 1];
  }
  return n == 0 ? count : -1;
}

// the line feeds of a file (-1 if it cannot be read)
long runFileLines(string *const &path) {
  int fd = open(path->c_str(), O_RDONLY);
  if (fd < 0) return -1;
  char last;
  const long count = lineFeeds(fd, last);
  close(fd);
  return count;
}

// a file this run wrote: exactly `lines` complete lines, then on the disk
long runFileComplete(string *const &path, const long &lines) {
  int fd = open(path->c_str(), O_RDONLY);
  if (fd < 0) fail(7, "cannot read back " + *path + ": " + errorText());
  char last;
  const long count = lineFeeds(fd, last);
  const bool readOk = count >= 0, synced = fsync(fd) == 0;
  const std::string why = errorText();
  close(fd);
  if (!readOk || !synced) fail(7, "cannot write " + *path + ": " + why);
  if (count != lines || last != '\n')
    fail(7, "cannot write " + *path + " completely: " + std::to_string(count) + " of " + std::to_string(lines)
            + " lines are there (is the disk full?)");
  return 0;
}

bool copyFile(const std::string &from, const std::string &to) {
  int in = open(from.c_str(), O_RDONLY);
  if (in < 0) return false;
  int out = open(to.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
  if (out < 0) { close(in); return false; }
  char buffer[65536];
  ssize_t n;
  bool ok = true;
  while (ok && (n = read(in, buffer, sizeof buffer)) > 0)
    for (ssize_t done = 0; ok && done < n;) {
      ssize_t w = write(out, buffer + done, n - done);
      if (w <= 0) ok = false; else done += w;
    }
  ok = ok && n == 0 && fsync(out) == 0;
  close(in);
  ok = close(out) == 0 && ok;
  if (!ok) unlink(to.c_str());
  return ok;
}
long runCopyFile(string *const &from, string *const &to) { return copyFile(*from, *to) ? 0 : 1; }
// an empty file, before FreeFEM's ofstream writes it (FreeFEM stops with its own error when it
// cannot open a file: no inode left, a path too long, ...)
long runCreateFile(string *const &path) {
  const int fd = open(path->c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
  if (fd < 0 || close(fd) != 0) fail(7, "cannot create " + *path + ": " + errorText());
  return 0;
}
void forgetTemporary(const std::string &path) { if (haveTemporary && path == temporaryC) haveTemporary = 0; }
long runRemoveFolder(string *const &path) { removeTree(path->c_str()); return 0; }
long runRemoveFile(string *const &path) { forgetTemporary(*path); return unlink(path->c_str()) == 0 ? 0 : 1; }
long runRename(string *const &from, string *const &to) {
  const bool ok = rename(from->c_str(), to->c_str()) == 0;
  if (ok) forgetTemporary(*from);
  return ok ? 0 : 1;
}

void syncFolder(const std::string &path) {
  int fd = open(path.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd >= 0) { fsync(fd); close(fd); }
}

// The earlier OUT once the new one has taken its place: its marker, the files the marker
// lists, then the folder. OUT was checked just before the exchange, but a file of the user's
// may have been put there since: then the folder is not empty, and it is kept, as
// OUT.kept.<pid>, with a note. No file that the marker does not list is ever removed.
// the earlier folder, when something stays in it: OUT.kept.<pid> (or where it is, if taken)
std::string keepAside(const std::string &replaced) {
  const std::string kept = RF.out + ".kept." + std::to_string(getpid());
  return syscall(SYS_renameat2, AT_FDCWD, replaced.c_str(), AT_FDCWD, kept.c_str(), 1 /* RENAME_NOREPLACE */) == 0 ? kept : replaced;
}
void removeReplaced(const std::string &replaced) {
  std::set<std::string> listed;
  if (completeListing(replaced, listed)) unlink((replaced + "/" + completeMarker).c_str());   // first: never complete-looking
  std::string stuck, stuckWhy;                     // listed files that could not be removed
  for (const std::string &name : listed)
    if (unlink((replaced + "/" + name).c_str()) != 0 && errno != ENOENT) {
      if (stuck.empty()) stuckWhy = errorText();
      stuck += (stuck.empty() ? "" : ", ") + name;
    }
  rmdir((replaced + "/" + seriesFolder).c_str());  // only if empty
  removeFigures(replaced);
  if (rmdir(replaced.c_str()) == 0) return;
  if (!stuck.empty()) {
    toStderr("note: the earlier results could not all be removed (" + stuck + ": " + stuckWhy + "); they are kept in "
             + keepAside(replaced) + "; the new ones are in " + RF.out + "\n");
    return;
  }
  std::vector<std::pair<std::string, bool>> entries;
  if (errno != ENOTEMPTY && errno != EEXIST) {
    toStderr("note: the earlier results could not all be removed from " + replaced + " (" + errorText() + "); the new ones are in "
             + RF.out + "\n");
    return;
  }
  listFolder(replaced, entries);
  std::string names;
  for (auto &e : entries) names += (names.empty() ? "" : ", ") + e.first;
  toStderr("note: " + names + " appeared in " + RF.out + " while this run replaced it: the earlier folder, with only that, is kept as "
           + keepAside(replaced) + "; the new results are in " + RF.out + "\n");
}

long runFolderFinish() {
  if (!RF.partialMade || RF.lock < 0) fail(7, "runFolderFinish without runFolderOpen");
  // OUT again: files someone put there during the run are not ours to remove
  const std::string why = whyNotReplaceable(RF.out);
  if (!why.empty())
    fail(7, "option -out = '" + RF.out + "' " + why + " since this run started: it is not replaced, and this run's "
            + "results are not kept; run it again with another -out");
  std::vector<std::string> files;
  std::string foreign;
  if (!runFilesOf(RF.partial, files, foreign)) fail(7, "cannot read " + RF.partial + ": " + errorText());
  std::string marker = std::string(completeSignature) + "\n";
  for (auto &name : files) if (name != completeMarker) marker += name + "\n";
  const std::string path = RF.partial + "/" + completeMarker;
  int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
  bool ok = fd >= 0;
  for (size_t done = 0; ok && done < marker.size();) {
    ssize_t w = write(fd, marker.data() + done, marker.size() - done);
    if (w <= 0) ok = false; else done += w;
  }
  ok = ok && fsync(fd) == 0;
  if (fd >= 0) ok = close(fd) == 0 && ok;
  if (!ok) fail(7, "cannot write " + path + ": " + errorText());
  syncFolder(RF.partial);
  // one atomic exchange: OUT is never missing, so no other run can take it meanwhile (the
  // earlier OUT, still locked, lands at OUT.partial.<pid>); where the file system cannot
  // exchange, two renames
  std::string replaced = RF.partial;
  if (syscall(SYS_renameat2, AT_FDCWD, RF.partial.c_str(), AT_FDCWD, RF.out.c_str(), 2 /* RENAME_EXCHANGE */) != 0) {
    replaced = RF.out + ".replaced." + std::to_string(getpid());
    if (rename(RF.out.c_str(), replaced.c_str()) != 0) fail(7, "cannot move the earlier " + RF.out + " aside: " + errorText());
    if (rename(RF.partial.c_str(), RF.out.c_str()) != 0) {
      const std::string why = errorText();
      rename(replaced.c_str(), RF.out.c_str());
      fail(7, "cannot move " + RF.partial + " to " + RF.out + ": " + why);
    }
  }
  RF.partialMade = false; RF.createdOut = false;
  madeParents = 0;
  syncBuffers();
  const size_t slash = RF.out.rfind('/');
  syncFolder(slash == std::string::npos ? "." : (slash == 0 ? "/" : RF.out.substr(0, slash)));
  removeReplaced(replaced);
  close(RF.lock); RF.lock = -1;
  return 0;
}

// ---------------------------------------------------------------- child processes, without a shell
// spawn file (searched in PATH) with args, its standard output and error into log (/dev/null
// by default); the child is stopped if the run is (by a signal the run handles, or, through
// PR_SET_PDEATHSIG, by its death even from SIGKILL); returns its exit status, 128 + the
// signal that ended it, or 127 when it could not be started
int spawnAndWait(const std::string &file, const std::vector<std::string> &args, const std::string &log = "/dev/null") {
  std::vector<char *> argv;
  for (auto &a : args) argv.push_back(const_cast<char *>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t child = fork();
  if (child < 0) return 127;
  if (child == 0) {                                  // system calls only until exec
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);             // the run died before prctl
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) _exit(127);
    dup2(fd, 1); dup2(fd, 2);
    if (fd > 2) close(fd);
    execvp(file.c_str(), argv.data());
    _exit(127);
  }
  runningChild = child;                              // stopped if the run is
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {}
  runningChild = 0;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

long runGeoDimension(string *const &path);
long runGmsh(string *const &geo, string *const &out, string *const &numbers) {
  string geoPath = *geo;
  std::vector<std::string> args = {"gmsh", runGeoDimension(&geoPath) == 3 ? "-3" : "-2", "-format", "msh22", "-v", "0"};
  std::stringstream in(*numbers);
  std::string name, value;
  while (in >> name >> value) { args.push_back("-setnumber"); args.push_back(name); args.push_back(value); }
  args.push_back(*geo); args.push_back("-o"); args.push_back(*out);
  std::snprintf(temporaryC, sizeof temporaryC, "%s", out->c_str());   // removed if the run fails
  haveTemporary = 1;
  return spawnAndWait("gmsh", args);
}

// this FreeFEM program again: program as it was started (ARGV[0]: FreeFem++-nw and FreeFem++
// are one binary that reads its own name), then the arguments of the text (one a line); its
// standard output and error into log (the pilot runs of -adapt)
long runFreeFem(string *const &program, string *const &arguments, string *const &log) {
  std::vector<std::string> args = {*program};
  std::stringstream in(*arguments);
  std::string line;
  while (std::getline(in, line)) args.push_back(line);
  return spawnAndWait(*program, args, *log);
}

// ---------------------------------------------------------------- the mesh checker
// A gmsh MSH 2.x ASCII file, as FreeFEM's gmshload would read it: every problem FreeFEM
// would abort on, crash on or silently misread is named here instead.
struct MeshProblem { std::string why; };
struct WriteProblem { std::string why; };          // the checked copy could not be written

struct Element { long id; int type; std::vector<long> tags, nodes; };

std::string numberText(double x) { char b[32]; std::snprintf(b, sizeof b, "%g", x); return b; }

const double maxExtentRatio = 1e8;                 // extent / shortest edge (see checkMesh)
const double maxCoordinate = 1e100;                // |x|, |y|, |z| of a node (see readNode)

// disjoint sets of triangles (union-find, with path halving)
struct Pieces {
  std::vector<size_t> parent;
  size_t pieces;
  explicit Pieces(size_t n) : parent(n), pieces(n) { for (size_t k = 0; k < n; k++) parent[k] = k; }
  size_t root(size_t k) { while (parent[k] != k) k = parent[k] = parent[parent[k]]; return k; }
  void join(size_t a, size_t b) { a = root(a); b = root(b); if (a != b) { parent[a] = b; pieces--; } }
  size_t count() const { return pieces; }
};

using Point = std::array<double, 2>;
double distanceToSegment(const Point &p, const Point &a, const Point &b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1], length2 = dx * dx + dy * dy;
  const double t = length2 > 0 ? std::max(0., std::min(1., ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length2)) : 0;
  return std::hypot(p[0] - (a[0] + t * dx), p[1] - (a[1] + t * dy));
}
double turn(const Point &o, const Point &a, const Point &b) { return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]); }

// Do the edges (a, b) and (c, d) (node indices) meet anywhere but at a node they share? Closer
// than tol counts as meeting.
bool edgesMeet(long a, long b, long c, long d, const std::vector<Point> &xy, double tol) {
  if (a == c || a == d || b == c || b == d) {       // a shared node s: overlapping if one other end lies on the other edge
    const long s = (a == c || a == d) ? a : b, u = s == a ? b : a, v = s == c ? d : c;
    return distanceToSegment(xy[u], xy[s], xy[v]) <= tol || distanceToSegment(xy[v], xy[s], xy[u]) <= tol;
  }
  if (distanceToSegment(xy[a], xy[c], xy[d]) <= tol || distanceToSegment(xy[b], xy[c], xy[d]) <= tol ||
      distanceToSegment(xy[c], xy[a], xy[b]) <= tol || distanceToSegment(xy[d], xy[a], xy[b]) <= tol)
    return true;
  const double o1 = turn(xy[a], xy[b], xy[c]), o2 = turn(xy[a], xy[b], xy[d]);
  const double o3 = turn(xy[c], xy[d], xy[a]), o4 = turn(xy[c], xy[d], xy[b]);
  return ((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0));
}

// Two boundary edges that meet elsewhere than at a shared end node, as {a, b, c, d}, or -1s.
// Near-linear: a uniform grid of square cells as wide as the mean edge; each edge, cut into
// pieces no longer than a cell, is entered in the cells the pieces touch, and only edges that
// share a cell are compared.
std::array<long, 4> meetingBoundaryEdges(const std::vector<Point> &xy, const std::set<std::vector<long>> &edges, double tol) {
  const std::array<long, 4> none = {-1, -1, -1, -1};
  std::vector<std::array<long, 2>> list;
  double total = 0, x0 = INFINITY, y0 = INFINITY;
  for (auto &e : edges) {
    list.push_back({e[0], e[1]});
    total += std::hypot(xy[e[1]][0] - xy[e[0]][0], xy[e[1]][1] - xy[e[0]][1]);
    for (long k : e) { x0 = std::min(x0, xy[k][0]); y0 = std::min(y0, xy[k][1]); }
  }
  if (list.size() < 2 || !(total > 0)) return none;
  const double h = total / list.size();
  auto cell = [&](double x, double y) -> std::uint64_t {
    const double ix = std::floor((x - x0) / h), iy = std::floor((y - y0) / h);
    return ((std::uint64_t)std::max(0., ix) << 32) | (std::uint64_t)std::max(0., iy);   // below 2^32 each: the extent is < 1e8 edges
  };
  std::vector<std::pair<std::uint64_t, long>> entries;   // (cell, edge)
  for (long k = 0; k < (long)list.size(); k++) {
    const Point &p = xy[list[k][0]], &q = xy[list[k][1]];
    const long parts = std::max(1L, (long)std::ceil(std::hypot(q[0] - p[0], q[1] - p[1]) / h));
    for (long m = 0; m < parts; m++) {
      const double s0 = (double)m / parts, s1 = (double)(m + 1) / parts;
      const double ax = p[0] + s0 * (q[0] - p[0]), ay = p[1] + s0 * (q[1] - p[1]);
      const double bx = p[0] + s1 * (q[0] - p[0]), by = p[1] + s1 * (q[1] - p[1]);
      const std::uint64_t low = cell(std::min(ax, bx) - tol, std::min(ay, by) - tol);
      const std::uint64_t high = cell(std::max(ax, bx) + tol, std::max(ay, by) + tol);
      for (std::uint64_t ix = low >> 32; ix <= high >> 32; ix++)
        for (std::uint64_t iy = low & 0xFFFFFFFFu; iy <= (high & 0xFFFFFFFFu); iy++) entries.push_back({(ix << 32) | iy, k});
    }
  }
  std::sort(entries.begin(), entries.end());
  entries.erase(std::unique(entries.begin(), entries.end()), entries.end());
  for (size_t first = 0, last; first < entries.size(); first = last) {
    for (last = first + 1; last < entries.size() && entries[last].first == entries[first].first; last++) {}
    for (size_t i = first; i < last; i++)
      for (size_t j = i + 1; j < last; j++) {
        const auto &e = list[entries[i].second], &f = list[entries[j].second];
        if (edgesMeet(e[0], e[1], f[0], f[1], xy, tol)) return {e[0], e[1], f[0], f[1]};
      }
  }
  return none;
}

// The text of a gmsh MSH 2.2 ASCII file: its lines (line ends and trailing blanks dropped, a
// UTF-8 byte order mark skipped), where its $Nodes and $Elements sections start and their counts
struct MeshText {
  std::vector<std::string> lines;
  long nodesAt = -1, elementsAt = -1, nodeCount = 0, elementCount = 0;
};
std::vector<std::string> fieldsOf(const std::string &text) {
  std::vector<std::string> words;
  std::stringstream in(text);
  std::string w;
  while (in >> w) words.push_back(w);
  return words;
}
MeshText readMeshText(const std::string &path) {
  MeshText M;
  std::vector<std::string> &lines = M.lines;
  std::ifstream f(path, std::ios::binary);
  if (!f) throw MeshProblem{"cannot read the file"};
  std::string line;
  auto trimmed = [](std::string text) {
    while (!text.empty() && (text.back() == '\r' || text.back() == ' ' || text.back() == '\t')) text.pop_back();
    return text;
  };
  // the first line must open the $MeshFormat section: anything else is refused unread
  if (!std::getline(f, line)) throw MeshProblem{"an empty file"};
  if (line.compare(0, 3, "\xEF\xBB\xBF") == 0) line = line.substr(3);
  if (trimmed(line) != "$MeshFormat") throw MeshProblem{"not a gmsh mesh file (it does not start with $MeshFormat)"};
  lines.push_back("$MeshFormat");
  while (std::getline(f, line)) lines.push_back(trimmed(line));
  auto section = [&](const std::string &name) -> long {
    for (size_t i = 0; i < lines.size(); i++) if (lines[i] == "$" + name) return (long)i;
    return -1;
  };
  const long format = section("MeshFormat");
  if (format < 0 || format + 1 >= (long)lines.size()) throw MeshProblem{"not a gmsh mesh file (no $MeshFormat section)"};
  const std::vector<std::string> header = fieldsOf(lines[format + 1]);
  if (header.size() < 3) throw MeshProblem{"not a gmsh mesh file (a $MeshFormat section without version)"};
  if (header[0].compare(0, 2, "2.") != 0 && header[0] != "2")
    throw MeshProblem{"gmsh format " + header[0] + ", not 2.2: re-export it with: gmsh -2 -format msh22 FILE.geo -o FILE.msh (-3 for a 3D body)"};
  if (header[1] != "0") throw MeshProblem{"binary MSH file: re-export it as text with: gmsh -2 -format msh22 FILE.geo -o FILE.msh (-3 for a 3D body)"};
  M.nodesAt = section("Nodes"); M.elementsAt = section("Elements");
  if (M.nodesAt < 0 || M.elementsAt < 0) throw MeshProblem{"truncated file: no $Nodes or $Elements section"};
  auto count = [&](long at, const char *what) {
    if (at + 1 >= (long)lines.size()) throw MeshProblem{std::string("truncated file: no count after $") + what};
    char *end = nullptr;
    const long n = std::strtol(lines[at + 1].c_str(), &end, 10);
    if (n < 0 || (end && *end)) throw MeshProblem{std::string("$") + what + " has no count: '" + lines[at + 1] + "'"};
    if (at + 2 + n >= (long)lines.size() || lines[at + 2 + n] != std::string("$End") + what)
      throw MeshProblem{std::string("$") + what + " declares " + std::to_string(n) + " entries but does not end after them "
                        "(a truncated file?): no $End" + what + " there"};
    return n;
  };
  M.nodeCount = count(M.nodesAt, "Nodes");
  M.elementCount = count(M.elementsAt, "Elements");
  return M;
}

// one line of $Nodes, "id x y z": the id fits FreeFEM, is new (entered in index with the next
// position), the coordinates finite
void readNode(const std::string &text, std::map<long, long> &index, long &id, double &x, double &y, double &z) {
  std::stringstream in(text);
  std::string rest;
  if (!(in >> id >> x >> y >> z) || (in >> rest)) throw MeshProblem{"$Nodes: cannot read the node line '" + text + "'"};
  if (id > 2147483647L || id < -2147483647L) throw MeshProblem{"node id " + std::to_string(id) + " does not fit FreeFEM's 32-bit ids"};
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) throw MeshProblem{"node " + std::to_string(id) + " has a non-finite coordinate"};
  const double largest = std::max(std::fabs(x), std::max(std::fabs(y), std::fabs(z)));
  if (largest > maxCoordinate)                       // lengths squared and cubed (areas, volumes) must stay finite
    throw MeshProblem{"node " + std::to_string(id) + " has the coordinate " + numberText(largest) + ", beyond " + numberText(maxCoordinate) +
                      ", where areas and volumes overflow: give the lengths in other units"};
  if (index.count(id)) throw MeshProblem{"node " + std::to_string(id) + " is defined twice"};
}

// an element line's numbers v (id, type, tag count, tags, nodes): its tags and node positions
// into e, checked (the count, defined nodes, none twice); returns its nodes sorted
std::vector<long> readElementNodes(Element &e, const std::vector<long> &v, long nodes, const std::map<long, long> &index) {
  const long ntags = v[2];
  if (ntags < 0 || (long)v.size() != 3 + ntags + nodes)
    throw MeshProblem{"element " + std::to_string(e.id) + ": " + std::to_string(v.size()) + " numbers, but its "
                      + std::to_string(ntags) + " tags and " + std::to_string(nodes) + " nodes need " + std::to_string(3 + ntags + nodes)};
  e.tags.assign(v.begin() + 3, v.begin() + 3 + ntags);
  for (long k = 0; k < nodes; k++) {
    const long id = v[3 + ntags + k];
    if (!index.count(id)) throw MeshProblem{"element " + std::to_string(e.id) + " uses node " + std::to_string(id) + ", which is not defined"};
    e.nodes.push_back(index.at(id));
  }
  std::vector<long> key = e.nodes;
  std::sort(key.begin(), key.end());
  if (std::adjacent_find(key.begin(), key.end()) != key.end())
    throw MeshProblem{"element " + std::to_string(e.id) + " uses a node twice"};
  return key;
}

// the labels the suite needs ("LABEL ROLE ..." in required), then the scene's Dirichlet labels,
// among the labels of the boundary elements (lines in 2D, triangles in 3D: element, physical)
void requireLabels(const std::set<long> &labels, const std::string &required, const std::string &dirichlet,
                   const std::string &element, const std::string &physical) {
  std::stringstream in(required);
  std::string label, role, missing, roles;
  while (in >> label >> role) {
    roles += (roles.empty() ? "" : ", ") + label + " " + role;
    if (!labels.count(std::atol(label.c_str()))) missing += " " + label;
  }
  if (!missing.empty()) throw MeshProblem{"no boundary " + element + " with physical tag" + missing + " (Physical " + physical + " " + roles + " are required)"};
  std::stringstream scene(dirichlet);
  while (scene >> label)
    if (std::atol(label.c_str()) >= 0 && !labels.count(std::atol(label.c_str())))
      throw MeshProblem{"the scene's dirichlet label " + label + " is not a physical " + (physical == "Curve" ? "curve" : "surface") + " of the mesh"};
}
// the mesh FreeFEM will read: the nodes (ids, x y z) and the groups of elements, on the disk
void writeCheckedMesh(const std::string &outPath, const std::vector<long> &idOf, const std::vector<std::array<double, 3>> &xyz,
                      std::initializer_list<std::vector<Element> *> groups) {
  if (outPath.empty()) return;                       // a check only (compare.edp reads a run's own mesh)
  size_t elements = 0;
  for (auto *group : groups) elements += group->size();
  std::ofstream o(outPath, std::ios::binary | std::ios::trunc);
  o.precision(17);
  o << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << idOf.size() << "\n";
  for (size_t i = 0; i < idOf.size(); i++) o << idOf[i] << " " << xyz[i][0] << " " << xyz[i][1] << " " << xyz[i][2] << "\n";
  o << "$EndNodes\n$Elements\n" << elements << "\n";
  for (auto *group : groups)
    for (Element &e : *group) {
      o << e.id << " " << e.type << " " << e.tags.size();
      for (long t : e.tags) o << " " << t;
      for (long k : e.nodes) o << " " << idOf[k];
      o << "\n";
    }
  o << "$EndElements\n";
  o.flush();
  o.close();
  if (!o) throw WriteProblem{"cannot write the checked mesh to " + outPath + " (is the disk full?)"};
  int fd = open(outPath.c_str(), O_RDONLY);         // on the disk
  const bool synced = fd >= 0 && fsync(fd) == 0;
  if (fd >= 0) close(fd);
  if (!synced) throw WriteProblem{"cannot write the checked mesh to " + outPath + ": " + errorText()};
}

void checkMesh(const std::string &path, const std::string &outPath, const std::string &required,
               const std::string &dirichlet) {
  MeshText M = readMeshText(path);
  const std::vector<std::string> &lines = M.lines;
  const long nodesAt = M.nodesAt, elementsAt = M.elementsAt;
  // nodes: id x y z, ids unique, coordinates finite, one plane
  const long nodeCount = M.nodeCount;
  std::map<long, long> index;
  std::vector<std::array<double, 2>> xy(nodeCount);
  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY, z0 = 0;
  for (long i = 0; i < nodeCount; i++) {
    const std::string &text = lines[nodesAt + 2 + i];
    long id;
    double x, y, z;
    readNode(text, index, id, x, y, z);
    if (i == 0) z0 = z;
    if (z != z0)
      throw MeshProblem{"node " + std::to_string(id) + " has z = " + numberText(z) + " and the first node z = " + numberText(z0) +
                        ": the mesh is not flat, and it has no volume element: a 3D body needs a Physical Volume meshed "
                        "with gmsh -3 (and a 3D scene); a 2D one lies in one plane z = constant"};
    index[id] = i;
    xy[i] = {x, y};
    xmin = std::min(xmin, x); xmax = std::max(xmax, x); ymin = std::min(ymin, y); ymax = std::max(ymax, y);
  }
  // elements: 2-node lines (boundary labels) and 3-node triangles; points are ignored
  const long elementCount = M.elementCount;
  std::vector<Element> triangles, edges;
  std::map<std::vector<long>, long> seenTriangles, seenEdges;
  for (long i = 0; i < elementCount; i++) {
    const std::string &text = lines[elementsAt + 2 + i];
    std::vector<std::string> w = fieldsOf(text);
    Element e;
    char *end = nullptr;
    bool ok = w.size() >= 3;
    std::vector<long> v;
    for (auto &s : w) { v.push_back(std::strtol(s.c_str(), &end, 10)); ok = ok && end && !*end; }
    if (!ok) throw MeshProblem{"$Elements: cannot read the element line '" + text + "'"};
    e.id = v[0]; e.type = (int)v[1];
    for (long number : v)
      if (number > 2147483647L || number < -2147483647L)
        throw MeshProblem{"element " + std::to_string(e.id) + ": the number " + std::to_string(number) + " does not fit FreeFEM's 32-bit ids and tags"};
    const std::map<int, int> nodesOfType = {{1, 2}, {2, 3}, {15, 1}};
    if (e.type == 8 || e.type == 9 || e.type == 16 || e.type == 21 || e.type == 23 || e.type == 25)
      throw MeshProblem{"element " + std::to_string(e.id) + " is of order 2 or more (gmsh type " + std::to_string(e.type) +
                        "): re-mesh with order 1 (gmsh -order 1)"};
    if (e.type == 3 || e.type == 10)
      throw MeshProblem{"element " + std::to_string(e.id) + " is a quadrangle (gmsh type " + std::to_string(e.type) +
                        "): only triangles are supported (re-mesh without Recombine)"};
    if (!nodesOfType.count(e.type))
      throw MeshProblem{"element " + std::to_string(e.id) + " has gmsh type " + std::to_string(e.type) +
                        ": only 3-node triangles (2), 2-node lines (1) and points (15) are supported (a 3D mesh?)"};
    std::vector<long> key = readElementNodes(e, v, nodesOfType.at(e.type), index);
    if (e.type == 2) {
      if (seenTriangles.count(key)) throw MeshProblem{"triangle " + std::to_string(e.id) + " repeats triangle " + std::to_string(seenTriangles[key])};
      seenTriangles[key] = e.id;
      triangles.push_back(e);
    }
    else if (e.type == 1) {
      if (e.tags.empty()) e.tags.push_back(0);      // no physical tag: label 0, as FreeFEM reads it
      if (seenEdges.count(key))
        throw MeshProblem{"line element " + std::to_string(e.id) + " repeats line element " + std::to_string(seenEdges[key]) +
                          " (the same edge listed twice would count its load or contact twice)"};
      seenEdges[key] = e.id;
      edges.push_back(e);
    }
  }
  if (triangles.empty()) throw MeshProblem{"no triangle (does the .geo define a Physical Surface?)"};
  // extent against the shortest edge: FreeFEM's reader exhausts the memory (tens of GB) on a
  // mesh whose extent is about 2^30 times its shortest edge; refused well before (1e8)
  double shortest = INFINITY;
  for (const Element &t : triangles)
    for (int k = 0; k < 3; k++) {
      const auto &p = xy[t.nodes[k]], &q = xy[t.nodes[(k + 1) % 3]];
      shortest = std::min(shortest, std::hypot(q[0] - p[0], q[1] - p[1]));
    }
  const double extent = std::max(xmax - xmin, ymax - ymin);
  if (shortest > 0 && extent > maxExtentRatio * shortest)
    throw MeshProblem{"the mesh extends over " + numberText(extent) + " (its bounding box) but its shortest edge is " +
                      numberText(shortest) + ", more than " + numberText(maxExtentRatio) + " times shorter, which FreeFEM's "
                      "mesh reader cannot handle (it exhausts the memory): give the lengths in other units, or cells closer "
                      "in size (a coarser ratio)"};
  // triangles: positive area, relative to their own size; FreeFEM's reader needs >= 1e-8
  std::vector<char> used(nodeCount, 0);
  std::map<std::pair<long, long>, std::vector<long>> directed;   // directed edge -> the triangles that run along it
  long reoriented = 0;
  for (Element &t : triangles) {
    const auto &a = xy[t.nodes[0]], &b = xy[t.nodes[1]], &c = xy[t.nodes[2]];
    const double area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
    double longest = 0;
    for (int k = 0; k < 3; k++) {
      const auto &p = xy[t.nodes[k]], &q = xy[t.nodes[(k + 1) % 3]];
      longest = std::max(longest, std::hypot(q[0] - p[0], q[1] - p[1]));
    }
    if (!(std::fabs(area) > 1e-12 * longest * longest))
      throw MeshProblem{"triangle " + std::to_string(t.id) + " has zero area"};
    if (std::fabs(area) < 1e-8)
      throw MeshProblem{"triangle " + std::to_string(t.id) + " has the area " + numberText(std::fabs(area)) +
                        ", below the 1e-8 that FreeFEM's mesh reader accepts: give the lengths in a smaller unit (millimetres instead of metres, say, with the material data in matching units)"};
    if (area < 0 && outPath.empty())               // no copy to reorient it in: FreeFEM's reader would stop
      throw MeshProblem{"triangle " + std::to_string(t.id) + " is clockwise (a mesh the suite wrote has none: a damaged file?)"};
    if (area < 0) { std::swap(t.nodes[1], t.nodes[2]); reoriented++; }
    for (long k : t.nodes) used[k] = 1;
    for (int k = 0; k < 3; k++) directed[{t.nodes[k], t.nodes[(k + 1) % 3]}].push_back(&t - triangles.data());
  }
  std::vector<long> idOf(nodeCount);
  for (auto &p : index) idOf[p.second] = p.first;
  auto edgeText = [&](long a, long b) { return "(nodes " + std::to_string(idOf[a]) + " " + std::to_string(idOf[b]) + ")"; };
  // counterclockwise triangles run along an interior edge once each way: twice the same way is
  // a fold (triangles on the same side of it), more is an overlap
  std::set<std::vector<long>> boundaryEdges, interiorEdges;
  Pieces pieces(triangles.size());                   // the triangles joined through their shared edges
  for (auto &e : directed) {
    const long a = e.first.first, b = e.first.second;
    const auto back = directed.find({b, a});
    const size_t forward = e.second.size(), backward = back == directed.end() ? 0 : back->second.size();
    if (forward > 1)
      throw MeshProblem{"triangles " + std::to_string(triangles[e.second[0]].id) + " and " + std::to_string(triangles[e.second[1]].id) +
                        " lie on the same side of their common edge " + edgeText(a, b) + ": the mesh is folded, tangled or overlapping"};
    std::vector<long> key = {std::min(a, b), std::max(a, b)};
    (backward ? interiorEdges : boundaryEdges).insert(key);
    if (backward) pieces.join(e.second[0], back->second[0]);
  }
  for (long i = 0; i < nodeCount; i++)
    if (!used[i]) {
      long id = 0;
      for (auto &p : index) if (p.second == i) id = p.first;
      throw MeshProblem{"node " + std::to_string(id) + " is not a vertex of any triangle"};
    }
  // two nodes at one point: a crack, or duplicated nodes
  std::vector<std::pair<std::array<double, 2>, long>> points;
  for (long i = 0; i < nodeCount; i++) points.push_back({xy[i], i});
  std::sort(points.begin(), points.end());
  for (size_t k = 1; k < points.size(); k++)
    if (points[k].first == points[k - 1].first)
      throw MeshProblem{"nodes " + std::to_string(idOf[points[k - 1].second]) + " and " + std::to_string(idOf[points[k].second]) +
                        " are at the same point (" + numberText(points[k].first[0]) + ", " + numberText(points[k].first[1]) +
                        "): a crack or duplicated nodes"};
  // one body: every triangle reached from the first through shared edges
  for (size_t k = 1; k < triangles.size(); k++)
    if (pieces.root(k) != pieces.root(0))
      throw MeshProblem{"the triangles form " + std::to_string(pieces.count()) + " separate pieces (triangles " +
                        std::to_string(triangles[0].id) + " and " + std::to_string(triangles[k].id) + " are joined by no chain of "
                        "triangles that share edges): the mesh must be one body, not two bodies, a loose triangle, or parts that "
                        "touch at a node only"};
  // its boundary edges meet at their shared end nodes only
  const double maxAbs = std::max(std::max(std::fabs(xmin), std::fabs(xmax)), std::max(std::fabs(ymin), std::fabs(ymax)));
  const std::array<long, 4> meeting = meetingBoundaryEdges(xy, boundaryEdges, 1e-9 * shortest + 8 * DBL_EPSILON * maxAbs);
  if (meeting[0] >= 0)
    throw MeshProblem{"the boundary edges " + edgeText(meeting[0], meeting[1]) + " and " + edgeText(meeting[2], meeting[3]) +
                      " cross or overlap (boundary edges may meet at a shared end node only): parts of the mesh lie over each "
                      "other, or a slit cuts the body (a hanging node, or line elements on a cut)"};
  // the labels the suite uses ("LABEL ROLE ..." required, then the scene's Dirichlet labels)
  std::set<long> used_labels;
  {
    std::stringstream roles(required + " " + dirichlet);
    std::string word;
    while (roles >> word) if (std::isdigit((unsigned char)word[0])) used_labels.insert(std::atol(word.c_str()));
  }
  std::set<long> labels;
  std::set<std::vector<long>> labelled;
  for (Element &e : edges) {
    std::vector<long> edge = e.nodes;
    std::sort(edge.begin(), edge.end());
    if (!boundaryEdges.count(edge) && !interiorEdges.count(edge))
      throw MeshProblem{"line element " + std::to_string(e.id) + " (physical tag " + std::to_string(e.tags[0]) +
                        ") is not an edge of any triangle"};
    if (interiorEdges.count(edge) && used_labels.count(e.tags[0]))
      throw MeshProblem{"line element " + std::to_string(e.id) + " (physical tag " + std::to_string(e.tags[0]) + ", a label the "
                        "run uses) lies inside the body, between two triangles: contact, load and Dirichlet labels go on its boundary"};
    labels.insert(e.tags[0]);
    labelled.insert(edge);
  }
  for (auto &edge : boundaryEdges)
    if (!labelled.count(edge))
      throw MeshProblem{"the boundary edge " + edgeText(edge[0], edge[1]) + " has no line element: give every boundary curve a "
                        "Physical Curve (a gap in the boundary, a crack or a hanging node leaves such an edge)"};
  requireLabels(labels, required, dirichlet, "line", "Curve");
  // the mesh FreeFEM will read: the same nodes and elements, triangles counterclockwise
  std::vector<std::array<double, 3>> xyz(nodeCount);
  for (long i = 0; i < nodeCount; i++) xyz[i] = {xy[i][0], xy[i][1], z0};
  writeCheckedMesh(outPath, idOf, xyz, {&edges, &triangles});
  (void)reoriented;
}

// A 3D mesh: 4-node tetrahedra (gmsh type 4) and 3-node boundary triangles (type 2, their
// physical tag the label); points and lines are dropped. Refused: bad ids, flat or inverted
// tetrahedra the reorientation cannot fix (zero volume), repeated tetrahedra, nodes of no
// tetrahedron, two nodes at one point, a face shared by more than two tetrahedra or whose two
// lie on one side of it (a fold, a tangle), pieces, a labelled triangle that is not a face, a
// used label inside the body, a boundary face without a triangle, missing labels.
// Written out with every tetrahedron positively oriented.
void checkMesh3(const std::string &path, const std::string &outPath, const std::string &required,
                const std::string &dirichlet) {
  MeshText M = readMeshText(path);
  const std::vector<std::string> &lines = M.lines;
  std::map<long, long> index;
  std::vector<std::array<double, 3>> xyz(M.nodeCount);
  std::vector<long> idOf(M.nodeCount);
  for (long i = 0; i < M.nodeCount; i++) {
    const std::string &text = lines[M.nodesAt + 2 + i];
    long id;
    double x, y, z;
    readNode(text, index, id, x, y, z);
    index[id] = i;
    idOf[i] = id;
    xyz[i] = {x, y, z};
  }
  std::vector<Element> tets, faces;
  std::set<std::vector<long>> seenTets;
  for (long i = 0; i < M.elementCount; i++) {
    const std::string &text = lines[M.elementsAt + 2 + i];
    std::vector<std::string> w = fieldsOf(text);
    std::vector<long> v;
    char *end = nullptr;
    bool ok = w.size() >= 3;
    for (auto &t : w) { v.push_back(std::strtol(t.c_str(), &end, 10)); ok = ok && end && !*end; }
    if (!ok) throw MeshProblem{"$Elements: cannot read the element line '" + text + "'"};
    Element e;
    e.id = v[0]; e.type = (int)v[1];
    const std::map<int, int> nodesOfType = {{1, 2}, {2, 3}, {4, 4}, {15, 1}};
    if (!nodesOfType.count(e.type))
      throw MeshProblem{"element " + std::to_string(e.id) + " has gmsh type " + std::to_string(e.type) +
                        ": a 3D mesh takes 4-node tetrahedra (4), 3-node boundary triangles (2), lines (1) and points (15) only "
                        "(order 1, no hexahedra or prisms: mesh without Recombine)"};
    std::vector<long> key = readElementNodes(e, v, nodesOfType.at(e.type), index);
    if (e.type == 1 || e.type == 15) continue;
    if (e.tags.empty()) e.tags.push_back(0);
    if (e.type == 4) {
      if (seenTets.count(key)) throw MeshProblem{"tetrahedron " + std::to_string(e.id) + " is listed twice"};
      seenTets.insert(key);
      tets.push_back(e);
    }
    else faces.push_back(e);
  }
  if (tets.empty()) throw MeshProblem{"no tetrahedron (does the .geo define a Physical Volume? mesh it with gmsh -3)"};
  std::vector<char> used(M.nodeCount, 0);
  std::map<std::vector<long>, std::vector<size_t>> faceTets;   // sorted face -> the tetrahedra that have it
  for (size_t k = 0; k < tets.size(); k++) {
    Element &t = tets[k];
    auto &a = xyz[t.nodes[0]], &b = xyz[t.nodes[1]], &c = xyz[t.nodes[2]], &d = xyz[t.nodes[3]];
    double u[3], v[3], w[3], longest = 0;
    for (int i = 0; i < 3; i++) { u[i] = b[i] - a[i]; v[i] = c[i] - a[i]; w[i] = d[i] - a[i]; }
    const double volume = (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0])) / 6;
    for (int i = 0; i < 4; i++)
      for (int j = i + 1; j < 4; j++) {
        const auto &p = xyz[t.nodes[i]], &q = xyz[t.nodes[j]];
        longest = std::max(longest, std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2])));
      }
    if (!(std::fabs(volume) > 1e-12 * longest * longest * longest)) throw MeshProblem{"tetrahedron " + std::to_string(t.id) + " has zero volume"};
    if (volume < 0) std::swap(t.nodes[1], t.nodes[2]);   // positively oriented (folds: the face check below)
    for (long n : t.nodes) used[n] = 1;
    for (int skip = 0; skip < 4; skip++) {
      std::vector<long> f;
      for (int i = 0; i < 4; i++) if (i != skip) f.push_back(t.nodes[i]);
      std::sort(f.begin(), f.end());
      faceTets[f].push_back(k);
    }
  }
  for (long i = 0; i < M.nodeCount; i++)
    if (!used[i]) throw MeshProblem{"node " + std::to_string(idOf[i]) + " is not a vertex of any tetrahedron"};
  // two nodes at one point: a crack, or duplicated nodes
  {
    std::vector<std::pair<std::array<double, 3>, long>> points;
    for (long i = 0; i < M.nodeCount; i++) points.push_back({xyz[i], i});
    std::sort(points.begin(), points.end());
    for (size_t k = 1; k < points.size(); k++)
      if (points[k].first == points[k - 1].first)
        throw MeshProblem{"nodes " + std::to_string(idOf[points[k - 1].second]) + " and " + std::to_string(idOf[points[k].second]) +
                          " are at the same point (" + numberText(points[k].first[0]) + ", " + numberText(points[k].first[1]) + ", " +
                          numberText(points[k].first[2]) + "): a crack or duplicated nodes"};
  }
  // the two tetrahedra of an interior face lie on its two sides (else they overlap: a fold)
  auto side = [&](const std::vector<long> &f, long p) {
    const auto &a = xyz[f[0]], &b = xyz[f[1]], &c = xyz[f[2]], &d = xyz[p];
    double u[3], v[3], w[3];
    for (int i = 0; i < 3; i++) { u[i] = b[i] - a[i]; v[i] = c[i] - a[i]; w[i] = d[i] - a[i]; }
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
  };
  auto fourth = [&](size_t k, const std::vector<long> &f) {
    for (long n : tets[k].nodes) if (n != f[0] && n != f[1] && n != f[2]) return n;
    return f[0];
  };
  for (auto &f : faceTets)
    if (f.second.size() == 2 && !(side(f.first, fourth(f.second[0], f.first)) * side(f.first, fourth(f.second[1], f.first)) < 0))
      throw MeshProblem{"tetrahedra " + std::to_string(tets[f.second[0]].id) + " and " + std::to_string(tets[f.second[1]].id) +
                        " lie on the same side of their common face: the mesh is folded, tangled or overlapping"};
  Pieces pieces(tets.size());
  for (auto &f : faceTets) {
    if (f.second.size() > 2)
      throw MeshProblem{"tetrahedra " + std::to_string(tets[f.second[0]].id) + ", " + std::to_string(tets[f.second[1]].id) + " and "
                        + std::to_string(tets[f.second[2]].id) + " share one face: the mesh overlaps"};
    if (f.second.size() == 2) pieces.join(f.second[0], f.second[1]);
  }
  if (pieces.count() > 1)
    throw MeshProblem{"the tetrahedra form " + std::to_string(pieces.count()) + " separate pieces (joined by no chain of shared faces): "
                      "the mesh must be one body"};
  std::set<long> usedLabels, labels;
  {
    std::stringstream roles(required + " " + dirichlet);
    std::string word;
    while (roles >> word) if (std::isdigit((unsigned char)word[0])) usedLabels.insert(std::atol(word.c_str()));
  }
  std::set<std::vector<long>> labelled;
  for (Element &e : faces) {
    std::vector<long> f = e.nodes;
    std::sort(f.begin(), f.end());
    const auto at = faceTets.find(f);
    if (at == faceTets.end())
      throw MeshProblem{"triangle " + std::to_string(e.id) + " (physical tag " + std::to_string(e.tags[0]) + ") is not a face of any tetrahedron"};
    if (at->second.size() == 2 && usedLabels.count(e.tags[0]))
      throw MeshProblem{"triangle " + std::to_string(e.id) + " (physical tag " + std::to_string(e.tags[0]) + ", a label the run uses) "
                        "lies inside the body, between two tetrahedra: contact, load and Dirichlet labels go on its boundary"};
    if (labelled.count(f)) throw MeshProblem{"triangle " + std::to_string(e.id) + " repeats another boundary triangle"};
    labelled.insert(f);
    labels.insert(e.tags[0]);
  }
  for (auto &f : faceTets)
    if (f.second.size() == 1 && !labelled.count(f.first))
      throw MeshProblem{"the boundary face (nodes " + std::to_string(idOf[f.first[0]]) + " " + std::to_string(idOf[f.first[1]]) + " " +
                        std::to_string(idOf[f.first[2]]) + ") has no triangle element: give every boundary surface a Physical Surface"};
  requireLabels(labels, required, dirichlet, "triangle", "Surface");
  writeCheckedMesh(outPath, idOf, xyz, {&faces, &tets});
}

// The dimension of a mesh file: 3 if it has a volume element (a tetrahedron, gmsh type 4, or
// another that the 3D checker then refuses: hexahedra, prisms, pyramids, of any order), 2 if
// it is a gmsh file without one, 0 if it cannot be read as one (the checker then says why)
// ---------------------------------------------------------------- two meshes of one domain
// compare.edp compares the fields of two runs only if their meshes cover the same domain with
// the same boundary labels. The boundary of a checked mesh is its labelled boundary elements
// (2D: lines, 3D: triangles; the first tag). Each element's centroid must lie on the other
// mesh's boundary, on an element of its label, within 1e-6 of the extent plus what a chord
// may lie off a curved boundary: the sagitta h theta / 8 of an element of length h whose
// neighbours turn by theta from it (the curve turns by about theta over h), of both elements.
// On a polygon theta is 0 away from the corners, so another length or a moved support is seen.
struct Boundary {
  std::vector<std::array<double, 3>> xyz;            // the nodes
  std::vector<std::array<long, 3>> corner;           // each element's nodes (two in 2D)
  std::vector<long> label;
  std::vector<std::array<double, 3>> centroid, axis; // its centroid; its direction (2D) or normal (3D)
  std::vector<double> length, sagitta, reach;        // its size h; h theta / 8; the farthest of its nodes from its centroid
  int corners = 2;
  double extent = 0;
};
double dot3(const std::array<double, 3> &a, const std::array<double, 3> &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
std::array<double, 3> minus3(const std::array<double, 3> &a, const std::array<double, 3> &b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
std::array<double, 3> cross3(const std::array<double, 3> &a, const std::array<double, 3> &b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Boundary readBoundary(const std::string &path) {
  MeshText M = readMeshText(path);
  Boundary B;
  std::map<long, long> index;
  B.xyz.resize(M.nodeCount);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (long i = 0; i < M.nodeCount; i++) {
    long id;
    double x, y, z;
    readNode(M.lines[M.nodesAt + 2 + i], index, id, x, y, z);
    index[id] = i;
    B.xyz[i] = {x, y, z};
    for (int k = 0; k < 3; k++) { lo[k] = std::min(lo[k], B.xyz[i][k]); hi[k] = std::max(hi[k], B.xyz[i][k]); }
  }
  for (int k = 0; k < 3; k++) B.extent = std::max(B.extent, hi[k] - lo[k]);
  bool three = false;
  std::vector<std::vector<long>> elements;
  for (long i = 0; i < M.elementCount; i++) {
    std::vector<std::string> w = fieldsOf(M.lines[M.elementsAt + 2 + i]);
    std::vector<long> v;
    for (auto &word : w) v.push_back(std::atol(word.c_str()));
    three = three || (v.size() > 1 && v[1] == 4);
    elements.push_back(v);
  }
  B.corners = three ? 3 : 2;
  const long wanted = three ? 2 : 1;                 // gmsh types: 1 line, 2 triangle
  for (auto &v : elements) {
    if (v.size() < 3 || v[1] != wanted || v[2] < 1 || (long)v.size() < 3 + v[2] + B.corners) continue;
    std::array<long, 3> nodes = {0, 0, 0};
    for (int k = 0; k < B.corners; k++) nodes[k] = index.at(v[3 + v[2] + k]);
    B.corner.push_back(nodes);
    B.label.push_back(v[3]);
  }
  const size_t n = B.corner.size();
  B.centroid.resize(n); B.axis.resize(n); B.length.assign(n, 0); B.sagitta.assign(n, 0); B.reach.assign(n, 0);
  std::map<long, std::vector<size_t>> at;            // the elements at each node
  for (size_t e = 0; e < n; e++) {
    std::array<double, 3> c = {0, 0, 0};
    for (int k = 0; k < B.corners; k++) for (int d = 0; d < 3; d++) c[d] += B.xyz[B.corner[e][k]][d] / B.corners;
    B.centroid[e] = c;
    const auto &a = B.xyz[B.corner[e][0]], &b = B.xyz[B.corner[e][1]];
    std::array<double, 3> axis = minus3(b, a);
    if (three) axis = cross3(axis, minus3(B.xyz[B.corner[e][2]], a));
    const double norm = std::sqrt(dot3(axis, axis));
    for (int d = 0; d < 3; d++) axis[d] = norm > 0 ? axis[d] / norm : 0;
    B.axis[e] = axis;
    for (int k = 0; k < B.corners; k++) {
      const auto r = minus3(B.xyz[B.corner[e][k]], c);
      B.reach[e] = std::max(B.reach[e], std::sqrt(dot3(r, r)));
      const auto side = minus3(B.xyz[B.corner[e][(k + 1) % B.corners]], B.xyz[B.corner[e][k]]);
      B.length[e] = std::max(B.length[e], std::sqrt(dot3(side, side)));
      at[B.corner[e][k]].push_back(e);
    }
  }
  for (size_t e = 0; e < n; e++) {
    double theta = 0;                                // the largest turn to a neighbour (lines: unoriented)
    for (int k = 0; k < B.corners; k++)
      for (size_t f : at[B.corner[e][k]]) {
        const double c = std::fabs(dot3(B.axis[e], B.axis[f]));
        theta = std::max(theta, std::acos(std::min(1., c)));
      }
    B.sagitta[e] = B.length[e] * theta / 8;
  }
  return B;
}
// the distance from p to element e of B (a segment, or a triangle)
double distanceTo(const Boundary &B, size_t e, const std::array<double, 3> &p) {
  const auto &a = B.xyz[B.corner[e][0]], &b = B.xyz[B.corner[e][1]];
  auto segment = [&](const std::array<double, 3> &s, const std::array<double, 3> &t) {
    const auto st = minus3(t, s), sp = minus3(p, s);
    const double along = dot3(st, st) > 0 ? std::max(0., std::min(1., dot3(sp, st) / dot3(st, st))) : 0.;
    const std::array<double, 3> q = {s[0] + along * st[0], s[1] + along * st[1], s[2] + along * st[2]};
    const auto d = minus3(p, q);
    return std::sqrt(dot3(d, d));
  };
  if (B.corners == 2) return segment(a, b);
  const auto &c = B.xyz[B.corner[e][2]];
  const auto ab = minus3(b, a), ac = minus3(c, a), ap = minus3(p, a);
  const double d00 = dot3(ab, ab), d01 = dot3(ab, ac), d11 = dot3(ac, ac), d20 = dot3(ap, ab), d21 = dot3(ap, ac);
  const double det = d00 * d11 - d01 * d01;
  if (det > 0) {                                     // inside the triangle's projection: the distance to its plane
    const double v = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
    if (v >= 0 && w >= 0 && v + w <= 1) return std::fabs(dot3(ap, B.axis[e]));
  }
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}
// "" if every element of A lies on an element of R of its label (within the tolerance), else
// why not; the elements of R sorted by the x of their centroids, searched outwards from p's x
std::string boundaryOff(const Boundary &A, const Boundary &R, const std::string &nameA, const std::string &nameR) {
  std::vector<size_t> order(R.corner.size());
  for (size_t f = 0; f < order.size(); f++) order[f] = f;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return R.centroid[a][0] < R.centroid[b][0]; });
  double widest = 0;
  for (double r : R.reach) widest = std::max(widest, r);
  const double floor = 1e-6 * std::max(A.extent, R.extent);
  for (size_t e = 0; e < A.corner.size(); e++) {
    const auto &p = A.centroid[e];
    double best = INFINITY, nearest = INFINITY;      // the least distance, less R's sagitta, to an element of the label; that distance
    const size_t start = std::lower_bound(order.begin(), order.end(), p[0],
                                          [&](size_t f, double x) { return R.centroid[f][0] < x; }) - order.begin();
    for (int side = 0; side < 2; side++)
      for (size_t k = side ? start : start - 1; k < order.size(); k = side ? k + 1 : k - 1) {
        const size_t f = order[k];
        if (std::fabs(R.centroid[f][0] - p[0]) - widest > best) break;
        if (R.label[f] == A.label[e]) {
          const double d = distanceTo(R, f, p);
          if (d - R.sagitta[f] < best) { best = d - R.sagitta[f]; nearest = d; }
        }
        if (!side && k == 0) break;
      }
    if (!(best <= floor + A.sagitta[e])) {
      char at[160];
      std::snprintf(at, sizeof at, "(%.6g, %.6g%s", p[0], p[1], A.corners == 3 ? "" : ")");
      std::string where = at;
      if (A.corners == 3) { std::snprintf(at, sizeof at, ", %.6g)", p[2]); where += at; }
      return "the boundary labelled " + std::to_string(A.label[e]) + " of " + nameA + " passes through " + where + ", "
             + (std::isfinite(best) ? numberText(nearest) + " away from " + nameR + "'s boundary of that label (tolerance "
                                      + numberText(nearest - best + floor + A.sagitta[e]) + ")"
                                    : "but " + nameR + " has no boundary of that label");
    }
  }
  return "";
}
// compare.edp: exit 2 naming where, unless the two meshes (checked before) cover one domain with
// the same boundary labels
long runSameDomain(string *const &pathA, string *const &pathR) {
  Boundary A, R;
  try { A = readBoundary(*pathA); R = readBoundary(*pathR); }
  catch (const MeshProblem &problem) { fail(3, "compare.edp: " + problem.why); }
  if (A.corners != R.corners) fail(2, "compare.edp: " + *pathA + " and " + *pathR + " are meshes of two dimensions");
  std::string why = boundaryOff(A, R, *pathA, *pathR);
  if (why.empty()) why = boundaryOff(R, A, *pathR, *pathA);
  if (!why.empty()) fail(2, "compare.edp: the runs' meshes do not cover the same domain with the same boundary labels: " + why);
  return 0;
}

long runMeshDimension(string *const &path) {
  try {
    MeshText M = readMeshText(*path);
    const std::set<std::string> volumes = {"4", "5", "6", "7", "11", "12", "13", "14", "17", "18", "19", "29", "30", "31"};
    for (long i = 0; i < M.elementCount; i++) {
      std::vector<std::string> w = fieldsOf(M.lines[M.elementsAt + 2 + i]);
      if (w.size() >= 2 && volumes.count(w[1])) return 3;
    }
    return 2;
  } catch (const MeshProblem &) {
    return 0;
  }
}
// The first of the labels (numbers in a text, negative ones skipped) that no boundary element
// of a checked mesh carries (lines in 2D, triangles in 3D: the first tag), or -1: a cached
// mesh is not checked again, but the scene that uses it may name other Dirichlet labels
long runMeshLacksLabel(string *const &path, string *const &labels) {
  std::set<long> lines, triangles;                   // the labels of each kind of element, in one pass
  bool three = false;
  try {
    MeshText M = readMeshText(*path);
    for (long i = 0; i < M.elementCount; i++) {
      std::vector<std::string> w = fieldsOf(M.lines[M.elementsAt + 2 + i]);
      three = three || (w.size() >= 2 && w[1] == "4");
      if (w.size() >= 4 && (w[1] == "1" || w[1] == "2") && std::atol(w[2].c_str()) > 0)
        (w[1] == "1" ? lines : triangles).insert(std::atol(w[3].c_str()));
    }
  } catch (const MeshProblem &) {
    return 0;
  }
  const std::set<long> &have = three ? triangles : lines;
  std::stringstream in(*labels);
  long label;
  while (in >> label) if (label >= 0 && !have.count(label)) return label;
  return -1;
}

// The dimension of a gmsh .geo: 3 if it defines a Physical Volume, else 2
long runGeoDimension(string *const &path) {
  std::ifstream f(*path);
  std::string line;
  while (std::getline(f, line)) {
    const size_t comment = line.find("//");
    if (line.substr(0, comment).find("Physical Volume") != std::string::npos) return 3;
  }
  return 2;
}
// Start this FreeFEM program again, in this process (execv), with the same arguments and one
// more (solve.edp: -Ddimension=3, which FreeFEM's lexer reads as a macro definition, for a 3D
// scene); returns only if that fails (1)
const char *restartVariable = "CONTACT_SUITE_RESTART";

// FreeFem++ reads two kinds of arguments wherever they stand on its command line, before any
// script runs: its own options (-v N, -jc, -cd, ...: its getprog), and macro definitions (its
// lexer: an argument that starts with '-' or 'D' and whose first '=' comes after its fourth
// character defines the macro named by its characters from the third to that '='; so
// "-DexportSystem=..." but also "Dxcout=..."). An option value of the user's that reads like
// one (a file named "-DNAME=...") would change the script or become FreeFEM code. So every
// such argument is refused (exit 2) when this plugin is loaded, which a script does on its first
// line, before any code of it runs; the one exception is the suite's own restart
// (runRestartWith), marked by CONTACT_SUITE_RESTART = this process's id.
bool freefemMacro(const std::string &a) {
  if (a.empty() || (a[0] != '-' && a[0] != 'D')) return false;
  const size_t equal = a.find('=');
  return equal != std::string::npos && equal > 3;
}
bool freefemOption(const std::string &a, bool &takesValue) {
  static const std::set<std::string> withValue = {"-v", "-f", "-fglut", "-glut", "-gff", "-check_plugin"};
  static const std::set<std::string> alone = {"-nw", "-ng", "-wg", "-md", "-ne", "-cd", "-cdtmp", "-jc", "-ns", "-nowait",
                                              "-nc", "-log", "-wait", "-?"};
  takesValue = withValue.count(a) > 0;
  return takesValue || alone.count(a) > 0;
}
void checkCommandLine() {
  std::ifstream f("/proc/self/cmdline", std::ios::binary);
  std::vector<std::string> args;
  std::string arg;
  while (std::getline(f, arg, '\0')) args.push_back(arg);
  const char *marker = std::getenv(restartVariable);
  const bool restarted = marker && std::string(marker) == std::to_string(getpid());
  unsetenv(restartVariable);                         // not for the processes this run starts
  size_t script = 0;                                 // the script: FreeFEM's first argument that is not its option
  for (size_t i = 1; i < args.size() && script == 0; i++) {
    bool takesValue = false;
    if (freefemOption(args[i], takesValue)) i += takesValue;
    else if (!freefemMacro(args[i])) script = i;
  }
  for (size_t i = 1; i < args.size(); i++) {
    const std::string &a = args[i];
    bool takesValue = false;
    if (restarted && i + 1 == args.size() && a == "-Ddimension=3") continue;
    if (freefemMacro(a))
      fail(2, "the argument '" + a + "' would be read by FreeFem++ as a macro definition (an argument that starts with '-' or 'D' "
              + "and has an '=' after its fourth character, wherever it stands), which could change the script: the suite refuses it"
              + (i > script && script > 0 && i > 1 && args[i - 1][0] == '-' ? " (as the value of " + args[i - 1] + ": rename that file or folder)" : ""));
    if (script > 0 && i > script && freefemOption(a, takesValue))
      fail(2, "the argument '" + a + "' is an option of FreeFem++ itself, which it reads wherever it stands: give it before the "
              + "script, or, as a value of an option of the suite, rename that file or folder");
  }
}

long runRestartWith(string *const &extra) {
  std::ifstream f("/proc/self/cmdline", std::ios::binary);
  std::vector<std::string> args;
  std::string arg;
  while (std::getline(f, arg, '\0')) args.push_back(arg);
  if (args.empty()) return 1;
  args.push_back(*extra);
  setenv(restartVariable, std::to_string(getpid()).c_str(), 1);   // this argument is the suite's own (checkCommandLine)
  std::vector<char *> argv;
  for (auto &a : args) argv.push_back(const_cast<char *>(a.c_str()));
  argv.push_back(nullptr);
  std::fflush(nullptr);
  execv("/proc/self/exe", argv.data());
  return 1;
}

double runMeshExtentRatio() { return maxExtentRatio; }

long runCheckMesh(string *const &in, string *const &out, string *const &required, string *const &dirichlet,
                  string *const &what, const long &fatal) {
  try {
    if (runMeshDimension(in) == 3) checkMesh3(*in, *out, *required, *dirichlet);
    else checkMesh(*in, *out, *required, *dirichlet);
  } catch (const MeshProblem &problem) {
    if (fatal) fail(3, *what + ": " + problem.why);
    return 1;
  } catch (const WriteProblem &problem) {
    fail(7, problem.why);
  }
  return 0;
}

}  // namespace

// FreeFEM's own errors (a failed assert, an error raised by a FreeFEM function or a plugin) end
// the program through exit(), with its own message: remove what the run created then, too.
void onExit() {
  if (!(cleanPartial || cleanOut || madeParents || haveTemporary)) return;
  const bool removed = cleanPartial;
  cleanUp();
  if (removed) say("note: the run stopped on an error (above); it removed its unfinished output folder\n");
}

static void Load_Init() {
  installSignalHandlers();                          // a signal at any moment removes what the run has created so far
  std::atexit(onExit);
  checkCommandLine();
  Global.Add("runError", "(", new OneOperator2_<long, long, string *>(runError));
  Global.Add("runNote", "(", new OneOperator1_<long, string *>(runNote));
  Global.Add("runWallClock", "(", new OneOperator0<double>(runWallClock));
  Global.Add("runProcessId", "(", new OneOperator0<long>(runProcessId));
  Global.Add("runFileReadable", "(", new OneOperator1_<long, string *>(runFileReadable));
  Global.Add("runChecksum", "(", new OneOperator1_<long, string *>(runChecksum));
  Global.Add("runByteOrderMark", "(", new OneOperator1_<long, string *>(runByteOrderMark));
  Global.Add("runControlCharacter", "(", new OneOperator1_<long, string *>(runControlCharacter));
  Global.Add("runNotUtf8", "(", new OneOperator1_<long, string *>(runNotUtf8));
  Global.Add("runEnvironmentSeconds", "(", new OneOperator1_<double, string *>(runEnvironmentSeconds));
  Global.Add("runOnlyCarriageReturns", "(", new OneOperator1_<long, string *>(runOnlyCarriageReturns));
  Global.Add("runFolderOpen", "(", new OneOperator1_<long, string *>(runFolderOpen));
  Global.Add("runFileComplete", "(", new OneOperator2_<long, string *, long>(runFileComplete));
  Global.Add("runCopyFile", "(", new OneOperator2_<long, string *, string *>(runCopyFile));
  Global.Add("runCreateFile", "(", new OneOperator1_<long, string *>(runCreateFile));
  Global.Add("runRemoveFile", "(", new OneOperator1_<long, string *>(runRemoveFile));
  Global.Add("runRemoveFolder", "(", new OneOperator1_<long, string *>(runRemoveFolder));
  Global.Add("runRename", "(", new OneOperator2_<long, string *, string *>(runRename));
  Global.Add("runMakeFolders", "(", new OneOperator1_<long, string *>(runMakeFolders));
  Global.Add("runFolderFinish", "(", new OneOperator0<long>(runFolderFinish));
  Global.Add("runGmsh", "(", new OneOperator3_<long, string *, string *, string *>(runGmsh));
  Global.Add("runFreeFem", "(", new OneOperator3_<long, string *, string *, string *>(runFreeFem));
  Global.Add("runFileLines", "(", new OneOperator1_<long, string *>(runFileLines));
  Global.Add("runCacheIntact", "(", new OneOperator1_<long, string *>(runCacheIntact));
  Global.Add("runMeshExtentRatio", "(", new OneOperator0<double>(runMeshExtentRatio));
  Global.Add("runMeshDimension", "(", new OneOperator1_<long, string *>(runMeshDimension));
  Global.Add("runGeoDimension", "(", new OneOperator1_<long, string *>(runGeoDimension));
  Global.Add("runMeshLacksLabel", "(", new OneOperator2_<long, string *, string *>(runMeshLacksLabel));
  Global.Add("runRestartWith", "(", new OneOperator1_<long, string *>(runRestartWith));
  Global.Add("runSameDomain", "(", new OneOperator2_<long, string *, string *>(runSameDomain));
  Global.Add("runCheckMesh", "(", new OneOperator6_<long, string *, string *, string *, string *, string *, long>(runCheckMesh));
}

LOADFUNC(Load_Init)
