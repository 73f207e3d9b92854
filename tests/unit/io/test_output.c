/* Result writers: CSV, JSON, VTU (both encodings, hex27 node order), PVD, output directory staging, progress. */
#define _POSIX_C_SOURCE 200809L

#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sk_test.h"
#include "stickslip/output.h"

static char tmp_dir[] = "/tmp/sk_io_output_XXXXXX";

static char *read_all(const char *path, size_t *length) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *text = malloc((size_t)n + 1);
  size_t got = text ? fread(text, 1, (size_t)n, f) : 0;
  fclose(f);
  if (text) text[got] = '\0';
  if (length) *length = got;
  return text;
}

static void tmp_path(char *out, size_t n, const char *name) { snprintf(out, n, "%s/%s", tmp_dir, name); }

static int contains(const char *haystack, const char *needle) {
  int found = haystack && strstr(haystack, needle) != NULL;
  if (!found) fprintf(stderr, "  expected '%s' in: %s\n", needle, haystack ? haystack : "(null)");
  return found;
}

static int have_python(void) { return system("python3 -c pass >/dev/null 2>&1") == 0; }

static void test_csv(void) {
  char path[512];
  tmp_path(path, sizeof path, "series.csv");
  const char *names[] = {"step", "t", "a,b", "energy"};
  sk_csv *csv = NULL;
  SK_CHECK(sk_csv_open(path, 4, names, &csv) == SK_OK);
  const double row1[] = {1, 0.1, 1e6, 1.5e-7};
  const double row2[] = {2, -0.0, -3, 1e300};
  SK_CHECK(sk_csv_row(csv, row1) == SK_OK);
  SK_CHECK(sk_csv_row(csv, row2) == SK_OK);
  SK_CHECK(sk_csv_close(csv) == SK_OK);
  char *text = read_all(path, NULL);
  SK_CHECK(text && strcmp(text, "step,t,\"a,b\",energy\n1,0.10000000000000001,1000000,1.4999999999999999e-07\n"
                                "2,0,-3,1.0000000000000001e+300\n") == 0);
  free(text);
  SK_CHECK(sk_csv_open("/nonexistent/dir/x.csv", 4, names, &csv) == SK_ERR_IO && csv == NULL);
  SK_CHECK(contains(sk_error_message(), "/nonexistent/dir/x.csv"));
}

static void test_json(void) {
  char path[512];
  tmp_path(path, sizeof path, "summary.json");
  sk_json *json = NULL;
  SK_CHECK(sk_json_open(path, &json) == SK_OK);
  SK_CHECK(sk_json_string(json, "program", "stickslip") == SK_OK);
  SK_CHECK(sk_json_string(json, "note", "say \"hi\"\\\n\ttab") == SK_OK);
  SK_CHECK(sk_json_number(json, "energy", 0.5) == SK_OK);
  SK_CHECK(sk_json_number(json, "bad", 1.0 / 0.0) == SK_OK);
  SK_CHECK(sk_json_int(json, "steps", 1234567890123L) == SK_OK);
  SK_CHECK(sk_json_bool(json, "converged", 1) == SK_OK);
  SK_CHECK(sk_json_close(json) == SK_OK);
  char *text = read_all(path, NULL);
  SK_CHECK(contains(text, "\"note\": \"say \\\"hi\\\"\\\\\\n\\ttab\""));
  SK_CHECK(contains(text, "\"bad\": null"));
  SK_CHECK(contains(text, "\"steps\": 1234567890123"));
  free(text);
  if (have_python()) {
    char command[1024];
    snprintf(command, sizeof command,
             "python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); "
             "sys.exit(0 if d[\"note\"]==\"say \\\"hi\\\"\\\\\\n\\ttab\" and d[\"converged\"] is True else 1)' %s",
             path);
    SK_CHECK(system(command) == 0);
  }
}

/* ---- VTU ---- */

static int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

/* Decodes the base64 payload of the DataArray called `name`; returns bytes (header included) or NULL. */
static unsigned char *decode_array(const char *text, const char *name, size_t *n_bytes) {
  char pattern[128];
  snprintf(pattern, sizeof pattern, "Name=\"%s\"", name);
  const char *start = strstr(text, pattern);
  if (!start || !(start = strchr(start, '>'))) return NULL;
  ++start;
  size_t cap = strlen(start);
  unsigned char *out = malloc(cap);
  size_t n = 0;
  unsigned acc = 0;
  int bits = 0;
  for (const char *c = start; *c && *c != '<'; ++c) {
    int v = base64_value(*c);
    if (v < 0) continue;
    acc = (acc << 6) | (unsigned)v;
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out[n++] = (unsigned char)(acc >> bits);
      acc &= (1u << bits) - 1;
    }
  }
  *n_bytes = n;
  return out;
}

/* Reads an appended array: offset attribute of `name`, data after the '_' marker. */
static const unsigned char *appended_array(const char *text, size_t length, const char *name, uint64_t *n_bytes) {
  char pattern[128];
  snprintf(pattern, sizeof pattern, "Name=\"%s\"", name);
  const char *element = strstr(text, pattern);
  const char *offset_attr = element ? strstr(element, "offset=\"") : NULL;
  const char *marker = strstr(text, "<AppendedData encoding=\"raw\">");
  if (!offset_attr || !marker || !(marker = strchr(marker, '_'))) return NULL;
  uint64_t offset = strtoull(offset_attr + 8, NULL, 10);
  const unsigned char *block = (const unsigned char *)marker + 1 + offset;
  if (block + 8 > (const unsigned char *)text + length) return NULL;
  memcpy(n_bytes, block, 8);
  return block + 8;
}

/* gmsh hex27 reference nodes: corners, edge midpoints in gmsh edge order, face centres z- y- x- x+ y+ z+, centre. */
static void gmsh_hex27_points(double *x) {
  static const double corner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                      {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  static const int edge[12][2] = {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 5}, {2, 3},
                                  {2, 6}, {3, 7}, {4, 5}, {4, 7}, {5, 6}, {6, 7}};
  static const double face[6][3] = {{0, 0, -1}, {0, -1, 0}, {-1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int a = 0; a < 8; ++a)
    for (int k = 0; k < 3; ++k) x[3 * a + k] = corner[a][k];
  for (int e = 0; e < 12; ++e)
    for (int k = 0; k < 3; ++k) x[3 * (8 + e) + k] = 0.5 * (corner[edge[e][0]][k] + corner[edge[e][1]][k]);
  for (int f = 0; f < 6; ++f)
    for (int k = 0; k < 3; ++k) x[3 * (20 + f) + k] = face[f][k];
  for (int k = 0; k < 3; ++k) x[3 * 26 + k] = 0;
}

/* VTK_TRIQUADRATIC_HEXAHEDRON parametric coordinates (vtkTriQuadraticHexahedron), on [0,1]^3. */
static const double vtk_hex27_pcoords[27][3] = {
    {0, 0, 0},     {1, 0, 0},     {1, 1, 0},     {0, 1, 0},     {0, 0, 1},     {1, 0, 1},     {1, 1, 1},
    {0, 1, 1},     {.5, 0, 0},    {1, .5, 0},    {.5, 1, 0},    {0, .5, 0},    {.5, 0, 1},    {1, .5, 1},
    {.5, 1, 1},    {0, .5, 1},    {0, 0, .5},    {1, 0, .5},    {1, 1, .5},    {0, 1, .5},    {0, .5, .5},
    {1, .5, .5},   {.5, 0, .5},   {.5, 1, .5},   {.5, .5, 0},   {.5, .5, 1},   {.5, .5, .5}};

enum { N_POINTS = 27 + 3, N_CELLS = 3 };

typedef struct {
  double points[3 * N_POINTS];
  sk_elem_type types[N_CELLS];
  int offsets[N_CELLS + 1];
  int conn[27 + 3 + 3];
  double temperature[N_POINTS];
  double velocity[3 * N_POINTS];
  double stress[9 * N_CELLS];
} test_mesh;

static void make_mesh(test_mesh *m) {
  gmsh_hex27_points(m->points);
  /* a tri3 and a line3 beside the hex */
  const double extra[3][3] = {{3, 0, 0}, {4, 0, 0}, {3, 1, 0}};
  memcpy(m->points + 3 * 27, extra, sizeof extra);
  m->types[0] = SK_HEX27;
  m->types[1] = SK_TRI3;
  m->types[2] = SK_LINE3;
  m->offsets[0] = 0;
  m->offsets[1] = 27;
  m->offsets[2] = 30;
  m->offsets[3] = 33;
  for (int a = 0; a < 27; ++a) m->conn[a] = a;
  m->conn[27] = 27, m->conn[28] = 28, m->conn[29] = 29;
  m->conn[30] = 27, m->conn[31] = 28, m->conn[32] = 1; /* line3: ends 27, 28, middle node 1 (any node will do) */
  for (int p = 0; p < N_POINTS; ++p) {
    m->temperature[p] = p;
    for (int k = 0; k < 3; ++k) m->velocity[3 * p + k] = p + 0.1 * k;
  }
  for (int i = 0; i < 9 * N_CELLS; ++i) m->stress[i] = i * 0.5;
}

static sk_status write_mesh(const char *path, const test_mesh *m) {
  const sk_vtu_field point_fields[] = {{"temperature", 1, m->temperature}, {"velocity <v>", 3, m->velocity}};
  const sk_vtu_field cell_fields[] = {{"stress", 9, m->stress}};
  return sk_vtu_write(path, N_POINTS, m->points, N_CELLS, m->types, m->offsets, m->conn, 2, point_fields, 1,
                      cell_fields);
}

/* VTK node k of the hex must sit at VTK's parametric position k (mapped to [-1,1]). */
static void check_hex27_order(const int32_t *conn, const double *points) {
  int wrong = 0;
  for (int k = 0; k < 27; ++k) {
    for (int d = 0; d < 3; ++d) {
      if (points[3 * conn[k] + d] != 2.0 * vtk_hex27_pcoords[k][d] - 1.0) ++wrong;
    }
  }
  SK_CHECK(wrong == 0);
}

static void test_vtu_base64(void) {
  test_mesh *m = calloc(1, sizeof *m);
  make_mesh(m);
  char path[512];
  tmp_path(path, sizeof path, "mesh_b64.vtu");
  sk_vtu_set_encoding(SK_VTU_BASE64);
  SK_CHECK(write_mesh(path, m) == SK_OK);
  sk_vtu_set_encoding(SK_VTU_RAW_APPENDED);
  char *text = read_all(path, NULL);
  SK_CHECK(contains(text, "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\""));
  SK_CHECK(contains(text, "header_type=\"UInt64\""));
  SK_CHECK(contains(text, "<Piece NumberOfPoints=\"30\" NumberOfCells=\"3\">"));
  SK_CHECK(contains(text, "Name=\"velocity &lt;v&gt;\" NumberOfComponents=\"3\""));
  SK_CHECK(contains(text, "Name=\"stress\" NumberOfComponents=\"9\""));
  if (text) {
    size_t n = 0;
    unsigned char *conn_bytes = decode_array(text, "connectivity", &n);
    SK_CHECK(conn_bytes && n == 8 + 33 * 4);
    if (conn_bytes && n == 8 + 33 * 4) {
      uint64_t header;
      memcpy(&header, conn_bytes, 8);
      SK_CHECK(header == 33 * 4);
      int32_t conn[33];
      memcpy(conn, conn_bytes + 8, sizeof conn);
      check_hex27_order(conn, m->points);
      SK_CHECK(conn[27] == 27 && conn[29] == 29 && conn[30] == 27 && conn[32] == 1);
    }
    free(conn_bytes);
    unsigned char *type_bytes = decode_array(text, "types", &n);
    SK_CHECK(type_bytes && n == 8 + 3 && type_bytes[8] == 29 && type_bytes[9] == 5 && type_bytes[10] == 21);
    free(type_bytes);
    unsigned char *offset_bytes = decode_array(text, "offsets", &n);
    int32_t ends[3] = {0};
    if (offset_bytes && n == 8 + 12) memcpy(ends, offset_bytes + 8, 12);
    SK_CHECK(ends[0] == 27 && ends[1] == 30 && ends[2] == 33);
    free(offset_bytes);
    unsigned char *stress_bytes = decode_array(text, "stress", &n);
    double s[27] = {0};
    if (stress_bytes && n == 8 + 27 * 8) memcpy(s, stress_bytes + 8, sizeof s);
    SK_CHECK(s[26] == 13.0);
    free(stress_bytes);
  }
  free(text);
  if (have_python()) {
    char command[1024];
    snprintf(command, sizeof command,
             "python3 -c 'import sys, xml.etree.ElementTree as E; r=E.parse(sys.argv[1]).getroot(); "
             "p=r.find(\"UnstructuredGrid/Piece\"); "
             "sys.exit(0 if p.get(\"NumberOfCells\")==\"3\" and len(p.findall(\"PointData/DataArray\"))==2 else 1)' %s",
             path);
    SK_CHECK(system(command) == 0);
  }
  free(m);
}

static void test_vtu_raw(void) {
  test_mesh *m = calloc(1, sizeof *m);
  make_mesh(m);
  char path[512];
  tmp_path(path, sizeof path, "mesh_raw.vtu");
  SK_CHECK(write_mesh(path, m) == SK_OK);
  size_t length = 0;
  char *text = read_all(path, &length);
  SK_CHECK(contains(text, "format=\"appended\" offset=\"0\""));
  SK_CHECK(contains(text, "<AppendedData encoding=\"raw\">"));
  if (text) {
    uint64_t n = 0;
    const unsigned char *data = appended_array(text, length, "connectivity", &n);
    SK_CHECK(data && n == 33 * 4);
    if (data && n == 33 * 4) {
      int32_t conn[33];
      memcpy(conn, data, sizeof conn);
      check_hex27_order(conn, m->points);
    }
    data = appended_array(text, length, "temperature", &n);
    double t[N_POINTS] = {0};
    if (data && n == sizeof t) memcpy(t, data, sizeof t);
    SK_CHECK(t[29] == 29.0);
    SK_CHECK(length > 10 && strcmp(text + length - 11, "</VTKFile>\n") == 0);
  }
  free(text);

  /* bad input is refused, nothing is left behind */
  char bad_path[512];
  tmp_path(bad_path, sizeof bad_path, "bad.vtu");
  m->conn[5] = 99;
  SK_CHECK(write_mesh(bad_path, m) == SK_ERR_INTERNAL);
  SK_CHECK(contains(sk_error_message(), "refers to node 99"));
  m->conn[5] = 5;
  m->offsets[1] = 26;
  SK_CHECK(write_mesh(bad_path, m) == SK_ERR_INTERNAL);
  SK_CHECK(access(bad_path, F_OK) != 0);
  char tmp[600];
  snprintf(tmp, sizeof tmp, "%s.tmp", bad_path);
  SK_CHECK(access(tmp, F_OK) != 0);
  free(m);
}

static void test_pvd(void) {
  char path[512];
  tmp_path(path, sizeof path, "result.pvd");
  sk_pvd *pvd = NULL;
  SK_CHECK(sk_pvd_open(path, &pvd) == SK_OK);
  char *text = read_all(path, NULL);
  SK_CHECK(contains(text, "<Collection>") && contains(text, "</VTKFile>"));
  free(text);
  SK_CHECK(sk_pvd_add(pvd, 0.0, "vtu/step_0000.vtu") == SK_OK);
  text = read_all(path, NULL);
  SK_CHECK(contains(text, "<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"vtu/step_0000.vtu\"/>"));
  SK_CHECK(contains(text, "</VTKFile>"));
  free(text);
  SK_CHECK(sk_pvd_add(pvd, 0.25, "vtu/step_0001.vtu") == SK_OK);
  text = read_all(path, NULL);
  SK_CHECK(contains(text, "timestep=\"0.25\" group=\"\" part=\"0\" file=\"vtu/step_0001.vtu\""));
  free(text);
  SK_CHECK(sk_pvd_close(pvd) == SK_OK);
  if (have_python()) {
    char command[1024];
    snprintf(command, sizeof command,
             "python3 -c 'import sys, xml.etree.ElementTree as E; r=E.parse(sys.argv[1]).getroot(); "
             "sys.exit(0 if len(r.findall(\"Collection/DataSet\"))==2 else 1)' %s", path);
    SK_CHECK(system(command) == 0);
  }
}

static void test_pvtu(void) {
  char path[512];
  tmp_path(path, sizeof path, "step-000001.pvtu");
  double values[3] = {0};
  const sk_vtu_field point_fields[] = {{"displacement", 3, values}, {"node_id", 1, values}};
  const sk_vtu_field cell_fields[] = {{"stress <s>", 9, values}};
  const char *const pieces[] = {"step-000001/rank-0000.vtu", "step-000001/rank-0001.vtu"};
  SK_CHECK(sk_pvtu_write(path, 2, pieces, 2, point_fields, 1, cell_fields) == SK_OK);
  char *text = read_all(path, NULL);
  SK_CHECK(contains(text, "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\""));
  SK_CHECK(contains(text, "header_type=\"UInt64\""));
  SK_CHECK(contains(text, "<PDataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\"/>"));
  SK_CHECK(contains(text, "Name=\"stress &lt;s&gt;\" NumberOfComponents=\"9\""));
  SK_CHECK(contains(text, "<PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>"));
  SK_CHECK(contains(text, "<Piece Source=\"step-000001/rank-0001.vtu\"/>"));
  free(text);
  if (have_python()) {
    char command[1024];
    snprintf(command, sizeof command,
             "python3 -c 'import sys, xml.etree.ElementTree as E; g=E.parse(sys.argv[1]).getroot()[0]; "
             "sys.exit(0 if len(g.findall(\"Piece\"))==2 and len(g.find(\"PPointData\"))==2 "
             "and len(g.find(\"PCellData\"))==1 else 1)' %s", path);
    SK_CHECK(system(command) == 0);
  }
  SK_CHECK(sk_pvtu_write(path, 0, pieces, 2, point_fields, 1, cell_fields) == SK_ERR_INTERNAL);
  SK_CHECK(sk_pvtu_write("/nonexistent/dir/x.pvtu", 2, pieces, 2, point_fields, 1, cell_fields) == SK_ERR_IO);
  SK_CHECK(contains(sk_error_message(), "/nonexistent/dir/x.pvtu"));
}

/* ---- output directories ---- */

static void test_progress(void) {
  char path[512];
  tmp_path(path, sizeof path, "progress.log");
  fflush(stderr);
  int saved = dup(fileno(stderr));
  int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  dup2(fd, fileno(stderr));
  close(fd);
  sk_progress_begin("test", 1.0);
  for (int step = 1; step <= 200; ++step) sk_progress_update(step, step / 200.0, 3, "slip 0.1");
  sk_progress_end(NULL);
  fflush(stderr);
  dup2(saved, fileno(stderr));
  close(saved);
  char *text = read_all(path, NULL);
  int lines = 0;
  for (const char *c = text; c && *c; ++c) lines += *c == '\n';
  SK_CHECK(lines == 11); /* 10% marks plus the final line (not a terminal) */
  SK_CHECK(contains(text, "test: step 200"));
  SK_CHECK(contains(text, "slip 0.1"));
  SK_CHECK(contains(text, "test: done, 200 steps"));
  SK_CHECK(text && strchr(text, '\r') == NULL);
  free(text);
}

int main(void) {
  if (!mkdtemp(tmp_dir)) {
    perror("mkdtemp");
    return 1;
  }
  test_csv();
  test_json();
  test_vtu_base64();
  test_vtu_raw();
  test_pvd();
  test_pvtu();
  test_progress();
  int result = sk_test_finish("test_io_output");
  if (result == 0) {
    char command[600];
    snprintf(command, sizeof command, "rm -rf '%s'", tmp_dir);
    if (system(command) != 0) fprintf(stderr, "could not remove %s\n", tmp_dir);
  } else {
    fprintf(stderr, "files kept in %s\n", tmp_dir);
  }
  return result;
}
