# Seeing a run: -help, VTK, the Newton log, progress; the lab sheet; the figure names.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
# ---- see a run: -help, the VTK series read back by VTK itself, the Newton log, progress
diag="$work/help.diag"; : > "$diag"; status=0
for flag in -help -h --help; do
  rc=0; solve -scene column "$flag" > "$work/help.txt" 2> "$work/help.err" || rc=$?
  [ "$rc" = 0 ] && [ ! -s "$work/help.err" ] || { echo "$flag: exit $rc" >> "$diag"; cat "$work/help.err" >> "$diag"; status=1; }
done
# the options that apply to the scene's body, with the scene's defaults: a 2D scene's all but
# -nz, a 3D scene's (slab3d) all but -plane; together every option of edp/options.txt, and the
# README's table: the paper scene's, and -nz (3D only)
solve -scene paper -help > "$work/help-paper.txt" 2>> "$diag" || status=1
solve -scene slab3d -help > "$work/help-3d.txt" 2>> "$diag" || status=1
help_names() { grep -o -- '^  -[a-zA-Z_]*' "$1" | tr -d ' '; }
for name in $(awk '!/^#/ && NF >= 5 && $1 != "when" { print $1 }' edp/options.txt); do
  cat "$work/help-paper.txt" "$work/help-3d.txt" | grep -q -- "^  -${name}  " || { echo "-help does not list -${name}" >> "$diag"; status=1; }
done
grep -q -- '^  -nz  ' "$work/help.txt" "$work/help-paper.txt" && { echo "a 2D scene's -help lists -nz" >> "$diag"; status=1; }
grep -q -- '^  -plane  ' "$work/help-3d.txt" && { echo "slab3d's -help lists -plane" >> "$diag"; status=1; }
grep -q '^options of a 3D run' "$work/help-3d.txt" && grep -q '^options of a 2D run' "$work/help-paper.txt" || { echo "-help does not name the dimension" >> "$diag"; status=1; }
readme_options=$(awk -F'|' '/^\| `-/ { print $2 }' README.md | grep -o -- '`-[a-zA-Z_]*`' | tr -d '`' | sort | tr '\n' ' ')
help_options=$({ help_names "$work/help-paper.txt"; echo -nz; } | sort | tr '\n' ' ')
[ "$readme_options" = "$help_options" ] || { echo "README's table: $readme_options; -help of paper, and -nz: $help_options" >> "$diag"; status=1; }
[ "$(help_names "$work/help.txt" | sort)" = "$(help_names "$work/help-paper.txt" | sort)" ] || { echo "column and paper list other options" >> "$diag"; status=1; }
[ "$(help_names "$work/help-3d.txt" | sort | tr '\n' ' ')" = "$(echo "$readme_options" | tr ' ' '\n' | grep -vx -- -plane | grep . | sort | tr '\n' ' ')" ] \
  || { echo "slab3d's -help is not the README's table without -plane" >> "$diag"; status=1; }
grep -q -- '^  -nx  8  ' "$work/help.txt" || { echo "-help does not give the column scene's nx 8" >> "$diag"; status=1; }
report $status "-help, -h, --help list the options of the scene's body (2D: no -nz; 3D: no -plane; the README's table) with the scene's defaults, exit 0" "$diag"

diag="$work/vtk.diag"; : > "$diag"; status=0
for scene in column cylinder; do
  rm -rf "$work/vtk-$scene"
  solve -scene "$scene" -nx 8 -T 0.2 -dt 0.05 -vtk 3 -out "$work/vtk-$scene" >> "$diag" 2>&1 || status=1
  "$PYTHON" tests/check_vtk.py "$work/vtk-$scene" >> "$diag" 2>&1 || status=1
  "$PYTHON" tests/check_results.py "$work/vtk-$scene" >> "$diag" 2>&1 || status=1
  ls "$work/vtk-$scene/vtk" | tr '\n' ' ' | grep -qx 'fields.pvd fields_000000.vtu fields_000003.vtu fields_000004.vtu ' \
    || { echo "$scene: vtk/ holds $(ls "$work/vtk-$scene/vtk" | tr '\n' ' ')" >> "$diag"; status=1; }
done
# a run replaced by another: the earlier vtk/ goes with it; a file of the user's in vtk/ is not ours to replace
solve -scene column -nx 8 -T 0.2 -dt 0.05 -out "$work/vtk-column" >> "$diag" 2>&1 || status=1
[ ! -e "$work/vtk-column/vtk" ] || { echo "the earlier vtk/ was left in a replaced folder" >> "$diag"; status=1; }
solve -scene column -nx 8 -T 0.2 -dt 0.05 -vtk 1 -out "$work/vtk-column" >> "$diag" 2>&1 || status=1
touch "$work/vtk-column/vtk/mine.txt"
rc=0; solve -scene column -nx 8 -T 0.2 -dt 0.05 -out "$work/vtk-column" >> "$diag" 2>&1 || rc=$?
[ "$rc" = 7 ] && [ -e "$work/vtk-column/vtk/mine.txt" ] || { echo "a file of the user's in vtk/: exit $rc" >> "$diag"; status=1; }
report $status "-vtk N: fields.pvd and .vtu frames read back by VTK equal fields.txt and the zones; replaced with their run, a user's file kept" "$diag"

diag="$work/log.diag"; : > "$diag"; status=0
rm -rf "$work/log"
solve -scene paper -nx 16 -ny 8 -T 0.2 -dt 0.05 -verbose -out "$work/log" > /dev/null 2> "$work/log.err" || status=1
[ "$(grep -c '^step [0-9]*/4 (t = ' "$work/log.err")" = 4 ] && grep -q '^Solver log: 16 normal slots .* and 15 tangential' "$work/log.err" \
  && grep -q '^  iteration 0 (the previous .*): residual .*; slots: damped 16, stick [0-9]*, slip [0-9]*$' "$work/log.err" \
  && grep -q '^  iteration 1: residual .* (the Newton iterate did not lower the merit: one fixed-point iteration instead); changed: stick +[0-9]*, slip -[0-9]*$' "$work/log.err" \
  || { echo "-verbose:" >> "$diag"; cat "$work/log.err" >> "$diag"; status=1; }
# progress lines on stderr, forced at every step (CONTACT_PROGRESS_SECONDS=0: no wait for a
# slow run); -quiet none; a bad value of the variable refused
rm -rf "$work/log"
CONTACT_PROGRESS_SECONDS=0 solve -nx 16 -ny 8 -T 0.2 -dt 0.05 -out "$work/log" > "$work/log.out" 2> "$work/log.err" || status=1
[ "$(grep -c '^step [0-9]*/4 (t = .*), [0-9]* iterations*; zones: [0-9]* free, ' "$work/log.err")" = 4 ] && ! grep -q '^step' "$work/log.out" \
  || { echo "not one progress line a step with CONTACT_PROGRESS_SECONDS=0:" >> "$diag"; cat "$work/log.err" >> "$diag"; status=1; }
rm -rf "$work/log"
CONTACT_PROGRESS_SECONDS=0 solve -nx 16 -ny 8 -T 0.2 -dt 0.05 -quiet -out "$work/log" > /dev/null 2> "$work/log.err" || status=1
[ ! -s "$work/log.err" ] || { echo "-quiet printed:" >> "$diag"; head -3 "$work/log.err" >> "$diag"; status=1; }
rm -rf "$work/log"
rc=0; CONTACT_PROGRESS_SECONDS=soon solve -nx 16 -ny 8 -T 0.2 -dt 0.05 -out "$work/log" > /dev/null 2> "$work/log.err" || rc=$?
[ "$rc" = 2 ] && [ ! -e "$work/log" ] && grep -q "^error: the environment variable CONTACT_PROGRESS_SECONDS = 'soon' is not a number of seconds >= 0" "$work/log.err" \
  || { echo "CONTACT_PROGRESS_SECONDS=soon: exit $rc" >> "$diag"; cat "$work/log.err" >> "$diag"; status=1; }
report $status "-verbose logs each Newton iteration and step; progress lines on stderr (forced by CONTACT_PROGRESS_SECONDS=0), -quiet silences them" "$diag"
grep -v '^#' edp/scenes/column.scene > "$work/quiet.scene"; echo "quiet on" >> "$work/quiet.scene"
expect_failure "a flag given a value in a scene" 3 "quiet.scene:[0-9]+: 'quiet' is a flag of the command line" -scene "$work/quiet.scene"
expect_failure "a flag given a value" 2 "option -quiet is a flag: it takes no value, got 'on'" -quiet on
expect_failure "-help as the value of an option" 2 "option -vtk needs a value, got the option '-help'" -vtk -help
expect_failure "-every below 0" 2 "option -every = -1 is out of range" -every -1

# ---- the lab sheet's commands run as written (docs/lab.md)
# tests/lab.sh runs every ```sh block of the sheet in order, in one shell with a fresh
# temporary $LAB, then checks the numbers the sheet states against the runs it made.
diag="$work/lab.diag"
bash tests/lab.sh "$work/lab.log" > "$diag" 2>&1
report $? "docs/lab.md: every command of the lab sheet runs, and gives the numbers the sheet states" "$diag"
# ---- end lab

# ---- the figures' names: edp/figures.txt is the one list. In a copy of edp/ with one name more,
# a figure of that name that figures.list names goes with its run; one not in the file keeps
# the folder from being replaced (exit 7)
diag="$work/names.diag"; : > "$diag"; status=0
names="$work/names"; rm -rf "$names" "$names-out" && mkdir -p "$names/meshes" && cp -r edp "$names/" && cp meshes/*.geo "$names/meshes/"
echo "extra.png" >> "$names/edp/figures.txt"
signature="# figures.list: the figures plots/ of this suite drew here; they go with the run's results"   # plots/figurefiles.py writes it
"${FREEFEM[@]}" "$names/edp/solve.edp" "${coarse[@]}" -out "$names-out" >> "$diag" 2>&1 || status=1
for figure in extra.png other.png; do
  mkdir -p "$names-out/figures" && : > "$names-out/figures/$figure" && printf '%s\n%s\n' "$signature" "$figure" > "$names-out/figures/figures.list"
  rc=0; "${FREEFEM[@]}" "$names/edp/solve.edp" "${coarse[@]}" -out "$names-out" >> "$diag" 2>&1 || rc=$?
  case "$figure:$rc" in
    extra.png:0) [ ! -e "$names-out/figures" ] || { echo "figures/extra.png stayed" >> "$diag"; status=1; } ;;
    other.png:7) grep -q "holds files that this suite did not write there (figures/other.png)" "$diag" || status=1 ;;
    *) echo "$figure: exit $rc" >> "$diag"; status=1 ;;
  esac
done
report $status "the figures' names: runtools follows edp/figures.txt (a name added there goes with its run, another blocks it)" "$diag"
# the same rules in both readers: a malformed edp/figures.txt stops the solver (exit 3, naming
# the file) and the plot tools' reader (runfiles.figure_names) alike
diag="$work/names-bad.diag"; : > "$diag"; status=0
for bad in crlf bom blank-name leading-dash list-name none; do
  cp edp/figures.txt "$names/edp/figures.txt"
  case $bad in
    crlf) sed -i 's/$/\r/' "$names/edp/figures.txt" ;;
    bom) sed -i '1s/^/\xef\xbb\xbf/' "$names/edp/figures.txt" ;;
    blank-name) echo " a.png" >> "$names/edp/figures.txt" ;;
    leading-dash) echo "-a.png" >> "$names/edp/figures.txt" ;;
    list-name) echo "figures.list" >> "$names/edp/figures.txt" ;;
    none) grep '^#' edp/figures.txt > "$names/edp/figures.txt" ;;
  esac
  rc=0; "${FREEFEM[@]}" "$names/edp/solve.edp" "${coarse[@]}" -out "$work/names-bad-out" >> "$diag" 2>&1 || rc=$?
  [ $rc = 3 ] && [ ! -e "$work/names-bad-out" ] || { echo "$bad: the solver exited $rc" >> "$diag"; status=1; }
  rc=0; "$PYTHON" -c "import sys; sys.path.insert(0, sys.argv[1]); import runfiles; runfiles.run_tool('names', runfiles.figure_names)" \
    "$names/edp" >> "$diag" 2>&1 || rc=$?
  [ $rc = 1 ] || { echo "$bad: figure_names exited $rc" >> "$diag"; status=1; }
done
[ "$(grep -c "figures.txt" "$diag")" -ge 12 ] || { echo "not every message names figures.txt" >> "$diag"; status=1; }
cp edp/figures.txt "$names/edp/figures.txt"
report $status "the figures' names: a malformed edp/figures.txt stops the solver (exit 3) and the plot tools alike" "$diag"
