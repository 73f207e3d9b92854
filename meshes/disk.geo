// 2D disk (plane z = 0) of the given radius centred at (cx, cy), all-quad "O-grid": a central square of
// n x n quads and four curved patches of n x n_radial quads, so n_around = 4 n divisions on the rim.
// Counts scale with refine; elements: n^2 + 4 n n_radial (defaults: 8 x 8 + 4 x 8 x 4 = 192).
DefineConstant[
  radius = 1,
  n = 8, n_radial = 4,
  square = 0.5,      // half-diagonal of the central square, as a fraction of the radius
  refine = 1,
  cx = 0, cy = 0
];
If (radius <= 0 || square <= 0 || square >= 1)
  Error("disk.geo: need radius > 0 and 0 < square < 1 (got radius = %g, square = %g)", radius, square);
  Abort;
EndIf
nq = Round(n * refine); If (nq < 1) nq = 1; EndIf
nr = Round(n_radial * refine); If (nr < 1) nr = 1; EndIf
Point(1) = {cx, cy, 0};
For i In {0 : 3}
  a = Pi / 4 + i * Pi / 2;
  Point(2 + i) = {cx + square * radius * Cos(a), cy + square * radius * Sin(a), 0};
  Point(6 + i) = {cx + radius * Cos(a), cy + radius * Sin(a), 0};
EndFor
For i In {0 : 3}
  j = (i + 1) % 4;
  Line(1 + i) = {2 + i, 2 + j};        // square sides
  Circle(5 + i) = {6 + i, 1, 6 + j};   // rim arcs
  Line(9 + i) = {2 + i, 6 + i};        // spokes
EndFor
Transfinite Curve{1 : 8} = nq + 1;
Transfinite Curve{9 : 12} = nr + 1;
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
For i In {0 : 3}
  j = (i + 1) % 4;
  Curve Loop(2 + i) = {9 + i, 5 + i, -(9 + j), -(1 + i)};   // counter-clockwise: positive quads
  Plane Surface(2 + i) = {2 + i};
EndFor
Transfinite Surface{1 : 5};
Recombine Surface{1 : 5};
Physical Surface("body") = {1 : 5};
Physical Curve("boundary") = {5 : 8};
