// Thin-walled tube (hollow circular cylinder) along z: radii r_inner < r_outer about the axis through (cx, cy),
// from z = z0 to z0 + length. Structured hex8: the annulus (n_around x n_wall quads, in four transfinite quarter
// patches, as ring.geo) extruded along z in n_length layers; all counts scaled by refine.
DefineConstant[
  r_inner = 0.9, r_outer = 1,
  length = 0.5, z0 = 0,
  n_around = 48, n_wall = 2, n_length = 4,
  refine = 1,
  cx = 0, cy = 0
];
If (r_inner <= 0 || r_outer <= r_inner || length <= 0)
  Error("tube.geo: need 0 < r_inner < r_outer and length > 0 (got r_inner = %g, r_outer = %g, length = %g)",
        r_inner, r_outer, length);
  Abort;
EndIf
na = Round(n_around * refine); If (na < 4) na = 4; EndIf
nw = Round(n_wall * refine); If (nw < 1) nw = 1; EndIf
nl = Round(n_length * refine); If (nl < 1) nl = 1; EndIf
Point(1) = {cx, cy, z0};
For i In {0 : 3}
  Point(2 + i) = {cx + r_inner * Cos(i * Pi / 2), cy + r_inner * Sin(i * Pi / 2), z0};
  Point(6 + i) = {cx + r_outer * Cos(i * Pi / 2), cy + r_outer * Sin(i * Pi / 2), z0};
EndFor
For i In {0 : 3}
  j = (i + 1) % 4;
  Circle(1 + i) = {2 + i, 1, 2 + j};
  Circle(5 + i) = {6 + i, 1, 6 + j};
  Line(9 + i) = {2 + i, 6 + i};
EndFor
bodies[] = {};
inner[] = {};
outer[] = {};
ends[] = {};
For i In {0 : 3}
  j = (i + 1) % 4;
  Transfinite Curve{1 + i, 5 + i} = Floor((i + 1) * na / 4) - Floor(i * na / 4) + 1;
  Transfinite Curve{9 + i} = nw + 1;
  Curve Loop(1 + i) = {9 + i, 5 + i, -(9 + j), -(1 + i)};
  Plane Surface(1 + i) = {1 + i};
  Transfinite Surface{1 + i};
  Recombine Surface{1 + i};
  out[] = Extrude{0, 0, length}{ Surface{1 + i}; Layers{nl}; Recombine; };
  // out[0] = end face, out[1] = volume, out[2..5] = faces swept from the loop's curves in loop order
  ends[] += {1 + i, out[0]};
  bodies[] += out[1];
  outer[] += out[3];
  inner[] += out[5];
EndFor
Physical Volume("body") = {bodies[]};
Physical Surface("inner") = {inner[]};
Physical Surface("outer") = {outer[]};
Physical Surface("ends") = {ends[]};
