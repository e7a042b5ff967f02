# Reliability: failed and killed runs, the run folder, the user's files.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
# ---- a failed run leaves earlier results untouched
diag="$work/keep.diag"; : > "$diag"; status=0
rm -rf "$work/keep"
solve "${coarse[@]}" -out "$work/keep" > "$diag" 2>&1 || status=1
cp "$work/keep/contact.txt" "$work/keep.contact.before" 2>/dev/null || status=1
solve "${coarse[@]}" -maxit 1 -out "$work/keep" >> "$diag" 2>&1 && status=1
cmp -s "$work/keep/contact.txt" "$work/keep.contact.before" || { echo "earlier results changed" >> "$diag"; status=1; }
compgen -G "$work/keep.partial*" > /dev/null && { echo "partial folder left behind" >> "$diag"; status=1; }
report $status "a failed run leaves the earlier results untouched" "$diag"
diag="$work/deep.diag"; : > "$diag"; status=0
deep="$work/deep"; for level in $(seq 20); do deep="$deep/$level"; done
rm -rf "$work/deep"; rc=0; solve "${coarse[@]}" -maxit 1 -out "$deep/run" >> "$diag" 2>&1 || rc=$?
[ "$rc" = 4 ] || { echo "exit $rc, expected 4" >> "$diag"; status=1; }
[ -e "$work/deep" ] && { echo "left: $(find "$work/deep" | tail -1)" >> "$diag"; status=1; }
report $status "a failed run removes the 20 parent folders of -out it created" "$diag"

# ---- a run killed by a signal leaves the earlier results untouched and nothing that looks valid;
# a handled signal (TERM, or SEGV of a crash) leaves nothing at all, and the exit status 128 + n
long_run() { # long_run OUT: a solve of about 5 s in the background (long enough to be killed), no core file
  (ulimit -c 0; exec "${FREEFEM[@]}" edp/solve.edp -nx 66 -ny 33 -dt 0.0002 -out "$1") >> "$diag" 2>&1 &
  pid=$!
}
for signal in TERM SEGV KILL; do
  diag="$work/kill.diag"; : > "$diag"; status=0
  rm -rf "$work/kill" "$work"/kill.partial* "$work/kill-new"
  solve "${coarse[@]}" -out "$work/kill" > "$diag" 2>&1 || status=1
  cp -r "$work/kill" "$work/kill.before"
  long_run "$work/kill"
  sleep 0.4
  kill -s "$signal" "$pid" 2>/dev/null || { echo "the run ended before the signal" >> "$diag"; status=1; }
  rc=0; wait "$pid" 2>/dev/null || rc=$?
  [ "$rc" = $((128 + $(kill -l "$signal"))) ] || { echo "the killed run exited $rc" >> "$diag"; status=1; }
  diff -r "$work/kill" "$work/kill.before" >> "$diag" 2>&1 || { echo "earlier results changed" >> "$diag"; status=1; }
  compgen -G "$work/kill.partial*/run.complete" > /dev/null && { echo "a complete-looking $work/kill.partial.* was left" >> "$diag"; status=1; }
  if [ "$signal" != KILL ]; then
    compgen -G "$work/kill.partial*" > /dev/null && { echo "SIG$signal left $work/kill.partial.*" >> "$diag"; status=1; }
    long_run "$work/kill-new/a/run"                 # a new OUT in new folders: none of them is left
    sleep 0.4
    kill -s "$signal" "$pid" 2>/dev/null || { echo "the second run ended before the signal" >> "$diag"; status=1; }
    wait "$pid" 2>/dev/null
    [ -e "$work/kill-new" ] && { echo "SIG$signal left $(find "$work/kill-new")" >> "$diag"; status=1; }
  fi
  rm -rf "$work/kill.before" "$work"/kill.partial* "$work/kill-new"
  report $status "a run killed with SIG$signal leaves the earlier results untouched$([ "$signal" != KILL ] && echo ", nothing else, and exits 128 + n")" "$diag"
done

# A signal once the results are in OUT changes nothing: the run exits 0, its results complete,
# no OUT.partial.* left. The earlier OUT here lists 3000 more (empty) files, so that removing
# it after the exchange takes a while; the signal is sent as soon as it lies at
# OUT.partial.<pid> (a run that ends first is checked alike), and is then held until the
# earlier folder is gone ("note: the run had finished ...")
diag="$work/late.diag"; : > "$diag"; status=0
rm -rf "$work/late" "$work"/late.partial.*
solve "${coarse[@]}" -out "$work/late" >> "$diag" 2>&1 || status=1
mkdir -p "$work/late/vtk"
for i in $(seq 100000 103000); do : > "$work/late/vtk/fields_$i.vtu"; echo "vtk/fields_$i.vtu" >> "$work/late/run.complete"; done
(exec "${FREEFEM[@]}" edp/solve.edp "${coarse[@]}" -out "$work/late") >> "$diag" 2>&1 &
pid=$!
for i in $(seq 1 4000); do compgen -G "$work/late.partial.*/vtk" > /dev/null && break; kill -0 "$pid" 2> /dev/null || break; sleep 0.005; done
kill -TERM "$pid" 2> /dev/null
rc=0; wait "$pid" || rc=$?
[ "$rc" = 0 ] || { echo "exit code $rc, not 0" >> "$diag"; status=1; }
[ -f "$work/late/run.complete" ] && [ ! -e "$work/late/vtk" ] || { echo "OUT does not hold the new run's results alone" >> "$diag"; status=1; }
compgen -G "$work/late.partial.*" > /dev/null && { echo "left: $(ls -d "$work"/late.partial.*)" >> "$diag"; status=1; }
report $status "a signal once the results are in OUT (the earlier OUT being removed): exit 0, the new results complete, nothing left" "$diag"
rm -rf "$work/late"

# ---- reliability: nothing of the user's is touched, runs never mix, every write is checked,
# no shell sees user text, meshes are checked before FreeFEM reads them, signals stop the solve
# contains FILE REGEX: FILE matches REGEX (for the diagnostics)
contains() { grep -Eq "$2" "$1" || { echo "no /$2/ in $1" >> "$diag"; return 1; }; }

diag="$work/userfiles.diag"; : > "$diag"; status=0
d="$work/userfiles"; rm -rf "$d" "$d".*
for sibling in old partial replaced; do mkdir -p "$d.$sibling" && echo "the user's" > "$d.$sibling/notes"; done
solve "${coarse[@]}" -out "$d" >> "$diag" 2>&1 || status=1
solve "${coarse[@]}" -maxit 1 -out "$d" >> "$diag" 2>&1 && status=1
solve "${coarse[@]}" -load 5 -out "$d" >> "$diag" 2>&1 || status=1
for sibling in old partial replaced; do [ "$(cat "$d.$sibling/notes" 2>/dev/null)" = "the user's" ] || { echo "$d.$sibling/notes changed" >> "$diag"; status=1; }; done
cp "$d/contact.txt" "$work/userfiles.contact"; echo "my notes" > "$d/notes.txt"
rc=0; solve "${coarse[@]}" -out "$d" >> "$diag" 2>&1 || rc=$?
[ "$rc" = 7 ] && contains "$diag" "holds files that this suite did not write there \(notes.txt\)" || status=1
[ -f "$d/notes.txt" ] && cmp -s "$d/contact.txt" "$work/userfiles.contact" || { echo "the folder with the user's notes changed" >> "$diag"; status=1; }
rm "$d/notes.txt"; cp -r "$d" "$d.copy"; rm "$d.copy/run.complete"
rc=0; solve "${coarse[@]}" -out "$d.copy" >> "$diag" 2>&1 || rc=$?
[ "$rc" = 7 ] && contains "$diag" "does not hold results of this suite \(no run.complete\)" && [ -f "$d.copy/summary.txt" ] || status=1
report $status "data loss: the user's D.old, D.partial, D.replaced and files in D are never touched; D without run.complete is not replaced" "$diag"

# a file put into OUT between the run's last check of OUT and the swap (written there by an
# LD_PRELOAD shim, tests/data/late_file.cpp, at the exchange itself): kept, with a note
diag="$work/latefile.diag"; : > "$diag"; status=0
d="$work/latefile"; rm -rf "$d" "$d".*
g++ -O2 -fPIC -shared tests/data/late_file.cpp -o "$work/late_file.so" -ldl >> "$diag" 2>&1 || status=1
solve "${coarse[@]}" -out "$d" >> "$diag" 2>&1 || status=1
LD_PRELOAD="$root/$work/late_file.so" LATE_FILE=notes.txt solve "${coarse[@]}" -load 5 -out "$d" >> "$diag" 2>&1 || status=1
kept=$(compgen -G "$d.kept.*")
[ -n "$kept" ] && [ "$(ls "$kept")" = notes.txt ] && [ "$(cat "$kept/notes.txt")" = "the user's late notes" ] \
  || { echo "the late file was not kept alone in $d.kept.*: $(ls -d "$d"*)" >> "$diag"; status=1; }
contains "$diag" "note: notes.txt appeared in $d while this run replaced it: .* is kept as $kept; the new results are in $d" || status=1
grep -qx 'load 5' "$d/summary.txt" && [ -f "$d/run.complete" ] && [ ! -e "$d/notes.txt" ] || { echo "the new results are not in $d" >> "$diag"; status=1; }
compgen -G "$d.partial*" > /dev/null && { echo "a partial folder was left" >> "$diag"; status=1; }
report $status "data loss: a file put into OUT just before the swap is kept (OUT.kept.PID, named in a note), the new results are in OUT" "$diag"

diag="$work/concurrent.diag"; : > "$diag"; status=0
for pair in 1 2 3 4 5 6; do
  rm -rf "$work/concurrent"
  solve -nx 16 -ny 8 -dt 0.01 -load 5 -out "$work/concurrent" > "$work/concurrent.a" 2>&1 & a=$!
  solve -nx 16 -ny 8 -dt 0.01 -load 20 -out "$work/concurrent" > "$work/concurrent.b" 2>&1 & b=$!
  ra=0; wait "$a" || ra=$?; rb=0; wait "$b" || rb=$?
  for r in "$ra:a" "$rb:b"; do
    case "${r%%:*}" in 0) ;; 7) contains "$work/concurrent.${r#*:}" "another run \(process [0-9]+\) is writing it" || status=1 ;;
      *) echo "pair $pair: exit ${r%%:*}" >> "$diag"; cat "$work/concurrent.${r#*:}" >> "$diag"; status=1 ;; esac
  done
  [ "$ra" = 0 ] || [ "$rb" = 0 ] || { echo "pair $pair: neither run finished" >> "$diag"; status=1; }
  loads=$(grep -h '^# load ' "$work"/concurrent/*.txt | sort -u | wc -l)
  [ "$loads" = 1 ] && [ -f "$work/concurrent/run.complete" ] || { echo "pair $pair: a mixed or incomplete folder" >> "$diag"; status=1; }
  "$PYTHON" tests/check_results.py "$work/concurrent" >> "$diag" 2>&1 || status=1
  compgen -G "$work/concurrent.partial*" > /dev/null && { echo "pair $pair: a partial folder was left" >> "$diag"; status=1; }
done
report $status "concurrency: 6 pairs of runs on one -out, each complete and unmixed or refused (exit 7, naming the other)" "$diag"

diag="$work/diskfull.diag"; : > "$diag"; status=0; disk="$work/small-disk"; mkdir -p "$disk"
if mount -t tmpfs -o size=400k tmpfs "$disk" 2> "$diag"; then
  solve -nx 16 -ny 8 -dt 0.05 -out "$disk/run" >> "$diag" 2>&1 || status=1
  cp "$disk/run/contact.txt" "$work/diskfull.contact"
  for case in "-nx 132 -ny 66" ""; do   # the mesh does not fit; the mesh fits but fields.txt does not
    rc=0; solve $case -out "$disk/run" >> "$diag" 2>&1 || rc=$?
    [ "$rc" = 7 ] && contains "$diag" "cannot write .*(is the disk full\?|No space left)" || { echo "exit $rc for '$case'" >> "$diag"; status=1; }
  done
  cmp -s "$disk/run/contact.txt" "$work/diskfull.contact" || { echo "earlier results changed" >> "$diag"; status=1; }
  [ "$(ls "$disk")" = run ] || { echo "left in $disk: $(ls "$disk")" >> "$diag"; status=1; }
  umount "$disk"
  report $status "a full disk: exit 7, earlier results untouched, no partial folder" "$diag"
else
  count=$((count + 1)); passed=$((passed + 1))
  echo "ok $count - a full disk: exit 7, earlier results untouched, no partial folder # SKIP cannot mount a tmpfs here (not root?)"
fi

diag="$work/injection.diag"; : > "$diag"; status=0
rm -f "$work/INJECTED"
grep -v '^geometry' edp/scenes/paper.scene > "$work/injection.scene"; echo "geometry x;touch $work/INJECTED" >> "$work/injection.scene"
rc=0; solve -scene "$work/injection.scene" -out "$work/injection" >> "$diag" 2>&1 || rc=$?
[ "$rc" = 3 ] || { echo "exit $rc" >> "$diag"; status=1; }
odd="$work/a b'c\$(touch $work/INJECTED)\`touch $work/INJECTED\`"
rm -rf "$odd"; solve "${coarse[@]}" -out "$odd" >> "$diag" 2>&1 && [ -f "$odd/run.complete" ] || { echo "the odd folder name failed" >> "$diag"; status=1; }
[ -e "$work/INJECTED" ] && { echo "a command ran from data" >> "$diag"; status=1; }
report $status "injection: shell characters in scene values are refused, in -out they name a folder; nothing runs" "$diag"

diag="$work/meshes.diag"; : > "$diag"; status=0
gmsh -2 -format msh22 -v 0 -setnumber nx 8 -setnumber ny 4 meshes/rectangle.geo -o "$work/good.msh" > /dev/null 2>&1
"$PYTHON" tests/bad_meshes.py "$work/good.msh" "$work/bad-meshes" >> "$diag" 2>&1 || status=1
while IFS='|' read -r name regex; do
  rc=0; solve -mesh "$work/bad-meshes/$name.msh" -dt 0.1 -out "$work/bad-mesh" > "$work/bad-mesh.log" 2>&1 || rc=$?
  if [ "$rc" != 3 ] || ! grep -Eq "$regex" "$work/bad-mesh.log" || [ -e "$work/bad-mesh" ]; then
    echo "$name: exit $rc, expected 3 and /$regex/, no results:" >> "$diag"; cat "$work/bad-mesh.log" >> "$diag"; status=1
  fi
done <<'MESHES'
undefined-node|uses node 999999, which is not defined
twice-listed-edge|repeats line element .* listed twice
quadrangle|is a quadrangle \(gmsh type 3\)
order-2|is of order 2 or more \(gmsh type 9\)
micrometres|below the 1e-8 that FreeFEM's mesh reader accepts
long-and-thin|extends over 5e\+07 \(its bounding box\) but its shortest edge is 0.25, more than 1e\+08 times shorter
unused-node|is not a vertex of any triangle
truncated|a truncated file
overlap|lie on the same side of their common edge
folded|lie on the same side of their common edge
interior-traction|lies inside the body, between two triangles
interior-contact|lies inside the body, between two triangles
gap-in-contact|has no line element: give every boundary curve a Physical Curve
64-bit-id|does not fit FreeFEM's 32-bit ids
two-bodies|the triangles form 2 separate pieces
loose-triangle|the triangles form 2 separate pieces
slit|the boundary edges \(nodes [0-9]+ [0-9]+\) and \(nodes [0-9]+ [0-9]+\) cross or overlap
arm-over-body|the boundary edges \(nodes [0-9]+ [0-9]+\) and \(nodes [0-9]+ [0-9]+\) cross or overlap
MESHES
solve -mesh "$work/good.msh" -dt 0.1 -out "$work/good-mesh" >> "$diag" 2>&1 || status=1
solve -mesh "$work/bad-meshes/clockwise.msh" -dt 0.1 -out "$work/clockwise-mesh" >> "$diag" 2>&1 || status=1
for f in contact.txt fields.txt history.txt; do
  cmp -s <(grep -v '^#' "$work/good-mesh/$f") <(grep -v '^#' "$work/clockwise-mesh/$f") || { echo "clockwise triangles change $f" >> "$diag"; status=1; }
done
grep -v '^dirichlet 2' edp/scenes/paper.scene > "$work/dirichlet9.scene"; echo "dirichlet 9 x" >> "$work/dirichlet9.scene"
rc=0; solve -scene "$work/dirichlet9.scene" -mesh "$work/good.msh" -dt 0.1 -out "$work/dirichlet9" >> "$diag" 2>&1 || rc=$?
[ "$rc" = 3 ] && contains "$diag" "dirichlet label 9 is not a physical curve of the mesh" || status=1
# a truncated cache is made again: in a copy of the suite (edp/, meshes/*.geo) whose cache
# meshes/build is its own, filled by a first run (the suite's cache serves the jobs that run
# meanwhile: a copy cut under one of them would fail it)
copy="$work/cachecopy"
rm -rf "$copy" && mkdir -p "$copy/meshes" && cp -r edp "$copy/" && cp meshes/*.geo "$copy/meshes/" && rm -rf "$copy/edp/plugins/build"
"${FREEFEM[@]}" "$copy/edp/solve.edp" "${coarse[@]}" -out "$work/cache-first" >> "$diag" 2>&1 || status=1
cached=$(ls "$copy"/meshes/build/rectangle_*_Lx2_Ly1_8x4.msh 2>/dev/null | head -1)
if [ -n "$cached" ]; then
  head -c 200 "$cached" > "$cached.cut" && mv "$cached.cut" "$cached"
  "${FREEFEM[@]}" "$copy/edp/solve.edp" "${coarse[@]}" -out "$work/cache" >> "$diag" 2>&1 && [ "$(wc -c < "$cached")" -gt 1000 ] || { echo "a truncated cached mesh" >> "$diag"; status=1; }
else
  echo "no cached mesh in $copy/meshes/build" >> "$diag"; status=1
fi
report $status "meshes: undefined or unused nodes, repeated edges, overlapping or folded triangles, labels inside the body, gaps, 64-bit ids, two bodies, a loose triangle, a slit, crossing boundaries, quadrangles, order 2, tiny, long and thin, truncated files, missing dirichlet labels refused (exit 3); clockwise triangles reoriented; a bad cache remade" "$diag"

diag="$work/signal.diag"; : > "$diag"; status=0
rm -rf "$work/signal" "$work"/signal.partial*
bash run.sh solve -nx 66 -ny 33 -dt 0.0002 -out "$work/signal" >> "$diag" 2>&1 & pid=$!
sleep 1
kill -TERM "$pid" 2>/dev/null; wait "$pid" 2>/dev/null && status=1
sleep 0.2
# (this checkout's solve only: another checkout's tests may run the same test meanwhile)
pgrep -f -- "${root_solve_pattern}.*-out $work/signal( |$)" > /dev/null \
  && { echo "the solve still runs after run.sh was killed" >> "$diag"; pkill -f -- "${root_solve_pattern}.*-out $work/signal( |$)"; status=1; }
[ -e "$work/signal" ] || compgen -G "$work/signal.partial*" > /dev/null && { echo "left: $(ls -d "$work"/signal "$work"/signal.partial* 2>/dev/null)" >> "$diag"; status=1; }
report $status "signals: killing ./run.sh solve stops the solve, which removes what it created" "$diag"

diag="$work/messages.diag"; : > "$diag"; status=0
printf '\xEF\xBB\xBF' > "$work/bom.scene"; cat edp/scenes/column.scene >> "$work/bom.scene"
solve -scene "$work/bom.scene" -out "$work/bom" >> "$diag" 2>&1 || { echo "a scene with a byte order mark" >> "$diag"; status=1; }
while IFS='|' read -r line regex; do
  grep -v "^${line%% *} " edp/scenes/column.scene > "$work/message.scene"; printf '%s\n' "$line" >> "$work/message.scene"
  [ "${line%% *}" = load ] && echo "load 10" >> "$work/message.scene"
  rc=0; solve -scene "$work/message.scene" -out "$work/message" > "$work/message.log" 2>&1 || rc=$?
  [ "$rc" = 3 ] && grep -Eq "$regex" "$work/message.log" || { echo "'$line': exit $rc, expected 3 and /$regex/" >> "$diag"; status=1; }
done <<'SCENES'
Lx 0|Lx must be a number > 0, got '0'
load 5|'load' is given a second time
contact_normal 0 -1e400|contact_normal needs two finite numbers
geometry ../rectangle|a name of meshes/NAME.geo
Lx 1e10|Lx 1e10 and Ly 2 with 8 x 16 cells make a mesh that extends over 1e\+10 but whose shortest edge is 0.125, more than 1e\+08 times shorter
SCENES
rc=0; solve "${coarse[@]}" -E 1e300 -out "$work/message" > "$work/message.log" 2>&1 || rc=$?
[ "$rc" = 2 ] && grep -q "give matrix entries up to .*use other units" "$work/message.log" || { echo "-E 1e300: exit $rc" >> "$diag"; status=1; }
rc=0; bash tests/run_tests.sh --bless '' > "$work/message.log" 2>&1 || rc=$?
[ "$rc" = 2 ] && grep -q "usage: ./run.sh test --bless CASE" "$work/message.log" || { echo "--bless '': exit $rc" >> "$diag"; status=1; }
mkdir -p "$work/corrupt/paper-original" "$work/corrupt/paper-penalty"; printf 'garbage\n\001\377\n' > "$work/corrupt/paper-original/summary.txt"
"$PYTHON" plots/tables.py --results "$work/corrupt" > "$work/message.log" 2>&1 && status=1
[ "$(wc -l < "$work/message.log")" = 1 ] && ! grep -q Traceback "$work/message.log" || { echo "tables.py on a corrupt summary:" >> "$diag"; cat "$work/message.log" >> "$diag"; status=1; }
report $status "messages: a byte order mark is read; Lx 0, Lx 1e10 (before gmsh), repeated keys, non-finite numbers, odd names, -E 1e300 named; --bless '' and corrupt inputs give one line" "$diag"

