/* mortar-dual glue: checkpoints (stickslip.checkpoint.v1): each owned node's committed state, multiplier and friction
 * history. */
#include <stdlib.h>
#include <string.h>

#include "mortar.h"
#include "records.h"

/* A node's record: its NCP branch, z_j, and the committed D^n / M^n coefficients of its slip (side, whole node index
 * on that side's surface, value). */
typedef struct {
  int32_t state, n_hist;
  double z[3];
  double slip_length; /* the slip accumulated (contact.csv's `slip`) */
} saved_node;
typedef struct {
  int32_t side, node;
  double value;
} saved_coefficient;

static sk_status save_state(sk_instance *inst, const sk_state *state, sk_record_writer *writer) {
  (void)state;
  size_t cap = 0;
  unsigned char *buffer = NULL;
  for (int oi = 0; oi < inst->n_owned; ++oi) {
    const owned_node *o = &inst->owned[oi];
    const int n_hist = inst->history_ready ? o->n_hist : 0;
    const size_t bytes = sizeof(saved_node) + sizeof(saved_coefficient) * (size_t)n_hist;
    if (bytes > cap) {
      unsigned char *grown = realloc(buffer, bytes);
      if (!grown) {
        free(buffer);
        return mortar_nomem(inst, "");
      }
      buffer = grown;
      cap = bytes;
    }
    saved_node head = {.state = o->c_state, .n_hist = n_hist, .slip_length = o->slip_length};
    for (int i = 0; i < inst->dim; ++i) head.z[i] = inst->z_committed[o->extra + i];
    memcpy(buffer, &head, sizeof head);
    for (int h = 0; h < n_hist; ++h) {
      const int side = inst->hist_side[o->hist + h];
      const sk_view *view = side == SIDE_SLAVE ? inst->slave : inst->master;
      const saved_coefficient c = {.side = side, .node = (int32_t)view->node_index[inst->hist_node[o->hist + h]],
                                   .value = inst->hist_value[o->hist + h]};
      memcpy(buffer + sizeof head + sizeof c * (size_t)h, &c, sizeof c);
    }
    writer->put(writer, inst->slave->node_index[o->node], buffer, (uint32_t)bytes);
  }
  free(buffer);
  return SK_OK;
}

static sk_status load_state(sk_instance *inst, const sk_state *state, const sk_record_reader *reader) {
  (void)state;
  inst->cache_valid = 0;
  int *slave_nodes = records_nodes_of_view(inst->slave);
  int *master_nodes = inst->master ? records_nodes_of_view(inst->master) : NULL;
  size_t cap = sizeof(saved_node) + 64 * sizeof(saved_coefficient);
  unsigned char *buffer = malloc(cap);
  sk_status status = slave_nodes && buffer && (!inst->master || master_nodes) ? SK_OK : mortar_nomem(inst, "");
  int total = 0;
  for (int oi = 0; oi < inst->n_owned && status == SK_OK; ++oi) {
    const owned_node *o = &inst->owned[oi];
    int64_t got = reader->get(reader, inst->slave->node_index[o->node], buffer, (uint32_t)cap);
    if (got > (int64_t)cap) {
      unsigned char *grown = realloc(buffer, (size_t)got);
      if (!grown) {
        status = mortar_nomem(inst, "");
        break;
      }
      buffer = grown;
      cap = (size_t)got;
      got = reader->get(reader, inst->slave->node_index[o->node], buffer, (uint32_t)cap);
    }
    saved_node head;
    if (got >= (int64_t)sizeof head) memcpy(&head, buffer, sizeof head);
    if (got < (int64_t)sizeof head || got != (int64_t)(sizeof head + sizeof(saved_coefficient) * (size_t)head.n_hist))
      status = inst->api->error(inst->host, SK_ERR_INPUT, "mortar-dual: slave node %lld: %s",
                                (long long)inst->slave->node_id[o->node],
                                got < 0 ? "no state in the checkpoint" : "a state record of another size");
    else
      total += head.n_hist;
  }
  /* the friction history's arrays, sized for all nodes' coefficients */
  if (status == SK_OK && total > inst->hist_cap) {
    int *hs = realloc(inst->hist_side, sizeof(int) * (size_t)total);
    if (hs) inst->hist_side = hs;
    int *hn = realloc(inst->hist_node, sizeof(int) * (size_t)total);
    if (hn) inst->hist_node = hn;
    double *hv = realloc(inst->hist_value, sizeof(double) * (size_t)total);
    if (hv) inst->hist_value = hv;
    if (!hs || !hn || !hv) status = mortar_nomem(inst, "");
    else inst->hist_cap = total;
  }
  memset(inst->z_committed, 0, sizeof(double) * (size_t)inst->n_extra);
  inst->n_hist = 0;
  for (int oi = 0; oi < inst->n_owned && status == SK_OK; ++oi) {
    owned_node *o = &inst->owned[oi];
    const int64_t got = reader->get(reader, inst->slave->node_index[o->node], buffer, (uint32_t)cap);
    saved_node head;
    memcpy(&head, buffer, sizeof head);
    (void)got;
    o->c_state = o->state = head.state;
    o->slip_length = head.slip_length;
    for (int i = 0; i < inst->dim; ++i) inst->z_committed[o->extra + i] = head.z[i];
    o->hist = inst->n_hist;
    for (int h = 0; h < head.n_hist && status == SK_OK; ++h) {
      saved_coefficient c;
      memcpy(&c, buffer + sizeof head + sizeof c * (size_t)h, sizeof c);
      const sk_view *view = c.side == SIDE_SLAVE ? inst->slave : inst->master;
      const int *nodes = c.side == SIDE_SLAVE ? slave_nodes : master_nodes;
      const int node = view && c.node >= 0 && c.node < view->n_nodes_global ? nodes[c.node] : -1;
      if (node < 0)
        status = inst->api->error(inst->host, SK_ERR_INPUT, "mortar-dual: slave node %lld: its slip history names a "
                                  "node this rank does not hold", (long long)inst->slave->node_id[o->node]);
      inst->hist_side[inst->n_hist] = c.side;
      inst->hist_node[inst->n_hist] = node;
      inst->hist_value[inst->n_hist++] = c.value;
    }
    o->n_hist = inst->n_hist - o->hist;
  }
  if (status == SK_OK && inst->master && inst->friction) inst->history_ready = 1;
  free(buffer);
  free(slave_nodes);
  free(master_nodes);
  return status;
}

const sk_checkpoint_ext mortar_checkpoint = {SK_TABLE_HEADER(sk_checkpoint_ext), .save = save_state,
                                             .load = load_state};
