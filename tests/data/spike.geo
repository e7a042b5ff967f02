// spike.geo (tests): a V-shaped body whose contact boundary (label 1, both slanted sides)
// turns by about 150 degrees at its lowest point: refused, its normal there is undefined.
DefineConstant[ nx = {4, Name "Parameters/nx"}, ny = {2, Name "Parameters/ny"} ];
h = 1/nx;
Point(1) = {0, 4, 0, h};
Point(2) = {1, 0, 0, h};
Point(3) = {2, 4, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 1};
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};
Physical Curve("contact", 1) = {1, 2};
Physical Curve("traction", 3) = {3};
Physical Surface("body", 1) = {1};
