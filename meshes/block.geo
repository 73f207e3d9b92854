// 3D box [x0, x0+lx] x [y0, y0+ly] x [z0, z0+lz], structured hex8 (transfinite + recombine).
// Element count: (nx*refine) x (ny*refine) x (nz*refine). grading != 1 grades the x divisions geometrically, in
// opposite directions at y = y0 and y = y0 + ly (slanted lines: distorted hexahedra; tests/bench/stress uses it).
DefineConstant[
  lx = 1, ly = 1, lz = 1,
  x0 = 0, y0 = 0, z0 = 0,
  nx = 4, ny = 4, nz = 4,
  refine = 1, grading = 1
];
Point(1) = {x0, y0, z0};
Point(2) = {x0 + lx, y0, z0};
Point(3) = {x0 + lx, y0 + ly, z0};
Point(4) = {x0, y0 + ly, z0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = Round(nx * refine) + 1 Using Progression grading;
Transfinite Curve{2, 4} = Round(ny * refine) + 1;
Transfinite Surface{1};
Recombine Surface{1};
// Extrusion with layers keeps the mesh structured and hexahedral.
out[] = Extrude{0, 0, lz}{ Surface{1}; Layers{Round(nz * refine)}; Recombine; };
// out[0] = top, out[1] = volume, out[2..5] = sides from curves 1..4 (y = y0, x = x0+lx, y = y0+ly, x = x0).
Physical Volume("body") = {out[1]};
Physical Surface("zmin") = {1};
Physical Surface("zmax") = {out[0]};
Physical Surface("ymin") = {out[2]};
Physical Surface("xmax") = {out[3]};
Physical Surface("ymax") = {out[4]};
Physical Surface("xmin") = {out[5]};
