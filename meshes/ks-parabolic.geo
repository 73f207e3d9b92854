// Konyukhov & Schweizerhof (2005), Example 6.2: a parabolic block on a parabolic base, one body per load of this
// script: part = 1 the block, the slab between z = c x^2 and z = H + c x^2 over |x| <= L/2; part = 2 the base, the
// slab between z = c x^2 - D and z = c x^2 (clamp it whole: the paper's fixed base). Both have thickness T in y
// (x-z is the plane of the motion, z up). Load it twice (scene `mesh:` list, names block and base): the two bodies
// touch along z = c x^2, and one gmsh model would merge their coincident points and so their interface nodes.
// Structured hex27 (QUAD9 contact faces) with order = 2, hex8 with order = 1; the paper: 20 x 1 x 5 18-node elements.
// The parabolas are quadratic Bezier curves (control point (0, c x0 x1) between x0 = -L/2 and x1 = L/2), so every
// node lies on z = c x^2 to round-off. gmsh spaces the nodes (and puts the mid-edge nodes) by arc length, not by x,
// so a QUAD9 edge is the parabola only approximately: measured 2.7e-6 at most from z = c x^2 and a slope jump of
// 7e-6 across element edges (docs/plugins/covariant-penalty.md §9): C1 for practical purposes, as the paper wants.
// Groups: part 1 `body`, `bottom` (contact), `top`, `sides` (y = 0 and y = T); part 2 `body`, `top` (contact).
DefineConstant[
  part = 1,
  c = 0.03, L = 10, H = 5, T = 1, D = 1,
  nx = 20, nz = 5, base_nz = 1,
  order = 2,
  refine = 1
];
If (L <= 0 || H <= 0 || T <= 0 || D <= 0 || (order != 1 && order != 2) || (part != 1 && part != 2))
  Error("ks-parabolic.geo: need L, H, T, D > 0, order 1 or 2 and part 1 or 2");
  Abort;
EndIf
x0 = -L / 2;
x1 = L / 2;
// The lower parabola at z = c x^2 + lo, the upper one at z = c x^2 + hi.
lo = (part == 1) ? 0 : -D;
hi = (part == 1) ? H : 0;
layers = (part == 1) ? nz : base_nz;
Point(1) = {x0, 0, c * x0 * x0 + lo};
Point(2) = {0, 0, c * x0 * x1 + lo};
Point(3) = {x1, 0, c * x1 * x1 + lo};
Point(4) = {x1, 0, c * x1 * x1 + hi};
Point(5) = {0, 0, c * x0 * x1 + hi};
Point(6) = {x0, 0, c * x0 * x0 + hi};
Bezier(1) = {1, 2, 3};
Line(2) = {3, 4};
Bezier(3) = {4, 5, 6};
Line(4) = {6, 1};
Curve Loop(1) = {1, 2, 3, 4};
Surface(1) = {1};
Transfinite Curve{1, 3} = Round(nx * refine) + 1;
Transfinite Curve{2, 4} = Round(layers * refine) + 1;
Transfinite Surface{1};
Recombine Surface{1};
// Extrude out[]: 0 the face y = T, 1 the volume, 2..5 the faces swept by curves 1..4 (bottom, x = L/2, top, x = -L/2).
out[] = Extrude{0, T, 0}{ Surface{1}; Layers{1}; Recombine; };
Physical Volume("body") = {out[1]};
Physical Surface("top") = {out[4]};
If (part == 1)
  Physical Surface("bottom") = {out[2]};
  Physical Surface("sides") = {1, out[0]};
EndIf
Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = 0; // order 2 gives hex27 / quad9 (with the centre nodes)
