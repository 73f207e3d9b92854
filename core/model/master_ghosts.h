/* Master faces ghosted by swept boxes instead of replicated (docs/design.md, "Master faces ghosted by swept boxes").
 * At set-up every rank bounds each rank's slave entities of a pair (the whole mesh is still held there, so the p
 * boxes need no exchange) and grows the boxes by the capture distance and a reach; a rank then holds only the master
 * faces whose reference box overlaps its own grown box (and those its element ghost layer holds anyway): their nodes
 * are exchanged and in the plugins' master view. At every step's predictor the swept boxes of the step are
 * all-gathered and each master face's owner checks that every rank its face can now reach holds it; when one does
 * not, the faces are ghosted again from the step's boxes. */
#ifndef STICKSLIP_MASTER_GHOSTS_H
#define STICKSLIP_MASTER_GHOSTS_H

#include <stdio.h>

#include "stickslip/model.h"
#include "system.h"

/* 1 unless STICKSLIP_MASTER_GHOSTING=replicated (the same on every rank: mpirun passes the environment to all). */
int sk_master_ghosting_on(void);
/* Fails with a clear message when STICKSLIP_MASTER_GHOSTING is set to anything but boxes or replicated. */
sk_status sk_master_ghosting_check_setting(void);
/* For `check --explain`: how master surfaces are held, and per pair the capture distance and the reach. */
void sk_master_ghosts_explain(const sk_model *model, FILE *out);
/* The whole model, before it is distributed: every eligible pair's (a deformable master that is not the slave)
 * per-rank boxes (sk_contact_pair.ghost_boxes). `face_owner_of_slave` gives each slave face's owning rank. */
sk_status sk_master_ghosts_plan(sk_model *model, sk_contact_pair *pair, const int *face_owner_of_slave);
/* After the model is distributed (every master node held): the faces this rank holds (sk_contact_pair.master_held):
 * those whose reference box overlaps its grown box, and those its element ghost layer holds anyway. */
sk_status sk_master_ghosts_hold(sk_model *model);
/* At the step's predictor (sys->q_n, sys->q current): collective. The number of (face, rank) pairs over all ranks
 * where a master face came within reach of a rank's slave region that does not hold it. */
sk_status sk_master_ghosts_check(sk_system *sys, int64_t *missing_faces);
/* Ghosts the master faces again from the step's swept boxes (collective): the state of every master node this rank
 * holds from its owner, the faces it holds, the nodes' roles and their exchange, and the plugin terms of those pairs
 * re-created over their new master views from their records. With `rebalanced` (a new contact partition,
 * contact_partition.h, whose boxes sk_master_ghosts_check took) also the terms of the pairs with a contact
 * partition, over their new slave views too. The layout and pattern of the attempt follow. */
sk_status sk_master_ghosts_renew(sk_system *sys, int rebalanced);
/* A restart (core/time/restart.c), with the state of every node it keeps read and q = q_n: the faces held from the
 * positions there (collective). The instances of the pairs it applies to (sk_master_ghosts_term) are then re-created
 * over their new master views as they load their records (sk_term_plugin_recreate). */
sk_status sk_master_ghosts_restart(sk_system *sys);
/* 1 when `term` is the plugin instance of a pair whose master faces are ghosted by swept boxes. */
int sk_master_ghosts_term(const sk_system *sys, const sk_term *term);

#endif
