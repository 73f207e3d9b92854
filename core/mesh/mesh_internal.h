/* stickslip — mesh module internals shared by its source files (not installed, not part of the API). */
#ifndef STICKSLIP_MESH_INTERNAL_H
#define STICKSLIP_MESH_INTERNAL_H

#include "stickslip/mesh.h"

/* Checks a .geo script and the scripts it includes before gmsh runs them (geo_scan.c): refuses statements that act
 * outside the mesh (shell commands, file writes, Exit, Includes of computed file names) unless scripts are trusted
 * (sk_mesh_trust_scripts), and lists the DefineConstant names, because gmsh 4.8 has no API to list them. On success
 * *names is an array of *n_names malloc'ed strings (free with sk_geo_names_free). */
sk_status sk_geo_scan(const char *path, char ***names, int *n_names);
void sk_geo_names_free(char **names, int n_names);

/* Makes body elements positively oriented and boundary elements face out of the body they bound (see
 * mesh_orient.c). */
sk_status sk_mesh_orient(sk_mesh *mesh);

/* ---- the gmsh model (gmsh_model.c, in libstickslip_gmsh.so) ---------------------------------------------- */

/* gmsh keeps global state: each load runs between its own gmsh initialize and finalize, with the terminal quiet and
 * the logger collecting errors for our message. */
void sk_gmsh_session_begin(void);
void sk_gmsh_session_end(void);
/* Non-zero when the last gmsh call failed (ierr) or logged an error; the error message then names the file. */
int sk_gmsh_failed(int ierr, const char *path, const char *what);
/* The physical groups up to dimension `dim` and the nodes they use, from the current gmsh model. */
sk_status sk_gmsh_read_model(const char *path, int dim, sk_mesh *mesh);
/* The highest dimension carrying a physical group (-1: none) in *highest; 0 when gmsh failed (error set). */
int sk_gmsh_highest_group_dimension(const char *path, int *highest);

/* What gmshModelMeshGetElements returns for one entity (gmsh_model.c): */

/* What gmshModelMeshGetElements returns for one entity: per element type t, tags_n[t] elements with their tags and
 * nodes (nodes_n[t] = tags_n[t] * nodes per element). */
typedef struct {
  int *types;
  size_t n_types, **tags, *tags_n, tags_nn, **nodes, *nodes_n, nodes_nn;
} sk_gmsh_elements;

/* The elements of the entity (dim, tag) (tag -1: all of dimension dim). Returns gmsh's ierr; free the arrays with
 * sk_gmsh_elements_free in every case. */
int sk_gmsh_elements_get(int dim, int tag, sk_gmsh_elements *elements);
void sk_gmsh_elements_free(sk_gmsh_elements *elements);

/* ---- the mesh generator's child process (mesh_sandbox.c) ---------------------------------------------------- */

typedef struct {
  double time_limit;    /* seconds of wall time gmsh may work, from sk_mesh_sandbox_start_clock; <= 0: none */
  size_t memory_limit;  /* bytes of resident memory of the child; 0: none */
  long max_elements;    /* for messages: the element limit the memory limit stands for */
} sk_mesh_sandbox_limits;

/* Work done in the child: fills `mesh` (whose `source` is set) or fails with a message. */
typedef sk_status (*sk_mesh_sandbox_work)(void *arg, sk_mesh *mesh);

/* Runs `work` in a child process and receives its mesh into `mesh` (source set, everything else zero). Every end
 * of the child becomes a status and a message naming mesh->source: its own error, a crash (signal), the time or
 * memory limit, SIGINT/SIGTERM to stickslip (SK_ERR_INTERRUPTED). */
sk_status sk_mesh_sandbox(sk_mesh_sandbox_work work, void *arg, const sk_mesh_sandbox_limits *limits,
                          sk_mesh *mesh);
/* In the child: what it is doing now ("meshing the surfaces (2D)"), for the messages above. */
void sk_mesh_sandbox_phase(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* In the child: the time limit counts from now (called once gmsh is loaded: mesh.time_limit bounds gmsh's work on
 * the file, not the loading of its libraries, which a loaded machine can stretch). */
void sk_mesh_sandbox_start_clock(void);
/* In the child: ends it at once with `status` and the current error message (from inside a gmsh callback). */
_Noreturn void sk_mesh_sandbox_fail(sk_status status);
/* The mesh as one buffer (malloc'ed; NULL when out of memory), and back (every size checked; a corrupt buffer is
 * SK_ERR_INTERNAL, the mesh then partly filled: free it). The pipe's and the mesh cache's format. */
char *sk_mesh_serialize(const sk_mesh *mesh, uint64_t *length);
sk_status sk_mesh_deserialize(const char *buffer, uint64_t length, sk_mesh *mesh);

/* ---- the cache of generated meshes (mesh_cache.c) ------------------------------------------------------------- */

/* What identifies a generated mesh: the .geo text, its parameters, the dimension asked for, mesh.max_elements, the element
 * order asked for (mesh.order, mesh.serendipity), the gmsh version and the cache format. */
typedef struct {
  uint64_t hash[2];
  char file[1100];      /* the cache file, "" when the mesh is not cached (why says why) */
  char why[160];
} sk_mesh_cache_key;

/* Fills the key for a .geo with its parameter text; key->file stays "" (with the reason) when caching is off
 * (STICKSLIP_MESH_CACHE=off, no cache folder, trusted scripts, an unreadable file). */
void sk_mesh_cache_key_make(const char *path, const char *parameters, int dim, const sk_mesh_options *options,
                            sk_mesh_cache_key *key);
/* 1 and the mesh when the cache holds it; 0 otherwise (mesh left empty, source kept). */
int sk_mesh_cache_load(const sk_mesh_cache_key *key, sk_mesh *mesh);
/* Stores a generated mesh (atomically: a private file renamed into place); failures only cost the cache. */
void sk_mesh_cache_store(const sk_mesh_cache_key *key, const sk_mesh *mesh);
/* Records what the cache did for one .geo (shown by sk_mesh_cache_explain): hit 1 read, 0 generated by gmsh. */
void sk_mesh_cache_note(const char *path, const sk_mesh_cache_key *key, int hit);
int sk_mesh_scripts_trusted(void); /* geo_scan.c */

/* ---- staged generation with a size guard (mesh_guard.c, in libstickslip_gmsh.so) ------------------------------ */

typedef struct {
  const char *path;      /* for messages */
  const char *parameters; /* "refine = 1e+06, h_contact = 0.02" or "" */
  long max_elements;
} sk_mesh_guard;

/* Meshes the current gmsh model up to `dim`, one dimension at a time, refusing (a message with the numbers) when the
 * estimate of the final element count or the final count exceeds guard->max_elements. `failed(ierr, what)` reports a
 * gmsh error after each stage (and records the message). */
sk_status sk_mesh_generate_guarded(const sk_mesh_guard *guard, int dim, int (*failed)(int ierr, const char *what));

/* ---- the mesh generator's work (gmsh_load.c, in libstickslip_gmsh.so, loaded only by the child) --------------- */

typedef struct {
  const char *path;        /* the file, for messages */
  const char *open_path;   /* the file gmsh opens (the parameter wrapper, or the file itself) */
  int is_geo, dim;
  int order, serendipity;  /* sk_mesh_options' */
  sk_mesh_guard guard;
} sk_gmsh_load_job;

/* Reads the file or meshes the script and fills `mesh` (its source set), or fails with a message. */
sk_status sk_gmsh_load(const sk_gmsh_load_job *job, sk_mesh *mesh);
typedef sk_status (*sk_gmsh_load_fn)(const sk_gmsh_load_job *job, sk_mesh *mesh);

#endif
