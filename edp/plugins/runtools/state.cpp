// state.cpp: the state file of a run, OUT/state.txt, read by a run started with -restart OUT
// (docs/design.md, "Restart"). Its lines: the run's "# name value" lines (the options, the
// versions, then restart_step, restart_time, mesh_checksum, dimension), the column header
// "# quantity index value", then one row per value: the quantity (u, v, fixed, multiplier,
// slot_velocity), its index (0, 1, ... in order) and the value (17 digits). Read strictly: a
// row of another form, an index out of order, a value that is not a finite number, a last line
// without its line end (a truncated file) stop the run with exit 3, naming the file and line.
#include "runtools.hpp"
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>

namespace runtools {

namespace {
const char *columnHeader = "# quantity index value";
const char *quantities[] = {"u", "v", "fixed", "multiplier", "slot_velocity"};

[[noreturn]] void stateFail(const std::string &path, long line, const std::string &what) {
  fail(3, shown(path) + (line > 0 ? ":" + std::to_string(line) : "") + ": " + what
          + " (the state a run writes for -restart: rebuild it by running that case again)");
}

// Every line of the file, each checked to end with a line feed. Read once per run (a run reads
// its state many times: every read sees the same file, even if its folder is replaced meanwhile).
const std::vector<std::string> &stateLines(const std::string &path) {
  static std::map<std::string, std::vector<std::string>> read;
  auto known = read.find(path);
  if (known != read.end()) return known->second;
  std::ifstream f(path, std::ios::binary);
  if (!f) stateFail(path, 0, "cannot be read");
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (text.empty()) stateFail(path, 0, "is empty");
  if (text.back() != '\n') stateFail(path, 0, "its last line has no line end: the file is truncated");
  if (text.find('\0') != std::string::npos) stateFail(path, 0, "holds a NUL byte: not a text file");
  if (text.find('\r') != std::string::npos) stateFail(path, 0, "has carriage returns (CR LF line ends): not the file a run writes");
  std::vector<std::string> lines;
  size_t start = 0;
  for (size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1) lines.push_back(text.substr(start, end - start));
  return read[path] = lines;
}
}  // namespace

// The value of the header line "# key value" (one word) of the state file at path; "" when it
// has none; a key given twice stops the run (exit 3).
std::string stateKey(const std::string &path, const std::string &key) {
  const std::vector<std::string> &lines = stateLines(path);
  std::string value;
  bool found = false;
  for (size_t k = 0; k < lines.size(); k++) {
    if (lines[k].empty() || lines[k][0] != '#') break;
    const std::vector<std::string> w = fieldsOf(lines[k].substr(1));
    if (w.size() == 2 && w[0] == key) {
      if (found) stateFail(path, (long)k + 1, "a second line '# " + key + "'");
      found = true;
      value = w[1];
    }
  }
  return value;
}

// The values of quantity, in the order of their indexes; the whole file is checked.
std::vector<double> stateValues(const std::string &path, const std::string &quantity) {
  const std::vector<std::string> &lines = stateLines(path);
  size_t k = 0;
  while (k < lines.size() && !lines[k].empty() && lines[k][0] == '#') k++;
  if (k == 0 || lines[k - 1] != columnHeader)
    stateFail(path, (long)k, std::string("the last header line is not '") + columnHeader + "'");
  std::vector<double> values;
  std::vector<long> next(sizeof quantities / sizeof *quantities, 0);
  for (; k < lines.size(); k++) {
    const std::vector<std::string> w = fieldsOf(lines[k]);
    const long line = (long)k + 1;
    if (w.size() != 3) stateFail(path, line, "not a row 'quantity index value'");
    size_t q = 0;
    while (q < next.size() && w[0] != quantities[q]) q++;
    if (q == next.size()) stateFail(path, line, "unknown quantity '" + w[0] + "' (u, v, fixed, multiplier, slot_velocity)");
    char *end = nullptr;
    errno = 0;
    const long index = std::strtol(w[1].c_str(), &end, 10);
    if (*end || errno || index != next[q] || w[1] != std::to_string(index)) stateFail(path, line, "index " + w[1] + " of " + w[0] + ", expected " + std::to_string(next[q]));
    next[q]++;
    errno = 0;
    const double value = std::strtod(w[2].c_str(), &end);
    if (*end || !std::isfinite(value) || w[2].find_first_of("xXpP") != std::string::npos) stateFail(path, line, "'" + w[2] + "' is not a finite number");
    if (w[0] == quantity) values.push_back(value);
  }
  return values;
}

}  // namespace runtools
