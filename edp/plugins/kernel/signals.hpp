// signals.hpp: a call into a library that sets signal handlers of its own, with the run's
// handlers put back whole after it (runtools' messages.cpp installs them: they remove what the
// run created, and hold a signal while the results are swapped into OUT). PETSc's start
// installs handlers for every signal; METIS traps SIGTERM and SIGABRT while it runs and puts
// the old ones back with signal(), whose one-shot flags would let a held signal kill the run.
#ifndef CONTACT_KERNEL_SIGNALS_HPP
#define CONTACT_KERNEL_SIGNALS_HPP
#include <csignal>

namespace contactkernel {
// (the signals of runtools' installSignalHandlers, and SIGPIPE, which it ignores)
template <class Call> auto keepingSignalHandlers(Call call) -> decltype(call()) {
  static const int signals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGPROF, SIGXCPU, SIGXFSZ,
                                SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS, SIGPIPE};
  const int count = sizeof signals / sizeof signals[0];
  struct sigaction kept[count];
  for (int q = 0; q < count; q++) sigaction(signals[q], nullptr, &kept[q]);
  auto result = call();
  for (int q = 0; q < count; q++) sigaction(signals[q], &kept[q], nullptr);
  return result;
}
}  // namespace contactkernel
#endif
