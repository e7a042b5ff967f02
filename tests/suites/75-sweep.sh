# ./run.sh sweep (README.md, "Sweeps"): one option over a list of values, a run each, in
# parallel; sweep.txt against the runs' own files (tests/check_sweep.py), failed cases, bad
# input, and the folder's rules (replaced only when it holds a finished sweep and nothing
# else; one sweep at a time; a signal leaves it as it was).
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (report, work, PYTHON, coarse_options, ...).
# ---- sweep
sweep_tree() { (cd "$1" 2>/dev/null && find . -printf '%p %y %s\n' | sort) || echo "no $1"; }   # names, kinds, sizes
sweep_left() { # sweep_left DIR: what a sweep or its runs left beside or inside DIR unfinished
  compgen -G "$1.partial.*" || compgen -G "$1.replaced.*" || compgen -G "$1/*.partial.*" || true
}
rm -rf "$work"/sweep-*

# -mu: three values on the coarse paper mesh, two at a time; each row is its run's own
diag="$work/sweep-mu.diag"; : > "$diag"; status=0
./run.sh sweep -mu 0.2,0.4,0.6 "${coarse_options[@]}" -out "$work/sweep-mu" -jobs 2 > "$work/sweep-mu.log" 2>> "$diag" \
  || { echo "exit $?, expected 0" >> "$diag"; status=1; }
"$PYTHON" tests/check_sweep.py "$work/sweep-mu" mu 0.2,0.4,0.6 >> "$diag" 2>&1 || status=1
grep -q "^sweep: 3 runs, 0 failed -> $work/sweep-mu/sweep.txt, $work/sweep-mu/sweep.png$" "$work/sweep-mu.log" \
  || { echo "no closing line in:" >> "$diag"; cat "$work/sweep-mu.log" >> "$diag"; status=1; }
# the check itself fails on a sweep.txt whose number is not its run's
cp -r "$work/sweep-mu" "$work/sweep-corrupt"
awk '!/^#/ && $1 == "0.4" { $5 = sprintf("%.17g", $5 * (1 + 1e-12)) } 1' "$work/sweep-mu/sweep.txt" > "$work/sweep-corrupt/sweep.txt"
"$PYTHON" tests/check_sweep.py "$work/sweep-corrupt" mu 0.2,0.4,0.6 > "$work/sweep-corrupt.log" 2>&1 \
  && { echo "check_sweep.py passed a normal_force off by 1e-12" >> "$diag"; status=1; }
grep -q "row 0.4: normal_force" "$work/sweep-corrupt.log" || { cat "$work/sweep-corrupt.log" >> "$diag"; status=1; }
rm -rf "$work/sweep-corrupt"
report $status "sweep of -mu (3 values, 2 at a time): sweep.txt's rows in the order given are each run's own summary.txt and contact_history.txt at T; sweep.png, sweep.complete; exit 0" "$diag"

# -dt: the runs take the swept time step (10 and 20 steps)
diag="$work/sweep-dt.diag"; : > "$diag"; status=0
./run.sh sweep -dt 0.1,0.05 -nx 8 -ny 4 -out "$work/sweep-dt" > /dev/null 2>> "$diag" || { echo "exit $?, expected 0" >> "$diag"; status=1; }
"$PYTHON" tests/check_sweep.py "$work/sweep-dt" dt 0.1,0.05 >> "$diag" 2>&1 || status=1
for pair in 0.1=10 0.05=20; do
  [ "$(awk '$1 == "steps" { print $2 }' "$work/sweep-dt/dt-${pair%=*}/summary.txt" 2>/dev/null)" = "${pair#*=}" ] \
    || { echo "dt-${pair%=*}: not ${pair#*=} steps" >> "$diag"; status=1; }
done
report $status "sweep of -dt (0.1, 0.05): the rows are the runs', which took 10 and 20 steps" "$diag"

# A value solve refuses and a run that does not converge: failed rows, the others ok, exit 1
diag="$work/sweep-failed.diag"; : > "$diag"; status=0
rc=0; ./run.sh sweep -mu 0.4,-1,0.2 "${coarse_options[@]}" -out "$work/sweep-refused" > /dev/null 2> "$work/sweep-refused.err" || rc=$?
[ "$rc" = 1 ] || { echo "-mu 0.4,-1,0.2: exit $rc, expected 1" >> "$diag"; status=1; }
"$PYTHON" tests/check_sweep.py "$work/sweep-refused" mu 0.4,-1,0.2 --failed -1=2 >> "$diag" 2>&1 || status=1
grep -q "^error: option -mu = -1 is out of range: it must be >= 0$" "$work/sweep-refused/mu--1.log" \
  || { echo "mu--1.log does not hold solve's message" >> "$diag"; status=1; }
grep -q "sweep.py: error: -mu -1 failed (exit 2); its log: $work/sweep-refused/mu--1.log" "$work/sweep-refused.err" \
  || { echo "the failure is not said on stderr:" >> "$diag"; cat "$work/sweep-refused.err" >> "$diag"; status=1; }
rc=0; ./run.sh sweep -maxit 1,50 "${coarse_options[@]}" -out "$work/sweep-maxit" -plot iterations_total,x_B > /dev/null 2>> "$diag" || rc=$?
[ "$rc" = 1 ] || { echo "-maxit 1,50: exit $rc, expected 1" >> "$diag"; status=1; }
"$PYTHON" tests/check_sweep.py "$work/sweep-maxit" maxit 1,50 --failed 1=4 >> "$diag" 2>&1 || status=1
grep -q "the contact solver did not converge after 1 iterations" "$work/sweep-maxit/maxit-1.log" \
  || { echo "maxit-1.log does not say why" >> "$diag"; status=1; }
[ -z "$(sweep_left "$work/sweep-refused")$(sweep_left "$work/sweep-maxit")" ] || { echo "unfinished folders left" >> "$diag"; status=1; }
report $status "sweep with a value solve refuses (-mu -1, exit 2) and one that does not converge (-maxit 1, exit 4): failed rows with nan, the message in NAME-VALUE.log, the others ok; exit 1" "$diag"

# Bad input: one line naming the parameter, exit 2, nothing written
diag="$work/sweep-refusals.diag"; : > "$diag"; status=0
bad="$work/sweep-bad"
sweep_refused() { # sweep_refused REGEX ARGUMENTS...: exit 2, one line matching REGEX, no $bad
  local regex="$1" rc=0; shift
  "${sweep_command[@]}" "$@" > "$work/sweep-refused.out" 2> "$work/sweep-refused.log" || rc=$?
  if [ "$rc" != 2 ] || [ "$(wc -l < "$work/sweep-refused.log")" != 1 ] || ! grep -Eq -- "$regex" "$work/sweep-refused.log" \
     || [ -s "$work/sweep-refused.out" ]; then
    { echo "sweep $*: exit $rc, expected 2 and one line /$regex/:"; cat "$work/sweep-refused.log" "$work/sweep-refused.out"; } >> "$diag"; status=1
  fi
  if [ -e "$bad" ] || [ -n "$(sweep_left "$bad")" ]; then echo "sweep $*: wrote $bad" >> "$diag"; status=1; fi
}
sweep_command=(./run.sh sweep)                 # (as a user types it; then the script itself, which run.sh runs)
sweep_refused "give the swept option and its values first"
sweep_refused "the list of -mu gives the same value twice \(value 1, 0.1, and value 3, 0.1\)" -mu 0.1,0.2,0.1 -out "$bad"
sweep_refused "the argument '-f' is an option of FreeFem\+\+ itself" -mu 0.1,0.2 -f x -out "$bad"
sweep_command=("$PYTHON" plots/sweep.py)
sweep_refused "give the swept option and its values first" mu 0.1,0.2 -out "$bad"
sweep_refused "unknown option '-mux' to sweep; options are -scene, " -mux 1,2 -out "$bad"
sweep_refused "option -quiet is a flag \(on when given\): it takes no values to sweep" -quiet 1,2 -out "$bad"
sweep_refused "option -out is the sweep's folder DIR .*: it cannot be swept" -out "$bad,$bad-2"
sweep_refused "option -mu needs a list of values, V1,V2,..., got the option '-out'" -mu -out "$bad"
sweep_refused "the list of -mu '0.1,,0.2' has an empty value \(value 2\)" -mu 0.1,,0.2 -out "$bad"
sweep_refused "the list of -mu '0.1,' has an empty value \(value 2\)" -mu 0.1, -out "$bad"
sweep_refused "the list of -mu gives the same value twice \(value 1, 0.1, and value 2, 1e-1: the same number\)" -mu 0.1,1e-1 -out "$bad"
sweep_refused "value 'a b' of -scene holds a space or a '#'" -scene "paper,a b" -out "$bad"
sweep_refused "option -out DIR is missing" -mu 0.1,0.2 "${coarse_options[@]}"
sweep_refused "option -out needs a value" -mu 0.1,0.2 -out
sweep_refused "option -out = '\.' is not a usable folder name" -mu 0.1,0.2 -out .
sweep_refused "unknown option '-foo'; options are" -mu 0.1 -foo 1 -out "$bad"
sweep_refused "option -mu is the swept one: give its values once" -mu 0.1 -mu 0.3 -out "$bad"
sweep_refused "option -nx is given twice" -mu 0.1 -nx 8 -nx 4 -out "$bad"
sweep_refused "option -quiet is a flag: it takes no value, got '1'" -mu 0.1 -quiet 1 -out "$bad"
sweep_refused "option -jobs = '0' must be a whole number from 1 to 1024" -mu 0.1 -jobs 0 -out "$bad"
sweep_refused "option -plot: 'speed' is not a quantity of sweep.txt" -mu 0.1 -plot normal_force,speed -out "$bad"
sweep_refused "option -out = '.*sweep-mu/mu-0.2/inner' lies inside .*sweep-mu/mu-0.2, the folder of a run of this suite" \
  -mu 0.1 -out "$work/sweep-mu/mu-0.2/inner"
sweep_refused "option -out = '.*sweep-bad' lies inside .*sweep-mu, the folder of a sweep of this suite" -mu 0.1 -out "$work/sweep-mu/sweep-bad"
sweep_refused "the argument .* holds a control character" -mu 0.1 -out "$bad
x"
[ -e "$work/sweep-mu/sweep-bad" ] && { echo "wrote $work/sweep-mu/sweep-bad" >> "$diag"; status=1; }
report $status "sweep refuses bad input in one line naming the parameter (no list, unknown or flag option, empty or repeated value, -out missing, swept, inside a run or a sweep, bad -jobs or -plot): exit 2, nothing written" "$diag"

# The folder: a folder of the user's, or a sweep with a file of the user's, is not replaced
# (exit 7, untouched); a finished sweep is replaced, whole; a second sweep on the same folder
# while one runs is refused (a run on it too); a sweep stopped by a signal leaves it as it was.
diag="$work/sweep-folder.diag"; : > "$diag"; status=0
unchanged_by() { # unchanged_by CODE REGEX DIR ARGUMENTS...: the sweep exits CODE saying REGEX, DIR as it was
  local code="$1" regex="$2" dir="$3" rc=0; shift 3
  sweep_tree "$dir" > "$work/sweep-before"
  ./run.sh sweep "$@" -out "$dir" > /dev/null 2> "$work/sweep-folder.log" || rc=$?
  [ "$rc" = "$code" ] && grep -Eq -- "$regex" "$work/sweep-folder.log" \
    || { echo "sweep $* -out $dir: exit $rc, expected $code and /$regex/:" >> "$diag"; cat "$work/sweep-folder.log" >> "$diag"; status=1; }
  sweep_tree "$dir" | cmp -s - "$work/sweep-before" || { echo "sweep $*: $dir changed" >> "$diag"; status=1; }
  [ -z "$(sweep_left "$dir")" ] || { echo "sweep $*: unfinished folders left" >> "$diag"; status=1; }
}
mkdir -p "$work/sweep-mine"; echo "mine" > "$work/sweep-mine/notes.txt"
unchanged_by 7 "option -out = '.*sweep-mine' is a folder that does not hold a sweep of this suite \(no sweep.complete\)" \
  "$work/sweep-mine" -mu 0.1 "${coarse_options[@]}"
./run.sh solve "${coarse_options[@]}" -out "$work/sweep-run" > /dev/null 2>> "$diag" || { echo "the run failed" >> "$diag"; status=1; }
unchanged_by 7 "option -out = '.*sweep-run' holds the results of one run \(run.complete\), not of a sweep" \
  "$work/sweep-run" -mu 0.1 "${coarse_options[@]}"
echo "mine" > "$work/sweep-mu/mu-0.4/notes.txt"
unchanged_by 7 "option -out = '.*sweep-mu' holds files that this suite did not write there \(mu-0.4/notes.txt\)" \
  "$work/sweep-mu" -mu 0.1 "${coarse_options[@]}"
rm "$work/sweep-mu/mu-0.4/notes.txt"
echo "mine" > "$work/sweep-mu/notes.txt"
unchanged_by 7 "holds files that this suite did not write there \(notes.txt\)" "$work/sweep-mu" -mu 0.1 "${coarse_options[@]}"
rm "$work/sweep-mu/notes.txt"
# replaced: the new values only (the earlier runs gone), the figures drawn into a run with it
./run.sh figures "$work/sweep-mu/mu-0.2" > /dev/null 2>> "$diag" || { echo "./run.sh figures failed" >> "$diag"; status=1; }
./run.sh sweep -mu 0.3,0.5 "${coarse_options[@]}" -out "$work/sweep-mu" > /dev/null 2>> "$diag" || { echo "the second sweep failed" >> "$diag"; status=1; }
"$PYTHON" tests/check_sweep.py "$work/sweep-mu" mu 0.3,0.5 >> "$diag" 2>&1 || status=1
[ -z "$(sweep_left "$work/sweep-mu")" ] && ! compgen -G "$work/sweep-mu.kept.*" > /dev/null || { echo "the replaced sweep left folders" >> "$diag"; status=1; }
# one at a time: a sweep of 200-step runs, one by one; while it runs (its sweep-one.partial.PID
# is there), another sweep and a run on the same folder are refused, naming its process
./run.sh sweep -mu 0.2,0.4,0.6 -nx 8 -ny 4 -dt 0.005 -jobs 1 -out "$work/sweep-one" > /dev/null 2> "$work/sweep-one.err" &
first=$!
for _ in $(seq 200); do compgen -G "$work/sweep-one.partial.*" > /dev/null && break; sleep 0.05; done
rc=0; ./run.sh sweep -mu 0.1 "${coarse_options[@]}" -out "$work/sweep-one" > /dev/null 2> "$work/sweep-two.err" || rc=$?
[ "$rc" = 7 ] && grep -q "option -out = '.*sweep-one': another sweep or run (process $first) is writing it" "$work/sweep-two.err" \
  || { echo "a second sweep during the first: exit $rc:" >> "$diag"; cat "$work/sweep-two.err" >> "$diag"; status=1; }
rc=0; ./run.sh solve "${coarse_options[@]}" -out "$work/sweep-one" > /dev/null 2> "$work/sweep-two.err" || rc=$?
[ "$rc" = 7 ] && grep -q "another run (process $first) is writing it" "$work/sweep-two.err" \
  || { echo "a run during the sweep: exit $rc:" >> "$diag"; cat "$work/sweep-two.err" >> "$diag"; status=1; }
rc=0; wait "$first" || rc=$?
[ "$rc" = 0 ] || { echo "the first sweep: exit $rc" >> "$diag"; cat "$work/sweep-one.err" >> "$diag"; status=1; }
"$PYTHON" tests/check_sweep.py "$work/sweep-one" mu 0.2,0.4,0.6 >> "$diag" 2>&1 || status=1
# a signal: the runs under way stop, the folder holds the earlier sweep as it was
sweep_tree "$work/sweep-one" > "$work/sweep-before"
./run.sh sweep -mu 0.3,0.5,0.7 -nx 8 -ny 4 -dt 0.005 -jobs 2 -out "$work/sweep-one" > /dev/null 2> "$work/sweep-stop.err" &
first=$!
for _ in $(seq 200); do compgen -G "$work/sweep-one.partial.*/mu-0.*.partial.*" > /dev/null && break; sleep 0.05; done
kill -TERM "$first"
rc=0; wait "$first" || rc=$?
[ "$rc" = 143 ] && grep -q "stopped by signal 15: the runs under way stopped, and what the sweep made is removed" "$work/sweep-stop.err" \
  || { echo "a stopped sweep: exit $rc:" >> "$diag"; cat "$work/sweep-stop.err" >> "$diag"; status=1; }
sweep_tree "$work/sweep-one" | cmp -s - "$work/sweep-before" || { echo "the stopped sweep changed $work/sweep-one" >> "$diag"; status=1; }
[ -z "$(sweep_left "$work/sweep-one")" ] || { echo "the stopped sweep left $(sweep_left "$work/sweep-one")" >> "$diag"; status=1; }
# (this checkout's runs only: another checkout's tests may run the same sweep meanwhile)
pgrep -fa "${root_solve_pattern}.*sweep-one\.partial" >> "$diag" && { echo "runs of the stopped sweep still run" >> "$diag"; status=1; }
report $status "sweep folder: a folder of the user's or a run's, or a sweep holding a file of the user's, is refused untouched (exit 7); a finished sweep is replaced whole; a second sweep or a run on it meanwhile exits 7 naming the process; a signal leaves it as it was" "$diag"
rm -rf "$work"/sweep-*
# ---- end sweep
