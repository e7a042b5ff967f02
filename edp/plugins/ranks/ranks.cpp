// ranks.cpp: a run across MPI ranks through PETSc (-ranks N; docs/design.md, "Across ranks").
// Built by ./run.sh with mpicxx into edp/plugins/build/contactkernelmpi.so, together with the
// kernel's files and the law, contactlaw.hpp: the ranks evaluate the same law, compiled in.
// Loaded by edp/solve.edp under FreeFem++-mpi instead of contactkernel.so.
//
// What each rank holds: the rows of S = M/k + A + kB + C'W Kn C of the vertices it owns
// (PETSc's MPIAIJ; assembled from the elements of its part of the mesh, each rank passing
// the triplets of its own elements), the same rows of M, A and B (the record's products, which
// rank 0's kernel asks for through products.external), the rows of the node rotation R, and the
// contact nodes of its vertices with their slots. No rank holds a matrix whole. A step is a semismooth Newton on the whole system, in the
// nodes' frames (w = R'v: a contact node's rows become its slots' velocities):
//   R'SR w + W m = R'b on the slots' rows, and on each slot its piece's relation
//   sum_t a_t c + sum_t d_t m = h (contactlaw.hpp, Slots::relations), c = w there.
// A slot whose relation fixes its velocity (the bound, stick: d = 0) is a Dirichlet row of
// the rotated system; the others' multipliers are eliminated node by node (m_F = D_FF^-1
// (h_F - A_F c)), which adds a small block to the node's rows. Each Newton iteration solves
// that system with the path of -ranksolver: direct (MUMPS LU, a factorization per iteration)
// or iterative (GMRES preconditioned by hypre's BoomerAMG). The multipliers then
// follow from the momentum rows, m = (R'b - R'SR w)/W, the law is evaluated on the rank's own
// slots, and the residual is reduced over the ranks (its largest).
//
// FreeFEM functions (collective: every rank calls them, in the same order)
//   contactRanksStart(string options)  PETSc started (MPI already is); options: PETSc's, e.g.
//       "-ranks_ksp_view"; returns this rank
//   contactRanksEngine(0)  the solver as built (after contactRanksContact): "PETSc 3.18.5, GMRES
//       with MUMPS LU" (direct), "..., GMRES with BoomerAMG" (iterative), or what PETSC_OPTIONS chose
//   contactRanksShareText(string text)  rank 0's text, on every rank
//   contactRanksNumbering(int[int] rowOf, int owned)  rowOf: the PETSc row of every FreeFEM
//       degree of freedom (the same array on every rank); owned: the rows of this rank
//   contactRanksMatrix(matrix S, int[int] l2g, matrix D, real[int] fixed, real[int] xyz)  S of the
//       rank's elements (local numbering; l2g: local to FreeFEM's global), D = C'W Kn C (global;
//       rank 0 adds it), fixed: 1 on the Dirichlet degrees of freedom, xyz: the coordinates of
//       every vertex, one after the other (the rigid-body modes, GAMG's near-null space)
//   contactRanksContact(matrix C, string path, real tol, int maxit, real r)  the contact nodes of the rank's
//       vertices, their frames and the law's data of their slots (from the kernel instance, which
//       contactKernelNodes filled), the solver path (direct or iterative)
//   contactRanksProducts(matrix M, matrix A, matrix B, int[int] l2g, real[int] largest)  M, A, B of
//       the rank's elements, distributed as S is; rank 0's record takes its products from them;
//       largest: their largest entries
//   contactRanksStep(real[int] rhs, real[int] v, real[int] c, real[int] m, real[int] info)
//       (rank 0) one step from its rhs and start (c, m); it gets v, c, m and info (the columns
//       "solver_info"); returns the iterations, or -1 (every rank: no convergence)
//   contactRanksServe(real[int] rhs, real[int] v, real[int] c, real[int] m, real[int] info)
//       (the other ranks) their part of every step and product rank 0 asks for, until rank 0
//       calls contactRanksPeaks at the end of its time loop
//   contactRanksFailure(0)  why the last step's linear solve failed, "" if it did not
//   contactRanksPeaks(real[int] peaks)  rank 0 gets every rank's peak memory (MB)
//   contactRanksCounters(real[int] counts)  Newton iterations, linear solves (each builds its
//       preconditioner: a MUMPS factorization or a BoomerAMG hierarchy), linear iterations
//   contactRanksFinish()  waits for every rank, then ends PETSc
#include "ff++.hpp"
#include "AFunction_ext.hpp"
#include <mpi.h>
#include <petscksp.h>
#include <sys/resource.h>
#include <csignal>
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>
#include "kernel/kernel.hpp"
#include "kernel/ffarrays.hpp"

namespace {
using contactkernel::Kernel;
using contactkernel::currentKernel;
using contactkernel::copyOf;

// a contact node of this rank: its rows (component k of the rotated node at row[k]; the first
// `slots` are its slots, in the order of local[]), dim rows in all
struct RankNode {
  PetscInt row[3] = {0, 0, 0};
  int local[3] = {-1, -1, -1};
  int slots = 0;
};

struct RankState {
  bool started = false;
  int rank = 0, size = 1, dim = 2;
  PetscInt n = 0, first = 0, owned = 0;
  std::vector<PetscInt> rowOf;            // FreeFEM dof -> PETSc row
  std::vector<int> ownedDofs;             // the FreeFEM dof of each owned row
  std::vector<int> rowCounts, rowDispls, allDofs;    // rank 0: for the gathers
  std::vector<double> xyz;                // owned vertices' coordinates (the rigid-body modes)
  std::vector<char> fixedOwned;           // the owned rows fixed by a Dirichlet condition
  Mat S = nullptr, R = nullptr, Srot = nullptr, J = nullptr;
  Mat products[3] = {nullptr, nullptr, nullptr};   // M, A, B: the record's products (contactRanksProducts)
  Vec x = nullptr, px[3] = {nullptr, nullptr, nullptr};
  Vec b = nullptr, brot = nullptr, w = nullptr, bJ = nullptr, Sw = nullptr, x0 = nullptr, vOwned = nullptr;
  KSP ksp = nullptr;
  MatNullSpace nearNull = nullptr;
  std::vector<PetscInt> fixedRows;        // the rotated system's Dirichlet rows (owned)
  contactlaw::Slots law;                  // the law on the rank's slots
  std::vector<int> slotGlobal;            // each owned slot's number among all slots
  std::vector<PetscInt> slotRow;          // its rotated row
  std::vector<double> W;                  // its weight
  std::vector<RankNode> nodes;
  std::vector<int> slotCounts, slotDispls, allSlots;   // rank 0
  int nc = 0;                             // all slots
  bool direct = true, verbose = false;
  PetscBool baseFactor = PETSC_FALSE;     // -ranks_base_factor: the direct path's LU of R'SR, once

  double tol = 1e-10;
  int maxit = 50;
  long newtonIterations = 0, linearSolves = 0, linearIterations = 0;
  std::string failure;                    // why the last step's linear solve failed ("" if it did not)
};
RankState state;

// An error of one rank: said with the rank, then the run stops as on a signal, but with the
// exit code given (runtools' handler removes the unfinished output folder and exits with
// CONTACT_SUITE_RANK_FAILED; mpirun stops the other ranks)
[[noreturn]] void rankFail(int code, const std::string &message) {
  std::fprintf(stderr, "error: rank %d of %d: %s; no results written\n", state.rank, state.size, message.c_str());
  std::fflush(stderr);
  setenv("CONTACT_SUITE_RANK_FAILED", std::to_string(code).c_str(), 1);   // runtools' handler: exit with code, said already
  raise(SIGTERM);
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}
void check(PetscErrorCode status, const char *what) {
  if (status) rankFail(3, std::string("PETSc error ") + std::to_string((int)status) + " in " + what);
}
#define CHECK(call) check((call), #call)

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

// ---------------------------------------------------------------- what rank 0 asks of the others
// Rank 0 runs the script's time loop; the other ranks serve it (contactRanksServe): each
// collective it starts is announced by a command, broadcast from rank 0.
enum Command { CommandStep = 1, CommandProducts = 2, CommandEnd = 3 };
void announce(int command) { if (state.rank == 0) MPI_Bcast(&command, 1, MPI_INT, 0, MPI_COMM_WORLD); }
int nextCommand() {
  int command = 0;
  MPI_Bcast(&command, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return command;
}

// ---------------------------------------------------------------- start, numbering
long start(string *const &options) {
  if (!state.started) {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) ExecError("contactRanksStart: MPI is not running (FreeFem++-mpi under mpirun runs -ranks)");
    // PETSc installs signal handlers of its own (a crash then exits 59, leaving the output
    // folder): the suite's (runtools: they remove what the run created) are put back
    const int signals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGPROF, SIGXCPU, SIGXFSZ,
                           SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS, SIGPIPE};
    struct sigaction before[sizeof signals / sizeof signals[0]];
    for (size_t q = 0; q < sizeof signals / sizeof signals[0]; q++) sigaction(signals[q], nullptr, &before[q]);
    CHECK(PetscInitializeNoArguments());
    for (size_t q = 0; q < sizeof signals / sizeof signals[0]; q++) sigaction(signals[q], &before[q], nullptr);
    state.started = true;
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
           + (state.baseFactor ? " of R'SR, once per run" : "");
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

long numbering(KN<long> *const &pRowOf, const long &owned) {
  const KN<long> &rowOf = *pRowOf;
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
long matrix(Matrice_Creuse<double> *const &pS, KN<long> *const &pl2g, Matrice_Creuse<double> *const &pD, KN<double> *const &pfixed,
            KN<double> *const &pxyz) {
  const KN<long> &l2g = *pl2g;
  std::vector<PetscInt> I, Jc;
  std::vector<PetscScalar> V;
  forEachEntry(pS, [&](int i, int j, double a) {
    if (i >= l2g.N() || j >= l2g.N()) ExecError("contactRanksMatrix: the local matrix is larger than its map");
    I.push_back(state.rowOf[l2g[i]]); Jc.push_back(state.rowOf[l2g[j]]); V.push_back(a);
  });
  if (state.rank == 0) forEachEntry(pD, [&](int i, int j, double a) {
    I.push_back(state.rowOf[i]); Jc.push_back(state.rowOf[j]); V.push_back(a);
  });
  // every owned row keeps its diagonal (a Dirichlet row of the rotated system is set to 1 there)
  for (PetscInt i = 0; i < state.owned; i++) { I.push_back(state.first + i); Jc.push_back(state.first + i); V.push_back(0.); }
  const std::vector<double> fixed = copyOf(*pfixed);
  if ((PetscInt)fixed.size() != state.n) ExecError("contactRanksMatrix: fixed must have one value per degree of freedom");
  const std::vector<double> xyz = copyOf(*pxyz);
  const size_t vertices = xyz.size() / 3;
  state.dim = vertices > 0 ? (int)(state.n / (PetscInt)vertices) : 2;
  if (state.dim != 2 && state.dim != 3) ExecError("contactRanksMatrix: xyz must hold 3 coordinates per vertex");
  state.fixedOwned.assign(state.owned, 0);
  state.xyz.assign(state.owned, 0.);
  for (PetscInt i = 0; i < state.owned; i++) {
    const int dof = state.ownedDofs[i];
    state.fixedOwned[i] = fixed[dof] != 0;
    state.xyz[i] = xyz[3 * (dof / state.dim) + dof % state.dim];
  }
  state.S = assembledCOO(I, Jc, V, state.dim);
  return 0;
}

// ---------------------------------------------------------------- M, A, B for the record
void multiplyProducts(const double *x, double *mx, double *ax, double *bx);
// M, A, B of the rank's elements (local numbering; l2g: local to FreeFEM's global), assembled
// into three MPIAIJ matrices (the rows of the rank's vertices); largest: their largest entries
// |M_ij|, |A_ij|, |B_ij| (on every rank). On rank 0, the kernel's record takes its products from
// them (products.external): no rank holds M, A or B whole.
long productsBinding(Matrice_Creuse<double> *const &pM, Matrice_Creuse<double> *const &pA, Matrice_Creuse<double> *const &pB,
                     KN<long> *const &pl2g, KN<double> *const &plargest) {
  const KN<long> &l2g = *pl2g;
  Matrice_Creuse<double> *local[3] = {pM, pA, pB};
  KN<double> &largest = *plargest;
  largest.resize(3);
  for (int q = 0; q < 3; q++) {
    std::vector<PetscInt> I, Jc;
    std::vector<PetscScalar> V;
    forEachEntry(local[q], [&](int i, int j, double a) {
      if (i >= l2g.N() || j >= l2g.N()) ExecError("contactRanksProducts: the local matrix is larger than its map");
      I.push_back(state.rowOf[l2g[i]]); Jc.push_back(state.rowOf[l2g[j]]); V.push_back(a);
    });
    Mat &P = state.products[q];
    P = assembledCOO(I, Jc, V, 1);
    Vec rowMax;
    CHECK(MatCreateVecs(P, &state.px[q], &rowMax));
    CHECK(MatGetRowMaxAbs(P, rowMax, nullptr));
    PetscReal most = 0;
    CHECK(VecNorm(rowMax, NORM_INFINITY, &most));
    CHECK(VecDestroy(&rowMax));
    largest[q] = most;
  }
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
  // (-ranks_base_factor in PETSC_OPTIONS: the direct path's LU is R'SR's, made once per run; a
  // measurement, docs/performance.md, "Across ranks")
  state.baseFactor = PETSC_FALSE;
  if (state.direct) PetscOptionsGetBool(nullptr, "ranks_", "-base_factor", &state.baseFactor, nullptr);
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
  CHECK(MatDuplicate(state.Srot, MAT_COPY_VALUES, &state.J));
  CHECK(MatSetOption(state.J, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  CHECK(MatSetOption(state.J, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
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
  for (Vec *v : {&state.brot, &state.bJ, &state.Sw, &state.x0, &state.vOwned}) CHECK(VecDuplicate(state.b, v));
  CHECK(KSPCreate(PETSC_COMM_WORLD, &state.ksp));
  CHECK(KSPSetOptionsPrefix(state.ksp, "ranks_"));
  PC pc;
  CHECK(KSPGetPC(state.ksp, &pc));
  // Both paths: GMRES(100) on the Newton matrix J, right-preconditioned (its test reads the
  // true residual, |bJ - J w| <= 1e-14 |bJ|: the multipliers come from the momentum rows,
  // m = (R'b - R'SR w)/W, and a looser solve leaves the contact residual above -tol), from
  // zero (the last iterate's w, far larger than b where a body stops, failed PETSc's divergence
  // test on the column scenes), at most 2000 iterations; preconditioned by MUMPS's LU of J (direct: one
  // iteration) or by BoomerAMG on J (iterative), built again at every Newton iteration. (Keeping the
  // factor or the hierarchy of an earlier J, rebuilt when GMRES needs 10 iterations more than
  // just after a build, halved the factorizations on the paper scene but cost 1.2 to 1.7 times
  // the time at 48x24x24 in 3D, where a quarter of the contact rows change at every iteration:
  // docs/performance.md, "Across ranks".)
  CHECK(KSPSetType(state.ksp, KSPGMRES));
  CHECK(KSPGMRESSetRestart(state.ksp, 100));
  CHECK(KSPSetPCSide(state.ksp, PC_RIGHT));
  CHECK(KSPSetNormType(state.ksp, KSP_NORM_UNPRECONDITIONED));
  CHECK(KSPSetTolerances(state.ksp, 1e-14, 0., 1e300, 2000));
  if (state.direct) {
    CHECK(PCSetType(pc, PCLU));
    CHECK(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
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
  return 0;
}

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
  // (-ranks_base_factor: preconditioned by R'SR, which never changes: factorized once)
  CHECK(KSPSetOperators(state.ksp, state.J, state.baseFactor ? state.Srot : state.J));
  CHECK(KSPSolve(state.ksp, state.bJ, state.w));
  KSPConvergedReason reason;
  PetscInt its;
  CHECK(KSPGetConvergedReason(state.ksp, &reason));
  CHECK(KSPGetIterationNumber(state.ksp, &its));
  state.linearSolves++;
  state.linearIterations += its;
  if (reason == KSP_DIVERGED_NANORINF) return false;   // a non-finite residual: exit 5, as for one process
  // the true residual |bJ - J w|, computed here (PETSc's own norm is 0 under -ranks_ksp_type
  // preonly or -ranks_ksp_norm_type none)
  PetscReal norm = 0, bnorm = 0;
  CHECK(MatMult(state.J, state.w, state.Sw));
  CHECK(VecAYPX(state.Sw, -1., state.bJ));
  CHECK(VecNorm(state.Sw, NORM_2, &norm));
  CHECK(VecNorm(state.bJ, NORM_2, &bnorm));
  if (!std::isfinite(norm)) return false;              // a non-finite solution: exit 5
  // whatever PETSc's options say (PETSC_OPTIONS), a solve whose true residual is above 1e-8 |b|
  // is not a solution: the step fails rather than writing results of it
  if (reason >= 0 && !(norm <= 1e-8 * bnorm)) reason = KSP_DIVERGED_DTOL;
  if (reason < 0) {
    char text[400];
    std::snprintf(text, sizeof text, "the linear solve of a Newton iteration (-ranksolver %s: %s) stopped after %d iterations, "
                  "relative residual %.3g (PETSc's reason %s)", state.direct ? "direct" : "iterative", builtSolver().c_str(),
                  (int)its, bnorm > 0 ? (double)(norm / bnorm) : (double)norm,
                  norm > 1e-8 * bnorm && reason == KSP_DIVERGED_DTOL ? "DIVERGED_DTOL, or a residual above 1e-8 after its own test" : KSPConvergedReasons[reason]);
    state.failure = text;
    const char *options = std::getenv("PETSC_OPTIONS");
    if (options && *options) state.failure += std::string(", under PETSC_OPTIONS=\"") + options + "\"";
    return false;
  }
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
void gatherSlots(const std::vector<double> &owned, KN<double> &out) {
  std::vector<double> all(state.rank == 0 ? state.nc : 0);
  MPI_Gatherv(owned.data(), (int)owned.size(), MPI_DOUBLE, all.data(), state.slotCounts.data(), state.slotDispls.data(), MPI_DOUBLE, 0,
              MPI_COMM_WORLD);
  if (state.rank == 0) {
    if (out.N() != state.nc) out.resize(state.nc);
    for (int j = 0; j < state.nc; j++) out[state.allSlots[j]] = all[j];
  }
}

long step(KN<double> *const &prhs, KN<double> *const &pv, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo) {
  if (!state.ksp) ExecError("contactRanksStep: call contactRanksContact first");
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
    else rankFail(3, "contactRanksServe: an unknown command from rank 0");
  }
}

// why the last step failed in its linear solve, "" if it did not (every rank knows)
string *failure(Stack stack, const long &) { return Add2StackOfPtr2Free(stack, new string(state.failure)); }

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
  out.resize(3);
  out[0] = state.newtonIterations; out[1] = state.linearSolves; out[2] = state.linearIterations;
  return 0;
}
long finish() {
  MPI_Barrier(MPI_COMM_WORLD);
  if (state.started) {
    if (state.ksp) KSPDestroy(&state.ksp);
    if (state.nearNull) MatNullSpaceDestroy(&state.nearNull);
    for (Mat *A : {&state.S, &state.R, &state.Srot, &state.J, &state.products[0], &state.products[1], &state.products[2]}) if (*A) MatDestroy(A);
    for (Vec *v : {&state.b, &state.brot, &state.w, &state.bJ, &state.Sw, &state.x0, &state.vOwned, &state.x, &state.px[0], &state.px[1],
                   &state.px[2]}) if (*v) VecDestroy(v);
    PetscFinalize();
    state.started = false;
  }
  return 0;
}
}  // namespace

typedef KN<double> *Array;
typedef KN<long> *Integers;
typedef Matrice_Creuse<double> *Matrix;

static void Load_Init() {
  Global.Add("contactRanksStart", "(", new OneOperator1_<long, string *>(start));
  Global.Add("contactRanksEngine", "(", new OneOperator1s_<string *, long>(engine));
  Global.Add("contactRanksShareText", "(", new OneOperator1s_<string *, string *>(shareText));
  Global.Add("contactRanksNumbering", "(", new OneOperator2_<long, Integers, long>(numbering));
  Global.Add("contactRanksMatrix", "(", new OneOperator5_<long, Matrix, Integers, Matrix, Array, Array>(matrix));
  Global.Add("contactRanksContact", "(", new OneOperator5_<long, Matrix, string *, double, long, double>(contact));
  Global.Add("contactRanksStep", "(", new OneOperator5_<long, Array, Array, Array, Array, Array>(step));
  Global.Add("contactRanksServe", "(", new OneOperator5_<long, Array, Array, Array, Array, Array>(serve));
  Global.Add("contactRanksProducts", "(", new OneOperator5_<long, Matrix, Matrix, Matrix, Integers, Array>(productsBinding));
  Global.Add("contactRanksFailure", "(", new OneOperator1s_<string *, long>(failure));
  Global.Add("contactRanksPeaks", "(", new OneOperator1_<long, Array>(peaks));
  Global.Add("contactRanksCounters", "(", new OneOperator1_<long, Array>(counters));
  Global.Add("contactRanksFinish", "(", new OneOperator0<long>(finish));
}

LOADFUNC(Load_Init)
