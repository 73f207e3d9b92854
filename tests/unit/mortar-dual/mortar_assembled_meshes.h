/* The meshes of test_mortar_assembled.c: small slave/master face sets in 2D (LINE2, LINE3) and 3D (QUAD4/TRI3,
 * QUAD9, TRI6, QUAD8), self-contact slots, built through the plugin test kit (tests/support/plugin_kit.h). */
#ifndef MORTAR_ASSEMBLED_MESHES_H
#define MORTAR_ASSEMBLED_MESHES_H

#include <math.h>

#include "plugin_kit.h"

/* 2D: an upper body's bottom (4 slave nodes, 3 faces, normal -y) over a lower body's top (5 master nodes, 4 faces,
 * normal +y), non-matching and slightly curved; without a master: the slave alone (for obstacles). */
static void mesh_2d(kit *k, int with_master) {
  static const double xs[4] = {0.0, 0.35, 0.7, 1.0}, xm[5] = {1.2, 0.85, 0.5, 0.2, -0.2};
  double X[18];
  for (int i = 0; i < 4; ++i) {
    X[2 * i] = xs[i];
    X[2 * i + 1] = 0.01 * sin(3.0 * xs[i]);
  }
  for (int i = 0; i < 5; ++i) {
    X[2 * (4 + i)] = xm[i];
    X[2 * (4 + i) + 1] = -0.004 + 0.02 * xm[i] * xm[i];
  }
  kit_init(k, 2, with_master ? 9 : 4, X);
  static const int slave[6] = {0, 1, 1, 2, 2, 3}, master[8] = {4, 5, 5, 6, 6, 7, 7, 8};
  kit_surface(k, 0, SK_LINE2, 2, 3, slave);
  if (with_master) kit_surface(k, 1, SK_LINE2, 2, 4, master);
}

/* 2D, LINE3 faces (mesh.order: 2): an upper body's curved bottom (2 faces, 5 slave nodes, normal -y) over a lower
 * body's curved top (3 faces, 7 master nodes), non-matching, the mid-side nodes off the chords' middles (distorted
 * parametrisations). gmsh order: the ends, then the middle. */
static void mesh_2d_line3(kit *k) {
  static const double xs[5] = {0.0, 0.27, 0.5, 0.78, 1.0}, xm[7] = {1.2, 1.04, 0.85, 0.62, 0.4, 0.18, -0.2};
  double X[24];
  for (int i = 0; i < 5; ++i) {
    X[2 * i] = xs[i];
    X[2 * i + 1] = 0.03 * sin(3.0 * xs[i]);
  }
  for (int i = 0; i < 7; ++i) {
    X[2 * (5 + i)] = xm[i];
    X[2 * (5 + i) + 1] = -0.004 + 0.05 * xm[i] * xm[i];
  }
  kit_init(k, 2, 12, X);
  static const int slave[6] = {0, 2, 1, 2, 4, 3}, master[9] = {5, 7, 6, 7, 9, 8, 9, 11, 10};
  kit_surface(k, 0, SK_LINE3, 3, 2, slave);
  kit_surface(k, 1, SK_LINE3, 3, 3, master);
}

/* 3D: a 2 x 2 quad4 slave patch (normal -z, slightly warped) over a tri3 master (2 x 2 squares split in two,
 * normal +z, curved), offset and rotated against each other. */
static void mesh_3d(kit *k) {
  double X[54];
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int a = 3 * j + i, m = 9 + a;
      X[3 * a] = 0.5 * i + 0.02 * j;
      X[3 * a + 1] = 0.5 * j - 0.03 * i;
      X[3 * a + 2] = 0.01 * (i - 1) * (j - 1);
      X[3 * m] = -0.1 + 0.62 * i;
      X[3 * m + 1] = -0.15 + 0.64 * j;
      X[3 * m + 2] = -0.005 - 0.01 * (i - 1) * (i - 1);
    }
  kit_init(k, 3, 18, X);
  int slave[16], master[24], ns = 0, nm = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = 3 * j + i, b = 9 + a;
      const int quad[4] = {a, a + 3, a + 4, a + 1}; /* clockwise from above: outward normal -z */
      const int t1[3] = {b, b + 1, b + 4}, t2[3] = {b, b + 4, b + 3};
      memcpy(slave + 4 * ns++, quad, sizeof quad);
      memcpy(master + 3 * nm++, t1, sizeof t1);
      memcpy(master + 3 * nm++, t2, sizeof t2);
    }
  kit_surface(k, 0, SK_QUAD4, 4, 4, slave);
  kit_surface(k, 1, SK_TRI3, 3, 8, master);
}

/* 3D, nearly matching: a 2 x 2 quad4 slave patch curved like the ironing indenter's bottom (z = 0.04 (x - 0.5)^2)
 * over a flat 2 x 2 quad4 master whose nodes lie under the slave's (before the step's perturbation of 2e-3):
 * slave edges on master edges, the configuration of the 3D ironing scene's matching meshes. */
static void mesh_3d_matching(kit *k) {
  double X[54];
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int a = 3 * j + i, m = 9 + a;
      X[3 * a] = X[3 * m] = 0.5 * i;
      X[3 * a + 1] = X[3 * m + 1] = 0.5 * j;
      X[3 * a + 2] = 0.04 * (0.5 * i - 0.5) * (0.5 * i - 0.5);
      X[3 * m + 2] = -0.001;
    }
  kit_init(k, 3, 18, X);
  int slave[16], master[16], ns = 0, nm = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = 3 * j + i, b = 9 + a;
      const int quad[4] = {a, a + 3, a + 4, a + 1}, mquad[4] = {b, b + 1, b + 4, b + 3};
      memcpy(slave + 4 * ns++, quad, sizeof quad);
      memcpy(master + 4 * nm++, mquad, sizeof mquad);
    }
  kit_surface(k, 0, SK_QUAD4, 4, 4, slave);
  kit_surface(k, 1, SK_QUAD4, 4, 4, master);
}

/* 3D, QUAD9 faces (hex27, mesh.order: 2): one curved quad9 slave face (normal -z) over two quad9 master faces (normal
 * +z, curved the other way, the first's right edge at x = 0.5), offset and rotated against it: every slave quarter
 * meets master quarters of both faces. Slave node (i, j) of a 3 x 3 grid is i + 3 j, master node (i, j) of a 5 x 3
 * grid 9 + i + 5 j; gmsh order: corners, mid-sides, centre. */
static void mesh_3d_quad9_nodes(kit *k) {
  double X[72];
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      double *x = X + 3 * (3 * j + i);
      x[0] = 0.5 * i + 0.02 * j;
      x[1] = 0.5 * j - 0.03 * i;
      x[2] = 0.02 * (0.5 * i - 0.5) * (0.5 * i - 0.5) + 0.01 * (0.5 * i - 0.5) * (0.5 * j - 0.5);
    }
    for (int i = 0; i < 5; ++i) {
      double *x = X + 3 * (9 + 5 * j + i);
      x[0] = -0.1 + 0.3 * i;
      x[1] = -0.15 + 0.62 * j;
      x[2] = -0.005 - 0.02 * (0.5 * j - 0.5) * (0.5 * j - 0.5);
    }
  }
  kit_init(k, 3, 24, X);
}

static void mesh_3d_quad9(kit *k) {
  mesh_3d_quad9_nodes(k);
  /* slave: clockwise from above (outward normal -z); master: counter-clockwise */
  static const int slave[9] = {0, 6, 8, 2, 3, 7, 5, 1, 4};
  int master[18];
  for (int f = 0; f < 2; ++f) {
    const int g = 9 + 2 * f;
    const int m[9] = {g, g + 2, g + 12, g + 10, g + 1, g + 7, g + 11, g + 5, g + 6};
    memcpy(master + 9 * f, m, sizeof m);
  }
  kit_surface(k, 0, SK_QUAD9, 9, 1, slave);
  kit_surface(k, 1, SK_QUAD9, 9, 2, master);
}

/* 3D, TRI6 faces (tet10, mesh.order: 2): the nodes of mesh_3d_quad9, the slave quad9 face split along its diagonal
 * 0-8 into two curved tri6 faces, each master quad9 face along its diagonal into two: every slave sub-triangle meets
 * master sub-triangles of several faces. gmsh order: corners, then the middles of edges 01, 12, 20. */
static void mesh_3d_tri6(kit *k) {
  mesh_3d_quad9_nodes(k);
  /* slave: clockwise from above (outward normal -z); master: counter-clockwise */
  static const int slave[12] = {0, 6, 8, 3, 7, 4, 0, 8, 2, 4, 5, 1};
  int master[24];
  for (int f = 0; f < 2; ++f) {
    const int g = 9 + 2 * f;
    const int m[12] = {g, g + 2, g + 12, g + 1, g + 7, g + 6, g, g + 12, g + 10, g + 6, g + 11, g + 5};
    memcpy(master + 12 * f, m, sizeof m);
  }
  kit_surface(k, 0, SK_TRI6, 6, 2, slave);
  kit_surface(k, 1, SK_TRI6, 6, 4, master);
}

/* 3D, QUAD8 faces (hex20, mesh.order: 2 with mesh.serendipity): mesh_3d_quad9's faces without their centre nodes
 * (those stay out of every face: their rows and columns are empty). */
static void mesh_3d_quad8(kit *k) {
  mesh_3d_quad9_nodes(k);
  static const int slave[8] = {0, 6, 8, 2, 3, 7, 5, 1};
  int master[16];
  for (int f = 0; f < 2; ++f) {
    const int g = 9 + 2 * f;
    const int m[8] = {g, g + 2, g + 12, g + 10, g + 1, g + 7, g + 11, g + 5};
    memcpy(master + 8 * f, m, sizeof m);
  }
  kit_surface(k, 0, SK_QUAD8, 8, 1, slave);
  kit_surface(k, 1, SK_QUAD8, 8, 2, master);
}

/* 2D self contact: one closed surface, the boundary of a thin slot (a hole 0.01 high between two walls, rounded
 * ends), traversed so that its outward normal points into the slot: the top wall (faces 0-2, normal -y) and the
 * bottom wall (faces 4-6, normal +y) face each other with non-matching nodes; slave and master are the same view. */
static void mesh_2d_self(kit *k) {
  static const double X[16] = {0.0, 0.005, 0.35, 0.006, 0.7, 0.004, 1.0, 0.005, 1.1, 0.0,
                               1.0, -0.005, 0.65, -0.004, 0.3, -0.006};
  static const double more[2] = {-0.1, 0.0};
  double Y[18];
  memcpy(Y, X, sizeof X);
  memcpy(Y + 16, more, sizeof more);
  kit_init(k, 2, 9, Y);
  /* top left -> right, the right end, bottom right -> left, the left end */
  static const int loop[18] = {0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 0};
  kit_surface(k, 0, SK_LINE2, 2, 9, loop);
  kit_surface(k, 1, SK_LINE2, 2, 9, loop);
  k->attach.self_contact = 1;
}

/* The slot of mesh_3d_self on QUAD9 faces: its 18 nodes (X, layers y ~ 0 and 0.5) are the faces' corners; the
 * mid-side and centre nodes are the means of their corners (straight edges, the QUAD4 slot's geometry): nodes
 * 0-8 and 9-17 as in mesh_3d_self, 18-26 the segments' midpoints at both layers (18 + s, 27 + s), 36-44 the
 * corners' mid-layer nodes, 45-53 the segments' mid-layer centres. */
static void mesh_3d_self_quad9(kit *k, const double *X) {
  double Y[54 * 3];
  memcpy(Y, X, sizeof(double) * 54);
  for (int s = 0; s < 9; ++s)
    for (int i = 0; i < 3; ++i) {
      const int a = s, b = (s + 1) % 9;
      Y[3 * (18 + s) + i] = 0.5 * (X[3 * a + i] + X[3 * b + i]);
      Y[3 * (27 + s) + i] = 0.5 * (X[3 * (a + 9) + i] + X[3 * (b + 9) + i]);
      Y[3 * (36 + s) + i] = 0.5 * (X[3 * a + i] + X[3 * (a + 9) + i]);
    }
  for (int s = 0; s < 9; ++s)
    for (int i = 0; i < 3; ++i) Y[3 * (45 + s) + i] = 0.5 * (Y[3 * (18 + s) + i] + Y[3 * (27 + s) + i]);
  kit_init(k, 3, 54, Y);
  int conn[81];
  for (int s = 0; s < 9; ++s) {
    const int a = s, b = (s + 1) % 9;
    /* the QUAD4 slot's corners {a, a + 9, b + 9, b}, then the edges' mid-nodes in that order and the centre */
    const int quad[9] = {a, a + 9, b + 9, b, 36 + a, 27 + s, 36 + b, 18 + s, 45 + s};
    memcpy(conn + 9 * s, quad, sizeof quad);
  }
  kit_surface(k, 0, SK_QUAD9, 9, 9, conn);
  kit_surface(k, 1, SK_QUAD9, 9, 9, conn);
  k->attach.self_contact = 1;
}

/* 3D self contact: the slot of mesh_2d_self (its left end steep, x from -0.01) extruded along y over about [0, 0.5] (nodes i and i + 9), warped, the
 * ends of the extrusion slanted differently on the two walls, so that the walls (top: normal -z, bottom: +z) face
 * each other with non-matching nodes and no edge of one parallel to an edge of the other (coinciding edges make the
 * clipped polygons' derivatives sharply curved, as in the matching quad4 case below); QUAD4 faces (one per 2D
 * segment) or TRI3 (two per segment, faces 2s and 2s + 1). */
static void mesh_3d_self(kit *k, sk_elem_type type) {
  static const double XZ[18] = {0.0, 0.005, 0.35, 0.006, 0.7, 0.004, 1.0, 0.005, 1.1, 0.0,
                                1.0, -0.005, 0.65, -0.004, 0.3, -0.006, -0.01, 0.0};
  double X[54];
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 9; ++i) {
      double *x = X + 3 * (i + 9 * j);
      x[0] = XZ[2 * i];
      x[1] = 0.5 * j + (i < 4 || i == 8 ? 0.1 : -0.1) * (XZ[2 * i] - 0.5); /* the walls' ends cross at 11 deg */
      x[2] = XZ[2 * i + 1] + 0.001 * j * (XZ[2 * i] - 0.5);
    }
  if (type == SK_QUAD9) {
    mesh_3d_self_quad9(k, X);
    return;
  }
  kit_init(k, 3, 18, X);
  int conn[54], n = 0;
  for (int s = 0; s < 9; ++s) {
    const int a = s, b = (s + 1) % 9; /* the 2D loop's segment a -> b */
    if (type == SK_QUAD4) {
      const int quad[4] = {a, a + 9, b + 9, b}; /* normal (a+9 - a) x (b - a): -z on the top wall */
      memcpy(conn + 4 * n++, quad, sizeof quad);
    } else {
      const int t1[3] = {a, a + 9, b + 9}, t2[3] = {a, b + 9, b};
      memcpy(conn + 3 * n++, t1, sizeof t1);
      memcpy(conn + 3 * n++, t2, sizeof t2);
    }
  }
  const int nen = type == SK_QUAD4 ? 4 : 3;
  kit_surface(k, 0, type, nen, n, conn);
  kit_surface(k, 1, type, nen, n, conn);
  k->attach.self_contact = 1;
}

#endif
