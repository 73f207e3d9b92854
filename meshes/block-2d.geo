// 2D rectangle [x0, x0+lx] x [y0, y0+ly] in the plane z = 0, structured quad4 (order = 2: quad9).
// Element count: (nx*refine) x (ny*refine).
DefineConstant[
  lx = 1, ly = 1,
  x0 = 0, y0 = 0,
  nx = 4, ny = 4,
  refine = 1,
  order = 1
];
Point(1) = {x0, y0, 0};
Point(2) = {x0 + lx, y0, 0};
Point(3) = {x0 + lx, y0 + ly, 0};
Point(4) = {x0, y0 + ly, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = Round(nx * refine) + 1;
Transfinite Curve{2, 4} = Round(ny * refine) + 1;
Transfinite Surface{1};
Recombine Surface{1};
Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = 0; // order 2 gives quad9 (with the centre node), not quad8
Physical Surface("body") = {1};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
