// flipped.geo: the rectangle of meshes/rectangle.geo with the contact label on the top
DefineConstant[
  Lx = {2, Name "Parameters/Lx"},
  Ly = {1, Name "Parameters/Ly"},
  nx = {66, Name "Parameters/nx"},
  ny = {33, Name "Parameters/ny"}
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
Transfinite Surface{1};
Physical Curve("contact", 1) = {3};
Physical Curve("right", 2) = {2};
Physical Curve("traction", 3) = {1};
Physical Curve("left", 4) = {4};
Physical Surface("body", 1) = {1};
