/* CSV time series and the flat JSON summary writer. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/output.h"

/* ---- CSV -------------------------------------------------------------------------------------------------- */

struct sk_csv {
  FILE *file;
  int n_columns;
  char *path;
};

/* Writes a header cell, quoting it when it holds a separator or a quote (RFC 4180). */
static void write_csv_name(FILE *f, const char *name) {
  if (!strpbrk(name, ",\"\n")) {
    fputs(name, f);
    return;
  }
  fputc('"', f);
  for (const char *c = name; *c; ++c) {
    if (*c == '"') fputc('"', f);
    fputc(*c, f);
  }
  fputc('"', f);
}

sk_status sk_csv_open(const char *path, int n_columns, const char *const *names, sk_csv **csv) {
  *csv = NULL;
  if (n_columns <= 0 || !names) return sk_error_set(SK_ERR_INTERNAL, "%s: a CSV file needs columns", path);
  sk_csv *c = calloc(1, sizeof *c);
  if (!c || !(c->path = strdup(path))) {
    free(c);
    return sk_error_set(SK_ERR_NOMEM, "%s: out of memory", path);
  }
  c->file = fopen(path, "w");
  if (!c->file) {
    sk_status status = sk_error_set(SK_ERR_IO, "cannot create '%s': %s", path, strerror(errno));
    free(c->path);
    free(c);
    return status;
  }
  c->n_columns = n_columns;
  for (int i = 0; i < n_columns; ++i) {
    if (i) fputc(',', c->file);
    write_csv_name(c->file, names[i] ? names[i] : "");
  }
  fputc('\n', c->file);
  *csv = c;
  return SK_OK;
}

/* %.17g round-trips doubles; integral values are printed plainly (step counts, iteration counts). */
static void format_value(char *buf, size_t n, double v) {
  if (isfinite(v) && v == floor(v) && fabs(v) < 1e17) {
    snprintf(buf, n, "%.0f", v == 0.0 ? 0.0 : v); /* no "-0" */
  } else {
    snprintf(buf, n, "%.17g", v);
  }
}

sk_status sk_csv_row(sk_csv *csv, const double *values) {
  if (!csv || !csv->file) return sk_error_set(SK_ERR_INTERNAL, "sk_csv_row: file not open");
  char buf[64];
  for (int i = 0; i < csv->n_columns; ++i) {
    format_value(buf, sizeof buf, values[i]);
    if (i) fputc(',', csv->file);
    fputs(buf, csv->file);
  }
  fputc('\n', csv->file);
  if (fflush(csv->file) != 0 || ferror(csv->file)) {
    return sk_error_set(SK_ERR_IO, "cannot write '%s': %s", csv->path, strerror(errno));
  }
  return SK_OK;
}

sk_status sk_csv_close(sk_csv *csv) {
  if (!csv) return SK_OK;
  sk_status status = SK_OK;
  if (csv->file && (ferror(csv->file) || fclose(csv->file) != 0)) {
    status = sk_error_set(SK_ERR_IO, "cannot write '%s'", csv->path);
  }
  free(csv->path);
  free(csv);
  return status;
}

/* ---- JSON ------------------------------------------------------------------------------------------------- */

struct sk_json {
  FILE *file;
  int n_keys;
  char *path;
};

static void write_json_string(FILE *f, const char *s) {
  fputc('"', f);
  for (const unsigned char *c = (const unsigned char *)(s ? s : ""); *c; ++c) {
    switch (*c) {
      case '"': fputs("\\\"", f); break;
      case '\\': fputs("\\\\", f); break;
      case '\n': fputs("\\n", f); break;
      case '\r': fputs("\\r", f); break;
      case '\t': fputs("\\t", f); break;
      default:
        if (*c < 0x20) {
          fprintf(f, "\\u%04x", *c);
        } else {
          fputc(*c, f);
        }
    }
  }
  fputc('"', f);
}

sk_status sk_json_open(const char *path, sk_json **json) {
  *json = NULL;
  sk_json *j = calloc(1, sizeof *j);
  if (!j || !(j->path = strdup(path))) {
    free(j);
    return sk_error_set(SK_ERR_NOMEM, "%s: out of memory", path);
  }
  j->file = fopen(path, "w");
  if (!j->file) {
    sk_status status = sk_error_set(SK_ERR_IO, "cannot create '%s': %s", path, strerror(errno));
    free(j->path);
    free(j);
    return status;
  }
  fputc('{', j->file);
  *json = j;
  return SK_OK;
}

static sk_status json_key(sk_json *json, const char *key) {
  if (!json || !json->file) return sk_error_set(SK_ERR_INTERNAL, "sk_json: file not open");
  fputs(json->n_keys++ ? ",\n  " : "\n  ", json->file);
  write_json_string(json->file, key);
  fputs(": ", json->file);
  return SK_OK;
}

static sk_status json_check(sk_json *json) {
  if (ferror(json->file)) return sk_error_set(SK_ERR_IO, "cannot write '%s'", json->path);
  return SK_OK;
}

sk_status sk_json_string(sk_json *json, const char *key, const char *value) {
  SK_TRY(json_key(json, key));
  write_json_string(json->file, value);
  return json_check(json);
}

sk_status sk_json_number(sk_json *json, const char *key, double value) {
  SK_TRY(json_key(json, key));
  if (isfinite(value)) {
    char buf[64];
    format_value(buf, sizeof buf, value);
    fputs(buf, json->file);
  } else {
    fputs("null", json->file); /* JSON has no inf/nan */
  }
  return json_check(json);
}

sk_status sk_json_int(sk_json *json, const char *key, long value) {
  SK_TRY(json_key(json, key));
  fprintf(json->file, "%ld", value);
  return json_check(json);
}

sk_status sk_json_bool(sk_json *json, const char *key, int value) {
  SK_TRY(json_key(json, key));
  fputs(value ? "true" : "false", json->file);
  return json_check(json);
}

sk_status sk_json_close(sk_json *json) {
  if (!json) return SK_OK;
  sk_status status = SK_OK;
  if (json->file) {
    fputs(json->n_keys ? "\n}\n" : "}\n", json->file);
    if (ferror(json->file) | (fclose(json->file) != 0)) {
      status = sk_error_set(SK_ERR_IO, "cannot write '%s'", json->path);
    }
  }
  free(json->path);
  free(json);
  return status;
}
