// a trapezoidal wedge, base [0, 0.4] on y = 0, top [0.1, 0.3] at y = 0.2 (quad4; mass 60 at density 1000)
DefineConstant[ n = 6 ];
Point(1) = {0, 0, 0};  Point(2) = {0.4, 0, 0};  Point(3) = {0.3, 0.2, 0};  Point(4) = {0.1, 0.2, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 3} = n + 1; Transfinite Curve{2, 4} = n/2 + 1;
Transfinite Surface{1}; Recombine Surface{1};
Physical Surface("wedge") = {1};
Physical Curve("bottom") = {1};
