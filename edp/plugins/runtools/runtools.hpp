// runtools.hpp: what the parts of the plugin runtools share. The plugin gives the scripts
// what FreeFEM lacks or gets wrong: its cerr writes to the standard output, its exit() prints
// trace lines, its ofstream hides write errors, it has no wall clock, and it would hand a
// value of the user's to a shell. Everything here uses system calls and argument vectors
// instead; no shell ever sees a value.
//
// The parts (run.sh compiles every .cpp of this folder into runtools.so):
//   messages.cpp    errors, notes, the signal and exit handlers
//   runfolder.cpp   the run folder as one transaction, and what a failure removes
//   files.cpp       file operations for the scripts and the run folder
//   spawn.cpp       gmsh, the 3D restart; the command-line guard
//   meshcheck.cpp   the MSH 2.2 checker, 2D and 3D
//   samedomain.cpp  whether two runs' meshes cover one domain (compare.edp)
//   bindings.cpp    what FreeFEM loads: the handlers, the guard, the functions of the scripts
// Only bindings.cpp includes FreeFEM's headers: the functions the scripts call take FreeFEM's
// types, which are standard ones (its string is std::string, its int long, its real double).
#ifndef RUNTOOLS_HPP
#define RUNTOOLS_HPP

#include <csignal>
#include <map>
#include <string>
#include <sys/types.h>
#include <utility>
#include <vector>

namespace runtools {

// ---------------------------------------------------------------- messages.cpp
// Exit codes: 2 option, 3 scene, mesh or suite file, 7 output folder or file.
[[noreturn]] void fail(int code, const std::string &message);
std::string shown(const std::string &text);        // a message as a terminal may show it
void toStderr(const std::string &text);
std::string errorText();                           // strerror(errno)
bool validUtf8(const std::string &text);
bool hasControlCharacter(const std::string &text);
void installSignalHandlers();
void defaultSignals();                             // in a forked child, before exec (system calls only)
void onExit();

// ---------------------------------------------------------------- runfolder.cpp
// What the run created and a failure removes. The signal handler reads it, so it is kept in
// fixed buffers and sig_atomic_t flags, and removed with system calls only.
extern volatile pid_t runningChild;                // a gmsh to stop
extern volatile pid_t runningRanks;                // -ranks N: the mpirun this run waits for (spawn.cpp)
extern volatile int ranksFileFd;                   // ... and the file where its ranks write their ids (runfolder.cpp)
void stopRanks();                                  // SIGTERM to every rank and to mpirun, then waits for mpirun
int ranksEnded(int code);                          // ... once mpirun ended: what a killed rank left removed, said; the exit code
extern volatile sig_atomic_t resultsInPlace;       // the results are in OUT
extern volatile sig_atomic_t holdSignals, heldSignal;   // a signal held (not a crash) until the work under way is done
const char *outFolderText();                       // OUT (for the signal handler)
void rememberTemporary(const std::string &path);   // a file this run writes outside OUT
void forgetTemporary(const std::string &path);
bool cleanUp();                                    // true if it removed the unfinished output folder

// ---------------------------------------------------------------- files.cpp
bool listFolder(const std::string &path, std::vector<std::pair<std::string, bool>> &entries);   // (name, is a folder)
bool makeFolders(const std::string &path, void (*made)(const std::string &) = nullptr);
void removeTree(const char *path);                 // system calls only
bool writeAll(int fd, const char *data, size_t size);
long long posixChecksum(const std::string &path);

// ---------------------------------------------------------------- spawn.cpp
void checkCommandLine();
void registerRank();                               // a rank of -ranks N: its id into the launching run's file
void tellLauncher(const std::string &line);        // ... and the first rank's folders (runfolder.cpp, ranksEnded)
std::string suiteVersion(const std::string &repository);   // git describe, or VERSION, or unknown
std::string gmshVersion(const std::string &cacheFolder);    // gmsh --version (kept in cacheFolder)
// ---------------------------------------------------------------- state.cpp
std::string stateKey(const std::string &path, const std::string &key);
std::vector<double> stateValues(const std::string &path, const std::string &quantity);

// ---------------------------------------------------------------- the FreeFEM functions (bindings.cpp adds them)
// messages.cpp
long runError(const long &code, std::string *const &message);
long runNote(std::string *const &message);
long runControlCharacter(std::string *const &text);
long runNotUtf8(std::string *const &text);
// runfolder.cpp
long runFigureNames(std::string *const &path);
long runFolderOpen(std::string *const &out);
long runFolderFinish();
// files.cpp
long runCreateFile(std::string *const &path);
long runFileComplete(std::string *const &path, const long &lines);
long runFileReadable(std::string *const &path);
long runChecksum(std::string *const &path);
long runCacheIntact(std::string *const &path);
long runByteOrderMark(std::string *const &path);
long runOnlyCarriageReturns(std::string *const &path);
long runFileLines(std::string *const &path);
long runCopyFile(std::string *const &from, std::string *const &to);
long runRemoveFile(std::string *const &path);
long runRemoveFolder(std::string *const &path);
long runRename(std::string *const &from, std::string *const &to);
long runMakeFolders(std::string *const &path);
// spawn.cpp
long runGmsh(std::string *const &geo, std::string *const &out, std::string *const &numbers);
long runRestartWith(std::string *const &extra);
long runLaunchRanks(const long &count, const long &dimension);   // -ranks N: this run on N MPI ranks (mpirun)
// meshcheck.cpp
long runCheckMesh(std::string *const &in, std::string *const &out, std::string *const &required,
                  std::string *const &dirichlet, std::string *const &what, const long &fatal);
double runMeshExtentRatio();
long runMeshDimension(std::string *const &path);
long runGeoDimension(std::string *const &path);
long runMeshLacksLabel(std::string *const &path, std::string *const &labels);
// samedomain.cpp
long runSameDomain(std::string *const &pathA, std::string *const &pathR);

// ---------------------------------------------------------------- meshcheck.cpp, for samedomain.cpp
// A gmsh MSH 2.2 ASCII file as lines, with where its $Nodes and $Elements sections start and
// their counts; a problem with it is thrown as a MeshProblem.
struct MeshProblem { std::string why; };
struct MeshText {
  std::vector<std::string> lines;
  long nodesAt = -1, elementsAt = -1, nodeCount = 0, elementCount = 0;
};
MeshText readMeshText(const std::string &path);
// one line of $Nodes: its id (new: entered in index by the caller) and coordinates
void readNode(const std::string &text, const std::map<long, long> &index, long &id, double &x, double &y, double &z);
std::vector<std::string> fieldsOf(const std::string &text);
std::string numberText(double x);

}  // namespace runtools

#endif
