# Three dimensions.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
# ---- 3D (docs/design.md, "Three dimensions"): the disk law (and a bound_table) on the three
# Newtons and the fixed point, the slab against the 2D plane-strain solution, a 3D run that repeats itself
scene_agreement slide3d -scene oblique-slide3d
scene_agreement slab3d-coarse -scene slab3d -nx 8 -ny 4 -nz 1 -T 0.2
scene_agreement table3d -scene bound-table3d
diag="$work/fixedpoint3d.diag"; : > "$diag"; status=0
for name in slide3d slab3d-coarse; do
  opts=(-scene oblique-slide3d); [ "$name" = slab3d-coarse ] && opts=(-scene slab3d -nx 8 -ny 4 -nz 1 -T 0.2)
  solve "${opts[@]}" -solver fixedpoint -out "$work/$name-fixedpoint" >> "$diag" 2>&1 \
    && "$PYTHON" tests/check_results.py "$work/$name-fixedpoint" --compare "$work/$name" --rtol 1e-8 >> "$diag" 2>&1 || status=1
done
report $status "3D: the fixed point = Newton to 1e-8 (oblique-slide3d, slab3d coarse: the disk's pair update)" "$diag"
# The slab between walls (u_z = 0 on z = 0 and z = Lz) is the plane-strain problem: at T, x_B
# equal and x_C within one mesh spacing of the 2D solution's, and the normal force per depth
# closer to it on the finer mesh (measured: 2.2e-4 then 1.2e-4 relative, 16x8 then 32x16)
diag="$work/slab3d-strain.diag"; : > "$diag"; status=0
previous=1
for n in 16 32; do
  solve -scene slab3d -nx "$n" -ny $((n / 2)) -nz 2 -quiet -out "$work/slab3d-$n" >> "$diag" 2>&1 || status=1
  solve -scene paper -plane strain -nx "$n" -ny $((n / 2)) -quiet -out "$work/slab2d-$n" >> "$diag" 2>&1 || status=1
  verdict=$(awk -v h="$(awk -v n="$n" 'BEGIN { print 2 / n }')" -v previous="$previous" '
    FNR == 1 { file++ } /^#/ { next } { last[file] = $0 }
    END { split(last[1], a); split(last[2], b)
          lz = 0.25; d = a[3] / lz - b[3]; if (d < 0) d = -d; rel = d / b[3]
          xc = a[11] - b[11]; if (xc < 0) xc = -xc
          ok = a[10] == b[10] && xc <= h * 1.000001 && rel < previous
          printf "%s %.3e x_B %s %s x_C %s %s normal force per depth %.9g against %.9g\n", ok ? "ok" : "FAIL", rel, a[10], b[10], a[11], b[11], a[3] / lz, b[3] }' \
    "$work/slab3d-$n/contact_history.txt" "$work/slab2d-$n/contact_history.txt")
  echo "${n}x$((n / 2)): $verdict" >> "$diag"
  case "$verdict" in ok*) previous=$(echo "$verdict" | cut -d' ' -f2) ;; *) status=1 ;; esac
done
report $status "3D: the slab between walls = 2D plane strain (x_B, x_C within one spacing, the normal force converging)" "$diag"
diag="$work/repeat3d.diag"; : > "$diag"; status=0
solve -scene "$work/slide3d/scene.scene" -mesh "$work/slide3d/mesh.msh" -out "$work/slide3d-repeat" >> "$diag" 2>&1 || status=1
same_outputs "$work/slide3d" "$work/slide3d-repeat" >> "$diag" || { echo "(these differ)" >> "$diag"; status=1; }
report $status "3D: a run repeats itself from its own scene.scene and mesh.msh" "$diag"
# A bound that varies over a 3D contact face (bound_table: bilinear on a grid over x and z,
# constant beyond it), pressed so hard that every node of Gamma3 is at its bound. The column g
# of contact.txt and of contact_nodes_history.txt is the bilinear interpolation of the scene's
# numbers at each node's (x, z), computed here from the scene line (1e-14 relative); every node
# has normal status 2 and v_nu = g (check_results.py: the constraint and complementarity
# against the column g); the run repeats itself from its scene.scene (the table echoed) and
# mesh.msh; a constant table gives the run of g alone (to 1e-9)
diag="$work/bound-table3d.diag"; : > "$diag"; status=0
rm -rf "$work/bound-table3d" "$work/bound-table3d-repeat"
solve -scene bound-table3d -out "$work/bound-table3d" >> "$diag" 2>&1 || status=1
"$PYTHON" tests/check_results.py "$work/bound-table3d" >> "$diag" 2>&1 || status=1
"$PYTHON" - edp/scenes/bound-table3d.scene "$work/bound-table3d" >> "$diag" 2>&1 <<'PY' || status=1
import sys
import numpy as np
sys.path.insert(0, "edp")
import runfiles
scene, run = sys.argv[1:]
words = next(line.split() for line in open(scene) if line.split()[:1] == ["bound_table"])
# bound_table A a1 .. B b1 .. g G11 .. (row by row: G_ij at (a_i, b_j))
axisA, posB = words[1], next(k for k in range(2, len(words)) if words[k] in ("x", "y", "z"))
axisB, posG = words[posB], words.index("g", posB)
A = np.array(words[2:posB], float); B = np.array(words[posB + 1:posG], float)
G = np.array(words[posG + 1:], float).reshape(len(A), len(B))
assert (axisA, axisB) == ("x", "z") and len(A) >= 2 and len(B) >= 2, words


def bilinear(a, b):
    """linear along b on each line a_i (constant beyond B), then linear along a (constant beyond A)"""
    return np.array([np.interp(p, A, [np.interp(q, B, row) for row in G]) for p, q in zip(a, b)])


for name in ("contact.txt", "contact_nodes_history.txt"):
    c = runfiles.read_table(f"{run}/{name}")
    expected = bilinear(c[axisA], c[axisB])
    error = np.max(np.abs(c["g"] - expected) / expected)
    print(f"{name}: g against the bilinear table, {len(expected)} rows: largest relative difference {error:.3e}")
    assert error <= 1e-14, name
c = runfiles.read_table(f"{run}/contact.txt")
assert np.all(c["normal_status"] == 2), "a node is not at its bound: " + str(c["normal_status"])
assert np.max(np.abs(c["v_nu"] - c["g"]) / c["g"]) <= 1e-9, "v_nu != g"
# g varies in both directions of the face, between and beyond the grid's lines
for fixed, along in (("x", "z"), ("z", "x")):
    for value in np.unique(c[fixed]):
        assert np.ptp(c["g"][c[fixed] == value]) > 1e-3, f"g does not vary along {along} at {fixed} = {value}"
assert np.any(c["z"] < B[0]) and np.any(c["z"] > B[-1]) and np.any((c["x"] > A[0]) & (c["x"] < A[1])), "no node beyond or between the lines"
PY
grep -q '^bound_table x 0 0.4.* z 0.1.* g 0.03 0.05 ' "$work/bound-table3d/scene.scene" && ! grep -q '^g ' "$work/bound-table3d/scene.scene" \
  && grep -q '^# g bound_table$' "$work/bound-table3d/contact.txt" || { echo "scene.scene or contact.txt's header: no bound_table line, or g" >> "$diag"; status=1; }
solve -scene "$work/bound-table3d/scene.scene" -mesh "$work/bound-table3d/mesh.msh" -out "$work/bound-table3d-repeat" >> "$diag" 2>&1 || status=1
same_outputs "$work/bound-table3d" "$work/bound-table3d-repeat" >> "$diag" || { echo "(these differ when repeated from scene.scene)" >> "$diag"; status=1; }
sed 's/^bound_table .*/bound_table x 0 0.4 1 z 0.1 0.9 g 0.05 0.05 0.05 0.05 0.05 0.05/' edp/scenes/bound-table3d.scene > "$work/bound-table3d-constant.scene"
sed 's/^bound_table .*/g 0.05/' edp/scenes/bound-table3d.scene > "$work/bound-table3d-g.scene"
for name in constant g; do
  rm -rf "$work/bound-table3d-$name"
  solve -scene "$work/bound-table3d-$name.scene" -out "$work/bound-table3d-$name" >> "$diag" 2>&1 || status=1
done
"$PYTHON" tests/check_results.py "$work/bound-table3d-constant" --compare "$work/bound-table3d-g" --rtol 1e-9 >> "$diag" 2>&1 || status=1
report $status "3D: a bound_table over the contact face: contact.txt's g = the bilinear table at each node's (x, z) to 1e-14, every node at its bound (v_nu = g, physics checks), repeated from scene.scene; a constant table = g alone (1e-9)" "$diag"
# In 2D a bound_table over x and y is g at each node's (x, y): one constant in y is the
# bound_profile through its values along x (the paper's block of bound-profile.scene)
diag="$work/bound-table2d.diag"; : > "$diag"; status=0
grep -v '^bound_profile' edp/scenes/bound-profile.scene > "$work/bound-table2d.scene"; echo "bound_table x 0 2 y 0 1 g 0.03 0.03 0.07 0.07" >> "$work/bound-table2d.scene"
rm -rf "$work/bound-table2d" "$work/bound-profile2d"
solve -scene "$work/bound-table2d.scene" -nx 16 -ny 8 -dt 0.05 -out "$work/bound-table2d" >> "$diag" 2>&1 || status=1
solve -scene bound-profile -nx 16 -ny 8 -dt 0.05 -out "$work/bound-profile2d" >> "$diag" 2>&1 || status=1
"$PYTHON" tests/check_results.py "$work/bound-table2d" --compare "$work/bound-profile2d" --rtol 1e-9 >> "$diag" 2>&1 || status=1
report $status "2D: a bound_table over x and y, constant in y, = the bound_profile of its values (1e-9)" "$diag"
# bad bound_table lines: exit 3 naming the file, the line and what is wrong; with g, -g or a
# bound_profile; over z in a 2D scene; and a law that is not usable at one of its points
diag="$work/bound-table-keys.diag"; : > "$diag"; status=0
while IFS='|' read -r line regex; do
  { grep -v '^bound_table' edp/scenes/bound-table3d.scene; printf '%s\n' "$line"; } > "$work/key.scene"
  rm -rf "$work/key"; rc=0; solve -scene "$work/key.scene" -out "$work/key" > "$work/key.log" 2>&1 || rc=$?
  { [ "$rc" = 3 ] && grep -Eq "key.scene:[0-9]+: .*$regex" "$work/key.log" && [ ! -e "$work/key" ]; } \
    || { echo "'$line': exit $rc, expected 3 and /$regex/: $(cat "$work/key.log")" >> "$diag"; status=1; }
done <<'KEYS'
bound_table x 0 1 z 0 1|cannot read 'bound_table x 0 1 z 0 1': bound_table A a1 a2 ... B b1 b2 ... g G11
bound_table w 0 1 z 0 1 g 1 1 1 1|cannot read .*: bound_table A a1 a2
bound_table x 0 1 x 0 1 g 1 1 1 1|bound_table: its two axes must differ, got x twice
bound_table x 0 1 z g 1 1|bound_table: no point along z
bound_table x 0 1 z 0 1 g 0.05 0.05 0.05|bound_table: 2 points along x by 2 along z need 4 values of g, got 3
bound_table x 0 0 z 0 1 g 0.05 0.05 0.05 0.05|bound_table: x: point 2 \(0\) does not come after the one before
bound_table x 0 1 z 0 1 g 0.05 0.05 0 0.05|bound_table: every g must be > 0, got 0 at \(x, z\) = \(1, 0\)
bound_table x 0 1 z 0 nan g 0.05 0.05 0.05 0.05|bound_table: z: 'nan' is not a finite number
bound_table x 0 1 z 0 1 g 0.05 0.05 0.05 1e3|bound_table: its g go from 0.05 to 1000, more than a factor 10000 apart
KEYS
report $status "scene keys: bad bound_table lines refused with file, line and what is wrong (the form, the axes, the points, the count of g, g > 0, its range) (exit 3)" "$diag"
{ grep -v '^bound_table' edp/scenes/bound-table3d.scene; echo "bound_table x 0 1 z 0 1 g 1e307 1e307 1e308 1e308"; } > "$work/table-law.scene"
expect_failure "a law not finite at a point of a bound_table" 3 "table-law.scene:[0-9]+ \\(damping\\), .*table-law.scene:[0-9]+ \\(bound_table\\): the law of edp/plugins/contactlaw.hpp cannot be used: p is not finite .*at the bound_table's point \\(x, z\\) = \\(0, 0\\)" -scene "$work/table-law.scene"
{ cat edp/scenes/bound-table3d.scene; echo "g 0.05"; } > "$work/table-g.scene"
expect_failure "g and bound_table in one scene" 3 "table-g.scene:[0-9]+: g gives one bound for all of Gamma3, but the bound_table of line [0-9]+" -scene "$work/table-g.scene"
expect_failure "-g with a bound_table" 2 "option -g gives one bound for all of Gamma3, but .*bound-table3d.scene:[0-9]+ gives a bound_table" -scene bound-table3d -g 0.2
{ cat edp/scenes/bound-table3d.scene; echo "bound_profile 0 0.05 1 0.06"; } > "$work/table-profile.scene"
expect_failure "bound_profile and bound_table in one scene" 3 "table-profile.scene:[0-9]+: bound_table gives g over Gamma3, but the bound_profile of line [0-9]+ gives it too" -scene "$work/table-profile.scene"
{ grep -v '^bound_profile' edp/scenes/bound-profile.scene; echo "bound_table x 0 2 z 0 1 g 0.03 0.03 0.07 0.07"; } > "$work/table-z2d.scene"
expect_failure "a bound_table over z in a 2D scene" 3 "table-z2d.scene:[0-9]+: bound_table over z: a z value, but geometry rectangle is 2D" -scene "$work/table-z2d.scene"

# OUT/scene.scene holds the values the run used: with OUT/mesh.msh it repeats the run, command-
# line overrides included (outputs identical but for the lines that name the run's own files
# and the timings)
diag="$work/repeat.diag"; : > "$diag"; status=0
rm -rf "$work/repeat" "$work/repeat2"
solve -scene bound-profile -nx 33 -ny 16 -dt 0.05 -load 20 -mu 0.3 -r 0.5 -out "$work/repeat" >> "$diag" 2>&1 || status=1
solve -scene "$work/repeat/scene.scene" -mesh "$work/repeat/mesh.msh" -out "$work/repeat2" >> "$diag" 2>&1 || status=1
same_outputs "$work/repeat" "$work/repeat2" >> "$diag" || { echo "(these differ)" >> "$diag"; status=1; }
grep -q '^load 20$' "$work/repeat/scene.scene" && grep -q '^r 0.5$' "$work/repeat/scene.scene" && grep -q '^bound_profile ' "$work/repeat/scene.scene" \
  || { echo "scene.scene lacks the override or the profile" >> "$diag"; status=1; }
# options left at the table's default are not pinned (the fixed point's r follows -solver), nor is g beside a profile
! grep -q -E '^(tol|maxit|solver|g) ' "$work/repeat/scene.scene" || { echo "scene.scene pins a table default or g" >> "$diag"; status=1; }
report $status "a run repeats itself from its OUT/scene.scene and OUT/mesh.msh, command-line overrides included" "$diag"

# -adapt: an adapted mesh (pilot runs, adaptmesh) gives the paper's zones, in order along
# Gamma3, with x_B and x_C within 0.02 m of the fine adapted reference of docs/performance.md
# (0.480, 1.337), passes every physics check, is made again byte for byte, and repeats the
# run from OUT/mesh.msh; a budget it would exceed and a pilot that fails stop the run
diag="$work/adapt.diag"; : > "$diag"; status=0
rm -rf "$work/adapt" "$work/adapt2" "$work/adapt3"
solve -nx 16 -ny 8 -adapt 2 -out "$work/adapt" >> "$diag" 2>&1 || status=1
"$PYTHON" tests/check_results.py "$work/adapt" >> "$diag" 2>&1 || status=1
"$PYTHON" - "$work/adapt" >> "$diag" 2>&1 <<'PY' || status=1
import sys
sys.path.insert(0, "edp")
import runfiles
run = sys.argv[1]
summary = runfiles.read_summary(run)
rounds = [int(summary[f"adapt_round_{r}_vertices"]) for r in range(3)]
assert rounds[0] == 153 and rounds[2] == int(summary["vertices"]) and rounds[2] > 4 * rounds[0], rounds
assert summary["mesh_source"].startswith("adaptmesh, 2 rounds at adapt_err 1e-3, from gmsh"), summary["mesh_source"]
table = runfiles.read_table(run + "/contact.txt")
codes = table["zone"][table["x"].argsort()].astype(int)
sequence = [c for k, c in enumerate(codes) if k == 0 or c != codes[k - 1]]
assert list(sequence) == [0, 1, 3, 4], sequence                  # free, damped-slip, bound-slip, bound-stick
history = runfiles.read_table(run + "/contact_history.txt")
xb, xc = history["x_B"][-1], history["x_C"][-1]
assert abs(xb - 0.480) < 0.02 and abs(xc - 1.337) < 0.02, (xb, xc)
# the last pilot is the companion of the error estimates (docs/design.md, "Error estimates")
assert summary["error_estimate_source"].startswith(f"companion: the pilot run of round 2, on the mesh of round 1, {rounds[1]} vertices"), summary["error_estimate_source"]
assert all(summary.real(k) > 0 for k in ("error_estimate_v_L2", "error_estimate_normal_force", "error_estimate_x_B", "error_estimate_x_C")), summary
PY
solve -nx 16 -ny 8 -adapt 2 -out "$work/adapt2" >> "$diag" 2>&1 || status=1
cmp "$work/adapt/mesh.msh" "$work/adapt2/mesh.msh" >> "$diag" 2>&1 || status=1
solve -scene "$work/adapt/scene.scene" -mesh "$work/adapt/mesh.msh" -out "$work/adapt3" >> "$diag" 2>&1 || status=1
for f in contact.txt fields.txt history.txt contact_history.txt; do
  cmp -s <(grep -v '^#' "$work/adapt/$f") <(grep -v '^#' "$work/adapt3/$f") || { echo "$f differs when repeated from OUT/mesh.msh" >> "$diag"; status=1; }
done
grep -q "^mesh_source $work/adapt/mesh.msh (made by the run in $work/adapt/: adaptmesh, 2 rounds at adapt_err 1e-3, from gmsh " "$work/adapt3/summary.txt" \
  || { echo "the repeated run's mesh_source does not say how the mesh was made:"; grep mesh_source "$work/adapt3/summary.txt"; status=1; } >> "$diag"
rm -rf "$work/adapt4"
solve -nx 16 -ny 8 -adapt 1 -adapt_err 0.0005 -adapt_vertices 500 -out "$work/adapt4" > "$work/adapt4.err" 2>&1; code=$?
{ [ "$code" = 2 ] && grep -Eq "(option -adapt_err = 0.0005 would make a mesh of about [0-9]* vertices in round 1|the mesh of adaptation round 1 has [0-9]* vertices), more than -adapt_vertices 500" "$work/adapt4.err" \
  && [ ! -e "$work/adapt4" ] && ! ls -d "$work"/adapt4.partial.* > /dev/null 2>&1; } || { echo "budget: exit $code"; cat "$work/adapt4.err"; status=1; } >> "$diag"
solve -nx 16 -ny 8 -adapt 1 -maxit 1 -out "$work/adapt4" > "$work/adapt4.err" 2>&1; code=$?
{ [ "$code" = 4 ] && grep -q "error: -adapt: the pilot run of round 1 (on the mesh of round 0, 153 vertices) failed: step 1 (t = 0.01): the contact solver did not converge" "$work/adapt4.err" \
  && [ ! -e "$work/adapt4" ]; } || { echo "pilot failure: exit $code"; cat "$work/adapt4.err"; status=1; } >> "$diag"
# fewer steps than the five snapshots of a pilot: a frame a step, the last standing for the rest
solve -nx 16 -ny 8 -adapt 1 -T 0.02 -out "$work/adapt5" >> "$diag" 2>&1 || { echo "-adapt with 2 steps failed" >> "$diag"; status=1; }
report $status "-adapt 2: the paper's zones in order, x_B and x_C within 0.02 m, physics checks; the same mesh byte for byte when made again; repeated from OUT/mesh.msh, whose mesh_source still says how it was made; a vertex budget or a failed pilot stops the run (exit 2, 4) with no output; fewer steps than snapshots; the last pilot is the companion of the error estimates" "$diag"

# -adapt_zones H: the last round refined around the zone boundaries B and C the last pilot
# found at T. Gamma3's spacing at the run's x_B_estimate and x_C_estimate at most 3 H (the
# target is H + 0.1 d, read at the vertices of the mesh adapted, and the pilot places the
# points a little off the run's), and both estimates within 2e-3 m of the reference's (0.47949,
# 1.33614; the settings of docs/performance.md, "Zone boundaries", are within 8.2e-4); without
# -adapt, a note and no refinement
diag="$work/adapt-zones.diag"; : > "$diag"; status=0
rm -rf "$work/adapt-zones" "$work/adapt-zones0"
solve -nx 16 -ny 8 -adapt 2 -adapt_zones 2e-3 -out "$work/adapt-zones" >> "$diag" 2>&1 || status=1
"$PYTHON" tests/check_results.py "$work/adapt-zones" >> "$diag" 2>&1 || status=1
"$PYTHON" - "$work/adapt-zones" >> "$diag" 2>&1 <<'PY' || status=1
import sys
import numpy as np
sys.path.insert(0, "edp")
import runfiles
run = sys.argv[1]
summary = runfiles.read_summary(run)
assert "refined to 2e-3 around 2 zone boundaries" in summary["mesh_source"], summary["mesh_source"]
xs = np.sort(runfiles.read_table(run + "/contact.txt")["x"])          # Gamma3's nodes (y = 0)
for key, reference in (("x_B_estimate", 0.47949), ("x_C_estimate", 1.33614)):
    x0 = summary.real(key)
    k = np.searchsorted(xs, x0)
    spacing = xs[k] - xs[k - 1]
    assert 0 < k < len(xs) and spacing <= 3 * 2e-3, (key, x0, spacing)
    assert abs(x0 - reference) < 2e-3, (key, x0, reference)
PY
# an H no mesh can have refused before any pilot; an H coarser than the mesh already is at
# the points changes nothing (the same mesh, byte for byte)
rm -rf "$work/adapt-zones-tiny" "$work/adapt-zones-big" "$work/adapt-zones-none"
solve -nx 16 -ny 8 -adapt 1 -adapt_zones 1e-4 -T 0.1 -out "$work/adapt-zones-tiny" > "$work/adapt-zones-tiny.err" 2>&1; code=$?
{ [ "$code" = 2 ] && grep -q "^error: option -adapt_zones = 1e-4: triangles of that side would have an area of .*: give 0 (none) or at least 1.6e-4" "$work/adapt-zones-tiny.err" \
  && [ ! -e "$work/adapt-zones-tiny" ] && ! compgen -G "$work/adapt-zones-tiny.partial*" > /dev/null; } \
  || { echo "-adapt_zones 1e-4: exit $code"; cat "$work/adapt-zones-tiny.err"; status=1; } >> "$diag"
solve -nx 16 -ny 8 -adapt 1 -adapt_zones 1e6 -T 0.1 -out "$work/adapt-zones-big" > "$work/adapt-zones-big.err" 2>&1 || status=1
solve -nx 16 -ny 8 -adapt 1 -T 0.1 -out "$work/adapt-zones-none" >> "$diag" 2>&1 || status=1
cmp "$work/adapt-zones-big/mesh.msh" "$work/adapt-zones-none/mesh.msh" >> "$diag" 2>&1 || { echo "-adapt_zones 1e6 changed the mesh" >> "$diag"; status=1; }
grep -q "already finer than -adapt_zones 1e6" "$work/adapt-zones-big.err" || { echo "-adapt_zones 1e6: no note"; cat "$work/adapt-zones-big.err"; status=1; } >> "$diag"
# a round whose mesh grows far more than the last round's did (here to about 187,000 vertices
# from 2,740): predicted from a mesh at 0.05, refused by the budget before adaptmesh runs out
# of room (past it, adaptmesh stops unfinished or crashes)
rm -rf "$work/adapt-room"
solve -nx 8 -ny 4 -adapt 2 -adapt_err 1e-6 -T 0.02 -adapt_vertices 60000 -out "$work/adapt-room" > "$work/adapt-room.err" 2>&1; code=$?
{ [ "$code" = 2 ] && grep -Eq "more than -adapt_vertices 60000" "$work/adapt-room.err" && [ ! -e "$work/adapt-room" ]; } \
  || { echo "a mesh far above the last round's: exit $code"; cat "$work/adapt-room.err"; status=1; } >> "$diag"
solve -nx 16 -ny 8 -adapt_zones 1e-3 -T 0.05 -out "$work/adapt-zones0" > "$work/adapt-zones0.err" 2>&1 || status=1
grep -q "^note: option -adapt_zones applies to -adapt N, N >= 1; this run does not adapt its mesh" "$work/adapt-zones0.err" \
  || { echo "no note for -adapt_zones without -adapt:"; cat "$work/adapt-zones0.err"; status=1; } >> "$diag"
report $status "-adapt_zones 2e-3: Gamma3's spacing at x_B_estimate and x_C_estimate at most 3 H, both within 2e-3 m of the reference, physics checks; 1e-4 refused (exit 2, no output); 1e6 the same mesh as none; a mesh far above the last round's held to -adapt_vertices; without -adapt a note" "$diag"

# -snapshots N: x, y, u, v at every vertex at the first step at or after j T/N; the last frame
# is fields.txt's u and v; N above the steps gives every step
diag="$work/snapshots.diag"; : > "$diag"; status=0
solve -scene column -snapshots 3 -out "$work/snap" >> "$diag" 2>&1 || status=1
solve -scene column -T 0.2 -snapshots 50 -out "$work/snap2" >> "$diag" 2>&1 || status=1
"$PYTHON" - "$work/snap" "$work/snap2" >> "$diag" 2>&1 <<'PY' || status=1
import sys
import numpy as np
sys.path.insert(0, "edp")
import runfiles
run, every = sys.argv[1], sys.argv[2]
snap, fields = runfiles.read_table(run + "/snapshots.txt"), runfiles.read_table(run + "/fields.txt")
steps = int(runfiles.read_summary(run)["steps"])
assert snap.columns == "step t x y u_x u_y v_x v_y".split(), snap.columns
wanted = [next(n for n in range(1, steps + 1) if n * 3 >= j * steps) for j in (1, 2, 3)]
assert sorted(set(snap["step"].astype(int))) == wanted, (sorted(set(snap["step"])), wanted)
nv = len(fields["x"])
assert len(snap["step"]) == 3 * nv
last = slice(2 * nv, 3 * nv)
for c in ("x", "y", "u_x", "u_y", "v_x", "v_y"):
    assert np.array_equal(snap[c][last], fields[c]), c
small = runfiles.read_table(every + "/snapshots.txt")
assert sorted(set(small["step"].astype(int))) == list(range(1, int(runfiles.read_summary(every)["steps"]) + 1))
PY
report $status "-snapshots N: the first step at or after each j T/N, every vertex, the last frame equal to fields.txt; N above the steps gives every step" "$diag"

# the mesh cache follows the .geo's contents: a copy of the suite with a finer quarterdisk.geo
diag="$work/geo.diag"; : > "$diag"; status=0
copy="$work/geocopy"; rm -rf "$copy" && mkdir -p "$copy/meshes" && cp -r edp run.sh freefem++.pref "$copy/" && cp meshes/*.geo "$copy/meshes/"
(cd "$copy" && "${FREEFEM[@]}" edp/solve.edp -scene cylinder -nx 8 -dt 0.5 -T 0.5 -out before) >> "$diag" 2>&1 || status=1
sed -i 's|^h = R/nx;|h = R/nx/2;|' "$copy/meshes/quarterdisk.geo"
(cd "$copy" && "${FREEFEM[@]}" edp/solve.edp -scene cylinder -nx 8 -dt 0.5 -T 0.5 -out after) >> "$diag" 2>&1 || status=1
a=$(awk '$1 == "vertices" { print $2 }' "$copy/before/summary.txt" 2>/dev/null); b=$(awk '$1 == "vertices" { print $2 }' "$copy/after/summary.txt" 2>/dev/null)
[ -n "$a" ] && [ -n "$b" ] && [ "$b" -gt $((3 * a)) ] || { echo "vertices before $a, after halving h $b" >> "$diag"; status=1; }
# a .geo that includes another: not cached (its checksum does not cover the included file)
cp "$copy/meshes/quarterdisk.geo" "$copy/meshes/body.geo"
printf 'Include "body.geo";\n' > "$copy/meshes/outer.geo"
sed 's|^geometry .*|geometry outer|' edp/scenes/cylinder.scene > "$copy/outer.scene"
(cd "$copy" && "${FREEFEM[@]}" edp/solve.edp -scene outer.scene -nx 8 -dt 0.5 -T 0.5 -out inc1) >> "$diag" 2>&1 || status=1
sed -i 's|^h = R/nx/2;|h = R/nx;|' "$copy/meshes/body.geo"
(cd "$copy" && "${FREEFEM[@]}" edp/solve.edp -scene outer.scene -nx 8 -dt 0.5 -T 0.5 -out inc2) >> "$diag" 2>&1 || status=1
c=$(awk '$1 == "vertices" { print $2 }' "$copy/inc1/summary.txt" 2>/dev/null); d=$(awk '$1 == "vertices" { print $2 }' "$copy/inc2/summary.txt" 2>/dev/null)
[ -n "$c" ] && [ "$c" = "$b" ] && [ "$d" = "$a" ] || { echo "included .geo: vertices $c (expected $b), after editing the included file $d (expected $a)" >> "$diag"; status=1; }
report $status "the mesh cache follows the .geo's contents: halving h in quarterdisk.geo gives a new mesh, an included .geo too" "$diag"

# an oblique contact boundary: the paper's block turned by 30 degrees (tests/data/tilted.geo,
# clamped on its left side, the traction turned with it) gives the same contact values
diag="$work/tilted.diag"; : > "$diag"; status=0
for a in 0 30; do
  gmsh -2 -format msh22 -v 0 -setnumber a "$a" tests/data/tilted.geo -o "$work/tilted$a.msh" > /dev/null 2>&1 || status=1
  grep -v -E '^(dirichlet|traction|contact_normal|nx|ny) ' edp/scenes/paper.scene > "$work/tilted$a.scene"
  awk -v a="$a" 'BEGIN { r = a * atan2(0, -1) / 180; printf "dirichlet 4 xy\ntraction %.17g %.17g\n", sin(r), -cos(r) }' >> "$work/tilted$a.scene"
  solve -scene "$work/tilted$a.scene" -mesh "$work/tilted$a.msh" -dt 0.05 -out "$work/tilted$a" >> "$diag" 2>&1 || status=1
done
paste <(grep -v '^#' "$work/tilted0/contact.txt") <(grep -v '^#' "$work/tilted30/contact.txt") \
  | awk 'NF % 2 { bad = 1 } { h = NF / 2; for (i = 2; i <= 6; i++) { d = $i - $(i + h); if (d < 0) d = -d; if (d > m) m = d } }
         END { if (bad || NR == 0 || m > 1e-9) { print "turned by 30 degrees: contact values differ by " m; exit 1 } }' >> "$diag" || status=1
report $status "an oblique contact boundary: the block turned by 30 degrees has the same v_nu, v_tau, p_nu, lambda_nu, lambda_tau to 1e-9" "$diag"

# boundaries where a normal means nothing are refused (exit 3, no output)
gmsh -2 -format msh22 -v 0 tests/data/spike.geo -o "$work/spike.msh" > /dev/null 2>&1
grep -v -E '^(dirichlet|contact_normal) ' edp/scenes/paper.scene > "$work/spike.scene"
expect_failure "a contact boundary that turns by 150 degrees" 3 "turns by more than 120 degrees at \(1, 0\)" -scene "$work/spike.scene" -mesh "$work/spike.msh"
# a bad step is caught at the step, not only at T: g = 1e-12, within the velocities' round-off,
# breaks the constraint or the complementarity (relative to g) from step 1 on, and the
# message names the step of the largest violation and the first step above the tolerance
# (exit 9); round-off may instead keep a step's statuses from meeting their thresholds (1e-6
# g), which that step reports (exit 4). Either names the cause.
grep -v -E '^(g|load_history|T|dt) ' edp/scenes/column.scene > "$work/midrun.scene"
printf 'g 1e-12\nload_history 0 0 0.1 0.1 0.2 -1\nT 0.2\ndt 0.05\n' >> "$work/midrun.scene"
diag="$work/midrun.diag"; : > "$diag"; status=0
rm -rf "$work/midrun"
rc=0; solve -scene "$work/midrun.scene" -out "$work/midrun" > "$work/midrun.log" 2>&1 || rc=$?
{ [ "$rc" = 9 ] && grep -Eq "end-of-run check failed: (complementarity|constraint violation) .* at step [0-9] \(first above it at step [12]\): the bound g \(1e-12 at its smallest\) is within the round-off" "$work/midrun.log"; } \
  || { [ "$rc" = 4 ] && grep -Eq "^error: step [0-9] \(t = .*the bound g \(1e-12 at its smallest\) is within the round-off" "$work/midrun.log"; } \
  || { echo "exit $rc"; cat "$work/midrun.log"; status=1; } >> "$diag"
[ -e "$work/midrun" ] && { echo "results were written" >> "$diag"; status=1; }
report $status "refused: a check that fails before T (exit 9 at its step, or exit 4 at the step whose statuses round-off keeps from their thresholds)" "$diag"
grep -v -E '^g ' edp/scenes/column.scene > "$work/gprofile.scene"; printf 'bound_profile 0 0.02 1 0.05\n' >> "$work/gprofile.scene"
expect_failure "-g with a bound_profile" 2 "option -g gives one bound for all of Gamma3, but .*gprofile.scene:[0-9]+ gives a bound_profile" -scene "$work/gprofile.scene" -g 0.2
printf 'g 0.05\n' >> "$work/gprofile.scene"
expect_failure "g and bound_profile in one scene" 3 "gprofile.scene:[0-9]+: g gives one bound for all of Gamma3, but the bound_profile of line [0-9]+" -scene "$work/gprofile.scene"
# the same turn at a node whose two edges differ in length 17 times (the lumped normal alone would not see it)
gmsh -2 -format msh22 -v 0 -setnumber turn 150 -setnumber nr 20 -setnumber pr 1.15 tests/data/vee.geo -o "$work/vee.msh" > /dev/null 2>&1
expect_failure "a 150-degree turn between edges of unequal length" 3 "turns by more than 120 degrees at \(0, 0\)" -scene "$work/spike.scene" -mesh "$work/vee.msh" -T 0.1 -dt 0.05
gmsh -2 -format msh22 -v 0 -setnumber nx 10 tests/data/halfdisk.geo -o "$work/halfdisk.msh" > /dev/null 2>&1
grep -v -E '^(dirichlet|contact_normal|geometry) ' edp/scenes/cylinder.scene > "$work/halfdisk.scene"; echo "dirichlet 3 x" >> "$work/halfdisk.scene"
expect_failure "a contact node whose free component is not a normal velocity" 3 "has its x velocity fixed by a dirichlet line, and its normal .* is more than 60 degrees from the free y axis" -scene "$work/halfdisk.scene" -mesh "$work/halfdisk.msh"

# every new key is checked when the scene is read: exit 3 naming the file, line and key
diag="$work/keys.diag"; : > "$diag"; status=0
while IFS='|' read -r line regex; do
  grep -v -E "^(${line%% *}|damping) " edp/scenes/column.scene > "$work/key.scene"; printf '%s\n' "$line" >> "$work/key.scene"
  case "$line" in damping*) ;; *) echo "damping linear 50" >> "$work/key.scene" ;; esac
  rm -rf "$work/key"; rc=0; solve -scene "$work/key.scene" -out "$work/key" > "$work/key.log" 2>&1 || rc=$?
  { [ "$rc" = 3 ] && grep -Eq "key.scene:[0-9]+: .*$regex" "$work/key.log" && [ ! -e "$work/key" ]; } \
    || { echo "'$line': exit $rc, expected 3 and /$regex/: $(cat "$work/key.log")" >> "$diag"; status=1; }
done <<'KEYS'
load_history 0 0 1|load_history: .*pairs
load_history 0 0 1 1 0.5 2|load_history: point 3 \(0.5, 2\) does not come after the one before
load_history -1 0 1 1|load_history: the times must be >= 0
bound_profile 0 0.05 1 0|bound_profile: every g must be > 0
bound_profile 1 0.05 0 0.06|bound_profile: point 2 \(0, 0.06\) does not come after
damping table 0 0 0.1 2 0.2 1|damping table: p decreases at point 3 \(0.2, 1\)
damping table 0.1 0 0.2 1|damping table: the first point must be \(0, 0\)
damping table 0 0|damping table: at least two points
damping power 1000 0.5|ALPHA must be >= 1
damping cubic 3|damping linear C, damping power C ALPHA
body_force 0|body_force
initial_velocity 0 nan|initial_velocity
contact_normal 0 0|contact_normal
KEYS
grep -v '^damping ' edp/scenes/column.scene > "$work/key.scene"; printf 'damping linear 50\nload_history 0 0 1 1\nload_history 0 0 1 2\n' >> "$work/key.scene"
rc=0; solve -scene "$work/key.scene" -out "$work/key" > "$work/key.log" 2>&1 || rc=$?
[ "$rc" = 3 ] && grep -q "'load_history' is given a second time" "$work/key.log" || { echo "a repeated load_history: exit $rc" >> "$diag"; status=1; }
{ grep -v '^damping ' edp/scenes/column.scene; echo 'cnu 50'; } > "$work/key.scene"
rc=0; solve -scene "$work/key.scene" -out "$work/key" > "$work/key.log" 2>&1 || rc=$?
[ "$rc" = 3 ] && grep -q "'cnu' is not a key of a scene: write 'damping linear C'" "$work/key.log" || { echo "cnu in a scene: exit $rc" >> "$diag"; status=1; }
rc=0; solve -scene tests/scenes/column-table.scene -cnu 30 -out "$work/key" > "$work/key.log" 2>&1 || rc=$?
[ "$rc" = 2 ] && grep -q "option -cnu gives C of damping linear or power, but the damping of .* is a table" "$work/key.log" || { echo "-cnu with a table: exit $rc" >> "$diag"; status=1; }
report $status "scene keys: bad load_history, bound_profile, damping, body_force, initial_velocity, contact_normal refused with file, line and key (exit 3); repeats, the key cnu (one spelling: damping linear C), -cnu with a table refused" "$diag"

