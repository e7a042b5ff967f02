// condensed.cpp: the direct path of the run on ranks (-ranksolver direct), as the one-process
// kernel solves a step: S factorized once per run, the contact problem condensed on the
// Delassus matrix Dw = C S^-1 C'W, and the kernel's own semismooth Newton on it (newton.cpp,
// the same code as one process, on rank 0). The ranks hold the factor: MUMPS's Cholesky of
//   F = R'SR, the Dirichlet rows and columns of the fixed components set to the identity's
// (R the node rotation, ranks.cpp: in the nodes' frames a slot's velocity is one row of w, so
// C = E R' with E the slots' rows, and C S^-1 C' = E F^-1 E'). They make
//   - Dw once per run (contactRanksDelassus): the entries of F^-1 at the slots' rows and columns,
//     MUMPS's entries of the inverse (ICNTL(30)), on rank 0;
//   - the two halves of a step's back-substitution, which rank 0's kernel asks for through
//     factor.externalFree and factor.externalFinish: cFree = E F^-1 R'b, then
//     v = R F^-1 (R'b - E'W m).
// Rank 0 holds Dw and the Newton's dense matrices (contact-size, nc x nc, as one process); no
// rank holds S or its factor whole.
#include "ranks.hpp"

namespace ranks {

namespace {
// R'b with the fixed rows zeroed (S's Dirichlet rows hold v = 0 there), in state.brot
void rotatedLoad() {
  CHECK(MatMultTranspose(state.R, state.b, state.brot));
  PetscScalar *bv;
  CHECK(VecGetArray(state.brot, &bv));
  for (PetscInt row : state.fixedRows) bv[row - state.first] = 0.;
  CHECK(VecRestoreArray(state.brot, &bv));
}
// F x = b; false if the solve failed (every rank knows: the check is collective), state.failure
// then saying why, or "" for a non-finite value. The kernel's Newton then meets NaN and the step
// fails as one process's would: exit 4 with the step and state.failure (the script's stepFailed,
// contactRanksFailure), or 5 for a non-finite value.
bool solved(Vec b, Vec x, const char *what) { return solveChecked(state.Srot, b, x, what); }
}  // namespace

// cFree = E F^-1 R'b (collective; rank 0 announces it: its kernel's freeVelocity calls it)
void freeAll(const double *b, double *cFree) {
  announce(CommandFree);
  scatterRows(b, state.b);
  rotatedLoad();
  const bool ok = solved(state.brot, state.y, "the back-substitution of a step (its free velocities)");
  const PetscScalar *yv;
  CHECK(VecGetArrayRead(state.y, &yv));
  std::vector<double> c(state.law.n);
  for (int l = 0; l < state.law.n; l++) c[l] = ok ? yv[state.slotRow[l] - state.first] : NAN;
  CHECK(VecRestoreArrayRead(state.y, &yv));
  gatherSlots(c, cFree);
}

// v = R F^-1 (R'b - E'W m), R'b the last freeAll's (collective; rank 0's kernel's finishVelocity)
void finishAll(const double *m, double *v) {
  announce(CommandFinish);
  std::vector<double> mAll(state.nc);
  if (state.rank == 0) std::copy(m, m + state.nc, mAll.begin());
  MPI_Bcast(mAll.data(), state.nc, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  CHECK(VecCopy(state.brot, state.bJ));
  PetscScalar *bv;
  CHECK(VecGetArray(state.bJ, &bv));
  for (int l = 0; l < state.law.n; l++) bv[state.slotRow[l] - state.first] -= state.W[l] * mAll[state.slotGlobal[l]];
  CHECK(VecRestoreArray(state.bJ, &bv));
  if (!solved(state.bJ, state.w, "the back-substitution of a step")) CHECK(VecSet(state.w, NAN));
  CHECK(MatMult(state.R, state.w, state.vOwned));
  const PetscScalar *vv;
  CHECK(VecGetArrayRead(state.vOwned, &vv));
  gatherRows(vv, v);
  CHECK(VecRestoreArrayRead(state.vOwned, &vv));
}

// A step on rank 0 (contactRanksStep with -ranksolver direct): the kernel's Newton on Dw, as
// one process, then made consistent. One process makes cFree, Dw and v from one factor by the
// same sweeps, so that C v = cFree - Dw m to round-off; here they come from separate solves,
// each with its own round-off, and where Dw has large entries (a body held by contact only: its
// rigid motion) C v and the Newton's c = cFree - Dw m parted by up to 4e-7 of the velocities
// (twisted3d at -load 30 on 2 ranks: stick nodes then read as slipping). So, after the Newton:
// v = S^-1 (b - C'W m), the mismatch d = C v - (cFree - Dw m), cFree += d (the model is then
// exact at m), and the step's test (-tol, the statuses) at (C v, m) on that model: if it passes,
// the step is (v, C v, m); if not, the Newton again from (c, m) with the iterations -maxit has
// left, then the same, at most 5 checks. Once a Newton run again no longer shrinks the
// mismatch tenfold (the round-off floor of the ranks' solves) and no status is unresolved at
// C v, the step is taken with the Newton's own residual; a step whose checks all fail fails
// (exit 4, contactRanksFailure saying why).
long condensedStep(KN<double> *const &prhs, KN<double> *const &pv, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  Kernel &k = currentKernel();
  const int nc = state.nc, cap = k.settings.maxit;
  if (prhs->N() != state.n || pc->N() != nc || pm->N() != nc) ExecError("contactRanksStep: wrong argument sizes");
  std::vector<double> rhs = copyOf(*prhs), c = copyOf(*pc), m = copyOf(*pm), cFree(nc), model(nc), cv, v(state.n, NAN);
  double info[contactkernel::solverInfoColumnCount] = {NAN, 0, 0, 0};
  state.failure = "";
  contactkernel::freeVelocity(k, rhs.data(), cFree.data());
  long it = state.failure.empty() ? contactkernel::newtonStep(k, cFree.data(), c.data(), m.data(), info) : -1;
  double iterations = info[contactkernel::InfoIterations];
  double previousMismatch = INFINITY, newtonResidual = info[contactkernel::InfoResidual];
  for (int pass = 0; it >= 0 && state.failure.empty(); pass++) {
    contactkernel::finishVelocity(k, m.data(), v.data());
    if (!state.failure.empty()) { it = -1; break; }
    contactkernel::slotVelocities(k, v.data(), cv);
    contactkernel::velocities(k, cFree.data(), m.data(), model.data());
    double mismatch = 0;
    for (int j = 0; j < nc; j++) {
      mismatch = std::max(mismatch, std::fabs(cv[j] - model[j]));
      cFree[j] += cv[j] - model[j];
    }
    contactkernel::roundoffScale(k, cFree.data(), m.data());
    double merit = 0;
    int unresolved = 0;
    const double residual = contactkernel::referenceEvaluate(k, cv.data(), m.data(), merit);
    const bool passes = contactkernel::stepConverged(k, residual, cv.data(), unresolved);
    // the round-off floor of the ranks' solves: the Newton run again did not shrink the mismatch
    // tenfold (twisted3d at -load 30: 4.9e-8, then 1.3e-10, 2.6e-10, 1.4e-10, the residual at
    // C v 1.6e-10 to 5.9e-10 against -tol 1e-10): the statuses at C v are those of the Newton's
    // solution, and the residual is the Newton's own, on its model, as one process reports it
    const bool floor = pass > 0 && unresolved == 0 && mismatch > 0.1 * previousMismatch;
    if (passes || floor) {
      info[contactkernel::InfoResidual] = passes ? residual : newtonResidual;
      info[contactkernel::InfoUnresolved] = 0;
      if (floor && !passes) state.floors++;
      c = cv;
      break;
    }
    info[contactkernel::InfoResidual] = residual;
    info[contactkernel::InfoUnresolved] = unresolved;
    if (pass == 4 || iterations >= cap) {                       // the step fails, said as such
      char text[600];
      std::snprintf(text, sizeof text, "the Newton converged, but at the velocities of its back-substitution on the ranks, C v, the "
                    "step's test failed after %d check%s (residual %.6g, tol %.6g, %d unresolved statuses; C v %.3g from the Newton's "
                    "velocities), %g of -maxit %d iterations made%s", pass + 1, pass == 0 ? "" : "s", residual, k.settings.tol, unresolved, mismatch, iterations, cap,
                    iterations >= cap ? (std::string(" (-maxit ") + std::to_string(2 * cap) + " leaves the Newton's runs again more)").c_str() : "");
      state.failure = text;
      it = -1;
      break;
    }
    if (k.settings.verbose)
      std::fprintf(stderr, "  (C v differs from the Newton's velocities by %.3e after the ranks' solves: residual %.3e, %d unresolved "
                   "at C v; Newton again from its solution)\n", mismatch, residual, unresolved);
    previousMismatch = mismatch;
    state.refinements++;
    k.settings.maxit = cap - (int)iterations;
    const long more = contactkernel::newtonStep(k, cFree.data(), c.data(), m.data(), info);
    k.settings.maxit = cap;
    iterations += info[contactkernel::InfoIterations];
    newtonResidual = info[contactkernel::InfoResidual];
    it = more < 0 ? -1 : it + more;
  }
  if (!state.failure.empty() || std::isnan(info[contactkernel::InfoResidual])) it = -1;
  info[contactkernel::InfoIterations] = iterations;
  state.newtonIterations += (long)iterations;
  copyInto(*pv, v.data(), state.n);
  copyInto(*pc, c.data(), nc);
  copyInto(*pm, m.data(), nc);
  copyInto(*pinfo, info, contactkernel::solverInfoColumnCount);
  return it;
}

// contactRanksDelassus(progress): Dw = E F^-1 E' W on rank 0's kernel, with the two halves above
// as its back-substitution (collective; after contactKernelExternalFactor and the kernel's
// parameters: r_j = r / Dw_jj reads -r). Nothing on the iterative path. progress > 0: rank 0
// says how far it is every that many seconds once it has taken twice that (the run's progress
// lines, edp/lib/series.idp; -quiet: none)
long delassus(const double &progress) {
  if (!state.direct) return 0;
  const double started = MPI_Wtime();
  double shown = started;
  PC pc;                                                      // (a factorization: contactRanksContact checked it)
  CHECK(KSPGetPC(state.ksp, &pc));
  Mat factor;
  CHECK(PCFactorGetMatrix(pc, &factor));
  const int nc = state.nc, ns = state.law.n;
  // the slots' rows, on rank 0 in the kernel's numbering of the slots; their order (row, slot)
  std::vector<PetscInt> mine(ns), gathered(state.rank == 0 ? nc : 0), rowOfSlot(state.rank == 0 ? nc : 0);
  for (int l = 0; l < ns; l++) mine[l] = state.slotRow[l];
  MPI_Gatherv(mine.data(), ns, MPIU_INT, gathered.data(), state.slotCounts.data(), state.slotDispls.data(), MPIU_INT, 0, MPI_COMM_WORLD);
  std::vector<std::pair<PetscInt, int>> byRow(state.rank == 0 ? nc : 0);
  for (int q = 0; q < (int)gathered.size(); q++) {
    rowOfSlot[state.allSlots[q]] = gathered[q];
    byRow[q] = {gathered[q], state.allSlots[q]};
  }
  std::sort(byRow.begin(), byRow.end());
  std::vector<PetscInt> rowsSorted(byRow.size());
  for (size_t q = 0; q < byRow.size(); q++) rowsSorted[q] = byRow[q].first;
  std::vector<double> Dw(state.rank == 0 ? (size_t)nc * nc : 0);
  // MUMPS's entries of the inverse (ICNTL(30), MatMumpsGetInverseTranspose): the requested
  // entries (the slots' rows and columns, n x n with its rows on rank 0) computed with the
  // sparsity of the right-hand sides and of the entries wanted, by blocks of columns (about 20,
  // for the progress lines). At 48x24x24 on 2 ranks 16 s, where dense blocks of MatMatSolve
  // took 42 s, the same peak memory. PETSc leaves ICNTL(20), (21) and (30) as that call sets
  // them, and a solve then fails (MUMPS's INFOG(1) = -22): they are put back.
  PetscInt kept[3];
  const PetscInt which[3] = {20, 21, 30};
  for (int q = 0; q < 3; q++) CHECK(MatMumpsGetIcntl(factor, which[q], &kept[q]));
  const int block = std::max(256, (nc + 19) / 20);
  for (int j0 = 0; j0 < nc; j0 += block) {
    const int columns = std::min(block, nc - j0);
    Mat wanted;
    CHECK(MatCreate(PETSC_COMM_WORLD, &wanted));
    CHECK(MatSetSizes(wanted, state.rank == 0 ? state.n : 0, state.rank == 0 ? state.n : 0, PETSC_DECIDE, PETSC_DECIDE));
    CHECK(MatSetType(wanted, MATAIJ));
    std::vector<PetscInt> perRow(state.rank == 0 ? state.n : 0, 0);
    for (int j = j0; j < j0 + columns && state.rank == 0; j++) perRow[rowOfSlot[j]] = nc;
    CHECK(MatSeqAIJSetPreallocation(wanted, 0, perRow.data()));
    CHECK(MatMPIAIJSetPreallocation(wanted, 0, perRow.data(), 0, nullptr));
    if (state.rank == 0) {
      const std::vector<PetscScalar> zeros(nc, 0.);
      for (int j = j0; j < j0 + columns; j++) CHECK(MatSetValues(wanted, 1, &rowOfSlot[j], nc, rowsSorted.data(), zeros.data(), INSERT_VALUES));
    }
    CHECK(MatAssemblyBegin(wanted, MAT_FINAL_ASSEMBLY));
    CHECK(MatAssemblyEnd(wanted, MAT_FINAL_ASSEMBLY));
    CHECK(MatMumpsGetInverseTranspose(factor, wanted));   // row r_j: (F^-T)_{r_j, r_i} = (F^-1)_{r_i, r_j}
    for (int q = 0; q < 3; q++) CHECK(MatMumpsSetIcntl(factor, which[q], kept[q]));
    for (int j = j0; j < j0 + columns && state.rank == 0; j++) {
      PetscInt count;
      const PetscInt *column;
      const PetscScalar *value;
      CHECK(MatGetRow(wanted, rowOfSlot[j], &count, &column, &value));
      if (count != nc) rankFail(3, "MUMPS's entries of the inverse: a column of the Delassus matrix came back incomplete");
      for (PetscInt e = 0; e < count; e++) {
        const auto at = std::lower_bound(byRow.begin(), byRow.end(), std::make_pair(column[e], -1));
        Dw[at->second + (size_t)j * nc] = value[e];
      }
      CHECK(MatRestoreRow(wanted, rowOfSlot[j], &count, &column, &value));
    }
    CHECK(MatDestroy(&wanted));
    const double now = MPI_Wtime();
    if (state.rank == 0 && progress > 0 && now - started >= 2 * progress && now - shown >= progress && j0 + columns < nc) {
      std::fprintf(stderr, "set-up: the Delassus matrix on the ranks, %d of %d columns (%.0f s)\n", j0 + columns, nc, now - started);
      shown = now;
    }
  }
  if (state.rank == 0) {
    Kernel &k = currentKernel();
    // E F^-1 E' is symmetric; MUMPS's entries are, to round-off: made exactly so (the Newton reads
    // Dw's rows from its columns, newton.cpp), then Dw = D W
    for (int j = 0; j < nc; j++)
      for (int i = j + 1; i < nc; i++) {
        const double mean = 0.5 * (Dw[i + (size_t)j * nc] + Dw[j + (size_t)i * nc]);
        Dw[i + (size_t)j * nc] = Dw[j + (size_t)i * nc] = mean;
      }
    for (int j = 0; j < nc; j++) for (int i = 0; i < nc; i++) Dw[i + (size_t)j * nc] *= k.nodes.slotWeight[j];
    k.factor.externalFree = freeAll;
    k.factor.externalFinish = finishAll;
    contactkernel::externalDelassus(k, std::move(Dw));
  }
  return 0;
}

}  // namespace ranks
