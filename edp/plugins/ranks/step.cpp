// step.cpp: a step of the run on ranks (contactRanksStep on rank 0, contactRanksServe on the
// others): the semismooth Newton on the whole system described in ranks.cpp, the gathers of
// its results on rank 0, and the record's products M x, A x, B x on the ranks' rows.
#include "ranks.hpp"

namespace ranks {

// ---------------------------------------------------------------- a step
struct Reduced { double residual, meritSquared; long unresolved; };
// the pieces, the residual (its largest over the ranks), the merit's square and the unresolved
// statuses (their sums) at the rank's (c, m)
Reduced evaluateAll(std::vector<double> &c, std::vector<double> &m) {
  contactlaw::Slots &law = state.law;
  const double worst = law.n ? law.evaluate(c.data(), m.data()) : 0.;
  const double merit = law.n ? law.merit() : 0.;
  double residual = std::isnan(worst) ? INFINITY : worst, sums[2] = {std::isnan(merit) ? INFINITY : merit * merit,
                                                                       law.n ? (double)law.unresolvedStatuses(c.data()) : 0.};
  MPI_Allreduce(MPI_IN_PLACE, &residual, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return {residual, sums[0], (long)sums[1]};
}

// direct: counts the numeric factorizations of MUMPS's factor (each changes its state; a solve
// does not): summary.txt's ranks_preconditioner_builds, 1 a run
void countFactorizations() {
  PC pc;
  Mat factor = nullptr;
  PetscObjectState now;
  CHECK(KSPGetPC(state.ksp, &pc));
  CHECK(PCFactorGetMatrix(pc, &factor));
  CHECK(PetscObjectStateGet((PetscObject)factor, &now));
  if (now != state.factorState) { state.factorizations++; state.factorState = now; }
}

// A x = b by the rank's KSP (A its operator and preconditioner's), then its true residual
// |b - A x| computed here (PETSc's own norm is 0 under -ranks_ksp_type preonly or
// -ranks_ksp_norm_type none): false if either failed, state.failure then saying why (what: the
// solve's name), or "" for a non-finite residual (exit 5, as for one process)
bool solveChecked(Mat A, Vec b, Vec x, const char *what) {
  CHECK(KSPSetOperators(state.ksp, A, A));
  CHECK(KSPSolve(state.ksp, b, x));
  if (state.direct) countFactorizations();
  KSPConvergedReason reason;
  PetscInt its;
  CHECK(KSPGetConvergedReason(state.ksp, &reason));
  CHECK(KSPGetIterationNumber(state.ksp, &its));
  state.linearSolves++;
  state.linearIterations += its;
  if (reason == KSP_DIVERGED_NANORINF) return false;   // a non-finite residual: exit 5, as for one process
  PetscReal norm = 0, bnorm = 0;
  CHECK(MatMult(A, x, state.Sw));
  CHECK(VecAYPX(state.Sw, -1., b));
  CHECK(VecNorm(state.Sw, NORM_2, &norm));
  CHECK(VecNorm(b, NORM_2, &bnorm));
  if (!std::isfinite(norm)) return false;              // a non-finite solution: exit 5
  // whatever PETSc's options say (PETSC_OPTIONS), a solve whose true residual is above 1e-8 |b|
  // is not a solution: the step fails rather than writing results of it
  if (reason >= 0 && !(norm <= 1e-8 * bnorm)) reason = KSP_DIVERGED_DTOL;
  if (reason < 0) {
    char text[400];
    std::snprintf(text, sizeof text, "%s (-ranksolver %s: %s) stopped after %d iterations, relative residual %.3g (PETSc's reason %s)",
                  what, state.direct ? "direct" : "iterative", builtSolver().c_str(), (int)its, bnorm > 0 ? (double)(norm / bnorm) : (double)norm,
                  norm > 1e-8 * bnorm && reason == KSP_DIVERGED_DTOL ? "DIVERGED_DTOL, or a residual above 1e-8 after its own test" : KSPConvergedReasons[reason]);
    state.failure = text + underOptions();
    return false;
  }
  return true;
}

// the Newton system of the pieces at the last evaluation, solved: w, then c and m of the slots
bool newtonSolve(std::vector<double> &c, std::vector<double> &m) {
  contactlaw::Slots &law = state.law;
  law.relations(c.data());
  const int T = contactlaw::Slots::termsPerRelation;
  CHECK(MatCopy(state.Srot, state.J, SAME_NONZERO_PATTERN));
  CHECK(VecCopy(state.brot, state.bJ));
  CHECK(VecSet(state.x0, 0.));
  std::vector<PetscInt> rows = state.fixedRows;
  for (const RankNode &node : state.nodes) {
    const int ns = node.slots;
    int fixedOf[3] = {0, 0, 0}, where[3] = {-1, -1, -1};     // where: a slot's place in the node
    for (int s = 0; s < ns; s++) where[s] = node.local[s];
    auto place = [&](int l) { for (int s = 0; s < ns; s++) if (node.local[s] == l) return s; return -1; };
    double A[3][3] = {{0}}, D[3][3] = {{0}}, h[3] = {0, 0, 0};
    for (int s = 0; s < ns; s++) {
      const int l = where[s];
      bool hasD = false;
      for (int t = 0; t < T; t++) {
        const double a = law.a[T * l + t], dd = law.d[T * l + t];
        if (a != 0) {
          const int p = place(law.aSlot[T * l + t]);
          if (p < 0) rankFail(3, "a relation of the law reaches a slot of another node: -ranks cannot eliminate it");
          A[s][p] += a;
        }
        if (dd != 0) {
          const int p = place(law.dSlot[T * l + t]);
          if (p < 0) rankFail(3, "a relation of the law reaches a slot of another node: -ranks cannot eliminate it");
          D[s][p] += dd;
          hasD = true;
        }
      }
      h[s] = law.h[l];
      fixedOf[s] = !hasD;
    }
    // fixed slots: c_s = h_s / a_ss, a Dirichlet row of the rotated system
    for (int s = 0; s < ns; s++) if (fixedOf[s]) {
      for (int p = 0; p < ns; p++)
        if (p != s && A[s][p] != 0) rankFail(3, "a relation that fixes a velocity reads another slot: -ranks cannot take it as a Dirichlet row");
      if (!(A[s][s] != 0)) rankFail(3, "a relation with neither velocity nor multiplier");
      CHECK(VecSetValue(state.x0, node.row[s], h[s] / A[s][s], INSERT_VALUES));
      rows.push_back(node.row[s]);
    }
    // the others: m_F = D_FF^-1 (h_F - A_F c); the momentum row of slot s gains -W_s (D^-1 A)_s. c
    int F[3], nf = 0;
    for (int s = 0; s < ns; s++) if (!fixedOf[s]) F[nf++] = s;
    if (nf == 0) continue;
    for (int a = 0; a < nf; a++) for (int s = 0; s < ns; s++)
      if (fixedOf[s] && D[F[a]][s] != 0) rankFail(3, "a relation reads the multiplier of a slot whose velocity is fixed: -ranks cannot eliminate it");
    double Dff[3][3], inv[3][3];
    for (int a = 0; a < nf; a++) for (int b = 0; b < nf; b++) Dff[a][b] = D[F[a]][F[b]];
    // the inverse of a 1x1, 2x2 or 3x3 block (Gauss-Jordan with partial pivoting)
    double M[3][6];
    for (int a = 0; a < nf; a++) for (int b = 0; b < 2 * nf; b++) M[a][b] = b < nf ? Dff[a][b] : (b - nf == a ? 1. : 0.);
    for (int col = 0; col < nf; col++) {
      int pivot = col;
      for (int a = col + 1; a < nf; a++) if (std::fabs(M[a][col]) > std::fabs(M[pivot][col])) pivot = a;
      if (!(std::fabs(M[pivot][col]) > 0)) rankFail(3, "a node's multiplier block of the relations is singular");
      for (int b = 0; b < 2 * nf; b++) std::swap(M[col][b], M[pivot][b]);
      const double p = M[col][col];
      for (int b = 0; b < 2 * nf; b++) M[col][b] /= p;
      for (int a = 0; a < nf; a++) if (a != col) {
        const double f = M[a][col];
        for (int b = 0; b < 2 * nf; b++) M[a][b] -= f * M[col][b];
      }
    }
    for (int a = 0; a < nf; a++) for (int b = 0; b < nf; b++) inv[a][b] = M[a][nf + b];
    for (int a = 0; a < nf; a++) {
      const int s = F[a], l = where[s];
      double coupling[3] = {0, 0, 0}, hs = 0;
      for (int b = 0; b < nf; b++) {
        hs += inv[a][b] * h[F[b]];
        for (int p = 0; p < ns; p++) coupling[p] += inv[a][b] * A[F[b]][p];
      }
      for (int p = 0; p < ns; p++) if (coupling[p] != 0)
        CHECK(MatSetValue(state.J, node.row[s], node.row[p], -state.W[l] * coupling[p], ADD_VALUES));
      CHECK(VecSetValue(state.bJ, node.row[s], -state.W[l] * hs, ADD_VALUES));
    }
  }
  CHECK(MatAssemblyBegin(state.J, MAT_FINAL_ASSEMBLY));
  CHECK(MatAssemblyEnd(state.J, MAT_FINAL_ASSEMBLY));
  for (Vec v : {state.x0, state.bJ}) { CHECK(VecAssemblyBegin(v)); CHECK(VecAssemblyEnd(v)); }
  std::sort(rows.begin(), rows.end());
  CHECK(MatZeroRowsColumns(state.J, (PetscInt)rows.size(), rows.data(), 1., state.x0, state.bJ));
  if (!solveChecked(state.J, state.bJ, state.w, "the linear solve of a Newton iteration")) return false;
  // c on the slots, m from the momentum rows: m = (R'b - R'SR w) / W
  CHECK(MatMult(state.Srot, state.w, state.Sw));
  const PetscScalar *wv, *bv, *sv;
  CHECK(VecGetArrayRead(state.w, &wv));
  CHECK(VecGetArrayRead(state.brot, &bv));
  CHECK(VecGetArrayRead(state.Sw, &sv));
  for (int l = 0; l < law.n; l++) {
    const PetscInt i = state.slotRow[l] - state.first;
    c[l] = wv[i];
    m[l] = (bv[i] - sv[i]) / state.W[l];
  }
  CHECK(VecRestoreArrayRead(state.w, &wv));
  CHECK(VecRestoreArrayRead(state.brot, &bv));
  CHECK(VecRestoreArrayRead(state.Sw, &sv));
  return true;
}

// gathers the owned values (per row, or per slot) into rank 0's array in FreeFEM's numbering
void gatherRows(const PetscScalar *owned, double *out) {
  std::vector<double> all(state.rank == 0 ? state.n : 0);
  MPI_Gatherv(owned, (int)state.owned, MPI_DOUBLE, all.data(), state.rowCounts.data(), state.rowDispls.data(), MPI_DOUBLE, 0,
              MPI_COMM_WORLD);
  if (state.rank == 0) for (PetscInt i = 0; i < state.n; i++) out[state.allDofs[i]] = all[i];
}
void gatherRows(const PetscScalar *owned, KN<double> &out) {
  if (state.rank == 0 && out.N() != state.n) out.resize(state.n);
  gatherRows(owned, state.rank == 0 ? &out[0] : nullptr);
}
// rank 0's array in FreeFEM's numbering, scattered into the owned rows of v
void scatterRows(const double *in, Vec v) {
  std::vector<double> all(state.rank == 0 ? state.n : 0);
  if (state.rank == 0) for (PetscInt i = 0; i < state.n; i++) all[i] = in[state.allDofs[i]];
  PetscScalar *owned;
  CHECK(VecGetArray(v, &owned));
  MPI_Scatterv(all.data(), state.rowCounts.data(), state.rowDispls.data(), MPI_DOUBLE, owned, (int)state.owned, MPI_DOUBLE, 0,
               MPI_COMM_WORLD);
  CHECK(VecRestoreArray(v, &owned));
}

// M x, A x, B x: rank 0's x, each rank multiplying its rows, the three products back on rank 0
// (collective; rank 0 announces it: the kernel's record calls it through products.external)
void multiplyProducts(const double *x, double *mx, double *ax, double *bx) {
  announce(CommandProducts);
  scatterRows(x, state.x);
  double *out[3] = {mx, ax, bx};
  for (int q = 0; q < 3; q++) {
    CHECK(MatMult(state.products[q], state.x, state.px[q]));
    const PetscScalar *p;
    CHECK(VecGetArrayRead(state.px[q], &p));
    gatherRows(p, out[q]);
    CHECK(VecRestoreArrayRead(state.px[q], &p));
  }
}
// gathers the owned slots' values into rank 0's array in the kernel's numbering of the slots
void gatherSlots(const std::vector<double> &owned, double *out) {
  std::vector<double> all(state.rank == 0 ? state.nc : 0);
  MPI_Gatherv(owned.data(), (int)owned.size(), MPI_DOUBLE, all.data(), state.slotCounts.data(), state.slotDispls.data(), MPI_DOUBLE, 0,
              MPI_COMM_WORLD);
  if (state.rank == 0) for (int j = 0; j < state.nc; j++) out[state.allSlots[j]] = all[j];
}
void gatherSlots(const std::vector<double> &owned, KN<double> &out) {
  if (state.rank == 0 && out.N() != state.nc) out.resize(state.nc);
  gatherSlots(owned, state.rank == 0 ? &out[0] : nullptr);
}

long step(KN<double> *const &prhs, KN<double> *const &pv, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  if (!state.ksp) ExecError("contactRanksStep: call contactRanksContact first");
  if (state.direct) return state.rank == 0 ? condensedStep(prhs, pv, pc, pm, pinfo) : 0;   // condensed.cpp
  state.verbose = currentKernel().settings.verbose;    // (-verbose: the iterations on the standard error)
  state.failure = "";
  announce(CommandStep);
  // rank 0's right-hand side and start, on every rank
  std::vector<double> rhs(state.n), c0(state.nc), m0(state.nc);
  if (state.rank == 0) {
    if (prhs->N() != state.n || pc->N() != state.nc || pm->N() != state.nc) ExecError("contactRanksStep: wrong argument sizes");
    rhs = copyOf(*prhs); c0 = copyOf(*pc); m0 = copyOf(*pm);
  }
  MPI_Bcast(rhs.data(), (int)state.n, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  MPI_Bcast(c0.data(), state.nc, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  MPI_Bcast(m0.data(), state.nc, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  PetscScalar *bv;
  CHECK(VecGetArray(state.b, &bv));
  for (PetscInt i = 0; i < state.owned; i++) bv[i] = rhs[state.ownedDofs[i]];
  CHECK(VecRestoreArray(state.b, &bv));
  CHECK(MatMultTranspose(state.R, state.b, state.brot));
  contactlaw::Slots &law = state.law;
  const int ns = law.n;
  std::vector<double> c(ns), m(ns), cOld(ns), mOld(ns), cNew(ns), mNew(ns);
  for (int l = 0; l < ns; l++) { c[l] = c0[state.slotGlobal[l]]; m[l] = m0[state.slotGlobal[l]]; law.velocityScale[l] = std::fabs(c[l]); }
  Reduced now = evaluateAll(c, m);                     // the pieces of the start (the last step's solution)
  Vec wOld;
  CHECK(VecDuplicate(state.w, &wOld));
  int it = 0;
  bool converged = false, failedSolve = false;
  while (it < state.maxit) {
    cOld = c; mOld = m;
    CHECK(VecCopy(state.w, wOld));
    const double meritOld = now.meritSquared;
    cNew = c; mNew = m;
    if (!newtonSolve(cNew, mNew)) { failedSolve = true; it++; break; }
    it++;
    c = cNew; m = mNew;
    now = evaluateAll(c, m);
    // from the second iteration on the iterates satisfy the momentum rows: a step that raises
    // the merit is shortened (halved up to 8 times; the full step if none lowers it)
    if (it >= 2 && now.meritSquared > meritOld && std::isfinite(meritOld)) {
      double alpha = 1;
      for (int cut = 0; cut < 8; cut++) {
        alpha *= 0.5;
        for (int l = 0; l < ns; l++) { c[l] = cOld[l] + alpha * (cNew[l] - cOld[l]); m[l] = mOld[l] + alpha * (mNew[l] - mOld[l]); }
        Reduced trial = evaluateAll(c, m);
        if (trial.meritSquared < meritOld) {
          now = trial;
          CHECK(VecAXPBY(state.w, 1 - alpha, alpha, wOld));   // w = alpha w + (1 - alpha) wOld
          break;
        }
        if (cut == 7) { c = cNew; m = mNew; now = evaluateAll(c, m); }
      }
    }
    if (state.verbose && state.rank == 0)
      std::fprintf(stderr, "ranks: Newton iteration %d: residual %.6e (merit %.6e), %ld unresolved\n", it, now.residual,
                   std::sqrt(now.meritSquared), now.unresolved);
    if (!std::isfinite(now.residual)) break;
    if (now.residual <= state.tol && now.unresolved == 0) {
      // One more Newton iteration, the pieces settled: it lands at round-off. (The residual's
      // weights use the estimate r_j of the augmentation, not the Delassus matrix's diagonal:
      // a velocity mismatch weighs less than for one process, and a 3D slip direction met
      // -tol 5e3 times further from the stress than one process's; twisted3d, -load 30.)
      // Kept only if it still passes the test.
      cOld = c; mOld = m;
      CHECK(VecCopy(state.w, wOld));
      cNew = c; mNew = m;
      bool kept = false;
      if (newtonSolve(cNew, mNew)) {
        Reduced polished = evaluateAll(cNew, mNew);
        if (polished.residual <= state.tol && polished.unresolved == 0) { c = cNew; m = mNew; now = polished; kept = true; it++; }
      }
      if (!kept) { state.failure = ""; CHECK(VecCopy(wOld, state.w)); c = cOld; m = mOld; now = evaluateAll(c, m); }
      converged = true;
      break;
    }
  }
  CHECK(VecDestroy(&wOld));
  state.newtonIterations += it;
  // v = R w, gathered on rank 0; c, m too
  CHECK(MatMult(state.R, state.w, state.vOwned));
  const PetscScalar *vv;
  CHECK(VecGetArrayRead(state.vOwned, &vv));
  gatherRows(vv, *pv);
  CHECK(VecRestoreArrayRead(state.vOwned, &vv));
  gatherSlots(c, *pc);
  gatherSlots(m, *pm);
  if (state.rank == 0) {
    KN<double> &info = *pinfo;
    info[contactkernel::InfoResidual] = failedSolve ? INFINITY : now.residual;
    info[contactkernel::InfoIterations] = it;
    info[contactkernel::InfoUnresolved] = now.unresolved;
    info[contactkernel::InfoStalled] = 0;
  }
  return converged ? it : -1;
}

// the other ranks: each step and each product rank 0 asks for, until the end of its time loop
long serve(KN<double> *const &prhs, KN<double> *const &pv, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  if (state.rank == 0) ExecError("contactRanksServe: rank 0 runs the time loop");
  while (true) {
    const int command = nextCommand();
    if (command == CommandEnd) return 0;
    if (command == CommandStep) step(prhs, pv, pc, pm, pinfo);
    else if (command == CommandProducts) multiplyProducts(nullptr, nullptr, nullptr, nullptr);
    else if (command == CommandFree) freeAll(nullptr, nullptr);
    else if (command == CommandFinish) finishAll(nullptr, nullptr);
    else rankFail(3, "contactRanksServe: an unknown command from rank 0");
  }
}

// why the last step failed in its linear solve, "" if it did not (every rank knows)
string *failure(Stack stack, const long &) { return Add2StackOfPtr2Free(stack, new string(state.failure)); }

}  // namespace ranks
