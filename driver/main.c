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
          "  keys SCENE.yaml    list every key of the scene with its value or default, unit and origin\n"
          "  plugins            list the plugins found, with their capabilities, strategies and parameters\n"
          "\n"
          "`stickslip <command> --help` tells more. Documentation: docs/user-guide.md, docs/scene-reference.md\n",
          STICKSLIP_VERSION);
}

static void usage_run(FILE *out, const char *command) {
  int run = strcmp(command, "run") == 0, keys = strcmp(command, "keys") == 0;
  fprintf(out,
          "usage: stickslip %s SCENE.yaml [--plugin NAME] [--set key.path=value ...] [--replace key.path=value ...]\n"
          "                      [--trust-scripts]%s%s\n%s\n",
          command, keys ? "" : " [--explain]", run ? " [--out DIR] [--steps N] [--quiet] [--verbose]" : "",
          keys ? "       stickslip keys --plugin NAME\n" : "");
  if (keys)
    fprintf(out,
            "Lists every key of the scene as it would run: its value (given, or the default in use), its unit and\n"
            "where it came from (file:line:column, --set, default); for each contact pair and body plugin every\n"
            "parameter of the plugin's table with its value or declared default. Without a scene: the parameters\n"
            "of plugin NAME with their declared defaults.\n\n");
  fprintf(out,
          "  --plugin NAME        use plugin NAME for every contact pair (refused without pairs); of each pair's\n"
          "                       parameters and strategy it keeps what NAME takes and drops the rest with a\n"
          "                       warning (NAME's defaults apply)\n"
          "  --set key=value      override a scene key, e.g. --set time.dt=0.005 --set contact.0.parameters.mu=0.3\n"
          "                       (sequence elements by index; the value is YAML: 0.3, true, [1, 2, 3]); a map\n"
          "                       merges into the scene's map: --set 'solver.newton={max_iterations: 40}' keeps\n"
          "                       the scene's other newton keys\n"
          "  --replace key=value  the same, but the value replaces what the scene has there (maps included)\n"
          "  --trust-scripts      let the scene's .geo scripts run shell commands and write files (SystemCall,\n"
          "                       Print, Save, CreateDir, Printf > file); refused otherwise. Only for scripts you trust\n");
  if (!keys)
    fprintf(out, "  --explain            print what each term of the scene needs, what will be computed and what is\n"
                 "                       skipped, and why (docs/performance.md)\n");
  if (run)
    fprintf(out,
            "  --out DIR            write history.csv, contact.csv, summary.json, scene.yaml and results.pvd/.vtu\n"
            "                       into DIR (replaced at the end as a whole; default: no files)\n"
            "  --steps N            stop after N steps\n"
            "  --quiet              no progress line and no information messages (warnings and errors stay)\n"
            "  --verbose            Newton residuals per iteration, step cuts, plugin messages\n");
}

typedef struct {
  const char *scene;
  const char *plugin;
  const char *out;
  const char **sets;
  sk_cfg_override_mode *modes; /* per entry of `sets`: --set merges, --replace replaces */
  int n_sets;
  int steps, quiet, verbose, trust_scripts, explain;
} arguments;

/* Returns 0 on success, 1 on bad usage (message printed), 2 when help was printed. */
static int parse_arguments(int argc, char **argv, const char *command, arguments *args) {
  memset(args, 0, sizeof *args);
  args->sets = calloc((size_t)argc, sizeof(char *));
  args->modes = calloc((size_t)argc, sizeof *args->modes);
  if (!args->sets || !args->modes) {
    fprintf(stderr, "stickslip: out of memory\n");
    return 1;
  }
  int allow_run_options = strcmp(command, "run") == 0, allow_explain = strcmp(command, "keys") != 0;
  for (int i = 2; i < argc; ++i) {
    const char *a = argv[i];
    const char *value = i + 1 < argc ? argv[i + 1] : NULL;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      if (rank_of_world() == 0) usage_run(stdout, command);
      return 2;
    } else if (strcmp(a, "--plugin") == 0 && value) {
      args->plugin = value;
      ++i;
    } else if ((strcmp(a, "--set") == 0 || strcmp(a, "--replace") == 0) && value) {
      if (!strchr(value, '=')) {
        fprintf(stderr, "stickslip: %s expects key.path=value, got '%s'\n", a, value);
        return 1;
      }
      args->modes[args->n_sets] = strcmp(a, "--replace") == 0 ? SK_CFG_REPLACE : SK_CFG_MERGE;
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
    } else if (strcmp(a, "--trust-scripts") == 0) {
      args->trust_scripts = 1;
    } else if (allow_explain && strcmp(a, "--explain") == 0) {
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
  if (!args->scene && !(strcmp(command, "keys") == 0 && args->plugin)) {
    fprintf(stderr, "stickslip %s: which scene? (stickslip %s SCENE.yaml%s)\n", command, command,
            strcmp(command, "keys") == 0 ? ", or stickslip keys --plugin NAME for a plugin's parameters" : "");
    return 1;
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

typedef enum { COMMAND_RUN, COMMAND_CHECK, COMMAND_KEYS } scene_command;

static int command_scene(int argc, char **argv, scene_command command) {
  sk_driver_mpi_init(&argc, &argv); /* the only commands that need a communicator */
  sk_interrupt_install();           /* after MPI_Init, which may install handlers of its own */
  const int run = command == COMMAND_RUN;
  arguments args;
  int parsed = parse_arguments(argc, argv, run ? "run" : command == COMMAND_KEYS ? "keys" : "check", &args);
  if (parsed != 0) {
    free(args.sets);
    free(args.modes);
    return parsed == 2 ? 0 : 1;
  }
  sk_log_verbosity = args.quiet ? -1 : args.verbose;
  sk_mesh_trust_scripts(args.trust_scripts);
  if (!args.scene) { /* keys --plugin NAME */
    const sk_plugin *plugin = NULL;
    sk_status status = sk_plugin_load(args.plugin, &plugin);
    if (status == SK_OK && rank_of_world() == 0) status = sk_plugin_keys(plugin, stdout);
    free(args.sets);
    free(args.modes);
    return status == SK_OK ? 0 : fail(status);
  }
  sk_scene scene;
  const sk_scene_overrides overrides = {
      .n = args.n_sets, .assignments = args.sets, .modes = args.modes, .plugin = args.plugin};
  sk_status status = sk_scene_load_with(args.scene, &overrides, MPI_COMM_WORLD, &scene);
  int code = 0;
  if (status != SK_OK) {
    code = fail(status);
  } else if (command == COMMAND_KEYS) {
    if (rank_of_world() == 0) sk_scene_keys(&scene, stdout);
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
                              .max_steps = args.steps};
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
  free(args.sets);
  free(args.modes);
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
    code = command_scene(argc, argv, COMMAND_RUN);
  } else if (strcmp(argv[1], "check") == 0) {
    code = command_scene(argc, argv, COMMAND_CHECK);
  } else if (strcmp(argv[1], "keys") == 0) {
    code = command_scene(argc, argv, COMMAND_KEYS);
  } else if (strcmp(argv[1], "plugins") == 0) {
    code = command_plugins(argc, argv);
  } else {
    if (rank_of_world() == 0)
      fprintf(stderr, "stickslip: unknown command '%s' (commands: run, check, keys, plugins; see stickslip --help)\n",
              argv[1]);
    code = 1;
  }
  sk_driver_mpi_finalize();
  return code;
}
