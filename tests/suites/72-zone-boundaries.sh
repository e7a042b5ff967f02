# The zone boundaries on Gamma3's edges, zone_boundaries.txt (docs/design.md, "Output files"):
# checked by tests/check_zone_boundaries.py on what holds whatever the round-off.
# Sourced by tests/run_tests.sh, in the order of the file names: it uses the harness's
# variables and functions (solve, report, work, PYTHON, case_names, ...).
# ---- every regression case: the file's steps, kinds and counts (summary.txt's
# boundaries_B, boundaries_C at T), every row on an edge of Gamma3 (its mesh.msh), in
# 2D its s the length along Gamma3 up to it (between its edge's nodes), nan in 3D
diag="$work/zone-boundaries.diag"; : > "$diag"; status=0
folders=()
for name in "${case_names[@]}"; do folders+=("$work/$name"); done
"$PYTHON" tests/check_zone_boundaries.py "${folders[@]}" >> "$diag" 2>&1 || status=1
report $status "zone_boundaries.txt of every regression case: steps, kinds, the counts of summary.txt at T, each row on an edge of Gamma3, s its length along Gamma3 (2D), nan (3D)" "$diag"

# ---- the paper scene (both problems, two meshes): at T its first B and C rows are
# x_B_estimate and x_C_estimate (a flat face ordered by x: the same interpolation)
diag="$work/zone-boundaries-paper.diag"; : > "$diag"; status=0
"$PYTHON" tests/check_zone_boundaries.py --estimates "$work/paper-original" "$work/paper-penalty" "$work/paper-fine-original" >> "$diag" 2>&1 || status=1
report $status "zone_boundaries.txt, paper scene (original, penalty, 132x66): the first B and C rows at T are x_B_estimate and x_C_estimate" "$diag"

# ---- a curved face: the half disk pressed on its flat top is symmetric about its lowest
# point x = 0; at T the bound zone and the sticking zone are centred there (the lowest node
# sticks: no tangential stress by symmetry), so B and C rows on both sides, mirror images of
# each other to within half an edge (the unstructured mesh is not exactly symmetric)
diag="$work/zone-boundaries-halfdisk.diag"; : > "$diag"; status=0
rm -rf "$work/zone-halfdisk"
solve -scene halfdisk -quiet -out "$work/zone-halfdisk" >> "$diag" 2>&1 || status=1
[ "$status" = 0 ] && { "$PYTHON" tests/check_zone_boundaries.py --mirror 0 "$work/zone-halfdisk" >> "$diag" 2>&1 || status=1; }
report $status "zone_boundaries.txt, half disk: B and C rows on both sides of the lowest point at T, mirror images, on Gamma3's edges, s along the arc" "$diag"

# ---- 3D: the slab (16 x 8 x 2, the regression case slab3d): at T both boundaries cross the
# face (nodes at the bound and damped ones, sticking and slipping ones, all in contact); every
# row of it and of the coarse slab (8 x 4 x 1, T = 0.2) on the face y = 0, inside its extent
# (and on an edge of its triangles: checked above for every case)
diag="$work/zone-boundaries-3d.diag"; : > "$diag"; status=0
"$PYTHON" tests/check_zone_boundaries.py --both "$work/slab3d" >> "$diag" 2>&1 || status=1
"$PYTHON" - "$work/slab3d" "$work/slab3d-coarse" >> "$diag" 2>&1 <<'PY' || status=1
# on the face (its nodes' y, within 1e-12 m) and inside its extent (its nodes' x and z)
import os, sys
sys.path.insert(0, "edp")
import numpy as np
import runfiles
failures = []
for folder in sys.argv[1:]:
    t = runfiles.read_table(os.path.join(folder, "zone_boundaries.txt"), empty=True)
    c = runfiles.read_table(os.path.join(folder, "contact.txt"))
    if np.ptp(c["y"]) != 0:
        failures.append(f"{folder}: the contact nodes are not on one face y = constant")
        continue
    inside = np.abs(t["y"] - c["y"][0]) <= 1e-12
    for axis in ("x", "z"):
        inside &= (t[axis] >= c[axis].min() - 1e-12) & (t[axis] <= c[axis].max() + 1e-12)
    if not inside.all():
        failures.append(f"{folder}: {int((~inside).sum())} rows off the face y = {c['y'][0]}, or beyond its nodes' x and z")
print("\n".join(failures))
sys.exit(1 if failures else 0)
PY
report $status "zone_boundaries.txt in 3D (slab3d): B and C rows at T, on the face y = 0 within its extent, on its triangles' edges, s nan" "$diag"
