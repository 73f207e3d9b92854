/* Configuration tree: parsing, positions in messages, typed getters, --set overrides, unknown keys, paths, output. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sk_test.h"
#include "stickslip/config.h"
#include "stickslip/files.h"

static const char *scene_text =
    "# a representative scene\n"          /* 1 */
    "mesh:\n"                             /* 2 */
    "  file: meshes/block.geo\n"          /* 3 */
    "  params: {refine: 2, radius: 0.5}\n" /* 4 */
    "time:\n"                             /* 5 */
    "  t_end: 1.0\n"                      /* 6 */
    "  dt: 1e-3\n"                        /* 7 */
    "  adaptive: true\n"                  /* 8 */
    "  steps: 1e3\n"                      /* 9 */
    "gravity: [0, -9.81, 0]\n"            /* 10 */
    "bodies:\n"                           /* 11 */
    "  - name: block\n"                   /* 12 */
    "    material: neo-hooke\n"           /* 13 */
    "    E: 2.1e11\n"                     /* 14 */
    "    density: 7800\n"                 /* 15 */
    "  - name: base\n"                    /* 16 */
    "    material: hooke\n"               /* 17 */
    "    densty: 2500\n"                  /* 18 */
    "contact:\n"                          /* 19 */
    "  mu: 0.3\n"                         /* 20 */
    "  pairs:\n"                          /* 21 */
    "    - plugin: mortar\n"              /* 22 */
    "      surfaces: [top, bottom]\n"     /* 23 */
    "title: \"Sliding: 'block'\"\n";      /* 24 */

static const char *const materials[] = {"hooke", "svk", "neo-hooke", NULL};

static int contains(const char *haystack, const char *needle) {
  int found = strstr(haystack, needle) != NULL;
  if (!found) fprintf(stderr, "  expected '%s' in: %s\n", needle, haystack);
  return found;
}

static sk_cfg *parse_scene(void) {
  sk_cfg *root = NULL;
  sk_status status = sk_cfg_parse_string(scene_text, "scenes/x.yaml", &root);
  if (status != SK_OK) fprintf(stderr, "parse failed: %s\n", sk_error_message());
  return root;
}

static void test_parse_and_getters(void) {
  sk_cfg *root = parse_scene();
  SK_CHECK(root != NULL);
  if (!root) return;
  SK_CHECK(sk_cfg_kind_of(root) == SK_CFG_MAP);
  SK_CHECK(sk_cfg_size(root) == 6);
  SK_CHECK(strcmp(sk_cfg_key_at(root, 0), "mesh") == 0);

  const sk_cfg *time = sk_cfg_get(root, "time");
  double dt = 0, t_end = 0;
  int steps = 0, adaptive = 0;
  SK_CHECK(sk_cfg_double(time, "dt", 1, 0.0, &dt) == SK_OK);
  SK_CHECK_CLOSE(dt, 1e-3, 1e-15);
  SK_CHECK(sk_cfg_double(time, "t_end", 1, 0.0, &t_end) == SK_OK);
  SK_CHECK_CLOSE(t_end, 1.0, 0);
  SK_CHECK(sk_cfg_int(time, "steps", 1, 0, &steps) == SK_OK && steps == 1000);
  SK_CHECK(sk_cfg_bool(time, "adaptive", 1, 0, &adaptive) == SK_OK && adaptive == 1);
  double t0 = -1;
  SK_CHECK(sk_cfg_double(time, "t_start", 0, 0.25, &t0) == SK_OK && t0 == 0.25);

  double g[3] = {0};
  SK_CHECK(sk_cfg_vector(root, "gravity", 1, 3, NULL, g) == SK_OK);
  SK_CHECK_CLOSE(g[1], -9.81, 1e-15);
  const char *title = NULL;
  SK_CHECK(sk_cfg_string(root, "title", 1, NULL, &title) == SK_OK && strcmp(title, "Sliding: 'block'") == 0);

  const sk_cfg *mesh = sk_cfg_get(root, "mesh");
  const sk_cfg *params = sk_cfg_get(mesh, "params");
  SK_CHECK(sk_cfg_kind_of(params) == SK_CFG_MAP && sk_cfg_size(params) == 2);
  SK_CHECK(strcmp(sk_cfg_key_at(params, 1), "radius") == 0);
  SK_CHECK(strcmp(sk_cfg_scalar(sk_cfg_at(params, 1)), "0.5") == 0);
  SK_CHECK(strcmp(sk_cfg_path(sk_cfg_at(params, 0)), "mesh.params.refine") == 0);

  const sk_cfg *bodies = sk_cfg_get(root, "bodies");
  SK_CHECK(sk_cfg_kind_of(bodies) == SK_CFG_SEQ && sk_cfg_size(bodies) == 2);
  int material = -1;
  SK_CHECK(sk_cfg_choice(sk_cfg_at(bodies, 0), "material", 1, materials, 0, &material) == SK_OK && material == 2);
  const sk_cfg *mu = sk_cfg_get(sk_cfg_get(root, "contact"), "mu");
  SK_CHECK(strcmp(sk_cfg_where(mu), "scenes/x.yaml:20:7") == 0);
  SK_CHECK(strcmp(sk_cfg_path(mu), "contact.mu") == 0);
  const sk_cfg *pairs = sk_cfg_get(sk_cfg_get(root, "contact"), "pairs");
  const sk_cfg *surfaces = sk_cfg_get(sk_cfg_at(pairs, 0), "surfaces");
  SK_CHECK(strcmp(sk_cfg_path(surfaces), "contact.pairs[0].surfaces") == 0);
  SK_CHECK(strcmp(sk_cfg_scalar(sk_cfg_at(surfaces, 1)), "bottom") == 0);
  SK_CHECK(sk_cfg_get(root, "nothing") == NULL && sk_cfg_get(NULL, "x") == NULL);
  SK_CHECK(sk_cfg_scalar(pairs) == NULL);

  /* Absent and empty ("section:") optional sections behave as empty maps. */
  double tol = 0;
  SK_CHECK(sk_cfg_double(sk_cfg_get(root, "solver"), "tol", 0, 1e-8, &tol) == SK_OK && tol == 1e-8);
  sk_cfg *sparse = NULL;
  SK_CHECK(sk_cfg_parse_string("solver:\nname: x\n", "s.yaml", &sparse) == SK_OK);
  tol = 0;
  SK_CHECK(sk_cfg_double(sk_cfg_get(sparse, "solver"), "tol", 0, 1e-6, &tol) == SK_OK && tol == 1e-6);
  SK_CHECK(sk_cfg_double(sk_cfg_get(sparse, "name"), "tol", 0, 1e-6, &tol) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "s.yaml:2:7: 'name' should be a map"));
  sk_cfg_free(sparse);

  /* Getter errors name position and key path. */
  SK_CHECK(sk_cfg_double(time, "t_start", 1, 0, &t0) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "scenes/x.yaml:6: missing key 'time.t_start'"));
  double number;
  SK_CHECK(sk_cfg_double(mesh, "file", 1, 0, &number) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "scenes/x.yaml:3:9: key 'mesh.file' expects a number, got 'meshes/block.geo'"));
  int flag;
  SK_CHECK(sk_cfg_bool(sk_cfg_at(bodies, 0), "name", 1, 0, &flag) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "key 'bodies[0].name' expects a boolean"));
  int n;
  SK_CHECK(sk_cfg_int(root, "gravity", 1, 0, &n) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "scenes/x.yaml:10:10: key 'gravity' expects an integer, got a sequence"));
  SK_CHECK(sk_cfg_int(sk_cfg_at(bodies, 0), "E", 1, 0, &n) == SK_ERR_INPUT); /* 2.1e11 overflows int */
  double v2[2];
  SK_CHECK(sk_cfg_vector(root, "gravity", 1, 2, NULL, v2) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "expects a sequence of 2 numbers, got 3"));
  SK_CHECK(sk_cfg_vector(sk_cfg_at(pairs, 0), "surfaces", 1, 2, NULL, v2) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "scenes/x.yaml:23:18: key 'contact.pairs[0].surfaces[0]' expects a number, got 'top'"));
  SK_CHECK(sk_cfg_choice(sk_cfg_at(bodies, 0), "name", 1, materials, 0, &material) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "expects one of 'hooke', 'svk', 'neo-hooke', got 'block'"));
  sk_cfg_free(root);
}

static void test_unused_keys(void) {
  sk_cfg *root = parse_scene();
  if (!root) return;
  sk_cfg_mark_used(sk_cfg_get(root, "mesh"));
  sk_cfg_mark_used(sk_cfg_get(root, "time"));
  sk_cfg_get(root, "gravity");
  sk_cfg_get(root, "title");
  sk_cfg_mark_used(sk_cfg_get(root, "contact"));
  const sk_cfg *bodies = sk_cfg_get(root, "bodies");
  for (int i = 0; i < sk_cfg_size(bodies); ++i) {
    const sk_cfg *body = sk_cfg_at(bodies, i);
    const char *s;
    double d;
    sk_cfg_string(body, "name", 1, NULL, &s);
    sk_cfg_string(body, "material", 1, NULL, &s);
    sk_cfg_double(body, "E", 0, 1.0, &d);
    sk_cfg_double(body, "density", 0, 1.0, &d);
  }
  SK_CHECK(sk_cfg_check_unused(root) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "scenes/x.yaml:18:5: unknown key 'bodies[1].densty' (did you mean 'density'?)"));

  /* Far from every known key: no suggestion. */
  sk_cfg *other = NULL;
  SK_CHECK(sk_cfg_parse_string("a: 1\nzzzzzz: 2\n", "o.yaml", &other) == SK_OK);
  int a;
  sk_cfg_int(other, "a", 1, 0, &a);
  SK_CHECK(sk_cfg_check_unused(other) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "o.yaml:2:1: unknown key 'zzzzzz'"));
  SK_CHECK(strstr(sk_error_message(), "did you mean") == NULL);
  sk_cfg_get(other, "zzzzzz");
  SK_CHECK(sk_cfg_check_unused(other) == SK_OK);
  sk_cfg_free(other);
  sk_cfg_free(root);
}

static void expect_parse_error(const char *text, const char *expected) {
  sk_cfg *root = (sk_cfg *)1;
  sk_status status = sk_cfg_parse_string(text, "bad.yaml", &root);
  SK_CHECK(status == SK_ERR_INPUT);
  SK_CHECK(root == NULL);
  SK_CHECK(contains(sk_error_message(), expected));
  if (status == SK_OK) sk_cfg_free(root);
}

static void test_malformed(void) {
  expect_parse_error("a: 1\nb:\n  c: 2\n d: 3\n", "bad.yaml:4:");
  expect_parse_error("a: 1\nb: [1, 2\nc: 3\n", "bad.yaml:");
  expect_parse_error("a: 1\nb: 'open\n", "bad.yaml:");
  expect_parse_error("a: 1\nb: 2\na: 3\n", "bad.yaml:3:1: duplicate key 'a' (first given at line 1)");
  expect_parse_error("m: {x: 1, x: 2}\n", "duplicate key 'x'");
  expect_parse_error("a: &anchor 1\nb: *anchor\n", "bad.yaml:1:4: anchors (&name) are not supported");
  expect_parse_error("- 1\n- 2\n", "must be a map");
  expect_parse_error("just text\n", "must be a map");
  expect_parse_error("", "empty");
  expect_parse_error("a: 1\n---\nb: 2\n", "several YAML documents");
  expect_parse_error("a:\n  b:\n    - c: 1\n      d: [1, 2]]\n", "bad.yaml:4:");
  /* Line of the problem (libyaml reports the token after the tab). */
  expect_parse_error("a: 1\nb: 2\nc: 3\n\td: 4\n", "bad.yaml:4:");

  sk_cfg *root = (sk_cfg *)1;
  SK_CHECK(sk_cfg_load("/nonexistent/scene.yaml", &root) == SK_ERR_IO);
  SK_CHECK(root == NULL);
  SK_CHECK(contains(sk_error_message(), "/nonexistent/scene.yaml"));
}

static void test_set(void) {
  sk_cfg *root = parse_scene();
  if (!root) return;
  /* existing key */
  SK_CHECK(sk_cfg_set(root, "contact.mu=0.5") == SK_OK);
  const sk_cfg *contact = sk_cfg_get(root, "contact");
  double mu = 0;
  SK_CHECK(sk_cfg_double(contact, "mu", 1, 0, &mu) == SK_OK && mu == 0.5);
  SK_CHECK(strcmp(sk_cfg_where(sk_cfg_get(contact, "mu")), "--set contact.mu") == 0);
  SK_CHECK(strcmp(sk_cfg_path(sk_cfg_get(contact, "mu")), "contact.mu") == 0);
  /* new keys, with intermediate maps */
  SK_CHECK(sk_cfg_set(root, "output.vtu.every=10") == SK_OK);
  int every = 0;
  SK_CHECK(sk_cfg_int(sk_cfg_get(sk_cfg_get(root, "output"), "vtu"), "every", 1, 0, &every) == SK_OK && every == 10);
  SK_CHECK(strcmp(sk_cfg_path(sk_cfg_get(sk_cfg_get(root, "output"), "vtu")), "output.vtu") == 0);
  /* sequence index, both spellings */
  SK_CHECK(sk_cfg_set(root, "contact.pairs.0.plugin=penalty") == SK_OK);
  SK_CHECK(sk_cfg_set(root, "bodies[1].material = svk") == SK_OK);
  const char *plugin = NULL;
  const sk_cfg *pair = sk_cfg_at(sk_cfg_get(contact, "pairs"), 0);
  SK_CHECK(sk_cfg_string(pair, "plugin", 1, NULL, &plugin) == SK_OK && strcmp(plugin, "penalty") == 0);
  int material = -1;
  SK_CHECK(sk_cfg_choice(sk_cfg_at(sk_cfg_get(root, "bodies"), 1), "material", 1, materials, 0, &material) == SK_OK);
  SK_CHECK(material == 1);
  SK_CHECK(strcmp(sk_cfg_where(sk_cfg_get(sk_cfg_at(sk_cfg_get(root, "bodies"), 1), "material")),
                  "--set bodies.1.material") == 0);
  /* flow sequence */
  SK_CHECK(sk_cfg_set(root, "gravity=[1, 2e-3,3]") == SK_OK);
  double g[3];
  SK_CHECK(sk_cfg_vector(root, "gravity", 1, 3, NULL, g) == SK_OK);
  SK_CHECK(g[0] == 1 && g[1] == 2e-3 && g[2] == 3);
  SK_CHECK(strcmp(sk_cfg_path(sk_cfg_at(sk_cfg_get(root, "gravity"), 2)), "gravity[2]") == 0);
  /* a value that is a map, replacing a scalar */
  SK_CHECK(sk_cfg_set(root, "title={text: x, size: 3}") == SK_OK);
  SK_CHECK(sk_cfg_kind_of(sk_cfg_get(root, "title")) == SK_CFG_MAP);
  /* type errors on overridden values name the override */
  SK_CHECK(sk_cfg_set(root, "time.dt=abc") == SK_OK);
  double dt;
  SK_CHECK(sk_cfg_double(sk_cfg_get(root, "time"), "dt", 1, 0, &dt) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "--set time.dt: key 'time.dt' expects a number, got 'abc'"));
  /* empty value = empty string */
  SK_CHECK(sk_cfg_set(root, "mesh.file=") == SK_OK);
  SK_CHECK(strcmp(sk_cfg_scalar(sk_cfg_get(sk_cfg_get(root, "mesh"), "file")), "") == 0);

  /* bad syntax */
  SK_CHECK(sk_cfg_set(root, "contact.mu") == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "expected KEY=VALUE"));
  SK_CHECK(sk_cfg_set(root, "=3") == SK_ERR_INPUT);
  SK_CHECK(sk_cfg_set(root, "a..b=3") == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "empty part"));
  SK_CHECK(sk_cfg_set(root, "contact.=3") == SK_ERR_INPUT);
  SK_CHECK(sk_cfg_set(root, "bodies]0.E=3") == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "']' without '['"));
  SK_CHECK(sk_cfg_set(root, "bodies[0.E=3") == SK_ERR_INPUT);
  SK_CHECK(sk_cfg_set(root, "contact.pairs.5.plugin=x") == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "index 5 is out of range: 'contact.pairs'"));
  SK_CHECK(sk_cfg_set(root, "contact.pairs.first.plugin=x") == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "expected an index"));
  SK_CHECK(sk_cfg_set(root, "contact.mu.x=1") == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "is a scalar"));
  SK_CHECK(sk_cfg_set(root, "gravity=[1, 2") == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "--set gravity: malformed value"));
  SK_CHECK(sk_cfg_set(root, "x=*alias") == SK_ERR_INPUT);
  /* failed overrides leave the tree intact */
  SK_CHECK(sk_cfg_double(contact, "mu", 1, 0, &mu) == SK_OK && mu == 0.5);
  sk_cfg_free(root);
}

static void test_paths(void) {
  sk_cfg *root = parse_scene();
  if (!root) return;
  char path[256];
  const sk_cfg *mesh = sk_cfg_get(root, "mesh");
  SK_CHECK(sk_cfg_resolve_path(mesh, "meshes/block.geo", path, sizeof path) == SK_OK);
  SK_CHECK(strcmp(path, "scenes/meshes/block.geo") == 0);
  SK_CHECK(sk_cfg_resolve_path(mesh, "/abs/block.msh", path, sizeof path) == SK_OK);
  SK_CHECK(strcmp(path, "/abs/block.msh") == 0);
  char small[8];
  SK_CHECK(sk_cfg_resolve_path(mesh, "meshes/block.geo", small, sizeof small) == SK_ERR_INPUT);
  /* nodes made by --set resolve against the scene file too */
  SK_CHECK(sk_cfg_set(root, "mesh.file=other.msh") == SK_OK);
  SK_CHECK(sk_cfg_resolve_path(sk_cfg_get(mesh, "file"), "other.msh", path, sizeof path) == SK_OK);
  SK_CHECK(strcmp(path, "scenes/other.msh") == 0);
  sk_cfg_free(root);

  sk_cfg *flat = NULL;
  SK_CHECK(sk_cfg_parse_string("a: 1\n", "x.yaml", &flat) == SK_OK);
  SK_CHECK(sk_cfg_resolve_path(flat, "m.msh", path, sizeof path) == SK_OK && strcmp(path, "m.msh") == 0);
  sk_cfg_free(flat);
}

static void test_load_and_write(void) {
  char dir[] = "/tmp/sk_io_config_XXXXXX";
  SK_CHECK(mkdtemp(dir) != NULL);
  char path[256], out_path[256];
  snprintf(path, sizeof path, "%s/scene.yaml", dir);
  snprintf(out_path, sizeof out_path, "%s/effective.yaml", dir);
  FILE *f = fopen(path, "w");
  SK_CHECK(f != NULL);
  if (!f) return;
  fputs(scene_text, f);
  fclose(f);

  sk_cfg *root = NULL;
  SK_CHECK(sk_cfg_load(path, &root) == SK_OK);
  if (!root) return;
  char expected[300];
  snprintf(expected, sizeof expected, "%s:20:7", path);
  SK_CHECK(strcmp(sk_cfg_where(sk_cfg_get(sk_cfg_get(root, "contact"), "mu")), expected) == 0);
  SK_CHECK(sk_cfg_set(root, "contact.mu=0.125") == SK_OK);
  SK_CHECK(sk_cfg_set(root, "extra.list=[a, 'yes', 3]") == SK_OK);
  SK_CHECK(sk_cfg_write_file(root, out_path) == SK_OK);
  sk_cfg_free(root);

  /* The written tree parses back to the same values, strings stay strings. */
  sk_cfg *back = NULL;
  SK_CHECK(sk_cfg_load(out_path, &back) == SK_OK);
  if (back) {
    double mu = 0, g[3];
    const char *title = NULL;
    SK_CHECK(sk_cfg_double(sk_cfg_get(back, "contact"), "mu", 1, 0, &mu) == SK_OK && mu == 0.125);
    SK_CHECK(sk_cfg_vector(back, "gravity", 1, 3, NULL, g) == SK_OK && g[1] == -9.81);
    SK_CHECK(sk_cfg_string(back, "title", 1, NULL, &title) == SK_OK && strcmp(title, "Sliding: 'block'") == 0);
    const sk_cfg *list = sk_cfg_get(sk_cfg_get(back, "extra"), "list");
    SK_CHECK(sk_cfg_size(list) == 3 && strcmp(sk_cfg_scalar(sk_cfg_at(list, 1)), "yes") == 0);
    SK_CHECK(sk_cfg_size(sk_cfg_get(back, "bodies")) == 2);
    sk_cfg_free(back);
  }
  remove(path);
  remove(out_path);
  rmdir(dir);
}

/* Non-finite numbers are refused wherever a number is read (issue 15, item 12), naming position and key. */
static void test_non_finite(void) {
  sk_cfg *root = NULL;
  SK_CHECK(sk_cfg_parse_string("a: .nan\nb: -.inf\nc: 1e999\nd: [0, .inf, 0]\ne: nan\nf: -1e-999\ng: .Inf\nh: 5e-324\n",
                               "n.yaml", &root) == SK_OK);
  if (!root) return;
  double x = 7, v[3];
  SK_CHECK(sk_cfg_double(root, "a", 1, 0, &x) == SK_ERR_INPUT && x == 7);
  SK_CHECK(contains(sk_error_message(), "n.yaml:1:4: key 'a' expects a finite number, got '.nan'"));
  SK_CHECK(sk_cfg_double(root, "b", 1, 0, &x) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "key 'b' expects a finite number, got '-.inf'"));
  SK_CHECK(sk_cfg_double(root, "c", 1, 0, &x) == SK_ERR_INPUT); /* overflows a double */
  SK_CHECK(contains(sk_error_message(), "n.yaml:3:4: key 'c' expects a finite number, got '1e999'"));
  SK_CHECK(sk_cfg_vector(root, "d", 1, 3, NULL, v) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "key 'd[1]' expects a finite number, got '.inf'"));
  SK_CHECK(sk_cfg_double(root, "e", 1, 0, &x) == SK_ERR_INPUT); /* strtod's spelling */
  SK_CHECK(sk_cfg_double(root, "f", 1, 0, &x) == SK_OK && x == 0.0); /* underflow to zero is a finite number */
  SK_CHECK(sk_cfg_double(root, "g", 1, 0, &x) == SK_ERR_INPUT);
  SK_CHECK(sk_cfg_double(root, "h", 1, 0, &x) == SK_ERR_INPUT); /* subnormal */
  SK_CHECK(contains(sk_error_message(), "n.yaml:8:4: key 'h' expects 0 or a number of normal size"));
  int n;
  SK_CHECK(sk_cfg_int(root, "b", 1, 0, &n) == SK_ERR_INPUT);
  SK_CHECK(sk_cfg_set(root, "a=.inf") == SK_OK);
  SK_CHECK(sk_cfg_double(root, "a", 1, 0, &x) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "--set a: key 'a' expects a finite number, got '.inf'"));
  sk_cfg_free(root);
}

/* An empty or null section asked for a required key names itself, where it is and the missing key (item 8). */
static void test_empty_section(void) {
  sk_cfg *root = NULL;
  SK_CHECK(sk_cfg_parse_string("bodies:\n  - name: a\n    material:\n  - name: b\n    material: ~\ntime: null\n",
                               "e.yaml", &root) == SK_OK);
  if (!root) return;
  const sk_cfg *bodies = sk_cfg_get(root, "bodies");
  const char *model;
  SK_CHECK(sk_cfg_string(sk_cfg_get(sk_cfg_at(bodies, 0), "material"), "model", 1, NULL, &model) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "e.yaml:3:5: 'bodies[0].material' is empty; missing key "
                                        "'bodies[0].material.model'"));
  SK_CHECK(sk_cfg_string(sk_cfg_get(sk_cfg_at(bodies, 1), "material"), "model", 1, NULL, &model) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "e.yaml:5:5: 'bodies[1].material' is empty"));
  double dt;
  SK_CHECK(sk_cfg_double(sk_cfg_get(root, "time"), "dt", 1, 0, &dt) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "e.yaml:6:1: 'time' is empty; missing key 'time.dt'"));
  SK_CHECK(sk_cfg_double(sk_cfg_get(root, "time"), "dt", 0, 0.5, &dt) == SK_OK && dt == 0.5); /* optional: fine */
  SK_CHECK(sk_cfg_set(root, "bodies.0.material=~") == SK_OK);
  bodies = sk_cfg_get(root, "bodies");
  SK_CHECK(sk_cfg_string(sk_cfg_get(sk_cfg_at(bodies, 0), "material"), "model", 1, NULL, &model) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "--set bodies.0.material: 'bodies[0].material' is empty; missing key "
                                        "'bodies[0].material.model'"));
  sk_cfg_free(root);
}

/* Scene files must be regular text files of bounded size: a FIFO, /dev/zero, a directory, a binary or an oversized
 * file is refused at once, naming it (item 17). */
static void test_special_files(void) {
  char dir[] = "/tmp/stickslip-config-test-XXXXXX";
  SK_CHECK(mkdtemp(dir) != NULL);
  char path[256];
  sk_cfg *root = (sk_cfg *)1;
  snprintf(path, sizeof path, "%s/fifo.yaml", dir);
  SK_CHECK(mkfifo(path, 0600) == 0);
  SK_CHECK(sk_cfg_load(path, &root) == SK_ERR_INPUT && root == NULL); /* returns at once: no writer needed */
  SK_CHECK(contains(sk_error_message(), "fifo.yaml' is a FIFO (named pipe), not a regular file"));
  unlink(path);
  SK_CHECK(sk_cfg_load("/dev/zero", &root) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "scene file '/dev/zero' is a character device"));
  SK_CHECK(sk_cfg_load(dir, &root) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "is a directory"));
  snprintf(path, sizeof path, "%s/binary.yaml", dir);
  FILE *f = fopen(path, "wb");
  SK_CHECK(f != NULL);
  if (f) {
    fwrite("a: 1\n\0b: 2\n", 1, 11, f);
    fclose(f);
  }
  SK_CHECK(sk_cfg_load(path, &root) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "binary.yaml' holds a NUL byte"));
  unlink(path);
  snprintf(path, sizeof path, "%s/huge.yaml", dir);
  f = fopen(path, "wb");
  SK_CHECK(f != NULL);
  if (f) {
    SK_CHECK(fseek(f, (long)SK_MAX_TEXT_FILE_BYTES, SEEK_SET) == 0 && fputc('\n', f) == '\n'); /* sparse */
    fclose(f);
  }
  SK_CHECK(sk_cfg_load(path, &root) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "huge.yaml' has 16777217 bytes; the limit is 16 MiB"));
  unlink(path);
  rmdir(dir);
}

/* --set merges a map into the map it lands on; --replace replaces it (issue 31: `--set solver.newton={...}` dropped
 * the scene's other newton keys). */
static void test_merge_and_replace(void) {
  sk_cfg *root = NULL;
  SK_CHECK(sk_cfg_parse_string("solver:\n  newton: {tolerance: 1e-12, line_search: backtrack, deep: {a: 1, b: 2}}\n"
                               "list: [{x: 1, y: 2}]\n", "s.yaml", &root) == SK_OK);
  if (!root) return;
  const sk_cfg *newton = sk_cfg_get(sk_cfg_get(root, "solver"), "newton");
  SK_CHECK(sk_cfg_set(root, "solver.newton={max_iterations: 40, deep: {b: 3, c: 4}}") == SK_OK);
  newton = sk_cfg_get(sk_cfg_get(root, "solver"), "newton");
  int iterations = 0, b = 0, a = 0, c = 0;
  const char *line_search = NULL;
  SK_CHECK(sk_cfg_int(newton, "max_iterations", 1, 0, &iterations) == SK_OK && iterations == 40);
  SK_CHECK(sk_cfg_string(newton, "line_search", 1, NULL, &line_search) == SK_OK && strcmp(line_search, "backtrack") == 0);
  const sk_cfg *deep = sk_cfg_get(newton, "deep");
  SK_CHECK(sk_cfg_int(deep, "a", 1, 0, &a) == SK_OK && a == 1);      /* kept: maps merge further down */
  SK_CHECK(sk_cfg_int(deep, "b", 1, 0, &b) == SK_OK && b == 3);      /* replaced */
  SK_CHECK(sk_cfg_int(deep, "c", 1, 0, &c) == SK_OK && c == 4);      /* added */
  SK_CHECK(strcmp(sk_cfg_where(sk_cfg_get(newton, "max_iterations")), "--set solver.newton") == 0);
  SK_CHECK(strcmp(sk_cfg_path(sk_cfg_get(deep, "c")), "solver.newton.deep.c") == 0);
  SK_CHECK(strcmp(sk_cfg_where(sk_cfg_get(newton, "tolerance")), "s.yaml:2:23") == 0); /* keeps its position */
  /* a list element that is a map merges too */
  SK_CHECK(sk_cfg_set(root, "list.0={y: 5}") == SK_OK);
  int x = 0, y = 0;
  SK_CHECK(sk_cfg_int(sk_cfg_at(sk_cfg_get(root, "list"), 0), "x", 1, 0, &x) == SK_OK && x == 1);
  SK_CHECK(sk_cfg_int(sk_cfg_at(sk_cfg_get(root, "list"), 0), "y", 1, 0, &y) == SK_OK && y == 5);
  /* --replace: the map is what was given, nothing else */
  SK_CHECK(sk_cfg_override(root, "solver.newton={max_iterations: 7}", SK_CFG_REPLACE) == SK_OK);
  newton = sk_cfg_get(sk_cfg_get(root, "solver"), "newton");
  SK_CHECK(sk_cfg_size(newton) == 1 && sk_cfg_get(newton, "line_search") == NULL);
  SK_CHECK(strcmp(sk_cfg_where(sk_cfg_get(newton, "max_iterations")), "--replace solver.newton") == 0);
  SK_CHECK(sk_cfg_override(root, "solver.newton", SK_CFG_REPLACE) == SK_ERR_INPUT);
  SK_CHECK(contains(sk_error_message(), "--replace 'solver.newton': expected KEY=VALUE"));
  /* a scalar replaced by a map, a map by a scalar */
  SK_CHECK(sk_cfg_set(root, "solver.newton=3") == SK_OK);
  SK_CHECK(sk_cfg_kind_of(sk_cfg_get(sk_cfg_get(root, "solver"), "newton")) == SK_CFG_SCALAR);
  /* the program's own edits: a scalar set verbatim (keeping its position, or at an origin), a key removed */
  SK_CHECK(sk_cfg_set_text(root, "list[0].x", "a: b # not YAML", NULL) == SK_OK);
  const sk_cfg *element = sk_cfg_at(sk_cfg_get(root, "list"), 0);
  SK_CHECK(strcmp(sk_cfg_scalar(sk_cfg_get(element, "x")), "a: b # not YAML") == 0);
  SK_CHECK(strcmp(sk_cfg_where(sk_cfg_get(element, "x")), "s.yaml:3:12") == 0);
  SK_CHECK(sk_cfg_set_text(root, "list.0.z", "new", "--plugin") == SK_OK);
  SK_CHECK(strcmp(sk_cfg_where(sk_cfg_get(element, "z")), "--plugin") == 0);
  SK_CHECK(sk_cfg_set_text(root, "nowhere.z", "new", "--plugin") == SK_ERR_INPUT); /* parents must exist */
  SK_CHECK(sk_cfg_remove(root, "list.0.y") == 1 && sk_cfg_get(element, "y") == NULL && sk_cfg_size(element) == 2);
  SK_CHECK(sk_cfg_remove(root, "list.0.y") == 0);
  sk_cfg_free(root);
}

/* The listing: given keys with their positions, the defaults of absent keys and sections the program read. */
typedef struct {
  char text[4096];
} listing_text;

static void list_entry(void *ctx, const sk_cfg_entry *entry) {
  listing_text *out = ctx;
  size_t used = strlen(out->text);
  snprintf(out->text + used, sizeof out->text - used, "%s=%s%s%s%s;", entry->path, entry->value,
           entry->given ? "@" : entry->literal ? " (default)" : " (described)", entry->given ? entry->where : "",
           entry->quantity ? " #" : "");
}

static void test_listing(void) {
  sk_cfg *root = NULL;
  SK_CHECK(sk_cfg_parse_string("time: {dt: 0.5}\nbodies:\n  - {name: a, velocity: [1, 2, 3]}\n", "s.yaml", &root) ==
           SK_OK);
  if (!root) return;
  double dt, start, tolerance, v[3];
  int cuts;
  const sk_cfg *time = sk_cfg_get(root, "time");
  SK_CHECK(sk_cfg_double(time, "dt", 1, 0, &dt) == SK_OK);
  SK_CHECK(sk_cfg_double(time, "start", 0, 0.25, &start) == SK_OK && start == 0.25);
  SK_CHECK(sk_cfg_int(time, "max_cuts", 0, 6, &cuts) == SK_OK);
  const sk_cfg *body = sk_cfg_at(sk_cfg_get(root, "bodies"), 0);
  const char *name;
  SK_CHECK(sk_cfg_string(body, "name", 1, NULL, &name) == SK_OK);
  SK_CHECK(sk_cfg_vector(body, "velocity", 0, 3, (double[3]){0, 0, 0}, v) == SK_OK);
  SK_CHECK(sk_cfg_vector(body, "center", 0, 3, (double[3]){0, 0, 1}, v) == SK_OK);
  const sk_cfg *solver = sk_cfg_section(root, "solver");
  SK_CHECK(solver != NULL && sk_cfg_section(root, "solver") == solver); /* one stand-in */
  SK_CHECK(sk_cfg_double(sk_cfg_section(solver, "newton"), "tolerance", 0, 1e-10, &tolerance) == SK_OK);
  sk_cfg_note_default(root, "dimension", "from the mesh", 0, NULL);
  listing_text out = {""};
  sk_cfg_each(root, list_entry, &out);
  SK_CHECK(contains(out.text, "time.dt=0.5@s.yaml:1:12 #;time.start=0.25 (default) #;time.max_cuts=6 (default);"));
  SK_CHECK(contains(out.text, "bodies[0].name=a@s.yaml:3:12;bodies[0].velocity=[1, 2, 3]@s.yaml:3:25 #;"
                              "bodies[0].center=[0, 0, 1] (default) #;"));
  SK_CHECK(contains(out.text, "dimension=from the mesh (described);solver.newton.tolerance=1e-10 (default) #;"));
  /* stand-ins are not part of the scene: not written, no unknown keys */
  SK_CHECK(sk_cfg_get(root, "solver") == NULL && sk_cfg_check_unused(root) == SK_OK);
  sk_cfg_free(root);
}

int main(void) {
  test_parse_and_getters();
  test_unused_keys();
  test_malformed();
  test_set();
  test_paths();
  test_load_and_write();
  test_non_finite();
  test_empty_section();
  test_special_files();
  test_merge_and_replace();
  test_listing();
  return sk_test_finish("test_io_config");
}
