// runtools.cpp: what a run needs from the operating system, as a FreeFEM plugin (load
// "runtools"), built by ./run.sh into edp/plugins/build/ like the kernel. FreeFEM's own
// cerr writes to the standard output, and its exit() prints trace lines; its clock() is CPU
// time and time() has a resolution of one second.
//
// FreeFEM functions:
//   runError(int code, string message)   "error: message" on stderr (nothing when empty),
//       then exit with code (no FreeFEM trace)
//   runWallClock()                       wall-clock seconds (steady clock)
//   runFileReadable(string path)         1 if path is a regular file this process can read
#include "ff++.hpp"
#include "AFunction_ext.hpp"
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

namespace {

// FreeFEM points std::cerr at the standard output: write to file descriptor 2 itself
void toStderr(const std::string &text) {
  std::fflush(nullptr);
  std::fputs(text.c_str(), stderr);
  std::fflush(stderr);
}

long runError(const long &code, string *const &message) {
  std::cout.flush();
  if (!message->empty()) toStderr("error: " + *message + "\n");
  std::fflush(nullptr);
  std::_Exit((int)code);
  return code;
}

long runFileReadable(string *const &path) {
  struct stat status;
  return stat(path->c_str(), &status) == 0 && S_ISREG(status.st_mode) && access(path->c_str(), R_OK) == 0;
}

double runWallClock() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

static void Load_Init() {
  Global.Add("runError", "(", new OneOperator2_<long, long, string *>(runError));
  Global.Add("runWallClock", "(", new OneOperator0<double>(runWallClock));
  Global.Add("runFileReadable", "(", new OneOperator1_<long, string *>(runFileReadable));
}

LOADFUNC(Load_Init)
