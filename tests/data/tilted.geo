// tilted.geo (tests): the paper's block (Lx x Ly, nx x ny cells, structured) turned by the
// angle a (degrees) about the origin; labels as meshes/rectangle.geo: 1 bottom (contact),
// 2 right, 3 top (traction), 4 left.
DefineConstant[
  Lx = {2, Name "Parameters/Lx"}, Ly = {1, Name "Parameters/Ly"},
  nx = {16, Name "Parameters/nx"}, ny = {8, Name "Parameters/ny"},
  a = {30, Name "Parameters/a"}
];
c = Cos(a*Pi/180); s = Sin(a*Pi/180);
Point(1) = {0, 0, 0};
Point(2) = {Lx*c, Lx*s, 0};
Point(3) = {Lx*c - Ly*s, Lx*s + Ly*c, 0};
Point(4) = {-Ly*s, Ly*c, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Transfinite Line{1, 3} = nx + 1;
Transfinite Line{2, 4} = ny + 1;
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Surface{1};
Physical Curve("contact", 1) = {1};
Physical Curve("right", 2) = {2};
Physical Curve("traction", 3) = {3};
Physical Curve("left", 4) = {4};
Physical Surface("body", 1) = {1};
