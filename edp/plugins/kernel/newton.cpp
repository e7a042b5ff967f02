// newton.cpp: the semismooth Newton of a step on the condensed equations c = cFree - Dw m, the
// safeguards shared by every Newton (this one, the script view and the full-system Newton of
// edp/lib/solvers.idp) and the -verbose log of every solver's iterations.
//
// The Newton matrix N (nc x nc) of the relations sum_t a_jt c[aSlot_jt] + d_jt m[dSlot_jt] = h_j
// (contactlaw.hpp; one term of each in 2D) with c = cFree - Dw m: row j = sum_t -a_jt Dw(aSlot_jt, :)
// + d_jt e_dSlot_jt'. A base matrix N0 (its relations baseA, baseD, baseS, baseT) is
// LU-factorized; a matrix whose relations differ from N0's in a few rows R only is solved with
// N0's factors and a rank-|R| (Woodbury) correction:
//   N = N0 + E_R Delta,  N^-1 b = x0 - Y K^-1 Delta x0,  x0 = N0^-1 b,  Y = N0^-1 E_R,  K = I + Delta Y,
// Y read from N0^-1 (computed from the factors when a first correction needs it) and K
// assembled from the changed rows' terms (newtonPrepare). N0 is factorized again when more than
// nc/3 rows changed for another reason than a 3D slip, or when a corrected solve fails its
// residual check (newtonSolve).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include "blas.hpp"
#include "kernel.hpp"

namespace contactkernel {
using contactlaw::Slip;

namespace {
const int relationTerms = contactlaw::Slots::termsPerRelation;   // the terms of a relation
// row j of the Newton matrix of the relations (a, aSlot, d, dSlot), its terms from first on,
// times sign, added into out[i * ld], i < nc (term 0 always; the others where nonzero)
void addNewtonRow(const Factorization &factor, int j, const std::vector<double> &a, const std::vector<int> &aSlot, const std::vector<double> &d,
                  const std::vector<int> &dSlot, double sign, double *out, size_t ld, int first = 0) {
  const int nc = factor.nc;
  for (int t = first; t < relationTerms; t++) {
    const double at = a[relationTerms * j + t];
    if (t > 0 && at == 0) continue;
    const double *row = factor.Dw.data() + aSlot[relationTerms * j + t];
    for (int i = 0; i < nc; i++) out[i * ld] += sign * (-at * row[(size_t)i * nc]);
  }
  for (int t = first; t < relationTerms; t++) if (t == 0 || d[relationTerms * j + t] != 0) out[dSlot[relationTerms * j + t] * ld] += sign * d[relationTerms * j + t];
}
void newtonDerivableRows(Kernel &k);
// does relation j read a velocity (else it fixes stresses only: a frictionless slip)
bool hasVelocityTerm(const contactlaw::Slots &law, int j) {
  for (int t = 0; t < relationTerms; t++) if (law.a[relationTerms * j + t] != 0) return true;
  return false;
}
// is relation j a 3D disk's slip (its coefficients follow the slip direction at every iteration)
bool diskSlip(const contactlaw::Slots &law, int j) { return law.pair[j] >= 0 && law.piece[j] == Slip; }
// ... that reads a velocity: the base writes it as a stick row (newtonFactorBase)
bool substitutedInBase(const contactlaw::Slots &law, int j) { return diskSlip(law, j) && hasVelocityTerm(law, j); }
// The LU factors of N0, the base Newton matrix (newton.N0: the relations when it was factorized, a
// 3D disk's slip rows as stick rows, when substitute), and its inverse (newton.N0inv, computed
// from them by newtonInverse): a solve uses the factors (backward stable: the inverse alone
// loses digits on the badly conditioned matrices of a literal penalty), a correction reads the
// columns N0^-1 E_R from the inverse instead of solving for them (newtonPrepare)
bool newtonFactorBase(Kernel &k, bool substitute = true) {
  NewtonState &newton = k.newton;
  const Factorization &factor = k.factor;
  const contactlaw::Slots &law = k.law;
  const int nc = factor.nc;
  // the base: the current relations, but a 3D disk's slip rows as stick rows (c_tau = 0), whose
  // rows of H0 are -e'_j (newtonDerivableRows): those rows change at every iteration anyway, and
  // the corrections then read no computed row of H0 for them
  newton.baseA = law.a; newton.baseD = law.d; newton.baseS = law.aSlot; newton.baseT = law.dSlot;
  for (int j = 0; j < nc; j++)
    if (substitute && substitutedInBase(law, j)) {
      for (int t = 0; t < relationTerms; t++) { newton.baseA[relationTerms * j + t] = 0; newton.baseD[relationTerms * j + t] = 0; newton.baseS[relationTerms * j + t] = j; newton.baseT[relationTerms * j + t] = j; }
      newton.baseA[relationTerms * j] = 1;
    }
  newton.N0.assign((size_t)nc * nc, 0.);
  for (int jj = 0; jj < nc; jj++)
    for (int j = 0; j < nc; j++) newton.N0[j + (size_t)jj * nc] = -newton.baseA[relationTerms * j] * factor.Dw[newton.baseS[relationTerms * j] + (size_t)jj * nc];
  for (int j = 0; j < nc; j++) newton.N0[j + (size_t)newton.baseT[relationTerms * j] * nc] += newton.baseD[relationTerms * j];
  for (int j = 0; j < nc; j++)                       // the further terms (a 3D disk's Slip)
    addNewtonRow(factor, j, newton.baseA, newton.baseS, newton.baseD, newton.baseT, 1., newton.N0.data() + j, nc, 1);
  newton.pivots.resize(nc);
  int info = 0;
  dgetrf_(&nc, &nc, newton.N0.data(), &nc, newton.pivots.data(), &info);
  newton.inverted = false;
  newton.haveRef = false;
  newton.factorizations++;
  newton.haveBase = info == 0;
  newton.generation = factor.generation;
  newton.changed.clear();
  newtonDerivableRows(k);
  newton.preparedS.assign(relationTerms * nc, -1);                    // the current relations are prepared by newtonPrepare
  return newton.haveBase;
}

// N0^-1 from the factors, the first time a correction needs it
bool newtonInverse(Kernel &k) {
  NewtonState &newton = k.newton;
  const Factorization &factor = k.factor;
  if (newton.inverted) return true;
  const int nc = factor.nc;
  newton.N0inv = newton.N0;
  int info = 0, lwork = -1;
  double query = 0;
  dgetri_(&nc, newton.N0inv.data(), &nc, newton.pivots.data(), &query, &lwork, &info);
  lwork = std::max(nc, (int)query);
  std::vector<double> work(lwork);
  if (info == 0) dgetri_(&nc, newton.N0inv.data(), &nc, newton.pivots.data(), work.data(), &lwork, &info);
  newton.inverted = info == 0;
  return newton.inverted;
}

bool sameAsPrepared(const Kernel &k) {
  const NewtonState &newton = k.newton;
  const Factorization &factor = k.factor;
  const contactlaw::Slots &law = k.law;
  return newton.haveBase && newton.generation == factor.generation && law.a == newton.preparedA && law.d == newton.preparedD && law.aSlot == newton.preparedS
         && law.dSlot == newton.preparedT;
}

// The rows of H0 = Dw N0^-1 that the corrections read (newtonPrepare). Row s is known from a
// row b of N0 whose one velocity term a0 sits at slot s: N0[b,:] = sum d0 e'_dSlot0 - a0 Dw[s,:]
// and N0[b,:] N0^-1 = e'_b give H0[s,:] = (sum d0 N0^-1[dSlot0,:] - e'_b) / a0 (newton.derive[s] = b:
// a stick, a bound, a free slot). The others (the slots of a 3D disk's slip, the normal slot of
// a damped node under a linear p, whose relation has no velocity term) are computed, Dw[s,:] N0^-1,
// the first time a correction reads them, and kept with the base (newton.H, row newton.hOf[s]).
void newtonDerivableRows(Kernel &k) {
  NewtonState &newton = k.newton;
  const Factorization &factor = k.factor;
  const int nc = factor.nc;
  newton.derive.assign(nc, -1);
  newton.deriveA0.assign(nc, 0.);
  newton.hOf.assign(nc, -1);
  newton.H.clear();
  newton.hCount = 0;
  for (int b = 0; b < nc; b++) {
    int count = 0, s = -1;
    double a0 = 0, dSum = 0;
    for (int t = 0; t < relationTerms; t++) {
      if (newton.baseA[relationTerms * b + t] != 0) { count++; s = newton.baseS[relationTerms * b + t]; a0 = newton.baseA[relationTerms * b + t]; }
      dSum += std::fabs(newton.baseD[relationTerms * b + t]);
    }
    // a velocity term too small against the stress terms would lose digits in the division
    if (count == 1 && std::fabs(a0) * factor.Dw[s + (size_t)s * nc] >= 1e-3 * dSum && (newton.derive[s] < 0 || b == s)) {
      newton.derive[s] = b;
      newton.deriveA0[s] = a0;
    }
  }
}
void computeH0Rows(Kernel &k, const std::vector<int> &slots) {
  NewtonState &newton = k.newton;
  const Factorization &factor = k.factor;
  const ContactNodes &nodes = k.nodes;
  const int nc = factor.nc, count = slots.size();
  if (count == 0) return;
  // Dw[slots, :], count x nc, column-major, from Dw's columns: Dw = D W with D symmetric, so
  // Dw[s, i] = Dw[i, s] w_i / w_s
  std::vector<double> DwRows((size_t)count * nc);
  for (int i = 0; i < count; i++) {
    const double *column = factor.Dw.data() + (size_t)slots[i] * nc;
    const double ws = nodes.slotWeight[slots[i]];
    for (int col = 0; col < nc; col++) DwRows[i + (size_t)col * count] = column[col] * nodes.slotWeight[col] / ws;
  }
  newton.H.resize((size_t)(newton.hCount + count) * nc);
  const double one = 1., zero = 0.;                    // the rows one after the other: (DwRows N0^-1)' = N0^-T DwRows'
  dgemm_("T", "T", &nc, &count, &nc, &one, newton.N0inv.data(), &nc, DwRows.data(), &count, &zero, newton.H.data() + (size_t)newton.hCount * nc, &nc);
  for (int i = 0; i < count; i++) newton.hOf[slots[i]] = newton.hCount + i;
  newton.hCount += count;
}

// N0 = N, the Newton matrix of the current relations, factorized (no correction): where a
// correction cannot be made or is not accurate enough
bool newtonExactBase(Kernel &k) {
  NewtonState &newton = k.newton;
  const contactlaw::Slots &law = k.law;
  if (!newtonFactorBase(k, false)) return false;
  newton.preparedA = law.a; newton.preparedD = law.d; newton.preparedS = law.aSlot; newton.preparedT = law.dSlot;
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
bool newtonPrepare(Kernel &k) {
  NewtonState &newton = k.newton;
  const Factorization &factor = k.factor;
  const contactlaw::Slots &law = k.law;
  const int nc = factor.nc;
  if ((!newton.haveBase || newton.generation != factor.generation) && !newtonFactorBase(k)) return false;
  std::vector<int> R;
  int stale = 0;                                     // changed rows other than the base's substituted ones
  auto changedRows = [&]() {
    R.clear(); stale = 0;
    for (int j = 0; j < nc; j++)
      for (int t = 0; t < relationTerms; t++) {
        const int e = relationTerms * j + t;
        if (law.a[e] != newton.baseA[e] || law.d[e] != newton.baseD[e] || law.aSlot[e] != newton.baseS[e] || law.dSlot[e] != newton.baseT[e]) {
          R.push_back(j);
          if (!substitutedInBase(law, j)) stale++;
          break;
        }
      }
  };
  changedRows();
  // a new base when a third of the rows changed for another reason than a 3D slip
  if (stale > nc / 3) {
    if (!newtonFactorBase(k)) return false;
    changedRows();
  }
  const int r = R.size();
  newton.changed = R;
  newton.preparedA = law.a; newton.preparedD = law.d; newton.preparedS = law.aSlot; newton.preparedT = law.dSlot;
  if (r == 0) return true;
  if (!newtonInverse(k)) return newtonExactBase(k);
  // each changed row as terms on rows of N0^-1 (onInv), on e'_b (onUnit) and on computed rows of H0 (onH)
  std::vector<int> missing;
  std::vector<char> listed(nc, 0);
  for (int q = 0; q < r; q++)
    for (int t = 0; t < relationTerms; t++) {
      const int s = law.aSlot[relationTerms * R[q] + t];
      if (law.a[relationTerms * R[q] + t] != 0 && newton.hOf[s] < 0 && newton.derive[s] < 0 && !listed[s]) { missing.push_back(s); listed[s] = 1; }
    }
  computeH0Rows(k, missing);
  newton.onInv.assign(r, {}); newton.onUnit.assign(r, {}); newton.onH.assign(r, {});
  for (int q = 0; q < r; q++) {
    const int j = R[q];
    for (int t = 0; t < relationTerms; t++) if (t == 0 || law.d[relationTerms * j + t] != 0) newton.onInv[q].push_back({law.dSlot[relationTerms * j + t], law.d[relationTerms * j + t]});
    for (int t = 0; t < relationTerms; t++) {
      const double a = law.a[relationTerms * j + t];
      const int s = law.aSlot[relationTerms * j + t];
      if (a == 0) continue;
      if (newton.hOf[s] >= 0) { newton.onH[q].push_back({newton.hOf[s], -a}); continue; }
      const int b = newton.derive[s];
      const double a0 = newton.deriveA0[s];
      for (int u = 0; u < relationTerms; u++)
        if (newton.baseD[relationTerms * b + u] != 0) newton.onInv[q].push_back({newton.baseT[relationTerms * b + u], -a * newton.baseD[relationTerms * b + u] / a0});
      newton.onUnit[q].push_back({b, a / a0});
    }
  }
  // K = (N N0^-1)[R, R]: the terms on N0^-1 column by column, then those on H0 row by row
  newton.K.assign((size_t)r * r, 0.);
  std::vector<int> position(nc, -1);
  for (int l = 0; l < r; l++) position[R[l]] = l;
  for (int l = 0; l < r; l++) {
    const double *column = newton.N0inv.data() + (size_t)R[l] * nc;
    double *out = newton.K.data() + (size_t)l * r;
    for (int q = 0; q < r; q++) {
      double v = 0;
      for (const Term &e : newton.onInv[q]) v += e.coef * column[e.index];
      out[q] = v;
    }
  }
  for (int q = 0; q < r; q++) {
    for (const Term &e : newton.onUnit[q]) if (position[e.index] >= 0) newton.K[q + (size_t)position[e.index] * r] += e.coef;
    for (const Term &e : newton.onH[q]) {
      const double *row = newton.H.data() + (size_t)e.index * nc;
      for (int l = 0; l < r; l++) newton.K[q + (size_t)l * r] += e.coef * row[R[l]];
    }
  }
  newton.Kpivots.resize(r);
  int info = 0;
  dgetrf_(&r, &r, newton.K.data(), &r, newton.Kpivots.data(), &info);
  if (info != 0) return newtonExactBase(k);
  newton.corrections++;
  return true;
}

// x0 = N0^-1 b with N0's factors; or, where b differs from the last right-hand side solved with
// them (bRef, when remember) in at most nc/8 entries, xRef plus those columns of the inverse: within a
// step only the rows whose relations changed change their right-hand side
void baseSolve(Kernel &k, const double *b, double *x, bool remember) {
  NewtonState &newton = k.newton;
  const Factorization &factor = k.factor;
  const int nc = factor.nc, one = 1, inc = 1;
  if (remember && newton.inverted && newton.haveRef) {
    std::vector<int> S;
    for (int i = 0; i < nc && (int)S.size() <= nc / 8; i++) if (b[i] != newton.bRef[i]) S.push_back(i);
    if ((int)S.size() <= nc / 8) {
      std::copy(newton.xRef.begin(), newton.xRef.end(), x);
      for (int i : S) {
        const double delta = b[i] - newton.bRef[i];
        daxpy_(&nc, &delta, newton.N0inv.data() + (size_t)i * nc, &inc, x, &inc);
      }
      return;
    }
  }
  int info = 0;
  std::copy(b, b + nc, x);
  dgetrs_("N", &nc, &one, newton.N0.data(), &nc, newton.pivots.data(), x, &nc, &info);
  if (remember) { newton.bRef.assign(b, b + nc); newton.xRef.assign(x, x + nc); newton.haveRef = true; }
}
// x = N^-1 b (x and b distinct) with N0's factors and the correction: x0 = N0^-1 b (baseSolve),
// then x = x0 - Y K^-1 (N x0 - b)_R, where (N x0)_R reads Dw x0 = H0 b at the a-slots as K reads
// H0 (a derived row: (sum d0 x0[dSlot0] - b_b)/a0); newtonSolve checks it
void correctedSolve(Kernel &k, const double *b, double *x, bool remember = false) {
  NewtonState &newton = k.newton;
  const Factorization &factor = k.factor;
  const int nc = factor.nc, one = 1, r = newton.changed.size();
  int info = 0;
  baseSolve(k, b, x, remember);
  if (r == 0) return;
  std::vector<double> t(r, 0.), hb(newton.hCount, 0.);     // hb = H0 b on the computed rows
  if (newton.hCount > 0) {
    const double plus = 1., zero = 0.;
    const int inc = 1;
    dgemv_("T", &nc, &newton.hCount, &plus, newton.H.data(), &nc, b, &inc, &zero, hb.data(), &inc);
  }
  for (int q = 0; q < r; q++) {
    double v = -b[newton.changed[q]];
    for (const Term &e : newton.onInv[q]) v += e.coef * x[e.index];
    for (const Term &e : newton.onUnit[q]) v += e.coef * b[e.index];
    for (const Term &e : newton.onH[q]) v += e.coef * hb[e.index];
    t[q] = v;
  }
  dgetrs_("N", &r, &one, newton.K.data(), &r, newton.Kpivots.data(), t.data(), &r, &info);
  for (int l = 0; l < r; l++) {
    const double minus = -t[l];
    const int inc = 1;
    daxpy_(&nc, &minus, newton.N0inv.data() + (size_t)newton.changed[l] * nc, &inc, x, &inc);
  }
}
// the largest row residual of N x = b relative to the size of the row's terms, |b_j| + |its
// terms at x| + (sum |a_jt| max|Dw x| + sum |d_jt| max|x|) / 10: a row is read against its own
// terms, but not below a tenth of the scale of the others (a row whose terms all vanish at the
// solution, a free slot's m_j = 0, would read round-off as a relative error of 1); the
// residuals in res; Dw x in newton.Dx (the safeguard's velocities at x reuse it)
double rowResidual(Kernel &k, const double *b, const double *x, double *res) {
  NewtonState &newton = k.newton;
  const Factorization &factor = k.factor;
  const contactlaw::Slots &law = k.law;
  const int nc = factor.nc, inc = 1;
  newton.Dx.assign(nc, 0.);
  std::vector<double> &Dx = newton.Dx;
  const double plus = 1., zero = 0.;
  dgemv_("N", &nc, &nc, &plus, factor.Dw.data(), &nc, x, &inc, &zero, Dx.data(), &inc);
  newton.haveDx = true;
  double worst = 0, xMax = 0, DxMax = 0;
  for (int j = 0; j < nc; j++) { xMax = std::max(xMax, std::fabs(x[j])); DxMax = std::max(DxMax, std::fabs(Dx[j])); }
  for (int j = 0; j < nc; j++) {
    double a = -law.a[relationTerms * j] * Dx[law.aSlot[relationTerms * j]], d = law.d[relationTerms * j] * x[law.dSlot[relationTerms * j]];
    double aSize = std::fabs(law.a[relationTerms * j]), dSize = std::fabs(law.d[relationTerms * j]);
    for (int t = 1; t < relationTerms; t++) {                    // the further terms (a 3D disk's Slip)
      if (law.a[relationTerms * j + t] != 0) a -= law.a[relationTerms * j + t] * Dx[law.aSlot[relationTerms * j + t]];
      if (law.d[relationTerms * j + t] != 0) d += law.d[relationTerms * j + t] * x[law.dSlot[relationTerms * j + t]];
      aSize += std::fabs(law.a[relationTerms * j + t]); dSize += std::fabs(law.d[relationTerms * j + t]);
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
void exactStressRows(const Kernel &k, const double *b, double *x) {
  const Factorization &factor = k.factor;
  const contactlaw::Slots &law = k.law;
  for (int j = 0; j < factor.nc; j++) {
    if (hasVelocityTerm(law, j)) continue;
    int terms = 0;
    for (int t = 0; t < relationTerms; t++) terms += t == 0 || law.d[relationTerms * j + t] != 0;
    if (terms == 1 && law.d[relationTerms * j] != 0) x[law.dSlot[relationTerms * j]] = b[j] / law.d[relationTerms * j];
  }
}
// x = N^-1 b to a hundredth of the tolerance: the row residual of the corrected solve
// (rowResidual) must be below max(1e-15, min(1e-6, tol / 100)). Once the pieces are right, a
// piecewise-linear law is then solved to tol in one iteration (finite termination: the paper
// scene takes 159 iterations at every tol from 1e-6 to 1e-12), and a steep damping table still
// converges (at tol / 10 it stalled at 8.5e-10); a fixed 1e-13, read row by row against each
// row's own terms, refined most solves of a 3D slab for nothing. Above the bound, one step of
// iterative refinement; still above max(1e-11, the bound), N0 = N is factorized.
bool newtonSolve(Kernel &k, const double *b, double *x) {
  NewtonState &newton = k.newton;
  const Factorization &factor = k.factor;
  const SolverSettings &settings = k.settings;
  const int nc = factor.nc;
  newton.haveDx = false;
  correctedSolve(k, b, x, true);
  if (newton.changed.empty()) return true;
  exactStressRows(k, b, x);
  const double bound = std::max(1e-15, std::min(1e-6, 0.01 * settings.tol));
  std::vector<double> res(nc), dx(nc);
  double worst = rowResidual(k, b, x, res.data());
  if (worst > bound) {
    correctedSolve(k, res.data(), dx.data());
    for (int j = 0; j < nc; j++) x[j] += dx[j];
    exactStressRows(k, b, x);
    newton.refinements++;
    worst = rowResidual(k, b, x, res.data());
  }
  if (!(worst <= std::max(1e-11, bound))) {
    if (!newtonExactBase(k)) return false;
    correctedSolve(k, b, x);
    newton.haveDx = false;
  }
  return true;
}

}  // namespace

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
int guard(Kernel &k, int it, const double *c, const double *m) {
  NewtonState &newton = k.newton;
  contactlaw::Slots &law = k.law;
  const SolverSettings &settings = k.settings;
  if ((int)newton.seen.size() < it + 1) newton.seen.resize(it + 1, -1.);
  if (it == 0) { std::fill(newton.seen.begin(), newton.seen.end(), -1.); newton.rDefault = law.r; }
  double fingerprint = 0;
  for (int j = 0; j < law.n; j++)
  {
    double term = law.key[j];
    if (!diskSlip(law, j)) {                              // a disk's slip row changes at every iteration: its piece only
      term += 0.6180339887 * law.a[relationTerms * j] + 0.4142135624 * law.d[relationTerms * j];
      for (int t = 1; t < relationTerms; t++) term += (0.6180339887 * law.a[relationTerms * j + t] + 0.4142135624 * law.d[relationTerms * j + t]) * (t + 1);
    }
    fingerprint += term * (1. + ((7919 * j + 104729) % 1009));
  }
  int halved = 0;
  // the scale of the current r against the operator's (r = 1): halving only down to it
  const double scale = law.n > 0 && newton.rDefault[0] > 0 ? settings.r * law.r[0] / newton.rDefault[0] : 0.;
  if (settings.safeguards && scale > 1)
    for (int earlier = 0; earlier < it; earlier++)
      if (newton.seen[earlier] == fingerprint) {
        for (int j = 0; j < law.n; j++) law.setAugmentation(j, 0.5 * law.r[j]);
        newton.halvings++;
        std::fill(newton.seen.begin(), newton.seen.end(), -1.);
        law.evaluate(c, m);
        halved = 1;
        break;
      }
  newton.seen[it] = fingerprint;
  return halved;
}
// What every solver's convergence test and Newton's safeguard read: the natural residual and
// its merit at the operator's scale r_j = 1/(Dw)_jj (the default -r 1), whatever -r and the
// guard's halvings. r only steers which pieces Newton tries next; measured at a large r the
// residual would weigh velocity mismatches r times more, at a small r stress mismatches, until
// round-off alone exceeds tol, and a merit that changes with r cannot compare iterates across
// a halving. Returns the residual, sets merit; the law's state is left at (c, m) and the
// current r (the pieces Newton linearizes next).
double referenceEvaluate(Kernel &k, const double *c, const double *m, double &merit) {
  const Factorization &factor = k.factor;
  contactlaw::Slots &law = k.law;
  if (factor.rReference.empty() || factor.rReference == law.r) {
    const double residual = law.evaluate(c, m);
    merit = law.merit();
    return residual;
  }
  const std::vector<double> current = law.r;
  for (int j = 0; j < law.n; j++) law.setAugmentation(j, factor.rReference[j]);
  const double reference = law.evaluate(c, m);
  merit = law.merit();
  for (int j = 0; j < law.n; j++) law.setAugmentation(j, current[j]);
  law.evaluate(c, m);
  return reference;
}
// r back to the user's after a step
void endStep(Kernel &k) {
  const NewtonState &newton = k.newton;
  contactlaw::Slots &law = k.law;
  if (!newton.rDefault.empty() && newton.rDefault != law.r) for (int j = 0; j < law.n; j++) law.setAugmentation(j, newton.rDefault[j]);
}

// A step has converged when its natural residual meets tol and no slot's status contradicts
// its piece (Slots::unresolvedStatuses, counted in unresolved; 0 while the residual is above tol).
bool stepConverged(Kernel &k, double residual, const double *c, int &unresolved) {
  const contactlaw::Slots &law = k.law;
  const SolverSettings &settings = k.settings;
  unresolved = residual <= settings.tol ? law.unresolvedStatuses(c) : 0;
  return residual <= settings.tol && unresolved == 0;
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
// The watchdog: when the safeguard has replaced two Newton iterates in a row, the Newton iterates
// are kept whatever their merit (at most watchdogLength in a row), until one lowers the merit of
// the reference (the iterate kept when it started) by the Armijo margin; if none does, or an
// iterate comes back to (nearly) the pieces of one kept before with no lower merit (a cycle), the
// iterate goes back to the reference and the monotone safeguard goes on, the watchdog not
// starting again before a Newton iterate passes or the merit has halved since. A slip front spreading along a curved face
// raises the merit at every Newton iterate of a step that converges in about ten (the half-disk:
// docs/stability.md, "Hard bodies"); two replacements in a row,
// not one, because a step of the paper's block starts with two, which its references record.
namespace {
const int watchdogLength = 12;
const double watchdogRestart = 0.5;   // a spent watchdog may start again below this times its reference's merit
bool accept(const SolverSettings &settings, double merit, double trialMerit, double trialResidual, double step = 1) {
  return trialMerit < (1 - 1e-4 * step) * merit || trialResidual <= settings.tol;
}
// safeguardStep's outcomes (edp/lib/solvers.idp reads 0 and 3 as a kept Newton iterate)
enum SafeguardOutcome { NewtonKept = 0, NewtonShortened = 1, FixedPointTaken = 2, WatchdogKept = 3, WatchdogReturned = 4 };
}  // namespace
int replaceNewtonIterate(Kernel &k, const double *cFree, const double *previous, const double *newtonM, double before,
                         double trialMerit, double *c, double *m, double &merit, double &residual, double &step);
// From the previous iterate and the Newton iterate (multipliers; c = cFree - Dw m), set (c, m)
// to the iterate the safeguard keeps and the law's state to its evaluation; its natural
// residual and merit (referenceEvaluate) in residual and merit (on entry: the previous
// iterate's merit), the step length in step (0 for a fixed-point iteration).
int safeguardStep(Kernel &k, const double *cFree, const double *previous, const double *newtonM, double &merit,
                  double *c, double *m, double &residual, double &step, const double *DwNewtonM) {
  NewtonState &newton = k.newton;
  const Factorization &factor = k.factor;
  const SolverSettings &settings = k.settings;
  const int nc = factor.nc;
  const double before = merit;
  newton.keptOverReplacements = false;
  std::copy(newtonM, newtonM + nc, m);
  if (DwNewtonM) for (int j = 0; j < nc; j++) c[j] = cFree[j] - DwNewtonM[j];   // Dw m known already
  else velocities(k, cFree, m, c);
  double trial = 0;
  residual = referenceEvaluate(k, c, m, trial);
  step = 1;
  NewtonState::Watchdog &watch = newton.watch;
  if (!settings.safeguards) { merit = trial; return NewtonKept; }
  if (watch.active) {
    if (accept(settings, watch.merit, trial, residual)) { watch.active = false; watch.replacedInRow = 0; merit = trial; return NewtonKept; }
    // a cycle: no lower merit than an iterate it kept before, with its pieces, or with nearly
    // its pieces (at most max(2, n/50) slots apart) two or more iterates back (the cylinder on
    // fine meshes alternated between two sets of pieces a slot or two apart; from one iterate
    // to the next a few slots moving while the merit rises is Newton's way); a non-finite
    // iterate ends it too
    bool cycle = !std::isfinite(trial);
    const int near = std::max(2, k.law.n / 50);
    for (size_t e = 0; e < watch.keys.size() && !cycle; e++) {
      if (trial < watch.merits[e]) continue;
      const int allowed = e + 1 < watch.keys.size() ? near : 0;
      int apart = 0;
      for (int j = 0; j < k.law.n && apart <= allowed; j++) apart += watch.keys[e][j] != k.law.key[j];
      cycle = apart <= allowed;
    }
    watch.keys.push_back(k.law.key);
    watch.merits.push_back(trial);
    if ((int)watch.keys.size() < watchdogLength && !cycle) { merit = trial; return WatchdogKept; }
    watch.active = false; watch.spent = true; watch.replacedInRow = 0;   // none lowered the reference's merit: back to it
    std::copy(watch.m.begin(), watch.m.end(), m);
    std::copy(watch.c.begin(), watch.c.end(), c);
    residual = referenceEvaluate(k, c, m, merit);
    step = 0;
    newton.watchdogReturns++;
    return WatchdogReturned;
  }
  if (accept(settings, before, trial, residual)) { merit = trial; watch.replacedInRow = 0; watch.spent = false; return NewtonKept; }
  const int outcome = replaceNewtonIterate(k, cFree, previous, newtonM, before, trial, c, m, merit, residual, step);
  if (outcome == NewtonKept) return outcome;
  // spent: not again before a Newton iterate passes, or before the monotone safeguard has
  // halved the merit of the iterate it went back to (the iterate has moved away from where
  // Newton cycled, and Newton from there takes another path: the twisted block at mu = 1 on
  // 16 x 8 x 4 crept 64 iterations at step 1 after its watchdog found a 2-cycle). Only where
  // the cycle guard cannot break cycles by halving r (r at the operator's scale or below, as
  // the default), and once a step: above it a review found the restart hurt the paper's block
  // (at r >= 1e3 the merit halves within one or two safeguarded iterations, the watchdog went
  // back and forth five times in step 1 and reached the cap at r = 5e3; 132 x 66 at r = 1e4
  // even with one restart)
  const double rScale = k.law.n > 0 && !newton.rDefault.empty() && newton.rDefault[0] > 0 ? settings.r * k.law.r[0] / newton.rDefault[0] : 0.;
  if (watch.spent && watch.restarts < 1 && rScale <= 1 && merit < watchdogRestart * watch.merit) { watch.spent = false; watch.restarts++; }
  if (++watch.replacedInRow >= 2 && !watch.spent) {
    watch.active = true; watch.merit = merit;
    watch.keys.clear(); watch.merits.clear();
    watch.c.assign(c, c + nc); watch.m.assign(m, m + nc);
    newton.watchdogs++;
  }
  return outcome;
}
// The monotone safeguard's replacement of a rejected Newton iterate newtonM (its merit
// trialMerit): the better of a shortened Newton step and a fixed-point iteration from the
// previous iterate (its merit before); the Newton iterate itself where both are worse
int replaceNewtonIterate(Kernel &k, const double *cFree, const double *previous, const double *newtonM, double before,
                         double trialMerit, double *c, double *m, double &merit, double &residual, double &step) {
  NewtonState &newton = k.newton;
  const SolverSettings &settings = k.settings;
  const int nc = k.factor.nc;
  // the line search's candidate
  std::vector<double> mCut(nc);
  double cutMerit = INFINITY, cutStep = 0;
  for (double t = 0.5; t > 1. / 1500; t *= 0.5) {
    for (int j = 0; j < nc; j++) m[j] = previous[j] + t * (newtonM[j] - previous[j]);
    velocities(k, cFree, m, c);
    double tm = 0;
    const double tr = referenceEvaluate(k, c, m, tm);
    if (accept(settings, before, tm, tr, t)) { cutMerit = tm; cutStep = t; mCut.assign(m, m + nc); break; }
  }
  // the fixed point's candidate
  std::copy(previous, previous + nc, m);
  residual = fixedPointIteration(k, cFree, c, m, merit);
  step = 0;
  if (std::isfinite(trialMerit) && !(cutMerit < trialMerit) && !(merit < trialMerit)) {
    // neither is better than the Newton iterate itself (one at a round-off floor, which cannot
    // lower the merit further): keep it, rather than leave the floor and come back to it
    std::copy(newtonM, newtonM + nc, m);
    velocities(k, cFree, m, c);
    residual = referenceEvaluate(k, c, m, merit);
    step = 1;
    newton.keptOverReplacements = true;
    return NewtonKept;
  }
  if (!(cutMerit < merit)) { newton.fallbacks++; return FixedPointTaken; }
  std::copy(mCut.begin(), mCut.end(), m);
  velocities(k, cFree, m, c);
  residual = referenceEvaluate(k, c, m, merit);
  step = cutStep;
  newton.cuts++;
  return NewtonShortened;
}

// Are the pieces of the law's last evaluate() those of the last call within the step (Newton's
// correction form: newtonIterations, and the script view)? newtonStart forgets them.
bool piecesRepeat(Kernel &k) {
  NewtonState &newton = k.newton;
  const bool repeat = newton.lastKeys == k.law.key;
  newton.lastKeys = k.law.key;
  return repeat;
}

// The start of a Newton step: the log's iteration 0 (the previous step's multipliers with this
// step's load, c = cFree - Dw m) and its merit, which the first iterate must lower; then the law
// is evaluated at (c, m), the previous step's solution, whose pieces the first Newton step
// linearizes. Returns the natural residual at (c, m).
double newtonStart(Kernel &k, const double *cFree, const double *c, const double *m, double &merit) {
  const Factorization &factor = k.factor;
  std::vector<double> cStart(factor.nc);
  velocities(k, cFree, m, cStart.data());
  k.newton.watch = NewtonState::Watchdog();
  k.newton.lastKeys.clear();
  roundoffScale(k, cFree, m);
  logIteration(k, 0, referenceEvaluate(k, cStart.data(), m, merit));
  double unused = 0;
  return referenceEvaluate(k, c, m, unused);
}

// -verbose: one line an iteration on the standard error, the residual and how many slots entered
// (+) or left (-) each piece of the law since the line before; iteration 0 gives the count of
// each piece at the start of the step (the previous step's multipliers with this step's load).
// Every solver calls it (the script ones through contactNewtonLog), after the law's evaluate()
// of the iterate; the first call says what the slots are.
void logIteration(Kernel &k, int it, double residual, int outcome, double step) {
  const contactlaw::Slots &law = k.law;
  SolverLog &log = k.log;
  if (!k.settings.verbose) return;
  if (!log.explained) {
    int normal = 0;
    for (size_t j = 0; j < law.piece.size(); j++) normal += law.normal[j] != 0;
    std::fprintf(stderr, "Solver log: %d normal slots (pieces free, damped, bound) and %d tangential ones (stick, slip; "
                 "a node with a fixed velocity component has none); per iteration, the slots that entered (+) or "
                 "left (-) each piece\n", normal, (int)law.piece.size() - normal);
    log.explained = true;
  }
  static const char *const pieceName[] = {"free", "damped", "bound", "stick", "slip"};
  int entered[5] = {0, 0, 0, 0, 0}, left[5] = {0, 0, 0, 0, 0};
  const bool first = it == 0 || log.loggedPieces.size() != law.piece.size();
  for (size_t j = 0; j < law.piece.size(); j++) {
    if (first) entered[law.piece[j]]++;
    else if (law.piece[j] != log.loggedPieces[j]) { entered[law.piece[j]]++; left[log.loggedPieces[j]]++; }
  }
  log.loggedPieces = law.piece;
  std::string line = "  iteration " + std::to_string(it);
  char number[32];
  std::snprintf(number, sizeof number, "%.3e", residual);
  line += std::string(first ? " (the previous step's multipliers, this step's load)" : "") + ": residual " + number;
  if (outcome == FixedPointTaken) line += " (the Newton iterate did not lower the merit: one fixed-point iteration instead)";
  if (outcome == NewtonShortened)
    line += " (the Newton iterate did not lower the merit: the step " + std::to_string((int)std::lround(1 / step)) + " times shorter)";
  if (outcome == NewtonKept && k.newton.keptOverReplacements)
    line += " (the Newton iterate did not lower the merit, but neither replacement did better: kept)";
  if (outcome == WatchdogKept) line += " (watchdog: the Newton iterate kept although the merit rose)";
  if (outcome == WatchdogReturned) line += " (watchdog: no kept iterate lowered the merit: back to where it started)";
  line += first ? "; slots:" : "; changed:";
  int shown = 0;
  for (int p = 0; p < 5; p++) {
    if (first && entered[p]) line += std::string(shown++ ? ", " : " ") + pieceName[p] + " " + std::to_string(entered[p]);
    if (!first && entered[p]) line += std::string(shown++ ? ", " : " ") + pieceName[p] + " +" + std::to_string(entered[p]);
    if (!first && left[p]) line += std::string(shown++ ? ", " : " ") + pieceName[p] + " -" + std::to_string(left[p]);
  }
  if (!shown) line += " none";
  std::fprintf(stderr, "%s\n", line.c_str());
}

void requireSolver(const Kernel &k, const char *who) {
  requireNodes(k, who);
  requireDelassus(k, who);
}

// The iterations of one Newton solve from (c, m): sets residual, it, unresolved; true when
// the step converged (stepConverged)
namespace {
bool newtonIterations(Kernel &k, const std::vector<double> &cFree, std::vector<double> &c, std::vector<double> &m, double &residual,
                      int &it, int &unresolved) {
  const NewtonState &newton = k.newton;
  const Factorization &factor = k.factor;
  contactlaw::Slots &law = k.law;
  const SolverSettings &settings = k.settings;
  const int nc = factor.nc;
  std::vector<double> previous(nc), rhs(nc), newtonM(nc), res(nc);
  double merit = 0;
  residual = newtonStart(k, cFree.data(), c.data(), m.data(), merit);
  it = 0; unresolved = 0;
  bool done = false;
  while (true) {
    law.relations(c.data());
    if (guard(k, it, c.data(), m.data())) law.relations(c.data());   // r halved: the pieces at the new r
    if (!sameAsPrepared(k) && !newtonPrepare(k)) { residual = NAN; break; }
    for (int j = 0; j < nc; j++) {
      rhs[j] = law.h[j] - law.a[relationTerms * j] * cFree[law.aSlot[relationTerms * j]];
      for (int t = 1; t < relationTerms; t++) if (law.a[relationTerms * j + t] != 0) rhs[j] -= law.a[relationTerms * j + t] * cFree[law.aSlot[relationTerms * j + t]];
    }
    previous = m;
    // the pieces of the last iteration again (a round-off floor, or a 3D disk's slip, whose rows
    // follow the slip direction): Newton as a correction of m, N d = rhs - N m, which refines
    // the last solve where a new solve from scratch would repeat its round-off (the sloped 3D
    // body of docs/stability.md crept at 1e-9 with the pieces settled)
    const bool correction = piecesRepeat(k);
    if (correction) {
      rowResidual(k, rhs.data(), m.data(), res.data());
      if (!newtonSolve(k, res.data(), newtonM.data())) { residual = NAN; break; }
      for (int j = 0; j < nc; j++) newtonM[j] += m[j];
    }
    else if (!newtonSolve(k, rhs.data(), newtonM.data())) { residual = NAN; break; }
    double step = 1;
    const int outcome = safeguardStep(k, cFree.data(), previous.data(), newtonM.data(), merit, c.data(), m.data(), residual, step,
                                      newton.haveDx && !correction ? newton.Dx.data() : nullptr);
    it++;
    logIteration(k, it, residual, outcome, step);
    done = stepConverged(k, residual, c.data(), unresolved);
    if (done || it >= settings.maxit || std::isnan(residual) || std::isinf(residual)) break;
  }
  endStep(k);
  return done;
}
}  // namespace

// One step's Newton. With a disk law (3D pairs), a safeguarded Newton that does not converge
// within -maxit is run again from the step's start without its safeguards (retry), as many
// iterations more: the disk's slip piece is curved, and on thin plates the merit test rejects
// the iterates of a Newton that converges (docs/stability.md, "Three dimensions": slab3d-thin
// at Lz = 0.025 and 0.01, where every Newton iterate was replaced and the fixed-point
// iterations crept, and plain Newton converges in 14 to 16). The iterations of both count.
long newtonStep(Kernel &k, const double *cFreeIn, double *cInOut, double *mInOut, double info[solverInfoColumnCount]) {
  requireSolver(k, "contactKernelNewton");
  const int nc = k.factor.nc;
  std::vector<double> cFree(cFreeIn, cFreeIn + nc), c(cInOut, cInOut + nc), m(mInOut, mInOut + nc);
  const std::vector<double> cStart = c, mStart = m;
  double residual = 0;
  int it = 0, unresolved = 0;
  bool done = newtonIterations(k, cFree, c, m, residual, it, unresolved);
  if (!done && k.settings.safeguards && k.law.hasPairs() && std::isfinite(residual)) {
    int more = 0;
    c = cStart; m = mStart;
    k.settings.safeguards = false;
    k.newton.retries++;
    if (k.settings.verbose) std::fprintf(stderr, "  (the safeguarded Newton did not converge in %d iterations: plain Newton from the step's start)\n", it);
    done = newtonIterations(k, cFree, c, m, residual, more, unresolved);
    k.settings.safeguards = true;
    it += more;
  }
  std::copy(c.begin(), c.end(), cInOut);
  std::copy(m.begin(), m.end(), mInOut);
  info[InfoResidual] = residual; info[InfoIterations] = it; info[InfoUnresolved] = unresolved; info[InfoStalled] = 0;
  return done ? it : -1;
}

}  // namespace contactkernel
