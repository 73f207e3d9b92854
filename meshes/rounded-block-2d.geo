// A 2D block [x0, x0 + w] x [y0, y0 + h] whose two lower corners are rounded with radius r: the ironing block of
// Hammer 2012, sec. 8.2 ("deep ironing"). Unstructured quads of size lc / refine (Blossom recombination), finer
// (lc_round / refine) along the rounded corners. Groups: block; block-top (the driven top edge), block-contact
// (everything else: the sides, the rounded corners and the bottom, which a deep indentation brings into contact).
DefineConstant[
  w = 30, h = 30, r = 10, x0 = 20, y0 = 0,
  lc = 2, lc_round = 1,
  refine = 1
];
If (w <= 0 || h <= 0 || r <= 0 || 2 * r > w || r > h || lc <= 0 || lc_round <= 0 || refine <= 0)
  Error("rounded-block-2d.geo: need positive sizes with 2 r <= w and r <= h");
  Abort;
EndIf
s = lc / refine; sr = lc_round / refine;
Point(1) = {x0, y0 + h, 0, s};
Point(2) = {x0, y0 + r, 0, sr};
Point(3) = {x0 + r, y0 + r, 0, sr};     // centre of the left arc
Point(4) = {x0 + r, y0, 0, sr};
Point(5) = {x0 + w - r, y0, 0, sr};
Point(6) = {x0 + w - r, y0 + r, 0, sr}; // centre of the right arc
Point(7) = {x0 + w, y0 + r, 0, sr};
Point(8) = {x0 + w, y0 + h, 0, s};
Line(1) = {1, 2};
Circle(2) = {2, 3, 4};
Line(3) = {4, 5};
Circle(4) = {5, 6, 7};
Line(5) = {7, 8};
Line(6) = {8, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
Mesh.MeshSizeExtendFromBoundary = 1;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.RecombineAll = 1;
Mesh.RecombinationAlgorithm = 3;
Physical Surface("block") = {1};
Physical Curve("block-top") = {6};
Physical Curve("block-contact") = {1, 2, 3, 4, 5};
