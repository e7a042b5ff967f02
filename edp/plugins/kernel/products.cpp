// products.cpp: M, A, B merged into one CSR structure with three values per entry (and 2x2
// blocks where the pattern allows: ProductMatrices, state.hpp), for the products of the record
// and the matrix S that contactKernelFactorizeStep sums from them.
#include <algorithm>
#include <climits>
#include "kernel.hpp"

namespace contactkernel {

// the blocks, when rows 2I and 2I+1 hold the columns 2J, 2J+1 of the same J's (sorted)
void ProductMatrices::makeBlocks() {
  blocked = false;
  std::vector<int>(1, 0).swap(blockStart); std::vector<int>().swap(blockColumn); std::vector<double>().swap(blockValues);
  auto fill = [&]() {
    if (n % 2) return false;
    for (int I = 0; I < n / 2; I++) {              // the pattern first: no copy if it is not blocked
      const int r0 = start[2 * I], r1 = start[2 * I + 1], length = r1 - r0;
      if (length % 2 || start[2 * I + 2] - r1 != length) return false;
      for (int e = 0; e < length; e += 2) {
        const int c = column[r0 + e];
        if (c % 2 || column[r0 + e + 1] != c + 1 || column[r1 + e] != c || column[r1 + e + 1] != c + 1) return false;
      }
    }
    const size_t blocks = column.size() / 4;
    blockStart.resize(n / 2 + 1);
    blockColumn.resize(blocks);
    blockValues.resize(12 * blocks);
    size_t b = 0;
    for (int I = 0; I < n / 2; I++) {
      const int r0 = start[2 * I], r1 = start[2 * I + 1], length = r1 - r0;
      blockStart[I] = (int)b;
      for (int e = 0; e < length; e += 2, b++) {
        blockColumn[b] = column[r0 + e] / 2;
        double *w = blockValues.data() + 12 * b;
        std::copy(values.begin() + 3 * (size_t)(r0 + e), values.begin() + 3 * (size_t)(r0 + e + 2), w);
        std::copy(values.begin() + 3 * (size_t)(r1 + e), values.begin() + 3 * (size_t)(r1 + e + 2), w + 6);
      }
    }
    blockStart[n / 2] = (int)b;
    return true;
  };
  if (!fill()) return;                            // the pattern is checked before any block is made
  blocked = true;
  std::vector<double>().swap(values);            // the blocks hold them now (entry() reads them)
}

// M, A, B as FreeFEM assembles them on one mesh: the same entries (i, j), in the same order,
// three values each; then one counting sort by row and a sort within each short row give the
// merged CSR form in one pass, without FreeFEM's CSR conversion of each matrix. Otherwise
// (patterns that differ) the rows of the three CSR forms are merged (mergeProductRows).
bool sameProductPattern(const SparseTriplets mats[3]) {
  for (int k = 1; k < 3; k++) {
    if (mats[k].count != mats[0].count || mats[k].oneBased != mats[0].oneBased) return false;
    if (!mats[k].row || !mats[k].column || !mats[0].row || !mats[0].column) return false;
    for (size_t e = 0; e < mats[0].count; e++)
      if (mats[k].row[e] != mats[0].row[e] || mats[k].column[e] != mats[0].column[e]) return false;
  }
  return !mats[0].oneBased;
}

void mergeProducts(Kernel &kernel, const SparseTriplets mats[3]) {
  ProductMatrices &products = kernel.products;
  const int n = mats[0].rows;
  const size_t nnz = mats[0].count;
  const int *I = mats[0].row, *J = mats[0].column;
  std::vector<int> count(n + 1, 0), order(nnz);
  for (size_t e = 0; e < nnz; e++) count[I[e] + 1]++;
  for (int r = 0; r < n; r++) count[r + 1] += count[r];
  std::vector<int> fill(count.begin(), count.end() - 1);
  for (size_t e = 0; e < nnz; e++) order[fill[I[e]]++] = (int)e;
  products.n = n;
  products.start.assign(n + 1, 0);
  products.column.clear(); products.values.clear();
  products.column.reserve(nnz); products.values.reserve(3 * nnz);
  for (int r = 0; r < n; r++) {
    int *first = order.data() + count[r], *last = order.data() + count[r + 1];
    std::sort(first, last, [&](int a, int b) { return J[a] < J[b]; });
    for (int *o = first; o < last; o++) {
      const int e = *o;
      if (o > first && J[e] == products.column.back()) {     // a repeated entry adds up
        for (int k = 0; k < 3; k++) products.values[products.values.size() - 3 + k] += mats[k].value[e];
        continue;
      }
      products.column.push_back(J[e]);
      for (int k = 0; k < 3; k++) products.values.push_back(mats[k].value[e]);
    }
    products.start[r + 1] = (int)products.column.size();
  }
  products.makeBlocks();
}

// the union of the three patterns, row by row, with the values of each matrix: the rows of
// the CSR forms (columns sorted within a row) merged three ways, in one pass over the entries
void mergeProductRows(Kernel &kernel, const SparseRows mats[3], int n) {
  ProductMatrices &products = kernel.products;
  for (int k = 0; k < 3; k++)
    for (int i = 0; i < n; i++)                        // CSR sorts (i, j): checked, not assumed
      for (int e = mats[k].start[i] + 1; e < mats[k].start[i + 1]; e++)
        if (mats[k].column[e] <= mats[k].column[e - 1]) kernelError("contactKernelProducts: FreeFEM's CSR form has unsorted rows");
  products.n = n;
  products.start.assign(n + 1, 0);
  products.column.clear(); products.values.clear();
  products.column.reserve(mats[0].start[n]); products.values.reserve(3 * (size_t)mats[0].start[n]);
  for (int i = 0; i < n; i++) {
    int e[3] = {mats[0].start[i], mats[1].start[i], mats[2].start[i]};
    while (true) {
      int next = INT_MAX;
      for (int k = 0; k < 3; k++) if (e[k] < mats[k].start[i + 1]) next = std::min(next, mats[k].column[e[k]]);
      if (next == INT_MAX) break;
      double v3[3] = {0., 0., 0.};
      for (int k = 0; k < 3; k++)                      // a column repeated in a row adds up, as in a sum of the matrices
        while (e[k] < mats[k].start[i + 1] && mats[k].column[e[k]] == next) v3[k] += mats[k].value[e[k]++];
      products.column.push_back(next);
      products.values.insert(products.values.end(), v3, v3 + 3);
    }
    products.start[i + 1] = (int)products.column.size();
  }
  products.makeBlocks();
}

void requireProducts(const Kernel &k, const char *who) {
  if (k.products.n == 0) kernelError(std::string(who) + ": call contactKernelProducts first");
}

}  // namespace contactkernel
