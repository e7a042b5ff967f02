#!/usr/bin/env bash
# run.sh: the one entry point of the suite.
#   ./run.sh                 the main job: the paper scene, both problems, and the figures
#   ./run.sh test [--bless CASE]   the test harness (ends with "N passed, N failed")
#   ./run.sh solve [options] one run of edp/solve.edp (options: see README.md)
#   ./run.sh figures [name]  redraw figures from existing results
# Checks for FreeFem++, gmsh, numdiff and python3 with matplotlib first, and installs
# what is missing with apt-get when run as root (otherwise prints the command).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

# Debian's python3-matplotlib is installed for /usr/bin/python3 only: use it everywhere.
PYTHON=/usr/bin/python3
PACKAGES=(freefem++ libfreefem++ gmsh numdiff python3 python3-numpy python3-matplotlib libopenblas0-pthread)

missing_dependencies() {
  command -v FreeFem++-nw >/dev/null 2>&1 || return 0
  [ -f /usr/lib/freefem++/gmsh.so ] && [ -f /usr/lib/freefem++/lapack.so ] || return 0
  command -v gmsh >/dev/null 2>&1 || return 0
  command -v numdiff >/dev/null 2>&1 || return 0
  "$PYTHON" -c 'import numpy, matplotlib' >/dev/null 2>&1 || return 0
  [ -e /usr/lib/x86_64-linux-gnu/openblas-pthread/libblas.so.3 ] || [ ! -d /usr/lib/x86_64-linux-gnu ] || return 0
  return 1
}

ensure_dependencies() {
  missing_dependencies || return 0
  if [ "$(id -u)" = 0 ]; then
    echo "run.sh: installing ${PACKAGES[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -q >&2 && apt-get install -y -q "${PACKAGES[@]}" >&2
    if missing_dependencies; then echo "run.sh: error: dependencies still missing after apt-get install" >&2; exit 1; fi
  else
    echo "run.sh: error: missing dependencies; install them with:" >&2
    echo "  sudo apt-get update && sudo apt-get install -y ${PACKAGES[*]}" >&2
    exit 1
  fi
}

# Debian's /etc/freefem++.pref points at folders that do not exist: give the plugin path here.
export FF_LOADPATH=/usr/lib/freefem++
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}"
export MPLBACKEND=Agg
export PYTHON
FREEFEM=(FreeFem++-nw -ns -v 0)

solve() { "${FREEFEM[@]}" "$here/edp/solve.edp" "$@"; }

main_job() {
  local results="$here/results"
  local problem
  for problem in original penalty; do
    echo "run.sh: solving the paper scene, $problem problem ..."
    solve -scene paper -problem "$problem" -out "$results/paper-$problem"
  done
  echo "run.sh: drawing figures ..."
  "$PYTHON" "$here/plots/figures.py" --results "$results" --out "$results/figures"
  echo "run.sh: results in $results/paper-original and $results/paper-penalty, figures in $results/figures"
}

command="${1:-main}"
[ $# -gt 0 ] && shift
case "$command" in
  main) ensure_dependencies; main_job ;;
  solve) ensure_dependencies; solve "$@" ;;
  test) ensure_dependencies; exec bash "$here/tests/run_tests.sh" "$@" ;;
  figures) ensure_dependencies; "$PYTHON" "$here/plots/figures.py" --results "$here/results" --out "$here/results/figures" "$@" ;;
  -h|--help|help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//' ;;
  *) echo "run.sh: error: unknown command '$command' (commands: solve, test, figures, or none for the main job)" >&2; exit 2 ;;
esac
