/* The mesh generator's work, in its child process (mesh_load.c loads this library there, never in a rank): the file
 * read or the script meshed by gmsh, the elements made second order if asked, and the model read into an sk_mesh. */
#include <gmshc.h>

#include "mesh_internal.h"

/* Second-order elements from the first-order mesh of the current model. gmsh puts the new nodes on the geometry
 * (curved boundaries stay curved) for a .geo script and on straight edges for a .msh file, which has no geometry. */
static sk_status raise_order(const char *path, int order, int serendipity) {
  int ierr = 0;
  gmshOptionSetNumber("Mesh.SecondOrderIncomplete", serendipity ? 1 : 0, &ierr);
  if (sk_gmsh_failed(ierr, path, "set Mesh.SecondOrderIncomplete")) return SK_ERR_INPUT;
  gmshModelMeshSetOrder(order, &ierr);
  if (sk_gmsh_failed(ierr, path, "make second-order elements")) return SK_ERR_INPUT;
  return SK_OK;
}

static const char *failed_path; /* the file sk_gmsh_failed names (the child is single-threaded) */

static int stage_failed(int ierr, const char *what) { return sk_gmsh_failed(ierr, failed_path, what); }

sk_status sk_gmsh_load(const sk_gmsh_load_job *job, sk_mesh *mesh) {
  const char *path = job->path;
  failed_path = path;
  sk_status status = SK_OK;
  int ierr = 0, dim = job->dim;
  sk_mesh_sandbox_phase(job->is_geo ? "evaluating the script" : "reading the file");
  sk_gmsh_session_begin();
  gmshOpen(job->open_path, &ierr);
  if (sk_gmsh_failed(ierr, path, "read the file")) status = SK_ERR_INPUT;

  int highest = -1;
  if (status == SK_OK && !sk_gmsh_highest_group_dimension(path, &highest)) status = SK_ERR_INPUT;
  if (status == SK_OK && highest < 0)
    status = sk_error_set(SK_ERR_INPUT, "mesh %s: no physical groups (name the bodies and boundaries with "
                                        "Physical Volume/Surface/Curve(\"name\"))", path);
  if (status == SK_OK && dim == 0) {
    dim = highest;
    if (dim != 2 && dim != 3)
      status = sk_error_set(SK_ERR_INPUT, "mesh %s: the highest physical group has dimension %d; stickslip meshes "
                                          "are 2D or 3D", path, dim);
  }
  /* Script errors stay exceptions (the API's General.AbortOnError = 2), which gmshOpen catches: with 0, an Error()
   * followed by Abort inside an Included script double-frees in gmsh 4.8.4. Meshing errors must not be exceptions:
   * thrown inside gmsh's OpenMP regions (a mesh size <= 0 while meshing curves) nothing can catch them and the
   * process aborts. With 0 gmsh logs them and goes on, and stage_failed() stops after the stage. */
  gmshOptionSetNumber("General.AbortOnError", 0, &ierr);
  if (status == SK_OK && job->is_geo) status = sk_mesh_generate_guarded(&job->guard, dim, stage_failed);
  if (status == SK_OK && job->order > 0) {
    sk_mesh_sandbox_phase("making the elements second order");
    status = raise_order(path, job->order, job->serendipity);
  }
  if (status == SK_OK) {
    sk_mesh_sandbox_phase("reading the mesh from gmsh");
    mesh->dim = dim;
    status = sk_gmsh_read_model(path, dim, mesh);
  }
  if (status == SK_OK && !job->is_geo) {
    double count = 0;
    for (int g = 0; g < mesh->n_groups; ++g) count += mesh->groups[g].dim == dim ? mesh->groups[g].n_elems : 0;
    if (count > (double)job->guard.max_elements)
      status = sk_error_set(SK_ERR_INPUT, "mesh %s has %.0f elements of dimension %d, more than mesh.max_elements = "
                            "%ld; raise mesh.max_elements if such a mesh is meant", path, count, dim,
                            job->guard.max_elements);
  }
  sk_gmsh_session_end();
  return status;
}
