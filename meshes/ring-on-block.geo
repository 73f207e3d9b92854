// The lower half of a two-layer ring above a block (docs/validation.md, "Ring pressed onto a block"): ring centred at
// (0, cy), inner layer r_inner..r_mid, outer layer r_mid..r_outer, its two ends on the line y = cy; the block
// [-block_width/2, block_width/2] x [-block_height, 0] below it (gap cy - r_outer). Structured quad4: n_around
// divisions along the half ring and n_layer through each layer; the block nx x ny, uniform. All counts scale with
// refine. The layers share the nodes on r = r_mid. thickness > 0 extrudes everything by that much along z, one hex8
// layer (a plane-strain slice for 3D plugins: fix u_z on the groups `front` and `back`).
DefineConstant[
  r_inner = 90, r_mid = 95, r_outer = 100, cy = 120,
  n_around = 64, n_layer = 2,
  block_width = 260, block_height = 50, nx = 52, ny = 10,
  refine = 1, thickness = 0
];
If (r_inner <= 0 || r_mid <= r_inner || r_outer <= r_mid || cy < r_outer)
  Error("ring-on-block.geo: need 0 < r_inner < r_mid < r_outer <= cy (got %g, %g, %g, %g)", r_inner, r_mid, r_outer, cy);
  Abort;
EndIf
na = Round(n_around * refine / 2); If (na < 2) na = 2; EndIf   // divisions per quarter
nl = Round(n_layer * refine); If (nl < 1) nl = 1; EndIf
bx = Round(nx * refine); If (bx < 1) bx = 1; EndIf
by = Round(ny * refine); If (by < 1) by = 1; EndIf

Point(1) = {0, cy, 0};
radii[] = {r_inner, r_mid, r_outer};
// points p(r, k) at angle pi (k = 0), 3 pi / 2 (k = 1), 2 pi (k = 2): tag 10 + 3 r + k
For r In {0 : 2}
  Point(10 + 3 * r + 0) = {-radii[r], cy, 0};
  Point(10 + 3 * r + 1) = {0, cy - radii[r], 0};
  Point(10 + 3 * r + 2) = {radii[r], cy, 0};
EndFor
// arcs a(r, q) for the quarters q = 0 (pi .. 3 pi/2), 1 (3 pi/2 .. 2 pi): tag 100 + 2 r + q
For r In {0 : 2}
  For q In {0 : 1}
    Circle(100 + 2 * r + q) = {10 + 3 * r + q, 1, 10 + 3 * r + q + 1};
    Transfinite Curve{100 + 2 * r + q} = na + 1;
  EndFor
EndFor
// radial lines l(layer, k) from radius layer to layer + 1 at angle k: tag 200 + 3 layer + k
For l In {0 : 1}
  For k In {0 : 2}
    Line(200 + 3 * l + k) = {10 + 3 * l + k, 10 + 3 * (l + 1) + k};
    Transfinite Curve{200 + 3 * l + k} = nl + 1;
  EndFor
EndFor
// patches: layer l, quarter q (tag 300 + 2 l + q)
For l In {0 : 1}
  For q In {0 : 1}
    Curve Loop(300 + 2 * l + q) = {100 + 2 * l + q, 200 + 3 * l + q + 1, -(100 + 2 * (l + 1) + q), -(200 + 3 * l + q)};
    Plane Surface(300 + 2 * l + q) = {300 + 2 * l + q};
    Transfinite Surface{300 + 2 * l + q};
    Recombine Surface{300 + 2 * l + q};
  EndFor
EndFor

// block
Point(401) = {-block_width / 2, -block_height, 0};
Point(402) = {block_width / 2, -block_height, 0};
Point(403) = {block_width / 2, 0, 0};
Point(404) = {-block_width / 2, 0, 0};
Line(411) = {401, 402};
Line(412) = {402, 403};
Line(413) = {403, 404};
Line(414) = {404, 401};
Transfinite Curve{411, 413} = bx + 1;
Transfinite Curve{412, 414} = by + 1;
Curve Loop(420) = {411, 412, 413, 414};
Plane Surface(420) = {420};
Transfinite Surface{420};
Recombine Surface{420};

If (thickness <= 0)
  Physical Surface("ring-inner") = {300, 301};
  Physical Surface("ring-outer") = {302, 303};
  Physical Surface("block") = {420};
  Physical Curve("ring-contact") = {104, 105};
  Physical Curve("ring-ends") = {200, 202, 203, 205};
  Physical Curve("block-top") = {413};
  Physical Curve("block-bottom") = {411};
Else
  // one command, so that the lateral faces of shared curves are shared; per surface: [top, volume, one lateral
  // face per boundary curve in the order of its curve loop]
  ex[] = Extrude {0, 0, thickness} { Surface{300, 301, 302, 303, 420}; Layers{1}; Recombine; };
  Physical Volume("ring-inner") = {ex[1], ex[7]};
  Physical Volume("ring-outer") = {ex[13], ex[19]};
  Physical Volume("block") = {ex[25]};
  Physical Surface("ring-contact") = {ex[16], ex[22]};       // the outer arcs of the outer layer's patches
  Physical Surface("ring-ends") = {ex[5], ex[3 + 6], ex[12 + 5], ex[18 + 3]};
  Physical Surface("block-top") = {ex[24 + 4]};
  Physical Surface("block-bottom") = {ex[24 + 2]};
  Physical Surface("front") = {300, 301, 302, 303, 420};
  Physical Surface("back") = {ex[0], ex[6], ex[12], ex[18], ex[24]};
EndIf
