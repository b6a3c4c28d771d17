/* A physics failure made on purpose, for the tests, preloaded into `sear` (LD_PRELOAD): after ODE's
 * step number SEAR_TEST_BREAK_STEP, the first body the simulator created is left with a NaN
 * velocity, as a solver that blew up would leave it. No valid project can make ODE fail (the loader
 * refuses the values that would), and the simulator carries no hook for it; this lets a test follow
 * a run's whole path through a physics failure. ODE is reached through dlsym, so that the shell
 * the test starts `sear` from loads this library harmlessly too. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <math.h>
#include <stdlib.h>

typedef struct dxWorld *dWorldID;
typedef struct dxBody *dBodyID;
typedef double dReal; /* Debian's libode is built in double precision */

static dBodyID first_body;

dBodyID dBodyCreate(dWorldID world) {
  static dBodyID (*real)(dWorldID);
  if (!real) real = (dBodyID(*)(dWorldID))dlsym(RTLD_NEXT, "dBodyCreate");
  dBodyID body = real(world);
  if (!first_body) first_body = body;
  return body;
}

int dWorldQuickStep(dWorldID world, dReal stepsize) {
  static int (*real)(dWorldID, dReal);
  static void (*set_velocity)(dBodyID, dReal, dReal, dReal);
  static long steps, break_at = -1;
  if (!real) {
    real = (int (*)(dWorldID, dReal))dlsym(RTLD_NEXT, "dWorldQuickStep");
    set_velocity = (void (*)(dBodyID, dReal, dReal, dReal))dlsym(RTLD_NEXT, "dBodySetLinearVel");
    const char *at = getenv("SEAR_TEST_BREAK_STEP");
    break_at = at ? atol(at) : -1;
  }
  const int result = real(world, stepsize);
  if (++steps == break_at && first_body) set_velocity(first_body, NAN, 0, 0);
  return result;
}
