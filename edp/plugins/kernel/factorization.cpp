// factorization.cpp: linear algebra with one factorization of S = M/k + A + kB + C'W Kn C
// (symmetric positive definite; Dirichlet rows carry FreeFEM's tgv). CHOLMOD factorizes
// P S P' = L L' with an ordering that puts the contact degrees of freedom (those C touches)
// last (CAMD in 2D; in 3D METIS's nested dissection of the others, then them:
// docs/performance.md, "Three dimensions", measured both), so the trailing block L_CC of L is
// the Cholesky factor of the Schur complement of S on Gamma3:
//   - the Delassus matrix C S^-1 C' = G'G with G = L_CC^-1 (P C')_C, no solve per slot;
//   - a back-substitution splits in two halves around the contact solve: the forward sweep
//     z = L^-1 P b gives the free slot velocities c_free = C S^-1 b, and the contact load only
//     changes the trailing block of z before the backward sweep v = P' L^-T z.
// docs/performance.md, "How a step is solved", explains the choices.
#include <algorithm>
#include <cmath>
#include "blas.hpp"
#include "kernel.hpp"
#include "signals.hpp"

namespace contactkernel {

void Factorization::release() {
  haveForward = false;
  external = false;
  n = nc = nt = 0;
  Ltrail.clear(); slotOf.clear(); posOf.clear(); dofOf.clear(); valOf.clear();
  z.clear(); Dw.clear();
  externalFree = nullptr; externalFinish = nullptr;
  if (!started) return;
  if (L) cholmod_free_factor(&L, &common);
  if (work) cholmod_free_dense(&work, &common);
  if (x) cholmod_free_dense(&x, &common);
  if (y) cholmod_free_dense(&y, &common);
  if (e) cholmod_free_dense(&e, &common);
  cholmod_finish(&common);
  started = false;
}

void Factorization::apply(int sys, const double *in, double *out) {
  std::copy(in, in + n, static_cast<double *>(work->x));
  cholmod_solve2(sys, L, work, nullptr, &x, nullptr, &y, &e, &common);
  std::copy(static_cast<double *>(x->x), static_cast<double *>(x->x) + n, out);
}

namespace {

void checkContactOperator(const Kernel &k, const SparseTriplets &C, int n, const char *who) {
  if (C.columns != n) kernelError(std::string(who) + ": S must be square, with as many columns as C");
  if (C.rows != k.law.n)
    kernelError(std::string(who) + ": C has " + std::to_string(C.rows) + " rows, but contactKernelNodes gave "
                + std::to_string(k.law.n) + " slots");
}

// the upper triangle of S (stype = 1) from its triplets; a half-stored (sym) matrix keeps its
// lower triangle
cholmod_sparse *upperFromTriplets(Factorization &factor, const SparseTriplets &S) {
  const int n = S.rows;
  size_t nz = 0;
  for (size_t e = 0; e < S.count; e++) if (S.lowerHalf || S.row[e] <= S.column[e]) nz++;
  cholmod_triplet *T = cholmod_allocate_triplet(n, n, nz, 1, CHOLMOD_REAL, &factor.common);
  int *Ti = static_cast<int *>(T->i), *Tj = static_cast<int *>(T->j);
  double *Tx = static_cast<double *>(T->x);
  for (size_t e = 0; e < S.count; e++) {
    int i = S.row[e], j = S.column[e];
    if (!S.lowerHalf && i > j) continue;
    Ti[T->nnz] = std::min(i, j); Tj[T->nnz] = std::max(i, j); Tx[T->nnz] = S.value[e]; T->nnz++;
  }
  cholmod_sparse *A = cholmod_triplet_to_sparse(T, nz, &factor.common);
  cholmod_free_triplet(&T, &factor.common);
  return A;
}

// S = cm M + ca A + cb B + D + tgv on the fixed degrees of freedom, from the merged CSR form of
// M, A, B (products.cpp) without a FreeFEM matrix: the upper triangle in CSC, the entries
// (i, j >= i) of each row i in column j, summed in the order of FreeFEM's sum
// (1/k) M + A + k B + D + Dirichlet: the same matrix, to the last bit, as that sum's upper
// triangle, which is what contactKernelFactorize would factorize.
cholmod_sparse *upperFromProducts(Kernel &k, const StepMatrix &step) {
  const ProductMatrices &products = k.products;
  Factorization &factor = k.factor;
  const int n = products.n;
  std::vector<int> columnStart(n + 1, 0);          // the entries (i, j >= i) of row i go to column j
  for (int i = 0; i < n; i++)
    for (int e = products.start[i]; e < products.start[i + 1]; e++) if (products.column[e] >= i) columnStart[products.column[e] + 1]++;
  for (int j = 0; j < n; j++) columnStart[j + 1] += columnStart[j];
  cholmod_sparse *A = cholmod_allocate_sparse(n, n, columnStart[n], 1, 1, 1, CHOLMOD_REAL, &factor.common);
  if (!A) return nullptr;
  int *Ap = static_cast<int *>(A->p), *Ai = static_cast<int *>(A->i);
  double *Ax = static_cast<double *>(A->x);
  std::copy(columnStart.begin(), columnStart.end(), Ap);
  std::vector<int> fill(columnStart.begin(), columnStart.end() - 1);
  for (int i = 0; i < n; i++)                        // rows in order: each column's rows come sorted
    for (int e = products.start[i]; e < products.start[i + 1]; e++) {
      const int j = products.column[e];
      if (j < i) continue;
      const double *v = products.entry(i, e);
      Ai[fill[j]] = i;
      Ax[fill[j]++] = step.cm * v[0] + v[1] * step.ca + step.cb * v[2];
    }
  auto entry = [&](int i, int j) -> double * {       // (i, j), i <= j: in column j, row i
    const int *first = Ai + Ap[j], *last = Ai + Ap[j + 1];
    const int *at = std::lower_bound(first, last, i);
    return at != last && *at == i ? Ax + (at - Ai) : nullptr;
  };
  const SparseTriplets &D = *step.D;
  for (size_t e = 0; e < D.count; e++) {
    int i = D.row[e], j = D.column[e];
    if (D.lowerHalf) { if (i > j) std::swap(i, j); }
    else if (i > j) continue;
    double *x = entry(i, j);
    if (!x) { cholmod_free_sparse(&A, &factor.common); kernelError("contactKernelFactorizeStep: C'W Kn C has an entry outside the pattern of M, A, B"); }
    *x += D.value[e];
  }
  for (int i = 0; i < n; i++)
    if (step.fixed[i] != 0) *entry(i, i) += step.tgv;
  return A;
}

// METIS (CHOLMOD's nested dissection through METIS_NodeND) on the interior unknowns, the
// pattern of A (upper triangle) restricted to them, then the contact unknowns (member 1) last,
// in their order; 1 if it worked
int metisContactLast(Factorization &factor, cholmod_sparse *A, const std::vector<int> &member, std::vector<int> &perm) {
  const int n = A->ncol;
  const int *Ap = static_cast<int *>(A->p), *Ai = static_cast<int *>(A->i);
  std::vector<int> position(n, -1), interior;
  for (int i = 0; i < n; i++) if (!member[i]) { position[i] = interior.size(); interior.push_back(i); }
  const int ni = interior.size();
  std::vector<int> start(ni + 1, 0);
  for (int j = 0; j < n; j++)
    if (position[j] >= 0)
      for (int e = Ap[j]; e < Ap[j + 1]; e++) if (position[Ai[e]] >= 0 && Ai[e] <= j) start[position[j] + 1]++;
  for (int q = 0; q < ni; q++) start[q + 1] += start[q];
  cholmod_sparse *B = cholmod_allocate_sparse(ni, ni, start[ni], 1, 1, 1, CHOLMOD_PATTERN, &factor.common);
  if (!B) return 0;
  int *Bp = static_cast<int *>(B->p), *Bi = static_cast<int *>(B->i);
  std::copy(start.begin(), start.end(), Bp);
  for (int j = 0; j < n; j++)                        // A's columns come with their rows sorted
    if (position[j] >= 0)
      for (int e = Ap[j]; e < Ap[j + 1]; e++) if (position[Ai[e]] >= 0 && Ai[e] <= j) Bi[start[position[j]]++] = position[Ai[e]];
  std::vector<int> order(std::max(ni, 1));
  const int ok = ni == 0 || keepingSignalHandlers([&] { return cholmod_metis(B, nullptr, 0, 1, order.data(), &factor.common); });   // (signals.hpp)
  cholmod_free_sparse(&B, &factor.common);
  if (!ok) return 0;
  int q = 0;
  for (int p = 0; p < ni; p++) perm[q++] = interior[order[p]];
  for (int i = 0; i < n; i++) if (member[i]) perm[q++] = i;
  return 1;
}

// S (its triplets, or from the products with step) factorized, the contact unknowns last;
// 0, or 1 (not positive definite), 2 (CHOLMOD failed)
long factorizeOrFail(Kernel &k, const SparseTriplets *S, const StepMatrix *step, const SparseTriplets &C, int n) {
  Factorization &factor = k.factor;
  cholmod_start(&factor.common);
  factor.started = true;
  factor.common.print = 0;
  factor.common.error_handler = nullptr;
  factor.n = n;
  factor.nc = C.rows;
  cholmod_sparse *A = S ? upperFromTriplets(factor, *S) : upperFromProducts(k, *step);
  if (!A) return 2;

  // the contact unknowns (columns of C) go last: CAMD with two constraint sets, or (ordering
  // 1) METIS's nested dissection of the interior, then the contact unknowns
  std::vector<int> member(n, 0);
  for (size_t e = 0; e < C.count; e++) if (C.value[e] != 0) member[C.column[e]] = 1;
  std::vector<int> perm(n);
  int ok = k.settings.ordering == 1 ? metisContactLast(factor, A, member, perm)
                                    : cholmod_camd(A, nullptr, 0, member.data(), perm.data(), &factor.common);
  factor.common.nmethods = 1;
  factor.common.method[0].ordering = CHOLMOD_GIVEN;
  factor.common.postorder = 0;
  factor.common.supernodal = CHOLMOD_SUPERNODAL;
  if (ok) factor.L = cholmod_analyze_p(A, perm.data(), nullptr, 0, &factor.common);
  if (factor.L) cholmod_factorize(A, factor.L, &factor.common);
  cholmod_free_sparse(&A, &factor.common);
  if (!ok || !factor.L || factor.common.status == CHOLMOD_OUT_OF_MEMORY || factor.common.status == CHOLMOD_INVALID) return 2;
  if (factor.common.status == CHOLMOD_NOT_POSDEF || factor.L->minor < (size_t)n) return 1;

  // position of each unknown in the factor; the contact unknowns must be the trailing block
  const int *P = static_cast<int *>(factor.L->Perm);
  std::vector<int> position(n);
  for (int q = 0; q < n; q++) position[P[q]] = q;
  int nt = 0;
  for (int i = 0; i < n; i++) nt += member[i];
  factor.nt = nt;
  for (int i = 0; i < n; i++) if (member[i] && position[i] < n - nt) return 2;
  for (size_t e = 0; e < C.count; e++) if (C.value[e] != 0) {
    factor.slotOf.push_back(C.row[e]); factor.posOf.push_back(position[C.column[e]] - (n - nt)); factor.valOf.push_back(C.value[e]);
    factor.dofOf.push_back(C.column[e]);
  }

  // L_CC from the supernodal factor: the columns n - nt ... n - 1 and their rows
  if (!factor.L->is_super) return 2;
  factor.Ltrail.assign((size_t)nt * nt, 0.);
  const int *super = static_cast<int *>(factor.L->super), *pi = static_cast<int *>(factor.L->pi);
  const int *px = static_cast<int *>(factor.L->px), *s = static_cast<int *>(factor.L->s);
  const double *Lx = static_cast<double *>(factor.L->x);
  for (size_t q = 0; q < factor.L->nsuper; q++) {
    int k1 = super[q], k2 = super[q + 1], nrow = pi[q + 1] - pi[q];
    for (int jj = k1; jj < k2; jj++) {
      if (jj < n - nt) continue;
      for (int r = 0; r < nrow; r++) {
        int row = s[pi[q] + r];
        if (row < jj) continue;
        factor.Ltrail[(size_t)(row - (n - nt)) + (size_t)(jj - (n - nt)) * nt] = Lx[px[q] + r + (size_t)(jj - k1) * nrow];
      }
    }
  }
  factor.work = cholmod_zeros(n, 1, CHOLMOD_REAL, &factor.common);
  factor.z.assign(n, 0.);
  factor.haveForward = false;
  return 0;
}

// trailing block of the solution of L' w = z (uses only the trailing block of z)
void trailingVelocity(const Factorization &factor, const double *zt, double *wt) {
  const int nt = factor.nt, inc = 1;
  std::copy(zt, zt + nt, wt);
  if (nt > 0) dtrsv_("L", "T", "N", &nt, factor.Ltrail.data(), &nt, wt, &inc);
}

}  // namespace

// On any failure the kernel is left with no factor, so that a later call raises an error.
long factorize(Kernel &k, const SparseTriplets &S, const SparseTriplets &C) {
  requireNodes(k, "contactKernelFactorize");
  if (S.rows != S.columns) kernelError("contactKernelFactorize: S must be square, with as many columns as C");
  checkContactOperator(k, C, S.rows, "contactKernelFactorize");
  k.factor.release();
  k.factor.generation++;
  const long status = factorizeOrFail(k, &S, nullptr, C, S.rows);
  if (status != 0) k.factor.release();
  return status;
}

// S = cm M + ca A + cb B + D (+ tgv on the degrees of freedom where fixed is 1), factorized as
// contactKernelFactorize would factorize that matrix (contactKernelProducts first)
long factorizeStep(Kernel &k, const StepMatrix &step, const SparseTriplets &C) {
  requireNodes(k, "contactKernelFactorizeStep");
  const ProductMatrices &products = k.products;
  if (products.n == 0) kernelError("contactKernelFactorizeStep: call contactKernelProducts first");
  const SparseTriplets &D = *step.D;
  if (D.rows != products.n || D.columns != products.n || step.fixedCount != products.n)
    kernelError("contactKernelFactorizeStep: D and the fixed degrees of freedom must have the size of M, A, B");
  checkContactOperator(k, C, products.n, "contactKernelFactorizeStep");
  for (int i = 0; i < products.n; i++) {             // a fixed degree of freedom needs its diagonal entry
    bool diagonal = false;
    for (int e = products.start[i]; e < products.start[i + 1]; e++) diagonal = diagonal || products.column[e] == i;
    if (!diagonal) kernelError("contactKernelFactorizeStep: M, A, B have no diagonal entry in row " + std::to_string(i));
  }
  k.factor.release();
  k.factor.generation++;
  const long status = factorizeOrFail(k, nullptr, &step, C, products.n);
  if (status != 0) k.factor.release();
  return status;
}

void requireFactor(const Kernel &k, const char *who) {
  if (!k.factor.L && !k.factor.externalFree) kernelError(std::string("contactkernel: ") + who + " without a successful contactKernelFactorize");
}
void requireSlots(const Kernel &k, const char *who) {
  if (!k.factor.L && !k.factor.external)
    kernelError(std::string("contactkernel: ") + who + " without a successful contactKernelFactorize (or contactKernelExternalFactor)");
}

// The steps are solved elsewhere (the ranks' PETSc solver, edp/plugins/ranks/): no factor here,
// only n and the map C, which the record and the nodal table read (slotVelocities)
void externalFactor(Kernel &k, int n, const SparseTriplets &C) {
  requireNodes(k, "contactKernelExternalFactor");
  checkContactOperator(k, C, n, "contactKernelExternalFactor");
  k.factor.release();
  k.factor.generation++;
  k.factor.n = n;
  k.factor.nc = k.law.n;
  for (size_t e = 0; e < C.count; e++) if (C.value[e] != 0) {
    const int row = C.oneBased ? C.row[e] - 1 : C.row[e], column = C.oneBased ? C.column[e] - 1 : C.column[e];
    k.factor.slotOf.push_back(row); k.factor.dofOf.push_back(column); k.factor.valOf.push_back(C.value[e]);
  }
  k.factor.external = true;
}
void requireDelassus(const Kernel &k, const char *who) {
  requireFactor(k, who);
  if (k.factor.delassusGeneration != k.factor.generation)
    kernelError(std::string(who) + ": call contactKernelDelassus after the last contactKernelFactorize");
}

namespace {
// r_j = r / Dw_jj once Dw is known: the stress a unit velocity of slot j produces through the
// body, so that the default r = 1 fits any scene (a 3D node's tangential pair shares one: 1 over
// the mean of its two Dw_jj)
void settleDelassus(Kernel &k) {
  Factorization &factor = k.factor;
  const int nc = factor.nc;
  factor.delassusGeneration = factor.generation;
  contactlaw::Slots &law = k.law;
  factor.rReference.assign(nc, 0.);
  for (int j = 0; j < nc; j++) {
    const int q = law.pair[j];
    factor.rReference[j] = q >= 0 ? 2. / (factor.Dw[j + (size_t)j * nc] + factor.Dw[q + (size_t)q * nc]) : 1. / factor.Dw[j + (size_t)j * nc];
  }
  for (int j = 0; j < nc; j++)
    law.setAugmentation(j, law.pair[j] >= 0 ? k.settings.r * factor.rReference[j] : k.settings.r / factor.Dw[j + (size_t)j * nc]);
}
}  // namespace

void externalDelassus(Kernel &k, std::vector<double> &&Dw) {
  if (!k.factor.externalFree || Dw.size() != (size_t)k.factor.nc * k.factor.nc)
    kernelError("contactkernel: the ranks' Delassus matrix without their factor, or of the wrong size");
  k.factor.Dw = std::move(Dw);
  settleDelassus(k);
}

void computeDelassus(Kernel &k) {
  requireFactor(k, "contactKernelDelassus");
  if (!k.factor.L) kernelError("contactKernelDelassus: the ranks compute the Delassus matrix (-ranks)");
  Factorization &factor = k.factor;
  const int nt = factor.nt, nc = factor.nc;
  // G = L_CC^-1 Ct (nt x nc), Ct = (P C')_C
  std::vector<double> G((size_t)nt * nc, 0.);
  for (size_t e = 0; e < factor.slotOf.size(); e++) G[factor.posOf[e] + (size_t)factor.slotOf[e] * nt] += factor.valOf[e];
  const double one = 1., zero = 0.;
  if (nt > 0 && nc > 0) dtrsm_("L", "L", "N", "N", &nt, &nc, &one, factor.Ltrail.data(), &nt, G.data(), &nt);
  std::vector<double> D((size_t)nc * nc, 0.);
  if (nt > 0 && nc > 0) dsyrk_("U", "T", &nc, &nt, &one, G.data(), &nt, &zero, D.data(), &nc);
  for (int j = 0; j < nc; j++) for (int i = j + 1; i < nc; i++) D[i + (size_t)j * nc] = D[j + (size_t)i * nc];
  factor.Dw.assign((size_t)nc * nc, 0.);
  for (int j = 0; j < nc; j++) for (int i = 0; i < nc; i++) factor.Dw[i + (size_t)j * nc] = D[i + (size_t)j * nc] * k.nodes.slotWeight[j];
  settleDelassus(k);
}

void solveWithFactor(Kernel &k, const double *b, double *x) {
  requireFactor(k, "contactKernelSolve");
  if (!k.factor.L) kernelError("contactKernelSolve: S is factorized across the ranks (-ranks)");
  k.factor.apply(CHOLMOD_A, b, x);
}

void freeVelocity(Kernel &k, const double *b, double *c) {
  requireFactor(k, "contactKernelFree");
  Factorization &factor = k.factor;
  if (factor.externalFree) factor.externalFree(b, c);   // -ranksolver direct: the ranks' solve
  else {
    // z = L^-1 P b (the permutation applied here, the triangular solve by CHOLMOD)
    const int *P = static_cast<int *>(factor.L->Perm);
    double *work = static_cast<double *>(factor.work->x);
    for (int q = 0; q < factor.n; q++) work[q] = b[P[q]];
    cholmod_solve2(CHOLMOD_L, factor.L, factor.work, nullptr, &factor.x, nullptr, &factor.y, &factor.e, &factor.common);
    std::copy(static_cast<double *>(factor.x->x), static_cast<double *>(factor.x->x) + factor.n, factor.z.begin());
    std::vector<double> wt(factor.nt);
    trailingVelocity(factor, factor.z.data() + (factor.n - factor.nt), wt.data());
    std::fill(c, c + factor.nc, 0.);
    for (size_t e = 0; e < factor.slotOf.size(); e++) c[factor.slotOf[e]] += factor.valOf[e] * wt[factor.posOf[e]];
  }
  factor.haveForward = true;
  // the size of the velocities a solver computes from them, c = cFree - Dw m: the law's
  // round-off guard weighs their round-off (Slots::evaluate)
  if ((int)k.law.velocityScale.size() == factor.nc) for (int j = 0; j < factor.nc; j++) k.law.velocityScale[j] = std::fabs(c[j]);
}

void finishVelocity(Kernel &k, const double *m, double *v) {
  requireFactor(k, "contactKernelFinish");
  Factorization &factor = k.factor;
  if (!factor.haveForward) kernelError("contactKernelFinish: call contactKernelFree first");
  if (factor.externalFinish) { factor.externalFinish(m, v); return; }   // -ranksolver direct: the ranks' solve
  const int nt = factor.nt, inc = 1;
  // the contact load changes the trailing block of z only: z_C -= L_CC^-1 (P C' W m)_C
  std::vector<double> load(nt, 0.);
  for (size_t e = 0; e < factor.slotOf.size(); e++)
    load[factor.posOf[e]] += factor.valOf[e] * k.nodes.slotWeight[factor.slotOf[e]] * m[factor.slotOf[e]];
  if (nt > 0) dtrsv_("L", "N", "N", &nt, factor.Ltrail.data(), &nt, load.data(), &inc);
  double *work = static_cast<double *>(factor.work->x);
  std::copy(factor.z.begin(), factor.z.end(), work);
  for (int i = 0; i < nt; i++) work[factor.n - nt + i] -= load[i];
  // v = P' L^-T z
  cholmod_solve2(CHOLMOD_Lt, factor.L, factor.work, nullptr, &factor.x, nullptr, &factor.y, &factor.e, &factor.common);
  const int *P = static_cast<int *>(factor.L->Perm);
  const double *w = static_cast<double *>(factor.x->x);
  for (int q = 0; q < factor.n; q++) v[P[q]] = w[q];
}

// slot velocities C v (after a factorization: C is kept as triplets)
void slotVelocities(const Kernel &k, const double *v, std::vector<double> &cv) {
  const Factorization &factor = k.factor;
  cv.assign(factor.nc, 0.);
  for (size_t e = 0; e < factor.slotOf.size(); e++) cv[factor.slotOf[e]] += factor.valOf[e] * v[factor.dofOf[e]];
}

// The size of the terms a solver computes the velocities from, c = cFree - Dw m, at a step's
// start (m: its first multipliers): velocityScale_j = |cFree_j| + sum_i |Dw_ji m_i|, whose
// round-off the law's guard weighs (Slots::evaluate). |cFree| alone misses a body held only by
// contact, whose rigid motion gives Dw large entries, under friction forces that cancel across
// the face: the half-disk at mu = 1 computes v_tau to about 1e-10 g where cFree is 1e-2 g.
void roundoffScale(Kernel &k, const double *cFree, const double *m) {
  const Factorization &factor = k.factor;
  contactlaw::Slots &law = k.law;
  const int nc = factor.nc;
  if ((int)law.velocityScale.size() != nc) return;
  for (int j = 0; j < nc; j++) law.velocityScale[j] = std::fabs(cFree[j]);
  for (int i = 0; i < nc; i++) {
    const double mi = std::fabs(m[i]);
    if (mi == 0) continue;
    const double *column = factor.Dw.data() + (size_t)i * nc;
    for (int j = 0; j < nc; j++) law.velocityScale[j] += std::fabs(column[j]) * mi;
  }
}

// c = cFree - Dw m
void velocities(const Kernel &k, const double *cFree, const double *m, double *c) {
  const int nc = k.factor.nc, inc = 1;
  const double minusOne = -1., one = 1.;
  std::copy(cFree, cFree + nc, c);
  dgemv_("N", &nc, &nc, &minusOne, k.factor.Dw.data(), &nc, m, &inc, &one, c, &inc);
}

}  // namespace contactkernel
