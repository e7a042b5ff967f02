// slopedbox.geo: hexbody.geo with a contact face sloped along x: its corners at x = Lx sit
// 0.25 above those at x = 0 (a slope of 1 in 8 on the default Lx = 2). Labels and
// parameters: hexbody.geo.
y10 = 0.25;
y11 = 0.25;
Include "hexbody.geo";
