// ffarrays.hpp: FreeFEM's sparse matrices and arrays as the kernel's plain types, for the two
// files that see FreeFEM's types: bindings.cpp (the kernel's FreeFEM functions) and
// edp/plugins/ranks/ (the ranks' functions, built into the same plugin). Include
// after ff++.hpp.
#ifndef CONTACTKERNEL_FFARRAYS_HPP
#define CONTACTKERNEL_FFARRAYS_HPP
#include <vector>
#include "state.hpp"

namespace contactkernel {

inline MatriceMorse<double> *morse(Matrice_Creuse<double> *A) {
  MatriceCreuse<double> *a = A->A;
  if (!a) ExecError("contactkernel: empty matrix");
  MatriceMorse<double> *m = dynamic_cast<MatriceMorse<double> *>(a);
  if (!m) ExecError("contactkernel: the matrix is not a sparse (Morse) matrix");
  return m;
}
// a matrix's entries as triplets, as FreeFEM holds them (call COO() first for a converted form)
inline SparseTriplets triplets(const MatriceMorse<double> &m) {
  SparseTriplets t;
  t.rows = m.n; t.columns = m.m; t.count = m.nnz;
  t.row = m.i; t.column = m.j; t.value = m.aij;
  t.lowerHalf = m.half; t.oneBased = m.fortran;
  return t;
}
inline SparseTriplets coo(Matrice_Creuse<double> *A) {
  MatriceMorse<double> *m = morse(A);
  m->COO();
  return triplets(*m);
}
inline std::vector<double> copyOf(const KN<double> &a) {
  std::vector<double> out(a.N());
  for (int i = 0; i < a.N(); i++) out[i] = a[i];
  return out;
}
// n values into a, resized to n
inline void copyInto(KN<double> &a, const double *values, int n) {
  if (a.N() != n) a.resize(n);
  for (int i = 0; i < n; i++) a[i] = values[i];
}

}  // namespace contactkernel
#endif
