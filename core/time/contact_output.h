/* The contact results of a run at its output steps (contact_output.c), internal to the simulation layer. */
#ifndef STICKSLIP_CONTACT_OUTPUT_H
#define STICKSLIP_CONTACT_OUTPUT_H

#include "../model/system.h"
#include "stickslip/output.h"

typedef struct sk_contact_output sk_contact_output;

/* For a model with contact pairs. dir: the staging folder on rank 0 ("" on the other ranks); write_csv: contact.csv;
 * write_vtu: contact-NNNNNN.vtu + contact.pvd (the slave surfaces), obstacles-NNNNNN.vtu + obstacles.pvd (the rigid
 * obstacles) and the contact fields of the bodies' VTU. *out is set even on failure. Collective. */
sk_status sk_contact_output_open(const sk_model *model, const char *dir, int write_csv, int write_vtu,
                                 sk_contact_output **out);
/* The contact points of every pair at the state the system holds (initial: the initial output), at time t: appends
 * their contact.csv rows and, with VTU output, writes the contact and obstacle files of `step`, whose points are the
 * mesh at displacement u. Collective. */
sk_status sk_contact_output_step(sk_contact_output *co, sk_system *sys, int initial, const double *u, double t,
                                 int64_t step);
/* The contact fields of the last sk_contact_output_step at the nodes this rank holds (local numbering, every rank; 0
 * at nodes that are no contact points), for its piece of the bodies' VTU: writes up to `max` fields into `fields`,
 * returns how many. */
int sk_contact_output_node_fields(const sk_contact_output *co, sk_vtu_field *fields, int max);
/* contact.csv (rank 0, when written) and its number of columns, for the rows a restarted run carries over; NULL
 * otherwise. */
sk_csv *sk_contact_output_csv(const sk_contact_output *co, int *n_columns);
/* Closes the files (contact.csv, the collections). */
sk_status sk_contact_output_close(sk_contact_output *co);
void sk_contact_output_free(sk_contact_output *co);

#endif
