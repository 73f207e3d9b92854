// The die of the 2D ironing problem (Yang, Laursen & Meng 2005): a half disk of radius R (the lower half, centre
// (x0, y0)) under a block [x0 - R, x0 + R] x [y0, y0 + H]. Structured quads: n_arc cells along the arc (a quarter-
// square core in the half disk), n_radial through the radius, n_block through the block's height; counts scaled by
// refine. The lowest point is (x0, y0 - R).
DefineConstant[
  R = 1, H = 1, x0 = 0, y0 = 1,
  n_arc = 16, n_radial = 4, n_block = 4,
  refine = 1
];
If (R <= 0 || H <= 0)
  Error("die-2d.geo: need R > 0 and H > 0");
  Abort;
EndIf
na = Round(n_arc * refine / 2); If (na < 1) na = 1; EndIf
nr = Round(n_radial * refine); If (nr < 1) nr = 1; EndIf
nb = Round(n_block * refine); If (nb < 1) nb = 1; EndIf
c = 0.5 * R;
Point(1) = {x0, y0, 0};
Point(2) = {x0 - R, y0, 0};
Point(3) = {x0 + R, y0, 0};
Point(4) = {x0, y0 - R, 0};
Point(5) = {x0 - c, y0, 0};
Point(6) = {x0 + c, y0, 0};
Point(7) = {x0, y0 - c, 0};
Point(8) = {x0 - R * Sqrt(0.5), y0 - R * Sqrt(0.5), 0};
Point(9) = {x0 + R * Sqrt(0.5), y0 - R * Sqrt(0.5), 0};
Point(10) = {x0 - c, y0 - c, 0};
Point(11) = {x0 + c, y0 - c, 0};
Point(12) = {x0 - R, y0 + H, 0};
Point(13) = {x0 - c, y0 + H, 0};
Point(14) = {x0, y0 + H, 0};
Point(15) = {x0 + c, y0 + H, 0};
Point(16) = {x0 + R, y0 + H, 0};
Circle(1) = {2, 1, 8}; Circle(2) = {8, 1, 4}; Circle(3) = {4, 1, 9}; Circle(4) = {9, 1, 3};
Line(5) = {2, 5}; Line(6) = {5, 1}; Line(7) = {1, 6}; Line(8) = {6, 3};
Line(9) = {5, 10}; Line(10) = {10, 7}; Line(11) = {7, 11}; Line(12) = {11, 6}; Line(13) = {1, 7};
Line(14) = {8, 10}; Line(15) = {4, 7}; Line(16) = {9, 11};
Line(17) = {2, 12}; Line(18) = {5, 13}; Line(19) = {1, 14}; Line(20) = {6, 15}; Line(21) = {3, 16};
Line(22) = {12, 13}; Line(23) = {13, 14}; Line(24) = {14, 15}; Line(25) = {15, 16};
Curve Loop(1) = {5, 9, -14, -1}; Plane Surface(1) = {1};
Curve Loop(2) = {14, 10, -15, -2}; Plane Surface(2) = {2};
Curve Loop(3) = {15, 11, -16, -3}; Plane Surface(3) = {3};
Curve Loop(4) = {16, 12, 8, -4}; Plane Surface(4) = {4};
Curve Loop(5) = {6, 13, -10, -9}; Plane Surface(5) = {5};
Curve Loop(6) = {7, -12, -11, -13}; Plane Surface(6) = {6};
Curve Loop(7) = {5, 18, -22, -17}; Plane Surface(7) = {7};
Curve Loop(8) = {6, 19, -23, -18}; Plane Surface(8) = {8};
Curve Loop(9) = {7, 20, -24, -19}; Plane Surface(9) = {9};
Curve Loop(10) = {8, 21, -25, -20}; Plane Surface(10) = {10};
Transfinite Curve{1, 2, 3, 4, 9, 10, 11, 12, 6, 7, 13, 23, 24} = na + 1;
Transfinite Curve{5, 8, 14, 15, 16, 22, 25} = nr + 1;
Transfinite Curve{17, 18, 19, 20, 21} = nb + 1;
Transfinite Surface{1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
Recombine Surface{1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
Physical Surface("die") = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
Physical Curve("die-contact") = {1, 2, 3, 4};
Physical Curve("die-top") = {22, 23, 24, 25};
