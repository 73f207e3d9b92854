/* gmsh runs in a child process, because what it is given cannot be trusted to end well in ours:
 * - gmsh 4.8 throws C++ exceptions out of OpenMP regions (mesh sizes <= 0, some degenerate geometry), which no
 *   caller can catch: std::terminate aborts the process (issue 15, item 1);
 * - a script can loop forever, sleep, or ask for a mesh that fills the memory (items 2, 17);
 * - a crafted .msh or a gmsh bug can crash it.
 * The child meshes and sends the mesh back through a pipe; the parent waits with a wall-time limit and a limit on
 * the child's resident memory, and turns every way the child can end into a message naming the file and what gmsh
 * was doing (the "phase" the child reports as it goes). Nothing of gmsh's state survives into the parent, so each
 * load also starts from fresh gmsh options. */
#define _GNU_SOURCE

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "mesh_internal.h"
#include "stickslip/interrupt.h"

/* ---- frames: [kind (1 byte)][length (8 bytes)][payload] ---------------------------------------------------- */

enum { FRAME_PHASE = 'P', FRAME_ERROR = 'E', FRAME_MESH = 'M', FRAME_CLOCK = 'C' };

static int child_fd = -1; /* the child's end of the pipe (-1 in the parent) */

static int write_all(int fd, const void *data, size_t n) {
  const char *p = data;
  while (n > 0) {
    ssize_t w = write(fd, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return 0;
    p += w;
    n -= (size_t)w;
  }
  return 1;
}

static int write_frame(int fd, char kind, const void *payload, uint64_t length) {
  return write_all(fd, &kind, 1) && write_all(fd, &length, sizeof length) && write_all(fd, payload, length);
}

void sk_mesh_sandbox_phase(const char *fmt, ...) {
  if (child_fd < 0) return;
  char text[256];
  va_list args;
  va_start(args, fmt);
  vsnprintf(text, sizeof text, fmt, args);
  va_end(args);
  write_frame(child_fd, FRAME_PHASE, text, strlen(text) + 1);
}

void sk_mesh_sandbox_start_clock(void) {
  if (child_fd >= 0) write_frame(child_fd, FRAME_CLOCK, "", 0);
}

_Noreturn void sk_mesh_sandbox_fail(sk_status status) {
  char message[2100];
  int32_t code = (int32_t)status;
  memcpy(message, &code, sizeof code);
  snprintf(message + sizeof code, sizeof message - sizeof code, "%s", sk_error_message());
  write_frame(child_fd, FRAME_ERROR, message, sizeof code + strlen(message + sizeof code) + 1);
  _exit(0);
}

/* The mesh as one buffer: dim, n_nodes, n_groups (int32), coordinates, then per group its header and conn. */
char *sk_mesh_serialize(const sk_mesh *mesh, uint64_t *length) {
  uint64_t n = 3 * sizeof(int32_t) + 3 * (uint64_t)mesh->n_nodes * sizeof(double);
  for (int g = 0; g < mesh->n_groups; ++g)
    n += sizeof mesh->groups[g].name + 4 * sizeof(int32_t) +
         (uint64_t)mesh->groups[g].n_elems * (uint64_t)mesh->groups[g].nen * sizeof(int32_t);
  char *buffer = malloc(n), *at = buffer;
  if (!buffer) return NULL;
#define PUT(src, size) (memcpy(at, (src), (size)), at += (size))
  int32_t head[3] = {mesh->dim, mesh->n_nodes, mesh->n_groups};
  PUT(head, sizeof head);
  PUT(mesh->x, 3 * (size_t)mesh->n_nodes * sizeof(double));
  for (int g = 0; g < mesh->n_groups; ++g) {
    const sk_group *group = &mesh->groups[g];
    int32_t h[4] = {group->dim, (int32_t)group->type, group->nen, group->n_elems};
    PUT(group->name, sizeof group->name);
    PUT(h, sizeof h);
    PUT(group->conn, (size_t)group->n_elems * (size_t)group->nen * sizeof(int32_t));
  }
#undef PUT
  *length = n;
  return buffer;
}

/* Rebuilds the mesh from sk_mesh_serialize()'s buffer; every size is checked against the buffer. */
sk_status sk_mesh_deserialize(const char *buffer, uint64_t length, sk_mesh *mesh) {
  const char *at = buffer, *end = buffer + length;
#define GET(dst, size) \
  do { \
    if ((uint64_t)(end - at) < (uint64_t)(size)) goto corrupt; \
    memcpy((dst), at, (size)); \
    at += (size); \
  } while (0)
  int32_t head[3];
  GET(head, sizeof head);
  if (head[1] < 0 || head[2] < 0) goto corrupt;
  mesh->dim = head[0];
  mesh->n_nodes = head[1];
  mesh->x = malloc(3 * ((size_t)mesh->n_nodes + 1) * sizeof(double));
  mesh->groups = calloc((size_t)head[2] + 1, sizeof *mesh->groups);
  if (!mesh->x || !mesh->groups) return sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory", mesh->source);
  GET(mesh->x, 3 * (size_t)mesh->n_nodes * sizeof(double));
  for (int g = 0; g < head[2]; ++g) {
    sk_group *group = &mesh->groups[g];
    int32_t h[4];
    GET(group->name, sizeof group->name);
    GET(h, sizeof h);
    group->name[sizeof group->name - 1] = '\0';
    if (h[1] < 0 || h[1] >= SK_ELEM_TYPE_COUNT || h[2] < 1 || h[3] < 0) goto corrupt;
    group->dim = h[0];
    group->type = (sk_elem_type)h[1];
    group->nen = h[2];
    group->n_elems = h[3];
    size_t count = (size_t)group->n_elems * (size_t)group->nen;
    group->conn = malloc((count + 1) * sizeof(int));
    if (!group->conn) return sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory", mesh->source);
    mesh->n_groups = g + 1;
    GET(group->conn, count * sizeof(int32_t));
    for (size_t k = 0; k < count; ++k)
      if (group->conn[k] < 0 || group->conn[k] >= mesh->n_nodes) goto corrupt;
  }
#undef GET
  if (at == end) return SK_OK;
corrupt:
  return sk_error_set(SK_ERR_INTERNAL, "mesh %s: the mesh generator's answer is corrupt", mesh->source);
}

/* ---- the child ------------------------------------------------------------------------------------------------ */

_Noreturn static void run_child(int fd, int err_fd, sk_mesh_sandbox_work work, void *arg, sk_mesh *mesh) {
#ifdef PR_SET_PDEATHSIG
  prctl(PR_SET_PDEATHSIG, SIGKILL); /* never outlive stickslip (a script stuck in a loop would) */
#endif
  /* Default dispositions: a crash or a Ctrl-C ends the child (the parent reports it); no handler of the parent's
   * libraries (MPI's backtrace printer, ours) runs here. */
  const int signals[] = {SIGINT, SIGTERM, SIGPIPE, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
  for (size_t k = 0; k < sizeof signals / sizeof signals[0]; ++k) signal(signals[k], SIG_DFL);
  /* gmsh may print or (GetValue) read the terminal: it gets neither. What reaches stderr (a C library abort
   * message, a sanitizer report) goes to the parent, which quotes it when the child ends badly. */
  int null = open("/dev/null", O_RDWR);
  if (null >= 0) {
    dup2(null, STDIN_FILENO);
    dup2(null, STDOUT_FILENO);
    if (null > STDERR_FILENO) close(null);
  }
  dup2(err_fd, STDERR_FILENO);
  child_fd = fd;
  sk_status status = work(arg, mesh);
  uint64_t length = 0;
  char *buffer = status == SK_OK ? sk_mesh_serialize(mesh, &length) : NULL;
  if (status == SK_OK && !buffer) status = sk_error_set(SK_ERR_NOMEM, "out of memory sending the mesh");
  if (status != SK_OK) sk_mesh_sandbox_fail(status);
  /* _exit: none of the parent's atexit handlers (MPI, gmsh) may run in the child */
  _exit(write_frame(fd, FRAME_MESH, buffer, length) ? 0 : 3);
}

/* ---- the parent ----------------------------------------------------------------------------------------------- */

static double seconds_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Resident memory of a process in bytes (0 if unknown). */
static size_t resident_bytes(pid_t pid) {
  char path[64];
  snprintf(path, sizeof path, "/proc/%ld/statm", (long)pid);
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  unsigned long size = 0, resident = 0;
  int got = fscanf(f, "%lu %lu", &size, &resident);
  fclose(f);
  return got == 2 ? (size_t)resident * (size_t)sysconf(_SC_PAGESIZE) : 0;
}

typedef struct {
  char *data;
  size_t used, capacity;
} byte_buffer;

static int append(byte_buffer *b, const char *data, size_t n) {
  if (b->used + n > b->capacity) {
    size_t capacity = 2 * b->capacity + n + 4096;
    char *grown = realloc(b->data, capacity);
    if (!grown) return 0;
    b->data = grown;
    b->capacity = capacity;
  }
  memcpy(b->data + b->used, data, n);
  b->used += n;
  return 1;
}

/* The end of what the child wrote to stderr: its last non-empty line, for messages. */
static void last_line(const byte_buffer *err, char *out, size_t n) {
  out[0] = '\0';
  size_t end = err->used;
  while (end > 0 && (err->data[end - 1] == '\n' || err->data[end - 1] == ' ')) --end;
  size_t begin = end;
  while (begin > 0 && err->data[begin - 1] != '\n') --begin;
  if (end > begin) snprintf(out, n, ": %.*s", (int)(end - begin), err->data + begin);
}

sk_status sk_mesh_sandbox(sk_mesh_sandbox_work work, void *arg, const sk_mesh_sandbox_limits *limits, sk_mesh *mesh) {
  const char *source = mesh->source;
  int fds[2], errs[2];
  if (pipe2(fds, O_CLOEXEC) != 0)
    return sk_error_set(SK_ERR_IO, "mesh %s: cannot create a pipe for the mesh generator: %s", source, strerror(errno));
  if (pipe2(errs, O_CLOEXEC) != 0) {
    close(fds[0]);
    close(fds[1]);
    return sk_error_set(SK_ERR_IO, "mesh %s: cannot create a pipe for the mesh generator: %s", source, strerror(errno));
  }
  fflush(NULL); /* nothing buffered in the parent is written twice */
  pid_t pid = fork();
  if (pid < 0) {
    for (int k = 0; k < 2; ++k) close(fds[k]), close(errs[k]);
    return sk_error_set(SK_ERR_IO, "mesh %s: cannot start the mesh generator: %s", source, strerror(errno));
  }
  if (pid == 0) {
    close(fds[0]);
    close(errs[0]);
    run_child(fds[1], errs[1], work, arg, mesh);
  }
  close(fds[1]);
  close(errs[1]);

  byte_buffer in = {0}, err = {0};
  char phase[256] = "starting gmsh";
  size_t parsed = 0; /* bytes of `in` already taken apart into frames */
  char *mesh_frame = NULL, *error_frame = NULL;
  uint64_t mesh_length = 0;
  double start = seconds_now();
  sk_status status = SK_OK;
  const char *stop = NULL; /* why the parent stopped the child */
  int open_pipes = 2;
  struct pollfd p[2] = {{.fd = fds[0], .events = POLLIN}, {.fd = errs[0], .events = POLLIN}};
  while (open_pipes > 0) {
    int ready = poll(p, 2, 50);
    for (int k = 0; ready > 0 && k < 2; ++k) {
      if (p[k].fd < 0 || !(p[k].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      char chunk[65536];
      ssize_t got = read(p[k].fd, chunk, sizeof chunk);
      if (got == 0 || (got < 0 && errno != EINTR && errno != EAGAIN)) {
        p[k].fd = -1;
        --open_pipes;
      } else if (got > 0 && k == 1) {
        if (err.used > 8192) err.used = 0; /* only the end matters */
        append(&err, chunk, (size_t)got);
      } else if (got > 0 && !append(&in, chunk, (size_t)got)) {
        stop = "out of memory";
      }
    }
    /* take complete frames apart */
    while (!stop && in.used - parsed >= 9) {
      uint64_t length;
      memcpy(&length, in.data + parsed + 1, sizeof length);
      if (in.used - parsed - 9 < length) break;
      char kind = in.data[parsed];
      char *payload = in.data + parsed + 9;
      if (kind == FRAME_PHASE) snprintf(phase, sizeof phase, "%.*s", (int)length, payload);
      if (kind == FRAME_MESH) mesh_frame = payload, mesh_length = length;
      if (kind == FRAME_ERROR) error_frame = payload;
      if (kind == FRAME_CLOCK) start = seconds_now(); /* gmsh loaded: its work on the file starts */
      parsed += 9 + length;
    }
    size_t resident = resident_bytes(pid);
    if (stop) {
    } else if (sk_interrupt_requested()) {
      stop = "interrupted";
    } else if (limits->time_limit > 0 && seconds_now() - start > limits->time_limit) {
      stop = "time";
    } else if (limits->memory_limit > 0 && resident > limits->memory_limit) {
      stop = "memory";
    }
    if (stop) {
      kill(pid, SIGKILL);
      break;
    }
  }
  close(fds[0]);
  close(errs[0]);
  int wait_status = 0;
  while (waitpid(pid, &wait_status, 0) < 0 && errno == EINTR) {
  }
  char said[600];
  last_line(&err, said, sizeof said);
  /* frames point into in.data, which stays valid until the end */
  if (stop && strcmp(stop, "interrupted") == 0) {
    status = sk_error_set(SK_ERR_INTERRUPTED, "mesh %s: interrupted by %s while %s", source,
                          sk_interrupt_name(sk_interrupt_requested()), phase);
  } else if (stop && strcmp(stop, "time") == 0) {
    status = sk_error_set(SK_ERR_INPUT, "mesh %s: gmsh did not finish within %g s while %s (an endless loop in the "
                          "script, or a mesh far too fine?); the limit is the scene key mesh.time_limit", source,
                          limits->time_limit, phase);
  } else if (stop && strcmp(stop, "memory") == 0) {
    status = sk_error_set(SK_ERR_INPUT, "mesh %s: gmsh used more than %zu MB while %s, more than a mesh of "
                          "mesh.max_elements = %ld elements needs: the mesh asked for is too large (check the mesh "
                          "sizes and refinement; raise mesh.max_elements if it is meant)", source,
                          limits->memory_limit >> 20, phase, limits->max_elements);
  } else if (stop) {
    status = sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory receiving the mesh", source);
  } else if (error_frame) {
    int32_t code;
    memcpy(&code, error_frame, sizeof code);
    status = sk_error_set(code > 0 ? (sk_status)code : SK_ERR_INTERNAL, "%s", error_frame + sizeof code);
  } else if (WIFSIGNALED(wait_status)) {
    int sig = WTERMSIG(wait_status);
    status = sk_error_set(SK_ERR_INPUT, "mesh %s: gmsh crashed (%s) while %s%s%s", source, strsignal(sig), phase,
                          sig == SIGKILL ? " (killed from outside: out of memory?)" : "", said);
  } else if (!mesh_frame) {
    status = sk_error_set(SK_ERR_INPUT, "mesh %s: gmsh stopped without a mesh (exit status %d) while %s%s", source,
                          WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : -1, phase, said);
  } else {
    status = sk_mesh_deserialize(mesh_frame, mesh_length, mesh);
  }
  free(in.data);
  free(err.data);
  return status;
}
