// Konyukhov & Schweizerhof (2005), Example 6.3: a short semi-cylinder of outer radius R and length l (along y),
// the lower half of a tube with wall thickness t, its axis at height R (the lowest outer line on z = 0). The paper
// meshes it with 16 x 3 linear solid-shell elements: here 16 around x 3 along y x 1 through the wall, hex8 (QUAD4
// faces). Groups: `outer` (the contact surface), `cut` (the two flat strips at the axis height, where the motion is
// prescribed).
DefineConstant[
  R = 1, t = 0.1, l = 0.4,
  n_around = 16, n_length = 3, n_wall = 1,
  refine = 1
];
If (R <= 0 || t <= 0 || t >= R || l <= 0 || n_around < 2)
  Error("ks-semicylinder.geo: need R > t > 0, l > 0 and n_around >= 2");
  Abort;
EndIf
r = R - t;
Point(1) = {0, 0, R};      // the axis
Point(2) = {-R, 0, R};
Point(3) = {0, 0, 0};
Point(4) = {R, 0, R};
Point(5) = {-r, 0, R};
Point(6) = {0, 0, R - r};
Point(7) = {r, 0, R};
Circle(1) = {2, 1, 3};     // outer, left quarter
Circle(2) = {3, 1, 4};     // outer, right quarter
Circle(3) = {5, 1, 6};     // inner
Circle(4) = {6, 1, 7};
Line(5) = {5, 2};          // cut, left
Line(6) = {6, 3};
Line(7) = {7, 4};          // cut, right
Curve Loop(1) = {5, 1, -6, -3};
Plane Surface(1) = {1};
Curve Loop(2) = {6, 2, -7, -4};
Plane Surface(2) = {2};
half = Round(n_around * refine / 2);
Transfinite Curve{1, 2, 3, 4} = half + 1;
Transfinite Curve{5, 6, 7} = Round(n_wall * refine) + 1;
Transfinite Surface{1, 2};
Recombine Surface{1, 2};
// Extrude out[]: 0 the face y = l, 1 the volume, 2..5 the faces swept by the loop's curves in order.
left[] = Extrude{0, l, 0}{ Surface{1}; Layers{Round(n_length * refine)}; Recombine; };
right[] = Extrude{0, l, 0}{ Surface{2}; Layers{Round(n_length * refine)}; Recombine; };
Physical Volume("tube") = {left[1], right[1]};
Physical Surface("outer") = {left[3], right[3]};   // swept by curves 1 and 2
Physical Surface("cut") = {left[2], right[4]};     // swept by curves 5 and 7
Physical Surface("ends") = {1, 2, left[0], right[0]};
