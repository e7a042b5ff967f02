#!/usr/bin/env bash
# bench.sh: the benchmark behind ./run.sh bench [--quick]. Not a test: these machines are
# shared and noisy, so read ratios measured in the same run (each run of edp/solve.edp
# times its own floor, one back-substitution with S, next to its median step).
#
# Writes under ${RESULTS_DIR:-results}/bench/:
#   runs/NAME/          one folder per run (the outputs of edp/solve.edp), NAME.time
#                       (wall seconds and peak memory of the whole process)
#   steps.txt           cost per step and setup costs against the mesh, per solver mode
#   steps_adapted.txt   step / floor on the adapted meshes of work_precision.txt (median of repeats)
#   steps3d.txt         the same as steps.txt for the 3D slab (slab3d) on three meshes of tetrahedra
#   iterations.txt      iterations and time per step against the augmentation r, Newton and
#                       fixed point, on 66x33 and 132x66
#   work_precision.txt  error against wall time for uniform and adapted meshes, time steps,
#                       modes, tolerances and eps; the errors of x_B, x_C (node positions and
#                       the estimates between the nodes) and the normal force; a run's own
#                       error estimates when it writes them (summary.txt error_estimate_*)
#   rates.txt           the observed convergence rates in h (uniform, adapted) and in k; those
#                       of x_B, x_C and their estimates in h
#   reference.txt       the reference's estimated error and its margin below the smallest error;
#                       how far the check run's x_B, x_C estimates lie from the reference's
#   *.png               the charts (plots/bench.py)
# --quick: the two coarsest meshes and fewer points.
# Runs one solve at a time, so that the timings are not disturbed by a second process.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
PYTHON="${PYTHON:-/usr/bin/python3}"
out="${RESULTS_DIR:-$root/results}/bench"
quick=0
case "${1:-}" in
  --quick) quick=1 ;;
  "") ;;
  *) echo "bench.sh: error: unknown argument '$1' (usage: bench.sh [--quick])" >&2; exit 2 ;;
esac
rm -rf "$out"
mkdir -p "$out/runs"
start=$(date +%s)

# run NAME OPTIONS...: one solve, timed as a whole process (wall seconds, peak KB)
run() {
  local name="$1"; shift
  local dir="$out/runs/$name"
  if /usr/bin/time -f "%e %M" -o "$dir.time" FreeFem++-nw -ns -v 0 edp/solve.edp "$@" -out "$dir" > "$dir.log" 2>&1; then
    printf 'bench: %-34s %7.2f s  %s\n' "$name" "$(cut -d' ' -f1 "$dir.time")" "$(grep -o '[0-9]* iterations (max [0-9]*/step)' "$dir.log")"
  else
    printf 'bench: %-34s failed: %s\n' "$name" "$(grep -m1 'error' "$dir.log" | cut -c1-120)"
  fi
}

# ---- cost per step against the mesh (T = 1, k = 0.01), both floors measured in each run
meshes=("66 33" "132 66" "264 132" "528 264")
[ "$quick" = 1 ] && meshes=("66 33" "132 66")
for m in "${meshes[@]}"; do
  set -- $m
  for problem in original penalty; do
    run "steps-${1}x${2}-newton-$problem" -nx "$1" -ny "$2" -problem "$problem" -umfpackfloor on
  done
  run "steps-${1}x${2}-fixedpoint-original" -nx "$1" -ny "$2" -solver fixedpoint
done
# ---- 3D: the paper's block as a slab (slab3d: the whole face y = 0 is Gamma3), P1 tetrahedra,
# 20 steps (T = 0.2): the size of a 3D run this machine takes, its memory and cost per step
slabs=("16 8 8" "32 16 16" "48 24 24")
[ "$quick" = 1 ] && slabs=("16 8 8" "32 16 16")
for m in "${slabs[@]}"; do
  set -- $m
  run "steps3d-${1}x${2}x${3}-newton-original" -scene slab3d -nx "$1" -ny "$2" -nz "$3" -T 0.2
done
# The same Newton written in FreeFEM's language (-kernel script), on the two coarsest meshes.
for m in "66 33" "132 66"; do
  set -- $m
  run "steps-${1}x${2}-script-original" -nx "$1" -ny "$2" -kernel script
done
# The full-system Newton re-factorizes at every iteration: 20 steps on the two coarsest meshes.
for m in "66 33" "132 66"; do
  set -- $m
  run "steps-${1}x${2}-full-original" -nx "$1" -ny "$2" -T 0.2 -solver full
done
# ---- iterations and time per step against the augmentation r, both solvers, two meshes
rlist=(1e-4 1e-3 1e-2 0.1 1 10 100 1e3 1e4)
[ "$quick" = 1 ] && rlist=(1e-4 1 1e4)
for m in "66 33" "132 66"; do
  set -- $m
  for r in "${rlist[@]}"; do
    run "iterations-${1}x${2}-newton-r$r" -nx "$1" -ny "$2" -r "$r" -maxit 200
    run "iterations-${1}x${2}-fixedpoint-r$r" -nx "$1" -ny "$2" -r "$r" -solver fixedpoint -maxit 2000
  done
done
# ---- work-precision: error against wall time. The space reference is an adapted mesh far
# finer than any run (about 205k vertices; its own error is estimated from the run at twice
# its -adapt_err, the "check" (about 103k), and reported in reference.txt); every run uses
# k = 0.01, so the distance is the error in space. The time error is measured on 66x33
# against the same mesh at k = 0.00125.
refopts=(-nx 66 -ny 33 -adapt 2 -adapt_err 1.25e-5 -adapt_vertices 400000); checkopts=(-nx 66 -ny 33 -adapt 2 -adapt_err 2.5e-5)
[ "$quick" = 1 ] && { refopts=(-nx 66 -ny 33 -adapt 2 -adapt_err 1e-4); checkopts=(-nx 66 -ny 33 -adapt 2 -adapt_err 2e-4); }
run "reference-adapted" "${refopts[@]}"
run "check-adapted" "${checkopts[@]}"
refdir="$out/runs/reference-adapted"
wp_meshes=("16 8" "33 16" "66 33" "132 66" "264 132")
[ "$quick" = 1 ] && wp_meshes=("16 8" "33 16" "66 33")
for m in "${wp_meshes[@]}"; do
  set -- $m
  run "wp-mesh-${1}x${2}" -nx "$1" -ny "$2"
done
# adapted meshes: one or two rounds from 33x16, each -adapt_err (the whole run timed, its
# pilot runs included); two rounds with -adapt_zones 1e-3 as well (the family adapt2z: the
# last mesh refined around the zone boundaries the last pilot found, for x_B and x_C)
errs1=(4e-3 2e-3 1e-3 5e-4 2.5e-4); errs2=(1e-3 7e-4 5e-4 2.5e-4); errs2z=(2e-3 1e-3 7e-4)
[ "$quick" = 1 ] && { errs1=(2e-3 1e-3 5e-4); errs2=(1e-3); errs2z=(1e-3); }
for e in "${errs1[@]}"; do run "wp-adapt1-$e" -nx 33 -ny 16 -adapt 1 -adapt_err "$e"; done
for e in "${errs2[@]}"; do run "wp-adapt2-$e" -nx 33 -ny 16 -adapt 2 -adapt_err "$e"; done
for e in "${errs2z[@]}"; do run "wp-adapt2z-$e" -nx 33 -ny 16 -adapt 2 -adapt_err "$e" -adapt_zones 1e-3; done
# step / floor on the adapted meshes: each mesh run again with -mesh (no pilot), several times,
# the median ratio per mesh in steps_adapted.txt (the ratios of small meshes move with the
# machine from run to run)
repeats=5; [ "$quick" = 1 ] && repeats=3
for dir in "$out"/runs/wp-adapt*; do
  [ -f "$dir/mesh.msh" ] || continue
  for ((i = 1; i <= repeats; i++)); do run "stepsadapted-$(basename "$dir")-$i" -mesh "$dir/mesh.msh"; done
done
run "timeref-66x33-dt0.00125" -dt 0.00125
for dt in 0.04 0.02 0.01 0.005 0.0025; do
  run "wp-dt-$dt" -dt "$dt"
done
run "wp-full-66x33" -solver full
# the tolerance: what a looser one buys each solver (66x33), against the fine reference and
# against the same mesh solved to tol 1e-13 (the solver's own error)
for tol in 1e-4 1e-6 1e-8 1e-10; do
  run "wp-tol-newton-$tol" -tol "$tol"
  run "wp-tol-fixedpoint-$tol" -tol "$tol" -solver fixedpoint
done
run "tight-66x33" -tol 1e-13
for eps in 1e-2 1e-3 1e-4 1e-5; do
  run "wp-penalty-eps$eps" -problem penalty -eps "$eps"
done
for dir in "$out"/runs/wp-* "$out/runs/check-adapted"; do
  [ -f "$dir/summary.txt" ] || continue
  against="$refdir"
  case "$dir" in */wp-dt-*) against="$out/runs/timeref-66x33-dt0.00125" ;; esac
  FreeFem++-nw -ns -v 0 edp/compare.edp -a "$dir" -ref "$against" > "$dir.error" 2> "$dir.error.log" || true   # a refusal says why in .error.log
done
for dir in "$out"/runs/wp-tol-*; do
  [ -f "$dir/summary.txt" ] || continue
  FreeFem++-nw -ns -v 0 edp/compare.edp -a "$dir" -ref "$out/runs/tight-66x33" > "$dir.solver_error" 2> "$dir.solver_error.log" || true
done

"$PYTHON" plots/bench.py --bench "$out" --reference "$refdir"
echo "bench: done in $(( $(date +%s) - start )) s; tables and charts in $out"
