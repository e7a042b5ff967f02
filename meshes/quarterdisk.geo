// quarterdisk.geo: the right half of a half disk of radius Lx, cut along its axis of symmetry
// (the classic curved-contact test, with symmetry): the arc (the contact boundary) from the
// lowest point (0, 0) to (Lx, Lx), the flat top y = Lx (the traction), the axis x = 0 (where
// a symmetric body has v_x = 0). An unstructured mesh of size Lx/nx (ny and Ly are not used).
// Generated on demand by edp/lib/meshes.idp; by hand:
//   gmsh -2 -format msh22 -setnumber Lx 1 -setnumber nx 40 quarterdisk.geo -o quarterdisk.msh
// Physical tags are the FreeFEM labels of edp/lib/forms.idp.
DefineConstant[
  Lx = {1, Name "Parameters/Lx"},
  Ly = {1, Name "Parameters/Ly"},
  nx = {40, Name "Parameters/nx"},
  ny = {40, Name "Parameters/ny"}
];
R = Lx;
h = R/nx;
Point(1) = {0, 0, 0, h};        // the lowest point, on the axis
Point(2) = {0, R, 0, h};        // the centre of the arc
Point(3) = {R, R, 0, h};
Circle(1) = {1, 2, 3};
Line(2) = {2, 1};
Line(3) = {3, 2};
Curve Loop(1) = {1, 3, 2};
Plane Surface(1) = {1};
Physical Curve("contact", 1) = {1};
Physical Curve("axis", 2) = {2};
Physical Curve("traction", 3) = {3};
Physical Surface("body", 1) = {1};
