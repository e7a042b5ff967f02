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
  for map in eps_method r_method k_mu paper_box fixedpoint_mesh_k bodies; do
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


# ---- hard bodies (docs/stability.md, "Hard bodies"). The half disk (edp/scenes/halfdisk.scene),
# held only by the contact and its top's x, at Newton's defaults with mu 0.4 (the scene) and 1
# (T = 0.3): exit 0, at most 30 iterations in any step (the target; they take about 9 here),
# the physics checks, and the same outputs as plain Newton (-safeguard off, another path
# through the pieces) to 1e-9 (check_results.py --compare). The twisted and the sloped 3D
# block (edp/scenes/twisted3d.scene, sloped3d.scene) at mu 0.7 (their scenes) and 1: exit 0 at
# the defaults, the physics checks, and the same outputs as Newton at r = 10 (another path;
# plain Newton fails on the twisted block at step 1) to 1e-9. The literal penalty
# row without safeguards at eps = 1e-10: converges, and equals the compliant row to 1e-9.
hard() { # hard NAME OPTIONS...: a run at the defaults that passes the physics checks
  local name="$1"; shift
  rm -rf "$work/hard-$name"
  solve "$@" -quiet -out "$work/hard-$name" >> "$diag" 2>&1 && "$PYTHON" tests/check_results.py "$work/hard-$name" >> "$diag" 2>&1 \
    || { echo "$name ($*): failed" >> "$diag"; status=1; return 1; }
}
diag="$work/hard-2d.diag"; : > "$diag"; status=0
for mu in 0.4 1; do
  hard "halfdisk-$mu" -scene halfdisk -mu "$mu" -T 0.3 || continue
  most="$(awk '$1 == "iterations_max" { print $2 }' "$work/hard-halfdisk-$mu/summary.txt")"
  [ -n "$most" ] && [ "$most" -le 30 ] || { echo "halfdisk -mu $mu: $most iterations in a step (at most 30 expected)" >> "$diag"; status=1; }
  hard "halfdisk-$mu-plain" -scene halfdisk -mu "$mu" -T 0.3 -safeguard off \
    && { "$PYTHON" tests/check_results.py "$work/hard-halfdisk-$mu-plain" --compare "$work/hard-halfdisk-$mu" --rtol 1e-9 >> "$diag" 2>&1 || { echo "halfdisk -mu $mu: not plain Newton's outputs to 1e-9" >> "$diag"; status=1; }; }
done
report $status "hard bodies, 2D: the half disk at Newton's defaults (mu 0.4, 1): at most 30 iterations a step, physics checks, plain Newton's outputs to 1e-9" "$diag"
# The fixed point on the half disk (two levels: fixedpoint.cpp), mu 0.4 and 1, T = 0.3, at its
# defaults: exit 0, at most 200 iterations in any step (the target; about 60 and 105 here),
# the physics checks, and Newton's outputs (the runs above) to 1e-9
diag="$work/hard-fixedpoint.diag"; : > "$diag"; status=0
for mu in 0.4 1; do
  [ -f "$work/hard-halfdisk-$mu/summary.txt" ] || { echo "no Newton run of mu $mu to compare with" >> "$diag"; status=1; continue; }
  hard "halfdisk-$mu-fixedpoint" -scene halfdisk -mu "$mu" -T 0.3 -solver fixedpoint || continue
  most="$(awk '$1 == "iterations_max" { print $2 }' "$work/hard-halfdisk-$mu-fixedpoint/summary.txt")"
  [ -n "$most" ] && [ "$most" -le 200 ] || { echo "halfdisk -mu $mu, fixed point: $most iterations in a step (at most 200 expected)" >> "$diag"; status=1; }
  "$PYTHON" tests/check_results.py "$work/hard-halfdisk-$mu-fixedpoint" --compare "$work/hard-halfdisk-$mu" --rtol 1e-9 >> "$diag" 2>&1 \
    || { echo "halfdisk -mu $mu: the fixed point's outputs are not Newton's to 1e-9" >> "$diag"; status=1; }
done
# at k = 1e-4 the two levels cycle (normal slots between free and damped) and the step is
# solved again on one level: converges, Newton's outputs to 1e-8 (the suite's fixed point
# against Newton agreement, docs/stability.md)
if hard "halfdisk-smalldt-fixedpoint" -scene halfdisk -dt 1e-4 -T 0.002 -solver fixedpoint \
   && hard "halfdisk-smalldt" -scene halfdisk -dt 1e-4 -T 0.002; then
  "$PYTHON" tests/check_results.py "$work/hard-halfdisk-smalldt-fixedpoint" --compare "$work/hard-halfdisk-smalldt" --rtol 1e-8 >> "$diag" 2>&1 \
    || { echo "halfdisk -dt 1e-4: the fixed point's outputs are not Newton's to 1e-8" >> "$diag"; status=1; }
fi
report $status "hard bodies, 2D: the fixed point on the half disk at its defaults (mu 0.4, 1): at most 200 iterations a step, physics checks, Newton's outputs to 1e-9; at k = 1e-4 (the two levels cycle, one level again) to 1e-8" "$diag"
diag="$work/hard-3d.diag"; : > "$diag"; status=0
for body in twisted3d sloped3d; do
  for mu in 0.7 1; do
    hard "$body-$mu" -scene "$body" -mu "$mu" || continue
    hard "$body-$mu-r10" -scene "$body" -mu "$mu" -r 10 \
      && { "$PYTHON" tests/check_results.py "$work/hard-$body-$mu-r10" --compare "$work/hard-$body-$mu" --rtol 1e-9 >> "$diag" 2>&1 || { echo "$body -mu $mu: not the outputs of -r 10 to 1e-9" >> "$diag"; status=1; }; }
  done
done
report $status "hard bodies, 3D: the twisted and the sloped block at Newton's defaults (mu 0.7, 1): physics checks, the outputs of -r 10 to 1e-9" "$diag"
# The twisted block at mu 1 on 16 x 8 x 4: exit 4 at step 1 before the watchdog could
# start again after going back (docs/stability.md, "What Newton does now"; -maxit 300: 79 in
# that step); now at most 30 iterations in any step, the physics checks, and the outputs of
# -r 10 (another path) to 1e-9
diag="$work/hard-3d-fine.diag"; : > "$diag"; status=0
if hard "twisted3d-fine" -scene twisted3d -mu 1 -nx 16 -ny 8 -nz 4; then
  most="$(awk '$1 == "iterations_max" { print $2 }' "$work/hard-twisted3d-fine/summary.txt")"
  [ -n "$most" ] && [ "$most" -le 30 ] || { echo "twisted3d -mu 1 16 x 8 x 4: $most iterations in a step (at most 30 expected)" >> "$diag"; status=1; }
  hard "twisted3d-fine-r10" -scene twisted3d -mu 1 -nx 16 -ny 8 -nz 4 -r 10 \
    && { "$PYTHON" tests/check_results.py "$work/hard-twisted3d-fine-r10" --compare "$work/hard-twisted3d-fine" --rtol 1e-9 >> "$diag" 2>&1 || { echo "twisted3d -mu 1 16 x 8 x 4: not the outputs of -r 10 to 1e-9" >> "$diag"; status=1; }; }
fi
# the watchdog's restart once a step: the paper's block at large r went back and forth five
# times in step 1 with it unbounded, and reached the cap at r = 5e3 (exit 4; 25 there before)
hard "paper-r5e3" -r 5e3
report $status "hard bodies, 3D: the twisted block at mu 1 on 16 x 8 x 4 at Newton's defaults: at most 30 iterations a step, physics checks, the outputs of -r 10 to 1e-9; the paper block at r = 5e3 converges" "$diag"
# The fixed point on the 3D blocks (the disk's two levels: fixedpoint.cpp, consistentStep), at
# its defaults: exit 0, the physics checks and Newton's outputs (the runs above) to 1e-9; at
# most 200 iterations in any step on the twisted and the sloped block at mu 0.7 and 1 (the
# target; about 50 to 80 here). The same on the thin plate (slab3d-thin), on its own 16 x 8 x 1
# and on 32 x 16 x 1 (K = 3 and 4 modes split off: about 70 and 90 here; 378 and exit 4 with one),
# and without friction (K = 3 stalls at step 24, where two nodes reach the bound: the step again,
# and the rest of the run, with one mode; about 30 here, exit 4 before that fallback).
diag="$work/hard-3d-fixedpoint.diag"; : > "$diag"; status=0
for run in "twisted3d 0.7 200" "twisted3d 1 200" "sloped3d 0.7 200" "sloped3d 1 200"; do
  set -- $run; body=$1; mu=$2; cap=$3
  [ -f "$work/hard-$body-$mu/summary.txt" ] || { echo "no Newton run of $body -mu $mu to compare with" >> "$diag"; status=1; continue; }
  hard "$body-$mu-fixedpoint" -scene "$body" -mu "$mu" -solver fixedpoint || continue
  most="$(awk '$1 == "iterations_max" { print $2 }' "$work/hard-$body-$mu-fixedpoint/summary.txt")"
  [ "$cap" = - ] || { [ -n "$most" ] && [ "$most" -le "$cap" ]; } || { echo "$body -mu $mu, fixed point: $most iterations in a step (at most $cap expected)" >> "$diag"; status=1; }
  "$PYTHON" tests/check_results.py "$work/hard-$body-$mu-fixedpoint" --compare "$work/hard-$body-$mu" --rtol 1e-9 >> "$diag" 2>&1 \
    || { echo "$body -mu $mu: the fixed point's outputs are not Newton's to 1e-9" >> "$diag"; status=1; }
done
for plate in "slab3d-thin" "slab3d-thin-32 -nx 32 -ny 16 -nz 1" "slab3d-thin-mu0 -mu 0"; do
  set -- $plate; name=$1; shift
  hard "$name-fixedpoint" -scene slab3d-thin "$@" -solver fixedpoint && hard "$name" -scene slab3d-thin "$@" || continue
  most="$(awk '$1 == "iterations_max" { print $2 }' "$work/hard-$name-fixedpoint/summary.txt")"
  [ -n "$most" ] && [ "$most" -le 200 ] || { echo "$name, fixed point: $most iterations in a step (at most 200 expected)" >> "$diag"; status=1; }
  "$PYTHON" tests/check_results.py "$work/hard-$name-fixedpoint" --compare "$work/hard-$name" --rtol 1e-9 >> "$diag" 2>&1 \
    || { echo "$name: the fixed point's outputs are not Newton's to 1e-9" >> "$diag"; status=1; }
done
report $status "hard bodies, 3D: the fixed point on the twisted and the sloped block (mu 0.7, 1) and the thin plate (16 x 8 x 1, 32 x 16 x 1, and mu 0) at its defaults: physics checks, Newton's outputs to 1e-9, at most 200 iterations a step" "$diag"
diag="$work/hard-literal.diag"; : > "$diag"; status=0
hard literal -problem penalty -eps 1e-10 -penaltyform literal -safeguard off -nx 33 -ny 16 \
  && hard compliant -problem penalty -eps 1e-10 -nx 33 -ny 16 \
  && { "$PYTHON" tests/check_results.py "$work/hard-compliant" --compare "$work/hard-literal" --rtol 1e-9 >> "$diag" 2>&1 || { echo "the literal row is not the compliant row's v to 1e-9" >> "$diag"; status=1; }; }
report $status "the literal penalty row without safeguards at eps = 1e-10 converges (Newton's correction form) and equals the compliant row to 1e-9" "$diag"
