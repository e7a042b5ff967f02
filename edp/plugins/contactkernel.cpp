// contactkernel.cpp: the compiled kernel of edp/solve.edp's default solver (-solver newton).
// A FreeFEM plugin (load "contactkernel"), built by ./run.sh into edp/plugins/build/.
//
// What it does, and why it is compiled (README "Performance", issue 4):
// 1. Linear algebra with one factorization of S. S = M/k + A + kB + C'W Kn C is symmetric
//    positive definite (Dirichlet rows carry FreeFEM's tgv on the diagonal). It is factorized
//    once by CHOLMOD (supernodal Cholesky, P S P' = L L') with an ordering (CAMD) that puts
//    the contact degrees of freedom (those C touches) last. The trailing block L_CC of L is
//    then the Cholesky factor of the Schur complement of S on Gamma3, so that
//      - the Delassus matrix is C S^-1 C' = G'G with G = L_CC^-1 (P C')_C: no solve per slot;
//      - one back-substitution is split in two halves around the contact solve: the forward
//        sweep z = L^-1 P b gives the free slot velocities c_free = C S^-1 b (a dense solve
//        with L_CC' on the trailing block), and, once the contact stresses are known, the
//        contact load only changes the trailing block of z, so the backward sweep
//        v = P' L^-T z' finishes the step. A time step costs one back-substitution.
// 2. The semismooth Newton on the condensed equations: the same iteration, pieces, residual,
//    line search and cycle guard as the script version in edp/lib/contact.idp (see the
//    comments there for the nodal laws); in compiled code the per-slot loops cost nothing.
//    The script version runs the fixed point and the full-system Newton (-solver full),
//    which the tests compare with this kernel.
// 3. The record of a step (the energy terms of history.txt, the forces, zones and x_B, x_C
//    of contact_history.txt), for the same reason: on the paper mesh FreeFEM's interpreter
//    spent as long on them as the back-substitution takes. Script version: -kernel script.
//
// FreeFEM functions (int = FreeFEM int; 0 means success unless said):
//   contactKernelFactorize(matrix S, matrix C)   factorize S, C's columns ordered last;
//       returns 0, or 1 (S not positive definite), 2 (CHOLMOD failed), 3 (bad sizes)
//   contactKernelDelassus(real[int] W, real[int,int] Dw)   Dw = C S^-1 C' diag(W)
//   contactKernelSolve(real[int] b, real[int] x)            x = S^-1 b (one back-substitution)
//   contactKernelFree(real[int] b, real[int] cFree)         cFree = C S^-1 b (forward half)
//   contactKernelFinish(real[int] m, real[int] v)           v = S^-1 (b - C' diag(W) m) for
//       the b of the last contactKernelFree (backward half)
//   contactKernelProducts(matrix M, matrix A, matrix B)   keep M, A, B (one pattern) for:
//   contactKernelMultiply(real[int] v, real[int] Mv, real[int] Av, real[int] Bv)  three products
//   contactKernelRecordSetup(real[int] f, real[int] nodeX, real[int] nodeW, int[int] normalSlot,
//       int[int] tangentSlot, real[int] [g, none])   the data of contactKernelRecord:
//   contactKernelRecord(real[int] v, real[int] vOld, real[int] u, real[int] Lambda, real[int] Mv,
//       real[int] Bu, real[int] record)   the energy terms, the energy balance and the nodal
//       quantities of a step; returns 0, or 1 if the balance is not finite (see stepRecord)
//   contactKernelLaws(int[int] kind, int[int] partner, real[int] r, real[int] p)  the laws:
//       kind 0 normal / 1 tangential, partner = normal slot of a tangential slot (-1 none),
//       r = augmentation per slot, p = [cnu, g, mu, eps, penalty, literal, tol, maxit,
//       safeguards, forceScale]
//   contactKernelNewton(real[int] cFree, real[int] c, real[int] m, real[int] info)
//       one step's Newton, warm-started from (c, m); returns the iteration count, or -1
//       (no convergence); info = [residual, iterations, line-search cuts, augmentation
//       halvings, Newton matrix factorizations, low-rank corrections] (the last four summed
//       over the run)
#include "ff++.hpp"
#include "AFunction_ext.hpp"
#include <cholmod.h>
#include <vector>
#include <cmath>
#include <algorithm>

extern "C" {
void dtrsv_(const char *uplo, const char *trans, const char *diag, const int *n, const double *a,
            const int *lda, double *x, const int *incx);
void dtrsm_(const char *side, const char *uplo, const char *transa, const char *diag, const int *m,
            const int *n, const double *alpha, const double *a, const int *lda, double *b, const int *ldb);
void dsyrk_(const char *uplo, const char *trans, const int *n, const int *k, const double *alpha,
            const double *a, const int *lda, const double *beta, double *c, const int *ldc);
void dgemv_(const char *trans, const int *m, const int *n, const double *alpha, const double *a,
            const int *lda, const double *x, const int *incx, const double *beta, double *y, const int *incy);
void dgemm_(const char *transa, const char *transb, const int *m, const int *n, const int *k, const double *alpha,
            const double *a, const int *lda, const double *b, const int *ldb, const double *beta, double *c, const int *ldc);
void dgetrf_(const int *m, const int *n, double *a, const int *lda, int *ipiv, int *info);
void dgetrs_(const char *trans, const int *n, const int *nrhs, const double *a, const int *lda,
             const int *ipiv, double *b, const int *ldb, int *info);
}

namespace {

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
  std::vector<double> weight;           // W per slot (set by contactKernelDelassus)
  std::vector<double> z;                // forward sweep of the last contactKernelFree
  std::vector<double> Dw;               // nc x nc, column-major
  bool haveForward = false;
  long generation = 0;                  // counts the calls of contactKernelFactorize

  // forget the factor and everything derived from it (the weights and Dw of
  // contactKernelDelassus too: they belong to this factor's C); L is then null, so a factor
  // exists (L != null) only after a successful contactKernelFactorize
  void release() {
    haveForward = false;
    n = nc = nt = 0;
    Ltrail.clear(); slotOf.clear(); posOf.clear(); dofOf.clear(); valOf.clear();
    weight.clear(); z.clear(); Dw.clear();
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

long factorizeOrFail(Matrice_Creuse<double> *const &pS, Matrice_Creuse<double> *const &pC);

// On any failure the kernel is left with no factor, so that a later call raises an error.
long factorize(Matrice_Creuse<double> *const &pS, Matrice_Creuse<double> *const &pC) {
  F.release();
  F.generation++;
  const long status = factorizeOrFail(pS, pC);
  if (status != 0) F.release();
  return status;
}

long factorizeOrFail(Matrice_Creuse<double> *const &pS, Matrice_Creuse<double> *const &pC) {
  MatriceMorse<double> &S = *morse(pS), &C = *morse(pC);
  if (S.n != S.m || C.m != S.n) return 3;
  const int n = S.n;
  cholmod_start(&F.common);
  F.started = true;
  F.common.print = 0;
  F.common.error_handler = nullptr;
  F.n = n;
  F.nc = C.n;

  // upper triangle of S (stype = 1); a half-stored (sym) matrix keeps its lower triangle
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

  // the contact unknowns (columns of C) go last: CAMD with two constraint sets
  C.COO();
  std::vector<int> member(n, 0);
  for (size_t k = 0; k < C.nnz; k++) if (C.aij[k] != 0) member[C.j[k]] = 1;
  std::vector<int> perm(n);
  int ok = cholmod_camd(A, nullptr, 0, member.data(), perm.data(), &F.common);
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
  F.slotOf.clear(); F.posOf.clear(); F.valOf.clear(); F.dofOf.clear();
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

void requireFactor(const char *who) {
  if (!F.L)
    ExecError(std::string("contactkernel: ") + who + " without a successful contactKernelFactorize");
}

long delassus(KN<double> *const &pW, KNM<double> *const &pDw) {
  requireFactor("contactKernelDelassus");
  KN<double> &W = *pW;
  if (W.N() != F.nc) ExecError("contactKernelDelassus: W must have one entry per row of C");
  F.weight.assign(W.N(), 0.);
  for (int j = 0; j < F.nc; j++) F.weight[j] = W[j];
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
  for (int j = 0; j < nc; j++) for (int i = 0; i < nc; i++) F.Dw[i + (size_t)j * nc] = D[i + (size_t)j * nc] * F.weight[j];
  KNM<double> &Dw = *pDw;
  Dw.resize(nc, nc);
  for (int j = 0; j < nc; j++) for (int i = 0; i < nc; i++) Dw(i, j) = F.Dw[i + (size_t)j * nc];
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
  return 0;
}

long finish(KN<double> *const &pm, KN<double> *const &pv) {
  requireFactor("contactKernelFinish");
  if (!F.haveForward) ExecError("contactKernelFinish: call contactKernelFree first");
  if (F.weight.empty()) ExecError("contactKernelFinish: call contactKernelDelassus first");
  KN<double> &m = *pm, &v = *pv;
  if (m.N() != F.nc) ExecError("contactKernelFinish: one multiplier per slot expected");
  if (v.N() != F.n) v.resize(F.n);
  const int nt = F.nt, inc = 1;
  // the contact load changes the trailing block of z only: z_C -= L_CC^-1 (P C' W m)_C
  std::vector<double> load(nt, 0.);
  for (size_t k = 0; k < F.slotOf.size(); k++) load[F.posOf[k]] += F.valOf[k] * F.weight[F.slotOf[k]] * m[F.slotOf[k]];
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
static double *contiguous(KN<double> &a, const char *what) {
  if (a.N() > 1 && a.step != 1) ExecError(what);
  return a.N() > 0 ? &a[0] : nullptr;
}

// ---------------------------------------------------------------- products with M, A, B
// The three matrices of the energy terms share one sparsity pattern (P1 on one mesh): kept
// as one CSR structure with three values per entry, so that M v, A v and B v cost one pass.
struct Products {
  int n = 0;
  std::vector<int> start, column;
  std::vector<double> values;       // 3 per entry: M, A, B

  // Mx, Ax, Bx for x (all of size n)
  void apply(const double *x, double *mx, double *ax, double *bx) const {
    const double *val = values.data();
    const int *col = column.data();
    for (int i = 0; i < n; i++) {
      double m = 0, a = 0, b = 0;
      for (int e = start[i]; e < start[i + 1]; e++) {
        const double xj = x[col[e]];
        m += val[3 * e] * xj; a += val[3 * e + 1] * xj; b += val[3 * e + 2] * xj;
      }
      mx[i] = m; ax[i] = a; bx[i] = b;
    }
  }
};
Products P3;

long products(Matrice_Creuse<double> *const &pM, Matrice_Creuse<double> *const &pA, Matrice_Creuse<double> *const &pB) {
  MatriceMorse<double> *mats[3] = {morse(pM), morse(pA), morse(pB)};
  const int n = mats[0]->n;
  for (int k = 0; k < 3; k++)
    if (mats[k]->n != n || mats[k]->m != n || mats[k]->half)
      ExecError("contactKernelProducts: M, A, B must be square, of one size, stored in full (not sym)");
  // the union of the three patterns, row by row, with the values of each matrix
  std::vector<std::pair<long long, double>> entries[3];
  for (int k = 0; k < 3; k++) {
    mats[k]->COO();
    entries[k].reserve(mats[k]->nnz);
    for (size_t e = 0; e < mats[k]->nnz; e++)
      entries[k].push_back({(long long)mats[k]->i[e] * n + mats[k]->j[e], mats[k]->aij[e]});
    std::sort(entries[k].begin(), entries[k].end());
  }
  std::vector<long long> keys;
  for (int k = 0; k < 3; k++) for (auto &e : entries[k]) keys.push_back(e.first);
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  P3.n = n;
  P3.start.assign(n + 1, 0);
  P3.column.resize(keys.size());
  P3.values.assign(3 * keys.size(), 0.);
  for (size_t e = 0; e < keys.size(); e++) { P3.start[keys[e] / n + 1]++; P3.column[e] = keys[e] % n; }
  for (int i = 0; i < n; i++) P3.start[i + 1] += P3.start[i];
  for (int k = 0; k < 3; k++)
    for (auto &e : entries[k]) {
      size_t pos = std::lower_bound(keys.begin(), keys.end(), e.first) - keys.begin();
      P3.values[3 * pos + k] += e.second;
    }
  return 0;
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

// ---------------------------------------------------------------- the record of a step
// What history.txt and contact_history.txt keep of a step, computed in one call: the terms
// of the discrete energy balance (DESIGN.md section 5) and the nodal quantities on Gamma3.
// The script version, and the definitions, are in edp/solve.edp (-kernel script) and
// nodalState in edp/lib/contact.idp; the tests compare the two.
struct Record {
  std::vector<double> f, nodeX, nodeW;  // unit traction; contact nodes sorted by x, weights
  std::vector<int> normalSlot, tangentSlot;
  double g = 0, none = 1e300;
  std::vector<double> Mv, Av, Bv;       // workspace
  double energyOld = 0;                 // kinetic + elastic of the previous step
  long generation = -1;                 // the factor (F.generation) the slots belong to
  bool ready = false;
};
Record RC;

long recordSetup(KN<double> *const &pf, KN<double> *const &px, KN<double> *const &pw,
                 KN<long> *const &pns, KN<long> *const &pts, KN<double> *const &pp) {
  KN<double> &f = *pf, &x = *px, &w = *pw, &p = *pp;
  KN<long> &ns = *pns, &ts = *pts;
  const int nn = x.N();
  if (w.N() != nn || ns.N() != nn || ts.N() != nn || p.N() != 2) ExecError("contactKernelRecordSetup: wrong argument sizes");
  if (!F.L || F.weight.empty()) ExecError("contactKernelRecordSetup: call contactKernelFactorize and contactKernelDelassus first");
  for (int i = 0; i < nn; i++)
    if (ns[i] < -1 || ns[i] >= F.nc || ts[i] < -1 || ts[i] >= F.nc)
      ExecError("contactKernelRecordSetup: a slot number is outside -1 .. (rows of C) - 1");
  RC.f.assign(f.N(), 0.);
  for (int i = 0; i < f.N(); i++) RC.f[i] = f[i];
  RC.nodeX.resize(nn); RC.nodeW.resize(nn); RC.normalSlot.resize(nn); RC.tangentSlot.resize(nn);
  for (int i = 0; i < nn; i++) { RC.nodeX[i] = x[i]; RC.nodeW[i] = w[i]; RC.normalSlot[i] = ns[i]; RC.tangentSlot[i] = ts[i]; }
  RC.g = p[0]; RC.none = p[1];
  RC.energyOld = 0;                     // u_0 = v_0 = 0
  RC.generation = F.generation;
  RC.ready = true;
  return 0;
}

// In: v = v_n, vOld = v_{n-1}, u = u_n, Lam (total contact stress per slot), Mv = M v_{n-1},
// Bu = B u_{n-1}, record[0] = k, record[1] = the load factor of f_n (load * t).
// Out: Mv = M v_n and Bu = B u_n (for the next right-hand side) and record = [kinetic,
// elastic, numerical_dissipation, viscous_dissipation, contact_dissipation, external_work,
// energy_residual, kinetic_jump, elastic_jump, normal_force, tangential_force, the five zone
// counts, x_B, x_C] (the columns of history.txt and contact_history.txt). The balance uses
// kinetic + elastic of the previous call (0 after contactKernelRecordSetup: u_0 = v_0 = 0).
long stepRecord(KN<double> *const &pv, KN<double> *const &pvOld, KN<double> *const &pu, KN<double> *const &pLam,
                KN<double> *const &pMv, KN<double> *const &pBu, KN<double> *const &prec) {
  if (P3.n == 0 || !RC.ready || !F.L || RC.generation != F.generation)
    ExecError("contactKernelRecord: call contactKernelProducts, contactKernelDelassus and contactKernelRecordSetup (after the last contactKernelFactorize) first");
  KN<double> &v = *pv, &vOld = *pvOld, &u = *pu, &Lam = *pLam, &Mv = *pMv, &Bu = *pBu, &rec = *prec;
  const int n = P3.n;
  if (v.N() != n || vOld.N() != n || u.N() != n || (int)RC.f.size() != n || Lam.N() != F.nc || rec.N() < 2)
    ExecError("contactKernelRecord: wrong argument sizes");
  const double k = rec[0], loadFactor = rec[1];
  if (Mv.N() != n || Bu.N() != n) ExecError("contactKernelRecord: wrong size of Mv or Bu");
  // three products in one pass; as in the script version, M (v_n - v_{n-1}) = M v_n - M v_{n-1}
  // and B u_n = B u_{n-1} + k B v_n (u_n = u_{n-1} + k v_n), so no product with vOld or u
  const char *strided = "contactKernelRecord: arrays must be contiguous";
  const double *pv0 = contiguous(v, strided), *pvOld0 = contiguous(vOld, strided), *pu0 = contiguous(u, strided);
  double *pMv0 = contiguous(Mv, strided), *pBu0 = contiguous(Bu, strided);
  const double *f = RC.f.data();
  std::vector<double> &m = RC.Mv, &a = RC.Av, &b = RC.Bv;
  m.resize(n); a.resize(n); b.resize(n);
  P3.apply(pv0, m.data(), a.data(), b.data());
  double vMv = 0, vAv = 0, vBv = 0, dvMdv = 0, uBu = 0, fv = 0;
  for (int i = 0; i < n; i++) {
    const double vi = pv0[i], bu = pBu0[i] + k * b[i];
    vMv += vi * m[i]; vAv += vi * a[i]; vBv += vi * b[i]; dvMdv += (vi - pvOld0[i]) * (m[i] - pMv0[i]);
    uBu += pu0[i] * bu;
    fv += f[i] * vi;
    pMv0[i] = m[i]; pBu0[i] = bu;
  }
  // slot velocities C v, and the contact term (C' W Lambda)' v
  std::vector<double> cv(F.nc, 0.);
  for (size_t e = 0; e < F.slotOf.size(); e++) cv[F.slotOf[e]] += F.valOf[e] * pv0[F.dofOf[e]];
  double contact = 0;
  for (int j = 0; j < F.nc; j++) contact += F.weight[j] * Lam[j] * cv[j];
  if (rec.N() != 18) rec.resize(18);
  const double kinetic = 0.5 * vMv, elastic = 0.5 * uBu, kineticJump = 0.5 * dvMdv, elasticJump = 0.5 * k * k * vBv;
  const double viscous = k * vAv, contactWork = k * contact, external = k * loadFactor * fv;
  const double numerical = kineticJump + elasticJump;
  // the balance, as in edp/solve.edp
  const double balance = kinetic + elastic - RC.energyOld + numerical + viscous + contactWork - external;
  const double largest = std::max({std::fabs(kinetic), std::fabs(elastic), std::fabs(RC.energyOld), numerical,
                                   viscous, std::fabs(contactWork), std::fabs(external)});
  RC.energyOld = kinetic + elastic;
  rec[0] = kinetic; rec[1] = elastic; rec[2] = numerical; rec[3] = viscous; rec[4] = contactWork;
  rec[5] = external; rec[6] = largest > 0 ? std::fabs(balance) / largest : 0.; rec[7] = kineticJump;
  rec[8] = elasticJump;
  // nodal quantities: the statuses and zones of nodalState (edp/lib/contact.idp)
  double normalForce = 0, tangentialForce = 0, xB = RC.none, xC = RC.none;
  long zones[5] = {0, 0, 0, 0, 0};
  for (size_t i = 0; i < RC.nodeX.size(); i++) {
    int sn = RC.normalSlot[i], st = RC.tangentSlot[i];
    double vn = sn >= 0 ? cv[sn] : 0., vt = st >= 0 ? cv[st] : 0.;
    double pn = sn >= 0 ? Lam[sn] : 0., lt = st >= 0 ? Lam[st] : 0.;
    int normalStatus = vn <= 0 ? 0 : (vn >= RC.g * (1 - 1e-6) ? 2 : 1);
    int tangentStatus = std::fabs(vt) <= 1e-6 * RC.g ? 0 : 1;
    zones[normalStatus > 0 ? 2 * normalStatus - tangentStatus : 0]++;
    if (normalStatus == 2) xB = std::min(xB, RC.nodeX[i]);
    if (normalStatus > 0 && tangentStatus == 0) xC = std::min(xC, RC.nodeX[i]);
    normalForce += RC.nodeW[i] * pn;
    tangentialForce += RC.nodeW[i] * lt;
  }
  rec[9] = normalForce; rec[10] = tangentialForce;
  for (int z = 0; z < 5; z++) rec[11 + z] = zones[z];
  rec[16] = xB; rec[17] = xC;
  return std::isfinite(balance) ? 0 : 1;
}

// ---------------------------------------------------------------- the nodal laws and Newton
// Same pieces, relations, residual and safeguards as edp/lib/contact.idp (classifyContact,
// contactRelations, solveContactCondensed); see the comments there.
struct Laws {
  int nc = 0;
  std::vector<int> isNormal, partner;          // partner: normal slot of a tangential slot, -1 none
  std::vector<double> damping, r, rDefault, threshold, residualWeight;
  double cnu = 0, g = 0, mu = 0, eps = 0, forceScale = 1, tol = 0;
  int penalty = 0, literal = 0, maxit = 0, safeguards = 1;
  double pieceA[5], pieceD[5], pieceH[5], kappa = 0;
  std::vector<double> keyWeight;
  // state of an iterate
  std::vector<double> stress, yv, bound, target, mismatch;
  std::vector<int> piece, key;
  // relations
  std::vector<double> velocityCoef, stressCoef, relationRhs;
  std::vector<int> velocitySlot;
  // The Newton matrix N, row j = -velocityCoef[j] Dw(velocitySlot[j], :) + stressCoef[j] e_j'.
  // A base matrix N0 (rows baseA, baseD, baseS) is LU-factorized; the matrix of other
  // pieces differs from N0 in a few rows R only (the pieces that changed), so it is solved
  // with N0's factors and a rank-|R| (Woodbury) correction: N = N0 + E_R Delta,
  //   N^-1 b = x0 - Y K^-1 Delta x0,  x0 = N0^-1 b,  Y = N0^-1 E_R,  K = I + Delta Y.
  // N0 is re-factorized when |R| exceeds nc/8 (the correction would cost more than a
  // quarter of a factorization), or when a corrected solve fails its residual check.
  std::vector<double> N0, Y, Delta, K;
  std::vector<int> pivots, Kpivots, newtonKey, changed, baseS;
  std::vector<double> baseA, baseD;
  bool haveBase = false;
  long cuts = 0, halvings = 0, factorizations = 0, corrections = 0;
  long generation = -1;                        // the factor (F.generation) these laws belong to
  bool ready = false;

  void setAugmentation(int j, double rj) {
    r[j] = rj;
    threshold[j] = (cnu + rj) * g;
    residualWeight[j] = std::max(1. / forceScale, 1. / (rj * g));
  }
  double merit() const {
    double s = 0;
    for (int j = 0; j < nc; j++) s += mismatch[j] * mismatch[j];
    return std::sqrt(s);
  }
  // pieces, targets and the weighted natural residual (max norm) at (c, m)
  double classify(const double *c, const double *m) {
    double worst = 0;
    for (int j = 0; j < nc; j++) {
      stress[j] = damping[j] * c[j] + m[j];
      yv[j] = r[j] * c[j] + stress[j];
      bound[j] = partner[j] >= 0 ? mu * cnu * std::max(c[partner[j]], 0.) : 0.;
      double y = yv[j];
      int p;
      if (isNormal[j]) p = y <= 0 ? 0 : (y < threshold[j] ? 1 : 2);
      else p = (bound[j] > 0 && std::fabs(y) <= bound[j]) ? 3 : 4;
      piece[j] = p;
      key[j] = 4 * p + (p == 4 ? 2 * (y > 0) + (bound[j] > 0) : 0);
      double t;
      if (p == 0) t = 0.;
      else if (p == 1) t = cnu * y / (cnu + r[j]);
      else if (p != 2) t = std::max(-bound[j], std::min(bound[j], y));
      else t = penalty ? (kappa * y - r[j] * g / eps) / (kappa + r[j]) : y - r[j] * g;
      target[j] = t;
      mismatch[j] = (stress[j] - t) * residualWeight[j];
      worst = std::max(worst, std::fabs(mismatch[j]));
      if (std::isnan(mismatch[j])) worst = mismatch[j];
    }
    return worst;
  }
  void relations() {
    for (int j = 0; j < nc; j++) {
      int p = piece[j];
      velocityCoef[j] = p == 4 ? -mu * cnu * (key[j] % 2) * (yv[j] > 0 ? 1. : -1.) : pieceA[p];
      stressCoef[j] = pieceD[p];
      relationRhs[j] = pieceH[p];
      velocitySlot[j] = p == 4 && partner[j] >= 0 ? partner[j] : j;
    }
  }
};
Laws Q;

long laws(KN<long> *const &pkind, KN<long> *const &ppartner, KN<double> *const &pr, KN<double> *const &pp) {
  KN<long> &kind = *pkind, &partner = *ppartner;
  KN<double> &r = *pr, &p = *pp;
  const int nc = kind.N();
  if (partner.N() != nc || r.N() != nc || p.N() != 10) ExecError("contactKernelLaws: wrong argument sizes");
  if (!F.L || nc != F.nc || (int)F.Dw.size() != nc * nc)
    ExecError("contactKernelLaws: call contactKernelFactorize and contactKernelDelassus first (same slots)");
  for (int j = 0; j < nc; j++)
    if ((kind[j] != 0 && kind[j] != 1) || (kind[j] == 1 && (partner[j] < -1 || partner[j] >= nc || (partner[j] >= 0 && kind[partner[j]] != 0))))
      ExecError("contactKernelLaws: kind must be 0 or 1, partner a normal slot (or -1)");
  Q = Laws();
  Q.nc = nc;
  Q.generation = F.generation;
  Q.cnu = p[0]; Q.g = p[1]; Q.mu = p[2]; Q.eps = p[3]; Q.penalty = p[4] != 0; Q.literal = p[5] != 0;
  Q.tol = p[6]; Q.maxit = (int)p[7]; Q.safeguards = p[8] != 0; Q.forceScale = p[9];
  Q.isNormal.resize(nc); Q.partner.resize(nc); Q.damping.resize(nc);
  Q.r.resize(nc); Q.rDefault.resize(nc); Q.threshold.resize(nc); Q.residualWeight.resize(nc);
  for (int j = 0; j < nc; j++) {
    Q.isNormal[j] = kind[j] == 0;
    Q.partner[j] = kind[j] == 0 ? -1 : (int)partner[j];
    Q.damping[j] = kind[j] == 0 ? Q.cnu : 0.;
    Q.setAugmentation(j, r[j]);
  }
  Q.rDefault = Q.r;
  const double pa[5] = {Q.cnu, 0., 1., 1., 0.};
  const double pd[5] = {1., 1., Q.penalty ? -Q.eps : 0., 0., 1.};
  const double ph[5] = {0., 0., Q.g, 0., 0.};
  std::copy(pa, pa + 5, Q.pieceA); std::copy(pd, pd + 5, Q.pieceD); std::copy(ph, ph + 5, Q.pieceH);
  if (Q.penalty && Q.literal) { Q.pieceA[2] = -1. / Q.eps; Q.pieceD[2] = 1.; Q.pieceH[2] = -Q.g / Q.eps; }
  Q.kappa = Q.cnu + 1. / Q.eps;
  Q.keyWeight.resize(nc);
  for (int j = 0; j < nc; j++) Q.keyWeight[j] = 1. + ((7919 * j + 104729) % 1009);
  Q.stress.resize(nc); Q.yv.resize(nc); Q.bound.resize(nc); Q.target.resize(nc); Q.mismatch.resize(nc);
  Q.piece.resize(nc); Q.key.resize(nc);
  Q.velocityCoef.resize(nc); Q.stressCoef.resize(nc); Q.relationRhs.resize(nc); Q.velocitySlot.resize(nc);
  Q.pivots.resize(nc); Q.newtonKey.assign(nc, -1);
  Q.ready = true;
  return 0;
}

// c = cFree - Dw m
void velocities(const double *cFree, const double *m, double *c) {
  const int nc = Q.nc, inc = 1;
  const double minusOne = -1., one = 1.;
  std::copy(cFree, cFree + nc, c);
  dgemv_("N", &nc, &nc, &minusOne, F.Dw.data(), &nc, m, &inc, &one, c, &inc);
}

// LU of N0 = the Newton matrix of the current relations
bool newtonFactorBase() {
  const int nc = Q.nc;
  Q.N0.assign((size_t)nc * nc, 0.);
  for (int jj = 0; jj < nc; jj++)           // column jj: row j uses Dw(velocitySlot[j], jj)
    for (int j = 0; j < nc; j++)
      Q.N0[j + (size_t)jj * nc] = -Q.velocityCoef[j] * F.Dw[Q.velocitySlot[j] + (size_t)jj * nc];
  for (int j = 0; j < nc; j++) Q.N0[j + (size_t)j * nc] += Q.stressCoef[j];
  int info = 0;
  dgetrf_(&nc, &nc, Q.N0.data(), &nc, Q.pivots.data(), &info);
  Q.factorizations++;
  Q.haveBase = info == 0;
  Q.changed.clear();
  Q.baseA = Q.velocityCoef; Q.baseD = Q.stressCoef; Q.baseS = Q.velocitySlot;
  Q.newtonKey = Q.key;
  if (!Q.haveBase) Q.newtonKey.assign(nc, -1);
  return Q.haveBase;
}

// Prepare the solves with the Newton matrix of the current pieces (Q.key).
bool newtonPrepare() {
  const int nc = Q.nc;
  if (!Q.haveBase) return newtonFactorBase();
  std::vector<int> R;
  for (int j = 0; j < nc; j++)
    if (Q.velocityCoef[j] != Q.baseA[j] || Q.stressCoef[j] != Q.baseD[j] || Q.velocitySlot[j] != Q.baseS[j]) R.push_back(j);
  const int r = R.size();
  if (r > nc / 8) return newtonFactorBase();
  Q.changed = R;
  Q.newtonKey = Q.key;
  if (r == 0) return true;
  // Delta (r x nc): the changed rows of N minus those of N0
  Q.Delta.assign((size_t)r * nc, 0.);
  for (int k = 0; k < r; k++) {
    int j = R[k];
    for (int i = 0; i < nc; i++)
      Q.Delta[k + (size_t)i * r] = -Q.velocityCoef[j] * F.Dw[Q.velocitySlot[j] + (size_t)i * nc]
                                 + Q.baseA[j] * F.Dw[Q.baseS[j] + (size_t)i * nc];
    Q.Delta[k + (size_t)j * r] += Q.stressCoef[j] - Q.baseD[j];
  }
  // Y = N0^-1 E_R, K = I + Delta Y
  Q.Y.assign((size_t)nc * r, 0.);
  for (int k = 0; k < r; k++) Q.Y[R[k] + (size_t)k * nc] = 1.;
  int info = 0;
  dgetrs_("N", &nc, &r, Q.N0.data(), &nc, Q.pivots.data(), Q.Y.data(), &nc, &info);
  Q.K.assign((size_t)r * r, 0.);
  for (int k = 0; k < r; k++) Q.K[k + (size_t)k * r] = 1.;
  const double one = 1.;
  dgemm_("N", "N", &r, &r, &nc, &one, Q.Delta.data(), &r, Q.Y.data(), &nc, &one, Q.K.data(), &r);
  Q.Kpivots.resize(r);
  dgetrf_(&r, &r, Q.K.data(), &r, Q.Kpivots.data(), &info);
  if (info != 0) return newtonFactorBase();
  Q.corrections++;
  return true;
}

// x = N^-1 b with N0's factors and the correction; the corrected solve is checked by its
// residual, row by row, against the size of the row's terms (falls back to a factorization).
bool newtonSolve(const double *b, double *x) {
  const int nc = Q.nc, one = 1, inc = 1;
  int info = 0;
  std::copy(b, b + nc, x);
  dgetrs_("N", &nc, &one, Q.N0.data(), &nc, Q.pivots.data(), x, &nc, &info);
  const int r = Q.changed.size();
  if (r == 0) return info == 0;
  std::vector<double> t(r, 0.), Dx(nc, 0.);
  const double plus = 1., minus = -1., zero = 0.;
  dgemv_("N", &r, &nc, &plus, Q.Delta.data(), &r, x, &inc, &zero, t.data(), &inc);
  dgetrs_("N", &r, &one, Q.K.data(), &r, Q.Kpivots.data(), t.data(), &r, &info);
  dgemv_("N", &nc, &r, &minus, Q.Y.data(), &nc, t.data(), &inc, &plus, x, &inc);
  dgemv_("N", &nc, &nc, &plus, F.Dw.data(), &nc, x, &inc, &zero, Dx.data(), &inc);
  for (int j = 0; j < nc; j++) {
    double a = -Q.velocityCoef[j] * Dx[Q.velocitySlot[j]], d = Q.stressCoef[j] * x[j];
    double scale = std::fabs(b[j]) + std::fabs(a) + std::fabs(d);
    if (!(std::fabs(a + d - b[j]) <= 1e-11 * scale)) {
      if (!newtonFactorBase()) return false;
      std::copy(b, b + nc, x);
      dgetrs_("N", &nc, &one, Q.N0.data(), &nc, Q.pivots.data(), x, &nc, &info);
      return info == 0;
    }
  }
  return true;
}

long newton(KN<double> *const &pcFree, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  if (!Q.ready) ExecError("contactKernelNewton: call contactKernelLaws first");
  if (!F.L || Q.generation != F.generation || (int)F.Dw.size() != Q.nc * Q.nc)
    ExecError("contactKernelNewton: the factor changed since contactKernelLaws; call contactKernelDelassus and contactKernelLaws again");
  const int nc = Q.nc, one = 1;
  KN<double> &cFreeK = *pcFree, &cK = *pc, &mK = *pm, &info = *pinfo;
  if (cFreeK.N() != nc || cK.N() != nc || mK.N() != nc) ExecError("contactKernelNewton: one value per slot expected");
  std::vector<double> cFree(nc), c(nc), m(nc), cStart(nc), previous(nc), newtonM(nc), rhs(nc), d(nc);
  for (int j = 0; j < nc; j++) { cFree[j] = cFreeK[j]; c[j] = cK[j]; m[j] = mK[j]; }
  std::vector<double> seen(Q.maxit + 1, -1.);
  // merit at the previous stresses with this step's cFree; first pieces from the previous solution
  velocities(cFree.data(), m.data(), cStart.data());
  Q.classify(cStart.data(), m.data());
  double merit = Q.merit();
  Q.classify(c.data(), m.data());
  double residual = 0;
  int it = 0;
  while (true) {
    Q.relations();
    // cycle guard: the fingerprint of the pieces; a repeat within the step halves r
    double fingerprint = 0;
    for (int j = 0; j < nc; j++) fingerprint += Q.key[j] * Q.keyWeight[j];
    if (Q.safeguards)
      for (int k = 0; k < it; k++)
        if (seen[k] == fingerprint) {
          for (int j = 0; j < nc; j++) Q.setAugmentation(j, 0.5 * Q.r[j]);
          Q.halvings++;
          std::fill(seen.begin(), seen.end(), -1.);
          break;
        }
    seen[it] = fingerprint;
    if (Q.key != Q.newtonKey && !newtonPrepare()) { residual = NAN; break; }
    for (int j = 0; j < nc; j++) rhs[j] = Q.relationRhs[j] - Q.velocityCoef[j] * cFree[Q.velocitySlot[j]];
    previous = m;
    if (!newtonSolve(rhs.data(), newtonM.data())) { residual = NAN; break; }
    for (int j = 0; j < nc; j++) d[j] = newtonM[j] - previous[j];
    double step = 1;
    for (int cut = 0; cut <= 10; cut++) {
      for (int j = 0; j < nc; j++) m[j] = previous[j] + step * d[j];
      velocities(cFree.data(), m.data(), c.data());
      residual = Q.classify(c.data(), m.data());
      if (!Q.safeguards || Q.merit() < (1 - 1e-4 * step) * merit || residual <= Q.tol || cut == 10) break;
      step *= 0.5;
      Q.cuts++;
    }
    merit = Q.merit();
    it++;
    if (residual <= Q.tol || it >= Q.maxit || std::isnan(residual) || std::isinf(residual)) break;
  }
  if (Q.r != Q.rDefault) for (int j = 0; j < nc; j++) Q.setAugmentation(j, Q.rDefault[j]);
  for (int j = 0; j < nc; j++) { cK[j] = c[j]; mK[j] = m[j]; }
  if (info.N() != 6) info.resize(6);
  info[0] = residual; info[1] = it; info[2] = Q.cuts; info[3] = Q.halvings; info[4] = Q.factorizations;
  info[5] = Q.corrections;
  return residual <= Q.tol ? it : -1;
}

}  // namespace

static void Load_Init() {
  Global.Add("contactKernelFactorize", "(", new OneOperator2_<long, Matrice_Creuse<double> *, Matrice_Creuse<double> *>(factorize));
  Global.Add("contactKernelDelassus", "(", new OneOperator2_<long, KN<double> *, KNM<double> *>(delassus));
  Global.Add("contactKernelSolve", "(", new OneOperator2_<long, KN<double> *, KN<double> *>(solve));
  Global.Add("contactKernelFree", "(", new OneOperator2_<long, KN<double> *, KN<double> *>(freeVelocity));
  Global.Add("contactKernelFinish", "(", new OneOperator2_<long, KN<double> *, KN<double> *>(finish));
  Global.Add("contactKernelProducts", "(", new OneOperator3_<long, Matrice_Creuse<double> *, Matrice_Creuse<double> *, Matrice_Creuse<double> *>(products));
  Global.Add("contactKernelMultiply", "(", new OneOperator4_<long, KN<double> *, KN<double> *, KN<double> *, KN<double> *>(multiply));
  Global.Add("contactKernelRecordSetup", "(", new OneOperator6_<long, KN<double> *, KN<double> *, KN<double> *, KN<long> *, KN<long> *, KN<double> *>(recordSetup));
  Global.Add("contactKernelRecord", "(", new OneOperator7_<long, KN<double> *, KN<double> *, KN<double> *, KN<double> *, KN<double> *, KN<double> *, KN<double> *>(stepRecord));
  Global.Add("contactKernelLaws", "(", new OneOperator4_<long, KN<long> *, KN<long> *, KN<double> *, KN<double> *>(laws));
  Global.Add("contactKernelNewton", "(", new OneOperator4_<long, KN<double> *, KN<double> *, KN<double> *, KN<double> *>(newton));
}

LOADFUNC(Load_Init)
