// nodes.cpp: the contact nodes of Gamma3 and the law's data (contactlaw.hpp): the parameters
// by name, the damping family, the nodes with their weights, bounds and slots (checkLaw runs
// here, when a run starts), the observation v -> (v_nu, v_tau) of every node, its frames (3D),
// Gamma3's edges and the positions along it.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <utility>
#include "kernel.hpp"

namespace contactkernel {
using namespace contactlaw;

void setParameter(Kernel &k, const std::string &name, double given) {
  const double value = given + 0.;             // -0 is 0
  Parameters &P = k.law.P;
  SolverSettings &settings = k.settings;
  bool law = true;                             // a law parameter: the slots must be set again
  if (name == "cnu") P.cnu = value;
  else if (name == "mu") P.mu = value;
  else if (name == "eps") P.eps = value;
  else if (name == "problem") P.penalty = value != 0;
  else if (name == "penaltyform") P.literal = value != 0;
  else if (name == "g") P.g = value;
  else {
    law = false;
    if (name == "tol") { settings.tol = value; k.law.roundoff = 10 * DBL_EPSILON / value; }
    else if (name == "maxit") settings.maxit = (int)value;
    else if (name == "safeguard") settings.safeguards = value != 0;
    else if (name == "r") settings.r = value;
    else if (name == "dt") settings.dt = value;
    else if (name == "step_offset") {
      if (!(value >= 0 && value <= 1e9 && value == std::floor(value))) kernelError("contactKernelParameter: step_offset must be a whole number >= 0");
      settings.stepOffset = (long)value;
    }
    else if (name == "verbose") settings.verbose = value != 0;
    else if (name == "ordering") settings.ordering = (int)value;
    else kernelError("contactKernelParameter: unknown parameter '" + name + "'");
  }
  if (law) k.nodes.ready = false;
}

void setDampingFamily(Kernel &k, int family, const std::vector<double> &numbers) {
  if (family < 0 || family >= dampingFamilyCount)
    kernelError("contactKernelDamping: no damping family " + std::to_string(family) + " in edp/plugins/contactlaw.hpp");
  const std::string why = checkDampingNumbers(family, numbers);
  if (!why.empty()) kernelError(std::string("contactKernelDamping: damping ") + dampingFamilies[family].name + ": " + why);
  std::vector<double> plain = numbers;
  for (double &x : plain) x += 0.;             // -0 is 0
  setDamping(k.law.P, family, plain);
  k.nodes.ready = false;
}

void setBoundProfile(Kernel &k, const std::vector<double> &x, const std::vector<double> &g) {
  if (x.size() != g.size()) kernelError("contactKernelBoundProfile: as many g as x expected");
  for (size_t j = 1; j < x.size(); j++)
    if (!(x[j] > x[j - 1])) kernelError("contactKernelBoundProfile: the x must increase");
  k.law.P.profileX = x; k.law.P.profileG = g;
  k.nodes.ready = false;
}

void setBoundTable(Kernel &k, const std::string &axes, const std::vector<double> &a, const std::vector<double> &b,
                   const std::vector<double> &g) {
  Parameters &P = k.law.P;
  k.nodes.ready = false;
  if (a.empty() && b.empty() && g.empty()) { P.tableA.clear(); P.tableB.clear(); P.tableG.clear(); return; }   // none
  const std::string names = "xyz";
  const size_t axisA = axes.size() == 2 ? names.find(axes[0]) : std::string::npos;
  const size_t axisB = axes.size() == 2 ? names.find(axes[1]) : std::string::npos;
  if (axisA == std::string::npos || axisB == std::string::npos || axisA == axisB)
    kernelError("contactKernelBoundTable: the axes are two of x, y, z, as \"xz\", not '" + axes + "'");
  if (a.empty() || b.empty() || g.size() != a.size() * b.size())
    kernelError("contactKernelBoundTable: as many g as points of the grid, a.n * b.n, expected (or none at all)");
  for (const std::vector<double> *line : {&a, &b})
    for (size_t j = 1; j < line->size(); j++)
      if (!((*line)[j] > (*line)[j - 1])) kernelError("contactKernelBoundTable: the grid's points must increase along each axis");
  for (double value : g)
    if (!(std::isfinite(value) && value > 0)) kernelError("contactKernelBoundTable: every g must be finite and > 0");
  P.tableAxisA = (int)axisA; P.tableAxisB = (int)axisB;
  P.tableA = a; P.tableB = b; P.tableG = g;
}

// every node's g from the law (velocityBound), at its position (x, y, z)
int setNodes(Kernel &k, int nn, const double *x, const double *y, const double *z, const double *w, const long *ns,
             const long *ts, const long *ts2) {
  if (!k.law.P.profileX.empty() && !k.law.P.tableG.empty())
    kernelError("contactKernelNodes: both a bound profile and a bound table are set (contactKernelBoundProfile, contactKernelBoundTable): one of them");
  int slots = 0;
  for (int i = 0; i < nn; i++) slots += (ns[i] >= 0) + (ts[i] >= 0) + (ts2[i] >= 0);
  std::vector<int> owner(slots, -1);
  for (int i = 0; i < nn; i++)
    for (long s : {ns[i], ts[i], ts2[i]})
      if (s >= 0) {
        if (s >= slots || owner[s] >= 0) kernelError("contactKernelNodes: slot numbers must be 0 .. slots-1, each used once");
        owner[s] = i;
      }
  ContactNodes &nodes = k.nodes;
  Slots &law = k.law;
  nodes = ContactNodes();
  k.factor.release();          // S's factor and the Delassus matrix belonged to the old nodes' slots
  std::string why;
  if (checkBound(law.P, why)) {                  // the bound over the profile's or table's grid, and the law at its points
    char data[160];
    std::snprintf(data, sizeof data, " (c_nu = %g, mu = %g)", law.P.cnu, law.P.mu);
    nodes.lawProblem = "the law of edp/plugins/contactlaw.hpp cannot be used: " + why + data;
    return 1;
  }
  std::vector<double> g(nn);
  for (int i = 0; i < nn; i++) {
    const double position[3] = {x[i], y[i], z[i]};
    g[i] = velocityBound(law.P, position);
  }
  nodes.x.assign(x, x + nn); nodes.y.assign(y, y + nn); nodes.z.assign(z, z + nn); nodes.weight.assign(w, w + nn); nodes.g = g;
  nodes.normalSlot.assign(ns, ns + nn); nodes.tangentSlot.assign(ts, ts + nn); nodes.tangentSlot2.assign(ts2, ts2 + nn);
  nodes.slotWeight.assign(slots, 0.);
  law.resize(slots);
  for (int i = 0; i < nn; i++) {
    if (!(g[i] > 0)) kernelError("contactKernelNodes: every velocity bound g must be > 0");
    if (ts[i] >= 0) { law.normal[ts[i]] = 0; law.partner[ts[i]] = ns[i]; }
    if (ts2[i] >= 0) { law.normal[ts2[i]] = 0; law.partner[ts2[i]] = ns[i]; }
    if (ts[i] >= 0 && ts2[i] >= 0) { law.pair[ts[i]] = ts2[i]; law.pair[ts2[i]] = ts[i]; }   // the disk
    for (long s : {ns[i], ts[i], ts2[i]}) if (s >= 0) nodes.slotWeight[s] = w[i];
  }
  for (int j = 0; j < slots; j++) { law.setBound(j, g[owner[j]]); law.setAugmentation(j, k.settings.r); }
  for (int i = 0; i < nn; i++)
    if (checkLaw(law.P, g[i], why)) {
      char data[160];
      std::snprintf(data, sizeof data, " (c_nu = %g, mu = %g, g = %g)", law.P.cnu, law.P.mu, g[i]);
      nodes.lawProblem = "the law of edp/plugins/contactlaw.hpp cannot be used: " + why + data;
      return 1;
    }
  nodes.ready = true;
  return 0;
}

void requireNodes(const Kernel &k, const char *who) {
  if (!k.nodes.ready) kernelError(std::string(who) + ": call contactKernelNodes first (after the last contactKernelParameter)");
}

// the rows of O, two per node (three in 3D), kept as CSR
void setNodeObservation(Kernel &k, const SparseTriplets &O) {
  requireNodes(k, "contactKernelNodeVelocity");
  ContactNodes &nodes = k.nodes;
  const int nn = nodes.count();
  if (O.rows != 2 * nn && O.rows != 3 * nn) kernelError("contactKernelNodeVelocity: two rows per node (2D) or three (3D) expected");
  nodes.rowsPerNode = nn > 0 ? O.rows / nn : 2;
  std::vector<std::vector<std::pair<int, double>>> rows(O.rows);
  for (size_t e = 0; e < O.count; e++) rows[O.row[e]].push_back({O.column[e], O.value[e]});
  nodes.observeStart.assign(1, 0); nodes.observeColumn.clear(); nodes.observeValue.clear();
  nodes.observeWidth = 0;
  for (auto &row : rows) {
    for (auto &entry : row) {
      nodes.observeColumn.push_back(entry.first); nodes.observeValue.push_back(entry.second);
      nodes.observeWidth = std::max(nodes.observeWidth, entry.first + 1);
    }
    nodes.observeStart.push_back(nodes.observeColumn.size());
  }
}

// 3D: the nodes' frames (rows n, t1, t2 of 9 values) and Gamma3's mean frame [T1, T2]: the
// record sums the friction stress as a vector, sum_i w_i (lambda_tau t1_i + lambda_tau2 t2_i),
// and reports it on T1 and T2 (the nodes' own frames may differ: a curved face, a node with a
// fixed axis)
void setNodeFrames(Kernel &k, const std::vector<double> &frames, const double mean[6]) {
  requireNodes(k, "contactKernelNodeFrames");
  if (frames.size() != 9 * (size_t)k.nodes.count()) kernelError("contactKernelNodeFrames: one row of 9 per node and 6 values expected");
  k.nodes.frame = frames;
  for (int c = 0; c < 3; c++) { k.nodes.meanT1[c] = mean[c]; k.nodes.meanT2[c] = mean[3 + c]; }
}

// Gamma3's edges, the pairs (a[e], b[e]) of neighbouring nodes (in either order, repeated or
// not): kept sorted, each once, with each node's neighbours. The positions along Gamma3 (2D)
// are the figures' arc length (plots/gamma3.py, boundary_arc_length): a walk along the edges
// from the end of smallest (x, y) (a node of one neighbour; a closed curve: its node of
// smallest (x, y)) to its unvisited neighbour (of smallest number), and on, the position
// growing by each edge's length; the next piece starts at its own end of smallest (x, y), the
// position going on by the straight distance across the gap: on a flat face, s = x - x of its
// first node. An edge the walk did not follow (the one that closes a closed curve) has its
// second end one edge's length further than its first, the end of larger position.
void setNodeEdges(Kernel &k, const std::vector<long> &a, const std::vector<long> &b) {
  requireNodes(k, "contactKernelNodeEdges");
  ContactNodes &nodes = k.nodes;
  const int nn = nodes.count();
  if (a.size() != b.size()) kernelError("contactKernelNodeEdges: as many second nodes as first nodes expected");
  std::vector<std::pair<int, int>> pairs;
  for (size_t e = 0; e < a.size(); e++) {
    if (a[e] < 0 || a[e] >= nn || b[e] < 0 || b[e] >= nn || a[e] == b[e])
      kernelError("contactKernelNodeEdges: an edge joins two different nodes, numbered 0 .. nodes-1");
    pairs.push_back({(int)std::min(a[e], b[e]), (int)std::max(a[e], b[e])});
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  const int ne = (int)pairs.size();
  nodes.edgeA.resize(ne); nodes.edgeB.resize(ne);
  nodes.neighbourStart.assign(nn + 1, 0);
  for (int e = 0; e < ne; e++) {
    nodes.edgeA[e] = pairs[e].first; nodes.edgeB[e] = pairs[e].second;
    nodes.neighbourStart[pairs[e].first + 1]++; nodes.neighbourStart[pairs[e].second + 1]++;
  }
  for (int i = 0; i < nn; i++) nodes.neighbourStart[i + 1] += nodes.neighbourStart[i];
  nodes.neighbour.assign(2 * ne, -1);
  std::vector<int> fill(nodes.neighbourStart.begin(), nodes.neighbourStart.end() - 1);
  for (int e = 0; e < ne; e++) {
    nodes.neighbour[fill[pairs[e].first]++] = pairs[e].second;
    nodes.neighbour[fill[pairs[e].second]++] = pairs[e].first;
  }
  for (int i = 0; i < nn; i++) std::sort(nodes.neighbour.begin() + nodes.neighbourStart[i], nodes.neighbour.begin() + nodes.neighbourStart[i + 1]);
  std::vector<double> arc(nn, 0.);
  std::vector<int> from(nn, -1);                 // the node the walk came from (-1: a piece's start)
  std::vector<char> visited(nn, 0);
  std::vector<int> order(nn);                    // the nodes by (x, y)
  for (int i = 0; i < nn; i++) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](int i, int j) { return std::make_pair(nodes.x[i], nodes.y[i]) < std::make_pair(nodes.x[j], nodes.y[j]); });
  double s = 0;
  int last = -1;
  for (size_t end = 0, any = 0;;) {              // (in the order of (x, y): the first unvisited end, else node)
    while (end < order.size() && (visited[order[end]] || nodes.neighbours(order[end]) != 1)) end++;
    while (any < order.size() && visited[order[any]]) any++;
    if (any == order.size()) break;
    int at = end < order.size() ? order[end] : order[any];
    if (last >= 0) s += nodes.distance(last, at);
    visited[at] = 1; arc[at] = s;
    for (;;) {
      int next = -1;
      for (int p = nodes.neighbourStart[at]; p < nodes.neighbourStart[at + 1] && next < 0; p++)
        if (!visited[nodes.neighbour[p]]) next = nodes.neighbour[p];
      if (next < 0) break;
      s += nodes.distance(at, next);
      visited[next] = 1; arc[next] = s; from[next] = at;
      at = next;
    }
    last = at;
  }
  nodes.edgeS.resize(2 * (size_t)ne);
  for (int e = 0; e < ne; e++) {
    const int i = nodes.edgeA[e], j = nodes.edgeB[e];
    if (from[i] == j || from[j] == i) { nodes.edgeS[2 * e] = arc[i]; nodes.edgeS[2 * e + 1] = arc[j]; continue; }
    const bool iFirst = arc[i] >= arc[j];        // not walked: from the end of larger position on
    nodes.edgeS[2 * e + (iFirst ? 0 : 1)] = std::max(arc[i], arc[j]);
    nodes.edgeS[2 * e + (iFirst ? 1 : 0)] = std::max(arc[i], arc[j]) + nodes.distance(i, j);
  }
}

void nodeVelocities(const Kernel &k, const double *v, const std::vector<double> &cv, std::vector<double> &ov) {
  const ContactNodes &nodes = k.nodes;
  const int nn = nodes.count(), rows = nodes.rowsPerNode;
  ov.assign(rows * nn, 0.);
  if (nodes.observeStart.size() == (size_t)(rows * nn + 1)) {
    if (nodes.observeWidth > k.factor.n)
      kernelError("contactkernel: the observation rows (contactKernelNodeVelocity) have " + std::to_string(nodes.observeWidth) +
                  " columns, the velocity " + std::to_string(k.factor.n) + " unknowns");
    for (int r = 0; r < rows * nn; r++)
      for (int e = nodes.observeStart[r]; e < nodes.observeStart[r + 1]; e++) ov[r] += nodes.observeValue[e] * v[nodes.observeColumn[e]];
    return;
  }
  for (int i = 0; i < nn; i++) {                  // without the observation rows: from the slots
    if (nodes.normalSlot[i] >= 0) ov[rows * i] = cv[nodes.normalSlot[i]];
    if (nodes.tangentSlot[i] >= 0) ov[rows * i + 1] = cv[nodes.tangentSlot[i]];
    if (rows == 3 && nodes.tangentSlot2[i] >= 0) ov[rows * i + 2] = cv[nodes.tangentSlot2[i]];
  }
}

}  // namespace contactkernel
