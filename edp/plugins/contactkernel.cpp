// contactkernel.cpp: the compiled kernel of edp/solve.edp, a FreeFEM plugin (load
// "contactkernel") that ./run.sh builds into edp/plugins/build/ whenever this file or
// contactlaw.hpp changes. docs/performance.md, "How a step is solved", explains the choices.
//
// 1. Linear algebra with one factorization of S = M/k + A + kB + C'W Kn C (symmetric
//    positive definite; Dirichlet rows carry FreeFEM's tgv). CHOLMOD factorizes P S P' = L L'
//    with an ordering that puts the contact degrees of freedom (those C touches) last (CAMD in
//    2D; in 3D METIS's nested dissection of the others, then them: docs/performance.md, "Three
//    dimensions", measured both),
//    so the trailing block L_CC of L is the Cholesky factor of the Schur complement of S on
//    Gamma3:
//      - the Delassus matrix C S^-1 C' = G'G with G = L_CC^-1 (P C')_C, no solve per slot;
//      - a back-substitution splits in two halves around the contact solve: the forward
//        sweep z = L^-1 P b gives the free slot velocities c_free = C S^-1 b, and the contact
//        load only changes the trailing block of z before the backward sweep v = P' L^-T z.
// 2. The nodal laws: contactlaw.hpp, the one definition. The solvers of a step use it
//    through the Slots object below: the semismooth Newton of contactKernelNewton, the
//    fixed point of contactKernelFixedPoint (projected Gauss-Seidel with Anderson
//    acceleration; Newton's safeguard falls back on its iteration), and the script solvers
//    of edp/lib/solvers.idp through contactNewtonStart / contactLawRelations /
//    contactNewtonGuard / contactNewtonSafeguard / contactNewtonEnd.
// 3. The record of a step (the energy terms of history.txt, the forces, zones, x_B, x_C of
//    contact_history.txt) and the nodal values of contact.txt, from the same statuses.
//
// FreeFEM functions (they return 0 unless said; misuse stops the run with an error):
//   contactKernelParameter(string name, real value)  a parameter, by its option name: cnu, mu,
//       eps, problem (0 original, 1 penalty), penaltyform (0 compliant, 1 literal), tol, maxit,
//       safeguard (0/1), r, dt, ordering (of S's factorization: 0 CAMD, 1 METIS on the interior);
//       and the scene's damping family: damping (0 linear, 1 power,
//       2 table), alpha
//   contactKernelDampingTable(real[int] r, real[int] p)   the points of the table family
//   contactKernelNodes(real[int] x, real[int] w, real[int] g, int[int] normalSlot,
//       int[int] tangentSlot, int[int] tangentSlot2)  the contact nodes: weight, velocity bound,
//       slots (-1: none; tangentSlot2, the second tangential slot of a 3D node, makes a pair
//       with tangentSlot under the disk law, or is alone where a Dirichlet condition fixes the
//       first tangent); returns 1 if the law of contactlaw.hpp is unusable (checkLaw; then
//       contactKernelLawProblem(string prefix) gives prefix + the reason)
//   contactKernelNodeVelocity(matrix O)   v -> (v_nu, v_tau) of every node (rows 2i, 2i + 1;
//       in 3D (v_nu, v_tau, v_tau2), rows 3i, 3i + 1, 3i + 2): what the nodes report (a node may
//       have fewer slots than velocities)
//   contactKernelNodeFrames(real[int,int] frame, real[int] mean)   3D: each node's n, t1, t2 and
//       Gamma3's mean frame T1, T2: the record's tangential forces are the total friction stress
//       vector on T1 and T2
//   contactKernelDampingSlope(real[int] Kn)   Kn per slot (p'(g) on normal slots), folded into S
//   contactKernelFactorize(matrix S, matrix C)   returns 0, or 1 (S not positive definite),
//       2 (CHOLMOD failed)
//   contactKernelFactorizeStep(real cm, real ca, real cb, matrix D, real[int] fixed, matrix C)
//       the same for S = cm M + ca A + cb B + D + 1e30 on the diagonal where fixed is 1, built
//       from the M, A, B of contactKernelProducts (called first): no FreeFEM matrix S
//   contactKernelLargestEntry(matrix S)   the largest |S_ij| (inf or nan if one is not finite)
//   contactKernelDelassus(real[int,int] Dw)   Dw = C S^-1 C' diag(W); sets r_j = r / Dw_jj
//   contactKernelSolve(real[int] b, real[int] x)    x = S^-1 b
//   contactKernelFree(real[int] b, real[int] cFree)  cFree = C S^-1 b (forward half)
//   contactKernelFinish(real[int] m, real[int] v)    v = S^-1 (b - C'W m), b of the last Free
//   contactKernelProducts(matrix M, matrix A, matrix B)   keep M, A, B for:
//   contactKernelMultiply(real[int] v, real[int] Mv, real[int] Av, real[int] Bv)
//   contactKernelRecordStart(real[int] v0, real[int] u0, real[int] Mv, real[int] Bu)
//       the initial state of the energy balance; Mv = M v0, Bu = B u0
//   contactKernelRecord(real[int] v, real[int] u, real[int] Lambda, real[int] f, real[int] Mv,
//       real[int] Bu, real[int] record)   the record of a step (see stepRecord); returns 1 if
//       the energy balance is not finite
//   contactKernelHistory(real[int] info, real[int] history, real[int] contactHistory)   the
//       arrays into which each contactKernelRecord then also writes its step's row
//       (writeHistoryRow), with the iterations and residual of the solvers' info
//   contactKernelAppendNodes(string file, int n, real t, real[int] x, real[int] y, real[int] z, real[int,int] table)
//       appends step n's rows of contact_nodes_history.txt (table: contactKernelNodal's; z, v_tau2 and
//       lambda_tau2 in 3D), through a
//       stream kept open until contactKernelCloseNodes() (1 if the file was not written whole)
//   contactKernelNodal(real[int] v, real[int] Lambda, real[int,int] table)  per node: v_nu,
//       v_tau, p_nu, lambda_nu, lambda_tau, normal_status, tangential_status, friction_bound,
//       force scale p(g), zone, v_tau2, lambda_tau2 (0 in 2D), the damped response p(v_nu), g
//   contactKernelNewton(real[int] cFree, real[int] c, real[int] m, real[int] info)  one step's
//       Newton from (c, m); returns the iterations, or -1; info = [residual, iterations,
//       unresolved statuses (Slots::unresolvedStatuses), 1 if the fixed point stalled]
//   contactKernelFixedPoint(real[int] cFree, real[int] c, real[int] m, real[int] info)  the
//       same for the fixed point (the variants of docs/stability.md, "Fixed point", change
//       FP.window and FP.omega below)
//   contactKernelNewtonStep(real[int] rhs, real[int] v, real[int] c, real[int] m, real[int] info)
//   contactKernelFixedPointStep(the same)   Free, the solver, then Finish, in one call
//   contactLawRelations(real[int] c, real[int] a, real[int] d, real[int] h, int[int] aSlot,
//       int[int] dSlot)  the relations of the pieces at the last evaluation: term t of slot j at
//       3 j + t (Slots::termsPerRelation), sum_t a c[aSlot] + d m[dSlot] = h_j
//   contactNewtonStart(real[int] cFree, real[int] c, real[int] m, real[int] info)   the start of
//       a Newton step (newtonStart): logs iteration 0; returns the natural residual at (c, m);
//       info = [that residual, 1, the merit the first iterate must lower]
//   contactNewtonSafeguard(real[int] cFree, real[int] previous, real[int] newton, real merit,
//       real[int] c, real[int] m, real[int] info)   the safeguard (safeguardStep): from the
//       previous multipliers (whose merit is merit) and the Newton iterate, the (c, m) it keeps;
//       returns 0 (the Newton iterate), 1 (a shortened Newton step) or 2 (a fixed-point
//       iteration); info = [natural residual, step, merit, unresolved statuses (when the
//       residual meets tol: Slots::unresolvedStatuses; the step has converged when it is 0)]
//   contactNewtonLog(int it, real residual, int outcome, real step)   -verbose: the log line of
//       iteration it (outcome and step: contactNewtonSafeguard's)
//   contactNewtonGuard(int it, real[int] c, real[int] m)   the cycle guard (guard): halves r
//       when the relations of iteration it repeat; returns 1 if it did (the law is then
//       evaluated again at (c, m))
//   contactNewtonEnd()   r back to the user's after a step
//   contactKernelCounters(real[int] info)   [Newton iterates replaced by a fixed-point
//       iteration, fixed-point sweeps, Newton matrix factorizations, low-rank corrections,
//       refinements of corrected solves, Newton steps shortened, halvings of r, steps retried
//       without the safeguards (a disk law's Newton: newton)], over the run
//   contactKernelSourcesChanged(string folder)   1 if the sources in folder are not those this
//       kernel was built from (./run.sh passes their names and POSIX cksum as PLUGIN_SOURCES,
//       PLUGIN_SOURCES_CKSUM), 0 if they are or if that is unknown
#include "ff++.hpp"
#include "AFunction_ext.hpp"
#include <cholmod.h>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>
#include <cmath>
#include <cfloat>
#include <algorithm>
#include "contactlaw.hpp"

extern "C" {
void dtrsv_(const char *uplo, const char *trans, const char *diag, const int *n, const double *a,
            const int *lda, double *x, const int *incx);
void dtrsm_(const char *side, const char *uplo, const char *transa, const char *diag, const int *m,
            const int *n, const double *alpha, const double *a, const int *lda, double *b, const int *ldb);
void dsyrk_(const char *uplo, const char *trans, const int *n, const int *k, const double *alpha,
            const double *a, const int *lda, const double *beta, double *c, const int *ldc);
void daxpy_(const int *n, const double *alpha, const double *x, const int *incx, double *y, const int *incy);
void dgemv_(const char *trans, const int *m, const int *n, const double *alpha, const double *a,
            const int *lda, const double *x, const int *incx, const double *beta, double *y, const int *incy);
void dgemm_(const char *transa, const char *transb, const int *m, const int *n, const int *k, const double *alpha,
            const double *a, const int *lda, const double *b, const int *ldb, const double *beta, double *c, const int *ldc);
void dgetrf_(const int *m, const int *n, double *a, const int *lda, int *ipiv, int *info);
void dgetrs_(const char *trans, const int *n, const int *nrhs, const double *a, const int *lda,
             const int *ipiv, double *b, const int *ldb, int *info);
void dgetri_(const int *n, double *a, const int *lda, const int *ipiv, double *work, const int *lwork, int *info);
}

namespace {
using namespace contactlaw;

// ---------------------------------------------------------------- the contact nodes and the law
struct Contact {
  std::vector<double> nodeX, nodeW, nodeG;
  std::vector<int> observeStart, observeColumn;          // v -> v_nu, v_tau per node (CSR)
  std::vector<double> observeValue;
  std::vector<int> normalSlot, tangentSlot, tangentSlot2;   // per node, -1: none (tangentSlot2: 3D)
  int rowsPerNode = 2;                         // of the observation: v_nu, v_tau (and v_tau2 in 3D)
  std::vector<double> frame;                   // 3D: per node n, t1, t2 (9 values), and Gamma3's mean
  double meanT1[3] = {0, 0, 0}, meanT2[3] = {0, 0, 0};   // frame T1, T2 (contactKernelNodeFrames)
  std::vector<double> weight;                  // W per slot: its node's weight
  bool ready = false;
};
Contact N;
Slots L;                                       // the law on every slot (contactlaw.hpp)

struct SolverParameters {
  double tol = 1e-10, r = 1, dt = 0;
  int maxit = 50;
  bool safeguards = true;
  bool verbose = false;                        // -verbose: the Newton log (logIteration)
  int ordering = 0;                            // of S's factorization: 0 CAMD, 1 METIS on the interior (factorizeOrFail)
};
SolverParameters SP;

long parameter(string *const &name, const double &value) {
  const std::string &key = *name;
  bool law = true;                             // a law parameter: the slots must be set again
  if (key == "damping") L.P.damping = (int)value;
  else if (key == "alpha") L.P.alpha = value;
  else if (key == "cnu") L.P.cnu = value;
  else if (key == "mu") L.P.mu = value;
  else if (key == "eps") L.P.eps = value;
  else if (key == "problem") L.P.penalty = value != 0;
  else if (key == "penaltyform") L.P.literal = value != 0;
  else {
    law = false;
    if (key == "tol") { SP.tol = value; L.roundoff = 10 * DBL_EPSILON / value; }
    else if (key == "maxit") SP.maxit = (int)value;
    else if (key == "safeguard") SP.safeguards = value != 0;
    else if (key == "r") SP.r = value;
    else if (key == "dt") SP.dt = value;
    else if (key == "verbose") SP.verbose = value != 0;
    else if (key == "ordering") SP.ordering = (int)value;
    else ExecError("contactKernelParameter: unknown parameter '" + key + "'");
  }
  if (law) N.ready = false;
  return 0;
}

long dampingTable(KN<double> *const &pr, KN<double> *const &pp) {
  KN<double> &r = *pr, &p = *pp;
  if (r.N() != p.N() || r.N() < 2) ExecError("contactKernelDampingTable: two arrays of at least two points, of one size");
  L.P.tableR.assign(r.N(), 0.); L.P.tableP.assign(p.N(), 0.);
  for (int k = 0; k < r.N(); k++) { L.P.tableR[k] = r[k]; L.P.tableP[k] = p[k]; }
  N.ready = false;
  return 0;
}

std::string lawProblem;                        // set by nodes() when checkLaw refuses the law
long nodes(KN<double> *const &px, KN<double> *const &pw, KN<double> *const &pg, KN<long> *const &pns,
           KN<long> *const &pts, KN<long> *const &pts2) {
  KN<double> &x = *px, &w = *pw, &g = *pg;
  KN<long> &ns = *pns, &ts = *pts, &ts2 = *pts2;
  const int nn = x.N();
  if (w.N() != nn || g.N() != nn || ns.N() != nn || ts.N() != nn || ts2.N() != nn) ExecError("contactKernelNodes: wrong argument sizes");
  int slots = 0;
  for (int i = 0; i < nn; i++) {
    slots += (ns[i] >= 0) + (ts[i] >= 0) + (ts2[i] >= 0);
  }
  std::vector<int> owner(slots, -1);
  for (int i = 0; i < nn; i++)
    for (long s : {ns[i], ts[i], ts2[i]})
      if (s >= 0) {
        if (s >= slots || owner[s] >= 0) ExecError("contactKernelNodes: slot numbers must be 0 .. slots-1, each used once");
        owner[s] = i;
      }
  N = Contact();
  N.nodeX.resize(nn); N.nodeW.resize(nn); N.nodeG.resize(nn); N.normalSlot.resize(nn); N.tangentSlot.resize(nn);
  N.tangentSlot2.resize(nn);
  for (int i = 0; i < nn; i++) {
    N.nodeX[i] = x[i]; N.nodeW[i] = w[i]; N.nodeG[i] = g[i]; N.normalSlot[i] = ns[i]; N.tangentSlot[i] = ts[i];
    N.tangentSlot2[i] = ts2[i];
  }
  N.weight.assign(slots, 0.);
  L.resize(slots);
  for (int i = 0; i < nn; i++) {
    if (!(g[i] > 0)) ExecError("contactKernelNodes: every velocity bound g must be > 0");
    if (ts[i] >= 0) { L.normal[ts[i]] = 0; L.partner[ts[i]] = ns[i]; }
    if (ts2[i] >= 0) { L.normal[ts2[i]] = 0; L.partner[ts2[i]] = ns[i]; }
    if (ts[i] >= 0 && ts2[i] >= 0) { L.pair[ts[i]] = ts2[i]; L.pair[ts2[i]] = ts[i]; }   // the disk
    for (long s : {ns[i], ts[i], ts2[i]}) if (s >= 0) N.weight[s] = w[i];
  }
  for (int j = 0; j < slots; j++) { L.setBound(j, g[owner[j]]); L.setAugmentation(j, SP.r); }
  std::string why;
  lawProblem.clear();
  for (int i = 0; i < nn; i++)
    if (checkLaw(L.P, g[i], why)) {
      char data[160];
      std::snprintf(data, sizeof data, " (c_nu = %g, mu = %g, g = %g)", L.P.cnu, L.P.mu, g[i]);
      lawProblem = "the law of edp/plugins/contactlaw.hpp cannot be used: " + why + data;
      return 1;
    }
  N.ready = true;
  return 0;
}
// why the law of the last contactKernelNodes that returned 1 cannot be used (the script names
// the scene's lines it came from)
string *lawProblemText(Stack stack, string *const &prefix) { return Add2StackOfPtr2Free(stack, new string(*prefix + lawProblem)); }

long nodeVelocity(Matrice_Creuse<double> *const &pO);

void requireNodes(const char *who) {
  if (!N.ready) ExecError(std::string(who) + ": call contactKernelNodes first (after the last contactKernelParameter)");
}

long dampingSlope(KN<double> *const &pKn) {
  requireNodes("contactKernelDampingSlope");
  KN<double> &Kn = *pKn;
  Kn.resize(L.n);
  for (int j = 0; j < L.n; j++) Kn[j] = L.Kn[j];
  return 0;
}

// ---------------------------------------------------------------- linear algebra state
struct Factor {
  cholmod_common common;
  bool started = false;
  cholmod_factor *L = nullptr;
  cholmod_dense *work = nullptr, *x = nullptr, *y = nullptr, *e = nullptr;
  int n = 0, nc = 0, nt = 0;            // unknowns, contact slots, trailing (contact) unknowns
  std::vector<double> Ltrail;           // L_CC, nt x nt, column-major, lower triangular
  std::vector<int> slotOf, posOf, dofOf; // C as triplets: slot, trailing position (dof), value
  std::vector<double> valOf;
  std::vector<double> z;                // forward sweep of the last contactKernelFree
  std::vector<double> Dw;               // nc x nc, column-major (contactKernelDelassus)
  std::vector<double> rReference;       // 1/(Dw)_jj: the augmentation the convergence test reads
  bool haveForward = false;
  long generation = 0;                  // counts the calls of contactKernelFactorize
  long delassusGeneration = -1;         // the factor Dw belongs to

  // forget the factor and everything derived from it; L is then null, so a factor exists
  // (L != null) only after a successful contactKernelFactorize
  void release() {
    haveForward = false;
    n = nc = nt = 0;
    Ltrail.clear(); slotOf.clear(); posOf.clear(); dofOf.clear(); valOf.clear();
    z.clear(); Dw.clear();
    if (!started) return;
    if (L) cholmod_free_factor(&L, &common);
    if (work) cholmod_free_dense(&work, &common);
    if (x) cholmod_free_dense(&x, &common);
    if (y) cholmod_free_dense(&y, &common);
    if (e) cholmod_free_dense(&e, &common);
    cholmod_finish(&common);
    started = false;
  }
  // x <- op(b) with CHOLMOD, workspace kept between calls
  void apply(int sys, const double *in, double *out) {
    std::copy(in, in + n, static_cast<double *>(work->x));
    cholmod_solve2(sys, L, work, nullptr, &x, nullptr, &y, &e, &common);
    std::copy(static_cast<double *>(x->x), static_cast<double *>(x->x) + n, out);
  }
};
Factor F;

MatriceMorse<double> *morse(Matrice_Creuse<double> *A) {
  MatriceCreuse<double> *a = A->A;
  if (!a) ExecError("contactkernel: empty matrix");
  MatriceMorse<double> *m = dynamic_cast<MatriceMorse<double> *>(a);
  if (!m) ExecError("contactkernel: the matrix is not a sparse (Morse) matrix");
  return m;
}

long factorizeOrFail(MatriceMorse<double> *S, MatriceMorse<double> &C, int n);
cholmod_sparse *upperFromProducts();

void checkContactOperator(MatriceMorse<double> &C, int n, const char *who) {
  if (C.m != n) ExecError(std::string(who) + ": S must be square, with as many columns as C");
  if (C.n != L.n)
    ExecError(std::string(who) + ": C has " + std::to_string(C.n) + " rows, but contactKernelNodes gave "
              + std::to_string(L.n) + " slots");
}

// On any failure the kernel is left with no factor, so that a later call raises an error.
long factorize(Matrice_Creuse<double> *const &pS, Matrice_Creuse<double> *const &pC) {
  requireNodes("contactKernelFactorize");
  MatriceMorse<double> &S = *morse(pS), &C = *morse(pC);
  if (S.n != S.m) ExecError("contactKernelFactorize: S must be square, with as many columns as C");
  checkContactOperator(C, S.n, "contactKernelFactorize");
  F.release();
  F.generation++;
  const long status = factorizeOrFail(&S, C, S.n);
  if (status != 0) F.release();
  return status;
}

// the upper triangle of S (stype = 1) from a FreeFEM matrix; a half-stored (sym) matrix keeps
// its lower triangle
cholmod_sparse *upperFromMorse(MatriceMorse<double> &S) {
  const int n = S.n;
  S.COO();
  size_t nz = 0;
  for (size_t k = 0; k < S.nnz; k++) if (S.half || S.i[k] <= S.j[k]) nz++;
  cholmod_triplet *T = cholmod_allocate_triplet(n, n, nz, 1, CHOLMOD_REAL, &F.common);
  int *Ti = static_cast<int *>(T->i), *Tj = static_cast<int *>(T->j);
  double *Tx = static_cast<double *>(T->x);
  for (size_t k = 0; k < S.nnz; k++) {
    int i = S.i[k], j = S.j[k];
    if (!S.half && i > j) continue;
    Ti[T->nnz] = std::min(i, j); Tj[T->nnz] = std::max(i, j); Tx[T->nnz] = S.aij[k]; T->nnz++;
  }
  cholmod_sparse *A = cholmod_triplet_to_sparse(T, nz, &F.common);
  cholmod_free_triplet(&T, &F.common);
  return A;
}

// METIS (CHOLMOD's nested dissection through METIS_NodeND) on the interior unknowns, the
// pattern of A (upper triangle) restricted to them, then the contact unknowns (member 1) last,
// in their order; 1 if it worked
int metisContactLast(cholmod_sparse *A, const std::vector<int> &member, std::vector<int> &perm) {
  const int n = A->ncol;
  const int *Ap = static_cast<int *>(A->p), *Ai = static_cast<int *>(A->i);
  std::vector<int> position(n, -1), interior;
  for (int i = 0; i < n; i++) if (!member[i]) { position[i] = interior.size(); interior.push_back(i); }
  const int ni = interior.size();
  std::vector<int> start(ni + 1, 0);
  for (int j = 0; j < n; j++)
    if (position[j] >= 0)
      for (int e = Ap[j]; e < Ap[j + 1]; e++) if (position[Ai[e]] >= 0 && Ai[e] <= j) start[position[j] + 1]++;
  for (int k = 0; k < ni; k++) start[k + 1] += start[k];
  cholmod_sparse *B = cholmod_allocate_sparse(ni, ni, start[ni], 1, 1, 1, CHOLMOD_PATTERN, &F.common);
  if (!B) return 0;
  int *Bp = static_cast<int *>(B->p), *Bi = static_cast<int *>(B->i);
  std::copy(start.begin(), start.end(), Bp);
  for (int j = 0; j < n; j++)                        // A's columns come with their rows sorted
    if (position[j] >= 0)
      for (int e = Ap[j]; e < Ap[j + 1]; e++) if (position[Ai[e]] >= 0 && Ai[e] <= j) Bi[start[position[j]]++] = position[Ai[e]];
  std::vector<int> order(std::max(ni, 1));
  const int ok = ni == 0 || cholmod_metis(B, nullptr, 0, 1, order.data(), &F.common);
  cholmod_free_sparse(&B, &F.common);
  if (!ok) return 0;
  int k = 0;
  for (int q = 0; q < ni; q++) perm[k++] = interior[order[q]];
  for (int i = 0; i < n; i++) if (member[i]) perm[k++] = i;
  return 1;
}

long factorizeOrFail(MatriceMorse<double> *S, MatriceMorse<double> &C, int n) {
  cholmod_start(&F.common);
  F.started = true;
  F.common.print = 0;
  F.common.error_handler = nullptr;
  F.n = n;
  F.nc = C.n;
  cholmod_sparse *A = S ? upperFromMorse(*S) : upperFromProducts();
  if (!A) return 2;

  // the contact unknowns (columns of C) go last: CAMD with two constraint sets, or (SP.ordering
  // 1) METIS's nested dissection of the interior, then the contact unknowns
  C.COO();
  std::vector<int> member(n, 0);
  for (size_t k = 0; k < C.nnz; k++) if (C.aij[k] != 0) member[C.j[k]] = 1;
  std::vector<int> perm(n);
  int ok = SP.ordering == 1 ? metisContactLast(A, member, perm) : cholmod_camd(A, nullptr, 0, member.data(), perm.data(), &F.common);
  F.common.nmethods = 1;
  F.common.method[0].ordering = CHOLMOD_GIVEN;
  F.common.postorder = 0;
  F.common.supernodal = CHOLMOD_SUPERNODAL;
  if (ok) F.L = cholmod_analyze_p(A, perm.data(), nullptr, 0, &F.common);
  if (F.L) cholmod_factorize(A, F.L, &F.common);
  cholmod_free_sparse(&A, &F.common);
  if (!ok || !F.L || F.common.status == CHOLMOD_OUT_OF_MEMORY || F.common.status == CHOLMOD_INVALID) return 2;
  if (F.common.status == CHOLMOD_NOT_POSDEF || F.L->minor < (size_t)n) return 1;

  // position of each unknown in the factor; the contact unknowns must be the trailing block
  const int *P = static_cast<int *>(F.L->Perm);
  std::vector<int> position(n);
  for (int k = 0; k < n; k++) position[P[k]] = k;
  int nt = 0;
  for (int i = 0; i < n; i++) nt += member[i];
  F.nt = nt;
  for (int i = 0; i < n; i++) if (member[i] && position[i] < n - nt) return 2;
  for (size_t k = 0; k < C.nnz; k++) if (C.aij[k] != 0) {
    F.slotOf.push_back(C.i[k]); F.posOf.push_back(position[C.j[k]] - (n - nt)); F.valOf.push_back(C.aij[k]);
    F.dofOf.push_back(C.j[k]);
  }

  // L_CC from the supernodal factor: the columns n - nt ... n - 1 and their rows
  if (!F.L->is_super) return 2;
  F.Ltrail.assign((size_t)nt * nt, 0.);
  const int *super = static_cast<int *>(F.L->super), *pi = static_cast<int *>(F.L->pi);
  const int *px = static_cast<int *>(F.L->px), *s = static_cast<int *>(F.L->s);
  const double *Lx = static_cast<double *>(F.L->x);
  for (size_t k = 0; k < F.L->nsuper; k++) {
    int k1 = super[k], k2 = super[k + 1], nrow = pi[k + 1] - pi[k];
    for (int jj = k1; jj < k2; jj++) {
      if (jj < n - nt) continue;
      for (int r = 0; r < nrow; r++) {
        int row = s[pi[k] + r];
        if (row < jj) continue;
        F.Ltrail[(size_t)(row - (n - nt)) + (size_t)(jj - (n - nt)) * nt] = Lx[px[k] + r + (size_t)(jj - k1) * nrow];
      }
    }
  }
  F.work = cholmod_zeros(n, 1, CHOLMOD_REAL, &F.common);
  F.z.assign(n, 0.);
  F.haveForward = false;
  return 0;
}

double largestEntry(Matrice_Creuse<double> *const &pS) {
  MatriceMorse<double> &S = *morse(pS);
  double largest = 0;
  for (size_t k = 0; k < S.nnz; k++) {
    const double a = std::fabs(S.aij[k]);
    if (!std::isfinite(a)) return a;
    largest = std::max(largest, a);
  }
  return largest;
}

// 3D: the nodes' frames (rows n, t1, t2 of 9 values) and Gamma3's mean frame [T1, T2]: the
// record sums the friction stress as a vector, sum_i w_i (lambda_tau t1_i + lambda_tau2 t2_i),
// and reports it on T1 and T2 (the nodes' own frames may differ: a curved face, a node with a
// fixed axis)
long nodeFrames(KNM<double> *const &pframe, KN<double> *const &pmean) {
  requireNodes("contactKernelNodeFrames");
  KNM<double> &frame = *pframe;
  KN<double> &mean = *pmean;
  const int nn = N.nodeX.size();
  if (frame.N() != nn || frame.M() != 9 || mean.N() != 6) ExecError("contactKernelNodeFrames: one row of 9 per node and 6 values expected");
  N.frame.assign(9 * (size_t)nn, 0.);
  for (int i = 0; i < nn; i++) for (int k = 0; k < 9; k++) N.frame[9 * i + k] = frame(i, k);
  for (int k = 0; k < 3; k++) { N.meanT1[k] = mean[k]; N.meanT2[k] = mean[3 + k]; }
  return 0;
}

long nodeVelocity(Matrice_Creuse<double> *const &pO) {
  requireNodes("contactKernelNodeVelocity");
  MatriceMorse<double> &O = *morse(pO);
  const int nn = N.nodeX.size();
  if (O.n != 2 * nn && O.n != 3 * nn) ExecError("contactKernelNodeVelocity: two rows per node (2D) or three (3D) expected");
  N.rowsPerNode = nn > 0 ? O.n / nn : 2;
  O.COO();
  std::vector<std::vector<std::pair<int, double>>> rows(O.n);
  for (size_t k = 0; k < O.nnz; k++) rows[O.i[k]].push_back({O.j[k], O.aij[k]});
  N.observeStart.assign(1, 0); N.observeColumn.clear(); N.observeValue.clear();
  for (auto &row : rows) {
    for (auto &e : row) { N.observeColumn.push_back(e.first); N.observeValue.push_back(e.second); }
    N.observeStart.push_back(N.observeColumn.size());
  }
  return 0;
}

// v_nu, v_tau (and v_tau2 in 3D) of every node from v (the observation rows); without them,
// from the slots
void nodeVelocities(const double *v, const std::vector<double> &cv, std::vector<double> &ov) {
  const int nn = N.nodeX.size(), k = N.rowsPerNode;
  ov.assign(k * nn, 0.);
  if (N.observeStart.size() == (size_t)(k * nn + 1)) {
    for (int r = 0; r < k * nn; r++)
      for (int e = N.observeStart[r]; e < N.observeStart[r + 1]; e++) ov[r] += N.observeValue[e] * v[N.observeColumn[e]];
    return;
  }
  for (int i = 0; i < nn; i++) {
    if (N.normalSlot[i] >= 0) ov[k * i] = cv[N.normalSlot[i]];
    if (N.tangentSlot[i] >= 0) ov[k * i + 1] = cv[N.tangentSlot[i]];
    if (k == 3 && N.tangentSlot2[i] >= 0) ov[k * i + 2] = cv[N.tangentSlot2[i]];
  }
}

void requireFactor(const char *who) {
  if (!F.L) ExecError(std::string("contactkernel: ") + who + " without a successful contactKernelFactorize");
}
void requireDelassus(const char *who) {
  requireFactor(who);
  if (F.delassusGeneration != F.generation)
    ExecError(std::string(who) + ": call contactKernelDelassus after the last contactKernelFactorize");
}

long delassus(KNM<double> *const &pDw) {
  requireFactor("contactKernelDelassus");
  const int nt = F.nt, nc = F.nc;
  // G = L_CC^-1 Ct (nt x nc), Ct = (P C')_C
  std::vector<double> G((size_t)nt * nc, 0.);
  for (size_t k = 0; k < F.slotOf.size(); k++) G[F.posOf[k] + (size_t)F.slotOf[k] * nt] += F.valOf[k];
  const double one = 1., zero = 0.;
  if (nt > 0 && nc > 0) dtrsm_("L", "L", "N", "N", &nt, &nc, &one, F.Ltrail.data(), &nt, G.data(), &nt);
  std::vector<double> D((size_t)nc * nc, 0.);
  if (nt > 0 && nc > 0) dsyrk_("U", "T", &nc, &nt, &one, G.data(), &nt, &zero, D.data(), &nc);
  for (int j = 0; j < nc; j++) for (int i = j + 1; i < nc; i++) D[i + (size_t)j * nc] = D[j + (size_t)i * nc];
  F.Dw.assign((size_t)nc * nc, 0.);
  for (int j = 0; j < nc; j++) for (int i = 0; i < nc; i++) F.Dw[i + (size_t)j * nc] = D[i + (size_t)j * nc] * N.weight[j];
  F.delassusGeneration = F.generation;
  KNM<double> &Dw = *pDw;
  Dw.resize(nc, nc);
  for (int j = 0; j < nc; j++) for (int i = 0; i < nc; i++) Dw(i, j) = F.Dw[i + (size_t)j * nc];
  // r_j = r / Dw_jj: the stress a unit velocity of slot j produces through the body, so that
  // the default r = 1 fits any scene
  // (a 3D node's tangential pair shares one: 1 over the mean of its two Dw_jj)
  F.rReference.assign(nc, 0.);
  for (int j = 0; j < nc; j++) {
    const int q = L.pair[j];
    F.rReference[j] = q >= 0 ? 2. / (F.Dw[j + (size_t)j * nc] + F.Dw[q + (size_t)q * nc]) : 1. / F.Dw[j + (size_t)j * nc];
  }
  for (int j = 0; j < nc; j++) L.setAugmentation(j, L.pair[j] >= 0 ? SP.r * F.rReference[j] : SP.r / F.Dw[j + (size_t)j * nc]);
  return 0;
}

long solve(KN<double> *const &pb, KN<double> *const &px) {
  requireFactor("contactKernelSolve");
  KN<double> &b = *pb, &x = *px;
  if (b.N() != F.n) ExecError("contactKernelSolve: wrong size of the right-hand side");
  if (x.N() != F.n) x.resize(F.n);
  std::vector<double> in(F.n), out(F.n);
  for (int i = 0; i < F.n; i++) in[i] = b[i];
  F.apply(CHOLMOD_A, in.data(), out.data());
  for (int i = 0; i < F.n; i++) x[i] = out[i];
  return 0;
}

// trailing block of the solution of L' w = z (uses only the trailing block of z)
void trailingVelocity(const double *zt, double *wt) {
  const int nt = F.nt, inc = 1;
  std::copy(zt, zt + nt, wt);
  if (nt > 0) dtrsv_("L", "T", "N", &nt, F.Ltrail.data(), &nt, wt, &inc);
}

long freeVelocity(KN<double> *const &pb, KN<double> *const &pc) {
  requireFactor("contactKernelFree");
  KN<double> &b = *pb, &c = *pc;
  if (b.N() != F.n) ExecError("contactKernelFree: wrong size of the right-hand side");
  if (c.N() != F.nc) c.resize(F.nc);
  // z = L^-1 P b (the permutation applied here, the triangular solve by CHOLMOD)
  const int *P = static_cast<int *>(F.L->Perm);
  double *work = static_cast<double *>(F.work->x);
  for (int k = 0; k < F.n; k++) work[k] = b[P[k]];
  cholmod_solve2(CHOLMOD_L, F.L, F.work, nullptr, &F.x, nullptr, &F.y, &F.e, &F.common);
  std::copy(static_cast<double *>(F.x->x), static_cast<double *>(F.x->x) + F.n, F.z.begin());
  F.haveForward = true;
  std::vector<double> wt(F.nt);
  trailingVelocity(F.z.data() + (F.n - F.nt), wt.data());
  c = 0.;
  for (size_t k = 0; k < F.slotOf.size(); k++) c[F.slotOf[k]] += F.valOf[k] * wt[F.posOf[k]];
  // the size of the velocities a solver computes from them, c = cFree - Dw m: the law's
  // round-off guard weighs their round-off (Slots::evaluate)
  if ((int)L.velocityScale.size() == F.nc) for (int j = 0; j < F.nc; j++) L.velocityScale[j] = std::fabs(c[j]);
  return 0;
}

long finish(KN<double> *const &pm, KN<double> *const &pv) {
  requireFactor("contactKernelFinish");
  if (!F.haveForward) ExecError("contactKernelFinish: call contactKernelFree first");
  KN<double> &m = *pm, &v = *pv;
  if (m.N() != F.nc) ExecError("contactKernelFinish: one multiplier per slot expected");
  if (v.N() != F.n) v.resize(F.n);
  const int nt = F.nt, inc = 1;
  // the contact load changes the trailing block of z only: z_C -= L_CC^-1 (P C' W m)_C
  std::vector<double> load(nt, 0.);
  for (size_t k = 0; k < F.slotOf.size(); k++) load[F.posOf[k]] += F.valOf[k] * N.weight[F.slotOf[k]] * m[F.slotOf[k]];
  if (nt > 0) dtrsv_("L", "N", "N", &nt, F.Ltrail.data(), &nt, load.data(), &inc);
  double *work = static_cast<double *>(F.work->x);
  std::copy(F.z.begin(), F.z.end(), work);
  for (int i = 0; i < nt; i++) work[F.n - nt + i] -= load[i];
  // v = P' L^-T z
  cholmod_solve2(CHOLMOD_Lt, F.L, F.work, nullptr, &F.x, nullptr, &F.y, &F.e, &F.common);
  const int *P = static_cast<int *>(F.L->Perm);
  const double *w = static_cast<double *>(F.x->x);
  for (int k = 0; k < F.n; k++) v[P[k]] = w[k];
  return 0;
}

// The data of a FreeFEM array as a plain pointer (the loops below index it directly: through
// KN's strided operator[] they take twice as long). Arrays declared in a script have step 1.
double *contiguous(KN<double> &a, const char *what) {
  if (a.N() > 1 && a.step != 1) ExecError(what);
  return a.N() > 0 ? &a[0] : nullptr;
}

std::vector<double> copyOf(const KN<double> &a) {
  std::vector<double> out(a.N());
  for (int i = 0; i < a.N(); i++) out[i] = a[i];
  return out;
}

// slot velocities C v (after a factorization: C is kept as triplets)
void slotVelocities(const double *v, std::vector<double> &cv) {
  cv.assign(F.nc, 0.);
  for (size_t e = 0; e < F.slotOf.size(); e++) cv[F.slotOf[e]] += F.valOf[e] * v[F.dofOf[e]];
}

// ---------------------------------------------------------------- products with M, A, B
// The three matrices of the energy terms share one sparsity pattern (P1 on one mesh): kept
// as one CSR structure with three values per entry, so that M v, A v and B v cost one pass.
// Where the pattern is made of full 2x2 blocks (the two components of a node, as [P1, P1]
// numbers them), also as blocks: one column index and two contiguous x values for four
// entries. Each row is summed over the same entries in the same order either way, so the
// results are the same to the last bit; the blocks only take less time.
struct Products {
  int n = 0;
  std::vector<int> start, column;
  std::vector<double> values;       // 3 per entry: M, A, B (emptied when the blocks hold them)
  bool blocked = false;
  std::vector<int> blockStart, blockColumn;
  std::vector<double> blockValues;  // 12 per block: rows 2I, 2I+1 by columns 2J, 2J+1, each M, A, B

  // row(i, (M x)_i, (A x)_i, (B x)_i) for i = 0 .. n-1, in that order
  template <class Row> void forEachRow(const double *x, Row row) const {
    if (blocked) {
      const double *val = blockValues.data();
      const int *col = blockColumn.data();
      for (int I = 0; I < n / 2; I++) {
        double m0 = 0, a0 = 0, b0 = 0, m1 = 0, a1 = 0, b1 = 0;
        for (int e = blockStart[I]; e < blockStart[I + 1]; e++) {
          const double *w = val + 12 * (size_t)e;
          const double x0 = x[2 * col[e]], x1 = x[2 * col[e] + 1];
          m0 += w[0] * x0; a0 += w[1] * x0; b0 += w[2] * x0;
          m0 += w[3] * x1; a0 += w[4] * x1; b0 += w[5] * x1;
          m1 += w[6] * x0; a1 += w[7] * x0; b1 += w[8] * x0;
          m1 += w[9] * x1; a1 += w[10] * x1; b1 += w[11] * x1;
        }
        row(2 * I, m0, a0, b0);
        row(2 * I + 1, m1, a1, b1);
      }
      return;
    }
    const double *val = values.data();
    const int *col = column.data();
    for (int i = 0; i < n; i++) {
      double m = 0, a = 0, b = 0;
      for (int e = start[i]; e < start[i + 1]; e++) {
        const double xj = x[col[e]];
        m += val[3 * e] * xj; a += val[3 * e + 1] * xj; b += val[3 * e + 2] * xj;
      }
      row(i, m, a, b);
    }
  }
  void apply(const double *x, double *mx, double *ax, double *bx) const {
    forEachRow(x, [&](int i, double m, double a, double b) { mx[i] = m; ax[i] = a; bx[i] = b; });
  }
  // the blocks, when rows 2I and 2I+1 hold the columns 2J, 2J+1 of the same J's (sorted)
  void makeBlocks() {
    blocked = false;
    std::vector<int>(1, 0).swap(blockStart); std::vector<int>().swap(blockColumn); std::vector<double>().swap(blockValues);
    auto fill = [&]() {
      if (n % 2) return false;
      for (int I = 0; I < n / 2; I++) {              // the pattern first: no copy if it is not blocked
        const int r0 = start[2 * I], r1 = start[2 * I + 1], length = r1 - r0;
        if (length % 2 || start[2 * I + 2] - r1 != length) return false;
        for (int e = 0; e < length; e += 2) {
          const int c = column[r0 + e];
          if (c % 2 || column[r0 + e + 1] != c + 1 || column[r1 + e] != c || column[r1 + e + 1] != c + 1) return false;
        }
      }
      const size_t blocks = column.size() / 4;
      blockStart.resize(n / 2 + 1);
      blockColumn.resize(blocks);
      blockValues.resize(12 * blocks);
      size_t b = 0;
      for (int I = 0; I < n / 2; I++) {
        const int r0 = start[2 * I], r1 = start[2 * I + 1], length = r1 - r0;
        blockStart[I] = (int)b;
        for (int e = 0; e < length; e += 2, b++) {
          blockColumn[b] = column[r0 + e] / 2;
          double *w = blockValues.data() + 12 * b;
          std::copy(values.begin() + 3 * (size_t)(r0 + e), values.begin() + 3 * (size_t)(r0 + e + 2), w);
          std::copy(values.begin() + 3 * (size_t)(r1 + e), values.begin() + 3 * (size_t)(r1 + e + 2), w + 6);
        }
      }
      blockStart[n / 2] = (int)b;
      return true;
    };
    if (!fill()) return;                            // the pattern is checked before any block is made
    blocked = true;
    std::vector<double>().swap(values);            // the blocks hold them now (entry() reads them)
  }
  // M, A, B of entry e (of row i) of the CSR pattern
  const double *entry(int i, int e) const {
    if (!blocked) return values.data() + 3 * (size_t)e;
    const int p = e - start[i];
    return blockValues.data() + 12 * (size_t)(blockStart[i / 2] + p / 2) + 6 * (i % 2) + 3 * (p % 2);
  }
};
Products P3;

// M, A, B as FreeFEM assembles them on one mesh: the same entries (i, j), in the same order,
// three values each; then one counting sort by row and a sort within each short row give the
// merged CSR form in one pass, without FreeFEM's CSR conversion of each matrix. Otherwise
// (patterns that differ) the rows of the three CSR forms are merged.
bool samePattern(MatriceMorse<double> *const mats[3]) {
  for (int k = 1; k < 3; k++) {
    if (mats[k]->nnz != mats[0]->nnz || mats[k]->fortran != mats[0]->fortran) return false;
    if (!mats[k]->i || !mats[k]->j || !mats[0]->i || !mats[0]->j) return false;
    for (size_t e = 0; e < mats[0]->nnz; e++)
      if (mats[k]->i[e] != mats[0]->i[e] || mats[k]->j[e] != mats[0]->j[e]) return false;
  }
  return mats[0]->fortran == 0;
}

void mergeByCountingSort(MatriceMorse<double> *const mats[3], int n) {
  const size_t nnz = mats[0]->nnz;
  const int *I = mats[0]->i, *J = mats[0]->j;
  std::vector<int> count(n + 1, 0), order(nnz);
  for (size_t e = 0; e < nnz; e++) count[I[e] + 1]++;
  for (int r = 0; r < n; r++) count[r + 1] += count[r];
  std::vector<int> fill(count.begin(), count.end() - 1);
  for (size_t e = 0; e < nnz; e++) order[fill[I[e]]++] = (int)e;
  P3.n = n;
  P3.start.assign(n + 1, 0);
  P3.column.clear(); P3.values.clear();
  P3.column.reserve(nnz); P3.values.reserve(3 * nnz);
  for (int r = 0; r < n; r++) {
    int *first = order.data() + count[r], *last = order.data() + count[r + 1];
    std::sort(first, last, [&](int a, int b) { return J[a] < J[b]; });
    for (int *o = first; o < last; o++) {
      const int e = *o;
      if (o > first && J[e] == P3.column.back()) {     // a repeated entry adds up
        for (int k = 0; k < 3; k++) P3.values[P3.values.size() - 3 + k] += mats[k]->aij[e];
        continue;
      }
      P3.column.push_back(J[e]);
      for (int k = 0; k < 3; k++) P3.values.push_back(mats[k]->aij[e]);
    }
    P3.start[r + 1] = (int)P3.column.size();
  }
}

long products(Matrice_Creuse<double> *const &pM, Matrice_Creuse<double> *const &pA, Matrice_Creuse<double> *const &pB) {
  MatriceMorse<double> *mats[3] = {morse(pM), morse(pA), morse(pB)};
  const int n = mats[0]->n;
  for (int k = 0; k < 3; k++)
    if (mats[k]->n != n || mats[k]->m != n || mats[k]->half)
      ExecError("contactKernelProducts: M, A, B must be square, of one size, stored in full (not sym)");
  if (samePattern(mats)) { mergeByCountingSort(mats, n); P3.makeBlocks(); return 0; }
  // the union of the three patterns, row by row, with the values of each matrix: the rows of
  // the CSR forms (columns sorted within a row) merged three ways, in one pass over the entries
  const int *rowStart[3], *col[3];
  const double *val[3];
  for (int k = 0; k < 3; k++) {
    mats[k]->CSR();
    rowStart[k] = mats[k]->p; col[k] = mats[k]->j; val[k] = mats[k]->aij;
    for (int i = 0; i < n; i++)                        // CSR sorts (i, j): checked, not assumed
      for (int e = rowStart[k][i] + 1; e < rowStart[k][i + 1]; e++)
        if (col[k][e] <= col[k][e - 1]) ExecError("contactKernelProducts: FreeFEM's CSR form has unsorted rows");
  }
  P3.n = n;
  P3.start.assign(n + 1, 0);
  P3.column.clear(); P3.values.clear();
  P3.column.reserve(mats[0]->nnz); P3.values.reserve(3 * mats[0]->nnz);
  for (int i = 0; i < n; i++) {
    int e[3] = {rowStart[0][i], rowStart[1][i], rowStart[2][i]};
    while (true) {
      int next = INT_MAX;
      for (int k = 0; k < 3; k++) if (e[k] < rowStart[k][i + 1]) next = std::min(next, col[k][e[k]]);
      if (next == INT_MAX) break;
      double v3[3] = {0., 0., 0.};
      for (int k = 0; k < 3; k++)                      // a repeated column adds up, as before
        while (e[k] < rowStart[k][i + 1] && col[k][e[k]] == next) v3[k] += val[k][e[k]++];
      P3.column.push_back(next);
      P3.values.insert(P3.values.end(), v3, v3 + 3);
    }
    P3.start[i + 1] = (int)P3.column.size();
  }
  P3.makeBlocks();
  return 0;
}

// S = cm M + ca A + cb B + D + tgv on the fixed degrees of freedom, from the merged CSR form
// of M, A, B (contactKernelProducts) without a FreeFEM matrix: the upper triangle in CSC, the
// entries (i, j >= i) of each row i in column j, summed in the order of FreeFEM's sum
// (1/k) M + A + k B + D + Dirichlet: the same matrix, to the last bit, as that sum's upper
// triangle, which is what contactKernelFactorize would factorize.
struct StepMatrix {
  double cm = 0, ca = 0, cb = 0, tgv = 1e30;
  MatriceMorse<double> *D = nullptr;
  const double *fixed = nullptr;
};
StepMatrix SM;

cholmod_sparse *upperFromProducts() {
  const int n = P3.n;
  std::vector<int> columnStart(n + 1, 0);          // the entries (i, j >= i) of row i go to column j
  for (int i = 0; i < n; i++)
    for (int e = P3.start[i]; e < P3.start[i + 1]; e++) if (P3.column[e] >= i) columnStart[P3.column[e] + 1]++;
  for (int j = 0; j < n; j++) columnStart[j + 1] += columnStart[j];
  cholmod_sparse *A = cholmod_allocate_sparse(n, n, columnStart[n], 1, 1, 1, CHOLMOD_REAL, &F.common);
  if (!A) return nullptr;
  int *Ap = static_cast<int *>(A->p), *Ai = static_cast<int *>(A->i);
  double *Ax = static_cast<double *>(A->x);
  std::copy(columnStart.begin(), columnStart.end(), Ap);
  std::vector<int> fill(columnStart.begin(), columnStart.end() - 1);
  for (int i = 0; i < n; i++)                        // rows in order: each column's rows come sorted
    for (int e = P3.start[i]; e < P3.start[i + 1]; e++) {
      const int j = P3.column[e];
      if (j < i) continue;
      const double *v = P3.entry(i, e);
      Ai[fill[j]] = i;
      Ax[fill[j]++] = SM.cm * v[0] + v[1] * SM.ca + SM.cb * v[2];
    }
  auto entry = [&](int i, int j) -> double * {       // (i, j), i <= j: in column j, row i
    const int *first = Ai + Ap[j], *last = Ai + Ap[j + 1];
    const int *at = std::lower_bound(first, last, i);
    return at != last && *at == i ? Ax + (at - Ai) : nullptr;
  };
  MatriceMorse<double> &D = *SM.D;
  D.COO();
  for (size_t e = 0; e < D.nnz; e++) {
    int i = D.i[e], j = D.j[e];
    if (D.half) { if (i > j) std::swap(i, j); }
    else if (i > j) continue;
    double *x = entry(i, j);
    if (!x) { cholmod_free_sparse(&A, &F.common); ExecError("contactKernelFactorizeStep: C'W Kn C has an entry outside the pattern of M, A, B"); }
    *x += D.aij[e];
  }
  for (int i = 0; i < n; i++)
    if (SM.fixed[i] != 0) *entry(i, i) += SM.tgv;
  return A;
}

// S = cm M + ca A + cb B + D (+ tgv on the degrees of freedom where fixed is 1), factorized as
// contactKernelFactorize would factorize that matrix (contactKernelProducts first)
long factorizeStep(const double &cm, const double &ca, const double &cb, Matrice_Creuse<double> *const &pD,
                   KN<double> *const &fixed, Matrice_Creuse<double> *const &pC) {
  requireNodes("contactKernelFactorizeStep");
  if (P3.n == 0) ExecError("contactKernelFactorizeStep: call contactKernelProducts first");
  MatriceMorse<double> &D = *morse(pD), &C = *morse(pC);
  if (D.n != P3.n || D.m != P3.n || (int)fixed->N() != P3.n)
    ExecError("contactKernelFactorizeStep: D and the fixed degrees of freedom must have the size of M, A, B");
  checkContactOperator(C, P3.n, "contactKernelFactorizeStep");
  for (int i = 0; i < P3.n; i++) {                   // a fixed degree of freedom needs its diagonal entry
    bool diagonal = false;
    for (int e = P3.start[i]; e < P3.start[i + 1]; e++) diagonal = diagonal || P3.column[e] == i;
    if (!diagonal) ExecError("contactKernelFactorizeStep: M, A, B have no diagonal entry in row " + std::to_string(i));
  }
  SM.cm = cm; SM.ca = ca; SM.cb = cb; SM.D = &D; SM.fixed = &(*fixed)[0];
  F.release();
  F.generation++;
  const long status = factorizeOrFail(nullptr, C, P3.n);
  if (status != 0) F.release();
  SM.D = nullptr; SM.fixed = nullptr;
  return status;
}

long multiply(KN<double> *const &pv, KN<double> *const &pMv, KN<double> *const &pAv, KN<double> *const &pBv) {
  if (P3.n == 0) ExecError("contactKernelMultiply: call contactKernelProducts first");
  KN<double> &v = *pv, &Mv = *pMv, &Av = *pAv, &Bv = *pBv;
  const int n = P3.n;
  if (v.N() != n) ExecError("contactKernelMultiply: wrong size of v");
  if (Mv.N() != n) Mv.resize(n);
  if (Av.N() != n) Av.resize(n);
  if (Bv.N() != n) Bv.resize(n);
  const char *strided = "contactKernelMultiply: arrays must be contiguous";
  const double *x = contiguous(v, strided);
  double *pm = contiguous(Mv, strided), *pa = contiguous(Av, strided), *pb = contiguous(Bv, strided);
  if (x == pm || x == pa || x == pb) ExecError("contactKernelMultiply: v must not be one of Mv, Av, Bv");
  P3.apply(x, pm, pa, pb);
  return 0;
}

// ---------------------------------------------------------------- nodal values, the record
// The values of node i from its velocities ov (nodeVelocities) and the contact stresses Lam,
// with the statuses of contactlaw.hpp (+ 0. turns -0 into 0).
struct NodeValues {
  double vn, vt, vt2, pn, ln, lt, lt2, bound;
  int normal, tangential;
};
NodeValues nodeValues(int i, const double *ov, const double *Lam) {
  const int sn = N.normalSlot[i], st = N.tangentSlot[i], st2 = N.tangentSlot2[i], k = N.rowsPerNode;
  NodeValues s;
  s.vn = ov[k * i] + 0.;
  s.vt = ov[k * i + 1] + 0.;
  s.vt2 = k == 3 ? ov[k * i + 2] + 0. : 0.;
  s.pn = sn >= 0 ? Lam[sn] : 0.;
  s.lt = st >= 0 ? Lam[st] : 0.;
  s.lt2 = st2 >= 0 ? Lam[st2] : 0.;
  s.ln = (sn >= 0 ? s.pn - dampedResponse(L.P, s.vn) : 0.) + 0.;
  s.bound = frictionBound(L.P, s.vn);
  s.normal = normalStatus(s.vn, N.nodeG[i]);
  s.tangential = tangentialStatus(k == 3 ? std::hypot(s.vt, s.vt2) : s.vt, N.nodeG[i]);
  return s;
}

long nodal(KN<double> *const &pv, KN<double> *const &pLam, KNM<double> *const &ptable) {
  requireNodes("contactKernelNodal");
  requireFactor("contactKernelNodal");
  KN<double> &v = *pv, &Lam = *pLam;
  if (v.N() != F.n || Lam.N() != F.nc) ExecError("contactKernelNodal: wrong argument sizes");
  std::vector<double> vv = copyOf(v), lam = copyOf(Lam), cv, ov;
  slotVelocities(vv.data(), cv);
  nodeVelocities(vv.data(), cv, ov);
  KNM<double> &table = *ptable;
  const int nn = N.nodeX.size();
  table.resize(nn, 14);
  for (int i = 0; i < nn; i++) {
    const NodeValues s = nodeValues(i, ov.data(), lam.data());
    // the force scale p(g) of the node (Slots::setBound), also where it has no slot at all
    const double pg = dampedResponse(L.P, N.nodeG[i]), scale = pg > 0 ? pg : 1.;
    const double row[14] = {s.vn, s.vt, s.pn, s.ln, s.lt, (double)s.normal, (double)s.tangential, s.bound,
                            scale, (double)zone(s.normal, s.tangential), s.vt2, s.lt2, dampedResponse(L.P, s.vn), N.nodeG[i]};
    for (int k = 0; k < 14; k++) table(i, k) = row[k];
  }
  return 0;
}

// Append the rows of step n of contact_nodes_history.txt (edp/lib/series.idp) to path: one per
// node, "step t node x y" then the nodal table's columns 0..6 and its zone, 17 digits, as
// FreeFEM's own streams would write them (compiled, through one stream kept open until
// contactKernelCloseNodes: written from the interpreter, or reopened at every step, the rows
// cost as much as the step). 1 if the file cannot be written.
std::ofstream nodesStream;
std::string nodesPath;
long closeNodes() {
  if (!nodesStream.is_open()) return 0;
  nodesStream.flush();
  const bool ok = (bool)nodesStream;
  nodesStream.close();
  nodesPath.clear();
  return ok && !nodesStream.fail() ? 0 : 1;
}
long appendNodes(string *const &path, const long &n, const double &t, KN<double> *const &px, KN<double> *const &py,
                 KN<double> *const &pz, KNM<double> *const &ptable) {
  KN<double> &x = *px, &y = *py, &z = *pz;
  KNM<double> &table = *ptable;
  if (x.N() != y.N() || table.N() != x.N() || table.M() < 14) ExecError("contactKernelAppendNodes: wrong argument sizes");
  const bool three = N.rowsPerNode == 3;               // 3D: z after y, v_tau2 and lambda_tau2 after the zone
  if (three && z.N() != x.N()) ExecError("contactKernelAppendNodes: wrong argument sizes");
  if (nodesPath != *path) {
    if (closeNodes()) return 1;
    nodesStream.open(*path, std::ios::app);
    nodesStream.precision(17);
    nodesPath = *path;
  }
  std::ofstream &f = nodesStream;
  for (int i = 0; i < (int)x.N(); i++) {
    f << n << " " << t << " " << i << " " << x[i] << " " << y[i];
    if (three) f << " " << z[i];
    for (int k = 0; k < 7; k++) f << " " << table(i, k);
    f << " " << std::lround(table(i, 9));
    if (three) f << " " << table(i, 10) << " " << table(i, 11);
    f << " " << table(i, 13) << " " << table(i, 7) << " " << table(i, 12) << " " << table(i, 8);   // g, the bound, p(v_nu), p(g)
    f << "\n";
  }
  return f ? 0 : 1;
}

struct HistoryArrays { KN<double> *info = nullptr, *history = nullptr, *contactHistory = nullptr; };
HistoryArrays HA;

struct Record {
  std::vector<double> vOld, Mv, Av, Bv;  // v_{n-1}; workspace
  double energyOld = 0;                  // kinetic + elastic of the previous step
  long generation = -1;                  // the factor (F.generation) the record started with
  long step = 0;                         // the steps recorded into the history arrays
};
Record RC;

long recordStart(KN<double> *const &pv0, KN<double> *const &pu0, KN<double> *const &pMv, KN<double> *const &pBu) {
  requireNodes("contactKernelRecordStart");
  requireFactor("contactKernelRecordStart");
  if (P3.n == 0) ExecError("contactKernelRecordStart: call contactKernelProducts first");
  KN<double> &v0 = *pv0, &u0 = *pu0, &Mv = *pMv, &Bu = *pBu;
  const int n = P3.n;
  if (v0.N() != n || u0.N() != n || F.n != n) ExecError("contactKernelRecordStart: wrong argument sizes");
  RC.vOld = copyOf(v0);
  RC.Mv.resize(n); RC.Av.resize(n); RC.Bv.resize(n);
  std::vector<double> u = copyOf(u0), Mu(n);
  Mv.resize(n); Bu.resize(n);
  P3.apply(RC.vOld.data(), RC.Mv.data(), RC.Av.data(), RC.Bv.data());
  double kinetic = 0;
  for (int i = 0; i < n; i++) { Mv[i] = RC.Mv[i]; kinetic += 0.5 * RC.vOld[i] * RC.Mv[i]; }
  P3.apply(u.data(), Mu.data(), RC.Av.data(), RC.Bv.data());
  double elastic = 0;
  for (int i = 0; i < n; i++) { Bu[i] = RC.Bv[i]; elastic += 0.5 * u[i] * RC.Bv[i]; }
  RC.energyOld = kinetic + elastic;
  RC.generation = F.generation;
  RC.step = 0;
  HA = HistoryArrays();                  // a new record writes no rows until contactKernelHistory
  return 0;
}

// In: v = v_n, u = u_n, Lam (total contact stress per slot), f = f_n (the load of the step),
// Mv = M v_{n-1}, Bu = B u_{n-1}. Out: Mv = M v_n and Bu = B u_n (for the next right-hand
// side) and record = [kinetic, elastic, numerical_dissipation, viscous_dissipation,
// contact_dissipation, external_work, energy_residual, kinetic_jump, elastic_jump,
// normal_force, tangential_force, the five zone counts, x_B, x_C, tangential_force2] (the columns
// of history.txt and contact_history.txt; 1e300 for an x_B or x_C that does not exist; the
// tangential forces sum W lambda_tau and W lambda_tau2 in 2D (the second 0), and in 3D are the
// vector sum of W (lambda_tau t1 + lambda_tau2 t2) on Gamma3's mean frame T1, T2). The discrete energy
// balance (docs/design.md, section "Energy identity"), test function w = v_n:
//   E_n - E_{n-1} + 1/2 m(v_n - v_{n-1}) + k^2/2 b(v_n) + k a(v_n) + k (C'W Lam)'v_n = k f_n'v_n
void writeHistoryRow(const KN<double> &rec);
long stepRecord(KN<double> *const &pv, KN<double> *const &pu, KN<double> *const &pLam, KN<double> *const &pf,
                KN<double> *const &pMv, KN<double> *const &pBu, KN<double> *const &prec) {
  if (RC.generation != F.generation || !F.L) ExecError("contactKernelRecord: call contactKernelRecordStart (after the last contactKernelFactorize) first");
  KN<double> &v = *pv, &u = *pu, &Lam = *pLam, &f = *pf, &Mv = *pMv, &Bu = *pBu, &rec = *prec;
  const int n = P3.n;
  if (v.N() != n || u.N() != n || f.N() != n || Mv.N() != n || Bu.N() != n || Lam.N() != F.nc)
    ExecError("contactKernelRecord: wrong argument sizes");
  const double k = SP.dt;
  // three products in one pass; M (v_n - v_{n-1}) = M v_n - M v_{n-1} and B u_n = B u_{n-1} + k B v_n
  // (u_n = u_{n-1} + k v_n), so no product with v_{n-1} or u
  const char *strided = "contactKernelRecord: arrays must be contiguous";
  const double *pv0 = contiguous(v, strided), *pu0 = contiguous(u, strided), *pf0 = contiguous(f, strided);
  double *pMv0 = contiguous(Mv, strided), *pBu0 = contiguous(Bu, strided);
  // Mv and Bu are overwritten row by row while v and u are still read
  if (pMv0 == pv0 || pMv0 == pu0 || pBu0 == pv0 || pBu0 == pu0 || pMv0 == pBu0)
    ExecError("contactKernelRecord: Mv and Bu must be arrays of their own, not v or u");
  double *vOld = RC.vOld.data();
  double vMv = 0, vAv = 0, vBv = 0, dvMdv = 0, uBu = 0, fv = 0;
  P3.forEachRow(pv0, [&](int i, double m, double a, double b) {   // each row once its products are known
    const double vi = pv0[i], bu = pBu0[i] + k * b;
    vMv += vi * m; vAv += vi * a; vBv += vi * b; dvMdv += (vi - vOld[i]) * (m - pMv0[i]);
    uBu += pu0[i] * bu;
    fv += pf0[i] * vi;
    pMv0[i] = m; pBu0[i] = bu; vOld[i] = vi;
  });
  std::vector<double> cv;
  slotVelocities(pv0, cv);
  double contact = 0;
  for (int j = 0; j < F.nc; j++) contact += N.weight[j] * Lam[j] * cv[j];
  if (rec.N() != 19) rec.resize(19);
  const double kinetic = 0.5 * vMv, elastic = 0.5 * uBu, kineticJump = 0.5 * dvMdv, elasticJump = 0.5 * k * k * vBv;
  const double viscous = k * vAv, contactWork = k * contact, external = k * fv;
  const double numerical = kineticJump + elasticJump;
  const double balance = kinetic + elastic - RC.energyOld + numerical + viscous + contactWork - external;
  const double largest = std::max({std::fabs(kinetic), std::fabs(elastic), std::fabs(RC.energyOld), numerical,
                                   viscous, std::fabs(contactWork), std::fabs(external)});
  RC.energyOld = kinetic + elastic;
  rec[0] = kinetic; rec[1] = elastic; rec[2] = numerical; rec[3] = viscous; rec[4] = contactWork;
  rec[5] = external; rec[6] = largest > 0 ? std::fabs(balance) / largest : 0.; rec[7] = kineticJump;
  rec[8] = elasticJump;
  std::vector<double> lam = copyOf(Lam), ov;
  nodeVelocities(pv0, cv, ov);
  double normalForce = 0, tangentialForce = 0, tangentialForce2 = 0, xB = 1e300, xC = 1e300;
  long zones[5] = {0, 0, 0, 0, 0};
  for (size_t i = 0; i < N.nodeX.size(); i++) {
    const NodeValues s = nodeValues(i, ov.data(), lam.data());
    zones[zone(s.normal, s.tangential)]++;
    if (s.normal == 2) xB = std::min(xB, N.nodeX[i]);
    if (s.normal > 0 && s.tangential == 0) xC = std::min(xC, N.nodeX[i]);
    normalForce += N.nodeW[i] * s.pn;
    if (N.frame.empty()) {                         // 2D: along each node's tangent
      tangentialForce += N.nodeW[i] * s.lt;
      tangentialForce2 += N.nodeW[i] * s.lt2;
    }
    else {                                         // 3D: the vector on Gamma3's mean frame
      const double *f = N.frame.data() + 9 * i;
      for (int k = 0; k < 3; k++) {
        const double component = N.nodeW[i] * (s.lt * f[3 + k] + s.lt2 * f[6 + k]);
        tangentialForce += component * N.meanT1[k];
        tangentialForce2 += component * N.meanT2[k];
      }
    }
  }
  rec[9] = normalForce; rec[10] = tangentialForce;
  for (int z = 0; z < 5; z++) rec[11 + z] = zones[z];
  rec[16] = xB; rec[17] = xC; rec[18] = tangentialForce2;
  writeHistoryRow(rec);
  return std::isfinite(balance) ? 0 : 1;
}

// The history arrays the record writes into (contactKernelHistory): row n of history
// (12 columns: t, iterations, residual, then the record's 0..8) and of contactHistory (10: t,
// then the record's 9..17; 11 in 3D, with the record's 18) at the n-th contactKernelRecord since contactKernelRecordStart
// (t = n k), the iterations and residual from info (the solvers' [residual, iterations, ...]).
// Arrays of the script, kept by address: sized before, not resized while the record runs.
// One call a step instead of a line per column (each line costs the interpreter about 1 us).
// contactKernelRecordStart forgets them (HA, declared with the Record).
long historyArrays(KN<double> *const &pinfo, KN<double> *const &phistory, KN<double> *const &pcontactHistory) {
  HA.info = pinfo; HA.history = phistory; HA.contactHistory = pcontactHistory;
  return 0;
}

void writeHistoryRow(const KN<double> &rec) {
  if (!HA.history) return;
  KN<double> &info = *HA.info, &history = *HA.history, &contactHistory = *HA.contactHistory;
  const long n = ++RC.step, columns = N.rowsPerNode == 3 ? 11 : 10;
  if (info.N() < 2 || history.N() < 12 * n || contactHistory.N() < columns * n)
    ExecError("contactKernelRecord: the history arrays hold fewer rows than the steps recorded");
  const double t = n * SP.dt;
  const long h = 12 * (n - 1), c = columns * (n - 1);
  history[h] = t; history[h + 1] = info[1]; history[h + 2] = info[0];
  for (int k = 0; k < 9; k++) history[h + 3 + k] = rec[k];
  contactHistory[c] = t;
  for (int k = 0; k < columns - 1; k++) contactHistory[c + 1 + k] = rec[9 + k];
}

// ---------------------------------------------------------------- Newton
// The Newton matrix N (nc x nc) of the relations sum_t a_jt c[aSlot_jt] + d_jt m[dSlot_jt] = h_j
// (contactlaw.hpp; one term of each in 2D) with c = cFree - Dw m: row j = sum_t -a_jt Dw(aSlot_jt, :)
// + d_jt e_dSlot_jt'. A base matrix N0 (its relations baseA, baseD, baseS, baseT) is LU-factorized; a matrix whose relations differ from N0's in a few
// rows R only is solved with N0's factors and a rank-|R| (Woodbury) correction:
//   N = N0 + E_R Delta,  N^-1 b = x0 - Y K^-1 Delta x0,  x0 = N0^-1 b,  Y = N0^-1 E_R,  K = I + Delta Y,
// Y read from N0^-1 (computed from the factors when a first correction needs it) and K
// assembled from the changed rows' terms (newtonPrepare). N0 is factorized again when more than
// nc/3 rows changed for another reason than a 3D slip, or when a corrected solve fails its
// residual check (newtonSolve).
struct Term { int index; double coef; };
struct Newton {
  std::vector<double> N0, N0inv, K;
  std::vector<int> derive, hOf;        // the rows of H0 = Dw N0^-1 (newtonDerivableRows)
  std::vector<double> deriveA0;        // the velocity term of the base row each is derived from
  std::vector<double> H;               // its computed rows, one after the other
  int hCount = 0;
  std::vector<double> bRef, xRef;      // the last right-hand side solved with N0's factors (baseSolve)
  bool haveRef = false;
  std::vector<std::vector<Term>> onInv, onUnit, onH;   // the changed rows of N as terms (newtonPrepare)
  bool inverted = false;
  std::vector<double> Dx;              // Dw x for the last x newtonSolve checked (haveDx)
  bool haveDx = false;
  std::vector<int> pivots, Kpivots, changed, baseS, baseT, preparedS, preparedT;
  std::vector<double> baseA, baseD, preparedA, preparedD;
  bool haveBase = false;
  long factorizations = 0, corrections = 0, refinements = 0;
  long fallbacks = 0;                  // iterates the safeguard replaced by a fixed-point iteration
  long cuts = 0;                       // ... by a shortened Newton step
  long halvings = 0;                   // of r by the cycle guard
  long retries = 0;                    // steps a disk's Newton solved again without its safeguards
  std::vector<double> seen;            // the cycle guard's fingerprints of the step's iterations
  std::vector<double> rDefault;        // r_j at the start of a step
  long generation = -1;                // the factor the base matrix belongs to
};
Newton Q;

// c = cFree - Dw m
void velocities(const double *cFree, const double *m, double *c) {
  const int nc = F.nc, inc = 1;
  const double minusOne = -1., one = 1.;
  std::copy(cFree, cFree + nc, c);
  dgemv_("N", &nc, &nc, &minusOne, F.Dw.data(), &nc, m, &inc, &one, c, &inc);
}

// ---------------------------------------------------------------- the fixed point
// Projected Gauss-Seidel over the slots (nonsmooth Gauss-Seidel): each slot in turn solves its
// own law exactly, with the other slots' multipliers held. With c = cFree - Dw m, a change of
// m_j moves c_j by -Dw_jj times it, so y = Lambda_j + rho_j c_j with rho_j = 1/Dw_jj - Kn_j
// equals m_j + c_j/Dw_jj whatever m_j is: the law's piece at y (Slots::resolve, with the local
// augmentation rho_j) gives the slot's new stress and velocity at once. A tangential slot reads
// its normal partner's current velocity for its bound. No parameter to tune: rho_j is exact.
// The map G of one iteration is a forward sweep then a backward one (symmetric Gauss-Seidel);
// contactKernelFixedPoint accelerates it (Anderson), and Newton falls back on it.
struct FixedPoint {
  std::vector<double> rho;              // the local augmentations 1/Dw_jj - Kn_j
  long generation = -1;                 // the Delassus matrix they belong to
  // the variants measured in docs/stability.md, "Fixed point", set these two and rebuild
  const double omega = 1;               // relaxation of each slot's update
  const int window = 10;                // Anderson acceleration's window (0: none)
  long sweeps = 0;                      // over the run
};
FixedPoint FP;

void fixedPointPrepare() {
  if (FP.generation == F.delassusGeneration) return;
  const int nc = F.nc;
  FP.rho.assign(nc, 0.);
  for (int j = 0; j < nc; j++) {
    const double djj = F.Dw[j + (size_t)j * nc];
    // Dw_jj Kn_j < 1 (S holds W Kn C'C): the floor only guards round-off
    FP.rho[j] = std::max(1. / djj - L.Kn[j], 1e-3 / djj);
  }
  FP.generation = F.delassusGeneration;
}

// A 3D node's tangential pair (j, q) in one update: with the pair's block D of Dw and the
// others held, c_tau = b - D m_tau (b = c_tau + D m_tau now), and the disk law asks for
// b - D m in the normal cone of the disk |m| <= s at m: the minimum of m'Dm/2 - b'm on the
// disk. Inside (|D^-1 b| <= s): stick, m = D^-1 b. Else m = (D + nu I)^-1 b with nu > 0 such
// that |m| = s (Newton on 1/|m(nu)| - 1/s, kept in its bracket by bisection). Exact, as the
// scalar slots' update.
void fixedPointDisk(int j, int q, double *c, double *m) {
  const int nc = F.nc, inc = 1;
  const double Djj = F.Dw[j + (size_t)j * nc], Djq = F.Dw[j + (size_t)q * nc];
  const double Dqj = F.Dw[q + (size_t)j * nc], Dqq = F.Dw[q + (size_t)q * nc];
  const double bj = c[j] + Djj * m[j] + Djq * m[q], bq = c[q] + Dqj * m[j] + Dqq * m[q];
  const int p = L.partner[j];
  const double s = p >= 0 ? frictionBound(L.P, c[p]) : 0.;
  double mj = 0, mq = 0;
  auto solveShifted = [&](double nu, double &xj, double &xq) {   // (D + nu I) x = b
    const double a11 = Djj + nu, a22 = Dqq + nu, det = a11 * a22 - Djq * Dqj;
    xj = (a22 * bj - Djq * bq) / det; xq = (a11 * bq - Dqj * bj) / det;
  };
  if (s > 0) {
    solveShifted(0., mj, mq);
    const double bLength = std::hypot(bj, bq);
    if (std::hypot(mj, mq) > s) {
      double lo = 0, hi = bLength / s, nu = 0;
      for (int k = 0; k < 100; k++) {
        double xj, xq;
        solveShifted(nu, xj, xq);
        const double length = std::hypot(xj, xq), psi = 1 / length - 1 / s;
        if (psi < 0) lo = nu; else hi = nu;
        // psi'(nu) = x'(D + nu I)^-1 x / |x|^3
        double yj, yq;
        { const double a11 = Djj + nu, a22 = Dqq + nu, det = a11 * a22 - Djq * Dqj;
          yj = (a22 * xj - Djq * xq) / det; yq = (a11 * xq - Dqj * xj) / det; }
        const double slope = (xj * yj + xq * yq) / (length * length * length);
        double next = nu - psi / slope;
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::fabs(psi) * s <= 1e-15 || hi - lo <= 1e-15 * hi) { mj = xj; mq = xq; break; }
        nu = next;
        mj = xj; mq = xq;
      }
      const double length = std::hypot(mj, mq);   // on the circle exactly
      if (length > 0) { mj *= s / length; mq *= s / length; }
    }
  }
  const double deltaJ = FP.omega * (mj - m[j]), deltaQ = FP.omega * (mq - m[q]);
  m[j] += deltaJ; m[q] += deltaQ;
  const double minusJ = -deltaJ, minusQ = -deltaQ;
  if (deltaJ != 0) daxpy_(&nc, &minusJ, F.Dw.data() + (size_t)j * nc, &inc, c, &inc);
  if (deltaQ != 0) daxpy_(&nc, &minusQ, F.Dw.data() + (size_t)q * nc, &inc, c, &inc);
}

// one sweep over the slots, forward or backward; c = cFree - Dw m follows m
void fixedPointSweep(bool forward, double *c, double *m) {
  const int nc = F.nc, inc = 1;
  for (int k = 0; k < nc; k++) {
    const int j = forward ? k : nc - 1 - k;
    const int q = L.pair[j];
    if (q >= 0) {                                    // a 3D pair, at the first of its two slots
      if (forward ? q > j : q < j) fixedPointDisk(j, q, c, m);
      continue;
    }
    const double *column = F.Dw.data() + (size_t)j * nc;
    const double y = m[j] + c[j] / column[j];
    double t = 0, v = 0;
    L.resolve(j, y, FP.rho[j], c, t, v);
    const double cj = (y - t) / FP.rho[j];
    const double delta = FP.omega * (t - L.Kn[j] * cj - m[j]);
    if (delta == 0) continue;
    m[j] += delta;
    const double minus = -delta;
    daxpy_(&nc, &minus, column, &inc, c, &inc);
  }
  FP.sweeps++;
}

// One iteration of the map G from m (c is recomputed from m): the forward and backward sweeps;
// returns the natural residual at the new (c, m) and sets its merit (referenceEvaluate).
double referenceEvaluate(const double *c, const double *m, double &merit);
double fixedPointIteration(const double *cFree, double *c, double *m, double &merit) {
  fixedPointPrepare();
  velocities(cFree, m, c);
  fixedPointSweep(true, c, m);
  fixedPointSweep(false, c, m);
  velocities(cFree, m, c);
  return referenceEvaluate(c, m, merit);
}


// The LU factors of N0, the base Newton matrix (Q.N0: the relations when it was factorized, a
// 3D disk's slip rows as stick rows), and its inverse (Q.N0inv) computed from them: a solve
// uses the factors (backward stable: the inverse alone loses digits on the badly conditioned
// matrices of a literal penalty), a correction reads the columns N0^-1 E_R from the inverse
// instead of solving for them (newtonPrepare)
const int T = Slots::termsPerRelation;
// row j of the Newton matrix of the relations (a, aSlot, d, dSlot), its terms from first on,
// times sign, added into out[i * ld], i < nc (term 0 always; the others where nonzero)
void addNewtonRow(int j, const std::vector<double> &a, const std::vector<int> &aSlot, const std::vector<double> &d,
                  const std::vector<int> &dSlot, double sign, double *out, size_t ld, int first = 0) {
  const int nc = F.nc;
  for (int t = first; t < T; t++) {
    const double at = a[T * j + t];
    if (t > 0 && at == 0) continue;
    const double *row = F.Dw.data() + aSlot[T * j + t];
    for (int i = 0; i < nc; i++) out[i * ld] += sign * (-at * row[(size_t)i * nc]);
  }
  for (int t = first; t < T; t++) if (t == 0 || d[T * j + t] != 0) out[dSlot[T * j + t] * ld] += sign * d[T * j + t];
}
void newtonDerivableRows();
// does relation j read a velocity (else it fixes stresses only: a frictionless slip)
bool hasVelocityTerm(int j) {
  for (int t = 0; t < T; t++) if (L.a[T * j + t] != 0) return true;
  return false;
}
// is relation j a 3D disk's slip (its coefficients follow the slip direction at every iteration)
bool diskSlip(int j) { return L.pair[j] >= 0 && L.piece[j] == Slip; }
// ... that reads a velocity: the base writes it as a stick row (newtonFactorBase)
bool substitutedInBase(int j) { return diskSlip(j) && hasVelocityTerm(j); }
bool newtonFactorBase(bool substitute = true);
bool newtonFactorBase(bool substitute) {
  const int nc = F.nc;
  // the base: the current relations, but a 3D disk's slip rows as stick rows (c_tau = 0), whose
  // rows of H0 are -e'_j (newtonDerivableRows): those rows change at every iteration anyway, and
  // the corrections then read no computed row of H0 for them
  Q.baseA = L.a; Q.baseD = L.d; Q.baseS = L.aSlot; Q.baseT = L.dSlot;
  for (int j = 0; j < nc; j++)
    if (substitute && substitutedInBase(j)) {
      for (int t = 0; t < T; t++) { Q.baseA[T * j + t] = 0; Q.baseD[T * j + t] = 0; Q.baseS[T * j + t] = j; Q.baseT[T * j + t] = j; }
      Q.baseA[T * j] = 1;
    }
  Q.N0.assign((size_t)nc * nc, 0.);
  for (int jj = 0; jj < nc; jj++)
    for (int j = 0; j < nc; j++) Q.N0[j + (size_t)jj * nc] = -Q.baseA[T * j] * F.Dw[Q.baseS[T * j] + (size_t)jj * nc];
  for (int j = 0; j < nc; j++) Q.N0[j + (size_t)Q.baseT[T * j] * nc] += Q.baseD[T * j];
  for (int j = 0; j < nc; j++)                       // the further terms (a 3D disk's Slip)
    addNewtonRow(j, Q.baseA, Q.baseS, Q.baseD, Q.baseT, 1., Q.N0.data() + j, nc, 1);
  Q.pivots.resize(nc);
  int info = 0;
  dgetrf_(&nc, &nc, Q.N0.data(), &nc, Q.pivots.data(), &info);
  Q.inverted = false;
  Q.haveRef = false;
  Q.factorizations++;
  Q.haveBase = info == 0;
  Q.generation = F.generation;
  Q.changed.clear();
  newtonDerivableRows();
  Q.preparedS.assign(T * nc, -1);                    // the current relations are prepared by newtonPrepare
  return Q.haveBase;
}

// N0^-1 from the factors, the first time a correction needs it
bool newtonInverse() {
  if (Q.inverted) return true;
  const int nc = F.nc;
  Q.N0inv = Q.N0;
  int info = 0, lwork = -1;
  double query = 0;
  dgetri_(&nc, Q.N0inv.data(), &nc, Q.pivots.data(), &query, &lwork, &info);
  lwork = std::max(nc, (int)query);
  std::vector<double> work(lwork);
  if (info == 0) dgetri_(&nc, Q.N0inv.data(), &nc, Q.pivots.data(), work.data(), &lwork, &info);
  Q.inverted = info == 0;
  return Q.inverted;
}

bool sameAsPrepared() {
  return Q.haveBase && Q.generation == F.generation && L.a == Q.preparedA && L.d == Q.preparedD && L.aSlot == Q.preparedS
         && L.dSlot == Q.preparedT;
}

// The rows of H0 = Dw N0^-1 that the corrections read (newtonPrepare). Row s is known from a
// row b of N0 whose one velocity term a0 sits at slot s: N0[b,:] = sum d0 e'_dSlot0 - a0 Dw[s,:]
// and N0[b,:] N0^-1 = e'_b give H0[s,:] = (sum d0 N0^-1[dSlot0,:] - e'_b) / a0 (Q.derive[s] = b:
// a stick, a bound, a free slot). The others (the slots of a 3D disk's slip, the normal slot of
// a damped node under a linear p, whose relation has no velocity term) are computed, Dw[s,:] N0^-1,
// the first time a correction reads them, and kept with the base (Q.H, row Q.hOf[s]).
void newtonDerivableRows() {
  const int nc = F.nc;
  Q.derive.assign(nc, -1);
  Q.deriveA0.assign(nc, 0.);
  Q.hOf.assign(nc, -1);
  Q.H.clear();
  Q.hCount = 0;
  for (int b = 0; b < nc; b++) {
    int count = 0, s = -1;
    double a0 = 0, dSum = 0;
    for (int t = 0; t < T; t++) {
      if (Q.baseA[T * b + t] != 0) { count++; s = Q.baseS[T * b + t]; a0 = Q.baseA[T * b + t]; }
      dSum += std::fabs(Q.baseD[T * b + t]);
    }
    // a velocity term too small against the stress terms would lose digits in the division
    if (count == 1 && std::fabs(a0) * F.Dw[s + (size_t)s * nc] >= 1e-3 * dSum && (Q.derive[s] < 0 || b == s)) {
      Q.derive[s] = b;
      Q.deriveA0[s] = a0;
    }
  }
}
void computeH0Rows(const std::vector<int> &slots) {
  const int nc = F.nc, k = slots.size();
  if (k == 0) return;
  // Dw[slots, :], k x nc, column-major, from Dw's columns: Dw = D W with D symmetric, so
  // Dw[s, i] = Dw[i, s] w_i / w_s
  std::vector<double> W((size_t)k * nc);
  for (int i = 0; i < k; i++) {
    const double *column = F.Dw.data() + (size_t)slots[i] * nc;
    const double ws = N.weight[slots[i]];
    for (int col = 0; col < nc; col++) W[i + (size_t)col * k] = column[col] * N.weight[col] / ws;
  }
  Q.H.resize((size_t)(Q.hCount + k) * nc);
  const double one = 1., zero = 0.;                    // the rows one after the other: (W N0^-1)' = N0^-T W'
  dgemm_("T", "T", &nc, &k, &nc, &one, Q.N0inv.data(), &nc, W.data(), &k, &zero, Q.H.data() + (size_t)Q.hCount * nc, &nc);
  for (int i = 0; i < k; i++) Q.hOf[slots[i]] = Q.hCount + i;
  Q.hCount += k;
}

// N0 = N, the Newton matrix of the current relations, factorized (no correction): where a
// correction cannot be made or is not accurate enough
bool newtonExactBase() {
  if (!newtonFactorBase(false)) return false;
  Q.preparedA = L.a; Q.preparedD = L.d; Q.preparedS = L.aSlot; Q.preparedT = L.dSlot;
  return true;
}

// Prepare the solves with the Newton matrix N of the current relations. N0 (factorized, its
// inverse at hand) differs from N in the rows R; with Y = N0^-1 E_R, the columns R of the
// inverse, N^-1 = N0^-1 - Y K^-1 (N - N0)_R N0^-1 (Woodbury), where K = I + (N - N0)_R Y is
// (N N0^-1)[R, R]: the rows R of N, sum d e'_dSlot - sum a Dw[aSlot,:], times the columns R of
// N0^-1. So K reads N0^-1 at the d-slots of those rows and H0 = Dw N0^-1 at their a-slots
// (newtonDerivableRows): about 6 r^2 multiply-adds and an r x r LU, whatever rows changed (a
// disk's slip rows change at every iteration). A new base when more than nc/3 rows changed for
// another reason than a 3D slip.
bool newtonPrepare() {
  const int nc = F.nc;
  if ((!Q.haveBase || Q.generation != F.generation) && !newtonFactorBase()) return false;
  std::vector<int> R;
  int stale = 0;                                     // changed rows other than the base's substituted ones
  auto changedRows = [&]() {
    R.clear(); stale = 0;
    for (int j = 0; j < nc; j++)
      for (int t = 0; t < T; t++) {
        const int e = T * j + t;
        if (L.a[e] != Q.baseA[e] || L.d[e] != Q.baseD[e] || L.aSlot[e] != Q.baseS[e] || L.dSlot[e] != Q.baseT[e]) {
          R.push_back(j);
          if (!substitutedInBase(j)) stale++;
          break;
        }
      }
  };
  changedRows();
  // a new base when a third of the rows changed for another reason than a 3D slip
  if (stale > nc / 3) {
    if (!newtonFactorBase()) return false;
    changedRows();
  }
  const int r = R.size();
  Q.changed = R;
  Q.preparedA = L.a; Q.preparedD = L.d; Q.preparedS = L.aSlot; Q.preparedT = L.dSlot;
  if (r == 0) return true;
  if (!newtonInverse()) return newtonExactBase();
  // each changed row as terms on rows of N0^-1 (onInv), on e'_b (onUnit) and on computed rows of H0 (onH)
  std::vector<int> missing;
  std::vector<char> listed(nc, 0);
  for (int k = 0; k < r; k++)
    for (int t = 0; t < T; t++) {
      const int s = L.aSlot[T * R[k] + t];
      if (L.a[T * R[k] + t] != 0 && Q.hOf[s] < 0 && Q.derive[s] < 0 && !listed[s]) { missing.push_back(s); listed[s] = 1; }
    }
  computeH0Rows(missing);
  Q.onInv.assign(r, {}); Q.onUnit.assign(r, {}); Q.onH.assign(r, {});
  for (int k = 0; k < r; k++) {
    const int j = R[k];
    for (int t = 0; t < T; t++) if (t == 0 || L.d[T * j + t] != 0) Q.onInv[k].push_back({L.dSlot[T * j + t], L.d[T * j + t]});
    for (int t = 0; t < T; t++) {
      const double a = L.a[T * j + t];
      const int s = L.aSlot[T * j + t];
      if (a == 0) continue;
      if (Q.hOf[s] >= 0) { Q.onH[k].push_back({Q.hOf[s], -a}); continue; }
      const int b = Q.derive[s];
      const double a0 = Q.deriveA0[s];
      for (int u = 0; u < T; u++)
        if (Q.baseD[T * b + u] != 0) Q.onInv[k].push_back({Q.baseT[T * b + u], -a * Q.baseD[T * b + u] / a0});
      Q.onUnit[k].push_back({b, a / a0});
    }
  }
  // K = (N N0^-1)[R, R]: the terms on N0^-1 column by column, then those on H0 row by row
  Q.K.assign((size_t)r * r, 0.);
  std::vector<int> position(nc, -1);
  for (int l = 0; l < r; l++) position[R[l]] = l;
  for (int l = 0; l < r; l++) {
    const double *column = Q.N0inv.data() + (size_t)R[l] * nc;
    double *out = Q.K.data() + (size_t)l * r;
    for (int k = 0; k < r; k++) {
      double v = 0;
      for (const Term &e : Q.onInv[k]) v += e.coef * column[e.index];
      out[k] = v;
    }
  }
  for (int k = 0; k < r; k++) {
    for (const Term &e : Q.onUnit[k]) if (position[e.index] >= 0) Q.K[k + (size_t)position[e.index] * r] += e.coef;
    for (const Term &e : Q.onH[k]) {
      const double *row = Q.H.data() + (size_t)e.index * nc;
      for (int l = 0; l < r; l++) Q.K[k + (size_t)l * r] += e.coef * row[R[l]];
    }
  }
  Q.Kpivots.resize(r);
  int info = 0;
  dgetrf_(&r, &r, Q.K.data(), &r, Q.Kpivots.data(), &info);
  if (info != 0) return newtonExactBase();
  Q.corrections++;
  return true;
}

// x0 = N0^-1 b with N0's factors; or, where b differs from the last right-hand side solved with
// them (bRef, when remember) in at most nc/8 entries, xRef plus those columns of the inverse: within a
// step only the rows whose relations changed change their right-hand side
void baseSolve(const double *b, double *x, bool remember) {
  const int nc = F.nc, one = 1, inc = 1;
  if (remember && Q.inverted && Q.haveRef) {
    std::vector<int> S;
    for (int i = 0; i < nc && (int)S.size() <= nc / 8; i++) if (b[i] != Q.bRef[i]) S.push_back(i);
    if ((int)S.size() <= nc / 8) {
      std::copy(Q.xRef.begin(), Q.xRef.end(), x);
      for (int i : S) {
        const double delta = b[i] - Q.bRef[i];
        daxpy_(&nc, &delta, Q.N0inv.data() + (size_t)i * nc, &inc, x, &inc);
      }
      return;
    }
  }
  int info = 0;
  std::copy(b, b + nc, x);
  dgetrs_("N", &nc, &one, Q.N0.data(), &nc, Q.pivots.data(), x, &nc, &info);
  if (remember) { Q.bRef.assign(b, b + nc); Q.xRef.assign(x, x + nc); Q.haveRef = true; }
}
// x = N^-1 b (x and b distinct) with N0's factors and the correction: x0 = N0^-1 b (baseSolve),
// then x = x0 - Y K^-1 (N x0 - b)_R, where (N x0)_R reads Dw x0 = H0 b at the a-slots as K reads
// H0 (a derived row: (sum d0 x0[dSlot0] - b_b)/a0); newtonSolve checks it
void correctedSolve(const double *b, double *x, bool remember = false) {
  const int nc = F.nc, one = 1, r = Q.changed.size();
  int info = 0;
  baseSolve(b, x, remember);
  if (r == 0) return;
  std::vector<double> t(r, 0.), hb(Q.hCount, 0.);     // hb = H0 b on the computed rows
  if (Q.hCount > 0) {
    const double plus = 1., zero = 0.;
    const int inc = 1;
    dgemv_("T", &nc, &Q.hCount, &plus, Q.H.data(), &nc, b, &inc, &zero, hb.data(), &inc);
  }
  for (int k = 0; k < r; k++) {
    double v = -b[Q.changed[k]];
    for (const Term &e : Q.onInv[k]) v += e.coef * x[e.index];
    for (const Term &e : Q.onUnit[k]) v += e.coef * b[e.index];
    for (const Term &e : Q.onH[k]) v += e.coef * hb[e.index];
    t[k] = v;
  }
  dgetrs_("N", &r, &one, Q.K.data(), &r, Q.Kpivots.data(), t.data(), &r, &info);
  for (int l = 0; l < r; l++) {
    const double minus = -t[l];
    const int inc = 1;
    daxpy_(&nc, &minus, Q.N0inv.data() + (size_t)Q.changed[l] * nc, &inc, x, &inc);
  }
}
// the largest row residual of N x = b relative to the size of the row's terms, |b_j| + |its
// terms at x| + (sum |a_jt| max|Dw x| + sum |d_jt| max|x|) / 10: a row is read against its own
// terms, but not below a tenth of the scale of the others (a row whose terms all vanish at the
// solution, a free slot's m_j = 0, would read round-off as a relative error of 1); the
// residuals in res; Dw x in Q.Dx (the safeguard's velocities at x reuse it)
double rowResidual(const double *b, const double *x, double *res) {
  const int nc = F.nc, inc = 1;
  Q.Dx.assign(nc, 0.);
  std::vector<double> &Dx = Q.Dx;
  const double plus = 1., zero = 0.;
  dgemv_("N", &nc, &nc, &plus, F.Dw.data(), &nc, x, &inc, &zero, Dx.data(), &inc);
  Q.haveDx = true;
  double worst = 0, xMax = 0, DxMax = 0;
  for (int j = 0; j < nc; j++) { xMax = std::max(xMax, std::fabs(x[j])); DxMax = std::max(DxMax, std::fabs(Dx[j])); }
  for (int j = 0; j < nc; j++) {
    double a = -L.a[T * j] * Dx[L.aSlot[T * j]], d = L.d[T * j] * x[L.dSlot[T * j]];
    double aSize = std::fabs(L.a[T * j]), dSize = std::fabs(L.d[T * j]);
    for (int t = 1; t < T; t++) {                    // the further terms (a 3D disk's Slip)
      if (L.a[T * j + t] != 0) a -= L.a[T * j + t] * Dx[L.aSlot[T * j + t]];
      if (L.d[T * j + t] != 0) d += L.d[T * j + t] * x[L.dSlot[T * j + t]];
      aSize += std::fabs(L.a[T * j + t]); dSize += std::fabs(L.d[T * j + t]);
    }
    const double scale = std::fabs(b[j]) + std::fabs(a) + std::fabs(d) + 0.1 * (aSize * DxMax + dSize * xMax);
    res[j] = b[j] - a - d;
    const double relative = scale > 0 ? std::fabs(res[j]) / scale : (res[j] == 0 ? 0. : INFINITY);
    if (!(relative <= worst)) worst = relative;             // a NaN row stays the worst
  }
  return worst;
}
// A relation with no velocity term and one stress term (a free slot, a frictionless slip: m_j =
// h_j / d_j) holds exactly, as a solve with N's own factors gives it: the correction would leave
// round-off there (lambda_tau of 1e-17 where mu = 0)
void exactStressRows(const double *b, double *x) {
  for (int j = 0; j < F.nc; j++) {
    if (hasVelocityTerm(j)) continue;
    int terms = 0;
    for (int t = 0; t < T; t++) terms += t == 0 || L.d[T * j + t] != 0;
    if (terms == 1 && L.d[T * j] != 0) x[L.dSlot[T * j]] = b[j] / L.d[T * j];
  }
}
// x = N^-1 b to a hundredth of the tolerance: the row residual of the corrected solve
// (rowResidual) must be below max(1e-15, min(1e-6, tol / 100)). Once the pieces are right, a
// piecewise-linear law is then solved to tol in one iteration (finite termination: the paper
// scene takes 159 iterations at every tol from 1e-6 to 1e-12), and a steep damping table still
// converges (at tol / 10 it stalled at 8.5e-10); a fixed 1e-13, read row by row against each
// row's own terms, refined most solves of a 3D slab for nothing. Above the bound, one step of
// iterative refinement; still above max(1e-11, the bound), N0 = N is factorized.
bool newtonSolve(const double *b, double *x) {
  const int nc = F.nc;
  Q.haveDx = false;
  correctedSolve(b, x, true);
  if (Q.changed.empty()) return true;
  exactStressRows(b, x);
  const double bound = std::max(1e-15, std::min(1e-6, 0.01 * SP.tol));
  std::vector<double> res(nc), dx(nc);
  double worst = rowResidual(b, x, res.data());
  if (worst > bound) {
    correctedSolve(res.data(), dx.data());
    for (int j = 0; j < nc; j++) x[j] += dx[j];
    exactStressRows(b, x);
    Q.refinements++;
    worst = rowResidual(b, x, res.data());
  }
  if (!(worst <= std::max(1e-11, bound))) {
    if (!newtonExactBase()) return false;
    correctedSolve(b, x);
    Q.haveDx = false;
  }
  return true;
}

// The cycle guard (with -safeguard on): the relations of iteration it are fingerprinted (the
// pieces, and the coefficients for a nonlinear p; a 3D disk's slip by its piece alone, as its
// coefficients follow the slip direction at every iteration); when a fingerprint repeats within the step
// and r is above the operator's scale (-r > 1, after earlier halvings), r is halved on every
// slot for the rest of the step, and the law is evaluated again at (c, m) with the new r. The
// solution does not depend on r, only which pieces Newton tries next: at large r a slot's
// piece follows the sign of a small velocity, and the same wrong pieces come back. (At small
// r halving would only slow it further; there the fixed-point iterations of the safeguard
// below do the work.) The convergence test keeps reading the natural residual at the user's r
// (referenceEvaluate). The weights are fixed pseudo-random numbers in [1, 1009].
int guard(int it, const double *c, const double *m) {
  if ((int)Q.seen.size() < it + 1) Q.seen.resize(it + 1, -1.);
  if (it == 0) { std::fill(Q.seen.begin(), Q.seen.end(), -1.); Q.rDefault = L.r; }
  double fingerprint = 0;
  for (int j = 0; j < L.n; j++)
  {
    double term = L.key[j];
    if (!diskSlip(j)) {                              // a disk's slip row changes at every iteration: its piece only
      term += 0.6180339887 * L.a[T * j] + 0.4142135624 * L.d[T * j];
      for (int t = 1; t < T; t++) term += (0.6180339887 * L.a[T * j + t] + 0.4142135624 * L.d[T * j + t]) * (t + 1);
    }
    fingerprint += term * (1. + ((7919 * j + 104729) % 1009));
  }
  int halved = 0;
  // the scale of the current r against the operator's (r = 1): halving only down to it
  const double scale = L.n > 0 && Q.rDefault[0] > 0 ? SP.r * L.r[0] / Q.rDefault[0] : 0.;
  if (SP.safeguards && scale > 1)
    for (int k = 0; k < it; k++)
      if (Q.seen[k] == fingerprint) {
        for (int j = 0; j < L.n; j++) L.setAugmentation(j, 0.5 * L.r[j]);
        Q.halvings++;
        std::fill(Q.seen.begin(), Q.seen.end(), -1.);
        L.evaluate(c, m);
        halved = 1;
        break;
      }
  Q.seen[it] = fingerprint;
  return halved;
}
// What every solver's convergence test and Newton's safeguard read: the natural residual and
// its merit at the operator's scale r_j = 1/(Dw)_jj (the default -r 1), whatever -r and the
// guard's halvings. r only steers which pieces Newton tries next; measured at a large r the
// residual would weigh velocity mismatches r times more, at a small r stress mismatches, until
// round-off alone exceeds tol, and a merit that changes with r cannot compare iterates across
// a halving. Returns the residual, sets merit; the law's state is left at (c, m) and the
// current r (the pieces Newton linearizes next).
double referenceEvaluate(const double *c, const double *m, double &merit) {
  if (F.rReference.empty() || F.rReference == L.r) {
    const double residual = L.evaluate(c, m);
    merit = L.merit();
    return residual;
  }
  const std::vector<double> current = L.r;
  for (int j = 0; j < L.n; j++) L.setAugmentation(j, F.rReference[j]);
  const double reference = L.evaluate(c, m);
  merit = L.merit();
  for (int j = 0; j < L.n; j++) L.setAugmentation(j, current[j]);
  L.evaluate(c, m);
  return reference;
}
// r back to the user's after a step
void endStep() {
  if (!Q.rDefault.empty() && Q.rDefault != L.r) for (int j = 0; j < L.n; j++) L.setAugmentation(j, Q.rDefault[j]);
}

// A step has converged when its natural residual meets tol and no slot's status contradicts
// its piece (Slots::unresolvedStatuses, counted in unresolved; 0 while the residual is above tol).
bool stepConverged(double residual, const double *c, int &unresolved) {
  unresolved = residual <= SP.tol ? L.unresolvedStatuses(c) : 0;
  return residual <= SP.tol && unresolved == 0;
}

// The safeguard, shared by every Newton (compiled here, or the script view and the full-system
// Newton of edp/lib/solvers.idp), in safeguardStep: the Newton iterate is kept when it lowers
// the merit ||Phi||_2 of the weighted natural residual (Armijo, 1e-4) or meets tol. Otherwise
// two candidates from the previous iterate compete, and the one with the lower merit is taken:
// the Newton step shortened (1/2, 1/4, ... 1/1024, the first that passes the Armijo test), and
// one fixed-point iteration (fixedPointIteration). The fixed point does not depend on r, and
// wins where the line search would creep (small r); the line search wins where the fixed
// point is slow (fine meshes far from the solution). Near the solution the Newton iterates
// pass the test and convergence stays quadratic. (A line search alone, with r halved on a
// repeated active set, and the fixed-point iteration alone were tried first: docs/stability.md.)
bool accept(double merit, double trialMerit, double trialResidual, double step = 1) {
  return trialMerit < (1 - 1e-4 * step) * merit || trialResidual <= SP.tol;
}
enum SafeguardOutcome { NewtonKept = 0, NewtonShortened = 1, FixedPointTaken = 2 };
void logIteration(int it, double residual, int outcome = 0, double step = 1);
// From the previous iterate and the Newton iterate (multipliers; c = cFree - Dw m), set (c, m)
// to the iterate the safeguard keeps and the law's state to its evaluation; its natural
// residual and merit (referenceEvaluate) in residual and merit (on entry: the previous
// iterate's merit), the step length in step (0 for a fixed-point iteration).
int safeguardStep(const double *cFree, const double *previous, const double *newtonM, double &merit,
                  double *c, double *m, double &residual, double &step, const double *DwNewtonM = nullptr) {
  const int nc = F.nc;
  const double before = merit;
  std::copy(newtonM, newtonM + nc, m);
  if (DwNewtonM) for (int j = 0; j < nc; j++) c[j] = cFree[j] - DwNewtonM[j];   // Dw m known already
  else velocities(cFree, m, c);
  double trial = 0;
  residual = referenceEvaluate(c, m, trial);
  step = 1;
  if (!SP.safeguards || accept(before, trial, residual)) { merit = trial; return NewtonKept; }
  // the line search's candidate
  std::vector<double> mCut(nc);
  double cutMerit = INFINITY, cutStep = 0;
  for (double t = 0.5; t > 1. / 1500; t *= 0.5) {
    for (int j = 0; j < nc; j++) m[j] = previous[j] + t * (newtonM[j] - previous[j]);
    velocities(cFree, m, c);
    double tm = 0;
    const double tr = referenceEvaluate(c, m, tm);
    if (accept(before, tm, tr, t)) { cutMerit = tm; cutStep = t; mCut.assign(m, m + nc); break; }
  }
  // the fixed point's candidate
  std::copy(previous, previous + nc, m);
  residual = fixedPointIteration(cFree, c, m, merit);
  step = 0;
  if (!(cutMerit < merit)) { Q.fallbacks++; return FixedPointTaken; }
  std::copy(mCut.begin(), mCut.end(), m);
  velocities(cFree, m, c);
  residual = referenceEvaluate(c, m, merit);
  step = cutStep;
  Q.cuts++;
  return NewtonShortened;
}

// The start of a Newton step: the log's iteration 0 (the previous step's multipliers with this
// step's load, c = cFree - Dw m) and its merit, which the first iterate must lower; then the law
// is evaluated at (c, m), the previous step's solution, whose pieces the first Newton step
// linearizes. Returns the natural residual at (c, m).
double newtonStart(const double *cFree, const double *c, const double *m, double &merit) {
  std::vector<double> cStart(F.nc);
  velocities(cFree, m, cStart.data());
  logIteration(0, referenceEvaluate(cStart.data(), m, merit));
  double unused = 0;
  return referenceEvaluate(c, m, unused);
}

// -verbose: one line an iteration on the standard error, the residual and how many slots entered
// (+) or left (-) each piece of the law since the line before; iteration 0 gives the count of
// each piece at the start of the step (the previous step's multipliers with this step's load).
// Every solver calls it (the script ones through contactNewtonLog), after the law's evaluate()
// of the iterate; the first call says what the slots are.
std::vector<int> loggedPieces;
bool logExplained = false;
void logIteration(int it, double residual, int outcome, double step) {
  if (!SP.verbose) return;
  if (!logExplained) {
    int normal = 0;
    for (size_t j = 0; j < L.piece.size(); j++) normal += L.normal[j] != 0;
    std::fprintf(stderr, "Solver log: %d normal slots (pieces free, damped, bound) and %d tangential ones (stick, slip; "
                 "a node with a fixed velocity component has none); per iteration, the slots that entered (+) or "
                 "left (-) each piece\n", normal, (int)L.piece.size() - normal);
    logExplained = true;
  }
  static const char *pieceName[] = {"free", "damped", "bound", "stick", "slip"};
  int entered[5] = {0, 0, 0, 0, 0}, left[5] = {0, 0, 0, 0, 0};
  const bool first = it == 0 || loggedPieces.size() != L.piece.size();
  for (size_t j = 0; j < L.piece.size(); j++) {
    if (first) entered[L.piece[j]]++;
    else if (L.piece[j] != loggedPieces[j]) { entered[L.piece[j]]++; left[loggedPieces[j]]++; }
  }
  loggedPieces = L.piece;
  std::string line = "  iteration " + std::to_string(it);
  char number[32];
  std::snprintf(number, sizeof number, "%.3e", residual);
  line += std::string(first ? " (the previous step's multipliers, this step's load)" : "") + ": residual " + number;
  if (outcome == FixedPointTaken) line += " (the Newton iterate did not lower the merit: one fixed-point iteration instead)";
  if (outcome == NewtonShortened)
    line += " (the Newton iterate did not lower the merit: the step " + std::to_string((int)std::lround(1 / step)) + " times shorter)";
  line += first ? "; slots:" : "; changed:";
  int shown = 0;
  for (int k = 0; k < 5; k++) {
    if (first && entered[k]) line += std::string(shown++ ? ", " : " ") + pieceName[k] + " " + std::to_string(entered[k]);
    if (!first && entered[k]) line += std::string(shown++ ? ", " : " ") + pieceName[k] + " +" + std::to_string(entered[k]);
    if (!first && left[k]) line += std::string(shown++ ? ", " : " ") + pieceName[k] + " -" + std::to_string(left[k]);
  }
  if (!shown) line += " none";
  std::fprintf(stderr, "%s\n", line.c_str());
}

void requireSolver(const char *who) {
  requireNodes(who);
  requireDelassus(who);
}

// The iterations of one Newton solve from (c, m): sets residual, it, unresolved; true when
// the step converged (stepConverged)
bool newtonIterations(const std::vector<double> &cFree, std::vector<double> &c, std::vector<double> &m, double &residual,
                      int &it, int &unresolved) {
  const int nc = F.nc;
  std::vector<double> previous(nc), rhs(nc), newtonM(nc);
  double merit = 0;
  residual = newtonStart(cFree.data(), c.data(), m.data(), merit);
  it = 0; unresolved = 0;
  bool done = false;
  while (true) {
    L.relations(c.data());
    if (guard(it, c.data(), m.data())) L.relations(c.data());   // r halved: the pieces at the new r
    if (!sameAsPrepared() && !newtonPrepare()) { residual = NAN; break; }
    for (int j = 0; j < nc; j++) {
      rhs[j] = L.h[j] - L.a[T * j] * cFree[L.aSlot[T * j]];
      for (int t = 1; t < T; t++) if (L.a[T * j + t] != 0) rhs[j] -= L.a[T * j + t] * cFree[L.aSlot[T * j + t]];
    }
    previous = m;
    if (!newtonSolve(rhs.data(), newtonM.data())) { residual = NAN; break; }
    double step = 1;
    const int outcome = safeguardStep(cFree.data(), previous.data(), newtonM.data(), merit, c.data(), m.data(), residual, step,
                                      Q.haveDx ? Q.Dx.data() : nullptr);
    it++;
    logIteration(it, residual, outcome, step);
    done = stepConverged(residual, c.data(), unresolved);
    if (done || it >= SP.maxit || std::isnan(residual) || std::isinf(residual)) break;
  }
  endStep();
  return done;
}

// One step's Newton. With a disk law (3D pairs), a safeguarded Newton that does not converge
// within -maxit is run again from the step's start without its safeguards (retry), as many
// iterations more: the disk's slip piece is curved, and on thin plates the merit test rejects
// the iterates of a Newton that converges (docs/stability.md, "Three dimensions": slab3d-thin
// at Lz = 0.025 and 0.01, where every Newton iterate was replaced and the fixed-point
// iterations crept, and plain Newton converges in 14 to 16). The iterations of both count.
long newton(KN<double> *const &pcFree, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  requireSolver("contactKernelNewton");
  const int nc = F.nc;
  KN<double> &cFreeK = *pcFree, &cK = *pc, &mK = *pm, &info = *pinfo;
  if (cFreeK.N() != nc || cK.N() != nc || mK.N() != nc) ExecError("contactKernelNewton: one value per slot expected");
  std::vector<double> cFree(nc), c(nc), m(nc);
  for (int j = 0; j < nc; j++) { cFree[j] = cFreeK[j]; c[j] = cK[j]; m[j] = mK[j]; }
  const std::vector<double> cStart = c, mStart = m;
  double residual = 0;
  int it = 0, unresolved = 0;
  bool done = newtonIterations(cFree, c, m, residual, it, unresolved);
  if (!done && SP.safeguards && L.hasPairs() && std::isfinite(residual)) {
    int more = 0;
    c = cStart; m = mStart;
    SP.safeguards = false;
    Q.retries++;
    if (SP.verbose) std::fprintf(stderr, "  (the safeguarded Newton did not converge in %d iterations: plain Newton from the step's start)\n", it);
    done = newtonIterations(cFree, c, m, residual, more, unresolved);
    SP.safeguards = true;
    it += more;
  }
  for (int j = 0; j < nc; j++) { cK[j] = c[j]; mK[j] = m[j]; }
  if (info.N() != 4) info.resize(4);
  info[0] = residual; info[1] = it; info[2] = unresolved; info[3] = 0;
  return done ? it : -1;
}

// Anderson-accelerated fixed point: m <- G(m), G the symmetric sweep above; the new iterate
// mixes the last FP.window iterates to minimise G(m) - m, and is kept only when its natural
// residual is below G's (else the history restarts). The test is Newton's natural residual.
long fixedPoint(KN<double> *const &pcFree, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  requireSolver("contactKernelFixedPoint");
  const int nc = F.nc;
  KN<double> &cFreeK = *pcFree, &cK = *pc, &mK = *pm, &info = *pinfo;
  if (cFreeK.N() != nc || cK.N() != nc || mK.N() != nc) ExecError("contactKernelFixedPoint: one value per slot expected");
  fixedPointPrepare();
  // the convergence test at the operator's scale, as Newton's (referenceEvaluate)
  const std::vector<double> userR = L.r;
  for (int j = 0; j < nc; j++) L.setAugmentation(j, F.rReference[j]);
  std::vector<double> cFree(nc), c(nc), m(nc);
  for (int j = 0; j < nc; j++) { cFree[j] = cFreeK[j]; m[j] = mK[j]; }
  auto exactVelocities = [&]() { velocities(cFree.data(), m.data(), c.data()); };
  exactVelocities();
  double residual = L.evaluate(c.data(), m.data());
  logIteration(0, residual);
  int unresolved = 0;
  bool done = stepConverged(residual, c.data(), unresolved);
  // Anderson acceleration of the map G: m -> two sweeps (forward, backward), window FP.window
  const int window = FP.window;
  std::vector<double> dX((size_t)window * nc), dF((size_t)window * nc), xPrev(nc), fPrev(nc), x(nc), f(nc), gm(nc), gc(nc);
  int stored = 0, head = 0;
  bool havePrev = false, stalled = false;
  std::vector<double> recent(20, 0.);                // the residuals of the last 20 iterations
  int it = 0;
  while (!done && it < SP.maxit && std::isfinite(residual)) {
    x = m;
    fixedPointSweep(true, c.data(), m.data());
    fixedPointSweep(false, c.data(), m.data());
    it++;
    if (it % 25 == 0) exactVelocities();             // the updates' round-off does not pile up
    residual = L.evaluate(c.data(), m.data());
    if (residual <= SP.tol) { exactVelocities(); residual = L.evaluate(c.data(), m.data()); }
    done = stepConverged(residual, c.data(), unresolved);
    // stalled: the residual has not changed by 1e-6 of itself in 20 iterations, away from a
    // solution (the sweeps then have a fixed point that is not one of the law, seen with steep
    // damping tables: a backward sweep undoes the forward one); stop, exit 4 follows
    recent[it % 20] = residual;
    if (!done && it >= 20 && std::fabs(residual - recent[(it + 1) % 20]) <= 1e-6 * residual) {
      stalled = true;
      logIteration(it, residual);
      break;
    }
    if (window > 0 && !done && std::isfinite(residual)) {
      for (int j = 0; j < nc; j++) f[j] = m[j] - x[j];
      if (havePrev) {
        for (int j = 0; j < nc; j++) { dX[(size_t)head * nc + j] = x[j] - xPrev[j]; dF[(size_t)head * nc + j] = f[j] - fPrev[j]; }
        head = (head + 1) % window;
        stored = std::min(stored + 1, window);
      }
      xPrev = x; fPrev = f; havePrev = true;
      if (stored > 0) {
        // gamma = argmin |f - dF gamma| (normal equations, regularized)
        const int w = stored;
        std::vector<double> A((size_t)w * w), rhs(w);
        double trace = 0;
        for (int a = 0; a < w; a++) {
          for (int b = 0; b < w; b++) {
            double sum = 0;
            for (int j = 0; j < nc; j++) sum += dF[(size_t)a * nc + j] * dF[(size_t)b * nc + j];
            A[a + (size_t)b * w] = sum;
          }
          double sum = 0;
          for (int j = 0; j < nc; j++) sum += dF[(size_t)a * nc + j] * f[j];
          rhs[a] = sum;
          trace += A[a + (size_t)a * w];
        }
        for (int a = 0; a < w; a++) A[a + (size_t)a * w] += 1e-12 * trace + 1e-300;
        std::vector<int> piv(w);
        int one = 1, info2 = 0;
        dgetrf_(&w, &w, A.data(), &w, piv.data(), &info2);
        if (info2 == 0) dgetrs_("N", &w, &one, A.data(), &w, piv.data(), rhs.data(), &w, &info2);
        if (info2 == 0) {
          gm = m; gc = c;
          for (int j = 0; j < nc; j++) {
            double s = 0;
            for (int a = 0; a < w; a++) s += (dX[(size_t)a * nc + j] + dF[(size_t)a * nc + j]) * rhs[a];
            m[j] = gm[j] - s;
          }
          exactVelocities();
          const double accelerated = L.evaluate(c.data(), m.data());
          if (accelerated <= residual) {
            residual = accelerated;
            done = stepConverged(residual, c.data(), unresolved);
          }
          else {                                     // not better: keep G's iterate, forget the history
            m = gm; c = gc;
            residual = L.evaluate(c.data(), m.data());
            stored = 0; head = 0; havePrev = false;
          }
        }
      }
    }
    logIteration(it, residual);
  }
  for (int j = 0; j < nc; j++) L.setAugmentation(j, userR[j]);
  for (int j = 0; j < nc; j++) { cK[j] = c[j]; mK[j] = m[j]; }
  if (info.N() != 4) info.resize(4);
  info[0] = residual; info[1] = it; info[2] = unresolved; info[3] = stalled;
  return done ? it : -1;
}

// A whole contact solve in one call: cFree = C S^-1 rhs (contactKernelFree), the solver,
// then v = S^-1 (rhs - C'W m) (contactKernelFinish). The same three calls the script makes
// for its own solvers, without the interpreter's cost of three.
template <long (*solver)(KN<double> *const &, KN<double> *const &, KN<double> *const &, KN<double> *const &)>
long wholeStep(KN<double> *const &prhs, KN<double> *const &pv, KN<double> *const &pc, KN<double> *const &pm,
               KN<double> *const &pinfo) {
  KN<double> cFree(F.nc);
  KN<double> *pFree = &cFree;
  freeVelocity(prhs, pFree);
  const long it = solver(pFree, pc, pm, pinfo);
  finish(pm, pv);
  return it;
}

// ---------------------------------------------------------------- the law for the script solvers
long lawRelations(KN<double> *const &pc, KN<double> *const &pa, KN<double> *const &pd, KN<double> *const &ph,
                  KN<long> *const &paSlot, KN<long> *const &pdSlot) {
  requireNodes("contactLawRelations");
  KN<double> &cK = *pc, &a = *pa, &d = *pd, &h = *ph;
  KN<long> &aSlot = *paSlot, &dSlot = *pdSlot;
  if (cK.N() != L.n) ExecError("contactLawRelations: one value per slot expected");
  std::vector<double> c = copyOf(cK);
  L.relations(c.data());
  a.resize(T * L.n); d.resize(T * L.n); h.resize(L.n); aSlot.resize(T * L.n); dSlot.resize(T * L.n);
  for (int j = 0; j < L.n; j++) h[j] = L.h[j];
  for (int e = 0; e < T * L.n; e++) { a[e] = L.a[e]; d[e] = L.d[e]; aSlot[e] = L.aSlot[e]; dSlot[e] = L.dSlot[e]; }
  return 0;
}

long newtonLog(const long &it, const double &residual, const long &outcome, const double &step) {
  requireNodes("contactNewtonLog");
  logIteration((int)it, residual, (int)outcome, step);
  return 0;
}
long newtonSafeguard(KN<double> *const &pcFree, KN<double> *const &pprevious, KN<double> *const &pnewton,
                     const double &meritBefore, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  requireSolver("contactNewtonSafeguard");
  const int nc = F.nc;
  KN<double> &cK = *pc, &mK = *pm, &info = *pinfo;
  if (pcFree->N() != nc || pprevious->N() != nc || pnewton->N() != nc || cK.N() != nc || mK.N() != nc)
    ExecError("contactNewtonSafeguard: one value per slot expected");
  std::vector<double> cFree = copyOf(*pcFree), previous = copyOf(*pprevious), newtonM = copyOf(*pnewton), c(nc), m(nc);
  double residual = 0, step = 1, merit = meritBefore;
  const int outcome = safeguardStep(cFree.data(), previous.data(), newtonM.data(), merit, c.data(), m.data(), residual, step);
  for (int j = 0; j < nc; j++) { cK[j] = c[j]; mK[j] = m[j]; }
  if (info.N() != 4) info.resize(4);
  info[0] = residual; info[1] = step; info[2] = merit;
  int unresolved = 0;
  stepConverged(residual, c.data(), unresolved);
  info[3] = unresolved;
  return outcome;
}
double newtonStartScript(KN<double> *const &pcFree, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  requireSolver("contactNewtonStart");
  if (pcFree->N() != F.nc || pc->N() != F.nc || pm->N() != F.nc) ExecError("contactNewtonStart: one value per slot expected");
  std::vector<double> cFree = copyOf(*pcFree), c = copyOf(*pc), m = copyOf(*pm);
  double merit = 0;
  const double residual = newtonStart(cFree.data(), c.data(), m.data(), merit);
  KN<double> &info = *pinfo;
  if (info.N() != 4) info.resize(4);
  info[0] = residual; info[1] = 1; info[2] = merit; info[3] = 0;
  return residual;
}

long newtonGuard(const long &it, KN<double> *const &pc, KN<double> *const &pm) {
  requireNodes("contactNewtonGuard");
  if (pc->N() != L.n || pm->N() != L.n) ExecError("contactNewtonGuard: one value per slot expected");
  std::vector<double> c = copyOf(*pc), m = copyOf(*pm);
  return guard((int)it, c.data(), m.data());
}
long newtonEnd() { endStep(); return 0; }

long counters(KN<double> *const &pinfo) {
  KN<double> &info = *pinfo;
  info.resize(8);
  info[0] = Q.fallbacks; info[1] = FP.sweeps; info[2] = Q.factorizations; info[3] = Q.corrections; info[4] = Q.refinements;
  info[5] = Q.cuts; info[6] = Q.halvings; info[7] = Q.retries;
  return 0;
}

// POSIX cksum (CRC-32, polynomial 0x04C11DB7, then the length) of the files' concatenation,
// as `cat FILES | cksum` prints it; -1 if a file cannot be read
long long posixChecksum(const std::vector<std::string> &files) {
  std::uint32_t table[256];
  for (std::uint32_t i = 0; i < 256; i++) {
    std::uint32_t c = i << 24;
    for (int k = 0; k < 8; k++) c = (c & 0x80000000u) ? (c << 1) ^ 0x04C11DB7u : c << 1;
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

static void Load_Init() {
  Global.Add("contactKernelParameter", "(", new OneOperator2_<long, string *, double>(parameter));
  Global.Add("contactKernelDampingTable", "(", new OneOperator2_<long, KN<double> *, KN<double> *>(dampingTable));
  Global.Add("contactKernelNodes", "(", new OneOperator6_<long, KN<double> *, KN<double> *, KN<double> *, KN<long> *, KN<long> *, KN<long> *>(nodes));
  Global.Add("contactKernelLawProblem", "(", new OneOperator1s_<string *, string *>(lawProblemText));
  Global.Add("contactKernelNodeVelocity", "(", new OneOperator1_<long, Matrice_Creuse<double> *>(nodeVelocity));
  Global.Add("contactKernelNodeFrames", "(", new OneOperator2_<long, KNM<double> *, KN<double> *>(nodeFrames));
  Global.Add("contactKernelDampingSlope", "(", new OneOperator1_<long, KN<double> *>(dampingSlope));
  Global.Add("contactKernelFactorize", "(", new OneOperator2_<long, Matrice_Creuse<double> *, Matrice_Creuse<double> *>(factorize));
  Global.Add("contactKernelFactorizeStep", "(", new OneOperator6_<long, double, double, double, Matrice_Creuse<double> *, KN<double> *,
                                                                    Matrice_Creuse<double> *>(factorizeStep));
  Global.Add("contactKernelDelassus", "(", new OneOperator1_<long, KNM<double> *>(delassus));
  Global.Add("contactKernelLargestEntry", "(", new OneOperator1_<double, Matrice_Creuse<double> *>(largestEntry));
  Global.Add("contactKernelSolve", "(", new OneOperator2_<long, KN<double> *, KN<double> *>(solve));
  Global.Add("contactKernelFree", "(", new OneOperator2_<long, KN<double> *, KN<double> *>(freeVelocity));
  Global.Add("contactKernelFinish", "(", new OneOperator2_<long, KN<double> *, KN<double> *>(finish));
  Global.Add("contactKernelProducts", "(", new OneOperator3_<long, Matrice_Creuse<double> *, Matrice_Creuse<double> *, Matrice_Creuse<double> *>(products));
  Global.Add("contactKernelMultiply", "(", new OneOperator4_<long, KN<double> *, KN<double> *, KN<double> *, KN<double> *>(multiply));
  Global.Add("contactKernelRecordStart", "(", new OneOperator4_<long, KN<double> *, KN<double> *, KN<double> *, KN<double> *>(recordStart));
  Global.Add("contactKernelRecord", "(", new OneOperator7_<long, KN<double> *, KN<double> *, KN<double> *, KN<double> *, KN<double> *, KN<double> *, KN<double> *>(stepRecord));
  Global.Add("contactKernelHistory", "(", new OneOperator3_<long, KN<double> *, KN<double> *, KN<double> *>(historyArrays));
  Global.Add("contactKernelNodal", "(", new OneOperator3_<long, KN<double> *, KN<double> *, KNM<double> *>(nodal));
  Global.Add("contactKernelCloseNodes", "(", new OneOperator0<long>(closeNodes));
  Global.Add("contactKernelAppendNodes", "(",
             new OneOperator7_<long, string *, long, double, KN<double> *, KN<double> *, KN<double> *, KNM<double> *>(appendNodes));
  Global.Add("contactKernelNewton", "(", new OneOperator4_<long, KN<double> *, KN<double> *, KN<double> *, KN<double> *>(newton));
  Global.Add("contactKernelFixedPoint", "(", new OneOperator4_<long, KN<double> *, KN<double> *, KN<double> *, KN<double> *>(fixedPoint));
  Global.Add("contactKernelNewtonStep", "(", new OneOperator5_<long, KN<double> *, KN<double> *, KN<double> *, KN<double> *, KN<double> *>(wholeStep<newton>));
  Global.Add("contactKernelFixedPointStep", "(", new OneOperator5_<long, KN<double> *, KN<double> *, KN<double> *, KN<double> *, KN<double> *>(wholeStep<fixedPoint>));
  Global.Add("contactLawRelations", "(", new OneOperator6_<long, KN<double> *, KN<double> *, KN<double> *, KN<double> *, KN<long> *, KN<long> *>(lawRelations));
  Global.Add("contactNewtonLog", "(", new OneOperator4_<long, long, double, long, double>(newtonLog));
  Global.Add("contactNewtonGuard", "(", new OneOperator3_<long, long, KN<double> *, KN<double> *>(newtonGuard));
  Global.Add("contactNewtonEnd", "(", new OneOperator0<long>(newtonEnd));
  Global.Add("contactNewtonStart", "(", new OneOperator4_<double, KN<double> *, KN<double> *, KN<double> *, KN<double> *>(newtonStartScript));
  Global.Add("contactNewtonSafeguard", "(", new OneOperator7_<long, KN<double> *, KN<double> *, KN<double> *, double, KN<double> *, KN<double> *, KN<double> *>(newtonSafeguard));
  Global.Add("contactKernelCounters", "(", new OneOperator1_<long, KN<double> *>(counters));
  Global.Add("contactKernelSourcesChanged", "(", new OneOperator1_<long, string *>(sourcesChanged));
}

LOADFUNC(Load_Init)
