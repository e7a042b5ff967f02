// rectangle.geo: the structured mesh of a rectangle (0,Lx) x (0,Ly), nx x ny squares
// each cut into two triangles by one diagonal (paper section 5, Fig. 1: Lx = 2, Ly = 1,
// h = 1/33); -setnumber diagonal 1 cuts the squares by the other diagonal.
// Generated on demand by edp/solve.edp; by hand:
//   gmsh -2 -format msh22 -setnumber nx 66 -setnumber ny 33 rectangle.geo -o paper.msh
// Physical tags are the FreeFEM labels of edp/lib/forms.idp.
DefineConstant[
  Lx = {2, Name "Parameters/Lx"},
  Ly = {1, Name "Parameters/Ly"},
  nx = {66, Name "Parameters/nx"},
  ny = {33, Name "Parameters/ny"},
  diagonal = {0, Choices{0 = "Left (gmsh default)", 1 = "Right"}, Name "Parameters/diagonal"}
];
Point(1) = {0, 0, 0};
Point(2) = {Lx, 0, 0};
Point(3) = {Lx, Ly, 0};
Point(4) = {0, Ly, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = nx + 1;
Transfinite Curve{2, 4} = ny + 1;
If (diagonal == 1)
  Transfinite Surface{1} Right;     // the other orientation of the diagonals
Else
  Transfinite Surface{1};
EndIf
Physical Curve("contact", 1) = {1};
Physical Curve("right", 2) = {2};
Physical Curve("traction", 3) = {3};
Physical Curve("left", 4) = {4};
Physical Surface("body", 1) = {1};
