// Hollow torus about the axis through (cx, cy, cz) parallel to z: major radius R, tube wall from r_inner to
// r_outer. Structured hex8: the annular cross-section (n_tube x n_wall quads, in four transfinite quarter patches)
// is swept around the axis in four quarter turns (gmsh cannot revolve by 2 Pi at once) with n_around layers in all.
// Elements: n_around x n_tube x n_wall, each count scaled by refine. The defaults (118 x 34 x 2) give exactly
// 8024 hexahedra with nearly square faces on the skin; refine = 0.25 gives 30 x 9 x 1 = 270 (for CI).
DefineConstant[
  R = 76, r_outer = 24, r_inner = 19.5,
  n_around = 118, n_tube = 34, n_wall = 2,
  refine = 1,
  cx = 0, cy = 0, cz = 0
];
If (r_inner <= 0 || r_outer <= r_inner || R <= r_outer)
  Error("torus.geo: need 0 < r_inner < r_outer < R (got r_inner = %g, r_outer = %g, R = %g)", r_inner, r_outer, R);
  Abort;
EndIf
na = Round(n_around * refine); If (na < 4) na = 4; EndIf
nt = Round(n_tube * refine); If (nt < 4) nt = 4; EndIf
nw = Round(n_wall * refine); If (nw < 1) nw = 1; EndIf

// Cross-section in the plane y = cy, centred at (cx + R, cy, cz).
ox = cx + R;
Point(1) = {ox, cy, cz};
For i In {0 : 3}
  Point(2 + i) = {ox + r_inner * Cos(i * Pi / 2), cy, cz + r_inner * Sin(i * Pi / 2)};
  Point(6 + i) = {ox + r_outer * Cos(i * Pi / 2), cy, cz + r_outer * Sin(i * Pi / 2)};
EndFor
For i In {0 : 3}
  j = (i + 1) % 4;
  Circle(1 + i) = {2 + i, 1, 2 + j};   // inner arcs
  Circle(5 + i) = {6 + i, 1, 6 + j};   // outer arcs
  Line(9 + i) = {2 + i, 6 + i};        // radial lines
EndFor
For i In {0 : 3}
  j = (i + 1) % 4;
  // Divisions of patch i: an even split of nt into four (the quarters may differ by one).
  Transfinite Curve{1 + i, 5 + i} = Floor((i + 1) * nt / 4) - Floor(i * nt / 4) + 1;
  Transfinite Curve{9 + i} = nw + 1;
  // Loop order (inner, radial, outer, radial) fixes which lateral surface of the sweep is inner or outer.
  Curve Loop(1 + i) = {1 + i, 9 + j, -(5 + i), -(9 + i)};
  Plane Surface(1 + i) = {1 + i};
  Transfinite Surface{1 + i};
  Recombine Surface{1 + i};
EndFor

source[] = {1, 2, 3, 4};
bodies[] = {};
inner[] = {};
outer[] = {};
For q In {0 : 3}
  layers = Floor((q + 1) * na / 4) - Floor(q * na / 4);
  top[] = {};
  For s In {0 : 3}
    out[] = Extrude{{0, 0, 1}, {cx, cy, cz}, Pi / 2}{ Surface{source[s]}; Layers{layers}; Recombine; };
    // out[0] = end face, out[1] = volume, out[2..5] = faces swept from the loop's curves in loop order.
    top[] += out[0];
    bodies[] += out[1];
    inner[] += out[2];
    outer[] += out[4];
  EndFor
  source[] = top[];
EndFor
// The last quarter turn ends on the starting cross-section; removing duplicates makes the seam share its nodes.
Coherence;

Physical Volume("body") = {bodies[]};
Physical Surface("outer") = {outer[]};
Physical Surface("inner") = {inner[]};
