/* The rigid obstacles of a model as surfaces for ParaView and the plot scripts (obstacle_output.c). */
#ifndef STICKSLIP_OBSTACLE_OUTPUT_H
#define STICKSLIP_OBSTACLE_OUTPUT_H

#include "stickslip/model.h"

typedef struct sk_obstacle_output sk_obstacle_output;

/* Tessellates every obstacle of the model's pairs over the region of the mesh (its reference bounding box, widened
 * by half its diagonal): planes and parabolic cylinders as patches, cylinders as sections, spheres whole; in 2D as
 * curves in z = 0. Collective (the box is the whole mesh's). */
sk_status sk_obstacle_output_open(const sk_model *model, sk_obstacle_output **out);
int sk_obstacle_output_count(const sk_obstacle_output *obstacles);
/* A .vtu of the obstacles at time t (moved by their `motion`), with the cell field `obstacle` (index among them). */
sk_status sk_obstacle_output_write(const sk_obstacle_output *obstacles, double t, const char *path);
void sk_obstacle_output_free(sk_obstacle_output *obstacles);

#endif
