// A V-bottomed body for the turn check of the contact boundary: apex (0,0), contact edges to
// (+-1, s); each edge makes the angle turn/2 with the horizontal, so their outward normals
// differ by 'turn' degrees. nl, nr: cells on the left and right edges (pr: the right edge's
// progression, for unequal edge lengths at the apex).
DefineConstant[ turn = {120, Name "turn"}, nl = {6, Name "nl"}, nr = {6, Name "nr"}, pr = {1, Name "pr"}, h = {0.2, Name "h"} ];
a = turn/2*Pi/180;
s = Tan(a);
Point(1) = {0,0,0,h}; Point(2) = {1,s,0,h}; Point(3) = {1,s+1,0,h}; Point(4) = {-1,s+1,0,h}; Point(5) = {-1,s,0,h};
Line(1) = {1,2}; Line(2) = {2,3}; Line(3) = {3,4}; Line(4) = {4,5}; Line(5) = {5,1};
Transfinite Curve{5} = nl+1; Transfinite Curve{1} = nr+1 Using Progression pr;
Curve Loop(1) = {1,2,3,4,5}; Plane Surface(1) = {1};
Physical Curve("contact",1) = {1,5}; Physical Curve("right",2) = {2}; Physical Curve("traction",3) = {3}; Physical Curve("left",4) = {4};
Physical Surface("body",1) = {1};
