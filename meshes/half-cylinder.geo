// A half cylinder (the lower half, axis along y) of radius R and length L with a flat top: the indenter of the 3D
// ironing scene. Axis at (x0, y from y0 to y0 + L, z0); structured hexahedra: n_arc cells along the arc, n_radial
// through the radius (a quarter-square core), n_length along the axis; counts scaled by refine.
DefineConstant[
  R = 3, L = 4, x0 = 0, y0 = 0, z0 = 3,
  n_arc = 16, n_radial = 4, n_length = 8,
  refine = 1
];
If (R <= 0 || L <= 0)
  Error("half-cylinder.geo: need R > 0 and L > 0");
  Abort;
EndIf
na = Round(n_arc * refine / 2); If (na < 1) na = 1; EndIf
nr = Round(n_radial * refine); If (nr < 1) nr = 1; EndIf
nl = Round(n_length * refine); If (nl < 1) nl = 1; EndIf
c = 0.5 * R; // half-width of the core block
// cross-section in the x-z plane at y = y0 (the lower half disk), two patches left and right of the vertical
Point(1) = {x0, y0, z0};
Point(2) = {x0 - R, y0, z0};
Point(3) = {x0 + R, y0, z0};
Point(4) = {x0, y0, z0 - R};
Point(5) = {x0 - c, y0, z0};
Point(6) = {x0 + c, y0, z0};
Point(7) = {x0, y0, z0 - c};
Point(8) = {x0 - R * Sqrt(0.5), y0, z0 - R * Sqrt(0.5)};
Point(9) = {x0 + R * Sqrt(0.5), y0, z0 - R * Sqrt(0.5)};
Point(10) = {x0 - c, y0, z0 - c};
Point(11) = {x0 + c, y0, z0 - c};
Circle(1) = {2, 1, 8}; Circle(2) = {8, 1, 4}; Circle(3) = {4, 1, 9}; Circle(4) = {9, 1, 3};
Line(5) = {2, 5}; Line(6) = {5, 1}; Line(7) = {1, 6}; Line(8) = {6, 3};
Line(9) = {5, 10}; Line(10) = {10, 7}; Line(11) = {7, 11}; Line(12) = {11, 6}; Line(13) = {1, 7};
Line(14) = {8, 10}; Line(15) = {4, 7}; Line(16) = {9, 11};
Curve Loop(1) = {5, 9, -14, -1}; Plane Surface(1) = {1};        // left outer
Curve Loop(2) = {14, 10, -15, -2}; Plane Surface(2) = {2};      // lower left outer
Curve Loop(3) = {15, 11, -16, -3}; Plane Surface(3) = {3};      // lower right outer
Curve Loop(4) = {16, 12, 8, -4}; Plane Surface(4) = {4};        // right outer
Curve Loop(5) = {6, 13, -10, -9}; Plane Surface(5) = {5};       // core left
Curve Loop(6) = {7, -12, -11, -13}; Plane Surface(6) = {6};     // core right
Transfinite Curve{1, 2, 3, 4, 9, 10, 11, 12, 6, 7, 13} = na + 1;
Transfinite Curve{5, 8, 14, 15, 16} = nr + 1;
Transfinite Surface{1, 2, 3, 4, 5, 6};
Recombine Surface{1, 2, 3, 4, 5, 6};
out[] = Extrude{0, L, 0}{ Surface{1, 2, 3, 4, 5, 6}; Layers{nl}; Recombine; };
vols[] = Volume{:};
e = 1e-6 * R;
top[] = Surface In BoundingBox{x0 - R - e, y0 - e, z0 - e, x0 + R + e, y0 + L + e, z0 + e};
ends[] = Surface In BoundingBox{x0 - R - e, y0 - e, z0 - R - e, x0 + R + e, y0 + e, z0 + e};
ends[] += Surface In BoundingBox{x0 - R - e, y0 + L - e, z0 - R - e, x0 + R + e, y0 + L + e, z0 + e};
skin[] = CombinedBoundary{ Volume{vols[]}; };
arc[] = {};
For k In {0 : #skin[] - 1}
  s = Fabs(skin[k]);
  keep = 1;
  For j In {0 : #top[] - 1}
    If (s == top[j]) keep = 0; EndIf
  EndFor
  For j In {0 : #ends[] - 1}
    If (s == ends[j]) keep = 0; EndIf
  EndFor
  If (keep) arc[] += s; EndIf
EndFor
Physical Volume("indenter") = {vols[]};
Physical Surface("indenter-contact") = {arc[]};
Physical Surface("indenter-top") = {top[]};
