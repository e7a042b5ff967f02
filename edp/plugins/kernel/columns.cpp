// columns.cpp: the tables of columns.hpp, looked up by name (contactKernelColumn).
#include "columns.hpp"

#include <vector>

namespace contactkernel {
const char *zoneColumn(int zone) {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    for (int z = 0; z < contactlaw::zoneCount; z++) list.push_back(std::string("zone_") + contactlaw::zoneNames[z]);
    return list;
  }();
  return names[zone].c_str();
}

namespace {
#define CONTACTKERNEL_COLUMN(id, name, integer) {name, integer},
const Column nodal[] = {CONTACTKERNEL_NODAL_COLUMNS(CONTACTKERNEL_COLUMN)};
const Column record[] = {CONTACTKERNEL_RECORD_COLUMNS(CONTACTKERNEL_COLUMN)};
const Column history[] = {CONTACTKERNEL_HISTORY_COLUMNS(CONTACTKERNEL_COLUMN) CONTACTKERNEL_RECORD_COLUMNS(CONTACTKERNEL_COLUMN)};
const Column solverInfo[] = {CONTACTKERNEL_SOLVER_INFO_COLUMNS(CONTACTKERNEL_COLUMN)};
const Column safeguardInfo[] = {CONTACTKERNEL_SAFEGUARD_INFO_COLUMNS(CONTACTKERNEL_COLUMN)};
const Column counters[] = {CONTACTKERNEL_COUNTER_COLUMNS(CONTACTKERNEL_COLUMN)};
#undef CONTACTKERNEL_COLUMN
static_assert(sizeof nodal / sizeof nodal[0] == nodalColumnCount, "nodal");
static_assert(sizeof history / sizeof history[0] == historyColumnCount, "history");

struct Table { const char *name; const Column *columns; int count; };
const Table tables[] = {
  {"nodal", nodal, nodalColumnCount}, {"record", record, recordColumnCount}, {"history", history, historyColumnCount},
  {"solver_info", solverInfo, solverInfoColumnCount}, {"safeguard_info", safeguardInfo, safeguardInfoColumnCount},
  {"counters", counters, counterColumnCount},
};
}  // namespace

const Column *columnsOf(const std::string &table, int &count) {
  for (const Table &t : tables)
    if (table == t.name) { count = t.count; return t.columns; }
  count = 0;
  return nullptr;
}

int columnIndex(const std::string &table, const std::string &name) {
  int count = 0;
  const Column *columns = columnsOf(table, count);
  for (int k = 0; k < count; k++) if (name == columns[k].name) return k;
  return -1;
}

std::string tableNames() {
  std::string text;
  for (const Table &t : tables) text += std::string(text.empty() ? "" : ", ") + t.name;
  return text;
}

}  // namespace contactkernel
