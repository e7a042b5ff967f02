#!/usr/bin/env bash
# stability.sh: where each contact solver fails, behind ./run.sh stability [--quick].
# Runs parameter sweeps of edp/solve.edp, two solves at a time, and writes the tables
# and maps of docs/stability.md.
#
# Usage (from anywhere; the environment of run.sh is set here when missing):
#   plots/stability.sh [--quick] [--jobs N]
#     --quick    a few points per sweep (under a minute on 2 cores; the tests call it)
#     --jobs N   solves run in parallel (default 2)
#     --list     print the points (SWEEP ID TIMEOUT OPTIONS...) and exit
#
# Methods (each with the safeguards on, the default, and off where they apply):
#   orig-newton-on|off            -problem original -solver newton           -maxit 100
#   orig-fixedpoint               -problem original -solver fixedpoint       -maxit 1000
#   pen-newton-compliant-on|off   -problem penalty -penaltyform compliant    -maxit 100
#   pen-newton-literal-on|off     -problem penalty -penaltyform literal      -maxit 100
#   pen-fixedpoint                -problem penalty -solver fixedpoint        -maxit 1000
# The fixed point ignores -safeguard and -r (Newton's; every solver's residual is read at the
# operator's scale, r = 1). Sweeps (reduced mesh 33x16, T = 1, k = 0.01 unless said; see the table in
# docs/stability.md): eps x method, r x method, k x mu (Newton and fixed point), mu, load
# and k (all methods), mesh x k (fixed point), mesh x r (Newton, T = 0.05), the defaults of
# both solvers on the paper mesh 66x33 over the paper box (maxit as shipped: 50 and 500),
# the agreement points and the hopeless settings. T = 0.4 (reduced mesh) or 0.2 (paper
# mesh) for k <= 1e-3.
#
# Writes under ${RESULTS_DIR:-results}/stability/ (removed first):
#   runs/SWEEP/ID/       contact.txt, fields.txt, summary.txt of each converged run (all
#                        its outputs in the agreement sweep, for tests/check_results.py)
#   runs/SWEEP/ID.rec    one record per point: options, exit code, wall time, message,
#                        the probes of a failure at the iteration cap
#   SWEEP.txt, agreement.txt, hopeless.txt, summary.txt   (plots/stability_tables.py)
#   maps/stability_*.png (plots/stability.py)
#   timing.txt           wall time of the sweeps and of the whole script
# A failure at the iteration cap is probed by re-running the point with -maxit cap-1 ...
# cap-4 and cap/2 (fixed point: cap/2 only): an exact repeat of the residual at the
# failing step is a cycle (period 1: stuck), growth is divergence, no decrease a stall.
#
# Exit: 0 when the sweeps ran and every check of agreement.txt and hopeless.txt passed,
# 1 otherwise (a failed point of a sweep is data, not an error), 2 bad argument.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
export FF_LOADPATH="${FF_LOADPATH:-/usr/lib/freefem++}"
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}"
export MPLBACKEND=Agg
PYTHON="${PYTHON:-/usr/bin/python3}"
out="${RESULTS_DIR:-$root/results}/stability"
runs="$out/runs"

NEWTON_CAP=100
FIXEDPOINT_CAP=1000
# A fixed-point run that has not ended after this many seconds is stopped and reported as
# 'timeout' (the slowest point of the full sweep takes about 10 s).
FIXEDPOINT_TIME_LIMIT=120
REDUCED=(-nx 33 -ny 16)

# ---- one point (called by xargs): stability.sh --point SWEEP ID TIMEOUT OPTIONS...
run_point() {
  local sweep="$1" id="$2" limit="$3"; shift 3
  local dir="$runs/$sweep/$id" log="$runs/$sweep/$id.log" rec="$runs/$sweep/$id.rec"
  mkdir -p "$runs/$sweep"
  rm -rf "$dir"
  local start end rc=0
  start=$(date +%s.%N)
  timeout -k 5 "$limit" FreeFem++-nw -ns -v 0 edp/solve.edp "$@" -out "$dir" > "$log" 2>&1 || rc=$?
  end=$(date +%s.%N)
  local message left=0 probes=""
  message="$(grep -m1 '^error:' "$log" | sed 's/^error: //' || true)"
  if [ "$rc" != 0 ]; then
    { [ -e "$dir" ] || compgen -G "$dir.partial.*" > /dev/null; } && left=1
  fi
  if [ "$rc" = 4 ] && [ "$sweep" != hopeless ] && [[ "$message" == *"iteration cap reached"* ]]; then
    probes="$(probe_failure "$dir" "$limit" "$@")"
  fi
  if [ "$rc" = 0 ] && [ "$sweep" != agree ]; then   # keep what the tables and the agreement need
    rm -f "$dir/history.txt" "$dir/contact_history.txt" "$dir/mesh.msh" "$dir/scene.scene"
  fi
  if [ "$rc" = 0 ]; then
    rm -f "$log"
  elif [ "$rc" = 4 ] || [ "$rc" = 5 ] || [ "$rc" = 9 ]; then
    rm -f "$log"
  fi
  {
    echo "sweep=$sweep"
    echo "id=$id"
    echo "options=$*"
    echo "exit=$rc"
    echo "wall=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }')"
    echo "message=$message"
    echo "output_left=$left"
    echo "probes=$probes"
  } > "$rec.tmp"
  mv "$rec.tmp" "$rec"
  printf 'stability: %-9s %-44s exit %d %7.2f s %s\n' "$sweep" "$id" "$rc" \
    "$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')" "$(echo "$message" | cut -c1-90)"
}

# probe_failure DIR TIMEOUT OPTIONS...: re-run a point that failed at the iteration cap with
# smaller caps; prints cap:step:residual for each (step 'ok' if the probe converged).
probe_failure() {
  local dir="$1" limit="$2"; shift 2
  local args=("$@") cap=0 i fixed=0
  for ((i = 0; i < ${#args[@]}; i++)); do
    [ "${args[$i]}" = -maxit ] && cap="${args[$((i + 1))]}"
    [ "${args[$i]}" = -solver ] && [ "${args[$((i + 1))]}" = fixedpoint ] && fixed=1
  done
  [ "$cap" -ge 2 ] || return 0
  local caps=("$((cap / 2))")
  [ "$fixed" = 0 ] && caps=("$((cap - 1))" "$((cap - 2))" "$((cap - 3))" "$((cap - 4))" "$((cap / 2))")
  local m line result="" step residual
  for m in "${caps[@]}"; do
    [ "$m" -ge 1 ] || continue
    for ((i = 0; i < ${#args[@]}; i++)); do [ "${args[$i]}" = -maxit ] && args[$((i + 1))]="$m"; done
    line="$(timeout -k 5 "$limit" FreeFem++-nw -ns -v 0 edp/solve.edp "${args[@]}" -out "$dir.probe" 2>&1 | grep -m1 '^error:' || true)"
    rm -rf "$dir.probe"
    step="$(echo "$line" | sed -n 's/.*step \([0-9]*\) (t = .*/\1/p')"
    residual="$(echo "$line" | sed -n 's/.*, residual \([^ ]*\) > tol.*/\1/p')"
    result+="${result:+,}$m:${step:-ok}:${residual:--}"
  done
  echo "$result"
}

if [ "${1:-}" = --point ]; then
  shift
  run_point "$@"
  exit 0
fi

quick=0
jobs=2
list=0
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --list) list=1 ;;
    --jobs) [ $# -ge 2 ] && [[ "$2" =~ ^[1-9][0-9]*$ ]] || { echo "stability.sh: error: --jobs needs a positive whole number" >&2; exit 2; }
            jobs="$2"; shift ;;
    -h|--help) sed -n '2,40p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "stability.sh: error: unknown argument '$1' (usage: stability.sh [--quick] [--jobs N] [--list])" >&2; exit 2 ;;
  esac
  shift
done

# ---- the points: one line "COST SWEEP ID TIMEOUT OPTIONS..." each (COST only orders them)
method_options() { # method -> solver options (the cap included)
  case "$1" in
    orig-newton-on) echo "-problem original -solver newton -safeguard on -maxit $NEWTON_CAP" ;;
    orig-newton-off) echo "-problem original -solver newton -safeguard off -maxit $NEWTON_CAP" ;;
    orig-fixedpoint) echo "-problem original -solver fixedpoint -maxit $FIXEDPOINT_CAP" ;;
    orig-full) echo "-problem original -solver full -maxit $NEWTON_CAP" ;;
    pen-newton-compliant-on) echo "-problem penalty -solver newton -penaltyform compliant -safeguard on -maxit $NEWTON_CAP" ;;
    pen-newton-compliant-off) echo "-problem penalty -solver newton -penaltyform compliant -safeguard off -maxit $NEWTON_CAP" ;;
    pen-newton-literal-on) echo "-problem penalty -solver newton -penaltyform literal -safeguard on -maxit $NEWTON_CAP" ;;
    pen-newton-literal-off) echo "-problem penalty -solver newton -penaltyform literal -safeguard off -maxit $NEWTON_CAP" ;;
    pen-fixedpoint) echo "-problem penalty -solver fixedpoint -maxit $FIXEDPOINT_CAP" ;;
    pen-full) echo "-problem penalty -solver full -maxit $NEWTON_CAP" ;;
    *) echo "stability.sh: internal error: unknown method $1" >&2; exit 1 ;;
  esac
}
# point SWEEP ID OPTIONS...: cost ~ steps x mesh size (x 30 for the fixed point)
point() {
  local sweep="$1" id="$2"; shift 2
  local limit=600
  [[ " $* " == *" fixedpoint "* ]] && limit=$FIXEDPOINT_TIME_LIMIT
  [ "$quick" = 1 ] && [ "$limit" -gt 60 ] && limit=60
  echo "$*" | awk -v s="$sweep" -v id="$id" -v lim="$limit" '{
    T = 1; dt = 0.01; nx = 66; ny = 33; fp = 1
    for (i = 1; i < NF; i++) {
      if ($i == "-T") T = $(i + 1); if ($i == "-dt") dt = $(i + 1)
      if ($i == "-nx") nx = $(i + 1); if ($i == "-ny") ny = $(i + 1)
      if ($i == "-solver" && $(i + 1) == "fixedpoint") fp = 30
    }
    printf "%.0f %s %s %s %s\n", 1000 * (T / dt) * (nx * ny / 528 + 1) * fp / 100 + 10, s, id, lim, $0 }'
}
# T for a time step k: 1, or 0.4 (reduced mesh) for k <= 1e-3
final_time() { awk -v k="$1" -v t="${2:-0.4}" 'BEGIN { print (k <= 1e-3 + 1e-12 ? t : 1) }'; }

NEWTON_METHODS=(orig-newton-on orig-newton-off pen-newton-compliant-on pen-newton-compliant-off
                pen-newton-literal-on pen-newton-literal-off)

points() {
  local m e r k mu load T mesh
  # eps x method (penalty; reduced mesh)
  local eps_list=(1e-1 1e-2 1e-3 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10 1e-11 1e-12)
  local eps_methods=(pen-newton-compliant-on pen-newton-compliant-off pen-newton-literal-on pen-newton-literal-off pen-fixedpoint)
  [ "$quick" = 1 ] && { eps_list=(1e-1 1e-6 1e-12); eps_methods=(pen-newton-compliant-on pen-newton-compliant-off pen-newton-literal-on pen-newton-literal-off); }
  for m in "${eps_methods[@]}"; do for e in "${eps_list[@]}"; do
    point eps "${m}_eps$e" "${REDUCED[@]}" $(method_options "$m") -eps "$e"
  done; done
  # r x method (reduced mesh; the penalty at its default eps = 2e-5)
  local r_list=(1e-4 3e-4 1e-3 3e-3 1e-2 3e-2 1e-1 3e-1 1 3 10 30 100 300 1e3 3e3 1e4)
  local r_methods=("${NEWTON_METHODS[@]}" orig-fixedpoint)
  [ "$quick" = 1 ] && { r_list=(1e-3 1 1e3); r_methods=(orig-newton-on orig-newton-off); }
  for m in "${r_methods[@]}"; do for r in "${r_list[@]}"; do
    point r "${m}_r$r" "${REDUCED[@]}" $(method_options "$m") -r "$r"
  done; done
  # k x mu (Newton; reduced mesh)
  local k_list=(0.2 0.1 0.05 0.02 0.01 5e-3 2e-3 1e-3 5e-4 2e-4 1e-4)
  local mu_list=(0 0.1 0.2 0.4 0.7 1 1.5)
  local kmu_methods=(orig-newton-on orig-newton-off pen-newton-compliant-on pen-newton-compliant-off orig-fixedpoint)
  [ "$quick" = 1 ] && { k_list=(0.2 0.01); mu_list=(0 0.4 1.5); kmu_methods=(orig-newton-on orig-newton-off); }
  for m in "${kmu_methods[@]}"; do for k in "${k_list[@]}"; do for mu in "${mu_list[@]}"; do
    T=$(final_time "$k")
    point kmu "${m}_k${k}_mu$mu" "${REDUCED[@]}" $(method_options "$m") -dt "$k" -T "$T" -mu "$mu"
  done; done; done
  # mu, load, k: every method (reduced mesh)
  local mu1=(0 0.1 0.2 0.3 0.4 0.5 0.7 1 1.25 1.5) load1=(1 2 5 10 20 50 100) k1=(0.2 0.1 0.05 0.02 0.01 1e-3 1e-4)
  local methods1=(orig-newton-on orig-newton-off orig-fixedpoint pen-newton-compliant-on pen-newton-compliant-off
                  pen-newton-literal-on pen-newton-literal-off)
  [ "$quick" = 1 ] && { mu1=(0 1.5); load1=(1 100); k1=(0.2); methods1=(orig-newton-on pen-newton-literal-off); }
  for m in "${methods1[@]}"; do
    for mu in "${mu1[@]}"; do point mu "${m}_mu$mu" "${REDUCED[@]}" $(method_options "$m") -mu "$mu"; done
    for load in "${load1[@]}"; do point load "${m}_load$load" "${REDUCED[@]}" $(method_options "$m") -load "$load"; done
    for k in "${k1[@]}"; do
      T=$(final_time "$k")
      point k "${m}_k$k" "${REDUCED[@]}" $(method_options "$m") -dt "$k" -T "$T"
    done
  done
  # mesh x k, fixed point (T = 0.4): its iterations grow with the mesh
  local fmesh=(16x8 33x16 66x33 132x66) fk=(0.2 0.05 0.01 1e-3)
  [ "$quick" = 1 ] && { fmesh=(16x8); fk=(0.2 0.01); }
  for mesh in "${fmesh[@]}"; do for k in "${fk[@]}"; do
    point fixedpoint "orig-fixedpoint_mesh${mesh}_k$k" -nx "${mesh%x*}" -ny "${mesh#*x}" $(method_options orig-fixedpoint) -dt "$k" -T 0.4
  done; done
  # mesh x r (Newton on/off, 5 steps: Newton without safeguards cycled at step 1 on fine meshes)
  local meshes=(16x8 33x16 66x33 132x66) mr=(1e-3 1e-2 1e-1 1 10 100 1e3)
  [ "$quick" = 1 ] && { meshes=(16x8); mr=(1 1e3); }
  for mesh in "${meshes[@]}"; do for m in orig-newton-on orig-newton-off; do for r in "${mr[@]}"; do
    point mesh "${m}_mesh${mesh}_r$r" -nx "${mesh%x*}" -ny "${mesh#*x}" $(method_options "$m") -r "$r" -T 0.05
  done; done; done
  # the defaults of both solvers (no -maxit: 50 and 500 as shipped) on the paper mesh 66x33
  # over the paper box
  local bp=("original" "penalty 2e-5" "penalty 1e-12") bmu=(0 0.4 1.5) bload=(1 10 100) bk=(0.2 0.01 1e-3)
  local bsmall=("0.4 10" "0 1" "1.5 100")   # k = 1e-4 (T = 0.2) at the paper point and two corners
  [ "$quick" = 1 ] && { bp=("original" "penalty 1e-12"); bmu=(0.4); bload=(10); bk=(0.01); bsmall=(); }
  local p pname popts ml solver sname
  for solver in newton fixedpoint; do
    sname=""; [ "$solver" = fixedpoint ] && sname="fixedpoint-"
    for p in "${bp[@]}"; do
      if [ "$p" = original ]; then pname=original; popts="-problem original"
      else pname="penalty-eps${p#* }"; popts="-problem penalty -eps ${p#* }"; fi
      for mu in "${bmu[@]}"; do for load in "${bload[@]}"; do for k in "${bk[@]}"; do
        T=$(final_time "$k" 0.2)
        point box "${sname}${pname}_mu${mu}_load${load}_k$k" -solver "$solver" $popts -mu "$mu" -load "$load" -dt "$k" -T "$T"
      done; done; done
      for ml in "${bsmall[@]}"; do
        point box "${sname}${pname}_mu${ml% *}_load${ml#* }_k1e-4" -solver "$solver" $popts -mu "${ml% *}" -load "${ml#* }" -dt 1e-4 -T 0.2
      done
    done
    if [ "$quick" = 0 ]; then                # the eps line (1e-12 is in the grid above)
      for e in 1e-1 1e-2 1e-3 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10 1e-11; do
        point box "${sname}penalty-eps${e}_mu0.4_load10_k0.01" -solver "$solver" -problem penalty -eps "$e"
      done
    fi
  done
  # agreement: points where the fixed point and the full-system Newton converge too
  local amethods=(orig-newton-on orig-newton-off orig-fixedpoint orig-full)
  local pmethods=(pen-newton-compliant-on pen-newton-compliant-off pen-newton-literal-on pen-newton-literal-off pen-fixedpoint pen-full)
  local settings=("mu0_k0.1:-mu 0 -dt 0.1" "mu0.4_k0.1_T0.2:-mu 0.4 -dt 0.1 -T 0.2"
                  "mu0.4_k0.01_T0.05:-mu 0.4 -T 0.05" "mu1.5_load100_k0.01_T0.05:-mu 1.5 -load 100 -T 0.05")
  [ "$quick" = 1 ] && { settings=("mu0.4_k0.01_T0.05:-mu 0.4 -T 0.05"); amethods=(orig-newton-on orig-newton-off orig-fixedpoint orig-full);
                        pmethods=(pen-newton-compliant-on pen-newton-literal-on pen-newton-literal-off pen-fixedpoint); }
  local s name opts
  for s in "${settings[@]}"; do
    name="${s%%:*}"; opts="${s#*:}"
    for m in "${amethods[@]}" "${pmethods[@]}"; do
      local extra=""
      [[ "$m" == pen-* ]] && extra="-eps 1e-3"
      point agree "${m}_$name" "${REDUCED[@]}" $(method_options "$m") $opts $extra
    done
    for r in 0.1 10; do point agree "orig-newton-on_${name}_r$r" "${REDUCED[@]}" $(method_options orig-newton-on) $opts -r "$r"; done
  done
  # hard bodies (docs/stability.md, "Hard bodies"): a curved 2D body and a twisted 3D body,
  # held by the contact (and their top's x), at the defaults of each method (no -maxit) over mu
  local bodies=(halfdisk twisted3d) bmu2=(0 0.4 0.7 1) body
  [ "$quick" = 1 ] && bmu2=(0.4)
  for body in "${bodies[@]}"; do for mu in "${bmu2[@]}"; do
    point bodies "${body}_newton_mu$mu" -scene "$body" -mu "$mu"
    point bodies "${body}_newton-script_mu$mu" -scene "$body" -mu "$mu" -kernel script
    point bodies "${body}_penalty_mu$mu" -scene "$body" -mu "$mu" -problem penalty
    point bodies "${body}_fixedpoint_mu$mu" -scene "$body" -mu "$mu" -solver fixedpoint
  done; done
  # hopeless settings: each must exit non-zero, say why, and leave no output folder
  point hopeless maxit1 "${REDUCED[@]}" -maxit 1
  point hopeless tol1e-20 "${REDUCED[@]}" -tol 1e-20
  point hopeless newton-off-r1e3 "${REDUCED[@]}" -safeguard off -r 1e3 -maxit $NEWTON_CAP
  point hopeless fixedpoint-maxit2 "${REDUCED[@]}" -solver fixedpoint -maxit 2
  point hopeless load1e308 "${REDUCED[@]}" -load 1e308
  point hopeless g1e-300 "${REDUCED[@]}" -g 1e-300
}

if [ "$list" = 1 ]; then points | sort -k1,1nr -s | cut -d' ' -f2-; exit 0; fi
rm -rf "$out"
mkdir -p "$runs"
start=$(date +%s.%N)
points | sort -k1,1nr -s | cut -d' ' -f2- > "$out/points.list"
total=$(wc -l < "$out/points.list")
echo "stability: $total points, $jobs at a time, results in $out"
xargs -P "$jobs" -L 1 bash "$0" --point < "$out/points.list"
sweeps_end=$(date +%s.%N)
status=0
"$PYTHON" plots/stability_tables.py --results "$out" || status=1
"$PYTHON" plots/stability.py --results "$out" --out "$out/maps" || status=1
end=$(date +%s.%N)
{
  echo "# wall time of plots/stability.sh (seconds)"
  echo "# key value"
  echo "mode $([ "$quick" = 1 ] && echo quick || echo full)"
  echo "jobs $jobs"
  echo "points $total"
  echo "wall_sweeps $(awk -v a="$start" -v b="$sweeps_end" 'BEGIN { printf "%.1f", b - a }')"
  echo "wall_total $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }')"
} > "$out/timing.txt"
echo "stability: $total points in $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.0f", b - a }') s; tables in $out, maps in $out/maps"
exit $status
