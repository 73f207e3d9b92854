/* sk_mesh_load: .geo scripts are meshed and .msh files read through the gmsh C API in a child process (gmsh_load.c); the physical groups become
 * sk_groups with compact 0-based node ids (gmsh's element node ordering is kept). */
#define _GNU_SOURCE /* realpath, mkstemps, dladdr */

#include <errno.h>
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mesh_internal.h"
#include "stickslip/files.h"

/* ---- .geo parameters --------------------------------------------------------------------------------------- */

static int is_identifier(const char *name) {
  if (!name || !(name[0] == '_' || (name[0] >= 'a' && name[0] <= 'z') || (name[0] >= 'A' && name[0] <= 'Z')))
    return 0;
  for (const char *c = name; *c; ++c)
    if (!(*c == '_' || (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9'))) return 0;
  return 1;
}

/* Every parameter must be a DefineConstant of the script: typos are errors, not silently ignored values. */
static sk_status check_parameters(const char *path, const sk_mesh_param *params, int n_params) {
  char **names = NULL;
  int n_names = 0;
  SK_TRY(sk_geo_scan(path, &names, &n_names));
  sk_status status = SK_OK;
  for (int p = 0; p < n_params && status == SK_OK; ++p) {
    const char *name = params[p].name;
    if (!is_identifier(name)) {
      status = sk_error_set(SK_ERR_INPUT, "mesh %s: parameter name '%s' is not a valid identifier", path,
                            name ? name : "(null)");
      break;
    }
    if (!isfinite(params[p].value)) {
      status = sk_error_set(SK_ERR_INPUT, "mesh %s: parameter '%s' has a non-finite value", path, name);
      break;
    }
    int known = 0;
    for (int i = 0; i < n_names; ++i) known |= strcmp(names[i], name) == 0;
    if (!known) {
      char list[1024] = "";
      for (int i = 0; i < n_names; ++i) {
        size_t used = strlen(list);
        snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", names[i]);
      }
      status = sk_error_set(SK_ERR_INPUT, "mesh %s: unknown parameter '%s' (the script defines: %s)", path, name,
                            n_names ? list : "none");
    }
  }
  sk_geo_names_free(names, n_names);
  return status;
}

/* gmsh 4.8's ways to set a DefineConstant (-setnumber, ONELAB) outlive gmshFinalize, so a later load would see
 * stale values. Instead a temporary script assigns the values and includes the real one: DefineConstant keeps a
 * value that already exists. */
static sk_status write_wrapper_script(const char *path, const sk_mesh_param *params, int n_params,
                                      char *wrapper, size_t wrapper_size) {
  char *absolute = realpath(path, NULL);
  if (!absolute) return sk_error_set(SK_ERR_IO, "mesh %s: cannot resolve path: %s", path, strerror(errno));
  if (strchr(absolute, '"')) {
    free(absolute);
    return sk_error_set(SK_ERR_INPUT, "mesh %s: the path must not contain a double quote", path);
  }
  const char *tmpdir = getenv("TMPDIR");
  if (!tmpdir || !tmpdir[0]) tmpdir = "/tmp";
  int n = snprintf(wrapper, wrapper_size, "%s/stickslip-mesh-XXXXXX.geo", tmpdir);
  if (n < 0 || (size_t)n >= wrapper_size) {
    free(absolute);
    return sk_error_set(SK_ERR_IO, "mesh %s: TMPDIR path too long", path);
  }
  int fd = mkstemps(wrapper, 4);
  if (fd < 0) {
    free(absolute);
    return sk_error_set(SK_ERR_IO, "mesh %s: cannot create a temporary script in %s: %s", path, tmpdir,
                        strerror(errno));
  }
  FILE *file = fdopen(fd, "w");
  if (!file) {
    close(fd);
    unlink(wrapper);
    free(absolute);
    return sk_error_set(SK_ERR_IO, "mesh %s: cannot write a temporary script: %s", path, strerror(errno));
  }
  for (int p = 0; p < n_params; ++p) fprintf(file, "%s = %.17g;\n", params[p].name, params[p].value);
  fprintf(file, "Include \"%s\";\n", absolute);
  free(absolute);
  if (fclose(file) != 0) {
    unlink(wrapper);
    return sk_error_set(SK_ERR_IO, "mesh %s: cannot write a temporary script: %s", path, strerror(errno));
  }
  return SK_OK;
}


static sk_status check_plane(const char *path, const sk_mesh *mesh) {
  double extent = 0.0;
  for (int i = 0; i < 3 * mesh->n_nodes; ++i) extent = fmax(extent, fabs(mesh->x[i]));
  for (int n = 0; n < mesh->n_nodes; ++n)
    if (fabs(mesh->x[3 * n + 2]) > 1e-12 * fmax(extent, 1.0))
      return sk_error_set(SK_ERR_INPUT, "mesh %s: a 2D mesh must lie in the plane z = 0, but node %d has z = %g",
                          path, n, mesh->x[3 * n + 2]);
  return SK_OK;
}

/* ---- the work done in the mesh generator's child process ------------------------------------------------------ */

/* gmsh and what it links (OpenCASCADE, FLTK, X11, image and network libraries: 79 libraries, 37 MiB resident) are
 * mapped only in the mesh generator's child: it loads libstickslip_gmsh.so from the folder of this library, so no
 * rank of a run ever holds them (docs/scaling.md, "What the part that does not fall with p is made of"). A library
 * that is dlclose'd is not unmapped here (gmsh's C++ libraries are marked NODELETE), hence the child. */
static sk_status load_in_child(void *arg, sk_mesh *mesh) {
  const sk_gmsh_load_job *job = arg;
  Dl_info self;
  if (!dladdr((void *)sk_mesh_load_with, &self) || !self.dli_fname)
    return sk_error_set(SK_ERR_INTERNAL, "mesh %s: cannot find the folder of libstickslip_core", job->path);
  char library[4096];
  const char *slash = strrchr(self.dli_fname, '/');
  int folder = slash ? (int)(slash - self.dli_fname) : 1;
  int n = snprintf(library, sizeof library, "%.*s/libstickslip_gmsh.so", folder, slash ? self.dli_fname : ".");
  if (n < 0 || (size_t)n >= sizeof library)
    return sk_error_set(SK_ERR_INTERNAL, "mesh %s: the path of libstickslip_core is too long", job->path);
  sk_mesh_sandbox_phase("loading gmsh");
  void *handle = dlopen(library, RTLD_NOW | RTLD_LOCAL);
  if (!handle)
    return sk_error_set(SK_ERR_IO, "mesh %s: cannot load the mesh reader %s: %s (is stickslip installed whole?)",
                        job->path, library, dlerror());
  sk_gmsh_load_fn load;
  *(void **)&load = dlsym(handle, "sk_gmsh_load");
  if (!load) return sk_error_set(SK_ERR_INTERNAL, "mesh %s: %s has no sk_gmsh_load", job->path, library);
  sk_mesh_sandbox_start_clock();
  return load(job, mesh); /* the child ends after it: the library is never unloaded */
}

/* ---- public -------------------------------------------------------------------------------------------------- */

static int has_suffix(const char *text, const char *suffix) {
  size_t n = strlen(text), m = strlen(suffix);
  return n >= m && strcmp(text + n - m, suffix) == 0;
}

/* gmsh's peak resident memory per element stays below 1 kB on every mesh measured (0.35-0.85 kB with gmsh 4.8.4:
 * build/bin/bench_mesh_limits, tests/bench/mesh-limits), and the child starts with what it shares with stickslip
 * (libraries, MPI): 2 kB per element plus 256 MB is a limit no mesh within mesh.max_elements reaches, which stops a
 * runaway mesh early. */
static size_t memory_limit_for(long max_elements) { return ((size_t)256 << 20) + (size_t)max_elements * 2048; }

void sk_mesh_options_default(sk_mesh_options *options) {
  memset(options, 0, sizeof *options);
  options->max_elements = SK_MESH_DEFAULT_MAX_ELEMENTS;
  options->time_limit = SK_MESH_DEFAULT_TIME_LIMIT;
}

static sk_status finish_load(const char *path, sk_mesh *mesh, sk_status status);

sk_status sk_mesh_load(const char *path, const sk_mesh_param *params, int n_params, int dim, sk_mesh *mesh) {
  sk_mesh_options options;
  sk_mesh_options_default(&options);
  options.dim = dim;
  return sk_mesh_load_with(path, params, n_params, &options, mesh);
}

sk_status sk_mesh_load_with(const char *path, const sk_mesh_param *params, int n_params,
                            const sk_mesh_options *options, sk_mesh *mesh) {
  if (!mesh) return sk_error_set(SK_ERR_INTERNAL, "sk_mesh_load: mesh is NULL");
  memset(mesh, 0, sizeof *mesh);
  if (!path || !path[0]) return sk_error_set(SK_ERR_INPUT, "sk_mesh_load: no mesh file given");
  snprintf(mesh->source, sizeof mesh->source, "%s", path);
  if (n_params < 0 || (n_params > 0 && !params))
    return sk_error_set(SK_ERR_INTERNAL, "mesh %s: bad parameter list (n_params = %d)", path, n_params);
  if (!options) return sk_error_set(SK_ERR_INTERNAL, "mesh %s: no load options", path);
  int dim = options->dim;
  if (dim != 0 && dim != 2 && dim != 3)
    return sk_error_set(SK_ERR_INPUT, "mesh %s: dimension %d requested; stickslip meshes are 2D or 3D", path, dim);
  if (options->max_elements < 1)
    return sk_error_set(SK_ERR_INPUT, "mesh %s: max_elements must be at least 1 (got %ld)", path,
                        options->max_elements);
  if (!(options->time_limit > 0))
    return sk_error_set(SK_ERR_INPUT, "mesh %s: time_limit must be positive (got %g s)", path, options->time_limit);
  if (options->order < 0 || options->order > 2)
    return sk_error_set(SK_ERR_INPUT, "mesh %s: element order %d requested; stickslip elements are of order 1 or 2",
                        path, options->order);
  if (options->serendipity && options->order != 2)
    return sk_error_set(SK_ERR_INPUT, "mesh %s: serendipity elements (quad8, hex20) need element order 2", path);

  int is_geo = has_suffix(path, ".geo");
  if (!is_geo && !has_suffix(path, ".msh"))
    return sk_error_set(SK_ERR_INPUT, "mesh %s: unknown mesh format (expected a gmsh .geo script or .msh file)", path);
  SK_TRY(sk_require_regular_file(path, "mesh"));
  if (!is_geo && n_params > 0)
    return sk_error_set(SK_ERR_INPUT, "mesh %s: parameter '%s' given, but a .msh file takes no parameters", path,
                        params[0].name ? params[0].name : "(null)");
  if (is_geo) SK_TRY(check_parameters(path, params, n_params));

  char parameters[512] = "";
  for (int p = 0; p < n_params; ++p) {
    size_t used = strlen(parameters);
    snprintf(parameters + used, sizeof parameters - used, "%s%s = %g", p ? ", " : "", params[p].name,
             params[p].value);
  }
  /* a script meshed before with the same text and parameters comes from the cache (mesh_cache.c) */
  sk_mesh_cache_key key;
  memset(&key, 0, sizeof key);
  if (is_geo) sk_mesh_cache_key_make(path, parameters, dim, options, &key);
  if (is_geo && sk_mesh_cache_load(&key, mesh)) {
    sk_mesh_cache_note(path, &key, 1);
    return finish_load(path, mesh, SK_OK);
  }
  char wrapper[1024] = "";
  if (n_params > 0) SK_TRY(write_wrapper_script(path, params, n_params, wrapper, sizeof wrapper));
  sk_gmsh_load_job job = {.path = path, .open_path = wrapper[0] ? wrapper : path, .is_geo = is_geo, .dim = dim,
                  .order = options->order, .serendipity = options->serendipity,
                  .guard = {.path = path, .parameters = parameters, .max_elements = options->max_elements}};
  sk_mesh_sandbox_limits limits = {.time_limit = options->time_limit,
                                   .memory_limit = memory_limit_for(options->max_elements),
                                   .max_elements = options->max_elements};
  sk_status status = sk_mesh_sandbox(load_in_child, &job, &limits, mesh);
  if (wrapper[0]) unlink(wrapper);
  if (status == SK_OK && is_geo && mesh->n_groups > 0) {
    sk_mesh_cache_store(&key, mesh);
    sk_mesh_cache_note(path, &key, 0);
  }
  /* gmsh's own errors say what went wrong but not with which values: name the parameters the scene gave */
  if (status == SK_ERR_INPUT && parameters[0] && !strstr(sk_error_message(), "(parameters: ")) {
    char message[2048];
    snprintf(message, sizeof message, "%s", sk_error_message());
    sk_error_set(status, "%s (parameters: %s)", message, parameters);
  }
  return finish_load(path, mesh, status);
}

/* The checks and orientation of a mesh from gmsh or the cache (the cache holds gmsh's mesh as it came). */
static sk_status finish_load(const char *path, sk_mesh *mesh, sk_status status) {
  if (status == SK_OK && mesh->n_groups == 0)
    status = sk_error_set(SK_ERR_INPUT, "mesh %s: no physical groups of dimension %d or lower", path, mesh->dim);
  if (status == SK_OK && mesh->dim == 2) status = check_plane(path, mesh);
  if (status == SK_OK) status = sk_mesh_orient(mesh);
  if (status == SK_OK) status = sk_mesh_check_elements(mesh);
  if (status != SK_OK) {
    char source[sizeof mesh->source];
    memcpy(source, mesh->source, sizeof source);
    sk_mesh_free(mesh);
    memcpy(mesh->source, source, sizeof source);
  }
  return status;
}

void sk_mesh_free(sk_mesh *mesh) {
  if (!mesh) return;
  for (int g = 0; g < mesh->n_groups; ++g) free(mesh->groups[g].conn);
  free(mesh->groups);
  free(mesh->x);
  memset(mesh, 0, sizeof *mesh);
}
