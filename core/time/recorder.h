/* The result files of a run (recorder.c), internal to the simulation layer. */
#ifndef STICKSLIP_RECORDER_H
#define STICKSLIP_RECORDER_H

#include "../model/system.h"
#include "stickslip/run.h"

typedef struct sk_recorder sk_recorder;

/* Opens the staging folder (rank 0, when options->out_dir) and the history columns. *rec is set even on failure. */
sk_status sk_recorder_open(sk_scene *scene, sk_system *sys, const sk_run_options *options, double wall_start,
                           sk_recorder **rec);
/* Row 0 (and the initial VTU) at the initial state. Collective. */
sk_status sk_recorder_initial(sk_recorder *rec);
/* In place of sk_recorder_initial for a restarted run: the rows of the checkpoint (history.csv up to its step) and
 * the accumulated dissipation. Rank 0 reads; its status. */
sk_status sk_recorder_resume(sk_recorder *rec, const sk_restart *restart);
/* What a checkpoint keeps of the recorder (checkpoint.h). */
struct sk_recorder_state_s;
void sk_recorder_checkpoint_state(sk_recorder *rec, struct sk_recorder_state_s *state);
/* After a commit, before the system advances: the step's row, and an output (VTU, contact points) every vtu_every
 * scheduled steps or at the last. scheduled: the scheduled times reached; substep: 0 when the step landed on a scheduled time, else the
 * number of sub-steps (of a cut step) since the last one. */
sk_status sk_recorder_step(sk_recorder *rec, int64_t scheduled, int substep, int last);
/* The total energy of the last row (for the progress line). */
double sk_recorder_total_energy(const sk_recorder *rec);
/* summary.json, and the folder swapped in (or dropped on an output error); sets
 * summary->results_dir to where the files are. Returns
 * `status` unless the output failed. Collective. */
sk_status sk_recorder_close(sk_recorder *rec, sk_run_summary *summary, sk_status status);
void sk_recorder_free(sk_recorder *rec);

#endif
