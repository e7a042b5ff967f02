# check_msh22.awk: refuse a gmsh mesh file that edp/solve.edp cannot use, before
# FreeFEM reads it (its reader aborts on degenerate triangles and silently re-meshes
# a file without triangles). Usage (edp/lib/meshes.idp passes the labels of forms.idp, in
# the order contact, right, traction, left):
#   awk -v labels="1 2 3 4" -f check_msh22.awk FILE.msh
# Prints one line: "ok", or what is wrong; exits 0 or 1.
function fail(msg) { print msg; bad = 1; exit 1 }
NR == 2 && section == "MeshFormat" { version = $1; binary = $2 }
/^\$MeshFormat/ { section = "MeshFormat"; next }
/^\$Nodes/ { section = "Nodes"; count = -1; seen = 0; next }
/^\$Elements/ { section = "Elements"; count = -1; seen = 0; next }
/^\$EndNodes/ { if (seen != nodeCount) fail("$Nodes declares " nodeCount " nodes but holds " seen); endNodes = 1; section = ""; next }
/^\$EndElements/ { if (seen != elementCount) fail("$Elements declares " elementCount " elements but holds " seen); endElements = 1; section = ""; next }
/^\$End/ { section = ""; next }
section == "Nodes" {
  if (count < 0) { count = $1; nodeCount = $1; next }
  seen++
  x[$1] = $2; y[$1] = $3
  if (xmin == "" || $2 < xmin) xmin = $2; if (xmax == "" || $2 > xmax) xmax = $2
  if (ymin == "" || $3 < ymin) ymin = $3; if (ymax == "" || $3 > ymax) ymax = $3
  next
}
section == "Elements" {
  if (count < 0) { count = $1; elementCount = $1; next }
  seen++
  ntags = $3; first = 4 + ntags
  if ($2 == 2) {
    triangles++
    a = $(first); b = $(first + 1); c = $(first + 2)
    if (!(a in x) || !(b in x) || !(c in x)) fail("triangle " $1 " uses a node that is not defined")
    area = 0.5 * ((x[b] - x[a]) * (y[c] - y[a]) - (x[c] - x[a]) * (y[b] - y[a]))
    if (area < 0) area = -area
    if (area <= 1e-12 * (xmax - xmin) * (ymax - ymin)) fail("triangle " $1 " (nodes " a " " b " " c ") has zero area")
  }
  if ($2 == 1 && ntags >= 1) tags[$4] = 1
  next
}
END {
  if (bad) exit 1
  if (labels == "") fail("check_msh22.awk: give the labels with -v labels=\"CONTACT RIGHT TRACTION LEFT\"")
  if (version == "") fail("not a gmsh mesh file (no $MeshFormat section)")
  if (version !~ /^2\.2/) fail("gmsh format " version ", not 2.2: re-export it with: gmsh -2 -format msh22 FILE.geo -o FILE.msh")
  if (binary != 0) fail("binary MSH file: re-export it as text with: gmsh -2 -format msh22 FILE.geo -o FILE.msh")
  if (!endNodes || !endElements) fail("truncated file: no $EndNodes or $EndElements")
  if (triangles == 0) fail("no triangle (does the .geo define a Physical Surface?)")
  split(labels, needed, " ")
  split("contact right traction left", role, " ")
  for (l = 1; l <= 4; l++) {
    if (!(needed[l] in tags)) missing = missing " " needed[l]
    roles = roles (l > 1 ? ", " : "") needed[l] " " role[l]
  }
  if (missing != "") fail("no boundary line with physical tag" missing " (Physical Curve " roles " are required)")
  print "ok"
}
