// a square bar along x: [-L/2, L/2] x [-a/2, a/2] x [0, a] (hex8)
DefineConstant[ L = 1, a = 0.2, n = 8, m = 2 ];
Point(1) = {-L/2, -a/2, 0}; Point(2) = {L/2, -a/2, 0}; Point(3) = {L/2, a/2, 0}; Point(4) = {-L/2, a/2, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 3} = n + 1; Transfinite Curve{2, 4} = m + 1;
Transfinite Surface{1}; Recombine Surface{1};
out[] = Extrude {0, 0, a} { Surface{1}; Layers{m}; Recombine; };
Physical Volume("bar") = {out[1]};
Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
