# Figures for any run.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
# ---- figures for any run (plots)
# ./run.sh figures RUN_DIR ... and ./run.sh animate RUN_DIR (docs/figures.md) on a coarse paper
# run with a VTK time series and a coarse cylinder run (a curved Gamma3: arc length).
diag="$work/figures.diag"; : > "$diag"; status=0
paper="$work/figures-paper" cylinder="$work/figures-cylinder"
rm -rf "$paper" "$cylinder"                  # their figures/ would make the solves refuse the folders
solve "${coarse[@]}" -vtk 2 -out "$paper" >> "$diag" 2>&1 || { echo "the paper run failed" >> "$diag"; status=1; }
solve -scene cylinder -nx 12 -ny 12 -dt 0.1 -out "$cylinder" >> "$diag" 2>&1 || { echo "the cylinder run failed" >> "$diag"; status=1; }
./run.sh figures "$paper" "$cylinder" > "$work/figures.log" 2>> "$diag" || { echo "./run.sh figures failed" >> "$diag"; status=1; }
for file in "$paper"/figures/{contact_at_T,histories,deformed,zone_map,compare_contact}.png \
            "$cylinder"/figures/{contact_at_T,histories,deformed,zone_map}.png; do
  [ -s "$file" ] && grep -qxF "$file" "$work/figures.log" || { echo "$file: missing, empty or not listed" >> "$diag"; status=1; }
done
report $status "figures of any run: the paper scene and the cylinder (curved Gamma3), every figure and the comparison" "$diag"

diag="$work/animate.diag"; : > "$diag"; status=0
./run.sh animate "$paper" > "$work/animate.log" 2>> "$diag" || { echo "./run.sh animate failed" >> "$diag"; status=1; }
"$PYTHON" -c 'import sys; from PIL import Image
frames = Image.open(sys.argv[1]).n_frames
assert frames > 1, f"{frames} frame"' "$paper/figures/animation.gif" >> "$diag" 2>&1 || status=1
[ "$(stat -c %s "$paper/figures/animation.gif" 2>/dev/null || echo 0)" -lt 5000000 ] || { echo "animation.gif: 5 MB or more" >> "$diag"; status=1; }
report $status "animation: a GIF of more than one frame, under 5 MB" "$diag"

diag="$work/figures-refused.diag"; : > "$diag"; status=0
refused() { # refused EXIT REGEX COMMAND...: the command exits EXIT with one line matching REGEX on stderr
  local code="$1" regex="$2" rc=0; shift 2
  "$@" > /dev/null 2> "$work/refused.log" || rc=$?
  [ "$rc" = "$code" ] && [ "$(wc -l < "$work/refused.log")" = 1 ] && grep -Eq "$regex" "$work/refused.log" \
    || { echo "$*: exit $rc, expected $code and one line /$regex/:" >> "$diag"; cat "$work/refused.log" >> "$diag"; status=1; }
}
refused 2 "is not the folder of a finished run" ./run.sh figures "$work"
refused 2 "no such folder" ./run.sh figures "$work/no-such-run/"
refused 2 "has no vtk/ time series: run with -vtk N" ./run.sh animate "$cylinder"
refused 2 "no run folder 'myrun' and no figure named myrun \(figures: fig2 " ./run.sh figures myrun
report $status "figures and animate refuse a folder that is not a run, or a run without vtk/, in one line" "$diag"

# The safety of figures/ (docs/figures.md, "The figures/ folder"), on copies of the paper run.
figs=(plots/run_figures.py) anim=(plots/animate.py)
snapshot() { (cd "$1" 2>/dev/null && ls -A && md5sum -- * 2>/dev/null) || echo "no $1"; }   # the folder as it is
unchanged() { # unchanged FOLDER SNAPSHOT WHAT: the folder is as the snapshot says
  snapshot "$1" | cmp -s - "$2" || { echo "$3: $1 changed:" >> "$diag"; snapshot "$1" | diff "$2" - >> "$diag"; status=1; }
}
diag="$work/figures-safe.diag"; : > "$diag"; status=0
a="$work/figures-a" b="$work/figures-b"
rm -rf "$a" "$b"; cp -r "$paper" "$a"; cp -r "$paper" "$b"; rm -rf "$b/figures"
echo "mine" > "$a/figures/deformed.png"; echo "mine" > "$a/figures/animation.gif"
sed -i '/^deformed.png$/d; /^animation.gif$/d' "$a/figures/figures.list"
snapshot "$a/figures" > "$work/a.before"
refused 2 "figures-a/figures/deformed.png: not a figure this suite drew \(figures.list does not list it\)" "$PYTHON" "${figs[@]}" "$a"
refused 2 "figures-a/figures/animation.gif: not a figure this suite drew" "$PYTHON" "${anim[@]}" "$a"
unchanged "$a/figures" "$work/a.before" "a refused drawing"
rm "$a/figures/deformed.png" "$a/figures/animation.gif"
echo "notes.txt" >> "$a/figures/figures.list"                    # a name the tools never draw
"$PYTHON" "${anim[@]}" "$a" > /dev/null 2>> "$diag" || { echo "animate failed" >> "$diag"; status=1; }
grep -qx "notes.txt" "$a/figures/figures.list" && { echo "figures.list kept notes.txt" >> "$diag"; status=1; }
snapshot "$a/figures" > "$work/a.before"
{ awk '/^#/ || n++ < 3' "$paper/contact_nodes_history.txt"; echo "2 0.2 0"; } > "$b/contact_nodes_history.txt"
refused 2 "figures-b/contact_nodes_history.txt:[0-9]+: 3 values for the [0-9]+ columns" "$PYTHON" "${figs[@]}" "$a" "$b"
unchanged "$a/figures" "$work/a.before" "figures A B failing on B"
[ -e "$b/figures" ] && { echo "figures A B failing on B left $b/figures" >> "$diag"; status=1; }
middle="$(ls "$a"/vtk/fields_*.vtu | sed -n 3p)"
head -c 3000 "$paper/vtk/$(basename "$middle")" > "$middle"                             # a corrupt frame
refused 2 "$(basename "$middle"): not an XML file" "$PYTHON" "${anim[@]}" "$a"
unchanged "$a/figures" "$work/a.before" "a failing animate"
for list in "$paper/figures/figures.list" "$cylinder/figures/figures.list" "$a/figures/figures.list"; do
  tail -n +2 "$list" | grep -vxF -f <(grep -v '^#' edp/figures.txt) \
    | sed "s|^|$list lists |" >> "$diag"
done
grep -q " lists " "$diag" && status=1
report $status "figures and animate: never over a file figures.list does not list; all or nothing (figures/ as before a failure); figures.list names only the figures drawn" "$diag"

# Corrupt inputs are refused in one line, not drawn.
diag="$work/figures-corrupt.diag"; : > "$diag"; status=0
corrupt() { # corrupt REGEX TOOL FILE AWK: a copy of the paper run with FILE passed through AWK is refused
  local regex="$1" tool="$2" file="$3" program="$4" run="$work/figures-corrupt"
  rm -rf "$run"; cp -r "$paper" "$run"; rm -rf "$run/figures"
  awk "$program" "$paper/$file" > "$run/$file"
  refused 2 "$regex" "$PYTHON" "plots/$tool.py" "$run"
  [ -e "$run/figures" ] && { echo "$file: $run/figures left behind" >> "$diag"; status=1; }
}
row='!/^#/ && !done { done = 1;'
corrupt "contact.txt:[0-9]+: normal_status = 3, not one of 0..2" run_figures contact.txt "$row \$7 = 3 } 1"
corrupt "contact.txt:[0-9]+: tangential_status = 2, not one of 0..1" run_figures contact.txt "$row \$8 = 2 } 1"
corrupt "contact.txt:[0-9]+: p_nu = nan is not a finite number" run_figures contact.txt "$row \$4 = \"nan\" } 1"
corrupt "contact_nodes_history.txt:[0-9]+: zone = 5, not one of 0..4" run_figures contact_nodes_history.txt "$row \$13 = 5 } 1"
corrupt "fields.txt:[0-9]+: von_mises = inf is not a finite number" run_figures fields.txt "$row \$7 = \"inf\" } 1"
corrupt "history.txt:[0-9]+: kinetic = nan is not a finite number" run_figures history.txt "$row \$5 = \"nan\" } 1"
corrupt "fields.pvd: the DataSet of fields_[0-9]+.vtu has timestep nan" animate vtk/fields.pvd '/timestep=/ && !done { done = 1; sub(/timestep="[^"]*"/, "timestep=\"nan\"") } 1'
corrupt "fields_[0-9]+.vtu: point data 'von_mises' holds nan" animate vtk/fields_000002.vtu 'found && !done { done = 1; $1 = "nan" } /Name="von_mises"/ { found = 1 } 1'
corrupt "contact.txt: no column g \(columns: " run_figures contact.txt '/^# x / { sub(/ g /, " bound ") } 1'
report $status "figures and animate refuse corrupt inputs in one line (statuses, zones, nan or inf drawn, a pvd timestep, no column g)" "$diag"

# A contact boundary in two pieces (tests/data/twofeet.geo: feet x 0-0.6 and 1.4-2): the
# curves break between them, no node's shading crosses the gap, the zone map leaves it blank.
diag="$work/figures-pieces.diag"; : > "$diag"; status=0
gmsh -2 -format msh22 -v 0 -setnumber h 0.2 tests/data/twofeet.geo -o "$work/twofeet.msh" > /dev/null 2>> "$diag" || status=1
"$PYTHON" - "$work/twofeet.msh" >> "$diag" 2>&1 <<'PY' || status=1
import sys
import numpy as np
sys.path[:0] = ["edp", "plots"]
import gamma3
import runfiles
mesh = runfiles.read_msh22(sys.argv[1])
x, y = mesh.xy[np.unique(mesh.lines[mesh.line_labels == 1])].T
order = np.random.default_rng(1).permutation(len(x))              # in no particular order
x, y = x[order], y[order]
pieces = gamma3.contact_pieces(mesh, x, y)
assert len(set(pieces)) == 2 and len(set(pieces[x < 1])) == 1 and len(set(pieces[x > 1])) == 1, pieces
s, = gamma3.along_gamma3(x, pieces)
gap = np.flatnonzero(np.isnan(s))
assert len(gap) == 1 and np.allclose([s[gap[0] - 1], s[gap[0] + 1]], [0.6, 1.4]), s
start, end = gamma3.node_cells(x, pieces)
assert not ((start < 1.4 - 1e-9) & (end > 0.6 + 1e-9)).any(), (start, end)
assert np.isclose(start.min(), 0) and np.isclose(end.max(), 2), (start, end)
edges, columns = gamma3.map_columns(x, pieces)
blank = np.flatnonzero(columns < 0)
assert len(blank) == 1 and np.allclose(edges[blank[0]:blank[0] + 2], [0.6, 1.4]), (edges, columns)
assert sorted(columns[columns >= 0]) == list(range(len(x))) and np.all(np.diff(edges) >= 0)
found = gamma3.stretches(x, [0] * len(x), pieces)
assert np.allclose([(a, b) for _, a, b, _ in found], [(0, 0.6), (1.4, 2)]), found
PY
report $status "a contact boundary in two pieces: curves broken, shading and zone map cells stop at the gap" "$diag"

# A 3D run (docs/figures.md, "The figures of a 3D run"): every figure of a small slab3d run, its
# comparison with the 2D paper run, and its animation (from contact_nodes_history.txt, no vtk/),
# each a PNG or a GIF; corrupt 3D inputs refused in one line, leaving no figures/.
diag="$work/figures-3d.diag"; : > "$diag"; status=0
slab="$work/figures-slab3d"
rm -rf "$slab"
solve -scene slab3d -nx 8 -ny 4 -nz 1 -dt 0.1 -out "$slab" >> "$diag" 2>&1 || { echo "the slab3d run failed" >> "$diag"; status=1; }
./run.sh figures "$slab" "$paper" > "$work/figures-3d.log" 2>> "$diag" || { echo "./run.sh figures (3D and 2D) failed" >> "$diag"; status=1; }
./run.sh animate "$slab" >> "$work/figures-3d.log" 2>> "$diag" || { echo "./run.sh animate (3D) failed" >> "$diag"; status=1; }
for file in "$slab"/figures/{contact_at_T,histories,deformed,zone_map,compare_contact}.png "$slab/figures/animation.gif"; do
  grep -qxF "$file" "$work/figures-3d.log" || { echo "$file: not listed" >> "$diag"; status=1; }
  "$PYTHON" -c 'import sys; from PIL import Image
image = Image.open(sys.argv[1]); kind = image.format; frames = getattr(image, "n_frames", 1); image.verify()
assert kind == sys.argv[1].rsplit(".", 1)[1].upper() and (kind == "PNG" or frames > 1), (kind, frames)' "$file" >> "$diag" 2>&1 \
    || { echo "$file: not a PNG, or a GIF of more than one frame" >> "$diag"; status=1; }
done
broken="$work/figures-slab3d-corrupt"
for case in "run_figures contact.txt 13 nan contact.txt:[0-9]+: v_tau2 = nan is not a finite number" \
            "run_figures fields.txt 9 inf fields.txt:[0-9]+: u_z = inf is not a finite number" \
            "animate contact_nodes_history.txt 14 5 contact_nodes_history.txt:[0-9]+: zone = 5, not one of 0..4"; do
  read -r tool file column value regex <<< "$case"
  rm -rf "$broken"; cp -r "$slab" "$broken"; rm -rf "$broken/figures"
  awk -v c="$column" -v v="$value" '!/^#/ && !done { done = 1; $c = v } 1' "$slab/$file" > "$broken/$file"
  refused 2 "$regex" "$PYTHON" "plots/$tool.py" "$broken"
  [ -e "$broken/figures" ] && { echo "$file: $broken/figures left behind" >> "$diag"; status=1; }
done
report $status "a 3D run: every figure, the comparison with a 2D run and the animation (PNG, GIF); corrupt 3D inputs refused" "$diag"
# Round-off is drawn flat (docs/figures.md, "Round-off is drawn flat"): the figures of a column
# whose v_nu is g at every node at T (to round-off), of a column pulled off the foundation
# (every node free, its stresses round-off of 0), and of both in 3D; every axis checked on the
# figures' matplotlib objects (tests/figure_axes.py): none with an offset text, each one in
# m/s, GPa, GPa m or GN spanning at least a thousandth of the run's g, p(g) (mu p(g)), p(g)
# times the area of Gamma3. The runs' premises are checked first.
diag="$work/figures-flat.diag"; : > "$diag"; status=0
flat="$work/figures-flat" free="$work/figures-free" flat3d="$work/figures-flat3d" free3d="$work/figures-free3d"
rm -rf "$flat" "$free" "$flat3d" "$free3d"
solve -scene column -vtk 5 -quiet -out "$flat" >> "$diag" 2>&1 || { echo "the flat column failed" >> "$diag"; status=1; }
solve -scene tests/scenes/column-history.scene -T 0.8 -rho 2e-3 -vtk 4 -quiet -out "$free" >> "$diag" 2>&1 \
  || { echo "the pulled column failed" >> "$diag"; status=1; }
solve -scene column3d -quiet -out "$flat3d" >> "$diag" 2>&1 || { echo "the flat 3D column failed" >> "$diag"; status=1; }
solve -scene column3d -load -2 -T 0.2 -rho 2e-3 -quiet -out "$free3d" >> "$diag" 2>&1 \
  || { echo "the pulled 3D column failed" >> "$diag"; status=1; }
"$PYTHON" - "$flat" "$flat3d" "$free" "$free3d" >> "$diag" 2>&1 <<'PY' || status=1
import sys
sys.path.insert(0, "edp")
import runfiles
for folder, flat in zip(sys.argv[1:], (True, True, False, False)):
    c = runfiles.read_table(folder + "/contact.txt")
    if flat:      # every node at the bound: v_nu = g to round-off
        assert (c["normal_status"] == 2).all() and abs(c["v_nu"] - c["g"]).max() <= 1e-9 * c["g"].max(), folder
    else:         # every node free: p(v_nu) = 0, its stresses round-off of 0
        assert (c["normal_status"] == 0).all() and abs(c["p_nu"]).max() <= 1e-9 * c["force_scale"].max(), folder
PY
"$PYTHON" tests/figure_axes.py "$flat" "$free" "$flat3d" "$free3d" >> "$diag" 2>&1 || status=1
"$PYTHON" tests/figure_axes.py "$flat3d" "$flat" >> "$diag" 2>&1 || status=1          # compare_contact, 3D first
for run in "$flat" "$free"; do
  "$PYTHON" tests/figure_axes.py --paper "$run" >> "$diag" 2>&1 || status=1
done
report $status "round-off drawn flat: v_nu = g and an all-free Gamma3 (2D, 3D, the paper's figures, the animation): no offset, every axis spans a thousandth of g, p(g), p(g) |Gamma3|" "$diag"

# Runs made by different versions of the suite (summary.txt: suite_version) drawn or compared
# together: compare_contact.png's title, the paper's figures and tables.py --compare say so;
# with the same version, or none, nothing is said.
diag="$work/figures-versions.diag"; : > "$diag"; status=0
va="$work/figures-version-a" vb="$work/figures-version-b"
rm -rf "$va" "$vb"; cp -r "$flat" "$va"; cp -r "$flat" "$vb"; rm -rf "$va/figures" "$vb/figures"
for version in none same different; do
  sed -i '/^suite_version /d' "$va/summary.txt" "$vb/summary.txt"
  case $version in
    same) echo "suite_version 1.0" | tee -a "$va/summary.txt" >> "$vb/summary.txt" ;;
    different) echo "suite_version 1.0" >> "$va/summary.txt"; echo "suite_version 2.0-test" >> "$vb/summary.txt" ;;
  esac
  "$PYTHON" - "$va" "$vb" "$version" >> "$diag" 2>&1 <<'PY' || status=1
import os, sys, tempfile
sys.path[:0] = ["edp", "plots"]
import figures, run_figures, style
a, b, version = sys.argv[1:]
expected = {"compare_contact": "figures-version-a (1.0); figures-version-b (2.0-test)",   # the runs' folders
            "fig4": "paper-original (1.0); paper-penalty (2.0-test)"}                    # (the names in DIR)
title = run_figures.compare_contact([run_figures.Run(a), run_figures.Run(b)]).axes[0].get_title()
drawn = []
style.save = lambda fig, out, name, tight_layout=True: drawn.append(fig)
with tempfile.TemporaryDirectory() as results:
    os.symlink(os.path.abspath(a), os.path.join(results, "paper-original"))
    os.symlink(os.path.abspath(b), os.path.join(results, "paper-penalty"))
    figures.fig4_velocities(results, results)
suptitle = drawn[0]._suptitle.get_text().replace("\n", " ") if drawn[0]._suptitle else ""
for where, text in (("compare_contact", title), ("fig4", suptitle)):
    if version == "different":
        assert "runs made by different versions of the suite: " + expected[where] in text, f"{version}: {where}: {text!r}"
    else:
        assert "different versions" not in text, f"{version}: {where}: {text!r}"
PY
  "$PYTHON" plots/tables.py --compare "$va" "$vb" > "$work/figures-versions.log" 2>> "$diag" || status=1
  if [ "$version" = different ]; then
    grep -q "^tables.py: note: runs made by different versions of the suite: .*figures-version-a (1.0); .*figures-version-b (2.0-test)$" \
      "$work/figures-versions.log" || { echo "$version: tables.py --compare said no note:" >> "$diag"; cat "$work/figures-versions.log" >> "$diag"; status=1; }
  else
    grep -q "different versions" "$work/figures-versions.log" && { echo "$version: tables.py --compare noted versions" >> "$diag"; status=1; }
  fi
done
report $status "runs of different suite_version drawn or compared together: compare_contact, the paper's figures and tables.py --compare say so (same or no version: nothing)" "$diag"
# ---- end figures
