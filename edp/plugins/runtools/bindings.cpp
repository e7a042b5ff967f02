// bindings.cpp: the plugin as FreeFEM loads it (load "runtools", the first line of solve.edp
// and compare.edp): the signal and exit handlers and the command-line guard, at once, then the
// functions the scripts call, each with its file. The only file that includes FreeFEM's headers.
#include "ff++.hpp"
#include "AFunction_ext.hpp"
#include "runtools.hpp"
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fcntl.h>
#include <iostream>
#include <unistd.h>

namespace runtools {
namespace {

// x as the shortest text "%.Ng" (N = 1 to 17) gives that strtod reads back as the same double,
// its exponent without "+" and leading zeros (a tie: the one without an exponent): 0.6, not
// 0.59999999999999998; 0.001; 2e-6; 100; 1e20; 0.3333333333333333 (OUT/scene.scene's numbers)
std::string exponentTrimmed(const std::string &s) {
  const size_t e = s.find('e');
  if (e == std::string::npos) return s;
  size_t digits = e + 1;
  const std::string sign = s[digits] == '-' ? "-" : "";
  if (s[digits] == '+' || s[digits] == '-') digits++;
  while (digits + 1 < s.size() && s[digits] == '0') digits++;
  return s.substr(0, e + 1) + sign + s.substr(digits);
}
std::string shortestText(double x) {
  char text[40];
  std::string best;
  for (int digits = 1; digits <= 17; digits++) {
    std::snprintf(text, sizeof text, "%.*g", digits, x);
    if (!std::isfinite(x)) return text;
    if (std::strtod(text, nullptr) != x) continue;
    const std::string candidate = exponentTrimmed(text);
    if (best.empty() || candidate.size() < best.size()
        || (candidate.size() == best.size() && best.find('e') != std::string::npos && candidate.find('e') == std::string::npos))
      best = candidate;
  }
  return best;
}
string *runShortestText(Stack stack, const double &x) { return Add2StackOfPtr2Free(stack, new string(shortestText(x))); }

// (Th, file): a 2D mesh as a gmsh MSH 2.2 file: its vertices (z = 0), its boundary edges with
// their labels as physical and elementary tags, its triangles with their region labels, the
// numbers as a FreeFEM ofstream of precision 17 writes them (%.17g; std::to_chars, several
// times faster than the script's loop): -adapt's meshes. 0, or 1 if the file was not written whole.
long runWriteMsh22(pmesh const &mesh, string *const &file) {
  const Fem2D::Mesh &Th = *mesh;
  std::string text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n";
  char digits[64];
  auto number = [&](double x) { text.append(digits, std::to_chars(digits, digits + sizeof digits, x, std::chars_format::general, 17).ptr); };
  auto integer = [&](long n) { text.append(digits, std::to_chars(digits, digits + sizeof digits, n).ptr); };
  integer(Th.nv); text += '\n';
  for (int i = 0; i < Th.nv; i++) {
    integer(i + 1); text += ' '; number(Th(i).x); text += ' '; number(Th(i).y); text += " 0\n";
  }
  text += "$EndNodes\n$Elements\n";
  integer((long)Th.neb + Th.nt); text += '\n';
  for (int k = 0; k < Th.neb; k++) {
    const Fem2D::BoundaryEdge &e = Th.bedges[k];
    integer(k + 1); text += " 1 2 "; integer(e.lab); text += ' '; integer(e.lab);
    for (int j = 0; j < 2; j++) { text += ' '; integer(Th(e[j]) + 1); }
    text += '\n';
  }
  for (int k = 0; k < Th.nt; k++) {
    const Fem2D::Triangle &t = Th[k];
    integer((long)Th.neb + k + 1); text += " 2 2 "; integer(t.lab); text += ' '; integer(t.lab);
    for (int j = 0; j < 3; j++) { text += ' '; integer(Th(t[j]) + 1); }
    text += '\n';
  }
  text += "$EndElements\n";
  const int fd = open(file->c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
  if (fd < 0) return 1;
  const bool ok = writeAll(fd, text.data(), text.size()) && fsync(fd) == 0;   // on the disk, as the mesh checker's files
  return close(fd) == 0 && ok ? 0 : 1;
}

// FreeFEM has no wall clock (its clock() is CPU time): progress lines and the timings of a run
double runWallClock() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
long runProcessId() { return (long)getpid(); }
// (on): 1 sends the standard output to /dev/null, 0 brings it back: the companion run of the
// error estimates (edp/lib/companion.idp) catches its own failures, whose FreeFEM messages
// would otherwise print as if the run had failed
long runQuiet(const long &on) {
  static int saved = -1;
  std::cout.flush();
  std::fflush(stdout);
  if (on && saved < 0) {
    saved = dup(1);
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) { dup2(null, 1); close(null); }
  }
  else if (!on && saved >= 0) {
    dup2(saved, 1);
    close(saved);
    saved = -1;
  }
  return 0;
}
// the seconds an environment variable gives (a number >= 0), -1 when it is unset or empty;
// another value is refused (exit 2) rather than read as 0
double runEnvironmentSeconds(string *const &name) {
  const char *text = std::getenv(name->c_str());
  if (!text || !*text) return -1;
  char *end = nullptr;
  const double value = std::strtod(text, &end);
  if (!*text || *end || !std::isfinite(value) || value < 0)
    fail(2, "the environment variable " + *name + " = '" + text + "' is not a number of seconds >= 0");
  return value;
}
string *newString(Stack stack, const std::string &text) { return Add2StackOfPtr2Free(stack, new string(text)); }
// the versions of what makes a run (summary.txt, the outputs' headers)
string *runSuiteVersion(Stack stack, string *const &repository) { return newString(stack, suiteVersion(*repository)); }
string *runGmshVersion(Stack stack, string *const &cacheFolder) { return newString(stack, gmshVersion(*cacheFolder)); }
// state.cpp: the state file of -restart
string *runStateKey(Stack stack, string *const &path, string *const &key) { return newString(stack, stateKey(*path, *key)); }
long runStateValues(string *const &path, string *const &quantity, KN<double> *const &out) {
  const std::vector<double> values = stateValues(*path, *quantity);
  out->resize((long)values.size());
  for (size_t i = 0; i < values.size(); i++) (*out)[(long)i] = values[i];
  return (long)values.size();
}

// Global.Add for a function of 0 to 3 arguments, its FreeFEM operator from its type
template <class R> void add(const char *name, R (*f)()) { Global.Add(name, "(", new OneOperator0<R>(f)); }
template <class R, class A> void add(const char *name, R (*f)(const A &)) { Global.Add(name, "(", new OneOperator1_<R, A>(f)); }
template <class R, class A, class B> void add(const char *name, R (*f)(const A &, const B &)) {
  Global.Add(name, "(", new OneOperator2_<R, A, B>(f));
}
template <class R, class A, class B, class C> void add(const char *name, R (*f)(const A &, const B &, const C &)) {
  Global.Add(name, "(", new OneOperator3_<R, A, B, C>(f));
}

}  // namespace
}  // namespace runtools

static void Load_Init() {
  using namespace runtools;
  installSignalHandlers();                         // from the start: a signal at any moment removes what the run created
  registerRank();                                  // -ranks N: the launching run can stop this rank at once
  std::atexit(onExit);
  checkCommandLine();                              // before any code of the script runs
  // messages.cpp: exit codes 2 option, 3 scene, mesh or suite file, 7 output folder or file
  add("runError", runError);                       // (code, message): remove what the run created, "error: message", exit code
  add("runNote", runNote);                         // (message): one line on the standard error
  add("runControlCharacter", runControlCharacter); // (text): 1 if it holds a control character or a line separator
  add("runNotUtf8", runNotUtf8);                   // (text): 1 if it is not valid UTF-8
  // here
  add("runWallClock", runWallClock);               // (): wall-clock seconds (steady clock)
  add("runProcessId", runProcessId);               // (): this process's id
  add("runQuiet", runQuiet);                       // (on): 1 the standard output to /dev/null, 0 back
  add("runEnvironmentSeconds", runEnvironmentSeconds);   // (name): the seconds it gives, -1 if unset
  Global.Add("runShortestText", "(", new OneOperator1s_<string *, double>(runShortestText));   // (x): the shortest text that reads back as x
  // runfolder.cpp: the run folder (docs/design.md, "Output files")
  add("runFigureNames", runFigureNames);           // (path): the figures a run folder's figures/ may hold (edp/figures.txt)
  add("runFolderOpen", runFolderOpen);             // (out): lock OUT, check it may be replaced, make OUT.partial.<pid>
  add("runFolderFinish", runFolderFinish);         // (): run.complete, then OUT.partial.<pid> exchanged with OUT
  // files.cpp
  add("runCreateFile", runCreateFile);             // (path): an empty file, or exit 7
  add("runFileComplete", runFileComplete);         // (path, lines): exactly that many complete lines, on the disk, or exit 7
  add("runFileReadable", runFileReadable);         // (path): 1 if a regular file this process can read
  add("runFileLines", runFileLines);               // (path): its line feeds, -1 if unreadable
  add("runChecksum", runChecksum);                 // (path): its POSIX cksum, -1 if unreadable
  add("runCacheIntact", runCacheIntact);           // (path): 1 if PATH.cksum holds its checksum
  add("runByteOrderMark", runByteOrderMark);       // (path): 3 if it starts with a UTF-8 byte order mark, else 0
  add("runOnlyCarriageReturns", runOnlyCarriageReturns);   // (path): 1 if its line ends are carriage returns only
  add("runCopyFile", runCopyFile);                 // (from, to): 0, or 1 (no partial copy left)
  add("runRename", runRename);                     // (from, to): 0, or 1
  add("runRemoveFile", runRemoveFile);             // (path): 0, or 1
  add("runRemoveFolder", runRemoveFolder);         // (path): the folder and all it holds
  add("runMakeFolders", runMakeFolders);           // (path): mkdir -p; 0, or 1
  // spawn.cpp
  add("runGmsh", runGmsh);                         // (geo, out, "NAME VALUE ..."): gmsh's exit status, 127 if it cannot start
  add("runLaunchRanks", runLaunchRanks);           // (count, dimension): this run again on count MPI ranks; returns 1 only if mpirun cannot start
  add("runRestartWith", runRestartWith);           // (argument): this program again with it; returns 1 only if that fails
  Global.Add("runSuiteVersion", "(", new OneOperator1s_<string *, string *>(runSuiteVersion));   // (repository): git describe --always --dirty, or its VERSION
  Global.Add("runGmshVersion", "(", new OneOperator1s_<string *, string *>(runGmshVersion));  // (cache folder): gmsh --version
  // state.cpp
  Global.Add("runStateKey", "(", new OneOperator2s_<string *, string *, string *>(runStateKey));   // (path, key): a "# key value" header line's value, "" if none
  Global.Add("runStateValues", "(", new OneOperator3_<long, string *, string *, KN<double> *>(runStateValues));   // (path, quantity, out): its values; exit 3 on a malformed file
  // meshcheck.cpp, samedomain.cpp
  Global.Add("runCheckMesh", "(", new OneOperator6_<long, string *, string *, string *, string *, string *, long>(runCheckMesh));
  //   (in, out, required, dirichlet, what, fatal): an MSH 2.2 file checked and written to out; exit 3, or 1 when not fatal
  add("runMeshExtentRatio", runMeshExtentRatio);   // (): 1e8, the largest extent / shortest edge of a mesh
  add("runMeshDimension", runMeshDimension);       // (path): 3 if the mesh has tetrahedra, 2 if not, 0 if unreadable
  add("runGeoDimension", runGeoDimension);         // (path): 3 if the .geo defines a Physical Volume, else 2
  Global.Add("runWriteMsh22", "(", new OneOperator2_<long, pmesh, string *>(runWriteMsh22));   // (Th, file): a 2D mesh as MSH 2.2; 0, or 1
  add("runMeshLacksLabel", runMeshLacksLabel);     // (path, labels): the first label no boundary element carries, or -1
  add("runSameDomain", runSameDomain);             // (a, b): exit 2 unless the meshes cover one domain with the same labels
}

LOADFUNC(Load_Init)
