// stickslip — Belos GMRES, right-preconditioned on the nodal block by MueLu smoothed aggregation, Ifpack2 ILU(1) or
// one symmetric Gauss-Seidel sweep; constraint rows (contact multipliers) through their Schur complement
// (constraint_block.cpp).
//
// Why the nodal block alone: the multiplier rows of contact have a zero diagonal (in `reduced` a round-off one,
// 1e-23 .. 1e-29, from the element condensation), and every point smoother divides by it. GMRES + MueLu on the
// whole system of scenes/two-tori-coarse.yaml therefore failed at every contact pattern: MueLu's Gauss-Seidel
// returned |P^-1 b| = 1e49 in the multiplier row and GMRES stalled at relative residual 1.0 for 500 iterations
// (39 of 39 retries). On the nodal block (block size 3, rigid-body modes) the same system takes 11-15 iterations
// (docs/linear-solvers.md).
//
// Reuse. AMG and ILU are kept across solves and across pattern changes (the nodal distribution depends on the node
// count alone): GMRES always runs on the current matrix, so an older preconditioner costs iterations, never
// accuracy. They are recomputed from the current values when a solve needs kRefreshGrowth times the iterations it
// took right after the last computation, or fails: on one rank MueLu keeps its aggregates on the matrix it was built
// for, on several ranks (and on a new pattern) it is built afresh. Gauss-Seidel is
// recomputed every solve (its set-up is the inverse diagonal: 0.01 s at 72k unknowns).
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <BelosSolverFactory.hpp>
#include <BelosTpetraAdapter.hpp>
#include <Ifpack2_Factory.hpp>
#include <MueLu_CreateTpetraPreconditioner.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_XMLParameterListHelpers.hpp>

#include "bridge_internal.hpp"
#include "linear_system.hpp"

namespace stickslip::bridge {

namespace {

constexpr int kGmresRestart = 100;
// Recompute the preconditioner once a solve takes more than kRefreshGrowth x (iterations after the last
// computation) + kRefreshSlack iterations.
constexpr double kRefreshGrowth = 1.5;
constexpr int kRefreshSlack = 3;

int nodal_block_size(const sk_linear_system *sys) {
  return sys->coordinate_dim > 0 ? sys->coordinate_dim : sys->block_size;
}

RCP<Teuchos::ParameterList> muelu_parameters(const sk_linear_system *sys) {
  auto p = rcp(new Teuchos::ParameterList);
  p->set("verbosity", sys->options.verbose ? "low" : "none");
  p->set("multigrid algorithm", "sa");
  p->set("number of equations", nodal_block_size(sys));
  // keep the aggregates (tentative prolongator) when the values change
  p->set("reuse: type", "tP");
  if (sys->size > 1) {
    // the default coarse solver is Amesos2 KLU2 on the distributed coarse matrix: the defective path
    p->set("coarse: type", "RELAXATION");
    p->sublist("coarse: params").set("relaxation: type", "Symmetric Gauss-Seidel");
    p->sublist("coarse: params").set("relaxation: sweeps", 4);
  }
  // an expert's override, for measuring other settings without rebuilding (docs/linear-solvers.md)
  if (const char *xml = std::getenv("STICKSLIP_MUELU_XML"))
    Teuchos::updateParametersFromXmlFileAndBroadcast(xml, p.ptr(), *sys->tcomm);
  return p;
}

// Rigid-body modes on this rank's nodal rows (coordinates centred on the centre of all ranks' nodes, so the rotations
// are well scaled against the translations and the same on every rank): 2D (1,0) (0,1) (-y,x); 3D adds (0,0,1) and
// the rotations about x, y, z.
RCP<MultiVector> rigid_body_modes(const sk_linear_system *sys) {
  const int dim = sys->coordinate_dim;
  const int n_modes = dim == 2 ? 3 : 6;
  const size_t n_nodes = sys->coordinates.size() / static_cast<size_t>(dim);
  double sums[4] = {0, 0, 0, static_cast<double>(n_nodes)};
  for (size_t node = 0; node < n_nodes; ++node)
    for (int c = 0; c < dim; ++c) sums[c] += sys->coordinates[node * dim + c];
  MPI_Allreduce(MPI_IN_PLACE, sums, 4, MPI_DOUBLE, MPI_SUM, sys->comm);
  double centre[3] = {0, 0, 0};
  for (int c = 0; c < dim; ++c) centre[c] = sums[3] > 0 ? sums[c] / sums[3] : 0.0;
  auto modes = rcp(new MultiVector(sys->nodal_map, static_cast<size_t>(n_modes)));
  const int n_owned = nodal_row_end(sys) - sys->first_row;
  for (int m = 0; m < n_modes; ++m) {
    auto data = modes->getDataNonConst(static_cast<size_t>(m));
    for (int i = 0; i < n_owned; ++i) {
      const int node = i / dim, c = i % dim;
      const double x = sys->coordinates[node * dim] - centre[0], y = sys->coordinates[node * dim + 1] - centre[1];
      const double z = dim == 3 ? sys->coordinates[node * dim + 2] - centre[2] : 0.0;
      double v = m == c ? 1.0 : 0.0;  // translations
      if (dim == 2 && m == 2) v = c == 0 ? -y : x;
      if (dim == 3 && m == 3) v = c == 0 ? -y : (c == 1 ? x : 0.0);  // about z
      if (dim == 3 && m == 4) v = c == 1 ? -z : (c == 2 ? y : 0.0);  // about x
      if (dim == 3 && m == 5) v = c == 2 ? -x : (c == 0 ? z : 0.0);  // about y
      data[i] = v;
    }
  }
  return modes;
}

// The nodal map (persistent while its layout holds, so preconditioners built on it stay usable), the nodal block
// K and the constraint block of the current pattern.
void prepare_blocks(sk_linear_system *sys) {
  const int first_row = sys->first_row;
  const size_t n_owned = static_cast<size_t>(nodal_row_end(sys) - first_row);
  int stale = sys->nodal_map.is_null() || sys->nodal_map->getGlobalNumElements() != static_cast<size_t>(sys->n_nodal) ||
              sys->nodal_map->getNodeNumElements() != n_owned;
  MPI_Allreduce(MPI_IN_PLACE, &stale, 1, MPI_INT, MPI_MAX, sys->comm);
  if (stale) {
    release_iterative(sys);
    sys->nodal_map = sys->n_nodal == sys->n ? sys->row_map
                                            : RCP<const Map>(rcp(new Map(static_cast<Tpetra::global_size_t>(sys->n_nodal),
                                                                         n_owned, 0, sys->tcomm)));
  }
  if (sys->n_nodal < sys->n && sys->nodal.matrix.is_null()) {
    sys->nodal = build_submatrix(sys, first_row, nodal_row_end(sys), 0, sys->n_nodal, sys->nodal_map, sys->nodal_map,
                                 sys->nodal_map);
    build_constraint_block(sys);
  }
}

RCP<Matrix> nodal_matrix(sk_linear_system *sys) { return sys->n_nodal < sys->n ? sys->nodal.matrix : sys->matrix; }

NodalPreconditioner &preconditioner_of(sk_linear_system *sys, sk_linear_solver_kind kind) {
  return sys->preconditioners[kind == SK_LINEAR_GMRES_MUELU ? 0
                              : kind == SK_LINEAR_GMRES_ILU ? 1
                              : kind == SK_LINEAR_GMRES_SGS ? 2
                                                            : 3];
}

// (Re)computes the preconditioner of the nodal block for the current values. `full`: from scratch (aggregates
// included); otherwise MueLu keeps its aggregates and ILU its symbolic factorisation where the matrix is the same.
void compute_nodal_preconditioner(sk_linear_system *sys, sk_linear_solver_kind kind, bool full) {
  RCP<Matrix> k = nodal_matrix(sys);
  NodalPreconditioner &p = preconditioner_of(sys, kind);
  if (kind == SK_LINEAR_GMRES_MUELU) {
    // Aggregates reused on one rank only, and on the matrix they were built for (a new pattern is a new matrix
    // object). The reuse recomputes the products into their old static graphs and throws where a product gained an
    // entry: on several ranks that happens on some ranks and not on others (scenes/corner-contact.yaml, 4 ranks,
    // gmres-muelu, the same matrix: ranks 1-3 threw "insert a new entry into a static graph" in the first contact
    // step), and the ranks that caught it built afresh while the others went on into the reuse's collectives:
    // MPI_ERR_TRUNCATE and an aborted run. A fresh set-up is collective on every rank alike.
    if (!full && !p.muelu.is_null() && p.matrix == k && sys->size == 1) {
      try {
        MueLu::ReuseTpetraPreconditioner(k, *p.muelu);
        p.matrix = k;
        return;
      } catch (...) {
        // a matrix MueLu cannot reuse its aggregates for: build afresh below
      }
    }
    auto params = muelu_parameters(sys);
    // without a nullspace MueLu takes the constants per equation: the translations
    if (sys->coordinate_dim > 0 && sys->options.nullspace == SK_NULLSPACE_RIGID_BODY)
      params->sublist("user data").set("Nullspace", rigid_body_modes(sys));
    p.muelu = MueLu::CreateTpetraPreconditioner(RCP<Operator>(k), *params);
    p.matrix = k;
    return;
  }
  if (full || p.ifpack.is_null() || p.matrix != k) {
    Teuchos::ParameterList params;
    if (kind == SK_LINEAR_GMRES_ILU) {
      p.ifpack = Ifpack2::Factory::create<RowMatrix>("RILUK", k);
      params.set("fact: iluk level-of-fill", 1);
    } else {
      p.ifpack = Ifpack2::Factory::create<RowMatrix>("RELAXATION", k);
      params.set("relaxation: type", kind == SK_LINEAR_GMRES_SGS ? "Symmetric Gauss-Seidel" : "Jacobi");
    }
    p.ifpack->setParameters(params);
    p.ifpack->initialize();
    p.matrix = k;
  }
  p.ifpack->compute();
}

}  // namespace

GmresResult run_gmres(sk_linear_system *sys, const RCP<Operator> &preconditioner, const RCP<Vector> &b,
                      const RCP<Vector> &x, int max_iterations) {
  x->putScalar(0.0);
  auto params = rcp(new Teuchos::ParameterList);
  params->set("Convergence Tolerance", sys->options.tolerance);
  params->set("Maximum Iterations", max_iterations);
  params->set("Num Blocks", std::min(kGmresRestart, std::max(1, max_iterations)));
  params->set("Implicit Residual Scaling", "Norm of RHS");
  // Iterated modified Gram-Schmidt: its dot products run in Kokkos where ICGS's block products run in the reference
  // BLAS (Debian's default libblas). Full tori, gmres-jacobi, 40 steps: solve time -20 % on 2 ranks, -13 % on one;
  // the same with MueLu / SGS (docs/fast-solves-tori.md)
  params->set("Orthogonalization", "IMGS");
  params->set("Explicit Residual Scaling", "Norm of RHS");
  params->set("Verbosity", sys->options.verbose && sys->rank == 0
                               ? Belos::Errors + Belos::Warnings + Belos::FinalSummary
                               : static_cast<int>(Belos::Errors));
  auto problem = rcp(new Belos::LinearProblem<Scalar, MultiVector, Operator>(sys->matrix, x, b));
  problem->setRightPrec(preconditioner);
  problem->setProblem();
  Belos::SolverFactory<Scalar, MultiVector, Operator> factory;
  auto solver = factory.create("GMRES", params);
  solver->setProblem(problem);
  GmresResult result;
  result.converged = solver->solve() == Belos::Converged;
  result.iterations = solver->getNumIters();
  return result;
}

void release_iterative_pattern(sk_linear_system *sys) {
  release_constraint_block(sys);
  sys->nodal = SubMatrix{};
}

void release_iterative(sk_linear_system *sys) {
  release_iterative_pattern(sys);
  for (NodalPreconditioner &p : sys->preconditioners) p = NodalPreconditioner{};
  sys->nodal_map = Teuchos::null;
}

sk_status solve_iterative(sk_linear_system *sys, sk_linear_solver_kind kind, const double *b, double *x,
                          sk_linear_report *report) {
  prepare_blocks(sys);
  if (sys->n_nodal < sys->n) refill_submatrix(sys, sys->nodal);
  NodalPreconditioner &p = preconditioner_of(sys, kind);
  const bool have = !p.op().is_null();
  bool fresh = false;
  if (!have || p.refresh || kind == SK_LINEAR_GMRES_SGS || kind == SK_LINEAR_GMRES_JACOBI) {
    const double setup_start = cpu_seconds();
    compute_nodal_preconditioner(sys, kind, !have);
    if (!have) sys->setup_cpu_seconds = cpu_seconds() - setup_start;  // built from scratch: kept from now on
    report->refactored_symbolic = !have;
    fresh = true;
    p.refresh = false;
  }
  if (sys->constraints) {
    const sk_status status = update_constraint_block(sys, *sys->constraints);
    if (status != SK_OK) {
      report->failure = SK_LINEAR_FAILURE_SINGULAR;
      return status;
    }
  }
  auto preconditioner = [sys, &p]() -> RCP<Operator> {
    return sys->constraints ? constraint_preconditioner(sys, *sys->constraints, p.op()) : p.op();
  };
  SolveScratch &scratch = solve_scratch(sys);
  const RCP<Vector> &xv = scratch.x, &bv = scratch.b;
  copy_to(b, *bv);
  // a trial by `auto` gets fewer iterations than a solver the user chose (auto_choice.cpp)
  const int cap = sys->auto_memory.iteration_cap;
  const int max_iterations = cap > 0 ? std::min(cap, sys->options.max_iterations) : sys->options.max_iterations;
  GmresResult result = run_gmres(sys, preconditioner(), bv, xv, max_iterations);
  int iterations = result.iterations;
  if (!result.converged && !fresh) {
    // an older preconditioner may have drifted too far from the matrix: recompute it and try once more
    compute_nodal_preconditioner(sys, kind, false);
    fresh = true;
    result = run_gmres(sys, preconditioner(), bv, xv, max_iterations);
    iterations += result.iterations;
  }
  if (result.converged) {
    if (fresh) {
      p.iterations = result.iterations;
    } else if (result.iterations > kRefreshGrowth * p.iterations + kRefreshSlack) {
      p.refresh = true;
    }
  }
  report->iterations = iterations;
  copy_from(*xv, x);
  report->relative_residual = relative_residual(sys, *bv, *xv);
  if (!result.converged || !std::isfinite(report->relative_residual)) {
    report->failure = SK_LINEAR_FAILURE_NOT_CONVERGED;
    return sk_error_set(SK_ERR_LINEAR_SOLVER, "%s: no convergence to %.3g in %d iterations (relative residual %.3g)",
                        sk_linear_solver_name(kind), sys->options.tolerance, result.iterations,
                        report->relative_residual);
  }
  return SK_OK;
}

}  // namespace stickslip::bridge
