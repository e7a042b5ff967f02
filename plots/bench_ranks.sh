#!/usr/bin/env bash
# bench_ranks.sh: the benchmark of -ranks N behind ./run.sh bench-ranks [--quick | --big].
# Not a test: these machines are shared and noisy, and have 2 cores (N > 2 is oversubscribed:
# its times say little, its memory per rank still does). The 3D slab (slab3d) over two steps.
#
# Writes under ${RESULTS_DIR:-results}/bench_ranks/:
#   runs/NAME/        one folder per run (the outputs of edp/solve.edp)
#   scaling.txt       one row per run: the mesh, unknowns, ranks, path, wall seconds, time per
#                     step, Newton and linear iterations, each rank's peak memory (largest, mean),
#                     and the one-process run of the same mesh (its peak memory, time per step)
#   projection.txt    memory per unknown and per rank of each path (fitted on scaling.txt),
#                     projected to 1e7 and 1e8 unknowns (plots/bench_ranks.py)
#   ranks_*.png       the charts
# --quick: the slab 16x8x8 (4,131 unknowns), one process and N = 1, 2, both paths, under
# bench_ranks/quick/ (a full benchmark's files are left as they are); --iterative, --direct: that path's rows again (the
# others kept); --agree: the agreement with one process (the paper scene, original and penalty,
# slab3d and oblique-slide3d on N = 1, 2, 3, 4 ranks, both paths: tests/check_results.py
# --compare at 1e-9 and ./run.sh compare's relative L2 distance of v at T, into agreement.txt);
# --big: the slab 96x48x48 (698,691 unknowns)
# on 2 ranks, iterative path, and the direct path one size down (48x24x24) for its accuracy,
# over one step (T = dt = 0.01).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
PYTHON="${PYTHON:-/usr/bin/python3}"
out="${RESULTS_DIR:-$root/results}/bench_ranks"
mode=full
case "${1:-}" in
  --quick) mode=quick ;;
  --big) mode=big ;;
  --iterative) mode=iterative ;;
  --direct) mode=direct ;;
  --agree) mode=agree ;;
  "") ;;
  *) echo "bench_ranks.sh: error: unknown argument '$1' (usage: bench_ranks.sh [--quick | --big | --iterative | --direct | --agree])" >&2; exit 2 ;;
esac
[ "$mode" = quick ] && out="$out/quick"   # (a smoke run: the full benchmark's files stay)
mkdir -p "$out/runs"
if [ "$mode" = agree ]; then
  list="$out/agreement.txt"
  echo "# scene ranks path check_results_1e-9 relative_l2_v" > "$list"
  for spec in "paper|-scene paper -T 0.2" "paper-penalty|-scene paper -problem penalty -T 0.2" "slab3d|-scene slab3d -T 0.02" \
              "oblique-slide3d|-scene oblique-slide3d -T 0.1"; do
    name=${spec%%|*}; read -r -a opts <<< "${spec#*|}"
    one="$out/runs/agree-$name-1p"
    rm -rf "$one"
    ./run.sh solve "${opts[@]}" -estimate off -quiet -out "$one" > "$one.log" 2>&1 || { echo "bench_ranks.sh: $name on one process failed"; continue; }
    for n in 1 2 3 4; do for path in direct iterative; do
      dir="$out/runs/agree-$name-$n-$path"
      rm -rf "$dir"
      if ! ./run.sh solve "${opts[@]}" -ranks "$n" -ranksolver "$path" -quiet -out "$dir" > "$dir.log" 2>&1; then
        echo "$name $n $path failed nan" >> "$list"; echo "$name, $n rank$([ "$n" = 1 ] || echo s), $path: failed"; continue
      fi
      verdict=passes
      "$PYTHON" tests/check_results.py "$dir" --compare "$one" --rtol 1e-9 > "$dir.compare" 2>&1 || verdict=fails
      distance=$(./run.sh compare -a "$dir" -ref "$one" 2>/dev/null | awk '{ printf "%.3g", $2 / $4 }')
      echo "$name $n $path $verdict $distance" >> "$list"
      echo "$name, $n rank$([ "$n" = 1 ] || echo s), $path: check_results --compare 1e-9 $verdict, relative L2 of v $distance"
    done; done
  done
  exit 0
fi
table="$out/scaling.txt"
case "$mode" in
  big) ;;
  iterative|direct) [ -f "$table" ] && sed -i "/ $mode /d" "$table"; rm -rf "$out/runs"/*"$mode"* ;;   # that path's rows again
  *) rm -rf "$out/runs"/* "$table" ;;
esac
[ -f "$table" ] || echo "# name nx ny nz unknowns ranks path wall_s step_s newton_iterations linear_iterations memory_peak_rank_mb_max memory_peak_rank_mb_mean one_process_memory_mb one_process_step_s" > "$table"
# value FILE KEY: a key of summary.txt
value() { awk -v k="$2" '$1 == k { print $2; exit }' "$1"; }
# run NAME NX NY NZ RANKS PATH [options]: one solve (RANKS 0: one process), its row
declare -A oneMemory oneStep
run() {
  local name="$1" nx="$2" ny="$3" nz="$4" ranks="$5" path="$6"; shift 6
  local dir="$out/runs/$name" t0 t1 opts=(-scene slab3d -nx "$nx" -ny "$ny" -nz "$nz" -T "$T" -dt 0.01 -estimate off -quiet -out "$out/runs/$name")
  [ "$ranks" = 0 ] || opts+=(-ranks "$ranks" -ranksolver "$path")
  t0=$(date +%s.%N)
  if [ "$ranks" = 0 ]; then
    /usr/bin/time -f "%M" -o "$dir.mem" ./run.sh solve "${opts[@]}" "$@" > "$dir.log" 2>&1 || { echo "bench_ranks.sh: $name failed:"; tail -5 "$dir.log"; return 0; }
  else
    ./run.sh solve "${opts[@]}" "$@" > "$dir.log" 2>&1 || { echo "bench_ranks.sh: $name failed:"; tail -5 "$dir.log"; return 0; }
  fi
  t1=$(date +%s.%N)
  local s="$dir/summary.txt" steps wall step
  steps=$(value "$s" steps); wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }')
  step=$(awk -v l="$(value "$s" time_loop)" -v n="$steps" 'BEGIN { printf "%.4g", l / n }')
  local key="$nx.$ny.$nz"
  if [ "$ranks" = 0 ]; then
    oneMemory[$key]=$(awk '{ printf "%.1f", $1 / 1024 }' "$dir.mem"); oneStep[$key]=$step
    echo "$name: one process, $(value "$s" dofs) unknowns, ${step} s a step, peak ${oneMemory[$key]} MB, wall $wall s"
    return 0
  fi
  local max mean
  max=$(awk -v m="$(value "$s" memory_peak_rank_mb_max)" 'BEGIN { printf "%.1f", m }')
  mean=$(awk '$1 ~ /^memory_peak_rank_mb_[0-9]+$/ { s += $2; n++ } END { printf "%.1f", s / n }' "$s")
  echo "$name $nx $ny $nz $(value "$s" dofs) $ranks $path $wall $step $(value "$s" ranks_newton_iterations) $(value "$s" ranks_linear_iterations) $max $mean ${oneMemory[$key]:-nan} ${oneStep[$key]:-nan}" >> "$table"
  echo "$name: $ranks rank$([ "$ranks" = 1 ] || echo s), $path, $(value "$s" dofs) unknowns, ${step} s a step, peak per rank $max MB (mean $mean), wall $wall s"
}

T=0.02                               # two steps; --big: one (the first, from rest: the costliest)
if [ "$mode" = big ]; then
  T=0.01
  # beyond the one process: the slab 96x48x48 on 2 ranks, iterative; one size down, direct
  run big-it-96 96 48 48 2 iterative
  run big-direct-48 48 24 24 2 direct
  run big-it-48 48 24 24 2 iterative
  "$PYTHON" plots/bench_ranks.py "$out"
  echo "bench_ranks.sh: wrote $out/scaling.txt, projection.txt and the charts ranks_*.png"
  exit 0
fi
# At fixed size: N = 1, 2, 4, 8 (above 2 oversubscribed), both paths (--iterative, --direct: that one)
paths="direct iterative"
{ [ "$mode" = iterative ] || [ "$mode" = direct ]; } && paths=$mode
sizes=("24 12 12" "48 24 24")
[ "$mode" = quick ] && sizes=("16 8 8")
counts=(1 2 4 8)
[ "$mode" = quick ] && counts=(1 2)
for size in "${sizes[@]}"; do
  read -r nx ny nz <<< "$size"
  run "one-$nx" "$nx" "$ny" "$nz" 0 -
  for path in $paths; do
    for n in "${counts[@]}"; do run "fixed-$nx-$path-$n" "$nx" "$ny" "$nz" "$n" "$path"; done
  done
done
# At fixed size per rank: about 12,000 unknowns per rank (24x12x12 on one), N = 1, 2, 4, 8
if [ "$mode" = full ] || [ "$mode" = iterative ] || [ "$mode" = direct ]; then
  for spec in "1 24 12 12" "2 30 15 15" "4 38 19 19" "8 48 24 24"; do
    read -r n nx ny nz <<< "$spec"
    for path in $paths; do run "weak-$nx-$path-$n" "$nx" "$ny" "$nz" "$n" "$path"; done
  done
fi
"$PYTHON" plots/bench_ranks.py "$out"
echo "bench_ranks.sh: wrote $out/scaling.txt, projection.txt and the charts ranks_*.png (the projection needs 3 runs a path or more)"
