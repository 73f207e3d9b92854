// lower half of a disk of radius R, centre (0, R): flat top at y = R, touching y = 0 at the origin
DefineConstant[ R = 1, h = 0.08 ];
Point(1) = {0, R, 0, h}; Point(2) = {-R, R, 0, h}; Point(3) = {0, 0, 0, h/4}; Point(4) = {R, R, 0, h};
Circle(1) = {2, 1, 3}; Circle(2) = {3, 1, 4}; Line(3) = {4, 2};
Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};
Recombine Surface{1};
Physical Surface("cyl") = {1};
Physical Curve("arc") = {1, 2};
Physical Curve("top") = {3};
