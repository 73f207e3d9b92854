/* stickslip — the thin driver: command line → scene → run. */
#include <errno.h>
#include <limits.h>
#include <mpi.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mpi_start.h"
#include "tools.h"
#include "stickslip/bridge.h"
#include "stickslip/fe.h"
#include "stickslip/interrupt.h"
#include "stickslip/mesh.h"
#include "stickslip/plugins.h"
#include "stickslip/run.h"
#include "stickslip/scene.h"
#include "stickslip/text.h"

#ifndef STICKSLIP_VERSION
#define STICKSLIP_VERSION "0.1.0"
#endif


/* "results: DIR/ (history.csv, contact.csv, ...)": the result files the run wrote, those that are there */
static void print_results_line(const char *dir) {
  static const char *const files[] = {"history.csv", "contact.csv", "summary.json", "scene.yaml",
                                      "results.pvd", "contact.pvd", "obstacles.pvd"};
  printf("results: %s/ (", dir);
  const char *separator = "";
  for (size_t k = 0; k < sizeof files / sizeof files[0]; ++k) {
    char path[4096];
    if (snprintf(path, sizeof path, "%s/%s", dir, files[k]) >= (int)sizeof path || access(path, F_OK) != 0) continue;
    printf("%s%s", separator, files[k]);
    separator = ", ";
  }
  printf(")\n");
}

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
          "  compare SCENE.yaml --vary KEY=A,B ...\n"
          "                     run variants of a scene (plugins, strategies, parameters), tabulate and plot their\n"
          "                     cost against their error\n"
          "\n"
          "`stickslip <command> --help` (or `stickslip help <command>`) tells more. Documentation: docs/user-guide.md,\n"
          "docs/scene-reference.md\n",
          STICKSLIP_VERSION);
}

static void usage_run(FILE *out, const char *command) {
  int run = strcmp(command, "run") == 0, keys = strcmp(command, "keys") == 0;
  fprintf(out,
          "usage: stickslip %s SCENE.yaml [--plugin NAME] [--set key.path=value ...] [--replace key.path=value ...]\n"
          "                      [--trust-scripts]%s%s\n%s%s\n",
          command, keys ? "" : " [--explain]", run ? " [--out DIR] [--steps N] [--quiet] [--verbose]" : "",
          run ? "                      [--checkpoint-every N [--checkpoint DIR]]\n"
                "       stickslip run [--restart DIR] [--out DIR] [--steps N] ...   (no SCENE.yaml, --plugin, --set or\n"
                "                      --replace: the checkpoint's)\n" : "",
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
            "  --out DIR            write history.csv, contact.csv, summary.json, scene.yaml and results.pvd/.pvtu\n"
            "                       into DIR (replaced at the end as a whole; default: no files)\n"
            "  --steps N            stop after N steps\n"
            "  --checkpoint-every N write a checkpoint every N steps (the state and the plugins' history); the\n"
            "                       last two are kept\n"
            "  --checkpoint DIR     where the checkpoints go (default DIR.checkpoint for --out DIR)\n"
            "  --restart DIR        continue from the checkpoint in DIR (its latest, or DIR/step-NNNNNNNN), on any\n"
            "                       number of ranks; no SCENE: it is the checkpoint's (docs/user-guide.md)\n"
            "  --quiet              no progress line and no information messages (warnings and errors stay; with\n"
            "                       --verbose only the progress line goes)\n"
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
  int checkpoint_every;
  const char *checkpoint, *restart;
  char checkpoint_default[4200];
} arguments;

/* The options of the scene commands: each with the commands that take it and, if it takes one, its value's name. */
enum { FOR_RUN = 1, FOR_CHECK = 2, FOR_KEYS = 4, FOR_ALL = 7 };
typedef struct {
  const char *name, *value;
  unsigned commands;
} option;
static const option scene_options[] = {
    {"--plugin", "NAME", FOR_ALL},        {"--set", "key.path=value", FOR_ALL},
    {"--replace", "key.path=value", FOR_ALL}, {"--trust-scripts", NULL, FOR_ALL},
    {"--explain", NULL, FOR_RUN | FOR_CHECK}, {"--out", "DIR", FOR_RUN},
    {"--steps", "N", FOR_RUN},            {"--quiet", NULL, FOR_RUN},
    {"--verbose", NULL, FOR_RUN},         {"--checkpoint-every", "N", FOR_RUN},
    {"--checkpoint", "DIR", FOR_RUN},     {"--restart", "DIR", FOR_RUN},
    {"--help", NULL, FOR_ALL},
};
enum { N_OPTIONS = sizeof scene_options / sizeof scene_options[0] };

static unsigned command_bit(const char *command) {
  return strcmp(command, "run") == 0 ? FOR_RUN : strcmp(command, "check") == 0 ? FOR_CHECK : FOR_KEYS;
}

/* A bad command line: one message on stderr in the form every command uses, "stickslip COMMAND: what is wrong; see
 * stickslip COMMAND --help", from rank 0 only. Returns 1 (the exit status of every error). */
static int usage_error(const char *command, const char *format, ...) __attribute__((format(printf, 2, 3)));
static int usage_error(const char *command, const char *format, ...) {
  if (rank_of_world() != 0) return 1;
  va_list args;
  va_start(args, format);
  fprintf(stderr, "stickslip %s: ", command);
  vfprintf(stderr, format, args);
  fprintf(stderr, "; see stickslip %s --help\n", command);
  va_end(args);
  return 1;
}

/* An option this command does not know: the option it was probably meant to be, or the command that takes it. */
static int unknown_option(const char *command, const char *given, const char *name) {
  for (int k = 0; k < N_OPTIONS; ++k)
    if (strcmp(scene_options[k].name, name) == 0) {
      const char *owner = scene_options[k].commands & FOR_RUN ? "run" : "check";
      return usage_error(command, "%s is an option of stickslip %s, not of stickslip %s", name, owner, command);
    }
  sk_closest closest = SK_CLOSEST_NONE;
  for (int k = 0; k < N_OPTIONS; ++k)
    if (scene_options[k].commands & command_bit(command)) sk_closest_offer(&closest, name, scene_options[k].name);
  if (closest.best) return usage_error(command, "unknown option '%s' (did you mean '%s'?)", given, closest.best);
  return usage_error(command, "unknown option '%s'", given);
}

/* Returns 0 on success, 1 on bad usage (message printed), 2 when help was printed. Options are `--name value` or
 * `--name=value`, in any order around the scene. */
static int parse_arguments(int argc, char **argv, const char *command, arguments *args) {
  memset(args, 0, sizeof *args);
  args->sets = calloc((size_t)argc, sizeof(char *));
  args->modes = calloc((size_t)argc, sizeof *args->modes);
  if (!args->sets || !args->modes) {
    fprintf(stderr, "stickslip: out of memory\n");
    return 1;
  }
  int set_ends_at = -1; /* the argument holding the last --set or --replace value, and which of the two it was */
  const char *set_option = "--set";
  for (int i = 2; i < argc; ++i) {
    const char *a = argv[i];
    if (strcmp(a, "-h") == 0) a = "--help";
    if (a[0] != '-' || strcmp(a, "-") == 0) {
      if (set_ends_at == i - 1) /* `--set key={a: 1}` split by the shell */
        return usage_error(command, "'%s' after %s '%s': a value with spaces needs quotes (%s 'key={a: 1, b: 2}')",
                           a, set_option, args->sets[args->n_sets - 1], set_option);
      if (args->scene) return usage_error(command, "a second scene '%s' after '%s': one scene at a time", a,
                                          args->scene);
      args->scene = a;
      continue;
    }
    char name[64];
    const char *equals = strchr(a, '=');
    size_t length = equals ? (size_t)(equals - a) : strlen(a);
    snprintf(name, sizeof name, "%.*s", (int)(length < sizeof name ? length : sizeof name - 1), a);
    const option *opt = NULL;
    for (int k = 0; k < N_OPTIONS && !opt; ++k)
      if (strcmp(scene_options[k].name, name) == 0 && (scene_options[k].commands & command_bit(command))) opt = &scene_options[k];
    if (!opt) return unknown_option(command, a, name);
    const char *value = NULL;
    if (opt->value) {
      value = equals ? equals + 1 : i + 1 < argc && strncmp(argv[i + 1], "--", 2) != 0 ? argv[++i] : NULL;
      if (!value || !value[0]) return usage_error(command, "%s needs a value (%s %s)", name, name, opt->value);
    } else if (equals) {
      return usage_error(command, "%s takes no value, got '%s'", name, a);
    }
    if (strcmp(name, "--help") == 0) {
      if (rank_of_world() == 0) usage_run(stdout, command);
      return 2;
    } else if (strcmp(name, "--plugin") == 0) {
      args->plugin = value;
    } else if (strcmp(name, "--set") == 0 || strcmp(name, "--replace") == 0) {
      if (!strchr(value, '=') || value[0] == '=')
        return usage_error(command, "%s expects key.path=value, got '%s'", name, value);
      args->modes[args->n_sets] = strcmp(name, "--replace") == 0 ? SK_CFG_REPLACE : SK_CFG_MERGE;
      args->sets[args->n_sets++] = value;
      set_ends_at = i;
      set_option = strcmp(name, "--replace") == 0 ? "--replace" : "--set";
    } else if (strcmp(name, "--out") == 0) {
      args->out = value;
    } else if (strcmp(name, "--steps") == 0) {
      char *end;
      errno = 0;
      long steps = strtol(value, &end, 10);
      if (*end || end == value || errno || steps < 1 || steps > INT_MAX)
        return usage_error(command, "--steps expects a positive integer, got '%s'", value);
      args->steps = (int)steps;
    } else if (strcmp(name, "--checkpoint-every") == 0) {
      char *end;
      errno = 0;
      long every = strtol(value, &end, 10);
      if (*end || end == value || errno || every < 1 || every > INT_MAX)
        return usage_error(command, "--checkpoint-every expects a positive integer, got '%s'", value);
      args->checkpoint_every = (int)every;
    } else if (strcmp(name, "--checkpoint") == 0) {
      args->checkpoint = value;
    } else if (strcmp(name, "--restart") == 0) {
      args->restart = value;
    } else if (strcmp(name, "--trust-scripts") == 0) {
      args->trust_scripts = 1;
    } else if (strcmp(name, "--explain") == 0) {
      args->explain = 1;
    } else if (strcmp(name, "--quiet") == 0) {
      args->quiet = 1;
    } else if (strcmp(name, "--verbose") == 0) {
      args->verbose = 1;
    }
  }
  if (args->restart && (args->scene || args->n_sets > 0 || args->plugin))
    return usage_error(command, "--restart continues the checkpoint's scene, with its --set values and --plugin: give "
                       "no SCENE, --set, --replace or --plugin");
  if (args->checkpoint && !args->checkpoint_every)
    return usage_error(command, "--checkpoint DIR needs --checkpoint-every N");
  if (args->checkpoint_every && !args->checkpoint && args->out) {
    snprintf(args->checkpoint_default, sizeof args->checkpoint_default, "%s.checkpoint", args->out);
    args->checkpoint = args->checkpoint_default;
  }
  if (!args->scene && !args->restart && !(strcmp(command, "keys") == 0 && args->plugin))
    return usage_error(command, "which scene? (stickslip %s SCENE.yaml%s)", command,
                       strcmp(command, "keys") == 0 ? ", or stickslip keys --plugin NAME for a plugin's parameters" : "");
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
    if (rank_of_world() == 0)
      fprintf(stderr, "stickslip plugins: unexpected argument '%s'; see stickslip plugins --help\n", argv[i]);
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
  const int run = command == COMMAND_RUN;
  arguments args; /* read before MPI starts: --help and a mistyped option answer at once */
  int parsed = parse_arguments(argc, argv, run ? "run" : command == COMMAND_KEYS ? "keys" : "check", &args);
  if (parsed != 0) {
    free(args.sets);
    free(args.modes);
    return parsed == 2 ? 0 : 1;
  }
  sk_driver_mpi_init(&argc, &argv); /* the only commands that need a communicator */
  sk_interrupt_install();           /* after MPI_Init, which may install handlers of its own */
  /* --verbose asks for messages by name: with --quiet too, only the progress line goes (tests read a run's
   * messages without the progress line) */
  sk_log_verbosity = args.verbose ? 1 : args.quiet ? -1 : 0;
  sk_mesh_trust_scripts(args.trust_scripts);
  if (!args.scene && !args.restart) { /* keys --plugin NAME */
    const sk_plugin *plugin = NULL;
    sk_status status = sk_plugin_load(args.plugin, &plugin);
    if (status == SK_OK && rank_of_world() == 0) status = sk_plugin_keys(plugin, stdout);
    free(args.sets);
    free(args.modes);
    return status == SK_OK ? 0 : fail(status);
  }
  sk_scene scene;
  sk_restart *restart = NULL;
  const char *const *sets = args.sets;
  const sk_cfg_override_mode *modes = args.modes;
  sk_status status = SK_OK;
  if (args.restart) { /* the checkpoint's scene, as it was loaded */
    status = sk_restart_open(args.restart, MPI_COMM_WORLD, &restart);
    if (status == SK_OK) {
      args.scene = sk_restart_scene(restart);
      args.plugin = sk_restart_plugin(restart);
      args.n_sets = sk_restart_sets(restart, &sets, &modes);
    }
  }
  const sk_scene_overrides overrides = {.n = args.n_sets, .assignments = sets, .modes = modes, .plugin = args.plugin};
  if (status == SK_OK) status = sk_scene_load_with(args.scene, &overrides, MPI_COMM_WORLD, &scene);
  else memset(&scene, 0, sizeof scene);
  int code = 0;
  if (status != SK_OK) {
    code = fail(status);
  } else if (command == COMMAND_KEYS) {
    if (rank_of_world() == 0) sk_scene_keys(&scene, stdout);
  } else if (!run) {
    if (rank_of_world() == 0) {
      const sk_model *m = &scene.model;
      int n_elements = 0; /* the whole mesh's, also on several ranks (each holds its part) */
      for (int b = 0; b < m->n_bodies; ++b) n_elements += m->bodies[b].n_elems_global;
      printf("%s: ok — %dD, %d nodes, %d elements in %d bodies, %d dofs, %d contact pairs, %g to %g by %g\n",
             args.scene, m->dim, m->n_nodes_global, n_elements, m->n_bodies, (int)m->n_dofs_global, m->n_pairs, m->time.t_start,
             m->time.t_end, m->time.dt);
      for (int b = 0; b < m->n_bodies; ++b)
        printf("  body '%s': %d %s elements\n", m->bodies[b].name, m->bodies[b].n_elems_global,
               sk_elem_name(m->bodies[b].group->type));
      for (int k = 0; k < m->n_pairs; ++k)
        printf("  pair '%s': plugin %s, strategy %s, slave %s (%d nodes, %s faces), master %s\n", m->pairs[k].name,
               m->pairs[k].plugin->name, m->pairs[k].plugin->strategies[m->pairs[k].strategy],
               m->pairs[k].slave.name, m->pairs[k].slave.n_nodes_global, sk_elem_name(m->pairs[k].slave.face_type),
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
    if (args.steps) {
      char note[160];
      snprintf(note, sizeof note, "run with --steps %d: it stopped there; `stickslip run scene.yaml` runs to "
               "time.end", args.steps);
      sk_scene_note(&scene, note);
    }
    sk_run_options options = {.out_dir = args.out,
                              .progress = !args.quiet && rank_of_world() == 0,
                              .verbose = args.verbose,
                              .max_steps = args.steps,
                              .checkpoint_every = args.checkpoint_every,
                              .checkpoint_dir = args.checkpoint,
                              .scene_path = args.scene,
                              .sets = sets,
                              .set_modes = modes,
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
        /* on several ranks the phases are rank 0's; the contact work may sit on another rank, whose wait shows in
         * rank 0's solve (a collective follows the contact phase): its figure is given beside */
        char largest[64] = "", switches[96] = "";
        if (summary.contact_seconds_largest > summary.contact_seconds)
          snprintf(largest, sizeof largest, " (largest rank %.2f)", summary.contact_seconds_largest);
        /* solves that made no progress under the full step and went on with backtracking (docs/stability.md, 28) */
        if (summary.newton_backtrack_switches > 0)
          snprintf(switches, sizeof switches, " (%d solve%s switched to backtracking)",
                   summary.newton_backtrack_switches, summary.newton_backtrack_switches == 1 ? "" : "s");
        printf("%s: %d steps to t = %g, %d Newton iterations%s, %d linear solves (%d LU factorisations, %lld Krylov "
               "iterations), %.2f s (rank 0: assembly %.2f, contact %.2f%s, solve %.2f)\n",
               args.scene, summary.steps, summary.final_time, summary.newton_iterations, switches,
               summary.linear_solves, summary.linear_factorisations, (long long)summary.krylov_iterations,
               summary.wall_seconds, summary.assembly_seconds, summary.contact_seconds, largest, summary.solve_seconds);
        if (summary.results_dir[0]) print_results_line(summary.results_dir);
      }
    } else if (status != SK_OK) {
      code = 1;
    }
  }
  sk_scene_free(&scene);
  sk_restart_free(restart);
  free(args.sets);
  free(args.modes);
  return code;
}

int main(int argc, char **argv) {
  int code;
  char help_flag[] = "--help";
  char *help_argv[] = {argv[0], argc > 2 ? argv[2] : NULL, help_flag, NULL};
  if (argc == 3 && strcmp(argv[1], "help") == 0 && strcmp(argv[2], "help") != 0) {
    argc = 3; /* `stickslip help COMMAND` is `stickslip COMMAND --help` */
    argv = help_argv;
  }
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
  } else if (strcmp(argv[1], "compare") == 0) {
    code = sk_driver_exec_tool("stickslip-compare", argc, argv);
  } else {
    static const char *const words[] = {"run", "check", "keys", "plugins", "compare", "help", "--help", "--version"};
    sk_closest closest = SK_CLOSEST_NONE;
    for (size_t k = 0; k < sizeof words / sizeof words[0]; ++k) sk_closest_offer(&closest, argv[1], words[k]);
    if (rank_of_world() == 0)
      fprintf(stderr, "stickslip: unknown command '%s'%s%s%s; see stickslip --help\n", argv[1],
              closest.best ? " (did you mean '" : " (commands: run, check, keys, plugins, compare)",
              closest.best ? closest.best : "", closest.best ? "'?)" : "");
    code = 1;
  }
  sk_driver_mpi_finalize();
  return code;
}
