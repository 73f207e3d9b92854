// Contact patch test in 3D: two stacked boxes with non-matching interface meshes.
// lower = [0, lx] x [0, ly] x [-h_lower, 0] with n_lower x n_lower x nz_lower cells, upper = [0, lx] x [0, ly] x
// [gap, gap + h_upper] with n_upper x n_upper x nz_upper cells; hexahedra (tets = 0, QUAD4 contact faces) or
// tetrahedra (tets = 1, TRI3 faces); counts scaled by refine. The bodies share no nodes.
DefineConstant[
  lx = 1, ly = 1, h_lower = 0.5, h_upper = 0.5, gap = 0,
  n_lower = 3, n_upper = 4, nz_lower = 2, nz_upper = 2,
  tets = 0,
  refine = 1
];
If (lx <= 0 || ly <= 0 || h_lower <= 0 || h_upper <= 0 || gap < 0 || n_lower < 1 || n_upper < 1)
  Error("patch-test-3d.geo: need positive sizes and counts, gap >= 0");
  Abort;
EndIf
Geometry.AutoCoherence = 0;
nl = Round(n_lower * refine); nu = Round(n_upper * refine);
ml = Round(nz_lower * refine); mu = Round(nz_upper * refine);
If (ml < 1) ml = 1; EndIf
If (mu < 1) mu = 1; EndIf

Point(1) = {0, 0, -h_lower}; Point(2) = {lx, 0, -h_lower}; Point(3) = {lx, ly, -h_lower}; Point(4) = {0, ly, -h_lower};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = nl + 1;
Transfinite Surface{1};
If (tets == 0) Recombine Surface{1}; EndIf
If (tets == 0)
  lo[] = Extrude{0, 0, h_lower}{ Surface{1}; Layers{ml}; Recombine; };
Else
  lo[] = Extrude{0, 0, h_lower}{ Surface{1}; Layers{ml}; };
EndIf

p = newp;
Point(p) = {0, 0, gap}; Point(p + 1) = {lx, 0, gap}; Point(p + 2) = {lx, ly, gap}; Point(p + 3) = {0, ly, gap};
l = newl;
Line(l) = {p, p + 1}; Line(l + 1) = {p + 1, p + 2}; Line(l + 2) = {p + 2, p + 3}; Line(l + 3) = {p + 3, p};
cl = newll;
Curve Loop(cl) = {l, l + 1, l + 2, l + 3};
su = news;
Plane Surface(su) = {cl};
Transfinite Curve{l, l + 1, l + 2, l + 3} = nu + 1;
Transfinite Surface{su};
If (tets == 0) Recombine Surface{su}; EndIf
If (tets == 0)
  up[] = Extrude{0, 0, h_upper}{ Surface{su}; Layers{mu}; Recombine; };
Else
  up[] = Extrude{0, 0, h_upper}{ Surface{su}; Layers{mu}; };
EndIf
// Extrude: [0] top, [1] volume, [2..5] sides from curves (y = 0, x = lx, y = ly, x = 0)
Physical Volume("lower") = {lo[1]};
Physical Volume("upper") = {up[1]};
Physical Surface("lower-bottom") = {1};
Physical Surface("lower-top") = {lo[0]};
Physical Surface("upper-bottom") = {su};
Physical Surface("upper-top") = {up[0]};
Physical Surface("xmin") = {lo[5], up[5]};
Physical Surface("ymin") = {lo[2], up[2]};
