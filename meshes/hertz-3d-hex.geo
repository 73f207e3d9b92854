// Hertz contact in 3D with hexahedra, quarter model (x >= 0, y >= 0; symmetry planes x = 0 and y = 0): the lower half
// of a sphere of radius R (centre (0, 0, gap + R)) resting on a block [0, block_width]^2 x [-block_height, 0], the
// same bodies and physical groups as hertz-3d.geo. The eighth ball is a "cubed sphere": an inner cube at the centre
// and three blocks between its outer faces and the three patches of the sphere, all transfinite; the contact point
// (the sphere's lowest point) is a corner of the bottom patch. Cells: n_tangential along the horizontal cube edges and
// sphere arcs, n_vertical along the vertical ones (cube, x and y blocks: from the bottom patch up to the equator), both
// with a geometric progression that makes them smallest towards the contact point, n_radial from the cube to the
// sphere, smallest at the sphere. The block: n_block cells across (smallest at the contact corner), n_block_z deep
// (smallest at the top). refine multiplies every count and takes the refine-th root of every progression, so the
// cells near the contact shrink like 1 / refine.
DefineConstant[
  R = 1,
  gap = 0,
  block_width = 1.5, block_height = 1,
  cube = 0.4,                      // half-size of the inner cube / R
  n_tangential = 8, progression_tangential = 1.25,  // contact cells 0.040 / refine
  n_vertical = 4, progression_vertical = 1.5,
  n_radial = 6, progression_radial = 1.35,          // 0.042 / refine at the sphere
  n_block = 8, progression_block = 1.35,            // 0.052 / refine at the contact corner
  n_block_z = 5, progression_block_z = 1.5,
  refine = 1
];
If (R <= 0 || gap < 0 || block_width <= 0 || block_height <= 0 || cube <= 0 || cube >= 0.55 || refine <= 0)
  Error("hertz-3d-hex.geo: need R, block_width, block_height, refine > 0, gap >= 0 and 0 < cube < 0.55");
  Abort;
EndIf
Geometry.AutoCoherence = 0; // the two bodies touch at one point and keep separate nodes there

zc = gap + R;
b = cube * R;
s2 = 1 / Sqrt(2);
s3 = 1 / Sqrt(3);
nt = Round(n_tangential * refine);
nr = Round(n_radial * refine);
nv = Round(n_vertical * refine);
pt = progression_tangential ^ (1 / refine);
pv = progression_vertical ^ (1 / refine);
pr = progression_radial ^ (1 / refine);

// Points: the centre C, the cube corners, the sphere points (direction in the name: x, y, z = -z).
C = newp; Point(C) = {0, 0, zc};
Cx = newp; Point(Cx) = {b, 0, zc};
Cy = newp; Point(Cy) = {0, b, zc};
Cz = newp; Point(Cz) = {0, 0, zc - b};
Cxy = newp; Point(Cxy) = {b, b, zc};
Cxz = newp; Point(Cxz) = {b, 0, zc - b};
Cyz = newp; Point(Cyz) = {0, b, zc - b};
Cxyz = newp; Point(Cxyz) = {b, b, zc - b};
Sx = newp; Point(Sx) = {R, 0, zc};
Sy = newp; Point(Sy) = {0, R, zc};
Sz = newp; Point(Sz) = {0, 0, zc - R};
Sxy = newp; Point(Sxy) = {R * s2, R * s2, zc};
Sxz = newp; Point(Sxz) = {R * s2, 0, zc - R * s2};
Syz = newp; Point(Syz) = {0, R * s2, zc - R * s2};
Sxyz = newp; Point(Sxyz) = {R * s3, R * s3, zc - R * s3};

// Cube edges (tangential), radial lines (cube to sphere), sphere arcs (tangential). Arcs and cube edges run away from
// the contact side (from z- towards the equator, from the axes outwards), so one progression direction serves all.
l_C_Cx = newl; Line(l_C_Cx) = {C, Cx};
l_C_Cy = newl; Line(l_C_Cy) = {C, Cy};
l_Cz_C = newl; Line(l_Cz_C) = {Cz, C};
l_Cx_Cxy = newl; Line(l_Cx_Cxy) = {Cx, Cxy};
l_Cy_Cxy = newl; Line(l_Cy_Cxy) = {Cy, Cxy};
l_Cxz_Cx = newl; Line(l_Cxz_Cx) = {Cxz, Cx};
l_Cyz_Cy = newl; Line(l_Cyz_Cy) = {Cyz, Cy};
l_Cz_Cxz = newl; Line(l_Cz_Cxz) = {Cz, Cxz};
l_Cz_Cyz = newl; Line(l_Cz_Cyz) = {Cz, Cyz};
l_Cxz_Cxyz = newl; Line(l_Cxz_Cxyz) = {Cxz, Cxyz};
l_Cyz_Cxyz = newl; Line(l_Cyz_Cxyz) = {Cyz, Cxyz};
l_Cxyz_Cxy = newl; Line(l_Cxyz_Cxy) = {Cxyz, Cxy};
r_x = newl; Line(r_x) = {Cx, Sx};
r_y = newl; Line(r_y) = {Cy, Sy};
r_z = newl; Line(r_z) = {Cz, Sz};
r_xy = newl; Line(r_xy) = {Cxy, Sxy};
r_xz = newl; Line(r_xz) = {Cxz, Sxz};
r_yz = newl; Line(r_yz) = {Cyz, Syz};
r_xyz = newl; Line(r_xyz) = {Cxyz, Sxyz};
a_Sx_Sxy = newl; Circle(a_Sx_Sxy) = {Sx, C, Sxy};
a_Sy_Sxy = newl; Circle(a_Sy_Sxy) = {Sy, C, Sxy};
a_Sxz_Sx = newl; Circle(a_Sxz_Sx) = {Sxz, C, Sx};
a_Syz_Sy = newl; Circle(a_Syz_Sy) = {Syz, C, Sy};
a_Sz_Sxz = newl; Circle(a_Sz_Sxz) = {Sz, C, Sxz};
a_Sz_Syz = newl; Circle(a_Sz_Syz) = {Sz, C, Syz};
a_Sxz_Sxyz = newl; Circle(a_Sxz_Sxyz) = {Sxz, C, Sxyz};
a_Syz_Sxyz = newl; Circle(a_Syz_Sxyz) = {Syz, C, Sxyz};
a_Sxyz_Sxy = newl; Circle(a_Sxyz_Sxy) = {Sxyz, C, Sxy};

Transfinite Curve{l_C_Cx, l_C_Cy, l_Cx_Cxy, l_Cy_Cxy, l_Cz_Cxz, l_Cz_Cyz, l_Cxz_Cxyz, l_Cyz_Cxyz, a_Sx_Sxy, a_Sy_Sxy,
                  a_Sz_Sxz, a_Sz_Syz, a_Sxz_Sxyz, a_Syz_Sxyz} = nt + 1 Using Progression pt;
Transfinite Curve{l_Cz_C, l_Cxz_Cx, l_Cyz_Cy, l_Cxyz_Cxy, a_Sxz_Sx, a_Syz_Sy, a_Sxyz_Sxy} = nv + 1 Using Progression pv;
// Radial lines: smallest cells at the sphere (progression 1/pr from the cube outwards).
Transfinite Curve{r_x, r_y, r_z, r_xy, r_xz, r_yz, r_xyz} = nr + 1 Using Progression 1 / pr;

// Surfaces. Planar ones by corner loops (orientation is fixed by the loader); sphere patches lie In Sphere{C}. A macro
// runs after the rest of the line that calls it, so each Call stands on its own line.
Macro PlaneQuad
  cl = newll; Curve Loop(cl) = {e1, e2, e3, e4};
  made = news; Plane Surface(made) = {cl};
Return
Macro SphereQuad
  cl = newll; Curve Loop(cl) = {e1, e2, e3, e4};
  made = news; Surface(made) = {cl} In Sphere{C};
Return
e1 = l_C_Cx; e2 = l_Cx_Cxy; e3 = -l_Cy_Cxy; e4 = -l_C_Cy;
Call PlaneQuad;
cube_top = made;
e1 = l_C_Cy; e2 = -l_Cyz_Cy; e3 = -l_Cz_Cyz; e4 = l_Cz_C;
Call PlaneQuad;
cube_x0 = made;
e1 = l_C_Cx; e2 = -l_Cxz_Cx; e3 = -l_Cz_Cxz; e4 = l_Cz_C;
Call PlaneQuad;
cube_y0 = made;
e1 = l_Cxz_Cx; e2 = l_Cx_Cxy; e3 = -l_Cxyz_Cxy; e4 = -l_Cxz_Cxyz;
Call PlaneQuad;
cube_xb = made;
e1 = l_Cyz_Cy; e2 = l_Cy_Cxy; e3 = -l_Cxyz_Cxy; e4 = -l_Cyz_Cxyz;
Call PlaneQuad;
cube_yb = made;
e1 = l_Cz_Cxz; e2 = l_Cxz_Cxyz; e3 = -l_Cyz_Cxyz; e4 = -l_Cz_Cyz;
Call PlaneQuad;
cube_zb = made;
e1 = r_x; e2 = a_Sx_Sxy; e3 = -r_xy; e4 = -l_Cx_Cxy;
Call PlaneQuad;
top_x = made;
e1 = r_y; e2 = a_Sy_Sxy; e3 = -r_xy; e4 = -l_Cy_Cxy;
Call PlaneQuad;
top_y = made;
e1 = r_x; e2 = -a_Sxz_Sx; e3 = -r_xz; e4 = l_Cxz_Cx;
Call PlaneQuad;
y0_x = made;
e1 = r_y; e2 = -a_Syz_Sy; e3 = -r_yz; e4 = l_Cyz_Cy;
Call PlaneQuad;
x0_y = made;
e1 = r_z; e2 = a_Sz_Sxz; e3 = -r_xz; e4 = -l_Cz_Cxz;
Call PlaneQuad;
y0_z = made;
e1 = r_z; e2 = a_Sz_Syz; e3 = -r_yz; e4 = -l_Cz_Cyz;
Call PlaneQuad;
x0_z = made;
e1 = r_xy; e2 = -a_Sxyz_Sxy; e3 = -r_xyz; e4 = l_Cxyz_Cxy;
Call PlaneQuad;
diag_xy = made;
e1 = r_xz; e2 = a_Sxz_Sxyz; e3 = -r_xyz; e4 = -l_Cxz_Cxyz;
Call PlaneQuad;
diag_xz = made;
e1 = r_yz; e2 = a_Syz_Sxyz; e3 = -r_xyz; e4 = -l_Cyz_Cxyz;
Call PlaneQuad;
diag_yz = made;
e1 = a_Sxz_Sx; e2 = a_Sx_Sxy; e3 = -a_Sxyz_Sxy; e4 = -a_Sxz_Sxyz;
Call SphereQuad;
patch_x = made;
e1 = a_Syz_Sy; e2 = a_Sy_Sxy; e3 = -a_Sxyz_Sxy; e4 = -a_Syz_Sxyz;
Call SphereQuad;
patch_y = made;
e1 = a_Sz_Sxz; e2 = a_Sxz_Sxyz; e3 = -a_Syz_Sxyz; e4 = -a_Sz_Syz;
Call SphereQuad;
patch_z = made;

sphere_surfaces[] = {cube_top, cube_x0, cube_y0, cube_xb, cube_yb, cube_zb, top_x, top_y, y0_x, x0_y, y0_z, x0_z,
                     diag_xy, diag_xz, diag_yz, patch_x, patch_y, patch_z};
Transfinite Surface{sphere_surfaces[]};
Recombine Surface{sphere_surfaces[]};

sl = newsl; Surface Loop(sl) = {cube_top, cube_x0, cube_y0, cube_xb, cube_yb, cube_zb};
v_cube = newv; Volume(v_cube) = {sl};
sl = newsl; Surface Loop(sl) = {cube_xb, patch_x, top_x, y0_x, diag_xy, diag_xz};
v_x = newv; Volume(v_x) = {sl};
sl = newsl; Surface Loop(sl) = {cube_yb, patch_y, top_y, x0_y, diag_xy, diag_yz};
v_y = newv; Volume(v_y) = {sl};
sl = newsl; Surface Loop(sl) = {cube_zb, patch_z, y0_z, x0_z, diag_xz, diag_yz};
v_z = newv; Volume(v_z) = {sl};
Transfinite Volume{v_cube, v_x, v_y, v_z};

// The block: structured, cells smallest at the contact corner (0, 0, 0).
nb = Round(n_block * refine);
nbz = Round(n_block_z * refine);
pb = progression_block ^ (1 / refine);
pbz = progression_block_z ^ (1 / refine);
B000 = newp; Point(B000) = {0, 0, 0};
B100 = newp; Point(B100) = {block_width, 0, 0};
B110 = newp; Point(B110) = {block_width, block_width, 0};
B010 = newp; Point(B010) = {0, block_width, 0};
B001 = newp; Point(B001) = {0, 0, -block_height};
B101 = newp; Point(B101) = {block_width, 0, -block_height};
B111 = newp; Point(B111) = {block_width, block_width, -block_height};
B011 = newp; Point(B011) = {0, block_width, -block_height};
bx0 = newl; Line(bx0) = {B000, B100}; bx1 = newl; Line(bx1) = {B010, B110};
bx2 = newl; Line(bx2) = {B001, B101}; bx3 = newl; Line(bx3) = {B011, B111};
by0 = newl; Line(by0) = {B000, B010}; by1 = newl; Line(by1) = {B100, B110};
by2 = newl; Line(by2) = {B001, B011}; by3 = newl; Line(by3) = {B101, B111};
bz0 = newl; Line(bz0) = {B000, B001}; bz1 = newl; Line(bz1) = {B100, B101};
bz2 = newl; Line(bz2) = {B010, B011}; bz3 = newl; Line(bz3) = {B110, B111};
Transfinite Curve{bx0, bx1, bx2, bx3, by0, by1, by2, by3} = nb + 1 Using Progression pb;
Transfinite Curve{bz0, bz1, bz2, bz3} = nbz + 1 Using Progression pbz;
e1 = bx0; e2 = by1; e3 = -bx1; e4 = -by0;
Call PlaneQuad;
b_top = made;
e1 = bx2; e2 = by3; e3 = -bx3; e4 = -by2;
Call PlaneQuad;
b_bottom = made;
e1 = bx0; e2 = bz1; e3 = -bx2; e4 = -bz0;
Call PlaneQuad;
b_y0 = made;
e1 = bx1; e2 = bz3; e3 = -bx3; e4 = -bz2;
Call PlaneQuad;
b_y1 = made;
e1 = by0; e2 = bz2; e3 = -by2; e4 = -bz0;
Call PlaneQuad;
b_x0 = made;
e1 = by1; e2 = bz3; e3 = -by3; e4 = -bz1;
Call PlaneQuad;
b_x1 = made;
block_surfaces[] = {b_top, b_bottom, b_y0, b_y1, b_x0, b_x1};
Transfinite Surface{block_surfaces[]};
Recombine Surface{block_surfaces[]};
sl = newsl; Surface Loop(sl) = {block_surfaces[]};
v_block = newv; Volume(v_block) = {sl};
Transfinite Volume{v_block};

Physical Volume("sphere") = {v_cube, v_x, v_y, v_z};
Physical Volume("block") = {v_block};
Physical Surface("sphere-contact") = {patch_x, patch_y, patch_z};
Physical Surface("sphere-top") = {cube_top, top_x, top_y};
Physical Surface("block-contact") = {b_top};
Physical Surface("block-bottom") = {b_bottom};
Physical Surface("sym-x") = {cube_x0, x0_y, x0_z, b_x0};
Physical Surface("sym-y") = {cube_y0, y0_x, y0_z, b_y0};
