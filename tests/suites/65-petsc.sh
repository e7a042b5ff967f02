# The PETSc route (prototype).
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
# ---- the PETSc route, a prototype (docs/performance.md, "Three dimensions"): S of a 3D step,
# exported by the macro -DexportSystem, factorized and solved by MUMPS through petsc4py on 2
# ranks, equals the kernel's solve (and x_true) to 1e-9
diag="$work/petsc.diag"; : > "$diag"; status=0
mkdir -p "$work/petsc-system"
solve -scene slab3d -nx 8 -ny 4 -nz 4 -T 0.01 -quiet "-DexportSystem=\"$work/petsc-system\"" -out "$work/petsc-run" >> "$diag" 2>&1 || status=1
mpirun --allow-run-as-root --oversubscribe -np 2 "$PYTHON" tests/petsc_step.py "$work/petsc-system" >> "$diag" 2>&1 || status=1
grep -q "2 rank(s)" "$diag" || { echo "no line from the two ranks" >> "$diag"; status=1; }
report $status "PETSc route (prototype): a 3D step's S solved by MUMPS on 2 ranks = the kernel's solve to 1e-9" "$diag"

