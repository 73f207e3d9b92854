/* The results folder guarantees (issue 15, items 5, 6, 10; docs/user-guide.md): only files stickslip wrote are
 * replaced (a manifest lists them; anything else is a refusal naming the file), unfinished results never replace
 * finished ones (they go to DIR.incomplete), a failed write leaves DIR as it was, "--out ." is refused, and staging
 * folders of killed runs are named on the next run. */
#define _DEFAULT_SOURCE /* mkdtemp */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sk_test.h"
#include "stickslip/output.h"

static char root[] = "/tmp/sk_outdir_XXXXXX";

static void path_of(char *out, size_t n, const char *name) { snprintf(out, n, "%s/%s", root, name); }

static void write_file(const char *dir, const char *name, const char *text) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  SK_CHECK(f != NULL);
  if (f) {
    fputs(text, f);
    fclose(f);
  }
}

static int file_exists(const char *dir, const char *name) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  return access(path, F_OK) == 0;
}

static char *read_text(const char *dir, const char *name) {
  static char text[8192];
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "r");
  text[0] = '\0';
  if (!f) return text;
  size_t n = fread(text, 1, sizeof text - 1, f);
  text[n] = '\0';
  fclose(f);
  return text;
}

/* One run: begin, write `file` with `content`, commit with `status`. Returns the commit status; *final where. */
static sk_status run_once(const char *out, const char *file, const char *content, sk_results_status status,
                          char *final, size_t final_size) {
  char staging[1024];
  sk_status s = sk_outdir_begin(out, staging, sizeof staging);
  if (s != SK_OK) return s;
  write_file(staging, file, content);
  return sk_outdir_commit(staging, out, status, final, final_size);
}

static void test_replace_only_own_files(void) {
  char out[512], final[1024];
  path_of(out, sizeof out, "runs/out");
  SK_CHECK(run_once(out, "history.csv", "1", SK_RESULTS_OK, final, sizeof final) == SK_OK);
  SK_CHECK(strcmp(final, out) == 0 && file_exists(out, "history.csv"));
  const char *manifest = read_text(out, SK_OUTDIR_MARKER);
  SK_CHECK(sk_test_contains(manifest, "status: ok\n") && sk_test_contains(manifest, "\nhistory.csv\n"));
  /* the next run replaces it completely */
  SK_CHECK(run_once(out, "summary.json", "2", SK_RESULTS_OK, final, sizeof final) == SK_OK);
  SK_CHECK(file_exists(out, "summary.json") && !file_exists(out, "history.csv"));
  /* a file the user added to the results folder: refused before the run, naming it; nothing is touched */
  write_file(out, "notes.txt", "precious");
  char staging[1024];
  SK_CHECK(sk_outdir_begin(out, staging, sizeof staging) == SK_ERR_IO);
  SK_CHECK(sk_test_contains(sk_error_message(), "refusing to replace") && sk_test_contains(sk_error_message(), "'notes.txt'"));
  SK_CHECK(file_exists(out, "notes.txt") && file_exists(out, "summary.json"));
  /* item 6: a summary.json that merely says "stickslip" does not make a folder stickslip's */
  char thesis[512];
  path_of(thesis, sizeof thesis, "runs/d");
  mkdir(thesis, 0777);
  write_file(thesis, "summary.json", "stickslip\n");
  write_file(thesis, "thesis.tex", "precious");
  SK_CHECK(sk_outdir_begin(thesis, staging, sizeof staging) == SK_ERR_IO);
  SK_CHECK(sk_test_contains(sk_error_message(), "it holds 'summary.json', 'thesis.tex', which stickslip did not write"));
  SK_CHECK(sk_test_contains(sk_error_message(), "not a stickslip results folder"));
  SK_CHECK(file_exists(thesis, "thesis.tex"));
  /* ... and at the end, when the file appeared during the run: the new results stay where they are, and say so */
  char late[512];
  path_of(late, sizeof late, "runs/late");
  SK_CHECK(sk_outdir_begin(late, staging, sizeof staging) == SK_OK);
  mkdir(late, 0777);
  write_file(late, "notes.txt", "precious");
  SK_CHECK(sk_outdir_commit(staging, late, SK_RESULTS_OK, final, sizeof final) == SK_ERR_IO);
  SK_CHECK(sk_test_contains(sk_error_message(), "the new results are in") && strcmp(final, staging) == 0);
  SK_CHECK(file_exists(late, "notes.txt") && file_exists(staging, SK_OUTDIR_MARKER));
  /* a bare marker of an older stickslip: its usual file names may be replaced, nothing else */
  char legacy[512];
  path_of(legacy, sizeof legacy, "runs/legacy");
  mkdir(legacy, 0777);
  write_file(legacy, SK_OUTDIR_MARKER, "stickslip output directory: may be replaced by the next run\n");
  write_file(legacy, "history.csv", "1");
  write_file(legacy, "step-000010.vtu", "1");
  SK_CHECK(run_once(legacy, "history.csv", "2", SK_RESULTS_OK, final, sizeof final) == SK_OK);
  write_file(legacy, SK_OUTDIR_MARKER, "stickslip output directory: may be replaced by the next run\n");
  write_file(legacy, "plot.png", "mine");
  SK_CHECK(sk_outdir_begin(legacy, staging, sizeof staging) == SK_ERR_IO && sk_test_contains(sk_error_message(), "plot.png"));
  /* an empty folder may be replaced; a plain file, "" and "/" may not */
  char empty[512];
  path_of(empty, sizeof empty, "runs/empty/");
  mkdir(empty, 0777);
  SK_CHECK(run_once(empty, "history.csv", "1", SK_RESULTS_OK, NULL, 0) == SK_OK);
  char runs[512], plain[512];
  path_of(runs, sizeof runs, "runs");
  write_file(runs, "plain", "data");
  path_of(plain, sizeof plain, "runs/plain");
  SK_CHECK(sk_outdir_begin(plain, staging, sizeof staging) == SK_ERR_IO && sk_test_contains(sk_error_message(), "not a directory"));
  SK_CHECK(sk_outdir_begin("", staging, sizeof staging) == SK_ERR_INPUT);
  SK_CHECK(sk_outdir_begin("/", staging, sizeof staging) == SK_ERR_INPUT);
}

/* Item 5: unfinished results never replace finished ones; failed ones replace failed ones. */
static void test_unfinished(void) {
  char out[512], final[1024], incomplete[600];
  path_of(out, sizeof out, "runs/keep");
  snprintf(incomplete, sizeof incomplete, "%s.incomplete", out);
  SK_CHECK(run_once(out, "history.csv", "good", SK_RESULTS_OK, final, sizeof final) == SK_OK);
  SK_CHECK(run_once(out, "history.csv", "failed", SK_RESULTS_FAILED, final, sizeof final) == SK_OK);
  SK_CHECK(strcmp(final, incomplete) == 0);
  SK_CHECK(strcmp(read_text(out, "history.csv"), "good") == 0);
  SK_CHECK(strcmp(read_text(incomplete, "history.csv"), "failed") == 0);
  SK_CHECK(sk_test_contains(read_text(incomplete, SK_OUTDIR_MARKER), "status: failed"));
  SK_CHECK(run_once(out, "history.csv", "stopped", SK_RESULTS_INTERRUPTED, final, sizeof final) == SK_OK);
  SK_CHECK(strcmp(final, incomplete) == 0 && strcmp(read_text(incomplete, "history.csv"), "stopped") == 0);
  SK_CHECK(strcmp(read_text(out, "history.csv"), "good") == 0);
  /* a finished run replaces the finished one (DIR.incomplete stays until the user removes it) */
  SK_CHECK(run_once(out, "history.csv", "better", SK_RESULTS_OK, final, sizeof final) == SK_OK);
  SK_CHECK(strcmp(final, out) == 0 && strcmp(read_text(out, "history.csv"), "better") == 0);
  /* failed over failed: replaced in place */
  char failing[512];
  path_of(failing, sizeof failing, "runs/failing");
  SK_CHECK(run_once(failing, "history.csv", "1", SK_RESULTS_FAILED, final, sizeof final) == SK_OK);
  SK_CHECK(run_once(failing, "history.csv", "2", SK_RESULTS_FAILED, final, sizeof final) == SK_OK);
  SK_CHECK(strcmp(final, failing) == 0 && strcmp(read_text(failing, "history.csv"), "2") == 0);
  /* a run that cannot complete its files (a full disk) aborts: staging gone, DIR as it was */
  char staging[1024];
  SK_CHECK(sk_outdir_begin(out, staging, sizeof staging) == SK_OK);
  write_file(staging, "history.csv", "half");
  SK_CHECK(sk_outdir_abort(staging) == SK_OK && access(staging, F_OK) != 0);
  SK_CHECK(strcmp(read_text(out, "history.csv"), "better") == 0);
  SK_CHECK(sk_outdir_abort(staging) == SK_OK);                           /* already gone: fine */
  SK_CHECK(sk_outdir_abort(out) == SK_ERR_IO && file_exists(out, "history.csv")); /* not a staging folder */
}

/* Item 10: "--out ." (or any folder holding the current directory) is refused with a clear message. */
static void test_current_directory(void) {
  char here[512], inner[600], staging[1024], saved[1024];
  path_of(here, sizeof here, "runs/here");
  mkdir(here, 0777);
  snprintf(inner, sizeof inner, "%s/inner", here);
  mkdir(inner, 0777);
  SK_CHECK(getcwd(saved, sizeof saved) != NULL);
  SK_CHECK(chdir(inner) == 0);
  SK_CHECK(sk_outdir_begin(".", staging, sizeof staging) == SK_ERR_INPUT);
  SK_CHECK(sk_test_contains(sk_error_message(), "--out '.' is the current directory or contains it"));
  SK_CHECK(sk_outdir_begin("..", staging, sizeof staging) == SK_ERR_INPUT);
  SK_CHECK(sk_outdir_begin("./", staging, sizeof staging) == SK_ERR_INPUT);
  SK_CHECK(access("..partial-1", F_OK) != 0);
  SK_CHECK(sk_outdir_begin("results", staging, sizeof staging) == SK_OK); /* a folder of its own is fine */
  SK_CHECK(sk_outdir_commit(staging, "results", SK_RESULTS_OK, NULL, 0) == SK_OK);
  SK_CHECK(chdir(saved) == 0);
}

/* Item 7 (output side): the staging folder of a killed run is named, never deleted. */
static void test_stale_staging(void) {
  char out[512], stale[600], staging[1024], log[600];
  path_of(out, sizeof out, "runs/killed");
  snprintf(stale, sizeof stale, "%s.partial-999999999", out); /* above any pid_max: no such process */
  SK_CHECK(mkdir(stale, 0777) == 0 || access(stale, F_OK) == 0);
  write_file(stale, "history.csv", "rows before the kill");
  path_of(log, sizeof log, "stale.log");
  fflush(stderr);
  int saved = dup(fileno(stderr));
  int fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  dup2(fd, fileno(stderr));
  close(fd);
  sk_status status = sk_outdir_begin(out, staging, sizeof staging);
  fflush(stderr);
  dup2(saved, fileno(stderr));
  close(saved);
  SK_CHECK(status == SK_OK);
  SK_CHECK(sk_test_contains(read_text(root, "stale.log"), "killed.partial-999999999 holds the unfinished results of process "
                                                  "999999999"));
  SK_CHECK(file_exists(stale, "history.csv"));
  SK_CHECK(sk_outdir_abort(staging) == SK_OK);
}

int main(void) {
  if (!mkdtemp(root)) {
    perror("mkdtemp");
    return 1;
  }
  test_replace_only_own_files();
  test_unfinished();
  test_current_directory();
  test_stale_staging();
  int result = sk_test_finish("test_io_outdir");
  if (result == 0) {
    char command[600];
    snprintf(command, sizeof command, "rm -rf %s", root);
    if (system(command) != 0) fprintf(stderr, "could not remove %s\n", root);
  }
  return result;
}
