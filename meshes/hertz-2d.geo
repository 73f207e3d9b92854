// Hertz contact in plane strain, half model (x >= 0, symmetry line x = 0): the lower half of a cylinder of
// radius R (a quarter disk, centre (0, gap + R)) resting on a block [0, block_width] x [-block_height, 0].
// The load goes on the cylinder's flat top (cylinder-top, at the centre height). All-quad unstructured mesh (quads = 0:
// triangles), graded from size h_contact near the contact point to h_far; sizes are divided by refine.
DefineConstant[
  R = 1,
  gap = 0,
  block_width = 2, block_height = 1,
  contact_angle = 30,      // degrees from the bottom of the cylinder covered by cylinder-contact
  h_contact = 0.02, h_far = 0.2,
  contact_zone = 0.3,      // distance from the contact point over which the mesh is fine
  quads = 1,               // 1: quadrilaterals (Blossom recombination), 0: triangles of the same sizes
  refine = 1
];
If (R <= 0 || gap < 0 || block_width <= 0 || block_height <= 0 || contact_angle <= 0 || contact_angle >= 90 ||
    (quads != 0 && quads != 1))
  Error("hertz-2d.geo: need R, block_width, block_height > 0, gap >= 0, 0 < contact_angle < 90 and quads 0 or 1");
  Abort;
EndIf
// Two separate bodies touching at one point: their points must not be merged.
Geometry.AutoCoherence = 0;
theta = contact_angle * Pi / 180;
yc = gap + R;

// cylinder: quarter disk below its centre
Point(1) = {0, yc, 0};
Point(2) = {0, gap, 0};
Point(3) = {R * Sin(theta), yc - R * Cos(theta), 0};
Point(4) = {R, yc, 0};
Circle(1) = {2, 1, 3};      // contact arc
Circle(2) = {3, 1, 4};      // free arc
Line(3) = {4, 1};           // flat top, loaded
Line(4) = {1, 2};           // symmetry
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

// block
Point(5) = {0, 0, 0};
Point(6) = {0, -block_height, 0};
Point(7) = {block_width, -block_height, 0};
Point(8) = {block_width, 0, 0};
Line(5) = {5, 6};           // symmetry
Line(6) = {6, 7};           // bottom
Line(7) = {7, 8};           // side
Line(8) = {8, 5};           // top: contact
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(2) = {2};

// Size grading around the contact point.
Field[1] = Distance;
Field[1].PointsList = {2, 5};
Field[1].CurvesList = {1, 8};
Field[1].NumPointsPerCurve = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_contact / refine;
Field[2].SizeMax = h_far / refine;
Field[2].DistMin = 0.25 * contact_zone;
Field[2].DistMax = contact_zone + 2 * h_far;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
// Quads: Blossom recombination that always finishes all-quad (triangles and quads of one size setting have about the
// same number of nodes: 1279 and 1468 at refine 1).
Mesh.Algorithm = 6; // Frontal-Delaunay (8, "for quads", crashes with a background field in gmsh 4.8.4)
Mesh.RecombineAll = quads;
Mesh.RecombinationAlgorithm = 3;

Physical Surface("cylinder") = {1};
Physical Surface("block") = {2};
Physical Curve("cylinder-contact") = {1};
Physical Curve("cylinder-free") = {2};
Physical Curve("cylinder-top") = {3};
Physical Curve("block-contact") = {8};
Physical Curve("block-bottom") = {6};
Physical Curve("block-side") = {7};
Physical Curve("symmetry") = {4, 5};
