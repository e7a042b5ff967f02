# Scenes: every new law on the three Newtons.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, FREEFEM, PYTHON, coarse_options, ...).
# ---- scenes (docs/design.md, "Scenes"): every new law on the three Newtons, a run that
# repeats itself from its own folder, the mesh cache, oblique and curved boundaries, bad keys
# compiled = script Newton = full-system Newton to 1e-9, for each scene key: the column cases
# (small already) and the paper-sized scenes on a coarse mesh (scene_agreement: tests/run_tests.sh)
# shellcheck disable=SC2086
for name in column-power column-table column-profile-bound column-history-pulled column-body; do scene_agreement "$name" ${case_options[$name]}; done
scene_agreement unloading-coarse -scene unloading -nx 16 -ny 8 -dt 0.05
scene_agreement power-damping-coarse -scene power-damping -nx 16 -ny 8 -dt 0.05
scene_agreement bound-profile-coarse -scene bound-profile -nx 16 -ny 8 -dt 0.05
scene_agreement cylinder-coarse -scene cylinder -nx 12 -dt 0.05

