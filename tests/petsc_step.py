#!/usr/bin/python3
"""petsc_step.py: a prototype of the route past one machine (docs/performance.md, "Three
dimensions"): the linear solve of a time step, S x = b, by PETSc's parallel direct solver
(MUMPS through petsc4py), checked against the suite's own solve (CHOLMOD in
edp/plugins/contactkernel.cpp). FreeFEM still meshes and assembles: a run started with the
macro -DexportSystem="FOLDER" writes FOLDER/S.mtx (S = M/k + A + kB + C'W Kn C with FreeFEM's
tgv on the Dirichlet rows, Matrix Market) and FOLDER/b.txt (b = S x_true, x_true_i = sin(1 + i),
and the kernel's x = S^-1 b, one row each).

USAGE (Debian's python3-petsc4py-real; its PETSC_DIR is not set by the package)
  ./run.sh solve -scene slab3d -nx 48 -ny 24 -nz 24 -T 0.01 '-DexportSystem="/tmp/sys"'
  PETSC_DIR=/usr/lib/petscdir/petsc3.18/x86_64-linux-gnu-real mpirun -np 2 /usr/bin/python3 tests/petsc_step.py /tmp/sys
Prints, on rank 0: the unknowns and ranks, the wall seconds of reading, assembling, the
factorization and one solve, and the largest difference from the kernel's x and from
x_true relative to |x|_inf. Exit 0 when both are below 1e-9, 1 otherwise, 2 on bad input.
./run.sh (which sets PETSC_DIR) installs petsc4py and Open MPI; ./run.sh test runs this on 2
ranks for a small slab."""
import os
import sys
import time

try:
    import petsc4py
    petsc4py.init(sys.argv[:1])
    from petsc4py import PETSc
except ImportError as error:
    sys.exit(f"petsc_step.py: error: cannot import petsc4py ({error}): apt-get install python3-petsc4py-real, and set "
             "PETSC_DIR=/usr/lib/petscdir/petsc3.18/x86_64-linux-gnu-real")
import numpy as np


def main(folder):
    comm = PETSc.COMM_WORLD
    rank, size = comm.getRank(), comm.getSize()
    clock = time.perf_counter()
    # every rank reads the file and keeps its rows (a prototype: a real route would write one
    # file per rank, or hand the matrix over in memory)
    with open(os.path.join(folder, "S.mtx")) as f:
        if not f.readline().startswith("%%MatrixMarket matrix coordinate real general"):
            raise ValueError("S.mtx is not a Matrix Market coordinate file")
        n, m, nnz = (int(w) for w in f.readline().split())
        data = np.loadtxt(f, ndmin=2)
    bx = np.loadtxt(os.path.join(folder, "b.txt"), ndmin=2)
    if n != m or len(data) != nnz or len(bx) != n:
        raise ValueError(f"S is {n} x {m} with {len(data)} of {nnz} entries, b has {len(bx)} rows")
    read = time.perf_counter() - clock
    clock = time.perf_counter()
    # this rank's rows (PETSc's default split) as CSR
    local = PETSc.Vec().createMPI(n, comm=comm)
    start, end = local.getOwnershipRange()
    rows, cols = data[:, 0].astype(np.int32) - 1, data[:, 1].astype(np.int32) - 1
    mine = np.flatnonzero((rows >= start) & (rows < end))
    order = mine[np.lexsort((cols[mine], rows[mine]))]
    indptr = np.concatenate([[0], np.cumsum(np.bincount(rows[order] - start, minlength=end - start))]).astype(PETSc.IntType)
    A = PETSc.Mat().createAIJ([[end - start, n], [end - start, n]], csr=(indptr, cols[order].astype(PETSc.IntType),
                              data[order, 2]), comm=comm)
    A.assemble()
    b = A.createVecLeft()
    b.setValues(range(start, end), bx[start:end, 0])
    b.assemble()
    assembled = time.perf_counter() - clock
    ksp = PETSc.KSP().create(comm=comm)
    ksp.setOperators(A)
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("lu")
    pc.setFactorSolverType("mumps")
    x = b.duplicate()
    clock = time.perf_counter()
    ksp.setUp()                                        # the factorization
    factor = time.perf_counter() - clock
    clock = time.perf_counter()
    ksp.solve(b, x)
    solve = time.perf_counter() - clock
    scatter, whole = PETSc.Scatter.toZero(x)
    scatter.scatter(x, whole, addv=PETSc.InsertMode.INSERT_VALUES, mode=PETSc.ScatterMode.FORWARD)
    if rank == 0:
        xs = whole.getArray()
        scale = np.abs(bx[:, 1]).max()
        kernel = np.abs(xs - bx[:, 1]).max() / scale
        truth = np.abs(xs - np.sin(1.0 + np.arange(n))).max() / scale
        print(f"petsc_step: {n} unknowns, {nnz} entries, {size} rank(s): read {read:.2f} s, assembly {assembled:.2f} s, "
              f"MUMPS factorization {factor:.2f} s, one solve {solve:.3f} s; |x - kernel's x| {kernel:.1e}, "
              f"|x - x_true| {truth:.1e} (relative to |x|_inf)")
        return 0 if kernel <= 1e-9 and truth <= 1e-9 else 1
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    try:
        sys.exit(main(sys.argv[1]))
    except (OSError, ValueError) as error:
        print(f"petsc_step.py: error: {error}", file=sys.stderr)
        sys.exit(2)
