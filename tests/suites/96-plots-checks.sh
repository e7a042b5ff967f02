# The plots never write through a symbolic link and refuse names that are not UTF-8;
# tests/check_results.py's round-off allowances and its refusal of a pull-then-push column.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, PYTHON, ...).
# ---- plots: symbolic links and names (docs/figures.md, "The figures/ folder")
plots_refused() { # plots_refused DIAG EXIT REGEX COMMAND...: the command exits EXIT with one line matching REGEX on stderr
  local log="$1" code="$2" regex="$3" rc=0; shift 3
  "$@" > /dev/null 2> "$work/plots-refused.log" || rc=$?
  [ "$rc" = "$code" ] && [ "$(wc -l < "$work/plots-refused.log")" = 1 ] && grep -Eq -- "$regex" "$work/plots-refused.log" \
    || { echo "$*: exit $rc, expected $code and one line /$regex/:" >> "$log"; cat "$work/plots-refused.log" >> "$log"; return 1; }
}
plots_tree() { (cd "$1" 2>/dev/null && find . -printf '%p %y %s %l\n' | sort) || echo "no $1"; }   # names, kinds, sizes, link targets

# A small paper run with a VTK series; each case makes a symbolic link where the figures would
# go, and both tools must refuse it in one line (exit 2) and write nothing, there or anywhere.
diag="$work/plots-links.diag"; : > "$diag"; status=0
run="$work/plots-run" elsewhere="$work/plots-elsewhere"
rm -rf "$run" "$elsewhere" "$work/plots-link"
mkdir -p "$elsewhere"
solve -nx 8 -ny 4 -dt 0.05 -T 0.1 -vtk 1 -quiet -out "$run" >> "$diag" 2>&1 || { echo "the run failed" >> "$diag"; status=1; }
links_refused() { # links_refused REGEX RUN_DIR: figures and animate refuse; the run and $elsewhere unchanged
  local regex="$1" folder="$2" tool
  plots_tree "$run" > "$work/plots-run.before"; plots_tree "$elsewhere" > "$work/plots-elsewhere.before"
  for tool in figures animate; do
    plots_refused "$diag" 2 "$regex" ./run.sh "$tool" "$folder" || status=1
  done
  plots_tree "$run" | cmp -s - "$work/plots-run.before" || { echo "$regex: $run changed" >> "$diag"; status=1; }
  plots_tree "$elsewhere" | cmp -s - "$work/plots-elsewhere.before" || { echo "$regex: $elsewhere changed" >> "$diag"; status=1; }
}
ln -s "../plots-elsewhere" "$run/figures"                           # figures/ itself
links_refused "plots-run/figures is a symbolic link: the suite does not write through one" "$run"
rm "$run/figures"; mkdir "$run/figures"
ln -s "../../plots-elsewhere/figures.list" "$run/figures/figures.list"  # its list (the target does not exist)
links_refused "figures/figures.list is a symbolic link" "$run"
rm -r "$run/figures"; mkdir "$run/figures"
ln -s "../../plots-elsewhere/figure.png" "$run/figures/deformed.png"   # a figure (run_figures draws it)
ln -s "../../plots-elsewhere/figure.gif" "$run/figures/animation.gif"  # (animate draws this one)
plots_refused "$diag" 2 "figures/deformed.png is a symbolic link: the suite does not write through one" \
  ./run.sh figures "$run" || status=1
plots_refused "$diag" 2 "figures/animation.gif is a symbolic link" ./run.sh animate "$run" || status=1
[ -z "$(ls -A "$elsewhere")" ] || { echo "a figure was written through its link: $(ls -A "$elsewhere")" >> "$diag"; status=1; }
rm -r "$run/figures"
ln -s .. "$run/figures"                                             # the run reached through a link of its own folder
links_refused "plots-run/figures/plots-run is reached through .*plots-run/figures, a symbolic link in a run folder" \
  "$run/figures/plots-run"
rm "$run/figures"
ln -s plots-run "$work/plots-link"                                  # the run folder given as a link
links_refused "plots-link is a symbolic link: the suite does not write through one; give the folder it points to" \
  "$work/plots-link"
rm "$work/plots-link"
[ -e "$run/figures" ] && { echo "$run/figures left behind" >> "$diag"; status=1; }
report $status "figures and animate never write through a symbolic link (figures/, figures.list, a figure, the run's path): refused in one line, nothing written" "$diag"

# A run folder whose name is not UTF-8 (the byte 0xff), a name with a line feed, a very long
# name: refused at the start (exit 2), the name shown escaped and cut; nothing written.
diag="$work/plots-names.diag"; : > "$diag"; status=0
bad="$work/plots-run-$(printf '\377')"
rm -rf "$bad"; cp -r "$run" "$bad"
plots_refused "$diag" 2 "run_figures.py: error: the argument '.*plots-run-\\\\xff' is not valid UTF-8" ./run.sh figures "$bad" || status=1
LC_ALL=C grep -q "$(printf '\377')" "$work/plots-refused.log" && { echo "the raw byte 0xff was printed" >> "$diag"; status=1; }
plots_refused "$diag" 2 "animate.py: error: the argument '.*plots-run-\\\\xff' is not valid UTF-8" ./run.sh animate "$bad" || status=1
plots_refused "$diag" 2 "figures.py: error: the argument 'fig2\\\\xff' is not valid UTF-8" ./run.sh figures "$(printf 'fig2\377')" || status=1
plots_refused "$diag" 2 "tables.py: error: the argument '.*plots-run-\\\\xff' is not valid UTF-8" \
  "$PYTHON" plots/tables.py --compare "$run" "$bad" || status=1
[ -e "$bad/figures" ] && { echo "$bad/figures was made" >> "$diag"; status=1; }
plots_refused "$diag" 2 "the argument '.*/a\\\\nb' holds a control character or a line separator" ./run.sh figures "$work/a
b" || status=1
long="$work/$(printf 'x%.0s' {1..300})"
plots_refused "$diag" 2 "^run_figures.py: error: tests/work/x+\.\.\.x+: no such folder$" ./run.sh figures "$long" || status=1
[ "$(wc -c < "$work/plots-refused.log")" -lt 160 ] || { echo "the long name was not cut" >> "$diag"; status=1; }
rm -rf "$bad"
report $status "plots refuse a name that is not UTF-8 or holds a line feed (exit 2, shown escaped) and cut a long one" "$diag"

# ---- tests/check_results.py: round-off allowances, the column's pull-then-push history
# Three valid runs it once failed (tests/data/check-*.scene): the column with p = 7 r^3.5 (a
# total force off by 9e-15 of 10 against an inertia bound of 3e-17), on a flat table p = 0
# (v_nu = g computed from terms of 1e5 m/s), and pulled then pushed (it flies away: --column
# is refused, saying why, and the other checks pass).
diag="$work/plots-checks.diag"; : > "$diag"; status=0
for name in power flat pull-push; do
  rm -rf "$work/check-$name"
  solve -scene "tests/data/check-$name-column.scene" -quiet -out "$work/check-$name" >> "$diag" 2>&1 \
    || { echo "the $name column failed" >> "$diag"; status=1; }
done
for name in power flat; do
  "$PYTHON" tests/check_results.py "$work/check-$name" --column >> "$diag" 2>&1 || { echo "$name: check_results --column failed" >> "$diag"; status=1; }
done
"$PYTHON" tests/check_results.py "$work/check-pull-push" >> "$diag" 2>&1 || { echo "pull-push: check_results failed" >> "$diag"; status=1; }
plots_refused "$diag" 2 "check-pull-push: --column does not apply: the load history pulls the column \(step 1, t = 0.05\) before it presses it \(step 10, t = 0.5\); pulled, the column flies off the foundation" \
  "$PYTHON" tests/check_results.py "$work/check-pull-push" --column || status=1
report $status "check_results passes a column with p = 7 r^3.5, one with p = 0, and refuses --column for a pull-then-push history (exit 2)" "$diag"

# Corrupted copies still fail, with the check that names the corruption: v_nu above g by
# 1e-6 g on the flat column (the largest round-off allowance of the three: 1.4e-7 g), lambda_tau
# above the friction bound by 1e-5 of it on the paper run, the total force of the last step
# of the power column off by 1e-6 of it (--column).
diag="$work/plots-corrupt.diag"; : > "$diag"; status=0
corrupt_fails() { # corrupt_fails RUN FILE AWK REGEX [OPTIONS]: check_results fails on a copy of RUN with FILE through AWK
  local source="$1" file="$2" program="$3" regex="$4" copy="$work/check-corrupt" rc=0; shift 4
  rm -rf "$copy"; cp -r "$source" "$copy"
  awk "$program" "$source/$file" > "$copy/$file"
  cmp -s "$source/$file" "$copy/$file" && { echo "$file: the corruption changed nothing" >> "$diag"; status=1; }
  "$PYTHON" tests/check_results.py "$copy" "$@" > "$work/check-corrupt.log" 2>&1 || rc=$?
  [ "$rc" = 1 ] && grep -Eq -- "$regex" "$work/check-corrupt.log" \
    || { echo "$file /$regex/: exit $rc, expected 1 with that failure:" >> "$diag"; cat "$work/check-corrupt.log" >> "$diag"; status=1; }
}
corrupt_fails "$work/check-flat" contact.txt '!/^#/ && $7 == 2 && !done { done = 1; $2 = sprintf("%.17g", $2 * (1 + 1e-6)) } 1' \
  "constraint v_nu <= g violated by [0-9.]+e-0[67] g"
corrupt_fails "$run" contact.txt '!/^#/ && $8 == 1 && $11 > 0 && !done { done = 1; $6 = sprintf("%.17g", $6 * (1 + 1e-5)) } 1' \
  "friction cone \|lambda_tau\| <= mu p\(v_nu\) violated by [0-9.]+e-0[67] p\(g\)"
corrupt_fails "$work/check-power" contact_history.txt 'NR > 1 { print last } { last = $0 } END { $0 = last; $3 = sprintf("%.17g", $3 * (1 + 1e-6)); print }' \
  "step 20: total contact force .* != q L" --column
report $status "check_results still fails corrupted copies: v_nu above g, lambda_tau above the friction bound, a total force off q L" "$diag"
rm -rf "$work/check-corrupt" "$elsewhere"
# ---- end plots and checks
