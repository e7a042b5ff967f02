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
#include <algorithm>
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

// A 3D node's tangential pair (j, q) in one update: b = c_tau + D m_tau with the pair's block D
// of Dw, the disk's exact local solve (Slots::diskUpdate), then c follows m.
void fixedPointDisk(Kernel &k, int j, int q, double *c, double *m) {
  const Factorization &factor = k.factor;
  const int nc = factor.nc, inc = 1;
  const double Djj = factor.Dw[j + (size_t)j * nc], Djq = factor.Dw[j + (size_t)q * nc];
  const double Dqj = factor.Dw[q + (size_t)j * nc], Dqq = factor.Dw[q + (size_t)q * nc];
  const double bj = c[j] + Djj * m[j] + Djq * m[q], bq = c[q] + Dqj * m[j] + Dqq * m[q];
  double mj = 0, mq = 0;
  k.law.diskUpdate(j, Djj, Djq, Dqj, Dqq, bj, bq, c, mj, mq);
  const double omega = k.fixedPoint.omega;
  const double deltaJ = omega * (mj - m[j]), deltaQ = omega * (mq - m[q]);
  m[j] += deltaJ; m[q] += deltaQ;
  const double minusJ = -deltaJ, minusQ = -deltaQ;
  if (deltaJ != 0) daxpy_(&nc, &minusJ, factor.Dw.data() + (size_t)j * nc, &inc, c, &inc);
  if (deltaQ != 0) daxpy_(&nc, &minusQ, factor.Dw.data() + (size_t)q * nc, &inc, c, &inc);
}

// one sweep over the slots, forward or backward; c = cFree - Dw m follows m
void fixedPointSweep(Kernel &k, bool forward, double *c, double *m) {
  const Factorization &factor = k.factor;
  FixedPointState &fixedPoint = k.fixedPoint;
  const contactlaw::Slots &law = k.law;
  const int nc = factor.nc, inc = 1;
  for (int step = 0; step < nc; step++) {
    const int j = forward ? step : nc - 1 - step;
    const int q = law.pair[j];
    if (q >= 0) {                                    // a 3D pair, at the first of its two slots
      if (forward ? q > j : q < j) fixedPointDisk(k, j, q, c, m);
      continue;
    }
    const double *column = factor.Dw.data() + (size_t)j * nc;
    const double y = m[j] + c[j] / column[j];
    double t = 0, v = 0;
    law.resolve(j, y, fixedPoint.rho[j], c, t, v);
    const double cj = (y - t) / fixedPoint.rho[j];
    const double delta = fixedPoint.omega * (t - law.Kn[j] * cj - m[j]);
    if (delta == 0) continue;
    m[j] += delta;
    const double minus = -delta;
    daxpy_(&nc, &minus, column, &inc, c, &inc);
  }
  fixedPoint.sweeps++;
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
  // the convergence test at the operator's scale, as Newton's (referenceEvaluate)
  const std::vector<double> userR = law.r;
  for (int j = 0; j < nc; j++) law.setAugmentation(j, factor.rReference[j]);
  std::vector<double> cFree(nc), c(nc), m(nc);
  for (int j = 0; j < nc; j++) { cFree[j] = cFreeIn[j]; m[j] = mInOut[j]; }
  roundoffScale(k, cFree.data(), m.data());
  auto exactVelocities = [&]() { velocities(k, cFree.data(), m.data(), c.data()); };
  exactVelocities();
  double residual = law.evaluate(c.data(), m.data());
  logIteration(k, 0, residual);
  int unresolved = 0;
  bool done = stepConverged(k, residual, c.data(), unresolved);
  // Anderson acceleration of the map G: m -> two sweeps (forward, backward), window fixedPoint.window
  const int window = fixedPoint.window;
  std::vector<double> dX((size_t)window * nc), dF((size_t)window * nc), xPrev(nc), fPrev(nc), x(nc), f(nc), gm(nc), gc(nc);
  int stored = 0, head = 0;
  bool havePrev = false, stalled = false;
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
    recent[it % 20] = residual;
    if (!done && it >= 20 && std::fabs(residual - recent[(it + 1) % 20]) <= 1e-6 * residual) {
      stalled = true;
      logIteration(k, it, residual);
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
          const double accelerated = law.evaluate(c.data(), m.data());
          if (accelerated <= residual) {
            residual = accelerated;
            done = stepConverged(k, residual, c.data(), unresolved);
          }
          else {                                     // not better: keep G's iterate, forget the history
            m = gm; c = gc;
            residual = law.evaluate(c.data(), m.data());
            stored = 0; head = 0; havePrev = false;
          }
        }
      }
    }
    logIteration(k, it, residual);
  }
  for (int j = 0; j < nc; j++) law.setAugmentation(j, userR[j]);
  std::copy(c.begin(), c.end(), cInOut);
  std::copy(m.begin(), m.end(), mInOut);
  info[InfoResidual] = residual; info[InfoIterations] = it; info[InfoUnresolved] = unresolved; info[InfoStalled] = stalled;
  return done ? it : -1;
}

}  // namespace contactkernel
