/* The configuration tree's node, shared by the files of the tree (config.c: nodes and parsing; config_get.c: reading
 * and the unknown-key check; config_set.c: overrides; config_write.c: writing and listing). Not a public header. */
#ifndef STICKSLIP_CONFIG_TREE_H
#define STICKSLIP_CONFIG_TREE_H

#include <yaml.h>

#include "stickslip/config.h"

/* How the program read a key (for the listing: units apply to quantities). */
typedef enum { READ_ANY, READ_NUMBER, READ_INT, READ_BOOL, READ_STRING, READ_VECTOR, READ_CHOICE } read_kind;

/* A key the program asked a map for, found or not: suggestions for misspelt keys come from these, and the listing
 * shows the default of an absent one. */
typedef struct {
  char *key;
  read_kind kind;
  char *dflt;    /* the default's text (NULL: none; the key is required or read without a default) */
  int literal;   /* dflt is a value ("0.5", "[0, 0, 0]") rather than a description ("from the mesh") */
  char *meaning; /* shown with the default (plugin parameters), or NULL */
} asked_key;

struct sk_cfg {
  sk_cfg_kind kind;
  char *text;                /* scalar text */
  yaml_scalar_style_t style; /* scalar style as written, kept when writing back */
  int flow;                  /* map/seq written in flow style ([1, 2]) */
  int n, cap;
  char **keys;               /* map keys (NULL for sequences) */
  sk_cfg **items;            /* map values or sequence elements */
  char *path;                /* "contact.pairs[0].plugin" */
  char *where;               /* "file:line:col" or "--set key" */
  char *file;                /* file the node came from (for messages and relative paths) */
  int line, col;             /* 1-based; 0 for nodes created by --set */
  int key_line, key_col;     /* position of the key naming this node in its parent map */
  int used;
  asked_key *asked;
  int n_asked, cap_asked;
  /* Empty maps standing in for absent sections (sk_cfg_section): not part of the scene, never written; they hold
   * what the program asked them for, so that the listing shows the defaults of an absent section's keys. */
  char **absent_keys;
  sk_cfg **absent;
  int n_absent;
};

char *sk_cfgi_dup_n(const char *s, size_t n);
char *sk_cfgi_dup(const char *s);
char *sk_cfgi_format(const char *fmt, const char *a, const char *b); /* malloc'd snprintf with two strings */
sk_status sk_cfgi_no_memory(void);
/* A node at file:line:col, or at `origin` ("--set key") when origin is non-NULL. */
sk_cfg *sk_cfgi_node_new(sk_cfg_kind kind, const char *file, const char *origin, int line, int col);
int sk_cfgi_append(sk_cfg *parent, char *key, sk_cfg *child); /* takes `key` on success */
int sk_cfgi_find(const sk_cfg *map, const char *key);          /* index of `key` in a map, or -1 */
int sk_cfgi_assign_paths(sk_cfg *node, const char *path);      /* key paths of a subtree placed at `path` */
/* Parses one YAML document; `origin` non-NULL: a --set value, every node's position is that text. */
sk_status sk_cfgi_parse_text(const char *text, size_t length, const char *name, const char *origin, sk_cfg **root);
/* A plain ~, null or empty scalar. */
int sk_cfgi_is_null(const sk_cfg *node);

#endif
