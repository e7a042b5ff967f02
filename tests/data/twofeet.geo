// twofeet.geo (tests): the paper's block (0,2) x (0,1) standing on two feet: a notch
// (0.6,1.4) x (0,0.3) cut out of its bottom, so that the contact boundary Gamma3 (label 1)
// is in two pieces, x from 0 to 0.6 and from 1.4 to 2. The notch's sides and roof are
// traction free (label 5), the right side label 2, the top the traction (3), the left side 4.
// The figures must draw Gamma3 in two pieces, the gap between them blank.
DefineConstant[ h = {0.1, Name "h"} ];
Point(1) = {0, 0, 0, h}; Point(2) = {0.6, 0, 0, h}; Point(3) = {0.6, 0.3, 0, h};
Point(4) = {1.4, 0.3, 0, h}; Point(5) = {1.4, 0, 0, h}; Point(6) = {2, 0, 0, h};
Point(7) = {2, 1, 0, h}; Point(8) = {0, 1, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 1};
Curve Loop(1) = {1:8}; Plane Surface(1) = {1};
Physical Curve("contact", 1) = {1, 5};
Physical Curve("right", 2) = {6};
Physical Curve("traction", 3) = {7};
Physical Curve("left", 4) = {8};
Physical Curve("notch", 5) = {2, 3, 4};
Physical Surface("body", 1) = {1};
