/* Lists the DefineConstant names of a .geo script, so that sk_mesh_load can reject parameters the script does not
 * declare (a typo would otherwise be silently ignored by gmsh). */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"

/* The file's text with comments and string literals blanked out, so the scanner never matches inside them. */
static sk_status read_code(const char *path, char **code) {
  FILE *file = fopen(path, "rb");
  if (!file) return sk_error_set(SK_ERR_IO, "mesh %s: cannot open: %s", path, strerror(errno));
  size_t capacity = 4096, length = 0;
  char *text = malloc(capacity);
  if (!text) {
    fclose(file);
    return sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory reading the script", path);
  }
  size_t got;
  while ((got = fread(text + length, 1, capacity - length - 1, file)) > 0) {
    length += got;
    if (capacity - length - 1 == 0) {
      char *bigger = realloc(text, capacity * 2);
      if (!bigger) {
        free(text);
        fclose(file);
        return sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory reading the script", path);
      }
      text = bigger;
      capacity *= 2;
    }
  }
  int read_failed = ferror(file);
  fclose(file);
  if (read_failed) {
    free(text);
    return sk_error_set(SK_ERR_IO, "mesh %s: read error", path);
  }
  text[length] = '\0';

  for (size_t i = 0; i < length; ++i) {
    if (text[i] == '/' && text[i + 1] == '/') {
      while (i < length && text[i] != '\n') text[i++] = ' ';
    } else if (text[i] == '/' && text[i + 1] == '*') {
      while (i < length && !(text[i] == '*' && text[i + 1] == '/')) text[i++] = ' ';
      if (i < length) text[i] = text[i + 1] = ' ';
    } else if (text[i] == '"') {
      ++i;
      while (i < length && text[i] != '"') {
        if (text[i] == '\\' && i + 1 < length) text[i++] = ' ';
        text[i++] = ' ';
      }
    }
  }
  *code = text;
  return SK_OK;
}

static sk_status append_name(char ***names, int *n_names, const char *start, size_t length) {
  for (int i = 0; i < *n_names; ++i)
    if (strlen((*names)[i]) == length && strncmp((*names)[i], start, length) == 0) return SK_OK;
  char **bigger = realloc(*names, (size_t)(*n_names + 1) * sizeof **names);
  if (!bigger) return sk_error_set(SK_ERR_NOMEM, "out of memory listing .geo parameters");
  *names = bigger;
  char *copy = malloc(length + 1);
  if (!copy) return sk_error_set(SK_ERR_NOMEM, "out of memory listing .geo parameters");
  memcpy(copy, start, length);
  copy[length] = '\0';
  (*names)[(*n_names)++] = copy;
  return SK_OK;
}

static int is_ident_char(char c) { return isalnum((unsigned char)c) || c == '_'; }

sk_status sk_geo_defined_constants(const char *path, char ***names, int *n_names) {
  static const char keyword[] = "DefineConstant";
  char *code = NULL;
  *names = NULL;
  *n_names = 0;
  SK_TRY(read_code(path, &code));

  sk_status status = SK_OK;
  for (char *at = strstr(code, keyword); at && status == SK_OK; at = strstr(at, keyword)) {
    int starts_word = at == code || !is_ident_char(at[-1]);
    at += sizeof keyword - 1;
    if (!starts_word || is_ident_char(*at)) continue;
    while (isspace((unsigned char)*at)) ++at;
    if (*at != '[') continue;
    ++at;
    /* Entries are "name = value" or "name = {value, options...}", separated by commas at bracket depth 0. */
    int depth = 0, entry_start = 1;
    for (; *at && status == SK_OK; ++at) {
      if (entry_start) {
        while (isspace((unsigned char)*at)) ++at;
        const char *name = at;
        while (is_ident_char(*at)) ++at;
        size_t length = (size_t)(at - name);
        const char *after = at;
        while (isspace((unsigned char)*after)) ++after;
        if (length > 0 && *after == '=') status = append_name(names, n_names, name, length);
        entry_start = 0;
        if (!*at) break;
      }
      char c = *at;
      if (c == '(' || c == '{' || c == '[') {
        ++depth;
      } else if (c == ')' || c == '}' || c == ']') {
        if (depth == 0) break; /* the closing ']' of DefineConstant */
        --depth;
      } else if (c == ',' && depth == 0) {
        entry_start = 1;
      }
    }
  }
  free(code);
  if (status != SK_OK) {
    sk_geo_names_free(*names, *n_names);
    *names = NULL;
    *n_names = 0;
  }
  return status;
}

void sk_geo_names_free(char **names, int n_names) {
  for (int i = 0; i < n_names; ++i) free(names[i]);
  free(names);
}
