# edp/compare.edp and reproducibility.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
# ---- edp/compare.edp (the benchmark's errors): a run against itself is 0, against a finer mesh small
diag="$work/compare.diag"; : > "$diag"; status=0
rm -rf "$work/cmp-a" "$work/cmp-b"
solve -nx 16 -ny 8 -dt 0.1 -out "$work/cmp-a" >> "$diag" 2>&1 || status=1
solve -nx 32 -ny 16 -dt 0.1 -out "$work/cmp-b" >> "$diag" 2>&1 || status=1
self=$("${FREEFEM[@]}" edp/compare.edp -a "$work/cmp-a" -ref "$work/cmp-a" 2>> "$diag")
other=$("${FREEFEM[@]}" edp/compare.edp -a "$work/cmp-a" -ref "$work/cmp-b" 2>> "$diag")
echo "self: $self; against 32x16: $other" >> "$diag"
awk '{ exit !($1 == "error_L2" && $2 == 0 && $6 == 0) }' <<< "$self" || status=1
awk '{ exit !($1 == "error_L2" && $2 > 0 && $2 < 0.1 * $4) }' <<< "$other" || status=1
rm -rf "$work/cmp-c"
solve -nx 16 -ny 8 -dt 0.1 -plane strain -out "$work/cmp-c" >> "$diag" 2>&1 || status=1
"${FREEFEM[@]}" edp/compare.edp -a "$work/cmp-c" -ref "$work/cmp-b" > "$work/cmp-c.out" 2>&1; code=$?
{ [ "$code" = 2 ] && grep -q "the runs differ in -plane" "$work/cmp-c.out"; } || { echo "a plane-strain run against a plane-stress one: exit $code"; cat "$work/cmp-c.out"; status=1; } >> "$diag"
report $status "edp/compare.edp: a run against itself gives 0, against a finer mesh a small error, against another body (-plane strain) refused" "$diag"

# compare_accepts A REF CONDITION: compare.edp gives exit 0 and one line "error_L2 E norm_L2 N
# error_gamma3 G" for which the awk CONDITION on E ($2), N ($4), G ($6) holds
compare_accepts() {
  local out code
  out=$("${FREEFEM[@]}" edp/compare.edp -a "$1" -ref "$2" 2>> "$diag"); code=$?
  echo "$1 against $2: exit $code: $out" >> "$diag"
  [ "$code" = 0 ] && awk "NR == 1 && \$1 == \"error_L2\" && \$3 == \"norm_L2\" && \$5 == \"error_gamma3\" { ok = $3 } END { exit !(ok && NR == 1) }" <<< "$out"
}
# compare_refuses CODE PATTERN A REF: compare.edp exits CODE, prints nothing on stdout (the
# benchmark reads it) and one "error: compare.edp: ..." line on stderr matching the extended
# regular expression PATTERN
compare_refuses() {
  local code
  "${FREEFEM[@]}" edp/compare.edp -a "$3" -ref "$4" > "$work/cmp.stdout" 2> "$work/cmp.stderr"; code=$?
  if [ "$code" = "$1" ] && [ ! -s "$work/cmp.stdout" ] && [ "$(wc -l < "$work/cmp.stderr")" = 1 ] \
     && grep -qE -- "^error: compare\.edp: $2" "$work/cmp.stderr"; then return 0; fi
  { echo "$3 against $4: exit $code (expected $1 and /$2/)"; cat "$work/cmp.stdout" "$work/cmp.stderr"; } >> "$diag"
  return 1
}
# a variant of the run cmp-a: its effective scene edited by sed (SCRIPT) and run again
cmp_variant() {
  local name="$1" script="$2"; shift 2
  rm -rf "$work/$name"
  sed -e "$script" "$work/cmp-a/scene.scene" > "$work/$name.scene"
  solve -scene "$work/$name.scene" "$@" -out "$work/$name" >> "$diag" 2>&1 || { echo "the variant $name did not run" >> "$diag"; status=1; }
}

# what the benchmark compares (plots/bench.sh): another time step, a -mesh (here the
# reference's own mesh) with the penalty problem at another eps, -tol, -solver full, -r, an
# explicit default (-plane stress), an adapted mesh as the run and as the reference; and a
# coarse mesh of the curved cylinder against a fine one (the domain check's tolerance)
diag="$work/compare-accepts.diag"; : > "$diag"; status=0
rm -rf "$work/cmp-dt" "$work/cmp-mesh" "$work/cmp-full" "$work/cmp-adapt" "$work/cmp-cyl4" "$work/cmp-cyl16"
solve -nx 16 -ny 8 -dt 0.05 -out "$work/cmp-dt" >> "$diag" 2>&1 || status=1
solve -mesh "$work/cmp-b/mesh.msh" -dt 0.1 -problem penalty -eps 1e-3 -out "$work/cmp-mesh" >> "$diag" 2>&1 || status=1
solve -nx 16 -ny 8 -dt 0.1 -solver full -tol 1e-6 -r 10 -plane stress -out "$work/cmp-full" >> "$diag" 2>&1 || status=1
solve -nx 16 -ny 8 -dt 0.1 -adapt 1 -adapt_err 4e-3 -out "$work/cmp-adapt" >> "$diag" 2>&1 || status=1
solve -scene cylinder -nx 4 -ny 4 -T 0.1 -dt 0.05 -out "$work/cmp-cyl4" >> "$diag" 2>&1 || status=1
solve -scene cylinder -nx 16 -ny 16 -T 0.1 -dt 0.05 -out "$work/cmp-cyl16" >> "$diag" 2>&1 || status=1
compare_accepts "$work/cmp-dt" "$work/cmp-a" '$2 > 0 && $2 < 0.1 * $4 && $6 < 0.005' || status=1
compare_accepts "$work/cmp-mesh" "$work/cmp-b" '$2 > 0 && $2 < 0.1 * $4 && $6 < 0.025' || status=1   # eps 1e-3: v_nu passes g by eps lambda_nu
compare_accepts "$work/cmp-full" "$work/cmp-b" '$2 > 0 && $2 < 0.1 * $4 && $6 < 0.005' || status=1
compare_accepts "$work/cmp-a" "$work/cmp-adapt" '$2 > 0 && $2 < 0.1 * $4 && $6 < 0.005' || status=1
compare_accepts "$work/cmp-adapt" "$work/cmp-b" '$2 > 0 && $2 < 0.1 * $4 && $6 < 0.005' || status=1
compare_accepts "$work/cmp-cyl4" "$work/cmp-cyl16" '$2 > 0 && $2 < 0.1 * $4 && $6 > 0 && $6 < 0.005' || status=1
# contact_normal checks the mesh's normals; the same run with 'auto' is the same model (0 apart)
rm -rf "$work/cmp-auto"
sed 's/^contact_normal .*/contact_normal auto/' "$work/cmp-a/scene.scene" > "$work/cmp-auto.scene"
solve -scene "$work/cmp-auto.scene" -out "$work/cmp-auto" >> "$diag" 2>&1 || status=1
compare_accepts "$work/cmp-auto" "$work/cmp-a" '$2 == 0 && $6 == 0' || status=1
report $status "edp/compare.edp accepts what the benchmark compares (-dt, -mesh, penalty at another eps, -tol, -solver full, -adapt), a coarse against a fine mesh of a curved body, contact_normal auto against given" "$diag"

# another model: refused with exit 2, the key, both values (a long one cut with "...") and
# both folders named
diag="$work/compare-model.diag"; : > "$diag"; status=0
cmp_variant cmp-lx 's/^Lx 2$/Lx 3/'
cmp_variant cmp-zero '$a load_history 0 0 1 0'
cmp_variant cmp-oblique 's/^traction 0 -1$/traction 1 -1/'
cmp_variant cmp-power 's/^damping linear 50$/damping power 1000 2/'
cmp_variant cmp-profile "/^g /d; \$a bound_profile $(awk 'BEGIN { for (i = 0; i <= 20; i++) printf "%g %g ", i/10, 0.04 + i/1000 }')"
cmp_variant cmp-square 's/^Lx 2$/Lx 1/; s/^nx 16$/nx 8/'
rm -rf "$work/cmp-domain" "$work/cmp-cylsquare"
solve -mesh "$work/cmp-lx/mesh.msh" -dt 0.1 -out "$work/cmp-domain" >> "$diag" 2>&1 || status=1   # the paper scene on a body 3 long
solve -scene cylinder -mesh "$work/cmp-square/mesh.msh" -T 0.1 -dt 0.05 -out "$work/cmp-cylsquare" >> "$diag" 2>&1 || status=1   # the quarter disk's box, not its area
a="$work/cmp-a"; b="$work/cmp-b"
compare_refuses 2 "the runs differ in Lx \\($work/cmp-lx: '3', $b: '2'\\): they do not solve the same problem" "$work/cmp-lx" "$b" || status=1
compare_refuses 2 "the runs differ in load_history \\($work/cmp-zero: '0 0 1 0', $b: no load_history line\\)" "$work/cmp-zero" "$b" || status=1
compare_refuses 2 "the runs differ in load_history \\($a: no load_history line, $work/cmp-zero: '0 0 1 0'\\)" "$a" "$work/cmp-zero" || status=1
compare_refuses 2 "the runs differ in traction \\($work/cmp-oblique: '0\\.7071[0-9]* -0\\.7071[0-9]*', $b: '0 -1'\\)" "$work/cmp-oblique" "$b" || status=1
compare_refuses 2 "the runs differ in damping \\($work/cmp-power: 'power 1000 2', $b: 'linear 50'\\)" "$work/cmp-power" "$b" || status=1
cmp_variant cmp-two 's/^Lx 2$/Lx 3/; s/^traction 0 -1$/traction 1 -1/'
compare_refuses 2 "the runs differ in Lx \\($work/cmp-two: '3', $b: '2'\\); traction \\($work/cmp-two: '0\\.7071[0-9]* -0\\.7071[0-9]*', $b: '0 -1'\\): they" "$work/cmp-two" "$b" || status=1
compare_refuses 2 "the runs differ in bound_profile \\($work/cmp-profile: '0 0\\.04[^']{71}\\.\\.\\.', $b: no bound_profile line\\)" "$work/cmp-profile" "$b" || status=1
domain="the runs' meshes do not cover the same domain with the same boundary labels: the boundary labelled"
compare_refuses 2 "$domain 1 of $work/cmp-domain/mesh\\.msh passes through \\(2\\.[0-9]*, 0\\), 0\\.[0-9]* away from $b/mesh\\.msh's boundary of that label" "$work/cmp-domain" "$b" || status=1
compare_refuses 2 "$domain [0-9] of $work/cmp-cylsquare/mesh\\.msh passes through .* away from $work/cmp-cyl16/mesh\\.msh's boundary of that label" "$work/cmp-cylsquare" "$work/cmp-cyl16" || status=1
# the same rectangle with its supports on the other sides (x -> 2 - x), and a one-cell mesh of
# the body against a mesh of one 1.5 times larger (a coarse mesh must not widen the tolerance)
awk '/^\$Nodes/ { n = 1; print; next } /^\$EndNodes/ { n = 0 } n && NF == 4 { $2 = 2 - $2 } { print }' "$work/cmp-a/mesh.msh" > "$work/cmp-mirror.msh"
awk '/^\$Nodes/ { n = 1; print; next } /^\$EndNodes/ { n = 0 } n && NF == 4 { $2 *= 1.5; $3 *= 1.5 } { print }' "$work/cmp-a/mesh.msh" > "$work/cmp-large.msh"
rm -rf "$work/cmp-mirror" "$work/cmp-large" "$work/cmp-one"
solve -mesh "$work/cmp-mirror.msh" -dt 0.1 -out "$work/cmp-mirror" >> "$diag" 2>&1 || status=1
solve -mesh "$work/cmp-large.msh" -dt 0.1 -out "$work/cmp-large" >> "$diag" 2>&1 || status=1
solve -nx 1 -ny 1 -dt 0.1 -out "$work/cmp-one" >> "$diag" 2>&1 || status=1
compare_refuses 2 "$domain [24] of $work/cmp-mirror/mesh\\.msh passes through \\([02], 0\\.[0-9]*\\), 2 away from $work/cmp-a/mesh\\.msh's boundary of that label" "$work/cmp-mirror" "$work/cmp-a" || status=1
compare_refuses 2 "$domain [0-9] of $work/cmp-one/mesh\\.msh passes through .* away from $work/cmp-large/mesh\\.msh's boundary of that label" "$work/cmp-one" "$work/cmp-large" || status=1
report $status "edp/compare.edp refuses runs of another model (exit 2, every key, both values and both folders): Lx, a zero load_history, the traction direction, the damping family, a bound_profile (cut at 80 characters), bodies of other domains or supports given with -mesh (a longer box, another area, supports on the other sides, a one-cell mesh against a larger body)" "$diag"

# 3D: the slab (slab3d) on two meshes of tetrahedra; another depth Lz, and a 2D run, refused
diag="$work/compare-3d.diag"; : > "$diag"; status=0
rm -rf "$work/cmp-3a" "$work/cmp-3b" "$work/cmp-3lz"
solve -scene slab3d -nx 8 -ny 4 -nz 1 -T 0.1 -dt 0.05 -out "$work/cmp-3a" >> "$diag" 2>&1 || status=1
solve -scene slab3d -nx 16 -ny 8 -nz 2 -T 0.1 -dt 0.05 -out "$work/cmp-3b" >> "$diag" 2>&1 || status=1
sed 's/^Lz 0\.25$/Lz 0.5/' "$work/cmp-3a/scene.scene" > "$work/cmp-3lz.scene"
solve -scene "$work/cmp-3lz.scene" -out "$work/cmp-3lz" >> "$diag" 2>&1 || status=1
compare_accepts "$work/cmp-3a" "$work/cmp-3a" '$2 <= 1e-12 * $4 && $4 > 0 && $6 <= 1e-12' || status=1
compare_accepts "$work/cmp-3a" "$work/cmp-3b" '$2 > 0 && $2 < 0.1 * $4 && $6 > 0 && $6 < 0.005' || status=1
compare_refuses 2 "the runs differ in Lz \\($work/cmp-3lz: '0\\.5', $work/cmp-3b: '0\\.25'\\)" "$work/cmp-3lz" "$work/cmp-3b" || status=1
compare_refuses 2 "a 3D run \\($work/cmp-3a\\) and a 2D run \\($b\\): they do not solve the same problem" "$work/cmp-3a" "$b" || status=1
report $status "edp/compare.edp compares 3D runs (itself 0, a finer mesh a small error) and refuses another Lz and a 2D run against a 3D one" "$diag"

# damaged runs: exit 3 naming the file and line (exit 2 for a folder without its files)
diag="$work/compare-damaged.diag"; : > "$diag"; status=0
damaged() {   # damaged NAME RUN FILE COMMAND...: a copy of RUN whose FILE is COMMAND's output on RUN's
  local name="$1" run="$2" file="$3"; shift 3
  rm -rf "$work/$name"; cp -r "$work/$run" "$work/$name"
  "$@" "$work/$run/$file" > "$work/$name/$file"
}
damaged cmp-cut cmp-a fields.txt head -c -30
damaged cmp-short cmp-a fields.txt head -n -3
damaged cmp-nan cmp-a fields.txt awk 'NR == 60 { $5 = "nan" } { print }'
damaged cmp-inf cmp-a fields.txt awk 'NR == 61 { $6 = "-inf" } { print }'
damaged cmp-fewer cmp-a fields.txt awk 'NR == 62 { NF = 6 } { print }'
damaged cmp-longer cmp-a fields.txt awk '{ print } END { print "1 2 3 4 5 6 7" }'
moved=$(( $(grep -c '^#' "$work/cmp-a/fields.txt") + 36 ))   # the 36th vertex, at (0.75, 1), whatever the header's length
damaged cmp-moved cmp-a fields.txt awk -v row="$moved" 'NR == row { t = $1; $1 = $2; $2 = t } { print }'
damaged cmp-badmesh cmp-a mesh.msh head -c 2000
damaged cmp-clockwise cmp-a mesh.msh awk '/^\$Elements/ { e = 1 } e && $2 == 2 && NF >= 8 { t = $NF; $NF = $(NF - 1); $(NF - 1) = t } { print }'
damaged cmp-3nan cmp-3a fields.txt awk '/^# x / { h = NR } h && NR == h + 5 { $10 = "nan" } { print }'
rm -rf "$work/cmp-noscene"; cp -r "$work/cmp-a" "$work/cmp-noscene"; rm "$work/cmp-noscene/scene.scene"
rm -rf "$work/cmp-nomesh"; cp -r "$work/cmp-a" "$work/cmp-nomesh"; rm "$work/cmp-nomesh/mesh.msh"
rows=$(grep -vc '^#' "$work/cmp-a/fields.txt"); lines=$(wc -l < "$work/cmp-a/fields.txt")
compare_refuses 3 "$work/cmp-cut/fields\\.txt:$lines: the line has no line end \\(a truncated file\\?\\)" "$work/cmp-cut" "$b" || status=1
compare_refuses 3 "$work/cmp-short/fields\\.txt ends at line $((lines - 3)): $((rows - 3)) rows for the $rows vertices of the mesh" "$work/cmp-short" "$b" || status=1
compare_refuses 3 "$work/cmp-nan/fields\\.txt:60: v_x = 'nan' is not a finite number" "$b" "$work/cmp-nan" || status=1
compare_refuses 3 "$work/cmp-inf/fields\\.txt:61: v_y = '-inf' is not a finite number" "$work/cmp-inf" "$b" || status=1
compare_refuses 3 "$work/cmp-fewer/fields\\.txt:62: not 7 numbers separated by single spaces" "$work/cmp-fewer" "$b" || status=1
compare_refuses 3 "$work/cmp-longer/fields\\.txt:$((lines + 1)): a line more than the $rows vertices of the mesh" "$work/cmp-longer" "$b" || status=1
compare_refuses 3 "$work/cmp-moved/fields\\.txt:$moved: a row at \\(1, 0\\.75\\), but vertex [0-9]+ of $work/cmp-moved/mesh\\.msh is at \\(0\\.75, 1\\)" "$work/cmp-moved" "$b" || status=1
compare_refuses 3 "$work/cmp-badmesh/mesh\\.msh is no readable gmsh MSH 2\\.2 mesh" "$work/cmp-badmesh" "$b" || status=1
compare_refuses 3 "$work/cmp-clockwise/mesh\\.msh: triangle [0-9]+ is clockwise" "$work/cmp-clockwise" "$b" || status=1
compare_refuses 3 "$work/cmp-3nan/fields\\.txt:[0-9]+: v_z = 'nan' is not a finite number" "$work/cmp-3nan" "$work/cmp-3b" || status=1
compare_refuses 2 "$work/cmp-noscene has no readable scene\\.scene" "$work/cmp-noscene" "$b" || status=1
compare_refuses 2 "$work/cmp-nomesh has no readable mesh\\.msh" "$b" "$work/cmp-nomesh" || status=1
report $status "edp/compare.edp refuses damaged runs (exit 3, file and line named: a truncated, short, nan, inf or longer fields.txt, a row short of a number or away from its vertex, a truncated mesh.msh, clockwise triangles) and folders without scene.scene or mesh.msh (exit 2)" "$diag"

# ---- reproducibility: the same options give byte-identical outputs (timings aside)
diag="$work/repro.diag"; : > "$diag"; status=0
rm -rf "$work/repro" "$work/repro.first"
solve "${coarse[@]}" -out "$work/repro" > "$diag" 2>&1 && mv "$work/repro" "$work/repro.first" || status=1
solve "${coarse[@]}" -out "$work/repro" >> "$diag" 2>&1 || status=1
for f in "${OUTPUT_FILES[@]}"; do
  cmp -s <(strip_timing "$work/repro.first/$f") <(strip_timing "$work/repro/$f") || { echo "$f differs between two runs" >> "$diag"; status=1; }
done
report $status "two runs with the same options give identical outputs" "$diag"

