// record.cpp: what the kernel reports, from the statuses of contactlaw.hpp: the nodal table of
// a step (contactKernelNodal: contact.txt and the end-of-run checks), the rows of
// contact_nodes_history.txt in the columns the script names, and the record of a step (the
// energy terms of history.txt, the forces, zones, x_B and x_C of contact_history.txt, the rows
// of zone_boundaries.txt).
#include <charconv>
#include <algorithm>
#include <cmath>
#include <sstream>
#include "kernel.hpp"

namespace contactkernel {
using namespace contactlaw;

namespace {
// The values of node i from its velocities ov (nodeVelocities) and the contact stresses Lam,
// with the statuses of contactlaw.hpp (+ 0. turns -0 into 0).
struct NodeValues {
  double vn, vt, vt2, pn, ln, lt, lt2, frictionBound;
  int normal, tangential;
};
NodeValues nodeValues(const Kernel &k, int i, const double *ov, const double *Lam) {
  const ContactNodes &nodes = k.nodes;
  const Parameters &P = k.law.P;
  const int sn = nodes.normalSlot[i], st = nodes.tangentSlot[i], st2 = nodes.tangentSlot2[i], rows = nodes.rowsPerNode;
  NodeValues s;
  s.vn = ov[rows * i] + 0.;
  s.vt = ov[rows * i + 1] + 0.;
  s.vt2 = rows == 3 ? ov[rows * i + 2] + 0. : 0.;
  s.pn = sn >= 0 ? Lam[sn] : 0.;
  s.lt = st >= 0 ? Lam[st] : 0.;
  s.lt2 = st2 >= 0 ? Lam[st2] : 0.;
  s.ln = (sn >= 0 ? s.pn - dampedResponse(P, s.vn) : 0.) + 0.;
  s.frictionBound = frictionBound(P, s.vn);
  s.normal = normalStatus(s.vn, nodes.g[i]);
  s.tangential = tangentialStatus(rows == 3 ? std::hypot(s.vt, s.vt2) : s.vt, nodes.g[i]);
  return s;
}
// The law's switching functions at every node (contactlaw.hpp: boundSwitch, slipSwitch; >= 0
// on the piece, < 0 next to it): bound, boundSwitch (the piece: at the bound); stick,
// -slipSwitch of the lengths |lambda_tau|, |v_tau| (the piece: stick), nan off contact (normal
// status 0), where there is neither slip nor stick.
struct Switches {
  std::vector<double> bound, stick;
};
void nodeSwitches(const Parameters &P, const NodeValues &s, double g, double &bound, double &stick) {
  bound = boundSwitch(P, s.pn, s.vn, g);
  stick = s.normal > 0 ? -slipSwitch(P, std::hypot(s.lt, s.lt2), std::hypot(s.vt, s.vt2), s.vn, g) : NAN;
}
// the zero between a and b of the line through (a, fa), (b, fb)
double crossing(double a, double fa, double b, double fb) { return a + (b - a) * (-fa) / (fb - fa); }
// Where the bound begins between a node off it (at position aOff, switching function fOff < 0)
// and its neighbour at it (aOn, fOn >= 0), positions along Gamma3: the velocity reaches g
// tangentially (v_nu - g is quadratic on the damped side, as the gap of an obstacle problem),
// while the bound's multiplier grows linearly from 0, so the zero of the straight line through
// the switching function at the node at the bound and at its next neighbour beyond it (aBeyond,
// fBeyond) when that one is further into the bound (fBeyond > fOn; nan: no such neighbour),
// otherwise the crossing between the two; kept between aOff and aOn.
double boundStart(double aOff, double fOff, double aOn, double fOn, double aBeyond, double fBeyond) {
  const double at = fBeyond > fOn ? crossing(aOn, fOn, aBeyond, fBeyond) : crossing(aOff, fOff, aOn, fOn);
  return std::min(std::max(at, std::min(aOff, aOn)), std::max(aOff, aOn));
}

// x_B_estimate, x_C_estimate: the first zone boundaries between the nodes (2D, Gamma3 ordered
// by x; between neighbours on Gamma3 only), from the switching functions f:
// - x_C, where sticking begins: the slip velocity falls to 0 linearly and the stick margin
//   grows linearly from 0, so the switching function is linear across the boundary: its
//   zero between the first sticking node and its neighbour of next smaller x;
// - x_B, where the bound begins: boundStart between the first node at the bound and its
//   neighbour of next smaller x, with its neighbour of next larger x beyond it.
// The node's own x where no crossing is found; 1e300 where the zone does not exist, and in 3D.
void zoneEstimates(const Kernel &k, const Switches &f, double xB, double xC, double &estimateB, double &estimateC) {
  const ContactNodes &nodes = k.nodes;
  estimateB = 1e300; estimateC = 1e300;
  if (!nodes.frame.empty()) return;
  const int nn = nodes.count();
  // the node at x (the zone's first) and its neighbours on Gamma3 (its edges: none across a gap
  // between two pieces) of next smaller and next larger x (-1: none); without the edges, the
  // nodes of next smaller and larger x
  const bool edges = !nodes.neighbourStart.empty();
  auto around = [&](double x, int &at, int &left, int &right) {
    at = -1; left = -1; right = -1;
    for (int i = 0; i < nn && at < 0; i++) if (nodes.x[i] == x) at = i;
    auto consider = [&](int i) {
      if (nodes.x[i] < x && (left < 0 || nodes.x[i] > nodes.x[left])) left = i;
      if (nodes.x[i] > x && (right < 0 || nodes.x[i] < nodes.x[right])) right = i;
    };
    if (edges && at >= 0) for (int e = nodes.neighbourStart[at]; e < nodes.neighbourStart[at + 1]; e++) consider(nodes.neighbour[e]);
    else for (int i = 0; i < nn; i++) consider(i);
  };
  int at = -1, left = -1, right = -1;
  if (xB < 1e300) {
    around(xB, at, left, right);
    estimateB = xB;
    const double fAt = at >= 0 ? f.bound[at] : NAN, fLeft = left >= 0 ? f.bound[left] : NAN;
    const double fRight = right >= 0 ? f.bound[right] : NAN;
    if (left >= 0 && fAt >= 0 && fLeft < 0)          // a neighbour off the bound: the crossing is between them
      estimateB = boundStart(nodes.x[left], fLeft, xB, fAt, right >= 0 ? nodes.x[right] : NAN, fRight);
  }
  if (xC < 1e300) {
    around(xC, at, left, right);
    estimateC = xC;
    const double fAt = at >= 0 ? f.stick[at] : NAN, fLeft = left >= 0 ? f.stick[left] : NAN;
    if (fAt >= 0 && fLeft < 0) estimateC = crossing(nodes.x[left], fLeft, xC, fAt);
  }
}

// The zone boundaries on Gamma3's edges (zone_boundaries.txt): on every edge of
// contactKernelNodeEdges whose two nodes' switching function has opposite signs (one < 0, the
// other >= 0; nan at either end: none), the point where it vanishes, kind 1 for the bound (B),
// 2 for stick (C). 2D: the bound's start by boundStart (the node beyond the one at the bound:
// its other neighbour, where it has two), stick's by the straight line between the two nodes,
// both along the edge; s, the position along Gamma3, interpolated between its ends'. 3D: the
// straight line between the two nodes for both (the rows trace the boundary curve on the
// face), s nan. The rows of a step: kind 1, then 2; each by s in 2D, by edge in 3D. Kept in
// the record (written at the end: formatting them at every step would cost more than
// finding them); counted into countB, countC.
void zoneBoundaryRows(Kernel &k, const Switches &f, long step, long &countB, long &countC) {
  const ContactNodes &nodes = k.nodes;
  const bool curve = nodes.frame.empty();
  std::vector<ZoneBoundary> &rows = k.record.boundaries;
  for (int kind = 1; kind <= 2; kind++) {
    const std::vector<double> &value = kind == 1 ? f.bound : f.stick;
    const size_t first = rows.size();
    for (size_t e = 0; e < nodes.edgeA.size(); e++) {
      const int a = nodes.edgeA[e], b = nodes.edgeB[e];
      if (std::isnan(value[a]) || std::isnan(value[b]) || (value[a] < 0) == (value[b] < 0)) continue;
      const bool aOff = value[a] < 0;
      const int off = aOff ? a : b, on = aOff ? b : a;
      double theta = crossing(0, value[off], 1, value[on]);   // from off (0) to on (1)
      if (kind == 1 && curve) {
        int beyond = -1;
        if (nodes.neighbours(on) == 2)
          for (int p = nodes.neighbourStart[on]; p < nodes.neighbourStart[on + 1]; p++)
            if (nodes.neighbour[p] != off) beyond = nodes.neighbour[p];
        theta = boundStart(0, value[off], 1, value[on], beyond >= 0 ? 1 + nodes.distance(on, beyond) / nodes.distance(off, on) : NAN,
                           beyond >= 0 ? value[beyond] : NAN);
      }
      const double sOff = nodes.edgeS[2 * e + (aOff ? 0 : 1)], sOn = nodes.edgeS[2 * e + (aOff ? 1 : 0)];
      rows.push_back({step, kind, curve ? sOff + theta * (sOn - sOff) : NAN, nodes.x[off] + theta * (nodes.x[on] - nodes.x[off]),
                      nodes.y[off] + theta * (nodes.y[on] - nodes.y[off]), nodes.z[off] + theta * (nodes.z[on] - nodes.z[off])});
    }
    if (curve)
      std::stable_sort(rows.begin() + first, rows.end(), [](const ZoneBoundary &p, const ZoneBoundary &q) { return p.s < q.s; });
    (kind == 1 ? countB : countC) = (long)(rows.size() - first);
  }
}
}  // namespace

void nodalTable(Kernel &k, const double *v, const double *Lam, std::vector<double> &table) {
  requireNodes(k, "contactKernelNodal");
  requireSlots(k, "contactKernelNodal");
  const Parameters &P = k.law.P;
  const ContactNodes &nodes = k.nodes;
  std::vector<double> cv, ov;
  slotVelocities(k, v, cv);
  nodeVelocities(k, v, cv, ov);
  const int nn = nodes.count();
  table.assign((size_t)nn * nodalColumnCount, 0.);
  for (int i = 0; i < nn; i++) {
    const NodeValues s = nodeValues(k, i, ov.data(), Lam);
    double *row = table.data() + (size_t)i * nodalColumnCount;
    row[NodalVNu] = s.vn; row[NodalVTau] = s.vt; row[NodalPNu] = s.pn; row[NodalLambdaNu] = s.ln; row[NodalLambdaTau] = s.lt;
    row[NodalNormalStatus] = s.normal; row[NodalTangentialStatus] = s.tangential; row[NodalFrictionBound] = s.frictionBound;
    row[NodalForceScale] = forceScale(P, nodes.g[i]);   // (also where the node has no slot)
    row[NodalZone] = zone(s.normal, s.tangential); row[NodalVTau2] = s.vt2;
    row[NodalLambdaTau2] = s.lt2; row[NodalDampedResponse] = dampedResponse(P, s.vn); row[NodalG] = nodes.g[i];
    row[NodalDampingSlope] = dampedResponseSlope(P, nodes.g[i]);   // p'(g): the slope Kn the solvers fold into S
  }
}

// ---------------------------------------------------------------- contact_nodes_history.txt
// The script (edp/lib/series.idp) names the file's columns once: the row's own step, t, node,
// x, y, z, and any column of the nodal table; the kernel then writes the rows, compiled,
// through one stream kept open until contactKernelCloseNodes (written from the interpreter,
// or reopened at every step, the rows cost as much as the step), 17 digits as FreeFEM's own
// streams write them, the integer columns as integers.
void setNodesFileColumns(Kernel &k, const std::string &names) {
  NodesFile &file = k.nodesFile;
  file.columns.clear();
  file.hasZ = false;
  std::istringstream words(names);
  std::string name;
  while (words >> name) {
    int source = columnIndex("nodal", name);
    if (name == "step") source = NodesFile::Step;
    else if (name == "t") source = NodesFile::Time;
    else if (name == "node") source = NodesFile::Node;
    else if (name == "x") source = NodesFile::X;
    else if (name == "y") source = NodesFile::Y;
    else if (name == "z") { source = NodesFile::Z; file.hasZ = true; }
    else if (source < 0)
      kernelError("contactKernelNodesColumns: no column '" + name + "' (step, t, node, x, y, z, or one of the nodal table)");
    file.columns.push_back(source);
  }
}

long closeNodesFile(Kernel &k) {
  NodesFile &file = k.nodesFile;
  if (!file.stream.is_open()) return 0;
  file.stream.flush();
  const bool ok = (bool)file.stream;
  file.stream.close();
  file.path.clear();
  return ok && !file.stream.fail() ? 0 : 1;
}

long appendNodes(Kernel &k, const std::string &path, long n, double t, const double *x, const double *y, const double *z,
                 const std::vector<double> &table) {
  NodesFile &file = k.nodesFile;
  if (file.columns.empty()) kernelError("contactKernelAppendNodes: call contactKernelNodesColumns first");
  if (file.path != path) {
    if (closeNodesFile(k)) return 1;
    file.stream.open(path, std::ios::app);
    file.stream.precision(17);
    file.path = path;
  }
  int nodalColumns = 0;
  const Column *nodal = columnsOf("nodal", nodalColumns);
  // the rows made in a buffer by std::to_chars, which writes what the stream's 17 digits would
  // ("as if by printf %.17g") three times as fast: on small meshes these rows cost as much as
  // the step's solve
  std::string text;
  char digits[64];
  auto number = [&](double value) { text.append(digits, std::to_chars(digits, digits + sizeof digits, value, std::chars_format::general, 17).ptr); };
  auto integer = [&](long value) { text.append(digits, std::to_chars(digits, digits + sizeof digits, value).ptr); };
  const int nn = (int)(table.size() / nodalColumnCount);
  for (int i = 0; i < nn; i++) {
    const double *row = table.data() + (size_t)i * nodalColumnCount;
    for (size_t c = 0; c < file.columns.size(); c++) {
      if (c > 0) text += ' ';
      switch (const int source = file.columns[c]) {
        case NodesFile::Step: integer(n); break;
        case NodesFile::Time: number(t); break;
        case NodesFile::Node: integer(i); break;
        case NodesFile::X: number(x[i]); break;
        case NodesFile::Y: number(y[i]); break;
        case NodesFile::Z: number(z[i]); break;
        default:
          if (nodal[source].integer) integer(std::lround(row[source]));
          else number(row[source]);
      }
    }
    text += '\n';
  }
  std::ofstream &f = file.stream;
  f.write(text.data(), (std::streamsize)text.size());
  return f ? 0 : 1;
}

// ---------------------------------------------------------------- zone_boundaries.txt
// The rows the records kept (zoneBoundaryRows), appended to path (the script wrote the header),
// 17 digits; t = step dt, as the history's. 1 if the file was not written whole.
long writeZoneBoundaries(const Kernel &k, const std::string &path) {
  std::ofstream f(path, std::ios::app);
  f.precision(17);
  for (const ZoneBoundary &r : k.record.boundaries) {
    f << r.step << " " << r.step * k.settings.dt << " " << r.kind << " ";
    if (std::isnan(r.s)) f << "nan"; else f << r.s + 0.;
    f << " " << r.x + 0. << " " << r.y + 0. << " " << r.z + 0. << "\n";
  }
  f.close();
  return f.fail() ? 1 : 0;
}

// ---------------------------------------------------------------- the record of a step
void recordStart(Kernel &k, const double *v0, const double *u0, double *Mv, double *Bu) {
  requireNodes(k, "contactKernelRecordStart");
  requireSlots(k, "contactKernelRecordStart");
  requireProducts(k, "contactKernelRecordStart");
  const ProductMatrices &products = k.products;
  EnergyRecord &record = k.record;
  const int n = products.n;
  if (k.factor.n != n) kernelError("contactKernelRecordStart: wrong argument sizes");
  record.vOld.assign(v0, v0 + n);
  record.Mv.resize(n); record.Av.resize(n); record.Bv.resize(n);
  std::vector<double> u(u0, u0 + n), Mu(n);
  products.apply(record.vOld.data(), record.Mv.data(), record.Av.data(), record.Bv.data());
  double kinetic = 0;
  for (int i = 0; i < n; i++) { Mv[i] = record.Mv[i]; kinetic += 0.5 * record.vOld[i] * record.Mv[i]; }
  products.apply(u.data(), Mu.data(), record.Av.data(), record.Bv.data());
  double elastic = 0;
  for (int i = 0; i < n; i++) { Bu[i] = record.Bv[i]; elastic += 0.5 * u[i] * record.Bv[i]; }
  record.energyOld = kinetic + elastic;
  record.generation = k.factor.generation;
  record.step = 0;
  record.boundaries.clear();
}

// In: v = v_n, u = u_n, Lam (total contact stress per slot), f = f_n (the load of the step),
// Mv = M v_{n-1}, Bu = B u_{n-1}. Out: Mv = M v_n and Bu = B u_n (for the next right-hand
// side) and rec, the columns "record" of columns.hpp: the energy terms, the forces, the zone
// counts, x_B and x_C (1e300 for one that does not exist), their estimates, the counts of the
// zone boundaries on Gamma3's edges (their rows kept for writeZoneBoundaries, the step numbered
// on after step_offset); the tangential forces sum W lambda_tau and W lambda_tau2 in 2D (the
// second 0), and in 3D are the vector sum of W (lambda_tau t1 + lambda_tau2 t2) on Gamma3's
// mean frame T1, T2. The discrete energy balance
// (docs/design.md, section "Energy identity"), test function w = v_n:
//   E_n - E_{n-1} + 1/2 m(v_n - v_{n-1}) + k^2/2 b(v_n) + k a(v_n) + k (C'W Lam)'v_n = k f_n'v_n
bool recordStep(Kernel &kernel, const double *pv0, const double *pu0, const double *Lam, const double *pf0, double *pMv0,
                double *pBu0, double *rec) {
  const ProductMatrices &products = kernel.products;
  const ContactNodes &nodes = kernel.nodes;
  EnergyRecord &record = kernel.record;
  const double dt = kernel.settings.dt;
  // three products in one pass; M (v_n - v_{n-1}) = M v_n - M v_{n-1} and B u_n = B u_{n-1} + k B v_n
  // (u_n = u_{n-1} + k v_n), so no product with v_{n-1} or u
  double *vOld = record.vOld.data();
  double vMv = 0, vAv = 0, vBv = 0, dvMdv = 0, uBu = 0, fv = 0;
  products.forEachRow(pv0, [&](int i, double m, double a, double b) {   // each row once its products are known
    const double vi = pv0[i], bu = pBu0[i] + dt * b;
    vMv += vi * m; vAv += vi * a; vBv += vi * b; dvMdv += (vi - vOld[i]) * (m - pMv0[i]);
    uBu += pu0[i] * bu;
    fv += pf0[i] * vi;
    pMv0[i] = m; pBu0[i] = bu; vOld[i] = vi;
  });
  std::vector<double> cv;
  slotVelocities(kernel, pv0, cv);
  double contact = 0;
  for (int j = 0; j < kernel.factor.nc; j++) contact += nodes.slotWeight[j] * Lam[j] * cv[j];
  const double kinetic = 0.5 * vMv, elastic = 0.5 * uBu, kineticJump = 0.5 * dvMdv, elasticJump = 0.5 * dt * dt * vBv;
  const double viscous = dt * vAv, contactWork = dt * contact, external = dt * fv;
  const double numerical = kineticJump + elasticJump;
  const double balance = kinetic + elastic - record.energyOld + numerical + viscous + contactWork - external;
  const double largest = std::max({std::fabs(kinetic), std::fabs(elastic), std::fabs(record.energyOld), numerical,
                                   viscous, std::fabs(contactWork), std::fabs(external)});
  record.energyOld = kinetic + elastic;
  rec[RecordKinetic] = kinetic; rec[RecordElastic] = elastic; rec[RecordNumericalDissipation] = numerical;
  rec[RecordViscousDissipation] = viscous; rec[RecordContactDissipation] = contactWork; rec[RecordExternalWork] = external;
  rec[RecordEnergyResidual] = largest > 0 ? std::fabs(balance) / largest : 0.; rec[RecordKineticJump] = kineticJump;
  rec[RecordElasticJump] = elasticJump;
  std::vector<double> ov;
  nodeVelocities(kernel, pv0, cv, ov);
  double normalForce = 0, tangentialForce = 0, tangentialForce2 = 0, xB = 1e300, xC = 1e300;
  long zones[zoneCount] = {};
  Switches switches;
  switches.bound.resize(nodes.count()); switches.stick.resize(nodes.count());
  for (int i = 0; i < nodes.count(); i++) {
    const NodeValues s = nodeValues(kernel, i, ov.data(), Lam);
    nodeSwitches(kernel.law.P, s, nodes.g[i], switches.bound[i], switches.stick[i]);
    zones[zone(s.normal, s.tangential)]++;
    if (marksB(s.normal, s.tangential)) xB = std::min(xB, nodes.x[i]);
    if (marksC(s.normal, s.tangential)) xC = std::min(xC, nodes.x[i]);
    normalForce += nodes.weight[i] * s.pn;
    if (nodes.frame.empty()) {                     // 2D: along each node's tangent
      tangentialForce += nodes.weight[i] * s.lt;
      tangentialForce2 += nodes.weight[i] * s.lt2;
    }
    else {                                         // 3D: the vector on Gamma3's mean frame
      const double *f = nodes.frame.data() + 9 * i;
      for (int c = 0; c < 3; c++) {
        const double component = nodes.weight[i] * (s.lt * f[3 + c] + s.lt2 * f[6 + c]);
        tangentialForce += component * nodes.meanT1[c];
        tangentialForce2 += component * nodes.meanT2[c];
      }
    }
  }
  rec[RecordNormalForce] = normalForce; rec[RecordTangentialForce] = tangentialForce;
  for (int z = 0; z < zoneCount; z++) rec[RecordZone0 + z] = zones[z];
  rec[RecordXB] = xB; rec[RecordXC] = xC; rec[RecordTangentialForce2] = tangentialForce2;
  zoneEstimates(kernel, switches, xB, xC, rec[RecordXBEstimate], rec[RecordXCEstimate]);
  const long step = kernel.settings.stepOffset + ++record.step;   // (steps numbered on after a restart)
  long countB = 0, countC = 0;
  zoneBoundaryRows(kernel, switches, step, countB, countC);
  rec[RecordBoundariesB] = countB; rec[RecordBoundariesC] = countC;
  return std::isfinite(balance);
}

}  // namespace contactkernel
