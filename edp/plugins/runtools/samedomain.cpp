// samedomain.cpp: compare.edp compares the fields of two runs only if their meshes cover the
// same domain with the same boundary labels (docs/design.md, "Comparing two runs"); this says
// whether they do, and where not.
//
// The boundary of a checked mesh is its labelled boundary elements (2D: lines, 3D: triangles;
// the first tag). Each element's centroid must lie on the other mesh's boundary, on an element
// of its label, within 1e-6 of the extent plus what a chord may lie off a curved boundary: the
// sagitta h theta / 8 of an element of length h whose neighbours turn by theta from it (the
// curve turns by about theta over h), of both elements. On a polygon theta is 0 away from the
// corners, so another length or a moved support is seen.
#include "runtools.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace runtools {

namespace {
struct Boundary {
  std::vector<std::array<double, 3>> xyz;            // the nodes
  std::vector<std::array<long, 3>> corner;           // each element's nodes (two in 2D)
  std::vector<long> label;
  std::vector<std::array<double, 3>> centroid, axis; // its centroid; its direction (2D) or normal (3D)
  std::vector<double> length, sagitta, reach;        // its size h; h theta / 8; the farthest of its nodes from its centroid
  int corners = 2;
  double extent = 0;
};
double dot3(const std::array<double, 3> &a, const std::array<double, 3> &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
std::array<double, 3> minus3(const std::array<double, 3> &a, const std::array<double, 3> &b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
std::array<double, 3> cross3(const std::array<double, 3> &a, const std::array<double, 3> &b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Boundary readBoundary(const std::string &path) {
  MeshText M = readMeshText(path);
  Boundary B;
  std::map<long, long> index;
  B.xyz.resize(M.nodeCount);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (long i = 0; i < M.nodeCount; i++) {
    long id;
    double x, y, z;
    readNode(M.lines[M.nodesAt + 2 + i], index, id, x, y, z);
    index[id] = i;
    B.xyz[i] = {x, y, z};
    for (int k = 0; k < 3; k++) { lo[k] = std::min(lo[k], B.xyz[i][k]); hi[k] = std::max(hi[k], B.xyz[i][k]); }
  }
  for (int k = 0; k < 3; k++) B.extent = std::max(B.extent, hi[k] - lo[k]);
  bool three = false;
  std::vector<std::vector<long>> elements;
  for (long i = 0; i < M.elementCount; i++) {
    std::vector<std::string> w = fieldsOf(M.lines[M.elementsAt + 2 + i]);
    std::vector<long> v;
    for (auto &word : w) v.push_back(std::atol(word.c_str()));
    three = three || (v.size() > 1 && v[1] == 4);
    elements.push_back(v);
  }
  B.corners = three ? 3 : 2;
  const long wanted = three ? 2 : 1;                 // gmsh types: 1 line, 2 triangle
  for (auto &v : elements) {
    if (v.size() < 3 || v[1] != wanted || v[2] < 1 || (long)v.size() < 3 + v[2] + B.corners) continue;
    std::array<long, 3> nodes = {0, 0, 0};
    for (int k = 0; k < B.corners; k++) nodes[k] = index.at(v[3 + v[2] + k]);
    B.corner.push_back(nodes);
    B.label.push_back(v[3]);
  }
  const size_t n = B.corner.size();
  B.centroid.resize(n); B.axis.resize(n); B.length.assign(n, 0); B.sagitta.assign(n, 0); B.reach.assign(n, 0);
  std::map<long, std::vector<size_t>> at;            // the elements at each node
  for (size_t e = 0; e < n; e++) {
    std::array<double, 3> c = {0, 0, 0};
    for (int k = 0; k < B.corners; k++) for (int d = 0; d < 3; d++) c[d] += B.xyz[B.corner[e][k]][d] / B.corners;
    B.centroid[e] = c;
    const auto &a = B.xyz[B.corner[e][0]], &b = B.xyz[B.corner[e][1]];
    std::array<double, 3> axis = minus3(b, a);
    if (three) axis = cross3(axis, minus3(B.xyz[B.corner[e][2]], a));
    const double norm = std::sqrt(dot3(axis, axis));
    for (int d = 0; d < 3; d++) axis[d] = norm > 0 ? axis[d] / norm : 0;
    B.axis[e] = axis;
    for (int k = 0; k < B.corners; k++) {
      const auto r = minus3(B.xyz[B.corner[e][k]], c);
      B.reach[e] = std::max(B.reach[e], std::sqrt(dot3(r, r)));
      const auto side = minus3(B.xyz[B.corner[e][(k + 1) % B.corners]], B.xyz[B.corner[e][k]]);
      B.length[e] = std::max(B.length[e], std::sqrt(dot3(side, side)));
      at[B.corner[e][k]].push_back(e);
    }
  }
  for (size_t e = 0; e < n; e++) {
    double theta = 0;                                // the largest turn to a neighbour (lines: unoriented)
    for (int k = 0; k < B.corners; k++)
      for (size_t f : at[B.corner[e][k]]) {
        const double c = std::fabs(dot3(B.axis[e], B.axis[f]));
        theta = std::max(theta, std::acos(std::min(1., c)));
      }
    B.sagitta[e] = B.length[e] * theta / 8;
  }
  return B;
}
// the distance from p to element e of B (a segment, or a triangle)
double distanceTo(const Boundary &B, size_t e, const std::array<double, 3> &p) {
  const auto &a = B.xyz[B.corner[e][0]], &b = B.xyz[B.corner[e][1]];
  auto segment = [&](const std::array<double, 3> &s, const std::array<double, 3> &t) {
    const auto st = minus3(t, s), sp = minus3(p, s);
    const double along = dot3(st, st) > 0 ? std::max(0., std::min(1., dot3(sp, st) / dot3(st, st))) : 0.;
    const std::array<double, 3> q = {s[0] + along * st[0], s[1] + along * st[1], s[2] + along * st[2]};
    const auto d = minus3(p, q);
    return std::sqrt(dot3(d, d));
  };
  if (B.corners == 2) return segment(a, b);
  const auto &c = B.xyz[B.corner[e][2]];
  const auto ab = minus3(b, a), ac = minus3(c, a), ap = minus3(p, a);
  const double d00 = dot3(ab, ab), d01 = dot3(ab, ac), d11 = dot3(ac, ac), d20 = dot3(ap, ab), d21 = dot3(ap, ac);
  const double det = d00 * d11 - d01 * d01;
  if (det > 0) {                                     // inside the triangle's projection: the distance to its plane
    const double v = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
    if (v >= 0 && w >= 0 && v + w <= 1) return std::fabs(dot3(ap, B.axis[e]));
  }
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}
// "" if every element of A lies on an element of R of its label (within the tolerance), else
// why not; the elements of R sorted by the x of their centroids, searched outwards from p's x
std::string boundaryOff(const Boundary &A, const Boundary &R, const std::string &nameA, const std::string &nameR) {
  std::vector<size_t> order(R.corner.size());
  for (size_t f = 0; f < order.size(); f++) order[f] = f;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return R.centroid[a][0] < R.centroid[b][0]; });
  double widest = 0;
  for (double r : R.reach) widest = std::max(widest, r);
  const double floor = 1e-6 * std::max(A.extent, R.extent);
  for (size_t e = 0; e < A.corner.size(); e++) {
    const auto &p = A.centroid[e];
    double best = INFINITY, nearest = INFINITY;      // the least distance, less R's sagitta, to an element of the label; that distance
    const size_t start = std::lower_bound(order.begin(), order.end(), p[0],
                                          [&](size_t f, double x) { return R.centroid[f][0] < x; }) - order.begin();
    for (int side = 0; side < 2; side++)
      for (size_t k = side ? start : start - 1; k < order.size(); k = side ? k + 1 : k - 1) {
        const size_t f = order[k];
        if (std::fabs(R.centroid[f][0] - p[0]) - widest > best) break;
        if (R.label[f] == A.label[e]) {
          const double d = distanceTo(R, f, p);
          if (d - R.sagitta[f] < best) { best = d - R.sagitta[f]; nearest = d; }
        }
        if (!side && k == 0) break;
      }
    if (!(best <= floor + A.sagitta[e])) {
      char at[160];
      std::snprintf(at, sizeof at, "(%.6g, %.6g%s", p[0], p[1], A.corners == 3 ? "" : ")");
      std::string where = at;
      if (A.corners == 3) { std::snprintf(at, sizeof at, ", %.6g)", p[2]); where += at; }
      return "the boundary labelled " + std::to_string(A.label[e]) + " of " + nameA + " passes through " + where + ", "
             + (std::isfinite(best) ? numberText(nearest) + " away from " + nameR + "'s boundary of that label (tolerance "
                                      + numberText(nearest - best + floor + A.sagitta[e]) + ")"
                                    : "but " + nameR + " has no boundary of that label");
    }
  }
  return "";
}
}  // namespace

// the meshes were checked before (runCheckMesh): a problem here is a damaged file (exit 3)
long runSameDomain(std::string *const &pathA, std::string *const &pathR) {
  Boundary A, R;
  try { A = readBoundary(*pathA); R = readBoundary(*pathR); }
  catch (const MeshProblem &problem) { fail(3, "compare.edp: " + problem.why); }
  if (A.corners != R.corners) fail(2, "compare.edp: " + *pathA + " and " + *pathR + " are meshes of two dimensions");
  std::string why = boundaryOff(A, R, *pathA, *pathR);
  if (why.empty()) why = boundaryOff(R, A, *pathR, *pathA);
  if (!why.empty()) fail(2, "compare.edp: the runs' meshes do not cover the same domain with the same boundary labels: " + why);
  return 0;
}

}  // namespace runtools
