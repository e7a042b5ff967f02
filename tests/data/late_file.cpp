// late_file.cpp: an LD_PRELOAD shim for a test of the run folder (tests/run_tests.sh, "a file
// put into OUT just before the swap"). When the run exchanges OUT.partial.<pid> and OUT (the
// system call renameat2 with RENAME_EXCHANGE, made through syscall()), the shim first writes
// the file named by $LATE_FILE into OUT, as a user could between the run's last check of OUT
// and the exchange. Every system call then goes on unchanged.
//   g++ -O2 -fPIC -shared late_file.cpp -o late_file.so -ldl
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <dlfcn.h>
#include <string>
#include <sys/syscall.h>

extern "C" long syscall(long number, ...) {
  va_list arguments;
  va_start(arguments, number);
  long a[6];
  for (long &x : a) x = va_arg(arguments, long);     // as glibc's syscall() does: six argument registers
  va_end(arguments);
  static auto real = reinterpret_cast<long (*)(long, ...)>(dlsym(RTLD_NEXT, "syscall"));
  const char *late = std::getenv("LATE_FILE");
  if (number == SYS_renameat2 && a[4] == 2 /* RENAME_EXCHANGE */ && late) {
    const std::string path = std::string(reinterpret_cast<const char *>(a[3])) + "/" + late;
    if (FILE *f = std::fopen(path.c_str(), "w")) { std::fputs("the user's late notes\n", f); std::fclose(f); }
  }
  return real(number, a[0], a[1], a[2], a[3], a[4], a[5]);
}
