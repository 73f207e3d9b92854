/* stickslip driver — commands that are scripts installed with the driver (tools.c). */
#ifndef STICKSLIP_DRIVER_TOOLS_H
#define STICKSLIP_DRIVER_TOOLS_H

/* Replaces this process with `python3 <bin>/../share/stickslip/tools/<script> argv[2..]`, STICKSLIP_BIN set to this
 * driver so the script runs the same build. Returns only on failure (message printed): 1. */
int sk_driver_exec_tool(const char *script, int argc, char **argv);

#endif
