# The stability study's reduced sweep and the safeguarded penalty.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
# ---- stability: the reduced sweep, the safeguarded penalty at tiny eps, and
# the defaults on the corners of the paper's parameter box
diag="$work/stability.diag"; : > "$diag"; status=0
rm -rf "$work/stability"
if RESULTS_DIR="$work" bash plots/stability.sh --quick > "$diag" 2>&1; then
  line=$(grep -o 'agreement [0-9]*/[0-9]* pairs.*hopeless settings failing loudly [0-9]*/[0-9]*' "$diag" | tail -1)
  agree=$(echo "$line" | sed -n 's/agreement \([0-9]*\)\/\([0-9]*\) pairs.*/\1 \2/p')
  loud=$(echo "$line" | sed -n 's/.*failing loudly \([0-9]*\)\/\([0-9]*\)/\1 \2/p')
  set -- $agree; [ -n "${1:-}" ] && [ "$1" = "$2" ] || { echo "agreement between methods: ${agree:-missing}" >> "$diag"; status=1; }
  set -- $loud; [ -n "${1:-}" ] && [ "$1" = "$2" ] || { echo "hopeless settings failing loudly: ${loud:-missing}" >> "$diag"; status=1; }
  for map in eps_method r_method k_mu paper_box fixedpoint_mesh_k; do
    [ -s "$work/stability/maps/stability_$map.png" ] || { echo "missing map stability_$map.png" >> "$diag"; status=1; }
  done
  for key in default_failures fixedpoint_default_failures; do
    [ "$(awk -v k="$key" '$1 == k { print $2 }' "$work/stability/summary.txt")" = 0 ] || { echo "$key is not 0" >> "$diag"; status=1; }
  done
else
  status=1
fi
report $status "./run.sh stability --quick: methods agree, both solvers' defaults converge in the box, hopeless settings fail loudly, maps drawn" "$diag"

diag="$work/tiny-eps.diag"; : > "$diag"
if solve -problem penalty -eps 1e-10 -out "$work/tiny-eps" > "$diag" 2>&1 \
   && "$PYTHON" tests/check_results.py "$work/tiny-eps" --zones 1,15,0,29,22 >> "$diag" 2>&1; then
  report 0 "the compliant penalty converges at eps = 1e-10 (paper scene, physics checks, zones 15/29)"
else
  report 1 "the compliant penalty converges at eps = 1e-10 (paper scene, physics checks, zones 15/29)" "$diag"
fi

diag="$work/box.diag"; : > "$diag"; status=0
for problem in original penalty; do
  for mu in 0 1.5; do
    for load in 1 100; do
      for k in "0.2 -T 1" "1e-4 -T 0.01"; do
        # shellcheck disable=SC2086
        if ! solve -nx 33 -ny 16 -problem "$problem" -mu "$mu" -load "$load" -dt $k -out "$work/box" >> "$diag" 2>&1 \
           || ! "$PYTHON" tests/check_results.py "$work/box" >> "$diag" 2>&1; then
          echo "failed: -nx 33 -ny 16 -problem $problem -mu $mu -load $load -dt $k" >> "$diag"; status=1
        fi
      done
    done
  done
done
report $status "the defaults converge on the 16 corners of the paper box (mu 0, 1.5; load 1, 100; k 0.2 to T = 1, 1e-4 to T = 0.01)" "$diag"

