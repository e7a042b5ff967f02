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

# ---- reproducibility: the same options give byte-identical outputs (timings aside)
diag="$work/repro.diag"; : > "$diag"; status=0
rm -rf "$work/repro" "$work/repro.first"
solve "${coarse[@]}" -out "$work/repro" > "$diag" 2>&1 && mv "$work/repro" "$work/repro.first" || status=1
solve "${coarse[@]}" -out "$work/repro" >> "$diag" 2>&1 || status=1
for f in "${OUTPUT_FILES[@]}"; do
  cmp -s <(strip_timing "$work/repro.first/$f") <(strip_timing "$work/repro/$f") || { echo "$f differs between two runs" >> "$diag"; status=1; }
done
report $status "two runs with the same options give identical outputs" "$diag"

