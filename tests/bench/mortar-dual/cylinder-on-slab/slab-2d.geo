// slab [-W, W] x [-H, 0]
DefineConstant[ W = 2, H = 2, h = 0.25, hc = 0.04 ];
Point(1) = {-W, -H, 0, h}; Point(2) = {W, -H, 0, h}; Point(3) = {W, 0, 0, h}; Point(4) = {0.3, 0, 0, hc};
Point(5) = {-0.3, 0, 0, hc}; Point(6) = {-W, 0, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 6}; Line(6) = {6, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6}; Plane Surface(1) = {1};
Recombine Surface{1};
Physical Surface("slab") = {1};
Physical Curve("surface") = {3, 4, 5};
Physical Curve("base") = {1};
