// box.geo: the structured mesh of a box (0,Lx) x (0,Ly) x (0,Lz) in tetrahedra: the
// rectangle (0,Lx) x (0,Ly) of rectangle.geo (nx x ny squares, each cut into two triangles)
// extruded along z in nz layers, each prism cut into three tetrahedra.
// Generated on demand by edp/solve.edp; by hand:
//   gmsh -3 -format msh22 -setnumber nx 8 -setnumber ny 4 -setnumber nz 4 box.geo -o box.msh
// Physical tags are the FreeFEM labels of edp/lib/forms.idp: 1 the bottom y = 0 (contact),
// 2 x = Lx, 3 the top y = Ly (traction), 4 x = 0, 5 the face z = 0, 6 the face z = Lz.
DefineConstant[
  Lx = {2, Name "Parameters/Lx"},
  Ly = {1, Name "Parameters/Ly"},
  Lz = {0.5, Name "Parameters/Lz"},
  nx = {8, Name "Parameters/nx"},
  ny = {4, Name "Parameters/ny"},
  nz = {2, Name "Parameters/nz"}
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
side[] = Extrude {0, 0, Lz} { Surface{1}; Layers{nz}; };
// side[0]: the face z = Lz, side[1]: the volume, side[2..5]: the faces swept by lines 1..4
Physical Surface("contact", 1) = {side[2]};
Physical Surface("right", 2) = {side[3]};
Physical Surface("traction", 3) = {side[4]};
Physical Surface("left", 4) = {side[5]};
Physical Surface("front", 5) = {1};
Physical Surface("back", 6) = {side[0]};
Physical Volume("body", 1) = {side[1]};
