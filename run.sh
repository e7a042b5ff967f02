#!/usr/bin/env bash
# run.sh: the one entry point of the suite.
#   ./run.sh                 the main job: the paper scene, both problems, the eps study,
#                            the runs for the open choices, the tables and every figure
#   ./run.sh test [--bless CASE]   the test harness (ends with "N passed, N failed")
#   ./run.sh solve [options] one run of edp/solve.edp (options: see README.md)
#   ./run.sh compare -a RUN -ref REF   the distance between two runs at T (edp/compare.edp)
#   ./run.sh figures [name]  redraw figures from existing results
#   ./run.sh figures RUN_DIR [RUN_DIR ...]   every figure of those run folders, into RUN_DIR/figures
#   ./run.sh animate RUN_DIR the deformed body over time (a run with -vtk N) -> RUN_DIR/figures
#   ./run.sh bench [--quick] the benchmark: cost per step, work-precision (results/bench)
#   ./run.sh bench-ranks [--quick | --iterative | --direct | --agree | --big]   -ranks N: scaling, the slab beyond one process (results/bench_ranks)
#   ./run.sh stability [--quick]  where each method fails (results/stability)
#   ./run.sh sweep -NAME V1,V2,... [options] -out DIR [-plot Q,...] [-jobs N]   one solve per value -> DIR
# Checks for FreeFem++, gmsh, numdiff and python3 with matplotlib first, and installs
# what is missing with apt-get when run as root (otherwise prints the command).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

# Debian's python3-matplotlib is installed for /usr/bin/python3 only: use it everywhere.
PYTHON=/usr/bin/python3
PACKAGES=(freefem++ libfreefem++ gmsh numdiff python3 python3-numpy python3-matplotlib libopenblas0-pthread
          g++ libfreefem++-dev libsuitesparse-dev liblapack-dev libblas-dev)
BENCH_PACKAGES=(time)                              # only the benchmark needs them (/usr/bin/time: memory)
TEST_PACKAGES=(python3-vtk9)                       # only the tests need them (they read -vtk output back)

missing_dependencies() { # missing_dependencies [solve|bench|test]: "solve" skips what only tests and plots need
  command -v FreeFem++-nw >/dev/null 2>&1 || return 0
  [ -f /usr/lib/freefem++/gmsh.so ] && [ -f /usr/lib/freefem++/lapack.so ] || return 0
  command -v gmsh >/dev/null 2>&1 || return 0
  kernel_buildable || return 0
  [ "${1:-}" = solve ] && return 1
  command -v numdiff >/dev/null 2>&1 || return 0
  # numpy and matplotlib (and vtk, for the tests) found, not imported: an import of matplotlib
  # costs a third of a second at every ./run.sh figures, animate, sweep
  # shellcheck disable=SC2046
  "$PYTHON" -c 'import importlib.util, sys; sys.exit(any(importlib.util.find_spec(m) is None for m in sys.argv[1:]))' \
    numpy matplotlib $([ "${1:-}" != test ] || echo vtk) >/dev/null 2>&1 || return 0
  [ -e /usr/lib/x86_64-linux-gnu/openblas-pthread/libblas.so.3 ] || [ ! -d /usr/lib/x86_64-linux-gnu ] || return 0
  [ "${1:-}" != bench ] || [ -x /usr/bin/time ] || return 0
  return 1
}

# The plugins of edp/plugins/, built with g++ against FreeFEM's headers (libfreefem++-dev):
# contactkernel (CHOLMOD from libsuitesparse-dev, LAPACK), whose law is contactlaw.hpp, and
# runtools (errors, clock). Each is rebuilt when the POSIX cksum of its sources changes; the
# kernel also gets it compiled in, to refuse to run with sources it was not built from.
PLUGINS="$here/edp/plugins"
# KERNEL_CXXFLAGS: the optimization flags of the plugins (default -O2). Another setting, e.g.
# "-O0" or "-O2 -march=native -ffp-contract=fast", changes the order of floating-point
# operations: the tests must pass with any of them (docs/reproduction.md, "What the tests check").
KERNEL_CXXFLAGS="${KERNEL_CXXFLAGS:--O2}"
kernel_buildable() {
  command -v g++ >/dev/null 2>&1 && [ -f /usr/include/freefem++/ff++.hpp ] && [ -f /usr/include/suitesparse/cholmod.h ] \
    && { [ -e /usr/lib/x86_64-linux-gnu/liblapack.so ] || [ -e /usr/lib/liblapack.so ]; }
}
# plugin_sources FOLDER [HEADER...]: the sources of a plugin, relative to edp/plugins, in the
# order of its checksum: the headers given (the kernel's law), then the folder's headers and
# C++ files, sorted
plugin_sources() {
  local folder="$1"; shift
  echo "$*" $(cd "$PLUGINS" && LC_ALL=C ls -1 "$folder"/*.hpp "$folder"/*.cpp 2> /dev/null)
}
build_plugin() { # build_plugin NAME "SOURCES..." [LIBRARIES...]: (re)build edp/plugins/build/NAME.so
  local name="$1" sources="$2"; shift 2
  local target="$PLUGINS/build/$name.so" sum file units=()
  for file in $sources; do
    [ -r "$PLUGINS/$file" ] || { echo "run.sh: error: cannot read $PLUGINS/$file (a source of the $name plugin)" >&2; exit 1; }
    case "$file" in *.cpp) units+=("$PLUGINS/$file") ;; esac
  done
  # shellcheck disable=SC2086
  sum="$(cd "$PLUGINS" && cat $sources | cksum | cut -d' ' -f1)"
  # the compiler flags are part of what was built: another KERNEL_CXXFLAGS rebuilds
  [ -f "$target" ] && [ "$(cat "$target.cksum" 2>/dev/null)" = "$sum $KERNEL_CXXFLAGS" ] && return 0
  mkdir -p "$PLUGINS/build"
  echo "run.sh: building $target (its sources changed; up to a minute)" >&2
  local tmp="$target.$$" saved compiler
  saved="$(trap -p TERM INT HUP)"
  # Each source compiled apart, as many at once as the machine has cores, then linked. (The
  # plugin compares its sources with these at run time: PLUGIN_SOURCES, PLUGIN_SOURCES_CKSUM.)
  compile_units() {
    local jobs unit k=0 running=()
    jobs="$(nproc 2>/dev/null || echo 1)"
    trap 'kill "${running[@]}" 2>/dev/null; exit 143' TERM
    mkdir -p "$tmp.o" || return 1
    for unit in "${units[@]}"; do
      # shellcheck disable=SC2086
      "$PLUGIN_CXX" $KERNEL_CXXFLAGS -std=c++14 -fPIC -DNDEBUG -DPLUGIN_SOURCES_CKSUM="$sum" -DPLUGIN_SOURCES="\"$sources\"" \
          -Wno-deprecated-declarations -I/usr/include/freefem++ -I/usr/include/suitesparse -I"$PLUGINS" $PLUGIN_INCLUDES -c "$unit" -o "$tmp.o/$k.o" &
      running+=($!); k=$((k + 1))
      if [ "${#running[@]}" -ge "$jobs" ]; then wait "${running[0]}" || { kill "${running[@]:1}" 2>/dev/null; return 1; }; running=("${running[@]:1}"); fi
    done
    for unit in "${running[@]}"; do wait "$unit" || { kill "${running[@]}" 2>/dev/null; return 1; }; done
    # shellcheck disable=SC2086
    "$PLUGIN_CXX" $KERNEL_CXXFLAGS -shared "$tmp.o"/*.o -o "$tmp" "$@"
  }
  compile_units "$@" &
  compiler=$!                                     # a signal during the build stops it and leaves no partial .so
  trap 'kill "$compiler" 2>/dev/null; wait "$compiler"; rm -rf "$tmp" "$tmp.o"; exit 143' TERM
  trap 'kill "$compiler" 2>/dev/null; wait "$compiler"; rm -rf "$tmp" "$tmp.o"; exit 130' INT
  trap 'kill "$compiler" 2>/dev/null; wait "$compiler"; rm -rf "$tmp" "$tmp.o"; exit 129' HUP
  if ! wait "$compiler"; then
    rm -rf "$tmp" "$tmp.o"; echo "run.sh: error: cannot build $target from $sources in $PLUGINS" >&2; exit 1
  fi
  rm -rf "$tmp.o"
  mv "$tmp" "$target"
  trap - TERM INT HUP; eval "$saved"
  echo "$sum $KERNEL_CXXFLAGS" > "$target.cksum"
  echo "run.sh: built $target" >&2
}
PLUGIN_CXX=g++ PLUGIN_INCLUDES=""                 # (the ranks' kernel: mpicxx and PETSc's headers)
build_kernel() {
  build_plugin contactkernel "$(plugin_sources kernel contactlaw.hpp)" -lcholmod -llapack -lblas
  build_plugin runtools "$(plugin_sources runtools)"
}

# -ranks N: the same kernel and law with edp/plugins/ranks/ (PETSc across MPI ranks), compiled
# with Open MPI's mpicxx against Debian's PETSc 3.18 into contactkernelmpi.so, which solve.edp
# loads under FreeFem++-mpi. Its packages are installed only for -ranks (and the tests of it).
RANKS_PACKAGES=(openmpi-bin libopenmpi-dev libpetsc-real3.18-dev libmetis-dev)
# Debian's PETSc 3.18 for this machine's architecture (x86_64-linux-gnu-real on amd64)
petsc_dir() {
  local d
  for d in /usr/lib/petscdir/petsc3.18/*-real; do [ -d "$d" ] && { echo "$d"; return; }; done
  echo /usr/lib/petscdir/petsc3.18/x86_64-linux-gnu-real
}
ranks_buildable() {
  local PETSC_DIR_DEBIAN; PETSC_DIR_DEBIAN=$(petsc_dir)
  command -v mpicxx >/dev/null 2>&1 && command -v mpirun >/dev/null 2>&1 && command -v FreeFem++-mpi >/dev/null 2>&1 \
    && [ -f "$PETSC_DIR_DEBIAN/include/petscksp.h" ] && [ -f /usr/include/metis.h ]
}
build_ranks_kernel() {
  local PETSC_DIR_DEBIAN; PETSC_DIR_DEBIAN=$(petsc_dir)
  PLUGIN_CXX=mpicxx PLUGIN_INCLUDES="-I$PETSC_DIR_DEBIAN/include" \
    build_plugin contactkernelmpi "$(plugin_sources kernel contactlaw.hpp) $(plugin_sources ranks)" \
      -lcholmod -llapack -lblas -L"$PETSC_DIR_DEBIAN/lib" -lpetsc_real -lmetis
}
ensure_ranks() { # the packages and the plugin of -ranks
  if ! ranks_buildable; then
    if [ "$(id -u)" = 0 ]; then
      echo "run.sh: installing ${RANKS_PACKAGES[*]} (for -ranks)" >&2
      export DEBIAN_FRONTEND=noninteractive
      apt-get update -q >&2 && apt-get install -y -q "${RANKS_PACKAGES[@]}" >&2
      ranks_buildable || { echo "run.sh: error: Open MPI, PETSc or METIS's headers still missing after apt-get install" >&2; exit 1; }
    else
      echo "run.sh: error: -ranks (and ./run.sh test, bench-ranks) needs Open MPI, PETSc and METIS's headers; install them with:" >&2
      echo "  sudo apt-get update && sudo apt-get install -y ${RANKS_PACKAGES[*]}" >&2
      exit 1
    fi
  fi
  build_ranks_kernel
}
# does this solve run on ranks: -ranks N, N > 0, on the command line; without -ranks there, a
# scene file (-scene FILE, else -restart DIR's DIR/scene.scene) whose line 'ranks N' says so
wants_ranks() {
  local previous="" a value="" scene="" restart=""
  for a in "$@"; do
    case "$previous" in -ranks) value="$a" ;; -scene) scene="$a" ;; -restart) restart="$a" ;; esac
    previous="$a"
  done
  if [ -n "$value" ]; then [[ "$value" =~ ^[0-9]+$ ]] && [ "$((10#$value))" -gt 0 ]; return; fi   # (a bad value: solve refuses it)
  [ -z "$scene" ] && [ -n "$restart" ] && scene="$restart/scene.scene"
  [ -f "$scene" ] && grep -Eq '^[[:space:]]*ranks[[:space:]]+0*[1-9]' "$scene" 2>/dev/null
}

ensure_dependencies() { # ensure_dependencies [solve|bench|test]
  if ! missing_dependencies "${1:-}"; then build_kernel; return 0; fi
  local wanted=("${PACKAGES[@]}")
  [ "${1:-}" = bench ] && wanted+=("${BENCH_PACKAGES[@]}")
  [ "${1:-}" = test ] && wanted+=("${TEST_PACKAGES[@]}")
  if [ "$(id -u)" = 0 ]; then
    echo "run.sh: installing ${wanted[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -q >&2 && apt-get install -y -q "${wanted[@]}" >&2
    if missing_dependencies "${1:-}"; then echo "run.sh: error: dependencies still missing after apt-get install" >&2; exit 1; fi
    build_kernel
  else
    echo "run.sh: error: missing dependencies; install them with:" >&2
    echo "  sudo apt-get update && sudo apt-get install -y ${wanted[*]}" >&2
    exit 1
  fi
}

# Debian's /etc/freefem++.pref points at folders that do not exist: give the plugin paths here.
export FF_LOADPATH="/usr/lib/freefem++;$here/edp/plugins/build"
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}"
export MPLBACKEND=Agg
export PYTHON
FREEFEM=(FreeFem++-nw -ns -v 0)

solve() { "${FREEFEM[@]}" "$here/edp/solve.edp" "$@"; }

# FreeFem++ reads an argument that starts with '-' or 'D' and has its first '=' after its fourth
# character as a macro definition, wherever it stands: a value of the user's (a file named
# "-DNAME=...") would change the script. Refused here before FreeFEM starts (and again by
# edp/plugins/runtools/spawn.cpp, for FreeFem++ started by hand).
# FreeFem++ also reads its own options wherever they stand, before any script or plugin runs
# (-f runs another script, -glut a program, -fglut truncates a file, -check_plugin loads a
# library, ...): refused here too (runtools refuses them when it is loaded, too late for
# those; started by hand, FreeFem++ should get the suite's options only).
FREEFEM_OPTIONS=" -v -f -fglut -glut -gff -check_plugin -nw -ng -wg -md -ne -cd -cdtmp -jc -ns -nowait -nc -log -wait -? "
refuse_freefem_arguments() {
  local a before shown
  for a in "$@"; do
    shown="${a:0:80}"; [ "${#a}" -le 80 ] || shown="$shown..."
    if [[ "$FREEFEM_OPTIONS" == *" $a "* ]]; then
      echo "error: the argument '$shown' is an option of FreeFem++ itself, which it reads wherever it stands: the suite refuses it (as the value of an option: rename that file or folder)" >&2
      exit 2
    fi
    case "$a" in -*=*|D*=*) ;; *) continue ;; esac
    before="${a%%=*}"
    if [ "${#before}" -gt 3 ]; then
      echo "error: the argument '$shown' would be read by FreeFem++ as a macro definition (an argument that starts with '-' or 'D' and has an '=' after its fourth character, wherever it stands), which could change the script: the suite refuses it" >&2
      exit 2
    fi
  done
}

# The main job runs each solve as a child and waits for it, so that a signal to run.sh reaches
# the solve too (it then removes its unfinished folder) before run.sh stops.
child=""
forward_signal() { # forward_signal NUMBER: stop the solve (TERM: a background job ignores INT)
  if [ -n "$child" ]; then kill -s TERM "$child" 2>/dev/null || true; wait "$child" 2>/dev/null || true; fi
  rm -f "${log:-}"
  exit $((128 + $1))
}

# The eps values of the penalty study (Fig. 5): decades from 1e-1 to 1e-8.
EPS_STUDY=(1e-1 1e-2 1e-3 1e-4 1e-5 1e-6 1e-7 1e-8)

run_logged() { # run_logged LABEL OPTIONS...: one progress line per run
  local label="$1"; shift
  local start end
  start=$(date +%s.%N)
  "${FREEFEM[@]}" "$here/edp/solve.edp" "$@" > "$log" 2>&1 &     # $! is the solve itself
  child=$!
  if ! wait "$child"; then
    cat "$log" >&2; echo "run.sh: error: $label failed" >&2; rm -f "$log"; exit 1
  fi
  child=""
  end=$(date +%s.%N)
  printf 'run.sh: %-44s %5.2f s  %s\n' "$label" "$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')" "$(grep -o 'zones on Gamma3: .*;' "$log" | sed 's/;$//')"
}

main_job() {
  results="${RESULTS_DIR:-$here/results}"      # RESULTS_DIR: another folder (the tests use one)
  mkdir -p "$results"
  log="$results/.log.$$"                         # this job's own, removed at its end
  local problem eps i
  for problem in original penalty; do                # (the original's fields every 5 steps, for ParaView)
    run_logged "paper scene, $problem" -scene paper -problem "$problem" -vtk "$([ "$problem" = original ] && echo 5 || echo 0)" \
      -out "$results/paper-$problem"
  done
  for i in "${!EPS_STUDY[@]}"; do
    eps="${EPS_STUDY[$i]}"
    run_logged "eps study, penalty eps = $eps" -scene paper -problem penalty -eps "$eps" -out "$results/eps-study/eps-$((i + 1))"
  done
  # Choices the paper leaves open: the time step and the orientation of the diagonals.
  local right="$results/choices/mesh-right-diagonal.msh"
  mkdir -p "$results/choices"
  gmsh -2 -format msh22 -v 0 -setnumber nx 66 -setnumber ny 33 -setnumber diagonal 1 "$here/meshes/rectangle.geo" -o "$right" > /dev/null
  for problem in original penalty; do
    run_logged "choices: $problem, k = 0.001" -scene paper -problem "$problem" -dt 0.001 -out "$results/choices/$problem-dt0.001"
    run_logged "choices: $problem, other diagonals" -scene paper -problem "$problem" -mesh "$right" -out "$results/choices/$problem-right-diagonal"
  done
  # The scenes of edp/scenes/ beyond the paper's (one figure each)
  local scene
  for scene in unloading cylinder bound-profile power-damping; do
    run_logged "scene $scene" -scene "$scene" -out "$results/scenes/$scene"
  done
  rm -f "$log"
  "$PYTHON" "$here/plots/tables.py" --results "$results"
  "$PYTHON" "$here/plots/figures.py" --results "$results" --out "$results/figures"
  "$PYTHON" "$here/plots/run_figures.py" "$results/paper-original" > /dev/null   # any run's figures, the animation
  "$PYTHON" "$here/plots/animate.py" "$results/paper-original" > /dev/null
  echo "run.sh: results in $results (zones: $results/zones.txt, eps study: $results/eps-study/eps_study.txt), figures in $results/figures"
}

command="${1:-main}"
[ $# -gt 0 ] && shift
case "$command" in
  main)
    trap 'forward_signal 15' TERM; trap 'forward_signal 2' INT; trap 'forward_signal 1' HUP
    ensure_dependencies; main_job ;;
  solve) refuse_freefem_arguments "$@"; ensure_dependencies solve; if wants_ranks "$@"; then ensure_ranks; fi; exec "${FREEFEM[@]}" "$here/edp/solve.edp" "$@" ;;   # a signal reaches the solve
  compare) refuse_freefem_arguments "$@"; ensure_dependencies solve; exec "${FREEFEM[@]}" "$here/edp/compare.edp" "$@" ;;
  test) ensure_dependencies test; ensure_ranks; exec bash "$here/tests/run_tests.sh" "$@" ;;
  bench) ensure_dependencies bench; exec bash "$here/plots/bench.sh" "$@" ;;
  bench-ranks) ensure_dependencies bench; ensure_ranks; exec bash "$here/plots/bench_ranks.sh" "$@" ;;
  stability) ensure_dependencies; exec bash "$here/plots/stability.sh" "$@" ;;
  figures) ensure_dependencies
    # A folder (an existing one, or a path with a '/') means run folders; otherwise figure names.
    if [ $# -gt 0 ] && { [ -d "$1" ] || [[ "$1" == */* ]]; }; then exec "$PYTHON" "$here/plots/run_figures.py" "$@"; fi
    "$PYTHON" "$here/plots/figures.py" --results "${RESULTS_DIR:-$here/results}" --out "${RESULTS_DIR:-$here/results}/figures" "$@" ;;
  animate) ensure_dependencies; exec "$PYTHON" "$here/plots/animate.py" "$@" ;;
  sweep) refuse_freefem_arguments "$@"; ensure_dependencies; exec "$PYTHON" "$here/plots/sweep.py" "$@" ;;   # each value: ./run.sh solve
  -h|--help|help) sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//' ;;
  *) echo "run.sh: error: unknown command '$command' (commands: solve, compare, test, figures, animate, sweep, bench, bench-ranks, stability, or none for the main job)" >&2; exit 2 ;;
esac
