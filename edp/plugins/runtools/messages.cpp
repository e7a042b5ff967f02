// messages.cpp: how a run says what went wrong, and how it stops. Every failure with exit 2
// to 9 is one line "error: MESSAGE" on the standard error (docs/design.md, "Exit codes and
// failure messages"); a signal or FreeFEM's own exit() still removes what the run created.
#include "runtools.hpp"
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <unistd.h>

namespace runtools {

// FreeFEM points std::cerr at the standard output, which a caller may keep for results: the
// standard error is file descriptor 2 itself
void toStderr(const std::string &text) {
  std::fflush(nullptr);
  std::fputs(text.c_str(), stderr);
  std::fflush(stderr);
}

std::string errorText() { return std::strerror(errno); }

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
// a name the suite's own tools could not read back, nor show, is refused
bool validUtf8(const std::string &s) {
  for (size_t i = 0; i < s.size();) { const size_t n = utf8Length(s, i); if (n == 0) return false; i += n; }
  return true;
}

// Control characters (below 0x20, 0x7F, U+0080 to U+009F with U+0085) and the Unicode line and
// paragraph separators U+2028, U+2029 each end a line for some reader of the outputs (Python's
// splitlines, for one), which echo the option values: no value may hold one.
bool hasControlCharacter(const std::string &text) {
  for (size_t i = 0; i < text.size(); i++) {
    const unsigned char c = text[i], next = i + 1 < text.size() ? text[i + 1] : 0, third = i + 2 < text.size() ? text[i + 2] : 0;
    if (c < 0x20 || c == 0x7F || (c == 0xC2 && next >= 0x80 && next <= 0x9F) || (c == 0xE2 && next == 0x80 && (third == 0xA8 || third == 0xA9)))
      return true;
  }
  return false;
}

// A message echoes values of the user's, which may hold anything: bytes that are not UTF-8 and
// control characters (but line ends) are shown as \xHH, the C1 controls (U+0080 to U+009F), the
// line and paragraph separators U+2028, U+2029 and the byte-order mark U+FEFF as \uHHHH, so
// that a terminal shows them and does not act on them, and no reader splits the line there; a word (a value, a path) longer than longWord bytes is cut in its middle,
// with its length, and a message longer than longMessage bytes too: a megabyte value is not
// echoed whole.
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
    const unsigned char next = n > 1 ? text[i + 1] : 0, third = n > 2 ? text[i + 2] : 0;
    unsigned code = 0;
    if (n == 2 && c == 0xC2 && next <= 0x9F) code = next;                                   // C1 controls, U+0085
    else if (n == 3 && c == 0xE2 && next == 0x80 && (third == 0xA8 || third == 0xA9)) code = 0x2000 + third - 0x80;
    else if (n == 3 && c == 0xEF && next == 0xBB && third == 0xBF) code = 0xFEFF;
    if (code) { char u[12]; std::snprintf(u, sizeof u, "\\u%04X", code); word += u; i += n; continue; }
    word += text.substr(i, n); i += n;
  }
  flush();
  if (out.size() > longMessage) {
    size_t head = 800, tail = 300;
    while (head > 0 && ((unsigned char)out[head] & 0xC0) == 0x80) head--;
    while (tail > 0 && ((unsigned char)out[out.size() - tail] & 0xC0) == 0x80) tail--;
    out = out.substr(0, head) + " ...(" + std::to_string(out.size() - head - tail) + " bytes cut)... " + out.substr(out.size() - tail);
  }
  return out;
}

// A rank of a run under mpirun other than the first (-ranks N): its notes are the first
// rank's, which says them once
bool quietRank() {
  const char *rank = std::getenv("OMPI_COMM_WORLD_RANK");
  return rank && std::string(rank) != "0";
}

const bool otherRank = quietRank();                // (read once, as the plugin loads: the signal handler may not call getenv)
// a rank of a run that runLaunchRanks started: that run says an interruption (ranksEnded), which
// mpirun, stopped too, may not pass on from a rank
const bool launchedRank = std::getenv("CONTACT_SUITE_RANK_IDS") && std::getenv("OMPI_COMM_WORLD_SIZE");

// _Exit: FreeFEM's exit handlers would print trace lines after the message. Another rank than
// the first waits 3 s before it says why and stops: where every rank checks the same data the
// first fails the same way and says it, and mpirun stops the others meanwhile; a failure of
// that rank alone is said, with its rank.
[[noreturn]] void fail(int code, const std::string &message) {
  std::cout.flush();
  cleanUp();
  if (otherRank) {                                 // said after 3 s, if mpirun has not stopped this rank by then
    std::fflush(nullptr);
    sleep(3);
    if (!message.empty()) toStderr("error: (rank " + std::string(std::getenv("OMPI_COMM_WORLD_RANK")) + ") " + shown(message) + "\n");
    std::fflush(nullptr);
    std::_Exit(code);
  }
  if (!message.empty()) toStderr("error: " + shown(message) + "\n");
  std::fflush(nullptr);
  std::_Exit(code);
}

long runError(const long &code, std::string *const &message) { fail((int)code, *message); }
// progress and the Newton log: unbuffered, so that they interleave with FreeFEM's own output
long runNote(std::string *const &message) {
  if (otherRank) return 0;
  toStderr(shown(*message) + "\n");
  return 0;
}
long runControlCharacter(std::string *const &text) { return hasControlCharacter(*text) ? 1 : 0; }
long runNotUtf8(std::string *const &text) { return validUtf8(*text) ? 0 : 1; }

// ---------------------------------------------------------------- signals and FreeFEM's exit()
namespace {

// a crash is a bug, or too little memory: FreeFEM does not check every allocation
const char *crashName(int signal) {
  switch (signal) {
    case SIGSEGV: return "SIGSEGV"; case SIGBUS: return "SIGBUS"; case SIGFPE: return "SIGFPE"; case SIGILL: return "SIGILL";
    case SIGABRT: return "SIGABRT"; case SIGTRAP: return "SIGTRAP"; case SIGSYS: return "SIGSYS"; default: return nullptr;
  }
}
void say(const char *text) { if (write(2, text, std::strlen(text)) < 0) {} }

struct sigaction handlerAction = {};               // onSignal's, as installSignalHandlers sets it
// System calls only (the run may be stopped anywhere, inside malloc too). Then the signal's
// default action, so that the caller sees the exit status 128 + signal.
void onSignal(int signal) {
  if (holdSignals && !crashName(signal)) {         // raised again once the work under way is done: this handler kept for it
    heldSignal = signal;                           // (a library's signal() may have made it one-shot: METIS's does)
    sigaction(signal, &handlerAction, nullptr);
    return;
  }
  const bool launcher = runningRanks > 0;         // -ranks N: the run that started mpirun (it says what happened: ranksEnded)
  const bool removed = cleanUp();                  // (the launcher: its ranks stopped, mpirun ended)
  if (resultsInPlace || (launcher && ranksEnded(128 + signal) == 0)) {   // nothing left to stop: the results are whole
    if (!launcher && !launchedRank) { say("note: the run had finished: its results are complete in "); say(outFolderText()); say("\n"); }
    _exit(0);
  }
  if (!launcher) {                                 // (the launcher's: said by ranksEnded)
    if (signal == SIGXFSZ) {                       // a file could not be written: the output folder's exit code
      say("error: a file of the run grew past the file-size limit (ulimit -f; SIGXFSZ)");
      say(removed ? ": the run removed its unfinished output folder\n" : "\n");
      _exit(7);
    }
    // (ranks.cpp's rankFail: an error of PETSc on a rank, said already; its exit code, not a signal's)
    const char *rankFailed = signal == SIGTERM ? std::getenv("CONTACT_SUITE_RANK_FAILED") : nullptr;
    if (rankFailed) _exit(std::atoi(rankFailed) > 0 ? std::atoi(rankFailed) : 3);
    const char *crash = crashName(signal);
    if (crash) { say("error: the run crashed ("); say(crash); say(": a bug, or too little memory)"); }
    else if (!otherRank && !launchedRank) say("interrupted");   // (another rank of -ranks: mpirun stops it after the first rank failed)
    if (crash || (!otherRank && !launchedRank)) say(removed ? ": the run removed its unfinished output folder\n" : "\n");
  }
  struct sigaction action = {};
  action.sa_handler = SIG_DFL;
  sigaction(signal, &action, nullptr);
  raise(signal);                                   // blocked in here: delivered on return
}

}  // namespace

// Every signal that ends a process, from the plugin's load on. The handler runs on a stack of
// its own, so that a stack overflow (SIGSEGV) is handled too. A closed standard output
// (SIGPIPE) does not stop a run: its results go to files.
namespace {
// (kernel/signals.hpp keeps the same list around library calls that set handlers of their own)
const int handledSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGPROF, SIGXCPU, SIGXFSZ,
                              SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS};
}
void installSignalHandlers() {
  static char alternate[1 << 18];                  // removeTree's buffers, 8 folder levels deep
  stack_t stack = {};
  stack.ss_sp = alternate;
  stack.ss_size = sizeof alternate;
  sigaltstack(&stack, nullptr);
  struct sigaction &action = handlerAction;
  action.sa_handler = onSignal;
  action.sa_flags = SA_ONSTACK | SA_RESTART;
  sigfillset(&action.sa_mask);                     // (a second signal waits until the handler has done its work)
  for (int signal : handledSignals) sigaction(signal, &action, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
}
// A child this run forks (gmsh, mpirun), before its exec: the signals' default actions (the
// run's handler is the run's: in the child it would say "interrupted" a second time); the
// parent blocks every signal across the fork, until it knows the child (system calls only)
void defaultSignals() {
  struct sigaction action = {};
  action.sa_handler = SIG_DFL;
  sigemptyset(&action.sa_mask);
  for (int signal : handledSignals) sigaction(signal, &action, nullptr);
  sigaction(SIGPIPE, &action, nullptr);
}

// FreeFEM's own errors (a failed assert, an error raised by a FreeFEM function or a plugin) end
// the program through exit(), after its own message: what the run created goes then, too.
void onExit() {
  if (cleanUp()) say("note: the run stopped on an error (above); it removed its unfinished output folder\n");
}

}  // namespace runtools
