// arc.geo: a block whose contact side (bottom, physical curve 1) is a concave arc that bulges
// into the body (centre (1, -2.4), radius 2.6: from (0, 0) up to y = 0.2 and down to (2, 0)); the
// held-out test of the solvers (tests/run_tests.sh) runs the paper scene on it
h = 0.04;
Point(1) = {0, 0, 0, h}; Point(2) = {2, 0, 0, h}; Point(3) = {2, 1, 0, h}; Point(4) = {0, 1, 0, h};
Point(5) = {1, -2.4, 0, h};   // centre of the arc through (0,0), (2,0): radius 2.6, top at y = 0.2
Circle(1) = {1, 5, 2};
Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Curve("contact", 1) = {1}; Physical Curve("right", 2) = {2}; Physical Curve("traction", 3) = {3}; Physical Curve("left", 4) = {4};
Physical Surface("body", 1) = {1};
