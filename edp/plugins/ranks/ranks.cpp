// ranks.cpp: a run across MPI ranks through PETSc (-ranks N; docs/design.md, "Across ranks").
// Built by ./run.sh with mpicxx into edp/plugins/build/contactkernelmpi.so, together with the
// kernel's files and the law, contactlaw.hpp: the ranks evaluate the same law, compiled in.
// Loaded by edp/solve.edp under FreeFem++-mpi instead of contactkernel.so. This file: the
// set-up, the run's figures and the FreeFEM functions; step.cpp: a step of the iterative path
// and the record's products; condensed.cpp: the direct path; ranks.hpp: what they share.
//
// What each rank holds: the rows of S = M/k + A + kB + C'W Kn C of the vertices it owns
// (PETSc's MPIAIJ; summed from M, A and B, which are assembled from the elements of its part
// of the mesh, each rank passing the triplets of its own elements), the same rows of M, A and B (the record's products, which
// rank 0's kernel asks for through products.external), the rows of the node rotation R, and the
// contact nodes of its vertices with their slots. No rank holds S, M, A, B or a factor whole.
// In the nodes' frames (w = R'v) a contact node's rows are its slots' velocities.
// -ranksolver direct (condensed.cpp): F = R'SR (the fixed rows and columns the identity's)
// factorized once per run by MUMPS (Cholesky), the Delassus matrix made from its solves and
// the kernel's own Newton on it on rank 0, as one process. -ranksolver iterative (step.cpp): a
// semismooth Newton on the whole system,
//   R'SR w + W m = R'b on the slots' rows, and on each slot its piece's relation
//   sum_t a_t c + sum_t d_t m = h (contactlaw.hpp, Slots::relations), c = w there.
// A slot whose relation fixes its velocity (the bound, stick: d = 0) is a Dirichlet row of
// the rotated system; the others' multipliers are eliminated node by node (m_F = D_FF^-1
// (h_F - A_F c)), which adds a small block to the node's rows. Each Newton iteration solves
// that system by GMRES preconditioned by hypre's BoomerAMG. The multipliers then follow from
// the momentum rows, m = (R'b - R'SR w)/W, the law is evaluated on the rank's own slots, and
// the residual is reduced over the ranks (its largest).
//
// FreeFEM functions (collective: every rank calls them, in the same order)
//   contactRanksStart(string options)  PETSc started (MPI already is); options: PETSc's, e.g.
//       "-ranks_ksp_view"; returns this rank
//   contactRanksEngine(0)  the solver as built (after contactRanksContact): "PETSc 3.18.5, GMRES
//       with MUMPS Cholesky of S, once per run; the kernel's Newton on the Delassus matrix"
//       (direct), "..., GMRES with BoomerAMG" (iterative), or what PETSC_OPTIONS chose
//   contactRanksShareText(string text)  rank 0's text, on every rank
//   contactRanksNumbering(int[int] rowOf, int owned, int dim)  rowOf: the PETSc row of every
//       FreeFEM degree of freedom (the same array on every rank); owned: the rows of this rank;
//       dim: the body's dimension (the components of a vertex, PETSc's block size)
//   contactRanksProduct(matrix X, int q, int[int] l2g, real[int] largest)  X = M, A, B (q = 0, 1,
//       2) of the rank's elements (local numbering; l2g: local to FreeFEM's global), distributed
//       as S is, one at a time; rank 0's record takes its products from them; largest[q]: the
//       largest entry of X
//   contactRanksMatrix(real k, matrix D, real[int] fixed, real[int] xyz)  S = M/k + A + kB from
//       them, D = C'W Kn C (global; rank 0 adds it), fixed: 1 on the Dirichlet degrees of
//       freedom, xyz: the coordinates of every vertex, one after the other (the rigid-body modes,
//       GAMG's near-null space)
//   contactRanksContact(matrix C, string path, real tol, int maxit, real r)  the contact nodes of the rank's
//       vertices, their frames and the law's data of their slots (from the kernel instance, which
//       contactKernelNodes filled), the solver path (direct or iterative); direct: S factorized
//   contactRanksDelassus(real progress)  direct: the Delassus matrix on rank 0's kernel (after its
//       parameters); progress > 0: a line every that many seconds once it has taken twice that
//   contactRanksStep(real[int] rhs, real[int] v, real[int] c, real[int] m, real[int] info)
//       (rank 0) one step from its rhs and start (c, m); it gets v, c, m and info (the columns
//       "solver_info"); returns the iterations, or -1 (no convergence). Direct: the kernel's
//       Newton, the ranks' solves on rank 0's commands (condensed.cpp)
//   contactRanksServe(real[int] rhs, real[int] v, real[int] c, real[int] m, real[int] info)
//       (the other ranks) their part of every step and product rank 0 asks for, until rank 0
//       calls contactRanksPeaks at the end of its time loop
//   contactRanksFailure(0)  why the last step's linear solve failed, "" if it did not
//   contactRanksPeaks(real[int] peaks)  rank 0 gets every rank's peak memory (MB)
//   contactRanksCounters(real[int] counts)  Newton iterations (of the ranks' Newton), linear
//       solves, linear iterations, preconditioner builds (direct: MUMPS's factorizations, one a
//       run; iterative: a BoomerAMG hierarchy a linear solve), refinements (direct: the kernel's
//       Newton run again after a step's consistency test, condensed.cpp), the steps taken at
//       that test's round-off floor
//   contactRanksPetscOptions(0)  PETSC_OPTIONS as the run had it ("none"), for summary.txt
//   contactRanksFinish()  waits for every rank; rank 0 warns of an option of PETSC_OPTIONS with
//       the prefix ranks_ that nothing used; then ends PETSc
#include "ranks.hpp"
#include "kernel/signals.hpp"

namespace ranks {
RankState state;

// An error of one rank: said with the rank, then the run stops as on a signal, but with the
// exit code given (runtools' handler removes the unfinished output folder and exits with
// CONTACT_SUITE_RANK_FAILED; mpirun stops the other ranks)
[[noreturn]] void rankFail(int code, const std::string &message) {
  int rank = state.rank, size = state.size, initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized) { MPI_Comm_rank(MPI_COMM_WORLD, &rank); MPI_Comm_size(MPI_COMM_WORLD, &size); }   // (before PETSc is started too)
  std::fprintf(stderr, "error: rank %d of %d: %s; no results written\n", rank, size, message.c_str());
  std::fflush(stderr);
  setenv("CONTACT_SUITE_RANK_FAILED", std::to_string(code).c_str(), 1);   // runtools' handler: exit with code, said already
  raise(SIGTERM);
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}
// ", under PETSC_OPTIONS=\"...\"" when they are set (a failure's message names them), else ""
std::string underOptions() {
  const char *options = std::getenv("PETSC_OPTIONS");
  return options && *options ? std::string(", under PETSC_OPTIONS=\"") + options + "\"" : std::string();
}
// An error every rank finds alike (the options, the factorization): rank 0 says it, the others
// wait 3 s first (mpirun stops them once rank 0 has failed), as the script's checks do
[[noreturn]] void failAlike(int code, const std::string &message) {
  if (state.rank != 0) sleep(3);
  rankFail(code, message);
}
// PETSc's error: its code, the call, and PETSc's own words (its traceback is not printed:
// start() sets PETSc's error handler to return the error only)
void check(PetscErrorCode status, const char *what) {
  if (!status) return;
  const char *generic = nullptr;
  char *specific = nullptr;
  PetscErrorMessage(status, &generic, &specific);
  std::string words = specific && *specific ? specific : (generic ? generic : "");
  while (!words.empty() && (words.back() == '\n' || words.back() == ' ')) words.pop_back();
  rankFail(3, std::string("PETSc error ") + std::to_string((int)status) + " in " + what + (words.empty() ? "" : ": " + words) + underOptions());
}

double peakMegabytes() {
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.;
}

// the entries (i, j, a) of a FreeFEM matrix, 0-based, both halves of a symmetric one
template <class F> void forEachEntry(Matrice_Creuse<double> *A, F f) {
  const contactkernel::SparseTriplets t = contactkernel::coo(A);
  const int base = t.oneBased ? 1 : 0;
  for (size_t e = 0; e < t.count; e++) {
    const int i = t.row[e] - base, j = t.column[e] - base;
    f(i, j, t.value[e]);
    if (t.lowerHalf && i != j) f(j, i, t.value[e]);
  }
}

// ---------------------------------------------------------------- start, numbering
// FreeFEM's end of the run (ff_atend): reached with PETSc still started only when a FreeFEM
// error stopped this rank's script (contactRanksFinish ends PETSc at a run's normal end, and the
// suite's own failures exit at once). The other ranks would wait for it in their next
// collective call forever: this rank fails as on a crash, and mpirun stops the others (an
// error every rank meets is said once, by rank 0: failAlike). (A script's exit(n) after
// contactRanksStart would come here too, as a failure: the suite's scripts end by runError.)
void stopOnError() {
  if (state.started) failAlike(1, "a FreeFEM error on this rank stopped the run (FreeFEM's message, where it gives one on this rank, is above)");
}
long start(string *const &options) {
  if (!state.started) {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) ExecError("contactRanksStart: MPI is not running (FreeFem++-mpi under mpirun runs -ranks)");
    // PETSc installs signal handlers of its own (a crash then exits 59, leaving the output
    // folder): the suite's are put back (kernel/signals.hpp)
    CHECK(contactkernel::keepingSignalHandlers([] { return PetscInitializeNoArguments(); }));
    CHECK(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));   // (check() says the error in one line)
    state.started = true;
    ff_atend(stopOnError);
  }
  CHECK(PetscOptionsInsertString(nullptr, options->c_str()));
  MPI_Comm_rank(MPI_COMM_WORLD, &state.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &state.size);
  return state.rank;
}

// the engine as summary.txt names it: PETSc's version and the linear solver of the path
// (once the solver is built, contactRanksContact, the Krylov method and preconditioner it has:
// PETSC_OPTIONS may have chosen others, e.g. -ranks_pc_type gamg)
std::string builtSolver() {
  KSPType krylov;
  PCType preconditioner;
  PC pc;
  CHECK(KSPGetType(state.ksp, &krylov));
  CHECK(KSPGetPC(state.ksp, &pc));
  CHECK(PCGetType(pc, &preconditioner));
  std::string method = std::string(krylov) == KSPGMRES ? "GMRES" : std::string("PETSc's ") + krylov, with;
  const std::string p = preconditioner ? preconditioner : "none";
  if (p == PCLU || p == PCCHOLESKY) {
    MatSolverType package = nullptr;
    CHECK(PCFactorGetMatSolverType(pc, &package));
    with = (package && std::string(package) == MATSOLVERMUMPS ? std::string("MUMPS") : std::string(package ? package : "PETSc")) + (p == PCLU ? " LU" : " Cholesky")
           + (state.direct ? " of S, once per run; the kernel's Newton on the Delassus matrix" : "");
  } else if (p == PCHYPRE) {
    const char *kind = nullptr;
    CHECK(PCHYPREGetType(pc, &kind));
    with = kind && std::string(kind) == "boomeramg" ? "BoomerAMG" : std::string("hypre ") + (kind ? kind : "");
  } else if (p == PCGAMG) with = "GAMG";
  else with = "PETSc's preconditioner " + p;
  return method + " with " + with;
}
string *engine(Stack stack, const long &) {
  if (!state.ksp) ExecError("contactRanksEngine: call contactRanksContact first");
  const std::string solver = builtSolver();
  return Add2StackOfPtr2Free(stack, new string("PETSc " + std::to_string(PETSC_VERSION_MAJOR) + "." + std::to_string(PETSC_VERSION_MINOR) + "."
                                                    + std::to_string(PETSC_VERSION_SUBMINOR) + ", " + solver));
}

string *shareText(Stack stack, string *const &text) {
  int length = (int)text->size();
  MPI_Bcast(&length, 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::string out(length, ' ');
  if (state.rank == 0) out = *text;
  MPI_Bcast(&out[0], length, MPI_CHAR, 0, MPI_COMM_WORLD);
  return Add2StackOfPtr2Free(stack, new string(out));
}

long numbering(KN<long> *const &pRowOf, const long &owned, const long &dim) {
  const KN<long> &rowOf = *pRowOf;
  if (dim != 2 && dim != 3) ExecError("contactRanksNumbering: dim is 2 or 3");
  state.dim = (int)dim;
  state.n = rowOf.N();
  state.owned = owned;
  state.rowOf.resize(state.n);
  for (PetscInt i = 0; i < state.n; i++) state.rowOf[i] = rowOf[i];
  PetscInt first = 0, mine = owned;
  MPI_Exscan(&mine, &first, 1, MPIU_INT, MPI_SUM, MPI_COMM_WORLD);
  if (state.rank == 0) first = 0;
  state.first = first;
  state.ownedDofs.assign(owned, -1);
  for (PetscInt i = 0; i < state.n; i++) {
    const PetscInt row = state.rowOf[i];
    if (row < 0 || row >= state.n) ExecError("contactRanksNumbering: a row out of range");
    if (row >= first && row < first + owned) state.ownedDofs[row - first] = (int)i;
  }
  for (PetscInt i = 0; i < owned; i++) if (state.ownedDofs[i] < 0) ExecError("contactRanksNumbering: the rows are not a numbering");
  // rank 0 gathers the owned dofs of every rank (it scatters v back into FreeFEM's numbering)
  int count = (int)owned;
  state.rowCounts.assign(state.size, 0);
  MPI_Gather(&count, 1, MPI_INT, state.rowCounts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  state.rowDispls.assign(state.size, 0);
  for (int r = 1; r < state.size; r++) state.rowDispls[r] = state.rowDispls[r - 1] + state.rowCounts[r - 1];
  state.allDofs.assign(state.rank == 0 ? state.n : 0, 0);
  MPI_Gatherv(state.ownedDofs.data(), count, MPI_INT, state.allDofs.data(), state.rowCounts.data(), state.rowDispls.data(), MPI_INT, 0,
              MPI_COMM_WORLD);
  return 0;
}

// ---------------------------------------------------------------- S
// the MPIAIJ matrix (n x n, the owned rows) of the triplets (I, J, V), repeated ones summed;
// the triplets emptied. PETSc keeps the COO maps of a matrix for a next MatSetValuesCOO (two
// counts per triplet): the matrix returned is a copy without them.
Mat assembledCOO(std::vector<PetscInt> &I, std::vector<PetscInt> &Jc, std::vector<PetscScalar> &V, int blockSize) {
  Mat coo, out;
  CHECK(MatCreate(PETSC_COMM_WORLD, &coo));
  CHECK(MatSetSizes(coo, state.owned, state.owned, state.n, state.n));
  CHECK(MatSetType(coo, MATAIJ));
  CHECK(MatSetBlockSize(coo, blockSize));
  CHECK(MatSetPreallocationCOO(coo, (PetscCount)I.size(), I.data(), Jc.data()));
  std::vector<PetscInt>().swap(I); std::vector<PetscInt>().swap(Jc);
  CHECK(MatSetValuesCOO(coo, V.data(), ADD_VALUES));
  std::vector<PetscScalar>().swap(V);
  CHECK(MatDuplicate(coo, MAT_COPY_VALUES, &out));
  CHECK(MatDestroy(&coo));
  return out;
}
// S = M/k + A + kB (the record's M, A, B on the ranks, contactRanksProduct), plus D = C'W Kn C
// (global; rank 0 adds its entries) and an entry on every owned row's diagonal; fixed: 1 on the
// Dirichlet degrees of freedom, xyz: the coordinates of every vertex (the near-null space)
long matrix(const double &k, Matrice_Creuse<double> *const &pD, KN<double> *const &pfixed, KN<double> *const &pxyz) {
  for (int q = 0; q < 3; q++) if (!state.products[q]) ExecError("contactRanksMatrix: M, A and B first (contactRanksProduct)");
  std::vector<PetscInt> I, Jc;
  std::vector<PetscScalar> V;
  if (state.rank == 0) forEachEntry(pD, [&](int i, int j, double a) {
    I.push_back(state.rowOf[i]); Jc.push_back(state.rowOf[j]); V.push_back(a);
  });
  // every owned row keeps its diagonal (a Dirichlet row of the rotated system is set to 1 there)
  for (PetscInt i = 0; i < state.owned; i++) { I.push_back(state.first + i); Jc.push_back(state.first + i); V.push_back(0.); }
  const std::vector<double> fixed = copyOf(*pfixed);
  if ((PetscInt)fixed.size() != state.n) ExecError("contactRanksMatrix: fixed must have one value per degree of freedom");
  const std::vector<double> xyz = copyOf(*pxyz);
  if ((PetscInt)(xyz.size() / 3) * state.dim != state.n) ExecError("contactRanksMatrix: xyz must hold 3 coordinates per vertex");
  state.fixedOwned.assign(state.owned, 0);
  state.xyz.assign(state.owned, 0.);
  for (PetscInt i = 0; i < state.owned; i++) {
    const int dof = state.ownedDofs[i];
    state.fixedOwned[i] = fixed[dof] != 0;
    state.xyz[i] = xyz[3 * (dof / state.dim) + dof % state.dim];
  }
  Mat D = assembledCOO(I, Jc, V, state.dim);
  if (state.S) CHECK(MatDestroy(&state.S));
  CHECK(MatDuplicate(state.products[0], MAT_COPY_VALUES, &state.S));
  CHECK(MatScale(state.S, 1. / k));
  CHECK(MatAXPY(state.S, 1., state.products[1], DIFFERENT_NONZERO_PATTERN));
  CHECK(MatAXPY(state.S, k, state.products[2], DIFFERENT_NONZERO_PATTERN));
  CHECK(MatAXPY(state.S, 1., D, DIFFERENT_NONZERO_PATTERN));
  CHECK(MatDestroy(&D));
  return 0;
}

// ---------------------------------------------------------------- M, A, B for the record
// X (q = 0, 1, 2: M, A, B) of the rank's elements (local numbering; l2g: local to FreeFEM's
// global), assembled into an MPIAIJ matrix (the rows of the rank's vertices); largest[q]: its
// largest entry |X_ij| (on every rank). One at a time, each freed by the script before the
// next is assembled: a rank's peak memory is one local matrix and PETSc's copies, not four
// local matrices. With all three, the kernel's record on rank 0 takes its products from them
// (products.external): no rank holds M, A or B whole.
long productBinding(Matrice_Creuse<double> *const &pX, const long &q, KN<long> *const &pl2g, KN<double> *const &plargest) {
  if (q < 0 || q > 2) ExecError("contactRanksProduct: q is 0 (M), 1 (A) or 2 (B)");
  const KN<long> &l2g = *pl2g;
  KN<double> &largest = *plargest;
  if (largest.N() != 3) largest.resize(3);
  std::vector<PetscInt> I, Jc;
  std::vector<PetscScalar> V;
  forEachEntry(pX, [&](int i, int j, double a) {
    if (i >= l2g.N() || j >= l2g.N()) ExecError("contactRanksProduct: the local matrix is larger than its map");
    I.push_back(state.rowOf[l2g[i]]); Jc.push_back(state.rowOf[l2g[j]]); V.push_back(a);
  });
  Mat &P = state.products[q];
  if (P) CHECK(MatDestroy(&P));
  if (state.px[q]) CHECK(VecDestroy(&state.px[q]));
  P = assembledCOO(I, Jc, V, state.dim);
  Vec rowMax;
  CHECK(MatCreateVecs(P, &state.px[q], &rowMax));
  CHECK(MatGetRowMaxAbs(P, rowMax, nullptr));
  PetscReal most = 0;
  CHECK(VecNorm(rowMax, NORM_INFINITY, &most));
  CHECK(VecDestroy(&rowMax));
  largest[q] = most;
  if (!state.products[0] || !state.products[1] || !state.products[2]) return 0;
  if (state.x) CHECK(VecDestroy(&state.x));
  CHECK(VecDuplicate(state.px[0], &state.x));
  if (state.rank == 0) {
    Kernel &k = currentKernel();
    k.products = contactkernel::ProductMatrices();
    k.products.n = (int)state.n;
    k.products.external = multiplyProducts;
  }
  return 0;
}

// ---------------------------------------------------------------- the contact nodes, R, the solver
long contact(Matrice_Creuse<double> *const &pC, string *const &path, const double &tol, const long &maxit, const double &r) {
  Kernel &k = currentKernel();
  contactkernel::requireNodes(k, "contactRanksContact");
  const contactkernel::ContactNodes &nodes = k.nodes;
  const int dim = state.dim, nc = k.law.n;
  state.nc = nc;
  state.direct = *path == "direct";
  state.tol = tol;
  state.maxit = (int)maxit;
  // C by slots: (dof, value) pairs
  std::vector<std::vector<std::pair<int, double>>> rowsOf(nc);
  forEachEntry(pC, [&](int i, int j, double a) { if (a != 0 && i < nc) rowsOf[i].push_back({j, a}); });
  const PetscInt first = state.first, last = state.first + state.owned;
  // R: identity but on the contact nodes' rows
  CHECK(MatCreate(PETSC_COMM_WORLD, &state.R));
  CHECK(MatSetSizes(state.R, state.owned, state.owned, state.n, state.n));
  CHECK(MatSetType(state.R, MATAIJ));
  CHECK(MatSeqAIJSetPreallocation(state.R, dim, nullptr));
  CHECK(MatMPIAIJSetPreallocation(state.R, dim, nullptr, 0, nullptr));
  std::vector<char> inNode(state.owned, 0);
  std::vector<int> ownedSlots;
  state.nodes.clear();
  state.fixedRows.clear();
  for (int i = 0; i < nodes.count(); i++) {
    const int slotsOf[3] = {nodes.normalSlot[i], nodes.tangentSlot[i], (int)nodes.tangentSlot2.size() > i ? nodes.tangentSlot2[i] : -1};
    int vertex = -1;
    for (int s : slotsOf) if (s >= 0) for (auto &e : rowsOf[s]) vertex = e.first / dim;
    if (vertex < 0) continue;                                 // no slot
    const PetscInt row0 = state.rowOf[(size_t)dim * vertex];
    if (row0 < first || row0 >= last) continue;               // another rank's node
    RankNode node;
    double Q[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    int q = 0;
    for (int s : slotsOf) {
      if (s < 0) continue;
      for (auto &e : rowsOf[s]) {
        if (e.first / dim != vertex) ExecError("contactRanksContact: a slot's row spans two vertices");
        Q[q][e.first % dim] = e.second;
      }
      node.local[q] = (int)ownedSlots.size();
      ownedSlots.push_back(s);
      q++;
    }
    node.slots = q;
    for (int c = 0; c < dim; c++)                             // the fixed components complete the frame
      if (state.fixedOwned[state.rowOf[(size_t)dim * vertex + c] - first]) {
        if (q >= dim) ExecError("contactRanksContact: a contact node with more slots and fixed components than its dimension");
        Q[q][c] = 1;
        q++;
      }
    for (int a = 0; a < dim; a++) for (int b = 0; b < dim; b++) {
      double dot = 0;
      for (int c = 0; c < dim; c++) dot += Q[a][c] * Q[b][c];
      if (q != dim || std::fabs(dot - (a == b ? 1. : 0.)) > 1e-9)
        rankFail(3, "the contact node at (" + std::to_string(nodes.x[i]) + ", " + std::to_string(nodes.y[i]) + ", " + std::to_string(nodes.z[i])
                 + ") has slot directions and fixed components that are not an orthonormal frame: -ranks cannot rotate it");
    }
    for (int c = 0; c < dim; c++) node.row[c] = state.rowOf[(size_t)dim * vertex + c];
    for (int kk = 0; kk < dim; kk++) {                         // v_a = sum_k Q[k][a] w_k
      for (int a = 0; a < dim; a++) CHECK(MatSetValue(state.R, node.row[a], node.row[kk], Q[kk][a], INSERT_VALUES));
      if (kk >= node.slots) state.fixedRows.push_back(node.row[kk]);
    }
    for (int c = 0; c < dim; c++) inNode[node.row[c] - first] = 1;
    state.nodes.push_back(node);
  }
  for (PetscInt i = 0; i < state.owned; i++) if (!inNode[i]) {
    CHECK(MatSetValue(state.R, first + i, first + i, 1., INSERT_VALUES));
    if (state.fixedOwned[i]) state.fixedRows.push_back(first + i);
  }
  CHECK(MatAssemblyBegin(state.R, MAT_FINAL_ASSEMBLY));
  CHECK(MatAssemblyEnd(state.R, MAT_FINAL_ASSEMBLY));
  CHECK(MatPtAP(state.S, state.R, MAT_INITIAL_MATRIX, 1.5, &state.Srot));
  CHECK(MatDestroy(&state.S));                                // (R'SR only from here on)
  if (state.direct) {
    // F: R'SR with the fixed rows and columns the identity's, factorized once (condensed.cpp)
    std::vector<PetscInt> rows = state.fixedRows;
    std::sort(rows.begin(), rows.end());
    CHECK(MatZeroRowsColumns(state.Srot, (PetscInt)rows.size(), rows.data(), 1., nullptr, nullptr));
  } else {                                                    // the Newton matrix of the whole system (step.cpp)
    CHECK(MatDuplicate(state.Srot, MAT_COPY_VALUES, &state.J));
    CHECK(MatSetOption(state.J, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
    CHECK(MatSetOption(state.J, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
  }
  // the law on the owned slots: the kernel's data of each (contactlaw.hpp's Slots)
  const int ns = (int)ownedSlots.size();
  std::vector<int> localOf(nc, -1);
  for (int l = 0; l < ns; l++) localOf[ownedSlots[l]] = l;
  contactlaw::Slots &law = state.law;
  law.P = k.law.P;
  law.resize(ns);
  state.slotGlobal = ownedSlots;
  state.slotRow.assign(ns, 0);
  state.W.assign(ns, 0.);
  for (const RankNode &node : state.nodes) for (int s = 0; s < node.slots; s++) state.slotRow[node.local[s]] = node.row[s];
  Vec diagonal;
  CHECK(MatCreateVecs(state.Srot, &diagonal, nullptr));
  CHECK(MatGetDiagonal(state.Srot, diagonal));
  const PetscScalar *d;
  CHECK(VecGetArrayRead(diagonal, &d));
  for (int l = 0; l < ns; l++) {
    const int j = ownedSlots[l];
    law.normal[l] = k.law.normal[j];
    law.partner[l] = k.law.partner[j] >= 0 ? localOf[k.law.partner[j]] : -1;
    law.pair[l] = k.law.pair[j] >= 0 ? localOf[k.law.pair[j]] : -1;
    if ((k.law.partner[j] >= 0 && law.partner[l] < 0) || (k.law.pair[j] >= 0 && law.pair[l] < 0))
      ExecError("contactRanksContact: a slot's partner is on another rank");
    law.setBound(l, k.law.g[j]);
    state.W[l] = nodes.slotWeight[j];
  }
  // r_j = r / Dw_jj with Dw = C S^-1 C'W: here with the estimate Dw_jj ~ W_j / (R'SR)_jj (no solve
  // per slot); a 3D pair shares its r (contactlaw.hpp), 2 / (Dw_jj + Dw_qq) as the kernel's
  auto delassus = [&](int l) { return state.W[l] / d[state.slotRow[l] - first]; };
  for (int l = 0; l < ns; l++) {
    const int q = law.pair[l];
    law.setAugmentation(l, q >= 0 ? r * 2 / (delassus(l) + delassus(q)) : r / delassus(l));
  }
  law.roundoff = 10 * DBL_EPSILON / tol;
  CHECK(VecRestoreArrayRead(diagonal, &d));
  CHECK(VecDestroy(&diagonal));
  // rank 0 gathers the slots of every rank
  state.slotCounts.assign(state.size, 0);
  MPI_Gather(&ns, 1, MPI_INT, state.slotCounts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  state.slotDispls.assign(state.size, 0);
  for (int q = 1; q < state.size; q++) state.slotDispls[q] = state.slotDispls[q - 1] + state.slotCounts[q - 1];
  state.allSlots.assign(state.rank == 0 ? nc : 0, 0);
  MPI_Gatherv(state.slotGlobal.data(), ns, MPI_INT, state.allSlots.data(), state.slotCounts.data(), state.slotDispls.data(), MPI_INT, 0,
              MPI_COMM_WORLD);
  // vectors, the linear solver (options prefix ranks_)
  CHECK(MatCreateVecs(state.Srot, &state.w, &state.b));
  for (Vec *v : {&state.brot, &state.bJ, &state.Sw, &state.x0, &state.vOwned, &state.y}) CHECK(VecDuplicate(state.b, v));
  CHECK(KSPCreate(PETSC_COMM_WORLD, &state.ksp));
  CHECK(KSPSetOptionsPrefix(state.ksp, "ranks_"));
  PC pc;
  CHECK(KSPGetPC(state.ksp, &pc));
  // Both paths: GMRES(100), right-preconditioned (its test reads the true residual,
  // |b - A x| <= 1e-14 |b|), from zero, at most 2000 iterations. Direct: on F, preconditioned by
  // MUMPS's Cholesky of F, made here once per run (one iteration: the back-substitutions of
  // condensed.cpp, refined). Iterative: on the Newton matrix J of the whole system (the
  // multipliers come from its momentum rows, m = (R'b - R'SR w)/W, and a looser solve leaves
  // the contact residual above -tol; from zero: the last iterate's w, far larger than b where a
  // body stops, failed PETSc's divergence test on the column scenes), preconditioned by
  // BoomerAMG on J, built again at every Newton iteration. (Keeping the hierarchy of an
  // earlier J, rebuilt when GMRES needs 10 iterations more than just after a build, cost 1.7
  // times the time at 48x24x24 in 3D, where a quarter of the contact rows change at every
  // iteration: docs/performance.md, "Across ranks".)
  CHECK(KSPSetType(state.ksp, KSPGMRES));
  CHECK(KSPGMRESSetRestart(state.ksp, 100));
  CHECK(KSPSetPCSide(state.ksp, PC_RIGHT));
  CHECK(KSPSetNormType(state.ksp, KSP_NORM_UNPRECONDITIONED));
  CHECK(KSPSetTolerances(state.ksp, 1e-14, 0., 1e300, 2000));
  if (state.direct) {
    CHECK(PCSetType(pc, PCCHOLESKY));
    CHECK(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
    CHECK(KSPSetOperators(state.ksp, state.Srot, state.Srot));
  } else {
    // BoomerAMG (hypre): with GAMG at its defaults (Chebyshev smoothing) the linear solve of the
    // slab's first step failed at 212k unknowns and broke down at 700k (GMRES breakdown), where
    // BoomerAMG takes about 25 iterations (docs/performance.md, "Across ranks"); GAMG stays
    // available (-ranks_pc_type gamg, with the rigid-body modes below as its near-null space)
    CHECK(PCSetType(pc, PCHYPRE));
    CHECK(PCHYPRESetType(pc, "boomeramg"));
    // the rigid-body modes in the nodes' frames: R' z for each mode z of the coordinates
    Vec coordinates;
    CHECK(VecDuplicate(state.b, &coordinates));
    CHECK(VecSetBlockSize(coordinates, state.dim));
    PetscScalar *x;
    CHECK(VecGetArray(coordinates, &x));
    for (PetscInt i = 0; i < state.owned; i++) x[i] = state.xyz[i];
    CHECK(VecRestoreArray(coordinates, &x));
    MatNullSpace modes;
    CHECK(MatNullSpaceCreateRigidBody(coordinates, &modes));
    PetscBool hasConstant;
    PetscInt count;
    const Vec *vectors;
    CHECK(MatNullSpaceGetVecs(modes, &hasConstant, &count, &vectors));
    std::vector<Vec> rotated(count);
    for (PetscInt q = 0; q < count; q++) {
      CHECK(VecDuplicate(state.b, &rotated[q]));
      CHECK(MatMultTranspose(state.R, vectors[q], rotated[q]));
    }
    CHECK(MatNullSpaceCreate(PETSC_COMM_WORLD, PETSC_FALSE, count, rotated.data(), &state.nearNull));
    for (Vec &v : rotated) CHECK(VecDestroy(&v));
    CHECK(MatNullSpaceDestroy(&modes));
    CHECK(VecDestroy(&coordinates));
    CHECK(MatSetNearNullSpace(state.J, state.nearNull));
  }
  CHECK(KSPSetFromOptions(state.ksp));
  // a factorization with no package named (PETSC_OPTIONS=-ranks_pc_type lu, which also forgets
  // the direct path's package set above): MUMPS's, as PETSc itself picks on several ranks, named
  // now so that ranks_engine says which (it read "PETSc LU" while PETSc chose MUMPS at the first
  // solve)
  PCType type;
  CHECK(PCGetType(pc, &type));
  const bool factorization = type && (std::string(type) == PCLU || std::string(type) == PCCHOLESKY);
  MatSolverType package = nullptr;
  if (factorization) {
    CHECK(PCFactorGetMatSolverType(pc, &package));
    if (!package) {
      CHECK(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
      CHECK(PCFactorGetMatSolverType(pc, &package));
    }
  }
  if (state.direct) {                                         // the factorization, once per run
    if (!factorization)
      failAlike(2, std::string("option -ranksolver direct: its preconditioner must be a factorization (LU or Cholesky), but PETSC_OPTIONS chose ")
                   + (type ? type : "none") + "; use -ranksolver iterative");
    // the Delassus matrix is MUMPS's entries of the inverse (condensed.cpp): MUMPS's factor only
    if (!package || std::string(package) != MATSOLVERMUMPS)
      failAlike(2, std::string("option -ranksolver direct: its factorization must be MUMPS's (the Delassus matrix is made from MUMPS's "
                               "entries of the inverse), but PETSC_OPTIONS chose ") + (package ? package : "PETSc's own")
                   + "; use -ranksolver iterative with that factorization as its preconditioner");
    CHECK(KSPSetUp(state.ksp));
    // a factorization that failed (MUMPS's INFOG(1) < 0: out of memory, a matrix not positive
    // definite, options of PETSC_OPTIONS) is said here, not at its first solve
    PCFailedReason why = PC_NOERROR;
    CHECK(PCGetFailedReason(pc, &why));
    if (why != PC_NOERROR) {                                  // (MUMPS's, as checked above)
      Mat factor = nullptr;
      PetscInt info1 = 0, info2 = 0;
      CHECK(PCFactorGetMatrix(pc, &factor));
      CHECK(MatMumpsGetInfog(factor, 1, &info1));
      CHECK(MatMumpsGetInfog(factor, 2, &info2));
      failAlike(3, "the factorization of S (-ranksolver direct: " + builtSolver() + ") failed (PETSc's reason " + PCFailedReasons[why]
                   + ", MUMPS's INFOG(1) = " + std::to_string((long)info1) + ", INFOG(2) = " + std::to_string((long)info2)
                   + "): out of memory, or a matrix that is not positive definite (check the mesh)" + underOptions());
    }
    countFactorizations();
  }
  return 0;
}

// ---------------------------------------------------------------- the run's figures, the end
long peaks(KN<double> *const &pout) {
  announce(CommandEnd);                               // (the other ranks' contactRanksServe returns)
  double mine = peakMegabytes();
  std::vector<double> all(state.size);
  MPI_Gather(&mine, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  if (state.rank == 0) {
    KN<double> &out = *pout;
    out.resize(state.size);
    for (int r = 0; r < state.size; r++) out[r] = all[r];
  }
  return 0;
}
long counters(KN<double> *const &pout) {
  KN<double> &out = *pout;
  out.resize(6);
  out[0] = state.newtonIterations; out[1] = state.linearSolves; out[2] = state.linearIterations;
  out[3] = state.direct ? state.factorizations : state.linearSolves;   // (iterative: a BoomerAMG hierarchy a solve)
  out[4] = state.refinements; out[5] = state.floors;
  return 0;
}
// PETSC_OPTIONS as the run had it, for summary.txt: "none" if unset or empty; control bytes
// and bytes outside ASCII as '?' (the file is plain text)
string *petscOptions(Stack stack, const long &) {
  const char *options = std::getenv("PETSC_OPTIONS");
  std::string text = options && *options ? options : "none";
  for (char &c : text) if ((unsigned char)c < 32 || (unsigned char)c > 126) c = '?';
  return Add2StackOfPtr2Free(stack, new string(text));
}

long finish() {
  MPI_Barrier(MPI_COMM_WORLD);
  if (state.started && state.rank == 0) {
    // an option of the ranks' solver (prefix ranks_) that nothing read: misspelt, or not for
    // this path (said once, by rank 0; the run's results stand)
    PetscInt count = 0;
    char **names = nullptr, **values = nullptr;
    if (PetscOptionsLeftGet(nullptr, &count, &names, &values) == 0) {
      for (PetscInt i = 0; i < count; i++) {
        const std::string name = names[i] ? names[i] : "";
        if (name.rfind("ranks_", 0) == 0)
          std::fprintf(stderr, "warning: PETSC_OPTIONS: -%s was not used by the solver (misspelt, or not for -ranksolver %s)\n", names[i],
                       state.direct ? "direct" : "iterative");
        // an option of a solver's object without the prefix: the ranks' solver reads -ranks_...
        else for (const char *object : {"ksp_", "pc_", "mat_", "mg_", "sub_"})
          if (name.rfind(object, 0) == 0) {
            std::fprintf(stderr, "warning: PETSC_OPTIONS: -%s was not used: the solver's options have the prefix ranks_ (-ranks_%s)\n",
                         names[i], names[i]);
            break;
          }
      }
      PetscOptionsLeftRestore(nullptr, &count, &names, &values);
    }
  }
  if (state.started) {
    if (state.ksp) KSPDestroy(&state.ksp);
    if (state.nearNull) MatNullSpaceDestroy(&state.nearNull);
    for (Mat *A : {&state.S, &state.R, &state.Srot, &state.J, &state.products[0], &state.products[1], &state.products[2]}) if (*A) MatDestroy(A);
    for (Vec *v : {&state.b, &state.brot, &state.w, &state.bJ, &state.Sw, &state.x0, &state.vOwned, &state.x, &state.px[0], &state.px[1],
                   &state.px[2], &state.y}) if (*v) VecDestroy(v);
    PetscFinalize();
    state.started = false;
  }
  return 0;
}
}  // namespace ranks

using namespace ranks;

typedef KN<double> *Array;
typedef KN<long> *Integers;
typedef Matrice_Creuse<double> *Matrix;

static void Load_Init() {
  Global.Add("contactRanksStart", "(", new OneOperator1_<long, string *>(start));
  Global.Add("contactRanksEngine", "(", new OneOperator1s_<string *, long>(engine));
  Global.Add("contactRanksShareText", "(", new OneOperator1s_<string *, string *>(shareText));
  Global.Add("contactRanksNumbering", "(", new OneOperator3_<long, Integers, long, long>(numbering));
  Global.Add("contactRanksMatrix", "(", new OneOperator4_<long, double, Matrix, Array, Array>(matrix));
  Global.Add("contactRanksContact", "(", new OneOperator5_<long, Matrix, string *, double, long, double>(contact));
  Global.Add("contactRanksStep", "(", new OneOperator5_<long, Array, Array, Array, Array, Array>(step));
  Global.Add("contactRanksServe", "(", new OneOperator5_<long, Array, Array, Array, Array, Array>(serve));
  Global.Add("contactRanksProduct", "(", new OneOperator4_<long, Matrix, long, Integers, Array>(productBinding));
  Global.Add("contactRanksFailure", "(", new OneOperator1s_<string *, long>(failure));
  Global.Add("contactRanksPeaks", "(", new OneOperator1_<long, Array>(peaks));
  Global.Add("contactRanksCounters", "(", new OneOperator1_<long, Array>(counters));
  Global.Add("contactRanksFinish", "(", new OneOperator0<long>(finish));
  Global.Add("contactRanksPetscOptions", "(", new OneOperator1s_<string *, long>(petscOptions));
  Global.Add("contactRanksDelassus", "(", new OneOperator1_<long, double>(delassus));
}

LOADFUNC(Load_Init)
