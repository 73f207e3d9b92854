/* Reads a .geo script (and every file it includes) before gmsh sees it, for two things gmsh cannot tell us:
 * - the DefineConstant names, so sk_mesh_load can reject parameters the script does not declare (gmsh would
 *   silently ignore a misspelt one; gmsh 4.8 has no API to list them);
 * - statements that reach outside the mesh: a scene shared by someone else must not run commands or write files on
 *   the machine that runs `stickslip check` (issue 15, item 16). The .geo language can run shell commands
 *   (SystemCall, System, NonBlockingSystemCall, OnelabRun), write files (Print, Save, CreateDir, Printf > file),
 *   end the process (Exit) and read further scripts (Include, Merge). Those are refused unless the user trusts the
 *   scripts (sk_mesh_trust_scripts, `--trust-scripts`); included scripts are checked the same way, and an Include or
 *   Merge whose file name is computed (not a plain string) is refused, as it cannot be checked.
 * The scan works on tokens (comments skipped, strings kept apart), so a word inside a string or comment never
 * counts, and it is conservative: a refused statement inside an If that would not run is still refused. */
#define _DEFAULT_SOURCE /* realpath */

#include <ctype.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"
#include "stickslip/files.h"

static int trust_scripts = 0;

void sk_mesh_trust_scripts(int trust) { trust_scripts = trust != 0; }
int sk_mesh_scripts_trusted(void) { return trust_scripts; }

/* ---- tokens ------------------------------------------------------------------------------------------------- */

typedef enum { TOKEN_END, TOKEN_NAME, TOKEN_STRING, TOKEN_NUMBER, TOKEN_PUNCT } token_kind;

typedef struct {
  token_kind kind;
  const char *start; /* for strings: the text between the quotes */
  size_t length;
  int line;
} token;

typedef struct {
  const char *at;
  int line;
} lexer;

static int is_name_start(char c) { return isalpha((unsigned char)c) || c == '_'; }
static int is_name_char(char c) { return isalnum((unsigned char)c) || c == '_'; }

/* gmsh's lexer: // and C comments, strings in "" or '' without escapes, names, numbers, single characters. */
static token next_token(lexer *lx) {
  for (;;) {
    while (*lx->at && isspace((unsigned char)*lx->at)) lx->line += *lx->at++ == '\n';
    if (lx->at[0] == '/' && lx->at[1] == '/') {
      while (*lx->at && *lx->at != '\n') ++lx->at;
    } else if (lx->at[0] == '/' && lx->at[1] == '*') {
      lx->at += 2;
      while (*lx->at && !(lx->at[0] == '*' && lx->at[1] == '/')) lx->line += *lx->at++ == '\n';
      if (*lx->at) lx->at += 2;
    } else {
      break;
    }
  }
  token t = {.kind = TOKEN_END, .start = lx->at, .length = 0, .line = lx->line};
  char c = *lx->at;
  if (!c) return t;
  if (c == '"' || c == '\'') {
    t.kind = TOKEN_STRING;
    t.start = ++lx->at;
    while (*lx->at && *lx->at != c) lx->line += *lx->at++ == '\n';
    t.length = (size_t)(lx->at - t.start);
    if (*lx->at) ++lx->at;
  } else if (is_name_start(c)) {
    t.kind = TOKEN_NAME;
    while (is_name_char(*lx->at)) ++lx->at;
    t.length = (size_t)(lx->at - t.start);
  } else if (isdigit((unsigned char)c) || (c == '.' && isdigit((unsigned char)lx->at[1]))) {
    t.kind = TOKEN_NUMBER;
    while (isalnum((unsigned char)*lx->at) || *lx->at == '.' ||
           ((*lx->at == '+' || *lx->at == '-') && (lx->at[-1] == 'e' || lx->at[-1] == 'E')))
      ++lx->at;
    t.length = (size_t)(lx->at - t.start);
  } else {
    t.kind = TOKEN_PUNCT;
    t.length = 1;
    ++lx->at;
  }
  return t;
}

static int is_name(const token *t, const char *name) {
  return t->kind == TOKEN_NAME && strlen(name) == t->length && strncmp(t->start, name, t->length) == 0;
}
static int is_punct(const token *t, char c) { return t->kind == TOKEN_PUNCT && t->start[0] == c; }

/* ---- the scan ----------------------------------------------------------------------------------------------- */

enum { MAX_SCRIPTS = 64, MAX_DEPTH = 16 };

typedef struct {
  char *seen[MAX_SCRIPTS]; /* real paths of the scripts scanned (an Include cycle is scanned once) */
  int n_seen;
  char **names;            /* DefineConstant names */
  int n_names;
} scan;

static sk_status add_name(scan *sc, const char *start, size_t length) {
  for (int i = 0; i < sc->n_names; ++i)
    if (strlen(sc->names[i]) == length && strncmp(sc->names[i], start, length) == 0) return SK_OK;
  char **bigger = realloc(sc->names, (size_t)(sc->n_names + 1) * sizeof *sc->names);
  if (!bigger) return sk_error_set(SK_ERR_NOMEM, "out of memory listing .geo parameters");
  sc->names = bigger;
  char *copy = malloc(length + 1);
  if (!copy) return sk_error_set(SK_ERR_NOMEM, "out of memory listing .geo parameters");
  memcpy(copy, start, length);
  copy[length] = '\0';
  sc->names[sc->n_names++] = copy;
  return SK_OK;
}

/* DefineConstant[ name = value, name = {value, options...}, ... ]: the names of entries at bracket depth 0. */
static sk_status read_define_constant(scan *sc, lexer *lx) {
  token t = next_token(lx);
  if (!is_punct(&t, '[')) return SK_OK;
  int depth = 0, entry_start = 1;
  for (t = next_token(lx); t.kind != TOKEN_END; t = next_token(lx)) {
    if (entry_start && t.kind == TOKEN_NAME) {
      lexer ahead = *lx;
      token after = next_token(&ahead);
      if (is_punct(&after, '=')) SK_TRY(add_name(sc, t.start, t.length));
    }
    entry_start = 0;
    if (is_punct(&t, '(') || is_punct(&t, '{') || is_punct(&t, '[')) {
      ++depth;
    } else if (is_punct(&t, ')') || is_punct(&t, '}') || is_punct(&t, ']')) {
      if (depth == 0) break;
      --depth;
    } else if (is_punct(&t, ',') && depth == 0) {
      entry_start = 1;
    }
  }
  return SK_OK;
}

/* Statements that act outside the mesh, by their first word; what each does, for the message. */
static const struct {
  const char *word, *does;
} unsafe_words[] = {
    {"SystemCall", "runs a shell command"},   {"System", "runs a shell command"},
    {"NonBlockingSystemCall", "runs a shell command"}, {"OnelabRun", "runs a program"},
    {"OnelabAction", "runs a program"},       {"Print", "writes a file"},
    {"Save", "writes a file"},                {"CreateDir", "creates a directory"},
    {"SendToServer", "talks to a server"},    {"Exit", "would end stickslip itself"},
};

static sk_status refuse(const char *path, int line, const char *what, const char *does) {
  return sk_error_set(SK_ERR_INPUT,
                      "mesh script %s:%d: '%s' %s; stickslip refuses scripts that act outside the mesh (a shared "
                      "scene could run anything on your machine). If you trust this script, run stickslip with "
                      "--trust-scripts",
                      path, line, what, does);
}

static sk_status scan_file(scan *sc, const char *path, int depth);

/* Include/Merge "file": the file is checked too (a script) or must be mesh or CAD data. */
static sk_status scan_included(scan *sc, const char *path, int depth, const token *command, lexer *lx) {
  char word[32];
  snprintf(word, sizeof word, "%.*s", (int)command->length, command->start);
  token arg = next_token(lx);
  lexer ahead = *lx;
  token end = next_token(&ahead);
  if (arg.kind != TOKEN_STRING || !is_punct(&end, ';')) {
    if (trust_scripts) return SK_OK;
    return refuse(path, command->line, word, "reads a file whose name is computed, which stickslip cannot check");
  }
  char relative[PATH_MAX], resolved[PATH_MAX + 8];
  snprintf(relative, sizeof relative, "%.*s", (int)arg.length, arg.start);
  const char *slash = strrchr(path, '/');
  if (relative[0] == '/' || !slash) {
    snprintf(resolved, sizeof resolved, "%s", relative);
  } else {
    snprintf(resolved, sizeof resolved, "%.*s/%s", (int)(slash - path), path, relative);
  }
  static const char *const data_suffixes[] = {".msh", ".step", ".stp", ".brep", ".iges", ".igs", ".stl", NULL};
  if (is_name(command, "Merge")) {
    size_t n = strlen(resolved);
    for (int k = 0; data_suffixes[k]; ++k) {
      size_t m = strlen(data_suffixes[k]);
      if (n >= m && strcmp(resolved + n - m, data_suffixes[k]) == 0) return SK_OK;
    }
  }
  sk_status status = scan_file(sc, resolved, depth + 1);
  if (status != SK_OK) return sk_error_prefix(status, "(%s at %s:%d) ", word, path, command->line);
  return SK_OK;
}

static sk_status scan_text(scan *sc, const char *path, int depth, const char *text) {
  lexer lx = {.at = text, .line = 1};
  token previous = {.kind = TOKEN_PUNCT, .start = ";", .length = 1, .line = 0};
  for (token t = next_token(&lx); t.kind != TOKEN_END; previous = t, t = next_token(&lx)) {
    if (t.kind != TOKEN_NAME || is_punct(&previous, '.')) continue; /* Mesh.SaveAll is an option, not Save */
    if (is_name(&t, "DefineConstant")) {
      SK_TRY(read_define_constant(sc, &lx));
      continue;
    }
    if (is_name(&t, "Include") || is_name(&t, "Merge") || is_name(&t, "MergeWithBoundingBox")) {
      SK_TRY(scan_included(sc, path, depth, &t, &lx));
      continue;
    }
    if (trust_scripts) continue;
    if (is_name(&t, "Printf")) {
      /* Printf("...", ...) > "file" or >> "file" writes a file; plain Printf only logs. */
      int level = 0;
      token u = next_token(&lx);
      for (; u.kind != TOKEN_END; u = next_token(&lx)) {
        if (is_punct(&u, '(')) ++level;
        if (is_punct(&u, ')') && --level <= 0) break;
      }
      lexer ahead = lx;
      token after = next_token(&ahead);
      if (is_punct(&after, '>')) return refuse(path, t.line, "Printf > file", "writes a file");
      continue;
    }
    for (size_t k = 0; k < sizeof unsafe_words / sizeof unsafe_words[0]; ++k)
      if (is_name(&t, unsafe_words[k].word)) return refuse(path, t.line, unsafe_words[k].word, unsafe_words[k].does);
  }
  return SK_OK;
}

static sk_status scan_file(scan *sc, const char *path, int depth) {
  if (depth > MAX_DEPTH)
    return sk_error_set(SK_ERR_INPUT, "mesh script %s: Include nested deeper than %d levels", path, MAX_DEPTH);
  char *real = realpath(path, NULL);
  if (!real) return sk_require_regular_file(path, "mesh script"); /* names the missing file */
  for (int i = 0; i < sc->n_seen; ++i) {
    if (strcmp(sc->seen[i], real) == 0) {
      free(real);
      return SK_OK;
    }
  }
  if (sc->n_seen == MAX_SCRIPTS) {
    free(real);
    return sk_error_set(SK_ERR_INPUT, "mesh script %s: more than %d scripts included", path, MAX_SCRIPTS);
  }
  sc->seen[sc->n_seen++] = real;
  char *text = NULL;
  size_t length = 0;
  SK_TRY(sk_read_text_file(path, "mesh script", SK_MAX_TEXT_FILE_BYTES, &text, &length));
  sk_status status = scan_text(sc, path, depth, text);
  free(text);
  return status;
}

sk_status sk_geo_scan(const char *path, char ***names, int *n_names) {
  scan sc = {.n_seen = 0, .names = NULL, .n_names = 0};
  sk_status status = scan_file(&sc, path, 0);
  for (int i = 0; i < sc.n_seen; ++i) free(sc.seen[i]);
  if (status != SK_OK) {
    sk_geo_names_free(sc.names, sc.n_names);
    *names = NULL;
    *n_names = 0;
    return status;
  }
  *names = sc.names;
  *n_names = sc.n_names;
  return SK_OK;
}

void sk_geo_names_free(char **names, int n_names) {
  for (int i = 0; i < n_names; ++i) free(names[i]);
  free(names);
}
