# -restart DIR (docs/design.md, "Restart"), and the versions every run records.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, expect_failure, work, PYTHON, ...).
# ---- a run split at t0 gives the whole run from t0 on: each restart passes the physics checks
# and agrees with the whole run to 1e-9 of each column's scale (the solver stops at 1e-10;
# measured 2e-14 in 2D, 3e-13 in 3D), its steps numbered on from the first part's; its
# zone_boundaries.txt holds the whole run's rows from its first step on
restart_case() { # restart_case NAME T0 T OPTIONS...: whole to T, first part to T0, the restart to T
  local name="$1" t0="$2" T="$3" diag="$work/restart-$1.diag"; shift 3
  local status=0
  rm -rf "$work/restart-$name"-*
  : > "$diag"
  solve "$@" -T "$T" -out "$work/restart-$name-whole" >> "$diag" 2>&1 || status=1
  solve "$@" -T "$t0" -out "$work/restart-$name-first" >> "$diag" 2>&1 || status=1
  solve -restart "$work/restart-$name-first" -T "$T" -out "$work/restart-$name-second" >> "$diag" 2>&1 || status=1
  "$PYTHON" tests/check_results.py "$work/restart-$name-second" --compare "$work/restart-$name-whole" --rtol 1e-9 >> "$diag" 2>&1 || status=1
  # zone_boundaries.txt numbered on too: the whole run's rows from the restart's first step on
  "$PYTHON" tests/check_zone_boundaries.py --restart-of "$work/restart-$name-whole" "$work/restart-$name-second" >> "$diag" 2>&1 || status=1
  # the restart starts where the first part ended: its first step is the next one
  local first last
  first="$(awk '$1 == "first_step" { print $2 }' "$work/restart-$name-second/summary.txt" 2>/dev/null)"
  last="$(awk '$2 == "restart_step" { print $3 }' "$work/restart-$name-first/state.txt" 2>/dev/null)"
  [ -n "$first" ] && [ "$first" = "$((last + 1))" ] || { echo "first_step '$first' after a first part of '$last' steps" >> "$diag"; status=1; }
  report $status "-restart: $name split at t = $t0 gives the whole run to T = $T (physics checks, 1e-9 of each column's scale, the zone boundaries' rows)" "$diag"
}
restart_case paper-original 0.5 1 -scene paper -nx 8 -ny 4 -dt 0.1
restart_case paper-penalty 0.5 1 -scene paper -nx 8 -ny 4 -dt 0.1 -problem penalty
restart_case slab3d-friction 0.5 1 -scene slab3d -nx 8 -ny 4 -nz 2 -dt 0.1 -mu 0.7
restart_case column-fixedpoint 0.3 0.6 -scene column -dt 0.05 -solver fixedpoint

# ---- what a restart refuses, with no results written: another body, mesh, supports or
# dimension (exit 3), a time step that does not divide t0, a final time not after it, a
# folder without a state (exit 2), a damaged state (exit 3)
first="$work/restart-paper-original-first"
expect_failure "-restart with another material" 3 "option -restart .*: not the same material, -rho: 2e-6 in .*state.txt, 1e-3 in this run" \
  -restart "$first" -T 1 -rho 1e-3
expect_failure "-restart on another mesh" 3 "option -restart .*: not the same mesh \\(the POSIX checksum of mesh.msh\\)" \
  -restart "$first" -T 1 -mesh "$work/restart-column-fixedpoint-first/mesh.msh"
{ grep -v '^dirichlet 2' "$first/scene.scene"; } > "$work/restart-supports.scene"
expect_failure "-restart with other supports" 3 "option -restart .*: not the same supports \\(the scene's dirichlet lines\\)" \
  -restart "$first" -T 1 -scene "$work/restart-supports.scene"
expect_failure "-restart of a 3D run as a 2D one" 3 "3D mesh, but the scene .* is 2D|not the same dimension" \
  -restart "$work/restart-slab3d-friction-first" -T 1 -scene paper
expect_failure "-restart with a -dt that does not divide t0" 2 "option -dt 0.2: a restart at t0 = 0.5 .* needs a time step that divides t0" \
  -restart "$first" -T 1 -dt 0.2
expect_failure "-restart to a -T not after t0" 2 "option -T 0.5: a restart continues .* from t0 = 0.5: give -T > t0" \
  -restart "$first" -T 0.5
expect_failure "-restart of a folder without state.txt" 2 "option -restart .*: no readable .*/state.txt" \
  -restart "$work" -T 1
expect_failure "-restart with -adapt" 2 "option -adapt 1: a restart runs on the mesh of the run it continues" \
  -restart "$first" -T 1 -adapt 1
rm -rf "$work/restart-damaged"; cp -r "$first" "$work/restart-damaged"
head -c -7 "$first/state.txt" > "$work/restart-damaged/state.txt"
expect_failure "-restart of a truncated state.txt" 3 "restart-damaged/state.txt: its last line has no line end: the file is truncated" \
  -restart "$work/restart-damaged" -T 1
sed 's/^v 5 .*/v 5 nan/' "$first/state.txt" > "$work/restart-damaged/state.txt"
expect_failure "-restart of a state.txt holding nan" 3 "restart-damaged/state.txt:[0-9]+: 'nan' is not a finite number" \
  -restart "$work/restart-damaged" -T 1
sed 's/^u 3 /u 4 /' "$first/state.txt" > "$work/restart-damaged/state.txt"
expect_failure "-restart of a state.txt with an index out of order" 3 "restart-damaged/state.txt:[0-9]+: index 4 of u, expected 3" \
  -restart "$work/restart-damaged" -T 1

sed 's/^# restart_time .*/# restart_time -1/' "$first/state.txt" > "$work/restart-damaged/state.txt"
expect_failure "-restart of a state.txt whose t0 is not restart_step x dt" 3 "restart-damaged/state.txt: restart_time -1, restart_step 5 and dt 0.1 do not agree" \
  -restart "$work/restart-damaged" -T 1
awk '{ print } /^# restart_step/ { print }' "$first/state.txt" > "$work/restart-damaged/state.txt"
expect_failure "-restart of a state.txt giving a key twice" 3 "restart-damaged/state.txt:[0-9]+: a second line '# restart_step'" \
  -restart "$work/restart-damaged" -T 1
sed 's/$/\r/' "$first/state.txt" > "$work/restart-damaged/state.txt"
expect_failure "-restart of a state.txt with CR LF line ends" 3 "restart-damaged/state.txt: has carriage returns" \
  -restart "$work/restart-damaged" -T 1
grep -v '^v [0-9]*[02468] ' "$first/state.txt" > "$work/restart-damaged/state.txt"
expect_failure "-restart of a state.txt that lost rows" 3 "restart-damaged/state.txt:[0-9]+: index 1 of v, expected 0" \
  -restart "$work/restart-damaged" -T 1
expect_failure "-restart without its own -T" 2 "option -T: a restart continues .* from t0 = 0.5: give its final time, -T > t0" \
  -restart "$first"
# a restart asks for its own -every, -vtk, -snapshots (the first part's scene.scene echoes them), and
# its scene.scene has no restart line (a state is no part of a scene)
diag="$work/restart-own.diag"; : > "$diag"; status=0
rm -rf "$work/restart-own-first" "$work/restart-own-second"
solve -scene paper -nx 8 -ny 4 -dt 0.1 -T 0.5 -every 2 -vtk 2 -snapshots 3 -out "$work/restart-own-first" >> "$diag" 2>&1 || status=1
solve -restart "$work/restart-own-first" -T 1 -out "$work/restart-own-second" >> "$diag" 2>&1 || status=1
[ -e "$work/restart-own-second/vtk" ] || [ -e "$work/restart-own-second/snapshots.txt" ] && { echo "the restart wrote vtk/ or snapshots.txt"; status=1; } >> "$diag"
grep -Eq '^# (every 0|vtk 0|snapshots 0)$' "$work/restart-own-second/history.txt" && [ "$(grep -Ec '^# (every 0|vtk 0|snapshots 0)$' "$work/restart-own-second/history.txt")" = 3 ] \
  || { echo "the restart's header does not say every 0, vtk 0, snapshots 0"; status=1; } >> "$diag"
grep -q "^restart " "$work/restart-own-second/scene.scene" && { echo "scene.scene echoes the restart"; status=1; } >> "$diag"
report $status "-restart asks for its own -T, -every, -vtk, -snapshots; its scene.scene has no restart line" "$diag"

# ---- every output records what made it: the suite, FreeFEM and gmsh versions, in each header and
# in summary.txt, the same everywhere; compare.edp notes runs of different versions
diag="$work/versions.diag"; : > "$diag"; status=0
run="$work/restart-paper-original-whole"
# (a checkout git will not read, another user's, records the release marked as such)
expected_suite="$(git -C . describe --always --dirty 2>/dev/null || { [ -e .git ] && echo "$(head -n 1 VERSION)+commit-unknown"; } || head -n 1 VERSION)"
for f in contact.txt fields.txt history.txt contact_history.txt contact_nodes_history.txt state.txt; do
  for key in suite_version freefem_version gmsh_version; do
    a="$(awk -v k="$key" '$1 == "#" && $2 == k { print $3; exit }' "$run/$f")"
    b="$(awk -v k="$key" '$1 == k { print $2 }' "$run/summary.txt")"
    [ -n "$a" ] && [ "$a" = "$b" ] || { echo "$f: $key '$a', summary.txt '$b'"; status=1; } >> "$diag"
  done
done
[ "$(awk '$1 == "suite_version" { print $2 }' "$run/summary.txt")" = "$expected_suite" ] || { echo "suite_version is not '$expected_suite'"; status=1; } >> "$diag"
[ "$(awk '$1 == "gmsh_version" { print $2 }' "$run/summary.txt")" = "$(gmsh --version 2>&1 | head -n 1)" ] || { echo "gmsh_version is not gmsh --version's"; status=1; } >> "$diag"
rm -rf "$work/versions-other"; cp -r "$run" "$work/versions-other"
sed -i 's/^# suite_version .*/# suite_version v0-other/' "$work/versions-other/fields.txt"
"${FREEFEM[@]}" edp/compare.edp -a "$work/versions-other" -ref "$run" > "$work/versions.out" 2> "$work/versions.err" || status=1
grep -q "note: compare.edp: the runs were made by different versions (.*suite_version v0-other" "$work/versions.err" \
  && grep -q "^error_L2 0 " "$work/versions.out" || { echo "compare.edp on runs of two versions:"; cat "$work/versions.out" "$work/versions.err"; status=1; } >> "$diag"
report $status "every file's header and summary.txt name the suite, FreeFEM and gmsh versions; compare.edp notes two versions" "$diag"
