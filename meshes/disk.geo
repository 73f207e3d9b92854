// 2D disk (plane z = 0) of the given radius centred at (cx, cy), all-quad "O-grid": a central square of
// n x n quads and four curved patches of n x n_radial quads, so n_around = 4 n divisions on the rim.
// Counts scale with refine; elements: n^2 + 4 n n_radial (defaults: 8 x 8 + 4 x 8 x 4 = 192).
// aspect != 1 makes it an ellipse with semi-axes radius (x) and aspect * radius (y). Its rim arcs are splines
// through 25 points of the ellipse each (rim nodes within 5e-7 radius of it): gmsh 4.8's Ellipse arcs fail across
// the angle Pi and its Dilate leaves a Circle's interior on the circle.
DefineConstant[
  radius = 1,
  n = 8, n_radial = 4,
  square = 0.5,      // half-diagonal of the central square, as a fraction of the radius
  refine = 1,
  cx = 0, cy = 0,
  aspect = 1         // y semi-axis / x semi-axis
];
If (radius <= 0 || square <= 0 || square >= 1 || aspect <= 0)
  Error("disk.geo: need radius > 0, 0 < square < 1 and aspect > 0 (got radius = %g, square = %g, aspect = %g)",
        radius, square, aspect);
  Abort;
EndIf
nq = Round(n * refine); If (nq < 1) nq = 1; EndIf
nr = Round(n_radial * refine); If (nr < 1) nr = 1; EndIf
Point(1) = {cx, cy, 0};
For i In {0 : 3}
  a = Pi / 4 + i * Pi / 2;
  Point(2 + i) = {cx + square * radius * Cos(a), cy + aspect * square * radius * Sin(a), 0};
  Point(6 + i) = {cx + radius * Cos(a), cy + aspect * radius * Sin(a), 0};
EndFor
For i In {0 : 3}
  j = (i + 1) % 4;
  Line(1 + i) = {2 + i, 2 + j};        // square sides
  If (aspect == 1)
    Circle(5 + i) = {6 + i, 1, 6 + j};   // rim arcs
  Else
    arc[] = {6 + i};
    For k In {1 : 23}
      a = Pi / 4 + i * Pi / 2 + k * Pi / 48;
      arc[] += newp;
      Point(newp) = {cx + radius * Cos(a), cy + aspect * radius * Sin(a), 0};
    EndFor
    arc[] += 6 + j;
    Spline(5 + i) = arc[];
  EndIf
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
