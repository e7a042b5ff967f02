# Messages and echoes: a misspelt scene key or option (the key it likely meant), a scene
# without a mesh of its own, a step that did not converge (exit 4: what to try, in order); the
# numbers of the scene echo.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
# ---- an unknown key: its file and line, the key it most likely meant (the same but for case,
# else one or two edits away), then every key; none suggested when none is near
grep -v -E '^(traction|rho) ' edp/scenes/column.scene > "$work/typo-base.scene"
{ cat "$work/typo-base.scene"; echo "rho 2e-6"; echo "tracton 0 -1"; } > "$work/typo-edit.scene"
expect_failure "a misspelt scene key (one edit)" 3 \
  "typo-edit.scene:$(wc -l < "$work/typo-edit.scene"): unknown key 'tracton' \\(did you mean 'traction'\\?\\); the keys of a scene: geometry .*traction.* damping, and the default of an option: .* rho .*\\(docs/design.md" \
  -scene "$work/typo-edit.scene"
{ cat "$work/typo-base.scene"; echo "traction 0 -1"; echo "Rho 2e-6"; } > "$work/typo-case.scene"
expect_failure "a scene key in the wrong case" 3 "typo-case.scene:$(wc -l < "$work/typo-case.scene"): unknown key 'Rho' \\(did you mean 'rho'\\?\\); the keys of a scene: " \
  -scene "$work/typo-case.scene"
{ cat "$work/typo-base.scene"; echo "traction 0 -1"; echo "rho 2e-6"; echo "gravity 9.81"; } > "$work/typo-far.scene"
expect_failure "an unknown scene key near no key" 3 "typo-far.scene:$(wc -l < "$work/typo-far.scene"): unknown key 'gravity'; the keys of a scene: geometry " \
  -scene "$work/typo-far.scene"
{ cat "$work/typo-base.scene"; echo "traction 0 -1"; echo "rho 2e-6 3e-6"; } > "$work/typo-values.scene"
expect_failure "an option's default with two values in a scene" 3 "typo-values.scene:[0-9]+: cannot read 'rho 2e-6 3e-6': rho takes one value, the default of the option -rho" \
  -scene "$work/typo-values.scene"
expect_failure "a misspelt option" 2 "unknown option '-Rho' \\(did you mean '-rho'\\?\\); options are -scene, " -Rho 2e-6
expect_failure "an option near none" 2 "unknown option '-gravity'; options are -scene, " -gravity 9.81

# ---- a scene without a mesh of its own: geometry none needs -mesh (said before the options
# that would size a structured mesh are asked for), and runs with one; -help still answers
grep -v -E '^(geometry|nx|ny) ' edp/scenes/paper.scene > "$work/nomesh.scene"; echo "geometry none" >> "$work/nomesh.scene"
expect_failure "geometry none without -mesh" 3 "nomesh.scene:$(wc -l < "$work/nomesh.scene"): geometry none: the scene has no mesh of its own; give one with -mesh FILE.msh" \
  -scene "$work/nomesh.scene"
sed 's/^geometry none$/geometry nothere/' "$work/nomesh.scene" > "$work/nogeo.scene"
expect_failure "a geometry without its .geo" 3 "nogeo.scene:[0-9]+: geometry nothere: no readable file .*meshes/nothere.geo \\(a geometry is a .geo of meshes/\\); or give -mesh FILE.msh" \
  -scene "$work/nogeo.scene"
diag="$work/nomesh.diag"; : > "$diag"; status=0
rm -rf "$work/nomesh"
solve -scene "$work/nomesh.scene" -mesh "$work/paper-coarse-original/mesh.msh" -T 0.1 -dt 0.05 -quiet -out "$work/nomesh" >> "$diag" 2>&1 \
  && "$PYTHON" tests/check_results.py "$work/nomesh" >> "$diag" 2>&1 || status=1
solve -scene "$work/nomesh.scene" -help > "$work/nomesh-help.txt" 2>> "$diag" && grep -q -- '^  -nx  (none)  ' "$work/nomesh-help.txt" || status=1
report $status "geometry none runs with -mesh; its -help lists the options" "$diag"

# ---- exit 4 says what to try, in order (docs/stability.md, "When a step does not converge"):
# the half disk of edp/scenes/halfdisk.scene under a cap of 4 iterations (its step 1 needs
# about twice that); the first remedy, -maxit 300, runs to T and passes the physics checks.
# The fixed point's message puts -solver newton -maxit 300 first: the paper's block without its
# supports (its scene without the dirichlet lines), where the fixed point fails at step 1
# (docs/stability.md, "The fixed point on hard bodies"; the half disk it now gets through).
grep -v '^dirichlet' edp/scenes/paper.scene > "$work/nosupport.scene"
expect_failure "exit 4 at a small cap of Newton, with the remedies in order" 4 \
  "the contact solver did not converge after 4 iterations \\(iteration cap reached\\), residual [^ ]+ > tol 1e-10; no results written\\. Try, in this order: -maxit 300 \\(a larger cap\\), -dt 0.001 \\(a time step 10 times smaller\\), -safeguard off \\(plain Newton: the safeguards can slow it down\\); see docs/stability.md, \"When a step does not converge\"" \
  -scene halfdisk -maxit 4
expect_failure "exit 4 of the fixed point, with its remedies in order" 4 \
  "the contact solver did not converge after 500 iterations \\(iteration cap reached\\), residual [^ ]+ > tol 1e-10; no results written\\. Try, in this order: -solver newton -maxit 300 \\(Newton: fewer, costlier iterations\\), -maxit 2000 \\(a larger cap\\), -dt 0.001 \\(" \
  -scene "$work/nosupport.scene" -nx 33 -ny 16 -T 0.02 -solver fixedpoint
diag="$work/remedies.diag"; : > "$diag"; status=0
rm -rf "$work/halfdisk-maxit"
solve -scene halfdisk -maxit 300 -quiet -out "$work/halfdisk-maxit" >> "$diag" 2>&1 && "$PYTHON" tests/check_results.py "$work/halfdisk-maxit" >> "$diag" 2>&1 \
  || { echo "-maxit 300 did not get through" >> "$diag"; status=1; }
report $status "the first remedy exit 4 names for the half disk (-maxit 300) runs to T with the physics checks" "$diag"

# ---- the scene echo: every number in the shortest text that reads back as the same double
# (0.6, not 0.59999999999999998; 0.001; 2e-6), a direction normalized (traction 3 -4 as 0.6
# -0.8); a run repeated from its own scene.scene and mesh.msh gives the same outputs and the
# same echo (also with traction 1 -3, whose unit vector normalized again could change in its
# last digit)
diag="$work/echo.diag"; : > "$diag"; status=0
sed 's/^traction 3 -4$/traction 1 -3/' tests/data/short-numbers.scene > "$work/echo-oblique.scene"
for scene in tests/data/short-numbers.scene "$work/echo-oblique.scene"; do
  run="$work/echo-$(basename "$scene" .scene)"
  rm -rf "$run" "$run-again"
  solve -scene "$scene" -quiet -out "$run" >> "$diag" 2>&1 || status=1
  solve -scene "$run/scene.scene" -mesh "$run/mesh.msh" -quiet -out "$run-again" >> "$diag" 2>&1 || status=1
  same_outputs "$run" "$run-again" > "$work/echo.differ" || { echo "$scene: $(cat "$work/echo.differ") differ(s) when repeated" >> "$diag"; status=1; }
  cmp -s <(grep -v -E '^(#|nx |ny )' "$run/scene.scene") <(grep -v '^#' "$run-again/scene.scene") \
    || { echo "$scene: the repeated run's scene.scene is not the first's" >> "$diag"; diff "$run/scene.scene" "$run-again/scene.scene" >> "$diag"; status=1; }
done
for line in "traction 0.6 -0.8" "load_history 0 0 0.1 0.6 1 0.3333333333333333" "body_force 0.1 -0.001" "initial_velocity 2e-6 0" \
            "bound_profile 0 0.05 1 0.03333333333333333" "damping table 0 0 0.1 5 1 50"; do
  grep -qx -- "$line" "$work/echo-short-numbers/scene.scene" || { echo "scene.scene lacks '$line'" >> "$diag"; status=1; }
done
report $status "scene.scene writes the shortest numbers that read back (0.6, 0.001, 2e-6, 0.3333333333333333); repeated from it, the run is the same" "$diag"
