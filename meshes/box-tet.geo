// 3D box [x0, x0+lx] x [y0, y0+ly] x [z0, z0+lz] meshed with tetrahedra (TRI3 boundary faces), element size h /
// refine. The tetrahedral companion of block.geo (same groups).
DefineConstant[
  lx = 1, ly = 1, lz = 1,
  x0 = 0, y0 = 0, z0 = 0,
  h = 0.25,
  refine = 1
];
If (lx <= 0 || ly <= 0 || lz <= 0 || h <= 0)
  Error("box-tet.geo: need positive lx, ly, lz and h");
  Abort;
EndIf
Point(1) = {x0, y0, z0, h / refine};
Point(2) = {x0 + lx, y0, z0, h / refine};
Point(3) = {x0 + lx, y0 + ly, z0, h / refine};
Point(4) = {x0, y0 + ly, z0, h / refine};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
out[] = Extrude{0, 0, lz}{ Surface{1}; };
// out[0] = top, out[1] = volume, out[2..5] = sides from curves 1..4 (y = y0, x = x0+lx, y = y0+ly, x = x0).
Physical Volume("body") = {out[1]};
Physical Surface("zmin") = {1};
Physical Surface("zmax") = {out[0]};
Physical Surface("ymin") = {out[2]};
Physical Surface("xmax") = {out[3]};
Physical Surface("ymax") = {out[4]};
Physical Surface("xmin") = {out[5]};
