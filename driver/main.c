/* stickslip — the thin driver: command line → scene → run. */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mpi_start.h"
#include "stickslip/bridge.h"
#include "stickslip/fe.h"
#include "stickslip/interrupt.h"
#include "stickslip/mesh.h"
#include "stickslip/plugins.h"
#include "stickslip/run.h"
#include "stickslip/scene.h"

#ifndef STICKSLIP_VERSION
#define STICKSLIP_VERSION "0.1.0"
#endif


static int rank_of_world(void) { return sk_driver_rank(); }

static void usage_main(FILE *out) {
  fprintf(out,
          "stickslip %s — large-deformation frictional contact, formulations as plugins\n"
          "\n"
          "usage: stickslip <command> [options]\n"
          "\n"
          "commands:\n"
          "  run SCENE.yaml     run a scene (under `mpirun -np N` for N ranks)\n"
          "  check SCENE.yaml   validate a scene (YAML, meshes, groups, plugins, parameters) without running\n"
          "  plugins            list the plugins found, with their capabilities, strategies and parameters\n"
          "\n"
          "`stickslip <command> --help` tells more. Documentation: docs/user-guide.md, docs/scene-reference.md\n",
          STICKSLIP_VERSION);
}

static void usage_run(FILE *out, const char *command) {
  fprintf(out,
          "usage: stickslip %s SCENE.yaml [--plugin NAME] [--set key.path=value ...] [--trust-scripts]%s\n"
          "\n"
          "  --plugin NAME        use plugin NAME for every contact pair (overrides the scene; refused without pairs)\n"
          "  --set key=value      override any scene key, e.g. --set time.dt=0.005 --set contact.0.parameters.mu=0.3\n"
          "                       (sequence elements by index; the value is YAML: 0.3, true, [1, 2, 3])\n"
          "  --trust-scripts      let the scene's .geo scripts run shell commands and write files (SystemCall,\n"
          "                       Print, Save, CreateDir, Printf > file); refused otherwise. Only for scripts you trust\n"
          "  --explain            print what each term of the scene needs, what will be computed and what is\n"
          "                       skipped, and why (docs/performance.md)\n",
          command, strcmp(command, "run") == 0 ? " [--out DIR] [--steps N] [--quiet] [--verbose]" : "");
  if (strcmp(command, "run") == 0)
    fprintf(out,
            "  --out DIR            write history.csv, contact.csv, summary.json, scene.yaml and results.pvd/.vtu\n"
            "                       into DIR (replaced at the end as a whole; default: no files)\n"
            "  --steps N            stop after N steps\n"
            "  --checkpoint-every N write a checkpoint every N steps (the state and the plugins' history) into\n"
            "                       --checkpoint DIR (default DIR.checkpoint for --out DIR); the last two are kept\n"
            "  --restart DIR        continue from the checkpoint in DIR (its latest, or DIR/step-NNNNNNNN), on any\n"
            "                       number of ranks; no SCENE: it is the checkpoint's (docs/user-guide.md)\n"
            "  --quiet              no progress line\n"
            "  --verbose            Newton residuals per iteration, step cuts, plugin messages\n");
}

typedef struct {
  const char *scene;
  const char *plugin;
  const char *out;
  const char **sets;
  int n_sets;
  int steps, quiet, verbose, trust_scripts, explain;
  int checkpoint_every;
  const char *checkpoint, *restart;
  char checkpoint_default[4200];
} arguments;

/* Returns 0 on success, 1 on bad usage (message printed), 2 when help was printed. */
static int parse_arguments(int argc, char **argv, const char *command, arguments *args) {
  memset(args, 0, sizeof *args);
  args->sets = calloc((size_t)argc, sizeof(char *));
  int allow_run_options = strcmp(command, "run") == 0;
  for (int i = 2; i < argc; ++i) {
    const char *a = argv[i];
    const char *value = i + 1 < argc ? argv[i + 1] : NULL;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      if (rank_of_world() == 0) usage_run(stdout, command);
      return 2;
    } else if (strcmp(a, "--plugin") == 0 && value) {
      args->plugin = value;
      ++i;
    } else if (strcmp(a, "--set") == 0 && value) {
      if (!strchr(value, '=')) {
        fprintf(stderr, "stickslip: --set expects key.path=value, got '%s'\n", value);
        return 1;
      }
      args->sets[args->n_sets++] = value;
      ++i;
    } else if (allow_run_options && strcmp(a, "--out") == 0 && value) {
      args->out = value;
      ++i;
    } else if (allow_run_options && strcmp(a, "--steps") == 0 && value) {
      char *end;
      long steps = strtol(value, &end, 10);
      if (*end || steps < 1) {
        fprintf(stderr, "stickslip: --steps expects a positive integer, got '%s'\n", value);
        return 1;
      }
      args->steps = (int)steps;
      ++i;
    } else if (allow_run_options && strcmp(a, "--checkpoint-every") == 0 && value) {
      char *end;
      long every = strtol(value, &end, 10);
      if (*end || every < 1) {
        fprintf(stderr, "stickslip: --checkpoint-every expects a positive integer, got '%s'\n", value);
        return 1;
      }
      args->checkpoint_every = (int)every;
      ++i;
    } else if (allow_run_options && strcmp(a, "--checkpoint") == 0 && value) {
      args->checkpoint = value;
      ++i;
    } else if (allow_run_options && strcmp(a, "--restart") == 0 && value) {
      args->restart = value;
      ++i;
    } else if (strcmp(a, "--trust-scripts") == 0) {
      args->trust_scripts = 1;
    } else if (strcmp(a, "--explain") == 0) {
      args->explain = 1;
    } else if (allow_run_options && strcmp(a, "--quiet") == 0) {
      args->quiet = 1;
    } else if (allow_run_options && strcmp(a, "--verbose") == 0) {
      args->verbose = 1;
    } else if (a[0] == '-') {
      fprintf(stderr, "stickslip %s: unknown option '%s'%s (see stickslip %s --help)\n", command, a,
              value || a[1] != '-' ? "" : " or missing value", command);
      return 1;
    } else if (!args->scene) {
      args->scene = a;
    } else {
      fprintf(stderr, "stickslip %s: unexpected argument '%s'\n", command, a);
      return 1;
    }
  }
  if (args->restart && (args->scene || args->n_sets > 0 || args->plugin)) {
    fprintf(stderr, "stickslip %s: --restart continues the checkpoint's scene, with its --set values and --plugin: "
            "give no SCENE, --set or --plugin\n", command);
    return 1;
  }
  if (!args->scene && !args->restart) {
    fprintf(stderr, "stickslip %s: which scene? (stickslip %s SCENE.yaml)\n", command, command);
    return 1;
  }
  if (args->checkpoint && !args->checkpoint_every) {
    fprintf(stderr, "stickslip %s: --checkpoint DIR needs --checkpoint-every N\n", command);
    return 1;
  }
  if (args->checkpoint_every && !args->checkpoint && args->out) {
    snprintf(args->checkpoint_default, sizeof args->checkpoint_default, "%s.checkpoint", args->out);
    args->checkpoint = args->checkpoint_default;
  }
  return 0;
}

static void print_plugin(void *ctx, const sk_plugin *plugin, const char *path) {
  (void)ctx;
  char caps[512], kinds[32];
  sk_capabilities_string(plugin->caps, caps, sizeof caps);
  sk_kinds_string(plugin->kinds, kinds, sizeof kinds);
  printf("%s  (ABI %u.%u)\n  %s\n  attaches to:  %s\n  capabilities: %s\n  strategies:  ", plugin->name,
         plugin->abi_major, plugin->abi_minor, plugin->summary, kinds, caps);
  for (int s = 0; plugin->strategies[s]; ++s) printf("%s%s%s", s ? ", " : "", plugin->strategies[s], s ? "" : " (default)");
  printf("\n");
  if (plugin->parameters && plugin->parameters[0]) {
    printf("  parameters:\n");
    for (int k = 0; plugin->parameters[k]; ++k) printf("    %s\n", plugin->parameters[k]);
  }
  printf("  library:     %s\n\n", path);
}

static void print_broken(void *ctx, const char *path, const char *message) {
  (void)ctx;
  (void)path;
  fprintf(stderr, "warning: %s\n", message);
}

static int command_plugins(int argc, char **argv) {
  for (int i = 2; i < argc; ++i) {
    if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
      printf("usage: stickslip plugins\n\nLists the plugins in STICKSLIP_PLUGIN_PATH and the build's plugin "
             "folder.\n");
      return 0;
    }
    fprintf(stderr, "stickslip plugins: unexpected argument '%s'\n", argv[i]);
    return 1;
  }
  if (rank_of_world() != 0) return 0;
  int n = sk_plugin_each(print_plugin, print_broken, NULL);
  if (n == 0) {
    fprintf(stderr, "stickslip: no plugins found (looked in STICKSLIP_PLUGIN_PATH and <bin>/../lib/stickslip/plugins)\n");
    return 1;
  }
  return 0;
}

/* 1 for every failure, 128 + the signal number when stopped by SIGINT/SIGTERM (the shell's convention). */
static int exit_code(sk_status status) {
  int sig = sk_interrupt_requested();
  return status == SK_ERR_INTERRUPTED && sig ? 128 + sig : 1;
}

static int fail(sk_status status) {
  if (rank_of_world() == 0) fprintf(stderr, "stickslip: %s\n", sk_error_message());
  return exit_code(status);
}

/* Where the results of a failed run are, exactly: the --out folder, DIR.incomplete next to finished results that
 * were kept, the staging folder when it could not be put in place, or nowhere (a write error: the disk is full). */
static void report_results_after_failure(const arguments *args, const sk_run_summary *summary) {
  if (!args->out) return;
  if (summary->results_dir[0]) {
    fprintf(stderr, "stickslip: results up to t = %g (step %d) are in %s (status \"%s\")\n", summary->final_time,
            summary->steps, summary->results_dir,
            summary->interrupted ? "interrupted" : summary->failed ? "failed" : "ok");
    if (strcmp(summary->results_dir, args->out) != 0 && access(args->out, F_OK) == 0)
      fprintf(stderr, "stickslip: the results already in %s were kept\n", args->out);
  } else {
    fprintf(stderr, "stickslip: no results were written%s%s%s\n", access(args->out, F_OK) == 0 ? "; " : "",
            access(args->out, F_OK) == 0 ? args->out : "", access(args->out, F_OK) == 0 ? " is unchanged" : "");
  }
}

static int command_scene(int argc, char **argv, int run) {
  sk_driver_mpi_init(&argc, &argv); /* the only commands that need a communicator */
  sk_interrupt_install();           /* after MPI_Init, which may install handlers of its own */
  arguments args;
  int parsed = parse_arguments(argc, argv, run ? "run" : "check", &args);
  if (parsed != 0) {
    free(args.sets);
    return parsed == 2 ? 0 : 1;
  }
  sk_log_verbosity = args.verbose;
  sk_mesh_trust_scripts(args.trust_scripts);
  sk_scene scene;
  sk_restart *restart = NULL;
  const char *const *sets = args.sets;
  sk_status status = SK_OK;
  if (args.restart) { /* the checkpoint's scene, as it was loaded */
    status = sk_restart_open(args.restart, MPI_COMM_WORLD, &restart);
    if (status == SK_OK) {
      args.scene = sk_restart_scene(restart);
      args.plugin = sk_restart_plugin(restart);
      args.n_sets = sk_restart_sets(restart, &sets);
    }
  }
  if (status == SK_OK) status = sk_scene_load(args.scene, args.n_sets, sets, args.plugin, MPI_COMM_WORLD, &scene);
  else memset(&scene, 0, sizeof scene);
  int code = 0;
  if (status == SK_OK && args.plugin && scene.model.n_pairs == 0) {
    status = sk_error_set(SK_ERR_INPUT, "--plugin %s: %s has no contact pairs (no `contact` list), so no plugin "
                          "would be used", args.plugin, args.scene);
  }
  if (status != SK_OK) {
    code = fail(status);
  } else if (!run) {
    if (rank_of_world() == 0) {
      const sk_model *m = &scene.model;
      printf("%s: ok — %dD, %d nodes, %d elements in %d bodies, %d dofs, %d contact pairs, %g to %g by %g\n",
             args.scene, m->dim, m->n_nodes, m->n_elements, m->n_bodies, m->n_dofs, m->n_pairs, m->time.t_start,
             m->time.t_end, m->time.dt);
      for (int b = 0; b < m->n_bodies; ++b)
        printf("  body '%s': %d %s elements\n", m->bodies[b].name, m->bodies[b].group->n_elems,
               sk_elem_name(m->bodies[b].group->type));
      for (int k = 0; k < m->n_pairs; ++k)
        printf("  pair '%s': plugin %s, strategy %s, slave %s (%d nodes, %s faces), master %s\n", m->pairs[k].name,
               m->pairs[k].plugin->name, m->pairs[k].plugin->strategies[m->pairs[k].strategy],
               m->pairs[k].slave.name, m->pairs[k].slave.n_nodes, sk_elem_name(m->pairs[k].slave.face_type),
               m->pairs[k].has_obstacle ? m->pairs[k].obstacle.name : m->pairs[k].master.name);
      for (int b = 0; b < m->n_bodies; ++b)
        if (m->bodies[b].plugin)
          printf("  body '%s': plugin %s, strategy %s\n", m->bodies[b].name, m->bodies[b].plugin->name,
                 m->bodies[b].plugin->strategies[m->bodies[b].strategy]);
      if (args.explain) sk_scene_explain(&scene, NULL, !args.quiet, stdout);
    }
  } else {
    if (args.explain && rank_of_world() == 0) {
      sk_scene_explain(&scene, args.out, !args.quiet, stdout);
      fflush(stdout);
    }
    sk_run_options options = {.out_dir = args.out,
                              .progress = !args.quiet && rank_of_world() == 0,
                              .verbose = args.verbose,
                              .max_steps = args.steps,
                              .checkpoint_every = args.checkpoint_every,
                              .checkpoint_dir = args.checkpoint,
                              .scene_path = args.scene,
                              .sets = sets,
                              .n_sets = args.n_sets,
                              .plugin = args.plugin,
                              .restart = restart};
    sk_run_summary summary;
    /* the stepper polls the signal handlers installed in main() before each step (sk_run) */
    status = sk_run(&scene, &options, &summary);
    if (rank_of_world() == 0) {
      if (status != SK_OK) {
        fprintf(stderr, "stickslip: %s: %s\n", args.scene, sk_error_message());
        report_results_after_failure(&args, &summary);
        code = exit_code(status);
      } else {
        printf("%s: %d steps to t = %g, %d Newton iterations, %d linear solves, %.2f s (assembly %.2f, contact "
               "%.2f, solve %.2f)\n",
               args.scene, summary.steps, summary.final_time, summary.newton_iterations, summary.linear_solves,
               summary.wall_seconds, summary.assembly_seconds, summary.contact_seconds, summary.solve_seconds);
        if (summary.results_dir[0]) printf("results: %s/ (history.csv, summary.json, results.pvd)\n", summary.results_dir);
      }
    } else if (status != SK_OK) {
      code = 1;
    }
  }
  sk_scene_free(&scene);
  sk_restart_free(restart);
  free(args.sets);
  return code;
}

int main(int argc, char **argv) {
  int code;
  if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "help") == 0) {
    if (rank_of_world() == 0) usage_main(argc < 2 ? stderr : stdout);
    code = argc < 2 ? 1 : 0;
  } else if (strcmp(argv[1], "--version") == 0) {
    if (rank_of_world() == 0) printf("stickslip %s (plugin ABI %u.%u)\n", STICKSLIP_VERSION, SK_ABI_MAJOR, SK_ABI_MINOR);
    code = 0;
  } else if (strcmp(argv[1], "run") == 0) {
    code = command_scene(argc, argv, 1);
  } else if (strcmp(argv[1], "check") == 0) {
    code = command_scene(argc, argv, 0);
  } else if (strcmp(argv[1], "plugins") == 0) {
    code = command_plugins(argc, argv);
  } else {
    if (rank_of_world() == 0)
      fprintf(stderr, "stickslip: unknown command '%s' (commands: run, check, plugins; see stickslip --help)\n",
              argv[1]);
    code = 1;
  }
  sk_driver_mpi_finalize();
  return code;
}
