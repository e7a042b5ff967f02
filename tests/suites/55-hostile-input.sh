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
  for place in 'adaptMesh();' '  recordStep(n, t, v, u, Lam, stepLoad)' 'finishSeries();'; do
    cp edp/solve.edp "$faulty/edp/solve.edp"
    awk -v place="$place" -v fault="$fault" '{ print } $0 == place || index($0, place) == 1 { print fault }' edp/solve.edp > "$faulty/edp/solve.edp"
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
