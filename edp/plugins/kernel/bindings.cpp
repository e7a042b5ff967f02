// bindings.cpp: the FreeFEM functions of the compiled kernel (load "contactkernel"), built by
// ./run.sh into edp/plugins/build/ from contactlaw.hpp and the files of this folder whenever
// one of them changes. Each function acts on the current kernel instance (registry.cpp),
// converts FreeFEM's arrays and matrices to plain ones, and calls a module (kernel.hpp). They
// return 0 unless said; misuse stops the run with an error. Tables of values are read by name:
// contactKernelColumn(table, name) is the index of a column (columns.hpp), never a bare number.
//
// Instances
//   contactKernelNew()  a new, empty kernel instance, made current; returns its id (the one the
//       plugin starts with is 0)
//   contactKernelUse(int id)  makes instance id current; returns the id that was
//   contactKernelCurrent()  the current instance's id
//   contactKernelDelete(int id)  frees instance id (not the current one)
// Columns
//   contactKernelColumn(string table, string name)  the index of column name of table (nodal,
//       record, history, solver_info, safeguard_info, counters; columns.hpp); an error if none
//   contactKernelColumns(string table)  how many columns table has
// The law's data (contactlaw.hpp)
//   contactKernelParameter(string name, real value)  a parameter, by its option name: cnu, mu,
//       g, eps, problem (0 original, 1 penalty), penaltyform (0 compliant, 1 literal), tol, maxit,
//       safeguard (0/1), r, dt, ordering (of S's factorization: 0 CAMD, 1 METIS on the
//       interior), verbose (0/1), step_offset (the steps before the record: a restart)
//   contactKernelDampingFamily(string name)  the damping family of that name (dampingFamilies
//       of contactlaw.hpp), -1 if none
//   contactKernelDampingHasC(int family)  1 if the family's first number is C (-cnu overrides it)
//   contactKernelDampingCheck(int family, real[int] numbers)  "" if a scene line "damping NAME
//       numbers..." can be used (numbers: all of them, C included), else why
//   contactKernelDampingText(string what)  for messages: "syntax", every family as
//       "damping NAME NUMBERS"; "with C", the names of the families with C ("linear or power")
//   contactKernelDamping(int family, real[int] numbers)  the law's family and numbers (as the
//       scene line gives them; C itself comes with contactKernelParameter("cnu", ...))
//   contactKernelBoundProfile(real[int] x, real[int] g)  the scene's bound_profile (x
//       increasing; empty arrays: none, g is contactKernelParameter("g", ...) everywhere)
//   contactKernelBoundTable(string axes, real[int] a, real[int] b, real[int] g)  the scene's
//       bound_table: its axes ("xz": any two of x, y, z), its grid along each (increasing) and
//       its values row by row (g[i b.n + j] at (a_i, b_j)); empty arrays: none (not both a
//       profile and a table)
//   contactKernelNodes(real[int] x, real[int] y, real[int] z, real[int] w, int[int] normalSlot,
//       int[int] tangentSlot, int[int] tangentSlot2)  the contact nodes: position (z = 0 in 2D;
//       each node's velocity bound g is the law's there, velocityBound of contactlaw.hpp),
//       weight, slots (-1: none; tangentSlot2, the second tangential slot of a 3D node, makes a pair
//       with tangentSlot under the disk law, or is alone where a Dirichlet condition fixes the
//       first tangent); returns 1 if the law of contactlaw.hpp or its bound is unusable
//       (checkBound, checkLaw; then contactKernelLawProblem(string prefix) gives prefix + the reason)
//   contactKernelNodeVelocity(matrix O)  v -> (v_nu, v_tau) of every node (rows 2i, 2i + 1; in
//       3D (v_nu, v_tau, v_tau2), rows 3i, 3i + 1, 3i + 2): what the nodes report
//   contactKernelNodeFrames(real[int,int] frame, real[int] mean)  3D: each node's n, t1, t2 and
//       Gamma3's mean frame T1, T2 (the record's tangential forces are on T1 and T2)
//   contactKernelNodeEdges(int[int] a, int[int] b)  Gamma3's edges, the pairs (a[e], b[e]) of
//       neighbouring nodes (2D: its boundary edges; 3D: the edges of its triangles), after
//       contactKernelNodes: where the record looks for zone boundaries, and in 2D the positions
//       along Gamma3 (nodes.cpp, setNodeEdges)
//   contactKernelNodeBounds(real[int] g)  each node's velocity bound g (the law's)
//   contactKernelDampingSlope(real[int] Kn)  Kn per slot (p'(g) on normal slots), folded into S
//   contactKernelZones()  how many zones the law has (contactlaw.hpp, zone)
//   contactKernelZoneProblem(0)  why the zones' names cannot name columns ("" if they can)
//   contactKernelZoneName(int z)  zone z's name, as the outputs spell it (free, damped_slip, ...)
// S and the back-substitutions (factorization.cpp, products.cpp)
//   contactKernelFactorize(matrix S, matrix C)  returns 0, or 1 (S not positive definite),
//       2 (CHOLMOD failed)
//   contactKernelFactorizeStep(real cm, real ca, real cb, matrix D, real[int] fixed, matrix C)
//       the same for S = cm M + ca A + cb B + D + 1e30 on the diagonal where fixed is 1, built
//       from the M, A, B of contactKernelProducts (called first): no FreeFEM matrix S
//   contactKernelExternalFactor(int n, matrix C)  no factor: the steps are solved elsewhere (the
//       ranks' solver, edp/plugins/ranks/), the record and the nodal table read n and C
//   contactKernelLargestEntry(matrix S)  the largest |S_ij| (inf or nan if one is not finite)
//   contactKernelDelassus(real[int,int] Dw)  Dw = C S^-1 C' diag(W); sets r_j = r / Dw_jj
//   contactKernelSolve(real[int] b, real[int] x)  x = S^-1 b
//   contactKernelFree(real[int] b, real[int] cFree)  cFree = C S^-1 b (forward half)
//   contactKernelFinish(real[int] m, real[int] v)  v = S^-1 (b - C'W m), b of the last Free
//   contactKernelProducts(matrix M, matrix A, matrix B)  keep M, A, B for:
//   contactKernelMultiply(real[int] v, real[int] Mv, real[int] Av, real[int] Bv)
// The solvers (newton.cpp, fixedpoint.cpp); info: the columns "solver_info"
//   contactKernelNewton(real[int] cFree, real[int] c, real[int] m, real[int] info)  one step's
//       Newton from (c, m); returns the iterations, or -1
//   contactKernelFixedPoint(the same)  the same for the fixed point
//   contactKernelNewtonStep(real[int] rhs, real[int] v, real[int] c, real[int] m, real[int] info)
//   contactKernelFixedPointStep(the same)  Free, the solver, then Finish, in one call
//   contactLawTermsPerRelation()  the terms t of a slot's relation (Slots::termsPerRelation)
//   contactLawRelations(real[int] c, real[int] a, real[int] d, real[int] h, int[int] aSlot,
//       int[int] dSlot)  the relations of the pieces at the last evaluation: term t of slot j
//       at termsPerRelation j + t, sum_t a c[aSlot] + d m[dSlot] = h_j
//   contactNewtonStart(real[int] cFree, real[int] c, real[int] m, real[int] info)  the start of
//       a Newton step: logs iteration 0; returns the natural residual at (c, m); info: the
//       columns "safeguard_info" (its merit: the one the first iterate must lower)
//   contactNewtonSafeguard(real[int] cFree, real[int] previous, real[int] newton, real merit,
//       real[int] c, real[int] m, real[int] info)  the safeguard: from the previous multipliers
//       (whose merit is merit) and the Newton iterate, the (c, m) it keeps; returns 0 (the
//       Newton iterate), 1 (a shortened Newton step), 2 (a fixed-point iteration), 3 (the Newton
//       iterate, kept by the watchdog although its merit rose) or 4 (the watchdog's return to
//       where it started: newton.cpp, safeguardStep); info: the
//       columns "safeguard_info" (unresolved: Slots::unresolvedStatuses when the residual meets
//       tol; the step has converged when it is 0)
//   contactNewtonLog(int it, real residual, int outcome, real step)  -verbose: the log line
//   contactNewtonGuard(int it, real[int] c, real[int] m)  the cycle guard: halves r when the
//       relations of iteration it repeat; returns 1 if it did
//   contactNewtonEnd()  r back to the user's after a step
//   contactNewtonPiecesRepeat()  1 if the pieces of the law's last evaluation are those of the
//       last call in the step (Newton then solves for a correction of m: newton.cpp)
//   contactKernelCounters(real[int] counts)  the run's counts, the columns "counters"
// The record and the outputs (record.cpp)
//   contactKernelRecordStart(real[int] v0, real[int] u0, real[int] Mv, real[int] Bu)  the
//       initial state of the energy balance; Mv = M v0, Bu = B u0
//   contactKernelRecord(real[int] v, real[int] u, real[int] Lambda, real[int] f, real[int] Mv,
//       real[int] Bu, real[int] record)  the record of a step, the columns "record"; Mv, Bu
//       become M v, B u; returns 1 if the energy balance is not finite; keeps the zone
//       boundaries it finds on Gamma3's edges (contactKernelNodeEdges) for:
//   contactKernelZoneBoundaries(string file)  appends the rows of zone_boundaries.txt of every
//       record since contactKernelRecordStart to file (its header written); 1 if the file was
//       not written whole
//   contactKernelStepZoneBoundaries(int step, real[int] points)  the zone boundaries the record
//       of step found, as x y z kind per boundary (kind 1: B, 2: C); returns their count
//       (-adapt refines the mesh around those of a pilot's last step)
//   contactKernelHistory(real[int] info, real[int] history)  the arrays into which each
//       contactKernelRecord then also writes its step's row of the table "history" (t,
//       iterations and residual from info, the solvers' "solver_info", then the record), row n
//       at the n-th record since contactKernelRecordStart; sized before, not resized after
//   contactKernelNodal(real[int] v, real[int] Lambda, real[int,int] table)  per node, the
//       columns "nodal"
//   contactKernelNodesColumns(string names)  the columns of contact_nodes_history.txt's rows:
//       step, t, node, x, y, z, and names of the table "nodal"
//   contactKernelAppendNodes(string file, int n, real t, real[int] x, real[int] y, real[int] z,
//       real[int,int] table)  appends step n's rows (table: contactKernelNodal's) through a
//       stream kept open until contactKernelCloseNodes() (1 if the file was not written whole)
//   contactKernelSourcesChanged(string folder)  1 if the sources in folder are not those this
//       kernel was built from (./run.sh passes their names and POSIX cksum as PLUGIN_SOURCES,
//       PLUGIN_SOURCES_CKSUM), 0 if they are or if that is unknown
#include "ff++.hpp"
#include "AFunction_ext.hpp"
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include "kernel.hpp"
#include "ffarrays.hpp"

namespace contactkernel {

void kernelError(const std::string &message) {
  ExecError(message);
  throw std::runtime_error(message);               // (ExecError throws: not reached)
}

namespace {
Kernel &kernel() { return currentKernel(); }

// The data of a FreeFEM array as a plain pointer (the loops index it directly: through KN's
// strided operator[] they take twice as long). Arrays declared in a script have step 1.
double *contiguous(KN<double> &a, const char *what) {
  if (a.N() > 1 && a.step != 1) ExecError(what);
  return a.N() > 0 ? &a[0] : nullptr;
}
// the values of a (sized n by the caller) as a plain pointer: its own storage when contiguous,
// else a copy in spare (the per-step calls, Free and Finish, copy nothing)
double *plain(KN<double> &a, std::vector<double> &spare) {
  if (a.N() <= 1 || a.step == 1) return a.N() > 0 ? &a[0] : nullptr;
  spare.resize(a.N());
  for (int i = 0; i < a.N(); i++) spare[i] = a[i];
  return spare.data();
}
string *newString(Stack stack, const std::string &text) { return Add2StackOfPtr2Free(stack, new string(text)); }

// ---------------------------------------------------------------- instances, columns
long kernelNew() { return newKernel(); }
long kernelUse(const long &id) { return useKernel(id); }
long kernelCurrent() { return currentKernelId(); }
long kernelDelete(const long &id) { deleteKernel(id); return 0; }

long column(string *const &table, string *const &name) {
  int count = 0;
  if (!columnsOf(*table, count)) ExecError("contactKernelColumn: no table '" + *table + "' (tables: " + tableNames() + ")");
  const int index = columnIndex(*table, *name);
  if (index < 0) ExecError("contactKernelColumn: the table " + *table + " has no column '" + *name + "'");
  return index;
}
long columns(string *const &table) {
  int count = 0;
  if (!columnsOf(*table, count)) ExecError("contactKernelColumns: no table '" + *table + "' (tables: " + tableNames() + ")");
  return count;
}

// ---------------------------------------------------------------- the law's data
long parameter(string *const &name, const double &value) { setParameter(kernel(), *name, value); return 0; }

long dampingFamily(string *const &name) { return contactlaw::findDampingFamily(*name); }
void requireFamily(long family, const char *who) {
  if (family < 0 || family >= contactlaw::dampingFamilyCount) ExecError(std::string(who) + ": no damping family " + std::to_string(family));
}
long dampingHasC(const long &family) {
  requireFamily(family, "contactKernelDampingHasC");
  return contactlaw::dampingFamilies[family].firstIsC;
}
string *dampingCheck(Stack stack, const long &family, KN<double> *const &numbers) {
  requireFamily(family, "contactKernelDampingCheck");
  return newString(stack, contactlaw::checkDampingNumbers((int)family, copyOf(*numbers)));
}
string *dampingText(Stack stack, string *const &what) {
  if (*what == "syntax") return newString(stack, contactlaw::dampingSyntax());
  if (*what == "with C") return newString(stack, contactlaw::dampingNamesWithC());
  ExecError("contactKernelDampingText: 'syntax' or 'with C', not '" + *what + "'");
  return nullptr;
}
long damping(const long &family, KN<double> *const &numbers) {
  setDampingFamily(kernel(), (int)family, copyOf(*numbers));
  return 0;
}

long boundProfile(KN<double> *const &px, KN<double> *const &pg) {
  setBoundProfile(kernel(), copyOf(*px), copyOf(*pg));
  return 0;
}

long boundTable(string *const &axes, KN<double> *const &pa, KN<double> *const &pb, KN<double> *const &pg) {
  setBoundTable(kernel(), *axes, copyOf(*pa), copyOf(*pb), copyOf(*pg));
  return 0;
}

long nodes(KN<double> *const &px, KN<double> *const &py, KN<double> *const &pz, KN<double> *const &pw, KN<long> *const &pns,
           KN<long> *const &pts, KN<long> *const &pts2) {
  const int nn = px->N();
  if (py->N() != nn || pz->N() != nn || pw->N() != nn || pns->N() != nn || pts->N() != nn || pts2->N() != nn)
    ExecError("contactKernelNodes: wrong argument sizes");
  std::vector<double> x = copyOf(*px), y = copyOf(*py), z = copyOf(*pz), w = copyOf(*pw);
  std::vector<long> ns(nn), ts(nn), ts2(nn);
  for (int i = 0; i < nn; i++) { ns[i] = (*pns)[i]; ts[i] = (*pts)[i]; ts2[i] = (*pts2)[i]; }
  return setNodes(kernel(), nn, x.data(), y.data(), z.data(), w.data(), ns.data(), ts.data(), ts2.data());
}
long nodeBounds(KN<double> *const &pg) {
  requireNodes(kernel(), "contactKernelNodeBounds");
  copyInto(*pg, kernel().nodes.g.data(), kernel().nodes.count());
  return 0;
}
long zones() { return contactlaw::zoneCount; }
string *zoneProblem(Stack stack, const long &) { return newString(stack, contactlaw::zoneNamesProblem()); }
string *zoneName(Stack stack, const long &z) {
  if (z < 0 || z >= contactlaw::zoneCount) ExecError("contactKernelZoneName: no zone " + std::to_string(z));
  return newString(stack, contactlaw::zoneNames[z]);
}
// why the law of the last contactKernelNodes that returned 1 cannot be used (the script names
// the scene's lines it came from)
string *lawProblem(Stack stack, string *const &prefix) { return newString(stack, *prefix + kernel().nodes.lawProblem); }

long nodeVelocity(Matrice_Creuse<double> *const &pO) {
  requireNodes(kernel(), "contactKernelNodeVelocity");
  setNodeObservation(kernel(), coo(pO));
  return 0;
}

long nodeFrames(KNM<double> *const &pframe, KN<double> *const &pmean) {
  Kernel &k = kernel();
  requireNodes(k, "contactKernelNodeFrames");
  KNM<double> &frame = *pframe;
  const int nn = k.nodes.count();
  if (frame.N() != nn || frame.M() != 9 || pmean->N() != 6) ExecError("contactKernelNodeFrames: one row of 9 per node and 6 values expected");
  std::vector<double> frames(9 * (size_t)nn);
  for (int i = 0; i < nn; i++) for (int c = 0; c < 9; c++) frames[9 * i + c] = frame(i, c);
  const std::vector<double> mean = copyOf(*pmean);
  setNodeFrames(k, frames, mean.data());
  return 0;
}

long nodeEdges(KN<long> *const &pa, KN<long> *const &pb) {
  std::vector<long> a(pa->N()), b(pb->N());
  for (int e = 0; e < pa->N(); e++) a[e] = (*pa)[e];
  for (int e = 0; e < pb->N(); e++) b[e] = (*pb)[e];
  setNodeEdges(kernel(), a, b);
  return 0;
}

long dampingSlope(KN<double> *const &pKn) {
  Kernel &k = kernel();
  requireNodes(k, "contactKernelDampingSlope");
  copyInto(*pKn, k.law.Kn.data(), k.law.n);
  return 0;
}

// ---------------------------------------------------------------- S and the back-substitutions
long factorizeS(Matrice_Creuse<double> *const &pS, Matrice_Creuse<double> *const &pC) {
  requireNodes(kernel(), "contactKernelFactorize");
  const SparseTriplets S = coo(pS), C = coo(pC);
  return factorize(kernel(), S, C);
}

long factorizeFromProducts(const double &cm, const double &ca, const double &cb, Matrice_Creuse<double> *const &pD,
                           KN<double> *const &fixed, Matrice_Creuse<double> *const &pC) {
  requireNodes(kernel(), "contactKernelFactorizeStep");
  requireProducts(kernel(), "contactKernelFactorizeStep");
  const SparseTriplets D = coo(pD), C = coo(pC);
  StepMatrix step;
  step.cm = cm; step.ca = ca; step.cb = cb; step.D = &D;
  step.fixedCount = fixed->N();
  std::vector<double> fixedValues = copyOf(*fixed);
  step.fixed = fixedValues.data();
  return factorizeStep(kernel(), step, C);
}

long externalFactorBinding(const long &n, Matrice_Creuse<double> *const &pC) {
  externalFactor(kernel(), (int)n, coo(pC));
  return 0;
}

double largestEntry(Matrice_Creuse<double> *const &pS) {
  MatriceMorse<double> &S = *morse(pS);
  double largest = 0;
  for (size_t e = 0; e < S.nnz; e++) {
    const double a = std::fabs(S.aij[e]);
    if (!std::isfinite(a)) return a;
    largest = std::max(largest, a);
  }
  return largest;
}

long delassus(KNM<double> *const &pDw) {
  Kernel &k = kernel();
  computeDelassus(k);
  const int nc = k.factor.nc;
  KNM<double> &Dw = *pDw;
  Dw.resize(nc, nc);
  for (int j = 0; j < nc; j++) for (int i = 0; i < nc; i++) Dw(i, j) = k.factor.Dw[i + (size_t)j * nc];
  return 0;
}

long solve(KN<double> *const &pb, KN<double> *const &px) {
  Kernel &k = kernel();
  requireFactor(k, "contactKernelSolve");
  if (pb->N() != k.factor.n) ExecError("contactKernelSolve: wrong size of the right-hand side");
  std::vector<double> b = copyOf(*pb), x(k.factor.n);
  solveWithFactor(k, b.data(), x.data());
  copyInto(*px, x.data(), k.factor.n);
  return 0;
}

// who: the FreeFEM function called (contactKernelFree, or a *Step function that calls it)
long freeHalfAs(const char *who, KN<double> *const &pb, KN<double> *const &pc) {
  Kernel &k = kernel();
  requireFactor(k, who);
  if (pb->N() != k.factor.n) ExecError(std::string(who) + ": wrong size of the right-hand side");
  std::vector<double> spare, c(k.factor.nc);
  freeVelocity(k, plain(*pb, spare), c.data());
  copyInto(*pc, c.data(), k.factor.nc);
  return 0;
}

long finishHalfAs(const char *who, KN<double> *const &pm, KN<double> *const &pv) {
  Kernel &k = kernel();
  requireFactor(k, who);
  if (!k.factor.haveForward) ExecError(std::string(who) + ": call contactKernelFree first");
  if (pm->N() != k.factor.nc) ExecError(std::string(who) + ": one multiplier per slot expected");
  std::vector<double> m = copyOf(*pm), spare;
  KN<double> &v = *pv;
  if (v.N() != k.factor.n) v.resize(k.factor.n);
  double *out = plain(v, spare);
  finishVelocity(k, m.data(), out);
  if (out == spare.data()) copyInto(v, out, k.factor.n);     // a strided v: written back
  return 0;
}
long freeHalf(KN<double> *const &pb, KN<double> *const &pc) { return freeHalfAs("contactKernelFree", pb, pc); }
long finishHalf(KN<double> *const &pm, KN<double> *const &pv) { return finishHalfAs("contactKernelFinish", pm, pv); }

long products(Matrice_Creuse<double> *const &pM, Matrice_Creuse<double> *const &pA, Matrice_Creuse<double> *const &pB) {
  MatriceMorse<double> *mats[3] = {morse(pM), morse(pA), morse(pB)};
  const int n = mats[0]->n;
  for (int c = 0; c < 3; c++)
    if (mats[c]->n != n || mats[c]->m != n || mats[c]->half)
      ExecError("contactKernelProducts: M, A, B must be square, of one size, stored in full (not sym)");
  const SparseTriplets assembled[3] = {triplets(*mats[0]), triplets(*mats[1]), triplets(*mats[2])};
  if (sameProductPattern(assembled)) { mergeProducts(kernel(), assembled); return 0; }
  SparseRows rows[3];
  for (int c = 0; c < 3; c++) {
    mats[c]->CSR();
    rows[c].start = mats[c]->p; rows[c].column = mats[c]->j; rows[c].value = mats[c]->aij;
  }
  mergeProductRows(kernel(), rows, n);
  return 0;
}

long multiply(KN<double> *const &pv, KN<double> *const &pMv, KN<double> *const &pAv, KN<double> *const &pBv) {
  const Kernel &k = kernel();
  requireProducts(k, "contactKernelMultiply");
  KN<double> &v = *pv, &Mv = *pMv, &Av = *pAv, &Bv = *pBv;
  const int n = k.products.n;
  if (v.N() != n) ExecError("contactKernelMultiply: wrong size of v");
  if (Mv.N() != n) Mv.resize(n);
  if (Av.N() != n) Av.resize(n);
  if (Bv.N() != n) Bv.resize(n);
  const char *strided = "contactKernelMultiply: arrays must be contiguous";
  const double *x = contiguous(v, strided);
  double *pm = contiguous(Mv, strided), *pa = contiguous(Av, strided), *pb = contiguous(Bv, strided);
  if (x == pm || x == pa || x == pb) ExecError("contactKernelMultiply: v must not be one of Mv, Av, Bv");
  k.products.apply(x, pm, pa, pb);
  return 0;
}

// ---------------------------------------------------------------- the solvers
typedef long (*StepSolver)(Kernel &, const double *, double *, double *, double *);
long solveContact(StepSolver solver, const char *who, KN<double> *const &pcFree, KN<double> *const &pc,
                  KN<double> *const &pm, KN<double> *const &pinfo) {
  Kernel &k = kernel();
  requireSolver(k, who);
  const int nc = k.factor.nc;
  if (pcFree->N() != nc || pc->N() != nc || pm->N() != nc) ExecError(std::string(who) + ": one value per slot expected");
  std::vector<double> cFree = copyOf(*pcFree), c = copyOf(*pc), m = copyOf(*pm);
  double info[solverInfoColumnCount];
  const long it = solver(k, cFree.data(), c.data(), m.data(), info);
  copyInto(*pc, c.data(), nc);
  copyInto(*pm, m.data(), nc);
  copyInto(*pinfo, info, solverInfoColumnCount);
  return it;
}
long newton(KN<double> *const &pcFree, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  return solveContact(newtonStep, "contactKernelNewton", pcFree, pc, pm, pinfo);
}
long fixedPoint(KN<double> *const &pcFree, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  return solveContact(fixedPointStep, "contactKernelFixedPoint", pcFree, pc, pm, pinfo);
}

// A whole contact solve in one call: cFree = C S^-1 rhs (contactKernelFree), the solver,
// then v = S^-1 (rhs - C'W m) (contactKernelFinish). The same three calls the script makes
// for its own solvers, without the interpreter's cost of three. Messages name the function
// called (contactKernelNewtonStep, contactKernelFixedPointStep).
const char newtonStepName[] = "contactKernelNewtonStep", fixedPointStepName[] = "contactKernelFixedPointStep";
template <StepSolver solver, const char *who>
long wholeStep(KN<double> *const &prhs, KN<double> *const &pv, KN<double> *const &pc, KN<double> *const &pm,
               KN<double> *const &pinfo) {
  requireFactor(kernel(), who);
  KN<double> cFree(kernel().factor.nc);
  KN<double> *pFree = &cFree;
  freeHalfAs(who, prhs, pFree);
  const long it = solveContact(solver, who, pFree, pc, pm, pinfo);
  finishHalfAs(who, pm, pv);
  return it;
}

long termsPerRelation() { return contactlaw::Slots::termsPerRelation; }

long lawRelations(KN<double> *const &pc, KN<double> *const &pa, KN<double> *const &pd, KN<double> *const &ph,
                  KN<long> *const &paSlot, KN<long> *const &pdSlot) {
  Kernel &k = kernel();
  requireNodes(k, "contactLawRelations");
  contactlaw::Slots &law = k.law;
  if (pc->N() != law.n) ExecError("contactLawRelations: one value per slot expected");
  std::vector<double> c = copyOf(*pc);
  law.relations(c.data());
  const int terms = contactlaw::Slots::termsPerRelation * law.n;
  KN<double> &a = *pa, &d = *pd;
  KN<long> &aSlot = *paSlot, &dSlot = *pdSlot;
  copyInto(*ph, law.h.data(), law.n);
  a.resize(terms); d.resize(terms); aSlot.resize(terms); dSlot.resize(terms);
  for (int e = 0; e < terms; e++) { a[e] = law.a[e]; d[e] = law.d[e]; aSlot[e] = law.aSlot[e]; dSlot[e] = law.dSlot[e]; }
  return 0;
}

long newtonLog(const long &it, const double &residual, const long &outcome, const double &step) {
  requireNodes(kernel(), "contactNewtonLog");
  logIteration(kernel(), (int)it, residual, (int)outcome, step);
  return 0;
}

long newtonSafeguard(KN<double> *const &pcFree, KN<double> *const &pprevious, KN<double> *const &pnewton,
                     const double &meritBefore, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  Kernel &k = kernel();
  requireSolver(k, "contactNewtonSafeguard");
  const int nc = k.factor.nc;
  if (pcFree->N() != nc || pprevious->N() != nc || pnewton->N() != nc || pc->N() != nc || pm->N() != nc)
    ExecError("contactNewtonSafeguard: one value per slot expected");
  std::vector<double> cFree = copyOf(*pcFree), previous = copyOf(*pprevious), newtonM = copyOf(*pnewton), c(nc), m(nc);
  double residual = 0, step = 1, merit = meritBefore;
  const int outcome = safeguardStep(k, cFree.data(), previous.data(), newtonM.data(), merit, c.data(), m.data(), residual, step);
  copyInto(*pc, c.data(), nc);
  copyInto(*pm, m.data(), nc);
  int unresolved = 0;
  stepConverged(k, residual, c.data(), unresolved);
  double info[safeguardInfoColumnCount];
  info[SafeguardResidual] = residual; info[SafeguardStep] = step; info[SafeguardMerit] = merit; info[SafeguardUnresolved] = unresolved;
  copyInto(*pinfo, info, safeguardInfoColumnCount);
  return outcome;
}

double newtonStartScript(KN<double> *const &pcFree, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  Kernel &k = kernel();
  requireSolver(k, "contactNewtonStart");
  const int nc = k.factor.nc;
  if (pcFree->N() != nc || pc->N() != nc || pm->N() != nc) ExecError("contactNewtonStart: one value per slot expected");
  std::vector<double> cFree = copyOf(*pcFree), c = copyOf(*pc), m = copyOf(*pm);
  double merit = 0;
  const double residual = newtonStart(k, cFree.data(), c.data(), m.data(), merit);
  double info[safeguardInfoColumnCount];
  info[SafeguardResidual] = residual; info[SafeguardStep] = 1; info[SafeguardMerit] = merit; info[SafeguardUnresolved] = 0;
  copyInto(*pinfo, info, safeguardInfoColumnCount);
  return residual;
}

long newtonGuard(const long &it, KN<double> *const &pc, KN<double> *const &pm) {
  Kernel &k = kernel();
  requireNodes(k, "contactNewtonGuard");
  if (pc->N() != k.law.n || pm->N() != k.law.n) ExecError("contactNewtonGuard: one value per slot expected");
  std::vector<double> c = copyOf(*pc), m = copyOf(*pm);
  return guard(k, (int)it, c.data(), m.data());
}
long newtonEnd() { endStep(kernel()); return 0; }
long newtonPiecesRepeat() { return piecesRepeat(kernel()); }

long counters(KN<double> *const &pcounts) {
  const Kernel &k = kernel();
  double counts[counterColumnCount];
  counts[CounterFallbacks] = k.newton.fallbacks; counts[CounterSweeps] = k.fixedPoint.sweeps;
  counts[CounterFactorizations] = k.newton.factorizations; counts[CounterCorrections] = k.newton.corrections;
  counts[CounterRefinements] = k.newton.refinements; counts[CounterCuts] = k.newton.cuts;
  counts[CounterHalvings] = k.newton.halvings; counts[CounterRetries] = k.newton.retries;
  counts[CounterWatchdogs] = k.newton.watchdogs; counts[CounterWatchdogReturns] = k.newton.watchdogReturns;
  copyInto(*pcounts, counts, counterColumnCount);
  return 0;
}

// ---------------------------------------------------------------- the record and the outputs
long recordStartBinding(KN<double> *const &pv0, KN<double> *const &pu0, KN<double> *const &pMv, KN<double> *const &pBu) {
  Kernel &k = kernel();
  requireNodes(k, "contactKernelRecordStart");
  requireSlots(k, "contactKernelRecordStart");
  requireProducts(k, "contactKernelRecordStart");
  const int n = k.products.n;
  if (pv0->N() != n || pu0->N() != n || k.factor.n != n) ExecError("contactKernelRecordStart: wrong argument sizes");
  std::vector<double> v0 = copyOf(*pv0), u0 = copyOf(*pu0), Mv(n), Bu(n);
  recordStart(k, v0.data(), u0.data(), Mv.data(), Bu.data());
  copyInto(*pMv, Mv.data(), n);
  copyInto(*pBu, Bu.data(), n);
  k.historyArrays = HistoryArrays();                 // a new record writes no rows until contactKernelHistory
  return 0;
}

// The history arrays the record writes into (contactKernelHistory): one call a step instead of
// a line per column (each line costs the interpreter about 1 us). Arrays of the script, kept
// by address.
long historyArrays(KN<double> *const &pinfo, KN<double> *const &phistory) {
  kernel().historyArrays.info = pinfo;
  kernel().historyArrays.rows = phistory;
  return 0;
}
void writeHistoryRow(Kernel &k, const KN<double> &rec) {
  if (!k.historyArrays.rows) return;
  KN<double> &info = *k.historyArrays.info, &history = *k.historyArrays.rows;
  const long n = k.record.step;                     // (recordStep counted this step)
  if (info.N() < solverInfoColumnCount || history.N() < historyColumnCount * n)
    ExecError("contactKernelRecord: the history array holds fewer rows than the steps recorded");
  const long h = historyColumnCount * (n - 1);
  history[h + HistoryT] = (k.settings.stepOffset + n) * k.settings.dt;   // steps numbered on after a restart
  history[h + HistoryIterations] = info[InfoIterations];
  history[h + HistoryResidual] = info[InfoResidual];
  for (int c = 0; c < recordColumnCount; c++) history[h + historyRecordStart + c] = rec[c];
}

long stepRecord(KN<double> *const &pv, KN<double> *const &pu, KN<double> *const &pLam, KN<double> *const &pf,
                KN<double> *const &pMv, KN<double> *const &pBu, KN<double> *const &prec) {
  Kernel &k = kernel();
  if (k.record.generation != k.factor.generation || (!k.factor.L && !k.factor.external))
    ExecError("contactKernelRecord: call contactKernelRecordStart (after the last contactKernelFactorize) first");
  KN<double> &v = *pv, &u = *pu, &f = *pf, &Mv = *pMv, &Bu = *pBu, &rec = *prec;
  const int n = k.products.n;
  if (v.N() != n || u.N() != n || f.N() != n || Mv.N() != n || Bu.N() != n || pLam->N() != k.factor.nc)
    ExecError("contactKernelRecord: wrong argument sizes");
  const char *strided = "contactKernelRecord: arrays must be contiguous";
  const double *pv0 = contiguous(v, strided), *pu0 = contiguous(u, strided), *pf0 = contiguous(f, strided);
  double *pMv0 = contiguous(Mv, strided), *pBu0 = contiguous(Bu, strided);
  // Mv and Bu are overwritten row by row while v and u are still read
  if (pMv0 == pv0 || pMv0 == pu0 || pBu0 == pv0 || pBu0 == pu0 || pMv0 == pBu0)
    ExecError("contactKernelRecord: Mv and Bu must be arrays of their own, not v or u");
  const std::vector<double> Lam = copyOf(*pLam);
  double values[recordColumnCount];
  const bool finite = recordStep(k, pv0, pu0, Lam.data(), pf0, pMv0, pBu0, values);
  copyInto(rec, values, recordColumnCount);
  writeHistoryRow(k, rec);
  return finite ? 0 : 1;
}

long nodal(KN<double> *const &pv, KN<double> *const &pLam, KNM<double> *const &ptable) {
  Kernel &k = kernel();
  requireNodes(k, "contactKernelNodal");
  requireSlots(k, "contactKernelNodal");
  if (pv->N() != k.factor.n || pLam->N() != k.factor.nc) ExecError("contactKernelNodal: wrong argument sizes");
  std::vector<double> v = copyOf(*pv), Lam = copyOf(*pLam), table;
  nodalTable(k, v.data(), Lam.data(), table);
  const int nn = k.nodes.count();
  KNM<double> &out = *ptable;
  out.resize(nn, nodalColumnCount);
  for (int i = 0; i < nn; i++) for (int c = 0; c < nodalColumnCount; c++) out(i, c) = table[(size_t)i * nodalColumnCount + c];
  return 0;
}

long zoneBoundaries(string *const &path) { return writeZoneBoundaries(kernel(), *path); }
long stepZoneBoundaries(const long &step, KN<double> *const &ppoints) {
  std::vector<double> points;
  for (const ZoneBoundary &r : kernel().record.boundaries)
    if (r.step == step) { points.push_back(r.x); points.push_back(r.y); points.push_back(r.z); points.push_back(r.kind); }
  ppoints->resize((long)points.size());
  for (size_t i = 0; i < points.size(); i++) (*ppoints)[(long)i] = points[i];
  return (long)points.size() / 4;
}
long nodesColumns(string *const &names) { setNodesFileColumns(kernel(), *names); return 0; }
long closeNodes() { return closeNodesFile(kernel()); }
long appendNodesBinding(string *const &path, const long &n, const double &t, KN<double> *const &px, KN<double> *const &py,
                        KN<double> *const &pz, KNM<double> *const &ptable) {
  Kernel &k = kernel();
  KNM<double> &table = *ptable;
  const int nn = px->N();
  if (py->N() != nn || table.N() != nn || table.M() < nodalColumnCount) ExecError("contactKernelAppendNodes: wrong argument sizes");
  if (k.nodesFile.hasZ && pz->N() != nn) ExecError("contactKernelAppendNodes: wrong argument sizes");
  std::vector<double> x = copyOf(*px), y = copyOf(*py), z = k.nodesFile.hasZ ? copyOf(*pz) : std::vector<double>();
  std::vector<double> rows((size_t)nn * nodalColumnCount);
  for (int i = 0; i < nn; i++) for (int c = 0; c < nodalColumnCount; c++) rows[(size_t)i * nodalColumnCount + c] = table(i, c);
  return appendNodes(k, *path, n, t, x.data(), y.data(), z.data(), rows);
}

// POSIX cksum (CRC-32, polynomial 0x04C11DB7, then the length) of the files' concatenation,
// as `cat FILES | cksum` prints it; -1 if a file cannot be read
long long posixChecksum(const std::vector<std::string> &files) {
  std::uint32_t table[256];
  for (std::uint32_t i = 0; i < 256; i++) {
    std::uint32_t c = i << 24;
    for (int b = 0; b < 8; b++) c = (c & 0x80000000u) ? (c << 1) ^ 0x04C11DB7u : c << 1;
    table[i] = c;
  }
  std::uint32_t crc = 0;
  unsigned long long length = 0;
  for (const std::string &name : files) {
    std::ifstream f(name, std::ios::binary);
    if (!f) return -1;
    char buffer[65536];
    while (f.read(buffer, sizeof buffer) || f.gcount() > 0) {
      for (std::streamsize i = 0; i < f.gcount(); i++)
        crc = (crc << 8) ^ table[((crc >> 24) ^ (unsigned char)buffer[i]) & 0xFF];
      length += f.gcount();
    }
  }
  for (unsigned long long n = length; n > 0; n >>= 8) crc = (crc << 8) ^ table[((crc >> 24) ^ (n & 0xFF)) & 0xFF];
  return (long long)(~crc);
}

long sourcesChanged(string *const &folder) {
#if defined(PLUGIN_SOURCES_CKSUM) && defined(PLUGIN_SOURCES)
  std::vector<std::string> files;
  std::stringstream in(PLUGIN_SOURCES);
  std::string name;
  while (in >> name) files.push_back(*folder + "/" + name);
  return posixChecksum(files) != (long long)PLUGIN_SOURCES_CKSUM;
#else
  return 0;
#endif
}

}  // namespace
}  // namespace contactkernel

using namespace contactkernel;
typedef KN<double> *Array;
typedef KN<long> *Integers;
typedef KNM<double> *Table;
typedef Matrice_Creuse<double> *Matrix;

static void Load_Init() {
  Global.Add("contactKernelNew", "(", new OneOperator0<long>(kernelNew));
  Global.Add("contactKernelUse", "(", new OneOperator1_<long, long>(kernelUse));
  Global.Add("contactKernelCurrent", "(", new OneOperator0<long>(kernelCurrent));
  Global.Add("contactKernelDelete", "(", new OneOperator1_<long, long>(kernelDelete));
  Global.Add("contactKernelColumn", "(", new OneOperator2_<long, string *, string *>(column));
  Global.Add("contactKernelColumns", "(", new OneOperator1_<long, string *>(columns));
  Global.Add("contactKernelParameter", "(", new OneOperator2_<long, string *, double>(parameter));
  Global.Add("contactKernelDampingFamily", "(", new OneOperator1_<long, string *>(dampingFamily));
  Global.Add("contactKernelDampingHasC", "(", new OneOperator1_<long, long>(dampingHasC));
  Global.Add("contactKernelDampingCheck", "(", new OneOperator2s_<string *, long, Array>(dampingCheck));
  Global.Add("contactKernelDampingText", "(", new OneOperator1s_<string *, string *>(dampingText));
  Global.Add("contactKernelDamping", "(", new OneOperator2_<long, long, Array>(damping));
  Global.Add("contactKernelBoundProfile", "(", new OneOperator2_<long, Array, Array>(boundProfile));
  Global.Add("contactKernelBoundTable", "(", new OneOperator4_<long, string *, Array, Array, Array>(boundTable));
  Global.Add("contactKernelNodes", "(", new OneOperator7_<long, Array, Array, Array, Array, Integers, Integers, Integers>(nodes));
  Global.Add("contactKernelNodeBounds", "(", new OneOperator1_<long, Array>(nodeBounds));
  Global.Add("contactKernelZones", "(", new OneOperator0<long>(zones));
  Global.Add("contactKernelZoneProblem", "(", new OneOperator1s_<string *, long>(zoneProblem));
  Global.Add("contactKernelZoneName", "(", new OneOperator1s_<string *, long>(zoneName));
  Global.Add("contactKernelLawProblem", "(", new OneOperator1s_<string *, string *>(lawProblem));
  Global.Add("contactKernelNodeVelocity", "(", new OneOperator1_<long, Matrix>(nodeVelocity));
  Global.Add("contactKernelNodeFrames", "(", new OneOperator2_<long, Table, Array>(nodeFrames));
  Global.Add("contactKernelNodeEdges", "(", new OneOperator2_<long, Integers, Integers>(nodeEdges));
  Global.Add("contactKernelDampingSlope", "(", new OneOperator1_<long, Array>(dampingSlope));
  Global.Add("contactKernelFactorize", "(", new OneOperator2_<long, Matrix, Matrix>(factorizeS));
  Global.Add("contactKernelFactorizeStep", "(", new OneOperator6_<long, double, double, double, Matrix, Array, Matrix>(factorizeFromProducts));
  Global.Add("contactKernelExternalFactor", "(", new OneOperator2_<long, long, Matrix>(externalFactorBinding));
  Global.Add("contactKernelLargestEntry", "(", new OneOperator1_<double, Matrix>(largestEntry));
  Global.Add("contactKernelDelassus", "(", new OneOperator1_<long, Table>(delassus));
  Global.Add("contactKernelSolve", "(", new OneOperator2_<long, Array, Array>(solve));
  Global.Add("contactKernelFree", "(", new OneOperator2_<long, Array, Array>(freeHalf));
  Global.Add("contactKernelFinish", "(", new OneOperator2_<long, Array, Array>(finishHalf));
  Global.Add("contactKernelProducts", "(", new OneOperator3_<long, Matrix, Matrix, Matrix>(products));
  Global.Add("contactKernelMultiply", "(", new OneOperator4_<long, Array, Array, Array, Array>(multiply));
  Global.Add("contactKernelNewton", "(", new OneOperator4_<long, Array, Array, Array, Array>(newton));
  Global.Add("contactKernelFixedPoint", "(", new OneOperator4_<long, Array, Array, Array, Array>(fixedPoint));
  Global.Add("contactKernelNewtonStep", "(", new OneOperator5_<long, Array, Array, Array, Array, Array>(wholeStep<newtonStep, newtonStepName>));
  Global.Add("contactKernelFixedPointStep", "(", new OneOperator5_<long, Array, Array, Array, Array, Array>(wholeStep<fixedPointStep, fixedPointStepName>));
  Global.Add("contactLawTermsPerRelation", "(", new OneOperator0<long>(termsPerRelation));
  Global.Add("contactLawRelations", "(", new OneOperator6_<long, Array, Array, Array, Array, Integers, Integers>(lawRelations));
  Global.Add("contactNewtonLog", "(", new OneOperator4_<long, long, double, long, double>(newtonLog));
  Global.Add("contactNewtonGuard", "(", new OneOperator3_<long, long, Array, Array>(newtonGuard));
  Global.Add("contactNewtonEnd", "(", new OneOperator0<long>(newtonEnd));
  Global.Add("contactNewtonPiecesRepeat", "(", new OneOperator0<long>(newtonPiecesRepeat));
  Global.Add("contactNewtonStart", "(", new OneOperator4_<double, Array, Array, Array, Array>(newtonStartScript));
  Global.Add("contactNewtonSafeguard", "(", new OneOperator7_<long, Array, Array, Array, double, Array, Array, Array>(newtonSafeguard));
  Global.Add("contactKernelCounters", "(", new OneOperator1_<long, Array>(counters));
  Global.Add("contactKernelRecordStart", "(", new OneOperator4_<long, Array, Array, Array, Array>(recordStartBinding));
  Global.Add("contactKernelRecord", "(", new OneOperator7_<long, Array, Array, Array, Array, Array, Array, Array>(stepRecord));
  Global.Add("contactKernelHistory", "(", new OneOperator2_<long, Array, Array>(historyArrays));
  Global.Add("contactKernelNodal", "(", new OneOperator3_<long, Array, Array, Table>(nodal));
  Global.Add("contactKernelNodesColumns", "(", new OneOperator1_<long, string *>(nodesColumns));
  Global.Add("contactKernelAppendNodes", "(", new OneOperator7_<long, string *, long, double, Array, Array, Array, Table>(appendNodesBinding));
  Global.Add("contactKernelCloseNodes", "(", new OneOperator0<long>(closeNodes));
  Global.Add("contactKernelZoneBoundaries", "(", new OneOperator1_<long, string *>(zoneBoundaries));
  Global.Add("contactKernelStepZoneBoundaries", "(", new OneOperator2_<long, long, KN<double> *>(stepZoneBoundaries));
  Global.Add("contactKernelSourcesChanged", "(", new OneOperator1_<long, string *>(sourcesChanged));
}

LOADFUNC(Load_Init)
