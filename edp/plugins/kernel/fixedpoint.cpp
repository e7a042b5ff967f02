// fixedpoint.cpp: the fixed point of a step (-solver fixedpoint), and the fixed-point
// iteration Newton's safeguard falls back on.
//
// Projected Gauss-Seidel over the slots (nonsmooth Gauss-Seidel): each slot in turn solves its
// own law exactly, with the other slots' multipliers held. With c = cFree - Dw m, a change of
// m_j moves c_j by -Dw_jj times it, so y = Lambda_j + rho_j c_j with rho_j = 1/Dw_jj - Kn_j
// equals m_j + c_j/Dw_jj whatever m_j is: the law's piece at y (Slots::resolve, with the local
// augmentation rho_j) gives the slot's new stress and velocity at once; a 3D node's tangential
// pair is solved together, on the disk (Slots::diskUpdate). A tangential slot reads its normal
// partner's current velocity for its bound. No parameter to tune: rho_j is exact.
// The map G of one iteration is a forward sweep then a backward one (symmetric Gauss-Seidel);
// contactKernelFixedPoint accelerates it (Anderson), and Newton falls back on it.
//
// Two levels (2D): a body that holds a motion by its mass alone (the half disk of
// docs/stability.md, "Hard bodies") gives Dw one eigenvalue thousands of times the next; every
// slot's Dw_jj is then that motion's, and the sweeps crawl. When the largest gap between the
// top eigenvalues of Dw (made symmetric by the weights) exceeds coarseGap, the K modes above it
// are split off: Dw = D' + sum_k delta_k P_k Q_k', D' keeping them at the first eigenvalue below
// the gap. The sweeps run on D' with the modes' velocity a held (c = cFree - P a - D' m); after
// each iteration a Newton step on the K equations a = delta Q'm, whose Jacobian is the
// linearized response of every slot's relation (the law's relations(), as Newton's; its LU
// kept while the relations repeat), moves a and m together, shortened until the natural
// residual falls.
// In 3D (the disk) that coarse step did not converge on the twisted and sloped blocks: the
// sweeps with a held go to the solution at that a, which is steep in a. There, with one mode
// split off, each half-sweep on D' takes the a with which it ends consistent, a = delta Q'm
// after it (a scalar root, found by secant steps; consistentStep): a splitting of Dw that
// converges whatever delta (docs/stability.md, "The fixed point on hard bodies"). A thin
// plate's bending gives Dw a few more modes far above the bulk of its spectrum (no gap between
// them): with the mode above the gap, those above coarseGap^2 times the median eigenvalue are
// split off too, and the root is then one in K unknowns (consistentRoots: Broyden).
#include <algorithm>
#include <cfloat>
#include <cmath>
#include "blas.hpp"
#include "kernel.hpp"



namespace contactkernel {
namespace {

void fixedPointPrepare(Kernel &k) {
  FixedPointState &fixedPoint = k.fixedPoint;
  const Factorization &factor = k.factor;
  if (fixedPoint.generation == factor.delassusGeneration) return;
  const int nc = factor.nc;
  fixedPoint.rho.assign(nc, 0.);
  for (int j = 0; j < nc; j++) {
    const double djj = factor.Dw[j + (size_t)j * nc];
    // Dw_jj Kn_j < 1 (S holds W Kn C'C): the floor only guards round-off
    fixedPoint.rho[j] = std::max(1. / djj - k.law.Kn[j], 1e-3 / djj);
  }
  fixedPoint.generation = factor.delassusGeneration;
}

// A 3D node's tangential pair (j, q) in one update: b = c_tau + D m_tau with the pair's block of
// D (Dw, or D' of the two levels), the disk's exact local solve (Slots::diskUpdate), then c
// follows m.
void fixedPointDisk(Kernel &k, int j, int q, double *c, double *m, const double *D) {
  const int nc = k.factor.nc, inc = 1;
  const double Djj = D[j + (size_t)j * nc], Djq = D[j + (size_t)q * nc];
  const double Dqj = D[q + (size_t)j * nc], Dqq = D[q + (size_t)q * nc];
  const double bj = c[j] + Djj * m[j] + Djq * m[q], bq = c[q] + Dqj * m[j] + Dqq * m[q];
  double mj = 0, mq = 0;
  k.law.diskUpdate(j, Djj, Djq, Dqj, Dqq, bj, bq, c, mj, mq);
  const double omega = k.fixedPoint.omega;
  const double deltaJ = omega * (mj - m[j]), deltaQ = omega * (mq - m[q]);
  m[j] += deltaJ; m[q] += deltaQ;
  const double minusJ = -deltaJ, minusQ = -deltaQ;
  if (deltaJ != 0) daxpy_(&nc, &minusJ, D + (size_t)j * nc, &inc, c, &inc);
  if (deltaQ != 0) daxpy_(&nc, &minusQ, D + (size_t)q * nc, &inc, c, &inc);
}

// one sweep over the slots, forward or backward, on Dw (or, two levels, on D' with its own
// local augmentations); c = cFree - D m follows m
void fixedPointSweep(Kernel &k, bool forward, double *c, double *m, const double *D = nullptr, const double *rho = nullptr) {
  const Factorization &factor = k.factor;
  FixedPointState &fixedPoint = k.fixedPoint;
  const contactlaw::Slots &law = k.law;
  const int nc = factor.nc, inc = 1;
  if (!D) { D = factor.Dw.data(); rho = fixedPoint.rho.data(); }
  for (int step = 0; step < nc; step++) {
    const int j = forward ? step : nc - 1 - step;
    const int q = law.pair[j];
    if (q >= 0) {                                    // a 3D pair, at the first of its two slots
      if (forward ? q > j : q < j) fixedPointDisk(k, j, q, c, m, D);
      continue;
    }
    const double *column = D + (size_t)j * nc;
    const double y = m[j] + c[j] / column[j];
    double t = 0, v = 0;
    law.resolve(j, y, rho[j], c, t, v);
    const double cj = (y - t) / rho[j];
    const double delta = fixedPoint.omega * (t - law.Kn[j] * cj - m[j]);
    if (delta == 0) continue;
    m[j] += delta;
    const double minus = -delta;
    daxpy_(&nc, &minus, column, &inc, c, &inc);
  }
  fixedPoint.sweeps++;
}


// The start of a step of every fixed point: the convergence test at the operator's scale, as
// Newton's (referenceEvaluate: the augmentations rReference; the user's kept for
// fixedPointFinish), the velocities of the first iterate m, its natural residual (logged as
// iteration 0) and whether it already passes
struct FixedPointStart {
  std::vector<double> userR, cFree, c, m;
  double residual = 0;
  int unresolved = 0;
  bool done = false;
  FixedPointStart(Kernel &k, const double *cFreeIn, const double *mIn) {
    const int nc = k.factor.nc;
    contactlaw::Slots &law = k.law;
    userR = law.r;
    for (int j = 0; j < nc; j++) law.setAugmentation(j, k.factor.rReference[j]);
    cFree.assign(cFreeIn, cFreeIn + nc); m.assign(mIn, mIn + nc); c.assign(nc, 0.);
    roundoffScale(k, cFree.data(), m.data());
    velocities(k, cFree.data(), m.data(), c.data());
    residual = law.evaluate(c.data(), m.data());
    logIteration(k, 0, residual);
    done = stepConverged(k, residual, c.data(), unresolved);
  }
};

// The end of a step of either fixed point: the user's augmentations back, c and m out, the
// solver's info; the iterations, or -1 if the step did not converge
long fixedPointFinish(Kernel &k, const std::vector<double> &userR, const std::vector<double> &c, const std::vector<double> &m,
                      double residual, int it, int unresolved, bool stalled, bool done, double *cInOut, double *mInOut,
                      double info[solverInfoColumnCount]) {
  for (int j = 0; j < k.factor.nc; j++) k.law.setAugmentation(j, userR[j]);
  std::copy(c.begin(), c.end(), cInOut);
  std::copy(m.begin(), m.end(), mInOut);
  info[InfoResidual] = residual; info[InfoIterations] = it; info[InfoUnresolved] = unresolved; info[InfoStalled] = stalled;
  return done ? it : -1;
}

// Anderson acceleration of a map G of m (its window: FixedPointState::window): after an
// iteration x -> m = G(x) (c its velocities, residual its natural residual), the iterate that
// mixes the last window iterates to minimise G(m) - m, kept only when its natural residual is
// not above G's (else G's iterate is kept and the history restarts). Returns whether the mixed
// iterate was kept (c, m and residual are then its own).
struct Anderson {
  int window, nc, stored = 0, head = 0;
  bool havePrev = false;
  std::vector<double> dX, dF, xPrev, fPrev, f, gm, gc;
  Anderson(int window, int nc)
    : window(window), nc(nc), dX((size_t)window * nc), dF((size_t)window * nc), xPrev(nc), fPrev(nc), f(nc), gm(nc), gc(nc) {}
  bool mix(Kernel &k, const double *cFree, const std::vector<double> &x, std::vector<double> &c, std::vector<double> &m, double &residual,
           double allowed = 1) {
    contactlaw::Slots &law = k.law;
    for (int j = 0; j < nc; j++) f[j] = m[j] - x[j];
    if (havePrev) {
      for (int j = 0; j < nc; j++) { dX[(size_t)head * nc + j] = x[j] - xPrev[j]; dF[(size_t)head * nc + j] = f[j] - fPrev[j]; }
      head = (head + 1) % window;
      stored = std::min(stored + 1, window);
    }
    xPrev = x; fPrev = f; havePrev = true;
    if (stored == 0) return false;
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
    int one = 1, info = 0;
    dgetrf_(&w, &w, A.data(), &w, piv.data(), &info);
    if (info == 0) dgetrs_("N", &w, &one, A.data(), &w, piv.data(), rhs.data(), &w, &info);
    if (info != 0) return false;
    gm = m; gc = c;
    for (int j = 0; j < nc; j++) {
      double s = 0;
      for (int a = 0; a < w; a++) s += (dX[(size_t)a * nc + j] + dF[(size_t)a * nc + j]) * rhs[a];
      m[j] = gm[j] - s;
    }
    velocities(k, cFree, m.data(), c.data());
    const double accelerated = law.evaluate(c.data(), m.data());
    if (accelerated <= allowed * residual) { residual = accelerated; return true; }
    m = gm; c = gc;                                  // not better: keep G's iterate, forget the history
    residual = law.evaluate(c.data(), m.data());
    stored = 0; head = 0; havePrev = false;
    return false;
  }
};

// The two levels (see the head of this file): K and the split of Dw, once per Delassus matrix.
// K = 0 (one level) where no gap between the top eigenvalues exceeds coarseGap, and in 3D (the
// disk) unless that gap sets one mode apart; in 3D, K then grows by the modes above
// coarseGap^2 times the median eigenvalue (at most coarseModesMax).
void coarseSplit(Kernel &k, int K);
const int coarseModesMax = 8;                        // at most this many modes split off
const double coarseGap = 10;                         // ... when the gap is above this ratio
void coarsePrepare(Kernel &k) {
  FixedPointState &fp = k.fixedPoint;
  const Factorization &factor = k.factor;
  if (fp.coarseGeneration == factor.delassusGeneration) return;
  fp.coarseGeneration = factor.delassusGeneration;
  fp.K = 0;
  const int nc = factor.nc;
  if (nc < 2) return;
  const bool disk = k.law.hasPairs();
  const std::vector<double> &w = k.nodes.slotWeight, &Dw = factor.Dw;
  // W^1/2 Dw W^-1/2 = W^1/2 C S^-1 C' W^1/2, symmetric (up to round-off: averaged)
  std::vector<double> A((size_t)nc * nc), eig(nc);
  for (int j = 0; j < nc; j++) for (int i = 0; i < nc; i++)
    A[i + (size_t)j * nc] = 0.5 * (std::sqrt(w[i] / w[j]) * Dw[i + (size_t)j * nc] + std::sqrt(w[j] / w[i]) * Dw[j + (size_t)i * nc]);
  int lwork = -1, info = 0;
  double query = 0;
  dsyev_("V", "U", &nc, A.data(), &nc, eig.data(), &query, &lwork, &info);
  lwork = std::max(1, (int)query);
  std::vector<double> work(lwork);
  dsyev_("V", "U", &nc, A.data(), &nc, eig.data(), work.data(), &lwork, &info);
  if (info != 0) return;
  int K = 0;
  double gap = 0;
  for (int kk = 1; kk <= std::min(coarseModesMax, nc - 1); kk++) {     // eig ascending: the top is eig[nc - 1]
    const double ratio = eig[nc - kk] / std::max(eig[nc - kk - 1], 1e-300 * eig[nc - 1]);
    if (ratio > gap) { gap = ratio; K = kk; }
  }
  if (!(gap > coarseGap) || (disk && K != 1)) return;   // the disk: one mode above the gap
  // the disk: with it, the modes that stand coarseGap^2 above the median eigenvalue (the bulk
  // of the spectrum: a slot's own compliance), the bending of a thin plate (consistentRoots)
  if (disk)
    while (K < std::min(coarseModesMax, nc - 1) && eig[nc - 1 - K] > coarseGap * coarseGap * eig[nc / 2]) K++;
  fp.coarseVectors.swap(A);
  fp.coarseValues.swap(eig);
  coarseSplit(k, K);
}

// Dw split into its K stiffest modes (the eigenpairs coarsePrepare kept) and the rest
void coarseSplit(Kernel &k, int K) {
  FixedPointState &fp = k.fixedPoint;
  const int nc = k.factor.nc;
  const std::vector<double> &w = k.nodes.slotWeight, &Dw = k.factor.Dw, &A = fp.coarseVectors, &eig = fp.coarseValues;
  const double below = eig[nc - K - 1];
  fp.K = K;
  fp.delta.assign(K, 0.); fp.P.assign((size_t)K * nc, 0.); fp.Q.assign((size_t)K * nc, 0.);
  fp.deflated = Dw;
  for (int kk = 0; kk < K; kk++) {
    fp.delta[kk] = eig[nc - 1 - kk] - below;
    const double *u = A.data() + (size_t)(nc - 1 - kk) * nc;
    double *P = fp.P.data() + (size_t)kk * nc, *Q = fp.Q.data() + (size_t)kk * nc;
    for (int i = 0; i < nc; i++) { P[i] = u[i] / std::sqrt(w[i]); Q[i] = u[i] * std::sqrt(w[i]); }
    for (int j = 0; j < nc; j++) for (int i = 0; i < nc; i++) fp.deflated[i + (size_t)j * nc] -= fp.delta[kk] * P[i] * Q[j];
  }
  fp.rhoDeflated.assign(nc, 0.);
  for (int j = 0; j < nc; j++) {
    const double djj = fp.deflated[j + (size_t)j * nc];
    fp.rhoDeflated[j] = std::max(1. / djj - k.law.Kn[j], 1e-3 / djj);
  }
  // the disk's coarse root (consistentStep): its first slope, the response of every slot to a
  // alone, 1 + delta sum Q_j P_j / D'_jj
  fp.coarseSlope = 1;
  for (int j = 0; j < nc; j++) fp.coarseSlope += fp.delta[0] * fp.Q[j] * fp.P[j] / fp.deflated[j + (size_t)j * nc];
  fp.coarseJacobian.clear();
}

// The disk's first Jacobian of R(a) with K modes: I + diag(delta) Q' diag(1/D') P, every slot's
// response to a alone (coarseSlope's, K x K)
void coarseFirstJacobian(const FixedPointState &fp, int nc, std::vector<double> &J) {
  const int K = fp.K;
  J.assign((size_t)K * K, 0.);
  for (int r = 0; r < K; r++) for (int q = 0; q < K; q++) {
    double sum = 0;
    for (int j = 0; j < nc; j++) sum += fp.Q[(size_t)r * nc + j] * fp.P[(size_t)q * nc + j] / fp.deflated[j + (size_t)j * nc];
    J[r + (size_t)q * K] = (r == q ? 1. : 0.) + fp.delta[r] * sum;
  }
}

// a = delta Q'm: the velocity of the split-off modes that m gives
void coarseVelocity(const FixedPointState &fp, int nc, const double *m, std::vector<double> &a) {
  for (int kk = 0; kk < fp.K; kk++) {
    double sum = 0;
    for (int j = 0; j < nc; j++) sum += fp.Q[(size_t)kk * nc + j] * m[j];
    a[kk] = fp.delta[kk] * sum;
  }
}

// The stall test of either fixed point: the residual has not changed by 1e-6 of itself in 20
// iterations, away from a solution (recent: the residuals of the last 20 iterations)
bool stalledNow(std::vector<double> &recent, int it, double residual, bool done) {
  recent[it % 20] = residual;
  return !done && it >= 20 && std::fabs(residual - recent[(it + 1) % 20]) <= 1e-6 * residual;
}

// The coarse correction after an iteration's sweeps: G = a - delta Q'm, the Newton step
// da = J^-1 G with J = I - diag(delta) Q'X, X = dm/da the response of every slot's relation
// (row j: sum d dm - sum a D' dm = sum a P da, the relations of the law at the current pieces);
// a -= t da and m -= t X da, t = 1, 1/2, ... 1/1024, the first that lowers the natural
// residual; if none does, a = delta Q'm (the coarse velocity the sweeps then hold is m's own).
// c = cFree - Dw m after it. Returns the natural residual at (c, m).
double coarseCorrection(Kernel &k, const double *cFree, double *c, double *m, std::vector<double> &a) {
  FixedPointState &fp = k.fixedPoint;
  contactlaw::Slots &law = k.law;
  const int nc = k.factor.nc, K = fp.K, T = contactlaw::Slots::termsPerRelation;
  velocities(k, cFree, m, c);
  const double before = law.evaluate(c, m);
  law.relations(c);
  std::vector<double> G(K);
  coarseVelocity(fp, nc, m, G);
  for (int kk = 0; kk < K; kk++) G[kk] = a[kk] - G[kk];
  // X = N'^-1 (A_c P): computed again only when the relations changed (a piece, or a
  // coefficient of a nonlinear one); the same relations give the same X
  std::vector<double> &X = fp.coarseResponse;
  int info = 0, one = 1;
  const bool same = fp.coarseResponseGeneration == k.factor.delassusGeneration && fp.coarseRelationA == law.a
                    && fp.coarseRelationD == law.d && fp.coarseRelationASlot == law.aSlot && fp.coarseRelationDSlot == law.dSlot;
  if (!same) {
    std::vector<double> N((size_t)nc * nc, 0.);
    X.assign((size_t)nc * K, 0.);
    for (int j = 0; j < nc; j++) for (int t = 0; t < T; t++) {
      const double dj = law.d[T * j + t], aj = law.a[T * j + t];
      if (dj != 0) N[j + (size_t)law.dSlot[T * j + t] * nc] += dj;
      if (aj == 0) continue;
      const int r = law.aSlot[T * j + t];
      for (int i = 0; i < nc; i++) N[j + (size_t)i * nc] -= aj * fp.deflated[r + (size_t)i * nc];
      for (int kk = 0; kk < K; kk++) X[j + (size_t)kk * nc] += aj * fp.P[(size_t)kk * nc + r];
    }
    std::vector<int> pivots(nc);
    dgetrf_(&nc, &nc, N.data(), &nc, pivots.data(), &info);
    if (info == 0) dgetrs_("N", &nc, &K, N.data(), &nc, pivots.data(), X.data(), &nc, &info);
    fp.coarseResponseGeneration = info == 0 ? k.factor.delassusGeneration : -1;
    fp.coarseRelationA = law.a; fp.coarseRelationD = law.d; fp.coarseRelationASlot = law.aSlot; fp.coarseRelationDSlot = law.dSlot;
  }
  std::vector<int> coarsePivots(K);
  std::vector<double> J((size_t)K * K), da = G, dm(nc, 0.), trial(nc), cTrial(nc);
  if (info == 0) {
    for (int r = 0; r < K; r++) for (int q = 0; q < K; q++) {
      double sum = 0;
      for (int j = 0; j < nc; j++) sum += fp.Q[(size_t)r * nc + j] * X[j + (size_t)q * nc];
      J[r + (size_t)q * K] = (r == q ? 1. : 0.) - fp.delta[r] * sum;
    }
    dgetrf_(&K, &K, J.data(), &K, coarsePivots.data(), &info);
  }
  if (info == 0) dgetrs_("N", &K, &one, J.data(), &K, coarsePivots.data(), da.data(), &K, &info);
  if (info == 0) {
    for (int j = 0; j < nc; j++) for (int kk = 0; kk < K; kk++) dm[j] += X[j + (size_t)kk * nc] * da[kk];
    double t = 1;
    for (int h = 0; h <= 10; h++, t *= 0.5) {
      for (int j = 0; j < nc; j++) trial[j] = m[j] - t * dm[j];
      velocities(k, cFree, trial.data(), cTrial.data());
      const double residual = law.evaluate(cTrial.data(), trial.data());
      if (residual < before) {
        std::copy(trial.begin(), trial.end(), m);
        std::copy(cTrial.begin(), cTrial.end(), c);
        for (int kk = 0; kk < K; kk++) a[kk] -= t * da[kk];
        return residual;
      }
    }
  }
  coarseVelocity(fp, nc, m, a);
  velocities(k, cFree, m, c);
  return law.evaluate(c, m);
}

// The fixed point of a step with two levels (K > 0): each iteration a forward and a backward
// sweep on D' (c_in = cFree - P a - D' m, a held), then the coarse correction. No Anderson
// mixing: the coarse correction is already a Newton step on the slow modes. The stopping
// test, the stall test and the outputs are fixedPointStep's.
long twoLevelStep(Kernel &k, const double *cFreeIn, double *cInOut, double *mInOut, double info[solverInfoColumnCount], bool &cycled) {
  cycled = false;
  const Factorization &factor = k.factor;
  FixedPointState &fp = k.fixedPoint;
  contactlaw::Slots &law = k.law;
  const SolverSettings &settings = k.settings;
  const int nc = factor.nc, K = fp.K, inc = 1;
  FixedPointStart start(k, cFreeIn, mInOut);
  const std::vector<double> &userR = start.userR, &cFree = start.cFree;
  std::vector<double> &c = start.c, &m = start.m, cin(nc), a(K, 0.);
  double &residual = start.residual;
  int &unresolved = start.unresolved, it = 0;
  bool &done = start.done, stalled = false;
  coarseVelocity(fp, nc, m.data(), a);
  std::vector<double> recent(20, 0.);
  int cycling = 0;
  while (!done && it < settings.maxit && std::isfinite(residual)) {
    const double minusOne = -1., one = 1.;
    cin = cFree;                                     // c_in = cFree - P a - D' m
    dgemv_("N", &nc, &nc, &minusOne, fp.deflated.data(), &nc, m.data(), &inc, &one, cin.data(), &inc);
    for (int kk = 0; kk < K; kk++) for (int i = 0; i < nc; i++) cin[i] -= fp.P[(size_t)kk * nc + i] * a[kk];
    fixedPointSweep(k, true, cin.data(), m.data(), fp.deflated.data(), fp.rhoDeflated.data());
    fixedPointSweep(k, false, cin.data(), m.data(), fp.deflated.data(), fp.rhoDeflated.data());
    it++;
    residual = coarseCorrection(k, cFree.data(), c.data(), m.data(), a);
    done = stepConverged(k, residual, c.data(), unresolved);
    // a cycle of two (the residual back to its value of two iterations before, ten times in a
    // row: seen at small time steps, normal slots switching between free and damped): stop,
    // and the step is solved again from its start on one level (fixedPointStep); then the
    // stall test
    cycling = !done && it >= 3 && std::fabs(residual - recent[(it - 2 + 20) % 20]) <= 1e-9 * residual ? cycling + 1 : 0;
    if (cycling >= 10) { cycled = true; logIteration(k, it, residual); break; }
    if (stalledNow(recent, it, residual, done)) {
      stalled = true;
      logIteration(k, it, residual);
      break;
    }
    logIteration(k, it, residual);
  }
  return fixedPointFinish(k, userR, c, m, residual, it, unresolved, stalled, done, cInOut, mInOut, info);
}
// The disk's two levels with K > 1 modes: one half of consistentStep's iteration, its root
// R(a) = a - diag(delta) Q'm_a = 0 in K unknowns, a = base + s as with one mode; damped Newton
// steps on the Jacobian last found (first: coarseFirstJacobian), kept up to date by Broyden's
// update at every evaluation of R, each step halved (at most 10 times) until the weighted
// mismatch sum_k weight_k |R_k| falls. Stops when that mismatch is at most a tenth of the
// residual, or every R_k is within one rounding of delta_k Q_k'm, or after 60 sweeps, or when
// no step lowers it. m becomes the sweep's at the root; lastRoot its a.
void consistentRoots(Kernel &k, bool forward, const std::vector<double> &cFree, std::vector<double> &m, double residual,
                     const std::vector<double> &weights, std::vector<double> &lastRoot) {
  FixedPointState &fp = k.fixedPoint;
  const int nc = k.factor.nc, K = fp.K, one = 1;
  const double *P = fp.P.data(), *Q = fp.Q.data();
  std::vector<double> own(K), size(K), base(K), cBase(nc), cTrial(nc), mTrial(nc), mBest(m);
  for (int kk = 0; kk < K; kk++) {
    double sum = 0, sz = 0;
    for (int j = 0; j < nc; j++) { sum += Q[(size_t)kk * nc + j] * m[j]; sz += std::fabs(Q[(size_t)kk * nc + j] * m[j]); }
    own[kk] = fp.delta[kk] * sum; size[kk] = fp.delta[kk] * sz;
    base[kk] = std::isfinite(lastRoot[kk]) ? lastRoot[kk] : own[kk];
  }
  velocities(k, cFree.data(), m.data(), cBase.data());
  for (int kk = 0; kk < K; kk++) for (int j = 0; j < nc; j++) cBase[j] += P[(size_t)kk * nc + j] * (own[kk] - base[kk]);
  int sweeps = 0;
  auto R = [&](const std::vector<double> &s, std::vector<double> &r) {
    mTrial = m;
    cTrial = cBase;
    for (int kk = 0; kk < K; kk++) for (int j = 0; j < nc; j++) cTrial[j] -= P[(size_t)kk * nc + j] * s[kk];
    fixedPointSweep(k, forward, cTrial.data(), mTrial.data(), fp.deflated.data(), fp.rhoDeflated.data());
    sweeps++;
    for (int kk = 0; kk < K; kk++) {
      double sum = 0;
      for (int j = 0; j < nc; j++) sum += Q[(size_t)kk * nc + j] * mTrial[j];
      r[kk] = s[kk] + (base[kk] - fp.delta[kk] * sum);
    }
  };
  auto mismatch = [&](const std::vector<double> &r) {
    double sum = 0;
    for (int kk = 0; kk < K; kk++) sum += weights[kk] * std::fabs(r[kk]);
    return sum;
  };
  double weightSum = 0;
  for (int kk = 0; kk < K; kk++) weightSum += weights[kk];
  auto small = [&](const std::vector<double> &r) {
    if (weightSum > 0 && mismatch(r) <= 0.1 * residual) return true;
    for (int kk = 0; kk < K; kk++) if (std::fabs(r[kk]) > DBL_EPSILON * (std::fabs(own[kk]) + size[kk])) return false;
    return true;
  };
  std::vector<double> s(K, 0.), r(K), sNew(K), rNew(K), ds(K), LU((size_t)K * K);
  std::vector<int> pivots(K);
  R(s, r);
  mBest = mTrial;
  std::vector<double> &J = fp.coarseJacobian;
  if (J.size() != (size_t)K * K) coarseFirstJacobian(fp, nc, J);
  bool fresh = false;                                // J is the first Jacobian (a second non-finite step ends the root)
  while (!small(r) && sweeps < 60) {
    int info = 0;
    LU = J; ds = r;
    dgetrf_(&K, &K, LU.data(), &K, pivots.data(), &info);
    if (info == 0) dgetrs_("N", &K, &one, LU.data(), &K, pivots.data(), ds.data(), &K, &info);
    bool finite = info == 0;
    for (int kk = 0; kk < K; kk++) finite = finite && std::isfinite(ds[kk]);
    if (!finite && fresh) break;                     // (a review: no loop without a sweep)
    if (!finite) { coarseFirstJacobian(fp, nc, J); fresh = true; continue; }
    fresh = false;
    bool accepted = false;
    double t = 1;
    for (int h = 0; h <= 10 && sweeps < 60; h++, t *= 0.5) {
      for (int kk = 0; kk < K; kk++) sNew[kk] = s[kk] - t * ds[kk];
      R(sNew, rNew);
      // Broyden: J += (dr - J ds) ds' / ds'ds
      double dd = 0;
      for (int kk = 0; kk < K; kk++) dd += (sNew[kk] - s[kk]) * (sNew[kk] - s[kk]);
      if (dd > 0) for (int rr = 0; rr < K; rr++) {
        double u = rNew[rr] - r[rr];
        for (int q = 0; q < K; q++) u -= J[rr + (size_t)q * K] * (sNew[q] - s[q]);
        for (int q = 0; q < K; q++) J[rr + (size_t)q * K] += u * (sNew[q] - s[q]) / dd;
      }
      if (mismatch(rNew) < mismatch(r) || small(rNew)) { s = sNew; r = rNew; mBest = mTrial; accepted = true; break; }
    }
    if (!accepted) break;
  }
  for (int kk = 0; kk < K; kk++) lastRoot[kk] = base[kk] + s[kk];
  m = mBest;
}

// The disk's two levels (3D, K = 1: see the head of this file). One sweep on D' from m with the
// coarse velocity a held gives m_a; R(a) = a - delta Q'm_a is the mismatch of a with the
// velocity m_a gives. Each half of an iteration (the forward sweep, then the backward one)
// takes the a with R(a) = 0, so that its sweep ends where c_in = cFree - P a - D'm equals
// cFree - Dw m: a splitting of Dw (the triangle of D' plus the mode), convergent for the
// linear part whatever delta. R is a scalar function, increasing (a faster coarse motion
// presses the slots harder), piecewise smooth: found from the last root of the same half (the
// first: a = delta Q'm) by secant steps on the slope last found, then, once bracketed, secant
// steps kept inside the bracket (bisection when one leaves it), until the mismatch R moves the
// residual by at most a tenth of the last natural residual (weight |R|), or R is within one
// rounding of delta Q'm, or no double is left inside the bracket. a is held as base + s (base
// the start), so that the root is not limited by the last place of a: R is steep in a.
// Every R costs a sweep (counted: fixed_point_sweeps). The iterates of the map m -> both halves
// are mixed by Anderson, as the one-level fixed point's. The stopping and the stall tests, and
// the outputs, are fixedPointStep's.
const double consistentAllowed = 5;                  // Anderson's iterate kept up to 5 times G's residual
long consistentStep(Kernel &k, const double *cFreeIn, double *cInOut, double *mInOut, double info[solverInfoColumnCount]) {
  const Factorization &factor = k.factor;
  FixedPointState &fp = k.fixedPoint;
  contactlaw::Slots &law = k.law;
  const SolverSettings &settings = k.settings;
  const int nc = factor.nc, inc = 1;
  FixedPointStart start(k, cFreeIn, mInOut);
  const std::vector<double> &userR = start.userR, &cFree = start.cFree;
  std::vector<double> &c = start.c, &m = start.m, x(nc), cBase(nc), mTrial(nc), cTrial(nc);
  double &residual = start.residual;
  int &unresolved = start.unresolved, it = 0;
  bool &done = start.done, stalled = false;
  double weight = 0;                                 // of a mismatch R of a in the residual
  for (int j = 0; j < nc; j++) weight = std::max(weight, std::fabs(fp.P[j]) * factor.rReference[j] * law.residualWeight[j]);
  std::vector<double> recent(20, 0.);
  Anderson anderson(fp.window, nc);
  const double delta = fp.delta[0], *P = fp.P.data(), *Q = fp.Q.data();
  auto coarse = [&](const std::vector<double> &mm, double &size) {   // delta Q'm, and delta sum |Q_j m_j|
    double sum = 0;
    size = 0;
    for (int j = 0; j < nc; j++) { sum += Q[j] * mm[j]; size += std::fabs(Q[j] * mm[j]); }
    size *= delta;
    return delta * sum;
  };
  double lastRoot[2] = {NAN, NAN};
  const int K = fp.K;
  std::vector<double> lastRoots[2] = {std::vector<double>(K, NAN), std::vector<double>(K, NAN)}, weights(K, 0.);
  for (int kk = 0; kk < K; kk++) for (int j = 0; j < nc; j++)
    weights[kk] = std::max(weights[kk], std::fabs(P[(size_t)kk * nc + j]) * factor.rReference[j] * law.residualWeight[j]);
  while (!done && it < settings.maxit && std::isfinite(residual)) {
    x = m;
    for (int half = 0; half < 2; half++) {
      const bool forward = half == 0;
      if (K > 1) {
        consistentRoots(k, forward, cFree, m, residual, weights, lastRoots[half]);
        continue;
      }
      double size = 0;
      const double own = coarse(m, size);
      // a = base + s: the sweeps start from cFree - D'm - P base, and s keeps the digits that
      // |a| would lose (R's slope is steep: one unit in the last place of a moves R by 1e3 of it)
      const double base = std::isfinite(lastRoot[half]) ? lastRoot[half] : own;
      // from the velocities the test reads, cFree - Dw m = cFree - D'm - P own (the sweeps then
      // go to the iterate that the test, not a rounding of its split, finds consistent)
      velocities(k, cFree.data(), m.data(), cBase.data());
      for (int j = 0; j < nc; j++) cBase[j] += P[j] * (own - base);
      auto R = [&](double s) {                       // the sweep from m with a = base + s held: mTrial, cTrial
        mTrial = m;
        for (int j = 0; j < nc; j++) cTrial[j] = cBase[j] - P[j] * s;
        fixedPointSweep(k, forward, cTrial.data(), mTrial.data(), fp.deflated.data(), fp.rhoDeflated.data());
        double trialSize = 0;
        return s + (base - coarse(mTrial, trialSize));
      };
      const double enough = std::max(weight > 0 ? 0.1 * residual / weight : 0., DBL_EPSILON * (std::fabs(own) + size));
      double s = 0, r = R(s);
      double below = NAN, rBelow = NAN, above = NAN, rAbove = NAN, previous = NAN, rPrevious = NAN;
      auto note = [&]() { if (r < 0) { below = s; rBelow = r; } else { above = s; rAbove = r; } };
      note();
      for (int n = 0; std::fabs(r) > enough && n < 60; n++) {
        const bool secant = std::isfinite(previous) && r != rPrevious;
        double next;
        if (std::isfinite(below) && std::isfinite(above)) {
          const double lo = std::min(below, above), hi = std::max(below, above), middle = 0.5 * (lo + hi);
          if (!(middle > lo && middle < hi)) break;                      // no double between: R's resolution
          next = secant ? s - r * (s - previous) / (r - rPrevious) : NAN;
          if (!(next > lo && next < hi)) next = below - rBelow * (above - below) / (rAbove - rBelow);
          if (!(next > lo && next < hi)) next = middle;
        }
        else {
          const double slope = secant ? (r - rPrevious) / (s - previous) : 0;
          if (slope > 0) fp.coarseSlope = slope;
          next = s - r / fp.coarseSlope;
          // not decreasing along the last step (R not monotone there): twice that step, away
          if (secant && !(slope > 0)) next = s + 2 * std::fabs(s - previous) * (r > 0 ? -1. : 1.);
        }
        previous = s; rPrevious = r;
        s = next; r = R(s);
        note();
      }
      if (std::isfinite(previous) && s != previous && (r - rPrevious) / (s - previous) > 0) fp.coarseSlope = (r - rPrevious) / (s - previous);
      lastRoot[half] = base + s;
      m = mTrial;
    }
    it++;
    velocities(k, cFree.data(), m.data(), c.data());
    residual = law.evaluate(c.data(), m.data());
    done = stepConverged(k, residual, c.data(), unresolved);
    if (stalledNow(recent, it, residual, done)) {
      stalled = true;
      logIteration(k, it, residual);
      break;
    }
    if (fp.window > 0 && !done && std::isfinite(residual) && anderson.mix(k, cFree.data(), x, c, m, residual, consistentAllowed))
      done = stepConverged(k, residual, c.data(), unresolved);
    logIteration(k, it, residual);
  }
  return fixedPointFinish(k, userR, c, m, residual, it, unresolved, stalled, done, cInOut, mInOut, info);
}
}  // namespace

// One iteration of the map G from m (c is recomputed from m): the forward and backward sweeps;
// returns the natural residual at the new (c, m) and sets its merit (referenceEvaluate).
double fixedPointIteration(Kernel &k, const double *cFree, double *c, double *m, double &merit) {
  fixedPointPrepare(k);
  velocities(k, cFree, m, c);
  fixedPointSweep(k, true, c, m);
  fixedPointSweep(k, false, c, m);
  velocities(k, cFree, m, c);
  return referenceEvaluate(k, c, m, merit);
}

// Anderson-accelerated fixed point: m <- G(m), G the symmetric sweep above; the new iterate
// mixes the last window iterates to minimise G(m) - m, and is kept only when its natural
// residual is below G's (else the history restarts). The test is Newton's natural residual.
long fixedPointStep(Kernel &k, const double *cFreeIn, double *cInOut, double *mInOut, double info[solverInfoColumnCount]) {
  requireSolver(k, "contactKernelFixedPoint");
  const Factorization &factor = k.factor;
  const FixedPointState &fixedPoint = k.fixedPoint;
  contactlaw::Slots &law = k.law;
  const SolverSettings &settings = k.settings;
  const int nc = factor.nc;
  fixedPointPrepare(k);
  coarsePrepare(k);
  int before = 0;                                    // iterations of a two-level try that cycled
  if (k.fixedPoint.K > 0 && law.hasPairs()) {
    const int modes = k.fixedPoint.K;
    std::vector<double> cStart(cInOut, cInOut + nc), mStart(mInOut, mInOut + nc);
    const long it = consistentStep(k, cFreeIn, cInOut, mInOut, info);
    if (it >= 0 || modes == 1) return it;
    // K > 1 modes did not converge (found by a review: the plate without friction stalls where
    // two nodes reach the bound; a stiffer or nearly incompressible block takes a second mode
    // and fails at step 1): the step again from its start with the one mode above the gap,
    // and so every step after it (the Delassus matrix is the run's); its iterations count too
    const double spent = info[InfoIterations];
    std::copy(cStart.begin(), cStart.end(), cInOut);
    std::copy(mStart.begin(), mStart.end(), mInOut);
    coarseSplit(k, 1);
    const long again = consistentStep(k, cFreeIn, cInOut, mInOut, info);
    info[InfoIterations] += spent;
    return again < 0 ? -1 : again + (long)spent;
  }
  if (k.fixedPoint.K > 0) {
    std::vector<double> cStart(cInOut, cInOut + nc), mStart(mInOut, mInOut + nc);
    bool cycled = false;
    const long it = twoLevelStep(k, cFreeIn, cInOut, mInOut, info, cycled);
    if (!cycled) return it;
    before = (int)info[InfoIterations];               // from the step's start again, on one level
    std::copy(cStart.begin(), cStart.end(), cInOut);
    std::copy(mStart.begin(), mStart.end(), mInOut);
  }
  FixedPointStart start(k, cFreeIn, mInOut);
  const std::vector<double> &userR = start.userR, &cFree = start.cFree;
  std::vector<double> &c = start.c, &m = start.m;
  double &residual = start.residual;
  int &unresolved = start.unresolved;
  bool &done = start.done;
  auto exactVelocities = [&]() { velocities(k, cFree.data(), m.data(), c.data()); };
  // Anderson acceleration of the map G: m -> two sweeps (forward, backward), window fixedPoint.window
  const int window = fixedPoint.window;
  Anderson anderson(window, nc);
  std::vector<double> x(nc);
  bool stalled = false;
  std::vector<double> recent(20, 0.);                // the residuals of the last 20 iterations
  int it = 0;
  while (!done && it < settings.maxit && std::isfinite(residual)) {
    x = m;
    fixedPointSweep(k, true, c.data(), m.data());
    fixedPointSweep(k, false, c.data(), m.data());
    it++;
    if (it % 25 == 0) exactVelocities();             // the updates' round-off does not pile up
    residual = law.evaluate(c.data(), m.data());
    if (residual <= settings.tol) { exactVelocities(); residual = law.evaluate(c.data(), m.data()); }
    done = stepConverged(k, residual, c.data(), unresolved);
    // stalled: the residual has not changed by 1e-6 of itself in 20 iterations, away from a
    // solution (the sweeps then have a fixed point that is not one of the law, seen with steep
    // damping tables: a backward sweep undoes the forward one); stop, exit 4 follows
    if (stalledNow(recent, it, residual, done)) {
      stalled = true;
      logIteration(k, it, residual);
      break;
    }
    if (window > 0 && !done && std::isfinite(residual) && anderson.mix(k, cFree.data(), x, c, m, residual))
      done = stepConverged(k, residual, c.data(), unresolved);
    logIteration(k, it, residual);
  }
  return fixedPointFinish(k, userR, c, m, residual, before + it, unresolved, stalled, done, cInOut, mInOut, info);
}

}  // namespace contactkernel
