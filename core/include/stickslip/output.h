/* stickslip — result files: CSV time series, VTU/PVD fields for ParaView, a flat summary.json, atomic output
 * directories and a progress line. */
#ifndef STICKSLIP_OUTPUT_H
#define STICKSLIP_OUTPUT_H

#include <stddef.h>

#include "stickslip/error.h"
#include "stickslip/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- CSV: one header line, then one row per call (flushed, so the file can be watched while running) ------ */
typedef struct sk_csv sk_csv;
sk_status sk_csv_open(const char *path, int n_columns, const char *const *names, sk_csv **csv);
/* n_columns values: %.17g, integral values without exponent (e.g. 1000000 not 1e+06). */
sk_status sk_csv_row(sk_csv *csv, const double *values);
sk_status sk_csv_close(sk_csv *csv); /* NULL is fine */

/* ---- VTU / PVD -------------------------------------------------------------------------------------------- */
typedef struct {
  const char *name;
  int components;       /* 1 (scalar), 3 (vector), 9 (tensor, row-major) or any other count */
  const double *values; /* components per point (or per cell) */
} sk_vtu_field;

typedef enum {
  SK_VTU_RAW_APPENDED = 0, /* binary appended raw: smallest and fastest (default) */
  SK_VTU_BASE64 = 1        /* base64 inline: pure XML text, for tools that parse the XML */
} sk_vtu_encoding;
/* Process-wide encoding used by sk_vtu_write. */
void sk_vtu_set_encoding(sk_vtu_encoding encoding);

/* Writes an unstructured grid. Connectivity is in gmsh node order (as in sk_mesh) and is permuted to VTK order
 * here (hex27 differs). cell_offsets has n_cells + 1 entries starting at 0; cell c uses
 * cell_conn[cell_offsets[c] .. cell_offsets[c+1]). The file appears atomically (written aside, then renamed). */
sk_status sk_vtu_write(const char *path, int n_points, const double *points /* 3 per point */, int n_cells,
                       const sk_elem_type *cell_types, const int *cell_offsets, const int *cell_conn,
                       int n_point_fields, const sk_vtu_field *point_fields, int n_cell_fields,
                       const sk_vtu_field *cell_fields);
/* VTK cell type id of an element type (line2 3, line3 21, tri3 5, quad4 9, quad9 28, tet4 10, hex8 12,
 * hex27 29, point1 1), and the VTK→gmsh node permutation (vtk node k is gmsh node perm[k]). */
int sk_vtu_cell_type(sk_elem_type type);
const int *sk_vtu_node_order(sk_elem_type type);

/* A parallel unstructured grid (.pvtu): the pieces (paths relative to the .pvtu) that sk_vtu_write wrote with these
 * point and cell fields, in this order (their values are not read: only names and components). Atomic as above. */
sk_status sk_pvtu_write(const char *path, int n_pieces, const char *const *pieces, int n_point_fields,
                        const sk_vtu_field *point_fields, int n_cell_fields, const sk_vtu_field *cell_fields);

/* ParaView collection: one entry per time step. The file is rewritten complete after each add. */
typedef struct sk_pvd sk_pvd;
sk_status sk_pvd_open(const char *path, sk_pvd **pvd);
sk_status sk_pvd_add(sk_pvd *pvd, double time, const char *vtu_relative_path);
sk_status sk_pvd_close(sk_pvd *pvd); /* NULL is fine */

/* ---- JSON: a flat object, one key per call; strings are escaped; non-finite numbers become null ------------ */
typedef struct sk_json sk_json;
sk_status sk_json_open(const char *path, sk_json **json);
sk_status sk_json_string(sk_json *json, const char *key, const char *value);
sk_status sk_json_number(sk_json *json, const char *key, double value);
sk_status sk_json_int(sk_json *json, const char *key, long value);
sk_status sk_json_bool(sk_json *json, const char *key, int value);
sk_status sk_json_close(sk_json *json); /* NULL is fine */

/* ---- the results folder (--out DIR): see core/io/outdir.c and docs/user-guide.md for the guarantees --------- */
typedef enum { SK_RESULTS_OK = 0, SK_RESULTS_FAILED = 1, SK_RESULTS_INTERRUPTED = 2 } sk_results_status;

/* Creates a fresh staging directory "DIR.partial-PID" next to `dir` (parents of `dir` are created) with a manifest
 * saying it is in progress. Refuses, before anything is written: a `dir` that holds anything stickslip did not write
 * (the message names the file), a `dir` that is or contains the current directory ("--out ."), "" and "/". Names on
 * stderr the staging folders of earlier runs into `dir` whose process no longer exists (killed runs). */
sk_status sk_outdir_begin(const char *dir, char *staging, size_t staging_size);
/* Writes the manifest (every file in `staging`, and `status`) and puts `staging` in place: as `dir`, or, when the
 * run did not finish (`status` not SK_RESULTS_OK) while `dir` holds finished results, as "DIR.incomplete". An
 * existing target is replaced only if it holds nothing but files its manifest lists. `final_dir` (may be NULL)
 * receives where the results are now: the target, or `staging` itself when the commit failed. */
sk_status sk_outdir_commit(const char *staging, const char *dir, sk_results_status status, char *final_dir,
                           size_t final_size);
/* Removes a staging directory (when its results cannot be completed, e.g. a full disk); refuses anything that is
 * not an in-progress staging directory. */
sk_status sk_outdir_abort(const char *staging);
/* Name of the manifest file in every results folder. */
#define SK_OUTDIR_MARKER ".stickslip-output"

/* ---- progress: one updating line on a terminal, one line per ~10% otherwise (logs) ------------------------ */
void sk_progress_begin(const char *label, double t_end);
void sk_progress_update(int step, double t, int newton_its, const char *extra);
/* The last line: "done, N steps in T", or with `stopped` ("failed", "interrupted") "<stopped> after N steps, T". */
void sk_progress_end(const char *stopped);

#ifdef __cplusplus
}
#endif
#endif
