# Across MPI ranks (-ranks N; docs/design.md, "Across ranks").
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, PYTHON, expect_failure, ...).
# ---- The run on 2 ranks through PETSc agrees with the one-process run to 1e-9 (every output,
# the zones identical: tests/check_results.py --compare), on both linear-solver paths, for the
# paper scene (2D, original and penalty) and the oblique slide (3D, the disk law); its own
# physics checks pass; summary.txt names the ranks, the engine and each rank's peak memory.
ranks_agreement() { # ranks_agreement NAME OPTIONS...: one process, then 2 ranks direct and iterative
  local name="$1"; shift
  local diag="$work/ranks-$name.diag" status=0 path
  : > "$diag"
  rm -rf "$work/ranks-$name-1p"
  solve "$@" -estimate off -quiet -out "$work/ranks-$name-1p" >> "$diag" 2>&1 || status=1
  for path in direct iterative; do
    rm -rf "$work/ranks-$name-$path"
    solve "$@" -ranks 2 -ranksolver "$path" -quiet -out "$work/ranks-$name-$path" >> "$diag" 2>&1 || { echo "-ranks 2 -ranksolver $path failed" >> "$diag"; status=1; continue; }
    "$PYTHON" tests/check_results.py "$work/ranks-$name-$path" >> "$diag" 2>&1 || status=1
    "$PYTHON" tests/check_results.py "$work/ranks-$name-$path" --compare "$work/ranks-$name-1p" --rtol 1e-9 >> "$diag" 2>&1 || status=1
    grep -qx "ranks 2" "$work/ranks-$name-$path/summary.txt" && grep -qx "ranksolver $path" "$work/ranks-$name-$path/summary.txt" \
      && grep -Eq '^ranks_engine PETSc [0-9.]+, ' "$work/ranks-$name-$path/summary.txt" \
      && [ "$(grep -c '^memory_peak_rank_mb_[01] [0-9.]*$' "$work/ranks-$name-$path/summary.txt")" = 2 ] \
      && grep -Eq '^memory_peak_rank_mb_max [0-9.]+$' "$work/ranks-$name-$path/summary.txt" \
      || { echo "$path: summary.txt lacks ranks, ranksolver, ranks_engine or memory_peak_rank_mb_*" >> "$diag"; status=1; }
    # the direct path factorizes S once per run, as one process (MUMPS's factor changed state once)
    [ "$path" = iterative ] || grep -qx "ranks_preconditioner_builds 1" "$work/ranks-$name-$path/summary.txt" \
      || { echo "direct: not one factorization in the run: $(grep ranks_preconditioner_builds "$work/ranks-$name-$path/summary.txt")" >> "$diag"; status=1; }
  done
  report $status "ranks: $name on 2 ranks (direct, iterative) = one process to 1e-9, zones identical; direct: one factorization" "$diag"
}
ranks_agreement paper -scene paper -T 0.2
ranks_agreement paper-penalty -scene paper -problem penalty -T 0.2
# The iterative path repeats to the bit (docs/design.md, "Output files"): the paper scene's run on
# 2 ranks made again gives the same files but the times and each rank's peak memory. (Not the
# direct path: MUMPS's distributed solves sum in the order the ranks' messages arrive.)
diag="$work/ranks-repeat.diag"; : > "$diag"; status=0
rm -rf "$work/ranks-paper-iterative.first"
mv "$work/ranks-paper-iterative" "$work/ranks-paper-iterative.first" 2>> "$diag" || status=1
solve -scene paper -T 0.2 -ranks 2 -ranksolver iterative -quiet -out "$work/ranks-paper-iterative" >> "$diag" 2>&1 || status=1
strip_ranks_timing() { strip_timing "$1" | grep -v '^memory_peak_rank_mb_'; }   # (run_tests.sh)
for f in "${OUTPUT_FILES[@]}"; do
  cmp -s <(strip_ranks_timing "$work/ranks-paper-iterative.first/$f") <(strip_ranks_timing "$work/ranks-paper-iterative/$f") \
    || { echo "$f differs between two runs" >> "$diag"; status=1; }
done
report $status "ranks: the iterative path on 2 ranks repeats to the bit (all but the times and peak memory)" "$diag"
ranks_agreement slide3d -scene oblique-slide3d -T 0.1
# twisted3d, pushed on (-load 30): the slip direction along the stress to the checker's 1e-9 g
# (the ranks' Newton stopped at -tol with a cross component 5e3 times one process's: one more
# iteration once the pieces settle)
ranks_agreement twisted3d-load30 -scene twisted3d -load 30
# What the run on ranks does not do, refused by name before mpirun starts; no output written
expect_failure "-ranks with the fixed point" 2 "option -solver fixedpoint: -ranks runs Newton only" -ranks 2 -solver fixedpoint
expect_failure "-ranks with -estimate on" 2 "option -estimate on: the error estimates' companion run is a one-process run" -ranks 2 -estimate on
expect_failure "-ranks with -adapt" 2 "option -adapt: mesh adaptation runs on one process" -ranks 2 -adapt 1
expect_failure "-ranks out of range" 2 "option -ranks" -ranks 300
# The scale of the matrix entries, checked on the ranks' distributed M, A, B (no rank holds them
# whole): the largest entry the one-process run names, exit 2, nothing written
expect_failure "-ranks: material data whose matrix entries pass 1e20" 2 "the material data, the time step \(-rho 2e-6 -E 1e40 .*\) and the mesh's lengths give matrix entries up to 2.91667e\+38" -ranks 2 -E 1e40 -T 0.05
# A step the ranks' Newton cannot solve: exit 4 with the step and residual, nothing written
expect_failure "-ranks: a step that does not converge" 4 "step 1 \(t = [^)]*\): the contact solver did not converge after 1 iterations" -ranks 2 -T 0.1 -maxit 1
# A linear solve that fails (GMRES capped at one iteration through PETSc's options): exit 4
# naming the linear solver, its iterations, residual and PETSc's reason; nothing written
# An options file in PETSC_OPTIONS that cannot be read: refused before mpirun (PETSc would
# fail on every rank as it starts), exit 2, nothing written
export PETSC_OPTIONS="-options_file $work/no-such-options-file"
expect_failure "-ranks: PETSC_OPTIONS names an unreadable options file" 2 "PETSC_OPTIONS names an options file \(-options_file FILE\) that cannot be read" -ranks 2 -T 0.02
unset PETSC_OPTIONS
export PETSC_OPTIONS="-ranks_ksp_max_it 1"
expect_failure "-ranks: a linear solve that fails" 4 "the linear solve of a Newton iteration \(-ranksolver iterative: GMRES with BoomerAMG\) stopped after 1 iterations, relative residual [0-9.e+-]+ \(PETSc's reason DIVERGED_ITS\)" -ranks 2 -ranksolver iterative -T 0.1
unset PETSC_OPTIONS
# The column (a body that stops on its foundation: GMRES from zero, PETSc's divergence test off)
ranks_agreement column -scene column
# A restart on ranks continues the run: 0.1 then 0.2 on 2 ranks = 0.2 on one process, to 1e-9
diag="$work/ranks-restart.diag"; : > "$diag"; status=0
rm -rf "$work/ranks-restart-a" "$work/ranks-restart-b" "$work/ranks-restart-1p"
solve -ranks 2 -T 0.1 -quiet -out "$work/ranks-restart-a" >> "$diag" 2>&1 || status=1
solve -restart "$work/ranks-restart-a" -T 0.2 -quiet -out "$work/ranks-restart-b" >> "$diag" 2>&1 || status=1
solve -T 0.2 -estimate off -quiet -out "$work/ranks-restart-1p" >> "$diag" 2>&1 || status=1
grep -qx "ranks 2" "$work/ranks-restart-b/summary.txt" 2>/dev/null || { echo "the restart did not run on the 2 ranks of its run" >> "$diag"; status=1; }
"$PYTHON" tests/check_results.py "$work/ranks-restart-b" --compare "$work/ranks-restart-1p" --rtol 1e-9 >> "$diag" 2>&1 || status=1
report $status "ranks: a run on 2 ranks restarted from its state.txt = one process over the whole time, to 1e-9" "$diag"
# A mesh too coarse for the ranks (fewer elements than ranks: refused before METIS), and a linear solve that
# "converges" above 1e-8 |b| by PETSc's own test (rtol 1): refused, nothing written
expect_failure "-ranks: a rank without elements" 2 "option -ranks 3: the mesh's 2 elements leave 1 of the 3 ranks without an element" -ranks 3 -nx 1 -ny 1 -T 0.05
export PETSC_OPTIONS="-ranks_ksp_rtol 1"
expect_failure "-ranks: a linear solve above 1e-8 |b|" 4 "the linear solve of a Newton iteration .* relative residual [0-9.e+-]+ \(PETSc's reason DIVERGED_DTOL, or a residual above 1e-8 after its own test\)" -ranks 2 -ranksolver iterative -T 0.05
unset PETSC_OPTIONS
# The direct path: a back-substitution that fails ends its step as the iterative path's linear
# solve does (exit 4, the step, PETSc's reason); a factorization that fails is said at set-up
# with MUMPS's INFOG (exit 3); nothing written either way
export PETSC_OPTIONS="-ranks_ksp_max_it 1"
expect_failure "-ranks direct: a back-substitution that fails" 4 "step 1 \(t = [^)]*\): the back-substitution of a step \(its free velocities\) \(-ranksolver direct: GMRES with MUMPS Cholesky of S, once per run; the kernel's Newton on the Delassus matrix\) stopped after 1 iterations, relative residual [0-9.e+-]+ \(PETSc's reason DIVERGED_ITS\)" -ranks 2 -scene twisted3d -T 0.02
export PETSC_OPTIONS="-ranks_mat_mumps_icntl_14 -90"
expect_failure "-ranks direct: a factorization that fails" 3 "error: rank 0 of 2: the factorization of S \(-ranksolver direct: [^)]*\) failed \(PETSc's reason [A-Z_]+, MUMPS's INFOG\(1\) = -[0-9]+, INFOG\(2\) = [0-9-]+\)" -ranks 2 -T 0.02
unset PETSC_OPTIONS
# The direct path needs MUMPS's factor (the Delassus matrix from its entries of the inverse):
# another factorization or preconditioner chosen by PETSC_OPTIONS is refused by name, exit 2,
# nothing written
export PETSC_OPTIONS="-ranks_pc_type lu -ranks_pc_factor_mat_solver_type superlu_dist"
expect_failure "-ranks: the direct path with another factorization than MUMPS's" 2 "option -ranksolver direct: its factorization must be MUMPS's \(the Delassus matrix is made from MUMPS's entries of the inverse\), but PETSC_OPTIONS chose superlu_dist" -ranks 2 -T 0.02
export PETSC_OPTIONS="-ranks_pc_type hypre"
expect_failure "-ranks: the direct path without a factorization" 2 "option -ranksolver direct: its preconditioner must be a factorization \(LU or Cholesky\), but PETSC_OPTIONS chose hypre; use -ranksolver iterative" -ranks 2 -T 0.02
unset PETSC_OPTIONS
# MUMPS's LU in place of its Cholesky (PETSC_OPTIONS=-ranks_pc_type lu) runs the direct path, = one process
diag="$work/ranks-lu.diag"; : > "$diag"; status=0
rm -rf "$work/ranks-lu"
PETSC_OPTIONS="-ranks_pc_type lu" solve -ranks 2 -T 0.2 -quiet -out "$work/ranks-lu" >> "$diag" 2>&1 || status=1
grep -qx "ranks_engine PETSc [0-9.]*, GMRES with MUMPS LU of S, once per run; the kernel's Newton on the Delassus matrix" "$work/ranks-lu/summary.txt" 2>/dev/null \
  || { echo "summary.txt does not name MUMPS LU"; grep ranks_engine "$work/ranks-lu/summary.txt"; } >> "$diag" 2>&1 || status=1
"$PYTHON" tests/check_results.py "$work/ranks-lu" --compare "$work/ranks-paper-1p" --rtol 1e-9 >> "$diag" 2>&1 || status=1
report $status "ranks: the direct path with MUMPS's LU (PETSC_OPTIONS=-ranks_pc_type lu) = one process to 1e-9" "$diag"
# An error of PETSc on a rank (an option it refuses): said with the rank, exit 3, nothing written
export PETSC_OPTIONS="-ranks_pc_type nosuchpc"
expect_failure "-ranks: PETSc refuses an option of PETSC_OPTIONS" 3 "error: rank 0 of 2: PETSc error [0-9]+ in KSPSetFromOptions" -ranks 2 -T 0.02
unset PETSC_OPTIONS
# The engine in summary.txt is the solver as built, on the iterative path: GAMG when
# PETSC_OPTIONS chooses it; MUMPS for a factorization it chooses without naming a package (the
# one PETSc picks on several ranks; it once read "PETSc LU")
engine_named() { # engine_named NAME PETSC_OPTIONS ENGINE TITLE: ranks_engine reads "..., GMRES with ENGINE"
  local diag="$work/ranks-$1.diag" status=0
  : > "$diag"
  rm -rf "$work/ranks-$1"
  PETSC_OPTIONS="$2" solve -ranks 2 -ranksolver iterative -T 0.02 -quiet -out "$work/ranks-$1" >> "$diag" 2>&1 || status=1
  grep -qx "ranks_engine PETSc [0-9.]*, GMRES with $3" "$work/ranks-$1/summary.txt" 2>/dev/null \
    || { echo "summary.txt does not name $3:"; grep ranks_engine "$work/ranks-$1/summary.txt"; } >> "$diag" 2>&1 || status=1
  report $status "ranks: ranks_engine names $4" "$diag"
}
engine_named gamg "-ranks_pc_type gamg" GAMG "the preconditioner PETSC_OPTIONS chose (GAMG)"
engine_named itlu "-ranks_pc_type lu" "MUMPS LU" "the factorization PETSc picks when PETSC_OPTIONS names none (MUMPS)"
# PETSC_OPTIONS is recorded in summary.txt, and an option of the solver's (prefix ranks_) that
# nothing read, a misspelt one, is said on stderr (the run's results stand)
diag="$work/ranks-unused.diag"; : > "$diag"; status=0
rm -rf "$work/ranks-unused"
PETSC_OPTIONS="-ranks_pc_typ lu" solve -ranks 2 -T 0.02 -quiet -out "$work/ranks-unused" > "$work/ranks-unused.out" 2>&1 || status=1
cat "$work/ranks-unused.out" >> "$diag"
grep -q "^warning: PETSC_OPTIONS: -ranks_pc_typ was not used by the solver" "$work/ranks-unused.out" || { echo "no warning of the unused option" >> "$diag"; status=1; }
grep -qx "ranks_petsc_options -ranks_pc_typ lu" "$work/ranks-unused/summary.txt" 2>/dev/null || { echo "summary.txt does not record PETSC_OPTIONS" >> "$diag"; status=1; }
report $status "ranks: PETSC_OPTIONS recorded in summary.txt; a misspelt option of the solver's said on stderr" "$diag"
# A small mesh whose METIS partition leaves a part empty (6 triangles among 4 ranks): it takes
# an element of the largest part, and the run = one process to 1e-9
diag="$work/ranks-small.diag"; : > "$diag"; status=0
rm -rf "$work/ranks-small" "$work/ranks-small-1p"
solve -nx 3 -ny 1 -T 0.05 -estimate off -quiet -out "$work/ranks-small-1p" >> "$diag" 2>&1 || status=1
solve -nx 3 -ny 1 -T 0.05 -ranks 4 -quiet -out "$work/ranks-small" >> "$diag" 2>&1 || status=1
"$PYTHON" tests/check_results.py "$work/ranks-small" --compare "$work/ranks-small-1p" --rtol 1e-9 >> "$diag" 2>&1 || status=1
report $status "ranks: 6 triangles on 4 ranks (METIS's empty part filled) = one process to 1e-9" "$diag"
# A FreeFEM error on one rank alone: the run stops (a non-zero exit, the rank and why), where
# the other ranks once waited for it forever
diag="$work/ranks-error.diag"; : > "$diag"; status=0; rc=0
OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 timeout -s KILL 120 mpirun -q -np 2 FreeFem++-mpi -nw -ns -v 0 tests/data/ranks_error.edp \
  > "$diag" 2>&1 || rc=$?
{ [ "$rc" != 0 ] && [ "$rc" != 137 ]; } || { echo "exit code $rc (137: still waiting after 120 s)" >> "$diag"; status=1; }
grep -q "error: rank 1 of 2: a FreeFEM error on this rank stopped the run" "$diag" || { echo "no message naming rank 1" >> "$diag"; status=1; }
report $status "ranks: a FreeFEM error on one rank stops the run (no rank left waiting)" "$diag"
# A rank killed outright (SIGKILL, as the system's out-of-memory killer does) cannot remove its
# folder, nor say why: the run that started mpirun removes what the first rank created and says
# so (exit 137); no rank is left running
diag="$work/ranks-killed.diag"; : > "$diag"; status=0; out="$work/ranks-killed"
rm -rf "$out" "$out".partial.*
solve -ranks 2 -scene slab3d -nx 12 -ny 6 -nz 6 -T 20 -quiet -out "$out" > "$diag" 2>&1 &
pid=$!
for i in $(seq 1 1200); do compgen -G "$out.partial.*" > /dev/null && break; sleep 0.05; done
rank0=""
for p in $(pgrep -f -- "-out $out( |$)"); do tr '\0' '\n' < "/proc/$p/environ" 2> /dev/null | grep -qx "OMPI_COMM_WORLD_RANK=0" && rank0=$p; done
[ -n "$rank0" ] && kill -KILL "$rank0" || { echo "no first rank found with $out.partial.* made" >> "$diag"; status=1; }
rc=0; wait "$pid" || rc=$?
[ "$rc" = 137 ] || { echo "exit code $rc, not 137" >> "$diag"; status=1; }
grep -q "^error: a process of the run was killed (SIGKILL: .*; the run removed its unfinished output folder$" "$diag" \
  || { echo "no message saying the run was killed and its folder removed" >> "$diag"; status=1; }
left=$(ls -d "$out" "$out".partial.* 2> /dev/null)
[ -z "$left" ] || { echo "left behind: $left" >> "$diag"; status=1; }
sleep 1; pgrep -f -- "-out $out( |$)" > /dev/null && { echo "a process of the run is still running" >> "$diag"; pkill -KILL -f -- "-out $out( |$)"; status=1; }
report $status "ranks: the first rank killed outright (SIGKILL): its output folder removed by the launching run, which says so (exit 137)" "$diag"
# mpirun by hand: without -ranks N, or a 3D body without -Ddimension=3, refused (exit 2) saying
# what to add; nothing written
hand_refusal() { # hand_refusal NAME REGEX ARGS...
  local name="$1" regex="$2" diag="$work/hand-refusal.diag" status=0 rc=0 out="$work/ranks-hand"; shift 2
  rm -rf "$out"*
  OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 timeout 300 mpirun -q -np 2 FreeFem++-mpi -nw -ns -v 0 edp/solve.edp \
    -out "$out" "$@" > "$diag" 2>&1 || rc=$?
  [ "$rc" = 2 ] || { echo "exit code $rc, expected 2" >> "$diag"; status=1; }
  grep -Eq "$regex" "$diag" || { echo "message does not match /$regex/" >> "$diag"; status=1; }
  if compgen -G "$out*" > /dev/null; then echo "results were written in $out" >> "$diag"; status=1; fi
  report $status "refused: mpirun by hand $name" "$diag"
}
hand_refusal "without -ranks N" "the run under mpirun \(-DranksMode=1\) needs option -ranks N" -T 0.02 -DranksMode=1
hand_refusal "for a 3D body without -Ddimension=3" "oblique-slide3d.scene is 3D: under mpirun, give -Ddimension=3 with -DranksMode=1" -ranks 2 -scene oblique-slide3d -T 0.02 -DranksMode=1
hand_refusal "with -ranks N but without -DranksMode=1" "option -ranks 2 under mpirun: add -DranksMode=1" -ranks 2 -T 0.02
hand_refusal "with -DranksMode=1 before the suite's options" "the argument '-DranksMode=1' under mpirun: give -DranksMode=1 \(and -Ddimension=3 for a 3D body\) as the last arguments" -DranksMode=1 -ranks 2 -T 0.02
