// ranks.hpp: what the files of the ranks' plugin share (ranks.cpp: the set-up, the run's
// figures and the FreeFEM functions; step.cpp: a step, the record's products; condensed.cpp:
// the direct path's steps; partition.cpp: the mesh's partition): the rank's
// state, its failure, and the commands rank 0 broadcasts to the other ranks.
#ifndef CONTACT_RANKS_HPP
#define CONTACT_RANKS_HPP
#include "ff++.hpp"
#include "AFunction_ext.hpp"
#include <mpi.h>
#include <petscksp.h>
#include <petsc/private/petscimpl.h>   // PetscObjectStateGet (the factor's state: its factorizations)
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

namespace ranks {
using contactkernel::Kernel;
using contactkernel::currentKernel;
using contactkernel::copyOf;
using contactkernel::copyInto;

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
  Mat products[3] = {nullptr, nullptr, nullptr};   // M, A, B: the record's products (contactRanksProduct)
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
  bool direct = true, verbose = false;   // direct: S factorized once, the kernel's Newton (condensed.cpp)
  Vec y = nullptr;                        // direct: F^-1 R'b of the step (its free velocities)

  double tol = 1e-10;
  int maxit = 50;
  long newtonIterations = 0, linearSolves = 0, linearIterations = 0;
  long factorizations = 0;                // direct: MUMPS's numeric factorizations (the factor's state changes)
  long refinements = 0;                   // direct: the Newton run again after a step's consistency test (condensed.cpp)
  long floors = 0;                        // direct: steps taken at the round-off floor of that test
  PetscObjectState factorState = -1;
  std::string failure;                    // why the last step's linear solve failed ("" if it did not)
};
extern RankState state;

// An error of one rank: said with the rank, then the run stops as on a signal, but with the
// exit code given (ranks.cpp)
[[noreturn]] void rankFail(int code, const std::string &message);
// ... an error every rank finds alike: rank 0 says it, the others wait 3 s first
[[noreturn]] void failAlike(int code, const std::string &message);
void check(PetscErrorCode status, const char *what);
#define CHECK(call) check((call), #call)

// ---------------------------------------------------------------- what rank 0 asks of the others
// Rank 0 runs the script's time loop; the other ranks serve it (contactRanksServe): each
// collective it starts is announced by a command, broadcast from rank 0.
enum Command { CommandStep = 1, CommandProducts = 2, CommandEnd = 3, CommandFree = 4, CommandFinish = 5 };
inline void announce(int command) { if (state.rank == 0) MPI_Bcast(&command, 1, MPI_INT, 0, MPI_COMM_WORLD); }
inline int nextCommand() {
  int command = 0;
  MPI_Bcast(&command, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return command;
}

// ranks.cpp
std::string builtSolver();                          // the Krylov method and preconditioner as built
std::string underOptions();                         // ", under PETSC_OPTIONS=..." if set, else ""
// step.cpp
bool solveChecked(Mat A, Vec b, Vec x, const char *what);   // KSPSolve, its true residual checked
void countFactorizations();
void gatherRows(const PetscScalar *owned, double *out);
void scatterRows(const double *in, Vec v);
void gatherSlots(const std::vector<double> &owned, double *out);
void multiplyProducts(const double *x, double *mx, double *ax, double *bx);
long step(KN<double> *const &prhs, KN<double> *const &pv, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo);
long serve(KN<double> *const &prhs, KN<double> *const &pv, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo);
string *failure(Stack stack, const long &);
// condensed.cpp (-ranksolver direct)
void freeAll(const double *b, double *cFree);
void finishAll(const double *m, double *v);
long delassus(const double &progress);
long condensedStep(KN<double> *const &prhs, KN<double> *const &pv, KN<double> *const &pc, KN<double> *const &pm, KN<double> *const &pinfo);

}  // namespace ranks
#endif
