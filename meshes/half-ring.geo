// The lower half of a ring (an arch) of mean radius R and wall thickness t, centre (cx, cy): the ring beam of the
// elastic ring example (Hammer 2012, 8.4, after Tur et al. 2009). Structured quads: n_arc cells along the half
// circumference, n_wall through the wall; counts scaled by refine. Groups: ring, ring-contact (the outer arc),
// ring-inner, ring-left and ring-right (the end cross-sections at the centre height, driven in the scene).
DefineConstant[
  R = 100, t = 5, cx = 0, cy = 120,
  n_arc = 60, n_wall = 2,
  refine = 1
];
If (R <= 0 || t <= 0 || t >= R)
  Error("half-ring.geo: need 0 < t < R");
  Abort;
EndIf
na = Round(n_arc * refine / 2); If (na < 1) na = 1; EndIf
nw = Round(n_wall * refine); If (nw < 1) nw = 1; EndIf
ri = R - 0.5 * t; ro = R + 0.5 * t;
Point(1) = {cx, cy, 0};
Point(2) = {cx - ri, cy, 0}; Point(3) = {cx, cy - ri, 0}; Point(4) = {cx + ri, cy, 0};
Point(5) = {cx - ro, cy, 0}; Point(6) = {cx, cy - ro, 0}; Point(7) = {cx + ro, cy, 0};
Circle(1) = {2, 1, 3}; Circle(2) = {3, 1, 4};
Circle(3) = {5, 1, 6}; Circle(4) = {6, 1, 7};
Line(5) = {5, 2}; Line(6) = {6, 3}; Line(7) = {7, 4};
Curve Loop(1) = {5, 1, -6, -3}; Plane Surface(1) = {1};
Curve Loop(2) = {6, 2, -7, -4}; Plane Surface(2) = {2};
Transfinite Curve{1, 2, 3, 4} = na + 1;
Transfinite Curve{5, 6, 7} = nw + 1;
Transfinite Surface{1, 2};
Recombine Surface{1, 2};
Physical Surface("ring") = {1, 2};
Physical Curve("ring-contact") = {3, 4};
Physical Curve("ring-inner") = {1, 2};
Physical Curve("ring-left") = {5};
Physical Curve("ring-right") = {7};
