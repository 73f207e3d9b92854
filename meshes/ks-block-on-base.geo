// Konyukhov & Schweizerhof (2005), Example 6.1: a block a x b x c (x along a, y up, z through the thickness c) on a
// base, the "lower supplementary block added to model a rigid base" (clamp the group `base` whole). Structured hex8
// (QUAD4 contact faces), one element through the thickness; the base's top is longer than the block and meshed
// differently (non-matching interface). Element counts scale with refine.
DefineConstant[
  a = 20, b = 5, c = 0.5,
  nx = 40, ny = 10,
  base_nx = 43, base_ny = 2,
  base_margin = 0.5, base_height = 1,
  refine = 1
];
If (a <= 0 || b <= 0 || c <= 0 || base_height <= 0 || base_margin <= 0)
  Error("ks-block-on-base.geo: need a, b, c, base_height, base_margin > 0");
  Abort;
EndIf
// block [0, a] x [0, b] x [0, c]
Point(1) = {0, 0, 0};
Point(2) = {a, 0, 0};
Point(3) = {a, b, 0};
Point(4) = {0, b, 0};
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
// Extrude out[]: 0 the face z = c, 1 the volume, 2..5 the faces swept by curves 1..4 (y = 0, x = a, y = b, x = 0).
blk[] = Extrude{0, 0, c}{ Surface{1}; Layers{1}; Recombine; };
// base [-base_margin, a + base_margin] x [-base_height, 0] x [0, c]
Point(1011) = {-base_margin, -base_height, 0};
Point(1012) = {a + base_margin, -base_height, 0};
Point(1013) = {a + base_margin, 0, 0};
Point(1014) = {-base_margin, 0, 0};
Line(1011) = {1011, 1012};
Line(1012) = {1012, 1013};
Line(1013) = {1013, 1014};
Line(1014) = {1014, 1011};
Curve Loop(1011) = {1011, 1012, 1013, 1014};
Plane Surface(1011) = {1011};
Transfinite Curve{1011, 1013} = Round(base_nx * refine) + 1;
Transfinite Curve{1012, 1014} = Round(base_ny * refine) + 1;
Transfinite Surface{1011};
Recombine Surface{1011};
bas[] = Extrude{0, 0, c}{ Surface{1011}; Layers{1}; Recombine; };
Physical Volume("block") = {blk[1]};
Physical Volume("base") = {bas[1]};
Physical Surface("block-bottom") = {blk[2]};
Physical Surface("block-top") = {blk[4]};
Physical Surface("block-sides") = {1, blk[0]};
Physical Surface("base-top") = {bas[4]};
// No shared nodes: no point of the base coincides with one of the block (base_margin > 0), so gmsh merges nothing.
