// partition.cpp: the partition of the mesh's elements among the ranks (ranks.idp,
// ranksAssemble). Rank 0 alone partitions, with METIS (METIS_PartMeshDual: the dual graph of
// elements that share a face, an edge in 2D), and every rank gets the parts. FreeFEM's
// metisdual, which every rank ran until this file, builds the graph of elements that share a
// vertex (about 20 neighbours a tetrahedron instead of 4): 1.9 kB per unknown on every rank,
// the largest part of what a rank held whole (docs/design.md, "Across ranks").
//
// FreeFEM function (collective)
//   contactRanksPartition(Th, int[int] part)  part[k]: the rank of element k (Th.nt values, the
//       same on every rank; no rank without an element when Th.nt >= the ranks); returns
//       METIS's edge cut (0 on one rank)
#include "ranks.hpp"
#include "kernel/signals.hpp"
#include <metis.h>

namespace ranks {
static_assert(sizeof(idx_t) == sizeof(int), "METIS's idx_t is sent as MPI_INT: a METIS of 32-bit indices");

// the parts of the elements whose vertices are vertexOf[(k * corners) ...] (rank 0's arrays),
// on every rank
static long partitionElements(int elements, int vertices, int corners, std::vector<idx_t> &vertexOf, KN<long> &part) {
  part.resize(elements);
  std::vector<idx_t> parts(elements, 0);
  long status[2] = {METIS_OK, 0};                  // METIS's status, the edge cut (rank 0's)
  if (state.size > 1 && state.rank == 0) {
    std::vector<idx_t> first(elements + 1);
    for (int k = 0; k <= elements; k++) first[k] = (idx_t)k * corners;
    std::vector<idx_t> nodeParts(vertices);
    idx_t ne = elements, nn = vertices, common = corners - 1, nparts = state.size, cut = 0;
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_NUMBERING] = 0;
    status[0] = contactkernel::keepingSignalHandlers([&] {     // (kernel/signals.hpp: METIS traps SIGTERM, SIGABRT)
      return METIS_PartMeshDual(&ne, &nn, first.data(), vertexOf.data(), nullptr, nullptr, &common, &nparts, nullptr, options, &cut,
                                parts.data(), nodeParts.data());
    });
    status[1] = cut;
    // METIS may leave a part empty on a small mesh (16 triangles among 6 ranks): each empty
    // part takes the last element of the largest part, so that any mesh with at least as many
    // elements as ranks runs (the script refuses fewer)
    if (status[0] == METIS_OK && elements >= state.size) {
      std::vector<int> count(state.size, 0);
      for (int k = 0; k < elements; k++) count[parts[k]]++;
      for (int p = 0; p < state.size; p++) {
        if (count[p] > 0) continue;
        const int largest = (int)(std::max_element(count.begin(), count.end()) - count.begin());
        for (int k = elements - 1; k >= 0; k--)
          if (parts[k] == largest) { parts[k] = p; count[largest]--; count[p]++; break; }
      }
    }
  }
  std::vector<idx_t>().swap(vertexOf);
  if (state.size > 1) {
    MPI_Bcast(status, 2, MPI_LONG, 0, MPI_COMM_WORLD);
    if (status[0] != METIS_OK)
      failAlike(3, "METIS could not partition the mesh's " + std::to_string(elements) + " elements among " + std::to_string(state.size)
                       + " ranks (METIS_PartMeshDual returned " + std::to_string(status[0]) + ")");
    MPI_Bcast(parts.data(), elements, MPI_INT, 0, MPI_COMM_WORLD);
  }
  for (int k = 0; k < elements; k++) part[k] = parts[k];
  return status[1];
}

// corners: 3 (triangles) or 4 (tetrahedra)
template <class MeshType, int corners>
long partition(const MeshType *const &pTh, KN<long> *const &pPart) {
  const MeshType &Th = *pTh;
  std::vector<idx_t> vertexOf;
  if (state.size > 1 && state.rank == 0) {
    vertexOf.resize((size_t)Th.nt * corners);
    for (int k = 0; k < Th.nt; k++)
      for (int j = 0; j < corners; j++) vertexOf[(size_t)k * corners + j] = (idx_t)Th(Th[k][j]);
  }
  return partitionElements(Th.nt, Th.nv, corners, vertexOf, *pPart);
}

}  // namespace ranks

static void Load_Init() {
  using namespace ranks;
  Global.Add("contactRanksPartition", "(", new OneOperator2_<long, pmesh, KN<long> *>(partition<Fem2D::Mesh, 3>));
  Global.Add("contactRanksPartition", "(", new OneOperator2_<long, pmesh3, KN<long> *>(partition<Fem2D::Mesh3, 4>));
}

LOADFUNC(Load_Init)
