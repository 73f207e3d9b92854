// Contact patch test in 3D: two stacked boxes with non-matching meshes at their interface.
// lower = [0, lx] x [0, ly] x [-h_lower, 0] with n_lower x n_lower x nz_lower cells, upper = [0, lx] x [0, ly] x
// [gap, gap + h_upper] with n_upper x n_upper x nz_upper cells (4 against 5 across by default). hexes = 1: structured
// hexahedra; hexes = 0: unstructured tetrahedra of about the same size. The bodies share no nodes.
SetFactory("OpenCASCADE");
DefineConstant[
  lx = 1, ly = 1, h_lower = 0.5, h_upper = 0.5, gap = 0,
  n_lower = 4, nz_lower = 2,
  n_upper = 5, nz_upper = 2,
  hexes = 1,
  refine = 1
];
If (lx <= 0 || ly <= 0 || h_lower <= 0 || h_upper <= 0 || n_lower < 1 || n_upper < 1 || nz_lower < 1 ||
    nz_upper < 1 || (hexes != 0 && hexes != 1))
  Error("patch-test-3d.geo: need positive sizes, cell counts >= 1 and hexes = 0 or 1");
  Abort;
EndIf
Box(1) = {0, 0, -h_lower, lx, ly, h_lower};
Box(2) = {0, 0, gap, lx, ly, h_upper};
// No BooleanFragments: the two boxes keep separate nodes on the interface.

// Cells per direction of each box: a curve's direction from its bounding box.
For box In {1 : 2}
  n = box == 1 ? n_lower : n_upper;
  nz = box == 1 ? nz_lower : nz_upper;
  surfaces() = Boundary{ Volume{box}; };
  curves() = Boundary{ Surface{surfaces()}; };
  For k In {0 : #curves() - 1}
    c = Abs(curves(k));
    bb() = BoundingBox Curve{c};
    along_z = bb(5) - bb(2) > 0.5 * (bb(3) - bb(0) + bb(4) - bb(1));
    count = Round((along_z ? nz : n) * refine);
    Transfinite Curve{c} = count + 1; // tetrahedra too: the edge counts make the two interface meshes differ
  EndFor
  If (hexes == 1)
    Transfinite Surface{surfaces()};
    Recombine Surface{surfaces()};
    Transfinite Volume{box};
  EndIf
EndFor
If (hexes == 1)
  Mesh.Recombine3DAll = 0;
EndIf

// Faces of each box by position (the interface faces of the two boxes coincide when gap = 0, so each box's faces
// are taken from its own boundary).
eps = 1e-6 * (lx + ly + h_lower + h_upper);
For box In {1 : 2}
  bottom[] = {}; top[] = {}; xmin[] = {}; ymin[] = {};
  faces() = Boundary{ Volume{box}; };
  For k In {0 : #faces() - 1}
    bb() = BoundingBox Surface{faces(k)};
    If (bb(5) - bb(2) < eps && bb(2) < (box == 1 ? -h_lower : gap) + eps)
      bottom[] += faces(k);
    ElseIf (bb(5) - bb(2) < eps)
      top[] += faces(k);
    ElseIf (bb(3) < eps)
      xmin[] += faces(k);
    ElseIf (bb(4) < eps)
      ymin[] += faces(k);
    EndIf
  EndFor
  If (box == 1)
    Physical Surface("lower-bottom") = {bottom[]};
    Physical Surface("lower-top") = {top[]};
    Physical Surface("lower-xmin") = {xmin[]};
    Physical Surface("lower-ymin") = {ymin[]};
  Else
    Physical Surface("upper-bottom") = {bottom[]};
    Physical Surface("upper-top") = {top[]};
    Physical Surface("upper-xmin") = {xmin[]};
    Physical Surface("upper-ymin") = {ymin[]};
  EndIf
EndFor
Physical Volume("lower") = {1};
Physical Volume("upper") = {2};
