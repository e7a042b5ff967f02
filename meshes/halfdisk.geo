// halfdisk.geo: a half disk of radius Lx, its flat side up: the centre (0, Lx), the lowest point
// (0, 0). The arc within 70 degrees of the lowest point is the contact boundary (label 1), the
// rest of the arc is free (label 2), the flat top y = Lx carries the traction (label 3). (The
// arc is not in contact up to the top: with v_x fixed on the top, nodes of horizontal normal
// would have no free normal velocity.) An unstructured mesh of size Lx/nx (ny, Ly not used).
// Generated on demand by edp/lib/meshes.idp; by hand:
//   gmsh -2 -format msh22 -setnumber Lx 1 -setnumber nx 20 halfdisk.geo -o halfdisk.msh
// Physical tags are the FreeFEM labels of edp/lib/forms.idp.
DefineConstant[
  Lx = {1, Name "Parameters/Lx"},
  Ly = {1, Name "Parameters/Ly"},
  nx = {20, Name "Parameters/nx"},
  ny = {20, Name "Parameters/ny"}
];
R = Lx;
h = R/nx;
contact = 70*Pi/180;            // the contact arc: within this angle of the lowest point
Point(1) = {0, R, 0, h};        // the centre
Point(2) = {0, 0, 0, h};        // the lowest point
Point(3) = {R*Sin(contact), R - R*Cos(contact), 0, h};
Point(4) = {-R*Sin(contact), R - R*Cos(contact), 0, h};
Point(5) = {R, R, 0, h};
Point(6) = {-R, R, 0, h};
Circle(1) = {4, 1, 2};          // the contact arc, in two halves
Circle(2) = {2, 1, 3};
Circle(3) = {3, 1, 5};          // the free ends of the arc
Circle(4) = {6, 1, 4};
Line(5) = {5, 6};               // the flat top
Curve Loop(1) = {1, 2, 3, 5, 4};
Plane Surface(1) = {1};
Physical Curve("contact", 1) = {1, 2};
Physical Curve("free", 2) = {3, 4};
Physical Curve("traction", 3) = {5};
Physical Surface("body", 1) = {1};
