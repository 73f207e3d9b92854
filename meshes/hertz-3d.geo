// Hertz contact in 3D, quarter model (x >= 0, y >= 0; symmetry planes x = 0 and y = 0): the lower half of a sphere
// of radius R (centre (0, 0, gap + R)) resting on a block [0, block_width]^2 x [-block_height, 0]. The load goes on
// the sphere's flat top (sphere-top, at the centre height). tet4 mesh graded from h_contact at the contact point
// to h_far; sizes are divided by refine.
SetFactory("OpenCASCADE");
DefineConstant[
  R = 1,
  gap = 0,
  block_width = 1.5, block_height = 1,
  h_contact = 0.05, h_far = 0.3,
  contact_zone = 0.4,
  refine = 1
];
If (R <= 0 || gap < 0 || block_width <= 0 || block_height <= 0)
  Error("hertz-3d.geo: need R, block_width, block_height > 0 and gap >= 0");
  Abort;
EndIf
zc = gap + R;
Sphere(1) = {0, 0, zc, R};
Box(2) = {0, 0, gap, R, R, R};
// The eighth of the ball below the centre, in the quadrant x, y >= 0.
sphere() = BooleanIntersection{ Volume{1}; Delete; }{ Volume{2}; Delete; };
Box(10) = {0, 0, -block_height, block_width, block_width, block_height};
block = 10;
// No BooleanFragments: the two bodies touch at one point and must keep separate nodes there.

eps = 1e-6 * (R + block_width + block_height);
sphere_faces() = Boundary{ Volume{sphere(0)}; };
s_symx() = Surface In BoundingBox{-eps, -eps, gap - eps, eps, R + eps, zc + eps};
s_symy() = Surface In BoundingBox{-eps, -eps, gap - eps, R + eps, eps, zc + eps};
s_top() = Surface In BoundingBox{-eps, -eps, zc - eps, R + eps, R + eps, zc + eps};
b_symx() = Surface In BoundingBox{-eps, -eps, -block_height - eps, eps, block_width + eps, eps};
b_symy() = Surface In BoundingBox{-eps, -eps, -block_height - eps, block_width + eps, eps, eps};
b_top() = Surface In BoundingBox{-eps, -eps, -eps, block_width + eps, block_width + eps, eps};
b_bottom() = Surface In BoundingBox{-eps, -eps, -block_height - eps, block_width + eps, block_width + eps,
                                    -block_height + eps};
s_curved() = sphere_faces();
s_curved() -= {s_symx(), s_symy(), s_top()};

Field[2] = MathEval;
// distance to the contact point (the origin), cheaper and exact
Field[2].F = "Sqrt(x * x + y * y + z * z)";
Field[3] = Threshold;
Field[3].InField = 2;
Field[3].SizeMin = h_contact / refine;
Field[3].SizeMax = h_far / refine;
Field[3].DistMin = 0.25 * contact_zone;
Field[3].DistMax = contact_zone + 2 * h_far;
Background Field = 3;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

Physical Volume("sphere") = {sphere(0)};
Physical Volume("block") = {block};
Physical Surface("sphere-contact") = {s_curved()};
Physical Surface("sphere-top") = {s_top()};
Physical Surface("block-contact") = {b_top()};
Physical Surface("block-bottom") = {b_bottom()};
Physical Surface("sym-x") = {s_symx(), b_symx()};
Physical Surface("sym-y") = {s_symy(), b_symy()};
