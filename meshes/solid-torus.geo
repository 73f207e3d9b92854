// Solid torus about the axis through (cx, cy, cz) parallel to z: major radius R, tube radius r (hole radius R - r,
// outer radius R + r). Structured hex8: the tube's cross-section is an O-grid disk (a central square of n x n quads
// and four curved patches of n x n_radial quads, as disk.geo) swept around the axis in four quarter turns (gmsh
// cannot revolve by 2 Pi at once) with n_around layers in all. Elements: n_around x (n^2 + 4 n n_radial), each count
// scaled by refine; the defaults (32 x (4 + 8)) give 384 hexahedra. Hauret et al. Sec. 6.5: R = 7, r = 1.
DefineConstant[
  R = 7, r = 1,
  n = 2, n_radial = 1, n_around = 32,
  square = 0.5,      // half-diagonal of the central square, as a fraction of r
  refine = 1,
  cx = 0, cy = 0, cz = 0
];
If (r <= 0 || R <= r || square <= 0 || square >= 1)
  Error("solid-torus.geo: need 0 < r < R and 0 < square < 1 (got r = %g, R = %g, square = %g)", r, R, square);
  Abort;
EndIf
nq = Round(n * refine); If (nq < 1) nq = 1; EndIf
nr = Round(n_radial * refine); If (nr < 1) nr = 1; EndIf
na = Round(n_around * refine); If (na < 4) na = 4; EndIf

// Cross-section in the plane y = cy, centred at (cx + R, cy, cz).
ox = cx + R;
Point(1) = {ox, cy, cz};
For i In {0 : 3}
  a = Pi / 4 + i * Pi / 2;
  Point(2 + i) = {ox + square * r * Cos(a), cy, cz + square * r * Sin(a)};
  Point(6 + i) = {ox + r * Cos(a), cy, cz + r * Sin(a)};
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
  Curve Loop(2 + i) = {9 + i, 5 + i, -(9 + j), -(1 + i)};
  Plane Surface(2 + i) = {2 + i};
EndFor
Transfinite Surface{1 : 5};
Recombine Surface{1 : 5};

source[] = {1, 2, 3, 4, 5};
bodies[] = {};
outer[] = {};
For q In {0 : 3}
  layers = Floor((q + 1) * na / 4) - Floor(q * na / 4);
  top[] = {};
  For s In {0 : 4}
    out[] = Extrude{{0, 0, 1}, {cx, cy, cz}, Pi / 2}{ Surface{source[s]}; Layers{layers}; Recombine; };
    // out[0] = end face, out[1] = volume, out[2..5] = faces swept from the loop's curves in loop order; the rim
    // arc is the second curve of a patch's loop.
    top[] += out[0];
    bodies[] += out[1];
    If (s > 0)
      outer[] += out[3];
    EndIf
  EndFor
  source[] = top[];
EndFor
// The last quarter turn ends on the starting cross-section; removing duplicates makes the seam share its nodes.
Coherence;

Physical Volume("body") = {bodies[]};
Physical Surface("outer") = {outer[]};
