/* VTK XML unstructured grids (.vtu) and ParaView collections (.pvd). */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/output.h"

static sk_vtu_encoding vtu_encoding = SK_VTU_RAW_APPENDED;

void sk_vtu_set_encoding(sk_vtu_encoding encoding) { vtu_encoding = encoding; }

static const int vtk_cell_ids[SK_ELEM_TYPE_COUNT] = {
    [SK_POINT1] = 1, [SK_LINE2] = 3, [SK_LINE3] = 21, [SK_TRI3] = 5,   [SK_QUAD4] = 9,  [SK_QUAD9] = 28,
    [SK_TET4] = 10,  [SK_HEX8] = 12, [SK_HEX27] = 29, [SK_TRI6] = 22,  [SK_QUAD8] = 23, [SK_TET10] = 24,
    [SK_HEX20] = 25,
};
static const int nodes_per_cell[SK_ELEM_TYPE_COUNT] = {
    [SK_POINT1] = 1, [SK_LINE2] = 2, [SK_LINE3] = 3,   [SK_TRI3] = 3, [SK_QUAD4] = 4,  [SK_QUAD9] = 9,
    [SK_TET4] = 4,   [SK_HEX8] = 8,  [SK_HEX27] = 27,  [SK_TRI6] = 6, [SK_QUAD8] = 8,  [SK_TET10] = 10,
    [SK_HEX20] = 20,
};

/* VTK node k = gmsh node order[k]. line3, tri6, quad8 and quad9 agree (corners, edge midpoints in edge order,
 * centre). tet10: gmsh's last two edges are (2,3) (1,3), VTK's (1,3) (2,3). For hex20 and hex27 gmsh lists edges
 * (0,1) (0,3) (0,4) (1,2) (1,5) (2,3) (2,6) (3,7) (4,5) (4,7) (5,6) (6,7) and faces z- y- x- x+ y+ z+, while VTK
 * lists edges (0,1) (1,2) (2,3) (3,0) (4,5) (5,6) (6,7) (7,4) (0,4) (1,5) (2,6) (3,7) and faces x- x+ y- y+ z- z+
 * (vtkQuadraticHexahedron, vtkTriQuadraticHexahedron; same permutation as meshio). */
static const int identity_order[27] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 12, 13,
                                       14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26};
static const int tet10_order[10] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};
/* hex20 is the first 20 entries (vtkQuadraticHexahedron has hex27's edge order). */
static const int hex27_order[27] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  11, 13, 9,  16, 18,
                                    19, 17, 10, 12, 14, 15, 22, 23, 21, 24, 20, 25, 26};

int sk_vtu_cell_type(sk_elem_type type) {
  return (unsigned)type < SK_ELEM_TYPE_COUNT ? vtk_cell_ids[type] : -1;
}

const int *sk_vtu_node_order(sk_elem_type type) {
  if (type == SK_HEX27 || type == SK_HEX20) return hex27_order;
  return type == SK_TET10 ? tet10_order : identity_order;
}

/* ---- encoding --------------------------------------------------------------------------------------------- */

typedef struct {
  FILE *f;
  unsigned char carry[3];
  int n_carry;
} base64_stream;

static void base64_flush_group(base64_stream *s, int n) {
  static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  unsigned v = (unsigned)s->carry[0] << 16 | (unsigned)(n > 1 ? s->carry[1] : 0) << 8 | (n > 2 ? s->carry[2] : 0);
  char out[4] = {digits[(v >> 18) & 63], digits[(v >> 12) & 63], n > 1 ? digits[(v >> 6) & 63] : '=',
                 n > 2 ? digits[v & 63] : '='};
  fwrite(out, 1, 4, s->f);
}

static void base64_write(base64_stream *s, const void *data, size_t n) {
  const unsigned char *p = data;
  for (size_t i = 0; i < n; ++i) {
    s->carry[s->n_carry++] = p[i];
    if (s->n_carry == 3) {
      base64_flush_group(s, 3);
      s->n_carry = 0;
    }
  }
}

static void base64_end(base64_stream *s) {
  if (s->n_carry) base64_flush_group(s, s->n_carry);
  s->n_carry = 0;
}

typedef struct {
  const char *name;
  const char *type; /* Float64, Int32, UInt8 */
  int components;
  const void *data;
  size_t n_bytes;
} data_array;

static void write_xml_text(FILE *f, const char *s) {
  for (; *s; ++s) {
    switch (*s) {
      case '&': fputs("&amp;", f); break;
      case '<': fputs("&lt;", f); break;
      case '>': fputs("&gt;", f); break;
      case '"': fputs("&quot;", f); break;
      default: fputc(*s, f);
    }
  }
}

/* The DataArray element; in appended mode its data goes to the end at *offset. */
static void write_array(FILE *f, const data_array *a, uint64_t *offset) {
  fprintf(f, "        <DataArray type=\"%s\" Name=\"", a->type);
  write_xml_text(f, a->name);
  fprintf(f, "\" NumberOfComponents=\"%d\"", a->components);
  if (vtu_encoding == SK_VTU_RAW_APPENDED) {
    fprintf(f, " format=\"appended\" offset=\"%llu\"/>\n", (unsigned long long)*offset);
    *offset += sizeof(uint64_t) + a->n_bytes;
    return;
  }
  fputs(" format=\"binary\">\n          ", f);
  /* Uncompressed inline binary: the byte-count header and the data form one base64 stream. */
  base64_stream s = {.f = f};
  uint64_t header = a->n_bytes;
  base64_write(&s, &header, sizeof header);
  base64_write(&s, a->data, a->n_bytes);
  base64_end(&s);
  fputs("\n        </DataArray>\n", f);
}

static int host_is_little_endian(void) {
  const uint16_t one = 1;
  return *(const unsigned char *)&one == 1;
}

/* ---- VTU -------------------------------------------------------------------------------------------------- */

static sk_status check_fields(const char *path, const char *what, int n, const sk_vtu_field *fields) {
  for (int i = 0; i < n; ++i) {
    if (!fields[i].name || fields[i].components < 1 || !fields[i].values) {
      return sk_error_set(SK_ERR_INTERNAL, "%s: %s field %d ('%s') has no name, values or components", path, what,
                          i, fields[i].name ? fields[i].name : "");
    }
  }
  return SK_OK;
}

sk_status sk_vtu_write(const char *path, int n_points, const double *points, int n_cells,
                       const sk_elem_type *cell_types, const int *cell_offsets, const int *cell_conn,
                       int n_point_fields, const sk_vtu_field *point_fields, int n_cell_fields,
                       const sk_vtu_field *cell_fields) {
  if (n_points < 0 || n_cells < 0 || (n_points > 0 && !points) ||
      (n_cells > 0 && (!cell_types || !cell_offsets || !cell_conn)) || n_point_fields < 0 || n_cell_fields < 0) {
    return sk_error_set(SK_ERR_INTERNAL, "%s: inconsistent mesh arguments for the VTU writer", path);
  }
  SK_TRY(check_fields(path, "point", n_point_fields, point_fields));
  SK_TRY(check_fields(path, "cell", n_cell_fields, cell_fields));
  if (n_cells > 0 && cell_offsets[0] != 0) {
    return sk_error_set(SK_ERR_INTERNAL, "%s: cell offsets must start at 0", path);
  }
  for (int c = 0; c < n_cells; ++c) {
    if ((unsigned)cell_types[c] >= SK_ELEM_TYPE_COUNT) {
      return sk_error_set(SK_ERR_INTERNAL, "%s: cell %d has an unknown element type %d", path, c, (int)cell_types[c]);
    }
    if (cell_offsets[c + 1] - cell_offsets[c] != nodes_per_cell[cell_types[c]]) {
      return sk_error_set(SK_ERR_INTERNAL, "%s: cell %d has %d nodes, its type needs %d", path, c,
                          cell_offsets[c + 1] - cell_offsets[c], nodes_per_cell[cell_types[c]]);
    }
  }
  size_t n_conn = n_cells > 0 ? (size_t)cell_offsets[n_cells] : 0;
  int32_t *conn = malloc(n_conn * sizeof *conn + 1);
  int32_t *ends = malloc((size_t)n_cells * sizeof *ends + 1);
  uint8_t *types = malloc((size_t)n_cells + 1);
  if (!conn || !ends || !types) {
    free(conn);
    free(ends);
    free(types);
    return sk_error_set(SK_ERR_NOMEM, "%s: out of memory", path);
  }
  sk_status status = SK_OK;
  for (int c = 0; c < n_cells && status == SK_OK; ++c) {
    const int *order = sk_vtu_node_order(cell_types[c]);
    const int *cell = cell_conn + cell_offsets[c];
    for (int k = 0; k < nodes_per_cell[cell_types[c]]; ++k) {
      int node = cell[order[k]];
      if (node < 0 || node >= n_points) {
        status = sk_error_set(SK_ERR_INTERNAL, "%s: cell %d refers to node %d, there are %d points", path, c, node,
                              n_points);
        break;
      }
      conn[cell_offsets[c] + k] = node;
    }
    ends[c] = cell_offsets[c + 1];
    types[c] = (uint8_t)vtk_cell_ids[cell_types[c]];
  }

  char tmp_path[4096];
  FILE *f = NULL;
  if (status == SK_OK) {
    if ((size_t)snprintf(tmp_path, sizeof tmp_path, "%s.tmp", path) >= sizeof tmp_path) {
      status = sk_error_set(SK_ERR_IO, "%s: path too long", path);
    } else if (!(f = fopen(tmp_path, "wb"))) {
      status = sk_error_set(SK_ERR_IO, "cannot create '%s': %s", tmp_path, strerror(errno));
    }
  }
  if (status == SK_OK) {
    int n_arrays = n_point_fields + n_cell_fields + 4;
    data_array *arrays = malloc((size_t)n_arrays * sizeof *arrays);
    if (!arrays) {
      status = sk_error_set(SK_ERR_NOMEM, "%s: out of memory", path);
    } else {
      int k = 0;
      for (int i = 0; i < n_point_fields; ++i) {
        arrays[k++] = (data_array){point_fields[i].name, "Float64", point_fields[i].components,
                                   point_fields[i].values,
                                   (size_t)n_points * (size_t)point_fields[i].components * sizeof(double)};
      }
      for (int i = 0; i < n_cell_fields; ++i) {
        arrays[k++] = (data_array){cell_fields[i].name, "Float64", cell_fields[i].components, cell_fields[i].values,
                                   (size_t)n_cells * (size_t)cell_fields[i].components * sizeof(double)};
      }
      arrays[k++] = (data_array){"Points", "Float64", 3, points, (size_t)n_points * 3 * sizeof(double)};
      arrays[k++] = (data_array){"connectivity", "Int32", 1, conn, n_conn * sizeof *conn};
      arrays[k++] = (data_array){"offsets", "Int32", 1, ends, (size_t)n_cells * sizeof *ends};
      arrays[k++] = (data_array){"types", "UInt8", 1, types, (size_t)n_cells};

      uint64_t offset = 0;
      fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"%s\" "
                 "header_type=\"UInt64\">\n  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"%d\" "
                 "NumberOfCells=\"%d\">\n",
              host_is_little_endian() ? "LittleEndian" : "BigEndian", n_points, n_cells);
      fputs("      <PointData>\n", f);
      for (int i = 0; i < n_point_fields; ++i) write_array(f, &arrays[i], &offset);
      fputs("      </PointData>\n      <CellData>\n", f);
      for (int i = 0; i < n_cell_fields; ++i) write_array(f, &arrays[n_point_fields + i], &offset);
      fputs("      </CellData>\n      <Points>\n", f);
      write_array(f, &arrays[k - 4], &offset);
      fputs("      </Points>\n      <Cells>\n", f);
      for (int i = k - 3; i < k; ++i) write_array(f, &arrays[i], &offset);
      fputs("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n", f);
      if (vtu_encoding == SK_VTU_RAW_APPENDED) {
        fputs("  <AppendedData encoding=\"raw\">\n   _", f);
        for (int i = 0; i < k; ++i) {
          uint64_t header = arrays[i].n_bytes;
          fwrite(&header, sizeof header, 1, f);
          if (arrays[i].n_bytes) fwrite(arrays[i].data, 1, arrays[i].n_bytes, f);
        }
        fputs("\n  </AppendedData>\n", f);
      }
      fputs("</VTKFile>\n", f);
      free(arrays);
    }
    int write_failed = ferror(f);
    if ((fclose(f) != 0 || write_failed) && status == SK_OK) {
      status = sk_error_set(SK_ERR_IO, "cannot write '%s': %s", tmp_path, strerror(errno));
    }
    if (status == SK_OK && rename(tmp_path, path) != 0) {
      status = sk_error_set(SK_ERR_IO, "cannot rename '%s' to '%s': %s", tmp_path, path, strerror(errno));
    }
    if (status != SK_OK) remove(tmp_path);
  }
  free(conn);
  free(ends);
  free(types);
  return status;
}

/* Closes a file written aside at tmp_path and puts it in place of path (removed on failure). */
static sk_status close_and_rename(FILE *f, const char *tmp_path, const char *path) {
  int write_failed = ferror(f);
  if ((fclose(f) != 0) | write_failed) {
    remove(tmp_path);
    return sk_error_set(SK_ERR_IO, "cannot write '%s'", tmp_path);
  }
  if (rename(tmp_path, path) != 0) {
    remove(tmp_path);
    return sk_error_set(SK_ERR_IO, "cannot rename '%s' to '%s': %s", tmp_path, path, strerror(errno));
  }
  return SK_OK;
}

/* ---- PVTU ------------------------------------------------------------------------------------------------- */

static void write_parallel_array(FILE *f, const char *type, const char *name, int components) {
  fprintf(f, "      <PDataArray type=\"%s\" Name=\"", type);
  write_xml_text(f, name);
  fprintf(f, "\" NumberOfComponents=\"%d\"/>\n", components);
}

sk_status sk_pvtu_write(const char *path, int n_pieces, const char *const *pieces, int n_point_fields,
                        const sk_vtu_field *point_fields, int n_cell_fields, const sk_vtu_field *cell_fields) {
  if (n_pieces < 1 || !pieces || n_point_fields < 0 || n_cell_fields < 0)
    return sk_error_set(SK_ERR_INTERNAL, "%s: a parallel grid needs pieces", path);
  char tmp_path[4096];
  if ((size_t)snprintf(tmp_path, sizeof tmp_path, "%s.tmp", path) >= sizeof tmp_path)
    return sk_error_set(SK_ERR_IO, "%s: path too long", path);
  FILE *f = fopen(tmp_path, "w");
  if (!f) return sk_error_set(SK_ERR_IO, "cannot create '%s': %s", tmp_path, strerror(errno));
  /* the same header type and byte order as the pieces (sk_vtu_write) */
  fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"%s\" "
             "header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n    <PPointData>\n",
          host_is_little_endian() ? "LittleEndian" : "BigEndian");
  for (int i = 0; i < n_point_fields; ++i)
    write_parallel_array(f, "Float64", point_fields[i].name, point_fields[i].components);
  fputs("    </PPointData>\n    <PCellData>\n", f);
  for (int i = 0; i < n_cell_fields; ++i)
    write_parallel_array(f, "Float64", cell_fields[i].name, cell_fields[i].components);
  fputs("    </PCellData>\n    <PPoints>\n", f);
  write_parallel_array(f, "Float64", "Points", 3);
  fputs("    </PPoints>\n", f);
  for (int k = 0; k < n_pieces; ++k) {
    fputs("    <Piece Source=\"", f);
    write_xml_text(f, pieces[k]);
    fputs("\"/>\n", f);
  }
  fputs("  </PUnstructuredGrid>\n</VTKFile>\n", f);
  return close_and_rename(f, tmp_path, path);
}

/* ---- PVD -------------------------------------------------------------------------------------------------- */

struct sk_pvd {
  char *path;
  int n, cap;
  double *times;
  char **files;
};

static sk_status pvd_rewrite(const sk_pvd *pvd) {
  char tmp_path[4096];
  if ((size_t)snprintf(tmp_path, sizeof tmp_path, "%s.tmp", pvd->path) >= sizeof tmp_path) {
    return sk_error_set(SK_ERR_IO, "%s: path too long", pvd->path);
  }
  FILE *f = fopen(tmp_path, "w");
  if (!f) return sk_error_set(SK_ERR_IO, "cannot create '%s': %s", tmp_path, strerror(errno));
  fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"%s\">\n"
             "  <Collection>\n", host_is_little_endian() ? "LittleEndian" : "BigEndian");
  for (int i = 0; i < pvd->n; ++i) {
    fprintf(f, "    <DataSet timestep=\"%.17g\" group=\"\" part=\"0\" file=\"", pvd->times[i]);
    write_xml_text(f, pvd->files[i]);
    fputs("\"/>\n", f);
  }
  fputs("  </Collection>\n</VTKFile>\n", f);
  return close_and_rename(f, tmp_path, pvd->path);
}

sk_status sk_pvd_open(const char *path, sk_pvd **pvd) {
  *pvd = NULL;
  sk_pvd *p = calloc(1, sizeof *p);
  if (!p || !(p->path = strdup(path))) {
    free(p);
    return sk_error_set(SK_ERR_NOMEM, "%s: out of memory", path);
  }
  sk_status status = pvd_rewrite(p); /* an empty but valid collection from the start */
  if (status != SK_OK) {
    free(p->path);
    free(p);
    return status;
  }
  *pvd = p;
  return SK_OK;
}

sk_status sk_pvd_add(sk_pvd *pvd, double time, const char *vtu_relative_path) {
  if (!pvd || !vtu_relative_path) return sk_error_set(SK_ERR_INTERNAL, "sk_pvd_add: NULL argument");
  if (pvd->n == pvd->cap) {
    int cap = pvd->cap ? 2 * pvd->cap : 64;
    double *times = realloc(pvd->times, (size_t)cap * sizeof *times);
    if (times) pvd->times = times;
    char **files = times ? realloc(pvd->files, (size_t)cap * sizeof *files) : NULL;
    if (!files) return sk_error_set(SK_ERR_NOMEM, "%s: out of memory", pvd->path);
    pvd->files = files;
    pvd->cap = cap;
  }
  char *file = strdup(vtu_relative_path);
  if (!file) return sk_error_set(SK_ERR_NOMEM, "%s: out of memory", pvd->path);
  pvd->times[pvd->n] = time;
  pvd->files[pvd->n++] = file;
  return pvd_rewrite(pvd);
}

sk_status sk_pvd_close(sk_pvd *pvd) {
  if (!pvd) return SK_OK;
  for (int i = 0; i < pvd->n; ++i) free(pvd->files[i]);
  free(pvd->files);
  free(pvd->times);
  free(pvd->path);
  free(pvd);
  return SK_OK;
}
