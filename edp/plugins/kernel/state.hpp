// state.hpp: the kernel's state, one value of type Kernel: the contact nodes and the law on
// their slots, the solver settings, the factorization of S and the Delassus matrix, the
// products with M, A, B, the record of the steps, the Newton and fixed-point states, the
// node rows' file and the solver log. The FreeFEM functions act on the current instance of
// the registry (registry.cpp); the modules take it as an argument:
//   bindings.cpp       the FreeFEM functions (the kernel's API, listed at its top)
//   registry.cpp       the instances, the current one
//   columns.cpp        the tables of columns.hpp, by name
//   nodes.cpp          the contact nodes, the law's data, the nodes' velocities
//   factorization.cpp  S factorized, the Delassus matrix, the back-substitutions
//   products.cpp       M, A, B merged; their products
//   newton.cpp         the semismooth Newton of a step and its safeguards
//   fixedpoint.cpp     the projected Gauss-Seidel of a step
//   record.cpp         the nodal table, the record of a step, contact_nodes_history.txt's and
//                      zone_boundaries.txt's rows
// No module includes FreeFEM's headers but bindings.cpp: the others see plain arrays.
#ifndef CONTACTKERNEL_STATE_HPP
#define CONTACTKERNEL_STATE_HPP
#include <cholmod.h>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <functional>
#include <string>
#include <vector>
#include "contactlaw.hpp"
#include "columns.hpp"

template <class R> class KN;   // FreeFEM's array (bindings.cpp): the history arrays are the script's

namespace contactkernel {

// Stops the FreeFEM function that called the kernel with this message (bindings.cpp: an
// execution error of the script, never a crash).
[[noreturn]] void kernelError(const std::string &message);

// A FreeFEM sparse matrix as the bindings hand it over: its entries as triplets (0-based).
struct SparseTriplets {
  int rows = 0, columns = 0;
  size_t count = 0;
  const int *row = nullptr, *column = nullptr;
  const double *value = nullptr;
  bool lowerHalf = false;           // symmetric, stored by one triangle (FreeFEM's "half")
  bool oneBased = false;            // FreeFEM's "fortran" numbering
};
// ... or by rows (CSR: the entries of row i at start[i] .. start[i+1]-1)
struct SparseRows {
  const int *start = nullptr, *column = nullptr;
  const double *value = nullptr;
};

// ---------------------------------------------------------------- the contact nodes
struct ContactNodes {
  std::vector<double> x, y, z, weight, g;                 // per node: x, y, z (0 in 2D), w, the velocity bound g
  std::vector<int> observeStart, observeColumn;          // v -> v_nu, v_tau per node (CSR)
  std::vector<double> observeValue;
  int observeWidth = 0;                                  // the observation's columns: its largest + 1
  std::vector<int> normalSlot, tangentSlot, tangentSlot2;   // per node, -1: none (tangentSlot2: 3D)
  int rowsPerNode = 2;                         // of the observation: v_nu, v_tau (and v_tau2 in 3D)
  std::vector<double> frame;                   // 3D: per node n, t1, t2 (9 values), and Gamma3's mean
  double meanT1[3] = {0, 0, 0}, meanT2[3] = {0, 0, 0};   // frame T1, T2 (contactKernelNodeFrames)
  std::vector<double> slotWeight;              // W per slot: its node's weight
  // Gamma3's edges (contactKernelNodeEdges): the pairs of neighbouring nodes a < b, sorted,
  // each once (2D: its boundary edges; 3D: the edges of its triangles); each node's neighbours
  // (CSR, ascending); and the positions along Gamma3 of each edge's two ends (2D: arc length
  // from Gamma3's first node, setNodeEdges; not used in 3D)
  std::vector<int> edgeA, edgeB, neighbourStart, neighbour;
  std::vector<double> edgeS;                   // 2 per edge: the position of a, of b
  bool ready = false;                          // set by contactKernelNodes, reset by a law parameter
  std::string lawProblem;                      // why checkLaw refused the law (contactKernelNodes returned 1)
  int count() const { return (int)x.size(); }
  int neighbours(int i) const { return neighbourStart.empty() ? 0 : neighbourStart[i + 1] - neighbourStart[i]; }
  double distance(int i, int j) const {        // between nodes i and j
    return std::sqrt((x[j] - x[i]) * (x[j] - x[i]) + (y[j] - y[i]) * (y[j] - y[i]) + (z[j] - z[i]) * (z[j] - z[i]));
  }
};

struct SolverSettings {
  double tol = 1e-10, r = 1, dt = 0;
  long stepOffset = 0;                                   // steps before the first recorded (a restart): t = (offset + n) dt
  int maxit = 50;
  bool safeguards = true;
  bool verbose = false;                        // -verbose: the Newton log (logIteration)
  int ordering = 0;                            // of S's factorization: 0 CAMD, 1 METIS on the interior
};

// ---------------------------------------------------------------- S, its factor, the Delassus matrix
struct Factorization {
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
  bool external = false;                // no factor: the steps are solved by the ranks (externalFactor)
  // -ranksolver direct (edp/plugins/ranks/condensed.cpp): S factorized once by MUMPS across the
  // ranks, which make the two halves of a back-substitution and Dw (externalDelassus); the
  // Newton of a step is this kernel's, on rank 0
  std::function<void(const double *b, double *cFree)> externalFree;   // cFree = C S^-1 b
  std::function<void(const double *m, double *v)> externalFinish;      // v = S^-1 (b - C'W m)
  long generation = 0;                  // counts the factorizations
  long delassusGeneration = -1;         // the factor Dw belongs to

  // forget the factor and everything derived from it; L is then null, so a factor exists
  // (L != null) only after a successful factorization
  void release();
  // out = S^-1 in with CHOLMOD, workspace kept between calls
  void apply(int sys, const double *in, double *out);
  ~Factorization() { release(); }
};

// The coefficients of S = cm M + ca A + cb B + D (+ tgv where fixed is 1), summed from the
// merged M, A, B by contactKernelFactorizeStep.
struct StepMatrix {
  double cm = 0, ca = 0, cb = 0, tgv = 1e30;
  const SparseTriplets *D = nullptr;
  const double *fixed = nullptr;      // 1 on the fixed degrees of freedom
  int fixedCount = 0;                 // its size
};

// ---------------------------------------------------------------- products with M, A, B
// The three matrices of the energy terms share one sparsity pattern (P1 on one mesh): kept
// as one CSR structure with three values per entry, so that M v, A v and B v cost one pass.
// Where the pattern is made of full 2x2 blocks (the two components of a node, as [P1, P1]
// numbers them), also as blocks: one column index and two contiguous x values for four
// entries. Each row is summed over the same entries in the same order either way, so the
// results are the same to the last bit; the blocks only take less time.
struct ProductMatrices {
  int n = 0;
  std::vector<int> start, column;
  std::vector<double> values;       // 3 per entry: M, A, B (emptied when the blocks hold them)
  bool blocked = false;
  std::vector<int> blockStart, blockColumn;
  std::vector<double> blockValues;  // 12 per block: rows 2I, 2I+1 by columns 2J, 2J+1, each M, A, B

  // -ranks: the products computed elsewhere (the ranks' distributed M, A, B: edp/plugins/ranks/step.cpp), the
  // three results whole on the first rank; none of the above is held then
  std::function<void(const double *x, double *mx, double *ax, double *bx)> external;

  // row(i, (M x)_i, (A x)_i, (B x)_i) for i = 0 .. n-1, in that order
  template <class Row> void forEachRow(const double *x, Row row) const {
    if (external) {
      std::vector<double> mx(n), ax(n), bx(n);
      external(x, mx.data(), ax.data(), bx.data());
      for (int i = 0; i < n; i++) row(i, mx[i], ax[i], bx[i]);
      return;
    }
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
  void makeBlocks();                // products.cpp
  // M, A, B of entry e (of row i) of the CSR pattern
  const double *entry(int i, int e) const {
    if (!blocked) return values.data() + 3 * (size_t)e;
    const int p = e - start[i];
    return blockValues.data() + 12 * (size_t)(blockStart[i / 2] + p / 2) + 6 * (i % 2) + 3 * (p % 2);
  }
};

// ---------------------------------------------------------------- the record of the steps
// a zone boundary located on an edge of Gamma3 (zone_boundaries.txt): its step, kind (1 B, 2 C),
// position along Gamma3 (2D; nan in 3D) and point
struct ZoneBoundary {
  long step;
  int kind;
  double s, x, y, z;
};
struct EnergyRecord {
  std::vector<double> vOld, Mv, Av, Bv;  // v_{n-1}; workspace
  double energyOld = 0;                  // kinetic + elastic of the previous step
  long generation = -1;                  // the factor (Factorization::generation) the record started with
  long step = 0;                         // the steps recorded since recordStart
  std::vector<ZoneBoundary> boundaries;  // those of every step recorded since recordStart
};
// the script's arrays each record writes a row into (contactKernelHistory; bindings.cpp)
struct HistoryArrays { KN<double> *info = nullptr, *rows = nullptr; };

// contact_nodes_history.txt: one stream kept open, the columns the script named
struct NodesFile {
  std::ofstream stream;
  std::string path;
  // per column: a nodal column (>= 0), or one of the row's own values below
  enum Source { Step = -1, Time = -2, Node = -3, X = -4, Y = -5, Z = -6 };
  std::vector<int> columns;
  bool hasZ = false;
};

// ---------------------------------------------------------------- Newton
struct Term { int index; double coef; };
// The Newton matrix of the relations and its base N0 with its LU factors, the low-rank
// correction of the rows that differ, and the counters of summary.txt (newton.cpp).
struct NewtonState {
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
  long watchdogs = 0;                  // watchdog starts (safeguardStep): Newton iterates kept although the merit rose
  long watchdogReturns = 0;            // ... that ended back at their reference
  std::vector<int> lastKeys;           // the pieces at the last piecesRepeat() of the step
  bool keptOverReplacements = false;   // the last safeguardStep kept a Newton iterate that did not
                                       // lower the merit, neither replacement doing better (the log says so)
  // the watchdog of the step under way (safeguardStep; reset by newtonStart)
  struct Watchdog {
    int replacedInRow = 0;             // Newton iterates the safeguard replaced in a row
    bool active = false;               // Newton iterates are kept whatever their merit
    bool spent = false;                // it ended at its reference: not again before a Newton iterate passes or the merit halves
    int restarts = 0;                  // ... the latter once a step
    double merit = 0;                  // the reference's merit, which a kept iterate must lower
    std::vector<double> c, m;          // the reference
    std::vector<std::vector<int>> keys;  // the pieces (Slots::key) of the iterates it kept
    std::vector<double> merits;        // ... and their merits
  } watch;
  std::vector<double> seen;            // the cycle guard's fingerprints of the step's iterations
  std::vector<double> rDefault;        // r_j at the start of a step
  long generation = -1;                // the factor the base matrix belongs to
};

// ---------------------------------------------------------------- the fixed point
struct FixedPointState {
  std::vector<double> rho;              // the local augmentations 1/Dw_jj - Kn_j
  long generation = -1;                 // the Delassus matrix they belong to
  // the variants measured in docs/stability.md, "Fixed point", set these two and rebuild
  const double omega = 1;               // relaxation of each slot's update
  const int window = 10;                // Anderson acceleration's window (0: none)
  long sweeps = 0;                      // over the run
  // the two levels (2D, fixedpoint.cpp, coarsePrepare): the K stiffest modes of the Delassus
  // matrix when a gap sets them apart (K = 0: none), Dw without them (deflated, its local
  // augmentations rhoDeflated), and Dw - deflated = sum_k delta_k P_k Q_k'
  long coarseGeneration = -1;
  int K = 0;
  std::vector<double> deflated, P, Q, delta, rhoDeflated;
  // the symmetrized Dw's eigenpairs (ascending), kept to split off fewer modes: the disk's K > 1
  // falls back to one mode for the rest of the run when a step does not converge with K
  std::vector<double> coarseVectors, coarseValues;
  // the coarse step's response X = dm/da, kept while the relations it came from repeat
  std::vector<double> coarseResponse, coarseRelationA, coarseRelationD;
  std::vector<int> coarseRelationASlot, coarseRelationDSlot;
  long coarseResponseGeneration = -1;
  // the disk's coarse root (fixedpoint.cpp, consistentStep): the slope of R(a) last found
  double coarseSlope = 1;
  // ... with K > 1 modes: the Jacobian of R(a) last found (K x K, column-major; Broyden)
  std::vector<double> coarseJacobian;
};

// -verbose: what the log said last (newton.cpp, logIteration)
struct SolverLog {
  std::vector<int> loggedPieces;
  bool explained = false;
};

// ---------------------------------------------------------------- the whole state
struct Kernel {
  ContactNodes nodes;
  contactlaw::Slots law;                // the law on every slot (contactlaw.hpp)
  SolverSettings settings;
  Factorization factor;
  ProductMatrices products;
  EnergyRecord record;
  HistoryArrays historyArrays;
  NodesFile nodesFile;
  NewtonState newton;
  FixedPointState fixedPoint;
  SolverLog log;
};

// registry.cpp: the instance the FreeFEM functions act on
Kernel &currentKernel();

}  // namespace contactkernel
#endif
