// Hertz line contact, plane strain, half model (x >= 0, symmetry line x = 0): the lower half of a cylinder of radius
// R (a quarter disk, centre (0, gap + R)) on a block [0, W] x [-H, 0]. Unlike hertz-2d.geo the contact surfaces are
// only the parts near the contact point (the arc within contact_angle of the bottom, the block top up to
// contact_width) and the mesh is graded by the distance to the contact point alone: h_contact within fine_radius,
// h_far beyond far_radius (sizes divided by refine). All quads (Blossom recombination).
DefineConstant[
  R = 70, gap = 0, W = 140, H = 70,
  contact_angle = 3,      // degrees of arc from the bottom in the cylinder's contact surface
  contact_width = 4,      // half-width of the block's contact surface
  h_contact = 0.05, h_far = 10,
  fine_radius = 1.5, far_radius = 40,
  refine = 1
];
If (R <= 0 || W <= 0 || H <= 0 || gap < 0 || contact_angle <= 0 || contact_angle >= 90 || contact_width <= 0 ||
    contact_width >= W)
  Error("hertz-cylinder-2d.geo: need positive sizes, 0 < contact_angle < 90, 0 < contact_width < W");
  Abort;
EndIf
Geometry.AutoCoherence = 0;
theta = contact_angle * Pi / 180;
yc = gap + R;
// cylinder
Point(1) = {0, yc, 0};
Point(2) = {0, gap, 0};
Point(3) = {R * Sin(theta), yc - R * Cos(theta), 0};
Point(4) = {R, yc, 0};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Line(3) = {4, 1};
Line(4) = {1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
// block
Point(5) = {0, 0, 0};
Point(6) = {0, -H, 0};
Point(7) = {W, -H, 0};
Point(8) = {W, 0, 0};
Point(9) = {contact_width, 0, 0};
Line(5) = {5, 6};
Line(6) = {6, 7};
Line(7) = {7, 8};
Line(8) = {8, 9};
Line(9) = {9, 5};
Curve Loop(2) = {5, 6, 7, 8, 9};
Plane Surface(2) = {2};
// sizes: by the distance to the contact point
Field[1] = Distance;
Field[1].PointsList = {2, 5};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_contact / refine;
Field[2].SizeMax = h_far / refine;
Field[2].DistMin = fine_radius;
Field[2].DistMax = far_radius;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.RecombineAll = 1;
Mesh.RecombinationAlgorithm = 3;
Physical Surface("cylinder") = {1};
Physical Surface("block") = {2};
Physical Curve("cylinder-contact") = {1};
Physical Curve("cylinder-free") = {2};
Physical Curve("cylinder-top") = {3};
Physical Curve("block-contact") = {9};
Physical Curve("block-free") = {8};
Physical Curve("block-bottom") = {6};
Physical Curve("block-side") = {7};
Physical Curve("symmetry") = {4, 5};
