# Hostile input (issue 26): values that FreeFem++ would read as code, FreeFEM-level errors after
# the run folder opens, bounds and tables at the edge of floating point, names that are not
# UTF-8, values too long to echo, and the messages that name the real cause.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, expect_failure, coarse, ...).

# ---- no option value can become FreeFEM code: an argument FreeFem++ would read as a macro
# (it starts with '-' or 'D' and has an '=' after its fourth character) or as its own option is
# refused, by run.sh before FreeFEM starts and by the plugin runtools when FreeFem++ is started
# by hand; nothing runs, nothing is written
diag="$work/macros.diag"; : > "$diag"; status=0
hostile='-DexportSystem=("x"+exec("id>pwned.txt"))'
mkdir -p "$work/macros" && : > "$work/macros/$hostile"          # a file with that name, as the user's
for how in run.sh direct; do
  for args in "-mesh|$hostile" "-out|$hostile" "-mesh|Dxcout=1" "-scene|-Dload=1" "-out|-jc" "-out|-cd"; do
    option="${args%%|*}" value="${args#*|}"
    # started by hand, a macro named load breaks the script's first line itself: FreeFEM stops
    # on that syntax error (exit 1) before anything runs (checked below)
    [ "$how/$value" = "direct/-Dload=1" ] && continue
    rm -f pwned.txt "$work/macros/pwned.txt"
    if [ "$how" = run.sh ]; then (cd "$work/macros" && bash "$root/run.sh" solve -T 0.1 -dt 0.1 "$option" "$value") > "$work/macros.log" 2>&1
    else (cd "$work/macros" && "${FREEFEM[@]}" "$root/edp/solve.edp" -T 0.1 -dt 0.1 "$option" "$value") > "$work/macros.log" 2>&1; fi
    rc=$?
    if [ "$rc" != 2 ] || ! grep -Eq "^error: the argument '.*' (would be read by FreeFem\+\+ as a macro definition|is an option of FreeFem\+\+ itself)" "$work/macros.log" \
       || [ -e pwned.txt ] || [ -e "$work/macros/pwned.txt" ] || compgen -G "$work/macros/results*" > /dev/null; then
      { echo "$how $option '$value': exit $rc"; cat "$work/macros.log"; } >> "$diag"; status=1
    fi
  done
done
rc=0; (cd "$work/macros" && "${FREEFEM[@]}" "$root/edp/solve.edp" -T 0.1 -dt 0.1 -scene -Dload=1 -out run) > "$work/macros.log" 2>&1 || rc=$?
[ "$rc" = 1 ] && grep -q "syntax error" "$work/macros.log" && ! compgen -G "$work/macros/run*" > /dev/null \
  || { echo "FreeFem++ by hand, -scene -Dload=1: exit $rc"; cat "$work/macros.log"; } >> "$diag"
[ -s "$diag" ] && status=1
report $status "an option value FreeFem++ would read as a macro or as its own option is refused (exit 2), through run.sh and FreeFem++ alike; nothing runs" "$diag"

# ---- a FreeFEM-level error after the run folder is opened (an assert, an error raised in a
# FreeFEM function, in the kernel) removes what the run created; earlier results stay intact
diag="$work/late-errors.diag"; : > "$diag"; status=0
faulty="$work/faulty"
rm -rf "$faulty" && mkdir -p "$faulty/meshes" && cp -r edp run.sh freefem++.pref "$faulty/" && cp meshes/*.geo "$faulty/meshes/"
rm -rf "$work/late-out" "$work/late-out.before"
solve "${coarse[@]}" -out "$work/late-out" > /dev/null 2>&1 || status=1
cp -r "$work/late-out" "$work/late-out.before"
for fault in 'assert(optionText("T") == "never");' 'real[int] tooShort(2); tooShort[7] = 1;' '{ real[int] kernelWrong(3); contactKernelSolve(kernelWrong, kernelWrong); }'; do
  # the places: in the driver, in the time loop and at the end of the run (edp/lib/run.idp)
  for place in '  adaptMesh();' '    recordStep(step, t, v, u, Lam, stepLoad)' '  finishSeries();'; do
    cp edp/solve.edp "$faulty/edp/solve.edp"; cp edp/lib/run.idp "$faulty/edp/lib/run.idp"
    file=edp/solve.edp; grep -qF -- "$place" "$file" || file=edp/lib/run.idp
    grep -qF -- "$place" "$file" || { echo "no line '$place' in edp/solve.edp or edp/lib/run.idp" >> "$diag"; status=1; }
    awk -v place="$place" -v fault="$fault" '{ print } $0 == place || index($0, place) == 1 { print fault }' "$file" > "$faulty/$file"
    (cd "$faulty" && bash run.sh solve "${coarse[@]}" -out "$root/$work/late-out") > "$work/late.log" 2>&1
    rc=$?
    case "$rc" in 1|6|8) ;; *) echo "fault '$fault' after '$place': exit $rc (FreeFEM's own: 1, 6 or 8)" >> "$diag"; status=1 ;; esac
    grep -q "^note: the run stopped on an error (above); it removed its unfinished output folder" "$work/late.log" \
      || { echo "fault '$fault' after '$place': no note of the removal"; cat "$work/late.log"; status=1; } >> "$diag"
    compgen -G "$work/late-out.partial*" > /dev/null && { echo "fault '$fault' after '$place': a partial folder is left" >> "$diag"; status=1; }
    diff -r "$work/late-out" "$work/late-out.before" > /dev/null || { echo "fault '$fault' after '$place': the earlier results changed" >> "$diag"; status=1; }
  done
done
rm -rf "$work/late-new"
(cd "$faulty" && bash run.sh solve "${coarse[@]}" -out "$root/$work/late-new") > "$work/late.log" 2>&1
[ ! -e "$work/late-new" ] || { echo "a new -out folder is left after a FreeFEM error" >> "$diag"; status=1; }
report $status "FreeFEM's own errors after the run folder opens (assert, out-of-bounds, kernel): exit 1/6/8, nothing left, earlier results intact" "$diag"

# ---- bounds and tables at the edge of floating point: refused with the scene's line
grep -v '^bound_profile' edp/scenes/bound-profile.scene > "$work/profile-base.scene"
for profile in "0 1 2 1e-17" "0 0.05 2 1e-300" "0 1e300 2 0.05"; do
  { cat "$work/profile-base.scene"; echo "bound_profile $profile"; } > "$work/profile-edge.scene"
  expect_failure "bound_profile $profile" 3 "profile-edge.scene:[0-9]+: bound_profile: its g go from .* more than a factor 10000 apart" -scene "$work/profile-edge.scene" "${coarse[@]}"
done
{ grep -v -e '^Lz' -e '^geometry' edp/scenes/slab3d.scene; echo "geometry box"; echo "Lz 0.25"; echo "bound_profile 0 1e300 2 0.05"; } > "$work/profile-edge3d.scene"
expect_failure "bound_profile 0 1e300 2 0.05 in 3D" 3 "profile-edge3d.scene:[0-9]+: bound_profile: its g go from" -scene "$work/profile-edge3d.scene" -nx 4 -ny 2 -nz 1 -T 0.1 -dt 0.1
# a profile whose points are close in value: g between its points stays between them (the
# run's check of every node's g > 0 passes, and the physics checks)
{ cat "$work/profile-base.scene"; echo "bound_profile 0 0.05 1 0.0500000000000000001 2 0.03"; } > "$work/profile-near.scene"
diag="$work/profile-near.diag"; : > "$diag"; status=0
rm -rf "$work/profile-near"
solve -scene "$work/profile-near.scene" "${coarse[@]}" -out "$work/profile-near" > "$diag" 2>&1 && "$PYTHON" tests/check_results.py "$work/profile-near" >> "$diag" 2>&1 || status=1
report $status "a bound_profile with nearly equal points runs and passes the physics checks" "$diag"

# ---- names and values: not UTF-8 refused (exit 2), long values refused fast, cut in messages
expect_failure "an -out that is not UTF-8" 2 "option -out is not valid UTF-8" -out "$work/$(printf 'bad\xffname')" "${coarse[@]}"
expect_failure "a -scene that is not UTF-8" 2 "option -scene is not valid UTF-8" -scene "$work/$(printf 'bad\xfe').scene" "${coarse[@]}"
expect_failure "a value of 5000 characters" 2 "option -load has a value of 5000 characters: at most 4096" -load "$(printf '1%.0s' $(seq 1 5000))" "${coarse[@]}"
diag="$work/long-line.diag"; : > "$diag"; status=0
{ printf 'Lx 1'; head -c 1000000 /dev/zero | tr '\0' '1'; echo; grep -v '^Lx' edp/scenes/paper.scene; } > "$work/long-line.scene"
rm -rf "$work/long-line"
start=$(date +%s)
rc=0; solve -scene "$work/long-line.scene" -out "$work/long-line" > "$work/long-line.log" 2>&1 || rc=$?
# (a bound far above the 0.2 s this takes: the parse was 30 s, quadratic in the line's length)
[ "$rc" = 3 ] && [ $(( $(date +%s) - start )) -lt 20 ] && grep -q "long-line.scene:1: a line of 1000004 characters: a scene's lines hold at most 16384" "$work/long-line.log" \
  && [ "$(wc -c < "$work/long-line.log")" -lt 1000 ] && [ ! -e "$work/long-line" ] || { echo "exit $rc"; head -c 600 "$work/long-line.log"; } >> "$diag"
[ -s "$diag" ] && status=1
report $status "a scene line of a megabyte is refused at once (exit 3, its line), and not echoed" "$diag"
expect_failure "a megabyte word in a message is cut" 2 "unknown option '-x{98}\\.\\.\\.\\(100004 bytes\\)\\.\\.\\.x{38}'; options are" "-$(head -c 100000 /dev/zero | tr '\0' 'x')"
expect_failure "raw bytes in a message are escaped" 2 "unknown option '-\\\\xFF\\\\xFEname'" "-$(printf '\xff\xfe')name"

# ---- messages that name the real cause
python3 - "$work/paper-coarse-original/mesh.msh" "$work/huge.msh" <<'PY'
import sys
lines, out, nodes = open(sys.argv[1]).read().split('\n'), [], False
for line in lines:
    if line in ('$Nodes', '$EndNodes'): nodes = line == '$Nodes'
    elif nodes and len(line.split()) == 4:
        i, x, y, z = line.split(); line = f"{i} {float(x) * 1e300!r} {float(y) * 1e300!r} {z}"
    out.append(line)
open(sys.argv[2], 'w').write('\n'.join(out))
PY
expect_failure "coordinates times 1e300" 3 "node [0-9]+ has the coordinate .*e\\+300, beyond 1e\\+100, where areas and volumes overflow" -mesh "$work/huge.msh"
expect_failure "-adapt 8 -adapt_err 1e-6" 2 "option -adapt_err = 1e-6 with -adapt 8: round [0-9] asks for cells smaller than FreeFEM's mesh reader accepts" -nx 8 -ny 4 -T 0.1 -dt 0.05 -adapt 8 -adapt_err 1e-6
{ cat edp/scenes/paper.scene; echo "dirichlet 12345678901234567890 x"; } > "$work/label20.scene"
expect_failure "a 20-digit Dirichlet label" 3 "label20.scene:[0-9]+: dirichlet: a label is a whole number from 0 to 999999999 .*got 12345678901234567890" -scene "$work/label20.scene"
expect_failure "an -out longer than the system allows" 2 "option -out is 4090 bytes long: the run's files under it would pass the system's limit of 4095 bytes" \
  -out "$(python3 -c 'import sys
p = sys.argv[1] + "/"
while len(p) + 200 < 4090: p += "d" * 199 + "/"
print(p + "e" * (4090 - len(p)))' "$work")" "${coarse[@]}"

# ---- FreeFem++'s own options given as values are refused by run.sh before FreeFem++ starts
# (FreeFem++ acts on -f, -glut, -fglut, -check_plugin before any script or plugin runs)
diag="$work/freefem-options.diag"; : > "$diag"; status=0
printf 'exec("touch %s/pwned-f");\n' "$root/$work/macros" > "$work/macros/other.edp"
echo keep > "$work/macros/victim.txt"
for args in "-f|$work/macros/other.edp" "-glut|touch $root/$work/macros/pwned-glut" "-fglut|$work/macros/victim.txt" \
            "-check_plugin|/nonexistent.so" "-scene|-?" "-out|-wg"; do
  option="${args%%|*}" value="${args#*|}"
  rc=0; bash run.sh solve "${coarse[@]}" -out "$work/macros/run" "$option" "$value" > "$work/macros.log" 2>&1 || rc=$?
  if [ "$rc" != 2 ] || ! grep -q "^error: the argument '.*' is an option of FreeFem++ itself" "$work/macros.log" \
     || compgen -G "$work/macros/pwned*" > /dev/null || [ "$(cat "$work/macros/victim.txt")" != keep ] || [ -e "$work/macros/run" ]; then
    { echo "$option '$value': exit $rc"; cat "$work/macros.log"; } >> "$diag"; status=1
  fi
done
report $status "FreeFem++'s own options (-f, -glut, -fglut, -check_plugin, -?, -wg) given to ./run.sh solve are refused before FreeFem++ starts: nothing runs, nothing is written" "$diag"

# ---- a bound within the velocities' round-off: exit 9, saying so; a law or a slope that
# cannot be used names the scene's lines
# (round-off decides which fails first: the statuses' thresholds of a step, exit 4, or the
# end-of-run check, exit 9; either names the cause)
diag="$work/tiny-g.diag"; : > "$diag"; status=0
for sizes in "-nx 8 -ny 4 -dt 0.1" "-nx 8 -ny 4 -T 0.1 -dt 0.05"; do
  rm -rf "$work/tiny-g"
  # shellcheck disable=SC2086
  rc=0; solve $sizes -g 1e-13 -out "$work/tiny-g" > "$work/tiny-g.log" 2>&1 || rc=$?
  { [ "$rc" = 4 ] || [ "$rc" = 9 ]; } && grep -q "the bound g (1e-13 at its smallest) is within the round-off of the velocities" "$work/tiny-g.log" \
    && [ ! -e "$work/tiny-g" ] || { echo "$sizes -g 1e-13: exit $rc"; cat "$work/tiny-g.log"; status=1; } >> "$diag"
done
report $status "-g 1e-13, within the velocities' round-off: exit 4 or 9 naming that cause, no results" "$diag"
grep -v '^damping' edp/scenes/paper.scene > "$work/law-edge.scene"; echo "damping table 0 0 1 1e300" >> "$work/law-edge.scene"
expect_failure "a damping table whose slope passes 1e20" 3 "law-edge.scene:[0-9]+ \\(damping\\): the damped response's slope p'\\(g\\) \\(up to 1e\\+300\\) gives matrix entries" -scene "$work/law-edge.scene" "${coarse[@]}"
{ grep -v '^bound_profile' edp/scenes/bound-profile.scene; echo "bound_profile 0 1e307 2 1e308"; } > "$work/law-edge2.scene"
expect_failure "a law not finite at the bound" 3 "law-edge2.scene:[0-9]+ \\(damping\\), .*law-edge2.scene:[0-9]+ \\(bound_profile\\): the law of edp/plugins/contactlaw.hpp cannot be used: p is not finite" -scene "$work/law-edge2.scene" "${coarse[@]}"

# ---- scene parsing stays linear: at most 256 entries; a long value of many words is cut
{ cat edp/scenes/paper.scene; for i in $(seq 1 300); do echo "dirichlet $((100 + i)) x"; done; } > "$work/many.scene"
expect_failure "300 dirichlet lines" 3 "many.scene:[0-9]+: more than 256 entries" -scene "$work/many.scene"
diag="$work/many-words.diag"; : > "$diag"; status=0
rc=0; solve -mesh "$(for i in $(seq 1 110); do printf 'abcdefghijabcdefghijabcdefghij%05d ' "$i"; done)" -out "$work/many-words" > "$work/many-words.log" 2>&1 || rc=$?
[ "$rc" = 3 ] && [ "$(wc -c < "$work/many-words.log")" -lt 1300 ] && grep -q "bytes cut" "$work/many-words.log" || { echo "exit $rc, $(wc -c < "$work/many-words.log") bytes"; head -c 400 "$work/many-words.log"; } >> "$diag"
[ -s "$diag" ] && status=1
report $status "a value of many words is cut in the message (under 1300 bytes)" "$diag"

# ---- a file-size limit: the run exits 7 and removes its folder; gmsh stopped by it says so
diag="$work/file-size.diag"; : > "$diag"; status=0
rm -rf "$work/big-fields"
solve -nx 100 -ny 50 -T 0.05 -dt 0.05 -out "$work/big-fields" > /dev/null 2>&1 || status=1     # the mesh, cached
rm -rf "$work/big-fields"
rc=0; (ulimit -f 200; solve -nx 100 -ny 50 -T 0.05 -dt 0.05 -out "$work/big-fields") > "$work/file-size.log" 2>&1 || rc=$?
[ "$rc" = 7 ] && grep -q "^error: a file of the run grew past the file-size limit (ulimit -f; SIGXFSZ): the run removed its unfinished output folder" "$work/file-size.log" \
  && [ ! -e "$work/big-fields" ] && ! compgen -G "$work/big-fields.partial*" > /dev/null || { echo "fields past the limit: exit $rc"; cat "$work/file-size.log"; } >> "$diag"
rc=0; (ulimit -f 20; solve -nx 101 -ny 53 -T 0.05 -dt 0.05 -out "$work/big-fields") > "$work/file-size.log" 2>&1 || rc=$?
[ "$rc" = 3 ] && grep -q "^error: gmsh failed on .* (stopped by SIGXFSZ: the file-size limit, ulimit -f)" "$work/file-size.log" \
  && [ ! -e "$work/big-fields" ] || { echo "gmsh past the limit: exit $rc"; cat "$work/file-size.log"; } >> "$diag"
[ -s "$diag" ] && status=1
report $status "past the file-size limit: exit 7 and no folder; gmsh stopped by it: exit 3 naming SIGXFSZ" "$diag"

# ---- check_results.py: a released column (q = 0 after a push) passes --column; a node of
# mesh.msh moved away from fields.txt fails
diag="$work/checks-more.diag"; : > "$diag"; status=0
{ grep -v '^load_history' edp/scenes/column.scene; echo "load_history 0 0 0.5 1 0.75 0 1 0"; } > "$work/released.scene"
rm -rf "$work/released" "$work/moved"
solve -scene "$work/released.scene" -nx 4 -ny 8 -out "$work/released" >> "$diag" 2>&1 && "$PYTHON" tests/check_results.py "$work/released" --column >> "$diag" 2>&1 || status=1
cp -r "$work/paper-coarse-original" "$work/moved"
awk '/^\$Nodes/ { n = 1; print; next } /^\$EndNodes/ { n = 0 } n && $1 == 21 { $2 += 0.05; $3 += 0.05 } { print }' "$work/paper-coarse-original/mesh.msh" > "$work/moved/mesh.msh"
"$PYTHON" tests/check_results.py "$work/moved" > "$work/moved.log" 2>&1 && { echo "a moved node of mesh.msh passed"; status=1; } >> "$diag"
grep -q "fields.txt does not list the vertices of mesh.msh in its order" "$work/moved.log" || { echo "no message for the moved node"; cat "$work/moved.log"; status=1; } >> "$diag"
report $status "check_results.py: a released column passes --column; a node of mesh.msh away from fields.txt fails (2D)" "$diag"
# ---- the law's values on the command line are named (exit 2), and a bound profile whose knots'
# distance overflows still interpolates
expect_failure "-g bound_profile without a bound_profile in the scene" 2 "option -g bound_profile: .*paper.scene gives no bound_profile; give -g a number > 0" "${coarse[@]}" -g bound_profile
# a g far above every velocity: the test and the checks, relative to g, are blind: said
diag="$work/huge-g.diag"; : > "$diag"; status=0
rm -rf "$work/huge-g"
solve "${coarse[@]}" -g 1e20 -out "$work/huge-g" > "$work/huge-g.log" 2>&1 || status=1
grep -q "^note: the bound g (1e+20 at its smallest) is .* times the largest velocity of the run" "$work/huge-g.log" \
  || { echo "-g 1e20: no note"; cat "$work/huge-g.log"; status=1; } >> "$diag"
report $status "-g 1e20, far above the velocities: a note that the test and the checks, relative to g, were that much looser" "$diag"
expect_failure "-g 1e-300: p(g) below what the residual can weigh, the option named" 3 "option -g 1e-300 with .*paper.scene:[0-9]+ \\(damping\\): the law of edp/plugins/contactlaw.hpp cannot be used: p\\(g\\) = 5e-299" "${coarse[@]}" -g 1e-300
diag="$work/profile-span.diag"; : > "$diag"; status=0
sed 's/^g 0.05/bound_profile -1.7e308 0.03 1.7e308 0.07/' edp/scenes/paper.scene > "$work/profile-span.scene"
rm -rf "$work/profile-span"
solve -scene "$work/profile-span.scene" "${coarse[@]}" -out "$work/profile-span" >> "$diag" 2>&1 || status=1
# halfway between knots at -1.7e308 and 1.7e308, every node (x in [0, 2]) has g = 0.05 to round-off
awk '/^# x / { for (i = 2; i <= NF; i++) if ($i == "g") c = i - 1; next } !/^#/ { if (!(c && $c > 0.05 - 1e-15 && $c < 0.05 + 1e-15)) bad = 1; n++ }
     END { exit bad || !n }' "$work/profile-span/contact.txt" 2>> "$diag" || { echo "g is not 0.05 at every node"; status=1; } >> "$diag"
report $status "a bound_profile whose knots are 3.4e308 apart gives g = 0.05 halfway (no overflow to a weight of 0)" "$diag"
# ---- the tools refuse what they cannot use, in one line
diag="$work/tools-args.diag"; : > "$diag"; status=0
out="$("${FREEFEM[@]}" edp/compare.edp -a "$work/profile-span" -ref "$work/profile-span" -a "$work/profile-span" 2>&1)"; rc=$?
[ "$rc" = 2 ] && grep -q "option -a is given twice" <<< "$out" || { echo "compare -a twice: exit $rc: $out"; status=1; } >> "$diag"
out="$("${FREEFEM[@]}" edp/compare.edp -a -ref "$work/profile-span" 2>&1)"; rc=$?
[ "$rc" = 2 ] && grep -q "option -a needs a value" <<< "$out" || { echo "compare -a -ref: exit $rc: $out"; status=1; } >> "$diag"
for bad in -1 nan 1; do
  out="$("$PYTHON" tests/check_results.py "$work/profile-span" --rtol "$bad" 2>&1)"; rc=$?
  [ "$rc" = 2 ] && grep -q "is not a relative tolerance" <<< "$out" || { echo "check_results --rtol $bad: exit $rc: $out"; status=1; } >> "$diag"
done
out="$("$PYTHON" tests/check_results.py "$work/no-such-run" 2>&1)"; rc=$?
[ "$rc" = 1 ] && [ "$(wc -l <<< "$out")" = 1 ] && grep -q "no such folder" <<< "$out" || { echo "check_results on no folder: exit $rc: $out"; status=1; } >> "$diag"
rm -rf "$work/dup-summary"; cp -r "$work/profile-span" "$work/dup-summary"; echo "zone_free 7" >> "$work/dup-summary/summary.txt"
out="$("$PYTHON" tests/check_results.py "$work/dup-summary" 2>&1)"; rc=$?
[ "$rc" = 1 ] && grep -q "the key zone_free is given twice" <<< "$out" || { echo "a key twice in summary.txt: exit $rc: $out"; status=1; } >> "$diag"
report $status "compare.edp refuses an option twice or without its value; check_results refuses a bad --rtol, a missing folder, a summary key given twice" "$diag"
