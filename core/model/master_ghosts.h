/* Master faces ghosted by swept boxes instead of replicated (docs/design.md, "Master faces ghosted by swept boxes";
 * on with STICKSLIP_MASTER_GHOSTING=boxes, off by default). At set-up every rank bounds each rank's slave entities of
 * a pair (the whole mesh is still held there, so the p boxes need no exchange) and grows the boxes by the capture
 * distance and a reach; a rank then holds only the master faces whose reference box overlaps its own grown box (and
 * those its element ghost layer holds anyway). At every step's predictor the swept boxes of the step are all-gathered
 * and each master face's owner checks that every rank its face can now reach holds it. */
#ifndef STICKSLIP_MASTER_GHOSTS_H
#define STICKSLIP_MASTER_GHOSTS_H

#include "stickslip/model.h"
#include "system.h"

/* 1 when STICKSLIP_MASTER_GHOSTING=boxes (the same on every rank: mpirun passes the environment to all). */
int sk_master_ghosting_on(void);
/* The whole model, before it is distributed: every eligible pair's (a deformable master that is not the slave)
 * per-rank boxes (sk_contact_pair.ghost_boxes). `face_owner_of_slave` gives each slave face's owning rank. */
sk_status sk_master_ghosts_plan(sk_model *model, sk_contact_pair *pair, const int *face_owner_of_slave);
/* 1 when master face `conn` (nen nodes of the model's numbering) is ghosted to `rank` (its reference box overlaps the
 * rank's grown slave box): sk_model_node_roles and the step's check ask the same question. */
int sk_master_face_ghosted(const sk_model *model, const sk_contact_pair *pair, const int *conn, int rank);
/* At the step's predictor (sys->q_n, sys->q current): collective. Fails with a clear message when a master face
 * came within reach of a rank's slave region that does not hold it (re-ghosting during a run is not built). */
sk_status sk_master_ghosts_check(sk_system *sys);

#endif
