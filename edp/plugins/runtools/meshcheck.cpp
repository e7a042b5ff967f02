// meshcheck.cpp: the mesh checker. A gmsh MSH 2.2 ASCII file is checked as FreeFEM's gmshload
// would read it, before FreeFEM reads it: every problem FreeFEM would abort on, crash on or
// silently misread is named here instead (exit 3; docs/design.md, "Exit codes and failure
// messages"), 2D (triangles) and 3D (tetrahedra) alike. FreeFEM then reads the checked copy,
// every element positively oriented. Also what the scripts ask of a mesh or .geo file without
// checking it (its dimension, its labels).
#include "runtools.hpp"
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <initializer_list>
#include <set>
#include <sys/stat.h>
#include <sstream>
#include <unistd.h>

namespace runtools {

const double maxExtentRatio = 1e8;                 // extent / shortest edge (see checkMesh)
const double maxCoordinate = 1e100;                // |x|, |y|, |z| of a node (see readNode)

std::string numberText(double x) { char b[32]; std::snprintf(b, sizeof b, "%g", x); return b; }

std::vector<std::string> fieldsOf(const std::string &text) {
  std::vector<std::string> words;
  std::stringstream in(text);
  std::string w;
  while (in >> w) words.push_back(w);
  return words;
}
// Line ends (CRLF too) and trailing blanks are dropped and a UTF-8 byte order mark skipped, so
// that a file an editor saved still reads (FreeFEM reads the checked copy); a file that does not
// start with $MeshFormat is refused unread.
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

// the id must fit FreeFEM's 32-bit ids, the coordinates be finite and far from overflowing
void readNode(const std::string &text, const std::map<long, long> &index, long &id, double &x, double &y, double &z) {
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

namespace {
struct WriteProblem { std::string why; };          // the checked copy could not be written: exit 7, not 3

struct Element { long id; int type; std::vector<long> tags, nodes; };

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

// an element line's numbers (id, type, tag count, tags, nodes), each within FreeFEM's 32-bit ints
std::vector<long> elementNumbers(const std::string &text) {
  const std::vector<std::string> w = fieldsOf(text);
  std::vector<long> v;
  char *end = nullptr;
  bool ok = w.size() >= 3;
  for (auto &word : w) { v.push_back(std::strtol(word.c_str(), &end, 10)); ok = ok && end && !*end; }
  if (!ok) throw MeshProblem{"$Elements: cannot read the element line '" + text + "'"};
  for (long number : v)
    if (number > 2147483647L || number < -2147483647L)
      throw MeshProblem{"element " + std::to_string(v[0]) + ": the number " + std::to_string(number) + " does not fit FreeFEM's 32-bit ids and tags"};
  return v;
}
// an element's tags and node positions from its numbers v; returns its nodes sorted, the key
// that finds it listed twice
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

// the labels the run uses: those of required ("LABEL ROLE ...") and the scene's Dirichlet labels
std::set<long> labelsUsed(const std::string &required, const std::string &dirichlet) {
  std::set<long> used;
  std::stringstream roles(required + " " + dirichlet);
  std::string word;
  while (roles >> word) if (std::isdigit((unsigned char)word[0])) used.insert(std::atol(word.c_str()));
  return used;
}
// two nodes at one point: a crack, or duplicated nodes; either leaves the body cut there
template <size_t N>
void refuseSharedPoints(const std::vector<std::array<double, N>> &points, const std::vector<long> &idOf) {
  std::vector<std::pair<std::array<double, N>, long>> sorted;
  for (size_t i = 0; i < points.size(); i++) sorted.push_back({points[i], (long)i});
  std::sort(sorted.begin(), sorted.end());
  for (size_t k = 1; k < sorted.size(); k++)
    if (sorted[k].first == sorted[k - 1].first) {
      std::string at;
      for (size_t d = 0; d < N; d++) at += (d ? ", " : "") + numberText(sorted[k].first[d]);
      throw MeshProblem{"nodes " + std::to_string(idOf[sorted[k - 1].second]) + " and " + std::to_string(idOf[sorted[k].second]) +
                        " are at the same point (" + at + "): a crack or duplicated nodes"};
    }
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
    const std::vector<long> v = elementNumbers(lines[elementsAt + 2 + i]);
    Element e;
    e.id = v[0]; e.type = (int)v[1];
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
    if (area < 0) std::swap(t.nodes[1], t.nodes[2]);
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
    if (!used[i]) throw MeshProblem{"node " + std::to_string(idOf[i]) + " is not a vertex of any triangle"};
  refuseSharedPoints(xy, idOf);
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
  const std::set<long> usedLabels = labelsUsed(required, dirichlet);
  std::set<long> labels;
  std::set<std::vector<long>> labelled;
  for (Element &e : edges) {
    std::vector<long> edge = e.nodes;
    std::sort(edge.begin(), edge.end());
    if (!boundaryEdges.count(edge) && !interiorEdges.count(edge))
      throw MeshProblem{"line element " + std::to_string(e.id) + " (physical tag " + std::to_string(e.tags[0]) +
                        ") is not an edge of any triangle"};
    if (interiorEdges.count(edge) && usedLabels.count(e.tags[0]))
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
    const std::vector<long> v = elementNumbers(lines[M.elementsAt + 2 + i]);
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
  refuseSharedPoints(xyz, idOf);
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
  const std::set<long> usedLabels = labelsUsed(required, dirichlet);
  std::set<long> labels;
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

}  // namespace

// ---------------------------------------------------------------- the FreeFEM functions
// 3 if the file has a volume element (a tetrahedron, gmsh type 4, or one the 3D checker then
// refuses: hexahedra, prisms, pyramids, of any order), 2 if it is a gmsh file without one, 0 if
// it cannot be read as one (the checker then says why)
long runMeshDimension(std::string *const &path) {
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
// A cached mesh is not checked again, but the scene that uses it may name other Dirichlet
// labels: the first of the labels (negative ones skipped) that no boundary element carries
// (lines in 2D, triangles in 3D: the first tag), or -1 (0 if the file cannot be read)
long runMeshLacksLabel(std::string *const &path, std::string *const &labels) {
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

// a .geo is meshed in 3D (gmsh -3) if it defines a Physical Volume, itself or in a file it
// includes (Include "NAME"; on one line, NAME relative to its folder: meshes/twistedbox.geo
// includes hexbody.geo), outside // and /* */ comments. Each file is read once (a file that
// includes itself, or one included many times, costs one reading), regular files only, the
// first 16 MB of each.
namespace {
int geoDimension(const std::string &path, std::set<std::string> &read) {
  struct ::stat info;
  if (!read.insert(path).second || ::stat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) return 2;
  std::ifstream f(path);
  std::string line;
  const size_t slash = path.rfind('/');
  const std::string folder = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  bool inBlock = false;
  size_t total = 0;
  while (total < (16u << 20) && std::getline(f, line)) {
    total += line.size() + 1;
    std::string code;                                 // the line without its comments
    for (size_t at = 0; at < line.size();) {
      if (inBlock) {
        const size_t end = line.find("*/", at);
        if (end == std::string::npos) break;
        inBlock = false; at = end + 2;
        continue;
      }
      const size_t block = line.find("/*", at), rest = line.find("//", at);
      if (rest != std::string::npos && (block == std::string::npos || rest < block)) { code += line.substr(at, rest - at); break; }
      if (block == std::string::npos) { code += line.substr(at); break; }
      code += line.substr(at, block - at);
      inBlock = true; at = block + 2;
    }
    if (code.find("Physical Volume") != std::string::npos) return 3;
    const size_t include = code.find("Include");
    if (include == std::string::npos) continue;
    const size_t open = code.find('"', include), close = open == std::string::npos ? open : code.find('"', open + 1);
    if (close == std::string::npos) continue;
    const std::string name = code.substr(open + 1, close - open - 1);
    if (!name.empty() && geoDimension(name[0] == '/' ? name : folder + name, read) == 3) return 3;
  }
  return 2;
}
}  // namespace
long runGeoDimension(std::string *const &path) {
  std::set<std::string> read;
  return geoDimension(*path, read);
}

// one limit: meshes.idp refuses a scene's structured mesh of that ratio before gmsh makes it
double runMeshExtentRatio() { return maxExtentRatio; }

// The file in, checked and written to out (unless out is ""): on a problem exit 3 with "what: why" when
// fatal (else 1: a cached or made mesh the caller makes again); exit 7 if out cannot be written
long runCheckMesh(std::string *const &in, std::string *const &out, std::string *const &required,
                  std::string *const &dirichlet, std::string *const &what, const long &fatal) {
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

}  // namespace runtools
