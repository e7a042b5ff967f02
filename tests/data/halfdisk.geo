// halfdisk.geo (tests): a half disk of diameter Lx, its flat side up, the arc the contact
// boundary (label 1), the flat top the traction (label 3). With v_x = 0 on the top, the arc's end
// nodes have one free component (v_y) but a horizontal normal: refused.
DefineConstant[
  Lx = {2, Name "Parameters/Lx"},
  Ly = {1, Name "Parameters/Ly"},
  nx = {40, Name "Parameters/nx"},
  ny = {20, Name "Parameters/ny"}
];
R = Lx/2;
h = Lx/nx;
Point(1) = {0, R, 0, h};
Point(2) = {R, R, 0, h};        // the centre
Point(3) = {Lx, R, 0, h};
Point(4) = {R, 0, 0, h};        // the lowest point
Circle(1) = {1, 2, 4};
Circle(2) = {4, 2, 3};
Line(3) = {3, 1};
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};
Physical Curve("contact", 1) = {1, 2};
Physical Curve("traction", 3) = {3};
Physical Surface("body", 1) = {1};
