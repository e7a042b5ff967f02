// kernel.hpp: what each module of the kernel offers the others and the FreeFEM bindings
// (bindings.cpp). Every function acts on the Kernel it is given (state.hpp); misuse stops the
// calling FreeFEM function with kernelError.
#ifndef CONTACTKERNEL_KERNEL_HPP
#define CONTACTKERNEL_KERNEL_HPP
#include "state.hpp"

namespace contactkernel {

// ---- registry.cpp: the instances; the first exists when the plugin is loaded
long newKernel();                       // a new instance, made current; its id
long useKernel(long id);                // makes instance id current; the id that was
long currentKernelId();
void deleteKernel(long id);             // not the current one

// ---- nodes.cpp: the contact nodes and the law's data
void setParameter(Kernel &k, const std::string &name, double value);
void setDampingFamily(Kernel &k, int family, const std::vector<double> &numbers);
// the bound profile (x increasing; empty: the parameter g everywhere, or the bound table)
void setBoundProfile(Kernel &k, const std::vector<double> &x, const std::vector<double> &g);
// the bound table: axes "xz" (any two of x, y, z), the grid along each (increasing), the
// values row by row (g[i b.size() + j] at (a_i, b_j)); empty: none
void setBoundTable(Kernel &k, const std::string &axes, const std::vector<double> &a, const std::vector<double> &b,
                   const std::vector<double> &g);
// the nodes at (x, y, z) (z = 0 in 2D), each with its g from the law there (velocityBound):
// returns 1 if the law or the bound is unusable (then k.nodes.lawProblem says why)
int setNodes(Kernel &k, int count, const double *x, const double *y, const double *z, const double *w, const long *normalSlot,
             const long *tangentSlot, const long *tangentSlot2);
void requireNodes(const Kernel &k, const char *who);
void setNodeObservation(Kernel &k, const SparseTriplets &O);
void setNodeFrames(Kernel &k, const std::vector<double> &frames, const double mean[6]);
// Gamma3's edges: pairs of neighbouring nodes (2D: its boundary edges; 3D: its triangles' edges)
void setNodeEdges(Kernel &k, const std::vector<long> &a, const std::vector<long> &b);
// v_nu, v_tau (v_tau2 in 3D) of every node from v, or from the slot velocities cv
void nodeVelocities(const Kernel &k, const double *v, const std::vector<double> &cv, std::vector<double> &ov);

// ---- factorization.cpp: S, the Delassus matrix, the two halves of a back-substitution
long factorize(Kernel &k, const SparseTriplets &S, const SparseTriplets &C);
long factorizeStep(Kernel &k, const StepMatrix &step, const SparseTriplets &C);
void requireFactor(const Kernel &k, const char *who);
void requireSlots(const Kernel &k, const char *who);              // a factor, or an external one
void externalFactor(Kernel &k, int n, const SparseTriplets &C);    // the steps solved elsewhere (-ranks)
void requireDelassus(const Kernel &k, const char *who);
void computeDelassus(Kernel &k);                                   // factor.Dw; r_j = r / Dw_jj
void externalDelassus(Kernel &k, std::vector<double> &&Dw);         // the ranks' Dw (nc x nc); r_j = r / Dw_jj
void solveWithFactor(Kernel &k, const double *b, double *x);       // x = S^-1 b
void freeVelocity(Kernel &k, const double *b, double *cFree);      // cFree = C S^-1 b (forward half)
void finishVelocity(Kernel &k, const double *m, double *v);        // v = S^-1 (b - C'W m) (backward half)
void slotVelocities(const Kernel &k, const double *v, std::vector<double> &cv);   // C v
void velocities(const Kernel &k, const double *cFree, const double *m, double *c);  // c = cFree - Dw m
void roundoffScale(Kernel &k, const double *cFree, const double *m);

// ---- products.cpp
bool sameProductPattern(const SparseTriplets matrices[3]);
void mergeProducts(Kernel &k, const SparseTriplets matrices[3]);    // the assembled triplets of one pattern
void mergeProductRows(Kernel &k, const SparseRows matrices[3], int n);   // the CSR forms, any patterns
void requireProducts(const Kernel &k, const char *who);

// ---- newton.cpp
void requireSolver(const Kernel &k, const char *who);   // the nodes and the Delassus matrix of the last factor
// one step's Newton from (c, m): returns the iterations, or -1; info: solver_info
long newtonStep(Kernel &k, const double *cFree, double *c, double *m, double info[solverInfoColumnCount]);
double newtonStart(Kernel &k, const double *cFree, const double *c, const double *m, double &merit);
int safeguardStep(Kernel &k, const double *cFree, const double *previous, const double *newtonM, double &merit,
                  double *c, double *m, double &residual, double &step, const double *DwNewtonM = nullptr);
bool piecesRepeat(Kernel &k);
int guard(Kernel &k, int it, const double *c, const double *m);
void endStep(Kernel &k);
bool stepConverged(Kernel &k, double residual, const double *c, int &unresolved);
double referenceEvaluate(Kernel &k, const double *c, const double *m, double &merit);
void logIteration(Kernel &k, int it, double residual, int outcome = 0, double step = 1);

// ---- fixedpoint.cpp
long fixedPointStep(Kernel &k, const double *cFree, double *c, double *m, double info[solverInfoColumnCount]);
// one iteration of the fixed point's map from m (c recomputed): its natural residual and merit
double fixedPointIteration(Kernel &k, const double *cFree, double *c, double *m, double &merit);

// ---- record.cpp
// the nodal table: per node, the columns of columns.hpp's "nodal", row after row
void nodalTable(Kernel &k, const double *v, const double *Lam, std::vector<double> &table);
void setNodesFileColumns(Kernel &k, const std::string &names);
// append step n's rows (the nodal table: row after row) to path; 1 if it cannot be written
long appendNodes(Kernel &k, const std::string &path, long n, double t, const double *x, const double *y, const double *z,
                 const std::vector<double> &table);
long closeNodesFile(Kernel &k);
// zone_boundaries.txt: the rows the records since recordStart kept, appended to path (the
// script wrote its header); 1 if it was not written whole
long writeZoneBoundaries(const Kernel &k, const std::string &path);
void recordStart(Kernel &k, const double *v0, const double *u0, double *Mv, double *Bu);
// the record of a step into record (recordColumnCount values); false if the energy balance is not finite
bool recordStep(Kernel &k, const double *v, const double *u, const double *Lam, const double *f, double *Mv, double *Bu,
                double *record);

}  // namespace contactkernel
#endif
