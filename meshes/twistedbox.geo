// twistedbox.geo: hexbody.geo with a twisted contact face, the saddle through the corner
// heights 0, 0.1, 0.1, 0 (x = 0 and Lx at z = 0, then at z = Lz): the outward normal
// turns by about 6 degrees from the middle to each corner. Labels and parameters: hexbody.geo.
y10 = 0.1;
y01 = 0.1;
Include "hexbody.geo";
