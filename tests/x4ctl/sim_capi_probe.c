// SPDX-License-Identifier: GPL-2.0
// The manual's C API, unchanged, for check-sim-nodev.sh: run with
// X4STEP_SIM=1 it drives the simulated port (a move, an output, the inputs).
#include <stdio.h>

#include "x4step.h"

int main(void) {
  if (X4Init(LPT1) != X4NoErr) {
    /* A second try: the library said what to fix once already. */
    X4Init(LPT1);
    fprintf(stderr, "sim_capi_probe: X4Init(LPT1) failed\n");
    return 1;
  }
  if (X4Load(500, -250, 0, 0, 5000, 20) != X4NoErr || X4Start() != X4NoErr) {
    fprintf(stderr, "sim_capi_probe: the move was refused\n");
    return 1;
  }
  while (X4GetState()) {
  }
  X4SetOut(SIGNAL1ON);
  printf("steps %ld %ld inputs %d\n", X4GetSteps(1), X4GetSteps(2), X4GetIn());
  return X4ReInit() == X4NoErr ? 0 : 1;
}
