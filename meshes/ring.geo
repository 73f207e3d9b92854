// 2D annulus (plane z = 0) centred at (cx, cy) with radii r_inner < r_outer, structured quad4: n_around
// divisions around (in four transfinite quarter patches) and n_wall through the wall, both scaled by refine.
DefineConstant[
  r_inner = 0.5, r_outer = 1,
  n_around = 32, n_wall = 4,
  refine = 1,
  cx = 0, cy = 0
];
If (r_inner <= 0 || r_outer <= r_inner)
  Error("ring.geo: need 0 < r_inner < r_outer (got r_inner = %g, r_outer = %g)", r_inner, r_outer);
  Abort;
EndIf
na = Round(n_around * refine); If (na < 4) na = 4; EndIf
nw = Round(n_wall * refine); If (nw < 1) nw = 1; EndIf
Point(1) = {cx, cy, 0};
For i In {0 : 3}
  Point(2 + i) = {cx + r_inner * Cos(i * Pi / 2), cy + r_inner * Sin(i * Pi / 2), 0};
  Point(6 + i) = {cx + r_outer * Cos(i * Pi / 2), cy + r_outer * Sin(i * Pi / 2), 0};
EndFor
For i In {0 : 3}
  j = (i + 1) % 4;
  Circle(1 + i) = {2 + i, 1, 2 + j};
  Circle(5 + i) = {6 + i, 1, 6 + j};
  Line(9 + i) = {2 + i, 6 + i};
EndFor
For i In {0 : 3}
  j = (i + 1) % 4;
  Transfinite Curve{1 + i, 5 + i} = Floor((i + 1) * na / 4) - Floor(i * na / 4) + 1;
  Transfinite Curve{9 + i} = nw + 1;
  Curve Loop(1 + i) = {9 + i, 5 + i, -(9 + j), -(1 + i)};   // counter-clockwise: positive quads
  Plane Surface(1 + i) = {1 + i};
  Transfinite Surface{1 + i};
  Recombine Surface{1 + i};
EndFor
Physical Surface("body") = {1 : 4};
Physical Curve("inner") = {1 : 4};
Physical Curve("outer") = {5 : 8};
Physical Curve("boundary") = {1 : 8};   // inner and outer: the whole boundary
