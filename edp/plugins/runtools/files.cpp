// files.cpp: the file operations the scripts need, by system calls: FreeFEM can neither test
// nor copy, rename or remove a file, and a shell would see the user's names. Also the folder
// helpers of the run folder (runfolder.cpp), whose removal of a tree the signal handler uses.
#include "runtools.hpp"
#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <dirent.h>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace runtools {

namespace {
// getdents64 rather than readdir: readdir may allocate, which a signal handler may not
struct Dirent64 { std::uint64_t ino; std::int64_t off; unsigned short reclen; unsigned char type; char name[]; };

// Deleting while reading a folder may skip entries: it is read again until empty.
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
}  // namespace

void removeTree(const char *path) { removeTreeAt(AT_FDCWD, path, 0); }

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

// mkdir -p; made(folder) is told of each folder made here, so that a failed run can remove it
bool makeFolders(const std::string &path, void (*made)(const std::string &)) {
  std::string partial;
  std::stringstream in(path);
  std::string part;
  if (!path.empty() && path[0] == '/') partial = "/";
  while (std::getline(in, part, '/')) {
    if (part.empty()) continue;
    partial += part;
    if (mkdir(partial.c_str(), 0777) == 0) { if (made) made(partial); }
    else if (errno != EEXIST) return false;
    partial += "/";
  }
  struct stat status;
  return stat(path.c_str(), &status) == 0 && S_ISDIR(status.st_mode);
}

bool writeAll(int fd, const char *data, size_t size) {
  for (size_t done = 0; done < size;) {
    const ssize_t w = write(fd, data + done, size - done);
    if (w <= 0) return false;
    done += w;
  }
  return true;
}

// POSIX cksum (CRC-32, polynomial 0x04C11DB7, then the length), as `cksum FILE` prints it: the
// mesh cache's checksums, which run.sh and a user can check with cksum
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

// ---------------------------------------------------------------- the FreeFEM functions
long runFileReadable(std::string *const &path) {
  struct stat status;
  return stat(path->c_str(), &status) == 0 && S_ISREG(status.st_mode) && access(path->c_str(), R_OK) == 0;
}
long runChecksum(std::string *const &path) { return (long)posixChecksum(*path); }
// a cached file is used only if its NAME.cksum holds its checksum and nothing else: a cache
// cut short by a full disk or a killed gmsh is made again
long runCacheIntact(std::string *const &path) {
  std::ifstream f(*path + ".cksum");
  long long recorded = -1;
  if (!(f >> recorded) || recorded < 0) return 0;
  std::string rest;
  if (f >> rest) return 0;
  return posixChecksum(*path) == recorded ? 1 : 0;
}
// FreeFEM's getline keeps a byte order mark in the first line; 3 is its length
long runByteOrderMark(std::string *const &path) {
  std::ifstream f(*path, std::ios::binary);
  char head[3] = {0, 0, 0};
  f.read(head, 3);
  return f.gcount() == 3 && std::memcmp(head, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
}
// old Mac line ends (carriage returns, no line feed): FreeFEM's getline would read one line
long runOnlyCarriageReturns(std::string *const &path) {
  std::ifstream f(*path, std::ios::binary);
  bool cr = false;
  char ch;
  while (f.get(ch)) { if (ch == '\n') return 0; cr = cr || ch == '\r'; }
  return cr ? 1 : 0;
}
// the line feeds of a file, -1 if it cannot be read (a written file's check)
long runFileLines(std::string *const &path) {
  int fd = open(path->c_str(), O_RDONLY);
  if (fd < 0) return -1;
  char last;
  const long count = lineFeeds(fd, last);
  close(fd);
  return count;
}
// A file this run wrote: exactly `lines` complete lines, then on the disk. FreeFEM's ofstream
// does not report a failed write (a full disk, an I/O error): a short file is found here.
long runFileComplete(std::string *const &path, const long &lines) {
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
// FreeFEM stops with its own error when its ofstream cannot open a file (no inode left, a path
// too long, ...): the file is made here first, so that the run says why, with exit 7
long runCreateFile(std::string *const &path) {
  const int fd = open(path->c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
  if (fd < 0 || close(fd) != 0) fail(7, "cannot create " + *path + ": " + errorText());
  return 0;
}
// 0, or 1 if the copy is not whole and on the disk (then it is removed)
long runCopyFile(std::string *const &from, std::string *const &to) {
  int in = open(from->c_str(), O_RDONLY);
  if (in < 0) return 1;
  int out = open(to->c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
  if (out < 0) { close(in); return 1; }
  char buffer[65536];
  ssize_t n;
  bool ok = true;
  while (ok && (n = read(in, buffer, sizeof buffer)) > 0) ok = writeAll(out, buffer, n);
  ok = ok && n == 0 && fsync(out) == 0;
  close(in);
  ok = close(out) == 0 && ok;
  if (!ok) unlink(to->c_str());
  return ok ? 0 : 1;
}
long runRemoveFile(std::string *const &path) { forgetTemporary(*path); return unlink(path->c_str()) == 0 ? 0 : 1; }
long runRemoveFolder(std::string *const &path) { removeTree(path->c_str()); return 0; }
long runRename(std::string *const &from, std::string *const &to) {
  const bool ok = rename(from->c_str(), to->c_str()) == 0;
  if (ok) forgetTemporary(*from);
  return ok ? 0 : 1;
}
long runMakeFolders(std::string *const &path) { return makeFolders(*path) ? 0 : 1; }

}  // namespace runtools
