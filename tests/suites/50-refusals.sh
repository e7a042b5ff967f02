# Runs that must fail: exit code, message, and no results.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
# ---- runs that must fail: exit code, message, and no results
expect_failure "unknown option" 2 "unknown option '-foo'" -foo 1
expect_failure "not an option" 2 "expected an option -name, got '12'" 12
expect_failure "option without value" 2 "option -dt needs a value" -dt
expect_failure "repeated option" 2 "option -nx is given twice" -nx 8 -nx 9
expect_failure "real not a number" 2 "option -dt must be a real number >0, got 'abc'" -dt abc
expect_failure "real half a number" 2 "option -E must be a real number [^,]*, got '1e'" -E 1e
expect_failure "a 3D mesh for a 2D scene" 3 "option -mesh: 'tests/data/tetrahedron.msh' is a 3D mesh, but the scene .*paper.scene is 2D \\(geometry rectangle, vectors of two components" -mesh tests/data/tetrahedron.msh
expect_failure "a 2D mesh for a 3D scene" 3 "option -mesh: '.*mesh.msh' is a 2D mesh \\(it has no tetrahedra: a 3D mesh needs a Physical Volume.*the scene .*column3d.scene is 3D" -scene column3d -mesh "$work/paper-coarse-original/mesh.msh"
"$PYTHON" tests/bad_meshes3d.py "$work/column3d/mesh.msh" "$work/bad-meshes3d" > /dev/null 2>&1
expect_failure "a folded 3D mesh" 3 "lie on the same side of their common face: the mesh is folded, tangled or overlapping" -scene column3d -mesh "$work/bad-meshes3d/fold.msh"
expect_failure "two 3D nodes at one point" 3 "are at the same point \\(0, 0, 0\\): a crack or duplicated nodes" -scene column3d -mesh "$work/bad-meshes3d/coincident.msh"
expect_failure "a cached mesh without the scene's Dirichlet label" 3 "the scene's dirichlet label 7 is not a physical surface of the mesh" -scene tests/data/column3d-label7.scene
expect_failure "-nz with -mesh" 2 "options -nx, -ny and -nz size the scene's structured mesh; they do not apply with -mesh" -scene column3d -mesh "$work/column3d/mesh.msh" -nz 3
expect_failure "a 3D mesh without the scene's labels" 3 "'tests/data/tetrahedron.msh': the scene's dirichlet label 5 is not a physical surface of the mesh" -scene column3d -mesh tests/data/tetrahedron.msh
expect_failure "a z value in a scene of a 2D geometry" 3 "traction with a z component: a z value, but geometry rectangle is 2D" -scene tests/data/z-in-2d.scene
expect_failure "-plane for a 3D body" 2 "option -plane: plane stress or strain is a 2D model; geometry box is a 3D body" -scene column3d -plane strain
expect_failure "-nz for a 2D body" 2 "option -nz: cells along z, for a 3D body; geometry rectangle is 2D" -nz 3
expect_failure "-adapt for a 3D body" 2 "option -adapt: mesh adaptation is 2D only" -scene column3d -adapt 1
expect_failure "-Ddimension=3 given by the user" 2 "the argument '-Ddimension=3' would be read by FreeFem\+\+ as a macro definition" -Ddimension=3
expect_failure "a choice out of its list" 2 "option -plane = 'Strain' is not one of stress\|strain" -plane Strain
expect_failure "real overflows" 2 "option -load = 1e999 is not a finite number" -load 1e999
expect_failure "integer not whole" 2 "option -nx must be a whole number >=1 and <=4096, got '1.5'" -nx 1.5
expect_failure "integer too large" 2 "option -ny = 5000 is out of range: it must be <= 4096" -ny 5000
expect_failure "nx < 1" 2 "option -nx = 0 is out of range: it must be >= 1" -nx 0
expect_failure "T <= 0" 2 "option -T = -1 is out of range: it must be > 0" -T -1
expect_failure "dt <= 0" 2 "option -dt = 0 is out of range: it must be > 0" -dt 0
expect_failure "dt > T" 2 "option -dt = 2 is out of range: it must be <= T = 1" -dt 2
expect_failure "T/dt not whole" 2 "option -dt = 0.3 does not divide T = 1" -dt 0.3
expect_failure "too many steps" 2 "ask for more than 1e6 steps" -dt 1e-7
expect_failure "empty value" 2 "option -mu has an empty value" -mu ''
expect_failure "an option as a value" 2 "option -nx needs a value, got the option '-ny'" -nx -ny 3
# control characters and line separators break readers of the outputs (summary.txt echoes the values)
separator="holds a control character or a line separator"
expect_failure "a vertical tab in -mesh" 2 "option -mesh $separator" -mesh $'a\vb.msh'
expect_failure "a form feed in -scene" 2 "option -scene $separator" -scene $'paper\f'
expect_failure "a record separator (0x1e) in -out" 2 "option -out $separator" -out "$work/a"$'\x1e'b
expect_failure "U+0085 (next line) in -mesh" 2 "option -mesh $separator" -mesh $'a\xc2\x85b.msh'
expect_failure "U+2028 (line separator) in -out" 2 "option -out $separator" -out "$work/a"$'\xe2\x80\xa8'b
grep -v '^#' edp/scenes/column.scene > "$work/separator.scene"; printf 'body_force 0 a\034b\n' >> "$work/separator.scene"
expect_failure "a file separator (0x1c) in a scene's value" 3 "separator.scene:[0-9]+: body_force: value 2 $separator" -scene "$work/separator.scene"
status=0
printf 'a\034b\342\200\250c\n# d\302\205e\f\n' > "$work/separators.txt"
"$PYTHON" -c 'import sys; sys.path.insert(0, "edp"); import runfiles; lines = runfiles.read_lines(sys.argv[1]); assert lines == ["a\x1cb\u2028c", "# d\x85e\f"], lines' \
  "$work/separators.txt" > "$work/separators.diag" 2>&1 || status=1
report $status "edp/runfiles.py reads lines split at line feeds only, not at form feeds, 0x1c or U+2028" "$work/separators.diag"
expect_failure "a scene name with a quote and a semicolon" 2 "option -scene = 'x'y; ls': no readable scene file" -scene "x'y; ls"
expect_failure "tol below round-off" 2 "option -tol = 1e-15 is out of range: it must be >= 1e-13" -tol 1e-15
expect_failure "output named ." 2 "option -out = '.' is not a usable folder name" -out .
mkdir -p "$work/userfolder" && touch "$work/userfolder/thesis.tex"
expect_failure "output folder of the user" 7 "does not hold results of this suite" -out "$work/userfolder"
status=0; [ -f "$work/userfolder/thesis.tex" ] || status=1
report $status "a folder of the user's given as -out is left as it was"
printf '$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n' > "$work/truncated.msh"
expect_failure "truncated mesh file" 3 "declares 3 nodes but holds|truncated file" -mesh "$work/truncated.msh"
expect_failure "rho <= 0" 2 "option -rho = 0 is out of range: it must be > 0" -rho 0
expect_failure "E <= 0" 2 "option -E = -100 is out of range: it must be > 0" -E -100
expect_failure "nu >= 0.5" 2 "option -nu = 0.5 is out of range: it must be < 0.5" -nu 0.5
expect_failure "nu < 0" 2 "option -nu = -0.1 is out of range: it must be >= 0" -nu -0.1
expect_failure "muv < 0" 2 "option -muv = -1 is out of range: it must be >= 0" -muv -1
expect_failure "eta < 0" 2 "option -eta = -0.5 is out of range: it must be >= 0" -eta -0.5
expect_failure "cnu < 0" 2 "option -cnu = -50 is out of range: it must be >= 0" -cnu -50
expect_failure "g <= 0" 2 "option -g = 0 is out of range: it must be > 0" -g 0
expect_failure "mu < 0" 2 "option -mu = -0.4 is out of range: it must be >= 0" -mu -0.4
expect_failure "eps <= 0" 2 "option -eps = 0 is out of range: it must be > 0" -eps 0
expect_failure "tol <= 0" 2 "option -tol = -1e-10 is out of range: it must be >= 1e-13" -tol -1e-10
expect_failure "tol too large for the checks" 2 "option -tol = 1 is out of range: it must be <= 1e-4" -tol 1
expect_failure "maxit < 1" 2 "option -maxit = 0 is out of range: it must be >= 1" -maxit 0
expect_failure "r <= 0" 2 "option -r = 0 is out of range: it must be >= 1e-8" -r 0
expect_failure "r above 1e8" 2 "option -r = 1e12 is out of range: it must be <= 1e8" -r 1e12
expect_failure "unknown problem" 2 "option -problem = 'dual' is not one of original\|penalty" -problem dual
expect_failure "unknown solver" 2 "option -solver = 'cg' is not one of newton.fixedpoint.full" -solver cg
expect_failure "unknown safeguard" 2 "option -safeguard = 'maybe' is not one of on.off" -safeguard maybe
expect_failure "unknown kernel" 2 "option -kernel = 'gpu' is not one of compiled.script" -kernel gpu
expect_failure "script kernel with another solver" 2 "option -kernel script applies to -solver newton only" -kernel script -solver full
expect_failure "unknown umfpackfloor" 2 "option -umfpackfloor = 'yes' is not one of on.off" -umfpackfloor yes
expect_failure "unknown penalty form" 2 "option -penaltyform = 'soft' is not one of compliant.literal" -penaltyform soft
expect_failure "unknown scene" 2 "option -scene = 'moon'" -scene moon
expect_failure "scene file with a bad line" 3 "bad.scene:5: unknown key 'gravity'; the keys of a scene: " -scene tests/data/bad.scene
grep -v '^nx ' edp/scenes/column.scene > "$work/nx0.scene"; echo "nx 0" >> "$work/nx0.scene"
expect_failure "an option out of range in a scene file" 3 "nx0.scene:[0-9]+: option -nx = 0 is out of range: it must be >= 1 \(a value of the scene file\)" -scene "$work/nx0.scene"
# the option table edp/options.txt is checked when it is read: a copy of edp/ with one line changed
table_refused() { # table_refused NAME OLD NEW REGEX
  local name="$1" old="$2" new="$3" regex="$4" diag="$work/table.diag" status=0 rc=0 copy="$work/table"
  rm -rf "$copy" "$work/table-out" && mkdir -p "$copy/meshes" && cp -r edp "$copy/" && cp meshes/*.geo "$copy/meshes/" && rm -rf "$copy/edp/plugins/build"
  OLD="$old" NEW="$new" "$PYTHON" -c 'import os, sys; p = sys.argv[1]; s = open(p).read(); o, n = os.environ["OLD"], os.environ["NEW"]
assert o in s, "not found: " + o; open(p, "w").write(s.replace(o, n, 1))' "$copy/edp/options.txt" > "$diag" 2>&1 || status=1
  "${FREEFEM[@]}" "$copy/edp/solve.edp" -out "$work/table-out" >> "$diag" 2>&1 || rc=$?
  [ "$rc" = 3 ] || { echo "exit code $rc, expected 3" >> "$diag"; status=1; }
  grep -Eq "$regex" "$diag" || { echo "message does not match /$regex/" >> "$diag"; status=1; }
  { [ -e "$work/table-out" ] || ls -d "$work"/table-out.partial* > /dev/null 2>&1; } && { echo "results were written" >> "$diag"; status=1; }
  report $status "refused: an option table with $name" "$diag"
}
table_refused "a missing option" "tol           real" "tolerance     real" "options.txt has no option -tol, which the scripts need"
table_refused "a malformed range" "nx            int     >=1,<=4096" "nx            int     >=1," "options.txt:[0-9]+: the range of -nx must read"
table_refused "an unknown type" "problem       choice" "problem       choise" "options.txt:[0-9]+: type 'choise' of -problem is not one of"
table_refused "a rule on an unknown option" "when solver=fixedpoint maxit 500" "when solvr=fixedpoint maxit 500" "options.txt:[0-9]+: the rule names an option that is not in the table"
table_refused "a default out of its range" ">=1e-13,<=1e-4      1e-10" ">=1e-13,<=1e-4      1e-20" "options.txt:[0-9]+: the default of -tol"
expect_failure "missing mesh file" 3 "cannot read the file" -mesh "$work/no-such.msh"
printf '$MeshFormat\n4.1 0 8\n$EndMeshFormat\n' > "$work/v41.msh"
expect_failure "MSH 4.1 mesh" 3 "gmsh format 4.1, not 2.2: re-export it with: gmsh -2 -format msh22" -mesh "$work/v41.msh"
printf 'hello\n' > "$work/text.msh"
expect_failure "not a mesh file" 3 "not a gmsh mesh file" -mesh "$work/text.msh"
mesh_of() { gmsh -2 -format msh22 -v 0 -setnumber nx 4 -setnumber ny 2 "tests/data/$1.geo" -o "$work/$1.msh" > /dev/null 2>&1; }
mesh_of unlabelled
expect_failure "mesh without physical curves" 3 "no boundary line with physical tag 1 3 \(Physical Curve 1 contact, 3 traction are required\)" -mesh "$work/unlabelled.msh"
mesh_of flipped
expect_failure "contact boundary on the wrong side" 3 "the scene expects the outward normal \(0, -1\)" -mesh "$work/flipped.msh"
expect_failure "mesh without triangles" 3 "no triangle" -mesh tests/data/no-triangle.msh
expect_failure "zero-area triangle" 3 "has zero area" -mesh tests/data/zero-area.msh
expect_failure "output is a file" 7 "exists and is not a folder" -out tests/cases.txt
expect_failure "output not writable" 7 "cannot create the output folder" -out /proc/no-such-folder
expect_failure "no convergence (maxit 1)" 4 "step 1 \(t = .*\): the contact solver did not converge after 1 iterations .*residual" "${coarse[@]}" -maxit 1

