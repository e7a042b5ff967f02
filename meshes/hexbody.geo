// hexbody.geo: a hexahedral body (0,Lx) x (., Ly) x (0,Lz) whose bottom (the contact face) is
// ruled: its corners sit at the heights y00 (x = 0, z = 0), y10 (x = Lx, z = 0), y01 (x = 0,
// z = Lz) and y11 (x = Lx, z = Lz), the face between them the bilinear surface through them.
// Equal heights give the box of box.geo (in another cut into tetrahedra); y10 = y11 = s a face
// sloped along x; y10 = y01 = t, y00 = y11 = 0 a twisted face (a saddle, its normal turning
// from node to node). The top y = Ly is flat. The faces are structured (nx x nz squares on
// the bottom and top, ny along y, each cut into two triangles), the inside is meshed by gmsh's
// tetrahedral mesher to match them. Generated on demand by edp/lib/meshes.idp; by hand:
//   gmsh -3 -format msh22 -setnumber y10 0.2 -setnumber y01 0.2 hexbody.geo -o hexbody.msh
// Physical tags are the FreeFEM labels of edp/lib/forms.idp: 1 the bottom (contact), 2 x = Lx,
// 3 the top y = Ly (traction), 4 x = 0, 5 the face z = 0, 6 the face z = Lz.
DefineConstant[
  Lx = {2, Name "Parameters/Lx"},
  Ly = {1, Name "Parameters/Ly"},
  Lz = {1, Name "Parameters/Lz"},
  nx = {8, Name "Parameters/nx"},
  ny = {4, Name "Parameters/ny"},
  nz = {4, Name "Parameters/nz"},
  y00 = {0, Name "Parameters/y00"},
  y10 = {0, Name "Parameters/y10"},
  y01 = {0, Name "Parameters/y01"},
  y11 = {0, Name "Parameters/y11"}
];
Point(1) = {0, y00, 0};
Point(2) = {Lx, y10, 0};
Point(3) = {Lx, y11, Lz};
Point(4) = {0, y01, Lz};
Point(5) = {0, Ly, 0};
Point(6) = {Lx, Ly, 0};
Point(7) = {Lx, Ly, Lz};
Point(8) = {0, Ly, Lz};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};      // the bottom
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};      // the top
Line(9) = {1, 5}; Line(10) = {2, 6}; Line(11) = {3, 7}; Line(12) = {4, 8};   // the sides
Curve Loop(1) = {1, 2, 3, 4};     Surface(1) = {1};        // bottom: bilinear through its corners
Curve Loop(2) = {5, 6, 7, 8};     Surface(2) = {2};        // top
Curve Loop(3) = {2, 11, -6, -10}; Surface(3) = {3};        // x = Lx
Curve Loop(4) = {4, 9, -8, -12};  Surface(4) = {4};        // x = 0
Curve Loop(5) = {1, 10, -5, -9};  Surface(5) = {5};        // z = 0
Curve Loop(6) = {3, 12, -7, -11}; Surface(6) = {6};        // z = Lz
Surface Loop(1) = {1, 2, 3, 4, 5, 6};
Volume(1) = {1};
Transfinite Curve{1, 3, 5, 7} = nx + 1;
Transfinite Curve{2, 4, 6, 8} = nz + 1;
Transfinite Curve{9, 10, 11, 12} = ny + 1;
Transfinite Surface{1, 2, 3, 4, 5, 6};
Physical Surface("contact", 1) = {1};
Physical Surface("right", 2) = {3};
Physical Surface("traction", 3) = {2};
Physical Surface("left", 4) = {4};
Physical Surface("front", 5) = {5};
Physical Surface("back", 6) = {6};
Physical Volume("body", 1) = {1};
