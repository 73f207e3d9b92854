// Contact patch test in 2D (plane strain): two stacked rectangles with non-matching meshes at their interface.
// lower = [0, lx] x [-h_lower, 0] with nx_lower x ny_lower quads, upper = [0, lx] x [gap, gap + h_upper] with
// nx_upper x ny_upper quads (4 against 5 across by default). The bodies share no nodes. grading != 1 grades the
// divisions across each block geometrically with that ratio, opposite on a block's bottom and top edges (its
// interior lines slant: distorted quads) and opposite on the two sides of the interface (a badly graded,
// non-matching interface); tests/bench/stress uses it. quads = 0 splits the cells into triangles (tri3, tri6 with
// mesh.order: 2).
DefineConstant[
  lx = 1, h_lower = 0.5, h_upper = 0.5, gap = 0,
  nx_lower = 4, ny_lower = 2,
  nx_upper = 5, ny_upper = 2,
  refine = 1, grading = 1, quads = 1
];
// Two separate bodies: no automatic merging of the coincident interface points.
Geometry.AutoCoherence = 0;

// lower body
Point(1) = {0, -h_lower, 0}; Point(2) = {lx, -h_lower, 0}; Point(3) = {lx, 0, 0}; Point(4) = {0, 0, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 3} = Round(nx_lower * refine) + 1 Using Progression grading;
Transfinite Curve{2, 4} = Round(ny_lower * refine) + 1;
Transfinite Surface{1};
If (quads)
  Recombine Surface{1};
EndIf

// upper body
Point(5) = {0, gap, 0}; Point(6) = {lx, gap, 0}; Point(7) = {lx, gap + h_upper, 0}; Point(8) = {0, gap + h_upper, 0};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Transfinite Curve{5, 7} = Round(nx_upper * refine) + 1 Using Progression grading;
Transfinite Curve{6, 8} = Round(ny_upper * refine) + 1;
Transfinite Surface{2};
If (quads)
  Recombine Surface{2};
EndIf

Physical Surface("lower") = {1};
Physical Surface("upper") = {2};
Physical Curve("lower-bottom") = {1};
Physical Curve("lower-right") = {2};
Physical Curve("lower-top") = {3};
Physical Curve("lower-left") = {4};
Physical Curve("upper-bottom") = {5};
Physical Curve("upper-right") = {6};
Physical Curve("upper-top") = {7};
Physical Curve("upper-left") = {8};
