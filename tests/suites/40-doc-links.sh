# Every path, link and section cited in the docs and comments exists.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
# ---- every repository path, link and section cited in README.md, docs/ and code comments exists
diag="$work/references.diag"
"$PYTHON" tests/check_references.py > "$diag" 2>&1; report $? "no dangling reference in README.md, docs/ and comments; none to files outside the repository or to issue numbers" "$diag"

